"""``thermocal demo``: the retrofit workflow (fifth-order RC method) on built-in data."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app


@app.command()
def demo(
    out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
        "thermocal-demo"
    ),
    weather: Annotated[
        Path | None,
        typer.Option(
            "--weather",
            help="EPW/TMY3 file: regenerate the demo measurements with this weather and use it "
            "for the annual demand (default: pvlib's TMY3 of Greensboro, NC)",
        ),
    ] = None,
    regenerate: Annotated[
        bool, typer.Option("--regenerate", help="simulate the demo data afresh")
    ] = False,
    draws: Annotated[
        int, typer.Option("--draws", min=0, help="parameter draws for the uncertainty intervals")
    ] = 200,
    advise: Annotated[
        bool,
        typer.Option(
            "--advise",
            help="also say which in-situ U-value (a heat-flux plate) would narrow the savings' "
            "intervals most (about 10 more analyses)",
        ),
    ] = False,
) -> None:
    """Run the retrofit analysis (fifth-order RC method) on built-in demo data.

    The data: a 1950s three-storey house simulated by the detailed multi-zone model
    (radiators under thermostat control, Feb 2 - Mar 15, Greensboro NC typical-year weather).
    Writes results.json, CSV tables, figures and report.html into --out.
    """
    import json

    from rich.console import Console

    from thermocal.commands.retrofit import (
        RETROFIT_SIGNATURE,
        print_measurement_advice,
        print_summary,
    )
    from thermocal.demos.retrofit import prepare_demo
    from thermocal.errors import ThermocalInputError
    from thermocal.io.output import output_folder
    from thermocal.retrofit import load_config, run_retrofit, write_outputs
    from thermocal.retrofit.config import MAX_DRAWS

    if draws > MAX_DRAWS:
        raise ThermocalInputError(
            f"--draws {draws}: at most {MAX_DRAWS:,} draws (a 90 % interval settles within a "
            "few thousand; the default is 200)"
        )
    if advise:  # before the demo runs
        from thermocal.retrofit.advice import check_advice_draws

        check_advice_draws(draws, option="--draws")
    if weather is not None and not Path(weather).is_file():
        raise ThermocalInputError(
            f"--weather {weather}: "
            + ("is a folder, not a file" if Path(weather).is_dir() else "file not found")
        )
    console = Console(stderr=True)
    with (
        output_folder(out, command="demo", signature=RETROFIT_SIGNATURE) as tmp,
        console.status("preparing demo data") as status,
    ):
        if weather is not None or regenerate:
            status.update("simulating the demo house with the multi-zone model")
        config_path, true_hlc = prepare_demo(
            tmp, weather=weather, regenerate=regenerate, draws=draws
        )
        cfg = load_config(config_path)
        analysis = run_retrofit(cfg, progress=lambda msg: status.update(msg))
        advice = None
        if advise:
            from thermocal.retrofit.advice import advise_measurements

            advice = advise_measurements(cfg, analysis, progress=status.update)
        status.update("writing results, figures and report")
        truth = json.loads((config_path.parent / "truth.json").read_text())
        results = write_outputs(
            analysis,
            tmp,
            true_hlc=true_hlc,
            title="thermocal demo: retrofit analysis of a 1950s house",
            reference_demands=truth.get("annual_heating_demand_20C_kWh"),
            reference_monthly=truth.get("monthly_heating_demand_20C_kWh"),
            reference_label="the generator (multi-zone model, ideal heating at 20 C)",
            measurement_advice=advice,
        )
    print_summary(results, out)
    if advice is not None:
        print_measurement_advice(advice)
    console.print(f"demo data and configuration: {out / config_path.parent.name}")
