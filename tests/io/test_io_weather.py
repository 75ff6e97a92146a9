"""Weather readers: EPW, TMY3, CSV; time conventions; resampling; bad-input messages."""

from __future__ import annotations

import calendar
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.weather import read_weather, resample_weather

PVLIB_TMY3 = Path(__import__("pvlib").__file__).parent / "data" / "723170TYA.CSV"


def _epw_rows(path: Path) -> list[list[str]]:
    return [line.rstrip("\n").split(",") for line in path.read_text().splitlines()[8:]]


def _daylight_violations(weather: pd.DataFrame, meta: dict, shift_hours: int = 0) -> int:
    """Intervals with GHI > 0 although the sun is below -1 deg during the whole interval.

    A physical check of the time labelling: with the right convention (label = interval start)
    this count is (nearly) zero; shifting the labels by one hour in either direction makes it
    jump by hundreds.
    """
    import pvlib

    start = weather.index + pd.Timedelta(hours=shift_hours)
    end = start + pd.Timedelta(hours=1)
    lat, lon = meta["latitude"], meta["longitude"]
    e0 = pvlib.solarposition.get_solarposition(start, lat, lon)["apparent_elevation"].to_numpy()
    e1 = pvlib.solarposition.get_solarposition(end, lat, lon)["apparent_elevation"].to_numpy()
    sun_down = (e0 < -1.0) & (e1 < -1.0)
    return int(np.sum((weather["ghi"].to_numpy() > 0) & sun_down))


def _labelling_is_right(weather: pd.DataFrame, meta: dict) -> bool:
    right = _daylight_violations(weather, meta, 0)
    wrong = min(_daylight_violations(weather, meta, -1), _daylight_violations(weather, meta, 1))
    return right < 0.5 * wrong and right < 0.015 * int((weather["ghi"] > 0).sum())


# ---------------------------------------------------------------------------------------------
# EPW
# ---------------------------------------------------------------------------------------------
def test_zurich_epw_frame_and_metadata(shared_data):
    path = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    weather, meta = read_weather(path)
    assert len(weather) == 8760
    assert weather.index[0] == pd.Timestamp("2015-01-01 00:00", tz="Etc/GMT-1")
    assert weather.index[-1] == pd.Timestamp("2015-12-31 23:00", tz="Etc/GMT-1")
    assert weather.index[0].utcoffset() == pd.Timedelta(hours=1)
    assert weather.index.is_monotonic_increasing and weather.index.is_unique
    for column in ("temp_air", "ghi", "dni", "dhi", "ghi_infrared", "wind_speed", "pressure"):
        assert column in weather
    assert meta["latitude"] == pytest.approx(47.378)
    assert meta["longitude"] == pytest.approx(8.567)
    assert meta["altitude"] == pytest.approx(556.0)
    assert meta["tz"] == 1.0
    assert meta["coerced_year"] is None  # actual-year file keeps its year
    assert meta["step"] == pd.Timedelta(hours=1)
    # SOURCE.md statistics: mean T 10.63 C; GHI 1259, DNI 1327, DHI 531 kWh/m2 a
    assert weather["temp_air"].mean() == pytest.approx(10.63, abs=0.01)
    assert weather["ghi"].sum() / 1000 == pytest.approx(1259, abs=1)
    assert weather["dni"].sum() / 1000 == pytest.approx(1327, abs=1)
    assert weather["dhi"].sum() / 1000 == pytest.approx(531, abs=1)
    assert meta["ground_temperatures"][1.0][0] == pytest.approx(7.4)


def test_epw_labelling_interval_start_and_instant_values_true_time(shared_data):
    """EPW hour 1 (00:00-01:00) -> label 00:00; its temperature (at 01:00) -> label 01:00."""
    path = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    weather, _ = read_weather(path)
    rows = _epw_rows(path)
    # irradiance of EPW row k (fields 14-16) is the mean over the interval labelled k
    noon_row = 24 * 180 + 12  # EPW hour 13 of day 181: 12:00-13:00
    assert weather["ghi"].iloc[noon_row] == float(rows[noon_row][13])
    assert weather["dni"].iloc[noon_row] == float(rows[noon_row][14])
    assert weather["dhi"].iloc[noon_row] == float(rows[noon_row][15])
    assert weather.index[noon_row].hour == 12
    # temperature of EPW row k is measured at the end of its hour = the label of row k + 1
    assert weather["temp_air"].iloc[noon_row + 1] == float(rows[noon_row][6])
    assert weather["temp_air"].iloc[1] == float(rows[0][6])
    # a whole typical/actual year is cyclic: the first label takes the last row's value
    assert weather["temp_air"].iloc[0] == float(rows[-1][6])


def test_epw_irradiance_labels_agree_with_the_sun(shared_data):
    """GHI > 0 only in intervals in which the sun is up: the labels are interval starts."""
    weather, meta = read_weather(shared_data("weather_switzerland", "Zuerich-SMA_2015.epw"))
    assert _labelling_is_right(weather, meta)


@pytest.mark.parametrize("name", ["DRYCOLDTMY.epw", "725650TYCST.epw"])
def test_bestest_typical_year_epw_coerced_to_one_year(shared_data, name):
    path = shared_data("ashrae140_bestest", name)
    rows = _epw_rows(path)
    assert len({r[0] for r in rows}) > 1  # the file mixes years
    weather, meta = read_weather(path)
    assert len(weather) == 8760
    assert weather.index.is_monotonic_increasing
    assert (np.diff(weather.index.asi8) == np.diff(weather.index.asi8)[0]).all()
    year = meta["coerced_year"]
    assert set(weather.index.year) == {year}
    assert not calendar.isleap(year)
    # DATA PERIODS declares the first day a Sunday: keep weekday schedules as EnergyPlus does
    assert weather.index[0].day_name() == "Sunday"
    assert weather.index[0].utcoffset() == pd.Timedelta(hours=-7)
    assert meta["latitude"] == pytest.approx(39.76 if name.startswith("DRY") else 39.83)
    assert "ghi_infrared" in weather
    assert _daylight_violations(weather, meta) <= 1
    assert _labelling_is_right(weather, meta)
    assert weather.notna().all().all()


def test_old_epw_without_albedo_fields_has_no_albedo_column(shared_data):
    weather, _ = read_weather(shared_data("ashrae140_bestest", "DRYCOLDTMY.epw"))
    assert "albedo" not in weather  # absent from the file: absent, not faked


def test_explicit_coerce_year_and_tz_conversion(shared_data):
    path = shared_data("ashrae140_bestest", "725650TYCST.epw")
    weather, meta = read_weather(path, coerce_year=1999, tz="UTC")
    assert meta["coerced_year"] == 1999
    assert weather.index[0] == pd.Timestamp("1999-01-01 07:00", tz="UTC")


def test_a_typical_year_put_on_a_leap_year_names_the_missing_29_february(shared_data):
    """A RunPeriod's Begin Year 2016 on a TMY file without 29 February: before, 'rows are
    missing, duplicated or out of order' at line 1425 (fuzzing round 3)."""
    path = shared_data("ashrae140_bestest", "725650TYCST.epw")
    with pytest.raises(
        ThermocalInputError,
        match=r"a year without 29 February put on 2016, a leap year \(line 1425 follows 28 "
        r"February with 1 March\).*leave the RunPeriod's Begin Year blank",
    ):
        read_weather(path, coerce_year=2016)


# ---------------------------------------------------------------------------------------------
# TMY3
# ---------------------------------------------------------------------------------------------
def test_tmy3_pvlib_example():
    weather, meta = read_weather(PVLIB_TMY3)
    assert meta["format"] == "tmy3"
    assert len(weather) == 8760
    assert weather.index[0].hour == 0  # "01:00" (hour ending) -> label 00:00
    assert weather.index[0].utcoffset() == pd.Timedelta(hours=-5)
    raw = pd.read_csv(PVLIB_TMY3, skiprows=1)
    row = 24 * 180 + 12
    assert raw["Time (HH:MM)"].iloc[row] == "13:00"
    assert weather["ghi"].iloc[row] == raw["GHI (W/m^2)"].iloc[row]
    assert weather.index[row].hour == 12
    assert weather["pressure"].iloc[row + 1] == 100 * raw["Pressure (mbar)"].iloc[row]  # Pa
    assert weather["temp_air"].iloc[row + 1] == raw["Dry-bulb (C)"].iloc[row]
    assert _daylight_violations(weather, meta) == 0
    assert _labelling_is_right(weather, meta)
    assert weather.index.is_monotonic_increasing


# ---------------------------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------------------------
def _write_csv(tmp_path, text, name="w.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


CSV_TEXT = (
    "time,T_out,G_h,DNI,DHI,RH\n"
    "2019-02-02 00:00,1.0,0,0,0,80\n"
    "2019-02-02 01:00,2.0,100,200,50,81\n"
    "2019-02-02 02:00,3.0,300,400,60,82\n"
)
MAPPING = {"temp_air": "T_out", "ghi": "G_h", "dni": "DNI", "dhi": "DHI", "relative_humidity": "RH"}


def test_csv_with_mapping(tmp_path):
    path = _write_csv(tmp_path, CSV_TEXT)
    weather, meta = read_weather(
        path, columns=MAPPING, tz=1.0, metadata={"latitude": 47.4, "longitude": 8.5}
    )
    assert list(weather.columns) == ["temp_air", "relative_humidity", "ghi", "dni", "dhi"]
    assert weather.index[1] == pd.Timestamp("2019-02-02 01:00", tz="Etc/GMT-1")
    assert weather["ghi"].tolist() == [0, 100, 300]
    assert meta["latitude"] == 47.4 and meta["tz"] == 1.0 and meta["format"] == "csv"


def test_csv_hour_ending_labels_are_relabelled(tmp_path):
    path = _write_csv(tmp_path, CSV_TEXT)
    weather, _ = read_weather(path, columns=MAPPING, tz=1.0, time_label="end")
    assert weather.index[0] == pd.Timestamp("2019-02-01 23:00", tz="Etc/GMT-1")
    assert weather["ghi"].tolist() == [0, 100, 300]
    # temperature stamped 01:00 stays at 01:00 (its true time), now the label of row 2
    assert weather["temp_air"].tolist() == [1.0, 1.0, 2.0]


@pytest.mark.parametrize(
    ("text", "kwargs", "fragments"),
    [
        (CSV_TEXT, {"columns": MAPPING}, ["no time zone", "tz="]),
        (CSV_TEXT, {"columns": None, "tz": 1}, ["column mapping"]),
        (CSV_TEXT, {"columns": {**MAPPING, "temp_air": "Tout"}, "tz": 1}, ["'Tout'", "T_out"]),
        (CSV_TEXT, {"columns": {"temperature": "T_out"}, "tz": 1}, ["temperature", "temp_air"]),
        (
            CSV_TEXT.replace("2.0,100", "275.1,100")
            .replace("1.0,0", "274.1,0")
            .replace("3.0,300", "276.2,300"),
            {"columns": MAPPING, "tz": 1},
            ["'T_out'", "line 2", "Kelvin"],
        ),
        (
            CSV_TEXT.replace("3.0,300", "x,300"),
            {"columns": MAPPING, "tz": 1},
            ["'T_out'", "line 4", "'x'", "not a number"],
        ),
        (
            CSV_TEXT.replace("02:00,3.0", "01:00,3.0"),
            {"columns": MAPPING, "tz": 1},
            ["line 4", "duplicated"],
        ),
        (
            CSV_TEXT.replace("02:00,3.0", "03:00,3.0"),
            {"columns": MAPPING, "tz": 1},
            ["line 4", "regular grid"],
        ),
        (
            CSV_TEXT.replace("2019-02-02 01:00", "yesterday"),
            {"columns": MAPPING, "tz": 1},
            ["'time'", "line 3", "yesterday"],
        ),
        (CSV_TEXT, {"columns": MAPPING, "tz": "Mars/Olympus"}, ["Mars/Olympus"]),
    ],
)
def test_csv_bad_input_messages(tmp_path, text, kwargs, fragments):
    path = _write_csv(tmp_path, text)
    with pytest.raises(ThermocalInputError) as info:
        read_weather(path, **kwargs)
    message = str(info.value)
    assert str(path) in message
    for fragment in fragments:
        assert fragment in message


def test_csv_relative_humidity_fraction_is_refused(tmp_path):
    text = (
        CSV_TEXT.replace(",80\n", ",0.8\n").replace(",81\n", ",0.81\n").replace(",82\n", ",0.7\n")
    )
    with pytest.raises(ThermocalInputError, match="fraction"):
        read_weather(_write_csv(tmp_path, text), columns=MAPPING, tz=1)


# ---------------------------------------------------------------------------------------------
# bad EPW / TMY3 files
# ---------------------------------------------------------------------------------------------
def _corrupt_copy(source: Path, tmp_path: Path, line_number: int, new_line: str | None) -> Path:
    lines = source.read_text().splitlines()
    if new_line is None:
        del lines[line_number - 1]
    else:
        lines[line_number - 1] = new_line
    target = tmp_path / source.name
    target.write_text("\n".join(lines) + "\n")
    return target


def test_epw_non_numeric_field_names_line(shared_data, tmp_path):
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    line = source.read_text().splitlines()[99].split(",")
    line[6] = "warm"
    path = _corrupt_copy(source, tmp_path, 100, ",".join(line))
    with pytest.raises(ThermocalInputError) as info:
        read_weather(path)
    assert "line 100" in str(info.value) and "'warm'" in str(info.value)
    assert "temp_air" in str(info.value) and str(path) in str(info.value)


def test_epw_missing_row_names_line(shared_data, tmp_path):
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    path = _corrupt_copy(source, tmp_path, 500, None)
    with pytest.raises(ThermocalInputError) as info:
        read_weather(path)
    assert "line 500" in str(info.value) and "missing" in str(info.value)


def test_epw_truncated_line_names_line(shared_data, tmp_path):
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    path = _corrupt_copy(source, tmp_path, 300, "2015,1,13")
    with pytest.raises(ThermocalInputError) as info:
        read_weather(path)
    assert "line 300" in str(info.value)


def test_epw_missing_codes_become_nan(shared_data, tmp_path):
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    line = source.read_text().splitlines()[99].split(",")
    line[6] = "99.9"  # EPW code for a missing dry-bulb temperature
    path = _corrupt_copy(source, tmp_path, 100, ",".join(line))
    weather, meta = read_weather(path)
    assert meta["missing"] == {"temp_air": 1}
    assert np.isnan(weather["temp_air"].iloc[100 - 9 + 1])  # data row 91 -> true time: row 92


def test_tmy3_bad_time_names_line(tmp_path):
    lines = PVLIB_TMY3.read_text().splitlines()
    lines[11] = lines[11].replace("10:00", "1O:00", 1)
    path = tmp_path / "bad_tmy3.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ThermocalInputError) as info:
        read_weather(path, format="tmy3")
    assert "line 12" in str(info.value)


def test_unknown_file_and_format(tmp_path):
    with pytest.raises(ThermocalInputError, match="does not exist"):
        read_weather(tmp_path / "nope.epw")
    path = tmp_path / "weather.dat"
    path.write_text("hello\n")
    with pytest.raises(ThermocalInputError, match="format="):
        read_weather(path)


# ---------------------------------------------------------------------------------------------
# resampling
# ---------------------------------------------------------------------------------------------
def test_resample_hourly_to_5min_and_back(shared_data):
    weather, _ = read_weather(shared_data("weather_switzerland", "Zuerich-SMA_2015.epw"))
    fine = resample_weather(weather, "5min")
    assert len(fine) == 12 * 8760
    assert fine.index[-1] == weather.index[-1] + pd.Timedelta(minutes=55)
    # irradiance: interval means, energy conserved, constant within the hour
    assert fine["ghi"].sum() / 12 == pytest.approx(weather["ghi"].sum(), rel=1e-12)
    assert (fine["dni"].iloc[12 * 4000 : 12 * 4001] == weather["dni"].iloc[4000]).all()
    # temperatures: linear interpolation between instantaneous values
    t0, t1 = weather["temp_air"].iloc[4000], weather["temp_air"].iloc[4001]
    assert fine["temp_air"].iloc[12 * 4000 + 6] == pytest.approx(0.5 * (t0 + t1))
    assert fine["temp_air"].iloc[12 * 4000 + 3] == pytest.approx(0.75 * t0 + 0.25 * t1)
    back = resample_weather(fine, "1h")
    pd.testing.assert_series_equal(back["ghi"], weather["ghi"], check_freq=False)
    pd.testing.assert_series_equal(back["temp_air"], weather["temp_air"], check_freq=False)


def test_resample_wind_direction_is_circular():
    index = pd.date_range("2020-01-01", periods=2, freq="1h", tz="UTC")
    weather = pd.DataFrame({"wind_direction": [350.0, 10.0], "ghi": [0.0, 120.0]}, index=index)
    fine = resample_weather(weather, "30min")
    assert fine["wind_direction"].iloc[1] == pytest.approx(0.0, abs=1e-9) or fine[
        "wind_direction"
    ].iloc[1] == pytest.approx(360.0)
    assert fine["ghi"].tolist() == [0.0, 0.0, 120.0, 120.0]


def test_resample_to_non_dividing_step_conserves_energy():
    index = pd.date_range("2020-01-01", periods=6, freq="1h", tz="UTC")
    weather = pd.DataFrame({"ghi": [0.0, 60.0, 120.0, 0.0, 30.0, 90.0]}, index=index)
    coarse = resample_weather(weather, "90min")
    # [0, 1.5h): (0 * 1 + 60 * 0.5) / 1.5 = 20; [3h, 4.5h): (0 * 1 + 30 * 0.5) / 1.5 = 10
    assert coarse["ghi"].tolist() == pytest.approx([20.0, 100.0, 10.0, 70.0])


def test_resample_missing_irradiance_is_not_filled():
    index = pd.date_range("2020-01-01", periods=4, freq="1h", tz="UTC")
    weather = pd.DataFrame(
        {"ghi": [10.0, np.nan, 30.0, 40.0], "temp_air": [0.0, np.nan, 2.0, 3.0]}, index=index
    )
    fine = resample_weather(weather, "30min")
    assert np.isnan(fine["ghi"].iloc[2:4]).all()
    assert np.isnan(fine["temp_air"].iloc[1:4]).all()
    assert fine["temp_air"].iloc[4] == 2.0


def test_resample_bad_step():
    index = pd.date_range("2020-01-01", periods=3, freq="1h", tz="UTC")
    weather = pd.DataFrame({"ghi": [1.0, 2.0, 3.0]}, index=index)
    with pytest.raises(ThermocalInputError, match="step"):
        resample_weather(weather, "fortnightly-ish")


def test_subhourly_epw(shared_data, tmp_path):
    """4 records per hour (DATA PERIODS field 2): minute 15 ends the interval 00:00-00:15."""
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    lines = source.read_text().splitlines()
    header = lines[:8]
    header[7] = header[7].replace("DATA PERIODS,1,1,", "DATA PERIODS,1,4,")
    data = []
    for line in lines[8 : 8 + 48]:
        fields = line.split(",")
        for k, minute in enumerate((15, 30, 45, 60)):
            fields[4] = str(minute)
            fields[13] = str(100 * k)  # ghi: 0, 100, 200, 300 within each hour
            data.append(",".join(fields))
    path = tmp_path / "subhourly.epw"
    path.write_text("\n".join(header + data) + "\n")
    weather, meta = read_weather(path)
    assert meta["step"] == pd.Timedelta(minutes=15)
    assert len(weather) == 48 * 4
    assert weather.index[1] - weather.index[0] == pd.Timedelta(minutes=15)
    assert weather.index[0] == pd.Timestamp("2015-01-01 00:00", tz="Etc/GMT-1")
    assert weather["ghi"].iloc[:4].tolist() == [0, 100, 200, 300]
    hourly = resample_weather(weather, "1h")
    assert hourly["ghi"].iloc[0] == pytest.approx(150.0)


def test_csv_with_offsets_across_dst_change(tmp_path):
    text = (
        "time,T_out\n"
        "2019-03-31T01:00+01:00,1.0\n"
        "2019-03-31T03:00+02:00,2.0\n"
        "2019-03-31T04:00+02:00,3.0\n"
    )
    path = _write_csv(tmp_path, text)
    weather, meta = read_weather(path, columns={"temp_air": "T_out"}, tz=1.0)
    assert weather.index[1] == pd.Timestamp("2019-03-31 02:00", tz="Etc/GMT-1")
    assert meta["step"] == pd.Timedelta(hours=1)


def test_epw_holidays_and_daylight_saving_header(shared_data, tmp_path):
    """The HOLIDAYS/DAYLIGHT SAVINGS line: DST start/end and (name, date) pairs as written."""
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    _, meta = read_weather(source)  # the file's 'No,0,0,0': no holidays, no DST
    assert meta["holidays"] == [] and meta["daylight_saving"] is None
    line = (
        "HOLIDAYS/DAYLIGHT SAVINGS,No,2nd Sunday in March,1st Sunday in November,5,"
        "New Years Day,1/1,Memorial Day,Last Monday in May,Independence Day,Jul 4,"
        "MLK Day,3rd Monday in January,Thanksgiving,4 Thursday in November"
    )
    weather, meta = read_weather(_corrupt_copy(source, tmp_path, 5, line))
    assert meta["daylight_saving"] == ("2nd Sunday in March", "1st Sunday in November")
    assert meta["holidays"] == [
        ("New Years Day", "1/1"),
        ("Memorial Day", "Last Monday in May"),
        ("Independence Day", "Jul 4"),
        ("MLK Day", "3rd Monday in January"),
        ("Thanksgiving", "4 Thursday in November"),
    ]
    assert len(weather) == 8760 and meta["latitude"] == pytest.approx(47.378)
    # a count larger than the pairs given keeps the pairs there are; DST '4/2,0' is none
    line = "HOLIDAYS/DAYLIGHT SAVINGS,No,4/2,0,3,Xmas,12/25"
    _, meta = read_weather(_corrupt_copy(source, tmp_path, 5, line))
    assert meta["holidays"] == [("Xmas", "12/25")] and meta["daylight_saving"] is None
