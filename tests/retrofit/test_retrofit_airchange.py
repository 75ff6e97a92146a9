"""The air change's stack term (``thermocal.retrofit.airchange``, issue 25 item 1).

Truths we did not make: a steady-state house whose air-change conductance grows linearly with
the indoor-outdoor difference (the design-flow-rate infiltration of EnergyPlus with a ``B``
coefficient) has daily heat residuals, against the same house with a constant conductance,
of exactly ``k dT (dT - dT0)``; and the demand of that house, hour by hour, is the brute-force
answer the adjusted demand must reproduce."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.retrofit.airchange import (
    adjust_demand,
    air_change_summary,
    estimate_slope,
    stack_prior,
)
from thermocal.retrofit.demand import DemandResult


def _weather(days: int, seed: int = 3) -> pd.Series:
    idx = pd.date_range("2015-02-01", periods=24 * days, freq="h", tz="Europe/Zurich")
    rng = np.random.default_rng(seed)
    day = np.repeat(rng.normal(0.0, 4.0, days), 24)  # synoptic swings [K]
    hour = -3.0 * np.cos(2 * np.pi * (idx.hour.to_numpy() - 3) / 24)
    return pd.Series(-2.0 + day + hour, index=idx)


def test_stack_coefficient_recovered_from_the_residuals():
    """H(dT) = 40 + 1.3 (dT - dT0) W/K of air change plus 150 W/K of transmission; the model
    with the calibrated constant 40 W/K: the data's k is 1.3 W/K^2 (2 % meter noise)."""
    te = _weather(28)
    ti = pd.Series(20.0, index=te.index)
    dt = ti - te
    dt0 = float(dt.mean())
    k_true = 1.3
    truth = (150.0 + 40.0 + k_true * (dt - dt0)) * dt
    rng = np.random.default_rng(0)
    measured = truth * (1.0 + 0.02 * rng.normal(size=len(truth)))
    model = (150.0 + 40.0) * dt
    fit = estimate_slope(measured, model, ti, te, h_est=40.0)
    assert fit["k_data"] == pytest.approx(k_true, rel=0.05)
    assert fit["k_data_std"] < 0.1 * k_true
    assert fit["applied"]
    # the precise data dominate the prior (k_s / 2 = 40 / (4 dT0))
    assert fit["k_prior"] == pytest.approx(40.0 / (4.0 * dt0))
    assert fit["k_W_per_K2"] == pytest.approx(k_true, rel=0.06)
    assert "applied" in air_change_summary(fit)


def test_no_information_in_the_data_gives_the_prior_and_a_contradiction_is_not_applied():
    te = _weather(28)
    ti = pd.Series(20.0, index=te.index)
    dt = ti - te
    rng = np.random.default_rng(1)
    model = 190.0 * dt
    noisy = model + rng.normal(0.0, 3000.0, len(dt))  # residuals unrelated to dT
    fit = estimate_slope(noisy, model, ti, te, h_est=40.0)
    k_p, s_p = stack_prior(40.0, fit["dT0_K"])
    assert abs(fit["k_W_per_K2"] - k_p) < 0.5 * s_p
    assert fit["k_std"] <= s_p
    # a house whose air change shrinks with dT contradicts the stack effect: not applied
    falling = (190.0 - 3.0 * (dt - dt.mean())) * dt
    fit = estimate_slope(falling, model, ti, te, h_est=40.0)
    assert fit["k_data"] < 0 and not fit["applied"]
    assert "not applied" in air_change_summary(fit)


def test_adjusted_demand_equals_the_brute_force_house():
    """A year of a steady-state house held at 20 C: demand with the constant conductance,
    adjusted, against the house with the growing one computed hour by hour."""
    idx = pd.date_range("2015-01-01", periods=8760, freq="h", tz="Europe/Zurich")
    doy = idx.day_of_year.to_numpy()
    te = pd.Series(9.0 - 9.0 * np.cos(2 * np.pi * (doy - 20) / 365), index=idx)
    dt = 20.0 - te.to_numpy()
    gains = 1500.0  # [W] free heat: no heating on mild hours
    hlc = np.array([[190.0], [120.0]])  # baseline and a retrofit (air change unchanged)
    k, dt0 = 1.2, 22.0
    base = np.maximum(hlc * dt[None, :] - gains, 0.0)  # (scenarios, hours) [W]
    month = idx.month.to_numpy() - 1
    monthly = np.stack([np.bincount(month, weights=q, minlength=12) / 1000.0 for q in base])
    demand = DemandResult(monthly[:, None, :], base, idx)
    slope = {"k_W_per_K2": k, "k_std": 0.0, "dT0_K": dt0, "applied": True}
    out = adjust_demand(demand, slope, te, 20.0)
    for s in range(2):
        heated = base[s] > 0
        brute = np.where(heated, np.maximum(base[s] + k * dt * (dt - dt0), 0.0), 0.0)
        want = np.bincount(month, weights=brute, minlength=12) / 1000.0
        np.testing.assert_allclose(out.monthly[s, 0], want, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(out.hourly[s], brute, atol=1e-9)
    # mild months lose heat, January (dT near dT0) barely changes
    assert out.monthly[0, 0, 4] < monthly[0, 4]
    assert abs(out.annual_kwh()[0, 0] / demand.annual_kwh()[0, 0] - 1.0) < 0.2
    # not applied: the same object
    assert adjust_demand(demand, {**slope, "applied": False}, te, 20.0) is demand


def test_draws_carry_the_coefficient_uncertainty():
    idx = pd.date_range("2015-01-01", periods=24 * 60, freq="h", tz="UTC")
    te = pd.Series(np.linspace(-5.0, 12.0, len(idx)), index=idx)
    q = np.maximum(200.0 * (20.0 - te.to_numpy()), 0.0)[None, :]
    month = idx.month.to_numpy() - 1
    monthly = np.bincount(month, weights=q[0], minlength=12)[None, None, :] / 1000.0
    demand = DemandResult(np.repeat(monthly, 400, axis=1), q, idx)
    slope = {"k_W_per_K2": 1.0, "k_std": 0.5, "dT0_K": 20.0, "applied": True}
    annual = adjust_demand(demand, slope, te, 20.0, seed=4).annual_kwh()[0]
    extra = annual - demand.annual_kwh()[0]
    # the change is linear in k: its spread over the draws is 0.5 of the first draw's
    assert np.std(extra[1:]) / abs(extra[0]) == pytest.approx(0.5, rel=0.15)


def test_daily_energy_keeps_the_days_of_the_clock_changes():
    # in a zone with clock changes the autumn day has 25 hours and the spring day 23: complete
    # days, kept (every day was taken as 24 hours and those two dropped from verify's and the
    # stack term's daily sums)
    from thermocal.retrofit.airchange import daily_energy

    for start, hours in (("2006-10-27", 25.0), ("2006-03-30", 23.0)):
        index = pd.date_range(start, periods=5 * 24, freq="1h", tz="America/Chicago")
        daily = daily_energy(pd.DataFrame({"heat": 1000.0}, index=index))
        assert set(daily["heat"]) == {24.0, hours}
    partial = pd.date_range("2006-01-01 06:00", periods=30, freq="1h", tz="UTC")
    assert daily_energy(pd.DataFrame({"heat": 1000.0}, index=partial)).empty
