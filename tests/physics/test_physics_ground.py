"""ISO 13370 ground heat transfer (hand calculations) and the ground temperature at depth."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.physics import ground


# ---------------------------------------------------------------------------------------------
# ISO 13370: hand calculations
# ---------------------------------------------------------------------------------------------
def test_slab_on_ground_uninsulated_hand_calculation():
    """10 m x 10 m slab, w = 0.3 m, lambda = 2.0 W/(m K), R_f = 0.

    B' = 100 / (0.5 * 40) = 5.0 m
    d_t = 0.3 + 2.0 * (0.17 + 0 + 0.04) = 0.72 m  (< B': uninsulated formula)
    U = 2 * 2.0 / (pi * 5 + 0.72) * ln(pi * 5 / 0.72 + 1)
      = 4 / 16.4280 * ln(22.8166) = 0.243487 * 3.127487 = 0.76150 W/(m2 K)
    """
    assert ground.characteristic_dimension(100.0, 40.0) == pytest.approx(5.0)
    assert ground.equivalent_thickness(2.0, 0.0, wall_thickness=0.3) == pytest.approx(0.72)
    u = ground.iso13370_slab_on_ground(100.0, 40.0, wall_thickness=0.3, soil_conductivity=2.0)
    assert u == pytest.approx(0.76150, abs=5e-5)


def test_slab_on_ground_well_insulated_hand_calculation():
    """Same slab with R_f = 5 m2K/W: d_t = 0.3 + 2 * 5.21 = 10.72 m >= B' = 5 m.

    U = 2.0 / (0.457 * 5 + 10.72) = 2.0 / 13.005 = 0.153787 W/(m2 K)
    """
    u = ground.iso13370_slab_on_ground(
        100.0, 40.0, wall_thickness=0.3, floor_resistance=5.0, soil_conductivity=2.0
    )
    assert u == pytest.approx(0.153787, abs=1e-6)


def test_slab_formulas_meet_at_the_switch():
    """At d_t = B' both ISO 13370 formulas give 2 ln(pi+1)/(pi+1) ~ 1/1.457 lambda/B'."""
    lam, b = 2.0, 5.0
    below = 2 * lam / (math.pi * b + b) * math.log(math.pi + 1)
    above = lam / (0.457 * b + b)
    assert below == pytest.approx(above, rel=1e-3)
    # and the implementation is continuous across the switch (R_f chosen so d_t = B' +/- eps)
    r_switch = (b - 0.3) / lam - 0.21
    u_minus = ground.iso13370_slab_on_ground(
        100, 40, wall_thickness=0.3, floor_resistance=r_switch - 1e-6
    )
    u_plus = ground.iso13370_slab_on_ground(
        100, 40, wall_thickness=0.3, floor_resistance=r_switch + 1e-6
    )
    assert u_minus == pytest.approx(u_plus, rel=1e-3)


def test_slab_u_decreases_with_size_and_insulation():
    small = ground.iso13370_slab_on_ground(25, 20, wall_thickness=0.3)
    large = ground.iso13370_slab_on_ground(400, 80, wall_thickness=0.3)
    insulated = ground.iso13370_slab_on_ground(400, 80, wall_thickness=0.3, floor_resistance=2.0)
    assert small > large > insulated


def test_heated_basement_hand_calculation():
    """10 x 10 m heated basement, z = 2 m, w = 0.3 m, lambda = 2, R_f = 0, R_w = 0.

    d_t = 0.72 m; d_t + z/2 = 1.72 < B' = 5:
      U_bf = 4 / (15.70796 + 1.72) * ln(15.70796 / 1.72 + 1) = 0.229516 * 2.315752 = 0.531503
    d_w = 2 * (0.13 + 0 + 0.04) = 0.34 m < d_t -> d_t replaced by d_w in the first factor:
      U_bw = 2 * 2 / (pi * 2) * (1 + 0.5 * 0.34 / (0.34 + 2)) * ln(2 / 0.34 + 1)
           = 0.636620 * 1.072650 * 1.928960 = 1.317229
    H_g = 100 * 0.531503 + 2 * 40 * 1.317229 = 158.529 W/K
    """
    result = ground.iso13370_heated_basement(100.0, 40.0, 2.0, wall_thickness=0.3)
    assert result["u_floor"] == pytest.approx(0.531503, abs=2e-6)
    assert result["u_wall"] == pytest.approx(1.317229, abs=2e-6)
    assert result["heat_transfer_coefficient"] == pytest.approx(158.529, abs=1e-3)


def test_unheated_basement_hand_calculation():
    """Cellar ceiling U_f = 1.0 over the basement above, with h = 0.5 m, U_w = 1.5, V = 200 m3,
    n = 0.3 /h:

      basement = 100 * 0.531503 + 2 * 40 * 1.317229 + 0.5 * 40 * 1.5 + 0.33 * 0.3 * 200
               = 53.1503 + 105.3783 + 30 + 19.8 = 208.329 W/K
      1/U = 1/1.0 + 100/208.329 = 1.480011 -> U = 0.675671 W/(m2 K)
    """
    result = ground.iso13370_unheated_basement(
        100.0,
        40.0,
        2.0,
        u_ceiling=1.0,
        wall_thickness=0.3,
        u_wall_above_ground=1.5,
        height_above_ground=0.5,
        basement_volume=200.0,
        air_changes=0.3,
    )
    assert result["basement_loss_coefficient"] == pytest.approx(208.329, abs=1e-3)
    assert result["u_equivalent"] == pytest.approx(0.675671, abs=2e-6)
    assert result["heat_transfer_coefficient"] == pytest.approx(67.5671, abs=2e-4)
    # an insulated ceiling dominates the series path
    insulated = ground.iso13370_unheated_basement(
        100.0,
        40.0,
        2.0,
        u_ceiling=0.19,
        wall_thickness=0.3,
        u_wall_above_ground=1.5,
        height_above_ground=0.5,
        basement_volume=200.0,
    )
    assert insulated["u_equivalent"] < 0.19


def test_ground_heat_transfer_coefficient_dispatch():
    slab = ground.ground_heat_transfer_coefficient(100, 40, wall_thickness=0.3)
    assert slab == pytest.approx(76.150, abs=5e-3)
    with_psi = ground.ground_heat_transfer_coefficient(
        100, 40, wall_thickness=0.3, linear_thermal_transmittance=0.1
    )
    assert with_psi == pytest.approx(slab + 4.0)
    heated = ground.ground_heat_transfer_coefficient(
        100, 40, basement="heated", wall_thickness=0.3, depth=2.0
    )
    assert heated == pytest.approx(158.529, abs=1e-3)
    with pytest.raises(ThermocalInputError, match="depth"):
        ground.ground_heat_transfer_coefficient(100, 40, basement="heated", wall_thickness=0.3)
    with pytest.raises(ThermocalInputError, match="basement"):
        ground.ground_heat_transfer_coefficient(100, 40, basement="cave", wall_thickness=0.3)


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"area": -1.0, "perimeter": 40.0}, "area"),
        ({"area": 100.0, "perimeter": 0.0}, "perimeter"),
        ({"area": 100.0, "perimeter": 10.0}, "swapped"),
    ],
)
def test_iso13370_bad_input(kwargs, fragment):
    with pytest.raises(ThermocalInputError, match=fragment):
        ground.iso13370_slab_on_ground(**kwargs, wall_thickness=0.3)


def test_unheated_basement_flags_u_typo():
    with pytest.raises(ThermocalInputError, match="typo"):
        ground.iso13370_unheated_basement(
            100,
            40,
            2,
            u_ceiling=19.0,
            wall_thickness=0.3,
            u_wall_above_ground=1.5,
            height_above_ground=0.5,
            basement_volume=200,
        )


# ---------------------------------------------------------------------------------------------
# ground temperature
# ---------------------------------------------------------------------------------------------
def _year(freq="1D", year=2023):
    return pd.date_range(f"{year}-01-01", periods=365 if freq == "1D" else 8760, freq=freq)


def test_ground_temperature_at_surface_is_the_surface_wave():
    times = _year()
    t = ground.ground_temperature(times, 0.0, annual_mean=10.0, amplitude=9.0, phase_day=20.0)
    assert t.min() == pytest.approx(1.0, abs=1e-3)
    assert t.max() == pytest.approx(19.0, abs=1e-3)
    assert t.idxmin().day_of_year - 1 == 20


def test_ground_temperature_damping_and_lag():
    """Amplitude ratio exp(-dz sqrt(pi/(365 a))) and delay dz/2 sqrt(365/(pi a)) days."""
    alpha = 6.45e-7
    a_day = alpha * 86400
    times = pd.date_range("2023-01-01", periods=365 * 24, freq="1h")
    params = {"annual_mean": 10.0, "amplitude": 9.0, "phase_day": 20.0, "diffusivity": alpha}
    deep = ground.ground_temperature(times, 2.0, **params)
    amplitude = 0.5 * (deep.max() - deep.min())
    assert amplitude == pytest.approx(
        9.0 * math.exp(-2.0 * math.sqrt(math.pi / (365 * a_day))), rel=1e-4
    )
    lag = 1.0 * math.sqrt(365 / (math.pi * a_day))
    day_of_min = (deep.idxmin() - times[0]) / pd.Timedelta(days=1)
    assert day_of_min == pytest.approx(20.0 + lag, abs=0.05)
    very_deep = ground.ground_temperature(times, 30.0, **params)
    assert very_deep.max() - very_deep.min() < 0.01
    assert very_deep.mean() == pytest.approx(10.0, abs=1e-3)


def test_ground_temperature_solves_the_heat_equation():
    """dT/dt = alpha d2T/dz2 by finite differences at z = 1.5 m, several days."""
    alpha = 8e-7
    params = {"annual_mean": 9.0, "amplitude": 10.0, "phase_day": 25.0, "diffusivity": alpha}
    times = pd.DatetimeIndex(["2023-02-10", "2023-05-01", "2023-08-20", "2023-11-11"])
    dt = pd.Timedelta(hours=1)
    dz = 0.01
    z = 1.5
    lhs = (
        ground.ground_temperature(times + dt, z, **params).to_numpy()
        - ground.ground_temperature(times - dt, z, **params).to_numpy()
    ) / (2 * dt.total_seconds())
    curvature = (
        ground.ground_temperature(times, z + dz, **params).to_numpy()
        - 2 * ground.ground_temperature(times, z, **params).to_numpy()
        + ground.ground_temperature(times, z - dz, **params).to_numpy()
    ) / dz**2
    # the model's year is 365 days; allow for the finite-difference error
    np.testing.assert_allclose(lhs, alpha * curvature, rtol=2e-3, atol=1e-10)


def test_ground_temperature_parameters_recover_known_wave():
    times = pd.date_range("2023-01-01", periods=8760, freq="1h", tz="Etc/GMT-1")
    rng = np.random.default_rng(3)
    day = (times.day_of_year - 1) + times.hour / 24
    temp = 9.0 - 8.0 * np.cos(2 * np.pi / 365 * (day - 22.0)) + rng.normal(0, 2.0, len(times))
    temp += 3.0 * np.cos(2 * np.pi * times.hour / 24)  # daily cycle averages out
    weather = pd.DataFrame({"temp_air": temp}, index=times)
    params = ground.ground_temperature_parameters(weather)
    assert params["annual_mean"] == pytest.approx(9.0, abs=0.1)
    assert params["amplitude"] == pytest.approx(8.0, abs=0.15)
    assert params["phase_day"] == pytest.approx(22.0, abs=1.5)


def test_ground_temperature_parameters_zurich(shared_data):
    from thermocal.io.weather import read_weather

    weather, _ = read_weather(shared_data("weather_switzerland", "Zuerich-SMA_2015.epw"))
    params = ground.ground_temperature_parameters(weather)
    assert params["annual_mean"] == pytest.approx(10.63, abs=0.05)
    assert 7.0 < params["amplitude"] < 12.0
    assert 5.0 < params["phase_day"] < 45.0  # coldest in January
    at_2m = ground.ground_temperature(weather.index, 2.0, **params)
    # at 2 m the soil is warmer than the air in winter and colder in summer
    assert (
        at_2m[weather.index.month == 1].mean()
        > weather["temp_air"][weather.index.month == 1].mean()
    )
    assert (
        at_2m[weather.index.month == 7].mean()
        < weather["temp_air"][weather.index.month == 7].mean()
    )


def test_ground_temperature_bad_input():
    with pytest.raises(ThermocalInputError, match="diffusivity"):
        ground.ground_temperature(
            _year(), 2.0, annual_mean=10, amplitude=9, phase_day=20, diffusivity=0.05
        )
    with pytest.raises(ThermocalInputError, match="depth"):
        ground.ground_temperature(_year(), -2.0, annual_mean=10, amplitude=9, phase_day=20)
    short = pd.DataFrame(
        {"temp_air": np.zeros(48)}, index=pd.date_range("2023-01-01", periods=48, freq="1h")
    )
    with pytest.raises(ThermocalInputError, match="300"):
        ground.ground_temperature_parameters(short)


# ISO 13370 periodic (monthly) heat flow ------------------------------------------------------
def test_periodic_penetration_depth_reproduces_table_h1():
    """ISO 13370 Table H.1 (2.2 / 3.2 / 4.2 m) from Table 7's lambda and rho c."""
    from thermocal.physics.ground import periodic_penetration_depth

    assert periodic_penetration_depth(1.5, 3.0e6) == pytest.approx(2.2, abs=0.05)
    assert periodic_penetration_depth(2.0, 2.0e6) == pytest.approx(3.2, abs=0.05)
    assert periodic_penetration_depth(3.5, 2.0e6) == pytest.approx(4.2, abs=0.05)
    # by hand: sqrt(3.15e7 * 2 / (pi * 2e6)) = sqrt(10.0268)
    assert periodic_penetration_depth(2.0, 2.0e6) == pytest.approx(3.16651, rel=1e-5)


def test_slab_periodic_coefficients_by_hand():
    """A = 100 m2, P = 40 m, w = 0.3 m, R_f = 0, lambda 2, rho c 2e6, by hand:
    d_t = 0.3 + 2 (0.17 + 0.04) = 0.72 m, delta = 3.16651 m;
    H_pi = 100 * 2 / 0.72 * sqrt(2 / ((1 + 3.16651 / 0.72)^2 + 1)) = 71.56 W/K;
    H_pe = 0.37 * 40 * 2 * ln(3.16651 / 0.72 + 1) = 49.91 W/K."""
    from thermocal.physics.ground import iso13370_slab_periodic_coefficients

    c = iso13370_slab_periodic_coefficients(100.0, 40.0, wall_thickness=0.3)
    assert c["d_t"] == pytest.approx(0.72)
    assert c["delta"] == pytest.approx(3.16651, rel=1e-5)
    assert c["h_pi"] == pytest.approx(71.56, abs=0.01)
    assert c["h_pe"] == pytest.approx(49.91, abs=0.01)
    # insulation lowers both
    ins = iso13370_slab_periodic_coefficients(100.0, 40.0, wall_thickness=0.3, floor_resistance=2.0)
    assert ins["h_pi"] < c["h_pi"] and ins["h_pe"] < c["h_pe"]


def test_monthly_heat_flow_is_the_cosine_form_for_sinusoids():
    """With sinusoidal monthly temperatures the monthly-series form equals ISO 13370's
    ``H_g (Ti - Te) - H_pi Ti_amp cos(2 pi (m - tau + alpha)/12)
    + H_pe Te_amp cos(2 pi (m - tau - beta)/12)``; with a constant internal temperature the
    internal periodic term is zero (only the set point's swing charges the ground)."""
    from thermocal.physics.ground import iso13370_monthly_heat_flow, virtual_ground_temperature

    m = np.arange(1, 13)
    tau = 1.0  # coldest month
    ti = 23.0 - 5.0 * np.cos(2 * np.pi * (m - tau) / 12)
    te = 9.0 - 9.0 * np.cos(2 * np.pi * (m - tau) / 12)
    h_g, h_pi, h_pe = 84.0, 36.0, 30.0
    for alpha, beta in ((0, 1), (1, 2)):
        phi = iso13370_monthly_heat_flow(h_g, h_pi, h_pe, ti, te, lead_months=alpha,
                                         lag_months=beta)  # fmt: skip
        expected = (
            h_g * (23.0 - 9.0)
            - h_pi * 5.0 * np.cos(2 * np.pi * (m - tau + alpha) / 12)
            + h_pe * 9.0 * np.cos(2 * np.pi * (m - tau - beta) / 12)
        )
        np.testing.assert_allclose(phi, expected, atol=1e-9)
    flat = iso13370_monthly_heat_flow(h_g, h_pi, h_pe, np.full(12, 20.0), te)
    np.testing.assert_allclose(
        flat, iso13370_monthly_heat_flow(h_g, 0.0, h_pe, np.full(12, 20.0), te), atol=1e-12
    )
    theta = virtual_ground_temperature(ti, phi, 80.0)
    np.testing.assert_allclose(80.0 * (ti - theta), phi)
    with pytest.raises(ThermocalInputError):
        iso13370_monthly_heat_flow(h_g, h_pi, h_pe, ti[:11], te)
