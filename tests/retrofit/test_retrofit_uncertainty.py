"""Uncertainty propagation of the retrofit workflow: parameter draws from the estimated
covariance (declared units -> SI, truncated at the estimation bounds) and intervals of the
savings from paired draws, checked against brute force."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from thermocal.retrofit.calibration import Calibration, draw_parameters
from thermocal.retrofit.demand import DemandResult
from thermocal.retrofit.model import ESTIMATED_PARAMETERS
from thermocal.retrofit.outputs import scenario_table
from thermocal.retrofit.strategies import all_strategies

NAMES = list(ESTIMATED_PARAMETERS)  # H_est [W/K], then capacities [MJ/K]
#: (lower, initial, upper, unit) as FifthOrderModel.estimated
BOUNDS = {
    "H_est": (10.0, 100.0, 600.0, "W/K"),
    "C_env": (5.0, 35.0, 160.0, "MJ/K"),
    "C_gf": (1.6, 14.0, 40.0, "MJ/K"),
    "C_im": (2.0, 17.0, 90.0, "MJ/K"),
    "C_i": (0.7, 2.2, 9.0, "MJ/K"),
    "C_h": (0.06, 0.4, 3.3, "MJ/K"),
}
SI = np.array([1.0 if BOUNDS[n][3] == "W/K" else 1e6 for n in NAMES])


def _calibration(mean_declared, sd_declared, corr) -> Calibration:
    mean = np.asarray(mean_declared, float) * SI
    sd = np.asarray(sd_declared, float) * SI
    cov = corr * np.outer(sd, sd)
    empty = pd.Series(dtype=float)
    return Calibration(
        estimates_si=dict(zip(NAMES, mean, strict=True)), cov_si=cov, params=empty, bse=empty,
        correlation=pd.DataFrame(corr, index=NAMES, columns=NAMES), loglike=0.0, aic=0.0,
        bic=0.0, converged=True, flags=[], x0=np.zeros(5), fit_seconds=0.0,
    )  # fmt: skip


def _corr():
    corr = np.eye(6)
    corr[0, 1] = corr[1, 0] = 0.6  # H_est, C_env
    corr[2, 3] = corr[3, 2] = -0.5  # C_gf, C_im
    return corr


def test_draws_reproduce_mean_and_covariance_in_si():
    model = SimpleNamespace(estimated=BOUNDS)
    mean = [150.0, 60.0, 15.0, 30.0, 3.0, 0.8]
    sd = [10.0, 5.0, 1.5, 3.0, 0.2, 0.05]  # far from every bound
    cal = _calibration(mean, sd, _corr())
    draws = draw_parameters(cal, model, 20000, seed=1)
    x = np.column_stack([draws[n] for n in NAMES])
    assert x.shape == (20001, 6)
    np.testing.assert_array_equal(x[0], np.asarray(mean) * SI)  # first row = estimate
    body = x[1:]
    se = np.asarray(sd) * SI / np.sqrt(len(body))
    assert np.all(np.abs(body.mean(axis=0) - np.asarray(mean) * SI) < 4.5 * se)
    np.testing.assert_allclose(body.std(axis=0), np.asarray(sd) * SI, rtol=0.03)
    np.testing.assert_allclose(np.corrcoef(body.T), _corr(), atol=0.03)


def test_draws_at_a_bound_are_the_truncated_normal():
    """C_gf estimated at its upper bound: the draws follow the truncated multivariate normal
    (brute force: rejection from the untruncated one), never leave the bounds."""
    model = SimpleNamespace(estimated=BOUNDS)
    mean = [150.0, 60.0, 40.0, 30.0, 3.0, 0.8]
    sd = [10.0, 5.0, 1.5, 3.0, 0.2, 0.05]
    cal = _calibration(mean, sd, _corr())
    draws = draw_parameters(cal, model, 20000, seed=2)
    x = np.column_stack([draws[n] for n in NAMES])[1:]
    lo = np.array([BOUNDS[n][0] for n in NAMES]) * SI
    hi = np.array([BOUNDS[n][2] for n in NAMES]) * SI
    assert np.all((x >= lo) & (x <= hi))
    rng = np.random.default_rng(99)
    brute = rng.multivariate_normal(np.asarray(mean) * SI, cal.cov_si, size=200000)
    brute = brute[np.all((brute >= lo) & (brute <= hi), axis=1)]
    for i in (2, 3):  # C_gf (half-normal below 40) and C_im, pulled up by r = -0.5
        q_draw = np.quantile(x[:, i], [0.05, 0.5, 0.95])
        q_brute = np.quantile(brute[:, i], [0.05, 0.5, 0.95])
        np.testing.assert_allclose(q_draw, q_brute, atol=0.05 * sd[i] * SI[i] * 2)
    # the C_im shift from truncating C_gf is real and reproduced (not just the estimate)
    assert np.mean(x[:, 3]) - mean[3] * 1e6 == pytest.approx(
        np.mean(brute[:, 3]) - mean[3] * 1e6, abs=0.06 * sd[3] * 1e6
    )


def _analysis(annual: np.ndarray, interval: float = 0.9):
    """An analysis stand-in with the annual demand (S, D+1) spread evenly over 12 months."""
    monthly = np.repeat(annual[..., None] / 12.0, 12, axis=-1)
    index = pd.date_range("2001-01-01", periods=8760, freq="h", tz="Etc/GMT+5")
    return SimpleNamespace(
        config=SimpleNamespace(uncertainty=SimpleNamespace(interval=interval)),
        demand=DemandResult(monthly, np.zeros((annual.shape[0], 8760)), index),
        strategies=all_strategies(),
    )


def test_saving_intervals_come_from_paired_draws():
    """Every strategy scales the baseline of the same draw: the saving is then certain even
    though each demand is uncertain; unpaired quantiles would give a wide saving interval."""
    rng = np.random.default_rng(5)
    base = np.concatenate([[20000.0], rng.normal(20000.0, 3000.0, 400)])
    keep = np.linspace(1.0, 0.5, 16)  # strategy i keeps this fraction of the demand
    table = scenario_table(_analysis(keep[:, None] * base[None, :]))
    np.testing.assert_allclose(table["saving_pct"], 100.0 * (1.0 - keep), atol=1e-9)
    np.testing.assert_allclose(table["saving_pct_p05"], 100.0 * (1.0 - keep), atol=1e-9)
    np.testing.assert_allclose(table["saving_pct_p95"], 100.0 * (1.0 - keep), atol=1e-9)
    # the demand intervals are the draws' quantiles (brute force), not the estimate +- sd
    for i in (0, 7, 15):
        d = keep[i] * base[1:]
        assert table["annual_kWh_p05"][i] == pytest.approx(np.quantile(d, 0.05))
        assert table["annual_kWh_p95"][i] == pytest.approx(np.quantile(d, 0.95))


def test_interval_level_follows_the_configuration():
    rng = np.random.default_rng(6)
    base = np.concatenate([[20000.0], rng.normal(20000.0, 3000.0, 400)])
    other = base * rng.normal(0.7, 0.05, base.size)
    annual = np.vstack([base] + [other] * 15)
    sv = 100.0 * (1.0 - other[1:] / base[1:])
    table = scenario_table(_analysis(annual, interval=0.5))
    assert table["saving_pct_p05"][4] == pytest.approx(np.quantile(sv, 0.25))
    assert table["saving_pct_p95"][4] == pytest.approx(np.quantile(sv, 0.75))


def test_interval_labels_of_the_report():
    from thermocal.retrofit.outputs import _interval_labels

    assert _interval_labels(0.9) == ("p05", "p95")
    assert _interval_labels(0.8) == ("p10", "p90")
    assert _interval_labels(0.95) == ("p2.5", "p97.5")
