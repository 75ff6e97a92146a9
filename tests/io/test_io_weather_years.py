"""Weather years (issue 28): a typical-year file follows the year of the measurements, an
actual-year file must cover the period."""

from __future__ import annotations

import functools

import numpy as np
import pandas as pd
import pytest

from conftest import shared_data_path
from thermocal.errors import ThermocalInputError
from thermocal.io.weather import read_weather, weather_for_period


@functools.cache
def _tmy():
    return read_weather(shared_data_path("ashrae140_bestest", "725650TYCST.epw"))


def test_typical_year_follows_the_measurement_year():
    weather, meta = _tmy()
    assert meta["coerced_year"] == 2023  # the file's own placement (EnergyPlus' weekday)
    out, info = weather_for_period(weather, meta, "2013-03-04", "2013-03-18")
    assert out.index[0] == pd.Timestamp("2013-01-01", tz=weather.index.tz)
    steps = out.index.to_series().diff().iloc[1:]
    assert len(out) == 8760 and (steps == pd.Timedelta("1h")).all()
    # every row keeps its month, day and hour: 5 March 12:00 of the file is 5 March 2013 12:00
    row = weather.index[(weather.index.month == 3) & (weather.index.day == 5)][12]
    stamp = pd.Timestamp("2013-03-05 12:00", tz=weather.index.tz)
    pd.testing.assert_series_equal(out.loc[stamp], weather.loc[row], check_names=False)
    # weekdays are the measurement year's: 5 March 2013 a Tuesday (a Sunday in the file's 2023)
    assert stamp.day_name() == "Tuesday" and row.day_name() == "Sunday"
    year = info["weather_year"]
    assert year["kind"] == "typical" and year["years"] == [2013] and year["file_year"] == 2023
    assert "725650TYCST.epw put on 2013" in year["statement"]
    assert "1 January 2013 a Tuesday" in year["statement"]
    assert info["coerced_year"] == 2013


def test_typical_year_across_new_year_and_in_a_leap_year():
    weather, meta = _tmy()
    out, info = weather_for_period(weather, meta, "2015-12-20", "2016-03-10")
    assert info["weather_year"]["years"] == [2015, 2016]
    steps = out.index.to_series().diff().iloc[1:]
    assert len(out) == 8760 + 8784 and (steps == pd.Timedelta("1h")).all()
    tz = weather.index.tz
    feb29 = out.loc[pd.Timestamp("2016-02-29", tz=tz) : pd.Timestamp("2016-02-29 23:00", tz=tz)]
    feb28 = out.loc[pd.Timestamp("2016-02-28", tz=tz) : pd.Timestamp("2016-02-28 23:00", tz=tz)]
    np.testing.assert_array_equal(feb29.to_numpy(), feb28.to_numpy())
    assert "29 February repeats 28 February" in info["weather_year"]["statement"]
    # the new year continues the file's cycle: 31 December 23:00 -> 1 January 00:00
    last = out.loc[pd.Timestamp("2015-12-31 23:00", tz=tz), "ghi"]
    first = out.loc[pd.Timestamp("2016-01-01 00:00", tz=tz), "ghi"]
    assert last == weather["ghi"].iloc[-1] and first == weather["ghi"].iloc[0]


def test_actual_year_must_cover_the_period():
    weather, meta = read_weather(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"))
    assert meta["coerced_year"] is None
    out, info = weather_for_period(weather, meta, "2015-02-01", "2015-02-10")
    assert out is weather and info["weather_year"]["kind"] == "actual"
    with pytest.raises(ThermocalInputError) as caught:
        weather_for_period(weather, meta, "2013-02-01", "2013-02-10")
    message = str(caught.value)
    assert "Zuerich-SMA_2015.epw" in message and "actual-year file of 2015" in message
    assert "[2013-02-01 00:00:00+01:00, 2013-02-10 00:00:00+01:00)" in message
    assert "typical-year file" in message  # what to do


def _first_lines(source, target, days: int):
    """The 8 header lines and the first ``days`` days of hourly rows of an EPW file."""
    lines = source.read_text().splitlines(keepends=True)
    target.write_text("".join(lines[: 8 + 24 * days]))
    return target


def test_a_truncated_typical_year_is_said_to_be_truncated_not_an_actual_year(tmp_path):
    """Before: the first 10 days of a TMY (all from 1995, so read as an actual year) were
    called "an actual-year file of 1995" that does not cover the period; the header declares
    1/1 to 12/31, so the file is cut short: say so, with its rows and dates."""
    path = _first_lines(
        shared_data_path("ashrae140_bestest", "725650TYCST.epw"), tmp_path / "w.epw", 10
    )
    weather, meta = read_weather(path)
    with pytest.raises(ThermocalInputError) as caught:
        weather_for_period(weather, meta, "2023-01-02", "2023-01-09", source="w.epw")
    message = str(caught.value)
    assert "actual-year file" not in message
    assert "w.epw" in message and "truncated or incomplete" in message
    assert "DATA PERIODS line declares data from 1/1 to 12/31" in message
    assert "240 hourly rows (10 days) from 1995-01-01 00:00 to 1995-01-10 23:00" in message
    assert "complete file" in message
    # a complete actual year (Zurich 2015) keeps its message: test_actual_year_must_cover...


def test_annual_results_need_one_whole_year_of_weather(tmp_path):
    """check_full_year: a typical year and an actual year pass; half a TMY is refused with its
    rows, dates and the header's declared period; several years are refused too."""
    from thermocal.io.weather import check_full_year

    check_full_year(*_tmy(), source="tmy.epw")
    check_full_year(
        *read_weather(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")), source="z"
    )
    path = _first_lines(
        shared_data_path("ashrae140_bestest", "725650TYCST.epw"), tmp_path / "half.epw", 181
    )
    with pytest.raises(ThermocalInputError) as caught:
        check_full_year(*read_weather(path), source="half.epw")
    message = str(caught.value)
    assert "half.epw" in message and "one whole year" in message and "8,760 hours" in message
    assert "4,344 hourly rows (181 days) from 1 January 00:00 to 30 June 23:00" in message
    assert "truncated" in message and "declares data from 1/1 to 12/31" in message
    weather, meta = _tmy()
    two = pd.concat([weather, weather.set_axis(weather.index + pd.DateOffset(years=1))])
    with pytest.raises(ThermocalInputError, match="17,520 hourly rows.*one year of it"):
        check_full_year(two, {**meta, "coerced_year": None, "data_period": None}, source="2y")
