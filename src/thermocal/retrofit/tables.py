"""The retrofit analysis' strategy tables: demand and saving with their interval, economics,
the recommended strategy and the short measure labels of the figures. Used by the outputs
(results.json, CSV), the figures and the report."""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.montecarlo import interval_end_error
from thermocal.retrofit.economics import measure_areas, strategy_economics
from thermocal.retrofit.workflow import RetrofitAnalysis


def scenario_table(analysis: RetrofitAnalysis) -> pd.DataFrame:
    """Annual demand and saving of every strategy, with the uncertainty interval and the Monte
    Carlo standard error of its ends (``saving_pct_mcse`` [percentage points], the draws being
    independent)."""
    cfg = analysis.config
    lo_q = 0.5 * (1.0 - cfg.uncertainty.interval)
    hi_q = 1.0 - lo_q
    annual = analysis.demand.annual_kwh()  # (S, D+1); draw 0 = estimate
    base = annual[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        saving = 100.0 * (1.0 - annual / base[None, :])
    has_draws = annual.shape[1] > 1
    rows = []
    for i, s in enumerate(analysis.strategies):
        d = annual[i, 1:] if has_draws else annual[i, :1]
        sv = saving[i, 1:] if has_draws else saving[i, :1]
        rows.append({
            "code": s.code,
            "measures": " + ".join(s.measures) if s.measures else "none",
            "annual_kWh": float(annual[i, 0]),
            "annual_kWh_p05": float(np.quantile(d, lo_q)),
            "annual_kWh_p95": float(np.quantile(d, hi_q)),
            "saving_pct": float(saving[i, 0]) if i else 0.0,
            "saving_pct_p05": float(np.quantile(sv, lo_q)) if i else 0.0,
            "saving_pct_p95": float(np.quantile(sv, hi_q)) if i else 0.0,
            # how well the interval's ends are known from this many draws (Monte Carlo)
            "saving_pct_mcse": interval_end_error(sv, cfg.uncertainty.interval)
            if i and has_draws else 0.0,
        })  # fmt: skip
    return pd.DataFrame(rows)


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
    from thermocal.retrofit.economics import recommend

    if analysis.gate is not None and not analysis.gate["passed"]:
        return None  # a model that failed its validation recommends nothing
    scen = scenario_table(analysis)
    rec = recommend(economics_table(analysis), scen["saving_pct"])
    return None if rec is None else rec["code"]
