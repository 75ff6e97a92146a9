"""Tracking metrics and the unoccupied-variance calibration metric.

The calibration metric of the heat-balance identification is the variance of the building-wide
identified heat (the sum of Q_ID over all zones at each step) over the unoccupied steps: with a
well calibrated envelope, the heat needed at night and on weekends is only the small, constant
load of idle equipment, so whatever varies (and follows the weather) is envelope error.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.identification.occupancy import OccupancySchedule, unoccupied_mask


def building_heat(q_id) -> pd.Series:
    """Building-wide identified heat per step [W] from per-zone Q_ID (a frame) or a total."""
    if isinstance(q_id, pd.Series):
        return q_id
    if isinstance(q_id, pd.DataFrame):
        return q_id.sum(axis=1)
    total = getattr(q_id, "building_heat", None)
    if total is not None:
        return total
    raise ThermocalInputError(
        "unoccupied_variance: expected an IdentificationResult, a frame of Q_ID per zone or a "
        "series of the building total"
    )


def unoccupied_variance(
    q_id,
    schedule: OccupancySchedule | None = None,
    *,
    settle: str | pd.Timedelta | None = "1D",
) -> float:
    """Variance of the building-wide identified heat over the unoccupied steps [W^2].

    Parameters
    ----------
    q_id : IdentificationResult, DataFrame or Series
        Identified heat per zone and step [W] (summed over the zones), or its building total.
    schedule : OccupancySchedule, optional
        Default: the paper's (nights 20-04, Saturdays 11-20, Sundays).
    settle : str, Timedelta or None
        Steps in this first part of the period are left out (the initial state of walls and
        floors is estimated, not measured); None keeps every step.

    Returns
    -------
    float [W^2]
        Population variance (``ddof=0``) of the building total over the unoccupied steps.
    """
    total = building_heat(q_id)
    mask = unoccupied_steps(total.index, schedule, settle=settle)
    values = total.to_numpy(dtype=float)[mask]
    if len(values) < 2:
        raise ThermocalInputError(
            "unoccupied_variance: fewer than two unoccupied steps in the period; check the "
            "occupancy schedule and the period"
        )
    if not np.isfinite(values).all():
        return float("nan")
    return float(np.var(values))


def unoccupied_steps(
    index: pd.DatetimeIndex,
    schedule: OccupancySchedule | None = None,
    *,
    settle: str | pd.Timedelta | None = "1D",
) -> np.ndarray:
    """Boolean mask of the steps that enter the metric (unoccupied and after ``settle``)."""
    mask = unoccupied_mask(index, schedule)
    if settle is not None and len(index):
        mask &= index >= index[0] + pd.Timedelta(settle)
    return mask


#: Zones whose tracking errors :func:`tracking_metrics` computes at a time [-].
TRACKING_METRICS_BLOCK = 16


def tracking_metrics(model: pd.DataFrame, reference: pd.DataFrame) -> pd.DataFrame:
    """Per-zone tracking error of the model temperature against the reference.

    Parameters
    ----------
    model, reference : DataFrame (steps x zones) [C]

    Returns
    -------
    DataFrame indexed by zone
        ``rmse_K``, ``max_abs_error_K``, ``bias_K`` and ``error_std_percent``: the paper's
        Fig. 4 quantity, the standard deviation from zero of the error in percent of the
        reference temperature [C], here normalised by the zone's mean ``|T_ref|`` instead of
        each step's ``T_ref`` (which explodes in a free-floating building near 0 C).
    """
    model_values = model.to_numpy(dtype=float)
    reference_values = reference.to_numpy(dtype=float)
    n_zones = reference_values.shape[1]
    rmse, max_abs, bias, level = (np.empty(n_zones) for _ in range(4))
    # a block of zones at a time: the month-long error of every zone at once would be a
    # temporary the size of the frames (13 MiB for the clinic) several times over
    for first in range(0, n_zones, TRACKING_METRICS_BLOCK):
        block = slice(first, first + TRACKING_METRICS_BLOCK)
        error = model_values[:, block] - reference_values[:, block]
        rmse[block] = np.sqrt(np.nanmean(error**2, axis=0))
        max_abs[block] = np.nanmax(np.abs(error), axis=0)
        bias[block] = np.nanmean(error, axis=0)
        level[block] = np.nanmean(np.abs(reference_values[:, block]), axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        percent = np.where(level > 1e-9, 100.0 * rmse / level, np.nan)
    return pd.DataFrame(
        {
            "rmse_K": rmse,
            "max_abs_error_K": max_abs,
            "bias_K": bias,
            "error_std_percent": percent,
        },
        index=pd.Index(reference.columns, name="zone"),
    )


def guideline14(simulated, measured) -> dict[str, float]:
    """ASHRAE Guideline 14 goodness of fit of a simulated against a measured series.

    ``CV(RMSE) = sqrt(sum (m - s)^2 / (n - 1)) / mean(m)`` and
    ``NMBE = sum (m - s) / ((n - 1) mean(m))``, both in percent (ASHRAE Guideline 14-2014,
    clause 4.3.3.4; hourly criteria for a calibrated model: CV(RMSE) <= 30 %, |NMBE| <= 10 %).

    Parameters
    ----------
    simulated, measured : array-like (same length)

    Returns
    -------
    dict with ``cv_rmse_percent``, ``nmbe_percent``, ``n``
    """
    s = np.asarray(simulated, dtype=float)
    m = np.asarray(measured, dtype=float)
    keep = np.isfinite(s) & np.isfinite(m)
    s, m = s[keep], m[keep]
    n = len(m)
    mean = m.mean() if n else np.nan
    if n < 2 or mean == 0:
        return {"cv_rmse_percent": float("nan"), "nmbe_percent": float("nan"), "n": n}
    return {
        "cv_rmse_percent": float(100.0 * np.sqrt(((m - s) ** 2).sum() / (n - 1)) / mean),
        "nmbe_percent": float(100.0 * (m - s).sum() / ((n - 1) * mean)),
        "n": n,
    }
