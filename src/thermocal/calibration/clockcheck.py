"""The sensor log's clock against the model's: a log an hour off calibrates the wrong envelope.

A sensor log written in local time with the wrong UTC offset (daylight saving time, a logger
set to another zone) puts every reading an hour or more away from the weather and the schedules
the model runs on. Nothing in the log itself says so, and the campaign then fits the timing
error: on the EnergyPlus twin of 5ZoneAirCooled with its log an hour off, the slab's
resistance came out "determined" at 0.0525 m2 K/W against 0.0838 with the right clock (its
truth 0.0776), and the nominal model's unoccupied heat varied 2.3 times as much.

That last figure is the check. The heat the model needs to follow the measured temperatures is
smoothest when the log's clock is the model's: the nominal model is identified with the log as
it is and shifted by an hour either way (:data:`SHIFTS`), over the same hours, and a shift that
lowers the building's unoccupied standard deviation by more than :data:`CLOCK_TOLERANCE` is
reported. On the twin with its right clock the unshifted log is the minimum by far (0.59 kW
against 1.29 and 1.32 kW an hour either way; docs/calibration.md, "The sensor log's clock").
A model whose own timing is off (its capacities) could in principle prefer a shifted log too,
so the warning names both causes.

One implementation for both commands: :func:`check_log_clock` is the campaign's (the nominal
problem rebuilt on the shifted log); ``thermocal identify`` computes its own standard deviation
per shift (:func:`thermocal.identification.workflow.check_identified_log_clock`); both take the
period (:func:`clock_check_window`), the search (:func:`best_clock_shift`), the verdict and its
note (:func:`clock_result`) and the warning (:func:`warn_if_clock_off`) from here.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

__all__ = ["CAMPAIGN_CONSEQUENCE", "CLOCK_TOLERANCE", "SHIFTS", "LogClockWarning",
           "best_clock_shift", "check_log_clock", "clock_check_window", "clock_result",
           "warn_if_clock_off"]  # fmt: skip


class LogClockWarning(UserWarning):
    """The sensor log agrees better with the model shifted by an hour or more."""


#: Shifts of the sensor log tried [h]; a better one is followed further, up to the largest.
SHIFTS = (-1.0, 1.0)
#: Largest shift tried when one of :data:`SHIFTS` is better [h].
MAX_SHIFT_H = 3.0
#: Relative reduction of the unoccupied standard deviation a shift must bring to be reported
#: [-]: the twin's wrong clock gave 2.3 times its right clock's.
CLOCK_TOLERANCE = 0.2


def shifted_log(sensor_log: pd.DataFrame, hours: float) -> pd.DataFrame:
    """The sensor log with every time stamp moved by ``hours`` [h] (long or wide form)."""
    out = sensor_log.copy()
    shift = pd.Timedelta(hours=hours)
    if "time" in out.columns:
        out["time"] = out["time"] + shift
    else:
        out.index = out.index + shift
    return out


def check_log_clock(campaign, inputs, problem, evaluator_for, log) -> dict | None:
    """Identify the nominal model with the log as it is and shifted; report a better shift.

    Parameters
    ----------
    campaign : CampaignSpec
        The campaign (its step and file, for the message).
    inputs : CampaignInputs
        Its inputs (the sensor log and the period).
    problem : IdentificationProblem
        The campaign's problem, its quiet-hour schedule chosen.
    evaluator_for : callable
        ``evaluator_for(problem)`` -> the campaign's evaluator of that problem (its
        ``outputs(heat)["unoccupied_std"]`` [W]).
    log : callable
        Progress lines.

    Returns
    -------
    dict or None
        ``std`` (shift [h] -> unoccupied std [W]), ``best`` (the shift [h] with the lowest),
        ``passed`` and the report's ``note`` (a :class:`LogClockWarning` when it failed); None
        when the period is too short to shift (under two days once :data:`MAX_SHIFT_H` is taken
        off each end) or the log as written gives no unoccupied heat to compare.
    """
    from thermocal.calibration.inputs import build_problem

    window = clock_check_window(inputs.start, inputs.end, campaign.step_timedelta())
    if window is None:
        return None
    start, end = window
    log("sensor log's clock: identifying the nominal model with the log shifted by +-1 h")

    def unoccupied_std(hours: float) -> float:
        shifted = dataclasses.replace(inputs, sensor_log=shifted_log(inputs.sensor_log, hours))
        try:
            with warnings.catch_warnings():  # the campaign's own set-up said them already
                warnings.simplefilter("ignore")
                candidate, _ = build_problem(campaign, shifted, start=start, end=end,
                                             schedule=problem.schedule)  # fmt: skip
        except ThermocalInputError:
            return float("nan")
        candidate.series_outputs = True
        return float(evaluator_for(candidate).outputs(candidate.run({}).heat)["unoccupied_std"])

    found = best_clock_shift(unoccupied_std)
    if found is None:
        return None  # nothing to compare with (the shortened period left no quiet hours)
    result = clock_result(*found, consequence=CAMPAIGN_CONSEQUENCE)
    warn_if_clock_off(result, campaign.path)
    return result


def clock_check_window(start, end, step) -> tuple[pd.Timestamp, pd.Timestamp] | None:
    """The hours every shift of the log is compared over: the period less :data:`MAX_SHIFT_H`
    at each end, on the step's grid.

    Parameters
    ----------
    start, end : timestamp-like
        The period ``[start, end)`` of the identification.
    step : Timedelta
        The model's step [time].

    Returns
    -------
    (Timestamp, Timestamp) or None
        ``[start + MAX_SHIFT_H, end - MAX_SHIFT_H)`` rounded inwards to the step; None when it
        is shorter than two days (too short to tell a shift from the weather).
    """
    margin = pd.Timedelta(hours=MAX_SHIFT_H)
    first = (pd.Timestamp(start) + margin).ceil(step)
    last = (pd.Timestamp(end) - margin).floor(step)
    if last - first < pd.Timedelta(days=2):
        return None
    return first, last


def best_clock_shift(unoccupied_std) -> tuple[dict, float] | None:
    """Search the log's shift that makes the model's unoccupied heat smoothest.

    The log as written and :data:`SHIFTS` are tried; a shift better than the log as written is
    followed an hour at a time while it keeps improving, up to :data:`MAX_SHIFT_H`.

    Parameters
    ----------
    unoccupied_std : callable
        ``unoccupied_std(hours)`` -> the standard deviation [W] of the building's identified
        heat over the quiet hours with the log's time stamps moved by ``hours`` [h] (NaN when
        that shift cannot be identified).

    Returns
    -------
    (dict, float) or None
        The standard deviations tried (shift [h] -> std [W]) and the best shift [h]; None when
        the log as written gives no finite, positive standard deviation to compare with.
    """
    std = {0.0: unoccupied_std(0.0)}
    if not np.isfinite(std[0.0]) or std[0.0] <= 0.0:
        return None
    for first in SHIFTS:
        std[first] = unoccupied_std(first)
    best = min((h for h in std if np.isfinite(std[h])), key=std.get, default=0.0)
    direction = np.sign(best)
    while best != 0.0 and abs(best) < MAX_SHIFT_H:  # follow a better shift to its minimum
        further = best + direction
        std[further] = unoccupied_std(further)
        if not std[further] < std[best]:
            break
        best = further
    return std, best


#: What a log an hour off does to a calibration campaign, and its remedy (the warning's middle).
CAMPAIGN_CONSEQUENCE = (
    "A campaign on a log an hour off fits the timing error into the envelope; correct the time "
    "stamps (or 'tz' in the campaign's identification section) and run again."
)


def clock_result(std: dict, best: float, *, consequence: str) -> dict:
    """The clock check's figures and its note (the warning's text when a shift is better).

    Parameters
    ----------
    std : dict
        Shift of the log [h] -> standard deviation of the unoccupied heat [W]
        (:func:`best_clock_shift`); 0.0 is the log as written.
    best : float
        The shift with the lowest [h].
    consequence : str
        What a log an hour off does to this command's answer and how to correct the clock
        (:data:`CAMPAIGN_CONSEQUENCE` for a campaign), put between the question about the clocks
        and the other cause (the model's timing).

    Returns
    -------
    dict
        ``std`` (by the shift as text), ``best`` [h], ``gain`` (relative reduction of the
        standard deviation at ``best`` [-]), ``tolerance`` (:data:`CLOCK_TOLERANCE`),
        ``passed`` and ``note``.
    """
    own = std[0.0]
    gain = 1.0 - std[best] / own
    passed = best == 0.0 or not gain > CLOCK_TOLERANCE
    around = ", ".join(f"{h:+g} h {std[h] / 1000:.3f} kW" for h in sorted(std) if h != 0.0)
    if passed:
        note = (
            f"Sensor log's clock: the model's unoccupied heat is smoothest with the log as "
            f"written ({own / 1000:.3f} kW standard deviation; shifted {around})."
        )
    else:
        later = "later" if best > 0 else "earlier"
        note = (
            f"Sensor log's clock: the model follows the log much better with its time stamps "
            f"{abs(best):g} h {later} ({std[best] / 1000:.3f} kW standard deviation of the "
            f"unoccupied heat against {own / 1000:.3f} kW as written; shifted {around}). Is "
            "the log written in local time with the wrong UTC offset (daylight saving time, a "
            "logger set to another zone), or the weather file's clock off? "
            f"{consequence} If both clocks "
            "are right, the model's timing (its heat capacities) is far from the building's."
        )
    return {
        "std": {str(h): v for h, v in sorted(std.items())},
        "best": best,
        "gain": gain,
        "tolerance": CLOCK_TOLERANCE,
        "passed": bool(passed),
        "note": note,
    }


def warn_if_clock_off(result: dict, path) -> None:
    """Warn (:class:`LogClockWarning`, naming the campaign file ``path``) when a clock check's
    ``result`` found a better shift.

    Parameters
    ----------
    result : dict
        As returned by :func:`check_log_clock` (or stored with the campaign).
    path : path
        The campaign file.
    """
    if not result["passed"]:
        warnings.warn(f"{path}: {result['note']}", LogClockWarning, stacklevel=3)
