"""Shading objects of an IDF file as :class:`thermocal.multizone.shading.ShadingSurface`.

Stage of the import (:class:`ShadingStages`, mixed into the builder of
:func:`thermocal.multizone.idf.read_idf`): ``Shading:Zone:Detailed``,
``Shading:Building:Detailed``, ``Shading:Site:Detailed`` polygons (and the rectangles of
``Shading:Building`` and ``Shading:Site``, :mod:`.simple_geometry`), the overhangs and fins of
windows (``Shading:Overhang``, ``Shading:Overhang:Projection``, ``Shading:Fin``,
``Shading:Fin:Projection``), and the solar and convection settings read with them
(``ShadowCalculation``, ``SurfaceConvectionAlgorithm:Inside`` / ``:Outside``).
"""

from __future__ import annotations

import math

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.geometry import _vertices, newell_normal, to_world_coordinates
from thermocal.multizone.idf.parse import _number
from thermocal.multizone.idf.report import EP_CHECK


class ShadingStages:
    """Stage ``_shading`` of the builder: fills ``info.shading_surfaces``,
    ``info.subsurfaces_of``, ``info.convection`` and ``info.shadow_update_days``."""

    def _shading(self) -> None:
        """Stage: shading surfaces (detailed polygons, overhangs and fins of windows)."""
        from thermocal.multizone.shading import ShadingSurface

        for name, _obj, rec in self.fenestration.values():
            host = self.surface_data.get(rec["building_surface_name"].upper())
            if host is not None:
                self.info.subsurfaces_of.setdefault(host["name"], []).append(name)
        found: list[ShadingSurface] = []

        def schedule(rec):
            sched = rec.get("transmittance_schedule_name", "")
            if not sched:
                return None
            if sched not in self.schedules:
                raise ThermocalInputError(
                    f"{rec['_object'].where()}: field 'Transmittance Schedule Name' = "
                    f"'{sched}' is not a schedule of the file."
                )
            return sched

        def polygon(rec, **frame):
            obj = rec["_object"]
            world = to_world_coordinates(_vertices(rec), rules=self.rules, **frame)
            if 0.5 * float(np.linalg.norm(newell_normal(world))) <= 1e-9:
                raise ThermocalInputError(
                    f"{obj.where()}: the vertices enclose zero area (degenerate polygon)."
                )
            return ShadingSurface(rec["name"], world, schedule(rec), obj.where())

        for rec in self.records("SHADING:ZONE:DETAILED"):
            base = self.surface_data.get(rec["base_surface_name"].upper())
            if base is None:
                raise ThermocalInputError(
                    f"{rec['_object'].where()}: field 'Base Surface Name' = "
                    f"'{rec['base_surface_name']}' is not a building surface of the file."
                )
            geometry = self.zone_geometry[base["zone"].upper()]
            found.append(
                polygon(
                    rec,
                    zone_origin=geometry["origin"],
                    zone_north_axis=geometry["north"],
                    building_north_axis=self.north_axis,
                )
            )
        for rec in self.records("SHADING:BUILDING:DETAILED"):
            found.append(polygon(rec, building_north_axis=self.north_axis))
        for rec in self.records("SHADING:BUILDING"):
            found.append(
                polygon(self._rectangular_shading(rec), building_north_axis=self.north_axis)
            )
        for rec in self.records("SHADING:SITE:DETAILED"):
            found.append(polygon(rec))  # site coordinates: not rotated with the building
        for rec in self.records("SHADING:SITE"):
            found.append(polygon(self._rectangular_shading(rec)))
        for key in ("SHADING:OVERHANG", "SHADING:OVERHANG:PROJECTION"):
            for rec in self.records(key):
                found.append(self._overhang(rec, projection=key.endswith("PROJECTION")))
        for key in ("SHADING:FIN", "SHADING:FIN:PROJECTION"):
            for rec in self.records(key):
                found.extend(self._fins(rec, projection=key.endswith("PROJECTION")))
        self.info.shading_surfaces = self._solar_distribution(found)
        if self.info.solar_distribution.replace(" ", "").upper() != "MINIMALSHADOWING":
            self.info.shading_surfaces = self.info.shading_surfaces + self._own_shadows()

        for side in ("inside", "outside"):
            rec = self.single(f"SURFACECONVECTIONALGORITHM:{side.upper()}")
            if rec is not None and rec["algorithm"]:
                self.info.convection[side] = rec["algorithm"]
        rec = self.single("SHADOWCALCULATION")
        if rec is not None:
            # read by content, not by name: the layout changed in EnergyPlus 9.x (Calculation
            # Method, Frequency before; Calculation Method, Update Frequency Method, Frequency
            # since)
            values = [f.upper() for f in rec["_object"].fields]
            numbers = [v for v in values[:4] if v.replace(".", "", 1).isdigit()]
            if any(v in ("TIMESTEP", "TIMESTEPFREQUENCY") for v in values[:3]):
                self.info.shadow_update_days = 0
            elif numbers:
                self.info.shadow_update_days = max(1, int(float(numbers[0])))
            self.info.notes.extend(_shadow_settings_not_applied(rec["_object"]))

    def _own_shadows(self) -> list:
        """The building's own exterior surfaces as shading polygons (EnergyPlus' FullExterior:
        the exterior surfaces of all zones cast shadows, e.g. one wing on another, or a row of
        flats on the facade across a breezeway). A surface only shades what lies in front of
        it, so a convex building casts no shadow on itself (and costs nothing)."""
        from thermocal.multizone.shading import ShadingSurface

        own = [
            ShadingSurface(
                f"{data['name']} (building surface)",
                _outward(data["world"], data["normal"]),
                None,
                data["obj"].where(),
                front_only=True,
            )
            for data in self.surface_data.values()
            if data["boundary"] == "outdoors"
        ]
        if not own:
            return []
        mutual = _casts_on_others(own)
        if mutual:
            merged = _merge_coplanar(mutual)
            self.info.notes.append(
                f"{len(mutual)} exterior surface(s) of the building cast shadows on others "
                f"(EnergyPlus' FullExterior): simulated as {len(merged)} shading polygon(s) "
                "(coplanar surfaces tiling a rectangle merged into it)"
            )
            mutual = merged
        return mutual

    def _solar_distribution(self, found: list) -> list:
        """The ``Building`` object's Solar Distribution: ``MinimalShadowing`` drops the shading
        surfaces (EnergyPlus casts no shadow from them); the beam entering a zone lands on its
        floor under ``FullExterior`` and ``MinimalShadowing`` and where the sun puts it under
        ``FullInteriorAndExterior`` (the simulation casts the rays; noted); the reflections of
        the ``...WithReflections`` options are not modelled (noted). Sets
        ``info.solar_distribution``."""
        rec = self.single("BUILDING")
        text = (rec["solar_distribution"] if rec is not None else "") or "FullExterior"
        key = text.replace(" ", "").upper()
        options = {
            "MINIMALSHADOWING",
            "FULLEXTERIOR",
            "FULLINTERIORANDEXTERIOR",
            "FULLEXTERIORWITHREFLECTIONS",
            "FULLINTERIORANDEXTERIORWITHREFLECTIONS",
        }
        if key not in options:
            raise ThermocalInputError(
                f"{rec['_object'].where()}: field 'Solar Distribution' = '{text}' is not one of "
                "MinimalShadowing, FullExterior, FullInteriorAndExterior, "
                "FullExteriorWithReflections, FullInteriorAndExteriorWithReflections."
            )
        self.info.solar_distribution = text
        notes = self.info.notes
        if key == "MINIMALSHADOWING" and found:
            notes.append(
                f"Solar Distribution MinimalShadowing: the {len(found)} shading surface(s) cast no "
                "shadow, as in EnergyPlus"
            )
            found = []
        if key.startswith("FULLINTERIORANDEXTERIOR"):
            notes.append(
                f"Solar Distribution {text}: the direct sun entering a zone lands on the faces "
                "it reaches (rays from each window along the sun, windows included, updated as "
                "the exterior shadows), as EnergyPlus"
            )
        if key.endswith("WITHREFLECTIONS"):
            notes.append(
                f"Solar Distribution {text}: the solar reflected by exterior surfaces onto the "
                "building is not modelled"
            )
        return found

    def _window_frame(self, rec):
        """Corner, right and up axes, outward normal, width and height of a window or door.

        ``info.surface_vertices`` holds the window counter-clockwise seen from outside whatever
        the file's vertex order (:func:`.geometry.outward_order`): the normal points out. One
        exception follows EnergyPlus 25.2 (:func:`_overhang_side`): under ``ClockWise`` it
        builds the overhangs and fins of a ``FenestrationSurface:Detailed`` on the zone's side
        (noted); those of a simple ``Window``/``Door``/``GlazedDoor``, whose vertices it makes
        itself, outside.
        """
        obj = rec["_object"]
        target = rec["window_or_door_name"]
        entry = self.fenestration.get(target)
        if entry is None:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Window or Door Name' = '{target}' is not a window or "
                "door (FenestrationSurface:Detailed, Window, Door, GlazedDoor) of the file."
            )
        world = self.info.surface_vertices[entry[0]]
        side = _overhang_side(entry[1].key, clockwise=self.rules.clockwise)
        if side < 0:
            self.info.notes.append(
                f"{EP_CHECK}{obj.where()}: built on the inside of '{entry[0]}' (a "
                f"{entry[1].class_name} of a file with GlobalGeometryRules ClockWise), where "
                "EnergyPlus 25.2 builds it; for an overhang or fin outside, give the window "
                "counter-clockwise (or as a simple Window) or use Shading:Zone:Detailed"
            )
        normal = side * newell_normal(world)
        normal = normal / np.linalg.norm(normal)
        up = np.array([0.0, 0.0, 1.0]) - normal[2] * normal
        if np.linalg.norm(up) < 1e-6:
            raise ThermocalInputError(
                f"{obj.where()}: window '{entry[0]}' is horizontal; overhangs and fins are "
                "defined for tilted or vertical windows only (use Shading:Zone:Detailed)."
            )
        up = up / np.linalg.norm(up)
        right = np.cross(up, normal)  # to the right seen from outside
        x = world @ right
        y = world @ up
        corner = world[0] + (x.min() - x[0]) * right + (y.min() - y[0]) * up
        return corner, right, up, normal, float(np.ptp(x)), float(np.ptp(y))

    def _overhang(self, rec, *, projection: bool):
        from thermocal.multizone.shading import ShadingSurface

        corner, right, up, normal, width, height = self._window_frame(rec)
        above = _number(rec, "height_above_window_or_door", default=0.0)
        tilt = math.radians(_number(rec, "tilt_angle_from_window_door", default=90.0))
        left = _number(rec, "left_extension_from_window_door_width", default=0.0)
        right_ext = _number(rec, "right_extension_from_window_door_width", default=0.0)
        if projection:
            depth = height * _number(rec, "depth_as_fraction_of_window_door_height")
        else:
            depth = _number(rec, "depth")
        if depth <= 0:
            raise ThermocalInputError(
                f"{rec['_object'].where()}: field "
                f"'{'Depth as Fraction of Window/Door Height' if projection else 'Depth'}' "
                "must be > 0."
            )
        outward = math.cos(tilt) * up + math.sin(tilt) * normal
        a = corner + (-left) * right + (height + above) * up
        b = corner + (width + right_ext) * right + (height + above) * up
        vertices = np.array([a, b, b + depth * outward, a + depth * outward])
        return ShadingSurface(rec["name"], vertices, None, rec["_object"].where())

    def _fins(self, rec, *, projection: bool):
        from thermocal.multizone.shading import ShadingSurface

        corner, right, up, normal, width, height = self._window_frame(rec)
        fins = []
        for side, sign, x0 in (("left", -1.0, 0.0), ("right", 1.0, width)):
            if projection:
                fraction = _number(
                    rec, f"{side}_depth_as_fraction_of_window_door_width", default=0.0
                )
                depth = fraction * width
            else:
                depth = _number(rec, f"{side}_depth", default=0.0)
            if depth <= 0:
                continue
            ext = _number(rec, f"{side}_extension_from_window_door", default=0.0)
            top = _number(rec, f"{side}_distance_above_top_of_window", default=0.0)
            bottom = _number(rec, f"{side}_distance_below_bottom_of_window", default=0.0)
            tilt = math.radians(_number(rec, f"{side}_tilt_angle_from_window_door", default=90.0))
            outward = math.sin(tilt) * normal + sign * math.cos(tilt) * right
            base = corner + (x0 + sign * ext) * right
            low, high = base - bottom * up, base + (height + top) * up
            vertices = np.array([low, high, high + depth * outward, low + depth * outward])
            fins.append(
                ShadingSurface(f"{rec['name']} {side}", vertices, None, rec["_object"].where())
            )
        return fins


def _overhang_side(window_class: str, *, clockwise: bool) -> float:
    """The side of a window EnergyPlus builds its ``Shading:Overhang`` / ``Shading:Fin`` on.

    Parameters
    ----------
    window_class : str
        Upper-case class of the window or door (``FENESTRATIONSURFACE:DETAILED``, ``WINDOW``,
        ...).
    clockwise : bool
        Whether the file's ``GlobalGeometryRules`` say ``ClockWise``.

    Returns
    -------
    float
        +1 outside, -1 on the zone's side: a ``FenestrationSurface:Detailed`` of a clockwise
        file (measured with EnergyPlus 25.2: NREL 4ZoneWithShading_Simple_1 rewritten as
        detailed objects, clockwise, with the same overhangs and fins, runs 0.3-0.6 K warmer
        than counter-clockwise, as without them shading the windows). The simple classes
        (:data:`.simple_geometry.RECTANGULAR_SUBSURFACE_CLASSES`) get outside whatever the
        vertex order: EnergyPlus makes their vertices itself.
    """
    from thermocal.multizone.idf.simple_geometry import RECTANGULAR_SUBSURFACE_CLASSES

    return -1.0 if clockwise and window_class not in RECTANGULAR_SUBSURFACE_CLASSES else 1.0


def _outward(world: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """The vertices ordered counter-clockwise seen from the side ``normal`` points to."""
    return world if float(newell_normal(world) @ normal) >= 0 else world[::-1].copy()


def _casts_on_others(surfaces: list) -> list:
    """The polygons of ``surfaces`` with a part in front of another one's plane (by more than
    1 mm): those that can shade another surface of the same building."""
    vertices = [np.asarray(surface.vertices, dtype=float) for surface in surfaces]
    normals = np.array([newell_normal(verts) for verts in vertices])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    origins = np.array([verts[0] for verts in vertices])
    keep = []
    for i, verts in enumerate(vertices):
        # every vertex's height over every other surface's plane, at once
        height = np.einsum("vjk,jk->vj", verts[:, None, :] - origins[None, :, :], normals)
        ahead = height.max(axis=0) > 1e-3
        ahead[i] = False
        if ahead.any():
            keep.append(surfaces[i])
    return keep


def _merge_coplanar(surfaces: list, tolerance: float = 1e-3) -> list:
    """Coplanar polygons that tile their common bounding rectangle exactly (the storeys and
    flats of one facade) replaced by that rectangle: the same shadow, fewer polygons.

    Polygons are grouped by plane (unit normal and offset within ``tolerance`` [m]); a group
    whose areas sum to the area of its bounding rectangle in the plane (within 0.1 %) covers
    it without gaps (building surfaces do not overlap), so the rectangle casts the same
    shadow; this is checked per set of touching polygons (the two rows of a facade plane
    apart). Other polygons are kept one by one.
    """
    groups: list[tuple[np.ndarray, float, list]] = []
    for surface in surfaces:
        verts = np.asarray(surface.vertices, dtype=float)
        normal = newell_normal(verts)
        area = 0.5 * float(np.linalg.norm(normal))
        normal = normal / np.linalg.norm(normal)
        offset = float(verts[0] @ normal)
        for g_normal, g_offset, members in groups:
            if np.abs(g_normal - normal).max() < 1e-6 and abs(g_offset - offset) < tolerance:
                members.append((surface, verts, area))
                break
        else:
            groups.append((normal, offset, [(surface, verts, area)]))
    out = []
    for normal, _, group in groups:
        for members in _touching(group, tolerance):
            out.extend(_tiled_rectangle(members, normal))
    return out


def _touching(members: list, tolerance: float) -> list[list]:
    """The members (surface, vertices, area) in groups whose bounding boxes touch (connected
    components)."""
    lows = [verts.min(axis=0) - tolerance for _, verts, _ in members]
    highs = [verts.max(axis=0) + tolerance for _, verts, _ in members]
    parent = list(range(len(members)))

    def root(i):
        while parent[i] != i:
            i = parent[i]
        return i

    for i in range(len(members)):
        for j in range(i + 1, len(members)):
            if np.all(lows[i] <= highs[j]) and np.all(lows[j] <= highs[i]):
                parent[root(i)] = root(j)
    components: dict[int, list] = {}
    for i, member in enumerate(members):
        components.setdefault(root(i), []).append(member)
    return list(components.values())


def _tiled_rectangle(members: list, normal: np.ndarray) -> list:
    """``[rectangle]`` when the members tile their bounding rectangle, else their surfaces."""
    from thermocal.multizone.shading import ShadingSurface

    if len(members) > 1:
        points = np.concatenate([verts for _, verts, _ in members])
        helper = np.array([0.0, 0.0, 1.0]) if abs(normal[2]) < 0.9 else np.array([1.0, 0, 0])
        u = np.cross(helper, normal)
        u /= np.linalg.norm(u)
        v = np.cross(normal, u)
        origin = points[0]
        pu, pv = (points - origin) @ u, (points - origin) @ v
        box = (pu.max() - pu.min()) * (pv.max() - pv.min())
        total = sum(area for _, _, area in members)
        if abs(total - box) <= 1e-3 * box:
            rectangle = np.array(
                [
                    origin + a * u + b * v
                    for a, b in (
                        (pu.min(), pv.min()),
                        (pu.max(), pv.min()),
                        (pu.max(), pv.max()),
                        (pu.min(), pv.max()),
                    )
                ]
            )
            if float(newell_normal(rectangle) @ normal) < 0:
                rectangle = rectangle[::-1]
            names = ", ".join(surface.name for surface, _, _ in members[:3])
            return [
                ShadingSurface(
                    f"{len(members)} coplanar surfaces ({names}, ...)",
                    rectangle,
                    None,
                    members[0][0].source,
                    front_only=members[0][0].front_only,
                )
            ]
    return [surface for surface, _, _ in members]


def _shadow_settings_not_applied(obj) -> list[str]:
    """Notes on ``ShadowCalculation`` settings the model does not apply: a calculation method
    other than polygon clipping (``Scheduled`` or ``Imported`` sunlit fractions, pixel
    counting is the same geometry) and the self-shading switches of shading zone groups (the
    model's building shades itself everywhere, as EnergyPlus' default)."""
    fields = [f.strip() for f in obj.fields]
    method = fields[0].upper() if fields else ""
    notes = []
    where = obj.where()
    if method in ("SCHEDULED", "IMPORTED"):
        notes.append(
            f"{where}: 'Shading Calculation Method' = {fields[0]}: NOT APPLIED, the model computes "
            "the sunlit fractions from the geometry (PolygonClipping)"
        )
    for position, label in ((8, "Disable Self-Shading Within Shading Zone Groups"),
                            (9, "Disable Self-Shading From Shading Zone Groups to Other Zones")):
        if len(fields) > position and fields[position].upper() == "YES":
            notes.append(
                f"{where}: '{label}' = Yes: NOT APPLIED, the building's surfaces shade one "
                "another everywhere"
            )  # fmt: skip
    return notes
