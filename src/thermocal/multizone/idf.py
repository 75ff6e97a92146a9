"""EnergyPlus IDF import: tokenizer, a small schema, surface geometry, mapping to a Building.

The importer covers the envelope subset of EnergyPlus input that the multi-zone model represents:
``Zone``, ``BuildingSurface:Detailed`` (and its ``Wall/RoofCeiling/Floor:Detailed`` siblings),
``FenestrationSurface:Detailed``, ``Material``, ``Material:NoMass``, ``Material:AirGap``,
``Construction``, ``WindowMaterial:SimpleGlazingSystem``, ``WindowMaterial:Glazing`` +
``WindowMaterial:Gas`` (layered glazing, optics by :mod:`thermocal.multizone.glazing`),
``ZoneInfiltration:DesignFlowRate``, ``Site:Location``, ``Site:GroundTemperature:BuildingSurface``,
``GlobalGeometryRules``, ``Building`` (north axis), ``ZoneList``, ``InternalMass`` (adiabatic
surfaces), the internal gains
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
import warnings
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
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
    """IDF objects the importer does not represent (listed, never silently dropped)."""


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
    "INTERNALMASS": (("name", "construction_name", "zone_name", "surface_area"), None, 0),
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
    "SURFACECONVECTIONALGORITHM:INSIDE": (("algorithm",), None, 0),
    "SURFACECONVECTIONALGORITHM:OUTSIDE": (("algorithm",), None, 0),
    "SHADOWCALCULATION": ((), "fields", 1),  # layouts differ by version: read by content
    "TIMESTEP": (("number_of_timesteps_per_hour",), None, 0),
    "RUNPERIOD": ((), "fields", 1),  # layouts differ by version: read by position
    "SHADING:ZONE:DETAILED": (
        ("name", "base_surface_name", "transmittance_schedule_name", "number_of_vertices"),
        "vertices",
        3,
    ),
    "SHADING:BUILDING:DETAILED": (
        ("name", "transmittance_schedule_name", "number_of_vertices"),
        "vertices",
        3,
    ),
    "SHADING:SITE:DETAILED": (
        ("name", "transmittance_schedule_name", "number_of_vertices"),
        "vertices",
        3,
    ),
    "SHADING:OVERHANG": (
        (
            "name",
            "window_or_door_name",
            "height_above_window_or_door",
            "tilt_angle_from_window_door",
            "left_extension_from_window_door_width",
            "right_extension_from_window_door_width",
            "depth",
        ),
        None,
        0,
    ),
    "SHADING:OVERHANG:PROJECTION": (
        (
            "name",
            "window_or_door_name",
            "height_above_window_or_door",
            "tilt_angle_from_window_door",
            "left_extension_from_window_door_width",
            "right_extension_from_window_door_width",
            "depth_as_fraction_of_window_door_height",
        ),
        None,
        0,
    ),
    "SHADING:FIN": (
        (
            "name",
            "window_or_door_name",
            "left_extension_from_window_door",
            "left_distance_above_top_of_window",
            "left_distance_below_bottom_of_window",
            "left_tilt_angle_from_window_door",
            "left_depth",
            "right_extension_from_window_door",
            "right_distance_above_top_of_window",
            "right_distance_below_bottom_of_window",
            "right_tilt_angle_from_window_door",
            "right_depth",
        ),
        None,
        0,
    ),
    "SHADING:FIN:PROJECTION": (
        (
            "name",
            "window_or_door_name",
            "left_extension_from_window_door",
            "left_distance_above_top_of_window",
            "left_distance_below_bottom_of_window",
            "left_tilt_angle_from_window_door",
            "left_depth_as_fraction_of_window_door_width",
            "right_extension_from_window_door",
            "right_distance_above_top_of_window",
            "right_distance_below_bottom_of_window",
            "right_tilt_angle_from_window_door",
            "right_depth_as_fraction_of_window_door_width",
        ),
        None,
        0,
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
    "SCHEDULE:WEEK:COMPACT": (("name",), "day_rules", 2),
    "SCHEDULE:DAY:LIST": (
        ("name", "schedule_type_limits_name", "interpolate_to_timestep", "minutes_per_item"),
        "values",
        1,
    ),
    "SCHEDULE:FILE": (
        (
            "name",
            "schedule_type_limits_name",
            "file_name",
            "column_number",
            "rows_to_skip_at_top",
            "number_of_hours_of_data",
            "column_separator",
            "interpolate_to_timestep",
            "minutes_per_item",
            "adjust_schedule_for_daylight_savings",
            "translate_file_with_relative_path",
        ),
        None,
        0,
    ),
    "RUNPERIODCONTROL:SPECIALDAYS": (
        ("name", "start_date", "duration", "special_day_type"),
        None,
        0,
    ),
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

#: Design-level methods of OtherEquipment, used to tell the layouts with and without Fuel Type.
_EQUIPMENT_METHODS = {"EQUIPMENTLEVEL", "POWER/AREA", "POWER/PERSON", "WATTS/AREA", "WATTS/PERSON"}


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
    elif key == "INTERNALMASS" and len(fields) > 4:
        names.insert(3, "space_name")  # newer versions: Zone or ZoneList, Space or SpaceList
    elif (
        key == "OTHEREQUIPMENT"
        and len(fields) > 3
        and fields[3].upper() in _EQUIPMENT_METHODS
        and not (len(fields) > 4 and fields[4].upper() in _EQUIPMENT_METHODS)
    ):
        names.remove("fuel_type")  # written before the Fuel Type field existed
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


def _field_float(raw: str, obj: IdfObject, label: str) -> float:
    """Float of a raw field of an extensible group, with an error naming the object."""
    try:
        return float(raw)
    except ValueError:
        raise ThermocalInputError(f"{obj.where()}: {label} '{raw}' is not a number.") from None


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
    coordinates the vertices are used as given and both rotations are ignored (EnergyPlus IDD,
    BuildingSurface:Detailed note: "If world, then building and zone origins are used for some
    internal calculations, but all coordinates are given in an 'absolute' system").
    """
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    if not rules.relative:
        return v.copy()
    building = _rotate_z(v, zone_north_axis) + np.asarray(zone_origin, dtype=float)
    return _rotate_z(building, building_north_axis)


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


# ------------------------------------------------------------------------------------------------
# 4. Schedules
# ------------------------------------------------------------------------------------------------

#: Day types of EnergyPlus week schedules, in Schedule:Week:Daily field order.
DAY_TYPES = (
    "SUNDAY",
    "MONDAY",
    "TUESDAY",
    "WEDNESDAY",
    "THURSDAY",
    "FRIDAY",
    "SATURDAY",
    "HOLIDAY",
    "SUMMERDESIGNDAY",
    "WINTERDESIGNDAY",
    "CUSTOMDAY1",
    "CUSTOMDAY2",
)
_SCHEDULE_CLASSES = (
    "SCHEDULE:CONSTANT",
    "SCHEDULE:COMPACT",
    "SCHEDULE:YEAR",
    "SCHEDULE:WEEK:DAILY",
    "SCHEDULE:DAY:INTERVAL",
    "SCHEDULE:DAY:HOURLY",
    "SCHEDULE:WEEK:COMPACT",
    "SCHEDULE:DAY:LIST",
    "SCHEDULE:FILE",
)
_MINUTES_PER_DAY = 1440


class UnsupportedScheduleError(ThermocalInputError):
    """A referenced schedule cannot be evaluated (missing or of an unsupported class)."""


def _parse_time(text: str, where: str) -> int:
    """'hh:mm' -> minutes after midnight (1..1440)."""
    try:
        hours, _, minutes = text.strip().partition(":")
        value = int(hours) * 60 + int(minutes or 0)
    except ValueError:
        raise ThermocalInputError(f"{where}: time '{text}' is not hh:mm.") from None
    if not 0 < value <= _MINUTES_PER_DAY:
        raise ThermocalInputError(f"{where}: time '{text}' is outside 00:01..24:00.")
    return value


class ScheduleEvaluator:
    """Evaluates the schedules of an IDF file over a calendar year.

    Supported: ``Schedule:Constant``, ``Schedule:Compact`` (Through/For/Interpolate/Until),
    ``Schedule:Year`` with ``Schedule:Week:Daily`` / ``Schedule:Week:Compact`` and
    ``Schedule:Day:Interval`` / ``Schedule:Day:Hourly`` / ``Schedule:Day:List``, and
    ``Schedule:File``. ``Interpolate`` ``Average`` (``Yes``) and ``No`` hold each value over its
    interval (the step mean of :meth:`on_grid` is EnergyPlus' average); ``Linear`` ramps over each
    interval from the previous value (:func:`~thermocal.multizone.idf_schedules.interval_profile`).
    Special days of ``RunPeriodControl:SpecialDays`` (Holiday, SummerDesignDay, WinterDesignDay,
    CustomDay1/2) replace the weekday of their dates; holidays of the weather file are not read.

    Parameters
    ----------
    objects : iterable of IdfObject
        All objects of the file (the schedule and special-day classes are picked out).
    year : int
        Calendar year for day-of-week and leap-year handling.
    base_dir : Path or None
        Folder against which relative ``Schedule:File`` names are resolved (the IDF's folder).
    """

    def __init__(
        self,
        objects: Iterable[IdfObject],
        year: int = 2006,
        version=(9, 3),
        base_dir: Path | None = None,
    ):
        import datetime as _dt

        from thermocal.multizone import idf_schedules as _sched

        self.year = year
        self.base_dir = Path(base_dir) if base_dir is not None else Path.cwd()
        self._records: dict[str, dict] = {}
        special: list[dict] = []
        for obj in objects:
            if obj.key in _SCHEDULE_CLASSES:
                self._records[obj.name.upper()] = record(obj, version=version)
            elif obj.key == "RUNPERIODCONTROL:SPECIALDAYS":
                special.append(record(obj, version=version))
        first = _dt.date(year, 1, 1)
        n_days = (_dt.date(year + 1, 1, 1) - first).days
        self.n_days = n_days
        self._day_type = np.array(
            [((first + _dt.timedelta(days=d)).weekday() + 1) % 7 for d in range(n_days)]
        )
        #: Day of year -> special day type name, from RunPeriodControl:SpecialDays.
        self.special_days: dict[int, str] = {}
        for rec in special:
            where = rec["_object"].where()
            kind = (rec["special_day_type"] or "Holiday").replace(" ", "").upper()
            if kind not in DAY_TYPES[7:]:
                raise ThermocalInputError(
                    f"{where}: field 'Special Day Type' = '{rec['special_day_type']}' must be "
                    "Holiday, SummerDesignDay, WinterDesignDay, CustomDay1 or CustomDay2."
                )
            start = (_sched.special_day(rec["start_date"], year, where) - first).days
            duration = int(_number(rec, "duration", default=1.0))
            if duration < 1:
                raise ThermocalInputError(
                    f"{where}: field 'Duration' = {duration} must be 1 or more."
                )
            for d in range(start, min(start + duration, n_days)):
                self._day_type[d] = DAY_TYPES.index(kind)
                self.special_days[d] = kind
        self._month_day = [
            ((first + _dt.timedelta(days=d)).month, (first + _dt.timedelta(days=d)).day)
            for d in range(n_days)
        ]
        self._cache: dict[str, np.ndarray] = {}
        #: schedule name -> days (bool, n_days) interpolated 'Average' (step mean)
        self._average_days: dict[str, np.ndarray] = {}

    def __contains__(self, name: str) -> bool:
        return name.upper() in self._records

    def _doy(self, month: int, day: int, where: str) -> int:
        import datetime as _dt

        try:
            return (_dt.date(self.year, month, day) - _dt.date(self.year, 1, 1)).days
        except ValueError:
            if month == 2 and day == 29:  # Feb 29 in a non-leap year: end of February
                return (_dt.date(self.year, 2, 28) - _dt.date(self.year, 1, 1)).days
            raise ThermocalInputError(f"{where}: invalid date {month}/{day}.") from None

    def minutes(self, name: str) -> np.ndarray:
        """Values at one-minute resolution over the year, shape (n_days, 1440)."""
        key = name.upper()
        if key in self._cache:
            return self._cache[key]
        rec = self._records.get(key)
        if rec is None:
            raise UnsupportedScheduleError(
                f"schedule '{name}' is not defined by a supported schedule object "
                f"({', '.join(c.title() for c in _SCHEDULE_CLASSES)})."
            )
        obj: IdfObject = rec["_object"]
        if obj.key == "SCHEDULE:CONSTANT":
            value = _number(rec, "hourly_value", default=0.0)
            out = np.full((self.n_days, _MINUTES_PER_DAY), value)
        elif obj.key == "SCHEDULE:COMPACT":
            out = self._compact(rec)
        elif obj.key == "SCHEDULE:YEAR":
            out = self._year(rec)
        elif obj.key == "SCHEDULE:FILE":
            out = self._file(rec)
        else:
            raise UnsupportedScheduleError(
                f"{obj.where()} is a day/week schedule and cannot be used as a full schedule."
            )
        self._cache[key] = out
        return out

    def on_grid(self, name: str, times, step) -> np.ndarray:
        """Value of each simulation step ``[t, t + step)`` as EnergyPlus gives it [schedule unit].

        Parameters
        ----------
        name : str
            Schedule name.
        times : pandas.DatetimeIndex
            Step starts (local standard time, as the weather file). Each is placed in the
            schedule calendar by its month, day and time of day (the day of week and holidays
            come from the calendar year of the import, as EnergyPlus takes them from the
            RunPeriod); February 29 of a leap grid year takes February 28's values in a common
            calendar year.
        step : pandas.Timedelta

        Returns
        -------
        numpy.ndarray, shape (len(times),)

        Notes
        -----
        As EnergyPlus: the value at the step's end (its last minute) for ``Interpolate`` ``No``
        (the default) and ``Linear``, the mean over the step for ``Average``. For a step
        function and steps that tile the ``Until`` times both are the interval value.
        """
        import pandas as pd

        key = ("grid", name.upper(), len(times), times[0], pd.Timedelta(step))
        if key in self._cache:
            return self._cache[key]
        flat = self.minutes(name).ravel()
        width = max(int(round(pd.Timedelta(step).total_seconds() / 60.0)), 1)
        cumulative = np.concatenate(([0.0], np.cumsum(np.concatenate((flat, flat[:1440])))))
        index = self.minute_index(times)
        out = np.concatenate((flat, flat[:1440]))[index + width - 1]
        average = self._average_days.get(name.upper())
        if average is not None and average.any():
            mean = (cumulative[index + width] - cumulative[index]) / width
            day = np.minimum(index // _MINUTES_PER_DAY, self.n_days - 1)
            out = np.where(average[day], mean, out)
        self._cache[key] = out
        return out

    def minute_index(self, times) -> np.ndarray:
        """Minute of the schedule year of each time (by month, day, hour, minute)."""
        import datetime as _dt

        import pandas as pd

        times = pd.DatetimeIndex(times)
        first = _dt.date(self.year, 1, 1).toordinal()
        month = times.month.to_numpy()
        day = times.day.to_numpy()
        leap = (self.year % 4 == 0 and self.year % 100 != 0) or self.year % 400 == 0
        day = np.where((month == 2) & (day == 29) & (not leap), 28, day)
        month_start = np.array(
            [_dt.date(self.year, m, 1).toordinal() - first for m in range(1, 13)]
        )
        doy = month_start[month - 1] + day - 1
        minute = times.hour.to_numpy() * 60 + times.minute.to_numpy()
        return doy * _MINUTES_PER_DAY + minute

    def hourly(self, name: str) -> np.ndarray:
        """Hourly mean values over the year, shape (n_days * 24,)."""
        return self.minutes(name).reshape(self.n_days * 24, 60).mean(axis=1)

    def annual_mean(self, name: str) -> float:
        """Time-weighted mean over the year."""
        return float(self.minutes(name).mean())

    def mode(self, name: str) -> float:
        """The value in effect for the largest share of the year."""
        values, counts = np.unique(self.minutes(name), return_counts=True)
        return float(values[np.argmax(counts)])

    def value_range(self, name: str) -> tuple[float, float]:
        """Minimum and maximum value over the year."""
        m = self.minutes(name)
        return float(m.min()), float(m.max())

    # -- compact ---------------------------------------------------------------------------------
    def _compact(self, rec: dict) -> np.ndarray:
        from thermocal.multizone import idf_schedules as _sched

        obj: IdfObject = rec["_object"]
        where = obj.where()
        tokens = [t[0] for t in rec["compact_fields"]]
        out = np.full((self.n_days, _MINUTES_PER_DAY), np.nan)
        average = self._average_days[obj.name.upper()] = np.zeros(self.n_days, dtype=bool)
        block_start = 0
        assigned: dict[int, np.ndarray] = {}
        targets: list[int] = []
        untils: list[int] = []
        values: list[float] = []
        pending_until: int | None = None
        block_end: int | None = None

        kind = "no"

        def finish_day():
            nonlocal untils, values, targets, kind
            if targets:
                profile = _sched.interval_profile(untils, values, where, kind)
                for t in targets:
                    assigned.setdefault(t, profile)
            targets, untils, values, kind = [], [], [], "no"

        def finish_block():
            nonlocal assigned, block_start
            finish_day()
            if block_end is None:
                return
            for d in range(block_start, block_end + 1):
                profile = assigned.get(int(self._day_type[d]))
                if profile is None:
                    raise ThermocalInputError(
                        f"{where}: no 'For:' rule covers {DAY_TYPES[self._day_type[d]].title()}s "
                        f"(day {d + 1} of the year); add 'For: AllOtherDays'."
                    )
                out[d] = profile
                average[d] = getattr(profile, "average", False)
            block_start = block_end + 1
            assigned = {}

        for token in tokens:
            head, colon, rest = token.partition(":")
            keyword = head.strip().upper() if colon else ""
            if keyword == "THROUGH":
                finish_block()
                month, _, day = rest.strip().partition("/")
                try:
                    block_end = self._doy(int(month), int(day), where)
                except ValueError:
                    raise ThermocalInputError(f"{where}: bad date in '{token}'.") from None
            elif keyword == "FOR":
                finish_day()
                targets = self._day_types(rest, assigned, where)
            elif keyword == "INTERPOLATE":
                kind = _sched.interpolation_kind(rest, f"{where}, field '{token}'")
            elif keyword == "UNTIL":
                time_text = rest.strip()
                # "Until: 24:00" -> rest is "24:00" (partition splits at the first colon only)
                pending_until = _parse_time(time_text, where)
            else:
                try:
                    value = float(token)
                except ValueError:
                    raise ThermocalInputError(
                        f"{where}: unexpected field '{token}' (expected Through:/For:/Until: or a "
                        "number)."
                    ) from None
                if pending_until is None:
                    raise ThermocalInputError(f"{where}: value {token} without a preceding Until.")
                untils.append(pending_until)
                values.append(value)
                pending_until = None
        finish_block()
        if block_start < self.n_days:
            raise ThermocalInputError(f"{where}: the last 'Through:' must be 12/31.")
        return out

    @staticmethod
    def _day_types(text: str, assigned: dict, where: str) -> list[int]:
        result: list[int] = []
        for word in text.split():
            w = word.upper()
            if w == "ALLDAYS":
                result += list(range(12))
            elif w == "WEEKDAYS":
                result += [1, 2, 3, 4, 5]
            elif w in ("WEEKENDS", "WEEKEND"):
                result += [0, 6]
            elif w in ("HOLIDAY", "HOLIDAYS"):
                result.append(7)
            elif w == "ALLOTHERDAYS":
                result += [i for i in range(12) if i not in assigned and i not in result]
            elif w in DAY_TYPES:
                result.append(DAY_TYPES.index(w))
            else:
                raise ThermocalInputError(f"{where}: unknown day type '{word}' in 'For:'.")
        return result

    # -- year/week/day ---------------------------------------------------------------------------
    def _day_object(self, name: str, where: str) -> np.ndarray:
        rec = self._records.get(name.upper())
        if rec is None:
            raise UnsupportedScheduleError(f"{where}: day schedule '{name}' is not defined.")
        from thermocal.multizone import idf_schedules as _sched

        obj: IdfObject = rec["_object"]
        if obj.key == "SCHEDULE:DAY:INTERVAL":
            pairs = rec["time_value_pairs"]
            untils = [_parse_time(t, obj.where()) for t, *_ in pairs]
            values = [_field_float(v[0] if v else "0", obj, "value") for _, *v in pairs]
            kind = _sched.interpolation_kind(rec["interpolate_to_timestep"], obj.where())
            return _sched.interval_profile(untils, values, obj.where(), kind)
        if obj.key == "SCHEDULE:DAY:LIST":
            values = [_field_float(v[0], obj, "value") for v in rec["values"]]
            kind = _sched.interpolation_kind(rec["interpolate_to_timestep"], obj.where())
            minutes = int(_number(rec, "minutes_per_item", default=60.0))
            return _sched.list_profile(values, minutes, obj.where(), kind)
        if obj.key == "SCHEDULE:DAY:HOURLY":
            values = [float(v[0]) for v in rec["hourly_values"]]
            if len(values) != 24:
                raise ThermocalInputError(f"{obj.where()}: needs 24 hourly values.")
            return np.repeat(values, 60)
        raise UnsupportedScheduleError(f"{where}: '{name}' is not a day schedule.")

    def _year(self, rec: dict) -> np.ndarray:
        obj: IdfObject = rec["_object"]
        where = obj.where()
        out = np.full((self.n_days, _MINUTES_PER_DAY), np.nan)
        average = self._average_days[obj.name.upper()] = np.zeros(self.n_days, dtype=bool)
        for group in rec["week_periods"]:
            if len(group) < 5:
                raise ThermocalInputError(f"{where}: incomplete week period {group}.")
            week_name, m1, d1, m2, d2 = group[:5]
            start = self._doy(int(float(m1)), int(float(d1)), where)
            end = self._doy(int(float(m2)), int(float(d2)), where)
            profiles = self._week(week_name, where)
            for d in range(start, end + 1):
                out[d] = profiles[int(self._day_type[d])]
                average[d] = getattr(profiles[int(self._day_type[d])], "average", False)
        if np.isnan(out).any():
            raise ThermocalInputError(f"{where}: the week periods do not cover the whole year.")
        return out

    def _week(self, week_name: str, where: str) -> list[np.ndarray]:
        """Day profiles of a week schedule, one per day type (:data:`DAY_TYPES` order)."""
        week = self._records.get(week_name.upper())
        kind = week["_object"].key if week is not None else ""
        if kind == "SCHEDULE:WEEK:DAILY":
            wwhere = week["_object"].where()
            names = SCHEMA["SCHEDULE:WEEK:DAILY"][0][1:]
            cache: dict[str, np.ndarray] = {}
            profiles = []
            for n in names:
                day_name = week[n]
                if not day_name:
                    raise ThermocalInputError(
                        f"{wwhere}: field '{_label(n)} Schedule:Day Name' is blank."
                    )
                if day_name.upper() not in cache:
                    cache[day_name.upper()] = self._day_object(day_name, wwhere)
                profiles.append(cache[day_name.upper()])
            return profiles
        if kind == "SCHEDULE:WEEK:COMPACT":
            wwhere = week["_object"].where()
            assigned: dict[int, np.ndarray] = {}
            for group in week["day_rules"]:
                if len(group) < 2 or not group[1]:
                    raise ThermocalInputError(
                        f"{wwhere}: day type list '{group[0]}' has no Schedule:Day name."
                    )
                text = group[0]
                head, colon, rest = text.partition(":")
                if colon and head.strip().upper() == "FOR":
                    text = rest
                profile = self._day_object(group[1], wwhere)
                for t in self._day_types(text, assigned, wwhere):
                    assigned.setdefault(t, profile)
            missing = [DAY_TYPES[i].title() for i in range(len(DAY_TYPES)) if i not in assigned]
            if missing:
                raise ThermocalInputError(
                    f"{wwhere}: no day type list covers {', '.join(missing)}; add AllOtherDays."
                )
            return [assigned[i] for i in range(len(DAY_TYPES))]
        raise UnsupportedScheduleError(
            f"{where}: week schedule '{week_name}' is not a Schedule:Week:Daily or "
            "Schedule:Week:Compact."
        )

    def _file(self, rec: dict) -> np.ndarray:
        import calendar

        from thermocal.multizone import idf_schedules as _sched

        obj: IdfObject = rec["_object"]
        where = obj.where()
        name = rec["file_name"]
        if not name:
            raise ThermocalInputError(f"{where}: field 'File Name' is blank.")
        path = Path(name)
        if not path.is_absolute():
            path = self.base_dir / path
        kind = _sched.interpolation_kind(rec["interpolate_to_timestep"], where)
        self._average_days[obj.name.upper()] = np.full(self.n_days, kind == "average")
        return _sched.file_profile(
            path,
            column=int(_number(rec, "column_number")),
            rows_to_skip=int(_number(rec, "rows_to_skip_at_top", default=0.0)),
            separator=rec["column_separator"],
            minutes_per_item=int(_number(rec, "minutes_per_item", default=60.0)),
            n_days=self.n_days,
            leap=calendar.isleap(self.year),
            kind=kind,
            where=where,
        )


# ------------------------------------------------------------------------------------------------
# 5. Mapping to the multi-zone Building
# ------------------------------------------------------------------------------------------------

#: Reference wind speed [m/s] at which the wind terms of ZoneInfiltration:DesignFlowRate are
#: evaluated when converting to a constant air-change rate: 4.47 m/s (10 mph), the speed at which
#: the DOE-2 coefficient set (A, B, C, D) = (0, 0, 0.224, 0) gives the design flow.
INFILTRATION_REFERENCE_WIND_SPEED = 4.47

#: Angles [deg] of the angular optics tables handed to the WindowType.
WINDOW_TABLE_ANGLES = tuple(float(a) for a in range(0, 91, 5))

#: Sensible heat per person [-] of People objects with an autocalculated sensible fraction.
DEFAULT_PEOPLE_SENSIBLE_FRACTION = 0.6

#: Zone temperature [C] at which the autocalculated People sensible heat is evaluated.
PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE = 22.0

#: EnergyPlus default ground temperature [C] when Site:GroundTemperature:BuildingSurface is absent.
ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE = 18.0


@dataclass
class InternalGainInfo:
    """One internal-gain object of the file, resolved for one zone.

    Attributes
    ----------
    object_class, name, zone : str
    design_level : float [W]
        Sensible design level (latent and lost fractions removed).
    radiant_fraction : float [-]
        Radiant (long-wave + visible) share of the sensible gain.
    schedule : str or None
        Fraction schedule (People: number-of-people schedule).
    annual_mean : float [W]
        ``design_level`` x time-weighted annual mean of the schedule.
    """

    object_class: str
    name: str
    zone: str
    design_level: float
    radiant_fraction: float
    schedule: str | None
    annual_mean: float
    people_count: float = 0.0
    activity_schedule: str | None = None
    sensible_fraction: float | None = None
    latent_level: float = 0.0


def people_sensible_heat(activity, temperature=PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE):
    """Sensible heat per person [W] of EnergyPlus' autocalculated People sensible fraction.

    Parameters
    ----------
    activity : float or ndarray [W/person]
        Total metabolic heat (the Activity Level schedule).
    temperature : float or ndarray [C]
        Zone air temperature.

    References
    ----------
    EnergyPlus Engineering Reference, "People" (sensible heat gain from occupants, polynomial
    fit of the ASHRAE Handbook table).
    """
    m = np.asarray(activity, dtype=float)
    t = np.asarray(temperature, dtype=float)
    value = (
        6.461927
        + 0.946892 * m
        + 0.0000255737 * m**2
        + 7.139322 * t
        - 0.0627909 * t * m
        + 0.0000589172 * t * m**2
        - 0.198550 * t**2
        + 0.000940018 * t**2 * m
        - 0.00000149532 * t**2 * m**2
    )
    return np.clip(value, 0.0, m)


@dataclass
class InfiltrationInfo:
    """One ``ZoneInfiltration:DesignFlowRate`` object resolved for one zone.

    The flow is ``design_flow x schedule x (A + B |T_zone - T_out| + C v + D v^2)`` with ``v``
    the wind speed at the zone's centroid height (EnergyPlus' zone local wind speed).

    Attributes
    ----------
    name, zone : str
    design_flow : float [m3/s]
    schedule : str or None
    coefficients : tuple of float
        ``(A, B, C, D)``: constant [-], temperature [1/K], wind [s/m], wind squared [s2/m2].
    """

    name: str
    zone: str
    design_flow: float
    schedule: str | None
    coefficients: tuple[float, float, float, float]


#: Wind boundary-layer exponent and thickness [m] per terrain (EnergyPlus ``Building`` field
#: Terrain; ASHRAE Handbook of Fundamentals 2005, ch. 16, Table 1).
TERRAIN_WIND_PROFILE = {
    "COUNTRY": (0.14, 270.0),
    "SUBURBS": (0.22, 370.0),
    "CITY": (0.33, 460.0),
    "OCEAN": (0.10, 210.0),
    "URBAN": (0.22, 370.0),
}
#: Weather station: exponent, boundary-layer thickness [m], anemometer height [m].
WEATHER_STATION_WIND_PROFILE = (0.14, 270.0, 10.0)


def local_wind_factor(height: float, terrain: str = "Suburbs") -> float:
    """Ratio of the wind speed at ``height`` [m] to the weather station's [-] (EnergyPlus).

    ``(delta_met / z_met)^a_met x (z / delta)^a`` with the terrain's exponent ``a`` and
    boundary-layer thickness ``delta``; 0 at or below the ground.
    """
    a, delta = TERRAIN_WIND_PROFILE.get(terrain.upper(), TERRAIN_WIND_PROFILE["SUBURBS"])
    a_met, delta_met, z_met = WEATHER_STATION_WIND_PROFILE
    if height <= 0.0:
        return 0.0
    return (delta_met / z_met) ** a_met * (height / delta) ** a


@dataclass
class ScheduledInputs:
    """The file's schedules evaluated on a simulation grid (rows = steps, columns = zones).

    Attributes
    ----------
    heating_setpoint, cooling_setpoint : ndarray [C]
        NaN where a zone has no such set point.
    gains_convective, gains_radiant : ndarray [W]
        Sensible internal gains entering the zone air / the zone's surfaces.
    gains_latent : ndarray [W]
        Latent gains (reported, not part of the sensible balance).
    infiltration_ach : ndarray [1/h]
        Air changes from the schedule and the constant and wind terms.
    infiltration_ach_per_kelvin : ndarray [1/(h K)]
        Temperature term: air changes per kelvin of ``|T_zone - T_out|`` (applied in the time
        loop with the zone temperature of the previous step, as EnergyPlus does).
    """

    heating_setpoint: np.ndarray
    cooling_setpoint: np.ndarray
    gains_convective: np.ndarray
    gains_radiant: np.ndarray
    gains_latent: np.ndarray
    infiltration_ach: np.ndarray
    infiltration_ach_per_kelvin: np.ndarray


@dataclass
class IdfImportInfo:
    """What the importer read, derived or approximated; attached to the Building as ``idf_info``.

    Attributes
    ----------
    source : str
        File path.
    version : tuple of int
    unsupported : dict
        ``{class name: count}`` of the objects not represented (also in the warning).
    notes : list of str
        Approximations made (time-varying schedules reduced to constants, ...).
    surface_vertices : dict
        ``{surface or window name: (n, 3) array}`` world coordinates [m] (x east, y north, z up).
    surface_types : dict
        ``{surface name: EnergyPlus surface type}`` (Wall, Floor, Roof, Ceiling, Door, Window, ...).
    glazing : dict
        ``{window construction name: LayeredGlazing or SimpleGlazing}``.
    internal_gains : list of InternalGainInfo
    setpoint_schedules : dict
        ``{zone: (heating schedule or None, cooling schedule or None)}``.
    infiltration_schedules : dict
        ``{zone: [schedule names]}``.
    zone_multipliers : dict
        ``{zone: multiplier}`` (EnergyPlus zone multiplier; not applied by the model).
    schedules : ScheduleEvaluator
    """

    source: str
    version: tuple[int, int]
    unsupported: dict[str, int] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    surface_vertices: dict[str, np.ndarray] = field(default_factory=dict)
    surface_types: dict[str, str] = field(default_factory=dict)
    glazing: dict = field(default_factory=dict)
    internal_gains: list[InternalGainInfo] = field(default_factory=list)
    setpoint_schedules: dict[str, tuple[str | None, str | None]] = field(default_factory=dict)
    infiltration_schedules: dict[str, list[str]] = field(default_factory=dict)
    zone_multipliers: dict[str, float] = field(default_factory=dict)
    schedules: ScheduleEvaluator | None = None
    infiltration: list[InfiltrationInfo] = field(default_factory=list)
    zone_wind_factor: dict[str, float] = field(default_factory=dict)
    zone_nominal_ach: dict[str, float] = field(default_factory=dict)
    zone_volume: dict[str, float] = field(default_factory=dict)
    run_period: tuple | None = None  # (name, begin month, day, end month, day, begin year|None)
    #: ``Timestep``: steps per hour of the file (EnergyPlus' default 6 when absent)
    timesteps_per_hour: int | None = None
    shading_surfaces: list = field(default_factory=list)  # shading.ShadingSurface
    subsurfaces_of: dict[str, list[str]] = field(default_factory=dict)  # host -> windows, doors
    #: ShadowCalculation: sunlit fractions of the first day reused for this many days (EnergyPlus'
    #: "Periodic" default 20); 0 = every time step ("Timestep")
    shadow_update_days: int = 20
    #: SurfaceConvectionAlgorithm:Inside / :Outside as written ({"inside": "TARP", ...})
    convection: dict[str, str] = field(default_factory=dict)

    def network_options(self):
        """NetworkOptions honouring the file's convection algorithms, and notes on fallbacks."""
        from thermocal.multizone.network import NetworkOptions

        notes = []
        inside = self.convection.get("inside", "TARP")
        outside = self.convection.get("outside", "DOE-2")
        interior = {"TARP": "tarp", "SIMPLE": "simple"}.get(inside.upper())
        if interior is None:
            interior = "tarp"
            notes.append(f"SurfaceConvectionAlgorithm:Inside {inside} is not available: TARP used")
        exterior = {"DOE-2": "doe2", "SIMPLECOMBINED": "simple_combined"}.get(outside.upper())
        if exterior is None:
            exterior = "doe2"
            notes.append(
                f"SurfaceConvectionAlgorithm:Outside {outside} is not available: DOE-2 used"
            )
        return NetworkOptions(interior_convection=interior, exterior_convection=exterior), notes

    def scheduled_inputs(self, zones, times, step, weather) -> ScheduledInputs:
        """Set points, internal gains and infiltration of every zone on a simulation grid.

        Parameters
        ----------
        zones : sequence of str
            Column order.
        times : pandas.DatetimeIndex
            Step starts.
        step : pandas.Timedelta
        weather : pandas.DataFrame
            The weather on the grid (``wind_speed`` [m/s] used when present).

        Returns
        -------
        ScheduledInputs
        """
        n, nz = len(times), len(zones)
        column = {z: i for i, z in enumerate(zones)}
        sched = self.schedules

        def values(name):
            return np.ones(n) if name is None else sched.on_grid(name, times, step)

        heating = np.full((n, nz), np.nan)
        cooling = np.full((n, nz), np.nan)
        for zone, (heat_name, cool_name) in self.setpoint_schedules.items():
            if zone not in column:
                continue
            if heat_name:
                heating[:, column[zone]] = values(heat_name)
            if cool_name:
                cooling[:, column[zone]] = values(cool_name)
        convective = np.zeros((n, nz))
        radiant = np.zeros((n, nz))
        latent = np.zeros((n, nz))
        for gain in self.internal_gains:
            if gain.zone not in column:
                continue
            fraction = values(gain.schedule)
            if gain.people_count > 0 and gain.activity_schedule is not None:
                # People: number x (sensible heat per person at the step's activity)
                activity = sched.on_grid(gain.activity_schedule, times, step)
                if gain.sensible_fraction is None:
                    sensible = people_sensible_heat(activity)
                else:
                    sensible = activity * gain.sensible_fraction
                level = gain.people_count * fraction * sensible
                lat = gain.people_count * fraction * (activity - sensible)
            else:
                level = gain.design_level * fraction
                lat = gain.latent_level * fraction
            c = column[gain.zone]
            radiant[:, c] += level * gain.radiant_fraction
            convective[:, c] += level * (1.0 - gain.radiant_fraction)
            latent[:, c] += lat
        wind = (
            np.nan_to_num(weather["wind_speed"].to_numpy(dtype=float))
            if "wind_speed" in weather
            else np.zeros(n)
        )
        ach = np.zeros((n, nz))
        ach_dt = np.zeros((n, nz))
        for inf in self.infiltration:
            if inf.zone not in column:
                continue
            c = column[inf.zone]
            a, b, c_wind, d = inf.coefficients
            v = wind * self.zone_wind_factor.get(inf.zone, 1.0)
            base = inf.design_flow * 3600.0 / self.zone_volume[inf.zone] * values(inf.schedule)
            ach[:, c] += base * (a + c_wind * v + d * v * v)
            ach_dt[:, c] += base * b
        return ScheduledInputs(heating, cooling, convective, radiant, latent, ach, ach_dt)

    def internal_gains_profile(self, times) -> pd.DataFrame:  # noqa: F821 (pandas lazily)
        """Hourly internal sensible gains per zone [W] from the file's schedules.

        Parameters
        ----------
        times : pandas.DatetimeIndex
            Evaluation times; each takes the value of the hour of the year it falls in (the
            schedule calendar year is reused for every year).

        Returns
        -------
        pandas.DataFrame [W], one column per zone with gains.

        Notes
        -----
        The imported zones already carry the annual mean of these gains as the constant
        ``Zone.internal_gains``; to simulate the hourly profile instead, set those to 0 and pass
        the profile as heat input (otherwise the gains are counted twice).
        """
        import pandas as pd

        hour_of_year = _hour_of_year(times, self.schedules.n_days)
        out = {}
        for gain in self.internal_gains:
            values = (
                np.ones(self.schedules.n_days * 24)
                if gain.schedule is None
                else self.schedules.hourly(gain.schedule)
            )
            series = gain.design_level * values[hour_of_year]
            out[gain.zone] = out.get(gain.zone, 0.0) + series
        return pd.DataFrame(out, index=times)

    def setpoint_profile(self, times) -> pd.DataFrame:  # noqa: F821
        """Hourly heating and cooling set points [C], columns ``(zone, "heating"|"cooling")``."""
        import pandas as pd

        hour_of_year = _hour_of_year(times, self.schedules.n_days)
        out = {}
        for zone, (heating, cooling) in self.setpoint_schedules.items():
            for kind, name in (("heating", heating), ("cooling", cooling)):
                if name is not None:
                    out[(zone, kind)] = self.schedules.hourly(name)[hour_of_year]
        return pd.DataFrame(out, index=times)


def _hour_of_year(times, n_days: int) -> np.ndarray:
    import pandas as pd

    times = pd.DatetimeIndex(times)
    hours = (times.day_of_year.to_numpy() - 1) * 24 + times.hour.to_numpy()
    return np.minimum(hours, n_days * 24 - 1)


class _Names:
    """Case-insensitive name registry of one kind of object (EnergyPlus names ignore case)."""

    def __init__(self, kind: str):
        self.kind = kind
        self.items: dict[str, tuple[str, IdfObject, dict]] = {}

    def add(self, rec: dict) -> None:
        obj: IdfObject = rec["_object"]
        name = rec.get("name", obj.name)
        if not name:
            raise ThermocalInputError(f"{obj.where()}: the Name field is blank.")
        key = name.upper()
        if key in self.items:
            first = self.items[key][1]
            raise ThermocalInputError(
                f"{obj.where()}: the name '{name}' is already used by {first.where()}; "
                f"{self.kind} names must be unique (EnergyPlus ignores case)."
            )
        self.items[key] = (name, obj, rec)

    def get(self, name: str):
        return self.items.get(name.upper())

    def __contains__(self, name: str) -> bool:
        return name.upper() in self.items

    def values(self):
        return self.items.values()


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


def _wrap(obj: IdfObject, factory, *args, **kwargs):
    """Build a model object; prefix its validation error with the IDF object's identity."""
    try:
        return factory(*args, **kwargs)
    except ThermocalInputError as exc:
        raise ThermocalInputError(f"{obj.where()}: {exc}") from None


#: Mean glazing temperatures [C] at which the glass-to-glass conductance of layered glazing is
#: tabulated (the simulation interpolates, and holds the end values outside).
GLASS_CONDUCTANCE_TEMPERATURES = tuple(float(t) for t in range(-40, 101, 10))


def window_type_from_glazing(name: str, glazing, *, angles=WINDOW_TABLE_ANGLES):
    """:class:`~thermocal.multizone.model.WindowType` from layered or simple glazing.

    Parameters
    ----------
    name : str
        Window type (construction) name.
    glazing : LayeredGlazing or SimpleGlazing
    angles : sequence of float [deg]
        Incidence angles of the angular tables.

    Notes
    -----
    ``u_value`` is the NFRC winter centre-of-glass U-factor incl. films (EnergyPlus reports the
    same quantity; its film resistances, about 0.034 + 0.136 m2 K/W, are close to the ISO 6946
    0.04 + 0.13 the model removes to get the glass-to-glass resistance). With gas gaps, the
    glass-to-glass conductance relative to its NFRC winter value is tabulated against the mean
    glazing temperature (:meth:`LayeredGlazing.glass_conductance_ratio`), so the simulation
    follows the temperature dependence of the gap as EnergyPlus' window heat balance does.
    ``shgc`` is the NFRC
    summer SHGC at normal incidence. Transmittance and per-pane absorptances are tabulated
    against the angle of incidence; their hemispherical averages give the diffuse values.
    For simple glazing the equivalent layer follows the EnergyPlus angular curves (A-J, chosen
    by U-factor and SHGC).
    """
    from thermocal.multizone import glazing as gz
    from thermocal.multizone.model import WindowType

    if isinstance(glazing, gz.SimpleGlazing):
        system = gz.LayeredGlazing([glazing.as_pane(name)], [], name=name)
        u_value, shgc = glazing.u_factor, glazing.shgc
    else:
        system = glazing
        u_value, shgc = system.u_value(), system.shgc(0.0)
    angles = np.asarray(angles, dtype=float)
    tau, _, absorbed = system.optics(angles)
    tau0 = float(tau[0])
    relative = tau / tau0 if tau0 > 0 else np.zeros_like(tau)
    return WindowType(
        name=name,
        u_value=float(u_value),
        shgc=float(shgc),
        solar_transmittance=tau0,
        pane_absorptances=tuple(float(a) for a in absorbed[0]),
        incidence_angles=tuple(angles),
        relative_transmittance=tuple(float(r) for r in relative),
        pane_absorptances_angular=absorbed,
        diffuse_transmittance=float(system.diffuse_transmittance),
        diffuse_pane_absorptances=tuple(float(a) for a in system.diffuse_absorptance),
        n_panes=len(system.panes),
        emissivity_outside=system.panes[0].front_emissivity,
        emissivity_inside=system.panes[-1].back_emissivity,
        glass_conductance_temperatures=GLASS_CONDUCTANCE_TEMPERATURES if system.gaps else None,
        glass_conductance_ratio=tuple(
            float(r) for r in system.glass_conductance_ratio(GLASS_CONDUCTANCE_TEMPERATURES)
        )
        if system.gaps
        else None,
    )


def read_idf(path: str | Path, *, year: int | None = None):
    """Read the envelope of an EnergyPlus IDF file into a multi-zone Building.

    Parameters
    ----------
    path : str or Path
        IDF file.
    year : int or None
        Calendar year used to evaluate schedules (day of week); default: the RunPeriod's begin
        year, else 2006 (starts on a Sunday, the EnergyPlus default start day).

    Returns
    -------
    thermocal.multizone.model.Building
        With an extra attribute ``idf_info`` (:class:`IdfImportInfo`) holding geometry, schedules
        and the approximations made. Objects not represented are listed in one
        :class:`IdfImportWarning`.

    Raises
    ------
    ThermocalInputError
        Naming the object (class, name, file line) and the field at fault.

    Notes
    -----
    Mapping decisions:

    * Surface areas and orientations come from the vertices (see :func:`to_world_coordinates`);
      ``Surface.area`` is the gross area (windows included), opaque doors become surfaces of
      their own (their area is removed from the host).
    * Zone floor area (if not given) is the sum of the zone's Floor surfaces; volume (if not given)
      comes from the closed surface polyhedron, else floor area x ceiling height.
    * Infiltration: design flow rate (Flow/Zone, Flow/Area, Flow/ExteriorArea,
      Flow/ExteriorWallArea, AirChanges/Hour) x (A + C v + D v^2) at
      :data:`INFILTRATION_REFERENCE_WIND_SPEED` -> air changes per hour; the schedule and
      temperature term are not represented (noted).
    * Internal gains: sensible design level x the schedule's annual mean -> constant
      ``Zone.internal_gains``; the hourly profile is available from
      ``building.idf_info.internal_gains_profile(times)`` (pass it as heat input).
    * Thermostats: constant set-point schedules map exactly; time-varying ones are represented
      by the value in effect for most of the year (noted; hourly values from
      ``idf_info.setpoint_profile``). HVAC systems are not modelled: thermostatted zones get ideal
      heating/cooling at these set points.
    """
    return _IdfReader(Path(path), year).build()


class _IdfReader:
    """One import by :func:`read_idf`: the file's objects, lookups and the stages of the mapping.

    Each ``_stage`` method reads one group of classes and stores what later stages need as
    attributes (materials, constructions, zones, surfaces, ...); :meth:`build` runs them in order.
    """

    def __init__(self, path: Path, year: int | None):
        from thermocal.multizone import glazing as gz
        from thermocal.multizone import model as mz

        self.gz, self.mz = gz, mz
        self.path = Path(path)
        self.year = year
        self.objects = read_idf_objects(self.path)
        self.version = _version_tuple(self.objects)
        self.info = IdfImportInfo(source=str(self.path), version=self.version)
        self.by_key: dict[str, list[IdfObject]] = {}
        for obj in self.objects:
            self.by_key.setdefault(obj.key, []).append(obj)

    def records(self, *keys):
        """Named-field records of all objects of the given (upper-case) classes."""
        for key in keys:
            for obj in self.by_key.get(key, []):
                yield record(obj, version=self.version)

    def single(self, key):
        """Record of the only object of a class (None when absent; error when repeated)."""
        found = self.by_key.get(key, [])
        if len(found) > 1:
            raise ThermocalInputError(
                f"{found[1].where()}: only one {found[1].class_name} object is allowed."
            )
        return record(found[0], version=self.version) if found else None

    def zone_targets(self, rec: dict) -> list[str]:
        """Zones named by a 'Zone or ZoneList Name' field."""
        obj = rec["_object"]
        target = rec["zone_name"]
        entry = self.zones.get(target)
        if entry is not None:
            return [entry[0]]
        if target.upper() in self.zone_lists:
            return self.zone_lists[target.upper()]
        raise ThermocalInputError(
            f"{obj.where()}: field 'Zone or ZoneList Name' = '{target}' is neither a Zone nor a "
            "ZoneList of the file."
        )

    def build(self):
        """Run the stages and return the Building (with ``idf_info``)."""
        self._unsupported_classes()
        self._site()
        self._materials()
        self._constructions()
        self._zones()
        self._surfaces()
        self._subsurfaces()
        self._shading()
        self._model_surfaces()
        self._zone_volumes()
        self._infiltration()
        self._internal_gains()
        self._setpoints()
        self._model_zones()
        self._ground()
        return self._building()

    def _unsupported_classes(self) -> None:
        """Stage: unsupported classes."""
        unsupported = Counter(obj.class_name for obj in self.objects if obj.key not in SCHEMA)
        canonical: dict[str, str] = {}
        for obj in self.objects:
            canonical.setdefault(obj.key, obj.class_name)
        grouped: Counter = Counter()
        for obj in self.objects:
            if obj.key not in SCHEMA:
                grouped[canonical[obj.key]] += 1
        self.info.unsupported = dict(sorted(grouped.items()))
        del unsupported

    def _site(self) -> None:
        """Stage: site, rules, building."""
        building_rec = self.single("BUILDING")
        self.building_name = self.path.stem
        self.north_axis = 0.0
        if building_rec is not None:
            self.building_name = building_rec["name"] or self.building_name
            self.north_axis = _number(building_rec, "north_axis", default=0.0)
        rules_rec = self.single("GLOBALGEOMETRYRULES")
        self.rules = GeometryRules()
        if rules_rec is not None:
            self.rules = GeometryRules(
                rules_rec["starting_vertex_position"] or "UpperLeftCorner",
                rules_rec["vertex_entry_direction"] or "Counterclockwise",
                rules_rec["coordinate_system"] or "Relative",
            )
            if self.rules.vertex_entry_direction.upper() not in ("COUNTERCLOCKWISE", "CLOCKWISE"):
                raise ThermocalInputError(
                    f"{rules_rec['_object'].where()}: field 'Vertex Entry Direction' = "
                    f"'{self.rules.vertex_entry_direction}' must be Counterclockwise or Clockwise."
                )
            if self.rules.coordinate_system.upper() not in ("RELATIVE", "WORLD", "ABSOLUTE"):
                raise ThermocalInputError(
                    f"{rules_rec['_object'].where()}: field 'Coordinate System' = "
                    f"'{self.rules.coordinate_system}' must be Relative, World or Absolute."
                )
        self.location = self.mz.Location()
        loc_rec = self.single("SITE:LOCATION")
        if loc_rec is not None:
            self.location = _wrap(
                loc_rec["_object"],
                self.mz.Location,
                latitude=_number(loc_rec, "latitude", default=0.0),
                longitude=_number(loc_rec, "longitude", default=0.0),
                altitude=_number(loc_rec, "elevation", default=0.0),
                timezone=_number(loc_rec, "time_zone", default=0.0),
            )
        else:
            self.info.notes.append("no Site:Location: the model's default location is used")
        timestep = self.single("TIMESTEP")
        if timestep is not None:
            per_hour = _number(timestep, "number_of_timesteps_per_hour", default=6.0)
            divisors = (1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30, 60)
            if not 1 <= per_hour <= 60:
                raise ThermocalInputError(
                    f"{timestep['_object'].where()}: field 'Number of Timesteps per Hour' = "
                    f"{per_hour:g}: give 1 to 60 (a divisor of 60: 1, 2, 3, 4, 5, 6, 10, 12, "
                    "15, 20, 30 or 60)"
                )
            if per_hour not in divisors:
                chosen = min(d for d in divisors if d >= per_hour)
                self.info.notes.append(
                    f"{timestep['_object'].where()}: {per_hour:g} timesteps per hour do not "
                    f"divide an hour; {chosen} per hour used"
                )
                per_hour = chosen
            self.info.timesteps_per_hour = int(per_hour)
        for rp in self.by_key.get("RUNPERIOD", [])[:1]:
            # Name, Begin Month, Begin Day, Begin Year, End Month, End Day (9.x and later)
            f = [x.strip() for x in rp.fields] + [""] * 6
            try:
                begin_year = int(float(f[3])) if f[3] else None
                self.info.run_period = (
                    f[0],
                    int(float(f[1])),
                    int(float(f[2])),
                    int(float(f[4])),
                    int(float(f[5])),
                    begin_year,
                )
            except ValueError:
                raise ThermocalInputError(
                    f"{rp.where()}: the begin/end month and day fields must be numbers."
                ) from None
        if self.year is None:
            self.year = 2006
            for rp in self.by_key.get("RUNPERIOD", [])[:1]:
                # 9.x layout: Name, Begin Month, Begin Day, Begin Year, End Month, End Day,
                # End Year, Day of Week for Start Day, ...
                f = [x.strip() for x in rp.fields] + [""] * 8
                if f[3]:
                    try:
                        self.year = int(float(f[3]))
                    except ValueError:
                        pass
                elif self.version >= (9, 0) and f[7].upper() != "USEWEATHERFILE":
                    # no year: EnergyPlus starts on the given day of week (Sunday when blank)
                    from thermocal.multizone.idf_schedules import year_for_start_day

                    self.year = year_for_start_day(
                        int(float(f[1] or 1)), int(float(f[2] or 1)), f[7] or "Sunday", rp.where()
                    )
                elif self.version >= (9, 0) and f[7]:
                    self.info.notes.append(
                        f"{rp.where()}: 'Day of Week for Start Day' = {f[7]}: weekdays of 2006 used"
                    )
        for rp in self.by_key.get("RUNPERIOD", [])[:1] if self.version >= (9, 0) else []:
            f = [x.strip().upper() for x in rp.fields] + [""] * 11
            if f[8] in ("", "YES"):
                self.info.notes.append(
                    f"{rp.where()}: 'Use Weather File Holidays and Special Days' = Yes: the "
                    "weather file's holidays are not read (RunPeriodControl:SpecialDays are)"
                )
            if f[10] == "YES":
                self.info.notes.append(
                    f"{rp.where()}: 'Apply Weekend Holiday Rule' = Yes is not applied"
                )
        self.schedules = ScheduleEvaluator(
            self.objects, year=self.year, version=self.version, base_dir=self.path.parent
        )
        self.info.schedules = self.schedules

    def _materials(self) -> None:
        """Stage: materials."""
        self.materials = _Names("material")
        for rec in self.records(
            "MATERIAL",
            "MATERIAL:NOMASS",
            "MATERIAL:AIRGAP",
            "WINDOWMATERIAL:GLAZING",
            "WINDOWMATERIAL:GAS",
            "WINDOWMATERIAL:SIMPLEGLAZINGSYSTEM",
        ):
            self.materials.add(rec)
        self.model_materials = []
        self.glass_layers: dict[str, object] = {}
        for name, obj, rec in self.materials.values():
            key = obj.key
            if key == "MATERIAL":
                self.model_materials.append(
                    _wrap(
                        obj,
                        self.mz.Material,
                        name=name,
                        conductivity=_number(rec, "conductivity"),
                        density=_number(rec, "density"),
                        specific_heat=_number(rec, "specific_heat"),
                        thickness=_number(rec, "thickness"),
                        thermal_absorptance=_number(rec, "thermal_absorptance", default=0.9),
                        solar_absorptance=_number(rec, "solar_absorptance", default=0.7),
                        roughness=rec["roughness"] or None,
                    )
                )
            elif key == "MATERIAL:NOMASS":
                self.model_materials.append(
                    _wrap(
                        obj,
                        self.mz.NoMassMaterial,
                        name=name,
                        resistance=_number(rec, "thermal_resistance"),
                        thermal_absorptance=_number(rec, "thermal_absorptance", default=0.9),
                        solar_absorptance=_number(rec, "solar_absorptance", default=0.7),
                        roughness=rec["roughness"] or None,
                    )
                )
            elif key == "MATERIAL:AIRGAP":
                self.model_materials.append(
                    _wrap(
                        obj,
                        self.mz.NoMassMaterial,
                        name=name,
                        resistance=_number(rec, "thermal_resistance"),
                    )
                )
            elif key == "WINDOWMATERIAL:GLAZING":
                optical = (rec["optical_data_type"] or "SpectralAverage").upper()
                if optical != "SPECTRALAVERAGE":
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Optical Data "
                        f"Type' = '{rec['optical_data_type']}' is "
                        "not supported; give SpectralAverage data."
                    )
                dirt = _number(rec, "dirt_correction_factor", default=1.0) or 1.0
                self.glass_layers[name.upper()] = _wrap(
                    obj,
                    self.gz.GlassPane,
                    thickness=_number(rec, "thickness"),
                    solar_transmittance=_number(rec, "solar_transmittance") * dirt,
                    front_solar_reflectance=_number(rec, "front_solar_reflectance"),
                    back_solar_reflectance=_number(rec, "back_solar_reflectance"),
                    front_emissivity=_number(rec, "front_infrared_emissivity", default=0.84),
                    back_emissivity=_number(rec, "back_infrared_emissivity", default=0.84),
                    conductivity=_number(rec, "conductivity", default=0.9),
                    infrared_transmittance=_number(rec, "infrared_transmittance", default=0.0),
                    name=name,
                )
            elif key == "WINDOWMATERIAL:GAS":
                gas_type = rec["gas_type"] or "Air"
                if gas_type.upper() == "CUSTOM":
                    fill = self.gz.Gas(
                        name,
                        tuple(
                            _number(rec, f"conductivity_coefficient_{c}", default=0.0)
                            for c in "abc"
                        ),
                        tuple(
                            _number(rec, f"viscosity_coefficient_{c}", default=0.0) for c in "abc"
                        ),
                        tuple(
                            _number(rec, f"specific_heat_coefficient_{c}", default=0.0)
                            for c in "abc"
                        ),
                        _number(rec, "molecular_weight"),
                    )
                else:
                    fill = _wrap(obj, self.gz.gas, gas_type)
                self.glass_layers[name.upper()] = _wrap(
                    obj, self.gz.GasGap, thickness=_number(rec, "thickness"), fill=fill, name=name
                )
            else:  # simple glazing
                self.glass_layers[name.upper()] = _wrap(
                    obj,
                    self.gz.simple_glazing_system,
                    _number(rec, "u_factor"),
                    _number(rec, "solar_heat_gain_coefficient"),
                    _number(rec, "visible_transmittance", required=False),
                    name=name,
                )

    def _constructions(self) -> None:
        """Stage: constructions."""
        self.constructions = _Names("construction")
        for rec in self.records("CONSTRUCTION"):
            self.constructions.add(rec)
        self.model_constructions = []
        self.window_types: dict[str, object] = {}
        self.opaque_constructions: set[str] = set()
        for name, obj, rec in self.constructions.values():
            layer_names = [g[0] for g in rec["layers"] if g and g[0]]
            if not layer_names:
                raise ThermocalInputError(f"{obj.where()}: the construction has no layers.")
            resolved = []
            for index, layer in enumerate(layer_names, start=1):
                entry = self.materials.get(layer)
                if entry is None:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Layer {index}' = '{layer}' is not defined (no "
                        "Material, Material:NoMass, Material:AirGap "
                        "or WindowMaterial of that name)."
                    )
                resolved.append(entry)
            kinds = {entry[1].key.startswith("WINDOWMATERIAL") for entry in resolved}
            if kinds == {False}:
                self.model_constructions.append(
                    _wrap(
                        obj, self.mz.Construction, name=name, layers=tuple(e[0] for e in resolved)
                    )
                )
                self.opaque_constructions.add(name.upper())
                continue
            if kinds != {True}:
                raise ThermocalInputError(
                    f"{obj.where()}: mixes opaque materials and window materials; a window "
                    "construction must contain only WindowMaterial layers."
                )
            layers = [self.glass_layers[e[0].upper()] for e in resolved]
            if len(layers) == 1 and isinstance(layers[0], self.gz.SimpleGlazing):
                glazing = layers[0]
            else:
                panes = layers[0::2]
                gaps = layers[1::2]
                if not all(isinstance(p, self.gz.GlassPane) for p in panes) or not all(
                    isinstance(g, self.gz.GasGap) for g in gaps
                ):
                    raise ThermocalInputError(
                        f"{obj.where()}: window layers must alternate WindowMaterial:Glazing and "
                        "WindowMaterial:Gas, starting and ending with glazing (shades, blinds and "
                        "simple glazing inside layered constructions are not supported)."
                    )
                glazing = _wrap(obj, self.gz.LayeredGlazing, panes, gaps, name=name)
            self.info.glazing[name] = glazing
            self.window_types[name.upper()] = (name, obj, glazing)

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

    def _surfaces(self) -> None:
        """Stage: surfaces."""
        self.surfaces = _Names("surface")
        for rec in self.records("BUILDINGSURFACE:DETAILED", *_SURFACE_CLASS_TYPE):
            self.surfaces.add(rec)
        self.fenestration = _Names("fenestration surface")
        for rec in self.records("FENESTRATIONSURFACE:DETAILED"):
            if rec["name"].upper() in self.surfaces:
                raise ThermocalInputError(
                    f"{rec['_object'].where()}: the name is already used by a building surface."
                )
            self.fenestration.add(rec)

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
                    f"{obj.where()}: the vertices enclose zero area (degenerate polygon)."
                )
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
            self.info.surface_vertices[name] = world
            self.info.surface_types[name] = surface_type.title()
        self._check_closed_zones()

    def _check_closed_zones(self) -> None:
        """A surface whose vertices run the wrong way in an otherwise closed zone is refused.

        The area vectors (outward normal x area) of a closed zone sum to zero; when one surface
        is reversed they sum to twice its area vector instead. Zones that are not closed
        (surfaces missing) are left alone: no surface explains their sum.
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
            best = int(np.argmin(misfit))
            if misfit[best] <= 0.01 * np.linalg.norm(vectors[best]):
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
                    f"'{rec['building_surface_name']}' is not a building surface of the file."
                )
            kind = (rec["surface_type"] or "Window").upper()
            geometry = self.zone_geometry[base["zone"].upper()]
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
                    f"{obj.where()}: the vertices enclose zero area (degenerate polygon)."
                )
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
            multiplier = _number(rec, "multiplier", default=1.0)
            total_area = area * multiplier
            self.info.surface_vertices[name] = world
            self.info.surface_types[name] = kind.title()
            cons = rec["construction_name"]
            if kind in ("WINDOW", "GLASSDOOR"):
                wt = self.window_types.get(cons.upper())
                if wt is None:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Construction Name' = '{cons}' is not a window "
                        "construction (Construction of WindowMaterial layers) of the file."
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
        for rec in self.records("SHADING:SITE:DETAILED"):
            found.append(polygon(rec))  # site coordinates: not rotated with the building
        for key in ("SHADING:OVERHANG", "SHADING:OVERHANG:PROJECTION"):
            for rec in self.records(key):
                found.append(self._overhang(rec, projection=key.endswith("PROJECTION")))
        for key in ("SHADING:FIN", "SHADING:FIN:PROJECTION"):
            for rec in self.records(key):
                found.extend(self._fins(rec, projection=key.endswith("PROJECTION")))
        self.info.shading_surfaces = found
        for side in ("inside", "outside"):
            rec = self.single(f"SURFACECONVECTIONALGORITHM:{side.upper()}")
            if rec is not None and rec["algorithm"]:
                self.info.convection[side] = rec["algorithm"]
        rec = self.single("SHADOWCALCULATION")
        if rec is not None:
            values = [f.upper() for (f,) in rec["fields"]]
            numbers = [v for v in values[:4] if v.replace(".", "", 1).isdigit()]
            if any(v in ("TIMESTEP", "TIMESTEPFREQUENCY") for v in values[:3]):
                self.info.shadow_update_days = 0
            elif numbers:
                self.info.shadow_update_days = max(1, int(float(numbers[0])))

    def _window_frame(self, rec):
        """Corner, right and up axes, outward normal, width and height of a window or door."""
        obj = rec["_object"]
        target = rec["window_or_door_name"]
        entry = self.fenestration.get(target)
        if entry is None:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Window or Door Name' = '{target}' is not a "
                "FenestrationSurface:Detailed of the file."
            )
        world = self.info.surface_vertices[entry[0]]
        normal = newell_normal(world)
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

    def _model_surfaces(self) -> None:
        """Stage: model surfaces."""
        self.model_surfaces = []
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
                    boundary = (
                        "adiabatic"  # a surface facing itself: internal mass (EnergyPlus idiom)
                    )
                else:
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
            elif boundary == "unsupported":
                self.info.notes.append(
                    f"surface '{data['name']}': boundary "
                    f"{rec['outside_boundary_condition']} is not "
                    "modelled; treated as adiabatic"
                )
                boundary = "adiabatic"
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
            self.model_surfaces.append(
                _wrap(
                    obj,
                    self.mz.Surface,
                    name=data["name"],
                    zone=data["zone"],
                    area=area,
                    boundary=boundary,
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
                continue
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
                    view_factor_ground=base_surface.view_factor_ground,
                    sun_exposed=base_surface.sun_exposed,
                    wind_exposed=base_surface.wind_exposed,
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
                        sun_exposed=False,
                        wind_exposed=False,
                    )
                )
                self.info.surface_types[mass_name] = "InternalMass"

    def _zone_volumes(self) -> None:
        """Stage: zone areas and volumes."""
        self.zone_floor_area: dict[str, float] = {}
        self.zone_polygons: dict[str, list] = {}
        for data in self.surface_data.values():
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
                    z = np.concatenate([d["world"][:, 2] for d in polys])
                    height = float(z.max() - z.min())
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

    def _infiltration(self) -> None:
        """Stage: infiltration."""
        building_rec = self.single("BUILDING")
        terrain = (building_rec["terrain"] if building_rec is not None else "") or "Suburbs"
        if terrain.upper() not in TERRAIN_WIND_PROFILE:
            raise ThermocalInputError(
                f"{building_rec['_object'].where()}: field 'Terrain' = '{terrain}' is not one of "
                "Country, Suburbs, City, Ocean, Urban."
            )
        moments: dict[str, list[float]] = {}
        for data in self.surface_data.values():
            m = moments.setdefault(data["zone"], [0.0, 0.0])
            m[0] += data["area"] * float(np.mean(data["world"][:, 2]))
            m[1] += data["area"]
        for zone_name, (za, area) in moments.items():
            height = za / area if area > 0 else 0.0
            self.info.zone_wind_factor[zone_name] = local_wind_factor(height, terrain)
        self.info.zone_volume = dict(self.zone_volume)
        self.zone_ach: dict[str, float] = {}
        self.zone_infiltration_group: dict[str, str] = {}
        exterior_area: dict[str, float] = {}
        exterior_wall_area: dict[str, float] = {}
        for data in self.surface_data.values():
            if data["boundary"] == "outdoors":
                exterior_area[data["zone"]] = exterior_area.get(data["zone"], 0.0) + data["area"]
                if data["type"].upper() == "WALL":
                    exterior_wall_area[data["zone"]] = (
                        exterior_wall_area.get(data["zone"], 0.0) + data["area"]
                    )
        for rec in self.records("ZONEINFILTRATION:DESIGNFLOWRATE"):
            obj = rec["_object"]
            method = (rec["design_flow_rate_calculation_method"] or "Flow/Zone").upper()
            coefficients = [
                _number(rec, "constant_term_coefficient", default=1.0 if _all_blank(rec) else 0.0),
                _number(rec, "temperature_term_coefficient", default=0.0),
                _number(rec, "velocity_term_coefficient", default=0.0),
                _number(rec, "velocity_squared_term_coefficient", default=0.0),
            ]
            v = INFILTRATION_REFERENCE_WIND_SPEED
            factor = coefficients[0] + coefficients[2] * v + coefficients[3] * v * v
            targets = self.zone_targets(rec)
            for zone_name in targets:
                volume = self.zone_volume[zone_name]
                if method in ("FLOW/ZONE",):
                    flow = _number(rec, "design_flow_rate")
                elif method == "FLOW/AREA":
                    flow = _number(rec, "flow_per_zone_floor_area") * self.zone_area[zone_name]
                elif method == "FLOW/EXTERIORAREA":
                    flow = _number(rec, "flow_per_exterior_surface_area") * exterior_area.get(
                        zone_name, 0.0
                    )
                elif method == "FLOW/EXTERIORWALLAREA":
                    flow = _number(rec, "flow_per_exterior_surface_area") * exterior_wall_area.get(
                        zone_name, 0.0
                    )
                elif method in ("AIRCHANGES/HOUR", "AIRCHANGESPERHOUR"):
                    flow = _number(rec, "air_changes_per_hour") * volume / 3600.0
                else:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Design Flow Rate Calculation Method' = "
                        f"'{rec['design_flow_rate_calculation_method']}' is not one of Flow/Zone, "
                        "Flow/Area, Flow/ExteriorArea, Flow/ExteriorWallArea, AirChanges/Hour."
                    )
                if flow < 0:
                    raise ThermocalInputError(f"{obj.where()}: the design flow rate is negative.")
                self.zone_ach[zone_name] = (
                    self.zone_ach.get(zone_name, 0.0) + flow * 3600.0 / volume * factor
                )
                self.info.infiltration.append(
                    InfiltrationInfo(
                        rec["name"],
                        zone_name,
                        flow,
                        rec["schedule_name"] or None,
                        tuple(coefficients),
                    )
                )
                if len(targets) > 1:
                    self.zone_infiltration_group[zone_name] = rec["name"]
                schedule = rec["schedule_name"]
                if schedule:
                    self.info.infiltration_schedules.setdefault(zone_name, []).append(schedule)
                    try:
                        low, high = self.schedules.value_range(schedule)
                    except UnsupportedScheduleError:
                        low, high = (math.nan, math.nan)
                    if not (low == high == 1.0):
                        self.info.notes.append(
                            f"infiltration '{rec['name']}' (zone "
                            f"{zone_name}): schedule '{schedule}' "
                            f"(range {low:g}..{high:g}): the constant zone rate "
                            "(schedules='constant') ignores it"
                        )
        self.info.zone_nominal_ach = dict(self.zone_ach)
        for rec in self.records("ZONEINFILTRATION:DESIGNFLOWRATE"):
            coefficients = [
                _number(rec, "constant_term_coefficient", default=1.0 if _all_blank(rec) else 0.0),
                _number(rec, "temperature_term_coefficient", default=0.0),
                _number(rec, "velocity_term_coefficient", default=0.0),
                _number(rec, "velocity_squared_term_coefficient", default=0.0),
            ]
            v = INFILTRATION_REFERENCE_WIND_SPEED
            factor = coefficients[0] + coefficients[2] * v + coefficients[3] * v * v
            if coefficients != [1.0, 0.0, 0.0, 0.0]:
                self.info.notes.append(
                    f"infiltration '{rec['name']}': coefficients (A, B, C, D) = "
                    f"{tuple(coefficients)} evaluated at wind {v} m/s and dT = 0 (factor "
                    f"{factor:.3f}) for the constant zone rate (schedules='constant')"
                )

    def _internal_gains(self) -> None:
        """Stage: internal gains."""
        people_count: dict[str, float] = {}
        for rec in self.records("PEOPLE"):
            for zone_name in self.zone_targets(rec):
                people_count[zone_name] = people_count.get(zone_name, 0.0) + _people_number(
                    rec, self.zone_area[zone_name]
                )
        for key in ("OTHEREQUIPMENT", "ELECTRICEQUIPMENT", "LIGHTS", "PEOPLE"):
            for rec in self.records(key):
                for zone_name in self.zone_targets(rec):
                    gain = _internal_gain(
                        rec,
                        zone_name,
                        self.zone_area[zone_name],
                        people_count.get(zone_name, 0.0),
                        self.schedules,
                    )
                    self.info.internal_gains.append(gain)
        self.zone_gains: dict[str, float] = {}
        self.zone_radiant: dict[str, float] = {}
        for gain in self.info.internal_gains:
            self.zone_gains[gain.zone] = self.zone_gains.get(gain.zone, 0.0) + gain.annual_mean
            self.zone_radiant[gain.zone] = (
                self.zone_radiant.get(gain.zone, 0.0) + gain.annual_mean * gain.radiant_fraction
            )
            if gain.schedule is not None:
                try:
                    low, high = self.schedules.value_range(gain.schedule)
                except UnsupportedScheduleError:
                    low, high = math.nan, math.nan
                if low != high:
                    self.info.notes.append(
                        f"{gain.object_class} '{gain.name}' (zone {gain.zone}): schedule "
                        f"'{gain.schedule}' varies ({low:g}..{high:g}); its annual mean gives the "
                        "constant internal gain of schedules='constant'"
                    )

    def _setpoints(self) -> None:
        """Stage: thermostats."""
        self.setpoints = _thermostats(
            self.records, self.zones, self.zone_lists, self.schedules, self.info
        )
        hvac = sorted(
            cls
            for cls in self.info.unsupported
            if cls.upper().startswith(("ZONEHVAC:", "AIRLOOPHVAC", "AIRTERMINAL:", "PLANTLOOP"))
        )
        if self.setpoints and hvac:
            self.info.notes.append(
                f"HVAC equipment ({', '.join(hvac[:3])}{', ...' if len(hvac) > 3 else ''}) is not "
                "modelled: thermostatted zones get ideal heating/cooling at their set points"
            )

    def _model_zones(self) -> None:
        """Stage: zones."""
        self.model_zones = []
        for name, obj, _rec in self.zones.values():
            heating, cooling = self.setpoints.get(name, (None, None))
            gains = self.zone_gains.get(name, 0.0)
            self.model_zones.append(
                _wrap(
                    obj,
                    self.mz.Zone,
                    name=name,
                    volume=self.zone_volume[name],
                    floor_area=self.zone_area[name],
                    infiltration_ach=self.zone_ach.get(name, 0.0),
                    internal_gains=gains,
                    internal_gains_radiative_fraction=(self.zone_radiant.get(name, 0.0) / gains)
                    if gains > 0
                    else 0.5,
                    heating_setpoint=heating,
                    cooling_setpoint=cooling,
                    infiltration_group=self.zone_infiltration_group.get(name),
                )
            )

    def _ground(self) -> None:
        """Stage: ground."""
        ground_rec = self.single("SITE:GROUNDTEMPERATURE:BUILDINGSURFACE")
        self.ground = None
        if ground_rec is not None:
            self.ground = tuple(
                _number(ground_rec, n, default=ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE)
                for n in SCHEMA["SITE:GROUNDTEMPERATURE:BUILDINGSURFACE"][0]
            )
        elif any(s.boundary == "ground" for s in self.model_surfaces):
            self.ground = (ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE,) * 12
            self.info.notes.append(
                "no Site:GroundTemperature:BuildingSurface: ground surfaces see the EnergyPlus "
                f"default {ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE:g} C"
            )

    def _building(self):
        """Stage: window types; assemble and validate the Building."""
        used_types = {w.window_type.upper() for w in self.model_windows}
        self.model_window_types = [
            _wrap(obj, window_type_from_glazing, name, glazing)
            for key, (name, obj, glazing) in self.window_types.items()
            if key in used_types
        ]
        try:
            building = self.mz.Building(
                name=self.building_name,
                location=self.location,
                materials=self.model_materials,
                constructions=self.model_constructions,
                window_types=self.model_window_types,
                zones=self.model_zones,
                surfaces=self.model_surfaces,
                windows=self.model_windows,
                ground_temperatures=self.ground,
            )
        except ThermocalInputError as exc:
            raise ThermocalInputError(f"{self.path.name}: {exc}") from None
        building.idf_info = self.info
        _warn_unsupported(self.path.name, self.info)
        return building


def _all_blank(rec: dict) -> bool:
    return all(
        rec.get(n, "") == ""
        for n in (
            "constant_term_coefficient",
            "temperature_term_coefficient",
            "velocity_term_coefficient",
            "velocity_squared_term_coefficient",
        )
    )


def _reversed_construction(name, constructions, model_constructions, mz) -> str:
    """Name of the construction with reversed layers (created when needed)."""
    cons = next(c for c in model_constructions if c.name == name)
    if tuple(reversed(cons.layers)) == cons.layers:
        return name
    reversed_name = f"{name} (reversed)"
    if not any(c.name == reversed_name for c in model_constructions):
        model_constructions.append(mz.Construction(reversed_name, tuple(reversed(cons.layers))))
    return reversed_name


def _people_number(rec: dict, floor_area: float) -> float:
    obj = rec["_object"]
    method = (rec["number_of_people_calculation_method"] or "People").upper()
    if method == "PEOPLE":
        return _number(rec, "number_of_people")
    if method == "PEOPLE/AREA":
        return _number(rec, "people_per_zone_floor_area") * floor_area
    if method == "AREA/PERSON":
        per = _number(rec, "zone_floor_area_per_person")
        return floor_area / per if per > 0 else 0.0
    raise ThermocalInputError(
        f"{obj.where()}: field 'Number of People Calculation Method' = "
        f"'{rec['number_of_people_calculation_method']}' is not People, People/Area or Area/Person."
    )


def _internal_gain(rec, zone_name, floor_area, people, schedules) -> InternalGainInfo:
    obj: IdfObject = rec["_object"]
    if obj.key == "PEOPLE":
        count = _people_number(rec, floor_area)
        activity_schedule = rec["activity_level_schedule_name"] or None
        try:
            activity = schedules.annual_mean(activity_schedule) if activity_schedule else 120.0
        except UnsupportedScheduleError as exc:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Activity Level Schedule Name': {exc}"
            ) from None
        if _is_auto(rec, "sensible_heat_fraction"):
            sensible_fraction = None
            sensible = float(people_sensible_heat(activity)) / activity if activity > 0 else 0.0
        else:
            sensible_fraction = sensible = _number(rec, "sensible_heat_fraction")
        design = count * activity * sensible
        latent_level = count * activity * (1.0 - sensible)
        radiant = _number(rec, "fraction_radiant", default=0.3)
        schedule = rec["number_of_people_schedule_name"] or None
    else:
        method = (rec["design_level_calculation_method"] or "").upper()
        if method in ("EQUIPMENTLEVEL", "LIGHTINGLEVEL"):
            level = _number(rec, "design_level")
        elif method in ("WATTS/AREA", "POWER/AREA"):
            level = _number(rec, "power_per_zone_floor_area") * floor_area
        elif method in ("WATTS/PERSON", "POWER/PERSON"):
            level = _number(rec, "power_per_person") * people
        else:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Design Level Calculation Method' = "
                f"'{rec['design_level_calculation_method']}' is not supported."
            )
        if obj.key == "LIGHTS":
            lost = 0.0
            radiant_total = _number(rec, "fraction_radiant", default=0.0) + _number(
                rec, "fraction_visible", default=0.0
            )
        else:
            lost = _number(rec, "fraction_latent", default=0.0) + _number(
                rec, "fraction_lost", default=0.0
            )
            radiant_total = _number(rec, "fraction_radiant", default=0.0)
        sensible_share = max(1.0 - lost, 0.0)
        design = level * sensible_share
        radiant = min(radiant_total / sensible_share, 1.0) if sensible_share > 0 else 0.0
        schedule = rec["schedule_name"] or None
        count = 0.0
        activity_schedule = sensible_fraction = None
        latent_level = level * (
            _number(rec, "fraction_latent", default=0.0) if obj.key != "LIGHTS" else 0.0
        )
    mean_factor = 1.0
    if schedule is not None:
        try:
            mean_factor = schedules.annual_mean(schedule)
        except UnsupportedScheduleError as exc:
            raise ThermocalInputError(f"{obj.where()}: {exc}") from None
    return InternalGainInfo(
        object_class=obj.class_name,
        name=rec["name"],
        zone=zone_name,
        design_level=design,
        radiant_fraction=radiant,
        schedule=schedule,
        annual_mean=design * mean_factor,
        people_count=count,
        activity_schedule=activity_schedule,
        sensible_fraction=sensible_fraction,
        latent_level=latent_level,
    )


def _thermostats(records, zones, zone_lists, schedules, info) -> dict:
    """Zone -> (heating set point, cooling set point) from the thermostat objects."""
    setpoint_objects: dict[str, dict] = {}
    for rec in records(
        "THERMOSTATSETPOINT:DUALSETPOINT",
        "THERMOSTATSETPOINT:SINGLEHEATING",
        "THERMOSTATSETPOINT:SINGLECOOLING",
        "THERMOSTATSETPOINT:SINGLEHEATINGORCOOLING",
    ):
        setpoint_objects[rec["name"].upper()] = rec
    result: dict[str, tuple[float | None, float | None]] = {}

    def constant(schedule: str | None, obj: IdfObject, what: str) -> float | None:
        if not schedule:
            return None
        try:
            low, high = schedules.value_range(schedule)
            value = schedules.mode(schedule)
        except UnsupportedScheduleError as exc:
            raise ThermocalInputError(f"{obj.where()}: {exc}") from None
        if low != high:
            info.notes.append(
                f"{obj.where()}: {what} schedule '{schedule}' varies ({low:g}..{high:g} C); the "
                f"value in effect most of the year ({value:g} C) is the constant set point of "
                "schedules='constant'"
            )
        return value

    for rec in records("ZONECONTROL:THERMOSTAT"):
        obj = rec["_object"]
        target = rec["zone_name"]
        entry = zones.get(target)
        targets = [entry[0]] if entry is not None else zone_lists.get(target.upper())
        if not targets:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Zone or ZoneList Name' = '{target}' is not a zone."
            )
        control_types = {}
        for group in rec["controls"]:
            if len(group) == 2 and group[1]:
                control_types[group[0].upper()] = group[1]
        control_schedule = rec["control_type_schedule_name"]
        try:
            mode = int(round(schedules.mode(control_schedule))) if control_schedule else 4
        except UnsupportedScheduleError as exc:
            raise ThermocalInputError(f"{obj.where()}: {exc}") from None
        wanted = {
            1: "THERMOSTATSETPOINT:SINGLEHEATING",
            2: "THERMOSTATSETPOINT:SINGLECOOLING",
            3: "THERMOSTATSETPOINT:SINGLEHEATINGORCOOLING",
            4: "THERMOSTATSETPOINT:DUALSETPOINT",
        }.get(mode)
        if control_schedule:
            low, high = schedules.value_range(control_schedule)
            if low != high:
                info.notes.append(
                    f"{obj.where()}: control type schedule varies; control type {mode} "
                    "(most of the year) is used"
                )
        name = control_types.get(wanted or "")
        if name is None:
            info.notes.append(f"{obj.where()}: no set-point object for control type {mode}")
            continue
        sp = setpoint_objects.get(name.upper())
        if sp is None:
            raise ThermocalInputError(
                f"{obj.where()}: the set-point object '{name}' ({wanted.title()}) is not defined."
            )
        sp_obj = sp["_object"]
        heating_schedule = cooling_schedule = None
        if wanted == "THERMOSTATSETPOINT:DUALSETPOINT":
            heating_schedule = sp["heating_setpoint_temperature_schedule_name"]
            cooling_schedule = sp["cooling_setpoint_temperature_schedule_name"]
        elif wanted == "THERMOSTATSETPOINT:SINGLEHEATING":
            heating_schedule = sp["setpoint_temperature_schedule_name"]
        elif wanted == "THERMOSTATSETPOINT:SINGLECOOLING":
            cooling_schedule = sp["setpoint_temperature_schedule_name"]
        else:
            heating_schedule = cooling_schedule = sp["setpoint_temperature_schedule_name"]
        heating = constant(heating_schedule, sp_obj, "heating set-point")
        cooling = constant(cooling_schedule, sp_obj, "cooling set-point")
        for zone_name in targets:
            result[zone_name] = (heating, cooling)
            info.setpoint_schedules[zone_name] = (
                heating_schedule or None,
                cooling_schedule or None,
            )

    templates = {rec["name"].upper(): rec for rec in records("HVACTEMPLATE:THERMOSTAT")}
    for rec in records("HVACTEMPLATE:ZONE:IDEALLOADSAIRSYSTEM"):
        obj = rec["_object"]
        entry = zones.get(rec["zone_name"])
        if entry is None:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Zone Name' = '{rec['zone_name']}' is not a zone."
            )
        template = templates.get(rec["template_thermostat_name"].upper())
        if template is None:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Template Thermostat Name' = "
                f"'{rec['template_thermostat_name']}' is not an HVACTemplate:Thermostat."
            )
        t_obj = template["_object"]
        if template["heating_setpoint_schedule_name"]:
            heating = constant(template["heating_setpoint_schedule_name"], t_obj, "heating")
        else:
            heating = _number(template, "constant_heating_setpoint", required=False)
        if template["cooling_setpoint_schedule_name"]:
            cooling = constant(template["cooling_setpoint_schedule_name"], t_obj, "cooling")
        else:
            cooling = _number(template, "constant_cooling_setpoint", required=False)
        result[entry[0]] = (heating, cooling)
        info.setpoint_schedules[entry[0]] = (
            template["heating_setpoint_schedule_name"] or None,
            template["cooling_setpoint_schedule_name"] or None,
        )
    return result


def _warn_unsupported(source: str, info: IdfImportInfo) -> None:
    parts = []
    if info.unsupported:
        listing = ", ".join(f"{cls} ({count})" for cls, count in info.unsupported.items())
        parts.append(
            f"{source}: {sum(info.unsupported.values())} objects of {len(info.unsupported)} "
            f"classes are not represented by the multi-zone model and were skipped: {listing}."
        )
    if info.notes:
        parts.append("Approximations: " + "; ".join(info.notes) + ".")
    if parts:
        warnings.warn(" ".join(parts), IdfImportWarning, stacklevel=5)
