"""The two layouts of a sensor log: long (one report per row) and wide (one column per sensor),
parsed into per-sensor reports with file line numbers.

Part of :mod:`thermocal.io.measurements`; see its docstring for the conventions.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io.decimal_comma import decimal_comma_numbers
from thermocal.io.measurements.units import (
    UNITS,
    _convert_units,
    _resolve_unit,
    _split_header_unit,
    _suggest,
)


def _parse_numbers(
    series: pd.Series, *, source: str, column: str, lines: np.ndarray, decimal: str
) -> np.ndarray:
    """Float values of a column; unparseable entries are errors naming the line."""
    if pd.api.types.is_numeric_dtype(series.dtype) and not pd.api.types.is_bool_dtype(series.dtype):
        return series.to_numpy(dtype=np.float64, na_value=np.nan)
    text = series.astype("string")
    if decimal == ",":
        # a point groups thousands there (7.476 is 7,476, not 7.476); any other is ambiguous
        numbers, ambiguous = decimal_comma_numbers(series)
        if ambiguous.any():
            first = int(np.flatnonzero(ambiguous.to_numpy())[0])
            raise ThermocalInputError(
                f"{source}, column '{column}', line {lines[first]}: {series.iloc[first]!r} has a "
                "decimal point, but the file's decimal mark is ',' (a point is read only as a "
                f"thousands separator, as in 1.203,5); {int(ambiguous.sum())} such value(s) in "
                "this column: write them with a decimal comma"
            )
    else:
        if decimal != ".":
            text = text.str.replace(decimal, ".", regex=False)
        numbers = pd.to_numeric(text, errors="coerce")
    bad = numbers.isna().to_numpy() & text.notna().to_numpy() & (text.str.strip() != "").to_numpy()
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        value = series.iloc[first]
        hint = ""
        if isinstance(value, str) and re.fullmatch(r"\s*-?\d+,\d+\s*", value):
            hint = " (a decimal comma: pass decimal=',')"
        raise ThermocalInputError(
            f"{source}, column '{column}', line {lines[first]}: cannot read {value!r} as a "
            f"number{hint}; {int(bad.sum())} such value(s) in this column. Fix the file, or "
            f"leave the cell empty for a missing value"
        )
    return numbers.to_numpy(dtype=np.float64, na_value=np.nan)


def _check_order(
    times_ns: np.ndarray,
    lines: np.ndarray,
    *,
    source: str,
    column: str,
    what: str,
    duplicates: str,
) -> np.ndarray:
    """Indices to keep (file order); errors on decreasing or (by default) repeated times."""
    step = np.diff(times_ns)
    decreasing = np.flatnonzero(step < 0)
    if decreasing.size:
        i = int(decreasing[0])
        back = times_ns[i] - times_ns[i + 1]
        # a reset: the time jumps back more than a day and runs forward again (a log written
        # newest first goes back at every row, two rows swapped by minutes: sort it)
        rises_again = i + 2 < times_ns.size and times_ns[i + 2] > times_ns[i + 1]
        if rises_again and back > 86_400 * 10**9:
            # a logger whose clock was reset (to 2000-01-01, its battery changed): sorting
            # would move the rows after the reset to the front, under wrong dates
            raise ThermocalInputError(
                f"{source}, column '{column}', line {lines[i + 1]}: the time goes back from "
                f"{pd.Timestamp(times_ns[i], tz='UTC').isoformat()} (line {lines[i]}) to "
                f"{pd.Timestamp(times_ns[i + 1], tz='UTC').isoformat()} (UTC){what}, "
                f"{back / 86_400e9:.1f} days back"
                + (", before the log's first time" if times_ns[i + 1] < times_ns[0] else "")
                + ": the logger's clock was reset there. Correct the times from that line on "
                "(or remove those rows); sorting would put them under wrong dates"
            )
        raise ThermocalInputError(
            f"{source}, column '{column}', line {lines[i + 1]}: time "
            f"{pd.Timestamp(times_ns[i + 1], tz='UTC').isoformat()} (UTC) is earlier than the "
            f"previous one{what} on line {lines[i]} "
            f"({pd.Timestamp(times_ns[i], tz='UTC').isoformat()}); the log must be in time "
            f"order: sort it, or pass sort=True"
        )
    repeated = np.flatnonzero(step == 0)
    keep = np.ones(times_ns.size, dtype=bool)
    if repeated.size:
        if duplicates == "error":
            i = int(repeated[0])
            raise ThermocalInputError(
                f"{source}, column '{column}', line {lines[i + 1]}: duplicated time "
                f"{pd.Timestamp(times_ns[i], tz='UTC').isoformat()} (UTC){what}, already on "
                f"line {lines[i]} ({repeated.size} duplicate(s)); remove them, or pass "
                f"duplicates='first' or 'last'"
            )
        if duplicates == "first":
            keep[repeated + 1] = False
        else:
            keep[repeated] = False
    return keep


def _rename_map(
    names: Sequence[str],
    sensors: Sequence[str] | Mapping[str, str] | None,
    *,
    source: str,
    column: str,
    first_line: Mapping[str, int] | None,
) -> dict[str, str]:
    """File name -> thermocal name; unknown and missing sensors are errors."""
    if sensors is None:
        return {name: name for name in names}
    if isinstance(sensors, str):
        sensors = [sensors]
    mapping = dict(sensors) if isinstance(sensors, Mapping) else {s: s for s in sensors}
    unknown = [name for name in names if name not in mapping]
    if unknown:
        name = unknown[0]
        line = f", line {first_line[name]}" if first_line else ", line 1 (header)"
        raise ThermocalInputError(
            f"{source}, column '{column}'{line}: unknown sensor '{name}'"
            f"{_suggest(name, list(mapping))} ({len(unknown)} unknown: {unknown[:10]}); expected "
            f"sensors: {list(mapping)}. Add it to sensors= or fix the name"
        )
    missing = [name for name in mapping if name not in set(names)]
    if missing:
        raise ThermocalInputError(
            f"{source}: expected sensor(s) {missing} not found in column '{column}'"
            f"{_suggest(missing[0], list(names))}"
        )
    targets = list(mapping.values())
    clash = {t for t in targets if targets.count(t) > 1}
    if clash:
        raise ThermocalInputError(f"sensors=: several file names map to {sorted(clash)}")
    return mapping


def _lookup(mapping: Mapping[str, Any], file_name: str, name: str) -> Any:
    if name in mapping:
        return mapping[name]
    return mapping.get(file_name)


def _read_long(
    frame: pd.DataFrame,
    times: pd.DatetimeIndex,
    *,
    sensor_col: str,
    value_col: str,
    unit_col: str | None,
    source: str,
    lines: np.ndarray,
    sensors,
    units,
    quantities,
    decimal,
    duplicates,
    sort,
    notes,
    time_col,
) -> tuple[pd.DataFrame, dict]:
    codes, raw_names = pd.factorize(frame[sensor_col], sort=False)
    stripped = [str(n).strip() for n in raw_names]
    position = {name: i for i, name in enumerate(dict.fromkeys(stripped))}
    names = list(position)  # names equal after stripping blanks are merged
    remap = np.asarray([position[n] for n in stripped] + [-1], dtype=np.int64)
    codes = remap[codes]  # code -1 (missing) stays -1
    empty = [position[""]] if "" in position else []
    missing_sensor = (codes < 0) | np.isin(codes, empty)
    if missing_sensor.any():
        first = int(np.flatnonzero(missing_sensor)[0])
        raise ThermocalInputError(
            f"{source}, column '{sensor_col}', line {lines[first]}: missing sensor name"
        )
    first_rows = np.full(len(names), -1, dtype=np.int64)
    order_first = np.unique(codes, return_index=True)
    first_rows[order_first[0]] = order_first[1]
    first_line = {names[c]: int(lines[first_rows[c]]) for c in range(len(names))}
    rename = _rename_map(names, sensors, source=source, column=sensor_col, first_line=first_line)
    values = _parse_numbers(
        frame[value_col], source=source, column=value_col, lines=lines, decimal=decimal
    )
    times_ns = times.asi8
    # per-sensor order: stable sort by sensor keeps file order within each sensor
    order = np.argsort(codes, kind="stable")
    codes_sorted = codes[order]
    if sort:
        order = np.lexsort((times_ns, codes))
        if not np.array_equal(order, np.argsort(codes, kind="stable")):
            notes.append("rows out of time order were sorted (sort=True)")
        codes_sorted = codes[order]
    bounds = np.flatnonzero(np.diff(codes_sorted)) + 1
    starts = np.concatenate(([0], bounds))
    ends = np.concatenate((bounds, [len(order)]))

    unit_codes, unit_names = None, None
    if unit_col is not None:  # codes and their stripped names: no text column per row
        unit_codes, found = pd.factorize(frame[unit_col], sort=False)
        unit_names = np.asarray([str(u).strip() for u in found] + [""], dtype=object)
        unit_codes = np.where(unit_codes < 0, len(found), unit_codes)

    keep_sorted = np.ones(len(order), dtype=bool)
    out_values = values[order]
    meta_units, meta_file_units, meta_quantities, conversions, n_reports = {}, {}, {}, {}, {}
    for begin, end in zip(starts, ends, strict=True):
        rows = order[begin:end]
        file_name = names[codes_sorted[begin]]
        name = rename[file_name]
        keep = _check_order(
            times_ns[rows],
            lines[rows],
            source=source,
            column=time_col,
            what=f" of sensor '{file_name}'",
            duplicates=duplicates,
        )
        keep_sorted[begin:end] = keep
        unit = _lookup(units, file_name, name)
        if unit_codes is not None:
            declared = [
                u for u in dict.fromkeys(unit_names[pd.unique(unit_codes[rows])]) if u
            ]
            if len(declared) > 1:
                sensor_units = unit_names[unit_codes[rows]]
                position = int(
                    np.flatnonzero((sensor_units != declared[0]) & (sensor_units != ""))[0]
                )
                raise ThermocalInputError(
                    f"{source}, column '{unit_col}', line {lines[rows[position]]}: sensor "
                    f"'{file_name}' changes unit from '{declared[0]}' to "
                    f"'{sensor_units[position]}'; one unit per sensor"
                )
            if declared:
                if unit is not None and _resolve_unit(unit, source) != _resolve_unit(
                    declared[0], source
                ):
                    raise ThermocalInputError(
                        f"{source}: sensor '{file_name}' has unit '{declared[0]}' in column "
                        f"'{unit_col}' but units= says '{unit}'"
                    )
                unit = declared[0]
        converted, quantity, canonical, note = _convert_units(
            name,
            out_values[begin:end],
            unit=unit,
            quantity=_lookup(quantities, file_name, name),
            source=source,
            column_label=f"{value_col}' of sensor '{file_name}",
            lines=lines[rows],
        )
        out_values[begin:end] = converted
        meta_units[name] = canonical
        meta_file_units[name] = unit
        meta_quantities[name] = quantity
        if note:
            conversions[name] = note
        n_reports[name] = int(keep.sum())
    if not keep_sorted.all():
        notes.append(
            f"{int((~keep_sorted).sum())} duplicated report(s) dropped (duplicates='{duplicates}')"
        )
    order = order[keep_sorted]
    categories = list(dict.fromkeys(rename[n] for n in names))
    category_of = {name: i for i, name in enumerate(categories)}
    sensor_names = pd.Categorical.from_codes(
        np.asarray([category_of[rename[n]] for n in names])[codes[order]],
        categories=categories,
    )
    raw = pd.DataFrame(
        {
            "time": times[order],
            "sensor": sensor_names,
            "value": out_values[keep_sorted],
        },
        index=pd.Index(lines[order], name="line"),
    )
    meta = {
        "layout": "long",
        "sensors": categories,
        "units": meta_units,
        "units_in_file": meta_file_units,
        "quantities": meta_quantities,
        "conversions": conversions,
        "n_reports": n_reports,
    }
    return raw, meta


def _read_wide(
    frame: pd.DataFrame,
    times: pd.DatetimeIndex,
    *,
    source: str,
    lines: np.ndarray,
    sensors,
    units,
    quantities,
    decimal,
    duplicates,
    sort,
    notes,
    time_col,
) -> tuple[pd.DataFrame, dict]:
    if frame.shape[1] == 0:
        raise ThermocalInputError(f"{source}: no sensor columns besides '{time_col}'")
    header = {column: _split_header_unit(column) for column in frame.columns}
    file_names = [header[c][0] for c in frame.columns]
    repeated = {n for n in file_names if file_names.count(n) > 1}
    if repeated:
        raise ThermocalInputError(
            f"{source}, line 1 (header): repeated column(s) {sorted(repeated)}"
        )
    rename = _rename_map(file_names, sensors, source=source, column="(header)", first_line=None)
    times_ns = times.asi8
    order = np.arange(len(times_ns))
    if sort and np.any(np.diff(times_ns) < 0):
        order = np.argsort(times_ns, kind="stable")
        notes.append("rows out of time order were sorted (sort=True)")
    keep = _check_order(
        times_ns[order],
        lines[order],
        source=source,
        column=time_col,
        what="",
        duplicates=duplicates,
    )
    rows = order[keep]
    data: dict[str, np.ndarray] = {}
    meta_units, meta_file_units, meta_quantities, conversions, n_reports = {}, {}, {}, {}, {}
    for column in frame.columns:
        file_name, header_unit = header[column]
        name = rename[file_name]
        values = _parse_numbers(
            frame[column], source=source, column=column, lines=lines, decimal=decimal
        )[rows]
        unit = _lookup(units, file_name, name)
        if header_unit is not None:
            # the same unit under another name ('°C' and 'C', 'W/m²' and 'W/m2') agrees
            if unit is not None and UNITS[_resolve_unit(unit, source)] != UNITS[
                _resolve_unit(header_unit, f"{source}, column '{column}'")
            ]:
                raise ThermocalInputError(
                    f"{source}, column '{column}': the header declares '{header_unit}' but "
                    f"the unit given for it (the configuration, or units=) is '{unit}'"
                )
            unit = header_unit
        converted, quantity, canonical, note = _convert_units(
            name,
            values,
            unit=unit,
            quantity=_lookup(quantities, file_name, name),
            source=source,
            column_label=column,
            lines=lines[rows],
        )
        data[name] = converted
        meta_units[name] = canonical
        meta_file_units[name] = unit
        meta_quantities[name] = quantity
        if note:
            conversions[name] = note
        n_reports[name] = int(np.isfinite(converted).sum())
    if not keep.all():
        notes.append(f"{int((~keep).sum())} duplicated row(s) dropped (duplicates='{duplicates}')")
    raw = pd.DataFrame(data, index=pd.DatetimeIndex(times[rows], name="time"))
    meta = {
        "layout": "wide",
        "sensors": list(data),
        "units": meta_units,
        "units_in_file": meta_file_units,
        "quantities": meta_quantities,
        "conversions": conversions,
        "n_reports": n_reports,
    }
    return raw, meta
