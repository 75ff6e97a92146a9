"""Time columns of data files -> tz-aware DatetimeIndex (private helper of :mod:`thermocal.io`).

One parser for every table reader (weather CSV, measurement logs): ISO 8601 text with or without
UTC offsets (pyarrow fast path), an explicit strftime format, numbers with a unit and an origin,
or an already parsed datetime column (parquet). Naive times are placed in ``tz``; aware ones are
converted to it. Every failure names the file, the column and the line.

References
----------
.. [1] ISO 8601-1:2019, Date and time representations (timestamps with UTC offsets).
"""

from __future__ import annotations

import datetime as _dt
import math
import re
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

#: Units of numeric time columns -> pandas unit.
TIME_UNITS = {"s": "s", "min": "min", "h": "h", "d": "D", "ms": "ms"}
_OFFSET = re.compile(r"(Z|[+-]\d\d(:?\d\d)?)$")


def as_timezone(tz: Any, source: str):
    """A tzinfo from a name (``"Europe/Zurich"``), a tzinfo, or hours east of UTC (``1.0``).

    Parameters
    ----------
    tz : str, datetime.tzinfo, int or float
        Time zone; numbers are fixed offsets [h east of UTC].
    source : str
        What is being read (for the error message), e.g. ``"weather file w.csv"``.

    Returns
    -------
    datetime.tzinfo
    """
    if isinstance(tz, (int, float)) and not isinstance(tz, bool):
        hours = float(tz)
        if math.isnan(hours) or not -14.0 <= hours <= 14.0:
            raise ThermocalInputError(
                f"{source}: tz={tz!r} hours is not a valid UTC offset (-14..14)"
            )
        return _dt.timezone(_dt.timedelta(hours=hours))
    try:
        return pd.Timestamp("2000-01-01").tz_localize(tz).tz
    except Exception as exc:
        raise ThermocalInputError(
            f"{source}: unknown time zone {tz!r} (use an IANA name such as 'Europe/Zurich' or "
            "'Etc/GMT-1', or hours east of UTC such as 1.0)"
        ) from exc


def _where(lines: np.ndarray | None, i: int) -> str:
    return f"line {int(lines[i])}" if lines is not None else f"row {i + 1}"


def parse_time_column(
    values: pd.Series,
    *,
    source: str,
    column: str,
    lines: np.ndarray | None = None,
    tz: Any = None,
    time_format: str | None = None,
    time_unit: str | None = None,
    start: Any = None,
) -> tuple[pd.DatetimeIndex, str]:
    """Parse a time column into a tz-aware DatetimeIndex (ns resolution).

    Parameters
    ----------
    values : pandas.Series
        The column: text, numbers (with ``time_unit``) or datetimes (naive or aware).
    source : str
        The file, as it should appear in messages (``"weather file w.csv"``).
    column : str
        The column name, for messages.
    lines : numpy.ndarray, optional
        1-based line number in the file of every row; messages say "row k" (1-based) without.
    tz : str, tzinfo or float, optional
        Time zone of naive times (required for them) and of the result [name or h east of
        UTC]; aware times are converted to it. None keeps the file's offset (UTC when the
        offsets differ between rows, e.g. across a daylight-saving change).
    time_format : str, optional
        strftime format of non-ISO text, e.g. ``"%d.%m.%Y %H:%M"``.
    time_unit : {"s", "min", "h", "d", "ms"}, optional
        Unit of numeric times; ``start`` is the time of 0.
    start : str or Timestamp, optional
        Origin of numeric times (default 1970-01-01 UTC).

    Returns
    -------
    times : pandas.DatetimeIndex
        Tz-aware, one entry per row.
    note : str
        What was assumed ("" when nothing), for the reader's notes.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Unreadable or missing times, naive times without ``tz``, local times that do not exist
        or are ambiguous in ``tz``; the message names the file, column and line.
    """
    zone = None if tz is None else as_timezone(tz, source)
    if isinstance(values.dtype, pd.DatetimeTZDtype) or pd.api.types.is_datetime64_dtype(
        values.dtype
    ):
        return _finish(pd.DatetimeIndex(values), values, source, column, lines, tz, zone)
    if pd.api.types.is_numeric_dtype(values.dtype) and not pd.api.types.is_bool_dtype(values.dtype):
        return _numeric_times(values, source, column, lines, zone, time_unit, start)
    text = values.astype("string").str.strip()
    sample = text.dropna()
    offset_match = _OFFSET.search(str(sample.iloc[0])) if len(sample) else None
    parsed = None if time_format else _parse_arrow(text, offset_match)
    if parsed is None:
        parsed = _parse_pandas(text, time_format, offset_match is not None)
    bad = parsed.isna().to_numpy()
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        hint = (
            f"the format {time_format!r}"
            if time_format
            else "ISO 8601, e.g. 2019-02-02T13:05:00+01:00, or pass time_format= "
            "(e.g. '%d.%m.%Y %H:%M')"
        )
        raise ThermocalInputError(
            f"{source}, column '{column}', {_where(lines, first)}: cannot read "
            f"{values.iloc[first]!r} as a time; use {hint} ({int(bad.sum())} unreadable "
            "time(s) in this column)"
        )
    return _finish(pd.DatetimeIndex(parsed), values, source, column, lines, tz, zone)


def _numeric_times(values, source, column, lines, zone, time_unit, start):
    if time_unit is None:
        raise ThermocalInputError(
            f"{source}, column '{column}': the times are numbers; pass time_unit= "
            f"({', '.join(TIME_UNITS)}) and start= (the time of 0, e.g. "
            f"'2009-02-05 14:26:00+01:00'; default 1970-01-01 UTC)"
        )
    if time_unit not in TIME_UNITS:
        raise ThermocalInputError(
            f"time_unit = {time_unit!r} is not one of {', '.join(TIME_UNITS)}"
        )
    numbers = values.to_numpy(dtype=np.float64, na_value=np.nan)
    bad = ~np.isfinite(numbers)
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        raise ThermocalInputError(
            f"{source}, column '{column}', {_where(lines, first)}: missing or invalid time"
        )
    origin = pd.Timestamp(start if start is not None else "1970-01-01T00:00:00Z")
    if origin.tzinfo is None:
        if zone is None:
            raise ThermocalInputError(
                f"{source}: start={start!r} has no UTC offset; give one "
                f"('2009-02-05 14:26:00+01:00') or pass tz="
            )
        origin = origin.tz_localize(zone)
    elif zone is not None:
        origin = origin.tz_convert(zone)
    offsets = pd.to_timedelta(numbers, unit=TIME_UNITS[time_unit])
    times = pd.DatetimeIndex(origin + offsets).as_unit("ns")
    return times, f"numeric times in {time_unit} from {origin.isoformat()}"


def _parse_arrow(text: pd.Series, offset_match: re.Match | None) -> pd.Series | None:
    """ISO 8601 strings -> times with pyarrow (fast path); None when pyarrow cannot parse all.

    With offsets the result is in UTC, or in the fixed offset of the first timestamp when every
    timestamp carries the same offset text.
    """
    import pyarrow as pa
    import pyarrow.compute as pc

    try:
        array = pa.array(text, type=pa.string(), from_pandas=True)
        if offset_match is None:
            parsed = pc.cast(array, pa.timestamp("ns"))
        else:
            parsed = pc.cast(array, pa.timestamp("ns", tz="UTC"))
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError, pa.ArrowTypeError, ValueError):
        return None
    if parsed.null_count != array.null_count:
        return None
    result = pd.Series(parsed.to_numpy(zero_copy_only=False), index=text.index)
    if offset_match is None:
        return result
    result = result.dt.tz_localize("UTC")
    suffix = offset_match.group(0)
    if suffix != "Z" and pc.all(pc.ends_with(array, suffix)).as_py():
        result = result.dt.tz_convert(pd.Timestamp(str(text.dropna().iloc[0])).tzinfo)
    return result


def _parse_pandas(text: pd.Series, time_format: str | None, has_offset: bool) -> pd.Series:
    fmt = time_format or "ISO8601"
    try:
        parsed = pd.to_datetime(text, format=fmt, errors="coerce")
    except (ValueError, TypeError):  # mixed offsets (e.g. +01:00 and +02:00 across DST)
        return pd.to_datetime(text, format=fmt, errors="coerce", utc=True)
    if has_offset and not isinstance(parsed.dtype, pd.DatetimeTZDtype):
        parsed = pd.to_datetime(text, format=fmt, errors="coerce", utc=True)
    return parsed


def _finish(times, values, source, column, lines, tz, zone) -> tuple[pd.DatetimeIndex, str]:
    """Missing times are errors; naive times are placed in ``zone``, aware ones converted."""
    missing = np.asarray(times.isna())
    if missing.any():
        first = int(np.flatnonzero(missing)[0])
        raise ThermocalInputError(
            f"{source}, column '{column}', {_where(lines, first)}: missing time"
        )
    if times.tz is not None:
        if zone is not None:
            times = times.tz_convert(zone)
        return times.as_unit("ns"), ""
    if zone is None:
        raise ThermocalInputError(
            f"{source}, column '{column}': the time stamps have no time zone and no UTC offset; "
            "pass tz= (e.g. 'Europe/Zurich', 'UTC' or hours east of UTC such as 1.0) or write "
            "them with an offset (2019-02-02T13:05:00+01:00)"
        )
    localized = times.tz_localize(zone, ambiguous="NaT", nonexistent="NaT")
    failed = np.asarray(localized.isna())
    if failed.any():
        first = int(np.flatnonzero(failed)[0])
        raise ThermocalInputError(
            f"{source}, column '{column}', {_where(lines, first)}: the local time "
            f"{values.iloc[first]!r} does not exist or is ambiguous in time zone {tz!r} "
            f"(clock change; {int(failed.sum())} such time(s)); write the time stamps with UTC "
            "offsets or in standard time and pass a fixed offset, e.g. tz=1.0"
        )
    return localized.as_unit("ns"), f"time stamps without offset interpreted in {tz}"
