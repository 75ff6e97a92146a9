"""Kalman filter, Rauch-Tung-Striebel smoother and simulation of :class:`RCModel` objects.

The exact discretisation and the filter recursions run in the compiled kernels
(:mod:`thermocal.statespace.kernels`); this module prepares their arguments, splits the data
into periods with their own initial states, and returns the filtered, smoothed or simulated
trajectories. The optimiser (:mod:`thermocal.statespace.estimation`), the results
(:mod:`thermocal.statespace.results`) and the profiles build on it.

References
----------
.. [1] N. R. Kristensen, H. Madsen, S. B. Jorgensen, "Parameter estimation in stochastic grey-box
   models", Automatica 40(2), 225-237, 2004.
.. [2] H. E. Rauch, F. Tung, C. T. Striebel, "Maximum likelihood estimates of linear dynamic
   systems", AIAA Journal 3(8), 1445-1450, 1965.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.statespace import kernels
from thermocal.statespace.data import PreparedData, prepare_data, time_axis_jumps


def _hold_flag(hold: str) -> bool:
    if hold not in ("zoh", "foh"):
        raise ThermocalInputError(f"hold must be 'zoh' or 'foh', got '{hold}'")
    return hold == "foh"


def _periods(model, prep: PreparedData, values=None) -> tuple[np.ndarray, np.ndarray]:
    """(first sample of each later period, their initial means [C]) for the kernels.

    ``values``: SI value vector (default: the declared values). The model must declare an
    initial state per period (:meth:`RCModel.with_periods`, done by :func:`fit`).
    """
    st = model.structure()
    if values is None:
        values = model.values_si()
    seg_x0 = kernels.period_initial_means(values, st.arrays[19], st.n_states)
    segments = prep.segments
    if seg_x0.shape[0] < segments.size:
        raise ThermocalInputError(
            f"model '{model.name}': the data is split into {segments.size + 1} periods (long "
            f"input gaps) but the model has initial states for {seg_x0.shape[0] + 1}; use the "
            "fitted model of that data (res.model) or model.with_periods(...)"
        )
    return segments, seg_x0[: segments.size]


def _loglike_values(model, values, prep: PreparedData, foh: bool) -> float:
    st = model.structure()
    lam, T, Tinv, TB, M, meas_var, x0, P0 = kernels.system_from_values(
        values, *st.arrays[:19], st.n_inputs
    )
    seg_start, seg_x0 = _periods(model, prep, values)
    e2, e3 = np.empty((0, 0)), np.empty((0, 0, 0))
    return float(
        kernels.kalman_filter(
            lam, T, Tinv, TB, M, st.C, meas_var, x0, P0, prep.dts, prep.U, prep.Y, foh,
            False, e2, e3, e2, e3, e3, seg_start, seg_x0, prep.Y.shape[0] + 1,
            kernels.handoff_buffers(st.n_states, st.C.shape[0], st.n_inputs),
        )
    )  # fmt: skip


def nonfinite_culprit(model, prep: PreparedData, foh: bool) -> str:
    """Where a non-finite likelihood comes from, at the declared values: a parameter giving a
    degenerate system, or the first row where the filtered state leaves the finite numbers
    (with the inputs of that row, largest first)."""
    try:
        lam = model.system()[0]
    except (ValueError, ZeroDivisionError, np.linalg.LinAlgError):
        lam = np.array([np.nan])
    if not np.all(np.isfinite(lam)):
        return (
            "the system matrices are not finite at the declared parameter values "
            f"({', '.join(f'{n}={p.value:g} {p.unit}' for n, p in model.parameters.items())}); "
            "check capacities and conductances for zeros or absurd values"
        )
    f = filter_arrays(model, prep, None, foh)
    bad = ~(np.all(np.isfinite(f["xf"]), axis=1) & np.all(np.isfinite(f["Pp"]), axis=(1, 2)))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        # the input of row k-1 acts over the step into row k (zero-order hold)
        values = sorted(
            (
                (abs(prep.U[r, j]), c, prep.U[r, j], r)
                for r in range(max(k - 1, 0), k + 1)
                for j, c in enumerate(model.input_names)
            ),
            key=lambda item: item[0],
            reverse=True,
        )
        shown = ", ".join(f"'{c}' = {v:.4g} (row {r})" for _, c, v, r in values[:3])
        return (
            f"the filtered state becomes non-finite at row {k} ({prep.index[k]}); largest "
            f"inputs of rows {max(k - 1, 0)}-{k}: {shown}; check those columns for absurd "
            "values or units, and the declared parameter values"
        )
    return (
        "the filter stays finite at the declared values, but every optimiser start ran into "
        "non-finite values; narrow the parameter bounds or check the initial values"
    )


def simulate(
    model,
    data,
    params=None,
    *,
    hold="zoh",
    time_column=None,
    time_unit="s",
    initial_state=None,
    interval_means=False,
):
    """Deterministic state and output trajectories from the initial-state mean.

    ``initial_state`` ({state: temperature [C]}) replaces the initial means of the states it
    names (a validation period starting later than the fit period starts elsewhere).
    ``interval_means``: report each state's and output's mean over the interval a time label
    starts (:func:`interval_means_of`), as an averaging logger records it, instead of its value
    at the label.

    Returns a DataFrame (index = the data's time labels) with one column per state [C] and one per
    output (named after its data column) [C].
    """
    prep = (
        data
        if isinstance(data, PreparedData)
        else prepare_data(
            model, data, time_column=time_column, time_unit=time_unit, require_outputs=False
        )
    )
    lam, T, Tinv, TB, M, _, x0, _ = model.system(params)
    values = model.values_si(params)
    seg_start, seg_x0 = _periods(model, prep, values)
    for state, value in (initial_state or {}).items():
        if state not in model.state_names:
            raise ThermocalInputError(
                f"initial_state: '{state}' is not a state of model '{model.name}' "
                f"(states: {', '.join(model.state_names)})"
            )
        x0[model.state_names.index(state)] = float(value)
    X = kernels.simulate_states(
        lam, T, Tinv, TB, M, x0, prep.dts, prep.U, _hold_flag(hold), seg_start, seg_x0
    )
    if interval_means:
        X = interval_means_of(model, prep, X, params, hold)
    out = pd.DataFrame(X, index=prep.index, columns=model.state_names)
    Yhat = X @ model.structure().C.T
    for r, col in enumerate(model.output_names):
        out[col] = Yhat[:, r]
    return out


#: Share of the intervals equal to the median one (within 0.1 %) that makes a time axis a
#: logger's regular one, whose longer steps are rows missing [-].
REGULAR_SHARE = 0.9


def interval_means_of(model, prep: PreparedData, X: np.ndarray, params, hold: str) -> np.ndarray:
    """Each state's mean over the interval that starts at each sample [C].

    ``X`` (samples, states) holds the states at the samples [C], as :func:`simulate` computes
    them; the mean over ``[t_k, t_k+1]`` follows exactly from ``X[k]`` and the inputs
    (:func:`thermocal.statespace.discretise.interval_mean_matrices`, one set per distinct
    interval length). The last sample's interval lies beyond the data: it takes the previous
    interval's length with the last inputs held; so does the last sample before a gap, whether
    the gap splits the data into periods or the time axis jumps over it (its interval is the
    regular step: a logger's mean covers one interval, not the gap; a time axis is a logger's
    regular one when :data:`REGULAR_SHARE` of its intervals equal the median).
    """
    from thermocal.statespace.discretise import interval_mean_matrices

    _hold_flag(hold)
    A, B, _, _ = model.continuous_matrices(params)
    N = X.shape[0]
    if N < 2:
        return X.copy()
    dts = prep.dts[:N]  # dts[k]: sample k to k + 1 (the last repeats the one before)
    U_next = np.vstack([prep.U[1:], prep.U[-1:]])
    # before a long gap that splits the data into periods the next row lies after the gap: the
    # interval holds its inputs, as at the end of the data (its dts is the regular step)
    ends = prep.segments[(prep.segments > 0) & (prep.segments <= N - 1)] - 1
    U_next[ends] = prep.U[ends]
    # before a jump of a regular time axis (a logger's rows missing, bridged) the same: its
    # mean is over one regular step, not the whole jump (irregular samples are left as they
    # are: each row's interval runs to the next)
    seconds = np.asarray(prep.seconds[:N], dtype=float)
    step = float(np.median(np.diff(seconds)))
    regular = np.mean(np.abs(np.diff(seconds) - step) <= 1e-3 * step) >= REGULAR_SHARE
    jumps = time_axis_jumps(seconds)[0] - 1 if regular else np.zeros(0, dtype=np.int64)
    if jumps.size:
        dts = dts.copy()
        dts[jumps] = step
        U_next[jumps] = prep.U[jumps]
    means = np.empty_like(X)
    for dt in np.unique(dts):
        rows = dts == dt
        S, H0, H1 = interval_mean_matrices(A, B, float(dt), hold)
        means[rows] = X[rows] @ S.T + prep.U[rows] @ H0.T + U_next[rows] @ H1.T
    return means


def filter_arrays(model, prep: PreparedData, params: Mapping[str, float] | None, foh: bool):
    """Run the Kalman filter storing predicted and filtered moments.

    Returns a dict with ``xp, Pp`` (predicted before the update at each sample), ``xf, Pf``
    (filtered), ``Ads`` (transition k -> k+1), ``loglike`` and the system.
    """
    st = model.structure()
    lam, T, Tinv, TB, M, meas_var, x0, P0 = model.system(params)
    seg_start, seg_x0 = _periods(model, prep, model.values_si(params))
    N, n = prep.Y.shape[0], st.n_states
    xp, xf = np.empty((N, n)), np.empty((N, n))
    Pp, Pf, Ads = np.empty((N, n, n)), np.empty((N, n, n)), np.zeros((N, n, n))
    ll = kernels.kalman_filter(
        lam, T, Tinv, TB, M, st.C, meas_var, x0, P0, prep.dts, prep.U, prep.Y, foh,
        True, xp, Pp, xf, Pf, Ads, seg_start, seg_x0, N + 1,
        kernels.handoff_buffers(n, st.C.shape[0], st.n_inputs),
    )  # fmt: skip
    return {
        "xp": xp, "Pp": Pp, "xf": xf, "Pf": Pf, "Ads": Ads, "loglike": float(ll),
        "system": (lam, T, Tinv, TB, M), "meas_var": meas_var, "C": st.C,
    }  # fmt: skip


def rts_smoother(filtered: dict) -> tuple[np.ndarray, np.ndarray]:
    """Rauch-Tung-Striebel smoothed state means [C] and covariances [K2].

    References
    ----------
    .. [1] H. E. Rauch, F. Tung, C. T. Striebel, "Maximum likelihood estimates of linear dynamic
       systems", AIAA Journal 3(8), 1445-1450, 1965.
    """
    xp, Pp, xf, Pf, Ads = (filtered[k] for k in ("xp", "Pp", "xf", "Pf", "Ads"))
    N = xf.shape[0]
    xs, Ps = xf.copy(), Pf.copy()
    for k in range(N - 2, -1, -1):
        J = np.linalg.solve(Pp[k + 1].T, (Pf[k] @ Ads[k].T).T).T  # Pf A^T Pp^-1
        xs[k] = xf[k] + J @ (xs[k + 1] - xp[k + 1])
        Ps[k] = Pf[k] + J @ (Ps[k + 1] - Pp[k + 1]) @ J.T
        Ps[k] = 0.5 * (Ps[k] + Ps[k].T)
    return xs, Ps


def simulate_stochastic(
    model,
    data,
    params: Mapping[str, float] | None = None,
    *,
    seed: int | None = None,
    hold: str = "zoh",
    time_column: str | None = None,
    time_unit: str = "s",
) -> pd.DataFrame:
    """One random realisation of the stochastic model (states with process noise, outputs with
    measurement noise), exactly discretised; for synthetic data and parameter-recovery studies.

    The initial state is drawn from its declared mean and standard deviation. Returns a DataFrame
    with the state columns [C] and the output columns [C] on the data's index.
    """
    foh = _hold_flag(hold)
    prep = (
        data
        if isinstance(data, PreparedData)
        else prepare_data(
            model, data, time_column=time_column, time_unit=time_unit, require_outputs=False
        )
    )
    rng = np.random.default_rng(seed)
    lam, T, Tinv, TB, M, meas_var, x0, P0 = model.system(params)
    C = model.structure().C
    n, m = T.shape[0], TB.shape[1]
    Ad, G0, G1, Q = np.empty((n, n)), np.empty((n, m)), np.empty((n, m)), np.empty((n, n))
    N = prep.U.shape[0]
    X = np.empty((N, n))
    x = rng.multivariate_normal(x0, P0)
    last_dt = -1.0
    for k in range(N):
        X[k] = x
        if k == N - 1:
            break
        if prep.dts[k] != last_dt:
            kernels.discretise_from_eigen(lam, T, Tinv, TB, M, prep.dts[k], foh, Ad, G0, G1, Q)
            last_dt = prep.dts[k]
            w, v = np.linalg.eigh(Q)
            Lq = v * np.sqrt(np.clip(w, 0.0, None))
        x = Ad @ x + G0 @ prep.U[k] + (G1 @ prep.U[k + 1] if foh else 0.0)
        x = x + Lq @ rng.standard_normal(n)
    Y = X @ C.T + rng.standard_normal((N, C.shape[0])) * np.sqrt(meas_var)[None, :]
    out = pd.DataFrame(X, index=prep.index, columns=model.state_names)
    for r, col in enumerate(model.output_names):
        out[col] = Y[:, r]
    return out
