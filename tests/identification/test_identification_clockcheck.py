"""``thermocal identify`` checks the sensor log's clock as ``thermocal calibrate`` does
(:mod:`thermocal.calibration.clockcheck`), on a building thermocal did not write: NREL's
5ZoneAirCooled, the nominal IDF without its loads and the log EnergyPlus wrote of its hidden
envelope (``tests/reference/calibration_energyplus_5zone``: ``sensors.csv.gz``, stamped with
the UTC offset).

Before, a log an hour off was identified without a word: its identified heat is the heat a
wrong timing needs. Measured 2026-11-30 on these five January days (exact inverse, the paper's
unoccupied hours, kW of the building's unoccupied standard deviation): the log as written
0.464 (-1 h 1.649, +1 h 1.608); the same log with its stamps an hour late 1.608 as written,
0.464 shifted back, a LogClockWarning.
"""

from __future__ import annotations

import gzip
import json
import shutil
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from conftest import requires_energyplus, shared_data_path
from thermocal.cli import app

REFERENCE = Path(__file__).resolve().parents[1] / "reference" / "calibration_energyplus_5zone"
#: Wednesday to Monday, one weekend: the check compares the period less 3 h at each end
START, END = "2023-01-04", "2023-01-09"


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """nominal.idf, weather.epw, mapping.yaml, the committed log (sensors.csv) and the same log
    with every time stamp an hour late (late.csv), as a logger on the wrong offset writes it."""
    from thermocal.multizone.energyplus import energyplus_weather_folder

    shared = shared_data_path("energyplus_reference")
    sys.path.insert(0, str(REFERENCE))
    sys.modules.pop("make_reference", None)  # other reference folders have one too
    try:
        from make_reference import nominal_envelope
    finally:
        sys.path.remove(str(REFERENCE))
    folder = tmp_path_factory.mktemp("identify_clock")
    nominal_envelope(folder / "nominal.idf", shared)
    weather = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    shutil.copy(weather, folder / "weather.epw")
    shutil.copy(REFERENCE / "mapping.yaml", folder / "mapping.yaml")
    with gzip.open(REFERENCE / "sensors.csv.gz", "rb") as fh:
        (folder / "sensors.csv").write_bytes(fh.read())
    log = pd.read_csv(folder / "sensors.csv")
    late = pd.to_datetime(log["time"]) + pd.Timedelta(hours=1)
    log.assign(time=late.dt.strftime("%Y-%m-%dT%H:%M:%S%z")).to_csv(
        folder / "late.csv", index=False
    )
    times = pd.to_datetime(log["time"])  # the clock an hour on from 6 January noon (a switch)
    after = (times >= pd.Timestamp("2023-01-06 12:00-06:00")).astype(int)
    switched = times + pd.to_timedelta(after, unit="h")
    log.assign(time=switched.dt.strftime("%Y-%m-%dT%H:%M:%S%z")).to_csv(
        folder / "switch.csv", index=False
    )
    return folder


def _identify(folder: Path, out: Path, log: str, *options, start=START, end=END,
              idf="nominal.idf", weather=None):  # fmt: skip
    weather = weather or folder / "weather.epw"
    args = [
        "identify", str(folder / idf), str(weather), str(folder / log),
        "--mapping", str(folder / "mapping.yaml"), "--out", str(out), "--method", "inverse",
        "--start", start, "--end", end, *options,
    ]  # fmt: skip
    result = CliRunner().invoke(app, args, terminal_width=200)
    assert result.exit_code == 0, (result.exception, result.output)
    summary = json.loads((out / "identification.json").read_text())
    return " ".join(result.output.split()), summary


@requires_energyplus
def test_a_log_an_hour_late_is_a_warning_with_its_numbers_in_the_summary(twin, tmp_path):
    text, summary = _identify(twin, tmp_path / "out", "late.csv")
    assert "warning: " in text and "late.csv: Sensor log's clock" in text, text
    assert "time stamps 1 h earlier" in text
    assert "the model's timing (its heat capacities)" in text  # the other cause named
    assert "--tz" in text and "identify again" in text  # what to do
    clock = summary["log_clock"]
    assert clock["passed"] is False and clock["best"] == -1.0, clock
    std = {float(hours): value for hours, value in clock["std"].items()}
    assert std[-1.0] < 0.5 * std[0.0], std
    assert clock["gain"] > clock["tolerance"] == 0.2
    assert clock["halves"]["disagree"] is False and clock["at_limit"] is False, clock
    assert "the whole log is off" in text  # both halves of the period agree
    assert "clock_check" in summary["timings_s"]
    report = (tmp_path / "out" / "report.html").read_text()
    assert "Sensor log&#x27;s clock" in report or "Sensor log's clock" in report


@requires_energyplus
def test_the_log_as_written_passes_with_its_numbers_in_the_summary(twin, tmp_path):
    text, summary = _identify(twin, tmp_path / "out", "sensors.csv")
    assert "Sensor log's clock:" not in text  # no warning
    assert "as written 0." in text  # the summary's line of the check
    clock = summary["log_clock"]
    assert clock["passed"] is True and clock["best"] == 0.0, clock
    std = {float(hours): value for hours, value in clock["std"].items()}
    assert sorted(std) == [-1.0, 0.0, 1.0]
    assert std[-1.0] > 2.0 * std[0.0] and std[1.0] > 2.0 * std[0.0], std
    assert "smoothest with the log as written" in clock["note"]


@requires_energyplus
def test_no_clock_check_switches_it_off(twin, tmp_path):
    text, summary = _identify(twin, tmp_path / "out", "late.csv", "--no-clock-check")
    assert "Sensor log's clock" not in text, text
    assert "not checked (--no-clock-check)" in text
    assert summary["log_clock"] is None
    assert "clock_check" not in summary["timings_s"]


def test_shifted_values_move_the_references_by_whole_and_partial_steps():
    from thermocal.identification.workflow import shifted_values

    elapsed = 0.5 * np.arange(6.0)  # 30-minute steps [h]
    reference = np.column_stack([np.arange(6.0), 10.0 + np.arange(6.0)])  # zones A, B
    later = shifted_values(reference, elapsed, 1.0)  # the stamps an hour later: two steps on
    assert later.shape == reference.shape and later.flags["C_CONTIGUOUS"]
    np.testing.assert_allclose(later[:, 0], [0.0, 0.0, 0.0, 1.0, 2.0, 3.0])  # held at the start
    np.testing.assert_allclose(shifted_values(reference, elapsed, -0.25)[:, 1],
                               [10.5, 11.5, 12.5, 13.5, 14.5, 15.0])  # fmt: skip


def test_the_shift_search_follows_a_better_shift_to_its_minimum():
    from thermocal.calibration.clockcheck import best_clock_shift, clock_check_window

    tried = []

    def std(hours):  # smoothest two hours earlier
        tried.append(hours)
        return 100.0 + 50.0 * abs(hours + 2.0)

    values, best = best_clock_shift(std)
    assert best == -2.0 and tried == [0.0, -1.0, 1.0, -2.0, -3.0], (best, tried)
    assert values[-2.0] == 100.0
    assert best_clock_shift(lambda hours: float("nan")) is None  # nothing to compare with
    step = pd.Timedelta("5min")
    assert clock_check_window("2023-01-04", "2023-01-06", step) is None  # under two days left
    first, last = clock_check_window("2023-01-04", "2023-01-09", step)
    assert (first, last) == (pd.Timestamp("2023-01-04 03:00"), pd.Timestamp("2023-01-08 21:00"))


@requires_energyplus
def test_the_python_identify_warns_and_can_be_switched_off(twin):
    """``identify(..., clock_check=False)`` in Python, the log an hour late."""
    from thermocal.calibration.clockcheck import LogClockWarning
    from thermocal.identification.sensors import load_mapping
    from thermocal.identification.workflow import identify
    from thermocal.io.measurements import read_measurements
    from thermocal.io.weather import read_weather
    from thermocal.multizone.files import load_building

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = load_building(twin / "nominal.idf")
    weather, site = read_weather(twin / "weather.epw")
    log, _ = read_measurements(twin / "late.csv")
    mapping = load_mapping(twin / "mapping.yaml")
    kwargs = dict(start=START, end=END, method="inverse", log_name="late.csv")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        checked = identify(building, weather, site, log, mapping, **kwargs)
        unchecked = identify(building, weather, site, log, mapping, clock_check=False, **kwargs)
    clock_warnings = [w for w in caught if issubclass(w.category, LogClockWarning)]
    assert len(clock_warnings) == 1, [str(w.message) for w in caught]
    assert str(clock_warnings[0].message).startswith("late.csv: Sensor log's clock")
    assert checked.log_clock["best"] == -1.0 and unchecked.log_clock is None
    pd.testing.assert_frame_equal(checked.q_id, unchecked.q_id)  # the answer itself unchanged


@requires_energyplus
def test_a_period_too_short_to_check_says_why(twin, tmp_path):
    """Found by fuzzing (C.7, 2026-12): on a 2-day period the check was skipped and the summary
    said "not checked", as --no-clock-check does; now the summary, identification.json and the
    report say the period is too short and how long it must be."""
    text, summary = _identify(twin, tmp_path / "out", "late.csv", start="2023-01-05",
                              end="2023-01-07")  # fmt: skip
    from thermocal.commands.identify import _clock_summary

    assert "not checked: period too short (48 h;" in text, text  # the summary (wrapped)
    clock = summary["log_clock"]
    assert _clock_summary(clock) == (
        "not checked: period too short (48 h; the check needs at least 54 h)"
    )
    assert clock["checked"] is False and clock["passed"] is None, clock
    assert "54 h" in clock["note"] and "longer period" in clock["note"]
    assert "Sensor log's clock:" not in text.split("heat-balance identification")[0]  # no warning
    report = (tmp_path / "out" / "report.html").read_text()
    assert "period too short (48 h" in report


@requires_energyplus
def test_a_clock_that_jumps_mid_log_is_told_from_a_whole_log_shift(twin, tmp_path):
    """Found by fuzzing (C.8, 2026-12): the log right until 6 January noon and an hour late
    after (a daylight-saving switch) was warned as a whole log to shift an hour earlier, which
    breaks its first half. The halves of the period are compared (on the same inverses) and
    disagree: the warning says the clock jumped and to correct only the stamps after it."""
    text, summary = _identify(twin, tmp_path / "out", "switch.csv")
    clock = summary["log_clock"]
    assert clock["passed"] is False and clock["best"] == -1.0, clock
    assert clock["halves"]["disagree"] is True and clock["halves"]["shifted"] == [False, True]
    first, second = clock["halves"]["halves"]
    assert first["gain"] < 0.0 < 0.2 < second["gain"], clock["halves"]
    assert "jumped by about 1 h within the period" in text, text
    assert "correct only the stamps after the jump, not the whole log" in text
    from thermocal.commands.identify import _clock_summary

    assert _clock_summary(clock).startswith("-1 h better in the second half only (a clock jump?)")
    report = (tmp_path / "out" / "report.html").read_text()
    assert "in one half only (a clock jump?)" in report


def test_a_best_shift_at_the_search_limit_is_at_least_that():
    """Found by fuzzing (C.6, 2026-12): UTC stamps read as Chicago time (6 h off) were warned as
    "3 h earlier" with the spread still falling at the search's limit; following the advice
    left the log 3 h off. The warning says "at least" and points at the time zone."""
    from thermocal.calibration.clockcheck import MAX_SHIFT_H, best_clock_shift, clock_result

    std, best = best_clock_shift(lambda hours: 100.0 + 50.0 * abs(hours + 6.0))
    assert best == -MAX_SHIFT_H == -3.0
    result = clock_result(std, best, consequence="REMEDY.")
    assert not result["passed"] and result["at_limit"] is True
    assert "time stamps at least 3 h earlier" in result["note"], result["note"]
    assert "may be larger" in result["note"] and "time-zone error" in result["note"]
    assert "REMEDY." in result["note"]
    std, best = best_clock_shift(lambda hours: 100.0 + 50.0 * abs(hours + 2.0))
    two = clock_result(std, best, consequence="REMEDY.")
    assert two["at_limit"] is False and "at least" not in two["note"]  # a minimum: the shift


def test_a_shift_smoother_within_the_tolerance_is_named_with_its_numbers():
    """Found by fuzzing (C.9, 2026-12): +1 h gave 5.377 kW against 5.445 kW as written, and the
    note said the heat was "smoothest with the log as written"."""
    from thermocal.calibration.clockcheck import clock_result

    std = {-1.0: 5692.0, 0.0: 5445.0, 1.0: 5377.0, 2.0: 5599.0}
    result = clock_result(std, 1.0, consequence="REMEDY.")
    assert result["passed"] is True and result["best"] == 1.0
    note = result["note"]
    assert "smoothest with the log as written" not in note, note
    assert "no shift of the log makes the model's unoccupied heat markedly smoother" in note
    assert "+1 h gives 5.377 kW" in note and "5.445 kW as written, 1.2 % lower" in note
    assert "under the 20 %" in note


def test_the_halves_and_the_skipped_check_are_pure_functions():
    """C.7 and C.8 without a model: the halves' split and verdict, a skipped check's result
    (no warning: ``passed`` None)."""
    from thermocal.calibration.clockcheck import (
        clock_halves,
        clock_skipped,
        compare_halves,
        too_short_reason,
        warn_if_clock_off,
    )

    step = pd.Timedelta("10min")
    window = (pd.Timestamp("2023-01-04 03:00"), pd.Timestamp("2023-01-08 21:00"))
    halves = clock_halves(window, step)
    assert halves == ((window[0], pd.Timestamp("2023-01-06 12:00")),
                      (pd.Timestamp("2023-01-06 12:00"), window[1]))  # fmt: skip

    def jumped(hours, half):  # right in the first half, an hour late in the second
        off = 0.0 if half[0] == window[0] else -1.0
        return 100.0 + 300.0 * abs(hours - off)

    split = compare_halves(jumped, -1.0, halves)
    assert split["shifted"] == [False, True] and split["disagree"] is True
    whole = compare_halves(lambda hours, half: 100.0 + 300.0 * abs(hours + 1.0), -1.0, halves)
    assert whole["disagree"] is False
    assert compare_halves(lambda hours, half: float("nan"), -1.0, halves) is None
    reason = too_short_reason("2023-01-05", "2023-01-07")
    assert reason == "period too short (48 h; the check needs at least 54 h)"
    skipped = clock_skipped(reason)
    assert skipped["checked"] is False and skipped["passed"] is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warn_if_clock_off(skipped, "log.csv")  # no warning


@requires_energyplus
def test_a_clock_that_jumps_near_the_middle_is_found_by_the_halves(twin, tmp_path):
    """Found by a review (2026-11-30): the log right until 11 January and an hour late after,
    identified January 4-18: over the whole period neither shift is better (1.12 kW at -1 h
    against 1.04 kW as written), so the check passed "smoothest as written" while the second
    half is 55 % smoother an hour earlier. identify compares the halves on the runs it made."""
    log = pd.read_csv(twin / "sensors.csv")
    times = pd.to_datetime(log["time"])
    after = (times >= pd.Timestamp("2023-01-11 00:00-06:00")).astype(int)
    jumped = times + pd.to_timedelta(after, unit="h")
    log.assign(time=jumped.dt.strftime("%Y-%m-%dT%H:%M:%S%z")).to_csv(
        twin / "jump_middle.csv", index=False
    )
    text, summary = _identify(twin, tmp_path / "out", "jump_middle.csv", end="2023-01-18")
    clock = summary["log_clock"]
    std = {float(hours): value for hours, value in clock["std"].items()}
    assert std[0.0] <= min(std.values()), std  # the whole period alone passes
    assert clock["passed"] is False and clock["best"] == -1.0, clock
    assert clock["halves"]["disagree"] is True and clock["halves"]["shifted"] == [False, True]
    assert "warning: " in text and "the two halves of the compared hours disagree" in text


def test_a_spread_falling_all_the_way_to_the_search_limit_fails_the_check():
    """A log in UTC read as local time 7 h off: the spread fell by 14 % at -3 h, every hour
    lower than the last, and the check passed under its 20 % tolerance (the identified heat
    +26 %; exploratory test, 2026-11-30). At the limit, falling all the way, 5 % suffice."""
    from thermocal.calibration.clockcheck import clock_result, shift_within_tolerance

    falling = {0.0: 2.101, -1.0: 2.013, -2.0: 1.912, -3.0: 1.805, 1.0: 2.171}
    assert not shift_within_tolerance(falling, -3.0)
    result = clock_result(falling, -3.0, consequence="")
    assert not result["passed"] and result["at_limit"]
    assert "better with its time stamps at least 3 h earlier" in result["note"]
    assert "much better" not in result["note"]
    # not falling all the way (the same reduction at the limit, a bump on the way): passes
    bumpy = {0.0: 2.101, -1.0: 2.2, -2.0: 1.912, -3.0: 1.805, 1.0: 2.171}
    assert shift_within_tolerance(bumpy, -3.0)
    # falling all the way but by less than 5 %: passes; a 1-hour best: the 20 % tolerance
    assert shift_within_tolerance({0.0: 2.0, -1.0: 1.99, -2.0: 1.97, -3.0: 1.96}, -3.0)
    assert shift_within_tolerance({0.0: 2.0, -1.0: 1.7, 1.0: 2.1}, -1.0)


DST = Path(__file__).resolve().parents[1] / "reference" / "identification_clock_dst"


@pytest.fixture(scope="module")
def dst_twin(tmp_path_factory):
    """The EnergyPlus twin of InternalMass_wZoneList in July at Golden, CO
    (``tests/reference/identification_clock_dst``): its log in standard time without an offset
    (``standard.csv``) and the same readings on the local wall clock, daylight saving time
    (``local.csv``, every stamp an hour later: the right clock read with ``--tz
    America/Denver``)."""
    folder = tmp_path_factory.mktemp("identify_clock_dst")
    shutil.copy(DST / "user.idf", folder / "user.idf")
    shutil.copy(DST / "mapping.yaml", folder / "mapping.yaml")
    with gzip.open(DST / "sensors.csv.gz", "rb") as fh:
        (folder / "standard.csv").write_bytes(fh.read())
    log = pd.read_csv(folder / "standard.csv")
    local = pd.to_datetime(log["time"]) + pd.Timedelta(hours=1)
    log.assign(time=local.dt.strftime("%Y-%m-%d %H:%M:%S")).to_csv(folder / "local.csv",
                                                                    index=False)  # fmt: skip
    return folder


def _identify_dst(folder: Path, out: Path, log: str):
    from thermocal.multizone.energyplus import energyplus_weather_folder

    weather = energyplus_weather_folder() / "USA_CO_Golden-NREL.724666_TMY3.epw"
    return _identify(
        folder, out, log, "--step", "5min", "--tz", "America/Denver", "--site", "weather",
        start="2023-07-09T00:00", end="2023-07-22T23:00", idf="user.idf", weather=weather,
    )  # fmt: skip


@requires_energyplus
def test_a_log_in_standard_time_read_with_daylight_saving_is_an_hour_off(dst_twin, tmp_path):
    """Found by an exploratory run (2026-12-01): the log in standard time read with --tz
    America/Denver in July (every stamp an hour early) gave 0.214 kW as written, 0.177 kW at
    +1 h (17 % lower, under the 20 %), 0.260 -> 0.226 and 0.106 -> 0.040 kW in the halves; the
    note said "the log fits best as written", "the two halves ... disagree" twice and "correct
    only the stamps after the jump". Both halves are smoother an hour later: the whole log is an
    hour off, said once, as most likely standard time read as daylight saving time."""
    text, summary = _identify_dst(dst_twin, tmp_path / "out", "standard.csv")
    clock = summary["log_clock"]
    std = {float(hours): value for hours, value in clock["std"].items()}
    assert clock["passed"] is False and clock["best"] == 1.0, clock
    assert min(std, key=std.get) == 1.0 and 0.1 < clock["gain"] < 0.2, std
    note = clock["note"]
    sentences = [s.strip() for s in note.split(". ") if s.strip()]
    assert len(sentences) == len(set(sentences)), sentences  # each sentence once
    assert "fits best as written" not in note and "disagree" not in note, note
    assert "time stamps 1 h later" in note, note
    assert "after the jump" not in note and "not a clock that jumped within it" in note
    assert "kept in standard time" in note and "daylight saving time" in note
    # identify passes its --tz on: July in Denver is daylight time, said with the share
    assert "daylight-saving hour (America/Denver keeps daylight time over 100 %" in note, note
    halves = clock["halves"]
    assert halves["disagree"] is False and halves["both"] is True, halves
    from thermocal.calibration.clockcheck import HOUR_HALF_TOLERANCE

    # each half by the margin a model's own timing error does not reach (13 % and 62 %)
    assert all(HOUR_HALF_TOLERANCE < half["gain"] for half in halves["halves"]), halves
    assert "warning: " in text and "standard.csv: Sensor log's clock" in text
    from thermocal.commands.identify import _clock_summary

    assert _clock_summary(clock).startswith("+1 h better, see the warning")


@requires_energyplus
def test_the_same_log_on_the_local_wall_clock_passes(dst_twin, tmp_path):
    """The same readings stamped on the local wall clock (daylight saving time) and read with
    --tz America/Denver: smoothest as written (0.177 kW; +1 h 0.183, -1 h 0.213)."""
    text, summary = _identify_dst(dst_twin, tmp_path / "out", "local.csv")
    clock = summary["log_clock"]
    assert clock["passed"] is True and clock["best"] == 0.0, clock
    assert "Sensor log's clock:" not in text


def _whole(std):
    """``unoccupied_std`` of the shifts in ``std`` [W] (infinite beyond them)."""
    return lambda hours: std.get(hours, float("inf"))


def _halves_of(gains, own=(260.0, 106.0), at=(1.0,), month=7):
    """A ``half_std`` giving each half's standard deviation [W] as written, ``gains`` [-]
    smoother at the shifts ``at`` [h] and half as large again at the others, and the two halves
    it tells apart (9 to 22 ``month``, 2023)."""
    first = (pd.Timestamp(f"2023-{month:02d}-09 03:00"), pd.Timestamp(f"2023-{month:02d}-15 23:30"))
    second = (first[1], pd.Timestamp(f"2023-{month:02d}-22 20:00"))

    def half_std(hours, half):
        i = 0 if half == first else 1
        if hours == 0.0:
            return own[i]
        return own[i] * (1.0 - gains[i]) if hours in at else 1.5 * own[i]

    return half_std, (first, second)


def test_a_whole_log_an_hour_off_under_the_tolerance_is_reported_with_its_halves():
    """The exploratory run's figures (2026-12-01) without the model: +1 h 17 % smoother over the
    whole period, 13 % and 62 % in the halves. Before: passed by the whole, then reported as a
    jump (the halves "disagree", 13 % under the 20 %) with a note saying the log fits best as
    written. Now the whole log an hour off, +1 h named as best."""
    from thermocal.calibration.clockcheck import LogClockWarning, run_clock_check

    std = {-1.0: 294.0, 0.0: 214.0, 1.0: 177.0, 2.0: 183.0}
    half_std, halves = _halves_of((0.132, 0.621))
    with pytest.warns(LogClockWarning) as caught:
        result = run_clock_check(_whole(std), half_std, halves, consequence="REMEDY.",
                                 path="log.csv", halves_always=True)  # fmt: skip
    note = result["note"]
    assert "fits best as written" not in note and "after the jump" not in note, note
    assert "better with its time stamps 1 h later (0.177 kW" in note
    assert "0.214 kW as written, 17.3 % lower" in note
    assert result["passed"] is False and result["best"] == 1.0, result
    assert result["halves"]["both"] and not result["halves"]["disagree"], result["halves"]
    assert "under the 20 %" in note and "kept in standard time" in note
    assert note.count("REMEDY.") == 1 and len(caught) == 1


@pytest.mark.parametrize(
    ("std", "gains"),
    [
        # a right clock (the exploration's WindowTestsSimple, a sunny sensor): +1 h 6.4 %
        ({-1.0: 58.701, 0.0: 53.271, 1.0: 49.837, 2.0: 50.374}, (0.064, 0.065)),
        # 17 % over the whole period, one half no smoother: not the whole log
        ({-1.0: 294.0, 0.0: 214.0, 1.0: 177.0, 2.0: 183.0}, (0.15, -0.02)),
        # both halves smoother but the best shift two hours (not the daylight-saving hour)
        ({-1.0: 1.396, 0.0: 1.303, 1.0: 1.207, 2.0: 1.117, 3.0: 1.348}, (0.114, 0.17)),
    ],
)
def test_a_shift_under_the_tolerance_not_an_hour_in_both_halves_passes(std, gains):
    from thermocal.calibration.clockcheck import run_clock_check

    half_std, halves = _halves_of(gains)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no LogClockWarning
        result = run_clock_check(_whole(std), half_std, halves, consequence="", path="log.csv",
                                 halves_always=True)  # fmt: skip
    assert result["passed"] is True, result
    assert "taken as written" in result["note"]


def test_a_jump_note_names_the_whole_periods_best_shift_and_says_each_sentence_once():
    """Before: "over the whole period the log fits best as written" when a shift was smoother
    within the tolerance, and "the two halves of the compared hours disagree" twice."""
    from thermocal.calibration.clockcheck import LogClockWarning, run_clock_check

    std = {-2.0: 110.0, -1.0: 95.0, 0.0: 100.0, 1.0: 130.0}
    half_std, halves = _halves_of((-0.5, 0.4), own=(80.0, 120.0), at=(-1.0,))
    with pytest.warns(LogClockWarning):
        result = run_clock_check(_whole(std), half_std, halves, consequence="REMEDY.",
                                 path="log.csv", halves_always=True)  # fmt: skip
    assert result["passed"] is False and result["best"] == -1.0
    note = result["note"]
    assert "fits best as written" not in note, note
    assert note.count("the two halves of the compared hours disagree") == 1, note
    assert "the best, -1 h, gives 0.095 kW" in note and "5.0 % lower" in note
    assert result["halves"]["disagree"] and result["halves"]["as_written"] == [True, False]
    assert "the first fits as written" in note
    assert "correct only the stamps after the jump" in note
    # as written the best over the whole period: said so
    std = {-1.0: 105.0, 0.0: 100.0, 1.0: 130.0}
    with pytest.warns(LogClockWarning):
        result = run_clock_check(_whole(std), half_std, halves, consequence="", path="log.csv",
                                 halves_always=True)  # fmt: skip
    assert "over the whole period the log fits best as written (0.100 kW" in result["note"]
    assert result["note"].count("disagree") == 1


def test_the_halves_of_a_check_failed_at_the_search_limit_are_judged_by_its_tolerance():
    """A spread falling all the way to -3 h fails by 14 % (over 5 % at the limit): its halves,
    27 % and 10 % smoother, were judged against the 20 % and "disagreed" (a jump, correct only
    the stamps after it) though both are smoother: the whole log off."""
    from thermocal.calibration.clockcheck import LogClockWarning, run_clock_check

    falling = {0.0: 2101.0, -1.0: 2013.0, -2.0: 1912.0, -3.0: 1805.0, 1.0: 2171.0}
    half_std, halves = _halves_of((0.27, 0.10), at=(-3.0,))
    with pytest.warns(LogClockWarning):
        result = run_clock_check(_whole(falling), half_std, halves, consequence="", path="log.csv")
    split = result["halves"]
    assert result["passed"] is False and result["at_limit"], result
    assert "correct only the stamps" not in result["note"], result["note"]
    assert "the whole log is off, not a clock that jumped" in result["note"]
    assert not split["disagree"] and split["both"]
    assert split["tolerance"] == 0.05 and split["shifted"] == [True, True], split


def test_compare_halves_tells_a_jump_only_when_the_other_half_fits_as_written():
    from thermocal.calibration.clockcheck import compare_halves

    for gains, disagree, both in [
        ((0.132, 0.621), False, True),
        ((-0.3, 0.5), True, False),
        ((0.0, 0.5), True, False),
        ((0.05, -0.1), False, False),
    ]:
        half_std, halves = _halves_of(gains)
        split = compare_halves(half_std, 1.0, halves)
        assert (split["disagree"], split.get("both")) == (disagree, both), (gains, split)


@pytest.mark.parametrize("gains", [(0.02, 0.03), (0.01, 0.01), (0.03, 0.62)])
def test_a_one_hour_shift_with_a_half_barely_smoother_passes(gains):
    """Found by a review (2026-12-01): the exploration's figures over the whole period (+1 h
    17 % smoother) with halves only 1-3 % smoother failed the check as the whole log an hour
    off, since each half had to be smoother "at all"; a model whose own timing is off (its heat
    capacities before calibration) gives that. Each half must now be more than 5 % smoother."""
    from thermocal.calibration.clockcheck import run_clock_check

    std = {-1.0: 294.0, 0.0: 214.0, 1.0: 177.0, 2.0: 183.0}
    half_std, halves = _halves_of(gains)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no LogClockWarning
        result = run_clock_check(_whole(std), half_std, halves, consequence="", path="log.csv",
                                 halves_always=True, tz="America/Denver")  # fmt: skip
    assert result["passed"] is True, result["note"]
    assert "not more than 5 % smoother in each half of the compared hours at +1 h" in (
        result["note"]
    )
    assert "taken as written" in result["note"]


def test_a_january_period_an_hour_off_does_not_blame_daylight_saving():
    """Found by a review (2026-12-01): the note of a whole log an hour off said "most likely by
    the daylight-saving hour ... while it is in force" for a January period in Denver, where no
    daylight saving time is in force then. The zone's rules (the IANA database, through
    zoneinfo) decide: January in Denver names the neighbouring zone's and the weather file's
    clocks only; July names daylight saving; without a zone, both are named alike."""
    from thermocal.calibration.clockcheck import LogClockWarning, run_clock_check

    std = {-1.0: 294.0, 0.0: 214.0, 1.0: 177.0, 2.0: 183.0}

    def note(month, tz):
        half_std, halves = _halves_of((0.132, 0.621), month=month)
        with pytest.warns(LogClockWarning):
            result = run_clock_check(_whole(std), half_std, halves, consequence="REMEDY.",
                                     path="log.csv", halves_always=True, tz=tz)  # fmt: skip
        assert result["passed"] is False and result["best"] == 1.0
        return result["note"]

    january = note(1, "America/Denver")
    assert "not the daylight-saving hour (America/Denver keeps standard time over 100 %" in (
        january
    ), january
    assert "most likely by the daylight-saving hour" not in january
    assert "kept in standard time" not in january and "in force" not in january
    assert "neighbouring time zone" in january and "weather file's clock" in january
    july = note(7, "America/Denver")
    assert "most likely by the daylight-saving hour (America/Denver keeps daylight time" in july
    assert "kept in standard time all year" in july
    # the southern summer: January in Sydney is daylight time
    assert "by the daylight-saving hour (Australia/Sydney" in note(1, "Australia/Sydney")
    unknown = note(1, None)
    assert "most likely by the daylight-saving hour" not in unknown
    assert "standard against daylight time" in unknown and "neighbouring time zone" in unknown
    assert "give the log's time zone" in unknown


def test_daylight_fraction_follows_the_zones_rules():
    from thermocal.calibration.clockcheck import daylight_fraction

    assert daylight_fraction("2023-01-04", "2023-01-18", "America/Denver") == 0.0
    assert daylight_fraction("2023-07-09", "2023-07-22", "America/Denver") == 1.0
    assert daylight_fraction("2023-07-09", "2023-07-22", "America/Phoenix") == 0.0  # no DST
    # Zurich switches on 26 March 2023 at 02:00 (to 03:00): of the 119 h from 24 March 00:00
    # (+01:00) to 29 March 00:00 (+02:00), 21 h on the 26th and two days after in daylight time
    share = daylight_fraction(pd.Timestamp("2023-03-24 00:00+01:00"),
                              pd.Timestamp("2023-03-29 00:00+02:00"), "Europe/Zurich")  # fmt: skip
    assert share == pytest.approx((21 + 48) / 119)
    assert daylight_fraction("2023-07-09", "2023-07-22", None) is None
    assert daylight_fraction("2023-07-09", "2023-07-22", 1.0) is None  # a fixed offset
    assert daylight_fraction("2023-07-09", "2023-07-22", "Not/AZone") is None
