"""Posterior of calibrated parameters: the MCMC against the analytic Gaussian, identifiability."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from thermocal.calibration.posterior import calibration_posterior


def _series_model(jacobian, intercept, names, nominal):
    """A fitted series meta-model as the posterior sees it (coefficients per hour)."""
    return SimpleNamespace(
        feature_names_in_=np.array(names, dtype=object),
        estimator_=SimpleNamespace(coef_=np.asarray(jacobian), intercept_=np.asarray(intercept)),
        nominal=dict(zip(names, nominal, strict=True)),
    )


def test_mcmc_matches_the_analytic_posterior_of_a_linear_gaussian_model():
    """Wide bounds: the posterior in z = log(p/p0) is Gaussian (tilted by the uniform prior's
    Jacobian exp(sum z)); mean and covariance computed by hand with numpy."""
    rng = np.random.default_rng(5)
    n, d = 400, 3
    names = ["construction/Roof/resistance", "window/w/u_value", "zone/z/infiltration_ach"]
    nominal = np.array([3.0, 1.4, 0.5])
    J = rng.normal(0.0, 300.0, (n, d))
    z_true = np.array([0.3, -0.2, 0.1])
    intercept = -(J - J.mean(0)) @ z_true + rng.normal(0.0, 150.0, n)
    surrogate = _series_model(J, intercept, names, nominal)
    lower, upper = nominal * np.exp(-3.0), nominal * np.exp(3.0)
    post = calibration_posterior(surrogate, names, lower, upper, steps=3000, seed=2)
    # by hand: centred least squares, residual variance, lag-1 autocorrelation, Gaussian
    Jc, oc = J - J.mean(0), intercept - intercept.mean()
    z_ls, *_ = np.linalg.lstsq(Jc, -oc, rcond=None)
    r = oc + Jc @ z_ls
    var = r @ r / (n - 1 - d)
    rho = min(max(np.corrcoef(r[:-1], r[1:])[0, 1], 0.0), 0.99)
    precision = (1 - rho) / (1 + rho) * Jc.T @ Jc / var
    mean = np.linalg.solve(precision, precision @ z_ls + 1.0)
    std = np.sqrt(np.diag(np.linalg.inv(precision)))
    z_draws = np.log(post.samples.to_numpy() / nominal)
    assert np.allclose(z_draws.mean(0), mean, atol=0.15 * std)
    assert np.allclose(z_draws.std(0), std, rtol=0.15)
    assert np.all(np.abs(mean - z_true) < 4 * std)  # and the truth is inside
    assert post.noise_std == pytest.approx(np.sqrt(var), rel=1e-6)
    assert post.determined == names


def test_compensating_and_undetermined_parameters_are_named():
    """Walls and windows acting with the same signature compensate; a parameter without any
    effect on the series is not determined."""
    rng = np.random.default_rng(1)
    n = 300
    base = rng.normal(0.0, 400.0, n)
    J = np.column_stack([base, 0.9 * base + rng.normal(0.0, 20.0, n), np.zeros(n)])
    intercept = rng.normal(0.0, 100.0, n)
    names = ["construction/Wall/resistance", "window/w/u_value", "material/x/density"]
    nominal = np.array([2.0, 1.5, 800.0])
    post = calibration_posterior(
        _series_model(J, intercept, names, nominal), names, nominal * 0.5, nominal * 1.5,
        units=["m2 K/W", "W/(m2 K)", "kg/m3"], steps=1500, seed=0,
    )
    pairs = {(a, b) for a, b, _ in post.compensating}
    assert ("construction/Wall/resistance", "window/w/u_value") in pairs
    assert not post.summary.at["material/x/density", "determined"]
    words = " ".join(post.sentences())
    assert "compensate each other" in words and "material/x/density" in words
    assert set(post.to_dict()["parameters"]) == set(names)
