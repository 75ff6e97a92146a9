"""Zones, surfaces, sub-surfaces and internal mass of an IDF file.

Stages of the import (:class:`SurfaceStages`, mixed into the builder of
:func:`thermocal.multizone.idf.read_idf`): ``Zone``, ``ZoneList``, ``BuildingSurface:Detailed``
and its ``Wall/RoofCeiling/Floor:Detailed`` siblings, ``FenestrationSurface:Detailed`` (windows,
glass doors, doors), the model surfaces (inter-zone partners, doors, ``InternalMass`` as adiabatic
surfaces) and the zone floor areas and volumes. The geometry is :mod:`.geometry`'s.
"""

from __future__ import annotations

import math

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.constructions import _reversed_construction
from thermocal.multizone.idf.fields import _SURFACE_CLASS_TYPE, SCHEMA
from thermocal.multizone.idf.geometry import (
    _boundary,
    _check_planar,
    _vertices,
    outside_of_host,
    outward_normal,
    outward_order,
    polyhedron_is_closed,
    tilt_azimuth,
    to_world_coordinates,
    zone_volume_from_surfaces,
)
from thermocal.multizone.idf.loads import local_wind_factor
from thermocal.multizone.idf.parse import _is_auto, _Names, _number, _wrap
from thermocal.multizone.idf.report import EP_CHECK
from thermocal.multizone.idf.simple_geometry import (
    RECTANGULAR_SUBSURFACE_CLASSES,
    RECTANGULAR_SURFACE_CLASSES,
)


class SurfaceStages:
    """Stages ``_zones``, ``_surfaces``, ``_subsurfaces``, ``_model_surfaces`` and
    ``_zone_volumes`` of the builder.

    They set ``zones``, ``zone_lists``, ``zone_geometry``, ``surfaces``, ``fenestration``,
    ``surface_data``, ``model_windows``, ``door_surfaces``, ``subtract``, ``model_surfaces``,
    ``zone_floor_area``, ``zone_polygons``, ``zone_volume`` and ``zone_area``; they fill
    ``info.surface_vertices``, ``info.surface_types`` and ``info.zone_multipliers``.
    """

    def _zones(self) -> None:
        """Stage: zones."""
        self.zones = _Names("zone")
        for rec in self.records("ZONE"):
            self.zones.add(rec)
        if not self.zones.items:
            raise ThermocalInputError(f"{self.path.name}: the file defines no Zone object.")
        self.zone_lists: dict[str, list[str]] = {}
        for rec in self.records("ZONELIST"):
            members = []
            for (member,) in rec["zone_names"]:
                entry = self.zones.get(member)
                if entry is None:
                    raise ThermocalInputError(
                        f"{rec['_object'].where()}: zone '{member}' is not defined."
                    )
                members.append(entry[0])
            self.zone_lists[rec["name"].upper()] = members

        self.zone_geometry = {}
        for name, _obj, rec in self.zones.values():
            multiplier = _number(rec, "multiplier", default=1.0)
            self.info.zone_multipliers[name] = multiplier
            self.zone_geometry[name.upper()] = {
                "origin": (
                    _number(rec, "x_origin", default=0.0),
                    _number(rec, "y_origin", default=0.0),
                    _number(rec, "z_origin", default=0.0),
                ),
                "north": _number(rec, "direction_of_relative_north", default=0.0),
            }
            if multiplier != 1.0:
                self.info.notes.append(
                    f"zone '{name}' has multiplier {multiplier:g}; the model simulates it once"
                )
            for side in ("inside", "outside"):
                algorithm = rec.get(f"zone_{side}_convection_algorithm") or ""
                if algorithm:  # building-wide in the model: noted by info.network_options()
                    self.info.zone_convection.setdefault(side, {})[name] = algorithm
        self._zone_groups()

    def _zone_groups(self) -> None:
        """``ZoneGroup``: its zone list's zones count its multiplier times more (EnergyPlus'
        *Zone List Multiplier*, times each zone's own), in the building's totals as a zone
        multiplier does; the zones are simulated once."""
        for rec in self.records("ZONEGROUP"):
            members = self.zone_lists.get((rec["zone_list_name"] or "").upper())
            if members is None:
                raise ThermocalInputError(
                    f"{rec['_object'].where()}: zone list '{rec['zone_list_name']}' is not "
                    "defined."
                )
            factor = _number(rec, "zone_list_multiplier", default=1.0)
            if not factor >= 1.0:
                raise ThermocalInputError(
                    f"{rec['_object'].where()}: field 'Zone List Multiplier' = {factor:g}: "
                    "give a whole number of 1 or more."
                )
            for zone in members:
                own = self.info.zone_multipliers.get(zone, 1.0)
                self.info.zone_multipliers[zone] = own * factor
            self.info.notes.append(
                f"ZoneGroup '{rec['name']}': the {len(members)} zone(s) of zone list "
                f"'{rec['zone_list_name']}' count {factor:g} times in the building's totals, as "
                "EnergyPlus multiplies them; the model simulates each once"
            )

    def _surfaces(self) -> None:
        """Stage: surfaces."""
        self.surfaces = _Names("surface")
        for rec in self.records("BUILDINGSURFACE:DETAILED", *_SURFACE_CLASS_TYPE):
            self.surfaces.add(rec)
        for rec in self._rectangular_surfaces():  # Wall:Exterior, Roof, ... (simple geometry)
            self.surfaces.add(rec)
        self.fenestration = _Names("fenestration surface")
        for rec in self.records("FENESTRATIONSURFACE:DETAILED"):
            if rec["name"].upper() in self.surfaces:
                raise ThermocalInputError(
                    f"{rec['_object'].where()}: the name is already used by a building surface."
                )
            self.fenestration.add(rec)
        for key, kind in RECTANGULAR_SUBSURFACE_CLASSES.items():
            for rec in self.records(key):
                if rec["name"].upper() in self.surfaces:
                    raise ThermocalInputError(
                        f"{rec['_object'].where()}: the name is already used by a building surface."
                    )
                self.fenestration.add(self._rectangular_subsurface(rec, kind))

        self.surface_data: dict[str, dict] = {}
        for name, obj, rec in self.surfaces.values():
            surface_type = rec.get("surface_type") or _SURFACE_CLASS_TYPE[obj.key]
            zone_entry = self.zones.get(rec["zone_name"])
            if zone_entry is None:
                raise ThermocalInputError(
                    f"{obj.where()}: field 'Zone Name' = '{rec['zone_name']}' is not a Zone of "
                    "the file."
                )
            zone_name = zone_entry[0]
            cons = rec["construction_name"]
            if cons.upper() in self.window_types:
                raise ThermocalInputError(
                    f"{obj.where()}: field 'Construction Name' "
                    f"= '{cons}' is a window construction; "
                    "opaque surfaces need an opaque construction."
                )
            cons_entry = self.constructions.get(cons)
            if cons_entry is None:
                other = next(
                    (
                        o.class_name
                        for o in self.objects
                        if o.key.startswith("CONSTRUCTION:") and o.name.upper() == cons.upper()
                    ),
                    None,
                )
                hint = (
                    f" ({other} is not supported; give a layered Construction instead)"
                    if other
                    else ""
                )
                raise ThermocalInputError(
                    f"{obj.where()}: field 'Construction Name' "
                    f"= '{cons}' is not a Construction of the "
                    f"file{hint}."
                )
            world, normal, area = self._world_polygon(rec, zone_name)
            _check_planar(world, normal, obj)
            tilt, azimuth = tilt_azimuth(normal)
            self.surface_data[name.upper()] = {
                "name": name,
                "obj": obj,
                "rec": rec,
                "type": surface_type,
                "zone": zone_name,
                "construction": cons_entry[0],
                "world": world,
                "normal": normal,
                "area": area,
                "tilt": tilt,
                "azimuth": azimuth,
                "boundary": _boundary(rec["outside_boundary_condition"], obj),
            }
            self.info.surface_vertices[name] = outward_order(world, self.rules)
            self.info.surface_types[name] = surface_type.title()
        self._check_closed_zones()

    def _check_closed_zones(self) -> None:
        """A surface whose vertices run the wrong way in an otherwise closed zone is refused.

        The area vectors (outward normal x area) of a closed zone sum to zero; when one surface
        is reversed they sum to twice its area vector instead. Zones that are not closed
        (surfaces missing) are left alone: no single surface explains their sum.
        """
        by_zone: dict[str, list[dict]] = {}
        for data in self.surface_data.values():
            by_zone.setdefault(data["zone"], []).append(data)
        for zone, surfaces in by_zone.items():
            if len(surfaces) < 4:
                continue
            vectors = np.array([d["normal"] for d in surfaces])  # |Newell normal| = 2 area
            total = vectors.sum(axis=0)
            scale = float(np.linalg.norm(vectors, axis=1).sum())
            if np.linalg.norm(total) <= 1e-3 * scale:
                continue
            misfit = np.linalg.norm(vectors - total / 2.0, axis=1)
            fits = np.flatnonzero(misfit <= 0.01 * np.linalg.norm(vectors, axis=1))
            # the surface whose reversal closes the zone edge to edge (an open zone such as a
            # breezeway of stacked floors without walls has none: left alone)
            closing = [k for k in fits if self._closed_with_reversed(surfaces, k)]
            if len(closing) == 1:
                best = closing[0]
                data = surfaces[best]
                raise ThermocalInputError(
                    f"{data['obj'].where()}: its vertices run the wrong way: the outward "
                    f"normal (tilt {data['tilt']:.0f} deg, azimuth {data['azimuth']:.0f} deg) "
                    f"points into zone '{zone}' (the zone's other surfaces close around it "
                    "only when it is reversed); reverse the vertex order (the file's "
                    f"GlobalGeometryRules: {self.rules.vertex_entry_direction.lower()} seen "
                    "from outside)."
                )

    def _subsurfaces(self) -> None:
        """Stage: sub-surfaces."""
        self.model_windows = []
        self.door_surfaces = []
        self.subtract: dict[str, float] = {}
        for name, obj, rec in self.fenestration.values():
            base = self.surface_data.get(rec["building_surface_name"].upper())
            if base is None:
                raise ThermocalInputError(
                    f"{obj.where()}: field 'Building Surface Name' = "
                    f"'{rec['building_surface_name']}' is not a building surface of the file"
                    f"{self._unread_surface_hint(rec['building_surface_name'])}."
                )
            kind = (rec["surface_type"] or "Window").upper()
            world, normal, area = self._world_polygon(rec, base["zone"])
            cos_angle = float(np.dot(normal, base["normal"])) / (
                np.linalg.norm(normal) * np.linalg.norm(base["normal"])
            )
            if cos_angle < 0.999:
                raise ThermocalInputError(
                    f"{obj.where()}: its outward normal differs from that of its base surface "
                    f"'{base['name']}' by "
                    f"{math.degrees(math.acos(max(-1, min(1, cos_angle)))):.1f} "
                    "deg; check the vertex order and coplanarity."
                )
            outside = outside_of_host(world, base["world"], base["normal"])
            if outside > 1e-3:
                self.info.notes.append(
                    f"{EP_CHECK}{obj.where()}: reaches {outside:.2f} m beyond its base surface "
                    f"'{base['name']}' (EnergyPlus warns 'Base surface does not surround "
                    "subsurface (CHKSBS)' and runs it; so does thermocal, the area taken "
                    "from the base surface as given); check 'Starting X/Z Coordinate', "
                    "'Length' and 'Height' or the vertices"
                )
            multiplier = self._subsurface_multiplier(rec, obj)
            total_area = area * multiplier
            self.info.surface_vertices[name] = outward_order(world, self.rules)
            self.info.surface_types[name] = kind.title()
            cons = rec["construction_name"]
            if kind in ("WINDOW", "GLASSDOOR"):
                wt = self.window_types.get(cons.upper())
                if wt is None:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Construction Name' = '{cons}' is not a window "
                        "construction (Construction of WindowMaterial layers) of the file"
                        f"{self._unread_window_construction_hint(cons)}."
                    )
                if base["boundary"] != "outdoors":
                    self.info.notes.append(
                        f"interior window '{name}' (host '{base['name']}', boundary "
                        f"{base['boundary']}) is not modelled; its area stays opaque"
                    )
                    continue
                if rec.get("frame_and_divider_name"):
                    self.info.notes.append(
                        f"window '{name}': WindowProperty:FrameAndDivider "
                        f"'{rec['frame_and_divider_name']}' is ignored (frame_fraction 0)"
                    )
                self.model_windows.append(
                    _wrap(
                        obj,
                        self.mz.Window,
                        name=name,
                        surface=base["name"],
                        window_type=wt[0],
                        area=total_area,
                        frame_fraction=0.0,
                        height=_slope_height(world, normal, area),
                    )
                )
            elif kind == "DOOR":
                cons_entry = self.constructions.get(cons)
                if cons_entry is None or cons.upper() not in self.opaque_constructions:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Construction Name' = '{cons}' is not an opaque "
                        "Construction of the file (doors need one)."
                    )
                self.subtract[base["name"]] = self.subtract.get(base["name"], 0.0) + total_area
                self.door_surfaces.append((name, obj, base, cons_entry[0], total_area))
            else:
                self.info.notes.append(
                    f"sub-surface '{name}' of type {kind.title()} is not modelled"
                )

    def _check_partner_faces_back(self, data: dict, partner: dict) -> None:
        """Note an interzone pair whose outward normals are not opposite (EnergyPlus warns
        "InterZone Surface Tilts do not match as expected" and runs it, each side as given;
        so does thermocal)."""
        a, b = data["normal"], partner["normal"]
        cosine = float(a @ b) / float(np.linalg.norm(a) * np.linalg.norm(b))
        if cosine <= -0.999:
            return
        self.info.notes.append(
            f"{EP_CHECK}{data['obj'].where()} (tilt {data['tilt']:.0f} deg, azimuth "
            f"{data['azimuth']:.0f} deg) and its partner {partner['obj'].where()} (tilt "
            f"{partner['tilt']:.0f} deg, azimuth {partner['azimuth']:.0f} deg) do not face "
            "each other (EnergyPlus warns 'InterZone Surface Tilts do not match as expected'); "
            "a floor faces down (tilt 180), the ceiling under it up (tilt 0): check the "
            "'Tilt Angle' / 'Azimuth Angle' or the vertex order"
        )

    def _subsurface_multiplier(self, rec: dict, obj) -> float:
        """A sub-surface's ``Multiplier`` [-] as EnergyPlus applies it.

        A ``FenestrationSurface:Detailed``'s multiplies its area (EnergyPlus: the window's
        area, the host's net area and the solar through it). A simple ``Window``, ``Door``,
        ``GlazedDoor`` (or ``:Interzone``) has one too, but EnergyPlus (25.2) does not apply it:
        ``GetRectSubSurfaces`` stores it, ``MakeRelativeRectangularVertices`` then sets the area
        to one rectangle's, and the host loses one rectangle (EnergyPlus 25.2's eio lists a
        3 x 5 m Window of Multiplier 3 at 15 m2 and its 20 x 10 m wall, which holds one more
        such window, at 170 m2 net; as a FenestrationSurface:Detailed, 45 m2 and 140 m2). So 1
        here, noted when the file gives another value.
        """
        multiplier = _number(rec, "multiplier", default=1.0)
        if obj.key in RECTANGULAR_SUBSURFACE_CLASSES and multiplier != 1.0:
            self.info.notes.append(
                f"{EP_CHECK}{obj.where()}: field 'Multiplier' = {multiplier:g} is not applied, "
                f"as EnergyPlus does not apply it to a {obj.class_name} (one "
                f"{rec['length']} x {rec['height']} m rectangle, area and solar once); for "
                f"{multiplier:g} of them give it as a FenestrationSurface:Detailed with this "
                "Multiplier or as separate objects, or set the Multiplier to 1"
            )
            return 1.0
        return multiplier

    def _unread_window_construction_hint(self, name: str) -> str:
        """What to do when a window names a construction of a class the importer does not
        read (``Construction:WindowDataFile``, ``Construction:ComplexFenestrationState``,
        ...): the class and its replacement, else ""."""
        found = next(
            (
                o
                for o in self.objects
                if o.key.startswith("CONSTRUCTION:")
                and o.key not in SCHEMA
                and o.name.upper() == name.upper()
            ),
            None,
        )
        if found is None:
            return ""
        replacement = (
            "describe the glazing as a Construction of WindowMaterial:Glazing and "
            "WindowMaterial:Gas layers (the panes and gaps of the Window5 data file's entry) "
            "or as a WindowMaterial:SimpleGlazingSystem with the entry's U-factor and SHGC"
            if found.key == "Construction:WindowDataFile".upper()
            else "describe the glazing as a Construction of WindowMaterial:Glazing and "
            "WindowMaterial:Gas layers or as a WindowMaterial:SimpleGlazingSystem"
        )
        return (
            f" (it is the {found.class_name} of line {found.line}, a class thermocal does not "
            f"import; {replacement})"
        )

    def _check_zones_have_surfaces(self) -> None:
        """Refuse a zone that no heat-transfer surface bounds: it would exchange no heat
        through an envelope and float at its start temperature (or at the outdoor air's with
        infiltration), a wrong number with no sign of it."""
        bounded = {data["zone"] for data in self.surface_data.values()}
        bounded |= {data["zone"] for data in self._zone_partners()}
        for name, obj, _rec in self.zones.values():
            if name in bounded:
                continue
            raise ThermocalInputError(
                f"{obj.where()}: zone '{name}' has no heat-transfer surface: no "
                "BuildingSurface:Detailed, Wall:Detailed, RoofCeiling:Detailed, Floor:Detailed "
                "or simple-geometry surface (Wall:Exterior, Roof, Floor:Adiabatic, ...) names "
                "it in field 'Zone Name', and no surface with Outside Boundary Condition = Zone "
                "faces it. Without surfaces the zone exchanges no heat through an envelope and "
                "its temperature would stay where it starts; add its surfaces, or remove the "
                "zone and the objects that name it."
            )

    def _closed_with_reversed(self, surfaces: list[dict], k: int) -> bool:
        """True if the zone's polygons close edge to edge with polygon ``k`` reversed."""
        polygons = []
        for i, data in enumerate(surfaces):
            world = data["world"][::-1] if i == k else data["world"]
            polygons.append(world[::-1] if self.rules.clockwise else world)
        return polyhedron_is_closed(polygons)

    def _world_polygon(self, rec: dict, zone_name: str):
        """World vertices, outward (Newell) normal and area [m2] of a surface's polygon in the
        coordinates of ``zone_name``; a degenerate polygon is an error naming the object."""
        geometry = self.zone_geometry[zone_name.upper()]
        world = to_world_coordinates(
            _vertices(rec),
            rules=self.rules,
            zone_origin=geometry["origin"],
            zone_north_axis=geometry["north"],
            building_north_axis=self.north_axis,
        )
        normal = outward_normal(world, self.rules)
        area = 0.5 * float(np.linalg.norm(normal))
        if area <= 1e-9:
            raise ThermocalInputError(
                f"{rec['_object'].where()}: the vertices enclose zero area (degenerate polygon)."
            )
        return world, normal, area

    def _foundation_grounds(self) -> None:
        """The ground sections of the floors on a ``Foundation`` boundary
        (``self.foundations``, by floor) and the basements' walls that meet them
        (``self.foundation_walls``); floors without an exposed perimeter stay adiabatic."""
        from thermocal.multizone.idf.foundation import foundation_ground, kiva_settings

        self.foundations, self.foundation_walls = {}, set()

        def on_foundation(data) -> bool:
            return data["rec"]["outside_boundary_condition"].upper() == "FOUNDATION"

        floors = [d for d in self.surface_data.values() if on_foundation(d) and d["tilt"] >= 135.0]
        if not floors:
            return
        settings, notes = kiva_settings(self.objects, float(self.location.altitude or 0.0))
        self.info.notes.extend(notes)
        materials = {m.name.upper(): m for m in self.model_materials}
        constructions = {c.name.upper(): c for c in self.model_constructions}
        for data in floors:
            target = data["rec"].get("outside_boundary_condition_object", "")
            walls = [
                other
                for other in self.surface_data.values()
                if on_foundation(other)
                and other["zone"] == data["zone"]
                and 45.0 <= other["tilt"] < 135.0
                and other["rec"].get("outside_boundary_condition_object", "").upper()
                == target.upper()
            ]
            ground, notes = foundation_ground(
                data["name"], data["world"], target, self.objects, materials, constructions,
                settings, walls=[(w["name"], w["world"], w["construction"]) for w in walls],
                floor_construction=data["construction"],
            )  # fmt: skip
            self.info.notes.extend(notes)
            if ground is not None:
                self.foundations[data["name"]] = ground
                self.foundation_walls.update(w for w, _ in ground.walls)

    def _model_surfaces(self) -> None:
        """Stage: model surfaces."""
        self.model_surfaces = []
        self._foundation_grounds()
        for key, data in self.surface_data.items():
            obj, rec = data["obj"], data["rec"]
            boundary = data["boundary"]
            other_surface = None
            other_zone = None
            if boundary == "surface":
                target = rec["outside_boundary_condition_object"]
                partner = self.surface_data.get(target.upper())
                if partner is None:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Outside Boundary Condition Object' = '{target}' is "
                        "not a building surface of the file "
                        "(inter-zone surfaces need their partner)."
                    )
                if partner["name"].upper() == key:
                    # a surface facing itself: internal mass (EnergyPlus idiom), its outside face
                    # at its inside face's temperature
                    boundary = "adiabatic"
                else:
                    _check_partner_points_back(data, partner)
                    if key < partner["name"].upper():  # each pair once
                        self._check_partner_faces_back(data, partner)
                    boundary = "zone"
                    other_surface = partner["name"]
                    other_zone = partner["zone"]
            elif boundary == "zone":
                target = rec["outside_boundary_condition_object"]
                other = self.zones.get(target)
                if other is None:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Outside Boundary Condition Object' = '{target}' is "
                        "not a Zone of the file."
                    )
                # EnergyPlus creates the reversed partner surface automatically; so do we
                boundary = "zone"
                other_zone = other[0]
                other_surface = f"{data['name']} (partner)"
            elif boundary == "unsupported" and (
                data["name"] in self.foundations or data["name"] in self.foundation_walls
            ):
                boundary = "ground"
            elif boundary == "unsupported":
                condition = rec["outside_boundary_condition"]
                note = (
                    f"surface '{data['name']}': boundary {condition} is not modelled; treated "
                    "as adiabatic (no heat crosses it)"
                )
                if condition.upper() == "OTHERSIDECOEFFICIENTS":
                    # not the word 'ground' (the note would be counted among the ground ones)
                    note += (
                        "; the error grows with the difference between the zone and the other "
                        "side's temperature: on NREL's OSC test file (a wall held at 16-20 C "
                        "beside a 21-28 C zone) the zone ran 0.4-0.7 K warmer than in EnergyPlus "
                        "(hourly mean bias)"
                    )
                self.info.notes.append(note)
            area = data["area"] - self.subtract.get(data["name"], 0.0)
            sun = (rec.get("sun_exposure") or "SunExposed").upper() != "NOSUN"
            wind = (rec.get("wind_exposure") or "WindExposed").upper() != "NOWIND"
            vf_raw = rec.get("view_factor_to_ground", "")
            view_factor = None if _is_auto(rec, "view_factor_to_ground") else float(vf_raw)
            common = {
                "construction": data["construction"],
                "tilt": data["tilt"],
                "azimuth": data["azimuth"],
                "view_factor_ground": view_factor,
                "sun_exposed": sun,
                "wind_exposed": wind,
            }
            if boundary == "outdoors":
                common.update(_exterior_exposure(data["world"], self.terrain()))
            self.model_surfaces.append(
                _wrap(
                    obj,
                    self.mz.Surface,
                    name=data["name"],
                    zone=data["zone"],
                    area=area,
                    # EnergyPlus' adiabatic and self-facing surfaces: outside face at the inside
                    # face's temperature; an unsupported boundary: no heat through it
                    boundary="adiabatic" if boundary == "unsupported" else boundary,
                    outside_at_inside=boundary == "adiabatic",
                    other_zone=other_zone,
                    other_surface=other_surface,
                    **common,
                )
            )
            if other_surface is not None and other_surface.endswith(" (partner)"):
                reversed_name = _reversed_construction(
                    data["construction"], self.constructions, self.model_constructions, self.mz
                )
                flipped = -data["normal"]
                tilt, azimuth = tilt_azimuth(flipped)
                self.model_surfaces.append(
                    _wrap(
                        obj,
                        self.mz.Surface,
                        name=other_surface,
                        zone=other_zone,
                        construction=reversed_name,
                        area=area,
                        tilt=tilt,
                        azimuth=azimuth,
                        boundary="zone",
                        other_zone=data["zone"],
                        other_surface=data["name"],
                        sun_exposed=False,
                        wind_exposed=False,
                    )
                )
        for name, obj, base, cons_name, area in self.door_surfaces:
            base_surface = next(s for s in self.model_surfaces if s.name == base["name"])
            if base_surface.boundary == "zone":
                self.info.notes.append(
                    f"door '{name}' in inter-zone surface '{base['name']}' is merged into its host"
                )
                base_surface.area += area
                # the partner EnergyPlus makes for a Zone boundary was given the host's net area
                partner = f"{base['name']} (partner)"
                for surface in self.model_surfaces:
                    if surface.name == partner:
                        surface.area += area
                continue
            exposure = {}
            if base_surface.boundary == "outdoors":
                # the door's own height and perimeter (EnergyPlus), not its host's
                exposure = _exterior_exposure(self.info.surface_vertices[name], self.terrain())
            self.model_surfaces.append(
                _wrap(
                    obj,
                    self.mz.Surface,
                    name=name,
                    zone=base_surface.zone,
                    construction=cons_name,
                    area=area,
                    tilt=base_surface.tilt,
                    azimuth=base_surface.azimuth,
                    boundary=base_surface.boundary,
                    outside_at_inside=base_surface.outside_at_inside,
                    view_factor_ground=base_surface.view_factor_ground,
                    sun_exposed=base_surface.sun_exposed,
                    wind_exposed=base_surface.wind_exposed,
                    **exposure,
                )
            )

        for rec in self.records("INTERNALMASS"):
            obj = rec["_object"]
            cons = rec["construction_name"]
            if cons.upper() not in self.opaque_constructions:
                raise ThermocalInputError(
                    f"{obj.where()}: field 'Construction Name' = '{cons}' is not an opaque "
                    "Construction of the file."
                )
            for zone_name in self.zone_targets(rec):
                mass_name = (
                    rec["name"]
                    if self.zones.get(rec["zone_name"])
                    else f"{rec['name']} {zone_name}"
                )
                self.model_surfaces.append(
                    _wrap(
                        obj,
                        self.mz.Surface,
                        name=mass_name,
                        zone=zone_name,
                        construction=self.constructions.get(cons)[0],
                        area=_number(rec, "surface_area"),
                        tilt=90.0,
                        azimuth=0.0,
                        boundary="adiabatic",
                        outside_at_inside=True,  # EnergyPlus: both faces in the zone
                        sun_exposed=False,
                        wind_exposed=False,
                    )
                )
                self.info.surface_types[mass_name] = "InternalMass"
        self._note_unmirrored_pairs()

    def _note_unmirrored_pairs(self) -> None:
        """A note per pair of constructions of inter-zone surfaces that are not each other's
        mirror: EnergyPlus gives each side its own construction (and warns), thermocal builds
        the wall once, from the first surface of the pair."""
        from thermocal.multizone.elements import unmirrored_partners, unmirrored_partners_note

        layers = {c.name: tuple(c.layers) for c in self.model_constructions}
        for (built, far), walls in unmirrored_partners(self.model_surfaces, layers).items():
            self.info.notes.append(unmirrored_partners_note(built, far, walls))

    def _zone_partners(self) -> list[dict]:
        """The reversed partners EnergyPlus creates for surfaces whose outside boundary is a
        Zone (``Outside Boundary Condition`` = Zone): polygon reversed, in the other zone, a
        ceiling's partner a floor and a floor's a ceiling (EnergyPlus' surface types), so that
        they count in that zone's floor area and close its geometry."""
        partners = []
        kinds = {"CEILING": "Floor", "ROOF": "Floor", "FLOOR": "Ceiling", "WALL": "Wall"}
        for data in self.surface_data.values():
            rec = data["rec"]
            if (rec["outside_boundary_condition"] or "").upper() != "ZONE":
                continue
            other = self.zones.get(rec["outside_boundary_condition_object"])
            if other is None:
                continue  # refused with the file's line by the model surfaces
            partners.append(
                {
                    **data,
                    "zone": other[0],
                    "type": kinds.get(data["type"].upper(), data["type"]),
                    "world": data["world"][::-1].copy(),
                    "normal": -data["normal"],
                }
            )
        return partners

    def _zone_volumes(self) -> None:
        """Stage: zone areas and volumes (the partners of Zone-boundary surfaces included)."""
        self._check_zones_have_surfaces()
        self.zone_floor_area: dict[str, float] = {}
        self.zone_polygons: dict[str, list] = {}
        for data in [*self.surface_data.values(), *self._zone_partners()]:
            self.zone_polygons.setdefault(data["zone"], []).append(data)
            if data["type"].upper() == "FLOOR":
                self.zone_floor_area[data["zone"]] = (
                    self.zone_floor_area.get(data["zone"], 0.0) + data["area"]
                )
        self.zone_volume: dict[str, float] = {}
        self.zone_area: dict[str, float] = {}
        for name, obj, rec in self.zones.values():
            floor_area = (
                self.zone_floor_area.get(name, 0.0)
                if _is_auto(rec, "floor_area")
                else _number(rec, "floor_area")
            )
            self.zone_area[name] = floor_area
            if not _is_auto(rec, "volume") and _number(rec, "volume") > 0:
                self.zone_volume[name] = _number(rec, "volume")
                continue
            polys = self.zone_polygons.get(name, [])
            volume = 0.0
            entered_height = (
                _number(rec, "ceiling_height") if not _is_auto(rec, "ceiling_height") else 0.0
            )
            if entered_height > 0 and floor_area > 0:
                # EnergyPlus: a Ceiling Height entered with the Volume blank gives floor area x
                # height, whatever the surfaces enclose (a 48 m2 zone with 4.0 m entered: 192
                # m3 in its eio; the closed geometry's 129.6 m3 heated 12 % less)
                self.zone_volume[name] = floor_area * entered_height
                continue
            if polys and polyhedron_is_closed(
                [d["world"] if not self.rules.clockwise else d["world"][::-1] for d in polys]
            ):
                volume = zone_volume_from_surfaces(
                    [d["world"] for d in polys], [d["normal"] for d in polys]
                )
            if volume <= 0.0:
                if not _is_auto(rec, "ceiling_height") and _number(rec, "ceiling_height") > 0:
                    height = _number(rec, "ceiling_height")
                elif polys:
                    height = _ceiling_height(polys)
                else:
                    height = 0.0
                volume = floor_area * height
            if volume <= 0.0:
                raise ThermocalInputError(
                    f"{obj.where()}: the volume is not given "
                    "and cannot be derived from the surfaces "
                    "(no closed geometry, floor area or ceiling height); set field 'Volume'."
                )
            self.zone_volume[name] = volume


def _exterior_exposure(world: np.ndarray, terrain: str) -> dict:
    """Wind speed factor and perimeter of an exterior surface or door, as EnergyPlus takes them.

    EnergyPlus evaluates the wind at each exterior surface's centroid height in the site's
    terrain (a door at 1.2 m sees a third of the wind of the default factor) and TARP's
    exterior convection uses the perimeter of the gross polygon.

    Parameters
    ----------
    world : (n, 3) array [m]
        Vertices in world coordinates.
    terrain : str
        The Building object's terrain (:data:`~thermocal.multizone.idf.loads.TERRAIN_WIND_PROFILE`).

    Returns
    -------
    dict
        ``wind_speed_factor`` [-] (local over the weather station's wind speed) and
        ``perimeter`` [m], keyword arguments of :class:`~thermocal.multizone.model.Surface`.

    References
    ----------
    .. [1] EnergyPlus Engineering Reference 25.2, "Outside Surface Heat Balance", "Local Wind
       Speed Calculation".
    """
    world = np.asarray(world, dtype=float)
    return {
        "wind_speed_factor": local_wind_factor(float(np.mean(world[:, 2])), terrain),
        "perimeter": float(np.linalg.norm(np.roll(world, -1, axis=0) - world, axis=1).sum()),
    }


def _slope_height(world, normal, area: float) -> float:
    """Height [m] of a planar polygon along its slope (the vertical extent of a wall window,
    the length up the slope of a tilted one), as EnergyPlus' surface height; ``sqrt(area)``
    for a horizontal polygon, whose slope is undefined."""
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n)
    up = np.array([0.0, 0.0, 1.0]) - n[2] * n
    if np.linalg.norm(up) < 1e-6:
        return math.sqrt(area)
    up = up / np.linalg.norm(up)
    along = np.asarray(world, dtype=float) @ up
    height = float(along.max() - along.min())
    return height if height > 0 else math.sqrt(area)


def _ceiling_height(polys: list[dict]) -> float:
    """A zone's ceiling height [m] from its surfaces, as EnergyPlus derives it when the zone
    is not closed: the area-weighted mean height of its ceilings and roofs minus that of its
    floors; the zone's height range when it has no floor or no ceiling."""

    def mean_z(kinds):
        chosen = [d for d in polys if d["type"].upper() in kinds]
        area = sum(d["area"] for d in chosen)
        if area <= 0.0:
            return None
        return sum(d["area"] * float(np.mean(d["world"][:, 2])) for d in chosen) / area

    top, bottom = mean_z(("CEILING", "ROOF")), mean_z(("FLOOR",))
    if top is not None and bottom is not None and top > bottom:
        return top - bottom
    z = np.concatenate([d["world"][:, 2] for d in polys])
    return float(z.max() - z.min())


def _check_partner_points_back(data: dict, partner: dict) -> None:
    """Refuse an interzone pair whose second surface does not name the first back, in the
    file's terms (class, object, line and field of both).

    Parameters
    ----------
    data, partner : dict
        Entries of the surface registry (``surface_data``): the surface whose ``Outside
        Boundary Condition Object`` names ``partner``, and that partner.
    """
    rec = partner["rec"]
    back = rec.get("outside_boundary_condition_object", "")
    if partner["boundary"] == "surface" and back.upper() == data["name"].upper():
        return
    named = f"its Outside Boundary Condition Object '{back}'"
    if partner["obj"].key not in RECTANGULAR_SURFACE_CLASSES:  # a class with the field
        named = f"its Outside Boundary Condition '{rec['outside_boundary_condition']}', {named}"
    fix = (
        f"set its field 'Outside Boundary Condition Object' to '{data['name']}'"
        if partner["boundary"] == "surface"
        else f"make it a surface with Outside Boundary Condition 'Surface' and Outside "
        f"Boundary Condition Object '{data['name']}'"
    )
    raise ThermocalInputError(
        f"{data['obj'].where()}: field 'Outside Boundary Condition Object' names "
        f"'{partner['name']}', but {partner['obj'].where()} does not name it back ({named}); "
        f"the two sides of an interzone surface name each other: {fix}, or point "
        f"'{data['name']}' at the surface that names it."
    )
