"""The spike screen of the quality report tells a logger's spike from a room's real excursion.

The real excursions are EnergyPlus 25.2's zone air temperatures of a twin of NREL's
WindowTestsSimple_noShadingControl (ideal loads holding 20-25 C, Golden TMY3, January 2023;
hourly means of its 5-minute values, as a logger writing interval means has them): rooms that
float above their heating set point in the afternoon sun for one or two hours. A fixed 1.5 K
floor removed them (the room held at its set point has no jitter to raise the threshold), and
``thermocal identify`` then refused the log (no data for 8.8 h) or, with a longer
``--max-gap``, invented 4.9 kW of cooling in an hour EnergyPlus had none.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.io.measurements import resample_measurements
from thermocal.io.measurements.quality import _spikes, spike_threshold

#: zone SPHW, 2023-01-12 08:00-22:00 (-07:00), hourly means stamped at the interval end [C]
SPHW_SUNNY_AFTERNOON = [20.0] * 6 + [20.128, 23.21, 22.663, 20.415] + [20.0] * 5
#: zone DPW, 2023-01-08 11:00-19:00: up to the cooling set point and back [C]
DPW_TO_COOLING = [20.0, 20.0, 20.0, 20.026, 23.002, 25.0, 24.961, 22.235, 20.0]
START = pd.Timestamp("2023-01-12 08:00", tz="America/Denver")


def _log(values, every="1h", start=START, sensor="T_SPHW") -> pd.DataFrame:
    times = pd.date_range(start, periods=len(values), freq=every)
    return pd.DataFrame({"time": times, "sensor": sensor, "value": np.asarray(values, float)})


def _flags(values, every="1h"):
    _, report = resample_measurements(
        _log(values, every), "5min", quantities={"T_SPHW": "temperature"}, outliers="remove",
        max_gap="3h",
    )  # fmt: skip
    return report.flags


def test_a_sunny_rooms_hourly_float_above_its_set_point_is_kept():
    assert _flags(SPHW_SUNNY_AFTERNOON).empty
    assert _flags(DPW_TO_COOLING).empty
    # the same shapes read every 5 minutes would be 12 times as steep: still spikes there
    assert len(_flags(SPHW_SUNNY_AFTERNOON, every="5min")) == 2


def test_a_loggers_spikes_are_still_removed_in_an_hourly_log():
    for code in (0.0, 85.0, 5.0, 31.0):  # dropout, DS18B20 power-on, glitches > 10 K away
        values = list(SPHW_SUNNY_AFTERNOON)
        values[3] = code
        flags = _flags(values)
        assert list(flags["value"]) == [code], (code, flags)
        assert (flags["action"] == "removed").all()
        assert "10 C/h times half the time between the neighbours" in flags["reason"].iloc[0]
    values = list(SPHW_SUNNY_AFTERNOON)
    values[11:13] = [85.0, 85.0]  # two readings
    assert list(_flags(values)["value"]) == [85.0, 85.0]


def test_the_spike_threshold_grows_with_the_time_between_the_neighbours():
    hours = np.array([10 / 60, 0.25, 0.5, 1.0, 2.0, 3.0, 48.0])
    np.testing.assert_allclose(
        spike_threshold(hours, 1.5, 10.0, 10.0), [1.5, 1.5, 2.5, 5.0, 10.0, 10.0, 10.0]
    )
    np.testing.assert_allclose(spike_threshold(hours, 1.5), 1.5)  # no slope: the floor
    # without times the screen is the old fixed floor
    assert _spikes(np.array(SPHW_SUNNY_AFTERNOON), 5.0, 1.5).sum() == 2
    seconds = np.arange(len(SPHW_SUNNY_AFTERNOON)) * 3600.0
    assert not _spikes(
        np.array(SPHW_SUNNY_AFTERNOON), 5.0, 1.5, times_s=seconds, slope=10.0, ceiling=10.0
    ).any()


@pytest.mark.parametrize("every", ["5min", "10min"])
def test_short_spacing_keeps_the_floor(every):
    """At 5 minutes the neighbours are 10 min apart (1-report run) or 15 min (2 reports):
    the floor of 1.5 K is unchanged; at 10 minutes a 2-report run spans 30 min (2.5 K)."""
    rng = np.random.default_rng(3)
    values = np.round(21 + 0.05 * rng.standard_normal(60), 2)
    values[30] = 23.6  # 2.6 K away and back
    flags = _flags(values, every=every)
    assert list(flags["value"]) == [23.6]
