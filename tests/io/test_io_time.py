"""The shared time-column parser of thermocal.io (weather CSV and measurement logs)."""

from __future__ import annotations

import datetime as dt

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io._time import as_timezone, parse_time_column
from thermocal.io.measurements import read_measurements
from thermocal.io.weather import read_weather

LINES = np.array([2, 3, 4])


def _parse(values, **kwargs):
    kwargs.setdefault("lines", LINES[: len(values)])
    return parse_time_column(pd.Series(values), source="log.csv", column="time", **kwargs)


def test_offsets_across_dst_give_the_right_instants():
    times, note = _parse(["2019-03-31T01:30+01:00", "2019-03-31T03:30+02:00"])
    assert note == ""
    assert times[1] - times[0] == pd.Timedelta(hours=1)  # one real hour across the change
    assert times[0] == pd.Timestamp("2019-03-31 00:30", tz="UTC")


def test_same_offset_is_kept_and_tz_converts():
    times, _ = _parse(["2019-01-01T00:00+01:00", "2019-01-01T01:00+01:00"])
    assert times[0].utcoffset() == pd.Timedelta(hours=1)
    times, _ = _parse(["2019-01-01T00:00+01:00"], tz="UTC")
    assert times[0] == pd.Timestamp("2018-12-31 23:00", tz="UTC")


def test_naive_times_placed_in_hours_or_name():
    times, note = _parse(["2019-01-01 00:00", "2019-07-01 00:00"], tz=1.0)
    assert [t.utcoffset() for t in times] == [pd.Timedelta(hours=1)] * 2
    assert "interpreted in 1.0" in note
    times, _ = _parse(["2019-01-01 00:00", "2019-07-01 00:00"], tz="Europe/Zurich")
    assert [t.utcoffset() for t in times] == [pd.Timedelta(hours=1), pd.Timedelta(hours=2)]


def test_naive_times_without_tz_are_refused():
    with pytest.raises(ThermocalInputError, match="no time zone and no UTC offset; pass tz="):
        _parse(["2019-01-01 00:00"])


def test_local_time_at_clock_change_names_the_line():
    with pytest.raises(ThermocalInputError) as info:
        _parse(["2019-03-30 12:00", "2019-03-31 02:30"], tz="Europe/Zurich")
    message = str(info.value)
    for fragment in ("log.csv", "'time'", "line 3", "2019-03-31 02:30", "never happened",
                     "Europe/Zurich", "UTC+0100"):  # fmt: skip
        assert fragment in message, message


def test_an_ambiguous_local_time_written_once_is_read_as_daylight_time():
    """The autumn's repeated hour written once: the first (daylight-time) hour, said in the
    note (was: refused, though the zone had been given by name as the messages ask)."""
    times, note = _parse(["2019-03-30 12:00", "2019-10-27 02:30"], tz="Europe/Zurich")
    assert times[1] == pd.Timestamp("2019-10-27 00:30", tz="UTC")
    assert "line 3 ('2019-10-27 02:30')" in note and "written once" in note


def test_unreadable_time_names_line_and_suggests_a_format():
    with pytest.raises(ThermocalInputError) as info:
        _parse(["2019-01-01 00:00", "01.01.2019 01:00"], tz=1.0)
    message = str(info.value)
    assert "line 3" in message and "'01.01.2019 01:00'" in message and "time_format=" in message
    times, _ = _parse(
        ["01.01.2019 00:00", "13.01.2019 01:00"], tz=1.0, time_format="%d.%m.%Y %H:%M"
    )
    assert times[1] == pd.Timestamp("2019-01-13 01:00", tz=dt.timezone(dt.timedelta(hours=1)))


def test_rows_instead_of_lines_without_line_numbers():
    with pytest.raises(ThermocalInputError, match="row 2: cannot read"):
        _parse(["2019-01-01 00:00", "never"], tz=1.0, lines=None)


def test_datetime_columns_are_used_as_they_are():
    naive = pd.Series(pd.to_datetime(["2019-01-01 00:00", "2019-01-01 01:00"]))
    times, _ = parse_time_column(naive, source="x.parquet", column="time", tz="UTC")
    assert times[1] == pd.Timestamp("2019-01-01 01:00", tz="UTC")
    aware = naive.dt.tz_localize("Europe/Zurich")
    times, _ = parse_time_column(aware, source="x.parquet", column="time", tz="UTC")
    assert times[0] == pd.Timestamp("2018-12-31 23:00", tz="UTC")
    with pytest.raises(ThermocalInputError, match="row 2: missing time"):
        parse_time_column(
            pd.Series([naive[0], pd.NaT]), source="x.parquet", column="time", tz="UTC"
        )


def test_numeric_times_need_a_unit_and_an_aware_origin():
    times, note = _parse([0.0, 1.5], time_unit="h", start="2019-01-01T00:00+01:00")
    assert times[1] - times[0] == pd.Timedelta(minutes=90)
    assert "numeric times in h" in note
    with pytest.raises(ThermocalInputError, match="time_unit="):
        _parse([0.0, 1.0])
    with pytest.raises(ThermocalInputError, match="line 3: missing or invalid time"):
        _parse([0.0, np.nan], time_unit="h")


def test_as_timezone():
    assert as_timezone(-5, "w") == dt.timezone(dt.timedelta(hours=-5))
    with pytest.raises(ThermocalInputError, match="w: tz=20"):
        as_timezone(20, "w")
    with pytest.raises(ThermocalInputError, match="unknown time zone 'Mars/Olympus'"):
        as_timezone("Mars/Olympus", "w")


def test_weather_csv_and_measurements_share_the_parser(tmp_path):
    text = "time,T_out\n01.01.2019 00:00,1.0\n01.02.2019 00:00,2.0\n"
    path = tmp_path / "w.csv"
    path.write_text(text)
    # day-first stamps are not guessed (01.02 could be 2 January or 1 February) ...
    with pytest.raises(ThermocalInputError, match="line 2.*time_format="):
        read_weather(path, columns={"temp_air": "T_out"}, tz=1.0)
    with pytest.raises(ThermocalInputError, match="line 2.*time_format="):
        read_measurements(path, tz=1.0)
    # ... but read with the format given
    weather, _ = read_weather(
        path, columns={"temp_air": "T_out"}, tz=1.0, time_format="%d.%m.%Y %H:%M"
    )
    assert weather.index[1] - weather.index[0] == pd.Timedelta(days=31)
    raw, _ = read_measurements(path, tz=1.0, time_format="%d.%m.%Y %H:%M")
    assert raw.index[1] == pd.Timestamp("2019-02-01", tz=dt.timezone(dt.timedelta(hours=1)))
