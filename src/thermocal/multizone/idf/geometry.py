"""Surface geometry with the EnergyPlus conventions.

:func:`newell_normal`, :func:`polygon_area`, :func:`tilt_azimuth`, :func:`to_world_coordinates`,
:func:`zone_volume_from_surfaces`: vertices counter-clockwise seen from outside unless
``GlobalGeometryRules`` (:class:`GeometryRules`) says clockwise; relative coordinates are rotated
by the zone's direction of relative north and shifted by its origin, then rotated by the
building's north axis; world coordinates are used as given. ``_vertices`` reads the vertex group
of a surface record, ``_boundary`` its outside boundary condition.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.fields import _BOUNDARY_CONDITIONS
from thermocal.multizone.idf.parse import IdfObject


def newell_normal(vertices: np.ndarray) -> np.ndarray:
    """Newell's polygon normal (not normalised).

    For a planar polygon the vector is perpendicular to it with length twice the polygon area;
    it points towards the side from which the vertices run counter-clockwise. Robust for
    non-convex and slightly non-planar polygons.

    Parameters
    ----------
    vertices : array-like, shape (n, 3) [m]

    Returns
    -------
    numpy.ndarray, shape (3,) [m2]
    """
    v = np.asarray(vertices, dtype=float)
    nxt = np.concatenate((v[1:], v[:1]))  # the next vertex (np.roll, without its overhead)
    return np.array(
        [
            np.sum((v[:, 1] - nxt[:, 1]) * (v[:, 2] + nxt[:, 2])),
            np.sum((v[:, 2] - nxt[:, 2]) * (v[:, 0] + nxt[:, 0])),
            np.sum((v[:, 0] - nxt[:, 0]) * (v[:, 1] + nxt[:, 1])),
        ]
    )


def polygon_area(vertices: np.ndarray) -> float:
    """Area of a planar polygon [m2] (half the length of the Newell normal).

    Parameters
    ----------
    vertices : array-like, shape (n, 3) [m]
    """
    return 0.5 * float(np.linalg.norm(newell_normal(vertices)))


def tilt_azimuth(normal: np.ndarray) -> tuple[float, float]:
    """Tilt and azimuth of an outward normal in world coordinates (x east, y north, z up).

    Parameters
    ----------
    normal : array-like, shape (3,)
        Outward normal (any length > 0).

    Returns
    -------
    tilt : float [deg]
        0 = facing up (roof), 90 = vertical, 180 = facing down (floor).
    azimuth : float [deg]
        Direction the surface faces, clockwise from north (0 N, 90 E, 180 S, 270 W); 0 for
        horizontal surfaces, whose azimuth is undefined.
    """
    n = np.asarray(normal, dtype=float)
    length = np.linalg.norm(n)
    if length == 0.0:
        raise ValueError("zero normal: degenerate polygon")
    n = n / length
    tilt = math.degrees(math.acos(max(-1.0, min(1.0, n[2]))))
    horizontal = math.hypot(n[0], n[1])
    if horizontal < 1e-9:
        azimuth = 0.0
    else:
        azimuth = math.degrees(math.atan2(n[0], n[1])) % 360.0
        if azimuth > 360.0 - 1e-9:
            azimuth = 0.0
    # clean round-off (e.g. 89.99999999 -> 90)
    tilt = round(tilt, 9)
    azimuth = round(azimuth, 9) % 360.0
    return tilt, azimuth


@dataclass(frozen=True)
class GeometryRules:
    """``GlobalGeometryRules`` of a file.

    Attributes
    ----------
    starting_vertex_position : str
        UpperLeftCorner, LowerLeftCorner, UpperRightCorner or LowerRightCorner. Does not affect
        areas or normals.
    vertex_entry_direction : str
        ``Counterclockwise`` (seen from outside the zone) or ``Clockwise``.
    coordinate_system : str
        ``Relative`` (to the zone origin and rotated by zone and building north) or
        ``World``/``Absolute``.
    rectangular_surface_coordinate_system : str
        The field of the same name: the system of the starting corners of the simple-geometry
        classes (``Wall:Exterior``, ``Window``, ``Shading:Building``, ...), ``Relative``
        (EnergyPlus' default) or ``World``/``Absolute``.
    """

    starting_vertex_position: str = "UpperLeftCorner"
    vertex_entry_direction: str = "Counterclockwise"
    coordinate_system: str = "Relative"
    rectangular_surface_coordinate_system: str = "Relative"

    @property
    def clockwise(self) -> bool:
        return self.vertex_entry_direction.upper() == "CLOCKWISE"

    @property
    def relative(self) -> bool:
        return self.coordinate_system.upper() == "RELATIVE"

    @property
    def rectangular_relative(self) -> bool:
        return self.rectangular_surface_coordinate_system.upper() == "RELATIVE"


def _rotate_z(points: np.ndarray, angle_deg: float) -> np.ndarray:
    """Rotate points about the z axis by a north-axis angle (clockwise seen from above)."""
    if angle_deg == 0.0:
        return points
    a = math.radians(angle_deg)
    c, s = math.cos(a), math.sin(a)
    x, y = points[:, 0], points[:, 1]
    # the local +y axis points to azimuth `angle`: local (0, 1) -> world (sin a, cos a)
    return np.column_stack([x * c + y * s, -x * s + y * c, points[:, 2]])


def to_world_coordinates(
    vertices: np.ndarray,
    *,
    rules: GeometryRules,
    zone_origin: Sequence[float] = (0.0, 0.0, 0.0),
    zone_north_axis: float = 0.0,
    building_north_axis: float = 0.0,
) -> np.ndarray:
    """Vertices in world coordinates (x east, y north, z up) [m].

    Parameters
    ----------
    vertices : array-like, shape (n, 3) [m]
        As written in the file.
    rules : GeometryRules
    zone_origin : sequence of 3 floats [m]
        Zone X/Y/Z origin (used with relative coordinates only).
    zone_north_axis : float [deg]
        Zone "Direction of Relative North", clockwise.
    building_north_axis : float [deg]
        Building "North Axis", clockwise from true north.

    Notes
    -----
    With relative coordinates EnergyPlus rotates the vertices by the zone's relative north, adds
    the zone origin (building coordinates), then rotates by the building north axis. With world
    coordinates the vertices are used as given and both rotations are ignored (EnergyPlus IDD,
    BuildingSurface:Detailed note: "If world, then building and zone origins are used for some
    internal calculations, but all coordinates are given in an 'absolute' system").
    """
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    if not rules.relative:
        return v.copy()
    building = _rotate_z(v, zone_north_axis) + np.asarray(zone_origin, dtype=float)
    return _rotate_z(building, building_north_axis)


def from_world_coordinates(
    world: np.ndarray,
    *,
    rules: GeometryRules,
    zone_origin: Sequence[float] = (0.0, 0.0, 0.0),
    zone_north_axis: float = 0.0,
    building_north_axis: float = 0.0,
) -> np.ndarray:
    """Vertices as a file with these rules writes them: the inverse of
    :func:`to_world_coordinates`.

    Parameters
    ----------
    world : array-like, shape (n, 3) [m]
        Vertices in world coordinates (x east, y north, z up).
    rules : GeometryRules
    zone_origin : sequence of 3 floats [m]
        Zone X/Y/Z origin (relative coordinates only).
    zone_north_axis : float [deg]
        Zone "Direction of Relative North", clockwise.
    building_north_axis : float [deg]
        Building "North Axis", clockwise from true north.

    Returns
    -------
    numpy.ndarray, shape (n, 3) [m]
        ``to_world_coordinates(from_world_coordinates(w, ...), ...) == w`` (to round-off).
    """
    w = np.asarray(world, dtype=float).reshape(-1, 3)
    if not rules.relative:
        return w.copy()
    building = _rotate_z(w, -building_north_axis)
    return _rotate_z(building - np.asarray(zone_origin, dtype=float), -zone_north_axis)


def _check_planar(world: np.ndarray, normal: np.ndarray, obj) -> None:
    """Refuse a polygon with a vertex off its plane by more than 5 cm + 1 % of its size.

    The culprit named is the vertex whose removal leaves the others flattest; its distance is
    measured from the plane of the others.
    """
    unit = normal / np.linalg.norm(normal)
    distance = (world - world.mean(axis=0)) @ unit
    size = float(np.ptp(world, axis=0).max())
    tolerance = 0.05 + 0.01 * size
    if np.abs(distance).max() <= tolerance or len(world) < 4:
        return
    best, best_spread, best_distance = 0, np.inf, 0.0
    for i in range(len(world)):
        others = np.delete(world, i, axis=0)
        n = newell_normal(others)
        if np.linalg.norm(n) == 0:
            continue
        n = n / np.linalg.norm(n)
        centre = others.mean(axis=0)
        spread = float(np.abs((others - centre) @ n).max())
        if spread < best_spread:
            best, best_spread, best_distance = i, spread, float(abs((world[i] - centre) @ n))
    raise ThermocalInputError(
        f"{obj.where()}: vertex {best + 1} lies {best_distance:.2f} m off the plane of the "
        "other vertices; a surface must be flat (check that vertex's coordinates, or split "
        "the surface)"
    )


def outward_normal(vertices_world: np.ndarray, rules: GeometryRules) -> np.ndarray:
    """Outward (away from the zone) normal with length 2 x area, honouring the vertex order."""
    n = newell_normal(vertices_world)
    return -n if rules.clockwise else n


def outside_of_host(sub: np.ndarray, host: np.ndarray, normal: np.ndarray) -> float:
    """How far a sub-surface reaches beyond its host, in the host's plane [m].

    Parameters
    ----------
    sub, host : numpy.ndarray, shape (n, 3) and (m, 3) [m]
        World vertices of the sub-surface and of its (convex or not) host polygon.
    normal : numpy.ndarray, shape (3,)
        The host's normal (either sense; only its direction is used).

    Returns
    -------
    float
        0 when every vertex of ``sub`` lies in ``host`` (edges included), else the largest
        distance of a vertex outside ``host`` to its boundary [m].
    """
    n = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    helper = np.array([0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    u = np.cross(helper, n)
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    origin = host[0]
    poly = np.column_stack([(host - origin) @ u, (host - origin) @ v])
    points = np.column_stack([(sub - origin) @ u, (sub - origin) @ v])
    start, end = poly, np.roll(poly, -1, axis=0)
    worst = 0.0
    for p in points:
        crosses = (start[:, 1] > p[1]) != (end[:, 1] > p[1])
        with np.errstate(divide="ignore", invalid="ignore"):
            x = start[:, 0] + (p[1] - start[:, 1]) * (end[:, 0] - start[:, 0]) / (
                end[:, 1] - start[:, 1]
            )
        if np.count_nonzero(crosses & (p[0] < x)) % 2:
            continue  # inside
        edge = end - start
        share = np.clip(
            np.einsum("ij,ij->i", p - start, edge) / np.maximum((edge**2).sum(axis=1), 1e-30),
            0.0,
            1.0,
        )
        gap = np.linalg.norm(start + share[:, None] * edge - p, axis=1).min()
        worst = max(worst, float(gap))
    return worst


def outward_order(vertices_world: np.ndarray, rules: GeometryRules) -> np.ndarray:
    """A surface's vertices counter-clockwise seen from outside, whatever the file's order.

    Parameters
    ----------
    vertices_world : numpy.ndarray, shape (n, 3) [m]
        The vertices in the file's order (``GlobalGeometryRules`` ``Vertex Entry Direction``).
    rules : GeometryRules
        The file's rules.

    Returns
    -------
    numpy.ndarray, shape (n, 3) [m]
        Reversed under ``Clockwise``, else as given: the order EnergyPlus holds them in, and the
        one the shadow and solar code expects (Newell normal pointing out of the zone).
    """
    return vertices_world[::-1].copy() if rules.clockwise else vertices_world


def zone_volume_from_surfaces(
    polygons: Sequence[np.ndarray], normals: Sequence[np.ndarray]
) -> float:
    """Volume enclosed by a zone's surfaces by the divergence theorem [m3].

    Parameters
    ----------
    polygons : sequence of arrays (n_i, 3) [m]
        Vertices of every base surface of the zone (world coordinates).
    normals : sequence of arrays (3,)
        Their outward normals (any length).

    Returns
    -------
    float [m3]
        ``sum(A_i (c_i . n_i)) / 3``; meaningful only for a closed polyhedron (check the result).
    """
    total = 0.0
    for poly, normal in zip(polygons, normals, strict=True):
        poly = np.asarray(poly, dtype=float)
        n = np.asarray(normal, dtype=float)
        length = np.linalg.norm(n)
        if length == 0:
            continue
        area = polygon_area(poly)
        total += area * float(np.dot(poly[0], n / length))
    return total / 3.0


def polyhedron_is_closed(polygons: Sequence[np.ndarray], *, decimals: int = 4) -> bool:
    """True if every polygon edge is shared, in opposite direction, by other polygons (an
    edge may be shared piecewise: it is split at the other polygons' vertices on it).

    Parameters
    ----------
    polygons : sequence of arrays (n_i, 3) [m]
        With consistent orientation (all outward normals by the same vertex rule).
    decimals : int
        Vertex coordinates are rounded to this many decimals [m] before matching.
    """
    rounded = [
        [tuple(np.round(np.asarray(v, dtype=float), decimals) + 0.0) for v in poly]
        for poly in polygons
    ]
    points = np.array(sorted({v for poly in rounded for v in poly}))
    tolerance = 10.0 ** (-decimals) * 2.0
    edges: Counter = Counter()
    for p in rounded:
        for a, b in zip(p, p[1:] + p[:1], strict=True):
            # an edge split by the vertices of other polygons lying on it (a T-junction, e.g.
            # a roof edge above three floors), as EnergyPlus' enclosure check does
            starts, ends = _split_edge(np.array(a), np.array(b), points, tolerance)
            for piece in zip(starts, ends, strict=True):
                edges[piece] += 1
    for (a, b), count in edges.items():
        if edges.get((b, a), 0) != count:
            return False
    return True


def _split_edge(a: np.ndarray, b: np.ndarray, points: np.ndarray, tolerance: float):
    """The pieces (starts, ends) of the edge a -> b split at ``points`` lying on it [m]."""
    d = b - a
    length2 = float(d @ d)
    if length2 == 0.0:
        return [], []
    t = (points - a) @ d / length2
    foot = a + t[:, None] * d
    on = (np.linalg.norm(points - foot, axis=1) <= tolerance) & (t > 0.0) & (t < 1.0)
    inner = points[on][np.argsort(t[on])]
    inner = [
        tuple(p) for p in inner if min(np.linalg.norm(p - a), np.linalg.norm(p - b)) > tolerance
    ]
    chain = [tuple(a), *inner, tuple(b)]
    return chain[:-1], chain[1:]


def _vertices(rec: dict) -> np.ndarray:
    obj: IdfObject = rec["_object"]
    groups = rec["vertices"]
    points = []
    for i, group in enumerate(groups, start=1):
        if len(group) != 3:
            raise ThermocalInputError(
                f"{obj.where()}: vertex {i} has {len(group)} coordinates; give X, Y, Z."
            )
        try:
            points.append([float(c) for c in group])
        except ValueError:
            raise ThermocalInputError(
                f"{obj.where()}: vertex {i} {group} is not numeric."
            ) from None
    if len(points) < 3:
        raise ThermocalInputError(
            f"{obj.where()}: a surface needs at least 3 vertices, got {len(points)}."
        )
    declared = rec.get("number_of_vertices", "")
    if declared and declared.upper() != "AUTOCALCULATE":
        try:
            n_declared = int(float(declared))
        except ValueError:
            n_declared = len(points)
        if n_declared != len(points):
            raise ThermocalInputError(
                f"{obj.where()}: field 'Number Of Vertices' = {declared} but {len(points)} "
                "vertices are given."
            )
    return np.asarray(points)


def _boundary(raw: str, obj: IdfObject) -> str:
    key = raw.upper()
    if key == "OUTDOORS":
        return "outdoors"
    if key.startswith("GROUND"):
        return "ground"
    if key in ("SURFACE", "ZONE"):
        return key.lower()
    if key == "ADIABATIC":
        return "adiabatic"
    if key in _BOUNDARY_CONDITIONS:
        return "unsupported"
    raise ThermocalInputError(
        f"{obj.where()}: field 'Outside Boundary Condition' = '{raw}' is not an EnergyPlus "
        "boundary condition (Outdoors, Ground, Surface, Zone, Adiabatic, ...)."
    )
