"""A zone that is really hot (or cold) is declared plausible in the mapping (issue 28): its
sensors are checked against the declared range instead of being refused as a unit slip."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.identification.sensors import check_sensor_plausibility, mapping_from_dict

STEP = pd.Timedelta("1h")


def _grid(boiler_mean: float) -> pd.DataFrame:
    index = pd.date_range("2024-01-08", periods=96, freq=STEP, tz="UTC")
    wave = np.sin(np.arange(96) * 2 * np.pi / 24)
    return pd.DataFrame(
        {"S0": 21.0 + wave, "S1": 20.5 + 0.8 * wave, "S9": boiler_mean + 3.0 * wave}, index=index
    )


def _mapping(extra=None):
    data = {"sensors": {"S0": "living", "S1": "office", "S9": "boiler room"}}
    if extra is not None:
        data["zones"] = {"boiler room": extra}
    return mapping_from_dict(data, source="mapping.yaml")


def test_a_65_C_room_is_refused_with_the_way_to_declare_it():
    with pytest.raises(ThermocalInputError) as caught:
        check_sensor_plausibility(_grid(65.0), _mapping(), STEP, "log.csv")
    message = str(caught.value)
    assert "sensor 'S9' (zone 'boiler room') reads 65.0 on average" in message
    assert "zones: {boiler room: {plausible: [low, high]}} in C" in message


def test_a_declared_hot_room_passes_and_its_range_is_checked():
    mapping = _mapping({"plausible": [40, 80]})
    assert mapping.zone_plausible == {"boiler room": (40.0, 80.0)}
    check_sensor_plausibility(_grid(65.0), mapping, STEP, "log.csv")
    # the declared range still catches a slip: 65 C logged in Fahrenheit reads 149
    with pytest.raises(ThermocalInputError, match=r"outside the range \[40, 80\] C declared"):
        check_sensor_plausibility(_grid(149.0), mapping, STEP, "log.csv")
    # the other zones are still checked against each other (not against the hot room)
    grid = _grid(65.0)
    grid["S1"] = grid["S1"] + 273.15
    with pytest.raises(ThermocalInputError, match=r"'S1' \(zone 'office'\).*Kelvin\?"):
        check_sensor_plausibility(grid, mapping, STEP, "log.csv")


@pytest.mark.parametrize("value", [[80, 40], [40], "hot", [40, 200], [True, 50]])
def test_a_bad_declared_range_is_named(value):
    with pytest.raises(ThermocalInputError, match=r"zones\.boiler room: plausible must be"):
        _mapping({"plausible": value})


def test_a_warm_room_with_a_hot_day_is_no_unit_slip_but_a_day_in_tenths_is():
    """A room that usually reads 29 C and one day 36 C (an MRI control room in free float on
    the DOE outpatient prototype) was refused as 'tenths of a degree?': the day is now judged
    against the sensor's own typical day; a day logged in tenths still is a slip."""
    grid = _grid(21.0)
    grid["S9"] = 29.0 + 0.5 * np.sin(np.arange(96) * 2 * np.pi / 24)
    grid.loc[grid.index[72:], "S9"] += 7.0  # the fourth day averages 36 C
    check_sensor_plausibility(grid, _mapping(), STEP, "log.csv")
    grid.loc[grid.index[72:], "S9"] = 10.0 * grid["S9"].iloc[:24].to_numpy()  # 290 for 29.0
    with pytest.raises(ThermocalInputError, match=r"'S9'.*tenths of a degree"):
        check_sensor_plausibility(grid, _mapping(), STEP, "log.csv")
