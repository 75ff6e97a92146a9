"""What an EPW says about rain: liquid precipitation (field 33, a depth per record) and present
weather (fields 27-28), read as EnergyPlus reads them (EPW data dictionary, EnergyPlus
Auxiliary Programs; a missing depth, 999, is no rain; present weather counts only where the
observation indicator is 0, rain when one of the first three code digits is below 9)."""

from __future__ import annotations

import numpy as np

from conftest import shared_data_path
from thermocal.io.weather import read_weather


def _edited(tmp_path, edit) -> tuple:
    source = shared_data_path("ashrae140_bestest", "725650TYCST.epw")
    lines = source.read_text().splitlines()
    rows = [line.split(",") for line in lines[8:]]
    edit(rows)
    path = tmp_path / "edited.epw"
    path.write_text("\n".join(lines[:8] + [",".join(r) for r in rows]) + "\n")
    return rows, read_weather(path)[0]


def test_precipitation_is_the_files_depth_per_hour_and_missing_is_none(tmp_path):
    rows, weather = _edited(tmp_path, lambda rows: None)
    depth = np.array([float(r[33]) for r in rows])
    assert (depth >= 999).sum() > 1000  # Denver's TMY3 misses most of it
    expected = np.where(depth >= 999, 0.0, depth)
    np.testing.assert_array_equal(weather["precipitation"].to_numpy(), expected)
    assert expected.max() >= 4.0 and "weather_rain" not in weather  # no observations


def test_present_weather_rain_only_where_observed(tmp_path):
    def edit(rows):
        rows[10][26], rows[10][27] = "0", "919999999"  # observed: rain (second digit 1)
        rows[11][26], rows[11][27] = "0", "999999999"  # observed: nothing
        rows[12][26], rows[12][27] = "9", "919999999"  # not observed: ignored
        rows[13][26], rows[13][27] = "0", "999099999"  # observed: snow only (fourth digit)

    _, weather = _edited(tmp_path, edit)
    flags = weather["weather_rain"].to_numpy()
    assert flags[10] == 1.0 and flags[11:14].sum() == 0.0 and flags.sum() == 1.0
