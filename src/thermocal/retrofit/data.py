"""Reading and checking the measurements of the retrofit workflow.

The measurement file is a CSV (or parquet) table with a time column and one column per
quantity (names mapped by the configuration). Timestamps label the START of the averaging
interval (thermocal convention); naive timestamps are local standard time of the configured
time zone (default: the building's). The file is read by
:func:`thermocal.io.measurements.read_measurements` (wide layout, rows = interval means, units
declared from the configuration); the retrofit-specific checks (flow sign, Kelvin, irradiance
sign and magnitude) follow, with messages naming the configured column. Everything is then
averaged onto the configured step by :func:`thermocal.io.measurements.resample_measurements`,
which also reports the data quality.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import QualityReport
from thermocal.physics.hydronics import heating_power
from thermocal.retrofit.config import (
    FUEL_VOLUME_UNITS,
    MEASUREMENT_COLUMNS,
    MeasurementsConfig,
)
from thermocal.textformat import duration_text

TEMPERATURE_COLUMNS = ("temp_out", "temp_supply", "temp_return", "temp_in")
#: Highest supply or return water temperature [C] (liquid water at ambient pressure), and
#: highest indoor or outdoor air temperature [C]; above, a unit slip.
WATER_LIMIT, AIR_LIMIT = 100.0, 150.0
#: Irradiance above this [W/m2] is impossible at the ground (the solar constant is 1361 W/m2);
#: the upper physical limit of :func:`thermocal.io.measurements.resample_measurements`.
IRRADIANCE_LIMIT = 1600.0


def _timezone(tz):
    """A time zone for :func:`read_measurements`: a name, or a fixed offset [h] as float."""
    if tz is None:
        return None
    if isinstance(tz, int | float):
        return float(tz)
    return tz


#: The reader's remedies name its Python options; the retrofit user has the configuration.
_READER_REMEDIES = (
    ("; pass time_column=", "; set measurements.time_column in the retrofit configuration"),
    (": sort it, or pass sort=True", ": sort the file by time"),
    ("(a decimal comma: pass decimal=',')", "(a decimal comma: set measurements.decimal: ',')"),
    ("pass time_format=", "set measurements.time_format"),
    ("pass tz=", "set measurements.timezone"),
    ("pass the time zone (--tz Europe/Zurich)", "set measurements.timezone (e.g. Europe/Zurich)"),
    ("pass a fixed offset, e.g. tz=1.0", "set measurements.timezone to an offset, e.g. 1.0"),
    (", or pass duplicates='first' or 'last'", ""),
    ("; pass interval=", "; supply more than one row"),
)
#: A log whose times are numbers: the retrofit configuration has no key for their unit.
_NUMERIC_TIMES = re.compile(r"(the times are numbers \([^)]*\)); give their unit.*$", re.S)


def _units(cfg: MeasurementsConfig, electricity_unit: str | None = None) -> dict[str, str]:
    """The unit of every mapped file column, from the configuration."""
    # a fuel volume is read as kWh and multiplied by the fuel's energy per unit afterwards
    heat = "kWh" if cfg.heat_unit in FUEL_VOLUME_UNITS else cfg.heat_unit
    unit = {"flow": cfg.flow_unit, "heat": heat, "dni": "W/m2", "dhi": "W/m2", "ghi": "W/m2"}
    unit.update({name: cfg.temperature_unit_of(name) for name in TEMPERATURE_COLUMNS})
    if electricity_unit:
        unit["electricity"] = electricity_unit
    return {col: unit.get(std, "C") for std, col in cfg.columns.items()}


def with_beam_and_diffuse(grid: pd.DataFrame, cfg: MeasurementsConfig, location) -> pd.DataFrame:
    """The averaged measurements with ``dni`` and ``dhi`` [W/m2]: as measured, or, for a
    pyranometer's global horizontal irradiance (``measurements.irradiance: ghi``), split by
    :func:`thermocal.physics.solar.beam_and_diffuse_from_global` at the building's site.

    Parameters
    ----------
    grid : DataFrame
        From :func:`prepare_measurements` (``ghi`` [W/m2] when the configuration says so).
    cfg : MeasurementsConfig
    location : the building file's location (``latitude``, ``longitude`` [deg], ``altitude`` [m])
    """
    if cfg.irradiance != "ghi":
        return grid
    from thermocal.physics.solar import beam_and_diffuse_from_global

    split = beam_and_diffuse_from_global(
        grid["ghi"], float(location.latitude), float(location.longitude),
        float(getattr(location, "altitude", 0.0) or 0.0),
    )  # fmt: skip
    return grid.assign(dni=split["dni"], dhi=split["dhi"])


#: Solar constant [W/m2] (Kopp and Lean 2011).
SOLAR_CONSTANT = 1361.0


def irradiance_limits(index: pd.DatetimeIndex, location) -> dict[str, np.ndarray]:
    """The physically possible limits of the irradiance on ``index`` [W/m2]: the BSRN quality
    control's (Long and Dutton 2002) for the global and diffuse horizontal,
    ``S_a 1.5 mu0^1.2 + 100`` and ``S_a 0.95 mu0^1.2 + 50``, with ``S_a`` the solar constant
    at the day's sun-earth distance and ``mu0`` the cosine of the zenith at each interval's
    representative sun (:func:`thermocal.physics.solar.interval_solar_position`); NaN where the
    sun is below the horizon."""
    from thermocal.physics.solar import interval_solar_position

    position = interval_solar_position(
        index, float(location.latitude), float(location.longitude),
        float(getattr(location, "altitude", 0.0) or 0.0),
    )  # fmt: skip
    mu0 = np.cos(np.radians(position["apparent_zenith"].to_numpy(float)))
    day = np.asarray(index.day_of_year, float)
    s_a = SOLAR_CONSTANT * (1.0 + 0.033 * np.cos(2.0 * np.pi * day / 365.0))
    up = np.where(mu0 > 0.0, mu0, np.nan) ** 1.2
    return {"ghi": s_a * 1.5 * up + 100.0, "dhi": s_a * 0.95 * up + 50.0}


def check_irradiance_limits(
    grid: pd.DataFrame, cfg: MeasurementsConfig, location, source: str
) -> None:
    """Refuse a horizontal irradiance beyond what the sun can give at that hour, or too dim
    for W/m2 on the days the sun climbs (:func:`check_dim_irradiance`).

    A log with the direct normal and the diffuse columns swapped passes every range check
    (both are irradiances below 1,600 W/m2), and the fit then takes the beam for diffuse light:
    a wrong building with no error (the retrofit demo: HLC 694 instead of 570 W/K). The diffuse
    (or global) horizontal irradiance above the BSRN physically possible limit
    (:func:`irradiance_limits`) in more than 1 % of the sunlit rows (at least 3) is refused.

    Parameters
    ----------
    grid : DataFrame
        Averaged measurements with ``dhi`` (or ``ghi``) [W/m2].
    cfg : MeasurementsConfig
    location : the building file's location (``latitude``, ``longitude`` [deg], ``altitude`` [m])
    source : str
        The measurement file, for the message.
    """
    check_dim_irradiance(grid, cfg, location, source)
    std = "ghi" if cfg.irradiance == "ghi" else "dhi"
    values = grid[std].to_numpy(float)
    limit = irradiance_limits(grid.index, location)[std]
    sunlit = np.isfinite(limit) & np.isfinite(values)
    above = sunlit & (values > np.where(np.isfinite(limit), limit, np.inf))
    if above.sum() <= max(3, 0.01 * sunlit.sum()):
        return
    first = int(np.argmax(above))
    column = cfg.columns.get(std, std)
    what = "diffuse" if std == "dhi" else "global"
    hint = (
        "the direct normal and the diffuse columns may be swapped (measurements.columns.dni and "
        ".dhi)"
        if std == "dhi"
        else "the column may be the direct normal irradiance or not in W/m2"
    )
    raise ThermocalInputError(
        f"{source}, column '{column}' (measurements.columns.{std}): the {what} horizontal "
        f"irradiance exceeds what the sun can give (the BSRN physically possible limit, Long "
        f"and Dutton 2002) in {int(above.sum())} of {int(sunlit.sum())} sunlit rows, first at "
        f"{grid.index[first]} ({values[first]:.0f} W/m2 where the limit is "
        f"{limit[first]:.0f}): {hint}; check the building's location too"
    )


def check_dim_irradiance(
    grid: pd.DataFrame, cfg: MeasurementsConfig, location, source: str
) -> None:
    """Refuse irradiance columns too dim for W/m2 on the days the sun climbs at the building.

    :func:`thermocal.statespace.units.dim_irradiance` on the days whose noon sun rises above
    :data:`~thermocal.statespace.units.DIM_IRRADIANCE_NOON_SUN_DEG` at the building's latitude
    (:func:`~thermocal.statespace.units.daylight_rows`): a log in kW/m2 (or kWh/m2 per hour)
    is refused, a polar night (the sun below the horizon all day, a few W/m2 of twilight at
    most) is not.

    Parameters
    ----------
    grid : DataFrame
        Averaged measurements with the irradiance columns [W/m2] (``dni`` and ``dhi``, or
        ``ghi``; tz-aware DatetimeIndex).
    cfg : MeasurementsConfig
    location : the building file's location (``latitude`` [deg])
    source : str
        The measurement file, for the message.
    """
    from thermocal.statespace.units import (
        DIM_IRRADIANCE_NOON_SUN_DEG,
        DIM_IRRADIANCE_W_M2,
        daylight_rows,
        dim_irradiance,
    )

    solar = [std for std in cfg.irradiance_columns() if std in grid]
    if not solar or not len(grid):
        return
    days = (grid.index - grid.index[0]) / pd.Timedelta(days=1)
    daylight = daylight_rows(grid.index, float(location.latitude))
    dim = dim_irradiance(grid[solar].to_numpy(float), days, daylight)
    if dim is None:
        return
    peak, span = dim
    polar = "" if daylight.all() else " (days of a polar night and at its edges not counted)"
    keys = " and ".join(f"measurements.columns.{std}" for std in solar)
    raise ThermocalInputError(
        f"{source}: irradiance column(s) {' and '.join(repr(cfg.columns[std]) for std in solar)} "
        f"never exceed {peak:.2f} W/m2 over {span:.3g} days on which the noon sun at the "
        f"building's latitude ({float(location.latitude):g} deg) climbs above "
        f"{DIM_IRRADIANCE_NOON_SUN_DEG:g} deg{polar}, where sunlight gives more than "
        f"{DIM_IRRADIANCE_W_M2:g} W/m2; they must be in W/m2 (hourly Wh/m2 are the same "
        f"numbers; kWh/m2: multiply by 1000) in the columns of {keys}; check the building's "
        "location too"
    )


def clock_notes(raw: pd.DataFrame, cfg: MeasurementsConfig, location) -> list[str]:
    """Check the measurements' clock against the sun at the building: refuse two hours or
    more, say one hour in a note.

    The centre of the measured irradiance's days against the sun's
    (:func:`thermocal.io.measurements.check_clock_against_sun`, at the log's own resolution):
    two hours or more off (a wrong time zone) are refused naming the setting that fixes the
    clock; one hour is what time stamps labelling the interval's end (thermocal reads starts)
    or daylight-saving time give, and it moves every solar gain by an hour: a note. On the
    shipped logs the offset is 0; shifted by an hour, 1.

    Parameters
    ----------
    raw : DataFrame
        The measurements as read (:func:`read_raw_measurements`), with the irradiance columns
        [W/m2] (``dni`` and ``dhi``, or ``ghi``).
    cfg : MeasurementsConfig
    location : the building file's location (``latitude``, ``longitude`` [deg], ``timezone``)

    Raises
    ------
    ThermocalInputError
        The clock two hours or more off the sun.
    """
    from thermocal.io.measurements import check_clock_against_sun
    from thermocal.io.measurements.clock import hours_text

    columns = [c for c in cfg.irradiance_columns() if c in raw.columns]
    if not columns:
        return []
    setting = (
        f"measurements.timezone (now {cfg.timezone!r})"
        if cfg.timezone is not None
        else f"the building's location.timezone (now {location.timezone!r})"
    )
    source = f"measurement file {cfg.file}"
    hours = check_clock_against_sun(
        raw[columns].sum(axis=1, min_count=len(columns)),
        float(location.latitude), float(location.longitude), source=source,
        column=" + ".join(cfg.columns.get(c, c) for c in columns), timezone_setting=setting,
    )  # fmt: skip
    if abs(hours) < 1.0:
        return []
    direction = "later" if hours > 0 else "earlier"
    return [
        f"{source}: the measured irradiance's days are centred {hours_text(hours)} {direction} "
        "than the sun's "
        "at the building: time stamps labelling the interval's end "
        "(thermocal reads them as its start) or in daylight-saving time? Every solar gain is "
        "moved by that much; check the labels and measurements.timezone"
    ]


#: Mean indoor temperature of a heated home over the measured weeks [C]; outside, a unit slip
#: (or not the heated rooms' temperature).
HEATED_INDOOR_RANGE = (5.0, 35.0)
#: The measured outdoor temperature's mean over the measured days and the weather file's over
#: the same days of its year may differ by this much (a typical year against a real one)
#: before it is reported [K].
OUTDOOR_TOLERANCE = 12.0
#: A converted mean this close to the expected one identifies a unit slip [K].
UNIT_MATCH = 5.0


def _slip_remedy(label: str, name: str, column: str) -> str:
    """What to write in the retrofit configuration (or the file) for a unit slip."""
    unit = {"Kelvin?": "K", "Fahrenheit?": "F"}.get(label)
    if unit:
        return (
            f"set measurements.temperature_unit: {{{name}: {unit}}} (or {unit} for every "
            f"temperature column) in the retrofit configuration"
        )
    factor = 10 if label.startswith("tenths") else 100
    return f"divide the values of column '{column}' by {factor} in the file"


def check_temperature_units(
    grid: pd.DataFrame, weather: pd.DataFrame, cfg: MeasurementsConfig, source: str
) -> list[str]:
    """Refuse an indoor or outdoor temperature logged in another unit than declared.

    The reader refuses a Kelvin log declared in C (values above 100). A Fahrenheit log looks
    like a plausible number in C: a heated home at 68 (20 C), or a winter's outdoor air at 35
    (2 C), and the fit then returns a wrong building with no error. Two checks, on the
    averaged measurements:

    - the indoor temperature's mean over the measured weeks lies within
      :data:`HEATED_INDOOR_RANGE` (a heated home); outside it, the unit slip that brings it
      there is named (:func:`thermocal.io.measurements.units.temperature_unit_slip`:
      Fahrenheit, Kelvin, tenths or hundredths of a degree);
    - the outdoor temperature's mean over the measured days against the weather file's mean
      over the same days of its year: more than :data:`OUTDOOR_TOLERANCE` apart and within
      :data:`UNIT_MATCH` once converted from Fahrenheit, it is refused; more than the tolerance
      apart otherwise, a note (the weather file of another place, or an exceptional period).

    Parameters
    ----------
    grid : DataFrame
        Averaged measurements with ``temp_in`` and ``temp_out`` [C as declared].
    weather : DataFrame
        The weather year with ``temp_air`` [C] (:func:`thermocal.retrofit.workflow.
        load_weather_year`).
    cfg : MeasurementsConfig
    source : str
        The measurement file, for the messages.

    Returns
    -------
    list of str
        Notes (the outdoor temperature far from the weather file's without a unit slip).

    Raises
    ------
    ThermocalInputError
        A unit slip, naming the column, the mean and the configuration key to set.
    """
    from thermocal.io.measurements.units import temperature_unit_slip

    notes: list[str] = []
    indoor = grid["temp_in"].to_numpy(float)
    if np.isfinite(indoor).any():
        mean = float(np.nanmean(indoor))
        slip = temperature_unit_slip(mean, plausible=HEATED_INDOOR_RANGE)
        if slip is not None:
            label, _, value = slip
            column = cfg.columns.get("temp_in", "temp_in")
            what = (
                f"{label} ({value:.1f} C): {_slip_remedy(label, 'temp_in', column)}"
                if np.isfinite(value)
                else "check its unit and that it is the heated rooms' air temperature"
            )
            raise ThermocalInputError(
                f"{source}, column '{column}' (measurements.columns.temp_in, declared in "
                f"{cfg.temperature_unit_of('temp_in')}): the indoor temperature averages "
                f"{mean:.1f} over the measurements, outside {HEATED_INDOOR_RANGE[0]:g}-"
                f"{HEATED_INDOOR_RANGE[1]:g} C for a heated home; {what}"
            )
    outdoor = grid["temp_out"].to_numpy(float)
    days = np.unique(grid.index.day_of_year)
    same = weather["temp_air"].to_numpy(float)[np.isin(weather.index.day_of_year, days)]
    if not (np.isfinite(outdoor).any() and np.isfinite(same).any()):
        return notes
    mean, expected = float(np.nanmean(outdoor)), float(np.nanmean(same))
    if abs(mean - expected) <= OUTDOOR_TOLERANCE:
        return notes
    column = cfg.columns.get("temp_out", "temp_out")
    period = f"{grid.index[0]:%Y-%m-%d} to {grid.index[-1]:%Y-%m-%d}"
    converted = (mean - 32.0) * 5.0 / 9.0
    if cfg.temperature_unit_of("temp_out") == "C" and abs(converted - expected) <= UNIT_MATCH:
        raise ThermocalInputError(
            f"{source}, column '{column}' (measurements.columns.temp_out, declared in C): the "
            f"outdoor temperature averages {mean:.1f} over {period}, the weather file's same "
            f"days {expected:.1f} C; Fahrenheit? ({converted:.1f} C): "
            + _slip_remedy("Fahrenheit?", "temp_out", column)
        )
    notes.append(
        f"the measured outdoor temperature averages {mean:.1f} C over {period}, the weather "
        f"file's same days {expected:.1f} C ({mean - expected:+.1f} K): the weather file may be "
        f"of another place (weather.file), or the outdoor column '{column}' of another unit or "
        "sensor; the annual demand uses the weather file's climate"
    )
    return notes


def read_raw_measurements(
    cfg: MeasurementsConfig, *, default_tz=None, electricity_unit: str | None = None
) -> pd.DataFrame:
    """Measurement table with standard column names [C, m3/s, W/m2], tz-aware DatetimeIndex.

    Read by :func:`thermocal.io.measurements.read_measurements` (CSV or parquet, ISO 8601
    times or ``measurements.time_format``, rows = interval means labelled by their start or,
    with ``measurements.rows: interval_end``, their end; ``measurements.decimal``);
    ``raw.attrs["measurements"]`` keeps its metadata (logging interval, units, notes). Only
    the columns of the configured heat source (``measurements.heat_source``) are read, plus
    the electricity meter when
    ``electricity_unit`` is given; meter columns come in W (power) or J (energy).

    Raises
    ------
    ThermocalInputError
        File missing or unreadable, time column missing or unparsable, duplicated or
        unsorted timestamps, a mapped column missing, non-numeric values, negative flows,
        temperatures that look like Kelvin, irradiance negative or beyond sunlight (a
        column too dim for W/m2 is refused by :func:`check_dim_irradiance`, which knows the
        building's latitude).
    """
    from thermocal.io.measurements import read_measurements

    path = Path(cfg.file)
    if not path.is_file():
        raise ThermocalInputError(f"measurement file {path} not found (measurements.file)")
    tz = _timezone(cfg.timezone) or _timezone(default_tz)
    needed = cfg.required_columns(electricity=electricity_unit is not None)
    names = {cfg.columns[std]: std for std in needed}
    try:
        raw, _ = read_measurements(
            path,
            layout="wide",
            time_column=cfg.time_column,
            sensors=names,
            units=_units(cfg, electricity_unit),
            tz=tz,
            rows=cfg.rows,
            decimal=cfg.decimal,
            time_format=cfg.time_format,
            unknown_sensors="ignore",
        )
    except ThermocalInputError as exc:
        text = str(exc)
        for option, remedy in _READER_REMEDIES:
            text = text.replace(option, remedy)
        text = _NUMERIC_TIMES.sub(
            r"\1; write them as dates and times (ISO 8601, e.g. 2021-01-04T00:00:00+01:00): the "
            "retrofit configuration reads no numeric time",
            text,
        )
        hint = ""
        if "not found" in text:
            named = [
                f"{col!r} is the {MEASUREMENT_COLUMNS[std]} (measurements.columns.{std})"
                for std, col in cfg.columns.items()
                if repr(col) in text and std in needed
            ]
            if named:
                hint = "; " + "; ".join(named) + ": map your column names there"
        raise ThermocalInputError(text + hint) from None
    if raw.index.tz is None:  # pragma: no cover - read_measurements localises naive times
        raise ThermocalInputError(
            f"measurement file {path}: timestamps have no time zone; set measurements.timezone"
        )
    out = raw[needed].copy()
    if cfg.heat_unit in FUEL_VOLUME_UNITS and "heat" in out:
        out["heat"] = out["heat"] * float(cfg.fuel_kWh_per_unit)  # read as kWh per unit
    index = out.index
    neg = out["flow"].to_numpy() < 0 if "flow" in out else np.zeros(len(out), bool)
    if neg.any():
        row = int(np.argmax(neg))
        raise ThermocalInputError(
            f"measurement file {path}: heating flow column {cfg.columns['flow']!r} is negative "
            f"({out['flow'].iloc[row] / _flow_factor(cfg):g} {cfg.flow_unit}) at row {row + 2} "
            f"({index[row]}); flows must be >= 0 (check the sensor direction or sign convention)"
        )
    for std in TEMPERATURE_COLUMNS:
        if std not in out:
            continue
        high = np.nanmax(out[std].to_numpy()) if out[std].notna().any() else np.nan
        # heating water is liquid (at most 100 C, the limit of the heating power's check)
        limit = WATER_LIMIT if std in ("temp_supply", "temp_return") else AIR_LIMIT
        if np.isfinite(high) and high > limit:
            # above 250 Kelvin; below it Fahrenheit (212 F boils; 113 F is 45 C)
            unit, value = ("K", high - 273.15) if high > 250.0 else ("F", (high - 32.0) / 1.8)
            # supply and return come from one controller: both are in that unit
            names = ("temp_supply", "temp_return") if limit == WATER_LIMIT else (std,)
            declared = ", ".join(f"{name}: {unit}" for name in names if name in out)
            raise ThermocalInputError(
                f"measurement file {path}: column {cfg.columns[std]!r} (measurements.columns."
                f"{std}, declared in {cfg.temperature_unit_of(std)}) reaches {high:.1f}; "
                f"{'Kelvin' if unit == 'K' else 'Fahrenheit'}? ({value:.1f} C): set "
                f"measurements.temperature_unit: {{{declared}}} (or {unit} for every "
                "temperature column) in the retrofit configuration"
            )
    solar = list(cfg.irradiance_columns())
    for std in solar:
        low = np.nanmin(out[std].to_numpy()) if out[std].notna().any() else 0.0
        if low < -10.0:
            raise ThermocalInputError(
                f"measurement file {path}: irradiance column {cfg.columns[std]!r} has "
                f"{low:.1f} W/m2 < 0"
            )
    for std in solar:
        values = out[std].to_numpy()
        above = values > IRRADIANCE_LIMIT
        sunny = np.isfinite(values) & (values > 5.0)
        if above.sum() > max(3, 0.01 * sunny.sum()):
            first = int(np.argmax(above))
            raise ThermocalInputError(
                f"measurement file {path}: irradiance column {cfg.columns[std]!r} exceeds "
                f"{IRRADIANCE_LIMIT:g} W/m2 in {int(above.sum())} of {int(sunny.sum())} sunny rows "
                f"(up to {np.nanmax(values):,.0f} W/m2, first at row {first + 2}, {index[first]}); "
                "sunlight never exceeds about 1,400 W/m2, so the column is not in W/m2 (a factor "
                "1000 points to kW vs W or W/m2 written as mW/m2): convert the column to W/m2"
            )
    out.attrs["measurements"] = raw.attrs["measurements"]
    return out


def _flow_factor(cfg: MeasurementsConfig) -> float:
    from thermocal.retrofit.config import FLOW_UNITS

    return FLOW_UNITS[cfg.flow_unit]


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
    "ghi": "irradiance",
    "phi_h": "power",
    "phi_el": "power",
}
#: The heating power may be slightly negative (supply below return within the sensor
#: uncertainty at a small flow); removing those values would bias the interval means.
PHI_H_LIMITS = (-1e8, 1e8)


def meter_power(
    values: pd.Series,
    *,
    energy: bool,
    cumulative: bool,
    interval,
    label: str = "the meter reading",
    unit: tuple[str, float] = ("kWh", 3.6e6),
) -> pd.Series:
    """Mean power [W] over each row's interval from a meter column.

    A cumulative reading's heat of a row is the next reading present minus this one, over the
    time between them (missing rows in between included). An energy per row covers the row's
    own logging interval ``[t, t + d)``, the span over which
    :func:`thermocal.io.measurements.resample_measurements` holds the row: until the column's
    next value but at most ``interval``, so ``d = min(t_next - t, interval)`` (``interval``
    for the last row). A missing row (a gap in a regular log) then stays missing, as for a
    power column, instead of spreading the row before it over two intervals at half its power.

    Parameters
    ----------
    values : pd.Series
        Power [W] (``energy`` False), energy of the row's interval [J], or a cumulative
        reading [J] (``cumulative``), rows labelled by the start of their interval.
    energy : bool
        The column is an energy (of the row's interval, or cumulative), not a power.
    cumulative : bool
        The column is a meter reading; a reading that falls or jumps up is refused
        (:func:`check_cumulative_reading`).
    interval : pd.Timedelta
        Logging interval [duration] (length of the last row's interval, and the longest an
        energy per row covers); None: the median spacing of the rows.
    label : str
        The file and column, for the message of a falling or jumping reading.
    unit : tuple of (str, float)
        The file's unit of the reading and its size [J], for that message.

    Returns
    -------
    pd.Series [W]; a cumulative reading gives NaN for the last row (no next reading), an
    energy per row NaN where the row's value is missing.
    """
    if not energy:
        return values.astype(float)
    t = values.index
    ns = t.as_unit("ns").asi8
    v = values.to_numpy(float)
    if cumulative:
        seconds = np.diff(ns) / 1e9 if len(t) > 1 else np.array([])
        seconds = np.append(seconds, pd.Timedelta(interval).total_seconds())
        check_cumulative_reading(values, label, unit)
        return pd.Series(np.append(np.diff(v), np.nan) / seconds, index=t)
    if interval is None and len(t) > 1:
        interval = pd.Series(t).diff().median()
    typical = pd.Timedelta(interval).total_seconds()
    present = np.flatnonzero(np.isfinite(v))
    seconds = np.full(len(v), np.nan)
    # each value until the column's next value, but no longer than the spacing the log has
    # around it (the median of the nine spacings nearest it): the row before a missing one
    # keeps its own interval, and a log that thins from 15 to 30 min rows keeps its 30 min
    # (capped at the file's median interval, those rows doubled their power)
    spacing = np.diff(ns[present]) / 1e9
    if spacing.size:
        local = pd.Series(spacing).rolling(9, center=True, min_periods=1).median().to_numpy()
        cap = np.append(local, local[-1])
    else:
        cap = np.full(present.size, typical)
    seconds[present] = np.minimum(np.append(spacing, np.inf), cap)
    return pd.Series(v / seconds, index=t)


#: A cumulative reading may fall by this many times the 95th percentile of its rises before
#: it is refused: a reading written with fewer digits, or a meter re-read, jitters by less
#: than one interval's consumption; a reset or a roll-over drops by thousands of them.
READING_DROP_FACTOR = 3.0


def reading_drops(readings: np.ndarray) -> np.ndarray:
    """Positions where a cumulative meter reading falls by more than reading jitter.

    Parameters
    ----------
    readings : ndarray
        The readings in time order, any energy unit; NaN (missing) are skipped, a drop is
        measured between consecutive readings present.

    Returns
    -------
    ndarray of int
        Positions in ``readings`` of the first reading after each drop larger than
        :data:`READING_DROP_FACTOR` times the 95th percentile of the rises (any drop when the
        reading never rises).
    """
    v = np.asarray(readings, float)
    present = np.flatnonzero(np.isfinite(v))
    steps = np.diff(v[present])
    rises = steps[steps > 0]
    tolerance = READING_DROP_FACTOR * float(np.quantile(rises, 0.95)) if rises.size else 0.0
    return present[1:][steps < -tolerance]


#: A cumulative reading may rise in one step by this many times the record's 99th-percentile
#: rise, in energy and in mean power (the rise over the time between the readings), before it
#: is refused. A heating system runs at full load in about the coldest 1 % of the hours it is
#: sized for, so the 99th-percentile rise is close to its output: the highest hour of the
#: reference records (EnergyPlus houses, constant and with a night setback; the Bacher and
#: Madsen 2011 PRBS-heated test box, 5-min rows) is 1.0-1.4 times it, a cold snap or a morning
#: boost of an oversized boiler in a mild record a few times. Ten times is heat no system that
#: delivered the rest of the record gives: a meter replaced by one starting at a higher
#: register, or a misentered reading. The energy condition spares a reading a few seconds
#: after the last one, the power condition a reading after a gap in the log.
READING_JUMP_FACTOR = 10.0
#: Fewer rises than this give no percentile to judge a jump by: not checked.
READING_JUMP_MIN_RISES = 10


def reading_jumps(readings: np.ndarray, seconds: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Positions where a cumulative meter reading jumps up by more than any heating gives.

    Parameters
    ----------
    readings : ndarray
        The readings in time order, any energy unit; NaN (missing) are skipped, a rise is
        measured between consecutive readings present.
    seconds : ndarray
        The time of each reading [s] (any origin).

    Returns
    -------
    positions : ndarray of int
        Positions in ``readings`` of the reading after each rise larger than
        :data:`READING_JUMP_FACTOR` times the 99th percentile of the rises both in energy
        and in mean power (rise over the time since the previous reading present); empty
        with fewer than :data:`READING_JUMP_MIN_RISES` rises.
    energy : float
        The 99th percentile of the rises [the readings' unit].
    power : float
        The 99th percentile of the rises' mean powers [the readings' unit per second].
    """
    v = np.asarray(readings, float)
    t = np.asarray(seconds, float)
    present = np.flatnonzero(np.isfinite(v))
    steps, spans = np.diff(v[present]), np.diff(t[present])
    rising = (steps > 0) & (spans > 0)
    if rising.sum() < READING_JUMP_MIN_RISES:
        return np.array([], int), np.nan, np.nan
    # "lower": the percentile is one of the rises, never interpolated towards a jump
    energy = float(np.quantile(steps[rising], 0.99, method="lower"))
    power = float(np.quantile(steps[rising] / spans[rising], 0.99, method="lower"))
    with np.errstate(divide="ignore", invalid="ignore"):
        jump = (
            rising
            & (steps > READING_JUMP_FACTOR * energy)
            & (steps / spans > READING_JUMP_FACTOR * power)
        )
    # a jump stands alone: a run of READING_JUMP_MAX_RUN + 1 or more such rises is heating
    # starting after weeks of almost none (a summer's 0.02 kWh an hour, then 4 kWh hours)
    jump &= ~_long_runs(jump, READING_JUMP_MAX_RUN)
    return present[1:][jump], energy, power


#: Longest run of consecutive rises above the jump threshold still called a jump [rises].
READING_JUMP_MAX_RUN = 2


def _long_runs(mask: np.ndarray, longest: int) -> np.ndarray:
    """``mask`` where its runs of True are longer than ``longest``."""
    out = np.zeros(mask.size, dtype=bool)
    start = None
    for i, value in enumerate(np.append(mask, False)):
        if value and start is None:
            start = i
        elif not value and start is not None:
            if i - start > longest:
                out[start:i] = True
            start = None
    return out


def rollover_limit(before: float, after: float) -> float | None:
    """The register size a meter rolled over at, or None for another drop.

    A meter with ``k`` digits counts to ``10^k`` and starts again at 0: the reading before
    the drop lies in the register's top tenth, the one after it in its bottom tenth.

    Parameters
    ----------
    before, after : float
        The readings before and after the drop, in the file's unit (e.g. kWh).
    """
    if not before > 0:
        return None
    limit = 10.0 ** np.ceil(np.log10(before))
    if limit == before:
        limit *= 10.0
    return float(limit) if before >= 0.9 * limit and 0 <= after < 0.1 * limit else None


def check_cumulative_reading(
    values: pd.Series, label: str, unit: tuple[str, float] = ("kWh", 3.6e6)
) -> None:
    """Refuse a cumulative meter reading that falls (a reset, a replaced meter, a roll-over)
    or jumps up (a meter replaced by one starting at a higher register, a misentered value).

    The heat of an interval is the next reading minus this one; a reading that drops to 0
    or rolls over turns one interval into minus the whole count and the period's mean heat
    negative, which is then blamed on the units. A reading that jumps up puts the jump into
    one interval as heat (the verify demo with +300 kWh on one day: a 70 kWh day read as
    329 kWh and the measured saving 45.5 % instead of 58.3 %, with no message); a jump is a
    rise :data:`READING_JUMP_FACTOR` times the record's 99th-percentile rise in energy and in
    power (:func:`reading_jumps`). The first event is named with its time, the row of the
    file and its size, and the edit that makes the readings continuous.

    Parameters
    ----------
    values : pd.Series
        The reading [J], rows labelled by time in the file's order.
    label : str
        The file and column (or configuration key), for the message.
    unit : tuple of (str, float)
        The file's unit of the reading and its size [J] (e.g. ``("kWh", 3.6e6)``).

    Raises
    ------
    ThermocalInputError
        Naming the first drop or jump (and how many there are) and what to do.
    """
    name, size = unit
    v = values.to_numpy(float) / size
    drops = reading_drops(v)
    seconds = values.index.as_unit("ns").asi8 / 1e9 if len(v) else np.array([])
    jumps, typical, typical_power = reading_jumps(v, seconds)
    if jumps.size and not (drops.size and drops[0] < jumps[0]):
        _refuse_jump(values, v, seconds, jumps, typical, typical_power, label, unit)
    if not drops.size:
        return
    at = int(drops[0])
    before_at = int(np.flatnonzero(np.isfinite(v[:at]))[-1])
    before, after = float(v[before_at]), float(v[at])
    limit = rollover_limit(before, after)
    if limit is not None:
        remedy = (
            f"the meter rolled over at {limit:,.0f} {name}: add {limit:,.0f} {name} to every "
            "reading from that row on"
        )
    else:
        remedy = (
            f"if the meter was reset or replaced there, add {before:,.1f} {name} (the last "
            "reading before the drop) to every reading from that row on, or use only the "
            "measurements on one side of it; a single misread value: delete it (its interval "
            "is then missing)"
        )
    more = f" ({drops.size} drops in all)" if drops.size > 1 else ""
    raise ThermocalInputError(
        f"{label}: a cumulative meter reading never falls, but it drops from {before:,.1f} "
        f"to {after:,.1f} {name} (by {before - after:,.1f} {name}) at {values.index[at]} "
        f"(row {at + 2} of the file){more}; {remedy}"
    )


def _refuse_jump(
    values: pd.Series,
    v: np.ndarray,
    seconds: np.ndarray,
    jumps: np.ndarray,
    typical: float,
    typical_power: float,
    label: str,
    unit: tuple[str, float],
) -> None:
    """Raise the message of :func:`check_cumulative_reading` for its first jump.

    Parameters
    ----------
    values : pd.Series
        The reading [J], rows labelled by time in the file's order.
    v : ndarray
        The same readings in the file's unit.
    seconds : ndarray
        The readings' times [s].
    jumps, typical, typical_power
        From :func:`reading_jumps`: positions, the 99th percentiles of the rises [file unit]
        and of their mean powers [file unit per second].
    label : str
        The file and column, for the message.
    unit : tuple of (str, float)
        The file's unit of the reading and its size [J].
    """
    name, size = unit
    at = int(jumps[0])
    present = np.flatnonzero(np.isfinite(v))
    before_at = int(present[present < at][-1])
    before, after = float(v[before_at]), float(v[at])
    jump = after - before
    span = pd.Timedelta(seconds=float(seconds[at] - seconds[before_at]))
    kw = size / 1e3  # the file's unit per second -> kW (the readings are held in J)
    later = present[present > at]
    fall = before - float(v[later[0]]) if later.size else np.nan
    if np.isfinite(fall) and fall > -0.5 * jump:  # back near the reading before: one value
        remedy = (
            f"the next reading ({float(v[later[0]]):,.1f} {name}) is back near the one before: "
            "a misentered value: correct it, or delete it (its interval is then missing)"
        )
    else:
        remedy = (
            "if the meter was replaced there (or its register set), subtract the offset (the "
            "new meter's first reading minus the old one's last; at most the jump, "
            f"{jump:,.1f} {name}) from every reading from that row on, or use only the "
            "measurements on one side of it; a misentered reading: correct it"
        )
    more = f" ({jumps.size} jumps in all)" if jumps.size > 1 else ""
    raise ThermocalInputError(
        f"{label}: a cumulative meter reading rises by the energy used, but it jumps from "
        f"{before:,.1f} to {after:,.1f} {name} (by {jump:,.1f} {name} in "
        f"{duration_text(span)}, a mean {jump * kw / span.total_seconds():,.1f} kW) at "
        f"{values.index[at]} (row {at + 2} of the file){more}, more than "
        f"{READING_JUMP_FACTOR:g} times the record's 99th-percentile rise ({typical:,.3g} "
        f"{name}, {typical_power * kw:,.3g} kW) in energy and in power, far beyond what the "
        f"metered system gave in the rest of the record; {remedy}"
    )


def file_unit(raw: pd.DataFrame, std: str) -> tuple[str, float]:
    """The unit a column of :func:`read_raw_measurements` had in the file and its size in
    the unit ``raw`` holds (e.g. ``("kWh", 3.6e6)`` for a meter read into J).

    Parameters
    ----------
    raw : pd.DataFrame
        From :func:`read_raw_measurements` (``raw.attrs["measurements"]``).
    std : str
        Standard column name (e.g. ``"heat"``).

    Returns
    -------
    tuple of (str, float)
        The file's unit and its factor to ``raw``'s; ``(the unit held, 1.0)`` when the
        reader converted nothing (or did not record it) or converted with an offset
        (Fahrenheit, Kelvin). A fuel volume (m3, l) is read as its energy in kWh.
    """
    from thermocal.io.measurements.units import UNITS

    meta = raw.attrs.get("measurements", {}) if isinstance(raw.attrs, dict) else {}
    held = (meta.get("units") or {}).get(std, "")
    name = (meta.get("units_in_file") or {}).get(std, held)
    known = name in UNITS and held in UNITS and UNITS[name][0] == UNITS[held][0]
    if known and UNITS[name][2] == UNITS[held][2]:  # a factor, no offset (F, K: kept in C)
        return name, UNITS[name][1] / UNITS[held][1]
    return held, 1.0


def values_in_file_units(raw: pd.DataFrame, fuel_kWh_per_unit: float | None = None):
    """The measurements of :func:`read_raw_measurements` in the units of the file.

    The reader converts energies to J and powers to W; a reading step (0.1 kWh, 1 m3) is
    only visible in the file's own unit.

    Parameters
    ----------
    raw : pd.DataFrame
        From :func:`read_raw_measurements`.
    fuel_kWh_per_unit : float, optional
        ``measurements.fuel_kWh_per_unit`` [kWh per m3 or l] of a fuel meter read in a
        volume: its ``heat`` column goes back to that volume.

    Returns
    -------
    pd.DataFrame
        The same index and columns, each in its file unit (temperatures with an offset,
        e.g. Kelvin, stay in C: only factors are undone).
    """
    out = raw.copy()
    for std in raw.columns:
        _, factor = file_unit(raw, std)
        divisor = factor * (fuel_kWh_per_unit if std == "heat" and fuel_kWh_per_unit else 1.0)
        if divisor != 1.0:
            out[std] = raw[std] / divisor
    return out


#: Relative slack of the comparison of the grid step with the log's interval: a logger's
#: time stamps jitter by seconds, which moves the median spacing a little off the nominal one.
LOG_INTERVAL_SLACK = 0.05


def log_interval(raw: pd.DataFrame) -> pd.Timedelta:
    """The logging interval of a measurement table [duration].

    Parameters
    ----------
    raw : pd.DataFrame
        From :func:`read_raw_measurements` (tz-aware DatetimeIndex, at least two rows).

    Returns
    -------
    pd.Timedelta
        The reader's interval (``raw.attrs["measurements"]["interval"]``, the median spacing
        of the file's time stamps), else the median spacing of ``raw``'s index.
    """
    meta = raw.attrs.get("measurements", {}) if isinstance(raw.attrs, dict) else {}
    interval = meta.get("interval")
    return pd.Timedelta(interval) if interval else pd.Series(raw.index).diff().median()


def log_source(raw: pd.DataFrame) -> str:
    """The measurement file of ``raw`` (its reader's ``source``), for messages."""
    meta = raw.attrs.get("measurements", {}) if isinstance(raw.attrs, dict) else {}
    return str(meta.get("source") or "the measurement file")


def check_step_against_log(step: str, interval: pd.Timedelta, source: str) -> None:
    """Refuse a grid step finer than the log's own interval.

    Each logged value is the mean over its interval; on a finer grid it is held over several
    steps, a staircase the house never followed. The calibration then fits dynamics the data
    do not have (the one-step residuals of an hourly log on a 15-min grid are those of a
    held value), and the calibrated model, the annual demands and the savings change with the
    step (the verify demo's predicted saving 61.1 % -> 71.8 % at 15 min on its hourly log).

    Parameters
    ----------
    step : str
        ``measurements.step`` [duration], already a divisor of an hour
        (:func:`thermocal.retrofit.config.step_problem`).
    interval : pd.Timedelta
        The log's interval (:func:`log_interval`) [duration].
    source : str
        The measurement file, for the message.

    Raises
    ------
    ThermocalInputError
        Naming the key, both intervals and the steps allowed.
    """
    from thermocal.retrofit.config import GRID_STEPS

    step_td = pd.Timedelta(step)
    if step_td >= interval * (1.0 - LOG_INTERVAL_SLACK):
        return
    allowed = [s for s in GRID_STEPS if pd.Timedelta(s) >= interval * (1.0 - LOG_INTERVAL_SLACK)]
    remedy = (
        f"set measurements.step to the log's interval or coarser ({', '.join(allowed)})"
        if allowed
        else "the analysis is hourly at most: give a log with an interval of 1 h or less"
    )
    raise ThermocalInputError(
        f"measurements.step {step!r} is finer than the interval of the log {source} "
        f"({duration_text(interval)}, the median spacing of its time stamps): each logged value "
        "would be held over several steps, a staircase the house never followed, and the "
        f"calibration and the savings would change with the step; {remedy}"
    )


def _meter_label(raw: pd.DataFrame, std: str, columns: dict[str, str] | None) -> str:
    """The file and column of a meter, for messages (the configuration key without
    ``columns``)."""
    column = (columns or {}).get(std)
    named = f"column {column!r}" if column else f"the {std} column"
    where = f"{named} (measurements.columns.{std})"
    return f"{log_source(raw)}, {where}"


def prepare_measurements(
    raw: pd.DataFrame,
    step: str,
    *,
    heat_source: str = "hydronic",
    heat_energy: bool = False,
    heat_cumulative: bool = False,
    boiler_efficiency: float | None = None,
    electricity_energy: bool = False,
    electricity_cumulative: bool = False,
    columns: dict[str, str] | None = None,
) -> tuple[pd.DataFrame, QualityReport]:
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
    columns : dict, optional
        Standard name -> the file's column (``measurements.columns``), for messages.

    Returns
    -------
    grid : pd.DataFrame
        Regular grid labelled by interval start with the raw columns and ``phi_h`` [W].
    report : thermocal.io.measurements.QualityReport
    """
    from thermocal.io.measurements import resample_measurements
    from thermocal.retrofit.config import step_problem

    why = step_problem(step)
    if why is not None:
        raise ThermocalInputError(f"measurements.step {step!r}: {why}")
    step_td = pd.Timedelta(step)
    if len(raw) < 2:
        raise ThermocalInputError("measurement file: fewer than two rows of measurements")
    frame = raw.copy()
    logging_interval = log_interval(raw)
    check_step_against_log(step, logging_interval, log_source(raw))
    if heat_source == "hydronic":
        frame["phi_h"] = heating_power(frame["flow"], frame["temp_supply"], frame["temp_return"])
    else:  # a heat meter's useful heat, or fuel energy times the boiler's efficiency
        power = meter_power(
            frame.pop("heat"), energy=heat_energy, cumulative=heat_cumulative,
            interval=logging_interval, label=_meter_label(raw, "heat", columns),
            unit=file_unit(raw, "heat"),
        )  # fmt: skip
        frame["phi_h"] = power * (boiler_efficiency if heat_source == "fuel_meter" else 1.0)
    if "electricity" in frame:
        frame["phi_el"] = meter_power(
            frame.pop("electricity"), energy=electricity_energy,
            cumulative=electricity_cumulative, interval=logging_interval,
            label=_meter_label(raw, "electricity", columns),
            unit=file_unit(raw, "electricity"),
        )  # fmt: skip
    for std in ("dni", "dhi", "ghi"):
        if std in frame:
            frame[std] = frame[std].clip(lower=0.0)
    grid, report = resample_measurements(
        frame,
        step_td,
        max_gap=logging_interval,
        interval=logging_interval,
        quantities={c: QUANTITIES[c] for c in frame.columns if c in QUANTITIES},
        limits={"phi_h": PHI_H_LIMITS},
    )
    return grid[list(frame.columns)], report


def removed_values_notes(report: QualityReport, columns: dict[str, str]) -> list[str]:
    """One plain sentence per sensor whose physically impossible values were removed.

    Parameters
    ----------
    report : QualityReport
        From :func:`prepare_measurements`.
    columns : dict
        Standard name -> column in the file (``measurements.columns``).
    """
    notes = []
    flags = report.flags
    if flags.empty:
        return notes
    for sensor, rows in flags[flags["flag"] == "impossible"].groupby("sensor", sort=False):
        n = int(report.sensors.loc[sensor, "n_reports"]) if sensor in report.sensors.index else 0
        col = columns.get(sensor, sensor)
        name = f"column {col!r}" if sensor in columns else f"the derived {sensor!r}"
        notes.append(
            f"measurements: {len(rows)} physically impossible value(s) of {name} removed "
            f"({rows['reason'].iloc[0]}; first {rows['value'].iloc[0]:g} at "
            f"{rows['time'].iloc[0]}), of {n} rows; an interval's mean uses its remaining "
            "values, an interval left without any is missing. Check the sensor if this is more "
            "than a glitch"
        )
    return notes
