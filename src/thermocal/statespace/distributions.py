"""The few distribution functions of the engine, from :mod:`scipy.special`.

They are the functions ``scipy.stats`` itself evaluates (same numbers), without importing
``scipy.stats`` (1.5-2.5 s of a command's start-up on the shared 2-core machine, measured
2026-11-28; `thermocal select` and `fit` need none of its other content).
"""

from __future__ import annotations

import numpy as np
from scipy import special


def normal_quantile(p):
    """Quantile of the standard normal distribution at probability ``p`` [-]
    (``scipy.stats.norm.ppf``)."""
    return special.ndtri(p)


def chi2_sf(x, df):
    """Survival function ``P(X > x)`` of the chi-squared distribution with ``df`` degrees of
    freedom, for ``x >= 0`` (``scipy.stats.chi2.sf``)."""
    return special.chdtrc(df, np.maximum(x, 0.0))


def chi2_quantile(p, df):
    """Quantile of the chi-squared distribution with ``df`` degrees of freedom at probability
    ``p`` [-] (``scipy.stats.chi2.ppf``)."""
    return 2.0 * special.gammaincinv(0.5 * df, p)
