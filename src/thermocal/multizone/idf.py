"""EnergyPlus IDF import: tokenizer, a small schema, surface geometry, mapping to a Building.

The importer covers the envelope subset of EnergyPlus input that the multi-zone model represents:
``Zone``, ``BuildingSurface:Detailed`` (and its ``Wall/RoofCeiling/Floor:Detailed`` siblings),
``FenestrationSurface:Detailed``, ``Material``, ``Material:NoMass``, ``Material:AirGap``,
``Construction``, ``WindowMaterial:SimpleGlazingSystem``, ``WindowMaterial:Glazing`` +
``WindowMaterial:Gas`` (layered glazing, optics by :mod:`thermocal.multizone.glazing`),
``ZoneInfiltration:DesignFlowRate``, ``Site:Location``, ``Site:GroundTemperature:BuildingSurface``,
``GlobalGeometryRules``, ``Building`` (north axis), ``ZoneList``, the internal gains
``OtherEquipment``/``ElectricEquipment``/``Lights``/``People`` and the thermostat objects
(``ZoneControl:Thermostat`` with ``ThermostatSetpoint:*``, ``HVACTemplate:Thermostat``) with the
schedules they use (``Schedule:Constant``, ``Schedule:Compact``, ``Schedule:Year`` /
``Schedule:Week:Daily`` / ``Schedule:Day:Interval`` / ``Schedule:Day:Hourly``).

Everything else is listed in ONE :class:`IdfImportWarning` grouped by class with counts.

Layers of this module, each usable on its own:

1. :func:`parse_idf` / :func:`read_idf_objects`: text -> list of :class:`IdfObject` (class name as
   written, raw string fields, the ``!-`` field comments, line numbers). Class names are matched
   case-insensitively everywhere.
2. :data:`SCHEMA` and :func:`record`: field names for the supported classes (EnergyPlus 8.9 to
   24.x layouts, including the ``Space Name`` field of newer surfaces, detected from content).
3. Geometry: :func:`newell_normal`, :func:`polygon_area`, :func:`tilt_azimuth`,
   :func:`to_world_coordinates`, :func:`zone_volume_from_surfaces` with the EnergyPlus conventions
   (vertices counter-clockwise seen from outside unless ``GlobalGeometryRules`` says clockwise;
   relative coordinates are rotated by the zone's direction of relative north and shifted by its
   origin, then rotated by the building's north axis; world coordinates are used as given).
4. :func:`read_idf` -> :class:`thermocal.multizone.model.Building`.

References
----------
EnergyPlus Input Output Reference (v9.3), sections Group -- Thermal Zone Description/Geometry
(GlobalGeometryRules, Zone, BuildingSurface:Detailed, FenestrationSurface:Detailed), Group --
Surface Construction Elements (Material, Material:NoMass, Material:AirGap, WindowMaterial:*),
Group -- Internal Gains, Group -- Airflow (ZoneInfiltration:DesignFlowRate), Group -- Schedules.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from thermocal.errors import ThermocalInputError

__all__ = [
    "IdfObject",
    "IdfImportWarning",
    "SCHEMA",
    "parse_idf",
    "read_idf_objects",
    "record",
    "newell_normal",
    "polygon_area",
    "tilt_azimuth",
    "GeometryRules",
    "to_world_coordinates",
    "zone_volume_from_surfaces",
]


class IdfImportWarning(UserWarning):
    """Objects of an IDF file that the importer does not represent (listed, not silently dropped)."""


# ------------------------------------------------------------------------------------------------
# 1. Tokenizer
# ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class IdfObject:
    """One object of an IDF file.

    Attributes
    ----------
    class_name : str
        Class as written in the file (e.g. ``"BuildingSurface:Detailed"``).
    fields : tuple of str
        Raw field values after the class name, stripped of whitespace ("" for blank fields).
    comments : tuple of str
        The ``!-`` (or ``!``) comment written after each field on its line, "" where none.
    line : int
        1-based line number of the class name in the file.
    source : str
        File name (or ``"<string>"``) for messages.
    """

    class_name: str
    fields: tuple[str, ...]
    comments: tuple[str, ...]
    line: int
    source: str = "<string>"

    @property
    def key(self) -> str:
        """Upper-case class name, the case-insensitive identity of the class."""
        return self.class_name.upper()

    @property
    def name(self) -> str:
        """First field (the object name for nearly every class), "" when absent."""
        return self.fields[0] if self.fields else ""

    def where(self) -> str:
        """``"<class> '<name>' (file line n)"`` for error messages."""
        label = f"{self.class_name} '{self.name}'" if self.name else self.class_name
        return f"{label} ({self.source} line {self.line})"


def parse_idf(text: str, *, source: str = "<string>") -> list[IdfObject]:
    """Split IDF text into objects.

    Commas separate fields, a semicolon ends an object, ``!`` starts a comment that runs to the
    end of the line. The comment text (without the ``!-`` marker) is kept for the last field
    completed on that line, which is how IDF editors label fields.

    Parameters
    ----------
    text : str
        Content of an IDF file.
    source : str
        Name used in messages.

    Returns
    -------
    list of IdfObject
        In file order.

    Raises
    ------
    ThermocalInputError
        When the file ends inside an object (missing ``;``).
    """
    finished: list[tuple[list[str], list[str], int]] = []
    tokens: list[str] = []
    comments: list[str] = []
    current: list[str] = []
    start_line = 0
    for line_number, raw_line in enumerate(text.splitlines(), start=1):
        code, bang, comment = raw_line.partition("!")
        comment = comment.lstrip("-").strip() if bang else ""
        last_comments: list[str] | None = None
        last_index = -1
        for char in code:
            if char in ",;":
                value = "".join(current).strip()
                current = []
                if not tokens and value == "":
                    continue  # a stray separator outside any object
                tokens.append(value)
                comments.append("")
                last_comments, last_index = comments, len(comments) - 1
                if char == ";":
                    finished.append((tokens, comments, start_line))
                    tokens, comments = [], []
            else:
                if not tokens and not current and char.isspace():
                    continue
                if not tokens and not current:
                    start_line = line_number
                current.append(char)
        if comment and last_comments is not None:
            last_comments[last_index] = comment
        if current:
            current.append(" ")  # a line break inside a field is whitespace
    if tokens or "".join(current).strip():
        name = tokens[0] if tokens else "".join(current).strip()
        raise ThermocalInputError(
            f"{source}: the object '{name}' starting at line {start_line} is not terminated by "
            "';' before the end of the file; add the missing semicolon."
        )
    return [
        IdfObject(
            class_name=toks[0],
            fields=tuple(toks[1:]),
            comments=tuple(coms[1:]),
            line=line,
            source=source,
        )
        for toks, coms, line in finished
    ]


def read_idf_objects(path: str | Path) -> list[IdfObject]:
    """Read an IDF file into a list of :class:`IdfObject` (see :func:`parse_idf`).

    Parameters
    ----------
    path : str or Path
        IDF file (UTF-8; Latin-1 accepted as a fallback).
    """
    path = Path(path)
    if not path.exists():
        raise ThermocalInputError(f"IDF file {path} does not exist; check the path.")
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    return parse_idf(text, source=path.name)


# ------------------------------------------------------------------------------------------------
# 2. Schema of the supported classes
# ------------------------------------------------------------------------------------------------

#: Field names of the supported classes (after the class name), upper-case class -> (fixed field
#: names, name of the repeated group or None, size of the repeated group). Names follow the
#: EnergyPlus IDD in snake case. Layout variants between versions are handled in :func:`record`.
SCHEMA: dict[str, tuple[tuple[str, ...], str | None, int]] = {
    "VERSION": (("version_identifier",), None, 0),
    "BUILDING": (
        (
            "name",
            "north_axis",
            "terrain",
            "loads_convergence_tolerance",
            "temperature_convergence_tolerance",
            "solar_distribution",
            "maximum_warmup_days",
            "minimum_warmup_days",
        ),
        None,
        0,
    ),
    "GLOBALGEOMETRYRULES": (
        (
            "starting_vertex_position",
            "vertex_entry_direction",
            "coordinate_system",
            "daylighting_reference_point_coordinate_system",
            "rectangular_surface_coordinate_system",
        ),
        None,
        0,
    ),
    "SITE:LOCATION": (("name", "latitude", "longitude", "time_zone", "elevation"), None, 0),
    "SITE:GROUNDTEMPERATURE:BUILDINGSURFACE": (
        tuple(
            f"{m}_ground_temperature"
            for m in (
                "january",
                "february",
                "march",
                "april",
                "may",
                "june",
                "july",
                "august",
                "september",
                "october",
                "november",
                "december",
            )
        ),
        None,
        0,
    ),
    "ZONE": (
        (
            "name",
            "direction_of_relative_north",
            "x_origin",
            "y_origin",
            "z_origin",
            "type",
            "multiplier",
            "ceiling_height",
            "volume",
            "floor_area",
            "zone_inside_convection_algorithm",
            "zone_outside_convection_algorithm",
            "part_of_total_floor_area",
        ),
        None,
        0,
    ),
    "ZONELIST": (("name",), "zone_names", 1),
    "BUILDINGSURFACE:DETAILED": (
        (
            "name",
            "surface_type",
            "construction_name",
            "zone_name",
            "outside_boundary_condition",
            "outside_boundary_condition_object",
            "sun_exposure",
            "wind_exposure",
            "view_factor_to_ground",
            "number_of_vertices",
        ),
        "vertices",
        3,
    ),
    "WALL:DETAILED": (
        (
            "name",
            "construction_name",
            "zone_name",
            "outside_boundary_condition",
            "outside_boundary_condition_object",
            "sun_exposure",
            "wind_exposure",
            "view_factor_to_ground",
            "number_of_vertices",
        ),
        "vertices",
        3,
    ),
    "FENESTRATIONSURFACE:DETAILED": (
        (
            "name",
            "surface_type",
            "construction_name",
            "building_surface_name",
            "outside_boundary_condition_object",
            "view_factor_to_ground",
            "frame_and_divider_name",
            "multiplier",
            "number_of_vertices",
        ),
        "vertices",
        3,
    ),
    "MATERIAL": (
        (
            "name",
            "roughness",
            "thickness",
            "conductivity",
            "density",
            "specific_heat",
            "thermal_absorptance",
            "solar_absorptance",
            "visible_absorptance",
        ),
        None,
        0,
    ),
    "MATERIAL:NOMASS": (
        (
            "name",
            "roughness",
            "thermal_resistance",
            "thermal_absorptance",
            "solar_absorptance",
            "visible_absorptance",
        ),
        None,
        0,
    ),
    "MATERIAL:AIRGAP": (("name", "thermal_resistance"), None, 0),
    "CONSTRUCTION": (("name",), "layers", 1),
    "WINDOWMATERIAL:SIMPLEGLAZINGSYSTEM": (
        ("name", "u_factor", "solar_heat_gain_coefficient", "visible_transmittance"),
        None,
        0,
    ),
    "WINDOWMATERIAL:GLAZING": (
        (
            "name",
            "optical_data_type",
            "window_glass_spectral_data_set_name",
            "thickness",
            "solar_transmittance",
            "front_solar_reflectance",
            "back_solar_reflectance",
            "visible_transmittance",
            "front_visible_reflectance",
            "back_visible_reflectance",
            "infrared_transmittance",
            "front_infrared_emissivity",
            "back_infrared_emissivity",
            "conductivity",
            "dirt_correction_factor",
            "solar_diffusing",
        ),
        None,
        0,
    ),
    "WINDOWMATERIAL:GAS": (
        (
            "name",
            "gas_type",
            "thickness",
            "conductivity_coefficient_a",
            "conductivity_coefficient_b",
            "conductivity_coefficient_c",
            "viscosity_coefficient_a",
            "viscosity_coefficient_b",
            "viscosity_coefficient_c",
            "specific_heat_coefficient_a",
            "specific_heat_coefficient_b",
            "specific_heat_coefficient_c",
            "molecular_weight",
            "specific_heat_ratio",
        ),
        None,
        0,
    ),
    "ZONEINFILTRATION:DESIGNFLOWRATE": (
        (
            "name",
            "zone_name",
            "schedule_name",
            "design_flow_rate_calculation_method",
            "design_flow_rate",
            "flow_per_zone_floor_area",
            "flow_per_exterior_surface_area",
            "air_changes_per_hour",
            "constant_term_coefficient",
            "temperature_term_coefficient",
            "velocity_term_coefficient",
            "velocity_squared_term_coefficient",
        ),
        None,
        0,
    ),
    "OTHEREQUIPMENT": (
        (
            "name",
            "fuel_type",
            "zone_name",
            "schedule_name",
            "design_level_calculation_method",
            "design_level",
            "power_per_zone_floor_area",
            "power_per_person",
            "fraction_latent",
            "fraction_radiant",
            "fraction_lost",
        ),
        None,
        0,
    ),
    "ELECTRICEQUIPMENT": (
        (
            "name",
            "zone_name",
            "schedule_name",
            "design_level_calculation_method",
            "design_level",
            "power_per_zone_floor_area",
            "power_per_person",
            "fraction_latent",
            "fraction_radiant",
            "fraction_lost",
        ),
        None,
        0,
    ),
    "LIGHTS": (
        (
            "name",
            "zone_name",
            "schedule_name",
            "design_level_calculation_method",
            "design_level",
            "power_per_zone_floor_area",
            "power_per_person",
            "return_air_fraction",
            "fraction_radiant",
            "fraction_visible",
            "fraction_replaceable",
        ),
        None,
        0,
    ),
    "PEOPLE": (
        (
            "name",
            "zone_name",
            "number_of_people_schedule_name",
            "number_of_people_calculation_method",
            "number_of_people",
            "people_per_zone_floor_area",
            "zone_floor_area_per_person",
            "fraction_radiant",
            "sensible_heat_fraction",
            "activity_level_schedule_name",
        ),
        None,
        0,
    ),
    "ZONECONTROL:THERMOSTAT": (
        ("name", "zone_name", "control_type_schedule_name"),
        "controls",
        2,
    ),
    "THERMOSTATSETPOINT:DUALSETPOINT": (
        (
            "name",
            "heating_setpoint_temperature_schedule_name",
            "cooling_setpoint_temperature_schedule_name",
        ),
        None,
        0,
    ),
    "THERMOSTATSETPOINT:SINGLEHEATING": (
        ("name", "setpoint_temperature_schedule_name"),
        None,
        0,
    ),
    "THERMOSTATSETPOINT:SINGLECOOLING": (
        ("name", "setpoint_temperature_schedule_name"),
        None,
        0,
    ),
    "THERMOSTATSETPOINT:SINGLEHEATINGORCOOLING": (
        ("name", "setpoint_temperature_schedule_name"),
        None,
        0,
    ),
    "HVACTEMPLATE:THERMOSTAT": (
        (
            "name",
            "heating_setpoint_schedule_name",
            "constant_heating_setpoint",
            "cooling_setpoint_schedule_name",
            "constant_cooling_setpoint",
        ),
        None,
        0,
    ),
    "HVACTEMPLATE:ZONE:IDEALLOADSAIRSYSTEM": (
        ("zone_name", "template_thermostat_name"),
        "other_fields",
        1,
    ),
    "SCHEDULE:CONSTANT": (("name", "schedule_type_limits_name", "hourly_value"), None, 0),
    "SCHEDULE:COMPACT": (("name", "schedule_type_limits_name"), "compact_fields", 1),
    "SCHEDULE:YEAR": (("name", "schedule_type_limits_name"), "week_periods", 5),
    "SCHEDULE:WEEK:DAILY": (
        (
            "name",
            "sunday",
            "monday",
            "tuesday",
            "wednesday",
            "thursday",
            "friday",
            "saturday",
            "holiday",
            "summer_design_day",
            "winter_design_day",
            "custom_day_1",
            "custom_day_2",
        ),
        None,
        0,
    ),
    "SCHEDULE:DAY:INTERVAL": (
        ("name", "schedule_type_limits_name", "interpolate_to_timestep"),
        "time_value_pairs",
        2,
    ),
    "SCHEDULE:DAY:HOURLY": (("name", "schedule_type_limits_name"), "hourly_values", 1),
}

#: Surface classes with the shape of BuildingSurface:Detailed but an implied surface type.
_SURFACE_CLASS_TYPE = {
    "WALL:DETAILED": "Wall",
    "ROOFCEILING:DETAILED": "Roof",
    "FLOOR:DETAILED": "Floor",
}
SCHEMA["ROOFCEILING:DETAILED"] = SCHEMA["WALL:DETAILED"]
SCHEMA["FLOOR:DETAILED"] = SCHEMA["WALL:DETAILED"]

_BOUNDARY_CONDITIONS = {
    "OUTDOORS",
    "GROUND",
    "SURFACE",
    "ZONE",
    "ADIABATIC",
    "OTHERSIDECOEFFICIENTS",
    "OTHERSIDECONDITIONSMODEL",
    "FOUNDATION",
    "GROUNDFCFACTORMETHOD",
    "GROUNDSLABPREPROCESSORAVERAGE",
    "GROUNDSLABPREPROCESSORCORE",
    "GROUNDSLABPREPROCESSORPERIMETER",
    "GROUNDBASEMENTPREPROCESSORAVERAGEWALL",
    "GROUNDBASEMENTPREPROCESSORAVERAGEFLOOR",
    "GROUNDBASEMENTPREPROCESSORUPPERWALL",
    "GROUNDBASEMENTPREPROCESSORLOWERWALL",
}

_FUEL_TYPES = {
    "NONE",
    "ELECTRICITY",
    "NATURALGAS",
    "GAS",
    "PROPANE",
    "PROPANEGAS",
    "FUELOILNO1",
    "FUELOILNO2",
    "FUELOIL#1",
    "FUELOIL#2",
    "DIESEL",
    "GASOLINE",
    "COAL",
    "STEAM",
    "DISTRICTHEATING",
    "DISTRICTHEATINGWATER",
    "DISTRICTHEATINGSTEAM",
    "DISTRICTCOOLING",
    "OTHERFUEL1",
    "OTHERFUEL2",
}


def _version_tuple(objects: Iterable[IdfObject]) -> tuple[int, int]:
    for obj in objects:
        if obj.key == "VERSION" and obj.fields:
            parts = obj.fields[0].split(".")
            try:
                major = int(parts[0])
                minor = int(parts[1]) if len(parts) > 1 and parts[1] else 0
            except ValueError:
                break
            return major, minor
    return (9, 3)


def record(obj: IdfObject, *, version: tuple[int, int] = (9, 3)) -> dict:
    """Name the fields of a supported object.

    Parameters
    ----------
    obj : IdfObject
        Object of a class listed in :data:`SCHEMA`.
    version : tuple of int
        EnergyPlus version of the file (``Version`` object), used where field layouts changed.

    Returns
    -------
    dict
        ``{field_name: raw string}`` for the fixed fields present (blank fields as ""), plus the
        repeated group under its name as a list of tuples (e.g. ``"vertices"`` -> list of 3-tuples
        of strings, ``"layers"`` -> list of 1-tuples), ``"_object"`` -> the object itself.

    Notes
    -----
    Layout variants handled: the ``Space Name`` field that newer EnergyPlus versions insert after
    ``Zone Name`` in surfaces (detected because the field after it must be an outside boundary
    condition); the ``Shading Control Name`` field of ``FenestrationSurface:Detailed`` before
    version 9.0; ``OtherEquipment`` files written before the ``Fuel Type`` field existed
    (detected from the content of the second field).
    """
    key = obj.key
    if key not in SCHEMA:
        raise KeyError(f"no schema for class {obj.class_name}")
    names, group_name, group_size = SCHEMA[key]
    names = list(names)
    fields = list(obj.fields)
    if key in ("BUILDINGSURFACE:DETAILED", *_SURFACE_CLASS_TYPE):
        zone_index = names.index("zone_name")
        bc_index = zone_index + 1
        if (
            len(fields) > bc_index + 1
            and fields[bc_index].upper() not in _BOUNDARY_CONDITIONS
            and fields[bc_index + 1].upper() in _BOUNDARY_CONDITIONS
        ):
            names.insert(bc_index, "space_name")
    elif key == "FENESTRATIONSURFACE:DETAILED" and version < (9, 0):
        names.insert(names.index("view_factor_to_ground") + 1, "shading_control_name")
    elif key == "OTHEREQUIPMENT" and len(fields) > 1 and fields[1].upper() not in _FUEL_TYPES:
        names.remove("fuel_type")
    out: dict = {"_object": obj}
    n_fixed = len(names)
    for index, name in enumerate(names):
        out[name] = fields[index] if index < len(fields) else ""
    if group_name is not None:
        rest = fields[n_fixed:]
        # drop trailing blank fields (IDF editors pad extensible groups)
        while rest and rest[-1] == "":
            rest.pop()
        groups = [tuple(rest[i : i + group_size]) for i in range(0, len(rest), group_size)]
        out[group_name] = groups
    return out


def _number(rec: dict, name: str, *, default: float | None = None, required: bool = True) -> float:
    """Float value of a named field, with an error naming the object and field when invalid."""
    obj: IdfObject = rec["_object"]
    raw = rec.get(name, "")
    if raw == "" or raw.upper() in ("AUTOCALCULATE", "AUTOSIZE"):
        if default is not None or not required:
            return default  # type: ignore[return-value]
        raise ThermocalInputError(
            f"{obj.where()}: field '{_label(name)}' is blank but required; give a number."
        )
    try:
        value = float(raw)
    except ValueError:
        raise ThermocalInputError(
            f"{obj.where()}: field '{_label(name)}' = '{raw}' is not a number."
        ) from None
    if not math.isfinite(value):
        raise ThermocalInputError(f"{obj.where()}: field '{_label(name)}' = '{raw}' is not finite.")
    return value


def _is_auto(rec: dict, name: str) -> bool:
    raw = rec.get(name, "")
    return raw == "" or raw.upper() in ("AUTOCALCULATE", "AUTOSIZE")


def _label(name: str) -> str:
    return name.replace("_", " ").title()


# ------------------------------------------------------------------------------------------------
# 3. Geometry
# ------------------------------------------------------------------------------------------------


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
    nxt = np.roll(v, -1, axis=0)
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
    """

    starting_vertex_position: str = "UpperLeftCorner"
    vertex_entry_direction: str = "Counterclockwise"
    coordinate_system: str = "Relative"

    @property
    def clockwise(self) -> bool:
        return self.vertex_entry_direction.upper() == "CLOCKWISE"

    @property
    def relative(self) -> bool:
        return self.coordinate_system.upper() == "RELATIVE"


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
    coordinates the vertices are used as given and both rotations are ignored (EnergyPlus
    Input Output Reference, GlobalGeometryRules and Building/North Axis).
    """
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    if not rules.relative:
        return v.copy()
    building = _rotate_z(v, zone_north_axis) + np.asarray(zone_origin, dtype=float)
    return _rotate_z(building, building_north_axis)


def outward_normal(vertices_world: np.ndarray, rules: GeometryRules) -> np.ndarray:
    """Outward (away from the zone) normal with length 2 x area, honouring the vertex order."""
    n = newell_normal(vertices_world)
    return -n if rules.clockwise else n


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
    """True if every polygon edge is shared, in opposite direction, by another polygon.

    Parameters
    ----------
    polygons : sequence of arrays (n_i, 3) [m]
        With consistent orientation (all outward normals by the same vertex rule).
    decimals : int
        Vertex coordinates are rounded to this many decimals [m] before matching.
    """
    edges: Counter = Counter()
    for poly in polygons:
        p = [tuple(np.round(np.asarray(v, dtype=float), decimals) + 0.0) for v in poly]
        for a, b in zip(p, p[1:] + p[:1], strict=True):
            edges[(a, b)] += 1
    for (a, b), count in edges.items():
        if edges.get((b, a), 0) != count:
            return False
    return True
