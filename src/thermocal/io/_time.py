"""Time columns of data files -> tz-aware DatetimeIndex (private helper of :mod:`thermocal.io`).

One parser for every table reader (weather CSV, measurement logs): ISO 8601 text with or without
UTC offsets (pyarrow fast path), an explicit strftime format, numbers with a unit and an origin,
or an already parsed datetime column (parquet). Numeric dates written day and month first
(``01/02/2015 00:00``, ``01.02.2015``) are read in the order the file's times decide, or
refused. Naive times are placed in ``tz``; aware ones are converted to it. In a zone with clock
changes the autumn's repeated hour is read in file order; in a fixed offset, a clock that
changes as a place's did is refused (:func:`check_fixed_zone_clock`). Every failure names the
file, the column and the line.

References
----------
.. [1] ISO 8601-1:2019, Date and time representations (timestamps with UTC offsets).
"""

from __future__ import annotations

import datetime as _dt
import functools
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


#: The areas of the IANA time zone database whose zones are places (``Europe/Zurich``); the
#: rest are aliases (``US/Central``, ``CST6CDT``) or fixed offsets (``Etc/GMT+6``).
_ZONE_AREAS = (
    "Africa", "America", "Antarctica", "Asia", "Atlantic", "Australia", "Europe", "Indian",
    "Pacific",
)  # fmt: skip
#: Zones a remedy names first when they fit (else the first fitting zone by name).
_USUAL_ZONES = (
    "America/Chicago", "America/New_York", "America/Denver", "America/Los_Angeles",
    "Europe/Zurich", "Europe/Berlin", "Europe/London", "Australia/Sydney",
)  # fmt: skip
#: Zones named in a message about a clock change, at most.
_ZONES_SHOWN = 3


@functools.lru_cache(maxsize=1)
def _place_zones() -> tuple[str, ...]:
    """The time zones of places in the IANA database (``zoneinfo``), sorted by name."""
    import zoneinfo

    return tuple(
        sorted(n for n in zoneinfo.available_timezones() if n.split("/")[0] in _ZONE_AREAS)
    )


@functools.lru_cache(maxsize=1)
def _place_zone_objects() -> tuple[tuple[str, _dt.tzinfo], ...]:
    """The zones of :func:`_place_zones` with their loaded ``zoneinfo.ZoneInfo`` (kept: the
    module's own cache keeps only a few, and reading a zone's file is most of a search)."""
    import zoneinfo

    return tuple((name, zoneinfo.ZoneInfo(name)) for name in _place_zones())


@functools.lru_cache(maxsize=1024)
def _zones_changing_around(day: _dt.date) -> tuple[str, ...]:
    """The zones whose UTC offset at noon the day before ``day`` differs from that at noon the
    day after (a clock change on, or next to, that local date)."""
    before = _dt.datetime.combine(day - _dt.timedelta(days=1), _dt.time(12))
    after = before + _dt.timedelta(days=2)
    changing = []
    for name, zone in _place_zone_objects():
        if before.replace(tzinfo=zone).utcoffset() != after.replace(tzinfo=zone).utcoffset():
            changing.append(name)
    return tuple(changing)


def clock_change_zones(
    before: pd.Timestamp, after: pd.Timestamp, step: pd.Timedelta, offset: pd.Timedelta
) -> list[str]:
    """The time zones in which two local clock readings are ``step`` apart across a clock
    change, one side of it at ``offset`` from UTC.

    A logger on local time with daylight saving read in a zone without clock changes: in
    spring its clock jumps an hour beyond the log's interval (``01:00`` then ``03:00``), in
    autumn it goes back by an hour less the interval (``01:00`` twice, or ``01:45`` then
    ``01:00``). In a zone of the IANA time zone database (``zoneinfo``) that changed its
    clocks there, the first reading taken before the change (daylight time where a reading
    is ambiguous) and the second after it are one interval apart, as the logger's are.

    Parameters
    ----------
    before, after : pandas.Timestamp
        Two consecutive clock readings of the log (naive: the wall clock).
    step : pandas.Timedelta
        The log's regular interval; a zone fits within 10 % of it.
    offset : pandas.Timedelta
        UTC offset of the zone the stamps were read in [h east of UTC, as a Timedelta]: one
        of a fitting zone's offsets, before or after the change (the logger's standard or
        daylight time).

    Returns
    -------
    list of str
        The fitting zones' names, sorted: those whose standard time is at ``offset`` (a
        weather file's time zone is standard time) when there are any, else those whose
        daylight time is; empty when no zone changed its clocks between the two readings (an
        ordinary gap or a repeated record).
    """
    import zoneinfo

    first, second = before.to_pydatetime(), after.to_pydatetime()
    names = set(_zones_changing_around(first.date())) | set(_zones_changing_around(second.date()))
    standard, daylight = [], []
    for name in sorted(names):
        zone = zoneinfo.ZoneInfo(name)
        was = first.replace(tzinfo=zone, fold=0).utcoffset()
        now = second.replace(tzinfo=zone, fold=1).utcoffset()
        if was == now or offset not in (was, now):
            continue
        apart = (second - now) - (first - was)
        if abs(apart - step) <= 0.1 * step:
            (standard if offset == min(was, now) else daylight).append(name)
    return standard or daylight


def _zones_text(zones: list[str], offset: pd.Timedelta) -> str:
    """``America/Cancun, America/Chicago, America/Matamoros and 9 other zone(s) at UTC-06:00``
    for a message."""
    shown = ", ".join(zones[:_ZONES_SHOWN])
    others = len(zones) - _ZONES_SHOWN
    rest = f" and {others} other zone(s)" if others > 0 else ""
    return f"{shown}{rest} at UTC{_format_offset(offset.total_seconds() / 60)}"


def _example_zone(zones: list[str]) -> str:
    """The zone to name in a remedy: America/Chicago, Europe/Zurich ... when among ``zones``."""
    for usual in _USUAL_ZONES:
        if usual in zones:
            return usual
    return zones[0]


def check_fixed_zone_clock(
    times: pd.DatetimeIndex, *, source: str, column: str, lines: np.ndarray | None = None
) -> None:
    """Refuse stamps without offsets placed in a zone without clock changes (a fixed offset
    such as ``--tz -6``, or UTC) whose clock changes as a place's did with daylight saving: a
    logger on local time, which the fixed zone would put an hour off all summer.

    In spring the clock jumps an hour beyond the log's interval (an hour missing), in autumn
    it goes back by an hour less the interval (an hour repeated; hourly stamps are
    duplicated), each exactly when a zone of the time zone database at the given offset
    changed its clocks (:func:`clock_change_zones`); the same stamps with their offsets
    written were refused already. A gap or a repeated record on any other night is left to
    the reader's checks.

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
        Naming the line, the two clock readings, the zones whose clocks changed then and the
        time zone to give by name.
    """
    if times.tz is None or len(times) < 3:
        return
    winter = pd.Timestamp("2021-01-15", tz=times.tz).utcoffset()
    summer = pd.Timestamp("2021-07-15", tz=times.tz).utcoffset()
    if winter != summer:
        return  # the zone has its clock changes: the parse placed the stamps right
    utc = times.as_unit("ns").asi8
    unique, first_row, counts = np.unique(utc, return_index=True, return_counts=True)
    spacing = _regular_spacing(unique)
    if spacing is None:
        return
    steps, regular = spacing
    interval = pd.Timedelta(int(regular), unit="ns")
    candidates = [(int(k), int(k) + 1, int(first_row[k + 1])) for k in _hour_jumps(steps, regular)]
    if abs(regular - 3600e9) <= 0.1 * regular:
        # hourly: the repeated hour is a time written more often than the log's usual rows
        # per time (once in a wide log, once per sensor in a long one)
        per_time = max(1, int(np.median(counts)))
        for k in np.flatnonzero(counts > per_time):
            row = int(np.flatnonzero(utc == unique[k])[per_time])
            candidates.append((int(k), int(k), row))
    else:
        back = np.flatnonzero(np.abs(np.diff(utc) - (regular - 3600e9)) <= 0.1 * regular)
        position = np.searchsorted(unique, utc)
        candidates += [(int(position[i]), int(position[i + 1]), int(i) + 1) for i in back]
    wall = unique + int(times[0].utcoffset().total_seconds() * 1e9)
    days = pd.to_datetime(wall, unit="ns").date
    changing = {
        day for day in {days[k] for c in candidates for k in c[:2]} if _zones_changing_around(day)
    }
    candidates = sorted(
        (c for c in candidates if days[c[0]] in changing or days[c[1]] in changing),
        key=lambda c: c[2],
    )
    shown = pd.DatetimeIndex(pd.to_datetime(unique, unit="ns", utc=True)).tz_convert(times.tz)
    for k, m, row in candidates[:_MAX_CLOCK_CANDIDATES]:
        before, after = shown[k], shown[m]
        offset = before.utcoffset()
        zones = clock_change_zones(
            before.tz_localize(None), after.tz_localize(None), interval, offset
        )
        if not zones:
            continue
        at = f"{source}, column '{column}', {_where(lines, row)}"
        if after > before:
            what = (
                f"the clock jumps from {before:%H:%M} to {after:%H:%M} on {before:%A %Y-%m-%d}, "
                f"one hour more than the log's interval of {regular / 60e9:g} min (an hour "
                "missing): clocks went forward that night"
            )
        else:
            repeat = "repeats" if after == before else f"goes back from {before:%H:%M} to"
            what = (
                f"the clock {repeat} {after:%H:%M} on {before:%A %Y-%m-%d} (an hour repeated): "
                "clocks went back from daylight saving to standard time that night"
            )
        example = _example_zone(zones)
        raise ThermocalInputError(
            f"{at}: {what} in {_zones_text(zones, offset)}, while the time zone given "
            f"({before:%z}) has no clock change: the log is in local time with daylight "
            "saving, and in the fixed zone the summer's times would be an hour off. Give the "
            f"time zone by name, which knows its clock changes (--tz {example} on the command "
            f"line, measurements.timezone: {example} in a retrofit or verify configuration), "
            "or write the times with their UTC offsets"
        )


#: Steps checked by :func:`check_fixed_zone_clock` for a clock change, at most, among those
#: on a date when a zone of the database changed its clocks (each fitting zone is searched).
_MAX_CLOCK_CANDIDATES = 50


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
    localized, repeated_note = _localize_local_clock(
        times, zone, values, source=source, column=column, lines=lines, tz=tz
    )
    note = f"{LOCAL_TIMES_NOTE} {tz}"
    return localized.as_unit("ns"), "; ".join(n for n in (note, repeated_note) if n)


def _localize_local_clock(times, zone, values, *, source, column, lines, tz):
    """Naive clock readings placed in ``zone``, the autumn's repeated hour in file order.

    Where the clocks go back (daylight saving to standard time), a local time such as 01:30
    happens twice. A logger on local time writes the hour twice, in order: each run of
    consecutive rows whose times are ambiguous in ``zone`` is read in daylight time up to
    the row where the clock goes back (:func:`_clock_goes_back_at`: a reading earlier than
    the one before it, or a reading written more often than the log's rows per time, so that
    the sensors of a long log sorted by time at one reading are not taken for the clock going
    back), and in standard time from there (pandas' ``ambiguous="infer"`` does the same, but
    fails when the hour is written once). A run the clock does not go back in, the hour written once
    (a logger that kept one of the two hours' records), is read as the first, daylight-time
    hour, with a warning: the standard-time hour after it is then missing, a gap as any
    other. Where the clocks go forward, the hour skipped never happened in ``zone``: a time
    in it is refused.

    Parameters
    ----------
    times : pandas.DatetimeIndex
        Naive clock readings, in file order.
    zone : datetime.tzinfo
        The time zone (with its clock changes).
    values : pandas.Series
        The column as written, for messages.
    source, column : str
        For messages.
    lines : numpy.ndarray, optional
        1-based file line of every row.
    tz : str or float
        The time zone as given, for messages.

    Returns
    -------
    times : pandas.DatetimeIndex
        In ``zone``.
    note : str
        How a repeated hour written once was read ("" when none was).

    Raises
    ------
    thermocal.errors.ThermocalInputError
        A clock reading in the hour skipped in spring, naming the line, the night's change and
        what to do.
    """
    n = len(times)
    daylight = times.tz_localize(zone, ambiguous=np.ones(n, dtype=bool), nonexistent="NaT")
    standard = times.tz_localize(zone, ambiguous=np.zeros(n, dtype=bool), nonexistent="NaT")
    skipped = np.asarray(daylight.isna())
    if skipped.any():
        first = int(np.flatnonzero(skipped)[0])
        wall = times[first]
        near = dict(ambiguous=True, nonexistent="shift_forward")
        before = pd.Timestamp(wall - pd.Timedelta(hours=3)).tz_localize(zone, **near)
        after = pd.Timestamp(wall + pd.Timedelta(hours=3)).tz_localize(zone, **near)
        raise ThermocalInputError(
            f"{source}, column '{column}', {_where(lines, first)}: the local time "
            f"{values.iloc[first]!r} never happened in time zone {tz!r}: that night the clocks "
            f"went forward from UTC{before:%z} to UTC{after:%z} (daylight saving time) and "
            f"skipped it ({int(skipped.sum())} such time(s)). A logger on that local time has "
            "no record there: remove the row (an hour filled in by hand?). If the logger keeps "
            "standard time all year, give the time zone as its standard time's fixed offset "
            f"(UTC{before:%z}), which has no clock change"
        )
    ambiguous = np.asarray(daylight != standard)
    if not ambiguous.any():
        return daylight, ""
    in_daylight = np.ones(n, dtype=bool)
    wall = times.as_unit("ns").asi8
    per_time = _rows_per_time(wall)
    starts = np.flatnonzero(ambiguous & ~np.r_[False, ambiguous[:-1]])
    ends = np.flatnonzero(ambiguous & ~np.r_[ambiguous[1:], False]) + 1
    once = []
    for start, end in zip(starts, ends, strict=True):
        back = _clock_goes_back_at(wall[start:end], per_time)
        if back is not None:
            in_daylight[start + back : end] = False
        else:
            once.append(int(start))
    utc = np.where(in_daylight, daylight.as_unit("ns").asi8, standard.as_unit("ns").asi8)
    placed = pd.DatetimeIndex(pd.to_datetime(utc, unit="ns", utc=True))
    placed = placed.tz_convert(zone)
    if not once:
        return placed, ""
    k = once[0]
    note = (
        f"{_where(lines, k)} ({values.iloc[k]!r}): the hour repeated when the clocks went "
        f"back in {tz} is written once ({len(once)} such night(s)); read as the first, "
        f"daylight-time hour (UTC{placed[k]:%z}), so the standard-time hour after it "
        f"(UTC{standard[k]:%z}) is missing. If the logger keeps standard time all year, give "
        f"the time zone as its fixed offset (UTC{standard[k]:%z}) instead"
    )
    log.warning("%s, column '%s', %s", source, column, note)
    return placed, note


def _rows_per_time(wall: np.ndarray) -> int:
    """The usual number of consecutive rows with the same clock reading: 1 in a wide log, the
    number of sensors in a long log (one row per sensor and time) sorted by time.

    Parameters
    ----------
    wall : numpy.ndarray
        Clock readings [ns], in file order.

    Returns
    -------
    int
        The median length of the runs of equal consecutive readings, at least 1.
    """
    if wall.size == 0:
        return 1
    bounds = np.r_[0, np.flatnonzero(np.diff(wall) != 0) + 1, wall.size]
    return max(1, int(np.median(np.diff(bounds))))


def _clock_goes_back_at(wall: np.ndarray, per_time: int) -> int | None:
    """Where, in a run of rows whose clock readings are ambiguous (the autumn's repeated hour),
    the clock went back: the first row read in standard time; None when it did not (the hour
    written once).

    Consecutive rows with the same reading are one clock reading (the sensors of a long log
    at one time). The clock went back at the first reading earlier than the one before it
    (``01:45`` then ``01:00``); without one, at the row after the first ``per_time`` rows of
    a reading written more often than ``per_time`` rows (hourly: ``01:00`` twice in a wide
    log, ``01:00`` for each sensor twice in a long log).

    Parameters
    ----------
    wall : numpy.ndarray
        The run's clock readings [ns], in file order.
    per_time : int
        The log's usual number of rows per reading (:func:`_rows_per_time`).

    Returns
    -------
    int or None
        0-based position in ``wall``.
    """
    earlier = np.flatnonzero(np.diff(wall) < 0)
    if earlier.size:
        return int(earlier[0]) + 1
    bounds = np.r_[0, np.flatnonzero(np.diff(wall) != 0) + 1, wall.size]
    for first, end in zip(bounds[:-1], bounds[1:], strict=True):
        if end - first > per_time:
            return int(first) + per_time
    return None
