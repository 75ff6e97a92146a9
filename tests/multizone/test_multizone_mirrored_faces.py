"""EnergyPlus' adiabatic, self-facing and InternalMass surfaces: the outside face at the inside
face's temperature (``Surface.outside_at_inside``), and the shadows the building's own surfaces
may cast (``building_surface_can_shade``); see ``tests/identification/
test_identification_forward_outpatient.py`` for the comparison with EnergyPlus."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.multizone.model import (
    Building,
    Construction,
    Location,
    Material,
    NoMassMaterial,
    Surface,
    Zone,
)
from thermocal.multizone.network import STEFAN_BOLTZMANN, NetworkOptions
from thermocal.multizone.shading import ShadingSurface, ShadowCaster, building_surface_can_shade
from thermocal.multizone.simulation import Simulation, steady_state_heat_loss_coefficient


def swinging_weather(days=6, mean=5.0):
    """Dark, calm weather whose air temperature swings 10 K around ``mean`` [C] each day."""
    index = pd.date_range("2021-01-01", periods=int(days * 24), freq="1h", tz="UTC+01:00")
    temp = mean + 10.0 * np.sin(2 * np.pi * np.arange(len(index)) / 24.0)
    frame = pd.DataFrame(
        {
            "temp_air": temp,
            "ghi": 0.0,
            "dni": 0.0,
            "dhi": 0.0,
            "ghi_infrared": STEFAN_BOLTZMANN * (temp + 273.15) ** 4,
            "wind_speed": 2.0,
            "wind_direction": 180.0,
            "pressure": 101325.0,
        },
        index=index,
    )
    return frame, {"latitude": 47.4, "longitude": 8.5, "altitude": 0.0}


def room_with_mass(thickness, mirrored, heating=None):
    """A massless room (30 m2 faces outdoors) with 60 m2 of concrete internal mass."""
    materials = [
        NoMassMaterial("board", 2.0),
        Material("concrete", 1.311, 2240.0, 836.8, thickness),
    ]
    surfaces = [
        Surface("roof", "room", "light", 30.0, 0, 0),
        Surface("floor", "room", "light", 30.0, 180, 0),
        *(Surface(f"wall {az}", "room", "light", 30.0, 90, az) for az in (0, 90, 180, 270)),
        Surface(
            "mass",
            "room",
            "slab",
            60.0,
            90,
            0,
            boundary="adiabatic",
            outside_at_inside=mirrored,
            sun_exposed=False,
            wind_exposed=False,
        ),
    ]
    return Building(
        name="room",
        location=Location(47.4, 8.5, 0.0),
        materials=materials,
        constructions=[Construction("light", ("board",)), Construction("slab", ("concrete",))],
        zones=[Zone("room", 90.0, 30.0, internal_gains=300.0, heating_setpoint=heating)],
        surfaces=surfaces,
    )


def _air(building, cells):
    weather, meta = swinging_weather()
    result = Simulation(
        building, weather, meta, step="1h", options=NetworkOptions(cells_per_layer=cells)
    ).run(free_float=True)
    return result.air_temperature["room"].to_numpy()


def test_a_mirrored_slab_is_half_a_slab_with_an_insulated_back():
    """Both faces of a symmetric slab held at the inside temperature: the zone sees half of it
    with an insulated back (the midplane carries no heat), not the whole slab insulated."""
    mirrored = _air(room_with_mass(0.2, mirrored=True), cells=8)
    half = _air(room_with_mass(0.1, mirrored=False), cells=4)  # the same cells
    whole = _air(room_with_mass(0.2, mirrored=False), cells=8)
    assert np.abs(mirrored - half).max() < 1e-3
    assert np.abs(mirrored - whole).max() > 0.1  # the insulated whole slab stores twice as much


def test_a_mirrored_face_passes_no_heat_in_steady_state():
    """The heat loss coefficient (the network's conductance matrix, rows of mirrored faces
    included) is that of the envelope alone."""
    mirrored = steady_state_heat_loss_coefficient(room_with_mass(0.2, True, heating=20.0))
    insulated = steady_state_heat_loss_coefficient(room_with_mass(0.2, False, heating=20.0))
    assert mirrored == pytest.approx(insulated, rel=1e-6)


def test_outside_at_inside_needs_an_adiabatic_surface():
    with pytest.raises(ThermocalInputError, match="outside_at_inside"):
        Surface("w", "room", "light", 10.0, boundary="outdoors", outside_at_inside=True)


def _row_of_rooms():
    """Three rooms in a row with an asymmetric mirrored floor each (carpet over concrete: the
    network is not reciprocal) and different heating set points."""
    materials = [
        Material("board", 0.1, 600.0, 1200.0, 0.05),
        Material("concrete", 1.311, 2240.0, 836.8, 0.1),
        NoMassMaterial("carpet", 0.2165),
        Material("gypsum", 0.16, 785.0, 830.0, 0.0127),
    ]
    zones, surfaces = [], []
    for i, setpoint in enumerate((21.0, 18.0, 19.5)):
        name = f"room {i}"
        zones.append(Zone(name, 75.0, 25.0, internal_gains=150.0 * i, heating_setpoint=setpoint))
        surfaces += [
            Surface(f"roof {i}", name, "light", 25.0, 0, 0),
            Surface(f"south {i}", name, "light", 15.0, 90, 180),
            Surface(f"north {i}", name, "light", 15.0, 90, 0),
            Surface(f"floor {i}", name, "floor", 25.0, 180, 0, "adiabatic", outside_at_inside=True),
        ]
    for i in range(2):
        a, b = f"room {i}", f"room {i + 1}"
        surfaces += [
            Surface(f"p{i}a", a, "partition", 15.0, 90, 90, "zone", b, f"p{i}b"),
            Surface(f"p{i}b", b, "partition", 15.0, 90, 270, "zone", a, f"p{i}a"),
        ]
    surfaces += [
        Surface("west", "room 0", "light", 15.0, 90, 270),
        Surface("east", "room 2", "light", 15.0, 90, 90),
    ]
    return Building(
        name="row",
        location=Location(47.4, 8.5, 0.0),
        materials=materials,
        constructions=[
            Construction("light", ("board",)),
            Construction("floor", ("concrete", "carpet")),
            Construction("partition", ("gypsum", "gypsum")),
        ],
        zones=zones,
        surfaces=surfaces,
    )


def test_ideal_loads_hold_their_set_points_with_mirrored_faces():
    """The ideal loads' active-set inverse, updated zone by zone, is exact on the non-reciprocal
    network: every heated step ends exactly at the zone's set point."""
    weather, meta = swinging_weather(days=4, mean=16.0)
    result = Simulation(_row_of_rooms(), weather, meta, step="15min").run()
    for zone, setpoint in zip(result.air_temperature, (21.0, 18.0, 19.5), strict=True):
        heated = result.heating[zone] > 1e-6
        assert heated.any() and (~heated).any()  # zones join and leave the active set
        air = result.air_temperature[zone]
        assert np.abs(air[heated] - setpoint).max() < 1e-8
        assert air[~heated].min() >= setpoint - 1e-8


def _square(x0, x1, y0, y1, z0, z1):
    return np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z1], [x0, y1, z1]], dtype=float)


def test_a_building_surface_shades_only_what_lies_in_front_of_it():
    """EnergyPlus' shadow projection: a roof facing up casts no shadow, nor a wall on a surface
    behind it; both faces of a detached shading surface do."""
    receiver = np.array([[0, 0, 3], [0, 0, 0], [4, 0, 0], [4, 0, 3]], float)  # faces -y (south)
    south_facade = np.array([[0, -5, 9], [0, -5, 0], [4, -5, 0], [4, -5, 9]], float)  # faces -y
    north_facing = south_facade[::-1].copy()  # faces +y, toward the receiver
    roof = np.array([[0, -5, 9], [4, -5, 9], [4, 0, 9], [0, 0, 9]], float)  # faces up
    assert not building_surface_can_shade(south_facade, receiver)  # the receiver is behind it
    assert building_surface_can_shade(north_facing, receiver)
    assert not building_surface_can_shade(roof, receiver)
    sun = np.array([[0.0, -0.8, 0.6]])  # from the south, 37 deg high
    receivers = {"r": (receiver, [])}
    for caster, front_only, lit in (
        (south_facade, True, 1.0),
        (south_facade, False, 0.0),
        (north_facing, True, 0.0),
        (roof, True, 1.0),
    ):
        shader = ShadingSurface("s", caster, front_only=front_only)
        fraction = ShadowCaster([shader], receivers).sunlit_fraction("r", sun)[0]
        assert fraction == pytest.approx(lit, abs=0.02), (front_only, caster)


def test_the_active_set_inverse_is_exact_for_a_non_symmetric_response():
    """The rank-one additions and removals of the ideal loads' cached inverse on a response
    matrix that is not symmetric (mirrored faces) against a fresh inversion."""
    from thermocal.multizone._kernel import _sync_inverse

    rng = np.random.default_rng(3)
    n = 5
    g = np.eye(n) * 2.0 + 0.3 * rng.random((n, n))  # diagonally dominant, not symmetric
    member = np.zeros(n, dtype=np.bool_)
    inverse = np.zeros((n, n))
    counters = np.array([-1, 0, 0, 0, 0], dtype=np.int64)
    for active in ([1, 0, 0, 0, 0], [1, 1, 0, 1, 0], [0, 1, 1, 1, 0], [1, 1, 1, 1, 1]):
        active = np.array(active, dtype=np.int64)
        _sync_inverse(g, active, member, inverse, counters)
        idx = np.flatnonzero(active)
        expected = np.linalg.inv(g[np.ix_(idx, idx)])
        assert np.abs(inverse[np.ix_(idx, idx)] - expected).max() < 1e-12
    assert counters[1] > 0  # the updates, not fresh inversions, were tested
