"""A sensor reading one value for a day or more: a frozen sensor or a controlled room.

Before: every such run was refused as "stuck", also a room held at its set point and logged at
0.1 K (a BMS export), with two remedies that both discarded the data and no override. Now the
run is accepted, with a warning saying why, when it is a set point of the zone, when the log's
resolution explains it, or when the mapping says ``constant_readings: accept``; a constant no
rule explains is still refused, naming the override as a third remedy.
"""

from __future__ import annotations

import types
import warnings

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.identification.sensors import (
    ReferenceWarning,
    check_sensor_plausibility,
    log_resolution,
    mapping_from_dict,
    zone_references,
    zone_setpoints,
)

STEP = pd.Timedelta("15min")
TIMES = pd.date_range("2024-01-08", periods=4 * 96, freq=STEP, tz="UTC")
HELD = slice(96, 96 + 144)  # 1.5 days from the second day on


def _grid(held: float = 20.0, resolution: float = 0.1, other: bool = True) -> pd.DataFrame:
    """S1 (office) moves around ``held`` and reads exactly ``held`` for 1.5 days; S2 (hall)
    moves throughout. Both rounded to ``resolution`` [K]."""
    hours = np.arange(len(TIMES)) * 0.25
    s1 = held + 0.6 * np.sin(2 * np.pi * hours / 24)
    s1[HELD] = held
    s2 = 18.0 + 1.5 * np.sin(2 * np.pi * hours / 24 + 1)
    grid = pd.DataFrame({"S1": s1, "S2": s2}, index=TIMES)
    grid = (grid / resolution).round() * resolution
    return grid if other else grid[["S1"]]


def _mapping(**extra):
    return mapping_from_dict(
        {"sensors": {"S1": "office", "S2": "hall"}, **extra}, source="mapping.yaml"
    )


def _check(grid, mapping=None, **kwargs) -> list[str]:
    """check_sensor_plausibility on the grid as the raw log too; the ReferenceWarning texts."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_sensor_plausibility(
            grid, mapping or _mapping(), STEP, "log.csv", raw=grid, **kwargs
        )
    return [str(w.message) for w in caught if issubclass(w.category, ReferenceWarning)]


def _setpoints(heating: float, cooling: float | None = None) -> pd.DataFrame:
    columns = {("office", "heating"): heating}
    if cooling is not None:
        columns[("office", "cooling")] = cooling
    frame = pd.DataFrame({k: np.full(len(TIMES), v) for k, v in columns.items()}, index=TIMES)
    frame.columns = pd.MultiIndex.from_tuples(list(columns))
    return frame


def test_a_room_at_its_heating_set_point_is_accepted_with_a_warning():
    texts = _check(_grid(20.0, resolution=0.01), setpoints=_setpoints(20.0, 26.0))
    assert len(texts) == 1
    assert "sensor 'S1' (zone 'office') reads exactly 20 C" in texts[0]
    assert "1.5 days" in texts[0]
    assert "not refused as a stuck sensor" in texts[0]
    assert "20 C is the heating set point the building declares for zone 'office'" in texts[0]


def test_a_set_point_that_changes_during_the_run_does_not_explain_it():
    """A set-back to 15 C in the middle of the run: the room read 20 C also when the
    thermostat asked for 15 C; with 0.01 K resolution nothing else explains it."""
    setpoints = _setpoints(20.0)
    setpoints.iloc[150:170] = 15.0
    with pytest.raises(ThermocalInputError) as info:
        _check(_grid(20.0, resolution=0.01), setpoints=setpoints)
    message = str(info.value)
    assert "20 C is no set point the building declares for zone 'office' throughout" in message
    assert "resolution of 0.01 K, too fine" in message


def test_a_stuck_sensor_is_still_refused_naming_three_remedies():
    with pytest.raises(ThermocalInputError) as info:
        _check(_grid(21.37, resolution=0.01))
    message = str(info.value)
    for part in (
        "log.csv: sensor 'S1' (zone 'office') reads exactly 21.37 C from 2024-01-09",
        "a stuck or frozen sensor",
        "the building declares no set point for zone 'office'",
        "remove those values from the log (a gap)",
        "list the sensor under 'ignore:' in mapping.yaml",
        "'constant_readings: {S1: accept}' (or 'constant_readings: accept' for every sensor)",
    ):
        assert part in message, message


def test_the_log_resolution_explains_a_controlled_room():
    texts = _check(_grid(21.0, resolution=0.1))
    assert len(texts) == 1
    assert "the log's resolution of 0.1 K explains it" in texts[0]
    assert "other sensors of the log change (e.g. 'S2')" in texts[0]
    texts = _check(_grid(21.5, resolution=0.5))
    assert "resolution of 0.5 K" in texts[0]


def test_resolution_does_not_explain_an_implausible_constant_or_a_lone_sensor():
    with pytest.raises(ThermocalInputError, match=r"31\.5 C is no temperature a room is held at"):
        _check(_grid(31.5, resolution=0.1))
    with pytest.raises(ThermocalInputError, match=r"no other sensor of the log changes"):
        _check(_grid(21.0, resolution=0.1, other=False))
    frozen = _grid(21.0, resolution=0.1)
    frozen.iloc[HELD, 1] = 18.0  # the whole logger repeats its last row
    with pytest.raises(ThermocalInputError, match=r"no other sensor of the log changes"):
        _check(frozen)


@pytest.mark.parametrize(
    "extra",
    [{"constant_readings": "accept"}, {"constant_readings": {"S1": "accept"}}],
    ids=["all-sensors", "one-sensor"],
)
def test_the_mapping_accepts_constant_readings(extra):
    texts = _check(_grid(21.37, resolution=0.01), _mapping(**extra))
    assert len(texts) == 1
    assert "'constant_readings' in mapping.yaml accepts it" in texts[0]


def test_constant_readings_per_sensor_leaves_the_others_checked():
    grid = _grid(21.37, resolution=0.01)
    with pytest.raises(ThermocalInputError, match=r"sensor 'S1'"):
        _check(grid, _mapping(constant_readings={"S2": "accept"}))


@pytest.mark.parametrize(
    ("value", "pattern"),
    [
        ("yes", r"constant_readings must be accept or check .*got 'yes'"),
        ({"S1": "ok"}, r"got 'ok' for sensor 'S1'"),
        ({"S9": "accept"}, r"constant_readings names sensor 'S9', which is not under 'sensors:'"),
        ([], r"constant_readings must be accept or check"),
    ],
)
def test_constant_readings_values_are_checked(value, pattern):
    with pytest.raises(ThermocalInputError, match=pattern):
        _mapping(constant_readings=value)


def test_log_resolution():
    assert log_resolution([20.0, 20.1, 20.3, np.nan, 20.0]) == pytest.approx(0.1)
    fahrenheit = (np.array([68.0, 68.1, 68.3]) - 32) / 1.8  # a 0.1 F log converted
    assert log_resolution(fahrenheit) == pytest.approx(0.1 / 1.8, abs=1e-5)
    assert log_resolution([20.0, 20.0, 20.1]) is None  # two values show no grid
    assert log_resolution([20.0, 20.1, 20.25]) is None  # not evenly stepped


def test_zone_setpoints_from_an_imported_file_and_from_constants():
    times = TIMES[:4]

    class Info:
        setpoint_schedules = {"office": ("Heat SP", None)}

        @staticmethod
        def setpoint_profile(t):
            return pd.DataFrame({("office", "heating"): np.full(len(t), 21.0)}, index=t)

    building = types.SimpleNamespace(
        idf_info=Info(),
        zones={
            "office": types.SimpleNamespace(heating_setpoint=19.0, cooling_setpoint=26.0),
            "hall": types.SimpleNamespace(heating_setpoint=None, cooling_setpoint=None),
        },
    )
    frame = zone_setpoints(building, times)
    assert sorted(frame.columns) == [("office", "cooling"), ("office", "heating")]
    assert (frame[("office", "heating")] == 21.0).all()  # the schedule, not the constant
    assert (frame[("office", "cooling")] == 26.0).all()


def test_zone_references_accepts_a_room_held_at_the_building_set_point():
    """Through zone_references: the building's set point (a zone's constant) explains a
    one-sensor log at 0.001 K resolution that reads 20 C for 1.5 days."""
    index = pd.date_range("2024-01-07 22:00", "2024-01-12 02:00", freq="5min", tz="UTC")
    hours = np.asarray((index - index[0]) / pd.Timedelta("1h"))
    values = 20.0 + 0.5 * np.sin(2 * np.pi * hours / 24)
    values[(index >= "2024-01-09") & (index < "2024-01-10 12:00")] = 20.0
    log = pd.DataFrame({"S1": values.round(3)}, index=index.rename("time"))
    building = types.SimpleNamespace(
        name="b",
        zones={"office": types.SimpleNamespace(heating_setpoint=20.0, cooling_setpoint=None)},
        surfaces={},
    )
    mapping = mapping_from_dict({"sensors": {"S1": "office"}}, source="mapping.yaml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        reference, _ = zone_references(log, building, mapping, TIMES, STEP, source="log.csv")
    texts = [str(w.message) for w in caught if issubclass(w.category, ReferenceWarning)]
    assert any("20 C is the heating set point" in t for t in texts), texts
    assert reference["office"].notna().all()
    building.zones["office"].heating_setpoint = 18.0
    with pytest.raises(ThermocalInputError, match=r"reads exactly 20 C.*constant_readings"):
        zone_references(log, building, mapping, TIMES, STEP, source="log.csv")
