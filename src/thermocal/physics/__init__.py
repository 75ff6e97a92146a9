"""Building physics as pure functions in SI units (temperatures in C).

Submodules: :mod:`~thermocal.physics.solar` (sun position, irradiance on surfaces, window and
opaque solar gains; ISO 52010-1, ISO 52016-1), :mod:`~thermocal.physics.surfaces` (surface
heat-transfer coefficients; ISO 52016-1, ISO 6946).
"""

from thermocal.physics import solar, surfaces
from thermocal.physics.solar import (
    interval_solar_position,
    irradiance_on_surface,
    irradiance_on_surfaces,
    opaque_solar_gains,
    solar_position,
    window_solar_gains,
)

__all__ = [
    "solar",
    "surfaces",
    "solar_position",
    "interval_solar_position",
    "irradiance_on_surface",
    "irradiance_on_surfaces",
    "window_solar_gains",
    "opaque_solar_gains",
]
