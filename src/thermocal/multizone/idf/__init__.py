"""EnergyPlus IDF import: tokenizer, field layouts from EnergyPlus' schema, surface geometry,
mapping to a multi-zone Building.

The importer covers the envelope subset of EnergyPlus input that the multi-zone model represents:
``Zone``, ``BuildingSurface:Detailed`` (and its ``Wall/RoofCeiling/Floor:Detailed`` siblings),
``FenestrationSurface:Detailed`` and ``Window``/``Door``/``GlazedDoor``, the simple-geometry
classes (``Wall:Exterior``, ``Roof``, ``Floor:Interzone``, ``Window:Interzone``,
``Shading:Site``, ... read as the detailed objects EnergyPlus makes of them,
:mod:`.simple_geometry`), ``Material``,
``Material:NoMass``, ``Material:AirGap``, ``Construction``,
``WindowMaterial:SimpleGlazingSystem``, ``WindowMaterial:Glazing`` + ``WindowMaterial:Gas``
(layered glazing, optics by :mod:`thermocal.multizone.glazing`),
``ZoneInfiltration:DesignFlowRate``/``EffectiveLeakageArea``, ``Site:Location``,
``Site:GroundTemperature:BuildingSurface``, ``GlobalGeometryRules``, ``Building`` (north axis),
``ZoneList``, ``InternalMass`` (adiabatic surfaces), the internal gains
``OtherEquipment``/``ElectricEquipment``/``GasEquipment``/``Lights``/``People`` and the
thermostat objects (``ZoneControl:Thermostat`` with ``ThermostatSetpoint:*``,
``HVACTemplate:Thermostat``) with the schedules they use (``Schedule:Constant``,
``Schedule:Compact``, ``Schedule:Year`` / ``Schedule:Week:Daily`` / ``Schedule:Day:Interval`` /
``Schedule:Day:Hourly``, ...), and the shading surfaces (``Shading:*``; the building's own
exterior surfaces cast shadows too).

Everything else is summarised in ONE :class:`IdfImportWarning`: the classes that change the heat
balance by name, HVAC (replaced by ideal loads) and harmless classes (outputs, sizing) by count;
``building.idf_info.report()`` and ``thermocal simulate``'s summary.json give the full lists.

Modules of this package, each usable on its own:

1. :mod:`.parse`: :func:`parse_idf` / :func:`read_idf_objects`: text -> list of
   :class:`IdfObject` (class name as written, raw string fields, the ``!-`` field comments, line
   numbers; class names are matched case-insensitively everywhere); :func:`record` names the
   fields.
2. :mod:`.fields`: the field layouts (:data:`SCHEMA`), from EnergyPlus' ``Energy+.schema.epJSON``
   through the shipped data file written by :mod:`.make_fields`, with the layouts of older files
   (EnergyPlus 8.9 to 25.x, including the ``Space Name`` field of newer surfaces, detected from
   content) as differences against it.
3. :mod:`.geometry`: :func:`newell_normal`, :func:`polygon_area`, :func:`tilt_azimuth`,
   :func:`to_world_coordinates`, :func:`zone_volume_from_surfaces` with the EnergyPlus
   conventions (vertices counter-clockwise seen from outside unless ``GlobalGeometryRules`` says
   clockwise; relative coordinates are rotated by the zone's direction of relative north and
   shifted by its origin, then rotated by the building's north axis; world coordinates are used
   as given).
4. :mod:`.schedules`: :class:`ScheduleEvaluator`, the file's schedules over a calendar year.
5. The stages of :func:`read_idf` -> :class:`thermocal.multizone.model.Building`, one module per
   group of classes: :mod:`.site`, :mod:`.constructions`, :mod:`.surfaces` (with
   :mod:`.simple_geometry`), :mod:`.shading`, :mod:`.loads`; :mod:`.report` holds
   :class:`IdfImportInfo` and the warning. The builder below
   runs them in order.

References
----------
EnergyPlus Input Output Reference (v9.3), sections Group -- Thermal Zone Description/Geometry
(GlobalGeometryRules, Zone, BuildingSurface:Detailed, FenestrationSurface:Detailed), Group --
Surface Construction Elements (Material, Material:NoMass, Material:AirGap, WindowMaterial:*),
Group -- Internal Gains, Group -- Airflow (ZoneInfiltration:DesignFlowRate), Group -- Schedules.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.constructions import (
    GLASS_CONDUCTANCE_TEMPERATURES,
    WINDOW_TABLE_ANGLES,
    ConstructionStages,
    window_type_from_glazing,
)
from thermocal.multizone.idf.fields import SCHEMA
from thermocal.multizone.idf.geometry import (
    GeometryRules,
    newell_normal,
    outward_normal,
    polygon_area,
    polyhedron_is_closed,
    tilt_azimuth,
    to_world_coordinates,
    zone_volume_from_surfaces,
)
from thermocal.multizone.idf.loads import (
    DEFAULT_PEOPLE_SENSIBLE_FRACTION,
    INFILTRATION_REFERENCE_WIND_SPEED,
    PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE,
    TERRAIN_WIND_PROFILE,
    WEATHER_STATION_WIND_PROFILE,
    InfiltrationInfo,
    InternalGainInfo,
    LoadStages,
    local_wind_factor,
    people_sensible_heat,
)
from thermocal.multizone.idf.parse import (
    IdfObject,
    _version_tuple,
    _wrap,
    parse_idf,
    read_idf_objects,
    record,
)
from thermocal.multizone.idf.report import (
    IdfImportInfo,
    IdfImportWarning,
    ScheduledInputs,
    _warn_unsupported,
    import_report,
    import_summary,
    unsupported_kind,
)
from thermocal.multizone.idf.schedules import (
    DAY_TYPES,
    ScheduleEvaluator,
    UnsupportedScheduleError,
)
from thermocal.multizone.idf.shading import ShadingStages
from thermocal.multizone.idf.simple_geometry import RectangularGeometryStages
from thermocal.multizone.idf.site import ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE, SiteStages
from thermocal.multizone.idf.surfaces import SurfaceStages

__all__ = [
    "read_idf",
    "IdfImportInfo",
    "IdfImportWarning",
    "IdfObject",
    "SCHEMA",
    "parse_idf",
    "read_idf_objects",
    "record",
    "newell_normal",
    "polygon_area",
    "tilt_azimuth",
    "GeometryRules",
    "to_world_coordinates",
    "outward_normal",
    "zone_volume_from_surfaces",
    "polyhedron_is_closed",
    "DAY_TYPES",
    "ScheduleEvaluator",
    "UnsupportedScheduleError",
    "ScheduledInputs",
    "import_report",
    "import_summary",
    "unsupported_kind",
    "InternalGainInfo",
    "InfiltrationInfo",
    "people_sensible_heat",
    "local_wind_factor",
    "window_type_from_glazing",
    "INFILTRATION_REFERENCE_WIND_SPEED",
    "WINDOW_TABLE_ANGLES",
    "GLASS_CONDUCTANCE_TEMPERATURES",
    "DEFAULT_PEOPLE_SENSIBLE_FRACTION",
    "PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE",
    "ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE",
    "TERRAIN_WIND_PROFILE",
    "WEATHER_STATION_WIND_PROFILE",
]


#: Oldest EnergyPlus version whose field layouts the importer knows (older files differ in
#: RunPeriod, surfaces and schedules beyond what is adapted) and the newest one it was built for.
OLDEST_VERSION, NEWEST_VERSION = (8, 0), (25, 2)


def _has_version(objects) -> bool:
    return any(obj.key == "VERSION" and obj.fields for obj in objects)


def check_version(version: tuple[int, int], path, *, declared: bool = True) -> list[str]:
    """Refuse an IDF older than the importer knows; a note for a newer or undeclared one.

    Parameters
    ----------
    version : (int, int)
        The file's ``Version`` (major, minor).
    path : str or Path
        The file, for the message.
    declared : bool
        Whether the file has a ``Version`` object (else 9.3 is assumed).

    Returns
    -------
    list of str
        Notes for the import summary.

    Raises
    ------
    ThermocalInputError
        A version older than :data:`OLDEST_VERSION`, naming it and what to do.
    """
    from thermocal.errors import ThermocalInputError

    text = f"{version[0]}.{version[1]}"
    supported = (
        f"{OLDEST_VERSION[0]}.{OLDEST_VERSION[1]} to {NEWEST_VERSION[0]}.{NEWEST_VERSION[1]}"
    )
    if not declared:
        return [
            f"{path}: no Version object; the field layouts of EnergyPlus 9.3 are assumed "
            f"(supported: {supported})"
        ]
    if version < OLDEST_VERSION:
        raise ThermocalInputError(
            f"{path}: EnergyPlus version {text} is older than the IDF versions thermocal reads "
            f"({supported}); convert it with EnergyPlus' IDFVersionUpdater (or its "
            "Transition-V*-to-V* programs) to a supported version first"
        )
    if version > NEWEST_VERSION:
        return [
            f"{path}: EnergyPlus version {text} is newer than the newest layout thermocal "
            f"knows ({NEWEST_VERSION[0]}.{NEWEST_VERSION[1]}); fields are read with that "
            "layout: check the import summary and compare with EnergyPlus"
        ]
    return []


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


class _IdfReader(
    SiteStages,
    ConstructionStages,
    SurfaceStages,
    RectangularGeometryStages,
    ShadingStages,
    LoadStages,
):
    """One import by :func:`read_idf`: the file's objects, lookups and the stages of the mapping.

    Each ``_stage`` method reads one group of classes and stores what later stages need as
    attributes (materials, constructions, zones, surfaces, ...); :meth:`build` runs them in order.
    The stages live in the modules of their classes (``SiteStages`` in :mod:`.site`, ...).
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
        self.info.notes.extend(
            check_version(self.version, self.path, declared=_has_version(self.objects))
        )
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
        self._ventilation()
        self._internal_gains()
        self._setpoints()
        self._model_zones()
        self._ground()
        return self._building()

    def _unsupported_classes(self) -> None:
        """Stage: unsupported classes."""
        canonical: dict[str, str] = {}
        for obj in self.objects:
            canonical.setdefault(obj.key, obj.class_name)
        grouped: Counter = Counter()
        for obj in self.objects:
            if obj.key not in SCHEMA:
                grouped[canonical[obj.key]] += 1
        self.info.unsupported = dict(sorted(grouped.items()))

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
                ground_reflectance=self.ground_reflectance,
                foundations=self.foundations,
            )
        except ThermocalInputError as exc:
            raise ThermocalInputError(f"{self.path.name}: {exc}") from None
        building.idf_info = self.info
        _warn_unsupported(self.path.name, self.info)
        return building
