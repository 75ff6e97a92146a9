"""Figures (matplotlib) and self-contained HTML reports shared by the thermocal workflows.

Public API
----------
HtmlReport
    Builder of a single-file HTML report: headings, paragraphs, key-value summaries, tables
    (from DataFrames) and figures embedded as base64 PNG.
figure_to_png, figure_to_base64, save_figure
    Render a matplotlib figure.
plot_measured_vs_simulated, plot_monthly_bars, plot_bars_with_intervals
    The standard figures of the workflows.
"""

from thermocal.report.figures import (
    figure_to_base64,
    figure_to_png,
    plot_bars_with_intervals,
    plot_measured_vs_simulated,
    plot_monthly_bars,
    save_figure,
)
from thermocal.report.html import HtmlReport

__all__ = [
    "HtmlReport",
    "figure_to_base64",
    "figure_to_png",
    "plot_bars_with_intervals",
    "plot_measured_vs_simulated",
    "plot_monthly_bars",
    "save_figure",
]
