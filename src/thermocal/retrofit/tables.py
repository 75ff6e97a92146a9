"""The retrofit analysis' strategy tables: demand and saving with their interval, economics,
the recommended strategy and the short measure labels of the figures. Used by the outputs
(results.json, CSV), the figures and the report."""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.montecarlo import interval_end_error, interval_ends
from thermocal.retrofit.economics import measure_areas, strategy_economics
from thermocal.retrofit.workflow import RetrofitAnalysis


def scenario_table(analysis: RetrofitAnalysis) -> pd.DataFrame:
    """Annual demand and saving of every strategy, with the uncertainty interval and the Monte
    Carlo standard error of its ends (``saving_pct_mcse`` [percentage points], the draws being
    independent); without draws (``uncertainty.draws: 0``) the interval columns are NaN."""
    cfg = analysis.config
    interval = cfg.uncertainty.interval
    annual = analysis.demand.annual_kwh()  # (S, D+1); draw 0 = estimate
    base = annual[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        saving = 100.0 * (1.0 - annual / base[None, :])
    has_draws = annual.shape[1] > 1
    rows = []
    for i, s in enumerate(analysis.strategies):
        kwh_lo, kwh_hi = interval_ends(annual[i, 1:], interval)
        sv_lo, sv_hi = interval_ends(saving[i, 1:], interval) if i else (0.0, 0.0)
        if not has_draws:
            sv_lo = sv_hi = float("nan")
        rows.append({
            "code": s.code,
            "measures": " + ".join(s.measures) if s.measures else "none",
            "annual_kWh": float(annual[i, 0]),
            "annual_kWh_p05": kwh_lo,
            "annual_kWh_p95": kwh_hi,
            "saving_pct": float(saving[i, 0]) if i else 0.0,
            "saving_pct_p05": sv_lo,
            "saving_pct_p95": sv_hi,
            # how well the interval's ends are known from this many draws (Monte Carlo)
            "saving_pct_mcse": (interval_end_error(saving[i, 1:], interval) if i else 0.0)
            if has_draws else float("nan"),
        })  # fmt: skip
    return pd.DataFrame(rows)


def has_intervals(results: dict) -> bool:
    """Whether the results carry the demand's and the savings' intervals.

    Parameters
    ----------
    results : dict
        The results.json content (:func:`thermocal.retrofit.outputs.results_dict`).

    Returns
    -------
    bool
        False after ``uncertainty.draws: 0`` (no uncertainty analysis: the interval ends are
        null and the outputs say :data:`thermocal.retrofit.config.NO_INTERVAL`).
    """
    return results["annual_heating_demand_kWh"].get("p05") is not None


def _areas(analysis: RetrofitAnalysis) -> dict[str, float]:
    return measure_areas(analysis.model.envelope, float(analysis.building.heated_floor_area))


def economics_table(analysis: RetrofitAnalysis) -> pd.DataFrame:
    """Final energy, cost, CO2, investment and payback per strategy (see
    :func:`thermocal.retrofit.economics.strategy_economics`)."""
    cfg = analysis.config
    eco = cfg.economics
    return strategy_economics(
        analysis.demand.annual_kwh(),
        analysis.strategies,
        cfg.measure_objects(),
        _areas(analysis),
        system_efficiency=eco.system_efficiency,
        energy_price=eco.energy_price,
        emission_factor=eco.emission_factor,
        interval=cfg.uncertainty.interval,
    )


_SHORT_MEASURE = {
    "roof": "roof",
    "walls": "walls",
    "windows": "windows",
    "cellar_ceiling": "cellar",
}


def _measures_short(measures, n_total: int = 4) -> str:
    """Measures of a strategy, one per line, for a bar label ("none", "all four")."""
    if not measures:
        return "none"
    if len(measures) == n_total and n_total > 2:
        return "all\nfour" if n_total == 4 else f"all\n{n_total}"
    return "\n".join(_SHORT_MEASURE.get(m, m) for m in measures)


def _recommended_code(analysis: RetrofitAnalysis) -> str | None:
    rule = _recommendation_rule(analysis)
    return None if rule is None else rule["code"]


def _recommendation_rule(analysis: RetrofitAnalysis) -> dict | None:
    """The recommended strategy's code and the rule that chose it (None: nothing is)."""
    from thermocal.retrofit.economics import recommend

    if analysis.gate is not None and not analysis.gate["passed"]:
        return None  # a model that failed its validation recommends nothing
    scen = scenario_table(analysis)
    rec = recommend(economics_table(analysis), scen["saving_pct"])
    return None if rec is None else {"code": rec["code"], "rule": rec["rule"]}
