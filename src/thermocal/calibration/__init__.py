"""Envelope calibration (workflow 2b): parameter spaces, sampling, campaigns, meta-models,
sensitivity and optimisation.

Modules: :mod:`~thermocal.calibration.space`, :mod:`~thermocal.calibration.sampling`,
:mod:`~thermocal.calibration.store`, :mod:`~thermocal.calibration.runner`,
:mod:`~thermocal.calibration.surrogate`, :mod:`~thermocal.calibration.sensitivity`,
:mod:`~thermocal.calibration.optimise`, :mod:`~thermocal.calibration.config`.
Heavy dependencies (scikit-learn, SALib, dask) are imported by the modules that need them only.
"""

import importlib

#: The package's names and the modules that define them, imported on first use (PEP 562): a
#: submodule such as :mod:`~thermocal.calibration.clockcheck`, which ``thermocal identify``
#: uses, does not pay for scipy.stats (about 0.6 s and 20 MB) through this package.
_EXPORTS = {
    "CampaignStore": "store",
    "ParameterSpace": "space",
    "SampleSet": "sampling",
    "campaign_definition": "store",
    "campaign_fingerprint": "store",
    "sample": "sampling",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS])
