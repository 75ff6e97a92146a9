"""Retrofit measures and strategies.

A *measure* changes one part of the building: the U-value of a component (roof, external
walls, windows, cellar ceiling / ground floor), the g-value of the windows, the air-change rate
(airtightness) or adds mechanical ventilation with heat recovery. Each measure has a cost.

A *strategy* is a set of measures. By default the strategies are every combination of the
configured measures that does not apply two measures to the same part, grouped by size and,
inside a group, in lexicographic combination order (:func:`itertools.combinations`): ``0`` none;
``1a``, ``1b``, ... the single measures; ``2a``, ... the pairs; and so on; the group of all
measures is coded by its size alone. With the four measures of the fifth-order RC method (roof,
external walls, windows, cellar ceiling) this is the method's Table 3: 16 strategies, ``3c`` =
roof + windows + cellar ceiling.

References
----------
The retrofit method: see :data:`thermocal.retrofit.references.RETROFIT_METHOD`, Table 1
(measures, U-values after retrofit) and Table 3 (strategies).
Sigrist et al. (2019): the four measures most frequently undertaken in Switzerland and their
cost-optimal variants (cited by the method for Table 1).
"""

from __future__ import annotations

import string
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from itertools import combinations, product

#: The envelope components a U-value measure can act on, in the method's column order.
MEASURE_ORDER: tuple[str, ...] = ("roof", "walls", "windows", "cellar_ceiling")

#: Components a U-value measure can act on: the method's four and the slab on ground (floor
#: insulation of a house without cellar; ``cellar_ceiling`` insulates the ceiling of an
#: unheated cellar).
U_VALUE_COMPONENTS: tuple[str, ...] = (
    *MEASURE_ORDER, "ground_floor", "attic_ceiling", "wall_to_unheated",
)  # fmt: skip

#: Parts a measure can act on: the U-value components and the two ventilation measures.
MEASURE_COMPONENTS: tuple[str, ...] = (*U_VALUE_COMPONENTS, "airtightness", "heat_recovery")

#: U-values after retrofit [W/(m2 K)], Table 1 of the fifth-order RC method.
PAPER_MEASURE_U_VALUES: dict[str, float] = {
    "roof": 0.18,  # inter-rafter insulation, 20 cm mineral wool
    "walls": 0.19,  # ventilated curtain facade, 16 cm EPS
    "windows": 0.76,  # triple glazing
    "cellar_ceiling": 0.19,  # 16 cm mineral wool
}

#: Human-readable measure descriptions (Table 1 of the method).
PAPER_MEASURE_DESCRIPTIONS: dict[str, str] = {
    "roof": "Inter-rafter insulation with 20 cm mineral wool",
    "walls": "Ventilated curtain facade with 16 cm expanded polystyrene",
    "windows": "Replacement with triple-glazed windows",
    "cellar_ceiling": "Insulation with 16 cm mineral wool",
}

#: Default full cost of the four standard measures per m2 of the component [currency/m2].
#: Indicative placeholders of the order of Swiss contractor prices (material + labour + VAT,
#: scaffolding included for walls): they are NOT from a cost database; replace them with
#: quotes (``measures.<name>.cost_per_m2`` in the configuration). See docs/retrofit.md.
DEFAULT_COST_PER_M2: dict[str, float] = {
    "roof": 150.0,
    "walls": 250.0,
    "windows": 800.0,
    "cellar_ceiling": 70.0,
    "ground_floor": 120.0,  # insulation and new screed on the slab, from inside
    "attic_ceiling": 60.0,  # insulation laid on the ceiling from the attic
    "wall_to_unheated": 90.0,  # insulation boards on the garage / staircase side
}

#: Volumetric heat capacity of air / 3600 [W h/(m3 K)] -> conductance of 1 1/h per m3 [W/K].
AIR_HEAT_CAPACITY_WH_PER_M3K = 1200.0 / 3600.0


@dataclass(frozen=True)
class Measure:
    """One retrofit measure.

    Attributes
    ----------
    name : str
        Name used in strategy labels and tables.
    component : str
        What it acts on: ``roof``, ``walls``, ``windows``, ``cellar_ceiling`` (ceiling of an
        unheated cellar), ``ground_floor`` (slab on ground), ``airtightness`` or
        ``heat_recovery``; a U-value measure on a floor of the other kind is refused.
    u_value : float or None [W/(m2 K)]
        U-value of the component after the retrofit (components only).
    g_value : float or None [-]
        Total solar energy transmittance of the glazing after the retrofit (windows only).
    air_change_rate_change : float [1/h]
        Change of the infiltration / natural air-change rate (airtightness; negative = tighter).
    heat_recovery_air_change_rate : float [1/h]
        Air-change rate of the mechanical ventilation with heat recovery (heat_recovery).
    heat_recovery_efficiency : float [-]
        Temperature efficiency of the heat exchanger (heat_recovery).
    cost_per_m2 : float [currency/m2]
        Cost per m2 of the component (heated floor area for the two ventilation measures).
    cost : float [currency]
        Fixed cost, added to ``cost_per_m2`` x area.
    description : str
    """

    name: str
    component: str
    u_value: float | None = None
    g_value: float | None = None
    air_change_rate_change: float = 0.0
    heat_recovery_air_change_rate: float = 0.0
    heat_recovery_efficiency: float = 0.0
    cost_per_m2: float = 0.0
    cost: float = 0.0
    description: str = ""

    def heat_loss_change(self, volume: float) -> float:
        """Change of the ventilation heat transfer coefficient [W/K] for an air volume [m3].

        ``rho c V (dn - n_hr eta)``: airtightness changes the infiltration rate by ``dn``;
        mechanical ventilation at ``n_hr`` with heat recovery ``eta`` replaces the same amount
        of window / infiltration air (which the calibrated ``H_est`` contains) by air
        pre-heated to ``eta`` of the indoor-outdoor difference.

        References
        ----------
        ISO 13789:2017, 8.1 (ventilation heat transfer coefficient ``H_V = rho c q_V``, and
        the temperature adjustment of heat-recovered supply air).
        """
        dn = self.air_change_rate_change - (
            self.heat_recovery_air_change_rate * self.heat_recovery_efficiency
        )
        return AIR_HEAT_CAPACITY_WH_PER_M3K * float(volume) * dn


def paper_measures(costs: Mapping[str, float] | None = None) -> dict[str, Measure]:
    """The four measures of the method (Table 1) with default (or given) costs per m2."""
    costs = {**DEFAULT_COST_PER_M2, **(costs or {})}
    return {
        m: Measure(
            name=m,
            component=m,
            u_value=u,
            cost_per_m2=costs[m],
            description=PAPER_MEASURE_DESCRIPTIONS[m],
        )
        for m, u in PAPER_MEASURE_U_VALUES.items()
    }


@dataclass(frozen=True)
class Strategy:
    """One retrofit strategy: a code and the set of measures it applies."""

    code: str
    measures: tuple[str, ...]

    def contains(self, other: Strategy) -> bool:
        """True when every measure of ``other`` is part of this strategy."""
        return set(other.measures) <= set(self.measures)

    @property
    def label(self) -> str:
        """``"3c: roof + windows + cellar_ceiling"`` style label."""
        body = " + ".join(self.measures) if self.measures else "no retrofit"
        return f"{self.code}: {body}"


def _letters():
    """a, b, ..., z, aa, ab, ... (codes inside a size group)."""
    for width in range(1, 4):
        for combo in product(string.ascii_lowercase, repeat=width):
            yield "".join(combo)


#: Most measures whose combinations are generated automatically (2**8 = 256 strategies).
MAX_COMBINED_MEASURES = 8


def all_strategies(
    measures: Sequence[str] = MEASURE_ORDER,
    components: Mapping[str, str] | None = None,
) -> list[Strategy]:
    """All combinations of ``measures`` coded as in Table 3 of the method.

    Parameters
    ----------
    measures : sequence of str
        Measure names in the order that defines the lexicographic combination order.
    components : mapping name -> component, optional
        What each measure acts on; combinations with two measures on the same component
        (e.g. two window options) are left out.

    Returns
    -------
    list of Strategy
        ``0``, then for k = 1 .. n-1 the k-subsets coded ``"<k><letters>"``, then ``"<n>"``
        for all measures (when they can be combined).
    """
    measures = tuple(measures)
    if len(measures) > MAX_COMBINED_MEASURES:
        raise ValueError(
            f"{len(measures)} measures give {2 ** len(measures)} combinations; list the "
            f"strategies to analyse instead (at most {MAX_COMBINED_MEASURES} measures combined)"
        )
    comp = dict(components or {m: m for m in measures})
    n = len(measures)
    strategies = [Strategy("0", ())]
    for k in range(1, n + 1):
        subsets = [
            s for s in combinations(measures, k) if len({comp.get(m, m) for m in s}) == len(s)
        ]
        if not subsets:
            continue
        if len(subsets) == 1 and k == n:
            strategies.append(Strategy(str(k), subsets[0]))
            continue
        for letters, subset in zip(_letters(), subsets, strict=False):
            strategies.append(Strategy(f"{k}{letters}", subset))
    return strategies


def listed_strategies(
    listed: Mapping[str, Iterable[str]], measures: Mapping[str, Measure]
) -> list[Strategy]:
    """Strategies named by the user (code -> measures), with ``0`` (no retrofit) first.

    Raises
    ------
    ValueError
        Naming the strategy with an unknown measure, or with two measures on one component.
    """
    out = [Strategy("0", ())]
    seen: dict[frozenset, str] = {}
    for code, names in listed.items():
        names = tuple(names)
        if str(code) == "0":
            if names:
                raise ValueError("strategy '0' is reserved for 'no retrofit'")
            continue
        if not names:
            raise ValueError(
                f"strategy {code!r} lists no measure: it would be the house as it is (strategy "
                "0, always analysed); give its measures or remove it"
            )
        if frozenset(names) in seen:
            raise ValueError(
                f"strategy {code!r} applies the same measures as strategy "
                f"{seen[frozenset(names)]!r}; remove one"
            )
        seen[frozenset(names)] = str(code)
        unknown = [m for m in names if m not in measures]
        if unknown:
            raise ValueError(
                f"strategy {code!r} names unknown measures {unknown}; defined: {list(measures)}"
            )
        comps = [measures[m].component for m in names]
        dup = sorted({c for c in comps if comps.count(c) > 1})
        if dup:
            raise ValueError(f"strategy {code!r} applies two measures to the same part {dup}")
        out.append(Strategy(str(code), names))
    if len(out) == 1:
        raise ValueError(
            "no strategy besides '0' (the house as it is, always analysed) is listed; list "
            "strategies as code: [measures], or leave the key out for every combination"
        )
    return out
