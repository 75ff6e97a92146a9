"""Occupancy schedules: which steps count as unoccupied for the calibration metric.

The default is the schedule of the heat-balance identification paper: unoccupied from 20:00 to
04:00 every night, additionally 11:00-20:00 on Saturdays and all day on Sundays. A step
``[t, t + dt)`` is unoccupied when its start ``t`` (local time of the data) lies in one of the
unoccupied windows or on a listed holiday.

File form (YAML, the ``occupancy`` section of an identification or campaign file)::

    occupancy:
      unoccupied:
        - {days: all, from: "20:00", to: "04:00"}     # windows may cross midnight
        - {days: [Sat], from: "11:00", to: "20:00"}
        - {days: [Sun], from: "00:00", to: "24:00"}
      holidays: [2001-01-01, 2001-01-15]              # whole days unoccupied

Holidays are dates written year first (``YYYY-MM-DD``). A date written with a numeric day and
month before the year is read only when its numbers decide the order (``25/12/2001``); one that
reads as two dates (``01/09/2001``: 1 September or 9 January) is refused.
"""

from __future__ import annotations

import datetime as dt
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io._time import day_month_readings

#: A date written year first: ``2001-01-15``, ``2001-1-15``, ``2001/01/15``, ``2001.01.15``.
_YEAR_FIRST = re.compile(r"(\d{4})([-/.])(\d{1,2})\2(\d{1,2})")

DAY_NAMES = ("Mon", "Tue", "Wed", "Thu", "Fri", "Sat", "Sun")


@dataclass(frozen=True)
class UnoccupiedWindow:
    """Daily window ``[start, end)`` on the given weekdays (0 = Monday) [h]; may cross midnight.

    A window crossing midnight (``start > end``) belongs to the day it starts on.
    """

    days: tuple[int, ...]
    start: float
    end: float


@dataclass(frozen=True)
class OccupancySchedule:
    """Unoccupied windows and holidays.

    Parameters
    ----------
    windows : tuple of UnoccupiedWindow
    holidays : tuple of datetime.date
        Whole days unoccupied (local dates of the data).
    """

    windows: tuple[UnoccupiedWindow, ...] = field(
        default_factory=lambda: (
            UnoccupiedWindow(tuple(range(7)), 20.0, 4.0),
            UnoccupiedWindow((5,), 11.0, 20.0),
            UnoccupiedWindow((6,), 0.0, 24.0),
        )
    )
    holidays: tuple = ()

    @classmethod
    def paper(cls) -> OccupancySchedule:
        """The paper's schedule (nights 20-04, Saturdays 11-20, Sundays)."""
        return cls()

    @classmethod
    def from_dict(cls, spec: Mapping | None, *, source: str = "occupancy") -> OccupancySchedule:
        """Schedule from its file form (module docstring); None = the paper's default."""
        if spec is None:
            return cls()
        if not isinstance(spec, Mapping):
            raise ThermocalInputError(f"{source}: expected a mapping with 'unoccupied' windows")
        unknown = set(spec) - {"unoccupied", "holidays"}
        if unknown:
            raise ThermocalInputError(
                f"{source}: unknown keys {sorted(unknown)} (allowed: unoccupied, holidays)"
            )
        windows = cls().windows
        if "unoccupied" in spec:
            items = spec["unoccupied"]
            if not isinstance(items, Sequence) or isinstance(items, str):
                raise ThermocalInputError(f"{source}.unoccupied: expected a list of windows")
            windows = tuple(
                _window(item, f"{source}.unoccupied[{i}]") for i, item in enumerate(items)
            )
        entries = spec.get("holidays")
        entries = () if entries is None else entries
        if isinstance(entries, (str, dt.date, Mapping)) or not isinstance(entries, Iterable):
            raise ThermocalInputError(
                f"{source}.holidays: expected a list of dates, e.g. [2001-01-01, 2001-12-25]; "
                f"got {entries!r}"
            )
        holidays = tuple(
            holiday_date(value, f"{source}.holidays[{i}]") for i, value in enumerate(entries)
        )
        return cls(windows, holidays)

    def as_dict(self) -> dict:
        return {
            "unoccupied": [
                {
                    "days": [DAY_NAMES[d] for d in w.days],
                    "from": _clock(w.start),
                    "to": _clock(w.end),
                }
                for w in self.windows
            ],
            "holidays": [str(d) for d in self.holidays],
        }

    def unoccupied(self, times: pd.DatetimeIndex) -> np.ndarray:
        """Boolean mask of the unoccupied steps (by their start, in the index's local time)."""
        return unoccupied_mask(times, self)


def unoccupied_mask(times: pd.DatetimeIndex, schedule: OccupancySchedule | None = None):
    """True where the step starting at ``times`` is unoccupied.

    Parameters
    ----------
    times : DatetimeIndex
        Step starts (local time of the building; tz-aware indexes are used in their own zone).
    schedule : OccupancySchedule, optional
        Default: the paper's.

    Returns
    -------
    ndarray of bool
    """
    schedule = schedule or OccupancySchedule()
    times = pd.DatetimeIndex(times)
    hour = times.hour.to_numpy() + times.minute.to_numpy() / 60.0 + times.second.to_numpy() / 3600
    weekday = times.day_of_week.to_numpy()
    previous = (weekday - 1) % 7
    mask = np.zeros(len(times), dtype=bool)
    for w in schedule.windows:
        days = np.asarray(w.days)
        if w.start <= w.end:
            mask |= np.isin(weekday, days) & (hour >= w.start) & (hour < w.end)
        else:  # crosses midnight: evening part on the day, morning part on the next day
            mask |= np.isin(weekday, days) & (hour >= w.start)
            mask |= np.isin(previous, days) & (hour < w.end)
    if schedule.holidays:
        dates = np.array([t.date() for t in times])
        mask |= np.isin(dates, np.array(schedule.holidays))
    return mask


def holiday_date(value, where: str) -> dt.date:
    """One entry of a schedule's ``holidays`` as a date.

    Parameters
    ----------
    value : datetime.date, datetime.datetime or str
        A date as YAML reads it (``2001-01-15`` unquoted), or text: year first (``2001-01-15``,
        ``2001/1/15``), or day and month before the year (``25/12/2001``, ``12.25.2001``) when
        only one order gives a date (or both give the same one, ``05/05/2001``).
    where : str
        The file and key of the entry, for the message (``"occ.yaml: occupancy.holidays[0]"``).

    Returns
    -------
    datetime.date

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Text that is no calendar date (``2001-13-01``, ``2023-02-30``, ``31/31/2001``, ``2001``)
        or a numeric date that reads as two (``01/09/2001``); the message names ``where``, the
        entry and, for the latter, both readings.
    """
    if isinstance(value, dt.datetime):
        return value.date()
    if isinstance(value, dt.date):
        return value
    text = str(value).strip()
    year_first = _YEAR_FIRST.fullmatch(text)
    if year_first is not None:
        year, month, day = (int(year_first.group(k)) for k in (1, 3, 4))
        try:
            return dt.date(year, month, day)
        except ValueError as exc:
            raise ThermocalInputError(
                f"{where} = {value!r} is not a date ({exc}); write it as YYYY-MM-DD"
            ) from None
    readings = day_month_readings(text)
    if readings is None:
        # other unambiguous forms pandas reads ('2001-01-15 00:00', '15 January 2001',
        # '20010115'), as before; a bare year ('2001') is no day
        try:
            stamp = None if text.isdigit() and len(text) < 8 else pd.Timestamp(text)
        except (ValueError, OverflowError):
            stamp = None
        if stamp is None or pd.isna(stamp):
            raise ThermocalInputError(
                f"{where} = {value!r} is not a date; write it as YYYY-MM-DD (e.g. 2001-12-25)"
            )
        return stamp.date()
    dates = sorted(set(readings.values()))
    if not dates:
        raise ThermocalInputError(
            f"{where} = {value!r} is not a date (neither day-first nor month-first); write it "
            "as YYYY-MM-DD"
        )
    if len(dates) > 1:
        day_first, month_first = readings["day-first"], readings["month-first"]
        raise ThermocalInputError(
            f"{where} = {value!r} is ambiguous: {day_first.day} {day_first:%B %Y} read "
            f"day-first, {month_first.day} {month_first:%B %Y} month-first; write it year "
            f"first, YYYY-MM-DD ({day_first.isoformat()} or {month_first.isoformat()})"
        )
    return dates[0]


def _window(item, where: str) -> UnoccupiedWindow:
    if not isinstance(item, Mapping):
        raise ThermocalInputError(f"{where}: expected {{days: ..., from: 'HH:MM', to: 'HH:MM'}}")
    unknown = set(item) - {"days", "from", "to"}
    if unknown or not {"from", "to"} <= set(item):
        raise ThermocalInputError(
            f"{where}: needs 'from' and 'to' (and optionally 'days'); got keys {sorted(item)}"
        )
    days_spec = item.get("days", "all")
    if days_spec == "all":
        days = tuple(range(7))
    else:
        if isinstance(days_spec, str):
            days_spec = [days_spec]
        days = []
        for name in days_spec:
            key = str(name)[:3].title()
            if key not in DAY_NAMES:
                raise ThermocalInputError(
                    f"{where}: day {name!r} is not one of {', '.join(DAY_NAMES)} or 'all'"
                )
            days.append(DAY_NAMES.index(key))
        days = tuple(days)
    return UnoccupiedWindow(days, _hours(item["from"], where), _hours(item["to"], where))


def _hours(value, where: str) -> float:
    if isinstance(value, int) and not isinstance(value, bool):
        # YAML 1.1 reads an unquoted 20:00 as the sexagesimal integer 1200 (minutes)
        return _hours(f"{value}:00" if value <= 24 else f"{value // 60}:{value % 60}", where)
    text = str(value)
    try:
        hours, minutes = (text.split(":") + ["0"])[:2]
        result = int(hours) + int(minutes) / 60.0
    except ValueError as exc:
        raise ThermocalInputError(f"{where}: time {value!r} is not HH:MM") from exc
    if not 0.0 <= result <= 24.0:
        raise ThermocalInputError(f"{where}: time {value!r} outside 00:00-24:00")
    return result


def _clock(hours: float) -> str:
    return f"{int(hours):02d}:{int(round((hours % 1) * 60)):02d}"
