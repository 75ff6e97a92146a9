"""Deprecated module name: the envelope description lives in :mod:`thermocal.io.envelope`.

``Building`` and ``Location`` here were renamed :class:`~thermocal.io.envelope.EnvelopeDescription`
and :class:`~thermocal.io.envelope.Site`, so that they are not confused with
:class:`thermocal.multizone.Building` and :class:`thermocal.multizone.Location` (the detailed
multi-zone model). The old names still work and warn.
"""

from __future__ import annotations

import warnings
from typing import Any

from thermocal.io import envelope as _envelope
from thermocal.io.envelope import *  # noqa: F403
from thermocal.io.envelope import (  # noqa: F401  (the old function names)
    building_from_dict,
    read_building,
    write_building,
)

_RENAMED = {"Building": "EnvelopeDescription", "Location": "Site"}


def __getattr__(name: str) -> Any:
    if name in _RENAMED:
        warnings.warn(
            f"thermocal.io.building.{name} is now thermocal.io.envelope.{_RENAMED[name]}",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(_envelope, _RENAMED[name])
    try:
        return getattr(_envelope, name)
    except AttributeError:
        raise AttributeError(f"module 'thermocal.io.building' has no attribute {name!r}") from None
