"""Maximum-likelihood estimation: parameter recovery, interval coverage, results object."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from thermocal.statespace import FitResults, RCModel
from thermocal.statespace.estimation import simulate_stochastic

TRUTH = {
    "Ci": 2.0,
    "Ce": 20.0,
    "Hie": 300.0,
    "Hea": 200.0,
    "si": 0.1,
    "e": 0.1,
    "Ti0": 20.0,
}


def two_state_model(initial_std: float = 0.01) -> RCModel:
    """Envelope/indoor model: Ti -- Hie -- Te -- Hea -- Ta, heating into Ti, Ti observed."""
    m = RCModel("two_state")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=initial_std)
    m.add_state("Te", capacity="Ce", noise=0.0, initial_mean=10.0, initial_std=2.0)
    m.add_conductance("Ti", "Te", conductance="Hie")
    m.add_conductance("Te", "Ta", conductance="Hea")
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    units = {"Ci": "MJ/K", "Ce": "MJ/K", "Hie": "W/K", "Hea": "W/K", "si": "K/sqrt(h)"}
    units |= {"e": "K", "Ti0": "C"}
    for name, value in TRUTH.items():
        m.add_parameter(name, value, unit=units[name])
    return m


def inputs(n: int = 230, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    t = pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC")
    hours = np.arange(n)
    return pd.DataFrame(
        {
            "Ta": 5 + 3 * np.sin(hours / 24 * 2 * np.pi) + rng.normal(0, 0.5, n),
            "Ph": 3000.0 * (rng.uniform(size=n) > 0.5),  # PRBS-like heating
        },
        index=t,
    )


def test_coverage_of_95_percent_intervals():
    """100 simulated data sets: each Wald interval covers the truth with probability ~0.95.

    Acceptance: per parameter the count is inside the central 99.9 % binomial band of
    Bin(100, 0.95); pooled over the 7 parameters the rate is within [0.91, 0.99].
    """
    truth_model = two_state_model()
    start = truth_model.with_parameters(
        {"Ci": 1, "Ce": 10, "Hie": 200, "Hea": 100, "si": 0.3, "e": 0.3, "Ti0": 18}
    )
    base = inputs()
    n_rep = 100
    hits = {s: np.zeros((n_rep, len(TRUTH)), dtype=bool) for s in ("natural", "transformed")}
    estimates = np.zeros((n_rep, len(TRUTH)))
    for rep in range(n_rep):
        data = base.copy()
        data["y"] = simulate_stochastic(truth_model, base, seed=1000 + rep)["y"]
        res = start.fit(data, n_starts=1)  # coverage, not the multi-start search
        assert res.converged
        names = start.free_parameter_names
        for scale, h in hits.items():
            ci = res.conf_int(scale=scale)
            h[rep] = [ci.loc[n, "lower"] <= TRUTH[n] <= ci.loc[n, "upper"] for n in names]
            if scale == "transformed":  # positive parameters keep positive bounds
                assert (ci["lower"][[n for n in names if n != "Ti0"]] >= 0).all()
        estimates[rep] = res.params[names]
    lo = stats.binom.ppf(0.0005, n_rep, 0.95)
    for scale, h in hits.items():
        counts = h.sum(axis=0)
        assert np.all(counts >= lo), (scale, dict(zip(names, counts, strict=True)))
        assert 0.91 <= h.mean() <= 0.99, scale
    # estimates are centred on the truth (bias small against the spread)
    truth = np.array([TRUTH[n] for n in start.free_parameter_names])
    z = (estimates.mean(0) - truth) / (estimates.std(0) / np.sqrt(n_rep))
    assert np.all(np.abs(z[:4]) < 4.0), z  # capacities and conductances


def test_fit_results_interface_and_json(tmp_path):
    model = two_state_model(initial_std=0.5)
    data = inputs()
    data["y"] = simulate_stochastic(model, data, seed=7)["y"]
    res = model.with_parameters({"Ci": 1.0, "Hie": 150.0}).fit(data, n_starts=3, seed=1)
    assert isinstance(res, FitResults)
    assert res.converged
    assert list(res.params.index) == model.parameter_names
    assert len(res.start_loglikes) == 4  # 3 + the energy-balance start
    assert res.loglike == pytest.approx(max(res.start_loglikes), abs=1e-4)
    assert res.to_dict()["start_loglikes"] == pytest.approx(res.start_loglikes)
    assert "Optimiser starts (4)" in res.summary()
    cov = res.cov_params()
    assert list(cov.index) == model.free_parameter_names
    np.testing.assert_allclose(np.sqrt(np.diag(cov)), res.bse[model.free_parameter_names])
    assert np.allclose(np.diag(res.correlation), 1.0)
    assert res.nobs == 230
    k = model.n_free
    assert res.aic == pytest.approx(-2 * res.loglike + 2 * k)
    assert res.bic == pytest.approx(-2 * res.loglike + k * np.log(230))
    # the likelihood at the estimates, recomputed from scratch
    assert model.loglike(data, res.params.to_dict()) == pytest.approx(res.loglike, rel=1e-10)
    d = res.to_dict()
    json.dumps(d)
    for key in ("loglike", "aic", "bic", "nobs", "converged", "fit_seconds", "params"):
        assert key in d
    assert set(d["params"]["Ci"]) >= {"value", "std_error", "lower", "upper", "fixed"}
    assert d["correlation"]["names"] == model.free_parameter_names
    assert "Ci" in res.summary()


def test_bse_agrees_with_brute_force_hessian_in_declared_units():
    """Delta-method standard errors equal those from a Hessian taken directly in declared units."""
    model = two_state_model(initial_std=0.5)
    data = inputs(150, seed=3)
    data["y"] = simulate_stochastic(model, data, seed=3)["y"]
    res = model.fit(data)
    names = model.free_parameter_names
    x = res.params[names].to_numpy()
    h = 1e-4 * np.abs(x)

    def ll(v):
        return model.loglike(data, dict(zip(names, v, strict=True)))

    k = len(x)
    H = np.zeros((k, k))
    for i in range(k):
        for j in range(k):
            ei, ej = np.eye(k)[i] * h[i], np.eye(k)[j] * h[j]
            H[i, j] = (ll(x + ei + ej) - ll(x + ei - ej) - ll(x - ei + ej) + ll(x - ei - ej)) / (
                4 * h[i] * h[j]
            )
    bse = np.sqrt(np.diag(np.linalg.inv(-H)))
    np.testing.assert_allclose(res.bse[names].to_numpy(), bse, rtol=0.02)


def test_flags_correlated_pair_and_bound():
    """Two conductances in series through a state-less path are not separately identifiable:
    the fit flags the correlation (paper 000's |r| > 0.98 test)."""
    m = RCModel("series")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0")
    m.add_conductance("Ti", "Ta", conductance=["H1", "H2"])
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    m.add_parameter("Ci", 2.0, unit="MJ/K")
    m.add_parameter("H1", 300.0, unit="W/K", lower=1, upper=1e4)
    m.add_parameter("H2", 400.0, unit="W/K", lower=1, upper=1e4)
    m.add_parameter("si", 0.1, unit="K/sqrt(h)")
    m.add_parameter("e", 0.1, unit="K", lower=0.05, upper=1)
    m.add_parameter("Ti0", 20.0, unit="C")
    data = inputs(200, seed=2)
    truth = m.with_parameters({"e": 0.0500001})
    data["y"] = simulate_stochastic(truth, data, seed=2)["y"]
    res = m.fit(data)
    assert any("correlation(H1, H2)" in f or "not negative definite" in f for f in res.flags)


def test_unidentifiable_parameter_is_named_and_the_others_keep_standard_errors():
    """Two parallel conductances between the same nodes: only their sum is identifiable, so the
    information matrix is singular. The fit names one of them and still gives the capacity and the
    noise standard errors (conditional on the named one), equal to those of the model in which it
    is fixed at its estimate."""
    m = RCModel("parallel")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0")
    m.add_conductance("Ti", "Ta", conductance="H1")
    m.add_conductance("Ti", "Ta", conductance="H2")
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    m.add_parameter("Ci", 2.0, unit="MJ/K")
    m.add_parameter("H1", 300.0, unit="W/K", lower=1, upper=1e4)
    m.add_parameter("H2", 400.0, unit="W/K", lower=1, upper=1e4)
    m.add_parameter("si", 0.1, unit="K/sqrt(h)")
    m.add_parameter("e", 0.1, unit="K", lower=0.01, upper=1)
    m.add_parameter("Ti0", 20.0, unit="C")
    data = inputs(200, seed=4)
    data["y"] = simulate_stochastic(m, data, seed=4)["y"]
    res = m.fit(data, compute_hessian=True)
    singular = [f for f in res.flags if "not negative definite" in f]
    assert singular, res.flags
    named = "H1" if "along H1" in singular[0] else "H2"
    assert f"along {named}" in singular[0] and "conditional on it being fixed" in singular[0]
    assert np.isnan(res.bse[named])
    identified = ["Ci", "si", "e", "Ti0"]
    assert np.all(np.isfinite(res.bse[identified].to_numpy()))
    # brute force: numerical Hessian of the log-likelihood over the others, the named one fixed
    names = [n for n in m.free_parameter_names if n != named]
    x = res.params[names].to_numpy()
    h = 1e-4 * np.abs(x)

    def ll(v):
        return m.loglike(data, {**res.params.to_dict(), **dict(zip(names, v, strict=True))})

    k = len(x)
    H = np.zeros((k, k))
    for i in range(k):
        for j in range(k):
            ei, ej = np.eye(k)[i] * h[i], np.eye(k)[j] * h[j]
            H[i, j] = (ll(x + ei + ej) - ll(x + ei - ej) - ll(x - ei + ej) + ll(x - ei - ej)) / (
                4 * h[i] * h[j]
            )
    bse = pd.Series(np.sqrt(np.diag(np.linalg.inv(-H))), index=names)
    np.testing.assert_allclose(res.bse[identified], bse[identified], rtol=0.05)


def test_fixed_parameters_are_not_estimated():
    model = two_state_model(initial_std=0.5)
    data = inputs()
    data["y"] = simulate_stochastic(model, data, seed=11)["y"]
    fixed = model.with_parameters({"Ce": 25.0, "Hea": 210.0}, fix=True)
    res = fixed.fit(data)
    assert res.params["Ce"] == 25.0 and res.params["Hea"] == 210.0
    assert np.isnan(res.bse["Ce"])
    assert "Ce" not in res.cov_params().index
    assert res.n_free == model.n_free - 2


def test_random_starts_of_wide_positive_ranges_stay_near_the_declared_value():
    """A capacity declared 0.5 in [1e-4, 50]: uniform starts over the range would nearly all lie
    above 0.5 * 50 (two orders of magnitude off); the starts are log-normal around the declared
    value instead (median factor ~e^0.67), and narrow ranges stay uniform."""
    from thermocal.statespace.estimation import _start_points

    m = RCModel("one_state")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean=20.0)
    m.add_conductance("Ti", "Ta", conductance="Hie")
    m.add_output("y", state="Ti", noise=0.1)
    m.add_parameter("Ci", 0.5, unit="MJ/K", lower=1e-4, upper=50.0)
    m.add_parameter("Hie", 300.0, unit="W/K", lower=250.0, upper=350.0)
    m.add_parameter("si", 0.1, unit="K/sqrt(h)")
    starts = _start_points(m, 401, seed=1)[1:]
    free = m.free_parameter_names
    ci = np.array([m.parameters["Ci"].from_unconstrained(t[free.index("Ci")]) for t in starts])
    hie = np.array([m.parameters["Hie"].from_unconstrained(t[free.index("Hie")]) for t in starts])
    assert np.all((ci > 1e-4) & (ci < 50.0))
    assert np.median(np.abs(np.log(ci / 0.5))) == pytest.approx(0.674, abs=0.1)
    assert stats.kstest((hie - 251.0) / 98.0, "uniform").pvalue > 0.01


def test_exchange_pairs_of_the_bacher_madsen_models():
    """Only hidden, unheated states with a shared neighbour exchange roles; the swap covers
    capacities, noises, initial means and the paths to the shared node."""
    from pathlib import Path

    from thermocal.statespace.exchange import exchange_pairs, exchanged_values

    models = Path(__file__).resolve().parents[2] / "examples" / "models"
    pairs = {n: exchange_pairs(RCModel.from_yaml(models / f"{n}.yaml"))
             for n in ("Ti", "TiTe", "TiTeTh", "TiTmTeTh", "TiTmTeThRia")}  # fmt: skip
    swap = [("Cm", "Ce"), ("sigma_m", "sigma_e"), ("Tm0", "Te0"), ("Rim", "Rie")]
    assert pairs == {"Ti": [], "TiTe": [], "TiTeTh": [], "TiTmTeTh": [swap],
                     "TiTmTeThRia": [swap]}  # fmt: skip
    values = {"Cm": 1.0, "Ce": 2.0, "sigma_m": 0.1, "sigma_e": 0.2, "Tm0": 20.0, "Te0": 10.0,
              "Rim": 3.0, "Rie": 4.0, "Rea": 5.0}  # fmt: skip
    out = exchanged_values(values, swap)
    assert out == {"Cm": 2.0, "Ce": 1.0, "sigma_m": 0.2, "sigma_e": 0.1, "Tm0": 10.0,
                   "Te0": 20.0, "Rim": 4.0, "Rie": 3.0, "Rea": 5.0}  # fmt: skip
