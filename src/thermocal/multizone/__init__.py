"""Detailed multi-zone building model: data model, sparse thermal network, simulation.

Public API: the dataclasses of :mod:`thermocal.multizone.model`, :func:`load_building` /
:func:`save_building` (YAML, IDF), :class:`Simulation`, :class:`SimulationResult`,
:func:`steady_state_heat_loss_coefficient`, :class:`NetworkOptions`; ``generators`` is
:mod:`thermocal.demos.buildings` (the generated demo buildings, formerly
``thermocal.multizone.generators``). The simulation layer (numba) is imported lazily.
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

_LAZY = {
    "load_building": "thermocal.multizone.files",
    "save_building": "thermocal.multizone.files",
    "Simulation": "thermocal.multizone.simulation",
    "SimulationResult": "thermocal.multizone.simulation",
    "steady_state_heat_loss_coefficient": "thermocal.multizone.simulation",
    "NetworkOptions": "thermocal.multizone.network",
    "generators": "thermocal.demos.buildings",
}

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
    *_LAZY,
]


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        module = importlib.import_module(_LAZY[name])
        return module if name == "generators" else getattr(module, name)
    raise AttributeError(f"module 'thermocal.multizone' has no attribute {name!r}")
