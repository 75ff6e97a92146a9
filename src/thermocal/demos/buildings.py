"""Parametric test buildings: a 1950s single-family house and a single-storey clinic.

Both are generated from a rectangular floor plan (:func:`plan_building`): zones are axis-aligned
rectangles on storeys; shared edges become inter-zone partitions (described from both sides),
free edges become exterior walls (or ground-contact walls below grade), overlaps between storeys
become floors/ceilings, the rest of the top becomes roof and the rest of the bottom ground floor.
Coordinates: x to the east, y to the north [m]; the plan can be rotated by ``orientation``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from thermocal.errors import ThermocalInputError
from thermocal.multizone.model import (
    Building,
    Construction,
    Location,
    Material,
    NoMassMaterial,
    Surface,
    Window,
    WindowType,
    Zone,
)

_SIDES = {"south": 180.0, "east": 90.0, "north": 0.0, "west": 270.0}


@dataclass
class Room:
    """A rectangular zone on a storey of a plan [m]."""

    name: str
    storey: int
    x0: float
    x1: float
    y0: float
    y1: float
    infiltration_ach: float = 0.3
    internal_gains: float = 0.0
    heating_setpoint: float | None = None
    cooling_setpoint: float | None = None
    infiltration_group: str | None = None
    furniture_area_ratio: float = 0.5
    kind: str = "room"

    @property
    def floor_area(self) -> float:
        return (self.x1 - self.x0) * (self.y1 - self.y0)


@dataclass
class Storey:
    """A storey: height [m]; ``below_grade`` storeys have ground-contact walls and floor.

    ``roof_tilt`` [deg] > 0 gives a pitched roof (slopes facing south/north) over the storey's rooms
    and ``knee_wall_height`` [m] for its south/north walls.
    """

    height: float
    below_grade: bool = False
    roof_tilt: float = 0.0
    knee_wall_height: float | None = None


@dataclass
class Constructions:
    """Construction names by role."""

    exterior_wall: str
    roof: str
    ground_floor: str
    interior_wall: str
    intermediate_floor: str
    furniture: str | None = None
    ground_wall: str | None = None
    cellar_ceiling: str | None = None


def _overlap(a0, a1, b0, b1) -> float:
    return max(0.0, min(a1, b1) - max(a0, b0))


def _edges(room: Room):
    """(side, fixed coordinate, start, end) of the four walls of a room."""
    return (
        ("south", room.y0, room.x0, room.x1),
        ("north", room.y1, room.x0, room.x1),
        ("west", room.x0, room.y0, room.y1),
        ("east", room.x1, room.y0, room.y1),
    )


_OPPOSITE = {"south": "north", "north": "south", "west": "east", "east": "west"}


def plan_building(
    name: str,
    rooms: Sequence[Room],
    storeys: Sequence[Storey],
    constructions: Constructions,
    *,
    materials,
    construction_list,
    window_types,
    window_rule: Callable[[Room, str, float], list[tuple[str, float, float]]] | None = None,
    door_rule: Callable[[Room, Room], tuple[str, float] | None] | None = None,
    location: Location | None = None,
    orientation: float = 0.0,
    ground_temperatures=None,
) -> Building:
    """Build a :class:`Building` from rectangular rooms on storeys.

    Parameters
    ----------
    name : str
    rooms : sequence of Room
    storeys : sequence of Storey
    constructions : Constructions
        Construction names by role.
    materials, construction_list, window_types : sequences
        Passed to :class:`Building`.
    window_rule : callable, optional
        ``f(room, side, wall_area) -> [(window_type, area [m2], frame_fraction)]`` for each
        exterior wall.
    door_rule : callable, optional
        ``f(room_a, room_b) -> (construction, area [m2]) or None``: a door carved out of the
        partition between two rooms of a storey.
    location : Location, optional
    orientation : float [deg]
        Rotation of the plan (clockwise, added to all azimuths).
    ground_temperatures : sequence of 12 floats or None [C]
    """
    zones = []
    surfaces: list[Surface] = []
    windows: list[Window] = []
    by_storey: dict[int, list[Room]] = {}
    for room in rooms:
        by_storey.setdefault(room.storey, []).append(room)
        height = storeys[room.storey].height
        zones.append(
            Zone(
                room.name,
                volume=room.floor_area * height,
                floor_area=room.floor_area,
                infiltration_ach=room.infiltration_ach,
                internal_gains=room.internal_gains,
                heating_setpoint=room.heating_setpoint,
                cooling_setpoint=room.cooling_setpoint,
                infiltration_group=room.infiltration_group,
            )
        )

    def az(side: str) -> float:
        return (_SIDES[side] + orientation) % 360.0

    pair_count = 0

    def partition(a: Room, b: Room, area: float, tilt_a: float, az_a: float, construction: str):
        nonlocal pair_count
        pair_count += 1
        name_a = f"{a.name} | {b.name} #{pair_count}"
        name_b = f"{b.name} | {a.name} #{pair_count}"
        tilt_b = 180.0 - tilt_a
        az_b = (az_a + 180.0) % 360.0
        surfaces.append(
            Surface(name_a, a.name, construction, area, tilt_a, az_a, "zone", b.name, name_b)
        )
        surfaces.append(
            Surface(name_b, b.name, construction, area, tilt_b, az_b, "zone", a.name, name_a)
        )

    for level, members in by_storey.items():
        storey = storeys[level]
        for room in members:
            for side, coord, start, end in _edges(room):
                length = end - start
                shared = 0.0
                for other in members:
                    if other is room:
                        continue
                    for o_side, o_coord, o_start, o_end in _edges(other):
                        if o_side != _OPPOSITE[side] or abs(o_coord - coord) > 1e-6:
                            continue
                        common = _overlap(start, end, o_start, o_end)
                        if common <= 1e-9:
                            continue
                        shared += common
                        # describe each shared wall once: from the room with the smaller name order
                        if (level, room.name) < (level, other.name):
                            wall_height = storey.height
                            area = common * wall_height
                            door = door_rule(room, other) if door_rule else None
                            if door is not None and door[1] < area:
                                partition(room, other, door[1], 90.0, az(side), door[0])
                                area -= door[1]
                            partition(
                                room, other, area, 90.0, az(side), constructions.interior_wall
                            )
                free = length - shared
                if free <= 1e-6:
                    continue
                wall_height = storey.height
                if storey.roof_tilt > 0 and side in ("south", "north"):
                    wall_height = storey.knee_wall_height or storey.height
                area = free * wall_height
                wall_name = f"{room.name} {side} wall"
                if storey.below_grade:
                    surfaces.append(
                        Surface(
                            wall_name,
                            room.name,
                            constructions.ground_wall or constructions.exterior_wall,
                            area,
                            90.0,
                            az(side),
                            "ground",
                        )
                    )
                    continue
                surfaces.append(
                    Surface(wall_name, room.name, constructions.exterior_wall, area, 90.0, az(side))
                )
                if window_rule is not None:
                    for k, (wt, w_area, frame) in enumerate(window_rule(room, side, area)):
                        windows.append(
                            Window(f"{wall_name} window {k + 1}", wall_name, wt, w_area, frame)
                        )
            # floor / ceiling
            below = by_storey.get(level - 1, [])
            covered = 0.0
            for other in below:
                common = _overlap(room.x0, room.x1, other.x0, other.x1) * _overlap(
                    room.y0, room.y1, other.y0, other.y1
                )
                if common > 1e-9:
                    covered += common
                    construction = (
                        constructions.cellar_ceiling
                        if storeys[level - 1].below_grade and constructions.cellar_ceiling
                        else constructions.intermediate_floor
                    )
                    partition(room, other, common, 180.0, 0.0, construction)
            rest = room.floor_area - covered
            if rest > 1e-6:
                surfaces.append(
                    Surface(
                        f"{room.name} floor",
                        room.name,
                        constructions.ground_floor,
                        rest,
                        180.0,
                        0.0,
                        "ground",
                    )
                )
            above = by_storey.get(level + 1, [])
            covered = sum(
                _overlap(room.x0, room.x1, o.x0, o.x1) * _overlap(room.y0, room.y1, o.y0, o.y1)
                for o in above
            )
            rest = room.floor_area - covered
            if rest > 1e-6:
                roof_name = f"{room.name} roof"
                if storey.roof_tilt > 0:
                    y_mid = 0.5 * (min(r.y0 for r in members) + max(r.y1 for r in members))
                    side = "south" if 0.5 * (room.y0 + room.y1) < y_mid else "north"
                    tilt = storey.roof_tilt
                    surfaces.append(
                        Surface(
                            roof_name,
                            room.name,
                            constructions.roof,
                            rest / math.cos(math.radians(tilt)),
                            tilt,
                            az(side),
                        )
                    )
                else:
                    surfaces.append(
                        Surface(roof_name, room.name, constructions.roof, rest, 0.0, 0.0)
                    )
                if window_rule is not None:
                    for k, (wt, w_area, frame) in enumerate(window_rule(room, "roof", rest)):
                        windows.append(
                            Window(f"{roof_name} window {k + 1}", roof_name, wt, w_area, frame)
                        )
            if constructions.furniture and room.furniture_area_ratio > 0:
                surfaces.append(
                    Surface(
                        f"{room.name} furniture",
                        room.name,
                        constructions.furniture,
                        room.furniture_area_ratio * room.floor_area,
                        90.0,
                        0.0,
                        "adiabatic",
                    )
                )
    return Building(
        name=name,
        location=location or Location(),
        materials=materials,
        constructions=construction_list,
        window_types=window_types,
        zones=zones,
        surfaces=surfaces,
        windows=windows,
        ground_temperatures=ground_temperatures,
    )


# ----------------------------------------------------------------------------------------------
# single-family house
# ----------------------------------------------------------------------------------------------


def single_family_house(
    *,
    heating_setpoint: float | None = 20.0,
    infiltration_ach: float = 0.45,
    internal_gains_per_area: float = 0.0,
    orientation: float = 0.0,
    location: Location | None = None,
) -> Building:
    """A 1950s Swiss-like single-family house: unheated cellar and three heated storeys.

    Footprint 10 m x 8 m; cellar (unheated, below grade), ground and first floor (2.7 m, three
    zones each), attic under a 40 deg pitched roof (two zones, 60 m2 usable). About 220 m2 heated
    floor area. Constructions of the period: 30 cm hollow-brick walls (U ~1.1), uninsulated timber
    roof with wood-wool boards (U ~1.1), concrete cellar ceiling with a cork layer (U ~1.0),
    double-glazed wooden windows (U 2.7, g 0.65, 30 % frame); 0.45 air changes per hour.
    Heat loss coefficient ~450-550 W/K (see :func:`steady_state_heat_loss_coefficient`).

    Parameters
    ----------
    heating_setpoint : float or None [C]
        Ideal heating set point of the heated zones (None: free-floating).
    infiltration_ach : float [1/h]
        Air changes of the heated zones (the cellar gets 0.3).
    internal_gains_per_area : float [W/m2]
    orientation : float [deg]
        Rotation of the plan, clockwise.
    location : Location, optional
        Default: Zurich (47.38 N, 8.54 E, 556 m).
    """
    materials = [
        Material("exterior render", 0.87, 1800.0, 1000.0, 0.02, solar_absorptance=0.5),
        Material("hollow clay brick", 0.44, 1200.0, 900.0, 0.30),
        Material("lime plaster", 0.70, 1400.0, 1000.0, 0.015),
        Material("concrete", 1.80, 2300.0, 1000.0, 0.30),
        Material("concrete slab", 1.80, 2300.0, 1000.0, 0.15),
        Material("screed", 1.40, 2000.0, 1000.0, 0.04),
        Material("cork board", 0.045, 120.0, 1800.0, 0.02),
        Material("oak parquet", 0.18, 700.0, 1600.0, 0.02),
        Material("roof boarding", 0.13, 500.0, 1600.0, 0.024, solar_absorptance=0.7),
        Material("wood-wool board", 0.09, 400.0, 1500.0, 0.05),
        Material("timber floor", 0.13, 500.0, 1600.0, 0.024),
        NoMassMaterial("joist cavity", 0.20),
        Material("interior brick", 0.50, 1400.0, 900.0, 0.12),
        Material("soil", 1.50, 1800.0, 1000.0, 0.5),
        Material("furniture wood", 0.13, 600.0, 1600.0, 0.02),
    ]
    constructions = [
        Construction("external wall", ("exterior render", "hollow clay brick", "lime plaster")),
        Construction("roof", ("roof boarding", "wood-wool board", "lime plaster")),
        # floors are described from the room above: layers from the room below (outside) upwards
        Construction("cellar ceiling", ("concrete slab", "screed", "cork board", "oak parquet")),
        Construction("intermediate floor", ("lime plaster", "joist cavity", "timber floor")),
        Construction("cellar wall", ("soil", "concrete")),
        Construction("cellar floor", ("soil", "concrete slab")),
        Construction("interior wall", ("lime plaster", "interior brick", "lime plaster")),
        Construction("furniture", ("furniture wood",)),
    ]
    window_types = [WindowType("double glazing 1950s", 2.7, 0.65)]
    roles = Constructions(
        exterior_wall="external wall",
        roof="roof",
        ground_floor="cellar floor",
        interior_wall="interior wall",
        intermediate_floor="intermediate floor",
        furniture="furniture",
        ground_wall="cellar wall",
        cellar_ceiling="cellar ceiling",
    )
    storeys = [
        Storey(2.3, below_grade=True),
        Storey(2.7),
        Storey(2.7),
        Storey(2.4, roof_tilt=40.0, knee_wall_height=1.0),
    ]
    sp = heating_setpoint

    def room(name, storey, x0, x1, y0, y1, heated=True):
        area = (x1 - x0) * (y1 - y0)
        return Room(
            name,
            storey,
            x0,
            x1,
            y0,
            y1,
            infiltration_ach=infiltration_ach if heated else 0.3,
            internal_gains=internal_gains_per_area * area if heated else 0.0,
            heating_setpoint=sp if heated else None,
            furniture_area_ratio=0.5 if heated else 0.0,
        )

    rooms = [
        room("cellar", 0, 0, 10, 0, 8, heated=False),
        room("ground living", 1, 0, 10, 0, 4),
        room("ground kitchen", 1, 5, 10, 4, 8),
        room("ground hall", 1, 0, 5, 4, 8),
        room("first bedroom south", 2, 0, 10, 0, 4),
        room("first bedroom east", 2, 5, 10, 4, 8),
        room("first bath and hall", 2, 0, 5, 4, 8),
        room("attic south", 3, 0, 10, 0, 4),
        room("attic north", 3, 0, 10, 4, 8),
    ]
    # attic usable floor area: 60 m2 of the 80 m2 (low parts under the slopes)
    glazing = "double glazing 1950s"

    def windows(r: Room, side: str, area: float):
        if r.storey == 0:
            return []
        if side == "roof":
            return [(glazing, 1.0, 0.3)] if r.storey == 3 else []
        if r.storey == 3:
            return [(glazing, 1.2, 0.3)] if side in ("east", "west") else []
        share = {"south": 0.24, "east": 0.16, "west": 0.16, "north": 0.12}[side]
        return [(glazing, round(share * area, 2), 0.3)]

    building = plan_building(
        "single-family house 1950s",
        rooms,
        storeys,
        roles,
        materials=materials,
        construction_list=constructions,
        window_types=window_types,
        window_rule=windows,
        location=location or Location(47.38, 8.54, 556.0),
        orientation=orientation,
    )
    for name in ("attic south", "attic north"):
        zone = building.zones[name]
        zone.floor_area = 30.0
    return building


# ----------------------------------------------------------------------------------------------
# clinic
# ----------------------------------------------------------------------------------------------


def clinic(
    n_rooms: int = 180,
    *,
    n_corridors: int = 3,
    room_width: float = 4.0,
    room_depth: float = 5.0,
    corridor_width: float = 2.4,
    height: float = 3.0,
    corridor_sections: int = 2,
    window_fraction: float = 0.35,
    heating_setpoint: float | None = None,
    cooling_setpoint: float | None = None,
    internal_gains_per_area: float = 0.0,
    orientation: float = 0.0,
    location: Location | None = None,
) -> Building:
    """Single-storey 1970s outpatient clinic: rows of rooms along double-loaded corridors.

    The size and envelope of the envelope-calibration case study's building: ``n_rooms`` rooms in
    ``2 n_corridors`` rows, each corridor cut into ``corridor_sections`` zones (so 180 rooms + 6
    corridor zones = 186 zones by default); outer rows have windows, inner rows are back to back;
    corridor ends have glazed exterior doors, corridors have skylights. Constructions from the US
    DOE commercial reference building "outpatient health care, pre-1980" with an added R16
    insulation layer (13 materials); no internal gains and no HVAC by default (free-floating), as
    in that study. Infiltration groups (one calibration parameter each): every room row split into
    a west and an east wing, and one per corridor. About 70 envelope parameters
    (:meth:`Building.parameters`).

    Parameters
    ----------
    n_rooms : int
        Multiple of ``2 n_corridors``.
    n_corridors : int
    room_width, room_depth, corridor_width, height : float [m]
    corridor_sections : int
    window_fraction : float [-]
        Window share of the exterior walls of rooms.
    heating_setpoint, cooling_setpoint : float or None [C]
    internal_gains_per_area : float [W/m2]
    orientation : float [deg]
    location : Location, optional
        Default: Champaign, Illinois (40.1 N, 88.2 W, 230 m).
    """
    rows = 2 * n_corridors
    if n_rooms <= 0 or n_rooms % rows:
        raise ThermocalInputError(
            f"clinic: n_rooms={n_rooms} must be a positive multiple of 2 * n_corridors = {rows} "
            f"(e.g. {rows * max(1, round(n_rooms / rows))})"
        )
    per_row = n_rooms // rows
    length = per_row * room_width
    if corridor_sections < 1 or corridor_sections > per_row:
        raise ThermocalInputError(f"clinic: corridor_sections must lie in [1, {per_row}]")
    materials = [
        Material("Stucco", 0.6918, 1858.0, 836.8, 0.0253, solar_absorptance=0.7),
        Material("Concrete block", 0.9, 1200.0, 920.0, 0.2032),
        NoMassMaterial("R16 insulation", 2.818),
        Material("Gypsum board", 0.16, 800.0, 1090.0, 0.0159),
        Material("Metal decking", 45.006, 7680.0, 418.4, 0.0015),
        Material("Roof membrane", 0.16, 1121.3, 1460.0, 0.0095, solar_absorptance=0.7),
        Material("Roof insulation", 0.049, 265.0, 836.8, 0.05),
        Material("Concrete slab", 1.311, 2240.0, 836.8, 0.1524),
        Material("Carpet", 0.06, 200.0, 1300.0, 0.01),
        Material("Structural wood", 0.12, 100.0, 1210.0, 0.01),
        Material("Wood door", 0.15, 608.0, 1630.0, 0.0445),
        Material("Steel", 45.0, 7850.0, 500.0, 0.0015),
        Material("Soil", 1.5, 1800.0, 1000.0, 0.3),
    ]
    constructions = [
        Construction(
            "Exterior wall", ("Stucco", "Concrete block", "R16 insulation", "Gypsum board")
        ),
        Construction("Roof", ("Roof membrane", "Roof insulation", "Metal decking")),
        Construction("Slab on grade", ("Soil", "Concrete slab", "Carpet")),
        Construction("Interior wall", ("Gypsum board", "Gypsum board")),
        Construction("Interior door", ("Wood door",)),
        Construction("Exterior door", ("Steel", "Wood door")),
        Construction("Furnishings", ("Structural wood",)),
    ]
    window_types = [
        WindowType("Exterior window", 4.0, 0.6),
        WindowType("Door glazing", 5.8, 0.8, n_panes=1),
        WindowType("Skylight", 5.5, 0.7, n_panes=1),
    ]
    roles = Constructions(
        exterior_wall="Exterior wall",
        roof="Roof",
        ground_floor="Slab on grade",
        interior_wall="Interior wall",
        intermediate_floor="Interior wall",
        furniture="Furnishings",
    )
    rooms: list[Room] = []
    y = 0.0
    row = 0
    section_length = length / corridor_sections
    for c in range(n_corridors):
        for side in ("south", "north"):
            if side == "north":
                y_corr = y
                for s in range(corridor_sections):
                    rooms.append(
                        Room(
                            f"Corridor {c + 1}.{s + 1}",
                            0,
                            s * section_length,
                            (s + 1) * section_length,
                            y_corr,
                            y_corr + corridor_width,
                            infiltration_ach=0.3,
                            internal_gains=internal_gains_per_area
                            * section_length
                            * corridor_width,
                            heating_setpoint=heating_setpoint,
                            cooling_setpoint=cooling_setpoint,
                            infiltration_group=f"corridor {c + 1}",
                            furniture_area_ratio=0.0,
                            kind="corridor",
                        )
                    )
                y += corridor_width
            for i in range(per_row):
                wing = "west" if i < per_row / 2 else "east"
                rooms.append(
                    Room(
                        f"Room {row * per_row + i + 1}",
                        0,
                        i * room_width,
                        (i + 1) * room_width,
                        y,
                        y + room_depth,
                        infiltration_ach=0.25 if row in (0, rows - 1) else 0.15,
                        internal_gains=internal_gains_per_area * room_width * room_depth,
                        heating_setpoint=heating_setpoint,
                        cooling_setpoint=cooling_setpoint,
                        infiltration_group=f"row {row + 1} {wing}",
                    )
                )
            y += room_depth
            row += 1

    def windows(r: Room, side: str, area: float):
        if r.kind == "corridor":
            if side == "roof":
                return [("Skylight", 2.0, 0.2)]
            if side in ("east", "west"):
                return [("Door glazing", 0.8, 0.1)]
            return []
        if side in ("south", "north", "east", "west"):
            return [("Exterior window", round(window_fraction * area, 3), 0.15)]
        return []

    def doors(a: Room, b: Room):
        if (a.kind == "corridor") != (b.kind == "corridor"):
            return ("Interior door", 2.1)
        return None

    building = plan_building(
        f"clinic ({n_rooms} rooms)",
        rooms,
        [Storey(height)],
        roles,
        materials=materials,
        construction_list=constructions,
        window_types=window_types,
        window_rule=windows,
        door_rule=doors,
        location=location or Location(40.11, -88.24, 230.0),
        orientation=orientation,
    )
    # corridor end walls are glazed exterior doors
    for surface in building.surfaces.values():
        if surface.name.startswith("Corridor") and surface.name.endswith(
            ("east wall", "west wall")
        ):
            surface.construction = "Exterior door"
    building.validate()
    return building
