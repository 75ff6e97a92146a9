"""Exact discretisation of a general continuous LTI system by augmented matrix exponentials.

These dense routines (``scipy.linalg.expm``) work for any ``A``; the estimation kernels use the
closed forms of :mod:`thermocal.statespace.kernels` for RC networks, and the tests check the two
against each other.

References
----------
.. [1] C. F. Van Loan, "Computing integrals involving the matrix exponential", IEEE Trans.
   Automatic Control 23(3), 395-404, 1978.
.. [2] G. F. Franklin, J. D. Powell, M. L. Workman, "Digital Control of Dynamic Systems", 3rd ed.,
   1998, sec. 6.3 (zero- and first-order hold equivalents).

:func:`interval_mean_matrices` gives the mean of the state over a sampling interval (what a
logger that averages, labelled by the interval's start, records) from the same kind of
augmented exponential, one integral deeper.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm


def discretise(
    A: np.ndarray, B: np.ndarray, Sigma: np.ndarray, dt: float, hold: str = "zoh"
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Discrete system ``x[k+1] = Ad x[k] + Gam0 u[k] + Gam1 u[k+1] + w``, ``w ~ N(0, Q)``.

    Parameters
    ----------
    A : ndarray (n, n) [1/s]
    B : ndarray (n, m) [state unit / (s input unit)]
    Sigma : ndarray (n, n) [state unit / sqrt(s)]
        Diffusion matrix of ``dx = (A x + B u) dt + Sigma dw``.
    dt : float [s]
        Sampling interval.
    hold : {"zoh", "foh"}
        Zero-order hold (``Gam1 = 0``) or first-order (linear) hold of the inputs.

    Returns
    -------
    Ad, Gam0, Gam1, Q : ndarray
    """
    A = np.atleast_2d(np.asarray(A, dtype=float))
    B = np.asarray(B, dtype=float).reshape(A.shape[0], -1)
    n, m = B.shape
    # [[A, B, 0], [0, 0, I/dt], [0, 0, 0]] dt  ->  [[Ad, G1, G2], ...] with
    # G1 = int_0^dt e^{A r} dr B, G2 = int_0^dt e^{A r} (dt - r)/dt dr B
    big = np.zeros((n + 2 * m, n + 2 * m))
    big[:n, :n] = A * dt
    big[:n, n : n + m] = B * dt
    big[n : n + m, n + m :] = np.eye(m)
    E = expm(big)
    Ad = E[:n, :n]
    G1 = E[:n, n : n + m]
    G2 = E[:n, n + m :]
    if hold == "zoh":
        Gam0, Gam1 = G1, np.zeros_like(G1)
    elif hold == "foh":
        # coefficient of u[k]: int e^{A r} r/dt dr B = G1 - G2; of u[k+1]: G2
        Gam0, Gam1 = G1 - G2, G2
    else:
        raise ValueError(f"hold must be 'zoh' or 'foh', got {hold!r}")
    # Van Loan: expm([[-A, S S^T], [0, A^T]] dt) = [[., F12], [0, F22]]; Q = F22^T F12
    SS = Sigma @ Sigma.T
    vl = np.zeros((2 * n, 2 * n))
    vl[:n, :n] = -A * dt
    vl[:n, n:] = SS * dt
    vl[n:, n:] = A.T * dt
    F = expm(vl)
    Q = F[n:, n:].T @ F[:n, n:]
    return Ad, Gam0, Gam1, 0.5 * (Q + Q.T)


def interval_mean_matrices(
    A: np.ndarray, B: np.ndarray, dt: float, hold: str = "zoh"
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean of the state over ``[t_k, t_k + dt]``: ``xbar[k] = S x[k] + H0 u[k] + H1 u[k+1]``.

    A sensor logger that averages over its interval and labels the mean by the interval's start
    records ``xbar[k]``, not ``x[k]``; comparing ``x[k]`` with it puts the model half an
    interval early (on an hourly log the difference is largest at a thermostat's step).

    Parameters
    ----------
    A : ndarray (n, n) [1/s]
    B : ndarray (n, m) [state unit / (s input unit)]
    dt : float [s]
        The interval's length.
    hold : {"zoh", "foh"}
        The inputs' hold within the interval, as in :func:`discretise`.

    Returns
    -------
    S : ndarray (n, n) [-]
        ``(1/dt) int_0^dt e^{A r} dr``.
    H0, H1 : ndarray (n, m) [state unit / input unit]
        Coefficients of ``u[k]`` and ``u[k+1]`` (``H1 = 0`` with ``zoh``).

    Notes
    -----
    With ``[[A dt, [B, I] dt, 0, 0], [0, 0, I, 0], [0, 0, 0, I], [0, 0, 0, 0]]`` the exponential's
    first block row holds ``G_j = int_0^dt e^{A r} ((dt - r)/dt)^(j-1) / (j-1)! dr [B, I]``,
    j = 1, 2, 3 (Van Loan 1978). The mean of the zero-order-hold response is
    ``(1/dt) int_0^dt int_0^t e^{A r} dr dt B = G_2 B``; a first-order hold adds the ramp
    ``(u[k+1] - u[k]) t / dt``, whose mean response is ``G_3 B``.
    """
    A = np.atleast_2d(np.asarray(A, dtype=float))
    n = A.shape[0]
    B = np.asarray(B, dtype=float).reshape(n, -1)
    if hold not in ("zoh", "foh"):
        raise ValueError(f"hold must be 'zoh' or 'foh', got {hold!r}")
    m = B.shape[1] + n  # the inputs and an identity, whose first integral gives S
    size = n + 3 * m
    big = np.zeros((size, size))
    big[:n, :n] = A * dt
    big[:n, n : n + m] = np.hstack([B, np.eye(n)]) * dt
    big[n : n + m, n + m : n + 2 * m] = np.eye(m)
    big[n + m : n + 2 * m, n + 2 * m :] = np.eye(m)
    E = expm(big)
    G1, G2, G3 = (E[:n, n + j * m : n + (j + 1) * m] for j in range(3))
    S = G1[:, B.shape[1] :] / dt
    H2, H3 = G2[:, : B.shape[1]], G3[:, : B.shape[1]]
    if hold == "zoh":
        return S, H2, np.zeros_like(H2)
    return S, H2 - H3, H3
