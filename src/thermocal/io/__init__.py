"""Readers that turn user files into standard frames with SI units (temperatures in C).

Submodules
----------
:mod:`~thermocal.io.weather`
    Weather files (EPW, TMY3, CSV) -> standard frame + metadata; resampling to the model step.
:mod:`~thermocal.io.measurements`
    Sensor logs (long or wide CSV, irregular event-based) -> regular grid + quality report.
:mod:`~thermocal.io.building`
    Building description files (YAML/TOML) validated with clear, unit-aware messages.
"""

from thermocal.io.building import Building, building_from_dict, read_building
from thermocal.io.measurements import QualityReport, read_measurements, resample_measurements
from thermocal.io.weather import (
    read_epw,
    read_tmy3,
    read_weather,
    read_weather_csv,
    resample_weather,
    weather_step,
)

__all__ = [
    "Building",
    "QualityReport",
    "building_from_dict",
    "read_building",
    "read_epw",
    "read_measurements",
    "read_tmy3",
    "read_weather",
    "read_weather_csv",
    "resample_measurements",
    "resample_weather",
    "weather_step",
]
