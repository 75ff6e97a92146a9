"""Binding a data table to a model: time axis in seconds, input and output matrices, validation."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.statespace.units import time_unit_seconds

#: A temperature column whose median exceeds this [C] is taken for Kelvin by mistake.
KELVIN_SUSPICION_C = 150.0
#: An indoor (output) temperature whose median exceeds this [C] is taken for Fahrenheit by
#: mistake: no heated room has a median above 45 C, while rooms at 60-80 F (16-27 C) read as
#: such. Applied to the outputs of the room's state only (:func:`indoor_outputs`): a boundary
#: or another state's output (a heating circuit's supply water, a radiator) may be that hot.
FAHRENHEIT_SUSPICION_C = 45.0


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
    #: The data column the times were read from (None: the index), the default of the
    #: results' methods on other data.
    time_column: str | None = None
    #: What was done to the data (e.g. interpolated input gaps), for the report.
    notes: list[str] = field(default_factory=list)
    #: First sample of each period after the first when the likelihood is split at long gaps
    #: (``input_gaps="split"``); empty for one contiguous period.
    segments: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))

    @property
    def n_periods(self) -> int:
        """Number of contiguous periods with their own initial states."""
        return int(self.segments.size) + 1

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

    Text that is neither numeric nor ISO 8601 is refused with the remedy its content suggests
    (:func:`time_text_hint`: ``--time-format`` for day-first dates, ``--decimal`` or ``--sep``
    for commas); numeric times whose median interval is implausible in ``time_unit`` are
    refused too (:func:`check_sampling_interval`: hours read as seconds).

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
            hint = time_text_hint(raw)
            raise ThermocalInputError(
                f"{source}: time column '{time_column or raw.name}' is neither numeric nor "
                f"ISO 8601 date-time (first value {raw.iloc[0]!r}); "
                + (hint or "write the times as ISO 8601 (2019-02-01 13:00 or "
                   "2019-02-01T13:00+01:00) or give numeric times with --time-unit")
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
    if not isinstance(index, pd.DatetimeIndex):  # date-times carry their unit
        check_sampling_interval(
            seconds, time_column=str(time_column or raw.name or "index"), time_unit=time_unit,
            source=source,
        )  # fmt: skip
    return index, seconds


#: Median sampling interval of building data [s]: from a second to a day. Outside, the numbers
#: of a numeric time axis are in another unit (hours read as seconds: 5-minute data become
#: 0.083-second steps).
PLAUSIBLE_SAMPLING_S = (1.0, 86400.0)
#: The unit to suggest for numeric times whose interval is implausible in ``time_unit``.
_TIME_UNIT_HINT = {"s": "h", "min": "h", "h": "s", "d": "h"}


def check_sampling_interval(
    seconds: np.ndarray, *, time_column: str, time_unit: str, source: str = "data",
    numeric: bool = True,
) -> None:  # fmt: skip
    """Refuse a median sampling interval implausible for building data.

    Parameters
    ----------
    seconds : ndarray [s]
        Strictly increasing sample times as read in ``time_unit``.
    time_column : str
        Name of the time column (or index), for the message.
    time_unit : str
        Unit the times were read in (``s``, ``min``, ``h``, ``d``).
    source : str
        Name of the data (file), for the message.
    numeric : bool
        The times are numbers in ``time_unit`` (the remedy is their unit); False: date-times
        (the remedy is finer data).

    Raises
    ------
    ThermocalInputError
        When the median interval lies outside :data:`PLAUSIBLE_SAMPLING_S` (under a second or
        over a day): the message names the interval and the unit to give.
    """
    step = float(np.median(np.diff(seconds))) if len(seconds) > 1 else 0.0
    lo, hi = PLAUSIBLE_SAMPLING_S
    if not (0 < step < lo or step > hi):
        return
    hint = _TIME_UNIT_HINT.get(time_unit, "h")
    shown = f"{step:.3g} s" if step < 60 else f"{step / 3600:.3g} h"
    if not numeric:
        raise ThermocalInputError(
            f"{source}: the median sampling interval of '{time_column}' is {shown}, "
            "implausible for building data (under a second or over a day); give data sampled "
            "every few minutes to an hour (resample to hourly means)"
        )
    raise ThermocalInputError(
        f"{source}: the median sampling interval of '{time_column}' is {shown} when read with "
        f"--time-unit {time_unit} (time_unit='{time_unit}'), implausible for building data "
        f"(under a second or over a day); give the unit of the numbers, e.g. --time-unit "
        f"{hint} (time_unit='{hint}')"
    )


#: Dates written day or month first: day/month, separator, month/day, year, optional time.
_DMY = r"(\d{1,2})([./-])(\d{1,2})\2(\d{2}|\d{4})(?:[ T](\d{1,2}:\d{2})(:\d{2})?)?"


def time_text_hint(raw: pd.Series) -> str | None:
    """What to do about time stamps that are neither numeric nor ISO 8601, from their text.

    - numbers with decimal commas (``0,0833``): the file's decimal mark (``--decimal ','``);
    - numbers stored as text (a file with decimal points read with ``--decimal ','``);
    - other values containing a comma: the separator (``--sep``);
    - dates written day or month first (``05/02/2009 14:26``, ``05.02.2009``): the
      ``--time-format`` that reads them (day first when a first field exceeds 12 or the
      separator is a dot, month first when a second field does).

    Parameters
    ----------
    raw : Series
        The time column as read (text).

    Returns
    -------
    str or None
        The remedy, naming the option and an example value; None when none applies.
    """
    text = raw.dropna().astype(str).str.strip()
    text = text[text != ""]
    if text.empty:
        return None
    sample = text.iloc[:500]
    if sample.str.fullmatch(r"[-+]?\d+,\d*").mean() > 0.5:
        example = sample[sample.str.contains(",")].iloc[0]
        return (
            f"the times are numbers with a decimal comma ({example!r}): read the file with "
            "--decimal ',' (pandas: read_csv(..., decimal=','))"
        )
    if pd.to_numeric(sample, errors="coerce").notna().all():
        example = sample[sample.str.contains(r"\.")]
        shown = f" ({example.iloc[0]!r})" if len(example) else ""
        return (
            f"the times are numbers stored as text{shown}: a file with decimal points read "
            "with --decimal ',' keeps them as text; leave out --decimal ',' (or convert the "
            "column with pandas.to_numeric) and give their unit with --time-unit"
        )
    if sample.str.contains(",").mean() > 0.5:
        return (
            f"the values contain commas ({sample.iloc[0]!r}): is the separator right? give "
            "it with --sep (e.g. --sep ',' or --sep ';')"
        )
    parts = sample.str.extract(rf"^{_DMY}$")
    if parts[0].notna().mean() > 0.9:
        return _date_format_hint(parts, sample[parts[0].notna().to_numpy()])
    return None


def _date_format_hint(parts: pd.DataFrame, text: pd.Series) -> str:
    """The ``--time-format`` for the dates ``text`` matched by :data:`_DMY` (``parts``: its
    groups); when every field fits both orders, the order that reads them as a regular axis."""
    example = text.iloc[0]
    first = pd.to_numeric(parts[0], errors="coerce")
    second = pd.to_numeric(parts[2], errors="coerce")
    sep = parts[1].dropna().iloc[0]
    year = "%Y" if parts[3].dropna().str.len().iloc[0] == 4 else "%y"
    clock = ""
    if parts[4].notna().any():
        clock = " %H:%M" + (":%S" if parts[5].notna().any() else "")
    day_first = f"%d{sep}%m{sep}{year}{clock}"
    month_first = f"%m{sep}%d{sep}{year}{clock}"
    if (second > 12).any() and not (first > 12).any():
        return _format_remedy("month first", month_first, example)
    if (first > 12).any() or sep == ".":
        return _format_remedy("day first", day_first, example)
    regular = {fmt: _regularity(text, fmt) for fmt in (day_first, month_first)}
    if regular[day_first] < regular[month_first]:
        return _format_remedy("day first", day_first, example)
    if regular[month_first] < regular[day_first]:
        return _format_remedy("month first", month_first, example)
    return (
        f"the dates are written day or month first ({example!r}): give --time-format "
        f"'{day_first}' (day first) or '{month_first}' (month first), or write the times as "
        "ISO 8601 (2009-02-05 14:26)"
    )


def _regularity(text: pd.Series, fmt: str) -> float:
    """How irregular the times ``text`` read with ``fmt`` are: the largest step over the
    median step [-] (inf when they do not parse or do not increase). Read in the wrong order,
    dates within one month jump by months at each new day."""
    times = pd.to_datetime(text, format=fmt, errors="coerce")
    if times.isna().any() or len(times) < 3:
        return math.inf
    step = np.diff(times.to_numpy().astype("datetime64[s]").astype(np.int64)).astype(float)
    if not np.all(step > 0):
        return math.inf
    return float(step.max() / np.median(step))


def _format_remedy(order: str, fmt: str, example: str) -> str:
    """The remedy for dates written ``order`` ("day first"), readable with ``fmt``."""
    try:
        iso = f", {example!r} is {pd.to_datetime(example, format=fmt):%Y-%m-%d %H:%M}"
    except (ValueError, TypeError):
        iso = ""
    return (
        f"the dates are written {order} ({example!r}): give --time-format '{fmt}' (pandas: "
        f"to_datetime(..., format='{fmt}')), or write the times as ISO 8601{iso}"
    )


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
      or end, are errors naming the period (cut the data there);
    - ``"split"``: short gaps interpolated as above; the rows of a longer gap are left out and
      the likelihood is split there into contiguous periods, each with its own initial states
      (:meth:`RCModel.with_periods`, done by ``fit``); gaps at the start or end are trimmed; a
      jump of the time axis missing more than ``max_gap`` samples (rows missing altogether,
      :func:`time_axis_jumps`) splits as well. Everything is listed in ``PreparedData.notes``.
      Missing outputs never split: the filter skips them exactly.

    A jump of the time axis is a gap of the samples it misses: with ``"error"`` and
    ``"interpolate"`` one missing more than ``max_gap`` samples is an error naming the rows
    (the filter would hold the inputs across it), shorter ones are bridged and noted.
    Temperatures whose median looks like kelvin or Fahrenheit (:func:`temperature_unit_slip`)
    are errors naming the column.

    Column names: the model's ``columns`` mapping (``{model name: data name}``, the model
    file's ``columns:`` section) renames the data's columns first.
    """
    if input_gaps not in ("error", "interpolate", "split"):
        raise ThermocalInputError(
            f"input_gaps must be 'error', 'interpolate' or 'split', got {input_gaps!r}"
        )
    if isinstance(data, pd.DataFrame) and model.columns:
        data = _apply_column_mapping(model, data, source)
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
    drop = np.zeros(len(data), dtype=bool)  # rows of long input gaps (input_gaps="split")
    for j, col in enumerate(model.input_names):
        values = pd.to_numeric(data[col], errors="coerce").to_numpy(dtype=float)
        bad = ~np.isfinite(values)
        garbled = bad & data[col].notna().to_numpy() & ~np.isinf(values)
        if bad.any() and input_gaps != "error" and not garbled.any():
            values, long_rows = _interpolate_gaps(
                values, seconds, index, col, max_gap, source, notes, split=input_gaps == "split"
            )
            drop |= long_rows
            bad = ~np.isfinite(values) & ~long_rows
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
            infinite = np.isinf(Y[:, r])
            if infinite.any():
                row = int(np.flatnonzero(infinite)[0])
                raise ThermocalInputError(
                    f"{source}: output column '{col}' is infinite in row {row} ({index[row]}); "
                    "leave missing values empty (NaN)"
                )
            if not np.isfinite(Y[:, r]).any():
                raise ThermocalInputError(
                    f"{source}: output column '{col}' has no valid value (all NaN); "
                    "check the column or the period selected"
                )
        temperature_columns += model.output_names
    indoor = indoor_outputs(model)
    for col in temperature_columns:
        median = float(pd.to_numeric(data[col], errors="coerce").median())
        slip = temperature_unit_slip(median)
        boundary = col in model.boundary_names
        if slip == "Fahrenheit" and col not in indoor:
            # a boundary or another state's output may be hot for real (a heating circuit's
            # supply water, a radiator): only kelvin there
            slip = None
        if slip is not None:
            limit = KELVIN_SUSPICION_C if slip == "kelvin" else FAHRENHEIT_SUSPICION_C
            raise ThermocalInputError(
                f"{source}: {'boundary' if boundary else 'indoor (output)'} temperature column "
                f"'{col}' has median {median:.1f}, which looks like {slip} "
                f"({celsius(median, slip):.1f} C): no "
                f"{'outdoor air or adjacent space' if boundary else 'heated room'} has a median "
                f"above {limit:g} C; temperatures must be in degrees C: {_CONVERSIONS[slip]}"
            )
    jump_rows, jump_missing = time_axis_jumps(seconds)
    if jump_rows.size:
        # a simulation of given inputs (no outputs to fit) holds them over any jump, noted
        bridge = max_gap if require_outputs else int(jump_missing.max())
        long = np.flatnonzero(jump_missing > bridge)
        if long.size and input_gaps != "split":  # "split" splits there (_split_periods)
            k, missing = int(jump_rows[long[0]]), int(jump_missing[long[0]])
            raise ThermocalInputError(
                f"{source}: the time axis jumps from {index[k - 1]} to {index[k]} (rows {k - 1} "
                f"and {k}): {missing} sample(s) of the median interval "
                f"({float(np.median(np.diff(seconds))):g} s) are missing there, more than the "
                f"{max_gap} bridged (max_gap, --max-gap); split the likelihood there "
                "(input_gaps='split', --gaps split: each period gets its own initial states), "
                "cut the data, or raise max_gap"
            )
        bridged = jump_missing[jump_missing <= bridge]
        if bridged.size:
            notes.append(
                f"time axis: {bridged.size} jump(s) of at most {int(bridged.max())} missing "
                "sample(s) bridged (the inputs held over them)"
            )
    # intervals rounded to the microsecond: times given as decimal hours (0.0833333...) would
    # otherwise differ in the last bits and defeat the uniform-sampling fast path
    segments = np.zeros(0, dtype=np.int64)
    if input_gaps == "split":
        index, seconds, U, Y, segments = _split_periods(
            index, seconds, U, Y, drop, max_gap, source, notes
        )
    dts = np.round(np.diff(seconds), 6)
    dts = np.append(dts, dts[-1])
    if segments.size:
        # the step into a new period is never propagated (the state restarts): give it the
        # common interval so uniform sampling keeps its single discretisation
        regular = float(np.median(dts))
        dts[segments - 1] = regular
    return PreparedData(
        index=index, seconds=seconds, dts=dts, U=U, Y=Y, time_unit=time_unit,
        time_column=time_column, notes=notes, segments=segments,
    )  # fmt: skip


#: Conversion to degrees C of a temperature slip (:func:`temperature_unit_slip`).
_CONVERSIONS = {"kelvin": "subtract 273.15", "Fahrenheit": "convert with (F - 32) x 5/9"}


def indoor_outputs(model) -> set[str]:
    """The output columns that observe the room: the model's heat-loss state alone
    (:meth:`RCModel.heat_loss_state`); empty when the model has none.

    Parameters
    ----------
    model : RCModel

    Returns
    -------
    set of str
        Data columns of those outputs.
    """
    state = model.heat_loss_state()
    if state is None:
        return set()
    st = model.structure()
    k = model.state_names.index(state)
    return {
        col for r, col in enumerate(model.output_names)
        if np.flatnonzero(st.C[r]).tolist() == [k] and st.C[r, k] == 1.0
    }  # fmt: skip


def temperature_unit_slip(median: float) -> str | None:
    """The unit a temperature column was probably written in instead of degrees C.

    Parameters
    ----------
    median : float [C as read]
        Median of an indoor (output) or boundary temperature column.

    Returns
    -------
    str or None
        ``"kelvin"`` above :data:`KELVIN_SUSPICION_C`, ``"Fahrenheit"`` above
        :data:`FAHRENHEIT_SUSPICION_C`, None for a plausible temperature in C (or NaN).
    """
    if median > KELVIN_SUSPICION_C:
        return "kelvin"
    if median > FAHRENHEIT_SUSPICION_C:
        return "Fahrenheit"
    return None


def celsius(value: float, unit: str) -> float:
    """``value`` [``unit``: ``"kelvin"`` or ``"Fahrenheit"``] in degrees C."""
    return value - 273.15 if unit == "kelvin" else (value - 32.0) * 5.0 / 9.0


def time_axis_jumps(seconds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Jumps of the time axis: rows missing altogether.

    A step longer than the median interval by more than half an interval misses
    ``round(step / median) - 1`` samples (rounded half up), a gap of that length as if the rows
    were there with empty cells.

    Parameters
    ----------
    seconds : ndarray [s]
        Strictly increasing sample times.

    Returns
    -------
    (rows, missing)
        The first row after each jump and the number of samples missing before it.
    """
    step = np.diff(np.asarray(seconds, dtype=float))
    if step.size == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    missing = np.floor(step / np.median(step) + 0.5).astype(np.int64) - 1
    at = np.flatnonzero(missing >= 1)
    return at + 1, missing[at]


def _apply_column_mapping(model, data: pd.DataFrame, source: str) -> pd.DataFrame:
    """``data`` with its columns renamed by the model's ``columns`` mapping (model <- data)."""
    model.check_columns()
    renames = {}
    for name, data_name in model.columns.items():
        if data_name == name:
            continue
        if data_name not in data.columns:
            if name in data.columns:
                continue  # already renamed (e.g. by --map)
            raise ThermocalInputError(
                f"{source}: the model file maps '{name}' to data column '{data_name}' "
                f"(columns:), which is not in the data; columns present: "
                f"{', '.join(map(str, data.columns))}"
            )
        if name in data.columns:
            raise ThermocalInputError(
                f"{source}: the model file maps '{name}' to data column '{data_name}' "
                f"(columns:), but the data has a column '{name}' as well; remove the mapping "
                "or rename one of the columns"
            )
        renames[data_name] = name
    return data.rename(columns=renames) if renames else data


#: A period shorter than this many samples is left out of a split likelihood.
MIN_PERIOD_SAMPLES = 2


def _split_periods(index, seconds, U, Y, drop, max_gap, source, notes):
    """Leave out the rows of long input gaps and split the rest into contiguous periods.

    Returns the kept ``index, seconds, U, Y`` and the first sample of each later period.
    A jump of the time axis missing more than ``max_gap`` samples (:func:`time_axis_jumps`)
    splits too.
    """
    n = len(seconds)
    keep = ~drop
    # period labels: a new period after every dropped run and every long time jump
    boundary = np.zeros(n, dtype=bool)
    rows, missing = time_axis_jumps(seconds)
    jumps = rows[missing > max_gap]
    boundary[jumps] = True
    boundary[1:] |= drop[:-1] & keep[1:]
    period = np.cumsum(boundary & keep)
    kept_rows = np.flatnonzero(keep)
    if kept_rows.size == 0:
        raise ThermocalInputError(f"{source}: no row has all inputs; nothing to fit")
    labels = period[kept_rows]
    starts_in_kept = np.flatnonzero(np.diff(labels) != 0) + 1
    bounds = np.concatenate([[0], starts_in_kept, [kept_rows.size]])
    pieces, described, left_out = [], [], []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        rows = kept_rows[a:b]
        if rows.size < MIN_PERIOD_SAMPLES or not np.isfinite(Y[rows]).any():
            left_out.append(f"{index[rows[0]]} ({rows.size} sample(s), no use)")
            continue
        pieces.append(rows)
        described.append(f"{index[rows[0]]} to {index[rows[-1]]} ({rows.size} samples)")
    if not pieces:
        raise ThermocalInputError(
            f"{source}: after leaving out the long input gaps no period of at least "
            f"{MIN_PERIOD_SAMPLES} samples with observations is left"
        )
    rows = np.concatenate(pieces)
    segments = np.cumsum([p.size for p in pieces])[:-1].astype(np.int64)
    n_dropped = int(drop.sum())
    if n_dropped or segments.size or left_out:
        notes.append(
            f"likelihood split into {len(pieces)} period(s) with their own initial states "
            f"({n_dropped} row(s) with long input gaps left out"
            + (f", {jumps.size} jump(s) of the time axis" if jumps.size else "")
            + "): "
            + "; ".join(described)
            + (f"; left out: {'; '.join(left_out)}" if left_out else "")
        )
    seconds = seconds[rows] - seconds[rows[0]]
    return index[rows], seconds, U[rows], Y[rows], segments


def _interpolate_gaps(values, seconds, index, col, max_gap, source, notes, split=False):
    """``values`` with interior NaN runs of at most ``max_gap`` samples interpolated linearly
    in time, and the mask of rows left for a split (longer runs and runs at either end, with
    ``split``; without, such a run is an error naming its period)."""
    bad = ~np.isfinite(values)
    edges = np.diff(np.concatenate([[0], bad.astype(int), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # [start, end)
    long_rows = np.zeros(values.size, dtype=bool)
    short = np.zeros(values.size, dtype=bool)
    for a, b in zip(starts, ends, strict=True):
        where = f"rows {a} to {b - 1} ({index[a]} to {index[b - 1]})"
        if split and (a == 0 or b == values.size or b - a > max_gap):
            long_rows[a:b] = True
            continue
        short[a:b] = True
        if a == 0 or b == values.size:
            raise ThermocalInputError(
                f"{source}: input column '{col}' is missing at the "
                f"{'start' if a == 0 else 'end'} of the data, {where}: nothing to interpolate "
                "from; cut the period (input_gaps='split', --gaps split, trims it)"
            )
        if b - a > max_gap:
            raise ThermocalInputError(
                f"{source}: input column '{col}' is missing for {b - a} consecutive samples, "
                f"{where}, longer than the {max_gap} interpolated (max_gap, --max-gap); split the "
                "likelihood there (input_gaps='split', --gaps split: each period gets its own "
                "initial states), cut the data, or raise max_gap"
            )
    ok = ~bad
    out = values.copy()
    if short.any():
        out[short] = np.interp(seconds[short], seconds[ok], values[ok])
        lengths = [b - a for a, b in zip(starts, ends, strict=True) if short[a]]
        notes.append(
            f"input '{col}': {int(short.sum())} missing value(s) in {len(lengths)} gap(s) of "
            f"at most {max(lengths)} sample(s) interpolated linearly"
        )
    return out, long_rows


def end_stamped_inputs(data: pd.DataFrame, inputs) -> pd.DataFrame:
    """Inputs stamped at the END of each interval moved onto the zero-order hold.

    A logger's mean over ``[t_k-1, t_k]`` stamped ``t_k`` is the input over the step INTO
    sample ``k``; the zero-order hold applies ``u[k]`` over ``[t_k, t_k+1)``. The ``inputs``
    columns present are shifted one row earlier and the last row (without an input for its
    step) is dropped.
    """
    return shifted_inputs(data, inputs, -1).iloc[:-1]


def shifted_inputs(data, inputs, shift: int):
    """``data`` with its ``inputs`` columns moved ``shift`` rows.

    Parameters
    ----------
    data : DataFrame
        The data as stamped.
    inputs : sequence of str
        The input columns to move (absent ones are skipped).
    shift : int [samples]
        The input of row k becomes that of row ``k - shift`` (negative: earlier, as
        ``--time-stamps end``); the rows left without an input hold NaN.

    Returns
    -------
    DataFrame
    """
    cols = [c for c in inputs if c in data.columns]
    moved = data.copy()
    moved[cols] = data[cols].shift(shift)
    return moved



def midpoint_observations(
    data: pd.DataFrame, outputs, *, hold: str = "zoh"
) -> pd.DataFrame:
    """Interval means observed at their interval's middle: a grid of half intervals.

    A logger that averages over each interval and labels the mean by the interval's start
    records the mean of ``[t_k, t_k+1]``; a filter that compares it with the state at ``t_k``
    puts every observation half an interval early. On synthetic hourly means of a two-state
    house with a morning recovery (three weeks, six noise seeds, 2026-11-30) that lag biased
    the fitted heat loss coefficient by +6.8 % (sd 2.9 %) and the air's capacity by +83 %;
    observed at ``t_k + dt/2`` (the midpoint rule for the mean, exact for a linear trend) the
    bias is +0.2 % (sd 1.0 %) and +6 %, as with instantaneous readings at ``t_k`` (+0.15 %,
    -1 %) (``tests/statespace/test_statespace_kalman.py::
    test_interval_means_fitted_at_their_midpoints``, three two-week seeds).

    Parameters
    ----------
    data : DataFrame
        Rows labelled by the start of their interval in the index (a DatetimeIndex or numeric
        times; not a time column), holding only the model's inputs and outputs (numbers);
        inputs and outputs are interval means.
    outputs : sequence of str
        The columns observed: every output of the model (an output left out would be observed
        on both rows).
    hold : {"zoh", "foh"}
        The inputs' hold, as the model will be fitted with: ``zoh`` repeats row k's inputs on
        its middle row; ``foh`` interpolates linearly between rows k and k + 1 there.

    Returns
    -------
    DataFrame
        Twice the rows: each start row with its inputs and no observation (NaN outputs), then
        its middle row with the inputs and the outputs. An interval is the step to the next
        row, at most the median step (a row before a gap in the index averaged one logger
        interval, not the gap); the last row's is the step before it. A gap of ``g`` missing
        rows is ``2 g`` missing rows on the new grid (a fit's ``max_gap`` counts rows). Results
        of a fit on it (residuals, smoothed states) are on this grid: the middle rows are the
        observations.
    """
    outputs = list(outputs)
    missing = [c for c in outputs if c not in data.columns]
    if missing:
        raise ThermocalInputError(f"midpoint_observations: no column {', '.join(missing)}")
    if len(data) < 2:
        raise ThermocalInputError("midpoint_observations: at least two rows are needed")
    if hold not in ("zoh", "foh"):
        raise ThermocalInputError(f"hold must be 'zoh' or 'foh', got '{hold}'")
    index = data.index
    if not (index.is_monotonic_increasing and index.is_unique):
        raise ThermocalInputError(
            "midpoint_observations: the rows' labels must be strictly increasing (sort the data "
            "and remove duplicated time stamps first)"
        )
    steps = np.diff(index.to_numpy())
    steps = np.append(steps, steps[-1])
    half = np.minimum(steps, np.median(steps)) / 2
    start = data.copy()
    start[outputs] = np.nan
    middle = data.copy()
    if hold == "foh":
        inputs = [c for c in data.columns if c not in outputs]
        values = data[inputs].to_numpy(float)
        following = np.vstack([values[1:], values[-1:]])
        # before a missing input the middle row holds the row's own (as before a time gap):
        # a gap of g rows stays 2 g rows, and the observed rows every second one
        following = np.where(np.isfinite(following), following, values)
        weight = (half / steps).astype(float)[:, None]  # 0.5 unless a gap follows
        middle[inputs] = values + weight * (following - values)
    middle.index = pd.Index(index.to_numpy() + half, name=index.name)
    if isinstance(index, pd.DatetimeIndex):
        middle.index = pd.DatetimeIndex(middle.index, tz=index.tz, name=index.name)
    both = pd.concat([start, middle])
    order = np.argsort(np.concatenate([np.arange(len(data)) * 2, np.arange(len(data)) * 2 + 1]))
    return both.iloc[order]
