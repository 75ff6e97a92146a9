"""Calendar and profile helpers of the IDF schedule evaluator.

Used by :class:`thermocal.multizone.idf.ScheduleEvaluator`.

Pure functions on plain values (no IDF objects): day profiles at one-minute resolution from
``Until`` times with EnergyPlus' interpolation kinds, ``Schedule:Day:List`` items,
``Schedule:File`` columns, the dates of ``RunPeriodControl:SpecialDays`` and the calendar year
that puts a ``RunPeriod`` start on its ``Day of Week for Start Day``.
"""

from __future__ import annotations

import calendar
import datetime as _dt
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from thermocal.errors import ThermocalInputError

MINUTES_PER_DAY = 1440

#: Interpolation kinds of ``Interpolate to Timestep`` (Schedule:Day:Interval/List, Schedule:File)
#: and of ``Interpolate:`` in Schedule:Compact. ``Yes`` is the pre-9.0 spelling of ``Average``.
INTERPOLATION_KINDS = {"NO": "no", "AVERAGE": "average", "YES": "average", "LINEAR": "linear"}

_WEEKDAYS = ("MONDAY", "TUESDAY", "WEDNESDAY", "THURSDAY", "FRIDAY", "SATURDAY", "SUNDAY")
_MONTHS = {name.upper(): i for i, name in enumerate(calendar.month_name) if name} | {
    name.upper(): i for i, name in enumerate(calendar.month_abbr) if name
}
_NTH = {"1ST": 1, "2ND": 2, "3RD": 3, "4TH": 4, "5TH": 5, "LAST": -1}


class DayProfile(np.ndarray):
    """A day profile (1440 minute values) that knows whether it is interpolated ``Average``
    (EnergyPlus gives a timestep of such a day the step mean, of the others, ``No`` and
    ``Linear``, the value at the step's end)."""

    average: bool = False


def _profile(values: np.ndarray, kind: str) -> DayProfile:
    out = values.view(DayProfile)
    out.average = kind == "average"
    return out


def interpolation_kind(text: str, where: str) -> str:
    """``"no"``, ``"average"`` or ``"linear"`` from an ``Interpolate`` field ("" -> ``"no"``)."""
    key = text.strip().upper() or "NO"
    if key not in INTERPOLATION_KINDS:
        raise ThermocalInputError(
            f"{where}: field 'Interpolate to Timestep' = '{text}' must be No, Average or Linear."
        )
    return INTERPOLATION_KINDS[key]


def interval_profile(
    untils: Sequence[int], values: Sequence[float], where: str, kind: str = "no"
) -> np.ndarray:
    """Day profile at one-minute resolution from ``Until`` times [min] and values.

    ``kind="no"`` / ``"average"``: the value holds from the previous ``Until`` time to its own
    (``average`` differs from ``no`` only in how a timestep that splits an interval is valued,
    which the step mean of the evaluator already does). ``kind="linear"``: as EnergyPlus, the
    value ramps linearly over each interval from the previous interval's value to its own,
    reaching it at the ``Until`` time (minute ``i`` of an ``n``-minute interval holds
    ``prev + (value - prev) (i + 1) / n``); the first interval of the day holds its value.
    """
    profile = np.empty(MINUTES_PER_DAY)
    start = 0
    previous = values[0] if len(values) else 0.0
    for until, value in zip(untils, values, strict=True):
        if until <= start:
            raise ThermocalInputError(f"{where}: 'Until' times must increase.")
        if kind == "linear":
            n = until - start
            profile[start:until] = previous + (value - previous) * np.arange(1, n + 1) / n
        else:
            profile[start:until] = value
        previous = value
        start = until
    if start != MINUTES_PER_DAY:
        raise ThermocalInputError(f"{where}: the day schedule must end with 'Until: 24:00'.")
    return _profile(profile, kind)


def list_profile(
    values: Sequence[float], minutes_per_item: int, where: str, kind: str
) -> np.ndarray:
    """``Schedule:Day:List``: one value per ``minutes_per_item`` minutes over the day."""
    if minutes_per_item <= 0 or 60 % minutes_per_item != 0:
        raise ThermocalInputError(
            f"{where}: field 'Minutes per Item' = {minutes_per_item} must divide 60."
        )
    n = MINUTES_PER_DAY // minutes_per_item
    if len(values) != n:
        raise ThermocalInputError(
            f"{where}: {len(values)} values given, {n} needed (1440 / Minutes per Item)."
        )
    untils = [(i + 1) * minutes_per_item for i in range(n)]
    return interval_profile(untils, values, where, kind)


def file_profile(
    path: Path,
    *,
    column: int,
    rows_to_skip: int,
    separator: str,
    minutes_per_item: int,
    n_days: int,
    leap: bool,
    kind: str,
    where: str,
) -> np.ndarray:
    """``Schedule:File``: the column's values at one-minute resolution, shape (n_days, 1440).

    Each item covers ``minutes_per_item`` minutes; a file for a leap year (366 days) read in a
    common year drops February 29 (days are matched by month and day, as the evaluator does for
    the grid); a common-year file read in a leap year is an error (too few values).
    ``kind="linear"`` ramps between consecutive items (the first item holds).
    """
    separators = {"COMMA": ",", "TAB": "\t", "SPACE": None, "SEMICOLON": ";", "": ","}
    sep_key = separator.strip().upper()
    if sep_key not in separators:
        raise ThermocalInputError(
            f"{where}: field 'Column Separator' = '{separator}' must be Comma, Tab, Space or "
            "Semicolon."
        )
    if minutes_per_item <= 0 or 60 % minutes_per_item != 0:
        raise ThermocalInputError(
            f"{where}: field 'Minutes per Item' = {minutes_per_item} must divide 60."
        )
    if column < 1:
        raise ThermocalInputError(f"{where}: field 'Column Number' = {column} must be 1 or more.")
    if not path.exists():
        raise ThermocalInputError(f"{where}: field 'File Name': {path} does not exist.")
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()[rows_to_skip:]
    values: list[float] = []
    sep = separators[sep_key]
    for number, line in enumerate(lines, start=rows_to_skip + 1):
        if not line.strip():
            continue
        cells = line.split(sep)
        if len(cells) < column:
            raise ThermocalInputError(
                f"{where}: {path.name} line {number} has {len(cells)} columns, "
                f"'Column Number' is {column}."
            )
        try:
            values.append(float(cells[column - 1]))
        except ValueError:
            raise ThermocalInputError(
                f"{where}: {path.name} line {number} column {column} = "
                f"'{cells[column - 1].strip()}' is not a number."
            ) from None
    per_day = MINUTES_PER_DAY // minutes_per_item
    items_file = len(values)
    if items_file >= 366 * per_day and not leap:
        data = np.asarray(values[: 366 * per_day]).reshape(366, per_day)
        data = np.delete(data, 59, axis=0)  # February 29
    elif items_file >= n_days * per_day:
        data = np.asarray(values[: n_days * per_day]).reshape(n_days, per_day)
    else:
        raise ThermocalInputError(
            f"{where}: {path.name} column {column} has {items_file} values after "
            f"{rows_to_skip} skipped rows, {n_days * per_day} needed "
            f"({n_days} days x {per_day} items)."
        )
    flat = np.repeat(data.ravel(), minutes_per_item)
    if kind == "linear":
        ends = data.ravel()
        starts = np.concatenate((ends[:1], ends[:-1]))
        frac = np.tile(np.arange(1, minutes_per_item + 1) / minutes_per_item, ends.size)
        flat = (
            np.repeat(starts, minutes_per_item) + np.repeat(ends - starts, minutes_per_item) * frac
        )
    return flat.reshape(n_days, MINUTES_PER_DAY)


def special_day(text: str, year: int, where: str) -> _dt.date:
    """Date of a ``RunPeriodControl:SpecialDays`` ``Start Date`` in ``year``.

    Forms accepted, as EnergyPlus: ``7/4``, ``July 4``, ``4 July``, ``Jul 4``,
    ``1st Monday in September``, ``4th Thursday in November``, ``Last Monday in May``.
    """
    words = text.replace(",", " ").split()
    upper = [w.upper() for w in words]
    try:
        if len(words) == 1 and "/" in text:
            month, _, day = text.strip().partition("/")
            return _dt.date(year, int(month), int(day))
        if len(upper) == 2:
            if upper[0] in _MONTHS:
                return _dt.date(year, _MONTHS[upper[0]], int(words[1]))
            if upper[1] in _MONTHS:
                return _dt.date(year, _MONTHS[upper[1]], int(words[0]))
        if len(upper) == 4 and upper[0] in _NTH and upper[1] in _WEEKDAYS and upper[2] == "IN":
            month = _MONTHS[upper[3]]
            weekday = _WEEKDAYS.index(upper[1])
            days = [
                d
                for d in range(1, calendar.monthrange(year, month)[1] + 1)
                if _dt.date(year, month, d).weekday() == weekday
            ]
            nth = _NTH[upper[0]]
            return _dt.date(year, month, days[nth - 1 if nth > 0 else -1])
    except (ValueError, KeyError, IndexError):
        pass
    raise ThermocalInputError(
        f"{where}: field 'Start Date' = '{text}' is not a date EnergyPlus accepts "
        "('7/4', 'July 4', '1st Monday in September', 'Last Monday in May')."
    )


def year_for_start_day(month: int, day: int, weekday: str, where: str) -> int:
    """A common year (a leap year for a February 29 start) whose ``month/day`` is ``weekday``.

    EnergyPlus picks such a year when the RunPeriod gives no ``Begin Year``; every year with the
    same weekday of January 1 and leap status gives the same calendar.
    """
    key = weekday.strip().upper()
    if key not in _WEEKDAYS:
        raise ThermocalInputError(
            f"{where}: field 'Day of Week for Start Day' = '{weekday}' must be a day name "
            "(Sunday..Saturday)."
        )
    for year in range(2006, 2034):
        if calendar.isleap(year) != (month == 2 and day == 29):
            continue
        try:
            if _dt.date(year, month, day).weekday() == _WEEKDAYS.index(key):
                return year
        except ValueError:
            break
    raise ThermocalInputError(f"{where}: invalid begin date {month}/{day}.")
