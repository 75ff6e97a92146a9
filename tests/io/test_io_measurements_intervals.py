"""Logs of interval means (rows='interval_start'/'interval_end', interval=) and parquet input."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import read_measurements, resample_measurements

TZ = "Etc/GMT-1"


def _ten_minute_log(n_hours=6, seed=1):
    rng = np.random.default_rng(seed)
    index = pd.date_range("2021-01-04 00:00", periods=6 * n_hours, freq="10min", tz=TZ)
    return pd.DataFrame(
        {"T_in": 20.0 + rng.normal(0.0, 0.5, index.size), "flow": rng.uniform(0, 1e-4, index.size)},
        index=pd.DatetimeIndex(index, name="time"),
    )


def test_interval_means_resample_to_the_plain_mean_of_their_rows_including_the_last_hour():
    log = _ten_minute_log()
    grid, report = resample_measurements(log, "1h", interval="10min")
    expected = log.groupby(log.index.floor("1h")).mean()
    assert len(grid) == 6  # the last hour [05:00, 06:00) is covered by its six rows
    np.testing.assert_allclose(grid.to_numpy(), expected.to_numpy(), rtol=0, atol=1e-12)
    assert report.sensors["n_reports"].tolist() == [36, 36]
    assert any("interval means" in action for action in report.actions)
    # as reports (the default), the last row is a point: the last hour averages five rows
    as_reports, _ = resample_measurements(log, "1h")
    last_five = log.iloc[-6:-1].mean()
    np.testing.assert_allclose(as_reports.iloc[-1].to_numpy(), last_five.to_numpy(), atol=1e-12)


def test_missing_rows_are_not_bridged_and_match_the_closing_row_recipe():
    """Brute force: the retrofit recipe (a closing row at t_last + interval, max_gap=interval)."""
    log = _ten_minute_log(n_hours=12)
    log = log.drop(log.index[[7, 8, 9, 30, 31, 32, 33, 34, 50]])
    log.loc[log.index[40:44], "T_in"] = np.nan  # one sensor silent for 40 min
    interval = pd.Timedelta("10min")
    grid, report = resample_measurements(log, "30min", interval=interval, max_gap=interval)
    closing = log.iloc[[-1]].copy()
    closing.index = closing.index + interval
    reference, ref_report = resample_measurements(
        pd.concat([log, closing]), "30min", max_gap=interval
    )
    pd.testing.assert_frame_equal(grid, reference)
    pd.testing.assert_frame_equal(report.gaps, ref_report.gaps)
    assert report.gaps["sensor"].tolist().count("T_in") == 3
    # hand check of one half-hour: [01:00, 01:30) lost rows 01:10 and 01:20 (coverage 1/3)
    assert np.isnan(grid.loc["2021-01-04 01:00", "T_in"])
    # brute force of a covered interval: mean of the rows it holds
    rows = log.loc["2021-01-04 02:00":"2021-01-04 02:29"]
    assert grid.loc["2021-01-04 02:00", "flow"] == pytest.approx(rows["flow"].mean(), abs=1e-15)


def _write_wide(tmp_path, log, label="start"):
    frame = log.copy()
    if label == "end":
        frame.index = frame.index + pd.Timedelta("10min")
    frame.index = frame.index.strftime("%Y-%m-%dT%H:%M:%S+01:00")
    path = tmp_path / f"log_{label}.csv"
    frame.rename(columns={"T_in": "T_in [C]", "flow": "flow [l/h]"}).to_csv(path)
    return path


@pytest.mark.parametrize("label", ["start", "end"])
def test_read_interval_means_labelled_by_start_or_end(tmp_path, label):
    log = _ten_minute_log()
    raw, meta = read_measurements(_write_wide(tmp_path, log, label), rows=f"interval_{label}")
    assert meta["rows"] == "interval means" and meta["interval"] == pd.Timedelta("10min")
    assert raw.index[0] == pd.Timestamp("2021-01-04 00:00", tz=TZ)
    grid, _ = resample_measurements(raw, "1h")  # the interval comes from raw.attrs
    expected = log.groupby(log.index.floor("1h")).mean()
    np.testing.assert_allclose(grid["T_in"].to_numpy(), expected["T_in"].to_numpy(), atol=1e-12)
    np.testing.assert_allclose(
        grid["flow"].to_numpy(), expected["flow"].to_numpy() / 3.6e6, rtol=1e-12
    )


def test_reports_stay_the_default(tmp_path):
    raw, meta = read_measurements(_write_wide(tmp_path, _ten_minute_log()))
    assert meta["rows"] == "reports" and meta["interval"] is None
    assert raw.index[0] == pd.Timestamp("2021-01-04 00:00", tz=TZ)


def test_interval_argument_errors(tmp_path):
    path = _write_wide(tmp_path, _ten_minute_log())
    with pytest.raises(ThermocalInputError, match="rows = 'means'"):
        read_measurements(path, rows="means")
    with pytest.raises(ThermocalInputError, match="rows='interval_start'"):
        read_measurements(path, interval="10min")
    with pytest.raises(ThermocalInputError, match="interval = '-5min'"):
        read_measurements(path, rows="interval_start", interval="-5min")
    raw, meta = read_measurements(path, rows="interval_start", interval="5min")
    assert meta["interval"] == pd.Timedelta("5min")  # given, not inferred


@pytest.mark.parametrize("time_as", ["datetime", "text", "index"])
def test_parquet_equals_csv(tmp_path, time_as):
    log = _ten_minute_log()
    csv_path = _write_wide(tmp_path, log)
    table = log.rename(columns={"T_in": "T_in [C]", "flow": "flow [l/h]"})
    if time_as == "text":
        table.index = table.index.strftime("%Y-%m-%dT%H:%M:%S+01:00")
    if time_as != "index":
        table = table.reset_index()
    parquet_path = tmp_path / "log.parquet"
    table.to_parquet(parquet_path)
    from_csv, _ = read_measurements(csv_path, rows="interval_start")
    from_parquet, meta = read_measurements(parquet_path, rows="interval_start")
    np.testing.assert_array_equal(from_parquet.index.asi8, from_csv.index.asi8)
    pd.testing.assert_frame_equal(
        from_parquet.reset_index(drop=True), from_csv.reset_index(drop=True)
    )
    assert meta["source"] == str(parquet_path)


def test_parquet_long_layout_and_errors_name_the_row(tmp_path):
    times = pd.date_range("2021-01-04", periods=4, freq="5min", tz=TZ)
    table = pd.DataFrame(
        {"time": times.tz_localize(None), "sensor": ["a", "b", "a", "b"], "value": [1.0, 2, 3, 4]}
    )
    path = tmp_path / "long.parquet"
    table.to_parquet(path)
    raw, meta = read_measurements(path, tz=TZ, quantities={"a": "temperature", "b": "temperature"})
    assert meta["layout"] == "long" and raw["time"].iloc[0] == times[0]
    with pytest.raises(ThermocalInputError, match="no time zone"):
        read_measurements(path)  # naive datetimes need tz=
    table["value"] = ["1.0", "2.0", "broken", "4.0"]  # a text column with one bad entry
    table.to_parquet(path)
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(path, tz=TZ)
    message = str(info.value)
    assert "long.parquet (parquet; line = table row)" in message and "line 3" in message
    bad = tmp_path / "bad.parquet"
    bad.write_text("not parquet")
    with pytest.raises(ThermocalInputError, match="cannot read as parquet"):
        read_measurements(bad)


@pytest.mark.parametrize("layout", ["wide", "long"])
def test_unknown_sensors_can_be_skipped(tmp_path, layout):
    if layout == "wide":
        text = "time,T_in,flow,comment\n2021-01-04T00:00+01:00,20.0,ok\n"
    else:
        text = (
            "time,sensor,value\n2021-01-04T00:00+01:00,T_in,20.0\n"
            "2021-01-04T00:00+01:00,door,1\n2021-01-04T00:05+01:00,T_in,21.0\n"
        )
    path = tmp_path / f"{layout}.csv"
    path.write_text(text)
    with pytest.raises(ThermocalInputError, match="unknown sensor"):
        read_measurements(path, sensors={"T_in": "temp_in"})
    raw, meta = read_measurements(path, sensors={"T_in": "temp_in"}, unknown_sensors="ignore")
    assert meta["sensors"] == ["temp_in"]
    assert any(
        "skipped" in note and ("comment" in note or "door" in note) for note in meta["notes"]
    )
    if layout == "long":
        assert raw["value"].tolist() == [20.0, 21.0]
        assert raw.index.tolist() == [2, 4]  # file lines kept
    else:
        assert list(raw.columns) == ["temp_in"]
