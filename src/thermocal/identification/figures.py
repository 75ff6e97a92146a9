"""Figures of the heat-balance identification (matplotlib, Agg)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.report.figures import COLORS, plt


def tuning_oscillation(tuning):
    """The Ziegler-Nichols experiment at the ultimate gain (the paper's Fig. 3)."""
    fig, ax = plt.subplots(figsize=(9, 3.2))
    trace = tuning.oscillation
    shown = trace[trace.index <= max(6.0, trace.index[0])]
    ax.plot(
        shown.index,
        shown["model_temperature_C"],
        color=COLORS["simulated"],
        lw=1,
        label="model air temperature",
    )
    ax.plot(
        shown.index,
        shown["reference_C"],
        color=COLORS["measured"],
        lw=1,
        ls="--",
        label="reference (step)",
    )
    ax.set_xlabel("time [h]")
    ax.set_ylabel("temperature [C]")
    ku = tuning.experiment_gain or tuning.ultimate_gain
    ax.set_title(
        f"Ziegler-Nichols on {tuning.zone}: proportional gain {ku:.0f} W/K (ultimate), "
        f"period {tuning.ultimate_period / 60:.0f} min"
    )
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    return fig


def typical_zone(result, zone: str | None = None):
    """Sensor vs model temperature of a typical zone, with the tracking error (Fig. 4-5)."""
    method = "pid" if "pid" in result.model_temperature else result.metric_source
    metrics = result.tracking[method]
    if zone is None:
        ranked = metrics["rmse_K"].sort_values()
        zone = ranked.index[len(ranked) // 2]
    model = result.model_temperature[method][zone]
    reference = result.reference[zone]
    error = model - reference
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(10, 5.2), sharex=True)
    ax1.plot(
        _plot_times(reference.index, ax1, ax2),
        reference.to_numpy(),
        color=COLORS["measured"],
        lw=0.8,
        label="sensor",
    )
    ax1.plot(
        _plot_times(model.index, ax1, ax2),
        model.to_numpy(),
        color=COLORS["simulated"],
        lw=0.8,
        label=f"model ({method})",
    )
    ax1.set_ylabel("temperature [C]")
    ax1.legend(loc="upper right", fontsize=8)
    row = metrics.loc[zone]
    ax1.set_title(
        f"{zone}: tracking RMSE {row['rmse_K']:.3f} K, max |error| {row['max_abs_error_K']:.2f} K, "
        f"error std {row['error_std_percent']:.2f} % points"
    )
    ax2.plot(_plot_times(error.index, ax1, ax2), error.to_numpy(), color=COLORS["primary"], lw=0.7)
    ax2.axhline(0, color="k", lw=0.5)
    ax2.set_ylabel("model - sensor [K]")
    fig.autofmt_xdate()
    fig.tight_layout()
    return fig


def building_heat(result, extra: dict[str, pd.Series] | None = None):
    """Building-wide Q_ID, unoccupied steps shaded; outdoor temperature and sun below (Fig. 7)."""
    fig, (ax1, ax2) = plt.subplots(
        2, 1, figsize=(10, 5.6), sharex=True, gridspec_kw={"height_ratios": [2, 1]}
    )
    mask = result.unoccupied_mask_all()
    index = result.q_id.index
    times = _plot_times(index, ax1, ax2)
    series = {}
    if result.q_inverse is not None:
        series["exact inverse"] = result.q_inverse.sum(axis=1)
    if result.q_pid is not None:
        series["PID"] = result.q_pid.sum(axis=1)
    series.update(extra or {})
    colors = [COLORS["primary"], COLORS["simulated"], "#2ca02c", "#7f7f7f"]
    for (label, values), color in zip(series.items(), colors, strict=False):
        ax1.plot(
            _plot_times(values.index, ax1, ax2),
            (values / 1000.0).to_numpy(),
            lw=0.7,
            color=color,
            label=label,
        )
    _shade(ax1, index, mask)
    ax1.set_ylabel("identified heat [kW]")
    ax1.legend(loc="upper right", fontsize=8)
    std = np.sqrt(result.unoccupied_variance())
    ax1.set_title(
        f"Building-wide identified heat (grey: unoccupied); unoccupied std {std / 1000:.2f} kW"
    )
    ax2.plot(times, result.weather["temp_air"].to_numpy(), color=COLORS["reference"], lw=0.8)
    ax2.set_ylabel("outdoor [C]", color=COLORS["reference"])
    twin = ax2.twinx()
    twin.fill_between(times, result.weather["ghi"].to_numpy(), color="#f0b400", alpha=0.4, lw=0)
    twin.set_ylabel("global horizontal [W/m2]", color="#a07800")
    fig.autofmt_xdate()
    fig.tight_layout()
    return fig


def _plot_times(index, *axes):
    """Step times for matplotlib: a time-zone aware index as naive UTC ``datetime64`` with the
    ``axes``' date labels set to its time zone.

    Matplotlib converts aware timestamps one by one (about a second for a month of 5-minute
    steps in three series); ``datetime64`` values are converted at once. Aware timestamps are
    plotted at their UTC instants and labelled in their zone, so the figure is the same.

    Parameters
    ----------
    index : DatetimeIndex
    *axes : matplotlib Axes
        The axes (sharing the x axis) the times are plotted on.

    Returns
    -------
    ndarray of datetime64 or the index (naive)
    """
    if getattr(index, "tz", None) is None:
        return index
    for ax in axes:
        ax.xaxis_date(index.tz)
    return index.tz_convert("UTC").tz_localize(None).to_numpy()


def _shade(ax, index, mask):
    mask = np.asarray(mask)
    if not mask.any():
        return
    from thermocal.io.measurements.quality import true_runs

    step = index[1] - index[0]
    for a, b in zip(*true_runs(mask), strict=True):
        ax.axvspan(index[a], index[b - 1] + step, color="#e4e9ef", lw=0, zorder=0)


def identification_figures(result) -> dict:
    """All figures of a result, by file stem."""
    figures = {"building_q_id": building_heat(result), "typical_zone": typical_zone(result)}
    if result.tuning is not None:
        figures["tuning_oscillation"] = tuning_oscillation(result.tuning)
    return figures
