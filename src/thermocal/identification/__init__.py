"""Heat-balance identification: the heat each zone of a detailed model needs to track measurements.

A per-zone discrete PID in controller canonical form (tuned by Ziegler-Nichols on one zone and
scaled by zone volume), or the exact inverse (the heat that puts the model on the measured
temperatures at every step), run in closed loop inside the compiled multi-zone kernel; sensor
logs mapped to zones; occupancy schedules and the unoccupied-variance calibration metric.

Public API: :func:`identify` (the orchestrator) and :class:`IdentificationResult`,
:func:`unoccupied_variance`, :class:`OccupancySchedule`, :class:`PIDGains`,
:func:`ziegler_nichols`, :func:`tune_zone`, :func:`load_mapping`, :class:`IdentificationProblem`.
"""

#: The method's source, cited in reports and docs. Our copy of the paper gives neither its
#: authors nor its venue; complete this entry when the bibliographic data are at hand.
REFERENCE = (
    '"Calibration of envelope parameters using control-based heat balance identification and '
    'uncertainty analysis" (conference paper; case study of a 182-zone student health centre '
    "with 82 wireless sensors, January 2013 data): per-zone PID heat identification, "
    "Ziegler-Nichols tuning, 500-sample campaign, SVR meta-model."
)

_LAZY = {
    "identify": "thermocal.identification.workflow",
    "IdentificationResult": "thermocal.identification.workflow",
    "IdentificationProblem": "thermocal.identification.problem",
    "unoccupied_variance": "thermocal.identification.metrics",
    "OccupancySchedule": "thermocal.identification.occupancy",
    "PIDGains": "thermocal.identification.pid",
    "ziegler_nichols": "thermocal.identification.pid",
    "tune_zone": "thermocal.identification.tuning",
    "load_mapping": "thermocal.identification.sensors",
}

__all__ = ["REFERENCE", *_LAZY]


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'thermocal.identification' has no attribute {name!r}")
