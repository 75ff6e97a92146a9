"""Building files: thermocal's own YAML format and EnergyPlus IDF (see docs/multizone-file.md).

``load_building(path)`` reads ``.yaml``/``.yml`` (this module) or ``.idf``
(:func:`thermocal.multizone.idf.read_idf`); ``save_building(building, path)`` writes YAML.
"""

from __future__ import annotations

import dataclasses
import difflib
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
    "description",
    *_SECTIONS,
}
_NOT_IN_FILES = {"angular_transmittance"}  # callables cannot be written to a file


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
    if is_envelope_tree(data):
        raise ThermocalInputError(
            f"{path} is an envelope description (components with areas and U-values, the "
            "retrofit analysis' building file), not a multi-zone building file (zones, surfaces, "
            f"constructions) that this command needs, e.g. {MULTIZONE_EXAMPLE} "
            "(format: docs/multizone-file.md)"
        )
    try:
        return building_from_dict(data)
    except ThermocalInputError as exc:
        raise ThermocalInputError(f"building file {path}: {exc}") from None


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


def building_from_dict(data: Mapping) -> Building:
    """Build a :class:`Building` from the YAML structure (see docs/multizone-file.md)."""
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
                    _check_gains_unit(built[-1])
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
    return Building(
        name=str(data["name"]),
        location=location,
        ground_temperatures=data.get("ground_temperatures"),
        ground_reflectance=data.get("ground_reflectance"),
        **objects,
    )


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
        "materials": [clean(m) for m in building.materials.values()],
        "constructions": [clean(c) for c in building.constructions.values()],
        "window_types": [clean(w) for w in building.window_types.values()],
        "zones": [clean(z) for z in building.zones.values()],
        "surfaces": [clean(s) for s in building.surfaces.values()],
        "windows": [clean(w) for w in building.windows.values()],
    }


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
    """
    import yaml

    path = Path(path)
    if path.suffix.lower() not in (".yaml", ".yml"):
        raise ThermocalInputError(f"save_building: {path} must end in .yaml or .yml")
    text = yaml.safe_dump(building_to_dict(building), sort_keys=False, allow_unicode=True)
    path.write_text(text)
    return path
