"""A zone read well beyond a set point the building file holds it at is named.

Before: a sensor in a sunny spot gave a large wrong zone heat with no warning (an EnergyPlus
25.2 twin of NREL's InternalMass_wZoneList, Golden in January, the West zone's sensor reading
1 K per kW of sun above the air: up to 4.4 K above its 24 C cooling set point, its identified
heating +61 %), though thermocal read the file's set points. The EnergyPlus check of a sensor
beside a cold window is in ``test_identification_ideal_loads.py``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from conftest import requires_energyplus
from thermocal.identification.sensors import (
    SETPOINT_MARGIN,
    setpoint_excursion_text,
    setpoint_excursions,
)

STEP = pd.Timedelta("15min")
TIMES = pd.date_range("2023-01-09", periods=4 * 96, freq=STEP, tz="-07:00")
HOUR = np.asarray((TIMES - TIMES.normalize()) / pd.Timedelta("1h"))


def _setpoints(heating, cooling, zone="West"):
    return pd.DataFrame(
        {(zone, "heating"): np.broadcast_to(heating, HOUR.shape).astype(float),
         (zone, "cooling"): np.broadcast_to(cooling, HOUR.shape).astype(float)},
        index=TIMES,
    )  # fmt: skip


def _sunny_afternoons(peak):
    """Held at 24 C from 11 to 17 h, the sensor reading up to ``peak`` K more in the sun."""
    air = np.where((HOUR >= 11) & (HOUR < 17), 24.0, 22.0)
    sun = np.clip(np.sin(np.pi * (HOUR - 8) / 10), 0, None)
    return pd.DataFrame({"West": air + peak * sun}, index=TIMES)


def test_a_sensor_in_the_sun_above_the_cooling_set_point_is_named():
    (record,) = setpoint_excursions(_sunny_afternoons(4.0), _setpoints(20.0, 24.0), {"West"},
                                    STEP)  # fmt: skip
    assert (record["zone"], record["side"], record["setpoint_C"]) == ("West", "above cooling",
                                                                      24.0)  # fmt: skip
    assert 3.9 < record["max_excess_K"] <= 4.0
    assert record["hours"] == record["share"] * record["hours_held"] > 12, record
    text = setpoint_excursion_text(record)
    assert text.startswith("zone 'West' (its sensors) reads above the cooling set point")
    assert "a sensor in the sun or near a heat source" in text
    assert "the set points in the file are not the building's" in text
    assert "setpoint_excursions in identification.json" in text


def test_a_room_held_at_its_set_points_is_not_named():
    held = _sunny_afternoons(0.0)
    assert setpoint_excursions(held, _setpoints(20.0, 24.0), {"West"}, STEP) == []
    # within the margin: a thermostat's throttling range, a sensor a few metres away
    near = held + SETPOINT_MARGIN - 0.05
    assert setpoint_excursions(near, _setpoints(20.0, 24.0), {"West"}, STEP) == []


def test_no_equipment_no_set_point_or_a_short_excursion_is_not_named():
    sunny = _sunny_afternoons(4.0)
    assert setpoint_excursions(sunny, _setpoints(20.0, 24.0), {"East"}, STEP) == []
    off = _setpoints(20.0, np.nan)  # the file's cooling switched off
    assert setpoint_excursions(sunny, off, {"West"}, STEP) == []
    for hours in (1.5, 4.5):  # fewer than 2 h; 5 % of the 96 h or fewer
        once = _sunny_afternoons(0.0)
        at = np.flatnonzero(HOUR == 12)[0]
        once.iloc[at : at + int(hours * 4)] += 3.0
        assert setpoint_excursions(once, _setpoints(20.0, 24.0), {"West"}, STEP) == [], hours
    once.iloc[at : at + 24] += 3.0  # 6 h: named
    assert len(setpoint_excursions(once, _setpoints(20.0, 24.0), {"West"}, STEP)) == 1


def test_the_recovery_after_a_set_back_is_not_named():
    """Heating set back to 16 C overnight, 21 C from 6 h; the room needs 1.5 h to get there
    every morning (below 21 C by more than the margin for about an hour a day)."""
    heating = np.where((HOUR >= 6) & (HOUR < 22), 21.0, 16.0)
    room = np.where(HOUR < 6, 16.0, np.minimum(21.0, 16.0 + 5.0 * (HOUR - 6) / 1.5))
    room = np.where(HOUR >= 22, 16.0, room)
    measured = pd.DataFrame({"West": room}, index=TIMES)
    assert setpoint_excursions(measured, _setpoints(heating, 30.0), {"West"}, STEP) == []
    # a room that never gets there (the sensor against a cold window) is named
    (record,) = setpoint_excursions(measured - 2.0, _setpoints(heating, 30.0), {"West"}, STEP)
    assert record["side"] == "below heating" and record["setpoint_C"] == 21.0
    assert record["max_excess_K"] == 2.0


# --- the equipment the file gives a zone, against EnergyPlus 25.2 (Case 600 in January) ---

_CASE_600_HVAC = (
    "ZoneHVAC:EquipmentConnections",
    "NodeList",
    "ZoneHVAC:IdealLoadsAirSystem",
    "ZoneHVAC:EquipmentList",
)


def _case_600(shared_data, tmp_path, extra: str):
    """Case 600 cut to January (its 20/27 C dual-setpoint thermostat), its ideal loads replaced
    by ``extra``: the file, and EnergyPlus' hourly zone air temperature [C]."""
    import re

    from thermocal.multizone.energyplus import read_eso, run_energyplus

    text = shared_data("energyplus_reference", "case_600_v25.idf").read_text()
    end_month = "  12,                                   !- End Month"
    assert end_month in text
    text = text.replace(end_month, "  1,  !- End Month", 1)
    for cls in _CASE_600_HVAC:
        text = re.sub(rf"\n{re.escape(cls)},[^;]*;", "\n", text)
    idf = tmp_path / "case.idf"
    idf.write_text(text + extra)
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    eso = read_eso(run_energyplus(idf, weather, tmp_path / "ep"), year=2009)
    return idf, eso["ZONE ONE:Zone Mean Air Temperature [C]"]


def _read(idf):
    import warnings

    from thermocal.multizone.idf import read_idf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_idf(idf)


_BASEBOARD = "\nHVACTemplate:Zone:BaseboardHeat, ZONE ONE, , , Electric, {}, 10000, , None;\n"
_OFF_FIRST_HALF = (
    "\nSchedule:Compact, OffFirstHalf, , Through: 1/15, For: AllDays, Until: 24:00, 0,"
    " Through: 12/31, For: AllDays, Until: 24:00, 1;\n"
)


@requires_energyplus
def test_a_room_whose_baseboards_are_switched_off_is_not_named(shared_data, tmp_path):
    """Baseboards only (heating), the file's dual thermostat at 20/27 C, the baseboards'
    availability schedule off for the first half of January: EnergyPlus floats the room there
    (down to -6 C), then heats it to 20 C. Its own air temperature as the readings gives no
    warning. Before: the heating set point applied on the steps the baseboards were off and the
    room was named 'below heating' for 219 h of the month's 744 (share 0.29, up to 26 K below)."""
    from thermocal.identification.sensors import heated_or_cooled, held_setpoints, zone_setpoints

    idf, air = _case_600(shared_data, tmp_path, _BASEBOARD.format("OffFirstHalf")
                         + _OFF_FIRST_HALF)  # fmt: skip
    building = _read(idf)
    times = pd.date_range("2009-01-01", periods=31 * 24, freq="1h")  # the hours' starts
    assert len(air) == len(times)
    measured = pd.DataFrame({"ZONE ONE": air.to_numpy()}, index=times)
    assert air.iloc[: 15 * 24].min() < 0.0 and air.iloc[20 * 24 :].min() > 19.5
    # heating only: the importer already drops the cooling set point (no false 'above cooling')
    setpoints = zone_setpoints(building, times)
    assert list(setpoints.columns) == [("ZONE ONE", "heating")]
    # the importer switches the baseboards off where their availability schedule is 0
    off = setpoints[("ZONE ONE", "heating")].isna().to_numpy()
    assert off[: 15 * 24].all() and not off[15 * 24 :].any()
    equipped = heated_or_cooled(building)
    step = pd.Timedelta("1h")
    assert setpoint_excursions(measured, held_setpoints(building, times), equipped, step) == []
    always = setpoints.fillna(20.0)  # the set point on every step: the old check
    (before,) = setpoint_excursions(measured, always, equipped, step)
    assert before["side"] == "below heating" and before["hours"] > 200, before
    # the same room with its baseboards always available and a sensor against the cold window
    # (2 K below the air) is still named
    colder = measured - 2.0
    colder.iloc[: 15 * 24] = 20.0 - 2.0
    (record,) = setpoint_excursions(colder, held_setpoints(building, times), equipped, step)
    assert record["side"] == "below heating" and record["hours"] < 17 * 24


def test_an_operative_thermostat_zone_is_not_checked(shared_data, tmp_path):
    """An operative-temperature thermostat (radiative fraction 0.5) holds (T_air + T_mrt) / 2 at
    20 C: beside cold walls the air sits above it, by as much as the walls are below it, so its
    air is not checked against the set point (Case 600 in January in EnergyPlus 25.2: the air
    up to 2-3 K above 20 C on the coldest mornings)."""
    from thermocal.identification.sensors import held_setpoints, zone_setpoints

    text = shared_data("energyplus_reference", "case_600_v25.idf").read_text()
    idf = tmp_path / "operative.idf"
    idf.write_text(text + "\nZoneControl:Thermostat:OperativeTemperature, ZONE ONE Thermostat, "
                   "Constant, 0.5, , None;\n")  # fmt: skip
    building = _read(idf)
    times = pd.date_range("2009-01-01", periods=48, freq="1h")
    assert building.idf_info.operative_fraction == {"ZONE ONE": 0.5}
    assert ("ZONE ONE", "heating") in zone_setpoints(building, times).columns
    assert held_setpoints(building, times).empty
