"""Outputs of the retrofit workflow: results.json, CSV tables, figures and report.html."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.retrofit.model import ESTIMATED_PARAMETERS
from thermocal.retrofit.strategies import PAPER_MEASURE_DESCRIPTIONS
from thermocal.retrofit.workflow import RetrofitAnalysis, heat_loss_coefficient_draws

MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")


def _num(x):
    if x is None:
        return None
    if isinstance(x, int | np.integer):
        return int(x)
    x = float(x)
    return x if math.isfinite(x) else None


def _clean(obj):
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_clean(v) for v in obj.tolist()]
    if isinstance(obj, float | np.floating | int | np.integer) and not isinstance(obj, bool):
        return _num(obj)
    return obj


def scenario_table(analysis: RetrofitAnalysis) -> pd.DataFrame:
    """Annual demand and saving of every strategy, with the uncertainty interval."""
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
        })  # fmt: skip
    return pd.DataFrame(rows)


def results_dict(analysis: RetrofitAnalysis, *, true_hlc: float | None = None) -> dict:
    """The content of results.json."""
    cfg = analysis.config
    cal = analysis.calibration
    model = analysis.model
    lo_q = 0.5 * (1.0 - cfg.uncertainty.interval)
    params = {}
    for name in cal.params.index:
        unit = ""
        if name in model.estimated:
            unit = model.estimated[name][3]
        params[name] = {
            "value": _num(cal.params[name]),
            "std_error": _num(cal.bse.get(name, np.nan)),
            "unit": unit or _unit_guess(name),
            "estimated": bool(name in cal.correlation.columns),
        }
        if name in model.estimated:
            lo, ini, hi, _ = model.estimated[name]
            params[name].update({"lower": lo, "initial": ini, "upper": hi})
    corr = cal.correlation.to_numpy(float)
    off = corr[~np.eye(len(corr), dtype=bool)] if corr.size else np.array([])
    phys = [n for n in ESTIMATED_PARAMETERS if n in cal.correlation.columns]
    cphys = cal.correlation.loc[phys, phys].to_numpy(float)
    off_phys = cphys[~np.eye(len(cphys), dtype=bool)]
    hlc_draws = heat_loss_coefficient_draws(
        analysis,
        np.random.default_rng(0).normal(
            cal.estimates_si["H_est"], max(cal.heat_loss_coefficient_std, 0), 2000
        ),
    )
    hlc = {
        "value": _num(cal.heat_loss_coefficient),
        "std": _num(cal.heat_loss_coefficient_std),
        "p05": _num(np.quantile(hlc_draws, lo_q)),
        "p95": _num(np.quantile(hlc_draws, 1 - lo_q)),
        "calculated_part": _num(cal.heat_loss_coefficient - cal.estimates_si["H_est"]),
        "H_est": _num(cal.estimates_si["H_est"]),
        "audit_prior": _num(model.calculated_heat_loss_coefficient() + model.audit_h_est),
    }
    if cfg.reference.audit_heat_loss_coefficient_W_per_K is not None:
        hlc["audit"] = cfg.reference.audit_heat_loss_coefficient_W_per_K
    true = true_hlc if true_hlc is not None else cfg.reference.true_heat_loss_coefficient_W_per_K
    if true is not None:
        hlc["true"] = float(true)
        hlc["relative_error_pct"] = 100.0 * (cal.heat_loss_coefficient - true) / true
    monthly = analysis.demand.monthly_kwh()  # (S, D+1, 12)
    annual = analysis.demand.annual_kwh()
    has_draws = annual.shape[1] > 1
    base_draws = annual[0, 1:] if has_draws else annual[0, :1]
    mdraws = monthly[0, 1:] if has_draws else monthly[0, :1]
    demand = {
        "value": _num(annual[0, 0]),
        "p05": _num(np.quantile(base_draws, lo_q)),
        "p95": _num(np.quantile(base_draws, 1 - lo_q)),
        "monthly": [_num(v) for v in monthly[0, 0]],
        "monthly_p05": [_num(v) for v in np.quantile(mdraws, lo_q, axis=0)],
        "monthly_p95": [_num(v) for v in np.quantile(mdraws, 1 - lo_q, axis=0)],
        "indoor_profile_C": [_num(v) for v in analysis.indoor_profile],
        "weather": {
            k: analysis.weather_meta.get(k) for k in ("name", "latitude", "longitude", "source")
        },
        "per_m2_kWh": _num(annual[0, 0] / float(analysis.building.heated_floor_area)),
    }
    ref = cfg.reference
    references = {}
    if ref.rating_kWh is not None:
        references[ref.rating_label] = ref.rating_kWh
    if ref.measured_fuel_kWh is not None:
        references["measured fuel use"] = ref.measured_fuel_kWh
        if ref.boiler_efficiency is not None:
            references["measured fuel use x boiler efficiency"] = (
                ref.measured_fuel_kWh * ref.boiler_efficiency
            )
    if ref.rating_monthly_kWh is not None:
        references[f"{ref.rating_label} monthly"] = ref.rating_monthly_kWh
    demand["references"] = references
    scen = scenario_table(analysis)
    scenarios = []
    for row, s in zip(scen.to_dict("records"), analysis.strategies, strict=True):
        scenarios.append(
            {
                **row,
                "measures": list(s.measures),
                "u_values": {m: cfg.measures[m] for m in s.measures},
            }
        )
    h = model.conductances()
    return _clean({
        "thermocal_workflow": "retrofit (paper 000)",
        "building": analysis.building.name,
        "periods": {
            "training": [str(analysis.training[0]), str(analysis.training[1])],
            "test": [str(analysis.test[0]), str(analysis.test[1])] if analysis.test else None,
        },
        "calibration": {
            "params": params,
            "calculated_conductances_W_per_K": h,
            "max_abs_correlation": _num(np.nanmax(np.abs(off))) if off.size else None,
            "max_abs_correlation_physical": _num(np.nanmax(np.abs(off_phys)))
            if off_phys.size else None,
            "max_abs_pairwise_correlation_physical": _max_off_diagonal(cal.pairwise_correlation),
            "correlated_pairs": [
                {"a": a, "b": b, "r": r} for a, b, r in cal.correlated_pairs
            ],
            "loglike": cal.loglike,
            "aic": cal.aic,
            "bic": cal.bic,
            "converged": cal.converged,
            "flags": cal.flags,
            "full_fit_flags": cal.nuisance_flags,
            "parameters_at_bounds": cal.at_bounds,
            "fit_seconds": cal.fit_seconds,
        },
        "heat_loss_coefficient_W_per_K": hlc,
        "validation": analysis.validation,
        "annual_heating_demand_kWh": demand,
        "scenarios": scenarios,
        "measures_u_values": cfg.measures,
        "uncertainty": {"draws": cfg.uncertainty.draws, "interval": cfg.uncertainty.interval,
                        "seed": cfg.uncertainty.seed},
        "measurements_quality": _quality_dict(analysis.measurements_quality),
        "notes": analysis.notes,
        "timings_s": analysis.timings,
    })  # fmt: skip


def _quality_dict(report) -> dict | None:
    """The measurement QualityReport as JSON content, with its plain-text summary."""
    if report is None:
        return None
    return {"summary": report.summary(), **report.to_dict()}


def _fmt(value, spec: str) -> str:
    """Format a number that may be missing (None/NaN) as ``n/a``."""
    if value is None or not np.isfinite(value):
        return "n/a"
    return format(value, spec)


def _interval_labels(interval: float) -> tuple[str, str]:
    """Names of the lower and upper interval quantiles, e.g. ("p05", "p95") for 90 %."""
    lo = round(50.0 * (1.0 - interval), 6)

    def name(q: float) -> str:
        return f"p{q:02.0f}" if q == int(q) else f"p{q:g}"

    return name(lo), name(100.0 - lo)


_SHORT_MEASURE = {
    "roof": "roof",
    "walls": "walls",
    "windows": "windows",
    "cellar_ceiling": "cellar",
}


def _measures_short(measures) -> str:
    """Measures of a strategy, one per line, for a bar label ("none", "all four")."""
    if not measures:
        return "none"
    if len(measures) == 4:
        return "all\nfour"
    return "\n".join(_SHORT_MEASURE.get(m, m) for m in measures)


def _max_off_diagonal(corr: pd.DataFrame | None) -> float | None:
    """Largest finite |off-diagonal| entry of a correlation matrix, None when there is none."""
    if corr is None or corr.shape[0] < 2:
        return None
    c = np.abs(corr.to_numpy(float))[~np.eye(corr.shape[0], dtype=bool)]
    return _num(np.nanmax(c)) if np.isfinite(c).any() else None


def _unit_guess(name: str) -> str:
    if name.startswith("sigma_"):
        return "K/sqrt(h)"
    if name.endswith("0") or name == "e_std":
        return "C"
    return ""


def write_outputs(
    analysis: RetrofitAnalysis,
    out_dir: Path | str,
    *,
    true_hlc: float | None = None,
    title: str | None = None,
    reference_demands: dict[str, float] | None = None,
    reference_monthly: list[float] | None = None,
    reference_label: str = "reference",
) -> dict:
    """Write results.json, the CSV tables, the figures and report.html into ``out_dir``.

    Parameters
    ----------
    reference_demands : dict code -> kWh, optional
        Annual demands at a constant 20 C of some or all strategies from another model (the
        demo: the multi-zone generator); compared with the model's at 20 C.

    Returns
    -------
    dict
        The results.json content.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    results = results_dict(analysis, true_hlc=true_hlc)
    if reference_demands:
        from thermocal.retrofit.workflow import compare_with_reference_demands

        check = compare_with_reference_demands(analysis, reference_demands)
        check["reference"] = reference_label
        if reference_monthly is not None:
            check["monthly_reference_kWh"] = list(reference_monthly)
        results["reference_check"] = _clean(check)
    (out / "results.json").write_text(json.dumps(results, indent=2))
    tables = write_tables(analysis, out, results)
    from thermocal.report.figures import close, figure_to_png

    fig_dir = out / "figures"
    fig_dir.mkdir(exist_ok=True)
    figures = {}
    for name, fig in make_figures(analysis, results).items():
        figures[name] = figure_to_png(fig)  # rendered once: file and report share the bytes
        close(fig)
        (fig_dir / f"{name}.png").write_bytes(figures[name])
    write_report(analysis, results, tables, figures, out / "report.html", title=title)
    return results


def write_tables(analysis: RetrofitAnalysis, out: Path, results: dict) -> dict[str, pd.DataFrame]:
    """CSV tables (temperatures in C, energies in kWh)."""
    cal = analysis.calibration
    params = pd.DataFrame([
        {"parameter": k, "value": v["value"], "std_error": v["std_error"], "unit": v["unit"],
         "lower": v.get("lower"), "upper": v.get("upper"), "estimated": v["estimated"]}
        for k, v in results["calibration"]["params"].items()
    ])  # fmt: skip
    ts = pd.DataFrame({
        "Te_C": analysis.data["Te"], "Tgr_C": analysis.data["Tgr"],
        "phi_h_W": analysis.data["phi_h"], "phi_sol_W": analysis.data["phi_sol"],
        "Ti_measured_C": analysis.data["Ti_measured"], "Ti_simulated_C": analysis.simulated_ti,
    })  # fmt: skip
    ts["period"] = np.where(ts.index < analysis.training[1], "train", "test")
    ts.index.name = "time"
    val = pd.DataFrame(analysis.validation).T.reset_index(names="period")
    monthly = analysis.demand.monthly_kwh()[:, 0, :]
    monthly_df = pd.DataFrame(monthly, columns=list(MONTHS))
    monthly_df.insert(0, "code", [s.code for s in analysis.strategies])
    hourly = pd.DataFrame(
        {
            f"heating_W_{s.code}": analysis.demand.hourly[i]
            for i, s in enumerate(analysis.strategies)
        },
        index=analysis.demand.index,
    )
    hourly.index.name = "time"
    scen = scenario_table(analysis)
    corr = cal.correlation
    params.to_csv(out / "calibration_parameters.csv", index=False)
    corr.to_csv(out / "calibration_correlation.csv")
    ts.to_csv(out / "validation_timeseries.csv")
    val.to_csv(out / "validation_metrics.csv", index=False)
    hourly.to_csv(out / "demand_hourly.csv")
    monthly_df.to_csv(out / "demand_monthly.csv", index=False)
    scen.to_csv(out / "scenarios.csv", index=False)
    return {"parameters": params, "validation": val, "monthly": monthly_df, "scenarios": scen}


def make_figures(analysis: RetrofitAnalysis, results: dict) -> dict:
    """The standard figures: Ti training, Ti test, monthly demand, scenario savings."""
    from thermocal.report.figures import (
        plot_bars_with_intervals,
        plot_measured_vs_simulated,
        plot_monthly_bars,
    )

    figs = {}
    d = analysis.data
    for name, period in (("train", analysis.training), ("test", analysis.test)):
        if period is None:
            continue
        sel = (d.index >= period[0]) & (d.index < period[1])
        m = analysis.validation[name]
        text = (
            f"MAE {m['mae']:.2f} K   MAPE {m['mape']:.2f} %   MSE {m['mse']:.2f} K²\n"
            f"mean simulated {m['mean_simulated']:.2f} C vs measured "
            f"{m['mean_measured']:.2f} C ({m['mean_deviation_pct']:+.2f} %)"
        )
        label = "training" if name == "train" else "test"
        figs[f"ti_{label}"] = plot_measured_vs_simulated(
            d.index[sel],
            d["Ti_measured"][sel],
            analysis.simulated_ti[sel],
            title=f"Indoor air temperature, {label} period (multi-step simulation)",
            metrics_text=text,
        )
    dem = results["annual_heating_demand_kWh"]
    ref = analysis.config.reference
    interval = f"{int(round(100 * analysis.config.uncertainty.interval))} % interval"
    figs["monthly_demand"] = plot_monthly_bars(
        dem["monthly"],
        low=dem["monthly_p05"],
        high=dem["monthly_p95"],
        reference=ref.rating_monthly_kWh,
        reference_label=ref.rating_label,
        label="calibrated model",
        title=f"Monthly heating demand (whiskers: {interval} of the parameter uncertainty)",
    )
    scen = scenario_table(analysis)
    sublabels = [_measures_short(s.measures) for s in analysis.strategies]
    figs["scenario_savings"] = plot_bars_with_intervals(
        list(scen["code"]),
        scen["saving_pct"],
        scen["saving_pct_p05"],
        scen["saving_pct_p95"],
        ylabel="Saving vs. no retrofit [%]",
        highlight=("4", "3c"),
        highlight_label="strategies quoted in paper 000 (3c: -31 %, 4: -48 %)",
        sublabels=sublabels,
        interval_label=f"{interval} (parameter uncertainty)",
        title="Saving of the 16 retrofit strategies",
    )
    measured = None
    if ref.measured_fuel_kWh is not None:
        measured = ref.measured_fuel_kWh * (ref.boiler_efficiency or 1.0)
    annual_refs = {k: v for k, v in dem["references"].items() if not isinstance(v, list)}
    if annual_refs:
        figs["annual_comparison"] = _annual_comparison_figure(dem, annual_refs)
    if "reference_check" in results:
        check = results["reference_check"]
        figs["reference_check"] = _reference_figure(check, sublabels, interval)
        if "monthly_reference_kWh" in check:
            figs["monthly_reference_check"] = plot_monthly_bars(
                check["monthly_model_kWh"], low=check["monthly_model_kWh_p05"],
                high=check["monthly_model_kWh_p95"], reference=check["monthly_reference_kWh"],
                reference_label="reference", label="calibrated model",
                title=f"Monthly heating demand at {check['setpoint_C']:.0f} C: model vs "
                "reference",
            )  # fmt: skip
    figs["scenario_demand"] = plot_bars_with_intervals(
        list(scen["code"]),
        scen["annual_kWh"],
        scen["annual_kWh_p05"],
        scen["annual_kWh_p95"],
        ylabel="Annual heating demand [kWh]",
        highlight=("0",),
        highlight_label="no retrofit (today)",
        sublabels=sublabels,
        interval_label=f"{interval} (parameter uncertainty)",
        hline=measured,
        hline_label="measured heat use",
        title="Annual heating demand per strategy",
    )
    return figs


def _annual_comparison_figure(dem: dict, references: dict):
    """Simulated annual demand next to reference values (paper 000 Fig. 7)."""
    import textwrap

    import matplotlib.pyplot as plt

    labels = [textwrap.fill(lab, 16) for lab in ["calibrated model", *references]]
    values = [dem["value"]] + [float(v) for v in references.values()]
    fig, ax = plt.subplots(figsize=(1.8 * len(values) + 2.0, 3.6))
    colors = ["#1b6ca8"] + ["#9ecae1"] * len(references)
    bars = ax.bar(range(len(values)), values, 0.6, color=colors)
    ax.errorbar(
        [0],
        [dem["value"]],
        yerr=[[dem["value"] - dem["p05"]], [dem["p95"] - dem["value"]]],
        color="black",
        capsize=4,
        lw=1,
    )
    for bar, value in zip(bars, values, strict=True):
        ax.text(
            bar.get_x() + bar.get_width() / 2,
            value,
            f"{value:,.0f}",
            ha="center",
            va="bottom",
            fontsize=9,
        )
    ax.set_xticks(range(len(values)), labels, fontsize=9)
    ax.set_ylabel("Annual heating demand [kWh]")
    ax.set_title("Annual heating demand vs references", loc="left", fontsize=11)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


def _reference_figure(check: dict, sublabels=None, interval: str = "90 % interval"):
    import matplotlib.pyplot as plt

    rows = check["strategies"]
    codes = [r["code"] for r in rows]
    x = np.arange(len(codes))
    model = np.array([r["model_saving_pct"] for r in rows])
    lo = np.array([r["model_saving_pct_p05"] for r in rows])
    hi = np.array([r["model_saving_pct_p95"] for r in rows])
    ref = np.array(
        [np.nan if r["reference_saving_pct"] is None else r["reference_saving_pct"] for r in rows]
    )
    fig, ax = plt.subplots(figsize=(10, 4.4 if sublabels else 3.8))
    ax.bar(
        x - 0.2,
        model,
        0.4,
        color="#1b6ca8",
        label=f"fifth-order model (calibrated), whiskers: {interval}",
        yerr=np.clip(np.vstack([model - lo, hi - model]), 0, None),
        capsize=2,
    )
    ax.bar(x + 0.2, ref, 0.4, color="#d95f02", label=check.get("reference", "reference"))
    ax.set_xticks(x, codes)
    for xi, sub in zip(x, sublabels or [], strict=False):
        ax.annotate(
            sub, (xi, 0), xycoords=("data", "axes fraction"), xytext=(0, -18),
            textcoords="offset points", ha="center", va="top", fontsize=7, color="#444444",
        )  # fmt: skip
    ax.set_ylabel(f"Saving at {check['setpoint_C']:.0f} C [%]")
    ax.set_title("Retrofit savings: calibrated model vs reference", loc="left", fontsize=11)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(frameon=False, fontsize=9)
    fig.tight_layout()
    return fig


def write_report(
    analysis: RetrofitAnalysis,
    results: dict,
    tables: dict,
    figures: dict,
    path: Path,
    *,
    title: str | None = None,
) -> Path:
    """The self-contained report.html."""
    from thermocal.report import HtmlReport

    cfg = analysis.config
    hlc = results["heat_loss_coefficient_W_per_K"]
    dem = results["annual_heating_demand_kWh"]
    b = analysis.building
    rep = HtmlReport(
        title or f"Retrofit analysis: {b.name}",
        subtitle="Calibrated fifth-order RC model (paper 000), annual heating "
        "demand and 16 envelope-retrofit strategies",
    )
    rep.section("Summary")
    tiles = {
        "Heat loss coefficient": f"{hlc['value']:.0f} ± {_fmt(hlc['std'], '.0f')} W/K",
        "Annual heating demand": f"{dem['value']:,.0f} kWh",
        f"{int(100 * cfg.uncertainty.interval)} % interval": f"{dem['p05']:,.0f} – "
        f"{dem['p95']:,.0f} kWh",
        "Test-period MAE": f"{analysis.validation['test']['mae']:.2f} K"
        if "test" in analysis.validation
        else "n/a",
    }
    if "true" in hlc:
        tiles["True HLC (generator)"] = (
            f"{hlc['true']:.0f} W/K ({hlc['relative_error_pct']:+.1f} %)"
        )
    if "audit" in hlc:
        tiles["Audit HLC"] = f"{hlc['audit']:.0f} W/K"
    all4 = next(s for s in results["scenarios"] if s["code"] == "4")
    tiles["Saving, all four measures"] = (
        f"{all4['saving_pct']:.0f} % ({all4['saving_pct_p05']:.0f}–{all4['saving_pct_p95']:.0f} %)"
    )
    rep.key_values(tiles)
    for note in analysis.notes:
        rep.note(note)
    rep.paragraph(
        f"Building: {b.name}, {b.floors} floors, {b.heated_floor_area:.0f} m² heated floor "
        f"area, {b.volume:.0f} m³, emitter: {b.emitter}. Training period "
        f"{analysis.training[0]:%Y-%m-%d %H:%M} to {analysis.training[1]:%Y-%m-%d %H:%M}"
        + (f", test period to {analysis.test[1]:%Y-%m-%d %H:%M}." if analysis.test else ".")
    )

    rep.section("Calibration")
    cal = results["calibration"]
    rep.paragraph(
        f"Maximum-likelihood fit: log-likelihood {cal['loglike']:.1f}, AIC {cal['aic']:.1f}, "
        f"converged: {cal['converged']}, {cal['fit_seconds']:.1f} s. Largest |correlation| "
        f"between the physical parameters: {cal['max_abs_correlation_physical']:.3f} "
        f"(limit {cfg.model.max_correlation}); over all free parameters "
        f"{cal['max_abs_correlation']:.3f}."
        + (
            " Largest pairwise |correlation| from the log-likelihood curvature in declared "
            f"units (still valid at a bound): {cal['max_abs_pairwise_correlation_physical']:.3f}."
            if cal.get("max_abs_pairwise_correlation_physical") is not None
            else ""
        )
    )
    if cal["flags"]:
        rep.flags(cal["flags"])
    p = tables["parameters"]
    rep.table(
        p[p["estimated"]].drop(columns=["estimated"]),
        caption="Estimated parameters",
        number_format="{:,.4g}",
    )
    hc = pd.DataFrame(
        [{"conductance": k, "value": v} for k, v in cal["calculated_conductances_W_per_K"].items()]
    )
    rep.table(
        hc,
        caption="Calculated conductances [W/K] and shares [-] (ISO 52016-1, ISO 13370)",
        number_format="{:,.4g}",
    )
    rep.paragraph(
        f"HLC = calculated part {hlc['calculated_part']:.1f} W/K + H_est {hlc['H_est']:.1f} W/K "
        f"= {hlc['value']:.1f} W/K (std {_fmt(hlc['std'], '.1f')} W/K). Prior from the "
        f"building file (ventilation 0.5 1/h, thermal bridges, doors): "
        f"{hlc['audit_prior']:.1f} W/K."
    )

    phys = [n for n in ESTIMATED_PARAMETERS if n in analysis.calibration.correlation.columns]
    if phys:
        corr = analysis.calibration.correlation.loc[phys, phys].reset_index(names="parameter")
        rep.table(
            corr,
            caption="Correlation of the estimated parameters (|r| < "
            f"{cfg.model.max_correlation} required)",
            number_format="{:+.3f}",
        )
    d = analysis.data
    periods = [("training", analysis.training)] + (
        [("test", analysis.test)] if analysis.test else []
    )
    rows = []
    for name, (t0, t1) in periods:
        sel = (d.index >= t0) & (d.index < t1)
        rows.append(
            {
                "period": name,
                "Te mean [C]": d["Te"][sel].mean(),
                "Tgr mean [C]": d["Tgr"][sel].mean(),
                "Ti measured mean [C]": d["Ti_measured"][sel].mean(),
                "heating mean [W]": d["phi_h"][sel].mean(),
                "window solar mean [W]": d["phi_sol"][sel].mean(),
            }
        )
    rep.table(pd.DataFrame(rows), caption="Model inputs over the periods", number_format="{:,.1f}")

    rep.section("Validation")
    shown = {
        "period": ("period", None),
        "mae": ("MAE [K]", "{:.3f}"),
        "mape": ("MAPE [%]", "{:.2f}"),
        "mse": ("MSE [K²]", "{:.3f}"),
        "mean_simulated": ("mean simulated [C]", "{:.2f}"),
        "mean_measured": ("mean measured [C]", "{:.2f}"),
        "mean_deviation_pct": ("deviation of the mean [%]", "{:+.2f}"),
        "n": ("hours", "{:.0f}"),
    }
    val = tables["validation"][list(shown)].rename(columns={k: v[0] for k, v in shown.items()})
    rep.table(
        val,
        caption="Multi-step simulation of Ti (paper 000 Table 2)",
        number_format={v[0]: v[1] for v in shown.values() if v[1]},
    )
    for key, label in (("ti_training", "training"), ("ti_test", "test")):
        if key in figures:
            rep.figure(
                figures[key],
                caption=f"Indoor air temperature over the {label} period: measured and "
                "simulated from the inputs alone (no feedback of the measurements)",
                close_figure=False,
            )

    rep.section("Annual heating demand")
    refs = dem["references"]
    ref_text = "; ".join(f"{k}: {v:,.0f} kWh" for k, v in refs.items() if not isinstance(v, list))
    rep.paragraph(
        f"Simulated with the {dem['weather'].get('name') or 'typical-year'} weather and the "
        f"24-hour indoor profile from the measured Ti (ideal heating-only control): "
        f"{dem['value']:,.0f} kWh/a ({dem['per_m2_kWh']:.0f} kWh/m²a)."
        + (f" References: {ref_text}." if ref_text else "")
    )
    low, high = _interval_labels(cfg.uncertainty.interval)
    mon = pd.DataFrame(
        {
            "month": list(MONTHS),
            "demand [kWh]": dem["monthly"],
            f"{low} [kWh]": dem["monthly_p05"],
            f"{high} [kWh]": dem["monthly_p95"],
        }
    )
    rep.figure(figures["monthly_demand"], caption="Monthly heating demand", close_figure=False)
    if "annual_comparison" in figures:
        rep.figure(figures["annual_comparison"], caption="Annual demand vs references")
    rep.table(mon, caption="Monthly demand [kWh]", number_format="{:,.0f}")

    rep.section("Retrofit strategies")
    meas = pd.DataFrame(
        [
            {
                "measure": m,
                "U after retrofit [W/(m2 K)]": u,
                "description": PAPER_MEASURE_DESCRIPTIONS.get(m, ""),
            }
            for m, u in cfg.measures.items()
        ]
    )
    rep.table(meas, caption="Measures", number_format="{:.2f}")
    rep.figure(figures["scenario_savings"], caption="Savings with intervals", close_figure=False)
    rep.figure(figures["scenario_demand"], caption="Annual demand per strategy", close_figure=False)
    scen = tables["scenarios"]
    shown = {
        "annual_kWh": ("annual demand [kWh]", "{:,.0f}"),
        "annual_kWh_p05": (f"{low} [kWh]", "{:,.0f}"),
        "annual_kWh_p95": (f"{high} [kWh]", "{:,.0f}"),
        "saving_pct": ("saving [%]", "{:.1f}"),
        "saving_pct_p05": (f"saving {low} [%]", "{:.1f}"),
        "saving_pct_p95": (f"saving {high} [%]", "{:.1f}"),
    }
    rep.table(
        scen.rename(columns={k: v[0] for k, v in shown.items()}),
        caption="Strategies (codes as paper 000 Table 3; highlighted: the two the paper quotes, "
        "3c -31 % and 4 -48 %)",
        number_format={v[0]: v[1] for v in shown.values()},
        highlight_rows=[i for i, c in enumerate(scen["code"]) if c in ("3c", "4")],
    )
    if "reference_check" in results:
        check = results["reference_check"]
        rep.heading(f"Check against {check['reference']}")
        rep.paragraph(
            f"Annual demand of every strategy with a constant indoor temperature of "
            f"{check['setpoint_C']:.0f} C, from the calibrated fifth-order model and from "
            f"{check['reference']}."
        )
        rep.figure(figures["reference_check"], caption="Savings: model vs reference")
        if "monthly_reference_check" in figures:
            rep.figure(
                figures["monthly_reference_check"],
                caption=f"Monthly demand at {check['setpoint_C']:.0f} C: model vs "
                f"{check['reference']}",
            )
        names = {
            "model_kWh": "model [kWh]",
            "model_kWh_p05": f"model {low} [kWh]",
            "model_kWh_p95": f"model {high} [kWh]",
            "model_saving_pct": "model saving [%]",
            "model_saving_pct_p05": f"model saving {low} [%]",
            "model_saving_pct_p95": f"model saving {high} [%]",
            "reference_kWh": "reference [kWh]",
            "reference_saving_pct": "reference saving [%]",
        }
        rep.table(
            pd.DataFrame(check["strategies"]).rename(columns=names),
            caption="Model vs reference at constant set point",
            number_format={v: "{:,.0f}" if "kWh" in v else "{:.1f}" for v in names.values()},
        )
    fixed = [
        n for n in ESTIMATED_PARAMETERS
        if not np.isfinite(results["calibration"]["params"].get(n, {}).get("std_error") or np.nan)
    ]  # fmt: skip
    rep.paragraph(
        f"Intervals ({low} to {high}): {cfg.uncertainty.draws} draws of (H_est, capacities) "
        "from the estimated covariance (truncated to the bounds)"
        + (
            f"; without a standard error, {', '.join(fixed)} stay at their estimates"
            if fixed
            else ""
        )
        + (
            f"; audit U-values varied by {100 * cfg.uncertainty.u_value_rel_std:.0f} % "
            "(log-normal) with the calibrated HLC kept"
            if cfg.uncertainty.u_value_rel_std > 0
            else ""
        )
        + ". Savings are paired (the same draw for the strategy and for no retrofit). "
        "Retrofits change only the U-value-based conductances."
    )
    return rep.write(path)
