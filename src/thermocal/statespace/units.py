"""Units of model parameters and data columns, and their conversion to SI.

Every parameter of an :class:`~thermocal.statespace.RCModel` declares the unit its value, bounds and
reported estimate are given in. The engine works in SI (seconds, joules, watts, kelvin) and converts
with the multiplicative factors below. Temperatures (``C``, ``K`` for differences) have factor 1:
node temperatures are kept in degrees Celsius, which is exact for a linear model.
"""

from __future__ import annotations

import math

from thermocal.errors import ThermocalInputError

_SQRT_H = math.sqrt(3600.0)
_SQRT_MIN = math.sqrt(60.0)
_SQRT_D = math.sqrt(86400.0)

#: Factor from the declared unit to SI, for parameter units.
PARAMETER_UNITS: dict[str, float] = {
    # heat capacity [J/K]
    "J/K": 1.0,
    "kJ/K": 1e3,
    "MJ/K": 1e6,
    "GJ/K": 1e9,
    "Wh/K": 3600.0,
    "kWh/K": 3.6e6,
    "MWh/K": 3.6e9,
    # conductance / heat transfer coefficient [W/K]
    "W/K": 1.0,
    "kW/K": 1e3,
    # thermal resistance [K/W]
    "K/W": 1.0,
    "K/kW": 1e-3,
    "K/MW": 1e-6,
    # areas, dimensionless factors, temperatures and temperature standard deviations
    "m2": 1.0,
    "-": 1.0,
    "C": 1.0,
    "K": 1.0,
    # diffusion standard deviation of a state [K/sqrt(s)]
    "K/sqrt(s)": 1.0,
    "K/sqrt(min)": 1.0 / _SQRT_MIN,
    "K/sqrt(h)": 1.0 / _SQRT_H,
    "K/sqrt(d)": 1.0 / _SQRT_D,
}

#: Physical role of a unit, used to check that a parameter fits where it is used.
UNIT_KIND: dict[str, str] = {
    "J/K": "capacity",
    "kJ/K": "capacity",
    "MJ/K": "capacity",
    "GJ/K": "capacity",
    "Wh/K": "capacity",
    "kWh/K": "capacity",
    "MWh/K": "capacity",
    "W/K": "conductance",
    "kW/K": "conductance",
    "K/W": "resistance",
    "K/kW": "resistance",
    "K/MW": "resistance",
    "m2": "area",
    "-": "dimensionless",
    "C": "temperature",
    "K": "temperature",
    "K/sqrt(s)": "diffusion",
    "K/sqrt(min)": "diffusion",
    "K/sqrt(h)": "diffusion",
    "K/sqrt(d)": "diffusion",
}

#: Factor from the unit of a heat-input data column to watts (after any area scale parameter
#: [m2]: a column in W/m2 multiplied by an aperture in m2 gives W).
HEAT_COLUMN_UNITS: dict[str, float] = {
    "W": 1.0,
    "kW": 1e3,
    "MW": 1e6,
    "W/m2": 1.0,
    "kW/m2": 1e3,
}

#: Factor from a time unit to seconds.
TIME_UNITS: dict[str, float] = {
    "s": 1.0,
    "min": 60.0,
    "h": 3600.0,
    "d": 86400.0,
}


def parameter_si_factor(unit: str, *, parameter: str = "?") -> float:
    """Factor converting a parameter value from its declared unit to SI.

    Parameters
    ----------
    unit : str
        Declared unit, one of :data:`PARAMETER_UNITS`.
    parameter : str
        Name of the parameter, for the error message.

    Returns
    -------
    float
        Multiplicative factor to SI [-].
    """
    try:
        return PARAMETER_UNITS[unit]
    except KeyError:
        raise ThermocalInputError(
            f"parameter '{parameter}': unknown unit '{unit}'; use one of "
            f"{', '.join(PARAMETER_UNITS)}"
        ) from None


def time_unit_seconds(unit: str) -> float:
    """Seconds per time unit ``unit`` (``s``, ``min``, ``h``, ``d``)."""
    try:
        return TIME_UNITS[unit]
    except KeyError:
        raise ThermocalInputError(
            f"unknown time unit '{unit}'; use one of {', '.join(TIME_UNITS)}"
        ) from None
