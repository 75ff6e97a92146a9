"""Unit tests of the retrofit building blocks: strategies, metrics, model, demand, config."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from retrofit_synthetic import building_dict

from thermocal.errors import ThermocalInputError
from thermocal.io.envelope import EnvelopeDescription
from thermocal.physics.ground import iso13370_slab_on_ground
from thermocal.retrofit.calibration import initial_params_si
from thermocal.retrofit.config import parse_config
from thermocal.retrofit.demand import simulate_demand, steady_state_demand
from thermocal.retrofit.metrics import daily_profile, monthly_energy_kwh, validation_metrics
from thermocal.retrofit.model import (
    build_fifth_order_model,
    calculated_hlc,
    element_conductances,
    system_matrices,
)
from thermocal.retrofit.strategies import MEASURE_ORDER, all_strategies


def test_strategies_match_paper_table_3():
    codes = [s.code for s in all_strategies()]
    assert codes == [
        "0",
        "1a",
        "1b",
        "1c",
        "1d",
        "2a",
        "2b",
        "2c",
        "2d",
        "2e",
        "2f",
        "3a",
        "3b",
        "3c",
        "3d",
        "4",
    ]
    by_code = {s.code: s for s in all_strategies()}
    assert by_code["3c"].measures == ("roof", "windows", "cellar_ceiling")  # stated in the text
    assert by_code["1b"].measures == ("walls",)
    assert by_code["2f"].measures == ("windows", "cellar_ceiling")
    assert by_code["4"].measures == MEASURE_ORDER
    # every subset exactly once
    assert len({frozenset(s.measures) for s in all_strategies()}) == 16


def test_validation_metrics_brute_force():
    rng = np.random.default_rng(0)
    meas = 20 + rng.normal(0, 1, 300)
    sim = meas + rng.normal(0.2, 0.5, 300)
    m = validation_metrics(sim, meas)
    err = sim - meas
    assert m["mae"] == pytest.approx(sum(abs(e) for e in err) / 300)
    assert m["mse"] == pytest.approx(sum(e * e for e in err) / 300)
    assert m["mape"] == pytest.approx(
        100 * np.mean([abs(e / x) for e, x in zip(err, meas, strict=True)])
    )
    assert m["mean_deviation_pct"] == pytest.approx(100 * (sim.mean() / meas.mean() - 1))
    # the paper's own numbers: 21.90 vs 22.05 C is -0.68 %
    m2 = validation_metrics([21.90], [22.05])
    assert m2["mean_deviation_pct"] == pytest.approx(-0.68, abs=0.005)


def test_monthly_energy_and_profile():
    idx = pd.date_range("2001-01-01", "2001-12-31 23:00", freq="h", tz="UTC")
    power = pd.Series(1000.0, index=idx)
    monthly = monthly_energy_kwh(power)
    assert monthly[1] == pytest.approx(31 * 24.0)
    assert monthly[2] == pytest.approx(28 * 24.0)
    assert monthly.sum() == pytest.approx(8760.0)
    ti = pd.Series(20 + idx.hour / 10.0, index=idx)
    assert np.allclose(daily_profile(ti), 20 + np.arange(24) / 10.0)


def test_element_conductances_series_equals_u_times_area():
    h_in, h_out, share = element_conductances(50.0, 0.8, 0.13, 0.04)
    assert 1 / (1 / h_in + 1 / h_out) == pytest.approx(0.8 * 50.0)
    r_cond = 1 / 0.8 - 0.17
    assert share == pytest.approx((2 / r_cond) / (1 / 0.04 + 2 / r_cond))


def test_iso13370_slab_known_value():
    # ISO 13370 Eq. (5): 10 m x 10 m, B' = 100 / (0.5 x 40) = 5 m,
    # dt = 0.3 + 2 (0.17 + 0 + 0.04) = 0.72 m
    u = iso13370_slab_on_ground(
        100.0, 40.0, wall_thickness=0.3, floor_resistance=0.0, soil_conductivity=2.0
    )
    b, dt = 5.0, 0.3 + 2.0 * 0.21
    assert u == pytest.approx(2 * 2.0 / (np.pi * b + dt) * np.log(np.pi * b / dt + 1))


def _model():
    return build_fifth_order_model(EnvelopeDescription.model_validate(building_dict()))


def test_system_matrices_conserve_energy():
    m = _model()
    h = m.conductances()
    p = {"H_est": 150.0, "C_env": 4e7, "C_gf": 1e7, "C_im": 2e7, "C_i": 2e6, "C_h": 4e5}
    a, b = system_matrices(h, p)
    caps = np.array([2e6, 4e7, 1e7, 2e7, 4e5])
    # steady state with all boundary temperatures = T: all states = T (rows of C.A sum with B)
    k = caps[:, None] * a[0]
    kb = caps[:, None] * b[0]
    assert np.allclose(k.sum(axis=1) + kb[:, 0] + kb[:, 1], 0.0, atol=1e-9)
    # HLC from the matrices = calculated HLC + H_est
    x = np.linalg.solve(a[0], -b[0][:, :2] @ np.array([0.0, 0.0]) - b[0][:, 2] * 1000.0)
    # 1 kW into the heating node: Ti rises by 1000 / HLC above the boundaries
    assert x[0] == pytest.approx(1000.0 / (calculated_hlc(h) + 150.0), rel=1e-9)


def test_demand_mode_reproduces_steady_state_hand_calculation():
    """Constant Te, no sun, ground at Te: demand = HLC x (Ti - Te) (issue 4)."""
    m = _model()
    idx = pd.date_range("2001-01-01", periods=24 * 40, freq="h", tz="UTC")
    inputs = pd.DataFrame(
        {"Te": -2.0, "Tgr": -2.0, "phi_sol": 0.0, "phi_abs_roof": 0.0, "phi_abs_walls": 0.0},
        index=idx,
    )
    p = {
        "H_est": np.array([120.0, 240.0]),
        "C_env": np.array([4e7, 6e7]),
        "C_gf": np.array([1e7, 1e7]),
        "C_im": np.array([2e7, 3e7]),
        "C_i": np.array([2e6, 2e6]),
        "C_h": np.array([4e5, 4e5]),
    }
    retro = m.envelope.with_measures({"roof": 0.18, "walls": 0.19})
    res = simulate_demand(m, p, [m.envelope, retro], inputs, 20.0)
    for s, env in enumerate([m.envelope, retro]):
        for d, h_est in enumerate(p["H_est"]):
            expected = steady_state_demand(m, h_est, 20.0, -2.0, env)
            hand = (calculated_hlc(m.conductances(env)) + h_est) * 22.0
            assert expected == pytest.approx(hand)
            # every draw: January energy of the constant load (31 days)
            assert res.monthly[s, d, 0] == pytest.approx(hand * 31 * 24 / 1000.0, rel=1e-6)
        assert res.hourly[s, -1] == pytest.approx(
            (calculated_hlc(m.conductances(env)) + p["H_est"][0]) * 22.0, rel=1e-6
        )
    # annual energy = sum of the hourly powers of the estimate
    assert res.annual_kwh()[0, 0] == pytest.approx(res.hourly[0].sum() / 1000.0)


def test_demand_heating_only_never_negative_and_floats_with_sun():
    m = _model()
    idx = pd.date_range("2001-06-01", periods=24 * 10, freq="h", tz="UTC")
    inputs = pd.DataFrame(
        {"Te": 25.0, "Tgr": 12.0, "phi_sol": 5000.0, "phi_abs_roof": 0.0, "phi_abs_walls": 0.0},
        index=idx,
    )
    p = {
        "H_est": np.array([150.0]),
        "C_env": np.array([4e7]),
        "C_gf": np.array([1e7]),
        "C_im": np.array([2e7]),
        "C_i": np.array([2e6]),
        "C_h": np.array([4e5]),
    }
    res = simulate_demand(m, p, [m.envelope], inputs, 20.0)
    assert np.all(res.hourly >= 0.0) and np.all(res.monthly >= 0.0)
    assert res.hourly[0, -24:].max() == 0.0


def test_retrofit_lowers_conductances_only():
    m = _model()
    h0 = m.conductances()
    h4 = m.conductances(
        m.envelope.with_measures(
            {"roof": 0.18, "walls": 0.19, "windows": 0.76, "cellar_ceiling": 0.19}
        )
    )
    assert calculated_hlc(h4) < calculated_hlc(h0)
    assert h4["H_h"] == h0["H_h"] and h4["H_im"] == h0["H_im"]
    assert h4["H_win"] == pytest.approx(0.76 * m.envelope.windows_area)


def _cfg(**over):
    base = {"building": "b.yaml", "measurements": {"file": "m.csv"}, "weather": {"file": "w.epw"}}
    base.update(over)
    return base


def test_config_errors_name_the_key():
    with pytest.raises(ThermocalInputError, match="measurements.columns"):
        parse_config(_cfg(measurements={"file": "m.csv", "columns": {"Te": "x"}}))
    with pytest.raises(ThermocalInputError, match="measures.*component"):
        parse_config(_cfg(measures={"roof": 0.18, "attic": 0.19}))
    with pytest.raises(ThermocalInputError, match="model.bounds.C_env"):
        parse_config(_cfg(model={"bounds": {"C_env": [200, 100]}}))
    with pytest.raises(ThermocalInputError, match="unknown parameters"):
        parse_config(_cfg(model={"fixed": {"C_x": 1.0}}))
    three = parse_config(_cfg(measures={"roof": 0.18, "walls": 0.19, "windows": 0.76}))
    assert len(three.strategy_list()) == 8  # a subset of the measures is fine
    with pytest.raises(ThermocalInputError, match="typo_key"):
        parse_config(_cfg(typo_key=1))
    with pytest.raises(ThermocalInputError, match="training_days"):
        parse_config(_cfg(periods={"training_days": -1}))
    cfg = parse_config(_cfg(), base_dir="/data")
    assert str(cfg.measurements.file) == "/data/m.csv"
    assert cfg.measures["windows"].u_value == 0.76


def test_example_config_is_valid_and_complete():
    from pathlib import Path

    from thermocal.retrofit.config import load_config
    from thermocal.retrofit.workflow import resolve_weather_path

    path = Path(__file__).resolve().parents[2] / "examples" / "retrofit" / "config.yaml"
    cfg = load_config(path)
    assert Path(cfg.building).is_file()
    assert cfg.measurements.file.is_file()
    assert resolve_weather_path(cfg.weather.file).is_file()
    assert {k: m.u_value for k, m in cfg.measures.items()} == {
        "roof": 0.18, "walls": 0.19, "windows": 0.76, "cellar_ceiling": 0.19
    }  # fmt: skip


@pytest.mark.parametrize("kind", ["slab", "heated"])
def test_ground_variants_steady_state(kind):
    """Slab on ground and heated basement: the gf path carries the ISO 13370 H_g and the
    demand mode still reproduces HLC x dT."""
    from thermocal.physics.ground import iso13370_heated_basement, iso13370_slab_on_ground

    data = building_dict()
    for c in data["components"]:
        if c["type"] == "cellar_ceiling":
            c["type"] = "ground_floor"
    data["ground"] = {
        "perimeter": 38.0,
        "wall_thickness": 0.3,
        "basement": "none" if kind == "slab" else "heated",
    }
    if kind == "heated":
        data["ground"].update({"basement_depth": 2.2, "basement_wall_u_value": 1.2})
    building = EnvelopeDescription.model_validate(data)
    m = build_fifth_order_model(building)
    h = m.conductances()
    area = m.envelope.floor_area
    r_f = 1 / m.envelope.floor_u - 0.17 - 0.04
    if kind == "slab":
        expected = area * iso13370_slab_on_ground(
            area, 38.0, wall_thickness=0.3, floor_resistance=r_f
        )
    else:
        expected = iso13370_heated_basement(
            area,
            38.0,
            2.2,
            wall_thickness=0.3,
            floor_resistance=r_f,
            wall_resistance=1 / 1.2 - 0.13 - 0.04,
        )["heat_transfer_coefficient"]
    assert 1 / (1 / h["H_gf_in"] + 1 / h["H_gf_gr"]) == pytest.approx(expected)
    idx = pd.date_range("2001-01-01", periods=24 * 35, freq="h", tz="UTC")
    inputs = pd.DataFrame(
        {"Te": 0.0, "Tgr": 0.0, "phi_sol": 0.0, "phi_abs_roof": 0.0, "phi_abs_walls": 0.0},
        index=idx,
    )
    p = {
        "H_est": np.array([100.0]),
        "C_env": np.array([4e7]),
        "C_gf": np.array([1e7]),
        "C_im": np.array([2e7]),
        "C_i": np.array([2e6]),
        "C_h": np.array([4e5]),
    }
    res = simulate_demand(m, p, [m.envelope], inputs, 20.0)
    assert res.hourly[0, -1] == pytest.approx((calculated_hlc(h) + 100.0) * 20.0, rel=1e-6)


def test_uncertain_u_values_keep_the_calibrated_hlc():
    from thermocal.retrofit.strategies import PAPER_MEASURE_U_VALUES
    from thermocal.retrofit.workflow import scenario_envelopes

    m = _model()
    n = 50
    draws = {
        "H_est": np.full(n, 200.0),
        "C_env": np.full(n, 4e7),
        "C_gf": np.full(n, 1e7),
        "C_im": np.full(n, 2e7),
        "C_i": np.full(n, 2e6),
        "C_h": np.full(n, 4e5),
    }
    envs = scenario_envelopes(m, all_strategies(), PAPER_MEASURE_U_VALUES, draws, 0.15)
    hlc0 = calculated_hlc(m.conductances()) + 200.0
    base = envs[0]
    assert len(envs) == 16 and len(base) == n
    assert base[0] == m.envelope  # the first draw is the estimate
    hlc = [calculated_hlc(m.conductances(e)) + h for e, h in zip(base, draws["H_est"], strict=True)]
    assert np.allclose(hlc, hlc0)
    walls = np.array([e.walls_u for e in base])
    assert 0.08 < np.std(walls / m.envelope.walls_u) < 0.25
    # retrofitted walls get the insulation that takes the described wall to the target, added
    # to each draw's wall (the estimate: the target); new windows keep each draw's correction
    # of the old ones as their films' resistance (the estimate: the target)
    target = PAPER_MEASURE_U_VALUES["walls"]
    d_r = 1.0 / target - 1.0 / m.envelope.walls_u
    after = np.array([e.walls_u for e in envs[-1]])
    assert after[0] == pytest.approx(target, rel=1e-12)
    assert np.allclose(after, 1.0 / (1.0 / walls + d_r), rtol=1e-12)
    from thermocal.retrofit.model import replaced_window_u

    new = PAPER_MEASURE_U_VALUES["windows"]
    assert envs[-1][0].windows_u == pytest.approx(new, rel=1e-12)
    for before, after in zip(base, envs[-1], strict=True):
        expected = replaced_window_u(new, before.windows_u, m.envelope.windows_u)
        assert after.windows_u == pytest.approx(expected, rel=1e-12)


def _ground_variant(kind):
    data = building_dict()
    if kind != "unheated_basement":
        for c in data["components"]:
            if c["type"] == "cellar_ceiling":
                c["type"] = "ground_floor"
        data["ground"] = {
            "perimeter": 38.0,
            "wall_thickness": 0.3,
            "basement": "none" if kind == "slab" else "heated",
        }
        if kind == "heated":
            data["ground"].update({"basement_depth": 2.2, "basement_wall_u_value": 1.2})
    return build_fifth_order_model(EnvelopeDescription.model_validate(data))


def _hand_written_matrices(h, p, demand):
    """The node equations of the fifth-order network (its Fig. 3), written out by hand."""
    ti, env, gf, im, th = range(5)
    ns = 4 if demand else 5
    a, b = np.zeros((ns, ns)), np.zeros((ns, 6))
    h_est = max(p["H_est"] + h.get("H_est_change", 0.0), 0.0)
    g = h.get("g_factor", 1.0)
    for i, j, c in ((ti, env, h["H_env_in"]), (ti, gf, h["H_gf_in"]), (ti, im, h["H_im"])):
        a[i, j] += c
        a[j, i] += c
        a[i, i] -= c
        a[j, j] -= c
    a[ti, ti] -= h["H_win"] + h_est
    a[env, env] -= h["H_env_out"]
    a[gf, gf] -= h["H_gf_gr"] + h["H_gf_e"]
    if demand:
        te, tgr, sol, roof, walls, q = range(6)
        b[ti, q] = 1.0
    else:
        te, tgr, phih, sol, roof, walls = range(6)
        a[ti, th] = a[th, ti] = h["H_h"]
        a[ti, ti] -= h["H_h"]
        a[th, th] = -h["H_h"]
        b[th, phih] = 1.0
    b[ti, te], b[env, te], b[gf, te], b[gf, tgr] = (
        h["H_win"] + h_est, h["H_env_out"], h["H_gf_e"], h["H_gf_gr"]
    )  # fmt: skip
    b[ti, sol], b[im, sol] = (1.0 - h["f_im"]) * g, h["f_im"] * g
    b[env, roof], b[env, walls] = h["share_roof"], h["share_walls"]
    caps = np.array([p["C_i"], p["C_env"], p["C_gf"], p["C_im"], p["C_h"]][:ns])
    return a / caps[:, None], b / caps[:, None]


@pytest.mark.parametrize("kind", ["unheated_basement", "slab", "heated"])
def test_network_matrices_equal_the_hand_written_node_equations(kind):
    """The matrices the engine builds from the network (calibration and demand mode, with
    ventilation and g-value measures) equal the node equations written out by hand, and
    the calibration's network (calculated conductances as numbers) gives the same ones."""
    from thermocal.retrofit.calibration import rc_spec
    from thermocal.retrofit.model import (
        ESTIMATED_PARAMETERS,
        INPUT_NAMES,
        STATE_NAMES,
        discrete_system_matrices,
    )
    from thermocal.statespace import RCModel, discretise

    m = _ground_variant(kind)
    h = m.conductances()
    assert h["H_gf_e"] > 0 if kind == "unheated_basement" else h["H_gf_e"] == 0
    rc = RCModel.from_dict(rc_spec(m, np.full(5, 20.0)))
    assert rc.state_names == list(STATE_NAMES) and rc.input_names == list(INPUT_NAMES)
    rng = np.random.default_rng(42)
    for _ in range(3):
        declared = {}  # declared units (W/K, MJ/K), drawn log-uniformly within the bounds
        for name in ESTIMATED_PARAMETERS:
            lo, _, hi, _ = m.estimated[name]
            declared[name] = float(np.exp(rng.uniform(np.log(lo), np.log(hi))))
        si = {k: v * (1e6 if m.estimated[k][3] == "MJ/K" else 1.0) for k, v in declared.items()}
        a_rc, b_rc, _, _ = rc.continuous_matrices(declared)
        measures = {**h, "H_est_change": -0.3 * si["H_est"], "g_factor": 0.6}
        for demand, hh, fitted in ((False, h, (a_rc, b_rc)), (True, measures, None)):
            a, b = system_matrices(hh, si, indoor_input=demand)
            a_ref, b_ref = _hand_written_matrices(hh, si, demand)
            np.testing.assert_allclose(a[0], a_ref, rtol=1e-12, atol=1e-12 * np.abs(a_ref).max())
            np.testing.assert_allclose(b[0], b_ref, rtol=1e-12, atol=1e-12 * np.abs(b_ref).max())
            # the engine's eigen-form discretisation = the augmented matrix exponential
            ad, bd = discrete_system_matrices(hh, si, 3600.0, indoor_input=demand)
            ad_ref, bd_ref, _, _ = discretise(a_ref, b_ref, np.zeros_like(a_ref), 3600.0)
            np.testing.assert_allclose(ad[0], ad_ref, rtol=1e-9, atol=1e-12)
            np.testing.assert_allclose(bd[0], bd_ref, rtol=1e-9, atol=1e-12 * np.abs(bd_ref).max())
            if fitted is not None:
                np.testing.assert_allclose(fitted[0], a_ref, rtol=1e-12, atol=1e-20)
                np.testing.assert_allclose(fitted[1], b_ref, rtol=1e-12, atol=1e-20)


def _raw_log(freq: str, periods: int, seed: int = 1) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    idx = pd.date_range("2001-02-01", periods=periods, freq=freq, tz="UTC", name="time")
    return pd.DataFrame(
        {
            "temp_out": rng.normal(0.0, 3.0, periods),
            "flow": rng.uniform(0.0, 3e-4, periods),
            "temp_supply": rng.uniform(40.0, 55.0, periods),
            "temp_return": rng.uniform(30.0, 40.0, periods),
            "dni": rng.uniform(0.0, 600.0, periods),
            "dhi": rng.uniform(0.0, 200.0, periods),
            "temp_in": rng.normal(20.0, 1.0, periods),
        },
        index=idx,
    )


def test_measurement_grid_equals_plain_interval_means():
    """A regular 10-minute log: every hourly value is the plain mean of its six rows (brute
    force), phi_h from the rows before averaging; the last hour is complete."""
    from thermocal.physics.hydronics import heating_power
    from thermocal.retrofit.data import prepare_measurements

    raw = _raw_log("10min", 6 * 48)
    grid, report = prepare_measurements(raw, "1h")
    assert len(grid) == 48 and report.ok
    phi = heating_power(raw["flow"], raw["temp_supply"], raw["temp_return"])
    for k in (0, 17, 47):
        rows = slice(6 * k, 6 * k + 6)
        assert grid["temp_in"].iloc[k] == pytest.approx(raw["temp_in"].iloc[rows].mean())
        assert grid["phi_h"].iloc[k] == pytest.approx(np.mean(phi[rows]), rel=1e-12)
    assert (report.sensors["n_reports"] == len(raw)).all()


def test_measurement_gaps_are_reported_and_left_missing():
    """Three missing hours of an hourly log: NaN on the grid, one gap per sensor in the
    QualityReport, nothing interpolated."""
    from thermocal.retrofit.data import prepare_measurements

    raw = _raw_log("1h", 48)
    raw = raw.drop(raw.index[10:13])
    grid, report = prepare_measurements(raw, "1h")
    assert len(grid) == 48
    assert grid.iloc[10:13].isna().all().all() and grid.drop(grid.index[10:13]).notna().all().all()
    assert set(report.gaps["sensor"]) == set(grid.columns)
    assert (report.gaps["duration_hours"] == 4.0).all() and (report.gaps["n_missing"] == 3).all()


def test_steady_states_with_indoor_balance_every_node_but_the_air():
    from thermocal.retrofit.model import steady_states_with_indoor

    m = _model()
    p = {k: np.array([v, 1.5 * v]) for k, v in initial_params_si(m).items()}
    a, b = system_matrices(m.conductances(), p)
    u = np.array([-3.0, 8.0, 2500.0, 800.0, 300.0, 400.0])  # Te, Tgr, phi_h, gains
    x = steady_states_with_indoor(a, b, u, 21.0)
    assert np.allclose(x[:, 0], 21.0)
    rates = np.einsum("nij,nj->ni", a, x) + np.einsum("nij,j->ni", b, u)
    assert np.allclose(rates[:, 1:], 0.0, atol=1e-12)
    # a heated building: the air node needs heat, i.e. loses it at this state
    assert np.all(rates[:, 0] < 0)


def test_binned_monthly_demand_equals_the_hourly_series():
    """The parallel binned kernel (all draws) and the hourly kernel (the estimate) agree, with
    a 24-h set-point profile, varying weather and sun across a month boundary."""
    m = _model()
    idx = pd.date_range("2001-01-20", periods=24 * 20, freq="h", tz="UTC")
    hours = np.arange(len(idx))
    inputs = pd.DataFrame(
        {
            "Te": 2.0 + 6.0 * np.sin(2 * np.pi * hours / 24.0) + 0.05 * hours,
            "Tgr": 8.0,
            "phi_sol": np.clip(4000.0 * np.sin(2 * np.pi * (hours - 6) / 24.0), 0.0, None),
            "phi_abs_roof": 0.0,
            "phi_abs_walls": 0.0,
        },
        index=idx,
    )
    profile = np.where((np.arange(24) >= 6) & (np.arange(24) < 22), 21.0, 17.0)
    p = {k: np.array([v, 1.3 * v]) for k, v in initial_params_si(m).items()}
    retro = m.envelope.with_measures({"roof": 0.18, "windows": 0.76})
    res = simulate_demand(m, p, [m.envelope, retro], inputs, profile)
    for s in range(2):
        hourly = pd.Series(res.hourly[s], index=idx)
        brute = monthly_energy_kwh(hourly).to_numpy()
        assert np.allclose(res.monthly[s, 0], brute, rtol=1e-10, atol=1e-9)
        assert brute[0] > 0 and brute[1] > 0  # both months counted
    assert np.all(res.monthly[1, :, :2] < res.monthly[0, :, :2])  # the retrofit saves


def test_demand_holds_the_24h_profile_as_hourly_means():
    """Ti is the model input in demand mode: the profile's value of hour h is the mean indoor
    temperature over [h, h+1) (interval means labelled by their start, as measured), so the
    set point at the end of the step [t, t+1h), the boundary between two hours, is the mean of
    the two hours' values, as the heat fit's controller takes the measured series
    (``gate.heat_to_follow``). With heat needed every hour the simulated indoor temperature
    ends every step on its set point, and the mean of a step's two ends reproduces the hour's
    profile value wherever the profile is linear (hours 1-22 of a ramp); the next hour's value
    at the end of the step (until 2026-11-30) shifted it by one hour, 1/8 K here."""
    from thermocal.retrofit.demand import setpoint_series
    from thermocal.retrofit.model import discrete_system_matrices
    from thermocal.retrofit.simulation import ideal_heating_batch

    m = _model()
    idx = pd.date_range("2001-01-10", periods=24 * 5, freq="h", tz="UTC")
    profile = 18.0 + np.arange(24) / 8.0  # every hour a different value
    sp = setpoint_series(idx, profile)
    assert sp[0] == 0.5 * (profile[0] + profile[1])
    assert sp[23] == 0.5 * (profile[23] + profile[0])
    p = {k: np.array([v]) for k, v in initial_params_si(m).items()}
    ad, bd = discrete_system_matrices(m.conductances(), p, 3600.0, indoor_input=True)
    u = np.tile([-8.0, 6.0, 0.0, 0.0, 0.0], (len(idx), 1))
    x0 = np.full((1, ad.shape[1]), 10.0)
    heat, temp_in, _ = ideal_heating_batch(ad, bd, x0, u, sp)
    assert np.all(heat > 0)
    np.testing.assert_allclose(temp_in[0], sp, atol=1e-9)
    hour_mean = 0.5 * (temp_in[0][:-1] + temp_in[0][1:])  # over the steps 1 .. n-1
    hours = np.asarray(idx.hour)[1:]
    ramp = (hours >= 1) & (hours <= 22)
    np.testing.assert_allclose(hour_mean[ramp], profile[hours[ramp]], atol=1e-9)
    # steps shorter than an hour: the hour's value inside it, the mean at its end
    quarter = pd.date_range("2001-01-10", periods=8, freq="15min", tz="UTC")
    sq = setpoint_series(quarter, profile)
    assert list(sq[:3]) == [profile[0]] * 3 and list(sq[4:7]) == [profile[1]] * 3
    assert sq[3] == 0.5 * (profile[0] + profile[1]) and sq[7] == 0.5 * (profile[1] + profile[2])


def test_air_change_rate_sets_the_prior_of_the_extra_loss():
    """``air_change_rate`` in the building file (1/h; a blower-door test's n50 / 20, or a
    ventilation's flow over the volume) is the median of ``H_est``'s prior: rho c n V plus the
    thermal bridges and doors; the default is the standard 0.5 1/h."""
    from pathlib import Path

    from thermocal.io.envelope import read_envelope
    from thermocal.retrofit.model import build_fifth_order_model

    path = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_house"
    building = read_envelope(path / "building.yaml")
    default = build_fifth_order_model(building).audit_h_est
    tight = build_fifth_order_model(building.model_copy(update={"air_change_rate": 0.1}))
    assert building.air_change_rate == 0.5
    assert default - tight.audit_h_est == pytest.approx(0.4 * building.volume / 3.0, rel=1e-12)
    lo, _, hi, _ = tight.estimated["H_est"]
    assert lo < tight.audit_h_est < hi
