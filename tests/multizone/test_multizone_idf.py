"""EnergyPlus IDF import (thermocal.multizone.idf): tokenizer, geometry, the two reference files,
and clear errors for bad input."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import (
    GeometryRules,
    IdfImportWarning,
    ScheduleEvaluator,
    newell_normal,
    parse_idf,
    polygon_area,
    read_idf,
    record,
    tilt_azimuth,
    to_world_coordinates,
)
from thermocal.multizone.model import construction_u_value


def _read(path):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        building = read_idf(path)
    return building, [w for w in caught if issubclass(w.category, IdfImportWarning)]


# ------------------------------------------------------------------------------------------------
# tokenizer and schema
# ------------------------------------------------------------------------------------------------


def test_parse_idf_fields_comments_and_case():
    text = """
    ! a comment line
    VERSION, 9.3;   ! trailing
      zone,
        Room A,        !- Name
        0, 1.5,
        2 ,            !- Z Origin {m}
        ;
    Material:NoMass, Board, Rough, 0.5;
    """
    objects = parse_idf(text, source="t.idf")
    assert [o.class_name for o in objects] == ["VERSION", "zone", "Material:NoMass"]
    zone = objects[1]
    assert zone.key == "ZONE"
    assert zone.fields == ("Room A", "0", "1.5", "2", "")
    assert zone.comments[0] == "Name"
    assert zone.comments[3] == "Z Origin {m}"
    assert zone.line == 4
    assert record(zone)["y_origin"] == "2"
    assert "t.idf line 4" in zone.where()


def test_parse_idf_missing_semicolon_names_object_and_line():
    with pytest.raises(ThermocalInputError, match=r"'Zone' starting at line 2 .*semicolon"):
        parse_idf("Version,9.3;\nZone,\n  A,\n  0", source="bad.idf")


def test_record_detects_space_name_field_of_newer_versions():
    old = parse_idf(
        "BuildingSurface:Detailed,W,Wall,C,Z,Outdoors,,SunExposed,WindExposed,0.5,4,"
        "0,0,1,0,0,0,1,0,0,1,0,1;"
    )[0]
    new = parse_idf(
        "BuildingSurface:Detailed,W,Wall,C,Z,Space 1,Outdoors,,SunExposed,WindExposed,"
        "0.5,4,0,0,1,0,0,0,1,0,0,1,0,1;"
    )[0]
    for obj in (old, new):
        rec = record(obj)
        assert rec["outside_boundary_condition"] == "Outdoors"
        assert len(rec["vertices"]) == 4
    assert record(new)["space_name"] == "Space 1"


# ------------------------------------------------------------------------------------------------
# geometry
# ------------------------------------------------------------------------------------------------


def test_polygon_area_convex_and_concave():
    square = np.array([[0, 0, 0], [2, 0, 0], [2, 3, 0], [0, 3, 0]], dtype=float)
    assert polygon_area(square) == pytest.approx(6.0)
    ell = np.array([[0, 0, 0], [4, 0, 0], [4, 1, 0], [1, 1, 0], [1, 3, 0], [0, 3, 0]], float)
    assert polygon_area(ell) == pytest.approx(4 + 2)
    tilted = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 1]], float)  # 45 deg roof
    assert polygon_area(tilted) == pytest.approx(math.sqrt(2))


@pytest.mark.parametrize(
    ("normal", "tilt", "azimuth"),
    [
        ((0, -1, 0), 90, 180),
        ((1, 0, 0), 90, 90),
        ((0, 1, 0), 90, 0),
        ((-1, 0, 0), 90, 270),
        ((0, 0, 1), 0, 0),
        ((0, 0, -1), 180, 0),
        ((0, -1, 1), 45, 180),
        ((1, 1, 0), 90, 45),
    ],
)
def test_tilt_azimuth_conventions(normal, tilt, azimuth):
    t, a = tilt_azimuth(np.array(normal, float))
    assert t == pytest.approx(tilt)
    assert a == pytest.approx(azimuth)


def test_vertex_order_and_coordinate_systems():
    # south wall of Case 600, counter-clockwise seen from outside (upper-left corner first)
    wall = np.array([[0, 0, 2.7], [0, 0, 0], [8, 0, 0], [8, 0, 2.7]], float)
    ccw = GeometryRules("UpperLeftCorner", "Counterclockwise", "Relative")
    assert tilt_azimuth(newell_normal(wall))[1] == pytest.approx(180)
    cw = GeometryRules("UpperLeftCorner", "Clockwise", "Relative")
    from thermocal.multizone.idf import outward_normal

    assert tilt_azimuth(outward_normal(wall, cw))[1] == pytest.approx(0)
    # relative coordinates: zone rotated 90 deg, building 30 deg -> faces 180 + 90 + 30 = 300
    world = to_world_coordinates(
        wall, rules=ccw, zone_origin=(10, 5, 3), zone_north_axis=90, building_north_axis=30
    )
    assert tilt_azimuth(outward_normal(world, ccw))[1] == pytest.approx(300)
    assert polygon_area(world) == pytest.approx(8 * 2.7)
    assert world[:, 2].min() == pytest.approx(3.0)
    # the zone origin is rotated with the building: it lands at R(30 deg) (10, 5)
    a = math.radians(30)
    origin_world = to_world_coordinates(
        np.zeros((1, 3)), rules=ccw, zone_origin=(10, 5, 0), building_north_axis=30
    )[0]
    assert origin_world[0] == pytest.approx(10 * math.cos(a) + 5 * math.sin(a))
    assert origin_world[1] == pytest.approx(-10 * math.sin(a) + 5 * math.cos(a))
    # world coordinates ignore origins and rotations
    world_rules = GeometryRules("UpperLeftCorner", "Counterclockwise", "World")
    same = to_world_coordinates(
        wall, rules=world_rules, zone_origin=(10, 5, 3), zone_north_axis=90, building_north_axis=30
    )
    np.testing.assert_allclose(same, wall)


# ------------------------------------------------------------------------------------------------
# ASHRAE 140 Case 600
# ------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def case600():
    from tests.conftest import shared_data_path

    return _read(shared_data_path("ashrae140_bestest", "case_en_600.idf"))


def test_case600_geometry(case600):
    building, _ = case600
    assert list(building.zones) == ["ZONE ONE"]
    zone = building.zones["ZONE ONE"]
    assert zone.floor_area == pytest.approx(48.0)
    assert zone.volume == pytest.approx(129.6)
    s = building.surfaces
    expected = {
        "ZONE SURFACE FLOOR": (48.0, 180, None, "ground"),
        "ZONE SURFACE ROOF": (48.0, 0, None, "outdoors"),
        "ZONE SURFACE SOUTH": (21.6, 90, 180, "outdoors"),
        "ZONE SURFACE NORTH": (21.6, 90, 0, "outdoors"),
        "ZONE SURFACE EAST": (16.2, 90, 90, "outdoors"),
        "ZONE SURFACE WEST": (16.2, 90, 270, "outdoors"),
    }
    assert set(s) == set(expected)
    for name, (area, tilt, azimuth, boundary) in expected.items():
        assert s[name].area == pytest.approx(area), name
        assert s[name].tilt == pytest.approx(tilt), name
        if azimuth is not None:
            assert s[name].azimuth == pytest.approx(azimuth), name
        assert s[name].boundary == boundary
    windows = building.windows
    assert len(windows) == 2
    assert all(
        w.area == pytest.approx(6.0) and w.surface == "ZONE SURFACE SOUTH" for w in windows.values()
    )
    assert building.net_area("ZONE SURFACE SOUTH") == pytest.approx(21.6 - 12.0)
    # closed box: the divergence-theorem volume equals the given one
    from thermocal.multizone.idf import zone_volume_from_surfaces

    info = building.idf_info
    names = list(expected)
    polys = [info.surface_vertices[n] for n in names]
    normals = [newell_normal(p) for p in polys]
    assert zone_volume_from_surfaces(polys, normals) == pytest.approx(129.6)
    # exterior convection as EnergyPlus: each surface's wind at its centroid height in the
    # file's terrain (Country: (270/10)^0.14 (z/270)^0.14 = (z/10)^0.14) and its perimeter
    assert s["ZONE SURFACE SOUTH"].wind_speed_factor == pytest.approx((1.35 / 10) ** 0.14)
    assert s["ZONE SURFACE ROOF"].wind_speed_factor == pytest.approx((2.7 / 10) ** 0.14)
    assert s["ZONE SURFACE SOUTH"].perimeter == pytest.approx(2 * (8.0 + 2.7))
    assert s["ZONE SURFACE ROOF"].perimeter == pytest.approx(2 * (8.0 + 6.0))
    assert s["ZONE SURFACE FLOOR"].wind_speed_factor is None  # ground: no wind


def test_case600_constructions_and_materials(case600):
    building, _ = case600
    m = building.materials
    assert m["FIBERGLASS QUILT-1"].conductivity == 0.04
    assert m["FIBERGLASS QUILT-1"].thickness == 0.066
    assert m["FIBERGLASS QUILT-1"].density == 12
    assert m["FIBERGLASS QUILT-1"].specific_heat == 840
    assert m["R-25 INSULATION"].resistance == pytest.approx(25.075)
    assert building.constructions["LTWALL"].layers == (
        "WOOD SIDING-1",
        "FIBERGLASS QUILT-1",
        "PLASTERBOARD-1",
    )
    # Standard 140 Case 600 U-values with its surface coefficients (interior 8.29, exterior
    # 29.3 W/(m2 K) combined): wall 0.514, roof 0.318 W/(m2 K); hand calculation of layers
    films = {"inside_resistance": 1 / 8.29, "outside_resistance": 1 / 29.3}
    wall = construction_u_value(building.construction_layers("LTWALL"), **films)
    hand_wall = 1 / (1 / 8.29 + 0.009 / 0.14 + 0.066 / 0.04 + 0.012 / 0.16 + 1 / 29.3)
    assert wall == pytest.approx(hand_wall, rel=1e-12)
    assert wall == pytest.approx(0.514, abs=0.001)
    roof = construction_u_value(building.construction_layers("LTROOF"), **films)
    assert roof == pytest.approx(0.318, abs=0.001)
    floor = construction_u_value(
        building.construction_layers("LTFLOOR"), outside_resistance=0, inside_resistance=1 / 8.29
    )
    assert floor == pytest.approx(1 / (25.075 + 0.025 / 0.14 + 1 / 8.29), rel=1e-12)
    assert floor == pytest.approx(0.039, abs=0.001)


def test_case600_window_loads_and_site(case600):
    building, warned = case600
    wt = building.window_types["Double Pane Window"]
    assert wt.solar_transmittance == pytest.approx(0.747, abs=0.001)  # Standard 140 spec
    assert wt.shgc == pytest.approx(0.789, abs=0.005)
    assert 2.6 < wt.u_value < 2.85  # NFRC centre-of-glass (spec 3.0 with its film coefficients)
    assert wt.transmittance(60.0) < wt.transmittance(0.0)
    assert wt.transmittance(90.0) == 0.0
    assert len(wt.pane_absorptances) == 2
    zone = building.zones["ZONE ONE"]
    assert zone.infiltration_ach == pytest.approx(0.5)
    assert zone.internal_gains == pytest.approx(200.0)
    assert zone.internal_gains_radiative_fraction == pytest.approx(0.6)
    assert (zone.heating_setpoint, zone.cooling_setpoint) == (20.0, 27.0)
    assert building.ground_temperatures == (10.0,) * 12
    loc = building.location
    assert (loc.latitude, loc.longitude, loc.altitude, loc.timezone) == (39.76, -104.86, 1611, -7)
    # exactly one short warning: counts per kind; the classes by kind in the report
    assert len(warned) == 1
    message = str(warned[0].message)
    assert "classes not represented, HVAC and plant" in message
    assert "Output:Variable" not in message and "NOT SIMULATED" not in message
    assert len(message.splitlines()) <= 5
    assert building.idf_info.unsupported["Output:Variable"] == 16
    report = building.idf_info.report()["unsupported"]
    assert report["hvac"]["ZoneHVAC:IdealLoadsAirSystem"] == 1
    assert report["harmless"]["LifeCycleCost:UsePriceEscalation"] == 5
    assert report["physics"] == {}


def test_case600_parameters_are_addressable(case600):
    building, _ = case600
    params = building.parameters()
    assert params["zone/ZONE ONE/infiltration_ach"] == pytest.approx(0.5)
    assert params["material/FIBERGLASS QUILT-1/conductivity"] == 0.04
    changed = building.with_parameters({"window/Double Pane Window/shgc": 0.6})
    assert changed.window_types["Double Pane Window"].shgc == pytest.approx(0.6)


# ------------------------------------------------------------------------------------------------
# 5ZoneAirCooled
# ------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def five_zone():
    from tests.conftest import shared_data_path

    return _read(shared_data_path("energyplus_idf", "5ZoneAirCooled.idf"))


def test_five_zone_geometry_matches_energyplus_report(five_zone):
    # EnergyPlus "Input Verification and Results Summary" of this building (EnergyPlus docs,
    # Using EnergyPlus for Compliance): total building area 927.20 m2 (plenum included), gross
    # wall area N/E/S/W 91.50/45.60/91.50/45.60 m2, window opening area 20.85/9.12/21.81/9.12 m2,
    # FRONT-1 azimuth 210 (north axis 30 deg).
    building, warned = five_zone
    assert len(building.zones) == 6
    assert sum(z.floor_area for z in building.zones.values()) == pytest.approx(927.2, abs=0.05)
    walls = {"N": 0.0, "E": 0.0, "S": 0.0, "W": 0.0}
    glass = dict.fromkeys(walls, 0.0)

    def sector(azimuth):
        return "NESW"[int(((azimuth + 45) % 360) // 90)]

    for s in building.surfaces.values():
        if s.boundary == "outdoors" and s.tilt == pytest.approx(90):
            walls[sector(s.azimuth)] += s.area
    for w in building.windows.values():
        glass[sector(building.surfaces[w.surface].azimuth)] += w.area
    assert walls == pytest.approx({"N": 91.5, "E": 45.6, "S": 91.5, "W": 45.6}, abs=0.01)
    assert glass == pytest.approx({"N": 20.85, "E": 9.12, "S": 21.81, "W": 9.12}, abs=0.01)
    assert building.surfaces["FRONT-1"].azimuth == pytest.approx(210)
    assert building.surfaces["RIGHT-1"].azimuth == pytest.approx(120)
    assert building.surfaces["TOP-1"].tilt == pytest.approx(0)
    assert len(warned) == 1


def test_five_zone_interzone_surfaces_and_windows(five_zone):
    building, _ = five_zone
    sb12, sb21 = building.surfaces["SB12"], building.surfaces["SB21"]
    assert sb12.boundary == "zone" and sb12.other_surface == "SB21"
    assert sb21.other_surface == "SB12" and sb21.zone == "SPACE2-1"
    assert sb12.area == pytest.approx(sb21.area)
    assert (sb12.azimuth - sb21.azimuth) % 360 == pytest.approx(180)
    ceiling, plenum_floor = building.surfaces["C1-1"], building.surfaces["C1-1P"]
    assert (ceiling.tilt, plenum_floor.tilt) == (0.0, 180.0)
    # window types: EnergyPlus tabular report U 2.720 / SHGC 0.764 and U 5.894 / SHGC 0.716
    dbl = building.window_types["Dbl Clr 3mm/13mm Air"]
    grey = building.window_types["Sgl Grey 3mm"]
    assert dbl.u_value == pytest.approx(2.720, rel=0.005)
    assert dbl.shgc == pytest.approx(0.764, abs=0.003)
    assert grey.u_value == pytest.approx(5.894, rel=0.005)
    assert grey.shgc == pytest.approx(0.716, abs=0.003)
    assert building.windows["DF-1"].area == pytest.approx(2.5 * 2.1)


def test_five_zone_loads(five_zone):
    building, _ = five_zone
    space1 = building.zones["SPACE1-1"]
    # Flow/Zone 0.032 m3/s in 239.25 m3, velocity coefficient 0.2237 at the 4.47 m/s reference
    assert space1.infiltration_ach == pytest.approx(0.032 * 3600 / 239.247360229 * 0.2237 * 4.47)
    assert building.zones["PLENUM-1"].infiltration_ach == 0
    assert not building.zones["PLENUM-1"].conditioned
    # set points: value in effect for most of the year (nights and weekends)
    assert (space1.heating_setpoint, space1.cooling_setpoint) == (16.7, 29.4)
    info = building.idf_info
    assert info.setpoint_schedules["SPACE1-1"] == ("Htg-SetP-Sch", "Clg-SetP-Sch")
    times = pd.date_range("2006-01-02 00:30", periods=24, freq="h")  # a Monday
    setpoints = info.setpoint_profile(times)
    assert setpoints[("SPACE1-1", "heating")].iloc[10] == pytest.approx(22.2)
    assert setpoints[("SPACE1-1", "heating")].iloc[3] == pytest.approx(16.7)
    # internal gains on a Monday 10:00-11:00 in SPACE1-1: lights 1584 W x 1.0 less the 20 %
    # return-air fraction (EnergyPlus sends it to the return air, in this file none), equipment
    # 1056 W x 0.9, 11 people x 78.05 W sensible x 1.0 (EnergyPlus' autocalculated sensible heat
    # at 117.24 W activity and 22 C, by hand from the Engineering Reference polynomial)
    gains = info.internal_gains_profile(times)["SPACE1-1"]
    assert gains.iloc[10] == pytest.approx(1584 * 0.8 + 1056 * 0.9 + 11 * 78.0475, rel=1e-5)
    assert gains.iloc[3] == pytest.approx(1584 * 0.8 * 0.05 + 1056 * 0.02)
    assert space1.internal_gains == pytest.approx(
        info.internal_gains_profile(pd.date_range("2006-01-01", periods=8760, freq="h"))[
            "SPACE1-1"
        ].mean(),
        rel=1e-9,
    )
    assert building.ground_temperatures[0] == 20.03


def test_five_zone_schedules_on_the_simulation_grid(five_zone):
    """Schedules as EnergyPlus applies them, hand-checked against the file's Schedule:Compact."""
    building, _ = five_zone
    info = building.idf_info
    # 15-min steps of Monday 2006-01-02 (the calendar of the file: 2006 starts on a Sunday)
    times = pd.date_range("2006-01-02", periods=96, freq="15min")
    step = pd.Timedelta("15min")
    heating = info.schedules.on_grid("Htg-SetP-Sch", times, step)
    # Htg-SetP-Sch weekdays: 16.7 until 06:00, 22.2 until 20:00, then 16.7
    assert heating[23] == pytest.approx(16.7) and heating[24] == pytest.approx(22.2)
    assert heating[79] == pytest.approx(22.2) and heating[80] == pytest.approx(16.7)
    # a step straddling a change takes the value at its end (Interpolate: No, as EnergyPlus)
    half = info.schedules.on_grid("Htg-SetP-Sch", pd.DatetimeIndex(["2006-01-02 05:30"]), "1h")
    assert half[0] == pytest.approx(22.2)
    # Sunday: the set-back all day
    sunday = info.schedules.on_grid(
        "Htg-SetP-Sch", pd.date_range("2006-01-01", periods=96, freq="15min"), step
    )
    assert np.all(sunday == pytest.approx(16.7))
    grid = pd.DataFrame({"wind_speed": np.full(96, 4.0)}, index=times)
    inputs = info.scheduled_inputs(list(building.zones), times, step, grid)
    space1 = list(building.zones).index("SPACE1-1")
    # infiltration in January: 0.032 m3/s x INFIL-SCH 1.0 x 0.2237 x (4 m/s at the zone height:
    # City terrain, centroid 1.22 m above ground -> factor (270/10)^0.14 (z/460)^0.33)
    height = 1.2192
    factor = (270 / 10) ** 0.14 * (height / 460) ** 0.33
    expected = 0.032 * 3600 / 239.247360229 * 0.2237 * 4.0 * factor
    assert inputs.infiltration_ach[40, space1] == pytest.approx(expected, rel=0.02)
    # lights: 59 % radiant + 20 % visible = radiant, 1 % convective; the 20 % return-air fraction
    # reaches no zone (EnergyPlus 25.2 on this file: Lights Return Air Heating Rate 108 W mean,
    # not in the zone air heat balance)
    total = inputs.gains_convective[40, space1] + inputs.gains_radiant[40, space1]
    assert total == pytest.approx(1584 * 0.8 + 1056 * 0.9 + 11 * 78.0475, rel=1e-4)


# ------------------------------------------------------------------------------------------------
# synthetic files: methods, schedules, errors
# ------------------------------------------------------------------------------------------------

BOX = """
Version,9.3;
Building,Box,{north};
GlobalGeometryRules,UpperLeftCorner,Counterclockwise,Relative;
Material,M1,Rough,0.2,1.0,2000,1000,0.9,0.6,0.6;
Construction,C1,M1;
Zone,Z1,{zone_north},{ox},{oy},0,,1,,{volume};
BuildingSurface:Detailed,Floor,Floor,C1,Z1,Ground,,NoSun,NoWind,0,4,4,3,0,4,0,0,0,0,0,0,3,0;
BuildingSurface:Detailed,Roof,Roof,C1,Z1,Outdoors,,SunExposed,WindExposed,0,4,4,0,2.5,4,3,2.5,0,3,2.5,0,0,2.5;
BuildingSurface:Detailed,South,Wall,C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,0,0,2.5,0,0,0,4,0,0,4,0,2.5;
BuildingSurface:Detailed,North,Wall,C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,4,3,2.5,4,3,0,0,3,0,0,3,2.5;
BuildingSurface:Detailed,East,Wall,C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,4,0,2.5,4,0,0,4,3,0,4,3,2.5;
BuildingSurface:Detailed,West,Wall,C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,0,3,2.5,0,3,0,0,0,0,0,0,2.5;
{extra}
"""


def _box(
    tmp_path, *, extra="", north=0, zone_north=0, ox=0, oy=0, volume="autocalculate", name="box.idf"
):
    path = tmp_path / name
    path.write_text(
        BOX.format(extra=extra, north=north, zone_north=zone_north, ox=ox, oy=oy, volume=volume)
    )
    return path


def test_box_volume_orientation_and_infiltration_methods(tmp_path):
    extra = """
    ZoneInfiltration:DesignFlowRate,I1,Z1,,Flow/Area,,0.0001,,,,,,;
    ZoneInfiltration:DesignFlowRate,I2,Z1,,Flow/ExteriorArea,,,0.0002,,,,,;
    ZoneInfiltration:DesignFlowRate,I3,Z1,,AirChanges/Hour,,,,0.3,,,,;
    """
    building, _ = _read(_box(tmp_path, extra=extra, north=20, zone_north=10, ox=5, oy=7))
    zone = building.zones["Z1"]
    assert zone.volume == pytest.approx(4 * 3 * 2.5)  # closed polyhedron
    assert zone.floor_area == pytest.approx(12.0)
    assert building.surfaces["South"].azimuth == pytest.approx(210)
    assert building.surfaces["East"].azimuth == pytest.approx(120)
    exterior = 12 + 2 * 4 * 2.5 + 2 * 3 * 2.5  # roof and walls (the floor is on the ground)
    ach = (0.0001 * 12 + 0.0002 * exterior) * 3600 / 30 + 0.3
    assert zone.infiltration_ach == pytest.approx(ach)


def test_box_with_zonelist_gains_and_compact_schedule(tmp_path):
    extra = """
    ZoneList,All,Z1;
    Schedule:Compact,Occ,Fraction,Through: 12/31,For: Weekdays,Until: 08:00,0,Until: 18:00,1,
      Until: 24:00,0,For: AllOtherDays,Until: 24:00,0.5;
    ElectricEquipment,E1,All,Occ,Watts/Area,,10,,0.1,0.3,0.1;
    HVACTemplate:Thermostat,T1,,19,,26;
    HVACTemplate:Zone:IdealLoadsAirSystem,Z1,T1;
    """
    building, warned = _read(_box(tmp_path, extra=extra))
    zone = building.zones["Z1"]
    sensible = 10 * 12 * (1 - 0.1 - 0.1)
    weekday = 10 / 24  # 2006: 260 weekdays, 105 weekend days
    mean = sensible * (260 * weekday + 105 * 0.5) / 365
    assert zone.internal_gains == pytest.approx(mean)
    assert zone.internal_gains_radiative_fraction == pytest.approx(0.3 / 0.8)
    assert (zone.heating_setpoint, zone.cooling_setpoint) == (19.0, 26.0)
    assert "1 more notes apply only where the file's schedules" in str(warned[0].message)
    assert any("varies" in n for n in building.idf_info.report()["notes"]["constant_schedules"])


def test_schedule_year_week_day_objects():
    text = """
    Schedule:Day:Interval,D1,Any,No,06:00,1,24:00,3;
    Schedule:Day:Hourly,D2,Any,0,0,0,0,0,0,0,0,0,0,0,0,2,2,2,2,2,2,2,2,2,2,2,2;
    Schedule:Week:Daily,W1,D2,D1,D1,D1,D1,D1,D2,D1,D1,D1,D1,D1;
    Schedule:Year,Y1,Any,W1,1,1,12,31;
    """
    evaluator = ScheduleEvaluator(parse_idf(text), year=2006)  # Jan 1 2006 is a Sunday
    hourly = evaluator.hourly("Y1")
    assert hourly.size == 8760
    assert hourly[:24].tolist() == [0.0] * 12 + [2.0] * 12  # Sunday: D2
    assert hourly[24:48].tolist() == [1.0] * 6 + [3.0] * 18  # Monday: D1
    assert evaluator.annual_mean("Y1") == pytest.approx((260 * 60 / 24 + 105 * 1.0) / 365)


@pytest.mark.parametrize(
    ("extra", "replace", "match"),
    [
        (
            "",
            (
                "C1,Z1,Outdoors,,SunExposed,WindExposed,0.5,4,0,0",
                "C1,Z9,Outdoors,,SunExposed,WindExposed,0.5,4,0,0",
            ),
            r"BuildingSurface:Detailed 'South' \(box.idf line \d+\): field 'Zone Name' = 'Z9'",
        ),
        (
            "",
            ("Construction,C1,M1;", "Construction,C1,M1,M2;"),
            r"Construction 'C1' .*field 'Layer 2' = 'M2' is not defined",
        ),
        ("", ("Material,M1,Rough,0.2,", "Material,M1,Rough,0,"), r"Material 'M1' .*thickness"),
        (
            "",
            (
                "Outdoors,,SunExposed,WindExposed,0.5,4,4,0,2.5",
                "Surface,Nowhere,SunExposed,WindExposed,0.5,4,4,0,2.5",
            ),
            r"BuildingSurface:Detailed 'East' .*'Nowhere' is not a building surface",
        ),
        (
            "",
            ("Floor,Floor,C1,Z1,Ground", "Floor,Floor,C1,Z1,Sky"),
            r"'Floor' .*Outside Boundary Condition' = 'Sky'",
        ),
        (
            "ZoneInfiltration:DesignFlowRate,I1,Z1,,Flow/Zone,,,,,,,,;",
            ("", ""),
            r"ZoneInfiltration:DesignFlowRate 'I1' .*'Design Flow Rate' is blank",
        ),
        ("Material,M1,Rough,0.1,1,1,1;", ("", ""), r"name 'M1' is already used"),
    ],
)
def test_bad_input_names_object_and_field(tmp_path, extra, replace, match):
    path = _box(tmp_path, extra=extra)
    text = path.read_text()
    if replace[0]:
        assert replace[0] in text
        text = text.replace(replace[0], replace[1], 1)
    path.write_text(text)
    with pytest.raises(ThermocalInputError, match=match):
        read_idf(path)


def test_window_construction_on_opaque_surface_and_one_sided_partner(tmp_path):
    glazing = """
    WindowMaterial:SimpleGlazingSystem,SG,1.8,0.5;
    Construction,Win,SG;
    FenestrationSurface:Detailed,W1,Window,Win,South,,0.5,,2,4,1,0,2,1,0,1,3,0,1,3,0,2;
    """
    building, _ = _read(_box(tmp_path, extra=glazing))
    assert building.windows["W1"].area == pytest.approx(4.0)  # 2 m x 1 m, multiplier 2
    assert building.window_types["Win"].u_value == pytest.approx(1.8)
    assert building.window_types["Win"].shgc == pytest.approx(0.5)
    path = _box(
        tmp_path, extra=glazing.replace(",Window,Win,South", ",Window,C1,South"), name="b2.idf"
    )
    with pytest.raises(ThermocalInputError, match=r"'W1' .*'C1' is not a window construction"):
        read_idf(path)
    # a zone boundary without partner surface gets a mirrored partner (EnergyPlus "Zone")
    extra = "Zone,Z2,0,0,0,0,,1,,10;"
    path = _box(tmp_path, extra=extra, name="b3.idf")
    text = path.read_text().replace("North,Wall,C1,Z1,Outdoors,,", "North,Wall,C1,Z1,Zone,Z2,")
    path.write_text(text)
    building, _ = _read(path)
    partner = building.surfaces["North (partner)"]
    assert partner.zone == "Z2" and partner.other_surface == "North"
    assert partner.azimuth == pytest.approx(180)
    # a door in that wall is merged into it (an inter-zone door), on both sides: the file
    # loads (it was refused: "area 10.0 m2 differs from its partner (8.0 m2)", survey of NREL's
    # 4ZoneWithShading_Simple_2, 2026-11-30)
    door = "Construction,DoorC,M1;\nFenestrationSurface:Detailed,D1,Door,DoorC,North,,0.5,,1,4,"
    door += "2,3,2,2,3,0,1,3,0,1,3,2;\n"
    path.write_text(text + door)
    building, _ = _read(path)
    assert "D1" not in building.surfaces
    assert building.surfaces["North"].area == pytest.approx(4 * 2.5)
    assert building.surfaces["North (partner)"].area == pytest.approx(4 * 2.5)


def test_world_coordinates_ignore_zone_origin_and_north(tmp_path):
    path = _box(tmp_path, north=30, zone_north=45, ox=100, oy=50, volume=30)
    text = path.read_text().replace("Counterclockwise,Relative;", "Counterclockwise,World;")
    path.write_text(text)
    building, _ = _read(path)
    assert building.surfaces["South"].azimuth == pytest.approx(180)
    vertices = building.idf_info.surface_vertices["South"]
    assert vertices[:, 0].min() == pytest.approx(0.0)  # not shifted by the zone origin


def test_door_becomes_a_surface_and_is_removed_from_its_host(tmp_path):
    extra = """
    Construction,DoorC,M1;
    FenestrationSurface:Detailed,D1,Door,DoorC,South,,0.5,,1,4,1,0,2,1,0,0,2,0,0,2,0,2;
    """
    building, _ = _read(_box(tmp_path, extra=extra))
    door = building.surfaces["D1"]
    assert door.area == pytest.approx(2.0)
    assert door.azimuth == pytest.approx(180) and door.boundary == "outdoors"
    assert building.surfaces["South"].area == pytest.approx(4 * 2.5 - 2.0)


def test_gain_with_unsupported_schedule_names_the_object(tmp_path):
    extra = "OtherEquipment,Eq,None,Z1,FromFile,EquipmentLevel,100,,,0,0.5,0;"
    with pytest.raises(ThermocalInputError, match=r"OtherEquipment 'Eq' .*'FromFile'"):
        read_idf(_box(tmp_path, extra=extra))


def test_internal_mass_becomes_an_adiabatic_surface(tmp_path):
    extra = "InternalMass,Furniture,C1,Z1,25;"
    building, _ = _read(_box(tmp_path, extra=extra))
    mass = building.surfaces["Furniture"]
    assert (mass.zone, mass.construction, mass.area, mass.boundary) == (
        "Z1",
        "C1",
        25.0,
        "adiabatic",
    )


def test_other_equipment_layouts_with_and_without_fuel_type(tmp_path):
    with_fuel = parse_idf("OtherEquipment,Eq,,Z1,Sch,EquipmentLevel,100,,,0,0.5,0;")[0]
    without = parse_idf("OtherEquipment,Eq,Z1,Sch,EquipmentLevel,100,,,0,0.5,0;")[0]
    for obj in (with_fuel, without):
        rec = record(obj)
        assert (rec["zone_name"], rec["design_level"], rec["fraction_radiant"]) == (
            "Z1",
            "100",
            "0.5",
        )


def test_unsupported_construction_class_is_named(tmp_path):
    path = _box(tmp_path, extra="Construction:AirBoundary,Slab,None;")
    text = path.read_text().replace("Floor,Floor,C1,Z1,Ground", "Floor,Floor,Slab,Z1,Ground")
    path.write_text(text)
    with pytest.raises(ThermocalInputError, match="Construction:AirBoundary is not supported"):
        read_idf(path)


def test_five_zone_exterior_roughness_from_the_outer_material(five_zone):
    # DOE-2 roughness multipliers by the outermost layer's Roughness, as EnergyPlus:
    # WALL-1 starts with WD01 (MediumSmooth, 1.13), ROOF-1 with RG01 (Rough, 1.67), glass 1.0
    from thermocal.multizone.model import Material
    from thermocal.multizone.network import assemble

    building, _ = five_zone
    assert building.materials["WD01"].roughness == "MediumSmooth"
    net = assemble(building, 900.0)
    factor = dict(zip(net.ext_names, net.ext_roughness, strict=True))
    assert factor["FRONT-1"] == 1.13
    assert factor["TOP-1"] == 1.67
    assert factor["WF-1"] == 1.0
    with pytest.raises(ThermocalInputError, match="material 'stucco': roughness 'Bumpy'"):
        Material("stucco", 0.7, 1800.0, 900.0, 0.02, roughness="Bumpy")


# ------------------------------------------------------------------------------------------------
# geometry and property checks (issue 13): each of these was accepted silently before
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("replace", "match"),
    [
        (  # the south wall's vertices reversed: it would face north, silently
            ("0.5,4,0,0,2.5,0,0,0,4,0,0,4,0,2.5;", "0.5,4,4,0,2.5,4,0,0,0,0,0,0,0,2.5;"),
            r"BuildingSurface:Detailed 'South' \(box.idf line \d+\): its vertices run the wrong "
            r"way.*points into zone 'Z1'.*reverse the vertex order",
        ),
        (  # one vertex of the north wall 3 m out of its plane: area and tilt changed silently
            ("0.5,4,4,3,2.5,4,3,0,0,3,0,0,3,2.5;", "0.5,4,4,3,2.5,4,6,0,0,3,0,0,3,2.5;"),
            r"BuildingSurface:Detailed 'North' .*vertex 2 lies 3\.00 m off the plane",
        ),
        (
            ("Material,M1,Rough,0.2,1.0,", "Material,M1,Rough,0.2,1e30,"),
            r"material 'M1'.*conductivity 1e\+30 W/\(m K\) is outside the physically plausible",
        ),
        (
            ("Material,M1,Rough,0.2,", "Material,M1,Rough,1e-9,"),
            r"material 'M1'.*thickness 1e-09 m is outside",
        ),
        (
            ("Material,M1,Rough,0.2,", "Material,M1,Rough,200,"),
            r"material 'M1'.*thickness 200 m .*given in mm\? then write 0\.2",
        ),
        (
            ("Material,M1,Rough,0.2,1.0,2000,1000,", "Material,M1,Rough,0.2,1.0,2,1000,"),
            r"material 'M1'.*density 2 kg/m3 .*g/cm3 or t/m3\? then write 2000",
        ),
        (
            ("Material,M1,Rough,0.2,1.0,2000,1000,", "Material,M1,Rough,0.2,1.0,2000,1,"),
            r"material 'M1'.*specific_heat 1 J/\(kg K\) .*kJ/\(kg K\)\? then write 1000",
        ),
    ],
)
def test_geometry_and_properties_are_checked(tmp_path, replace, match):
    path = _box(tmp_path)
    text = path.read_text()
    assert replace[0] in text
    path.write_text(text.replace(replace[0], replace[1], 1))
    with pytest.raises(ThermocalInputError, match=match):
        read_idf(path)


def test_open_zone_is_not_mistaken_for_a_reversed_surface(tmp_path):
    """A zone with a surface missing does not close: no surface is blamed for it."""
    path = _box(tmp_path)
    lines = path.read_text().splitlines()
    text = "\n".join(line for line in lines if not line.startswith("BuildingSurface:Detailed,Roof"))
    path.write_text(text)
    building, _ = _read(path)
    assert "Roof" not in building.surfaces


def test_people_sensible_heat_follows_the_zone_temperature():
    """EnergyPlus' polynomial of the People sensible heat as coefficients of T and T^2 (the
    time loop adds b (T - 22) + c (T^2 - 22^2) to the gains held at 22 C)."""
    from thermocal.multizone import _kernel
    from thermocal.multizone.idf.loads import (
        PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE,
        people_sensible_coefficients,
        people_sensible_heat,
    )

    assert _kernel.PEOPLE_T0 == PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE
    activity = np.array([100.0, 120.0, 200.0])
    a, b, c = people_sensible_coefficients(activity)
    for t in (18.0, 22.0, 28.0):
        np.testing.assert_allclose(a + b * t + c * t * t, people_sensible_heat(activity, t))
    # ASHRAE table values EnergyPlus fits: about 70 W of 120 W sensible at 24 C, less when warmer
    assert 65 < float(people_sensible_heat(120.0, 24.0)) < 80
    assert people_sensible_heat(120.0, 28.0) < people_sensible_heat(120.0, 22.0)


def test_import_summary_on_the_terminal_and_full_report_in_summary_json(tmp_path, shared_data):
    """A class that changes the heat balance is named on the terminal; HVAC classes and the notes
    are counted in a few lines, the harmless classes stay quiet; summary.json holds every class
    and note by kind."""
    import json

    from typer.testing import CliRunner

    from thermocal.cli import app

    extra = """
    ZoneMixing,Mix,Z1,Always,Flow/Zone,0.1,,,,Z1;
    Schedule:Constant,Always,,1;
    Output:Variable,*,Zone Mean Air Temperature,Hourly;
    ZoneHVAC:IdealLoadsAirSystem,Ideal,,,,,,,;
    Schedule:Compact,Occ,Fraction,Through: 12/31,For: Weekdays,Until: 08:00,0,Until: 18:00,1,
      Until: 24:00,0,For: AllOtherDays,Until: 24:00,0.5;
    ElectricEquipment,E1,Z1,Occ,EquipmentLevel,100;
    """
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    out = tmp_path / "out"
    result = CliRunner().invoke(
        app,
        [
            "simulate",
            str(_box(tmp_path, extra=extra)),
            str(weather),
            "--start",
            "2023-01-10",
            "--end",
            "2023-01-11",
            "--step",
            "1h",
            "--out",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "NOT SIMULATED although they change the heat balance (1 objects): ZoneMixing (1)" in text
    assert "1 objects of 1 classes not represented, HVAC and plant" in text
    assert "more notes apply only where the file's schedules are replaced" in text
    assert "varies" not in text  # the constant-mode notes are counted, not printed
    assert "Output:Variable" not in text and "outputs, sizing" not in text
    report = json.loads((out / "summary.json").read_text())["idf_import"]
    assert report["unsupported"]["physics"] == {"ZoneMixing": 1}
    assert report["unsupported"]["harmless"] == {"Output:Variable": 1}
    assert any("E1" in n for n in report["notes"]["constant_schedules"])


@pytest.mark.parametrize(
    "cls, kind",
    [
        ("Output:Variable", "harmless"),
        ("Sizing:Zone", "harmless"),
        ("LifeCycleCost:Parameters", "harmless"),
        ("ZoneHVAC:IdealLoadsAirSystem", "hvac"),
        ("Coil:Heating:Water", "hvac"),
        ("ZoneMixing", "physics"),
        ("WindowShadingControl", "physics"),
        ("Daylighting:Controls", "physics"),
        ("EnergyManagementSystem:Program", "physics"),
    ],
)
def test_unsupported_class_kinds(cls, kind):
    from thermocal.multizone.idf import unsupported_kind

    assert unsupported_kind(cls) == kind


@pytest.mark.parametrize(
    ("version", "outcome"),
    [("7.2", "older than the IDF versions thermocal reads"), ("99.1", "newer than the newest"),
     ("9.3", None), ("25.2", None)],
)
def test_idf_version_outside_the_supported_range_is_named(tmp_path, version, outcome):
    """An IDF of version 7.2 failed on a RunPeriod field without naming its version; 99.1 was
    accepted silently."""
    path = _box(tmp_path)
    path.write_text(path.read_text().replace("Version,9.3;", f"Version,{version};"))
    if outcome and outcome.startswith("older"):
        with pytest.raises(ThermocalInputError, match=rf"version {version} is {outcome}.*8\.0"):
            _read(path)
        return
    building, _ = _read(path)
    notes = " ".join(building.idf_info.notes)
    assert (outcome in notes) if outcome else ("newer than" not in notes)
