"""Field layouts of the IDF classes the importer reads, taken from EnergyPlus' own schema.

The layouts live in a data file shipped with the package (:data:`DATA_FILE`), written by
``python -m thermocal.multizone.idf.make_fields`` from the ``Energy+.schema.epJSON`` of an
EnergyPlus installation: for each class of :data:`IMPORTED_CLASSES`, the ordered field names of
the IDD (``legacy_idd`` -> ``fields``) and its extensible group (``extension``, ``extensibles``,
``extensible_size``). The data file records the EnergyPlus version and the schema's sha256.

On top of the schema, three small explicit tables:

* :data:`ALIASES`: the names the importer reads where EnergyPlus' differ;
* :data:`NUMBERED_GROUPS`: runs of numbered fields (``Layer 2``, ``Vertex 1 X-coordinate``, ...)
  that the IDD lists as fixed fields but the importer reads as a repeated group;
* :func:`layout`: the layouts of older files (EnergyPlus 8.x/9.x), as differences against the
  schema's (newest) layout.

:data:`SCHEMA` is the resulting table, upper-case class -> (fixed field names, name of the
repeated group or None, size of the repeated group); a class absent from it is not read.
"""

from __future__ import annotations

import json
from importlib import resources

__all__ = [
    "DATA_FILE",
    "IMPORTED_CLASSES",
    "ALIASES",
    "NUMBERED_GROUPS",
    "SCHEMA",
    "layout",
    "load_data",
]

#: Data file of the package written by :mod:`thermocal.multizone.idf.make_fields`.
DATA_FILE = "fields_25_2.json"

#: The classes the importer reads, spelled as EnergyPlus does (objects of any other class are
#: listed in the IdfImportWarning as not represented). make_fields writes exactly these.
IMPORTED_CLASSES = (
    "Version",
    "Building",
    "GlobalGeometryRules",
    "Site:Location",
    "Site:GroundTemperature:BuildingSurface",
    "Site:GroundReflectance",
    "Site:GroundReflectance:SnowModifier",
    "Timestep",
    "RunPeriod",
    "RunPeriodControl:SpecialDays",
    "RunPeriodControl:DaylightSavingTime",
    "ShadowCalculation",
    "SurfaceConvectionAlgorithm:Inside",
    "SurfaceConvectionAlgorithm:Outside",
    "Zone",
    "ZoneList",
    "ZoneGroup",
    "BuildingSurface:Detailed",
    "Wall:Detailed",
    "RoofCeiling:Detailed",
    "Floor:Detailed",
    "Wall:Exterior",
    "Wall:Adiabatic",
    "Wall:Underground",
    "Wall:Interzone",
    "Roof",
    "Ceiling:Adiabatic",
    "Ceiling:Interzone",
    "Floor:GroundContact",
    "Floor:Adiabatic",
    "Floor:Interzone",
    "FenestrationSurface:Detailed",
    "Window",
    "Door",
    "GlazedDoor",
    "Window:Interzone",
    "Door:Interzone",
    "GlazedDoor:Interzone",
    "InternalMass",
    "Shading:Zone:Detailed",
    "Shading:Building:Detailed",
    "Shading:Site:Detailed",
    "Shading:Site",
    "Shading:Building",
    "Shading:Overhang",
    "Shading:Overhang:Projection",
    "Shading:Fin",
    "Shading:Fin:Projection",
    "Material",
    "Material:NoMass",
    "Material:AirGap",
    "WindowMaterial:SimpleGlazingSystem",
    "WindowMaterial:Glazing",
    "WindowMaterial:Gas",
    "Construction",
    "Construction:FfactorGroundFloor",
    "Construction:CfactorUndergroundWall",
    "Site:GroundTemperature:FCfactorMethod",
    "Foundation:Kiva",
    "Foundation:Kiva:Settings",
    "SurfaceProperty:ExposedFoundationPerimeter",
    "ZoneInfiltration:DesignFlowRate",
    "ZoneInfiltration:EffectiveLeakageArea",
    "ZoneVentilation:DesignFlowRate",
    "ZoneVentilation:WindandStackOpenArea",
    "OtherEquipment",
    "ElectricEquipment",
    "GasEquipment",
    "Lights",
    "People",
    "ZoneControl:Thermostat",
    "ThermostatSetpoint:DualSetpoint",
    "ThermostatSetpoint:SingleHeating",
    "ThermostatSetpoint:SingleCooling",
    "ThermostatSetpoint:SingleHeatingOrCooling",
    "HVACTemplate:Thermostat",
    "HVACTemplate:Zone:IdealLoadsAirSystem",
    "Schedule:Constant",
    "Schedule:Compact",
    "Schedule:Year",
    "Schedule:Week:Daily",
    "Schedule:Week:Compact",
    "Schedule:Day:Interval",
    "Schedule:Day:Hourly",
    "Schedule:Day:List",
    "Schedule:File",
)

_ZONE_OR_SPACE = "zone_or_zonelist_or_space_or_spacelist_name"

#: Importer name of a field or repeated group whose EnergyPlus (epJSON) name differs, per class:
#: ``{class: {EnergyPlus name: importer name}}``. Only names the importer reads (or that its
#: layout variants and tests name) are listed. Why: the gain and infiltration code reads one name
#: for the zone field and the design-level fields of every class (``zone_name``, ``design_level``,
#: ``power_per_zone_floor_area``, ...), which EnergyPlus names per class (``lighting_level``,
#: ``watts_per_floor_area``, ...) and renamed when Spaces arrived (9.6: "Zone or ZoneList Name"
#: -> "Zone or ZoneList or Space or SpaceList Name"); InternalMass' space field is ``space_name``
#: as in the surfaces; the glazing and week-schedule names are the short ones of the importer's
#: parameters and messages ("Sunday Schedule:Day Name"); the group names say what a group holds.
ALIASES: dict[str, dict[str, str]] = {
    "ZoneList": {"zones": "zone_names"},
    "InternalMass": {
        "zone_or_zonelist_name": "zone_name",
        "space_or_spacelist_name": "space_name",
    },
    "WindowMaterial:Glazing": {
        "solar_transmittance_at_normal_incidence": "solar_transmittance",
        "front_side_solar_reflectance_at_normal_incidence": "front_solar_reflectance",
        "back_side_solar_reflectance_at_normal_incidence": "back_solar_reflectance",
        "infrared_transmittance_at_normal_incidence": "infrared_transmittance",
        "front_side_infrared_hemispherical_emissivity": "front_infrared_emissivity",
        "back_side_infrared_hemispherical_emissivity": "back_infrared_emissivity",
        "dirt_correction_factor_for_solar_and_visible_transmittance": "dirt_correction_factor",
    },
    "ZoneInfiltration:DesignFlowRate": {
        _ZONE_OR_SPACE: "zone_name",
        "flow_rate_per_floor_area": "flow_per_zone_floor_area",
        "flow_rate_per_exterior_surface_area": "flow_per_exterior_surface_area",
    },
    "ZoneInfiltration:EffectiveLeakageArea": {"zone_or_space_name": "zone_name"},
    "ZoneVentilation:DesignFlowRate": {_ZONE_OR_SPACE: "zone_name"},
    "ZoneVentilation:WindandStackOpenArea": {"zone_or_space_name": "zone_name"},
    "OtherEquipment": {
        _ZONE_OR_SPACE: "zone_name",
        "power_per_floor_area": "power_per_zone_floor_area",
    },
    "ElectricEquipment": {
        _ZONE_OR_SPACE: "zone_name",
        "watts_per_floor_area": "power_per_zone_floor_area",
        "watts_per_person": "power_per_person",
    },
    "GasEquipment": {
        _ZONE_OR_SPACE: "zone_name",
        "power_per_floor_area": "power_per_zone_floor_area",
    },
    "Lights": {
        _ZONE_OR_SPACE: "zone_name",
        "lighting_level": "design_level",
        "watts_per_floor_area": "power_per_zone_floor_area",
        "watts_per_person": "power_per_person",
    },
    "People": {
        _ZONE_OR_SPACE: "zone_name",
        "people_per_floor_area": "people_per_zone_floor_area",
        "floor_area_per_person": "zone_floor_area_per_person",
    },
    "ZoneControl:Thermostat": {"zone_or_zonelist_name": "zone_name"},
    "Schedule:Compact": {"data": "compact_fields"},
    "Schedule:Year": {"schedule_weeks": "week_periods"},
    "Schedule:Week:Daily": {
        "sunday_schedule_day_name": "sunday",
        "monday_schedule_day_name": "monday",
        "tuesday_schedule_day_name": "tuesday",
        "wednesday_schedule_day_name": "wednesday",
        "thursday_schedule_day_name": "thursday",
        "friday_schedule_day_name": "friday",
        "saturday_schedule_day_name": "saturday",
        "holiday_schedule_day_name": "holiday",
        "summerdesignday_schedule_day_name": "summer_design_day",
        "winterdesignday_schedule_day_name": "winter_design_day",
        "customday1_schedule_day_name": "custom_day_1",
        "customday2_schedule_day_name": "custom_day_2",
    },
    "Schedule:Week:Compact": {"data": "day_rules"},
    "Schedule:Day:Interval": {"data": "time_value_pairs"},
    "Schedule:Day:List": {"extensions": "values"},
}

#: Numbered fields the IDD lists as fixed fields, read as a repeated group: ``{class: (first
#: field of the run, group name, group size)}``. The group runs from that field to the end of the
#: object (any number of layers or vertices, whatever limit the IDD sets).
NUMBERED_GROUPS: dict[str, tuple[str, str, int]] = {
    "Construction": ("outside_layer", "layers", 1),
    "FenestrationSurface:Detailed": ("vertex_1_x_coordinate", "vertices", 3),
    "Schedule:Day:Hourly": ("hour_1", "hourly_values", 1),
    "ZoneControl:Thermostat": ("control_1_object_type", "controls", 2),
}


def load_data() -> dict:
    """The shipped data file (see :mod:`thermocal.multizone.idf.make_fields`)."""
    text = resources.files("thermocal.multizone.idf").joinpath(DATA_FILE).read_text("utf-8")
    return json.loads(text)


def _schema(data: dict) -> dict[str, tuple[tuple[str, ...], str | None, int]]:
    """Importer layouts (aliases and numbered groups applied) from the data file."""
    out = {}
    for cls, entry in data["classes"].items():
        alias = ALIASES.get(cls, {})
        fields = [alias.get(f, f) for f in entry["fields"]]
        group, size = None, 0
        if cls in NUMBERED_GROUPS:
            first, group, size = NUMBERED_GROUPS[cls]
            fields = fields[: entry["fields"].index(first)]
        elif entry.get("extension"):
            group = alias.get(entry["extension"], entry["extension"])
            size = int(entry["extensible_size"])
        out[cls.upper()] = (tuple(fields), group, size)
    return out


#: Upper-case class -> (fixed field names, repeated group name or None, group size): the layout
#: of the newest EnergyPlus (the data file's); :func:`layout` gives that of a given file.
SCHEMA: dict[str, tuple[tuple[str, ...], str | None, int]] = _schema(load_data())

# ------------------------------------------------------------------------------------------------
# Layouts of older files, as differences against the schema's
# ------------------------------------------------------------------------------------------------

#: Surface classes with the shape of BuildingSurface:Detailed but an implied surface type.
_SURFACE_CLASS_TYPE = {
    "WALL:DETAILED": "Wall",
    "ROOFCEILING:DETAILED": "Roof",
    "FLOOR:DETAILED": "Floor",
}
_SURFACE_CLASSES = ("BUILDINGSURFACE:DETAILED", *_SURFACE_CLASS_TYPE)

#: The simple-geometry (rectangular) surface classes: their ``Space Name`` field (9.6 and later)
#: sits before the azimuth, which older files write in its place.
_RECTANGULAR_SURFACE_CLASSES = (
    "WALL:EXTERIOR",
    "WALL:ADIABATIC",
    "WALL:UNDERGROUND",
    "WALL:INTERZONE",
    "ROOF",
    "CEILING:ADIABATIC",
    "CEILING:INTERZONE",
    "FLOOR:GROUNDCONTACT",
    "FLOOR:ADIABATIC",
    "FLOOR:INTERZONE",
)

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


def _without(names: tuple[str, ...], name: str) -> tuple[str, ...]:
    return tuple(n for n in names if n != name)


def _is_number(text: str) -> bool:
    """Whether a raw field is a number (a blank one is not)."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def _without_space_name(
    names: tuple[str, ...], fields: tuple[str, ...] | list[str], version: tuple[int, int]
) -> bool:
    """Whether a simple-geometry surface (``Wall:Exterior``, ``Roof``, ...) was written without
    the ``Space Name`` field of EnergyPlus 9.6 and later.

    Parameters
    ----------
    names : tuple of str
        The class's field names with ``space_name`` (:data:`SCHEMA`).
    fields : sequence of str
        The object's raw fields.
    version : tuple of int
        EnergyPlus version of the file (``Version`` object).

    Returns
    -------
    bool
        True when the field in the azimuth's place less one is a number (the azimuth of a file
        written without the field) and either the file is older than 9.6 or the object is one
        field short of the full layout (its last field, the height or width, is required). A
        9.6+ object with all its fields keeps its ``Space Name`` even when that is a number (a
        room number such as ``101``).
    """
    i = names.index("azimuth_angle")
    if len(fields) < i or not _is_number(fields[i - 1]):
        return False
    return version < (9, 6) or len(fields) < len(names)


def layout(
    key: str, fields: tuple[str, ...] | list[str], version: tuple[int, int]
) -> tuple[tuple[str, ...], str | None, int]:
    """Layout of one object: :data:`SCHEMA`'s, adjusted for files of older EnergyPlus versions.

    Parameters
    ----------
    key : str
        Upper-case class name (a key of :data:`SCHEMA`).
    fields : sequence of str
        The object's raw fields (some older layouts are recognised from the content).
    version : tuple of int
        EnergyPlus version of the file (``Version`` object).

    Returns
    -------
    (fixed field names, repeated group name or None, group size)

    Notes
    -----
    Differences against the schema's layout:

    * surfaces (``BuildingSurface:Detailed``, ``Wall/RoofCeiling/Floor:Detailed``): the
      ``Space Name`` field after ``Zone Name`` (EnergyPlus 9.6 and later) is dropped unless it is
      there, i.e. unless the field after it is an outside boundary condition while it is not;
    * the simple-geometry surfaces (``Wall:Exterior``, ``Roof``, ``Floor:Interzone``, ...): the
      ``Space Name`` field after ``Zone Name`` (9.6 and later) is dropped when the object was
      written without it (:func:`_without_space_name`);
    * ``Window`` and ``GlazedDoor`` before version 9.0: the ``Shading Control Name`` field after
      ``Building Surface Name`` (removed in 9.0) is inserted;
    * ``InternalMass``: ``Space or SpaceList Name`` (9.6 and later) is dropped for objects of 4
      fields or fewer;
    * ``FenestrationSurface:Detailed`` before version 9.0: the ``Shading Control Name`` field
      after ``View Factor to Ground`` (removed in 9.0) is inserted;
    * ``OtherEquipment`` written before the ``Fuel Type`` field existed: dropped when the fourth
      field is a design-level method and the fifth is not.
    """
    names, group, size = SCHEMA[key]
    if key in _SURFACE_CLASSES:
        i = names.index("space_name")
        if not (
            len(fields) > i + 1
            and fields[i].upper() not in _BOUNDARY_CONDITIONS
            and fields[i + 1].upper() in _BOUNDARY_CONDITIONS
        ):
            names = _without(names, "space_name")
    elif key in _RECTANGULAR_SURFACE_CLASSES:
        if _without_space_name(names, fields, version):
            names = _without(names, "space_name")  # written before 9.6: the azimuth moves up
    elif key == "FENESTRATIONSURFACE:DETAILED" and version < (9, 0):
        i = names.index("view_factor_to_ground") + 1
        names = (*names[:i], "shading_control_name", *names[i:])
    elif key in ("WINDOW", "GLAZEDDOOR") and version < (9, 0):
        i = names.index("building_surface_name") + 1
        names = (*names[:i], "shading_control_name", *names[i:])
    elif key == "INTERNALMASS" and len(fields) <= 4:
        names = _without(names, "space_name")
    elif (
        key == "OTHEREQUIPMENT"
        and len(fields) > 3
        and fields[3].upper() in _EQUIPMENT_METHODS
        and not (len(fields) > 4 and fields[4].upper() in _EQUIPMENT_METHODS)
    ):
        names = _without(names, "fuel_type")
    return names, group, size
