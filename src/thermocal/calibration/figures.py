"""Figures of the envelope calibration (matplotlib, Agg)."""

from __future__ import annotations

import numpy as np

from thermocal.report.figures import COLORS, plt


def sensitivity_bars(result, *, show: int = 30):
    """Influence of each parameter on the metric, critical ones highlighted (the paper's Fig. 6)."""
    ranking = result.ranking.sort_values(ascending=False).head(show)
    fig, ax = plt.subplots(figsize=(10, 0.22 * len(ranking) + 1.2))
    colors = [
        COLORS["simulated"] if name in result.critical else COLORS["secondary"]
        for name in ranking.index
    ]
    ax.barh(range(len(ranking)), ranking.to_numpy(), color=colors)
    ax.set_yticks(range(len(ranking)))
    ax.set_yticklabels(ranking.index, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("share of the meta-model's response to a 10 % change in each range [-]")
    ax.set_title(
        f"Parameter influence on the unoccupied variance (top {len(result.critical)} coloured; "
        f"{len(result.ranking)} parameters, {min(show, len(result.ranking))} shown)"
    )
    fig.tight_layout()
    return fig


def heat_cases(result):
    """Building-wide Q_ID for the nominal, minimum- and maximum-variance models (Fig. 7)."""
    fig, axes = plt.subplots(
        3, 1, figsize=(10, 7.2), sharex=True, gridspec_kw={"height_ratios": [2, 2, 1.2]}
    )
    for key, color, label in (
        ("nominal", COLORS["measured"], "nominal"),
        ("min", COLORS["primary"], "minimum variance"),
    ):
        if key not in result.heat:  # a re-analysis does not simulate a new optimum
            continue
        series = result.heat[key]
        axes[0].plot(series.index, series / 1000, lw=0.7, color=color, label=label)
    axes[0].set_ylabel("Q_ID [kW]")
    axes[0].legend(loc="upper right", fontsize=8)
    axes[0].set_title("Building-wide identified heat: nominal and calibrated (minimum variance)")
    if "max" in result.heat:
        series = result.heat["max"]
        axes[1].plot(series.index, series / 1000, lw=0.7, color=COLORS["reference"])
    axes[1].set_ylabel("Q_ID [kW]")
    axes[1].set_title("Maximum-variance parameters (note the scale)")
    axes[2].plot(
        result.weather.index, result.weather["temp_air"], color=COLORS["reference"], lw=0.8
    )
    axes[2].set_ylabel("outdoor [C]")
    twin = axes[2].twinx()
    twin.fill_between(result.weather.index, result.weather["ghi"], color="#f0b400", alpha=0.4, lw=0)
    twin.set_ylabel("GHI [W/m2]")
    fig.autofmt_xdate()
    fig.tight_layout()
    return fig


def parity(result):
    """Meta-model out-of-fold prediction vs the simulated metric."""
    y = result.store_frame.loc[result.store_frame["error"].isna(), "out:unoccupied_variance"]
    predicted = result.surrogate.oof_prediction_
    fig, ax = plt.subplots(figsize=(5.2, 5))
    scale = 1e6
    ax.scatter(y / scale, predicted / scale, s=8, alpha=0.6, color=COLORS["primary"])
    low = min(y.min(), np.min(predicted)) / scale
    high = max(y.max(), np.max(predicted)) / scale
    ax.plot([low, high], [low, high], color="k", lw=0.8)
    ax.set_xlabel("simulated unoccupied variance [kW^2]")
    ax.set_ylabel("meta-model, out of fold [kW^2]")
    ax.set_title(
        f"Meta-model parity: R2 {result.surrogate.cv_r2_:.3f}, "
        f"RMSE {result.surrogate.cv_rmse_ / scale:.3g} kW^2"
    )
    fig.tight_layout()
    return fig


def calibration_figures(result) -> dict:
    """All figures of a calibration result, by file stem."""
    return {
        "sensitivity": sensitivity_bars(result),
        "q_id_cases": heat_cases(result),
        "metamodel_parity": parity(result),
    }
