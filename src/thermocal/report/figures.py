"""Standard figures of the thermocal workflows (matplotlib, non-interactive Agg backend)."""

from __future__ import annotations

import base64
import io
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.dates as mdates  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

MONTH_LABELS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")
COLORS = {
    "measured": "#1f1f1f",
    "simulated": "#d95f02",
    "primary": "#1b6ca8",
    "secondary": "#9ecae1",
    "reference": "#c0392b",
    "band": "#fdd0a2",
}


def figure_to_png(fig, *, dpi: int = 110) -> bytes:
    """PNG bytes of a figure (render once, then write and embed the same bytes)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    return buf.getvalue()


def figure_to_base64(fig, *, dpi: int = 110) -> str:
    """PNG of a figure, base64-encoded (for ``<img src="data:image/png;base64,...">``)."""
    return base64.b64encode(figure_to_png(fig, dpi=dpi)).decode("ascii")


def save_figure(fig, path: Path | str, *, dpi: int = 110) -> Path:
    """Write a figure as PNG and return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    return path


def plot_measured_vs_simulated(
    index: pd.DatetimeIndex,
    measured,
    simulated,
    *,
    title: str = "",
    ylabel: str = "Indoor air temperature [C]",
    band=None,
    metrics_text: str | None = None,
):
    """Measured and simulated time series on one axis (Figs. 4-5 of the retrofit method).

    Parameters
    ----------
    index : pd.DatetimeIndex
    measured, simulated : array-like [C]
    band : tuple of array-like (low, high), optional
        Shaded interval around the simulation.
    metrics_text : str, optional
        Text box in the upper left corner (e.g. ``"MAE 0.86 K"``).
    """
    fig, ax = plt.subplots(figsize=(10, 3.6))
    if band is not None:
        ax.fill_between(
            index, band[0], band[1], color=COLORS["band"], alpha=0.6, lw=0, label="90 % interval"
        )
    ax.plot(index, np.asarray(measured, float), color=COLORS["measured"], lw=1.0, label="measured")
    ax.plot(
        index, np.asarray(simulated, float), color=COLORS["simulated"], lw=1.3, label="simulated"
    )
    ax.set_ylabel(ylabel)
    ax.set_title(title, loc="left", fontsize=11)
    ax.grid(alpha=0.3)
    if len(index):
        ax.set_xlim(index[0], index[-1])  # the period itself, no empty days on either side
    ax.xaxis.set_major_formatter(mdates.DateFormatter("%d %b"))
    ax.legend(loc="upper right", ncol=3, fontsize=9, frameon=False)
    if metrics_text:
        ax.text(
            0.01,
            0.97,
            metrics_text,
            transform=ax.transAxes,
            va="top",
            fontsize=9,
            bbox={"boxstyle": "round", "fc": "white", "ec": "#cccccc"},
        )
    fig.tight_layout()
    return fig


def plot_monthly_bars(
    values,
    *,
    reference=None,
    reference_label: str = "reference",
    label: str = "simulated",
    ylabel: str = "Heating demand [kWh]",
    title: str = "",
    low=None,
    high=None,
):
    """Monthly bars (12 values) with an optional reference series and interval whiskers."""
    x = np.arange(12)
    fig, ax = plt.subplots(figsize=(9, 3.6))
    width = 0.38 if reference is not None else 0.7
    vals = np.asarray(values, float)
    yerr = None
    if low is not None and high is not None:
        yerr = np.vstack([vals - np.asarray(low, float), np.asarray(high, float) - vals])
        yerr = np.clip(yerr, 0, None)
    offset = -width / 2 if reference is not None else 0.0
    ax.bar(
        x + offset,
        vals,
        width,
        color=COLORS["primary"],
        label=label,
        yerr=yerr,
        capsize=2,
        error_kw={"elinewidth": 0.8},
    )
    if reference is not None:
        ax.bar(
            x + width / 2,
            np.asarray(reference, float),
            width,
            color=COLORS["secondary"],
            label=reference_label,
        )
    ax.set_xticks(x, MONTH_LABELS)
    ax.set_ylabel(ylabel)
    ax.set_title(title, loc="left", fontsize=11)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(frameon=False, fontsize=9)
    fig.tight_layout()
    return fig


def plot_bars_with_intervals(
    labels: Sequence[str],
    values,
    low,
    high,
    *,
    ylabel: str = "",
    title: str = "",
    highlight: Sequence[str] = (),
    highlight_label: str = "",
    sublabels: Sequence[str] | None = None,
    interval_label: str = "",
    hline: float | None = None,
    hline_label: str = "",
):
    """Bars with interval whiskers, e.g. the savings of the retrofit strategies (paper Fig. 8).

    Parameters
    ----------
    labels : sequence of str
    values, low, high : array-like
        Central values and the interval bounds (``low`` and ``high`` None: no whiskers).
    highlight : sequence of str
        Labels drawn in the accent colour.
    highlight_label : str
        Legend entry explaining the accent colour (shown when something is highlighted).
    sublabels : sequence of str, optional
        Smaller text under each label (e.g. the measures of a strategy code).
    interval_label : str
        Legend entry of the whiskers (e.g. ``"90 % interval"``).
    hline : float, optional
        A horizontal reference line (e.g. a measured value).
    """
    vals = np.asarray(values, float)
    yerr = None
    if low is not None and high is not None:
        yerr = np.clip(
            np.vstack([vals - np.asarray(low, float), np.asarray(high, float) - vals]), 0, None
        )
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    colors = [COLORS["simulated"] if lab in highlight else COLORS["primary"] for lab in labels]
    fig, ax = plt.subplots(figsize=(10, 4.4 if sublabels is not None else 3.8))
    x = np.arange(len(labels))
    ax.bar(x, vals, 0.7, color=colors, yerr=yerr, capsize=3, error_kw={"elinewidth": 0.9})
    ax.set_xticks(x, labels)
    if sublabels is not None:
        for xi, sub in zip(x, sublabels, strict=True):
            ax.annotate(
                sub, (xi, 0), xycoords=("data", "axes fraction"), xytext=(0, -18),
                textcoords="offset points", ha="center", va="top", fontsize=7, color="#444444",
            )  # fmt: skip
    ax.set_ylabel(ylabel)
    ax.set_title(title, loc="left", fontsize=11)
    ax.grid(axis="y", alpha=0.3)
    handles = []
    if highlight and highlight_label and any(lab in highlight for lab in labels):
        handles.append(Patch(color=COLORS["simulated"], label=highlight_label))
    if interval_label:
        handles.append(
            Line2D([], [], color="black", lw=0.9, marker="_", ms=8, label=interval_label)
        )
    if hline is not None:
        ax.axhline(hline, color=COLORS["reference"], lw=1.5)
        handles.append(Line2D([], [], color=COLORS["reference"], lw=1.5, label=hline_label))
    if handles:
        top = np.nanmax(np.concatenate([vals, np.asarray(vals if high is None else high, float)]))
        if np.isfinite(top) and top > 0:
            ax.set_ylim(top=1.12 * top + 0.06 * top * len(handles))  # room for the legend
        ax.legend(handles=handles, frameon=False, fontsize=9, loc="best")
    fig.tight_layout()
    return fig


def close(fig) -> None:
    """Release a figure's memory."""
    plt.close(fig)
