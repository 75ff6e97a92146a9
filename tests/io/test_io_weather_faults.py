"""Weather faults of issue 13: Kelvin before missing codes, cut lines, one missing value."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.weather import fill_short_gaps, read_weather


def _copy_with(source: Path, tmp_path: Path, edit) -> Path:
    lines = source.read_text().splitlines()
    edit(lines)
    target = tmp_path / source.name
    target.write_text("\n".join(lines) + "\n")
    return target


def test_epw_in_kelvin_is_named_not_dropped_as_missing(shared_data, tmp_path):
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")

    def kelvin(lines):
        for i in range(8, len(lines)):
            fields = lines[i].split(",")
            fields[6] = f"{float(fields[6]) + 273.15:.1f}"
            lines[i] = ",".join(fields)

    with pytest.raises(ThermocalInputError) as info:
        read_weather(_copy_with(source, tmp_path, kelvin))
    message = str(info.value)
    assert "'temp_air'" in message and "look like Kelvin" in message
    assert "subtract 273.15" in message and "line 9" in message


def test_epw_line_cut_in_the_middle_is_refused(shared_data, tmp_path):
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")

    def cut(lines):
        lines[500] = ",".join(lines[500].split(",")[:25])

    with pytest.raises(ThermocalInputError, match=r"line 501: only 25 comma-separated fields"):
        read_weather(_copy_with(source, tmp_path, cut))


def test_one_missing_infrared_value_is_filled_aloud():
    index = pd.date_range("2001-01-01", periods=48, freq="h", tz="UTC")
    ir = np.linspace(250, 300, 48)
    ir[47] = np.nan  # one missing value on the last row (31 December in a year file)
    temp = np.linspace(0, 5, 48)
    temp[10:20] = np.nan  # ten hours: too long to invent
    weather = pd.DataFrame({"ghi_infrared": ir, "temp_air": temp, "dni": np.zeros(48)}, index)
    filled, notes = fill_short_gaps(weather)
    assert filled["ghi_infrared"].notna().all()
    assert filled["temp_air"].isna().sum() == 10
    assert notes == [
        "1 missing value(s) of 'ghi_infrared' in gaps of at most 3 rows interpolated (first at "
        "2001-01-02 23:00:00+00:00)"
    ]
    assert weather["ghi_infrared"].isna().sum() == 1  # the reader's frame is left as it was
