"""Time stamps in microseconds (pandas 3's default for date_range and to_datetime) give the same
powers as in nanoseconds: a reading's interval was taken from nanosecond integers."""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.retrofit.data import meter_power


def test_a_meter_reading_gives_the_same_power_whatever_the_time_resolution():
    readings = [0.0, 1.5, 2.5, 4.5, 5.0]
    powers = []
    for unit in ("ns", "us", "s"):
        index = pd.date_range("2025-01-01", periods=5, freq="1h", unit=unit)
        series = pd.Series(readings, index=index)
        powers.append(
            meter_power(series, energy=True, cumulative=True, interval=None).to_numpy()
        )
    assert np.allclose(powers[0], powers[1], equal_nan=True)
    assert np.allclose(powers[0], powers[2], equal_nan=True)
