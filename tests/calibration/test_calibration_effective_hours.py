"""Effectively independent hours of the residual identified heat, against brute force.

The posterior's likelihood counts the residual's hours as ``n / tau`` independent ones
(:func:`thermocal.calibration.posterior.effective_hours`). The truth here is the variance of the
mean over many independent replicates of the same process, ``tau = n Var(mean) / sigma^2``,
computed by brute force, not by the estimator.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from thermocal.calibration.posterior import effective_hours


def _replicates(rng, reps: int, n: int, slow: float) -> np.ndarray:
    """An AR(1) of coefficient 0.5 plus ``slow`` times one of 0.97 (warmed up), per row."""
    fast = lfilter([1.0], [1.0, -0.5], rng.standard_normal((reps, n)), axis=1)
    drift = lfilter([1.0], [1.0, -0.97], rng.standard_normal((reps, n + 500)), axis=1)[:, 500:]
    return fast + slow * drift


def _brute_force_tau(x: np.ndarray) -> float:
    n = x.shape[1]
    return float(n * x.mean(axis=1).var() / x.var(axis=1).mean())


def _lag1_tau(x: np.ndarray) -> float:
    rho = np.corrcoef(x[:-1], x[1:])[0, 1]
    return float((1 + rho) / (1 - rho))


def test_effective_hours_of_a_first_order_autoregression():
    """AR(1), coefficient 0.8: tau = (1 + 0.8) / (1 - 0.8) = 9 analytically and by brute force;
    the estimate within 20 % on 2,000 hours; white noise counts every hour."""
    rng = np.random.default_rng(11)
    n = 2000
    x = lfilter([1.0], [1.0, -0.8], rng.standard_normal((400, n)), axis=1)
    assert abs(_brute_force_tau(x) / 9.0 - 1.0) < 0.15
    taus = np.array([n / effective_hours(row, [(0, n)]) for row in x[:40]])
    assert abs(np.median(taus) / 9.0 - 1.0) < 0.2, taus
    white = rng.standard_normal(n)
    assert effective_hours(white, [(0, n)]) > 0.8 * n
    assert effective_hours(white, [(0, n)]) <= n


def test_effective_hours_see_the_slow_part_the_lag1_form_misses():
    """A fast AR(1) plus a slow drift, 600 hours a series (a month's quiet hours): the brute-force
    tau is about 31 h, the lag-1 form says about 5.5, the integrated autocorrelation time (short
    series bias it low) about 16-18: at least twice the lag-1 one, and not below 0.4 of the
    truth (0.52-0.58 of it on seeds 0-9)."""
    rng = np.random.default_rng(3)
    n = 600
    x = _replicates(rng, 2000, n, 0.25)
    truth = _brute_force_tau(x)
    assert 25.0 < truth < 38.0, truth
    iact = np.median([n / effective_hours(row, [(0, n)]) for row in x[:200]])
    lag1 = np.median([_lag1_tau(row) for row in x[:200]])
    assert iact > 2.0 * lag1, (iact, lag1)
    assert 0.4 * truth < iact < 1.2 * truth, (iact, truth)


def test_effective_hours_add_over_the_series():
    """Each series counts its own hours over its own time; series one after the other are not
    correlated across their boundary."""
    rng = np.random.default_rng(4)
    a = lfilter([1.0], [1.0, -0.8], rng.standard_normal(1500))
    b = rng.standard_normal(800)
    both = effective_hours(np.concatenate([a, b]), [(0, 1500), (1500, 2300)])
    assert both == effective_hours(a, [(0, 1500)]) + effective_hours(b, [(0, 800)])
    assert effective_hours(np.zeros(30), [(0, 30)]) == 30  # no variance: every hour


def test_a_smooth_oscillation_keeps_the_lag1_time():
    """A residual that oscillates over two days (a model error with its own daily shape): the
    integrated time sums its negative lobes away (as in a mean), the lag-1 time does not; the
    count takes the longer, so such a residual is not counted as nearly independent hours."""
    import emcee

    rng = np.random.default_rng(5)
    n = 480
    t = np.arange(n)
    r = 30.0 * np.cos(t / 7.0) + rng.normal(0.0, 2.0, n)
    integrated = emcee.autocorr.integrated_time(r, c=5, tol=0)[0]
    lag1 = _lag1_tau(r)
    assert lag1 > 5.0 * max(integrated, 1.0), (lag1, integrated)
    assert effective_hours(r, [(0, n)]) == pytest.approx(n / lag1)


def test_a_short_series_takes_the_lag1_time_alone():
    """Fewer than ``IACT_MIN_HOURS`` hours: too short for Sokal's window, the lag-1 time alone."""
    from thermocal.calibration.posterior import IACT_MIN_HOURS

    rng = np.random.default_rng(6)
    n = IACT_MIN_HOURS - 10
    r = lfilter([1.0], [1.0, -0.6], rng.standard_normal(n))
    assert effective_hours(r, [(0, n)]) == pytest.approx(n / _lag1_tau(r))
