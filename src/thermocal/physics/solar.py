"""Solar position, irradiance on tilted surfaces and solar heat gains (ISO 52010-1, ISO 52016-1).

Conventions
-----------
* Azimuth in degrees clockwise from north (0 N, 90 E, 180 S, 270 W), for the sun and for the
  outward normal of a surface; tilt 0 = horizontal facing up, 90 = vertical, 180 = facing down.
* Weather frames follow :mod:`thermocal.io.weather`: rows labelled by interval start, irradiance
  = mean over ``[t, t + step)``. The sun position representative of an interval is taken at its
  midpoint; for the intervals that contain sunrise or sunset, at the midpoint of the part of the
  interval in which the sun is above the horizon (ISO 52010-1:2017, 6.4.1.3 does the same for the
  sunrise and sunset hours), so that the beam irradiance of those intervals is neither lost nor
  projected with a sun below the horizon.

Transposition uses :func:`pvlib.irradiance.get_total_irradiance` (Perez 1990 by default, or the
isotropic sky of ISO 52010-1, 6.4.3 / Liu-Jordan), with ground reflection of ``albedo * ghi`` as
seen by the surface.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from types import SimpleNamespace

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

__all__ = [
    "STEFAN_BOLTZMANN",
    "solar_position",
    "interval_solar_position",
    "beam_and_diffuse_from_global",
    "irradiance_on_surface",
    "irradiance_on_surfaces",
    "glazing_angular_factor",
    "window_solar_gains",
    "opaque_solar_gains",
    "sky_temperature",
    "sky_temperature_difference",
    "building_solar_gains",
]

#: Stefan-Boltzmann constant [W/(m2 K4)].
STEFAN_BOLTZMANN = 5.670374419e-8

_TRANSPOSITION_MODELS = ("perez", "isotropic", "haydavies", "reindl", "klucher")


def solar_position(
    times: pd.DatetimeIndex,
    latitude: float,
    longitude: float,
    altitude: float = 0.0,
    *,
    pressure: float | None = None,
    temperature: float = 12.0,
) -> pd.DataFrame:
    """Sun position at the given instants (NREL SPA via :mod:`pvlib`).

    For interval data pass the interval midpoints, or use :func:`interval_solar_position`.

    Parameters
    ----------
    times : pandas.DatetimeIndex
        tz-aware instants (naive stamps are refused: their time zone would be a guess).
    latitude : float
        Site latitude [deg N].
    longitude : float
        Site longitude [deg E].
    altitude : float
        Site altitude above sea level [m].
    pressure : float, optional
        Air pressure for refraction [Pa]; default from the altitude.
    temperature : float
        Air temperature for refraction [C].

    Returns
    -------
    pandas.DataFrame
        ``apparent_zenith``, ``zenith``, ``apparent_elevation``, ``elevation``, ``azimuth``
        [deg] (azimuth clockwise from north), indexed like ``times``.

    References
    ----------
    .. [1] Reda, I. and Andreas, A. (2004), "Solar position algorithm for solar radiation
       applications", Solar Energy 76(5), 577-589.
    .. [2] ISO 52010-1:2017, 6.4.1 (solar angles).
    """
    import pvlib

    times = pd.DatetimeIndex(times)
    if times.tz is None:
        raise ThermocalInputError(
            "solar_position: times have no time zone; localise them (weather files are in local "
            "standard time, e.g. tz_localize('Etc/GMT-1') for central Europe)"
        )
    _check_site(latitude, longitude)
    if pressure is None:
        pressure = pvlib.atmosphere.alt2pres(altitude)
    position = pvlib.solarposition.get_solarposition(
        times,
        latitude,
        longitude,
        altitude=altitude,
        pressure=pressure,
        temperature=temperature,
        method="nrel_numpy",
    )
    return position[["apparent_zenith", "zenith", "apparent_elevation", "elevation", "azimuth"]]


def interval_solar_position(
    index: pd.DatetimeIndex,
    latitude: float,
    longitude: float,
    altitude: float = 0.0,
    *,
    step: pd.Timedelta | str | None = None,
) -> pd.DataFrame:
    """Sun position representative of each interval ``[t, t + step)``.

    At the interval midpoint; for an interval that contains sunrise or sunset, at the midpoint of
    its sunlit part (the crossing of the horizon is interpolated linearly in apparent elevation).

    Parameters
    ----------
    index : pandas.DatetimeIndex
        Interval-start labels (tz-aware), as in a standard weather frame.
    latitude : float
        Site latitude [deg N].
    longitude : float
        Site longitude [deg E].
    altitude : float
        Site altitude [m].
    step : pandas.Timedelta or str, optional
        Interval length; inferred from the index when omitted.

    Returns
    -------
    pandas.DataFrame
        As :func:`solar_position`, plus ``time`` (the instant used), indexed by ``index``.

    References
    ----------
    .. [1] ISO 52010-1:2017, 6.4.1.3 (solar angles for the sunrise and sunset hours).
    """
    index = pd.DatetimeIndex(index)
    if len(index) == 0:
        raise ThermocalInputError("interval_solar_position: the time index is empty")
    step = _step_of(index) if step is None else pd.Timedelta(step)
    index_ns = index.as_unit("ns")
    instants = pd.DatetimeIndex(index_ns + step / 2)
    position = solar_position(instants, latitude, longitude, altitude)
    # Only intervals whose midpoint is close to the horizon can contain sunrise or sunset: the
    # sun's elevation changes by at most 15 deg/h (at the equator), so half a step away the
    # elevation differs by at most 7.5 deg/h * step.
    margin = 7.5 * step / pd.Timedelta(hours=1) + 1.0
    candidate = np.abs(position["apparent_elevation"].to_numpy()) < margin
    if candidate.any():
        starts = index_ns[candidate]
        ends = starts + step
        at_edges = solar_position(starts.append(ends), latitude, longitude, altitude)
        elevation = at_edges["apparent_elevation"].to_numpy()
        e0, e1 = elevation[: len(starts)], elevation[len(starts) :]
        rising = (e0 <= 0.0) & (e1 > 0.0)
        setting = (e0 > 0.0) & (e1 <= 0.0)
        crossing = np.where(rising | setting, e0 / np.where(e0 == e1, 1.0, e0 - e1), 0.5)
        fraction = np.where(rising, 0.5 * (crossing + 1.0), np.where(setting, 0.5 * crossing, 0.5))
        special = rising | setting
        if special.any():
            moved = pd.DatetimeIndex(
                starts[special]
                + pd.to_timedelta(np.round(fraction[special] * step.value).astype(np.int64))
            )
            rows = np.flatnonzero(candidate)[special]
            refined = solar_position(moved, latitude, longitude, altitude)
            position.iloc[rows] = refined.to_numpy()
            instants_ns = instants.as_unit("ns").asi8.copy()
            instants_ns[rows] = moved.as_unit("ns").asi8
            instants = pd.DatetimeIndex(instants_ns).tz_localize("UTC").tz_convert(index.tz)
    position.insert(0, "time", instants)
    position.index = index
    return position


def beam_and_diffuse_from_global(
    ghi: pd.Series,
    latitude: float,
    longitude: float,
    altitude: float = 0.0,
    *,
    solar_position: pd.DataFrame | None = None,
) -> pd.DataFrame:
    """Direct normal and diffuse horizontal irradiance from the global horizontal alone.

    A pyranometer measures the global horizontal irradiance; the transposition to walls, roof
    and windows needs its beam and diffuse parts. Their split is the Erbs et al. (1982)
    correlation of the diffuse fraction with the clearness index (``pvlib.irradiance.
    erbs_driesse``: Driesse et al. 2024's continuous form of it), at each interval's
    representative sun position (:func:`interval_solar_position`). The parts add up to the
    global: ``dhi + dni cos(zenith) = ghi`` wherever the sun is more than 3 deg above the
    horizon; lower, all of it is diffuse.

    Parameters
    ----------
    ghi : pandas.Series
        Global horizontal irradiance [W/m2], interval means labelled by interval start
        (tz-aware index).
    latitude : float
        Site latitude [deg N].
    longitude : float
        Site longitude [deg E].
    altitude : float
        Site altitude [m].
    solar_position : pandas.DataFrame, optional
        Precomputed :func:`interval_solar_position` of ``ghi.index``.

    Returns
    -------
    pandas.DataFrame
        ``dni``, ``dhi`` [W/m2] and ``ghi`` [W/m2] (as given), indexed as ``ghi``; NaN where
        ``ghi`` is NaN.

    References
    ----------
    .. [1] D. G. Erbs, S. A. Klein, J. A. Duffie, "Estimation of the diffuse radiation fraction
       for hourly, daily and monthly-average global radiation", Solar Energy 28 (1982)
       293-302.
    .. [2] A. Driesse, A. Jensen, R. Perez, "A continuous form of the Perez diffuse sky model
       for forward and reverse transposition", Solar Energy 267 (2024) 112093.
    """
    import pvlib

    _check_site(latitude, longitude)
    if solar_position is None:
        solar_position = interval_solar_position(ghi.index, latitude, longitude, altitude)
    values = ghi.to_numpy(dtype=float)
    zenith = solar_position["apparent_zenith"].to_numpy(dtype=float)
    split = pvlib.irradiance.erbs_driesse(
        np.clip(np.nan_to_num(values, nan=0.0), 0.0, None), zenith,
        datetime_or_doy=ghi.index.day_of_year.to_numpy(),
    )  # fmt: skip
    dni = np.asarray(split["dni"], dtype=float)
    dhi = np.asarray(split["dhi"], dtype=float)
    missing = ~np.isfinite(values)
    dni[missing] = np.nan
    dhi[missing] = np.nan
    return pd.DataFrame({"dni": dni, "dhi": dhi, "ghi": values}, index=ghi.index)


def irradiance_on_surface(
    weather: pd.DataFrame,
    latitude: float,
    longitude: float,
    tilt: float,
    azimuth: float,
    *,
    altitude: float = 0.0,
    model: str = "perez",
    albedo: float | str | np.ndarray | pd.Series = 0.2,
    solar_position: pd.DataFrame | None = None,
) -> pd.DataFrame:
    """Irradiance on a tilted, oriented surface from DNI and DHI (ISO 52010-1).

    Parameters
    ----------
    weather : pandas.DataFrame
        Standard weather frame with ``dni`` and ``dhi`` [W/m2] (interval means, rows labelled by
        interval start); ``ghi`` [W/m2] is used for ground reflection and computed as
        ``dni cos(zenith) + dhi`` when absent.
    latitude : float
        Site latitude [deg N].
    longitude : float
        Site longitude [deg E].
    tilt : float
        Surface tilt [deg], 0 horizontal facing up, 90 vertical.
    azimuth : float
        Azimuth of the surface's outward normal [deg], clockwise from north (180 = south).
    altitude : float
        Site altitude [m].
    model : {"perez", "isotropic", "haydavies", "reindl", "klucher"}
        Sky diffuse model.
    albedo : float, array-like or "weather"
        Ground reflectance [-]; "weather" uses the frame's ``albedo`` column (0.2 where missing).
    solar_position : pandas.DataFrame, optional
        Precomputed :func:`interval_solar_position` for ``weather.index`` (saves time for many
        surfaces).

    Returns
    -------
    pandas.DataFrame
        ``poa_global``, ``poa_direct``, ``poa_sky_diffuse``, ``poa_ground_diffuse`` [W/m2],
        ``aoi`` [deg] (angle of incidence) and the parts of the sky diffuse [W/m2]:
        ``poa_sky_isotropic`` (the dome), ``poa_sky_circumsolar`` (Perez and Hay-Davies: the
        disc around the sun) and ``poa_sky_horizon`` (Perez and Reindl: the horizon band, may be
        negative under overcast skies); they sum to ``poa_sky_diffuse`` (the Klucher model's
        sky is all dome), indexed like ``weather``.

    References
    ----------
    .. [1] ISO 52010-1:2017, 6.4.2 (direct and diffuse irradiance on an inclined surface) and
       6.4.3 (anisotropic sky, Perez).
    .. [2] Perez, R. et al. (1990), "Modeling daylight availability and irradiance components from
       direct and global irradiance", Solar Energy 44(5), 271-289.
    """
    prepared = _prepare(weather, latitude, longitude, altitude, model, albedo, solar_position)
    return _transpose(prepared, float(tilt), float(azimuth))


def irradiance_on_surfaces(
    weather: pd.DataFrame,
    latitude: float,
    longitude: float,
    surfaces: Mapping[str, tuple[float, float]],
    *,
    altitude: float = 0.0,
    model: str = "perez",
    albedo: float | str | np.ndarray | pd.Series = 0.2,
    solar_position: pd.DataFrame | None = None,
) -> dict[str, pd.DataFrame]:
    """:func:`irradiance_on_surface` for several surfaces sharing one sun-position calculation.

    Parameters
    ----------
    weather : pandas.DataFrame
        Standard weather frame (see :func:`irradiance_on_surface`).
    latitude : float
        Site latitude [deg N].
    longitude : float
        Site longitude [deg E].
    surfaces : mapping
        ``{name: (tilt [deg], azimuth [deg])}``.
    altitude : float
        Site altitude [m].
    model : str
        Sky diffuse model.
    albedo : float, array-like or "weather"
        Ground reflectance [-].
    solar_position : pandas.DataFrame, optional
        Precomputed :func:`interval_solar_position`.

    Returns
    -------
    dict
        ``{name: DataFrame}`` as returned by :func:`irradiance_on_surface`.
    """
    prepared = _prepare(weather, latitude, longitude, altitude, model, albedo, solar_position)
    out = {}
    cache: dict[tuple[float, float], pd.DataFrame] = {}
    for name, (tilt, azimuth) in surfaces.items():
        key = (float(tilt), float(azimuth) % 360.0)
        if key not in cache:
            cache[key] = _transpose(prepared, *key)
        out[name] = cache[key]
    return out


def glazing_angular_factor(
    aoi: np.ndarray | pd.Series, *, refractive_index: float = 1.526, panes: int = 2
) -> np.ndarray:
    """Direct solar transmittance at incidence angle relative to normal incidence [-].

    Fresnel reflection and absorption for ``panes`` uncoated panes (pvlib ``iam.physical``
    per pane), so a double glazing at 60 deg transmits ~0.8 of its normal-incidence value.
    Applied to the beam part of the window irradiance; diffuse light uses the hemispherical
    average (see :func:`window_solar_gains`).

    Parameters
    ----------
    aoi : array-like
        Angle of incidence [deg].
    refractive_index : float
        Refractive index of the glass [-].
    panes : int
        Number of panes [-].

    Returns
    -------
    numpy.ndarray
        Factor in [0, 1] [-].

    References
    ----------
    .. [1] De Soto, W. et al. (2006), Solar Energy 80(1), 78-88 (the single-pane model).
    .. [2] ISO 52022-3:2017 (angular dependence of glazing transmittance).
    """
    import pvlib

    aoi = np.asarray(aoi, dtype=float)
    single = pvlib.iam.physical(np.clip(aoi, 0.0, 90.0), n=refractive_index)
    factor = np.asarray(single, dtype=float) ** int(panes)
    factor = np.where(aoi >= 90.0, 0.0, factor)
    return np.nan_to_num(factor, nan=0.0)


def _hemispherical_angular_factor(refractive_index: float, panes: int) -> float:
    """Mean angular factor for isotropic diffuse light on a surface [-] (numerical integral)."""
    theta = np.linspace(0.0, 90.0, 181)
    factor = glazing_angular_factor(theta, refractive_index=refractive_index, panes=panes)
    weight = np.sin(np.deg2rad(2.0 * theta))  # cos(theta) sin(theta) projected solid angle
    return float(np.trapezoid(factor * weight, theta) / np.trapezoid(weight, theta))


def window_solar_gains(
    irradiance: pd.DataFrame,
    area: float,
    g_value: float,
    *,
    frame_fraction: float = 0.3,
    shading_factor: float | np.ndarray | pd.Series = 1.0,
    angular_dependence: bool = False,
    g_correction: float = 1.0,
    panes: int = 2,
) -> pd.Series:
    """Solar heat gain through a window, ``phi_sol`` [W].

    ``phi_sol = F_sh * g * (1 - F_F) * A_w * I_sol`` with ``I_sol`` the irradiance on the window
    plane. Without angular dependence ``g = g_correction * g_value`` for all light (ISO 13790
    suggests ``g_correction = F_w = 0.9`` to turn the normal-incidence g into a time average).
    With ``angular_dependence=True`` the beam part is multiplied by
    :func:`glazing_angular_factor` at its angle of incidence and the diffuse parts by its
    hemispherical average (then leave ``g_correction = 1``).

    Parameters
    ----------
    irradiance : pandas.DataFrame
        Output of :func:`irradiance_on_surface` for the window's tilt and azimuth [W/m2].
    area : float
        Window area including frame [m2].
    g_value : float
        Total solar energy transmittance of the glazing at normal incidence [-].
    frame_fraction : float
        Frame area fraction ``F_F`` [-].
    shading_factor : float or array-like
        Shading reduction factor ``F_sh`` (1 = unshaded) [-]; a series aligned to the weather
        for movable shading.
    angular_dependence : bool
        Apply the angle-of-incidence dependence of the glazing transmittance.
    g_correction : float
        Constant correction of the g-value [-] (``F_w`` of ISO 13790, 11.4.2).
    panes : int
        Number of panes for the angular dependence [-].

    Returns
    -------
    pandas.Series
        ``phi_sol`` [W], indexed like ``irradiance``.

    References
    ----------
    .. [1] ISO 52016-1:2017, 6.5.13.2 (solar transmission through windows).
    .. [2] ISO 13790:2008, 11.3.2-11.3.3 and 11.4.2 (effective collecting area of glazing).
    """
    _check_range("area", area, 0.0, 1e5, "m2")
    _check_range("g_value", g_value, 0.0, 1.0, "-")
    _check_range("frame_fraction", frame_fraction, 0.0, 1.0, "-")
    _check_range("g_correction", g_correction, 0.0, 1.0, "-")
    if isinstance(shading_factor, pd.Series) and not shading_factor.index.equals(irradiance.index):
        raise ThermocalInputError(
            "window_solar_gains: the shading_factor series is not indexed like the irradiance "
            f"({len(shading_factor)} rows from {shading_factor.index[:1].tolist()} vs "
            f"{len(irradiance)} from {irradiance.index[:1].tolist()}); reindex it to the "
            "weather's time index"
        )
    shading = np.asarray(shading_factor, dtype=float)
    if np.any((shading < 0.0) | (shading > 1.0)):
        raise ThermocalInputError(
            f"window_solar_gains: shading_factor must lie in [0, 1] (1 = unshaded), got values "
            f"from {np.nanmin(shading):g} to {np.nanmax(shading):g}"
        )
    _require_columns(irradiance, ("poa_global",), "window_solar_gains: irradiance")
    collecting = g_correction * g_value * (1.0 - frame_fraction) * area
    if angular_dependence:
        _require_columns(
            irradiance, ("poa_direct", "poa_sky_diffuse", "poa_ground_diffuse", "aoi"), "irradiance"
        )
        beam = irradiance["poa_direct"].to_numpy() * glazing_angular_factor(
            irradiance["aoi"].to_numpy(), panes=panes
        )
        diffuse = (
            irradiance["poa_sky_diffuse"].to_numpy() + irradiance["poa_ground_diffuse"].to_numpy()
        ) * _hemispherical_angular_factor(1.526, panes)
        transmitted = beam + diffuse
    else:
        transmitted = irradiance["poa_global"].to_numpy()
    return pd.Series(shading * collecting * transmitted, index=irradiance.index, name="phi_sol")


def sky_temperature(
    temp_air: np.ndarray | pd.Series,
    *,
    ghi_infrared: np.ndarray | pd.Series | None = None,
    temp_dew: np.ndarray | pd.Series | None = None,
    cloud_cover: np.ndarray | pd.Series | None = None,
) -> np.ndarray:
    """Effective sky temperature [C].

    From the horizontal infrared irradiance when given (``T_sky = (IR / sigma)^0.25``, as
    EnergyPlus does), else from the dew point with the Berdahl-Martin clear-sky emissivity
    ``eps = 0.711 + 0.56 (Td/100) + 0.73 (Td/100)^2`` corrected for cloud cover
    (``1 + 0.0224 N - 0.0035 N^2 + 0.00028 N^3``, ``N`` in tenths) when given.

    Parameters
    ----------
    temp_air : array-like
        Air temperature [C].
    ghi_infrared : array-like, optional
        Horizontal infrared irradiance from the sky [W/m2].
    temp_dew : array-like, optional
        Dew-point temperature [C].
    cloud_cover : array-like, optional
        Opaque sky cover [tenths].

    Returns
    -------
    numpy.ndarray
        Sky temperature [C].

    References
    ----------
    .. [1] EnergyPlus Engineering Reference, "Sky Radiance Model / Sky temperature".
    .. [2] Berdahl, P. and Martin, M. (1984), Solar Energy 32(5), 663-664.
    """
    temp_air = np.asarray(temp_air, dtype=float)
    if ghi_infrared is not None:
        infrared = np.asarray(ghi_infrared, dtype=float)
        return (np.clip(infrared, 0.0, None) / STEFAN_BOLTZMANN) ** 0.25 - 273.15
    if temp_dew is None:
        raise ThermocalInputError(
            "sky_temperature: give ghi_infrared [W/m2] or temp_dew [C] (or use the default "
            "sky temperature difference of 11 K of ISO 52016-1)"
        )
    dew = np.asarray(temp_dew, dtype=float) / 100.0
    emissivity = 0.711 + 0.56 * dew + 0.73 * dew**2
    if cloud_cover is not None:
        n = np.asarray(cloud_cover, dtype=float)
        emissivity = emissivity * (1.0 + 0.0224 * n - 0.0035 * n**2 + 0.00028 * n**3)
    return (temp_air + 273.15) * emissivity**0.25 - 273.15


def sky_temperature_difference(
    weather: pd.DataFrame | None = None, *, default: float = 11.0
) -> np.ndarray | float:
    """Difference between air and apparent sky temperature ``dT_sky`` [K].

    From the weather's ``ghi_infrared`` (or ``temp_dew``) when present, else the ISO 52016-1 /
    ISO 13790 default of 11 K (intermediate climatic zones). Like the irradiance, the result
    of row ``t`` is the mean over ``[t, t + step)``: the instantaneous temperatures of the
    standard weather frame are averaged over each interval first.

    Parameters
    ----------
    weather : pandas.DataFrame, optional
        Standard weather frame with ``temp_air`` [C] and optionally ``ghi_infrared`` [W/m2]
        or ``temp_dew`` [C].
    default : float
        Value used without such data [K].

    Returns
    -------
    numpy.ndarray or float
        ``temp_air - temp_sky`` [K]; the default (float) when the weather lacks the data.

    References
    ----------
    .. [1] ISO 52016-1:2017, 6.5.13.3; ISO 13790:2008, 11.4.6 (dT_er = 11 K).
    """
    if weather is None or "temp_air" not in weather:
        return float(default)
    temp_air = weather["temp_air"].to_numpy(dtype=float)
    if "ghi_infrared" in weather and weather["ghi_infrared"].notna().any():
        # the infrared is a mean over [t, t + step): compare it with the interval-mean air
        # temperature, not with the instantaneous value at t
        temp_mean = _interval_mean_of_instants(temp_air)
        sky = sky_temperature(temp_mean, ghi_infrared=weather["ghi_infrared"].to_numpy())
        difference = temp_mean - sky
    elif "temp_dew" in weather and weather["temp_dew"].notna().any():
        sky = sky_temperature(temp_air, temp_dew=weather["temp_dew"].to_numpy())
        difference = _interval_mean_of_instants(temp_air - sky)
    else:
        return float(default)
    return np.where(np.isfinite(difference), difference, default)


def _interval_mean_of_instants(values: np.ndarray) -> np.ndarray:
    """Mean over ``[t_k, t_k+1)`` of an instantaneous quantity, ``(x_k + x_k+1) / 2``.

    Standard weather frames label rows by interval start and keep temperatures at their true
    time (:mod:`thermocal.io.weather`); the last row has no successor and keeps its value.
    """
    values = np.asarray(values, dtype=float)
    if values.size < 2:
        return values.copy()
    following = np.append(values[1:], values[-1])
    return 0.5 * (values + following)


def opaque_solar_gains(
    irradiance: pd.DataFrame | pd.Series,
    area: float,
    u_value: float,
    *,
    tilt: float,
    absorptance: float = 0.6,
    external_resistance: float = 0.04,
    emissivity: float = 0.9,
    sky_temperature_difference: float | np.ndarray = 11.0,
    temp_mean: float | None = None,
) -> pd.Series:
    """Net solar heat input through an opaque element, ``phi_re`` [W].

    ``phi_re = alpha R_se U A I_sol - F_sky R_se U A h_r dT_sky``: the absorbed solar irradiance
    minus the long-wave radiation to the sky, both reaching the inside through the fraction
    ``R_se U`` of the element's thermal resistance. ``F_sky = (1 + cos tilt) / 2`` is the view
    factor to the sky and ``h_r`` the external radiative coefficient (``h_re = 4.14 eps / 0.9``
    W/(m2 K) of ISO 52016-1 Table 25, or ``4 eps sigma (T_mn + 273.15)^3`` when ``temp_mean``
    is given).

    Parameters
    ----------
    irradiance : pandas.DataFrame or pandas.Series
        :func:`irradiance_on_surface` output (``poa_global`` is used) or ``I_sol`` [W/m2].
    area : float
        Element area [m2].
    u_value : float
        Thermal transmittance of the element [W/(m2 K)].
    tilt : float
        Tilt of the element [deg] (for the sky view factor).
    absorptance : float
        Solar absorptance of the external surface [-].
    external_resistance : float
        External surface resistance ``R_se`` [m2 K/W] (0.04, ISO 6946).
    emissivity : float
        Long-wave emissivity of the external surface [-].
    sky_temperature_difference : float or array-like
        ``dT_sky`` between air and sky [K] (see :func:`sky_temperature_difference`).
    temp_mean : float, optional
        Mean of surface and sky temperature for the linearised ``h_r`` [C].

    Returns
    -------
    pandas.Series
        ``phi_re`` [W], indexed like ``irradiance``.

    References
    ----------
    .. [1] ISO 13790:2008, 11.3.4-11.3.5 and 11.4.6 (solar gains of opaque elements, thermal
       radiation to the sky, F_r, h_r = 5 eps).
    .. [2] ISO 52016-1:2017, 6.5.13.3 (solar and sky long-wave on opaque elements).
    """
    _check_range("area", area, 0.0, 1e6, "m2")
    _check_range("u_value", u_value, 0.0, 10.0, "W/(m2 K)")
    _check_range("absorptance", absorptance, 0.0, 1.0, "-")
    _check_range("external_resistance", external_resistance, 0.0, 1.0, "m2 K/W")
    _check_range("emissivity", emissivity, 0.0, 1.0, "-")
    _check_range("tilt", tilt, 0.0, 180.0, "deg")
    if isinstance(irradiance, pd.DataFrame):
        _require_columns(irradiance, ("poa_global",), "opaque_solar_gains: irradiance")
        i_sol = irradiance["poa_global"]
    else:
        i_sol = irradiance
    from thermocal.physics.surfaces import external_surface_coefficient

    _, h_r = external_surface_coefficient(emissivity=emissivity, temp_mean=temp_mean, split=True)
    f_sky = 0.5 * (1.0 + np.cos(np.deg2rad(tilt)))
    conductance_share = external_resistance * u_value * area  # [m2 K/W * W/(m2 K) * m2] = [m2]
    phi = conductance_share * (
        absorptance * i_sol.to_numpy(dtype=float)
        - f_sky * h_r * np.asarray(sky_temperature_difference, dtype=float)
    )
    return pd.Series(phi, index=i_sol.index, name="phi_re")


def _field(component, name: str, default=None):
    if isinstance(component, Mapping):
        value = component.get(name, default)
    else:
        value = getattr(component, name, default)
    return default if value is None else value


def building_solar_gains(
    weather: pd.DataFrame,
    latitude: float,
    longitude: float,
    *,
    windows: Sequence = (),
    opaque: Sequence = (),
    altitude: float = 0.0,
    model: str = "perez",
    albedo: float | str = 0.2,
    angular_dependence: bool = False,
    sky_temperature_difference: float | np.ndarray | None = None,
) -> pd.DataFrame:
    """Solar gains of a whole envelope: ``phi_sol`` (windows) and ``phi_re`` (opaque) [W].

    One sun-position calculation, one transposition per distinct orientation.

    Parameters
    ----------
    weather : pandas.DataFrame
        Standard weather frame (``dni``, ``dhi``, optionally ``ghi``, ``temp_air``,
        ``ghi_infrared``, ``temp_dew``).
    latitude : float
        Site latitude [deg N].
    longitude : float
        Site longitude [deg E].
    windows : sequence of mappings or objects
        Each with ``area`` [m2], ``tilt`` [deg], ``azimuth`` [deg], ``g_value`` [-] and
        optionally ``frame_fraction`` [-] (0.3), ``shading_factor`` [-] (1.0), ``name``.
    opaque : sequence of mappings or objects
        Each with ``area`` [m2], ``u_value`` [W/(m2 K)], ``tilt`` [deg], ``azimuth`` [deg] and
        optionally ``absorptance`` [-] (0.6), ``name``.
    altitude : float
        Site altitude [m].
    model : str
        Sky diffuse model (see :func:`irradiance_on_surface`).
    albedo : float or "weather"
        Ground reflectance [-].
    angular_dependence : bool
        Angular dependence of the glazing transmittance (see :func:`window_solar_gains`).
    sky_temperature_difference : float or array-like, optional
        ``dT_sky`` [K]; by default from the weather (infrared or dew point) else 11 K.

    Returns
    -------
    pandas.DataFrame
        ``phi_sol`` and ``phi_re`` [W] (totals), then one column per component named
        ``phi_sol/<name>`` or ``phi_re/<name>`` [W].

    References
    ----------
    .. [1] ISO 52016-1:2017, 6.5.13; ISO 13790:2008, 11.3.
    """
    components = [("window", c) for c in windows] + [("opaque", c) for c in opaque]
    orientations = {}
    for i, (kind, component) in enumerate(components):
        for field in ("area", "tilt", "azimuth") + (
            ("g_value",) if kind == "window" else ("u_value",)
        ):
            if _field(component, field) is None:
                raise ThermocalInputError(
                    f"building_solar_gains: {kind} #{i} ({_field(component, 'name', 'unnamed')}) "
                    f"lacks {field}"
                )
        orientations[
            (float(_field(component, "tilt")), float(_field(component, "azimuth")) % 360)
        ] = 1
    prepared = _prepare(weather, latitude, longitude, altitude, model, albedo, None)
    irradiance = {key: _transpose(prepared, *key) for key in orientations}
    if sky_temperature_difference is None:
        sky_temperature_difference = globals()["sky_temperature_difference"](weather)
    columns: dict[str, np.ndarray] = {}
    phi_sol = np.zeros(len(weather))
    phi_re = np.zeros(len(weather))
    for i, (kind, component) in enumerate(components):
        key = (float(_field(component, "tilt")), float(_field(component, "azimuth")) % 360)
        name = str(_field(component, "name", f"{kind}{i}"))
        if kind == "window":
            gains = window_solar_gains(
                irradiance[key],
                float(_field(component, "area")),
                float(_field(component, "g_value")),
                frame_fraction=float(_field(component, "frame_fraction", 0.3)),
                shading_factor=_field(component, "shading_factor", 1.0),
                angular_dependence=angular_dependence,
            ).to_numpy()
            phi_sol += gains
            columns[f"phi_sol/{name}"] = gains
        else:
            gains = opaque_solar_gains(
                irradiance[key],
                float(_field(component, "area")),
                float(_field(component, "u_value")),
                tilt=key[0],
                absorptance=float(_field(component, "absorptance", 0.6)),
                sky_temperature_difference=sky_temperature_difference,
            ).to_numpy()
            phi_re += gains
            columns[f"phi_re/{name}"] = gains
    return pd.DataFrame({"phi_sol": phi_sol, "phi_re": phi_re, **columns}, index=weather.index)


# --------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------
def _prepare(weather, latitude, longitude, altitude, model, albedo, solar_position):
    import pvlib

    if not isinstance(weather, pd.DataFrame) or not isinstance(weather.index, pd.DatetimeIndex):
        raise ThermocalInputError(
            "irradiance_on_surface: weather must be a DataFrame with a DatetimeIndex (the "
            "standard frame of thermocal.io.weather.read_weather)"
        )
    _require_columns(weather, ("dni", "dhi"), "irradiance_on_surface: weather")
    if model not in _TRANSPOSITION_MODELS:
        raise ThermocalInputError(
            f"irradiance_on_surface: unknown sky model {model!r}; use one of "
            f"{', '.join(_TRANSPOSITION_MODELS)}"
        )
    if solar_position is None:
        solar_position = interval_solar_position(weather.index, latitude, longitude, altitude)
    elif len(solar_position) != len(weather) or not solar_position.index.equals(weather.index):
        raise ThermocalInputError(
            "irradiance_on_surface: solar_position is not indexed like the weather; compute it "
            "with interval_solar_position(weather.index, ...)"
        )
    zenith = solar_position["apparent_zenith"].to_numpy(dtype=float)
    sun_azimuth = solar_position["azimuth"].to_numpy(dtype=float)
    dni = weather["dni"].to_numpy(dtype=float)
    dhi = weather["dhi"].to_numpy(dtype=float)
    _check_nonnegative(weather, ("dni", "dhi"))
    sun_up = zenith < 90.0
    dni = np.where(sun_up, dni, 0.0)  # beam with the sun below the horizon cannot be placed
    if "ghi" in weather:
        ghi = weather["ghi"].to_numpy(dtype=float)
    else:
        ghi = dni * np.cos(np.deg2rad(zenith)) + dhi
    instants = pd.DatetimeIndex(solar_position["time"]) if "time" in solar_position else None
    doy_times = instants if instants is not None else weather.index
    day_of_year = pd.DatetimeIndex(doy_times).tz_convert("UTC").day_of_year.to_numpy()
    dni_extra = np.asarray(pvlib.irradiance.get_extra_radiation(day_of_year), dtype=float)
    airmass = np.asarray(
        pvlib.atmosphere.get_relative_airmass(np.where(sun_up, zenith, 90.0)), dtype=float
    )
    prepared = SimpleNamespace(
        index=weather.index,
        zenith=zenith,
        sun_azimuth=sun_azimuth,
        dni=dni,
        dhi=dhi,
        ghi=ghi,
        dni_extra=dni_extra,
        airmass=airmass,
    )
    if isinstance(albedo, str):
        if albedo != "weather":
            raise ThermocalInputError(
                f"irradiance_on_surface: albedo must be a number in [0, 1] or 'weather', got "
                f"{albedo!r}"
            )
        if "albedo" in weather:
            albedo_values = weather["albedo"].to_numpy(dtype=float)
            albedo_values = np.where(np.isfinite(albedo_values), albedo_values, 0.2)
        else:
            albedo_values = np.full(len(weather), 0.2)
    else:
        albedo_values = np.asarray(albedo, dtype=float)
        if np.any((albedo_values < 0.0) | (albedo_values > 1.0)):
            raise ThermocalInputError(
                f"irradiance_on_surface: albedo must lie in [0, 1], got {albedo!r}"
            )
    prepared.model = model
    prepared.albedo = albedo_values
    return prepared


def _transpose(prepared, tilt: float, azimuth: float) -> pd.DataFrame:
    import pvlib

    _check_range("tilt", tilt, 0.0, 180.0, "deg")
    if not np.isfinite(azimuth):
        raise ThermocalInputError(f"irradiance_on_surface: azimuth must be finite, got {azimuth}")
    total = pvlib.irradiance.get_total_irradiance(
        tilt,
        azimuth,
        prepared.zenith,
        prepared.sun_azimuth,
        prepared.dni,
        prepared.ghi,
        prepared.dhi,
        dni_extra=prepared.dni_extra,
        airmass=prepared.airmass,
        albedo=prepared.albedo,
        model=prepared.model,
        diffuse_components=prepared.model != "klucher",
    )
    aoi = np.asarray(pvlib.irradiance.aoi(tilt, azimuth, prepared.zenith, prepared.sun_azimuth))
    direct = np.clip(np.nan_to_num(np.asarray(total["poa_direct"], dtype=float)), 0.0, None)
    sky = np.clip(np.nan_to_num(np.asarray(total["poa_sky_diffuse"], dtype=float)), 0.0, None)
    ground = np.clip(np.nan_to_num(np.asarray(total["poa_ground_diffuse"], dtype=float)), 0.0, None)
    # the sky's parts (Perez: dome, circumsolar disc, horizon band; shading treats each its own
    # way); the dome takes what is left so that the parts sum to the sky diffuse
    circumsolar = np.nan_to_num(np.asarray(total.get("poa_circumsolar", 0.0), dtype=float))
    horizon = np.nan_to_num(np.asarray(total.get("poa_horizon", 0.0), dtype=float))
    circumsolar = np.where(sky > 0.0, np.broadcast_to(circumsolar, sky.shape), 0.0)
    horizon = np.where(sky > 0.0, np.broadcast_to(horizon, sky.shape), 0.0)
    missing = ~(np.isfinite(prepared.dni) & np.isfinite(prepared.dhi) & np.isfinite(prepared.ghi))
    frame = pd.DataFrame(
        {
            "poa_global": direct + sky + ground,
            "poa_direct": direct,
            "poa_sky_diffuse": sky,
            "poa_ground_diffuse": ground,
            "aoi": aoi,
            "poa_sky_isotropic": sky - circumsolar - horizon,
            "poa_sky_circumsolar": circumsolar,
            "poa_sky_horizon": horizon,
        },
        index=prepared.index,
    )
    if missing.any():
        frame.loc[missing, [c for c in frame.columns if c.startswith("poa_")]] = np.nan
    return frame


def _step_of(index: pd.DatetimeIndex) -> pd.Timedelta:
    if len(index) < 2:
        return pd.Timedelta(hours=1)
    diffs = np.diff(index.as_unit("ns").asi8)
    return pd.Timedelta(int(np.median(diffs)), unit="ns")


def _check_site(latitude: float, longitude: float) -> None:
    if not -90.0 <= float(latitude) <= 90.0:
        raise ThermocalInputError(f"latitude {latitude} deg is outside [-90, 90] (deg north)")
    if not -180.0 <= float(longitude) <= 360.0:
        raise ThermocalInputError(
            f"longitude {longitude} deg is outside [-180, 180] (deg east of Greenwich)"
        )


def _check_range(name: str, value, low: float, high: float, unit: str) -> None:
    values = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(values)) or np.any((values < low) | (values > high)):
        raise ThermocalInputError(
            f"parameter {name} = {value!r} [{unit}] is outside the allowed range "
            f"[{low:g}, {high:g}] {unit}"
        )


def _check_nonnegative(frame: pd.DataFrame, columns: Sequence[str]) -> None:
    for column in columns:
        values = frame[column].to_numpy(dtype=float)
        bad = values < -10.0
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            raise ThermocalInputError(
                f"weather column {column!r}, row {row} ({frame.index[row]}): irradiance "
                f"{values[row]:g} W/m2 is negative"
            )


def _require_columns(frame: pd.DataFrame, columns: Sequence[str], what: str) -> None:
    absent = [c for c in columns if c not in frame.columns]
    if absent:
        raise ThermocalInputError(
            f"{what} lacks column(s) {absent} (has {list(frame.columns)}); read weather files with "
            "thermocal.io.weather.read_weather, which names the columns"
        )
