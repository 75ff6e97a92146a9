"""Closed-loop identification of the fifth-order model (``model.calibration: heat``).

Truth made by the fifth-order model itself with a known envelope that is NOT the building
file's: the roof and walls conduct 40 % less than calculated (the prebound effect), so the
calibration must lower the calculated losses. A thermostat holds the indoor temperature on a
day/night profile; the heat meter reads the model's ideal controller with 3 % noise.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from retrofit_synthetic import TMY3, building_dict

TRUE_K_ENV = 0.6
TRUE_H_EST = 40.0  # [W/K]


@pytest.fixture(scope="module")
def closed_loop():
    from thermocal.io.envelope import EnvelopeDescription
    from thermocal.io.weather import read_weather
    from thermocal.physics.ground import ground_temperature_parameters
    from thermocal.retrofit.calibration import initial_params_si, steady_initial_state
    from thermocal.retrofit.correction import scaled_envelope
    from thermocal.retrofit.demand import DEMAND_INPUTS
    from thermocal.retrofit.gate import heat_to_follow_measured
    from thermocal.retrofit.model import build_fifth_order_model, calculated_hlc
    from thermocal.retrofit.workflow import model_inputs

    building = EnvelopeDescription.model_validate(building_dict())
    weather, _ = read_weather(TMY3)
    start = pd.Timestamp("2001-01-10 00:00", tz=weather.index.tz)
    w = weather.loc[(weather.index >= start) & (weather.index < start + pd.Timedelta(days=14))]
    model = build_fifth_order_model(building)
    inp = model_inputs(w, building, ground_temperature_parameters(weather), temp_col="temp_air",
                       solar=True, depth=2.0)  # fmt: skip
    inp["phi_h"] = 0.0
    p = initial_params_si(model)
    p["H_est"] = TRUE_H_EST
    env = scaled_envelope(model.envelope, {"k_env": TRUE_K_ENV})
    setpoint = pd.Series(np.where((inp.index.hour >= 6) & (inp.index.hour < 22), 21.0, 18.0),
                         index=inp.index)  # fmt: skip
    x0 = steady_initial_state(model, p, inp.iloc[:24].mean().to_numpy(float), 20.0)
    heat = heat_to_follow_measured(model, p, env, x0, inp[list(DEMAND_INPUTS)], setpoint)
    rng = np.random.default_rng(5)
    data = inp.copy()
    data["phi_h_measured"] = heat.to_numpy() * (1.0 + rng.normal(0.0, 0.03, len(heat)))
    data["phi_int"] = 0.0
    data["phi_h"] = data["phi_h_measured"]
    data["Ti_measured"] = setpoint.to_numpy() + rng.normal(0.0, 0.03, len(heat))
    truth = calculated_hlc(model.conductances(env)) + TRUE_H_EST
    return model, data, setpoint, truth


def test_heat_fit_lowers_the_calculated_losses(closed_loop):
    """The group corrections fitted to the heat find the true heat loss coefficient, below the
    calculated one, inside the 90 % interval; the published topology (only H_est added)
    cannot go below the calculated conductances and stays too high."""
    from thermocal.retrofit.calibration import RETROFIT_HEAT_BLOCK_H, calibrate_to_heat
    from thermocal.retrofit.model import calculated_hlc

    model, data, setpoint, truth = closed_loop
    calculated = calculated_hlc(model.conductances())
    assert truth < 0.9 * calculated  # below what the published topology can reach
    # as the retrofit analysis makes it: capacities on the hourly, conductances on the daily heat
    cal = calibrate_to_heat(model, data, setpoint, gains=False, correction=True,
                            u_value_rel_std=0.2, block_h=RETROFIT_HEAT_BLOCK_H)  # fmt: skip
    assert abs(cal.heat_loss_coefficient / truth - 1.0) < 0.05, (cal.heat_loss_coefficient, truth)
    lo, hi = np.quantile(cal.heat_loss_coefficient_draws, [0.05, 0.95])
    assert lo <= truth <= hi
    assert cal.correction.factors["k_env"] < 0.95
    published = calibrate_to_heat(model, data, setpoint, gains=False)
    assert published.heat_loss_coefficient > calculated > truth / 0.9


def test_tight_control_selects_the_heat_fit(closed_loop):
    """``model.calibration: auto`` picks the heat fit under a thermostat, the temperature fit
    when the indoor temperature moves with the weather (a heating curve)."""
    from thermocal.retrofit.workflow import calibration_method

    _, data, _, _ = closed_loop
    auto = calibration_method("auto", data)
    assert auto["method"] == "heat" and auto["tight_control"]["tight"]
    assert "closed-loop" in auto["summary"]
    loose = data.copy()
    loose["Ti_measured"] += 0.1 * (loose["Te"] - loose["Te"].mean())
    assert calibration_method("auto", loose)["method"] == "temperature"
    assert calibration_method("temperature", data)["method"] == "temperature"


def test_split_mean_residuals_keeps_the_sum_of_squares():
    """The mean apart from the deviations: with the mean's standard error sd / sqrt(n) the
    weighted sum of squares is the plain one; a smaller standard error weighs the mean more."""
    from thermocal.retrofit.calibration import split_mean_residuals

    e = np.random.default_rng(5).normal(0.3, 1.0, 21)
    plain = split_mean_residuals(e, 0.8)
    np.testing.assert_allclose(plain, e / 0.8)
    same = split_mean_residuals(e, 0.8, 0.8 / np.sqrt(len(e)))
    assert same @ same == pytest.approx(plain @ plain)
    tight = split_mean_residuals(e, 0.8, 0.05)
    assert tight[-1] == pytest.approx(e.mean() / 0.05)
    np.testing.assert_allclose(tight[:-1], (e - e.mean()) / 0.8)


def test_mean_heat_sd_ignores_what_the_parameters_explain():
    """Residuals the parameters could remove (in the Jacobian's span) are not noise: a daily
    misfit proportional to the temperature difference plus white noise of 0.1 kW gives the
    noise's standard error of the mean (0.1 / sqrt(n)), not the misfit's."""
    from thermocal.retrofit.calibration import mean_heat_sd

    rng = np.random.default_rng(11)
    n = 400
    dt = 15.0 + 5.0 * np.sin(np.arange(n) / 3.0)
    jac = np.column_stack([dt, np.ones(n)])
    noise = rng.normal(0.0, 0.1, n)
    e = 0.08 * dt + 0.5 + noise
    sd = mean_heat_sd(e, jac, 2)
    assert sd == pytest.approx(0.1 / np.sqrt(n), rel=0.15)
    # autocorrelated noise widens it: AR(1) with rho 0.6 -> sqrt((1 + 0.6) / (1 - 0.6)) = 2
    ar = np.zeros(n)
    for i in range(1, n):
        ar[i] = 0.6 * ar[i - 1] + rng.normal(0.0, 0.1)
    assert mean_heat_sd(ar, jac, 2) / (ar.std() / np.sqrt(n)) == pytest.approx(2.0, rel=0.25)
