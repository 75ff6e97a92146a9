"""Moved to :mod:`thermocal.demos.retrofit` (the retrofit demo data generator).

This module is a deprecated alias kept so that old imports and the old command keep working:
every name of the new module, the private ones included, is the same object here, and
``python -m thermocal.retrofit.demo_data`` runs ``python -m thermocal.demos.retrofit`` (it
rewrites the shipped demo data). Assigning a name here (e.g. a monkeypatch) does not change the
new module: patch :mod:`thermocal.demos.retrofit` instead.
"""

import warnings as _warnings

from thermocal.demos import retrofit as _moved
from thermocal.demos.retrofit import *  # noqa: F403
from thermocal.demos.retrofit import main  # noqa: F401


def __getattr__(name: str):
    """The names that ``import *`` does not carry (the private ones)."""
    return getattr(_moved, name)


_warnings.warn(
    "thermocal.retrofit.demo_data moved to thermocal.demos.retrofit",
    DeprecationWarning,
    stacklevel=1 if __name__ == "__main__" else 2,
)

if __name__ == "__main__":  # pragma: no cover - rewrites the shipped data
    main()
