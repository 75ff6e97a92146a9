"""Reading a sensor log (CSV or parquet, long or wide layout) into raw reports in thermocal's units.

Part of :mod:`thermocal.io.measurements`; see its docstring for the conventions.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io._time import parse_time_column
from thermocal.io.measurements.layout import _read_long, _read_wide
from thermocal.io.measurements.units import (
    _NA_TOKENS,
    _TIME_CANDIDATES,
    _as_timedelta,
    _split_header_unit,
    _suggest,
)


def _data_line_numbers(path: Path, comment: str | None) -> tuple[int, np.ndarray]:
    """1-based line of the header and of every data row, as pandas' C parser counts them."""
    header = 0
    lines: list[int] = []
    with path.open("r", encoding="utf-8-sig", errors="replace", newline=None) as handle:
        for number, line in enumerate(handle, start=1):
            text = line.split(comment, 1)[0] if comment else line
            if not text.strip():
                continue
            if header == 0:
                header = number
            else:
                lines.append(number)
    return header, np.asarray(lines, dtype=np.int64)


def _line_numbers(path: Path, n_rows: int, comment: str | None) -> np.ndarray:
    """Line numbers of the data rows; fast when there are no blank or comment lines."""
    raw = path.read_bytes()
    simple = b"\n\n" not in raw and b"\r\n\r\n" not in raw and not raw.startswith((b"\n", b"\r"))
    if comment:
        simple = simple and comment.encode() not in raw
    if simple:
        return np.arange(2, n_rows + 2, dtype=np.int64)
    _, lines = _data_line_numbers(path, comment)
    if len(lines) != n_rows:  # quoted multi-line fields: fall back to row numbers
        return np.arange(2, n_rows + 2, dtype=np.int64)
    return lines


def _sniff_separator(path: Path, comment: str | None) -> str:
    with path.open("r", encoding="utf-8-sig", errors="replace") as handle:
        for line in handle:
            text = line.split(comment, 1)[0] if comment else line
            if text.strip():
                counts = {sep: text.count(sep) for sep in (",", ";", "\t", "|")}
                best = max(counts, key=counts.get)
                return best if counts[best] > 0 else ","
    raise ThermocalInputError(f"{path}: the file is empty (no header line)")


def read_measurements(
    path: str | Path,
    *,
    layout: Literal["auto", "long", "wide"] = "auto",
    time_column: str = "time",
    sensor_column: str = "sensor",
    value_column: str = "value",
    unit_column: str = "unit",
    sensors: Sequence[str] | Mapping[str, str] | None = None,
    units: Mapping[str, str] | None = None,
    quantities: Mapping[str, str] | None = None,
    tz: Any = None,
    time_format: str | None = None,
    time_unit: str | None = None,
    start: Any = None,
    sep: str | None = None,
    decimal: str = ".",
    comment: str | None = None,
    duplicates: Literal["error", "first", "last"] = "error",
    sort: bool = False,
    rows: Literal["reports", "interval_start", "interval_end"] = "reports",
    interval: Any = None,
    unknown_sensors: Literal["error", "ignore"] = "error",
) -> tuple[pd.DataFrame, dict]:
    """Read a sensor log (CSV or parquet, long or wide) into reports in thermocal units.

    Parameters
    ----------
    path : str or Path
        CSV file (the separator is sniffed from the header: ``,``, ``;``, tab, ``|``), or a
        parquet table (``.parquet``, ``.pq``; its time column may be text, numbers or
        datetimes). Messages about a parquet table count its rows as lines (1 = first row).
    layout : {"auto", "long", "wide"}
        "long": one report per row with ``time_column``, ``sensor_column``, ``value_column``
        (and optionally ``unit_column``); "wide": ``time_column`` plus one column per sensor,
        empty cells meaning "not reported". "auto": long when the sensor and value columns exist.
    time_column : str
        Name of the time column. When absent, a single column called time, timestamp, datetime,
        date or t (any case) is used.
    sensor_column, value_column, unit_column : str
        Column names of the long layout.
    sensors : sequence of str or mapping, optional
        The expected sensors. A mapping renames file names to thermocal names
        (``{"Sensor 12": "temp_living"}``). Sensors in the file but not here are errors (with the
        line of their first report) unless ``unknown_sensors="ignore"``; expected sensors absent
        from the file are errors.
    units : mapping, optional
        Unit per sensor (file or renamed name), e.g. ``{"flow": "l/h", "T_cellar": "K"}``;
        overrides nothing: a unit also declared in the file must agree.
    quantities : mapping, optional
        Quantity per sensor (``"temperature"``, ``"flow"``, ``"power"``, ...) when no unit is
        declared; otherwise guessed from the name (``T_...``, ``temp...`` -> temperature,
        ``...flow...`` -> flow).
    tz : str, datetime.tzinfo, float or None
        Time zone of timestamps written without UTC offset (required for those), and of the
        result; timestamps with offsets are converted to it. A number is a fixed offset [h east
        of UTC] (local standard time, e.g. 1.0). None keeps the file's offset (UTC when the
        offsets vary). Local times that do not exist or are ambiguous at a clock change are
        errors naming the line.
    time_format : str, optional
        strftime format of the time column when it is not ISO 8601, e.g. "%d.%m.%Y %H:%M".
    time_unit : {"s", "ms", "min", "h", "d"}, optional
        For numeric time columns: the unit of the numbers; ``start`` is the time of 0.
    start : str or Timestamp, optional
        Origin of numeric times (default 1970-01-01 UTC).
    sep : str, optional
        Field separator (sniffed when None).
    decimal : str
        Decimal mark ("." or ",").
    comment : str, optional
        Lines (or line ends) after this character are ignored, e.g. "#".
    duplicates : {"error", "first", "last"}
        Repeated timestamps (per sensor): an error, or keep the first/last report.
    sort : bool
        Sort out-of-order rows by time instead of raising an error (reported in ``meta``).
    rows : {"reports", "interval_start", "interval_end"}
        What a row is. "reports" (default): an event or sample at its time stamp, held until
        the next report by :func:`resample_measurements`. "interval_start": the mean over the
        logging interval ``[t, t + interval)`` labelled by its start (typical of data loggers
        and of exported hourly/10-minute tables); "interval_end": the same labelled by its end
        (the times are shifted back by ``interval``). For both, ``meta["interval"]`` tells
        :func:`resample_measurements` to hold each row until the next one but for at most
        ``interval``, and the last row until its interval end.
    interval : str or Timedelta, optional
        The logging interval of ``rows="interval_start"``/``"interval_end"`` [duration];
        default the median spacing of the time stamps (per sensor in the long layout, the
        median over the sensors).
    unknown_sensors : {"error", "ignore"}
        With ``sensors`` given: columns (wide) or rows (long) of other sensors are an error, or
        are skipped (listed in ``meta["notes"]``), e.g. to read a few columns of a big table.

    Returns
    -------
    raw : DataFrame
        Long layout: columns ``time`` (tz-aware), ``sensor`` (category), ``value`` [canonical
        unit], sorted by sensor then time, indexed by the 1-based line number in the file
        (``line``). Wide layout: tz-aware DatetimeIndex ``time``, one float column per sensor
        (NaN = no report). Either can be passed to :func:`resample_measurements`. ``raw.attrs
        ["measurements"]`` holds ``meta``.
    meta : dict
        ``source``, ``layout``, ``sensors``, ``units`` (canonical, per sensor),
        ``units_in_file``, ``quantities``, ``conversions`` (per sensor, e.g. "K -> C (detected
        ...)"), ``notes`` (everything assumed or changed), ``n_reports`` (per sensor), ``tz``,
        ``rows`` and ``interval`` (Timedelta, or None for reports).

    Raises
    ------
    ThermocalInputError
        Missing file or columns, unreadable times or values, duplicated or decreasing
        timestamps, unknown or missing sensors, unknown or ambiguous units; the message names
        the file, the column and the 1-based line.
    """
    path = Path(path)
    source = str(path)
    if not path.is_file():
        raise ThermocalInputError(f"measurement file {path} does not exist")
    if layout not in ("auto", "long", "wide"):
        raise ThermocalInputError(f"layout = {layout!r}; use 'auto', 'long' or 'wide'")
    if duplicates not in ("error", "first", "last"):
        raise ThermocalInputError(f"duplicates = {duplicates!r}; use 'error', 'first' or 'last'")
    if rows not in ("reports", "interval_start", "interval_end"):
        raise ThermocalInputError(
            f"rows = {rows!r}; use 'reports', 'interval_start' or 'interval_end'"
        )
    interval_td = _as_timedelta(interval, "interval")
    if interval_td is not None and rows == "reports":
        raise ThermocalInputError(
            "interval= describes logs of interval means: pass rows='interval_start' or "
            "'interval_end' with it"
        )
    if path.suffix.lower() in (".parquet", ".pq"):
        frame = _read_parquet_table(path)
        lines = np.arange(1, len(frame) + 1, dtype=np.int64)
        source = f"{path} (parquet; line = table row)"
    else:
        frame = _read_csv_table(path, sep=sep, decimal=decimal, comment=comment)
        lines = _line_numbers(path, len(frame), comment)
    notes: list[str] = []

    time_col = _find_time_column(frame.columns, time_column, source, notes)
    columns_folded = {c.casefold(): c for c in frame.columns}
    is_long = sensor_column.casefold() in columns_folded and (
        value_column.casefold() in columns_folded
    )
    if layout == "long" and not is_long:
        missing = [c for c in (sensor_column, value_column) if c.casefold() not in columns_folded]
        raise ThermocalInputError(
            f"{source}: layout 'long' needs columns '{sensor_column}' and '{value_column}'; "
            f"missing {missing} (columns: {list(frame.columns)}); pass sensor_column= / "
            f"value_column="
        )
    long_layout = layout == "long" or (layout == "auto" and is_long)
    if unknown_sensors not in ("error", "ignore"):
        raise ThermocalInputError(f"unknown_sensors = {unknown_sensors!r}; use 'error' or 'ignore'")
    if unknown_sensors == "ignore" and sensors is not None:
        wanted = {sensors} if isinstance(sensors, str) else set(sensors)
        if long_layout:
            names = frame[columns_folded[sensor_column.casefold()]].astype("string").str.strip()
            keep = names.isin(wanted).to_numpy()
            skipped = sorted(set(names[~keep].dropna()))
            frame, lines = frame[keep].reset_index(drop=True), lines[keep]
        else:
            skipped = [
                c for c in frame.columns if c != time_col and _split_header_unit(c)[0] not in wanted
            ]
            frame = frame.drop(columns=skipped)
        if skipped:
            notes.append(f"sensors not in sensors= skipped: {skipped}")
    times, time_note = parse_time_column(
        frame[time_col],
        source=source,
        column=time_col,
        lines=lines,
        tz=tz,
        time_unit=time_unit,
        start=start,
        time_format=time_format,
    )
    if time_note:
        notes.append(time_note)
    context = dict(
        source=source,
        lines=lines,
        sensors=sensors,
        units=units or {},
        quantities=quantities or {},
        decimal=decimal,
        duplicates=duplicates,
        sort=sort,
        notes=notes,
        time_col=time_col,
    )
    if long_layout:
        raw, meta = _read_long(
            frame,
            times,
            sensor_col=columns_folded[sensor_column.casefold()],
            value_col=columns_folded[value_column.casefold()],
            unit_col=columns_folded.get(unit_column.casefold()),
            **context,
        )
    else:
        raw, meta = _read_wide(frame.drop(columns=[time_col]), times, **context)
    if rows != "reports":
        raw, interval_td = _as_interval_means(raw, rows, interval_td, source, notes)
    meta.update(
        source=str(path),
        tz=str(raw_tz(raw)),
        notes=notes,
        rows="reports" if rows == "reports" else "interval means",
        interval=interval_td,
    )
    raw.attrs["measurements"] = meta
    del frame
    _release_arrow_memory()
    return raw, meta


def _read_csv_table(path: Path, *, sep: str | None, decimal: str, comment: str | None):
    separator = sep or _sniff_separator(path, comment)
    try:
        frame = pd.read_csv(
            path,
            sep=separator,
            decimal=decimal,
            comment=comment,
            na_values=_NA_TOKENS,
            keep_default_na=False,
            skipinitialspace=True,
            encoding="utf-8-sig",
            low_memory=False,
        )
    except (pd.errors.ParserError, UnicodeDecodeError, pd.errors.EmptyDataError) as exc:
        raise ThermocalInputError(f"{path}: cannot read as CSV ({exc})") from None
    frame.columns = [str(c).strip() for c in frame.columns]
    _check_repeated_header(path, frame.columns, separator=separator, comment=comment)
    if frame.empty:
        raise ThermocalInputError(f"{path}: no data rows below the header")
    return frame


#: pandas' name for the n-th repeat of a column name: "S1", "S1.1", "S1.2", ...
_MANGLED_REPEAT = re.compile(r"^(?P<name>.+)\.(?P<count>[1-9]\d*)$")


def _check_repeated_header(
    path: Path, columns: Sequence[str], *, separator: str, comment: str | None
) -> None:
    """Refuse a CSV header that names a column twice, with the name and the column positions.

    pandas renames the repeats ("S1", "S1.1"), so the log would show a sensor "S1.1" that the
    file does not name; the header as written is read again when a column looks renamed so,
    or when two names are the same once stripped ("S1" and "S1 ").

    Parameters
    ----------
    path : Path
        The CSV file.
    columns : sequence of str
        The column names pandas gave (stripped).
    separator : str
        The field separator.
    comment : str or None
        The comment character.

    Raises
    ------
    ThermocalInputError
        Naming the file, the header's line, each repeated name and its 1-based column
        positions.
    """
    names = set(columns)
    renamed = any(
        (match := _MANGLED_REPEAT.match(column)) and match.group("name") in names
        for column in columns
    )
    if not renamed and len(names) == len(columns):
        return
    header = pd.read_csv(
        path,
        sep=separator,
        comment=comment,
        header=None,
        nrows=1,
        dtype=str,
        keep_default_na=False,
        skipinitialspace=True,
        encoding="utf-8-sig",
    )
    written = [str(value).strip() for value in header.iloc[0]]
    positions: dict[str, list[int]] = {}
    for position, name in enumerate(written, start=1):
        positions.setdefault(name, []).append(position)
    # blank header cells (a spreadsheet's trailing empty columns) are not names
    repeated = {name: where for name, where in positions.items() if name and len(where) > 1}
    if not repeated:
        return
    line, _ = _data_line_numbers(path, comment)
    described = "; ".join(
        f"'{name}' in columns {', '.join(map(str, where[:-1]))} and {where[-1]}"
        for name, where in repeated.items()
    )
    raise ThermocalInputError(
        f"{path}, line {line} (header): the same column name twice: {described}; every column "
        "needs its own name (one per sensor): rename or remove the repeats"
    )


def _release_arrow_memory() -> None:
    """Hand the memory Arrow's allocator kept after a parquet read back to the system.

    The file's text columns are Arrow strings (pandas 3) and the allocator keeps the blocks
    they freed for later use; after the identification demo's month-long sensor log (810,893
    rows) that was about 70 MB of the process's memory.
    """
    import pyarrow

    pyarrow.default_memory_pool().release_unused()


def _read_parquet_table(path: Path) -> pd.DataFrame:
    """The table as a frame, its text columns as categories.

    A sensor log's text columns (sensor names, units, sometimes the time) repeat a few values
    over every row: read dictionary-encoded they are codes, not a string per row (on the
    identification demo's 810,893 rows this halves the read's peak memory).
    """
    import pyarrow
    import pyarrow.parquet

    try:
        schema = pyarrow.parquet.read_schema(path)
        text = [
            field.name
            for field in schema
            if pyarrow.types.is_string(field.type) or pyarrow.types.is_large_string(field.type)
        ]
        frame = pyarrow.parquet.read_table(path, read_dictionary=text).to_pandas()
    except Exception as exc:  # noqa: BLE001 - pyarrow raises many types for a bad file
        raise ThermocalInputError(f"{path}: cannot read as parquet ({exc})") from None
    if not isinstance(frame.index, pd.RangeIndex):  # e.g. a DatetimeIndex written by pandas
        frame = frame.reset_index()
    frame.columns = [str(c).strip() for c in frame.columns]
    if frame.empty:
        raise ThermocalInputError(f"{path}: the parquet table has no rows")
    return frame.reset_index(drop=True)


def _as_interval_means(
    raw: pd.DataFrame, rows: str, interval: pd.Timedelta | None, source: str, notes: list[str]
) -> tuple[pd.DataFrame, pd.Timedelta]:
    """Logging interval of a log of interval means; rows labelled by their end are moved back."""
    if interval is None:
        if isinstance(raw.index, pd.DatetimeIndex):
            spacings = [np.diff(raw.index.asi8)]
        else:
            spacings = [np.diff(g.asi8) for _, g in raw.groupby("sensor", observed=True)["time"]]
        medians = [float(np.median(d)) for d in spacings if d.size]
        if not medians:
            raise ThermocalInputError(
                f"{source}: one row per sensor: the logging interval cannot be inferred; "
                "pass interval="
            )
        interval = pd.Timedelta(int(round(float(np.median(medians)))), unit="ns")
        notes.append(f"logging interval {interval} (median spacing of the time stamps)")
    if rows == "interval_end":
        if isinstance(raw.index, pd.DatetimeIndex):
            raw.index = pd.DatetimeIndex(raw.index - interval, name=raw.index.name)
        else:
            raw["time"] = raw["time"] - interval
        notes.append(f"rows labelled by their interval end moved back by {interval}")
    notes.append(f"rows are means over [t, t + {interval}) labelled by their start (rows='{rows}')")
    return raw, interval


def raw_tz(raw: pd.DataFrame):
    """Time zone of a raw measurement frame (long or wide)."""
    if isinstance(raw.index, pd.DatetimeIndex):
        return raw.index.tz
    return raw["time"].dt.tz


def _find_time_column(columns: Sequence[str], wanted: str, source: str, notes: list[str]) -> str:
    if wanted in columns:
        return wanted
    folded = {c.casefold(): c for c in columns}
    if wanted.casefold() in folded:
        return folded[wanted.casefold()]
    names = [_split_header_unit(c)[0].casefold() for c in columns]
    candidates = [columns[i] for i, n in enumerate(names) if n in _TIME_CANDIDATES]
    if len(candidates) == 1:
        notes.append(f"time column '{candidates[0]}' used (no column '{wanted}')")
        return candidates[0]
    raise ThermocalInputError(
        f"{source}: no time column '{wanted}'{_suggest(wanted, list(columns))} (columns: "
        f"{list(columns)}); pass time_column="
    )
