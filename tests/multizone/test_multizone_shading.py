"""Shadows of overhangs and fins against their analytic sunlit fractions."""

from __future__ import annotations

import numpy as np
import pytest

from thermocal.multizone.shading import (
    ShadingSurface,
    ShadowCaster,
    interior_beam_fractions,
    sun_vectors,
)


def _south_window(width=2.0, height=1.5):
    # outward normal -y (south), vertices counter-clockwise seen from outside
    return np.array([[width, 0, height], [0, 0, height], [0, 0, 0], [width, 0, 0]], float)


def test_overhang_sunlit_fraction_is_the_analytic_one():
    width, height, gap, depth = 2.0, 1.5, 0.3, 1.0
    overhang = ShadingSurface(
        "overhang",
        np.array(
            [
                [-50, 0, height + gap],
                [50, 0, height + gap],
                [50, -depth, height + gap],
                [-50, -depth, height + gap],
            ],
            float,
        ),
    )
    caster = ShadowCaster([overhang], {"w": (_south_window(width, height), ())})
    assert caster.shaded == ["w"]
    altitude = np.array([10.0, 30.0, 45.0, 55.0, 60.0, 70.0])
    wall_solar = np.array([0.0, 20.0, -40.0, 10.0, 0.0, 0.0])
    sun = sun_vectors(90 - altitude, 180 + wall_solar)
    ours = caster.sunlit_fraction("w", sun)
    # vertical shadow (profile) angle: tan = tan(altitude) / cos(wall-solar azimuth)
    drop = depth * np.tan(np.radians(altitude)) / np.cos(np.radians(wall_solar))
    exact = 1 - np.clip(drop - gap, 0, height) / height
    np.testing.assert_allclose(ours, exact, atol=0.015)
    # sun behind the window: no beam to shade
    assert caster.sunlit_fraction("w", sun_vectors([60.0], [0.0]))[0] == 1.0
    # a 40 % transparent overhang lets 40 % of the shadowed beam through
    tau = np.full((len(sun), 1), 0.4)
    np.testing.assert_allclose(
        caster.sunlit_fraction("w", sun, tau), exact + 0.4 * (1 - exact), atol=0.015
    )


def test_fin_shadow_and_sky_diffuse_ratio():
    width, height, depth = 2.0, 1.5, 0.5
    # fin on the east edge (x = width), full height, sticking out to the south
    fin = ShadingSurface(
        "fin",
        np.array([[width, 0, -10], [width, 0, 10], [width, -depth, 10], [width, -depth, -10]]),
    )
    caster = ShadowCaster([fin], {"w": (_south_window(width, height), ())})
    # sun low in the south-east: the fin's shadow covers depth tan(gamma) of the width
    gamma = np.array([0.0, 20.0, 45.0, 70.0])
    sun = sun_vectors(np.full(4, 80.0), 180 - gamma)
    exact = 1 - np.clip(depth * np.tan(np.radians(gamma)), 0, width) / width
    np.testing.assert_allclose(caster.sunlit_fraction("w", sun), exact, atol=0.015)
    ratio = caster.sky_diffuse_ratio("w")
    assert 0.7 < ratio < 1.0
    # an unshaded receiver sees the whole sky
    assert ShadowCaster([], {"w": (_south_window(), ())}).sky_diffuse_ratio("w") == 1.0


def test_sky_dome_and_horizon_shading_ratios_are_energyplus_ones():
    """EnergyPlus' own unit test (tst/EnergyPlus/unit/SolarShading.unit.cc,
    ``SolarShadingTest_FigureSolarBeamAtTimestep``, ``SkyDifSolarShading``): a 6 x 2 m south
    window under a 1 m deep overhang as wide as the window, at its head, has
    ``DifShdgRatioIsoSky`` 0.6504 and ``DifShdgRatioHoriz`` 0.9152 (thermocal 0.648 / 0.910 at
    its default sampling, 0.651 / 0.916 with 16 x as many cells)."""
    window = np.array([[-3, -5, 2.5], [-3, -5, 0.5], [3, -5, 0.5], [3, -5, 2.5]], float)
    overhang = ShadingSurface(
        "shade", np.array([[-3, -5, 2.5], [-3, -6, 2.5], [3, -6, 2.5], [3, -5, 2.5]], float)
    )
    dome, horizon = ShadowCaster([overhang], {"w": (window, ())}).sky_diffuse_ratios("w")
    assert dome == pytest.approx(0.6504, abs=0.005)
    assert horizon == pytest.approx(0.9152, abs=0.01)
    # the horizon band is the lowest row of sky patches: an overhang hides less of it
    assert horizon > dome


@pytest.mark.parametrize("hole", [True, False])
def test_wall_minus_its_window(hole):
    wall = np.array([[4, 0, 3], [0, 0, 3], [0, 0, 0], [4, 0, 0]], float)
    window = np.array([[3, 0, 2], [1, 0, 2], [1, 0, 1], [3, 0, 1]], float)
    # a shade exactly in front of the window, 1 m out, sun straight from the south at 0 altitude
    shade = ShadingSurface("s", np.array([[3, -1, 2], [1, -1, 2], [1, -1, 1], [3, -1, 1]], float))
    caster = ShadowCaster([shade], {"wall": (wall, (window,) if hole else ())})
    lit = caster.sunlit_fraction("wall", sun_vectors([89.9], [180.0]))[0]
    assert lit == pytest.approx(1.0 if hole else 1 - 2 / 12, abs=0.02)


OVERHANG_AND_FINS = """
Shading:Overhang,
  WINDOW 1 OVERHANG, ZONE SUBSURFACE 1, 0.5, 90, 0.2, 0.3, 1.0;
Shading:Fin:Projection,
  WINDOW 2 FINS, ZONE SUBSURFACE 2, 0.1, 0.2, 0.0, 90, 0.25, 0.1, 0.2, 0.0, 90, 0.0;
"""


def test_idf_overhang_and_fins_are_placed_on_their_windows():
    import warnings

    from conftest import shared_data_path
    from thermocal.multizone.idf import read_idf

    source = shared_data_path("energyplus_reference") / "case_600_v25.idf"
    if not source.exists():
        pytest.skip(f"{source} not available")
    text = source.read_text() + OVERHANG_AND_FINS
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "case_600_shaded.idf"
        path.write_text(text)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            info = read_idf(path).idf_info
    shaders = {s.name: s.vertices for s in info.shading_surfaces}
    # window 1: x 0.5..3.5, z 0.2..2.2 in the south wall y = 0 (outward -y)
    overhang = shaders["WINDOW 1 OVERHANG"]
    np.testing.assert_allclose(overhang[:, 2], 2.7)
    np.testing.assert_allclose(sorted(set(np.round(overhang[:, 0], 6))), [0.3, 3.8])
    np.testing.assert_allclose(sorted(set(np.round(overhang[:, 1], 6))), [-1.0, 0.0])
    # window 2 (x 4.5..7.5): a left fin 0.25 x 3 m deep at x = 4.4 (seen from outside, west)
    assert set(shaders) == {"WINDOW 1 OVERHANG", "WINDOW 2 FINS left"}
    fin = shaders["WINDOW 2 FINS left"]
    np.testing.assert_allclose(fin[:, 0], 4.4)
    np.testing.assert_allclose(sorted(set(np.round(fin[:, 1], 6))), [-0.75, 0.0])
    np.testing.assert_allclose(sorted(set(np.round(fin[:, 2], 6))), [0.2, 2.4])
    assert "Shading:Overhang" not in info.unsupported


def test_interior_beam_lands_where_the_sun_puts_it():
    """A south window in an 8 x 6 x 2.7 m box (window sill 0.2 m, head 2.2 m), the sun due
    south: a ray from height z reaches the floor at z / tan(altitude) from the facade, the north
    wall beyond 6 m; at 10 deg the floor gets (6 tan 10 - 0.2) / 2 = 0.429 of the beam."""
    width, depth, height = 8.0, 6.0, 2.7
    faces = {
        "floor": [[0, 0, 0], [width, 0, 0], [width, depth, 0], [0, depth, 0]],
        "ceiling": [[0, 0, height], [0, depth, height], [width, depth, height], [width, 0, height]],
        "south": [[0, 0, 0], [0, 0, height], [width, 0, height], [width, 0, 0]],
        "north": [[0, depth, 0], [width, depth, 0], [width, depth, height], [0, depth, height]],
        "east": [[width, 0, 0], [width, 0, height], [width, depth, height], [width, depth, 0]],
        "west": [[0, 0, 0], [0, depth, 0], [0, depth, height], [0, 0, height]],
    }
    faces = {name: np.array(v, float) for name, v in faces.items()}
    window = np.array([[7, 0, 2.2], [1, 0, 2.2], [1, 0, 0.2], [7, 0, 0.2]], float)
    altitude = np.array([10.0, 20.0, 60.0])
    shares = interior_beam_fractions(window, faces, sun_vectors(90.0 - altitude, 180.0))
    names = list(faces)
    floor = np.clip((depth * np.tan(np.radians(altitude)) - 0.2) / 2.0, 0.0, 1.0)
    np.testing.assert_allclose(shares[:, names.index("floor")], floor, atol=0.01)
    np.testing.assert_allclose(shares[:, names.index("north")], 1.0 - floor, atol=0.01)
    np.testing.assert_allclose(shares.sum(axis=1), 1.0)
    # the sun from the south-west at 10 deg: part of the beam reaches the east wall
    oblique = interior_beam_fractions(window, faces, sun_vectors([80.0], [225.0]))[0]
    assert oblique[names.index("east")] > 0.3 and oblique[names.index("west")] == 0.0
    # the sun behind the window: no beam
    assert not interior_beam_fractions(window, faces, sun_vectors([60.0], [0.0])).any()


def test_interior_beam_skips_faces_in_the_windows_plane():
    """A window a few micrometres outside its host wall's plane (vertices written to five
    decimals on a wall off the axes): the rays leave the wall's plane and land on the floor and
    the far wall, none on the host (before: the cells outside the plane hit the host at once)."""
    faces = {
        "floor": [[0, 0, 0], [8, 0, 0], [8, 6, 0], [0, 6, 0]],
        "south": [[0, 0, 0], [0, 0, 2.7], [8, 0, 2.7], [8, 0, 0]],
        "north": [[0, 6, 0], [8, 6, 0], [8, 6, 2.7], [0, 6, 2.7]],
        "east": [[8, 0, 0], [8, 0, 2.7], [8, 6, 2.7], [8, 6, 0]],
        "west": [[0, 0, 0], [0, 6, 0], [0, 6, 2.7], [0, 0, 2.7]],
    }
    faces = {name: np.array(v, float) for name, v in faces.items()}
    # the window's upper edge 4 micrometres outside the south wall, its sill 4 inside
    window = np.array([[7, -4e-6, 2.2], [1, -4e-6, 2.2], [1, 4e-6, 0.2], [7, 4e-6, 0.2]], float)
    shares = interior_beam_fractions(window, faces, sun_vectors([60.0, 80.0], [180.0, 200.0]))
    names = list(faces)
    assert not shares[:, names.index("south")].any()
    np.testing.assert_allclose(shares.sum(axis=1), 1.0)
