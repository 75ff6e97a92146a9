"""The forcing of a multi-zone simulation on its time grid: weather interpolated as EnergyPlus
does, the sun's position (per step or per shadow period), irradiance on every surface and window.

Used by :class:`thermocal.multizone.simulation.Simulation`; the time convention is its own (steps
labelled by their start, forcing as interval means).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError


def _window_inputs(wt, irradiance: dict, n_steps: int):
    """Transmitted beam, transmitted diffuse, outer- and inner-pane absorbed [W/m2 glazing]."""
    direct = irradiance["poa_direct"]
    diffuse = irradiance["poa_sky_diffuse"] + irradiance["poa_ground_diffuse"]
    aoi = irradiance["aoi"]
    beam = direct * wt.transmittance(aoi)
    diffuse_in = diffuse * wt.diffuse_transmittance_value
    outer = np.zeros(n_steps)
    inner = np.zeros(n_steps)
    if wt.layered:
        absorbed = wt.pane_absorptance(aoi) * direct[:, None]
        absorbed = absorbed + wt.diffuse_pane_absorptance_values[None, :] * diffuse[:, None]
        n_panes = absorbed.shape[1]
        outer = absorbed[:, 0].copy()
        if n_panes == 1:
            # one layer between the two nodes (a single pane, or EnergyPlus' simple-glazing
            # equivalent layer, whose resistance is most of the window's): absorbed at its
            # middle, half on each face, so that the inward-flowing fraction is EnergyPlus'
            # (R_out + R_layer / 2) / R_total
            outer *= 0.5
            inner = outer.copy()
        if n_panes > 1:
            inner = absorbed[:, -1].copy()
        if n_panes > 2:
            middle = absorbed[:, 1:-1].sum(axis=1)
            outer += 0.5 * middle
            inner += 0.5 * middle
    return beam, diffuse_in, outer, inner


def _weather_grid(
    weather: pd.DataFrame, step: pd.Timedelta, start, end, interpolation: str = "hold"
) -> pd.DataFrame:
    """Weather resampled to the simulation step, restricted to ``[start, end)``.

    ``interpolation="energyplus"``: :func:`_energyplus_weather` (hourly weather only).
    """
    from thermocal.io.weather import resample_weather, weather_step
    from thermocal.physics.solar import sky_temperature

    if not isinstance(weather, pd.DataFrame) or not isinstance(weather.index, pd.DatetimeIndex):
        raise ThermocalInputError(
            "Simulation: weather must be the DataFrame of thermocal.io.weather.read_weather"
        )
    missing = [c for c in ("temp_air", "dni", "dhi") if c not in weather]
    if missing:
        raise ThermocalInputError(
            f"Simulation: the weather lacks the columns {missing} (needed: temp_air [C], dni and "
            "dhi [W/m2])"
        )
    if interpolation == "energyplus":
        grid = _energyplus_weather(weather, step)
    elif weather_step(weather) != step:
        grid = resample_weather(weather, step)
    else:
        grid = weather.copy()
    index = grid.index

    def stamp(value, what):
        try:
            ts = pd.Timestamp(value)
        except ValueError as exc:
            raise ThermocalInputError(f"Simulation: cannot read {what} {value!r}") from exc
        if ts.tzinfo is None and index.tz is not None:
            ts = ts.tz_localize(index.tz)
        return ts

    t0 = index[0] if start is None else stamp(start, "start")
    t1 = index[-1] + step if end is None else stamp(end, "end")
    if t1 <= t0:
        raise ThermocalInputError(
            f"Simulation: period [{t0}, {t1}) is empty: it ends before it starts"
        )
    if t0 < index[0] or t1 > index[-1] + step:
        year = ""
        if index[0].year != t0.year:
            year = (
                f"; the weather runs in {index[0].year} (a typical year's months are put in "
                f"one calendar year: give the period in {index[0].year})"
            )
        past = "; a period cannot run past the weather's last step" if t1 > index[-1] + step else ""
        raise ThermocalInputError(
            f"Simulation: period [{t0}, {t1}) is not inside the weather data "
            f"[{index[0]}, {index[-1] + step}){year}{past}"
        )
    # the steps must tile the period exactly: a start between two steps or a length that is not
    # a whole number of steps would silently simulate another period
    if (t0 - index[0]) % step != pd.Timedelta(0) or (t1 - t0) % step != pd.Timedelta(0):
        raise ThermocalInputError(
            f"Simulation: the period [{t0}, {t1}) is not a whole number of "
            f"{step.total_seconds() / 60:g}-min steps on the "
            f"weather's grid (which starts at {index[0]}); choose start, end and step so that "
            "the step divides both the offset from the grid start and the period length"
        )
    # interval-mean temperatures from the instant values at both ends of each step
    temp = grid["temp_air"].to_numpy(dtype=float)
    following = np.append(temp[1:], temp[-1])
    if interpolation == "energyplus":
        grid["temp_air_mean"] = following  # the value at the step's end
    else:
        grid["temp_air_mean"] = 0.5 * (temp + following)
    if "ghi_infrared" in grid and grid["ghi_infrared"].notna().all():
        sky = sky_temperature(grid["temp_air_mean"], ghi_infrared=grid["ghi_infrared"])
    elif "temp_dew" in grid and grid["temp_dew"].notna().all():
        sky = sky_temperature(grid["temp_air_mean"], temp_dew=grid["temp_dew"])
    else:
        warnings.warn(
            "weather has neither ghi_infrared nor temp_dew: sky temperature = air - 11 K "
            "(ISO 52016-1 default)",
            stacklevel=3,
        )
        sky = grid["temp_air_mean"].to_numpy() - 11.0
    grid["temp_sky"] = sky
    selected = grid.loc[(index >= t0) & (index < t1)]
    if len(selected) == 0:
        raise ThermocalInputError(f"Simulation: no weather rows in [{t0}, {t1})")
    for column in ("temp_air_mean", "dni", "dhi"):
        if selected[column].isna().any():
            bad = selected.index[selected[column].isna()][0]
            raise ThermocalInputError(
                f"Simulation: weather column {column} has missing values (first at {bad}); fill "
                "the gap or choose another period"
            )
    return selected


#: Instant columns that EnergyPlus interpolates to the end of each step (air temperature is kept at
#: the step start in ``temp_air``; the step value is ``temp_air_mean``).
_STEP_END_COLUMNS = ("temp_dew", "relative_humidity", "pressure", "wind_speed", "wind_direction")


#: Irradiance columns interpolated between the hourly values placed at the half hours.
_HALF_HOUR_COLUMNS = ("ghi", "dni", "dhi")


#: Interval columns of the weather frame that EnergyPlus interpolates as instants at the hour's
#: end (the EPW horizontal infrared of hour h as the value at h:00, like the temperatures).
_HOUR_END_COLUMNS = ("ghi_infrared",)


def _energyplus_weather(weather: pd.DataFrame, step: pd.Timedelta) -> pd.DataFrame:
    """Hourly weather on sub-hourly steps as EnergyPlus' weather manager does.

    Each step ``[t, t + step)`` takes values at ``t + step``: irradiance linearly interpolated
    between the hourly means placed at the middle of their hours (held before the first and after
    the last middle), instant quantities linearly interpolated between the hourly instants
    (:func:`thermocal.io.weather.resample_weather`, then shifted one step; the last step holds).
    ``temp_air`` stays the instant at ``t`` (the caller takes the step value from its end).
    """
    from thermocal.io.weather import resample_weather, weather_step

    hour = pd.Timedelta("1h")
    if weather_step(weather) != hour:
        raise ThermocalInputError(
            "Simulation: weather_interpolation='energyplus' needs hourly weather, the weather step "
            f"is {weather_step(weather)}; use weather_interpolation='hold'"
        )
    if hour % step != pd.Timedelta(0):
        raise ThermocalInputError(
            f"Simulation: weather_interpolation='energyplus' needs a step dividing the hour, got "
            f"{step}"
        )
    grid = resample_weather(weather, step) if step != hour else weather.copy()
    ends = (grid.index + step).as_unit("ns").asi8.astype(float)
    middles = (weather.index + hour / 2).as_unit("ns").asi8.astype(float)
    for column in _HALF_HOUR_COLUMNS:
        if column in grid:
            grid[column] = np.interp(ends, middles, weather[column].to_numpy(dtype=float))
    hour_ends = (weather.index + hour).as_unit("ns").asi8.astype(float)
    for column in _HOUR_END_COLUMNS:
        if column in grid:
            grid[column] = np.interp(ends, hour_ends, weather[column].to_numpy(dtype=float))
    for column in _STEP_END_COLUMNS:
        if column in grid:
            values = grid[column].to_numpy(dtype=float)
            grid[column] = np.append(values[1:], values[-1])
    return grid


def _sun_position(index: pd.DatetimeIndex, site: dict, at_end: pd.Timedelta | None):
    """Sun position of each step: representative of the interval (``at_end`` None, see
    :func:`~thermocal.physics.solar.interval_solar_position`) or, as EnergyPlus, at the step's end
    ``t + at_end``."""
    from thermocal.physics.solar import interval_solar_position, solar_position

    if at_end is None:
        return interval_solar_position(index, site["latitude"], site["longitude"], site["altitude"])
    position = solar_position(index + at_end, site["latitude"], site["longitude"], site["altitude"])
    position.index = index
    return position


def _period_sun_vectors(times, step, at_end, site, period, days) -> np.ndarray:
    """Unit vectors toward the sun (x east, y north, z up) per step as EnergyPlus' periodic
    shadow calculation places it: the step's clock instant (its end with ``at_end``, else its
    middle), with the mean sine of the declination and the mean equation of time of the days of
    the step's period (``period`` index per step, ``days`` per period) that the run covers
    (Spencer 1971 series, as pvlib).

    References
    ----------
    .. [1] EnergyPlus Engineering Reference 25.2, "Shading Module" (periodic calculation with
       the period's average solar declination and equation of time); SolarShading.cc,
       ``PerformSolarCalculations``.
    .. [2] Spencer, J. W. (1971), "Fourier series representation of the position of the sun",
       Search 2(5), 172.
    """
    from pvlib.solarposition import declination_spencer71, equation_of_time_spencer71

    instants = times + (at_end if at_end is not None else step / 2)
    utc = instants.tz_convert("UTC") if instants.tz is not None else instants
    day_of_year = utc.day_of_year.to_numpy()
    sin_decl = np.sin(declination_spencer71(day_of_year))
    eot = np.asarray(equation_of_time_spencer71(day_of_year), dtype=float)  # [min]
    period = np.asarray(period)
    # the days (one value each) of each period, averaged
    day_key = utc.normalize().as_unit("s").asi8 // 86_400
    _, first_of_day = np.unique(day_key, return_index=True)
    mean_sin = np.zeros(period.max() + 1)
    mean_eot = np.zeros(period.max() + 1)
    for p in range(period.max() + 1):
        in_period = first_of_day[period[first_of_day] == p][:days]
        if len(in_period):
            mean_sin[p] = sin_decl[in_period].mean()
            mean_eot[p] = eot[in_period].mean()
    decl = np.arcsin(mean_sin[period])
    hours = (utc - utc.normalize()).total_seconds().to_numpy() / 3600.0
    hour_angle = np.radians(15.0 * (hours - 12.0) + site["longitude"] + mean_eot[period] / 4.0)
    lat = np.radians(site["latitude"])
    up = np.sin(lat) * np.sin(decl) + np.cos(lat) * np.cos(decl) * np.cos(hour_angle)
    east = -np.cos(decl) * np.sin(hour_angle)
    north = np.cos(lat) * np.sin(decl) - np.sin(lat) * np.cos(decl) * np.cos(hour_angle)
    return np.stack([east, north, up], axis=1)


def _ground_reflectance(grid: pd.DataFrame, monthly) -> str | float | np.ndarray:
    """Ground reflectance [-] per step: the building's monthly values (January first) when it
    has them (an imported IDF always has, as EnergyPlus: ``Site:GroundReflectance`` or 0.2),
    else the weather's albedo column, else 0.2."""
    if monthly is not None:
        return np.asarray(monthly, dtype=float)[grid.index.month.to_numpy() - 1]
    return "weather" if "albedo" in grid else 0.2


def _irradiance(
    grid: pd.DataFrame,
    site: dict,
    orientations,
    model: str,
    at_end: pd.Timedelta | None = None,
    *,
    albedo: str | float | np.ndarray = "weather",
) -> dict:
    from thermocal.physics.solar import irradiance_on_surfaces

    position = _sun_position(grid.index, site, at_end)
    surfaces = {key: key for key in orientations}
    frames = irradiance_on_surfaces(
        grid,
        site["latitude"],
        site["longitude"],
        surfaces,
        altitude=site["altitude"],
        model=model,
        albedo=albedo if not (isinstance(albedo, str) and "albedo" not in grid) else 0.2,
        solar_position=position,
    )
    out = {}
    for key, frame in frames.items():
        out[key] = {
            c: np.nan_to_num(frame[c].to_numpy(dtype=float))
            for c in (
                "poa_global",
                "poa_direct",
                "poa_sky_diffuse",
                "poa_ground_diffuse",
                "aoi",
                "poa_sky_isotropic",
                "poa_sky_circumsolar",
                "poa_sky_horizon",
            )
        }
        out[key]["aoi"] = np.where(np.isfinite(frame["aoi"].to_numpy()), out[key]["aoi"], 90.0)
    return out


#: EnergyPlus' rain threshold: a step is wet when its (interpolated) liquid precipitation is at
#: least 0.8 mm per hour (WeatherManager: ``IsRainThreshold = 0.8 / TimeStepsInHour`` [mm] on the
#: step's depth)
RAIN_THRESHOLD_MM_PER_H = 0.8
#: liquid precipitation EnergyPlus assumes in an hour whose present weather says rain but whose
#: precipitation depth is zero or missing [mm/h]
PRESENT_WEATHER_RAIN_MM = 2.0


def _saturation_pressure(t):
    """Saturation vapour pressure over water (t >= 0) or ice [Pa] (ASHRAE HOF 2017, ch. 1)."""
    tk = np.asarray(t, dtype=float) + 273.15
    ice = np.exp(
        -5.6745359e3 / tk
        + 6.3925247
        - 9.677843e-3 * tk
        + 6.2215701e-7 * tk**2
        + 2.0747825e-9 * tk**3
        - 9.484024e-13 * tk**4
        + 4.1635019 * np.log(tk)
    )
    water = np.exp(
        -5.8002206e3 / tk
        + 1.3914993
        - 4.8640239e-2 * tk
        + 4.1764768e-5 * tk**2
        - 1.4452093e-8 * tk**3
        + 6.5459673 * np.log(tk)
    )
    return np.where(tk >= 273.15, water, ice)


def dew_point_temperature(temp_air, relative_humidity):
    """Dew point [C] of air at ``temp_air`` [C] and ``relative_humidity`` [%]: the temperature
    whose saturation pressure (:func:`_saturation_pressure`, ASHRAE) is the air's vapour
    pressure, found by bisection; NaN where the humidity is missing or not positive."""
    t = np.asarray(temp_air, dtype=float)
    rh = np.asarray(relative_humidity, dtype=float)
    target = np.clip(rh, 1e-3, 100.0) / 100.0 * _saturation_pressure(t)
    lo = np.full(t.shape, -100.0)
    hi = t.copy()
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        below = _saturation_pressure(mid) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return np.where(np.isfinite(rh) & (rh > 0), 0.5 * (lo + hi), np.nan)


def wet_bulb_temperature(temp_air, temp_dew, pressure):
    """Psychrometric wet-bulb temperature [C] from dry bulb [C], dew point [C], pressure [Pa]
    (ASHRAE HOF 2017 ch. 1 eq. 33/35 solved by bisection; EnergyPlus' PsyTwbFnTdbWPb)."""
    t = np.asarray(temp_air, dtype=float)
    p = np.broadcast_to(np.asarray(pressure, dtype=float), t.shape)
    pw = _saturation_pressure(np.minimum(np.asarray(temp_dew, dtype=float), t))
    w = 0.621945 * pw / (p - pw)
    lo = np.full(t.shape, -100.0)
    hi = t.copy()
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        ps = _saturation_pressure(mid)
        ws = 0.621945 * ps / (p - ps)
        w_mid = np.where(
            mid >= 0.0,
            ((2501.0 - 2.326 * mid) * ws - 1.006 * (t - mid)) / (2501.0 + 1.86 * t - 4.186 * mid),
            ((2830.0 - 0.24 * mid) * ws - 1.006 * (t - mid)) / (2830.0 + 1.86 * t - 2.1 * mid),
        )
        # w_mid grows with the guess: the wet bulb lies above mid when w_mid < w
        above = w_mid < w
        lo = np.where(above, mid, lo)
        hi = np.where(above, hi, mid)
    return 0.5 * (lo + hi)


def rain_steps(weather: pd.DataFrame, grid: pd.DataFrame, step: pd.Timedelta, interpolation: str):
    """Wet steps of the simulation grid as EnergyPlus flags them (bool (steps,)), None when the
    weather has neither precipitation nor present-weather observations.

    Hourly liquid precipitation (missing = 0; an hour whose present weather says rain with no
    depth takes 2 mm) is, with ``interpolation="energyplus"``, placed at the end of its hour and
    interpolated linearly to each step's end (EnergyPlus' weather manager); a step is wet when
    the rate is at least 0.8 mm/h. At one step per hour EnergyPlus skips that interpolation and
    takes the present-weather flag alone. With ``"hold"`` the step's mean rate is compared.
    """
    if "precipitation" not in weather and "weather_rain" not in weather:
        return None
    hour = pd.Timedelta("1h")
    flag = (
        weather["weather_rain"].fillna(0.0).to_numpy(dtype=float) > 0.0
        if "weather_rain" in weather
        else np.zeros(len(weather), dtype=bool)
    )
    if "precipitation" in weather:
        rate = weather["precipitation"].fillna(0.0).to_numpy(dtype=float)
    else:
        rate = np.zeros(len(weather))
    rate = np.where(flag & (rate == 0.0), PRESENT_WEATHER_RAIN_MM, rate)
    if interpolation == "energyplus":
        from thermocal.io.weather import weather_step

        wstep = weather_step(weather)
        if step == hour and wstep == hour:
            on = pd.Series(flag, index=weather.index).reindex(grid.index).fillna(0.0)
            return on.to_numpy(dtype=float) > 0.0
        n = int(round(hour / step))
        ends = (grid.index + step).as_unit("ns").asi8.astype(float)
        hour_ends = (weather.index + wstep).as_unit("ns").asi8.astype(float)
        depth = np.interp(ends, hour_ends, rate) / n  # [mm] per step (``rate`` in mm/h)
        return depth >= RAIN_THRESHOLD_MM_PER_H / n
    if "precipitation" in grid:
        g = grid["precipitation"].fillna(0.0).to_numpy(dtype=float)
    else:
        g = np.zeros(len(grid))
    if "weather_rain" in grid:
        pw = grid["weather_rain"].fillna(0.0).to_numpy(dtype=float) > 0.0
        g = np.where(pw & (g == 0.0), PRESENT_WEATHER_RAIN_MM, g)
    return g >= RAIN_THRESHOLD_MM_PER_H
