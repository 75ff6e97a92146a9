"""A CSV header naming a column twice (fuzzing round 4, e04_dup_column).

pandas renames the repeat ("S1", "S1.1"); ``identify`` then said sensor 'S1.1', a name the file
does not have, was mapped to no zone. The reader now names the header as written and the
column positions.
"""

from __future__ import annotations

import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import read_measurements

ROWS = (
    "2023-01-01T00:05:00-06:00,14.1,16.9,17.1,16.9\n"
    "2023-01-01T00:10:00-06:00,14.0,16.8,17.0,16.8\n"
)


def test_a_repeated_column_name_is_named_as_written_with_its_positions(tmp_path):
    path = tmp_path / "sensors.csv"
    path.write_text("time,S0,S1,S1 ,S3\n" + ROWS, encoding="utf-8")
    with pytest.raises(ThermocalInputError) as caught:
        read_measurements(path)
    message = str(caught.value)
    assert f"{path}, line 1 (header): the same column name twice: 'S1' in columns 3 and 4" in (
        message
    )
    assert "S1.1" not in message


def test_a_header_after_comment_lines_names_its_own_line(tmp_path):
    path = tmp_path / "sensors.csv"
    path.write_text(
        "# logger export\ntime;S1;S2;S1\n2023-01-01T00:05:00-06:00;1;2;3\n"
        "2023-01-01T00:10:00-06:00;1;2;3\n",
        encoding="utf-8",
    )
    with pytest.raises(ThermocalInputError, match=r"line 2 \(header\).*'S1' in columns 2 and 4"):
        read_measurements(path, comment="#")


def test_a_column_really_named_like_a_renamed_repeat_is_read(tmp_path):
    """A header with S1 and S1.1 (two sensors) is no repeat."""
    path = tmp_path / "sensors.csv"
    path.write_text("time,S0,S1,S1.1,S3\n" + ROWS, encoding="utf-8")
    raw, _ = read_measurements(path)
    assert list(raw.columns) == ["S0", "S1", "S1.1", "S3"]


def test_blank_header_cells_beside_a_dotted_name_are_read_as_before(tmp_path):
    """Review: a spreadsheet's trailing empty header cells are not a repeated name (with an
    'S1.1' column beside them the header was read again and '' refused as repeated)."""
    path = tmp_path / "sensors.csv"
    rows = "".join(line + ",,\n" for line in ROWS.splitlines())
    path.write_text("time,S0,S1,S1.1,S3,,\n" + rows, encoding="utf-8")
    raw, _ = read_measurements(path)
    assert {"S0", "S1", "S1.1", "S3"} <= set(raw.columns)
