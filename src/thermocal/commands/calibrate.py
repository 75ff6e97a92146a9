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
    reanalyse: Annotated[
        bool,
        typer.Option(
            "--reanalyse",
            help="Analyse the stored campaign again (another metric, meta-model, top_k, "
            "optimisation or posterior setting in the campaign file) without simulating.",
        ),
    ] = False,
    max_hours: Annotated[
        float,
        typer.Option(
            help="Refuse a campaign estimated to take longer (hours; samples x time per "
            "identification / workers)."
        ),
    ] = 24.0,
    advise: Annotated[
        bool,
        typer.Option(
            "--advise",
            help="Also say which heat-flux plate on an element would determine which "
            "parameters (the campaign file's posterior.advise; no simulation).",
        ),
    ] = False,
) -> None:
    """Find which envelope parameters are wrong and by how much, from zone temperature sensors.

    Writes into OUT: calibration.json, table1.csv (the critical parameters),
    samples.parquet and samples.csv (the campaign), campaign.sqlite (the durable store,
    continued by --resume), calibrated_building.yaml, figures and report.html. The results
    replace OUT in one step when all are written; the store is updated sample by sample.
    With --reanalyse nothing is simulated: the samples and the earlier analysis' model runs
    are read from the store.
    """
    from rich.console import Console

    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate as run_calibration
    from thermocal.errors import ThermocalInputError
    from thermocal.io import output
    from thermocal.io.output import check_output_folder, output_folder

    console = Console(stderr=True)
    if demo == (campaign is not None):
        raise ThermocalInputError("calibrate needs a CAMPAIGN file or --demo (not both)")
    if workers is not None and workers < 1:
        raise ThermocalInputError(f"--workers must be >= 1, got {workers}")
    if samples is not None and samples < 1:
        raise ThermocalInputError(f"--samples must be >= 1, got {samples}")
    if not max_hours > 0:
        raise ThermocalInputError(f"--max-hours must be positive, got {max_hours}")
    if reanalyse and (samples is not None or resume or scheduler is not None):
        raise ThermocalInputError(
            "--reanalyse uses the samples in the store as they are; leave out --samples, "
            "--resume and --scheduler (run the campaign without --reanalyse to add samples)"
        )
    check_output_folder(out, signature=SIGNATURE, state=STATE)
    if demo:
        # the demo's campaign file, written so that it can be edited and run again
        campaign = out / "demo_campaign.yaml"
        if reanalyse and not campaign.exists():
            raise ThermocalInputError(
                f"--reanalyse: {out} holds no demo campaign (no {campaign.name}); run "
                f"thermocal calibrate --demo --out {out} first"
            )
        if not campaign.exists() and not reanalyse:
            out.mkdir(parents=True, exist_ok=True)
            campaign.write_text(DEMO_CAMPAIGN)
    spec = load_campaign(campaign)
    if advise:
        posterior = spec.posterior.model_copy(update={"advise": True})
        spec = spec.model_copy(update={"posterior": posterior})
    store = Path(spec.store) if spec.store is not None else out / "campaign.sqlite"
    total = samples if samples is not None else spec.sampling.samples
    try:
        if reanalyse:
            from thermocal.calibration.workflow import reanalyse as run_reanalysis

            result = run_reanalysis(spec, store, log=lambda line: console.print(line))
        else:
            result = run_calibration(
                spec,
                samples=samples,
                workers=workers,
                scheduler=scheduler,
                resume=resume,
                store_path=store,
                log=lambda line: console.print(line),
                max_hours=max_hours,
            )
        with output_folder(
            out, command="calibrate", signature=SIGNATURE, state=STATE
        ) as tmp:
            written = [out / Path(p).name for p in result.to_files(tmp)]
            written += [out / p.name for p in _carry_over(out, tmp, store)]
    except KeyboardInterrupt:
        output.last_interrupted = _interrupted_message(out, store, total)
        raise
    _print_summary(result)
    for path in dict.fromkeys([store, *written]):
        console.print(f"wrote {path}")


#: Files a campaign keeps up to date in its output folder between runs (the stores, SQLite's
#: journals, the demo's campaign file, which the user may edit; see io/output.py).
STATE = ("*.sqlite", "*.sqlite-wal", "*.sqlite-shm", "*.sqlite-journal", "demo_campaign.yaml")

#: Files that mark an output folder as a calibrate result (see io/output.py).
SIGNATURE = (
    "calibration.json",
    "table1.csv",
    "campaign.sqlite",
    "demo_campaign.yaml",
    "report.html",
)


def _carry_over(out: Path, tmp: Path, store: Path) -> list[Path]:
    """Copy the campaign's durable files from ``out`` into the new results ``tmp``.

    The store (when it lives in ``out``), the Morris store and the demo's campaign file are
    the campaign's state, not results of this run: they move with the folder. SQLite files are
    copied with SQLite's backup (a consistent copy, WAL included).
    """
    import shutil
    import sqlite3

    copied = []
    names = [store.name, store.stem + "_morris.sqlite", "demo_campaign.yaml"]
    for name in dict.fromkeys(names):
        source = out / name
        if (name != "demo_campaign.yaml" and store.parent.resolve() != out.resolve()) or (
            not source.is_file() or (tmp / name).exists()
        ):
            continue
        if name.endswith(".sqlite"):
            with sqlite3.connect(str(source)) as src, sqlite3.connect(str(tmp / name)) as dst:
                src.backup(dst)
            src.close()
            dst.close()
        else:
            shutil.copy2(source, tmp / name)
        copied.append(tmp / name)
    return copied


def _interrupted_message(out: Path, store: Path, total: int) -> str:
    """What an interrupted campaign keeps: samples in the store, the previous results."""
    import sqlite3

    from thermocal.io import output

    kept = output.last_interrupted or (
        f"nothing written; {out} keeps its previous results"
        if (out / "calibration.json").exists()
        else "no results written"
    )
    try:
        con = sqlite3.connect(f"file:{store}?mode=ro", uri=True)
        try:
            done = con.execute("SELECT COUNT(*) FROM results WHERE error IS NULL").fetchone()[0]
        finally:
            con.close()
    except sqlite3.Error:
        return kept
    return (
        f"{kept}; {done} of {total} samples are kept in {store}: run the same command with "
        "--resume to continue the campaign"
    )


def _print_summary(result) -> None:
    import numpy as np
    from rich.console import Console
    from rich.table import Table

    from thermocal.textformat import format_number

    console = Console()
    table = Table(title="critical parameters (Table 1 of the published calibration method)")
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
    title = (
        "unoccupied std of the building-wide identified heat [kW]"
        if result.metric == "building"
        else "square root of the zone groups' summed unoccupied variance [kW]"
    )
    summary = Table(title=title, show_header=True)
    for column in ("model", "meta-model [kW]", "confirmed [kW]"):
        summary.add_column(column, justify="left" if column == "model" else "right")
    rows = [
        ("nominal", confirm["nominal"]),
        ("meta-model minimum", confirm["min"]),
        (f"calibrated ({confirm['calibrated']['source']})", confirm["calibrated"]),
        ("max variance", confirm["max"]),
    ]
    zoom = result.zoom
    if zoom and zoom.get("min"):  # the local campaign's meta-model minimum, after the global one
        rows.insert(2, (f"zoom: meta-model minimum ({zoom['local_samples']} local samples)",
                        zoom["min"]))  # fmt: skip
    for label, case in rows:
        predicted = case.get("predicted")
        std = case["confirmed_std_W"]
        summary.add_row(
            label,
            "" if predicted is None else f"{np.sqrt(max(predicted, 0)) / 1000:.3f}",
            format_number(std / 1000, ".3f", missing="not simulated"),
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
                else f"{100 * row['recovered_fraction'] + 0.0:.0f} %".replace("-0 %", "0 %"),
            )
        console.print(truth)
    for note in result.notes:
        console.print(f"[yellow]note:[/yellow] {note}")
