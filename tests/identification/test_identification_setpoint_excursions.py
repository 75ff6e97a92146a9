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
