"""Units of the named envelope parameters of :meth:`thermocal.multizone.Building.parameters`.

Names are ``material/<name>/{conductivity,density,specific_heat,thickness}``,
``material/<name>/resistance``, ``window/<name>/{u_value,shgc}``,
``zone/<name>/infiltration_ach``, ``infiltration/<group>/ach`` and the building-wide factor
``infiltration/building/factor`` (:data:`INFILTRATION_FACTOR`), and the construction-level
``construction/<name>/{resistance,heat_capacity}`` of :mod:`thermocal.multizone.elements`; the
kind is the last part.
"""

from __future__ import annotations

#: Unit of each parameter kind (the last part of the name), for tables.
PARAMETER_UNITS: dict[str, str] = {
    "conductivity": "W/(m K)",
    "density": "kg/m3",
    "specific_heat": "J/(kg K)",
    "thickness": "m",
    "resistance": "m2 K/W",
    "heat_capacity": "J/(m2 K)",
    "u_value": "W/(m2 K)",
    "shgc": "-",
    "infiltration_ach": "1/h",
    "ach": "1/h",
    "factor": "-",
}

#: The building-wide infiltration factor [-]: every zone's air change rate times this value.
INFILTRATION_FACTOR = "infiltration/building/factor"


def parameter_kind(name: str) -> str:
    """Kind of a parameter: the last ``/``-separated part of its name (e.g. ``"shgc"``)."""
    return str(name).rsplit("/", 1)[-1]


def parameter_unit(name: str, unknown: str = "?") -> str:
    """Unit of a parameter from its kind (``"W/(m K)"`` for a conductivity), else ``unknown``."""
    return PARAMETER_UNITS.get(parameter_kind(name), unknown)
