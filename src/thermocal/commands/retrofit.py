"""``thermocal retrofit CONFIG.yaml --out DIR``: retrofit analysis with the fifth-order RC
method (calibration, validation, annual demand, retrofit strategies, report)."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app


def measure_abbreviations(names) -> dict[str, str]:
    """Shortest unique prefix of each measure name, capitalised (roof -> R, walls -> Wa,
    windows -> Wi), for a strategy table that fits an 80-column terminal."""
    out = {}
    for name in names:
        for n in range(1, len(name) + 1):
            prefix = name[:n]
            if not any(o != name and o.startswith(prefix) for o in names):
                break
        out[name] = prefix.capitalize()
    return out


def interval_text(low, high, spec: str = ".0f") -> str:
    """An interval's two ends as ``low–high``, or ``n/a`` when an end is missing.

    A saving's interval has no end when draws leave no demand to save from (a calibration that
    failed its validation: internal gains larger than the losses), and results.json then holds
    null.

    Parameters
    ----------
    low, high : float or None
        The ends, any unit (formatted as given).
    spec : str
        Format specification of each end.
    """
    from thermocal.jsonsafe import json_number

    if json_number(low) is None or json_number(high) is None:
        return "n/a"
    return f"{format(low, spec)}–{format(high, spec)}"


def print_summary(results: dict, out: Path) -> None:
    """Rich tables of the key results (stdout): HLC, validation, annual demand, strategies.

    The calibration's flags go to the ``thermocal`` logger as warnings (stderr on the command
    line; ``-q`` silences them).
    """
    import logging

    from rich import box
    from rich.console import Console
    from rich.table import Table

    from thermocal.retrofit.config import NO_INTERVAL
    from thermocal.retrofit.tables import has_intervals
    from thermocal.textformat import format_number

    console = Console()
    hlc = results["heat_loss_coefficient_W_per_K"]
    dem = results["annual_heating_demand_kWh"]
    pct = f"{100 * results.get('uncertainty', {}).get('interval', 0.9):.0f} %"
    intervals = has_intervals(results)  # uncertainty.draws: 0 -> the estimates alone
    std = hlc["std"]
    line = f"HLC {hlc['value']:.0f} ± {'n/a' if std is None else format(std, '.0f')} W/K"
    if hlc.get("p05") is not None:
        line += f", {pct} interval {hlc['p05']:.0f} – {hlc['p95']:.0f} W/K"
    if "true" in hlc:
        line += f" (true {hlc['true']:.0f} W/K, {hlc['relative_error_pct']:+.1f} %)"
    console.print(f"[bold]{line}[/bold]")
    corr = results.get("calibration", {}).get("correction")
    if corr:
        console.print(corr["summary"])

    val = Table(title="Validation: multi-step simulation of the indoor temperature Ti")
    for col in ("period", "MAE [K]", "MAPE [%]", "MSE [K²]", "mean sim. [C]", "mean meas. [C]",
                "dev. [%]"):  # fmt: skip
        val.add_column(col, justify="left" if col == "period" else "right")
    for period, m in results["validation"].items():
        val.add_row(
            {"train": "training", "test": "test"}.get(period, period),
            f"{m['mae']:.2f}",
            f"{m['mape']:.2f}",
            f"{m['mse']:.2f}",
            f"{m['mean_simulated']:.2f}",
            f"{m['mean_measured']:.2f}",
            f"{m['mean_deviation_pct']:+.2f}" if "mean_deviation_pct" in m else "",
        )
    console.print(val)
    gate = results.get("validation_gate")
    if gate:
        style = "green" if gate["passed"] else "bold red"
        console.print(f"[{style}]{gate['summary']}[/{style}]")

    console.print(
        f"[bold]annual heating demand {dem['value']:,.0f} kWh[/bold]"
        + (f" ({pct} interval {dem['p05']:,.0f} – {dem['p95']:,.0f} kWh)" if intervals
           else f", {NO_INTERVAL}")
    )  # fmt: skip
    for name, value in dem.get("references", {}).items():
        if not isinstance(value, list):
            console.print(f"  reference, {name}: {value:,.0f} kWh")

    names = list(results.get("measures", {})) or list(
        dict.fromkeys(m for s in results["scenarios"] for m in s["measures"])
    )
    short = measure_abbreviations(names)
    title = "Retrofit strategies" + ("" if intervals else f", {NO_INTERVAL}")
    table = Table(title=title, box=box.SIMPLE_HEAD, padding=(0, 1))
    eco = results.get("economics", {})
    cur = eco.get("currency", "")
    cols = ["code", "measures", "kWh/a", "saving %"] + ([pct] if intervals else [])
    if eco:
        cols += [f"invest {cur}", f"{cur}/a", "payback a"]
    labels = ["+".join(short[m] for m in s["measures"]) or "none" for s in results["scenarios"]]
    for col in cols:
        table.add_column(
            col,
            justify="left" if col == "measures" else "right",
            no_wrap=col == "measures",
            min_width=max(map(len, labels)) if col == "measures" else None,
        )
    for s, label in zip(results["scenarios"], labels, strict=True):
        row = [
            s["code"],
            label,
            format_number(s["annual_kWh"], ",.0f"),
            format_number(s["saving_pct"], ".1f"),
        ]
        if intervals:
            row.append(interval_text(s["saving_pct_p05"], s["saving_pct_p95"]))
        if eco:
            e = s.get("economics", {})
            payback = e.get("payback_years")
            row += [
                f"{e.get('investment', 0):,.0f}",
                f"{e.get('cost_saving_per_year', 0):,.0f}",
                format_number(payback, ".0f", missing=""),
            ]
        table.add_row(*row)
    console.print(table)
    console.print("measures: " + ", ".join(f"{a} {m.replace('_', ' ')}" for m, a in short.items()))
    end_error = max((s.get("saving_pct_mcse") or 0.0 for s in results["scenarios"]), default=0.0)
    if end_error > 0:
        console.print(
            f"interval ends ±{end_error:.1f} pp (Monte Carlo error; more draws: uncertainty.draws)"
        )
    console.print(_track_record_line())
    if gate and not gate["passed"]:
        why = (
            "the model failed its validation"
            if gate.get("period")
            else "the model was not checked on a test period (periods.test_days)"
        )
        console.print(f"[bold red]no strategy recommended: {why}[/]")
    elif results.get("recommendation"):
        rule = results.get("recommendation_rule") or ""
        why = ""
        if "none pays back" in rule:
            code = results["recommendation"]
            row = next((s for s in results["scenarios"] if s["code"] == code), {})
            years = (row.get("economics") or {}).get("payback_years")
            why = (
                " (no strategy pays back within 30 years at today's energy price; this one "
                + (f"soonest, in about {years:.0f} years)" if years else "soonest)")
            )
        console.print(f"recommended strategy: [bold]{results['recommendation']}[/bold]{why}")
    log = logging.getLogger("thermocal.retrofit")
    for flag in results["calibration"]["flags"]:
        log.warning("calibration: %s", flag)
    for note in results.get("notes", []):
        if not note.startswith("measurements:"):  # those were logged while computing
            log.warning("%s", note)
    console.print(f"results in [bold]{out}[/bold] (results.json, report.html, CSV, figures/)")


def print_measurement_advice(advice: dict) -> None:
    """The expected savings' intervals after each heat-flux plate (``--advise``; stdout)."""
    from rich import box
    from rich.console import Console
    from rich.table import Table

    console = Console()
    if not advice["available"]:
        console.print(f"measurement advice: none ({advice['reason']})")
        return
    table = Table(
        title="Which measurement next: savings' interval half-widths \\[pp]",
        box=box.SIMPLE_HEAD,
        padding=(0, 1),
    )
    for col in ("heat-flux plate on", "U now", "median: now", "expected", "recommended"):
        table.add_column(col, justify="left" if col == "heat-flux plate on" else "right")
    for a in advice["components"]:
        rec = a["recommended_half_width_pp"]
        table.add_row(
            a["element"],
            f"{a['expected_u']:.3g}",
            f"{a['median_half_width_pp']:.1f}",
            f"{a['expected_median_half_width_pp']:.1f}",
            "" if rec is None else f"{rec:.1f} -> {a['expected_recommended_half_width_pp']:.1f}",
        )
    console.print(table)
    console.print(advice["summary"])


def _track_record_line() -> str:
    """One line on how far the savings were from EnergyPlus on the houses thermocal did not
    write (``thermocal.retrofit.track_record``; the report has the table)."""
    from thermocal.retrofit.track_record import INDEPENDENT_CHECKS

    checks = INDEPENDENT_CHECKS.values()
    means = sorted(c.savings_mean_abs_pp for c in checks)
    largest = max(c.savings_max_abs_pp for c in checks)
    return (
        f"independent EnergyPlus houses: savings off by {means[0]:.1f}-{means[-1]:.1f} pp on "
        f"average, max {largest:.1f} pp"
    )


def _check_site(cfg, opt_in: str | None = None) -> str | None:
    """Refuse, before computing, a weather file far from the building or not one whole year
    (:func:`thermocal.io.weather.check_full_year`: the annual demand of a half year would be
    a half year's); the measurements' clock against the sun is checked where the analysis
    reads them (:func:`thermocal.retrofit.data.clock_notes`). With ``weather.site: weather``
    a building far from its weather is not refused: the analysis runs at the weather file's
    site (:func:`thermocal.retrofit.workflow.building_at_weather_site`, which warns and notes
    it there); the note is returned. ``opt_in`` is how the configuration asks for that, named
    in the refusal (default: the retrofit configuration's key)."""
    from thermocal.io.weather import check_full_year, read_weather
    from thermocal.retrofit.workflow import (
        SITE_OPT_IN,
        building_at_weather_site,
        resolve_weather_path,
    )

    building, source = _rc_building(cfg)
    weather = resolve_weather_path(cfg.weather.file)
    year, meta = read_weather(weather, format=cfg.weather.format, columns=cfg.weather.columns)
    check_full_year(year, meta, source=str(cfg.weather.file))
    _, note = building_at_weather_site(
        building, cfg, building_source=source, weather_meta=meta, opt_in=opt_in or SITE_OPT_IN
    )
    return note


def _check_configured_gains(cfg) -> None:
    """Refuse, before computing, configured internal gains no home has per m2 of the building
    file's heated floor (:func:`thermocal.retrofit.gains.check_configured_gains`, the check of
    the fifth-order analysis and the verification), for ``--detailed-only``: the building
    file is read for it when the configuration names one beside constant or scheduled
    gains."""
    from thermocal.retrofit.gains import check_configured_gains

    if cfg.building is None or cfg.internal_gains.source not in ("constant", "schedule"):
        return
    building, _ = _rc_building(cfg)
    check_configured_gains(
        cfg.internal_gains, float(building.heated_floor_area), building.name
    )


def _rc_building(cfg):
    """The RC analysis's building file, read, and its name for messages."""
    from thermocal.retrofit.workflow import load_building

    building = load_building(
        cfg.building, config_source=f"the retrofit configuration in {cfg.base_dir}"
    )
    return building, str(cfg.building if isinstance(cfg.building, Path) else "the inline building")


def _check_detailed_pair(cfg, detailed: Path, setpoint: float | None) -> list[str]:
    """Refuse a ``--detailed`` building that is not the RC building file's, before computing
    (:func:`thermocal.retrofit.detailed.check_same_building`); the warnings it returns."""
    from thermocal.retrofit.detailed import check_same_building, heated_detailed_building

    envelope, source = _rc_building(cfg)
    with warnings.catch_warnings():  # the detailed run reads it again and shows its warnings
        warnings.simplefilter("ignore")
        building = heated_detailed_building(detailed, setpoint)
    return check_same_building(
        envelope, building, rc_source=source, detailed_source=str(detailed),
        heated_by_setpoint=setpoint is not None,
    )  # fmt: skip


#: Files of a retrofit output folder: an existing folder holding one of them is replaced.
RETROFIT_SIGNATURE = ("results.json", "report.html")


def print_detailed_summary(detailed: dict, rc: dict | None = None) -> None:
    """Strategy table of the detailed model (stdout), beside the RC model's when both exist."""
    from rich import box
    from rich.console import Console
    from rich.table import Table

    from thermocal.textformat import format_number

    console = Console()
    console.print(
        f"[bold]detailed model ({detailed['building']}): annual heating demand "
        f"{detailed['annual_heating_demand_kWh']:,.0f} kWh[/bold]"
    )
    scenarios = detailed["scenarios"]
    short = measure_abbreviations(list(dict.fromkeys(m for s in scenarios for m in s["measures"])))
    rc_by_code = {s["code"]: s for s in (rc or {}).get("scenarios", [])}
    cur = detailed["economics"]["currency"]
    table = Table(title="Retrofit strategies, detailed model", box=box.SIMPLE_HEAD, padding=(0, 1))
    cols = ["code", "measures", "kWh/a", "saving %"]
    if rc_by_code:
        cols += ["RC %"]
    cols += [f"invest {cur}", f"{cur}/a", "payback a"]
    labels = ["+".join(short[m] for m in s["measures"]) or "none" for s in scenarios]
    for col in cols:
        table.add_column(
            col,
            justify="left" if col == "measures" else "right",
            no_wrap=col == "measures",
            min_width=max(map(len, labels)) if col == "measures" else None,
        )
    for s, label in zip(scenarios, labels, strict=True):
        e = s["economics"]
        row = [s["code"], label, f"{s['annual_kWh']:,.0f}", f"{s['saving_pct']:.1f}"]
        if rc_by_code:
            other = rc_by_code.get(s["code"])
            row.append("" if other is None else f"{other['saving_pct']:.1f}")
        payback = e.get("payback_years")
        row += [
            f"{e['investment']:,.0f}",
            f"{e['cost_saving_per_year']:,.0f}",
            format_number(payback, ".0f", missing=""),
        ]
        table.add_row(*row)
    console.print(table)
    console.print("measures: " + ", ".join(f"{a} {m.replace('_', ' ')}" for m, a in short.items()))
    if detailed.get("recommendation"):
        console.print(
            f"detailed model, recommended strategy: [bold]{detailed['recommendation']}[/bold] "
            f"({detailed['recommendation_rule']})"
        )


def _add_detailed(folder: Path, detailed: dict, report: str) -> None:
    """Put the detailed model's results into the folder's results.json, its CSV and an HTML
    report named ``report``."""
    import json

    from thermocal.retrofit.detailed import write_detailed_outputs
    from thermocal.retrofit.detailed_report import write_detailed_report

    path = folder / "results.json"
    rc = json.loads(path.read_text()) if path.exists() else None
    results = dict(rc or {})
    results["detailed_model"] = detailed
    path.write_text(json.dumps(results, indent=1, default=str) + "\n")
    write_detailed_outputs(detailed, folder)
    write_detailed_report(detailed, folder / report, rc=rc)


@app.command()
def retrofit(
    config: Annotated[Path, typer.Argument(help="retrofit configuration (YAML)")],
    out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
        "retrofit-results"
    ),
    detailed: Annotated[
        Path | None,
        typer.Option(
            "--detailed",
            help="also simulate the strategies with this multi-zone building (thermocal "
            "building YAML, e.g. calibrated_building.yaml, or an EnergyPlus IDF)",
        ),
    ] = None,
    setpoint: Annotated[
        float | None,
        typer.Option(
            "--setpoint",
            help="with --detailed, for a building without set points (e.g. a "
            "calibrated_building.yaml): heat every zone at this temperature [C]",
        ),
    ] = None,
    detailed_only: Annotated[
        bool,
        typer.Option(
            "--detailed-only",
            help="only the detailed model (no measurements needed; the configuration gives "
            "weather, measures, strategies and economics)",
        ),
    ] = False,
    advise: Annotated[
        bool,
        typer.Option(
            "--advise",
            help="also say which in-situ U-value (a heat-flux plate) would narrow the savings' "
            "intervals most: the analysis rerun with each plate's expected readings (about "
            "10 runs, a minute on 2 cores)",
        ),
    ] = False,
) -> None:
    """Retrofit analysis: calibrate, validate, annual demand, retrofit strategies, report.

    Calibrates the fifth-order RC model on the training period, validates it on training and
    test periods, simulates the annual heating demand and the retrofit strategies (default:
    the 16 combinations of roof, walls, windows and cellar ceiling) with uncertainty intervals
    (default 90 %), computes final energy, cost, CO2 and payback, and writes results.json,
    CSV tables, figures and report.html. With --detailed the same strategies are also
    simulated with a detailed multi-zone model (results.json 'detailed_model',
    strategies_detailed.csv, report_detailed.html), side by side in the summary.
    """
    import logging

    from rich.console import Console

    from thermocal.errors import ThermocalInputError
    from thermocal.io.output import check_output_folder, output_folder
    from thermocal.retrofit import load_config, run_retrofit, write_outputs

    console = Console(stderr=True)
    if detailed_only and detailed is None:
        raise ThermocalInputError("--detailed-only needs --detailed BUILDING (YAML or IDF)")
    if setpoint is not None and detailed is None:
        raise ThermocalInputError(
            "--setpoint heats the zones of the detailed model: it needs --detailed BUILDING (the "
            "fifth-order analysis takes its indoor temperature from demand.indoor_profile)"
        )
    if detailed_only and advise:
        raise ThermocalInputError(
            "--advise reruns the fifth-order analysis of the measurements, which --detailed-only "
            "leaves out: drop one of the two"
        )
    check_output_folder(out, signature=RETROFIT_SIGNATURE, inputs=(config, detailed))
    if detailed_only:
        from thermocal.retrofit.detailed import (
            detailed_results,
            load_detailed_config,
            run_detailed_retrofit,
        )

        cfg = load_detailed_config(config)
        _check_configured_gains(cfg)
        with (
            output_folder(out, command="retrofit", signature=RETROFIT_SIGNATURE) as tmp,
            console.status("retrofit with the detailed model") as status,
        ):
            result = run_detailed_retrofit(cfg, detailed, setpoint=setpoint, progress=status.update)
            det = detailed_results(result, cfg)
            det["notes"] = cfg.economics_notes() + det["notes"]
            _add_detailed(tmp, det, "report.html")
        print_detailed_summary(det)
        for note in cfg.economics_notes():
            logging.getLogger("thermocal.retrofit").warning("%s", note)
        console.print(f"results in {out} (results.json, strategies_detailed.csv, report.html)")
        return
    cfg = load_config(config)
    if advise:  # before the analysis runs
        from thermocal.retrofit.advice import check_advice_draws

        check_advice_draws(cfg.uncertainty.draws, source=str(config))
    _check_site(cfg)
    pair_notes = [] if detailed is None else _check_detailed_pair(cfg, detailed, setpoint)
    with (
        output_folder(out, command="retrofit", signature=RETROFIT_SIGNATURE) as tmp,
        console.status("retrofit analysis") as status,
    ):
        analysis = run_retrofit(cfg, progress=lambda msg: status.update(msg))
        advice = None
        if advise:
            from thermocal.retrofit.advice import advise_measurements

            advice = advise_measurements(cfg, analysis, progress=status.update)
        status.update("writing results, figures and report")
        results = write_outputs(analysis, tmp, measurement_advice=advice)
        det = None
        if detailed is not None:
            from thermocal.retrofit.detailed import detailed_results, run_detailed_retrofit

            result = run_detailed_retrofit(cfg, detailed, setpoint=setpoint, progress=status.update)
            det = detailed_results(result, cfg)
            det["notes"] = pair_notes + cfg.economics_notes() + det["notes"]
            _add_detailed(tmp, det, "report_detailed.html")
    print_summary(results, out)
    if advice is not None:
        print_measurement_advice(advice)
    if det is not None:
        print_detailed_summary(det, results)
        for note in pair_notes:
            logging.getLogger("thermocal.retrofit").warning("%s", note)
