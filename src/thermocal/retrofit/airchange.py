"""The air-change loss's dependence on the indoor-outdoor temperature difference.

The fifth-order model has one constant conductance ``H_est`` for ventilation and infiltration.
A real house's infiltration is driven by the stack effect and the wind: its air flow grows with
the indoor-outdoor difference (EnergyPlus' design-flow-rate infiltration,
``Q = Q_design (A + B |dT| + C v + D v^2)``; the Sherman and Grimsrud 1980 / LBL model), so
its heat loss ``rho c_p Q(dT) dT`` is convex in ``dT`` and the calibrated ``H_est`` is its
linearisation at the calibration period's conditions. On the savings verification's
EnergyPlus house (docs/verify.md) the infiltration conductance is 63.5 W/K at a 24.6 K
difference and 56.7 W/K at 19.1 K (1.24 W/K per K). A model calibrated in February therefore
over-predicts the milder days of the heating season.

The retrofit analysis declares the air-change conductance ``H_est + k (dT - dT0)`` about the
calibration period's mean difference ``dT0``; the stack coefficient ``k`` comes from the
calibration period's daily heat residuals (:func:`estimate_slope`) combined with a physical
prior (:func:`stack_prior`, Sherman and Grimsrud 1980), and the term ``k dT (dT - dT0)`` is
added to every heated hour of the demand year (:func:`adjust_demand`).

The savings verification regresses the same residuals on the daily difference itself
(:func:`residual_adjustment`, ``r = c + b (dT - mean dT_pre)``, ASHRAE Guideline 14's
two-parameter inverse model) and applies it to a reporting period close to the baseline's
conditions, only when the slope is resolved (``|b| >= 2 se(b)``).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

#: Residual adjustment only when its slope is at least this many standard errors [-].
MIN_SLOPE_T = 2.0


def residual_adjustment(
    residual_pre: np.ndarray,
    dt_pre: np.ndarray,
    dt_post: np.ndarray,
    rho: float,
    *,
    min_t: float = MIN_SLOPE_T,
) -> dict:
    """Linear adjustment of the baseline model's daily heat in the indoor-outdoor difference.

    The fifth-order model is linear with one constant ``H_est`` (ventilation, infiltration);
    a real house's air change grows with the indoor-outdoor temperature difference (stack
    effect) and the wind, so the calibrated ``H_est`` is the linearisation at the baseline
    period's conditions. The daily residuals of the baseline period (measured minus model)
    regressed on the daily mean indoor-outdoor difference, ``r = c + b (dT - mean dT_pre)``
    (the two-parameter form of ASHRAE Guideline 14's inverse baseline models), measure that
    slope error; applied to the reporting period's days it corrects the extrapolation to
    warmer or colder weather. Estimated from the baseline period only, and applied only when
    that period resolves the slope (``|b| >= 2 se(b)``, the usual t-test of a regression
    term, with the standard error widened for autocorrelated residuals); otherwise no
    adjustment (``applied`` False).

    Parameters
    ----------
    residual_pre : ndarray [kWh/day]
        Measured minus model daily heat of the baseline period.
    dt_pre, dt_post : ndarray [K]
        Daily mean indoor minus outdoor temperature of the baseline and reporting days.
    rho : float [-]
        Lag-1 autocorrelation of the residuals (inflates the variances by ``n / n'``).
    min_t : float [-]
        Applied only when ``|b| >= min_t se(b)`` (0: always, the slope and its standard
        error then go into a posterior, :func:`estimate_slope`).

    Returns
    -------
    dict: ``per_day`` [kWh/day] for the reporting days, ``intercept`` [kWh/day],
    ``slope`` [kWh/(day K)], ``slope_se``, ``sum_se`` [kWh] (standard error of the summed
    adjustment), ``residual`` [kWh/day] of the baseline days after the adjustment,
    ``applied`` (bool).
    """
    r = np.asarray(residual_pre, float)
    x = np.asarray(dt_pre, float) - float(np.mean(dt_pre))
    xp = np.asarray(dt_post, float) - float(np.mean(dt_pre))
    n = len(r)
    sxx = float(np.sum(x**2))
    if n < 4 or sxx <= 0:
        return {"per_day": np.zeros(len(xp)), "intercept": 0.0, "slope": 0.0,
                "slope_se": 0.0, "sum_se": 0.0, "residual": r, "applied": False}  # fmt: skip
    b = float(np.sum(x * r) / sxx)
    c = float(np.mean(r))
    e = r - c - b * x
    rho = max(float(rho), 0.0) if np.isfinite(rho) else 0.0
    inflation = (1.0 + rho) / (1.0 - min(rho, 0.95))  # n / n' of autocorrelated residuals
    s2 = float(np.sum(e**2) / (n - 2)) * inflation
    se_b = float(np.sqrt(s2 / sxx))
    applied = abs(b) >= min_t * se_b
    if not applied:  # the baseline period does not resolve the slope: no adjustment
        return {"per_day": np.zeros(len(xp)), "intercept": c, "slope": b, "slope_se": se_b,
                "sum_se": 0.0, "residual": r, "applied": False}  # fmt: skip
    m, sx = len(xp), float(np.sum(xp))
    sum_var = s2 * (m**2 / n + sx**2 / sxx)
    return {"per_day": c + b * xp, "intercept": c, "slope": b, "slope_se": se_b,
            "sum_se": float(np.sqrt(sum_var)), "residual": e, "applied": True}  # fmt: skip


def daily_energy(power: pd.DataFrame) -> pd.DataFrame:
    """Daily energy [kWh] of complete days of power columns [W].

    A day is complete when it has a value for every step of its length on the index's clock:
    in a time zone with clock changes the spring day has 23 hours and the autumn day 25 (both
    kept; they were dropped as incomplete when every day was taken as 24 hours).
    """
    step = power.index[1] - power.index[0]
    step_h = step / pd.Timedelta(hours=1)
    midnight = power.index.normalize()
    days = power.groupby(midnight)
    starts = pd.DatetimeIndex(days.size().index)
    per_day = np.round(((starts + pd.DateOffset(days=1)) - starts) / step).astype(int)
    complete = days.count().eq(pd.Series(per_day, index=days.size().index), axis=0).all(axis=1)
    return (days.sum(min_count=1) * step_h / 1000.0)[complete]


def lag1(e: np.ndarray) -> float:
    """Lag-1 autocorrelation [-] of a residual series (0 for fewer than three values)."""
    e = np.asarray(e, float)
    if len(e) < 3 or np.std(e[:-1]) == 0 or np.std(e[1:]) == 0:
        return 0.0
    return float(np.corrcoef(e[:-1], e[1:])[0, 1])


def stack_regressor(dt: np.ndarray, dt0: float) -> np.ndarray:
    """``dT (dT - dT0)`` [K^2]: the heat the stack term adds to the linearised model per unit
    ``k`` (the air-change conductance ``H_est + k (dT - dT0)`` times ``dT``, minus ``H_est dT``).
    """
    dt = np.asarray(dt, float)
    return dt * (dt - dt0)


def stack_prior(h_est: float, dt0: float) -> tuple[float, float]:
    """Prior mean and standard deviation [W/K^2] of the stack coefficient ``k``.

    Sherman and Grimsrud (1980): the infiltration flow ``Q = A_L sqrt(C_s dT + C_w v^2)``; with
    no wind ``Q`` grows as ``sqrt(dT)``, so ``dH/d(dT) = H / (2 dT)``: if all of ``H_est`` were
    stack-driven infiltration, ``k_s = H_est / (2 dT0)``. Wind, mechanical ventilation and the
    other losses ``H_est`` holds make ``k`` smaller, down to 0: the prior is ``k_s / 2 +/- k_s /
    2`` (0 and ``k_s`` one standard deviation away).
    """
    if not (h_est > 0 and dt0 > 0):
        return 0.0, 0.0
    k_s = h_est / (2.0 * dt0)
    return 0.5 * k_s, 0.5 * k_s


def estimate_slope(
    measured: pd.Series,
    model: pd.Series,
    indoor: pd.Series,
    temp_out: pd.Series,
    h_est: float,
) -> dict:
    """The stack coefficient ``k`` of the air change from the calibration period's heat.

    The air-change conductance is ``H_est + k (dT - dT0)``: the calibrated ``H_est`` at the
    calibration period's mean difference ``dT0``, growing with the difference (stack effect).
    The daily residuals of the calibrated model (metered minus model heat) are regressed on the
    daily mean of ``dT (dT - dT0)`` (:func:`residual_adjustment`, the savings verification's
    regression, here on the stack term's regressor and without its significance test), and
    the slope combined with the physical prior of :func:`stack_prior` (precision-weighted
    normal posterior). A negative posterior mean (the data contradict the physics) is not
    applied.

    Parameters
    ----------
    measured, model : pd.Series [W]
        Metered heat and the calibrated model's heat on the same regular index.
    indoor : pd.Series [C]
        Indoor temperature the model's heat follows (set point or measured).
    temp_out : pd.Series [C]
        Outdoor air temperature.
    h_est : float [W/K]
        Calibrated air-change conductance.

    Returns
    -------
    dict: ``k_W_per_K2`` and ``k_std`` (posterior), ``k_data`` and ``k_data_std`` (the
    regression), ``k_prior`` and ``k_prior_std``, ``dT0_K`` [K], ``days``, ``applied``.
    """
    dt = (indoor - temp_out).astype(float)
    dt0 = float(dt.mean())
    z = pd.Series(stack_regressor(dt.to_numpy(float), dt0), index=dt.index)
    daily = daily_energy(pd.DataFrame({"measured": measured, "model": model})).dropna()
    z_day = z.groupby(z.index.normalize()).mean().reindex(daily.index)
    ok = z_day.notna().to_numpy()
    resid = (daily["measured"] - daily["model"]).to_numpy(float)[ok]
    fit = residual_adjustment(resid, z_day.to_numpy(float)[ok], np.zeros(0), lag1(resid),
                              min_t=0.0)  # fmt: skip
    to_k = 1000.0 / 24.0  # kWh/(day K^2) -> W/K^2
    k_d, se_d = fit["slope"] * to_k, fit["slope_se"] * to_k
    k_p, se_p = stack_prior(float(h_est), dt0)
    w_p = 1.0 / se_p**2 if se_p > 0 else 0.0
    w_d = 1.0 / se_d**2 if se_d > 0 and fit["applied"] else 0.0
    if fit["applied"] and se_d == 0.0:  # residuals exactly on the stack term
        k, sd = k_d, 0.0
    elif w_p + w_d > 0:
        k = (w_p * k_p + w_d * k_d) / (w_p + w_d)
        sd = float(np.sqrt(1.0 / (w_p + w_d)))
    else:
        k, sd = 0.0, 0.0
    return {
        "k_W_per_K2": float(k), "k_std": sd, "k_data": float(k_d), "k_data_std": float(se_d),
        "k_prior": k_p, "k_prior_std": se_p, "dT0_K": dt0, "days": int(len(resid)),
        "intercept_kWh_per_day": fit["intercept"], "applied": bool(k > 0),
    }  # fmt: skip


def air_change_summary(slope: dict) -> str:
    """One sentence on the estimated stack coefficient and whether the demand uses it."""
    head = (
        f"air change vs indoor-outdoor difference: stack coefficient "
        f"{slope['k_W_per_K2']:.2f} +/- {slope['k_std']:.2f} W/K per K (data "
        f"{slope['k_data']:.2f} +/- {slope['k_data_std']:.2f} over {slope['days']} days, "
        f"physical prior {slope['k_prior']:.2f} +/- {slope['k_prior_std']:.2f}) about the "
        f"calibration's mean difference {slope['dT0_K']:.1f} K"
    )
    if slope["applied"]:
        return f"{head}; applied to the demand year's heated hours"
    return f"{head}; not applied"


def adjust_demand(demand, slope: dict, temp_out: pd.Series, profile, seed: int = 0):
    """The demand with the air change's stack term ``k dT (dT - dT0)`` added.

    On each heated hour (the scenario's estimate needs heat) of the demand year the heat
    changes by ``k_d dT (dT - dT0)``, no hour below zero (measured from the estimate's heat in
    every draw); ``k_d`` is the posterior mean in the first draw and drawn from its normal
    posterior in the others (independent of the other parameters). The same term in every
    strategy: the air change is not retrofitted.

    Parameters
    ----------
    demand : thermocal.retrofit.demand.DemandResult
    slope : dict
        :func:`estimate_slope`; nothing changes unless ``applied``.
    temp_out : pd.Series [C]
        Outdoor air temperature on ``demand.index``.
    profile : float or array (24,) [C]
        The demand's indoor set point.
    seed : int
        Seed of the draws of ``k``.

    Returns
    -------
    DemandResult (a new one; ``demand`` itself when the term is not applied).
    """
    from thermocal.retrofit.demand import DemandResult, interval_setpoint

    if not slope.get("applied"):
        return demand
    idx = demand.index
    step_h = demand.step_hours
    # the interval's mean indoor temperature, as the slope's estimate takes the measured
    # interval means (not the controller's set point at the interval's end)
    sp = interval_setpoint(idx, profile)
    extra = stack_regressor(sp - temp_out.to_numpy(float), slope["dT0_K"])  # [K^2]
    n_scen, n_draws, _ = demand.monthly.shape
    rng = np.random.default_rng(seed + 7919)
    k = slope["k_W_per_K2"] + slope["k_std"] * rng.normal(size=n_draws)
    k[0] = slope["k_W_per_K2"]
    month = idx.month.to_numpy() - 1
    monthly = demand.monthly.copy()
    hourly = demand.hourly.copy()
    for s in range(n_scen):
        q0 = demand.hourly[s]
        heated = np.flatnonzero(q0 > 0)
        # per draw and heated hour: the change, no hour below zero heat (the estimate's heat)
        delta = np.maximum(q0[heated][None, :] + k[:, None] * extra[heated][None, :], 0.0)
        delta -= q0[heated][None, :]
        for m in range(12):
            sel = month[heated] == m
            monthly[s, :, m] += delta[:, sel].sum(axis=1) * step_h / 1000.0
        hourly[s, heated] = q0[heated] + delta[0]
    return DemandResult(np.maximum(monthly, 0.0), hourly, idx)


__all__ = [
    "MIN_SLOPE_T",
    "adjust_demand",
    "air_change_summary",
    "stack_prior",
    "stack_regressor",
    "daily_energy",
    "estimate_slope",
    "residual_adjustment",
]
