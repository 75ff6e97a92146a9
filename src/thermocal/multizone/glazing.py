"""Glazing optics and heat transfer: layered glass/gas systems and the EnergyPlus simple model.

Layered glazing (EnergyPlus ``WindowMaterial:Glazing`` + ``WindowMaterial:Gas``):

* Each pane's normal-incidence solar transmittance and reflectance are inverted into the air/glass
  interface reflectance, the refractive index and the internal (absorption) transmittance of the
  glass -- the procedure EnergyPlus and WINDOW use for uncoated glass -- so that Fresnel's equations
  (both polarisations) and Bouguer's law give the pane's properties at any angle of incidence
  (coated glass: the EnergyPlus clear/bronze reference curves).
* The panes are combined by the net-radiation (multiple reflection) method into the system
  transmittance, reflectance and the absorptance of every pane.
* The centre-of-glass U-value comes from the ISO 15099 steady-state heat balance: gas properties
  as linear functions of temperature (ISO 15099 Annex B, Table B.1, the defaults of EnergyPlus),
  Nusselt number of vertical cavities (ISO 15099 §5.3.3.3, Wright's correlation), grey-body
  radiation between panes, and the boundary conditions of NFRC 100 (winter: -18 C outside with
  a 26 W/(m2 K) convective coefficient, 21 C inside with the ISO 15099 §8.3.2.2 natural convection
  coefficient for a 1 m high window, radiation to surroundings at air temperature) -- the
  conditions EnergyPlus uses for the U-factor it reports. The EN 673 calculation (fixed
  h_e = 23, h_i = 3.6 + 4.4 eps/0.837 W/(m2 K), gas properties at 283 K with 15 K across the
  glazing) is available too.
* SHGC(angle) = tau(angle) + sum_i N_i alpha_i(angle), the inward-flowing fraction N_i of the solar
  energy absorbed in pane i coming from the thermal network solved at the NFRC summer conditions
  (32 C outside, h_c,out = 15 W/(m2 K), 24 C inside, 783 W/m2 at normal incidence).

Simple glazing (EnergyPlus ``WindowMaterial:SimpleGlazingSystem``): :func:`simple_glazing_system`
converts a U-factor and SHGC into an equivalent single layer (thickness, conductivity, normal solar
transmittance, reflectance, absorptance) following the EnergyPlus Engineering Reference, "Simple
Window Model" (Arasteh, Kohler, Griffith, LBNL-2804E, 2009), with the EnergyPlus angular
dependence (ten curves A-J selected by U-factor and SHGC, :func:`simple_glazing_angular_factors`).

References
----------
ISO 15099:2003, Thermal performance of windows, doors and shading devices -- Detailed calculations:
    §5.3 (gap heat transfer), §6 (optical properties, multiple reflections), §8.3 (boundary
    conditions), Annex B (gas properties).
EN 673:2011 / ISO 10292, Glass in building -- Determination of thermal transmittance (U value).
NFRC 100-2010, Procedure for determining fenestration product U-factors (environmental conditions).
EnergyPlus Engineering Reference, "Window Calculation Module": "Optical properties of glazing"
    (uncoated glass angular dependence), "Simple Window Model".
ASHRAE Standard 140-2020, Case 600 window: n = 1.526, extinction 0.0196/mm, U = 3.0 W/(m2 K)
    with h_out = 21.0 and h_in = 8.29 W/(m2 K), SHGC 0.789, tau 0.747 at normal incidence.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from thermocal.errors import ThermocalInputError

__all__ = [
    "STEFAN_BOLTZMANN",
    "Gas",
    "GASES",
    "gas",
    "GlassPane",
    "GasGap",
    "BoundaryConditions",
    "NFRC_WINTER",
    "NFRC_SUMMER",
    "pane_optical_constants",
    "pane_angular_properties",
    "is_uncoated",
    "simple_glazing_angular_factors",
    "multilayer_optics",
    "gap_nusselt_vertical",
    "indoor_convection_coefficient",
    "solve_glazing_heat_balance",
    "LayeredGlazing",
    "en673_u_value",
    "SimpleGlazing",
    "simple_glazing_system",
    "hemispherical_average",
]

STEFAN_BOLTZMANN = 5.670374419e-8  # W/(m2 K4)
GRAVITY = 9.81  # m/s2, ISO 15099
UNIVERSAL_GAS_CONSTANT = 8314.462618  # J/(kmol K)
STANDARD_PRESSURE = 101325.0  # Pa
KELVIN = 273.15


# ------------------------------------------------------------------------------------------------
# Gas properties
# ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Gas:
    """A fill gas with ISO 15099 Annex B property polynomials ``a + b T + c T^2`` (T in K).

    Attributes
    ----------
    name : str
    conductivity : tuple of 3 floats [W/(m K)]
    viscosity : tuple of 3 floats [Pa s]
    specific_heat : tuple of 3 floats [J/(kg K)]
    molar_mass : float [kg/kmol]
    """

    name: str
    conductivity: tuple[float, float, float]
    viscosity: tuple[float, float, float]
    specific_heat: tuple[float, float, float]
    molar_mass: float

    def properties(self, temperature: float, pressure: float = STANDARD_PRESSURE):
        """Conductivity [W/(m K)], viscosity [Pa s], specific heat [J/(kg K)], density [kg/m3].

        Parameters
        ----------
        temperature : float [K]
        pressure : float [Pa]
        """
        t = temperature

        def poly(c):
            return c[0] + c[1] * t + c[2] * t * t

        density = pressure * self.molar_mass / (UNIVERSAL_GAS_CONSTANT * t)
        return poly(self.conductivity), poly(self.viscosity), poly(self.specific_heat), density


#: ISO 15099 Table B.1 coefficients (also the EnergyPlus ``WindowMaterial:Gas`` defaults).
GASES: dict[str, Gas] = {
    "air": Gas(
        "air",
        (2.873e-3, 7.760e-5, 0.0),
        (3.723e-6, 4.940e-8, 0.0),
        (1002.737, 1.2324e-2, 0.0),
        28.97,
    ),
    "argon": Gas(
        "argon", (2.285e-3, 5.149e-5, 0.0), (3.379e-6, 6.451e-8, 0.0), (521.929, 0.0, 0.0), 39.948
    ),
    "krypton": Gas(
        "krypton", (9.443e-4, 2.826e-5, 0.0), (2.213e-6, 7.777e-8, 0.0), (248.091, 0.0, 0.0), 83.80
    ),
    "xenon": Gas(
        "xenon", (4.538e-4, 1.723e-5, 0.0), (1.069e-6, 7.414e-8, 0.0), (158.340, 0.0, 0.0), 131.30
    ),
}


def gas(name: str) -> Gas:
    """The :class:`Gas` named ``name`` (air, argon, krypton, xenon; case-insensitive)."""
    key = name.strip().lower()
    if key not in GASES:
        raise ThermocalInputError(
            f"unknown gas '{name}'; use one of {sorted(GASES)} or give a custom Gas(...)."
        )
    return GASES[key]


# ------------------------------------------------------------------------------------------------
# Layers
# ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class GlassPane:
    """One glazing layer (EnergyPlus ``WindowMaterial:Glazing``, spectral-average data).

    Attributes
    ----------
    thickness : float [m]
    solar_transmittance : float [-]
        At normal incidence.
    front_solar_reflectance, back_solar_reflectance : float [-]
        At normal incidence; front faces outdoors.
    front_emissivity, back_emissivity : float [-]
        Hemispherical infrared emissivities.
    conductivity : float [W/(m K)]
    infrared_transmittance : float [-]
        Must be 0 (opaque to long-wave radiation, true for glass).
    name : str
    simple_glazing : tuple (U-factor, SHGC) or None
        Set for the equivalent layer of an EnergyPlus simple glazing system: its angular
        dependence then follows the EnergyPlus simple-glazing curves
        (:func:`simple_glazing_angular_factors`) instead of Fresnel's equations.
    """

    thickness: float
    solar_transmittance: float
    front_solar_reflectance: float
    back_solar_reflectance: float
    front_emissivity: float = 0.84
    back_emissivity: float = 0.84
    conductivity: float = 1.0
    infrared_transmittance: float = 0.0
    name: str = "glass"
    simple_glazing: tuple[float, float] | None = None

    def __post_init__(self):
        label = f"glazing layer '{self.name}'"
        if not self.thickness > 0:
            raise ThermocalInputError(f"{label}: thickness must be > 0 m, got {self.thickness}.")
        if not self.conductivity > 0:
            raise ThermocalInputError(
                f"{label}: conductivity must be > 0, got {self.conductivity}."
            )
        for attr in ("solar_transmittance", "front_solar_reflectance", "back_solar_reflectance"):
            value = getattr(self, attr)
            if not 0.0 <= value <= 1.0:
                raise ThermocalInputError(f"{label}: {attr} = {value} is outside [0, 1].")
        for refl in (self.front_solar_reflectance, self.back_solar_reflectance):
            if self.solar_transmittance + refl > 1.0 + 1e-12:
                raise ThermocalInputError(
                    f"{label}: solar transmittance + reflectance = "
                    f"{self.solar_transmittance + refl:.4f} > 1; check the optical data."
                )
        for attr in ("front_emissivity", "back_emissivity"):
            value = getattr(self, attr)
            if not 0.0 < value <= 1.0:
                raise ThermocalInputError(f"{label}: {attr} = {value} is outside (0, 1].")
        if self.infrared_transmittance > 0.0:
            raise ThermocalInputError(
                f"{label}: infrared transmittance {self.infrared_transmittance} > 0 is not "
                "supported (glass is opaque in the long-wave range); set it to 0."
            )


@dataclass(frozen=True)
class GasGap:
    """A gas-filled cavity between two panes (EnergyPlus ``WindowMaterial:Gas``).

    Attributes
    ----------
    thickness : float [m]
    fill : Gas
    name : str
    """

    thickness: float
    fill: Gas = GASES["air"]
    name: str = "gap"

    def __post_init__(self):
        if not self.thickness > 0:
            raise ThermocalInputError(
                f"gas layer '{self.name}': thickness must be > 0 m, got {self.thickness}."
            )


# ------------------------------------------------------------------------------------------------
# Optics
# ------------------------------------------------------------------------------------------------


def pane_optical_constants(solar_transmittance: float, solar_reflectance: float):
    """Interface reflectance, refractive index and internal transmittance of an uncoated pane.

    Inverts the slab equations ``tau = (1-r)^2 T / (1 - r^2 T^2)``, ``rho = r + r T tau`` for the
    air/glass interface reflectance ``r`` and the internal transmittance ``T = exp(-K d)``.

    Parameters
    ----------
    solar_transmittance : float [-]
        At normal incidence.
    solar_reflectance : float [-]
        At normal incidence.

    Returns
    -------
    interface_reflectance : float [-]
    refractive_index : float [-]
        ``(1 + sqrt(r)) / (1 - sqrt(r))``.
    internal_transmittance : float [-]
        At normal incidence (in (0, 1]).

    References
    ----------
    EnergyPlus Engineering Reference, Window Calculation Module, "Glass optical properties at
    non-normal incidence (uncoated glass)"; ISO 15099 §6.
    """
    tau = float(solar_transmittance)
    rho = float(solar_reflectance)
    if tau <= 0.0:
        return rho, 1.0, 0.0
    beta = tau * tau - rho * rho + 2.0 * rho + 1.0
    disc = max(beta * beta - 4.0 * (2.0 - rho) * rho, 0.0)
    r = (beta - math.sqrt(disc)) / (2.0 * (2.0 - rho))
    if r <= 0.0:
        return 0.0, 1.0, tau
    internal = min((rho - r) / (r * tau), 1.0)
    internal = max(internal, 1e-12)
    sqrt_r = math.sqrt(r)
    return r, (1.0 + sqrt_r) / (1.0 - sqrt_r), internal


def _uncoated_slab(cos_incidence: np.ndarray, n: float, internal0: float):
    """Fresnel + Bouguer slab properties at the given cosines (polarisation-averaged)."""
    c = np.clip(np.asarray(cos_incidence, dtype=float), 0.0, 1.0)
    sin2 = 1.0 - c * c
    cos_t = np.sqrt(np.maximum(1.0 - sin2 / (n * n), 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        r_s = ((c - n * cos_t) / (c + n * cos_t)) ** 2
        r_p = ((n * c - cos_t) / (n * c + cos_t)) ** 2
        internal = np.where(cos_t > 0, internal0 ** (1.0 / np.maximum(cos_t, 1e-12)), 0.0)
    tau = np.zeros_like(c)
    rho = np.zeros_like(c)
    for r in (r_s, r_p):
        r = np.nan_to_num(r, nan=1.0)
        denom = 1.0 - r * r * internal * internal
        t = np.where(denom > 0, (1.0 - r) ** 2 * internal / np.where(denom > 0, denom, 1.0), 0.0)
        tau += 0.5 * t
        rho += 0.5 * (r + r * internal * t)
    tau = np.where(c <= 0.0, 0.0, tau)
    rho = np.where(c <= 0.0, 1.0, rho)
    return tau, rho


def _interface_reflectance(tau: float, rho: float) -> float:
    """Air/glass interface reflectance of a slab from its normal-incidence tau and rho."""
    beta = tau * tau - rho * rho + 2.0 * rho + 1.0
    disc = max(beta * beta - 4.0 * (2.0 - rho) * rho, 0.0)
    return (beta - math.sqrt(disc)) / (2.0 * (2.0 - rho))


def is_uncoated(pane: GlassPane) -> bool:
    """EnergyPlus test for uncoated glass: front/back interface reflectances within 0.1 %.

    ``|r_f - r_b| / (r_f + r_b) < 0.001`` with the interface reflectances obtained from the front
    and back normal-incidence data (EnergyPlus WindowManager, TransAndReflAtPhi).
    """
    tau = pane.solar_transmittance
    r_f = _interface_reflectance(tau, pane.front_solar_reflectance)
    r_b = _interface_reflectance(tau, pane.back_solar_reflectance)
    if r_f + r_b <= 0.0:
        return True
    return abs(r_f - r_b) / (r_f + r_b) < 0.001


def _reference_glass_curves(cos_incidence: np.ndarray, clear: bool):
    """Normalised transmittance and reflectance of the EnergyPlus clear or bronze reference glass.

    Used for coated glass: ``tau = tau0 t(cos)``, ``rho = rho0 (1 - r(cos)) + r(cos)``.
    """
    c = cos_incidence
    if clear:
        t = -0.0015 + (3.355 + (-3.840 + (1.460 + 0.0288 * c) * c) * c) * c
        r = 0.999 + (-0.563 + (2.043 + (-2.532 + 1.054 * c) * c) * c) * c - t
    else:
        t = -0.002 + (2.813 + (-2.341 + (-0.05725 + 0.599 * c) * c) * c) * c
        r = 0.997 + (-1.868 + (6.513 + (-7.862 + 3.225 * c) * c) * c) * c - t
    t = np.where(c > 0.999, 1.0, np.where(c < 0.001, 0.0, t))
    r = np.where(c > 0.999, 0.0, np.where(c < 0.001, 1.0, r))
    return t, r


def pane_angular_properties(pane: GlassPane, incidence_angle):
    """Solar transmittance and front/back reflectance of one pane at an angle of incidence.

    Parameters
    ----------
    pane : GlassPane
    incidence_angle : float or array-like [deg]
        0 = normal incidence, 90 = grazing.

    Returns
    -------
    tau, rho_front, rho_back : numpy.ndarray [-]

    Notes
    -----
    The three cases of EnergyPlus (Engineering Reference, "Glass optical properties at
    non-normal incidence"; WindowManager ``TransAndReflAtPhi``):

    * uncoated glass (:func:`is_uncoated`): Fresnel's equations for both polarisations with the
      refractive index and absorption of :func:`pane_optical_constants` (exact at normal
      incidence);
    * coated glass: the normalised curves of a clear (``tau0 > 0.645``) or bronze reference glass,
      ``tau = tau0 t(cos)``, ``rho = rho0 (1 - r(cos)) + r(cos)``;
    * the equivalent layer of a simple glazing system: :func:`simple_glazing_angular_factors`.
    """
    angle = np.atleast_1d(np.asarray(incidence_angle, dtype=float))
    cos_i = np.cos(np.radians(np.clip(angle, 0.0, 90.0)))
    cos_i = np.where(angle >= 90.0, 0.0, cos_i)
    tau0 = pane.solar_transmittance
    rf0, rb0 = pane.front_solar_reflectance, pane.back_solar_reflectance
    if pane.simple_glazing is not None:
        t, r = simple_glazing_angular_factors(*pane.simple_glazing, cos_i)
        tau = np.clip(tau0 * t, 0.0, 1.0)
        rho = np.clip(rf0 * (1.0 - r) + r, 0.0, np.maximum(0.9999 - tau, 0.0))
        return tau, rho, rho.copy()
    if tau0 <= 0.0:  # opaque layer: reflectances kept, nothing transmitted
        return np.zeros_like(cos_i), np.full_like(cos_i, rf0), np.full_like(cos_i, rb0)
    if not is_uncoated(pane):
        t, r = _reference_glass_curves(cos_i, clear=tau0 > 0.645)
        return tau0 * t, rf0 * (1.0 - r) + r, rb0 * (1.0 - r) + r
    _, n, internal0 = pane_optical_constants(tau0, 0.5 * (rf0 + rb0))
    t, r = _uncoated_slab(cos_i, n, internal0)
    t0, r0 = _uncoated_slab(np.array([1.0]), n, internal0)
    # t0 = tau0 and r0 = rho0 to round-off: rescale so normal incidence is reproduced exactly
    tau = tau0 * t / t0[0]
    rho_f = rf0 + (1.0 - rf0) * (r - r0[0]) / (1.0 - r0[0])
    rho_b = rb0 + (1.0 - rb0) * (r - r0[0]) / (1.0 - r0[0])
    return tau, rho_f, rho_b


# EnergyPlus simple glazing angular curves A..J: transmittance ratio T(c) = sum a_k c^k (k = 1..4)
# and reflectance factor R(c) = b0 + b1 c + ... + b4 c^4 - T(c), c = cos(incidence)
# (EnergyPlus WindowManager TransAndReflAtPhi; Arasteh, Kohler, Griffith, LBNL-2804E, 2009).
_SIMPLE_T = {
    "A": (3.36, -3.85, 1.49, 0.01),
    "B": (2.83, -2.42, 0.04, 0.55),
    "C": (2.45, -1.58, -0.64, 0.77),
    "D": (2.85, -2.58, 0.40, 0.35),
    "E": (1.51, 2.49, -5.87, 2.88),
    "F": (1.21, 3.14, -6.37, 3.03),
    "G": (1.09, 3.54, -6.84, 3.23),
    "H": (0.98, 3.83, -7.13, 3.33),
    "I": (0.79, 3.93, -6.86, 3.15),
    "J": (0.08, 6.02, -8.84, 3.74),
}
_SIMPLE_R = {
    "A": (1.00, -0.70, 2.57, -3.20, 1.33),
    "B": (1.00, -1.87, 6.50, -7.86, 3.23),
    "C": (1.00, -2.52, 8.40, -9.86, 3.99),
    "D": (1.00, -1.85, 6.40, -7.64, 3.11),
    "E": (1.00, -1.57, 5.60, -6.82, 2.80),
    "F": (1.00, -3.15, 10.98, -13.14, 5.32),
    "G": (1.00, -3.25, 11.32, -13.54, 5.49),
    "H": (1.00, -3.39, 11.70, -13.94, 5.64),
    "I": (1.00, -4.06, 13.55, -15.74, 6.27),
    "J": (1.00, -4.35, 14.27, -16.32, 6.39),
}


def _simple_curve(name: str, c: np.ndarray):
    """(T, R) of a named curve or of the averaged curves FGHI, FH and BDCD."""
    if len(name) > 1:  # averaged curves; "BDCD" counts D twice, as EnergyPlus does
        parts = list(name)
        values = [_simple_curve(p, c) for p in parts]
        return (
            sum(v[0] for v in values) / len(parts),
            sum(v[1] for v in values) / len(parts),
        )
    a = _SIMPLE_T[name]
    t = a[0] * c + a[1] * c**2 + a[2] * c**3 + a[3] * c**4
    b = _SIMPLE_R[name]
    r = b[0] + b[1] * c + b[2] * c**2 + b[3] * c**3 + b[4] * c**4 - t
    return t, r


def _lerp(x, x0, x1, f0, f1):
    return f0 + (x - x0) / (x1 - x0) * (f1 - f0)


def _bilerp(x, y, x1, x2, y1, y2, f11, f12, f21, f22):
    """EnergyPlus InterpolateBetweenFourValues: f_ij at (x_i, y_j)."""
    area = (x2 - x1) * (y2 - y1)
    return (
        f11 * (x2 - x) * (y2 - y)
        + f21 * (x - x1) * (y2 - y)
        + f12 * (x2 - x) * (y - y1)
        + f22 * (x - x1) * (y - y1)
    ) / area


def simple_glazing_angular_factors(u_factor: float, shgc: float, cos_incidence):
    """Angular transmittance ratio and reflectance factor of the EnergyPlus simple glazing model.

    The (U, SHGC) plane is divided into 28 cells; each uses one of ten curves (A-J), an average of
    curves, or a linear/bilinear interpolation between them. The layer properties at incidence
    angle theta are ``tau = tau0 T(cos theta)`` and ``rho = rho0 (1 - R) + R``.

    Parameters
    ----------
    u_factor : float [W/(m2 K)]
    shgc : float [-]
    cos_incidence : array-like [-]

    Returns
    -------
    T, R : numpy.ndarray [-]
        ``T = 1``, ``R = 0`` at normal incidence.

    References
    ----------
    EnergyPlus Engineering Reference, "Simple Window Model" (angular properties);
    EnergyPlus source, WindowManager.cc ``TransAndReflAtPhi`` (curve coefficients, cells).
    """
    c = np.asarray(cos_incidence, dtype=float)
    u, g = float(u_factor), float(shgc)

    def curve(name):
        return _simple_curve(name, c)

    def two(x, x0, x1, a, b):
        (ta, ra), (tb, rb) = curve(a), curve(b)
        return _lerp(x, x0, x1, ta, tb), _lerp(x, x0, x1, ra, rb)

    def four(y1, y2, u1, u2, f11, f12, f21, f22):
        fs = [curve(n) for n in (f11, f12, f21, f22)]
        return tuple(_bilerp(u, g, u1, u2, y1, y2, *(f[k] for f in fs)) for k in (0, 1))

    if u < 1.4195:
        if g > 0.45:
            t, r = curve("E")
        elif g >= 0.35:
            t, r = two(g, 0.35, 0.45, "J", "E")
        else:
            t, r = curve("J")
    elif u <= 1.7034:
        u1, u2 = 1.4195, 1.7034
        if g > 0.55:
            t, r = curve("E")
        elif g > 0.5:
            t, r = four(0.50, 0.55, u1, u2, "E", "E", "FGHI", "E")
        elif g > 0.45:
            t, r = two(u, u1, u2, "E", "FGHI")
        elif g > 0.35:
            t, r = four(0.35, 0.45, u1, u2, "J", "E", "FGHI", "FGHI")
        elif g > 0.3:
            t, r = two(u, u1, u2, "J", "FGHI")
        elif g > 0.25:
            t, r = four(0.25, 0.30, u1, u2, "J", "J", "FH", "FGHI")
        else:
            t, r = two(u, u1, u2, "J", "FH")
    elif u < 3.4068:
        if g > 0.55:
            t, r = curve("E")
        elif g >= 0.5:
            t, r = two(g, 0.5, 0.55, "FGHI", "E")
        elif g > 0.3:
            t, r = curve("FGHI")
        elif g >= 0.25:
            t, r = two(g, 0.25, 0.30, "FH", "FGHI")
        else:
            t, r = curve("FH")
    elif u <= 4.5424:
        u1, u2 = 3.4068, 4.5424
        if g > 0.65:
            t, r = two(u, u1, u2, "E", "A")
        elif g > 0.6:
            t, r = four(0.60, 0.65, u1, u2, "E", "E", "BDCD", "A")
        elif g > 0.55:
            t, r = two(u, u1, u2, "E", "BDCD")
        elif g > 0.5:
            t, r = four(0.50, 0.55, u1, u2, "FGHI", "E", "BDCD", "BDCD")
        elif g > 0.45:
            t, r = two(u, u1, u2, "FGHI", "BDCD")
        elif g > 0.3:
            t, r = four(0.30, 0.45, u1, u2, "FGHI", "FGHI", "D", "BDCD")
        elif g > 0.25:
            t, r = four(0.25, 0.30, u1, u2, "FH", "FGHI", "D", "D")
        else:
            t, r = two(u, u1, u2, "FH", "D")
    else:
        if g > 0.65:
            t, r = curve("A")
        elif g >= 0.6:
            t, r = two(g, 0.6, 0.65, "BDCD", "A")
        elif g > 0.45:
            t, r = curve("BDCD")
        elif g >= 0.3:
            t, r = two(g, 0.3, 0.45, "D", "BDCD")
        else:
            t, r = curve("D")
    t = np.where(c >= 1.0, 1.0, t)
    r = np.where(c >= 1.0, 0.0, r)
    return t, r


def multilayer_optics(tau, rho_front, rho_back):
    """Net-radiation combination of layers: system transmittance, reflectance, layer absorptances.

    Parameters
    ----------
    tau, rho_front, rho_back : sequence of floats [-]
        Properties of each layer, outermost first, for one angle of incidence (radiation arriving
        from outdoors on the front side).

    Returns
    -------
    transmittance : float [-]
    reflectance : float [-]
        Front (outdoor side) reflectance of the system.
    absorptance : numpy.ndarray [-]
        Fraction of the incident radiation absorbed in each layer (front + back incidence from the
        inter-reflections).

    References
    ----------
    ISO 15099 §6.1 (multiple reflections between parallel layers); Finlayson et al., WINDOW 4.0
    documentation, LBL-33943 (1993), net radiation method.
    """
    tau = np.asarray(tau, dtype=float)
    rf = np.asarray(rho_front, dtype=float)
    rb = np.asarray(rho_back, dtype=float)
    n = tau.size
    if tau[0] <= 0.0 and rf[0] >= 1.0:  # grazing incidence: everything reflected by layer 1
        return 0.0, 1.0, np.zeros(n)
    # unknowns: f_1..f_n (inward flux after layer i), b_0..b_{n-1} (outward flux before layer i+1)
    # f_0 = 1 (incident), b_n = 0.
    size = 2 * n
    a = np.zeros((size, size))
    rhs = np.zeros(size)

    def fi(i):  # index of f_i, i = 1..n
        return i - 1

    def bi(i):  # index of b_i, i = 0..n-1
        return n + i

    for layer in range(1, n + 1):
        t, front, back = tau[layer - 1], rf[layer - 1], rb[layer - 1]
        # f_i = t f_{i-1} + back * b_i
        row = fi(layer)
        a[row, fi(layer)] = 1.0
        if layer > 1:
            a[row, fi(layer - 1)] -= t
        else:
            rhs[row] += t
        if layer < n:
            a[row, bi(layer)] -= back
        # b_{i-1} = front f_{i-1} + t b_i
        row = bi(layer - 1)
        a[row, bi(layer - 1)] = 1.0
        if layer > 1:
            a[row, fi(layer - 1)] -= front
        else:
            rhs[row] += front
        if layer < n:
            a[row, bi(layer)] -= t
    x = np.linalg.solve(a, rhs)
    f = np.concatenate([[1.0], x[:n]])  # f_0..f_n
    b = np.concatenate([x[n:], [0.0]])  # b_0..b_n
    alpha_f = 1.0 - tau - rf
    alpha_b = 1.0 - tau - rb
    absorbed = alpha_f * f[:-1] + alpha_b * b[1:]
    return float(f[-1]), float(b[0]), absorbed


def hemispherical_average(values_at_angle, *, n_points: int = 40) -> float:
    """Diffuse (hemispherical, isotropic) average ``2 * int_0^pi/2 v(t) sin t cos t dt``.

    Parameters
    ----------
    values_at_angle : callable
        Function of the incidence angle [deg] (array in, array out).
    n_points : int
        Gauss-Legendre points in ``cos^2`` (exact for polynomials of degree < 2 n in cos^2).
    """
    # substitute u = cos^2(t): 2 sin t cos t dt = -du, integral over u in [0, 1]
    nodes, weights = np.polynomial.legendre.leggauss(n_points)
    u = 0.5 * (nodes + 1.0)
    angles = np.degrees(np.arccos(np.sqrt(u)))
    return float(0.5 * np.sum(weights * np.asarray(values_at_angle(angles), dtype=float)))


# ------------------------------------------------------------------------------------------------
# Heat transfer
# ------------------------------------------------------------------------------------------------


def gap_nusselt_vertical(rayleigh: float, aspect_ratio: float) -> float:
    """Nusselt number of a vertical gas cavity (ISO 15099 §5.3.3.3, tilt 90 deg).

    Parameters
    ----------
    rayleigh : float [-]
        Rayleigh number based on the gap width.
    aspect_ratio : float [-]
        Cavity height / gap width.
    """
    ra = max(rayleigh, 0.0)
    if ra > 5.0e4:
        nu1 = 0.0673838 * ra ** (1.0 / 3.0)
    elif ra > 1.0e4:
        nu1 = 0.028154 * ra**0.4134
    else:
        nu1 = 1.0 + 1.7596678e-10 * ra**2.2984755
    nu2 = 0.242 * (ra / aspect_ratio) ** 0.272 if ra > 0 else 0.0
    return max(nu1, nu2, 1.0)


def indoor_convection_coefficient(
    temp_surface: float, temp_air: float, *, height: float = 1.0, tilt: float = 90.0
) -> float:
    """Natural-convection coefficient on the room side of a window [W/(m2 K)].

    ISO 15099 §8.3.2.2: ``h = Nu k / H`` with ``Ra = rho^2 H^3 g c_p |dT| / (T_mf mu k)``,
    film temperature ``T_mf = T_air + (T_surface - T_air)/4``; for the laminar range
    ``Nu = 0.56 (Ra sin(tilt))^(1/4)``, turbulent above ``Ra_cv``.

    Parameters
    ----------
    temp_surface, temp_air : float [K]
    height : float [m]
        Window height (NFRC/EnergyPlus nominal: 1 m).
    tilt : float [deg]
        90 = vertical (only near-vertical windows are handled by this correlation).
    """
    dt = abs(temp_surface - temp_air)
    if dt < 1e-9:
        return 0.0
    t_film = temp_air + 0.25 * (temp_surface - temp_air)
    k, mu, cp, rho = GASES["air"].properties(t_film)
    rayleigh = rho * rho * height**3 * GRAVITY * cp * dt / (t_film * mu * k)
    gamma = math.radians(tilt)
    sin_g = max(math.sin(gamma), 1e-6)
    ra_cv = 2.5e5 * (math.exp(0.72 * tilt) / sin_g) ** 0.2
    if rayleigh <= ra_cv:
        nusselt = 0.56 * (rayleigh * sin_g) ** 0.25
    else:
        nusselt = 0.13 * (rayleigh ** (1 / 3) - ra_cv ** (1 / 3)) + 0.56 * (ra_cv * sin_g) ** 0.25
    return nusselt * k / height


@dataclass(frozen=True)
class BoundaryConditions:
    """Environmental conditions for the glazing heat balance.

    Attributes
    ----------
    temp_out, temp_in : float [C]
        Outdoor and indoor air temperatures; radiant surroundings at the same temperatures.
    h_conv_out : float [W/(m2 K)]
        Outdoor convective coefficient (radiation is computed separately from the emissivity).
    h_conv_in : float or None [W/(m2 K)]
        Indoor convective coefficient; None = ISO 15099 natural convection for ``height``.
    solar_irradiance : float [W/m2]
        At normal incidence (for the SHGC calculation).
    height : float [m]
        Window height for the indoor convection and the cavity aspect ratio.
    name : str
    """

    temp_out: float
    temp_in: float
    h_conv_out: float
    h_conv_in: float | None = None
    solar_irradiance: float = 0.0
    height: float = 1.0
    name: str = "custom"


#: NFRC 100 winter conditions (EnergyPlus nominal U-factor).
NFRC_WINTER = BoundaryConditions(-18.0, 21.0, 26.0, None, 0.0, 1.0, "NFRC winter")
#: NFRC 200 summer conditions (EnergyPlus nominal SHGC).
NFRC_SUMMER = BoundaryConditions(32.0, 24.0, 15.0, None, 783.0, 1.0, "NFRC summer")
#: Hemispherical infrared emissivity of uncoated soda-lime glass [-] (EN 673).
UNCOATED_GLASS_EMISSIVITY = 0.837
#: A gap face is coated when its emissivity is below this [-] (uncoated glass 0.84; hard
#: low-e coatings about 0.15-0.2, soft ones 0.02-0.1).
COATED_BELOW = 0.5
#: Infrared emissivities [-] of the coated gap faces of
#: :meth:`LayeredGlazing.coated_conductance_family`: uncoated glass down to the best
#: soft low-e coatings (about 0.02; hard coatings 0.15-0.2, ISO 10292 / EN 673 practice).
#: Eight points keep the interpolated tables within 0.3 % of the coated glazing's own.
COATING_EMISSIVITIES = (UNCOATED_GLASS_EMISSIVITY, 0.6, 0.4, 0.25, 0.15, 0.09, 0.05, 0.02)


@dataclass(frozen=True)
class HeatBalanceResult:
    """Converged glazing heat balance.

    Attributes
    ----------
    temperatures : numpy.ndarray [C]
        Per pane: (front surface, centre, back surface), shape (n_panes, 3).
    heat_flux_in : float [W/m2]
        Heat flux into the room (positive inward).
    resistances : numpy.ndarray [m2 K/W]
        Series resistances of the linearised network: outdoor film, each pane half, each gap
        (convection and radiation in parallel), indoor film (length 2 n + 2 (n-1) ... see code).
    inward_fractions : numpy.ndarray [-]
        Share of the heat absorbed at each pane centre that flows into the room.
    h_in : float [W/(m2 K)]
        Indoor combined (convective + radiative) coefficient.
    h_out : float [W/(m2 K)]
        Outdoor combined coefficient.
    gap_conductances : numpy.ndarray [W/(m2 K)]
        Combined conductance of every gap.
    """

    temperatures: np.ndarray
    heat_flux_in: float
    resistances: np.ndarray
    inward_fractions: np.ndarray
    h_in: float
    h_out: float
    gap_conductances: np.ndarray


def solve_glazing_heat_balance(
    panes: Sequence[GlassPane],
    gaps: Sequence[GasGap],
    conditions: BoundaryConditions,
    absorbed_solar: Sequence[float] | None = None,
    *,
    tolerance: float = 1e-9,
    max_iterations: int = 200,
) -> HeatBalanceResult:
    """Steady-state centre-of-glass heat balance (ISO 15099 §8, one-dimensional).

    Each pane has three nodes (outer face, centre, inner face) joined by conductances ``2 k / d``;
    absorbed solar heat is released at the centre. Gaps transfer heat by convection
    (``Nu k / s``, :func:`gap_nusselt_vertical`, gas properties at the mean gap temperature) and
    grey-body radiation ``sigma (T1^2 + T2^2)(T1 + T2) / (1/e1 + 1/e2 - 1)``; the outdoor and
    indoor faces exchange radiation with surroundings at the air temperatures. Non-linear
    coefficients are updated by successive substitution.

    Parameters
    ----------
    panes : sequence of GlassPane
        Outermost first.
    gaps : sequence of GasGap
        ``len(panes) - 1`` gaps, outermost first.
    conditions : BoundaryConditions
    absorbed_solar : sequence of float or None [W/m2]
        Heat absorbed in each pane; None = no sun.

    Returns
    -------
    HeatBalanceResult
    """
    n = len(panes)
    if n == 0:
        raise ThermocalInputError("a glazing system needs at least one glass layer.")
    if len(gaps) != n - 1:
        raise ThermocalInputError(
            f"a glazing system with {n} glass layers needs {n - 1} gas layers, got {len(gaps)}."
        )
    source = np.zeros(n) if absorbed_solar is None else np.asarray(absorbed_solar, dtype=float)
    t_out = conditions.temp_out + KELVIN
    t_in = conditions.temp_in + KELVIN
    n_nodes = 3 * n
    temps = np.linspace(t_out, t_in, n_nodes + 2)[1:-1]
    sigma = STEFAN_BOLTZMANN
    result_h = None
    for _ in range(max_iterations):
        # series conductances between consecutive nodes: out-air, nodes..., in-air
        conductances = []
        t_face = temps[0]
        e_front = panes[0].front_emissivity
        h_out = conditions.h_conv_out + e_front * sigma * (t_face**2 + t_out**2) * (t_face + t_out)
        conductances.append(h_out)
        gap_h = []
        for i, pane in enumerate(panes):
            k_half = 2.0 * pane.conductivity / pane.thickness
            conductances += [k_half, k_half]
            if i < n - 1:
                t1, t2 = temps[3 * i + 2], temps[3 * i + 3]
                gap = gaps[i]
                t_mean = 0.5 * (t1 + t2)
                k, mu, cp, rho = gap.fill.properties(t_mean)
                dt = abs(t1 - t2)
                rayleigh = rho * rho * gap.thickness**3 * GRAVITY * cp * dt / (t_mean * mu * k)
                nusselt = gap_nusselt_vertical(rayleigh, conditions.height / gap.thickness)
                h_conv = nusselt * k / gap.thickness
                e1, e2 = pane.back_emissivity, panes[i + 1].front_emissivity
                h_rad = sigma * (t1**2 + t2**2) * (t1 + t2) / (1.0 / e1 + 1.0 / e2 - 1.0)
                gap_h.append(h_conv + h_rad)
                conductances.append(h_conv + h_rad)
        t_face = temps[-1]
        h_conv_in = (
            conditions.h_conv_in
            if conditions.h_conv_in is not None
            else indoor_convection_coefficient(t_face, t_in, height=conditions.height)
        )
        e_back = panes[-1].back_emissivity
        h_in = h_conv_in + e_back * sigma * (t_face**2 + t_in**2) * (t_face + t_in)
        conductances.append(h_in)
        g = np.asarray(conductances)
        # assemble the chain: node j connected to j-1 by g[j] and to j+1 by g[j+1]
        a = np.zeros((n_nodes, n_nodes))
        rhs = np.zeros(n_nodes)
        for j in range(n_nodes):
            a[j, j] = g[j] + g[j + 1]
            if j > 0:
                a[j, j - 1] = -g[j]
            else:
                rhs[j] += g[0] * t_out
            if j < n_nodes - 1:
                a[j, j + 1] = -g[j + 1]
            else:
                rhs[j] += g[-1] * t_in
        rhs[1::3] += source
        new = np.linalg.solve(a, rhs)
        change = float(np.max(np.abs(new - temps)))
        temps = new
        result_h = (g, h_in, h_out, np.asarray(gap_h))
        if change < tolerance:
            break
    g, h_in, h_out, gap_h = result_h
    resistances = 1.0 / g
    total = resistances.sum()
    cumulative = np.cumsum(resistances)
    # resistance from the outdoor air to each pane centre = cumulative up to that node
    centre_nodes = np.arange(n) * 3 + 1
    inward = cumulative[centre_nodes] / total
    heat_flux_in = float(g[-1] * (temps[-1] - t_in))
    return HeatBalanceResult(
        temperatures=(temps - KELVIN).reshape(n, 3),
        heat_flux_in=heat_flux_in,
        resistances=resistances,
        inward_fractions=inward,
        h_in=float(h_in),
        h_out=float(h_out),
        gap_conductances=gap_h,
    )


def en673_u_value(panes: Sequence[GlassPane], gaps: Sequence[GasGap]) -> float:
    """Centre-of-glass U-value by EN 673 / ISO 10292 [W/(m2 K)].

    ``1/U = 1/h_e + sum d_j/k_j + sum 1/h_s + 1/h_i`` with ``h_e = 23``,
    ``h_i = 3.6 + 4.4 eps/0.837`` W/(m2 K), gap conductance ``h_s = h_r + h_g``,
    ``h_r = 4 sigma T_m^3 / (1/e1 + 1/e2 - 1)``, ``h_g = Nu k / s``,
    ``Nu = max(1, 0.035 (Gr Pr)^0.38)`` for vertical glazing,
    properties at ``T_m = 283 K`` with 15 K shared equally by the gaps.

    Parameters
    ----------
    panes : sequence of GlassPane
    gaps : sequence of GasGap

    References
    ----------
    EN 673:2011 §5 and Table 1 constants (vertical glazing).
    """
    t_mean = 283.0
    dt_per_gap = 15.0 / max(len(gaps), 1)
    resistance = 1.0 / 23.0 + sum(p.thickness / p.conductivity for p in panes)
    resistance += 1.0 / (3.6 + 4.4 * panes[-1].back_emissivity / 0.837)
    for i, gap_layer in enumerate(gaps):
        k, mu, cp, rho = gap_layer.fill.properties(t_mean)
        s = gap_layer.thickness
        grashof = GRAVITY * s**3 * dt_per_gap * rho * rho / (t_mean * mu * mu)
        prandtl = mu * cp / k
        nusselt = max(1.0, 0.035 * (grashof * prandtl) ** 0.38)
        e1, e2 = panes[i].back_emissivity, panes[i + 1].front_emissivity
        h_r = 4.0 * STEFAN_BOLTZMANN * t_mean**3 / (1.0 / e1 + 1.0 / e2 - 1.0)
        resistance += 1.0 / (h_r + nusselt * k / s)
    return 1.0 / resistance


class LayeredGlazing:
    """A glazing system of glass panes and gas gaps (outermost first).

    Parameters
    ----------
    panes : sequence of GlassPane
    gaps : sequence of GasGap
        One fewer than the panes.
    name : str

    Examples
    --------
    >>> clear = GlassPane(0.003175, 0.86156, 0.07846, 0.07846, 0.84, 0.84, 1.06)
    >>> glazing = LayeredGlazing([clear, clear], [GasGap(0.013, gas("air"))])
    >>> round(glazing.transmittance(0.0), 3)
    0.747
    """

    def __init__(self, panes: Sequence[GlassPane], gaps: Sequence[GasGap], name: str = "glazing"):
        self.panes = tuple(panes)
        self.gaps = tuple(gaps)
        self.name = name
        if not self.panes:
            raise ThermocalInputError(f"glazing '{name}': no glass layer.")
        if len(self.gaps) != len(self.panes) - 1:
            raise ThermocalInputError(
                f"glazing '{name}': {len(self.panes)} glass layers need {len(self.panes) - 1} "
                f"gas layers between them, got {len(self.gaps)}; layers must alternate "
                "glass/gas starting and ending with glass."
            )

    # -- optics ---------------------------------------------------------------------------------
    def optics(self, incidence_angle):
        """System transmittance, front reflectance and pane absorptances at the angle(s).

        Parameters
        ----------
        incidence_angle : float or array-like [deg]

        Returns
        -------
        tau : numpy.ndarray [-], shape (n_angles,)
        rho : numpy.ndarray [-], shape (n_angles,)
        absorptance : numpy.ndarray [-], shape (n_angles, n_panes)
        """
        angles = np.atleast_1d(np.asarray(incidence_angle, dtype=float))
        props = [pane_angular_properties(p, angles) for p in self.panes]
        tau = np.empty(angles.size)
        rho = np.empty(angles.size)
        absorbed = np.empty((angles.size, len(self.panes)))
        for k in range(angles.size):
            t_k = [p[0][k] for p in props]
            rf_k = [p[1][k] for p in props]
            rb_k = [p[2][k] for p in props]
            tau[k], rho[k], absorbed[k] = multilayer_optics(t_k, rf_k, rb_k)
        return tau, rho, absorbed

    def transmittance(self, incidence_angle=0.0):
        """Direct solar transmittance [-] at the angle(s) of incidence [deg]."""
        tau = self.optics(incidence_angle)[0]
        return float(tau[0]) if np.ndim(incidence_angle) == 0 else tau

    def absorptance(self, incidence_angle=0.0):
        """Solar absorptance of every pane [-], shape (n_angles, n_panes) (or (n_panes,))."""
        a = self.optics(incidence_angle)[2]
        return a[0] if np.ndim(incidence_angle) == 0 else a

    @cached_property
    def diffuse_transmittance(self) -> float:
        """Hemispherical (isotropic diffuse) solar transmittance [-]."""
        return hemispherical_average(lambda a: self.optics(a)[0])

    @cached_property
    def diffuse_absorptance(self) -> np.ndarray:
        """Hemispherical solar absorptance of every pane [-]."""
        return np.array(
            [
                hemispherical_average(lambda a, i=i: self.optics(a)[2][:, i])
                for i in range(len(self.panes))
            ]
        )

    # -- heat transfer --------------------------------------------------------------------------
    def heat_balance(self, conditions: BoundaryConditions = NFRC_WINTER, absorbed_solar=None):
        """:func:`solve_glazing_heat_balance` for this system."""
        return solve_glazing_heat_balance(self.panes, self.gaps, conditions, absorbed_solar)

    def u_value(self, conditions: BoundaryConditions | str = NFRC_WINTER) -> float:
        """Centre-of-glass U-value incl. surface coefficients [W/(m2 K)].

        Parameters
        ----------
        conditions : BoundaryConditions or "nfrc" or "en673"
            ``"nfrc"`` (default, :data:`NFRC_WINTER`, the EnergyPlus U-factor conditions) or
            ``"en673"`` (:func:`en673_u_value`).
        """
        if isinstance(conditions, str):
            key = conditions.lower()
            if key == "en673":
                return en673_u_value(self.panes, self.gaps)
            if key != "nfrc":
                raise ThermocalInputError(f"unknown U-value conditions '{conditions}'.")
            conditions = NFRC_WINTER
        result = self.heat_balance(conditions)
        return result.heat_flux_in / (conditions.temp_out - conditions.temp_in)

    def glass_conductance_ratio(self, temperatures, *, reference=NFRC_WINTER) -> np.ndarray:
        """Glass-to-glass conductance at mean glazing temperatures over its value at ``reference``.

        The conductance between the outer face of the outermost pane and the inner face of the
        innermost pane (panes and gaps in series) rises with temperature: grey-body radiation
        across each gap goes with ``T^3`` and the gas conductivity with ``T``. It is evaluated
        with :func:`solve_glazing_heat_balance` at 10 K across the glazing (outdoor air 5 K
        below, indoor air 5 K above each mean temperature) and divided into its value in the
        ``reference`` state (the nominal U-value's), whose larger temperature difference also
        drives some gap convection (Case 600 glazing, NFRC winter: Nu = 1.05 instead of 1).

        Parameters
        ----------
        temperatures : array-like [C]
            Mean glazing temperatures.
        reference : BoundaryConditions
            Conditions of the nominal U-value (NFRC winter).

        Returns
        -------
        numpy.ndarray [-]
            1 for a single pane (no gap).

        References
        ----------
        .. [1] ISO 15099:2003, 5.3 (gap convection) and 8 (heat balance); EnergyPlus Engineering
           Reference, "Window Heat Balance Calculation" (solved at every time step).
        """
        temperatures = np.atleast_1d(np.asarray(temperatures, dtype=float))
        if not self.gaps:
            return np.ones_like(temperatures)

        def glass_resistance(t_mean):
            conditions = BoundaryConditions(
                t_mean - 5.0, t_mean + 5.0, reference.h_conv_out, reference.h_conv_in
            )
            return float(self.heat_balance(conditions).resistances[1:-1].sum())

        r_ref = float(self.heat_balance(reference).resistances[1:-1].sum())
        return np.asarray([r_ref / glass_resistance(t) for t in temperatures])

    def coated_conductance_family(
        self, temperatures, emissivities=COATING_EMISSIVITIES, *, reference=NFRC_WINTER
    ) -> tuple[np.ndarray, np.ndarray]:
        """U-values and glass conductance tables of these panes and gaps with coated gap faces,
        this glazing's own among them.

        A lower U-value of a glazing of the same build comes from a low-emissivity coating on a
        gap face (or a heavier gas): radiation across the gap, which goes with ``T^3``, then
        carries less of the heat and the glass-to-glass conductance depends less on the
        temperature. So a new U-value should bring the temperature dependence of the glazing
        that has it, not the nominal gaps' dependence scaled. This gives that dependence for a
        range of coatings, each ``e`` of ``emissivities`` on the faces :meth:`coated_faces`
        names (the glazing's own coated faces; in an uncoated glazing the inner pane's face in
        every gap, surface 3 of a double glazing, where heating climates put the coating: for
        a gap's conductance either face is the same), the other faces and the panes' optics
        kept (the SHGC is a parameter of its own). The glazing itself is one of the rows, so
        the family passes through it exactly.

        Parameters
        ----------
        temperatures : array-like [C]
            Mean glazing temperatures of the tables (:meth:`glass_conductance_ratio`).
        emissivities : sequence of float [-]
            Infrared emissivities of the coated faces, in (0, 1].
        reference : BoundaryConditions
            Conditions of the U-values (NFRC winter, as :meth:`u_value`).

        Returns
        -------
        u_values : numpy.ndarray [W/(m2 K)]
            Increasing, distinct (a coating within 0.01 W/(m2 K) of the glazing's own U-value
            is left out: its own row is the better one there).
        ratios : numpy.ndarray [-]
            Shape ``(len(u_values), len(temperatures))``: each glazing's conductance over its
            own value at ``reference``.

        Raises
        ------
        ThermocalInputError
            A single pane (no gap to coat).
        """
        if not self.gaps:
            raise ThermocalInputError(
                f"glazing '{self.name}': a single pane has no gap whose coating sets its U-value"
            )
        own_u = self.u_value(reference)
        rows = [(own_u, self.glass_conductance_ratio(temperatures, reference=reference))]
        faces = self.coated_faces()
        for e in emissivities:
            panes = list(self.panes)
            for pane, side in faces:
                panes[pane] = replace(panes[pane], **{f"{side}_emissivity": float(e)})
            coated = LayeredGlazing(panes, self.gaps, name=self.name)
            u = coated.u_value(reference)
            if abs(u - own_u) > 0.01:
                rows.append((u, coated.glass_conductance_ratio(temperatures, reference=reference)))
        rows.sort(key=lambda row: row[0])
        u_values = np.array([u for u, _ in rows])
        keep = np.concatenate([[True], np.diff(u_values) > 1e-9])
        return u_values[keep], np.array([r for _, r in rows])[keep]

    def coated_faces(self) -> list[tuple[int, str]]:
        """The gap faces :meth:`coated_conductance_family` coats: ``(pane index, "front" or
        "back")``.

        The faces already coated (emissivity below :data:`COATED_BELOW`); when none is, the
        inner pane's face in every gap (its front).
        """
        coated = []
        for j in range(1, len(self.panes)):
            if self.panes[j - 1].back_emissivity < COATED_BELOW:
                coated.append((j - 1, "back"))
            if self.panes[j].front_emissivity < COATED_BELOW:
                coated.append((j, "front"))
        return coated or [(j, "front") for j in range(1, len(self.panes))]

    @cached_property
    def inward_flowing_fractions(self) -> np.ndarray:
        """Share of the solar heat absorbed in each pane that reaches the room [-] (NFRC summer).

        Evaluated with the network linearised at the converged NFRC summer state with the
        normal-incidence absorbed solar heat.
        """
        absorbed = self.absorptance(0.0) * NFRC_SUMMER.solar_irradiance
        return self.heat_balance(NFRC_SUMMER, absorbed).inward_fractions

    def shgc(self, incidence_angle=0.0):
        """Solar heat gain coefficient [-] at the angle(s) of incidence [deg].

        ``tau(theta) + sum_i N_i alpha_i(theta)`` with the NFRC summer inward-flowing fractions.
        """
        tau, _, absorbed = self.optics(incidence_angle)
        g = tau + absorbed @ self.inward_flowing_fractions
        return float(g[0]) if np.ndim(incidence_angle) == 0 else g

    @cached_property
    def diffuse_shgc(self) -> float:
        """Hemispherical (isotropic diffuse) SHGC [-]."""
        return hemispherical_average(lambda a: self.shgc(a))

    def angular_table(self, angles=(0, 10, 20, 30, 40, 50, 60, 70, 80, 90)):
        """Transmittance, reflectance, pane absorptances and SHGC at the given angles.

        Returns
        -------
        pandas.DataFrame indexed by angle [deg].
        """
        import pandas as pd

        angles = np.asarray(angles, dtype=float)
        tau, rho, absorbed = self.optics(angles)
        frame = pd.DataFrame({"transmittance": tau, "reflectance": rho}, index=angles)
        for i in range(absorbed.shape[1]):
            frame[f"absorptance_{i + 1}"] = absorbed[:, i]
        frame["shgc"] = tau + absorbed @ self.inward_flowing_fractions
        frame.index.name = "incidence_angle"
        return frame


# ------------------------------------------------------------------------------------------------
# EnergyPlus simple glazing system
# ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SimpleGlazing:
    """Equivalent single layer of the EnergyPlus simple glazing model.

    Attributes
    ----------
    u_factor, shgc : float [W/(m2 K)], [-]
        Input values.
    thickness : float [m]
    conductivity : float [W/(m K)]
    solar_transmittance : float [-]
        Normal incidence.
    solar_reflectance : float [-]
        Front = back, normal incidence.
    solar_absorptance : float [-]
    inward_flowing_fraction : float [-]
    resistance_inside_winter, resistance_outside_winter, resistance_layer : float [m2 K/W]
    resistance_inside_summer, resistance_outside_summer : float [m2 K/W]
    visible_transmittance : float [-]
    """

    u_factor: float
    shgc: float
    thickness: float
    conductivity: float
    solar_transmittance: float
    solar_reflectance: float
    solar_absorptance: float
    inward_flowing_fraction: float
    resistance_inside_winter: float
    resistance_outside_winter: float
    resistance_layer: float
    resistance_inside_summer: float
    resistance_outside_summer: float
    visible_transmittance: float

    def as_pane(self, name: str = "simple glazing") -> GlassPane:
        """The equivalent layer as a :class:`GlassPane` (emissivities 0.84, as EnergyPlus)."""
        return GlassPane(
            self.thickness,
            self.solar_transmittance,
            self.solar_reflectance,
            self.solar_reflectance,
            0.84,
            0.84,
            self.conductivity,
            0.0,
            name,
            simple_glazing=(self.u_factor, self.shgc),
        )


def _interpolate_u(u: float, low_value: float, high_value: float) -> float:
    """Linear interpolation between the U <= 3.4 and U >= 4.5 correlations."""
    if u <= 3.4:
        return low_value
    if u >= 4.5:
        return high_value
    w = (u - 3.4) / (4.5 - 3.4)
    return low_value + w * (high_value - low_value)


def simple_glazing_system(
    u_factor: float, shgc: float, visible_transmittance: float | None = None, *, name: str = ""
) -> SimpleGlazing:
    """EnergyPlus ``WindowMaterial:SimpleGlazingSystem`` -> equivalent glazing layer.

    Steps of the EnergyPlus Engineering Reference ("Simple Window Model"):

    1. Winter film resistances ``R_i,w = 1/(0.359073 ln U + 6.949915)`` (U < 5.85) or
       ``1/(1.788041 U - 2.886625)``, ``R_o,w = 1/(0.025342 U + 29.163853)``; layer resistance
       ``R_l,w = 1/U - R_i,w - R_o,w``.
    2. Thickness ``0.002 m`` if ``1/R_l,w > 7`` else ``0.05914 - 0.00714/R_l,w``; conductivity
       ``thickness / R_l,w``.
    3. Normal solar transmittance from SHGC by the U >= 4.5 and U <= 3.4 correlations, linear in U
       between.
    4. Summer film resistances from ``SHGC - T_sol`` (same interpolation), inward-flowing fraction
       ``N = (R_o,s + R_l,w/2)/(R_o,s + R_l,w + R_i,s)``, absorptance ``(SHGC - T_sol)/N``,
       reflectance ``1 - T_sol - absorptance``.

    Parameters
    ----------
    u_factor : float [W/(m2 K)]
        NFRC U-factor incl. surface films (0 < U <= 7).
    shgc : float [-]
        Normal-incidence SHGC (0 < SHGC < 1).
    visible_transmittance : float or None [-]
        Defaults to the solar transmittance.
    name : str
        For messages.

    Returns
    -------
    SimpleGlazing

    References
    ----------
    EnergyPlus Engineering Reference, Window Calculation Module, "Simple Window Model";
    D. Arasteh, J. C. Kohler, B. Griffith, "Modeling windows in EnergyPlus with simple performance
    indices", LBNL-2804E, 2009.
    """
    label = f"WindowMaterial:SimpleGlazingSystem '{name}'" if name else "simple glazing"
    if not 0.0 < u_factor <= 7.0:
        raise ThermocalInputError(
            f"{label}: U-factor {u_factor} W/(m2 K) must be in (0, 7] (the film resistances "
            "alone limit the model to U <= 7)."
        )
    if not 0.0 < shgc < 1.0:
        raise ThermocalInputError(f"{label}: SHGC {shgc} must be in (0, 1).")
    u = float(u_factor)
    if u < 5.85:
        r_iw = 1.0 / (0.359073 * math.log(u) + 6.949915)
    else:
        r_iw = 1.0 / (1.788041 * u - 2.886625)
    r_ow = 1.0 / (0.025342 * u + 29.163853)
    r_lw = 1.0 / u - r_iw - r_ow
    if r_lw <= 0.0:
        raise ThermocalInputError(
            f"{label}: U-factor {u} is higher than the surface films alone allow; lower it."
        )
    thickness = 0.002 if 1.0 / r_lw > 7.0 else 0.05914 - 0.00714 / r_lw
    conductivity = thickness / r_lw

    def tsol_high(g):
        return 0.939998 * g * g + 0.20332 * g if g < 0.7206 else 1.30415 * g - 0.30515

    def tsol_low(g):
        return 0.41040 * g if g <= 0.15 else 0.085775 * g * g + 0.963954 * g - 0.084958

    t_sol = max(_interpolate_u(u, tsol_low(shgc), tsol_high(shgc)), 0.0)
    x = shgc - t_sol
    r_is = _interpolate_u(
        u,
        1.0 / (199.8208128 * x**3 - 90.639733 * x**2 + 19.737055 * x + 6.766575),
        1.0 / (29.436546 * x**3 - 21.943415 * x**2 + 9.945872 * x + 7.426151),
    )
    r_os = _interpolate_u(u, 1.0 / (5.763355 * x + 20.541528), 1.0 / (2.225824 * x + 20.57708))
    inward = (r_os + 0.5 * r_lw) / (r_os + r_lw + r_is)
    absorptance = x / inward
    reflectance = 1.0 - t_sol - absorptance
    if reflectance < 0.0:
        raise ThermocalInputError(
            f"{label}: U = {u}, SHGC = {shgc} give a negative solar reflectance "
            f"({reflectance:.3f}); the combination is outside the simple model's range."
        )
    tvis = t_sol if visible_transmittance is None else float(visible_transmittance)
    return SimpleGlazing(
        u_factor=u,
        shgc=float(shgc),
        thickness=thickness,
        conductivity=conductivity,
        solar_transmittance=t_sol,
        solar_reflectance=reflectance,
        solar_absorptance=absorptance,
        inward_flowing_fraction=inward,
        resistance_inside_winter=r_iw,
        resistance_outside_winter=r_ow,
        resistance_layer=r_lw,
        resistance_inside_summer=r_is,
        resistance_outside_summer=r_os,
        visible_transmittance=tvis,
    )
