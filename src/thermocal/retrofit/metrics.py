"""Validation metrics and aggregation used by the retrofit workflow (the method's Table 2)."""

from __future__ import annotations

import numpy as np
import pandas as pd


def validation_metrics(simulated, measured) -> dict[str, float]:
    """MAE, MAPE, MSE and means of a simulated against a measured temperature series.

    Parameters
    ----------
    simulated : array-like [C]
        Simulated (deterministic, multi-step) indoor temperature.
    measured : array-like [C]
        Measured indoor temperature at the same times; NaNs are skipped pairwise.

    Returns
    -------
    dict
        ``mae`` [K], ``mape`` [%] (relative to the measured value in degrees C, as in the
        paper), ``mse`` [K2], ``rmse`` [K], ``mean_simulated`` [C], ``mean_measured`` [C],
        ``mean_deviation_pct`` [%] (relative deviation of the means, the paper's -0.68 %),
        ``n`` (number of compared values).

    References
    ----------
    The retrofit method (see thermocal.retrofit.references), Table 2 and the "Model
    validation" section.
    """
    sim = np.asarray(simulated, dtype=float)
    meas = np.asarray(measured, dtype=float)
    if sim.shape != meas.shape:
        raise ValueError(f"simulated {sim.shape} and measured {meas.shape} differ in shape")
    ok = np.isfinite(sim) & np.isfinite(meas)
    if not ok.any():
        raise ValueError("no finite pairs of simulated and measured values")
    s, m = sim[ok], meas[ok]
    err = s - m
    with np.errstate(divide="ignore", invalid="ignore"):
        ape = np.abs(err / m)
    ape = ape[np.isfinite(ape)]
    mean_s, mean_m = float(s.mean()), float(m.mean())
    return {
        "mae": float(np.mean(np.abs(err))),
        "mape": float(100.0 * np.mean(ape)) if ape.size else float("nan"),
        "mse": float(np.mean(err**2)),
        "rmse": float(np.sqrt(np.mean(err**2))),
        "mean_simulated": mean_s,
        "mean_measured": mean_m,
        "mean_deviation_pct": float(100.0 * (mean_s - mean_m) / mean_m) if mean_m else float("nan"),
        "n": int(ok.sum()),
    }


def monthly_energy_kwh(power_w: pd.Series) -> pd.Series:
    """Monthly energy [kWh] from a regular power series [W] labelled by interval start.

    Parameters
    ----------
    power_w : pd.Series [W]
        Mean power over each interval ``[t, t + step)``; regular DatetimeIndex.

    Returns
    -------
    pd.Series [kWh]
        Indexed by month number 1..12 (months absent from the data are 0).
    """
    if len(power_w) < 2:
        raise ValueError("need at least two values to infer the time step")
    step_h = (power_w.index[1] - power_w.index[0]) / pd.Timedelta(hours=1)
    energy = power_w * step_h / 1000.0
    monthly = energy.groupby(power_w.index.month).sum()
    return monthly.reindex(range(1, 13), fill_value=0.0)


def daily_profile(series: pd.Series) -> np.ndarray:
    """Mean 24-hour profile (hour 0..23) of an hourly or finer series, NaNs skipped.

    Parameters
    ----------
    series : pd.Series [C]
        e.g. measured indoor temperature with a DatetimeIndex.

    Returns
    -------
    np.ndarray, shape (24,)
        Mean value for each hour of the day (local time of the index).
    """
    profile = series.groupby(series.index.hour).mean()
    if profile.reindex(range(24)).isna().any():
        missing = sorted(set(range(24)) - set(profile.dropna().index))
        raise ValueError(f"no data for hours {missing} of the day: cannot build a 24-h profile")
    return profile.reindex(range(24)).to_numpy(dtype=float)
