"""The report's assumptions say where each economic value comes from (fuzzing round 5)."""

from __future__ import annotations

from thermocal.retrofit.config import parse_config
from thermocal.retrofit.report import ECONOMICS_SOURCES, economics_source


def _cfg(economics=None, measurements=None):
    return parse_config(
        {
            "building": "b.yaml",
            "measurements": {"file": "m.csv", **(measurements or {})},
            "weather": {"file": "w.epw"},
            **({"economics": economics} if economics is not None else {}),
        }
    )


def test_the_oil_defaults_keep_their_documented_sources():
    config = _cfg()
    for key in ("system_efficiency", "energy_price", "emission_factor"):
        assert economics_source(config, key) == ECONOMICS_SOURCES[key]


def test_a_given_value_a_carrier_default_and_the_measured_boiler_are_named():
    """Before, every source text described heating oil: a gas house's 0.240 factor was
    "heating oil 310 g", a measured boiler's 0.95 "an assumption ... no measurement"."""
    gas = _cfg({"energy_carrier": "natural gas"})
    assert "natural gas 240 g CO2-eq/kWh" in economics_source(gas, "emission_factor")
    assert economics_source(gas, "energy_price").startswith("not natural gas's")
    given = _cfg({"energy_carrier": "natural gas", "energy_price": 0.1})
    assert economics_source(given, "energy_price") == (
        "given in the configuration (economics.energy_price)"
    )
    pump = _cfg({"energy_carrier": "heat pump"})
    assert "an assumed seasonal COP" in economics_source(pump, "system_efficiency")
    fuel = _cfg(measurements={"heat_source": "fuel_meter", "boiler_efficiency": 0.95,
                              "columns": {"heat": "gas_m3"}, "heat_unit": "m3",
                              "fuel_kWh_per_unit": 10.4})  # fmt: skip
    assert fuel.economics.system_efficiency == 0.95
    assert economics_source(fuel, "system_efficiency").startswith("the measured boiler's")


def test_district_heating_is_named_as_such_not_as_electricity_or_oil():
    heat = _cfg({"energy_carrier": "district heating"})
    assert "metered at the building's substation" in economics_source(heat, "system_efficiency")
    factor = economics_source(heat, "emission_factor")
    assert "kept as a placeholder" in factor and "district heating's depends" in factor
