"""Time columns of data files -> tz-aware DatetimeIndex (private helper of :mod:`thermocal.io`).

One parser for every table reader (weather CSV, measurement logs): ISO 8601 text with or without
UTC offsets (pyarrow fast path), an explicit strftime format, numbers with a unit and an origin,
or an already parsed datetime column (parquet). Numeric dates written day and month first
(``01/02/2015 00:00``, ``01.02.2015``) are read in the order the file's times decide, or
refused. Naive times are placed in ``tz``; aware ones are converted to it. Every failure names
the file, the column and the line.

References
----------
.. [1] ISO 8601-1:2019, Date and time representations (timestamps with UTC offsets).
"""

from __future__ import annotations

import datetime as _dt
import logging
import math
import re
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

log = logging.getLogger(__name__)

#: Units of numeric time columns -> pandas unit.
TIME_UNITS = {"s": "s", "min": "min", "h": "h", "d": "D", "ms": "ms"}
_OFFSET = re.compile(r"(Z|[+-]\d\d(:?\d\d)?)$")
#: A time zone written as hours east of UTC: ``1``, ``+1``, ``-7``, ``-7.0``, ``5.5``.
_HOURS = re.compile(r"^\s*(?:UTC|GMT)?\s*[+-]?\d{1,2}(\.\d+)?\s*$", re.IGNORECASE)
#: ... or as an ISO 8601 offset: ``+01:00``, ``-0700``, ``UTC+05:30``.
_HHMM = re.compile(r"^\s*(?:UTC|GMT)?\s*([+-])(\d\d):?(\d\d)\s*$", re.IGNORECASE)
#: A date with numeric day and month before the year, either way round, and an optional time,
#: 24-hour or 12-hour with AM/PM (a US spreadsheet's export): ``01/02/2015 00:00``,
#: ``1.2.2015``, ``01-02-2015 00:00:00``, ``01/02/2015 12:05 AM``, ``1/2/2015 1:05:00 pm``.
_DAY_MONTH = re.compile(
    r"(\d{1,2})([/.-])(\d{1,2})\2(\d{4})(?:([ T])\d{1,2}:\d\d(:\d\d)?( ?[AaPp][Mm])?)?"
)
#: How a reader's note starts when the times were numbers (``time_unit``, ``start`` used) ...
NUMERIC_TIMES_NOTE = "numeric times in"
#: ... and when stamps without UTC offset were placed in ``tz``: a caller can tell from
#: ``meta["notes"]`` whether its time options were used.
LOCAL_TIMES_NOTE = "time stamps without offset interpreted in"


def as_timezone(tz: Any, source: str):
    """A tzinfo from a name (``"Europe/Zurich"``), a tzinfo, or hours east of UTC (``1.0``).

    Parameters
    ----------
    tz : str, datetime.tzinfo, int or float
        Time zone: an IANA name, or a fixed offset [h east of UTC] as a number or as text
        (``"1"``, ``"+1"``, ``"-7"``, ``"-7.0"``, ``"+05:30"``, ``"UTC-7"``).
    source : str
        What is being read (for the error message), e.g. ``"weather file w.csv"``.

    Returns
    -------
    datetime.tzinfo
    """
    if isinstance(tz, str) and _HOURS.match(tz):
        tz = float(re.sub(r"(?i)utc|gmt|\s", "", tz))
    elif isinstance(tz, str) and _HHMM.match(tz):
        sign, hh, mm = _HHMM.match(tz).groups()
        tz = (1.0 if sign == "+" else -1.0) * (int(hh) + int(mm) / 60.0)
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
            "'America/Denver', or signed hours east of UTC such as 1, +1, -7 or +05:30)"
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
    order_note = ""
    if time_format is None and bool(parsed.isna().any()):
        parsed, order_note = day_month_order(
            text, parsed, source=source, column=column, lines=lines
        )
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
    result = _finish(pd.DatetimeIndex(parsed), values, source, column, lines, tz, zone)
    if offset_match is not None:
        check_clock_offsets(text, result[0], source=source, column=column, lines=lines)
    else:
        check_fixed_zone_clock(result[0], source=source, column=column, lines=lines)
    if order_note:
        result = (result[0], "; ".join(n for n in (order_note, result[1]) if n))
    return result


def _disorder(times: pd.Series) -> tuple[int, int]:
    """How far times in file order are from a sorted series at a regular step.

    Parameters
    ----------
    times : pandas.Series
        Parsed times (naive datetimes; missing ones are skipped), in the order of the file.

    Returns
    -------
    backward : int
        Steps that go back in time.
    irregular : int
        Forward steps more than 10 % away from the most frequent forward step (steps of zero,
        several reports of one time, count as neither); a log of calendar months (28-31 days)
        is regular.
    """
    stamps = pd.DatetimeIndex(times.dropna()).as_unit("ns").asi8
    steps = np.diff(stamps)
    forward = steps[steps > 0]
    backward = int(np.count_nonzero(steps < 0))
    if forward.size == 0:
        return backward, 0
    values, counts = np.unique(forward, return_counts=True)
    usual = float(values[np.argmax(counts)])
    return backward, int(np.count_nonzero(np.abs(forward - usual) > 0.1 * usual))


def day_month_order(
    text: pd.Series,
    parsed: pd.Series,
    *,
    source: str,
    column: str,
    lines: np.ndarray | None = None,
) -> tuple[pd.Series, str]:
    """Read numeric dates day-first or month-first, as the file's times decide.

    Applies when every stamp is a date with numeric day and month before a four-digit year,
    separated by ``/``, ``.`` or ``-``, and an optional time (``01/02/2015 00:00``,
    ``01.02.2015 00:00:00``). Both orders are parsed strictly (``%d/%m/%Y %H:%M`` and
    ``%m/%d/%Y %H:%M``, with the file's separator and seconds). The order that reads every row
    is kept when the other does not; when both do, the one whose times go back less often
    and, then, have fewer steps off the log's usual step.

    Parameters
    ----------
    text : pandas.Series
        The stamps as written (stripped text; missing values are ``<NA>``).
    parsed : pandas.Series
        The stamps as read so far (ISO 8601; with missing times): returned when the stamps
        are not numeric dates of that form.
    source : str
        The file, as it should appear in messages.
    column : str
        The column name, for messages.
    lines : numpy.ndarray, optional
        1-based file line of every row; messages say "row k" (1-based) without.

    Returns
    -------
    times : pandas.Series
        The stamps read in the order decided (naive); when neither order reads every row, the
        reading with fewer unreadable rows, for the caller's message naming the first.
    note : str
        The order used and why ("" when the stamps are not of this form).

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Both orders read every row and give equally plausible times (e.g. one row, or two
        rows both ways ordered and evenly spaced); the message names the file, the column
        and the first row whose day and month are both at most 12.
    """
    written = text.dropna()
    forms = written.str.fullmatch(_DAY_MONTH.pattern)
    if written.empty or not bool(forms.all()):
        return parsed, ""
    first = _DAY_MONTH.fullmatch(str(written.iloc[0]))
    sep, clock = first.group(2), ""
    if first.group(5):
        twelve = first.group(7)
        clock = (
            first.group(5)
            + ("%I:%M" if twelve else "%H:%M")
            + (":%S" if first.group(6) else "")
            + ("" if not twelve else " %p" if twelve.startswith(" ") else "%p")
        )
    formats = {"day-first": f"%d{sep}%m{sep}%Y{clock}", "month-first": f"%m{sep}%d{sep}%Y{clock}"}
    clocks = _clock_formats(text)
    readings = {
        order: _read_dates(text, clocks, f"%d{sep}%m{sep}%Y" if order == "day-first"
                           else f"%m{sep}%d{sep}%Y")
        for order in formats
    }  # fmt: skip
    failed = {order: int((times.isna() & text.notna()).sum()) for order, times in readings.items()}
    day_first, month_first = readings["day-first"], readings["month-first"]
    if failed["day-first"] and failed["month-first"]:
        return readings[min(failed, key=failed.get)], ""
    if failed["day-first"] or failed["month-first"]:
        order = "month-first" if failed["day-first"] else "day-first"
        other = "day-first" if order == "month-first" else "month-first"
        row = int(np.flatnonzero((readings[other].isna() & text.notna()).to_numpy())[0])
        why = f"{_where(lines, row)} ({text.iloc[row]!r}) cannot be {other}"
    else:
        disorder = {order: _disorder(times) for order, times in readings.items()}
        if disorder["day-first"] == disorder["month-first"]:
            raise _ambiguous_order(text, day_first, month_first, source, column, lines)
        order = min(disorder, key=disorder.get)
        other = "day-first" if order == "month-first" else "month-first"
        back, off = disorder[other]
        why = (
            f"read {other}, {off} step(s) would be off the log's usual step and {back} would go "
            f"back in time ({order}: {disorder[order][1]} and {disorder[order][0]})"
        )
    note = f"dates read {order} ({formats[order]}): {why}"
    log.info("%s, column '%s': %s", source, column, note)
    return readings[order], note


def day_month_readings(text: str) -> dict[str, _dt.date] | None:
    """The dates a numeric date written with day and month before the year can be.

    One date alone has no neighbours to decide the order by (:func:`day_month_order` decides
    for a column of times): ``25/12/2001`` can only be day-first, ``01/09/2001`` either.

    Parameters
    ----------
    text : str
        A date such as ``01/09/2001``, ``1.9.2001`` or ``01-09-2001`` (a time after it is
        allowed and not read).

    Returns
    -------
    dict or None
        ``{"day-first": date, "month-first": date}`` restricted to the orders that give a
        valid calendar date (empty when neither does); None when ``text`` is not of that form.
    """
    match = _DAY_MONTH.fullmatch(str(text).strip())
    if match is None:
        return None
    first, second, year = int(match.group(1)), int(match.group(3)), int(match.group(4))
    readings = {}
    for order, (day, month) in (("day-first", (first, second)), ("month-first", (second, first))):
        try:
            readings[order] = _dt.date(year, month, day)
        except ValueError:
            continue
    return readings


def _clock_formats(text: pd.Series) -> pd.Series:
    """Per row, the strftime form of its time of day (``" %H:%M"``, ``"T%H:%M:%S"``,
    ``" %I:%M %p"`` with AM/PM, or ``""`` for a date alone: spreadsheets write midnight as the
    date alone)."""
    parts = text.str.extract(_DAY_MONTH.pattern)
    joint, seconds, twelve = parts[4].fillna(""), parts[5].notna(), parts[6].fillna("")
    hours = np.where(twelve != "", "%I:%M", "%H:%M")
    marker = np.where(twelve == "", "", np.where(twelve.str.startswith(" "), " %p", "%p"))
    return joint + np.where(joint != "", hours, "") + np.where(seconds, ":%S", "") + marker


def _read_dates(text: pd.Series, clocks: pd.Series, date_format: str) -> pd.Series:
    """The stamps read with ``date_format`` followed by each row's own clock form (missing
    where it does not fit)."""
    times = pd.Series(pd.NaT, index=text.index, dtype="datetime64[ns]")
    for clock in clocks.dropna().unique():
        rows = (clocks == clock).to_numpy()
        times[rows] = pd.to_datetime(text[rows], format=date_format + clock, errors="coerce")
    return times


def _ambiguous_order(
    text: pd.Series,
    day_first: pd.Series,
    month_first: pd.Series,
    source: str,
    column: str,
    lines: np.ndarray | None,
) -> ThermocalInputError:
    """The error for numeric dates that fit day-first and month-first equally well.

    Parameters
    ----------
    text : pandas.Series
        The stamps as written (all of the form ``01/02/2015 00:00``; missing ones ``<NA>``).
    day_first, month_first : pandas.Series
        The stamps read both ways (naive times).
    source, column : str
        The file and the column, for the message.
    lines : numpy.ndarray, optional
        1-based file line of every row.

    Returns
    -------
    thermocal.errors.ThermocalInputError
        Naming the first row whose day and month are both at most 12, a stamp that the two
        orders read as different dates, and ISO 8601 as the remedy.
    """
    fields = text.str.extract(_DAY_MONTH.pattern)[[0, 2]].astype(float).to_numpy()
    row = int(np.flatnonzero((fields <= 12).all(axis=1))[0])
    differ = np.flatnonzero((day_first.notna() & (day_first != month_first)).to_numpy(dtype=bool))
    example = ""
    if differ.size:
        k = int(differ[0])
        d, m = day_first.iloc[k], month_first.iloc[k]
        at = f" on {_where(lines, k)}" if k != row else ""
        example = (
            f" ({text.iloc[k]!r}{at} is {d.day} {d:%B %Y} day-first, {m.day} {m:%B %Y} month-first)"
        )
    return ThermocalInputError(
        f"{source}, column '{column}', {_where(lines, row)}: cannot read {text.iloc[row]!r} as "
        f"a time: the file does not show whether its dates are day-first or month-first"
        f"{example}; read either way, its times are as well ordered and evenly spaced. Write "
        "the times in ISO 8601, year first (2015-02-01 00:00), or pass time_format= (e.g. "
        "'%d.%m.%Y %H:%M')"
    )


def _offset_minutes(text: pd.Series) -> np.ndarray:
    """The UTC offset written at the end of every ISO 8601 stamp [min east of UTC]."""
    parts = text.astype(object).str.extract(r"(?:(Z)|([+-])(\d\d):?(\d\d)?)$")
    hours = parts[2].astype(float).to_numpy()
    minutes = hours * 60 + parts[3].astype(float).fillna(0.0).to_numpy()
    minutes = np.where((parts[1] == "-").to_numpy(dtype=bool), -minutes, minutes)
    return np.where((parts[0] == "Z").to_numpy(dtype=bool), 0.0, minutes)


def _format_offset(minutes: float) -> str:
    sign = "-" if minutes < 0 else "+"
    minutes = abs(int(round(minutes)))
    return f"{sign}{minutes // 60:02d}:{minutes % 60:02d}"


def check_clock_offsets(
    text: pd.Series,
    times: pd.DatetimeIndex,
    *,
    source: str,
    column: str,
    lines: np.ndarray | None = None,
) -> None:
    """Refuse a log whose UTC offsets disagree with its clock (a wrong offset or DST jump).

    Two slips that would otherwise leave a 1-hour gap (interpolated) or shift all later data:

    * the offset changes between two stamps while the *wall clock* goes on at the log's
      regular interval, so that the times in UTC jump: one of the offsets is wrong (e.g. a
      summer ``+01:00`` in a log otherwise ``+02:00``); at a real clock change the wall clock
      jumps and UTC goes on;
    * the offset stays the same while the clock jumps forward by exactly one hour beyond the
      interval in the small hours of a Sunday: the logger's wall clock switched to summer time
      but its offset was not updated.

    Parameters
    ----------
    text : pandas.Series
        The stamps as written (ISO 8601 with offsets).
    times : pandas.DatetimeIndex
        The parsed, tz-aware times (one per row).
    source, column : str
        For the message.
    lines : numpy.ndarray, optional
        1-based file line of every row.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Naming the line, the local hour and both offsets.
    """
    utc = times.as_unit("ns").asi8
    spacing = _regular_spacing(utc)
    if spacing is None:
        return
    steps, regular = spacing
    hour = 3600e9
    near = np.abs(steps - regular) <= 0.1 * regular
    stamp = str(text.iloc[0])
    suffix = _OFFSET.search(stamp).group(0) if _OFFSET.search(stamp) else ""
    same_suffix = bool(text.str.endswith(suffix).all()) if suffix else False
    if not same_suffix:
        offsets = _offset_minutes(text) * 60e9
        wall = utc + offsets.astype(np.int64)
        wall_steps = np.diff(wall)
        changed = np.flatnonzero(
            (np.diff(offsets) != 0)
            & (np.abs(wall_steps - regular) <= 0.1 * regular)
            & ~near
            & (np.abs(steps) < 3 * hour + regular)
        )
        if changed.size:
            i = int(changed[0])
            local = pd.Timestamp(int(wall[i + 1])).strftime("%Y-%m-%d %H:%M")
            jump = abs(steps[i] - regular) / hour
            raise ThermocalInputError(
                f"{source}, column '{column}', {_where(lines, i + 1)}: the UTC offset changes "
                f"from {_format_offset(offsets[i] / 60e9)} to "
                f"{_format_offset(offsets[i + 1] / 60e9)} at {local} (local clock), but the "
                f"clock readings go on at the log's interval of {regular / 60e9:g} min; in UTC "
                f"the time would jump by {jump:g} h (a gap interpolated or an hour repeated). "
                "At a real clock change the local clock jumps, not UTC: one of the offsets is "
                "wrong (summer time written with the winter offset?). Fix the offsets in the "
                "file, or write the times without offsets and pass the time zone (--tz "
                "Europe/Zurich)"
            )
        return
    for i in _hour_jumps(steps, regular):
        before = pd.Timestamp(int(utc[i]), tz="UTC").tz_convert(times.tz)
        if before.day_of_week == 6 and 0 <= before.hour <= 3 and before.month in (3, 4, 9, 10, 11):
            after = pd.Timestamp(int(utc[i + 1]), tz="UTC").tz_convert(times.tz)
            raise ThermocalInputError(
                f"{source}, column '{column}', {_where(lines, i + 1)}: the clock jumps from "
                f"{before:%H:%M} to {after:%H:%M} on Sunday {before:%Y-%m-%d}, one hour more "
                f"than the log's interval of {regular / 60e9:g} min, while the offset stays "
                f"{suffix}: this looks like the spring clock change written with the winter "
                "offset, which would shift every later time by an hour. Fix the offsets (summer "
                "time has its own, e.g. +02:00), or write the times without offsets and pass the "
                "time zone (--tz Europe/Zurich)"
            )


def _regular_spacing(utc: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The steps between stamps [ns] and their regular (median positive) interval [ns]; None
    for fewer than three stamps or two positive steps, or a log coarser than hourly (a one-hour
    slip is not visible in its spacing)."""
    if utc.size < 3:
        return None
    steps = np.diff(utc)
    positive = steps[steps > 0]
    if positive.size < 2:
        return None
    regular = float(np.median(positive))
    if regular > 3600e9:
        return None
    return steps, regular


def _hour_jumps(steps: np.ndarray, regular: float) -> np.ndarray:
    """Positions of the steps one hour longer than the regular interval (within 10 % of it)."""
    return np.flatnonzero(np.abs(steps - (regular + 3600e9)) <= 0.1 * regular)


def spring_change_sunday(stamp: pd.Timestamp) -> bool:
    """Whether ``stamp``'s date is a Sunday on which clocks go forward somewhere.

    The rules in use: the second Sunday of March (North America), the last Sunday of March
    (Europe), the last Sunday of September (New Zealand), the first Sunday of October
    (Australia) and the first Sunday of September (Chile). Any other Sunday a missing hour is a
    logger's gap, not a clock change (a check on every spring and autumn Sunday refused ordinary
    gaps on about 35 Sundays a year; review of 2026-11-30).

    Parameters
    ----------
    stamp : Timestamp
        A local time.

    Returns
    -------
    bool
    """
    if stamp.day_of_week != 6:
        return False
    day, month = stamp.day, stamp.month
    last = day + 7 > pd.Timestamp(stamp.year, month, 1).days_in_month
    return (
        (month == 3 and (8 <= day <= 14 or last))
        or (month == 9 and (last or day <= 7))
        or (month == 10 and day <= 7)
    )


def check_fixed_zone_clock(
    times: pd.DatetimeIndex, *, source: str, column: str, lines: np.ndarray | None = None
) -> None:
    """Refuse stamps without offsets placed in a zone without clock changes (a fixed offset
    such as ``--tz -6``, or UTC) whose clock jumps one hour forward in the small hours of a
    spring Sunday: a logger's local time with daylight saving, which the fixed zone would shift
    by an hour from then on (the same stamps with their offsets written were refused already).

    Parameters
    ----------
    times : pandas.DatetimeIndex
        The parsed, tz-aware times.
    source, column : str
        For the message.
    lines : numpy.ndarray, optional
        1-based file line of every row.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Naming the line, the jump and what to pass instead.
    """
    if times.tz is None or len(times) < 3:
        return
    winter = pd.Timestamp("2021-01-15", tz=times.tz).utcoffset()
    summer = pd.Timestamp("2021-07-15", tz=times.tz).utcoffset()
    if winter != summer:
        return  # the zone has its clock changes: the parse placed the stamps right
    spacing = _regular_spacing(times.as_unit("ns").asi8)
    if spacing is None:
        return
    steps, regular = spacing
    for i in _hour_jumps(steps, regular):
        before = times[i]
        if spring_change_sunday(before) and 0 <= before.hour <= 2:
            raise ThermocalInputError(
                f"{source}, column '{column}', {_where(lines, i + 1)}: the clock jumps from "
                f"{before:%H:%M} to {times[i + 1]:%H:%M} on Sunday {before:%Y-%m-%d}, one hour "
                f"more than the log's interval of {regular / 60e9:g} min, while the time zone "
                f"given ({before:%z}) has no clock change: the log seems written in local time "
                "with daylight saving, and every later time would be an hour off. Give the "
                "zone by name, which knows its clock changes (--tz America/Chicago on the "
                "command line, measurements.timezone: Europe/Zurich in a retrofit "
                "configuration)"
            )


def _numeric_times(values, source, column, lines, zone, time_unit, start):
    if time_unit is None:
        raise ThermocalInputError(
            f"{source}, column '{column}': the times are numbers ({values.iloc[0]} in the "
            f"first row); give their unit, one of {', '.join(TIME_UNITS)} (--time-unit on the "
            "command line, time_unit= in Python), and the time of 0 if it is not 1970-01-01 UTC "
            "(--time-origin, start=; e.g. '2009-02-05 14:26:00+01:00'); Unix time stamps such "
            "as 1546300800 are --time-unit s"
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
    return times, f"{NUMERIC_TIMES_NOTE} {time_unit} from {origin.isoformat()}"


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
    return localized.as_unit("ns"), f"{LOCAL_TIMES_NOTE} {tz}"
