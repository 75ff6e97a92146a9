"""Smoothing, k-step prediction, residual diagnostics, likelihood-ratio test, forward selection."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy import stats
from statespace_reference import dense_moments
from test_statespace_kalman import random_data, three_state_model

from thermocal.statespace import RCModel
from thermocal.statespace.diagnostics import (
    autocorrelation,
    cumulated_periodogram,
    fraction_outside_band,
    likelihood_ratio_test,
)
from thermocal.statespace.estimation import simulate_stochastic
from thermocal.statespace.selection import forward_selection


@pytest.mark.parametrize("hold", ["zoh", "foh"])
def test_rts_smoother_equals_dense_conditional_mean(hold):
    model = three_state_model()
    df = random_data(40, seed=4, irregular=True)
    res = model.evaluate(df, hold=hold)
    sm = res.smooth()
    prep, xmean, xcov, ymean, ycov, xycov = dense_moments(model, df, hold)
    y = prep.Y.ravel()
    obs = np.isfinite(y)
    gain = np.linalg.solve(ycov[np.ix_(obs, obs)], xycov[:, obs].T).T
    x_cond = xmean + gain @ (y[obs] - ymean[obs])
    cov_cond = xcov - gain @ xycov[:, obs].T
    n = len(model.state_names)
    np.testing.assert_allclose(sm[model.state_names].to_numpy().ravel(), x_cond, atol=1e-8)
    std = np.sqrt(np.diag(cov_cond)).reshape(-1, n)
    np.testing.assert_allclose(sm[[f"{s}_std" for s in model.state_names]].to_numpy(), std,
                               rtol=1e-6)  # fmt: skip


@pytest.mark.parametrize("steps", [1, 3])
def test_k_step_prediction_equals_dense_conditional(steps):
    model = three_state_model()
    df = random_data(30, seed=6)
    res = model.evaluate(df)
    pred = res.predict(steps=steps)
    prep, _, _, ymean, ycov, _ = dense_moments(model, df)
    ny = len(model.output_names)
    y = prep.Y.ravel()
    for t in (steps + 2, 17, 29):
        past = np.zeros_like(y, dtype=bool)
        past[: (t - steps + 1) * ny] = True
        past &= np.isfinite(y)
        target = slice(t * ny, (t + 1) * ny)
        K = np.linalg.solve(ycov[np.ix_(past, past)], ycov[past, target]).T
        mean = ymean[target] + K @ (y[past] - ymean[past])
        cov = ycov[target, target] - K @ ycov[past, target]
        np.testing.assert_allclose(pred[model.output_names].iloc[t].to_numpy(), mean, atol=1e-8)
        np.testing.assert_allclose(
            pred[[f"{c}_std" for c in model.output_names]].iloc[t].to_numpy(),
            np.sqrt(np.diag(cov)),
            rtol=1e-6,
        )
    assert pred.iloc[:steps].isna().all().all()
    if steps == 1:
        one = res.one_step_residuals()
        np.testing.assert_allclose(pred["yTi"].iloc[1:], one["yTi_pred"].iloc[1:], atol=1e-10)


def test_acf_and_cumulated_periodogram_against_definitions():
    rng = np.random.default_rng(1)
    n = 2000
    white = rng.normal(size=n)
    ar = np.zeros(n)
    for k in range(1, n):
        ar[k] = 0.7 * ar[k - 1] + white[k]
    acf = autocorrelation(ar, nlags=5)
    assert acf["acf"].iloc[0] == 1.0
    assert acf["acf"].iloc[1] == pytest.approx(0.7, abs=0.04)
    assert acf["acf"].iloc[2] == pytest.approx(0.49, abs=0.05)
    assert acf["bound"].iloc[0] == pytest.approx(1.96 / np.sqrt(n), rel=1e-3)
    e = ar - ar.mean()
    brute = np.sum(e[:-3] * e[3:]) / np.sum(e * e)
    assert acf["acf"].iloc[3] == pytest.approx(brute, rel=1e-12)
    # white noise: ~95 % of the lags inside the bound, periodogram inside its band
    acf_w = autocorrelation(white, nlags=100)
    assert (acf_w["acf"].iloc[1:].abs() > acf_w["bound"].iloc[0]).mean() < 0.12
    cp_w = cumulated_periodogram(white)
    assert fraction_outside_band(cp_w) == 0.0
    assert cp_w["cumulated"].iloc[-1] == pytest.approx(1.0)
    # the AR(1) process has its power at low frequencies: far outside the band
    assert fraction_outside_band(cumulated_periodogram(ar)) > 0.5
    # periodogram ordinates by brute-force DFT
    cp = cumulated_periodogram(white[:101])
    e = white[:101] - white[:101].mean()
    t = np.arange(101)
    ords = [abs(np.sum(e * np.exp(-2j * np.pi * j * t / 101))) ** 2 for j in range(1, 51)]
    np.testing.assert_allclose(cp["cumulated"], np.cumsum(ords) / np.sum(ords), rtol=1e-10)


def test_acf_with_missing_residuals_keeps_the_lags_on_the_grid():
    """Missing residuals (unobserved outputs) must not shift the lags: an AR(1) series with
    30 % of its values missing still shows acf(1) = 0.7 (dropping the gaps would mix lags)."""
    rng = np.random.default_rng(5)
    n = 6000
    ar = np.zeros(n)
    for k in range(1, n):
        ar[k] = 0.7 * ar[k - 1] + rng.normal()
    e = ar.copy()
    e[rng.uniform(size=n) < 0.3] = np.nan
    acf = autocorrelation(e, nlags=3)
    assert acf["acf"].iloc[1] == pytest.approx(0.7, abs=0.05)
    assert acf["acf"].iloc[2] == pytest.approx(0.49, abs=0.05)
    finite = np.isfinite(e)
    # brute force: mean product over the pairs where both residuals exist
    d = e - np.nanmean(e)
    pairs = [d[t] * d[t + 2] for t in range(n - 2) if finite[t] and finite[t + 2]]
    brute = (1 - 2 / n) * np.mean(pairs) / np.nanmean(d * d)
    assert acf["acf"].iloc[2] == pytest.approx(brute, rel=1e-12)
    assert acf["bound"].iloc[2] == pytest.approx(1.96 / np.sqrt(len(pairs) * n / (n - 2)), rel=1e-3)
    # white noise with the same gaps: about 5 % of the lags outside their bounds
    white = rng.normal(size=n)
    white[~finite] = np.nan
    acf_w = autocorrelation(white, nlags=200)
    outside = (acf_w["acf"].abs() > acf_w["bound"]).iloc[1:].mean()
    assert 0.01 < outside < 0.10


def one_state(fix_h: bool) -> RCModel:
    m = RCModel("one_state_fixed_H" if fix_h else "one_state")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.2)
    m.add_conductance("Ti", "Ta", conductance="H")
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    m.add_parameter("Ci", 5.0, unit="MJ/K")
    m.add_parameter("H", 150.0, unit="W/K", fixed=fix_h)
    m.add_parameter("si", 0.2, unit="K/sqrt(h)")
    m.add_parameter("e", 0.1, unit="K")
    m.add_parameter("Ti0", 20.0, unit="C")
    return m


def test_likelihood_ratio_statistic_is_chi2_under_the_null():
    """60 data sets from the restricted model (H at its true value): the LR statistic of
    'H free' against 'H fixed' follows chi2(1): mean ~1, rejection rate at 5 % ~5 %."""
    restricted, general = one_state(True), one_state(False)
    rng = np.random.default_rng(0)
    n = 200
    t = pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC")
    base = pd.DataFrame({"Ta": 3 + rng.normal(0, 2, n), "Ph": 3000.0 * (rng.uniform(size=n) > 0.5)},
                        index=t)  # fmt: skip
    stats_ = []
    for rep in range(60):
        d = base.copy()
        d["y"] = simulate_stochastic(restricted, base, seed=rep)["y"]
        test = likelihood_ratio_test(restricted.fit(d, n_starts=1), general.fit(d, n_starts=1))
        assert test.df == 1
        assert test.statistic > -1e-6
        assert test.pvalue == pytest.approx(stats.chi2.sf(max(test.statistic, 0), 1))
        stats_.append(test.statistic)
    stats_ = np.array(stats_)
    # chi2(1) has mean 1 and sd sqrt(2): the mean of 60 draws is within 1 +- 4 sqrt(2/60)
    assert abs(stats_.mean() - 1.0) < 4 * np.sqrt(2 / 60)
    rejections = int((stats_ > stats.chi2.ppf(0.95, 1)).sum())
    assert rejections <= stats.binom.ppf(0.999, 60, 0.05)
    # the Kolmogorov-Smirnov test does not reject chi2(1)
    assert stats.kstest(stats_, stats.chi2(1).cdf).pvalue > 0.001


def test_forward_selection_finds_the_second_state():
    """Data from a two-state model: starting from one state, forward selection accepts the
    envelope state and rejects a further split of the heat input."""
    truth = RCModel("TiTe")
    truth.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.2)
    truth.add_state("Te", capacity="Ce", noise="se", initial_mean="Te0", initial_std=1.0)
    truth.add_conductance("Ti", "Te", conductance="Hie")
    truth.add_conductance("Te", "Ta", conductance="Hea")
    truth.add_heat_input("Ph", into="Ti")
    truth.add_output("y", state="Ti", noise="e")
    for name, value, unit in [("Ci", 2.0, "MJ/K"), ("Ce", 30.0, "MJ/K"), ("Hie", 400.0, "W/K"),
                              ("Hea", 150.0, "W/K"), ("si", 0.1, "K/sqrt(h)"),
                              ("se", 0.05, "K/sqrt(h)"), ("e", 0.05, "K"), ("Ti0", 20.0, "C"),
                              ("Te0", 12.0, "C")]:  # fmt: skip
        truth.add_parameter(name, value, unit=unit)
    split = truth.copy()
    split.name = "TiTe_split"
    split._heat_inputs = [{"column": "Ph", "into": {"Ti": "f", "Te": "rest"}, "scale": None,
                           "unit": "W"}]  # fmt: skip
    split.add_parameter("f", 0.9, unit="-", lower=0, upper=1)
    one = one_state(False)
    one.name = "Ti"
    rng = np.random.default_rng(3)
    n = 400
    t = pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC")
    data = pd.DataFrame({"Ta": 3 + 3 * np.sin(np.arange(n) / 24 * 2 * np.pi),
                         "Ph": 3000.0 * (rng.uniform(size=n) > 0.5)}, index=t)  # fmt: skip
    data["y"] = simulate_stochastic(truth, data, seed=3)["y"]
    start = truth.with_parameters({"Ci": 1.0, "Ce": 10.0, "Hie": 200.0, "Hea": 100.0})
    split = split.with_parameters({"Ci": 1.0, "Ce": 10.0, "Hie": 200.0, "Hea": 100.0})
    result = forward_selection(
        {"Ti": one, "TiTe": start, "TiTe_split": split},
        {"Ti": ["TiTe"], "TiTe": ["TiTe_split"]},
        data,
        start="Ti",
        seed=0,
    )
    assert result.path == ["Ti", "TiTe"]
    assert result.selected == "TiTe"
    table = result.table.set_index("model")
    assert table.loc["TiTe", "pvalue"] < 1e-6
    assert table.loc["TiTe_split", "pvalue"] > 0.001
    assert not table.loc["TiTe_split", "accepted"]
    # the split model nests TiTe (f = 1, on its bound): its optimum is not lower, up to the
    # optimiser's stall tolerance for a parameter creeping towards a bound
    assert table.loc["TiTe_split", "loglike"] >= table.loc["TiTe", "loglike"] - 0.01


def test_distribution_functions_equal_scipy_stats_and_select_does_not_import_it():
    """The engine's chi-squared and normal functions are scipy.stats' own numbers, and the
    commands' modules no longer import scipy.stats (1.5-2.5 s of start-up)."""
    import subprocess
    import sys

    from scipy import stats

    from thermocal.statespace.distributions import chi2_quantile, chi2_sf, normal_quantile

    for p in (0.5, 0.9, 0.95, 0.975, 0.995):
        assert normal_quantile(p) == stats.norm.ppf(p)
        for df in (1, 2, 4, 20):
            assert chi2_quantile(p, df) == stats.chi2.ppf(p, df)
    for x in (0.0, 1e-9, 0.9, 3.84, 31.2, 138.8, 2000.0):
        for df in (1, 4, 20):
            assert chi2_sf(x, df) == stats.chi2.sf(x, df)
    code = (
        "import sys, thermocal.cli, thermocal.commands.select, thermocal.commands.fit, "
        "thermocal.statespace.diagnostics, thermocal.statespace.profile, "
        "thermocal.statespace.checks; print('scipy.stats' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_forward_selection_names_at_their_old_place_are_deprecated_aliases():
    import thermocal.statespace.diagnostics as diagnostics
    from thermocal.statespace import selection

    with pytest.warns(DeprecationWarning, match="moved to thermocal.statespace.selection"):
        assert diagnostics.forward_selection is selection.forward_selection
    with pytest.raises(AttributeError):
        diagnostics.no_such_name  # noqa: B018
