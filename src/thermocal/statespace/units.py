"""Units of model parameters and data columns, and their conversion to SI.

Every parameter of an :class:`~thermocal.statespace.RCModel` declares the unit its value, bounds and
reported estimate are given in. The engine works in SI (seconds, joules, watts, kelvin) and converts
with the multiplicative factors below. Temperatures (``C``, ``K`` for differences) have factor 1:
node temperatures are kept in degrees Celsius, which is exact for a linear model.
"""

from __future__ import annotations

import math

import numpy as np

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

#: Declared heat-column unit -> (the unit a factor 1000 off, the factor to it).
HEAT_UNIT_SLIPS: dict[str, list[tuple[str, float]]] = {
    "W": [("kW", 1e3)], "kW": [("W", 1e-3), ("MW", 1e3)], "MW": [("kW", 1e-3)],
    "W/m2": [("kW/m2", 1e3)], "kW/m2": [("W/m2", 1e-3)],
}  # fmt: skip

#: Heat loss coefficients of buildings [W/K]: from a test cell of about a cubic metre (a few
#: W/K) to the largest single buildings (a hospital or terminal of some 100,000 m2 floor,
#: a few 10^4 W/K). A house read with its heating in W as kW lies a factor 1000 above
#: (100-500 kW/K), read in kW as W a factor 1000 below (0.05-0.5 W/K).
PLAUSIBLE_HEAT_LOSS_W_PER_K = (0.5, 5.0e4)


def heat_unit_slip(heat_loss: float, unit: str) -> tuple[str, float] | None:
    """The unit a heat column was probably written in, judged by the heat loss coefficient.

    Parameters
    ----------
    heat_loss : float [W/K]
        Heat loss coefficient with the column read in ``unit`` (proportional to the column:
        an energy balance, or a fit with no other heat input of known power).
    unit : str
        Declared unit of the column, a key of :data:`HEAT_COLUMN_UNITS`.

    Returns
    -------
    (str, float) or None
        The unit a factor 1000 away (:data:`HEAT_UNIT_SLIPS`) that brings the coefficient into
        :data:`PLAUSIBLE_HEAT_LOSS_W_PER_K`, and the coefficient read so [W/K]; None when the
        coefficient is plausible (or not finite), or no such unit does.
    """
    lo, hi = PLAUSIBLE_HEAT_LOSS_W_PER_K
    if not math.isfinite(heat_loss) or lo <= heat_loss <= hi:
        return None
    for alt, factor in HEAT_UNIT_SLIPS.get(unit, []):
        if lo <= heat_loss * factor <= hi:
            return alt, heat_loss * factor
    return None


#: An irradiance whose maximum stays below this [W/m2] over at least
#: :data:`DIM_IRRADIANCE_DAYS` days of daylight is in another unit (kW/m2 read as W/m2):
#: sunlight exceeds it on every day the sun climbs (:func:`dim_irradiance`).
DIM_IRRADIANCE_W_M2 = 5.0
DIM_IRRADIANCE_DAYS = 2.0
#: Days whose noon sun stays below this elevation [deg] do not count as daylight for
#: :func:`dim_irradiance`: the polar night, and the days at its edges when the sun barely rises
#: and an overcast sky lets a few W/m2 through (at 10 deg the sun gives 236 W/m2 on a
#: horizontal plane above the atmosphere; 5 W/m2 is 2 % of it).
DIM_IRRADIANCE_NOON_SUN_DEG = 10.0


def daylight_rows(index, latitude: float) -> np.ndarray:
    """Rows of days on which the noon sun climbs above :data:`DIM_IRRADIANCE_NOON_SUN_DEG`.

    The noon elevation is ``90 - |latitude - declination|``, with the declination of the day
    (Spencer 1971, :func:`pvlib.solarposition.declination_spencer71`).

    Parameters
    ----------
    index : pandas.DatetimeIndex
        Row times (their calendar day is used).
    latitude : float [deg N]
        Site latitude.

    Returns
    -------
    ndarray of bool
        One per row: False in the polar night and at its edges.
    """
    from pvlib.solarposition import declination_spencer71

    declination = np.degrees(declination_spencer71(np.asarray(index.day_of_year, float)))
    noon_elevation = 90.0 - np.abs(float(latitude) - declination)
    return noon_elevation > DIM_IRRADIANCE_NOON_SUN_DEG


def dim_irradiance(values, days, daylight=None) -> tuple[float, float] | None:
    """An irradiance too dim for W/m2: its maximum and the daylight it covers, or None.

    Sunlight gives hundreds of W/m2 on most days and more than :data:`DIM_IRRADIANCE_W_M2`
    on every day the sun climbs; a maximum below that over at least
    :data:`DIM_IRRADIANCE_DAYS` days of daylight is a column in another unit (kW/m2, or
    kWh/m2 per hour, read as W/m2) or a covered sensor.

    Parameters
    ----------
    values : array_like [W/m2]
        Irradiance of each row, one column (shape (n,)) or several (shape (n, k): the row's
        largest counts); NaN for missing values.
    days : array_like [d]
        Time of each row, increasing, from any origin.
    daylight : array_like of bool, optional
        Rows that count (:func:`daylight_rows`, where the site's latitude is known); default:
        every row.

    Returns
    -------
    (float, float) or None
        The maximum [W/m2] and the daylight span [d] (the time from each counted row to the
        next, summed) when the irradiance is too dim; None when it exceeds the threshold, has
        no values, or the span is shorter than :data:`DIM_IRRADIANCE_DAYS`.
    """
    values = np.asarray(values, float)
    if values.ndim > 1:
        values = np.fmax.reduce(values, axis=1)  # NaN only where every column is
    days = np.asarray(days, float)
    if not days.size:
        return None
    counted = np.ones(days.size, bool) if daylight is None else np.asarray(daylight, bool)
    span = float(np.diff(days, append=days[-1])[counted].sum())
    lit = values[counted]
    if span < DIM_IRRADIANCE_DAYS or not np.isfinite(lit).any():
        return None
    peak = float(np.nanmax(lit))
    return (peak, span) if peak < DIM_IRRADIANCE_W_M2 else None


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
