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


def test_the_problem_tracks_its_reference_frame_without_a_copy():
    """The zone references are held once (issue 22, the clinic month's memory): the tracking
    reads the very array the problem's frame is a view of, and a problem whose frame was
    replaced builds its own array from the new frame."""
    import dataclasses

    problem = _problem()
    problem.simulation()
    values = problem._reference
    assert values.flags.c_contiguous and values.flags.writeable
    assert np.shares_memory(values, problem.reference.to_numpy())
    np.testing.assert_array_equal(values, problem.reference.to_numpy())
    shifted = dataclasses.replace(problem, reference=problem.reference + 1.0)
    shifted._sim, shifted._reference = None, values  # a stale array from elsewhere
    shifted.simulation()
    assert not np.shares_memory(shifted._reference, values)
    np.testing.assert_array_equal(shifted._reference, values + 1.0)


def test_tracking_metrics_by_blocks_equal_the_whole_array_at_once():
    """The per-zone tracking errors, computed a block of zones at a time, are those of the
    whole month's error array (brute force), NaN hours and a constant zone included."""
    from thermocal.identification.metrics import TRACKING_METRICS_BLOCK, tracking_metrics

    rng = np.random.default_rng(4)
    n_zones = 2 * TRACKING_METRICS_BLOCK + 5
    columns = [f"Z{i}" for i in range(n_zones)]
    reference = pd.DataFrame(20.0 + rng.normal(0, 2, (500, n_zones)), columns=columns)
    model = reference + rng.normal(0.1, 0.3, reference.shape)
    model.iloc[::7, 3] = np.nan
    reference.iloc[:, -1] = 0.0
    got = tracking_metrics(model, reference)
    error = model.to_numpy() - reference.to_numpy()
    np.testing.assert_allclose(got["rmse_K"], np.sqrt(np.nanmean(error**2, axis=0)), rtol=1e-14)
    np.testing.assert_allclose(got["max_abs_error_K"], np.nanmax(np.abs(error), axis=0))
    np.testing.assert_allclose(got["bias_K"], np.nanmean(error, axis=0), rtol=1e-12)
    level = np.mean(np.abs(reference.to_numpy()), axis=0)
    expected = 100.0 * np.sqrt(np.nanmean(error**2, axis=0)) / level
    np.testing.assert_allclose(got["error_std_percent"].to_numpy()[:-1], expected[:-1])
    assert np.isnan(got["error_std_percent"].iloc[-1])
    assert list(got.index) == columns
