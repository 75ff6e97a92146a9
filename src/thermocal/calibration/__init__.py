"""Envelope calibration (workflow 2b): parameter spaces, sampling, campaigns, meta-models,
sensitivity and optimisation.

Modules: :mod:`~thermocal.calibration.space`, :mod:`~thermocal.calibration.sampling`,
:mod:`~thermocal.calibration.store`, :mod:`~thermocal.calibration.runner`,
:mod:`~thermocal.calibration.surrogate`, :mod:`~thermocal.calibration.sensitivity`,
:mod:`~thermocal.calibration.optimise`, :mod:`~thermocal.calibration.config`.
Heavy dependencies (scikit-learn, SALib, dask) are imported by the modules that need them only.
"""

from thermocal.calibration.sampling import SampleSet, sample
from thermocal.calibration.space import ParameterSpace
from thermocal.calibration.store import CampaignStore, campaign_definition, campaign_fingerprint

__all__ = [
    "CampaignStore",
    "ParameterSpace",
    "SampleSet",
    "campaign_definition",
    "campaign_fingerprint",
    "sample",
]
