"""Building files: thermocal's own YAML format and EnergyPlus IDF (see docs/multizone-file.md).

``load_building(path)`` reads ``.yaml``/``.yml`` (this module) or ``.idf``
(:func:`thermocal.multizone.idf.read_idf`); ``save_building(building, path)`` writes YAML.
"""

from __future__ import annotations

import dataclasses
import difflib
import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.model import (
    Building,
    Construction,
    Location,
    Material,
    NoMassMaterial,
    Surface,
    Window,
    WindowType,
    Zone,
    setpoint_celsius,
)

_SECTIONS = {
    "materials": None,  # Material or NoMassMaterial, decided by the keys
    "constructions": Construction,
    "window_types": WindowType,
    "zones": Zone,
    "surfaces": Surface,
    "windows": Window,
}
_TOP_LEVEL = {
    "name",
    "location",
    "ground_temperatures",
    "ground_reflectance",
    "foundations",
    "description",
    *_SECTIONS,
}
_NOT_IN_FILES = {"angular_transmittance"}  # callables cannot be written to a file

#: Heating set points of a zone in a building file [C]: from frost protection of an unheated
#: garage, staircase or cellar (a few degrees above zero) to the warmest room's; a Fahrenheit
#: one (60-75 F) lies above, a stray minus sign below.
HEATING_SETPOINT_RANGE = (0.0, 35.0)
#: Highest cooling set point of a zone in a building file [C]: EnergyPlus files set the cooling
#: up to 30-40 C in unoccupied hours (the value ``thermocal calibrate`` writes for an IDF's
#: zone is the one its schedule holds most of the year); a Fahrenheit one (72-85) lies above.
MAX_COOLING_SETPOINT = 40.0
#: Set points accepted in a building file [C], by key (:func:`_check_setpoints`). An IDF's
#: schedule may hold an "off" value outside them (heating -50 C, cooling 100 C): the file
#: :func:`save_building` writes leaves such a set point out (no heating or cooling, which is
#: what the value means), so that thermocal reads every file it writes.
SETPOINT_RANGES = {
    "heating_setpoint": HEATING_SETPOINT_RANGE,
    "cooling_setpoint": (5.0, MAX_COOLING_SETPOINT),
}

#: Air changes per hour above which a zone's ``infiltration_ach`` in a building file is
#: warned about [1/h]: air leaking through an envelope is 0.1-1.5 1/h, a few 1/h in the
#: leakiest old house (an n50 of 20 1/h at 50 Pa is about 1 1/h in use), so 45 is 0.45 typed
#: as a percentage. A warning, not an error: the rate is all the zone's outdoor air, and a
#: ventilation system's (a kitchen hood, a laboratory; an IDF's ZoneVentilation, which the
#: calibrated building of an IDF carries in it) can be this high.
MAX_INFILTRATION_ACH = 10.0

#: Lowest mean height (volume over floor area) of a zone in a building file [m]: the shallowest
#: air spaces modelled as zones, ceiling and raised-floor plenums and crawl spaces, are 0.2 m
#: and more (5ZoneAirCooled's plenums 0.61 m, an attic of the EnergyPlus basement house
#: 0.76 m); 1 m would refuse those, while a volume typed in litres / 1000, as the room's height
#: or as 0.001 lies below.
MIN_ZONE_MEAN_HEIGHT = 0.2


class BuildingFileWarning(UserWarning):
    """A building file's value that is unusual but possible (shown as a ``warning:`` line)."""


def load_building(path: str | Path) -> Building:
    """Read a building file: thermocal YAML (``.yaml``/``.yml``) or EnergyPlus IDF (``.idf``).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    Building

    Raises
    ------
    ThermocalInputError
        Unknown extension, unreadable file, unknown keys, bad values, broken references; the
        message names the file and the object.
    """
    path = Path(path)
    if path.is_dir():
        raise ThermocalInputError(f"building file {path} is a folder, not a file")
    if not path.is_file():
        raise ThermocalInputError(f"building file {path} does not exist (check the path)")
    suffix = path.suffix.lower()
    if suffix == ".idf":
        from thermocal.multizone.idf import read_idf

        return read_idf(path)
    if suffix not in (".yaml", ".yml"):
        raise ThermocalInputError(
            f"building file {path}: unknown extension {path.suffix!r}; use .yaml/.yml "
            "(thermocal format, docs/multizone-file.md) or .idf (EnergyPlus)"
        )
    from thermocal.io.envelope import MULTIZONE_EXAMPLE, is_envelope_tree
    from thermocal.io.yamlfile import read_yaml

    data = read_yaml(path, what="building file")
    if isinstance(data, Mapping) and "idf" in data:
        return idf_with_parameters(data, path)
    if is_envelope_tree(data):
        raise ThermocalInputError(
            f"{path} is an envelope description (components with areas and U-values, the "
            "retrofit analysis' building file), not a multi-zone building file (zones, surfaces, "
            f"constructions) that this command needs, e.g. {MULTIZONE_EXAMPLE} "
            "(format: docs/multizone-file.md)"
        )
    try:
        return building_from_dict(data, source=f"building file {path}")
    except ThermocalInputError as exc:
        raise ThermocalInputError(f"building file {path}: {exc}") from None


#: Keys of a building file that names an IDF and the parameters to change in it.
IDF_WITH_PARAMETERS_KEYS = ("idf", "idf_sha256", "parameters")


def idf_with_parameters(data: Mapping, path: Path) -> Building:
    """The building of a file that names an EnergyPlus IDF and parameters to change in it.

    ``thermocal calibrate`` writes its calibrated building in this form when the campaign's
    building is an IDF: a thermocal YAML file cannot hold what the importer keeps besides the
    envelope (schedules, internal loads, scheduled and wind-driven infiltration, shading
    surfaces, the run period), so the calibrated building is the IDF as imported with the
    calibrated values applied (:meth:`Building.with_parameters`)::

        idf: ../nominal.idf            # relative to this file
        idf_sha256: 3f5c...            # optional: the IDF the values were calibrated on
        parameters:
          construction/ROOF-1/resistance: 3.04
          window/Dbl Clr 3mm/13mm Air/u_value: 1.60

    Parameters
    ----------
    data : Mapping
        The file's content.
    path : Path
        The file (for the IDF's relative path and messages).

    Returns
    -------
    Building

    Warns
    -----
    BuildingFileWarning
        The IDF differs from the one the values were calibrated on (``idf_sha256``).
    """
    from thermocal.io.digest import file_sha256
    from thermocal.multizone.idf import read_idf

    where = f"building file {path}"
    unknown = sorted(set(data) - set(IDF_WITH_PARAMETERS_KEYS))
    if unknown:
        raise ThermocalInputError(
            f"{where}: unknown keys {unknown} beside 'idf' (allowed: "
            f"{', '.join(IDF_WITH_PARAMETERS_KEYS)}); a file naming an IDF holds only the IDF "
            "and the parameters to change in it"
        )
    idf = _idf_path(data, path)
    if not idf.is_file():
        raise ThermocalInputError(
            f"{where}: its 'idf' {data['idf']!r} ({idf}) does not exist; the path is relative "
            "to the building file: fix it or copy the IDF there"
        )
    parameters = data.get("parameters") or {}
    if not isinstance(parameters, Mapping) or not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in parameters.values()
    ):
        raise ThermocalInputError(
            f"{where}: 'parameters' must map parameter names to numbers, e.g. "
            "{'construction/ROOF-1/resistance': 3.04}"
        )
    expected = data.get("idf_sha256")
    if expected is not None and str(expected) != file_sha256(idf):
        warnings.warn(
            f"{where}: {idf} is not the IDF the parameters were calibrated on (its SHA-256 "
            "differs from 'idf_sha256'); they are applied to the file as it is now",
            BuildingFileWarning,
            stacklevel=3,
        )
    try:
        return read_idf(idf).with_parameters(dict(parameters))
    except ThermocalInputError as exc:
        raise ThermocalInputError(f"{where}: {exc}") from None


def _idf_path(data: Mapping, path: Path) -> Path:
    """The ``idf`` of a building file's content, relative to the file unless absolute."""
    idf = Path(str(data["idf"]))
    return idf if idf.is_absolute() else Path(path).parent / idf


def named_idf(path: str | Path) -> tuple[Path, dict] | None:
    """The IDF a building file names and the parameters it changes in it.

    Parameters
    ----------
    path : str or Path
        A building file.

    Returns
    -------
    (Path, dict) or None
        The IDF (which may not exist) and ``parameters`` (name -> value); None for a file that
        is not a readable YAML file naming an IDF.
    """
    import yaml

    path = Path(path)
    if path.suffix.lower() not in (".yaml", ".yml") or not path.is_file():
        return None
    try:
        data = yaml.safe_load(path.read_text())
    except (yaml.YAMLError, OSError, UnicodeDecodeError):
        return None
    if not isinstance(data, Mapping) or "idf" not in data:
        return None
    parameters = data.get("parameters") or {}
    return _idf_path(data, path), dict(parameters) if isinstance(parameters, Mapping) else {}


def imported_idf(building, source=None) -> Path | None:
    """The IDF a building was imported from: ``source`` when it is one, else the importer's
    record of it (also for a building file naming an IDF and parameters, as ``thermocal
    calibrate`` writes); None for a building that is not an IDF's. For what the import leaves
    to its users: the retrofit's ``Foundation:Kiva`` floors, the calibrated file's ``idf``.

    Parameters
    ----------
    building : Building
    source : str or Path, optional
        The file the building was read from.
    """
    if source is not None and str(source).lower().endswith(".idf"):
        return Path(source)
    recorded = getattr(getattr(building, "idf_info", None), "source", None)
    if recorded and str(recorded).lower().endswith(".idf") and Path(recorded).is_file():
        return Path(recorded).resolve()
    return None


def _entries(section: str, value) -> list[dict]:
    """A section as a list of dicts: accepts a list of mappings or a name-keyed mapping."""
    if value is None:
        return []
    if isinstance(value, Mapping):
        out = []
        for name, fields in value.items():
            if not isinstance(fields, Mapping):
                raise ThermocalInputError(f"{section} '{name}': expected a mapping of fields")
            entry = dict(fields)
            if "name" in entry and entry["name"] != name:
                raise ThermocalInputError(
                    f"{section} '{name}': the key and the 'name' field differ ({entry['name']!r})"
                )
            entry["name"] = name
            out.append(entry)
        return out
    if isinstance(value, list):
        for i, entry in enumerate(value):
            if not isinstance(entry, Mapping) or "name" not in entry:
                raise ThermocalInputError(
                    f"{section}[{i}]: expected a mapping with a 'name' field, got {entry!r}"
                )
        return [dict(e) for e in value]
    raise ThermocalInputError(
        f"{section}: expected a list or a mapping, got {type(value).__name__}"
    )


def _construct(cls, section: str, entry: dict):
    fields = {f.name for f in dataclasses.fields(cls)} - _NOT_IN_FILES
    unknown = sorted(set(entry) - fields)
    if unknown:
        hints = []
        for key in unknown:
            close = difflib.get_close_matches(key, fields, n=1)
            hints.append(f"'{key}'" + (f" (did you mean '{close[0]}'?)" if close else ""))
        raise ThermocalInputError(
            f"{section} '{entry.get('name')}': unknown field(s) {', '.join(hints)}; allowed: "
            f"{', '.join(sorted(fields))}"
        )
    try:
        return cls(**entry)
    except TypeError as exc:
        raise ThermocalInputError(f"{section} '{entry.get('name')}': {exc}") from None


def _check_gains_unit(zone) -> None:
    """A zone's constant gains written in kW (0.3 for 300 W) in a building file: named.

    Only for a file a user writes: an IDF's annual mean of a small scheduled gain can be below
    1 W and is right.
    """
    gains = float(zone.internal_gains)
    if 0.0 < abs(gains) < 1.0:
        raise ThermocalInputError(
            f"zone '{zone.name}': internal_gains {gains:g} W is no room's heat (people, lights "
            f"and appliances give tens to thousands of W); is it in kW? then write "
            f"{1000 * gains:g}"
        )


def _check_setpoints(zone: Zone) -> None:
    """A zone's set points in a building file: a room's (:data:`SETPOINT_RANGES`), not
    Fahrenheit or below zero.

    Only for a file a user writes: a :class:`Zone` made in code (the IDF import, whose
    schedules hold -50 or 100 C for "off") keeps the broad check of :func:`setpoint_celsius`.

    Parameters
    ----------
    zone : Zone
        Set points in C.
    """
    for key, plausible in SETPOINT_RANGES.items():
        setpoint_celsius(getattr(zone, key), f"zone '{zone.name}': {key}", plausible)


def _check_volume(zone: Zone) -> None:
    """A zone's volume that cannot stand on its floor (below :data:`MIN_ZONE_MEAN_HEIGHT`).

    Parameters
    ----------
    zone : Zone
        Volume in m3, floor area in m2 (0: no floor, nothing to compare).
    """
    if zone.floor_area > 0 and zone.volume < MIN_ZONE_MEAN_HEIGHT * zone.floor_area:
        raise ThermocalInputError(
            f"zone '{zone.name}': volume {zone.volume:g} m3 over floor_area "
            f"{zone.floor_area:g} m2 is a mean height of {zone.volume / zone.floor_area:.3g} m "
            f"(no room or plenum is lower than {MIN_ZONE_MEAN_HEIGHT:g} m); give the air "
            f"volume in m3, the floor area times the height (e.g. "
            f"{2.5 * zone.floor_area:g} for 2.5 m)"
        )


def _infiltration_note(zones: list[Zone]) -> str | None:
    """The warning on air changes above :data:`MAX_INFILTRATION_ACH`, or None.

    Parameters
    ----------
    zones : list of Zone
        ``infiltration_ach`` in 1/h.

    Returns
    -------
    str or None
        One note naming the zones (the first three) and their rates.
    """
    high = [zone for zone in zones if zone.infiltration_ach > MAX_INFILTRATION_ACH]
    if not high:
        return None
    named = ", ".join(f"'{z.name}' {z.infiltration_ach:g} 1/h" for z in high[:3])
    more = f" and {len(high) - 3} more zone(s)" if len(high) > 3 else ""
    meant = ", ".join(dict.fromkeys(f"{z.infiltration_ach / 100:g}" for z in high[:3]))
    return (
        f"infiltration_ach of zone(s) {named}{more}: far above the air leaking through an "
        f"envelope (0.1-1.5 1/h, a few in the leakiest house); a percentage? then write "
        f"{meant}. Taken as given (a ventilation system's outdoor air, a kitchen hood's, can "
        "be this high)"
    )


def _partner_notes(building: Building) -> list[str]:
    """The inter-zone walls whose two sides name constructions that are not each other's
    mirror (nor the same): the first surface's is built, the other not read."""
    from thermocal.multizone.elements import unmirrored_partners, unmirrored_partners_note

    layers = {c.name: c.layers for c in building.constructions.values()}
    pairs = unmirrored_partners(building.surfaces.values(), layers, identical_is_mirror=True)
    return [unmirrored_partners_note(built, far, walls) for (built, far), walls in pairs.items()]


def _surfaceless_zones(building: Building) -> tuple[list[str], list[str]]:
    """The zones of a building that no surface bounds (an inter-zone surface bounds both its
    zones), split by whether infiltration couples their air to the outdoor air.

    Parameters
    ----------
    building : Building

    Returns
    -------
    (list of str, list of str)
        Names of the zones without surfaces and without infiltration, and of those with
        infiltration (``infiltration_ach > 0`` [1/h]).
    """
    bounded = {surface.zone for surface in building.surfaces.values()}
    bounded |= {s.other_zone for s in building.surfaces.values() if s.other_zone is not None}
    alone = [name for name in building.zones if name not in bounded]
    sealed = [name for name in alone if building.zones[name].infiltration_ach <= 0.0]
    aired = [name for name in alone if building.zones[name].infiltration_ach > 0.0]
    return sealed, aired


def _check_surfaceless_zones(building: Building) -> str | None:
    """Refuse the zones of a building file without surfaces or infiltration; a note for those
    with infiltration only.

    A zone without surfaces or infiltration exchanges no heat with anything: it would be
    reported at its start temperature for the whole run (the model refuses it too when the
    building has other surfaces; a file without any surface reaches here). A zone without
    surfaces but with infiltration is an air node the model allows on purpose (a shaft or a
    ventilated void whose air follows the outdoor air; the test suite simulates one against
    the exact solution), but in a building file it is more often a zone whose surfaces were
    forgotten or misnamed: its temperature then follows the outdoor air with no wall, window
    or sun, so it is named in a warning.

    Parameters
    ----------
    building : Building

    Returns
    -------
    str or None
        The note on the zones with infiltration only.

    Raises
    ------
    ThermocalInputError
        Naming the zones without surfaces or infiltration.
    """
    sealed, aired = _surfaceless_zones(building)
    if sealed:
        raise ThermocalInputError(
            f"zone(s) {sealed[:5]} have no surfaces (no entry of 'surfaces' names them in "
            "'zone' or 'other_zone') and no infiltration: nothing connects their air to the "
            "outside or to another zone, so their temperature would stay where it starts and "
            "their heat at zero; add their surfaces or remove them"
        )
    if not aired:
        return None
    return (
        f"zone(s) {aired[:5]} have no surfaces (no entry of 'surfaces' names them in 'zone' or "
        "'other_zone'): their air exchanges heat only by its infiltration with the outdoor air "
        "(no walls, windows or sun), so their temperature follows the outdoor air's; if they "
        "have walls, add them to 'surfaces'"
    )


def _check_user_zone(zone: Zone) -> None:
    """A zone of a building file a user writes: refused on a unit slip.

    Parameters
    ----------
    zone : Zone
    """
    _check_gains_unit(zone)
    _check_setpoints(zone)
    _check_volume(zone)


def building_from_dict(data: Mapping, *, source: str | None = None) -> Building:
    """Build a :class:`Building` from the YAML structure (see docs/multizone-file.md).

    Parameters
    ----------
    data : mapping
        The file's structure.
    source : str or None
        What the warnings name first (``"building file house.yaml"``).

    Returns
    -------
    Building

    Warns
    -----
    BuildingFileWarning
        A value that is unusual but possible: an air change above
        :data:`MAX_INFILTRATION_ACH`, inter-zone walls whose sides are not each other's mirror,
        a zone without surfaces whose air is coupled by infiltration only.
    """
    if not isinstance(data, Mapping):
        raise ThermocalInputError("the file must contain a mapping (name, zones, surfaces, ...)")
    unknown = sorted(set(data) - _TOP_LEVEL)
    if unknown:
        raise ThermocalInputError(
            f"unknown top-level key(s) {unknown}; allowed: {', '.join(sorted(_TOP_LEVEL))}"
        )
    if "name" not in data:
        raise ThermocalInputError("the building needs a 'name'")
    objects: dict[str, list] = {}
    for section, cls in _SECTIONS.items():
        entries = _entries(section, data.get(section))
        built = []
        for entry in entries:
            if section == "materials":
                kind = NoMassMaterial if "resistance" in entry else Material
                built.append(_construct(kind, "material", entry))
            else:
                if section == "constructions" and isinstance(entry.get("layers"), list):
                    entry["layers"] = tuple(entry["layers"])
                built.append(_construct(cls, section[:-1].replace("_", " "), entry))
                if section == "zones":
                    _check_user_zone(built[-1])
        objects[section] = built
    location = data.get("location") or {}
    if not isinstance(location, Mapping):
        raise ThermocalInputError("location: expected latitude, longitude, altitude, timezone")
    allowed = {"latitude", "longitude", "altitude", "timezone"}
    if set(location) - allowed:
        raise ThermocalInputError(
            f"location: unknown field(s) {sorted(set(location) - allowed)}; allowed: "
            f"{', '.join(sorted(allowed))}"
        )
    location = Location(**location)
    building = Building(
        name=str(data["name"]),
        location=location,
        ground_temperatures=data.get("ground_temperatures"),
        ground_reflectance=data.get("ground_reflectance"),
        foundations=_foundations_from(data.get("foundations")),
        **objects,
    )
    notes = [
        _check_surfaceless_zones(building),
        _infiltration_note(objects["zones"]),
        *_partner_notes(building),
    ]
    for note in filter(None, notes):
        warnings.warn(
            f"{source}: {note}" if source else note, BuildingFileWarning, stacklevel=2
        )
    return building


def _foundations_from(value) -> dict:
    """``foundations:`` of a building file: surface name -> the fields of
    :class:`thermocal.multizone.foundation.FoundationGround` (``exposed_perimeter`` [m],
    ``soil`` [conductivity W/(m K), density kg/m3, specific heat J/(kg K)], ``wall_layers``
    [[thickness m, conductivity, density, specific heat], ...] inside first, ...)."""
    from thermocal.multizone.foundation import FoundationGround

    if not value:
        return {}
    if not isinstance(value, Mapping):
        raise ThermocalInputError("foundations: expected a mapping of surface name -> fields")
    allowed = {f.name for f in dataclasses.fields(FoundationGround)}
    out = {}
    for name, fields in value.items():
        if not isinstance(fields, Mapping) or set(fields) - allowed:
            raise ThermocalInputError(
                f"foundations '{name}': expected the fields {', '.join(sorted(allowed))}"
            )
        fields = dict(fields)
        if "soil" in fields:
            fields["soil"] = tuple(float(v) for v in fields["soil"])
        if "wall_layers" in fields:
            fields["wall_layers"] = tuple(
                tuple(float(v) for v in layer) for layer in fields["wall_layers"]
            )
        if "walls" in fields:
            fields["walls"] = tuple((str(w[0]), float(w[1])) for w in fields["walls"])
        try:
            out[str(name)] = FoundationGround(**fields)
        except TypeError as exc:
            raise ThermocalInputError(f"foundations '{name}': {exc}") from None
    return out


def building_to_dict(building: Building) -> dict:
    """The YAML structure of a building (inverse of :func:`building_from_dict`)."""

    def clean(obj) -> dict:
        out = {}
        defaults = {
            f.name: f.default
            for f in dataclasses.fields(obj)
            if f.default is not dataclasses.MISSING
        }
        for f in dataclasses.fields(obj):
            if f.name in _NOT_IN_FILES:
                continue
            value = getattr(obj, f.name)
            if f.name in defaults and _same(value, defaults[f.name]) and f.name != "name":
                continue
            out[f.name] = _plain(value)
        return out

    return {
        "name": building.name,
        "location": {
            "latitude": building.location.latitude,
            "longitude": building.location.longitude,
            "altitude": building.location.altitude,
            **(
                {"timezone": building.location.timezone}
                if building.location.timezone is not None
                else {}
            ),
        },
        **(
            {"ground_temperatures": list(building.ground_temperatures)}
            if building.ground_temperatures is not None
            else {}
        ),
        **(
            {"ground_reflectance": list(building.ground_reflectance)}
            if building.ground_reflectance is not None
            else {}
        ),
        **(
            {"foundations": {n: clean(f) for n, f in building.foundations.items()}}
            if building.foundations
            else {}
        ),
        "materials": [clean(m) for m in building.materials.values()],
        "constructions": [clean(c) for c in building.constructions.values()],
        "window_types": [clean(w) for w in building.window_types.values()],
        "zones": [_without_off_setpoints(clean(z)) for z in building.zones.values()],
        "surfaces": [clean(s) for s in building.surfaces.values()],
        "windows": [clean(w) for w in building.windows.values()],
    }


def _without_off_setpoints(zone: dict) -> dict:
    """A zone's YAML entry without set points outside :data:`SETPOINT_RANGES`: an IDF
    schedule's "off" value (heating -50 C, cooling 100 C) means no heating or cooling, which
    the missing key says; a building file with the value would be refused when read.

    Parameters
    ----------
    zone : dict
        The zone's entry (set points in C).

    Returns
    -------
    dict
        The entry, with such set points left out (a warning names them).
    """
    for key, (low, high) in SETPOINT_RANGES.items():
        value = zone.get(key)
        if value is not None and not low <= float(value) <= high:
            del zone[key]
            warnings.warn(
                f"zone '{zone.get('name')}': {key} {float(value):g} C (an 'off' value, outside "
                f"{low:g}-{high:g} C) is left out of the building file: no "
                f"{key.split('_')[0]} in that zone",
                BuildingFileWarning,
                stacklevel=3,
            )
    return zone


def _same(a, b) -> bool:
    try:
        return bool(a == b)
    except ValueError:
        return False


def _plain(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, tuple | list):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def save_building(building: Building, path: str | Path) -> Path:
    """Write a building as thermocal YAML.

    Parameters
    ----------
    building : Building
    path : str or Path
        ``.yaml`` or ``.yml`` file.

    Warns
    -----
    BuildingFileWarning
        The building was imported from an IDF: the file holds its envelope, zones and constant
        infiltration, not what the importer keeps besides (schedules, internal loads,
        scheduled and wind-driven infiltration, shading surfaces, the run period), so it is
        another building (the 5-zone IDF's ran 1.7-2.9 K colder); a file naming the IDF and
        the parameters keeps them (:func:`idf_with_parameters`).
    """
    import yaml

    path = Path(path)
    if path.suffix.lower() not in (".yaml", ".yml"):
        raise ThermocalInputError(f"save_building: {path} must end in .yaml or .yml")
    if getattr(building, "idf_info", None) is not None:
        warnings.warn(
            f"save_building: '{building.name}' was imported from an IDF; {path} holds its "
            "envelope, zones and constant infiltration but not the IDF's schedules, internal "
            "loads, scheduled and wind-driven infiltration, shading surfaces or run period, so "
            "it simulates another building. To keep them, write a file naming the IDF and the "
            "changed parameters ({'idf': ..., 'parameters': {...}}, docs/multizone-file.md)",
            BuildingFileWarning,
            stacklevel=2,
        )
    text = yaml.safe_dump(building_to_dict(building), sort_keys=False, allow_unicode=True)
    path.write_text(text)
    return path
