"""Moved to :mod:`thermocal.demos.identification` (the identification demo data generator).

This module is a deprecated alias kept so that old imports and the old command keep working:
every name of the new module, the private ones included, is the same object here, and
``python -m thermocal.identification.demo_data ...`` runs
``python -m thermocal.demos.identification ...``. Assigning a name here (e.g. a monkeypatch)
does not change the new module: patch :mod:`thermocal.demos.identification` instead.
"""

import warnings as _warnings

from thermocal.demos import identification as _moved
from thermocal.demos.identification import *  # noqa: F403
from thermocal.demos.identification import __all__, main  # noqa: F401


def __getattr__(name: str):
    """The names that ``import *`` does not carry (the private ones)."""
    return getattr(_moved, name)


_warnings.warn(
    "thermocal.identification.demo_data moved to thermocal.demos.identification",
    DeprecationWarning,
    stacklevel=1 if __name__ == "__main__" else 2,
)

if __name__ == "__main__":
    raise SystemExit(main())
