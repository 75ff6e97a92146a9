"""Weather faults of issue 13: Kelvin before missing codes, cut lines, one missing value."""

from __future__ import annotations

import json
import re
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


# ---------------------------------------------------------------- faults found by fuzzing
def test_epw_without_data_lines_is_named(shared_data, tmp_path):
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    path = _copy_with(source, tmp_path, lambda lines: lines.__delitem__(slice(8, None)))
    with pytest.raises(ThermocalInputError, match="no data lines after the 8 header lines"):
        read_weather(path)


@pytest.mark.parametrize(
    ("keep", "separator", "words"),
    [
        (20, ",", "20 comma-separated fields where an EPW data line has 35: wind direction, "
         "wind speed, total sky cover, opaque sky cover are missing"),
        (35, ";", "line 9: the fields are separated by semicolons"),
    ],
)  # fmt: skip
def test_epw_with_every_line_short_or_another_separator_is_refused(
    shared_data, tmp_path, keep, separator, words
):
    """Before: fields 21-35 read as missing, so the wind speed was absent and the simulation
    ran at still air (cooling +17 % on Case 600); semicolons gave 'year ... is not a number'."""
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")

    def edit(lines):
        for i in range(8, len(lines)):
            lines[i] = separator.join(lines[i].split(",")[:keep])

    with pytest.raises(ThermocalInputError, match=words):
        read_weather(_copy_with(source, tmp_path, edit))


def test_epw_time_zone_of_the_wrong_sign_is_refused(shared_data, tmp_path):
    """Denver (104.65 W) at UTC+7: the sun at night. Before: read without a word, and Case 600
    needed no cooling."""
    source = shared_data("ashrae140_bestest", "725650TYCST.epw")
    header = source.read_text().splitlines()[0].split(",")
    assert float(header[8]) == -7.0 and float(header[7]) < -100.0

    def flip(lines):
        fields = lines[0].split(",")
        fields[8] = "7.0"
        lines[0] = ",".join(fields)

    with pytest.raises(ThermocalInputError, match=r"time zone \+7 h does not fit its longitude"):
        read_weather(_copy_with(source, tmp_path, flip))
    read_weather(source)  # the file as it is


def test_simulate_refuses_a_weather_file_that_ends_inside_the_run_period(
    shared_data, tmp_path, capsys
):
    """A full-year RunPeriod and an EPW cut at a line boundary: before, the run stopped where
    the weather did (heating of January to mid-June reported as the year's) without a word."""
    from test_bad_input_table import run

    idf = shared_data("energyplus_reference", "case_600_v25.idf")
    source = shared_data("ashrae140_bestest", "725650TYCST.epw")
    path = _copy_with(source, tmp_path, lambda lines: lines.__delitem__(slice(8 + 4000, None)))
    code, text = run(["simulate", idf, path, "--step", "1h", "--out", tmp_path / "out"], capsys)
    text = " ".join(text.split())
    assert code == 2, text
    assert "RunPeriod" in text and "runs to 12/31" in text and "truncated weather file" in text
    assert not (tmp_path / "out" / "summary.json").exists()


def test_simulate_says_when_the_weather_is_another_sites(shared_data, tmp_path, capsys):
    """The multifamily prototype (Chicago) with Denver's weather: a forward run elsewhere is
    legitimate (EnergyPlus runs it with a warning), but it is said; before, nothing."""
    from test_bad_input_table import run

    idf = Path(__file__).resolve().parents[1] / "reference" / "identification_multifamily"
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    code, text = run(
        ["simulate", idf / "multifamily_5A_FF_v25.idf", weather, "--start", "2023-01-01",
         "--end", "2023-01-02", "--out", tmp_path / "out"],
        capsys,
    )  # fmt: skip
    text = " ".join(text.split())
    assert code == 0, text
    assert "1,424 km apart: simulated at the weather file's site and climate" in text, text
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert any("1,424 km apart: simulated at the weather" in n for n in summary["approximations"])


def test_an_epw_saved_with_a_byte_order_mark_is_read(shared_data, tmp_path):
    """A spreadsheet or an editor on Windows writes one; CSV and YAML were read with it, an EPW
    was refused ("found '\\ufeffLOCATION...'")."""
    source = shared_data("ashrae140_bestest", "725650TYCST.epw")
    path = tmp_path / "bom.epw"
    path.write_bytes(b"\xef\xbb\xbf" + source.read_bytes())
    weather, meta = read_weather(path)
    plain, plain_meta = read_weather(source)
    pd.testing.assert_frame_equal(weather, plain)
    assert meta["name"] == plain_meta["name"] == "DENVER INTL AP"


def test_simulate_refuses_irradiance_hours_away_from_the_sun(shared_data, tmp_path, capsys):
    """Irradiance 6 h early (UTC labels): before, the year's transmitted sun was 32.3 instead of
    13.0 MWh, 137 kW in one sunrise hour, a kitchen at 63 C, exit 0."""
    from test_bad_input_table import run

    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")

    def shift(lines):
        rows = [line.split(",") for line in lines[8:]]
        solar = [[row[i] for i in (13, 14, 15)] for row in rows]
        for k, row in enumerate(rows):
            row[13], row[14], row[15] = solar[(k + 6) % len(rows)]
            lines[8 + k] = ",".join(row)

    path = _copy_with(source, tmp_path, shift)
    building = Path(__file__).resolve().parents[2] / "examples" / "buildings"
    code, text = run(
        ["simulate", building / "multizone_single_family_house.yaml", path, "--step", "1h",
         "--out", tmp_path / "out"],
        capsys,
    )  # fmt: skip
    text = " ".join(text.split())
    assert code == 2, text
    # the file's own days are centred about 0.5 h late (test_bad_input_round2.py,
    # test_the_zurich_2015_weather_is_half_an_hour_late): 6 h early less that
    assert re.search(r"the time stamps are (5\.[5-9]|6) h early", text), text


def test_a_period_outside_a_typical_years_calendar_says_which_year(shared_data):
    """The file's own year (1995) was answered 'empty or outside the weather data [2023...'."""
    from thermocal.multizone.forcing import _weather_grid

    weather, _ = read_weather(shared_data("ashrae140_bestest", "725650TYCST.epw"))
    year = weather.index[0].year
    with pytest.raises(ThermocalInputError, match=f"give the period in {year}"):
        _weather_grid(weather, pd.Timedelta("1h"), "1995-12-25", "1995-12-28")
    with pytest.raises(ThermocalInputError, match="is empty: it ends before it starts"):
        _weather_grid(weather, pd.Timedelta("1h"), f"{year}-03-01", f"{year}-02-01")
