"""The sensor log's clock against the model's (``thermocal.calibration.clockcheck``), on a
building thermocal did not write: the EnergyPlus twin of 5ZoneAirCooled, whose committed log
EnergyPlus wrote with the right clock.

Found by fuzzing (2026-11-29): the same log written in local time with a UTC offset an hour off
ran a whole campaign without a word and declared the slab's resistance determined at 0.0525
m2 K/W against 0.0838 with the right clock; its nominal unoccupied heat varied 2.3 times as
much. The check identifies the nominal model with the log shifted by an hour either way.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import pandas as pd
import pytest

from conftest import requires_energyplus, shared_data_path

REFERENCE = Path(__file__).resolve().parents[1] / "reference" / "calibration_energyplus_5zone"

pytestmark = requires_energyplus


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """The twin's campaign inputs and problem (nominal envelope, its quiet hours chosen)."""
    shared = shared_data_path("energyplus_reference")
    sys.path.insert(0, str(REFERENCE))
    sys.modules.pop("make_reference", None)
    sys.modules.pop("calibrate_twin", None)
    try:
        import calibrate_twin as ct
    finally:
        sys.path.remove(str(REFERENCE))
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.inputs import build_problem, load_inputs
    from thermocal.calibration.workflow import choose_quiet_hours

    folder = tmp_path_factory.mktemp("clock_5zone")
    path = ct.prepare(folder, 8, shared=shared, period=("2023-01-04", "2023-01-14"))
    campaign = load_campaign(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        inputs = load_inputs(campaign)
        problem, _ = build_problem(campaign, inputs)
        problem.series_outputs = True
        heat = problem.run({}).heat.sum(axis=1)
        problem.schedule, _ = choose_quiet_hours(campaign, heat, log=lambda line: None)
    return campaign, inputs, problem


def _check(twin, hours: float):
    import dataclasses

    from thermocal.calibration.clockcheck import check_log_clock, shifted_log
    from thermocal.calibration.spatial import campaign_evaluator

    campaign, inputs, problem = twin
    moved = dataclasses.replace(inputs, sensor_log=shifted_log(inputs.sensor_log, hours))
    return check_log_clock(
        campaign, moved, problem, lambda p: campaign_evaluator(p, moved.building), lambda s: 0
    )


def test_the_right_clock_passes(twin):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no LogClockWarning
        result = _check(twin, 0.0)
    assert result["passed"] and result["best"] == 0.0, result
    std = {float(k): v for k, v in result["std"].items()}
    assert std[-1.0] > 1.5 * std[0.0] and std[1.0] > 1.5 * std[0.0], std


@pytest.mark.parametrize("hours", [1.0, -2.0])
def test_a_log_hours_off_is_a_warning_naming_the_shift(twin, hours):
    """The log's stamps an hour late (or two early): the shift that undoes it is found and
    named, with the campaign file, as a LogClockWarning."""
    from thermocal.calibration.clockcheck import LogClockWarning

    with pytest.warns(LogClockWarning, match=r"campaign\.yaml: Sensor log's clock") as caught:
        result = _check(twin, hours)
    assert not result["passed"] and result["best"] == -hours, result
    later = "earlier" if hours > 0 else "later"
    assert f"time stamps {abs(hours):g} h {later}" in str(caught[0].message)
    assert result["gain"] > 0.3
    # the whole log off: both halves of the period prefer the shift (not a clock that jumped)
    assert result["halves"]["shifted"] == [True, True], result["halves"]
    assert "the whole log is off, not a clock that jumped" in str(caught[0].message)


def test_a_period_too_short_to_check_says_why(twin):
    """Found by fuzzing (C.7, 2026-12): a period too short to shift was skipped without a word
    (None, nothing in the campaign's notes); now its result says why, logged, without a warning
    and without an identification."""
    import dataclasses

    from thermocal.calibration.clockcheck import check_log_clock

    campaign, inputs, problem = twin
    short = dataclasses.replace(inputs, start=pd.Timestamp("2023-01-05", tz=inputs.start.tz),
                                end=pd.Timestamp("2023-01-07", tz=inputs.start.tz))  # fmt: skip
    lines = []

    def unused(p):
        raise AssertionError("no identification for a period too short to check")

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no LogClockWarning
        result = check_log_clock(campaign, short, problem, unused, lines.append)
    assert result["checked"] is False and result["passed"] is None, result
    assert result["reason"] == "period too short (48 h; the check needs at least 54 h)"
    assert lines == [result["note"]] and "longer period" in result["note"]


def test_shifted_log_moves_long_and_wide_logs():
    from thermocal.calibration.clockcheck import shifted_log

    times = pd.date_range("2023-01-01", periods=3, freq="h", tz="UTC")
    wide = pd.DataFrame({"S1": [1.0, 2.0, 3.0]}, index=times)
    long = pd.DataFrame({"time": times, "sensor": "S1", "value": [1.0, 2.0, 3.0]})
    assert shifted_log(wide, 1.0).index[0] == times[1]
    assert shifted_log(long, -1.0)["time"].iloc[1] == times[0]
