"""``thermocal fit``: maximum-likelihood estimation of a grey-box RC model from a CSV file."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app


def read_table(path: Path, *, sep: str | None = None):
    """Read a CSV (separator detected among ``, ; tab`` unless given) or Parquet table."""
    import pandas as pd

    from thermocal.errors import ThermocalInputError

    if not path.exists():
        raise ThermocalInputError(f"data file {path} does not exist")
    if path.suffix.lower() in (".parquet", ".pq"):
        try:
            return pd.read_parquet(path)
        except (OSError, ValueError) as exc:  # pyarrow's ArrowInvalid is a ValueError
            raise ThermocalInputError(
                f"data file {path} could not be read as Parquet: {exc}"
            ) from None
    if sep is None:
        with path.open(encoding="utf-8", errors="replace") as fh:
            header = fh.readline()
        counts = {s: header.count(s) for s in (";", ",", "\t")}
        sep = max(counts, key=counts.get) if max(counts.values()) > 0 else ","
    try:
        return pd.read_csv(path, sep=sep)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ThermocalInputError(f"data file {path} could not be read as CSV: {exc}") from None


FIT_HELP = (
    "Fit a grey-box RC model by maximum likelihood (Kalman filter).\n\n"
    "Writes OUT/fit.json (log-likelihood, AIC, BIC, estimates with standard errors, correlation "
    "matrix, flags, residual diagnostics) and PNG figures (measured vs one-step prediction, "
    "residual autocorrelation, cumulated periodogram), and prints a summary. "
    "Example: thermocal fit examples/models/TiTe.yaml inputPRBS1.csv --time-column t "
    "--time-unit h --out fit_TiTe"
)


@app.command(help=FIT_HELP)
def fit(
    model_file: Annotated[Path, typer.Argument(help="YAML model file (see docs/model-file.md).")],
    data_file: Annotated[Path, typer.Argument(help="CSV or Parquet file, inputs and outputs.")],
    out: Annotated[Path, typer.Option("--out", "-o", help="Output directory.")] = Path(
        "fit_output"
    ),
    time_column: Annotated[
        str | None,
        typer.Option(
            "--time-column",
            help="Column with the time (date-times, or numbers in --time-unit). "
            "Default: 'time' if present, else the first column.",
        ),
    ] = None,
    time_unit: Annotated[
        str, typer.Option("--time-unit", help="Unit of numeric times: s, min, h, d.")
    ] = "s",
    sep: Annotated[
        str | None, typer.Option("--sep", help="CSV separator (default: detected).")
    ] = None,
    hold: Annotated[
        str, typer.Option("--hold", help="Input hold between samples: zoh or foh.")
    ] = "zoh",
    n_starts: Annotated[
        int, typer.Option("--n-starts", help="Optimiser starts (1 = the declared values only).")
    ] = 1,
    seed: Annotated[int | None, typer.Option("--seed", help="Seed of the random starts.")] = None,
    figures: Annotated[
        bool, typer.Option("--figures/--no-figures", help="Write PNG figures.")
    ] = True,
) -> None:
    """Fit a grey-box RC model (see :data:`FIT_HELP`)."""
    import json

    from rich.console import Console
    from rich.table import Table

    from thermocal.errors import ThermocalInputError
    from thermocal.statespace import RCModel
    from thermocal.statespace.diagnostics import (
        autocorrelation,
        cumulated_periodogram,
        fraction_outside_band,
    )

    console = Console()
    model = RCModel.from_yaml(model_file)
    data = read_table(data_file, sep=sep)
    if time_column is None:
        time_column = "time" if "time" in data.columns else str(data.columns[0])
    if time_column not in data.columns:
        raise ThermocalInputError(
            f"{data_file}: no time column '{time_column}'; columns: "
            f"{', '.join(map(str, data.columns))}; use --time-column"
        )
    with console.status(f"fitting {model.name} ({model.n_free} free parameters)..."):
        results = model.fit(
            data,
            hold=hold,
            n_starts=n_starts,
            seed=seed,
            time_column=time_column,
            time_unit=time_unit,
            source=str(data_file),
        )
    out.mkdir(parents=True, exist_ok=True)
    content = results.to_dict()
    diagnostics = {}
    residuals = results.residuals
    for col in model.output_names:
        acf = autocorrelation(residuals[col].to_numpy(), nlags=40)
        cp = cumulated_periodogram(residuals[col].to_numpy())
        outside = (acf["acf"].abs() > acf["bound"]).iloc[1:]
        diagnostics[col] = {
            "residual_std": float(residuals[col].std()),
            "acf_lags_outside_95_bound": int(outside.sum()),
            "acf_lags_tested": int(len(outside)),
            "cumulated_periodogram_fraction_outside_95_band": fraction_outside_band(cp),
        }
    content["diagnostics"] = diagnostics
    content["model_file"] = str(model_file)
    content["data_file"] = str(data_file)
    (out / "fit.json").write_text(json.dumps(content, indent=2))
    written = [out / "fit.json"]
    if figures:
        from thermocal.statespace.plots import plot_fit

        written += plot_fit(results, out)

    head = Table(title=f"{model.name}: maximum-likelihood fit", show_header=False)
    head.add_row("log-likelihood", f"{results.loglike:.4f}")
    head.add_row("AIC / BIC", f"{results.aic:.2f} / {results.bic:.2f}")
    head.add_row("observations / free parameters", f"{results.nobs} / {results.n_free}")
    head.add_row("converged", f"{results.converged} ({results.message})")
    head.add_row("time", f"{results.fit_seconds:.3f} s")
    console.print(head)
    table = Table(title="Parameters")
    for col, justify in [("parameter", "left"), ("value", "right"), ("std error", "right"),
                         ("unit", "left"), ("lower", "right"), ("upper", "right"),
                         ("fixed", "center")]:  # fmt: skip
        table.add_column(col, justify=justify)
    for name, row in results.parameter_table().iterrows():
        se = row["std_error"]
        table.add_row(
            name,
            f"{row['value']:.6g}",
            "" if se != se else f"{se:.3g}",
            row["unit"],
            f"{row['lower']:.4g}",
            f"{row['upper']:.4g}",
            "yes" if row["fixed"] else "",
        )
    console.print(table)
    for flag in results.flags:
        console.print(f"[yellow]flag:[/yellow] {flag}")
    for col, d in diagnostics.items():
        console.print(
            f"residuals {col}: std {d['residual_std']:.4f} K, "
            f"{d['acf_lags_outside_95_bound']}/{d['acf_lags_tested']} ACF lags outside the 95 % "
            f"bound, cumulated periodogram "
            f"{100 * d['cumulated_periodogram_fraction_outside_95_band']:.0f} % outside its band"
        )
    console.print("wrote " + ", ".join(str(p) for p in written))
