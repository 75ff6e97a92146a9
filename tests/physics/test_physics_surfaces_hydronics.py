"""ISO 52016-1 surface coefficients and hydronic heating power."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.physics import hydronics, surfaces


# ---------------------------------------------------------------------------------------------
# surfaces (ISO 52016-1 Table 25, ISO 6946 Table 7 / Annex C)
# ---------------------------------------------------------------------------------------------
def test_convective_coefficients_by_heat_flow_direction():
    assert surfaces.internal_convective_coefficient("upwards") == 5.0
    assert surfaces.internal_convective_coefficient("horizontal") == 2.5
    assert surfaces.internal_convective_coefficient("downwards") == 0.7
    assert surfaces.internal_convective_coefficient("up") == 5.0
    assert surfaces.external_convective_coefficient() == 20.0
    assert surfaces.external_convective_coefficient(4.0) == pytest.approx(20.0)  # 4 + 4 v
    np.testing.assert_allclose(surfaces.external_convective_coefficient([0.0, 2.5]), [4.0, 14.0])


def test_radiative_coefficient_formula_matches_tables():
    # ISO 6946 Annex C: h_r0 = 4 sigma T^3 = 5.7 at 20 C, 4.6 at 0 C (rounded)
    assert surfaces.radiative_coefficient(1.0, 20.0) == pytest.approx(5.7, abs=0.02)
    assert surfaces.radiative_coefficient(1.0, 0.0) == pytest.approx(4.6, abs=0.03)
    assert surfaces.radiative_coefficient(0.9, 20.0) == pytest.approx(5.13, abs=0.02)


def test_surface_resistances_reproduce_iso6946_table7():
    """R_si 0.10 (up), 0.13 (horizontal), 0.17 (down); R_se 0.04 m2K/W."""
    assert surfaces.internal_surface_resistance("upwards") == pytest.approx(0.10, abs=0.005)
    assert surfaces.internal_surface_resistance("horizontal") == pytest.approx(0.13, abs=0.005)
    assert surfaces.internal_surface_resistance("downwards") == pytest.approx(0.17, abs=0.005)
    assert surfaces.external_surface_resistance() == pytest.approx(0.04, abs=0.002)
    h_ci, h_ri = surfaces.internal_surface_coefficient("horizontal", split=True)
    assert (h_ci, h_ri) == (2.5, pytest.approx(5.13))
    h_ce, h_re = surfaces.external_surface_coefficient(split=True)
    assert (h_ce, h_re) == (20.0, pytest.approx(4.14))
    assert surfaces.external_surface_coefficient(emissivity=0.45) == pytest.approx(20 + 2.07)


def test_heat_flow_direction_from_tilt():
    assert surfaces.heat_flow_direction(30) == "upwards"  # roof in heating
    assert surfaces.heat_flow_direction(90) == "horizontal"
    assert surfaces.heat_flow_direction(65) == "horizontal"  # within 30 deg of horizontal
    assert surfaces.heat_flow_direction(180) == "downwards"  # floor in heating
    assert surfaces.heat_flow_direction(180, heat_flows_outwards=False) == "upwards"


def test_surface_conductance():
    assert surfaces.surface_conductance(10.0) == pytest.approx(10 * 7.63)
    assert surfaces.surface_conductance(10.0, "upwards", part="convective") == 50.0
    assert surfaces.surface_conductance(10.0, side="external") == pytest.approx(241.4)
    assert (
        surfaces.surface_conductance(10.0, side="external", wind_speed=1.0, part="convective")
        == 80.0
    )
    with pytest.raises(ThermocalInputError, match="heat_flow_direction"):
        surfaces.surface_conductance(10.0, "sideways")
    with pytest.raises(ThermocalInputError, match="area"):
        surfaces.surface_conductance(-1.0)
    with pytest.raises(ThermocalInputError, match="emissivity"):
        surfaces.internal_surface_coefficient(emissivity=1.5, temp_mean=20)
    with pytest.raises(ThermocalInputError, match="wind_speed"):
        surfaces.external_convective_coefficient(-3.0)


# ---------------------------------------------------------------------------------------------
# hydronics
# ---------------------------------------------------------------------------------------------
def test_water_properties_against_tables():
    # CRC Handbook / IAPWS-95 at 0.1 MPa
    np.testing.assert_allclose(
        hydronics.water_density([3.98, 20.0, 50.0, 80.0]),
        [999.972, 998.207, 988.04, 971.80],
        atol=0.02,
    )
    assert hydronics.water_specific_heat(20.0) == pytest.approx(4184.1, abs=0.5)
    assert hydronics.water_specific_heat(37.0) == pytest.approx(4179.6, abs=1.0)
    # enthalpy difference = integral of cp: close to cp(mean) * dT
    dh = hydronics.water_enthalpy_difference(70.0, 50.0)
    assert dh == pytest.approx(20 * hydronics.water_specific_heat(60.0), rel=1e-3)


def test_one_cubic_metre_per_hour_and_20_kelvin_is_about_23_kw():
    """1 m3/h, 70/50 C, meter in the return: 988.0 kg/m3 * 1/3600 m3/s * 4185 * 20 = 22.97 kW."""
    power = hydronics.heating_power(1.0 / 3600.0, 70.0, 50.0)
    assert power == pytest.approx(22_970, rel=2e-3)
    assert 22_500 < hydronics.heating_power(1.0 / 3600.0, 40.0, 20.0) < 23_500
    # supply-side meter sees the lighter water
    assert hydronics.heating_power(1 / 3600, 70, 50, meter_location="supply") < power


def test_heating_power_series_and_arrays():
    index = pd.date_range("2019-02-02", periods=3, freq="1h", tz="Etc/GMT-1")
    flow = pd.Series([0.0, 1e-4, 2e-4], index=index)
    power = hydronics.heating_power(flow, [60.0, 60.0, 60.0], [45.0, 45.0, 45.0])
    assert isinstance(power, pd.Series) and power.index.equals(index)
    assert power.iloc[0] == 0.0
    assert power.iloc[2] == pytest.approx(2 * power.iloc[1])
    assert hydronics.heating_power(1e-4, 40.0, 41.0) < 0  # return warmer: negative, not hidden


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        ((-1e-4, 60.0, 40.0), "negative"),
        ((1.0, 60.0, 40.0), "m3/h"),
        ((1e-4, 333.15, 313.15), "Kelvin"),
        ((1e-4, 160.0, 40.0), "temp_supply"),
    ],
)
def test_heating_power_bad_input(args, fragment):
    with pytest.raises(ThermocalInputError, match=fragment):
        hydronics.heating_power(*args)
