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
