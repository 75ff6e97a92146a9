"""Monte Carlo precision of quantiles: how well an interval end drawn from samples is known.

Used by the calibration posterior (:mod:`thermocal.calibration.mcmc`, draws of a Markov chain,
their effective number from the autocorrelation) and the retrofit analysis' intervals
(independent parameter draws).

References
----------
.. [1] Vehtari A., Gelman A., Simpson D., Carpenter B., Buerkner P.-C. (2021),
   Rank-normalization, folding, and localization: an improved R-hat for assessing
   convergence of MCMC, Bayesian Analysis 16, 667-718.
"""

from __future__ import annotations

import numpy as np

__all__ = ["interval_end_error", "quantile_standard_error"]


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
