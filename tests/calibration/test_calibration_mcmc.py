"""Posterior samplers against brute-force integration, and the interval's stability.

The affine meta-model's posterior is a Gaussian in ``z = log(p / p0)`` truncated to the prior
box; its marginal quantiles are computed here by integrating the density on a fine grid (no
sampler involved) and compared with the Gibbs sampler and with emcee's ensemble sampler.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from thermocal.calibration.mcmc import (
    ensemble_until_precise,
    quantile_standard_error,
    truncated_gaussian_gibbs,
)
from thermocal.calibration.posterior import calibration_posterior

# a correlated, tilted Gaussian whose mass is cut by the box on both parameters
PRECISION = np.array([[40.0, -30.0], [-30.0, 36.0]])
LINEAR = np.array([30.0, -10.0])
LOWER = np.array([0.2, -0.6])
UPPER = np.array([1.5, 0.3])


def _grid_quantiles(probabilities, points: int = 2001):
    """Marginal quantiles of the truncated density by integration on a grid."""
    x = np.linspace(LOWER[0], UPPER[0], points)
    y = np.linspace(LOWER[1], UPPER[1], points)
    X, Y = np.meshgrid(x, y, indexing="ij")
    Z = np.stack([X, Y], axis=-1)
    log_density = -0.5 * np.einsum("...i,ij,...j->...", Z, PRECISION, Z) + Z @ LINEAR
    density = np.exp(log_density - log_density.max())
    out = []
    for axis, grid in ((1, x), (0, y)):
        marginal = np.trapezoid(density, axis=axis)
        cdf = np.concatenate([[0.0], np.cumsum(0.5 * (marginal[1:] + marginal[:-1]))])
        out.append(np.interp(probabilities, cdf / cdf[-1], grid))
    return np.array(out).T  # (probabilities, d)


def _log_density(z):
    z = np.atleast_2d(z)
    inside = np.all((z >= LOWER) & (z <= UPPER), axis=1)
    lp = -0.5 * np.einsum("ij,jk,ik->i", z, PRECISION, z) + z @ LINEAR
    return np.where(inside, lp, -np.inf)


def test_gibbs_quantiles_match_the_integrated_truncated_gaussian():
    truth = _grid_quantiles([0.05, 0.5, 0.95])
    chain, effective, tau, _ = truncated_gaussian_gibbs(
        PRECISION, LINEAR, LOWER, UPPER, np.array([0.5, 0.0]), sweeps=200, seed=3,
        effective_draws=20000,
    )  # fmt: skip
    assert effective >= 20000 and tau >= 1.0
    sampled = np.quantile(chain, [0.05, 0.5, 0.95], axis=0)
    for k, p in enumerate((0.05, 0.5, 0.95)):
        mcse = quantile_standard_error(chain, p, effective)
        assert np.all(np.abs(sampled[k] - truth[k]) < 4.0 * mcse + 1e-3), (p, sampled[k], truth[k])


def test_ensemble_sampler_matches_the_integrated_truncated_gaussian():
    truth = _grid_quantiles([0.05, 0.95])
    rng = np.random.default_rng(0)
    start = np.clip(np.array([0.8, 0.0]) + 0.01 * rng.standard_normal((64, 2)), LOWER, UPPER)
    chain, effective, tau, acceptance = ensemble_until_precise(_log_density, start, 1000, 1, 4000)
    assert effective >= 4000 and 0.2 < acceptance < 0.9
    sampled = np.quantile(chain, [0.05, 0.95], axis=0)
    for k, p in enumerate((0.05, 0.95)):
        mcse = quantile_standard_error(chain, p, effective)
        assert np.all(np.abs(sampled[k] - truth[k]) < 4.0 * mcse + 2e-3), (p, sampled[k], truth[k])


def test_a_parameter_without_effect_keeps_its_uniform_prior():
    """Zero precision: the conditional is the prior's tilt exp(z) on the interval, i.e. the
    parameter p = exp(z) stays uniform between its bounds."""
    chain, effective, _, _ = truncated_gaussian_gibbs(
        np.zeros((1, 1)), np.ones(1), np.log([0.5]), np.log([1.5]), np.zeros(1), sweeps=200,
        seed=0, effective_draws=20000,
    )  # fmt: skip
    p = np.exp(chain[:, 0])
    assert np.quantile(p, 0.05) == pytest.approx(0.55, abs=0.01)
    assert np.quantile(p, 0.95) == pytest.approx(1.45, abs=0.01)
    assert np.mean(p) == pytest.approx(1.0, abs=0.01)


def _surrogate(jacobian, intercept, names, nominal):
    return SimpleNamespace(
        feature_names_in_=np.array(names, dtype=object),
        estimator_=SimpleNamespace(coef_=np.asarray(jacobian), intercept_=np.asarray(intercept)),
        nominal=dict(zip(names, nominal, strict=True)),
    )


def test_a_round_off_change_of_the_heat_moves_the_interval_by_round_off():
    """The knife edge found on the multifamily twin: a change of 5e-14 in the identified heat
    moved an emcee interval end by 1 % (another Markov chain). The affine posterior's
    interval is a continuous function of the meta-model for fixed random numbers."""
    rng = np.random.default_rng(11)
    n = 300
    names = ["construction/Wall/resistance", "zone/attic/infiltration_ach"]
    nominal = np.array([2.8, 0.6])
    J = rng.normal(0.0, 300.0, (n, 2))
    intercept = -(J - J.mean(0)) @ np.array([0.3, 0.35]) + rng.normal(0.0, 200.0, n)
    lower, upper = nominal * 0.5, nominal * 1.5
    a = calibration_posterior(_surrogate(J, intercept, names, nominal), names, lower, upper,
                              discrepancy="neighbours", seed=1)  # fmt: skip
    nudged = intercept * (1.0 + 5e-14 * rng.standard_normal(n))
    b = calibration_posterior(_surrogate(J, nudged, names, nominal), names, lower, upper,
                              discrepancy="neighbours", seed=1)  # fmt: skip
    for column in ("q05", "median", "q95"):
        assert np.allclose(a.summary[column], b.summary[column], rtol=1e-9, atol=0), column
    assert np.all(a.summary["q05_mcse"] > 0) and np.all(a.summary["q95_mcse"] > 0)
    assert a.effective_draws >= 4000
    assert "effectively independent posterior draws" in " ".join(a.sentences())
    assert a.to_dict()["effective_draws"] == pytest.approx(a.effective_draws)


@pytest.mark.parametrize("mean", [-1.0, 2.5, -5.0, 6.0])
def test_a_box_far_in_the_tail_of_the_gaussian(mean):
    """The box [0.5, 1] lies 15 or 50 standard deviations from the mean (either side; at 50
    the distribution function underflows in double precision): the draws crowd at the nearer
    bound with the tail's exponential shape, by integration."""
    q = 100.0
    chain, effective, _, _ = truncated_gaussian_gibbs(
        np.array([[q]]), np.array([q * mean]), np.array([0.5]), np.array([1.0]), np.array([0.75]),
        sweeps=200, seed=4, effective_draws=20000,
    )  # fmt: skip
    z = np.linspace(0.5, 1.0, 200001)
    log_density = -0.5 * q * (z - mean) ** 2
    density = np.exp(log_density - log_density.max())
    cdf = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]))])
    truth = np.interp([0.05, 0.5, 0.95], cdf / cdf[-1], z)
    sampled = np.quantile(chain[:, 0], [0.05, 0.5, 0.95])
    assert np.allclose(sampled, truth, atol=5e-4), (sampled, truth)


@pytest.mark.parametrize(
    ("shift", "q"),
    [(0.0, 0.0), (3.0, 0.0), (-5.0, 0.0), (0.0, 1e-7), (0.0, 0.5), (10.0, 5.0), (-30.0, 20.0),
     (2000.0, 1e4), (-1e5, 2e5)],
)  # fmt: skip
def test_the_conductance_conditional_is_its_density(shift, q):
    """A conductance coordinate's Gibbs conditional ``exp(-q x^2 / 2 + shift x) (1 - x)^-2``
    (a resistance from 0.5 to 6 m2 K/W, nominal 2, ISO 6946's films): its draws are
    distributed as the density itself (Kolmogorov-Smirnov against the distribution function
    integrated on a fine grid), flat, tilted, wide, narrow."""
    from scipy import stats

    from thermocal.calibration.mcmc import _conditional_draw_convex, _conductance_knots

    lower, upper = 1.0 - 2.17 / 0.67, 1.0 - 2.17 / 6.17
    n = 100_000
    draws = _conditional_draw_convex(
        np.full(n, shift), q, _conductance_knots(lower, upper), np.random.default_rng(7).random(n)
    )
    grid = np.linspace(lower, upper, 400_001)
    log_density = -0.5 * q * grid**2 + shift * grid - 2.0 * np.log1p(-grid)
    density = np.exp(log_density - log_density.max())
    cdf = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]))])
    assert stats.kstest(np.interp(draws, grid, cdf / cdf[-1]), "uniform").pvalue > 1e-3
