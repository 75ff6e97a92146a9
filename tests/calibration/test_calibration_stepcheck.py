"""A campaign coarser than its sensor log: the response of the identified heat to the design's
samples compared at the two steps (``thermocal.calibration.stepcheck``)."""

from __future__ import annotations

import functools

import numpy as np
import pandas as pd
import pytest
from clinic_sensor_log import write_clinic_inputs

from thermocal.calibration.stepcheck import (
    STEP_TOLERANCE,
    check_campaign_step,
    log_interval,
    response_difference,
)

START, END = "2001-01-08", "2001-01-12"


def test_log_interval_of_long_and_wide_logs():
    times = pd.date_range("2001-01-01", periods=50, freq="5min", tz="UTC")
    wide = pd.DataFrame({"S1": np.arange(50.0), "S2": np.arange(50.0)}, index=times)
    assert log_interval(wide) == pd.Timedelta("5min")
    long = pd.DataFrame(
        {
            "time": list(times) + list(times[::2]),
            "sensor": ["S1"] * 50 + ["S2"] * 25,
            "value": np.arange(75.0),
        }
    )
    # two sensors: every 5 and every 10 minutes; a third at 10 makes 10 the median
    third = long[long["sensor"] == "S2"].assign(sensor="S3")
    assert log_interval(pd.concat([long, third])) == pd.Timedelta("10min")
    single = pd.DataFrame({"time": [times[0]], "sensor": ["S1"], "value": [1.0]})
    assert log_interval(single) is None
    # review of the check: staggered wide sensors are not merged, unmapped fast meters do not
    # count, and a jittered clock rounds to the step that divides an hour
    quarter = pd.date_range("2001-01-01", periods=40, freq="15min", tz="UTC")
    staggered = pd.concat(
        [pd.DataFrame({"A": 1.0}, index=quarter),
         pd.DataFrame({"B": 2.0}, index=quarter + pd.Timedelta("1min"))]
    ).sort_index()  # fmt: skip
    assert log_interval(staggered) == pd.Timedelta("15min")
    fast = pd.DataFrame({"time": pd.date_range("2001-01-01", periods=400, freq="10s", tz="UTC"),
                         "sensor": "P1", "value": 1.0})  # fmt: skip
    temps = pd.DataFrame({"time": list(quarter) * 3, "value": 20.0,
                          "sensor": ["T1"] * 40 + ["T2"] * 40 + ["T3"] * 40})  # fmt: skip
    mixed = pd.concat([temps] + [fast.assign(sensor=f"P{i}") for i in range(4)])
    assert log_interval(mixed) == pd.Timedelta("10s")
    assert log_interval(mixed, sensors=["T1", "T2", "T3"]) == pd.Timedelta("15min")
    jitter = np.random.default_rng(1).uniform(-0.9, 0.9, 50)
    shaky = pd.DataFrame({"S": 1.0}, index=times + pd.to_timedelta(jitter, unit="s"))
    assert log_interval(shaky) == pd.Timedelta("5min")


def test_response_difference_is_relative_to_the_fine_response():
    rng = np.random.default_rng(0)
    nominal = rng.normal(1000, 50, 200)
    response = rng.normal(0, 100, 200)
    offset = nominal + 7.0  # a level that moves with the step does not count
    same = response_difference(nominal, nominal + response, offset, offset + response)
    assert same == pytest.approx(0.0, abs=1e-12)
    scaled = response_difference(nominal, nominal + response, nominal, nominal + 1.1 * response)
    assert scaled == pytest.approx(0.1)
    assert np.isnan(response_difference(nominal, nominal, nominal, nominal + response))


@functools.cache
def _inputs(tmp):
    """The 12-zone clinic's true building logged every 5 minutes, its nominal file, mapping."""
    from pathlib import Path

    truth = {"material/R16 insulation/resistance": 2.818 * 0.6}
    write_clinic_inputs(tmp, truth, step="5min", start=START, end=END, warmup_days=2)
    return Path(tmp)


def _check(tmp, step, *, with_nominal=False):
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.inputs import build_problem, load_inputs
    from thermocal.calibration.sampling import sample
    from thermocal.calibration.workflow import campaign_space
    from thermocal.demos.retrofit import pvlib_weather_path

    folder = _inputs(tmp)
    path = folder / f"campaign_{step}.yaml"
    path.write_text(
        f"""
building: building.yaml
weather: {pvlib_weather_path()}
sensors: sensors.csv
mapping: mapping.yaml
period: {{start: {START}, end: {END}}}
step: {step}
identification: {{method: inverse, settle: 1D, warmup_days: 2}}
parameters:
  include: ["material/R16 insulation/resistance", "window/Exterior window/u_value"]
  default_range: 0.5
sampling: {{method: sobol, samples: 8, seed: 3}}
"""
    )
    campaign = load_campaign(path)
    inputs = load_inputs(campaign)
    problem, _ = build_problem(campaign, inputs)
    design = sample(campaign_space(campaign, inputs.building), 8, "sobol", seed=3).values
    nominal = None
    if with_nominal:  # as the workflow: the campaign's own nominal outputs
        from thermocal.calibration.spatial import campaign_evaluator

        problem.series_outputs = True
        nominal = campaign_evaluator(problem, inputs.building).outputs(problem.run({}).heat)
    return check_campaign_step(campaign, inputs, problem, design, lambda line: None, nominal)


def test_the_campaign_step_is_checked_against_the_logs(tmp_path_factory):
    """At the log's step nothing is checked; at 15 minutes the response of the unoccupied
    heat to the design's first samples stays within the tolerance; at an hour (the model's
    largest step; implicit steps smear the day's heat) it moves further than at 15 minutes."""
    tmp = str(tmp_path_factory.mktemp("stepcheck"))
    assert _check(tmp, "5min") is None
    fine = _check(tmp, "15min")
    coarse = _check(tmp, "1h")
    assert fine["log_step"] == "5min" and len(fine["differences"]) == 2
    assert fine["passed"] and fine["largest"] <= STEP_TOLERANCE, fine
    assert "15min" in fine["note"] and "log's: 5min" in fine["note"]
    assert coarse["largest"] > 2 * fine["largest"], (fine, coarse)
    # the campaign's own nominal run stands for the check's identification of it
    assert _check(tmp, "15min", with_nominal=True)["differences"] == fine["differences"]
    if not coarse["passed"]:
        assert "run the campaign at a finer step" in coarse["note"]


def test_a_step_beyond_the_tolerance_is_a_warning(tmp_path_factory, monkeypatch):
    """With the tolerance below what 15 minutes give, the check fails: a warning naming the
    campaign file and the remedy, and the report's note."""
    import thermocal.calibration.stepcheck as stepcheck

    monkeypatch.setattr(stepcheck, "STEP_TOLERANCE", 1e-6)
    tmp = str(tmp_path_factory.mktemp("stepcheck"))
    with pytest.warns(stepcheck.CampaignStepWarning, match=r"campaign_15min\.yaml: .*finer step"):
        result = _check(tmp, "15min")
    assert not result["passed"] and result["tolerance"] == 1e-6


def test_a_resumed_campaign_takes_its_stored_step_check(tmp_path, monkeypatch):
    """The check runs once per campaign: its result is kept in the store, a resumed campaign
    (same definition) takes it instead of identifying three models again, and a failed one
    warns again. Before, every ``--resume`` re-ran it (a few seconds, the clinic's 7)."""
    from types import SimpleNamespace

    import thermocal.calibration.stepcheck as stepcheck
    from thermocal.calibration.store import CampaignStore
    from thermocal.calibration.workflow import _step_check

    calls = []
    failed = stepcheck._note("15min", "5min", [0.2, 0.1], None)

    def check(campaign, *args):  # as the real check: it warns when it fails
        calls.append(args)
        stepcheck.warn_if_failed(failed, campaign.path)
        return failed

    monkeypatch.setattr(stepcheck, "check_campaign_step", check)
    campaign = SimpleNamespace(path=tmp_path / "campaign.yaml")
    definition = {"step": "15min"}
    for resume in (False, True, True):
        with CampaignStore.open(tmp_path / "s.sqlite", definition=definition) as store:
            timings = {}
            with pytest.warns(stepcheck.CampaignStepWarning, match=r"campaign\.yaml: .*finer"):
                result = _step_check(campaign, None, None, None, None, store, resume, timings,
                                     lambda line: None)  # fmt: skip
            assert result == failed
            assert ("step_check" in timings) == (not resume)
    assert len(calls) == 1
    # a fresh (not resumed) campaign checks again
    with CampaignStore.open(tmp_path / "s.sqlite", definition=definition) as store:
        with pytest.warns(stepcheck.CampaignStepWarning):
            _step_check(campaign, None, None, None, None, store, False, {}, lambda line: None)
    assert len(calls) == 2
