"""EnergyPlus' simple-geometry classes as the detailed objects they stand for.

EnergyPlus describes a rectangular surface either by its vertices (``BuildingSurface:Detailed``,
``FenestrationSurface:Detailed``, ``Shading:*:Detailed``) or by its orientation, starting corner
and size (the "Surface(s) - Simple Geometry" classes of the Input Output Reference). EnergyPlus
turns the latter into vertices when it reads them (``SurfaceGeometry.cc``: ``GetRectSurfaces``,
``GetRectDetShdSurfaceData``, ``GetRectSubSurfaces``); so does this module, and the importer then
reads them exactly as the detailed objects (one implementation of surfaces downstream):

* walls, roofs, ceilings and floors (:data:`RECTANGULAR_SURFACE_CLASSES`) ->
  ``BuildingSurface:Detailed`` records with the class's surface type and outside boundary;
* ``Window``, ``Door``, ``GlazedDoor`` and their ``:Interzone`` variants
  (:data:`RECTANGULAR_SUBSURFACE_CLASSES`) -> ``FenestrationSurface:Detailed`` records placed on
  their host;
* ``Shading:Site`` / ``Shading:Building`` -> ``Shading:Site:Detailed`` /
  ``Shading:Building:Detailed`` records.

(``Shading:Overhang`` and ``Shading:Fin`` are built from their window's vertices by
:mod:`.shading`.) The placement, EnergyPlus' ``MakeRectangularVertices``: with ``az`` the azimuth
and ``t`` the tilt, the bottom edge runs along ``(-cos az, sin az, 0)`` (left to right seen from
outside) and the surface rises along ``(-cos t sin az, -cos t cos az, sin t)`` from the lower-left
corner; the vertices are upper-left, lower-left, lower-right, upper-right (counter-clockwise seen
from outside). Under a ``Relative`` ``Coordinate System`` of ``GlobalGeometryRules`` the azimuth
of a zone's surface is turned by the building's north axis plus the zone's relative north (a
``Shading:Building``'s by the building's only, a ``Shading:Site``'s not at all); under a
``Relative`` ``Rectangular Surface Coordinate System`` (the default) the starting corner is
turned by the zone's relative north, shifted by the zone origin and turned by the building's
north axis (a ``Shading:Building``'s turned by the building's, a ``Shading:Site``'s as given).
A sub-surface's corner lies ``Starting X`` along and ``Starting Z`` up from its host's lower-left
corner (``MakeRelativeRectangularVertices``).

The detailed records keep the original object (``"_object"``), so every message names the class
and the line the user wrote.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.geometry import (
    GeometryRules,
    _vertices,
    from_world_coordinates,
    newell_normal,
    to_world_coordinates,
)
from thermocal.multizone.idf.parse import _number

#: Simple-geometry surface classes -> (EnergyPlus surface type, outside boundary condition) of
#: the equivalent ``BuildingSurface:Detailed``. ``Interzone`` stands for ``Surface`` or ``Zone``,
#: after what the ``Outside Boundary Condition Object`` names; ``Ground`` becomes
#: ``GroundFCfactorMethod`` with a C-factor wall or F-factor floor construction, as EnergyPlus.
RECTANGULAR_SURFACE_CLASSES: dict[str, tuple[str, str]] = {
    "WALL:EXTERIOR": ("Wall", "Outdoors"),
    "WALL:ADIABATIC": ("Wall", "Adiabatic"),
    "WALL:UNDERGROUND": ("Wall", "Ground"),
    "WALL:INTERZONE": ("Wall", "Interzone"),
    "ROOF": ("Roof", "Outdoors"),
    "CEILING:ADIABATIC": ("Ceiling", "Adiabatic"),
    "CEILING:INTERZONE": ("Ceiling", "Interzone"),
    "FLOOR:GROUNDCONTACT": ("Floor", "Ground"),
    "FLOOR:ADIABATIC": ("Floor", "Adiabatic"),
    "FLOOR:INTERZONE": ("Floor", "Interzone"),
}

#: Simple-geometry sub-surface classes -> surface type of the ``FenestrationSurface:Detailed``.
RECTANGULAR_SUBSURFACE_CLASSES: dict[str, str] = {
    "WINDOW": "Window",
    "DOOR": "Door",
    "GLAZEDDOOR": "GlassDoor",
    "WINDOW:INTERZONE": "Window",
    "DOOR:INTERZONE": "Door",
    "GLAZEDDOOR:INTERZONE": "GlassDoor",
}

#: Simple-geometry shading classes -> the detailed class they stand for.
RECTANGULAR_SHADING_CLASSES: dict[str, str] = {
    "SHADING:SITE": "Shading:Site:Detailed",
    "SHADING:BUILDING": "Shading:Building:Detailed",
}

#: Construction classes that turn a ``Ground`` boundary into ``GroundFCfactorMethod``, by the
#: surface type they are meant for (EnergyPlus' ``GetRectSurfaces``).
_FC_FACTOR_CONSTRUCTIONS = {
    "Wall": "CONSTRUCTION:CFACTORUNDERGROUNDWALL",
    "Floor": "CONSTRUCTION:FFACTORGROUNDFLOOR",
}

#: What a file without the simple-geometry classes can write instead (for messages).
DETAILED_EQUIVALENTS = (
    "BuildingSurface:Detailed, FenestrationSurface:Detailed or Shading:*:Detailed with the "
    "vertices (EnergyPlus writes them for a file with Output:Surfaces:List,Lines;)"
)


@dataclass(frozen=True)
class Rectangle:
    """A rectangle placed as EnergyPlus places its simple-geometry surfaces.

    Attributes
    ----------
    lower_left : numpy.ndarray, shape (3,) [m]
        The lower-left corner seen from outside.
    along : numpy.ndarray, shape (3,) [-]
        Unit vector along the bottom edge, left to right seen from outside.
    up : numpy.ndarray, shape (3,) [-]
        Unit vector up the surface, perpendicular to ``along``.
    length : float [m]
        Along ``along``.
    height : float [m]
        Along ``up`` (the ``Width`` of roofs, ceilings and floors).
    """

    lower_left: np.ndarray
    along: np.ndarray
    up: np.ndarray
    length: float
    height: float

    def vertices(self) -> np.ndarray:
        """Upper-left, lower-left, lower-right, upper-right corners [m]: counter-clockwise seen
        from outside (the outward normal is ``along x up``)."""
        ll, a, u = self.lower_left, self.along * self.length, self.up * self.height
        return np.array([ll + u, ll, ll + a, ll + a + u])

    def part(self, x: float, z: float, length: float, height: float) -> Rectangle:
        """The rectangle ``length`` x ``height`` [m] whose lower-left corner lies ``x`` [m] along
        and ``z`` [m] up from this one's lower-left corner, in its plane (a sub-surface)."""
        corner = self.lower_left + x * self.along + z * self.up
        return Rectangle(corner, self.along, self.up, length, height)


def rectangle_axes(azimuth: float, tilt: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors along the bottom edge and up a surface of the given orientation.

    Parameters
    ----------
    azimuth : float [deg]
        Direction the outside faces, clockwise from the y axis (north when not rotated).
    tilt : float [deg]
        0 = facing up, 90 = vertical, 180 = facing down.

    Returns
    -------
    along, up : numpy.ndarray, shape (3,) [-]
        ``along = (-cos az, sin az, 0)`` (left to right seen from outside) and
        ``up = (-cos t sin az, -cos t cos az, sin t)``; ``along x up`` is the outward normal.
    """
    az, t = math.radians(azimuth), math.radians(tilt)
    along = np.array([-math.cos(az), math.sin(az), 0.0])
    up = np.array([-math.cos(t) * math.sin(az), -math.cos(t) * math.cos(az), math.sin(t)])
    return along, up


def world_rectangle(
    start: Sequence[float],
    azimuth: float,
    tilt: float,
    length: float,
    height: float,
    *,
    rules: GeometryRules,
    zone_origin: Sequence[float] = (0.0, 0.0, 0.0),
    zone_north_axis: float = 0.0,
    building_north_axis: float = 0.0,
) -> Rectangle:
    """A simple-geometry surface in world coordinates, as EnergyPlus places it.

    Parameters
    ----------
    start : sequence of 3 floats [m]
        Starting X, Y, Z coordinate (the lower-left corner seen from outside).
    azimuth : float [deg]
        Azimuth Angle as written.
    tilt : float [deg]
        Tilt Angle.
    length, height : float [m]
        Length and Height (Width for roofs, ceilings and floors).
    rules : GeometryRules
        The file's; ``coordinate_system`` decides whether the azimuth is turned,
        ``rectangular_surface_coordinate_system`` whether the starting corner is.
    zone_origin : sequence of 3 floats [m]
        The zone's X/Y/Z origin (zero for ``Shading:Building`` and ``Shading:Site``).
    zone_north_axis : float [deg]
        The zone's Direction of Relative North (zero for shading).
    building_north_axis : float [deg]
        The building's North Axis (zero for ``Shading:Site``).

    Returns
    -------
    Rectangle
        In world coordinates (x east, y north, z up).
    """
    world_azimuth = azimuth + (building_north_axis + zone_north_axis if rules.relative else 0.0)
    corner = np.asarray(start, dtype=float).reshape(1, 3)
    if rules.rectangular_relative:
        corner = to_world_coordinates(
            corner,
            rules=GeometryRules(),
            zone_origin=zone_origin,
            zone_north_axis=zone_north_axis,
            building_north_axis=building_north_axis,
        )
    along, up = rectangle_axes(world_azimuth, tilt)
    return Rectangle(corner[0], along, up, float(length), float(height))


def rectangle_from_corners(corners: np.ndarray) -> Rectangle:
    """The :class:`Rectangle` of four corners ordered as :meth:`Rectangle.vertices` gives them.

    Parameters
    ----------
    corners : array-like, shape (4, 3) [m]
        Upper-left, lower-left, lower-right, upper-right.
    """
    corners = np.asarray(corners, dtype=float)
    along, up = corners[2] - corners[1], corners[0] - corners[1]
    length, height = float(np.linalg.norm(along)), float(np.linalg.norm(up))
    return Rectangle(corners[1], along / length, up / height, length, height)


def _vertex_fields(vertices: np.ndarray, rules: GeometryRules) -> list[list[str]]:
    """Counter-clockwise corners as the vertex fields of a file with these rules."""
    ordered = vertices[::-1] if rules.clockwise else vertices
    return [[repr(float(c)) for c in point] for point in ordered]


def _positive_size(rec: dict, first: str, second: str) -> tuple[float, float]:
    """Two size fields [m] of a simple-geometry object, refused unless positive."""
    a, b = _number(rec, first), _number(rec, second)
    if a <= 0.0 or b <= 0.0:
        labels = f"'{first.title()}' and '{second.title()}'"
        raise ThermocalInputError(
            f"{rec['_object'].where()}: fields {labels} must be positive (got {a:g} m and "
            f"{b:g} m)."
        )
    return a, b


def _start(rec: dict) -> tuple[float, float, float]:
    """Starting X, Y, Z coordinate [m] (blank = 0, as EnergyPlus reads a blank number)."""
    return tuple(
        _number(rec, f"starting_{axis}_coordinate", default=0.0) for axis in "xyz"
    )


class RectangularGeometryStages:
    """The simple-geometry objects as detailed records, for the stages of
    :mod:`.surfaces` and :mod:`.shading` (mixed into the builder of
    :func:`thermocal.multizone.idf.read_idf`).

    ``_rectangular_surfaces`` sets ``rectangles`` (upper-case surface name -> its
    :class:`Rectangle` in the file's coordinates), which places the sub-surfaces.
    """

    def _rectangular_surfaces(self) -> list[dict]:
        """``BuildingSurface:Detailed`` records of the simple-geometry walls, roofs, ceilings
        and floors (:data:`RECTANGULAR_SURFACE_CLASSES`)."""
        self.rectangles: dict[str, Rectangle] = {}
        out = []
        for rec in self.records(*RECTANGULAR_SURFACE_CLASSES):
            detailed = self._detailed_surface(rec)
            self.rectangles[rec["name"].upper()] = rectangle_from_corners(
                _vertices(detailed)[::-1] if self.rules.clockwise else _vertices(detailed)
            )
            out.append(detailed)
        return out

    def _detailed_surface(self, rec: dict) -> dict:
        """One simple-geometry surface as the record of its ``BuildingSurface:Detailed``."""
        obj = rec["_object"]
        surface_type, boundary = RECTANGULAR_SURFACE_CLASSES[obj.key]
        zone_entry = self.zones.get(rec["zone_name"])
        if zone_entry is None:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Zone Name' = '{rec['zone_name']}' is not a Zone of the "
                "file."
            )
        geometry = self.zone_geometry[zone_entry[0].upper()]
        frame = {
            "zone_origin": geometry["origin"],
            "zone_north_axis": geometry["north"],
            "building_north_axis": self.north_axis,
        }
        length, height = _positive_size(
            rec, "length", "height" if surface_type == "Wall" else "width"
        )
        rectangle = world_rectangle(
            _start(rec),
            _number(rec, "azimuth_angle"),
            _number(rec, "tilt_angle", default=_DEFAULT_TILT[surface_type]),
            length,
            height,
            rules=self.rules,
            **frame,
        )
        other = ""
        if boundary == "Interzone":
            boundary, other = self._interzone_boundary(rec)
        elif boundary == "Ground" and self._is_fc_factor(rec["construction_name"], surface_type):
            boundary = "GroundFCfactorMethod"
        exposed = boundary == "Outdoors"
        vertices = from_world_coordinates(rectangle.vertices(), rules=self.rules, **frame)
        return {
            "_object": obj,
            "name": rec["name"],
            "surface_type": surface_type,
            "construction_name": rec["construction_name"],
            "zone_name": rec["zone_name"],
            "space_name": rec.get("space_name", ""),
            "outside_boundary_condition": boundary,
            "outside_boundary_condition_object": other,
            "sun_exposure": "SunExposed" if exposed else "NoSun",
            "wind_exposure": "WindExposed" if exposed else "NoWind",
            "view_factor_to_ground": "",
            "number_of_vertices": "4",
            "vertices": _vertex_fields(vertices, self.rules),
        }

    def _interzone_boundary(self, rec: dict) -> tuple[str, str]:
        """``("Zone", zone)`` when the ``Outside Boundary Condition Object`` names a zone
        (EnergyPlus then makes the partner), else ``("Surface", name)``."""
        other = rec["outside_boundary_condition_object"]
        if not other:
            raise ThermocalInputError(
                f"{rec['_object'].where()}: field 'Outside Boundary Condition Object' is blank; "
                "name the surface on the other side (or the zone there)."
            )
        return ("Zone" if other in self.zones else "Surface"), other

    def _is_fc_factor(self, construction: str, surface_type: str) -> bool:
        """Whether a construction is the C-factor wall or F-factor floor of this type."""
        key = _FC_FACTOR_CONSTRUCTIONS.get(surface_type)
        return any(
            obj.name.upper() == construction.upper() for obj in self.by_key.get(key or "", [])
        )

    def _rectangular_subsurface(self, rec: dict, kind: str) -> dict:
        """A ``Window``, ``Door``, ``GlazedDoor`` (or ``:Interzone``) object as the record of
        the equivalent ``FenestrationSurface:Detailed``.

        A rectangle ``length`` x ``height`` [m] whose lower-left corner (seen from outside) is
        ``starting x`` along and ``starting z`` up [m] from the lower-left corner of its host,
        in the host's plane (EnergyPlus: x along the host's bottom edge, left to right seen from
        outside, z up the host), in the host's coordinates, vertex order per
        GlobalGeometryRules. A simple-geometry host gives its own axes (also when horizontal:
        a skylight on a ``Roof``); a detailed host's axes come from its vertices (its lowest
        edge, x horizontal), which a horizontal host does not define (refused).
        """
        obj = rec["_object"]
        base = self.surfaces.get(rec["building_surface_name"])
        if base is None:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Building Surface Name' = "
                f"'{rec['building_surface_name']}' is not a building surface of the file"
                f"{self._unread_surface_hint(rec['building_surface_name'])}."
            )
        host = self.rectangles.get(base[0].upper())
        if host is None:
            host = _detailed_host_axes(base, kind, obj, clockwise=self.rules.clockwise)
        length, height = _positive_size(rec, "length", "height")
        window = host.part(
            _number(rec, "starting_x_coordinate", default=0.0),
            _number(rec, "starting_z_coordinate", default=0.0),
            length,
            height,
        )
        return {
            **rec,
            "surface_type": kind,
            "number_of_vertices": "4",
            "vertices": _vertex_fields(window.vertices(), self.rules),
        }

    def _unread_surface_hint(self, name: str) -> str:
        """``" (it is a <class>, which thermocal does not import: ...)"`` when an object of a
        class the importer does not read has this name, else ""."""
        from thermocal.multizone.idf.fields import SCHEMA

        found = next(
            (o for o in self.objects if o.key not in SCHEMA and o.name.upper() == name.upper()),
            None,
        )
        if found is None:
            return ""
        return (
            f" (it is the {found.class_name} of line {found.line}, a class thermocal does not "
            f"import; describe it as {DETAILED_EQUIVALENTS})"
        )

    def _rectangular_shading(self, rec: dict) -> dict:
        """A ``Shading:Site`` or ``Shading:Building`` as the record of its detailed class, in
        the coordinates that class is read in (site: as given; building: turned by the
        building's north axis under relative coordinates)."""
        obj = rec["_object"]
        site = obj.key == "SHADING:SITE"
        north = 0.0 if site else self.north_axis
        length, height = _positive_size(rec, "length", "height")
        rectangle = world_rectangle(
            _start(rec),
            _number(rec, "azimuth_angle"),
            _number(rec, "tilt_angle", default=90.0),
            length,
            height,
            rules=self.rules,
            building_north_axis=north,
        )
        vertices = from_world_coordinates(
            rectangle.vertices(), rules=self.rules, building_north_axis=north
        )
        return {
            "_object": obj,
            "name": rec["name"],
            "transmittance_schedule_name": "",
            "number_of_vertices": "4",
            "vertices": _vertex_fields(vertices, self.rules),
        }


#: Default Tilt Angle [deg] of the simple-geometry surfaces, by surface type (EnergyPlus IDD).
_DEFAULT_TILT = {"Wall": 90.0, "Roof": 0.0, "Ceiling": 0.0, "Floor": 180.0}


def _detailed_host_axes(base: tuple, kind: str, obj, *, clockwise: bool) -> Rectangle:
    """The placement frame of a sub-surface on a detailed host.

    Parameters
    ----------
    base : (name, IdfObject, record)
        The host's entry of the surface registry.
    kind : str
        The sub-surface's type, for the message.
    obj : IdfObject
        The sub-surface, for the message.
    clockwise : bool
        Whether the file's vertices run clockwise seen from outside.

    Returns
    -------
    Rectangle
        Lower-left corner (lowest along ``up``, leftmost along ``along``) and axes, ``along``
        horizontal; its size is not used (zero).
    """
    points = _vertices(base[2])
    normal = newell_normal(points)
    if clockwise:
        normal = -normal
    normal = normal / np.linalg.norm(normal)
    along = np.cross([0.0, 0.0, 1.0], normal)
    if np.linalg.norm(along) < 1e-6:
        raise ThermocalInputError(
            f"{obj.where()}: base surface '{base[0]}' is horizontal; give this {kind} as a "
            "FenestrationSurface:Detailed with its vertices."
        )
    along = along / np.linalg.norm(along)
    up = np.cross(normal, along)
    corner = points[0] + np.min((points - points[0]) @ along) * along
    corner = corner + np.min((points - points[0]) @ up) * up
    return Rectangle(corner, along, up, 0.0, 0.0)
