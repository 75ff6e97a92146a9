"""``thermocal identify``: the heat each zone of a detailed model needs to follow the sensors."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app

#: The sensor-log reader's remedies name its Python options; this command's are options.
_READER_REMEDIES = (
    ("pass tz= (", "pass --tz ("),
    ("or pass tz=", "or pass --tz"),
    ("pass the time zone (--tz Europe/Zurich)", "pass --tz (e.g. Europe/Zurich)"),
    ("pass a fixed offset, e.g. tz=1.0", "pass --tz with an offset, e.g. 1.0"),
    ("(--time-unit on the command line, time_unit= in Python)", "(--time-unit)"),
    ("(--time-origin, start=; ", "(--time-origin; "),
    (": sort it, or pass sort=True", ": sort it by time"),
    (", or pass duplicates='first' or 'last'", ""),
    ("(a decimal comma: pass decimal=',')", "(a decimal comma: pass --decimal ,)"),
    ("; pass interval=", "; log more than one row per sensor"),
    ("pass time_format=", "pass --time-format"),
    ("rows = ", "--rows "),
)

#: What a row of the sensor log is (``--rows``): a reading at its time, or the mean over the
#: logging interval labelled by the interval's start or end.
ROWS = ("reports", "interval_start", "interval_end")


@app.command()
def identify(
    building: Annotated[
        Path | None, typer.Argument(help="Building file: thermocal YAML or EnergyPlus IDF.")
    ] = None,
    weather: Annotated[Path | None, typer.Argument(help="Weather file (EPW, TMY3).")] = None,
    sensors: Annotated[
        Path | None,
        typer.Argument(help="Sensor log (CSV or parquet, long or wide layout) [C]."),
    ] = None,
    mapping: Annotated[
        Path | None, typer.Option(help="Mapping file: sensors -> zones (YAML).")
    ] = None,
    out: Annotated[Path, typer.Option(help="Output directory.")] = Path("identification"),
    method: Annotated[
        str, typer.Option(help="inverse (exact), pid (the paper's loop) or both.")
    ] = "both",
    feedback: Annotated[
        str | None,
        typer.Option(
            help="Sensor model, the tracked model temperature: air, operative or the air weight "
            "0..1 of a mix (default: the mapping's identified_heat.sensor, else air)."
        ),
    ] = None,
    radiant_fraction: Annotated[
        str | None,
        typer.Option(
            help="Share 0..1 of the identified heat put on the zone's surfaces as radiant "
            "internal gains, or 'declared': step by step from the IDF's own People, Lights and "
            "equipment objects, which the identified heat then stands for (default: the "
            "mapping's, else 0.6; the paper's: 0)."
        ),
    ] = None,
    unsensed: Annotated[
        str | None,
        typer.Option(
            help="Zones without a sensor: float (simulated, Q_ID = 0) or neighbour (an "
            "adjacent zone's data, the paper's rule); default: the mapping's, else float."
        ),
    ] = None,
    start: Annotated[str | None, typer.Option(help="First instant, e.g. 2001-01-01.")] = None,
    end: Annotated[str | None, typer.Option(help="End instant (exclusive).")] = None,
    step: Annotated[str, typer.Option(help="Model and controller step.")] = "5min",
    tuning_zone: Annotated[
        str | None,
        typer.Option(help="Zone of the Ziegler-Nichols tuning (default: median volume)."),
    ] = None,
    max_gap: Annotated[
        str,
        typer.Option(
            help="Zone data gaps up to this long are interpolated; a longer one takes another "
            "zone's data (named on the console when more than 10 % of the period)."
        ),
    ] = "1h",
    silence: Annotated[
        str,
        typer.Option(
            help="A sensor silent longer than this has a gap. A sensor that reports less "
            "often (at most every --max-gap) is judged on its own interval: a silence up to "
            "1.5 times it is no gap."
        ),
    ] = "15min",
    occupancy: Annotated[
        Path | None,
        typer.Option(help="YAML file with an 'occupancy' section (default: the paper's schedule)."),
    ] = None,
    limits: Annotated[
        str | None,
        typer.Option(help="PID output limits per zone in W, 'LOW,HIGH' (default: unlimited)."),
    ] = None,
    tz: Annotated[
        str | None, typer.Option(help="Time zone of sensor time stamps without UTC offset.")
    ] = None,
    time_unit: Annotated[
        str | None,
        typer.Option(help="Unit of numeric sensor time stamps: s, ms, min, h or d (Unix: s)."),
    ] = None,
    time_origin: Annotated[
        str | None,
        typer.Option(help="Time of 0 of numeric time stamps (default 1970-01-01 UTC)."),
    ] = None,
    decimal: Annotated[
        str,
        typer.Option(
            help="Decimal mark of the sensor log's numbers: . or , (a European export, "
            "usually ;-separated: --decimal ,)."
        ),
    ] = ".",
    time_format: Annotated[
        str | None,
        typer.Option(
            help="strftime format of the sensor log's time stamps when they are not ISO 8601, "
            "e.g. '%d.%m.%Y %H:%M' (day-first or month-first dates and 12-hour AM/PM clocks "
            "are recognised without it)."
        ),
    ] = None,
    rows: Annotated[
        str,
        typer.Option(
            help="What a row of the sensor log is: reports (a reading at its time), "
            "interval_start or interval_end (the mean over the logging interval, labelled by "
            "its start or its end, as many loggers and BMS exports write)."
        ),
    ] = "reports",
    clock_check: Annotated[
        bool,
        typer.Option(
            "--clock-check/--no-clock-check",
            help="Check the sensor log's clock against the model's: the exact inverse with the "
            "log shifted by an hour either way; a warning when a shift makes the unoccupied "
            "heat much smoother (a log an hour off). Two to four more inverses.",
        ),
    ] = True,
    sensor_accuracy: Annotated[
        float,
        typer.Option(
            "--sensor-accuracy",
            help="Standard uncertainty of each temperature sensor's offset [K] (default 0.2: "
            "the common +-0.2 K logger class); stated as the identified heat's uncertainty "
            "per zone and for the building.",
        ),
    ] = 0.2,
    site_choice: Annotated[
        str,
        typer.Option(
            "--site",
            help="Whose site when the building's location is more than 300 km from the weather "
            "file's: building (refused, the default: another city's weather) or weather (the "
            "weather file's site replaces the building's, as EnergyPlus does for a weather-file "
            "run; said in a warning and in the outputs' notes)."
        ),
    ] = "building",
    demo: Annotated[
        bool, typer.Option("--demo", help="Run on the built-in clinic demo data.")
    ] = False,
) -> None:
    """Identify, for every zone and step, the heat the model needs to follow the sensors.

    Writes into OUT: identification.json (gains with Ku and Pu, tracking per zone,
    every zone's reference source, the unoccupied-variance metric, PID vs inverse, the
    sensor log's clock check, the identified heat's uncertainty from the sensors' accuracy),
    q_id.parquet (per zone and total, per step), figures and report.html.
    """
    import warnings

    from rich.console import Console

    from thermocal.errors import ThermocalInputError
    from thermocal.identification.occupancy import OccupancySchedule
    from thermocal.identification.sensors import check_period_length
    from thermocal.identification.workflow import check_pid_only_options, gap_duration
    from thermocal.identification.workflow import identify as run_identification
    from thermocal.io.output import check_output_folder, output_folder

    check_pid_only_options(
        method, {"--tuning-zone": tuning_zone, "--limits": limits}, method_option="--method"
    )
    from thermocal.textformat import unitless_duration

    if step is not None and unitless_duration(step):
        raise ThermocalInputError(f"--step {step!r} has no unit: write it with one, e.g. {step}min")
    if not 0.0 < sensor_accuracy <= 5.0:
        raise ThermocalInputError(
            f"--sensor-accuracy {sensor_accuracy:g}: give a sensor's standard uncertainty in "
            "kelvin, more than 0 and at most 5 (e.g. 0.2)"
        )
    gap_duration(max_gap, "--max-gap", zero_allowed=True)
    gap_duration(silence, "--silence", zero_allowed=False)
    signature = ("identification.json", "q_id.parquet", "report.html")
    check_output_folder(out, signature=signature)
    console = Console(stderr=True)
    truth = None
    site_note = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if demo:
            from thermocal.demos.identification import load_demo

            model, frame, metadata, raw, mapping_data, truth = load_demo()
            start = start or str(metadata["period"][0])
            end = end or str(metadata["period"][1])
            site = metadata["weather"]
            log_name = str(metadata["files"]["sensors.parquet"])
            max_gap_used = max_gap
            silence = metadata.get("max_gap", silence)
        else:
            missing = [
                name
                for name, value in (
                    ("BUILDING", building),
                    ("WEATHER", weather),
                    ("SENSORS", sensors),
                    ("--mapping", mapping),
                )
                if value is None
            ]
            if missing:
                raise ThermocalInputError(
                    f"identify needs {', '.join(missing)} (or --demo for the built-in data)"
                )
            from thermocal.identification.sensors import load_mapping
            from thermocal.io.measurements import read_measurements
            from thermocal.io.weather import (
                building_site_or_weather,
                check_weather_clock,
                read_weather,
            )
            from thermocal.multizone.files import load_building

            _check_log_options(decimal, rows)
            model = load_building(building)
            frame, site = read_weather(weather)
            site_note = building_site_or_weather(
                model,
                site,
                site_choice,
                building_source=str(building),
                weather_source=str(weather),
                option="--site",
                opt_in="--site weather",
            )
            if site_note:  # at once: also when a later check stops the run
                console.print(f"[yellow]warning:[/yellow] {site_note}")
            check_weather_clock(frame, site, source=str(weather))
            try:
                raw, meta = read_measurements(
                    sensors,
                    tz=tz,
                    time_unit=time_unit,
                    start=time_origin,
                    decimal=decimal,
                    time_format=time_format,
                    rows=rows,
                )
            except ThermocalInputError as exc:  # the reader's remedies in this command's terms
                text = str(exc)
                for option, remedy in _READER_REMEDIES:
                    text = text.replace(option, remedy)
                raise ThermocalInputError(text) from None
            unused_tz = _check_time_options(
                raw, meta, str(sensors), tz=tz, time_unit=time_unit, time_origin=time_origin
            )
            if unused_tz:
                warnings.warn(unused_tz, stacklevel=1)
            frame, site = _weather_for_measurements(frame, site, raw, start, end, str(weather))
            if site.get("weather_year", {}).get("kind") == "typical":
                console.print(f"weather: {site['weather_year']['statement']}")
            mapping_data = load_mapping(mapping)
            log_name = str(sensors)
            max_gap_used = max_gap
            if start is None and end is None:
                start, end = _log_period(raw, frame.index, step, console, log_name)
        schedule = None
        if occupancy is not None:
            from thermocal.io.yamlfile import read_yaml

            data = read_yaml(occupancy, what="occupancy file")
            section = isinstance(data, dict) and "occupancy" in data
            schedule = OccupancySchedule.from_dict(
                data["occupancy"] if section else data,
                source=f"{occupancy}: occupancy" if section else str(occupancy),
            )
        pid_limits = _parse_limits(limits)
        check_period_length(start, end, frame.index)
        mapping_data = _with_unsensed(mapping_data, unsensed)
        feedback_value = _parse_feedback(feedback)
        radiant_fraction = _parse_radiant_fraction(radiant_fraction)
        console.print(
            f"{model.name}: {len(model.zones)} zones; method {method}"
            + (f", feedback {feedback}" if feedback else "")
            + (f", radiant fraction {radiant_fraction}" if radiant_fraction is not None else "")
        )
        result = run_identification(
            model,
            frame,
            site,
            raw,
            mapping_data,
            start=start,
            end=end,
            step=step,
            method=method,
            feedback=feedback_value,
            radiant_fraction=radiant_fraction,
            tuning_zone=tuning_zone,
            limits=pid_limits,
            schedule=schedule,
            max_gap=max_gap_used,
            silence=silence,
            progress=True,
            log_name=log_name,
            clock_check=clock_check,
            sensor_accuracy=sensor_accuracy,
            log_tz=None if demo else tz,
        )
    from thermocal.multizone.simulation import notes_summary

    import_warnings = 0
    for warning in caught:
        if warning.category.__name__ == "IdfImportWarning":
            import_warnings += 1  # the full text is in the report and identification.json
            continue
        console.print(f"[yellow]warning:[/yellow] {warning.message}")
    summary = notes_summary(result.import_notes)
    if summary or import_warnings:
        console.print(
            f"[yellow]import:[/yellow] {summary or 'see the notes'} "
            "(full list in identification.json and report.html)"
        )
    for note in energyplus_check_notes(result.import_notes):
        console.print(f"[yellow]import:[/yellow] {note}")
    if site_note:  # in identification.json and the report, not only on the console
        result.notes.insert(0, site_note)
    with output_folder(out, command="identify", signature=signature) as tmp:
        written = [out / Path(p).name for p in result.to_files(tmp)]
    _print_summary(result, truth)
    for path in written:
        console.print(f"wrote {path}")


def energyplus_check_notes(notes) -> list[str]:
    """The import notes on inputs EnergyPlus itself ignores, warns about or refuses (an IDF's
    ``EnergyPlus check:`` notes), which ``identify`` prints in full as ``simulate`` does: they
    say where the file does not mean what it seems to.

    Parameters
    ----------
    notes : sequence of str
        The import's notes (``IdentificationResult.import_notes``).
    """
    from thermocal.multizone.idf.report import EP_CHECK

    return [str(n) for n in notes if str(n).startswith(EP_CHECK)]


def _check_time_options(
    raw, meta: dict, source: str, *, tz, time_unit, time_origin
) -> str | None:
    """Refuse time options the sensor log's time column does not use; ``--tz`` unused is a
    warning.

    ``--time-unit`` and ``--time-origin`` read numeric time stamps; with date-times they would
    be silently ignored. ``--tz`` places stamps written without UTC offset; stamps with
    offsets are instants already, so it has no effect on the identification.

    Parameters
    ----------
    raw : DataFrame
        The log as read (:func:`thermocal.io.measurements.read_measurements`).
    meta : dict
        Its metadata; ``meta["notes"]`` says whether the times were numbers or were placed in
        ``tz`` (:data:`thermocal.io._time.NUMERIC_TIMES_NOTE`, ``LOCAL_TIMES_NOTE``).
    source : str
        The log file, for messages.
    tz, time_unit, time_origin : str or None
        The options as given (None: not given).

    Returns
    -------
    str or None
        The warning when ``--tz`` has no effect, else None.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        ``--time-unit`` or ``--time-origin`` with a log of date-times, naming its first time.
    """
    import pandas as pd

    from thermocal.errors import ThermocalInputError
    from thermocal.identification.sensors import log_span
    from thermocal.io._time import LOCAL_TIMES_NOTE, NUMERIC_TIMES_NOTE

    notes = [str(note) for note in meta.get("notes", ())]
    numeric = any(NUMERIC_TIMES_NOTE in note for note in notes)
    given = [
        f"{option} {value}"
        for option, value in (("--time-unit", time_unit), ("--time-origin", time_origin))
        if value is not None
    ]
    if given and not numeric:
        one = len(given) == 1
        raise ThermocalInputError(
            f"{' and '.join(given)}: the time stamps of {source} are date-times, not numbers "
            f"(the first: {log_span(raw)[0]}); "
            f"{'this option reads' if one else 'these options read'} numeric time stamps only: "
            f"drop {'it' if one else 'them'}"
        )
    if tz is None or any(LOCAL_TIMES_NOTE in note for note in notes):
        return None
    if numeric and time_origin is not None and pd.Timestamp(time_origin).tzinfo is None:
        return None  # the origin written without offset was placed in --tz
    what = "are numbers from an origin with a UTC offset" if numeric else "carry UTC offsets"
    return (
        f"the time stamps of {source} {what}, which fix their instants: "
        f"--tz {tz} has no effect (it places time stamps written without offset); the "
        "identification uses the file's times"
    )


def _check_log_options(decimal: str, rows: str) -> None:
    """Refuse a ``--decimal`` or ``--rows`` the sensor-log reader has no meaning for."""
    from thermocal.errors import ThermocalInputError

    if decimal not in (".", ","):
        raise ThermocalInputError(f"--decimal {decimal!r}: use . or ,")
    if rows not in ROWS:
        raise ThermocalInputError(f"--rows {rows!r}: use {', '.join(ROWS)}")


def _weather_for_measurements(frame, site, raw, start, end, source: str):
    """A typical-year weather file on the year(s) of the sensor log (or of --start/--end); an
    actual-year file must cover --start/--end (:func:`thermocal.io.weather.weather_for_period`)."""
    from thermocal.identification.sensors import log_span
    from thermocal.io.weather import weather_for_period

    if site.get("coerced_year") is None and (start is None or end is None):
        return frame, site  # an actual year: the log's span is checked against it later
    first, last = log_span(raw)
    return weather_for_period(
        frame,
        site,
        first if start is None else start,
        last if end is None else end,
        source=source,
    )


def _log_period(raw, weather_index, step: str, console, log_name: str):
    """Default period: the sensor log's span on the model grid (not the whole weather year).

    Returns ``(start, end)`` tz-aware, or ``(None, None)`` when the log does not lie inside
    the weather data (the overlap check then names both ranges).
    """
    import pandas as pd

    from thermocal.errors import ThermocalInputError
    from thermocal.identification.sensors import log_span_on_grid
    from thermocal.textformat import unitless_duration

    if unitless_duration(step):
        raise ThermocalInputError(
            f"--step {step!r} has no unit: write it with one, e.g. {step}min"
        )
    try:
        delta = pd.Timedelta(step)
    except ValueError:
        raise ThermocalInputError(f"--step {step!r}: give a duration such as 5min") from None
    if delta <= pd.Timedelta(0):
        raise ThermocalInputError(f"--step {step!r} must be positive")
    t0, t1 = log_span_on_grid(raw, weather_index, delta)
    if t0 is None:
        return None, None
    console.print(
        f"period: the span of {log_name}, [{t0}, {t1}) (pass --start/--end to choose another)"
    )
    return t0, t1


def _parse_radiant_fraction(text: str | None):
    """``--radiant-fraction``: None, "declared" or a number in [0, 1]."""
    from thermocal.errors import ThermocalInputError

    if text is None or text.strip().lower() == "declared":
        return None if text is None else "declared"
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0.0 <= value <= 1.0:
        raise ThermocalInputError(
            f"--radiant-fraction {text!r}: give a number in [0, 1] (the share of the identified "
            "heat on the zone's surfaces) or declared (the IDF's own load objects, step by step)"
        )
    return value


def _parse_feedback(text: str | None):
    """``--feedback``: None, "air", "operative" or an air weight as a number."""
    if text is None or text in ("air", "operative"):
        return text
    try:
        return float(text)
    except ValueError:
        from thermocal.errors import ThermocalInputError

        raise ThermocalInputError(
            f"--feedback {text!r}: give air, operative or the air weight of the sensed "
            "temperature, a number in [0, 1]"
        ) from None


def _with_unsensed(mapping, unsensed: str | None):
    """The mapping (file content or SensorMapping) with ``--unsensed`` applied."""
    if unsensed is None:
        return mapping
    from dataclasses import replace

    from thermocal.identification.sensors import SensorMapping, _treatment, mapping_from_dict

    _treatment(unsensed, "--unsensed")
    if not isinstance(mapping, SensorMapping):
        mapping = mapping_from_dict(mapping)
    return replace(mapping, unsensed=unsensed)


def _parse_limits(text: str | None) -> tuple[float, float] | None:
    """``"LOW,HIGH"`` [W] -> (low, high); None stays None."""
    from thermocal.errors import ThermocalInputError

    if text is None:
        return None
    try:
        low, high = (float(part) for part in text.split(","))
    except ValueError:
        raise ThermocalInputError(
            f"--limits {text!r}: give two numbers in W, 'LOW,HIGH', e.g. '-5000,20000'"
        ) from None
    if not low < high:
        raise ThermocalInputError(f"--limits {text!r}: LOW must be below HIGH")
    return low, high


def _clock_summary(log_clock: dict | None) -> str:
    """The summary's line of the sensor log's clock check
    (:func:`thermocal.identification.workflow.check_identified_log_clock`; None: switched off):
    the unoccupied standard deviations [kW] as written and shifted, or why it was not made."""
    if log_clock is None:
        return "not checked (--no-clock-check)"
    if log_clock["passed"] is None:  # not made: the reason
        return f"not checked: {log_clock['reason']}"
    std = {float(hours): value / 1000 for hours, value in log_clock["std"].items()}
    shifted = ", ".join(f"{h:+g} h {v:.3f}" for h, v in sorted(std.items()) if h != 0.0)
    if log_clock["passed"]:
        return f"as written {std[0.0]:.3f} kW ({shifted})"
    best = log_clock["best"]
    if (log_clock.get("halves") or {}).get("disagree"):
        which = "second" if log_clock["halves"]["shifted"][1] else "first"
        better = f"{best:+g} h better in the {which} half only (a clock jump?)"
    elif log_clock.get("at_limit"):
        better = f"{best:+g} h or more better (the search's limit)"
    else:
        better = f"{best:+g} h better"
    return f"{better}, see the warning: {std[best]:.3f} vs {std[0.0]:.3f} kW"


def _print_summary(result, truth) -> None:
    import numpy as np
    from rich.console import Console
    from rich.table import Table

    console = Console()
    summary = Table(title="heat-balance identification", show_header=False)
    summary.add_column("quantity")
    summary.add_column("value", justify="right")
    std = np.sqrt(result.unoccupied_variance())
    summary.add_row("metric source", result.metric_source)
    summary.add_row("unoccupied std of building Q_ID", f"{std / 1000:.3f} kW")
    if result.tuning is not None:
        t = result.tuning
        summary.add_row("tuned zone", t.zone)
        summary.add_row(
            "Ku exact / experiment",
            f"{t.ultimate_gain:.0f} / {(t.experiment_gain or float('nan')):.0f} W/K",
        )
        summary.add_row("Pu", f"{t.ultimate_period / 60:.1f} min")
    difference = result.method_difference()
    if difference is not None:
        summary.add_row("PID - inverse, building RMS", f"{difference['building_rms_W']:.0f} W")
    summary.add_row("sensor log's clock", _clock_summary(result.log_clock))
    if result.sensor_uncertainty is not None:
        u = result.sensor_uncertainty
        shared, ind = u["shared"], u["independent"]
        share = shared["building_share"]
        summary.add_row(
            f"building heat +- (sensors {u['accuracy_K']:g} K)",
            f"{shared['building_kwh']:,.0f} kWh"
            + (f" ({100 * share:.1f} %)" if share is not None else "")
            + f" alike, {ind['building_kwh']:,.0f} kWh each own",
        )
    for key, value in result.timings.items():
        summary.add_row(f"time: {key}", f"{value:.2f} s")
    counts = result.sources["source"].value_counts().to_dict()
    summary.add_row("zone references", ", ".join(f"{n} {k}" for k, n in counts.items()))
    if result.form is not None:
        tracked = result.form[result.form["treatment"] == "tracked"]
        fractions = sorted(set(tracked["radiant_fraction"].round(3)))
        shown = (
            ", ".join(f"{f:g}" for f in fractions)
            if len(fractions) <= 4
            else f"{fractions[0]:g}..{fractions[-1]:g} (period means per zone)"
        )
        summary.add_row(
            "identified heat form", f"radiant fraction {shown}; sensor {result.feedback}"
        )
    console.print(summary)
    for note in result.notes:
        console.print(f"[yellow]note:[/yellow] {note}")
    worst = result.worst_tracked(5)
    table = Table(title="worst-tracked zones")
    for column in ("zone", "RMSE K", "max |e| K", "bias K"):
        table.add_column(column, justify="left" if column == "zone" else "right")
    for zone, row in worst.iterrows():
        table.add_row(
            str(zone),
            f"{row['rmse_K']:.3f}",
            f"{row['max_abs_error_K']:.2f}",
            f"{row['bias_K']:+.3f}",
        )
    console.print(table)
