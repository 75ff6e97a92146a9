"""``thermocal verify CONFIG.yaml --out DIR``: post-retrofit verification, measured against
predicted saving (IPMVP Option D, ASHRAE Guideline 14-2014)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app


def _number(value: float | None, spec: str, unit: str) -> str:
    """A figure with its unit; "n/a" for one not computed (None in verify.json: NaN)."""
    return "n/a" if value is None else f"{value:{spec}} {unit}"


def _range(v: dict, spec: str) -> str:
    """The interval of a figure, "" without one (an end None in verify.json)."""
    if v.get("lo") is None or v.get("hi") is None:
        return ""
    return f"{v['lo']:{spec}} – {v['hi']:{spec}}"


def print_summary(results: dict, out: Path) -> None:
    """The verdict and the key figures (stdout, fits 80 columns)."""
    from rich import box
    from rich.console import Console
    from rich.table import Table

    console = Console()
    comp = results["comparison"]
    av = results["avoided_energy"]
    ph = results["physical_change"]
    pct = f"{100 * comp['interval']:.0f} %"
    table = Table(title="Post-retrofit verification", box=box.SIMPLE_HEAD, padding=(0, 1))
    for col in ("", "value", pct + " interval"):
        table.add_column(col, justify="left" if not col else "right")

    def row(label, v, unit="%", spec=".1f"):
        table.add_row(label, _number(v.get("value"), spec, unit), _range(v, spec))

    row("measured saving (normalised)", comp["measured_saving_pct"])
    row("predicted saving", comp["predicted_saving_pct"])
    row("difference", comp["difference_pp"], "pp", "+.1f")
    row(
        "avoided energy, post period",
        {"value": av["saving_pct"], "lo": av["saving_pct_lo"], "hi": av["saving_pct_hi"]},
    )
    table.add_row("comfort take-back", _number(av["take_back_pp"], "+.1f", "pp"), "")
    hl = ph["heat_loss_coefficient_W_per_K"]
    row("HLC before", hl["pre"], "W/K", ".0f")
    row("HLC after", hl["post"], "W/K", ".0f")
    for g in ph["groups"].values():
        row(f"{g['label']} change", g["change"], "W/K", "+.0f")
    console.print(table)
    fsu = av["fsu_at_68pct"]
    console.print(
        f"baseline (pre period, daily heat): NMBE {_number(av['baseline_nmbe_pct'], '+.1f', '%')}, "
        f"CV(RMSE) {_number(av['baseline_cv_rmse_pct'], '.1f', '%')}, FSU "
        f"{_number(None if fsu is None else 100 * fsu, '.0f', '%')} "
        "at 68 % (ASHRAE Guideline 14-2014); model fitted to the "
        + ("metered heat (indoor temperature held by a thermostat)"
           if av.get("calibration") == "heat" else "indoor temperature")
        + (f"; adjusted {av['adjustment']['post_period_kWh']:+,.0f} kWh for the post "
           "period's indoor-outdoor difference" if av.get("adjustment", {}).get("applied")
           else "")
    )  # fmt: skip
    if "truth_check" in results:
        t = results["truth_check"]["annual_saving_pct"]
        pp = results["truth_check"]["post_period_saving_pct_same_controls"]
        console.print(
            f"demo truth: annual saving {t['true']:.1f} %, verified {t['verified']:.1f} % "
            f"({t['error_pp']:+.1f} pp, {'covered' if t['covered'] else 'NOT covered'}); "
            f"post period with take-back {pp['true']:.1f} %, verified "
            f"{pp['verified_with_take_back']:.1f} %"
        )
    style = {"delivered": "green", "inconclusive": "yellow"}.get(comp["verdict"], "bold red")
    console.print(f"[{style}]{comp['verdict'].upper()}[/{style}]: {comp['explanation']}")
    # the verdict stands, but a period may hold days of the other house, or the metered
    # heat may not be on the scale of the house
    warnings = [av.get(key, {}).get("warning") for key in (
        "baseline_days_after_retrofit", "retrofitted_days_before_the_date")]  # fmt: skip
    for warning in [w for w in warnings if w] + list(comp.get("warnings") or []):
        console.print(f"[bold yellow]WARNING[/bold yellow]: {warning}")
    console.print(f"results in [bold]{out}[/bold] (verify.json, report.html, CSV, figures/)")


@app.command()
def verify(
    config: Annotated[Path | None, typer.Argument(help="verification configuration (YAML)")] = None,
    out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
        "verify-results"
    ),
    demo: Annotated[
        bool,
        typer.Option("--demo", help="verify the built-in demo house (roof + walls retrofitted)"),
    ] = False,
    regenerate: Annotated[
        bool, typer.Option("--regenerate", help="with --demo: simulate the demo data afresh")
    ] = False,
    draws: Annotated[
        int, typer.Option("--draws", min=10, help="with --demo: parameter draws")
    ] = 200,
) -> None:
    """Post-retrofit verification: did the retrofit deliver the predicted saving?

    Calibrates the fifth-order RC model on the measurements before and after the retrofit:
    avoided energy of the post period (IPMVP Option D, ASHRAE Guideline 14-2014 statistics and
    fractional savings uncertainty), heat loss coefficient before and after, the normalised
    saving against the prediction (a results.json of thermocal retrofit and a strategy code,
    or a saving given directly) and a verdict. Writes verify.json, daily_heat.csv, figures and
    report.html.
    """

    from rich.console import Console

    from thermocal.demos.verify import prepare_verify_demo
    from thermocal.errors import ThermocalInputError
    from thermocal.io.output import check_output_folder, output_folder
    from thermocal.retrofit.verify import (
        VERIFY_SIGNATURE,
        VERIFY_SITE_OPT_IN,
        load_verify_config,
        run_verify,
    )
    from thermocal.retrofit.verify_report import write_verify_outputs

    if demo == (config is not None):
        raise ThermocalInputError(
            "give a configuration file (thermocal verify CONFIG.yaml) or --demo, not both"
            if demo
            else "give a configuration file: thermocal verify CONFIG.yaml (or --demo)"
        )
    console = Console(stderr=True)
    check_output_folder(out, signature=VERIFY_SIGNATURE, inputs=(config,))
    vcfg = None if demo else load_verify_config(config)
    if vcfg is not None:  # weather far from the building (the clock: where it is read)
        from thermocal.commands.retrofit import _check_site

        _check_site(vcfg.retrofit, opt_in=VERIFY_SITE_OPT_IN)
    with (
        output_folder(out, command="verify", signature=VERIFY_SIGNATURE) as tmp,
        console.status("post-retrofit verification") as status,
    ):
        truth = None
        if demo:
            if regenerate:
                status.update("simulating the demo house with the multi-zone model")
            path, truth = prepare_verify_demo(tmp, regenerate=regenerate, draws=draws)
            vcfg = load_verify_config(path)
        ver = run_verify(vcfg, progress=lambda msg: status.update(msg), truth=truth)
        status.update("writing results, figures and report")
        results = write_verify_outputs(ver, tmp)
    print_summary(results, out)
    if demo:
        console.print(f"demo data and configuration: {out / 'data'}")
