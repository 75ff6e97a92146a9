"""Heat meter columns read into the heating power (exploratory testing of the meter paths).

- A cumulative reading that JUMPS UP (a meter replaced by one starting at a higher register,
  a misentered reading) passed silently, only drops were refused: +300 kWh on one day of the
  verify demo turned its measured saving from 58.3 % into 45.5 % ("REBOUND"), exit 0; in
  ``thermocal retrofit`` the HLC went from 566 to 718 W/K (+500 kWh) or 1,260 W/K (+2,000).
- An energy per row was divided by the time to the NEXT row: the row before a missing row
  was spread over two intervals at half its power (15-min kWh rows, 7 % missing: HLC 554.5
  instead of 566.2 W/K; the same rows in W gave 566.2).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import yaml
from retrofit_synthetic import make_dataset

from thermocal.errors import ThermocalInputError
from thermocal.retrofit.config import MeasurementsConfig
from thermocal.retrofit.data import (
    READING_JUMP_FACTOR,
    meter_power,
    prepare_measurements,
    read_raw_measurements,
)


def _heat_w(frame: pd.DataFrame) -> np.ndarray:
    """The hydronic heating power of a demo or synthetic log [W] (flow in l/h)."""
    from thermocal.physics.hydronics import heating_power

    return heating_power(frame["V_dot"] / 3.6e6, frame["T_supply"], frame["T_return"]).to_numpy(
        float
    )


def _as_heat_meter(config, folder, column, **measurements):
    """The configuration ``config`` with its heat as the meter column ``Q`` (``column`` of the
    log frame) in ``folder``; returns the new configuration's path."""
    cfg = yaml.safe_load(config.read_text())
    frame = pd.read_csv(config.parent / cfg["measurements"]["file"])
    frame["Q"] = column(frame)
    folder.mkdir(parents=True, exist_ok=True)
    frame.drop(columns=["V_dot", "T_supply", "T_return"]).to_csv(folder / "m.csv", index=False)
    cfg["building"] = str(config.parent / cfg["building"])
    weather = cfg["weather"]["file"]
    if not weather.startswith("pvlib:"):
        cfg["weather"]["file"] = str(config.parent / weather)
    mc = cfg["measurements"]
    mc["file"] = str(folder / "m.csv")
    for key in ("flow", "temp_supply", "temp_return"):
        mc["columns"].pop(key)
    mc.pop("flow_unit")
    mc["columns"]["heat"] = "Q"
    mc.update({"heat_source": "heat_meter", **measurements})
    path = folder / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


def _reading_kwh(power_w: np.ndarray, jump_kwh: float = 0.0, at: int | None = None):
    """A heat meter's reading [kWh] at each hourly row's start, 0.1 kWh resolution, with
    ``jump_kwh`` added from row ``at`` on."""
    reading = 12345.0 + np.concatenate([[0.0], np.cumsum(power_w)[:-1]]) / 1e3
    if at is not None:
        reading[at:] += jump_kwh
    return np.round(reading, 1)


# ------------------------------------------------------------------------------------------
# Bug A: a cumulative reading that jumps up
# ------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def verify_demo(tmp_path_factory):
    from thermocal.demos.verify import prepare_verify_demo

    config, _ = prepare_verify_demo(tmp_path_factory.mktemp("verify-jump"))
    return config


def test_a_jumping_reading_is_refused_by_verify_naming_column_time_and_size(verify_demo, tmp_path):
    """The tester's case: the verify demo's heat as a cumulative kWh reading, +300 kWh from
    2001-02-26 00:00 (post period). Before: verified at 45.5 % instead of 58.3 %, "REBOUND",
    no message. The clean reading passes the same checks."""
    from thermocal.retrofit.verify import load_verify_config, prepare_inputs

    frame = pd.read_csv(verify_demo.parent / "measurements.csv")
    at = int(np.flatnonzero(frame["time"] == "2001-02-26 00:00")[0])
    clean = _as_heat_meter(
        verify_demo, tmp_path / "clean", lambda f: _reading_kwh(_heat_w(f)),
        heat_unit="kWh", heat_cumulative=True,
    )  # fmt: skip
    vcfg = load_verify_config(clean)
    inputs = prepare_inputs(vcfg.retrofit, vcfg.source)[2]  # not refused
    assert np.nanmax(inputs["phi_h_measured"]) < 3e4
    jumped = _as_heat_meter(
        verify_demo, tmp_path / "jump", lambda f: _reading_kwh(_heat_w(f), 300.0, at),
        heat_unit="kWh", heat_cumulative=True,
    )  # fmt: skip
    reading = _reading_kwh(_heat_w(frame), 300.0, at)
    vcfg = load_verify_config(jumped)
    with pytest.raises(ThermocalInputError) as info:
        prepare_inputs(vcfg.retrofit, vcfg.source)
    message = str(info.value)
    assert message.startswith(f"{tmp_path / 'jump' / 'm.csv'}, column 'Q' (measurements.columns"
                              ".heat): a cumulative meter reading rises"), message  # fmt: skip
    assert f"jumps from {reading[at - 1]:,.1f} to {reading[at]:,.1f} kWh" in message, message
    assert f"(by {reading[at] - reading[at - 1]:,.1f} kWh in 1h" in message, message
    assert f"at 2001-02-26 00:00:00-05:00 (row {at + 2} of the file)" in message, message
    assert "meter was replaced there" in message and "from every reading from that row on" in (
        message
    )


def test_a_jumping_reading_is_refused_by_retrofit_and_peaks_are_not(tmp_path):
    """``thermocal retrofit`` on a house with a night setback (morning boosts up to the
    14 kW emitter) and a cold snap at 3 times the heat for three hours: no refusal; +500 kWh
    at one row (the tester's cum_jump_train500: HLC 718 instead of 566 W/K): refused before
    the calibration, naming the column, the time and the row."""
    from thermocal.retrofit.config import load_config
    from thermocal.retrofit.workflow import run_retrofit

    config = make_dataset(tmp_path / "house", days=16.0)
    frame = pd.read_csv(config.parent / "measurements.csv")
    power, time = _heat_w(frame), pd.to_datetime(frame["time"])
    snap = (time >= "2001-02-08 06:00") & (time < "2001-02-08 09:00")
    power = np.where(snap, 3.0 * power, power)
    at = int(np.flatnonzero(time == "2001-02-10 08:00")[0])
    peaks = _as_heat_meter(
        config, tmp_path / "peaks", lambda f: _reading_kwh(power),
        heat_unit="kWh", heat_cumulative=True,
    )  # fmt: skip
    mc = load_config(peaks).measurements
    grid, _ = prepare_measurements(
        read_raw_measurements(mc, default_tz=-5.0), mc.step, heat_source=mc.heat_source,
        heat_energy=True, heat_cumulative=True, columns=mc.columns,
    )  # fmt: skip
    # the cold snap's hours (under 1 % of the record) are far above its other hours, and not
    # refused
    in_snap = np.asarray(snap)
    assert np.nanmax(grid["phi_h"][in_snap]) > 2.5 * np.nanmax(grid["phi_h"][~in_snap])
    jumped = _as_heat_meter(
        config, tmp_path / "jump", lambda f: _reading_kwh(power, 500.0, at),
        heat_unit="kWh", heat_cumulative=True,
    )  # fmt: skip
    with pytest.raises(ThermocalInputError) as info:
        run_retrofit(load_config(jumped))
    message = str(info.value)
    assert "column 'Q' (measurements.columns.heat)" in message, message
    assert f"at 2001-02-10 08:00:00-05:00 (row {at + 2} of the file)" in message, message
    assert f"more than {READING_JUMP_FACTOR:g} times the record's 99th-percentile" in message


def _readings(values_kwh, index=None) -> pd.Series:
    if index is None:
        index = pd.date_range("2001-02-01", periods=len(values_kwh), freq="h", tz="UTC")
    return pd.Series(np.asarray(values_kwh, float) * 3.6e6, index=index)


def test_a_jump_is_told_from_a_misentered_value_a_gap_and_a_close_reading():
    """A single value too high (the next reading back near the one before) is named as a
    misentered value, not as a drop at the next row; a reading after a day without rows
    (a large rise at the usual power) and a reading seconds after the last one (a small rise
    at a high power) are no jumps."""
    rng = np.random.default_rng(1)
    rises = rng.uniform(3.0, 8.0, 200)
    reading = 5000.0 + np.concatenate([[0.0], np.cumsum(rises)])
    spike = reading.copy()
    spike[120] += 400.0
    with pytest.raises(ThermocalInputError) as info:
        meter_power(_readings(spike), energy=True, cumulative=True, interval="1h", label="Q")
    message = str(info.value)
    assert "at 2001-02-06 00:00:00+00:00 (row 122 of the file)" in message, message
    assert "a misentered value: correct it, or delete it" in message, message
    assert "drops" not in message
    # 24 missing rows: the next reading rises by 25 hours' heat, at the usual mean power
    index = pd.date_range("2001-02-01", periods=len(reading), freq="h", tz="UTC")
    gap = index.delete(slice(100, 124))
    power = meter_power(
        _readings(np.delete(reading, slice(100, 124)), gap), energy=True, cumulative=True,
        interval="1h",
    )  # fmt: skip
    assert power.iloc[99] == pytest.approx(rises[99:124].sum() / 25.0 * 1e3)
    # a reading 10 s after the last one, 0.1 kWh higher: 36 kW, but no jump
    close = index.insert(51, index[50] + pd.Timedelta(seconds=10))
    close_reading = np.insert(reading, 51, reading[50] + 0.1)
    power = meter_power(
        _readings(close_reading, close), energy=True, cumulative=True, interval="1h"
    )  # fmt: skip
    assert power.iloc[50] == pytest.approx(0.1 * 3.6e6 / 10.0)


# ------------------------------------------------------------------------------------------
# Bug B: energy per row with missing rows
# ------------------------------------------------------------------------------------------
def _quarter_hour_log(folder, rows: str, energy: bool):
    """Four days of 15-min rows with one row missing in 28 of the hours (7 %), the heat in
    kWh per row or in W, labelled by the interval's start or end; returns the configuration."""
    index = pd.date_range("2001-02-02", periods=4 * 96, freq="15min")
    hours = np.arange(len(index)) / 4.0
    power = 4000.0 + 2500.0 * np.sin(2.0 * np.pi * hours / 24.0) + 800.0 * np.cos(hours)
    rng = np.random.default_rng(7)
    missing = 4 * rng.choice(96, size=28, replace=False) + rng.integers(0, 4, size=28)
    keep = np.setdiff1d(np.arange(len(index)), missing)
    stamps = index + (pd.Timedelta("15min") if rows == "interval_end" else pd.Timedelta(0))
    log = pd.DataFrame({
        "time": stamps.strftime("%Y-%m-%d %H:%M"), "Te": 2.0, "DNI": 0.0, "DHI": 0.0,
        "Ti": 20.0, "Q": power * 0.25 / 1e3 if energy else power,
    }).iloc[keep]  # fmt: skip
    folder.mkdir(parents=True, exist_ok=True)
    log.to_csv(folder / "log.csv", index=False)
    cfg = MeasurementsConfig(
        file=folder / "log.csv", heat_source="heat_meter", heat_unit="kWh" if energy else "W",
        rows=rows, timezone=1.0,
        columns={"temp_out": "Te", "heat": "Q", "dni": "DNI", "dhi": "DHI", "temp_in": "Ti"},
    )  # fmt: skip
    return cfg


@pytest.mark.parametrize("rows", ["interval_start", "interval_end"])
def test_energy_per_row_with_missing_rows_gives_the_power_column_s_heat(tmp_path, rows):
    """kWh per 15-min row with 7 % of the rows missing (at most one an hour): each row's
    energy is its own 15 minutes' heat, a missing row a gap, and the hourly heating power
    equals that of the same rows in W (before: the row before a missing row at half its
    power, the hourly means up to 1/8 low, the HLC 554.5 instead of 566.2 W/K)."""
    grids = {}
    for energy in (True, False):
        cfg = _quarter_hour_log(tmp_path / str(energy), rows, energy)
        raw = read_raw_measurements(cfg)
        grids[energy], _ = prepare_measurements(
            raw, "1h", heat_source="heat_meter", heat_energy=energy, columns=cfg.columns
        )
    np.testing.assert_allclose(
        grids[True]["phi_h"].to_numpy(), grids[False]["phi_h"].to_numpy(), rtol=1e-9
    )
    # and each hour's heat is the mean of its present quarter hours
    frame = pd.read_csv(tmp_path / "True" / "log.csv")
    stamps = pd.to_datetime(frame["time"]) - (
        pd.Timedelta("15min") if rows == "interval_end" else pd.Timedelta(0)
    )
    hourly = (frame["Q"] * 4e3).groupby(stamps.dt.floor("h").to_numpy()).mean()
    np.testing.assert_allclose(grids[True]["phi_h"].to_numpy(), hourly.to_numpy(), rtol=1e-9)


def test_an_energy_per_row_is_divided_by_its_own_interval():
    """Rows at 0, 15, 45 and 60 min (the 30-min row missing): 1 kWh in each row is 4 kW,
    not 2 kW for the row before the gap; a cumulative reading keeps the time to the next
    reading (its difference covers the missing row too)."""
    index = pd.DatetimeIndex(
        ["2001-02-02 00:00", "2001-02-02 00:15", "2001-02-02 00:45", "2001-02-02 01:00"],
        tz="UTC",
    )
    kwh = pd.Series(3.6e6, index=index)
    power = meter_power(kwh, energy=True, cumulative=False, interval=pd.Timedelta("15min"))
    np.testing.assert_allclose(power.to_numpy(), 4000.0)
    reading = pd.Series(np.array([0.0, 1.0, 3.0, 4.0]) * 3.6e6, index=index)
    power = meter_power(reading, energy=True, cumulative=True, interval=pd.Timedelta("15min"))
    np.testing.assert_allclose(power.to_numpy()[:3], 4000.0)


def test_heating_after_weeks_of_almost_none_is_not_a_jump_and_thinned_rows_keep_their_length():
    """A review, 2026-11-30: 60 days of 0.02 kWh an hour, then 12 hours of heating at 4 kWh,
    were refused as jumps (their 99th percentile 0.02 kWh); and an energy per row whose log
    thins from 15 to 30 min rows had its 30-min rows divided by 15 min (4000 W for 2000)."""
    import numpy as np
    import pandas as pd

    from thermocal.retrofit.data import meter_power, reading_jumps

    rises = np.r_[np.full(60 * 24, 0.02), np.full(12, 4.0)]
    readings = np.r_[100.0, 100.0 + np.cumsum(rises)]
    hours = np.arange(readings.size) * 3600.0
    assert reading_jumps(readings, hours)[0].size == 0
    # one replaced meter among the same rises is still a jump
    jumped = readings.copy()
    jumped[700:] += 500.0
    assert reading_jumps(jumped, hours)[0].tolist() == [700]
    times = pd.DatetimeIndex(
        list(pd.date_range("2024-01-01", periods=128, freq="15min"))
        + list(pd.date_range("2024-01-02 08:00", periods=32, freq="30min")),
        tz="UTC",
    )
    energy = pd.Series(
        np.r_[np.full(128, 2000.0 * 900), np.full(32, 2000.0 * 1800)], index=times
    )  # J per row at a true 2000 W
    power = meter_power(energy, energy=True, cumulative=False, interval=pd.Timedelta("15min"),
                        label="log.csv, column 'heat'", unit=("J", 1.0))  # fmt: skip
    assert np.allclose(power.iloc[:127], 2000.0) and np.allclose(power.iloc[129:], 2000.0)
