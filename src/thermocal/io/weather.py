"""Weather files (EPW, TMY3, CSV) into one standard, tz-aware frame.

Every reader returns ``(weather, metadata)``.

Standard columns (a quantity absent from the file is absent from the frame, never faked):

=================  ======  ===========  ==================================================
column             unit    kind         meaning
=================  ======  ===========  ==================================================
temp_air           C       instant      dry-bulb air temperature
temp_dew           C       instant      dew-point temperature
relative_humidity  %       instant      relative humidity
pressure           Pa      instant      atmospheric station pressure
wind_speed         m/s     instant      wind speed
wind_direction     deg     instant      wind direction (from; 0 N, 90 E)
ghi                W/m2    interval     global horizontal irradiance
dni                W/m2    interval     direct normal irradiance
dhi                W/m2    interval     diffuse horizontal irradiance
ghi_infrared       W/m2    interval     horizontal long-wave (infrared) irradiance from the sky
albedo             -       interval     ground reflectance
precipitation      mm/h    interval     liquid precipitation (EPW field 33, depth per hour;
                                        missing values 0, as EnergyPlus reads them)
weather_rain       -       interval     EPW present-weather rain (1 rain), only when the file
                                        has observations (indicator 0)
=================  ======  ===========  ==================================================

Time convention (the same for every format)
-------------------------------------------
* The index is tz-aware. EPW and TMY3 files are in the site's local *standard* time (no daylight
  saving); the index carries that fixed UTC offset (e.g. ``UTC+01:00`` for Zurich) unless ``tz=``
  asks for a conversion.
* Each row is **labelled by the start of the interval it describes**: the row ``2015-01-01 00:00``
  describes ``[00:00, 01:00)``. EPW "hour 1" and TMY3 "01:00" (hour-ending labels) therefore become
  ``00:00``.
* Interval quantities (``ghi, dni, dhi, ghi_infrared, albedo``) are **means over**
  ``[t, t + step)``: the EPW/TMY3 irradiation of the *preceding* hour [Wh/m2] equals the mean
  irradiance [W/m2] of the hour that our label starts.
* Instant quantities (temperatures, humidity, pressure, wind) are kept at their **true time**: the
  files report them at the end of the hour, so the value of file row *k* (hour ending ``t_k + 1h``)
  becomes the value at label ``t_k + 1h``, i.e. of the next row. Linear interpolation between rows
  then gives the right value at any time (this is what EnergyPlus does with hourly weather) and
  :func:`resample_weather` interpolates them. The first row's instant values (the end of the hour
  *before* the file starts) are taken from the file's last row when the file covers a whole year (a
  typical year is cyclic), otherwise the first file row is repeated. EnergyPlus does not wrap: for
  the hour before a run period (and on each warm-up day) it interpolates from the first day's own
  hour-24 values (RunPeriod "First Hour Interpolation Starting Values", default Hour24); on
  1 January of a Chicago file -5.0 C and 8.8 m/s against the wrapped -19.4 C and calm
  (docs/energyplus.md, "The first hour of a run").
  Downstream code that needs an interval mean of the temperature uses
  ``(T(t) + T(t + step)) / 2``.
* Sun positions for interval data must be computed at the interval midpoints ``t + step / 2``:
  :func:`thermocal.physics.solar.irradiance_on_surface` does this.

Years
-----
EPW files of *typical* years (TMY, IWEC, ...) take each month from a different year, so the year
column varies from row to row and the raw time stamps are not monotonic. When the file's own years
give a strictly increasing, regular index (actual-year files such as ``Zuerich-SMA_2015.epw``) they
are kept. Otherwise all rows are coerced to one year: ``coerce_year`` if given, else the latest
year in 2001-2023 (non-leap unless the file contains 29 February) whose calendar puts the file's
first day on the weekday declared in the EPW ``DATA PERIODS`` line (so weekday schedules match
EnergyPlus), or 2001/2004 when no weekday is declared. ``metadata["coerced_year"]`` records it.

Measured periods (``identify``, ``calibrate``): :func:`weather_for_period` puts a typical year on
the year(s) of the measurements (every row keeps its month, day and hour; the weekdays become
those of the measurement year; 29 February repeats 28 February in a leap year) and refuses an
actual-year file that does not cover the period, naming the file, its years and the period.

References
----------
.. [1] EnergyPlus Auxiliary Programs, "Weather Converter Program", section "EnergyPlus Weather File
   (EPW) Data Dictionary".
.. [2] Wilcox, S. and Marion, W. (2008), "Users Manual for TMY3 Data Sets", NREL/TP-581-43156.
.. [3] ISO 52010-1:2017, clause 6.4 (interval conventions for solar calculations).
"""

from __future__ import annotations

import calendar
import io
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io._time import as_timezone, parse_time_column

__all__ = [
    "STANDARD_COLUMNS",
    "INTERVAL_COLUMNS",
    "INSTANT_COLUMNS",
    "read_weather",
    "read_epw",
    "read_tmy3",
    "read_weather_csv",
    "resample_weather",
    "weather_step",
    "weather_for_period",
    "check_full_year",
    "incomplete_file_statement",
]

#: Quantities that are means over the interval ``[t, t + step)`` [W/m2 or -].
INTERVAL_COLUMNS = (
    "ghi",
    "dni",
    "dhi",
    "ghi_infrared",
    "albedo",
    "precipitation",
    "weather_rain",
)
#: Quantities that are instantaneous values at the label time.
INSTANT_COLUMNS = (
    "temp_air",
    "temp_dew",
    "relative_humidity",
    "pressure",
    "wind_speed",
    "wind_direction",
)
#: All standard columns, in the order they appear in the returned frame.
STANDARD_COLUMNS = (
    "temp_air",
    "temp_dew",
    "relative_humidity",
    "pressure",
    "ghi",
    "dni",
    "dhi",
    "ghi_infrared",
    "wind_speed",
    "wind_direction",
    "albedo",
    "precipitation",
    "weather_rain",
)

# EPW "missing" codes per field (EnergyPlus Auxiliary Programs, EPW data dictionary); a value
# >= the code is missing.
_EPW_MISSING = {
    "temp_air": 99.9,
    "temp_dew": 99.9,
    "relative_humidity": 999.0,
    "pressure": 999999.0,
    "ghi_infrared": 9999.0,
    "ghi": 9999.0,
    "dni": 9999.0,
    "dhi": 9999.0,
    "wind_direction": 999.0,
    "wind_speed": 999.0,
    "albedo": 999.0,
    "precipitation": 999.0,
}

# Physically plausible ranges used to catch unit mix-ups and corrupt values.
_PLAUSIBLE = {
    "temp_air": (-90.0, 70.0, "C"),
    "temp_dew": (-100.0, 50.0, "C"),
    "relative_humidity": (0.0, 110.0, "%"),
    "pressure": (30_000.0, 120_000.0, "Pa"),
    "ghi": (-10.0, 1600.0, "W/m2"),
    "dni": (-10.0, 1500.0, "W/m2"),
    "dhi": (-10.0, 1000.0, "W/m2"),
    "ghi_infrared": (0.0, 700.0, "W/m2"),
    "wind_speed": (0.0, 80.0, "m/s"),
    "wind_direction": (0.0, 360.0, "deg"),
    "albedo": (0.0, 1.0, "-"),
    "precipitation": (0.0, 1000.0, "mm/h"),
    "weather_rain": (0.0, 1.0, "-"),
}

_EPW_FIELDS = 35
#: The EPW data fields in order (EnergyPlus Auxiliary Programs, the EPW data dictionary).
_EPW_FIELD_NAMES = (
    "year", "month", "day", "hour", "minute", "data source flags", "dry-bulb temperature",
    "dew-point temperature", "relative humidity", "station pressure",
    "extraterrestrial horizontal radiation", "extraterrestrial direct normal radiation",
    "horizontal infrared radiation", "global horizontal radiation", "direct normal radiation",
    "diffuse horizontal radiation", "global horizontal illuminance",
    "direct normal illuminance", "diffuse horizontal illuminance", "zenith luminance",
    "wind direction", "wind speed", "total sky cover", "opaque sky cover", "visibility",
    "ceiling height", "present weather observation", "present weather codes",
    "precipitable water", "aerosol optical depth", "snow depth", "days since last snowfall",
    "albedo", "liquid precipitation depth", "liquid precipitation quantity",
)  # fmt: skip
#: Fields a data line must have: up to the opaque sky cover (older files end after field 32;
#: thermocal reads nothing beyond the sky cover but the albedo, which may be absent).
_EPW_MIN_FIELDS = 24
_WEEKDAYS = {name.lower(): i for i, name in enumerate(calendar.day_name)}


# --------------------------------------------------------------------------------------------
# public API
# --------------------------------------------------------------------------------------------
def read_weather(
    path: str | Path,
    *,
    format: str | None = None,
    columns: Mapping[str, str] | None = None,
    tz: str | float | None = None,
    time_column: str = "time",
    time_label: str = "start",
    time_format: str | None = None,
    coerce_year: int | None = None,
    metadata: Mapping[str, Any] | None = None,
) -> tuple[pd.DataFrame, dict]:
    """Read a weather file (EPW, TMY3 or CSV) into the standard frame.

    Parameters
    ----------
    path : str or Path
        The weather file.
    format : {"epw", "tmy3", "csv"}, optional
        File format; detected from the extension and the first line when omitted.
    columns : mapping, optional
        CSV only: ``{standard_name: file_column}``, e.g. ``{"temp_air": "T_out", "ghi": "G"}``.
        Values must already be in the standard units (see the module docstring).
    tz : str or float, optional
        EPW/TMY3: convert the index to this time zone (name, or hours east of UTC).
        CSV: the time zone of naive time stamps (required for them); aware stamps are converted.
    time_column : str
        CSV only: the name of the time-stamp column [-].
    time_label : {"start", "end"}
        CSV only: whether each time stamp labels the start (default) or the end of the interval
        over which the irradiance columns are averaged.
    time_format : str, optional
        CSV only: strftime format of non-ISO-8601 time stamps, e.g. ``"%d.%m.%Y %H:%M"``.
    coerce_year : int, optional
        EPW/TMY3: put every row in this year (typical-year files). See the module docstring.
    metadata : mapping, optional
        CSV only: site metadata (``latitude`` [deg N], ``longitude`` [deg E], ``altitude`` [m],
        ``name``), copied into the returned metadata.

    Returns
    -------
    weather : pandas.DataFrame
        Standard columns, tz-aware index labelled by interval start.
    metadata : dict
        ``latitude`` [deg N], ``longitude`` [deg E], ``altitude`` [m], ``tz`` [h east of UTC or
        name], ``name``, ``source`` (path), ``format``, ``step`` (pandas Timedelta),
        ``time_label`` ("interval start"), ``coerced_year`` (int or None), ``missing``
        ({column: number of missing values}) and, for EPW, ``ground_temperatures``
        ({depth [m]: 12 monthly means [C]}), ``holidays`` ([(name, date text)] of the
        ``HOLIDAYS/DAYLIGHT SAVINGS`` line, dates as written: ``1/1``, ``Jan 1``,
        ``Last Monday in May``, ...) and ``daylight_saving`` ((start, end) date texts, None when
        the file gives none); for EPW and TMY3 ``data_period`` (``{"start": (month, day),
        "end": (month, day), "declared_by": str}``: the period the file declares, an EPW's
        ``DATA PERIODS`` line, a TMY3's whole year; None when unreadable), which tells a file
        cut short (:func:`incomplete_file_statement`).

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Unreadable file, unknown format, bad or missing columns, non-numeric values, irregular or
        duplicated time stamps, implausible values (e.g. Kelvin instead of Celsius); the message
        names the file, column and line.
    """
    path = Path(path)
    if not path.is_file():
        raise ThermocalInputError(f"weather file {path} does not exist (check the path)")
    fmt = (format or _detect_format(path)).lower()
    if fmt == "epw":
        return read_epw(path, tz=tz, coerce_year=coerce_year)
    if fmt in ("tmy3", "tmy"):
        return read_tmy3(path, tz=tz, coerce_year=coerce_year)
    if fmt == "csv":
        return read_weather_csv(
            path,
            columns=columns,
            tz=tz,
            time_column=time_column,
            time_label=time_label,
            time_format=time_format,
            metadata=metadata,
        )
    raise ThermocalInputError(
        f"weather file {path}: unknown format {format!r}; use 'epw', 'tmy3' or 'csv'"
    )


def read_epw(
    path: str | Path, *, tz: str | float | None = None, coerce_year: int | None = None
) -> tuple[pd.DataFrame, dict]:
    """Read an EnergyPlus weather (EPW) file into the standard frame.

    Uses :func:`pvlib.iotools.read_epw` for parsing; builds the interval-start index itself (see
    the module docstring for the conventions).

    Parameters
    ----------
    path : str or Path
        The ``.epw`` file.
    tz : str or float, optional
        Convert the index to this time zone (name, or hours east of UTC).
    coerce_year : int, optional
        Put every row in this year.

    Returns
    -------
    weather : pandas.DataFrame
    metadata : dict
        See :func:`read_weather`.

    References
    ----------
    .. [1] EnergyPlus Auxiliary Programs, EPW data dictionary.
    """
    import pvlib

    path = Path(path)
    header = _read_epw_header(path)
    buffer = _epw_buffer(path)
    try:
        raw, meta = pvlib.iotools.read_epw(buffer)
    except Exception as exc:  # pvlib fails deep inside pandas: find the culprit ourselves
        _diagnose_epw(path, exc)
        raise ThermocalInputError(f"weather file {path} is not a readable EPW file: {exc}") from exc
    n_header = 8
    raw = raw.reset_index(drop=True)
    for column in ("year", "month", "day", "hour", "minute"):
        _require_numeric(raw, column, path, first_line=n_header + 1, what="EPW field")
    records_per_hour = header["records_per_hour"]
    step = pd.Timedelta(minutes=60 // records_per_hour)
    # start of each record: (hour - 1) + (minute_end - step) for sub-hourly files
    if records_per_hour == 1:
        offset = pd.to_timedelta(raw["hour"].astype(int) - 1, unit="h")
    else:
        minute_end = raw["minute"].astype(int).where(raw["minute"].astype(int) > 0, 60)
        offset = (
            pd.to_timedelta(raw["hour"].astype(int) - 1, unit="h")
            + pd.to_timedelta(minute_end, unit="min")
            - step
        )
    start, coerced = _dates_with_years(
        raw[["year", "month", "day"]].astype(int),
        offset,
        step,
        path,
        first_line=n_header + 1,
        coerce_year=coerce_year,
        first_weekday=header["start_weekday"],
    )
    utc_offset = _checked_utc_offset(meta, path)
    index = pd.DatetimeIndex(start).tz_localize(as_timezone(utc_offset, f"weather file {path}"))
    frame = pd.DataFrame(index=index)
    missing: dict[str, int] = {}
    for column in STANDARD_COLUMNS:
        if column == "weather_rain":
            flag = _present_weather_rain(raw)
            if flag is not None:
                frame[column] = flag
            continue
        source = {
            "pressure": "atmospheric_pressure",
            "precipitation": "liquid_precipitation_depth",
        }.get(column, column)
        if source not in raw.columns:
            continue
        _require_numeric(raw, source, path, first_line=n_header + 1, what="EPW field")
        values = raw[source].to_numpy(dtype=float)
        if column in ("temp_air", "temp_dew") and 200 < np.median(values) < 400:
            row = int(np.argmax(values > 200))
            raise ThermocalInputError(
                f"weather file {path}, EPW field {column!r}: values around "
                f"{np.median(values):.1f} (line {row + n_header + 1}: {values[row]:g}) look like "
                "Kelvin; EPW temperatures are in C: subtract 273.15"
            )
        values = np.where(values >= _EPW_MISSING[column], np.nan, values)
        if column == "precipitation":
            # depth per record [mm] -> rate [mm/h]; a missing depth is no rain (EnergyPlus)
            values = np.where(np.isnan(values), 0.0, values) * records_per_hour
        if np.all(np.isnan(values)):
            continue  # absent from the file: absent from the frame
        frame[column] = values
    if "albedo" in frame and np.nanmax(frame["albedo"].to_numpy()) <= 0.0:
        frame = frame.drop(columns="albedo")  # EPW writers put 0 when unknown
    _check_plausible(frame, path, first_line=n_header + 1)
    full_year = _covers_whole_year(index, step)
    frame = _instant_values_to_true_time(frame, wrap=full_year)
    for column in frame.columns:
        n_missing = int(frame[column].isna().sum())
        if n_missing:
            missing[column] = n_missing
    if tz is not None:
        frame.index = frame.index.tz_convert(as_timezone(tz, f"weather file {path}"))
    metadata = {
        "latitude": float(meta["latitude"]),
        "longitude": float(meta["longitude"]),
        "altitude": float(meta["altitude"]),
        "tz": utc_offset,
        "name": str(meta.get("city", "")).strip() or path.stem,
        "source": str(path),
        "format": "epw",
        "step": step,
        "time_label": "interval start",
        "coerced_year": coerced,
        "missing": missing,
        "ground_temperatures": header["ground_temperatures"],
        "wmo": str(meta.get("WMO_code", "")).strip(),
        "holidays": header["holidays"],
        "daylight_saving": header["daylight_saving"],
        "data_period": None
        if header["data_period"] is None
        else {
            "start": header["data_period"][0],
            "end": header["data_period"][1],
            "declared_by": "its header's DATA PERIODS line",
        },
    }
    return frame, metadata


def read_tmy3(
    path: str | Path, *, tz: str | float | None = None, coerce_year: int | None = None
) -> tuple[pd.DataFrame, dict]:
    """Read an NREL TMY3 file into the standard frame.

    Uses :func:`pvlib.iotools.read_tmy3`; TMY3 time stamps are hour-ending in local standard time
    (``01:00`` is the hour 00:00-01:00, ``24:00`` the last hour of the day) and are re-labelled by
    interval start; pressure is converted from mbar to Pa. TMY3 has no infrared irradiance.

    Parameters
    ----------
    path : str or Path
        The TMY3 ``.csv`` file.
    tz : str or float, optional
        Convert the index to this time zone.
    coerce_year : int, optional
        Put every row in this year (default: see the module docstring).

    Returns
    -------
    weather : pandas.DataFrame
    metadata : dict
        See :func:`read_weather`.

    References
    ----------
    .. [1] Wilcox, S. and Marion, W. (2008), "Users Manual for TMY3 Data Sets",
       NREL/TP-581-43156, section 2.
    """
    import pvlib

    path = Path(path)
    try:
        raw, meta = pvlib.iotools.read_tmy3(str(path), map_variables=True)
    except Exception as exc:
        _diagnose_tmy3(path, exc)
        raise ThermocalInputError(
            f"weather file {path} is not a readable TMY3 file: {exc} (the first line holds the "
            "site, the second the column names, e.g. 'Date (MM/DD/YYYY),Time (HH:MM),...')"
        ) from exc
    n_header = 2
    raw = raw.reset_index(drop=True)
    # rebuild the stamps from the file's own date and hour-ending time (pvlib moves 24:00 to the
    # next day and 29 February to 1 March, which breaks typical-year files)
    dates = pd.to_datetime(raw["Date (MM/DD/YYYY)"], format="%m/%d/%Y", errors="coerce")
    clock = raw["Time (HH:MM)"].astype(str).str.split(":", expand=True)
    hours = pd.to_numeric(clock[0], errors="coerce")
    minutes = pd.to_numeric(clock[1], errors="coerce") if clock.shape[1] > 1 else hours * np.nan
    bad = dates.isna() | hours.isna() | minutes.isna() | (hours < 1) | (hours > 24)
    if bad.any():
        row = int(np.flatnonzero(bad.to_numpy())[0])
        raise ThermocalInputError(
            f"weather file {path}, line {row + n_header + 1}: cannot read date/time "
            f"{raw['Date (MM/DD/YYYY)'].iloc[row]!r} {raw['Time (HH:MM)'].iloc[row]!r} "
            "(expected MM/DD/YYYY and an hour-ending HH:MM from 01:00 to 24:00)"
        )
    step = pd.Timedelta(hours=1)
    ymd = pd.DataFrame({"year": dates.dt.year, "month": dates.dt.month, "day": dates.dt.day})
    offset = pd.to_timedelta(hours - 1, unit="h") + pd.to_timedelta(minutes, unit="min")
    start, coerced = _dates_with_years(
        ymd,
        offset,
        step,
        path,
        first_line=n_header + 1,
        coerce_year=coerce_year,
        first_weekday=None,
    )
    utc_offset = _checked_utc_offset(meta, path)
    index = pd.DatetimeIndex(start).tz_localize(as_timezone(utc_offset, f"weather file {path}"))
    frame = pd.DataFrame(index=index)
    for column in STANDARD_COLUMNS:
        if column not in raw.columns:
            continue
        _require_numeric(raw, column, path, first_line=n_header + 1, what="TMY3 column")
        values = raw[column].to_numpy(dtype=float)
        if column == "pressure":
            values = values * 100.0  # mbar -> Pa
        if column == "albedo":
            values = np.where(values <= 0.0, np.nan, values)
        if np.all(np.isnan(values)):
            continue
        frame[column] = values
    _check_plausible(frame, path, first_line=n_header + 1)
    frame = _instant_values_to_true_time(frame, wrap=_covers_whole_year(index, step))
    missing = {c: int(frame[c].isna().sum()) for c in frame.columns if frame[c].isna().any()}
    if tz is not None:
        frame.index = frame.index.tz_convert(as_timezone(tz, f"weather file {path}"))
    metadata = {
        "latitude": float(meta["latitude"]),
        "longitude": float(meta["longitude"]),
        "altitude": float(meta["altitude"]),
        "tz": utc_offset,
        "name": str(meta.get("Name", "")).strip().strip('"') or path.stem,
        "source": str(path),
        "format": "tmy3",
        "step": step,
        "time_label": "interval start",
        "coerced_year": coerced,
        "missing": missing,
        "wmo": str(meta.get("USAF", "")),
        "data_period": {
            "start": (1, 1),
            "end": (12, 31),
            "declared_by": "the TMY3 format (a typical year)",
        },
    }
    return frame, metadata


def read_weather_csv(
    path: str | Path,
    *,
    columns: Mapping[str, str] | None,
    tz: str | float | None = None,
    time_column: str = "time",
    time_label: str = "start",
    time_format: str | None = None,
    metadata: Mapping[str, Any] | None = None,
) -> tuple[pd.DataFrame, dict]:
    """Read a plain CSV weather file with a column mapping into the standard frame.

    Parameters
    ----------
    path : str or Path
        The CSV file (comma separated, one header line).
    columns : mapping
        ``{standard_name: file_column}``; values in standard units (temperatures [C], pressure
        [Pa], irradiance [W/m2] as interval means, wind [m/s], [deg], relative humidity [%]).
    tz : str or float, optional
        Time zone of naive time stamps (name or hours east of UTC); required if they are naive.
    time_column : str
        Name of the time-stamp column [-].
    time_label : {"start", "end"}
        Whether a time stamp labels the start or the end of its averaging interval. With "end"
        the rows are re-labelled by interval start and instant quantities are kept at their true
        time, exactly as for EPW files.
    time_format : str, optional
        strftime format of time stamps that are not ISO 8601, e.g. ``"%d.%m.%Y %H:%M"``
        (ISO 8601 with or without UTC offsets is read without it).
    metadata : mapping, optional
        ``latitude`` [deg N], ``longitude`` [deg E], ``altitude`` [m], ``name``.

    Returns
    -------
    weather : pandas.DataFrame
    metadata : dict
        See :func:`read_weather`.
    """
    path = Path(path)
    if not columns:
        raise ThermocalInputError(
            f"weather file {path}: a CSV weather file needs a column mapping "
            "{standard_name: file_column}, e.g. columns={'temp_air': 'T_out', 'ghi': 'G_h'}; "
            f"standard names are {', '.join(STANDARD_COLUMNS)}"
        )
    unknown = [name for name in columns if name not in STANDARD_COLUMNS]
    if unknown:
        raise ThermocalInputError(
            f"weather file {path}: unknown standard column name(s) {unknown} in the column "
            f"mapping; allowed: {', '.join(STANDARD_COLUMNS)}"
        )
    if time_label not in ("start", "end"):
        raise ThermocalInputError(
            f"weather file {path}: time_label must be 'start' or 'end', got {time_label!r}"
        )
    try:
        raw = pd.read_csv(path)
    except Exception as exc:
        raise ThermocalInputError(f"weather file {path} is not a readable CSV file: {exc}") from exc
    needed = [time_column, *columns.values()]
    absent = [c for c in needed if c not in raw.columns]
    if absent:
        raise ThermocalInputError(
            f"weather file {path}: column(s) {absent} not found; the file has "
            f"{list(raw.columns)} (fix the column mapping or time_column=)"
        )
    first_line = 2  # header is line 1
    index, _ = parse_time_column(
        raw[time_column],
        source=f"weather file {path}",
        column=time_column,
        lines=np.arange(first_line, first_line + len(raw)),
        tz=tz,
        time_format=time_format,
    )
    _check_time_index(index, path, time_column, first_line)
    step = pd.Timedelta(index[1] - index[0]) if len(index) > 1 else pd.Timedelta(hours=1)
    frame = pd.DataFrame(index=index)
    for name in STANDARD_COLUMNS:
        if name not in columns:
            continue
        source = columns[name]
        _require_numeric(raw, source, path, first_line=first_line, what="column")
        frame[name] = raw[source].to_numpy(dtype=float)
    _check_plausible(frame, path, first_line=first_line, names=dict(columns))
    if time_label == "end":
        frame.index = frame.index - step
        frame = _instant_values_to_true_time(frame, wrap=False)
    meta = dict(metadata or {})
    missing = {c: int(frame[c].isna().sum()) for c in frame.columns if frame[c].isna().any()}
    tzinfo = frame.index.tz
    utc = frame.index[0].utcoffset() if len(frame) else None
    out = {
        "latitude": _float_or_none(meta.get("latitude")),
        "longitude": _float_or_none(meta.get("longitude")),
        "altitude": _float_or_none(meta.get("altitude", 0.0)),
        "tz": utc.total_seconds() / 3600.0
        if _is_fixed(tzinfo) and utc is not None
        else str(tzinfo),
        "name": str(meta.get("name", path.stem)),
        "source": str(path),
        "format": "csv",
        "step": step,
        "time_label": "interval start",
        "coerced_year": None,
        "missing": missing,
    }
    return frame, out


#: Largest distance between a building and the site of its weather data [km]: a station a
#: few hundred km away may still be the nearest; beyond, sun and climate are another place's.
MAX_SITE_DISTANCE_KM = 300.0


def site_distance_km(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    """Great-circle distance between two sites (haversine, mean Earth radius 6371 km) [km].

    Parameters
    ----------
    lat1, lon1, lat2, lon2 : float
        Latitudes [deg N] and longitudes [deg E].
    """
    phi1, phi2 = np.radians(lat1), np.radians(lat2)
    dphi, dlam = phi2 - phi1, np.radians(lon2 - lon1)
    a = np.sin(dphi / 2) ** 2 + np.cos(phi1) * np.cos(phi2) * np.sin(dlam / 2) ** 2
    return float(2 * 6371.0 * np.arcsin(np.sqrt(min(1.0, a))))


def check_site_matches_weather(
    latitude: float | None,
    longitude: float | None,
    weather_meta: Mapping[str, Any],
    *,
    building_source: str,
    weather_source: str,
    max_km: float = MAX_SITE_DISTANCE_KM,
    remedy: str = "",
) -> float | None:
    """Refuse weather data from a site far from the building.

    The sun's position, the climate and (for a typical year) the demand are the weather site's:
    Zurich weather for a North Carolina house gives a plausible but wrong result.

    Parameters
    ----------
    latitude, longitude : float or None
        The building's site [deg N, deg E]; None: not given (nothing is checked).
    weather_meta : mapping
        The weather reader's metadata (``latitude``, ``longitude``, optional ``name``).
    building_source, weather_source : str
        The files, for the message.
    max_km : float
        Largest accepted distance [km].
    remedy : str
        The caller's way to simulate at the weather's site instead (its option or key, e.g.
        ``"pass --site weather ..."``), appended to the message; "" names none.

    Returns
    -------
    float or None
        The distance [km]; None when a location is unknown.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Naming both files, both latitude/longitude pairs and the distance.
    """
    w_lat, w_lon = weather_meta.get("latitude"), weather_meta.get("longitude")
    if None in (latitude, longitude, w_lat, w_lon):
        return None
    if not all(np.isfinite([latitude, longitude, w_lat, w_lon])):
        return None
    lon_b = ((float(longitude) + 180.0) % 360.0) - 180.0
    distance = site_distance_km(float(latitude), lon_b, float(w_lat), float(w_lon))
    if distance > max_km:
        name = weather_meta.get("name") or weather_meta.get("city")
        where = f" ({name})" if name else ""
        raise ThermocalInputError(
            f"the building ({building_source}) is at latitude {float(latitude):.2f}, longitude "
            f"{lon_b:.2f}, but the weather {weather_source}{where} is for latitude "
            f"{float(w_lat):.2f}, longitude {float(w_lon):.2f}: {distance:,.0f} km apart "
            f"(at most {max_km:g} km accepted); sun and climate would be another place's. "
            "Use weather of the building's site, or correct the building's location (or the "
            "weather file's header if its data are the site's)" + (f"; {remedy}" if remedy else "")
        )
    return distance


def _default_location(location) -> bool:
    """Whether ``location`` is its type's default (no site of the building's own)."""
    try:
        default = type(location)()
    except (TypeError, ValueError):  # no default (pydantic's ValidationError is a ValueError)
        return False
    return location == default


def check_building_site(
    building,
    weather_meta: Mapping[str, Any],
    *,
    building_source: str,
    weather_source: str,
    remedy: str = "",
) -> float | None:
    """:func:`check_site_matches_weather` for a multi-zone building (``building.location``).

    A building without a location of its own (the model's default site, as when a YAML file
    has no ``location:`` or an IDF no ``Site:Location``) takes the weather's and is not checked.
    ``remedy`` is the caller's opt-in to the weather's site, named in the message. A location
    type without a default (the retrofit envelope's ``Site``: latitude, longitude and time zone
    required) is always the building's own and checked.
    """
    location = getattr(building, "location", None)
    if location is None or _default_location(location):
        return None
    return check_site_matches_weather(
        location.latitude,
        location.longitude,
        weather_meta,
        building_source=building_source,
        weather_source=weather_source,
        remedy=remedy,
    )


#: The values of the option (``--site``, ``identification.site``) choosing whose site a run
#: uses when the building's and the weather's are more than :data:`MAX_SITE_DISTANCE_KM` apart.
SITE_CHOICES = ("building", "weather")


def building_site_or_weather(
    building,
    weather_meta: Mapping[str, Any],
    site: str,
    *,
    building_source: str,
    weather_source: str,
    option: str,
    opt_in: str,
) -> str | None:
    """The site check of a run, with the user's choice when the sites are far apart.

    ``site="building"`` (the default of every command): :func:`check_building_site`, whose
    refusal names ``opt_in`` as the way out. ``site="weather"``: what EnergyPlus does for a
    weather-file run (it warns and uses the weather file's site, so a stale ``Site:Location``
    does not matter there): the building's location is replaced by the weather file's latitude,
    longitude and altitude (its time zone kept) when they are more than
    :data:`MAX_SITE_DISTANCE_KM` apart, and the note saying so is returned for the caller's
    warning and outputs.

    Parameters
    ----------
    building : thermocal.multizone.Building
        Its ``location`` is replaced in place with ``site="weather"``.
    weather_meta : mapping
        The weather reader's metadata.
    site : {"building", "weather"}
    building_source, weather_source : str
        The files, for the messages.
    option : str
        The option or key as the user writes it (``"--site"``, ``"identification.site"``).
    opt_in : str
        How the user asks for the weather's site (``"--site weather"``,
        ``"identification.site: weather in the campaign file"``).

    Returns
    -------
    str or None
        The note when the building's site was replaced, else None.
    """
    if site not in SITE_CHOICES:
        raise ThermocalInputError(
            f"{option} {site!r}: use building (refuse weather of another site, the default) or "
            "weather (use the weather file's site, as EnergyPlus does)"
        )
    remedy = (
        f"or, if the building's location is stale and the weather is the site's (EnergyPlus "
        f"warns and uses the weather file's site), {opt_in} runs at the weather file's site"
    )
    try:
        check_building_site(
            building,
            weather_meta,
            building_source=building_source,
            weather_source=weather_source,
            remedy=remedy if site == "building" else "",
        )
        return None
    except ThermocalInputError as exc:
        if site == "building":
            raise
        text = str(exc).split(" (at most")[0]
    location = building.location
    altitude = weather_meta.get("altitude")
    building.location = type(location)(
        latitude=float(weather_meta["latitude"]),
        longitude=float(weather_meta["longitude"]),
        altitude=float(location.altitude if altitude is None else altitude),
        timezone=location.timezone,
    )
    return (
        f"site replaced ({opt_in}): {text}; the building's written location was replaced by "
        "the weather file's (latitude, longitude, altitude), as EnergyPlus does for a "
        "weather-file run: sun and climate are the weather's site"
    )


def check_weather_clock(
    weather: pd.DataFrame, metadata: Mapping[str, Any], *, source: str
) -> float:
    """Refuse weather whose irradiance does not follow the sun at its own site and clock.

    :func:`thermocal.io.measurements.check_clock_against_sun` on ``ghi`` (or ``dni + dhi``):
    a CSV read with the wrong ``tz``, or a header whose time zone is not the data's, moves the
    sun by hours.

    Parameters
    ----------
    weather : DataFrame
        From :func:`read_weather` (tz-aware index, irradiance [W/m2]).
    metadata : mapping
        Its metadata (``latitude``, ``longitude``).
    source : str
        The weather file, for the message.

    Returns
    -------
    float
        The clock's offset from the sun [h] (0 without irradiance or site).
    """
    from thermocal.io.measurements import check_clock_against_sun

    lat, lon = metadata.get("latitude"), metadata.get("longitude")
    if lat is None or lon is None:
        return 0.0
    if "ghi" in weather.columns:
        irradiance, column = weather["ghi"], "ghi"
    elif {"dni", "dhi"} <= set(weather.columns):
        irradiance, column = weather["dni"] + weather["dhi"], "dni + dhi"
    else:
        return 0.0
    return check_clock_against_sun(
        irradiance,
        float(lat),
        float(lon),
        source=f"weather file {source}",
        column=column,
        timezone_setting="the time zone of the weather file (its header, or tz= for a CSV)",
    )


def weather_for_period(
    weather: pd.DataFrame,
    metadata: Mapping | None,
    start,
    end,
    *,
    source: str | None = None,
) -> tuple[pd.DataFrame, dict]:
    """The weather on the calendar of a measured period ``[start, end)``.

    A *typical-year* file (``metadata["coerced_year"]`` set by :func:`read_weather`: TMY, IWEC,
    EPW with months from several years) follows the year of the measurements: its rows are put
    on every calendar year the period touches (month, day and hour kept; 29 February of a leap
    year repeats 28 February, a file's 29 February is dropped in other years), so weekdays are
    those of the measurement year, not the weekday the file declares. An *actual-year* file must
    cover the period.

    Parameters
    ----------
    weather : DataFrame
        From :func:`read_weather` (tz-aware index).
    metadata : dict
        Its metadata (``coerced_year``, ``source``).
    start, end : timestamp-like
        The period; naive times are read in the weather's time zone.
    source : str, optional
        File name for messages (default ``metadata["source"]``).

    Returns
    -------
    weather, metadata
        The (possibly re-stamped) weather and a copy of the metadata with ``weather_year``: a
        dict ``{"kind": "typical" | "actual", "years": [...], "statement": str}`` (the
        statement names the file, the years and the weekday alignment, for reports).

    Raises
    ------
    thermocal.errors.ThermocalInputError
        An actual-year file that does not cover the period (file, its years, the period).
    """
    meta = dict(metadata or {})
    source = source or str(meta.get("source", "the weather"))
    index = pd.DatetimeIndex(weather.index)
    tz = index.tz

    def instant(value):
        ts = pd.Timestamp(value)
        if ts.tzinfo is None and tz is not None:
            return ts.tz_localize(tz)
        return ts.tz_convert(tz) if tz is not None else ts

    t0, t1 = instant(start), instant(end)
    step = index[1] - index[0] if len(index) > 1 else pd.Timedelta("1h")
    file_end = index[-1] + step
    typical = meta.get("coerced_year") is not None
    if not typical:
        years = sorted({int(index[0].year), int(index[-1].year)})
        shown = "-".join(str(y) for y in dict.fromkeys(years))
        if t0 < index[0] or t1 > file_end:
            truncated = incomplete_file_statement(weather, meta)
            if truncated is not None:  # not an actual year: a file cut short
                raise ThermocalInputError(
                    f"weather file {source} does not cover the period [{t0}, {t1}): "
                    f"{truncated}; use the complete file (a typical-year file, TMY/EPW, follows "
                    "the year of the measurements), or the weather measured over that period."
                )
            raise ThermocalInputError(
                f"weather file {source}: an actual-year file of {shown} covering "
                f"[{index[0]}, {file_end}) does not cover the period [{t0}, {t1}); give the "
                "weather measured over that period (or a typical-year file, TMY/EPW with months "
                "from several years, which follows the year of the measurements)."
            )
        meta["weather_year"] = {
            "kind": "actual",
            "years": years,
            "statement": f"weather file {source}: actual year {shown}, covering the period",
        }
        return weather, meta
    file_year = int(meta["coerced_year"])
    years = list(range(int(t0.year), int(t1.year) + 1))
    local = index.tz_localize(None) if tz is not None else index
    month, day = local.month.to_numpy(), local.day.to_numpy()
    time_of_day = (local - local.normalize()).to_numpy()
    feb29 = (month == 2) & (day == 29)
    feb28 = (month == 2) & (day == 28)
    parts = []
    for year in years:
        leap = calendar.isleap(year)
        keep = ~feb29 if not leap else np.ones(len(local), dtype=bool)
        frame = weather[keep].copy()
        dates = (
            pd.to_datetime(
                pd.DataFrame({"year": year, "month": month[keep], "day": day[keep]})
            ).to_numpy()
            + time_of_day[keep]
        )
        stamps = pd.DatetimeIndex(dates)
        if leap and not feb29.any():
            extra = weather[feb28].copy()
            extra_dates = (
                pd.to_datetime(
                    pd.DataFrame({"year": year, "month": 2, "day": np.full(int(feb28.sum()), 29)})
                ).to_numpy()
                + time_of_day[feb28]
            )
            frame = pd.concat([frame, extra])
            stamps = stamps.append(pd.DatetimeIndex(extra_dates))
        frame.index = stamps.tz_localize(tz) if tz is not None else stamps
        parts.append(frame)
    out = pd.concat(parts).sort_index()
    out = out[~out.index.duplicated(keep="first")]
    names = ", ".join(
        f"1 January {y} a {calendar.day_name[calendar.weekday(y, 1, 1)]}" for y in years
    )
    meta["coerced_year"] = years[0]
    meta["weather_year"] = {
        "kind": "typical",
        "file_year": file_year,
        "years": years,
        "statement": (
            f"typical-year weather file {source} put on {', '.join(map(str, years))}, the "
            f"year(s) of the measurements: every row keeps its month, day and hour; weekdays "
            f"(schedules, holidays) follow the measurement calendar ({names})"
            + (
                "; 29 February repeats 28 February"
                if any(calendar.isleap(y) for y in years) and not feb29.any()
                else ""
            )
        ),
    }
    return out, meta


def _rows_statement(index: pd.DatetimeIndex, step: pd.Timedelta, *, typical: bool) -> str:
    """``"4,344 hourly rows (181 days) from 1 January 00:00 to 30 June 23:00"`` (interval
    starts; the year left out for a typical year, whose year is thermocal's choice)."""
    every = "hourly" if step == pd.Timedelta(hours=1) else f"{step.total_seconds() / 60:g}-min"
    days = (index[-1] + step - index[0]) / pd.Timedelta(days=1)

    def shown(stamp: pd.Timestamp) -> str:  # no "%-d": not portable
        return f"{stamp.day} {stamp:%B %H:%M}" if typical else f"{stamp:%Y-%m-%d %H:%M}"

    return (
        f"{len(index):,} {every} rows ({days:,.4g} days) from {shown(index[0])} to "
        f"{shown(index[-1])}"
    )


def _file_clock(index: pd.DatetimeIndex, metadata: Mapping) -> pd.DatetimeIndex:
    """The index on the weather file's own clock (its standard time, ``metadata["tz"]``)."""
    tz = metadata.get("tz")
    if tz is None or index.tz is None:
        return index
    return index.tz_convert(as_timezone(tz, f"weather file {metadata.get('source', '')}"))


def _undelivered_period(weather: pd.DataFrame, metadata: Mapping) -> str | None:
    """``"its header's DATA PERIODS line declares data from 1/1 to 12/31"`` when the rows do not
    run from the first to the last day of the period the file declares; None otherwise."""
    period = metadata.get("data_period")
    index = pd.DatetimeIndex(weather.index)
    if not period or len(index) == 0:
        return None
    local = _file_clock(index, metadata)
    first, last = (local[0].month, local[0].day), (local[-1].month, local[-1].day)
    start, end = tuple(period["start"]), tuple(period["end"])
    if (first, last) == (start, end):
        return None
    return (
        f"{period['declared_by']} declares data from {start[0]}/{start[1]} to "
        f"{end[0]}/{end[1]}"
    )


def incomplete_file_statement(weather: pd.DataFrame, metadata: Mapping | None) -> str | None:
    """Say that a weather file looks truncated when its rows stop short of (or start after)
    the period it declares: an EPW's ``DATA PERIODS`` line, a TMY3's whole year.

    Parameters
    ----------
    weather : DataFrame
        From :func:`read_weather` (tz-aware index labelled by interval start).
    metadata : mapping or None
        Its metadata (``data_period``: ``{"start": (month, day), "end": (month, day),
        "declared_by": str}`` or None, ``tz`` [h east of UTC], ``coerced_year``).

    Returns
    -------
    str or None
        ``"it looks truncated or incomplete: its header's DATA PERIODS line declares data from
        1/1 to 12/31, but it holds 240 hourly rows (10 days) from ... to ..."``; None when the
        rows span the declared period or no period is declared (CSV).
    """
    meta = metadata or {}
    declared = _undelivered_period(weather, meta)
    if declared is None:
        return None
    index = _file_clock(pd.DatetimeIndex(weather.index), meta)
    typical = meta.get("coerced_year") is not None
    rows = _rows_statement(index, weather_step(weather), typical=typical)
    return f"it looks truncated or incomplete: {declared}, but it holds {rows}"


def check_full_year(
    weather: pd.DataFrame,
    metadata: Mapping | None,
    *,
    source: str,
    needed_for: str = "the annual heating demand",
) -> None:
    """Refuse weather that is not one whole year (an annual result from it would be a part
    year's, or several years').

    Parameters
    ----------
    weather : DataFrame
        From :func:`read_weather` (regular, tz-aware index labelled by interval start).
    metadata : mapping or None
        Its metadata (``data_period``, ``tz``, ``coerced_year``: see
        :func:`incomplete_file_statement`).
    source : str
        The weather file, for the message.
    needed_for : str
        What needs the year, for the message.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Unless the rows span 365 or 366 days (a typical year's 8,760 or 8,784 hours, or an
        actual year); the message names the file, its rows and their dates, whether it looks
        truncated, and what is needed.
    """
    index = pd.DatetimeIndex(weather.index)
    if len(index) == 0:
        raise ThermocalInputError(f"weather file {source} holds no rows; {needed_for} needs a year")
    step = weather_step(weather)
    span = index[-1] + step - index[0]
    if span in (pd.Timedelta(days=365), pd.Timedelta(days=366)):
        return
    meta = metadata or {}
    typical = meta.get("coerced_year") is not None
    rows = _rows_statement(_file_clock(index, meta), step, typical=typical)
    declared = _undelivered_period(weather, meta)
    remedy = (
        "one year of it, or a typical-year file (TMY/EPW) of the site"
        if span > pd.Timedelta(days=366)
        else "the complete file (a typical year, e.g. the site's TMY/EPW), or a whole year "
        "of measured weather"
    )
    raise ThermocalInputError(
        f"weather file {source}: {needed_for} needs one whole year of weather (a typical "
        f"year's 8,760 hours, or an actual year of 365 or 366 days), but the "
        f"{'typical-year ' if typical else ''}file holds {rows}"
        + (f"; it looks truncated or incomplete: {declared}" if declared else "")
        + f". Use {remedy}"
    )


def weather_step(weather: pd.DataFrame) -> pd.Timedelta:
    """The regular time step of a weather frame.

    Parameters
    ----------
    weather : pandas.DataFrame
        Frame with a regular DatetimeIndex.

    Returns
    -------
    pandas.Timedelta
        The step; one hour for a single-row frame.
    """
    index = weather.index
    if len(index) < 2:
        return pd.Timedelta(hours=1)
    steps = np.diff(_ns(index))
    step = int(np.median(steps))
    return pd.Timedelta(step, unit="ns")


def resample_weather(weather: pd.DataFrame, step: str | pd.Timedelta) -> pd.DataFrame:
    """Resample a standard weather frame to another regular step.

    Interval quantities (irradiance, albedo) become exact means over the new intervals (the
    source is treated as piecewise constant over its intervals, so energy is conserved in up- and
    down-sampling); a new interval less than half covered by valid data is NaN. Instant
    quantities (temperatures, humidity, pressure, wind speed) are interpolated linearly in time at
    the new labels; wind direction is interpolated as a unit vector. Instant values beyond the
    last source label are held. Other columns are treated as instant values.

    Parameters
    ----------
    weather : pandas.DataFrame
        Standard weather frame (interval-start labels, regular step).
    step : str or pandas.Timedelta
        New step, e.g. ``"5min"`` or ``"1h"``.

    Returns
    -------
    pandas.DataFrame
        Same columns, index from the first label to the end of the covered period, labelled by
        interval start.
    """
    if not isinstance(weather.index, pd.DatetimeIndex):
        raise ThermocalInputError("resample_weather: the weather frame needs a DatetimeIndex")
    try:
        new_step = pd.Timedelta(step)
    except ValueError as exc:
        raise ThermocalInputError(
            f"resample_weather: cannot read step {step!r} (use e.g. '5min' or '1h')"
        ) from exc
    if new_step <= pd.Timedelta(0):
        raise ThermocalInputError(f"resample_weather: step must be positive, got {step!r}")
    _check_time_index(weather.index, "weather frame", "index", 0)
    old_step = weather_step(weather)
    start = weather.index[0]
    end = weather.index[-1] + old_step
    n_new = int((end - start) // new_step)
    new_index = pd.date_range(start, periods=n_new, freq=new_step).as_unit(weather.index.unit)
    t_old = (_ns(weather.index) - start.value).astype(float)
    t_new = (_ns(new_index) - start.value).astype(float)
    out = pd.DataFrame(index=new_index)
    for column in weather.columns:
        values = weather[column].to_numpy(dtype=float)
        if column in INTERVAL_COLUMNS:
            out[column] = _interval_means(values, t_old, old_step.value, t_new, new_step.value)
        elif column == "wind_direction":
            rad = np.deg2rad(values)
            east = _interp_nan(t_new, t_old, np.sin(rad))
            north = _interp_nan(t_new, t_old, np.cos(rad))
            out[column] = np.mod(np.rad2deg(np.arctan2(east, north)), 360.0)
        else:
            out[column] = _interp_nan(t_new, t_old, values)
    return out


# --------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------
def _detect_format(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix == ".epw":
        return "epw"
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as handle:
            first = handle.readline()
            second = handle.readline()
    except OSError as exc:
        raise ThermocalInputError(f"weather file {path} cannot be opened: {exc}") from exc
    if first.upper().startswith("LOCATION,"):
        return "epw"
    if "Date (MM/DD/YYYY)" in second:
        return "tmy3"
    if suffix in (".csv", ".txt", ".tsv"):
        return "csv"
    raise ThermocalInputError(
        f"weather file {path}: cannot tell the format from the extension or the content; "
        "pass format='epw', 'tmy3' or 'csv'"
    )


def _read_epw_header(path: Path) -> dict:
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as handle:
            lines = [handle.readline() for _ in range(8)]
    except OSError as exc:
        raise ThermocalInputError(f"weather file {path} cannot be opened: {exc}") from exc
    if not lines[0].upper().startswith("LOCATION"):
        raise ThermocalInputError(
            f"weather file {path}, line 1: an EPW file starts with 'LOCATION,...', found "
            f"{lines[0][:40]!r}"
        )
    records_per_hour = 1
    start_weekday = None
    ground: dict[float, list[float]] = {}
    holidays: list[tuple[str, str]] = []
    daylight_saving = None
    data_period = None
    for number, line in enumerate(lines, start=1):
        fields = [f.strip() for f in line.rstrip("\n").split(",")]
        key = fields[0].upper()
        if key == "DATA PERIODS" and len(fields) >= 5:
            try:
                records_per_hour = int(fields[2])
            except ValueError as exc:
                raise ThermocalInputError(
                    f"weather file {path}, line {number} (DATA PERIODS): the number of records "
                    f"per hour {fields[2]!r} is not an integer"
                ) from exc
            if records_per_hour < 1 or 60 % records_per_hour:
                raise ThermocalInputError(
                    f"weather file {path}, line {number} (DATA PERIODS): {records_per_hour} "
                    "records per hour does not divide an hour"
                )
            start_weekday = _WEEKDAYS.get(fields[4].lower())
            if fields[1] == "1" and len(fields) >= 7:  # one period: its first and last day
                begin, end = _month_day(fields[5]), _month_day(fields[6])
                data_period = (begin, end) if begin and end else None
        elif key == "GROUND TEMPERATURES" and len(fields) > 2:
            try:
                n_depths = int(fields[1])
                for i in range(n_depths):
                    block = fields[2 + 16 * i : 2 + 16 * (i + 1)]
                    ground[float(block[0])] = [float(v) for v in block[4:16]]
            except (ValueError, IndexError):
                ground = {}  # informative header only: ignore a malformed one
        elif key.startswith("HOLIDAYS/DAYLIGHT SAVING") and len(fields) >= 5:
            # LeapYear Observed, DST start, DST end, number of holidays, (name, date) pairs;
            # dates as EnergyPlus writes them ('1/1', 'Jan 1', 'Last Monday in May', ...),
            # "0" for no DST; kept as text (read by the IDF schedules' calendar)
            if fields[2] not in ("", "0") and fields[3] not in ("", "0"):
                daylight_saving = (fields[2], fields[3])
            try:
                n_holidays = int(float(fields[4] or 0))
            except ValueError:
                n_holidays = 0  # informative header only: ignore a malformed count
            pairs = fields[5 : 5 + 2 * n_holidays]
            holidays = [
                (pairs[i], pairs[i + 1])
                for i in range(0, len(pairs) - 1, 2)
                if pairs[i + 1] not in ("", "0")
            ]
    return {
        "records_per_hour": records_per_hour,
        "start_weekday": start_weekday,
        "ground_temperatures": ground,
        "holidays": holidays,
        "daylight_saving": daylight_saving,
        "data_period": data_period,
    }


def _month_day(text: str) -> tuple[int, int] | None:
    """``" 1/ 1"`` or ``"12/31"`` (an EPW DATA PERIODS date) -> (month, day); None otherwise."""
    parts = text.replace(" ", "").split("/")
    if len(parts) != 2 or not all(part.isdigit() for part in parts):
        return None
    month, day = int(parts[0]), int(parts[1])
    return (month, day) if 1 <= month <= 12 and 1 <= day <= 31 else None


#: Continuous weather fields whose isolated missing values :func:`fill_short_gaps` fills.
INTERPOLATED_COLUMNS = ("temp_air", "temp_dew", "relative_humidity", "pressure",
                        "ghi_infrared", "wind_speed")  # fmt: skip


def fill_short_gaps(
    weather: pd.DataFrame, *, max_gap: int = 3, columns=INTERPOLATED_COLUMNS
) -> tuple[pd.DataFrame, list[str]]:
    """Interpolate runs of at most ``max_gap`` missing values of continuous fields.

    One missing infrared value must not switch a whole simulation to another sky model, nor
    one missing temperature stop it; longer gaps stay missing for the consumer to decide.

    Parameters
    ----------
    weather : DataFrame
        Standard weather frame (see :func:`read_weather`).
    max_gap : int
        Longest run of missing values filled [rows].
    columns : iterable of str
        Columns considered (default :data:`INTERPOLATED_COLUMNS`).

    Returns
    -------
    weather : DataFrame
        A copy with the short gaps filled linearly.
    notes : list of str
        One line per column filled (count and first time stamp), to be said aloud.
    """
    out = weather.copy()
    notes: list[str] = []
    for column in columns:
        if column not in out:
            continue
        missing = out[column].isna().to_numpy()
        if not missing.any() or missing.all():
            continue
        runs = np.cumsum(np.r_[True, missing[1:] != missing[:-1]])
        run_length = pd.Series(missing).groupby(runs).transform("sum").to_numpy()
        short = missing & (run_length <= max_gap)
        if not short.any():
            continue
        filled = out[column].interpolate(limit_direction="both").to_numpy()
        out[column] = np.where(short, filled, out[column].to_numpy())
        first = out.index[int(np.flatnonzero(short)[0])]
        notes.append(
            f"{int(short.sum())} missing value(s) of {column!r} in gaps of at most {max_gap} "
            f"rows interpolated (first at {first})"
        )
    return out, notes


def _epw_buffer(path: Path) -> io.StringIO:
    """The EPW text, data lines padded to the 35 fields pvlib expects.

    Older EPW files (e.g. the ASHRAE 140 ``DRYCOLDTMY.epw``) end after field 32 and lack albedo
    and liquid precipitation; the padded fields read as missing.
    """
    try:
        text = path.read_text(encoding="utf-8-sig", errors="replace")
    except OSError as exc:
        raise ThermocalInputError(f"weather file {path} cannot be opened: {exc}") from exc
    lines = text.splitlines()
    n_fields = _EPW_FIELDS
    counts = [line.count(",") + 1 for line in lines[8:] if line.strip()]
    if not counts:
        raise ThermocalInputError(
            f"weather file {path}: no data lines after the 8 header lines (a truncated "
            "download?); download the file again"
        )
    usual = max(set(counts), key=counts.count)
    first = next(i for i in range(8, len(lines)) if lines[i].strip())
    for separator, word in ((";", "semicolons"), ("\t", "tabs")):
        if usual < _EPW_MIN_FIELDS and lines[first].count(separator) >= _EPW_MIN_FIELDS - 1:
            raise ThermocalInputError(
                f"weather file {path}, line {first + 1}: the fields are separated by {word}; an "
                "EPW file is comma-separated (a spreadsheet's export?): save it with commas"
            )
    if usual < _EPW_MIN_FIELDS:
        raise ThermocalInputError(
            f"weather file {path}: its data lines have {usual} comma-separated fields where an "
            f"EPW data line has {n_fields}: {', '.join(_EPW_FIELD_NAMES[usual:_EPW_MIN_FIELDS])} "
            "are missing (a file cut to fewer columns?); use the complete file"
        )
    for i in range(8, len(lines)):
        count = lines[i].count(",") + 1
        if count < usual and lines[i].strip():
            raise ThermocalInputError(
                f"weather file {path}, line {i + 1}: only {count} comma-separated fields where "
                f"the other data lines have {usual} (a line cut short: a truncated or corrupt "
                "file); restore the line or download the file again"
            )
        if count < n_fields and lines[i].strip():
            lines[i] = lines[i] + "," * (n_fields - count)
    return io.StringIO("\n".join(lines) + "\n")


def _diagnose_epw(path: Path, exc: Exception) -> None:
    """Raise a precise error for an EPW file pvlib could not parse (if we can find why)."""
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as handle:
            lines = handle.readlines()
    except OSError:
        return
    for number, line in enumerate(lines[8:], start=9):
        fields = line.rstrip("\n").split(",")
        if len(fields) < 22:
            raise ThermocalInputError(
                f"weather file {path}, line {number}: only {len(fields)} comma-separated fields, "
                "an EPW data line has 35 (truncated or corrupt line)"
            ) from exc
        for position, name in ((0, "year"), (1, "month"), (2, "day"), (3, "hour")):
            try:
                int(float(fields[position]))
            except ValueError:
                raise ThermocalInputError(
                    f"weather file {path}, line {number}, field {position + 1} ({name}): "
                    f"{fields[position]!r} is not a number"
                ) from exc


def _diagnose_tmy3(path: Path, exc: Exception) -> None:
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            lines = handle.readlines()
    except OSError:
        return
    if len(lines) < 3 or "Date (MM/DD/YYYY)" not in lines[1]:
        raise ThermocalInputError(
            f"weather file {path}, line 2: a TMY3 file has the column names on line 2 starting "
            "with 'Date (MM/DD/YYYY),Time (HH:MM)'"
        ) from exc
    for number, line in enumerate(lines[2:], start=3):
        fields = line.split(",")
        try:
            pd.to_datetime(fields[0], format="%m/%d/%Y")
            hour, minute = fields[1].split(":")
            int(hour), int(minute)
        except (ValueError, IndexError):
            raise ThermocalInputError(
                f"weather file {path}, line {number}: cannot read the date/time "
                f"{','.join(fields[:2])!r} (expected MM/DD/YYYY,HH:MM)"
            ) from exc


def _require_numeric(
    raw: pd.DataFrame, column: str, path: Path | str, *, first_line: int, what: str
) -> None:
    series = raw[column]
    if pd.api.types.is_numeric_dtype(series):
        return
    converted = pd.to_numeric(series, errors="coerce")
    bad = converted.isna() & series.notna()
    if bad.any():
        row = int(np.flatnonzero(bad.to_numpy())[0])
        raise ThermocalInputError(
            f"weather file {path}, {what} {column!r}, line {row + first_line}: "
            f"{series.iloc[row]!r} is not a number"
        )
    raw[column] = converted


def _check_plausible(
    frame: pd.DataFrame,
    path: Path | str,
    *,
    first_line: int,
    names: Mapping[str, str] | None = None,
) -> None:
    for column in frame.columns:
        low, high, unit = _PLAUSIBLE[column]
        values = frame[column].to_numpy(dtype=float)
        label = f"{names[column]!r} (mapped to {column})" if names else repr(column)
        bad = (values < low) | (values > high)
        if not bad.any():
            continue
        row = int(np.flatnonzero(bad)[0])
        hint = ""
        finite = values[np.isfinite(values)]
        if column in ("temp_air", "temp_dew") and finite.size and np.median(finite) > 200:
            hint = " (looks like Kelvin: subtract 273.15)"
        elif column == "pressure" and finite.size and np.median(finite) < 2000:
            hint = " (looks like hPa/mbar: multiply by 100)"
        elif column == "relative_humidity" and finite.size and np.max(finite) <= 1.0:
            hint = " (looks like a fraction: multiply by 100)"
        raise ThermocalInputError(
            f"weather file {path}, column {label}, line {row + first_line}: value "
            f"{values[row]:g} outside the plausible range [{low:g}, {high:g}] {unit}{hint}"
        )
    if names is not None and "relative_humidity" in frame:
        finite = frame["relative_humidity"].dropna().to_numpy()
        if finite.size and finite.max() <= 1.0:
            raise ThermocalInputError(
                f"weather file {path}, column {names['relative_humidity']!r}: relative humidity "
                "never exceeds 1; it looks like a fraction: give it in % (multiply by 100)"
            )


def _check_time_index(index: pd.DatetimeIndex, path: Path | str, column: str, first_line: int):
    if len(index) < 2:
        return
    diffs = np.diff(_ns(index))
    if (diffs <= 0).any():
        row = int(np.flatnonzero(diffs <= 0)[0]) + 1
        kind = "duplicated" if diffs[row - 1] == 0 else "earlier than the previous one"
        raise ThermocalInputError(
            f"weather file {path}, column {column!r}, line {row + first_line}: time stamp "
            f"{index[row]} is {kind}; sort the file and remove duplicates"
        )
    step = diffs[0]
    irregular = diffs != step
    if irregular.any():
        row = int(np.flatnonzero(irregular)[0]) + 1
        raise ThermocalInputError(
            f"weather file {path}, column {column!r}, line {row + first_line}: time step "
            f"{pd.Timedelta(int(diffs[row - 1]), unit='ns')} differs from the first step "
            f"{pd.Timedelta(int(step), unit='ns')}; weather data must be on a regular grid "
            "(fill or resample the gap first)"
        )


#: Largest difference between a weather file's time zone and its longitude's solar time [h]
#: (western China's UTC+8 at 75 E is 3 h; a time zone whose sign is flipped is 10-14 h off).
MAX_TIME_ZONE_OFFSET_H = 4.0


def _checked_utc_offset(meta: dict, path: Path) -> float:
    """The file's time zone [h east of UTC], refused when its longitude contradicts it.

    A time zone with a flipped sign (+7 for Denver) puts the sun at night: the simulation
    runs, silently wrong.
    """
    utc_offset = float(meta["TZ"])
    longitude = float(meta["longitude"])
    off = (utc_offset - longitude / 15.0 + 12.0) % 24.0 - 12.0
    if abs(off) > MAX_TIME_ZONE_OFFSET_H:
        raise ThermocalInputError(
            f"weather file {path}: its time zone {utc_offset:+g} h does not fit its longitude "
            f"{longitude:g} deg (about {longitude / 15.0:+.0f} h; east is positive): the sun "
            "would shine at the wrong hours; check the sign of the time zone (and of the "
            "longitude) in the file's header"
        )
    return utc_offset


def _dates_with_years(
    ymd: pd.DataFrame,
    offset: pd.Series,
    step: pd.Timedelta,
    path: Path,
    *,
    first_line: int,
    coerce_year: int | None,
    first_weekday: int | None,
) -> tuple[pd.Series, int | None]:
    """Interval-start stamps from year/month/day + offset; coerce years when needed."""
    month = ymd["month"].to_numpy()
    day = ymd["day"].to_numpy()
    bad = (month < 1) | (month > 12) | (day < 1) | (day > 31)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise ThermocalInputError(
            f"weather file {path}, line {row + first_line}: invalid month/day "
            f"{month[row]}/{day[row]}"
        )

    def build(years: np.ndarray) -> pd.Series:
        frame = pd.DataFrame({"year": years, "month": month, "day": day})
        dates = pd.to_datetime(frame, errors="coerce")
        if dates.isna().any():
            row = int(np.flatnonzero(dates.isna().to_numpy())[0])
            raise ThermocalInputError(
                f"weather file {path}, line {row + first_line}: the date "
                f"{years[row]}-{month[row]:02d}-{day[row]:02d} does not exist (29 February in a "
                "non-leap year?); pass coerce_year= a leap year"
            )
        return dates + offset.to_numpy()

    years = ymd["year"].to_numpy()
    coerced: int | None = None
    if coerce_year is None:
        if np.all(years == years[0]) or _regular(build(years), step):
            stamps = build(years)
        else:
            has_feb29 = bool(np.any((month == 2) & (day == 29)))
            coerced = _typical_year(int(month[0]), int(day[0]), first_weekday, has_feb29)
            stamps = build(np.full_like(years, coerced))
    else:
        coerced = int(coerce_year)
        stamps = build(np.full_like(years, coerced))
    values = stamps.to_numpy()
    diffs = np.diff(values).astype("timedelta64[ns]").astype(np.int64)
    wrong = diffs != step.value
    if wrong.any():
        row = int(np.flatnonzero(wrong)[0]) + 1
        after = pd.Timestamp(values[row])
        if coerced is not None and calendar.isleap(coerced) and (after.month, after.day) == (3, 1) \
                and not np.any((month == 2) & (day == 29)):  # fmt: skip
            raise ThermocalInputError(
                f"weather file {path}: a year without 29 February put on {coerced}, a leap "
                f"year (line {row + first_line} follows 28 February with 1 March): give a "
                "year that is not a leap year (for an IDF, leave the RunPeriod's Begin Year "
                "blank or use a common year), or a weather file with 29 February"
            )
        raise ThermocalInputError(
            f"weather file {path}, line {row + first_line}: time stamp "
            f"{pd.Timestamp(values[row])} (interval start) does not follow "
            f"{pd.Timestamp(values[row - 1])} by one step of {step}; rows are missing, "
            "duplicated or out of order"
        )
    return stamps, coerced


def _regular(stamps: pd.Series, step: pd.Timedelta) -> bool:
    values = stamps.to_numpy().astype("datetime64[ns]").astype(np.int64)
    return bool(np.all(np.diff(values) == step.value))


def _typical_year(month: int, day: int, weekday: int | None, leap: bool) -> int:
    candidates = [y for y in range(2023, 2000, -1) if calendar.isleap(y) == leap]
    if weekday is None:
        return 2004 if leap else 2001
    for year in candidates:
        if calendar.weekday(year, month, day) == weekday:
            return year
    return candidates[0]


def _covers_whole_year(index: pd.DatetimeIndex, step: pd.Timedelta) -> bool:
    if len(index) == 0:
        return False
    span = index[-1] + step - index[0]
    return (
        index[0].month == 1
        and index[0].day == 1
        and span
        in (
            pd.Timedelta(days=365),
            pd.Timedelta(days=366),
        )
    )


def _present_weather_rain(raw: pd.DataFrame) -> np.ndarray | None:
    """EPW present weather as EnergyPlus reads it: rain (1.0) when the observation indicator is 0
    and one of the first three weather-code digits (thunderstorm, rain, rain squalls/drizzle) is
    below 9; None when no row has an observation (indicator 9 everywhere, the usual case)."""
    if "present_weather_observation" not in raw or "present_weather_codes" not in raw:
        return None
    obs = pd.to_numeric(raw["present_weather_observation"], errors="coerce").to_numpy()
    if not np.any(obs == 0):
        return None
    written = raw["present_weather_codes"].astype(str).str.strip()
    # a code written as a number lost its leading zeros (restored); a blank one says nothing
    codes = written.where(written.str.fullmatch(r"\d{1,9}"), "999999999").str.zfill(9)
    wet = codes.str[:3].apply(lambda c: any(int(ch) < 9 for ch in c))
    return np.where((obs == 0) & wet.to_numpy(dtype=bool), 1.0, 0.0)


def _instant_values_to_true_time(frame: pd.DataFrame, *, wrap: bool) -> pd.DataFrame:
    """Move instant values from hour-ending rows to their true time (the next row's label)."""
    out = frame.copy()
    for column in frame.columns:
        if column not in INSTANT_COLUMNS:
            continue
        values = frame[column].to_numpy(dtype=float)
        shifted = np.empty_like(values)
        shifted[1:] = values[:-1]
        shifted[0] = values[-1] if wrap else values[0]
        out[column] = shifted
    return out


def _interval_means(
    values: np.ndarray, t_old: np.ndarray, old_step: int, t_new: np.ndarray, new_step: int
) -> np.ndarray:
    """Exact means over new intervals of a piecewise-constant signal (NaN-aware)."""
    valid = np.isfinite(values)
    edges_old = np.append(t_old, t_old[-1] + old_step)
    energy = np.concatenate([[0.0], np.cumsum(np.where(valid, values, 0.0) * old_step)])
    covered = np.concatenate([[0.0], np.cumsum(valid * float(old_step))])
    edges_new = np.append(t_new, t_new[-1] + new_step) if len(t_new) else t_new
    e = np.interp(edges_new, edges_old, energy)
    c = np.interp(edges_new, edges_old, covered)
    d_energy = np.diff(e)
    d_cover = np.diff(c)
    with np.errstate(invalid="ignore", divide="ignore"):
        means = d_energy / d_cover
    means[d_cover < 0.5 * new_step] = np.nan
    return means


def _interp_nan(t_new: np.ndarray, t_old: np.ndarray, values: np.ndarray) -> np.ndarray:
    valid = np.isfinite(values)
    if not valid.any():
        return np.full(t_new.shape, np.nan)
    out = np.interp(t_new, t_old[valid], values[valid])
    # do not bridge gaps: a new point between two valid neighbours more than one old step apart
    # from a missing value is NaN
    if not valid.all():
        nearest = np.searchsorted(t_old, t_new, side="right") - 1
        nearest = np.clip(nearest, 0, len(t_old) - 1)
        following = np.clip(nearest + 1, 0, len(t_old) - 1)
        on_point = t_new == t_old[nearest]
        missing = ~valid[nearest] | (~on_point & ~valid[following])
        out[missing] = np.nan
    return out


def _ns(index: pd.DatetimeIndex) -> np.ndarray:
    """Integer nanoseconds of a DatetimeIndex whatever its resolution (pandas 3 uses us)."""
    return index.as_unit("ns").asi8


def _is_fixed(tzinfo) -> bool:
    import datetime as _dt

    return isinstance(tzinfo, _dt.timezone)


def _float_or_none(value) -> float | None:
    return None if value is None else float(value)
