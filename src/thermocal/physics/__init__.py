"""Building physics as pure functions in SI units (temperatures in C).

Submodules
----------
:mod:`~thermocal.physics.solar`
    Sun position, irradiance on tilted surfaces, window (``phi_sol``) and opaque (``phi_re``)
    solar gains (ISO 52010-1, ISO 52016-1, ISO 13790).
:mod:`~thermocal.physics.surfaces`
    Surface heat-transfer coefficients (ISO 52016-1 Table 25, ISO 6946).
:mod:`~thermocal.physics.ground`
    ISO 13370 ground heat transfer; ground temperature at depth (Kusuda, Zuercher & Frank).
:mod:`~thermocal.physics.hydronics`
    Heating power from water flow and temperatures with temperature-dependent water properties.
"""

from thermocal.physics import ground, hydronics, solar, surfaces
from thermocal.physics.ground import (
    ground_heat_transfer_coefficient,
    ground_temperature,
    ground_temperature_parameters,
    iso13370_heated_basement,
    iso13370_slab_on_ground,
    iso13370_unheated_basement,
)
from thermocal.physics.hydronics import heating_power, water_density, water_specific_heat
from thermocal.physics.solar import (
    building_solar_gains,
    interval_solar_position,
    irradiance_on_surface,
    irradiance_on_surfaces,
    opaque_solar_gains,
    solar_position,
    window_solar_gains,
)
from thermocal.physics.surfaces import (
    external_surface_coefficient,
    internal_surface_coefficient,
    surface_conductance,
)

__all__ = [
    "ground",
    "hydronics",
    "solar",
    "surfaces",
    "solar_position",
    "interval_solar_position",
    "irradiance_on_surface",
    "irradiance_on_surfaces",
    "window_solar_gains",
    "opaque_solar_gains",
    "building_solar_gains",
    "internal_surface_coefficient",
    "external_surface_coefficient",
    "surface_conductance",
    "iso13370_slab_on_ground",
    "iso13370_heated_basement",
    "iso13370_unheated_basement",
    "ground_heat_transfer_coefficient",
    "ground_temperature",
    "ground_temperature_parameters",
    "heating_power",
    "water_density",
    "water_specific_heat",
]
