"""The validation gate: does the calibrated model reproduce the test period well enough to
recommend a retrofit?

Two checks on the held-out test period (never the training period):

- indoor temperature, the multi-step simulation of the fifth-order method: the bias (mean of
  simulated minus measured) and the mean absolute error;
- heat, ASHRAE Guideline 14 statistics (NMBE and CV(RMSE)) of the daily heat the calibrated
  model needs to follow the measured indoor temperature against the measured heat. The
  ideal controller of the demand simulation delivers that heat (into the air node), so this
  checks exactly the part of the model the annual demand and the savings use.

Defaults (``validation:`` in the retrofit configuration):

- ``max_abs_bias_K: 1.0``: a 1 K error of the mean indoor temperature is about 5 % of the heat
  at the 20 K mean indoor-outdoor difference of a central-European heating season;
- ``max_mae_K: 1.5``: well above the method's own case study (test MAE 0.86 K) and the
  demo (0.75 K), well below a model that does not describe the house (5 K);
- ``max_abs_nmbe_pct: 10`` and ``max_cv_rmse_pct: 30``: ASHRAE Guideline 14-2014 for hourly
  calibration data (monthly data: 5 % and 15 %), here applied to daily sums, which are
  smoother than hourly values, so the limits are lenient rather than strict.

References
----------
ASHRAE Guideline 14-2014, Measurement of Energy, Demand, and Water Savings, clause 4.3.2.4
(calibration criteria: NMBE and CV(RMSE) with ``n - p`` degrees of freedom, p = 1).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

#: Criteria and their defaults (also the ``validation:`` keys of the configuration).
DEFAULT_CRITERIA: dict[str, float] = {
    "max_abs_bias_K": 1.0,
    "max_mae_K": 1.5,
    "max_abs_nmbe_pct": 10.0,
    "max_cv_rmse_pct": 30.0,
}


def ashrae14_statistics(simulated, measured, p: int = 1) -> dict[str, float]:
    """NMBE and CV(RMSE) [%] of ASHRAE Guideline 14 (measured minus simulated in NMBE).

    Parameters
    ----------
    simulated, measured : array-like
        Simulated and measured energies of the same intervals (e.g. daily heat [kWh]).
    p : int
        Number of parameters subtracted from the degrees of freedom (Guideline 14: 1).

    Returns
    -------
    dict with ``nmbe_pct`` (positive: the model under-predicts), ``cv_rmse_pct``, ``n``.
    """
    s = np.asarray(simulated, dtype=float)
    m = np.asarray(measured, dtype=float)
    ok = np.isfinite(s) & np.isfinite(m)
    s, m = s[ok], m[ok]
    n = int(ok.sum())
    if n <= p or not m.mean() > 0:
        return {"nmbe_pct": float("nan"), "cv_rmse_pct": float("nan"), "n": n}
    mean = float(m.mean())
    return {
        "nmbe_pct": float(100.0 * np.sum(m - s) / ((n - p) * mean)),
        "cv_rmse_pct": float(100.0 * np.sqrt(np.sum((m - s) ** 2) / (n - p)) / mean),
        "n": n,
    }


class FollowInputs(NamedTuple):
    """The measured series of :func:`heat_to_follow_measured` as arrays, prepared once for
    many parameter sets (a fit evaluates thousands)."""

    dt: float  # [s]
    u: np.ndarray  # inputs, gaps interpolated
    ti: np.ndarray  # measured indoor temperature [C], gaps interpolated
    gains: np.ndarray | None  # internal gains into the air node [W]


def follow_inputs(
    inputs: pd.DataFrame, measured_ti: pd.Series, gains: pd.Series | None = None
) -> FollowInputs:
    """:class:`FollowInputs` of ``inputs`` (regular index, the columns of
    :data:`thermocal.retrofit.demand.DEMAND_INPUTS`), ``measured_ti`` [C] and ``gains`` [W]
    (see :func:`heat_to_follow_measured`)."""
    from thermocal.retrofit.demand import DEMAND_INPUTS

    dt = (inputs.index[1] - inputs.index[0]).total_seconds()
    u = inputs[list(DEMAND_INPUTS)].interpolate(limit_direction="both").to_numpy(float)
    ti = measured_ti.interpolate(limit_direction="both").to_numpy(float)
    g = None if gains is None else gains.interpolate(limit_direction="both").to_numpy(float)
    # C-ordered once: the controller would copy a frame's (column-ordered) values each time
    return FollowInputs(float(dt), np.ascontiguousarray(u), ti, g)


def heat_to_follow(
    model, params_si: dict, envelope, x_start: np.ndarray, follow: FollowInputs
) -> np.ndarray:
    """:func:`heat_to_follow_measured` on prepared arrays (:func:`follow_inputs`) [W]."""
    from thermocal.retrofit.model import discrete_system_matrices
    from thermocal.retrofit.simulation import ideal_heating_batch

    ti, u = follow.ti, follow.u
    # the controller's set point applies at the END of each interval. The measured Ti are
    # interval MEANS labelled by their start, so the temperature at the boundary between
    # intervals k and k + 1 is estimated by the mean of the two (not the next interval's mean:
    # that moves every thermostat step, a morning recovery or a night set-back, one interval
    # early, and the fit then shrinks the internal capacities to make the misplaced recovery
    # heat small; issue 25, the basement twin's C_im and C_i on their lower bounds)
    sp = 0.5 * (ti + np.append(ti[1:], ti[-1]))
    p = {k: np.atleast_1d(float(v)) for k, v in params_si.items()}
    h = model.conductances(envelope)
    ad, bd = discrete_system_matrices(h, p, follow.dt, indoor_input=True)
    if follow.gains is not None:
        from thermocal.retrofit.demand import with_gains
        from thermocal.retrofit.model import system_matrices

        a, b = system_matrices(h, p, indoor_input=True)
        _, _, ad, bd, u = with_gains(a, b, ad, bd, u, follow.gains, None)
    x0 = np.asarray(x_start, float)[: ad.shape[1]].copy()
    x0[0] = ti[0]
    q, _, _ = ideal_heating_batch(ad, bd, x0[None, :], u, sp)
    return q[0]


def heat_to_follow_measured(
    model,
    params_si: dict,
    envelope,
    x_start: np.ndarray,
    inputs: pd.DataFrame,
    measured_ti: pd.Series,
    gains: pd.Series | None = None,
) -> pd.Series:
    """Heat [W] the model needs to follow the measured indoor temperature (ideal controller).

    The demand model of :func:`thermocal.retrofit.demand.simulate_demand` (heating into the
    air node, the engine's exact discretisation, the compiled controller of
    :mod:`thermocal.retrofit.simulation`), with the measured ``Ti`` as set point.

    Parameters
    ----------
    model : FifthOrderModel
    params_si : dict
        Estimated parameters in SI (W/K, J/K).
    envelope : EnvelopeComponents or None
        The calibrated U-values (None: the building file's).
    x_start : ndarray [C]
        States (Ti, Tenv, Tgf, Tim, ...) at the first interval start.
    inputs : pd.DataFrame
        Regular index; columns of :data:`thermocal.retrofit.demand.DEMAND_INPUTS`.
    measured_ti : pd.Series [C]
        Measured indoor temperature (interval means labelled by their start) on the same index.
    gains : pd.Series [W], optional
        Internal gains into the air node (not part of the returned heat).

    Returns
    -------
    pd.Series [W], interval means on ``inputs.index``.
    """
    follow = follow_inputs(inputs, measured_ti, gains)
    q = heat_to_follow(model, params_si, envelope, x_start, follow)
    return pd.Series(q, index=inputs.index, name="phi_h_model")


def heat_validation(simulated_w: pd.Series, measured_w: pd.Series) -> dict[str, float]:
    """Daily heat [kWh] of model and measurement and their ASHRAE Guideline 14 statistics.

    Only whole days with every interval measured count.
    """
    step_h = (simulated_w.index[1] - simulated_w.index[0]) / pd.Timedelta(hours=1)
    per_day = round(24.0 / step_h)
    frame = pd.DataFrame({"sim": simulated_w, "meas": measured_w})
    days = frame.groupby(frame.index.normalize())
    complete = days["meas"].count() == per_day
    energy = days.sum(min_count=1)[complete] * step_h / 1000.0
    stats = ashrae14_statistics(energy["sim"], energy["meas"])
    stats.update(
        {
            "resolution": "daily",
            "model_kWh": float(energy["sim"].sum()),
            "measured_kWh": float(energy["meas"].sum()),
        }
    )
    return stats


def validation_gate(
    validation: dict,
    heat: dict | None,
    criteria: dict[str, float],
    *,
    unit_keys: str | None = None,
    heat_source: str = "meter",
) -> dict:
    """The verdict on the test period.

    Parameters
    ----------
    validation : dict
        ``{"train": metrics, "test": metrics}`` of :func:`thermocal.retrofit.metrics.
        validation_metrics` (``mean_simulated``, ``mean_measured`` [C], ``mae`` [K]).
    heat : dict or None
        :func:`heat_validation` of the test period (None: no heat check).
    criteria : dict
        Limits as :data:`DEFAULT_CRITERIA`.
    unit_keys : str, optional
        The configuration keys that set the metered heat's scale
        (:func:`thermocal.retrofit.calibration.heat_unit_keys`): named first when the heat
        check fails with the metered and the model's heat a unit slip's factor apart (3.6: kWh
        read as MJ; 4: 15-minute energies read as power; 1000).
    heat_source : str
        ``measurements.heat_source`` (the slips a hydronic circuit's flow units allow differ).

    Returns
    -------
    dict with ``passed`` (bool), ``period`` ("test" or None), ``checks`` (name, value, limit,
    unit, passed per criterion) and ``summary`` (one plain sentence for the report).
    """
    test = validation.get("test")
    if test is None:
        return {
            "passed": False,
            "period": None,
            "checks": [],
            "criteria": dict(criteria),
            "summary": (
                "The model was not checked on a test period (periods.test_days is 0 or the "
                "measurements end with the training period), so it is unvalidated: no strategy "
                "is recommended. Measure a few more weeks and rerun."
            ),
        }
    bias = float(test["mean_simulated"] - test["mean_measured"])
    checks = [
        _check("indoor temperature bias", bias, criteria["max_abs_bias_K"], "K", absolute=True),
        _check("indoor temperature MAE", float(test["mae"]), criteria["max_mae_K"], "K"),
    ]
    if heat is not None and np.isfinite(heat.get("nmbe_pct", np.nan)):
        checks += [
            _check("heat NMBE (daily, ASHRAE 14)", heat["nmbe_pct"],
                   criteria["max_abs_nmbe_pct"], "%", absolute=True),
            _check("heat CV(RMSE) (daily, ASHRAE 14)", heat["cv_rmse_pct"],
                   criteria["max_cv_rmse_pct"], "%"),
        ]  # fmt: skip
    failed = [c for c in checks if not c["passed"]]
    if failed:
        what = "; ".join(
            f"{c['name']} {c['value']:+.2f} {c['unit']} (limit {c['limit']:g} {c['unit']})"
            if c["absolute"]
            else f"{c['name']} {c['value']:.2f} {c['unit']} (limit {c['limit']:g} {c['unit']})"
            for c in failed
        )
        slip = _heat_unit_slip(heat, failed, unit_keys, heat_source)
        summary = (
            "The calibrated model FAILED its validation on the test period: "
            f"{what}. It does not reproduce this house well enough, so its demand and savings "
            "are not reliable and no strategy is recommended. "
            + (
                slip
                or "Check the building description (areas, U-values, unheated spaces), the heat "
                "and indoor-temperature measurements and the internal gains, then rerun."
            )
        )
    else:
        summary = (
            "The calibrated model passed its validation on the test period (indoor "
            f"temperature bias {bias:+.2f} K, MAE {test['mae']:.2f} K"
            + (
                f"; daily heat NMBE {heat['nmbe_pct']:+.1f} %, CV(RMSE) {heat['cv_rmse_pct']:.1f} %"
                if len(checks) > 2
                else ""
            )
            + ")."
        )
    return {
        "passed": not failed,
        "period": "test",
        "checks": checks,
        "criteria": dict(criteria),
        "summary": summary,
    }


def _heat_unit_slip(heat, failed, unit_keys, heat_source) -> str | None:
    """The sentence naming the heat's unit keys when a failed heat check's metered and model
    heat are a unit slip's factor apart (:func:`thermocal.retrofit.verify.unit_slip_near`)."""
    if heat is None or unit_keys is None or not any(c["name"].startswith("heat") for c in failed):
        return None
    from thermocal.retrofit.verify import unit_slip_near

    model, measured = heat.get("model_kWh", np.nan), heat.get("measured_kWh", np.nan)
    if not (np.isfinite(model) and np.isfinite(measured) and model > 0 and measured > 0):
        return None
    ratio = measured / model
    near = unit_slip_near(ratio, heat_source)
    if near is not None:
        return (
            f"The metered heat of the test period is {ratio:.3g} times the model's, near the "
            f"factor {near[0]:g} of {near[1]}: check {unit_keys} first, then rerun."
        )
    if max(ratio, 1.0 / ratio) < HEAT_SCALE_SUSPECT:
        return None
    # the calibration absorbs part of a slip (a temperature fit drives the model with the
    # metered heat): 3.6 or 4 in the meter's unit came out as 4.6 and 5.2 on the demo
    return (
        f"The metered heat of the test period is {ratio:.3g} times the model's: a unit slip of "
        "the heat is the likely cause (the calibration absorbs part of it, so the ratio is not "
        f"the slip's own factor): check {unit_keys} first, then the building description and "
        "the internal gains, and rerun."
    )


#: A failed heat check whose metered and model heat differ by this factor or more (either
#: way) names the heat's unit keys first [-]: a house's heat is not off by 2.5 times from a
#: description and a calibration on the same data for another reason as often.
HEAT_SCALE_SUSPECT = 2.5


def _check(name: str, value: float, limit: float, unit: str, *, absolute: bool = False) -> dict:
    measure = abs(value) if absolute else value
    return {
        "name": name,
        "value": float(value),
        "limit": float(limit),
        "unit": unit,
        "absolute": absolute,
        "passed": bool(np.isfinite(measure) and measure <= limit),
    }
