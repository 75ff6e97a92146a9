"""Surface heat-transfer coefficients (ISO 52016-1 Table 25, ISO 6946 Annex C, ISO 13789 Table 8).

Conventional values: internal convective ``h_ci`` = 5.0 (heat flow upwards), 2.5 (horizontal),
0.7 (downwards) W/(m2 K); external convective ``h_ce`` = 20 W/(m2 K) (or ``4 + 4 v`` with the wind
speed ``v``, ISO 6946 C.3); radiative ``h_r = eps h_r0`` with the black-body coefficient
``h_r0 = 4 sigma T_mn^3`` (ISO 6946 C.2), which gives the tabulated ``h_ri`` = 5.13 (eps = 0.9,
20 C) and ``h_re`` = 4.14 (eps = 0.9, 0 C). Heat flow within +/- 30 deg of the horizontal counts
as horizontal (ISO 6946, 6.8).
"""

from __future__ import annotations

import numpy as np

from thermocal.errors import ThermocalInputError

__all__ = [
    "H_CI_UPWARDS",
    "H_CI_HORIZONTAL",
    "H_CI_DOWNWARDS",
    "H_CE",
    "H_RI",
    "H_RE",
    "STEFAN_BOLTZMANN",
    "heat_flow_direction",
    "radiative_coefficient",
    "internal_convective_coefficient",
    "external_convective_coefficient",
    "internal_surface_coefficient",
    "external_surface_coefficient",
    "internal_surface_resistance",
    "external_surface_resistance",
    "surface_conductance",
]

#: Internal convective coefficient, heat flow upwards [W/(m2 K)] (ISO 52016-1 Table 25).
H_CI_UPWARDS = 5.0
#: Internal convective coefficient, horizontal heat flow [W/(m2 K)].
H_CI_HORIZONTAL = 2.5
#: Internal convective coefficient, heat flow downwards [W/(m2 K)].
H_CI_DOWNWARDS = 0.7
#: External convective coefficient [W/(m2 K)] (ISO 52016-1 Table 25; 4 + 4 v with v = 4 m/s).
H_CE = 20.0
#: Internal radiative coefficient [W/(m2 K)] (eps = 0.9 at 20 C).
H_RI = 5.13
#: External radiative coefficient [W/(m2 K)] (eps = 0.9 at 0 C).
H_RE = 4.14
#: Stefan-Boltzmann constant [W/(m2 K4)].
STEFAN_BOLTZMANN = 5.670374419e-8

_DIRECTIONS = {"upwards": H_CI_UPWARDS, "horizontal": H_CI_HORIZONTAL, "downwards": H_CI_DOWNWARDS}
_ALIASES = {"up": "upwards", "down": "downwards", "upward": "upwards", "downward": "downwards"}


def heat_flow_direction(tilt: float, *, heat_flows_outwards: bool = True) -> str:
    """Direction of the heat flow through an element of given tilt.

    Parameters
    ----------
    tilt : float
        Tilt of the element's outward normal [deg]: 0 roof facing up, 90 wall, 180 floor facing
        down.
    heat_flows_outwards : bool
        True in heating conditions (inside warmer than outside), False in cooling conditions.

    Returns
    -------
    str
        "upwards", "horizontal" or "downwards". Within +/- 30 deg of the horizontal (tilt 60 to
        120 deg) the flow is horizontal.

    References
    ----------
    .. [1] ISO 6946:2017, 6.8 (surface resistances; +/- 30 deg rule).
    """
    tilt = float(tilt)
    if not 0.0 <= tilt <= 180.0:
        raise ThermocalInputError(f"tilt = {tilt} deg is outside [0, 180] deg")
    if 60.0 <= tilt <= 120.0:
        return "horizontal"
    upward_normal = tilt < 60.0
    return "upwards" if upward_normal == heat_flows_outwards else "downwards"


def radiative_coefficient(emissivity: float = 0.9, temp_mean: float = 20.0) -> float:
    """Linearised radiative heat-transfer coefficient ``h_r = 4 eps sigma T_mn^3`` [W/(m2 K)].

    Parameters
    ----------
    emissivity : float
        Hemispherical emissivity of the surface [-].
    temp_mean : float
        Mean of the surface and its radiant surroundings [C].

    Returns
    -------
    float
        ``h_r`` [W/(m2 K)]; 5.13 for eps = 0.9 at 20 C, 4.14 at 0 C.

    References
    ----------
    .. [1] ISO 6946:2017, C.2 (h_r = eps h_r0, h_r0 = 4 sigma T_mn^3).
    """
    emissivity = np.asarray(emissivity, dtype=float)
    if np.any((emissivity < 0.0) | (emissivity > 1.0)):
        raise ThermocalInputError(f"emissivity = {emissivity} [-] is outside [0, 1]")
    if np.any(np.asarray(temp_mean) < -273.15):
        raise ThermocalInputError(f"temp_mean = {temp_mean} C is below absolute zero")
    value = 4.0 * emissivity * STEFAN_BOLTZMANN * (np.asarray(temp_mean, dtype=float) + 273.15) ** 3
    return float(value) if np.ndim(value) == 0 else value


def internal_convective_coefficient(heat_flow_direction: str) -> float:
    """Internal convective coefficient ``h_ci`` by heat-flow direction [W/(m2 K)].

    Parameters
    ----------
    heat_flow_direction : {"upwards", "horizontal", "downwards"}
        Direction of the heat flow (see :func:`heat_flow_direction`).

    Returns
    -------
    float
        5.0, 2.5 or 0.7 [W/(m2 K)].

    References
    ----------
    .. [1] ISO 52016-1:2017, Table 25; ISO 13789:2017, Table 8.
    """
    key = _ALIASES.get(str(heat_flow_direction).lower(), str(heat_flow_direction).lower())
    if key not in _DIRECTIONS:
        raise ThermocalInputError(
            f"heat_flow_direction = {heat_flow_direction!r}: use 'upwards', 'horizontal' or "
            "'downwards'"
        )
    return _DIRECTIONS[key]


def external_convective_coefficient(wind_speed: float | np.ndarray | None = None):
    """External convective coefficient ``h_ce`` [W/(m2 K)].

    Parameters
    ----------
    wind_speed : float or array-like, optional
        Wind speed near the surface [m/s]. Without it the conventional 20 W/(m2 K) of
        ISO 52016-1 Table 25 (= 4 + 4 x 4 m/s).

    Returns
    -------
    float or numpy.ndarray
        ``4 + 4 v`` or 20 [W/(m2 K)].

    References
    ----------
    .. [1] ISO 6946:2017, C.3; ISO 52016-1:2017, Table 25.
    """
    if wind_speed is None:
        return H_CE
    v = np.asarray(wind_speed, dtype=float)
    if np.any(v < 0.0):
        raise ThermocalInputError(f"wind_speed must be >= 0 m/s, got minimum {np.nanmin(v):g}")
    value = 4.0 + 4.0 * v
    return float(value) if np.ndim(value) == 0 else value


def internal_surface_coefficient(
    heat_flow_direction: str = "horizontal",
    *,
    emissivity: float = 0.9,
    temp_mean: float | None = None,
    split: bool = False,
):
    """Total internal surface coefficient ``h_si = h_ci + h_ri`` [W/(m2 K)].

    Parameters
    ----------
    heat_flow_direction : {"upwards", "horizontal", "downwards"}
        Direction of the heat flow.
    emissivity : float
        Surface emissivity [-].
    temp_mean : float, optional
        Mean radiant temperature for ``h_ri = 4 eps sigma T_mn^3`` [C]; when omitted the
        tabulated ``h_ri = 5.13 eps / 0.9`` of ISO 52016-1 Table 25.
    split : bool
        Return ``(h_ci, h_ri)`` instead of their sum.

    Returns
    -------
    float or tuple of float
        ``h_ci + h_ri`` [W/(m2 K)] (7.63 for a wall at the defaults), or ``(h_ci, h_ri)``.

    References
    ----------
    .. [1] ISO 52016-1:2017, 6.5.6.3 and Table 25.
    """
    h_ci = internal_convective_coefficient(heat_flow_direction)
    h_ri = _tabulated_or_linearised(H_RI, emissivity, temp_mean)
    return (h_ci, h_ri) if split else h_ci + h_ri


def external_surface_coefficient(
    wind_speed: float | np.ndarray | None = None,
    *,
    emissivity: float = 0.9,
    temp_mean: float | None = None,
    split: bool = False,
):
    """Total external surface coefficient ``h_se = h_ce + h_re`` [W/(m2 K)].

    Parameters
    ----------
    wind_speed : float or array-like, optional
        Wind speed [m/s]; without it ``h_ce`` = 20 W/(m2 K).
    emissivity : float
        Surface emissivity [-].
    temp_mean : float, optional
        Mean of surface and surroundings for ``h_re = 4 eps sigma T_mn^3`` [C]; when omitted
        the tabulated ``h_re = 4.14 eps / 0.9`` of ISO 52016-1 Table 25 (ISO 6946: h_r0 = 4.6
        at 0 C).
    split : bool
        Return ``(h_ce, h_re)`` instead of their sum.

    Returns
    -------
    float, numpy.ndarray or tuple
        ``h_ce + h_re`` [W/(m2 K)] (24.14 at the defaults, R_se = 0.04 m2 K/W).

    References
    ----------
    .. [1] ISO 52016-1:2017, 6.5.6.3 and Table 25; ISO 6946:2017, Annex C.
    """
    h_ce = external_convective_coefficient(wind_speed)
    h_re = _tabulated_or_linearised(H_RE, emissivity, temp_mean)
    return (h_ce, h_re) if split else h_ce + h_re


def internal_surface_resistance(heat_flow_direction: str = "horizontal", **kwargs) -> float:
    """Internal surface resistance ``R_si = 1 / (h_ci + h_ri)`` [m2 K/W].

    Parameters
    ----------
    heat_flow_direction : {"upwards", "horizontal", "downwards"}
        Direction of the heat flow.
    **kwargs
        ``emissivity`` [-], ``temp_mean`` [C], see :func:`internal_surface_coefficient`.

    Returns
    -------
    float
        0.13 (horizontal), 0.10 (upwards), 0.17 (downwards) [m2 K/W] at the defaults.

    References
    ----------
    .. [1] ISO 6946:2017, Table 7.
    """
    return 1.0 / internal_surface_coefficient(heat_flow_direction, **kwargs)


def external_surface_resistance(wind_speed=None, **kwargs):
    """External surface resistance ``R_se = 1 / (h_ce + h_re)`` [m2 K/W].

    Parameters
    ----------
    wind_speed : float or array-like, optional
        Wind speed [m/s].
    **kwargs
        ``emissivity`` [-], ``temp_mean`` [C], see :func:`external_surface_coefficient`.

    Returns
    -------
    float or numpy.ndarray
        0.04 m2 K/W at the defaults.

    References
    ----------
    .. [1] ISO 6946:2017, Table 7.
    """
    return 1.0 / external_surface_coefficient(wind_speed, **kwargs)


def surface_conductance(
    area: float,
    heat_flow_direction: str = "horizontal",
    *,
    side: str = "internal",
    wind_speed: float | np.ndarray | None = None,
    emissivity: float = 0.9,
    temp_mean: float | None = None,
    part: str = "total",
):
    """Surface heat-transfer conductance of an element, ``H = A h`` [W/K].

    Parameters
    ----------
    area : float
        Surface area [m2].
    heat_flow_direction : {"upwards", "horizontal", "downwards"}
        Heat-flow direction (internal side only).
    side : {"internal", "external"}
        Which side of the element.
    wind_speed : float or array-like, optional
        Wind speed for the external side [m/s].
    emissivity : float
        Surface emissivity [-].
    temp_mean : float, optional
        Mean radiant temperature [C]; default: the tabulated radiative coefficients.
    part : {"total", "convective", "radiative"}
        Which part of the coefficient.

    Returns
    -------
    float or numpy.ndarray
        ``H`` [W/K].

    References
    ----------
    .. [1] ISO 52016-1:2017, 6.5.6.3 and Table 25.
    """
    area = float(area)
    if not np.isfinite(area) or area < 0.0:
        raise ThermocalInputError(f"area = {area} m2 must be a finite number >= 0")
    if side == "internal":
        h_c, h_r = internal_surface_coefficient(
            heat_flow_direction,
            emissivity=emissivity,
            temp_mean=temp_mean,
            split=True,
        )
    elif side == "external":
        h_c, h_r = external_surface_coefficient(
            wind_speed,
            emissivity=emissivity,
            temp_mean=temp_mean,
            split=True,
        )
    else:
        raise ThermocalInputError(f"side = {side!r}: use 'internal' or 'external'")
    parts = {"total": h_c + h_r, "convective": h_c, "radiative": h_r}
    if part not in parts:
        raise ThermocalInputError(f"part = {part!r}: use 'total', 'convective' or 'radiative'")
    return area * parts[part]


def _tabulated_or_linearised(tabulated: float, emissivity: float, temp_mean: float | None):
    """Tabulated coefficient (for eps = 0.9) scaled by emissivity, or the linearised formula."""
    if temp_mean is not None:
        return radiative_coefficient(emissivity, temp_mean)
    radiative_coefficient(emissivity, 0.0)  # validates the emissivity
    return tabulated * float(emissivity) / 0.9
