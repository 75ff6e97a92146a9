"""``thermocal calibrate``: an envelope-calibration campaign."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app

DEMO_CAMPAIGN = """\
# Built-in demo: the clinic with known true envelope parameters (identification demo data).
# The paper varies most parameters by +-75 %, SHGC by +-10000 % and thicknesses by +-1000 %;
# with a few dozen samples in 70 dimensions such ranges leave almost every sample far from any
# plausible building, so the quick demo uses +-50 % for all (write the paper's ranges under
# 'ranges' for a full 500-sample campaign).
building: demo:clinic
step: 5min
identification: {method: inverse, feedback: air}
parameters:
  include: ["material/*", "window/*", "infiltration/*"]
  default_range: 0.5
sampling: {method: sobol, samples: 500, seed: 1}
metamodel: {kind: auto, top_k: 10}
optimisation: {starts: 8, seed: 1}
"""


@app.command()
def calibrate(
    campaign: Annotated[Path | None, typer.Argument(help="Campaign file (YAML).")] = None,
    out: Annotated[Path, typer.Option(help="Output directory.")] = Path("calibration"),
    samples: Annotated[
        int | None, typer.Option(help="Number of samples (overrides the campaign file).")
    ] = None,
    workers: Annotated[
        int | None, typer.Option(help="Local worker processes (default: all cores).")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option(help="Dask scheduler address, e.g. tcp://host:8786.")
    ] = None,
    resume: Annotated[
        bool, typer.Option("--resume", help="Continue the campaign in the existing store.")
    ] = False,
    demo: Annotated[
        bool, typer.Option("--demo", help="Run on the built-in clinic with known truth.")
    ] = False,
) -> None:
    """Find which envelope parameters are wrong and by how much, from zone temperature sensors.

    Writes into OUT: calibration.json, table1.csv (the critical parameters),
    samples.parquet and samples.csv (the campaign), campaign.sqlite (the durable store,
    continued by --resume), calibrated_building.yaml, figures and report.html.
    """
    from rich.console import Console

    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate as run_calibration
    from thermocal.errors import ThermocalInputError

    console = Console(stderr=True)
    if demo == (campaign is not None):
        raise ThermocalInputError("calibrate needs a CAMPAIGN file or --demo (not both)")
    if workers is not None and workers < 1:
        raise ThermocalInputError(f"--workers must be >= 1, got {workers}")
    if samples is not None and samples < 1:
        raise ThermocalInputError(f"--samples must be >= 1, got {samples}")
    out.mkdir(parents=True, exist_ok=True)
    if demo:
        # the demo's campaign file, written so that it can be edited and run again
        campaign = out / "demo_campaign.yaml"
        if not campaign.exists():
            campaign.write_text(DEMO_CAMPAIGN)
    spec = load_campaign(campaign)
    store = Path(spec.store) if spec.store is not None else out / "campaign.sqlite"
    result = run_calibration(
        spec,
        samples=samples,
        workers=workers,
        scheduler=scheduler,
        resume=resume,
        store_path=store,
        log=lambda line: console.print(line),
    )
    written = result.to_files(out)
    _print_summary(result)
    for path in [store, *written]:
        console.print(f"wrote {path}")


def _print_summary(result) -> None:
    import numpy as np
    from rich.console import Console
    from rich.table import Table

    console = Console()
    table = Table(title="critical parameters (the paper's Table 1)")
    for column in ("parameter", "unit", "nominal", "min variance", "max variance"):
        table.add_column(column, justify="left" if column == "parameter" else "right")
    for name, row in result.table1().iterrows():
        table.add_row(
            name,
            row["unit"],
            f"{row['nominal']:.4g}",
            f"{row['min_metric']:.4g}",
            f"{row['max_metric']:.4g}",
        )
    console.print(table)
    confirm = result.confirmed
    summary = Table(title="unoccupied std of the building-wide identified heat", show_header=True)
    for column in ("model", "meta-model [kW]", "confirmed [kW]"):
        summary.add_column(column, justify="left" if column == "model" else "right")
    for case, label in (
        ("nominal", "nominal"),
        ("min", "meta-model minimum"),
        ("calibrated", f"calibrated ({confirm['calibrated']['source']})"),
        ("max", "max variance"),
    ):
        predicted = confirm[case].get("predicted")
        summary.add_row(
            label,
            "" if predicted is None else f"{np.sqrt(max(predicted, 0)) / 1000:.3f}",
            f"{confirm[case]['confirmed_std_W'] / 1000:.3f}",
        )
    console.print(summary)
    if result.truth_comparison is not None:
        truth = Table(title="demo: calibrated vs the generator's truth")
        for column in ("parameter", "nominal", "calibrated", "true", "towards truth", "recovered"):
            truth.add_column(column, justify="left" if column == "parameter" else "right")
        for name, row in result.truth_comparison.iterrows():
            towards = row["moved_towards_truth"]
            truth.add_row(
                name,
                f"{row['nominal']:.4g}",
                f"{row['calibrated']:.4g}",
                f"{row['true']:.4g}",
                "-" if towards is None else ("yes" if towards else "no"),
                "-"
                if not np.isfinite(row["recovered_fraction"])
                else f"{100 * row['recovered_fraction']:.0f} %",
            )
        console.print(truth)
    for note in result.notes:
        console.print(f"[yellow]note:[/yellow] {note}")
