"""Verification with heat and fuel meters, and its periods (fuzzing round 5).

The verify demo's hydronic heat turned into the meter columns a user has: a cumulative
reading, energy per hour, a fuel meter, with the unit slips and meter events the fuzzing
round found handled badly (a reading not declared cumulative verified at -121,849 %, a
meter in kWh declared W crashing the summary, a correct cumulative meter refused with the
default periods, a reset blamed on the units, a false "meter exchanged" note on every
energy meter, a boiler replaced with the retrofit credited to the envelope).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import yaml

from thermocal.demos.verify import prepare_verify_demo
from thermocal.errors import ThermocalInputError
from thermocal.retrofit.verify import load_verify_config, run_verify

#: The verify demo's measured saving (docs/verify.md: 58.6-58.7 % with its hydronic heat).
DEMO_SAVING_PCT = 58.6


@pytest.fixture(scope="module")
def demo_folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("verify-meters")
    config, _ = prepare_verify_demo(out)
    return config


def _heat_w(frame: pd.DataFrame) -> np.ndarray:
    """The demo's hydronic heating power [W] (flow in l/h)."""
    from thermocal.physics.hydronics import heating_power

    return heating_power(
        frame["V_dot"] / 3.6e6, frame["T_supply"], frame["T_return"]
    ).to_numpy(float)


def _meter_config(config, tmp_path, column: np.ndarray, draws: int = 10, **measurements):
    """The demo with its heat as one meter column ``Q`` and the given measurement keys."""
    cfg = yaml.safe_load(config.read_text())
    frame = pd.read_csv(config.parent / cfg["measurements"]["file"])
    frame["Q"] = column(frame) if callable(column) else column
    frame.drop(columns=["V_dot", "T_supply", "T_return"]).to_csv(
        tmp_path / "meter.csv", index=False
    )
    cfg["building"] = str(config.parent / cfg["building"])
    mc = cfg["measurements"]
    mc["file"] = str(tmp_path / "meter.csv")
    for key in ("flow", "temp_supply", "temp_return"):
        mc["columns"].pop(key)
    mc.pop("flow_unit")
    mc["columns"]["heat"] = "Q"
    mc.update({"heat_source": "heat_meter", **measurements})
    cfg["uncertainty"]["draws"] = draws
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


def _cumulative_kwh(frame: pd.DataFrame) -> np.ndarray:
    """A heat meter's reading [kWh] at each row's start, 0.1 kWh resolution."""
    return np.round(12345.0 + np.concatenate([[0.0], np.cumsum(_heat_w(frame))[:-1]]) / 1e3, 1)


# ------------------------------------------------------------------------------------------
# U1, V-S2: a correctly declared cumulative meter, default periods, no false meter change
# ------------------------------------------------------------------------------------------
def test_a_cumulative_meter_is_verified_with_the_default_periods(demo_folder, tmp_path):
    """The last row of a cumulative reading has no next reading: the default post period
    ends with the last metered heat instead of refusing it as "missing values in the
    training period" (fuzz5 v05). The meter reads in 0.1 kWh before and after: no note of
    an exchanged meter (before: "2 before, 0.5 after" on every energy meter, v02)."""
    path = _meter_config(
        demo_folder, tmp_path, _cumulative_kwh, heat_unit="kWh", heat_cumulative=True
    )
    ver = run_verify(load_verify_config(path))
    last_row = pd.Timestamp("2001-03-11 23:00", tz=ver.post[1].tz)
    assert ver.post[1] == last_row, ver.post
    saving = ver.comparison["measured_saving_pct"]["value"]
    assert abs(saving - DEMO_SAVING_PCT) < 1.0, saving
    assert not any("resolution" in n or "exchanged" in n for n in ver.notes), ver.notes
    assert ver.comparison["warnings"] == []


# ------------------------------------------------------------------------------------------
# V-S1, C1: unit slips of the metered heat are refused as in thermocal retrofit
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("keys", "expected"),
    [
        # kWh per hourly row declared W (fuzz5 v04: a TypeError after a verify.json of 103 %)
        ({"heat_unit": "W"}, ["far too small", "measurements.heat_unit (now W"]),
        # a meter reading not declared cumulative (v08: -121,849 %, exit 0)
        ({"heat_unit": "kWh", "cumulative": True},
         ["far too large", "heat_cumulative (now false"]),
    ],
)  # fmt: skip
def test_a_unit_slip_of_the_metered_heat_is_refused(demo_folder, tmp_path, keys, expected):
    keys = dict(keys)
    column = _cumulative_kwh if keys.pop("cumulative", False) else lambda f: _heat_w(f) / 1e3
    path = _meter_config(demo_folder, tmp_path, column, **keys)
    with pytest.raises(ThermocalInputError) as info:
        run_verify(load_verify_config(path))
    message = str(info.value)
    assert "(pre-retrofit period)" in message and "column 'Q'" in message, message
    assert "training period" not in message, message
    for text in expected:
        assert text in message, message


def test_the_summary_prints_figures_that_were_not_computed(capsys, tmp_path):
    """NaN figures are None in verify.json; the summary says n/a instead of a TypeError
    (fuzz5 v04), and prints the verification's warnings."""
    from thermocal.commands.verify import print_summary

    none = {"value": None, "lo": None, "hi": None}
    results = {
        "comparison": {
            "interval": 0.9, "measured_saving_pct": {"value": 103.2, "lo": 100.0, "hi": None},
            "predicted_saving_pct": {"value": 61.2, "lo": 49.0, "hi": 69.7},
            "difference_pp": dict(none), "verdict": "inconclusive", "explanation": "why",
            "warnings": ["the heat is in another unit"],
        },
        "avoided_energy": {
            "saving_pct": None, "saving_pct_lo": None, "saving_pct_hi": None,
            "take_back_pp": None, "baseline_nmbe_pct": None, "baseline_cv_rmse_pct": None,
            "fsu_at_68pct": None, "calibration": "temperature", "adjustment": {},
        },
        "physical_change": {
            "heat_loss_coefficient_W_per_K": {"pre": dict(none), "post": dict(none)},
            "groups": {},
        },
    }  # fmt: skip
    print_summary(results, tmp_path)
    out = capsys.readouterr().out
    assert "n/a" in out and "INCONCLUSIVE" in out
    assert "WARNING" in out and "the heat is in another unit" in out


# ------------------------------------------------------------------------------------------
# U2: a cumulative reading that falls
# ------------------------------------------------------------------------------------------
def _readings(values_kwh) -> pd.Series:
    index = pd.date_range("2001-02-01", periods=len(values_kwh), freq="h", tz="UTC")
    return pd.Series(np.asarray(values_kwh, float) * 3.6e6, index=index)


def test_a_falling_cumulative_reading_names_the_row_and_the_fix():
    """A meter reset or rolled over (fuzz5 v06, v07, r53) turned one interval into minus the
    whole count and was blamed on heat_cumulative; now the drop is named with its time, row
    and size, and the edit that makes the readings continuous."""
    from thermocal.retrofit.data import meter_power

    rising = 14000.0 + 4.0 * np.arange(40)
    reset = rising.copy()
    reset[25:] = rising[25:] - rising[25] + 3.0
    with pytest.raises(ThermocalInputError) as info:
        meter_power(
            _readings(reset), energy=True, cumulative=True, interval=pd.Timedelta("1h"),
            label="log.csv, column 'Q_cum' (measurements.columns.heat)",
        )  # fmt: skip
    message = str(info.value)
    assert message.startswith("log.csv, column 'Q_cum' (measurements.columns.heat): ")
    assert "drops from 14,096.0 to 3.0 kWh (by 14,093.0 kWh)" in message, message
    assert "2001-02-02 01:00:00+00:00 (row 27 of the file)" in message, message
    assert "add 14,096.0 kWh" in message and "from that row on" in message
    roll = 99900.0 + 4.0 * np.arange(40)
    roll[roll >= 100000.0] -= 100000.0  # five digits
    with pytest.raises(ThermocalInputError, match="rolled over at 100,000 kWh: add 100,000"):
        meter_power(_readings(roll), energy=True, cumulative=True, interval="1h")
    from thermocal.retrofit.data import rollover_limit

    assert rollover_limit(99988.7, 2.5) == 100000.0 and rollover_limit(14973.6, 0.0) is None
    # a reading re-read a little lower (jitter: it falls by 2 kWh, then rises by 10) and a
    # gap are not a reset
    jitter = rising.copy()
    jitter[10] -= 6.0
    jitter[20] = np.nan
    assert np.diff(jitter)[9] == -2.0  # a real fall
    power = meter_power(_readings(jitter), energy=True, cumulative=True, interval="1h")
    assert power.iloc[:-1].notna().sum() == 37 and np.isnan(power.iloc[-1])
    assert power.iloc[9] < 0.0  # read as it is, not refused
    # the tolerance is READING_DROP_FACTOR times the 95th percentile of the rises (4 kWh):
    # a level that falls by just less is read, by just more refused
    from thermocal.retrofit.data import READING_DROP_FACTOR

    tolerance = READING_DROP_FACTOR * 4.0
    for fall, refused in ((0.95 * tolerance, False), (1.05 * tolerance, True)):
        step = rising.copy()
        step[25:] -= 4.0 + fall  # the reading at row 25 is `fall` below the one before
        if refused:
            with pytest.raises(ThermocalInputError, match="a cumulative meter reading never "):
                meter_power(_readings(step), energy=True, cumulative=True, interval="1h")
        else:
            meter_power(_readings(step), energy=True, cumulative=True, interval="1h")


# ------------------------------------------------------------------------------------------
# V-S2: reading steps in the file's unit
# ------------------------------------------------------------------------------------------
def test_reading_steps_are_compared_in_the_file_unit():
    """Energies are read into J: 1e7-1e8 J "were" multiples of 2 J within the relative
    tolerance, the smaller post-retrofit values of 0.5 J, and every retrofit metered in kWh
    got a note of an exchanged meter (fuzz5 v02, v31, v33, v35). Continuous readings have
    no step; a real change of step (1 kWh -> 0.1 kWh) is named in kWh."""
    from thermocal.retrofit.verify_periods import _resolution, sensor_change_notes

    rng = np.random.default_rng(2)
    assert np.isnan(_resolution(rng.uniform(1e6, 3e7, 500)))
    assert _resolution(np.round(rng.uniform(1.0, 30.0, 500), 1)) == 0.1
    from thermocal.retrofit.data import values_in_file_units

    index = pd.date_range("2001-01-29", periods=1000, freq="h", tz="UTC")
    kwh = rng.uniform(1.0, 12.0, len(index))
    date = index[500]
    raw = pd.DataFrame({"heat": kwh * 3.6e6}, index=index)
    raw.attrs["measurements"] = {"units": {"heat": "J"}, "units_in_file": {"heat": "kWh"}}
    pre, post = (index[0], date), (date, index[-1])
    assert sensor_change_notes(values_in_file_units(raw), pre, post, {}, "m.csv") == []
    stepped = np.where(index < date, np.round(kwh), np.round(kwh, 1)) * 3.6e6
    raw["heat"] = stepped
    notes = sensor_change_notes(values_in_file_units(raw), pre, post, {"heat": "Q"}, "m.csv")
    assert len(notes) == 1 and "column 'Q'" in notes[0] and "(1 before, 0.1 after)" in notes[0]
    # a gas meter's m3, read as kWh times the calorific value: back in m3
    raw["heat"] = np.round(kwh, 2) * 10.5 * 3.6e6
    assert values_in_file_units(raw, 10.5)["heat"].to_numpy() == pytest.approx(np.round(kwh, 2))


# ------------------------------------------------------------------------------------------
# U1, V-S5: periods and the measurements
# ------------------------------------------------------------------------------------------
def _section(**keys):
    from thermocal.retrofit.verify import VerifySection

    return VerifySection(retrofit_date="2001-02-19", prediction={"measures": ["roof"]}, **keys)


def test_periods_beyond_the_measurements_are_clipped_or_refused():
    """A pre_start before the data was reported as the baseline period (fuzz5 v39:
    "2000-12-01 to 2001-02-19" for data from 2001-01-29); now the period starts with the data
    and a note says so. A period entirely outside the data is refused naming its key; the
    default post period ends with the last metered heat (a cumulative meter's last row)."""
    from thermocal.retrofit.verify_periods import split_periods

    index = pd.date_range("2001-01-29", "2001-03-11 23:00", freq="h", tz="UTC")
    heat = pd.Series(1000.0, index=index)
    heat.iloc[-1] = np.nan  # a cumulative reading's last row
    pre, post, date, notes = split_periods(index, _section(pre_start="2000-12-01"), "m.csv", heat)
    assert pre[0] == index[0] and post[1] == index[-1]
    assert date == pd.Timestamp("2001-02-19", tz="UTC")
    assert len(notes) == 1 and "verify.pre_start 2000-12-01 lies before" in notes[0]
    assert "(2001-01-29 00:00)" in notes[0]
    _, post, _, notes = split_periods(index, _section(post_end="2001-04-01"), "m.csv", heat)
    assert post[1] == index[-1] and "verify.post_end 2001-04-01 lies after" in notes[0]
    _, post, _, notes = split_periods(index, _section(), "m.csv", heat)
    assert post[1] == index[-1] and notes == []
    with pytest.raises(ThermocalInputError, match="verify.pre_end 2001-01-10: the measurements"):
        split_periods(index, _section(pre_start="2000-12-01", pre_end="2001-01-10"), "m", heat)
    with pytest.raises(ThermocalInputError, match="verify.post_start 2001-03-20: the measured"):
        split_periods(index, _section(post_start="2001-03-20"), "m.csv", heat)


def _period_frame(phi_h: float) -> pd.DataFrame:
    """Two days of complete model inputs, 20 C inside, 2 C outside, ``phi_h`` [W]."""
    from thermocal.retrofit.calibration import BOUNDARY_COLUMNS, HEAT_COLUMNS, OUTPUT_COLUMN

    index = pd.date_range("2001-02-19", periods=48, freq="h", tz="UTC")
    data = pd.DataFrame({c: 0.0 for c in BOUNDARY_COLUMNS + HEAT_COLUMNS}, index=index)
    data["Te"] = 2.0
    data["phi_h"] = phi_h
    data[OUTPUT_COLUMN] = 20.0
    return data


def _heat_meter_config():
    from thermocal.retrofit.config import parse_config

    return parse_config(
        {"building": "b.yaml", "weather": {"file": "w.epw"},
         "measurements": {"file": "m.csv", "heat_source": "heat_meter", "heat_unit": "kWh",
                          "columns": {"heat": "Q"}}},
        source="cfg.yaml",
    )  # fmt: skip


def test_period_checks_speak_of_the_verification_keys():
    """Missing inputs in a period were reported "in the training period ... (fill or shorten
    the period)" (fuzz5 v05, v27), then rewritten by string replacement of another module's
    wording (review); the checks take the period's name and keys, and verify passes its own."""
    from thermocal.retrofit.calibration import check_training_data
    from thermocal.retrofit.verify import check_period_data

    data = _period_frame(3000.0)
    data.loc[data.index[:5], "phi_sol"] = np.nan
    with pytest.raises(ThermocalInputError) as info:
        check_period_data(_heat_meter_config(), data, "post", "m.csv", 400.0)
    message = str(info.value)
    assert message.startswith("m.csv (post-retrofit period): input 'phi_sol' has 5 missing")
    assert "in the post-retrofit period" in message and "training" not in message, message
    assert "move verify.post_start / verify.post_end to leave them out" in message, message
    # the retrofit analysis names its own period and keys (the default)
    with pytest.raises(ThermocalInputError, match=(
        r"in the training period .* \(fill them in the file, or move periods\.training_start "
        r"/ periods\.training_days to leave them out\)"
    )):  # fmt: skip
        check_training_data(data, "m.csv")
    negative = _period_frame(3000.0)
    negative.loc[negative.index[::2], "phi_h"] = -3000.0
    negative.loc[negative.index[1::2], "phi_h"] = 9000.0
    with pytest.raises(ThermocalInputError, match=r"in 24 of 48 intervals of the pre-retrofit "):
        check_period_data(_heat_meter_config(), negative, "pre", "m.csv", 400.0)


# ------------------------------------------------------------------------------------------
# review: the building file describes the house before the retrofit
# ------------------------------------------------------------------------------------------
def test_the_post_period_is_checked_for_upward_unit_slips_alone():
    """``check_heating_power_magnitude`` compares the heat with the building file's losses,
    which describe the house before the retrofit: a deep retrofit's post period (0.04 times
    them) was refused as "far too small". The pre period keeps both bounds, the post period
    the upper one (a cumulative reading, kWh read as W)."""
    from thermocal.retrofit.verify import check_period_data

    cfg = _heat_meter_config()
    deep = _period_frame(0.04 * 400.0 * 18.0)
    check_period_data(cfg, deep, "post", "m.csv", 400.0)
    with pytest.raises(ThermocalInputError, match=r"over the pre-retrofit period, 0\.04 times"):
        check_period_data(cfg, deep, "pre", "m.csv", 400.0)
    slip = _period_frame(30.0 * 400.0 * 18.0)
    with pytest.raises(ThermocalInputError) as info:
        check_period_data(cfg, slip, "post", "m.csv", 400.0)
    message = str(info.value)
    assert "over the post-retrofit period, 30 times" in message and "far too large" in message
    assert "kWh and MJ by 3.6" in message, message


def test_a_deep_retrofit_is_verified(demo_folder, tmp_path):
    """The review's reproduction: the demo's heat after the retrofit scaled to 12 % (an
    EnerPHit-like retrofit) exited 2 with "far too small for a heated building"; it is a
    saving of about 95 %, far more than the 61 % predicted."""

    def deep(frame):
        after = pd.to_datetime(frame["time"]) >= "2001-02-19"
        return _heat_w(frame) / 1e3 * np.where(after, 0.12, 1.0)

    path = _meter_config(demo_folder, tmp_path, deep, heat_unit="kW")
    ver = run_verify(load_verify_config(path))
    saving = ver.comparison["measured_saving_pct"]["value"]
    assert 90.0 < saving < 99.0, saving
    assert ver.comparison["verdict"] == "prebound", ver.comparison["verdict"]


# ------------------------------------------------------------------------------------------
# review: internal gains checked on every path, no division by a baseline without heat
# ------------------------------------------------------------------------------------------
def test_internal_gains_beyond_a_home_are_refused_before_verifying(demo_folder, tmp_path):
    """``internal_gains: {source: constant, constant_W: 40000}`` on 220 m2 was refused by
    ``thermocal retrofit`` only; ``thermocal verify`` calibrated, then crashed with a
    ZeroDivisionError (the baseline needed no heat)."""
    cfg = yaml.safe_load(demo_folder.read_text())
    cfg["building"] = str(demo_folder.parent / cfg["building"])
    cfg["measurements"]["file"] = str(demo_folder.parent / cfg["measurements"]["file"])
    cfg["internal_gains"] = {"source": "constant", "constant_W": 40000}
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    with pytest.raises(ThermocalInputError, match=(
        r"internal_gains\.constant_W: 40,000 W is 182 W per m2 of heated floor \(220 m2"
    )):  # fmt: skip
        run_verify(load_verify_config(path))


def test_a_baseline_without_heat_is_refused_not_divided_by():
    """What remained of the ZeroDivisionError: a baseline model that needs no heat over the
    post period (gains that cover the losses, a period out of the heating season) is refused
    naming internal_gains and the period's keys; residuals correlated throughout give no
    interval rather than a division by zero."""
    from thermocal.retrofit.verify import check_baseline_heat, fractional_savings_uncertainty

    post = (pd.Timestamp("2001-02-19", tz="UTC"), pd.Timestamp("2001-03-11", tz="UTC"))
    check_baseline_heat(900.0, 950.0, 400.0, post, "m.csv", "not set")
    for base, old in ((0.0, 950.0), (0.0, -3.0)):  # the comfort baseline alone: named as such
        with pytest.raises(ThermocalInputError) as info:
            check_baseline_heat(base, old, 400.0, post, "m.csv", "constant_W 20,000 W")
        message = str(info.value)
        assert message.startswith("m.csv: the baseline model (calibrated on the pre-retrofit "
                                  "period) needs 0 kWh of heat")  # fmt: skip
        assert "where 400 kWh were metered" in message
        assert "Check internal_gains (now constant_W 20,000 W" in message
        assert "(verify.post_start / verify.post_end)" in message
    fsu = fractional_savings_uncertainty(10.0, 20, 20, 1.0, 0.5, 0.9)
    assert fsu["half_width"] == float("inf")


# ------------------------------------------------------------------------------------------
# V-S3: a boiler replaced with the retrofit
# ------------------------------------------------------------------------------------------
def test_a_boiler_replaced_with_the_retrofit(demo_folder, tmp_path):
    """Fuel of a boiler at 0.80 before and 0.95 after the retrofit date (fuzz5 v44): one
    measurements.boiler_efficiency credited the boiler's saving to the envelope (64.9 %
    against 58.5 % with the same boiler), with no note. verify.boiler_efficiency_after
    gives the new boiler's efficiency; without it a fuel meter gets a note."""
    def fuel_kwh(frame):
        after = pd.to_datetime(frame["time"]) >= "2001-02-19"
        return _heat_w(frame) / 1e3 / np.where(after, 0.95, 0.80)

    path = _meter_config(
        demo_folder, tmp_path, fuel_kwh, heat_unit="kWh", boiler_efficiency=0.80
    )
    cfg = yaml.safe_load(path.read_text())
    cfg["measurements"]["heat_source"] = "fuel_meter"
    cfg["verify"]["boiler_efficiency_after"] = 0.95
    path.write_text(yaml.safe_dump(cfg))
    ver = run_verify(load_verify_config(path))
    saving = ver.comparison["measured_saving_pct"]["value"]
    assert abs(saving - DEMO_SAVING_PCT) < 1.0, saving
    assert not any("fuel meter measures the fuel" in n for n in ver.notes)
    # the pure parts: the heat from the date on, the note, the key only for a fuel meter
    from thermocal.retrofit.verify import fuel_meter_note, with_boiler_after

    index = pd.date_range("2001-02-18", periods=48, freq="h", tz="UTC")
    inputs = pd.DataFrame({"phi_h_measured": 800.0, "phi_int": 200.0}, index=index)
    out = with_boiler_after(inputs, pd.Timestamp("2001-02-19", tz="UTC"), 0.80, 0.95)
    assert out["phi_h_measured"].iloc[0] == 800.0 and out["phi_h"].iloc[0] == 1000.0
    assert out["phi_h_measured"].iloc[-1] == pytest.approx(950.0)
    assert out["phi_h"].iloc[-1] == pytest.approx(1150.0)
    note = fuel_meter_note(load_verify_config(path).retrofit.measurements)
    assert "boiler_efficiency 0.8" in note and "verify.boiler_efficiency_after" in note
    # the same boiler has a way to say so, which the note names (review: the note fired on
    # every fuel-meter verification, with no documented way to answer it)
    assert note.endswith("if it is the same boiler, say so with "
                         "verify.boiler_efficiency_after: 0.8 (this note is then left out)")
    same = inputs.copy()
    same["phi_h"] = same["phi_h_measured"] + same["phi_int"]
    pd.testing.assert_frame_equal(
        with_boiler_after(same, pd.Timestamp("2001-02-19", tz="UTC"), 0.80, 0.80), same
    )
    cfg["measurements"].update(heat_source="heat_meter")
    cfg["measurements"].pop("boiler_efficiency")
    path.write_text(yaml.safe_dump(cfg))
    with pytest.raises(ThermocalInputError, match="boiler_efficiency_after applies to a fuel"):
        load_verify_config(path)


# ------------------------------------------------------------------------------------------
# V-S3 (v09), V-S4: the metered heat's scale against the building file and the periods
# ------------------------------------------------------------------------------------------
def test_warnings_on_the_scale_of_the_metered_heat():
    """Calibrated HLC against the building file's (fuzz5 v03, v35: 1,245 against 611 W/K),
    the baseline's bias against the meter (v32: kWh per 30 min read as kW, NMBE -56 %) and an
    HLC after the retrofit above the one before (v09: a new meter in MJ, 776 against 578
    W/K): each warned about; the demo's figures not. Review: the warnings blamed the units for
    what is more often unmodelled internal gains (a shop, a server room, internal_gains
    unset): internal_gains come first, a unit only near the factor of a slip (2, 3.6, 1000),
    the building file's description first between 1.7 and 2."""
    from thermocal.retrofit.config import MeasurementsConfig
    from thermocal.retrofit.verify import (
        baseline_bias_warning,
        described_hlc_warning,
        heat_unit_keys,
        hlc_rise_warning,
        unit_slip_near,
    )

    gas = MeasurementsConfig(
        file="m.csv", columns={"temp_out": "Te", "dni": "DNI", "dhi": "DHI", "temp_in": "Ti",
                               "heat": "gas"},
        heat_source="fuel_meter", heat_unit="m3", fuel_kWh_per_unit=10.5, boiler_efficiency=0.9,
    )  # fmt: skip
    keys = heat_unit_keys(gas)
    assert "measurements.heat_unit (now m3" in keys and "the heat column 'gas'" in keys
    assert "fuel_kWh_per_unit (now 10.5 kWh per m3" in keys and "boiler_efficiency (now 0.9" in keys

    def hlc(ratio, gains="not set"):
        return described_hlc_warning(611.0 * ratio, 611.0, keys, gains, "fuel_meter")

    far = hlc(1245.0 / 611.0)
    assert "1,245 W/K, is 2.04 times the building file's calculated 611 W/K" in far
    assert "Also, the factor 2.04 is near 2, a unit slip (kWh per half-hourly row" in far
    assert far.endswith(f"check {keys}.")
    assert described_hlc_warning(578.0, 611.0, keys, "not set", "fuel_meter") is None
    # less heat than described, not near a slip: internal gains first, no unit
    shop = hlc(0.35, "constant_W 400 W")
    assert "is 0.35 times" in shop and keys not in shop
    assert "Likely heat the model is not told of: internal gains missing from internal_gains " \
           "(now constant_W 400 W; a shop, a server room" in shop
    assert shop.index("internal_gains") < shop.index("the building file's description")
    # more heat than described: the gains configured, then hot water on the meter
    assert "Likely heat metered that the rooms do not lose: internal_gains (now constant_W " \
           "4,000 W) larger than the house's" in hlc(2.8, "constant_W 4,000 W")
    # between 1.7 and 2: the description first
    assert "Likely the building file's description (old houses'" in hlc(1.75)
    assert keys not in hlc(1.75)
    # near 1000: a unit, nothing else
    assert hlc(1.0 / 950.0).startswith("the heat loss coefficient") and "Likely a unit: the " \
        "factor 950 is near 1,000" in hlc(1.0 / 950.0)
    # the slips of the source's units: a flow has no factor 2, l/s and m3/h differ by 3.6
    assert unit_slip_near(0.5, "hydronic") is None and unit_slip_near(0.5, "heat_meter")[0] == 2
    assert unit_slip_near(3.7, "hydronic") == (3.6, "l/s read as m3/h, or the reverse")
    assert unit_slip_near(1 / 58.0, "hydronic")[0] == 60.0
    # the baseline's bias: metered over model heat 1 / (1 - NMBE)
    bias = baseline_bias_warning(-56.3, keys, "not set", "fuel_meter")
    assert "needs 56 % more heat than was metered" in bias and keys not in bias
    assert "Likely heat the model is not told of: internal gains missing from internal_gains " \
           "(now not set" in bias
    half = baseline_bias_warning(50.0, keys, "not set", "fuel_meter")
    assert "Also, the factor 2 is near 2" in half and keys in half
    assert "needs no heat, where heat was metered," in baseline_bias_warning(
        150.0, keys, "not set", "fuel_meter")
    assert baseline_bias_warning(-2.4, keys, "not set", "fuel_meter") is None
    pre = {"value": 578.0, "lo": 548.0, "hi": 632.0}
    rise = hlc_rise_warning(pre, {"value": 776.0, "lo": 734.0, "hi": 820.0}, keys)
    assert "776 W/K (734 to 820), is above the one before, 578 W/K" in rise
    assert hlc_rise_warning(pre, {"value": 276.0, "lo": 261.0, "hi": 367.0}, keys) is None
    assert hlc_rise_warning(pre, {"value": 600.0, "lo": 560.0, "hi": 650.0}, keys) is None


def test_a_meter_in_another_unit_after_the_retrofit_is_warned_about(demo_folder, tmp_path):
    """A new heat meter in MJ after the retrofit date, the configuration still in kWh (fuzz5
    v09): the verification said -49 % saved and HLC 776 W/K after against 578 before,
    without a word; now its warnings say the HLC rose and name the heat's unit."""

    def kwh_then_mj(frame):
        after = pd.to_datetime(frame["time"]) >= "2001-02-19"
        return _heat_w(frame) / 1e3 * np.where(after, 3.6, 1.0)

    path = _meter_config(demo_folder, tmp_path, kwh_then_mj, heat_unit="kWh")
    ver = run_verify(load_verify_config(path))
    warnings = ver.comparison["warnings"]
    assert any("is above the one before" in w for w in warnings), warnings
    assert all("measurements.heat_unit (now kWh" in w for w in warnings), warnings


# ------------------------------------------------------------------------------------------
# D1: the documented Python API
# ------------------------------------------------------------------------------------------
def test_the_documented_python_api_resolves(tmp_path):
    """docs/verify.md lists write_verify_outputs with thermocal.retrofit.verify (fuzz5 a04:
    AttributeError); prepare_verify_demo returns the configuration's path and the truth."""
    from thermocal.retrofit import verify, verify_report
    from thermocal.retrofit.verify import load_verify_config as documented_load

    assert verify.write_verify_outputs is verify_report.write_verify_outputs
    config, truth = verify.prepare_verify_demo(tmp_path)
    assert config.name == "config.yaml" and "annual_saving_pct" in truth
    assert documented_load(config).verify.retrofit_date == truth["retrofit_date"]
    with pytest.raises(AttributeError):
        verify.no_such_function  # noqa: B018
