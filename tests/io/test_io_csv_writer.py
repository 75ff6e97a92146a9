"""The fast CSV writer against pandas' ``DataFrame.round(d).to_csv`` (the text it replaces)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.io.csv_writer import time_labels, write_frame_csv


@pytest.mark.parametrize(
    "index",
    [
        pd.date_range("2009-01-01", periods=7, freq="15min", tz="Etc/GMT+7"),
        pd.date_range("2021-03-28 00:00", periods=8, freq="30min", tz="Europe/Paris"),  # DST on
        pd.date_range("2021-10-31 00:00", periods=8, freq="30min", tz="Europe/Paris"),  # DST off
        pd.date_range("2009-01-01", periods=3, freq="1h"),
        pd.date_range("2009-01-01", periods=3, freq="1h", tz="Asia/Kolkata"),  # +05:30
        pd.date_range("2009-01-01", periods=3, freq="1500ms", tz="UTC"),  # sub-second
        pd.RangeIndex(4),
    ],
)
def test_time_labels_are_what_pandas_prints(index):
    assert time_labels(index).to_pylist() == list(index.astype(str))


def _frame(rows=300, columns=7, seed=1):
    rng = np.random.default_rng(seed)
    values = rng.normal(0.0, 500.0, (rows, columns)) * 10.0 ** rng.integers(-6, 6, (rows, columns))
    values[3, 2] = np.nan
    values[4, 1] = -0.00004  # rounds to (negative) zero
    values[5, 0] = 0.5
    values[6, 3] = -12.30004
    values[7, 4] = 2.0
    values[8, 5] = 99999.99996  # rounds up to 100000
    index = pd.date_range("2009-01-01", periods=rows, freq="5min", tz="Etc/GMT+7", name="time")
    return pd.DataFrame(
        values, index=index, columns=[f"zone {j}|air_temperature_C" for j in range(columns)]
    )


@pytest.mark.parametrize("decimals", [0, 1, 4, 6])
def test_numbers_and_labels_equal_pandas(tmp_path, decimals):
    frame = _frame()
    path = tmp_path / "fast.csv"
    write_frame_csv(frame, path, decimals=decimals)
    expected = tmp_path / "pandas.csv"
    frame.round(decimals).to_csv(expected)
    ours, theirs = pd.read_csv(path, index_col=0), pd.read_csv(expected, index_col=0)
    assert list(ours.columns) == list(theirs.columns)
    assert list(ours.index) == list(theirs.index)
    np.testing.assert_array_equal(ours.to_numpy(), theirs.to_numpy())  # NaN in the same places
    lines = path.read_text().splitlines()
    assert lines[0] == "time," + ",".join(frame.columns)
    assert lines[8].endswith(",2,") or ",2," in lines[8]  # no trailing zeros: 2, not 2.0000
    assert ",-0," not in lines[5] and ",," in lines[4]  # negative zero as 0; NaN as empty


def test_blocks_join_seamlessly(tmp_path, monkeypatch):
    import thermocal.io.csv_writer as writer

    monkeypatch.setattr(writer, "ROWS_PER_BLOCK", 7)
    frame = _frame(rows=50)
    write_frame_csv(frame, tmp_path / "a.csv")
    back = pd.read_csv(tmp_path / "a.csv", index_col=0)
    np.testing.assert_array_equal(back.to_numpy(), frame.round(4).to_numpy())
    assert len(back) == 50


def test_infinite_and_huge_values_fall_back_to_arrow(tmp_path):
    frame = _frame(rows=10)
    frame.iloc[0, 0] = np.inf
    frame.iloc[1, 1] = 3.5e15
    write_frame_csv(frame, tmp_path / "a.csv")
    back = pd.read_csv(tmp_path / "a.csv", index_col=0)
    assert np.isinf(back.iloc[0, 0]) and back.iloc[1, 1] == 3.5e15
    np.testing.assert_array_equal(back.to_numpy()[2:], frame.round(4).to_numpy()[2:])


def test_empty_frame(tmp_path):
    frame = _frame(rows=10).iloc[:0]
    write_frame_csv(frame, tmp_path / "a.csv")
    assert (tmp_path / "a.csv").read_text() == "time," + ",".join(frame.columns) + "\n"


def test_a_frame_of_several_quantities_is_written_as_one(tmp_path, monkeypatch):
    """``SimulationResult.to_files`` puts the quantities side by side without copying them
    (pandas concatenation: several blocks); the text is the one of the same frame in one block,
    block boundaries included."""
    import thermocal.io.csv_writer as writer

    monkeypatch.setattr(writer, "ROWS_PER_BLOCK", 11)
    frame = _frame(rows=60)
    parts = pd.concat([frame.iloc[:, :3], frame.iloc[:, 3:].copy()], axis=1)
    assert len(parts._mgr.blocks) == 2
    write_frame_csv(parts, tmp_path / "parts.csv")
    write_frame_csv(frame, tmp_path / "one.csv")
    assert (tmp_path / "parts.csv").read_bytes() == (tmp_path / "one.csv").read_bytes()
    huge = parts.copy()
    huge.iloc[5, 4] = 2e13  # beyond fixed point in the second block: Arrow's writer
    write_frame_csv(huge, tmp_path / "huge.csv")
    assert pd.read_csv(tmp_path / "huge.csv", index_col=0).iloc[5, 4] == 2e13
