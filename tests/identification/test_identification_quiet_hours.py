"""Quiet hours from the data, against a building whose routine is known."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.identification.occupancy import OccupancySchedule, unoccupied_mask
from thermocal.identification.quiet import check_schedule, quiet_hours


def _building_heat(weeks: int = 4, seed: int = 0) -> tuple[pd.Series, np.ndarray]:
    """5-min heat of an office: 6 kW base, +20 kW weekdays 07-19, +16 kW Saturdays 07-15
    (equipment at 80 %), decaying with a 15-min half-life after switch-off (stored and radiant
    gains); weather +-2 kW over 3.3-day cycles and 0.5 kW noise.
    Returns the series and the true "constant gains" mask of each step."""
    rng = np.random.default_rng(seed)
    index = pd.date_range("2013-01-07", periods=weeks * 7 * 288, freq="5min")  # a Monday
    hour = index.hour.to_numpy() + index.minute.to_numpy() / 60
    day = index.day_of_week.to_numpy()
    on = ((day < 5) & (hour >= 7) & (hour < 19)) | ((day == 5) & (hour >= 7) & (hour < 15))
    level = np.where(day == 5, 16e3, 20e3) * on
    gains = pd.Series(level, index=index).ewm(halflife=3).mean().to_numpy()
    weather = 2e3 * np.sin(2 * np.pi * np.arange(len(index)) / (288 * 3.3))
    heat = 6e3 + gains + weather + rng.normal(0, 500, len(index))
    constant = np.abs(gains) < 0.05 * 20e3
    return pd.Series(heat, index=index), constant


def test_quiet_hours_are_the_hours_with_constant_gains():
    heat, constant = _building_heat()
    quiet = quiet_hours(heat)
    mask = unoccupied_mask(heat.index, quiet.schedule)
    assert not (mask & ~constant).any()  # never an hour with running gains
    assert (mask & constant).sum() > 0.85 * constant.sum()  # nearly all the quiet ones
    # Saturday afternoon after 15:00 (+1 h decay) is quiet, Saturday morning is not
    saturday = heat.index.day_of_week == 5
    assert mask[saturday & (heat.index.hour == 17)].all()
    assert not mask[saturday & (heat.index.hour == 10)].any()


def test_the_published_schedule_is_flagged_when_saturday_mornings_run():
    """The published schedule counts Saturday 11-20 as unoccupied; here equipment runs until
    15:00: four hours a week at ~16 kW above the quiet level."""
    heat, _ = _building_heat()
    check = check_schedule(quiet_hours(heat), OccupancySchedule.paper())
    assert not check.quiet
    assert {24 * 5 + h for h in (11, 12, 13, 14)} <= set(check.not_quiet)
    assert check.excess > 8e3
    assert "Sat 11:00" in check.describe()


def test_a_schedule_that_fits_the_building_passes():
    heat, _ = _building_heat()
    fits = OccupancySchedule.from_dict(
        {"unoccupied": [{"days": "all", "from": "21:00", "to": "05:00"},
                        {"days": ["Sat"], "from": "17:00", "to": "24:00"},
                        {"days": ["Sun"], "from": "00:00", "to": "24:00"}]}
    )
    check = check_schedule(quiet_hours(heat), fits)
    assert check.quiet and check.not_quiet == []


def test_too_short_data_is_refused_with_the_reason():
    heat, _ = _building_heat(weeks=1)
    with pytest.raises(ThermocalInputError, match="at least 2 weeks"):
        quiet_hours(heat)


def test_quiet_hours_of_an_energyplus_office_follow_its_schedules(shared_data):
    """NREL's 5ZoneAirCooled, a file thermocal did not write: its People, Lights and
    Equipment schedules (read as EnergyPlus applies them, checked in the IDF tests) over four
    January weeks. The quiet hours found hold none of the occupied hours and nearly all hours
    at the minimum gain; the published schedule fits this office."""
    import warnings

    from thermocal.multizone.idf import read_idf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(shared_data("energyplus_reference", "5ZoneAirCooled_FF_v25.idf"))
    times = pd.date_range("2006-01-02", periods=4 * 7 * 24, freq="h")
    gains = building.idf_info.internal_gains_profile(times).sum(axis=1)
    quiet = quiet_hours(gains)
    mask = unoccupied_mask(times, quiet.schedule)
    low, high = gains.min(), gains.max()
    # measured 2026-11-25: quiet gains 0.4-1.3 kW of a 0.4-14.6 kW range; weekdays 21-08,
    # weekends all day
    assert gains[mask].max() <= low + 0.1 * (high - low)
    at_minimum = gains.to_numpy() <= low + 1.0
    assert (mask & at_minimum).sum() >= 0.8 * at_minimum.sum()
    assert check_schedule(quiet, OccupancySchedule.paper()).quiet
