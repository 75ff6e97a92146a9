"""``thermocal retrofit CONFIG.yaml --out DIR``: the retrofit analysis of paper 000."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app


def print_summary(results: dict, out: Path) -> None:
    """A rich table of the key results."""
    from rich.console import Console
    from rich.table import Table

    console = Console()
    hlc = results["heat_loss_coefficient_W_per_K"]
    dem = results["annual_heating_demand_kWh"]
    std = hlc["std"]
    line = f"HLC {hlc['value']:.0f} ± {'n/a' if std is None else format(std, '.0f')} W/K"
    if "true" in hlc:
        line += f" (true {hlc['true']:.0f} W/K, {hlc['relative_error_pct']:+.1f} %)"
    console.print(f"[bold]{line}[/bold]")
    for period, m in results["validation"].items():
        console.print(
            f"{period:5s}: MAE {m['mae']:.2f} K, MAPE {m['mape']:.2f} %, MSE {m['mse']:.2f} K², "
            f"mean simulated {m['mean_simulated']:.2f} C vs measured {m['mean_measured']:.2f} C"
        )
    console.print(
        f"annual heating demand {dem['value']:,.0f} kWh "
        f"(90 % interval {dem['p05']:,.0f} – {dem['p95']:,.0f} kWh)"
    )
    table = Table(title="Retrofit strategies")
    for col in ("code", "measures", "annual kWh", "saving %", "interval %"):
        table.add_column(col, justify="right" if col != "measures" else "left")
    for s in results["scenarios"]:
        table.add_row(
            s["code"],
            " + ".join(s["measures"]) or "none",
            f"{s['annual_kWh']:,.0f}",
            f"{s['saving_pct']:.1f}",
            f"{s['saving_pct_p05']:.1f} – {s['saving_pct_p95']:.1f}",
        )
    console.print(table)
    for flag in results["calibration"]["flags"]:
        console.print(f"[yellow]flag:[/yellow] {flag}")
    console.print(f"results in [bold]{out}[/bold] (results.json, report.html, CSV, figures/)")


@app.command()
def retrofit(
    config: Annotated[Path, typer.Argument(help="retrofit configuration (YAML)")],
    out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
        "retrofit-results"
    ),
) -> None:
    """Retrofit analysis of paper 000: calibrate, validate, annual demand, 16 strategies.

    Calibrates the fifth-order RC model on the training period, validates it on training and
    test periods, simulates the annual heating demand and the 16 envelope-retrofit strategies
    with 90 % intervals, and writes results.json, CSV tables, figures and report.html.
    """
    from rich.console import Console

    from thermocal.retrofit import load_config, run_retrofit, write_outputs

    console = Console(stderr=True)
    cfg = load_config(config)
    with console.status("retrofit analysis") as status:
        analysis = run_retrofit(cfg, progress=lambda msg: status.update(msg))
        status.update("writing results, figures and report")
        results = write_outputs(analysis, out)
    print_summary(results, out)
