"""The identification demo data: regenerable, and shaped like paper 001's sensor network.

The shipped copy (``src/thermocal/data/identification_demo``) must equal what the generator
produces with the default seed. The comparison is exact (times to the second, values to the
bit). The multi-zone kernel is compiled with numba ``fastmath``: on another CPU the last bits of
a temperature may differ, which can move a threshold crossing by a second or flip a value across
a quantisation boundary. When the exact comparison fails, the test therefore falls back to a
tolerance of one quantisation step (0.05 C) on the values and one second on the times, for at
most 0.1 % of the reports, and says so in the failure message of the exact part; a wrong
generator or stale data changes far more than that.
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
import yaml

from thermocal.demos import buildings as generators
from thermocal.demos import identification as dd
from thermocal.io.measurements import read_measurements, resample_measurements

FOLDER = dd.DEMO_FOLDER


@pytest.fixture(scope="module")
def regenerated():
    return dd.generate()


@pytest.fixture(scope="module")
def shipped_log():
    return pd.read_parquet(FOLDER / dd.SENSORS_FILE)


@pytest.fixture(scope="module")
def truth():
    return json.loads((FOLDER / dd.TRUTH_FILE).read_text(encoding="utf-8"))


def _seconds(times) -> np.ndarray:
    return (pd.DatetimeIndex(times).tz_convert("UTC").as_unit("s").asi8).astype(np.int64)


def test_shipped_log_equals_regenerated(regenerated, shipped_log):
    new = regenerated["log"]
    assert list(shipped_log.columns) == ["time", "sensor", "value", "unit"]
    assert str(shipped_log["time"].dt.tz) == str(new["time"].dt.tz) == "UTC-05:00"
    t_old, t_new = _seconds(shipped_log["time"]), _seconds(new["time"])
    exact = (
        len(t_old) == len(t_new)
        and np.array_equal(t_old, t_new)
        and np.array_equal(shipped_log["sensor"].to_numpy(), new["sensor"].to_numpy())
        and np.array_equal(shipped_log["value"].to_numpy(), new["value"].to_numpy())
    )
    if exact:
        return
    # tolerant fallback (numba fastmath on another CPU): per sensor, reports matched in time
    n_bad = abs(len(t_old) - len(t_new))
    for sensor in sorted(set(new["sensor"])):
        a = shipped_log[shipped_log["sensor"] == sensor]
        b = new[new["sensor"] == sensor]
        ta, tb = _seconds(a["time"]), _seconds(b["time"])
        idx = np.clip(np.searchsorted(tb, ta), 0, len(tb) - 1)
        idx_prev = np.clip(idx - 1, 0, len(tb) - 1)
        nearest = np.where(np.abs(tb[idx] - ta) <= np.abs(tb[idx_prev] - ta), idx, idx_prev)
        dt = np.abs(tb[nearest] - ta)
        dv = np.abs(b["value"].to_numpy()[nearest] - a["value"].to_numpy())
        n_bad += int(np.sum((dt > 1) | (dv > dd.QUANTUM + 1e-9)))
    assert n_bad <= 1e-3 * len(t_new), (
        f"the shipped sensor log differs from the regenerated one in {n_bad} of {len(t_new)} "
        "reports: regenerate it with `python -m thermocal.demos.identification --write "
        "src/thermocal/data/identification_demo`"
    )


def test_shipped_mapping_truth_and_loads_equal_regenerated(regenerated, truth):
    mapping = yaml.safe_load((FOLDER / dd.MAPPING_FILE).read_text(encoding="utf-8"))
    assert mapping == regenerated["mapping"]
    assert truth["parameters"] == regenerated["truth"]["parameters"]
    assert truth["sensor_offsets"] == regenerated["truth"]["sensor_offsets"]
    assert truth["defects"] == regenerated["truth"]["defects"]
    assert truth["equipment_rooms"] == regenerated["truth"]["equipment_rooms"]
    loads = pd.read_parquet(FOLDER / dd.TRUE_LOADS_FILE)
    new = regenerated["true_loads"]
    assert len(loads) == len(new) == 31 * 288
    np.testing.assert_allclose(loads["total"].to_numpy(), new["total"].to_numpy(), rtol=1e-6)


def test_log_reads_with_thermocal_io_and_resamples_with_the_gaps(truth):
    raw, meta = read_measurements(FOLDER / dd.SENSORS_FILE, layout="long")
    assert len(meta["sensors"]) == 82
    assert set(meta["units"].values()) == {"C"}
    assert set(meta["quantities"].values()) == {"temperature"}
    start, end = (pd.Timestamp(t) for t in truth["generator"]["period"])
    grid, report = resample_measurements(raw, "5min", max_gap=dd.MAX_GAP, start=start, end=end)
    assert grid.shape == (31 * 288, 82)
    assert grid.index[0] == start and grid.index[-1] == end - pd.Timedelta("5min")
    table = report.table if hasattr(report, "table") else None
    with_gaps = {s for s in grid.columns if grid[s].isna().any()}
    defects = truth["defects"]
    expected = {d["sensor"] for d in defects["dropouts"]} | {defects["dead_sensor"]}
    assert with_gaps == expected, table
    # the dead sensor is silent from its death to the end
    dead = grid[defects["dead_sensor"]]
    died = pd.Timestamp(defects["dead_after"])
    assert dead.loc[died + pd.Timedelta("15min") :].isna().all()
    assert dead.loc[: died - pd.Timedelta("10min")].notna().all()
    # temperatures are plausible room temperatures
    assert 15.0 < float(np.nanmedian(grid.to_numpy())) < 22.0


def test_network_shape_like_paper_001(truth):
    log = pd.read_parquet(FOLDER / dd.SENSORS_FILE)
    mapping = yaml.safe_load((FOLDER / dd.MAPPING_FILE).read_text(encoding="utf-8"))
    building = generators.clinic()
    sensors = mapping["sensors"]
    assert 75 <= len(sensors) <= 90
    assert set(log["sensor"]) == set(sensors)
    assert set(sensors.values()) <= set(building.zones)
    zones_with_sensor = set(sensors.values())
    counts = pd.Series(list(sensors.values())).value_counts()
    assert (counts == 2).sum() == dd.N_DOUBLE and counts.max() == 2
    # corridors and equipment rooms have none; not every room has one
    assert not any(z.startswith("Corridor") for z in zones_with_sensor)
    assert not set(truth["equipment_rooms"]) & zones_with_sensor
    assert len(zones_with_sensor) < 0.5 * len(building.zones)
    # named substitutes: zones without a sensor that use a zone with one
    for zone, entry in mapping["zones"].items():
        assert zone in building.zones and zone not in zones_with_sensor
        assert entry["use"] in zones_with_sensor
    # offsets: truncated normal, documented bounds
    offsets = np.array(list(truth["sensor_offsets"].values()))
    assert np.all(np.abs(offsets) <= dd.OFFSET_LIMIT)
    assert 0.1 < offsets.std() < 0.35


def test_report_rule_every_5_minutes_or_on_0_28_C(truth):
    log = pd.read_parquet(FOLDER / dd.SENSORS_FILE)
    log = log.sort_values(["sensor", "time"], kind="stable")
    t = _seconds(log["time"])
    same = log["sensor"].to_numpy()[1:] == log["sensor"].to_numpy()[:-1]
    interval = np.diff(t)[same]
    change = np.abs(np.diff(log["value"].to_numpy()))[same]
    sensor = log["sensor"].to_numpy()[1:][same]
    assert interval.min() >= 1
    # longer than the heartbeat only across the documented dropouts (or after the dead sensor)
    long_ = interval > dd.REPORT_INTERVAL
    dropout_sensors = {d["sensor"] for d in truth["defects"]["dropouts"]}
    assert set(sensor[long_]) <= dropout_sensors
    assert long_.sum() == len(truth["defects"]["dropouts"])
    assert interval[long_].min() >= 30 * 60
    # the heartbeat: the typical interval is exactly 5 minutes
    assert np.median(interval) == dd.REPORT_INTERVAL
    # between two reports the reading changed by less than the threshold (+ quantisation and
    # the one-second stamping of crossings); early reports are triggered by the threshold
    tol = dd.QUANTUM + 0.02
    assert change[~long_].max() <= dd.REPORT_THRESHOLD + tol
    early = interval < dd.REPORT_INTERVAL
    assert early.sum() > 1000  # event-driven reports exist (heating starts, stops)
    assert change[early].min() >= dd.REPORT_THRESHOLD - tol
    # quantised values
    values = log["value"].to_numpy()
    np.testing.assert_allclose(values, np.round(values / dd.QUANTUM) * dd.QUANTUM, atol=1e-9)
    # no report inside a dropout window, none after the death of the dead sensor
    for d in truth["defects"]["dropouts"]:
        rows = log[log["sensor"] == d["sensor"]]
        inside = (rows["time"] >= pd.Timestamp(d["start"])) & (
            rows["time"] < pd.Timestamp(d["end"])
        )
        assert not inside.any()
    dead = log[log["sensor"] == truth["defects"]["dead_sensor"]]
    died = pd.Timestamp(truth["defects"]["dead_after"])
    assert dead["time"].max() <= died
    assert dead["time"].max() > died - pd.Timedelta("5min")
    assert died - pd.Timestamp(truth["generator"]["period"][0]) >= pd.Timedelta("7D")


def test_truth_differs_from_nominal_on_the_documented_parameters(truth):
    building = generators.clinic()
    nominal = building.parameters()
    true = dd.true_parameters(building)
    assert set(truth["parameters"]) == set(dd.TRUE_FACTORS) == set(true)
    assert 8 <= len(true) <= 12
    for name, entry in truth["parameters"].items():
        assert entry["nominal"] == pytest.approx(nominal[name])
        assert entry["true"] == pytest.approx(true[name])
        assert entry["factor"] == dd.TRUE_FACTORS[name] != 1.0
        assert entry["true"] != pytest.approx(entry["nominal"], rel=0.05)
        assert entry["unit"] == dd.parameter_unit(name) and entry["unit"]
    # applied through the public API, the others stay nominal
    changed = building.with_parameters(true).parameters()
    differs = {k for k in nominal if changed[k] != pytest.approx(nominal[k])}
    assert differs == set(dd.TRUE_FACTORS)


def test_unknown_loads_constant_when_unoccupied(regenerated):
    loads = regenerated["loads"]
    occupied = dd.occupancy_mask(loads.index)
    unoccupied = loads.to_numpy()[~occupied]
    # per zone constant (the idle load) in every unoccupied step
    np.testing.assert_allclose(unoccupied, np.broadcast_to(unoccupied[0], unoccupied.shape))
    idle = regenerated["components"]["idle"]
    np.testing.assert_allclose(unoccupied[0], idle.to_numpy())
    area = regenerated["zones"]["floor_area"]
    assert ((idle / area) <= 10.0 + 1e-9).all() and ((idle / area) >= 1.0 - 1e-9).all()
    # occupied: much larger, varying with the outdoor temperature, some rooms cooled
    total = loads.sum(axis=1)
    assert total[occupied].mean() > 10 * total[~occupied].mean()
    assert (regenerated["components"]["hvac"].to_numpy() < 0).any()


def test_occupancy_mask_is_the_papers_schedule():
    t = pd.DatetimeIndex(
        [
            "2001-01-01 03:55",  # Monday night
            "2001-01-01 04:00",
            "2001-01-01 19:55",
            "2001-01-01 20:00",
            "2001-01-06 10:55",  # Saturday
            "2001-01-06 11:00",
            "2001-01-06 20:00",
            "2001-01-07 12:00",  # Sunday
        ]
    ).tz_localize("UTC-05:00")
    expected = [False, True, True, False, True, False, False, False]
    assert dd.occupancy_mask(t).tolist() == expected


def test_load_demo():
    building, weather, metadata, raw, mapping, truth = dd.load_demo()
    assert len(building.zones) == 186
    assert building.parameters() == generators.clinic().parameters()  # nominal
    start, end = metadata["period"]
    assert str(start) == "2001-01-01 00:00:00-05:00" and str(end) == "2001-02-01 00:00:00-05:00"
    assert weather.index[0] <= start and weather.index[-1] >= end - pd.Timedelta("1h")
    assert metadata["step"] == pd.Timedelta("5min")
    assert set(raw["sensor"].astype(str)) == set(mapping["sensors"])
    assert truth["generator"]["seed"] == dd.DEFAULT_SEED
