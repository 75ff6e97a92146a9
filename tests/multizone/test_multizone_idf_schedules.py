"""IDF schedule evaluation against hand-computed values: Schedule:Week:Compact, Schedule:Day:List,
Interpolate (Linear / Average), Schedule:File, RunPeriodControl:SpecialDays and the RunPeriod's
Day of Week for Start Day."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
from test_multizone_idf import BOX

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import IdfImportWarning, ScheduleEvaluator, parse_idf, read_idf


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


def test_weather_file_holidays_and_weekend_rule_are_listed_as_approximations(tmp_path):
    notes = _box_with_run_period(tmp_path, "1,1,,12,31,,,Yes,No,Yes,Yes,Yes").idf_info.notes
    assert any("weather file's holidays are not read" in n for n in notes)
    assert any("'Apply Weekend Holiday Rule' = Yes is not applied" in n for n in notes)
    notes = _box_with_run_period(tmp_path, "1,1,,12,31,,,No,No,No,Yes,Yes").idf_info.notes
    assert not any("holiday" in n.lower() for n in notes)
