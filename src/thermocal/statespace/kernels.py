"""Compiled numerical kernels: RC system assembly, exact discretisation, Kalman filter.

The kernels work on a *compiled model structure* (integer index arrays produced by
:meth:`thermocal.statespace.RCModel.structure`) and a vector ``values`` of all parameter values
in SI units followed by the model's literal constants. All loops are small and fixed-size so
that numba compiles them to allocation-free machine code.

Discretisation
--------------
An RC network has ``A = D^-1 G`` with ``D = diag(capacities)`` and ``G`` the symmetric
(negative semi-definite) conductance matrix, so ``A`` is similar to the symmetric matrix
``S = D^-1/2 G D^-1/2 = V diag(lam) V^T``. With ``T = D^-1/2 V`` the matrix exponential and the
hold integrals have closed forms::

    exp(A dt)                       = T diag(exp(lam dt)) T^-1
    int_0^dt exp(A r) dr B          = T diag(dt phi1(lam dt)) T^-1 B          (zero-order hold)
    int_0^dt exp(A r) r/dt dr B     = T diag(dt phi2(lam dt)) T^-1 B          (first-order hold)
    int_0^dt exp(A r) S S^T exp(A^T r) dr = T [M_ij dt phi1((lam_i + lam_j) dt)] T^T  (Van Loan)

with ``phi1(z) = (e^z - 1)/z``, ``phi2(z) = (e^z (z - 1) + 1)/z^2`` and
``M = T^-1 Sigma Sigma^T T^-T``. These are the exact discretisations of Van Loan (1978); the
tests check them against ``scipy.linalg.expm`` of the augmented matrices.

References
----------
.. [1] C. F. Van Loan, "Computing integrals involving the matrix exponential", IEEE Trans.
   Automatic Control 23(3), 395-404, 1978.
.. [2] H. Madsen, "Time Series Analysis", Chapman & Hall, 2008, ch. 10 (Kalman filter,
   prediction-error decomposition of the likelihood).
.. [3] N. R. Kristensen, H. Madsen, S. B. Jorgensen, "Parameter estimation in stochastic grey-box
   models", Automatica 40(2), 225-237, 2004.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

LOG_2PI = math.log(2.0 * math.pi)

# transform kinds (free parameters)
TRANSFORM_IDENTITY = 1
TRANSFORM_LOG = 2  # x = lower + exp(theta)
TRANSFORM_NEGLOG = 3  # x = upper - exp(theta)
TRANSFORM_LOGIT = 4  # x = lower + (upper - lower) / (1 + exp(-theta))


@njit(cache=True, error_model="numpy")
def phi1(z):
    """(exp(z) - 1) / z, continuous at 0."""
    if abs(z) < 1e-5:
        return 1.0 + z * (0.5 + z / 6.0)
    return math.expm1(z) / z


@njit(cache=True, error_model="numpy")
def phi2(z):
    """Integral of exp(z s) s over s in [0, 1] = (exp(z)(z - 1) + 1) / z^2, continuous at 0."""
    if abs(z) < 1e-2:
        total = 0.0
        term = 1.0  # z^k / k!
        for k in range(10):
            total += term / (k + 2.0)
            term *= z / (k + 1.0)
        return total
    return (math.exp(z) * (z - 1.0) + 1.0) / (z * z)


@njit(cache=True, error_model="numpy")
def to_natural(theta_i, kind, lower, upper):
    """Map one unconstrained value to the parameter's declared-unit value."""
    if kind == TRANSFORM_LOG:
        return lower + math.exp(theta_i)
    if kind == TRANSFORM_NEGLOG:
        return upper - math.exp(theta_i)
    if kind == TRANSFORM_LOGIT:
        if theta_i >= 0.0:
            e = math.exp(-theta_i)
            return lower + (upper - lower) / (1.0 + e)
        e = math.exp(theta_i)
        return lower + (upper - lower) * e / (1.0 + e)
    return theta_i


@njit(cache=True, error_model="numpy")
def fill_values(theta, free_idx, kind, lower, upper, si_factor, base_values):
    """SI value vector with the free parameters set from ``theta``."""
    values = base_values.copy()
    for i in range(theta.size):
        p = free_idx[i]
        values[p] = to_natural(theta[i], kind[i], lower[i], upper[i]) * si_factor[p]
    return values


@njit(cache=True, error_model="numpy")
def build_network(
    values,
    cap_idx,
    edge_a,
    edge_b,
    link_ptr,
    link_idx,
    link_is_resistance,
    heat_state,
    heat_input,
    heat_factor,
    heat_scale_idx,
    frac_const,
    frac_ptr,
    frac_idx,
    frac_sign,
    noise_idx,
    link_factor,
    n_inputs,
):
    """Assemble capacities, conductance matrix G, raw input matrix and diffusion stds.

    Returns ``cap`` [J/K], ``G`` [W/K] (symmetric), ``B_raw`` [W/K or W per column unit] with
    ``A = G / cap[:, None]``, ``B = B_raw / cap[:, None]``, and ``sigma`` [K/sqrt(s)].
    """
    n = cap_idx.size
    cap = np.empty(n)
    for i in range(n):
        cap[i] = values[cap_idx[i]]
    G = np.zeros((n, n))
    B_raw = np.zeros((n, n_inputs))
    for e in range(edge_a.size):
        resistance = 0.0
        for q in range(link_ptr[e], link_ptr[e + 1]):
            val = values[link_idx[q]] * link_factor[q]
            if link_is_resistance[q]:
                resistance += val
            else:
                resistance += 1.0 / val
        g = 1.0 / resistance
        a = edge_a[e]
        b = edge_b[e]
        G[a, a] -= g
        if b >= 0:
            G[b, b] -= g
            G[a, b] += g
            G[b, a] += g
        else:
            B_raw[a, -b - 1] += g
    for h in range(heat_state.size):
        c = heat_factor[h]
        if heat_scale_idx[h] >= 0:
            c *= values[heat_scale_idx[h]]
        f = frac_const[h]
        for q in range(frac_ptr[h], frac_ptr[h + 1]):
            f += frac_sign[q] * values[frac_idx[q]]
        B_raw[heat_state[h], heat_input[h]] += c * f
    sigma = np.zeros(n)
    for i in range(n):
        if noise_idx[i] >= 0:
            sigma[i] = values[noise_idx[i]]
    return cap, G, B_raw, sigma


@njit(cache=True, error_model="numpy")
def eigen_network(cap, G, B_raw, sigma):
    """Eigen-decomposition of the RC system used by :func:`discretise_from_eigen`.

    Returns ``lam`` [1/s], ``T`` (= D^-1/2 V), ``Tinv`` (= V^T D^1/2), ``TB`` (= T^-1 B) and
    ``M`` (= T^-1 Sigma Sigma^T T^-T).
    """
    n = cap.size
    dh = np.empty(n)
    sq = np.empty(n)
    for i in range(n):
        sq[i] = math.sqrt(cap[i])
        dh[i] = 1.0 / sq[i]
    S = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            S[i, j] = dh[i] * G[i, j] * dh[j]
    finite = True
    for i in range(n):
        if not (cap[i] > 0.0) or not math.isfinite(cap[i]) or not math.isfinite(sigma[i]):
            finite = False
        for j in range(n):
            if not math.isfinite(S[i, j]):
                finite = False
    if not finite:
        # invalid parameters (e.g. overflow of a transform): a NaN system makes the likelihood -inf
        nan_n = np.full(n, np.nan)
        nan_nn = np.full((n, n), np.nan)
        return nan_n, nan_nn, nan_nn.copy(), np.full((n, B_raw.shape[1]), np.nan), nan_nn.copy()
    lam, V = np.linalg.eigh(S)
    T = np.empty((n, n))
    Tinv = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            T[i, j] = dh[i] * V[i, j]
            Tinv[i, j] = V[j, i] * sq[j]
    m = B_raw.shape[1]
    TB = np.zeros((n, m))
    for i in range(n):
        for k in range(m):
            acc = 0.0
            for j in range(n):
                acc += Tinv[i, j] * B_raw[j, k] / cap[j]
            TB[i, k] = acc
    M = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            acc = 0.0
            for k in range(n):
                acc += Tinv[i, k] * sigma[k] * sigma[k] * Tinv[j, k]
            M[i, j] = acc
    return lam, T, Tinv, TB, M


@njit(cache=True, error_model="numpy")
def discretise_from_eigen(lam, T, Tinv, TB, M, dt, foh, Ad, Gam0, Gam1, Q):
    """Exact discretisation over ``dt`` [s], written into ``Ad, Gam0, Gam1, Q``.

    ``x[k+1] = Ad x[k] + Gam0 u[k] + Gam1 u[k+1] + w`` with ``w ~ N(0, Q)``. Zero-order hold
    (``foh=False``) gives ``Gam1 = 0``; first-order hold interpolates the inputs linearly.
    """
    n = lam.size
    m = TB.shape[1]
    e = np.empty(n)
    g = np.empty(n)
    g1 = np.empty(n)
    for i in range(n):
        z = lam[i] * dt
        e[i] = math.exp(z)
        g[i] = dt * phi1(z)
        g1[i] = dt * phi2(z)
    for i in range(n):
        for j in range(n):
            acc = 0.0
            for k in range(n):
                acc += T[i, k] * e[k] * Tinv[k, j]
            Ad[i, j] = acc
    for i in range(n):
        for c in range(m):
            acc_zoh = 0.0
            acc_k = 0.0
            for k in range(n):
                acc_zoh += T[i, k] * g[k] * TB[k, c]
                acc_k += T[i, k] * g1[k] * TB[k, c]
            if foh:
                Gam0[i, c] = acc_k
                Gam1[i, c] = acc_zoh - acc_k
            else:
                Gam0[i, c] = acc_zoh
                Gam1[i, c] = 0.0
    W = np.empty((n, n))
    for a in range(n):
        for b in range(n):
            W[a, b] = M[a, b] * dt * phi1((lam[a] + lam[b]) * dt)
    for i in range(n):
        for j in range(i, n):
            acc = 0.0
            for a in range(n):
                for b in range(n):
                    acc += T[i, a] * W[a, b] * T[j, b]
            Q[i, j] = acc
            Q[j, i] = acc


@njit(cache=True, error_model="numpy")
def modal_discretise(lam, TB, M, dt, foh, e, G0, G1, W):
    """Exact discretisation over ``dt`` [s] in modal coordinates ``z = T^-1 x``.

    The transition matrix is ``diag(e)``; ``G0``, ``G1`` multiply ``u[k]`` and ``u[k+1]``;
    ``W`` is the process-noise covariance (see :func:`discretise_from_eigen`).
    """
    n = lam.size
    m = TB.shape[1]
    for i in range(n):
        z = lam[i] * dt
        e[i] = math.exp(z)
        g = dt * phi1(z)
        g1 = dt * phi2(z)
        for c in range(m):
            if foh:
                G0[i, c] = g1 * TB[i, c]
                G1[i, c] = (g - g1) * TB[i, c]
            else:
                G0[i, c] = g * TB[i, c]
                G1[i, c] = 0.0
    for a in range(n):
        for b in range(a, n):
            w = M[a, b] * dt * phi1((lam[a] + lam[b]) * dt)
            W[a, b] = w
            W[b, a] = w


@njit(cache=True, error_model="numpy")
def _to_physical(T, z, Pz, x, P):
    """``x = T z`` and ``P = T Pz T^T``."""
    n = z.size
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += T[i, j] * z[j]
        x[i] = acc
    for i in range(n):
        for j in range(n):
            acc = 0.0
            for a in range(n):
                ta = T[i, a]
                for b in range(n):
                    acc += ta * Pz[a, b] * T[j, b]
            P[i, j] = acc


#: Relative change of the predicted covariance below which the filter is taken as stationary.
STEADY_STATE_TOLERANCE = 1e-13


@njit(cache=True, error_model="numpy")
def kalman_filter(
    lam, T, Tinv, TB, M, C, meas_var, x0, P0, dts, U, Y, foh, store, xp, Pp, xf, Pf, Ads,
    seg_start, seg_x0,
):
    """Kalman filter over the samples; returns the log-likelihood of ``Y``.

    The filter runs in the modal coordinates ``z = T^-1 x`` of the RC network, where the
    transition matrix is diagonal, so the time update costs O(n^2). Observations are processed
    one scalar at a time (exact because the measurement noise is diagonal); NaN entries are
    skipped, so partially observed vectors are handled. The covariance update is in Joseph form.
    ``dts[k]`` [s] is the interval from sample k to k+1; the discretisation is recomputed only
    when it changes (uniform sampling: once).

    Steady state: once the predicted covariance stops changing (relative change below
    :data:`STEADY_STATE_TOLERANCE` over a step with the same interval and all outputs observed),
    the gains and innovation variances are frozen and only the means are propagated, until an
    interval changes or an observation is missing. The effect on the log-likelihood is at the
    level of the tolerance. Not used when ``store`` is set.

    With ``store`` the predicted (``xp``, ``Pp``) and filtered (``xf``, ``Pf``) moments and the
    transition matrices ``Ads[k]`` (k -> k+1), in physical coordinates, are written into the
    given arrays.

    Separate periods (the likelihood split at long gaps): at sample ``seg_start[s]`` the state
    restarts from its own initial mean ``seg_x0[s]`` [C] with covariance ``P0`` (nothing is
    carried over the gap; ``Ads`` of the step into it is zero, so the RTS smoother treats the
    periods independently). Empty arrays: one period.
    """
    n = lam.size
    m = TB.shape[1]
    ny = C.shape[0]
    N = Y.shape[0]
    for i in range(n):
        if not math.isfinite(lam[i]):
            return -np.inf
    # modal coordinates
    Cz = np.zeros((ny, n))
    for r in range(ny):
        for j in range(n):
            acc = 0.0
            for i in range(n):
                acc += C[r, i] * T[i, j]
            Cz[r, j] = acc
    z = np.zeros(n)
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += Tinv[i, j] * x0[j]
        z[i] = acc
    P = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            acc = 0.0
            for a in range(n):
                for b in range(n):
                    acc += Tinv[i, a] * P0[a, b] * Tinv[j, b]
            P[i, j] = acc
    e = np.empty(n)
    G0 = np.empty((n, m))
    G1 = np.empty((n, m))
    W = np.empty((n, n))
    PC = np.empty(n)
    K = np.empty(n)
    LP = np.empty((n, n))
    Pprior = np.empty((n, n))
    Ppost = np.empty((n, n))
    Kfix = np.empty((ny, n))
    sfix = np.empty(ny)
    log_sfix = np.empty(ny)
    xs = np.empty(n)
    Ps = np.empty((n, n))
    steady = False
    last_dt = -1.0
    loglike = 0.0
    next_seg = 0
    for k in range(N):
        if next_seg < seg_start.size and k == seg_start[next_seg]:
            for i in range(n):
                acc = 0.0
                for j in range(n):
                    acc += Tinv[i, j] * seg_x0[next_seg, j]
                z[i] = acc
            for i in range(n):
                for j in range(n):
                    acc = 0.0
                    for a in range(n):
                        for b in range(n):
                            acc += Tinv[i, a] * P0[a, b] * Tinv[j, b]
                    P[i, j] = acc
            if store and k > 0:
                for i in range(n):
                    for j in range(n):
                        Ads[k - 1, i, j] = 0.0
            steady = False
            next_seg += 1
        complete = True
        for r in range(ny):
            if math.isnan(Y[k, r]):
                complete = False
        if steady and not complete:
            steady = False
        if store:
            _to_physical(T, z, P, xs, Ps)
            for i in range(n):
                xp[k, i] = xs[i]
                for j in range(n):
                    Pp[k, i, j] = Ps[i, j]
        if steady:
            for r in range(ny):
                v = Y[k, r]
                for i in range(n):
                    v -= Cz[r, i] * z[i]
                for i in range(n):
                    z[i] += Kfix[r, i] * v
                loglike -= 0.5 * (LOG_2PI + log_sfix[r] + v * v / sfix[r])
        else:
            for i in range(n):
                for j in range(n):
                    Pprior[i, j] = P[i, j]
            # measurement update, one scalar observation at a time
            for r in range(ny):
                y = Y[k, r]
                if math.isnan(y):
                    continue
                v = y
                for i in range(n):
                    v -= Cz[r, i] * z[i]
                s = meas_var[r]
                for i in range(n):
                    acc = 0.0
                    for j in range(n):
                        acc += P[i, j] * Cz[r, j]
                    PC[i] = acc
                    s += Cz[r, i] * acc
                if not (s > 0.0) or not math.isfinite(s):
                    return -np.inf
                for i in range(n):
                    K[i] = PC[i] / s
                    Kfix[r, i] = K[i]
                    z[i] += K[i] * v
                sfix[r] = s
                log_sfix[r] = math.log(s)
                # Joseph form: P = L P L^T + r K K^T with L = I - K c
                for i in range(n):
                    for j in range(n):
                        LP[i, j] = P[i, j] - K[i] * PC[j]  # (L P)_ij, since c P = PC^T
                for i in range(n):
                    for j in range(i, n):
                        acc = meas_var[r] * K[i] * K[j]
                        for q in range(n):
                            acc += LP[i, q] * ((1.0 if q == j else 0.0) - K[j] * Cz[r, q])
                        P[i, j] = acc
                        P[j, i] = acc
                loglike -= 0.5 * (LOG_2PI + log_sfix[r] + v * v / s)
            for i in range(n):
                for j in range(n):
                    Ppost[i, j] = P[i, j]
        if store:
            _to_physical(T, z, P, xs, Ps)
            for i in range(n):
                xf[k, i] = xs[i]
                for j in range(n):
                    Pf[k, i, j] = Ps[i, j]
        if k == N - 1:
            break
        # time update to sample k+1
        dt = dts[k]
        if dt != last_dt:
            modal_discretise(lam, TB, M, dt, foh, e, G0, G1, W)
            last_dt = dt
            if steady:
                # the steady stretch left P at the stationary *predicted* covariance; the time
                # update starts from the filtered one (stationary as well)
                for i in range(n):
                    for j in range(n):
                        P[i, j] = Ppost[i, j]
            steady = False
        if store:
            for i in range(n):
                for j in range(n):
                    acc = 0.0
                    for a in range(n):
                        acc += T[i, a] * e[a] * Tinv[a, j]
                    Ads[k, i, j] = acc
        for i in range(n):
            acc = e[i] * z[i]
            for c in range(m):
                acc += G0[i, c] * U[k, c]
            if foh:
                for c in range(m):
                    acc += G1[i, c] * U[k + 1, c]
            z[i] = acc
        if steady:
            continue
        change = 0.0
        scale = 0.0
        for i in range(n):
            for j in range(i, n):
                val = e[i] * e[j] * P[i, j] + W[i, j]
                P[i, j] = val
                P[j, i] = val
                change = max(change, abs(val - Pprior[i, j]))
                scale = max(scale, abs(val))
        if complete and not store and change <= STEADY_STATE_TOLERANCE * scale and k + 1 < N:
            if dts[k + 1] == dt:
                steady = True
    return loglike


@njit(cache=True, error_model="numpy")
def simulate_states(lam, T, Tinv, TB, M, x0, dts, U, foh, seg_start, seg_x0):
    """Deterministic (noise-free) state trajectory [C] from ``x0`` through all samples; at
    ``seg_start[s]`` it restarts from ``seg_x0[s]`` (see :func:`kalman_filter`)."""
    n = lam.size
    m = TB.shape[1]
    N = U.shape[0]
    X = np.empty((N, n))
    Ad = np.empty((n, n))
    Gam0 = np.empty((n, m))
    Gam1 = np.empty((n, m))
    Q = np.empty((n, n))
    x = x0.copy()
    last_dt = -1.0
    next_seg = 0
    for k in range(N):
        if next_seg < seg_start.size and k == seg_start[next_seg]:
            for i in range(n):
                x[i] = seg_x0[next_seg, i]
            next_seg += 1
        for i in range(n):
            X[k, i] = x[i]
        if k == N - 1:
            break
        dt = dts[k]
        if dt != last_dt:
            discretise_from_eigen(lam, T, Tinv, TB, M, dt, foh, Ad, Gam0, Gam1, Q)
            last_dt = dt
        xn = np.zeros(n)
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += Ad[i, j] * x[j]
            for c in range(m):
                acc += Gam0[i, c] * U[k, c]
                if foh:
                    acc += Gam1[i, c] * U[k + 1, c]
            xn[i] = acc
        x = xn
    return X


@njit(cache=True, error_model="numpy")
def _propagate(Ad, Gam0, Gam1, Q, u0, u1, foh, x, P, work_x, work_P):
    """One prediction step in place: ``x = Ad x + Gam0 u0 + Gam1 u1``, ``P = Ad P Ad^T + Q``."""
    n = x.size
    m = u0.size
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += Ad[i, j] * x[j]
        for c in range(m):
            acc += Gam0[i, c] * u0[c]
            if foh:
                acc += Gam1[i, c] * u1[c]
        work_x[i] = acc
    for i in range(n):
        x[i] = work_x[i]
        for j in range(n):
            acc = 0.0
            for a in range(n):
                acc += Ad[i, a] * P[a, j]
            work_P[i, j] = acc
    for i in range(n):
        for j in range(n):
            acc = Q[i, j]
            for a in range(n):
                acc += work_P[i, a] * Ad[j, a]
            P[i, j] = acc


@njit(cache=True, error_model="numpy")
def predict_ahead(lam, T, Tinv, TB, M, xf, Pf, dts, U, foh, steps):
    """k-step predictions: mean and covariance of x[t] given observations up to t - steps.

    Rows ``t < steps`` are NaN.
    """
    n = lam.size
    m = TB.shape[1]
    N = U.shape[0]
    Xk = np.full((N, n), np.nan)
    Pk = np.full((N, n, n), np.nan)
    Ad = np.empty((n, n))
    Gam0 = np.empty((n, m))
    Gam1 = np.empty((n, m))
    Q = np.empty((n, n))
    x = np.empty(n)
    P = np.empty((n, n))
    work_x = np.empty(n)
    work_P = np.empty((n, n))
    last_dt = -1.0
    for t in range(steps, N):
        for i in range(n):
            x[i] = xf[t - steps, i]
            for j in range(n):
                P[i, j] = Pf[t - steps, i, j]
        for k in range(t - steps, t):
            dt = dts[k]
            if dt != last_dt:
                discretise_from_eigen(lam, T, Tinv, TB, M, dt, foh, Ad, Gam0, Gam1, Q)
                last_dt = dt
            _propagate(Ad, Gam0, Gam1, Q, U[k], U[k + 1], foh, x, P, work_x, work_P)
        for i in range(n):
            Xk[t, i] = x[i]
            for j in range(n):
                Pk[t, i, j] = P[i, j]
    return Xk, Pk


@njit(cache=True, error_model="numpy")
def system_from_values(
    values,
    cap_idx,
    edge_a,
    edge_b,
    link_ptr,
    link_idx,
    link_is_resistance,
    heat_state,
    heat_input,
    heat_factor,
    heat_scale_idx,
    frac_const,
    frac_ptr,
    frac_idx,
    frac_sign,
    noise_idx,
    meas_idx,
    x0_idx,
    p0_idx,
    link_factor,
    n_inputs,
):
    """Eigen-form system, measurement variances [K2], initial mean [C] and covariance [K2]."""
    cap, G, B_raw, sigma = build_network(
        values,
        cap_idx,
        edge_a,
        edge_b,
        link_ptr,
        link_idx,
        link_is_resistance,
        heat_state,
        heat_input,
        heat_factor,
        heat_scale_idx,
        frac_const,
        frac_ptr,
        frac_idx,
        frac_sign,
        noise_idx,
        link_factor,
        n_inputs,
    )
    lam, T, Tinv, TB, M = eigen_network(cap, G, B_raw, sigma)
    n = cap.size
    ny = meas_idx.size
    meas_var = np.empty(ny)
    for r in range(ny):
        meas_var[r] = values[meas_idx[r]] ** 2
    x0 = np.empty(n)
    P0 = np.zeros((n, n))
    for i in range(n):
        x0[i] = values[x0_idx[i]]
        P0[i, i] = values[p0_idx[i]] ** 2
    return lam, T, Tinv, TB, M, meas_var, x0, P0


@njit(cache=True, error_model="numpy")
def period_initial_means(values, seg_x0_idx, n):
    """Initial means [C] of the periods after the first, shape (periods - 1, n):
    ``values[seg_x0_idx]`` row by row."""
    k = seg_x0_idx.size // n if n > 0 else 0
    out = np.empty((k, n))
    for s in range(k):
        for i in range(n):
            out[s, i] = values[seg_x0_idx[s * n + i]]
    return out


@njit(cache=True, error_model="numpy")
def loglike_theta(theta, tr, st, C, dts, U, Y, foh, seg_start):
    """Log-likelihood at unconstrained parameters ``theta``.

    ``tr`` = (free_idx, kind, lower, upper, si_factor, base_values) and ``st`` = the structure
    tuple of :meth:`RCModel.structure` (see :func:`system_from_values`; ``st[19]`` indexes the
    initial means of the periods after the first, see :func:`period_initial_means`);
    ``seg_start``: first sample of each later period (empty: one period).
    """
    values = fill_values(theta, tr[0], tr[1], tr[2], tr[3], tr[4], tr[5])
    lam, T, Tinv, TB, M, meas_var, x0, P0 = system_from_values(
        values,
        st[0],
        st[1],
        st[2],
        st[3],
        st[4],
        st[5],
        st[6],
        st[7],
        st[8],
        st[9],
        st[10],
        st[11],
        st[12],
        st[13],
        st[14],
        st[15],
        st[16],
        st[17],
        st[18],
        U.shape[1],
    )
    e2 = np.empty((0, 0))
    e3 = np.empty((0, 0, 0))
    # a literal False would make numba compile a second specialisation of the filter (typed
    # Literal[bool]) besides the one called with store=True from Python: a runtime False shares it
    store = U.shape[0] < 0
    seg_x0 = period_initial_means(values, st[19], x0.size)
    ll = kalman_filter(
        lam, T, Tinv, TB, M, C, meas_var, x0, P0, dts, U, Y, foh, store, e2, e3, e2, e3, e3,
        seg_start, seg_x0,
    )
    if not math.isfinite(ll):
        return -np.inf
    return ll


@njit(cache=True, error_model="numpy")
def negloglike_and_gradient(theta, tr, st, C, dts, U, Y, foh, seg_start, rel_step):
    """Negative log-likelihood and its central-difference gradient in ``theta``."""
    f0 = -loglike_theta(theta, tr, st, C, dts, U, Y, foh, seg_start)
    p = theta.size
    grad = np.empty(p)
    th = theta.copy()
    for i in range(p):
        h = rel_step * max(1.0, abs(theta[i]))
        th[i] = theta[i] + h
        fp = -loglike_theta(th, tr, st, C, dts, U, Y, foh, seg_start)
        th[i] = theta[i] - h
        fm = -loglike_theta(th, tr, st, C, dts, U, Y, foh, seg_start)
        th[i] = theta[i]
        grad[i] = (fp - fm) / (2.0 * h)
    return f0, grad
