"""Final energy, running cost, CO2 emissions, investment and simple payback of the strategies.

The demand model gives *useful heat* (what the emitters deliver). A heating system with an
annual efficiency ``eta`` (useful heat / final energy; a heat pump's seasonal COP) turns it
into *final energy* (what is bought), ``Q_final = Q_useful / eta``; its price and emission
factor give the running cost and the CO2 of a year. The investment of a strategy is the sum of
its measures' costs, ``cost + cost_per_m2 x area``, with the area of the component the measure
acts on (the heated floor area for airtightness and heat recovery). The simple payback is the
investment divided by the yearly saving of running cost, without discounting or price changes.

Intervals come from the same parameter draws as the demand (paired: the draw for a strategy
and for no retrofit are the same), so they cover the estimation uncertainty of the calibrated
model (and of the audit U-values when that is configured), not prices or efficiencies.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from thermocal.montecarlo import interval_ends
from thermocal.retrofit.strategies import Measure, Strategy


def measure_areas(envelope, heated_floor_area: float) -> dict[str, float]:
    """Area [m2] a measure's ``cost_per_m2`` applies to, per component."""
    return {
        "roof": float(envelope.roof_area),
        "walls": float(envelope.walls_area),
        "windows": float(envelope.windows_area),
        "cellar_ceiling": float(envelope.floor_area),
        "ground_floor": float(envelope.floor_area),
        "attic_ceiling": float(envelope.attic_area),
        "wall_to_unheated": float(envelope.adjacent_area),
        "airtightness": float(heated_floor_area),
        "heat_recovery": float(heated_floor_area),
    }


def measure_investment(measure: Measure, areas: Mapping[str, float]) -> float:
    """Cost of one measure [currency]: ``cost + cost_per_m2 x area``."""
    return float(measure.cost + measure.cost_per_m2 * areas[measure.component])


def strategy_economics(
    annual_kwh: np.ndarray,
    strategies: Sequence[Strategy],
    measures: Mapping[str, Measure],
    areas: Mapping[str, float],
    *,
    system_efficiency: float,
    energy_price: float,
    emission_factor: float,
    interval: float = 0.9,
) -> pd.DataFrame:
    """Per strategy: useful heat, final energy, cost, CO2, investment and simple payback.

    Parameters
    ----------
    annual_kwh : ndarray (n_strategies, n_draws + 1) [kWh]
        Annual useful heat; column 0 is the estimate, the others the parameter draws. The
        first strategy is "no retrofit".
    strategies : sequence of Strategy
    measures : mapping name -> Measure
    areas : mapping component -> area [m2] (see :func:`measure_areas`)
    system_efficiency : float [-]
        Useful heat / final energy over the year.
    energy_price : float [currency/kWh of final energy]
    emission_factor : float [kg CO2-eq/kWh of final energy]
    interval : float
        Central probability of the reported intervals.

    Returns
    -------
    pd.DataFrame
        Columns ``code``, ``useful_heat_kWh``, ``final_energy_kWh``, ``cost_per_year``,
        ``co2_kg_per_year``, ``investment``, ``cost_saving_per_year`` (with ``_lo``/``_hi``),
        ``co2_saving_kg_per_year``, ``payback_years`` (with ``_lo``/``_hi``; NaN when the
        strategy saves nothing), ``cost_per_kWh_saved_per_year``. Without draws (only the
        estimate's column) every ``_lo``/``_hi`` is NaN: no interval.
    """
    annual = np.asarray(annual_kwh, dtype=float)
    final = annual / system_efficiency
    cost = final * energy_price
    co2 = final * emission_factor
    rows = []
    for i, s in enumerate(strategies):
        invest = sum(measure_investment(measures[m], areas) for m in s.measures)
        saving = cost[0] - cost[i]  # paired per draw
        s_lo, s_hi = interval_ends(saving[1:], interval)
        heat_lo, heat_hi = interval_ends(annual[i, 1:], interval)

        def payback(x: float, invest: float = invest) -> float:
            return invest / x if x > 0 else float("nan")

        rows.append({
            "code": s.code,
            "useful_heat_kWh": annual[i, 0],
            "useful_heat_kWh_lo": heat_lo,
            "useful_heat_kWh_hi": heat_hi,
            "final_energy_kWh": final[i, 0],
            "cost_per_year": cost[i, 0],
            "co2_kg_per_year": co2[i, 0],
            "investment": float(invest),
            "cost_saving_per_year": float(saving[0]),
            "cost_saving_per_year_lo": float(s_lo),
            "cost_saving_per_year_hi": float(s_hi),
            "co2_saving_kg_per_year": float(co2[0, 0] - co2[i, 0]),
            "payback_years": payback(float(saving[0])) if i else float("nan"),
            # a larger saving pays back sooner: the interval bounds swap
            "payback_years_lo": payback(float(s_hi)) if i else float("nan"),
            "payback_years_hi": payback(float(s_lo)) if i else float("nan"),
            "cost_per_kWh_saved_per_year": invest / (annual[0, 0] - annual[i, 0])
            if i and annual[0, 0] > annual[i, 0] else float("nan"),
        })  # fmt: skip
    return pd.DataFrame(rows)


def recommend(table: pd.DataFrame, savings_pct: Sequence[float]) -> dict | None:
    """The strategy a report recommends, with the rule that chose it.

    Among the strategies that pay back (finite payback), the one with the largest yearly
    cost saving whose payback is at most 30 years (a typical service life of envelope
    measures); when none does, the shortest payback. None when nothing pays back.

    Parameters
    ----------
    table : DataFrame from :func:`strategy_economics`
    savings_pct : sequence of float
        Saving of useful heat [%] per strategy (same order).
    """
    t = table.assign(saving_pct=list(savings_pct)).iloc[1:]
    ok = t[np.isfinite(t["payback_years"])]
    if ok.empty:
        return None
    within = ok[ok["payback_years"] <= 30.0]
    if not within.empty:
        row = within.sort_values("cost_saving_per_year", ascending=False).iloc[0]
        rule = "the largest yearly saving among the strategies that pay back within 30 years"
    else:
        row = ok.sort_values("payback_years").iloc[0]
        rule = "the shortest payback (none pays back within 30 years)"
    return {"code": row["code"], "rule": rule, "row": row.to_dict()}
