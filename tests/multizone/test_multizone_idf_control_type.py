"""A thermostat whose Control Type Schedule varies switches its set points step by step.

NREL's PurchAirWindowBlind and StormWindow (EnergyPlus test files) heat only from October to
March (control type 1, ThermostatSetpoint:SingleHeating) and cool only from April to September
(type 2). The importer took the type in effect most of the year for the whole run: a January
simulation cooled at the summer set point and never heated (-100 % heating against
EnergyPlus's; -0.7 % after this change, survey of 2026-11-30).
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.multizone.idf import read_idf

SOURCE = (
    Path(__file__).resolve().parents[1]
    / "reference/forward_nrel_testfiles/1ZoneUncontrolled_win_1"
    / "1ZoneUncontrolled_win_1_layered_v25.idf"
)
THERMOSTAT = """
Schedule:Compact, Heating 20, Any Number, Through: 12/31, For: AllDays, Until: 24:00, 20;
Schedule:Compact, Cooling 24, Any Number, Through: 12/31, For: AllDays, Until: 24:00, 24;
Schedule:Compact, Control Type, Any Number, Through: 3/31, For: AllDays, Until: 24:00, 1,
    Through: 9/30, For: AllDays, Until: 24:00, 2, Through: 12/31, For: AllDays, Until: 24:00, 1;
ZoneControl:Thermostat, Zone One Thermostat, ZONE ONE, Control Type,
    ThermostatSetpoint:SingleHeating, Heat Only, ThermostatSetpoint:SingleCooling, Cool Only;
ThermostatSetpoint:SingleHeating, Heat Only, Heating 20;
ThermostatSetpoint:SingleCooling, Cool Only, Cooling 24;
"""


def _building(tmp_path, text=THERMOSTAT):
    source = SOURCE.read_text()
    source = re.sub(r"RunPeriod,[^;]*;", "RunPeriod, r, 1, 1, 2023, 12, 31, 2023;", source)
    path = tmp_path / "control_type.idf"
    path.write_text(source + text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_idf(path)


def _january_run(building):
    """Two January days at hourly steps on Denver's TMY3 (a day of warm-up before)."""
    from conftest import shared_data_path
    from thermocal.io.weather import read_weather
    from thermocal.multizone.simulation import Simulation

    weather, meta = read_weather(
        shared_data_path("ashrae140_bestest") / "725650TYCST.epw", coerce_year=2023
    )
    start = pd.Timestamp("2023-01-02")
    if weather.index.tz is not None:
        start = start.tz_localize(weather.index.tz)
    return Simulation(
        building, weather, meta, step="1h", start=start, end=start + pd.Timedelta(days=2),
        warmup_days=1, store_surfaces=False,
    ).run()  # fmt: skip


def test_the_set_points_follow_the_control_type_schedule(tmp_path):
    building = _building(tmp_path)
    info = building.idf_info
    times = pd.date_range("2023-01-01", "2023-12-31 23:00", freq="1h")
    inputs = info.scheduled_inputs(["ZONE ONE"], times, pd.Timedelta("1h"), pd.DataFrame())
    heating, cooling = inputs.heating_setpoint[:, 0], inputs.cooling_setpoint[:, 0]
    january, july = times.month == 1, times.month == 7
    assert np.all(heating[january] == 20) and np.isnan(cooling[january]).all()
    assert np.isnan(heating[july]).all() and np.all(cooling[july] == 24)
    assert inputs.setpoint_switched.tolist() == [True]
    profile = info.setpoint_profile(times)
    assert profile[("ZONE ONE", "heating")][january].eq(20).all()
    assert profile[("ZONE ONE", "cooling")][january].isna().all()
    assert any("follow it step by step" in note for note in info.notes)


def test_a_january_run_heats_and_does_not_cool(tmp_path):
    building = _building(tmp_path)
    result = _january_run(building)
    assert result.heating["ZONE ONE"].sum() > 0
    assert result.cooling["ZONE ONE"].sum() == 0
    assert result.air_temperature["ZONE ONE"].min() > 19.9


SEASONAL = """
Schedule:Compact, Heating Seasonal, Any Number, Through: 3/31, For: AllDays, Until: 24:00, 20,
    Through: 12/31, For: AllDays, Until: 24:00, 15;
Schedule:Compact, Cooling 30, Any Number, Through: 12/31, For: AllDays, Until: 24:00, 30;
Schedule:Compact, Dual, Any Number, Through: 12/31, For: AllDays, Until: 24:00, 4;
ZoneControl:Thermostat, T, ZONE ONE, Dual, ThermostatSetpoint:DualSetpoint, SP;
ThermostatSetpoint:DualSetpoint, SP, Heating Seasonal, Cooling 30;
"""


def test_a_set_point_constant_over_the_run_is_the_runs_value(tmp_path):
    """20 C in January-March, 15 C the rest of the year (the zone's constant): a January run
    is held at 20 C (it was held at 15 C: the per-step set points, constant over the run, were
    taken for the zone's constant ones)."""
    building = _building(tmp_path, SEASONAL)
    assert building.zones["ZONE ONE"].heating_setpoint == 15.0
    result = _january_run(building)
    assert result.air_temperature["ZONE ONE"].min() > 19.9


COOLING_MOSTLY_WITHOUT_ITS_OBJECT = """
Schedule:Compact, Heating 20, Any Number, Through: 12/31, For: AllDays, Until: 24:00, 20;
Schedule:Compact, Control Type, Any Number, Through: 3/31, For: AllDays, Until: 24:00, 1,
    Through: 10/31, For: AllDays, Until: 24:00, 2, Through: 12/31, For: AllDays, Until: 24:00, 1;
ZoneControl:Thermostat, Zone One Thermostat, ZONE ONE, Control Type,
    ThermostatSetpoint:SingleHeating, Heat Only;
ThermostatSetpoint:SingleHeating, Heat Only, Heating 20;
"""


def test_a_zone_whose_most_frequent_control_type_has_no_set_point_object_still_heats(tmp_path):
    """Cooling-only (type 2) from April to October, most of the year, without a cooling
    set-point object; heating-only (type 1) the rest: the zone heats at 20 C in winter and
    floats in summer (it was left uncontrolled the whole year, with a note)."""
    building = _building(tmp_path, COOLING_MOSTLY_WITHOUT_ITS_OBJECT)
    info = building.idf_info
    assert building.zones["ZONE ONE"].heating_setpoint == 20.0
    times = pd.date_range("2023-01-01", "2023-12-31 23:00", freq="1h")
    inputs = info.scheduled_inputs(["ZONE ONE"], times, pd.Timedelta("1h"), pd.DataFrame())
    heating = inputs.heating_setpoint[:, 0]
    assert np.all(heating[times.month == 1] == 20)
    assert np.isnan(heating[times.month == 7]).all()
    assert any("the zone floats on its steps" in note for note in info.notes)
