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


def selection_markdown(table, path: list[str]) -> str:
    """The path table as Markdown (the README's format)."""
    import pandas as pd

    lines = [
        "| iteration | model | parent | log-likelihood | free parameters | LR statistic | df "
        "| p-value | best of iteration | accepted |",
        "|---|---|---|---:|---:|---:|---:|---:|---|---|",
    ]
    for _, row in table.iterrows():
        stat = "" if pd.isna(row["statistic"]) else f"{row['statistic']:.1f}"
        df = "" if pd.isna(row["df"]) else f"{int(row['df'])}"
        if pd.isna(row["pvalue"]):
            pval = ""
        else:
            pval = "< 1e-16" if row["pvalue"] < 1e-16 else f"{row['pvalue']:.2g}"
        lines.append(
            f"| {row['iteration']} | {row['model']} | {row['parent']} | {row['loglike']:.1f} | "
            f"{row['n_free']} | {stat} | {df} | {pval} | {'yes' if row['selected'] else ''} | "
            f"{'yes' if row['accepted'] else ''} |"
        )
    lines += ["", f"Selected: {' -> '.join(path)}."]
    return "\n".join(lines) + "\n"


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
) -> None:
    """Forward model selection (see :data:`SELECT_HELP`)."""
    import json

    import pandas as pd
    import yaml
    from rich.console import Console
    from rich.table import Table

    from thermocal import __version__
    from thermocal.commands.fit import (
        check_numbers,
        check_time_axis,
        file_sha256,
        parse_mapping,
        read_table,
        resolve_time_column,
    )
    from thermocal.errors import ThermocalInputError
    from thermocal.io.output import output_folder
    from thermocal.statespace.diagnostics import forward_selection
    from thermocal.statespace.families import FAMILIES

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
    models, extensions, start = FAMILIES[family](
        heat_unit=heat_unit, solar_unit=solar_unit if solar else None
    )
    time_column = resolve_time_column(data, time_column, time_format, data_file)
    check_time_axis(data, time_column, time_unit, data_file)
    check_numbers(data, ["Ta", "Ph", "yTi", *(["Ps"] if solar else [])], data_file, decimal)

    with output_folder(out, command="select", signature=("selection.json",)) as tmp:

        def progress(name, res):
            console.print(
                f"{name:<12} log-likelihood {res.loglike:10.2f}  free {res.n_free:2d}  "
                f"{res.fit_seconds:6.1f} s"
            )

        result = forward_selection(
            models, extensions, data, start=start, alpha=alpha, n_starts=n_starts, seed=seed,
            hold=hold, time_column=time_column, time_unit=time_unit, callback=progress,
        )  # fmt: skip
        table = result.table
        for name, res in result.fits.items():
            folder = tmp / name
            folder.mkdir()
            (folder / "fit.json").write_text(json.dumps(res.to_dict(), indent=2))
            res.parameter_table().to_csv(folder / "parameters.csv")
            (folder / "model.yaml").write_text(yaml.safe_dump(res.model.to_dict(), sort_keys=False))
        records = [
            {k: (None if isinstance(v, float) and v != v else v) for k, v in row.items()}
            for row in json.loads(table.to_json(orient="records"))
        ]
        content = {
            "family": family,
            "path": result.path,
            "selected": result.selected,
            "alpha": alpha,
            "table": records,
            "data_notes": notes,
            "provenance": {
                "thermocal_version": __version__,
                "seed": seed,
                "n_starts": n_starts,
                "files": {str(data_file): {"sha256": file_sha256(data_file)}},
            },
        }
        (tmp / "selection.json").write_text(json.dumps(content, indent=2))
        table.to_csv(tmp / "selection.csv", index=False)
        (tmp / "selection.md").write_text(selection_markdown(table, result.path))

    view = Table(title=f"Forward selection ({family}, alpha {alpha:g})")
    for col in ("iteration", "model", "parent", "log-likelihood", "free", "LR statistic", "df",
                "p-value", "best", "accepted"):  # fmt: skip
        view.add_column(col)
    for _, row in table.iterrows():
        view.add_row(
            str(row["iteration"]), row["model"], row["parent"], f"{row['loglike']:.1f}",
            str(row["n_free"]), "" if pd.isna(row["statistic"]) else f"{row['statistic']:.1f}",
            "" if pd.isna(row["df"]) else str(int(row["df"])),
            "" if pd.isna(row["pvalue"]) else f"{row['pvalue']:.2g}",
            "yes" if row["selected"] else "", "yes" if row["accepted"] else "",
        )  # fmt: skip
    console.print(view)
    for note in notes:
        console.print(f"note: {note}")
    console.print(f"selected: {' -> '.join(result.path)}")
    for flag in result.fits[result.selected].flags:
        console.print(f"[yellow]flag ({result.selected}):[/yellow] {flag}")
    console.print(
        f"wrote {out / 'selection.json'}, {out / 'selection.md'} and one folder per model"
    )
