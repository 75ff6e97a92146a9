"""Numeric dates day-first or month-first (01/02/2015): the log's times decide, or refused."""

from __future__ import annotations

import datetime as dt
import logging

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import read_measurements

CET = dt.timezone(dt.timedelta(hours=1))
#: Hourly from 1 to 12 February 2015: every day and month at most 12.
FEBRUARY = pd.date_range("2015-02-01 00:00", "2015-02-12 23:00", freq="h")


def _wide_log(tmp_path, stamps, name="log.csv"):
    path = tmp_path / name
    rows = [f"{stamp},{20.0 + 0.01 * i:.2f}" for i, stamp in enumerate(stamps)]
    path.write_text("time,T_a\n" + "\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize(
    ("fmt", "order"),
    [
        ("%d/%m/%Y %H:%M", "day-first"),
        ("%d.%m.%Y %H:%M:%S", "day-first"),
        ("%m/%d/%Y %H:%M", "month-first"),
        ("%m-%d-%Y %H:%M", "month-first"),
    ],
    ids=["european-slash", "european-dots-seconds", "us-slash", "us-dash"],
)
def test_feb_1_to_12_hourly_is_read_as_february(tmp_path, caplog, fmt, order):
    path = _wide_log(tmp_path, FEBRUARY.strftime(fmt))
    with caplog.at_level(logging.INFO, logger="thermocal.io._time"):
        raw, meta = read_measurements(path, tz=1.0)
    expected = FEBRUARY.tz_localize(CET)
    assert raw.index.equals(expected.as_unit(raw.index.unit))
    assert raw["T_a"].iloc[-1] == pytest.approx(20.0 + 0.01 * (len(FEBRUARY) - 1))
    note = next(n for n in meta["notes"] if n.startswith("dates read"))
    assert f"dates read {order}" in note
    assert any(
        f"{path}, column 'time': dates read {order}" in record.getMessage()
        for record in caplog.records
        if record.levelno == logging.INFO
    )


def test_long_log_with_several_sensors_per_time_is_read_day_first(tmp_path):
    path = tmp_path / "long.csv"
    rows = [
        f"{stamp:%d/%m/%Y %H:%M},{sensor},{value:.1f}"
        for stamp in FEBRUARY
        for sensor, value in (("T_a", 20.0), ("T_b", 21.0))
    ]
    path.write_text("time,sensor,value\n" + "\n".join(rows) + "\n")
    raw, _ = read_measurements(path, layout="long", tz="Europe/Zurich")
    for sensor in ("T_a", "T_b"):
        times = pd.DatetimeIndex(raw.loc[raw["sensor"] == sensor, "time"])
        assert times.equals(FEBRUARY.tz_localize("Europe/Zurich").as_unit(times.unit))


@pytest.mark.parametrize(
    ("stamps", "expected"),
    [
        (["01/02/2015 00:00", "13/02/2015 00:00"], ["2015-02-01", "2015-02-13"]),
        (["02/01/2015 00:00", "02/13/2015 00:00"], ["2015-02-01", "2015-02-13"]),
        # an unsorted log (read with sort=True): the 25th still decides
        (["03/04/2015 00:00", "01/04/2015 07:00", "25/04/2015 00:00"], None),
    ],
    ids=["day-first", "month-first", "day-first-unsorted"],
)
def test_a_day_above_12_decides_the_order(tmp_path, stamps, expected):
    path = _wide_log(tmp_path, stamps)
    if expected is None:
        raw, meta = read_measurements(path, tz=1.0, sort=True)
        assert list(raw.index) == [
            pd.Timestamp(t, tz=CET) for t in ("2015-04-01 07:00", "2015-04-03", "2015-04-25")
        ]
    else:
        raw, meta = read_measurements(path, tz=1.0)
        assert list(raw.index) == [pd.Timestamp(t, tz=CET) for t in expected]
    note = next(n for n in meta["notes"] if n.startswith("dates read"))
    assert f"'{stamps[-1]}') cannot be" in note


@pytest.mark.parametrize(
    ("stamps", "shown"),
    [
        (["03/04/2015 10:00"], "3 April 2015 day-first, 4 March 2015 month-first"),
        (["01.01.2019 00:00", "01.02.2019 00:00"], "on line 3 is 1 February 2019 day-first"),
    ],
    ids=["one-row", "two-rows"],
)
def test_a_truly_ambiguous_file_is_refused(tmp_path, stamps, shown):
    path = _wide_log(tmp_path, stamps, name="ambiguous.csv")
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(path, tz=1.0)
    message = str(info.value)
    assert message.startswith(f"{path}, column 'time', line 2: cannot read '{stamps[0]}'")
    assert "does not show whether its dates are day-first or month-first" in message
    assert shown in message
    assert "ISO 8601, year first (2015-02-01 00:00)" in message
    assert "time_format=" in message


def test_month_first_reading_of_a_day_first_log_would_be_irregular(tmp_path):
    # both orders read every row and keep the times sorted: only the spacing decides
    stamps = FEBRUARY.strftime("%d/%m/%Y %H:%M")
    for fmt in ("%d/%m/%Y %H:%M", "%m/%d/%Y %H:%M"):
        assert pd.to_datetime(pd.Series(stamps), format=fmt).is_monotonic_increasing
    raw, _ = read_measurements(_wide_log(tmp_path, stamps), tz=1.0)
    assert np.all(np.diff(raw.index.asi8) == np.diff(raw.index.asi8)[0])


def test_a_spreadsheet_writes_midnight_as_the_date_alone(tmp_path):
    """Spreadsheet exports drop 00:00 at midnight ('13/01/2024', then '13/01/2024 01:00'): both
    orders failed on the midnight rows, so the file was refused as unreadable (review of the
    day/month reading); each row is now read with its own time of day."""
    stamps = pd.date_range("2024-01-13 00:00", periods=72, freq="h")
    written = [
        s.strftime("%d/%m/%Y") if s.hour == 0 else s.strftime("%d/%m/%Y %H:%M") for s in stamps
    ]
    raw, _ = read_measurements(_wide_log(tmp_path, written), tz=1.0)
    index = raw.index if isinstance(raw.index, pd.DatetimeIndex) else pd.DatetimeIndex(raw["time"])
    assert index[0] == pd.Timestamp("2024-01-13 00:00", tz=CET)
    assert index[24] == pd.Timestamp("2024-01-14 00:00", tz=CET)
    assert len(index.unique()) == 72
