"""The series meta-model: the metric as the variance of a linearly predicted heat series."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.calibration.surrogate import SeriesSurrogate, SVRSurrogate


def _campaign(n=60, d=12, hours=200, seed=0):
    """Series affine in the log-parameters (3 of 12 matter), plus within-hour variance."""
    rng = np.random.default_rng(seed)
    names = [f"p{i}" for i in range(d)]
    nominal = dict.fromkeys(names, 1.0)
    X = pd.DataFrame(np.exp(rng.uniform(-0.5, 0.5, size=(n, d))), columns=names)
    t = np.arange(hours)
    base = 300.0 + 50.0 * np.sin(2 * np.pi * t / 24)
    jac = np.zeros((d, hours))
    jac[0] = 400.0 * np.sin(2 * np.pi * t / 24)  # follows the weather
    jac[3] = 250.0 * np.cos(2 * np.pi * t / 60)
    jac[7] = 150.0 * (t > 100)
    Z = np.log(X.to_numpy())
    series = base + Z @ jac + rng.normal(0, 2.0, size=(n, hours))
    within = 40.0**2
    y = series.var(axis=1) + within
    return X, y, series, nominal, (base, jac, within)


def test_series_metamodel_predicts_the_variance_of_the_true_series():
    X, y, series, nominal, (base, jac, within) = _campaign()
    model = SeriesSurrogate(series=series, nominal=nominal, cv_folds=5, seed=1).fit(X, y)
    assert model.cv_r2_ > 0.97
    # brute force at new points: the variance of the noise-free series plus the within part
    rng = np.random.default_rng(5)
    new = pd.DataFrame(np.exp(rng.uniform(-0.5, 0.5, size=(20, X.shape[1]))), columns=X.columns)
    truth = (base + np.log(new.to_numpy()) @ jac).var(axis=1) + within
    np.testing.assert_allclose(model.predict(new), truth, rtol=0.05)
    assert model.within_hour_ == pytest.approx(within, rel=1e-9)
    # the generic regression of the scalar metric does far worse from the same samples
    svr = SVRSurrogate(cv_folds=5, seed=1).fit(X, y)
    assert svr.cv_r2_ < model.cv_r2_ - 0.2


def test_series_metamodel_bad_input():
    X, y, series, nominal, _ = _campaign(n=20)
    from thermocal.errors import ThermocalInputError

    with pytest.raises(ThermocalInputError, match="20 series for 19 samples"):
        SeriesSurrogate(series=series, nominal=nominal).fit(X.iloc[:19], y[:19])
    with pytest.raises(ThermocalInputError, match="no predictive std"):
        SeriesSurrogate(series=series, nominal=nominal, cv_folds=0).fit(X, y).predict(
            X, return_std=True
        )
