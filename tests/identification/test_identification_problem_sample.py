"""A calibration sample's lean path (issue 22): ``IdentificationProblem.evaluate`` takes the
identified heat without the tracking result's frames and gives exactly what the metric of the
whole result gives."""

from __future__ import annotations

import functools

import numpy as np
import pandas as pd
import pytest

from thermocal.demos import buildings as generators
from thermocal.errors import ThermocalInputError
from thermocal.identification.occupancy import OccupancySchedule, UnoccupiedWindow
from thermocal.identification.pid import PIDGains
from thermocal.identification.problem import problem_from_measurements
from thermocal.multizone import Simulation

START, END = "2001-01-08", "2001-01-11"
PARAMETERS = {
    "material/R16 insulation/resistance": 2.818 * 0.7,
    "window/Exterior window/u_value": 4.0 * 1.3,
}


@functools.cache
def _inputs():
    """A 12-zone clinic's weather and a sensor log of every other zone from its free run."""
    from thermocal.demos.retrofit import pvlib_weather_path
    from thermocal.io.weather import read_weather

    weather, meta = read_weather(pvlib_weather_path())
    building = generators.clinic(12, n_corridors=1, corridor_sections=2)
    truth = building.with_parameters({"material/R16 insulation/resistance": 2.0})
    air = (
        Simulation(truth, weather, meta, step="5min", start=START, end=END, warmup_days=1)
        .run(free_float=True)
        .air_temperature.iloc[:, ::2]
    )
    log = air.copy()
    log.index = log.index + pd.Timedelta("5min")
    names = {zone: f"S{i:02d}" for i, zone in enumerate(log.columns)}
    mapping = {"sensors": {sensor: zone for zone, sensor in names.items()}}
    return building, weather, meta, log.rename(columns=names), mapping


def _problem(**kwargs):
    building, weather, meta, log, mapping = _inputs()
    problem, _ = problem_from_measurements(
        building, weather, meta, log, mapping, start=START, end=END, warmup_days=1, **kwargs
    )
    return problem


@pytest.mark.parametrize(
    "kwargs",
    [{}, {"feedback": "operative", "radiant_fraction": 0.5}],
    ids=["air", "operative with a radiant fraction"],
)
def test_evaluate_is_the_metric_of_the_whole_tracking_result_bit_for_bit(kwargs):
    problem = _problem(**kwargs)
    problem.zone_outputs = True
    problem.series_outputs = True
    for parameters in (PARAMETERS, {}, PARAMETERS):
        lean = problem.evaluate(parameters)
        heat = problem.run(parameters).heat
        assert np.array_equal(problem.identified_heat(parameters), heat.to_numpy())
        whole = problem.metrics(heat)
        assert lean == whole
        assert len([k for k in lean if k.startswith("zone_variance/")]) == heat.shape[1]
        assert any(k.startswith("series/") for k in lean)


def test_evaluate_follows_a_changed_schedule():
    problem = _problem()
    before = problem.evaluate(PARAMETERS)
    problem.schedule = OccupancySchedule((UnoccupiedWindow(tuple(range(7)), 0.0, 6.0),))
    after = problem.evaluate(PARAMETERS)
    assert after == problem.metrics(problem.run(PARAMETERS).heat)
    assert after != before


def test_a_diverging_pid_is_refused_by_the_lean_path_too():
    building = _inputs()[0]
    wild = {zone: PIDGains(kp=2e6, ki=2e4, kd=0.0) for zone in building.zones}
    problem = _problem(method="pid", gains=wild)
    for call in (problem.evaluate, problem.run):
        with pytest.raises(ThermocalInputError, match="PID loop diverges"):
            call(PARAMETERS)


def test_the_campaign_evaluator_takes_the_lean_path_with_the_same_outputs():
    """``thermocal calibrate``'s evaluator (metrics and zone-group series) from the identified
    heat alone: the same outputs as from the whole tracking result, bit for bit."""
    from thermocal.calibration.spatial import campaign_evaluator

    problem = _problem()
    evaluator = campaign_evaluator(problem, problem.building)
    for parameters in (PARAMETERS, {}):
        frame = problem.identified_heat_frame(parameters)
        heat = problem.run(parameters).heat
        pd.testing.assert_frame_equal(frame, heat)
        assert evaluator.evaluate(parameters) == evaluator.outputs(heat)
