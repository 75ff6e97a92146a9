"""Figures of a fit: measured vs predicted output, residual ACF, cumulated periodogram."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thermocal.statespace.diagnostics import autocorrelation, cumulated_periodogram


def _pyplot():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def plot_prediction(results, output: str, path: str | Path, *, simulation=True) -> Path:
    """Measured output, one-step prediction (with 95 % band) and deterministic simulation [C]."""
    plt = _pyplot()
    res = results.one_step_residuals()
    fig, (ax, axr) = plt.subplots(
        2, 1, figsize=(10, 6), sharex=True, height_ratios=[3, 1], layout="constrained"
    )
    x = res.index
    ax.plot(x, res[output], ".", ms=2.5, color="k", label="measured")
    ax.plot(x, res[f"{output}_pred"], "-", lw=1.0, color="tab:blue", label="one-step prediction")
    ax.fill_between(
        x,
        res[f"{output}_pred"] - 1.96 * res[f"{output}_std"],
        res[f"{output}_pred"] + 1.96 * res[f"{output}_std"],
        color="tab:blue",
        alpha=0.2,
        lw=0,
        label="95 % prediction interval",
    )
    if simulation:
        sim = results.simulate()
        ax.plot(x, sim[output], "-", lw=1.0, color="tab:orange", label="simulation (no feedback)")
    ax.set_ylabel(f"{output} [C]")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"{results.model.name}: measured and predicted {output}")
    axr.plot(x, res[f"{output}_residual"], "-", lw=0.8, color="k")
    axr.axhline(0, color="0.5", lw=0.5)
    axr.set_ylabel("residual [K]")
    unit = getattr(results.data, "time_unit", "s")
    axr.set_xlabel("time" if hasattr(x, "tz") else f"time [{unit}]")
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_residual_diagnostics(results, output: str, path: str | Path, *, nlags: int = 40) -> Path:
    """Autocorrelation of the one-step residuals and their cumulated periodogram, with bands."""
    from thermocal.statespace.results import observation_rows

    plt = _pyplot()
    residuals = results.residuals
    # on the rows the residual tests take (a midpoint grid's observations, every second row:
    # all rows would make every odd lag NaN)
    rows = observation_rows(residuals[[output]].to_numpy(dtype=float))
    e = residuals[output].to_numpy()[rows]
    acf = autocorrelation(e, nlags=nlags)
    cp = cumulated_periodogram(e)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4), layout="constrained")
    a1.vlines(acf.index[1:], 0, acf["acf"].iloc[1:], color="k")
    a1.axhline(0, color="0.5", lw=0.5)
    a1.fill_between(
        acf.index,
        -acf["bound"],
        acf["bound"],
        step="mid",
        color="tab:blue",
        alpha=0.15,
        lw=0,
        label="95 % white-noise bound",
    )
    a1.set_xlabel("lag [samples]")
    a1.set_ylabel("autocorrelation [-]")
    a1.set_title(f"ACF of one-step residuals ({output})")
    a1.legend(fontsize=8)
    a2.plot(cp["frequency"], cp["cumulated"], color="k", lw=1, label="cumulated periodogram")
    a2.plot(cp["frequency"], cp["white_noise"], color="tab:blue", lw=0.8, label="white noise")
    a2.fill_between(
        cp["frequency"],
        np.clip(cp["lower"], 0, 1),
        np.clip(cp["upper"], 0, 1),
        color="tab:blue",
        alpha=0.15,
        lw=0,
        label="95 % band",
    )
    a2.set_xlim(0, 0.5)
    a2.set_ylim(0, 1)
    a2.set_xlabel("frequency [1/sample]")
    a2.set_ylabel("cumulated periodogram [-]")
    a2.set_title("Cumulated periodogram")
    a2.legend(fontsize=8, loc="lower right")
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_fit(results, outdir: str | Path) -> list[Path]:
    """All figures of a fit, one pair per output; returns the written paths."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    paths = []
    for output in results.model.output_names:
        paths.append(plot_prediction(results, output, outdir / f"prediction_{output}.png"))
        paths.append(plot_residual_diagnostics(results, output, outdir / f"residuals_{output}.png"))
    return paths
