"""The identified heat's uncertainty from the sensors' accuracy, against brute force: the
exact inverse run again with one sensor's reading offset, and a Monte Carlo of the offsets."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from thermocal.demos import buildings as generators
from thermocal.identification.sensor_accuracy import (
    held_zone_conductance,
    sensor_heat_uncertainty,
    sensor_weights,
)
from thermocal.multizone import Simulation


@functools.cache
def _tracked():
    from thermocal.demos.retrofit import pvlib_weather_path
    from thermocal.io.weather import read_weather

    weather, meta = read_weather(pvlib_weather_path())
    building = generators.clinic(12, n_corridors=1, corridor_sections=2)
    sim = Simulation(building, weather, meta, step="15min", start="2001-01-08",
                     end="2001-01-13", warmup_days=0, initial_temperature=15.0,
                     store_surfaces=False)  # fmt: skip
    heat = np.full((len(sim.times), len(building.zones)), 300.0)
    reference = sim.run(free_float=True, heat_input=heat).air_temperature.to_numpy()
    return sim, reference, sim.track(reference, method="inverse").heat.to_numpy()


@pytest.mark.parametrize("zone", [0, 3, 7])
def test_a_sensor_offset_moves_the_heat_the_steady_state_conductances_say(zone):
    sim, reference, base = _tracked()
    net = sim.network
    k = held_zone_conductance(net.conductance, net.air_node)
    offset = 0.5  # K
    moved = reference.copy()
    moved[:, zone] += offset
    again = sim.track(moved, method="inverse").heat.to_numpy()
    brute = (again - base).sum(axis=0) * sim.dt / 3.6e6  # kWh
    hours = len(sim.times) * sim.dt / 3600.0
    predicted = k[:, zone] * offset * hours / 1000.0
    # the offset's own zone and its neighbours (the walls' first charging is the difference)
    assert predicted[zone] == pytest.approx(brute[zone], rel=0.12)
    near = np.abs(brute) > 0.05 * abs(brute[zone])
    np.testing.assert_allclose(predicted[near], brute[near], rtol=0.15)
    assert np.abs(predicted[~near]).max() < 0.1 * abs(brute[zone])


def test_the_stated_uncertainty_is_the_spread_of_random_offsets():
    rng = np.random.default_rng(3)
    k = rng.normal(0.0, 5.0, (4, 4)) + np.diag([60.0, 50.0, 40.0, 70.0])
    zones = ["a", "b", "c", "d"]
    shared = {"a": "S1", "b": "S1", "c": "S2, S3", "d": ["S3"]}
    stated = sensor_heat_uncertainty(k, zones, 100.0, np.full(4, 50.0), accuracy=0.3,
                                     zone_sensors=shared)  # fmt: skip
    assert stated["sensors"] == 3
    offsets = rng.normal(0.0, 0.3, (200_000, 3))  # S1, S2, S3
    weights = sensor_weights(zones, shared)
    moved = offsets @ weights.T @ (k * 100.0 / 1000.0).T  # kWh per zone
    for i, zone in enumerate(zones):
        assert stated["independent"]["zones"][zone]["kwh"] == pytest.approx(
            moved[:, i].std(), rel=0.01
        )
    assert stated["independent"]["building_kwh"] == pytest.approx(
        moved.sum(axis=1).std(), rel=0.01
    )
    assert stated["shared"]["building_kwh"] == pytest.approx(0.3 * k.sum() * 0.1)
