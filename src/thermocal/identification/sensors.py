"""Sensors -> zones: the mapping file, substitutes for zones without a sensor, the references.

Mapping file (YAML)::

    sensors:            # every sensor -> the zone it hangs in (several in one zone: averaged)
      S01: Room 2
      S02: Room 4
      S03: Room 4
    unsensed: float     # optional: zones without a sensor float (default) or take a
                        # neighbour's data ("neighbour")
    identified_heat:    # optional: the form of Q_ID for every zone
      radiant_fraction: 0.6   # share of Q_ID on the zone's surfaces [-] (default 0.6), or
                              # declared: step by step from the IDF's own load objects
      sensor: air             # air | operative | the air weight of the sensed temperature [-]
    zones:              # optional, per zone
      Room 29: {use: Room 27}             # a zone without a sensor that uses another's data
      Plenum: {unsensed: neighbour}       # the treatment of one zone without a sensor
      Room 3: {radiant_fraction: 0.2, sensor: operative}
      Boiler room: {plausible: [40, 80]}  # a zone whose sensors may average 40-80 C [C]
    ignore: [S77]       # optional: sensors of the log left out
    constant_readings: accept   # optional: accept long constant readings of every sensor
                                # (or per sensor: {S01: accept}); see below

Sensor and zone names are read as written (``0101`` stays ``0101``, not YAML's octal 65). A
sensor under ``ignore:`` that is not in the log, or that is also mapped (it is left out), is
named in a warning; so are two sensors of one zone that differ by more than
:data:`SENSOR_DISAGREEMENT` on average (their mean is a temperature neither measures).

A sensor whose mean is not an indoor temperature (outside -30..35 C) or far from the others is
refused as a unit slip (Kelvin, Fahrenheit, tenths...); ``plausible: [low, high]`` declares the
mean range of a zone that is really that warm or cold (its sensors are then checked against that
range only, not against the other zones').

A sensor reading exactly the same value for :data:`STUCK_AFTER` or longer is refused as stuck
(a frozen logger repeats its last value) unless the run is explained
(:func:`constant_run_reason`, a warning says which): the value is a set point the building
declares for the sensor's zone throughout the run, or the log's resolution explains it (the
sensor's values lie on a grid of at least :data:`COARSE_RESOLUTION`, the value is a controlled
room's (:data:`CONTROLLED_RANGE`) and the log's other sensors change meanwhile), or the mapping
says ``constant_readings: accept`` (for all sensors, or ``{sensor: accept}`` for some).

A zone with neither a sensor nor a named substitute **floats** by default: it is simulated with
``Q_ID = 0`` and its temperature is reported. With ``unsensed: neighbour`` (globally or per zone,
the method's rule) it takes an adjacent zone's data: among the zones that share an inter-zone
surface with it and have a sensor, the one with the same main orientation (azimuth of its
largest exterior wall, "interior" when it has none) and, among those, the largest shared area;
a zone with no sensored neighbour floats. Every choice and its reason are reported.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import temperature_unit_slip
from thermocal.io.measurements.units import (
    INDOOR_MEAN_RANGE,
    NEIGHBOUR_TOLERANCE,
    log_unit_slips,
)

_log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SensorMapping:
    """Sensor -> zone assignments, named substitutes and ignored sensors."""

    sensors: dict[str, str]
    substitutes: dict[str, str] = field(default_factory=dict)
    ignore: tuple[str, ...] = ()
    source: str = "mapping"
    #: treatment of zones without a sensor nor a named substitute: "float" or "neighbour"
    unsensed: str = "float"
    #: per-zone treatment overriding ``unsensed``
    treatments: dict[str, str] = field(default_factory=dict)
    #: form of Q_ID: radiant fraction [-] and sensor model ("air", "operative" or air weight
    #: [-]) for every zone (None: the caller's default) and per zone
    radiant_fraction: float | str | None = None  # a number [-] or "declared"
    sensor: str | float | None = None
    zone_radiant_fraction: dict[str, float] = field(default_factory=dict)
    zone_sensor: dict[str, str | float] = field(default_factory=dict)
    #: declared plausible mean temperature [C] per zone (low, high)
    zone_plausible: dict[str, tuple[float, float]] = field(default_factory=dict)
    #: long constant readings: "check" (refused unless explained) or "accept", for every
    #: sensor, and per sensor overriding it
    constant_readings: str = "check"
    sensor_constant_readings: dict[str, str] = field(default_factory=dict)

    def constant_readings_of(self, sensor: str) -> str:
        """``"accept"`` or ``"check"``: how a long constant reading of ``sensor`` is judged."""
        return self.sensor_constant_readings.get(str(sensor), self.constant_readings)


@dataclass(frozen=True)
class ZoneSource:
    """Where a zone's reference temperature comes from.

    Attributes
    ----------
    kind : {"sensor", "named", "neighbour", "float"}
        "float": no reference, the zone is simulated with ``Q_ID = 0``.
    sensors : tuple of str
        The sensors averaged (the source zone's for "named" and "neighbour").
    zone : str
        The zone whose sensors are used (the zone itself for "sensor").
    reason : str
    """

    kind: str
    sensors: tuple[str, ...]
    zone: str
    reason: str = ""


def load_mapping(path: str | Path) -> SensorMapping:
    """Read and check the form of a mapping file (module docstring); its sensor and zone names
    are read as written (:func:`names_as_written`)."""
    from thermocal.io.yamlfile import read_yaml_text

    path = Path(path)
    data, text = read_yaml_text(path, what="mapping file")
    return mapping_from_dict(names_as_written(data, text), source=str(path))


def names_as_written(data, text: str):
    """The parsed mapping file with its sensor and zone names as the text written.

    YAML reads some names as something else: ``0101`` as the octal number 65, ``1.10`` as the
    number 1.1, ``12:30`` as 750, ``yes`` as True; a log column ``0101`` then matches no sensor
    of the mapping. The names (the keys of ``sensors`` and ``zones``, the zone of each sensor,
    ``use``, the items of ``ignore``) are taken from the document's nodes as written (quoted or
    not); everything else keeps its parsed value.

    Parameters
    ----------
    data : object
        The document parsed by :func:`thermocal.io.yamlfile.read_yaml_text` (its checks done).
    text : str
        The file's text.

    Returns
    -------
    object
        ``data`` with the names as written (``data`` itself when it is not a mapping).
    """
    import yaml

    if not isinstance(data, Mapping):
        return data
    loader = yaml.SafeLoader(text)
    try:
        root = loader.get_single_node()
        out = dict(data)
        for key_node, node in root.value:
            section = key_node.value if isinstance(key_node, yaml.ScalarNode) else None
            if section not in out:
                continue
            if section == "sensors" and isinstance(node, yaml.MappingNode):
                loader.flatten_mapping(node)  # merge keys (<<: *anchor) as the parser does
                out[section] = {
                    _name_as_written(loader, key): _name_as_written(loader, value)
                    for key, value in node.value
                }
            elif section == "zones" and isinstance(node, yaml.MappingNode):
                loader.flatten_mapping(node)
                out[section] = {
                    _name_as_written(loader, key): _zone_spec_as_written(loader, value)
                    for key, value in node.value
                }
            elif section == "ignore" and isinstance(node, yaml.SequenceNode):
                out[section] = [_name_as_written(loader, item) for item in node.value]
            elif section == "constant_readings" and isinstance(node, yaml.MappingNode):
                loader.flatten_mapping(node)
                out[section] = {
                    _name_as_written(loader, key): loader.construct_object(value, deep=True)
                    for key, value in node.value
                }
    finally:
        loader.dispose()
    return out


def _name_as_written(loader, node):
    """A scalar node's text as written (a name); a null or a list or mapping as parsed (the
    form checks name it)."""
    import yaml

    if isinstance(node, yaml.ScalarNode) and node.tag != "tag:yaml.org,2002:null":
        return node.value
    return loader.construct_object(node, deep=True)


def _zone_spec_as_written(loader, node):
    """A ``zones`` entry as parsed, its ``use`` (a zone name) as written."""
    import yaml

    spec = loader.construct_object(node, deep=True)
    if isinstance(node, yaml.MappingNode) and isinstance(spec, dict):
        for key, value in node.value:
            if isinstance(key, yaml.ScalarNode) and key.value == "use":
                spec["use"] = _name_as_written(loader, value)
    return spec


def mapping_from_dict(data, *, source: str = "mapping") -> SensorMapping:
    """:class:`SensorMapping` from the parsed file form."""
    if not isinstance(data, Mapping) or "sensors" not in data:
        raise ThermocalInputError(
            f"{source}: expected a mapping with a 'sensors' section (sensor name -> zone name)"
        )
    sections = {"sensors", "zones", "ignore", "unsensed", "identified_heat", "constant_readings"}
    unknown = set(data) - sections
    if unknown:
        raise ThermocalInputError(
            f"{source}: unknown sections {sorted(unknown)} (allowed: {', '.join(sorted(sections))})"
        )
    sensors = data["sensors"]
    if not isinstance(sensors, Mapping) or not sensors:
        raise ThermocalInputError(f"{source}: 'sensors' must map sensor names to zone names")
    out: dict[str, str] = {}
    for sensor, zone in sensors.items():
        if not isinstance(zone, str) or not zone.strip():
            raise ThermocalInputError(
                f"{source}: sensor {sensor!r} is mapped to {zone!r}; give one zone name"
            )
        out[str(sensor)] = zone
    unsensed = _treatment(data.get("unsensed", "float"), f"{source}: unsensed")
    heat = data.get("identified_heat") or {}
    if not isinstance(heat, Mapping) or set(heat) - {"radiant_fraction", "sensor"}:
        raise ThermocalInputError(
            f"{source}: identified_heat must be {{radiant_fraction: <0..1> | declared, "
            f"sensor: air | operative | <air weight 0..1>}}, got {heat!r}"
        )
    radiant = heat.get("radiant_fraction")
    if isinstance(radiant, str) and radiant.strip().lower() == "declared":
        radiant = "declared"  # the building file's own form (thermocal.identification.form)
    elif radiant is not None:
        radiant = _fraction(radiant, f"{source}: identified_heat")
    sensor = heat.get("sensor")
    sensor = None if sensor is None else sensor_weight(sensor, f"{source}: identified_heat")
    substitutes: dict[str, str] = {}
    treatments: dict[str, str] = {}
    zone_radiant: dict[str, float] = {}
    zone_sensor: dict[str, str | float] = {}
    zone_plausible: dict[str, tuple[float, float]] = {}
    keys = {"use", "unsensed", "radiant_fraction", "sensor", "plausible"}
    for zone, spec in (data.get("zones") or {}).items():
        where = f"{source}: zones.{zone}"
        if (
            not isinstance(spec, Mapping)
            or not spec
            or set(spec) - keys
            or ("use" in spec and not isinstance(spec["use"], str))
            or ("use" in spec and "unsensed" in spec)
        ):
            raise ThermocalInputError(
                f"{where} must hold {{use: <zone name>}} or {{unsensed: float | neighbour}} "
                f"and/or radiant_fraction / sensor / plausible, got {spec!r}"
            )
        zone = str(zone)
        if "use" in spec:
            substitutes[zone] = spec["use"]
        if "unsensed" in spec:
            treatments[zone] = _treatment(spec["unsensed"], where)
        if "radiant_fraction" in spec:
            zone_radiant[zone] = _fraction(spec["radiant_fraction"], where)
        if "sensor" in spec:
            zone_sensor[zone] = sensor_weight(spec["sensor"], where)
        if "plausible" in spec:
            zone_plausible[zone] = _plausible_range(spec["plausible"], where)
    ignore = data.get("ignore") or []
    if not isinstance(ignore, list):
        raise ThermocalInputError(f"{source}: 'ignore' must be a list of sensor names")
    constant, per_sensor = _constant_readings(data.get("constant_readings", "check"), out, source)
    return SensorMapping(
        out,
        substitutes,
        tuple(str(s) for s in ignore),
        source,
        unsensed=unsensed,
        treatments=treatments,
        radiant_fraction=radiant,
        sensor=sensor,
        zone_radiant_fraction=zone_radiant,
        zone_sensor=zone_sensor,
        zone_plausible=zone_plausible,
        constant_readings=constant,
        sensor_constant_readings=per_sensor,
    )


def _constant_readings(value, sensors: Mapping[str, str], source: str) -> tuple[str, dict]:
    """The mapping's ``constant_readings``: ``accept`` or ``check`` for every sensor, or
    ``{sensor: accept | check}`` (the others ``check``); returns (global, per sensor)."""
    allowed = ("accept", "check")
    usage = (
        f"{source}: constant_readings must be accept or check (for every sensor), or "
        "{sensor: accept | check} for some"
    )
    if isinstance(value, str):
        if value not in allowed:
            raise ThermocalInputError(f"{usage}, got {value!r}")
        return value, {}
    if not isinstance(value, Mapping) or not value:
        raise ThermocalInputError(f"{usage}, got {value!r}")
    per_sensor = {}
    for sensor, how in value.items():
        if how not in allowed:
            raise ThermocalInputError(f"{usage}, got {how!r} for sensor {sensor!r}")
        if str(sensor) not in sensors:
            raise ThermocalInputError(
                f"{source}: constant_readings names sensor {sensor!r}, which is not under "
                f"'sensors:'{_suggest(str(sensor), list(sensors))}"
            )
        per_sensor[str(sensor)] = how
    return "check", per_sensor


def _plausible_range(value, where: str) -> tuple[float, float]:
    """``[low, high]`` [C] of a zone's declared plausible mean temperature."""
    ok = (
        isinstance(value, list | tuple)
        and len(value) == 2
        and all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        and -60.0 <= value[0] < value[1] <= 150.0
    )
    if not ok:
        raise ThermocalInputError(
            f"{where}: plausible must be [low, high], the zone's plausible mean temperature in C "
            f"with -60 <= low < high <= 150 (e.g. [40, 80] for a hot room), got {value!r}"
        )
    return float(value[0]), float(value[1])


def _treatment(value, where: str) -> str:
    if value not in ("float", "neighbour"):
        raise ThermocalInputError(
            f"{where}: the treatment of a zone without a sensor is 'float' (simulated, Q_ID = 0) "
            f"or 'neighbour' (an adjacent zone's data), got {value!r}"
        )
    return value


def _fraction(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value <= 1:
        raise ThermocalInputError(
            f"{where}: radiant_fraction must be a number in [0, 1] (or declared for all zones), "
            f"got {value!r}"
        )
    return float(value)


def sensor_weight(value, where: str = "sensor") -> float:
    """Air weight ``w`` [-] of a sensor model: "air" 1, "operative" 0.5, or a number in [0, 1].

    The sensed temperature is ``w T_air + (1 - w) T_surf`` (``T_surf`` the zone's area-weighted
    interior surface temperature).
    """
    if isinstance(value, str) and value in ("air", "operative"):
        return 1.0 if value == "air" else 0.5
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value <= 1:
        raise ThermocalInputError(
            f"{where}: sensor must be 'air', 'operative' or the air weight of the sensed "
            f"temperature in [0, 1], got {value!r}"
        )
    return float(value)


def in_building_spelling(mapping: SensorMapping, building) -> tuple[SensorMapping, list[str]]:
    """The mapping with zone names written in another case than the building's respelled.

    EnergyPlus matches names regardless of case (an IDF's ``SPACE1-1`` is ``Space1-1``); a
    mapping written that way was refused. A zone name that is no zone of the building but
    equals exactly one of them ignoring case is taken as that zone; any other unknown name is
    left for the checks that name it (with "did you mean").

    Parameters
    ----------
    mapping : SensorMapping
        As read.
    building : thermocal.multizone.Building
        Its zones' names are the spelling used.

    Returns
    -------
    (SensorMapping, list of str)
        The mapping (the same object when nothing changed) and a note per respelled name.
    """
    zones = list(map(str, building.zones))
    by_folded: dict[str, list[str]] = {}
    for zone in zones:
        by_folded.setdefault(zone.casefold(), []).append(zone)
    renamed: dict[str, str] = {}

    def spelt(name):
        text = str(name)
        if text in building.zones:
            return name
        matches = by_folded.get(text.casefold(), [])
        if len(matches) != 1:
            return name
        renamed[text] = matches[0]
        return matches[0]

    def keys(table: dict) -> dict:
        return {spelt(zone): value for zone, value in table.items()}

    respelled = dataclasses.replace(
        mapping,
        sensors={sensor: spelt(zone) for sensor, zone in mapping.sensors.items()},
        substitutes={spelt(zone): spelt(source) for zone, source in mapping.substitutes.items()},
        treatments=keys(mapping.treatments),
        zone_radiant_fraction=keys(mapping.zone_radiant_fraction),
        zone_sensor=keys(mapping.zone_sensor),
        zone_plausible=keys(mapping.zone_plausible),
    )
    if not renamed:
        return mapping, []
    listed = ", ".join(f"'{old}' as '{new}'" for old, new in renamed.items())
    return respelled, [
        f"{mapping.source}: zone names read regardless of case, as EnergyPlus reads them: {listed}"
    ]


def _suggest(name: str, options) -> str:
    """`` (did you mean 'X'?)`` naming the options closest to ``name``, or "".

    The options equal to ``name`` but for case come first (``Space1-1`` for the IDF's
    ``SPACE1-1``: names are matched as written, and difflib alone, which compares case, finds
    nothing), then the close matches ignoring case.

    Parameters
    ----------
    name : str
        The name that matched nothing.
    options : iterable of str
        The names it could be.
    """
    import difflib

    by_folded: dict[str, str] = {}
    for option in map(str, options):
        by_folded.setdefault(option.casefold(), option)
    folded = str(name).casefold()
    same_but_case = [o for o in map(str, options) if o.casefold() == folded]
    if same_but_case:
        return (
            f" (did you mean {', '.join(map(repr, same_but_case))}? names are matched as "
            "written, case included)"
        )
    close = difflib.get_close_matches(folded, list(by_folded), n=3)
    return f" (did you mean {', '.join(repr(by_folded[c]) for c in close)}?)" if close else ""


def main_orientation(building, zone: str) -> str:
    """Azimuth of the zone's largest exterior wall, rounded to 45 degrees, or "interior"."""
    walls: dict[float, float] = {}
    for surface in building.surfaces.values():
        if surface.zone == zone and surface.boundary == "outdoors" and 45 < surface.tilt < 135:
            key = float(round(surface.azimuth / 45.0) * 45 % 360)
            walls[key] = walls.get(key, 0.0) + surface.area
    if not walls:
        return "interior"
    return f"{max(walls, key=walls.get):g} deg"


def shared_areas(building, zone: str) -> dict[str, float]:
    """Area of the inter-zone surfaces between ``zone`` and each neighbour [m2]."""
    areas: dict[str, float] = {}
    for surface in building.surfaces.values():
        if surface.boundary != "zone":
            continue
        if surface.zone == zone and surface.other_zone and surface.other_zone != zone:
            areas[surface.other_zone] = areas.get(surface.other_zone, 0.0) + surface.area
    return areas


def zone_sources(building, mapping: SensorMapping) -> dict[str, ZoneSource]:
    """The source of every zone's reference (own sensors, named substitute or neighbour)."""
    zones = list(building.zones)
    for sensor, zone in mapping.sensors.items():
        if zone not in building.zones:
            raise ThermocalInputError(
                f"{mapping.source}: sensor {sensor!r} is mapped to {zone!r}, which is not a zone "
                f"of building '{building.name}'{_suggest(zone, zones)}"
            )
    own: dict[str, list[str]] = {}
    for sensor, zone in mapping.sensors.items():
        if sensor not in mapping.ignore:
            own.setdefault(zone, []).append(sensor)
    sources: dict[str, ZoneSource] = {
        zone: ZoneSource("sensor", tuple(sensors), zone, f"{len(sensors)} own sensor(s)")
        for zone, sensors in own.items()
    }
    for zone, use in mapping.substitutes.items():
        for name in (zone, use):
            if name not in building.zones:
                raise ThermocalInputError(
                    f"{mapping.source}: zones.{zone}: {name!r} is not a zone of building "
                    f"'{building.name}'{_suggest(name, zones)}"
                )
        if zone in own:
            raise ThermocalInputError(
                f"{mapping.source}: zone {zone!r} has its own sensor(s) {own[zone]} and a named "
                f"substitute {use!r}; remove one of the two"
            )
        if use not in own:
            raise ThermocalInputError(
                f"{mapping.source}: zones.{zone} uses {use!r}, which has no sensor; name a zone "
                "with a sensor"
            )
        sources[zone] = ZoneSource("named", tuple(own[use]), use, "named in the mapping")
    # every per-zone entry names a zone: one misspelt would be left out without a word
    per_zone = (
        mapping.treatments,
        mapping.zone_radiant_fraction,
        mapping.zone_sensor,
        mapping.zone_plausible,
    )
    for zone in (zone for entries in per_zone for zone in entries):
        if zone not in building.zones:
            raise ThermocalInputError(
                f"{mapping.source}: zones.{zone}: {zone!r} is not a zone of building "
                f"'{building.name}'{_suggest(zone, zones)}"
            )
    for zone in zones:
        if zone in sources:
            continue
        treatment = mapping.treatments.get(zone, mapping.unsensed)
        if treatment == "float":
            where = "per zone" if zone in mapping.treatments else "the default"
            sources[zone] = ZoneSource(
                "float", (), zone, f"no sensor: floats freely (Q_ID = 0; {where})"
            )
            continue
        neighbours = {z: a for z, a in shared_areas(building, zone).items() if z in own}
        if not neighbours:
            sources[zone] = ZoneSource(
                "float",
                (),
                zone,
                "no sensor and no adjacent zone with a sensor: floats freely (Q_ID = 0)",
            )
            continue
        orientation = main_orientation(building, zone)
        same = {z: a for z, a in neighbours.items() if main_orientation(building, z) == orientation}
        pool = same or neighbours
        chosen = max(sorted(pool), key=pool.get)
        reason = (
            f"adjacent, {'same' if same else 'different'} orientation ({orientation}), "
            f"shared area {pool[chosen]:.1f} m2 (largest of {len(pool)} candidate(s))"
        )
        sources[zone] = ZoneSource("neighbour", tuple(own[chosen]), chosen, reason)
    return {zone: sources[zone] for zone in zones}


@dataclass
class ReferenceReport:
    """How the zone references were built.

    Attributes
    ----------
    sources : dict of zone -> ZoneSource
    interpolated : DataFrame
        Gaps filled by linear interpolation (zone, start, end, hours).
    substituted : DataFrame
        Longer gaps filled with another zone's reference (zone, from_zone, start, end, hours).
    quality : thermocal.io.measurements.QualityReport
    accepted_constant_readings : list of dict
        Long constant readings accepted as a controlled room (not refused as stuck): one
        record per run (:func:`check_sensor_plausibility`); :meth:`constant_notes` says them.
    setpoint_excursions : list of dict
        Zones whose reading stays beyond a set point the building file holds them at
        (:func:`setpoint_excursions`); :meth:`setpoint_notes` says them.
    """

    sources: dict
    interpolated: pd.DataFrame
    substituted: pd.DataFrame
    quality: object
    accepted_constant_readings: list = field(default_factory=list)
    setpoint_excursions: list = field(default_factory=list)

    def constant_notes(self) -> list[str]:
        """One note per sensor whose long constant reading was accepted (for the outputs)."""
        return accepted_constant_notes(self.accepted_constant_readings)

    def removed_readings(self) -> list[dict]:
        """The readings removed before the identification (:func:`removed_readings`)."""
        return removed_readings(self.quality, self.sources)

    def setpoint_notes(self) -> list[str]:
        """One note per zone whose reading stays beyond its set point (for the outputs)."""
        return [setpoint_excursion_text(r) for r in self.setpoint_excursions]

    def removed_notes(self) -> list[str]:
        """One note on the readings removed, if any (:func:`removed_readings_note`)."""
        records = self.removed_readings()
        counts = removed_counts(self.quality, {r["sensor"] for r in records})
        note = removed_readings_note(records, counts)
        return [note] if note else []

    def zone_table(self) -> pd.DataFrame:
        rows = []
        for zone, src in self.sources.items():
            rows.append(
                {
                    "zone": zone,
                    "source": src.kind,
                    "from_zone": src.zone,
                    "sensors": ", ".join(src.sensors),
                    "reason": src.reason,
                }
            )
        return pd.DataFrame(rows)


def frame_over_own_array(reference: pd.DataFrame) -> tuple[pd.DataFrame, np.ndarray]:
    """The zone references as a frame over a writable C-ordered (steps x zones) array, and
    that array: the tracking reads the array, the user the frame, one copy between them.

    Parameters
    ----------
    reference : DataFrame (steps x zones) [C]

    Returns
    -------
    frame : DataFrame (steps x zones) [C]
        The same values, index and columns, a view of ``values``.
    values : ndarray (steps, zones) [C]
    """
    values = np.array(reference.to_numpy(dtype=float), order="C")  # writable, its own
    frame = pd.DataFrame(values, index=reference.index, columns=reference.columns, copy=False)
    return frame, values


def zone_references(
    raw: pd.DataFrame,
    building,
    mapping: SensorMapping,
    times: pd.DatetimeIndex,
    step: pd.Timedelta,
    *,
    max_gap: str | pd.Timedelta = "1h",
    silence: str | pd.Timedelta = "15min",
    source: str = "sensor log",
) -> tuple[pd.DataFrame, ReferenceReport]:
    """Reference temperature of every zone on the simulation grid [C].

    The reference of step ``[t, t + dt)`` is the temperature the model must reach at its end:
    the time-weighted mean of the linearly interpolated sensor signal over
    ``[t + dt/2, t + 3 dt/2)``, centred on ``t + dt`` (exactly the temperature at ``t + dt``
    for a signal linear over the window; :func:`thermocal.io.measurements.resample_measurements`
    with ``how="mean_linear"``; a silence longer than ``silence`` is a gap). Several sensors in
    a zone are averaged; a zone without own data at a step takes its source zone's (named
    substitute or neighbour).

    Parameters
    ----------
    raw : DataFrame
        Sensor log from :func:`thermocal.io.measurements.read_measurements` [C].
    building : Building
    mapping : SensorMapping
    times : DatetimeIndex
        Step starts of the simulation (tz-aware).
    step : Timedelta
    max_gap : str or Timedelta
        Gaps of a zone's data up to this long are linearly interpolated (and reported); longer
        gaps take the reference of an adjacent sensored zone (reported), or are an error when
        the zone has none.
    silence : str or Timedelta
        Longest silence across which a sensor's last report is held (a sensor reporting every
        5 minutes that stays silent longer has dropped out). A sensor that reports less often
        (its own interval, the median spacing of its values in the period, longer than
        ``silence``) but at most every ``max_gap`` is bridged on its own terms: a silence up to
        :data:`OWN_INTERVAL_TOLERANCE` times its interval (at most ``max_gap``) is no gap, and
        a :class:`ReferenceWarning` says so; one that reports less often than ``max_gap`` is an
        error (raise ``silence`` to bridge it).
    source : str
        Name of the log, for messages.

    Returns
    -------
    reference : DataFrame (steps x tracked zones) [C]
        One column per zone that is not floating.
    report : ReferenceReport

    Raises
    ------
    thermocal.errors.ThermocalInputError
        A sensor of the log mapped to no zone, a mapped sensor absent from the log or without a
        value in the period, a sensor reporting less often than both ``silence`` and
        ``max_gap``, a log that does not overlap the period, a sensor in the wrong unit or
        stuck, a zone gap with no zone to take over.

    Warns
    -----
    ReferenceWarning
        Sensors bridged on their own reporting interval (one warning for all); a zone whose
        reference is taken from another zone for more than :data:`SUBSTITUTED_WARN_SHARE` of
        the period; two sensors of one zone more than :data:`SENSOR_DISAGREEMENT` apart on
        average; a sensor under ``ignore:`` that is not in the log or is also mapped.
    """
    from thermocal.io.measurements import resample_measurements

    max_gap = pd.Timedelta(max_gap)
    sources = zone_sources(building, mapping)
    logged = _sensor_names(raw)
    unmapped = sorted(set(logged) - set(mapping.sensors) - set(mapping.ignore))
    if unmapped:
        raise ThermocalInputError(
            f"{source}: sensor(s) {unmapped[:10]} are mapped to no zone in {mapping.source}; "
            "add them under 'sensors:' (sensor: zone) or list them under 'ignore:'"
        )
    absent = sorted(set(mapping.sensors) - set(logged) - set(mapping.ignore))
    if absent:
        raise ThermocalInputError(
            f"{mapping.source}: sensor(s) {absent[:10]} do not occur in {source}"
            f"{_suggest(absent[0], logged)}"
        )
    _warn_about_ignored(mapping, sources, logged, source)
    tz = times.tz
    half = step / 2
    start, end = times[0] + half, times[-1] + step + half
    first, last = log_span(raw)
    if tz is not None and first.tzinfo is not None:
        first, last = first.tz_convert(tz), last.tz_convert(tz)
    if last <= times[0] or first >= times[-1] + step:
        raise ThermocalInputError(
            f"{source} covers [{first}, {last}], which does not overlap the simulated period "
            f"[{times[0]}, {times[-1] + step}); check the period, and the time zones of the log "
            "and of the weather file"
        )
    silence = pd.Timedelta(silence)
    checked = [s for s in mapping.sensors if s not in mapping.ignore]
    silences = _sensor_silences(
        raw, checked, mapping, start, end, silence, max_gap, (times[0], times[-1] + step), source
    )
    grid, quality = resample_measurements(
        raw,
        step,
        how="mean_linear",
        # one silence for all (bit-identical to before) unless a sensor reports less often
        max_gap=silences or silence,
        start=start,
        end=end,
        # every mapped sensor is an air temperature, whatever its name: a reading outside
        # physical limits (a logger's -999) or an isolated spike (a DS18B20's power-on 85 C)
        # becomes a gap, which the inverse would otherwise track with absurd heat
        quantities={s: "temperature" for s in checked},
        limits={s: READING_LIMITS for s in checked},
        outliers="remove",
    )
    _warn_removed_readings(quality, mapping, source)
    check_level_excursions(raw, checked, mapping, source, period=(start, end))
    # pandas deep-copies ``attrs`` (the sensors' units) into every column and frame taken from
    # the grid; they are not used below: drop them once
    grid.attrs = {}
    if grid.index.tz is not None and tz is not None:
        grid.index = grid.index.tz_convert(tz)
    grid = grid.reindex(times + half)
    grid.index = times
    checked = [c for c in grid.columns if c in mapping.sensors and c not in mapping.ignore]
    declared_units = raw.attrs.get("measurements", {}).get("units_in_file", {})
    accepted_constant = check_sensor_plausibility(
        grid[checked],
        mapping,
        step,
        source,
        declared_units=declared_units,
        raw=raw,
        setpoints=lambda: zone_setpoints(building, times),
    )
    for sensor in checked:
        if grid[sensor].isna().all():
            raise ThermocalInputError(
                f"{source}: sensor {sensor!r} (zone {mapping.sensors[sensor]!r}) gives no "
                f"temperature in the period [{times[0]}, {times[-1] + step}): its values there "
                "are outside physical limits or isolated (see the quality report); remove it "
                f"from {mapping.source}, list it under 'ignore:', or fix the log"
            )
    own = {}
    for zone, src in sources.items():
        if src.kind == "sensor":
            own[zone] = grid[list(src.sensors)].mean(axis=1, skipna=True)
            _warn_if_sensors_disagree(grid[list(src.sensors)], zone, mapping, source)
    tracked = {zone: src for zone, src in sources.items() if src.kind != "float"}
    reference = pd.DataFrame(index=times, columns=list(tracked), dtype=float)
    interpolated, substituted = [], []
    for zone, src in tracked.items():
        series = own.get(zone, own.get(src.zone)).copy()
        series, filled = _interpolate_short_gaps(series, max_gap)
        series, held = _hold_edge_step(series, last, step, "last")
        series, held_first = _hold_edge_step(series, first, step, "first")
        interpolated += [{"zone": zone, **gap} for gap in held_first + filled + held]
        reference[zone] = series
    measured = reference.copy()  # before any zone takes over another's gap
    excursions = setpoint_excursions(
        measured[[z for z, src in tracked.items() if src.kind == "sensor"]],
        lambda: held_setpoints(building, times),
        heated_or_cooled(building),
        step,
        sources,
    )
    for record in excursions:
        text = setpoint_excursion_text(record)
        warnings.warn(f"{source}: {text}", ReferenceWarning, stacklevel=2)
    for zone, src in tracked.items():
        missing = reference[zone].isna()
        if not missing.any():
            continue
        fallback = _fallback_zone(building, zone, src, sources, reference, measured)
        if fallback is None:
            first_missing = reference.index[missing.argmax()]
            if (
                not missing.iloc[: missing.argmax()].any()
                and missing.iloc[missing.argmax() :].all()
            ):
                raise ThermocalInputError(
                    f"zone {zone!r} (sensors {', '.join(src.sensors)}) has no data for the last "
                    f"{missing.sum() * step / pd.Timedelta('1h'):.2f} h of the period (from "
                    f"{first_missing}): {source} ends at {last}; end the period there (--end) or "
                    "extend the log"
                )
            if (
                missing.iloc[0]
                and not missing.iloc[missing.argmin() :].any()
                and missing.argmin() > 0
            ):
                lead = missing.argmin()
                raise ThermocalInputError(
                    f"zone {zone!r} (sensors {', '.join(src.sensors)}) has no data for the first "
                    f"{lead * step / pd.Timedelta('1h'):.2f} h of the period (until "
                    f"{reference.index[lead]}): {source} starts at {first}; start the period "
                    "there (--start) or extend the log"
                )
            raise ThermocalInputError(
                f"zone {zone!r} (sensors {', '.join(src.sensors)}) has no data for "
                f"{missing.sum() * step / pd.Timedelta('1h'):.1f} h (first at {first_missing}), "
                f"longer than max_gap = {max_gap}, and no adjacent zone with data to take over; "
                "raise max_gap, name a substitute under 'zones:' in the mapping, or shorten the "
                "period"
            )
        for gap in _runs(missing.to_numpy(), reference.index, step):
            substituted.append({"zone": zone, "from_zone": fallback, **gap})
        reference.loc[missing, zone] = reference.loc[missing, fallback]
        share = float(missing.mean())
        if share > SUBSTITUTED_WARN_SHARE:
            hours = step / pd.Timedelta("1h")
            warnings.warn(
                f"zone {zone!r} takes its reference from zone {fallback!r} for "
                f"{100 * share:.0f} % of the period ({missing.sum() * hours:.1f} h of "
                f"{len(missing) * hours:.1f} h, first at {reference.index[missing.argmax()]}): "
                f"sensor(s) {', '.join(src.sensors)} in {source} have no data there, so its "
                f"identified heat follows the temperatures of {fallback!r}, not its own; fill "
                "the log or shorten the period (the gaps: substituted_gaps in "
                "identification.json)",
                ReferenceWarning,
                stacklevel=2,
            )
    report = ReferenceReport(
        sources=sources,
        interpolated=pd.DataFrame(interpolated, columns=["zone", "start", "end", "hours"]),
        substituted=pd.DataFrame(
            substituted, columns=["zone", "from_zone", "start", "end", "hours"]
        ),
        quality=quality,
        accepted_constant_readings=accepted_constant,
        setpoint_excursions=excursions,
    )
    return reference, report


#: Readings of a mapped sensor outside this range are removed as impossible [C]: wide enough
#: for a log in Kelvin, Fahrenheit or tenths of a degree, which the unit checks then name
#: (:func:`check_sensor_plausibility`); beyond it a missing-value code (-999, 9999, a
#: disconnected DS18B20's -127).
READING_LIMITS = (-100.0, 400.0)
#: A reading that jumps by more than this from the readings around it and back is no room's
#: air temperature [K]: a room's air changes by a few kelvin per reporting interval at most
#: (a heating set-back's recovery under an ideal heater: the set-back's 4-6 K in one step).
EXCURSION_JUMP = 10.0
#: Longest excursion called one (a logger's dropout to 0 C for hours) [duration]; a longer
#: one is a stuck sensor's run (:data:`STUCK_AFTER`) or the room's own state.
EXCURSION_LONGEST = pd.Timedelta("1D")


def check_level_excursions(
    raw: pd.DataFrame, sensors, mapping: SensorMapping, source: str, *, period=(None, None)
) -> None:
    """Refuse a sensor whose readings jump away by more than :data:`EXCURSION_JUMP` and back.

    Runs of one or two readings are isolated spikes, which the resampling removes (the
    QARTOD-style spike test); a longer run, up to :data:`EXCURSION_LONGEST`, is a logger's
    dropout or missing-value code for hours, which no resampling can tell from the room.

    Parameters
    ----------
    raw : DataFrame
        The sensor log as read (long or wide) [C].
    sensors : sequence of str
        The mapped sensors checked.
    mapping : SensorMapping
        For the zone of each sensor.
    source : str
        The sensor log, for messages.
    period : (Timestamp or None, Timestamp or None)
        The readings checked (the period with its margins); None: no limit.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Naming the sensor, its zone, the excursion's span and levels, and what to do.
    """
    from thermocal.io.measurements.quality import level_excursions

    for sensor, (times, values) in _raw_series(raw, [str(s) for s in sensors]).items():
        keep = np.ones(len(values), dtype=bool)
        if period[0] is not None and len(times) and (times.tz is None) == (period[0].tz is None):
            keep &= np.asarray(times >= period[0]) & np.asarray(times <= period[1])
        times, values = times[keep], values[keep]
        if len(values) < 3:
            continue
        order = np.argsort(times.asi8, kind="stable")
        times, values = times[order], values[order].copy()
        values[(values < READING_LIMITS[0]) | (values > READING_LIMITS[1])] = np.nan
        spacing = pd.Timedelta(int(np.median(np.diff(times.asi8))), unit="ns")
        longest = max(3, int(EXCURSION_LONGEST / max(spacing, pd.Timedelta("1s"))))
        found = level_excursions(values, EXCURSION_JUMP, longest, min_run=3)
        if not found:
            continue
        first, end = found[0]
        level = float(np.nanmedian(values[first:end]))
        around = float(np.nanmedian(values[max(0, first - 12) : first]))
        zone = mapping.sensors.get(str(sensor))
        raise ThermocalInputError(
            f"{source}: sensor {str(sensor)!r}" + (f" (zone {zone!r})" if zone else "")
            + f" reads about {level:.1f} C from {times[first]} to {times[end - 1]}, jumping "
            f"there from about {around:.1f} C and back ({len(found)} such excursion(s) of more "
            f"than {EXCURSION_JUMP:g} K in one reading): a logger's dropout or missing-value "
            "code, not the room's air, and the identification would track it with an absurd "
            "heat; remove those readings from the log (empty cells: a gap) and run again"
        )  # fmt: skip


def _raw_series(raw: pd.DataFrame, sensors) -> dict[str, tuple[pd.DatetimeIndex, np.ndarray]]:
    """Each sensor's reading times and finite values in the log as read (long or wide) [C].

    A long log is grouped once (comparing its 810,746 rows with each of the clinic's 82 sensors
    in turn took 7.7 s).
    """
    wanted = set(sensors)
    out = {}
    if {"sensor", "value"} <= set(raw.columns):
        groups = (
            (str(name), pd.DatetimeIndex(rows["time"]), rows["value"])
            for name, rows in raw.groupby("sensor", observed=True, sort=False)
        )
    else:
        groups = (
            (str(c), pd.DatetimeIndex(raw.index), raw[c]) for c in raw.columns if str(c) in wanted
        )
    for name, times, values in groups:
        if name not in wanted:
            continue
        values = pd.to_numeric(values, errors="coerce").to_numpy(float)
        finite = np.isfinite(values)
        out[name] = (times[finite], values[finite])
    return out


def removed_readings(quality, sources: Mapping | None = None) -> list[dict]:
    """The readings the resampling removed, one record each (``removed_readings`` in
    ``identification.json``).

    Parameters
    ----------
    quality : thermocal.io.measurements.QualityReport
        The resampling's quality report (its ``flags``; at most 1000 per sensor and flag).
    sources : mapping of zone -> ZoneSource, optional
        For the zone of each sensor; None: no zone.

    Returns
    -------
    list of dict
        ``sensor``, ``zone``, ``time`` (ISO 8601), ``value_C`` [C], ``flag`` ("impossible" or
        "outlier"), ``reason`` (the rule that removed it), in time order per sensor.
    """
    flags = getattr(quality, "flags", None)
    if flags is None or flags.empty:
        return []
    zone_of = {
        sensor: zone for zone, src in (sources or {}).items() if src.kind == "sensor"
        for sensor in src.sensors
    }  # fmt: skip
    removed = flags[flags["action"] == "removed"]
    if sources is not None:  # the mapped sensors (not those under 'ignore:')
        removed = removed[removed["sensor"].astype(str).isin(list(zone_of))]
    removed = removed.sort_values(["sensor", "time"], kind="stable")
    return [
        {
            "sensor": str(row.sensor),
            "zone": zone_of.get(str(row.sensor)),
            "time": pd.Timestamp(row.time).isoformat(),
            "value_C": float(row.value),
            "flag": str(row.flag),
            "reason": str(row.reason),
        }
        for row in removed.itertuples(index=False)
    ]


#: The resampling's quality report lists at most this many flagged reports per sensor and
#: flag ("impossible", "outlier"; :mod:`thermocal.io.measurements.resample`); its per-sensor
#: counts (``n_impossible``, ``n_outliers_removed``) are complete.
FLAGS_LISTED_PER_KIND = 1000


def removed_counts(quality, sensors=None) -> dict[str, int]:
    """How many readings of each sensor the resampling removed, all of them: its impossible
    values and the spikes it removed (the quality report's ``n_impossible`` and
    ``n_outliers_removed``; its ``flags`` list at most :data:`FLAGS_LISTED_PER_KIND` of each).

    Parameters
    ----------
    quality : thermocal.io.measurements.QualityReport
    sensors : iterable of str, optional
        The sensors counted; None: all.

    Returns
    -------
    dict of str -> int
        Sensor -> readings removed [-], for the sensors with any.
    """
    table = getattr(quality, "sensors", None)
    if table is None or getattr(table, "empty", True):
        return {}
    wanted = None if sensors is None else {str(s) for s in sensors}
    out = {}
    for sensor, row in table.iterrows():
        if wanted is not None and str(sensor) not in wanted:
            continue
        count = 0
        for column in ("n_impossible", "n_outliers_removed"):
            value = row.get(column, 0)
            count += int(value) if pd.notna(value) else 0
        if count:
            out[str(sensor)] = count
    return out


def removed_readings_note(
    records: Sequence[Mapping], counts: Mapping[str, int] | None = None
) -> str | None:
    """One sentence for the outputs on the readings removed before the identification.

    Parameters
    ----------
    records : sequence of dict
        From :func:`removed_readings`.
    counts : mapping of sensor -> int, optional
        The true number removed per sensor (:func:`removed_counts`): ``records`` hold at most
        :data:`FLAGS_LISTED_PER_KIND` per sensor and flag. None: ``records`` are all.

    Returns
    -------
    str or None
        None when nothing was removed.
    """
    if not records:
        return None
    per_sensor: dict[str, list] = {}
    for record in records:
        per_sensor.setdefault(record["sensor"], []).append(record)
    number = {
        sensor: max(len(rows), int((counts or {}).get(sensor, 0)))
        for sensor, rows in per_sensor.items()
    }
    parts = [
        f"{sensor} ({rows[0]['zone']}): {number[sensor]}, the first {rows[0]['value_C']:g} C at "
        f"{rows[0]['time']}"
        for sensor, rows in list(per_sensor.items())[:5]
    ]
    more = f" and {len(per_sensor) - 5} more sensor(s)" if len(per_sensor) > 5 else ""
    total = sum(number.values())
    if total > len(records):
        listed = (
            f" (removed_readings in identification.json lists {len(records)} of them, with "
            f"time, value and reason: the first {FLAGS_LISTED_PER_KIND} of each sensor's "
            "impossible values and of its spikes)."
        )
    else:
        listed = " (each with its time, value and reason: removed_readings in identification.json)."
    return (
        f"{total} sensor reading(s) removed before the identification as physically "
        "impossible (a logger's missing-value code) or as isolated spikes, and bridged as gaps: "
        + "; ".join(parts) + more + listed
    )


def _warn_removed_readings(quality, mapping: SensorMapping, source: str) -> None:
    """One :class:`ReferenceWarning` per mapped sensor with readings removed as impossible or
    as isolated spikes, with the true count (:func:`removed_counts`; ``removed_readings`` in
    ``identification.json`` lists at most :data:`FLAGS_LISTED_PER_KIND` of each kind)."""
    flags = getattr(quality, "flags", None)
    if flags is None or flags.empty:
        return
    removed = flags[(flags["action"] == "removed") & flags["sensor"].isin(list(mapping.sensors))]
    counts = removed_counts(quality, set(removed["sensor"].astype(str)))
    for sensor, rows in removed.groupby("sensor", sort=True):
        first = rows.iloc[0]
        count = max(len(rows), counts.get(str(sensor), 0))
        lists = (
            "lists each (time, value, reason)"
            if count <= len(rows)
            else f"lists {len(rows)} of them (time, value, reason: the first "
            f"{FLAGS_LISTED_PER_KIND} of each kind)"
        )
        warnings.warn(
            f"{source}: sensor {sensor!r} (zone {mapping.sensors[sensor]!r}): {count} "
            f"reading(s) removed as {' or '.join(sorted(set(rows['flag'])))} (the first "
            f"{first['value']:g} at {first['time']}; a logger's missing-value code or a spike), "
            f"bridged as gaps; removed_readings in identification.json {lists} and report.html "
            "counts them",
            ReferenceWarning,
            stacklevel=3,
        )


class ReferenceWarning(UserWarning):
    """How the zone references were built needs the user's attention (a sensor bridged on its
    own reporting interval, a zone following another zone's data for a large share)."""


#: A zone whose reference is taken from another zone (its own data missing for longer than
#: ``max_gap``) for more than this share of the period is named in a :class:`ReferenceWarning`
#: (on the console of ``thermocal identify``), not only in the report: its identified heat is
#: then largely the other zone's. 10 %: a few hours of a multi-day period pass unremarked.
SUBSTITUTED_WARN_SHARE = 0.10

#: Mean absolute difference [K] over the period between two air-temperature sensors of one
#: zone above which they are named in a :class:`ReferenceWarning`: two sensors in one room
#: differ by their height (stratification; ISO 7730 / ASHRAE 55 allow 3 K between head and
#: ankle, a heated room shows well below 2 K between two wall sensors) and position; 2 K on
#: average is more, and their mean, the zone's reference, is then a temperature neither
#: measures (a sensor in the room above, at a heater or in the sun).
SENSOR_DISAGREEMENT = 2.0

#: The same for a zone whose sensors see the surfaces (``sensor: operative`` or an air weight
#: below 1) [K]: a globe beside a cold window or in the sun differs more from one in the
#: middle of the room than two air sensors do.
SENSOR_DISAGREEMENT_SURFACES = 3.0


def sensor_disagreement(values: pd.DataFrame) -> tuple[str, str, float, float] | None:
    """The two sensors of one zone that differ most: names, mean and largest difference.

    Parameters
    ----------
    values : DataFrame
        The zone's sensors on the simulation grid [C], one column each (NaN where missing).

    Returns
    -------
    (str, str, float, float) or None
        The pair with the largest mean absolute difference [K] over the steps where both
        have a value, that mean [K] and their largest difference [K]; None with fewer than
        two sensors or no common step.
    """
    worst = None
    columns = list(values.columns)
    for i, first in enumerate(columns):
        for second in columns[i + 1 :]:
            difference = (values[first] - values[second]).abs().dropna()
            if difference.empty:
                continue
            mean = float(difference.mean())
            if worst is None or mean > worst[2]:
                worst = (str(first), str(second), mean, float(difference.max()))
    return worst


def _warn_if_sensors_disagree(
    values: pd.DataFrame, zone: str, mapping: SensorMapping, source: str
) -> None:
    """A :class:`ReferenceWarning` when two sensors of ``zone`` differ by more than
    :data:`SENSOR_DISAGREEMENT` on average (:data:`SENSOR_DISAGREEMENT_SURFACES` for sensors
    that see the surfaces, by the mapping's sensor model).

    Parameters
    ----------
    values : DataFrame
        The zone's sensors on the simulation grid [C].
    zone : str
    mapping : SensorMapping
        For the zone's sensor model and the file name in the message.
    source : str
        The sensor log, for the message.
    """
    pair = sensor_disagreement(values)
    if pair is None:
        return
    first, second, mean, largest = pair
    model = mapping.zone_sensor.get(zone, mapping.sensor)
    air_weight = 1.0 if model is None else float(model)
    threshold = SENSOR_DISAGREEMENT if air_weight >= 1.0 else SENSOR_DISAGREEMENT_SURFACES
    if mean <= threshold:
        return
    kind = "air-temperature sensors" if air_weight >= 1.0 else "sensors that see the surfaces"
    warnings.warn(
        f"zone {zone!r}: sensors {first!r} and {second!r} in {source} differ by {mean:.1f} K "
        f"on average over the period (largest {largest:.1f} K), more than the {threshold:g} K "
        f"two {kind} of one room differ by; the zone's reference is the mean of its "
        f"{values.shape[1]} sensors, a temperature none of them measures: check that both hang "
        f"in {zone!r} (not in another room, at a heater or window, in the sun), then map the "
        f"odd one to its zone or list it under 'ignore:' in {mapping.source}; a zone that "
        "spans several rooms (a floor, a perimeter zone) may differ this much between them: "
        "then the mean is the zone's temperature and nothing needs changing",
        ReferenceWarning,
        stacklevel=3,
    )


def _warn_about_ignored(
    mapping: SensorMapping, sources: dict, logged: list[str], source: str
) -> None:
    """A :class:`ReferenceWarning` for the sensors under ``ignore:`` that are not in the log
    (ignoring them changes nothing: a typo?) and for those also mapped under ``sensors:``
    (they are left out; the message says what their zones' references become).

    Parameters
    ----------
    mapping : SensorMapping
    sources : dict of zone -> ZoneSource
        :func:`zone_sources` of the mapping.
    logged : list of str
        The sensors of the log.
    source : str
        The sensor log, for messages.
    """
    in_log = set(logged)
    unknown = [name for name in mapping.ignore if name not in in_log]
    if unknown:
        warnings.warn(
            f"{mapping.source}: ignore: sensor(s) {unknown[:10]} do not occur in {source}, so "
            f"ignoring them changes nothing{_suggest(unknown[0], logged)}; a typo? correct the "
            "name(s) or remove them from 'ignore:'",
            ReferenceWarning,
            stacklevel=3,
        )
    mapped = [name for name in mapping.ignore if name in mapping.sensors]
    if mapped:
        zones = [
            f"{name!r} (zone {mapping.sensors[name]!r}: "
            f"{_reference_text(sources[mapping.sensors[name]])})"
            for name in mapped[:10]
        ]
        warnings.warn(
            f"{mapping.source}: sensor(s) {', '.join(zones)} are mapped under 'sensors:' and "
            "listed under 'ignore:': they are left out; to use them, remove them from 'ignore:'",
            ReferenceWarning,
            stacklevel=3,
        )


def _reference_text(src: ZoneSource) -> str:
    """What a zone's reference is, in words, for messages."""
    if src.kind == "sensor":
        return f"its reference from sensor(s) {', '.join(src.sensors)}"
    if src.kind == "float":
        return "no sensor left, it floats with Q_ID = 0"
    return f"no sensor left, it takes zone {src.zone!r}'s data"


#: A sensor reporting less often than ``silence`` (at most every ``max_gap``): silences up to
#: this multiple of its own reporting interval are bridged (a missed report, twice the
#: interval, stays a gap; a late report does not).
OWN_INTERVAL_TOLERANCE = 1.5


def _report_times(raw: pd.DataFrame, names) -> dict[str, np.ndarray]:
    """Sorted times [ns, UTC] of the finite values of the sensors ``names`` (tz-aware logs;
    empty for a log without time zone, which the resampling refuses)."""
    names = [str(n) for n in names]
    if {"sensor", "value"} <= set(raw.columns):
        times = pd.DatetimeIndex(raw["time"])
        if times.tz is None:
            return {}
        value = raw["value"]
        if not pd.api.types.is_numeric_dtype(value.dtype):
            value = pd.to_numeric(value, errors="coerce")
        sensor = raw["sensor"]
        if isinstance(sensor.dtype, pd.CategoricalDtype):  # the reader's: codes, no strings
            all_codes = sensor.cat.codes.to_numpy()
            labels = [str(label) for label in sensor.cat.categories]
        else:
            all_codes, found = pd.factorize(sensor)
            labels = [str(label) for label in found]
        ok = np.isfinite(value.to_numpy(float)) & (all_codes >= 0)
        codes = all_codes[ok]
        stamps = times.as_unit("ns").asi8[ok]
        order = np.lexsort((stamps, codes))
        bounds = np.searchsorted(codes[order], np.arange(len(labels) + 1))
        where = {str(label): i for i, label in enumerate(labels)}
        empty = np.array([], dtype=np.int64)
        return {
            name: stamps[order[bounds[where[name]] : bounds[where[name] + 1]]]
            if name in where
            else empty
            for name in names
        }
    index = pd.DatetimeIndex(raw["time"] if "time" in raw.columns else raw.index)
    if index.tz is None:
        return {}
    stamps = index.as_unit("ns").asi8
    columns = {str(c): c for c in raw.columns}
    out = {}
    for name in names:
        values = pd.to_numeric(raw[columns[name]], errors="coerce").to_numpy(float)
        out[name] = np.sort(stamps[np.isfinite(values)])
    return out


def _duration(delta: pd.Timedelta, *, up: bool = False) -> str:
    """A duration as a command-line value, "30min", "3h", "1h30min" (``up``: whole minutes
    rounded up, else to the nearest)."""
    minutes = delta / pd.Timedelta("1min")
    minutes = math.ceil(minutes - 1e-9) if up else round(minutes)
    hours, rest = divmod(int(minutes), 60)
    if not hours:
        return f"{rest}min"
    return f"{hours}h" + (f"{rest}min" if rest else "")


def _sensor_silences(
    raw: pd.DataFrame,
    sensors,
    mapping: SensorMapping,
    start: pd.Timestamp,
    end: pd.Timestamp,
    silence: pd.Timedelta,
    max_gap: pd.Timedelta,
    period: tuple[pd.Timestamp, pd.Timestamp],
    source: str,
) -> dict[str, pd.Timedelta]:
    """The silence of every logged sensor when one reports less often than ``silence``.

    A sensor's own reporting interval is the median spacing of its values over the resampled
    window ``[start, end]`` (with the values just outside it). One that reports less often than
    ``silence`` but at most every ``max_gap`` gets ``OWN_INTERVAL_TOLERANCE`` times its interval
    (at most ``max_gap``), with a :class:`ReferenceWarning`; the others keep ``silence``.

    Parameters
    ----------
    raw : DataFrame
        The sensor log (long or wide).
    sensors : list of str
        The sensors checked (mapped, not ignored).
    mapping : SensorMapping
        For the zones and the file name in messages.
    start, end : Timestamp
        The resampled window (tz-aware).
    silence, max_gap : Timedelta
        The command's ``--silence`` and ``--max-gap``.
    period : (Timestamp, Timestamp)
        The simulated period, for messages.
    source : str
        The sensor log, for messages.

    Returns
    -------
    dict of sensor -> Timedelta
        One entry per sensor of the log; empty when every sensor keeps ``silence``.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        A sensor without a value in the window, or reporting less often than ``silence`` and
        ``max_gap``.
    """
    times = _report_times(raw, sensors)
    if not times:
        return {}
    lo, hi = start.value, end.value
    own: dict[str, pd.Timedelta] = {}
    intervals: dict[str, pd.Timedelta] = {}
    for sensor in sensors:
        stamps = times[sensor]
        i0 = int(np.searchsorted(stamps, lo, side="left"))
        i1 = int(np.searchsorted(stamps, hi, side="right"))
        where = f"{source}: sensor {sensor!r} (zone {mapping.sensors[sensor]!r})"
        if i1 <= i0:
            found = "none in the log" if stamps.size == 0 else f"{stamps.size} outside the period"
            raise ThermocalInputError(
                f"{where} has no values in the period [{period[0]}, {period[1]}) ({found}): "
                f"remove it from {mapping.source}, list it under 'ignore:', or fix the log"
            )
        spacing = np.diff(stamps[max(i0 - 1, 0) : i1 + 1])
        if spacing.size == 0:
            continue  # one value: the check after the resampling names it
        interval = pd.Timedelta(int(np.median(spacing)), unit="ns")
        if interval <= silence:
            continue
        if interval > max_gap:
            raise ThermocalInputError(
                f"{where} reports every {_duration(interval)} (the median spacing of its "
                f"{i1 - i0} values in the period), longer than --silence {_duration(silence)} "
                f"and --max-gap {_duration(max_gap)}: its readings count as missing between "
                f"reports; raise --silence to at least {_duration(interval, up=True)} (its "
                "values are then interpolated linearly between reports), or list it under "
                f"'ignore:' in {mapping.source}"
            )
        own[sensor] = max(silence, min(OWN_INTERVAL_TOLERANCE * interval, max_gap))
        intervals[sensor] = interval
    if not own:
        return {}
    _warn_sparse_sensors(intervals, own, mapping, silence, max_gap, source)
    return {name: own.get(name, silence) for name in _sensor_names(raw)}


#: Sensors named in the one warning about sensors that report less often than ``--silence``
#: (every sensor and its interval: the debug log, ``-vv``).
SPARSE_NAMED = 5


def _warn_sparse_sensors(
    intervals: dict[str, pd.Timedelta],
    own: dict[str, pd.Timedelta],
    mapping: SensorMapping,
    silence: pd.Timedelta,
    max_gap: pd.Timedelta,
    source: str,
) -> None:
    """One :class:`ReferenceWarning` for the sensors reporting less often than ``silence``.

    One sensor: its name, zone, interval and the silence that is a gap. Several (a whole log
    every hour, a ``--silence`` below the log's interval): how many, the first
    :data:`SPARSE_NAMED` names, the range of their intervals and of the silences that are gaps;
    every sensor's line goes to the debug log (``-vv``) instead of one warning each.

    Parameters
    ----------
    intervals : dict of sensor -> Timedelta
        Own reporting interval of each sparse sensor [duration].
    own : dict of sensor -> Timedelta
        The silence bridged for each of them [duration].
    mapping : SensorMapping
        For the zones.
    silence, max_gap : Timedelta
        The command's ``--silence`` and ``--max-gap``.
    source : str
        The sensor log, for messages.
    """
    lines = {
        sensor: (
            f"{source}: sensor {sensor!r} (zone {mapping.sensors[sensor]!r}) reports every "
            f"{_duration(interval)}, less often than --silence {_duration(silence)}: its "
            f"values are interpolated linearly between reports (shorter than --max-gap "
            f"{_duration(max_gap)}), a silence longer than {_duration(own[sensor])} is a gap"
        )
        for sensor, interval in intervals.items()
    }
    if len(lines) == 1:
        warnings.warn(next(iter(lines.values())), ReferenceWarning, stacklevel=4)
        return
    for line in lines.values():
        _log.debug(line)
    names = sorted(intervals)
    shown = ", ".join(names[:SPARSE_NAMED]) + (", ..." if len(names) > SPARSE_NAMED else "")
    bridged = _duration(max(own.values()), up=True)  # what is bridged now, as the rule
    warnings.warn(
        f"{source}: {len(names)} sensors ({shown}) report every "
        f"{_span(intervals.values())}, less often than --silence {_duration(silence)}: their "
        f"values are interpolated linearly between reports (shorter than --max-gap "
        f"{_duration(max_gap)}), a silence longer than {_span(own.values())} is a gap (each "
        f"sensor: thermocal -vv); --silence {bridged} makes that the rule and this warning goes",
        ReferenceWarning,
        stacklevel=4,
    )


def _span(durations) -> str:
    """"1h", or "30min to 1h" for durations that differ, as command-line values."""
    texts = [_duration(d) for d in sorted(set(durations))]
    return texts[0] if len(texts) == 1 or texts[0] == texts[-1] else f"{texts[0]} to {texts[-1]}"


def _sensor_names(raw: pd.DataFrame) -> list[str]:
    if {"sensor", "value"} <= set(raw.columns):
        return sorted(map(str, raw["sensor"].unique()))
    return [str(c) for c in raw.columns if c not in ("time",)]


def log_span(raw: pd.DataFrame) -> tuple[pd.Timestamp, pd.Timestamp]:
    """The first and last time stamp of a sensor log.

    Parameters
    ----------
    raw : DataFrame
        The log as read by :func:`thermocal.io.measurements.read_measurements`: long (a
        ``time`` column) or wide (time stamps as the index).

    Returns
    -------
    (Timestamp, Timestamp)
        Its first and last reading's time, in the log's own time zone (or naive).
    """
    times = raw["time"] if "time" in raw.columns else raw.index
    times = pd.DatetimeIndex(times)
    return times.min(), times.max()


def log_span_on_grid(
    raw: pd.DataFrame, weather_index: pd.DatetimeIndex, step: pd.Timedelta
) -> tuple[pd.Timestamp | None, pd.Timestamp | None]:
    """The sensor log's span on the simulation grid: the default period of ``thermocal
    identify`` (no ``--start``/``--end``) and of a campaign without ``period:``.

    Parameters
    ----------
    raw : DataFrame
        The log as read by :func:`thermocal.io.measurements.read_measurements` (long or wide).
    weather_index : DatetimeIndex
        The weather's time stamps: their time zone and the grid's origin.
    step : Timedelta
        The simulation step [s resolution], positive.

    Returns
    -------
    (Timestamp, Timestamp) or (None, None)
        The first grid instant at or after the log's first reading and the last at or before
        its last reading, in the weather's time zone; (None, None) when the log or the weather
        has no time zone, the span holds no step or lies outside the weather (the overlap
        check then names both ranges).
    """
    first, last = log_span(raw)
    origin = weather_index[0]
    if first.tzinfo is None or origin.tzinfo is None:
        return None, None
    first, last = first.tz_convert(origin.tz), last.tz_convert(origin.tz)
    start = origin + -((origin - first) // step) * step  # first grid instant at or after
    end = origin + ((last - origin) // step) * step
    end_of_weather = weather_index[-1] + (weather_index[1] - weather_index[0])
    if end <= start or start < origin or end > end_of_weather:
        return None, None
    return start, end


#: A sensor reading exactly the same value for at least this long is stuck.
STUCK_AFTER = pd.Timedelta("1D")


def check_sensor_plausibility(
    grid: pd.DataFrame,
    mapping: SensorMapping,
    step: pd.Timedelta,
    source: str,
    *,
    declared_units: Mapping[str, str | None] | None = None,
    raw: pd.DataFrame | None = None,
    setpoints=None,
) -> list[dict]:
    """Refuse sensors in the wrong unit or stuck, naming file, sensor, zone and what to do.

    * a sensor whose mean is not an indoor temperature, or disagrees with the other sensors by
      a unit-like factor (Kelvin, Fahrenheit, tenths or hundredths of a degree; the conversion
      that brings it next to the others is named);
    * a log whose sensors' median is no indoor temperature either: the whole log is in another
      unit, and every conversion that makes it a building's temperatures is named with the
      values it gives (:func:`thermocal.io.measurements.units.log_unit_slips`: 287 K is
      14 C, or 28.7 C in tenths);
    * a sensor that disagrees with its own history: a day whose mean is such a factor away
      from the sensor's median day (the logger's unit changed);
    * a sensor reading exactly the same value for :data:`STUCK_AFTER` or longer (a frozen
      logger repeats its last value; identifying against it gives a plausible but wrong heat),
      unless :func:`constant_run_reason` explains the run (a set point of the zone, the log's
      resolution) or the mapping accepts it (``constant_readings``): then a
      :class:`ReferenceWarning` says it was accepted and why.

    Parameters
    ----------
    grid : DataFrame
        Sensor temperatures on the simulation grid [C], one column per sensor, NaN where
        missing.
    mapping : SensorMapping
        For the zone of each sensor.
    step : Timedelta
        Grid step.
    source : str
        The sensor log, for messages.
    declared_units : mapping of sensor -> str or None, optional
        The unit each sensor's values were declared in in the log (``units_in_file`` of
        :func:`thermocal.io.measurements.read_measurements`; None: undeclared), for messages.
    raw : DataFrame, optional
        The log as read, for the resolution of a sensor with a long constant run
        (:func:`log_resolution`); None: unknown.
    setpoints : DataFrame or callable returning one, optional
        The zones' set points on the grid (:func:`zone_setpoints`); a callable is called only
        when a sensor has a long constant run. None: none known.

    Returns
    -------
    list of dict
        The long constant readings accepted (warned), one record per run: ``sensor``,
        ``zone``, ``value_C``, ``start``, ``end`` (exclusive), ``duration_h`` and ``why``
        (the set point, the resolution or the mapping's ``constant_readings``); [] when none.

    Raises
    ------
    thermocal.errors.ThermocalInputError
    """
    means = grid.mean(axis=0, skipna=True).dropna()

    def where(sensor) -> str:
        zone = mapping.sensors.get(str(sensor))
        return f"{source}: sensor {str(sensor)!r}" + (f" (zone {zone!r})" if zone else "")

    declared = {
        sensor: mapping.zone_plausible[zone]
        for sensor, zone in mapping.sensors.items()
        if zone in mapping.zone_plausible
    }
    # the sensors judged against the others (those without a declared range), once
    undeclared = np.array([str(s) not in declared for s in means.index], dtype=bool)
    indoor = np.array([_plausible_indoor(float(m)) for m in means], dtype=bool)
    for position, (sensor, mean) in enumerate(means.items()):
        if str(sensor) in declared:
            low, high = declared[str(sensor)]
            if not low <= mean <= high:
                slip = temperature_unit_slip(float(mean), None, plausible=(low, high))
                hint = "" if slip is None or np.isnan(slip[2]) else f" ({slip[0]} {slip[2]:.1f} C)"
                raise ThermocalInputError(
                    f"{where(sensor)} reads {mean:.1f} on average, outside the range "
                    f"[{low:g}, {high:g}] C declared plausible for its zone in {mapping.source}"
                    f"{hint}; correct the unit of the values or the declared range"
                )
            continue
        keep = undeclared.copy()
        keep[position] = False
        keep &= np.asarray(means.index != sensor)
        others = means[keep]
        # judged against the others that read an indoor temperature: a log with a few sensors
        # in Kelvin among Celsius ones names each of them, not "the whole log"
        sensible = means[keep & indoor]
        if len(others) and not len(sensible):
            if _plausible_indoor(float(mean)):
                continue  # the others are wrong: each is named in its turn
            unit = (declared_units or {}).get(str(sensor))
            reference = float(others.median())
            text = _log_unit_text(str(sensor), float(mean), reference, len(others), unit)
            raise ThermocalInputError(f"{where(sensor)} {text}")
        reference = float(sensible.median()) if len(sensible) else None
        slip = temperature_unit_slip(float(mean), reference)
        if slip is None:
            continue
        label, remedy, converted = slip
        company = (
            f", while the other {len(sensible)} sensor(s) reading an indoor temperature average "
            f"{reference:.1f} C"
            if reference is not None
            else ""
        )
        as_converted = "" if np.isnan(converted) else f" (as {converted:.1f} C if so)"
        zone = mapping.sensors.get(str(sensor), "<zone>")
        raise ThermocalInputError(
            f"{where(sensor)} reads {mean:.1f} on average{company}: {label}{as_converted}; "
            f"{remedy.replace('NAME', str(sensor))} and run again (if the zone really is that "
            f"warm or cold, declare it in {mapping.source}: zones: {{{zone}: {{plausible: "
            "[low, high]}} in C)"
        )
    # every sensor's daily means in one resampling (per column the same means as one by one)
    all_daily = grid[list(means.index)].resample("1D").mean()
    for sensor in means.index:
        daily = all_daily[sensor].dropna()
        if len(daily) < 3:
            continue
        typical = float(daily.median())
        # a day is judged against the sensor's own typical day: a warm room's hot day (35 C
        # where it usually reads 29 C) is no unit slip, a day read in tenths or Kelvin is
        low, high = declared.get(str(sensor), INDOOR_MEAN_RANGE)
        if str(sensor) not in declared:
            low = min(low, typical - NEIGHBOUR_TOLERANCE)
            high = max(high, typical + NEIGHBOUR_TOLERANCE)
        for day, value in daily.items():
            slip = temperature_unit_slip(float(value), typical, plausible=(low, high))
            if slip is not None and not np.isnan(slip[2]):
                raise ThermocalInputError(
                    f"{where(sensor)} averages {value:.1f} on {day:%Y-%m-%d} but "
                    f"{typical:.1f} C on a typical day: {slip[0]} The logger's unit seems to "
                    f"change within the log; write all its values in one unit ({slip[1]} for "
                    "that part)"
                )
    steps_per_day = int(round(STUCK_AFTER / step))
    accepted: list[dict] = []
    if not steps_per_day:
        return accepted

    def accept(sensor, run, why: str) -> None:
        accepted.append({
            "sensor": str(sensor),
            "zone": mapping.sensors.get(str(sensor)),
            "value_C": float(grid[sensor].loc[run["start"]]),
            "start": str(run["start"]),
            "end": str(run["end"]),
            "duration_h": float(run["hours"]),
            "why": why,
        })

    for sensor in grid.columns:
        values = grid[sensor].to_numpy(dtype=float)
        same = np.abs(np.diff(values)) <= 1e-9 * np.maximum(1.0, np.abs(values[1:]))
        runs = _runs(np.append(same, False), grid.index, step, min_steps=int(STUCK_AFTER // step))
        long = [r for r in runs if r["hours"] * pd.Timedelta("1h") >= STUCK_AFTER]
        if not long:
            continue
        first = long[0]
        stuck_value = float(grid[sensor].loc[first["start"]])
        head = (
            f"{where(sensor)} reads exactly {stuck_value:g} C from {first['start']} for "
            f"{first['hours'] / 24:.1f} days ({len(long)} such period(s))"
        )
        if mapping.constant_readings_of(str(sensor)) == "accept":
            why = f"'constant_readings' in {mapping.source} accepts it"
            _warn_constant(head, why)
            for run in long:
                accept(sensor, run, why)
            continue
        if callable(setpoints):
            setpoints = setpoints()
        resolution = None if raw is None else log_resolution(_raw_values(raw, str(sensor)))
        reasons = []
        for run in long:
            value = float(grid[sensor].loc[run["start"]])
            reason, why_not = constant_run_reason(
                grid, str(sensor), mapping.sensors.get(str(sensor)), run, value, step,
                setpoints=setpoints, resolution=resolution,
            )  # fmt: skip
            if reason is None:
                days = run["hours"] / 24
                raise ThermocalInputError(
                    f"{where(sensor)} reads exactly {value:g} C from {run['start']} for "
                    f"{days:.1f} days ({len(long)} period(s) of a day or more): a stuck or frozen "
                    "sensor repeats its last value, and identifying against it gives a wrong "
                    f"heat ({why_not}); remove those values from the log (a gap), list the "
                    f"sensor under 'ignore:' in {mapping.source}, or, if the room really read "
                    f"{value:g} C all that time, accept it there with 'constant_readings: "
                    f"{{{sensor}: accept}}' (or 'constant_readings: accept' for every sensor)"
                )
            reasons.append(reason)
        _warn_constant(head, "; ".join(dict.fromkeys(reasons)))
        for run, reason in zip(long, reasons, strict=True):
            accept(sensor, run, reason)
    return accepted


#: A sensor whose values lie on a grid at least this coarse [K] (0.1 K, 0.5 K, 0.1 F) may
#: read one value for days in a controlled room: the room stays within half a step of it.
COARSE_RESOLUTION = 0.05
#: Temperatures a heated or cooled room is held at [C]: a constant outside is no control.
CONTROLLED_RANGE = (10.0, 30.0)
#: Largest difference [K] between a constant reading and a set point it is taken to be (at
#: least; half the sensor's resolution when coarser).
SETPOINT_TOLERANCE = 0.05


def accepted_constant_notes(records: Sequence[Mapping]) -> list[str]:
    """One note per sensor of the long constant readings accepted as a controlled room
    (the records of :func:`check_sensor_plausibility`), for identification.json's and the
    report's notes: the warning's content, kept with the results."""
    by_sensor: dict[str, list[Mapping]] = {}
    for record in records:
        by_sensor.setdefault(str(record["sensor"]), []).append(record)
    notes = []
    for sensor, runs in by_sensor.items():
        zone = runs[0].get("zone")
        periods = "; ".join(
            f"{r['value_C']:g} C from {r['start']} for {r['duration_h'] / 24:.1f} days "
            f"({r['why']})"
            for r in runs
        )
        notes.append(
            f"Constant reading accepted: sensor {sensor!r}"
            + (f" (zone {zone!r})" if zone else "")
            + f" reads exactly {periods}: taken as a room held at that temperature, not "
            "refused as a stuck sensor (accepted_constant_readings in identification.json). "
            "Identifying against a frozen sensor gives a wrong heat: check that the room "
            "really was held there"
        )
    return notes


def _warn_constant(head: str, reason: str) -> None:
    warnings.warn(
        f"{head}: accepted as a room held at that temperature, not refused as a stuck sensor: "
        f"{reason}. Identifying against a frozen sensor gives a wrong heat: check that the room "
        "really was held there",
        ReferenceWarning,
        stacklevel=3,
    )


def constant_run_reason(
    grid: pd.DataFrame,
    sensor: str,
    zone: str | None,
    run: Mapping,
    value: float,
    step: pd.Timedelta,
    *,
    setpoints: pd.DataFrame | None = None,
    resolution: float | None = None,
) -> tuple[str | None, str]:
    """Why a sensor's constant reading over a day or more is a controlled room, if it is.

    The rule (documented in docs/identification.md, "Stuck sensors"):

    1. **Set point**: the value is within :data:`SETPOINT_TOLERANCE` (or half the sensor's
       resolution when coarser) of the zone's heating or cooling set point at every step of
       the run (``setpoints``: the building's thermostat schedules, or its constant set
       points): a room held at its set point.
    2. **Resolution**: the sensor's values lie on a grid of ``resolution`` >=
       :data:`COARSE_RESOLUTION` (0.1 K, 0.5 K: a BMS that logs rounded values, or on change of
       value), the value is in :data:`CONTROLLED_RANGE`, and another sensor of the log changes
       during the run (the logger records; a frozen logger repeats all its columns).

    Parameters
    ----------
    grid : DataFrame
        The sensors on the simulation grid [C].
    sensor, zone : str
        The sensor and its zone (None: unmapped).
    run : mapping
        ``start``, ``end`` (exclusive) and ``hours`` of the run (the grid's times).
    value : float
        The constant [C].
    step : Timedelta
        The grid step.
    setpoints : DataFrame, optional
        :func:`zone_setpoints` on the grid.
    resolution : float, optional
        :func:`log_resolution` of the sensor's values [K].

    Returns
    -------
    (str or None, str)
        The reason it is accepted (None: not explained), and why not (for a refusal).
    """
    rows = slice(run["start"], run["end"] - step)
    tolerance = max(SETPOINT_TOLERANCE, (resolution or 0.0) / 2) + 1e-6
    named = []
    if setpoints is not None and zone is not None and len(setpoints.columns):
        for kind in ("heating", "cooling"):
            if (zone, kind) not in setpoints.columns:
                continue
            named.append(kind)
        if named:
            window = setpoints.loc[rows, [(zone, kind) for kind in named]].to_numpy(float)
            match = np.abs(window - value) <= tolerance
            if len(match) and match.any(axis=1).all():
                kinds = [kind for j, kind in enumerate(named) if match[:, j].any()]
                return (
                    f"{value:g} C is the {' and '.join(kinds)} set point the building declares "
                    f"for zone {zone!r} throughout the run, and a room held at its set point "
                    "reads it",
                    "",
                )
    lacks = (
        f"{value:g} C is no set point the building declares for zone {zone!r} throughout"
        if named
        else f"the building declares no set point for zone {zone!r}"
    )
    low, high = CONTROLLED_RANGE
    if resolution is None:
        return None, f"{lacks}, and the sensor's other values show no coarse resolution"
    if resolution < COARSE_RESOLUTION:
        return None, (
            f"{lacks}, and its values have a resolution of {resolution:.3g} K, too fine for a "
            "room to read the same value for a day"
        )
    if not low <= value <= high:
        return None, (
            f"{lacks}, and {value:g} C is no temperature a room is held at ({low:g} to {high:g} C)"
        )
    others = grid.loc[rows, [c for c in grid.columns if str(c) != sensor]]
    moving = [str(c) for c in others.columns if np.nanmax(others[c]) - np.nanmin(others[c]) > 1e-9]
    if not moving:
        return None, (
            f"{lacks}, and no other sensor of the log changes meanwhile (the logger itself may "
            "have stopped)"
        )
    return (
        f"the log's resolution of {resolution:.3g} K explains it (a room held within "
        f"{resolution / 2:.3g} K of {value:g} C reads it), while other sensors of the log change "
        f"(e.g. {moving[0]!r})",
        "",
    )


def log_resolution(values) -> float | None:
    """The step of the grid a sensor's values lie on [K] (0.1 for a log rounded to 0.1 K), or
    None when they lie on none (fewer than three distinct values, or not evenly stepped).

    Parameters
    ----------
    values : array-like
        The sensor's values [C] (NaN ignored).
    """
    v = np.asarray(values, dtype=float)
    distinct = np.unique(np.round(v[np.isfinite(v)], 6))
    if len(distinct) < 3:
        return None
    step = float(np.diff(distinct).min())
    if step <= 0:
        return None
    k = (distinct - distinct[0]) / step
    if float(np.max(np.abs(k - np.round(k)))) > 0.02:
        return None
    return step


def _raw_values(raw: pd.DataFrame, sensor: str) -> np.ndarray:
    """A sensor's values in the log as read (long or wide) [C]."""
    if {"sensor", "value"} <= set(raw.columns):
        values = raw.loc[(raw["sensor"].astype(str) == sensor).to_numpy(), "value"]
    else:
        columns = {str(c): c for c in raw.columns}
        if sensor not in columns:
            return np.array([], dtype=float)
        values = raw[columns[sensor]]
    return pd.to_numeric(values, errors="coerce").to_numpy(float)


#: A zone's reading beyond its set point by more than this counts as beyond it [K]: a
#: thermostat holds the air within its throttling range (0.5-1 K), and a sensor a few metres
#: from it in the same room reads within about as much (ASHRAE 55 allows 3 K head to ankle;
#: two wall sensors of a heated room read well below 2 K apart, :data:`SENSOR_DISAGREEMENT`).
SETPOINT_MARGIN = 1.0
#: Share of the hours a set point applies above which a zone that stays beyond it is named
#: [-]: a few hours of a short-lived overload pass unremarked.
SETPOINT_EXCURSION_SHARE = 0.05
#: Fewest hours beyond a set point named [h].
SETPOINT_EXCURSION_HOURS = 2.0
#: After a set point moves towards the room's temperature (a set-back ends), the room is
#: allowed this long to reach it (the plant's recovery) [duration].
SETPOINT_RECOVERY = pd.Timedelta("2h")
#: Before a set point moves away from the room's temperature (a set-back begins), the room may
#: leave it this early: a plant switched off ahead of the set-back (optimum stop), a log's clock
#: an hour off [duration].
SETPOINT_EARLY_STOP = pd.Timedelta("1h")


def heated_or_cooled(building) -> set[str] | None:
    """Zones the building file gives heating or cooling equipment.

    Parameters
    ----------
    building : thermocal.multizone.Building

    Returns
    -------
    set of str or None
        An imported IDF's zones with declared HVAC equipment
        (``building.idf_info.zone_heat_delivery``); None for a building without an IDF's
        record (a zone with a set point is then held by it).
    """
    info = getattr(building, "idf_info", None)
    delivery = getattr(info, "zone_heat_delivery", None)
    if info is None or delivery is None:
        return None
    return {str(zone) for zone in delivery}



def held_setpoints(building, times: pd.DatetimeIndex) -> pd.DataFrame:
    """The set points a zone's equipment holds its air at [C]: :func:`zone_setpoints` (NaN on
    the steps all the zone's equipment is switched off by its availability schedule: the
    import's ``idf_info.ideal_loads_availability``, for ideal loads and other equipment alike,
    :func:`thermocal.multizone.idf.hvac.equipment_availability`), without the
    zones whose thermostat holds the operative temperature (``idf_info.operative_fraction``:
    their air legitimately sits beyond the set point, by ``f / (1 - f)`` times the operative
    temperature's distance from the mean radiant one).

    Parameters
    ----------
    building : thermocal.multizone.Building
    times : DatetimeIndex
        The grid (local times of the building's calendar).
    """
    frame = zone_setpoints(building, times)
    if frame.empty:
        return frame
    info = getattr(building, "idf_info", None)
    operative = {str(z) for z, f in (getattr(info, "operative_fraction", None) or {}).items()
                 if f and f > 0}  # fmt: skip
    keep = [c for c in frame.columns if str(c[0]) not in operative]
    return frame[keep].copy()


def _changing(setpoint: np.ndarray, towards: int, after: int, before: int) -> np.ndarray:
    """Steps near a change of a set point: the ``after`` steps from a move in direction
    ``towards`` (+1 up, -1 down) or a switch-on (NaN to a value), the room still on its way
    there; the ``before`` steps up to a move the other way or a switch-off, where a plant that
    stops early (optimum stop) or a log's clock an hour off lets the room leave it first."""
    previous = np.r_[np.nan, setpoint[:-1]]
    with np.errstate(invalid="ignore"):
        rise = towards * (setpoint - previous)
        onto = (rise > 0.01) | (np.isnan(previous) & np.isfinite(setpoint))
        away = (rise < -0.01) | (np.isfinite(previous) & np.isnan(setpoint))
    onto[0] = away[0] = False
    out = np.zeros(setpoint.size, dtype=bool)
    for i in np.flatnonzero(onto):
        out[i : i + after] = True
    for i in np.flatnonzero(away):
        out[max(0, i - before) : i] = True
    return out


def setpoint_excursions(
    measured: pd.DataFrame,
    setpoints,
    equipped: set[str] | None,
    step: pd.Timedelta,
    sources: Mapping | None = None,
) -> list[dict]:
    """Zones whose measured temperature stays beyond a set point the building file holds them
    at.

    A zone the file heats (or cools) to a set point cannot stay well below its heating set
    point (above its cooling set point) for long: the file's heating (cooling) would act. A
    reading that does is not the room's air as the file's plant holds it: a sensor in the sun
    or near a heat source (above), against a cold window or in a draught (below), or set
    points in the file that are not the building's; the identified heat then follows the
    reading and is wrong, with nothing else to show it (an EnergyPlus 25.2 twin of NREL's
    InternalMass_wZoneList, Golden in January, a sensor reading 1 K per kW of sun above the
    air: up to 4.4 K above the 24 C cooling set point for 62 h, and the zone's identified heat
    +61 %). Steps within :data:`SETPOINT_RECOVERY` after the set point moved towards the room
    (a set-back's end) and within :data:`SETPOINT_EARLY_STOP` before it moves away (a
    set-back's start) are left out.

    Parameters
    ----------
    measured : DataFrame (steps x zones) [C]
        The zones' own measured temperatures (NaN: none).
    setpoints : DataFrame or callable returning it
        :func:`zone_setpoints` on the same index (columns ``(zone, "heating" | "cooling")``,
        NaN where the plant is off); called only when there are zones to check.
    equipped : set of str or None
        Zones with heating or cooling equipment in the file (:func:`heated_or_cooled`); None:
        every zone with a set point.
    step : Timedelta
    sources : mapping of zone -> ZoneSource, optional
        For the sensors of each zone, in the record.

    Returns
    -------
    list of dict
        One record per zone and side beyond :data:`SETPOINT_MARGIN` for more than
        :data:`SETPOINT_EXCURSION_SHARE` of the hours the set point applies and at least
        :data:`SETPOINT_EXCURSION_HOURS`: ``zone``, ``sensors``, ``side`` ("above cooling" or
        "below heating"), ``setpoint_C`` (the median set point there) [C], ``hours`` [h],
        ``share`` [-] of ``hours_held`` [h] (the hours the set point applies, less those
        near its changes), ``max_excess_K`` [K], ``first`` (time), ``margin_K`` [K].
    """
    zones = [z for z in measured.columns if equipped is None or str(z) in equipped]
    if not zones or measured.empty:
        return []
    frame = setpoints() if callable(setpoints) else setpoints
    if frame is None or frame.empty:
        return []
    hours_per_step = step / pd.Timedelta("1h")
    recovery = max(1, int(np.ceil(SETPOINT_RECOVERY / step)))
    early = max(1, int(np.ceil(SETPOINT_EARLY_STOP / step)))
    out = []
    for zone in zones:
        reading = measured[zone].to_numpy(float)
        for kind, side, sign in (("cooling", "above cooling", 1), ("heating", "below heating", -1)):
            if (zone, kind) not in frame.columns:
                continue
            setpoint = frame[(zone, kind)].to_numpy(float)
            held = np.isfinite(setpoint) & np.isfinite(reading)
            held &= ~_changing(setpoint, -sign, recovery, early)
            if not held.any():
                continue
            excess = np.where(held, sign * (reading - setpoint), np.nan)
            beyond = held & (excess > SETPOINT_MARGIN)
            hours = float(beyond.sum() * hours_per_step)
            share = float(beyond.sum() / held.sum())
            if hours < SETPOINT_EXCURSION_HOURS or share <= SETPOINT_EXCURSION_SHARE:
                continue
            src = (sources or {}).get(zone)
            out.append(
                {
                    "zone": str(zone),
                    "sensors": list(getattr(src, "sensors", ())),
                    "side": side,
                    "setpoint_C": float(np.median(setpoint[beyond])),
                    "hours": hours,
                    "share": share,
                    "hours_held": float(held.sum() * hours_per_step),
                    "max_excess_K": float(np.nanmax(excess[beyond])),
                    "first": str(measured.index[np.argmax(beyond)]),
                    "margin_K": SETPOINT_MARGIN,
                }
            )
    return out


def setpoint_excursion_text(record: Mapping) -> str:
    """The warning and note for one record of :func:`setpoint_excursions`.

    Parameters
    ----------
    record : dict

    Returns
    -------
    str
    """
    above = record["side"] == "above cooling"
    sensors = ", ".join(record.get("sensors") or []) or "its sensors"
    causes = (
        "a sensor in the sun or near a heat source (a lamp, a radiator, a computer) reads its "
        "spot, not the room's air"
        if above
        else "a sensor against a cold window or wall, in a draught or near a cold source reads "
        "its spot, not the room's air"
    )
    wrong = "too much heat, too little cooling" if above else "too little heat, too much cooling"
    return (
        f"zone {record['zone']!r} ({sensors}) reads {'above' if above else 'below'} the "
        f"{'cooling' if above else 'heating'} set point the building file holds it at (about "
        f"{record['setpoint_C']:g} C) by more than {record['margin_K']:g} K for "
        f"{record['hours']:.1f} h ({100 * record['share']:.0f} % of the {record['hours_held']:.0f} "
        f"h it applies), up to {record['max_excess_K']:.1f} K, where the file's "
        f"{'cooling' if above else 'heating'} would hold the room at it: {causes}, or the set "
        "points in the file are not the building's. The identified heat follows the reading "
        f"({wrong} than the room had); check where the sensor hangs and the thermostat's "
        "settings (setpoint_excursions in identification.json)"
    )


def zone_setpoints(building, times: pd.DatetimeIndex) -> pd.DataFrame:
    """Heating and cooling set points [C] of the zones at ``times``: columns
    ``(zone, "heating" | "cooling")``, from an imported IDF's thermostat schedules
    (``building.idf_info.setpoint_profile``), else the zones' constant set points; a zone
    without either has no column.

    Parameters
    ----------
    building : thermocal.multizone.Building
    times : DatetimeIndex
        The grid (local times of the building's calendar).
    """
    out = {}
    info = getattr(building, "idf_info", None)
    if info is not None and getattr(info, "setpoint_schedules", None):
        profile = info.setpoint_profile(times)
        for column in profile.columns:
            out[column] = profile[column].to_numpy(float)
    for name, zone in getattr(building, "zones", {}).items():
        for kind in ("heating", "cooling"):
            constant = getattr(zone, f"{kind}_setpoint", None)
            if constant is not None and (str(name), kind) not in out:
                out[(str(name), kind)] = np.full(len(times), float(constant))
    frame = pd.DataFrame(out, index=times)
    if out:
        frame.columns = pd.MultiIndex.from_tuples(list(out))
    return frame


def _plausible_indoor(mean: float) -> bool:
    """Whether a mean [C] is an indoor temperature (:data:`INDOOR_MEAN_RANGE`)."""
    return INDOOR_MEAN_RANGE[0] <= mean <= INDOOR_MEAN_RANGE[1]


def _log_unit_text(
    sensor: str, mean: float, median: float, n_others: int, unit: str | None
) -> str:
    """The message on a log whose sensors all read no indoor temperature in C, after the
    sensor's name: both means, every conversion that fits (with the values it gives) and what
    to do for each.

    Parameters
    ----------
    sensor : str
        The sensor named.
    mean : float
        Its mean as read [C].
    median : float
        The median of the other sensors' means as read [C].
    n_others : int
        How many other sensors.
    unit : str or None
        The unit the log declares for the sensor (None: undeclared).
    """
    low, high = INDOOR_MEAN_RANGE
    declared = f"the {unit} it declares" if unit else "C"
    head = (
        f"reads {mean:.1f} on average and the other {n_others} sensor(s) {median:.1f} (their "
        f"median): neither is an indoor temperature in C (a zone averages {low:g} to {high:g} "
        f"C), so the whole log seems to be in another unit than {declared}"
    )
    slips = log_unit_slips(mean, median)
    if not slips:
        return f"{head}; check its unit and run again"
    options = " or ".join(
        f"{label} ({value:.1f} C for {sensor}, {typical:.1f} C for the others' median if so)"
        for label, _, value, typical in slips
    )
    remedies = "; ".join(
        f"if {label.split('?')[0]}: {remedy.replace('NAME', sensor)}, for every sensor"
        if len(slips) > 1
        else f"{remedy.replace('NAME', sensor)}, for every sensor"
        for label, remedy, _, _ in slips
    )
    return f"{head}: {options}; {remedies}; and run again"


#: Shortest identification period [d]: the first day lets the controllers and the walls
#: settle and is not counted (``settle``), and the metric needs unoccupied hours after it.
MIN_PERIOD_DAYS = 2.0


def check_period_length(start, end, weather_index: pd.DatetimeIndex) -> None:
    """Refuse an identification period too short for the metric (:data:`MIN_PERIOD_DAYS`).

    Parameters
    ----------
    start, end : timestamp-like or None
        The period ``[start, end)``; None: the weather's first / last instant.
    weather_index : DatetimeIndex
        The weather's index (its time zone places naive times).

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Stating the period's length, the minimum and why.
    """

    def instant(value, default):
        if value is None:
            return default
        try:
            ts = pd.Timestamp(value)
        except ValueError:
            return None  # the simulation names an unreadable time
        return ts.tz_localize(default.tz) if ts.tzinfo is None and default.tzinfo else ts

    t0 = instant(start, weather_index[0])
    t1 = instant(end, weather_index[-1])
    if t0 is None or t1 is None or t1 <= t0:
        return
    days = (t1 - t0) / pd.Timedelta("1D")
    if days < MIN_PERIOD_DAYS:
        raise ThermocalInputError(
            f"the period [{t0}, {t1}) is {days * 24:.1f} h; identification needs at least "
            f"{MIN_PERIOD_DAYS:g} days: the first day lets the controllers and the building's "
            "walls settle and is not counted, and the unoccupied-variance metric needs the "
            "unoccupied hours after it; give a longer log or period (--start/--end)"
        )


def _runs(
    mask: np.ndarray, index: pd.DatetimeIndex, step: pd.Timedelta, *, min_steps: int = 1
) -> list[dict]:
    """Runs of True in ``mask`` of at least ``min_steps`` steps: start, end (timestamps) and
    length [h] each, in order (vectorised: only the runs kept are turned into timestamps)."""
    flags = np.concatenate(([False], np.asarray(mask, dtype=bool), [False]))
    edges = np.flatnonzero(flags[1:] != flags[:-1])
    starts, stops = edges[0::2], edges[1::2]
    keep = (stops - starts) >= max(1, int(min_steps))
    hour = step / pd.Timedelta("1h")
    return [
        {"start": index[i], "end": index[j - 1] + step, "hours": (j - i) * hour}
        for i, j in zip(starts[keep].tolist(), stops[keep].tolist(), strict=True)
    ]


def _interpolate_short_gaps(series: pd.Series, max_gap: pd.Timedelta):
    """Linear interpolation of interior NaN runs up to ``max_gap``; the runs filled."""
    step = series.index[1] - series.index[0] if len(series) > 1 else pd.Timedelta("1h")
    mask = series.isna().to_numpy()
    filled = []
    if not mask.any():
        return series, filled
    values = series.to_numpy(dtype=float).copy()
    positions = np.arange(len(values))
    good = ~mask
    if good.sum() < 2:
        return series, filled
    for run in _runs(mask, series.index, step):
        i0 = series.index.get_loc(run["start"])
        i1 = i0 + int(round(run["hours"] * pd.Timedelta("1h") / step))
        interior = i0 > 0 and i1 < len(values)
        if interior and run["hours"] * pd.Timedelta("1h") <= max_gap:
            values[i0:i1] = np.interp(positions[i0:i1], positions[good], values[good])
            filled.append(run)
    return pd.Series(values, index=series.index), filled


def _hold_edge_step(
    series: pd.Series, report: pd.Timestamp, step: pd.Timedelta, edge: str
) -> tuple[pd.Series, list[dict]]:
    """Fill a missing first or last step of a log that reaches into it.

    ``edge="last"``: a log ending at ``--end``. The reference of the final step is centred on
    the period's end, so its averaging window reaches half a step beyond the log; the last value
    is held there instead of calling the end of the log a gap.
    ``edge="first"``: a log whose first value is stamped at the end of the period's first step
    (EnergyPlus' convention, many loggers' too) leaves the first step's averaging window with a
    single point on its edge; the second step's value is held there.

    Parameters
    ----------
    series : Series [C]
        One zone's reference on the step grid (index: step starts).
    report : Timestamp
        Time stamp of the log's last (``edge="last"``) or first (``"first"``) value.
    step : Timedelta
        Simulation step [s].
    edge : {"first", "last"}

    Returns
    -------
    series : Series [C]
        With the edge step filled, or unchanged.
    filled : list of dict
        The filled run (start, end, hours) for the report; empty when nothing was filled.
    """
    at, inner = (-1, -2) if edge == "last" else (0, 1)
    if len(series) < 2 or not np.isnan(series.iloc[at]) or np.isnan(series.iloc[inner]):
        return series, []
    if edge == "last" and report < series.index[-1]:
        return series, []
    if edge == "first" and report > series.index[0] + step:
        return series, []
    series = series.copy()
    series.iloc[at] = series.iloc[inner]
    hours = step / pd.Timedelta("1h")
    return series, [{"start": series.index[at], "end": series.index[at] + step, "hours": hours}]


def _fallback_zone(building, zone, src, sources, reference, measured=None) -> str | None:
    """The nearest zone with complete data over a long gap of ``zone``'s own data.

    Adjacent zones first, then, through zones without a reference (floating ones), the zones
    next to those, and so on. Among the zones of one ring, the one whose reference is closest to
    ``zone``'s own where both are measured (root mean square difference; then the largest
    shared area): the largest shared area alone chose an office's ceiling plenum, and three days
    of its temperature made the office's identified heat -4.2 kW where about -25 W was true
    (exploratory test, 2026-11-30). ``measured``: the references before any gap was filled
    (default ``reference``), so that a zone filled from another does not look like it.
    """
    measured = reference if measured is None else measured
    missing = reference[zone].isna()
    own = measured[zone]
    seen = {zone}
    frontier = [zone]
    while frontier:
        ring: dict[str, float] = {}
        for current in frontier:
            for other, area in shared_areas(building, current).items():
                if other not in seen:
                    ring[other] = max(ring.get(other, 0.0), area)
        seen.update(ring)
        candidates = [
            other
            for other in sorted(ring)
            if other in reference
            and sources[other].zone != src.zone
            and reference.loc[missing, other].notna().all()
        ]
        if candidates:
            return min(
                candidates, key=lambda o: (_rms_difference(own, measured[o]), -ring[o], o)
            )
        frontier = [z for z in ring if z not in reference]
    return None


def _rms_difference(a: pd.Series, b: pd.Series) -> float:
    """Root mean square difference of two references where both are known [K] (inf: never)."""
    both = a.notna() & b.notna()
    if not both.any():
        return float("inf")
    return float(np.sqrt(np.mean((a[both].to_numpy() - b[both].to_numpy()) ** 2)))
