"""Assembly of a :class:`~thermocal.multizone.model.Building` into one sparse linear network.

Nodes
-----
* one air node per zone (capacity ``rho c_p V`` times ``air_capacity_factor``);
* one massless mean-radiant ("MRT star") node per zone with at least two interior faces;
* conduction nodes of every opaque construction: each massive layer is split into ``n`` equal
  cells (:func:`cells_per_layer`), nodes sit on the cell faces (so the outermost and innermost nodes
  ARE the surface temperatures), each node carries half of the capacity of its adjacent cells; a
  no-mass layer is one cell without capacity.  An inter-zone partition gets ONE set of nodes (from
  the first of its two :class:`~thermocal.multizone.model.Surface` descriptions).  With
  ``NetworkOptions(conduction="reduced")`` the interior nodes of each construction are replaced
  by the fewest states of a balanced truncation within ``conduction_tolerance``
  (:mod:`thermocal.multizone.conduction_reduction`); the two surface nodes stay;
* two massless nodes per window (outer and inner glass face).

Links
-----
* conduction between adjacent construction nodes (``k / dx`` or ``1 / R``);
* interior convection face -> zone air (``h_c0``; TARP by tilt, see
  :func:`tarp_natural_convection`);
* interior long-wave exchange face -> MRT node (linearised, Carroll's MRT network with a
  radiosity correction for grey faces, :func:`mrt_network_conductances`);
* exterior faces -> outdoor air (convection ``h_c0`` plus the part of the long-wave exchange that
  sees ground and air) and -> sky temperature (linearised long-wave);
* ground faces -> ground temperature (a large contact conductance, i.e. a Dirichlet condition on
  the outer face);
* adiabatic faces with ``Surface.outside_at_inside`` (EnergyPlus' adiabatic and internal-mass
  surfaces): the outer face held at the inner face's temperature, one row only
  (:func:`mirrored_outside_entries`: the matrix is symmetric but for these rows);
* infiltration: zone air -> outdoor air (``rho c_p ACH V / 3600``).

Every boundary temperature and every heat source is an *input* (a column of the sparse input
matrix ``B``), so one step of the backward-Euler scheme is
``(C / dt + K) x_new = C / dt x_old + B u`` with a matrix that depends only on the building
parameters and the step: it is factorised once and reused for every step.  The time-varying and
state-dependent parts of the coefficients (wind-driven exterior convection, TARP convection,
exact sigma T^4 sky exchange, air density) are applied as explicit corrections on the right-hand
side (see :mod:`thermocal.multizone.simulation`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from thermocal.errors import ThermocalInputError
from thermocal.multizone.elements import built_surfaces
from thermocal.multizone.model import ROUGHNESS_FACTORS, Building, Material

#: Stefan-Boltzmann constant [W/(m2 K4)].
STEFAN_BOLTZMANN = 5.670374419e-8
#: Specific heat of air at constant pressure [J/(kg K)].
AIR_SPECIFIC_HEAT = 1006.0


def window_film_resistance(u_value: float) -> float:
    """Inside + outside film resistance [m2 K/W] included in a window's NFRC U-value.

    EnergyPlus' winter film correlations of the simple glazing model (Engineering Reference,
    "Simple Window Model", step 1): ``R_i = 1/(0.359073 ln U + 6.949915)`` (U < 5.85) or
    ``1/(1.788041 U - 2.886625)``, ``R_o = 1/(0.025342 U + 29.163853)``. They give 0.170 at
    U = 2.7 (the ISO 6946 0.13 + 0.04), 0.176 at U = 1.3 and 0.166 at U = 5.8, where the fixed
    0.17 left single glazing a glass resistance below its 0.007 m2 K/W.
    """
    u = float(u_value)
    if u < 5.85:
        r_in = 1.0 / (0.359073 * math.log(u) + 6.949915)
    else:
        r_in = 1.0 / (1.788041 * u - 2.886625)
    return r_in + 1.0 / (0.025342 * u + 29.163853)


def iso15099_critical_rayleigh(angle: float, sin_tilt: float) -> float:
    """ISO 15099's critical Rayleigh number of a window at ``angle`` [deg] from facing up, where
    its 15-90 degree correlation turns turbulent: ``2.5e5 (exp(0.72 angle) / sin)^(1/5)`` [-]
    (0 outside that range, unused there)."""
    if not 15.0 <= angle <= 90.0:
        return 0.0
    return 2.5e5 * (math.exp(0.72 * angle) / max(sin_tilt, 1e-6)) ** 0.2


#: MoWiTT smooth-surface forced convection ``a V^b`` (a [W/(m2 K (m/s)^b)], b [-]) as EnergyPlus
#: uses it in its DOE-2 exterior model (Engineering Reference, table "MoWiTT coefficients").
MOWITT_WINDWARD = (3.26, 0.89)
MOWITT_LEEWARD = (3.55, 0.617)
#: DOE-2 roughness multiplier of glass ("very smooth"; EnergyPlus sets it for every glazing layer).
GLASS_ROUGHNESS_FACTOR = 1.0

#: Uniform grid of mean glazing temperatures [C] on which the windows' glass-to-glass
#: conductance ratios are handed to the time-stepping kernel.
WINDOW_TEMPERATURE_GRID = np.arange(-40.0, 100.1, 5.0)

# fixed input columns
IN_TEMP_OUT, IN_TEMP_SKY, IN_TEMP_GROUND, IN_ONE = 0, 1, 2, 3
#: Input of the sun on a foundation wall above the grade [W/m2]: Kiva's two-dimensional wall
#: (``Ground::setBoundaryConditions``), the average over a vertical cylinder: the beam
#: ``DNI cos(altitude) / pi``, half the sky's diffuse and half the grade's reflection.
KIVA_WALL_SUN = "kiva_wall_sun"
N_FIXED_INPUTS = 4


@dataclass(frozen=True)
class NetworkOptions:
    """Numerical and physical options of the network.

    Parameters
    ----------
    fourier_min : float [-]
        Space-discretisation criterion: a cell is at most ``sqrt(alpha * tau / fourier_min)`` thick.
    time_scale_min : float [s]
        ``tau = max(step, time_scale_min)``: the shortest time scale the conduction model resolves.
    max_cells_per_layer : int [-]
    cells_per_layer : int or None [-]
        Fixed number of cells for every massive layer (convergence studies); overrides the
        criterion.
    interior_convection : {"tarp", "fixed", "simple"}
        TARP natural convection by tilt and heat-flow direction (state-dependent, applied as a
        correction on top of ``h_c0``), fixed ISO 6946 values, or EnergyPlus' "Simple" values
        by heat-flow direction each step (walls 3.076; horizontal faces 4.040 when the flow is
        unstable, a face warmer than the air facing up or colder facing down, else 0.948;
        tilted faces 3.870 / 2.281 W/(m2 K)).
    window_interior_convection : {"iso15099", "tarp"}
        With ``interior_convection="tarp"``: the room side of windows by ISO 15099 §8.3.2.2
        natural convection at the window's height and the site's air pressure, as EnergyPlus'
        TARP algorithm does for windows (``CalcISO15099WindowIntConvCoeff``), or by the TARP
        wall correlation as the opaque faces (the behaviour before 2026-12). ISO 15099 gives a
        coefficient that depends on the window's height and the air's density: for a 1.5 m
        window at 5 K 12 % below ``1.31 |dT|^(1/3)`` at sea level and 20 % below at 83 kPa
        (Denver), 25-45 % below for 10 m glazing; above it for windows under about 0.5 m.
    exterior_convection : {"doe2", "tarp", "mowitt", "fixed", "simple_combined"}
        Wind-dependent exterior convection as EnergyPlus names it: "doe2" (its default,
        :func:`doe2_exterior_convection`), "tarp" (:func:`tarp_exterior_convection`), "mowitt"
        (:func:`mowitt_exterior_convection`); ``h_exterior_fixed``; or EnergyPlus'
        "SimpleCombined": a combined convective + radiative coefficient ``D + E V + F V^2`` by
        roughness, all of it to the outdoor air temperature (no sky long-wave exchange) on
        opaque faces, :func:`simple_combined_exterior_coefficient`; windows take it as their
        convective film and exchange long-wave radiation besides, as EnergyPlus' window heat
        balance does.
    h_exterior_fixed : float [W/(m2 K)]
        Exterior convective coefficient of the "fixed" option.
    h_interior_fixed : float or None [W/(m2 K)]
        Interior convective coefficient of the "fixed" option; None = ISO 6946 by direction (walls
        2.5, ceilings 5.0, floors 0.7, for heat flowing from the air to colder surfaces).
    interior_longwave : bool
        Long-wave exchange between the faces of a zone.
    exact_interior_longwave : bool
        Correct the interior long-wave exchange, linearised at ``radiant_temperature``, to the
        exact ``sigma (T_f^2 + T_r^2)(T_f + T_r)`` coefficient between each face and the zone's
        radiant star node (EnergyPlus exchanges ``sigma T^4`` exactly).
    interior_longwave_exchange : {"star", "view_factors"}
        "star" (default): each face exchanges with one mean-radiant star node per zone (Carroll
        1980), so a wall also exchanges with its own co-planar windows; "view_factors": every
        pair of faces exchanges directly with EnergyPlus' grey-body exchange factors (ScriptF,
        Hottel) on its approximate view factors, which exclude co-planar faces
        (:func:`grey_exchange_factors`). :class:`~thermocal.multizone.simulation.Simulation`
        uses "view_factors" for buildings imported from an IDF file (EnergyPlus' own rule): on
        NREL's 5ZoneAirCooled at night the star makes the exterior walls' inside faces
        0.23-0.28 K colder than EnergyPlus' (they see their own cold windows), the pairwise
        exchange within 0.02 K.
    exact_sky_longwave : bool
        Correct the linearised exterior long-wave exchange to the exact ``sigma T^4`` law.
    roughness_factor : float [-]
        DOE-2 roughness multiplier of opaque exterior faces whose outermost material gives no
        ``roughness`` (1.67 "rough", 1.52 "medium rough", 1.0 "very smooth"); windows always use
        glass, 1.0.
    wind_speed_factor : float [-]
        Local (surface-height) wind speed over the weather-station wind speed (EnergyPlus,
        terrain "country", ~3 m high: ``(3/10)^0.14 = 0.845``), for surfaces that give no
        ``wind_speed_factor`` of their own (the IDF importer gives each surface the factor of
        its centroid height and the site's terrain).
    ground_contact_conductance : float [W/(m2 K)]
        Contact conductance between a ground face and the ground temperature.
    radiant_temperature : float [C]
        Mean temperature at which the interior long-wave exchange is linearised.
    conduction : {"full", "reduced"}
        "full" (default): the finite-difference nodes of every opaque construction; "reduced":
        each construction's interior nodes replaced by the fewest states of a balanced
        truncation (singular perturbation, exact steady state) whose surface temperatures stay
        within ``conduction_tolerance`` of the finite-difference model's at every frequency
        from a year to the time step's Nyquist frequency
        (:mod:`thermocal.multizone.conduction_reduction`); the surface nodes stay physical.
    conduction_tolerance : float [K/K]
        Largest change of a surface temperature per kelvin of oscillation of its surroundings
        that the "reduced" conduction model may make (surface coefficients 3-30 W/(m2 K)).
    foundation_states : int or None
        States of each floor's two-dimensional ground section after balanced truncation
        (:func:`thermocal.multizone.foundation.reduced_section`; exact at steady state; 24
        reproduce the section's 328 cells to the kWh on NREL's SingleFamilyHouse, 12 within
        0.2 %); None: every cell a node.
    """

    fourier_min: float = 1.0 / 3.0
    time_scale_min: float = 900.0
    max_cells_per_layer: int = 12
    cells_per_layer: int | None = None
    interior_convection: str = "tarp"
    window_interior_convection: str = "iso15099"
    exterior_convection: str = "doe2"
    h_exterior_fixed: float = 20.0
    h_interior_fixed: float | None = None
    interior_longwave: bool = True
    exact_interior_longwave: bool = True
    interior_longwave_exchange: str = "star"
    exact_sky_longwave: bool = True
    roughness_factor: float = 1.67
    wind_speed_factor: float = 0.845
    ground_contact_conductance: float = 1000.0
    radiant_temperature: float = 20.0
    conduction: str = "full"
    conduction_tolerance: float = 1e-3
    foundation_states: int | None = 16

    def __post_init__(self) -> None:
        if self.conduction not in ("full", "reduced"):
            raise ThermocalInputError(
                f"conduction must be 'full' or 'reduced', got {self.conduction!r}"
            )
        if not (
            isinstance(self.conduction_tolerance, int | float) and self.conduction_tolerance > 0
        ):
            raise ThermocalInputError(
                "conduction_tolerance must be a positive number [K/K] (e.g. 1e-3), got "
                f"{self.conduction_tolerance!r}"
            )
        if self.foundation_states is not None and not (
            isinstance(self.foundation_states, int) and self.foundation_states >= 1
        ):
            raise ThermocalInputError(
                "foundation_states must be a positive integer or None, got "
                f"{self.foundation_states!r}"
            )
        if self.interior_convection not in ("tarp", "fixed", "simple"):
            raise ThermocalInputError(
                "interior_convection must be 'tarp', 'fixed' or 'simple', got "
                f"{self.interior_convection!r}"
            )
        if self.window_interior_convection not in ("iso15099", "tarp"):
            raise ThermocalInputError(
                "window_interior_convection must be 'iso15099' or 'tarp', got "
                f"{self.window_interior_convection!r}"
            )
        if self.exterior_convection not in (*WIND_DRIVEN_EXTERIOR, "fixed", "simple_combined"):
            raise ThermocalInputError(
                "exterior_convection must be 'doe2', 'tarp', 'mowitt', 'fixed' or "
                f"'simple_combined', got {self.exterior_convection!r}"
            )


# ----------------------------------------------------------------------------------------------
# physics: pure functions
# ----------------------------------------------------------------------------------------------


def cells_per_layer(
    thickness: float,
    diffusivity: float,
    step: float,
    *,
    fourier_min: float = 1.0 / 3.0,
    time_scale_min: float = 900.0,
    max_cells: int = 12,
) -> int:
    """Number of equal cells for a massive layer (the space-discretisation criterion).

    A cell may be at most ``dx_max = sqrt(alpha * tau / Fo_min)`` thick, with
    ``tau = max(step, time_scale_min)``: the cell Fourier number ``alpha tau / dx^2`` is then at
    least ``Fo_min``, i.e. a cell equilibrates internally within the shortest resolved time scale
    (EnergyPlus' CondFD uses the same rule with its "space discretisation constant" 3 =
    ``1 / Fo_min``).  Bounded to ``[1, max_cells]``.

    Parameters
    ----------
    thickness : float [m]
    diffusivity : float [m2/s]
    step : float [s]
        Time step of the simulation.
    fourier_min : float [-]
    time_scale_min : float [s]
    max_cells : int [-]

    Returns
    -------
    int [-]

    References
    ----------
    .. [1] EnergyPlus Engineering Reference, "Conduction Finite Difference Solution Algorithm",
       space discretisation.
    """
    tau = max(float(step), float(time_scale_min))
    dx_max = math.sqrt(diffusivity * tau / fourier_min)
    return int(min(max(math.ceil(thickness / dx_max - 1e-9), 1), max_cells))


def tarp_natural_convection(delta_t, cos_up):
    """Interior natural convection coefficient, TARP / Walton (EnergyPlus "TARP") [W/(m2 K)].

    Parameters
    ----------
    delta_t : array-like [K]
        Surface minus air temperature.
    cos_up : array-like [-]
        Cosine of the angle between the face's normal (pointing into the air) and the upward
        vertical: +1 a floor, -1 a ceiling, 0 a wall.

    Returns
    -------
    numpy.ndarray [W/(m2 K)]
        ``1.31 |dT|^(1/3)`` for vertical faces; ``9.482 |dT|^(1/3) / (7.238 - |cos|)`` when the
        configuration is unstable (warm face facing up, cold face facing down),
        ``1.810 |dT|^(1/3) / (1.382 + |cos|)`` when stable; at least 0.1.

    References
    ----------
    .. [1] Walton, G.N. (1983), "Thermal Analysis Research Program Reference Manual", NBSIR
       83-2655; EnergyPlus Engineering Reference, "TARP algorithm".
    """
    delta_t = np.asarray(delta_t, dtype=float)
    cos_up = np.asarray(cos_up, dtype=float)
    root = np.cbrt(np.abs(delta_t))
    abs_cos = np.abs(cos_up)
    unstable = delta_t * cos_up > 0
    horizontal = np.where(
        unstable, 9.482 * root / (7.238 - abs_cos), 1.810 * root / (1.382 + abs_cos)
    )
    h = np.where(abs_cos < 1e-3, 1.31 * root, horizontal)
    return np.maximum(h, 0.1)


#: EnergyPlus "SimpleCombined" exterior coefficients D, E, F by roughness (DOE-2 roughness
#: multiplier -> coefficients): EnergyPlus Engineering Reference, "Simple Combined" table (ASHRAE
#: Handbook of Fundamentals 1989)
SIMPLE_COMBINED_COEFFICIENTS = {
    2.17: (11.58, 5.894, 0.0),  # VeryRough
    1.67: (12.49, 4.065, 0.028),  # Rough
    1.52: (10.79, 4.192, 0.0),  # MediumRough
    1.13: (8.23, 4.0, -0.057),  # MediumSmooth
    1.11: (10.22, 3.1, 0.0),  # Smooth
    1.0: (8.23, 3.33, -0.036),  # VerySmooth
}


def simple_combined_exterior_coefficient(wind_speed, roughness_factor):
    """EnergyPlus' "SimpleCombined" exterior coefficient ``D + E V + F V^2`` [W/(m2 K)].

    Parameters
    ----------
    wind_speed : array-like [m/s]
        Local wind speed at the surface.
    roughness_factor : array-like [-]
        DOE-2 roughness multiplier naming the roughness class (2.17 very rough ... 1.0 very
        smooth); other values take the nearest class.

    References
    ----------
    .. [1] EnergyPlus Engineering Reference, "Outside Surface Heat Balance: Simple Combined".
    """
    classes = np.array(sorted(SIMPLE_COMBINED_COEFFICIENTS))
    rough = np.asarray(roughness_factor, dtype=float)
    nearest = classes[np.argmin(np.abs(rough[..., None] - classes), axis=-1)]
    table = np.array([SIMPLE_COMBINED_COEFFICIENTS[c] for c in classes])
    index = np.searchsorted(classes, nearest)
    d, e, f = table[index, 0], table[index, 1], table[index, 2]
    v = np.maximum(np.asarray(wind_speed, dtype=float), 0.0)
    return d + e * v + f * v**2


def doe2_exterior_convection(wind_speed, windward, *, h_natural, roughness_factor=1.67):
    """Exterior convection coefficient of the DOE-2 model [W/(m2 K)].

    ``h = h_n + R_f (sqrt(h_n^2 + (a V^b)^2) - h_n)``: the smooth-glass forced term of the MoWiTT
    correlation, ``a, b = 3.26, 0.89`` (windward) or ``3.55, 0.617`` (leeward), scaled by the
    roughness multiplier ``R_f``.

    Parameters
    ----------
    wind_speed : array-like [m/s]
        Local wind speed at the surface.
    windward : array-like of bool
    h_natural : array-like [W/(m2 K)]
        Natural convection part (TARP).
    roughness_factor : array-like [-]
        1.67 "rough", 1.52 "medium rough", 1.13 "medium smooth", 1.11 "smooth", 1.0 "very
        smooth" (glass).

    Returns
    -------
    numpy.ndarray [W/(m2 K)]

    References
    ----------
    .. [1] EnergyPlus Engineering Reference, "Outside Surface Heat Balance: DOE-2 model" and
       table "MoWiTT coefficients" (the values EnergyPlus uses in ``CalcDOE2Windward`` /
       ``CalcDOE2Leeward`` through ``CalcMoWITTForcedWindward`` / ``...Leeward``);
       Yazdanian, M. and Klems, J.H. (1994), ASHRAE Transactions 100(1).
    """
    h_glass = np.sqrt(h_natural**2 + mowitt_forced(wind_speed, windward) ** 2)
    return h_natural + roughness_factor * (h_glass - h_natural)


def mowitt_forced(wind_speed, windward):
    """MoWiTT smooth-surface forced term ``a V^b`` [W/(m2 K)], windward or leeward."""
    wind_speed = np.maximum(np.asarray(wind_speed, dtype=float), 0.0)
    a = np.where(windward, MOWITT_WINDWARD[0], MOWITT_LEEWARD[0])
    b = np.where(windward, MOWITT_WINDWARD[1], MOWITT_LEEWARD[1])
    return a * wind_speed**b


#: TARP forced-convection constant of ``2.537 W_f R_f sqrt(P V / A)`` (Sparrow, Ramsey and
#: Mass 1979, as EnergyPlus' "TARP" outside algorithm uses it).
TARP_FORCED = 2.537
#: MoWiTT natural-convection constant ``C_t`` [W/(m2 K^(4/3))] (Yazdanian and Klems 1994).
MOWITT_NATURAL = 0.84
#: Exterior algorithms whose coefficient follows the wind each step.
WIND_DRIVEN_EXTERIOR = ("doe2", "tarp", "mowitt")
#: Surface-air temperature difference at which the natural parts are evaluated [K].
NOMINAL_EXTERIOR_DELTA_T = 3.0


def tarp_exterior_convection(
    wind_speed, windward, *, h_natural, perimeter_over_area, roughness_factor=1.67
):
    """Exterior convection coefficient of EnergyPlus' "TARP" outside algorithm [W/(m2 K)].

    ``h = h_n + 2.537 W_f R_f sqrt(P V / A)``, ``W_f`` 1 windward and 0.5 leeward.

    Parameters
    ----------
    wind_speed : array-like [m/s]
        Local wind speed at the surface.
    windward : array-like of bool
    h_natural : array-like [W/(m2 K)]
        Natural convection part (TARP / Walton).
    perimeter_over_area : array-like [1/m]
        Perimeter over area of the surface.
    roughness_factor : array-like [-]
        Roughness multiplier (2.17 very rough ... 1.0 very smooth).

    References
    ----------
    .. [1] EnergyPlus Engineering Reference, "Outside Surface Heat Balance: TARP algorithm";
       Sparrow, E.M., Ramsey, J.W. and Mass, E.A. (1979), "Effect of finite width on heat
       transfer and fluid flow about an inclined rectangular plate", J. Heat Transfer 101.
    """
    wind_speed = np.maximum(np.asarray(wind_speed, dtype=float), 0.0)
    w_f = np.where(windward, 1.0, 0.5)
    forced = TARP_FORCED * w_f * roughness_factor * np.sqrt(perimeter_over_area * wind_speed)
    return h_natural + forced


def mowitt_exterior_convection(wind_speed, windward, *, delta_t=NOMINAL_EXTERIOR_DELTA_T):
    """Exterior convection coefficient of EnergyPlus' "MoWiTT" outside algorithm [W/(m2 K)].

    ``h = sqrt((C_t dT^(1/3))^2 + (a V^b)^2)`` with ``C_t = 0.84`` and the smooth-surface
    ``a, b`` of :data:`MOWITT_WINDWARD` / :data:`MOWITT_LEEWARD` (no roughness: MoWiTT was
    measured on smooth glazing).

    Parameters
    ----------
    wind_speed : array-like [m/s]
        Local wind speed at the surface.
    windward : array-like of bool
    delta_t : float [K]
        Surface-air temperature difference of the natural part.

    References
    ----------
    .. [1] Yazdanian, M. and Klems, J.H. (1994), "Measurement of the exterior convective film
       coefficient for windows in low-rise buildings", ASHRAE Transactions 100(1);
       EnergyPlus Engineering Reference, "Outside Surface Heat Balance: MoWiTT model".
    """
    natural = MOWITT_NATURAL * abs(delta_t) ** (1.0 / 3.0)
    return np.sqrt(natural**2 + mowitt_forced(wind_speed, windward) ** 2)


def exterior_convection(
    algorithm, wind_speed, windward, *, h_natural, roughness_factor, perimeter_over_area
):
    """Exterior convection coefficient of a wind-driven algorithm [W/(m2 K)].

    Parameters
    ----------
    algorithm : {"doe2", "tarp", "mowitt"}
    wind_speed : array-like [m/s]
        Local wind speed at the surface.
    windward : array-like of bool
    h_natural : array-like [W/(m2 K)]
        Natural part (TARP) of "doe2" and "tarp".
    roughness_factor : array-like [-]
    perimeter_over_area : array-like [1/m]
        Used by "tarp".
    """
    if algorithm == "doe2":
        return doe2_exterior_convection(
            wind_speed, windward, h_natural=h_natural, roughness_factor=roughness_factor
        )
    if algorithm == "tarp":
        return tarp_exterior_convection(
            wind_speed,
            windward,
            h_natural=h_natural,
            perimeter_over_area=perimeter_over_area,
            roughness_factor=roughness_factor,
        )
    if algorithm == "mowitt":
        return mowitt_exterior_convection(wind_speed, windward)
    raise ValueError(f"not a wind-driven exterior algorithm: {algorithm!r}")


def _wind_factor(surface, options) -> float:
    """Local over station wind speed of a surface (its own, or the options' default; 0 for a
    surface not exposed to the wind, as EnergyPlus' NoWind) [-]."""
    if not surface.wind_exposed:
        return 0.0
    if surface.wind_speed_factor is not None:
        return float(surface.wind_speed_factor)
    return float(options.wind_speed_factor)


def mrt_network_conductances(area, emissivity, h_black):
    """Conductances of each face to the zone's mean-radiant-temperature star node [W/K].

    Carroll's MRT network: face ``i`` sees the rest of the enclosure through the factor
    ``F_i = 1 / (1 - A_i F_i / sum_j A_j F_j)`` (solved by fixed-point iteration), which removes the
    self-viewing of large faces; a grey face adds the radiosity resistance
    ``(1 - eps_i) / (eps_i A_i h_b)``.

    Parameters
    ----------
    area : array-like [m2]
    emissivity : array-like [-]
    h_black : float [W/(m2 K)]
        Linearised black-body coefficient ``4 sigma T^3``.

    Returns
    -------
    numpy.ndarray [W/K]

    References
    ----------
    .. [1] Carroll, J.A. (1980), "An MRT method of computing radiant energy exchange in rooms",
       Proc. 2nd Systems Simulation and Economic Analysis Conference, San Diego.
    .. [2] Walton, G.N. (1980), "A new algorithm for radiant interchange in room loads
       calculations", ASHRAE Transactions 86(2).
    """
    area = np.asarray(area, dtype=float)
    emissivity = np.clip(np.asarray(emissivity, dtype=float), 0.05, 1.0)
    factor = np.ones_like(area)
    for _ in range(50):
        total = np.sum(area * factor)
        new = 1.0 / np.maximum(1.0 - area * factor / total, 1e-6)
        if np.max(np.abs(new - factor)) < 1e-10:
            factor = new
            break
        factor = new
    resistance = 1.0 / (area * factor * h_black) + (1.0 - emissivity) / (
        emissivity * area * h_black
    )
    return 1.0 / resistance


def radiant_gain_shares(face_zone, area, emissivity, n_zones):
    """Share of its zone's radiant internal gains that each interior face absorbs [-].

    EnergyPlus distributes the long-wave radiant part of internal gains over a zone's surfaces
    in proportion to area times interior thermal absorptance (``QL * TMULT * ITABSF`` with
    ``TMULT = 1 / sum(A ITABSF)``); the shares of a zone's faces sum to one.

    Parameters
    ----------
    face_zone : ndarray of int (n_faces,)
        Zone index of each interior face.
    area : ndarray (n_faces,) [m2]
    emissivity : ndarray (n_faces,) [-]
        Interior thermal emissivity (= absorptance) of each face.
    n_zones : int

    Returns
    -------
    ndarray (n_faces,) [-]

    References
    ----------
    EnergyPlus Engineering Reference, "Internal Long-Wave Radiation Exchange" and
    ``HeatBalanceIntRadExchange``/``InternalHeatGains`` (distribution of radiant gains).
    """
    face_zone = np.asarray(face_zone, dtype=np.int64)
    weight = np.asarray(area, dtype=float) * np.asarray(emissivity, dtype=float)
    total = np.bincount(face_zone, weights=weight, minlength=n_zones)
    denominator = total[face_zone]
    return np.divide(weight, denominator, out=np.zeros_like(weight), where=denominator > 0)


#: Conductance [W/(m2 K)] that holds the outside face of an ``outside_at_inside`` surface at its
#: inside face's temperature: the two differ by the construction's outside flux over it (below
#: 1e-4 K for the outpatient's 10 cm concrete slabs at 5-minute steps).
MIRROR_CONDUCTANCE = 1.0e6


def mirrored_outside_entries(outside, inside, area):
    """Matrix entries that hold a construction's outside face at its inside face's temperature.

    EnergyPlus' adiabatic surfaces, surfaces whose outside boundary is the surface itself and
    ``InternalMass`` objects take the inside face temperature of the same surface as their
    outside face temperature (EnergyPlus Engineering Reference, "Outside Surface Heat Balance",
    inter-zone surfaces: the outside face temperature is the inside face temperature of the
    other side's surface, here the surface itself): the construction is heated and cooled
    through both faces, and only the inside face's heat enters the zone's balance. In the
    network the outside node's row gets ``G (T_out - T_in)`` with ``G`` =
    :data:`MIRROR_CONDUCTANCE` x ``area`` and the inside node's row nothing: the heat that
    holds the outside face comes from no zone (the matrix is no longer symmetric).

    Parameters
    ----------
    outside, inside : int
        Outside and inside face nodes of the construction.
    area : float [m2]
        Net area of the surface.

    Returns
    -------
    rows, cols : tuple of int
    values : tuple of float [W/K]
    """
    g = MIRROR_CONDUCTANCE * float(area)
    return (outside, outside), (outside, inside), (g, -g)


def air_density(pressure=101325.0, temperature=20.0):
    """Dry-air density from the ideal-gas law [kg/m3].

    Parameters
    ----------
    pressure : array-like [Pa]
    temperature : array-like [C]
    """
    return np.asarray(pressure, dtype=float) / (287.05 * (np.asarray(temperature) + 273.15))


def pressure_at_altitude(altitude):
    """Standard-atmosphere pressure at an altitude [Pa] (ISO 2533).

    Parameters
    ----------
    altitude : float [m]
    """
    return 101325.0 * (1.0 - 2.25577e-5 * float(altitude)) ** 5.25588


# ----------------------------------------------------------------------------------------------
# construction templates
# ----------------------------------------------------------------------------------------------


@dataclass
class ConstructionTemplate:
    """Per-m2 conductances and node capacities of a construction (outside node first, inside
    node last).

    ``matrix`` is None for the finite-difference chain (``conductance`` between successive
    nodes); for a reduced model (``NetworkOptions.conduction = "reduced"``) it is the symmetric
    conductance matrix of the nodes with zero row sums, and ``conductance`` holds the
    finite-difference chain it replaces.
    """

    conductance: np.ndarray  # (n_cells,) [W/(m2 K)]
    capacity: np.ndarray  # (n_nodes,) [J/(m2 K)]
    resistance: float  # [m2 K/W], surface to surface
    matrix: np.ndarray | None = None  # (n_nodes, n_nodes) [W/(m2 K)]
    n_full: int = 0  # finite-difference nodes of the construction
    #: node at the outside face of each layer (finite-difference chain; empty when reduced)
    layer_nodes: tuple[int, ...] = ()

    @functools.cached_property
    def links(self) -> list[tuple[int, int, float]]:
        """Node pairs (i < j) and their conductance [W/(m2 K)] (negative ones possible in a
        reduced model)."""
        if self.matrix is None:
            return [(c, c + 1, float(g)) for c, g in enumerate(self.conductance)]
        rows, cols = np.nonzero(np.triu(self.matrix, 1))
        return [
            (int(i), int(j), float(-self.matrix[i, j])) for i, j in zip(rows, cols, strict=True)
        ]

    @functools.cached_property
    def link_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:attr:`links` as arrays: nodes ``i``, ``j`` and conductance [W/(m2 K)]."""
        links = self.links
        return (
            np.asarray([link[0] for link in links], dtype=np.int64),
            np.asarray([link[1] for link in links], dtype=np.int64),
            np.asarray([link[2] for link in links], dtype=float),
        )


def _chain_links(chains) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The conduction links of many surfaces at once, surface after surface in template order.

    Parameters
    ----------
    chains : sequence of (ConstructionTemplate, int, float)
        Each surface's template, its first node and its net area [m2].

    Returns
    -------
    i, j : ndarray of int
        The linked nodes.
    g : ndarray [W/K]
        Their conductances (per-m2 conductance x area).
    """
    if not chains:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, np.zeros(0)
    local = [tpl.link_arrays for tpl, _, _ in chains]
    counts = [len(arrays[0]) for arrays in local]
    first = np.repeat(np.asarray([c[1] for c in chains], dtype=np.int64), counts)
    area = np.repeat(np.asarray([c[2] for c in chains], dtype=float), counts)
    return (
        first + np.concatenate([a[0] for a in local]),
        first + np.concatenate([a[1] for a in local]),
        np.concatenate([a[2] for a in local]) * area,
    )


def _zone_members(face_zone: np.ndarray, n_zones: int) -> list[np.ndarray]:
    """The faces of each zone, ascending (``np.flatnonzero(face_zone == z)`` for every zone)."""
    order = np.argsort(face_zone, kind="stable")
    bounds = np.searchsorted(face_zone[order], np.arange(n_zones + 1))
    return [order[bounds[z] : bounds[z + 1]] for z in range(n_zones)]


class _Triplets:
    """The (row, column, value) triplets of a sparse matrix in the order they are added: one at a
    time into the lists ``rows``, ``cols``, ``vals`` (pending), many at once as arrays.

    The order matters: the conversion to a compressed matrix sums the values of a repeated
    position in an order that depends on the positions of each column's triplets.
    """

    def __init__(self) -> None:
        self.rows: list[int] = []
        self.cols: list[int] = []
        self.vals: list[float] = []
        self._blocks: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

    def flush(self) -> None:
        """Move the pending single triplets into a block."""
        if self.rows:
            self._blocks.append(
                (
                    np.asarray(self.rows, dtype=np.int64),
                    np.asarray(self.cols, dtype=np.int64),
                    np.asarray(self.vals, dtype=float),
                )
            )
            self.rows.clear()
            self.cols.clear()
            self.vals.clear()

    def add_links(self, i, j, g, *, before_pending: bool = False) -> None:
        """Conductances ``g`` [W/K] between nodes ``i`` and ``j`` (arrays): per link the
        triplets ``(i, i, g), (j, j, g), (i, j, -g), (j, i, -g)``, as one link at a time.

        ``before_pending``: the block goes before the pending single triplets.
        """
        i = np.asarray(i, dtype=np.int64)
        j = np.asarray(j, dtype=np.int64)
        g = np.asarray(g, dtype=float)
        if not before_pending:
            self.flush()
        self._blocks.append(
            (
                np.stack([i, j, i, j], axis=1).ravel(),
                np.stack([i, j, j, i], axis=1).ravel(),
                np.stack([g, g, -g, -g], axis=1).ravel(),
            )
        )

    def arrays(self) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
        """``(values, (rows, cols))`` of every triplet, as ``scipy.sparse.coo_matrix`` takes."""
        self.flush()
        if not self._blocks:
            return np.zeros(0), (np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64))
        rows, cols, vals = (np.concatenate(parts) for parts in zip(*self._blocks, strict=True))
        return vals, (rows, cols)


def construction_template(
    layers, step: float, options: NetworkOptions, cache: dict | None = None
) -> ConstructionTemplate:
    """Discretise a construction (layers outside -> inside) into cells, reduced if
    ``options.conduction`` is "reduced".

    Parameters
    ----------
    layers : sequence of Material or NoMassMaterial
    step : float [s]
    options : NetworkOptions
    cache : dict, optional
        Reduced models by finite-difference chain, step and tolerance (reused between
        assemblies).
    """
    conductance: list[float] = []
    capacity = [0.0]
    layer_nodes = []
    for layer in layers:
        layer_nodes.append(len(capacity) - 1)
        if isinstance(layer, Material):
            if options.cells_per_layer is not None:
                n = int(options.cells_per_layer)
            else:
                n = cells_per_layer(
                    layer.thickness,
                    layer.diffusivity,
                    step,
                    fourier_min=options.fourier_min,
                    time_scale_min=options.time_scale_min,
                    max_cells=options.max_cells_per_layer,
                )
            dx = layer.thickness / n
            half = 0.5 * layer.density * layer.specific_heat * dx
            for _ in range(n):
                conductance.append(layer.conductivity / dx)
                capacity[-1] += half
                capacity.append(half)
        else:
            conductance.append(1.0 / layer.resistance)
            capacity.append(0.0)
    conductance_arr = np.asarray(conductance)
    capacity_arr = np.asarray(capacity)
    template = ConstructionTemplate(
        conductance=conductance_arr,
        capacity=capacity_arr,
        resistance=float(np.sum(1.0 / conductance_arr)),
        n_full=len(capacity_arr),
        layer_nodes=tuple(layer_nodes),
    )
    if options.conduction == "full":
        return template
    from thermocal.multizone.conduction_reduction import reduce_construction

    key = (
        "reduced_conduction",
        conductance_arr.tobytes(),
        capacity_arr.tobytes(),
        float(step),
        float(options.conduction_tolerance),
    )
    cache = {} if cache is None else cache
    if key not in cache:
        cache[key] = reduce_construction(
            conductance_arr, capacity_arr, step, options.conduction_tolerance
        )
    reduced = cache[key]
    return dataclasses.replace(
        template, capacity=reduced.capacity, matrix=reduced.conductance, layer_nodes=()
    )


# ----------------------------------------------------------------------------------------------
# the network
# ----------------------------------------------------------------------------------------------


@dataclass(eq=False)
class GroundFaces:
    """The foundations' exterior faces (Kiva's grade, the foundation wall's face above it, a
    basement's walls above it), whose convection and long-wave the time loop corrects beyond
    the matrix's constant coefficients, lagged by a step, as an exterior face's
    (:func:`thermocal.multizone._kernel.exterior_excess`).

    A face's temperature is an output of its ground section: the sum of ``out_val`` times the
    nodes ``out_idx`` (CSR rows ``out_ptr``) and ``u_val`` times the input columns ``u_idx``
    (``u_ptr``) at the previous step (a reduced section's quasi-static states); its correction
    per m2 [W/m2] is written into the input column ``column``, which spreads it over the face's
    cells as the face's absorbed sun.
    """

    names: list[str]
    column: np.ndarray  # (g,) int64
    out_ptr: np.ndarray
    out_idx: np.ndarray
    out_val: np.ndarray
    u_ptr: np.ndarray
    u_idx: np.ndarray
    u_val: np.ndarray
    tilt: np.ndarray  # [deg]: 0 the grade, 90 a wall
    roughness: np.ndarray  # DOE-2 roughness multiplier [-]
    wind_factor: np.ndarray  # wind at the grade's roughness height over the station's [-]
    leeward_mean: np.ndarray  # bool: the forced term the mean of MoWiTT's windward and leeward
    hc0: np.ndarray  # the matrix's convection coefficient [W/(m2 K)]
    emissivity: np.ndarray
    view_sky: np.ndarray  # share of the long-wave to the sky (the rest to the outdoor air)
    capacity: np.ndarray  # the face's cells' capacity per m2 [J/(m2 K)] (the lag's bound)
    hr0: float  # the matrix's long-wave coefficient per unit emissivity [W/(m2 K)]

    def __eq__(self, other) -> bool:
        if not isinstance(other, GroundFaces):
            return NotImplemented
        return all(
            np.array_equal(getattr(self, f.name), getattr(other, f.name))
            for f in dataclasses.fields(self)
        )

    @staticmethod
    def empty() -> GroundFaces:
        """No ground faces (a building without foundations)."""
        i0, f0 = np.zeros(0, dtype=np.int64), np.zeros(0)
        return GroundFaces(
            [], i0, np.zeros(1, dtype=np.int64), i0, f0, np.zeros(1, dtype=np.int64), i0, f0,
            f0, f0, f0, np.zeros(0, dtype=bool), f0, f0, f0, f0, 0.0,
        )  # fmt: skip


@dataclass
class Network:
    """The assembled network (see the module docstring). Node temperatures in C.

    Attributes ending in ``_node`` are node indices; face arrays describe every face seen from a
    zone (``face_*``) and every face exposed to the outdoors (``ext_*``).
    """

    n_nodes: int
    foundation_nodes: np.ndarray  # nodes of the foundations' ground sections (int)
    capacity: np.ndarray  # (n,) [J/K]
    # K (n, n) [W/K]: Laplacian + boundary diagonal, symmetric but for the rows of the
    # outside faces held at their inside face's temperature (mirrored_outside_entries)
    conductance: sp.csc_matrix
    inputs: sp.csr_matrix  # B (n, n_inputs)
    input_names: list[str]
    zone_names: list[str]
    air_node: np.ndarray  # (nz,)
    mrt_node: np.ndarray  # (nz,), -1 when none
    # interior faces
    face_names: list[str]
    face_node: np.ndarray
    face_zone: np.ndarray
    face_area: np.ndarray
    face_cos_up: np.ndarray
    face_h0: np.ndarray
    face_hmax: np.ndarray
    face_capacity: np.ndarray  # capacity of the face node per m2 [J/(m2 K)]
    face_is_window: np.ndarray
    face_mrt_conductance: np.ndarray  # [W/K] face -> radiant star node at radiant_temperature
    face_mrt_node: np.ndarray  # radiant star node of the face's zone (-1: none)
    face_radiant_share: np.ndarray  # share of its zone's radiant internal gains [-]
    h_black: float  # 4 sigma T^3 at radiant_temperature [W/(m2 K)]
    # exterior faces
    ext_names: list[str]
    ext_node: np.ndarray
    ext_area: np.ndarray
    ext_tilt: np.ndarray
    ext_azimuth: np.ndarray
    ext_emissivity: np.ndarray
    ext_view_sky: np.ndarray  # F_sky * beta (sees the sky temperature)
    ext_view_air: np.ndarray  # F_ground + F_sky (1 - beta) (sees outdoor-air temperature)
    ext_h_natural: np.ndarray
    ext_roughness: np.ndarray  # DOE-2 roughness multiplier [-]
    ext_wind_factor: np.ndarray  # local over station wind speed [-]
    ext_perimeter_over_area: np.ndarray  # [1/m]
    ext_hc0: np.ndarray
    ext_hr0: float
    ext_capacity: np.ndarray  # node capacity per m2 [J/(m2 K)]
    # zones
    zone_infiltration: np.ndarray  # [W/K] at reference density
    zone_volume: np.ndarray
    reference_density: float
    # solar inputs
    orientation_inputs: dict = field(default_factory=dict)  # (tilt, az) -> input col (opaque)
    window_inputs: dict = field(default_factory=dict)  # (wt, tilt, az) -> 4 input cols
    #: window -> (beam input col, glazed area [m2], [(face, input col)]): the beam of windows
    #: whose interior distribution follows the sun (EnergyPlus' FullInteriorAndExterior)
    window_beam_targets: dict = field(default_factory=dict)
    #: the foundations' exterior faces corrected each step (:class:`GroundFaces`)
    ground_faces: GroundFaces = field(default_factory=GroundFaces.empty)
    zone_transmitted: sp.csr_matrix | None = None  # (nz, n_inputs): transmitted solar per zone
    # windows: glass-face nodes, matrix conductance [W/K] and its ratio on WINDOW_TEMPERATURE_GRID
    ext_is_window: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    window_outer: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    window_inner: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    window_conductance: np.ndarray = field(default_factory=lambda: np.zeros(0))
    window_conductance_ratio: np.ndarray = field(
        default_factory=lambda: np.ones((0, len(WINDOW_TEMPERATURE_GRID)))
    )
    # pairwise interior long-wave (interior_longwave_exchange "view_factors"): face nodes and
    # conductance at radiant_temperature [W/K]
    lw_pair_a: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    lw_pair_b: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    lw_pair_g: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: per face: (window height [m], tilt [deg], sin tilt, the critical Rayleigh numbers at the
    #: tilt and at 180 - tilt) of the windows whose room side uses ISO 15099 convection;
    #: height 0 for the other faces
    face_iso: np.ndarray = field(default_factory=lambda: np.zeros((0, 5)))

    def system_matrix(self, step: float) -> sp.csc_matrix:
        """``C / dt + K`` [W/K]."""
        return (self.conductance + sp.diags(self.capacity / step)).tocsc()


def assemble(
    building: Building,
    step: float,
    *,
    options: NetworkOptions | None = None,
    mean_wind_speed: float = 3.0,
    mean_outdoor_temperature: float = 10.0,
    pressure: float | None = None,
    cache: dict | None = None,
    gain_input_zones=(),
    own_solar_inputs=frozenset(),
    sky_view_ratio=None,
    interior_beam=None,
) -> Network:
    """Assemble the sparse network of a building for a time step.

    Parameters
    ----------
    building : Building
    step : float [s]
        Simulation time step (sets the discretisation, :func:`cells_per_layer`).
    options : NetworkOptions, optional
    mean_wind_speed : float [m/s]
        Station wind speed at which the matrix part of the exterior convection is evaluated.
    mean_outdoor_temperature : float [C]
        Temperature at which the exterior long-wave exchange and the infiltration air density are
        linearised.
    pressure : float or None [Pa]
        Mean atmospheric pressure; None = standard atmosphere at the site altitude.
    cache : dict, optional
        Reused between assemblies of the same geometry (parameter changes): radiation network
        conductances and window diffuse transmittances.
    gain_input_zones : sequence of str
        Zones with time-varying internal gains: each gets two input columns,
        ``gains_convective/<zone>`` (into the air) and ``gains_radiant/<zone>`` (shared by the
        zone's surfaces by area) [W]; give such zones ``internal_gains = 0``.
    own_solar_inputs : set of str
        Surfaces and windows (names) whose solar inputs get their own columns (keys with the
        name appended) instead of one per orientation: receivers of shadows.
    sky_view_ratio : dict of str -> float, optional [-]
        Exterior surfaces and windows (names) whose sky view is reduced by shading surfaces:
        the ratio of shaded to unshaded isotropic sky diffuse, which multiplies the sky's share
        of their long-wave exchange as in EnergyPlus (the rest is exchanged at the outdoor-air
        temperature).
    interior_beam : dict of str -> sequence of str, optional
        Windows (names) whose transmitted beam lands where the sun puts it (EnergyPlus'
        ``FullInteriorAndExterior``): the faces of their zone it can reach. Each (window, face)
        gets an input column [W of transmitted beam landing on the face], absorbed there and
        reflected as the floor's share is; the caller sets it per step
        (``Network.window_beam_targets``). Other windows put their beam on the floor.
    """
    options = options or NetworkOptions()
    cache = {} if cache is None else cache
    window_area_of: dict[str, float] = {}
    for window in building.windows.values():
        window_area_of[window.surface] = window_area_of.get(window.surface, 0.0) + window.area
    zones = list(building.zones.values())
    zone_index = {z.name: i for i, z in enumerate(zones)}
    nz = len(zones)

    cap: list[float] = [0.0] * nz  # air nodes first
    cap_blocks: list[np.ndarray] = []  # then the capacities of every later block of nodes
    n_nodes = [nz]
    entries = _Triplets()  # the conductance matrix K
    rows, cols, vals = entries.rows, entries.cols, entries.vals
    b_rows: list[int] = []
    b_cols: list[int] = []
    b_vals: list[float] = []
    input_names = ["temp_out", "temp_sky", "temp_ground", "one"]

    def new_nodes(capacities) -> int:
        first = n_nodes[0]
        cap_blocks.append(np.asarray(capacities, dtype=float))
        n_nodes[0] += len(cap_blocks[-1])
        return first

    def link(i: int, j: int, g: float) -> None:
        rows.extend((i, j, i, j))
        cols.extend((i, j, j, i))
        vals.extend((g, g, -g, -g))

    def boundary(i: int, column: int, g: float) -> None:
        rows.append(i)
        cols.append(i)
        vals.append(g)
        b_rows.append(i)
        b_cols.append(column)
        b_vals.append(g)

    def source(i: int, column: int, coefficient: float) -> None:
        b_rows.append(i)
        b_cols.append(column)
        b_vals.append(coefficient)

    def new_input(name: str) -> int:
        input_names.append(name)
        return len(input_names) - 1

    def entry(i: int, j: int, value: float) -> None:  # one entry of K
        rows.append(i)
        cols.append(j)
        vals.append(value)

    # zone air capacity and infiltration
    if pressure is None:
        pressure = pressure_at_altitude(building.location.altitude)
    rho_ref = float(air_density(pressure, mean_outdoor_temperature))
    rho_in = float(air_density(pressure, 20.0))
    zone_volume = np.array([z.volume for z in zones])
    zone_infiltration = np.array(
        [rho_ref * AIR_SPECIFIC_HEAT * z.infiltration_ach * z.volume / 3600.0 for z in zones]
    )
    for i, z in enumerate(zones):
        cap[i] = rho_in * AIR_SPECIFIC_HEAT * z.volume * z.air_capacity_factor
        if zone_infiltration[i] > 0:
            boundary(i, IN_TEMP_OUT, zone_infiltration[i])
    # heat delivered to the zone air (ideal loads, given heat) enters the air node directly in the
    # time loop, so it needs no input column

    # ---- opaque constructions --------------------------------------------------------------
    templates: dict[str, ConstructionTemplate] = {}

    def template(name: str) -> ConstructionTemplate:
        if name not in templates:
            templates[name] = construction_template(
                building.construction_layers(name), step, options, cache
            )
        return templates[name]

    # interior faces (seen from a zone)
    f_name, f_node, f_zone, f_area, f_cos, f_eps, f_alpha, f_cap, f_win = ([] for _ in range(9))
    f_window_tau: list[float] = []
    # face plane (tilt, azimuth of the outward normal of the surface [deg]) and internal mass flag
    # (approximate solar view factors), windows' back-side diffuse absorptance (outer, inner pane)
    f_tilt: list[float] = []
    f_az: list[float] = []
    f_mass: list[bool] = []
    f_back: list[tuple[float, float]] = []
    # exterior faces
    e_name, e_node, e_area, e_tilt, e_az, e_eps, e_alpha, e_cap, e_sun, e_rough = (
        [] for _ in range(10)
    )
    e_wind: list[float] = []  # local over station wind speed [-]
    e_win: list[bool] = []  # a window's outer glass face
    e_pa: list[float] = []  # perimeter over area [1/m]
    surface_nodes: dict[str, tuple[int, int]] = {}  # name -> (outside node, inside node)
    foundation_nodes: list[np.ndarray] = []  # the nodes of each foundation's ground section
    pending_foundations: list[tuple] = []  # added once every wall's outside node is known
    foundation_walls = {w for f in building.foundations.values() for w, _ in f.walls}

    def foundation_sun() -> int:
        # the grade's sun: the horizontal plane's irradiance (shared with horizontal faces)
        key = (0.0, 0.0)
        if key not in orientation_inputs:
            orientation_inputs[key] = new_input("poa_global/0.0/0.0")
        return orientation_inputs[key]

    orientation_inputs: dict[tuple[float, ...], int] = {}
    wall_sun_input: list[int] = []
    ground_faces: list[dict] = []

    def foundation_wall_sun() -> int:
        # a foundation wall's sun above the grade: Kiva's vertical cylinder (KIVA_WALL_SUN),
        # computed from the horizontal plane's components
        foundation_sun()
        if not wall_sun_input:
            wall_sun_input.append(new_input(KIVA_WALL_SUN))
        return wall_sun_input[0]

    def face_props(surface, layers, inside: bool):
        mat = layers[-1] if inside else layers[0]
        alpha = surface.solar_absorptance_inside if inside else surface.solar_absorptance_outside
        eps = surface.emissivity_inside if inside else surface.emissivity_outside
        return (
            mat.solar_absorptance if alpha is None else alpha,
            mat.thermal_absorptance if eps is None else eps,
        )

    # the conduction links of every surface go in one block, before the loop's single entries
    # (each surface's own nodes get their links first, as one link at a time did)
    entries.flush()
    chains: list[tuple[ConstructionTemplate, int, float]] = []
    layers_of: dict[str, list] = {}
    for surface in built_surfaces(building.surfaces.values()):  # a pair once, from its first
        if surface.construction not in layers_of:
            layers_of[surface.construction] = building.construction_layers(surface.construction)
        layers = layers_of[surface.construction]
        tpl = template(surface.construction)
        area = surface.area - window_area_of.get(surface.name, 0.0)
        first = new_nodes(tpl.capacity * area)
        chains.append((tpl, first, area))
        outside, inside = first, first + len(tpl.capacity) - 1
        surface_nodes[surface.name] = (outside, inside)
        alpha_in, eps_in = face_props(surface, layers, inside=True)
        f_name.append(surface.name)
        f_node.append(inside)
        f_zone.append(zone_index[surface.zone])
        f_area.append(area)
        f_cos.append(-math.cos(math.radians(surface.tilt)))
        f_eps.append(eps_in)
        f_alpha.append(alpha_in)
        f_cap.append(tpl.capacity[-1])
        f_win.append(False)
        f_window_tau.append(0.0)
        f_tilt.append(surface.tilt)
        f_az.append(surface.azimuth)
        f_mass.append(surface.boundary == "adiabatic")
        f_back.append((0.0, 0.0))
        alpha_out, eps_out = face_props(surface, layers, inside=False)
        if surface.boundary == "zone":
            partner = building.surfaces[surface.other_surface]
            surface_nodes[partner.name] = (inside, outside)
            # the partner's inside face is our outside face
            p_alpha = (
                alpha_out
                if partner.solar_absorptance_inside is None
                else partner.solar_absorptance_inside
            )
            p_eps = eps_out if partner.emissivity_inside is None else partner.emissivity_inside
            f_name.append(partner.name)
            f_node.append(outside)
            f_zone.append(zone_index[partner.zone])
            f_area.append(area)
            f_cos.append(-math.cos(math.radians(partner.tilt)))
            f_eps.append(p_eps)
            f_alpha.append(p_alpha)
            f_cap.append(tpl.capacity[0])
            f_win.append(False)
            f_window_tau.append(0.0)
            f_tilt.append(partner.tilt)
            f_az.append(partner.azimuth)
            f_mass.append(False)
            f_back.append((0.0, 0.0))
        elif surface.boundary == "ground" and surface.name in building.foundations:
            pending_foundations.append((surface.name, layers, tpl, outside, area))
        elif surface.boundary == "ground" and surface.name in foundation_walls:
            pass  # a basement's wall: its outside node meets its floor's ground section
        elif surface.boundary == "ground":
            boundary(outside, IN_TEMP_GROUND, options.ground_contact_conductance * area)
        elif surface.boundary == "outdoors":
            e_name.append(surface.name)
            e_node.append(outside)
            e_area.append(area)
            e_tilt.append(surface.tilt)
            e_az.append(surface.azimuth)
            e_eps.append(eps_out)
            e_alpha.append(alpha_out if surface.sun_exposed else 0.0)
            e_cap.append(tpl.capacity[0])
            e_sun.append(surface.sun_exposed)
            outer_roughness = layers[0].roughness
            e_rough.append(
                options.roughness_factor
                if outer_roughness is None
                else ROUGHNESS_FACTORS[outer_roughness]
            )
            e_wind.append(_wind_factor(surface, options))
            e_pa.append(surface.perimeter_over_area)
            e_win.append(False)
        elif surface.outside_at_inside:
            # EnergyPlus' adiabatic and internal-mass faces: the outside at the inside face's
            # temperature
            mirror_rows, mirror_cols, mirror_vals = mirrored_outside_entries(outside, inside, area)
            rows.extend(mirror_rows)
            cols.extend(mirror_cols)
            vals.extend(mirror_vals)
        # adiabatic: nothing on the outside
    entries.add_links(*_chain_links(chains), before_pending=True)
    for name, layers, tpl, outside, area in pending_foundations:
        from thermocal.multizone.foundation import grade_convection

        ground = building.foundations[name]
        grade_h = grade_convection(
            mean_wind_speed, ground.grade_roughness, ground.grade_roughness_factor
        )
        walls = [(surface_nodes[w][0], float(share)) for w, share in ground.walls]
        foundation_nodes.append(
            _add_foundation(
                ground, layers, tpl, outside, area, walls, options.foundation_states, grade_h,
                new_nodes, entry, source, foundation_sun, foundation_wall_sun, new_input,
                ground_faces, name,
                {w: surface_nodes[w][0] for w, _ in ground.walls},
                {
                    w: template(building.surfaces[w].construction).capacity[0]
                    for w, _ in ground.walls
                },
            )
        )

    # ---- windows -----------------------------------------------------------------------------
    window_nodes: dict[str, tuple[int, int]] = {}
    w_g0: list[float] = []
    w_ratio: list[np.ndarray] = []
    for window in building.windows.values():
        wt = building.window_types[window.window_type]
        host = building.surfaces[window.surface]
        first = new_nodes([0.0, 0.0])
        r_glass = max(1.0 / wt.u_value - window_film_resistance(wt.u_value), 0.005)
        link(first, first + 1, window.area / r_glass)
        window_nodes[window.name] = (first, first + 1)
        w_g0.append(window.area / r_glass)
        if wt.glass_conductance_ratio is None:
            w_ratio.append(np.ones(len(WINDOW_TEMPERATURE_GRID)))
        else:
            w_ratio.append(
                np.interp(
                    WINDOW_TEMPERATURE_GRID,
                    wt.glass_conductance_temperatures,
                    wt.glass_conductance_ratio,
                )
            )
        f_name.append(window.name)
        f_node.append(first + 1)
        f_zone.append(zone_index[host.zone])
        f_area.append(window.area)
        f_cos.append(-math.cos(math.radians(host.tilt)))
        f_eps.append(wt.emissivity_inside)
        f_alpha.append(0.0)
        f_cap.append(0.0)
        f_win.append(True)
        tau_key = ("tau_diffuse", wt.name, wt.shgc, wt.solar_transmittance)
        if tau_key not in cache:
            cache[tau_key] = wt.diffuse_transmittance_value
        f_window_tau.append(cache[tau_key])
        f_tilt.append(host.tilt)
        f_az.append(host.azimuth)
        f_mass.append(False)
        f_back.append(_window_back_absorptance(wt))
        e_name.append(window.name)
        e_node.append(first)
        e_area.append(window.area)
        e_tilt.append(host.tilt)
        e_az.append(host.azimuth)
        e_eps.append(wt.emissivity_outside)
        e_alpha.append(0.0)
        e_cap.append(0.0)
        e_sun.append(False)
        e_rough.append(GLASS_ROUGHNESS_FACTOR)
        e_wind.append(_wind_factor(host, options))
        e_pa.append(host.perimeter_over_area)  # EnergyPlus: the base surface's (TARP)
        e_win.append(True)

    face_node = np.asarray(f_node, dtype=np.int64)
    face_zone = np.asarray(f_zone, dtype=np.int64)
    face_area = np.asarray(f_area, dtype=float)
    face_cos = np.asarray(f_cos, dtype=float)
    face_cos = np.where(np.abs(face_cos) < 0.02, 0.0, face_cos)
    face_eps = np.asarray(f_eps, dtype=float)
    face_alpha = np.asarray(f_alpha, dtype=float)
    face_cap = np.asarray(f_cap, dtype=float)
    face_is_window = np.asarray(f_win, dtype=bool)
    face_tau = np.asarray(f_window_tau, dtype=float)
    face_back = np.reshape(np.asarray(f_back, dtype=float), (len(f_back), 2))
    # orientation and mass flag of every face, converted once (indexed per zone below)
    tilt_all, az_all, mass_all = np.asarray(f_tilt), np.asarray(f_az), np.asarray(f_mass)
    members_of = _zone_members(face_zone, nz)

    def zone_view(members: np.ndarray) -> np.ndarray:
        """Approximate view factors of the faces ``members`` of a zone, once per distinct zone
        geometry (areas, orientations, mass flags; shared by the long-wave exchange and the
        interior solar distribution, and between assemblies through ``cache``)."""
        key = (
            "view",
            face_area[members].tobytes(),
            tilt_all[members].tobytes(),
            az_all[members].tobytes(),
            mass_all[members].tobytes(),
        )
        if key not in cache:
            cache[key] = approximate_view_factors(
                face_area[members], tilt_all[members], az_all[members], mass_all[members]
            )
        return cache[key]

    # ---- interior convection -----------------------------------------------------------------
    face_iso = np.zeros((len(face_node), 5))
    if options.interior_convection == "tarp":
        nominal = 2.0  # [K] representative surface-air difference for the matrix part
        h0 = np.where(
            face_cos == 0.0,
            tarp_natural_convection(nominal, 0.0),
            0.5
            * (
                tarp_natural_convection(nominal, face_cos)
                + tarp_natural_convection(-nominal, face_cos)
            ),
        )
        if options.window_interior_convection == "iso15099":
            # EnergyPlus' TARP takes ISO 15099 for windows (ConvectionCoefficients.cc,
            # InitIntConvCoeff: CalcISO15099WindowIntConvCoeff at the window's height); the time
            # loop applies it as the correction on top of the TARP matrix part, which keeps
            # the windows' matrix part and stability bound (2 h0) as they were
            for k in np.flatnonzero(face_is_window):
                window = building.windows[f_name[k]]
                height = window.height if window.height else math.sqrt(window.area)
                tilt = float(tilt_all[k])
                sin_tilt = math.sin(math.radians(tilt))
                face_iso[k] = (
                    height,
                    tilt,
                    sin_tilt,
                    iso15099_critical_rayleigh(tilt, sin_tilt),
                    iso15099_critical_rayleigh(180.0 - tilt, sin_tilt),
                )
        # explicit-correction stability bound (see simulation module)
        hmax = 2.0 * h0 + face_cap / step
    else:
        if options.h_interior_fixed is not None:
            h0 = np.full(len(face_node), float(options.h_interior_fixed))
        elif options.interior_convection == "simple":
            # matrix part: the mean of EnergyPlus' stable and unstable values on horizontal
            # (tilted) faces, the simulation corrects it by the heat-flow direction each step
            abs_cos = np.abs(face_cos)
            h0 = np.where(
                abs_cos >= 0.9239,
                0.5 * (4.040 + 0.948),
                np.where(abs_cos >= 0.3827, 0.5 * (3.870 + 2.281), 3.076),
            )
        else:
            h0 = np.where(face_cos > 0.7, 0.7, np.where(face_cos < -0.7, 5.0, 2.5))
        hmax = h0.copy()
    entries.add_links(face_node, face_zone, h0 * face_area)

    # ---- interior long-wave: MRT star per zone, or pairwise exchange factors ------------------
    mrt_node = -np.ones(nz, dtype=np.int64)
    face_mrt_g = np.zeros(len(face_node))
    h_black = 4.0 * STEFAN_BOLTZMANN * (options.radiant_temperature + 273.15) ** 3
    pair_a: list[int] = []
    pair_b: list[int] = []
    pair_g: list[float] = []
    if options.interior_longwave_exchange not in ("star", "view_factors"):
        raise ThermocalInputError(
            "interior_longwave_exchange must be 'star' or 'view_factors', got "
            f"{options.interior_longwave_exchange!r}"
        )
    if options.interior_longwave and options.interior_longwave_exchange == "view_factors":
        for z in range(nz):
            members = members_of[z]
            if len(members) < 2:
                continue
            key = (
                "lw_view",
                face_area[members].tobytes(),
                face_eps[members].tobytes(),
                tilt_all[members].tobytes(),
                az_all[members].tobytes(),
                mass_all[members].tobytes(),
            )
            if key not in cache:
                cache[key] = grey_exchange_factors(zone_view(members), face_eps[members])
            script_f = cache[key]
            g = h_black * face_area[members][:, None] * script_f
            g = 0.5 * (g + g.T)
            upper_i, upper_j = np.triu_indices(len(members), 1)  # row by row, as the pairs
            seen = g[upper_i, upper_j] > 0.0
            upper_i, upper_j = upper_i[seen], upper_j[seen]
            pair_a.extend(face_node[members[upper_i]].tolist())
            pair_b.extend(face_node[members[upper_j]].tolist())
            pair_g.extend(g[upper_i, upper_j].tolist())
        entries.add_links(pair_a, pair_b, pair_g)
    elif options.interior_longwave:
        star_i: list[np.ndarray] = []
        star_j: list[np.ndarray] = []
        star_g: list[np.ndarray] = []
        for z in range(nz):
            members = members_of[z]
            if len(members) < 2:
                continue
            node = new_nodes([0.0])
            mrt_node[z] = node
            mrt_key = ("mrt", face_area[members].tobytes(), face_eps[members].tobytes(), h_black)
            if mrt_key not in cache:
                cache[mrt_key] = mrt_network_conductances(
                    face_area[members], face_eps[members], h_black
                )
            g = cache[mrt_key]
            face_mrt_g[members] = g
            star_i.append(face_node[members])
            star_j.append(np.full(len(members), node, dtype=np.int64))
            star_g.append(np.asarray(g, dtype=float))
        if star_i:
            entries.add_links(
                np.concatenate(star_i), np.concatenate(star_j), np.concatenate(star_g)
            )

    # ---- internal gains ----------------------------------------------------------------------
    # radiant internal gains (and the radiant part of identified heat) are shared by the zone's
    # faces in proportion to area x thermal absorptance, as EnergyPlus does
    face_radiant_share = radiant_gain_shares(face_zone, face_area, face_eps, nz)
    for z, zone in enumerate(zones):
        if zone.internal_gains == 0:
            continue
        radiative = zone.internal_gains * zone.internal_gains_radiative_fraction
        source(z, IN_ONE, zone.internal_gains - radiative)
        members = members_of[z]
        if len(members) == 0:
            source(z, IN_ONE, radiative)
            continue
        for m in members:
            source(int(face_node[m]), IN_ONE, radiative * float(face_radiant_share[m]))

    for name in gain_input_zones:
        z = zone_index[name]
        source(z, new_input(f"gains_convective/{name}"), 1.0)
        column = new_input(f"gains_radiant/{name}")
        members = members_of[z]
        if len(members) == 0:
            source(z, column, 1.0)
            continue
        for m in members:
            source(int(face_node[m]), column, float(face_radiant_share[m]))

    # ---- exterior faces -------------------------------------------------------------------------
    ext_node = np.asarray(e_node, dtype=np.int64)
    ext_area = np.asarray(e_area, dtype=float)
    ext_tilt = np.asarray(e_tilt, dtype=float)
    ext_eps = np.asarray(e_eps, dtype=float)
    # EnergyPlus' long-wave view factors follow the tilt alone (ViewFactorSkyIR = (1 + cos)/2,
    # SurfaceGeometry.cc); a surface's 'View Factor to Ground' field is its ground-reflected
    # solar only (a north roof of NREL's SingleFamilyHouse has 0.9: it still sees the sky)
    f_sky = 0.5 * (1.0 + np.cos(np.radians(ext_tilt)))
    if sky_view_ratio:
        # shading surfaces hide part of the sky in the long-wave too (EnergyPlus multiplies the
        # sky IR view factor by the isotropic sky-diffuse shading ratio; the hidden part sees
        # the shading surfaces, taken at the outdoor-air temperature as the ground)
        f_sky = f_sky * np.array([float(sky_view_ratio.get(name, 1.0)) for name in e_name])
    f_ground = 1.0 - f_sky
    beta = np.sqrt(0.5 * (1.0 + np.cos(np.radians(ext_tilt))))
    view_sky = f_sky * beta
    view_air = f_ground + f_sky * (1.0 - beta)
    ext_is_window = np.asarray(e_win, dtype=bool)
    if options.exterior_convection == "simple_combined":
        # the combined coefficient holds the long-wave exchange, all of it with the outdoor air,
        # on opaque faces; EnergyPlus' window heat balance (WindowManager) takes the combined
        # coefficient as the convective film of the outer glass and adds the long-wave exchange
        # with sky, air and ground explicitly, as for the other algorithms
        view_sky = np.where(ext_is_window, view_sky, 0.0)
        view_air = np.where(ext_is_window, view_air, 1.0)
    cos_tilt = np.cos(np.radians(ext_tilt))
    # natural part of the exterior convection at a nominal 3 K difference (the matrix part; the
    # time loop takes DOE-2's and TARP's at the face's own difference, see Simulation)
    dt_nominal = NOMINAL_EXTERIOR_DELTA_T
    h_natural = np.where(
        np.abs(cos_tilt) < 0.02,
        tarp_natural_convection(dt_nominal, 0.0),
        0.5
        * (
            tarp_natural_convection(dt_nominal, cos_tilt)
            + tarp_natural_convection(-dt_nominal, cos_tilt)
        ),
    )
    ext_rough = np.asarray(e_rough, dtype=float)
    ext_wind = np.asarray(e_wind, dtype=float)
    ext_pa = np.asarray(e_pa, dtype=float)
    if options.exterior_convection in WIND_DRIVEN_EXTERIOR:
        local_wind = mean_wind_speed * ext_wind
        # average of windward and leeward at the mean wind speed
        hc0 = 0.5 * sum(
            exterior_convection(
                options.exterior_convection,
                local_wind,
                windward,
                h_natural=h_natural,
                roughness_factor=ext_rough,
                perimeter_over_area=ext_pa,
            )
            for windward in (True, False)
        )
    else:
        hc0 = np.full(len(ext_node), float(options.h_exterior_fixed))
    t_mean = mean_outdoor_temperature + 273.15
    hr0 = 4.0 * STEFAN_BOLTZMANN * t_mean**3
    if options.exterior_convection == "simple_combined":
        combined = simple_combined_exterior_coefficient(mean_wind_speed * ext_wind, ext_rough)
        hc0 = np.where(ext_is_window, combined, np.maximum(combined - hr0 * ext_eps, 0.0))
    for k in range(len(ext_node)):
        node = int(ext_node[k])
        boundary(node, IN_TEMP_OUT, float((hc0[k] + hr0 * ext_eps[k] * view_air[k]) * ext_area[k]))
        if view_sky[k] > 0:
            boundary(node, IN_TEMP_SKY, float(hr0 * ext_eps[k] * view_sky[k] * ext_area[k]))

    # ---- solar: opaque exterior faces ------------------------------------------------------------
    for k in range(len(ext_node)):
        if not e_sun[k] or e_alpha[k] == 0:
            continue
        key = (round(float(ext_tilt[k]), 3), round(float(e_az[k]) % 360.0, 3))
        if e_name[k] in own_solar_inputs:
            key = (*key, e_name[k])
        if key not in orientation_inputs:
            orientation_inputs[key] = new_input("poa_global/" + "/".join(map(str, key)))
        source(int(ext_node[k]), orientation_inputs[key], e_alpha[k] * ext_area[k])

    # ---- solar: windows ----------------------------------------------------------------------
    # EnergyPlus' interior solar distribution (Engineering Reference, "Solar Distribution" of the
    # Building object and "Interior Solar Radiation Absorption"; SolarShading.cc,
    # CalcWinTransDifSolInitialDistribution; HeatBalanceSurfaceManager.cc,
    # ComputeIntSWAbsorpFactors):
    # * beam: all on the floor(s) by area (FullExterior; the interior projection of
    #   FullInteriorAndExterior needs the vertices, which the model does not keep), absorbed there
    #   with the floor's absorptance;
    # * transmitted diffuse of a window: first onto the zone's faces by approximate view factors
    #   (a face sees every face not in its own plane, by area; reciprocity and completeness
    #   enforced as in FixViewFactors), absorbed with each face's absorptance; reaching another
    #   window it leaves through it (tau) or is absorbed in its glass (back absorptance);
    # * everything reflected (beam off the floor, diffuse after its first incidence) is absorbed
    #   by the ISABSF weights A alpha (opaque) and A (tau + back absorptance) (windows), the tau
    #   part leaving the zone.
    window_face_of = {name: k for k, name in enumerate(f_name) if face_is_window[k]}
    face_glazed = face_area.copy()
    for window in building.windows.values():
        face_glazed[window_face_of[window.name]] = window.glazed_area
    zone_members: dict[int, np.ndarray] = {}
    isabsf: dict[int, list[tuple[int, float]]] = {}  # (node, weight) of the reflected pool
    view: dict[int, np.ndarray] = {}
    # per-face values as Python floats for the loops below (the same double arithmetic as numpy
    # scalars, without their overhead)
    is_window_of, glazed_of, area_of, alpha_of, tau_of, node_of = (
        a.tolist()
        for a in (face_is_window, face_glazed, face_area, face_alpha, face_tau, face_node)
    )
    back_outer_of, back_inner_of = face_back[:, 0].tolist(), face_back[:, 1].tolist()
    back_sum_of = face_back.sum(axis=1).tolist()
    member_list: dict[int, list[int]] = {}
    for z in range(nz):
        members = members_of[z]
        if len(members) == 0:
            continue
        zone_members[z] = members
        member_list[z] = members.tolist()
        pool = []
        for m in member_list[z]:
            if is_window_of[m]:
                outer, inner = window_nodes[f_name[m]]
                pool.append((outer, glazed_of[m] * back_outer_of[m]))
                pool.append((inner, glazed_of[m] * back_inner_of[m]))
            else:
                pool.append((node_of[m], area_of[m] * alpha_of[m]))
        total = face_area[members] @ np.where(face_is_window[members], 0.0, face_alpha[members])
        total += face_glazed[members] @ np.where(
            face_is_window[members], face_tau[members] + face_back[members].sum(axis=1), 0.0
        )
        isabsf[z] = [(node, w / total) for node, w in pool if total > 0 and w > 0]
        view[z] = zone_view(members)

    def first_incidence(z: int, fractions) -> tuple[dict[int, float], float]:
        """Absorbed share per node and reflected share of radiation first hitting the faces of
        zone ``z`` with the fractions ``fractions`` (per member)."""
        absorbed: dict[int, float] = {}
        reflected = 0.0
        for m, f in zip(member_list[z], np.asarray(fractions).tolist(), strict=True):
            if f <= 0:
                continue
            if is_window_of[m]:
                glazed = glazed_of[m] / area_of[m]
                outer, inner = window_nodes[f_name[m]]
                absorbed[outer] = absorbed.get(outer, 0.0) + f * glazed * back_outer_of[m]
                absorbed[inner] = absorbed.get(inner, 0.0) + f * glazed * back_inner_of[m]
                reflected += f * (1.0 - glazed * (tau_of[m] + back_sum_of[m]))
            else:
                node = node_of[m]
                absorbed[node] = absorbed.get(node, 0.0) + f * alpha_of[m]
                reflected += f * (1.0 - alpha_of[m])
        return absorbed, reflected

    def with_reflection(z: int, absorbed: dict[int, float], reflected: float):
        shares = dict(absorbed)
        for node, s in isabsf[z]:
            shares[node] = shares.get(node, 0.0) + reflected * s
        return [(node, s) for node, s in shares.items() if s > 0]

    beam_share: dict[int, list[tuple[int, float]]] = {}
    for z, members in zone_members.items():
        floors = (face_cos[members] > 0.7) & ~face_is_window[members]
        if not floors.any():
            beam_share[z] = isabsf[z]
            continue
        beam_share[z] = with_reflection(
            z,
            *first_incidence(
                z, np.where(floors, face_area[members], 0.0) / face_area[members][floors].sum()
            ),
        )
    diffuse_share: dict[str, list[tuple[int, float]]] = {}
    for window in building.windows.values():
        k = window_face_of[window.name]
        z = int(face_zone[k])
        row = view[z][int(np.flatnonzero(zone_members[z] == k)[0])]
        diffuse_share[window.name] = with_reflection(z, *first_incidence(z, row))

    window_inputs: dict[tuple[str, float, float], tuple[int, int, int, int]] = {}
    window_beam_targets: dict[str, tuple] = {}
    zt_rows: list[int] = []
    zt_cols: list[int] = []
    zt_vals: list[float] = []
    for window in building.windows.values():
        host = building.surfaces[window.surface]
        wt = building.window_types[window.window_type]
        if not host.sun_exposed:
            continue
        key = (wt.name, round(host.tilt, 3), round(host.azimuth % 360.0, 3))
        if window.name in own_solar_inputs:
            key = (*key, window.name)
        if key not in window_inputs:
            tag = "/".join(map(str, key))
            window_inputs[key] = (
                new_input(f"window_beam/{tag}"),
                new_input(f"window_diffuse/{tag}"),
                new_input(f"window_abs_outer/{tag}"),
                new_input(f"window_abs_inner/{tag}"),
            )
        c_beam, c_diff, c_out, c_in = window_inputs[key]
        area = window.glazed_area * window.shading_factor
        z = zone_index[host.zone]
        targets = (interior_beam or {}).get(window.name)
        if targets:
            in_zone = np.asarray(zone_members[z])
            on_faces = []
            for face in targets:
                onto = np.array([1.0 if f_name[m] == face else 0.0 for m in in_zone])
                c_face = new_input(f"window_beam_on/{window.name}/{face}")
                for node, s in with_reflection(z, *first_incidence(z, onto)):
                    source(node, c_face, s)
                on_faces.append((face, c_face))
            window_beam_targets[window.name] = (c_beam, area, on_faces)
        else:
            for node, s in beam_share.get(z, []):
                source(node, c_beam, area * s)
        for node, s in diffuse_share.get(window.name, []):
            source(node, c_diff, area * s)
        outer, inner = window_nodes[window.name]
        source(outer, c_out, area)
        source(inner, c_in, area)
        zt_rows.extend((z, z))
        zt_cols.extend((c_beam, c_diff))
        zt_vals.extend((area, area))

    n = n_nodes[0]
    n_inputs = len(input_names)
    conductance = sp.coo_matrix(entries.arrays(), shape=(n, n)).tocsc()
    inputs = sp.coo_matrix((b_vals, (b_rows, b_cols)), shape=(n, n_inputs)).tocsr()
    zone_transmitted = sp.coo_matrix((zt_vals, (zt_rows, zt_cols)), shape=(nz, n_inputs)).tocsr()
    return Network(
        n_nodes=n,
        foundation_nodes=(
            np.concatenate(foundation_nodes) if foundation_nodes else np.zeros(0, dtype=np.int64)
        ),
        capacity=np.concatenate([np.asarray(cap, dtype=float), *cap_blocks]),
        conductance=conductance,
        inputs=inputs,
        input_names=input_names,
        zone_names=[z.name for z in zones],
        air_node=np.arange(nz),
        mrt_node=mrt_node,
        face_names=f_name,
        face_node=face_node,
        face_zone=face_zone,
        face_area=face_area,
        face_cos_up=face_cos,
        face_h0=np.asarray(h0, dtype=float),
        face_iso=face_iso,
        face_hmax=np.asarray(hmax, dtype=float),
        face_capacity=face_cap,
        face_is_window=face_is_window,
        face_mrt_conductance=face_mrt_g,
        face_mrt_node=mrt_node[face_zone],
        lw_pair_a=np.asarray(pair_a, dtype=np.int64),
        lw_pair_b=np.asarray(pair_b, dtype=np.int64),
        lw_pair_g=np.asarray(pair_g, dtype=float),
        face_radiant_share=face_radiant_share,
        h_black=float(h_black),
        ext_names=e_name,
        ext_node=ext_node,
        ext_area=ext_area,
        ext_tilt=ext_tilt,
        ext_azimuth=np.asarray(e_az, dtype=float),
        ext_emissivity=ext_eps,
        ext_view_sky=view_sky,
        ext_view_air=view_air,
        ext_h_natural=h_natural,
        ext_roughness=ext_rough,
        ext_wind_factor=ext_wind,
        ext_perimeter_over_area=ext_pa,
        ext_hc0=np.asarray(hc0, dtype=float),
        ext_is_window=ext_is_window,
        ext_hr0=float(hr0),
        ext_capacity=np.asarray(e_cap, dtype=float),
        ground_faces=_ground_faces(ground_faces),
        zone_infiltration=zone_infiltration,
        zone_volume=zone_volume,
        reference_density=rho_ref,
        orientation_inputs=orientation_inputs,
        window_inputs=window_inputs,
        window_beam_targets=window_beam_targets,
        zone_transmitted=zone_transmitted,
        window_outer=np.array([n[0] for n in window_nodes.values()], dtype=np.int64),
        window_inner=np.array([n[1] for n in window_nodes.values()], dtype=np.int64),
        window_conductance=np.asarray(w_g0, dtype=float),
        window_conductance_ratio=np.ascontiguousarray(
            np.reshape(w_ratio, (len(w_g0), len(WINDOW_TEMPERATURE_GRID)))
        ),
    )


#: Faces whose tilts and azimuths differ by at most this much lie in one plane and do not see each
#: other (EnergyPlus, CalcApproximateViewFactors: SameAngleLimit) [deg].
SAME_PLANE_ANGLE = 10.0


@functools.lru_cache(maxsize=64)
def _foundation_grid(ground, area: float, floor_layers: tuple):
    """:func:`thermocal.multizone.foundation.foundation_grid`, kept between assemblies (the
    strategies of a retrofit, the samples of a campaign share their floors' sections)."""
    from thermocal.multizone.foundation import foundation_grid

    return foundation_grid(ground, area, floor_layers)


@functools.lru_cache(maxsize=64)
def _reduced_section(ground, area: float, floor_layers: tuple, n_states: int, grade_h: float):
    """:func:`thermocal.multizone.foundation.reduced_section` of :func:`_foundation_grid`'s
    section, kept between assemblies."""
    from thermocal.multizone.foundation import reduced_section

    return reduced_section(_foundation_grid(ground, area, floor_layers), n_states, grade_h)


def _ground_faces(faces: list[dict]) -> GroundFaces:
    """:class:`GroundFaces` of the faces :func:`_add_foundation` recorded."""
    from thermocal.multizone.foundation import grade_longwave_coefficient

    if not faces:
        return GroundFaces.empty()

    def csr(key):
        ptr = np.concatenate([[0], np.cumsum([len(f[key]) for f in faces])]).astype(np.int64)
        idx = np.array([i for f in faces for i, _ in f[key]], dtype=np.int64)
        val = np.array([v for f in faces for _, v in f[key]], dtype=float)
        return ptr, idx, val

    def column(key, dtype=float):
        return np.array([f[key] for f in faces], dtype=dtype)

    return GroundFaces(
        [f["name"] for f in faces],
        column("column", np.int64),
        *csr("out"),
        *csr("u"),
        column("tilt"),
        column("roughness"),
        column("wind_factor"),
        column("leeward_mean", bool),
        column("hc0"),
        column("emissivity"),
        column("view_sky"),
        column("capacity"),
        grade_longwave_coefficient(1.0),
    )


def _add_foundation(
    ground, layers, template, outside, area, walls, n_states, grade_h, new_nodes, entry,
    source, sun_column, wall_sun_column, new_input, ground_faces, name, wall_nodes,
    wall_capacity,
) -> np.ndarray:
    """Add a floor's two-dimensional ground section (:mod:`thermocal.multizone.foundation`).

    The section couples to its node ports: the floor's outside node (the top of the soil under
    the floor), the chain's node above any insulation under the slab (the slab's edge on the
    wall; the outside node for a reduced construction) and a basement's walls' outside nodes
    ``walls`` (node, share of the perimeter), whose port is their shares' weighted temperature
    and whose flow each takes by its share; and to the outdoor air, the sky and the heat fluxes
    on the grade and on the wall's face above it (``grade_h`` their convection coefficient
    [W/(m2 K)]): the absorbed sun (the horizontal plane's on the grade, Kiva's vertical cylinder
    on the wall) and the time loop's correction of their convection and long-wave (each face an
    entry of ``ground_faces``, :class:`GroundFaces`, its temperature an output of the section).
    A basement's walls above the grade meet the outdoor air directly, with the same sun and
    correction. With ``n_states`` the cells are replaced by that many balanced states
    (:func:`thermocal.multizone.foundation.reduced_section`, exact at steady state); with None
    every cell is a node.

    Returns
    -------
    ndarray of int
        The section's nodes.
    """
    from thermocal.multizone.foundation import (
        GRADE_ABSORPTANCE,
        GRADE_EMISSIVITY,
        GRADE_PORT,
        WALL_FACE_PORT,
        WALL_SKY_SHARE,
        grade_longwave_coefficient,
        grade_wind_factor,
        section_matrices,
    )

    floor_layers = []
    for layer in layers:
        if isinstance(layer, Material):
            floor_layers.append(
                (layer.thickness, layer.conductivity, layer.density, layer.specific_heat)
            )
        else:  # a resistance without mass: a thin layer of that resistance
            floor_layers.append((0.001, 0.001 / layer.resistance, 1.0, 1.0))
    grid = _foundation_grid(ground, float(area), tuple(floor_layers))
    if template.layer_nodes and grid.slab_interface < len(template.layer_nodes):
        slab = outside + template.layer_nodes[grid.slab_interface]
    else:
        slab = outside
    wind = grade_wind_factor(ground.grade_roughness)
    alpha_wall = float(ground.wall_absorptance)

    def face(label, tilt, emissivity, view_sky, capacity, leeward_mean=False) -> dict:
        record = {
            "name": f"{name}/{label}",
            "column": new_input(f"kiva_correction/{name}/{label}"),
            "out": [],
            "u": [],
            "tilt": tilt,
            "roughness": float(ground.grade_roughness_factor),
            "wind_factor": wind,
            "leeward_mean": leeward_mean,
            "hc0": float(grade_h),
            "emissivity": float(emissivity),
            "view_sky": float(view_sky),
            "capacity": float(capacity),
        }
        ground_faces.append(record)
        return record

    # the node ports as (node, weight) lists, then the input columns as (column, factor) lists
    ports = [[(outside, 1.0)], [(slab, 1.0)], walls]
    is_grade = grid.outdoor[:, 2] > 0.5 if len(grid.outdoor) else np.zeros(0, dtype=bool)
    cells, exposed = grid.outdoor[:, 0].astype(int), grid.outdoor[:, 1]
    per_area = grid.capacity[cells] / exposed if len(cells) else np.zeros(0)
    outputs = {}  # flux port -> its face record
    columns = [[(IN_TEMP_OUT, 1.0)], [(IN_TEMP_SKY, 1.0)], [], []]
    if is_grade.any():
        grade = face("grade", 0.0, GRADE_EMISSIVITY, 1.0, per_area[is_grade].min())
        columns[2] = [(sun_column(), GRADE_ABSORPTANCE), (grade["column"], 1.0)]
        outputs[GRADE_PORT] = grade
    if (~is_grade).any():  # a slab's wall face above the grade: Kiva gives it the floor's terms
        wall = face(
            "wall", 90.0, ground.wall_emissivity, WALL_SKY_SHARE, per_area[~is_grade].min()
        )
        columns[3] = [(wall_sun_column(), alpha_wall), (wall["column"], 1.0)]
        outputs[WALL_FACE_PORT] = wall
    if grid.wall_above_grade > 0:  # a basement's walls above the grade: to the outdoor air
        hr = grade_longwave_coefficient(ground.wall_emissivity)
        for (wall_name, _), (node, share) in zip(ground.walls, walls, strict=True):
            wall_area = grid.wall_above_grade * share
            g_air = (grade_h + (1.0 - WALL_SKY_SHARE) * hr) * wall_area
            g_sky = WALL_SKY_SHARE * hr * wall_area
            entry(node, node, g_air + g_sky)
            source(node, IN_TEMP_OUT, g_air)
            source(node, IN_TEMP_SKY, g_sky)
            source(node, wall_sun_column(), alpha_wall * wall_area)
            # Kiva's wall surfaces: the mean of MoWiTT's windward and leeward forced terms
            record = face(
                f"wall/{wall_name}", 90.0, ground.wall_emissivity, WALL_SKY_SHARE,
                wall_capacity[wall_name], leeward_mean=True,
            )  # fmt: skip
            record["out"].append((int(wall_nodes[wall_name]), 1.0))
            source(node, record["column"], wall_area)
    if n_states is None or n_states >= len(grid.capacity) - 1:
        a, capacity, h = section_matrices(grid, grade_h)
        first = new_nodes(capacity)
        rows, cols = np.nonzero(a)
        for i, j in zip(rows, cols, strict=True):
            entry(first + int(i), first + int(j), float(a[i, j]))
        for c in range(len(capacity)):
            for k, port in enumerate(ports):
                if not h[c, k]:
                    continue
                for node, weight in port:
                    entry(first + c, node, -h[c, k] * weight)
                    entry(node, first + c, -h[c, k] * weight)
                    entry(node, node, h[c, k] * weight)
            for k, column in enumerate(columns):
                for col, factor in column:
                    if h[c, 3 + k]:
                        source(first + c, col, h[c, 3 + k] * factor)
        for k, record in outputs.items():
            total = h[:, k].sum()
            record["out"].extend(
                (first + int(c), float(h[c, k] / total)) for c in np.flatnonzero(h[:, k])
            )
        return np.arange(first, first + len(capacity), dtype=np.int64)
    reduced = _reduced_section(
        ground, float(area), tuple(floor_layers), int(n_states), round(float(grade_h), 6)
    )
    m = len(reduced.rates)
    first = new_nodes(np.ones(m))
    d = reduced.feedthrough
    for q in range(m):
        entry(first + q, first + q, float(reduced.rates[q]))
        for k, port in enumerate(ports):
            for node, weight in port:
                entry(first + q, node, -float(reduced.coupling[q, k]) * weight)
                entry(node, first + q, -float(reduced.coupling[q, k]) * weight)
        for k, column in enumerate(columns):
            for col, factor in column:
                source(first + q, col, float(reduced.coupling[q, 3 + k]) * factor)
    for k, port in enumerate(ports):
        for node, weight in port:
            entry(node, node, float(reduced.node_conductance[k]) * weight)
            for kk, other in enumerate(ports):
                for node2, weight2 in other:
                    entry(node, node2, -float(d[k, kk]) * weight * weight2)
            for kk, column in enumerate(columns):
                for col, factor in column:
                    source(node, col, float(d[k, 3 + kk]) * weight * factor)
    # a flux port's face temperature: (its cells' areas) x T / its area, from the states and,
    # through the quasi-static ones, the ports (the previous step's inputs)
    for k, record in outputs.items():
        total = float(exposed[is_grade].sum() if k == GRADE_PORT else exposed[~is_grade].sum())
        record["out"].extend(
            (first + q, float(reduced.coupling[q, k]) / total) for q in range(m)
        )
        for kk, port in enumerate(ports):
            for node, weight in port:
                record["out"].append((node, float(d[k, kk]) * weight / total))
        for kk, column in enumerate(columns):
            for col, factor in column:
                record["u"].append((col, float(d[k, 3 + kk]) * factor / total))
    return np.arange(first, first + m, dtype=np.int64)


def approximate_view_factors(area, tilt, azimuth, internal_mass=None, iterations=200):
    """EnergyPlus' approximate view factors of the faces of one zone [-], ``F[i, j]``.

    A face sees every face not in its own plane (tilt and azimuth within
    :data:`SAME_PLANE_ANGLE`; internal mass is seen by all and sees all) in proportion to area
    (``F_ij = A_j / sum of the areas it sees``); reciprocity ``A_i F_ij = A_j F_ji`` and
    completeness ``sum_j F_ij = 1`` are then enforced by alternating symmetrisation and row
    scaling (EnergyPlus' FixViewFactors).  A face that sees nothing keeps a zero row.

    The iteration is a pure function of the current matrix, so once a matrix recurs (a fixed
    point, or a cycle of a few last-bit oscillations, typically after 70-140 sweeps) the result
    of the remaining sweeps is known: it is taken from the cycle, bit for bit what running all
    ``iterations`` gives.
    """
    area = np.asarray(area, dtype=float)
    tilt = np.asarray(tilt, dtype=float)
    azimuth = np.asarray(azimuth, dtype=float)
    n = len(area)
    mass = np.zeros(n, dtype=bool) if internal_mass is None else np.asarray(internal_mass, bool)
    d_az = np.abs((azimuth[:, None] - azimuth[None, :] + 180.0) % 360.0 - 180.0)
    horizontal = (tilt < SAME_PLANE_ANGLE) | (tilt > 180.0 - SAME_PLANE_ANGLE)
    same = (np.abs(tilt[:, None] - tilt[None, :]) <= SAME_PLANE_ANGLE) & (
        (d_az <= SAME_PLANE_ANGLE) | (horizontal[:, None] & horizontal[None, :])
    )
    sees = (~same | mass[:, None] | mass[None, :]) & ~np.eye(n, dtype=bool)
    seen_area = sees @ area
    f = np.where(sees, area[None, :], 0.0) / np.where(seen_area > 0, seen_area, 1.0)[:, None]
    af = area[:, None] * f
    af = 0.5 * (af + af.T)
    # iterates by their bytes: a repeat at sweep k of sweep j < k is a cycle of period k - j
    seen: dict[bytes, int] = {af.tobytes(): 0}
    history = [af]
    add, where = np.add, np.where  # (the sweep's arithmetic as written, minus call overhead)
    for k in range(1, iterations + 1):
        rows = add.reduce(af, axis=1)
        positive = rows > 0
        af = af * where(positive, area / where(positive, rows, 1.0), 0.0)[:, None]
        af = add(af, af.T)
        af *= 0.5
        first = seen.setdefault(af.tobytes(), k)
        if first != k:
            af = history[first + (iterations - first) % (k - first)]
            break
        history.append(af)
    return af / area[:, None]


def grey_exchange_factors(view, emissivity):
    """Grey-body exchange factors ``ScriptF[i, j]`` of the faces of one zone [-].

    The net long-wave exchange from face ``j`` to face ``i`` per area of ``i`` is
    ``ScriptF_ij sigma (T_j^4 - T_i^4)``, with ``ScriptF = diag(eps) (I - F diag(1 - eps))^-1 F
    diag(eps)`` (Hottel's total exchange areas divided by ``A_i``; EnergyPlus' CalcScriptF); the
    diagonal (self-exchange) is set to zero.

    Parameters
    ----------
    view : ndarray (n, n) [-]
        View factors (:func:`approximate_view_factors`).
    emissivity : ndarray (n,) [-]

    Returns
    -------
    ndarray (n, n) [-]
    """
    view = np.asarray(view, dtype=float)
    eps = np.clip(np.asarray(emissivity, dtype=float), 0.05, 1.0)
    n = len(eps)
    inner = np.linalg.solve(np.eye(n) - view * (1.0 - eps)[None, :], view)
    script_f = eps[:, None] * inner * eps[None, :]
    np.fill_diagonal(script_f, 0.0)
    return script_f


def _window_back_absorptance(wt) -> tuple[float, float]:
    """Diffuse solar absorptance of a window for radiation from the room [-]: (outer, inner pane).

    The panes' front-side hemispherical absorptances mirrored (a symmetric glazing seen from the
    other side); middle panes shared half and half; 0 for a window without layered optics.
    """
    front = np.asarray(wt.diffuse_pane_absorptance_values, dtype=float)
    if len(front) == 0:
        return 0.0, 0.0
    back = front[::-1]
    if len(back) == 1:  # one layer between the two nodes: absorbed at its middle
        return 0.5 * float(back[0]), 0.5 * float(back[0])
    middle = float(back[1:-1].sum())
    return float(back[0]) + 0.5 * middle, float(back[-1]) + 0.5 * middle
