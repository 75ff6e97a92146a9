"""The fifth-order RC model of the retrofit method (its Fig. 3), built from a building description.

States (in this order): indoor air ``Ti``, lumped roof + external walls ``Tenv``, ground floor /
cellar ceiling ``Tgf``, internal mass ``Tim``, heating system ``Th``.

Inputs (in this order): external air temperature ``Te`` [C], ground temperature at 2 m ``Tgr``
[C], heating power ``phi_h`` [W] (into ``Th``), solar gains through windows ``phi_sol`` [W]
(fraction ``f_im`` into ``Tim``, the rest into ``Ti``), and the solar radiation absorbed on the
outer surfaces of the roof and of the external walls minus their long-wave loss to the sky,
``phi_abs_roof`` and ``phi_abs_walls`` [W]. The absorbed radiation reaches the ``Tenv`` node
through the outer half of the element: only the share ``2 Hc / (he A + 2 Hc)`` enters the node
(the rest is re-emitted at the outer surface), exactly what eliminating the massless outer
surface node gives; so retrofits, which change ``Hc``, change the solar share as well.

Element network (``Hc = A / Rc`` conduction conductance, ``Rc = 1/U - Rsi - Rse``):

- env (roof + walls): ``Ti --[A/Rsi (+) 2Hc]-- Tenv --[2Hc (+) A/Rse]-- Te`` per component,
  summed over roof and walls; ``(+)`` is the series connection. The capacity sits in the middle
  of the construction. In steady state the path carries exactly ``U A``.
- win: massless ``U A`` between ``Te`` and ``Ti`` (U-values include surface resistances).
- gf: cellar ceiling over an unheated basement (ISO 13370:2017 clause 9.4):
  ``Ti --[A/Rsi (+) 2Hc]-- Tgf --[2Hc (+) A/Rse]-- cellar``; the massless cellar node connects to
  the ground (basement floor and walls below grade, ``A Ubf + z P Ubw``) and to the outdoor air
  (walls above grade and cellar ventilation, ``h P Uw + 0.33 n V``); eliminating it (star-delta)
  gives two conductances from ``Tgf``, to ``Tgr`` and to ``Te``. Slab on ground: the ISO 13370
  slab U-value, the capacity below the inner surface resistance and half the floor construction.
- est: one estimated conductance ``Hest`` between ``Te`` and ``Ti`` (ventilation, infiltration,
  thermal bridges, doors).
- ``Hh`` (heating surface) and ``Him`` (internal mass surface) from areas estimated from the
  floor area, number of floors and emitter type, times ISO 52016-1 surface coefficients.
- With ``interior="split"`` (:mod:`thermocal.retrofit.interior`) the four air-to-element paths
  (env, win, gf inner halves and ``Him``) become the Kron-reduced network of each element's
  inner surface (convection to the air, radiation to a star node) and the internal mass: ten
  pair conductances ``G_<a>_<b>`` among ``Ti, Tenv, Tgf, Tim, Te``; same states.

Estimated parameters: ``H_est`` [W/K], ``C_env``, ``C_gf``, ``C_im``, ``C_i``, ``C_h`` [MJ/K],
with bounds from ISO 52016-1 / ISO 13790 typical areal capacities.

References
----------
The retrofit method (:data:`thermocal.retrofit.references.RETROFIT_METHOD`), "Fifth-order RC
model for retrofit analysis" and Fig. 3.
ISO 52016-1:2017, Table 25 (surface heat transfer coefficients), Table B.14 (areal heat
capacities of construction classes).
ISO 6946:2017, Table 7 (surface resistances).
ISO 13370:2017, clauses 7.1-7.3 (slab on ground) and 9.3-9.4 (basements).
ISO 13790:2008, 12.2.2 (internal heat capacity classes, effective mass area).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.retrofit.interior import PAIR_NAMES as INTERIOR_PAIR_NAMES
from thermocal.retrofit.interior import PAIRS as INTERIOR_PAIRS

STATE_NAMES: tuple[str, ...] = ("Ti", "Tenv", "Tgf", "Tim", "Th")
INPUT_NAMES: tuple[str, ...] = ("Te", "Tgr", "phi_h", "phi_sol", "phi_abs_roof", "phi_abs_walls")
ESTIMATED_PARAMETERS: tuple[str, ...] = ("H_est", "C_env", "C_gf", "C_im", "C_i", "C_h")

# ISO 52016-1:2017 Table 25 / ISO 6946:2017 Table 7: surface resistances [m2 K/W] and
# convective / radiative coefficients [W/(m2 K)] (emissivity 0.9).
R_SI = {"upward": 0.10, "horizontal": 0.13, "downward": 0.17}
R_SE = 0.04
H_CI = {"upward": 5.0, "horizontal": 2.5, "downward": 0.7}
H_RI = 5.13
H_RE = 4.14

#: Emitter surface per m2 of heated floor area [m2/m2] and its surface coefficient
#: [W/(m2 K)] (radiators, convectors: vertical surface hci + hri; floor heating: upward).
EMITTERS: dict[str, tuple[float, float]] = {
    "radiators": (0.2, H_CI["horizontal"] + H_RI),
    "convectors": (0.1, 3.0 * H_CI["horizontal"] + H_RI),
    "floor_heating": (0.8, H_CI["upward"] + H_RI),
}

#: Internal partitions (both faces) and furniture per m2 of heated floor area [m2/m2].
PARTITION_AND_FURNITURE_AREA_PER_FLOOR_AREA = 1.5


def internal_mass_area(floor_area: float, floors: int) -> float:
    """Surface area of the internal mass [m2] from the floor area and the number of floors.

    Partitions and furniture ``1.5 A_f`` plus both faces of the ``floors - 1`` intermediate
    floors, ``2 A_f (n - 1) / n``: 2.83 A_f for three storeys, close to the effective mass
    area 2.5 A_f of ISO 13790 Table 12 (medium class).

    Parameters
    ----------
    floor_area : float [m2] heated floor area.
    floors : int [-] number of heated storeys.
    """
    n = max(int(floors), 1)
    return floor_area * (PARTITION_AND_FURNITURE_AREA_PER_FLOOR_AREA + 2.0 * (n - 1) / n)


#: Bounds of areal heat capacities [kJ/(m2 K)]: opaque elements from ISO 52016-1 Table B.14
#: (very light 50 .. very heavy 250, widened by a factor 2 either side); per m2 of floor area
#: for internal mass (ISO 13790 Table 12: 80 .. 370), air + furniture (ISO 52016-1 6.5.5.2:
#: 10 kJ/(m2 K)) and the heating system (radiators: water + steel; floor heating: screed).
AREAL_CAPACITY_BOUNDS: dict[str, tuple[float, float, float]] = {
    # name: (lower, initial, upper)
    "C_env": (20.0, 110.0, 500.0),
    "C_gf": (20.0, 175.0, 500.0),
    "C_im": (10.0, 80.0, 400.0),
    "C_i": (2.0, 10.0, 40.0),
}
HEATING_CAPACITY_BOUNDS: dict[str, tuple[float, float, float]] = {
    "radiators": (0.3, 2.0, 15.0),
    "convectors": (0.1, 0.5, 5.0),
    "floor_heating": (20.0, 80.0, 200.0),
}


def element_conductances(area, u_value, r_si, r_se):
    """Split a construction's ``U A`` into the inner and outer conductance of a mid-mass node.

    Parameters
    ----------
    area : float or array [m2]
    u_value : float or array [W/(m2 K)]
        Thermal transmittance including the surface resistances.
    r_si, r_se : float [m2 K/W]
        Internal and external surface resistances.

    Returns
    -------
    h_in, h_out : [W/K]
        ``A/Rsi (+) 2Hc`` and ``2Hc (+) A/Rse`` with ``Hc = A / (1/U - Rsi - Rse)``; their
        series connection is ``U A``.
    solar_share : [-]
        Share ``2Hc / (A/Rse + 2Hc)`` of radiation absorbed at the outer surface that enters
        the mass node.

    References
    ----------
    ISO 6946:2017, 6.7.1 (total resistance = Rsi + sum of layer resistances + Rse).
    """
    area = np.asarray(area, dtype=float)
    u_value = np.asarray(u_value, dtype=float)
    r_cond = 1.0 / u_value - r_si - r_se
    r_cond = np.maximum(r_cond, 1e-3)  # single glazing-like elements: conduction negligible
    h2 = 2.0 * area / r_cond
    h_in = 1.0 / (r_si / area + 1.0 / h2)
    h_out = 1.0 / (r_se / area + 1.0 / h2)
    share = h2 / (area / r_se + h2)
    return h_in, h_out, share


@dataclass(frozen=True)
class GroundPath:
    """Boundary side of the ground element: conductances from the cellar (or slab) outward."""

    to_ground: float  # [W/K] cellar -> Tgr (basement floor and walls below grade)
    to_air: float  # [W/K] cellar -> Te (walls above grade, cellar ventilation)
    kind: str  # "unheated_basement", "heated_basement" or "slab"


#: Change of the linear thermal transmittance of the wall / slab-on-ground junction when a
#: heavy slab next to an uninsulated heavy wall gets insulation on its underside [W/(m K)]:
#: 0.80 - 0.39 (default values of the floor / wall junction, "méthode 3CL-DPE 2021",
#: arrêté du 31 mars 2021, annexe 1, 3.4.1: wall not insulated, floor not insulated 0.39,
#: floor insulated underneath "en sous face" 0.80; the table's default when the position of
#: a floor's insulation is unknown). The table does not state its soil; taken as ISO 13370's
#: default, 2.0 W/(m K). The junction's heat flows through the ground, so for another soil it
#: scales with the soil's conductivity (as ISO 13370 Annex B's edge-insulation psi values
#: do). ISO 13370 (7.2) leaves this junction to a psi value of ISO 14683 / EN ISO 10211 and
#: counts it in the ground's coefficient, ``H_g = A U + P psi_g``; its floor U-value alone
#: lets the insulation act over the whole floor.
SLAB_EDGE_PSI_CHANGE = 0.41
#: Soil conductivity of the tabulated junction values [W/(m K)].
SLAB_EDGE_PSI_SOIL = 2.0


@dataclass(frozen=True)
class EnvelopeComponents:
    """Areas [m2] and U-values [W/(m2 K)] of the retrofit-relevant components."""

    roof_area: float
    roof_u: float
    walls_area: float
    walls_u: float
    windows_area: float
    windows_u: float
    floor_area: float  # cellar ceiling or ground floor
    floor_u: float
    floor_kind: str  # "cellar_ceiling" or "ground_floor"
    windows_g_factor: float = 1.0  # [-] g-value after / before retrofit (window solar gains)
    h_est_change: float = 0.0  # [W/K] change of the ventilation part of H_est (measures)
    # towards unheated spaces (ISO 13789 temperature adjustment factor b): part of env
    attic_area: float = 0.0  # ceiling under an unheated attic
    attic_u: float = 1.0
    attic_b: float = 1.0
    adjacent_area: float = 0.0  # walls to an unheated garage, staircase, ...
    adjacent_u: float = 1.0
    adjacent_b: float = 1.0
    # slab on ground: exposed perimeter [m] and the junction's psi change [W/(m K)] that
    # insulating the floor adds; after such a measure the junction's conductance [W/K] joins
    # the ground path (ISO 13370: H_g = A U + P psi_g)
    floor_perimeter: float = 0.0
    floor_edge_psi: float = 0.0
    floor_edge_conductance: float = 0.0
    # a floor on the ground: the data's correction of the ground path as a whole [-] (its
    # loss is the soil's far more than the slab's construction); measures add their
    # insulation in series with the corrected path
    floor_factor: float = 1.0
    # ground path of this envelope when it differs from the model's (uncertainty draws of
    # the soil conductivity and the basement air change); None: the model's
    ground: GroundPath | None = None

    def with_measures(self, u_values: dict[str, float]) -> EnvelopeComponents:
        """Copy with the U-values of the given measures replaced (capacities unchanged)."""
        key = {
            "roof": "roof_u",
            "walls": "walls_u",
            "windows": "windows_u",
            "cellar_ceiling": "floor_u",
            "ground_floor": "floor_u",
            "attic_ceiling": "attic_u",
            "wall_to_unheated": "adjacent_u",
        }
        return replace(self, **{key[m]: float(u) for m, u in u_values.items()})

    def apply(
        self,
        measures,
        *,
        volume: float,
        windows_g: float | None = None,
        audit: EnvelopeComponents | None = None,
    ):
        """Copy with retrofit measures applied.

        An opaque construction gets insulation: the layer that takes the described (audit)
        construction to the measure's U-value, ``Delta R = 1/U_target - 1/U_audit``, added to
        the construction as it is here, ``U = 1 / (1/U + Delta R)``. On the audit envelope that
        is the target; on an envelope the data corrected
        (:func:`thermocal.retrofit.correction.scaled_envelope`, or an uncertainty draw) the
        correction stays: a wall the data find 30 % better than described is still better than
        the target after the same insulation. (Taking the target instead would undo the
        correction, and a retrofit to a target above the corrected U-value would make the
        construction worse: the first EnergyPlus twin's attic ceiling, corrected to 0.097
        W/(m2 K), "retrofitted" to 0.10.)

        Windows are replaced, and the data's correction of the old ones is kept as what the new
        ones share with them, their surface films and frame: a series resistance
        ``R_c = 1/U - 1/U_audit``, so ``U = 1 / (1/U_target + R_c)`` (:func:`replaced_window_u`;
        none when the data find the old windows worse than described: that goes with them).
        A rated U-value holds at the rating's films (a strong wind outside); in the building
        the films are weaker and a poor window gains relatively more from them than a good
        one: on the DOE basement house EnergyPlus's windows conduct 1.36 W/(m2 K) against the
        rated 1.70, and after the measure 0.69 against 0.76, where the series resistance gives
        0.683 (the target itself 0.76, the factor on the target 0.61).

        Parameters
        ----------
        measures : iterable of :class:`thermocal.retrofit.strategies.Measure`
        volume : float [m3]
            Heated air volume (ventilation measures).
        windows_g : float [-], optional
            Area-weighted g-value of the windows before the retrofit (g-value measures).
        audit : EnvelopeComponents, optional
            The described envelope the measures' insulation was sized on (default: this one).
        """
        env = self
        audit = audit or self
        for m in measures:
            if m.u_value is not None:
                u = float(m.u_value)
                attr = MEASURE_TARGETS[m.component][0]
                u_audit = float(getattr(audit, attr))
                u_now = float(getattr(env, attr))
                if m.component == "windows":
                    u = replaced_window_u(u, u_now, u_audit)
                elif u_audit > 0 and u_now > 0:
                    u = 1.0 / (1.0 / u_now + (1.0 / u - 1.0 / u_audit))
                env = env.with_measures({m.component: u})
                if m.component == "ground_floor" and env.floor_edge_psi > 0:
                    # the edge of the slab stays uninsulated (ISO 13370 7.2, ISO 14683)
                    env = replace(
                        env, floor_edge_conductance=env.floor_edge_psi * env.floor_perimeter
                    )
            if m.g_value is not None:
                if not windows_g:
                    raise ThermocalInputError(
                        f"measure {m.name!r} sets a window g-value but the building has no "
                        "window g-value to start from"
                    )
                env = replace(env, windows_g_factor=env.windows_g_factor * m.g_value / windows_g)
            change = m.heat_loss_change(volume)
            if change:
                env = replace(env, h_est_change=env.h_est_change + change)
        return env


def replaced_window_u(u_target: float, u_now: float, u_audit: float) -> float:
    """U-value of a new window that replaces windows the data corrected [W/(m2 K)].

    The correction of the old windows (``u_now`` against the described ``u_audit``) is taken
    as their surface films' and frame's, which the new window shares: a series resistance
    ``R_c = 1/u_now - 1/u_audit`` added to the new window's rated resistance, ``1 / (1 /
    u_target + R_c)``. Films only add resistance to a rating's (whose outside film is a strong
    wind's), so a correction that finds the old windows worse than described (``R_c < 0``:
    their glazing, seals or frame) goes with them: the new window then takes its target.

    Parameters
    ----------
    u_target : float [W/(m2 K)]
        The measure's (rated) U-value of the new window.
    u_now : float [W/(m2 K)]
        The old windows as the data corrected them (or as an uncertainty draw has them).
    u_audit : float [W/(m2 K)]
        The old windows as described.

    Returns
    -------
    float [W/(m2 K)]
        The new window's U-value in the building, at most ``u_target``.
    """
    if not (u_now > 0 and u_audit > 0 and u_target > 0):
        return float(u_target)
    films = max(1.0 / u_now - 1.0 / u_audit, 0.0)
    return float(1.0 / (1.0 / u_target + films))


def check_ventilation_measures(strategies, measures, volume: float, h_est: float) -> list[str]:
    """Refuse airtightness measures that remove more ventilation loss than the calibrated house
    has; note a strategy whose ventilation measures together reach beyond it.

    ``H_est`` (the estimated loss beyond the envelope: ventilation, infiltration and the rest
    the calibration put there) bounds what tightening can remove; beyond it the demand
    simulation clips the loss at zero, so a change of -0.6 1/h and of -3 1/h (an n50
    difference written as a natural air change) gave the same saving without a word. With
    heat recovery on top the simple sum ``dn - n_hr eta`` over-states the reduction (the
    mechanical air replaces natural air that tightening already removed); such a strategy is
    clipped at zero as before, and said.

    Parameters
    ----------
    strategies : iterable of :class:`~thermocal.retrofit.strategies.Strategy`
    measures : dict name -> :class:`~thermocal.retrofit.strategies.Measure`
    volume : float
        Heated air volume [m3].
    h_est : float
        The calibrated ``H_est`` [W/K].

    Returns
    -------
    list of str
        A note per strategy whose ventilation measures together reach beyond ``H_est``.

    Raises
    ------
    ThermocalInputError
        An airtightness measure beyond ``H_est``, naming the air change it allows.
    """
    from thermocal.retrofit.strategies import AIR_HEAT_CAPACITY_WH_PER_M3K

    per_air_change = AIR_HEAT_CAPACITY_WH_PER_M3K * float(volume)  # [W/K per 1/h]
    allowed = h_est / per_air_change
    for name, m in measures.items():
        if m.component == "airtightness" and -m.air_change_rate_change > allowed * (1 + 1e-9):
            raise ThermocalInputError(
                f"measures.{name}: air_change_rate_change {m.air_change_rate_change:g} 1/h "
                f"removes more ventilation loss than the calibrated house has: H_est "
                f"{h_est:.0f} W/K, about {allowed:.2f} 1/h for {volume:.0f} m3. An n50 "
                "difference (at 50 Pa) is about 20 times the natural air change: divide it by "
                f"about 20; give at most -{allowed:.2f}"
            )
    notes = []
    for strategy in strategies:
        change = sum(measures[m].heat_loss_change(volume) for m in strategy.measures)
        if change < 0.0 and -change > h_est * (1.0 + 1e-9):
            notes.append(
                f"strategy {strategy.code}: its ventilation measures together remove "
                f"{-change:.0f} W/K, more than the calibrated H_est ({h_est:.0f} W/K); the "
                "demand simulation keeps the ventilation loss at zero, not below"
            )
    return notes


#: Envelope attribute (U-value) and floor kind of every U-value measure component.
MEASURE_TARGETS: dict[str, tuple[str, str | None]] = {
    "roof": ("roof_u", None),
    "walls": ("walls_u", None),
    "windows": ("windows_u", None),
    "cellar_ceiling": ("floor_u", "cellar_ceiling"),
    "ground_floor": ("floor_u", "ground_floor"),
    "attic_ceiling": ("attic_u", None),
    "wall_to_unheated": ("adjacent_u", None),
}
_BUILDING_TYPE = {"roof": "roof", "walls": "external_wall", "windows": "window"}


def check_measures(envelope: EnvelopeComponents, measures, building_name: str = "") -> None:
    """Refuse a measure on a component the building lacks, or one that does not improve it.

    Parameters
    ----------
    envelope : EnvelopeComponents
        The building file's envelope.
    measures : dict name -> :class:`~thermocal.retrofit.strategies.Measure`

    Raises
    ------
    ThermocalInputError
        Naming the configuration key ``measures.<name>`` and what to do.
    """
    for name, m in measures.items():
        if m.u_value is None or m.component not in MEASURE_TARGETS:
            continue
        attr, kind = MEASURE_TARGETS[m.component]
        area = getattr(envelope, attr.replace("_u", "_area"))
        if kind is not None and envelope.floor_kind != kind:
            other = "ground_floor" if kind == "cellar_ceiling" else "cellar_ceiling"
            what = {
                "cellar_ceiling": "a ceiling over an unheated cellar",
                "ground_floor": "a floor on the ground (slab)",
            }
            raise ThermocalInputError(
                f"measures.{name}: the measure insulates {what[kind]} (component {kind}), but "
                f"building {building_name!r} has {what[envelope.floor_kind]}; give the "
                f"measure as component {other} (e.g. measures: {{{other}: {{u_value: "
                f"{m.u_value:g}}}}}) or remove it"
                + (
                    " (the default measures are the method's, with a cellar ceiling)"
                    if name == "cellar_ceiling"
                    else ""
                )  # fmt: skip
            )
        if area <= 0:
            raise ThermocalInputError(
                f"measures.{name}: building {building_name!r} has no "
                f"{_BUILDING_TYPE.get(m.component, m.component)} component to retrofit; "
                "remove the measure or add the component to the building file"
            )
        current = float(getattr(envelope, attr))
        if not m.u_value < current:
            raise ThermocalInputError(
                f"measures.{name}: target U-value {m.u_value:g} W/(m2 K) is not better than the "
                f"existing {m.component.replace('_', ' ')} ({current:.3g} W/(m2 K), area-"
                "weighted from the building file): the measure would worsen or keep the "
                "envelope and cost money; lower measures."
                f"{name}.u_value below {current:.3g} or remove the measure"
            )


def _area_weighted_u(components) -> tuple[float, float]:
    area = sum(float(c.area) for c in components)
    if area <= 0:
        return 0.0, 1.0
    return area, sum(float(c.area) * float(c.u_value) for c in components) / area


def envelope_from_building(building) -> EnvelopeComponents:
    """Aggregate the building file's components into roof, walls, windows and floor."""

    def of(kind):
        return [c for c in building.components if c.type == kind]

    roof_a, roof_u = _area_weighted_u(of("roof"))
    wall_a, wall_u = _area_weighted_u(of("external_wall"))
    win_a, win_u = _area_weighted_u(of("window"))
    cel_a, cel_u = _area_weighted_u(of("cellar_ceiling"))
    gfl_a, gfl_u = _area_weighted_u(of("ground_floor"))
    attic = _adjacent(of("attic_ceiling"))
    adjacent = _adjacent(of("wall_to_unheated"))
    if wall_a + roof_a + attic[0] + adjacent[0] <= 0:
        raise ThermocalInputError(
            f"building {building.name!r} has no roof, external_wall, attic_ceiling or "
            "wall_to_unheated components: the env element of the fifth-order model needs one"
        )
    if cel_a > 0:
        floor = (cel_a, cel_u, "cellar_ceiling")
    elif gfl_a > 0:
        floor = (gfl_a, gfl_u, "ground_floor")
    else:
        raise ThermocalInputError(
            f"building {building.name!r} has neither a cellar_ceiling nor a ground_floor "
            "component: the gf element of the fifth-order model needs one"
        )
    return EnvelopeComponents(
        roof_a, roof_u, wall_a, wall_u, win_a, win_u, *floor,
        attic_area=attic[0], attic_u=attic[1], attic_b=attic[2],
        adjacent_area=adjacent[0], adjacent_u=adjacent[1], adjacent_b=adjacent[2],
    )  # fmt: skip


def _adjacent(components) -> tuple[float, float, float]:
    """Area [m2], area-weighted U [W/(m2 K)] and UA-weighted b [-] towards unheated spaces."""
    area, u = _area_weighted_u(components)
    ua = sum(float(c.area) * float(c.u_value) for c in components)
    b = (
        sum(float(c.area) * float(c.u_value) * float(c.b_factor) for c in components) / ua
        if ua
        else 1.0
    )
    return area, u, b


def ground_path(
    building,
    envelope: EnvelopeComponents,
    *,
    soil_conductivity: float | None = None,
    basement_air_changes: float | None = None,
) -> GroundPath:
    """ISO 13370 conductances between the cellar (or below-slab) and the boundaries [W/K].

    Parameters
    ----------
    building : thermocal.io.envelope.EnvelopeDescription
    envelope : EnvelopeComponents
    soil_conductivity : float [W/(m K)], optional
        Instead of the building file's ``ground.soil_conductivity`` (uncertainty draws).
    basement_air_changes : float [1/h], optional
        Instead of the building file's ``ground.basement_air_change_rate``.
    """
    g = building.ground
    if g is None:
        raise ThermocalInputError(
            f"building {building.name!r}: the ground section (perimeter, wall_thickness, "
            "basement, ...) is needed for the ISO 13370 ground path of the gf element"
        )
    basement = g.basement
    lam = float(g.soil_conductivity if soil_conductivity is None else soil_conductivity)
    perimeter = float(g.perimeter)
    w = float(g.wall_thickness)
    area = float(g.floor_area or envelope.floor_area)
    if envelope.floor_kind == "cellar_ceiling":
        if basement == "heated":
            raise ThermocalInputError(
                "building file: a cellar_ceiling component with ground.basement 'heated' is "
                "contradictory; use 'unheated' (cellar below the heated floors)"
            )
        depth = float(g.basement_depth) if g.basement_depth > 0 else 2.0
        # uninsulated 1950s concrete unless the file says otherwise
        u_floor = float(g.basement_floor_u_value or 2.5)
        u_wall = float(g.basement_wall_u_value or 1.8)
        r_floor = max(1.0 / u_floor - R_SI["downward"] - R_SE, 0.0)
        r_wall = max(1.0 / u_wall - R_SI["horizontal"] - R_SE, 0.0)
        h_above = float(g.basement_wall_height_above_ground)
        ach = float(
            g.basement_air_change_rate if basement_air_changes is None else basement_air_changes
        )
        volume = float(g.basement_volume or area * (depth + h_above))
        from thermocal.physics.ground import iso13370_unheated_basement

        parts = iso13370_unheated_basement(
            area, perimeter, depth, u_ceiling=envelope.floor_u, wall_thickness=w,
            u_wall_above_ground=u_wall, height_above_ground=h_above, basement_volume=volume,
            air_changes=ach, floor_resistance=r_floor, wall_resistance=r_wall,
            soil_conductivity=lam,
        )  # fmt: skip
        # split the basement's losses: floor and walls below grade -> ground; walls above
        # grade and ventilation -> outdoor air
        to_ground = area * parts["u_floor"] + depth * perimeter * parts["u_wall"]
        to_air = parts["basement_loss_coefficient"] - to_ground
        return GroundPath(to_ground, to_air, "unheated_basement")
    r_floor = max(1.0 / envelope.floor_u - R_SI["downward"] - R_SE, 0.0)
    if basement == "heated" and float(g.basement_depth) > 0:
        from thermocal.physics.ground import iso13370_heated_basement

        u_wall = float(g.basement_wall_u_value or 1.8)
        r_wall = max(1.0 / u_wall - R_SI["horizontal"] - R_SE, 0.0)
        parts = iso13370_heated_basement(
            area, perimeter, float(g.basement_depth), wall_thickness=w,
            floor_resistance=r_floor, wall_resistance=r_wall, soil_conductivity=lam,
        )  # fmt: skip
        return GroundPath(float(parts["heat_transfer_coefficient"]), 0.0, "heated_basement")
    from thermocal.physics.ground import iso13370_slab_on_ground

    u_slab = iso13370_slab_on_ground(
        area, perimeter, wall_thickness=w, floor_resistance=r_floor, soil_conductivity=lam
    )
    return GroundPath(u_slab * area, 0.0, "slab")


def _series(*conductances):
    return 1.0 / sum(1.0 / np.asarray(h, dtype=float) for h in conductances)


@dataclass
class FifthOrderModel:
    """The calculated part of the fifth-order model plus bounds of the estimated part.

    Build it with :func:`build_fifth_order_model`; :meth:`conductances` recomputes the
    calculated conductances for other U-values (retrofits).
    """

    envelope: EnvelopeComponents
    ground: GroundPath
    heating_conductance: float  # Hh [W/K]
    internal_mass_conductance: float  # Him [W/K]
    solar_to_internal_mass: float  # f_im [-]
    estimated: dict[str, tuple[float, float, float, str]] = field(default_factory=dict)
    # name -> (lower, initial, upper, unit)
    audit_h_est: float = 0.0  # [W/K] calculated prior of Hest (ventilation, bridges, doors)
    fixed: frozenset = frozenset()  # estimated parameters held at their initial value
    volume: float = 0.0  # [m3] heated air volume (ventilation measures)
    windows_g: float | None = None  # [-] area-weighted g-value of the windows
    bounds_source: dict = field(default_factory=dict)  # name -> "building file" / "configuration"
    #: the room's inside (:mod:`thermocal.retrofit.interior`): "combined" (the method's
    #: surface resistances to the air) or "split" (convection to the air, radiation among the
    #: surfaces)
    interior: str = "combined"
    #: in-situ U-values (:mod:`thermocal.retrofit.in_situ`): component -> mean and standard
    #: deviation of ``ln k``, its own correction factor's prior (measured / described U)
    in_situ: dict = field(default_factory=dict)

    def apply_measures(self, measures, envelope: EnvelopeComponents | None = None):
        """The envelope after the given :class:`~thermocal.retrofit.strategies.Measure` s."""
        return (envelope or self.envelope).apply(
            measures, volume=self.volume, windows_g=self.windows_g, audit=self.envelope
        )

    def conductances(self, envelope: EnvelopeComponents | None = None) -> dict[str, float]:
        """Calculated conductances [W/K] (and solar shares [-]) for the given U-values."""
        out, surfaces = self._elements(envelope)
        out.update(self._interior_pairs(out, surfaces))
        return out

    def _elements(self, envelope: EnvelopeComponents | None = None):
        """The elements' conductances [W/K] and shares [-], and each inner surface as (node,
        area [m2], conductance through ``Rsi`` [W/K], heat-flow direction)."""
        env = envelope or self.envelope
        ground = env.ground if env.ground is not None else self.ground
        out: dict[str, float] = {}
        surfaces: list[tuple[str, float, float, str]] = []  # node, A, combined, flow
        r_in, r_out, s_roof = element_conductances(
            max(env.roof_area, 1e-9), env.roof_u, R_SI["upward"], R_SE
        )
        w_in, w_out, s_walls = element_conductances(
            max(env.walls_area, 1e-9), env.walls_u, R_SI["horizontal"], R_SE
        )
        if env.roof_area <= 0:
            r_in = r_out = s_roof = 0.0
        else:
            surfaces.append(("Tenv", env.roof_area, float(r_in), "upward"))
        if env.walls_area <= 0:
            w_in = w_out = s_walls = 0.0
        else:
            surfaces.append(("Tenv", env.walls_area, float(w_in), "horizontal"))
        # towards unheated spaces: the effective U-value b U (ISO 13789), surface resistance
        # Rsi on both sides (ISO 6946 Table 7 note), no solar radiation
        for area, u, b, flow in (
            (env.attic_area, env.attic_u, env.attic_b, "upward"),
            (env.adjacent_area, env.adjacent_u, env.adjacent_b, "horizontal"),
        ):
            if area > 0:
                a_in, a_out, _ = element_conductances(area, b * u, R_SI[flow], R_SI[flow])
                r_in, r_out = r_in + a_in, r_out + a_out
                surfaces.append(("Tenv", area, float(a_in), flow))
        out["H_env_in"] = float(r_in + w_in)
        out["H_env_out"] = float(r_out + w_out)
        out["share_roof"] = float(s_roof)
        out["share_walls"] = float(s_walls)
        out["H_win"] = float(env.windows_area * env.windows_u)
        if ground.kind == "unheated_basement":
            # floor above an unheated space: Rse = Rsi (ISO 6946 Table 7 note)
            g_in, g_out, _ = element_conductances(
                env.floor_area, env.floor_u, R_SI["downward"], R_SI["downward"]
            )
            total = g_out + ground.to_ground + ground.to_air
            out["H_gf_in"] = float(g_in)
            out["H_gf_gr"] = float(g_out * ground.to_ground / total)
            out["H_gf_e"] = float(g_out * ground.to_air / total)
            surfaces.append(("Tgf", env.floor_area, float(g_in), "downward"))
        else:
            # under-slab insulation lies below the slab's mass: the room's side of the floor
            # keeps the described construction's inner half
            construction_u = (
                self.envelope.floor_u if self.envelope.floor_kind == "ground_floor" else env.floor_u
            )
            r_cond = max(1.0 / construction_u - R_SI["downward"] - R_SE, 1e-3)
            g_in = 1.0 / (R_SI["downward"] / env.floor_area + 0.5 * r_cond / env.floor_area)
            if self.envelope.floor_kind == "ground_floor" and env is not self.envelope:
                # the ground path as the data corrected it (floor_factor), then the retrofit's
                # resistance in series: Delta R from the change in the construction's U
                u13370 = env.floor_factor * ground.to_ground / self.envelope.floor_area
                d_r = 1.0 / env.floor_u - 1.0 / self.envelope.floor_u
                u13370 = 1.0 / (1.0 / u13370 + d_r)
                total = u13370 * env.floor_area + env.floor_factor * env.floor_edge_conductance
            else:
                total = ground.to_ground
            # a heated basement's walls can conduct more than the floor's inner half: then
            # the node moves towards the inside so the series still equals the ground U A
            g_in = max(g_in, 2.0 * total)
            out["H_gf_in"] = float(g_in)
            out["H_gf_gr"] = float(1.0 / (1.0 / total - 1.0 / g_in))
            out["H_gf_e"] = 0.0
            surfaces.append(("Tgf", env.floor_area, float(g_in), "downward"))
        out["H_h"] = float(self.heating_conductance)
        out["H_im"] = float(self.internal_mass_conductance)
        out["f_im"] = float(self.solar_to_internal_mass)
        out["g_factor"] = float(env.windows_g_factor)
        out["H_est_change"] = float(env.h_est_change)
        if env.windows_area > 0:
            surfaces.append(("Te", env.windows_area, out["H_win"], "horizontal"))
        return out, surfaces

    def _interior_pairs(self, h: dict, surfaces) -> dict[str, float]:
        """The inside's pair conductances ``G_<a>_<b>`` [W/K] (:mod:`~thermocal.retrofit.
        interior`) and the flag ``interior_split`` (1.0 for the split inside)."""
        if self.interior != "split":
            pairs = dict.fromkeys(INTERIOR_PAIR_NAMES, 0.0)
            pairs.update(G_Ti_Tenv=h["H_env_in"], G_Ti_Tgf=h["H_gf_in"], G_Ti_Tim=h["H_im"],
                         G_Ti_Te=h["H_win"], interior_split=0.0)  # fmt: skip
            return pairs
        return {**self.interior_network(surfaces).pairs, "interior_split": 1.0}

    def interior_network(self, surfaces):
        """The split inside of the given surfaces, reduced (a :class:`~thermocal.retrofit.
        interior.ReducedInterior`).

        Parameters
        ----------
        surfaces : sequence of (node, area [m2], combined conductance [W/K], heat-flow
            direction) per component, the combined conductance the one through ``Rsi``.
        """
        from thermocal.retrofit.interior import InteriorSurface, inner_conduction, reduce_interior

        parts = [
            InteriorSurface(
                node=node,
                convection=area * H_CI[flow],
                radiation=area * (1.0 / R_SI[flow] - H_CI[flow]),
                conduction=inner_conduction(combined, area, R_SI[flow]),
            )
            for node, area, combined, flow in surfaces
        ]
        # the internal mass: its surface is its node; the same coefficients as H_im
        area_im = self.internal_mass_conductance / (H_CI["horizontal"] + H_RI)
        return reduce_interior(parts, area_im * H_CI["horizontal"], area_im * H_RI)

    def reduced_interior(self, envelope: EnvelopeComponents | None = None):
        """The split inside of the given U-values (a :class:`~thermocal.retrofit.interior.
        ReducedInterior`); None for the combined inside."""
        if self.interior != "split":
            return None
        return self.interior_network(self._elements(envelope)[1])

    def calculated_heat_loss_coefficient(self, envelope: EnvelopeComponents | None = None) -> float:
        """Steady-state HLC [W/K] of the calculated conductances (without Hest)."""
        h = self.conductances(envelope)
        return calculated_hlc(h)


def calculated_hlc(h: dict[str, float]) -> float:
    """Steady-state conductance [W/K] of the calculated paths from ``Ti`` to all boundaries."""
    if h.get("interior_split"):
        from thermocal.retrofit.interior import steady_heat_loss

        return steady_heat_loss(h)
    env = _series(h["H_env_in"], h["H_env_out"]) if h["H_env_in"] > 0 else 0.0
    gf = _series(h["H_gf_in"], h["H_gf_gr"] + h["H_gf_e"])
    return float(env + h["H_win"] + gf)


def build_fifth_order_model(
    building,
    *,
    solar_to_internal_mass: float = 0.5,
    bounds: dict[str, tuple[float, float]] | None = None,
    fixed: dict[str, float] | None = None,
    interior: str = "combined",
) -> FifthOrderModel:
    """Calculated conductances and estimation bounds of the fifth-order model for a building.

    Parameters
    ----------
    building : thermocal.io.envelope.EnvelopeDescription
    solar_to_internal_mass : float [-]
        Fraction of the window solar gains absorbed by the internal mass.
    bounds : dict name -> (lower, upper), optional
        Estimation bounds replacing the defaults: ``H_est`` [W/K], capacities [MJ/K].
    fixed : dict name -> value, optional
        Parameters held at a value instead of estimated (same units).
    interior : {"combined", "split"}
        The room's inside (:mod:`thermocal.retrofit.interior`): the method's combined surface
        resistances to the air, or convection to the air and radiation among the surfaces.

    Returns
    -------
    FifthOrderModel
    """
    from thermocal.retrofit.interior import INTERIOR_FORMS

    if interior not in INTERIOR_FORMS:
        raise ThermocalInputError(
            f"model.interior {interior!r}: use one of {', '.join(INTERIOR_FORMS)}"
        )
    envelope = envelope_from_building(building)
    ground = ground_path(building, envelope)
    if ground.kind == "slab" and envelope.floor_kind == "ground_floor":
        envelope = replace(
            envelope, floor_perimeter=float(building.ground.perimeter),
            floor_edge_psi=SLAB_EDGE_PSI_CHANGE * float(building.ground.soil_conductivity)
            / SLAB_EDGE_PSI_SOIL,
        )  # fmt: skip
    floor_area = float(building.heated_floor_area)
    if floor_area <= 0:
        raise ThermocalInputError("building file: heated_floor_area must be > 0 m2")
    emitter = building.emitter  # validated by thermocal.io.envelope (EmitterType)
    if emitter not in EMITTERS:
        raise ThermocalInputError(
            f"building file: emitter {emitter!r} unknown; use one of {sorted(EMITTERS)}"
        )
    a_frac, h_em = EMITTERS[emitter]
    h_h = a_frac * floor_area * h_em
    h_im = internal_mass_area(floor_area, building.floors) * (H_CI["horizontal"] + H_RI)

    # prior of Hest: the description's air change (default 0.5 1/h), thermal bridges, doors
    volume = float(building.volume)
    opaque = (
        envelope.roof_area + envelope.walls_area + envelope.floor_area + envelope.attic_area
        + envelope.adjacent_area
    )  # fmt: skip
    bridges = float(building.thermal_bridge_allowance) * opaque
    doors = sum(float(c.area) * float(c.u_value) for c in building.components if c.type == "door")
    from thermocal.retrofit.strategies import AIR_HEAT_CAPACITY_WH_PER_M3K as air

    h_est0 = air * float(building.air_change_rate) * volume + bridges + doors
    h_est_lo = air * 0.05 * volume + 0.25 * bridges + doors * 0.5
    h_est_hi = air * 3.0 * volume + 4.0 * bridges + 2.0 * doors
    estimated: dict[str, tuple[float, float, float, str]] = {
        "H_est": (h_est_lo, h_est0, h_est_hi, "W/K")
    }
    area_of = {
        "C_env": envelope.roof_area
        + envelope.walls_area
        + envelope.attic_area
        + envelope.adjacent_area,
        "C_gf": envelope.floor_area,
        "C_im": floor_area,
        "C_i": floor_area,
    }
    for name, (lo, ini, hi) in AREAL_CAPACITY_BOUNDS.items():
        a = area_of[name]
        estimated[name] = (lo * a / 1000.0, ini * a / 1000.0, hi * a / 1000.0, "MJ/K")
    lo, ini, hi = HEATING_CAPACITY_BOUNDS[emitter]
    estimated["C_h"] = (
        lo * floor_area / 1000,
        ini * floor_area / 1000,
        hi * floor_area / 1000,
        "MJ/K",
    )
    # the air itself is the least capacity of C_i
    lo_i, ini_i, hi_i, unit = estimated["C_i"]
    estimated["C_i"] = (max(lo_i, 1.2e-3 * volume), max(ini_i, 2.4e-3 * volume), hi_i, unit)
    source = {name: "building file" for name in estimated}
    for name, (lo, hi) in (bounds or {}).items():
        _, ini, _, unit = estimated[name]
        pad = 0.01 * (hi - lo)
        estimated[name] = (float(lo), float(min(max(ini, lo + pad), hi - pad)), float(hi), unit)
        source[name] = "configuration (model.bounds)"
    for name, value in (fixed or {}).items():
        lo, _, hi, unit = estimated[name]
        estimated[name] = (min(lo, 0.5 * value), float(value), max(hi, 2.0 * value), unit)
        source[name] = "fixed (model.fixed)"
    windows = [c for c in building.components if c.type == "window"]
    win_area = sum(float(c.area) for c in windows)
    windows_g = (
        sum(float(c.area) * float(c.g_value or 0.0) for c in windows) / win_area
        if win_area > 0 else None
    )  # fmt: skip
    return FifthOrderModel(
        envelope=envelope,
        ground=ground,
        heating_conductance=float(h_h),
        internal_mass_conductance=float(h_im),
        solar_to_internal_mass=float(solar_to_internal_mass),
        estimated=estimated,
        audit_h_est=float(h_est0),
        fixed=frozenset(fixed or ()),
        volume=volume,
        windows_g=windows_g,
        bounds_source=source,
        interior=interior,
    )


#: The calculated conductances [W/K] and dimensionless factors of the network, as they are
#: named in :meth:`FifthOrderModel.conductances` and in the RC network of :func:`network_spec`.
CALCULATED_CONDUCTANCES: tuple[str, ...] = (
    "H_env_in", "H_env_out", "H_win", "H_gf_in", "H_gf_gr", "H_gf_e", "H_h", "H_im",
    "G_Ti_Tenv", "G_Ti_Tgf", "G_Ti_Tim", "G_Ti_Te", "G_Tenv_Tgf", "G_Tenv_Tim", "G_Tenv_Te",
    "G_Tgf_Tim", "G_Tgf_Te", "G_Tim_Te",
)  # fmt: skip
CALCULATED_FACTORS: tuple[str, ...] = ("share_roof", "share_walls", "f_im", "g_factor")


def network_spec(h: dict, *, demand: bool = False, calculated_as_parameters: bool = False) -> dict:
    """The fifth-order RC network as a :class:`thermocal.statespace.RCModel` specification.

    The one definition of the model's network: the calibration fits it, the validation
    simulates it and the demand simulation takes its matrices from it.

    Parameters
    ----------
    h : dict
        Calculated conductances [W/K] and factors [-] (:meth:`FifthOrderModel.conductances`);
        only their sign decides the structure (a window or cellar-to-air path exists when its
        conductance is positive).
    demand : bool
        False: the calibration model, states ``STATE_NAMES``, inputs ``INPUT_NAMES``.
        True: the demand model, states (Ti, Tenv, Tgf, Tim), inputs (Te, Tgr, phi_sol,
        phi_abs_roof, phi_abs_walls, Q) with the heating power ``Q`` [W] delivered directly
        into ``Ti`` (the heating-system node is dropped: its small capacity only shifts heat
        by minutes).
    calculated_as_parameters : bool
        False: the calculated conductances and factors enter as numbers (``h``'s values);
        True: as parameters named after them, so that one compiled network serves every
        retrofit scenario and draw (values given at evaluation).

    Returns
    -------
    dict with ``states``, ``conductances``, ``heat_inputs`` and ``outputs``; the states refer to
    the capacities ``C_i, C_env, C_gf, C_im, C_h``, the diffusions ``sigma_<state>`` and the
    initial means ``<state>0``, the ``Ti``-``Te`` path to ``H_est`` (parameters the caller
    declares).
    """

    def value(name):
        return name if calculated_as_parameters else float(h[name])

    names = STATE_NAMES[:4] if demand else STATE_NAMES
    capacity = {"Ti": "C_i", "Tenv": "C_env", "Tgf": "C_gf", "Tim": "C_im", "Th": "C_h"}
    states = {
        s: {
            "capacity": capacity[s],
            "noise": f"sigma_{s}",
            "initial_mean": f"{s}0",
            "initial_std": 0.5 if s == "Ti" else 2.0,
        }
        for s in names
    }
    if _split(h):
        # the split inside (thermocal.retrofit.interior): its pairs replace the four
        # air-to-element paths
        conductances = [
            {"between": [a, b], "conductance": value(name)}
            for (a, b), name in zip(INTERIOR_PAIRS, INTERIOR_PAIR_NAMES, strict=True)
            if float(np.max(h[name])) > 0
        ]
        conductances += [
            {"between": ["Tenv", "Te"], "conductance": value("H_env_out")},
            {"between": ["Tgf", "Tgr"], "conductance": value("H_gf_gr")},
            {"between": ["Ti", "Te"], "conductance": "H_est"},
        ]
        if not demand:
            conductances.append({"between": ["Ti", "Th"], "conductance": value("H_h")})
    else:
        conductances = [
            {"between": ["Ti", "Tenv"], "conductance": value("H_env_in")},
            {"between": ["Tenv", "Te"], "conductance": value("H_env_out")},
            {"between": ["Ti", "Tgf"], "conductance": value("H_gf_in")},
            {"between": ["Tgf", "Tgr"], "conductance": value("H_gf_gr")},
            {"between": ["Ti", "Tim"], "conductance": value("H_im")},
            {"between": ["Ti", "Te"], "conductance": "H_est"},
        ]
        if not demand:
            conductances.insert(5, {"between": ["Ti", "Th"], "conductance": value("H_h")})
        if float(np.max(h["H_win"])) > 0:
            conductances.append({"between": ["Ti", "Te"], "conductance": value("H_win")})
    if float(np.max(h["H_gf_e"])) > 0:
        conductances.append({"between": ["Tgf", "Te"], "conductance": value("H_gf_e")})
    solar = {"column": "phi_sol", "unit": "W"}
    if calculated_as_parameters:
        solar.update({"into": {"Ti": "rest", "Tim": "f_im"}, "scale": "g_factor"})
    else:
        f_im, g = float(h["f_im"]), float(h.get("g_factor", 1.0))
        solar["into"] = {"Ti": 1.0 - f_im, "Tim": f_im}
        if g != 1.0:
            solar["scale"] = g
    heat_inputs = [] if demand else [{"column": "phi_h", "unit": "W", "into": "Th"}]
    heat_inputs += [
        solar,
        {"column": "phi_abs_roof", "unit": "W", "into": "Tenv", "scale": value("share_roof")},
        {"column": "phi_abs_walls", "unit": "W", "into": "Tenv", "scale": value("share_walls")},
    ]
    if demand:
        heat_inputs.append({"column": "Q", "unit": "W", "into": "Ti"})
    return {
        "states": states,
        "conductances": conductances,
        "heat_inputs": heat_inputs,
        "outputs": [{"column": "Ti_measured", "state": "Ti", "noise": "e_std"}],
    }


_NETWORKS: dict = {}


def _split(h: dict) -> bool:
    """Whether ``h`` describes the split inside (``interior_split`` set in any set)."""
    return float(np.max(h.get("interior_split", 0.0))) > 0


def simulation_network(h: dict, *, demand: bool = False):
    """The compiled :class:`thermocal.statespace.RCModel` of :func:`network_spec` with every
    value a parameter in SI units (W/K, J/K, -), cached per structure."""
    from thermocal.statespace import RCModel

    key = (demand, float(np.max(h["H_win"])) > 0, float(np.max(h["H_gf_e"])) > 0)
    if _split(h):
        key += tuple(float(np.max(h[name])) > 0 for name in INTERIOR_PAIR_NAMES)
    rc = _NETWORKS.get(key)
    if rc is None:
        spec = network_spec(h, demand=demand, calculated_as_parameters=True)
        params: dict[str, dict] = {}
        for s in spec["states"]:
            params[f"sigma_{s}"] = {"value": 0.0, "fixed": True, "unit": "K/sqrt(s)"}
            params[f"{s}0"] = {"value": 20.0, "fixed": True, "unit": "C"}
        params["e_std"] = {"value": 0.1, "fixed": True, "unit": "C"}
        for name in ESTIMATED_PARAMETERS:
            if demand and name == "C_h":
                continue
            unit = "W/K" if name == "H_est" else "J/K"
            params[name] = {"value": 1.0, "lower": 0.0, "upper": 1e15, "unit": unit}
        for name in CALCULATED_CONDUCTANCES:
            params[name] = {"value": 1.0, "fixed": True, "unit": "W/K"}
        for name in CALCULATED_FACTORS:
            params[name] = {"value": 0.5, "fixed": True, "unit": "-", "lower": 0.0,
                            "upper": 1e6 if name == "g_factor" else 1.0}  # fmt: skip
        used = _referenced(spec)
        spec["parameters"] = {n: p for n, p in params.items() if n in used}
        spec.update(name="fifth_order_demand" if demand else "fifth_order_retrofit")
        rc = RCModel.from_dict(spec, source="fifth-order retrofit model")
        rc.structure()
        _NETWORKS[key] = rc
    return rc


def _referenced(spec: dict) -> set[str]:
    """Every text value of a network specification (the parameter names among them)."""
    out: set[str] = set()

    def walk(x):
        if isinstance(x, str):
            out.add(x)
        elif isinstance(x, dict):
            for v in x.values():
                walk(v)
        elif isinstance(x, list | tuple):
            for v in x:
                walk(v)

    walk(spec)
    return out


def _parameter_sets(h: dict, p: dict, indoor_input: bool):
    """The compiled network and the SI values of every parameter set of a batch."""
    values = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in h.items()}
    values.setdefault("H_est_change", np.zeros(1))
    values.setdefault("g_factor", np.ones(1))
    values.update({k: np.atleast_1d(np.asarray(p[k], dtype=float)) for k in ESTIMATED_PARAMETERS})
    n = max(v.shape[0] for v in values.values())
    values = {k: v if v.shape == (n,) else np.broadcast_to(v, (n,)) for k, v in values.items()}
    # retrofit measures on the ventilation part of H_est
    values["H_est"] = np.maximum(values["H_est"] + values["H_est_change"], 0.0)
    rc = simulation_network(values, demand=indoor_input)
    names = [name for name in rc.parameter_names if name in values]
    return rc, [{k: values[k][i] for k in names} for i in range(n)]


def system_matrices(h: dict, p: dict, *, indoor_input: bool = False):
    """Continuous-time matrices of the fifth-order model, batched over parameter sets.

    Each set is evaluated by :meth:`thermocal.statespace.RCModel.continuous_matrices` of the
    network :func:`network_spec` (the same network the calibration fits).

    Parameters
    ----------
    h : dict
        Calculated conductances [W/K] and shares from :meth:`FifthOrderModel.conductances`;
        values may be floats or arrays of shape (n,); optional ``H_est_change`` [W/K] and
        ``g_factor`` [-] (retrofit measures on ventilation and window g-value).
    p : dict
        Estimated parameters in SI: ``H_est`` [W/K], ``C_env``, ``C_gf``, ``C_im``, ``C_i``,
        ``C_h`` [J/K]; floats or arrays of shape (n,).
    indoor_input : bool
        False: the calibration model, states ``STATE_NAMES``, inputs ``INPUT_NAMES``.
        True: the demand model (see :func:`network_spec`), the heating power ``Q`` the LAST
        input column.

    Returns
    -------
    A : ndarray (n, ns, ns) [1/s]
    B : ndarray (n, ns, ni) [K/s per unit input]
    """
    rc, sets = _parameter_sets(h, p, indoor_input)
    ns, ni = len(rc.state_names), len(rc.input_names)
    a = np.empty((len(sets), ns, ns))
    b = np.empty((len(sets), ns, ni))
    for i, values in enumerate(sets):
        a[i], b[i], _, _ = rc.continuous_matrices(values)
    return a, b


def discrete_system_matrices(h: dict, p: dict, dt: float, *, indoor_input: bool = False):
    """Zero-order-hold discrete matrices of the fifth-order model, batched over parameter sets.

    The exact discretisation of the grey-box engine (the one its Kalman filter and
    simulation use: eigen-decomposition of the RC network, ``e^(lambda dt)`` and
    ``(e^(lambda dt) - 1) / lambda`` per mode) applied to :func:`network_spec`.

    Parameters
    ----------
    h, p, indoor_input : as :func:`system_matrices`
    dt : float [s]

    Returns
    -------
    ad : ndarray (n, ns, ns), bd : ndarray (n, ns, ni)
        ``x[k+1] = ad x[k] + bd u[k]`` with ``u`` held constant over ``[t_k, t_k + dt)``.
    """
    from thermocal.statespace import kernels

    rc, sets = _parameter_sets(h, p, indoor_input)
    ns, ni = len(rc.state_names), len(rc.input_names)
    ad = np.empty((len(sets), ns, ns))
    bd = np.empty((len(sets), ns, ni))
    gam1 = np.empty((ns, ni))
    q = np.empty((ns, ns))
    for i, values in enumerate(sets):
        lam, t, tinv, tb, m, *_ = rc.system(values)
        kernels.discretise_from_eigen(lam, t, tinv, tb, m, float(dt), False, ad[i], bd[i], gam1, q)
    return ad, bd


def steady_states_with_indoor(a, b, inputs, temp_in: float) -> np.ndarray:
    """States of a batch of systems with ``Ti`` (state 0) held at ``temp_in`` and the other
    states in equilibrium with constant ``inputs``.

    Parameters
    ----------
    a : ndarray (n, ns, ns) [1/s]
    b : ndarray (n, ns, ni) [K/(s unit)]
    inputs : array-like (k,) with k <= ni
        Values of the first k inputs (the remaining ones, e.g. the heating power of the
        demand model, are taken as zero).
    temp_in : float [C]

    Returns
    -------
    ndarray (n, ns) [C]
    """
    u = np.asarray(inputs, dtype=float)
    n, ns, _ = a.shape
    x = np.empty((n, ns))
    x[:, 0] = temp_in
    rest = slice(1, ns)
    rhs = -(a[:, rest, 0] * temp_in + np.einsum("nij,j->ni", b[:, rest, : u.shape[0]], u))
    x[:, rest] = np.linalg.solve(a[:, rest, rest], rhs[..., None])[..., 0]
    return x
