"""Monte Carlo precision of quantiles: how well an interval end drawn from samples is known.

Used by the calibration posterior (:mod:`thermocal.calibration.mcmc`, draws of a Markov chain,
their effective number from the autocorrelation) and the retrofit analysis' intervals
(independent parameter draws), and the retrofit analysis' truncated Gaussian parameter draws.

References
----------
.. [1] Vehtari A., Gelman A., Simpson D., Carpenter B., Buerkner P.-C. (2021),
   Rank-normalization, folding, and localization: an improved R-hat for assessing
   convergence of MCMC, Bayesian Analysis 16, 667-718.
"""

from __future__ import annotations

import numpy as np

#: Gauss-Hermite rule of three points for a standard normal variable (exact for polynomials up
#: to degree 5): abscissae [standard deviations] and weights [-] (1/6, 2/3, 1/6). The
#: measurement advice of both workflows averages over a plate's possible readings with it.
GAUSS_HERMITE_3 = (
    (-float(np.sqrt(3.0)), 0.0, float(np.sqrt(3.0))),
    (1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0),
)

__all__ = [
    "GAUSS_HERMITE_3",
    "interval_end_error",
    "interval_ends",
    "quantile_standard_error",
    "symmetric_square_root",
    "truncated_gaussian_draws",
]


def quantile_standard_error(values: np.ndarray, p: float, effective: float) -> np.ndarray:
    """Monte Carlo standard error of the ``p`` quantile of posterior draws.

    Half the distance between the quantiles at ``p -+ sqrt(p (1 - p) / n_eff)``: the draws'
    binomial uncertainty of which draw is the ``p`` quantile, mapped through the empirical
    distribution (the binomial approximation of Vehtari et al. 2021, Bayesian Analysis 16, 667-718).

    Parameters
    ----------
    values : ndarray (draws, d)
        Posterior draws [unit of each parameter].
    p : float
        Probability of the quantile [-].
    effective : float
        Effective number of independent draws [-].

    Returns
    -------
    ndarray (d,)
        Standard error of each parameter's quantile [unit of each parameter].
    """
    delta = np.sqrt(p * (1.0 - p) / max(float(effective), 1.0))
    lo, hi = np.quantile(values, [max(p - delta, 0.0), min(p + delta, 1.0)], axis=0)
    return (hi - lo) / 2.0



def interval_ends(draws, interval: float) -> tuple[float, float]:
    """The ends of the central interval of some draws, NaN when there are none.

    Parameters
    ----------
    draws : array-like (n,)
        Draws of one quantity, the estimate not among them [its unit]; empty when no
        uncertainty was propagated (the retrofit analysis' ``uncertainty.draws: 0``).
    interval : float
        Central probability of the interval, e.g. 0.9 [-].

    Returns
    -------
    tuple of float
        Lower and upper end [unit of the draws]; both NaN for no draws (no interval: a JSON
        null, not the estimate as an interval of zero width).

    Examples
    --------
    >>> interval_ends([1.0, 2.0, 3.0], 0.5)
    (1.5, 2.5)
    >>> interval_ends([], 0.9)
    (nan, nan)
    """
    values = np.asarray(draws, dtype=float)
    if values.size == 0:
        return float("nan"), float("nan")
    lo_q = 0.5 * (1.0 - float(interval))
    return float(np.quantile(values, lo_q)), float(np.quantile(values, 1.0 - lo_q))


def interval_end_error(draws, interval: float) -> float:
    """Larger Monte Carlo standard error of the two ends of a central interval of
    independent draws.

    Parameters
    ----------
    draws : array-like (n,)
        Independent draws of one quantity [its unit].
    interval : float
        Central probability of the interval, e.g. 0.9 [-].

    Returns
    -------
    float
        Standard error of the less precise end [unit of the draws]; 0 for fewer than two
        draws.
    """
    values = np.asarray(draws, dtype=float).reshape(-1, 1)
    values = values[np.isfinite(values[:, 0])]
    if len(values) < 2:
        return 0.0
    low = 0.5 * (1.0 - float(interval))
    return float(
        max(quantile_standard_error(values, p, len(values))[0] for p in (low, 1.0 - low))
    )


def symmetric_square_root(cov: np.ndarray) -> np.ndarray:
    """The symmetric square root of a covariance, its negative eigenvalues set to zero.

    Unlike the factor ``V sqrt(W)`` that ``numpy.random.Generator.multivariate_normal`` builds
    from an eigen-decomposition, the symmetric root ``V sqrt(W) V^T`` does not depend on the
    sign of each eigenvector nor on the basis chosen within a repeated eigenvalue, which a
    LAPACK build picks by round-off: draws made with it are a continuous function of the
    covariance for fixed random numbers, so the same seed gives the same draws (to round-off)
    on every machine.

    Parameters
    ----------
    cov : ndarray (d, d)
        Covariance [product of the parameters' units]; symmetrised first.

    Returns
    -------
    ndarray (d, d)
        ``S`` with ``S @ S = cov`` projected onto the positive semi-definite matrices.
    """
    cov = np.asarray(cov, dtype=float)
    w, v = np.linalg.eigh(0.5 * (cov + cov.T))
    return (v * np.sqrt(np.clip(w, 0.0, None))) @ v.T


def truncated_gaussian_draws(
    rng: np.random.Generator,
    mean: np.ndarray,
    cov: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    n_draws: int,
) -> np.ndarray:
    """Draws of a multivariate normal truncated to a box, by rejection.

    Candidates are ``mean + z S`` with ``S`` the :func:`symmetric_square_root` of ``cov`` and
    ``z`` standard normal; those outside ``[lower, upper]`` are rejected. After 50 rounds the
    remaining draws (a box holding almost none of the mass) are clipped to it.

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of the random numbers.
    mean : ndarray (d,)
        Mean [unit of each parameter].
    cov : ndarray (d, d)
        Covariance [product of the units]; not positive semi-definite parts are dropped.
    lower, upper : ndarray (d,)
        Bounds of the box [unit of each parameter].
    n_draws : int
        Number of draws [-].

    Returns
    -------
    ndarray (n_draws, d)
    """
    mean = np.asarray(mean, dtype=float)
    root = symmetric_square_root(cov)
    out = np.empty((n_draws, len(mean)))
    filled = 0
    for _ in range(50):
        if filled >= n_draws:
            break
        z = rng.standard_normal((2 * (n_draws - filled) + 10, len(mean)))
        cand = mean + z @ root
        ok = np.all((cand >= lower) & (cand <= upper), axis=1)
        take = cand[ok][: n_draws - filled]
        out[filled : filled + len(take)] = take
        filled += len(take)
    if filled < n_draws:
        z = rng.standard_normal((n_draws - filled, len(mean)))
        out[filled:] = np.clip(mean + z @ root, lower, upper)
    return out
