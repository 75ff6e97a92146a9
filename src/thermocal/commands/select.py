"""``thermocal select``: forward model selection by likelihood-ratio tests on a model family."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app

SELECT_HELP = (
    "Forward model selection (Bacher & Madsen 2011): fit the start model of a family, then all "
    "its extensions by one element (each warm-started from the current model's estimates), "
    "accept the best extension while its likelihood-ratio test rejects the current model.\n\n"
    "Data columns of the bacher-madsen family: Ta (ambient [C]), Ph (heating), Ps (solar "
    "irradiance, optional) and yTi (indoor [C]); map yours with --map, e.g. --map Ta=T_out "
    "--map Ph=heat_kW --map yTi=T_living. Writes OUT/selection.json, selection.md (the path "
    "table), and OUT/<model>/ (fit.json, parameters.csv, model.yaml) for every fitted model. "
    "Example: thermocal select inputPRBS1.csv --time-column t --time-unit h --out select"
)


def _hlc_cell(hlc) -> str:
    """Heat loss coefficient [W/K] with its interval (profile first), for the path table."""
    if not hlc:
        return ""
    if hlc.get("interval") == "profile":
        lo, hi = (
            "not found" if end is None else f"{end:.4g}{'(open)' if is_open else ''}"
            for end, is_open in ((hlc["lower"], hlc["open_lower"]),
                                 (hlc["upper"], hlc["open_upper"]))
        )  # fmt: skip
        return f"{hlc['value']:.4g} [{lo}, {hi}]"
    return f"{hlc['value']:.4g} +- {hlc['std_error']:.2g} (Wald)"


def selection_markdown(table, path: list[str], hlc: dict | None = None) -> str:
    """The path table as Markdown (the README's format), with convergence, the starts that
    reached the best value, why a candidate was not accepted, and the heat loss coefficient
    [W/K] with its 95 % profile-likelihood interval."""
    import pandas as pd

    hlc = hlc or {}
    lines = [
        "| iteration | model | parent | log-likelihood | free parameters | converged "
        "| starts at best | LR statistic | df | p-value | best of iteration | accepted "
        "| heat loss coefficient [W/K] | status |",
        "|---|---|---|---:|---:|---|---:|---:|---:|---:|---|---|---|---|",
    ]
    for _, row in table.iterrows():
        stat = "" if pd.isna(row["statistic"]) else f"{row['statistic']:.1f}"
        df = "" if pd.isna(row["df"]) else f"{int(row['df'])}"
        if pd.isna(row["pvalue"]):
            pval = ""
        else:
            pval = "< 1e-16" if row["pvalue"] < 1e-16 else f"{row['pvalue']:.2g}"
        starts = row.get("starts_at_best")
        starts = "" if starts is None or pd.isna(starts) else f"{int(starts)}"
        lines.append(
            f"| {row['iteration']} | {row['model']} | {row['parent']} | {row['loglike']:.1f} | "
            f"{row['n_free']} | {'yes' if row.get('converged', True) else '**no**'} | {starts} "
            f"| {stat} | {df} | {pval} | {'yes' if row['selected'] else ''} | "
            f"{'yes' if row['accepted'] else ''} | {_hlc_cell(hlc.get(row['model']))} | "
            f"{row.get('status', '') or ''} |"
        )
    lines += ["", f"Selected: {' -> '.join(path)}."]
    lines += [
        "",
        "Candidates are tested (likelihood-ratio test, Bacher & Madsen 2011) only when both "
        "fits converged (Newton criterion and two optimiser starts agreeing on the best value); "
        "a candidate with a capacity, resistance, conductance, aperture or fraction on a bound "
        "is not accepted. Heat loss coefficient: steady-state heat flow from the indoor state "
        "to the boundary temperatures per kelvin, with its 95 % profile-likelihood interval "
        "(Pawitan 2001).",
    ]
    return "\n".join(lines) + "\n"


def small_balance_note(h_balance: float, heat_unit: str) -> str | None:
    """A note on an energy balance below the range of buildings that the heating read a
    factor 1000 away brings inside (kW read as W: 0.17 W/K for 173 W/K).

    Not refused (:func:`thermocal.statespace.families.family_scale` refuses only the upward
    slip): the balance leaves out the gains and errs low in a test cell or a mostly
    free-floating period.

    Parameters
    ----------
    h_balance : float [W/K]
        The energy-balance heat loss coefficient (NaN: none).
    heat_unit : str
        The declared unit of ``Ph``.

    Returns
    -------
    str or None
    """
    from thermocal.statespace.units import PLAUSIBLE_HEAT_LOSS_W_PER_K, heat_unit_slip

    lo, hi = PLAUSIBLE_HEAT_LOSS_W_PER_K
    slip = heat_unit_slip(h_balance, heat_unit)
    if slip is None or not h_balance < lo:
        return None
    alt, alt_h = slip
    return (
        f"the energy balance of the data gives {h_balance:.3g} W/K with 'Ph' in {heat_unit} "
        f"(--heat-unit {heat_unit}), below any building ({lo:g} to {hi:g} W/K); read in {alt} "
        f"it would be {alt_h:.4g} W/K: is Ph in {alt}? use --heat-unit {alt}. Not refused: "
        "the balance leaves out the gains, so a test cell or a mostly free-floating period can "
        "give so little; the heat loss coefficients below then follow the unit given"
    )


def _name_data_columns(message: str, renames: dict, data_file) -> str:
    """A model-column name in an error message followed by the data column and file."""
    import re

    back = {m: d for d, m in renames.items()}
    for model_col, data_col in back.items():
        message = re.sub(
            rf"'{re.escape(model_col)}'(?! \(data column)",
            f"'{model_col}' (data column '{data_col}' of {data_file})",
            message,
        )
    return message


@app.command(help=SELECT_HELP)
def select(
    data_file: Annotated[Path, typer.Argument(help="CSV, Excel or Parquet file.")],
    out: Annotated[Path, typer.Option("--out", "-o", help="Output directory.")] = Path(
        "select_output"
    ),
    family: Annotated[
        str, typer.Option("--family", help="Candidate family: bacher-madsen.")
    ] = "bacher-madsen",
    mapping: Annotated[
        list[str] | None,
        typer.Option("--map", help="Model column = data column, e.g. --map Ph=heat_kW."),
    ] = None,
    heat_unit: Annotated[str, typer.Option("--heat-unit", help="Unit of Ph: W, kW, MW.")] = "kW",
    solar_unit: Annotated[
        str, typer.Option("--solar-unit", help="Unit of Ps: W/m2, kW/m2.")
    ] = "kW/m2",
    time_column: Annotated[
        str | None,
        typer.Option("--time-column", help="Time column (default: 'time' or the first)."),
    ] = None,
    time_unit: Annotated[
        str, typer.Option("--time-unit", help="Unit of numeric times: s, min, h, d.")
    ] = "s",
    time_format: Annotated[
        str | None, typer.Option("--time-format", help="strftime format of the time stamps.")
    ] = None,
    sep: Annotated[str | None, typer.Option("--sep", help="CSV separator.")] = None,
    decimal: Annotated[str, typer.Option("--decimal", help="Decimal mark: . or ,")] = ".",
    sheet: Annotated[str | None, typer.Option("--sheet", help="Excel sheet name.")] = None,
    alpha: Annotated[
        float, typer.Option("--alpha", help="Level of the likelihood-ratio tests.")
    ] = 0.05,
    n_starts: Annotated[
        int | None,
        typer.Option("--n-starts", min=1, help="Optimiser starts per model (plus a warm start)."),
    ] = None,
    seed: Annotated[int | None, typer.Option("--seed", help="Seed of the random starts.")] = None,
    hold: Annotated[str, typer.Option("--hold", help="Input hold: zoh or foh.")] = "zoh",
    max_gap: Annotated[
        int,
        typer.Option(
            "--max-gap",
            min=0,
            help="Input gaps of at most this many samples are interpolated (as thermocal fit).",
        ),
    ] = 3,
    gaps: Annotated[
        str,
        typer.Option(
            "--gaps", help="Longer input gaps: 'stop' or 'split' into periods (as thermocal fit)."
        ),
    ] = "stop",
    time_stamps: Annotated[
        str,
        typer.Option(
            "--time-stamps",
            help="'start' (default) or 'end' of each interval (inputs shifted one sample).",
        ),
    ] = "start",
    bound_factor: Annotated[
        float,
        typer.Option(
            "--bound-factor",
            help="Widen the family's bounds of capacities, resistances and the aperture by "
            "this factor on both sides (default 1: bounds made for the FlexHouse data).",
        ),
    ] = 1.0,
    bounds: Annotated[
        str,
        typer.Option(
            "--bounds",
            help="'auto' (default): the family's start values and bounds scaled to the "
            "building (capacities and aperture times, resistances divided by the power of ten "
            "nearest the data's energy-balance heat loss coefficient over the FlexHouse's "
            "~170 W/K); 'family': as published (made for the FlexHouse data).",
        ),
    ] = "auto",
    hlc_profile: Annotated[
        bool,
        typer.Option(
            "--hlc-profile/--no-hlc-profile",
            help="Profile-likelihood interval of the heat loss coefficient of the models on "
            "the selection path (a few constrained refits each; the others get the Wald "
            "interval); --no-hlc-profile: Wald intervals only.",
        ),
    ] = True,
) -> None:
    """Forward model selection (see :data:`SELECT_HELP`)."""
    import json

    import pandas as pd
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    from thermocal import __version__
    from thermocal.commands.fit import (
        check_numbers,
        check_time_axis,
        fitted_model_yaml,
        heat_loss_text,
        parse_mapping,
        read_table,
        resolve_time_column,
        shift_end_stamped,
    )
    from thermocal.errors import ThermocalInputError
    from thermocal.io.digest import file_sha256
    from thermocal.io.output import output_folder
    from thermocal.statespace.families import FAMILIES, family_scale
    from thermocal.statespace.results import heat_loss_coefficients, single_start_flag
    from thermocal.statespace.selection import forward_selection

    if family not in FAMILIES:
        raise ThermocalInputError(f"--family {family!r}: use one of {', '.join(FAMILIES)}")
    if hold not in ("zoh", "foh"):
        raise ThermocalInputError(f"--hold {hold!r}: use zoh or foh")
    if not 0 < alpha < 0.5:
        raise ThermocalInputError(f"--alpha {alpha}: give a level in (0, 0.5), e.g. 0.05")
    console = Console()
    data = read_table(data_file, sep=sep, decimal=decimal, sheet=sheet)
    notes = list(data.attrs.get("notes", []))
    renames = parse_mapping(mapping)
    absent = [c for c in renames if c not in data.columns]
    if absent:
        raise ThermocalInputError(
            f"{data_file}: --map names data column(s) {', '.join(map(repr, absent))}, not in "
            f"the data; columns present: {', '.join(map(str, data.columns))}"
        )
    if renames:
        data = data.rename(columns=renames)
        notes.append("columns mapped: " + ", ".join(f"{d} -> {m}" for d, m in renames.items()))
    needed = ["Ta", "Ph", "yTi"]
    missing = [c for c in needed if c not in data.columns]
    if missing:
        raise ThermocalInputError(
            f"{data_file}: the {family} family needs column(s) {', '.join(missing)} (Ta "
            "ambient [C], Ph heating, yTi indoor [C]; Ps solar optional); map yours with "
            f"--map, e.g. --map {missing[0]}=<your column>; columns present: "
            f"{', '.join(map(str, data.columns))}"
        )
    solar = "Ps" in data.columns
    if not solar:
        notes.append("no solar column Ps: the family is fitted without solar gains")
    time_column = resolve_time_column(data, time_column, time_format, data_file)
    check_time_axis(data, time_column, time_unit, data_file)
    if gaps not in ("stop", "split"):
        raise ThermocalInputError(f"--gaps {gaps!r}: use stop or split")
    try:
        check_numbers(data, ["Ta", "Ph", "yTi", *(["Ps"] if solar else [])], data_file, decimal)
    except ThermocalInputError as exc:
        raise ThermocalInputError(_name_data_columns(str(exc), renames, data_file)) from None
    as_stamped = data
    data = shift_end_stamped(data, ["Ta", "Ph", *(["Ps"] if solar else [])], time_stamps, notes)
    if bounds not in ("auto", "family"):
        raise ThermocalInputError(f"--bounds {bounds!r}: use auto or family")
    scale = 1.0
    if bounds == "auto":
        try:
            scale, h_balance = family_scale(data, heat_unit, source=str(data_file))
        except ThermocalInputError as exc:
            raise ThermocalInputError(_name_data_columns(str(exc), renames, data_file)) from None
        low = small_balance_note(h_balance, heat_unit)
        if low:
            notes.insert(0, low)
        if scale != 1.0:
            notes.append(
                f"family scaled to the data (--bounds auto): energy-balance heat loss "
                f"coefficient {h_balance:.4g} W/K, so capacities and the aperture x{scale:g}, "
                f"resistances /{scale:g} (start values and bounds); --bounds family: as "
                "published"
            )
    models, extensions, start = FAMILIES[family](
        heat_unit=heat_unit, solar_unit=solar_unit if solar else None, bound_factor=bound_factor,
        scale=scale,
    )  # fmt: skip

    with output_folder(out, command="select", signature=("selection.json",)) as tmp:

        def progress(name, res):
            console.print(
                f"{name:<12} log-likelihood {res.loglike:10.2f}  free {res.n_free:2d}  "
                f"{res.fit_seconds:6.1f} s"
            )

        try:
            result = forward_selection(
                models, extensions, data, start=start, alpha=alpha, n_starts=n_starts,
                seed=seed, hold=hold, time_column=time_column, time_unit=time_unit,
                callback=progress,
                input_gaps="split" if gaps == "split" else "interpolate" if max_gap else "error",
                max_gap=max_gap if gaps == "split" else max(max_gap, 1),
            )  # fmt: skip
        except ThermocalInputError as exc:
            raise ThermocalInputError(_name_data_columns(str(exc), renames, data_file)) from None
        table = result.table
        stamps = None
        if gaps != "split":
            from thermocal.statespace.checks import time_stamp_check

            # the start model refitted with the inputs as stamped and moved one sample
            stamps = time_stamp_check(
                result.fits[start], as_stamped, stamps=time_stamps, time_column=time_column,
                time_unit=time_unit,
                input_gaps="interpolate" if max_gap else "error", max_gap=max(max_gap, 1),
            )  # fmt: skip
            if stamps["message"]:
                notes.insert(0, stamps["message"])
            if stamps["note"]:
                notes.append(stamps["note"])
        single = single_start_flag(result.fits[start])
        if single:
            notes.insert(0, f"{start}: {single}")
        if hlc_profile:
            console.print(
                f"heat loss coefficient: profile likelihood of {', '.join(result.path)}..."
            )
        hlcs = heat_loss_coefficients(result.fits, profile=result.path if hlc_profile else ())
        for name, res in result.fits.items():
            folder = tmp / name
            folder.mkdir()
            content_fit = res.to_dict()
            if name in hlcs:
                content_fit["heat_loss_coefficient"] = hlcs[name]
            (folder / "fit.json").write_text(json.dumps(content_fit, indent=2))
            res.parameter_table().to_csv(folder / "parameters.csv")
            (folder / "model.yaml").write_text(fitted_model_yaml(res))
        records = [
            {k: (None if isinstance(v, float) and v != v else v) for k, v in row.items()}
            for row in json.loads(table.to_json(orient="records"))
        ]
        content = {
            "family": family,
            "path": result.path,
            "selected": result.selected,
            "heat_loss_coefficient": hlcs,
            "time_stamp_check": stamps,
            "alpha": alpha,
            "table": records,
            "data_notes": notes,
            "provenance": {
                "thermocal_version": __version__,
                "seed": seed,
                "n_starts": n_starts,
                "bounds": bounds,
                "family_scale": scale,
                "bound_factor": bound_factor,
                "files": {str(data_file): {"sha256": file_sha256(data_file)}},
            },
        }
        (tmp / "selection.json").write_text(json.dumps(content, indent=2))
        table.to_csv(tmp / "selection.csv", index=False)
        (tmp / "selection.md").write_text(selection_markdown(table, result.path, hlcs))

    # what fits 80 columns (13 columns cut every name to 'Ti…'; the whole table is in
    # selection.md): a model's step, its result, and the HLC of the accepted ones
    view = Table(title=f"Forward selection ({family}, alpha {alpha:g})", padding=(0, 1))
    for col, justify in (("it", "right"), ("model", "left"), ("parent", "left"),
                         ("loglik", "right"), ("k", "right"), ("LR", "right"),
                         ("p", "right"), ("step", "left"), ("HLC [W/K]", "left")):  # fmt: skip
        view.add_column(col, justify=justify, no_wrap=col in ("model", "parent"))
    statuses = []
    for _, row in table.iterrows():
        # the start model, the best candidate of a step accepted or rejected by its test
        step = (
            "start" if row["iteration"] == 0
            else "accepted" if row["accepted"]
            else "rejected" if row["selected"]
            else ""
        )  # fmt: skip
        if not row["converged"]:
            step = (step + " NOT CONVERGED").strip()
        if row["status"]:
            statuses.append(f"{row['model']}: {row['status']}")
        pvalue = (
            "" if pd.isna(row["pvalue"])
            else "<1e-16" if row["pvalue"] < 1e-16 else f"{row['pvalue']:.2g}"
        )  # fmt: skip
        lr = "" if pd.isna(row["statistic"]) else f"{row['statistic']:.1f}"
        if lr and not pd.isna(row["df"]):
            lr += f" ({int(row['df'])})"
        view.add_row(
            str(row["iteration"]), row["model"], row["parent"], f"{row['loglike']:.1f}",
            str(row["n_free"]), lr, pvalue, step,
            _hlc_cell(hlcs.get(row["model"])) if step in ("start", "accepted") else "",
        )  # fmt: skip
    console.print(view)
    console.print(
        "LR: likelihood-ratio statistic against the parent (degrees of freedom); k: free "
        "parameters; rejected: a step's best candidate its test does not accept"
    )
    for status in statuses:
        console.print(f"status: {escape(status)}")
    for note in notes:
        console.print(f"note: {escape(note)}")
    console.print(f"selected: {' -> '.join(result.path)}")
    if result.selected in hlcs:
        console.print(f"{result.selected}: {escape(heat_loss_text(hlcs[result.selected]))}")
    for name, res in result.fits.items():
        if not res.converged:
            console.print(f"[yellow]{name}: not converged[/yellow] ({escape(res.flags[0])})")
    for flag in result.fits[result.selected].flags:  # escaped: "[nan, nan]" is no markup
        console.print(f"[yellow]flag ({result.selected}):[/yellow] {escape(flag)}")
    console.print(
        f"wrote {out / 'selection.json'}, {out / 'selection.md'} and one folder per model"
    )
    if result.selected in hlcs:
        # the period dependence is not checked here (two more multi-start fits of the
        # selected model); `fit` compares the halves of the data by default
        console.print(
            "period dependence of the heat loss coefficient (not checked here): thermocal fit "
            f"{out / result.selected / 'model.yaml'} {data_file} with the same time and --map "
            "options compares the two halves of the data (or periods given by --hlc-split)"
        )
