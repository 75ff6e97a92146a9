"""Shadows of shading surfaces (overhangs, fins, neighbouring objects) on windows and walls.

The sunlit fraction of a receiving polygon is the share of its area from which a ray toward the
sun reaches the sky without crossing a shading polygon. It is computed by sampling: the receiver
(minus its sub-surfaces, for a wall hosting windows) is covered by a regular grid of cell centres,
each centre casts a ray toward the sun and the rays are intersected with every shading polygon
in front of the receiver. With ``n`` cells the area error of a straight shadow edge is of order
half a cell; the default 1600 cells per receiver gives a sunlit fraction within about 0.01 (a
shadow across a window) to 0.02 (a small shadow with edges along the grid on a large wall) of the
exact polygon clipping that EnergyPlus performs (tested against the analytic
overhang shadow in ``tests/multizone/test_multizone_shading.py``). Shading polygons cast shadows
from both faces (EnergyPlus mirrors detached shading surfaces) and may be partly transparent
(``transmittance`` per step); the building's own surfaces (``front_only``) cast shadows as
EnergyPlus lets them (:func:`building_surface_can_shade`).

The sky-diffuse view of a receiver is reduced in the same way as EnergyPlus'
``DifShdgRatioIsoSky`` (the dome) and ``DifShdgRatioHoriz`` (the horizon band): the sunlit
fraction is averaged over 6 x 24 sky patches (altitude bands of 15 deg, azimuth sectors of 15 deg),
weighted by ``cos(incidence) cos(altitude)``, over all of them or over the lowest band. The
circumsolar part of the sky is shaded like the beam (EnergyPlus Engineering Reference, "Shadowing
of Sky Diffuse Solar Radiation").

Coordinates are world coordinates [m]: x east, y north, z up.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numba import njit

from thermocal.multizone.idf.geometry import newell_normal

#: cells per receiver of the sampling (about)
DEFAULT_SAMPLES = 1600
_TIME_CHUNK = 512


@dataclass
class ShadingSurface:
    """A shading polygon.

    Attributes
    ----------
    name : str
    vertices : (n, 3) array [m]
        World coordinates, any orientation (both faces cast shadows).
    transmittance_schedule : str or None
        Name of a schedule (fraction) of the solar transmittance; None = opaque.
    source : str
        Where it came from (IDF object), for messages.
    front_only : bool
        A surface of the building itself (vertices ordered by its outward normal): it shades
        only where :func:`building_surface_can_shade` lets it (EnergyPlus mirrors detached
        shading surfaces, not the building's own).
    """

    name: str
    vertices: np.ndarray
    transmittance_schedule: str | None = None
    source: str = ""
    front_only: bool = False


#: Distance [m] within which a point counts as lying in a plane (shadow-casting checks).
PLANE_TOLERANCE = 1e-3


def building_surface_can_shade(caster, receiver, tolerance=PLANE_TOLERANCE) -> bool:
    """Whether a surface of the building can cast a shadow on a receiving surface (EnergyPlus).

    EnergyPlus' shadow projection skips a shadow-casting building surface that faces up (a flat
    roof: its normal within 0.8 deg of the zenith) and one with the receiving surface wholly on
    or behind its plane (its back faces the receiver); a caster wholly behind the receiver's
    plane is skipped for every shading polygon (:class:`ShadowCaster`). The building's walls
    around a courtyard or a recess therefore cast no shadow into it from their back faces.

    Parameters
    ----------
    caster : (n, 3) array [m]
        Vertices of the building surface, counter-clockwise seen from outside (outward normal).
    receiver : (m, 3) array [m]
        Vertices of the receiving surface.
    tolerance : float [m]
        Distance within which a receiver vertex counts as lying in the caster's plane.

    Returns
    -------
    bool

    References
    ----------
    .. [1] EnergyPlus Engineering Reference 25.2, "Shading Module", "Shadow Projection": the
       conditions under which a surface cannot shade another (``CHKGSS`` in SolarShading.cc).
    """
    caster = np.asarray(caster, dtype=float)
    normal = newell_normal(caster)
    norm = float(np.linalg.norm(normal))
    if norm <= 1e-12:
        return False
    return _plane_can_shade(caster[0], normal / norm, receiver, tolerance)


def _plane_can_shade(origin, normal, receiver, tolerance=PLANE_TOLERANCE) -> bool:
    """:func:`building_surface_can_shade` for a caster given by a vertex ``origin`` and its
    unit outward ``normal`` (computed once per caster by :class:`ShadowCaster`).

    Parameters
    ----------
    origin : (3,) array [m]
        The caster's first vertex.
    normal : (3,) array
        The caster's unit outward normal (Newell's, normalised).
    receiver : (m, 3) array [m]
        Vertices of the receiving surface.
    tolerance : float [m]

    Returns
    -------
    bool
    """
    if normal[2] > 0.9999:
        return False  # faces up
    height = (np.asarray(receiver, dtype=float) - origin) @ normal
    return bool(np.max(height) > tolerance)


@dataclass
class _Receiver:
    name: str
    origin: np.ndarray  # a vertex of the receiver
    normal: np.ndarray  # unit outward normal
    u_axis: np.ndarray
    v_axis: np.ndarray
    points: np.ndarray  # (p, 2) sample points in (u, v)
    weights: np.ndarray  # (p,) covered share of each point's cell
    shaders: list[tuple[int, np.ndarray]] = field(default_factory=list)  # (index, clipped verts)


def _clip_in_front(vertices: np.ndarray, origin: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """The part of a polygon in front of a plane (Sutherland-Hodgman against one plane)."""
    distance = (vertices - origin) @ normal
    out = []
    n = len(vertices)
    for i in range(n):
        a, b = vertices[i], vertices[(i + 1) % n]
        da, db = distance[i], distance[(i + 1) % n]
        if da > 0:
            out.append(a)
        if (da > 0) != (db > 0) and da != db:
            out.append(a + (b - a) * (da / (da - db)))
    return np.array(out) if len(out) >= 3 else np.zeros((0, 3))


def _cross(a, b) -> np.ndarray:
    """``numpy.cross`` of two 3-vectors, the same products without its per-call overhead."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def _plane_axes(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = normal / np.linalg.norm(normal)
    helper = (0.0, 0.0, 1.0) if abs(n[2]) < 0.9 else (1.0, 0.0, 0.0)
    u = _cross(helper, n)
    u /= np.linalg.norm(u)
    return u, _cross(n, u)


def _inside(polygon_2d: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Even-odd point-in-polygon test, vectorised over points (any array shape)."""
    inside = np.zeros(np.shape(x), dtype=bool)
    px, py = polygon_2d[:, 0], polygon_2d[:, 1]
    n = len(px)
    for i in range(n):
        x1, y1, x2, y2 = px[i], py[i], px[(i + 1) % n], py[(i + 1) % n]
        if y1 == y2:
            continue
        crosses = (y1 > y) != (y2 > y)
        x_at = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
        inside ^= crosses & (x < x_at)
    return inside


def sample_points(
    vertices: np.ndarray,
    normal: np.ndarray,
    *,
    holes=(),
    samples: int = DEFAULT_SAMPLES,
) -> np.ndarray:
    """Cell centres of a regular grid covering a planar polygon minus its holes.

    Parameters
    ----------
    vertices : (n, 3) array [m]
    normal : (3,) array
        Outward normal (any length).
    holes : sequence of (m, 3) arrays
        Sub-surfaces (windows, doors) excluded from the receiver.
    samples : int
        Number of cells over the polygon's area (about).

    Returns
    -------
    (p, 3) array [m]
        The centres of the cells that lie mostly on the polygon.
    """
    points, weights = sample_cells(vertices, normal, holes=holes, samples=samples)
    return points[weights > 0.5]


def sample_cells(
    vertices: np.ndarray,
    normal: np.ndarray,
    *,
    holes=(),
    samples: int = DEFAULT_SAMPLES,
    refine: int = 4,
) -> tuple[np.ndarray, np.ndarray]:
    """Cells of a regular grid over a planar polygon minus its holes, with their covered share.

    Each cell's share of polygon (minus holes) is counted on ``refine x refine`` sub-cells, so
    that a sunlit fraction averaged with these weights has the receiver's area right although
    the edges of its holes (a wall's windows) do not follow the grid; the shadow test is made
    at one point of the cell.

    Parameters
    ----------
    vertices : (n, 3) array [m]
    normal : (3,) array
        Outward normal (any length).
    holes : sequence of (m, 3) arrays
        Sub-surfaces (windows, doors) excluded from the receiver.
    samples : int
        Number of cells over the polygon's area (about).
    refine : int
        Sub-cells per cell side for the covered share.

    Returns
    -------
    points : (p, 3) array [m]
        One point in each cell that touches the polygon (jittered about its centre by a fixed
        pseudo-random sequence).
    weights : (p,) array [-]
        Their covered share (0, 1].
    """
    v = np.asarray(vertices, dtype=float)
    n = normal / np.linalg.norm(normal)
    u_axis, v_axis = _plane_axes(n)
    origin = v[0]
    local = np.stack([(v - origin) @ u_axis, (v - origin) @ v_axis], axis=1)
    area = 0.5 * float(np.linalg.norm(newell_normal(v)))
    cell = np.sqrt(max(area, 1e-12) / samples)
    lo, hi = local.min(axis=0), local.max(axis=0)
    nu = max(1, int(np.ceil((hi[0] - lo[0]) / cell)))
    nv = max(1, int(np.ceil((hi[1] - lo[1]) / cell)))
    r = max(1, int(refine))
    fu = lo[0] + (np.arange(nu * r) + 0.5) * (hi[0] - lo[0]) / (nu * r)
    fv = lo[1] + (np.arange(nv * r) + 0.5) * (hi[1] - lo[1]) / (nv * r)
    uu, vv = np.meshgrid(fu, fv, indexing="ij")
    keep = _inside(local, uu, vv)
    for hole in holes:
        h = np.asarray(hole, dtype=float)
        h_local = np.stack([(h - origin) @ u_axis, (h - origin) @ v_axis], axis=1)
        keep &= ~_inside(h_local, uu, vv)
    weights = keep.reshape(nu, r, nv, r).mean(axis=(1, 3)).ravel()
    gu = lo[0] + (np.arange(nu) + 0.5) * (hi[0] - lo[0]) / nu
    gv = lo[1] + (np.arange(nv) + 0.5) * (hi[1] - lo[1]) / nv
    cu, cv = np.meshgrid(gu, gv, indexing="ij")
    # the ray of each cell leaves from a point jittered within the cell (a fixed sequence), so
    # that shadow edges parallel to the grid (an overhang over a window) move the sunlit
    # fraction smoothly rather than a row at a time
    jitter = np.random.default_rng(20261125).uniform(-0.5, 0.5, size=(2, nu, nv))
    cu = cu + jitter[0] * (hi[0] - lo[0]) / nu
    cv = cv + jitter[1] * (hi[1] - lo[1]) / nv
    cu, cv = cu.ravel(), cv.ravel()
    touched = weights > 0
    cu, cv, weights = cu[touched], cv[touched], weights[touched]
    points = origin[None, :] + cu[:, None] * u_axis[None, :] + cv[:, None] * v_axis[None, :]
    return points, weights


class ShadowCaster:
    """Sunlit fractions of receiving polygons under a set of shading polygons.

    Parameters
    ----------
    shaders : sequence of ShadingSurface
    receivers : mapping
        ``{name: (vertices (n, 3), holes)}``: every receiver whose shadows are wanted
        (sun-exposed outdoor surfaces, windows); ``holes`` are the receiver's sub-surfaces.
    samples : int
        Sampling cells per receiver.

    Attributes
    ----------
    shaded : list of str
        Receivers that at least one shading polygon can shade (a vertex in front of the
        receiver's plane, and for the building's own surfaces
        :func:`building_surface_can_shade`); the others are always sunlit.
    """

    def __init__(self, shaders, receivers, *, samples: int = DEFAULT_SAMPLES) -> None:
        self.shaders = list(shaders)
        self._planes: list = []
        for shader in self.shaders:
            verts = np.asarray(shader.vertices, dtype=float)
            normal = newell_normal(verts)
            norm = float(np.linalg.norm(normal))
            if norm <= 1e-12:
                self._planes.append(None)
                continue
            normal = normal / norm
            u_axis, v_axis = _plane_axes(normal)
            local = np.stack([(verts - verts[0]) @ u_axis, (verts - verts[0]) @ v_axis], axis=1)
            self._planes.append((verts[0], normal, u_axis, v_axis, local, verts))
        self._receivers: dict[str, _Receiver] = {}
        # every caster's plane at once for building_surface_can_shade's test (a vertex, the unit
        # normal; "front only" casters that face up or have the receiver behind them are out)
        planar = [k for k, plane in enumerate(self._planes) if plane is not None]
        plane_origin = np.array([self._planes[k][0] for k in planar]).reshape(-1, 3)
        plane_normal = np.array([self._planes[k][1] for k in planar]).reshape(-1, 3)
        front_only = np.array([self.shaders[k].front_only for k in planar], dtype=bool)
        faces_up = plane_normal[:, 2] > 0.9999
        for name, (vertices, holes) in receivers.items():
            verts = np.asarray(vertices, dtype=float)
            normal = newell_normal(verts)
            if np.linalg.norm(normal) <= 1e-12:
                continue
            normal = normal / np.linalg.norm(normal)
            # lift the plane a little so that shaders touching the face do not shade it
            origin = verts[0] + 1e-6 * normal
            height = np.einsum(
                "smk,sk->sm", verts[None, :, :] - plane_origin[:, None, :], plane_normal
            )
            can_shade = ~faces_up & (height.max(axis=1, initial=-np.inf) > PLANE_TOLERANCE)
            candidates = []
            for j, k in enumerate(planar):
                if front_only[j] and not can_shade[j]:
                    continue
                clipped = _clip_in_front(self._planes[k][5], origin, normal)
                if len(clipped):
                    candidates.append((k, clipped))
            if not candidates:
                continue
            points, weights = sample_cells(verts, normal, holes=holes, samples=samples)
            if len(points) == 0:
                continue
            u_axis, v_axis = _plane_axes(normal)
            local = np.stack([(points - origin) @ u_axis, (points - origin) @ v_axis], axis=1)
            self._receivers[name] = _Receiver(
                name, origin, normal, u_axis, v_axis, local, weights, candidates
            )
        self.shaded = list(self._receivers)

    def sunlit_fraction(self, name: str, sun: np.ndarray, transmittance=None) -> np.ndarray:
        """Sunlit fraction of receiver ``name`` for each sun direction.

        Parameters
        ----------
        name : str
        sun : (t, 3) array
            Unit vectors toward the sun.
        transmittance : (t, n_shaders) array, optional
            Solar transmittance of each shading polygon per step (default 0: opaque).

        Returns
        -------
        (t,) array [-]
            1 where the sun is behind the receiver or below the horizon (no beam to shade).
        """
        rec = self._receivers.get(name)
        sun = np.atleast_2d(np.asarray(sun, dtype=float))
        out = np.ones(len(sun))
        if rec is None:
            return out
        front = (sun @ rec.normal > 1e-9) & (sun[:, 2] > -1e-9)
        steps = np.flatnonzero(front)
        if not len(steps):
            return out
        n_vertices = np.array([len(verts) for _, verts in rec.shaders], dtype=np.int64)
        shader_index = np.array([k for k, _ in rec.shaders], dtype=np.int64)
        # the shaders' vertices relative to the receiver, padded to the longest polygon (the
        # padding is never read: each polygon has its own vertex count)
        rel = np.zeros((len(rec.shaders), int(n_vertices.max()), 3))
        for j, (_, verts) in enumerate(rec.shaders):
            rel[j, : len(verts)] = verts - rec.origin
        height = rel @ rec.normal  # (n_shaders, width) > 0 after clipping
        px = np.ascontiguousarray(rec.points[:, 0])
        py = np.ascontiguousarray(rec.points[:, 1])
        for start in range(0, len(steps), _TIME_CHUNK):
            chunk = steps[start : start + _TIME_CHUNK]
            s = sun[chunk]  # (c, 3)
            cos_n = s @ rec.normal  # (c,) > 0
            # shadow of each polygon on the receiver's plane, along the sun's rays
            shadow = (
                rel[None, :, :, :]
                - (height[None, :, :, None] / cos_n[:, None, None, None]) * s[:, None, None, :]
            )
            su = np.ascontiguousarray(shadow @ rec.u_axis)
            sv = np.ascontiguousarray(shadow @ rec.v_axis)
            if transmittance is None:
                tau = np.zeros((len(chunk), len(rec.shaders)))
            else:
                tau = np.ascontiguousarray(transmittance[chunk][:, shader_index], dtype=float)
            out[chunk] = _lit_share(px, py, rec.weights, su, sv, n_vertices, tau)
        return out

    def sky_diffuse_ratio(self, name: str, transmittance=None) -> float:
        """Unshaded share of the isotropic sky diffuse on a receiver (EnergyPlus' 6 x 24 patches).

        ``transmittance``: (n_shaders,) constant transmittances (default opaque). Returns 1 for
        receivers no shading polygon can shade.
        """
        return self.sky_diffuse_ratios(name, transmittance)[0]

    def sky_diffuse_ratios(self, name: str, transmittance=None) -> tuple[float, float]:
        """Unshaded shares of the sky dome and of the horizon band on a receiver [-].

        EnergyPlus' ``SkyDifSolarShading``: the sunlit fraction toward 6 x 24 sky patches
        (altitudes 7.5 to 82.5 deg, azimuths every 15 deg), weighted by
        ``cos(altitude) cos(incidence)`` over the patches in front of the receiver:
        ``DifShdgRatioIsoSky`` over all of them, ``DifShdgRatioHoriz`` over the lowest band
        (7.5 deg). ``transmittance``: (n_shaders,) constant transmittances (default opaque).
        (1, 1) for receivers no shading polygon can shade.

        References
        ----------
        .. [1] EnergyPlus Engineering Reference 25.2, "Shadowing of Sky Diffuse Solar
           Radiation" (sky radiance model).
        """
        return self.beam_and_sky(name, np.zeros((0, 3)), None, transmittance)[1:]

    def beam_and_sky(
        self, name: str, sun: np.ndarray, transmittance=None, sky_transmittance=None
    ) -> tuple[np.ndarray, float, float]:
        """:meth:`sunlit_fraction` toward ``sun`` and :meth:`sky_diffuse_ratios` in one pass
        over the receiver's shadows (the sky patches appended to the sun's directions).

        Parameters
        ----------
        name : str
        sun : (t, 3) array
            Unit vectors toward the sun.
        transmittance : (t, n_shaders) array, optional
            Per direction toward the sun (default opaque).
        sky_transmittance : (n_shaders,) array, optional
            Constant transmittances for the sky patches (default opaque).

        Returns
        -------
        beam : (t,) array [-]
        dome, horizon : float [-]
        """
        sun = np.asarray(sun, dtype=float).reshape(-1, 3)
        if name not in self._receivers:
            return np.ones(len(sun)), 1.0, 1.0
        directions, altitude, band = _SKY_PATCHES
        cos_incidence = directions @ self._receivers[name].normal
        weight = np.where(cos_incidence > 0, cos_incidence * np.cos(altitude), 0.0)
        tau = None
        if transmittance is not None or sky_transmittance is not None:
            tau = np.zeros((len(sun) + len(directions), len(self.shaders)))
            if transmittance is not None:
                tau[: len(sun)] = transmittance
            if sky_transmittance is not None:
                tau[len(sun) :] = np.asarray(sky_transmittance, float)[None, :]
        lit = self.sunlit_fraction(name, np.concatenate([sun, directions]), tau)
        beam, lit = lit[: len(sun)], lit[len(sun) :]
        if weight.sum() <= 0:
            return beam, 1.0, 1.0
        dome = float((weight * lit).sum() / weight.sum())
        low = band == 0
        if weight[low].sum() <= 0:
            return beam, dome, 1.0
        return beam, dome, float((weight[low] * lit[low]).sum() / weight[low].sum())


def _sky_patches() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """EnergyPlus' 6 x 24 sky patches: unit vectors (144, 3), altitudes [rad] and bands."""
    altitudes = np.radians(np.arange(6) * 15.0 + 7.5)
    azimuths = np.radians(np.arange(24) * 15.0)
    alt, az = np.meshgrid(altitudes, azimuths, indexing="ij")
    band = np.broadcast_to(np.arange(6)[:, None], alt.shape).ravel()
    alt, az = alt.ravel(), az.ravel()
    directions = np.stack([np.cos(alt) * np.sin(az), np.cos(alt) * np.cos(az), np.sin(alt)], axis=1)
    return directions, alt, band


_SKY_PATCHES = _sky_patches()


@njit(cache=True)
def _lit_share(px, py, weights, su, sv, n_vertices, tau):  # pragma: no cover - compiled
    """Mean over the points ``(px, py)`` (weighted) of the light left after the shadow polygons
    ``(su, sv)[t, k, :n_vertices[k]]`` (even-odd rule; a point in shadow k keeps ``tau[t, k]``
    of it), per step ``t``; each polygon's bounding box first, against the points' box and
    then point by point; a step no polygon shades is 1 (the weighted mean of ones)."""
    n_steps, n_shaders, _ = su.shape
    n_points = len(px)
    out = np.ones(n_steps)
    lit = np.empty(n_points)
    if n_points == 0:
        return out
    points_u0, points_u1 = px.min(), px.max()
    points_v0, points_v1 = py.min(), py.max()
    norm = 0.0
    for p in range(n_points):
        norm += weights[p]
    for t in range(n_steps):
        lit[:] = 1.0
        shaded = False
        for k in range(n_shaders):
            m = n_vertices[k]
            u0 = su[t, k, 0]
            u1 = u0
            v0 = sv[t, k, 0]
            v1 = v0
            for i in range(1, m):
                u0 = min(u0, su[t, k, i])
                u1 = max(u1, su[t, k, i])
                v0 = min(v0, sv[t, k, i])
                v1 = max(v1, sv[t, k, i])
            if u1 < points_u0 or u0 > points_u1 or v1 < points_v0 or v0 > points_v1:
                continue
            keep = tau[t, k]
            for p in range(n_points):
                x = px[p]
                y = py[p]
                if x < u0 or x > u1 or y < v0 or y > v1:
                    continue
                inside = False
                for i in range(m):
                    j = i + 1 if i + 1 < m else 0
                    y1 = sv[t, k, i]
                    y2 = sv[t, k, j]
                    if (y1 > y) != (y2 > y):
                        x1 = su[t, k, i]
                        x_at = x1 + (y - y1) * (su[t, k, j] - x1) / (y2 - y1)
                        if x < x_at:
                            inside = not inside
                if inside:
                    lit[p] *= keep
                    shaded = True
        if not shaded:
            continue
        total = 0.0
        for p in range(n_points):
            total += weights[p] * lit[p]
        out[t] = total / norm if norm > 0.0 else 1.0
    return out


def interior_beam_fractions(
    window: np.ndarray, faces: dict, sun: np.ndarray, *, samples: int = 400
) -> np.ndarray:
    """Where the beam entering through a window lands: the share on each face of its zone.

    Rays from cells of the window (weighted by their covered share) travel along the sun's
    direction into the zone; each lands on the nearest face it crosses (EnergyPlus'
    ``FullInteriorAndExterior`` projects the sunlit window onto the zone's back surfaces, for
    convex zones the same). Rays that find no face (an open zone) are not counted. Faces in the
    window's own plane (its host wall, the other windows of that wall: every vertex of the
    window within :data:`PLANE_TOLERANCE` of the face's plane) receive none: the rays leave that
    plane, and coordinates written to a few digits put part of the window a few micrometres
    outside its host, where the rays would otherwise land on the host at once (EnergyPlus
    projects onto back surfaces only).

    Parameters
    ----------
    window : (n, 3) array [m]
        The window's vertices, counter-clockwise seen from outside (outward normal).
    faces : dict of str -> (m, 3) array [m]
        The zone's faces (any vertex order).
    sun : (t, 3) array
        Unit vectors toward the sun.
    samples : int
        Cells on the window (about).

    Returns
    -------
    (t, len(faces)) array [-]
        Shares of the transmitted beam per face (rows sum to 1, or 0 with the sun behind the
        window or below the horizon).
    """
    window = np.asarray(window, dtype=float)
    outward = newell_normal(window)
    outward = outward / np.linalg.norm(outward)
    points, weights = sample_cells(window, outward, samples=samples)
    sun = np.atleast_2d(np.asarray(sun, dtype=float))
    names = list(faces)
    out = np.zeros((len(sun), len(names)))
    width = max(len(faces[name]) for name in names) if names else 0
    origins = np.zeros((len(names), 3))
    normals = np.zeros((len(names), 3))
    u_axes = np.zeros((len(names), 3))
    v_axes = np.zeros((len(names), 3))
    polygons = np.zeros((len(names), max(width, 1), 2))
    n_vertices = np.zeros(len(names), dtype=np.int64)
    for k, name in enumerate(names):
        verts = np.asarray(faces[name], dtype=float)
        normal = newell_normal(verts)
        normal = normal / max(np.linalg.norm(normal), 1e-12)
        if np.max(np.abs((window - verts[0]) @ normal)) <= PLANE_TOLERANCE:
            continue  # in the window's plane: left with a zero normal, which _land skips
        u_axis, v_axis = _plane_axes(normal)
        origins[k], normals[k], u_axes[k], v_axes[k] = verts[0], normal, u_axis, v_axis
        polygons[k, : len(verts)] = np.stack(
            [(verts - verts[0]) @ u_axis, (verts - verts[0]) @ v_axis], axis=1
        )
        n_vertices[k] = len(verts)
    lit = np.flatnonzero((sun @ outward > 1e-6) & (sun[:, 2] > 0.0))
    if len(lit) and len(names):
        out[lit] = _land(
            points, weights, -sun[lit], origins, normals, u_axes, v_axes, polygons, n_vertices
        )
    return out


@njit(cache=True)
def _land(
    points, weights, directions, origins, normals, u_axes, v_axes, polygons, n_vertices
):  # pragma: no cover - compiled
    """Per direction, the weighted share of the rays from ``points`` landing first on each
    face (planes ``origins``/``normals``, polygons in their ``u``/``v`` axes); a face at the
    same distance as an earlier one does not take the ray.

    What does not depend on the direction is computed once: each point's distance numerator to
    each face's plane and each polygon's bounding box (a landing point outside it cannot be
    inside the polygon, so the even-odd test is skipped; the result is the same)."""
    n_dir = directions.shape[0]
    n_faces = origins.shape[0]
    n_points = points.shape[0]
    out = np.zeros((n_dir, n_faces))
    numerator = np.empty((n_points, n_faces))
    for p in range(n_points):
        x0, x1, x2 = points[p, 0], points[p, 1], points[p, 2]
        for k in range(n_faces):
            numerator[p, k] = (
                (origins[k, 0] - x0) * normals[k, 0]
                + (origins[k, 1] - x1) * normals[k, 1]
                + (origins[k, 2] - x2) * normals[k, 2]
            )
    box = np.empty((n_faces, 4))  # u min, u max, v min, v max
    for k in range(n_faces):
        box[k, 0] = box[k, 1] = polygons[k, 0, 0]
        box[k, 2] = box[k, 3] = polygons[k, 0, 1]
        for i in range(1, n_vertices[k]):
            box[k, 0] = min(box[k, 0], polygons[k, i, 0])
            box[k, 1] = max(box[k, 1], polygons[k, i, 0])
            box[k, 2] = min(box[k, 2], polygons[k, i, 1])
            box[k, 3] = max(box[k, 3], polygons[k, i, 1])
    den = np.empty(n_faces)
    for t in range(n_dir):
        d0, d1, d2 = directions[t, 0], directions[t, 1], directions[t, 2]
        for k in range(n_faces):
            den[k] = d0 * normals[k, 0] + d1 * normals[k, 1] + d2 * normals[k, 2]
        total = 0.0
        for p in range(n_points):
            x0, x1, x2 = points[p, 0], points[p, 1], points[p, 2]
            best = np.inf
            hit = -1
            for k in range(n_faces):
                if abs(den[k]) < 1e-9:
                    continue
                dist = numerator[p, k] / den[k]
                if dist <= 1e-6 or dist >= best - 1e-6:
                    continue
                w0 = x0 + dist * d0 - origins[k, 0]
                w1 = x1 + dist * d1 - origins[k, 1]
                w2 = x2 + dist * d2 - origins[k, 2]
                x = w0 * u_axes[k, 0] + w1 * u_axes[k, 1] + w2 * u_axes[k, 2]
                y = w0 * v_axes[k, 0] + w1 * v_axes[k, 1] + w2 * v_axes[k, 2]
                if x < box[k, 0] or x > box[k, 1] or y < box[k, 2] or y > box[k, 3]:
                    continue
                m = n_vertices[k]
                inside = False
                for i in range(m):
                    j = i + 1 if i + 1 < m else 0
                    y1 = polygons[k, i, 1]
                    y2 = polygons[k, j, 1]
                    if (y1 > y) != (y2 > y):
                        x_at = polygons[k, i, 0] + (y - y1) * (
                            polygons[k, j, 0] - polygons[k, i, 0]
                        ) / (y2 - y1)
                        if x < x_at:
                            inside = not inside
                if inside:
                    best = dist
                    hit = k
            if hit >= 0:
                out[t, hit] += weights[p]
                total += weights[p]
        if total > 0.0:
            for k in range(n_faces):
                out[t, k] /= total
    return out


def sun_vectors(zenith_deg, azimuth_deg) -> np.ndarray:
    """Unit vectors toward the sun (x east, y north, z up) from zenith and azimuth [deg]."""
    zen = np.radians(np.asarray(zenith_deg, dtype=float))
    azi = np.radians(np.asarray(azimuth_deg, dtype=float))
    return np.stack([np.sin(zen) * np.sin(azi), np.sin(zen) * np.cos(azi), np.cos(zen)], axis=1)
