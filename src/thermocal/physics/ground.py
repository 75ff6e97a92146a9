"""Heat transfer to the ground (ISO 13370:2017) and undisturbed ground temperature at depth.

ISO 13370 functions return steady-state thermal transmittances [W/(m2 K)] or the steady-state
ground heat-transfer coefficient ``H_g`` [W/K] between the internal and the external (air)
temperature; the ground temperature functions give the undisturbed soil temperature for models
that couple a floor to the soil at some depth (the fifth-order retrofit method uses the
temperature at 2 m, after Zuercher & Frank).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

__all__ = [
    "R_SI_FLOOR",
    "R_SI_WALL",
    "R_SE",
    "characteristic_dimension",
    "equivalent_thickness",
    "iso13370_slab_on_ground",
    "iso13370_heated_basement",
    "iso13370_unheated_basement",
    "ground_heat_transfer_coefficient",
    "periodic_penetration_depth",
    "iso13370_slab_periodic_coefficients",
    "iso13370_monthly_heat_flow",
    "virtual_ground_temperature",
    "ground_temperature",
    "ground_temperature_parameters",
]

#: Internal surface resistance of a floor, heat flow downwards [m2 K/W] (ISO 13370, 7.1).
R_SI_FLOOR = 0.17
#: Internal surface resistance of a wall, horizontal heat flow [m2 K/W].
R_SI_WALL = 0.13
#: External surface resistance [m2 K/W].
R_SE = 0.04
#: Volumetric heat capacity of air used by ISO 13370 for basement ventilation [Wh/(m3 K)].
_AIR_WH_PER_M3K = 0.33

_SECONDS_PER_DAY = 86400.0


def _positive(name: str, value, unit: str, *, allow_zero: bool = False) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError) as exc:
        raise ThermocalInputError(f"parameter {name} = {value!r} [{unit}] is not a number") from exc
    if not np.isfinite(value) or value < 0.0 or (value == 0.0 and not allow_zero):
        relation = ">= 0" if allow_zero else "> 0"
        raise ThermocalInputError(f"parameter {name} = {value!r} [{unit}] must be {relation}")
    return value


def characteristic_dimension(area: float, perimeter: float) -> float:
    """Characteristic dimension of a floor ``B' = A / (0.5 P)`` [m].

    Parameters
    ----------
    area : float
        Floor area (measured to the inside of the external walls) [m2].
    perimeter : float
        Exposed perimeter of the floor [m].

    Returns
    -------
    float
        ``B'`` [m].

    References
    ----------
    .. [1] ISO 13370:2017, 8.1, equation (2).
    """
    area = _positive("area", area, "m2")
    perimeter = _positive("perimeter", perimeter, "m")
    if perimeter < 2.0 * np.sqrt(np.pi * area) * (1 - 1e-6):
        raise ThermocalInputError(
            f"perimeter = {perimeter} m is too short for a floor area of {area} m2 (a circle "
            f"needs at least {2 * np.sqrt(np.pi * area):.2f} m): are area and perimeter swapped?"
        )
    return area / (0.5 * perimeter)


def equivalent_thickness(
    conductivity: float,
    resistance: float = 0.0,
    *,
    wall_thickness: float = 0.0,
    internal_resistance: float = R_SI_FLOOR,
) -> float:
    """Total equivalent thickness ``d = w + lambda (R_si + R + R_se)`` [m].

    Parameters
    ----------
    conductivity : float
        Thermal conductivity of the unfrozen ground ``lambda`` [W/(m K)].
    resistance : float
        Thermal resistance of the floor (or wall) construction incl. insulation, without
        surface resistances [m2 K/W].
    wall_thickness : float
        Full thickness of the external walls ``w`` [m] (0 for basement walls).
    internal_resistance : float
        Internal surface resistance [m2 K/W] (0.17 floors, 0.13 walls).

    Returns
    -------
    float
        Equivalent thickness [m].

    References
    ----------
    .. [1] ISO 13370:2017, 9.1 equation (3) (floors) and 9.3 equation (9) (basement walls).
    """
    conductivity = _positive("soil_conductivity", conductivity, "W/(m K)")
    resistance = _positive("floor_resistance", resistance, "m2 K/W", allow_zero=True)
    wall_thickness = _positive("wall_thickness", wall_thickness, "m", allow_zero=True)
    return wall_thickness + conductivity * (internal_resistance + resistance + R_SE)


def _floor_transmittance(conductivity: float, b_prime: float, d_eq: float) -> float:
    """ISO 13370 floor formula for an equivalent thickness d_eq (d_t, or d_t + z/2)."""
    if d_eq < b_prime:
        return 2.0 * conductivity / (np.pi * b_prime + d_eq) * np.log(np.pi * b_prime / d_eq + 1.0)
    return conductivity / (0.457 * b_prime + d_eq)


def iso13370_slab_on_ground(
    area: float,
    perimeter: float,
    *,
    wall_thickness: float,
    floor_resistance: float = 0.0,
    soil_conductivity: float = 2.0,
) -> float:
    """Thermal transmittance of a slab-on-ground floor ``U`` [W/(m2 K)].

    ``B' = A / (0.5 P)``, ``d_t = w + lambda (R_si + R_f + R_se)``;
    ``U = 2 lambda / (pi B' + d_t) ln(pi B' / d_t + 1)`` if ``d_t < B'`` (uninsulated and
    moderately insulated), else ``U = lambda / (0.457 B' + d_t)`` (well insulated).

    Parameters
    ----------
    area : float
        Floor area [m2].
    perimeter : float
        Exposed perimeter [m].
    wall_thickness : float
        Full thickness of the external walls at ground level ``w`` [m].
    floor_resistance : float
        Thermal resistance of the floor slab incl. insulation and covering ``R_f`` [m2 K/W].
    soil_conductivity : float
        Thermal conductivity of the ground ``lambda`` [W/(m K)] (ISO 13370 Table 7: 1.5 clay
        or silt; 2.0 sand or gravel, also the value to use when the soil is unknown; 3.5
        homogeneous rock).

    Returns
    -------
    float
        ``U`` [W/(m2 K)]; ``H_g = A U`` (+ ``P psi_g`` for the wall/floor junction).

    References
    ----------
    .. [1] ISO 13370:2017, 9.1, equations (2)-(5).
    """
    b_prime = characteristic_dimension(area, perimeter)
    d_t = equivalent_thickness(soil_conductivity, floor_resistance, wall_thickness=wall_thickness)
    return _floor_transmittance(float(soil_conductivity), b_prime, d_t)


def _basement_parts(
    area,
    perimeter,
    depth,
    wall_thickness,
    floor_resistance,
    wall_resistance,
    soil_conductivity,
):
    b_prime = characteristic_dimension(area, perimeter)
    depth = _positive("basement_depth", depth, "m")
    lam = _positive("soil_conductivity", soil_conductivity, "W/(m K)")
    d_t = equivalent_thickness(lam, floor_resistance, wall_thickness=wall_thickness)
    u_floor = _floor_transmittance(lam, b_prime, d_t + 0.5 * depth)
    d_w = equivalent_thickness(lam, wall_resistance, internal_resistance=R_SI_WALL)
    d_first = min(d_t, d_w)  # ISO 13370 9.3: replace d_t by d_w when d_w < d_t
    u_wall = (
        2.0 * lam / (np.pi * depth) * (1.0 + 0.5 * d_first / (d_first + depth))
        * np.log(depth / d_w + 1.0)
    )  # fmt: skip
    return u_floor, u_wall


def iso13370_heated_basement(
    area: float,
    perimeter: float,
    depth: float,
    *,
    wall_thickness: float,
    floor_resistance: float = 0.0,
    wall_resistance: float = 0.0,
    soil_conductivity: float = 2.0,
) -> dict[str, float]:
    """Heated basement: transmittances of the basement floor and walls, and ``H_g`` [W/K].

    Floor: the slab formula with ``d_t + 0.5 z`` in place of ``d_t``. Walls:
    ``U_bw = 2 lambda / (pi z) (1 + 0.5 d_t / (d_t + z)) ln(z / d_w + 1)`` with
    ``d_w = lambda (R_si + R_w + R_se)`` (``d_t`` replaced by ``d_w`` when ``d_w < d_t``).
    ``H_g = A U_bf + z P U_bw``.

    Parameters
    ----------
    area : float
        Basement floor area [m2].
    perimeter : float
        Exposed perimeter [m].
    depth : float
        Depth of the basement floor below ground level ``z`` [m].
    wall_thickness : float
        Thickness of the walls at ground level ``w`` [m].
    floor_resistance : float
        Thermal resistance of the basement floor ``R_f`` [m2 K/W].
    wall_resistance : float
        Thermal resistance of the basement walls below ground ``R_w`` [m2 K/W].
    soil_conductivity : float
        Ground conductivity ``lambda`` [W/(m K)].

    Returns
    -------
    dict
        ``u_floor`` [W/(m2 K)], ``u_wall`` [W/(m2 K)], ``heat_transfer_coefficient`` [W/K],
        ``u_equivalent`` (``H_g / A``) [W/(m2 K)].

    References
    ----------
    .. [1] ISO 13370:2017, 9.3, equations (7)-(11).
    """
    u_floor, u_wall = _basement_parts(
        area, perimeter, depth, wall_thickness, floor_resistance, wall_resistance, soil_conductivity
    )
    h_g = area * u_floor + depth * perimeter * u_wall
    return {
        "u_floor": u_floor,
        "u_wall": u_wall,
        "heat_transfer_coefficient": h_g,
        "u_equivalent": h_g / area,
    }


def iso13370_unheated_basement(
    area: float,
    perimeter: float,
    depth: float,
    *,
    u_ceiling: float,
    wall_thickness: float,
    u_wall_above_ground: float,
    height_above_ground: float,
    basement_volume: float,
    air_changes: float = 0.3,
    floor_resistance: float = 0.0,
    wall_resistance: float = 0.0,
    soil_conductivity: float = 2.0,
) -> dict[str, float]:
    """Unheated basement under a heated floor (the cellar ceiling in series with the cellar).

    ``1/U = 1/U_f + A / (A U_bf + z P U_bw + h P U_w + 0.33 n V)``: the ceiling ``U_f`` in series
    with the basement's losses through its floor and walls to the ground, its walls above ground
    and its ventilation.

    Parameters
    ----------
    area : float
        Floor area of the cellar ceiling / basement [m2].
    perimeter : float
        Exposed perimeter [m].
    depth : float
        Depth of the basement floor below ground level ``z`` [m].
    u_ceiling : float
        Thermal transmittance of the cellar ceiling (the floor above the basement) ``U_f``
        [W/(m2 K)].
    wall_thickness : float
        Thickness of the walls at ground level ``w`` [m].
    u_wall_above_ground : float
        Thermal transmittance of the basement walls above ground ``U_w`` [W/(m2 K)].
    height_above_ground : float
        Height of the cellar ceiling above outside ground level ``h`` [m].
    basement_volume : float
        Air volume of the basement ``V`` [m3].
    air_changes : float
        Ventilation rate of the basement ``n`` [1/h] (ISO 13370 default 0.3).
    floor_resistance : float
        Thermal resistance of the basement floor ``R_f`` [m2 K/W].
    wall_resistance : float
        Thermal resistance of the basement walls below ground ``R_w`` [m2 K/W].
    soil_conductivity : float
        Ground conductivity ``lambda`` [W/(m K)].

    Returns
    -------
    dict
        ``u_equivalent`` (``U``) [W/(m2 K)], ``heat_transfer_coefficient`` (``A U``) [W/K],
        ``u_floor``, ``u_wall`` [W/(m2 K)], ``basement_loss_coefficient`` (the denominator
        ``A U_bf + z P U_bw + h P U_w + 0.33 n V``) [W/K].

    References
    ----------
    .. [1] ISO 13370:2017, 9.4, equations (12)-(13).
    """
    u_ceiling = _positive("u_ceiling", u_ceiling, "W/(m2 K)")
    if u_ceiling > 10.0:
        raise ThermocalInputError(
            f"u_ceiling = {u_ceiling} W/(m2 K) is implausible for a cellar ceiling (0.2-3); a "
            "typo for a value 10 or 100 times smaller?"
        )
    u_wall_above = _positive(
        "u_wall_above_ground", u_wall_above_ground, "W/(m2 K)", allow_zero=True
    )
    height = _positive("height_above_ground", height_above_ground, "m", allow_zero=True)
    volume = _positive("basement_volume", basement_volume, "m3", allow_zero=True)
    air_changes = _positive("air_changes", air_changes, "1/h", allow_zero=True)
    u_floor, u_wall = _basement_parts(
        area, perimeter, depth, wall_thickness, floor_resistance, wall_resistance, soil_conductivity
    )
    basement = (
        area * u_floor
        + depth * perimeter * u_wall
        + height * perimeter * u_wall_above
        + _AIR_WH_PER_M3K * air_changes * volume
    )
    u = 1.0 / (1.0 / u_ceiling + area / basement)
    return {
        "u_equivalent": u,
        "heat_transfer_coefficient": area * u,
        "u_floor": u_floor,
        "u_wall": u_wall,
        "basement_loss_coefficient": basement,
    }


def ground_heat_transfer_coefficient(
    area: float,
    perimeter: float,
    *,
    basement: str = "none",
    wall_thickness: float,
    soil_conductivity: float = 2.0,
    floor_resistance: float = 0.0,
    linear_thermal_transmittance: float = 0.0,
    **basement_kwargs,
) -> float:
    """Steady-state ground heat-transfer coefficient ``H_g = A U + P psi_g`` [W/K].

    Parameters
    ----------
    area : float
        Floor area [m2].
    perimeter : float
        Exposed perimeter [m].
    basement : {"none", "heated", "unheated"}
        Slab on ground, heated or unheated basement.
    wall_thickness : float
        Wall thickness at ground level [m].
    soil_conductivity : float
        Ground conductivity [W/(m K)].
    floor_resistance : float
        Floor (slab or basement floor) resistance [m2 K/W].
    linear_thermal_transmittance : float
        ``psi_g`` of the wall/floor junction [W/(m K)].
    **basement_kwargs
        ``depth`` and the other keywords of :func:`iso13370_heated_basement` /
        :func:`iso13370_unheated_basement`.

    Returns
    -------
    float
        ``H_g`` [W/K].

    References
    ----------
    .. [1] ISO 13370:2017, 7.2 (H_g = A U + P psi_g) and clause 9.
    """
    if basement == "none":
        if basement_kwargs:
            raise ThermocalInputError(
                f"slab on ground takes no basement parameters, got {sorted(basement_kwargs)}"
            )
        u = iso13370_slab_on_ground(
            area,
            perimeter,
            wall_thickness=wall_thickness,
            floor_resistance=floor_resistance,
            soil_conductivity=soil_conductivity,
        )
        h = area * u
    elif basement in ("heated", "unheated"):
        if "depth" not in basement_kwargs:
            raise ThermocalInputError(f"a {basement} basement needs depth= (below ground) [m]")
        function = iso13370_heated_basement if basement == "heated" else iso13370_unheated_basement
        depth = basement_kwargs.pop("depth")
        try:
            h = function(
                area,
                perimeter,
                depth,
                wall_thickness=wall_thickness,
                floor_resistance=floor_resistance,
                soil_conductivity=soil_conductivity,
                **basement_kwargs,
            )["heat_transfer_coefficient"]
        except TypeError as exc:
            raise ThermocalInputError(f"{basement} basement: {exc}") from exc
    else:
        raise ThermocalInputError(
            f"basement = {basement!r}: use 'none' (slab on ground), 'heated' or 'unheated'"
        )
    return h + float(perimeter) * float(linear_thermal_transmittance)


# --------------------------------------------------------------------------------------------
# ISO 13370 periodic (monthly) heat flow
# --------------------------------------------------------------------------------------------
#: Period of the annual cycle ISO 13370 uses in the penetration depth [s] (equation H.1).
_ISO_YEAR_SECONDS = 3.15e7


def periodic_penetration_depth(soil_conductivity: float, volumetric_heat_capacity: float) -> float:
    """Periodic penetration depth of the annual cycle ``delta = sqrt(3.15e7 lambda / (pi rho c))``.

    Parameters
    ----------
    soil_conductivity : float
        Thermal conductivity of the ground ``lambda`` [W/(m K)].
    volumetric_heat_capacity : float
        ``rho c`` of the ground [J/(m3 K)] (ISO 13370 Table 7: 3.0e6 clay or silt, 2.0e6
        sand or gravel and rock).

    Returns
    -------
    float
        ``delta`` [m] (Table H.1: 2.2 m clay or silt, 3.2 m sand or gravel, 4.2 m rock).

    References
    ----------
    .. [1] ISO 13370:2017, Annex H, equation (H.1) and Table H.1.
    """
    lam = _positive("soil_conductivity", soil_conductivity, "W/(m K)")
    rho_c = _positive("volumetric_heat_capacity", volumetric_heat_capacity, "J/(m3 K)")
    return float(np.sqrt(_ISO_YEAR_SECONDS * lam / (np.pi * rho_c)))


def iso13370_slab_periodic_coefficients(
    area: float,
    perimeter: float,
    *,
    wall_thickness: float,
    floor_resistance: float = 0.0,
    soil_conductivity: float = 2.0,
    volumetric_heat_capacity: float = 2.0e6,
) -> dict[str, float]:
    """Periodic heat transfer coefficients of an uninsulated or all-over insulated slab.

    ``H_pi = A lambda / d_t sqrt(2 / ((1 + delta / d_t)^2 + 1))`` (internal) and
    ``H_pe = 0.37 P lambda ln(delta / d_t + 1)`` (external), with the total equivalent
    thickness ``d_t`` of :func:`equivalent_thickness` and the penetration depth ``delta`` of
    :func:`periodic_penetration_depth`.

    Parameters
    ----------
    area : float
        Floor area ``A`` [m2].
    perimeter : float
        Exposed perimeter ``P`` [m].
    wall_thickness : float
        Full thickness of the external walls at ground level ``w`` [m].
    floor_resistance : float
        Thermal resistance of the slab incl. insulation and covering ``R_f`` [m2 K/W].
    soil_conductivity : float
        ``lambda`` [W/(m K)].
    volumetric_heat_capacity : float
        ``rho c`` of the ground [J/(m3 K)] (default 2.0e6, ISO 13370 Table 7 for the default
        ``lambda`` of 2.0).

    Returns
    -------
    dict
        ``h_pi``, ``h_pe`` [W/K], ``d_t``, ``delta`` [m].

    References
    ----------
    .. [1] ISO 13370:2017, Annex H, equations (H.2) and (H.3) (slab on ground, no edge
       insulation).
    """
    area = _positive("area", area, "m2")
    perimeter = _positive("perimeter", perimeter, "m")
    lam = _positive("soil_conductivity", soil_conductivity, "W/(m K)")
    d_t = equivalent_thickness(lam, floor_resistance, wall_thickness=wall_thickness)
    delta = periodic_penetration_depth(lam, volumetric_heat_capacity)
    h_pi = area * lam / d_t * np.sqrt(2.0 / ((1.0 + delta / d_t) ** 2 + 1.0))
    h_pe = 0.37 * perimeter * lam * np.log(delta / d_t + 1.0)
    return {"h_pi": float(h_pi), "h_pe": float(h_pe), "d_t": float(d_t), "delta": float(delta)}


def iso13370_monthly_heat_flow(
    h_g: float,
    h_pi: float,
    h_pe: float,
    internal_monthly,
    external_monthly,
    *,
    lead_months: int = 0,
    lag_months: int = 1,
) -> np.ndarray:
    """Mean ground heat flow rate of each month (ISO 13370's monthly method) [W].

    ``Phi_m = H_g (Ti_mean - Te_mean) - H_pi (Ti_mean - Ti_(m + alpha))
    + H_pe (Te_mean - Te_(m - beta))`` with the annual means of the twelve monthly means, the
    heat flow leading the internal temperature by ``alpha`` and lagging the external one by
    ``beta`` months. For sinusoidal temperatures this is the standard's cosine form
    ``H_g (Ti_mean - Te_mean) - H_pi Ti_amp cos(2 pi (m - tau + alpha) / 12)
    + H_pe Te_amp cos(2 pi (m - tau - beta) / 12)``.

    Parameters
    ----------
    h_g : float
        Steady-state ground heat transfer coefficient [W/K].
    h_pi, h_pe : float
        Internal and external periodic heat transfer coefficients [W/K]
        (:func:`iso13370_slab_periodic_coefficients`).
    internal_monthly, external_monthly : array-like (12,)
        Monthly mean internal and external air temperatures, January first [C].
    lead_months, lag_months : int
        ``alpha`` and ``beta`` [months]; default 0 and 1, the values ISO 52016-1 takes for
        its virtual ground temperature.

    Returns
    -------
    ndarray (12,)
        ``Phi_m`` [W], heat out of the building positive.

    References
    ----------
    .. [1] ISO 13370:2017, Annex C (monthly heat flow rates) and Annex H (coefficients).
    .. [2] ISO 52016-1:2017, 6.5.8 (virtual ground temperature, time lead 0 and lag 1 month).
    """
    ti = np.asarray(internal_monthly, dtype=float)
    te = np.asarray(external_monthly, dtype=float)
    if ti.shape != (12,) or te.shape != (12,):
        raise ThermocalInputError(
            f"iso13370_monthly_heat_flow needs 12 monthly temperatures each, got {ti.shape} "
            f"and {te.shape}"
        )
    ti_lead = np.roll(ti, -int(lead_months))  # value of month m + alpha
    te_lag = np.roll(te, int(lag_months))  # value of month m - beta
    return (
        float(h_g) * (ti.mean() - te.mean())
        - float(h_pi) * (ti.mean() - ti_lead)
        + float(h_pe) * (te.mean() - te_lag)
    )


def virtual_ground_temperature(internal_monthly, heat_flow_monthly, conductance: float):
    """Monthly temperature behind a floor's ground conductance that gives ISO 13370's flow.

    ``theta_vi,m = Ti_m - Phi_m / (A U)``: a dynamic model that couples the floor to this
    temperature through ``A U`` loses ``Phi_m`` in each month's mean.

    Parameters
    ----------
    internal_monthly : array-like (12,)
        Monthly mean internal temperature [C].
    heat_flow_monthly : array-like (12,)
        ``Phi_m`` of :func:`iso13370_monthly_heat_flow` [W] (without the junction's
        ``P psi`` share).
    conductance : float
        ``A U`` [W/K].

    Returns
    -------
    ndarray (12,) [C]

    References
    ----------
    .. [1] ISO 13370:2017, Annex F, equation (F.2) (approximate virtual temperature).
    """
    conductance = _positive("conductance", conductance, "W/K")
    return np.asarray(internal_monthly, float) - np.asarray(heat_flow_monthly, float) / conductance


# --------------------------------------------------------------------------------------------
# ground temperature
# --------------------------------------------------------------------------------------------
def ground_temperature(
    times: pd.DatetimeIndex,
    depth: float,
    *,
    annual_mean: float,
    amplitude: float,
    phase_day: float,
    diffusivity: float = 6.45e-7,
) -> pd.Series:
    """Undisturbed ground temperature at depth: damped, delayed annual sinusoid (Kusuda).

    ``T(z, t) = T_m - A_s exp(-z sqrt(pi / (365 alpha)))
    cos(2 pi / 365 (t - t_0 - z / 2 sqrt(365 / (pi alpha))))`` with ``t`` the day of the year,
    ``t_0`` the day of the minimum surface temperature and ``alpha`` in m2/day.

    Parameters
    ----------
    times : pandas.DatetimeIndex
        Instants (day of year and fraction of day are used).
    depth : float
        Depth below the surface ``z`` [m].
    annual_mean : float
        Annual mean surface temperature ``T_m`` [C] (about the annual mean air temperature).
    amplitude : float
        Amplitude of the annual surface temperature wave ``A_s`` [K].
    phase_day : float
        Day of the year of the minimum surface temperature ``t_0`` [d] (about 15-35 in central
        Europe).
    diffusivity : float
        Thermal diffusivity of the soil ``alpha`` [m2/s]; default 6.45e-7 (0.025 ft2/h, the
        value of the EnergyPlus weather converter; moist soils 0.4e-6 to 1.0e-6).

    Returns
    -------
    pandas.Series
        Ground temperature [C], indexed by ``times``.

    References
    ----------
    .. [1] Kusuda, T. and Achenbach, P. R. (1965), "Earth temperature and thermal diffusivity at
       selected stations in the United States", ASHRAE Transactions 71(1).
    .. [2] Zuercher, C. and Frank, T. (2018), Bauphysik, 5th ed., vdf Zurich (ground temperature
       at depth, as used by the fifth-order retrofit method).
    """
    depth = _positive("depth", depth, "m", allow_zero=True)
    diffusivity = _positive("diffusivity", diffusivity, "m2/s")
    amplitude = float(amplitude)
    if diffusivity > 1e-4:
        raise ThermocalInputError(
            f"diffusivity = {diffusivity} m2/s is implausible for soil (~1e-7 to 2e-6 m2/s); "
            "was it given in m2/day or m2/h?"
        )
    alpha_day = diffusivity * _SECONDS_PER_DAY
    times = pd.DatetimeIndex(times)
    day = (times.day_of_year - 1) + (times.hour * 3600 + times.minute * 60 + times.second) / (
        _SECONDS_PER_DAY
    )
    day = np.asarray(day, dtype=float)
    damping = np.exp(-depth * np.sqrt(np.pi / (365.0 * alpha_day)))
    lag = 0.5 * depth * np.sqrt(365.0 / (np.pi * alpha_day))
    values = float(annual_mean) - amplitude * damping * np.cos(
        2.0 * np.pi / 365.0 * (day - float(phase_day) - lag)
    )
    return pd.Series(values, index=times, name="temp_ground")


def ground_temperature_parameters(weather: pd.DataFrame) -> dict[str, float]:
    """Annual mean, amplitude and phase of the surface temperature wave from a weather frame.

    Least-squares fit of ``T_m - A_s cos(2 pi (d - t_0) / 365)`` to the daily mean air
    temperatures (at least 300 days, ideally a whole year), the air temperature standing in for
    the surface temperature as in the EnergyPlus weather converter and Zuercher & Frank.

    Parameters
    ----------
    weather : pandas.DataFrame
        Standard weather frame with ``temp_air`` [C] and a DatetimeIndex.

    Returns
    -------
    dict
        ``annual_mean`` [C], ``amplitude`` [K], ``phase_day`` [d] (day of year of the minimum,
        0-based like :func:`ground_temperature`), for :func:`ground_temperature`.

    References
    ----------
    .. [1] Kusuda and Achenbach (1965), see :func:`ground_temperature`.
    """
    if "temp_air" not in weather:
        raise ThermocalInputError(
            f"ground_temperature_parameters: the weather has no 'temp_air' column (has "
            f"{list(weather.columns)})"
        )
    daily = weather["temp_air"].groupby(weather.index.normalize()).mean().dropna()
    if len(daily) < 300:
        raise ThermocalInputError(
            f"ground_temperature_parameters: {len(daily)} days of air temperature; at least 300 "
            "days (ideally a whole year) are needed to fit the annual wave"
        )
    day = np.asarray(pd.DatetimeIndex(daily.index).day_of_year - 1, dtype=float) + 0.5
    omega = 2.0 * np.pi / 365.0
    design = np.column_stack([np.ones_like(day), np.cos(omega * day), np.sin(omega * day)])
    (mean, a, b), *_ = np.linalg.lstsq(design, daily.to_numpy(), rcond=None)
    amplitude = float(np.hypot(a, b))
    # a cos + b sin = amplitude cos(omega d - phi); minimum where omega d - phi = pi
    phi = np.arctan2(b, a)
    phase_day = float(np.mod((phi + np.pi) / omega, 365.0))
    return {"annual_mean": float(mean), "amplitude": amplitude, "phase_day": phase_day}
