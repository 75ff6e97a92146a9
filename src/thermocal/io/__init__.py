"""Readers that turn user files into standard frames with SI units (temperatures in C).

Submodules
----------
:mod:`~thermocal.io.weather`
    Weather files (EPW, TMY3, CSV) -> standard frame + metadata; resampling to the model step.
:mod:`~thermocal.io.measurements`
    Sensor logs (long or wide CSV, irregular event-based) -> regular grid + quality report.
:mod:`~thermocal.io.envelope`
    Envelope descriptions (the retrofit analysis' building file, YAML/TOML) validated with
    clear, unit-aware messages. The detailed multi-zone model is :mod:`thermocal.multizone`.
"""

from thermocal.io.envelope import (
    EnvelopeDescription,
    building_from_dict,
    envelope_from_dict,
    read_building,
    read_envelope,
)
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
    "EnvelopeDescription",
    "QualityReport",
    "building_from_dict",
    "envelope_from_dict",
    "read_building",
    "read_envelope",
    "read_epw",
    "read_measurements",
    "read_tmy3",
    "read_weather",
    "read_weather_csv",
    "resample_measurements",
    "resample_weather",
    "weather_step",
]


def __getattr__(name: str):
    if name == "Building":  # renamed: not the multi-zone model thermocal.multizone.Building
        import warnings

        warnings.warn(
            "thermocal.io.Building is now thermocal.io.EnvelopeDescription",
            DeprecationWarning,
            stacklevel=2,
        )
        return EnvelopeDescription
    raise AttributeError(f"module 'thermocal.io' has no attribute {name!r}")
