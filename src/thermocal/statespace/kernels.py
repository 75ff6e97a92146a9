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

import numba
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
def heat_loss_from_network(G, s):
    """Steady-state heat loss coefficient [W/K] of state ``s`` to all boundary temperatures.

    ``H = -(G_ss + G_sf x_f)`` with ``G_ff x_f = -G_fs`` (``G`` [W/K] the conductance matrix,
    ``f`` the other states, floating without heat input); NaN when ``G_ff`` is singular.
    """
    n = G.shape[0]
    if n == 1:
        return -G[0, 0]
    f = np.empty(n - 1, dtype=np.int64)
    q = 0
    for i in range(n):
        if i != s:
            f[q] = i
            q += 1
    Gff = np.empty((n - 1, n - 1))
    rhs = np.empty(n - 1)
    for a in range(n - 1):
        rhs[a] = -G[f[a], s]
        for b in range(n - 1):
            Gff[a, b] = G[f[a], f[b]]
    if not np.all(np.isfinite(Gff)) or abs(np.linalg.det(Gff)) == 0.0:
        return np.nan
    x = np.linalg.solve(Gff, rhs)
    acc = G[s, s]
    for a in range(n - 1):
        acc += G[s, f[a]] * x[a]
    return -acc


@njit(cache=True, error_model="numpy")
def heat_loss_theta(theta, tr, st, n_inputs, s):
    """:func:`heat_loss_from_network` [W/K] at unconstrained parameters ``theta`` (``tr``,
    ``st`` as in :func:`loglike_theta`)."""
    values = fill_values(theta, tr[0], tr[1], tr[2], tr[3], tr[4], tr[5])
    _, G, _, _ = build_network(
        values, st[0], st[1], st[2], st[3], st[4], st[5], st[6], st[7], st[8], st[9], st[10],
        st[11], st[12], st[13], st[14], st[18], n_inputs,
    )  # fmt: skip
    return heat_loss_from_network(G, s)


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
    lam,
    T,
    Tinv,
    TB,
    M,
    C,
    meas_var,
    x0,
    P0,
    dts,
    U,
    Y,
    foh,
    store,
    xp,
    Pp,
    xf,
    Pf,
    Ads,
    seg_start,
    seg_x0,
    handoff,
    hand,
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

    Hand-off (used by :func:`loglike_batch`): when the filter is stationary at the start of a
    sample ``k >= handoff`` (no store), it stops there and writes what the rest of the run needs
    into the buffers ``hand`` (see :func:`handoff_buffers`: ``k``, the modal mean, the frozen
    gains and innovation variances, the modal output matrix and the discretisation); the
    returned value is then the log-likelihood of the samples before ``k``. ``handoff`` beyond
    the last sample: no hand-off.
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
        if steady and k >= handoff and not store:
            _write_handoff(hand, k, z, Kfix, sfix, log_sfix, Cz, e, G0, G1)
            return loglike
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
def handoff_buffers(n, ny, m):
    """Buffers of a filter hand-off (see :func:`kalman_filter`): ``(k, z, Kfix, sfix,
    log_sfix, Cz, e, G0, G1)``; ``k[0] = -1`` until a hand-off happens."""
    k = np.full(1, -1, dtype=np.int64)
    return (
        k, np.zeros(n), np.zeros((ny, n)), np.ones(ny), np.zeros(ny), np.zeros((ny, n)),
        np.zeros(n), np.zeros((n, m)), np.zeros((n, m)),
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def _write_handoff(hand, k, z, Kfix, sfix, log_sfix, Cz, e, G0, G1):
    # element by element: a slice assignment compiles numpy's broadcasting checks and their
    # error messages (about 3 s of the first run's compilation)
    hand[0][0] = k
    n, ny, m = z.size, sfix.size, G0.shape[1]
    for i in range(n):
        hand[1][i] = z[i]
        hand[6][i] = e[i]
        for c in range(m):
            hand[7][i, c] = G0[i, c]
            hand[8][i, c] = G1[i, c]
    for r in range(ny):
        hand[3][r] = sfix[r]
        hand[4][r] = log_sfix[r]
        for i in range(n):
            hand[2][r, i] = Kfix[r, i]
            hand[5][r, i] = Cz[r, i]


@njit(cache=True, error_model="numpy")
def stationary_from(dts, Y, seg_start):
    """First sample ``c >= 1`` from which the data cannot interrupt a stationary filter: every
    sample from ``c`` on has all outputs observed and starts no period, and the intervals from
    ``c - 1`` to the end are all equal. ``Y.shape[0]`` when there is none."""
    N = Y.shape[0]
    c = N
    if N < 2:
        return c
    dt = dts[N - 2]
    j = N - 1
    while j >= 1:
        ok = dts[j - 1] == dt
        for r in range(Y.shape[1]):
            if math.isnan(Y[j, r]):
                ok = False
        for s in range(seg_start.size):
            if seg_start[s] == j:
                ok = False
        if not ok:
            break
        c = j
        j -= 1
    return c


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
def _filter_theta(theta, tr, st, C, dts, U, Y, foh, seg_start, handoff, hand):
    """The likelihood filter at unconstrained ``theta`` (see :func:`loglike_theta`), with a
    hand-off from sample ``handoff`` on (see :func:`kalman_filter`)."""
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
    return kalman_filter(
        lam,
        T,
        Tinv,
        TB,
        M,
        C,
        meas_var,
        x0,
        P0,
        dts,
        U,
        Y,
        foh,
        store,
        e2,
        e3,
        e2,
        e3,
        e3,
        seg_start,
        seg_x0,
        handoff,
        hand,
    )


def loglike_theta(theta, tr, st, C, dts, U, Y, foh, seg_start):
    """Log-likelihood at unconstrained parameters ``theta``.

    ``tr`` = (free_idx, kind, lower, upper, si_factor, base_values) and ``st`` = the structure
    tuple of :meth:`RCModel.structure` (see :func:`system_from_values`; ``st[19]`` indexes the
    initial means of the periods after the first, see :func:`period_initial_means`);
    ``seg_start``: first sample of each later period (empty: one period).
    """
    hand = handoff_buffers(st[0].size, C.shape[0], U.shape[1])
    ll = _filter_theta(theta, tr, st, C, dts, U, Y, foh, seg_start, Y.shape[0] + 1, hand)
    return ll if math.isfinite(ll) else -np.inf


@njit(cache=True, error_model="numpy")
def _stationary_steps(k0, k1, b, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh):
    """Samples ``k0 .. k1 - 1`` of the stationary filter of column ``b`` of the batch arrays
    (the same operations, in the same order, as the stationary branch of
    :func:`kalman_filter`)."""
    n, ny, m, N = Z.shape[0], Y.shape[1], U.shape[1], Y.shape[0]
    for k in range(k0, k1):
        for r in range(ny):
            v = Y[k, r]
            for i in range(n):
                v -= CZ[r, i, b] * Z[i, b]
            for i in range(n):
                Z[i, b] += KF[r, i, b] * v
            LL[b] -= 0.5 * (LOG_2PI + LS[r, b] + v * v / S[r, b])
        if k == N - 1:
            break
        for i in range(n):
            acc = E[i, b] * Z[i, b]
            for c in range(m):
                acc += GA[i, c, b] * U[k, c]
            if foh:
                for c in range(m):
                    acc += GB[i, c, b] * U[k + 1, c]
            Z[i, b] = acc


#: Largest number of states with a compiled specialisation of the stationary batch filter
#: (:func:`_batch_stationary_fixed`); larger systems use the generic loops.
FIXED_MAX_STATES = 4


@njit(cache=True, error_model="numpy")
def _batch_stationary_fixed(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh, n):
    """:func:`_batch_stationary` for one output, compiled for ``n`` states given as a literal
    constant: the loops over the states are unrolled, so a sample is one loop over the columns
    for the measurement update and one for the time update (two or three inputs, zero-order
    hold; otherwise one per input plus two), which the compiler vectorises, instead of a short
    loop over the columns per state and input. The same operations, in the same order, for
    each column (bit-identical results)."""
    numba.literally(n)
    B = Z.shape[1]
    N, m = Y.shape[0], U.shape[1]
    acc = np.empty((n, B))
    for k in range(k0, N):
        y = Y[k, 0]
        for b in range(B):
            v = y
            for i in range(n):
                v -= CZ[0, i, b] * Z[i, b]
            for i in range(n):
                Z[i, b] += KF[0, i, b] * v
            LL[b] -= 0.5 * (LOG_2PI + LS[0, b] + v * v / S[0, b])
        if k == N - 1:
            break
        # time update, the terms added in the order of kalman_filter's
        if m == 3 and not foh:
            u0, u1, u2 = U[k, 0], U[k, 1], U[k, 2]
            for b in range(B):
                for i in range(n):
                    z = E[i, b] * Z[i, b] + GA[i, 0, b] * u0
                    Z[i, b] = z + GA[i, 1, b] * u1 + GA[i, 2, b] * u2
            continue
        if m == 2 and not foh:
            u0, u1 = U[k, 0], U[k, 1]
            for b in range(B):
                for i in range(n):
                    Z[i, b] = E[i, b] * Z[i, b] + GA[i, 0, b] * u0 + GA[i, 1, b] * u1
            continue
        for b in range(B):
            for i in range(n):
                acc[i, b] = E[i, b] * Z[i, b]
        for c in range(m):
            u = U[k, c]
            for b in range(B):
                for i in range(n):
                    acc[i, b] += GA[i, c, b] * u
        if foh:
            for c in range(m):
                u = U[k + 1, c]
                for b in range(B):
                    for i in range(n):
                        acc[i, b] += GB[i, c, b] * u
        for b in range(B):
            for i in range(n):
                Z[i, b] = acc[i, b]


def _batch_stationary(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh):
    """Samples ``k0`` to the end of the stationary filters of all columns of the batch arrays,
    advanced together (the innermost loops over the columns); the same operations, in the same
    order, as the stationary branch of :func:`kalman_filter`. One output and at most
    :data:`FIXED_MAX_STATES` states: the specialised loops of :func:`_batch_stationary_fixed`
    (the same numbers), compiled for the number of states on first use only.

    Called from Python, not from compiled code: a compiled caller would link (and the compiler
    optimise again) every specialisation into its own code, which tripled the first run's
    compilation time (about 60 s of the demo's first run were compilation)."""
    n = Z.shape[0]
    if k0 >= Y.shape[0]:
        return
    run = _BATCH_STATIONARY_FIXED.get(n) if Y.shape[1] == 1 else None
    (run or _batch_stationary_generic)(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh)


# one compiled entry per number of states (a literal argument given from Python would be
# typed again on every call, about 0.1 s each)
@njit(cache=True, error_model="numpy")
def _batch_stationary_1(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh):
    _batch_stationary_fixed(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh, 1)


@njit(cache=True, error_model="numpy")
def _batch_stationary_2(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh):
    _batch_stationary_fixed(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh, 2)


@njit(cache=True, error_model="numpy")
def _batch_stationary_3(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh):
    _batch_stationary_fixed(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh, 3)


@njit(cache=True, error_model="numpy")
def _batch_stationary_4(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh):
    _batch_stationary_fixed(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh, 4)


_BATCH_STATIONARY_FIXED = {
    1: _batch_stationary_1,
    2: _batch_stationary_2,
    3: _batch_stationary_3,
    4: _batch_stationary_4,
}


@njit(cache=True, error_model="numpy")
def _batch_stationary_generic(k0, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh):
    """:func:`_batch_stationary` for any number of states and outputs."""
    n, B = Z.shape
    ny, m, N = Y.shape[1], U.shape[1], Y.shape[0]
    v = np.empty(B)
    acc = np.empty(B)
    for k in range(k0, N):
        for r in range(ny):
            y = Y[k, r]
            for b in range(B):
                v[b] = y
            for i in range(n):
                for b in range(B):
                    v[b] -= CZ[r, i, b] * Z[i, b]
            for i in range(n):
                for b in range(B):
                    Z[i, b] += KF[r, i, b] * v[b]
            for b in range(B):
                LL[b] -= 0.5 * (LOG_2PI + LS[r, b] + v[b] * v[b] / S[r, b])
        if k == N - 1:
            break
        for i in range(n):
            for b in range(B):
                acc[b] = E[i, b] * Z[i, b]
            for c in range(m):
                u = U[k, c]
                for b in range(B):
                    acc[b] += GA[i, c, b] * u
            if foh:
                for c in range(m):
                    u = U[k + 1, c]
                    for b in range(B):
                        acc[b] += GB[i, c, b] * u
            for b in range(B):
                Z[i, b] = acc[b]


@njit(cache=True, error_model="numpy")
def _loglike_batch_complete(thetas, tr, st, C, dts, U, Y, foh):
    """:func:`loglike_batch` on data with every output observed, one period and one sampling
    interval: all rows' filters run together from the first sample (the innermost loops over
    the rows, also while the covariances are still converging); each row switches to its frozen
    gain when its own filter would (the same test), so the numbers are those of
    :func:`kalman_filter` row by row. Runs until every row's covariance is stationary and
    returns that sample, the rows whose system is not finite and the batch arrays
    ``(Z, KF, S, LS, CZ, E, GA, GB, LL)``: :func:`loglike_batch` finishes with
    :func:`_batch_stationary`."""
    B = thetas.shape[0]
    N = Y.shape[0]
    n = st[0].size
    ny = C.shape[0]
    m = U.shape[1]
    Z = np.zeros((n, B))
    P = np.zeros((n, n, B))
    KF = np.zeros((ny, n, B))
    S = np.ones((ny, B))
    LS = np.zeros((ny, B))
    CZ = np.zeros((ny, n, B))
    MV = np.ones((ny, B))
    E = np.zeros((n, B))
    GA = np.zeros((n, m, B))
    GB = np.zeros((n, m, B))
    W = np.zeros((n, n, B))
    LL = np.zeros(B)
    steady = np.zeros(B, dtype=np.bool_)
    dead = np.zeros(B, dtype=np.bool_)
    e1 = np.empty(n)
    g0 = np.empty((n, m))
    g1 = np.empty((n, m))
    w1 = np.empty((n, n))
    for b in range(B):
        values = fill_values(thetas[b], tr[0], tr[1], tr[2], tr[3], tr[4], tr[5])
        lam, T, Tinv, TB, M, meas_var, x0, P0 = system_from_values(
            values, st[0], st[1], st[2], st[3], st[4], st[5], st[6], st[7], st[8], st[9],
            st[10], st[11], st[12], st[13], st[14], st[15], st[16], st[17], st[18], m,
        )  # fmt: skip
        finite = True
        for i in range(n):
            if not math.isfinite(lam[i]):
                finite = False
        if not finite:
            dead[b] = True
            steady[b] = True  # never tested again
            continue
        # as kalman_filter: modal output matrix, initial mean and covariance, discretisation
        for r in range(ny):
            MV[r, b] = meas_var[r]
            for j in range(n):
                acc = 0.0
                for i in range(n):
                    acc += C[r, i] * T[i, j]
                CZ[r, j, b] = acc
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += Tinv[i, j] * x0[j]
            Z[i, b] = acc
        for i in range(n):
            for j in range(n):
                acc = 0.0
                for a in range(n):
                    for c in range(n):
                        acc += Tinv[i, a] * P0[a, c] * Tinv[j, c]
                P[i, j, b] = acc
        if N > 1:
            modal_discretise(lam, TB, M, dts[0], foh, e1, g0, g1, w1)
            for i in range(n):
                E[i, b] = e1[i]
                for c in range(m):
                    GA[i, c, b] = g0[i, c]
                    GB[i, c, b] = g1[i, c]
                for j in range(n):
                    W[i, j, b] = w1[i, j]
    # rows with the same covariance recursion (initial covariance, modal output matrix,
    # measurement variances, transition and process noise all equal bit for bit: e.g. the
    # gradient's rows that move an initial mean or an input coefficient only) share one
    # covariance row: its gains, innovation variances and stationarity are theirs
    cov_of = np.empty(B, dtype=np.int64)
    rep = np.empty(B, dtype=np.int64)
    NU = 0
    for b in range(B):
        cov_of[b] = -1
        for t in range(NU):
            a = rep[t]
            if dead[a] != dead[b]:
                continue
            same = True
            for r in range(ny):
                if MV[r, a] != MV[r, b]:
                    same = False
                for i in range(n):
                    if CZ[r, i, a] != CZ[r, i, b]:
                        same = False
            for i in range(n):
                if E[i, a] != E[i, b]:
                    same = False
                for j in range(n):
                    if P[i, j, a] != P[i, j, b] or W[i, j, a] != W[i, j, b]:
                        same = False
            if same:
                cov_of[b] = t
                break
        if cov_of[b] < 0:
            rep[NU] = b
            cov_of[b] = NU
            NU += 1
    # the covariance rows
    Pc = np.empty((n, n, NU))
    Wc = np.empty((n, n, NU))
    Ec = np.empty((n, NU))
    CZc = np.empty((ny, n, NU))
    MVc = np.empty((ny, NU))
    KFc = np.zeros((ny, n, NU))
    Sc = np.ones((ny, NU))
    LSc = np.zeros((ny, NU))
    steady_c = np.empty(NU, dtype=np.bool_)
    dead_c = np.empty(NU, dtype=np.bool_)
    for t in range(NU):
        a = rep[t]
        steady_c[t] = steady[a]
        dead_c[t] = dead[a]
        for i in range(n):
            Ec[i, t] = E[i, a]
            for j in range(n):
                Pc[i, j, t] = P[i, j, a]
                Wc[i, j, t] = W[i, j, a]
        for r in range(ny):
            MVc[r, t] = MV[r, a]
            for i in range(n):
                CZc[r, i, t] = CZ[r, i, a]
    v = np.empty(B)
    s = np.empty(NU)
    PC = np.empty((n, NU))
    K = np.empty((n, NU))
    LP = np.empty((n, n, NU))
    Pprior = np.empty((n, n, NU))
    acc_b = np.empty(B)
    acc_c = np.empty(NU)
    change = np.empty(NU)
    scale = np.empty(NU)
    k = 0
    while k < N:
        all_steady = True
        for t in range(NU):
            if not steady_c[t]:
                all_steady = False
        if all_steady:
            break
        for i in range(n):
            for j in range(n):
                for t in range(NU):
                    Pprior[i, j, t] = Pc[i, j, t]
        for r in range(ny):
            y = Y[k, r]
            for b in range(B):
                v[b] = y
            for i in range(n):
                for b in range(B):
                    v[b] -= CZ[r, i, b] * Z[i, b]
            for t in range(NU):
                s[t] = MVc[r, t]
            for i in range(n):
                for t in range(NU):
                    acc_c[t] = 0.0
                for j in range(n):
                    for t in range(NU):
                        acc_c[t] += Pc[i, j, t] * CZc[r, j, t]
                for t in range(NU):
                    PC[i, t] = acc_c[t]
                    s[t] += CZc[r, i, t] * acc_c[t]
            for t in range(NU):
                if not steady_c[t]:
                    if not (s[t] > 0.0) or not math.isfinite(s[t]):
                        dead_c[t] = True
                        steady_c[t] = True
                        s[t] = 1.0  # the row's result is -inf; keep its arithmetic finite
            for i in range(n):
                for t in range(NU):
                    K[i, t] = PC[i, t] / s[t]
            for t in range(NU):
                if not steady_c[t]:
                    for i in range(n):
                        KFc[r, i, t] = K[i, t]
                    Sc[r, t] = s[t]
                    LSc[r, t] = math.log(s[t])
            for b in range(B):
                t = cov_of[b]
                for i in range(n):
                    KF[r, i, b] = KFc[r, i, t]
                S[r, b] = Sc[r, t]
                LS[r, b] = LSc[r, t]
            for i in range(n):
                for b in range(B):
                    Z[i, b] += KF[r, i, b] * v[b]
            # Joseph form (computed for every row; a stationary row's covariance is unused)
            for i in range(n):
                for j in range(n):
                    for t in range(NU):
                        LP[i, j, t] = Pc[i, j, t] - K[i, t] * PC[j, t]
            for i in range(n):
                for j in range(i, n):
                    for t in range(NU):
                        acc_c[t] = MVc[r, t] * K[i, t] * K[j, t]
                    for q in range(n):
                        delta = 1.0 if q == j else 0.0
                        for t in range(NU):
                            acc_c[t] += LP[i, q, t] * (delta - K[j, t] * CZc[r, q, t])
                    for t in range(NU):
                        Pc[i, j, t] = acc_c[t]
            for i in range(n):
                for j in range(i + 1, n):
                    for t in range(NU):
                        Pc[j, i, t] = Pc[i, j, t]
            for b in range(B):
                LL[b] -= 0.5 * (LOG_2PI + LS[r, b] + v[b] * v[b] / S[r, b])
        if k == N - 1:
            k = N
            break
        if m == 3 and not foh:
            # the same sums as below, one loop per state
            u0, u1, u2 = U[k, 0], U[k, 1], U[k, 2]
            for i in range(n):
                for b in range(B):
                    z = E[i, b] * Z[i, b] + GA[i, 0, b] * u0
                    Z[i, b] = z + GA[i, 1, b] * u1 + GA[i, 2, b] * u2
            n_left = 0
        else:
            n_left = n
        for i in range(n_left):
            for b in range(B):
                acc_b[b] = E[i, b] * Z[i, b]
            for c in range(m):
                u = U[k, c]
                for b in range(B):
                    acc_b[b] += GA[i, c, b] * u
            if foh:
                for c in range(m):
                    u = U[k + 1, c]
                    for b in range(B):
                        acc_b[b] += GB[i, c, b] * u
            for b in range(B):
                Z[i, b] = acc_b[b]
        for t in range(NU):
            change[t] = 0.0
            scale[t] = 0.0
        # the upper triangle, its change, then the mirror (separate loops: each vectorises)
        for i in range(n):
            for j in range(i, n):
                for t in range(NU):
                    Pc[i, j, t] = Ec[i, t] * Ec[j, t] * Pc[i, j, t] + Wc[i, j, t]
        for i in range(n):
            for j in range(i, n):
                for t in range(NU):
                    val = Pc[i, j, t]
                    change[t] = max(change[t], abs(val - Pprior[i, j, t]))
                    scale[t] = max(scale[t], abs(val))
        for i in range(n):
            for j in range(i + 1, n):
                for t in range(NU):
                    Pc[j, i, t] = Pc[i, j, t]
        for t in range(NU):
            if not steady_c[t] and change[t] <= STEADY_STATE_TOLERANCE * scale[t] and k + 1 < N:
                steady_c[t] = True
        k += 1
    for b in range(B):
        dead[b] = dead_c[cov_of[b]]
    return k, dead, (Z, KF, S, LS, CZ, E, GA, GB, LL)


def loglike_batch(thetas, tr, st, C, dts, U, Y, foh, seg_start):
    """Log-likelihoods at the rows of ``thetas`` (see :func:`loglike_theta`), equal to
    evaluating them one by one (the same floating-point operations).

    Each row's filter runs on its own until it is stationary on a stretch the data cannot
    interrupt (:func:`stationary_from`); the rows then advance together, sample by sample, with
    the innermost loops over the rows, so the independent recursions overlap in the processor
    instead of each waiting on its own chain of dependent operations.

    The stages are compiled separately and joined here: a compiled caller would link its
    callees' code into its own and optimise it again, once per level.
    """
    N = Y.shape[0]
    start = stationary_from(dts, Y, seg_start)
    complete = N > 0 and not np.isnan(Y[0]).any()
    if complete and start == 1 and seg_start.size == 0:
        k, dead, batch = _loglike_batch_complete(thetas, tr, st, C, dts, U, Y, foh)
        _batch_stationary(k, *batch, U, Y, foh)
        LL = batch[-1]
        return np.where(dead | ~np.isfinite(LL), -np.inf, LL)
    out, kst, kmax, batch = _loglike_batch_rows(thetas, tr, st, C, dts, U, Y, foh, seg_start, start)
    if kmax >= 0:
        _batch_stationary(kmax, *batch, U, Y, foh)
        handed = kst < N
        out[handed] = batch[-1][handed]
    out[~np.isfinite(out)] = -np.inf
    return out


@njit(cache=True, error_model="numpy")
def _loglike_batch_rows(thetas, tr, st, C, dts, U, Y, foh, seg_start, start):
    """:func:`loglike_batch`'s rows filtered one by one until each is stationary: the
    log-likelihoods of the rows that never are, the sample each was handed over at (``N``:
    never), the latest of them (``-1``: none) and the batch arrays, every handed-over row
    brought to that latest sample."""
    B = thetas.shape[0]
    N = Y.shape[0]
    n = st[0].size
    ny = C.shape[0]
    m = U.shape[1]
    out = np.empty(B)
    Z = np.zeros((n, B))
    KF = np.zeros((ny, n, B))
    S = np.ones((ny, B))
    LS = np.zeros((ny, B))
    CZ = np.zeros((ny, n, B))
    E = np.zeros((n, B))
    GA = np.zeros((n, m, B))
    GB = np.zeros((n, m, B))
    LL = np.zeros(B)
    kst = np.full(B, N, dtype=np.int64)
    hand = handoff_buffers(n, ny, m)
    kmax = -1
    for b in range(B):
        hand[0][0] = -1
        ll = _filter_theta(thetas[b], tr, st, C, dts, U, Y, foh, seg_start, start, hand)
        out[b] = ll
        k = hand[0][0]
        if k < 0 or not math.isfinite(ll):
            continue
        kst[b] = k
        kmax = max(kmax, k)
        LL[b] = ll
        for i in range(n):
            Z[i, b] = hand[1][i]
            E[i, b] = hand[6][i]
            for c in range(m):
                GA[i, c, b] = hand[7][i, c]
                GB[i, c, b] = hand[8][i, c]
        for r in range(ny):
            S[r, b] = hand[3][r]
            LS[r, b] = hand[4][r]
            for i in range(n):
                KF[r, i, b] = hand[2][r, i]
                CZ[r, i, b] = hand[5][r, i]
    if kmax >= 0:
        # the rows that became stationary earlier catch up one by one
        for b in range(B):
            if kst[b] < kmax:
                _stationary_steps(kst[b], kmax, b, Z, KF, S, LS, CZ, E, GA, GB, LL, U, Y, foh)
    return out, kst, kmax, (Z, KF, S, LS, CZ, E, GA, GB, LL)


def negloglike_and_gradient(theta, tr, st, C, dts, U, Y, foh, seg_start, rel_step):
    """Negative log-likelihood and its central-difference gradient in ``theta`` (the ``2p + 1``
    likelihoods evaluated together by :func:`loglike_batch`)."""
    thetas, steps = _gradient_rows(theta, rel_step)
    ll = loglike_batch(thetas, tr, st, C, dts, U, Y, foh, seg_start)
    return -ll[0], _central_gradient(ll, steps)


@njit(cache=True, error_model="numpy")
def _gradient_rows(theta, rel_step):
    """The ``2p + 1`` rows of :func:`negloglike_and_gradient` (``theta``, then each parameter
    up and down by its step) and the steps."""
    p = theta.size
    thetas = np.empty((2 * p + 1, p))
    steps = np.empty(p)
    for j in range(2 * p + 1):
        for i in range(p):
            thetas[j, i] = theta[i]
    for i in range(p):
        h = rel_step * max(1.0, abs(theta[i]))
        steps[i] = h
        thetas[1 + 2 * i, i] = theta[i] + h
        thetas[2 + 2 * i, i] = theta[i] - h
    return thetas, steps


@njit(cache=True, error_model="numpy")
def _central_gradient(ll, steps):
    """The negative log-likelihood's central differences from the rows' log-likelihoods."""
    p = steps.size
    grad = np.empty(p)
    for i in range(p):
        grad[i] = (-ll[1 + 2 * i] - -ll[2 + 2 * i]) / (2.0 * steps[i])
    return grad
