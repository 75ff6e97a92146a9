"""Logs on local time across the clocks' changes, read by the shared time parser.

The truth is the IANA time zone database (through pandas): the real instants of a local clock
in America/Chicago, Europe/Zurich, Australia/Sydney or Asia/Tehran, written as the logger's
naive clock readings. Exploratory verify run on the EnergyPlus twin (2026-12-01): local
stamps with ``measurements.timezone: America/Chicago`` were refused at the autumn's repeated
01:00; without a zone, the spring's missing hour of 2006 (the first Sunday of April, the
United States' rule before 2007) surfaced as a missing outdoor temperature and the autumn's
repeated hour as a "duplicated time".
"""

from __future__ import annotations

import logging

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import read_measurements


def _clock(start: str, periods: int, freq: str, zone: str) -> tuple[pd.DatetimeIndex, list[str]]:
    """Real instants of a local clock and its readings as a logger on that clock writes them."""
    real = pd.date_range(start, periods=periods, freq=freq, tz=zone)
    return real, [t.strftime("%Y-%m-%d %H:%M") for t in real]


def _log(tmp_path, stamps, name="log.csv"):
    path = tmp_path / name
    values = 20 + 0.1 * np.arange(len(stamps))
    pd.DataFrame({"time": stamps, "S0": values}).to_csv(path, index=False)
    return path


def _times(raw: pd.DataFrame) -> pd.DatetimeIndex:
    return pd.DatetimeIndex(raw["time"] if "time" in raw.columns else raw.index)


@pytest.mark.parametrize("freq", ["h", "15min"])
def test_the_repeated_autumn_hour_is_read_in_order_in_a_named_zone(tmp_path, freq):
    """01:00 written twice (hourly) or 01:00-01:45 twice: the first in daylight time, the
    second in standard time, as the clock lived them (was: refused as ambiguous)."""
    real, stamps = _clock("2006-10-28 20:00", 12 * 4, freq, "America/Chicago")
    assert len(set(stamps)) < len(stamps)  # the hour is there twice
    raw, meta = read_measurements(_log(tmp_path, stamps), tz="America/Chicago")
    assert (_times(raw).tz_convert("UTC") == real.tz_convert("UTC")).all()
    assert not any("written once" in note for note in meta["notes"])


def test_the_repeated_hour_written_once_is_read_as_daylight_time(tmp_path, caplog):
    """Hourly means of which the logger kept one 01:00: read as the first (daylight-time)
    hour, said in a warning and the notes; the standard-time hour after it is a gap."""
    real, stamps = _clock("2006-10-28 20:00", 12, "h", "America/Chicago")
    once = list(dict.fromkeys(stamps))
    with caplog.at_level(logging.WARNING, logger="thermocal"):
        raw, meta = read_measurements(_log(tmp_path, once), tz="America/Chicago")
    times = _times(raw).tz_convert("UTC")
    assert times[5] == real[5].tz_convert("UTC")  # 01:00 CDT = 06:00 UTC
    assert times[6] - times[5] == pd.Timedelta(hours=2)  # 01:00 CST is missing
    note = next(n for n in meta["notes"] if "written once" in n)
    assert "line 7" in note and "daylight-time hour (UTC-0500)" in note
    assert "fixed offset (UTC-0600)" in note
    assert "written once" in caplog.text


def test_a_time_in_the_spring_hour_skipped_is_refused_in_a_named_zone(tmp_path):
    """02:00 on 2006-04-02 never happened in Chicago (a row filled in by hand): refused with
    the night's change and what to do."""
    _, stamps = _clock("2006-04-01 20:00", 12, "h", "America/Chicago")
    filled = stamps[:6] + ["2006-04-02 02:00"] + stamps[6:]
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(_log(tmp_path, filled), tz="America/Chicago")
    message = str(info.value)
    assert "line 8: the local time '2006-04-02 02:00' never happened" in message, message
    assert "went forward from UTC-0600 to UTC-0500" in message and "remove the row" in message


@pytest.mark.parametrize(
    ("zone", "start", "offset"),
    [
        # the first Sunday of April: the United States' rule until 2006 (was: a missing hour)
        ("America/Chicago", "2006-04-01", -6),
        ("Europe/Zurich", "2021-03-27", 1),
        ("Australia/Sydney", "2021-10-02", 10),
        # a Monday at midnight (was: a missing hour)
        ("Asia/Tehran", "2021-03-21", 3.5),
    ],
)
def test_the_spring_hour_missing_in_a_fixed_zone_is_a_clock_change(tmp_path, zone, start, offset):
    """Naive local stamps read in the zone's standard offset: the hour skipped in spring is
    refused as a clock change, naming the zone to give, on any rule of the zone database."""
    real, stamps = _clock(start, 72, "h", zone)
    assert (np.diff(real.tz_localize(None)) > pd.Timedelta(hours=1)).any()  # an hour skipped
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(_log(tmp_path, stamps), tz=offset)
    message = str(info.value)
    assert "clocks went forward that night in" in message and zone in message, message
    assert f"--tz {zone}" in message and f"measurements.timezone: {zone}" in message


@pytest.mark.parametrize("freq", ["h", "15min"])
def test_the_autumn_hour_repeated_in_a_fixed_zone_is_a_clock_change(tmp_path, freq):
    """Was: "duplicated time ... remove them" (hourly) or "earlier than the previous one:
    sort it" (15 min), neither of which names the cause."""
    _, stamps = _clock("2006-10-28 20:00", 12 * 4, freq, "America/Chicago")
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(_log(tmp_path, stamps), tz=-6)
    message = str(info.value)
    assert "(an hour repeated): clocks went back from daylight saving to standard time" in (message)
    assert "America/Chicago" in message and "duplicated" not in message, message


def test_gaps_and_repeats_on_other_nights_are_not_clock_changes(tmp_path):
    """A missing hour a week after the change, and a duplicated record at 01:00 on the
    change's night in a zone whose clocks did not change then, are the reader's usual cases."""
    _, stamps = _clock("2006-04-08 20:00", 12, "h", "Etc/GMT+6")
    read_measurements(_log(tmp_path, stamps[:6] + stamps[7:], "gap.csv"), tz=-6)
    _, stamps = _clock("2006-10-28 20:00", 12, "h", "Etc/GMT+6")
    repeated = stamps[:6] + stamps[5:]
    with pytest.raises(ThermocalInputError, match="duplicated time"):
        read_measurements(_log(tmp_path, repeated, "dup.csv"), tz=5)


def test_clock_change_zones_matches_the_zone_database():
    """Chicago's 2006 changes fit; a day later none does; the standard offset's zones first."""
    from thermocal.io._time import clock_change_zones

    hour = pd.Timedelta(hours=1)
    spring = clock_change_zones(
        pd.Timestamp("2006-04-02 01:00"), pd.Timestamp("2006-04-02 03:00"), hour, -6 * hour
    )
    assert "America/Chicago" in spring and "America/Denver" not in spring
    autumn = clock_change_zones(
        pd.Timestamp("2006-10-29 01:00"), pd.Timestamp("2006-10-29 01:00"), hour, -6 * hour
    )
    assert "America/Chicago" in autumn
    assert not clock_change_zones(
        pd.Timestamp("2006-04-03 01:00"), pd.Timestamp("2006-04-03 03:00"), hour, -6 * hour
    )


def test_a_parquet_column_of_clock_readings_is_read_in_order():
    """Naive datetimes (microseconds, as parquet keeps them) across the autumn change."""
    from thermocal.io._time import parse_time_column

    real = pd.date_range("2006-10-28 20:00", periods=12, freq="h", tz="America/Chicago")
    naive = pd.Series(real.tz_localize(None).as_unit("us"))
    times, _ = parse_time_column(naive, source="x.parquet", column="time", tz="America/Chicago")
    assert (times == real).all()


def _long_log(tmp_path, stamps, sensors=("A", "B", "C"), name="long.csv"):
    """One row per sensor and time, sorted by time (as a data logger's export writes them)."""
    path = tmp_path / name
    rows = [(s, k, 20 + 0.1 * i) for i, s in enumerate(stamps) for k in sensors]
    pd.DataFrame(rows, columns=["time", "sensor", "value"]).to_csv(path, index=False)
    return path


@pytest.mark.parametrize("freq", ["h", "15min"])
def test_the_repeated_autumn_hour_of_a_long_log_is_read_per_time_not_per_row(tmp_path, freq):
    """Was: '01:00 A' then '01:00 B' taken for the clock going back, so that sensor B's
    daylight-time 01:00 was read in standard time ("duplicated time ... of sensor 'B'", or
    with duplicates='first' B's reading an hour late). Every sensor's instants are the
    zone database's."""
    real, stamps = _clock("2006-10-28 20:00", 12 * 4, freq, "America/Chicago")
    raw, meta = read_measurements(_long_log(tmp_path, stamps), tz="America/Chicago")
    for sensor in ("A", "B", "C"):
        rows = raw[raw["sensor"] == sensor]
        assert (_times(rows).tz_convert("UTC") == real.tz_convert("UTC")).all(), sensor
        assert np.allclose(rows["value"], 20 + 0.1 * np.arange(len(real)))
    assert not any("written once" in note for note in meta["notes"])


def test_the_repeated_hour_written_once_in_a_long_log_is_read_as_daylight_time(tmp_path):
    """Each sensor's 01:00 once: daylight time for all, the note says so (not a clock going
    back between sensors)."""
    real, stamps = _clock("2006-10-28 20:00", 12, "h", "America/Chicago")
    once = list(dict.fromkeys(stamps))
    raw, meta = read_measurements(_long_log(tmp_path, once), tz="America/Chicago")
    times = _times(raw[raw["sensor"] == "C"]).tz_convert("UTC")
    assert times[5] == real[5].tz_convert("UTC")
    assert times[6] - times[5] == pd.Timedelta(hours=2)
    assert any("written once" in note for note in meta["notes"])


def test_the_spring_hour_missing_in_an_hourly_long_log_in_a_fixed_zone_is_refused(tmp_path):
    """Two sensors, hourly, 16 days of Chicago local time read at -6 h. Was accepted silently:
    every zero step between the sensors at one time was searched as a clock going back, and
    the cap of 50 searches was spent before the change (the parent of the autumn's handling
    refused it)."""
    _, stamps = _clock("2023-03-01 00:00", 24 * 16, "h", "America/Chicago")
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(_long_log(tmp_path, stamps, sensors=("A", "B")), tz=-6)
    message = str(info.value)
    # row 266 of the clock (03:00 on 2023-03-12), sensor A: file line 2 + 2 * 266
    assert "line 534: the clock jumps from 01:00 to 03:00 on Sunday 2023-03-12" in message
    assert "America/Chicago" in message, message


def test_the_spring_hour_missing_after_many_other_gaps_is_refused(tmp_path):
    """An hour missing at 10:00 every day from New Year (70 gaps on nights without a change)
    does not hide the spring's change (was: the first 50 gaps searched, the change never)."""
    real, stamps = _clock("2023-01-01 00:00", 24 * 75, "h", "America/Chicago")
    kept = [s for t, s in zip(real, stamps, strict=True) if t.hour != 10]
    with pytest.raises(ThermocalInputError, match="clocks went forward that night in"):
        read_measurements(_log(tmp_path, kept), tz=-6)


def test_the_autumn_hour_in_a_long_log_in_a_fixed_zone(tmp_path):
    """Chicago's clock in an hourly long log at -6 h: refused as the hour repeated. A logger
    on standard time all year (Etc/GMT+6) that night: read (was: the step from sensor A's
    01:00 to sensor B's taken for Chicago's clock going back, and refused)."""
    _, stamps = _clock("2006-10-28 20:00", 12, "h", "America/Chicago")
    with pytest.raises(ThermocalInputError, match=r"repeats 01:00 .* \(an hour repeated\)"):
        read_measurements(_long_log(tmp_path, stamps), tz=-6)
    real, stamps = _clock("2006-10-28 20:00", 12, "h", "Etc/GMT+6")
    raw, _ = read_measurements(_long_log(tmp_path, stamps, name="standard.csv"), tz=-6)
    assert (_times(raw[raw["sensor"] == "B"]) == real).all()
