"""Data model of the detailed multi-zone building (plain dataclasses, validated on construction).

A :class:`Building` holds named materials, constructions (layers listed outside -> inside), window
types, zones, surfaces and windows.  Everything refers to everything else *by name*; the
:class:`Building` constructor checks every reference and every number and raises
:class:`~thermocal.errors.ThermocalInputError` naming the object at fault.

Conventions
-----------
- SI units; temperatures in degrees C.
- Azimuth in degrees clockwise from north (0 N, 90 E, 180 S, 270 W); tilt 0 = horizontal facing
  up (roof), 90 = vertical (wall), 180 = horizontal facing down (floor, seen from the zone).
  Tilt and azimuth describe the *outward* normal of the surface as seen from its zone.
- ``Surface.area`` is the GROSS area, windows included (as EnergyPlus' BuildingSurface); the opaque
  net area is the gross area minus the areas of the windows hosted by the surface.
- ``Window.area`` is the whole opening (glass + frame); ``frame_fraction`` of it is frame, which
  conducts with the window U-value but admits no solar radiation.
- An inter-zone partition is described twice, once from each zone (two :class:`Surface` objects
  with ``boundary="zone"`` pointing at each other through ``other_surface``), as in EnergyPlus;
  the simulation builds one set of conduction nodes for the pair (from the first of the two).

Every numerical envelope parameter has a stable name (see :meth:`Building.parameters`), so that
calibration campaigns can perturb it with :meth:`Building.with_parameters`.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.parameters import INFILTRATION_FACTOR

#: Allowed surface boundary conditions.
BOUNDARIES = ("outdoors", "ground", "zone", "adiabatic")


def _finite_table(values, what: str, field_name: str) -> np.ndarray:
    """``values`` as a float array of finite numbers, or a clear error naming the field."""
    try:
        table = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        table = None
    if table is None or table.ndim == 0 or not np.all(np.isfinite(table)):
        raise ThermocalInputError(
            f"{what}: {field_name} must be a table of finite numbers (a list, or a list of "
            f"equal-length lists), got {values!r:.80}"
        )
    return table


def _positive(value: float, what: str, *, allow_zero: bool = False) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ThermocalInputError(f"{what} must be a number, got {value!r}") from None
    if not math.isfinite(number) or number < 0 or (number == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ThermocalInputError(f"{what} must be finite and {bound}, got {value!r}")
    return number


#: Physically plausible ranges of layer properties: (lower, upper, unit, likely unit slips as
#: (factor, wrong unit)): a value outside is refused, with the value probably meant.
PLAUSIBLE = {
    "conductivity": (1e-3, 1000.0, "W/(m K)", ((1e-3, "mW/(m K)"),)),
    "density": (5.0, 25000.0, "kg/m3", ((1000.0, "g/cm3 or t/m3"),)),
    "specific_heat": (100.0, 10000.0, "J/(kg K)", ((1000.0, "kJ/(kg K)"),)),
    "thickness": (1e-5, 5.0, "m", ((1e-3, "mm"), (1e-2, "cm"))),
}


def _plausible(value: float, quantity: str, what: str) -> float:
    """``value`` when inside :data:`PLAUSIBLE` for ``quantity``; otherwise a clear error."""
    lower, upper, unit, slips = PLAUSIBLE[quantity]
    if lower <= value <= upper:
        return value
    hint = ""
    for factor, wrong in slips:
        if lower <= value * factor <= upper:
            hint = f"; given in {wrong}? then write {value * factor:g}"
            break
    raise ThermocalInputError(
        f"{what}: {quantity} {value:g} {unit} is outside the physically plausible range "
        f"{lower:g} to {upper:g} {unit}{hint}"
    )


def setpoint_celsius(
    value, what: str, plausible: tuple[float, float] | None = None
) -> float | None:
    """A set point in C; Kelvin values (200-400) and absurd ones refused.

    Parameters
    ----------
    value : float or None [C]
        The set point as given; None (no heating or cooling) passes.
    what : str
        The zone and the key, for the message (``"zone 'living': heating_setpoint"``).
    plausible : tuple of float or None [C]
        ``(lowest, highest)`` set point accepted, with the value probably meant when a
        Fahrenheit value or a stray minus sign explains one outside; None accepts any
        temperature from -100 to 200 C (a :class:`Zone` made in code, e.g. by the IDF import,
        whose schedules use values such as -50 or 100 C for "off").

    Returns
    -------
    float or None [C]
    """
    if value is None:
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ThermocalInputError(f"{what} must be a number in C, got {value!r}") from None
    if not math.isfinite(number):
        raise ThermocalInputError(f"{what} must be finite, got {value!r}")
    if 200 <= number <= 400:
        raise ThermocalInputError(
            f"{what} {number:g} looks like Kelvin; set points are in C: did you mean "
            f"{number - 273.15:.2f}?"
        )
    if not -100 <= number <= 200:
        raise ThermocalInputError(f"{what} {number:g} C is not a plausible temperature")
    if plausible is not None and not plausible[0] <= number <= plausible[1]:
        raise ThermocalInputError(
            f"{what} {number:g} C is not a room's set point (expected "
            f"{plausible[0]:g}-{plausible[1]:g} C){_setpoint_slip(number, plausible)}"
        )
    return number


def _setpoint_slip(number: float, plausible: tuple[float, float]) -> str:
    """The end of the message on a set point outside ``plausible``: the value probably meant.

    Parameters
    ----------
    number : float [C as read]
    plausible : tuple of float [C]
        ``(lowest, highest)`` set point accepted.

    Returns
    -------
    str
        The Fahrenheit conversion or the value without its minus sign when that one is
        plausible, otherwise the remedy for a value meaning "off".
    """
    low, high = plausible
    fahrenheit = (number - 32.0) * 5.0 / 9.0
    if low <= fahrenheit <= high:
        return f"; Fahrenheit? then write {fahrenheit:.1f}"
    if low <= -number <= high:
        return f"; a minus sign too many? then write {-number:g}"
    return "; a zone without this heating or cooling leaves the key out"


def _fraction(value: float, what: str) -> float:
    number = _positive(value, what, allow_zero=True)
    if number > 1:
        raise ThermocalInputError(f"{what} must lie in [0, 1], got {value!r}")
    return number


# ----------------------------------------------------------------------------------------------
# materials and constructions
# ----------------------------------------------------------------------------------------------


#: DOE-2 / EnergyPlus surface roughness classes and their forced-convection multipliers [-].
ROUGHNESS_FACTORS = {
    "VeryRough": 2.17,
    "Rough": 1.67,
    "MediumRough": 1.52,
    "MediumSmooth": 1.13,
    "Smooth": 1.11,
    "VerySmooth": 1.0,
}


def _roughness(value, what: str) -> str | None:
    if value is None or (isinstance(value, str) and not value.strip()):
        return None
    key = {k.lower(): k for k in ROUGHNESS_FACTORS}.get(str(value).replace(" ", "").lower())
    if key is None:
        raise ThermocalInputError(
            f"{what}: roughness {value!r} is not one of {sorted(ROUGHNESS_FACTORS)}"
        )
    return key


@dataclass
class Material:
    """A homogeneous layer with thermal mass.

    Parameters
    ----------
    name : str
        Unique name.
    conductivity : float [W/(m K)]
    density : float [kg/m3]
    specific_heat : float [J/(kg K)]
    thickness : float [m]
        Must be > 0 (use :class:`NoMassMaterial` for a pure resistance).
    thermal_absorptance : float [-]
        Long-wave emissivity of the layer's face, used when the layer is the outermost or innermost
        layer of a construction (EnergyPlus "Thermal Absorptance", default 0.9).
    solar_absorptance : float [-]
        Short-wave absorptance of the layer's face (EnergyPlus "Solar Absorptance", default 0.6).
    roughness : str or None
        Surface roughness class of the layer's face (:data:`ROUGHNESS_FACTORS`, EnergyPlus
        "Roughness"), used for the exterior convection when the layer is the outermost one;
        None = the simulation's ``NetworkOptions.roughness_factor``.
    """

    name: str
    conductivity: float
    density: float
    specific_heat: float
    thickness: float
    thermal_absorptance: float = 0.9
    solar_absorptance: float = 0.6
    roughness: str | None = None

    def __post_init__(self) -> None:
        what = f"material '{self.name}'"
        self.roughness = _roughness(self.roughness, what)
        self.conductivity = _plausible(
            _positive(self.conductivity, f"{what}: conductivity [W/(m K)]"), "conductivity", what
        )
        self.density = _plausible(
            _positive(self.density, f"{what}: density [kg/m3]"), "density", what
        )
        self.specific_heat = _plausible(
            _positive(self.specific_heat, f"{what}: specific_heat [J/(kg K)]"),
            "specific_heat",
            what,
        )
        self.thickness = _plausible(
            _positive(self.thickness, f"{what}: thickness [m]"), "thickness", what
        )
        self.thermal_absorptance = _fraction(
            self.thermal_absorptance, f"{what}: thermal_absorptance"
        )
        self.solar_absorptance = _fraction(self.solar_absorptance, f"{what}: solar_absorptance")

    @property
    def resistance(self) -> float:
        """Thermal resistance of the layer [m2 K/W]."""
        return self.thickness / self.conductivity

    @property
    def diffusivity(self) -> float:
        """Thermal diffusivity [m2/s]."""
        return self.conductivity / (self.density * self.specific_heat)

    @property
    def heat_capacity(self) -> float:
        """Areal heat capacity of the layer [J/(m2 K)]."""
        return self.density * self.specific_heat * self.thickness


@dataclass
class NoMassMaterial:
    """A pure thermal resistance without heat capacity (air gap, light insulation board).

    Parameters
    ----------
    name : str
    resistance : float [m2 K/W]
        Must be > 0.
    thermal_absorptance, solar_absorptance : float [-]
    roughness : str or None
        Face properties, as for :class:`Material`.
    """

    name: str
    resistance: float
    thermal_absorptance: float = 0.9
    solar_absorptance: float = 0.6
    roughness: str | None = None

    def __post_init__(self) -> None:
        what = f"no-mass material '{self.name}'"
        self.roughness = _roughness(self.roughness, what)
        self.resistance = _positive(self.resistance, f"{what}: resistance [m2 K/W]")
        self.thermal_absorptance = _fraction(
            self.thermal_absorptance, f"{what}: thermal_absorptance"
        )
        self.solar_absorptance = _fraction(self.solar_absorptance, f"{what}: solar_absorptance")

    heat_capacity = 0.0


@dataclass
class Construction:
    """An opaque construction: material names listed from OUTSIDE to INSIDE."""

    name: str
    layers: tuple[str, ...]

    def __post_init__(self) -> None:
        if isinstance(self.layers, str):
            self.layers = (self.layers,)
        self.layers = tuple(self.layers)
        if not self.layers:
            raise ThermocalInputError(
                f"construction '{self.name}' has no layers; list at least one"
            )


# ----------------------------------------------------------------------------------------------
# windows
# ----------------------------------------------------------------------------------------------


def fresnel_relative_transmittance(
    aoi: np.ndarray | float, n_panes: int = 2, refractive_index: float = 1.526
) -> np.ndarray:
    """Transmittance at incidence angle ``aoi`` relative to normal incidence, clear glazing.

    Uses the Fresnel/Snell air-glass interface losses (pvlib's ``iam.physical`` with zero glass
    absorption) for ``n_panes`` identical uncoated panes: the relative transmittance of the whole
    glazing is that of one pane raised to the power ``n_panes``.

    Parameters
    ----------
    aoi : array-like [deg]
        Angle of incidence; values >= 90 give 0.
    n_panes : int [-]
    refractive_index : float [-]

    Returns
    -------
    numpy.ndarray [-]

    References
    ----------
    .. [1] Duffie J.A., Beckman W.A., Solar Engineering of Thermal Processes, 4th ed.,
       2013, sections 5.1-5.3.
    """
    theta = np.radians(np.clip(np.asarray(aoi, dtype=float), 0.0, 90.0))

    def pane(theta_):
        sin_r = np.sin(theta_) / refractive_index
        theta_r = np.arcsin(sin_r)
        with np.errstate(invalid="ignore", divide="ignore"):
            r_perp = np.sin(theta_r - theta_) ** 2 / np.sin(theta_r + theta_) ** 2
            r_par = np.tan(theta_r - theta_) ** 2 / np.tan(theta_r + theta_) ** 2
        r0 = ((refractive_index - 1) / (refractive_index + 1)) ** 2
        r_perp = np.where(theta_ < 1e-6, r0, r_perp)
        r_par = np.where(theta_ < 1e-6, r0, r_par)
        return 0.5 * ((1 - r_perp) / (1 + r_perp) + (1 - r_par) / (1 + r_par))

    rel = (pane(theta) / pane(np.zeros(1))) ** n_panes
    return np.where(theta >= np.radians(89.999), 0.0, rel)


@dataclass
class WindowType:
    """Glazing system: simple (U, SHGC) description, optionally with layered optics.

    Simple model (only ``u_value`` and ``shgc``): the whole solar heat gain coefficient is admitted
    as transmitted short-wave radiation (as ISO 13790 / ISO 52016-1 do), with the angular
    dependence of clear ``n_panes`` glazing (:func:`fresnel_relative_transmittance`).

    Layered optics (filled by the IDF importer from WindowMaterial:Glazing/Gas): normal-incidence
    solar transmittance ``solar_transmittance`` and per-pane absorptances ``pane_absorptances``
    (outside -> inside), with angular dependence given either as a callable
    ``angular_transmittance(aoi_deg) -> relative transmittance`` or as a table
    (``incidence_angles`` [deg] vs ``relative_transmittance`` [-]); optional angular absorptances
    ``pane_absorptances_angular`` (shape ``(len(incidence_angles), n_panes)``, absolute values) and
    hemispherical (diffuse) values.  Absorbed radiation is put on the outer/inner window surface
    nodes; the inward-flowing part then follows from the heat balance.

    Parameters
    ----------
    name : str
    u_value : float [W/(m2 K)]
        Whole-window U-value including standard surface resistances (ISO 6946: 0.13 + 0.04).
    shgc : float [-]
        Solar heat gain coefficient (g-value) at normal incidence.
    solar_transmittance : float or None [-]
        Normal-incidence direct solar transmittance (layered optics).
    pane_absorptances : sequence of float or None [-]
        Normal-incidence solar absorptance of each pane, outside -> inside.
    angular_transmittance : callable or None
        ``f(aoi [deg]) -> relative transmittance [-]`` (1 at normal incidence).
    incidence_angles, relative_transmittance : sequence of float or None [deg], [-]
        Tabulated angular dependence (used when no callable is given).
    pane_absorptances_angular : array-like or None [-]
        Absolute per-pane absorptances at ``incidence_angles``.
    diffuse_transmittance : float or None [-]
        Hemispherical transmittance for isotropic diffuse radiation; by default integrated from
        the angular dependence.
    diffuse_pane_absorptances : sequence of float or None [-]
    n_panes : int [-]
        Number of panes for the default angular curve (default 2).
    emissivity_outside, emissivity_inside : float [-]
        Long-wave emissivity of the outer and inner glass faces (uncoated glass 0.84).
    glass_conductance_temperatures, glass_conductance_ratio : sequence of float or None [C], [-]
        Temperature dependence of the glass-to-glass conductance (gas gaps): the conductance at a
        mean glazing temperature over the one implied by ``u_value`` (interpolated, end values
        held outside the table). None = constant conductance.
    coated_u_values, coated_glass_conductance_ratio : sequence of float, array-like or None
        [W/(m2 K)], [-]
        The glazing and the same panes and gaps with other coatings on their gap faces
        (:meth:`~thermocal.multizone.glazing.LayeredGlazing.coated_conductance_family`): their
        U-values (increasing) and their glass conductance tables (one row per U-value, at
        ``glass_conductance_temperatures``). When given, ``glass_conductance_ratio`` is the
        family's table at ``u_value`` (interpolated in U-value, held at the ends), so a changed
        U-value (:meth:`with_u_value`, or an edited building file) behaves as a glazing of that
        U-value does. None (a simple or single-pane window type): the table stays as given.
    """

    name: str
    u_value: float
    shgc: float
    solar_transmittance: float | None = None
    pane_absorptances: tuple[float, ...] | None = None
    angular_transmittance: Callable | None = None
    incidence_angles: tuple[float, ...] | None = None
    relative_transmittance: tuple[float, ...] | None = None
    pane_absorptances_angular: np.ndarray | None = None
    diffuse_transmittance: float | None = None
    diffuse_pane_absorptances: tuple[float, ...] | None = None
    n_panes: int = 2
    emissivity_outside: float = 0.84
    emissivity_inside: float = 0.84
    glass_conductance_temperatures: tuple[float, ...] | None = None
    glass_conductance_ratio: tuple[float, ...] | None = None
    coated_u_values: tuple[float, ...] | None = None
    coated_glass_conductance_ratio: np.ndarray | None = None

    def __post_init__(self) -> None:
        what = f"window type '{self.name}'"
        self.u_value = _positive(self.u_value, f"{what}: u_value [W/(m2 K)]")
        if (self.glass_conductance_temperatures is None) != (self.glass_conductance_ratio is None):
            raise ThermocalInputError(
                f"{what}: give both glass_conductance_temperatures and glass_conductance_ratio, "
                "or neither"
            )
        if self.glass_conductance_temperatures is not None:
            temps = _finite_table(self.glass_conductance_temperatures, what,
                                  "glass_conductance_temperatures")  # fmt: skip
            ratio = _finite_table(self.glass_conductance_ratio, what, "glass_conductance_ratio")
            if temps.ndim != 1 or temps.shape != ratio.shape or temps.size < 2:
                raise ThermocalInputError(
                    f"{what}: glass_conductance_temperatures and glass_conductance_ratio must be "
                    "1-D tables of equal length (>= 2)"
                )
            if np.any(np.diff(temps) <= 0) or not np.all(ratio > 0):
                raise ThermocalInputError(
                    f"{what}: glass_conductance_temperatures must increase strictly and "
                    "glass_conductance_ratio must be > 0"
                )
            self.glass_conductance_temperatures = tuple(float(t) for t in temps)
            self.glass_conductance_ratio = tuple(float(r) for r in ratio)
        self._follow_coated_family(what)
        self.emissivity_outside = _fraction(self.emissivity_outside, f"{what}: emissivity_outside")
        self.emissivity_inside = _fraction(self.emissivity_inside, f"{what}: emissivity_inside")
        if self.u_value > 10:
            raise ThermocalInputError(
                f"{what}: u_value {self.u_value} W/(m2 K) is implausible (single glazing ~5.8)"
            )
        self.shgc = _fraction(self.shgc, f"{what}: shgc")
        if self.solar_transmittance is not None:
            self.solar_transmittance = _fraction(
                self.solar_transmittance, f"{what}: solar_transmittance"
            )
        if self.pane_absorptances is not None:
            self.pane_absorptances = tuple(
                _fraction(a, f"{what}: pane_absorptances[{i}]")
                for i, a in enumerate(self.pane_absorptances)
            )
            if self.solar_transmittance is None:
                raise ThermocalInputError(
                    f"{what}: pane_absorptances given without solar_transmittance"
                )
            if self.solar_transmittance + sum(self.pane_absorptances) > 1 + 1e-9:
                raise ThermocalInputError(
                    f"{what}: solar_transmittance + pane absorptances exceed 1"
                )
        if (self.incidence_angles is None) != (self.relative_transmittance is None):
            raise ThermocalInputError(
                f"{what}: give both incidence_angles and relative_transmittance, or neither"
            )
        if self.incidence_angles is not None:
            angles = np.asarray(self.incidence_angles, dtype=float)
            rel = np.asarray(self.relative_transmittance, dtype=float)
            if angles.shape != rel.shape or angles.ndim != 1 or angles.size < 2:
                raise ThermocalInputError(
                    f"{what}: incidence_angles and relative_transmittance must be 1-D tables of "
                    "equal length (>= 2)"
                )
            if np.any(np.diff(angles) <= 0):
                raise ThermocalInputError(f"{what}: incidence_angles must increase strictly")
            self.incidence_angles = tuple(angles)
            self.relative_transmittance = tuple(rel)
        if self.pane_absorptances_angular is not None:
            table = np.asarray(self.pane_absorptances_angular, dtype=float)
            if (
                self.incidence_angles is None
                or self.pane_absorptances is None
                or table.shape != (len(self.incidence_angles), len(self.pane_absorptances))
            ):
                raise ThermocalInputError(
                    f"{what}: pane_absorptances_angular must have shape "
                    "(len(incidence_angles), len(pane_absorptances))"
                )
            self.pane_absorptances_angular = table

    def _follow_coated_family(self, what: str) -> None:
        """Validate the coated family and take its table at ``u_value``."""
        if (self.coated_u_values is None) != (self.coated_glass_conductance_ratio is None):
            raise ThermocalInputError(
                f"{what}: give both coated_u_values and coated_glass_conductance_ratio, or neither"
            )
        if self.coated_u_values is None:
            return
        u_values = _finite_table(self.coated_u_values, what, "coated_u_values")
        table = _finite_table(self.coated_glass_conductance_ratio, what,
                              "coated_glass_conductance_ratio")  # fmt: skip
        temps = self.glass_conductance_temperatures
        if (
            temps is None
            or u_values.ndim != 1
            or u_values.size < 2
            or table.shape != (u_values.size, len(temps))
        ):
            raise ThermocalInputError(
                f"{what}: coated_glass_conductance_ratio must have one row per coated U-value "
                "and one column per glass_conductance_temperatures value (both tables given)"
            )
        if np.any(np.diff(u_values) <= 0) or not np.all(u_values > 0) or not np.all(table > 0):
            raise ThermocalInputError(
                f"{what}: coated_u_values must be positive and increase strictly, and "
                "coated_glass_conductance_ratio must be > 0"
            )
        self.coated_u_values = tuple(float(u) for u in u_values)
        self.coated_glass_conductance_ratio = table
        self.glass_conductance_ratio = tuple(
            float(np.interp(self.u_value, u_values, table[:, j])) for j in range(table.shape[1])
        )

    def with_u_value(self, u_value: float) -> WindowType:
        """Copy with another U-value [W/(m2 K)], with the glass conductance of that glazing.

        With the coated family of the same panes and gaps (``coated_u_values``), the glass
        conductance's temperature table is the family's at the new U-value (interpolated in
        U-value; beyond the uncoated glazing's U-value the most conductive table, below the
        best coating's the least), so a window whose U-value is lowered loses the temperature
        dependence a coating removes. The result depends on the family and the U-value only
        (not on U-values set before). Without a family the table is kept.

        Parameters
        ----------
        u_value : float [W/(m2 K)]
        """
        return dataclasses.replace(self, u_value=u_value)

    # -- optics ---------------------------------------------------------------------------------
    @property
    def layered(self) -> bool:
        """True when layered optics (transmittance and pane absorptances) are available."""
        return self.solar_transmittance is not None and self.pane_absorptances is not None

    @property
    def normal_transmittance(self) -> float:
        """Direct solar transmittance at normal incidence [-] (the SHGC for the simple model)."""
        return self.solar_transmittance if self.solar_transmittance is not None else self.shgc

    def relative_transmittance_at(self, aoi: np.ndarray | float) -> np.ndarray:
        """Transmittance at incidence ``aoi`` [deg] relative to normal incidence [-]."""
        aoi = np.asarray(aoi, dtype=float)
        if self.angular_transmittance is not None:
            rel = np.asarray(self.angular_transmittance(aoi), dtype=float)
        elif self.incidence_angles is not None:
            rel = np.interp(aoi, self.incidence_angles, self.relative_transmittance, right=0.0)
        else:
            rel = fresnel_relative_transmittance(aoi, self.n_panes)
        return np.where(aoi >= 90.0, 0.0, np.clip(rel, 0.0, 1.0))

    def transmittance(self, aoi: np.ndarray | float) -> np.ndarray:
        """Direct-beam solar transmittance at incidence ``aoi`` [deg] [-]."""
        return self.normal_transmittance * self.relative_transmittance_at(aoi)

    def pane_absorptance(self, aoi: np.ndarray | float) -> np.ndarray:
        """Absolute per-pane absorptance of direct beam, shape ``aoi.shape + (n_panes,)`` [-]."""
        aoi = np.asarray(aoi, dtype=float)
        if not self.layered:
            return np.zeros(aoi.shape + (0,))
        if self.pane_absorptances_angular is not None:
            cols = [
                np.interp(aoi, self.incidence_angles, self.pane_absorptances_angular[:, j], right=0)
                for j in range(len(self.pane_absorptances))
            ]
            return np.stack(cols, axis=-1)
        # absorptance roughly follows the optical path: scale with 1/cos(refracted angle),
        # capped so that nothing exceeds the incident energy, and vanishing at grazing incidence
        rel = self.relative_transmittance_at(aoi)
        base = np.asarray(self.pane_absorptances)
        return np.clip(rel[..., None] ** 0.5, 0.0, 1.0) * base

    def _hemispherical(self, values: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
        theta = np.linspace(0.0, 90.0, 181)
        weights = 2 * np.sin(np.radians(theta)) * np.cos(np.radians(theta))
        vals = values(theta)
        if vals.ndim == 1:
            return np.trapezoid(vals * weights, np.radians(theta))
        return np.trapezoid(vals * weights[:, None], np.radians(theta), axis=0)

    @property
    def diffuse_transmittance_value(self) -> float:
        """Hemispherical transmittance for isotropic diffuse radiation [-]."""
        if self.diffuse_transmittance is not None:
            return float(self.diffuse_transmittance)
        return float(self._hemispherical(self.transmittance))

    @property
    def diffuse_pane_absorptance_values(self) -> np.ndarray:
        """Hemispherical per-pane absorptances for isotropic diffuse radiation [-]."""
        if self.diffuse_pane_absorptances is not None:
            return np.asarray(self.diffuse_pane_absorptances, dtype=float)
        if not self.layered:
            return np.zeros(0)
        return np.asarray(self._hemispherical(self.pane_absorptance), dtype=float)

    @property
    def shgc_limit(self) -> float:
        """The largest SHGC :meth:`with_shgc` can give this window type [-].

        A layered glazing's optics (transmittance and pane absorptances) are scaled together
        with its SHGC, and together they cannot exceed 1 (a pane cannot transmit and absorb
        more sun than falls on it): its limit is the SHGC at which they reach 1. A simple
        window type (U-value and SHGC only) has 1.
        """
        if not self.layered or self.shgc == 0:
            return 1.0
        total = self.solar_transmittance + sum(self.pane_absorptances)
        return min(1.0, self.shgc / total) if total > 0 else 1.0

    def with_shgc(self, shgc: float) -> WindowType:
        """Copy with another SHGC; layered optics are scaled by the same ratio.

        Raises
        ------
        ThermocalInputError
            An SHGC beyond :attr:`shgc_limit` (before, the optics stopped there while the
            window type reported the value asked for).
        """
        shgc = _fraction(shgc, f"window type '{self.name}': shgc")
        if not self.layered or self.shgc == 0:
            return dataclasses.replace(self, shgc=shgc)
        limit = self.shgc_limit
        if shgc > limit * (1.0 + 1e-9):
            raise ThermocalInputError(
                f"window type '{self.name}': shgc {shgc:.4g} is beyond what its layered glazing "
                f"can give ({limit:.4g}: its transmittance and pane absorptances, scaled with "
                f"the SHGC, would exceed 1); give at most {limit:.4g}, or describe the window "
                "by its U-value and SHGC alone"
            )
        total = self.solar_transmittance + sum(self.pane_absorptances)
        ratio = min(shgc / self.shgc, 1.0 / total)  # equal at the limit, but for round-off
        return dataclasses.replace(
            self,
            shgc=shgc,
            solar_transmittance=self.solar_transmittance * ratio,
            pane_absorptances=tuple(a * ratio for a in self.pane_absorptances),
            pane_absorptances_angular=None
            if self.pane_absorptances_angular is None
            else self.pane_absorptances_angular * ratio,
            diffuse_transmittance=None
            if self.diffuse_transmittance is None
            else self.diffuse_transmittance * ratio,
            diffuse_pane_absorptances=None
            if self.diffuse_pane_absorptances is None
            else tuple(a * ratio for a in self.diffuse_pane_absorptances),
        )


# ----------------------------------------------------------------------------------------------
# zones, surfaces, windows, building
# ----------------------------------------------------------------------------------------------


@dataclass
class Zone:
    """A well-mixed air volume.

    Parameters
    ----------
    name : str
    volume : float [m3]
        Air volume (> 0).
    floor_area : float [m2]
    infiltration_ach : float [1/h]
        Infiltration air changes per hour (outdoor air at outdoor temperature).
    internal_gains : float [W]
        Constant internal gains (time-varying gains go through ``heat_input`` of the run).
    internal_gains_radiative_fraction : float [-]
        Radiative part of the internal gains (to the zone's surfaces, area-weighted).
    heating_setpoint, cooling_setpoint : float or None [C]
        Ideal heating below / cooling above these air temperatures; None = no heating/cooling.
    infiltration_group : str or None
        Zones sharing a group share one calibration parameter ``infiltration/<group>/ach``.
    air_capacity_factor : float [-]
        Multiplier on the air heat capacity (furniture, EnergyPlus' zone capacitance multiplier).
    """

    name: str
    volume: float
    floor_area: float
    infiltration_ach: float = 0.0
    internal_gains: float = 0.0
    internal_gains_radiative_fraction: float = 0.5
    heating_setpoint: float | None = None
    cooling_setpoint: float | None = None
    infiltration_group: str | None = None
    air_capacity_factor: float = 1.0

    def __post_init__(self) -> None:
        what = f"zone '{self.name}'"
        self.volume = _positive(self.volume, f"{what}: volume [m3]")
        self.floor_area = _positive(self.floor_area, f"{what}: floor_area [m2]", allow_zero=True)
        self.infiltration_ach = _positive(
            self.infiltration_ach, f"{what}: infiltration_ach [1/h]", allow_zero=True
        )
        self.internal_gains = float(self.internal_gains)
        self.internal_gains_radiative_fraction = _fraction(
            self.internal_gains_radiative_fraction, f"{what}: internal_gains_radiative_fraction"
        )
        self.air_capacity_factor = _positive(
            self.air_capacity_factor, f"{what}: air_capacity_factor"
        )
        self.heating_setpoint = setpoint_celsius(
            self.heating_setpoint, f"{what}: heating_setpoint"
        )
        self.cooling_setpoint = setpoint_celsius(
            self.cooling_setpoint, f"{what}: cooling_setpoint"
        )
        if (
            self.heating_setpoint is not None
            and self.cooling_setpoint is not None
            and float(self.heating_setpoint) > float(self.cooling_setpoint)
        ):
            raise ThermocalInputError(
                f"{what}: heating_setpoint {self.heating_setpoint} C is above cooling_setpoint "
                f"{self.cooling_setpoint} C"
            )

    @property
    def conditioned(self) -> bool:
        """True when the zone has a heating or a cooling set point."""
        return self.heating_setpoint is not None or self.cooling_setpoint is not None


@dataclass
class Surface:
    """An opaque surface of a zone (wall, roof, floor, partition, internal mass).

    Parameters
    ----------
    name : str
    zone : str
        Name of the zone the surface faces.
    construction : str
        Construction name (layers outside -> inside; "inside" faces ``zone``).
    area : float [m2]
        GROSS area, hosted windows included.
    tilt : float [deg]
        0 roof (facing up), 90 wall, 180 floor (facing down); of the outward normal.
    azimuth : float [deg]
        Clockwise from north, of the outward normal.
    boundary : {"outdoors", "ground", "zone", "adiabatic"}
        Outside boundary condition. "adiabatic" with a construction gives internal mass.
    outside_at_inside : bool
        Only with ``boundary="adiabatic"``: the outside face is held at the inside face's
        temperature, as EnergyPlus does for its adiabatic surfaces, surfaces whose outside
        boundary is the surface itself and ``InternalMass`` (the construction exchanges heat
        with the zone through both faces, the zone paying only for its inside face; see
        :func:`thermocal.multizone.network.mirrored_outside_entries`). Default False: no heat
        crosses the outside face.
    other_zone, other_surface : str or None
        For ``boundary="zone"``: the zone on the other side and the partner surface (required).
    solar_absorptance_outside, solar_absorptance_inside : float or None [-]
        Default: the solar absorptance of the outermost / innermost layer.
    emissivity_outside, emissivity_inside : float or None [-]
        Long-wave emissivity; default: the thermal absorptance of the outermost / innermost layer.
    view_factor_ground : float or None [-]
        Outside view factor to the ground; default ``(1 - cos(tilt)) / 2``.
    sun_exposed, wind_exposed : bool
    perimeter : float or None [m]
        Perimeter of the gross surface (TARP exterior convection); default: a square of the
        same area.
    wind_speed_factor : float or None [-]
        Local wind speed at the surface (its centroid height and the site's terrain) over the
        weather station's wind speed, for the exterior convection; default
        ``NetworkOptions.wind_speed_factor``.
    """

    name: str
    zone: str
    construction: str
    area: float
    tilt: float = 90.0
    azimuth: float = 0.0
    boundary: str = "outdoors"
    other_zone: str | None = None
    other_surface: str | None = None
    solar_absorptance_outside: float | None = None
    solar_absorptance_inside: float | None = None
    emissivity_outside: float | None = None
    emissivity_inside: float | None = None
    view_factor_ground: float | None = None
    sun_exposed: bool = True
    wind_exposed: bool = True
    perimeter: float | None = None
    wind_speed_factor: float | None = None
    outside_at_inside: bool = False

    def __post_init__(self) -> None:
        what = f"surface '{self.name}' (zone '{self.zone}')"
        self.area = _positive(self.area, f"{what}: area [m2]")
        if self.perimeter is not None:
            self.perimeter = _positive(self.perimeter, f"{what}: perimeter [m]")
        if self.wind_speed_factor is not None:
            self.wind_speed_factor = float(self.wind_speed_factor)
            if not 0.0 <= self.wind_speed_factor <= 5.0:
                raise ThermocalInputError(
                    f"{what}: wind_speed_factor must lie in [0, 5] (local over station wind "
                    f"speed), got {self.wind_speed_factor}"
                )
        self.tilt = float(self.tilt)
        if not 0.0 <= self.tilt <= 180.0:
            raise ThermocalInputError(f"{what}: tilt must lie in [0, 180] degrees, got {self.tilt}")
        self.azimuth = float(self.azimuth) % 360.0
        self.boundary = str(self.boundary).lower()
        if self.boundary not in BOUNDARIES:
            raise ThermocalInputError(
                f"{what}: boundary must be one of {', '.join(BOUNDARIES)}, got {self.boundary!r}"
            )
        self.outside_at_inside = bool(self.outside_at_inside)
        if self.outside_at_inside and self.boundary != "adiabatic":
            raise ThermocalInputError(
                f"{what}: outside_at_inside holds the outside face at the inside face's "
                f"temperature; it needs boundary 'adiabatic', got {self.boundary!r}"
            )
        for attr in (
            "solar_absorptance_outside",
            "solar_absorptance_inside",
            "emissivity_outside",
            "emissivity_inside",
            "view_factor_ground",
        ):
            value = getattr(self, attr)
            if value is not None:
                setattr(self, attr, _fraction(value, f"{what}: {attr}"))

    @property
    def perimeter_over_area(self) -> float:
        """Perimeter over area [1/m] (a square of the same area when no perimeter is given)."""
        perimeter = self.perimeter if self.perimeter is not None else 4.0 * math.sqrt(self.area)
        return perimeter / self.area

    @property
    def ground_view_factor(self) -> float:
        """Outside view factor to the ground [-]."""
        if self.view_factor_ground is not None:
            return self.view_factor_ground
        return 0.5 * (1.0 - math.cos(math.radians(self.tilt)))


@dataclass
class Window:
    """A window hosted by an exterior :class:`Surface`.

    Parameters
    ----------
    name : str
    surface : str
        Host surface (boundary must be "outdoors"); tilt/azimuth/zone are the host's.
    window_type : str
    area : float [m2]
        Whole opening (glass + frame).
    frame_fraction : float [-]
        Frame share of ``area`` (no solar transmission).
    shading_factor : float [-]
        Constant external shading reduction of incident solar radiation (1 = unshaded).
    height : float or None [m]
        Height of the glazing (its extent along the slope of the host surface), used by the
        ISO 15099 natural convection on the room side (EnergyPlus' TARP for windows). None:
        ``sqrt(area)`` (a square window).
    """

    name: str
    surface: str
    window_type: str
    area: float
    frame_fraction: float = 0.0
    shading_factor: float = 1.0
    height: float | None = None

    def __post_init__(self) -> None:
        what = f"window '{self.name}'"
        self.area = _positive(self.area, f"{what}: area [m2]")
        self.frame_fraction = _fraction(self.frame_fraction, f"{what}: frame_fraction")
        if self.frame_fraction >= 1.0:
            raise ThermocalInputError(f"{what}: frame_fraction must be < 1")
        self.shading_factor = _fraction(self.shading_factor, f"{what}: shading_factor")
        if self.height is not None:
            self.height = _positive(self.height, f"{what}: height [m]")

    @property
    def glazed_area(self) -> float:
        """Glass area [m2]."""
        return self.area * (1.0 - self.frame_fraction)


@dataclass
class Location:
    """Site: latitude [deg N], longitude [deg E], altitude [m], timezone (hours or name)."""

    latitude: float = 47.0
    longitude: float = 8.0
    altitude: float = 0.0
    timezone: float | str | None = None

    def __post_init__(self) -> None:
        self.latitude = float(self.latitude)
        self.longitude = float(self.longitude)
        self.altitude = float(self.altitude)
        if not -90 <= self.latitude <= 90:
            raise ThermocalInputError(f"location: latitude {self.latitude} outside [-90, 90]")
        if not -180 <= self.longitude <= 360:
            raise ThermocalInputError(f"location: longitude {self.longitude} outside [-180, 180]")


def _by_name(items, kind: str, cls) -> dict:
    """Turn a sequence (or mapping) of named objects into a name-keyed dict; reject duplicates."""
    if items is None:
        return {}
    if isinstance(items, Mapping):
        values = list(items.values())
    else:
        values = list(items)
    out: dict = {}
    for item in values:
        if not isinstance(item, cls):
            raise ThermocalInputError(f"{kind}: expected {cls}, got {type(item).__name__}")
        if item.name in out:
            raise ThermocalInputError(
                f"{kind} '{item.name}' is defined twice; names must be unique"
            )
        out[item.name] = item
    return out


def _unknown(kind: str, name: str, known: Iterable[str], owner: str) -> ThermocalInputError:
    known = list(known)
    close = difflib.get_close_matches(str(name), known, n=3)
    hint = f" (did you mean {', '.join(repr(c) for c in close)}?)" if close else ""
    return ThermocalInputError(
        f"{owner} refers to {kind} '{name}', which is not defined{hint}; define it or fix the name"
    )


@dataclass
class Building:
    """A complete multi-zone building; validated on construction.

    Collections may be given as sequences or name-keyed mappings; they are stored as name-keyed
    dicts in definition order.  ``ground_temperatures``: 12 monthly values [C] (January first) for
    surfaces with ``boundary="ground"``; None lets the simulation derive them from the weather
    (annual mean outdoor temperature, ISO 13370 Annex-style damped and lagged annual wave).
    ``ground_reflectance``: 12 monthly ground reflectances [-] (January first) for the sun
    reflected onto the facades; None takes the weather file's albedo (0.2 where it has none).
    ``foundations``: floors on the ground (by surface name) whose ground is a two-dimensional
    section (:class:`thermocal.multizone.foundation.FoundationGround`, EnergyPlus's
    ``Foundation`` boundary) instead of the ground temperature.
    """

    name: str
    location: Location = field(default_factory=Location)
    materials: dict[str, Material | NoMassMaterial] = field(default_factory=dict)
    constructions: dict[str, Construction] = field(default_factory=dict)
    window_types: dict[str, WindowType] = field(default_factory=dict)
    zones: dict[str, Zone] = field(default_factory=dict)
    surfaces: dict[str, Surface] = field(default_factory=dict)
    windows: dict[str, Window] = field(default_factory=dict)
    ground_temperatures: tuple[float, ...] | None = None
    ground_reflectance: tuple[float, ...] | None = None
    foundations: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if isinstance(self.location, Mapping):
            self.location = Location(**self.location)
        self.materials = _by_name(self.materials, "material", (Material, NoMassMaterial))
        self.constructions = _by_name(self.constructions, "construction", Construction)
        self.window_types = _by_name(self.window_types, "window type", WindowType)
        self.zones = _by_name(self.zones, "zone", Zone)
        self.surfaces = _by_name(self.surfaces, "surface", Surface)
        self.windows = _by_name(self.windows, "window", Window)
        if self.ground_temperatures is not None:
            temps = tuple(float(t) for t in self.ground_temperatures)
            if len(temps) != 12 or not all(-50 < t < 60 for t in temps):
                raise ThermocalInputError(
                    f"building '{self.name}': ground_temperatures must be 12 monthly values in C "
                    f"(January first), got {self.ground_temperatures!r}"
                )
            self.ground_temperatures = temps
        if self.ground_reflectance is not None:
            values = tuple(float(r) for r in self.ground_reflectance)
            if len(values) != 12 or not all(0.0 <= r <= 1.0 for r in values):
                raise ThermocalInputError(
                    f"building '{self.name}': ground_reflectance must be 12 monthly values in "
                    f"[0, 1] (January first), got {self.ground_reflectance!r}"
                )
            self.ground_reflectance = values
        self.validate()

    # -- validation -----------------------------------------------------------------------------
    def validate(self) -> None:
        """Check every cross reference; raise :class:`ThermocalInputError` naming the culprit."""
        if not self.zones:
            raise ThermocalInputError(f"building '{self.name}' has no zones")
        for construction in self.constructions.values():
            for layer in construction.layers:
                if layer not in self.materials:
                    raise _unknown(
                        "material", layer, self.materials, f"construction '{construction.name}'"
                    )
        for surface in self.surfaces.values():
            owner = f"surface '{surface.name}'"
            if surface.zone not in self.zones:
                raise _unknown("zone", surface.zone, self.zones, owner)
            if surface.construction not in self.constructions:
                raise _unknown("construction", surface.construction, self.constructions, owner)
            if surface.boundary == "zone":
                self._check_partner(surface)
            elif surface.other_surface is not None or surface.other_zone is not None:
                raise ThermocalInputError(
                    f"{owner}: other_zone/other_surface given but boundary is "
                    f"'{surface.boundary}'; set boundary: zone or remove them"
                )
        for name, ground in self.foundations.items():
            for named in (name, *(w for w, _ in ground.walls)):
                surface = self.surfaces.get(named)
                if surface is None or surface.boundary != "ground":
                    raise ThermocalInputError(
                        f"building '{self.name}': foundation '{name}' must name surfaces with "
                        f"boundary: ground ('{named}' is not one)"
                    )
        bounded = {s.zone for s in self.surfaces.values()}
        lonely = [
            name
            for name, zone in self.zones.items()
            if name not in bounded and zone.infiltration_ach <= 0.0
        ]
        if lonely and self.surfaces:
            raise ThermocalInputError(
                f"building '{self.name}': zone(s) {lonely[:5]} have no surfaces and no "
                "infiltration: nothing connects their air to the outside or to another zone, so "
                "their temperature would stay where it starts and their heat at zero; add their "
                "surfaces (an inter-zone surface is described from both zones) or remove them"
            )
        window_area: dict[str, float] = {}
        for window in self.windows.values():
            owner = f"window '{window.name}'"
            if window.surface not in self.surfaces:
                raise _unknown("surface", window.surface, self.surfaces, owner)
            if window.window_type not in self.window_types:
                raise _unknown("window type", window.window_type, self.window_types, owner)
            host = self.surfaces[window.surface]
            if host.boundary != "outdoors":
                raise ThermocalInputError(
                    f"{owner}: host surface '{host.name}' has boundary '{host.boundary}'; only "
                    "exterior windows (host boundary 'outdoors') are modelled"
                )
            window_area[host.name] = window_area.get(host.name, 0.0) + window.area
        for host_name, area in window_area.items():
            host = self.surfaces[host_name]
            if area >= host.area * (1 - 1e-9):
                raise ThermocalInputError(
                    f"surface '{host_name}': its windows ({area:.3f} m2) fill or exceed its gross "
                    f"area ({host.area:.3f} m2); Surface.area is the gross area incl. windows"
                )

    def _check_partner(self, surface: Surface) -> None:
        owner = f"surface '{surface.name}' (zone '{surface.zone}', boundary zone)"
        if surface.other_surface is None:
            raise ThermocalInputError(
                f"{owner} has no partner: set other_surface to the matching surface of the "
                "adjacent zone (inter-zone surfaces are described from both sides)"
            )
        partner = self.surfaces.get(surface.other_surface)
        if partner is None:
            raise ThermocalInputError(
                f"{owner}: its partner surface '{surface.other_surface}' is not defined; "
                "inter-zone surfaces must be described from both sides"
            )
        if partner.boundary != "zone" or partner.other_surface != surface.name:
            raise ThermocalInputError(
                f"{owner}: partner '{partner.name}' does not point back (its boundary is "
                f"'{partner.boundary}', other_surface {partner.other_surface!r}); set its "
                f"boundary: zone and other_surface: {surface.name}"
            )
        if surface.other_zone is not None and surface.other_zone != partner.zone:
            raise ThermocalInputError(
                f"{owner}: other_zone '{surface.other_zone}' differs from the zone of its partner "
                f"'{partner.name}' ('{partner.zone}')"
            )
        if partner.zone not in self.zones:
            raise _unknown("zone", partner.zone, self.zones, f"surface '{partner.name}'")
        if abs(partner.area - surface.area) > 0.01 * max(surface.area, partner.area):
            raise ThermocalInputError(
                f"{owner}: area {surface.area} m2 differs from its partner '{partner.name}' "
                f"({partner.area} m2) by more than 1 %"
            )

    # -- convenience ----------------------------------------------------------------------------
    def net_area(self, surface_name: str) -> float:
        """Opaque (net) area of a surface: gross area minus its windows [m2]."""
        gross = self.surfaces[surface_name].area
        return gross - sum(w.area for w in self.windows.values() if w.surface == surface_name)

    def construction_layers(self, construction_name: str) -> list[Material | NoMassMaterial]:
        """Material objects of a construction, outside -> inside."""
        return [self.materials[n] for n in self.constructions[construction_name].layers]

    @property
    def conditioned_floor_area(self) -> float:
        """Floor area of zones with a heating or cooling set point [m2]."""
        return sum(z.floor_area for z in self.zones.values() if z.conditioned)

    # -- parameters -----------------------------------------------------------------------------
    def parameters(self) -> dict[str, float]:
        """All numerical envelope parameters by stable name.

        Names: ``material/<name>/{conductivity,density,specific_heat,thickness}`` (massive
        layers), ``material/<name>/resistance`` (no-mass layers), ``window/<name>/{u_value,shgc}``,
        ``zone/<name>/infiltration_ach`` (zones without an infiltration group) and
        ``infiltration/<group>/ach`` (one per group, the mean of its zones; setting it scales
        the members in proportion).
        """
        params: dict[str, float] = {}
        for mat in self.materials.values():
            if isinstance(mat, Material):
                for attr in ("conductivity", "density", "specific_heat", "thickness"):
                    params[f"material/{mat.name}/{attr}"] = getattr(mat, attr)
            else:
                params[f"material/{mat.name}/resistance"] = mat.resistance
        for wt in self.window_types.values():
            params[f"window/{wt.name}/u_value"] = wt.u_value
            params[f"window/{wt.name}/shgc"] = wt.shgc
        groups: dict[str, list[float]] = {}
        for zone in self.zones.values():
            if zone.infiltration_group is None:
                params[f"zone/{zone.name}/infiltration_ach"] = zone.infiltration_ach
            else:
                groups.setdefault(zone.infiltration_group, []).append(zone.infiltration_ach)
        for group, values in groups.items():
            params[f"infiltration/{group}/ach"] = float(np.mean(values))
        return params

    def with_parameters(self, mapping: Mapping[str, float]) -> Building:
        """Copy of the building with some parameters changed (names as in :meth:`parameters`).

        Besides the names listed by :meth:`parameters`, ``zone/<name>/infiltration_ach`` is
        accepted for every zone (also grouped ones), the construction-level
        ``construction/<name>/{resistance,heat_capacity}`` of
        :mod:`thermocal.multizone.elements` (applied after the material-level names), and
        ``infiltration/building/factor`` [-]: every zone's air change rate (as changed by the
        other names) times this value, one parameter for a building whose file gives each zone
        its own infiltration object.  Unknown names raise :class:`ThermocalInputError` with
        close matches.
        """
        from thermocal.multizone.elements import apply_element_parameters, is_element_parameter

        elements = {k: v for k, v in mapping.items() if is_element_parameter(k)}
        if elements:
            rest = {k: v for k, v in mapping.items() if not is_element_parameter(k)}
            return apply_element_parameters(self.with_parameters(rest), elements)
        factor = mapping.get(INFILTRATION_FACTOR)
        if factor is not None:
            return self._with_infiltration_factor(
                float(factor), {k: v for k, v in mapping.items() if k != INFILTRATION_FACTOR}
            )
        materials = dict(self.materials)
        window_types = dict(self.window_types)
        zones = dict(self.zones)
        known = None
        groups = None
        for key, value in mapping.items():
            parts = str(key).split("/")
            kind, attr = parts[0], parts[-1]
            name = "/".join(parts[1:-1])
            ok = False
            if kind == "material" and name in materials:
                mat = materials[name]
                allowed = (
                    ("conductivity", "density", "specific_heat", "thickness")
                    if isinstance(mat, Material)
                    else ("resistance",)
                )
                if attr in allowed:
                    materials[name] = dataclasses.replace(mat, **{attr: value})
                    ok = True
            elif kind == "window" and name in window_types:
                wt = window_types[name]
                if attr == "u_value":
                    window_types[name] = wt.with_u_value(value)
                    ok = True
                elif attr == "shgc":
                    window_types[name] = wt.with_shgc(value)
                    ok = True
            elif kind == "zone" and name in zones and attr == "infiltration_ach":
                zones[name] = dataclasses.replace(zones[name], infiltration_ach=value)
                ok = True
            elif kind == "infiltration" and attr == "ach":
                # the group's mean rate: members scaled in proportion, their differences kept
                # (the nominal value reproduces the nominal building)
                members = [z for z in zones.values() if z.infiltration_group == name]
                groups = dict(groups if groups is not None else self._infiltration_groups())
                rates, mean = _group_base(groups.get(name), members)
                for zone in members:
                    rate = rates[zone.name] * (value / mean) if mean > 0 else value
                    zones[zone.name] = dataclasses.replace(zone, infiltration_ach=rate)
                groups[name] = (rates, mean, float(value))
                ok = bool(members)
            if not ok:
                known = known if known is not None else list(self.parameters())
                close = difflib.get_close_matches(str(key), known, n=3)
                hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
                raise ThermocalInputError(
                    f"unknown building parameter '{key}'{hint} (see Building.parameters())"
                )
        result = self.replaced(materials=materials, window_types=window_types, zones=zones)
        if groups is not None:
            result.infiltration_groups = groups
        return result

    def _infiltration_groups(self) -> dict:
        """Per infiltration group scaled so far: the members' rates and mean it was scaled
        from and the last group value (travels with the building, see :func:`_group_base`)."""
        return getattr(self, "infiltration_groups", None) or {}

    def _with_infiltration_factor(self, value: float, rest: Mapping[str, float]) -> Building:
        """``with_parameters`` with ``infiltration/building/factor``: the other names first,
        then every zone's rate = its rate before any factor x ``value`` [-].

        The rates before the factor travel with the building (``infiltration_base``, the
        factor as ``infiltration_factor``), so a
        factor applied to a building already scaled by one replaces it instead of compounding
        (a campaign changes the parameters of one simulation sample after sample); a zone rate
        set in the same call is the new rate before the factor.
        """
        if not value >= 0.0:
            raise ThermocalInputError(
                f"{INFILTRATION_FACTOR} must be a non-negative number, got {value!r}"
            )
        changed = self.with_parameters(rest) if rest else self
        stored = getattr(self, "infiltration_base", None) or {}
        base = {}
        for name, zone in changed.zones.items():
            before = self.zones[name].infiltration_ach if name in self.zones else None
            if name in stored and zone.infiltration_ach == before:
                base[name] = stored[name]  # untouched by ``rest``: the rate before the factor
            else:
                base[name] = zone.infiltration_ach
        zones = {
            name: dataclasses.replace(zone, infiltration_ach=base[name] * value)
            for name, zone in changed.zones.items()
        }
        result = changed.replaced(zones=zones)
        result.infiltration_base = base
        result.infiltration_factor = value
        return result

    def replaced(self, **changes) -> Building:
        """Copy with some fields replaced (``dataclasses.replace``), keeping the attributes
        that are not fields, such as the IDF importer's ``idf_info``."""
        changed = dataclasses.replace(self, **changes)
        fields = {f.name for f in dataclasses.fields(self)}
        for key, value in self.__dict__.items():
            if key not in fields:
                setattr(changed, key, value)
        return changed


def construction_u_value(
    layers: Sequence[Material | NoMassMaterial],
    *,
    inside_resistance: float = 0.13,
    outside_resistance: float = 0.04,
) -> float:
    """Thermal transmittance of a layered construction [W/(m2 K)].

    Parameters
    ----------
    layers : sequence of Material or NoMassMaterial
    inside_resistance : float [m2 K/W]
        Internal surface resistance (ISO 6946: 0.13 horizontal heat flow, 0.10 up, 0.17 down).
    outside_resistance : float [m2 K/W]
        External surface resistance (ISO 6946: 0.04).

    References
    ----------
    .. [1] ISO 6946:2017, Building components and building elements -- Thermal resistance and
       thermal transmittance -- Calculation methods, 6.7 and 6.8.
    """
    total = inside_resistance + outside_resistance + sum(layer.resistance for layer in layers)
    return 1.0 / total


def _group_base(stored, members) -> tuple[dict, float]:
    """The rates and mean an infiltration group is scaled from [1/h].

    The first scaling takes the members' current rates. Later ones take the same rates again
    as long as every member still has the rate the last scaling gave it: a campaign that sets
    the group sample after sample on one simulation then gives a sample's rates from the
    sample's value alone, not from the rates the previous samples left (scaling the last
    rates by a ratio drifts by round-off, so the same sample's heat differed by up to 5e-11
    depending on what its worker had run before). A member changed otherwise since (e.g.
    ``zone/<name>/infiltration_ach``) starts a new base.

    Parameters
    ----------
    stored : tuple (rates, mean, value) or None
        The group's entry in ``Building.infiltration_groups``.
    members : list of Zone
        The group's zones now.

    Returns
    -------
    rates : dict of zone name -> rate [1/h]
    mean : float [1/h]
    """
    current = {z.name: z.infiltration_ach for z in members}
    if stored is not None:
        rates, mean, value = stored
        if set(rates) == set(current) and all(
            current[n] == (rates[n] * (value / mean) if mean > 0 else value) for n in current
        ):
            return rates, mean
    mean = float(np.mean(list(current.values()))) if current else 0.0
    return current, mean
