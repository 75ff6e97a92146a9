"""Detailed multi-zone building model: data model, sparse thermal network, simulation.

Public API: the dataclasses of :mod:`thermocal.multizone.model`, :func:`load_building`,
:class:`Simulation`, :func:`steady_state_heat_loss_coefficient` and the generators in
:mod:`thermocal.multizone.generators`.
"""

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
    construction_u_value,
)

__all__ = [
    "Building",
    "Construction",
    "Location",
    "Material",
    "NoMassMaterial",
    "Surface",
    "Window",
    "WindowType",
    "Zone",
    "construction_u_value",
]
