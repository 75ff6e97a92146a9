"""Profile-likelihood intervals against brute-force profiles (Nelder-Mead over the others)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy import optimize

from thermocal.statespace import RCModel
from thermocal.statespace.estimation import LikelihoodProblem, simulate_stochastic


def one_state() -> RCModel:
    m = RCModel("Ti")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.1)
    m.add_conductance("Ti", "Ta", conductance="H")
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    m.add_parameter("Ci", 3.0, unit="MJ/K", lower=0.01, upper=100)
    m.add_parameter("H", 150.0, unit="W/K")
    m.add_parameter("si", 0.2, unit="K/sqrt(h)")
    m.add_parameter("e", 0.1, unit="K")
    m.add_parameter("Ti0", 20.0, unit="C", lower=0, upper=40)
    m.add_derived("tau_h", "Ci / H / 0.0036", unit="h")  # MJ/K / (W/K) = 1e6 s
    return m


@pytest.fixture(scope="module")
def fitted():
    rng = np.random.default_rng(4)
    n = 120
    hours = np.arange(n)
    df = pd.DataFrame(
        {"Ta": 4 + 3 * np.sin(hours / 24 * 2 * np.pi), "Ph": 2500.0 * (rng.uniform(size=n) > 0.5)},
        index=pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC"),
    )
    df["y"] = simulate_stochastic(one_state(), df, seed=5)["y"]
    return one_state().fit(df, stall_tolerance=1e-6)


def brute_profile(res, fix) -> float:
    """max over the other unconstrained parameters of the log-likelihood, the profiled quantity
    imposed by ``fix(theta_rest) -> full theta``: Nelder-Mead from the ML estimates, twice."""
    problem = LikelihoodProblem(res.model, res.data, False)
    x = np.delete(res.theta, 0)
    for _ in range(2):
        out = optimize.minimize(
            lambda r: -problem.loglike(fix(r)), x, method="Nelder-Mead",
            options={"xatol": 1e-9, "fatol": 1e-11, "maxiter": 40000, "maxfev": 40000},
        )  # fmt: skip
        x = out.x
    return -out.fun


def check_interval(res, interval, brute_at):
    threshold = interval["threshold"]
    assert threshold == pytest.approx(res.loglike - 1.920729, abs=1e-5)
    lo, hi, est = interval["lower"], interval["upper"], interval["estimate"]
    assert lo < est < hi and not interval["open_lower"] and not interval["open_upper"]
    for end in (lo, hi):
        assert brute_at(end) == pytest.approx(threshold, abs=0.01)
    width = hi - lo
    assert brute_at(lo + 0.03 * width) > threshold > brute_at(lo - 0.03 * width)
    assert brute_at(hi - 0.03 * width) > threshold > brute_at(hi + 0.03 * width)


def test_profile_interval_of_a_parameter_matches_brute_force(fitted):
    res = fitted
    ci = res.profile_interval("Ci")
    ci_param = res.model.parameters["Ci"]

    def brute_at(value):
        t = ci_param.to_unconstrained(value)
        return brute_profile(res, lambda r: np.concatenate([[t], r]))

    check_interval(res, ci, brute_at)
    # asymmetric like the likelihood, and close to the Wald interval on the log scale
    wald = res.conf_int().loc["Ci"]
    assert ci["lower"] == pytest.approx(wald["lower"], rel=0.15)
    assert ci["upper"] == pytest.approx(wald["upper"], rel=0.15)


def test_profile_interval_of_a_derived_quantity_matches_brute_force(fitted):
    res = fitted
    tau = res.profile_interval("tau_h")
    names = res.model.free_parameter_names
    pars = [res.model.parameters[n] for n in names]

    def brute_at(value):
        def fix(r):  # Ci from the constraint Ci / H / 0.0036 = value
            h = pars[1].from_unconstrained(r[0])
            return np.concatenate([[pars[0].to_unconstrained(value * 0.0036 * h)], r])

        return brute_profile(res, fix)

    check_interval(res, tau, brute_at)
    table = res.profile_intervals(["H", "tau_h"])
    assert table.loc["tau_h", "lower"] == pytest.approx(tau["lower"], rel=1e-6)
    assert table.loc["H", "lower"] < res.params["H"] < table.loc["H", "upper"]
