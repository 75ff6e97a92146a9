"""Numbers of European spreadsheet exports: a decimal comma, points grouping thousands."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.decimal_comma import decimal_comma_numbers
from thermocal.io.measurements import read_measurements


@pytest.mark.parametrize(
    ("text", "value", "ambiguous"),
    [
        ("7.476", 7476.0, False),  # the tester's heat power: was read as 7.476
        ("-1.203,5", -1203.5, False),
        ("994,5", 994.5, False),
        ("12.345.678", 12345678.0, False),
        ("1 203,5", 1203.5, False),
        ("1\u00a0203", 1203.0, False),  # a non-breaking space groups thousands (fr-FR)
        ("0", 0.0, False),
        ("", np.nan, False),
        ("7.5", np.nan, True),  # a point grouping no thousands: its meaning is unknown
        ("1.5e3", np.nan, True),
        ("12.34,5", np.nan, True),
    ],
)
def test_decimal_comma_numbers(text, value, ambiguous):
    numbers, unclear = decimal_comma_numbers(pd.Series([text], dtype=object))
    assert bool(unclear.iloc[0]) is ambiguous
    if np.isnan(value):
        assert np.isnan(numbers.iloc[0])
    else:
        assert numbers.iloc[0] == value


def test_sensor_log_with_thousands_separators(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text(
        "time;P;T\n2019-02-02T00:00:00Z;7.476;20,5\n2019-02-02T01:00:00Z;994,5;20,6\n"
    )
    frames = read_measurements(path, decimal=",")[0]
    assert frames["P"].tolist() == [7476.0, 994.5]
    path.write_text("time;P;T\n2019-02-02T00:00:00Z;7.476;20,5\n2019-02-02T01:00:00Z;7.5;20,6\n")
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(path, decimal=",")
    message = str(info.value)
    assert "column 'P', line 3: '7.5' has a decimal point" in message
    assert "write them with a decimal comma" in message


def test_a_clock_reset_is_not_told_to_be_sorted(tmp_path):
    """A logger whose clock went back to 2000-01-01 mid-file was told to sort the file, which
    put the rows after the reset first, under 2000 dates (exploratory test, 2026-11-30)."""
    path = tmp_path / "reset.csv"
    path.write_text(
        "time,T\n2019-02-02T00:00:00Z,20\n2019-02-02T01:00:00Z,21\n"
        "2000-01-01T00:00:00Z,21\n2000-01-01T01:00:00Z,21\n"
    )
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(path)
    message = str(info.value)
    assert "line 4: the time goes back from 2019-02-02T01:00:00+00:00" in message
    assert "before the log's first time: the logger's clock was reset there" in message
    assert "sort" not in message.split("reset there")[0]
    # a log written newest first goes back at every row: told to sort (it was told not to)
    path.write_text("time,T\n2019-02-02T00:30:00Z,20\n2019-02-02T00:20:00Z,21\n"
                    "2019-02-02T00:10:00Z,21\n")  # fmt: skip
    with pytest.raises(ThermocalInputError, match="sort it"):
        read_measurements(path)
    assert read_measurements(path, sort=True)[0]["T"].tolist() == [21.0, 21.0, 20.0]
    # a row out of order by a few minutes is still told to sort
    path.write_text("time,T\n2019-02-02T00:10:00Z,20\n2019-02-02T00:20:00Z,21\n"
                    "2019-02-02T00:15:00Z,21\n")  # fmt: skip
    with pytest.raises(ThermocalInputError, match="sort it"):
        read_measurements(path)


def test_numbers_among_the_text_stay_numbers():
    """An Excel column holding both text and numbers: 1.5 was turned into '1.5' and refused."""
    values = pd.Series(["7.476", 1.5, "994,5", None, 3, "7.5"], dtype=object)
    numbers, ambiguous = decimal_comma_numbers(values)
    assert numbers.tolist()[:3] == [7476.0, 1.5, 994.5] and numbers.iloc[4] == 3.0
    assert ambiguous.tolist() == [False, False, False, False, False, True]
