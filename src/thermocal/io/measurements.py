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
                        instantaneous samples of a smooth quantity taken at regular times;
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
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io._time import parse_time_column

__all__ = [
    "OPERATIONS",
    "PHYSICAL_LIMITS",
    "UNITS",
    "QualityReport",
    "read_measurements",
    "resample_measurements",
    "time_weighted_mean",
]

# ----------------------------------------------------------------------------------------------
# units and quantities
# ----------------------------------------------------------------------------------------------
#: Known units: name -> (quantity, factor, offset, canonical unit); canonical = value * factor +
#: offset. Names are matched case-sensitively first, then case-insensitively.
UNITS: dict[str, tuple[str, float, float, str]] = {
    # temperature -> C
    "C": ("temperature", 1.0, 0.0, "C"),
    "°C": ("temperature", 1.0, 0.0, "C"),
    "degC": ("temperature", 1.0, 0.0, "C"),
    "deg C": ("temperature", 1.0, 0.0, "C"),
    "celsius": ("temperature", 1.0, 0.0, "C"),
    "K": ("temperature", 1.0, -273.15, "C"),
    "kelvin": ("temperature", 1.0, -273.15, "C"),
    "F": ("temperature", 5.0 / 9.0, -32.0 * 5.0 / 9.0, "C"),
    "°F": ("temperature", 5.0 / 9.0, -32.0 * 5.0 / 9.0, "C"),
    "degF": ("temperature", 5.0 / 9.0, -32.0 * 5.0 / 9.0, "C"),
    # volume flow -> m3/s
    "m3/s": ("flow", 1.0, 0.0, "m3/s"),
    "m³/s": ("flow", 1.0, 0.0, "m3/s"),
    "m3/h": ("flow", 1.0 / 3600.0, 0.0, "m3/s"),
    "m³/h": ("flow", 1.0 / 3600.0, 0.0, "m3/s"),
    "l/s": ("flow", 1e-3, 0.0, "m3/s"),
    "l/min": ("flow", 1e-3 / 60.0, 0.0, "m3/s"),
    "l/h": ("flow", 1e-3 / 3600.0, 0.0, "m3/s"),
    # power -> W
    "W": ("power", 1.0, 0.0, "W"),
    "kW": ("power", 1e3, 0.0, "W"),
    "MW": ("power", 1e6, 0.0, "W"),
    # energy -> J
    "J": ("energy", 1.0, 0.0, "J"),
    "kJ": ("energy", 1e3, 0.0, "J"),
    "MJ": ("energy", 1e6, 0.0, "J"),
    "Wh": ("energy", 3600.0, 0.0, "J"),
    "kWh": ("energy", 3.6e6, 0.0, "J"),
    "MWh": ("energy", 3.6e9, 0.0, "J"),
    # irradiance -> W/m2
    "W/m2": ("irradiance", 1.0, 0.0, "W/m2"),
    "W/m²": ("irradiance", 1.0, 0.0, "W/m2"),
    "kW/m2": ("irradiance", 1e3, 0.0, "W/m2"),
    "kW/m²": ("irradiance", 1e3, 0.0, "W/m2"),
    # relative humidity -> %
    "%": ("relative_humidity", 1.0, 0.0, "%"),
    "%RH": ("relative_humidity", 1.0, 0.0, "%"),
    "% RH": ("relative_humidity", 1.0, 0.0, "%"),
    # CO2 -> ppm
    "ppm": ("co2", 1.0, 0.0, "ppm"),
    # pressure -> Pa
    "Pa": ("pressure", 1.0, 0.0, "Pa"),
    "hPa": ("pressure", 100.0, 0.0, "Pa"),
    "mbar": ("pressure", 100.0, 0.0, "Pa"),
    "kPa": ("pressure", 1e3, 0.0, "Pa"),
    "bar": ("pressure", 1e5, 0.0, "Pa"),
    # speed -> m/s
    "m/s": ("speed", 1.0, 0.0, "m/s"),
    "km/h": ("speed", 1.0 / 3.6, 0.0, "m/s"),
    # dimensionless
    "-": ("dimensionless", 1.0, 0.0, "-"),
    "1": ("dimensionless", 1.0, 0.0, "-"),
}
_UNITS_FOLDED = {name.casefold(): name for name in UNITS}

#: Canonical unit per quantity.
CANONICAL_UNITS: dict[str, str] = {
    "temperature": "C",
    "flow": "m3/s",
    "power": "W",
    "energy": "J",
    "irradiance": "W/m2",
    "relative_humidity": "%",
    "co2": "ppm",
    "pressure": "Pa",
    "speed": "m/s",
    "dimensionless": "-",
}

#: Physically possible range per quantity, in canonical units: (low, high, reason). Values
#: outside are removed before resampling and listed in the report. Temperatures: building air,
#: outdoor air and hydronic heating water; flows: a building's heating circuit (360 m3/h max).
PHYSICAL_LIMITS: dict[str, tuple[float, float, str]] = {
    "temperature": (-60.0, 110.0, "building, outdoor and heating-water temperatures lie in"),
    "flow": (0.0, 0.1, "a heating-circuit volume flow lies in"),
    "power": (0.0, 1e8, "a heat or electric power lies in"),
    "energy": (0.0, math.inf, "a meter reading lies in"),
    "irradiance": (-20.0, 1600.0, "solar irradiance lies in"),
    "relative_humidity": (0.0, 100.0, "relative humidity lies in"),
    "co2": (0.0, 50_000.0, "a CO2 concentration lies in"),
    "pressure": (30_000.0, 110_000.0, "atmospheric pressure lies in"),
    "speed": (0.0, 100.0, "a wind or air speed lies in"),
}

#: Smallest deviation from the local median that can be a spike, per quantity (canonical units).
#: Quantities not listed (flow, power, irradiance, energy) legitimately jump and are not screened.
OUTLIER_FLOORS: dict[str, float] = {
    "temperature": 1.5,
    "relative_humidity": 10.0,
    "co2": 300.0,
    "pressure": 500.0,
}

#: Resampling operations (see the module docstring).
OPERATIONS: tuple[str, ...] = (
    "mean",
    "mean_linear",
    "last",
    "first",
    "min",
    "max",
    "sum",
    "count",
)

_DEFAULT_OPERATION = {"energy": "last"}
_NA_TOKENS = ["", "NA", "N/A", "NaN", "nan", "NAN", "null", "NULL", "None", "-", "#N/A"]
_TIME_CANDIDATES = ("time", "timestamp", "datetime", "date_time", "date", "zeit", "t")
_HEADER_UNIT = re.compile(r"^(?P<name>.*?)\s*[\[(](?P<unit>[^\[\]()]*)[\])]\s*$")
_TEMPERATURE_NAME = re.compile(
    r"(?i:temp|theta)|^[tT]($|[_\-\s\d])|^[tT][a-z]{1,2}$|^T[A-Z][a-z]|(^|_)[tT](_|$)"
)
_FLOW_NAME = re.compile(r"(?i)flow|durchfluss|^v_?dot|volume_?rate")


# ----------------------------------------------------------------------------------------------
# file helpers
# ----------------------------------------------------------------------------------------------
def _data_line_numbers(path: Path, comment: str | None) -> tuple[int, np.ndarray]:
    """1-based line of the header and of every data row, as pandas' C parser counts them."""
    header = 0
    lines: list[int] = []
    with path.open("r", encoding="utf-8-sig", errors="replace", newline=None) as handle:
        for number, line in enumerate(handle, start=1):
            text = line.split(comment, 1)[0] if comment else line
            if not text.strip():
                continue
            if header == 0:
                header = number
            else:
                lines.append(number)
    return header, np.asarray(lines, dtype=np.int64)


def _line_numbers(path: Path, n_rows: int, comment: str | None) -> np.ndarray:
    """Line numbers of the data rows; fast when there are no blank or comment lines."""
    raw = path.read_bytes()
    simple = b"\n\n" not in raw and b"\r\n\r\n" not in raw and not raw.startswith((b"\n", b"\r"))
    if comment:
        simple = simple and comment.encode() not in raw
    if simple:
        return np.arange(2, n_rows + 2, dtype=np.int64)
    _, lines = _data_line_numbers(path, comment)
    if len(lines) != n_rows:  # quoted multi-line fields: fall back to row numbers
        return np.arange(2, n_rows + 2, dtype=np.int64)
    return lines


def _sniff_separator(path: Path, comment: str | None) -> str:
    with path.open("r", encoding="utf-8-sig", errors="replace") as handle:
        for line in handle:
            text = line.split(comment, 1)[0] if comment else line
            if text.strip():
                counts = {sep: text.count(sep) for sep in (",", ";", "\t", "|")}
                best = max(counts, key=counts.get)
                return best if counts[best] > 0 else ","
    raise ThermocalInputError(f"{path}: the file is empty (no header line)")


def _split_header_unit(column: str) -> tuple[str, str | None]:
    match = _HEADER_UNIT.match(str(column))
    if match and match.group("name").strip():
        return match.group("name").strip(), match.group("unit").strip()
    return str(column).strip(), None


def _resolve_unit(unit: str, where: str) -> str:
    if unit in UNITS:
        return unit
    folded = _UNITS_FOLDED.get(unit.casefold())
    if folded is not None:
        return folded
    close = difflib.get_close_matches(unit, list(UNITS), n=1)
    suggestion = f"; did you mean '{close[0]}'?" if close else ""
    raise ThermocalInputError(
        f"{where}: unknown unit '{unit}'{suggestion} (known units: {', '.join(UNITS)})"
    )


def _suggest(name: str, options: Sequence[str]) -> str:
    close = difflib.get_close_matches(name, list(options), n=1)
    return f"; did you mean '{close[0]}'?" if close else ""


def _guess_quantity(name: str) -> str | None:
    if _FLOW_NAME.search(name):
        return "flow"
    if _TEMPERATURE_NAME.search(name):
        return "temperature"
    return None


# ----------------------------------------------------------------------------------------------
# parsing
# ----------------------------------------------------------------------------------------------
def _parse_numbers(
    series: pd.Series, *, source: str, column: str, lines: np.ndarray, decimal: str
) -> np.ndarray:
    """Float values of a column; unparseable entries are errors naming the line."""
    if pd.api.types.is_numeric_dtype(series.dtype) and not pd.api.types.is_bool_dtype(series.dtype):
        return series.to_numpy(dtype=np.float64, na_value=np.nan)
    text = series.astype("string")
    if decimal != ".":
        text = text.str.replace(decimal, ".", regex=False)
    numbers = pd.to_numeric(text, errors="coerce")
    bad = numbers.isna().to_numpy() & text.notna().to_numpy()
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        value = series.iloc[first]
        hint = ""
        if isinstance(value, str) and re.fullmatch(r"\s*-?\d+,\d+\s*", value):
            hint = " (a decimal comma: pass decimal=',')"
        raise ThermocalInputError(
            f"{source}, column '{column}', line {lines[first]}: cannot read {value!r} as a "
            f"number{hint}; {int(bad.sum())} such value(s) in this column. Fix the file, or "
            f"leave the cell empty for a missing value"
        )
    return numbers.to_numpy(dtype=np.float64, na_value=np.nan)


def _check_order(
    times_ns: np.ndarray,
    lines: np.ndarray,
    *,
    source: str,
    column: str,
    what: str,
    duplicates: str,
) -> np.ndarray:
    """Indices to keep (file order); errors on decreasing or (by default) repeated times."""
    step = np.diff(times_ns)
    decreasing = np.flatnonzero(step < 0)
    if decreasing.size:
        i = int(decreasing[0])
        raise ThermocalInputError(
            f"{source}, column '{column}', line {lines[i + 1]}: time "
            f"{pd.Timestamp(times_ns[i + 1], tz='UTC').isoformat()} (UTC) is earlier than the "
            f"previous one{what} on line {lines[i]} "
            f"({pd.Timestamp(times_ns[i], tz='UTC').isoformat()}); the log must be in time "
            f"order: sort it, or pass sort=True"
        )
    repeated = np.flatnonzero(step == 0)
    keep = np.ones(times_ns.size, dtype=bool)
    if repeated.size:
        if duplicates == "error":
            i = int(repeated[0])
            raise ThermocalInputError(
                f"{source}, column '{column}', line {lines[i + 1]}: duplicated time "
                f"{pd.Timestamp(times_ns[i], tz='UTC').isoformat()} (UTC){what}, already on "
                f"line {lines[i]} ({repeated.size} duplicate(s)); remove them, or pass "
                f"duplicates='first' or 'last'"
            )
        if duplicates == "first":
            keep[repeated + 1] = False
        else:
            keep[repeated] = False
    return keep


#: Temperatures a building's measurements can have (outdoor air included) [C].
PLAUSIBLE_TEMPERATURE = (-50.0, 60.0)
#: Mean indoor temperature a zone can have over a measured period [C]; outside, a unit slip.
INDOOR_MEAN_RANGE = (-30.0, 35.0)
#: A sensor whose mean differs from its neighbours' median by more than this is checked for a
#: unit slip [K] (an unheated cellar or attic may legitimately differ by 10-15 K).
NEIGHBOUR_TOLERANCE = 15.0
#: A converted mean this close to the neighbours' median identifies the unit slip [K].
UNIT_MATCH = 5.0

#: Unit slips of a temperature logged where degrees C are expected: (name, the unit to
#: declare, conversion of a mean to C).
TEMPERATURE_UNIT_SLIPS = (
    (
        "Kelvin?",
        "declare its unit as K (in the header, e.g. 'NAME [K]', a unit column, or units=)",
        lambda v: v - 273.15,
    ),
    (
        "Fahrenheit?",
        "declare its unit as F (in the header, e.g. 'NAME [F]', a unit column, or units=)",
        lambda v: (v - 32.0) * 5.0 / 9.0,
    ),
    (
        "tenths of a degree? (202 for 20.2 C)",
        "divide its values by 10 in the file",
        lambda v: v / 10.0,
    ),
    (
        "hundredths of a degree? (2020 for 20.20 C)",
        "divide its values by 100 in the file",
        lambda v: v / 100.0,
    ),
)


def temperature_unit_slip(
    mean: float,
    reference: float | None = None,
    *,
    plausible: tuple[float, float] = INDOOR_MEAN_RANGE,
):
    """The unit slip that explains a temperature read as C best, or None when it is plausible.

    Parameters
    ----------
    mean : float
        The (mean) value as read [C].
    reference : float, optional
        What it should be near: the neighbouring sensors' median or the sensor's typical day
        [C] (None: 20 C is used to rank the candidates).
    plausible : (float, float)
        Range of a plausible value [C]. A value outside it is always a slip (the best
        candidate, or "not an indoor temperature" when none fits); one inside it is a slip
        only when it is more than :data:`NEIGHBOUR_TOLERANCE` from ``reference`` and a
        conversion brings it within :data:`UNIT_MATCH` of it.

    Returns
    -------
    tuple or None
        ``(label, remedy, value in C)``: e.g. ``("Fahrenheit?", "declare its unit as F (...)",
        10.0)``; ``NAME`` in the remedy stands for the column.
    """
    low, high = plausible
    target = 20.0 if reference is None else reference
    plausible = low <= mean <= high
    if plausible and (reference is None or abs(mean - reference) <= NEIGHBOUR_TOLERANCE):
        return None
    fits = []
    for label, remedy, convert in TEMPERATURE_UNIT_SLIPS:  # in order of how common the slip is
        value = convert(mean)
        if low <= value <= high and (plausible is False or abs(value - target) <= UNIT_MATCH):
            fits.append((abs(value - target), label, remedy, value))
    close = [fit for fit in fits if fit[0] <= UNIT_MATCH]
    if close:
        return close[0][1:]
    if fits:
        return min(fits)[1:]
    return None if plausible else ("not an indoor temperature", "check its unit", float("nan"))


def _convert_units(
    name: str,
    values: np.ndarray,
    *,
    unit: str | None,
    quantity: str | None,
    source: str,
    column_label: str,
    lines: np.ndarray | None,
) -> tuple[np.ndarray, str | None, str, str | None]:
    """Convert to canonical units; returns (values, quantity, canonical unit, conversion note)."""
    where = f"{source}, column '{column_label}'"
    finite = values[np.isfinite(values)]
    if unit is not None:
        unit = _resolve_unit(unit, where)
        unit_quantity, factor, offset, canonical = UNITS[unit]
        if quantity is not None and quantity != unit_quantity:
            raise ThermocalInputError(
                f"{where}: declared quantity '{quantity}' does not match unit '{unit}' "
                f"({unit_quantity})"
            )
        quantity = unit_quantity
        if quantity == "temperature" and canonical == unit and finite.size:
            low_share = np.mean(finite < 100.0)
            if low_share < 0.5 and np.median(finite) > 150.0:
                median = float(np.median(finite))
                slip = temperature_unit_slip(median, plausible=PLAUSIBLE_TEMPERATURE)
                label, remedy = (
                    ("Kelvin?", "declare [K] if they are")
                    if slip is None or slip[0] == "not an indoor temperature"
                    else slip[:2]
                )
                raise ThermocalInputError(
                    f"{where}: the unit is declared as {unit} but the values (median "
                    f"{median:.1f}) look like {label.replace('?', '')}; "
                    f"{remedy.replace('NAME', name)}, or fix the values"
                )
        note = None
        if factor != 1.0 or offset != 0.0:
            values = values * factor + offset
            note = f"{unit} -> {canonical}"
        return values, quantity, canonical, note
    if quantity is not None and quantity not in CANONICAL_UNITS:
        raise ThermocalInputError(
            f"{where}: unknown quantity '{quantity}'{_suggest(quantity, CANONICAL_UNITS)} "
            f"(known: {', '.join(CANONICAL_UNITS)})"
        )
    if quantity is None:
        quantity = _guess_quantity(name)
    if quantity == "temperature" and finite.size:
        celsius_like = finite < 100.0
        kelvin_like = (finite > 200.0) & (finite < 400.0)
        if kelvin_like.any() and celsius_like.any():
            index_c = int(np.flatnonzero(np.isfinite(values) & (values < 100.0))[0])
            index_k = int(np.flatnonzero((values > 200.0) & (values < 400.0))[0])
            line_c = f" (line {lines[index_c]})" if lines is not None else ""
            line_k = f" (line {lines[index_k]})" if lines is not None else ""
            raise ThermocalInputError(
                f"{where}: temperature unit ambiguous: {values[index_c]:g}{line_c} looks like "
                f"Celsius but {values[index_k]:g}{line_k} like Kelvin "
                f"({int(celsius_like.sum())} values below 100, {int(kelvin_like.sum())} above "
                f"200); declare the unit ('{name} [K]' in the header or units={{'{name}': 'K'}}) "
                f"and fix the values that are in the other unit"
            )
        median_c = float(np.median(finite)) - 273.15
        plausible_kelvin = PLAUSIBLE_TEMPERATURE[0] <= median_c <= PLAUSIBLE_TEMPERATURE[1]
        if kelvin_like.all() and plausible_kelvin:  # 202 is 20.2 C in tenths, not -71 C
            return (
                values - 273.15,
                quantity,
                "C",
                f"K -> C (detected: values {finite.min():g} to {finite.max():g}, no unit declared)",
            )
    if quantity == "flow" and finite.size and np.nanmax(np.abs(finite)) > 0.1:
        raise ThermocalInputError(
            f"{where}: flow without a declared unit and values up to {np.max(finite):g}, "
            f"impossible in m3/s for a building; declare the unit in the header ('{name} [l/h]', "
            f"'[m3/h]') or with units={{'{name}': 'l/h'}}"
        )
    canonical = CANONICAL_UNITS.get(quantity, "") if quantity else ""
    note = None
    if quantity == "flow":
        note = "no unit declared: assumed m3/s"
    return values, quantity, canonical, note


# ----------------------------------------------------------------------------------------------
# reading
# ----------------------------------------------------------------------------------------------
def read_measurements(
    path: str | Path,
    *,
    layout: Literal["auto", "long", "wide"] = "auto",
    time_column: str = "time",
    sensor_column: str = "sensor",
    value_column: str = "value",
    unit_column: str = "unit",
    sensors: Sequence[str] | Mapping[str, str] | None = None,
    units: Mapping[str, str] | None = None,
    quantities: Mapping[str, str] | None = None,
    tz: Any = None,
    time_format: str | None = None,
    time_unit: str | None = None,
    start: Any = None,
    sep: str | None = None,
    decimal: str = ".",
    comment: str | None = None,
    duplicates: Literal["error", "first", "last"] = "error",
    sort: bool = False,
    rows: Literal["reports", "interval_start", "interval_end"] = "reports",
    interval: Any = None,
    unknown_sensors: Literal["error", "ignore"] = "error",
) -> tuple[pd.DataFrame, dict]:
    """Read a sensor log (CSV or parquet, long or wide) into reports in thermocal units.

    Parameters
    ----------
    path : str or Path
        CSV file (the separator is sniffed from the header: ``,``, ``;``, tab, ``|``), or a
        parquet table (``.parquet``, ``.pq``; its time column may be text, numbers or
        datetimes). Messages about a parquet table count its rows as lines (1 = first row).
    layout : {"auto", "long", "wide"}
        "long": one report per row with ``time_column``, ``sensor_column``, ``value_column``
        (and optionally ``unit_column``); "wide": ``time_column`` plus one column per sensor,
        empty cells meaning "not reported". "auto": long when the sensor and value columns exist.
    time_column : str
        Name of the time column. When absent, a single column called time, timestamp, datetime,
        date or t (any case) is used.
    sensor_column, value_column, unit_column : str
        Column names of the long layout.
    sensors : sequence of str or mapping, optional
        The expected sensors. A mapping renames file names to thermocal names
        (``{"Sensor 12": "temp_living"}``). Sensors in the file but not here are errors (with the
        line of their first report) unless ``unknown_sensors="ignore"``; expected sensors absent
        from the file are errors.
    units : mapping, optional
        Unit per sensor (file or renamed name), e.g. ``{"flow": "l/h", "T_cellar": "K"}``;
        overrides nothing: a unit also declared in the file must agree.
    quantities : mapping, optional
        Quantity per sensor (``"temperature"``, ``"flow"``, ``"power"``, ...) when no unit is
        declared; otherwise guessed from the name (``T_...``, ``temp...`` -> temperature,
        ``...flow...`` -> flow).
    tz : str, datetime.tzinfo, float or None
        Time zone of timestamps written without UTC offset (required for those), and of the
        result; timestamps with offsets are converted to it. A number is a fixed offset [h east
        of UTC] (local standard time, e.g. 1.0). None keeps the file's offset (UTC when the
        offsets vary). Local times that do not exist or are ambiguous at a clock change are
        errors naming the line.
    time_format : str, optional
        strftime format of the time column when it is not ISO 8601, e.g. "%d.%m.%Y %H:%M".
    time_unit : {"s", "ms", "min", "h", "d"}, optional
        For numeric time columns: the unit of the numbers; ``start`` is the time of 0.
    start : str or Timestamp, optional
        Origin of numeric times (default 1970-01-01 UTC).
    sep : str, optional
        Field separator (sniffed when None).
    decimal : str
        Decimal mark ("." or ",").
    comment : str, optional
        Lines (or line ends) after this character are ignored, e.g. "#".
    duplicates : {"error", "first", "last"}
        Repeated timestamps (per sensor): an error, or keep the first/last report.
    sort : bool
        Sort out-of-order rows by time instead of raising an error (reported in ``meta``).
    rows : {"reports", "interval_start", "interval_end"}
        What a row is. "reports" (default): an event or sample at its time stamp, held until
        the next report by :func:`resample_measurements`. "interval_start": the mean over the
        logging interval ``[t, t + interval)`` labelled by its start (typical of data loggers
        and of exported hourly/10-minute tables); "interval_end": the same labelled by its end
        (the times are shifted back by ``interval``). For both, ``meta["interval"]`` tells
        :func:`resample_measurements` to hold each row until the next one but for at most
        ``interval``, and the last row until its interval end.
    interval : str or Timedelta, optional
        The logging interval of ``rows="interval_start"``/``"interval_end"`` [duration];
        default the median spacing of the time stamps (per sensor in the long layout, the
        median over the sensors).
    unknown_sensors : {"error", "ignore"}
        With ``sensors`` given: columns (wide) or rows (long) of other sensors are an error, or
        are skipped (listed in ``meta["notes"]``), e.g. to read a few columns of a big table.

    Returns
    -------
    raw : DataFrame
        Long layout: columns ``time`` (tz-aware), ``sensor`` (category), ``value`` [canonical
        unit], sorted by sensor then time, indexed by the 1-based line number in the file
        (``line``). Wide layout: tz-aware DatetimeIndex ``time``, one float column per sensor
        (NaN = no report). Either can be passed to :func:`resample_measurements`. ``raw.attrs
        ["measurements"]`` holds ``meta``.
    meta : dict
        ``source``, ``layout``, ``sensors``, ``units`` (canonical, per sensor),
        ``units_in_file``, ``quantities``, ``conversions`` (per sensor, e.g. "K -> C (detected
        ...)"), ``notes`` (everything assumed or changed), ``n_reports`` (per sensor), ``tz``,
        ``rows`` and ``interval`` (Timedelta, or None for reports).

    Raises
    ------
    ThermocalInputError
        Missing file or columns, unreadable times or values, duplicated or decreasing
        timestamps, unknown or missing sensors, unknown or ambiguous units; the message names
        the file, the column and the 1-based line.
    """
    path = Path(path)
    source = str(path)
    if not path.is_file():
        raise ThermocalInputError(f"measurement file {path} does not exist")
    if layout not in ("auto", "long", "wide"):
        raise ThermocalInputError(f"layout = {layout!r}; use 'auto', 'long' or 'wide'")
    if duplicates not in ("error", "first", "last"):
        raise ThermocalInputError(f"duplicates = {duplicates!r}; use 'error', 'first' or 'last'")
    if rows not in ("reports", "interval_start", "interval_end"):
        raise ThermocalInputError(
            f"rows = {rows!r}; use 'reports', 'interval_start' or 'interval_end'"
        )
    interval_td = _as_timedelta(interval, "interval")
    if interval_td is not None and rows == "reports":
        raise ThermocalInputError(
            "interval= describes logs of interval means: pass rows='interval_start' or "
            "'interval_end' with it"
        )
    if path.suffix.lower() in (".parquet", ".pq"):
        frame = _read_parquet_table(path)
        lines = np.arange(1, len(frame) + 1, dtype=np.int64)
        source = f"{path} (parquet; line = table row)"
    else:
        frame = _read_csv_table(path, sep=sep, decimal=decimal, comment=comment)
        lines = _line_numbers(path, len(frame), comment)
    notes: list[str] = []

    time_col = _find_time_column(frame.columns, time_column, source, notes)
    columns_folded = {c.casefold(): c for c in frame.columns}
    is_long = sensor_column.casefold() in columns_folded and (
        value_column.casefold() in columns_folded
    )
    if layout == "long" and not is_long:
        missing = [c for c in (sensor_column, value_column) if c.casefold() not in columns_folded]
        raise ThermocalInputError(
            f"{source}: layout 'long' needs columns '{sensor_column}' and '{value_column}'; "
            f"missing {missing} (columns: {list(frame.columns)}); pass sensor_column= / "
            f"value_column="
        )
    long_layout = layout == "long" or (layout == "auto" and is_long)
    if unknown_sensors not in ("error", "ignore"):
        raise ThermocalInputError(f"unknown_sensors = {unknown_sensors!r}; use 'error' or 'ignore'")
    if unknown_sensors == "ignore" and sensors is not None:
        wanted = {sensors} if isinstance(sensors, str) else set(sensors)
        if long_layout:
            names = frame[columns_folded[sensor_column.casefold()]].astype("string").str.strip()
            keep = names.isin(wanted).to_numpy()
            skipped = sorted(set(names[~keep].dropna()))
            frame, lines = frame[keep].reset_index(drop=True), lines[keep]
        else:
            skipped = [
                c for c in frame.columns if c != time_col and _split_header_unit(c)[0] not in wanted
            ]
            frame = frame.drop(columns=skipped)
        if skipped:
            notes.append(f"sensors not in sensors= skipped: {skipped}")
    times, time_note = parse_time_column(
        frame[time_col],
        source=source,
        column=time_col,
        lines=lines,
        tz=tz,
        time_unit=time_unit,
        start=start,
        time_format=time_format,
    )
    if time_note:
        notes.append(time_note)
    context = dict(
        source=source,
        lines=lines,
        sensors=sensors,
        units=units or {},
        quantities=quantities or {},
        decimal=decimal,
        duplicates=duplicates,
        sort=sort,
        notes=notes,
        time_col=time_col,
    )
    if long_layout:
        raw, meta = _read_long(
            frame,
            times,
            sensor_col=columns_folded[sensor_column.casefold()],
            value_col=columns_folded[value_column.casefold()],
            unit_col=columns_folded.get(unit_column.casefold()),
            **context,
        )
    else:
        raw, meta = _read_wide(frame.drop(columns=[time_col]), times, **context)
    if rows != "reports":
        raw, interval_td = _as_interval_means(raw, rows, interval_td, source, notes)
    meta.update(
        source=str(path),
        tz=str(raw_tz(raw)),
        notes=notes,
        rows="reports" if rows == "reports" else "interval means",
        interval=interval_td,
    )
    raw.attrs["measurements"] = meta
    return raw, meta


def _read_csv_table(path: Path, *, sep: str | None, decimal: str, comment: str | None):
    separator = sep or _sniff_separator(path, comment)
    try:
        frame = pd.read_csv(
            path,
            sep=separator,
            decimal=decimal,
            comment=comment,
            na_values=_NA_TOKENS,
            keep_default_na=False,
            skipinitialspace=True,
            encoding="utf-8-sig",
            low_memory=False,
        )
    except (pd.errors.ParserError, UnicodeDecodeError, pd.errors.EmptyDataError) as exc:
        raise ThermocalInputError(f"{path}: cannot read as CSV ({exc})") from None
    frame.columns = [str(c).strip() for c in frame.columns]
    if frame.empty:
        raise ThermocalInputError(f"{path}: no data rows below the header")
    return frame


def _read_parquet_table(path: Path) -> pd.DataFrame:
    try:
        frame = pd.read_parquet(path)
    except Exception as exc:  # noqa: BLE001 - pyarrow raises many types for a bad file
        raise ThermocalInputError(f"{path}: cannot read as parquet ({exc})") from None
    if not isinstance(frame.index, pd.RangeIndex):  # e.g. a DatetimeIndex written by pandas
        frame = frame.reset_index()
    frame.columns = [str(c).strip() for c in frame.columns]
    if frame.empty:
        raise ThermocalInputError(f"{path}: the parquet table has no rows")
    return frame.reset_index(drop=True)


def _as_interval_means(
    raw: pd.DataFrame, rows: str, interval: pd.Timedelta | None, source: str, notes: list[str]
) -> tuple[pd.DataFrame, pd.Timedelta]:
    """Logging interval of a log of interval means; rows labelled by their end are moved back."""
    if interval is None:
        if isinstance(raw.index, pd.DatetimeIndex):
            spacings = [np.diff(raw.index.asi8)]
        else:
            spacings = [np.diff(g.asi8) for _, g in raw.groupby("sensor", observed=True)["time"]]
        medians = [float(np.median(d)) for d in spacings if d.size]
        if not medians:
            raise ThermocalInputError(
                f"{source}: one row per sensor: the logging interval cannot be inferred; "
                "pass interval="
            )
        interval = pd.Timedelta(int(round(float(np.median(medians)))), unit="ns")
        notes.append(f"logging interval {interval} (median spacing of the time stamps)")
    if rows == "interval_end":
        if isinstance(raw.index, pd.DatetimeIndex):
            raw.index = pd.DatetimeIndex(raw.index - interval, name=raw.index.name)
        else:
            raw["time"] = raw["time"] - interval
        notes.append(f"rows labelled by their interval end moved back by {interval}")
    notes.append(f"rows are means over [t, t + {interval}) labelled by their start (rows='{rows}')")
    return raw, interval


def raw_tz(raw: pd.DataFrame):
    """Time zone of a raw measurement frame (long or wide)."""
    if isinstance(raw.index, pd.DatetimeIndex):
        return raw.index.tz
    return raw["time"].dt.tz


def _find_time_column(columns: Sequence[str], wanted: str, source: str, notes: list[str]) -> str:
    if wanted in columns:
        return wanted
    folded = {c.casefold(): c for c in columns}
    if wanted.casefold() in folded:
        return folded[wanted.casefold()]
    names = [_split_header_unit(c)[0].casefold() for c in columns]
    candidates = [columns[i] for i, n in enumerate(names) if n in _TIME_CANDIDATES]
    if len(candidates) == 1:
        notes.append(f"time column '{candidates[0]}' used (no column '{wanted}')")
        return candidates[0]
    raise ThermocalInputError(
        f"{source}: no time column '{wanted}'{_suggest(wanted, list(columns))} (columns: "
        f"{list(columns)}); pass time_column="
    )


def _rename_map(
    names: Sequence[str],
    sensors: Sequence[str] | Mapping[str, str] | None,
    *,
    source: str,
    column: str,
    first_line: Mapping[str, int] | None,
) -> dict[str, str]:
    """File name -> thermocal name; unknown and missing sensors are errors."""
    if sensors is None:
        return {name: name for name in names}
    if isinstance(sensors, str):
        sensors = [sensors]
    mapping = dict(sensors) if isinstance(sensors, Mapping) else {s: s for s in sensors}
    unknown = [name for name in names if name not in mapping]
    if unknown:
        name = unknown[0]
        line = f", line {first_line[name]}" if first_line else ", line 1 (header)"
        raise ThermocalInputError(
            f"{source}, column '{column}'{line}: unknown sensor '{name}'"
            f"{_suggest(name, list(mapping))} ({len(unknown)} unknown: {unknown[:10]}); expected "
            f"sensors: {list(mapping)}. Add it to sensors= or fix the name"
        )
    missing = [name for name in mapping if name not in set(names)]
    if missing:
        raise ThermocalInputError(
            f"{source}: expected sensor(s) {missing} not found in column '{column}'"
            f"{_suggest(missing[0], list(names))}"
        )
    targets = list(mapping.values())
    clash = {t for t in targets if targets.count(t) > 1}
    if clash:
        raise ThermocalInputError(f"sensors=: several file names map to {sorted(clash)}")
    return mapping


def _lookup(mapping: Mapping[str, Any], file_name: str, name: str) -> Any:
    if name in mapping:
        return mapping[name]
    return mapping.get(file_name)


def _read_long(
    frame: pd.DataFrame,
    times: pd.DatetimeIndex,
    *,
    sensor_col: str,
    value_col: str,
    unit_col: str | None,
    source: str,
    lines: np.ndarray,
    sensors,
    units,
    quantities,
    decimal,
    duplicates,
    sort,
    notes,
    time_col,
) -> tuple[pd.DataFrame, dict]:
    codes, raw_names = pd.factorize(frame[sensor_col], sort=False)
    stripped = [str(n).strip() for n in raw_names]
    position = {name: i for i, name in enumerate(dict.fromkeys(stripped))}
    names = list(position)  # names equal after stripping blanks are merged
    remap = np.asarray([position[n] for n in stripped] + [-1], dtype=np.int64)
    codes = remap[codes]  # code -1 (missing) stays -1
    empty = [position[""]] if "" in position else []
    missing_sensor = (codes < 0) | np.isin(codes, empty)
    if missing_sensor.any():
        first = int(np.flatnonzero(missing_sensor)[0])
        raise ThermocalInputError(
            f"{source}, column '{sensor_col}', line {lines[first]}: missing sensor name"
        )
    first_rows = np.full(len(names), -1, dtype=np.int64)
    order_first = np.unique(codes, return_index=True)
    first_rows[order_first[0]] = order_first[1]
    first_line = {names[c]: int(lines[first_rows[c]]) for c in range(len(names))}
    rename = _rename_map(names, sensors, source=source, column=sensor_col, first_line=first_line)
    values = _parse_numbers(
        frame[value_col], source=source, column=value_col, lines=lines, decimal=decimal
    )
    times_ns = times.asi8
    # per-sensor order: stable sort by sensor keeps file order within each sensor
    order = np.argsort(codes, kind="stable")
    codes_sorted = codes[order]
    if sort:
        order = np.lexsort((times_ns, codes))
        if not np.array_equal(order, np.argsort(codes, kind="stable")):
            notes.append("rows out of time order were sorted (sort=True)")
        codes_sorted = codes[order]
    bounds = np.flatnonzero(np.diff(codes_sorted)) + 1
    starts = np.concatenate(([0], bounds))
    ends = np.concatenate((bounds, [len(order)]))

    unit_values = None
    if unit_col is not None:
        unit_values = frame[unit_col].astype("string").str.strip()

    keep_sorted = np.ones(len(order), dtype=bool)
    out_values = values[order]
    meta_units, meta_file_units, meta_quantities, conversions, n_reports = {}, {}, {}, {}, {}
    for begin, end in zip(starts, ends, strict=True):
        rows = order[begin:end]
        file_name = names[codes_sorted[begin]]
        name = rename[file_name]
        keep = _check_order(
            times_ns[rows],
            lines[rows],
            source=source,
            column=time_col,
            what=f" of sensor '{file_name}'",
            duplicates=duplicates,
        )
        keep_sorted[begin:end] = keep
        unit = _lookup(units, file_name, name)
        if unit_values is not None:
            declared = unit_values.iloc[rows].dropna().unique()
            declared = [u for u in declared if u]
            if len(declared) > 1:
                position = int(
                    np.flatnonzero((unit_values.iloc[rows] != declared[0]).fillna(False))[0]
                )
                raise ThermocalInputError(
                    f"{source}, column '{unit_col}', line {lines[rows[position]]}: sensor "
                    f"'{file_name}' changes unit from '{declared[0]}' to "
                    f"'{unit_values.iloc[rows[position]]}'; one unit per sensor"
                )
            if declared:
                if unit is not None and _resolve_unit(unit, source) != _resolve_unit(
                    declared[0], source
                ):
                    raise ThermocalInputError(
                        f"{source}: sensor '{file_name}' has unit '{declared[0]}' in column "
                        f"'{unit_col}' but units= says '{unit}'"
                    )
                unit = declared[0]
        converted, quantity, canonical, note = _convert_units(
            name,
            out_values[begin:end],
            unit=unit,
            quantity=_lookup(quantities, file_name, name),
            source=source,
            column_label=f"{value_col}' of sensor '{file_name}",
            lines=lines[rows],
        )
        out_values[begin:end] = converted
        meta_units[name] = canonical
        meta_file_units[name] = unit
        meta_quantities[name] = quantity
        if note:
            conversions[name] = note
        n_reports[name] = int(keep.sum())
    if not keep_sorted.all():
        notes.append(
            f"{int((~keep_sorted).sum())} duplicated report(s) dropped (duplicates='{duplicates}')"
        )
    order = order[keep_sorted]
    categories = list(dict.fromkeys(rename[n] for n in names))
    category_of = {name: i for i, name in enumerate(categories)}
    sensor_names = pd.Categorical.from_codes(
        np.asarray([category_of[rename[n]] for n in names])[codes[order]],
        categories=categories,
    )
    raw = pd.DataFrame(
        {
            "time": times[order],
            "sensor": sensor_names,
            "value": out_values[keep_sorted],
        },
        index=pd.Index(lines[order], name="line"),
    )
    meta = {
        "layout": "long",
        "sensors": categories,
        "units": meta_units,
        "units_in_file": meta_file_units,
        "quantities": meta_quantities,
        "conversions": conversions,
        "n_reports": n_reports,
    }
    return raw, meta


def _read_wide(
    frame: pd.DataFrame,
    times: pd.DatetimeIndex,
    *,
    source: str,
    lines: np.ndarray,
    sensors,
    units,
    quantities,
    decimal,
    duplicates,
    sort,
    notes,
    time_col,
) -> tuple[pd.DataFrame, dict]:
    if frame.shape[1] == 0:
        raise ThermocalInputError(f"{source}: no sensor columns besides '{time_col}'")
    header = {column: _split_header_unit(column) for column in frame.columns}
    file_names = [header[c][0] for c in frame.columns]
    repeated = {n for n in file_names if file_names.count(n) > 1}
    if repeated:
        raise ThermocalInputError(
            f"{source}, line 1 (header): repeated column(s) {sorted(repeated)}"
        )
    rename = _rename_map(file_names, sensors, source=source, column="(header)", first_line=None)
    times_ns = times.asi8
    order = np.arange(len(times_ns))
    if sort and np.any(np.diff(times_ns) < 0):
        order = np.argsort(times_ns, kind="stable")
        notes.append("rows out of time order were sorted (sort=True)")
    keep = _check_order(
        times_ns[order],
        lines[order],
        source=source,
        column=time_col,
        what="",
        duplicates=duplicates,
    )
    rows = order[keep]
    data: dict[str, np.ndarray] = {}
    meta_units, meta_file_units, meta_quantities, conversions, n_reports = {}, {}, {}, {}, {}
    for column in frame.columns:
        file_name, header_unit = header[column]
        name = rename[file_name]
        values = _parse_numbers(
            frame[column], source=source, column=column, lines=lines, decimal=decimal
        )[rows]
        unit = _lookup(units, file_name, name)
        if header_unit is not None:
            if unit is not None and _resolve_unit(unit, source) != _resolve_unit(
                header_unit, f"{source}, column '{column}'"
            ):
                raise ThermocalInputError(
                    f"{source}, column '{column}': the header declares '{header_unit}' but "
                    f"units= says '{unit}'"
                )
            unit = header_unit
        converted, quantity, canonical, note = _convert_units(
            name,
            values,
            unit=unit,
            quantity=_lookup(quantities, file_name, name),
            source=source,
            column_label=column,
            lines=lines[rows],
        )
        data[name] = converted
        meta_units[name] = canonical
        meta_file_units[name] = unit
        meta_quantities[name] = quantity
        if note:
            conversions[name] = note
        n_reports[name] = int(np.isfinite(converted).sum())
    if not keep.all():
        notes.append(f"{int((~keep).sum())} duplicated row(s) dropped (duplicates='{duplicates}')")
    raw = pd.DataFrame(data, index=pd.DatetimeIndex(times[rows], name="time"))
    meta = {
        "layout": "wide",
        "sensors": list(data),
        "units": meta_units,
        "units_in_file": meta_file_units,
        "quantities": meta_quantities,
        "conversions": conversions,
        "n_reports": n_reports,
    }
    return raw, meta


# ----------------------------------------------------------------------------------------------
# resampling kernels (pure numpy, times in seconds from the grid start)
# ----------------------------------------------------------------------------------------------
def _validity_ends(
    t: np.ndarray, data_end: float, max_gap: float, hold: float
) -> tuple[np.ndarray, np.ndarray]:
    """End of the interval each report holds for, and which silences after a report are gaps.

    A report holds until the next one unless the silence exceeds ``max_gap``; then it holds for
    ``hold`` only. The last report holds until the end of the data on the same terms.
    """
    following = np.append(t[1:], max(data_end, t[-1]))
    silence = following - t
    gap = silence > max_gap
    ends = np.where(gap, t + np.minimum(hold, silence), following)
    return ends, gap


def _held_integral(
    t: np.ndarray, v: np.ndarray, ends: np.ndarray, edges: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Integral of the held signal and of its coverage from -inf to each edge [value s, s]."""
    durations = ends - t
    cum_value = np.concatenate(([0.0], np.cumsum(v * durations)))
    cum_cover = np.concatenate(([0.0], np.cumsum(durations)))
    k = np.searchsorted(t, edges, side="right") - 1
    kk = np.clip(k, 0, None)
    partial = np.clip(np.minimum(edges, ends[kk]) - t[kk], 0.0, None)
    partial = np.where(k >= 0, partial, 0.0)
    value = cum_value[kk] + np.where(k >= 0, v[kk] * partial, 0.0)
    cover = cum_cover[kk] + partial
    return value, cover


def _linear_integral(
    t: np.ndarray, v: np.ndarray, gap: np.ndarray, edges: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Integral of the linearly interpolated signal (segments across gaps excluded)."""
    n = t.size
    if n < 2:
        zeros = np.zeros(edges.size)
        return zeros, zeros
    dt = np.diff(t)
    valid = ~gap[:-1]
    seg_value = np.where(valid, 0.5 * (v[:-1] + v[1:]) * dt, 0.0)
    seg_cover = np.where(valid, dt, 0.0)
    cum_value = np.concatenate(([0.0], np.cumsum(seg_value)))
    cum_cover = np.concatenate(([0.0], np.cumsum(seg_cover)))
    k = np.searchsorted(t, edges, side="right") - 1  # segment index containing the edge
    inside = (k >= 0) & (k < n - 1)
    kk = np.clip(k, 0, n - 2)
    x = np.where(inside, edges - t[kk], 0.0)
    slope = (v[kk + 1] - v[kk]) / dt[kk]
    partial_value = np.where(inside & valid[kk], x * (v[kk] + 0.5 * slope * x), 0.0)
    partial_cover = np.where(inside & valid[kk], x, 0.0)
    base = np.clip(k, 0, n - 1)
    value = np.where(k >= 0, cum_value[base] + partial_value, 0.0)
    cover = np.where(k >= 0, cum_cover[base] + partial_cover, 0.0)
    return value, cover


def _held_at(
    t: np.ndarray, v: np.ndarray, ends: np.ndarray, points: np.ndarray, *, before: bool
) -> np.ndarray:
    """Value held at ``points`` (``before=True``: just before them), NaN where unknown."""
    if before:
        k = np.searchsorted(t, points, side="left") - 1
        kk = np.clip(k, 0, None)
        ok = (k >= 0) & (points <= ends[kk])
    else:
        k = np.searchsorted(t, points, side="right") - 1
        kk = np.clip(k, 0, None)
        ok = (k >= 0) & (points < ends[kk])
    return np.where(ok, v[kk], np.nan)


def time_weighted_mean(
    times: np.ndarray,
    values: np.ndarray,
    edges: np.ndarray,
    *,
    max_gap: float = math.inf,
    hold: float | None = None,
    data_end: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Time-weighted mean of a held (zero-order-hold) signal over consecutive intervals.

    Parameters
    ----------
    times : array-like [s]
        Report times, strictly increasing.
    values : array-like
        Reported values (finite).
    edges : array-like [s]
        Interval edges, increasing; n + 1 edges give n means.
    max_gap : float [s]
        Longest silence across which a value is held.
    hold : float [s], optional
        How long a value before a gap is still held (default: ``max_gap``, capped by the
        silence).
    data_end : float [s], optional
        End of the observation (default: the last report time).

    Returns
    -------
    mean : ndarray
        Mean over the covered part of each interval (NaN when nothing is covered).
    coverage : ndarray [-]
        Covered fraction of each interval.
    """
    t = np.asarray(times, dtype=np.float64)
    v = np.asarray(values, dtype=np.float64)
    edges = np.asarray(edges, dtype=np.float64)
    end = t[-1] if data_end is None else data_end
    ends, _ = _validity_ends(t, end, max_gap, max_gap if hold is None else hold)
    reference = v[0]
    integral, cover = _held_integral(t, v - reference, ends, edges)
    covered = np.diff(cover)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.diff(integral) / covered + reference
    mean[covered <= 0] = np.nan
    return mean, covered / np.diff(edges)


def _spikes(values: np.ndarray, n_sigma: float, floor: float, max_run: int = 2) -> np.ndarray:
    """Boolean mask of spikes: runs of at most ``max_run`` reports that jump away and back.

    A run ``values[i:i + r]`` (1 <= r <= max_run) is a spike when every value in it lies more
    than the threshold above (or below) both neighbours ``values[i - 1]`` and ``values[i + r]``,
    and the neighbours agree within the threshold (the signal comes back). The threshold is
    ``max(floor, n_sigma * 1.4826 * MAD(first differences))``. A step (no return) and a real
    event reported by several change-triggered reports (small successive differences) are not
    spikes.

    References
    ----------
    .. [1] U.S. IOOS (2020). Manual for Real-Time Quality Control of In-situ Temperature and
       Salinity Data, version 2.1, QARTOD test 9 (spike test).
    """
    n = values.size
    spikes = np.zeros(n, dtype=bool)
    if n < 3:
        return spikes
    steps = np.diff(values)
    mad = float(np.median(np.abs(steps - np.median(steps))))
    threshold = max(floor, n_sigma * 1.4826 * mad)
    for run in range(1, max_run + 1):
        if n < run + 2:
            break
        before = values[: n - run - 1]
        after = values[run + 1 :]
        window = np.lib.stride_tricks.sliding_window_view(values[1 : n - 1], run)
        low_run, high_run = window.min(axis=1), window.max(axis=1)
        returns = np.abs(before - after) <= threshold
        up = low_run - np.maximum(before, after) > threshold
        down = np.minimum(before, after) - high_run > threshold
        for first in np.flatnonzero(returns & (up | down)):
            spikes[first + 1 : first + 1 + run] = True
    return spikes


# ----------------------------------------------------------------------------------------------
# quality report
# ----------------------------------------------------------------------------------------------
@dataclass
class QualityReport:
    """What :func:`resample_measurements` did and found.

    Attributes
    ----------
    step : Timedelta
        Grid step.
    start, end : Timestamp
        First interval start and last interval end of the grid.
    sensors : DataFrame
        One row per sensor: quantity, unit, operation, n_reports, median_interval [s],
        max_interval [s], n_gaps, gap_hours [h], n_impossible, n_outliers, n_outliers_removed,
        coverage [-] (mean covered fraction of the intervals), n_missing (NaN intervals).
    gaps : DataFrame
        One row per silence longer than ``max_gap``: sensor, start (last report before), end
        (first report after, or the end of the data), duration [h], n_missing (NaN intervals).
    flags : DataFrame
        One row per flagged report: sensor, time, value, line (1-based line in the file, long
        logs from :func:`read_measurements`; else None), flag ("impossible" or "outlier"),
        action ("removed" or "kept"), reason.
    coverage : DataFrame
        Covered fraction of every interval [-] (grid x sensors).
    actions : list of str
        Plain-language account of everything done (conversions, removals, gaps left NaN).
    """

    step: pd.Timedelta
    start: pd.Timestamp
    end: pd.Timestamp
    sensors: pd.DataFrame
    gaps: pd.DataFrame
    flags: pd.DataFrame
    coverage: pd.DataFrame
    actions: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """True when there were no gaps, impossible values or outliers."""
        return self.gaps.empty and self.flags.empty

    def summary(self) -> str:
        """Plain-text summary (one line per sensor, then the actions)."""
        head = (
            f"Measurement quality: {len(self.sensors)} sensor(s), grid {self.start.isoformat()} "
            f"to {self.end.isoformat()}, step {self.step}"
        )
        columns = [
            "quantity",
            "unit",
            "operation",
            "n_reports",
            "coverage",
            "n_gaps",
            "gap_hours",
            "n_impossible",
            "n_outliers",
            "n_missing",
        ]
        table = self.sensors[columns].to_string(float_format=lambda x: f"{x:.3g}")
        body = "\n".join(f"- {a}" for a in self.actions) if self.actions else "- nothing to report"
        return f"{head}\n{table}\n{body}"

    def __str__(self) -> str:
        return self.summary()

    def to_dict(self) -> dict:
        """JSON-serialisable content (times as ISO 8601 strings)."""

        def records(frame: pd.DataFrame) -> list[dict]:
            out = frame.copy()
            for column in out.columns:
                if isinstance(out[column].dtype, pd.DatetimeTZDtype):
                    out[column] = out[column].map(lambda x: x.isoformat())
            return out.astype(object).where(out.notna(), None).to_dict(orient="records")

        sensors = self.sensors.reset_index()
        return {
            "step_seconds": self.step.total_seconds(),
            "start": self.start.isoformat(),
            "end": self.end.isoformat(),
            "sensors": records(sensors),
            "gaps": records(self.gaps),
            "flags": records(self.flags),
            "actions": list(self.actions),
        }


# ----------------------------------------------------------------------------------------------
# resampling
# ----------------------------------------------------------------------------------------------
def _as_timedelta(value: Any, name: str) -> pd.Timedelta | None:
    if value is None:
        return None
    try:
        delta = pd.Timedelta(value)
    except (ValueError, TypeError):
        raise ThermocalInputError(
            f"{name} = {value!r} is not a duration; use e.g. '5min', '1h' or a Timedelta"
        ) from None
    if pd.isna(delta) or delta <= pd.Timedelta(0):
        raise ThermocalInputError(f"{name} = {value!r} must be a positive duration")
    return delta


def _per_sensor(option: Any, sensors: Sequence[str], name: str, default: Any) -> dict[str, Any]:
    if isinstance(option, Mapping):
        unknown = [key for key in option if key not in sensors]
        if unknown:
            raise ThermocalInputError(
                f"{name}: unknown sensor(s) {unknown}{_suggest(str(unknown[0]), sensors)} "
                f"(sensors: {list(sensors)})"
            )
        return {s: option.get(s, default(s) if callable(default) else default) for s in sensors}
    return dict.fromkeys(sensors, option)


def _split_raw(raw: pd.DataFrame) -> tuple[dict[str, tuple], Any]:
    """Per-sensor (times in ns, values, file line numbers or None) from a long or wide frame."""
    if raw.attrs:
        # pandas deep-copies ``attrs`` into every column taken: drop them once here
        raw = raw.copy(deep=False)
        raw.attrs = {}
    if isinstance(raw.index, pd.DatetimeIndex):
        if raw.index.tz is None:
            raise ThermocalInputError(
                "resample_measurements: the index has no time zone; use tz_localize first"
            )
        times = raw.index.as_unit("ns").asi8
        if np.any(np.diff(times) <= 0):
            raise ThermocalInputError(
                "resample_measurements: the time index must be strictly increasing"
            )
        out = {}
        for column in raw.columns:
            values = pd.to_numeric(raw[column], errors="coerce").to_numpy(
                dtype=np.float64, na_value=np.nan
            )
            ok = np.isfinite(values)
            out[str(column)] = (times[ok], values[ok], None)
        return out, raw.index.tz
    needed = {"time", "sensor", "value"}
    if not needed <= set(raw.columns):
        raise ThermocalInputError(
            "resample_measurements: raw must have a tz-aware DatetimeIndex (wide layout) or "
            f"columns time, sensor, value (long layout); got columns {list(raw.columns)}"
        )
    time = pd.DatetimeIndex(raw["time"])
    if time.tz is None:
        raise ThermocalInputError("resample_measurements: column 'time' has no time zone")
    times = time.as_unit("ns").asi8
    values = raw["value"].to_numpy(dtype=np.float64, na_value=np.nan)
    file_lines = raw.index.to_numpy() if raw.index.name == "line" else None
    if isinstance(raw["sensor"].dtype, pd.CategoricalDtype):
        codes = raw["sensor"].cat.codes.to_numpy()
        names = [str(n) for n in raw["sensor"].cat.categories]
    else:
        codes, names = pd.factorize(raw["sensor"], sort=False)
    if np.any(codes < 0):
        raise ThermocalInputError("resample_measurements: missing sensor names in column 'sensor'")
    code_step = np.diff(codes)
    if np.all(code_step >= 0) and np.all(np.diff(times)[code_step == 0] > 0):
        order = np.arange(codes.size)  # already sorted by sensor, then time (read_measurements)
    else:
        order = np.lexsort((times, codes))
    codes_sorted = codes[order]
    bounds = np.flatnonzero(np.diff(codes_sorted)) + 1
    out = {}
    for chunk in np.split(order, bounds):
        if chunk.size == 0:
            continue
        name = str(names[codes[chunk[0]]])
        t, v = times[chunk], values[chunk]
        if np.any(np.diff(t) <= 0):
            raise ThermocalInputError(
                f"resample_measurements: sensor '{name}' has repeated timestamps"
            )
        ok = np.isfinite(v)
        out[name] = (t[ok], v[ok], file_lines[chunk][ok] if file_lines is not None else None)
    return out, time.tz


def _grid(
    start_ns: int, end_ns: int, step: pd.Timedelta, tz: Any, start: Any, end: Any
) -> pd.DatetimeIndex:
    def stamp(value, ns):
        if value is not None:
            ts = pd.Timestamp(value)
            return ts.tz_localize(tz) if ts.tzinfo is None else ts.tz_convert(tz)
        return pd.Timestamp(ns, tz="UTC").tz_convert(tz)

    first = stamp(start, start_ns)
    last = stamp(end, end_ns)
    if start is None:
        try:
            first = first.floor(step, ambiguous=False, nonexistent="shift_backward")
        except (ValueError, TypeError):
            first = first.tz_convert("UTC").floor(step).tz_convert(tz)
    if last <= first:
        last = first + step
    n = int(math.ceil((last - first) / step))
    return pd.date_range(first, periods=n, freq=step, name="time")


def resample_measurements(
    raw: pd.DataFrame,
    step: Any,
    *,
    how: str | Mapping[str, str] | None = None,
    max_gap: Any = "1h",
    min_coverage: float = 0.5,
    start: Any = None,
    end: Any = None,
    quantities: Mapping[str, str] | None = None,
    limits: Mapping[str, tuple[float, float]] | None = None,
    outliers: Literal["flag", "remove", "ignore"] = "flag",
    outlier_sigma: float = 5.0,
    outlier_max_run: int = 2,
    interval: Any = None,
) -> tuple[pd.DataFrame, QualityReport]:
    """Resample irregular sensor reports to a regular grid, with a quality report.

    Parameters
    ----------
    raw : DataFrame
        From :func:`read_measurements` (long or wide), or any frame of the same shape: wide
        with a tz-aware DatetimeIndex and one column per sensor (NaN = no report), or long with
        columns time, sensor, value.
    step : str or Timedelta
        Grid step, e.g. "5min", "1h". Intervals are labelled by their start, ``[t, t + step)``.
    how : str or mapping, optional
        Operation for all sensors or per sensor: one of :data:`OPERATIONS` (see the module
        docstring). Default "mean" (time-weighted mean of the held signal), "last" for energy
        meter readings.
    max_gap : str, Timedelta, None or mapping
        Longest silence across which a value is held [duration], per sensor if a mapping;
        None: hold until the next report however long (sensors that report only on change,
        without heartbeat). Default "1h".
    min_coverage : float [-]
        Intervals covered less than this fraction are NaN (mean, mean_linear, min, max, sum).
    start, end : str or Timestamp, optional
        Grid limits (default: from the first report, floored to the step, to the last report).
    quantities : mapping, optional
        Quantity per sensor, overriding ``raw.attrs["measurements"]["quantities"]`` (used for
        the physical limits and the spike screening).
    limits : mapping, optional
        Physically possible (low, high) per sensor in its unit, overriding
        :data:`PHYSICAL_LIMITS` of its quantity.
    outliers : {"flag", "remove", "ignore"}
        Spikes (up to ``outlier_max_run`` consecutive reports that jump away from both
        neighbours by more than ``outlier_sigma`` robust standard deviations of the successive
        differences, and at least the quantity's floor in :data:`OUTLIER_FLOORS`, and come
        back): list them, list and remove them, or skip the screening.
    outlier_sigma : float [-]
        Threshold in robust standard deviations of the successive differences (1.4826 MAD).
    outlier_max_run : int
        Longest run of consecutive reports still called a spike [reports]; a longer excursion
        is an event (a window opened, the heating started) and is not flagged.
    interval : str or Timedelta, optional
        The rows are means over ``[t, t + interval)`` labelled by their start (a logger's
        interval means) [duration]: each row is held until the next one but for at most
        ``interval``, and the last row until ``t_last + interval`` (the grid extends to it).
        Silences longer than ``max_gap`` are still listed as gaps (pass ``max_gap=interval``
        to list every missing row). Default: ``raw.attrs["measurements"]["interval"]``, set by
        :func:`read_measurements` with ``rows="interval_start"`` or ``"interval_end"``; None
        there: the rows are reports (held until the next report, see ``max_gap``).

    Returns
    -------
    data : DataFrame
        Regular grid (tz-aware DatetimeIndex labelled by interval start), one column per sensor
        in its canonical unit; NaN where unknown. ``data.attrs["units"]`` holds the units.
    report : QualityReport
        Gaps, flags, coverage and the actions taken.

    Raises
    ------
    ThermocalInputError
        Bad step, operation, sensor names in ``how``/``max_gap``/``limits``, or a frame that
        is not a measurement log.
    """
    step_td = _as_timedelta(step, "step")
    if not 0.0 <= min_coverage <= 1.0:
        raise ThermocalInputError(f"min_coverage = {min_coverage} must be between 0 and 1")
    if outliers not in ("flag", "remove", "ignore"):
        raise ThermocalInputError(f"outliers = {outliers!r}; use 'flag', 'remove' or 'ignore'")
    series, tz = _split_raw(raw)
    if not series:
        raise ThermocalInputError("resample_measurements: no sensors in the data")
    meta = raw.attrs.get("measurements", {}) if isinstance(raw.attrs, dict) else {}
    interval_td = _as_timedelta(meta.get("interval") if interval is None else interval, "interval")
    sensors = list(series)
    quantity_of = dict(meta.get("quantities", {}))
    for name in sensors:
        quantity_of.setdefault(name, _guess_quantity(name))
    if quantities:
        for name, quantity in _per_sensor(quantities, sensors, "quantities", None).items():
            if quantity is not None:
                if quantity not in CANONICAL_UNITS:
                    raise ThermocalInputError(
                        f"quantities: unknown quantity '{quantity}' for '{name}' "
                        f"(known: {', '.join(CANONICAL_UNITS)})"
                    )
                quantity_of[name] = quantity
    unit_of = {
        s: meta.get("units", {}).get(s) or CANONICAL_UNITS.get(quantity_of[s] or "", "")
        for s in sensors
    }
    if how is None or isinstance(how, str):
        operations = {
            s: how or _DEFAULT_OPERATION.get(quantity_of[s] or "", "mean") for s in sensors
        }
    else:
        operations = _per_sensor(
            how, sensors, "how", lambda s: _DEFAULT_OPERATION.get(quantity_of[s] or "", "mean")
        )
    for name, operation in operations.items():
        if operation not in OPERATIONS:
            raise ThermocalInputError(
                f"how: operation '{operation}' for '{name}' is not one of {', '.join(OPERATIONS)}"
                f"{_suggest(str(operation), OPERATIONS)}"
            )
    gaps_of = {
        name: _as_timedelta(value, f"max_gap['{name}']")
        for name, value in _per_sensor(max_gap, sensors, "max_gap", "1h").items()
    }
    limit_of = _per_sensor(limits or {}, sensors, "limits", None)

    nonempty = [series[s][0] for s in sensors if series[s][0].size]
    if not nonempty:
        raise ThermocalInputError("resample_measurements: no finite values in the data")
    first_ns = min(int(t[0]) for t in nonempty)
    last_ns = max(int(t[-1]) for t in nonempty)
    if interval_td is not None:
        last_ns += interval_td.value  # the last row describes [t_last, t_last + interval)
    grid = _grid(first_ns, last_ns, step_td, tz, start, end)
    origin_ns = grid[0].value
    step_s = step_td.total_seconds()
    edges = np.arange(len(grid) + 1, dtype=np.float64) * step_s
    data_end = (last_ns - origin_ns) / 1e9
    if end is not None:
        data_end = min(data_end, edges[-1])

    columns: dict[str, np.ndarray] = {}
    coverage_columns: dict[str, np.ndarray] = {}
    sensor_rows: list[dict] = []
    gap_rows: list[dict] = []
    flag_rows: list[dict] = []
    actions: list[str] = []
    for note in meta.get("notes", []):
        actions.append(f"reading: {note}")
    for name, note in meta.get("conversions", {}).items():
        actions.append(f"{name}: converted {note}")
    if interval_td is not None:
        actions.append(
            f"rows are interval means: each held until the next row or for at most "
            f"{interval_td}, the last until {pd.Timestamp(last_ns, tz='UTC').tz_convert(tz)}"
        )

    for name in sensors:
        times_ns, values, lines_of = series[name]
        quantity = quantity_of[name]
        operation = operations[name]
        unit = unit_of[name]
        # physically impossible values
        if limit_of[name] is not None:
            low, high = limit_of[name]
            reason = "outside the limits given"
        elif quantity in PHYSICAL_LIMITS:
            low, high, reason = PHYSICAL_LIMITS[quantity]
        else:
            low, high, reason = -math.inf, math.inf, ""
        impossible = (values < low) | (values > high)
        n_impossible = int(impossible.sum())
        if n_impossible:
            for index in np.flatnonzero(impossible)[:1000]:
                flag_rows.append(
                    {
                        "sensor": name,
                        "time": pd.Timestamp(int(times_ns[index]), tz="UTC").tz_convert(tz),
                        "value": float(values[index]),
                        "line": None if lines_of is None else int(lines_of[index]),
                        "flag": "impossible",
                        "action": "removed",
                        "reason": f"{reason} {low:g} to {high:g} {unit}".strip(),
                    }
                )
            first_time = pd.Timestamp(int(times_ns[np.flatnonzero(impossible)[0]]), tz="UTC")
            actions.append(
                f"{name}: removed {n_impossible} physically impossible value(s) outside "
                f"{low:g} to {high:g} {unit} (first at {first_time.tz_convert(tz).isoformat()})"
            )
            times_ns, values = times_ns[~impossible], values[~impossible]
            lines_of = None if lines_of is None else lines_of[~impossible]
        # isolated spikes
        n_outliers = n_removed = 0
        if outliers != "ignore" and quantity in OUTLIER_FLOORS and values.size:
            spikes = _spikes(values, outlier_sigma, OUTLIER_FLOORS[quantity], outlier_max_run)
            n_outliers = int(spikes.sum())
            if n_outliers:
                action = "removed" if outliers == "remove" else "kept"
                for index in np.flatnonzero(spikes)[:1000]:
                    flag_rows.append(
                        {
                            "sensor": name,
                            "time": pd.Timestamp(int(times_ns[index]), tz="UTC").tz_convert(tz),
                            "value": float(values[index]),
                            "line": None if lines_of is None else int(lines_of[index]),
                            "flag": "outlier",
                            "action": action,
                            "reason": (
                                f"spike: jumps more than max({OUTLIER_FLOORS[quantity]:g} {unit}, "
                                f"{outlier_sigma:g} robust standard deviations of the successive "
                                f"differences) away from both neighbours and back within "
                                f"{outlier_max_run} report(s)"
                            ),
                        }
                    )
                actions.append(f"{name}: {n_outliers} isolated spike(s) {action}")
                if outliers == "remove":
                    n_removed = n_outliers
                    times_ns, values = times_ns[~spikes], values[~spikes]
                    lines_of = None if lines_of is None else lines_of[~spikes]

        n = len(grid)
        max_gap_s = math.inf if gaps_of[name] is None else gaps_of[name].total_seconds()
        if values.size == 0:
            result = np.zeros(n) if operation == "count" else np.full(n, np.nan)
            columns[name] = result
            coverage_columns[name] = np.zeros(n)
            sensor_rows.append(
                _sensor_row(
                    name,
                    quantity,
                    unit,
                    operation,
                    0,
                    np.nan,
                    np.nan,
                    1,
                    np.nan,
                    n_impossible,
                    n_outliers,
                    n_removed,
                    0.0,
                    n,
                )
            )
            actions.append(f"{name}: no usable report; all intervals NaN")
            continue
        t = (times_ns - origin_ns) / 1e9
        intervals = np.diff(t)
        typical = float(np.median(intervals)) if intervals.size else step_s
        hold = min(max_gap_s, typical if intervals.size else max_gap_s)
        if not math.isfinite(hold):
            hold = step_s
        ends, gap = _validity_ends(t, data_end, max_gap_s, hold)
        if interval_td is not None:
            ends = np.minimum(ends, t + interval_td.total_seconds())
        reference = float(values[0])
        integral, cover = _held_integral(t, values - reference, ends, edges)
        covered = np.diff(cover)
        coverage = covered / step_s
        enough = coverage >= min_coverage - 1e-12
        enough &= covered > 0
        if operation == "mean":
            with np.errstate(invalid="ignore", divide="ignore"):
                result = np.diff(integral) / covered + reference
            result[~enough] = np.nan
        elif operation == "mean_linear":
            integral_lin, cover_lin = _linear_integral(t, values - reference, gap, edges)
            covered_lin = np.diff(cover_lin)
            coverage = covered_lin / step_s
            enough = (coverage >= min_coverage - 1e-12) & (covered_lin > 0)
            with np.errstate(invalid="ignore", divide="ignore"):
                result = np.diff(integral_lin) / covered_lin + reference
            result[~enough] = np.nan
        elif operation == "last":
            result = _held_at(t, values, ends, edges[1:], before=True)
        elif operation == "first":
            result = _held_at(t, values, ends, edges[:-1], before=False)
        elif operation in ("min", "max", "sum", "count"):
            bins = np.searchsorted(edges, t, side="right") - 1
            inside = (bins >= 0) & (bins < n)
            b, vals = bins[inside], values[inside]
            if operation == "count":
                result = np.bincount(b, minlength=n).astype(np.float64)
            elif operation == "sum":
                result = np.bincount(b, weights=vals, minlength=n)
                result[~enough] = np.nan
            else:
                at_start = _held_at(t, values, ends, edges[:-1], before=False)
                fill = math.inf if operation == "min" else -math.inf
                extreme = np.where(np.isfinite(at_start), at_start, fill)
                (np.minimum if operation == "min" else np.maximum).at(extreme, b, vals)
                extreme[~np.isfinite(extreme)] = np.nan
                extreme[~enough] = np.nan
                result = extreme
        columns[name] = result
        coverage_columns[name] = coverage
        n_missing = int(np.isnan(result).sum())
        # gaps: silences after a report longer than max_gap, and before the first report
        gap_index = np.flatnonzero(gap)
        sensor_gaps = []
        lead = t[0] - max(edges[0], (first_ns - origin_ns) / 1e9)
        if lead > max_gap_s:
            sensor_gaps.append(((first_ns - origin_ns) / 1e9, t[0]))
        for index in gap_index:
            following = t[index + 1] if index + 1 < t.size else data_end
            sensor_gaps.append((t[index], following))
        gap_hours = 0.0
        for begin_s, end_s in sensor_gaps:
            lo = int(np.searchsorted(edges, begin_s, side="right") - 1)
            hi = int(np.searchsorted(edges, end_s, side="left"))
            missing_bins = int(np.isnan(result[max(lo, 0) : min(hi, n)]).sum())
            duration_h = (end_s - begin_s) / 3600.0
            gap_hours += duration_h
            gap_rows.append(
                {
                    "sensor": name,
                    "start": grid[0] + pd.Timedelta(seconds=begin_s),
                    "end": grid[0] + pd.Timedelta(seconds=end_s),
                    "duration_hours": duration_h,
                    "n_missing": missing_bins,
                }
            )
        if sensor_gaps:
            longest = max(e - b for b, e in sensor_gaps) / 3600.0
            actions.append(
                f"{name}: {len(sensor_gaps)} gap(s) longer than max_gap "
                f"{gaps_of[name]} (longest {longest:.2f} h, {gap_hours:.2f} h in total) left "
                f"NaN, not interpolated"
            )
        sensor_rows.append(
            _sensor_row(
                name,
                quantity,
                unit,
                operation,
                values.size,
                float(np.median(intervals)) if intervals.size else np.nan,
                float(intervals.max()) if intervals.size else np.nan,
                len(sensor_gaps),
                gap_hours,
                n_impossible,
                n_outliers,
                n_removed,
                float(np.mean(np.clip(coverage, 0.0, 1.0))),
                n_missing,
            )
        )

    data = pd.DataFrame(columns, index=grid)
    data.attrs["units"] = dict(unit_of)
    flags = pd.DataFrame(
        flag_rows, columns=["sensor", "time", "value", "line", "flag", "action", "reason"]
    )
    gaps = pd.DataFrame(gap_rows, columns=["sensor", "start", "end", "duration_hours", "n_missing"])
    report = QualityReport(
        step=step_td,
        start=grid[0],
        end=grid[-1] + step_td,
        sensors=pd.DataFrame(sensor_rows).set_index("sensor"),
        gaps=gaps,
        flags=flags,
        coverage=pd.DataFrame(coverage_columns, index=grid),
        actions=actions,
    )
    return data, report


def _sensor_row(
    name,
    quantity,
    unit,
    operation,
    n_reports,
    median_interval,
    max_interval,
    n_gaps,
    gap_hours,
    n_impossible,
    n_outliers,
    n_removed,
    coverage,
    n_missing,
) -> dict:
    return {
        "sensor": name,
        "quantity": quantity or "",
        "unit": unit or "",
        "operation": operation,
        "n_reports": int(n_reports),
        "median_interval": median_interval,
        "max_interval": max_interval,
        "n_gaps": int(n_gaps),
        "gap_hours": gap_hours,
        "n_impossible": int(n_impossible),
        "n_outliers": int(n_outliers),
        "n_outliers_removed": int(n_removed),
        "coverage": coverage,
        "n_missing": int(n_missing),
    }


# ----------------------------------------------------------------------------------------------
# the clock against the sun
# ----------------------------------------------------------------------------------------------
#: A clock this far off the sun is refused [h]; one hour is left alone (interval means labelled
#: by their start or end, or a daylight-saving hour, shift the profile by up to an hour).
MAX_SUN_SHIFT_H = 2.0


def check_clock_against_sun(
    irradiance: pd.Series,
    latitude: float,
    longitude: float,
    *,
    source: str,
    column: str,
    timezone_setting: str = "the time zone",
) -> float:
    """Refuse time stamps whose measured irradiance does not follow the sun.

    The mean daily profile of the measured irradiance is compared with that of the sine of the
    sun's elevation at the site (both by time of day in UTC); the circular shift that makes
    them agree best is the error of the clock. A wrong time zone (Europe/Zurich for North
    Carolina data: 6 h) moves the sun and every solar gain by hours without any other sign.

    Parameters
    ----------
    irradiance : pandas.Series
        Irradiance [W/m2] (e.g. DNI + DHI) on a regular, tz-aware index of at most one hour,
        interval means labelled by their start.
    latitude, longitude : float
        The site [deg N, deg E].
    source, column : str
        For the message.
    timezone_setting : str
        The setting that fixes the clock (e.g. ``"measurements.timezone (now -5)"``).

    Returns
    -------
    float
        The clock's offset from the sun [h] (positive: the stamps are late); 0 when the data
        have too little sun to tell.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        The offset is :data:`MAX_SUN_SHIFT_H` or more, naming the two times of the daily
        maximum and the offset.
    """
    from thermocal.physics.solar import solar_position

    values = irradiance.astype(float)
    values = values[np.isfinite(values.to_numpy())]
    if len(values) < 48 or values.index.tz is None:
        return 0.0
    values.index = pd.DatetimeIndex(values.index).as_unit("ns")
    step = pd.Timedelta(np.median(np.diff(values.index.asi8)), unit="ns")
    if not pd.Timedelta("1min") <= step <= pd.Timedelta("1h"):
        return 0.0
    mid = values.index + step / 2
    elevation = solar_position(mid, latitude, longitude)["elevation"].to_numpy()
    sun = np.clip(np.sin(np.radians(elevation)), 0.0, None)
    bins = int(round(pd.Timedelta("1D") / step))
    utc_seconds = (mid.asi8 // 10**9) % 86400
    which = (utc_seconds // int(step.total_seconds())).astype(int) % bins
    counts = np.bincount(which, minlength=bins)
    seen = counts > 0
    measured = np.bincount(which, weights=values.to_numpy(), minlength=bins)
    expected = np.bincount(which, weights=sun, minlength=bins)
    if seen.sum() < 0.9 * bins or measured.max() <= 0:
        return 0.0
    measured = np.where(seen, measured / np.maximum(counts, 1), 0.0)
    expected = np.where(seen, expected / np.maximum(counts, 1), 0.0)
    if measured.max() < 20.0:  # too little sun in the data to tell
        return 0.0

    def score(shift: int) -> float:
        a, b = measured, np.roll(expected, shift)
        a, b = a - a.mean(), b - b.mean()
        return float(a @ b / np.sqrt((a @ a) * (b @ b) + 1e-300))

    scores = np.array([score(k) for k in range(bins)])
    best = int(np.argmax(scores))
    if best > bins // 2:
        best -= bins
    hours = best * step / pd.Timedelta("1h")
    if abs(hours) >= MAX_SUN_SHIFT_H and scores[best % bins] - scores[0] > 0.05:
        tz = values.index.tz
        day = values.index[0].normalize()

        def clock(position: int) -> str:
            return (
                pd.Timestamp(day.tz_convert("UTC").normalize() + position * step + step / 2)
                .tz_convert(tz)
                .strftime("%H:%M")
            )

        peak = clock(int(np.argmax(measured)))
        raise ThermocalInputError(
            f"{source}: the irradiance ({column}) is highest around {peak} by the file's "
            f"clock, but at latitude {latitude:.2f}, longitude {longitude:.2f} the "
            f"sun is highest around {clock(int(np.argmax(expected)))}: the time stamps are "
            f"{abs(hours):.0f} h {'late' if hours > 0 else 'early'} (in UTC), which would move "
            f"every solar gain. Check {timezone_setting} and the UTC offsets of the time "
            "stamps (and the building's location)"
        )
    return hours
