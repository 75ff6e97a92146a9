"""Schedules of an IDF file evaluated over a calendar year, at one-minute resolution.

:class:`ScheduleEvaluator` reads ``Schedule:Constant``, ``Schedule:Compact``, ``Schedule:Year``
with ``Schedule:Week:Daily`` / ``Schedule:Week:Compact`` and ``Schedule:Day:Interval`` /
``Schedule:Day:Hourly`` / ``Schedule:Day:List``, ``Schedule:File`` and EnergyPlus' calendar:
the special days of ``RunPeriodControl:SpecialDays`` and of the weather file, the weekend holiday
rule, the weather file's daylight saving period.
The calendar and profile helpers below it are pure functions on plain values (no IDF objects):
day profiles at one-minute resolution from ``Until`` times with EnergyPlus' interpolation kinds,
``Schedule:Day:List`` items, ``Schedule:File`` columns, EnergyPlus' date fields
(:func:`parse_date`, :func:`resolve_date`) and the calendar year that puts a ``RunPeriod`` start
on its ``Day of Week for Start Day``.
"""

from __future__ import annotations

import calendar
import datetime as _dt
import re
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.fields import SCHEMA
from thermocal.multizone.idf.parse import IdfObject, _field_float, _label, _number, record

DAY_TYPES = (
    "SUNDAY",
    "MONDAY",
    "TUESDAY",
    "WEDNESDAY",
    "THURSDAY",
    "FRIDAY",
    "SATURDAY",
    "HOLIDAY",
    "SUMMERDESIGNDAY",
    "WINTERDESIGNDAY",
    "CUSTOMDAY1",
    "CUSTOMDAY2",
)
#: Keys of a ``For:`` field and the day types they select, as EnergyPlus' ProcessForDayTypes
#: (a key found anywhere in the upper-case field; "ALLOTHERDAY" apart).
_FOR_KEYS = (
    ("WEEKDAY", (1, 2, 3, 4, 5)),
    ("MONDAY", (1,)),
    ("TUESDAY", (2,)),
    ("WEDNESDAY", (3,)),
    ("THURSDAY", (4,)),
    ("FRIDAY", (5,)),
    ("SATURDAY", (6,)),
    ("SUNDAY", (0,)),
    ("WEEKEND", (0, 6)),
    ("ALLDAY", tuple(range(12))),
    ("HOLIDAY", (7,)),
    ("SUMMER", (8,)),
    ("WINTER", (9,)),
    ("CUSTOMDAY1", (10,)),
    ("CUSTOMDAY2", (11,)),
)
_SCHEDULE_CLASSES = (
    "SCHEDULE:CONSTANT",
    "SCHEDULE:COMPACT",
    "SCHEDULE:YEAR",
    "SCHEDULE:WEEK:DAILY",
    "SCHEDULE:DAY:INTERVAL",
    "SCHEDULE:DAY:HOURLY",
    "SCHEDULE:WEEK:COMPACT",
    "SCHEDULE:DAY:LIST",
    "SCHEDULE:FILE",
)
_MINUTES_PER_DAY = 1440


class UnsupportedScheduleError(ThermocalInputError):
    """A referenced schedule cannot be evaluated (missing or of an unsupported class)."""


#: A Schedule:Compact field's keyword, with or without its colon ("For AllOtherDays", which
#: EnergyPlus accepts as "For: AllOtherDays").
_COMPACT_KEYWORD = re.compile(r"^\s*(THROUGH|FOR|INTERPOLATE|UNTIL)\b\s*:?(.*)$", re.IGNORECASE)


def _compact_keyword(token: str) -> tuple[str, str]:
    """``(KEYWORD, rest)`` of a Schedule:Compact field (upper case; ``""`` for a value)."""
    found = _COMPACT_KEYWORD.match(token)
    if found is None:
        return "", token
    return found.group(1).upper(), found.group(2)


def _parse_time(text: str, where: str) -> int:
    """'hh:mm' -> minutes after midnight (1..1440)."""
    try:
        hours, _, minutes = text.strip().partition(":")
        value = int(hours) * 60 + int(minutes or 0)
    except ValueError:
        raise ThermocalInputError(f"{where}: time '{text}' is not hh:mm.") from None
    if not 0 < value <= _MINUTES_PER_DAY:
        raise ThermocalInputError(f"{where}: time '{text}' is outside 00:01..24:00.")
    return value


class ScheduleEvaluator:
    """Evaluates the schedules of an IDF file over a calendar year.

    Supported: ``Schedule:Constant``, ``Schedule:Compact`` (Through/For/Interpolate/Until),
    ``Schedule:Year`` with ``Schedule:Week:Daily`` / ``Schedule:Week:Compact`` and
    ``Schedule:Day:Interval`` / ``Schedule:Day:Hourly`` / ``Schedule:Day:List``, and
    ``Schedule:File``. ``Interpolate`` ``Average`` (``Yes``) and ``No`` hold each value over its
    interval (the step mean of :meth:`on_grid` is EnergyPlus' average); ``Linear`` ramps over each
    interval from the previous value (:func:`interval_profile`).
    Special days of ``RunPeriodControl:SpecialDays`` (Holiday, SummerDesignDay, WinterDesignDay,
    CustomDay1/2) and the weather file's holidays (:meth:`set_weather_calendar`, when
    ``weather_holidays``) replace the weekday of their dates; with ``weekend_rule`` a one-day
    special day given by month and day that falls on a Saturday or Sunday moves to the following
    Monday (EnergyPlus' ``SetSpecialDayDates``). On the days of the weather file's daylight saving
    period (when ``weather_daylight_saving``) :meth:`on_grid` evaluates the schedules one hour
    later (their clock is local daylight time; ``Schedule:File`` with 'Adjust Schedule for
    Daylight Savings' = No excepted); :meth:`minutes` and the statistics stay on the schedule
    clock. ``RunPeriodControl:DaylightSavingTime`` is not read (not among the importer's classes,
    it is listed as skipped).

    Parameters
    ----------
    objects : iterable of IdfObject
        All objects of the file (the schedule and special-day classes are picked out).
    year : int
        Calendar year for day-of-week and leap-year handling.
    base_dir : Path or None
        Folder against which relative ``Schedule:File`` names are resolved (the IDF's folder).
    weather_holidays, weather_daylight_saving, weekend_rule : bool
        The RunPeriod's 'Use Weather File Holidays and Special Days', 'Use Weather File Daylight
        Saving Period' and 'Apply Weekend Holiday Rule' (EnergyPlus' defaults: Yes, Yes, No).
    notes : list of str or None
        Receives (and keeps up to date) one note on the calendar applied: holidays of the weather
        file, DST period, special days moved by the weekend rule (the importer's notes).
    """

    def __init__(
        self,
        objects: Iterable[IdfObject],
        year: int = 2006,
        version=(9, 3),
        base_dir: Path | None = None,
        *,
        weather_holidays: bool = True,
        weather_daylight_saving: bool = True,
        weekend_rule: bool = False,
        notes: list[str] | None = None,
    ):
        self.year = year
        self.base_dir = Path(base_dir) if base_dir is not None else Path.cwd()
        #: RunPeriod 'Use Weather File Holidays and Special Days', 'Use Weather File Daylight
        #: Saving Period' and 'Apply Weekend Holiday Rule' (EnergyPlus' defaults: Yes, Yes, No)
        self.weather_holidays = bool(weather_holidays)
        self.weather_daylight_saving = bool(weather_daylight_saving)
        self.weekend_rule = bool(weekend_rule)
        #: list receiving the note on the calendar applied (the importer's notes)
        self.notes = notes
        self._records: dict[str, dict] = {}
        #: IDF special days: (spec, duration, day type, where)
        self._idf_special: list[tuple[DateSpec, int, str, str]] = []
        #: the weather file's holidays [(name, date text)], DST period (start, end) and path
        self._weather: tuple[tuple, tuple | None, str] | None = None
        self._note: str | None = None
        #: schedules not shifted by daylight saving time (Schedule:File 'Adjust Schedule for
        #: Daylight Savings' = No)
        self._standard_time: set[str] = set()
        #: RunPeriodControl:DaylightSavingTime (start, end, where): applied whatever the
        #: RunPeriod says about the weather file's period, as EnergyPlus does
        self._idf_daylight_saving: tuple | None = None
        for obj in objects:
            if obj.key in _SCHEDULE_CLASSES:
                rec = self._records[obj.name.upper()] = record(obj, version=version)
                adjust = rec.get("adjust_schedule_for_daylight_savings", "") or "Yes"
                if obj.key == "SCHEDULE:FILE" and adjust.strip().upper() == "NO":
                    self._standard_time.add(obj.name.upper())
            elif obj.key == "RUNPERIODCONTROL:SPECIALDAYS":
                self._idf_special.append(self._special_day(record(obj, version=version)))
            elif obj.key == "RUNPERIODCONTROL:DAYLIGHTSAVINGTIME":
                if self._idf_daylight_saving is not None:
                    raise ThermocalInputError(
                        f"{obj.where()}: only one RunPeriodControl:DaylightSavingTime object is "
                        "allowed."
                    )
                rec = record(obj, version=version)
                where = obj.where()
                self._idf_daylight_saving = (
                    parse_date(rec["start_date"], where, "Start Date"),
                    parse_date(rec["end_date"], where, "End Date"),
                    where,
                )
        first = _dt.date(year, 1, 1)
        self.n_days = (_dt.date(year + 1, 1, 1) - first).days
        self._month_day = [
            ((first + _dt.timedelta(days=d)).month, (first + _dt.timedelta(days=d)).day)
            for d in range(self.n_days)
        ]
        self._build_calendar()

    @staticmethod
    def _special_day(rec: dict) -> tuple[DateSpec, int, str, str]:
        where = rec["_object"].where()
        kind = (rec["special_day_type"] or "Holiday").replace(" ", "").upper()
        if kind not in DAY_TYPES[7:]:
            raise ThermocalInputError(
                f"{where}: field 'Special Day Type' = '{rec['special_day_type']}' must be "
                "Holiday, SummerDesignDay, WinterDesignDay, CustomDay1 or CustomDay2."
            )
        duration = int(_number(rec, "duration", default=1.0))
        if duration < 1:
            raise ThermocalInputError(f"{where}: field 'Duration' = {duration} must be 1 or more.")
        return parse_date(rec["start_date"], where), duration, kind, where

    def set_weather_calendar(
        self,
        holidays: Iterable[tuple[str, str]] = (),
        daylight_saving: tuple[str, str] | None = None,
        source: str = "",
    ) -> None:
        """Holidays and daylight saving period of the weather file (EPW ``HOLIDAYS/DAYLIGHT
        SAVINGS`` line, as :func:`thermocal.io.weather.read_epw` gives them in its metadata).

        Used as EnergyPlus does per the RunPeriod: the holidays (Holiday day type, one day each)
        when 'Use Weather File Holidays and Special Days' is Yes, the DST period when 'Use Weather
        File Daylight Saving Period' is Yes. Values already computed are recomputed; the calendar
        note in :attr:`notes` is replaced.

        Parameters
        ----------
        holidays : iterable of (name, date text)
        daylight_saving : (start date text, end date text) or None
        source : str
            The weather file, for messages.
        """
        weather = (
            tuple((str(n), str(d)) for n, d in holidays),
            None if daylight_saving is None else tuple(daylight_saving),
            str(source),
        )
        if weather != self._weather:
            self._weather = weather
            self._build_calendar()

    def _build_calendar(self) -> None:
        """Day types, special days and DST days of the year; clears the computed values."""
        year, n_days = self.year, self.n_days
        first = _dt.date(year, 1, 1)
        weekdays = np.array(
            [((first + _dt.timedelta(days=d)).weekday() + 1) % 7 for d in range(n_days)]
        )
        self._day_type = weekdays.copy()
        #: Day of year -> special day type name (weather file holidays, then
        #: RunPeriodControl:SpecialDays, which win where both fall on a day).
        self.special_days: dict[int, str] = {}
        entries = []
        holidays, dst_weather, source = self._weather or ((), None, "")
        where_weather = f"weather file {source}, HOLIDAYS/DAYLIGHT SAVINGS"
        if self.weather_holidays:
            for name, text in holidays:
                where = f"{where_weather}, holiday '{name}'"
                entries.append((parse_date(text, where, "date"), 1, "HOLIDAY", where))
        entries += self._idf_special
        moved = 0
        for spec, duration, kind, where in entries:
            start = (resolve_date(spec, year, where) - first).days
            if spec.kind == "monthday" and duration == 1 and self.weekend_rule:
                # EnergyPlus (SetSpecialDayDates): Sunday -> Monday, Saturday -> Monday
                shift = {0: 1, 6: 2}.get(int(weekdays[start]), 0)
                moved += shift > 0
                start = (start + shift) % n_days
            for d in range(start, start + duration):
                self._day_type[d % n_days] = DAY_TYPES.index(kind)
                self.special_days[d % n_days] = kind
        #: Days (bool, n_days) on daylight saving time: schedules evaluated one hour later
        self.daylight_saving = np.zeros(n_days, dtype=bool)
        #: (first day, last day, source) of the DST period applied, or None
        self.daylight_saving_period: tuple[_dt.date, _dt.date, str] | None = None
        period = self._idf_daylight_saving
        if period is None and self.weather_daylight_saving and dst_weather is not None:
            period = (
                parse_date(dst_weather[0], where_weather, "daylight saving start"),
                parse_date(dst_weather[1], where_weather, "daylight saving end"),
                f"weather file {Path(source).name}" if source else "weather file",
            )
        if period is not None:
            start_spec, end_spec, where = period
            start = resolve_date(start_spec, year, where, "Start Date")
            end = resolve_date(end_spec, year, where, "End Date")
            a, b = (start - first).days, (end - first).days
            if b >= a:
                self.daylight_saving[a : b + 1] = True
            else:  # southern hemisphere: over the new year
                self.daylight_saving[a:] = True
                self.daylight_saving[: b + 1] = True
            self.daylight_saving_period = (start, end, where)
        #: minutes by upper-case name; grid values, means, modes and ranges by (kind, name, ...)
        self._cache: dict = {}
        #: schedule name -> days (bool, n_days) interpolated 'Average' (step mean)
        self._average_days: dict[str, np.ndarray] = {}
        self._set_note(len(holidays), dst_weather, moved)

    def _set_note(self, n_weather: int, dst_weather, moved: int) -> None:
        parts = []
        if self._weather is not None:
            if self.weather_holidays:
                parts.append(f"{n_weather} holiday(s) from the weather file")
            elif n_weather:
                parts.append(
                    f"the weather file's {n_weather} holiday(s) not used ('Use Weather File "
                    "Holidays and Special Days' = No)"
                )
        if self.daylight_saving_period is not None:
            start, end, where = self.daylight_saving_period
            parts.append(
                f"daylight saving time {start.month}/{start.day} to {end.month}/{end.day} "
                f"({where}): schedules evaluated one hour later"
            )
        elif dst_weather is not None and not self.weather_daylight_saving:
            parts.append(
                "the weather file's daylight saving period not used ('Use Weather File "
                "Daylight Saving Period' = No)"
            )
        if self.weekend_rule:
            parts.append(
                f"'Apply Weekend Holiday Rule' = Yes: {moved} special day(s) on a Saturday or "
                "Sunday observed on the following Monday"
            )
        note = "schedule calendar: " + "; ".join(parts) if parts else None
        if self.notes is not None:
            if self._note in self.notes:
                self.notes.remove(self._note)
            if note:
                self.notes.append(note)
        self._note = note

    def __contains__(self, name: str) -> bool:
        return name.upper() in self._records

    def _doy(self, month: int, day: int, where: str) -> int:
        try:
            return (_dt.date(self.year, month, day) - _dt.date(self.year, 1, 1)).days
        except ValueError:
            if month == 2 and day == 29:  # Feb 29 in a non-leap year: end of February
                return (_dt.date(self.year, 2, 28) - _dt.date(self.year, 1, 1)).days
            raise ThermocalInputError(f"{where}: invalid date {month}/{day}.") from None

    def minutes(self, name: str) -> np.ndarray:
        """Values at one-minute resolution over the year, shape (n_days, 1440)."""
        key = name.upper()
        if key in self._cache:
            return self._cache[key]
        rec = self._records.get(key)
        if rec is None:
            raise UnsupportedScheduleError(
                f"schedule '{name}' is not defined by a supported schedule object "
                f"({', '.join(c.title() for c in _SCHEDULE_CLASSES)})."
            )
        obj: IdfObject = rec["_object"]
        if obj.key == "SCHEDULE:CONSTANT":
            value = _number(rec, "hourly_value", default=0.0)
            out = np.full((self.n_days, _MINUTES_PER_DAY), value)
        elif obj.key == "SCHEDULE:COMPACT":
            out = self._compact(rec)
        elif obj.key == "SCHEDULE:YEAR":
            out = self._year(rec)
        elif obj.key == "SCHEDULE:FILE":
            out = self._file(rec)
        else:
            raise UnsupportedScheduleError(
                f"{obj.where()} is a day/week schedule and cannot be used as a full schedule."
            )
        self._cache[key] = out
        return out

    def on_grid(self, name: str, times, step) -> np.ndarray:
        """Value of each simulation step ``[t, t + step)`` as EnergyPlus gives it [schedule unit].

        Parameters
        ----------
        name : str
            Schedule name.
        times : pandas.DatetimeIndex
            Step starts (local standard time, as the weather file). Each is placed in the
            schedule calendar by its month, day and time of day (the day of week and holidays
            come from the calendar year of the import, as EnergyPlus takes them from the
            RunPeriod); February 29 of a leap grid year takes February 28's values in a common
            calendar year.
        step : pandas.Timedelta

        Returns
        -------
        numpy.ndarray, shape (len(times),)

        Notes
        -----
        As EnergyPlus: the value at the step's end (its last minute) for ``Interpolate`` ``No``
        (the default) and ``Linear``, the mean over the step for ``Average``. For a step
        function and steps that tile the ``Until`` times both are the interval value.
        """
        import pandas as pd

        key = ("grid", name.upper(), len(times), times[0], pd.Timedelta(step))
        if key in self._cache:
            return self._cache[key]
        flat = self.minutes(name).ravel()
        width = max(int(round(pd.Timedelta(step).total_seconds() / 60.0)), 1)
        cumulative = np.concatenate(([0.0], np.cumsum(np.concatenate((flat, flat[:1440])))))
        index = self.minute_index(times)
        if name.upper() not in self._standard_time and self.daylight_saving.any():
            # the schedules' clock is local daylight time: one hour later on DST days (EnergyPlus
            # adds the DST indicator to the hour of day; past midnight: the next day's values)
            index = index + 60 * self.daylight_saving[index // _MINUTES_PER_DAY]
        out = np.concatenate((flat, flat[:1440]))[index + width - 1]
        average = self._average_days.get(name.upper())
        if average is not None and average.any():
            mean = (cumulative[index + width] - cumulative[index]) / width
            day = np.minimum(index // _MINUTES_PER_DAY, self.n_days - 1)
            out = np.where(average[day], mean, out)
        self._cache[key] = out
        return out

    def minute_index(self, times) -> np.ndarray:
        """Minute of the schedule year of each time (by month, day, hour, minute)."""
        import pandas as pd

        times = pd.DatetimeIndex(times)
        first = _dt.date(self.year, 1, 1).toordinal()
        month = times.month.to_numpy()
        day = times.day.to_numpy()
        leap = (self.year % 4 == 0 and self.year % 100 != 0) or self.year % 400 == 0
        day = np.where((month == 2) & (day == 29) & (not leap), 28, day)
        month_start = np.array(
            [_dt.date(self.year, m, 1).toordinal() - first for m in range(1, 13)]
        )
        doy = month_start[month - 1] + day - 1
        minute = times.hour.to_numpy() * 60 + times.minute.to_numpy()
        return doy * _MINUTES_PER_DAY + minute

    def hourly(self, name: str) -> np.ndarray:
        """Hourly mean values over the year, shape (n_days * 24,)."""
        return self.minutes(name).reshape(self.n_days * 24, 60).mean(axis=1)

    def annual_mean(self, name: str) -> float:
        """Time-weighted mean over the year."""
        key = ("mean", name.upper())
        if key not in self._cache:
            self._cache[key] = float(self.minutes(name).mean())
        return self._cache[key]

    def mode(self, name: str) -> float:
        """The value in effect for the largest share of the year."""
        key = ("mode", name.upper())
        if key not in self._cache:
            values, counts = np.unique(self.minutes(name), return_counts=True)
            self._cache[key] = float(values[np.argmax(counts)])
        return self._cache[key]

    def value_range(self, name: str) -> tuple[float, float]:
        """Minimum and maximum value over the year."""
        key = ("range", name.upper())
        if key not in self._cache:
            m = self.minutes(name)
            self._cache[key] = (float(m.min()), float(m.max()))
        return self._cache[key]

    # -- compact ---------------------------------------------------------------------------------
    def _compact(self, rec: dict) -> np.ndarray:
        obj: IdfObject = rec["_object"]
        where = obj.where()
        tokens = [t[0] for t in rec["compact_fields"]]
        out = np.full((self.n_days, _MINUTES_PER_DAY), np.nan)
        average = self._average_days[obj.name.upper()] = np.zeros(self.n_days, dtype=bool)
        block_start = 0
        assigned: dict[int, np.ndarray] = {}
        targets: list[int] = []
        untils: list[int] = []
        values: list[float] = []
        pending_until: int | None = None
        block_end: int | None = None

        kind = "no"

        def finish_day():
            nonlocal untils, values, targets, kind
            if targets:
                profile = interval_profile(untils, values, where, kind)
                for t in targets:
                    assigned.setdefault(t, profile)
            targets, untils, values, kind = [], [], [], "no"

        def finish_block():
            nonlocal assigned, block_start
            finish_day()
            if block_end is None:
                return
            for d in range(block_start, block_end + 1):
                profile = assigned.get(int(self._day_type[d]))
                if profile is None:
                    raise ThermocalInputError(
                        f"{where}: no 'For:' rule covers {DAY_TYPES[self._day_type[d]].title()}s "
                        f"(day {d + 1} of the year); add 'For: AllOtherDays'."
                    )
                out[d] = profile
                average[d] = getattr(profile, "average", False)
            block_start = block_end + 1
            assigned = {}

        for token in tokens:
            keyword, rest = _compact_keyword(token)
            if keyword == "THROUGH":
                finish_block()
                month, _, day = rest.strip().partition("/")
                try:
                    block_end = self._doy(int(month), int(day), where)
                except ValueError:
                    raise ThermocalInputError(f"{where}: bad date in '{token}'.") from None
            elif keyword == "FOR":
                finish_day()
                targets = self._day_types(rest, assigned, where)
            elif keyword == "INTERPOLATE":
                kind = interpolation_kind(rest, f"{where}, field '{token}'")
            elif keyword == "UNTIL":
                time_text = rest.strip()
                # "Until: 24:00" -> rest is "24:00" (partition splits at the first colon only)
                pending_until = _parse_time(time_text, where)
            else:
                try:
                    value = float(token)
                except ValueError:
                    raise ThermocalInputError(
                        f"{where}: unexpected field '{token}' (expected Through:/For:/Until: or a "
                        "number)."
                    ) from None
                if pending_until is None:
                    raise ThermocalInputError(f"{where}: value {token} without a preceding Until.")
                untils.append(pending_until)
                values.append(value)
                pending_until = None
        finish_block()
        if block_start < self.n_days:
            raise ThermocalInputError(f"{where}: the last 'Through:' must be 12/31.")
        return out

    @staticmethod
    def _day_types(text: str, assigned: dict, where: str) -> list[int]:
        """Day types (indices into :data:`DAY_TYPES`) of a ``For:`` field, as EnergyPlus reads
        it (``ProcessForDayTypes``): case-insensitive, each key found anywhere in the field, so
        singular and plural forms are the same (``Saturday``/``Saturdays``, ``Weekday``/
        ``Weekdays``, ``Holiday``/``Holidays``, ``AllDay``/``AllDays``,
        ``AllOtherDay``/``AllOtherDays``); ``Summer...`` is SummerDesignDay, ``Winter...``
        WinterDesignDay; several keys may share one field (``For: Weekends Holidays``).
        ``AllOtherDays`` takes the day types no earlier key of the ``Through:`` block took.
        """
        field = text.upper()
        result: list[int] = []

        def take(indices):
            result.extend(i for i in indices if i not in result)

        for key, indices in _FOR_KEYS:
            if key in field:
                take(indices)
        if "ALLOTHERDAY" in field:
            take(i for i in range(len(DAY_TYPES)) if i not in assigned)
        if not result:
            raise ThermocalInputError(
                f"{where}: 'For: {text.strip()}' names no day type; use Sunday..Saturday, "
                "Weekdays, Weekends, Holidays, SummerDesignDay, WinterDesignDay, CustomDay1, "
                "CustomDay2, AllDays or AllOtherDays (singular or plural, any case)."
            )
        return result

    # -- year/week/day ---------------------------------------------------------------------------
    def _day_object(self, name: str, where: str) -> np.ndarray:
        rec = self._records.get(name.upper())
        if rec is None:
            raise UnsupportedScheduleError(f"{where}: day schedule '{name}' is not defined.")
        obj: IdfObject = rec["_object"]
        if obj.key == "SCHEDULE:DAY:INTERVAL":
            pairs = rec["time_value_pairs"]
            untils = [_parse_time(t, obj.where()) for t, *_ in pairs]
            values = [_field_float(v[0] if v else "0", obj, "value") for _, *v in pairs]
            kind = interpolation_kind(rec["interpolate_to_timestep"], obj.where())
            return interval_profile(untils, values, obj.where(), kind)
        if obj.key == "SCHEDULE:DAY:LIST":
            values = [_field_float(v[0], obj, "value") for v in rec["values"]]
            kind = interpolation_kind(rec["interpolate_to_timestep"], obj.where())
            minutes = int(_number(rec, "minutes_per_item", default=60.0))
            return list_profile(values, minutes, obj.where(), kind)
        if obj.key == "SCHEDULE:DAY:HOURLY":
            values = [float(v[0]) for v in rec["hourly_values"]]
            if len(values) != 24:
                raise ThermocalInputError(f"{obj.where()}: needs 24 hourly values.")
            return np.repeat(values, 60)
        raise UnsupportedScheduleError(f"{where}: '{name}' is not a day schedule.")

    def _year(self, rec: dict) -> np.ndarray:
        obj: IdfObject = rec["_object"]
        where = obj.where()
        out = np.full((self.n_days, _MINUTES_PER_DAY), np.nan)
        average = self._average_days[obj.name.upper()] = np.zeros(self.n_days, dtype=bool)
        for group in rec["week_periods"]:
            if len(group) < 5:
                raise ThermocalInputError(f"{where}: incomplete week period {group}.")
            week_name, m1, d1, m2, d2 = group[:5]
            start = self._doy(int(float(m1)), int(float(d1)), where)
            end = self._doy(int(float(m2)), int(float(d2)), where)
            profiles = self._week(week_name, where)
            for d in range(start, end + 1):
                out[d] = profiles[int(self._day_type[d])]
                average[d] = getattr(profiles[int(self._day_type[d])], "average", False)
        if np.isnan(out).any():
            raise ThermocalInputError(f"{where}: the week periods do not cover the whole year.")
        return out

    def _week(self, week_name: str, where: str) -> list[np.ndarray]:
        """Day profiles of a week schedule, one per day type (:data:`DAY_TYPES` order)."""
        week = self._records.get(week_name.upper())
        kind = week["_object"].key if week is not None else ""
        if kind == "SCHEDULE:WEEK:DAILY":
            wwhere = week["_object"].where()
            names = SCHEMA["SCHEDULE:WEEK:DAILY"][0][1:]
            cache: dict[str, np.ndarray] = {}
            profiles = []
            for n in names:
                day_name = week[n]
                if not day_name:
                    raise ThermocalInputError(
                        f"{wwhere}: field '{_label(n)} Schedule:Day Name' is blank."
                    )
                if day_name.upper() not in cache:
                    cache[day_name.upper()] = self._day_object(day_name, wwhere)
                profiles.append(cache[day_name.upper()])
            return profiles
        if kind == "SCHEDULE:WEEK:COMPACT":
            wwhere = week["_object"].where()
            assigned: dict[int, np.ndarray] = {}
            for group in week["day_rules"]:
                if len(group) < 2 or not group[1]:
                    raise ThermocalInputError(
                        f"{wwhere}: day type list '{group[0]}' has no Schedule:Day name."
                    )
                text = group[0]
                head, colon, rest = text.partition(":")
                if colon and head.strip().upper() == "FOR":
                    text = rest
                profile = self._day_object(group[1], wwhere)
                for t in self._day_types(text, assigned, wwhere):
                    assigned.setdefault(t, profile)
            missing = [DAY_TYPES[i].title() for i in range(len(DAY_TYPES)) if i not in assigned]
            if missing:
                raise ThermocalInputError(
                    f"{wwhere}: no day type list covers {', '.join(missing)}; add AllOtherDays."
                )
            return [assigned[i] for i in range(len(DAY_TYPES))]
        raise UnsupportedScheduleError(
            f"{where}: week schedule '{week_name}' is not a Schedule:Week:Daily or "
            "Schedule:Week:Compact."
        )

    def _file(self, rec: dict) -> np.ndarray:
        obj: IdfObject = rec["_object"]
        where = obj.where()
        name = rec["file_name"]
        if not name:
            raise ThermocalInputError(f"{where}: field 'File Name' is blank.")
        path = Path(name)
        if not path.is_absolute():
            path = self.base_dir / path
        kind = interpolation_kind(rec["interpolate_to_timestep"], where)
        self._average_days[obj.name.upper()] = np.full(self.n_days, kind == "average")
        return file_profile(
            path,
            column=int(_number(rec, "column_number")),
            rows_to_skip=int(_number(rec, "rows_to_skip_at_top", default=0.0)),
            separator=rec["column_separator"],
            minutes_per_item=int(_number(rec, "minutes_per_item", default=60.0)),
            n_days=self.n_days,
            leap=calendar.isleap(self.year),
            kind=kind,
            where=where,
        )


#: Reference wind speed [m/s] at which the wind terms of ZoneInfiltration:DesignFlowRate are
#: evaluated when converting to a constant air-change rate: 4.47 m/s (10 mph), the speed at which

# ------------------------------------------------------------------------------------------------
# Calendar and profile helpers (pure functions)
# ------------------------------------------------------------------------------------------------

MINUTES_PER_DAY = 1440

#: Interpolation kinds of ``Interpolate to Timestep`` (Schedule:Day:Interval/List, Schedule:File)
#: and of ``Interpolate:`` in Schedule:Compact. ``Yes`` is the pre-9.0 spelling of ``Average``.
INTERPOLATION_KINDS = {"NO": "no", "AVERAGE": "average", "YES": "average", "LINEAR": "linear"}

_WEEKDAYS = ("MONDAY", "TUESDAY", "WEDNESDAY", "THURSDAY", "FRIDAY", "SATURDAY", "SUNDAY")
_MONTHS = {name.upper(): i for i, name in enumerate(calendar.month_name) if name} | {
    name.upper(): i for i, name in enumerate(calendar.month_abbr) if name
}


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


class DateSpec(NamedTuple):
    """A date of EnergyPlus' date fields, before it is placed in a year.

    ``kind``: ``"monthday"`` (``month``/``day``), ``"nth"`` (the ``day``-th ``weekday`` of
    ``month``) or ``"last"`` (the last ``weekday`` of ``month``); ``weekday`` 0 = Monday .. 6 =
    Sunday (-1 for ``"monthday"``).
    """

    kind: str
    month: int
    day: int
    weekday: int = -1


_DATE_FORMS = (
    "'7/4', 'July 4', '4 Jul', '1st Monday in September', '4 Thursday in November', "
    "'Last Monday in May'"
)
_END_OF_MONTH = (31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31)


def parse_date(text: str, where: str, field: str = "Start Date") -> DateSpec:
    """A date field as EnergyPlus reads it (``RunPeriodControl:SpecialDays``, the EPW
    ``HOLIDAYS/DAYLIGHT SAVINGS`` line).

    Forms accepted, as EnergyPlus' ``ProcessDateString``: month/day with ``/``, ``-`` or ``:``
    (``7/4``, ``7-4``, a trailing or leading year ignored: ``7/4/2006``, ``2006/7/4``), a month
    name or its first three letters before or after the day (``July 4``, ``4 Jul``), the n-th
    (1-5, with or without ``st``/``nd``/``rd``/``th``) or ``Last`` weekday ``in`` / ``of`` a month
    (``3rd Monday in January``, ``4 Thursday in November``, ``Last Monday in May``, the weekday
    and month in either order), and a day of the year (``185``, in a common year).
    """
    words = text.upper().replace("/", " ").replace("-", " ").replace(":", " ").split()
    in_month = False
    tokens: list[str] = []
    for word in words:
        if word in ("IN", "OF"):
            in_month = True
        elif word == "LAST":
            tokens.append(word)
            in_month = True
        elif len(word) > 2 and word[:-2].isdigit() and word[-2:] in ("ST", "ND", "RD", "TH"):
            tokens.append(word[:-2])
            in_month = True
        else:
            tokens.append(word)

    def month_of(word: str) -> int:
        return _MONTHS.get(word[:3], 0) if len(word) >= 3 else 0

    def weekday_of(word: str) -> int:
        return next(
            (i for i, w in enumerate(_WEEKDAYS) if len(word) >= 3 and w[:3] == word[:3]), -1
        )

    def month_day(month: int, day: int) -> DateSpec | None:
        if 1 <= month <= 12 and 1 <= day <= _END_OF_MONTH[month - 1]:
            return DateSpec("monthday", month, day)
        return None

    spec: DateSpec | None = None
    if len(tokens) == 1 and tokens[0].isdigit() and not in_month:
        n = int(tokens[0])
        if 1 <= n <= 365:
            d = _dt.date(2006, 1, 1) + _dt.timedelta(days=n - 1)
            spec = DateSpec("monthday", d.month, d.day)
    elif len(tokens) == 2:
        a, b = tokens
        if a.isdigit() and b.isdigit():
            spec = month_day(int(a), int(b))
        elif b.isdigit():
            spec = month_day(month_of(a), int(b))
        elif a.isdigit():
            spec = month_day(month_of(b), int(a))
    elif len(tokens) == 3 and in_month:
        first, second, third = tokens
        weekday, month = weekday_of(second), month_of(third)
        if weekday < 0:
            weekday, month = weekday_of(third), month_of(second)
        if weekday >= 0 and month:
            if first.isdigit() and 1 <= int(first) <= 5:
                spec = DateSpec("nth", month, int(first), weekday)
            elif first == "LAST":
                spec = DateSpec("last", month, 0, weekday)
    elif len(tokens) == 3 and all(t.isdigit() for t in tokens):
        a, b, c = (int(t) for t in tokens)
        spec = month_day(b, c) if a > 100 else month_day(a, b) if c > 100 else None
    if spec is None:
        raise ThermocalInputError(
            f"{where}: field '{field}' = '{text}' is not a date EnergyPlus accepts ({_DATE_FORMS})."
        )
    return spec


def resolve_date(spec: DateSpec, year: int, where: str, field: str = "Start Date") -> _dt.date:
    """The date of ``spec`` in ``year`` (February 29 of a common year: March 1, as EnergyPlus'
    ordinal day)."""
    if spec.kind == "monthday":
        if spec.month == 2 and spec.day == 29 and not calendar.isleap(year):
            return _dt.date(year, 3, 1)
        return _dt.date(year, spec.month, spec.day)
    days = [
        d
        for d in range(1, calendar.monthrange(year, spec.month)[1] + 1)
        if _dt.date(year, spec.month, d).weekday() == spec.weekday
    ]
    if spec.kind == "last":
        return _dt.date(year, spec.month, days[-1])
    if spec.day > len(days):
        raise ThermocalInputError(
            f"{where}: field '{field}': {calendar.month_name[spec.month]} {year} has no "
            f"{spec.day}th {calendar.day_name[spec.weekday]} (not enough Nths)."
        )
    return _dt.date(year, spec.month, days[spec.day - 1])


def special_day(text: str, year: int, where: str) -> _dt.date:
    """Date of a ``RunPeriodControl:SpecialDays`` ``Start Date`` in ``year`` (see
    :func:`parse_date` for the forms accepted)."""
    return resolve_date(parse_date(text, where), year, where)


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
