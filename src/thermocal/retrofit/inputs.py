"""Model inputs of the fifth-order model from measurements, weather and the building file.

- heating power ``phi_h`` [W] from water flow and supply / return temperatures;
- ground temperature at 2 m ``Tgr`` [C] from the annual cycle of the site's typical year;
- solar gains through the windows ``phi_sol`` [W] (ISO 52016-1 6.5.13: aperture x g-value x
  shading x non-normal-incidence factor 0.9 x irradiance on the window plane);
- solar radiation absorbed on the outer surfaces of roof and walls minus their long-wave loss
  to the sky, ``phi_abs_roof``, ``phi_abs_walls`` [W] (ISO 52016-1 6.5.13.3; ISO 13790 11.3.5:
  ``F_r h_r Delta theta_er`` with the sky view factor ``F_r = (1 + cos tilt) / 2``,
  ``h_r = 4.14 W/(m2 K)`` and ``Delta theta_er = 11 K``).

Irradiance columns are interval means labelled by the interval start (thermocal convention),
so sun positions are taken at the interval midpoints.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

#: ISO 52016-1 default correction of the g-value for non-normal incidence [-].
WINDOW_INCIDENCE_FACTOR = 0.9
#: ISO 13790 11.3.5 / ISO 52016-1: external radiative coefficient [W/(m2 K)] and mean
#: difference between air and apparent sky temperature [K].
H_RE_SKY = 4.14
DELTA_THETA_ER = 11.0


def heating_power(flow, temp_supply, temp_return):
    """Heat delivered by the heating water [W].

    Parameters
    ----------
    flow : array-like [m3/s]
    temp_supply, temp_return : array-like [C]

    Returns
    -------
    array [W]

    Notes
    -----
    Uses :func:`thermocal.physics.hydronics.heating_power` (temperature-dependent density and
    specific heat) when available, otherwise water at the mean temperature with
    ``rho = 1000 - 0.0062 (T - 4)^2`` [kg/m3] (less than 0.1 % off 10-90 C) and
    ``cp = 4186 J/(kg K)``.
    """
    try:
        from thermocal.physics.hydronics import heating_power as _hp

        return _hp(flow, temp_supply, temp_return)
    except ImportError:  # physics module not available: private fallback
        t_mean = 0.5 * (np.asarray(temp_supply, float) + np.asarray(temp_return, float))
        rho = 1000.0 - 0.0062 * (t_mean - 4.0) ** 2
        return (
            np.asarray(flow, float)
            * rho
            * 4186.0
            * (np.asarray(temp_supply, float) - np.asarray(temp_return, float))
        )


def ground_temperature_parameters(weather: pd.DataFrame) -> dict[str, float]:
    """Annual mean [C], amplitude [K] and day of the minimum of the air temperature of a year.

    See :func:`thermocal.physics.ground.ground_temperature_parameters`.
    """
    from thermocal.physics.ground import ground_temperature_parameters as _params

    return _params(weather)


def ground_temperature(
    times: pd.DatetimeIndex, params: dict[str, float], depth: float = 2.0
) -> pd.Series:
    """Undisturbed ground temperature at ``depth`` [m] in [C] (damped, delayed annual wave).

    Parameters
    ----------
    times : pd.DatetimeIndex
    params : dict from :func:`ground_temperature_parameters`
    depth : float [m]

    References
    ----------
    Kusuda and Achenbach (1965); Zuercher and Frank (2018), as in paper 000; implemented by
    :func:`thermocal.physics.ground.ground_temperature`.
    """
    from thermocal.physics.ground import ground_temperature as _ground

    return _ground(times, depth, **params).rename("Tgr")


def solar_inputs(frame: pd.DataFrame, building) -> pd.DataFrame:
    """Window gains and absorbed outer-surface radiation of roof and walls [W].

    Parameters
    ----------
    frame : pd.DataFrame
        Regular DatetimeIndex (interval starts) with ``dni`` and ``dhi`` [W/m2] (``ghi`` is
        computed as ``dhi + dni cos(zenith)`` when absent).
    building : thermocal.io.building.Building

    Returns
    -------
    pd.DataFrame with columns ``phi_sol``, ``phi_abs_roof``, ``phi_abs_walls`` [W].
    """
    from thermocal.physics.solar import irradiance_on_surfaces

    loc = building.location
    data = frame[["dni", "dhi"] + (["ghi"] if "ghi" in frame else [])]
    orientations = {}
    for c in building.components:
        if c.type in ("window", "roof", "external_wall"):
            tilt = float(c.tilt if c.tilt is not None else 90.0)
            azimuth = float(c.azimuth if c.azimuth is not None else 180.0)
            orientations[c.name] = (tilt, azimuth)
    poa_frames = irradiance_on_surfaces(
        data, loc.latitude, loc.longitude, orientations, altitude=loc.altitude
    )

    def poa(name):
        return np.nan_to_num(poa_frames[name]["poa_global"].to_numpy(float), nan=0.0).clip(0.0)

    n = len(frame)
    phi_sol = np.zeros(n)
    absorbed = {"roof": np.zeros(n), "external_wall": np.zeros(n)}
    for c in building.components:
        tilt = float(c.tilt if c.tilt is not None else 90.0)
        if c.type == "window":
            g = float(c.g_value if c.g_value is not None else 0.6)
            ff = float(c.frame_fraction if c.frame_fraction is not None else 0.3)
            fsh = float(c.shading_factor if c.shading_factor is not None else 1.0)
            phi_sol += c.area * (1 - ff) * g * fsh * WINDOW_INCIDENCE_FACTOR * poa(c.name)
        elif c.type in absorbed:
            alpha = float(c.absorptance if c.absorptance is not None else 0.6)
            sky_view = 0.5 * (1.0 + np.cos(np.radians(tilt)))
            absorbed[c.type] += c.area * (
                alpha * poa(c.name) - sky_view * H_RE_SKY * DELTA_THETA_ER
            )
    return pd.DataFrame(
        {
            "phi_sol": phi_sol,
            "phi_abs_roof": absorbed["roof"],
            "phi_abs_walls": absorbed["external_wall"],
        },
        index=frame.index,
    )
