"""IDF schedule evaluation against hand-computed values: Schedule:Week:Compact, Schedule:Day:List,
Interpolate (Linear / Average), Schedule:File, RunPeriodControl:SpecialDays and the RunPeriod's
Day of Week for Start Day."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pandas as pd
import pytest
from test_multizone_idf import BOX

from conftest import requires_energyplus
from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import IdfImportWarning, ScheduleEvaluator, parse_idf, read_idf
from thermocal.multizone.idf.schedules import parse_date, resolve_date


def _evaluator(text, **kwargs):
    return ScheduleEvaluator(parse_idf(text), year=2006, **kwargs)  # Jan 1 2006: a Sunday


def test_week_compact_and_day_list():
    values = ",".join(str(i) for i in range(48))
    text = f"""
    Schedule:Day:List,DL,Any,No,30,{values};
    Schedule:Day:Hourly,DH,Any,{",".join(["5"] * 24)};
    Schedule:Week:Compact,WC,For: Weekdays,DL,AllOtherDays,DH;
    Schedule:Year,Y,Any,WC,1,1,12,31;
    """
    hourly = _evaluator(text).hourly("Y")
    assert hourly[:24].tolist() == [5.0] * 24  # Sunday
    assert hourly[24:48].tolist() == [2 * h + 0.5 for h in range(24)]  # Monday: DL
    assert hourly[6 * 24 : 7 * 24].tolist() == [5.0] * 24  # Saturday


def test_day_list_and_week_compact_errors():
    bad_count = "Schedule:Day:List,DL,Any,No,30,1,2,3;Schedule:Year,Y,Any,WC,1,1,12,31;"
    bad_count += "Schedule:Week:Compact,WC,AllDays,DL;"
    with pytest.raises(ThermocalInputError, match=r"Schedule:Day:List 'DL'.*3 values given, 48"):
        _evaluator(bad_count).minutes("Y")
    uncovered = """
    Schedule:Day:Hourly,DH,Any,{h};
    Schedule:Week:Compact,WC,Weekdays,DH;
    Schedule:Year,Y,Any,WC,1,1,12,31;
    """.format(h=",".join(["1"] * 24))
    with pytest.raises(ThermocalInputError, match=r"Schedule:Week:Compact 'WC'.*Sunday"):
        _evaluator(uncovered).minutes("Y")


def test_linear_interpolation_in_day_interval_and_compact():
    text = """
    Schedule:Day:Interval,DI,Any,Linear,06:00,0,08:00,10,24:00,10;
    Schedule:Day:Interval,DA,Any,Average,06:00,0,08:00,10,24:00,10;
    Schedule:Week:Daily,W,DI,DI,DI,DI,DI,DI,DI,DI,DI,DI,DI,DI;
    Schedule:Week:Daily,WA,DA,DA,DA,DA,DA,DA,DA,DA,DA,DA,DA,DA;
    Schedule:Year,Y,Any,W,1,1,12,31;
    Schedule:Year,YA,Any,WA,1,1,12,31;
    Schedule:Compact,C,Any,Through: 12/31,For: AllDays,Interpolate: Linear,
      Until: 12:00,0,Until: 24:00,24;
    """
    ev = _evaluator(text)
    hourly = ev.hourly("Y")
    # 06:00-08:00 ramps 0 -> 10 over 120 minutes, minute i holding 10 (i + 1) / 120
    assert hourly[:6].tolist() == [0.0] * 6
    assert hourly[6] == pytest.approx(10 * 30.5 / 120)
    assert hourly[7] == pytest.approx(10 * 90.5 / 120)
    assert hourly[8:24].tolist() == [10.0] * 16
    times = pd.date_range("2006-01-02 06:00", periods=2, freq="15min")
    # EnergyPlus gives a step of a Linear day the value at the step's end
    assert ev.on_grid("Y", times, pd.Timedelta("15min")) == pytest.approx([1.25, 2.5])
    assert ev.on_grid("YA", times, pd.Timedelta("15min")) == pytest.approx([10.0, 10.0])
    # Average holds each value over its interval (the step mean)
    assert ev.hourly("YA")[:24].tolist() == [0.0] * 6 + [10.0] * 18
    compact = ev.hourly("C")
    assert compact[:12].tolist() == [0.0] * 12  # the first interval holds its value
    assert compact[12] == pytest.approx(24 * 30.5 / 720)
    assert compact[23] == pytest.approx(24 * (11 * 60 + 30.5) / 720)
    # Until times inside a step: No -> the value at the step's end, Average -> the step mean
    inside = """
    Schedule:Compact,N,Any,Through: 12/31,For: AllDays,Until: 06:10,0,Until: 24:00,12;
    Schedule:Compact,A,Any,Through: 12/31,For: AllDays,Interpolate: Average,
      Until: 06:10,0,Until: 24:00,12;
    """
    ev = _evaluator(inside)
    step = pd.date_range("2006-01-02 06:00", periods=1, freq="15min")
    assert ev.on_grid("N", step, pd.Timedelta("15min")) == pytest.approx([12.0])
    assert ev.on_grid("A", step, pd.Timedelta("15min")) == pytest.approx([12.0 * 5 / 15])
    bad = "Schedule:Compact,C,Any,Through: 12/31,For: AllDays,Interpolate: Maybe,Until: 24:00,1;"
    with pytest.raises(ThermocalInputError, match=r"Schedule:Compact 'C'.*'Interpolate: Maybe'"):
        _evaluator(bad).minutes("C")


def _csv(path, rows, *, header="hour;value", sep=";"):
    path.write_text(header + "\n" + "\n".join(f"{i}{sep}{v}" for i, v in enumerate(rows)) + "\n")


def test_schedule_file_column_rows_minutes_and_separator(tmp_path):
    _csv(tmp_path / "hourly.csv", [i % 24 for i in range(8760)])
    _csv(tmp_path / "half.csv", [i % 48 for i in range(17520)], sep="\t", header="a\tb")
    _csv(tmp_path / "leap.csv", [i // 24 for i in range(8784)])
    _csv(tmp_path / "short.csv", [1.0] * 100)
    text = """
    Schedule:File,F1,Any,hourly.csv,2,1,8760,Semicolon,No,60;
    Schedule:File,F2,Any,half.csv,2,1,8760,Tab,No,30;
    Schedule:File,F3,Any,leap.csv,2,1,8784,Semicolon,No,60;
    Schedule:File,F4,Any,hourly.csv,2,1,8760,Semicolon,Linear,60;
    Schedule:File,F5,Any,short.csv,2,1,8760,Semicolon,No,60;
    Schedule:File,F6,Any,hourly.csv,2,1,8760,Pipe,No,60;
    """
    ev = _evaluator(text, base_dir=tmp_path)
    assert ev.hourly("F1")[:48].tolist() == list(range(24)) * 2
    assert ev.hourly("F2")[:24].tolist() == [2 * h + 0.5 for h in range(24)]
    days = ev.hourly("F3").reshape(365, 24)[:, 0]
    assert days[58] == 58 and days[59] == 60  # Feb 29 of the leap-year file dropped
    # Linear: hour 1 ramps from 0 to 1 over its 60 minutes (mean 30.5 / 60)
    assert ev.hourly("F4")[1] == pytest.approx(30.5 / 60)
    with pytest.raises(ThermocalInputError, match=r"Schedule:File 'F5'.*100 values.*8760 needed"):
        ev.minutes("F5")
    with pytest.raises(ThermocalInputError, match=r"Schedule:File 'F6'.*'Column Separator'"):
        ev.minutes("F6")


def test_special_days_replace_the_weekday():
    text = """
    RunPeriodControl:SpecialDays,Independence,July 4,1,Holiday;
    RunPeriodControl:SpecialDays,Labor,1st Monday in September,1,Holiday;
    RunPeriodControl:SpecialDays,Memorial,Last Monday in May,1,Holiday;
    RunPeriodControl:SpecialDays,Xmas,12/25,2,CustomDay1;
    Schedule:Compact,C,Any,Through: 12/31,For: Weekdays,Until: 24:00,1,
      For: Holidays,Until: 24:00,2,For: CustomDay1,Until: 24:00,3,
      For: AllOtherDays,Until: 24:00,0;
    Schedule:Day:Hourly,D1,Any,{one};
    Schedule:Day:Hourly,D9,Any,{nine};
    Schedule:Week:Daily,W,D1,D1,D1,D1,D1,D1,D1,D9,D1,D1,D1,D1;
    Schedule:Year,Y,Any,W,1,1,12,31;
    """.format(one=",".join(["1"] * 24), nine=",".join(["9"] * 24))
    ev = _evaluator(text)
    daily = ev.minutes("C")[:, 0]
    doy = {
        d: (pd.Timestamp(d) - pd.Timestamp("2006-01-01")).days
        for d in (
            "2006-07-03",
            "2006-07-04",
            "2006-09-04",
            "2006-05-29",
            "2006-12-25",
            "2006-12-26",
            "2006-12-27",
            "2006-07-08",
        )
    }
    assert daily[doy["2006-07-03"]] == 1  # Monday
    assert daily[doy["2006-07-04"]] == 2  # Tuesday, a holiday
    assert daily[doy["2006-09-04"]] == 2 and daily[doy["2006-05-29"]] == 2
    assert daily[doy["2006-12-25"]] == 3 and daily[doy["2006-12-26"]] == 3
    assert daily[doy["2006-12-27"]] == 1 and daily[doy["2006-07-08"]] == 0  # Wed, Saturday
    year = ev.minutes("Y")[:, 0]
    assert year[doy["2006-07-04"]] == 9 and year[doy["2006-07-03"]] == 1
    assert (daily == 2).sum() == 3 and ev.special_days[doy["2006-07-04"]] == "HOLIDAY"


@pytest.mark.parametrize(
    ("line", "match"),
    [
        ("RunPeriodControl:SpecialDays,H,Someday,1,Holiday;", r"'H'.*'Start Date' = 'Someday'"),
        ("RunPeriodControl:SpecialDays,H,1/1,1,Festival;", r"'H'.*'Special Day Type' = 'Festival'"),
        ("RunPeriodControl:SpecialDays,H,1/1,0,Holiday;", r"'H'.*'Duration' = 0"),
    ],
)
def test_special_day_errors(line, match):
    with pytest.raises(ThermocalInputError, match=match):
        _evaluator(line)


def _box_with_run_period(tmp_path, fields):
    path = tmp_path / "box.idf"
    extra = f"RunPeriod,R,{fields};"
    path.write_text(
        BOX.format(extra=extra, north=0, zone_north=0, ox=0, oy=0, volume="autocalculate")
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        return read_idf(path)


@pytest.mark.parametrize(
    ("fields", "year"),
    [
        ("1,1,,12,31,,Wednesday,No,No,No,Yes,Yes", 2014),  # Jan 1 2014: a Wednesday
        ("7,1,,12,31,,,No,No,No,Yes,Yes", 2007),  # blank: Sunday; July 1 2007 is one
        ("1,1,2009,12,31,2009,Thursday,No,No,No,Yes,Yes", 2009),  # the year wins
    ],
)
def test_run_period_day_of_week_for_start_day(tmp_path, fields, year):
    building = _box_with_run_period(tmp_path, fields)
    schedules = building.idf_info.schedules
    assert schedules.year == year
    weekday = np.asarray(schedules._day_type)
    assert weekday.size == 365


def test_run_period_bad_start_day(tmp_path):
    with pytest.raises(ThermocalInputError, match=r"RunPeriod 'R'.*'Day of Week for Start Day'"):
        _box_with_run_period(tmp_path, "1,1,,12,31,,Someday,No,No,No,Yes,Yes")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("1/1", "2006-01-01"),
        ("Jan 1", "2006-01-01"),
        ("1 Jan", "2006-01-01"),
        ("January 1", "2006-01-01"),
        ("7-4", "2006-07-04"),
        ("7/4/2006", "2006-07-04"),
        ("185", "2006-07-04"),  # day of the year
        ("Last Monday in May", "2006-05-29"),
        ("3rd Monday in January", "2006-01-16"),  # Mondays 2, 9, 16
        ("4 Thursday in November", "2006-11-23"),  # Nov 1 a Wednesday: Thursdays 2, 9, 16, 23
        ("1st Sunday of April", "2006-04-02"),
        ("last sun in oct", "2006-10-29"),
        ("2nd March Sunday", "2006-03-12"),  # weekday and month in either order
    ],
)
def test_energyplus_date_forms(text, expected):
    spec = parse_date(text, "here")
    assert resolve_date(spec, 2006, "here") == pd.Timestamp(expected).date()


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("Someday", r"here: field 'Start Date' = 'Someday' is not a date"),
        ("13/1", "'13/1' is not a date"),
        ("2/30", "'2/30' is not a date"),
        ("4 Thursday November", "is not a date"),  # no 'in' / 'of' / ordinal suffix
        ("6th Monday in May", "is not a date"),
        ("5th Monday in February", r"February 2006 has no 5th Monday"),
    ],
)
def test_energyplus_date_errors(text, match):
    with pytest.raises(ThermocalInputError, match=match):
        resolve_date(parse_date(text, "here"), 2006, "here")


HOLIDAY_SCHEDULE = """
Schedule:Compact,C,Any,Through: 12/31,For: Weekdays,Until: 24:00,1,
  For: Holidays,Until: 24:00,2,For: AllOtherDays,Until: 24:00,0;
"""


def _doy(date):
    return (pd.Timestamp(date) - pd.Timestamp("2006-01-01")).days


def test_weather_file_holidays_take_the_holiday_day_type():
    holidays = [("New Year", "1/1"), ("Thanksgiving", "4 Thursday in November"), ("Ind", "Jul 4")]
    notes: list[str] = []
    ev = _evaluator(HOLIDAY_SCHEDULE, notes=notes)
    daily = ev.minutes("C")[:, 0]
    assert daily[_doy("2006-11-23")] == 1 and daily[_doy("2006-01-01")] == 0
    ev.set_weather_calendar(holidays, None, "x.epw")
    daily = ev.minutes("C")[:, 0]  # recomputed
    assert daily[_doy("2006-01-01")] == 2  # Sunday, a holiday
    assert daily[_doy("2006-11-23")] == 2 and daily[_doy("2006-07-04")] == 2
    assert daily[_doy("2006-11-22")] == 1 and daily[_doy("2006-11-25")] == 0  # Wed, Sat
    assert (daily == 2).sum() == 3
    step = pd.date_range("2006-11-23 10:00", periods=1, freq="15min")
    assert ev.on_grid("C", step, pd.Timedelta("15min")) == pytest.approx([2.0])
    assert notes == ["schedule calendar: 3 holiday(s) from the weather file"]
    # 'Use Weather File Holidays and Special Days' = No: the weekday
    off = _evaluator(HOLIDAY_SCHEDULE, weather_holidays=False, notes=notes)
    off.set_weather_calendar(holidays, None, "x.epw")
    assert off.minutes("C")[_doy("2006-11-23"), 0] == 1 and off.special_days == {}
    assert "the weather file's 3 holiday(s) not used" in notes[-1]
    with pytest.raises(ThermocalInputError, match=r"x.epw.*holiday 'Bad'.*'Someday'"):
        ev.set_weather_calendar([("Bad", "Someday")], None, "x.epw")


def test_weekend_holiday_rule_moves_to_monday():
    # 2006: Jan 1 a Sunday, Nov 11 a Saturday, Dec 25 a Monday
    text = HOLIDAY_SCHEDULE + "RunPeriodControl:SpecialDays,Vet,11/11,1,Holiday;"
    holidays = [("New Year", "1/1"), ("Memorial", "Last Monday in May"), ("Xmas", "Dec 25")]
    notes: list[str] = []
    ev = _evaluator(text, weekend_rule=True, notes=notes)
    ev.set_weather_calendar(holidays, None, "x.epw")
    daily = ev.minutes("C")[:, 0]
    assert daily[_doy("2006-01-01")] == 0 and daily[_doy("2006-01-02")] == 2  # Sunday -> Monday
    assert daily[_doy("2006-11-11")] == 0 and daily[_doy("2006-11-12")] == 0  # Saturday ->
    assert daily[_doy("2006-11-13")] == 2  # the Monday after (an IDF special day too)
    assert daily[_doy("2006-12-25")] == 2 and daily[_doy("2006-05-29")] == 2
    assert (daily == 2).sum() == 4
    assert "'Apply Weekend Holiday Rule' = Yes: 2 special day(s)" in notes[-1]
    ev = _evaluator(text)  # the rule off (EnergyPlus' default)
    ev.set_weather_calendar(holidays, None, "x.epw")
    daily = ev.minutes("C")[:, 0]
    assert daily[_doy("2006-01-01")] == 2 and daily[_doy("2006-01-02")] == 1
    assert daily[_doy("2006-11-11")] == 2 and daily[_doy("2006-11-13")] == 1


DST_SCHEDULE = """
Schedule:Compact,U,Any,Through: 12/31,For: AllDays,Until: 08:00,0,Until: 24:00,1;
Schedule:Compact,W,Any,Through: 12/31,For: Weekdays,Until: 24:00,1,For: AllOtherDays,
  Until: 24:00,0;
"""


def _steps(day, *hhmm):
    return pd.DatetimeIndex([pd.Timestamp(f"{day} {t}") for t in hhmm])


def test_daylight_saving_shifts_schedules_by_one_hour():
    step = pd.Timedelta("15min")
    notes: list[str] = []
    ev = _evaluator(DST_SCHEDULE, notes=notes)
    ev.set_weather_calendar([], ("4/2", "Last Sunday in October"), "x.epw")  # Apr 2 - Oct 29
    times = ("06:45", "07:00", "07:45", "08:00")
    # inside the period: 'Until: 08:00' ends at 07:00 standard time
    for day in ("2006-06-01", "2006-04-02", "2006-10-29"):
        assert ev.on_grid("U", _steps(day, *times), step).tolist() == [0, 1, 1, 1], day
    for day in ("2006-01-10", "2006-04-01", "2006-10-30"):
        assert ev.on_grid("U", _steps(day, *times), step).tolist() == [0, 0, 0, 1], day
    # 23:00 standard on Friday June 2 is Saturday 00:00 daylight time: Saturday's values
    friday = _steps("2006-06-02", "22:45", "23:00")
    assert ev.on_grid("W", friday, step).tolist() == [1, 0]
    assert "daylight saving time 4/2 to 10/29 (weather file x.epw)" in notes[-1]
    # 'Use Weather File Daylight Saving Period' = No: no shift
    off = _evaluator(DST_SCHEDULE, weather_daylight_saving=False)
    off.set_weather_calendar([], ("4/2", "10/29"), "x.epw")
    assert off.on_grid("U", _steps("2006-06-01", *times), step).tolist() == [0, 0, 0, 1]
    # southern hemisphere: over the new year
    south = _evaluator(DST_SCHEDULE)
    south.set_weather_calendar([], ("10/1", "Last Sunday in March"), "x.epw")  # to Mar 26
    dst = south.daylight_saving
    assert dst[_doy("2006-03-26")] and dst[_doy("2006-10-01")] and dst[_doy("2006-12-31")]
    assert not dst[_doy("2006-03-27")] and not dst[_doy("2006-09-30")]


def test_daylight_saving_object_of_the_file_wins_over_the_weather_file():
    """RunPeriodControl:DaylightSavingTime applies whatever the RunPeriod says about the weather
    file's period, and replaces it (EnergyPlus' WeatherManager)."""
    step = pd.Timedelta("15min")
    text = DST_SCHEDULE + "RunPeriodControl:DaylightSavingTime,2nd Sunday in March,11/5;"
    times = ("06:45", "07:00", "07:45", "08:00")
    for weather_dst in (True, False):
        notes: list[str] = []
        ev = _evaluator(text, notes=notes, weather_daylight_saving=weather_dst)
        ev.set_weather_calendar([], ("4/2", "Last Sunday in October"), "x.epw")
        # March 12 2006 is the 2nd Sunday of March; the weather file's period starts Apr 2
        for day in ("2006-03-12", "2006-11-05"):
            assert ev.on_grid("U", _steps(day, *times), step).tolist() == [0, 1, 1, 1], day
        for day in ("2006-03-11", "2006-11-06"):
            assert ev.on_grid("U", _steps(day, *times), step).tolist() == [0, 0, 0, 1], day
        assert "daylight saving time 3/12 to 11/5" in notes[-1], notes
        assert "DaylightSavingTime" in notes[-1], notes
    with pytest.raises(ThermocalInputError, match="only one RunPeriodControl:DaylightSavingTime"):
        _evaluator(text + "RunPeriodControl:DaylightSavingTime,4/1,10/1;")
    with pytest.raises(ThermocalInputError, match="Someday"):
        _evaluator(DST_SCHEDULE + "RunPeriodControl:DaylightSavingTime,Someday,11/5;")


def test_daylight_saving_not_applied_to_schedule_file_when_asked(tmp_path):
    (tmp_path / "v.csv").write_text("".join(f"{i % 24}\n" for i in range(8760)))
    text = """
    Schedule:File,F,Any,v.csv,1,0,8760,Comma,No,60,Yes;
    Schedule:File,S,Any,v.csv,1,0,8760,Comma,No,60,No;
    """
    ev = _evaluator(text, base_dir=tmp_path)
    ev.set_weather_calendar([], ("1/1", "12/31"), "x.epw")
    times = _steps("2006-06-01", "07:00")
    assert ev.on_grid("F", times, pd.Timedelta("1h")).tolist() == [8]
    assert ev.on_grid("S", times, pd.Timedelta("1h")).tolist() == [7]


def test_run_period_calendar_fields(tmp_path):
    """'Use Weather File Holidays and Special Days', 'Use Weather File Daylight Saving Period' and
    'Apply Weekend Holiday Rule' reach the evaluator; its note goes to the import notes."""
    building = _box_with_run_period(tmp_path, "1,1,,12,31,,,Yes,Yes,Yes,Yes,Yes")
    schedules, notes = building.idf_info.schedules, building.idf_info.notes
    assert (schedules.weather_holidays, schedules.weather_daylight_saving) == (True, True)
    assert schedules.weekend_rule
    assert not any("not read" in n or "not applied" in n for n in notes)
    schedules.set_weather_calendar([("A", "1/1"), ("B", "7/4")], ("4/2", "10/29"), "w.epw")
    calendar_notes = [n for n in notes if n.startswith("schedule calendar")]
    assert len(calendar_notes) == 1
    assert "2 holiday(s) from the weather file" in calendar_notes[0]
    assert "daylight saving time 4/2 to 10/29" in calendar_notes[0]
    assert "1 special day(s) on a Saturday or Sunday" in calendar_notes[0]  # 1/1/2006: Sunday
    building = _box_with_run_period(tmp_path, "1,1,,12,31,,,No,No,No,Yes,Yes")
    schedules, notes = building.idf_info.schedules, building.idf_info.notes
    assert not (schedules.weather_holidays or schedules.weather_daylight_saving)
    assert not schedules.weekend_rule
    assert not any("holiday" in n.lower() or "calendar" in n for n in notes)
    schedules.set_weather_calendar([("A", "1/1")], ("4/2", "10/29"), "w.epw")
    assert not schedules.daylight_saving.any() and not schedules.special_days
    # blank fields: EnergyPlus' defaults (Yes, Yes, No)
    schedules = _box_with_run_period(tmp_path, "1,1,,12,31,,,,,,Yes,Yes").idf_info.schedules
    assert schedules.weather_holidays and schedules.weather_daylight_saving
    assert not schedules.weekend_rule


#: EnergyPlus comparison: the RunPeriod of Case 600FF (2009, a Thursday start) with the weather
#: file's holidays and DST period and the weekend rule; holidays on a Saturday (7/4/2009), a
#: Sunday (8 Nov 2009) and weekdays in the date forms EnergyPlus accepts
CALENDAR_HEADER = (
    "HOLIDAYS/DAYLIGHT SAVINGS,No,2nd Sunday in March,1st Sunday in November,6,"
    "New Years Day,1/1,Memorial Day,Last Monday in May,Independence Day,Jul 4,"
    "Thanksgiving,4 Thursday in November,Sunday holiday,8 Nov,Christmas,12/25"
)
CALENDAR_SCHEDULES = """
RunPeriodControl:SpecialDays,Custom,Mar 17,2,CustomDay1;
Schedule:Compact,S_DST,Any Number,Through: 12/31,For: AllDays,
  Until: 08:00,0,Until: 17:30,5,Until: 24:00,2;
Schedule:Compact,S_HOL,Any Number,Through: 12/31,For: Weekdays,Until: 08:00,1,
  Until: 24:00,4,For: Holidays Sunday,Until: 10:00,7,Until: 24:00,6,For: CustomDay1,
  Until: 12:00,9,Until: 24:00,8,For: AllOtherDays,Until: 24:00,0;
Schedule:File,S_FILE,Any Number,{csv},2,1,8760,Comma,No,60,Yes;
Schedule:File,S_FILE_STD,Any Number,{csv},2,1,8760,Comma,No,60,No;
"""


@requires_energyplus
def test_calendar_against_energyplus(tmp_path):
    """Holidays and DST of the weather file, the weekend rule, a Schedule:File with and without
    the DST adjustment: every 15-min 'Schedule Value' of the year as EnergyPlus has it."""
    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import (
        energyplus_weather_folder,
        read_eso,
        run_energyplus,
    )

    if energyplus_weather_folder() is None:
        pytest.skip("the EnergyPlus installation has no WeatherData folder")
    from conftest import shared_data_path

    case = shared_data_path("energyplus_reference", "case_600FF_v25.idf")
    chicago = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    lines = chicago.read_text().splitlines()
    assert lines[4].startswith("HOLIDAYS/DAYLIGHT SAVINGS")
    lines[4] = CALENDAR_HEADER
    epw = tmp_path / "chicago_holidays.epw"
    epw.write_text("\n".join(lines) + "\n")
    csv = tmp_path / "values.csv"
    csv.write_text(
        "hour,value\n" + "".join(f"{i},{i % 24 + (i // 24) % 7 / 10}\n" for i in range(8760))
    )
    text = case.read_text()
    run_period = (
        "  No,                                   !- Use Weather File Holidays and Special Days\n"
        "  No,                                   !- Use Weather File Daylight Saving Period\n"
        "  No,                                   !- Apply Weekend Holiday Rule\n"
    )
    assert run_period in text
    names = ("S_DST", "S_HOL", "S_FILE", "S_FILE_STD")
    idf = tmp_path / "calendar.idf"
    idf.write_text(
        text.replace(run_period, run_period.replace("No,", "Yes,"))
        + CALENDAR_SCHEDULES.format(csv=csv)
        + "".join(f"Output:Variable,{n},Schedule Value,Timestep;\n" for n in names)
    )
    reference = read_eso(
        run_energyplus(idf, epw, tmp_path / "out"), year=2009, frequency="timestep"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        building = read_idf(idf)
    _, meta = read_weather(epw)
    schedules = building.idf_info.schedules
    schedules.set_weather_calendar(meta["holidays"], meta["daylight_saving"], meta["source"])
    assert schedules.year == 2009 and schedules.weekend_rule
    # Mar 8 - Nov 1 2009; 7/4 (a Saturday) and 8 Nov (a Sunday) observed on Monday 7/6 and 11/9
    assert schedules.daylight_saving.sum() == 239
    assert sorted(schedules.special_days) == [0, 75, 76, 144, 186, 312, 329, 358]
    # EnergyPlus 25.2 gives the weather file's holidays the Sunday day type (its eio lists them
    # as 'Sunday', the Input Output Reference says Holiday, as thermocal does): S_HOL treats
    # Holidays and Sundays alike; the dates, as EnergyPlus places them, are compared here
    eio = (tmp_path / "out" / "eplusout.eio").read_text().splitlines()
    theirs = {
        (line.split(",")[1].strip(), line.split(",")[4].strip())
        for line in eio
        if line.startswith("Environment:Special Days,")
    }
    start = pd.Timestamp("2009-01-01")
    ours = {
        (name.upper(), (start + pd.Timedelta(days=d)).strftime("%m/%d"))
        for name, d in (
            ("New Years Day", 0),
            ("Memorial Day", 144),
            ("Independence Day", 186),
            ("Thanksgiving", 329),
            ("Sunday holiday", 312),
            ("Christmas", 358),
            ("Custom", 75),
        )
    }
    assert theirs == ours
    assert "Environment:Daylight Saving,Yes,WeatherFile,03/08,11/01" in eio
    for name in names:
        ours = schedules.on_grid(name, reference.index, pd.Timedelta("15min"))
        theirs = reference[f"{name}:Schedule Value []"].to_numpy()
        assert len(theirs) == 35040
        np.testing.assert_allclose(ours, theirs, atol=1e-9, err_msg=name)


def test_simulation_passes_the_weather_calendar(tmp_path):
    """Simulation(building, weather, metadata): the EPW metadata's holidays and DST period reach
    the imported building's schedules; the calendar note is among the approximations."""
    from test_multizone_network import constant_weather

    from thermocal.multizone.simulation import Simulation

    building = _box_with_run_period(tmp_path, "1,1,,12,31,,,Yes,Yes,No,Yes,Yes")
    weather, meta = constant_weather(days=2)
    Simulation(building, weather, meta, step="15min", warmup_days=0)  # no EPW calendar: none
    schedules = building.idf_info.schedules
    assert not schedules.special_days and not schedules.daylight_saving.any()
    meta = dict(meta, holidays=[("A", "1/1"), ("B", "7/4")], daylight_saving=("4/2", "10/29"))
    sim = Simulation(building, weather, meta, step="15min", warmup_days=0)
    assert set(schedules.special_days.values()) == {"HOLIDAY"} and len(schedules.special_days) == 2
    assert schedules.daylight_saving.sum() == _doy("2006-10-29") - _doy("2006-04-02") + 1
    assert any(
        line.startswith("schedule calendar: 2 holiday(s) from the weather file")
        for line in sim.approximations()
    )


def test_run_period_of_an_8x_file_has_no_begin_year(tmp_path):
    """Before 9.0 the RunPeriod reads Name, Begin Month, Begin Day, End Month, End Day, Day of
    Week for Start Day: the end month is not a year."""
    path = tmp_path / "box8.idf"
    text = BOX.format(
        extra="RunPeriod,R,3,1,5,31,Tuesday,Yes,Yes,No,Yes,Yes;",
        north=0,
        zone_north=0,
        ox=0,
        oy=0,
        volume="autocalculate",
    )
    path.write_text(re.sub(r"Version,\s*[\d.]+\s*;", "Version,8.9;", text, count=1))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        info = read_idf(path).idf_info
    # name, begin month and day, end month and day, begin and end year (neither before 9.0)
    assert info.run_period[:7] == ("R", 3, 1, 5, 31, None, None)
    assert info.schedules.year == 2006


#: Every day-type key of a ``For:`` field, singular and plural, in several cases (issue 28)
DAY_TYPE_SCHEDULES = """
RunPeriodControl:SpecialDays,Hol,1/5,1,Holiday;
RunPeriodControl:SpecialDays,Cust1,1/6,1,CustomDay1;
RunPeriodControl:SpecialDays,Cust2,1/7,1,CustomDay2;
RunPeriodControl:SpecialDays,Summer,1/8,1,SummerDesignDay;
RunPeriodControl:SpecialDays,Winter,1/9,1,WinterDesignDay;
Schedule:Compact,D_PLURAL,Any Number,Through: 12/31,For: Saturdays,Until: 24:00,6,
  For: sundays,Until: 24:00,7,For: Weekdays,Until: 24:00,1,For: Holidays,Until: 24:00,8,
  For: SummerDesignDay,Until: 24:00,9,For: WinterDesignDay,Until: 24:00,10,
  For: CustomDay1,Until: 24:00,11,For: CustomDay2,Until: 24:00,12;
Schedule:Compact,D_SINGULAR,Any Number,Through: 12/31,For: Monday Tuesday,Until: 24:00,1,
  For: WEDNESDAY,Until: 24:00,3,For: Thursday Friday,Until: 24:00,4,
  For: Weekend Holiday,Until: 24:00,5,For: AllOtherDay,Until: 24:00,2;
Schedule:Compact,D_ALL,Any Number,Through: 1/9,For: alldays,Until: 07:00,0,Until: 24:00,1,
  Through: 12/31,For: AllDay,Until: 24:00,3;
Schedule:Compact,D_OTHER,Any Number,Through: 12/31,For: Weekends,Until: 24:00,1,
  For: AllOtherDays,Until: 12:00,2,Until: 24:00,3;
"""


def test_every_for_day_type_key_parses():
    ev = _evaluator(DAY_TYPE_SCHEDULES)  # 2006: Jan 1 a Sunday
    daily = {name: ev.minutes(name)[:14, 0] for name in ("D_PLURAL", "D_SINGULAR", "D_OTHER")}
    # Jan 1 Sun .. Jan 4 Wed; 5 Holiday, 6 Custom1, 7 Custom2, 8 Summer, 9 Winter, 10 Tue ..
    assert daily["D_PLURAL"].tolist() == [7, 1, 1, 1, 8, 11, 12, 9, 10, 1, 1, 1, 1, 6]
    assert daily["D_SINGULAR"].tolist() == [5, 1, 1, 3, 5, 2, 2, 2, 2, 1, 3, 4, 4, 5]
    assert daily["D_OTHER"].tolist() == [1, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 1]
    with pytest.raises(ThermocalInputError, match=r"Schedule:Compact 'X'.*'For: Satrudays'"):
        _evaluator("Schedule:Compact,X,Any,Through: 12/31,For: Satrudays,Until: 24:00,1;").minutes(
            "X"
        )


@requires_energyplus
def test_day_types_against_energyplus(tmp_path):
    """Every 'For:' key (plural, singular, any case) and the special day types give EnergyPlus'
    'Schedule Value' at every 15-min step of a 3-week run."""
    from conftest import shared_data_path
    from thermocal.multizone.energyplus import read_eso, run_energyplus

    case = shared_data_path("energyplus_reference", "case_600FF_v25.idf")
    text = case.read_text()
    end = "  12,                                   !- End Month\n  31,"
    assert end in text
    names = ("D_PLURAL", "D_SINGULAR", "D_ALL", "D_OTHER")
    idf = tmp_path / "day_types.idf"
    idf.write_text(
        text.replace(end, "  1,\n  21,")
        + DAY_TYPE_SCHEDULES
        + "".join(f"Output:Variable,{n},Schedule Value,Timestep;\n" for n in names)
    )
    weather = shared_data_path("ashrae140_bestest", "725650TYCST.epw")
    reference = read_eso(
        run_energyplus(idf, weather, tmp_path / "out"), year=2009, frequency="timestep"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        schedules = read_idf(idf).idf_info.schedules
    assert len(reference) == 21 * 96
    for name in names:
        ours = schedules.on_grid(name, reference.index, pd.Timedelta("15min"))
        theirs = reference[f"{name}:Schedule Value []"].to_numpy()
        np.testing.assert_allclose(ours, theirs, atol=1e-9, err_msg=name)


def test_compact_keywords_without_their_colon():
    # 'For AllOtherDays' (ASHRAE 90.1 prototype apartment, exploratory test 2026-12-01):
    # EnergyPlus reads it as 'For: AllOtherDays'; thermocal refused the file
    text = """
    Schedule:Compact, S, Any, Through: 12/31, For: Weekdays, Until: 24:00, 1,
      For AllOtherDays, Until: 12:00, 2, Until: 24:00, 3;
    Schedule:Compact, T, Any, Through: 12/31, For: Weekdays, Until: 24:00, 1,
      For: AllOtherDays, Until: 12:00, 2, Until: 24:00, 3;
    """
    evaluator = _evaluator(text)
    np.testing.assert_array_equal(evaluator.hourly("S"), evaluator.hourly("T"))
    assert evaluator.hourly("S")[:24].tolist() == [2.0] * 12 + [3.0] * 12  # Sunday


def test_shadow_settings_the_model_does_not_apply_are_named(tmp_path):
    from test_multizone_idf import _box

    path = _box(tmp_path, extra="ShadowCalculation, PolygonClipping, Periodic, 20, 15000, "
                "SutherlandHodgman, 512, SimpleSkyDiffuseModeling, No, Yes, No;")  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        notes = read_idf(path).idf_info.notes
    assert any("Disable Self-Shading Within Shading Zone Groups' = Yes: NOT APPLIED" in n
               for n in notes)  # fmt: skip
    assert not any("Disable Self-Shading From" in n for n in notes)
