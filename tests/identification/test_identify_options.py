"""``thermocal identify``: options that contradict the method or the sensor log, and the
occupancy schedule's holidays.

A 12-zone clinic, two days of a made-up sensor log (every zone's air at 20 C +- 1 K with its
own phase) and the pvlib TMY3 file keep every run to a few seconds.
"""

from __future__ import annotations

import datetime as dt

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from thermocal.cli import app
from thermocal.errors import ThermocalInputError
from thermocal.identification.occupancy import OccupancySchedule

START, END = "2001-01-08", "2001-01-10"


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """building.yaml, sensors.csv (ISO stamps with offsets), naive.csv (the same local times
    without offsets), numeric.csv (Unix seconds) and mapping.yaml of the small clinic; returns
    the folder and the weather file."""
    from thermocal.demos import buildings as generators
    from thermocal.demos.retrofit import pvlib_weather_path
    from thermocal.io.weather import read_weather
    from thermocal.multizone.files import save_building
    from thermocal.multizone.model import Location

    folder = tmp_path_factory.mktemp("identify_options")
    weather = pvlib_weather_path()
    _, meta = read_weather(weather)
    site = Location(meta["latitude"], meta["longitude"], meta.get("altitude") or 0.0)
    building = generators.clinic(12, n_corridors=1, corridor_sections=2, location=site)
    save_building(building, folder / "building.yaml")
    times = pd.date_range("2001-01-07 12:00", "2001-01-10 12:00", freq="5min", tz="-05:00")
    hours = np.arange(len(times)) / 12.0
    zones = list(building.zones)
    log = pd.DataFrame(
        {
            f"S{i:02d}": 20.0 + np.sin(2 * np.pi * (hours / 24.0 + i / len(zones)))
            for i in range(len(zones))
        },
        index=pd.Index(times, name="time"),
    )
    log.to_csv(folder / "sensors.csv", date_format="%Y-%m-%dT%H:%M:%S%z")
    log.to_csv(folder / "naive.csv", date_format="%Y-%m-%dT%H:%M:%S")
    numeric = log.copy()
    numeric.index = pd.Index(times.as_unit("s").asi8, name="time")
    numeric.to_csv(folder / "numeric.csv")
    (folder / "mapping.yaml").write_text(
        "sensors:\n" + "".join(f"  S{i:02d}: {zone}\n" for i, zone in enumerate(zones))
    )
    return folder, weather


def _identify(inputs, tmp_path, *options, log="sensors.csv"):
    folder, weather = inputs
    args = [
        "identify",
        str(folder / "building.yaml"),
        str(weather),
        str(folder / log),
        "--mapping",
        str(folder / "mapping.yaml"),
        "--out",
        str(tmp_path / "out"),
        "--start",
        START,
        "--end",
        END,
        *options,
    ]
    return CliRunner().invoke(app, args, terminal_width=200)


def _refused(result) -> str:
    assert isinstance(result.exception, ThermocalInputError), (result.exception, result.output)
    return str(result.exception)


# -- options only the PID loop uses -------------------------------------------------------------


def test_an_unknown_tuning_zone_is_refused_with_close_names(inputs, tmp_path):
    """--method both with a zone that does not exist was a KeyError after the inverse ran."""
    message = _refused(_identify(inputs, tmp_path, "--tuning-zone", "Room 99", "--method", "both"))
    assert "'Room 99'" in message and "did you mean" in message and "'Room 9'" in message


@pytest.mark.parametrize(
    ("option", "value"), [("--tuning-zone", "Room 9999"), ("--limits", "0,1000")]
)
def test_a_pid_option_with_the_inverse_method_is_refused(inputs, tmp_path, option, value):
    """The exact inverse has no tuning and no output limits: the option was silently ignored."""
    message = _refused(_identify(inputs, tmp_path, option, value, "--method", "inverse"))
    assert option in message and "--method inverse" in message
    assert "--method pid or both" in message


def test_the_python_api_refuses_pid_options_with_the_inverse_method():
    from thermocal.identification.workflow import check_pid_only_options

    with pytest.raises(ThermocalInputError, match=r"limits only applies to the PID loop"):
        check_pid_only_options("inverse", {"tuning_zone": None, "limits": (0.0, 1e3)})
    check_pid_only_options("both", {"tuning_zone": "Room 1", "limits": (0.0, 1e3)})


def test_an_unknown_tuning_zone_in_pid_gains_is_refused():
    """pid_gains_for (identify, a campaign's PID problem) read the zone's form before the
    tuning checked the name: a KeyError."""
    from thermocal.demos import buildings as generators
    from thermocal.identification.workflow import pid_gains_for

    building = generators.clinic(12, n_corridors=1, corridor_sections=2)
    form = pd.Series(0.0, index=list(building.zones))
    with pytest.raises(ThermocalInputError, match=r"tuning zone 'Room 99' is not a zone"):
        pid_gains_for(
            building, gains=None, step="5min", feedback=form, radiant_fraction=form,
            tuning_zone="Room 99",
        )  # fmt: skip


# -- the sensor log's time options --------------------------------------------------------------


@pytest.mark.parametrize(
    ("option", "value"), [("--time-unit", "s"), ("--time-origin", "2001-01-01")]
)
def test_numeric_time_options_with_text_stamps_are_refused(inputs, tmp_path, option, value):
    message = _refused(_identify(inputs, tmp_path, option, value, "--method", "inverse"))
    assert option in message and "sensors.csv" in message
    assert "2001-01-07 12:00:00-05:00" in message  # the log's first time stamp


def test_the_time_unit_of_a_numeric_log_is_used(inputs, tmp_path):
    result = _identify(inputs, tmp_path, "--time-unit", "s", "--method", "inverse",
                       log="numeric.csv")  # fmt: skip
    assert result.exit_code == 0, (result.exception, result.output)


def test_tz_with_offset_stamps_is_a_warning(inputs, tmp_path):
    """The offsets fix the instants; --tz only places stamps written without one."""
    result = _identify(inputs, tmp_path, "--tz", "Europe/Zurich", "--method", "inverse")
    assert result.exit_code == 0, (result.exception, result.output)
    text = " ".join(result.output.split())
    assert "warning:" in text and "--tz Europe/Zurich has no effect" in text
    assert "carry UTC offsets" in text


def test_tz_with_naive_stamps_is_used_without_a_warning(inputs, tmp_path):
    result = _identify(inputs, tmp_path, "--tz", "-5", "--method", "inverse", log="naive.csv")
    assert result.exit_code == 0, (result.exception, result.output)
    assert "has no effect" not in result.output


@pytest.mark.parametrize(
    "option", ["--max-gap=-1h", "--max-gap=abc", "--silence=-5min", "--silence=1", "--step=5"]
)
def test_a_negative_or_unreadable_gap_duration_is_refused(inputs, tmp_path, option):
    name, value = option.split("=")
    message = _refused(_identify(inputs, tmp_path, option, "--method", "inverse"))
    assert name in message and repr(value) in message


def test_gap_durations_in_python():
    from thermocal.identification.workflow import gap_duration

    assert gap_duration("0min", "max_gap", zero_allowed=True) == pd.Timedelta(0)
    assert gap_duration(pd.Timedelta("2h"), "max_gap", zero_allowed=True) == pd.Timedelta("2h")
    with pytest.raises(ThermocalInputError, match=r"silence '0s' must be positive"):
        gap_duration("0s", "silence", zero_allowed=False)
    with pytest.raises(ThermocalInputError, match=r"max_gap '-1h' must not be negative"):
        gap_duration("-1h", "max_gap", zero_allowed=True)
    # a bare number was read as nanoseconds (a silence of 1 ns, "--silence 0min" in the warning)
    with pytest.raises(ThermocalInputError, match=r"silence '1' has no unit .*'1min' or '1h'"):
        gap_duration("1", "silence", zero_allowed=False)
    with pytest.raises(ThermocalInputError, match=r"max_gap 2.5 has no unit"):
        gap_duration(2.5, "max_gap", zero_allowed=True)
    assert gap_duration("0", "max_gap", zero_allowed=True) == pd.Timedelta(0)  # 0 in any unit
    import numpy as np

    assert gap_duration(np.timedelta64(2, "h"), "max_gap", zero_allowed=True) == pd.Timedelta(
        "2h"
    )  # numpy's timedelta has its unit (an integer subclass: it raised TypeError)


# -- holidays of the occupancy schedule ---------------------------------------------------------


def _holidays(*entries):
    return OccupancySchedule.from_dict(
        {"holidays": list(entries)}, source="occ.yaml: occupancy"
    ).holidays


def test_an_ambiguous_numeric_holiday_is_refused():
    """01/09/2001 was read month-first (9 January): a working day counted as unoccupied."""
    with pytest.raises(ThermocalInputError) as caught:
        _holidays("01/09/2001")
    message = str(caught.value)
    for fragment in ("occ.yaml: occupancy.holidays[0]", "'01/09/2001'", "2001-09-01",
                     "2001-01-09", "YYYY-MM-DD"):  # fmt: skip
        assert fragment in message, message


def test_unambiguous_holidays_are_read():
    assert _holidays("25/12/2001", "12.25.2001", "05/05/2001", "2001-1-9") == (
        dt.date(2001, 12, 25),
        dt.date(2001, 12, 25),
        dt.date(2001, 5, 5),
        dt.date(2001, 1, 9),
    )
    assert _holidays(dt.date(2001, 1, 1), dt.datetime(2001, 1, 2)) == (
        dt.date(2001, 1, 1),
        dt.date(2001, 1, 2),
    )
    # review: other unambiguous forms read before the ambiguity check stay readable
    forms = ("2001-01-15 00:00", "2001-01-15T00:00", "15 January 2001", "Jan 15 2001", "20010115")
    assert _holidays(*forms) == (dt.date(2001, 1, 15),) * len(forms)


@pytest.mark.parametrize(
    ("entry", "reason"),
    [("2001-13-01", "month must be in 1..12"), ("2023-02-30", "day is out of range"),
     ("31/31/2001", "neither"), ("2001", "YYYY-MM-DD"), ("next monday", "YYYY-MM-DD")],
)  # fmt: skip
def test_a_holiday_that_is_no_date_is_refused_naming_it(entry, reason):
    with pytest.raises(ThermocalInputError) as caught:
        _holidays("2001-01-01", entry)
    message = str(caught.value)
    assert "occ.yaml: occupancy.holidays[1]" in message and repr(entry) in message
    assert reason in message


def test_holidays_must_be_a_list():
    with pytest.raises(ThermocalInputError, match=r"holidays: expected a list of dates"):
        OccupancySchedule.from_dict({"holidays": "2001-01-01"}, source="occ.yaml")


def test_the_occupancy_file_names_its_holiday(inputs, tmp_path):
    """The command's own file: the message names the file, the key and the entry."""
    occupancy = tmp_path / "occ.yaml"
    occupancy.write_text("occupancy:\n  holidays: [01/09/2001]\n")
    message = _refused(
        _identify(inputs, tmp_path, "--occupancy", str(occupancy), "--method", "inverse")
    )
    assert f"{occupancy}: occupancy.holidays[0] = '01/09/2001'" in message


@pytest.mark.parametrize("entry", ["2001-13-01", "2023-02-30"])
def test_an_impossible_unquoted_holiday_is_refused_naming_it(tmp_path, entry):
    """YAML reads an unquoted 2001-13-01 as a date and PyYAML's datetime.date raised a bare
    ValueError: an internal error of identify and calibrate (/tmp/fuzz4/y06_occ_25h,
    k51_occ_bad_holiday). The reader keeps such a scalar as text, as if quoted."""
    from thermocal.identification.occupancy import OccupancySchedule
    from thermocal.io.yamlfile import read_yaml

    path = tmp_path / "occ.yaml"
    path.write_text(f"occupancy:\n  holidays: [2001-01-01, {entry}]\n")
    data = read_yaml(path, what="occupancy file")
    with pytest.raises(ThermocalInputError, match=rf"holidays\[1\] = '{entry}' is not a date"):
        OccupancySchedule.from_dict(data["occupancy"], source=f"{path}: occupancy")


def test_tz_with_a_day_first_naive_log_is_used_without_a_warning():
    """Review: the reader's note for a day-first log starts with the date order, then says the
    stamps were placed in the zone; the check looked only at the note's start and told such a
    log that --tz had no effect."""
    from thermocal.commands.identify import _check_time_options

    index = pd.date_range("2001-01-13", periods=2, freq="h", tz="-05:00")
    raw = pd.DataFrame({"S1": [20.0, 20.1]}, index=index)
    note = ("dates read day-first (13/01/2001 has a day above 12); time stamps without offset "
            "interpreted in America/New_York")  # fmt: skip
    meta = {"notes": [note]}
    assert _check_time_options(raw, meta, "log.csv", tz="America/New_York", time_unit=None,
                               time_origin=None) is None
