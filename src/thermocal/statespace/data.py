"""Binding a data table to a model: time axis in seconds, input and output matrices, validation."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.statespace.units import time_unit_seconds

#: A temperature column whose median exceeds this [C] is taken for Kelvin by mistake.
KELVIN_SUSPICION_C = 150.0


@dataclass
class PreparedData:
    """Data of one model, ready for the kernels.

    Attributes
    ----------
    index : pandas.Index
        The data's time labels (DatetimeIndex, or numeric times in the given unit).
    seconds : ndarray [s]
        Time of each sample since the first one.
    dts : ndarray [s]
        Interval from each sample to the next (length N - 1; padded with the last interval).
    U : ndarray (N, n_inputs)
        Inputs in the model's input order, in the columns' own units.
    Y : ndarray (N, n_outputs) [C]
        Outputs; NaN = not observed.
    """

    index: pd.Index
    seconds: np.ndarray
    dts: np.ndarray
    U: np.ndarray
    Y: np.ndarray
    time_unit: str = "s"
    #: What was done to the data (e.g. interpolated input gaps), for the report.
    notes: list[str] = field(default_factory=list)

    @property
    def nobs(self) -> int:
        """Number of observed scalar output values."""
        return int(np.isfinite(self.Y).sum())

    @property
    def uniform(self) -> bool:
        """True when all sampling intervals are equal (to 1e-9 relative)."""
        d = self.dts[:-1] if self.dts.size > 1 else self.dts
        return bool(d.size == 0 or np.all(np.abs(d - d[0]) <= 1e-9 * d[0]))


def time_axis(
    data: pd.DataFrame,
    *,
    time_column: str | None = None,
    time_unit: str = "s",
    source: str = "data",
) -> tuple[pd.Index, np.ndarray]:
    """Time labels and seconds since the first sample, validated strictly increasing.

    Parameters
    ----------
    data : DataFrame
        With a DatetimeIndex, or a ``time_column`` (datetimes, or numbers in ``time_unit``), or a
        numeric index in ``time_unit``.
    time_column : str, optional
        Column holding the time.
    time_unit : str
        Unit of numeric times: ``s``, ``min``, ``h``, ``d``.
    source : str
        Name of the data (file), for error messages.

    Returns
    -------
    index : pandas.Index
    seconds : ndarray [s]
    """
    if time_column is not None:
        if time_column not in data.columns:
            raise ThermocalInputError(
                f"{source}: no time column '{time_column}'; columns present: "
                f"{', '.join(map(str, data.columns))}"
            )
        raw = data[time_column]
    else:
        if isinstance(data.index, pd.RangeIndex):
            raise ThermocalInputError(
                f"{source}: the data has no time axis (a plain row-number index); give it a "
                "DatetimeIndex or name the time column (time_column=..., --time-column)"
            )
        raw = data.index.to_series()
    if isinstance(raw.dtype, pd.DatetimeTZDtype) or pd.api.types.is_datetime64_any_dtype(raw):
        index = pd.DatetimeIndex(raw)
        if index.isna().any():
            row = int(np.flatnonzero(index.isna())[0])
            raise ThermocalInputError(f"{source}: time stamp missing in row {row}")
        seconds = (index - index[0]).total_seconds().to_numpy(dtype=float)
    elif pd.api.types.is_numeric_dtype(raw):
        values = raw.to_numpy(dtype=float)
        if not np.all(np.isfinite(values)):
            row = int(np.flatnonzero(~np.isfinite(values))[0])
            raise ThermocalInputError(f"{source}: time value missing or not finite in row {row}")
        index = pd.Index(values, name=time_column or raw.name)
        seconds = (values - values[0]) * time_unit_seconds(time_unit)
    else:
        # ISO 8601 only: a guessed format reads European dates (01.02.2019) month-first
        try:
            try:
                index = pd.DatetimeIndex(pd.to_datetime(raw, format="ISO8601"))
            except ValueError:  # e.g. local times with changing UTC offsets (DST)
                index = pd.DatetimeIndex(pd.to_datetime(raw, format="ISO8601", utc=True))
        except (ValueError, TypeError):
            raise ThermocalInputError(
                f"{source}: time column '{time_column or raw.name}' is neither numeric nor "
                f"ISO 8601 date-time (first value {raw.iloc[0]!r}); write the times as ISO 8601 "
                "(2019-02-01 13:00 or 2019-02-01T13:00+01:00) or give numeric times with "
                "--time-unit"
            ) from None
        seconds = (index - index[0]).total_seconds().to_numpy(dtype=float)
    if seconds.size < 2:
        raise ThermocalInputError(f"{source}: at least two samples are needed, got {seconds.size}")
    step = np.diff(seconds)
    if np.any(step == 0):
        row = int(np.flatnonzero(step == 0)[0]) + 1
        raise ThermocalInputError(
            f"{source}: duplicated time stamp {index[row]} in row {row} (data row, 0-based); "
            "remove or average the duplicates"
        )
    if np.any(step < 0):
        row = int(np.flatnonzero(step < 0)[0]) + 1
        raise ThermocalInputError(
            f"{source}: time stamps are not increasing at row {row} ({index[row - 1]} then "
            f"{index[row]}); sort the data by time"
        )
    return index, seconds


def prepare_data(
    model,
    data: pd.DataFrame,
    *,
    time_column: str | None = None,
    time_unit: str = "s",
    source: str = "data",
    require_outputs: bool = True,
    input_gaps: str = "error",
    max_gap: int = 3,
) -> PreparedData:
    """Validate ``data`` against ``model`` and build the kernel arrays.

    Outputs may contain NaN (those values are skipped by the filter) but must not be all NaN.
    Missing input values (NaN, e.g. values removed by the quality checks of
    :mod:`thermocal.io`) follow ``input_gaps``:

    - ``"error"`` (default): inputs must be complete; the message names the column and row;
    - ``"interpolate"``: gaps of at most ``max_gap`` consecutive samples are interpolated
      linearly in time and listed in ``PreparedData.notes``; longer gaps, and gaps at the start
      or end, are errors naming the period (cut the data there).
    """
    if input_gaps not in ("error", "interpolate"):
        raise ThermocalInputError(
            f"input_gaps must be 'error' or 'interpolate', got {input_gaps!r}"
        )
    notes: list[str] = []
    if not isinstance(data, pd.DataFrame):
        raise ThermocalInputError(
            f"{source}: expected a pandas DataFrame, got {type(data).__name__}"
        )
    index, seconds = time_axis(data, time_column=time_column, time_unit=time_unit, source=source)
    needed = [(c, "boundary temperature [C]") for c in model.boundary_names]
    needed += [(c, "heat input") for c in model.heat_input_names]
    if require_outputs:
        needed += [(c, "output (measured temperature) [C]") for c in model.output_names]
    missing = [(c, role) for c, role in needed if c not in data.columns]
    if missing:
        names = ", ".join(f"'{c}' ({role})" for c, role in missing)
        raise ThermocalInputError(
            f"{source}: model '{model.name}' needs column(s) {names}, not in the data; columns "
            f"present: {', '.join(map(str, data.columns))}. Rename the column or fix the model file"
        )
    U = np.empty((len(data), len(model.input_names)))
    for j, col in enumerate(model.input_names):
        values = pd.to_numeric(data[col], errors="coerce").to_numpy(dtype=float)
        bad = ~np.isfinite(values)
        garbled = bad & data[col].notna().to_numpy() & ~np.isinf(values)
        if bad.any() and input_gaps == "interpolate" and not garbled.any():
            values = _interpolate_gaps(values, seconds, index, col, max_gap, source, notes)
            bad = ~np.isfinite(values)
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            raise ThermocalInputError(
                f"{source}: input column '{col}' has {int(bad.sum())} missing or "
                f"non-numeric value(s), "
                f"first at row {row} ({index[row]}); inputs must be complete: fill the gaps "
                "(e.g. interpolate) or cut the period"
            )
        U[:, j] = values
    temperature_columns = list(model.boundary_names)
    Y = np.full((len(data), len(model.output_names)), np.nan)
    if require_outputs:
        for r, col in enumerate(model.output_names):
            Y[:, r] = pd.to_numeric(data[col], errors="coerce").to_numpy(dtype=float)
            garbled = np.isnan(Y[:, r]) & data[col].notna().to_numpy()
            if garbled.any():
                row = int(np.flatnonzero(garbled)[0])
                raise ThermocalInputError(
                    f"{source}: output column '{col}' has a non-numeric value "
                    f"{data[col].iloc[row]!r} in row {row}; leave missing values empty (NaN)"
                )
            if not np.isfinite(Y[:, r]).any():
                raise ThermocalInputError(
                    f"{source}: output column '{col}' has no valid value (all NaN); "
                    "check the column or the period selected"
                )
        temperature_columns += model.output_names
    for col in temperature_columns:
        values = pd.to_numeric(data[col], errors="coerce")
        if values.median() > KELVIN_SUSPICION_C:
            raise ThermocalInputError(
                f"{source}: temperature column '{col}' has median "
                f"{values.median():.1f}, which looks "
                "like kelvin; temperatures must be in degrees C (subtract 273.15)"
            )
    # intervals rounded to the microsecond: times given as decimal hours (0.0833333...) would
    # otherwise differ in the last bits and defeat the uniform-sampling fast path
    dts = np.round(np.diff(seconds), 6)
    dts = np.append(dts, dts[-1])
    return PreparedData(
        index=index, seconds=seconds, dts=dts, U=U, Y=Y, time_unit=time_unit, notes=notes
    )


def _interpolate_gaps(values, seconds, index, col, max_gap, source, notes) -> np.ndarray:
    """``values`` with interior NaN runs of at most ``max_gap`` samples interpolated linearly
    in time; a longer run or one at either end is an error naming its period."""
    bad = ~np.isfinite(values)
    edges = np.diff(np.concatenate([[0], bad.astype(int), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # [start, end)
    for a, b in zip(starts, ends, strict=True):
        where = f"rows {a} to {b - 1} ({index[a]} to {index[b - 1]})"
        if a == 0 or b == values.size:
            raise ThermocalInputError(
                f"{source}: input column '{col}' is missing at the "
                f"{'start' if a == 0 else 'end'} of the data, {where}: nothing to interpolate "
                "from; cut the period"
            )
        if b - a > max_gap:
            raise ThermocalInputError(
                f"{source}: input column '{col}' is missing for {b - a} consecutive samples, "
                f"{where}, longer than the {max_gap} interpolated (max_gap, --max-gap); cut the "
                "data there and fit the periods separately, or raise max_gap"
            )
    ok = ~bad
    out = values.copy()
    out[bad] = np.interp(seconds[bad], seconds[ok], values[ok])
    notes.append(
        f"input '{col}': {int(bad.sum())} missing value(s) in {starts.size} gap(s) of at most "
        f"{int((ends - starts).max())} sample(s) interpolated linearly"
    )
    return out
