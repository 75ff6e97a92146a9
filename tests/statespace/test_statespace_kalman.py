"""Kalman filter and discretisation against brute-force references."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.linalg import expm, solve_continuous_lyapunov
from statespace_reference import dense_loglike

from thermocal.errors import ThermocalInputError
from thermocal.statespace import RCModel, evaluate, kernels
from thermocal.statespace.data import prepare_data
from thermocal.statespace.discretise import discretise


def three_state_model() -> RCModel:
    """Ti (air), Tm (internal mass), Te (envelope), boundary Ta, heat Ph and solar Ps."""
    m = RCModel("three")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.4)
    m.add_state("Tm", capacity="Cm", noise=0.0, initial_mean=19.0, initial_std=1.0)
    m.add_state("Te", capacity="Ce", noise="se", initial_mean="Te0", initial_std=2.0)
    m.add_conductance("Ti", "Tm", conductance="Him")
    m.add_conductance("Ti", "Te", resistance=["Rie1", "Rie2"])
    m.add_conductance("Te", "Ta", conductance=["Hea", 400.0])
    m.add_heat_input("Ph", into={"Ti": "f_i", "Tm": "rest"}, unit="kW")
    m.add_heat_input("Ps", into="Te", scale="Ae", unit="W/m2")
    m.add_output("yTi", state="Ti", noise="e_i")
    m.add_output("yTm", states={"Tm": 0.5, "Ti": 0.5}, noise=0.3)
    m.add_parameter("Ci", 2.0, unit="MJ/K", lower=0.01, upper=100)
    m.add_parameter("Cm", 20.0, unit="MJ/K")
    m.add_parameter("Ce", 15.0, unit="MJ/K")
    m.add_parameter("Him", 300.0, unit="W/K")
    m.add_parameter("Rie1", 2.0, unit="K/kW")
    m.add_parameter("Rie2", 3.0, unit="K/kW")
    m.add_parameter("Hea", 150.0, unit="W/K")
    m.add_parameter("f_i", 0.7, unit="-", lower=0, upper=1)
    m.add_parameter("Ae", 3.0, unit="m2")
    m.add_parameter("si", 0.2, unit="K/sqrt(h)")
    m.add_parameter("se", 0.1, unit="K/sqrt(h)")
    m.add_parameter("e_i", 0.1, unit="K")
    m.add_parameter("Ti0", 20.0, unit="C", lower=0, upper=40)
    m.add_parameter("Te0", 8.0, unit="C", fixed=True)
    return m


def random_data(n: int, *, seed: int = 0, irregular: bool = False) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    if irregular:
        seconds = np.cumsum(rng.uniform(300, 2400, n)) - 300
    else:
        seconds = np.arange(n) * 900.0
    t = pd.to_datetime("2024-01-01", utc=True) + pd.to_timedelta(seconds, unit="s")
    df = pd.DataFrame(
        {
            "Ta": 5 + 3 * np.sin(seconds / 86400 * 2 * np.pi) + rng.normal(0, 0.3, n),
            "Ph": rng.uniform(0, 3, n),
            "Ps": np.clip(rng.normal(100, 150, n), 0, None),
            "yTi": 20 + rng.normal(0, 1, n),
            "yTm": 19.5 + rng.normal(0, 1, n),
        },
        index=t,
    )
    df.loc[df.index[3:8], "yTm"] = np.nan
    df.loc[df.index[10], ["yTi", "yTm"]] = np.nan
    df.loc[df.index[20], "yTi"] = np.nan
    return df


@pytest.mark.parametrize("hold", ["zoh", "foh"])
@pytest.mark.parametrize("irregular", [False, True])
def test_kalman_loglike_equals_dense_gaussian(hold, irregular):
    model = three_state_model()
    df = random_data(50, seed=3, irregular=irregular)
    ll_kalman = model.loglike(df, hold=hold)
    ll_dense = dense_loglike(model, df, hold)
    assert ll_kalman == pytest.approx(ll_dense, rel=1e-8)


@pytest.mark.parametrize("dt", [1.0, 300.0, 3600.0, 86400.0])
def test_closed_form_discretisation_matches_expm(dt):
    model = three_state_model()
    A, B, _, _ = model.continuous_matrices()
    Sigma = model.diffusion_matrix()
    lam, T, Tinv, TB, M, *_ = model.system()
    n, m = B.shape
    out = [np.empty((n, n)), np.empty((n, m)), np.empty((n, m)), np.empty((n, n))]
    for hold in ("zoh", "foh"):
        kernels.discretise_from_eigen(lam, T, Tinv, TB, M, dt, hold == "foh", *out)
        ref = list(discretise(A, B, Sigma, dt, hold))
        # Van Loan's augmented expm loses digits when exp(-A dt) is huge; for a stable A the
        # exact Q is also P_inf - Ad P_inf Ad^T with the stationary covariance P_inf
        P_inf = solve_continuous_lyapunov(A, -Sigma @ Sigma.T)
        ref[3] = P_inf - ref[0] @ P_inf @ ref[0].T
        for got, want in zip(out, ref, strict=True):
            np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12 * np.abs(want).max())
    np.testing.assert_allclose(out[0], expm(A * dt), rtol=1e-10, atol=1e-14)


def test_long_interval_noise_tends_to_stationary_covariance():
    """Over a very long interval (where Van Loan's augmented expm overflows) the discrete noise
    covariance is the stationary solution of A P + P A^T + Sigma Sigma^T = 0."""
    model = three_state_model()
    A, B, _, _ = model.continuous_matrices()
    Sigma = model.diffusion_matrix()
    lam, T, Tinv, TB, M, *_ = model.system()
    n, m = B.shape
    out = [np.empty((n, n)), np.empty((n, m)), np.empty((n, m)), np.empty((n, n))]
    kernels.discretise_from_eigen(lam, T, Tinv, TB, M, 86400.0 * 365, False, *out)
    P_inf = solve_continuous_lyapunov(A, -Sigma @ Sigma.T)
    np.testing.assert_allclose(out[3], P_inf, rtol=1e-8)
    np.testing.assert_allclose(out[1], -np.linalg.solve(A, B), rtol=1e-8)  # static gain
    assert np.abs(out[0]).max() < 1e-12


def test_foh_equals_zoh_for_constant_inputs():
    model = three_state_model()
    df = random_data(40, seed=1)
    for col in ("Ta", "Ph", "Ps"):
        df[col] = df[col].iloc[0]
    assert model.loglike(df, hold="foh") == pytest.approx(model.loglike(df, hold="zoh"), rel=1e-12)


def test_irregular_path_equals_uniform_path_on_uniform_grid():
    """Uniform data with one sample split in two (second half unobserved) gives the same likelihood
    under first-order hold with the inputs interpolated at the extra instant."""
    model = three_state_model()
    df = random_data(30, seed=2)
    mid = df.index[10] + (df.index[11] - df.index[10]) / 2
    extra = df.iloc[[10, 11]].mean().to_frame().T
    extra.index = [mid]
    extra[["yTi", "yTm"]] = np.nan
    df_irr = pd.concat([df, extra]).sort_index()
    assert model.loglike(df_irr, hold="foh") == pytest.approx(
        model.loglike(df, hold="foh"), rel=1e-10
    )


def test_foh_simulation_matches_ode_solution_with_linear_inputs():
    from scipy.integrate import solve_ivp

    model = three_state_model()
    df = random_data(25, seed=5, irregular=True)
    prep = prepare_data(model, df)
    A, B, C, _ = model.continuous_matrices()
    sim = model.simulate(df, hold="foh")
    x0 = sim.iloc[0][model.state_names].to_numpy()

    def rhs(t, x):
        u = np.array([np.interp(t, prep.seconds, prep.U[:, j]) for j in range(prep.U.shape[1])])
        return A @ x + B @ u

    sol = solve_ivp(rhs, (0, prep.seconds[-1]), x0, t_eval=prep.seconds, rtol=1e-11, atol=1e-11,
                    max_step=float(np.min(np.diff(prep.seconds))) / 4)  # fmt: skip
    np.testing.assert_allclose(sim[model.state_names].to_numpy(), sol.y.T, atol=1e-6)
    np.testing.assert_allclose(sim["yTm"], 0.5 * (sim["Tm"] + sim["Ti"]), atol=1e-12)


@pytest.mark.parametrize("hold", ["zoh", "foh"])
def test_interval_means_equal_the_integrated_ode(hold):
    """``simulate(interval_means=True)``: each value is the mean over the interval its label
    starts, against the ODE solved interval by interval with the state's integral carried along
    (irregular samples; the last interval, beyond the data, the one before's length with the
    last inputs held)."""
    from scipy.integrate import solve_ivp

    model = three_state_model()
    df = random_data(25, seed=7, irregular=True)
    prep = prepare_data(model, df)
    A, B, C, _ = model.continuous_matrices()
    points = model.simulate(df, hold=hold)
    means = model.simulate(df, hold=hold, interval_means=True)
    names = model.state_names
    n, N = len(names), len(df)
    x = points.iloc[0][names].to_numpy()
    expected = np.empty((N, n))
    for k in range(N):
        dt = prep.dts[k] if k < N - 1 else prep.dts[N - 2]
        u0 = prep.U[k]
        u1 = prep.U[k + 1] if (hold == "foh" and k < N - 1) else u0

        def rhs(t, z, u0=u0, u1=u1, dt=dt):
            u = u0 + (u1 - u0) * t / dt
            dx = A @ z[:n] + B @ u
            return np.concatenate([dx, z[:n]])

        sol = solve_ivp(rhs, (0.0, dt), np.concatenate([x, np.zeros(n)]), method="DOP853",
                        rtol=1e-12, atol=1e-12)  # fmt: skip
        expected[k] = sol.y[n:, -1] / dt
        x = sol.y[:n, -1]
        if k < N - 1:  # the simulated state at the next sample, the same solution
            np.testing.assert_allclose(points.iloc[k + 1][names].to_numpy(), x, atol=1e-7)
    np.testing.assert_allclose(means[names].to_numpy(), expected, atol=1e-7)
    # the outputs are the same combination of the means as of the states
    np.testing.assert_allclose(means["yTm"], 0.5 * (means["Tm"] + means["Ti"]), atol=1e-12)
    # and the mean differs from the value at the label (the check can fail)
    assert np.max(np.abs(means["Ti"] - points["Ti"])) > 0.05


def test_interval_means_of_a_constant_state_are_the_state():
    """At the steady state the mean over any interval is the state itself."""
    model = three_state_model()
    t = pd.date_range("2024-01-01", periods=3000, freq="h", tz="UTC")
    df = pd.DataFrame({"Ta": 0.0, "Ph": 2.0, "Ps": 0.0}, index=t)
    points = model.simulate(df)
    means = model.simulate(df, interval_means=True)
    np.testing.assert_allclose(means.iloc[-5:].to_numpy(), points.iloc[-5:].to_numpy(), rtol=1e-9)


@pytest.mark.parametrize("hold", ["zoh", "foh"])
def test_the_row_before_missing_rows_is_averaged_over_one_interval(hold):
    """A day of rows missing (the time axis jumps, the simulation bridges it): the row before
    the gap is a logger's mean over one interval, as on the complete data; it was averaged
    over the whole gap (21.42 C at the label, 21.54 C the hour's mean, 23.87 C the gap's;
    review of 2026-11-30)."""
    model = three_state_model()
    t = pd.date_range("2024-01-01", periods=72, freq="h", tz="UTC")
    df = pd.DataFrame({"Ta": 5.0, "Ph": np.where(t.hour < 12, 3.0, 0.0), "Ps": 0.0}, index=t)
    full = model.simulate(df, interval_means=True, hold=hold)
    gap = df.drop(df.index[30:54])
    bridged = model.simulate(gap, interval_means=True, hold=hold)
    before = gap.index[29]
    assert bridged.loc[before, "Ti"] == pytest.approx(full.loc[before, "Ti"], abs=1e-9)
    points = model.simulate(gap, hold=hold)
    assert abs(bridged.loc[before, "Ti"] - points.loc[before, "Ti"]) > 0.05  # a mean, not a point


def test_steady_state_of_simulation_is_the_network_solution():
    """Constant inputs for a long time: the states reach -A^-1 B u (the resistive network)."""
    model = three_state_model()
    n = 3000
    t = pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC")
    df = pd.DataFrame({"Ta": 0.0, "Ph": 2.0, "Ps": 0.0}, index=t)
    sim = model.simulate(df)
    A, B, _, _ = model.continuous_matrices()
    x_ss = -np.linalg.solve(A, B @ np.array([0.0, 2.0, 0.0]))
    np.testing.assert_allclose(sim[model.state_names].iloc[-1].to_numpy(), x_ss, rtol=1e-6)
    # heat balance: all 2 kW leave through Te-Ta: (Te - Ta) * 1/(1/150 + 1/400) W/K = 2000 W
    h_ea = 1.0 / (1.0 / 150.0 + 1.0 / 400.0)
    assert sim["Te"].iloc[-1] * h_ea == pytest.approx(2000.0, rel=1e-6)


def test_filter_is_compiled_once_for_likelihood_and_stored_moments():
    """The likelihood kernel (inside the optimiser) and the filter storing the moments (residuals,
    smoothing) share one compiled specialisation: a second one cost seconds on the first fit."""
    from thermocal.statespace.estimation import LikelihoodProblem, filter_arrays

    model = three_state_model()
    prep = prepare_data(model, random_data(30, seed=7))
    LikelihoodProblem(model, prep, False).loglike(model.theta0())
    filtered = filter_arrays(model, prep, None, False)
    assert np.isfinite(filtered["loglike"])
    assert len(kernels.kalman_filter.signatures) == 1


@pytest.mark.parametrize("hold", ["zoh", "foh"])
def test_steady_state_shortcut_survives_a_change_of_interval(hold):
    """Once the filter is stationary it freezes the gain; when the sampling interval then changes
    (a gap, a logger switching from 5 to 10 minutes) the covariance must restart from the
    filtered, not the predicted, covariance. Reference: the filter storing all moments, which
    never takes the shortcut (and equals the dense Gaussian likelihood, tested above)."""
    from thermocal.statespace.estimation import filter_arrays

    m = RCModel("one")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean=20.0, initial_std=1.0)
    m.add_conductance("Ti", "Ta", conductance="H")
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    m.add_parameter("Ci", 2.0, unit="MJ/K")
    m.add_parameter("H", 200.0, unit="W/K")
    m.add_parameter("si", 0.5, unit="K/sqrt(h)")
    m.add_parameter("e", 0.2, unit="K")
    rng = np.random.default_rng(3)
    n = 400
    seconds = np.arange(n) * 600.0
    seconds[250:] += 1500.0  # one 35-minute interval after 250 samples of 10 minutes
    seconds[330:] += np.cumsum(rng.uniform(0, 300, n - 330))  # then irregular
    t = pd.to_datetime("2024-01-01", utc=True) + pd.to_timedelta(seconds, unit="s")
    df = pd.DataFrame(
        {"Ta": rng.normal(5, 1, n), "Ph": rng.uniform(0, 3000, n), "y": rng.normal(20, 1, n)},
        index=t,
    )
    df.loc[df.index[300], "y"] = np.nan
    prep = prepare_data(m, df)
    reference = filter_arrays(m, prep, None, hold == "foh")["loglike"]
    assert m.loglike(df, hold=hold) == pytest.approx(reference, rel=1e-12)


def test_simulation_of_a_later_period_from_a_given_initial_state():
    """Simulating the second half from the full run's states at its first sample reproduces the
    second half of the full run (validation periods start elsewhere than the fit)."""
    model = three_state_model()
    df = random_data(40, seed=6, irregular=True)
    full = model.simulate(df, hold="foh")
    start = full.iloc[20][model.state_names].to_dict()
    late = model.simulate(df.iloc[20:], hold="foh", initial_state=start)
    np.testing.assert_allclose(late.to_numpy(), full.iloc[20:].to_numpy(), rtol=1e-12)
    plain = model.simulate(df.iloc[20:], hold="foh")
    assert plain["Ti"].iloc[0] == 20.0  # the declared initial mean Ti0
    with pytest.raises(ThermocalInputError, match="'Tx' is not a state.*Ti, Tm, Te"):
        model.simulate(df, initial_state={"Tx": 20.0})


@pytest.mark.parametrize("hold", ["zoh", "foh"])
@pytest.mark.parametrize("case", ["uniform", "gaps_and_missing", "irregular"])
def test_batched_likelihoods_equal_the_filter_run_row_by_row(hold, case):
    """The gradient and Hessian evaluate many likelihoods together (``loglike_batch``: rows
    advance sample by sample once stationary). Reference: the filter run one row at a time,
    bit for bit, on uniform data, on data with missing outputs and a change of interval near the
    end (where the stationary shortcut must stop), and on an irregular grid (no shortcut)."""
    from thermocal.statespace.estimation import LikelihoodProblem

    model = three_state_model()
    df = random_data(600, seed=11, irregular=case == "irregular")
    if case == "uniform":
        df[["yTi", "yTm"]] = df[["yTi", "yTm"]].ffill()
    if case == "gaps_and_missing":
        df.loc[df.index[550], "yTm"] = np.nan
        shift = np.where(np.arange(len(df)) >= 580, 1200.0, 0.0)  # one 35-min interval
        df.index = df.index + pd.to_timedelta(shift, unit="s")
    prep = prepare_data(model, df)
    problem = LikelihoodProblem(model, prep, hold == "foh")
    rng = np.random.default_rng(5)
    thetas = model.theta0() + rng.normal(0.0, 0.5, (9, model.n_free))
    thetas[4, 1] = 1e3  # an overflowing capacity (Cm): -inf in both
    one_by_one = np.array([problem.loglike(t) for t in thetas])
    together = problem.loglike_many(thetas)
    assert np.isneginf(one_by_one[4]) and np.isneginf(together[4])
    np.testing.assert_array_equal(together, one_by_one)
    start = kernels.stationary_from(prep.dts, prep.Y, problem.seg)
    assert start == {"uniform": 1, "gaps_and_missing": 581, "irregular": len(df) - 1}[case]


@pytest.mark.parametrize("hold", ["zoh", "foh"])
@pytest.mark.parametrize("name", ["Ti", "TiTh", "TiTeTh", "TiTmTeTh", "TiTmTeThRia", "two_inputs"])
def test_batched_gradient_rows_equal_the_filter_run_row_by_row(name, hold):
    """One output and 1-4 states (the compiled specialisations of the stationary batch filter)
    and the gradient's rows, of which those moving an initial mean or an input coefficient
    share one covariance recursion with the centre: bit for bit the filter run one row at a
    time (two and three inputs, both holds)."""
    from pathlib import Path

    from thermocal.statespace.estimation import GRADIENT_STEP, LikelihoodProblem

    if name == "two_inputs":
        model = RCModel("two_inputs")
        model.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.4)
        model.add_state("Te", capacity="Ce", noise="se", initial_mean="Te0", initial_std=2.0)
        model.add_conductance("Ti", "Te", conductance="Hie")
        model.add_conductance("Te", "Ta", conductance="Hea")
        model.add_heat_input("Ph", into="Ti", scale="eta", unit="kW")
        model.add_output("yTi", state="Ti", noise="e_i")
        for p, value, unit in [("Ci", 2.0, "MJ/K"), ("Ce", 20.0, "MJ/K"), ("Hie", 300.0, "W/K"),
                               ("Hea", 200.0, "W/K"), ("eta", 1.0, "-"), ("si", 0.5, "K/sqrt(h)"),
                               ("se", 0.5, "K/sqrt(h)"), ("e_i", 0.1, "K"), ("Ti0", 20.0, "C"),
                               ("Te0", 10.0, "C")]:  # fmt: skip
            model.add_parameter(p, value, unit=unit)
    else:
        repo = Path(__file__).resolve().parents[2]
        model = RCModel.from_yaml(repo / "examples" / "models" / f"{name}.yaml")
    df = random_data(500, seed=21)
    df["yTi"] = df["yTi"].rolling(5, min_periods=1).mean()
    prep = prepare_data(model, df)
    problem = LikelihoodProblem(model, prep, hold == "foh")
    rng = np.random.default_rng(8)
    theta = problem.clip(model.theta0() + rng.normal(0.0, 0.3, model.n_free))
    rows = [theta]
    for i in range(theta.size):
        h = GRADIENT_STEP * max(1.0, abs(theta[i]))
        for sign in (1.0, -1.0):
            row = theta.copy()
            row[i] += sign * h
            rows.append(row)
    rows.append(problem.clip(model.theta0() + rng.normal(0.0, 0.3, model.n_free)))
    thetas = np.array(rows)
    one_by_one = np.array([problem.loglike(t) for t in thetas])
    together = problem.loglike_many(thetas)
    assert np.all(np.isfinite(one_by_one))
    np.testing.assert_array_equal(together, one_by_one)


def _house_with_a_morning_recovery() -> RCModel:
    """Air (3 MJ/K) and envelope (40 MJ/K), 600 and 250 W/K in series: 176.5 W/K."""
    m = RCModel("TiTe")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.5)
    m.add_state("Te", capacity="Ce", noise="se", initial_mean="Te0", initial_std=1.0)
    m.add_conductance("Ti", "Te", conductance="Hie")
    m.add_conductance("Te", "Ta", conductance="Hea")
    m.add_heat_input("Ph", into="Ti", unit="kW")
    m.add_output("yTi", state="Ti", noise="e")
    m.add_parameter("Ci", 3.0, unit="MJ/K", lower=0.1, upper=50)
    m.add_parameter("Ce", 40.0, unit="MJ/K", lower=1, upper=500)
    m.add_parameter("Hie", 600.0, unit="W/K", lower=10, upper=5000)
    m.add_parameter("Hea", 250.0, unit="W/K", lower=10, upper=5000)
    m.add_parameter("si", 0.3, unit="K/sqrt(h)", lower=1e-4, upper=10)
    m.add_parameter("se", 0.05, unit="K/sqrt(h)", lower=1e-4, upper=10)
    m.add_parameter("e", 0.05, unit="K", lower=1e-4, upper=5)
    m.add_parameter("Ti0", 20.0, unit="C", lower=0, upper=40)
    m.add_parameter("Te0", 12.0, unit="C", lower=-20, upper=40)
    return m


def test_interval_means_fitted_at_their_midpoints():
    """Hourly means of a house simulated minute by minute (process noise, a 6 kW recovery at
    06:00, 3 kW by day, 0.5 kW at night), labelled by the hour's start as loggers write them.
    Fitted as if each were the state at the hour's start, the lag of half an hour biases the
    fit (measured 2026-11-30: heat loss coefficient +12.8, +5.6, +4.9 %, air capacity +46 to
    +94 %); observed at the hour's middle (``midpoint_observations``) the bias goes (+0.8,
    -1.8, +0.9 %; air capacity +7 to +9 %)."""
    from thermocal.statespace.data import midpoint_observations
    from thermocal.statespace.kalman import simulate_stochastic

    model = _house_with_a_morning_recovery()
    true_h = 1.0 / (1.0 / 600.0 + 1.0 / 250.0)
    at_start, at_middle = [], []
    for seed in range(3):
        rng = np.random.default_rng(seed)
        t = pd.date_range("2024-01-01", periods=14 * 1440, freq="min", tz="UTC")
        hour = t.hour + t.minute / 60
        ta = 2 + 4 * np.sin(2 * np.pi * (hour - 9) / 24) + np.repeat(rng.normal(0, 2, 14), 1440)
        ph = np.where((hour >= 6) & (hour < 7), 6.0, np.where((hour >= 7) & (hour < 22), 3.0, 0.5))
        minutes = pd.DataFrame({"Ta": ta, "Ph": ph * (1 + 0.1 * rng.normal(size=len(t)))}, t)
        states = simulate_stochastic(model, minutes, seed=seed)
        hourly = pd.concat([minutes, states[["Ti"]]], axis=1).resample("1h").mean()
        logged = hourly[["Ta", "Ph"]].assign(yTi=hourly["Ti"] + rng.normal(0, 0.05, len(hourly)))
        for rows, out in ((logged, at_start), (midpoint_observations(logged, ["yTi"]), at_middle)):
            fitted = model.fit(rows, n_starts=1, seed=0)
            p = fitted.params
            h = 1.0 / (1.0 / p["Hie"] + 1.0 / p["Hea"])
            out.append((h / true_h - 1.0, p["Ci"] / 3.0 - 1.0))
        # the whiteness test runs on the observed rows (every second one): a number, not NaN
        assert np.isfinite(fitted.checks["ljung_box"]["yTi"]["pvalue"]), fitted.checks
    start, middle = np.array(at_start), np.array(at_middle)
    assert start[:, 0].mean() > 0.03 and start[:, 1].mean() > 0.3, start  # the lag's bias
    assert abs(middle[:, 0].mean()) < 0.02 and np.all(np.abs(middle[:, 0]) < 0.04), middle
    assert np.all(np.abs(middle[:, 1]) < 0.2), middle


def test_midpoint_observations_rows():
    """Each row becomes its start (inputs, no observation) and its middle (the observation);
    a first-order hold takes the mean of the two rows' inputs at the middle."""
    from thermocal.statespace.data import midpoint_observations

    t = pd.date_range("2024-01-01", periods=3, freq="h", tz="UTC")
    rows = pd.DataFrame({"Ta": [1.0, 3.0, 5.0], "y": [20.0, 21.0, 22.0]}, index=t)
    grid = midpoint_observations(rows, ["y"])
    assert list(grid.index) == list(pd.date_range("2024-01-01", periods=6, freq="30min", tz="UTC"))
    assert grid["y"].isna().tolist() == [True, False] * 3
    assert grid["y"].dropna().tolist() == [20.0, 21.0, 22.0]
    assert grid["Ta"].tolist() == [1.0, 1.0, 3.0, 3.0, 5.0, 5.0]
    assert midpoint_observations(rows, ["y"], hold="foh")["Ta"].tolist() == [1, 2, 3, 4, 5, 5]
    with pytest.raises(ThermocalInputError, match="no column"):
        midpoint_observations(rows, ["yTi"])
    with pytest.raises(ThermocalInputError, match="strictly increasing"):
        midpoint_observations(rows.iloc[[0, 2, 1]], ["y"])
    # a row before a gap averaged one logger interval, not the gap: its middle is half an hour on
    gap = rows.drop(rows.index[1])
    gap = pd.concat([gap, rows.iloc[[2]].set_axis([t[2] + pd.Timedelta("1h")])])
    middles = midpoint_observations(gap, ["y"], hold="foh")["y"].dropna().index
    assert list(middles - gap.index) == [pd.Timedelta("30min")] * 3
    assert midpoint_observations(gap, ["y"], hold="foh")["Ta"].iloc[1] == pytest.approx(1.0 + 4 / 4)


def test_midpoint_grid_with_missing_inputs_keeps_its_observations_every_second_row():
    """A first-order hold's middle row before a missing input held the NaN: a gap of g rows
    became 2 g + 1, split periods dropped an odd number of rows and the residuals' Ljung-Box
    test, on every row then, was NaN ("could not be tested"; review of 2026-11-30)."""
    from thermocal.statespace.data import midpoint_observations, prepare_data
    from thermocal.statespace.results import observation_rows

    model = _house_with_a_morning_recovery()
    rng = np.random.default_rng(0)
    t = pd.date_range("2024-01-01", periods=200, freq="h", tz="UTC")
    rows = pd.DataFrame({"Ta": rng.normal(5, 1, 200), "Ph": rng.uniform(0, 3, 200),
                         "yTi": rng.normal(20, 0.5, 200)}, index=t)  # fmt: skip
    rows.iloc[100:104, rows.columns.get_loc("Ta")] = np.nan
    grid = midpoint_observations(rows, ["yTi"], hold="foh")
    assert int(grid["Ta"].isna().sum()) == 2 * 4
    prep = prepare_data(model, grid, input_gaps="split")
    assert np.all(np.diff(observation_rows(prep.Y)) == 2)
    fit = model.fit(grid, hold="foh", input_gaps="split", n_starts=1, seed=0)
    assert np.isfinite(fit.checks["ljung_box"]["yTi"]["pvalue"])


def test_time_constants_are_checked_against_the_observations_interval():
    """On a grid of half hours observed every hour (``midpoint_observations``) a 45-minute
    mode is shorter than the observations' interval and is flagged so (the rows' own
    interval, 30 minutes, would have passed it)."""
    from thermocal.statespace.data import midpoint_observations

    model = _house_with_a_morning_recovery().with_parameters({"Ci": 600.0 * 2700.0 / 1e6})
    t = pd.date_range("2024-01-01", periods=96, freq="h", tz="UTC")
    rng = np.random.default_rng(0)
    rows = pd.DataFrame({"Ta": rng.normal(5, 1, 96), "Ph": rng.uniform(0, 3, 96),
                         "yTi": rng.normal(20, 0.5, 96)}, index=t)  # fmt: skip
    flags = evaluate(model, midpoint_observations(rows, ["yTi"])).flags
    assert any("shorter than the sampling interval (60 min)" in f for f in flags), flags
