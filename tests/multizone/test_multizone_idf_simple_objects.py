"""IDF objects read since the multifamily prototype (issue 28 item 4), checked without
EnergyPlus against hand-computed values: ``Window`` / ``Door`` placed on their base surface,
``GasEquipment``, the Sherman-Grimsrud leakage linearisation, open zones, and the building's own
shadow casters (``test_multizone_idf_multifamily.py`` checks the same against EnergyPlus)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import read_idf
from thermocal.multizone.idf.loads import leakage_flow_linearised
from thermocal.multizone.idf.shading import _casts_on_others, _merge_coplanar
from thermocal.multizone.shading import ShadingSurface

BOX = """
Version,{version};
Building,Box,0;
GlobalGeometryRules,UpperLeftCorner,Counterclockwise,Relative;
Material,M1,Rough,0.2,1.0,2000,1000,0.9,0.6,0.6;
Construction,C1,M1;
WindowMaterial:SimpleGlazingSystem,SG,2.0,0.6;
Construction,Glass,SG;
Zone,Z1,0,0,0,0,,1,,autocalculate;
BuildingSurface:Detailed,Floor,Floor,C1,Z1,Ground,,NoSun,NoWind,0,4,4,3,0,4,0,0,0,0,0,0,3,0;
BuildingSurface:Detailed,Roof,Roof,C1,Z1,Outdoors,,SunExposed,WindExposed,0,4,4,0,2.5,4,3,2.5,0,3,2.5,0,0,2.5;
BuildingSurface:Detailed,South,Wall,C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,0,0,2.5,0,0,0,4,0,0,4,0,2.5;
BuildingSurface:Detailed,North,Wall,C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,4,3,2.5,4,3,0,0,3,0,0,3,2.5;
BuildingSurface:Detailed,East,Wall,C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,4,0,2.5,4,0,0,4,3,0,4,3,2.5;
BuildingSurface:Detailed,West,Wall,C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,0,3,2.5,0,3,0,0,0,0,0,0,2.5;
{extra}
"""


def _read(tmp_path, extra, version="9.3"):
    path = tmp_path / "box.idf"
    path.write_text(BOX.format(extra=extra, version=version))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_idf(path)


def _corners(points):
    return sorted(tuple(np.round(p, 6)) for p in np.asarray(points))


def test_window_and_door_placed_from_the_lower_left_corner_seen_from_outside(tmp_path):
    # south wall seen from the south: x runs east from (0, 0, 0); east wall seen from the east:
    # x runs north from (4, 0, 0)
    extra = "Window,W1,Glass,South,,1,0.5,0.8,2.0,1.2;\nDoor,D1,C1,East,1,1.0,0,0.9,2.0;"
    building = _read(tmp_path, extra)
    vertices = building.idf_info.surface_vertices
    assert _corners(vertices["W1"]) == _corners(
        [(0.5, 0, 0.8), (2.5, 0, 0.8), (2.5, 0, 2.0), (0.5, 0, 2.0)]
    )
    assert _corners(vertices["D1"]) == _corners([(4, 1, 0), (4, 1.9, 0), (4, 1.9, 2), (4, 1, 2)])
    assert building.windows["W1"].area == pytest.approx(2.4)
    assert building.surfaces["South"].area == pytest.approx(10.0)  # gross, as for any window
    assert building.surfaces["D1"].area == pytest.approx(1.8)
    assert building.surfaces["East"].area == pytest.approx(7.5 - 1.8)
    # before EnergyPlus 9.0 a Window had a 'Shading Control Name' after its base surface
    old = _read(tmp_path, "Window,W1,Glass,South,,,1,0.5,0.8,2.0,1.2;", version="8.6")
    assert _corners(old.idf_info.surface_vertices["W1"]) == _corners(vertices["W1"])


def test_window_on_a_horizontal_surface_is_refused(tmp_path):
    with pytest.raises(ThermocalInputError, match="base surface 'Roof' is horizontal"):
        _read(tmp_path, "Window,W1,Glass,Roof,,1,0.5,0.5,1,1;")


def test_gas_equipment_is_an_internal_gain(tmp_path):
    building = _read(tmp_path, "GasEquipment,G1,Z1,,EquipmentLevel,500,,,0.1,0.3,0.2;")
    zone = building.zones["Z1"]
    assert zone.internal_gains == pytest.approx(500 * (1 - 0.1 - 0.2))
    assert zone.internal_gains_radiative_fraction == pytest.approx(0.3 / 0.7)


def test_leakage_area_infiltration_tangent_of_sherman_grimsrud():
    leakage = (100.0, 0.00029, 0.000231)  # cm2, (L/s)2/(cm4 K), (L/s)2/(cm4 (m/s)2)
    outdoor = np.array([-10.0, 0.0, 5.0])
    wind = np.array([0.0, 3.0, 6.0])
    q0, q1 = leakage_flow_linearised(leakage, outdoor, wind, reference=18.0)

    def exact(dt):
        return 100.0 / 1000.0 * np.sqrt(0.00029 * dt + 0.000231 * wind**2)

    dt0 = np.abs(18.0 - outdoor)
    assert np.allclose(q0 + q1 * dt0, exact(dt0))  # exact at the reference
    for dt in (0.0, 5.0, 40.0):
        assert np.all(q0 + q1 * dt >= exact(dt) - 1e-15)  # the tangent lies above
    step = 1e-6
    slope = (exact(dt0 + step) - exact(dt0 - step)) / (2 * step)
    assert np.allclose(q1, slope, rtol=1e-5)


def test_leakage_area_object_read_per_zone(tmp_path):
    building = _read(tmp_path, "ZoneInfiltration:EffectiveLeakageArea,L1,Z1,,100,0.00029,0.000231;")
    (inf,) = building.idf_info.infiltration
    assert inf.leakage == (100.0, 0.00029, 0.000231)
    # the constant zone rate: wind 4.47 m/s, no indoor-outdoor difference
    flow = 100.0 / 1000.0 * np.sqrt(0.000231) * 4.47
    assert building.zones["Z1"].infiltration_ach == pytest.approx(flow * 3600 / 30.0)


def test_open_zone_of_stacked_floors_is_read_with_energyplus_ceiling_height(tmp_path):
    # a breezeway: two exterior floor slabs and a ceiling, no walls (EnergyPlus: not enclosed)
    extra = """
    Zone,B,0,0,0,0,,1,,autocalculate;
    BuildingSurface:Detailed,B1,Floor,C1,B,Outdoors,,SunExposed,WindExposed,,4,4,5,0,0,5,0,0,6,0,4,6,0;
    BuildingSurface:Detailed,B2,Floor,C1,B,Outdoors,,SunExposed,WindExposed,,4,4,5,3,0,5,3,0,6,3,4,6,3;
    BuildingSurface:Detailed,B3,Ceiling,C1,B,Outdoors,,SunExposed,WindExposed,,4,0,5,6,4,5,6,4,6,6,0,6,6;
    """
    building = _read(tmp_path, extra)
    # floor area 2 x 4 m2, ceiling height 6 - (0 + 3) / 2 = 4.5 m
    assert building.zones["B"].volume == pytest.approx(8.0 * 4.5)


def _rectangle(name, x0, x1, z0, z1, y=0.0, facing=-1.0):
    points = [(x0, y, z1), (x0, y, z0), (x1, y, z0), (x1, y, z1)]
    if facing > 0:
        points = points[::-1]
    return ShadingSurface(name, np.array(points, dtype=float))


def test_own_shadow_casters_and_facade_merging():
    # two rows facing each other across a gap: the row at y = 0 faces north (+y), the one at
    # y = 2 faces south (-y); storeys of each facade are coplanar
    south_row = [_rectangle(f"S{k}", 0, 10, 3 * k, 3 * k + 3, y=0.0, facing=1.0) for k in range(3)]
    north_row = [_rectangle(f"N{k}", 0, 10, 3 * k, 3 * k + 3, y=2.0) for k in range(3)]
    casting = _casts_on_others([*south_row, *north_row])
    assert len(casting) == 6
    # a convex building casts no shadow on itself
    box = [
        _rectangle("s", 0, 4, 0, 3, y=0.0),
        _rectangle("n", 0, 4, 0, 3, y=5.0, facing=1.0),
        ShadingSurface("e", np.array([(4, 0, 3), (4, 0, 0), (4, 5, 0), (4, 5, 3)], float)),
        ShadingSurface("w", np.array([(0, 5, 3), (0, 5, 0), (0, 0, 0), (0, 0, 3)], float)),
        ShadingSurface("r", np.array([(0, 0, 3), (4, 0, 3), (4, 5, 3), (0, 5, 3)], float)),
    ]
    assert _casts_on_others(box) == []
    merged = _merge_coplanar(casting)
    assert len(merged) == 2  # one rectangle per facade
    for polygon in merged:
        points = np.asarray(polygon.vertices)
        assert np.ptp(points[:, 0]) == pytest.approx(10) and np.ptp(points[:, 2]) == pytest.approx(
            9
        )
    # a gap in a facade keeps its pieces
    gapped = _merge_coplanar([south_row[0], _rectangle("S2", 0, 10, 6, 9, y=0.0, facing=1.0)])
    assert len(gapped) == 2
