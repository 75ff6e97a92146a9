"""Sensor-log formats and a stale building site, from where the user stands.

Before: the command line could not read a decimal-comma log, US 12-hour stamps or interval means
labelled by their end (the Python reader could), and its messages said "pass time_format=",
which only exists in Python; a building more than 300 km from its weather was refused with no
way to do what EnergyPlus does (use the weather file's site).
"""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
from test_bad_input_table import _building_yaml, run

from conftest import shared_data_path
from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import read_measurements
from thermocal.io.weather import building_site_or_weather
from thermocal.multizone.model import Location

TMY3 = __import__("pathlib").Path(__import__("pvlib").__file__).parent / "data" / "723170TYA.CSV"
ZURICH = {"latitude": 47.38, "longitude": 8.57, "altitude": 556.0, "name": "Zurich-Kloten"}


# ------------------------------------------------------------------------------------------
# 12-hour clocks are recognised
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("stamps", "order"),
    [
        (["01/13/2023 11:55 PM", "01/14/2023 12:00 AM", "01/14/2023 12:05 AM",
          "01/14/2023 12:00 PM"], "month-first"),
        (["1/13/2023 11:55:00 pm", "1/14/2023 12:00:00 am", "1/14/2023 12:05:00 am",
          "1/14/2023 12:00:00 pm"], "month-first"),
        (["13.01.2023 11:55PM", "14.01.2023 12:00AM", "14.01.2023 12:05AM",
          "14.01.2023 12:00PM"], "day-first"),
    ],
    ids=["us-excel", "seconds-lower-case", "day-first-no-space"],
)
def test_twelve_hour_stamps_are_read(tmp_path, stamps, order):
    path = tmp_path / "log.csv"
    pd.DataFrame({"time": stamps, "T1": [20.0, 20.1, 20.2, 20.3]}).to_csv(path, index=False)
    raw, meta = read_measurements(path, tz=-5)
    assert [t.strftime("%d %H:%M") for t in raw.index] == [
        "13 23:55", "14 00:00", "14 00:05", "14 12:00"
    ]  # fmt: skip
    assert any(f"dates read {order}" in note and "%I:%M" in note for note in meta["notes"])


# ------------------------------------------------------------------------------------------
# identify: --decimal, --time-format, --rows
# ------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict:
    d = tmp_path_factory.mktemp("logs")
    f = {"building": d / "two_rooms.yaml", "mapping": d / "mapping.yaml"}
    f["building"].write_text(_building_yaml())
    f["mapping"].write_text("sensors: {S1: living, S2: kitchen}\n")
    times = pd.date_range("2015-02-02", periods=12 * 12, freq="5min")  # 12 h: refused later
    rng = np.random.default_rng(3)
    values = {"S1": 21 + rng.normal(0, 0.1, len(times)), "S2": 20 + rng.normal(0, 0.1, len(times))}
    frame = pd.DataFrame({"time": times.astype(str), **values})
    f["iso"] = d / "iso.csv"
    frame.to_csv(f["iso"], index=False)
    f["comma"] = d / "comma.csv"
    frame.to_csv(f["comma"], index=False, sep=";", decimal=",")
    f["dots"] = d / "dots.csv"  # a form the reader does not recognise
    frame.assign(time=times.strftime("%d-%b-%Y %H.%M")).to_csv(f["dots"], index=False)
    return f


def _identify(files, log, extra, capsys, tmp_path, weather=None) -> tuple[int, str]:
    weather = weather or shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
    status, text = run(
        ["identify", files["building"], weather, files[log], "--mapping", files["mapping"],
         "--out", tmp_path / "out", "--method", "inverse", "--tz", "1", *extra],
        capsys,
    )  # fmt: skip
    return status, " ".join(text.split())


READ = r"is 11\.\d h; identification needs at least 2 days"  # the log was read


@pytest.mark.parametrize(
    ("log", "extra", "patterns", "absent"),
    [
        ("comma", [], [r"cannot read '21,\d+' as a number \(a decimal comma: pass --decimal ,\)"],
         "decimal="),
        ("comma", ["--decimal", ","], [READ], None),
        ("dots", [], [r"cannot read '02-Feb-2015 00\.00' as a time; use ISO 8601.*or pass "
                      r"--time-format \(e\.g\. '%d\.%m\.%Y %H:%M'\)"], "time_format="),
        ("dots", ["--time-format", "%d-%b-%Y %H.%M"], [READ], None),
        ("iso", ["--rows", "interval_end"], [READ], None),
        ("iso", ["--rows", "end"], [r"--rows 'end': use reports, interval_start, interval_end"],
         None),
        ("iso", ["--decimal", ";"], [r"--decimal ';': use \. or ,"], None),
    ],
    ids=["comma-named", "comma-read", "format-named", "format-read", "interval-end",
         "rows-unknown", "decimal-unknown"],
)  # fmt: skip
def test_identify_reads_the_log_as_told(files, tmp_path, capsys, log, extra, patterns, absent):
    status, text = _identify(files, log, extra, capsys, tmp_path)
    assert status == 2, text
    for pattern in patterns:
        assert re.search(pattern, text), f"{pattern!r} not in: {text}"
    if absent:
        assert absent not in text, text


def test_identify_labels_interval_means_by_their_end(files):
    """--rows interval_end moves every row back by the logging interval (the reader's)."""
    raw, meta = read_measurements(files["iso"], tz=1, rows="interval_end")
    assert str(raw.index[0]) == "2015-02-01 23:55:00+01:00"
    assert any("moved back by 0 days 00:05:00" in note for note in meta["notes"])


# ------------------------------------------------------------------------------------------
# calibrate's campaign and retrofit's configuration have the same options as keys
# ------------------------------------------------------------------------------------------
def test_campaign_identification_keys_read_the_log(files):
    from thermocal.calibration.inputs import identification_options, load_inputs

    def campaign(**identification):
        return SimpleNamespace(
            is_demo=False, path="campaign.yaml", building=files["building"],
            building_path=files["building"], mapping=files["mapping"],
            weather=shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"),
            sensors=files["comma"], identification={"tz": 1, **identification}, period=None,
            step_timedelta=lambda: pd.Timedelta("5min"),
        )  # fmt: skip

    with pytest.raises(ThermocalInputError, match=r"set identification\.decimal: ','") as info:
        load_inputs(campaign())
    assert "decimal=" not in str(info.value)
    inputs = load_inputs(campaign(decimal=","))
    assert inputs.sensor_log.shape == (144, 2)
    with pytest.raises(ThermocalInputError, match=r"identification\.rows 'end': use reports"):
        load_inputs(campaign(decimal=",", rows="end"))
    options = identification_options(
        campaign(decimal=",", time_format="%d", rows="interval_end", site="weather")
    )
    assert not {"tz", "decimal", "time_format", "rows", "site"} & set(options)


def test_retrofit_measurements_keys_read_the_file(tmp_path):
    from thermocal.retrofit.config import MeasurementsConfig
    from thermocal.retrofit.data import read_raw_measurements

    times = pd.date_range("2021-01-04", periods=48, freq="h")
    frame = pd.DataFrame(
        {"time": times.strftime("%m/%d/%Y %I:%M %p"), "temp_out": 2.5, "flow": 0.0001,
         "temp_supply": 45.5, "temp_return": 35.5, "dni": 0.0, "dhi": 0.0, "temp_in": 20.5}
    )  # fmt: skip
    path = tmp_path / "m.csv"
    frame.to_csv(path, index=False, sep=";", decimal=",")
    cfg = {"file": path, "timezone": 1}
    with pytest.raises(ThermocalInputError, match=r"set measurements\.decimal: ','"):
        read_raw_measurements(MeasurementsConfig(**cfg))
    raw = read_raw_measurements(MeasurementsConfig(**cfg, decimal=","))
    assert raw["temp_in"].iloc[0] == 20.5
    assert str(raw.index[0]) == "2021-01-04 00:00:00+01:00"  # 12:00 AM, month-first
    end = read_raw_measurements(MeasurementsConfig(**cfg, decimal=",", rows="interval_end"))
    assert str(end.index[0]) == "2021-01-03 23:00:00+01:00"
    dotted = tmp_path / "dots.csv"
    frame.assign(time=times.strftime("%d-%b-%Y %H.%M")).to_csv(dotted, index=False)
    with pytest.raises(ThermocalInputError, match=r"or set measurements\.time_format"):
        read_raw_measurements(MeasurementsConfig(file=dotted, timezone=1))
    raw = read_raw_measurements(
        MeasurementsConfig(file=dotted, timezone=1, time_format="%d-%b-%Y %H.%M")
    )
    assert len(raw) == 48


# ------------------------------------------------------------------------------------------
# a building far from its weather: refused, or the weather's site on request
# ------------------------------------------------------------------------------------------
def _far():
    return SimpleNamespace(location=Location(latitude=35.8, longitude=-78.6, timezone=-5))


def test_site_far_from_the_weather_is_refused_naming_the_opt_in():
    with pytest.raises(ThermocalInputError) as info:
        building_site_or_weather(
            _far(), ZURICH, "building", building_source="house.idf", weather_source="zrh.epw",
            option="--site", opt_in="--site weather",
        )  # fmt: skip
    message = str(info.value)
    assert "6,980 km apart (at most 300 km accepted)" in message
    assert "--site weather runs at the weather file's site" in message


def test_site_weather_replaces_the_building_site_and_says_so():
    building = _far()
    note = building_site_or_weather(
        building, ZURICH, "weather", building_source="house.idf", weather_source="zrh.epw",
        option="--site", opt_in="--site weather",
    )  # fmt: skip
    assert note.startswith("site replaced (--site weather): the building (house.idf)")
    assert "6,980 km apart" in note and "as EnergyPlus does" in note
    loc = building.location
    assert (loc.latitude, loc.longitude, loc.altitude, loc.timezone) == (47.38, 8.57, 556.0, -5)
    near = SimpleNamespace(location=Location(latitude=47.05, longitude=8.31))
    assert (
        building_site_or_weather(
            near, ZURICH, "weather", building_source="b", weather_source="w",
            option="--site", opt_in="--site weather",
        )  # fmt: skip
        is None
    )
    assert near.location.latitude == 47.05
    with pytest.raises(ThermocalInputError, match=r"identification\.site 'here': use building"):
        building_site_or_weather(
            near, ZURICH, "here", building_source="b", weather_source="w",
            option="identification.site", opt_in="identification.site: weather",
        )  # fmt: skip


def test_identify_site_option(files, tmp_path, capsys):
    """A Zurich building with Greensboro weather: refused naming --site weather; with it, the
    run goes on (to the short log's refusal) after a warning that the site was replaced."""
    status, text = _identify(files, "iso", [], capsys, tmp_path, weather=TMY3)
    assert status == 2
    assert "km apart" in text and "--site weather runs at the weather file's site" in text, text
    status, text = _identify(files, "iso", ["--site", "weather"], capsys, tmp_path, weather=TMY3)
    assert status == 2, text
    assert "site replaced (--site weather)" in text, text
    assert re.search(READ, text), text
    status, text = _identify(files, "iso", ["--site", "x"], capsys, tmp_path, weather=TMY3)
    assert status == 2 and "--site 'x': use building" in text, text
