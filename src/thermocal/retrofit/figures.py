"""The retrofit report's figures: inputs, residuals, the annual demand and savings against a
reference, drawn with matplotlib.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.retrofit.config import NO_INTERVAL
from thermocal.retrofit.tables import (
    _measures_short,
    _recommended_code,
    has_intervals,
    scenario_table,
)
from thermocal.retrofit.workflow import (
    RetrofitAnalysis,
)


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
    intervals = has_intervals(results)
    whiskers = (
        f" (whiskers: {interval} of the parameter uncertainty)" if intervals else f", {NO_INTERVAL}"
    )
    figs["monthly_demand"] = plot_monthly_bars(
        dem["monthly"],
        low=dem["monthly_p05"],
        high=dem["monthly_p95"],
        reference=ref.rating_monthly_kWh,
        reference_label=ref.rating_label,
        label="calibrated model",
        title=f"Monthly heating demand{whiskers}",
    )
    scen = scenario_table(analysis)
    ends = {
        key: scen[key] if intervals else None
        for key in ("saving_pct_p05", "saving_pct_p95", "annual_kWh_p05", "annual_kWh_p95")
    }
    interval_label = f"{interval} (parameter uncertainty)" if intervals else ""
    n_measures = len(analysis.config.measures)
    sublabels = [_measures_short(s.measures, n_measures) for s in analysis.strategies]
    highlight = _recommended_code(analysis)
    figs["scenario_savings"] = plot_bars_with_intervals(
        list(scen["code"]),
        scen["saving_pct"],
        ends["saving_pct_p05"],
        ends["saving_pct_p95"],
        ylabel="Saving of heat vs. no retrofit [%]",
        highlight=(highlight,) if highlight else (),
        highlight_label=f"recommended strategy ({highlight}: "
        f"{float(scen.loc[scen['code'] == highlight, 'saving_pct'].iloc[0]):.0f} % saving)"
        if highlight
        else "",
        sublabels=sublabels,
        interval_label=interval_label,
        title=f"Saving of the {len(scen)} retrofit strategies"
        + ("" if intervals else f", {NO_INTERVAL}"),
    )
    figs["inputs"] = _inputs_figure(analysis)
    if analysis.calibration.residuals is not None:
        figs["residuals"] = _residuals_figure(analysis.calibration.residuals)
    measured = None
    if ref.measured_fuel_kWh is not None:
        measured = ref.measured_fuel_kWh * (ref.boiler_efficiency or 1.0)
    annual_refs = {k: v for k, v in dem["references"].items() if not isinstance(v, list)}
    if annual_refs:
        figs["annual_comparison"] = _annual_comparison_figure(dem, annual_refs)
    if "reference_check" in results:
        check = results["reference_check"]
        figs["reference_check"] = _reference_figure(
            check, sublabels, f"whiskers: {interval}" if intervals else NO_INTERVAL
        )
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
        ends["annual_kWh_p05"],
        ends["annual_kWh_p95"],
        ylabel="Annual heating demand [kWh]",
        highlight=("0",),
        highlight_label="no retrofit (today)",
        sublabels=sublabels,
        interval_label=interval_label,
        hline=measured,
        hline_label="measured heat use",
        title="Annual heating demand per strategy",
    )
    return figs


def _inputs_figure(analysis: RetrofitAnalysis):
    """The measured inputs: temperatures, heating power, solar gains, periods shaded."""
    import matplotlib.dates as mdates
    import matplotlib.pyplot as plt

    d = analysis.data
    fig, axes = plt.subplots(3, 1, figsize=(10, 6.6), sharex=True)
    ax = axes[0]
    ax.plot(d.index, d["Ti_measured"], color="#1f1f1f", lw=0.9, label="indoor Ti (measured)")
    ax.plot(d.index, d["Te"], color="#1b6ca8", lw=0.9, label="outdoor Te")
    ax.plot(d.index, d["Tgr"], color="#7b8794", lw=0.9, ls="--", label="ground Tgr (model)")
    ax.set_ylabel("Temperature [C]")
    ax.legend(loc="upper left", ncol=3, fontsize=8, frameon=False)
    axes[1].plot(d.index, d["phi_h_measured"] / 1000.0, color="#d95f02", lw=0.8)
    axes[1].set_ylabel("Heating power [kW]")
    axes[2].plot(d.index, d["phi_sol"] / 1000.0, color="#f0b400", lw=0.8)
    axes[2].set_ylabel("Window solar\ngains [kW]")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.axvspan(*analysis.training, color="#1b6ca8", alpha=0.06, lw=0)
        if analysis.test:
            ax.axvspan(*analysis.test, color="#d95f02", alpha=0.05, lw=0)
    axes[0].set_title(
        "Measured inputs (blue background: training period, orange: test period)",
        loc="left", fontsize=11,
    )  # fmt: skip
    axes[-1].xaxis.set_major_formatter(mdates.DateFormatter("%d %b"))
    axes[-1].set_xlim(d.index[0], d.index[-1])
    fig.tight_layout()
    return fig


def _residuals_figure(res: pd.DataFrame):
    """One-step residuals of Ti: series, autocorrelation, cumulated periodogram."""
    import matplotlib.pyplot as plt

    from thermocal.statespace.diagnostics import autocorrelation, cumulated_periodogram

    col = [c for c in res.columns if c.endswith("_residual")][0]
    e = res[col]
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.2), gridspec_kw={"width_ratios": [2, 1, 1]})
    axes[0].plot(e.index, e.to_numpy(float), color="#1b6ca8", lw=0.7)
    axes[0].axhline(0, color="black", lw=0.6)
    axes[0].set_ylabel("Residual [K]")
    axes[0].set_title("One-step-ahead residuals of Ti", loc="left", fontsize=10)
    import matplotlib.dates as mdates

    axes[0].xaxis.set_major_formatter(mdates.DateFormatter("%d %b"))
    acf = autocorrelation(e.to_numpy(float), nlags=min(48, len(e) - 2))
    axes[1].bar(acf.index[1:], acf["acf"].iloc[1:], color="#1b6ca8", width=0.8)
    axes[1].plot(acf.index[1:], acf["bound"].iloc[1:], color="#c0392b", lw=0.8)
    axes[1].plot(acf.index[1:], -acf["bound"].iloc[1:], color="#c0392b", lw=0.8)
    axes[1].set_xlabel("Lag [steps]")
    axes[1].set_title("Autocorrelation (95 % band)", loc="left", fontsize=10)
    cp = cumulated_periodogram(e.to_numpy(float))
    axes[2].plot(cp["frequency"], cp["cumulated"], color="#1b6ca8", lw=1.0)
    axes[2].plot(cp["frequency"], cp["white_noise"], color="black", lw=0.6)
    axes[2].plot(cp["frequency"], cp["lower"], color="#c0392b", lw=0.8, ls="--")
    axes[2].plot(cp["frequency"], cp["upper"], color="#c0392b", lw=0.8, ls="--")
    axes[2].set_xlabel("Frequency [1/step]")
    axes[2].set_title("Cumulated periodogram", loc="left", fontsize=10)
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def _annual_comparison_figure(dem: dict, references: dict):
    """Simulated annual demand next to reference values (Fig. 7 of the retrofit method)."""
    import textwrap

    import matplotlib.pyplot as plt

    labels = [textwrap.fill(lab, 16) for lab in ["calibrated model", *references]]
    values = [dem["value"]] + [float(v) for v in references.values()]
    fig, ax = plt.subplots(figsize=(1.8 * len(values) + 2.0, 3.6))
    colors = ["#1b6ca8"] + ["#9ecae1"] * len(references)
    bars = ax.bar(range(len(values)), values, 0.6, color=colors)
    if dem["p05"] is not None:  # none after uncertainty.draws: 0
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


def _reference_figure(check: dict, sublabels=None, whiskers: str = "whiskers: 90 % interval"):
    """The model's savings (with ``whiskers``, the legend's words on them) beside the
    reference's; no whiskers when the interval ends are None (uncertainty.draws: 0)."""
    import matplotlib.pyplot as plt

    rows = check["strategies"]
    codes = [r["code"] for r in rows]
    x = np.arange(len(codes))
    model = np.array([r["model_saving_pct"] for r in rows])
    lo = np.array([r["model_saving_pct_p05"] for r in rows], dtype=float)
    hi = np.array([r["model_saving_pct_p95"] for r in rows], dtype=float)
    yerr = np.clip(np.vstack([model - lo, hi - model]), 0, None)
    ref = np.array(
        [np.nan if r["reference_saving_pct"] is None else r["reference_saving_pct"] for r in rows]
    )
    fig, ax = plt.subplots(figsize=(10, 4.4 if sublabels else 3.8))
    ax.bar(
        x - 0.2,
        model,
        0.4,
        color="#1b6ca8",
        label=f"fifth-order model (calibrated), {whiskers}",
        yerr=yerr if np.isfinite(yerr).all() else None,
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
