"""``thermocal fit``: maximum-likelihood estimation of a grey-box RC model from a CSV file."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from thermocal.cli import app
from thermocal.io.digest import file_sha256


def read_table(path: Path, *, sep: str | None = None, decimal: str = ".", sheet: str | None = None):
    """Read a CSV (separator detected among ``, ; tab`` unless given), Excel or Parquet table.

    A row right under the header without a single number while the next row has numbers is a
    unit row (``[C]; [kW]; ...``) and is dropped (noted in ``table.attrs["notes"]``).
    ``decimal=","`` reads decimal commas (the separator is then detected among ``; tab``).
    """
    import pandas as pd

    from thermocal.errors import ThermocalInputError

    if not path.exists():
        raise ThermocalInputError(f"data file {path} does not exist")
    if path.is_dir():
        raise ThermocalInputError(f"data file {path} is a folder, not a file")
    if decimal not in (".", ","):
        raise ThermocalInputError(f"--decimal {decimal!r}: use '.' or ','")
    if sep is not None and len(sep) != 1:
        raise ThermocalInputError(
            f"--sep {sep!r}: give one character, e.g. --sep ';' or --sep ',' (or leave it out: "
            "the separator is detected)"
        )
    suffix = path.suffix.lower()
    notes: list[str] = []
    if suffix in (".parquet", ".pq"):
        try:
            return pd.read_parquet(path)
        except (OSError, ValueError) as exc:  # pyarrow's ArrowInvalid is a ValueError
            raise ThermocalInputError(
                f"data file {path} could not be read as Parquet: {exc}"
            ) from None
    if suffix in (".xlsx", ".xlsm", ".xls", ".ods"):
        try:
            table = pd.read_excel(path, sheet_name=sheet or 0)
        except ImportError as exc:
            raise ThermocalInputError(
                f"data file {path}: reading Excel needs an extra package ({exc}); install "
                "openpyxl, or save the sheet as CSV"
            ) from None
        except (OSError, ValueError) as exc:
            raise ThermocalInputError(f"data file {path} could not be read: {exc}") from None
    else:
        with path.open("rb") as fh:
            head = fh.read(65536)
        if not head.strip():
            raise ThermocalInputError(
                f"data file {path} could not be read: it is empty; give a CSV with a header row"
            )
        if b"\x00" in head:
            raise ThermocalInputError(
                f"data file {path}: a binary file, not a CSV text file; export the data as CSV "
                "(UTF-8), Excel or Parquet"
            )
        try:
            head.decode("utf-8")
        except UnicodeDecodeError as exc:
            if exc.start < len(head) - 4:  # not merely a character cut at the block end
                raise ThermocalInputError(
                    f"data file {path}: not UTF-8 text (byte {exc.start}); save the CSV as UTF-8"
                ) from None
        if sep is None:
            with path.open(encoding="utf-8", errors="replace") as fh:
                header = fh.readline()
            candidates = (";", "\t") if decimal == "," else (";", ",", "\t")
            counts = {s: header.count(s) for s in candidates}
            sep = max(counts, key=counts.get) if max(counts.values()) > 0 else ","
        table = _read_csv(path, sep, decimal)
        _check_header(path, sep)
        table = _drop_empty_columns(table, notes)
    if table.empty:
        raise ThermocalInputError(
            f"data file {path} has a header but no data rows; give at least two rows of data"
        )
    table = _drop_unit_row(table, notes, decimal)
    table.attrs["notes"] = notes
    return table


def _read_csv(path: Path, sep: str, decimal: str):
    import pandas as pd

    from thermocal.errors import ThermocalInputError

    try:
        return pd.read_csv(path, sep=sep, decimal=decimal)
    except UnicodeDecodeError as exc:
        raise ThermocalInputError(
            f"data file {path}: not UTF-8 text (byte {exc.start}); save the CSV as UTF-8"
        ) from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError) as exc:
        raise ThermocalInputError(
            f"data file {path} could not be read as CSV with separator {sep!r}: {exc}; check "
            "--sep and --decimal"
        ) from None


def _drop_empty_columns(table, notes: list[str]):
    """The table without the unnamed, empty columns a spreadsheet's trailing separators make
    (``...;Ti;;``: Excel's export; they were refused as a column named twice)."""
    empty = [
        c for c in table.columns
        if str(c).startswith("Unnamed: ") and table[c].isna().all()
    ]  # fmt: skip
    if empty:
        notes.append(f"{len(empty)} unnamed empty column(s) dropped (trailing separators)")
        table = table.drop(columns=empty)
    return table


def _check_header(path: Path, sep: str) -> None:
    """Refuse a header naming one column twice (pandas would rename the second silently)."""
    import csv

    from thermocal.errors import ThermocalInputError

    with path.open(encoding="utf-8", errors="replace", newline="") as fh:
        header = next(csv.reader(fh, delimiter=sep), [])
    seen: dict[str, int] = {}
    for position, name in enumerate(header, start=1):
        name = name.strip()
        if not name:
            continue  # unnamed: dropped when empty, named "Unnamed: n" by pandas otherwise
        if name in seen:
            raise ThermocalInputError(
                f"data file {path}: column {name!r} appears twice in the header (columns "
                f"{seen[name]} and {position}); rename or remove one"
            )
        seen[name] = position


def shift_end_stamped(data, inputs, stamps: str, notes: list[str]):
    """Inputs of data stamped at the END of each interval, moved onto the zero-order hold.

    A logger's mean over ``[t_k-1, t_k]`` stamped ``t_k`` is the input over the step INTO
    sample ``k``; the zero-order hold applies ``u[k]`` over ``[t_k, t_k+1)``. With
    ``stamps="end"`` the input columns are shifted one row earlier (the last row, without an
    input for its step, is dropped) and a note says so. ``"start"``: unchanged.
    """
    from thermocal.errors import ThermocalInputError

    if stamps not in ("start", "end"):
        raise ThermocalInputError(f"--time-stamps {stamps!r}: use start or end")
    if stamps == "start":
        return data
    from thermocal.statespace.data import end_stamped_inputs

    cols = [c for c in inputs if c in data.columns]
    data = end_stamped_inputs(data, cols)
    notes.append(
        "--time-stamps end: input columns " + ", ".join(cols) + " shifted one sample earlier "
        "(each value is the mean over the interval ending at its stamp); last row dropped"
    )
    return data


def fitted_model_yaml(results) -> str:
    """The model file with the estimates as values (moved 1e-9 inside a bound they lie on, so
    that the file can be fitted again), the model's name and description kept."""
    import yaml

    from thermocal.statespace.profile import _inside

    model = results.model.with_parameters(_inside(results.model, results.params.to_dict()))
    return yaml.safe_dump(model.to_dict(), sort_keys=False)


def interval_end(value: float | None, is_open: bool, digits: int = 4, open_text: str = "open"
                 ) -> str:  # fmt: skip
    """One end of a profile-likelihood interval for the console: the value, marked when the
    interval is open there (the bound), or 'not found' (None)."""
    if value is None:
        return "not found"
    return f"{value:.{digits}g}{f' ({open_text})' if is_open else ''}"


def heat_loss_text(hlc: dict | None) -> str:
    """One line on the heat loss coefficient: the profile interval first when computed."""
    if hlc is None:
        return "heat loss coefficient: not implied by the model structure"
    pct = f"{100 * (1 - hlc['alpha']):g} %"
    import math

    no_wald = not math.isfinite(hlc["wald_lower"])
    wald = (
        "no Wald interval: a parameter it depends on has no standard error"
        if no_wald
        else f"Wald {hlc['wald_lower']:.4g} to {hlc['wald_upper']:.4g}"
    )
    text = f"heat loss coefficient {hlc['value']:.4g} W/K"
    if hlc.get("interval") == "profile":
        lo = interval_end(hlc["lower"], hlc["open_lower"])
        hi = interval_end(hlc["upper"], hlc["open_upper"])
        text += f", {pct} profile-likelihood interval [{lo}, {hi}] ({wald}"
        disagree = hlc["disagree"] and not no_wald
        text += "; they disagree: use the profile interval)" if disagree else ")"
    else:
        text += f", {pct} {wald}"
    held = hlc.get("held_by_bounds") or []
    if held:
        text += (
            f"; HELD BY A BOUND: {', '.join(held)} at {'its' if len(held) == 1 else 'their'} "
            "bound, so the coefficient is the bound's, not the data's, and no interval above "
            "is its uncertainty: widen the bound in the model file and refit"
        )
    if len(hlc["boundaries"]) > 1:
        text += (
            f"; the heat flows to {len(hlc['boundaries'])} boundary temperatures "
            f"({', '.join(hlc['boundaries'])}): it is a loss to all of them together, and an "
            "adjacent space that follows the test regime makes it period-dependent"
        )
    return text


def check_numbers(data, columns, path: Path, decimal: str) -> None:
    """Refuse text in the model's numeric columns, naming column, row and value; the columns
    read as text (decimal commas with thousands separators) are replaced by their numbers."""
    import re

    import pandas as pd

    from thermocal.errors import ThermocalInputError

    for column in columns:
        if column not in data.columns or pd.api.types.is_numeric_dtype(data[column]):
            continue
        values = data[column]
        text = values.astype(str).str.strip()
        if decimal == "." and text[values.notna()].str.fullmatch(r"[-+]?\d+,\d+").mean() > 0.5:
            raise ThermocalInputError(
                f"data file {path}: column '{column}' holds decimal commas (row 0: "
                f"{text.iloc[0]!r}); add --decimal , (and --sep ';' if needed)"
            )
        if decimal == ",":
            from thermocal.io.decimal_comma import decimal_comma_numbers

            # a point groups thousands (7.476 is 7,476 W, which was read as 7.476 W); any
            # other point is ambiguous there
            numbers, ambiguous = decimal_comma_numbers(values)
            if ambiguous.any():
                row = int(ambiguous.to_numpy().nonzero()[0][0])
                raise ThermocalInputError(
                    f"data file {path}: column '{column}', row {row} (file line {row + 2}): "
                    f"{values.iloc[row]!r} has a decimal point, but --decimal , reads a point "
                    "only as a thousands separator (1.203,5); write it with a decimal comma"
                )
        else:
            numbers = pd.to_numeric(text, errors="coerce")
        bad = values.notna() & numbers.isna() & (text != "")
        if bad.any():
            row = int(bad.to_numpy().nonzero()[0][0])
            sep_like = re.search(r"[;,\t]", text.iloc[row])
            hint = "; is the separator right (--sep)?" if sep_like else ""
            raise ThermocalInputError(
                f"data file {path}: column '{column}', row {row} (file line {row + 2}): "
                f"{values.iloc[row]!r} is not a number; write a number or leave the cell empty "
                f"(missing){hint}"
            )
        data[column] = numbers.to_numpy(dtype=float)  # the values as read, for the fit


def resolve_time_column(data, time_column: str | None, time_format: str | None, path: Path) -> str:
    """The time column of a data table (default "time", else the first column), parsed with
    ``--time-format`` when given (in place).

    Parameters
    ----------
    data : DataFrame
    time_column : str or None
    time_format : str or None
        strftime format of the time stamps.
    path : Path
        The data file, for messages.

    Returns
    -------
    str
        The time column's name.
    """
    import pandas as pd

    from thermocal.errors import ThermocalInputError

    if time_column is None:
        time_column = "time" if "time" in data.columns else str(data.columns[0])
    if time_column not in data.columns:
        raise ThermocalInputError(
            f"{path}: no time column '{time_column}'; columns: "
            f"{', '.join(map(str, data.columns))}; use --time-column"
        )
    if time_format is not None:
        try:
            data[time_column] = pd.to_datetime(data[time_column], format=time_format)
        except (ValueError, TypeError) as exc:
            raise ThermocalInputError(
                f"{path}: time column '{time_column}' does not follow --time-format "
                f"{time_format!r} ({exc})"
            ) from None
    return time_column


def check_time_axis(data, time_column: str, time_unit: str, path: Path) -> None:
    """Refuse time axes that are certainly wrong before any computation.

    Mixed naive and offset time stamps (row named), an unreadable stamp (row and value),
    the autumn clock change of naive local times, and a sampling interval implausible for
    building data (under a second or over a day: the wrong --time-unit).
    """
    import numpy as np
    import pandas as pd

    from thermocal.errors import ThermocalInputError
    from thermocal.statespace.data import check_sampling_interval, time_axis
    from thermocal.statespace.units import TIME_UNITS

    if time_unit not in TIME_UNITS:
        raise ThermocalInputError(f"--time-unit {time_unit!r}: use one of {', '.join(TIME_UNITS)}")
    raw = data[time_column]
    naive = False
    if not (pd.api.types.is_numeric_dtype(raw) or pd.api.types.is_datetime64_any_dtype(raw)):
        text = raw.astype(str).str.strip()
        parsed = pd.to_datetime(text, format="ISO8601", utc=True, errors="coerce")
        if parsed.isna().any() and parsed.notna().any():
            row = int(parsed.isna().to_numpy().nonzero()[0][0])
            raise ThermocalInputError(
                f"data file {path}: time column '{time_column}', row {row} (file line "
                f"{row + 2}): {raw.iloc[row]!r} is not an ISO 8601 date-time; write it like "
                f"{text.iloc[0 if row else 1]!r}"
            )
        aware = text.str.contains(r"(?:Z|[+-]\d\d:?\d\d)$", regex=True)
        if aware.any() and not aware.all():
            first_naive = int((~aware).to_numpy().nonzero()[0][0])
            first_aware = int(aware.to_numpy().nonzero()[0][0])
            raise ThermocalInputError(
                f"data file {path}: time column '{time_column}' mixes stamps without a UTC "
                f"offset (row {first_naive}: {text.iloc[first_naive]!r}) and with one (row "
                f"{first_aware}: {text.iloc[first_aware]!r}); give every time stamp its offset "
                "(e.g. +01:00) or none"
            )
        naive = not aware.any()
    try:
        index, seconds = time_axis(
            data, time_column=time_column, time_unit=time_unit, source=str(path)
        )
    except ThermocalInputError as exc:
        if (
            naive
            and isinstance(exc, ThermocalInputError)
            and ("not increasing" in str(exc) or "duplicated" in str(exc))
        ):
            stamps = pd.to_datetime(raw.astype(str), format="ISO8601", errors="coerce")
            steps = np.diff(stamps.to_numpy().astype("datetime64[s]").astype(np.int64))
            row = int(np.flatnonzero(steps <= 0)[0]) + 1
            stamp = stamps.iloc[row]
            if stamp.month in (10, 11) and stamp.day_of_week == 6 and 0 <= stamp.hour <= 3:
                raise ThermocalInputError(
                    f"data file {path}: time column '{time_column}' goes back at row {row} "
                    f"({stamps.iloc[row - 1]} then {stamp}): naive local times repeat an hour "
                    "at the autumn clock change, and sorting would interleave the two hours; "
                    "give the times in UTC or with their UTC offset (e.g. +01:00 / +02:00)"
                ) from None
        raise
    step = float(np.median(np.diff(seconds))) if seconds.size > 1 else 0.0
    if naive and step > 0:
        jumps = np.flatnonzero(np.isclose(np.diff(seconds), step + 3600.0))
        for row in jumps + 1:
            stamp = index[row]
            if stamp.month in (3, 4) and stamp.day_of_week == 6 and 1 <= stamp.hour <= 4:
                raise ThermocalInputError(
                    f"data file {path}: time column '{time_column}' jumps by one hour more "
                    f"than its step at row {row} ({index[row - 1]} then {stamp}): naive local "
                    "times skip an hour at the spring clock change, which would read as a gap; "
                    "give the times in UTC or with their UTC offset (e.g. +01:00 / +02:00)"
                )
    # numeric axes were checked by time_axis; date-times over a day apart are no building data
    check_sampling_interval(
        seconds, time_column=time_column, time_unit=time_unit, source=f"data file {path}",
        numeric=not isinstance(index, pd.DatetimeIndex),
    )  # fmt: skip
    if step == 1 and time_unit == "s" and pd.api.types.is_numeric_dtype(raw):
        raise ThermocalInputError(
            f"data file {path}: time column '{time_column}' counts 0, 1, 2, ... read as 1 s "
            "steps (the default --time-unit s); building data sampled every second is "
            "unlikely: give the unit of the numbers, e.g. --time-unit h or --time-unit min"
        )


def _drop_unit_row(table, notes: list[str], decimal: str = "."):
    """The table without a unit row under the header (then re-read as numbers)."""
    import pandas as pd

    if len(table) < 2 or table.shape[1] < 2:
        return table
    others = table.columns[1:]  # the first column is usually the time

    def as_numbers(values):
        if decimal == ",":
            from thermocal.io.decimal_comma import decimal_comma_numbers

            return decimal_comma_numbers(values)[0]
        return pd.to_numeric(values, errors="coerce")

    def numbers(row) -> int:
        return int(as_numbers(row[others].astype(object)).notna().sum())

    if numbers(table.iloc[0]) == 0 and numbers(table.iloc[1]) > 0:
        units = ", ".join(f"{c}: {table.iloc[0][c]}" for c in table.columns)
        notes.append(f"unit row under the header dropped: {units}")
        table = table.iloc[1:].reset_index(drop=True)
        for c in others:
            converted = as_numbers(table[c])
            if converted.notna().sum() >= table[c].notna().sum():
                table[c] = converted
    return table


def parse_mapping(items: list[str] | None) -> dict[str, str]:
    """``["Ps=Gv", ...]`` (model column = data column) as a dict data column -> model column."""
    from thermocal.errors import ThermocalInputError

    out: dict[str, str] = {}
    for item in items or []:
        model_name, sep_, data_name = item.partition("=")
        if not sep_ or not model_name.strip() or not data_name.strip():
            raise ThermocalInputError(
                f"--map {item!r}: write MODEL_COLUMN=DATA_COLUMN, e.g. --map Ph=heating_kW"
            )
        out[data_name.strip()] = model_name.strip()
    return out


def merge_mappings(model, cli_renames: dict[str, str], data_file: Path) -> dict[str, str]:
    """Renames data column -> model column from the model file's ``columns:`` and ``--map``
    (``--map`` wins for a model name given in both); the model's own mapping is then cleared
    (the data carries the model's names)."""
    if not model.columns:
        return cli_renames
    model.check_columns()
    by_model = {m: d for m, d in model.columns.items() if m != d}
    by_model |= {m: d for d, m in cli_renames.items()}
    model.set_columns({})
    return {d: m for m, d in by_model.items()}


#: Data with more rows than this get a measured work estimate before the fit.
ESTIMATE_ROWS = 100_000
#: Memory the stored filter moments (one-step predictions, smoothing) may take [bytes].
MAX_STORE_BYTES = 4e9
#: Likelihood evaluations per optimiser iteration are 2 k + 1 (central-difference gradient,
#: k free parameters); a typical fit takes about this many iterations per start.
TYPICAL_ITERATIONS = 200


def work_estimate(model, data, *, time_column, time_unit, n_starts, jobs) -> dict:
    """Rows x states, memory of the stored filter moments and, for large data, the fit time
    extrapolated from a timed likelihood evaluation on the first rows.

    Returns a dict with ``rows``, ``states``, ``store_bytes``, ``seconds_per_evaluation``,
    ``fit_seconds`` (NaN when not measured).
    """
    import math
    import os
    import time

    from thermocal.statespace.estimation import default_n_starts

    rows, n = len(data), len(model.state_names)
    store_bytes = 8.0 * rows * (3 * n * n + 3 * n + 4 * len(model.output_names))
    out = {"rows": rows, "states": n, "store_bytes": store_bytes,
           "seconds_per_evaluation": math.nan, "fit_seconds": math.nan}  # fmt: skip
    if rows > ESTIMATE_ROWS:
        sample = data.iloc[: min(rows, 20_000)]
        kwargs = {"time_column": time_column, "time_unit": time_unit}
        try:
            model.loglike(sample.iloc[:50], **kwargs)  # compile / load the kernels
            t0 = time.perf_counter()
            model.loglike(sample, **kwargs)
            per_row = (time.perf_counter() - t0) / len(sample)
        except Exception:  # noqa: BLE001 - the fit itself reports bad data with its message
            return out
        starts = n_starts or default_n_starts(model)
        parallel = max(1, min(starts, jobs or os.cpu_count() or 1))
        per_eval = per_row * rows
        out["seconds_per_evaluation"] = per_eval
        out["fit_seconds"] = (
            per_eval * (2 * model.n_free + 1) * TYPICAL_ITERATIONS * math.ceil(starts / parallel)
        )
    return out


def _readable(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


FIT_HELP = (
    "Fit a grey-box RC model by maximum likelihood (Kalman filter).\n\n"
    "Writes OUT/fit.json (log-likelihood, AIC, BIC, estimates with standard errors, correlation "
    "matrix, flags with remedies, residual diagnostics, provenance, the heat loss coefficient "
    "the model implies with its profile-likelihood interval), parameters.csv, model_fitted.yaml "
    "(the model file holding the estimates), predictions.csv and PNG figures (measured vs "
    "one-step prediction, residual autocorrelation, cumulated periodogram), and prints a "
    "summary. With --strict the exit code is 3 when any flag is raised (2: input error). "
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
        int | None,
        typer.Option(
            "--n-starts",
            min=1,
            help="Optimiser starts (1 = the declared values only, flagged: the global optimum "
            "is not checked). Default: max(3, half the free parameters) plus a start from the "
            "data's energy balance, and as many more when only one start reaches the best value "
            "(converged needs two that agree).",
        ),
    ] = None,
    seed: Annotated[int | None, typer.Option("--seed", help="Seed of the random starts.")] = None,
    jobs: Annotated[
        int | None,
        typer.Option("--jobs", min=1, help="Processes for the starts (default: one per CPU)."),
    ] = None,
    figures: Annotated[
        bool, typer.Option("--figures/--no-figures", help="Write PNG figures.")
    ] = True,
    mapping: Annotated[
        list[str] | None,
        typer.Option(
            "--map",
            help="Model column = data column, e.g. --map Ps=Gv (repeat for several).",
        ),
    ] = None,
    time_format: Annotated[
        str | None,
        typer.Option(
            "--time-format",
            help="strftime format of non-ISO time stamps, e.g. '%d.%m.%Y %H:%M' (day first).",
        ),
    ] = None,
    decimal: Annotated[
        str, typer.Option("--decimal", help="Decimal mark of the CSV: '.' or ','.")
    ] = ".",
    sheet: Annotated[
        str | None, typer.Option("--sheet", help="Excel sheet name (default: the first).")
    ] = None,
    max_gap: Annotated[
        int,
        typer.Option(
            "--max-gap",
            min=0,
            help="Missing input values: gaps of at most this many samples are interpolated "
            "linearly (noted in fit.json); longer gaps stop with the period to cut. 0: inputs "
            "must be complete.",
        ),
    ] = 3,
    gaps: Annotated[
        str,
        typer.Option(
            "--gaps",
            help="Input gaps longer than --max-gap: 'stop' (name the rows to cut) or 'split' "
            "(leave them out and split the likelihood into periods with their own initial "
            "states; also at jumps of the time axis).",
        ),
    ] = "stop",
    profile: Annotated[
        list[str] | None,
        typer.Option(
            "--profile",
            help="Profile-likelihood 95 % interval of a free parameter or derived quantity "
            "(repeat for several; each costs a few refits).",
        ),
    ] = None,
    max_hours: Annotated[
        float,
        typer.Option(
            "--max-hours",
            min=0,
            help="Refuse when the estimated fit time (measured on large data) exceeds this.",
        ),
    ] = 24.0,
    strict: Annotated[
        bool,
        typer.Option("--strict", help="Exit with code 3 when any flag is raised."),
    ] = False,
    time_stamps: Annotated[
        str,
        typer.Option(
            "--time-stamps",
            help="'start': each row's inputs hold from its time stamp to the next (default); "
            "'end': stamps at the end of each interval (common for loggers), inputs shifted "
            "one sample.",
        ),
    ] = "start",
    stamp_check: Annotated[
        bool,
        typer.Option(
            "--time-stamp-check/--no-time-stamp-check",
            help="Refit with the inputs as stamped and moved one sample (stamps at the end of "
            "each interval) and say which --time-stamps the data support (two refits).",
        ),
    ] = True,
    hlc_split: Annotated[
        list[str] | None,
        typer.Option(
            "--hlc-split",
            help="Start of another period (time stamp, or number in --time-unit; repeat for "
            "more): the model is fitted on each period too and their heat loss coefficients "
            "compared; a flag when their intervals do not overlap (e.g. a randomised heating "
            "sequence and a steady phase, adjacent spaces following the test).",
        ),
    ] = None,
    hlc_halves: Annotated[
        bool,
        typer.Option(
            "--hlc-halves/--no-hlc-halves",
            help="Without --hlc-split, with --hlc: fit the model on the first and on the "
            "second half of the data too (two more fits) and flag when the heat loss "
            "coefficients' intervals do not overlap (a period-dependent coefficient).",
        ),
    ] = True,
    hlc: Annotated[
        bool,
        typer.Option(
            "--hlc/--no-hlc",
            help="Heat loss coefficient implied by the model (with its profile interval).",
        ),
    ] = True,
) -> None:
    """Fit a grey-box RC model (see :data:`FIT_HELP`)."""
    import datetime
    import json
    import sys

    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    from thermocal import __version__
    from thermocal.errors import ThermocalInputError
    from thermocal.io.output import output_folder
    from thermocal.io.yamlfile import read_yaml
    from thermocal.statespace import RCModel
    from thermocal.statespace.diagnostics import (
        autocorrelation,
        cumulated_periodogram,
        fraction_outside_band,
    )
    from thermocal.statespace.results import single_start_flag

    if hold not in ("zoh", "foh"):
        raise ThermocalInputError(f"--hold {hold!r}: use zoh or foh")
    if gaps not in ("stop", "split"):
        raise ThermocalInputError(f"--gaps {gaps!r}: use stop or split")
    console = Console()
    model = RCModel.from_dict(read_yaml(model_file, what="model file"), source=str(model_file))
    data = read_table(data_file, sep=sep, decimal=decimal, sheet=sheet)
    notes = list(data.attrs.get("notes", []))
    renames = merge_mappings(model, parse_mapping(mapping), data_file)
    if renames:
        absent = [c for c in renames if c not in data.columns]
        if absent:
            raise ThermocalInputError(
                f"{data_file}: --map or the model file's columns: name data column(s) "
                f"{', '.join(map(repr, absent))}, not in the data; columns present: "
                f"{', '.join(map(str, data.columns))}"
            )
        clash = [m for d, m in renames.items() if m in data.columns and m not in renames]
        if clash:
            raise ThermocalInputError(
                f"{data_file}: column(s) {', '.join(map(repr, clash))} are mapped from another "
                "data column (--map or the model file's columns:) but exist in the data as "
                "well; remove the mapping or rename one of the columns"
            )
        data = data.rename(columns=renames)
        notes.append("columns mapped: " + ", ".join(f"{d} -> {m}" for d, m in renames.items()))
    time_column = resolve_time_column(data, time_column, time_format, data_file)
    for name in profile or []:
        if name not in model.free_parameter_names and name not in model.derived:
            raise ThermocalInputError(
                f"--profile {name!r}: not a free parameter or derived quantity of "
                f"{model_file} (free: {', '.join(model.free_parameter_names)}; derived: "
                f"{', '.join(model.derived) or 'none'})"
            )
    check_time_axis(data, time_column, time_unit, data_file)
    check_numbers(data, [*model.input_names, *model.output_names], data_file, decimal)
    as_stamped = data
    data = shift_end_stamped(data, model.input_names, time_stamps, notes)
    work = work_estimate(
        model, data, time_column=time_column, time_unit=time_unit, n_starts=n_starts, jobs=jobs
    )
    if work["store_bytes"] > MAX_STORE_BYTES:
        raise ThermocalInputError(
            f"{data_file}: {work['rows']:,} rows x {work['states']} states need about "
            f"{work['store_bytes'] / 1e9:.1f} GB for the one-step predictions and residuals "
            f"(limit {MAX_STORE_BYTES / 1e9:.0f} GB); resample to a coarser step (e.g. "
            "15-minute or hourly means) or fit a shorter period"
        )
    if work["fit_seconds"] == work["fit_seconds"]:  # measured
        console.print(
            f"work estimate: {work['rows']:,} rows x {work['states']} states, "
            f"{work['seconds_per_evaluation']:.2g} s per likelihood evaluation, fit about "
            f"{_readable(work['fit_seconds'])}"
        )
        if work["fit_seconds"] > max_hours * 3600:
            raise ThermocalInputError(
                f"{data_file}: the fit would take about {_readable(work['fit_seconds'])} "
                f"({work['rows']:,} rows x {work['states']} states, {model.n_free} free "
                f"parameters), more than --max-hours {max_hours:g}; resample to a coarser step, "
                "fit a shorter period, or raise --max-hours"
            )
    with output_folder(out, command="fit", signature=("fit.json",)) as tmp:
        started = datetime.datetime.now(datetime.UTC)
        console.print(f"fitting {model.name} ({model.n_free} free parameters)...")
        results = model.fit(
            data,
            hold=hold,
            n_starts=n_starts,
            seed=seed,
            time_column=time_column,
            time_unit=time_unit,
            source=str(data_file),
            n_jobs=jobs,
            progress=True,
            input_gaps="split" if gaps == "split" else "interpolate" if max_gap > 0 else "error",
            max_gap=max_gap if gaps == "split" else max(max_gap, 1),
        )
        single = single_start_flag(results)
        if single:
            results.flags.insert(0, single)
        content = results.to_dict()
        if profile:
            content["profile_intervals"] = {}
            for name in profile:
                console.print(f"profile likelihood of {name}...")
                interval = results.profile_interval(name)
                interval.pop("points")
                content["profile_intervals"][name] = interval
        if stamp_check and gaps != "split":
            from thermocal.statespace.checks import time_stamp_check

            console.print("time stamps: refitting with the inputs moved one sample...")
            try:
                stamps = time_stamp_check(
                    results, as_stamped, stamps=time_stamps, time_column=time_column,
                    time_unit=time_unit,
                    input_gaps="interpolate" if max_gap > 0 else "error",
                    max_gap=max(max_gap, 1),
                )  # fmt: skip
            except ThermocalInputError as exc:
                # the refits leave out the first and last rows: a fit of barely enough rows
                # has too few for them (12 rows for 10 parameters stopped the command after
                # a successful fit, blaming the data)
                stamps = {"message": None, "note": None, "skipped": str(exc)}
                notes.append(
                    "time stamps not checked: the refits with the inputs moved one sample "
                    f"leave out the first and last rows, and then: {exc}"
                )
            content["time_stamp_check"] = stamps
            if stamps["message"]:
                results.flags.insert(0, stamps["message"])
                content["flags"] = list(results.flags)
            if stamps["note"]:
                notes.append(stamps["note"])
        elif stamp_check:  # --gaps split: each piece its own start; the refits do not apply
            notes.append(
                "time stamps not checked: with --gaps split the data are separate pieces, each "
                "with its own start, which the refits with the inputs moved one sample do not "
                "handle; fill short gaps (--gaps interpolate) to have them checked"
            )
            content["time_stamp_check"] = {"message": None, "note": None,
                                           "skipped": "--gaps split"}  # fmt: skip
        if not hlc_split and hlc_halves and hlc and gaps == "split":
            notes.append(
                "heat loss coefficient per half of the data not compared: with --gaps split the "
                "halves would cut the pieces again; give the periods with --hlc-split to compare "
                "them"
            )
        halves = (
            not hlc_split and hlc_halves and hlc and gaps != "split"
            and model.heat_loss_state() is not None
        )  # fmt: skip
        regime = None
        if hlc_split or halves:
            from thermocal.statespace.checks import heat_loss_regime_check, split_at, split_halves

            console.print("heat loss coefficient per period...")
            # the periods as the main fit read the gaps (split there: each its own start)
            gap_kw = {
                "input_gaps": "split" if gaps == "split"
                else "interpolate" if max_gap > 0 else "error",
                "max_gap": max(max_gap, 1),
            }  # fmt: skip
            if hlc_split:
                periods = split_at(data, hlc_split, time_column=time_column,
                                   time_unit=time_unit, source=str(data_file))  # fmt: skip
                regime = heat_loss_regime_check(
                    model, periods, hold=hold, time_column=time_column, time_unit=time_unit,
                    profile=False, n_starts=n_starts, seed=seed, **gap_kw,
                )  # fmt: skip
            else:
                try:  # automatic: a period that cannot be fitted alone skips the check
                    periods = split_halves(data, time_column=time_column, time_unit=time_unit,
                                           source=str(data_file))  # fmt: skip
                    regime = heat_loss_regime_check(
                        model, periods, hold=hold, time_column=time_column,
                        time_unit=time_unit, profile=False, n_starts=n_starts, seed=seed,
                        **gap_kw,
                    )  # fmt: skip
                except ThermocalInputError as exc:
                    notes.append(f"heat loss coefficient per half of the data not compared: {exc}")
        if regime is not None:
            content["heat_loss_by_period"] = regime
            if regime["agree"] is False:
                results.flags.insert(0, regime["message"])
                content["flags"] = list(results.flags)
            elif regime["message"]:  # not compared: the fit's own flags say why
                notes.append(regime["message"])
        if hlc and model.heat_loss_state() is not None:
            console.print("heat loss coefficient and its profile likelihood...")
            content["heat_loss_coefficient"] = results.heat_loss_coefficient()
        # the profiles may add flags (an end not found, a better optimum)
        content["flags"], content["converged"] = list(results.flags), results.converged
        content["data_notes"] = notes + content.get("data_notes", [])
        content["provenance"] = {
            "thermocal_version": __version__,
            "command": " ".join(["thermocal", *sys.argv[1:]]) if sys.argv else "thermocal fit",
            "seed": seed,
            "n_starts": len(results.start_loglikes),
            "started_utc": started.isoformat(timespec="seconds"),
            "files": {
                str(model_file): {"sha256": file_sha256(model_file)},
                str(data_file): {"sha256": file_sha256(data_file)},
            },
        }
        diagnostics = {}
        residuals = results.residuals
        from thermocal.statespace.results import observation_rows

        for col in model.output_names:
            # the rows the residual tests take (a midpoint grid observes every second row)
            e = residuals[col].to_numpy()[observation_rows(residuals[[col]].to_numpy(float))]
            acf = autocorrelation(e, nlags=40)
            cp = cumulated_periodogram(e)
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
        (tmp / "fit.json").write_text(json.dumps(content, indent=2))
        results.parameter_table().to_csv(tmp / "parameters.csv")
        (tmp / "model_fitted.yaml").write_text(fitted_model_yaml(results))
        predictions = results.one_step_residuals()
        simulated = results.simulate()
        for col in model.output_names:
            predictions[f"{col}_simulated"] = simulated[col]
        predictions.index.name = "time"
        predictions.to_csv(tmp / "predictions.csv")
        written = [Path("fit.json"), Path("parameters.csv"), Path("model_fitted.yaml"),
                   Path("predictions.csv")]  # fmt: skip
        if figures:
            from thermocal.statespace.plots import plot_fit

            written += [Path(p.name) for p in plot_fit(results, tmp)]

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
            # at a bound the delta method maps the wide spread of the log or logit scale to a
            # tiny one (a capacity at its bound: 4 +- 1.5e-07 kWh/K): not an uncertainty; the
            # profile interval (--profile) is
            "at bound" if name in results.at_bound else "" if se != se else f"{se:.3g}",
            row["unit"],
            f"{row['lower']:.4g}",
            f"{row['upper']:.4g}",
            "yes" if row["fixed"] else "",
        )
    console.print(table)
    for name, iv in content.get("profile_intervals", {}).items():
        console.print(escape(
            f"profile 95 % interval {name}: {iv['estimate']:.6g} in "
            f"[{interval_end(iv['lower'], iv['open_lower'], 6, 'bound')}, "
            f"{interval_end(iv['upper'], iv['open_upper'], 6, 'bound')}]"
        ))  # fmt: skip
    if "heat_loss_coefficient" in content:
        console.print(escape(heat_loss_text(content["heat_loss_coefficient"])))
    for note in content["data_notes"]:
        console.print(f"note: {escape(note)}")
    for flag in results.flags:  # escaped: "[nan, nan]" would read as a markup tag
        console.print(f"[yellow]flag:[/yellow] {escape(flag)}")
    for col, d in diagnostics.items():
        console.print(
            f"residuals {col}: std {d['residual_std']:.4f} K, "
            f"{d['acf_lags_outside_95_bound']}/{d['acf_lags_tested']} ACF lags outside the 95 % "
            f"bound, cumulated periodogram "
            f"{100 * d['cumulated_periodogram_fraction_outside_95_band']:.0f} % outside its band"
        )
    console.print("wrote " + ", ".join(str(out / p) for p in written))
    if strict and results.flags:
        console.print(f"--strict: {len(results.flags)} flag(s) raised")
        raise typer.Exit(code=3)
