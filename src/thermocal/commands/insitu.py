"""``thermocal insitu LOG``: an element's in-situ U-value from a heat-flux meter's log (the
average method of ISO 9869-1), to check a log before an analysis takes it."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

import typer

from thermocal.cli import app

#: Files ``--out`` holds.
INSITU_SIGNATURE = ("in_situ.json", "running_average.csv")

#: The log's configuration keys in the messages of :mod:`thermocal.io.heat_flux_log`, and the
#: options of this command that set them.
_OPTIONS = (
    ("with LOG.heat_flux_sign inward", "with --inward"),
    ("set LOG.heat_flux_sign: outward (the default)", "drop --inward"),
    ("LOG.temperatures: surface", "--surface"),
    ("LOG.temperature_unit", "--temperature-unit"),
    ("LOG.timezone", "--timezone"),
    ("LOG.heat_flux_sign: inward", "--inward"),
    ("LOG.time_column", "--time-column"),
    ("LOG.time_unit", "--time-unit"),
    ("LOG.time_origin", "--time-origin"),
    ("LOG.columns.heat_flux", "--heat-flux"),
    ("LOG.columns.temp_in", "--temp-in"),
    ("LOG.columns.temp_out", "--temp-out"),
    ("LOG.columns (heat_flux, temp_in, temp_out)", "--heat-flux, --temp-in and --temp-out"),
    ("LOG.file", "LOG"),
    (" (LOG)", ""),
    ("LOG: ", ""),
)


def _in_options(text: str) -> str:
    """A message of the log's reader with this command's options for the configuration's
    keys."""
    for key, option in _OPTIONS:
        text = text.replace(key, option)
    return text


#: The configuration's fields in pydantic's messages (as the retrofit configuration's
#: formatter words them), the options of this command that set them, and what each allows.
_FIELDS = (
    ("areal_heat_capacity = ", "--heat-capacity ", "; give the element's areal heat capacity "
     "in kJ/(m2 K), a number above 0 and at most 2000 (about 300 for 20 cm of brick)"),
    ("(top level): ", "", ""),
    ("columns.heat_flux", "--heat-flux", ""),
    ("columns.temp_in", "--temp-in", ""),
    ("columns.temp_out", "--temp-out", ""),
    ("heat_flux, temp_in and temp_out", "--heat-flux, --temp-in and --temp-out", ""),
)  # fmt: skip


def _option_errors(exc) -> str:
    """A validation error of the options' :class:`~thermocal.io.heat_flux_log.InSituConfig`,
    worded as the retrofit configuration's (one line per problem), with this command's options
    for the configuration's keys and what each allows."""
    from thermocal.retrofit.config import _format_validation_error

    problems = []
    for line in _format_validation_error(exc, "").splitlines()[1:]:  # not the file's header
        text = line.removeprefix("  - ")
        for key, option, allowed in _FIELDS:
            if key in text:
                text = text.replace(key, option) + allowed
        problems.append(text)
    return "thermocal insitu: " + "\n  ".join(problems)


def print_result(result, source: str, running) -> None:
    """The value, its uncertainty and the criteria (stdout, fits 80 columns)."""
    import numpy as np
    from rich import box
    from rich.console import Console
    from rich.table import Table

    console = Console()
    table = Table(title=f"In-situ U-value: {source}", box=box.SIMPLE_HEAD, padding=(0, 1))
    table.add_column("")
    table.add_column("value", justify="right")
    table.add_row("U (air to air)", f"{result.u_value:.3f} W/(m2 K)")
    if np.isfinite(result.conductance):
        table.add_row("Lambda (surface to surface)", f"{result.conductance:.3f} W/(m2 K)")
    table.add_row("R (the element)", f"{result.resistance:.3f} m2 K/W")
    table.add_row("standard uncertainty", f"{100 * result.rel_std:.1f} %")
    for part, value in result.uncertainty.items():
        table.add_row(f"  of which {part}", f"{100 * value:.1f} %")
    table.add_row("whole days / mean difference", f"{result.days} / "
                  f"{result.mean_difference_K:.1f} K")  # fmt: skip
    for name, check in result.checks.items():
        value = (
            f"{check['value']:g} d" if name == "duration" else f"{100 * check['value']:.1f} %"
        )
        limit = f"{check['limit']:g} d" if name == "duration" else f"{100 * check['limit']:.0f} %"
        verdict = "passes" if check["passed"] else "FAILS"
        table.add_row(f"ISO 9869-1 {name}", f"{value} (limit {limit}) {verdict}")
    if "heat stored" not in result.checks:
        table.add_row("ISO 9869-1 heat stored", "NOT CHECKED (--heat-capacity)")
    console.print(table)
    from thermocal.physics.heat_flux import IMPLAUSIBLY_THICK

    for warning in result.warnings:
        console.print(f"[bold yellow]warning:[/bold yellow] {warning}")
    for note in result.notes:  # a likely fault of the log stands out from what was assumed
        warning = note.startswith(IMPLAUSIBLY_THICK)
        console.print(f"{'[bold yellow]warning:[/bold yellow]' if warning else 'note:'} {note}")
    if len(running) > 1:
        tail = ", ".join(f"{v:.3f}" for v in running.tail(4))
        console.print(f"running average at the last days' ends: {tail} W/(m2 K)")
    console.print(
        "as a surveyed value in a retrofit configuration (walls, roof, attic_ceiling, ...):\n"
        f"  in_situ: {{COMPONENT: {{u_value: {result.u_value:.3g}, "
        f"rel_std: {result.rel_std:.2g}}}}}"
    )
    # the average method refuses a U-value that leaves the element no resistance; a result
    # without one has nothing to give a campaign (its uncertainty would be NaN or negative)
    if result.resistance > 0 and result.resistance_rel_std > 0:
        console.print(
            "or in a calibration campaign:\n"
            f"  in_situ: {{construction/NAME/resistance: {{resistance: {result.resistance:.3g}, "
            f"rel_std: {result.resistance_rel_std:.2g}}}}}"
        )


@app.command()
def insitu(
    log: Annotated[Path, typer.Argument(help="heat-flux meter log (CSV or parquet, wide)")],
    heat_flux: Annotated[
        str, typer.Option("--heat-flux", help="column of the heat flux [W/m2]")
    ] = "q",
    temp_in: Annotated[str, typer.Option("--temp-in", help="column of the inside temperature")] = (
        "Ti"
    ),
    temp_out: Annotated[
        str, typer.Option("--temp-out", help="column of the other side's temperature")
    ] = "Te",
    time_column: Annotated[str, typer.Option("--time-column")] = "time",
    time_unit: Annotated[
        str | None,
        typer.Option("--time-unit", help="of numeric times: s (Unix seconds), min, h, d, ms"),
    ] = None,
    time_origin: Annotated[
        str | None,
        typer.Option("--time-origin", help="instant of numeric time 0 (default 1970-01-01 UTC)"),
    ] = None,
    temperature_unit: Annotated[
        Literal["C", "K", "F"], typer.Option("--temperature-unit")
    ] = "C",
    timezone: Annotated[str | None, typer.Option("--timezone", help="of naive stamps")] = None,
    surface: Annotated[
        bool,
        typer.Option(
            "--surface",
            help="the temperatures are the element's faces (air temperatures miss the sun on "
            "the outside face: ISO 9869-1 asks for a spot out of direct sun)",
        ),
    ] = False,
    flow: Annotated[
        Literal["horizontal", "upward", "downward"],
        typer.Option("--flow", help="heat flow through the element: wall, roof, floor"),
    ] = "horizontal",
    unheated: Annotated[
        bool, typer.Option("--unheated", help="the other side is an unheated space")
    ] = False,
    inward: Annotated[
        bool, typer.Option("--inward", help="the plate reports inward flow as positive")
    ] = False,
    heat_capacity: Annotated[
        float | None,
        typer.Option(
            "--heat-capacity",
            help="the element's, kJ/(m2 K): ISO 9869-1 criterion d, required above 20",
        ),
    ] = None,
    out: Annotated[
        Path | None, typer.Option("--out", "-o", help="write in_situ.json and the figure here")
    ] = None,
) -> None:
    """An element's in-situ U-value from a heat-flux meter's log (ISO 9869-1, average method).

    Sums the heat flux and the temperature difference over the log's whole days, checks the
    standard's convergence criteria (72 h; the last day and the first vs last two thirds within
    5 %; the stored heat with --heat-capacity, which ISO 9869-1 requires of any element above
    20 kJ/(m2 K): without it the result warns that convergence is not shown), and states the
    standard uncertainty (the defaults of the configurations' in_situ entries: plate 5 %, spot
    5 %, sensors 0.1 K). With --out: in_situ.json, running_average.csv and
    figures/running_average.png. Exits with 1 when the criteria fail (the analyses would refuse
    the log).
    """
    from pydantic import ValidationError

    from thermocal.errors import ThermocalInputError
    from thermocal.io.heat_flux_log import (
        InSituConfig,
        read_heat_flux_log,
        reduce_heat_flux_log,
        surface_resistances_of,
    )
    from thermocal.physics.heat_flux import running_average

    try:
        spec = InSituConfig(
            file=log, time_column=time_column, timezone=timezone, time_unit=time_unit,
            time_origin=time_origin,
            columns={"heat_flux": heat_flux, "temp_in": temp_in, "temp_out": temp_out},
            temperature_unit=temperature_unit, temperatures="surface" if surface else "air",
            heat_flux_sign="inward" if inward else "outward", areal_heat_capacity=heat_capacity,
            other_side="unheated" if unheated else "outdoors", flow=flow,
        )  # fmt: skip
    except ValidationError as exc:  # e.g. two options naming one column
        raise ThermocalInputError(_option_errors(exc)) from None
    try:
        times, q, ti, te = read_heat_flux_log(spec, "LOG")
        # not refused when it has not converged: this command shows why
        films = surface_resistances_of(spec, flow)
        result = reduce_heat_flux_log(spec, "LOG", times, q, ti, te, films)
    except ThermocalInputError as exc:
        raise ThermocalInputError(_in_options(str(exc))) from None
    source = f"{log.name}: ISO 9869-1 average method, {result.days} days"
    running = running_average(times, q, ti, te)
    if surface:  # the running average is Lambda; shown as U like the result
        films = sum(result.surface_resistances)
        running = 1.0 / (films + 1.0 / running)
    print_result(result, source, running)
    if out is not None:
        _write(out, result, source, running)
    from rich.console import Console

    from thermocal.physics.heat_flux import D_NOT_CHECKED

    if result.status == D_NOT_CHECKED:  # not a failure (a light element needs no d): said
        Console().print(
            f"[bold yellow]CONVERGENCE NOT SHOWN[/bold yellow] ({D_NOT_CHECKED}): give "
            "--heat-capacity for an element above 20 kJ/(m2 K) (ISO 9869-1 7.2.1)"
        )
    if not result.converged:
        Console().print(
            f"[bold red]NOT CONVERGED[/bold red] ({'; '.join(result.failed())}): log longer "
            "(whole days of winter); thermocal retrofit and calibrate refuse this log"
        )
        raise typer.Exit(1)


def _write(out: Path, result, source: str, running) -> None:
    """in_situ.json, running_average.csv and figures/running_average.png into ``out``."""
    import json

    from thermocal.io.output import output_folder

    with output_folder(out, command="insitu", signature=INSITU_SIGNATURE) as tmp:
        (tmp / "in_situ.json").write_text(
            json.dumps({"source": source, **result.as_dict()}, indent=1) + "\n"
        )
        running.rename_axis("day_end").to_csv(tmp / "running_average.csv")
        (tmp / "figures").mkdir()
        _figure(running, result).savefig(tmp / "figures" / "running_average.png", dpi=120)


def _figure(running, result):
    """The running average over the days against the result's +-5 % band."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.5))
    days = range(1, len(running) + 1)
    ax.plot(days, running.to_numpy(), marker="o", label="average up to the day's end")
    ax.axhspan(0.95 * result.u_value, 1.05 * result.u_value, alpha=0.2, label="the result +- 5 %")
    ax.set_xlabel("whole days of the log")
    ax.set_ylabel("U [W/(m2 K)]")
    ax.set_title("ISO 9869-1 average method: convergence")
    ax.legend(loc="best")
    fig.tight_layout()
    return fig
