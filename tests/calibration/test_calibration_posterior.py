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


def _data_precision(J, intercept):
    """By hand: the centred least squares ``z``, the data's precision in ``z`` and the residual
    variance: the longer of the residual's integrated (emcee's estimator) and lag-1
    autocorrelation times, at least 1, dividing the hours."""
    import emcee

    n, d = J.shape
    Jc, oc = J - J.mean(0), intercept - intercept.mean()
    z_ls, *_ = np.linalg.lstsq(Jc, -oc, rcond=None)
    r = oc + Jc @ z_ls
    var = r @ r / (n - 1 - d)
    rho = min(max(np.corrcoef(r[:-1], r[1:])[0, 1], 0.0), 0.99)
    tau = max(emcee.autocorr.integrated_time(r, c=5, tol=0)[0], (1 + rho) / (1 - rho), 1.0)
    return z_ls, Jc.T @ Jc / var / tau, var


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
    z_ls, precision, var = _data_precision(J, intercept)
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
        _series_model(J, intercept, names, nominal),
        names,
        nominal * 0.5,
        nominal * 1.5,
        units=["m2 K/W", "W/(m2 K)", "kg/m3"],
        steps=1500,
        seed=0,
    )
    pairs = {(a, b) for a, b, _ in post.compensating}
    assert ("construction/Wall/resistance", "window/w/u_value") in pairs
    assert not post.summary.at["material/x/density", "determined"]
    words = " ".join(post.sentences())
    assert "compensate each other" in words and "material/x/density" in words
    assert set(post.to_dict()["parameters"]) == set(names)


def _hand_posterior(J, intercept, tau2_fraction=1.0, discrepancy="floor"):
    """Gaussian posterior in z by hand (dense covariance): noise a I (autocorrelation
    inflated) plus the parameter-like discrepancy tau^2 U U^T, U the unit-RMS signatures."""
    n, d = J.shape
    Jc, oc = J - J.mean(0), intercept - intercept.mean()
    z_ls, *_ = np.linalg.lstsq(Jc, -oc, rcond=None)
    r = oc + Jc @ z_ls
    var = r @ r / (n - 1 - d)
    rho = min(max(np.corrcoef(r[:-1], r[1:])[0, 1], 0.0), 0.99)
    cov = var * (1 + rho) / (1 - rho) * np.eye(n)
    if discrepancy:
        U = Jc / np.sqrt(np.mean(Jc**2, axis=0))
        cov = cov + tau2_fraction * np.mean(r**2) * U @ U.T
    inv = np.linalg.inv(cov)
    precision = Jc.T @ inv @ Jc
    mean = np.linalg.solve(precision, -Jc.T @ inv @ oc + 1.0)
    return mean, np.sqrt(np.diag(np.linalg.inv(precision)))


def test_model_discrepancy_matches_the_dense_gaussian_and_widens_the_intervals():
    """With ``discrepancy="floor"`` the MCMC samples the Gaussian whose covariance adds the
    parameter-like discrepancy (checked against a dense inverse, not the Woodbury identity the
    code uses); the intervals widen."""
    rng = np.random.default_rng(7)
    n, d = 200, 2
    names = ["construction/Roof/resistance", "construction/Wall/resistance"]
    nominal = np.array([3.0, 2.0])
    J = rng.normal(0.0, 300.0, (n, d))
    intercept = -(J - J.mean(0)) @ np.array([0.2, -0.1]) + rng.normal(0.0, 150.0, n)
    surrogate = _series_model(J, intercept, names, nominal)
    lower, upper = nominal * np.exp(-3.0), nominal * np.exp(3.0)
    plain = calibration_posterior(surrogate, names, lower, upper, steps=1000, seed=1)
    post = calibration_posterior(
        surrogate, names, lower, upper, steps=2000, seed=1, discrepancy="floor"
    )
    mean, std = _hand_posterior(J, intercept)
    z = np.log(post.samples.to_numpy() / nominal)
    assert np.allclose(z.mean(0), mean, atol=0.15 * std)
    assert np.allclose(z.std(0), std, rtol=0.15)
    z_plain = np.log(plain.samples.to_numpy() / nominal)
    assert np.all(z.std(0) > 1.5 * z_plain.std(0))


def test_model_discrepancy_along_a_signature_is_covered_only_with_the_term():
    """The truth's residual heat holds, besides white noise, a model error that mimics a
    parameter change (a smooth series along the roof's signature, as large per hour as the
    noise): without the term the roof's 90 % interval misses the truth, with it it covers."""
    rng = np.random.default_rng(3)
    n = 400
    t = np.arange(n)
    roof = 400.0 * np.sin(2 * np.pi * t / 24) + 150.0 * np.sin(2 * np.pi * t / 97)
    wall = 300.0 * np.cos(2 * np.pi * t / 24 + 0.4) + rng.normal(0.0, 50.0, n)
    J = np.column_stack([roof, wall])
    names = ["construction/Roof/resistance", "construction/Wall/resistance"]
    nominal = np.array([3.0, 2.0])
    z_true = np.array([0.3, -0.2])
    noise = rng.normal(0.0, 60.0, n)
    mimic = 0.15 * (roof - roof.mean())  # looks like a roof change of 15 % in log
    intercept = -(J - J.mean(0)) @ z_true + noise + mimic
    surrogate = _series_model(J, intercept, names, nominal)
    lower, upper = nominal * np.exp(-1.5), nominal * np.exp(1.5)
    truth = nominal * np.exp(z_true)

    def covers(post):
        s = post.summary.loc["construction/Roof/resistance"]
        return s["q05"] <= truth[0] <= s["q95"], (s["q95"] - s["q05"]) / truth[0]

    plain, _ = covers(calibration_posterior(surrogate, names, lower, upper, steps=1000, seed=0))
    with_term, width = covers(
        calibration_posterior(
            surrogate, names, lower, upper, steps=1000, seed=0, discrepancy="floor"
        )
    )
    assert not plain and with_term
    assert width < 1.0  # still informative: narrower than the truth itself


def test_an_in_situ_measurement_replaces_the_prior_as_the_analytic_gaussian():
    """A measured parameter's log-normal prior (``measured=``) against the hand-computed
    Gaussian: the data's precision plus the measurement's, the means weighted by them; the
    measurement replaces the parameter's uniform prior. With data that carry nothing on it the
    posterior's median is the measurement."""
    rng = np.random.default_rng(7)
    n, d = 400, 2
    names = ["construction/Roof/resistance", "construction/Wall/resistance"]
    nominal = np.array([3.0, 2.0])
    J = rng.normal(0.0, 100.0, (n, d))
    intercept = -(J - J.mean(0)) @ np.array([0.3, -0.2]) + rng.normal(0.0, 300.0, n)
    surrogate = _series_model(J, intercept, names, nominal)
    lower, upper = nominal * np.exp(-3.0), nominal * np.exp(3.0)
    value, rel = 3.0 * np.exp(0.1), 0.08
    post = calibration_posterior(
        surrogate, names, lower, upper, steps=3000, seed=3, measured={names[0]: (value, rel)}
    )
    z_ls, data_precision, _ = _data_precision(J, intercept)
    prior_precision = np.diag([1.0 / np.log1p(rel**2), 0.0])
    prior_mean = np.array([np.log(value / 3.0), 0.0])
    precision = data_precision + prior_precision
    # the roof's log-normal prior replaces its uniform one (no exp(z) tilt); the wall keeps it
    tilt = np.array([0.0, 1.0])
    mean = np.linalg.solve(precision, data_precision @ z_ls + prior_precision @ prior_mean + tilt)
    std = np.sqrt(np.diag(np.linalg.inv(precision)))
    z_draws = np.log(post.samples.to_numpy() / nominal)
    assert np.allclose(z_draws.mean(0), mean, atol=0.15 * std)
    assert np.allclose(z_draws.std(0), std, rtol=0.15)
    # the measurement narrows the roof below what the data alone give
    alone = np.sqrt(np.diag(np.linalg.inv(data_precision)))
    assert std[0] < 0.8 * alone[0]
    assert list(post.summary["measured"]) == [True, False]
    assert "* with an in-situ measurement" in " ".join(post.sentences())
    # no information in the data on the roof: its posterior is the measurement itself
    J0 = np.column_stack([np.zeros(n), J[:, 1]])
    flat = calibration_posterior(
        _series_model(J0, intercept, names, nominal), names, lower, upper, steps=3000, seed=4,
        measured={names[0]: (value, rel)},
    )  # fmt: skip
    assert flat.summary.at[names[0], "median"] == pytest.approx(value, rel=0.01)


def test_a_measured_element_breaks_a_compensation():
    """Roof and wall with nearly the same signature: the data fix only their combination (both
    undetermined); measuring the roof determines both, the wall through the data."""
    rng = np.random.default_rng(11)
    n = 300
    base = rng.normal(0.0, 100.0, n)
    J = np.column_stack([base, -base + rng.normal(0.0, 3.0, n)])
    z_true = np.array([0.4, -0.3])
    intercept = -(J - J.mean(0)) @ z_true + rng.normal(0.0, 300.0, n)
    names = ["construction/Roof/resistance", "construction/Wall/resistance"]
    nominal = np.array([3.0, 2.0])
    surrogate = _series_model(J, intercept, names, nominal)
    lower, upper = nominal * 0.3, nominal * 3.0
    plain = calibration_posterior(surrogate, names, lower, upper, steps=1500, seed=0)
    assert not plain.determined
    measured = calibration_posterior(
        surrogate, names, lower, upper, steps=1500, seed=0,
        measured={names[0]: (3.0 * np.exp(0.4), 0.05)},
    )  # fmt: skip
    assert measured.determined == names
    s = measured.summary
    for name, z in zip(names, z_true, strict=True):
        assert s.at[name, "q05"] <= s.at[name, "nominal"] * np.exp(z) <= s.at[name, "q95"]
    with pytest.raises(Exception, match="not a parameter of the posterior"):
        calibration_posterior(
            surrogate,
            names,
            lower,
            upper,
            steps=100,
            measured={"construction/X/resistance": (1.0, 0.1)},
        )


def test_the_advice_finds_the_plate_that_breaks_a_compensation():
    """The measurement advice on the compensating roof and wall (no simulation): a plate on
    either determines both at every reading, a plate on a third, independent element (a floor
    with its own signature, determined already) determines nothing new; the three readings lie
    at the median and +-sqrt(3) sd of what the plate may read, inside the sampled range; an
    infiltration rate is not a candidate."""
    from thermocal.calibration.advice import advise_measurements, measurable_parameters

    rng = np.random.default_rng(11)
    n = 300
    base = rng.normal(0.0, 100.0, n)
    J = np.column_stack(
        [base, -base + rng.normal(0.0, 3.0, n), rng.normal(0.0, 400.0, n), np.zeros(n)]
    )
    z_true = np.array([0.4, -0.3, 0.2, 0.0])
    intercept = -(J - J.mean(0)) @ z_true + rng.normal(0.0, 300.0, n)
    names = [
        "construction/Roof/resistance",
        "construction/Wall/resistance",
        "construction/Floor/resistance",
        "zone/z/infiltration_ach",
    ]
    nominal = np.array([3.0, 2.0, 1.0, 0.5])
    surrogate = _series_model(J, intercept, names, nominal)
    lower, upper = nominal * 0.3, nominal * 3.0
    kwargs = {"steps": 1500, "seed": 0}
    post = calibration_posterior(surrogate, names, lower, upper, **kwargs)
    assert post.determined == ["construction/Floor/resistance"]
    assert measurable_parameters(names, {names[2]: (1.0, 0.1)}) == names[:2]
    advice = advise_measurements(surrogate, names, lower, upper, post, **kwargs)
    plates = {c["parameter"]: c for c in advice["candidates"]}
    assert set(plates) == set(names[:3])
    for name in names[:2]:
        assert plates[name]["determined"] == names[:3]
        for other in names[:3]:
            assert plates[name]["determined_probability"][other] == 1.0
        median = post.summary.at[name, "median"]
        i = names.index(name)
        readings = plates[name]["readings"]
        assert readings[1] == pytest.approx(median)
        assert lower[i] <= readings[0] < median < readings[2] <= upper[i]
    assert plates[names[2]]["determined"] == [names[2]]
    assert advice["candidates"][-1]["parameter"] == names[2]  # the least informative last
    best = advice["candidates"][0]["parameter"]
    other = names[1] if best == names[0] else names[0]
    assert f"would determine {best} and, through the data, {other} " in advice["summary"]
    assert advice["now"][names[2]]["determined"]


def _joint_posterior_with_nuisance(J, intercept, b, s2):
    """Brute force: the nuisance ``u ~ N(0, s2)`` as one more parameter of the affine model,
    the joint Gaussian posterior of ``(z, u)`` (noise as :func:`_hand_posterior` without
    discrepancy, the uniform prior's tilt on ``z`` only), then its ``z`` block."""
    n, d = J.shape
    Jc, oc = J - J.mean(0), intercept - intercept.mean()
    z_ls, *_ = np.linalg.lstsq(Jc, -oc, rcond=None)
    r = oc + Jc @ z_ls
    var = r @ r / (n - 1 - d)
    rho = min(max(np.corrcoef(r[:-1], r[1:])[0, 1], 0.0), 0.99)
    import emcee

    tau = max(emcee.autocorr.integrated_time(r, c=5, tol=0)[0], (1 + rho) / (1 - rho), 1.0)
    a = var * tau
    A = np.column_stack([Jc, b - b.mean()])
    precision = A.T @ A / a + np.diag([0.0] * d + [1.0 / s2])
    linear = -A.T @ oc / a + np.array([1.0] * d + [0.0])
    cov = np.linalg.inv(precision)
    mean = cov @ linear
    return mean[:d], np.sqrt(np.diag(cov)[:d])


def _roof_wall_and_air(strongly_like_the_roof: bool):
    """Hourly signatures of a roof, a wall and an air change [W per unit log] and the series
    of a truth whose air change is off by ``u_true = 0.35`` (not varied), with AR(1) noise."""
    rng = np.random.default_rng(11)
    n = 400
    t = np.arange(n)
    roof = 400.0 * np.sin(2 * np.pi * t / 24) + 100.0 * np.sin(2 * np.pi * t / 77)
    wall = 300.0 * np.cos(2 * np.pi * t / 24 + 0.9) + rng.normal(0.0, 60.0, n)
    own = 5.0 if strongly_like_the_roof else 300.0
    air = 0.8 * roof + own * np.sin(2 * np.pi * t / 50)
    noise = np.zeros(n)
    shocks = rng.normal(0.0, 40.0, n)
    for i in range(1, n):  # autocorrelated: the effective hours are a quarter of the hours
        noise[i] = 0.7 * noise[i - 1] + shocks[i]
    J = np.column_stack([roof, wall])
    z_true = np.array([0.3, -0.2])
    intercept = -(J - J.mean(0)) @ z_true - 0.35 * (air - air.mean()) + noise
    return J, air, intercept, z_true


NAMES = ["construction/Roof/resistance", "construction/Wall/resistance"]
AIR = {"label": "infiltration/building/factor", "rel_std": 0.4, "parameters": ["x"]}


def test_an_uncertain_input_is_the_exact_marginal_of_a_nuisance_parameter():
    """An input held nominal whose signature is nearly the roof's, and autocorrelated noise:
    the posterior of the calibrated parameters is the z-marginal of the joint Gaussian with
    the input as one more parameter of prior variance s^2 (the dense joint posterior, not the
    Woodbury form the code uses). The data hardly constrain the input here, so its prior
    variance sets the roof's width: a variance off by the effective-hours ratio (x4.3) or its
    inverse fails the comparison."""
    J, air, intercept, _ = _roof_wall_and_air(strongly_like_the_roof=True)
    nominal = np.array([3.0, 2.0])
    surrogate = _series_model(J, intercept, NAMES, nominal)
    lower, upper = nominal * np.exp(-3.0), nominal * np.exp(3.0)
    s2 = 0.385**2
    mean, std = _joint_posterior_with_nuisance(J, intercept, -air, s2)

    def matches(variance):
        post = calibration_posterior(
            surrogate, NAMES, lower, upper, steps=3000, seed=4, uncertain=[(AIR, -air, variance)]
        )
        z = np.log(post.samples.to_numpy() / nominal)
        same = np.allclose(z.mean(0), mean, atol=0.15 * std)
        return same and np.allclose(z.std(0), std, rtol=0.15), post

    exact, post = matches(s2)
    assert exact
    assert not matches(4.3 * s2)[0] and not matches(s2 / 4.3)[0]
    # the roof compensates the input: set by the input's prior, not called determined
    (item,) = post.uncertain
    assert item["effect"] and list(item["compensates"]) == ["construction/Roof/resistance"]
    assert not post.summary.at["construction/Roof/resistance", "determined"]
    assert post.summary.at["construction/Wall/resistance", "determined"]
    words = " ".join(post.sentences())
    assert "compensate each other" in words and "pressurisation test" in words


def test_an_uncertain_input_the_data_resolve_moves_the_roof_interval_onto_its_truth():
    """The air change also has a signature of its own (the data resolve it): taken as exact
    (held nominal) it biases the roof's interval off its truth; given as uncertain, the
    interval covers the truth and the roof stays determined (the data, not the prior, fix it)."""
    J, air, intercept, z_true = _roof_wall_and_air(strongly_like_the_roof=False)
    nominal = np.array([3.0, 2.0])
    surrogate = _series_model(J, intercept, NAMES, nominal)
    lower, upper = nominal * np.exp(-3.0), nominal * np.exp(3.0)
    plain = calibration_posterior(surrogate, NAMES, lower, upper, steps=3000, seed=4)
    post = calibration_posterior(
        surrogate, NAMES, lower, upper, steps=3000, seed=4, uncertain=[(AIR, -air, 0.385**2)]
    )
    truth = nominal * np.exp(z_true)

    def roof_covers(p):
        row = p.summary.loc["construction/Roof/resistance"]
        return row["q05"] <= truth[0] <= row["q95"]

    assert not roof_covers(plain) and roof_covers(post)
    assert post.uncertain[0]["compensates"] == {}
    assert post.summary["determined"].all()
    assert "did not vary" in " ".join(post.sentences())


def test_a_measured_parameter_stays_determined_when_it_compensates_an_uncertain_input():
    """A plate on the roof (2 %) fixes it whatever the input does: determined, and said so."""
    J, air, intercept, _ = _roof_wall_and_air(strongly_like_the_roof=True)
    nominal = np.array([3.0, 2.0])
    surrogate = _series_model(J, intercept, NAMES, nominal)
    lower, upper = nominal * np.exp(-3.0), nominal * np.exp(3.0)
    post = calibration_posterior(
        surrogate, NAMES, lower, upper, steps=2000, seed=4, uncertain=[(AIR, -air, 0.385**2)],
        measured={"construction/Roof/resistance": (4.0, 0.02)},
    )  # fmt: skip
    assert post.summary.at["construction/Roof/resistance", "determined"]


def test_an_uncertain_input_without_effect_is_named_and_left_out():
    J, air, intercept, _ = _roof_wall_and_air(strongly_like_the_roof=False)
    nominal = np.array([3.0, 2.0])
    surrogate = _series_model(J, intercept, NAMES, nominal)
    lower, upper = nominal * np.exp(-3.0), nominal * np.exp(3.0)
    flat = np.full(len(air), 7.0)  # a constant change: the unknown gains take it
    post = calibration_posterior(
        surrogate, NAMES, lower, upper, steps=1000, seed=4, uncertain=[(AIR, flat, 0.385**2)]
    )
    plain = calibration_posterior(surrogate, NAMES, lower, upper, steps=1000, seed=4)
    assert post.uncertain[0]["effect"] is False
    words = " ".join(post.sentences())
    assert "does not change the unoccupied heat" in words and "did not vary" not in words
    assert np.allclose(post.summary["q95"], plain.summary["q95"])
