"""The network set-up's shortcuts give the numbers of the work they skip (issue 28, item 8):
view factors stopped at a recurring iterate, view factors and grey exchange factors shared by
zones of one geometry, and the assembly cache reused across parameter changes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest
import scipy.sparse as sp

from thermocal.multizone.model import Building, Construction, Location, Material, Surface, Zone
from thermocal.multizone.network import (
    SAME_PLANE_ANGLE,
    NetworkOptions,
    approximate_view_factors,
    assemble,
)
from thermocal.multizone.simulation import Simulation


def full_sweeps(area, tilt, azimuth, internal_mass=None, iterations=200):
    """The view factors with every sweep run (the algorithm before the early stop)."""
    area = np.asarray(area, dtype=float)
    tilt = np.asarray(tilt, dtype=float)
    azimuth = np.asarray(azimuth, dtype=float)
    n = len(area)
    mass = np.zeros(n, dtype=bool) if internal_mass is None else np.asarray(internal_mass, bool)
    d_az = np.abs((azimuth[:, None] - azimuth[None, :] + 180.0) % 360.0 - 180.0)
    horizontal = (tilt < SAME_PLANE_ANGLE) | (tilt > 180.0 - SAME_PLANE_ANGLE)
    same = (np.abs(tilt[:, None] - tilt[None, :]) <= SAME_PLANE_ANGLE) & (
        (d_az <= SAME_PLANE_ANGLE) | (horizontal[:, None] & horizontal[None, :])
    )
    sees = (~same | mass[:, None] | mass[None, :]) & ~np.eye(n, dtype=bool)
    seen_area = sees @ area
    f = np.where(sees, area[None, :], 0.0) / np.where(seen_area > 0, seen_area, 1.0)[:, None]
    af = area[:, None] * f
    af = 0.5 * (af + af.T)
    for _ in range(iterations):
        rows = af.sum(axis=1)
        af = af * np.where(rows > 0, area / np.where(rows > 0, rows, 1.0), 0.0)[:, None]
        af = 0.5 * (af + af.T)
    return af / area[:, None]


ZONES = {
    # EnergyPlus Case 600: floor, roof, walls, two south windows (a fixed point after ~70 sweeps)
    "case600": (
        [48.0, 48.0, 21.6, 9.6, 16.2, 16.2, 6.0, 6.0],
        [180.0, 0.0, 90.0, 90.0, 90.0, 90.0, 90.0, 90.0],
        [0.0, 0.0, 0.0, 180.0, 90.0, 270.0, 180.0, 180.0],
        None,
    ),
    # the multifamily prototype's attic: recurs only after ~1,200 sweeps (all 200 run)
    "attic": (
        [55.678, 392.537, 392.537, 40.937, 40.937] + [111.524] * 6,
        [180.0, 22.59006303, 22.59006303, 90.0, 90.0] + [180.0] * 6,
        [0.0, 0.0, 180.0, 90.0, 270.0] + [0.0] * 6,
        None,
    ),
    # a room with internal mass (seen by all)
    "mass": (
        [20.0, 20.0, 12.0, 12.0, 15.0, 15.0, 30.0],
        [180.0, 0.0, 90.0, 90.0, 90.0, 90.0, 90.0],
        [0.0, 0.0, 0.0, 180.0, 90.0, 270.0, 0.0],
        [False] * 6 + [True],
    ),
    # two faces in one plane see nothing: zero rows
    "blind": ([3.0, 5.0], [90.0, 90.0], [10.0, 15.0], None),
}


@pytest.mark.parametrize("iterations", [0, 1, 7, 200, 1500, 1501])
@pytest.mark.parametrize("zone", sorted(ZONES))
def test_view_factors_stopped_at_a_recurring_iterate_are_bit_identical(zone, iterations):
    args = ZONES[zone]
    np.testing.assert_array_equal(
        approximate_view_factors(*args, iterations=iterations),
        full_sweeps(*args, iterations=iterations),
    )


def test_view_factors_of_random_zones_are_bit_identical():
    rng = np.random.default_rng(28)
    for _ in range(40):
        n = int(rng.integers(2, 24))
        area = rng.uniform(0.5, 60.0, n)
        tilt = rng.choice([0.0, 30.0, 90.0, 180.0], n) + rng.uniform(-4.0, 4.0, n)
        azimuth = rng.uniform(0.0, 360.0, n)
        mass = rng.random(n) < 0.1
        np.testing.assert_array_equal(
            approximate_view_factors(area, tilt, azimuth, mass),
            full_sweeps(area, tilt, azimuth, mass),
        )


def two_rooms(wall_b=12.0, azimuth_b=90.0, emissivity_b=None, conductivity=0.04):
    """Two 6-face rooms with one wall construction; room b's east wall may differ in area,
    azimuth (5 deg puts it in the north wall's plane: they no longer see each other) and inside
    emissivity."""
    materials = [
        Material("brick", 0.8, 1800.0, 900.0, 0.1),
        Material("wool", conductivity, 20.0, 840.0, 0.1),
    ]
    surfaces = []
    for room in ("a", "b"):
        east = (wall_b, azimuth_b) if room == "b" else (12.0, 90.0)
        geometry = [
            ("floor", 20.0, 180.0, 0.0),
            ("roof", 20.0, 0.0, 0.0),
            ("north", 12.0, 90.0, 0.0),
            ("south", 12.0, 90.0, 180.0),
            ("east", east[0], 90.0, east[1]),
            ("west", 12.0, 90.0, 270.0),
        ]
        for name, area, tilt, azimuth in geometry:
            surfaces.append(
                Surface(
                    f"{room} {name}",
                    room,
                    "wall",
                    area,
                    tilt,
                    azimuth,
                    emissivity_inside=emissivity_b if room == "b" and name == "east" else None,
                )
            )
    return Building(
        name="two rooms",
        location=Location(47.4, 8.5, 0.0),
        materials=materials,
        constructions=[Construction("wall", ("brick", "wool"))],
        zones=[Zone(room, 60.0, 20.0, heating_setpoint=20.0) for room in ("a", "b")],
        surfaces=surfaces,
    )


def network_arrays(network) -> dict:
    out = {}
    for f in dataclasses.fields(network):
        value = getattr(network, f.name)
        if sp.issparse(value):
            value = value.toarray()
        out[f.name] = value
    return out


def assert_same_network(a, b):
    a, b = network_arrays(a), network_arrays(b)
    assert a.keys() == b.keys()
    for key in a:
        if isinstance(a[key], np.ndarray):
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
        else:
            assert a[key] == b[key], key


def zone_pairs(network, zone):
    faces = set(network.face_node[network.face_zone == zone].tolist())
    return np.array(
        [g for a, g in zip(network.lw_pair_a, network.lw_pair_g, strict=True) if int(a) in faces]
    )


VIEW = NetworkOptions(interior_longwave_exchange="view_factors")


@pytest.mark.parametrize(
    "changes",
    [{}, {"wall_b": 14.0}, {"azimuth_b": 5.0}, {"emissivity_b": 0.5}],
    ids=["congruent", "area", "azimuth", "emissivity"],
)
def test_zones_share_view_factors_only_when_their_geometry_is_the_same(changes):
    network = assemble(two_rooms(**changes), 300.0, options=VIEW)
    a, b = zone_pairs(network, 0), zone_pairs(network, 1)
    if changes:
        assert a.shape != b.shape or not np.array_equal(a, b)
    else:
        np.testing.assert_array_equal(a, b)
    # solar: the diffuse of a window-less zone is not used, so compare the view factors the
    # assembly cached: one per distinct zone geometry
    cache: dict = {}
    assemble(two_rooms(**changes), 300.0, options=VIEW, cache=cache)
    views = [v for k, v in cache.items() if k[0] == "view"]
    geometry_differs = "wall_b" in changes or "azimuth_b" in changes
    assert len(views) == (2 if geometry_differs else 1)


@pytest.mark.parametrize("options", [NetworkOptions(), VIEW], ids=["star", "view_factors"])
def test_a_cache_filled_by_another_geometry_gives_the_fresh_network(options):
    cache: dict = {}
    assemble(two_rooms(), 300.0, options=options, cache=cache)
    for changes in ({"wall_b": 14.0}, {"azimuth_b": 5.0}, {"emissivity_b": 0.5}):
        building = two_rooms(**changes)
        assert_same_network(
            assemble(building, 300.0, options=options, cache=cache),
            assemble(building, 300.0, options=options),
        )


@pytest.mark.parametrize("conduction", ["full", "reduced"])
def test_set_parameters_reuses_the_cache_and_gives_the_fresh_network(conduction):
    """One construction on every face: new material parameters give new layers (not the cached
    ones of the first parameters), as a simulation built afresh with them."""
    index = pd.date_range("2021-01-01", periods=48, freq="1h", tz="UTC")
    weather = pd.DataFrame(
        {
            "temp_air": 0.0,
            "ghi": 0.0,
            "dni": 0.0,
            "dhi": 0.0,
            "ghi_infrared": 300.0,
            "wind_speed": 2.0,
            "wind_direction": 180.0,
            "pressure": 101325.0,
        },
        index=index,
    )
    meta = {"latitude": 47.4, "longitude": 8.5, "altitude": 0.0}
    options = NetworkOptions(conduction=conduction, interior_longwave_exchange="view_factors")
    sim = Simulation(two_rooms(), weather, meta, step="1h", warmup_days=0, options=options)
    before = network_arrays(sim.network)
    sim.set_parameters({"material/wool/conductivity": 0.02, "material/brick/thickness": 0.2})
    fresh = Simulation(
        two_rooms(conductivity=0.02).with_parameters({"material/brick/thickness": 0.2}),
        weather,
        meta,
        step="1h",
        warmup_days=0,
        options=options,
    )
    assert_same_network(sim.network, fresh.network)
    assert not np.array_equal(before["conductance"], network_arrays(sim.network)["conductance"])


def test_window_inputs_of_earlier_parameters_are_not_kept():
    """A campaign changes the SHGC at every sample: the window inputs of the earlier values are
    dropped (they grew by ~2 MB a sample on the clinic's month), and the inputs are a fresh
    simulation's."""
    from thermocal.demos import buildings as generators
    from thermocal.demos.retrofit import pvlib_weather_path
    from thermocal.io.weather import read_weather

    weather, meta = read_weather(pvlib_weather_path())
    building = generators.clinic(12, n_corridors=1, corridor_sections=2)
    common = dict(step="1h", start="2001-06-01", end="2001-06-03", warmup_days=0)
    sim = Simulation(building, weather, meta, **common)
    shgc = "window/Exterior window/shgc"

    def window_keys():
        return {key for key in sim._input_cache if key[0] == "window"}

    first = window_keys()
    assert first
    for value in (0.3, 0.45):
        sim.set_parameters({shgc: value})
        keys = window_keys()
        assert len(keys) == len(first)  # one entry a window type and orientation
        assert {key[2] for key in keys if key[1] == "Exterior window"} == {value}
        fresh = Simulation(building.with_parameters({shgc: value}), weather, meta, **common)
        assert np.array_equal(sim._inputs, fresh._inputs)
        first = keys
