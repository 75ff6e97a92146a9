"""The form of the identified heat that the building file declares: its People, Lights and
equipment objects give, step by step, the radiant share of the gains the identified heat stands
for (:func:`thermocal.multizone.idf.loads.declared_radiant_fraction`); the objects themselves are
then left out of the simulation.

``radiant_fraction: declared`` (the mapping's ``identified_heat``, ``--radiant-fraction declared``,
``identify(..., radiant_fraction="declared")``). Without it, a file's load objects are simulated
as known heat and the identified heat is what they do not account for; :func:`loads_note` says
so in the report.
"""

from __future__ import annotations

import dataclasses

import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.textformat import shortened_list

#: The value of ``radiant_fraction`` that asks for the form the building file declares
DECLARED = "declared"


def declared_form_requested(mapping, radiant_fraction) -> bool:
    """Whether the identification takes the file's declared form: ``radiant_fraction`` is
    ``"declared"``, or it is None and the mapping's ``identified_heat.radiant_fraction`` is."""
    if isinstance(radiant_fraction, str):
        if radiant_fraction.strip().lower() != DECLARED:
            raise ThermocalInputError(
                f"radiant_fraction must be a number in [0, 1] or '{DECLARED}', got "
                f"{radiant_fraction!r}"
            )
        return True
    if radiant_fraction is not None or mapping is None:
        return False
    return getattr(mapping, "radiant_fraction", None) == DECLARED


def _declared_gains(building) -> list:
    info = getattr(building, "idf_info", None)
    gains = [g for g in getattr(info, "internal_gains", []) if g.design_level > 0]
    return gains


def without_declared_loads(building, keep=()):
    """The building whose identified heat stands for its load objects: People, Lights and
    equipment removed from what is simulated (constant and scheduled gains alike), the rest
    (envelope, infiltration, ventilation, schedules) unchanged.

    Parameters
    ----------
    building : thermocal.multizone.Building
        Read from an IDF file with its load objects.
    keep : iterable of str
        Zones whose load objects stay simulated: the floating zones, which have no sensor and
        hence no identified heat to stand for their loads (:func:`floating_zones`).

    Raises
    ------
    ThermocalInputError
        When the building declares no load objects (not read from an IDF with People, Lights
        or equipment).
    """
    if not _declared_gains(building):
        raise ThermocalInputError(
            f"radiant_fraction: {DECLARED} takes the form of the identified heat from the "
            f"building file's People, Lights and equipment objects, and building "
            f"'{building.name}' declares none: give the IDF file with its load objects, or a "
            "number (default 0.6)"
        )
    info = building.idf_info
    keep = set(keep)
    zones = {
        name: zone if name in keep else dataclasses.replace(zone, internal_gains=0.0)
        for name, zone in building.zones.items()
    }
    stripped = building.replaced(zones=zones)
    stripped.idf_info = dataclasses.replace(
        info, internal_gains=[g for g in info.internal_gains if g.zone in keep]
    )
    return stripped


def floating_zones(building, mapping) -> list[str]:
    """The zones without a reference temperature (no sensor, no named or neighbour's data):
    they float freely with ``Q_ID = 0``."""
    from thermocal.identification.sensors import zone_sources

    return [z for z, src in zone_sources(building, mapping).items() if src.kind == "float"]


def building_to_simulate(building, mapping, declared: bool):
    """The building the identification simulates and the floating zones that keep their loads.

    Without the declared form: ``building`` itself (a file's load objects simulated as known
    heat everywhere). With it: the load objects left out of the tracked zones (the identified
    heat stands for them) and kept in the floating zones, which have no identified heat: the
    file's loads are the best knowledge of what those zones get, and leaving them out would
    make them float colder than the building and draw heat from their sensed neighbours.

    Returns
    -------
    building : thermocal.multizone.Building
    kept : list of str
        Floating zones whose load objects stay simulated (empty without the declared form).
    """
    if not declared:
        return building, []
    floating = floating_zones(building, mapping)
    kept = sorted({g.zone for g in _declared_gains(building)} & set(floating))
    return without_declared_loads(building, keep=kept), kept


def declared_form(building, mapping, times: pd.DatetimeIndex, step, fallback: float):
    """Per-step radiant fraction [-] of every zone (DataFrame, steps x zones) from the file's
    load objects; a zone given its own number in the mapping (``zones: {Z: {radiant_fraction:
    0.3}}``) keeps it at every step; a zone without gains takes ``fallback`` [-]."""
    from thermocal.multizone.idf.loads import declared_radiant_fraction

    zones = list(building.zones)
    frame = pd.DataFrame(
        declared_radiant_fraction(building.idf_info, zones, times, step, fallback),
        index=times,
        columns=zones,
    )
    for zone, value in getattr(mapping, "zone_radiant_fraction", {}).items():
        if zone in frame.columns:
            frame[zone] = float(value)
    return frame


def loads_note(
    building, declared: bool, form: pd.DataFrame | None = None, kept=()
) -> str | None:
    """The report's sentence on the file's load objects (None when it has none); ``kept``:
    floating zones whose objects stay simulated (:func:`building_to_simulate`)."""
    gains = _declared_gains(building)
    if not gains:
        return None
    kinds = sorted({g.object_class for g in gains})
    if declared:
        low = float(form.min().min()) if form is not None else float("nan")
        high = float(form.max().max()) if form is not None else float("nan")
        floating = (
            f" The {len(kept)} floating zone(s) with load objects keep them, simulated as known "
            f"heat (no sensor, no identified heat): {shortened_list(kept)}."
            if kept
            else ""
        )
        return (
            f"The identified heat takes the form the building file declares step by step "
            f"({len(gains)} objects: {', '.join(kinds)}; radiant share {low:.2f}..{high:.2f}); "
            "those objects are not simulated: the identified heat stands for them." + floating
        )
    return (
        f"The building file's {len(gains)} load objects ({', '.join(kinds)}) are simulated as "
        "known heat: the identified heat is the heat beyond them. To identify all internal heat "
        f"in the form the file declares, set identified_heat: {{radiant_fraction: {DECLARED}}} "
        f"in the mapping (or --radiant-fraction {DECLARED})."
    )

