"""Reading and checking the measurements of the retrofit workflow.

The measurement file is a CSV (or parquet) table with a time column and one column per
quantity (names mapped by the configuration). Timestamps label the START of the averaging
interval (thermocal convention); naive timestamps are local standard time of the configured
time zone (default: the building's). Everything is averaged onto the configured step by
:func:`thermocal.io.measurements.resample_measurements`, which also reports the data quality.
The file is read here rather than by :func:`thermocal.io.measurements.read_measurements`
because the workflow also accepts parquet and checks the retrofit-specific columns (flow
sign, Kelvin temperatures, irradiance sign) with messages naming the configured column.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import QualityReport
from thermocal.physics.hydronics import heating_power
from thermocal.retrofit.config import FLOW_UNITS, MEASUREMENT_COLUMNS, MeasurementsConfig

TEMPERATURE_COLUMNS = ("temp_out", "temp_supply", "temp_return", "temp_in")


def _timezone(tz):
    import datetime as _dt

    if tz is None:
        return None
    if isinstance(tz, int | float):
        return _dt.timezone(_dt.timedelta(hours=float(tz)))
    return tz


def read_raw_measurements(cfg: MeasurementsConfig, *, default_tz=None) -> pd.DataFrame:
    """Measurement table with standard column names, on a tz-aware DatetimeIndex.

    Raises
    ------
    ThermocalInputError
        File missing or unreadable, time column missing or unparsable, duplicated or
        unsorted timestamps, a mapped column missing, non-numeric values, negative flows,
        temperatures that look like Kelvin.
    """
    path = Path(cfg.file)
    if not path.is_file():
        raise ThermocalInputError(f"measurement file {path} not found")
    try:
        table = pd.read_parquet(path) if path.suffix == ".parquet" else pd.read_csv(path)
    except Exception as exc:  # noqa: BLE001 - any parser failure is an input error
        raise ThermocalInputError(f"measurement file {path} cannot be read: {exc}") from None
    if cfg.time_column not in table.columns:
        raise ThermocalInputError(
            f"measurement file {path}: time column {cfg.time_column!r} not found; columns are "
            f"{list(table.columns)} (set measurements.time_column in the configuration)"
        )
    missing = {std: col for std, col in cfg.columns.items() if col not in table.columns}
    if missing:
        what = ", ".join(f"{col!r} ({MEASUREMENT_COLUMNS[std]})" for std, col in missing.items())
        raise ThermocalInputError(
            f"measurement file {path}: missing column(s) {what}; the file has {list(table.columns)}"
            " (map your names in measurements.columns of the configuration)"
        )
    try:  # ISO 8601 only: a guessed format reads European dates (01.02.2019) month-first
        times = pd.to_datetime(table[cfg.time_column], format="ISO8601")
    except Exception:  # noqa: BLE001
        raise ThermocalInputError(
            f"measurement file {path}: column {cfg.time_column!r} is not an ISO 8601 date/time "
            f"(first value {table[cfg.time_column].iloc[0]!r}); write the times as "
            "2019-02-02 13:00 or 2019-02-02T13:00+01:00"
        ) from None
    index = pd.DatetimeIndex(times)
    tz = _timezone(cfg.timezone) or _timezone(default_tz)
    if index.tz is None:
        if tz is None:
            raise ThermocalInputError(
                f"measurement file {path}: timestamps have no time zone; set measurements.timezone"
            )
        try:
            index = index.tz_localize(tz, ambiguous="infer", nonexistent="shift_forward")
        except Exception as exc:  # noqa: BLE001 - pandas raises several types here
            raise ThermocalInputError(
                f"measurement file {path}: naive timestamps cannot be placed in time zone {tz!r}"
                f" ({exc}); give measurements.timezone as a fixed offset in hours (local "
                "standard time) or write the offset into the timestamps"
            ) from None
    if index.has_duplicates:
        dup = index[index.duplicated()][0]
        raise ThermocalInputError(f"measurement file {path}: duplicated timestamp {dup}")
    if not index.is_monotonic_increasing:
        pos = int(np.argmax(np.diff(index.asi8) < 0)) + 1
        raise ThermocalInputError(
            f"measurement file {path}: timestamps not increasing at row {pos + 2} "
            f"({index[pos]}); sort the file by time"
        )
    out = pd.DataFrame(index=index)
    for std, col in cfg.columns.items():
        values = pd.to_numeric(table[col], errors="coerce").to_numpy(float)
        bad = np.isnan(values) & table[col].notna().to_numpy()
        if bad.any():
            row = int(np.argmax(bad))
            raise ThermocalInputError(
                f"measurement file {path}: column {col!r} row {row + 2} is not a number "
                f"({table[col].iloc[row]!r})"
            )
        out[std] = values
    out["flow"] = out["flow"] * FLOW_UNITS[cfg.flow_unit]
    neg = out["flow"].to_numpy() < 0
    if neg.any():
        row = int(np.argmax(neg))
        raise ThermocalInputError(
            f"measurement file {path}: heating flow column {cfg.columns['flow']!r} is negative "
            f"({table[cfg.columns['flow']].iloc[row]}) at row {row + 2} ({index[row]}); flows "
            "must be >= 0 (check the sensor direction or sign convention)"
        )
    for std in TEMPERATURE_COLUMNS:
        high = np.nanmax(out[std].to_numpy()) if out[std].notna().any() else np.nan
        if np.isfinite(high) and high > 150.0:
            raise ThermocalInputError(
                f"measurement file {path}: column {cfg.columns[std]!r} reaches {high:.1f}; "
                "temperatures must be in degrees C (Kelvin? subtract 273.15)"
            )
    for std in ("dni", "dhi"):
        low = np.nanmin(out[std].to_numpy()) if out[std].notna().any() else 0.0
        if low < -10.0:
            raise ThermocalInputError(
                f"measurement file {path}: irradiance column {cfg.columns[std]!r} has "
                f"{low:.1f} W/m2 < 0"
            )
    span = (index[-1] - index[0]) if len(index) else pd.Timedelta(0)
    high = (
        np.nanmax(out[["dni", "dhi"]].to_numpy()) if out[["dni", "dhi"]].notna().any().any() else 0
    )
    if span >= pd.Timedelta(days=2) and high < 5.0:
        raise ThermocalInputError(
            f"measurement file {path}: irradiance columns {cfg.columns['dni']!r} and "
            f"{cfg.columns['dhi']!r} never exceed {high:.2f} over {span}; they must be in W/m2 "
            "(hourly Wh/m2 are the same numbers; kWh/m2: multiply by 1000)"
        )
    return out


#: Quantity of every standard column (for the physical limits and the spike screening of
#: :func:`thermocal.io.measurements.resample_measurements`).
QUANTITIES: dict[str, str] = {
    "temp_out": "temperature",
    "temp_supply": "temperature",
    "temp_return": "temperature",
    "temp_in": "temperature",
    "flow": "flow",
    "dni": "irradiance",
    "dhi": "irradiance",
    "phi_h": "power",
}
#: The heating power may be slightly negative (supply below return within the sensor
#: uncertainty at a small flow); removing those values would bias the interval means.
PHI_H_LIMITS = (-1e8, 1e8)


def prepare_measurements(raw: pd.DataFrame, step: str) -> tuple[pd.DataFrame, QualityReport]:
    """Average onto a regular grid, add the heating power ``phi_h`` [W], report the quality.

    The heating power is computed at the raw resolution (flow x temperature difference does
    not commute with averaging) with :func:`thermocal.physics.hydronics.heating_power`; then
    every column is averaged by :func:`thermocal.io.measurements.resample_measurements`
    (time-weighted mean, physically impossible values removed, spikes flagged, gaps left NaN
    and reported, intervals covered less than half NaN).

    Each row of the log is the mean over its logging interval, labelled by its start, so a
    value is held for one logging interval (the median spacing of the timestamps, also the
    longest silence bridged) and the last row is closed at its interval end. For a regular
    log on the grid (or finer) the result equals the plain mean of the rows in each interval.

    Parameters
    ----------
    raw : pd.DataFrame
        From :func:`read_raw_measurements` (standard column names, tz-aware index).
    step : str
        Grid step, e.g. "1h" (``measurements.step``).

    Returns
    -------
    grid : pd.DataFrame
        Regular grid labelled by interval start with the raw columns and ``phi_h`` [W].
    report : thermocal.io.measurements.QualityReport
    """
    from thermocal.io.measurements import resample_measurements

    try:
        step_td = pd.Timedelta(step)
    except ValueError as exc:
        raise ThermocalInputError(
            f"measurements.step {step!r} is not a valid step: {exc}"
        ) from None
    if step_td <= pd.Timedelta(0):
        raise ThermocalInputError(f"measurements.step {step!r} must be a positive duration")
    if len(raw) < 2:
        raise ThermocalInputError("measurement file: fewer than two rows of measurements")
    frame = raw.copy()
    frame["phi_h"] = heating_power(frame["flow"], frame["temp_supply"], frame["temp_return"])
    frame["dni"] = frame["dni"].clip(lower=0.0)
    frame["dhi"] = frame["dhi"].clip(lower=0.0)
    logging_interval = pd.Series(frame.index).diff().median()
    closing = frame.iloc[[-1]].copy()
    closing.index = closing.index + logging_interval
    frame = pd.concat([frame, closing])
    grid, report = resample_measurements(
        frame,
        step_td,
        max_gap=logging_interval,
        quantities={c: QUANTITIES[c] for c in frame.columns if c in QUANTITIES},
        limits={"phi_h": PHI_H_LIMITS},
    )
    # the closing row is not a report of the file: count only the file's rows
    closed = [c for c in closing.columns if np.isfinite(closing[c].iloc[0])]
    report.sensors.loc[closed, "n_reports"] -= 1
    report.actions.append(
        f"each row held for one logging interval ({logging_interval}), the last row until "
        f"{closing.index[0].isoformat()} (rows are interval means labelled by their start)"
    )
    return grid[list(raw.columns) + ["phi_h"]], report
