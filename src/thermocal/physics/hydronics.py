"""Heat delivered by a hydronic heating circuit from flow and temperatures.

``Phi = rho(T_meter) V_dot (h(T_supply) - h(T_return))`` with the water density at the flow
meter's temperature and the specific enthalpy difference obtained by integrating the
temperature-dependent isobaric specific heat (the heat-meter equation of EN 1434-1).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

__all__ = [
    "water_density",
    "water_specific_heat",
    "water_enthalpy_difference",
    "heating_power",
]

# Isobaric specific heat of liquid water at 0.1 MPa (100 C: saturated liquid) [J/(kg K)],
# IAPWS-95 values as tabulated e.g. in the VDI Heat Atlas, D2.1.
_CP_TEMPERATURES = np.array([0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0])
_CP_VALUES = np.array(
    [4219.9, 4195.5, 4184.1, 4180.1, 4179.6, 4181.3, 4185.1, 4190.4, 4196.9, 4205.0, 4215.6]
)
_VALID = (0.0, 100.0)


def _temperatures(name: str, values) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    finite = array[np.isfinite(array)]
    if finite.size and (finite.min() < _VALID[0] - 1e-9 or finite.max() > _VALID[1] + 1e-9):
        bad = finite.max() if finite.max() > _VALID[1] else finite.min()
        hint = " (looks like Kelvin: subtract 273.15)" if finite.min() > 200.0 else ""
        raise ThermocalInputError(
            f"{name} = {bad:g} C is outside the range of liquid heating water "
            f"[{_VALID[0]:g}, {_VALID[1]:g}] C{hint}"
        )
    return array


def water_density(temperature) -> np.ndarray | float:
    """Density of liquid water at atmospheric pressure [kg/m3] (Kell 1975).

    Parameters
    ----------
    temperature : float or array-like
        Water temperature [C], 0 to 100.

    Returns
    -------
    float or numpy.ndarray
        Density [kg/m3]: 999.97 at 4 C, 998.2 at 20 C, 988.0 at 50 C, 971.8 at 80 C.

    References
    ----------
    .. [1] Kell, G. S. (1975), "Density, thermal expansivity, and compressibility of liquid water
       from 0 to 150 C", J. Chem. Eng. Data 20(1), 97-105, equation (16).
    """
    t = _temperatures("temperature", temperature)
    numerator = (
        999.83952
        + 16.945176 * t
        - 7.9870401e-3 * t**2
        - 46.170461e-6 * t**3
        + 105.56302e-9 * t**4
        - 280.54253e-12 * t**5
    )
    rho = numerator / (1.0 + 16.879850e-3 * t)
    return float(rho) if np.ndim(rho) == 0 else rho


@lru_cache(maxsize=1)
def _cp_interpolant():
    from scipy.interpolate import PchipInterpolator

    cp = PchipInterpolator(_CP_TEMPERATURES, _CP_VALUES)
    return cp, cp.antiderivative()


def water_specific_heat(temperature) -> np.ndarray | float:
    """Isobaric specific heat of liquid water [J/(kg K)].

    Parameters
    ----------
    temperature : float or array-like
        Water temperature [C], 0 to 100.

    Returns
    -------
    float or numpy.ndarray
        ``c_p`` [J/(kg K)] (monotone cubic interpolation of IAPWS-95 values; 4184 at 20 C,
        minimum 4180 near 35-40 C).

    References
    ----------
    .. [1] IAPWS-95 (Wagner and Pruss 2002), values at 0.1 MPa.
    """
    t = _temperatures("temperature", temperature)
    cp, _ = _cp_interpolant()
    value = cp(t)
    return float(value) if np.ndim(value) == 0 else value


def water_enthalpy_difference(temp_supply, temp_return) -> np.ndarray | float:
    """Specific enthalpy difference ``h(T_s) - h(T_r) = integral of c_p dT`` [J/kg].

    Parameters
    ----------
    temp_supply : float or array-like
        Supply temperature [C].
    temp_return : float or array-like
        Return temperature [C].

    Returns
    -------
    float or numpy.ndarray
        Enthalpy difference [J/kg].
    """
    ts = _temperatures("temp_supply", temp_supply)
    tr = _temperatures("temp_return", temp_return)
    _, enthalpy = _cp_interpolant()
    value = enthalpy(ts) - enthalpy(tr)
    return float(value) if np.ndim(value) == 0 else value


def heating_power(
    flow,
    temp_supply,
    temp_return,
    *,
    meter_location: str = "return",
    max_flow: float = 0.1,
):
    """Heat delivered by a hydronic circuit ``Phi = rho V_dot (h_s - h_r)`` [W].

    Parameters
    ----------
    flow : float or array-like
        Volume flow rate of the water ``V_dot`` [m3/s] (1 m3/h = 2.778e-4 m3/s).
    temp_supply : float or array-like
        Supply (flow) temperature [C].
    temp_return : float or array-like
        Return temperature [C].
    meter_location : {"return", "supply", "mean"}
        Where the volume is measured (the density is evaluated at that temperature); heat meters
        usually sit in the return (EN 1434).
    max_flow : float
        Flows above this are refused as a probable unit error [m3/s] (0.1 m3/s = 360 m3/h).

    Returns
    -------
    float, numpy.ndarray or pandas.Series
        Heat flow [W]; a Series when ``flow`` is one. Negative when the return is warmer than the
        supply (cooling, or sensor noise with the pump running and the boiler off).

    References
    ----------
    .. [1] EN 1434-1:2015, 3 and Annex (heat-meter equation with the heat coefficient
       k = rho (h_s - h_r) / (T_s - T_r)).
    .. [2] Paper 000 (this project's seed): heat input from V_dot, T_supply, T_return.
    """
    index = getattr(flow, "index", None)
    v = np.asarray(flow, dtype=float)
    finite = v[np.isfinite(v)]
    if finite.size and finite.min() < 0.0:
        raise ThermocalInputError(
            f"flow = {finite.min():g} m3/s is negative; check the sensor's sign and units"
        )
    if finite.size and finite.max() > max_flow:
        raise ThermocalInputError(
            f"flow = {finite.max():g} m3/s exceeds {max_flow:g} m3/s ({max_flow * 3600:g} m3/h): "
            "flow must be in m3/s (divide m3/h by 3600, l/h by 3.6e6), or raise max_flow="
        )
    ts = _temperatures("temp_supply", temp_supply)
    tr = _temperatures("temp_return", temp_return)
    if meter_location == "return":
        t_meter = tr
    elif meter_location == "supply":
        t_meter = ts
    elif meter_location == "mean":
        t_meter = 0.5 * (ts + tr)
    else:
        raise ThermocalInputError(
            f"meter_location = {meter_location!r}: use 'return', 'supply' or 'mean'"
        )
    power = water_density(t_meter) * v * water_enthalpy_difference(ts, tr)
    if index is not None:
        return pd.Series(np.asarray(power, dtype=float), index=index, name="heating_power")
    return float(power) if np.ndim(power) == 0 else power
