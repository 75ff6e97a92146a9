"""Model validation: residual autocorrelation, cumulated periodogram, Ljung-Box and
likelihood-ratio tests (Bacher & Madsen 2011). Forward model selection is in
:mod:`thermocal.statespace.selection` (its old names here are deprecated aliases).

References
----------
.. [1] H. Madsen, "Time Series Analysis", Chapman & Hall/CRC, 2008: sec. 6.2.3 (sample
   autocorrelation and its approximate 95 % bounds +-2/sqrt(N)), sec. 6.3.4 (cumulated periodogram
   with Kolmogorov-Smirnov bands).
.. [2] P. Bacher, H. Madsen, "Identifying suitable models for the heat dynamics of buildings",
   Energy and Buildings 43(7), 1511-1522, 2011, sec. 4 (forward selection with likelihood-ratio
   tests).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.statespace.distributions import chi2_sf, normal_quantile

#: A likelihood-ratio statistic below minus this is reported (a general model below its
#: restricted one); smaller negative values are optimiser tolerance (see ``stall_tolerance``).
NEGATIVE_LR_TOLERANCE = 0.05

#: Kolmogorov-Smirnov coefficients K_alpha for the cumulated-periodogram band.
KS_COEFFICIENTS = {0.01: 1.63, 0.05: 1.36, 0.10: 1.22, 0.25: 1.02}


def _clean(residuals) -> np.ndarray:
    e = np.asarray(residuals, dtype=float).ravel()
    e = e[np.isfinite(e)]
    if e.size < 4:
        raise ValueError("at least 4 finite residuals are needed")
    return e


def autocorrelation(residuals, nlags: int = 40, alpha: float = 0.05) -> pd.DataFrame:
    """Sample autocorrelation of residuals with the white-noise confidence bound.

    For a complete series this is the textbook estimator
    ``r_k = sum_t e_t e_(t+k) / sum_t e_t^2`` (``e`` demeaned) with the bound
    ``z_(1-alpha/2) / sqrt(N)``. Missing residuals (NaN, unobserved outputs) keep their place
    on the sampling grid, so lags stay lags: the lag-k mean product is taken over the ``m_k``
    pairs where both residuals exist and scaled like the complete-series estimator,
    ``r_k = (1 - k/N) (sum_pairs e_t e_(t+k) / m_k) / (sum e_t^2 / n)``, ``n`` the number of
    finite residuals; its bound is ``z_(1-alpha/2) / sqrt(m_k N / (N - k))`` (the white-noise
    standard deviation of ``r_k``; ``z / sqrt(N)`` for a complete series).

    Parameters
    ----------
    residuals : array-like [K]
        One-step residuals on the sampling grid, NaN where missing.
    nlags : int
        Largest lag [samples].
    alpha : float
        Level of the bound.

    Returns
    -------
    DataFrame indexed by lag (0..nlags) with columns ``acf`` and ``bound`` (per lag).
    """
    _clean(residuals)  # enough finite values
    e = np.asarray(residuals, dtype=float).ravel()
    finite = np.isfinite(e)
    big_n = e.size
    d = np.where(finite, e - e[finite].mean(), 0.0)  # a missing value contributes no product
    ones = finite.astype(float)
    c0 = float(d @ d) / finite.sum()
    nlags = min(nlags, big_n - 1)
    lags = np.arange(nlags + 1)
    pairs = np.array([float(ones[: big_n - k] @ ones[k:]) for k in lags])
    sums = np.array([float(d[: big_n - k] @ d[k:]) for k in lags])
    with np.errstate(invalid="ignore", divide="ignore"):
        acf = (1.0 - lags / big_n) * (sums / pairs) / c0
        bound = normal_quantile(1 - alpha / 2) / np.sqrt(pairs * big_n / (big_n - lags))
    acf[0] = 1.0
    return pd.DataFrame({"acf": acf, "bound": bound}, index=pd.RangeIndex(nlags + 1, name="lag"))


def cumulated_periodogram(residuals, alpha: float = 0.05) -> pd.DataFrame:
    """Cumulated periodogram of residuals with its Kolmogorov-Smirnov band.

    For white noise the cumulated periodogram follows the straight line from (0, 0) to
    (0.5, 1); the band is ``line +- K_alpha / sqrt(q)`` with ``q = floor((N - 1) / 2)``.

    Parameters
    ----------
    residuals : array-like [K]
        One-step residuals (NaN values are dropped, so the frequencies of a series with gaps
        are approximate).
    alpha : float
        0.01, 0.05, 0.10 or 0.25.

    Returns
    -------
    DataFrame with columns ``frequency`` [cycles per sample], ``cumulated``, ``white_noise``,
    ``lower``, ``upper``.
    """
    if alpha not in KS_COEFFICIENTS:
        raise ValueError(f"alpha must be one of {sorted(KS_COEFFICIENTS)}")
    e = _clean(residuals)
    e = e - e.mean()
    n = e.size
    spec = np.abs(np.fft.rfft(e)) ** 2 / n
    q = (n - 1) // 2
    periodogram = spec[1 : q + 1]
    freq = np.arange(1, q + 1) / n
    cumulated = np.cumsum(periodogram) / periodogram.sum()
    line = freq / 0.5
    half_width = KS_COEFFICIENTS[alpha] / math.sqrt(q)
    return pd.DataFrame(
        {
            "frequency": freq,
            "cumulated": cumulated,
            "white_noise": line,
            "lower": line - half_width,
            "upper": line + half_width,
        }
    )


def ljung_box(residuals, nlags: int = 20) -> tuple[float, float]:
    """Ljung-Box portmanteau test of residual whiteness.

    ``Q = N (N + 2) sum_(k=1..h) r_k^2 / (N - k)`` with the sample autocorrelation ``r_k`` of
    :func:`autocorrelation` (missing residuals keep their place on the grid) and ``N`` the
    number of finite residuals; under white noise ``Q ~ chi2(h)``.

    Parameters
    ----------
    residuals : array-like [K]
        One-step residuals, NaN where missing.
    nlags : int
        Number of lags ``h`` [samples] (reduced to a fifth of the series when shorter).

    Returns
    -------
    statistic, pvalue : float

    References
    ----------
    .. [1] G. M. Ljung, G. E. P. Box, "On a measure of lack of fit in time series models",
       Biometrika 65(2), 297-303, 1978.
    """
    e = _clean(residuals)
    n = e.size
    h = int(max(1, min(nlags, n // 5)))
    r = autocorrelation(residuals, nlags=h)["acf"].to_numpy()[1:]
    k = np.arange(1, r.size + 1)
    q = float(n * (n + 2) * np.sum(r**2 / (n - k)))
    return q, float(chi2_sf(q, r.size))


def fraction_outside_band(cpgram: pd.DataFrame) -> float:
    """Fraction of frequencies where the cumulated periodogram leaves its band."""
    out = (cpgram["cumulated"] < cpgram["lower"]) | (cpgram["cumulated"] > cpgram["upper"])
    return float(out.mean())


@dataclass
class LikelihoodRatioTest:
    """Result of a likelihood-ratio test of a restricted model against a more general one.

    Attributes
    ----------
    statistic : float
        ``2 (loglike_general - loglike_restricted)``.
    df : int
        Difference in the number of free parameters.
    pvalue : float
        ``P(chi2(df) > statistic)``.
    """

    restricted: str
    general: str
    loglike_restricted: float
    loglike_general: float
    statistic: float
    df: int
    pvalue: float
    warning: str = ""

    def reject(self, alpha: float = 0.05) -> bool:
        """True when the general model is significantly better at level ``alpha``."""
        return self.pvalue < alpha


def likelihood_ratio_test(restricted, general) -> LikelihoodRatioTest:
    """Likelihood-ratio test of two nested fitted models (``FitResults``).

    Under the null hypothesis that the restricted model is adequate, the statistic is
    asymptotically chi-squared with ``df = k_general - k_restricted`` degrees of freedom
    (Wilks). When the restriction puts a parameter on the boundary of the general model's space
    (e.g. a heat capacity going to zero) the chi-squared p-value is conservative.
    """
    df = general.n_free - restricted.n_free
    if df <= 0:
        raise ThermocalInputError(
            f"likelihood-ratio test: model '{general.model.name}' ({general.n_free} free "
            f"parameters) is not more general than '{restricted.model.name}' "
            f"({restricted.n_free}); pass (restricted, general)"
        )
    if restricted.nobs != general.nobs:
        raise ThermocalInputError(
            "likelihood-ratio test: the two fits used different observations "
            f"({restricted.nobs} vs {general.nobs})"
        )
    statistic = 2.0 * (general.loglike - restricted.loglike)
    pvalue = float(chi2_sf(max(statistic, 0.0), df))
    warning = ""
    if statistic < -NEGATIVE_LR_TOLERANCE:
        warning = (
            f"likelihood-ratio test: the general model '{general.model.name}' ended "
            f"{-statistic / 2:.3g} log-units below the restricted model "
            f"'{restricted.model.name}' (statistic {statistic:.3g} < 0): if the models are "
            "nested, the general fit is a poor local optimum; refit it warm-started from the "
            "restricted optimum (fit(..., warm_start=restricted_results)) or with more starts"
        )
        warnings.warn(warning, stacklevel=2)
        if warning not in general.flags:
            general.flags.append(warning)
    return LikelihoodRatioTest(
        restricted=restricted.model.name,
        general=general.model.name,
        loglike_restricted=restricted.loglike,
        loglike_general=general.loglike,
        statistic=statistic,
        df=df,
        pvalue=pvalue,
        warning=warning,
    )


#: Names that moved to :mod:`thermocal.statespace.selection` (deprecated aliases here).
_MOVED_TO_SELECTION = frozenset(
    {"SelectionResult", "PHYSICAL_ROLES", "REPOLISH_GAIN", "physical_at_bound", "forward_selection"}
)


def __getattr__(name: str):
    """Deprecated aliases of the forward selection's names, now in the package's
    ``selection`` module (loaded with the package, so it is taken from there, not imported
    here: the selection builds on this module)."""
    if name in _MOVED_TO_SELECTION:
        import sys

        warnings.warn(
            f"thermocal.statespace.diagnostics.{name} moved to thermocal.statespace.selection",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(sys.modules[__package__ + ".selection"], name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
