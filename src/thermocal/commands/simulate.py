"""``thermocal simulate``: run the detailed multi-zone model over a weather period."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app

#: Most repetitions of the first day before a run.
MAX_WARMUP_DAYS = 366


def _add_import_report(path: Path, info) -> None:
    """Add the IDF import's full report (classes not represented and notes, by kind) to
    summary.json as ``idf_import``."""
    import json

    summary = json.loads(path.read_text())
    summary["idf_import"] = info.report()
    path.write_text(json.dumps(summary, indent=2))


def _run_period_weather(run_period, frame, metadata, building: Path, weather: Path):
    """The weather and the run's ``[start, end)`` (days, ``YYYY-MM-DD``) of an IDF's RunPeriod,
    with the note on it.

    The period is dated as EnergyPlus dates it
    (:func:`thermocal.multizone.idf.site.run_period_dates`); one that crosses new year past a
    typical-year weather file (TMY, or any file put on the RunPeriod's ``Begin Year``) has the
    file repeated over the next year (:func:`thermocal.io.weather.weather_for_period`), as
    EnergyPlus reads it cyclically.

    Parameters
    ----------
    run_period : thermocal.multizone.idf.site.RunPeriod
    frame, metadata
        From :func:`thermocal.io.weather.read_weather` (in the begin year when given).
    building, weather : Path
        The files, for messages.

    Returns
    -------
    frame, metadata, start, end, note

    Raises
    ------
    ThermocalInputError
        A RunPeriod that is no period (:func:`run_period_dates`), or one the weather does not
        cover: a truncated file, or an actual-year file of one year and a period that crosses
        new year.
    """
    import warnings

    import pandas as pd

    from thermocal.errors import ThermocalInputError
    from thermocal.io.weather import weather_for_period
    from thermocal.multizone.idf.site import run_period_dates

    first = frame.index[0]
    begin, last, notes = run_period_dates(run_period, first.year)
    for note in notes:  # a period other than the file's words: said on the console too
        warnings.warn(note, stacklevel=1)
    start, end = pd.Timestamp(begin), pd.Timestamp(last) + pd.Timedelta(days=1)
    span = f"{begin} to {last}"
    crosses = last.year > begin.year
    weather_end = frame.index[-1] + (frame.index[1] - frame.index[0])
    typical = metadata.get("coerced_year") is not None
    if crosses and typical and end.tz_localize(first.tz) > weather_end:
        frame, metadata = weather_for_period(frame, metadata, start, end, source=str(weather))
        weather_end = frame.index[-1] + (frame.index[1] - frame.index[0])
        notes.append(
            f"the period crosses new year: the typical-year weather repeats in {last.year}, "
            f"where the schedules' weekdays and holidays follow {begin.year}'s calendar (by "
            "month and day)"
        )
    if end.tz_localize(first.tz) > weather_end:
        what = (
            f"crosses new year (its end month/day before its begin's: {span}), but the "
            f"weather file {weather} is an actual-year file ending at {weather_end}: use a "
            "weather file that covers both years or a typical-year file (which repeats), "
            if crosses and not typical
            else f"runs to {run_period.end_month}/{run_period.end_day} ({last}), but the "
            f"weather file {weather} ends at {weather_end} (its last row starts at "
            f"{frame.index[-1]}): a truncated weather file? Use a complete file, "
        )
        # EnergyPlus stops with an error when the weather ends inside the RunPeriod
        raise ThermocalInputError(
            f"{building}: the RunPeriod '{run_period.name}' {what}or give --start and --end "
            "inside the weather"
        )
    note = (
        f"period from the IDF RunPeriod '{run_period.name}' ({run_period.begin_month}/"
        f"{run_period.begin_day} to {run_period.end_month}/{run_period.end_day}: {span}); "
        f"weather labelled {first.year}"
        + (
            ""
            if run_period.begin_year
            else " (the file gives no begin year: the weather's own calendar)"
        )
        + "".join(f"; {n}" for n in notes)
    )
    return frame, metadata, str(start.date()), str(end.date()), note


def _period_year(start: str | None, end: str | None, run_period) -> int | None:
    """The year a typical-year weather file is put on for ``--start`` / ``--end``.

    Until 2026-11-30 a typical year read with ``--start`` took the latest year whose calendar
    fits the file: an IDF's RunPeriod in 2009 ran in 2009 by default, but ``--start
    2009-06-01`` was refused as outside the weather (2023).

    Parameters
    ----------
    start, end : str or None
        The options as given (``end`` exclusive).
    run_period : RunPeriod or None
        The IDF's, for its begin year.

    Returns
    -------
    int or None
        None: the weather module's own choice.
    """
    import pandas as pd

    for text, back in ((start, False), (end, True)):
        if text:
            try:
                stamp = pd.Timestamp(text)
            except (ValueError, TypeError):
                return None  # the period's own check names it
            return int((stamp - pd.Timedelta("1s")).year if back else stamp.year)
    return getattr(run_period, "begin_year", None) or None


@app.command()
def simulate(
    building: Annotated[
        Path, typer.Argument(help="Building file: thermocal YAML or EnergyPlus IDF.")
    ],
    weather: Annotated[Path, typer.Argument(help="Weather file (EPW, TMY3).")],
    start: Annotated[
        str | None,
        typer.Option(help="First instant, e.g. 2023-01-01 (default: start of the weather)."),
    ] = None,
    end: Annotated[
        str | None,
        typer.Option(help="End instant, exclusive, e.g. 2023-02-01 (default: end of weather)."),
    ] = None,
    step: Annotated[
        str | None,
        typer.Option(
            help="Time step, e.g. 5min, 15min, 1h (default: the IDF's Timestep, otherwise 5min)."
        ),
    ] = None,
    out: Annotated[Path, typer.Option(help="Output directory.")] = Path("simulation"),
    free_float: Annotated[
        bool, typer.Option("--free-float", help="Ignore the zones' heating/cooling set points.")
    ] = False,
    output_format: Annotated[str, typer.Option("--format", help="csv or parquet.")] = "csv",
    outputs: Annotated[
        str | None,
        typer.Option(
            help="Quantities to write, comma-separated (default: all): air_temperature, "
            "operative_temperature, heating, cooling, heat_input, transmitted_solar, "
            "infiltration."
        ),
    ] = None,
    warmup_days: Annotated[
        int, typer.Option(help="Repetitions of the first day before the run.")
    ] = 7,
    report: Annotated[
        str | None,
        typer.Option(
            help="Rows of the output files: every step (default), or means over each hourly, "
            "daily or monthly interval or a duration such as 1h (EnergyPlus' reporting "
            "frequency; temperatures stamped at the interval's end, heat flows at its start)."
        ),
    ] = None,
) -> None:
    """Simulate BUILDING under WEATHER; write zone temperatures, heat flows and summary.json.

    Outputs in OUT: zone_temperatures.csv or .parquet (air and operative temperature in C per
    zone at the end of each step, rows stamped with that instant), zone_heat_flows.csv or
    .parquet (heating, cooling, given heat, transmitted solar, infiltration in W per zone, mean
    over each step, rows labelled by step start; --outputs keeps only the quantities named)
    and summary.json (per zone min/max/mean air temperature per step and hourly-integrated,
    heating and cooling energy in kWh, peak hourly loads in kW, and every approximation made).
    """
    import warnings

    from rich.console import Console
    from rich.table import Table

    from thermocal.errors import ThermocalInputError
    from thermocal.io.output import check_output_folder, output_folder
    from thermocal.io.weather import fill_short_gaps, read_weather
    from thermocal.multizone.files import load_building
    from thermocal.multizone.simulation import Simulation

    if not 0 <= warmup_days <= MAX_WARMUP_DAYS:
        raise ThermocalInputError(
            f"--warmup-days {warmup_days}: give 0 to {MAX_WARMUP_DAYS} days (a week or two "
            "brings the walls to their periodic state)"
        )
    from thermocal.textformat import unitless_duration

    if step is not None and unitless_duration(step):
        raise ThermocalInputError(
            f"--step {step!r} has no unit: write it with one, e.g. {step}min or {step}h"
        )
    if output_format not in ("csv", "parquet"):
        raise ThermocalInputError(f"--format must be csv or parquet, got {output_format!r}")
    from thermocal.multizone.simulation import output_quantities

    try:
        quantities = output_quantities(outputs)
    except ThermocalInputError as error:
        raise ThermocalInputError(f"--outputs: {error}") from None
    if report is not None and unitless_duration(report):
        raise ThermocalInputError(
            f"--report {report!r} has no unit: write it with one, e.g. {report}h, or hourly"
        )
    signature = ("summary.json", f"zone_temperatures.{output_format}")
    check_output_folder(out, signature=signature)
    console = Console(stderr=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = load_building(building)
        run_period = getattr(getattr(model, "idf_info", None), "run_period", None)
        period_note = None
        if run_period is not None and start is None and end is None:
            # the IDF's RunPeriod, in its begin year when it gives one (EnergyPlus' calendar)
            frame, metadata = read_weather(weather, coerce_year=run_period.begin_year)
            frame, metadata, start, end, period_note = _run_period_weather(
                run_period, frame, metadata, building, weather
            )
        else:
            # a typical year is put on the year the period asks for (--start's, else --end's),
            # else the RunPeriod's begin year; an actual-year file keeps its own
            frame, metadata = read_weather(weather)
            year = _period_year(start, end, run_period)
            if metadata.get("coerced_year") is not None and year not in (
                None, metadata["coerced_year"]
            ):  # a typical year (an actual-year file keeps its own years)
                frame, metadata = read_weather(weather, coerce_year=year)
        from thermocal.io.weather import check_building_site, check_weather_clock

        site_note = None

        # irradiance hours away from the sun (UTC labels, a shifted export) heats rooms by the
        # sun at night or sunrise: refused, as identify and calibrate do
        check_weather_clock(frame, metadata, source=str(weather))
        try:
            check_building_site(
                model, metadata, building_source=str(building), weather_source=str(weather)
            )
        except ThermocalInputError as exc:  # a forward run elsewhere is legitimate: said
            site_note = (
                f"{str(exc).split(' (at most')[0]}: simulated at the weather file's site and "
                "climate (as EnergyPlus does, with a warning); identify and calibrate refuse "
                "such a pair unless told to use the weather's site (--site weather, "
                "identification.site: weather), retrofit refuses it"
            )
            warnings.warn(site_note, stacklevel=1)
        per_hour = getattr(getattr(model, "idf_info", None), "timesteps_per_hour", None)
        step_note = None
        if step is None:
            step = f"{60 // per_hour}min" if per_hour else "5min"
            if per_hour:
                step_note = f"time step {step} from the IDF's Timestep ({per_hour} per hour)"
        frame, filled = fill_short_gaps(frame)
        for note in filled:
            warnings.warn(f"weather file {weather}: {note}", stacklevel=1)
        for column, what in (
            ("ghi_infrared", "the sky temperature falls back to the dew-point model"),
            ("temp_dew", "the sky temperature falls back to air - 11 K"),
        ):
            if column in frame and frame[column].isna().any():
                n = int(frame[column].isna().sum())
                first = frame.index[int(frame[column].isna().to_numpy().argmax())]
                warnings.warn(
                    f"weather file {weather}: {column!r} is missing in {n} row(s) in gaps "
                    f"longer than 3 rows (first at {first}); where the simulated period "
                    f"includes them, {what} for the whole run",
                    stacklevel=1,
                )
        sim = Simulation(
            model,
            frame,
            metadata,
            step=step,
            start=start,
            end=end,
            warmup_days=warmup_days,
            store_surfaces=False,
        )
    from thermocal.multizone.results import report_rule

    try:  # before the run, not after it
        report_rule(report, sim.step_size)
    except ThermocalInputError as error:
        raise ThermocalInputError(f"--report: {error}") from None
    for warning in caught:
        console.print(f"[yellow]warning:[/yellow] {warning.message}")
    console.print(
        f"{model.name}: {len(model.zones)} zones, {sim.network.n_nodes} nodes, "
        f"{len(sim.times)} steps of {step} from {sim.times[0]}"
    )
    with output_folder(out, command="simulate", signature=signature) as tmp:
        result = sim.run(free_float=free_float, progress=True)
        for note in (step_note, period_note, site_note):
            if note:
                result.approximations.insert(0, note)
        written = [
            out / Path(p).name
            for p in result.to_files(
                tmp, format=output_format, quantities=quantities, report=report
            )
        ]
        info = getattr(model, "idf_info", None)
        if info is not None:
            _add_import_report(Path(tmp) / "summary.json", info)
    # the summary as written (computing it again costs 0.06 s of the grid's 3.6-s process)
    summary = json.loads((out / "summary.json").read_text())
    table = Table(
        title="summary (first 20 zones; air temperature hourly-integrated, as ASHRAE 140)"
    )
    for column in (
        "zone",
        "T min C",
        "T mean C",
        "T max C",
        "heat kWh",
        "cool kWh",
        "peak heat kW",
    ):
        table.add_column(column, justify="right" if column != "zone" else "left")
    for zone, values in list(summary["zones"].items())[:20]:
        table.add_row(
            zone,
            f"{values['air_temperature_hourly_min_C']:.1f}",
            f"{values['air_temperature_hourly_mean_C']:.1f}",
            f"{values['air_temperature_hourly_max_C']:.1f}",
            f"{values['heating_kWh']:.0f}",
            f"{values['cooling_kWh']:.0f}",
            f"{values['heating_peak_kW']:.2f}",
        )
    Console().print(table)
    totals = summary["building"]
    console.print(
        f"building: heating {totals['heating_kWh']:.0f} kWh (peak {totals['heating_peak_kW']:.2f} "
        f"kW), cooling {totals['cooling_kWh']:.0f} kWh (peak {totals['cooling_peak_kW']:.2f} kW)"
    )
    multipliers = totals.get("zone_multipliers") or {}
    if multipliers:
        listed = ", ".join(f"{z} x{m:g}" for z, m in list(multipliers.items())[:5])
        more = ", ..." if len(multipliers) > 5 else ""
        console.print(
            f"  (zone multipliers counted in the building's totals: {listed}{more}; the zones' "
            "own rows are one zone's, as EnergyPlus reports them)"
        )
    for path in written:
        console.print(f"wrote {path}")
