"""Sensor logs: irregular, event-based measurements -> a regular grid, with a quality report.

Wireless sensor networks report irregularly: the envelope-calibration case study's sensors
send a value every 5 minutes or as soon as it changes by 0.28 C, whichever comes first; a
heat meter may report only on change.
This module reads such logs and puts them on a regular grid with the operation each quantity
needs, and says what it did.

Reading (:func:`read_measurements`)
    CSV or parquet logs in *long* form (one report per row: time, sensor, value[, unit]) or
    *wide* form (a time column and one column per sensor; an empty cell means "no report at
    this time"). Units
    may be declared in the header (``T_living [C]``, ``flow (l/h)``), in a ``unit`` column (long
    form) or with ``units=``; values are converted to thermocal's units (temperatures C, flows
    m3/s, power W, irradiance W/m2, energy J, pressure Pa). Temperature columns without a
    declared unit are checked for Kelvin (values around 290) and converted; a column mixing both
    is rejected with a message. Duplicated or non-increasing timestamps, unknown sensor names
    and unparseable values are errors naming the file, the column and the 1-based line number.

Resampling (:func:`resample_measurements`)
    A report holds until the next one (zero-order hold: an event-based sensor reports when the
    value changes, so between reports it did not change by more than the threshold). Per column:

    ``"mean"``          time-weighted mean of the held signal over each interval (exact for
                        step signals) -- temperatures, flows, power from event-based sensors;
    ``"mean_linear"``   time-weighted mean of the linearly interpolated signal (trapezoid) -- for
                        instantaneous samples of a smooth quantity taken at regular times
                        (interval means stand for their interval's middle);
    ``"last"``          value held at the end of the interval (states, set points, meter
                        readings);
    ``"first"``         value held at the start of the interval;
    ``"min"``, ``"max"`` extremes of the held signal within the interval;
    ``"sum"``           sum of the reported values within the interval (increments, pulses);
    ``"count"``         number of reports within the interval.

    A silence longer than ``max_gap`` is a *gap*: the last value before it is held only for the
    sensor's typical reporting interval, the rest is unknown, intervals covered less than
    ``min_coverage`` are NaN, and the gap is listed in the report. Nothing is interpolated across
    a gap. Physically impossible values (a negative flow, a relative humidity of 130 %, an air
    temperature of 300 C) are removed before resampling and listed; spikes (one or two reports
    that jump away and come back, the QARTOD spike test) are flagged, and removed on request.

Grid convention: each interval is labelled by its START, ``[t, t + step)``, as for the weather
(``thermocal.io.weather``). A report describes the time from its timestamp on. Logs whose rows
are *interval means* (a data logger's 10-minute averages, an hourly export) are read with
``rows="interval_start"`` (or ``"interval_end"`` when stamped at the end: they are moved back by
one interval); each row then holds until the next row but for at most its logging interval, and
the last row until its interval end (``resample_measurements(interval=...)``).

Files: CSV, or parquet (``.parquet``, ``.pq``) with the same long or wide layout.

References
----------
.. [1] U.S. IOOS (2020). Manual for Real-Time Quality Control of In-situ Temperature and
   Salinity Data, version 2.1 (QARTOD gap, range and spike tests).
.. [2] ISO 8601-1:2019, Date and time representations (timestamps with UTC offsets).
Modules: :mod:`.read` (files), :mod:`.layout` (long and wide logs), :mod:`.units` (units,
quantities, physical limits, unit slips), :mod:`.resample` (the grid), :mod:`.quality` (the
report, spikes), :mod:`.clock` (time stamps against the sun). Everything public is importable
from this package.
"""

from thermocal.io.measurements.clock import MAX_SUN_SHIFT_H, check_clock_against_sun
from thermocal.io.measurements.quality import QualityReport
from thermocal.io.measurements.read import raw_tz, read_measurements
from thermocal.io.measurements.resample import resample_measurements, time_weighted_mean
from thermocal.io.measurements.units import (
    CANONICAL_UNITS,
    INDOOR_MEAN_RANGE,
    NEIGHBOUR_TOLERANCE,
    OPERATIONS,
    OUTLIER_FLOORS,
    PHYSICAL_LIMITS,
    PLAUSIBLE_TEMPERATURE,
    TEMPERATURE_UNIT_SLIPS,
    UNIT_MATCH,
    UNITS,
    temperature_unit_slip,
)

__all__ = [
    "CANONICAL_UNITS",
    "INDOOR_MEAN_RANGE",
    "MAX_SUN_SHIFT_H",
    "NEIGHBOUR_TOLERANCE",
    "OPERATIONS",
    "OUTLIER_FLOORS",
    "PHYSICAL_LIMITS",
    "PLAUSIBLE_TEMPERATURE",
    "TEMPERATURE_UNIT_SLIPS",
    "UNITS",
    "UNIT_MATCH",
    "QualityReport",
    "check_clock_against_sun",
    "raw_tz",
    "read_measurements",
    "resample_measurements",
    "temperature_unit_slip",
    "time_weighted_mean",
]
