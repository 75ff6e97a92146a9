"""A campaign at a coarser time step than its sensor log, checked against the log's own step.

Each campaign sample is one identification of the month, and its cost is the number of time
steps. The calibration uses how the identified heat *responds* to the parameters (the
meta-model's fit of the samples' unoccupied-heat series, the posterior's Jacobian), not the
heat's level, and that response is much less sensitive to the step than the level. On the
clinic demo (sensors every 5 minutes; docs/calibration.md, "A coarser campaign step") the
500-sample campaign took 106 s at 15 minutes against 284 s at 5; its posterior was close but
not the same: the roof's resistance (insulation thickness over conductivity) 4 % lower, one
parameter no longer determined and another one now determined, for a response 6.3 % off.

So a campaign may run at a coarser ``step`` than the log, and :func:`check_campaign_step` says
whether it may for this building: before the campaign, the nominal model and the first
:data:`CHECKED_SAMPLES` samples of the design are identified at both steps, and the response of
the hourly unoccupied heat to each sample (its series minus the nominal one) is compared. A
response that differs by more than :data:`STEP_TOLERANCE` of its own size is reported: the
campaign's step then changes what the calibration sees. A pass does not bound how far the
answer moves: on the EnergyPlus twin of 5ZoneAirCooled (sensors every 5 minutes) 30 minutes
passed at 2.3 % and moved the wall's resistance by 7.2 % (0.41 of its 90 % half-width;
docs/calibration.md, ``tests/reference/calibration_energyplus_5zone/step.md``).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.textformat import duration_text

__all__ = ["CHECKED_SAMPLES", "STEP_TOLERANCE", "CampaignStepWarning", "check_campaign_step",
           "log_interval", "response_difference", "warn_if_failed"]  # fmt: skip


class CampaignStepWarning(UserWarning):
    """The campaign's step changes the identified heat's response to the parameters beyond
    :data:`STEP_TOLERANCE` of the sensor log's step."""

#: Samples of the design whose response is compared at the two steps [-].
CHECKED_SAMPLES = 2
#: A log step below this is not simulated for the check [duration].
MIN_CHECKED_STEP = pd.Timedelta("1min")
#: Nor one more than this many times finer than the campaign's [-].
MAX_STEP_RATIO = 12
#: Largest relative RMS difference of the responses at the two steps that passes [-]: the
#: clinic demo's 6.3 % at 15 minutes moved its roof's resistance by 4 % (500 samples).
STEP_TOLERANCE = 0.05


def log_interval(sensor_log: pd.DataFrame, sensors=None) -> pd.Timedelta | None:
    """The sensor log's reporting interval: the median over the sensors of the median spacing
    of each sensor's own readings, rounded to the nearest step that divides an hour.

    Parameters
    ----------
    sensor_log : DataFrame
        As read by :func:`thermocal.io.measurements.read_measurements`: long (``time``,
        ``sensor``, ``value``) or wide (a DatetimeIndex, a column per sensor; each column's
        spacing from its own non-missing readings, so staggered sensors are not merged).
    sensors : collection of str, optional
        The sensors that make the references (the mapping's); others (a fast power meter
        beside the temperatures) do not count. None: all.

    Returns
    -------
    Timedelta or None
        None when it cannot be told (fewer than two readings per sensor).
    """
    wanted = None if sensors is None else {str(s) for s in sensors}
    if {"time", "sensor"} <= set(sensor_log.columns):
        groups = (
            (str(name), pd.DatetimeIndex(times))
            for name, times in sensor_log.groupby("sensor", observed=True)["time"]
        )
    elif isinstance(sensor_log.index, pd.DatetimeIndex):
        groups = (
            (str(col), sensor_log.index[sensor_log[col].notna().to_numpy()])
            for col in sensor_log.columns
        )
    else:
        return None
    spacings = [
        float(np.median(np.diff(times.as_unit("ns").asi8)))
        for name, times in groups
        if (wanted is None or name in wanted) and len(times) > 1
    ]
    if not spacings:
        return None
    median = float(np.median(spacings))
    steps = [d * 10**9 for d in range(1, 3601) if 3600 % d == 0]  # [ns]
    nearest = min(steps, key=lambda step: abs(step - median))
    return pd.Timedelta(int(nearest), unit="ns")


def response_difference(nominal_fine, sample_fine, nominal_coarse, sample_coarse) -> float:
    """Relative RMS difference of a sample's response at two steps.

    Parameters
    ----------
    nominal_fine, sample_fine, nominal_coarse, sample_coarse : array-like (n_hours,) [W]
        The hourly unoccupied heat series of the nominal model and of the sample, at the
        fine and at the coarse step.

    Returns
    -------
    float
        ``|r_coarse - r_fine| / |r_fine|`` with ``r = sample - nominal`` [-]; NaN when the
        sample does not change the series at the fine step.
    """
    fine = np.asarray(sample_fine, float) - np.asarray(nominal_fine, float)
    coarse = np.asarray(sample_coarse, float) - np.asarray(nominal_coarse, float)
    size = float(np.sqrt(np.mean(fine**2)))
    if size == 0.0:
        return float("nan")
    return float(np.sqrt(np.mean((coarse - fine) ** 2)) / size)


def _series(outputs: dict) -> np.ndarray:
    keys = sorted(k for k in outputs if k.startswith("series/"))
    return np.array([outputs[k] for k in keys], dtype=float)


def check_campaign_step(
    campaign, inputs, problem, design: pd.DataFrame, log, nominal_outputs: dict | None = None
) -> dict | None:
    """Compare the responses of the first design samples at the campaign's and the log's step.

    Parameters
    ----------
    campaign : CampaignSpec
        The campaign (its ``step``).
    inputs : CampaignInputs
        Its inputs (the sensor log gives the fine step).
    problem : IdentificationProblem
        The campaign's problem at its step, with its quiet-hour schedule chosen.
    design : DataFrame
        The campaign's samples (a column per parameter, in its units).
    log : callable
        Progress lines.
    nominal_outputs : dict, optional
        The campaign's own outputs of the nominal model at its step (its ``series/*`` hours),
        which the check then does not identify again.

    Returns
    -------
    dict or None
        ``step``, ``log_step`` (text), ``differences`` (one per checked sample [-]),
        ``largest``, ``tolerance``, ``passed`` and the report's ``note``; None when the
        campaign runs at the log's step or finer (nothing to check).
    """
    from thermocal.calibration.inputs import build_problem

    mapping = inputs.mapping
    sensors = getattr(mapping, "sensors", None)
    if sensors is None and isinstance(mapping, dict):
        sensors = mapping.get("sensors")
    fine_step = log_interval(inputs.sensor_log, None if sensors is None else list(sensors))
    step = pd.Timedelta(campaign.step)
    if fine_step is None or fine_step >= step or design.empty:
        return None
    fine_text = duration_text(fine_step)
    if fine_step < MIN_CHECKED_STEP or step / fine_step > MAX_STEP_RATIO:
        return _note(campaign.step, fine_text, [], (
            f"not checked (the log's step is {step / fine_step:.0f} times finer: three "
            "identifications at it would cost more than the check is worth)"
        ))  # fmt: skip
    log(f"campaign step {campaign.step}: checking its response against the log's {fine_text}")
    try:
        with warnings.catch_warnings():  # the campaign's own set-up said them already
            warnings.simplefilter("ignore")
            fine, _ = build_problem(campaign, inputs, schedule=problem.schedule, step=fine_step)
    except ThermocalInputError as exc:
        return _note(campaign.step, fine_text, [], f"not checked ({exc})")
    fine.series_outputs = problem.series_outputs = True
    points = [{}] + [
        {k: float(v) for k, v in row.items()} for _, row in design.head(CHECKED_SAMPLES).iterrows()
    ]
    coarse_series = [
        _series(nominal_outputs) if not p and nominal_outputs else _series(problem.evaluate(p))
        for p in points
    ]
    fine_series = [_series(fine.evaluate(p)) for p in points]
    if any(len(c) != len(f) for c, f in zip(coarse_series, fine_series, strict=True)):
        return _note(campaign.step, fine_text, [], "not checked (the steps give other hours)")
    differences = [
        response_difference(fine_series[0], f, coarse_series[0], c)
        for f, c in zip(fine_series[1:], coarse_series[1:], strict=True)
    ]
    result = _note(campaign.step, fine_text, differences, None)
    warn_if_failed(result, campaign.path)
    return result


def warn_if_failed(result: dict, path) -> None:
    """Warn (:class:`CampaignStepWarning`, naming the campaign file ``path``) when a step
    check's ``result`` compared the responses and found them beyond its tolerance.

    Parameters
    ----------
    result : dict
        As returned by :func:`check_campaign_step` (or stored with the campaign).
    path : path
        The campaign file.
    """
    largest = result.get("largest")
    if not result["passed"] and largest is not None and np.isfinite(largest):
        warnings.warn(f"{path}: {result['note']}", CampaignStepWarning, stacklevel=3)


def _note(step: str, fine_text: str, differences: list[float], skipped: str | None) -> dict:
    finite = [d for d in differences if np.isfinite(d)]
    largest = max(finite) if finite else float("nan")
    passed = skipped is None and bool(finite) and largest <= STEP_TOLERANCE
    if skipped is not None or not finite:
        why = skipped or "not checked (the samples do not change the unoccupied heat)"
        note = f"Campaign step {step} (the sensor log's: {fine_text}): {why}."
    elif passed:
        note = (
            f"Campaign step {step} (the sensor log's: {fine_text}): the unoccupied heat's "
            f"response to the first {len(finite)} samples differs from the log step's by at "
            f"most {100 * largest:.1f} % (tolerance {100 * STEP_TOLERANCE:.0f} %). A pass does "
            "not bound how far the answer moves (on an EnergyPlus twin 30 minutes passed at 2.3 % "
            "and moved the wall's resistance by 7 %): calibrate at the log's step for the answer "
            "a decision rests on."
        )
    else:
        note = (
            f"Campaign step {step}: the unoccupied heat's response to the first "
            f"{len(finite)} samples differs from that at the sensor log's {fine_text} by up "
            f"to {100 * largest:.1f} % (tolerance {100 * STEP_TOLERANCE:.0f} %): the step "
            "changes what the calibration sees; run the campaign at a finer step"
        )
    return {
        "step": step,
        "log_step": fine_text,
        "differences": differences,
        "largest": largest,
        "tolerance": STEP_TOLERANCE,
        "passed": passed,
        "note": note,
    }
