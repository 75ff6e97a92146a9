"""Heat-flux meter logs: their configuration and their reduction to an in-situ U-value or
thermal resistance (ISO 9869-1's average method, :mod:`thermocal.physics.heat_flux`).

One configuration entry (:class:`InSituConfig`, the ``in_situ:`` sections of ``thermocal
retrofit`` and ``thermocal calibrate``) is either a logged measurement (a CSV or parquet file
with the heat flux through the element and the temperatures on both sides) or a value a survey
reported with its relative standard uncertainty. :func:`measure_in_situ_value` reads and reduces
it, and refuses a log the standard's convergence criteria reject with what to do.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from thermocal.errors import ThermocalInputError
from thermocal.physics.heat_flux import (
    SURFACE_RESISTANCES,
    InSituUValue,
    InwardHeatFlux,
    average_method,
)

__all__ = [
    "InSituConfig",
    "measure_in_situ_value",
    "read_heat_flux_log",
    "reduce_heat_flux_log",
    "surface_resistances_of",
]

log = logging.getLogger(__name__)


class InSituConfig(BaseModel):
    """An in-situ measurement of one element: a heat-flux meter's log analysed by the average
    method of ISO 9869-1, or a value with its uncertainty from a survey (``u_value`` or
    ``resistance``, with ``rel_std``)."""

    # NaN passes no bound (every comparison is false) and would read as "less than 2000"
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)

    file: Path | None = Field(None, description="heat-flux meter log (CSV or parquet)")
    time_column: str = "time"
    time_unit: Literal["s", "min", "h", "d", "ms"] | None = Field(
        None, description="of numeric times (a logger's Unix seconds: s); default: dates"
    )
    time_origin: str | None = Field(
        None, description="the instant of numeric time 0 (default 1970-01-01 UTC)"
    )
    columns: dict[str, str] = Field(
        default_factory=lambda: {"heat_flux": "q", "temp_in": "Ti", "temp_out": "Te"},
        description="heat_flux [W/m2], temp_in and temp_out [temperature_unit] -> file column",
    )
    timezone: str | float | None = Field(
        None, description="of time stamps without offset (default: the building's)"
    )
    temperature_unit: Literal["C", "K", "F"] = "C"
    temperatures: Literal["air", "surface"] = Field(
        "air", description="air: the room's air and the air on the element's other side "
        "(outdoors, or the unheated attic, garage or cellar): U; surface: the element's faces",
    )  # fmt: skip
    heat_flux_sign: Literal["outward", "inward"] = Field(
        "outward", description="the direction the plate reports as positive"
    )
    plate_rel_std: float = Field(
        0.05, ge=0, le=0.5, description="plate calibration and flow disturbance [-]"
    )
    temperature_std: float = Field(0.1, ge=0, le=2.0, description="per sensor [K]")
    spot_rel_std: float = Field(
        0.05, ge=0, le=0.5, description="how well the spot stands for the element [-]"
    )
    areal_heat_capacity: float | None = Field(
        None, gt=0, le=2000, description="of the element, for ISO 9869-1's criterion d "
        "[kJ/(m2 K)]",
    )  # fmt: skip
    other_side: Literal["outdoors", "unheated"] | None = Field(
        None, description="what is on the element's other side: outdoors (ISO 6946's outside "
        "surface resistance) or an unheated space (the inside one on both sides); the "
        "retrofit's components imply it",
    )  # fmt: skip
    flow: Literal["horizontal", "upward", "downward"] | None = Field(
        None, description="the heat flow's direction through the element (ISO 6946 surface "
        "resistances: walls horizontal, roofs upward, floors downward); the retrofit's "
        "components imply it",
    )  # fmt: skip
    component: str | None = Field(
        None, description="name of the building-file component the plate was on (needed when "
        "the type's components differ in U-value)",
    )  # fmt: skip
    u_value: float | None = Field(None, gt=0, le=6.0, description="a given value [W/(m2 K)]")
    resistance: float | None = Field(
        None, gt=0, le=50.0, description="a given surface-to-surface resistance [m2 K/W]"
    )
    rel_std: float | None = Field(
        None, gt=0, le=1.0, description="relative standard uncertainty of the given value [-]"
    )

    @model_validator(mode="after")
    def _one_source(self) -> InSituConfig:
        given = [k for k in ("u_value", "resistance") if getattr(self, k) is not None]
        if len(given) > 1:
            raise ValueError("give u_value or resistance, not both")
        if (self.file is None) == (not given):
            raise ValueError(
                "give either file (a heat-flux meter log, analysed by ISO 9869-1's average "
                "method) or u_value with rel_std (a measured value and its uncertainty)"
            )
        if given and self.rel_std is None:
            value = getattr(self, given[0])
            raise ValueError(f"{given[0]} {value:g}: give its rel_std too (e.g. 0.1)")
        needed = {"heat_flux", "temp_in", "temp_out"}
        missing, extra = needed - set(self.columns), set(self.columns) - needed
        if self.file is not None and missing:
            raise ValueError(f"columns: map {sorted(missing)} to the log's column names")
        if extra:
            raise ValueError(f"columns: {sorted(extra)} not used; map only {sorted(needed)}")
        for column in dict.fromkeys(self.columns.values()):
            keys = [f"columns.{k}" for k in sorted(needed) if self.columns.get(k) == column]
            if len(keys) > 1:
                raise ValueError(
                    f"{' and '.join(keys)} both name the log column {column!r}: each of "
                    "heat_flux, temp_in and temp_out needs its own log column"
                )
        return self


#: Relative standard uncertainty [-] of a plate's value at the defaults of an ``in_situ`` entry:
#: the plate's and the spot's parts (5 % each) in quadrature. A real log adds its sensors' and
#: its convergence parts (7.1-7.6 % in all on the EnergyPlus walls and roof); what the
#: measurement advice of both workflows assumes before anyone goes on site.
TYPICAL_REL_STD = float(
    np.hypot(
        InSituConfig.model_fields["plate_rel_std"].default,
        InSituConfig.model_fields["spot_rel_std"].default,
    )
)


def read_heat_flux_log(spec: InSituConfig, where: str, default_tz=None):
    """A heat-flux meter's log: time stamps, outward heat flux and temperatures.

    Parameters
    ----------
    spec : InSituConfig
        With ``file``.
    where : str
        The configuration key, for messages (e.g. ``in_situ.walls``).
    default_tz : str or float, optional
        Time zone of time stamps without offset when ``spec`` gives none.

    Returns
    -------
    times : DatetimeIndex
    heat_flux : ndarray [W/m2]
        Positive from inside to outside.
    temp_in, temp_out : ndarray [C]

    Raises
    ------
    ThermocalInputError
        The file missing or unreadable (the reader's message, with the key), temperatures that
        look like Kelvin or Fahrenheit.
    """
    from thermocal.io.measurements import read_measurements

    path = Path(spec.file)
    if not path.is_file():
        what = "is not a file" if path.exists() else "not found"
        raise ThermocalInputError(f"heat-flux log {path} {what} ({where}.file)")
    names = {col: std for std, col in spec.columns.items()}
    units = {
        spec.columns["heat_flux"]: "W/m2",
        spec.columns["temp_in"]: spec.temperature_unit,
        spec.columns["temp_out"]: spec.temperature_unit,
    }
    try:
        raw, _ = read_measurements(
            path, layout="wide", time_column=spec.time_column, sensors=names, units=units,
            # the average method counts whole days from the log's first row: without a zone
            # (given or the building's) the stamps are read as they are, as UTC
            tz=next((tz for tz in (spec.timezone, default_tz) if tz is not None), "UTC"),
            rows="interval_start",
            unknown_sensors="ignore",
            time_unit=spec.time_unit,
            start=spec.time_origin,
        )  # fmt: skip
    except ThermocalInputError as exc:
        text = str(exc)
        if "look like Kelvin" in text or "look like Fahrenheit" in text:
            text += f" (here: {where}.temperature_unit)"
        # the reader's remedies name its Python options; here the configuration's keys
        for option, remedy in (
            ("pass time_column=", f"set {where}.time_column"),
            (", or pass time_format= (e.g. '%d.%m.%Y %H:%M')", ""),
            ("pass tz=", f"set {where}.timezone:"),
            ("pass the time zone (--tz Europe/Zurich)", f"set {where}.timezone (Europe/Zurich)"),
            ("pass a fixed offset, e.g. tz=1.0", f"set {where}.timezone to an offset, e.g. 1.0"),
            ("(--time-unit on the command line, time_unit= in Python)",
             f"({where}.time_unit)"),
            ("(--time-origin, start=;", f"({where}.time_origin;"),
            ("but the unit given for it (the configuration, or units=) is 'W/m2'",
             "but the heat flux is read in W/m2: convert the column"),
            ("but the unit given for it (the configuration, or units=) is",
             f"but {where}.temperature_unit says"),
            ("pass sort=True", "sort the log by time"),
            (", or pass duplicates='first' or 'last'", ""),
            ("pass decimal=','", "write decimal points"),
            ("pass interval=", "log more than one row"),
        ):
            text = text.replace(option, remedy)
        units_row = _units_row(path) if "cannot read" in text and "line 2" in text else None
        if units_row:
            text += (
                f"; line 2 is a row of units ({', '.join(units_row)}), not a reading: delete it "
                f"(a unit can stand in the header, e.g. '{spec.columns['heat_flux']} [W/m2]')"
            )
        if "not found" in text:
            unit = _foreign_unit(path, spec.columns["heat_flux"])
            if unit:
                text = (
                    f"heat-flux log {path}: column {unit[0]!r} is {where}.columns.heat_flux "
                    f"{spec.columns['heat_flux']!r} in {unit[1]!r}, which thermocal does not "
                    "convert: convert the column to W/m2"
                    + (" (1 Btu/(h ft2) = 3.1546 W/m2)" if "btu" in unit[1].lower() else "")
                    + f" and head it {spec.columns['heat_flux']!r} or "
                    f"'{spec.columns['heat_flux']} [W/m2]'"
                )
            else:
                text += (
                    f"; map the log's columns with {where}.columns (heat_flux, temp_in, "
                    "temp_out)" + _header_hint(path)
                )
        raise ThermocalInputError(f"{where}: {text}") from None
    q = raw["heat_flux"].to_numpy(float)
    if spec.heat_flux_sign == "inward":
        q = -q
    ti, te = raw["temp_in"].to_numpy(float), raw["temp_out"].to_numpy(float)
    for std, values in (("temp_in", ti), ("temp_out", te)):
        high = np.nanmax(values) if np.isfinite(values).any() else np.nan
        if np.isfinite(high) and high > 60.0:
            guess = "Kelvin" if high > 250.0 else "Fahrenheit"
            raise ThermocalInputError(
                f"heat-flux log {path}: column {spec.columns[std]!r} ({where}.columns.{std}) "
                f"reaches {high:.1f} {spec.temperature_unit}; {guess}? Set "
                f"{where}.temperature_unit"
            )
    return raw.index, q, ti, te


def _csv_head(path: Path, rows: int):
    """The first ``rows`` rows of a CSV log as text (None for parquet or when unreadable)."""
    import pandas as pd

    if path.suffix.lower() in (".parquet", ".pq"):
        return None
    try:
        return pd.read_csv(path, nrows=rows, sep=None, engine="python", dtype=str)
    except Exception:  # noqa: BLE001 - only a hint; the reader's message stands
        return None


def _units_row(path: Path) -> list[str] | None:
    """The cells of a CSV log's first row under the header when they are units, not readings
    (no number among them, a unit-like cell such as ``W/m2`` or ``C``), else None."""
    import re

    head = _csv_head(path, 1)
    if head is None or not len(head):
        return None
    cells = [str(c).strip() for c in head.iloc[0].tolist() if isinstance(c, str) and c.strip()]
    if not cells or any(re.fullmatch(r"[-+]?\d+([.,]\d*)?([eE][-+]?\d+)?", c) for c in cells):
        return None
    unit = re.compile(r"(?i)^\[?\(?(w/m.?2|w/m²|mw/m2|°?c|deg\s*c|k|°?f|s|h|-|%)\)?\]?$")
    return cells if any(unit.match(c) for c in cells) else None


def _foreign_unit(path: Path, name: str) -> tuple[str, str] | None:
    """``(column, unit)`` when a CSV or parquet log heads the heat flux ``name [unit]`` or
    ``name (unit)`` with a unit the reader did not take, else None."""
    import re

    head = _csv_head(path, 0)
    columns = list(head.columns) if head is not None else []
    if head is None and path.suffix.lower() in (".parquet", ".pq"):
        try:
            import pyarrow.parquet as pq

            columns = pq.read_schema(path).names
        except Exception:  # noqa: BLE001 - only a hint
            return None
    for column in map(str, columns):
        found = re.fullmatch(rf"\s*{re.escape(name)}\s*[\[(](.+)[\])]\s*", column)
        if found:
            return column, found.group(1).strip()
    return None


def _header_hint(path: Path) -> str:
    """``"; the log's columns: ..."`` for a CSV or parquet log, empty when unreadable."""
    import pandas as pd

    try:
        if path.suffix.lower() in (".parquet", ".pq"):
            import pyarrow.parquet as pq

            names = pq.read_schema(path).names
        else:
            names = list(pd.read_csv(path, nrows=0, sep=None, engine="python").columns)
    except Exception:  # noqa: BLE001 - only a hint; the reader's message stands
        return ""
    return f"; the log's columns: {', '.join(map(str, names[:12]))}"


def surface_resistances_of(
    spec: InSituConfig, flow: str = "horizontal", given: tuple[float, float] | None = None
) -> tuple[float, float]:
    """The (inside, other side) surface resistances [m2 K/W] between U and the element's own
    resistance: ``given``, else ISO 6946's for ``flow``, the inside one on both sides when
    ``spec.other_side`` is an unheated space."""
    if given is not None:
        return tuple(given)
    r_si, r_se = SURFACE_RESISTANCES[flow]
    return (r_si, r_si if spec.other_side == "unheated" else r_se)


def reduce_heat_flux_log(
    spec: InSituConfig, where: str, times, q, ti, te, films: tuple[float, float]
) -> InSituUValue:
    """ISO 9869-1's average method on a log read by :func:`read_heat_flux_log`, whether or not
    it has converged (``result.converged``).

    Parameters
    ----------
    spec : InSituConfig
    where : str
        The configuration key, for messages.
    times, q, ti, te
        The log [W/m2, C].
    films : (float, float)
        :func:`surface_resistances_of` [m2 K/W].

    Raises
    ------
    ThermocalInputError
        What :func:`thermocal.physics.heat_flux.average_method` refuses, with the remedy (a
        plate reporting the other direction: ``heat_flux_sign``, inward or back to outward).
    """
    try:
        return average_method(
            times, q, ti, te, temperatures=spec.temperatures, surface_resistances=films,
            plate_rel_std=spec.plate_rel_std, temperature_std_K=spec.temperature_std,
            spot_rel_std=spec.spot_rel_std,
            areal_heat_capacity=None if spec.areal_heat_capacity is None
            else 1e3 * spec.areal_heat_capacity,
            heat_flux_column=spec.columns.get("heat_flux"),
        )  # fmt: skip
    except InwardHeatFlux as exc:
        if spec.heat_flux_sign == "inward":  # turned already: the plate reports outward flow
            raise ThermocalInputError(
                f"heat-flux log {spec.file}: with {where}.heat_flux_sign inward the heat flows "
                "inwards on average while the inside is warmer: the plate reports outward flow "
                f"as positive already; set {where}.heat_flux_sign: outward (the default)"
            ) from None
        raise ThermocalInputError(
            f"heat-flux log {spec.file}: {exc}; set {where}.heat_flux_sign: inward"
        ) from None
    except (ValueError, ZeroDivisionError) as exc:
        text = str(exc)
        if text.endswith("measured with its surface temperatures"):  # an impossible U-value
            text += f" ({where}.temperatures: surface)"
        raise ThermocalInputError(f"heat-flux log {spec.file} ({where}): {text}") from None


def measure_in_situ_value(
    spec: InSituConfig,
    where: str,
    *,
    flow: str = "horizontal",
    surface_resistances: tuple[float, float] | None = None,
    default_tz=None,
) -> tuple[InSituUValue, str]:
    """An entry's in-situ value: the log reduced by ISO 9869-1's average method, or the given
    value.

    Parameters
    ----------
    spec : InSituConfig
    where : str
        The configuration key, for messages.
    flow : {"horizontal", "upward", "downward"}
        The heat flow's direction through the element (ISO 6946's surface resistances).
    surface_resistances : (float, float), optional
        Inside and outside surface resistances [m2 K/W] instead of ``flow``'s (an element
        towards an unheated space: the inside one on both sides).
    default_tz : str or float, optional
        Time zone of log time stamps without offset.

    Returns
    -------
    InSituUValue
        A given ``resistance`` is returned as its conductance (``1 / R``) with ``u_value`` from
        ISO 6946's surface resistances; a given ``u_value`` as is.
    str
        Where the value comes from (the log and method, or "given").

    Raises
    ------
    ThermocalInputError
        The log's errors (:func:`read_heat_flux_log`), a heat flux whose mean points inwards
        while the inside is warmer (the plate's sign), a U-value the surface resistances alone
        do not allow (measured or given), a log that fails ISO 9869-1's criteria.

    Notes
    -----
    A log that passes criteria a-c without the element's heat capacity is taken with its
    warning (``result.status`` :data:`~thermocal.physics.heat_flux.D_NOT_CHECKED`) logged as a
    warning and kept in ``result.warnings``: ISO 9869-1 asks criterion d only of elements above
    20 kJ/(m2 K), which the log cannot tell.
    """
    films = surface_resistances_of(spec, flow, surface_resistances)
    if spec.file is None:
        if spec.resistance is not None:
            u = 1.0 / (sum(films) + spec.resistance)
            result = InSituUValue(
                u_value=u, rel_std=float(spec.rel_std) * u * spec.resistance,
                conductance=1.0 / spec.resistance, surface_resistances=films,
            )  # fmt: skip
        else:
            if spec.u_value >= 1.0 / sum(films):  # no element left beyond the films
                raise ThermocalInputError(
                    f"{where}: u_value {spec.u_value:g} W/(m2 K) is impossible: the surface "
                    f"resistances alone ({films[0]:g} + {films[1]:g} m2 K/W, ISO 6946"
                    + (", the inside one on both sides towards an unheated space"
                       if spec.other_side == "unheated" else "")
                    + f") allow at most {1.0 / sum(films):.2f} W/(m2 K); check the value "
                    "(air to air, W/(m2 K))"
                    + (f" and {where}.other_side" if spec.other_side == "unheated" else "")
                )  # fmt: skip
            result = InSituUValue(
                u_value=float(spec.u_value), rel_std=float(spec.rel_std),
                surface_resistances=films,
            )  # fmt: skip
        return result, "given"
    result = reduce_heat_flux_log(spec, where, *read_heat_flux_log(spec, where, default_tz), films)
    if not result.converged:
        raise ThermocalInputError(
            f"heat-flux log {spec.file} ({where}): the average method of ISO 9869-1 has not "
            f"converged ({'; '.join(result.failed())}): log longer (whole days of winter), "
            f"or give the value with a rel_std that covers the spread"
        )
    for note in result.notes:
        log.info("%s: %s", where, note)
    for warning in result.warnings:  # e.g. criterion d not checked: seen, and in results.json
        log.warning("%s: %s", where, warning)
    return result, f"{Path(spec.file).name}: ISO 9869-1 average method, {result.days} days"
