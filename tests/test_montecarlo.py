"""Monte Carlo error of an interval end against a brute-force repetition of the draws."""

from __future__ import annotations

import numpy as np
import pytest

from thermocal.montecarlo import interval_end_error, quantile_standard_error


@pytest.mark.parametrize("draws", [30, 200, 2000])
def test_interval_end_error_matches_the_spread_over_repeated_draws(draws):
    """Draw ``draws`` values from a skewed distribution 2,000 times: the standard deviation
    of the 5 % and 95 % quantiles over the repetitions is what the formula gives from one
    set of draws (on average, within 25 %)."""
    rng = np.random.default_rng(draws)
    repeats = rng.lognormal(0.0, 0.5, size=(2000, draws))
    lows, highs = np.quantile(repeats, [0.05, 0.95], axis=1)
    brute = max(lows.std(), highs.std())
    formula = np.mean([interval_end_error(row, 0.9) for row in repeats[:300]])
    assert formula == pytest.approx(brute, rel=0.25), (formula, brute)


def test_quantile_standard_error_shrinks_with_the_effective_draws():
    values = np.random.default_rng(0).normal(size=(4000, 2))
    wide = quantile_standard_error(values, 0.05, 100)
    narrow = quantile_standard_error(values, 0.05, 4000)
    assert np.all(narrow < wide) and np.all(narrow > 0)
    assert interval_end_error([1.0], 0.9) == 0.0


def test_gaussian_draws_do_not_depend_on_the_eigenvectors_a_lapack_build_picks():
    """numpy's eigen-decomposition draws map the same normals through eigenvectors whose signs
    (and basis within a repeated eigenvalue) are round-off's choice, so one seed gave other
    retrofit intervals on another machine (an interval end moved 2.6 pp on the EnergyPlus
    house). The symmetric root makes the draws continuous in the covariance."""
    from thermocal.montecarlo import symmetric_square_root, truncated_gaussian_draws

    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.standard_normal((4, 4)))
    cov = (q * np.array([2.0, 2.0, 0.5, 0.0])) @ q.T  # a repeated and a zero eigenvalue
    root = symmetric_square_root(cov)
    np.testing.assert_allclose(root, root.T, atol=1e-14)
    np.testing.assert_allclose(root @ root, cov, atol=1e-12)
    # the same covariance written with a rotated eigenbasis and flipped signs (what another
    # LAPACK returns): the same draws
    turn = np.eye(4)
    c, s = np.cos(0.7), np.sin(0.7)
    turn[:2, :2] = [[c, -s], [s, c]]
    q2 = q @ turn * np.array([-1.0, 1.0, -1.0, 1.0])
    cov2 = (q2 * np.array([2.0, 2.0, 0.5, 0.0])) @ q2.T + 1e-15 * np.eye(4)
    mean, lo, hi = np.zeros(4), np.full(4, -np.inf), np.full(4, np.inf)
    a = truncated_gaussian_draws(np.random.default_rng(1), mean, cov, lo, hi, 500)
    b = truncated_gaussian_draws(np.random.default_rng(1), mean, cov2, lo, hi, 500)
    np.testing.assert_allclose(a, b, atol=1e-6)
    # numpy's own eigh-method draws differ between the two (the reason for the change)
    ua = np.random.default_rng(1).multivariate_normal(mean, cov, size=500, method="eigh")
    ub = np.random.default_rng(1).multivariate_normal(mean, cov2, size=500, method="eigh")
    assert np.abs(ua - ub).max() > 0.1


def test_truncated_gaussian_draws_follow_the_truncated_distribution():
    """Against the truncated normal's own moments (scipy.stats.truncnorm): a correlated pair
    with one bound cutting the first parameter at its mean."""
    from scipy import stats

    from thermocal.montecarlo import truncated_gaussian_draws

    cov = np.array([[1.0, 0.6], [0.6, 2.0]])
    draws = truncated_gaussian_draws(
        np.random.default_rng(0),
        np.zeros(2),
        cov,
        np.array([0.0, -np.inf]),
        np.array([np.inf, np.inf]),
        40_000,
    )
    assert draws[:, 0].min() >= 0.0
    np.testing.assert_allclose(draws[:, 0].mean(), stats.truncnorm(0, np.inf).mean(), atol=0.015)
    np.testing.assert_allclose(draws[:, 0].var(), stats.truncnorm(0, np.inf).var(), atol=0.02)
    # the second, through the correlation: E[x2 | x1 > 0] = 0.6 E[x1 | x1 > 0]
    np.testing.assert_allclose(
        draws[:, 1].mean(), 0.6 * stats.truncnorm(0, np.inf).mean(), atol=0.03
    )
