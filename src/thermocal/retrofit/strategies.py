"""The 16 envelope-retrofit strategies of paper 000 (Table 3).

The four measures are, in this order, roof, external walls, windows and cellar ceiling. The
strategies are every subset of them, grouped by size and, inside a group, in lexicographic
combination order (:func:`itertools.combinations`): ``0`` none; ``1a``-``1d`` the single
measures; ``2a``-``2f`` the pairs; ``3a``-``3d`` the triples; ``4`` all four. So ``3c`` is
roof + windows + cellar ceiling, as the paper's text confirms.

References
----------
Paper 000, Table 1 (measures and U-values after retrofit) and Table 3 (strategies).
"""

from __future__ import annotations

import string
from dataclasses import dataclass
from itertools import combinations

#: The envelope components a measure can act on, in the paper's column order.
MEASURE_ORDER: tuple[str, ...] = ("roof", "walls", "windows", "cellar_ceiling")

#: U-values after retrofit [W/(m2 K)], paper 000 Table 1.
PAPER_MEASURE_U_VALUES: dict[str, float] = {
    "roof": 0.18,  # inter-rafter insulation, 20 cm mineral wool
    "walls": 0.19,  # ventilated curtain facade, 16 cm EPS
    "windows": 0.76,  # triple glazing
    "cellar_ceiling": 0.19,  # 16 cm mineral wool
}

#: Human-readable measure descriptions (paper 000 Table 1).
PAPER_MEASURE_DESCRIPTIONS: dict[str, str] = {
    "roof": "Inter-rafter insulation with 20 cm mineral wool",
    "walls": "Ventilated curtain facade with 16 cm expanded polystyrene",
    "windows": "Replacement with triple-glazed windows",
    "cellar_ceiling": "Insulation with 16 cm mineral wool",
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


def all_strategies(measures: tuple[str, ...] = MEASURE_ORDER) -> list[Strategy]:
    """All subsets of ``measures`` coded as in paper 000 Table 3.

    Parameters
    ----------
    measures : tuple of str
        Measure names in the order that defines the lexicographic combination order.

    Returns
    -------
    list of Strategy
        ``2**len(measures)`` strategies: ``0``, then for k = 1 .. n-1 the k-subsets coded
        ``"<k><letter>"``, then ``"<n>"`` for all measures.
    """
    n = len(measures)
    strategies = [Strategy("0", ())]
    for k in range(1, n + 1):
        subsets = list(combinations(measures, k))
        if len(subsets) == 1:
            strategies.append(Strategy(str(k), subsets[0]))
            continue
        for letter, subset in zip(string.ascii_lowercase, subsets, strict=False):
            strategies.append(Strategy(f"{k}{letter}", subset))
    return strategies
