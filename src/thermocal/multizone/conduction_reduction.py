"""Reduced-order conduction models of layered constructions.

The finite-difference model of a construction (:func:`~thermocal.multizone.network.
construction_template`) has one node per cell face. This module replaces the interior nodes of a
construction by fewer states while keeping its two surface nodes as physical nodes (so
convection, long-wave and solar exchange on the faces stay as they are), chosen by a tolerance
on the surface temperatures:

1. massless interior nodes (between no-mass layers) are condensed exactly;
2. the interior, ``C_ii dT_i/dt = -K_ii T_i - K_ib T_b`` driven by the surface temperatures
   ``T_b``, is a state-space-symmetric system in ``x = C_ii^1/2 T_i`` (its flux output is the
   transpose of its input), so its controllability and observability Gramians are equal and
   balancing is the eigenbasis of one Gramian (Moore 1981; Liu, Sreeram and Teo 1998 for
   symmetric systems): an orthogonal (Galerkin) change of variables that keeps the reduced model
   symmetric and passive;
3. the weakest balanced states are removed by singular perturbation (Fernando and Nicholson
   1982): they follow the others quasi-statically, which keeps the steady state exact (the
   surface-to-surface U-value and every steady temperature);
4. the kept states are rotated onto the eigenvectors of their conductance block (each state is
   then linked only to the two surfaces: a star) and each is scaled by its steady value under a
   uniform unit temperature, so that a uniform construction temperature gives every state that
   temperature: the reduced block is a small RC network with a diagonal capacity matrix and
   symmetric conductances with zero row sums (some links negative) that the sparse network
   assembles like any other, and the simulation's uniform initial state stays consistent.

The number of states of each construction is the smallest for which the surface temperatures of
the reduced model stay within a tolerance of the finite-difference model's
(:func:`reduction_error`: ``max ||(H + Y_r)^-1 H - (H + Y)^-1 H||_2`` with ``Y`` the 2 x 2 surface
admittance and ``H`` the surface coefficients, 3, 10 or 30 W/(m2 K) on each side) at all
frequencies from one cycle a year to the Nyquist frequency of the time step, evaluated for the
backward-Euler scheme the simulation uses (``s = (1 - exp(-i w dt)) / dt``): the comparison is
between the discrete-time models the time loop steps. When no state can be saved the
finite-difference chain is kept.

References
----------
.. [1] Moore, B.C. (1981), "Principal component analysis in linear systems: controllability,
   observability, and model reduction", IEEE Transactions on Automatic Control 26(1), 17-32.
.. [2] Fernando, K.V. and Nicholson, H. (1982), "Singular perturbational model reduction of
   balanced systems", IEEE Transactions on Automatic Control 27(2), 466-468.
.. [3] Liu, W.Q., Sreeram, V. and Teo, K.L. (1998), "Model reduction for state-space symmetric
   systems", Systems & Control Letters 34(4), 209-215.
.. [4] Craig, R.R. and Bampton, M.C.C. (1968), "Coupling of substructures for dynamic analyses",
   AIAA Journal 6(7), 1313-1319 (the modal alternative, measured less compact here: see
   docs/multizone.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from thermocal.errors import ThermocalInputError

#: Seconds in a year: the longest period of the frequency check [s].
YEAR = 365.0 * 86400.0
#: Number of log-spaced frequencies of the check.
N_FREQUENCIES = 80
#: Capacity below which a node counts as massless [J/(m2 K)].
MASSLESS = 1e-9


@dataclass(frozen=True)
class ReducedConstruction:
    """A construction's conduction model, per m2 of wall.

    Attributes
    ----------
    conductance : ndarray (n, n) [W/(m2 K)]
        Symmetric, zero row sums; node 0 the outside surface, node ``n - 1`` the inside surface,
        nodes ``1 .. n - 2`` the reduced interior states.
    capacity : ndarray (n,) [J/(m2 K)]
    n_states : int
        Interior states (the finite-difference interior nodes when no state could be saved).
    n_full : int
        Number of nodes of the finite-difference model it replaces.
    error : float [K/K]
        :func:`reduction_error` of the chosen model.
    """

    conductance: np.ndarray
    capacity: np.ndarray
    n_states: int
    n_full: int
    error: float


def chain_matrices(conductance, capacity) -> tuple[np.ndarray, np.ndarray]:
    """Conductance matrix and capacities of a finite-difference chain of nodes.

    Parameters
    ----------
    conductance : array-like (n_cells,) [W/(m2 K)]
        Between successive nodes.
    capacity : array-like (n_cells + 1,) [J/(m2 K)]

    Returns
    -------
    K : ndarray (n_cells + 1, n_cells + 1) [W/(m2 K)]
    C : ndarray (n_cells + 1,) [J/(m2 K)]
    """
    g = np.asarray(conductance, dtype=float)
    c = np.asarray(capacity, dtype=float)
    if len(c) != len(g) + 1:
        raise ValueError("a chain of n cells has n + 1 nodes")
    n = len(c)
    k = np.zeros((n, n))
    idx = np.arange(len(g))
    k[idx, idx] += g
    k[idx + 1, idx + 1] += g
    k[idx, idx + 1] -= g
    k[idx + 1, idx] -= g
    return k, c


def surface_admittance(k, c, s) -> np.ndarray:
    """Surface admittance matrices of a conduction model [W/(m2 K)].

    ``Y(s) = K_bb + s C_bb - K_bi (K_ii + s C_ii)^-1 K_ib``: the heat flowing into the
    construction through each surface node per kelvin of surface temperature (harmonic at the
    complex frequency ``s``), the other surface held.  ``Y[0, 0]`` is the outside admittance,
    ``Y[1, 1]`` the inside one, ``-Y[0, 1]`` the transmittance.  Evaluated through the
    generalised eigenvectors of ``(K_ii, C_ii)`` (massless interior nodes condensed first).

    Parameters
    ----------
    k : ndarray (n, n) [W/(m2 K)]
        Surface nodes first and last.
    c : ndarray (n,) [J/(m2 K)]
        Diagonal capacities.
    s : array-like (n_s,) complex [1/s]

    Returns
    -------
    ndarray (n_s, 2, 2) complex
    """
    k, c, _ = _condense_massless(
        np.asarray(k, dtype=float), np.asarray(c, dtype=float), keep=(0, len(c) - 1)
    )
    n = len(c)
    b = np.array([0, n - 1])
    s = np.atleast_1d(np.asarray(s, dtype=complex))
    y = k[np.ix_(b, b)][None] + s[:, None, None] * np.diag(c[b])[None]
    if n > 2:
        scale = 1.0 / np.sqrt(c[1:-1])
        lam, v = np.linalg.eigh(scale[:, None] * k[1:-1, 1:-1] * scale[None, :])
        proj = k[np.ix_(b, np.arange(1, n - 1))] @ (scale[:, None] * v)  # (2, n_i)
        y = y - np.einsum("ak,sk,bk->sab", proj, 1.0 / (lam[None, :] + s[:, None]), proj)
    return y


def backward_euler_frequencies(step: float, n: int = N_FREQUENCIES) -> np.ndarray:
    """Complex frequencies ``s = (1 - exp(-i w dt)) / dt`` of the backward-Euler scheme [1/s].

    ``w`` log-spaced from one cycle a year to the Nyquist frequency ``pi / dt``: the transfer
    function of a backward-Euler model at ``s`` is its discrete-time frequency response.

    Parameters
    ----------
    step : float [s]
    n : int
    """
    omega = np.logspace(np.log10(2.0 * np.pi / YEAR), np.log10(np.pi / step), n)
    return (1.0 - np.exp(-1j * omega * step)) / step


#: Surface coefficients (convective plus radiative, each side) at which the error of a reduced
#: model is measured [W/(m2 K)]: a still interior face, a typical interior face, an exterior face.
SURFACE_COEFFICIENTS = (3.0, 10.0, 30.0)


def surface_response(admittance, h_outside, h_inside) -> np.ndarray:
    """Surface temperatures per kelvin of the surroundings on each side [K/K].

    ``G(s) = (H + Y(s))^-1 H`` with ``H = diag(h_outside, h_inside)``: column ``j`` gives both
    surface temperatures when the temperature of the surroundings (air and radiant) on side
    ``j`` oscillates with unit amplitude; ``G H^-1`` is the response to heat absorbed on a face.

    Parameters
    ----------
    admittance : ndarray (n_s, 2, 2) [W/(m2 K)]
        :func:`surface_admittance`.
    h_outside, h_inside : float or array-like (n_h,) [W/(m2 K)]
        Surface coefficients (arrays: one response per pair).

    Returns
    -------
    ndarray (n_s, 2, 2) or (n_h, n_s, 2, 2) complex
    """
    h_o = np.asarray(h_outside, dtype=float)
    h_i = np.asarray(h_inside, dtype=float)
    h = np.zeros((*np.broadcast_shapes(h_o.shape, h_i.shape), 1, 2, 2), dtype=complex)
    h[..., 0, 0, 0] = h_o
    h[..., 0, 1, 1] = h_i
    y = np.asarray(admittance)
    return np.linalg.solve(h + y, np.broadcast_to(h, np.broadcast_shapes(h.shape, y.shape)))


def _response_grid(admittance, coefficients):
    h_out, h_in = np.meshgrid(coefficients, coefficients, indexing="ij")
    return surface_response(admittance, h_out.ravel(), h_in.ravel())


def reduction_error(y_full, y_reduced, coefficients=SURFACE_COEFFICIENTS) -> float:
    """Largest error of the surface temperatures of a reduced model [K/K].

    ``max ||G_r - G||_2`` over the frequencies of the admittances and every pair of surface
    coefficients of ``coefficients`` (:func:`surface_response`): the largest change of a surface
    temperature, per kelvin of oscillation of the surroundings, that the reduction makes.

    Parameters
    ----------
    y_full, y_reduced : ndarray (n_s, 2, 2) [W/(m2 K)]
    coefficients : sequence of float [W/(m2 K)]
    """
    return _spectral_max(
        _response_grid(y_reduced, coefficients) - _response_grid(y_full, coefficients)
    )


def _spectral_max(matrices) -> float:
    """Largest spectral norm of a stack of 2 x 2 matrices (closed form)."""
    m = np.asarray(matrices).reshape(-1, 2, 2)
    frob = np.sum(np.abs(m) ** 2, axis=(1, 2))
    det = np.abs(m[:, 0, 0] * m[:, 1, 1] - m[:, 0, 1] * m[:, 1, 0])
    return float(np.sqrt(np.max(0.5 * (frob + np.sqrt(np.maximum(frob**2 - 4 * det**2, 0))))))


def _condense_massless(k, c, keep):
    """Exact static condensation of the massless interior nodes; returns K, C, node positions
    of the boundary in the condensed order."""
    n = len(c)
    drop = np.array([j for j in range(n) if c[j] <= MASSLESS and j not in keep], dtype=int)
    stay = np.setdiff1d(np.arange(n), drop)
    if len(drop) == 0:
        return k, c, stay
    k_ss, k_sd, k_dd = k[np.ix_(stay, stay)], k[np.ix_(stay, drop)], k[np.ix_(drop, drop)]
    return k_ss - k_sd @ np.linalg.solve(k_dd, k_sd.T), c[stay], stay


def balanced_reduction(k, c, n_states: int) -> tuple[np.ndarray, np.ndarray]:
    """Reduced conduction model of a construction with ``n_states`` interior states.

    Parameters
    ----------
    k : ndarray (n, n) [W/(m2 K)]
        Conductance matrix of the finite-difference model (symmetric, zero row sums), surface
        nodes first and last.
    c : ndarray (n,) [J/(m2 K)]
    n_states : int
        Kept interior states (at most the number of massive interior nodes).

    Returns
    -------
    K_r : ndarray (n_states + 2, n_states + 2) [W/(m2 K)]
    C_r : ndarray (n_states + 2,) [J/(m2 K)]
        Outside surface first, inside surface last (see the module docstring).
    """
    return _truncate(_balanced_form(k, c), n_states)


def _balanced_form(k, c):
    """Surface block and balanced interior state space of a finite-difference construction."""
    k = np.asarray(k, dtype=float)
    c = np.asarray(c, dtype=float)
    k, c, _ = _condense_massless(k, c, keep=(0, len(c) - 1))
    n = len(c)
    b = np.array([0, n - 1])
    k_bb, c_b = k[np.ix_(b, b)], c[b]
    if n == 2:
        return k_bb, c_b, np.zeros((0, 0)), np.zeros((0, 2))
    # symmetric state space of the interior, x = C^1/2 T_i: dx/dt = A x + B T_b, flux -B^T x;
    # its two Gramians are equal, so balancing is the eigenbasis of one of them
    scale = 1.0 / np.sqrt(c[1:-1])
    a = -(scale[:, None] * k[1:-1, 1:-1] * scale[None, :])
    bm = -(scale[:, None] * k[np.ix_(b, np.arange(1, n - 1))].T)
    gramian = scipy.linalg.solve_continuous_lyapunov(a, -bm @ bm.T)
    _, v = np.linalg.eigh(0.5 * (gramian + gramian.T))
    v = v[:, ::-1]  # largest Hankel singular value first
    return k_bb, c_b, v.T @ a @ v, v.T @ bm


def _truncate(form, n_states: int):
    """Singular-perturbation truncation of :func:`_balanced_form` to ``n_states`` states, in
    temperature-like coordinates."""
    k_bb, c_b, a_t, b_t = form
    n_i = len(a_t)
    m = int(n_states)
    if m < 0 or m > n_i:
        raise ValueError(f"n_states must lie in [0, {n_i}], got {n_states}")
    a11, a12, a22 = a_t[:m, :m], a_t[:m, m:], a_t[m:, m:]
    b1, b2 = b_t[:m], b_t[m:]
    if m < n_i:  # singular perturbation: the discarded states follow quasi-statically
        a_r = a11 - a12 @ np.linalg.solve(a22, a12.T)
        b_r = b1 - a12 @ np.linalg.solve(a22, b2)
        static = b2.T @ np.linalg.solve(a22, b2)
    else:
        a_r, b_r, static = a11, b1, np.zeros((2, 2))
    (k_qq, c_q), k_qb = _temperature_like_modes(-a_r, -b_r)
    k_r = np.zeros((m + 2, m + 2))
    c_r = np.zeros(m + 2)
    outer = np.array([0, m + 1])
    inner = np.arange(1, m + 1)
    k_r[np.ix_(outer, outer)] = k_bb + static
    c_r[outer] = c_b
    if m:
        k_r[np.ix_(inner, inner)] = k_qq
        k_r[np.ix_(inner, outer)] = k_qb
        k_r[np.ix_(outer, inner)] = k_qb.T
        c_r[inner] = c_q
    return 0.5 * (k_r + k_r.T), c_r


#: Modes whose response to a uniform temperature is below this fraction of the largest one's are
#: paired with it before scaling (antisymmetric modes of symmetric constructions) [-].
WEAK_MODE = 1e-3


def _temperature_like_modes(k_qq, k_qb):
    """Sparse, temperature-like coordinates of reduced interior states of unit capacity.

    The states are first rotated onto the eigenvectors of ``k_qq`` (diagonal conductances, each
    state linked only to the two surfaces: a star, as sparse as a finite-difference chain per
    state), then each is scaled by its steady value ``g_k`` under a uniform unit temperature, so
    that a uniform construction temperature ``T`` gives every state the value ``T`` (the
    simulation starts from a uniform temperature) and the conductances have zero row sums.  A
    mode that a uniform temperature hardly excites (``|g_k|`` below :data:`WEAK_MODE` of the
    largest) is first rotated by 45 degrees with the strongest one (one off-diagonal link).

    Returns
    -------
    (K_qq, C_q) : (ndarray (m, m), ndarray (m,))
    K_qb : ndarray (m, 2)
    """
    m = len(k_qq)
    if m == 0:
        return (k_qq, np.zeros(0)), k_qb
    lam, w = np.linalg.eigh(0.5 * (k_qq + k_qq.T))
    k_qq = np.diag(lam)
    k_qb = w.T @ k_qb
    g = np.linalg.solve(k_qq, -k_qb @ np.ones(2))
    for k in np.argsort(np.abs(g)):
        if abs(g[k]) >= WEAK_MODE * np.max(np.abs(g)):
            break
        j = int(np.argmax(np.abs(g)))
        rot = np.eye(m)
        rot[np.ix_([j, k], [j, k])] = np.array([[1.0, -1.0], [1.0, 1.0]]) / np.sqrt(2.0)
        k_qq = rot.T @ k_qq @ rot
        k_qb = rot.T @ k_qb
        g = rot.T @ g
    k_qq = g[:, None] * k_qq * g[None, :]
    k_qq[np.abs(k_qq) < 1e-14 * np.max(np.abs(k_qq))] = 0.0
    return (k_qq, g**2), g[:, None] * k_qb


def reduce_construction(conductance, capacity, step: float, tolerance: float):
    """Fewest-state reduction of a finite-difference construction within a tolerance.

    Parameters
    ----------
    conductance : array-like (n_cells,) [W/(m2 K)]
        Between successive finite-difference nodes (outside -> inside).
    capacity : array-like (n_cells + 1,) [J/(m2 K)]
    step : float [s]
        Time step of the simulation (the highest frequency checked is its Nyquist frequency).
    tolerance : float [K/K]
        Largest :func:`reduction_error` accepted.

    Returns
    -------
    ReducedConstruction
    """
    if not tolerance > 0:
        raise ThermocalInputError(
            f"conduction_tolerance must be a positive number, got {tolerance!r}"
        )
    k, c = chain_matrices(conductance, capacity)
    s = backward_euler_frequencies(step)
    y_full = surface_admittance(k, c, s)
    form = _balanced_form(k, c)
    n_massive = len(form[2])
    g_full = _response_grid(y_full, SURFACE_COEFFICIENTS)
    for m in range(n_massive + 1):
        k_r, c_r = _truncate(form, m)
        error = _spectral_max(
            _response_grid(surface_admittance(k_r, c_r, s), SURFACE_COEFFICIENTS) - g_full
        )
        if error <= tolerance or m == n_massive:
            break
    if m + 2 >= len(c):  # no fewer nodes than the finite-difference chain: keep the chain
        return ReducedConstruction(k, c, len(c) - 2, len(c), 0.0)
    return ReducedConstruction(k_r, c_r, m, len(c), error)
