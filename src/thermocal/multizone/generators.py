"""Moved to :mod:`thermocal.demos.buildings` (the generated test buildings: house, clinic).

This module is a deprecated alias kept so that old imports keep working: every name of the new
module (:func:`~thermocal.demos.buildings.plan_building`, ``Room``, ``Storey``,
``Constructions``, :func:`~thermocal.demos.buildings.single_family_house`,
:func:`~thermocal.demos.buildings.clinic`, the private ones too) is the same object here.
Assigning a name here (e.g. a monkeypatch) does not change the new module: patch
:mod:`thermocal.demos.buildings` instead.
"""

import warnings as _warnings

from thermocal.demos import buildings as _moved
from thermocal.demos.buildings import *  # noqa: F403


def __getattr__(name: str):
    """The names that ``import *`` does not carry (the private ones)."""
    return getattr(_moved, name)


_warnings.warn(
    "thermocal.multizone.generators moved to thermocal.demos.buildings",
    DeprecationWarning,
    stacklevel=2,
)
