"""Configuration schema of ``thermocal retrofit`` (YAML file, pydantic v2).

A minimal configuration::

    building: building.yaml          # thermocal building file (or an inline mapping)
    measurements:
      file: measurements.csv
      columns: {temp_out: Te, flow: V_dot, temp_supply: T_sup, temp_return: T_ret,
                dni: DNI, dhi: DHI, temp_in: Ti}
    weather: {file: annual.epw}

Every path is relative to the configuration file. Unknown keys are rejected so typos do not go
unnoticed.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    PositiveFloat,
    PrivateAttr,
    ValidationError,
    field_validator,
    model_validator,
)

from thermocal.errors import ThermocalInputError
from thermocal.io.heat_flux_log import InSituConfig
from thermocal.retrofit.strategies import (
    DEFAULT_COST_PER_M2,
    MEASURE_COMPONENTS,
    MEASURE_ORDER,
    PAPER_MEASURE_DESCRIPTIONS,
    PAPER_MEASURE_U_VALUES,
    U_VALUE_COMPONENTS,
    Measure,
    all_strategies,
    listed_strategies,
)

#: Standard measurement names used by the workflow, with their meaning and unit.
MEASUREMENT_COLUMNS: dict[str, str] = {
    "temp_out": "external air temperature Te [C]",
    "flow": "heating water volume flow V_dot",
    "temp_supply": "heating supply water temperature [C]",
    "temp_return": "heating return water temperature [C]",
    "dni": "direct normal irradiance [W/m2] (hourly Wh/m2 is the same number)",
    "dhi": "diffuse horizontal irradiance [W/m2]",
    "ghi": "global horizontal irradiance [W/m2] (a pyranometer; measurements.irradiance: ghi)",
    "temp_in": "internal air temperature Ti [C]",
    "heat": "heat (or fuel) meter: power or energy, unit measurements.heat_unit",
    "electricity": "electricity meter: power or energy, unit internal_gains.electricity_unit",
}
#: Standard names needed by each heat source (measurements.heat_source).
HEAT_SOURCE_COLUMNS: dict[str, tuple[str, ...]] = {
    "hydronic": ("flow", "temp_supply", "temp_return"),
    "heat_meter": ("heat",),
    "fuel_meter": ("heat",),
}
#: Units of a meter column: power (row = mean power) or energy (row = energy of its interval,
#: or a cumulative reading with ``*_cumulative: true``).
METER_UNITS = ("W", "kW", "Wh", "kWh", "MWh", "MJ", "GJ")
#: Fuel volumes a fuel meter may be read in (measurements.heat_unit), with
#: measurements.fuel_kWh_per_unit.
FUEL_VOLUME_UNITS = ("m3", "l")

#: Conversion factors of supported flow units to m3/s.
FLOW_UNITS: dict[str, float] = {
    "m3/s": 1.0,
    "m3/h": 1.0 / 3600.0,
    "l/s": 1e-3,
    "l/min": 1e-3 / 60.0,
    "l/h": 1e-3 / 3600.0,
}


#: Most parameter draws for the intervals (a 90 % interval settles within a few thousand).
MAX_DRAWS = 100_000

#: Most occupants of one house (more: a block of flats, analyse it per dwelling).
MAX_OCCUPANTS = 30
#: Range of a person's sensible heat [W]: asleep (0.8 met) to active housework (~2.5 met).
OCCUPANT_SENSIBLE_RANGE_W = (30.0, 200.0)

#: A constant indoor temperature of the demand simulation must lie in this range [C].
INDOOR_PROFILE_RANGE = (5.0, 35.0)

#: Steps the analysis grid may take (``measurements.step``): divisors of an hour, which line
#: up with the log's clock, the hourly weather and the hour-of-day profiles.
GRID_STEPS = ("5min", "10min", "15min", "20min", "30min", "1h")


def step_problem(step: str) -> str | None:
    """Why ``measurements.step`` cannot be the grid of the fifth-order analysis, or None.

    The method is hourly at most: the air and heating nodes answer within the hour, and the
    thermostat's profile (:func:`thermocal.retrofit.calibration.heating_setpoint`), the
    comfort take-back and the internal gains are hour-of-day profiles that need every hour of
    the day on the grid. A step must therefore divide an hour.

    Parameters
    ----------
    step : str
        The grid step as written, e.g. ``"15min"`` or ``"1h"`` [duration].

    Returns
    -------
    str or None
        The reason with the steps to use instead (no key, no value: the caller names them).
    """
    import pandas as pd

    hour = pd.Timedelta(hours=1)
    try:
        step_td = pd.Timedelta(step)
    except ValueError as exc:
        return f"not a duration ({exc}); write e.g. {', '.join(GRID_STEPS)}"
    if step_td <= pd.Timedelta(0):
        return f"a step must be a positive duration, e.g. {', '.join(GRID_STEPS)}"
    if step_td > hour:
        return (
            "coarser than an hour: the fifth-order RC method is hourly at most (its air and "
            "heating nodes answer within the hour; the thermostat's set-backs, the comfort "
            "take-back and the internal gains are hour-of-day profiles that need every hour of "
            f"the day); use 1h or a divisor of it ({', '.join(GRID_STEPS)})"
        )
    if hour % step_td:
        return (
            "does not divide an hour: the grid would not line up with the log's clock (and "
            f"the hourly weather); use {', '.join(GRID_STEPS)}"
        )
    return None


#: Shortest training period of the fifth-order model [d]: its slowest time constants (envelope,
#: internal mass) are days long, and a weekly cycle of use should be inside.
MIN_TRAINING_DAYS = 7.0

#: Largest plausible annual energy of the house (fuel, rating) [kWh].
MAX_ANNUAL_KWH = 2.0e6

#: Smallest plausible heat loss coefficient of a building [W/K] (a tiny house has ~50).
MIN_HEAT_LOSS_COEFFICIENT = 5.0


#: The temperature columns of the measurements (standard names).
TEMPERATURE_NAMES = ("temp_out", "temp_in", "temp_supply", "temp_return")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


#: Energy of one unit of a fuel [kWh] (the bill's calorific value) per unit a fuel meter may be
#: read in, for any fuel sold by that unit: fuel gases from biogas (about 6 kWh/m3) over
#: natural gas (8-12.5) to propane (about 26); liquid fuels from LPG (about 7 kWh/l) to heating
#: oil (about 10).
FUEL_KWH_PER_UNIT_RANGE: dict[str, tuple[float, float]] = {"m3": (4.0, 28.5), "l": (5.0, 11.5)}
#: The same for a known fuel (``economics.energy_carrier`` given): natural gas per m3 (L- to
#: H-gas, lower to upper calorific value), heating oil per l.
CARRIER_KWH_PER_UNIT_RANGE: dict[tuple[str, str], tuple[float, float]] = {
    ("natural gas", "m3"): (8.0, 12.5),
    ("heating oil", "l"): (9.0, 11.0),
}
#: Megajoules per kilowatt-hour.
MJ_PER_KWH = 3.6


def fuel_energy_problem(value: float, unit: str, carrier: str | None = None) -> str | None:
    """Why ``measurements.fuel_kWh_per_unit`` is no fuel's energy per unit, or None.

    Parameters
    ----------
    value : float
        The configured energy of one unit of fuel [kWh per m3 or l].
    unit : {"m3", "l"}
        The fuel meter's unit (``measurements.heat_unit``).
    carrier : str, optional
        The fuel when known (:func:`energy_carrier_name` of ``economics.energy_carrier``);
        with a range in :data:`CARRIER_KWH_PER_UNIT_RANGE` that fuel's range is checked,
        otherwise :data:`FUEL_KWH_PER_UNIT_RANGE`.

    Returns
    -------
    str or None
        The reason, with the value in kWh when it looks like megajoules (a factor 3.6).
    """
    known = (carrier, unit) in CARRIER_KWH_PER_UNIT_RANGE
    low, high = (CARRIER_KWH_PER_UNIT_RANGE if known else FUEL_KWH_PER_UNIT_RANGE)[
        (carrier, unit) if known else unit
    ]
    if low <= value <= high:
        return None
    fuels = {"m3": "biogas about 6, natural gas 8-12.5, propane about 26 kWh/m3",
             "l": "LPG about 7, heating oil about 10 kWh/l"}[unit]  # fmt: skip
    kind = {"m3": "fuel gas", "l": "liquid fuel"}[unit]
    reason = (
        f"{value:g} kWh per {unit} is not {carrier}'s (economics.energy_carrier: {low:g}-"
        f"{high:g} kWh/{unit})"
        if known
        else f"{value:g} kWh per {unit} is no {kind}'s ({low:g}-{high:g} kWh/{unit}: {fuels})"
    )
    if low <= value / MJ_PER_KWH <= high:
        return (
            f"{reason}; {value:g} looks like MJ/{unit}: divide by {MJ_PER_KWH:g} and write "
            f"{value / MJ_PER_KWH:.3g}"
        )
    return f"{reason}; give the energy of one {unit} in kWh (the fuel bill's calorific value)"


class MeasurementsConfig(_Strict):
    """Where the measurements are and how their columns are named."""

    file: Path
    time_column: str = "time"
    columns: dict[str, str] = Field(
        default_factory=lambda: {name: name for name in MEASUREMENT_COLUMNS},
        description="mapping standard name -> column in the file",
    )
    flow_unit: Literal["m3/s", "m3/h", "l/s", "l/min", "l/h"] = "m3/s"
    temperature_unit: Literal["C", "K", "F"] | dict[str, Literal["C", "K", "F"]] = Field(
        "C",
        description="unit of the temperature columns: one for all, or per standard name "
        "(e.g. {temp_in: F} for a thermostat's log in Fahrenheit)",
    )
    timezone: str | float | None = Field(
        None, description="time zone of naive timestamps (name or hours from UTC)"
    )
    decimal: Literal[".", ","] = Field(
        ".", description="decimal mark of the file's numbers: ',' for a European export"
    )
    time_format: str | None = Field(
        None,
        description="strftime format of the time column when it is not ISO 8601, e.g. "
        "'%d.%m.%Y %H:%M' (day-first or month-first dates and 12-hour AM/PM clocks are "
        "recognised without it)",
    )
    rows: Literal["interval_start", "interval_end"] = Field(
        "interval_start",
        description="each row is the mean over the logging interval, labelled by its start "
        "(default) or by its end (as many loggers and BMS exports write)",
    )
    irradiance: Literal["dni_dhi", "ghi"] = Field(
        "dni_dhi",
        description="dni_dhi: the columns dni and dhi; ghi: a pyranometer's global horizontal "
        "irradiance alone, split into beam and diffuse by the Erbs et al. (1982) correlation",
    )
    step: str = Field("1h", description="resampling step of the calibration data")
    heat_source: Literal["hydronic", "heat_meter", "fuel_meter"] = Field(
        "hydronic",
        description="hydronic: flow x (supply - return); heat_meter: the 'heat' column is the "
        "useful heat; fuel_meter: the 'heat' column is fuel energy, times boiler_efficiency",
    )
    heat_unit: Literal["W", "kW", "Wh", "kWh", "MWh", "MJ", "GJ", "m3", "l"] = Field(
        "kW",
        description="unit of the heat column: power (mean over the row) or energy; for a fuel "
        "meter also the fuel's volume, m3 (gas) or l (oil), with fuel_kWh_per_unit",
    )
    fuel_kWh_per_unit: float | None = Field(
        None,
        gt=0.0,
        description="energy of one m3 or l of fuel [kWh] (the gas bill's calorific value, e.g. "
        "10.5 kWh/m3 for natural gas; about 10 kWh/l for heating oil)",
    )
    heat_cumulative: bool = Field(
        False, description="the heat column is a meter reading (counter), not per-row energy"
    )
    boiler_efficiency: float | None = Field(
        None, gt=0.3, le=1.1, description="useful heat / fuel energy (fuel_meter) [-]"
    )

    def required_columns(self, electricity: bool = False) -> list[str]:
        """Standard names read from the file for this heat source (and electricity meter)."""
        names = ["temp_out", *HEAT_SOURCE_COLUMNS[self.heat_source], *self.irradiance_columns(),
                 "temp_in"]  # fmt: skip
        return names + (["electricity"] if electricity else [])

    def irradiance_columns(self) -> tuple[str, ...]:
        """The irradiance columns read from the file (standard names)."""
        return ("ghi",) if self.irradiance == "ghi" else ("dni", "dhi")

    @model_validator(mode="before")
    @classmethod
    def _meter_keys_need_a_meter(cls, data: Any) -> Any:
        """Refuse a heat meter's column or unit beside ``heat_source: hydronic``, which
        computes the heat from the flow and the water temperatures and would ignore them."""
        if not isinstance(data, dict) or data.get("heat_source", "hydronic") != "hydronic":
            return data
        columns = data.get("columns")
        ignored = []
        if isinstance(columns, dict) and "heat" in columns:
            ignored.append(f"columns.heat ({columns['heat']!r})")
        if data.get("heat_unit", "kW") != "kW":
            ignored.append(f"heat_unit ({data['heat_unit']!r})")
        if data.get("heat_cumulative"):
            ignored.append("heat_cumulative")
        if ignored:
            raise ValueError(
                f"{' and '.join(ignored)}: a heat or fuel meter's "
                f"{'key' if len(ignored) == 1 else 'keys'}, but heat_source is 'hydronic' (the "
                "default), which computes the heat from flow x "
                "(supply - return) and ignores the meter: set heat_source: heat_meter (the "
                "meter gives the useful heat) or fuel_meter (fuel energy, with "
                "boiler_efficiency) to use it, or remove "
                + " and ".join(key.split(" ")[0] for key in ignored)
            )
        return data

    @model_validator(mode="after")
    def _fuel_needs_efficiency(self) -> MeasurementsConfig:
        if self.heat_source == "fuel_meter" and self.boiler_efficiency is None:
            raise ValueError(
                "heat_source 'fuel_meter' needs measurements.boiler_efficiency (useful heat / "
                "fuel energy, e.g. 0.85 for an older oil boiler, 0.95 for a condensing one)"
            )
        if self.heat_source != "fuel_meter" and self.boiler_efficiency is not None:
            raise ValueError(
                "measurements.boiler_efficiency applies to heat_source: fuel_meter only"
            )
        volume = self.heat_unit in FUEL_VOLUME_UNITS
        if volume and self.heat_source != "fuel_meter":
            raise ValueError(
                f"measurements.heat_unit {self.heat_unit!r} is a fuel's volume: it needs "
                "heat_source: fuel_meter (and fuel_kWh_per_unit, boiler_efficiency)"
            )
        if volume and self.fuel_kWh_per_unit is None:
            raise ValueError(
                f"measurements.heat_unit {self.heat_unit!r} needs measurements."
                f"fuel_kWh_per_unit: the energy of one {self.heat_unit} of fuel in kWh (the gas "
                "bill's calorific value, e.g. 10.5 kWh/m3 for natural gas; about 10 kWh/l for "
                "heating oil)"
            )
        if not volume and self.fuel_kWh_per_unit is not None:
            raise ValueError(
                "measurements.fuel_kWh_per_unit applies to a fuel meter read in m3 or l "
                "(heat_unit)"
            )
        if volume:
            why = fuel_energy_problem(self.fuel_kWh_per_unit, self.heat_unit)
            if why is not None:
                raise ValueError(f"fuel_kWh_per_unit {why}")
        if self.heat_cumulative and self.heat_unit in ("W", "kW"):
            raise ValueError(
                f"measurements.heat_cumulative: a meter reading is an energy, not a power "
                f"({self.heat_unit}); set heat_unit to kWh, MWh, MJ, ..."
            )
        return self

    @field_validator("temperature_unit")
    @classmethod
    def _temperature_names(cls, value):
        if isinstance(value, dict):
            other = sorted(set(value) - set(TEMPERATURE_NAMES))
            if other:
                raise ValueError(
                    f"temperature_unit: {other} are not temperature columns; use "
                    f"{list(TEMPERATURE_NAMES)} as keys"
                )
        return value

    @field_validator("step")
    @classmethod
    def _grid_step(cls, value: str) -> str:
        """A step that divides an hour (the method is hourly at most)."""
        why = step_problem(value)
        if why is not None:
            raise ValueError(why)
        return value

    def temperature_unit_of(self, name: str) -> str:
        """The declared unit of the temperature column ``name`` (a standard name)."""
        if isinstance(self.temperature_unit, dict):
            return self.temperature_unit.get(name, "C")
        return self.temperature_unit

    @field_validator("columns")
    @classmethod
    def _known_names(cls, value: dict[str, str]) -> dict[str, str]:
        unknown = sorted(set(value) - set(MEASUREMENT_COLUMNS))
        if unknown:
            raise ValueError(
                f"unknown standard names {unknown}; use {sorted(MEASUREMENT_COLUMNS)} as keys"
            )
        missing = sorted(set(MEASUREMENT_COLUMNS) - set(value))
        full = {name: name for name in missing}
        full.update(value)
        roles: dict[str, list[str]] = {}
        for role, column in full.items():
            roles.setdefault(column, []).append(role)
        shared = {column: names for column, names in roles.items() if len(names) > 1}
        if shared:
            column, names = next(iter(shared.items()))
            raise ValueError(
                f"column {column!r} is given for {' and '.join(sorted(names))}; every role "
                "needs its own column of the measurements file"
            )
        return full


class WeatherConfig(_Strict):
    """The typical-year weather file for the annual demand (EPW, TMY3 or CSV)."""

    file: Path
    format: Literal["epw", "tmy3", "csv"] | None = None
    columns: dict[str, str] | None = None
    site: Literal["building", "weather"] = Field(
        "building",
        description="whose site when the building's location is more than 300 km from the "
        "weather file's: building (refused, the default: another place's sun and climate) or "
        "weather (the weather file's latitude, longitude and altitude replace the building's, "
        "as EnergyPlus does for a weather-file run; said in a warning and the notes)",
    )


def date_text(value: Any) -> Any:
    """A configuration's date as text: a YAML date (``2005-01-01`` unquoted) in ISO form, a
    text checked to be a date (``2005-02-30``, which the YAML reader keeps as text, is refused
    here with the key's name instead of failing later); None and other types unchanged.

    Parameters
    ----------
    value : datetime.date, str or None
        The value as read.

    Returns
    -------
    str or None or the value
    """
    import datetime as _dt

    import pandas as pd

    if isinstance(value, _dt.date):
        return value.isoformat()
    if isinstance(value, str):
        try:
            pd.Timestamp(value)
        except (ValueError, OverflowError) as exc:
            raise ValueError(f"{value!r} is not a date ({exc}); write it as YYYY-MM-DD") from None
    return value


class PeriodsConfig(_Strict):
    """Training and test periods: explicit dates, or lengths from the first measurement."""

    training_start: str | None = None
    # at most ten years: beyond, the period is certainly a unit slip (hours or seconds)
    training_days: float = Field(21.0, gt=0, le=3660)
    test_days: float = Field(21.0, ge=0, le=3660)

    @field_validator("training_start", mode="before")
    @classmethod
    def _yaml_date(cls, value: Any) -> Any:
        """A YAML date (``training_start: 2005-01-01``) is read as that date."""
        return date_text(value)

    @field_validator("training_days")
    @classmethod
    def _long_enough(cls, value: float) -> float:
        """Refuse a training period too short to separate the heat loss from the capacities."""
        if value < MIN_TRAINING_DAYS:
            raise ValueError(
                f"{value:g} days are too few to calibrate the fifth-order model: at least "
                f"{MIN_TRAINING_DAYS:g} days are needed, because the envelope's and the internal "
                "mass's time constants are days long, so a shorter record cannot tell the heat "
                "loss coefficient from the capacities (and its interval would be far too "
                "narrow); the method's case study uses 21 days"
            )
        return value


#: Diffusion of the slow states (envelope, floor, internal mass) with
#: ``model.slow_state_diffusion: fixed`` [K/sqrt(h)]: a random walk of 0.2 K over three weeks.
SLOW_STATE_DIFFUSION = 0.01


class ModelConfig(_Strict):
    """Options of the fifth-order model."""

    solar_to_internal_mass: float = Field(
        0.5, ge=0, le=1, description="fraction of window solar gains absorbed by internal mass"
    )
    solar_gains: bool = Field(True, description="model solar gains (needs windows, dni, dhi)")
    n_starts: int = Field(1, ge=1, description="optimiser starts of the maximum likelihood fit")
    max_correlation: float = Field(0.98, gt=0, le=1)
    ground_depth: float = Field(2.0, gt=0, description="depth of the ground temperature [m]")
    seed: int = 0
    bounds: dict[str, tuple[float, float]] = Field(
        default_factory=dict,
        description="estimation bounds [lower, upper] of H_est [W/K] and the capacities "
        "C_env, C_gf, C_im, C_i, C_h [MJ/K], replacing the defaults from the building file",
    )
    fixed: dict[str, float] = Field(
        default_factory=dict,
        description="parameters held at a value instead of estimated: H_est [W/K] or a "
        "capacity [MJ/K]",
    )
    fixed_noise: dict[Literal["sigma_Ti", "sigma_Tenv", "sigma_Tgf", "sigma_Tim", "sigma_Th"],
                      PositiveFloat] = Field(
        default_factory=dict,
        description="diffusions held at a value [K/sqrt(h)] instead of estimated (the remedy "
        "for a diffusion-dominated state)",
    )  # fmt: skip
    correction: Literal["groups", "none"] = Field(
        "groups",
        description="groups: estimate a factor on the calculated U-values of roof + walls, "
        "windows and floor with a prior from uncertainty.u_value_rel_std (the data can lower "
        "or raise the calculated losses); none: the published topology (only H_est added)",
    )
    slow_state_diffusion: Literal["fixed", "estimated"] = Field(
        "estimated",
        description="fixed: the diffusions of the envelope, floor and internal-mass states "
        f"held at {SLOW_STATE_DIFFUSION} K/sqrt(h) in the temperature fit, so that the filter "
        "cannot hold those unmeasured states where the data want instead of where the physics "
        "sends them; "
        "estimated: the method's (every diffusion estimated); model.fixed_noise overrides "
        "either per state (docs/retrofit.md 'The room's inside')",
    )
    interior: Literal["auto", "combined", "split"] = Field(
        "auto",
        description="the room's inside: combined: each element's surface resistance Rsi to "
        "the indoor air (the method's); split: convection to the air and long-wave radiation "
        "among the surfaces (a convectively heated room controlled on its air temperature); "
        "auto: split with the heat fit (a thermostat holds the air temperature), combined "
        "with the temperature fit (docs/retrofit.md 'The room's inside')",
    )
    calibration: Literal["auto", "temperature", "heat"] = Field(
        "auto",
        description="temperature: the method's maximum-likelihood fit of the measured indoor "
        "temperature; heat: the model fitted to the metered heat it needs to follow the "
        "thermostat's set point (closed-loop identification); auto: heat when a thermostat "
        "holds the indoor temperature in the training period (median deviation from its "
        "daily profile below 0.1 K), else temperature",
    )
    air_change: Literal["slope", "constant"] = Field(
        "slope",
        description="slope: the air-change loss grows with the indoor-outdoor difference (stack "
        "effect): the calibration period's daily heat residuals regressed on that difference "
        "and, when the slope is resolved (2 standard errors), applied to each heated day of the "
        "demand year (docs/retrofit.md, 'Air change and the temperature difference'); "
        "constant: H_est as calibrated, the same at every difference",
    )

    def fixed_diffusions(self) -> dict[str, float]:
        """The diffusions held at a value [K/sqrt(h)]: the slow states' when
        ``slow_state_diffusion`` is "fixed", then ``fixed_noise`` over them."""
        fixed = (
            dict.fromkeys(("sigma_Tenv", "sigma_Tgf", "sigma_Tim"), SLOW_STATE_DIFFUSION)
            if self.slow_state_diffusion == "fixed" else {}
        )  # fmt: skip
        fixed.update(self.fixed_noise)
        return fixed

    @model_validator(mode="after")
    def _bounds_and_fixed(self) -> ModelConfig:
        from thermocal.retrofit.model import ESTIMATED_PARAMETERS

        for key, names in (("bounds", self.bounds), ("fixed", self.fixed)):
            unknown = sorted(set(names) - set(ESTIMATED_PARAMETERS))
            if unknown:
                raise ValueError(
                    f"model.{key}: unknown parameters {unknown}; allowed: "
                    f"{list(ESTIMATED_PARAMETERS)}"
                )
        for name, (lo, hi) in self.bounds.items():
            if not 0 <= lo < hi:
                raise ValueError(
                    f"model.bounds.{name}: needs 0 <= lower < upper, got [{lo}, {hi}] "
                    f"({'W/K' if name == 'H_est' else 'MJ/K'})"
                )
        for name, value in self.fixed.items():
            if not value > 0:
                raise ValueError(f"model.fixed.{name}: needs a positive value, got {value}")
        if len(self.fixed) == len(ESTIMATED_PARAMETERS):
            raise ValueError("model.fixed: at least one parameter must stay estimated")
        return self


#: Fewest Monte Carlo draws that make an interval (0: none) [-].
MIN_DRAWS = 10

#: What the outputs say where an interval would stand when ``uncertainty.draws`` is 0 (no
#: uncertainty analysis: the estimate alone, not an interval of zero width).
NO_INTERVAL = "no interval (uncertainty.draws: 0)"


class UncertaintyConfig(_Strict):
    """Propagation of the parameter uncertainty into demands and savings."""

    draws: int = Field(200, ge=0, le=MAX_DRAWS)
    interval: float = Field(0.90, gt=0, lt=1)
    u_value_rel_std: float = Field(
        0.2,
        ge=0,
        le=0.5,
        description="relative standard deviation of the audit U-values of roof, walls, windows "
        "and floor: the prior of the group corrections (model.correction: groups), or a spread "
        "around the fit with model.correction: none (0: only the estimation uncertainty, as "
        "in the fifth-order RC method)",
    )
    seed: int = 0
    heat_rel_std: float = Field(
        0.03,
        ge=0,
        le=0.3,
        description="relative standard uncertainty of the measured heat as a whole (meter "
        "calibration, flow and temperature-difference errors); with model.correction: groups "
        "it scales every estimated conductance and capacity in the draws",
    )
    ground: bool = Field(
        True,
        description="draw the ground's uncertain inputs: the soil conductivity, an unheated "
        "basement's air change and the slab-edge psi a floor-insulation measure leaves "
        "(thermocal.retrofit.ground_draws; false: the building file's values in every draw); "
        "on a slab with model.correction: groups the floor group's factor carries the soil",
    )

    @field_validator("draws")
    @classmethod
    def _enough_for_an_interval(cls, value: int) -> int:
        if 0 < value < MIN_DRAWS:
            raise ValueError(
                f"{value} draws give no 90 % interval (with 1 its ends are one draw, beside the "
                f"estimate); give at least {MIN_DRAWS} (200 by default; the report states each "
                "interval end's Monte Carlo error), or 0 for none"
            )
        return value


class ValidationConfig(_Strict):
    """Test-period criteria of the validation gate (:mod:`thermocal.retrofit.gate`); when one
    fails, the report recommends nothing."""

    max_abs_bias_K: float = Field(
        1.0, gt=0, description="|mean simulated - mean measured| indoor temperature [K]"
    )
    max_mae_K: float = Field(1.5, gt=0, description="mean absolute error of Ti [K]")
    max_abs_nmbe_pct: float = Field(
        10.0, gt=0, description="|NMBE| of the daily heat, ASHRAE Guideline 14 [%]"
    )
    max_cv_rmse_pct: float = Field(
        30.0, gt=0, description="CV(RMSE) of the daily heat, ASHRAE Guideline 14 [%]"
    )


#: Envelope components whose U-value a heat-flux meter can measure in situ (ISO 9869-1:
#: opaque elements between the heated inside and the outside or an unheated space), with the
#: direction of their heat flow, their building-file type and their surface resistances
#: (inside, other side) [m2 K/W] (ISO 6946 Table 7; towards an unheated space the inside value
#: on both sides, as the model takes them). Towards an unheated space the "outside" air of a
#: measurement is that space's air.
IN_SITU_COMPONENTS: dict[str, tuple[str, str, tuple[float, float]]] = {
    "walls": ("horizontal", "external_wall", (0.13, 0.04)),
    "roof": ("upward", "roof", (0.10, 0.04)),
    "attic_ceiling": ("upward", "attic_ceiling", (0.10, 0.10)),
    "wall_to_unheated": ("horizontal", "wall_to_unheated", (0.13, 0.13)),
    "cellar_ceiling": ("downward", "cellar_ceiling", (0.17, 0.17)),
}

#: Below this the largest of a household's internal gains is a unit slip (kW written) [W].
MIN_HOUSEHOLD_GAINS_W = 10.0


class InternalGainsConfig(_Strict):
    """Internal gains (occupants, appliances, lighting) into the heated air [W].

    ``none``: no input (the calibration then attributes the gains' effect to the losses, as
    the fifth-order method does); ``constant``: ``constant_W``; ``schedule``: 24 hourly values
    ``schedule_W`` (hour 0..23 local standard time, repeated every day); ``electricity``: the
    measurements' ``electricity`` column times ``fraction_inside`` during the measurements,
    its mean 24-hour profile in the demand year.

    ``occupants`` (on top of any source, also of ``none``): the number of people living in the
    house; their sensible heat ``occupant_sensible_W`` per person (default 70 W) times the
    hourly presence ``occupant_presence`` (default: 12 hours a day), both SIA 380/1:2016
    standard use values of housing (:mod:`thermocal.retrofit.gains`), relative uncertainty
    ``occupants_rel_std`` in the draws.
    """

    source: Literal["none", "constant", "schedule", "electricity"] = "none"
    constant_W: float | None = Field(None, ge=0, le=50_000, description="[W]")
    schedule_W: list[float] | None = Field(None, description="24 hourly values [W]")
    electricity_unit: Literal["W", "kW", "Wh", "kWh", "MWh", "MJ", "GJ"] = Field(
        "kW", description="unit of the electricity column: power or energy per row"
    )
    electricity_cumulative: bool = Field(False, description="the column is a meter reading")
    fraction_inside: float = Field(
        1.0, gt=0, le=1.0, description="share of the metered electricity released as heat "
        "inside the heated envelope (not: outdoor lights, a heat-pump compressor outside)",
    )  # fmt: skip
    rel_std: float = Field(
        0.3, ge=0, le=1.0, description="relative standard deviation of the gains in the demand"
    )
    occupants: float | None = Field(
        None, description="number of people living in the house (their sensible heat is on "
        "no meter; added to the source's gains)",
    )  # fmt: skip
    occupant_sensible_W: float = Field(
        70.0, description="sensible heat per occupant while present [W] (SIA 380/1:2016: 70 W)"
    )
    occupant_presence: list[float] | None = Field(
        None, description="24 hourly presence fractions 0..1 (hour 0..23, local standard "
        "time); default: thermocal.retrofit.gains.OCCUPANT_PRESENCE, 12 h a day (SIA 380/1)",
    )  # fmt: skip
    occupants_rel_std: float = Field(
        0.3, ge=0, le=1.0, description="relative standard deviation of the occupants' gains "
        "(presence and heat per person) in the demand",
    )  # fmt: skip

    @field_validator("occupants")
    @classmethod
    def _people(cls, value: float | None) -> float | None:
        """A house's occupants: not negative, not a block of flats."""
        if value is not None and not 0 <= value <= MAX_OCCUPANTS:
            raise ValueError(
                f"occupants = {value:g}: the number of people living in the house, between 0 "
                f"and {MAX_OCCUPANTS}"
            )
        return value

    @field_validator("occupant_sensible_W")
    @classmethod
    def _per_person(cls, value: float) -> float:
        """A person's sensible heat lies between sleeping (~40 W) and housework (~150 W)."""
        lo, hi = OCCUPANT_SENSIBLE_RANGE_W
        if not lo <= value <= hi:
            hint = f"; is it in kW? then write {value * 1000:g}" if 0 < value < 1 else ""
            raise ValueError(
                f"occupant_sensible_W = {value:g}: the sensible heat of one person [W], between "
                f"{lo:g} (asleep) and {hi:g} (active){hint}"
            )
        return value

    @field_validator("occupant_presence")
    @classmethod
    def _presence(cls, value: list[float] | None) -> list[float] | None:
        if value is None:
            return value
        if len(value) != 24:
            raise ValueError(f"occupant_presence needs 24 hourly fractions, got {len(value)}")
        bad = [f"hour {h}: {v:g}" for h, v in enumerate(value) if not 0.0 <= v <= 1.0]
        if bad:
            raise ValueError(
                "occupant_presence: fractions of the occupants at home, between 0 and 1 ("
                + ", ".join(bad[:3])
                + ")"
            )
        return value

    @model_validator(mode="after")
    def _complete(self) -> InternalGainsConfig:
        given = {"occupant_sensible_W", "occupant_presence"} & self.model_fields_set
        if given and self.occupants is None:
            raise ValueError(
                f"{', '.join(sorted(given))} without occupants: give the number of people "
                "(internal_gains.occupants)"
            )
        if self.source == "constant" and self.constant_W is None:
            raise ValueError("source 'constant' needs constant_W [W]")
        for key, used in (("constant_W", "constant"), ("schedule_W", "schedule")):
            if getattr(self, key) is not None and self.source != used:
                raise ValueError(
                    f"{key} is given but source is '{self.source}', so it would be ignored: set "
                    f"source: {used} (or remove {key})"
                )
        if self.source == "schedule":
            if self.schedule_W is None or len(self.schedule_W) != 24:
                raise ValueError("source 'schedule' needs schedule_W: 24 hourly values [W]")
            if min(self.schedule_W) < 0:
                raise ValueError("schedule_W: gains must not be negative")
        values = (
            [self.constant_W] if self.source == "constant" else list(self.schedule_W or [])
        )
        if self.source in ("constant", "schedule") and 0 < max(values) < MIN_HOUSEHOLD_GAINS_W:
            key = "constant_W" if self.source == "constant" else "schedule_W"
            raise ValueError(
                f"{key} at most {max(values):g} W: not a household's internal gains (a few "
                f"hundred W: appliances, lights, people); is it in kW? then write "
                f"{1000 * max(values):g}"
            )
        if self.electricity_cumulative and self.electricity_unit in ("W", "kW"):
            raise ValueError(
                "electricity_cumulative: a meter reading is an energy; set electricity_unit "
                "to kWh, MWh, MJ, ..."
            )
        return self


class ReferenceConfig(_Strict):
    """Optional reference values shown next to the simulated demand."""

    rating_label: str = "SIA 380/1"
    rating_kWh: float | None = Field(None, ge=0, description="annual demand of a rating [kWh]")
    rating_monthly_kWh: list[float] | None = None
    measured_fuel_kWh: float | None = Field(None, ge=0)
    boiler_efficiency: float | None = Field(None, gt=0, le=1.2)
    audit_heat_loss_coefficient_W_per_K: float | None = Field(None, gt=0)
    true_heat_loss_coefficient_W_per_K: float | None = Field(
        None, gt=0, description="known HLC (synthetic data only)"
    )

    @field_validator("measured_fuel_kWh", "rating_kWh")
    @classmethod
    def _kilowatt_hours(cls, value: float | None) -> float | None:
        """An annual energy above 2 GWh is no house's: Wh written where kWh belong."""
        if value is not None and value > MAX_ANNUAL_KWH:
            raise ValueError(
                f"{value:,.0f} kWh a year is the heating of a hundred houses (at most "
                f"{MAX_ANNUAL_KWH:,.0f} kWh accepted); is it in Wh? then write {value / 1000:,.0f}"
            )
        return value

    @field_validator("audit_heat_loss_coefficient_W_per_K")
    @classmethod
    def _watts_per_kelvin(cls, value: float | None) -> float | None:
        """A heat loss coefficient below 5 W/K is no building's: kW/K written as W/K."""
        if value is not None and value < MIN_HEAT_LOSS_COEFFICIENT:
            raise ValueError(
                f"{value:g} W/K is far below any building's heat loss coefficient (at least "
                f"{MIN_HEAT_LOSS_COEFFICIENT:g} W/K); is it in kW/K? then write {value * 1000:g}"
            )
        return value

    @field_validator("rating_monthly_kWh")
    @classmethod
    def _twelve(cls, value: list[float] | None) -> list[float] | None:
        if value is not None and len(value) != 12:
            raise ValueError(f"needs 12 monthly values, got {len(value)}")
        return value


#: What a measure can act on (``measures.<name>.component``): every part of
#: :data:`thermocal.retrofit.strategies.MEASURE_COMPONENTS`, so that two options on one part
#: (an attic ceiling with 15 or 25 cm) can be compared under names of their own.
MeasureComponent = Literal[MEASURE_COMPONENTS]


class MeasureConfig(_Strict):
    """One retrofit measure (see :class:`thermocal.retrofit.strategies.Measure`)."""

    component: MeasureComponent | None = Field(
        None, description="what it acts on (default: the measure's name)"
    )
    u_value: float | None = Field(None, ge=0.05, le=6.0, description="U after retrofit [W/(m2 K)]")
    g_value: float | None = Field(None, gt=0.0, lt=1.0, description="window g-value after [-]")
    air_change_rate_change: float = Field(
        0.0, ge=-3.0, le=3.0, description="change of the infiltration rate [1/h] (airtightness)"
    )
    air_change_rate: float = Field(
        0.0, ge=0.0, le=3.0, description="mechanical ventilation rate [1/h] (heat_recovery)"
    )
    efficiency: float = Field(
        0.0, ge=0.0, le=0.95, description="heat-recovery temperature efficiency [-]"
    )
    cost_per_m2: float | None = Field(
        None,
        ge=0,
        description="cost per m2 of the component (heated floor area for "
        "airtightness / heat_recovery) [currency/m2]",
    )
    cost: float = Field(0.0, ge=0, description="fixed cost [currency]")
    description: str = ""


#: Largest plausible emission factor of final energy [kg CO2-eq/kWh].
MAX_EMISSION_FACTOR = 2.0
#: Largest plausible price of final energy in the currencies worth about a US dollar
#: [currency/kWh]; other currencies (yen, rupees, ...) are not checked.
MAX_ENERGY_PRICE = 2.0
MAJOR_CURRENCIES = frozenset({"CHF", "EUR", "USD", "GBP", "CAD", "AUD", "NZD"})


#: Emission factor of final energy per energy carrier [kg CO2-eq/kWh]: GEG (2020) Anlage 9,
#: the values docs/retrofit.md gives; a heat pump's final energy is grid electricity. District
#: heating has none: its factor is its utility's (the plants' mix).
CARRIER_EMISSION_FACTORS: dict[str, float] = {
    "heating oil": 0.310,
    "natural gas": 0.240,
    "electricity": 0.560,
    "heat pump": 0.560,
    "wood": 0.020,
}
#: Other spellings of the known carriers (lower case, any character other than a letter or a
#: digit read as a space), each matched as whole words (:func:`energy_carrier_reading`).
CARRIER_ALIASES: dict[str, str] = {
    "oil": "heating oil",
    "fuel oil": "heating oil",
    "heating fuel oil": "heating oil",
    "gas": "natural gas",
    "grid electricity": "electricity",
    "electric": "electricity",
    "direct electric": "electricity",
    "electric heating": "electricity",
    "district heat": "district heating",
    "heat network": "district heating",
    "wood pellets": "wood",
    "pellets": "wood",
    "wood chips": "wood",
    "firewood": "wood",
    "logs": "wood",
}
#: Other spellings of a carrier's full name: in a longer text they name it as its name does.
CARRIER_SPELLINGS: dict[str, str] = {
    "heatpump": "heat pump",
    "fernwärme": "district heating",
    "fernwaerme": "district heating",
}
#: Annual system efficiency of a boiler with its distribution (useful heat / final energy)
#: [-]: the default of ``economics.system_efficiency`` for the fuels.
BOILER_SYSTEM_EFFICIENCY = 0.85
#: Default system efficiency [-] of the carriers a boiler's cannot stand for: direct electric
#: heating turns all its electricity into heat; a heat pump's is its seasonal performance
#: factor (useful heat / electricity over the year; about 2.5-3.5 air-water, 4 brine-water);
#: district heating's is 1 at the building's substation (the heat bought is the heat metered).
CARRIER_SYSTEM_EFFICIENCY: dict[str, float] = {
    "electricity": 1.0,
    "heat pump": 3.0,
    "district heating": 1.0,
}
#: The carriers ``economics.energy_carrier`` can name, with a default emission factor or
#: system efficiency (or both).
KNOWN_CARRIERS: tuple[str, ...] = tuple(
    dict.fromkeys([*CARRIER_EMISSION_FACTORS, *CARRIER_SYSTEM_EFFICIENCY])
)
#: The volume a fuel meter of each fuel reads (``measurements.heat_unit``): another volume
#: contradicts the carrier (:func:`fuel_unit_note`).
CARRIER_FUEL_UNIT: dict[str, str] = {"heating oil": "l", "natural gas": "m3"}


def _carrier_words(text: str) -> str:
    """``text`` in lower case, every run of characters other than letters and digits one
    space (``"Air-source heat_pump (hybrid)"`` -> ``"air source heat pump hybrid"``)."""
    return " ".join(re.sub(r"[\W_]+", " ", text.lower()).split())


def energy_carrier_reading(text: str) -> tuple[str | None, tuple[str, ...]]:
    """The carrier ``economics.energy_carrier`` names, and every carrier it names.

    The text (case and punctuation aside) is a carrier's name or alias
    (:data:`KNOWN_CARRIERS`, :data:`CARRIER_SPELLINGS`, :data:`CARRIER_ALIASES`), or contains
    them as whole words. A longer text names one carrier when it contains that carrier's full
    name (or another spelling of it) and no other
    carrier's name or alias (``"air-source heat pump"``, ``"natural gas condensing boiler"``;
    electricity beside a heat pump is the heat pump's); an alias alone in a longer text names
    none (``"propane gas"`` is not natural gas); several carriers are none either
    (``"gas boiler + heat pump (hybrid)"``: no carrier's defaults are taken, and
    :meth:`RetrofitConfig.economics_notes` says so).

    Parameters
    ----------
    text : str
        The energy carrier as written.

    Returns
    -------
    tuple of (str or None, tuple of str)
        The carrier (None: none or several), and the carriers named (several: ambiguous).
    """
    words = _carrier_words(text)
    exact = (
        words if words in KNOWN_CARRIERS
        else CARRIER_SPELLINGS.get(words) or CARRIER_ALIASES.get(words)
    )  # fmt: skip
    if exact is not None:
        return exact, (exact,)
    padded = f" {words} "
    spellings = [(name, name) for name in KNOWN_CARRIERS] + list(CARRIER_SPELLINGS.items())
    full = [name for spelling, name in spellings if f" {spelling} " in padded]
    aliased = [c for alias, c in CARRIER_ALIASES.items() if f" {alias} " in padded]
    named = list(dict.fromkeys(full + aliased))
    if "heat pump" in named and "electricity" in named:
        named.remove("electricity")  # an electric heat pump
    one = len(named) == 1 and named[0] in full
    return (named[0] if one else None), tuple(named)


def energy_carrier_name(text: str) -> str | None:
    """The known carrier that ``economics.energy_carrier`` names (:func:`energy_carrier_reading`).

    Parameters
    ----------
    text : str
        The energy carrier as written, e.g. ``"Natural gas"``, ``"air-source heat pump"``.

    Returns
    -------
    str or None
        One of :data:`KNOWN_CARRIERS` (``"heating oil"``, ``"natural gas"``, ``"electricity"``,
        ``"heat pump"``, ``"wood"``, ``"district heating"``); None for a carrier without
        defaults (propane, ...) or a text naming several.
    """
    return energy_carrier_reading(text)[0]


class EconomicsConfig(_Strict):
    """Final energy, running cost, CO2 and payback of the strategies.

    The defaults are documented in docs/retrofit.md with their sources; they are placeholders
    of the right order of magnitude for an oil-heated Swiss house, not advice: set your own.
    ``energy_carrier`` sets the default of ``emission_factor`` (:data:`CARRIER_EMISSION_FACTORS`;
    district heating has none). ``system_efficiency`` has one rule: a value given; else the
    carrier's own (:data:`CARRIER_SYSTEM_EFFICIENCY`: electricity 1, heat pump 3, district
    heating 1); else, for a boiler (any other carrier) with a fuel meter, the measured
    boiler's ``measurements.boiler_efficiency``
    (``RetrofitConfig._economics_of_the_measured_boiler``); else
    :data:`BOILER_SYSTEM_EFFICIENCY`.
    The price has no default per carrier (tariffs differ by country and year):
    :meth:`RetrofitConfig.economics_notes` says when a carrier other than heating oil keeps the
    oil price.
    """

    currency: str = "CHF"
    energy_carrier: str = "heating oil"
    system_efficiency: float = Field(
        BOILER_SYSTEM_EFFICIENCY,
        gt=0.1,
        le=5.0,
        description="useful heat / final energy over the year [-] "
        "(boiler + distribution; a heat pump's seasonal COP > 1); default from the carrier",
    )
    energy_price: float = Field(0.12, ge=0, description="price of final energy [currency/kWh]")
    emission_factor: float = Field(
        0.310,
        ge=0,
        description="greenhouse-gas emissions of final energy [kg CO2-eq/kWh]; default from the "
        "carrier (GEG 2020: heating oil 0.310, natural gas 0.240, electricity and heat pump "
        "0.560, wood 0.020; district heating: the utility's, no default)",
    )
    #: The keys the configuration gave (the others are defaults).
    _given: frozenset[str] = PrivateAttr(frozenset())

    @field_validator("emission_factor")
    @classmethod
    def _kilograms(cls, value: float) -> float:
        if value > MAX_EMISSION_FACTOR:
            raise ValueError(
                f"{value:g} kg CO2-eq per kWh of final energy is more than any fuel's (coal about "
                f"0.4, coal-fired electricity about 1.1); in g/kWh? write {value / 1000:g}"
            )
        return value

    @model_validator(mode="after")
    def _price_per_kwh(self) -> EconomicsConfig:
        if self.currency.upper() in MAJOR_CURRENCIES and self.energy_price > MAX_ENERGY_PRICE:
            raise ValueError(
                f"energy_price {self.energy_price:g} {self.currency}/kWh is more than any "
                "final energy costs (heating oil and gas about 0.1, electricity at most about "
                + (
                    f"0.6); per MWh? write {self.energy_price / 1000:g}"
                    if self.energy_price > 20.0
                    else f"0.6); in cents? write {self.energy_price / 100:g}"
                )
            )
        return self

    @model_validator(mode="after")
    def _carrier_defaults(self) -> EconomicsConfig:
        """The carrier's emission factor and system efficiency where none is given; a heat
        pump's given efficiency must be a seasonal COP (above 1)."""
        self._given = frozenset(self.model_fields_set)
        carrier = self.carrier()
        if carrier is None:
            return self
        if "emission_factor" not in self._given and carrier in CARRIER_EMISSION_FACTORS:
            self.emission_factor = CARRIER_EMISSION_FACTORS[carrier]
        if "system_efficiency" not in self._given and carrier in CARRIER_SYSTEM_EFFICIENCY:
            self.system_efficiency = CARRIER_SYSTEM_EFFICIENCY[carrier]
        if carrier == "heat pump" and self.system_efficiency <= 1.0:
            raise ValueError(
                f"system_efficiency {self.system_efficiency:g} with energy_carrier "
                f"{self.energy_carrier!r}: a heat pump's is its seasonal COP (useful heat / "
                "electricity over the year, about 2.5-3.5 air-water, 4 brine-water), above 1"
            )
        return self

    def carrier(self) -> str | None:
        """The carrier with defaults that ``energy_carrier`` names (:func:`energy_carrier_name`)."""
        return energy_carrier_name(self.energy_carrier)

    def given(self, key: str) -> bool:
        """Whether the configuration gave ``key`` (False: a default)."""
        return key in self._given


class DemandConfig(_Strict):
    """Annual demand simulation."""

    indoor_profile: Literal["measured"] | float = Field(
        "measured", description="'measured' (24-h profile of the measured Ti) or a constant [C]"
    )
    profile_period: Literal["all", "training"] = "all"

    @field_validator("indoor_profile")
    @classmethod
    def _celsius(cls, value: str | float) -> str | float:
        """A constant indoor temperature is in C: 293.15 (Kelvin) or 68 (F) is refused."""
        if isinstance(value, str):
            return value
        low, high = INDOOR_PROFILE_RANGE
        if not low <= value <= high:
            hint = ""
            if low <= value - 273.15 <= high:
                hint = f"; Kelvin? write {value - 273.15:.2f}"
            elif low <= (value - 32.0) * 5.0 / 9.0 <= high:
                hint = f"; Fahrenheit? write {(value - 32.0) * 5.0 / 9.0:.1f}"
            raise ValueError(
                f"{value:g} C is not an indoor temperature (expected {low:g}-{high:g} C){hint}"
            )
        return value


def _short_form_measure(name: str, u_value: float) -> MeasureConfig:
    """``walls: 0.2``: the measure on the component of that name with this U-value after the
    retrofit [W/(m2 K)]; a bad value is refused naming the measure (``measures.walls``)."""
    try:
        return MeasureConfig(u_value=u_value)
    except ValidationError as exc:
        reason = "; ".join(str(err["msg"]) for err in exc.errors())
        raise ValueError(
            f"measure {name!r} = {u_value!r} (the U-value after the retrofit [W/(m2 K)]): "
            f"{reason}"
        ) from None


def _listed(items: list[str]) -> str:
    """``a``, ``a and b``, ``a, b and c``."""
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def _oil_defaults_note(
    eco: EconomicsConfig, carrier: str | None, named: tuple[str, ...], fuel_meter: bool
) -> list[str]:
    """The note on a carrier other than heating oil that keeps a default meant for heating
    oil: the oil's price, the oil's emission factor (a carrier without one: district heating,
    propane, ...) or a boiler's system efficiency (a carrier without one), or none.

    Parameters
    ----------
    eco : EconomicsConfig
    carrier : str or None
        :func:`energy_carrier_name` of ``eco.energy_carrier``.
    named : tuple of str
        The carriers the text names (:func:`energy_carrier_reading`; several: ambiguous).
    fuel_meter : bool
        The measurements have a fuel meter (its boiler's efficiency, not 0.85, is then the
        system efficiency's default: nothing to say of it).
    """
    uses = {
        "energy_price": (f"{eco.currency}/kWh", "the running costs and paybacks"),
        "emission_factor": ("kg CO2-eq/kWh", "the CO2"),
    }
    kept = [
        key for key in uses
        if not eco.given(key)
        and (key == "energy_price" or carrier not in CARRIER_EMISSION_FACTORS)
    ]  # fmt: skip
    boiler = (
        carrier is None and not fuel_meter and not eco.given("system_efficiency")
    )  # a boiler's 0.85 kept for a carrier without a default of its own
    if not kept and not boiler:
        return []
    if carrier is None and len(named) > 1:
        why = ""  # the note on the ambiguous text says why
    elif carrier is None:
        why = f" (none of {', '.join(KNOWN_CARRIERS)}, whose defaults are known)"
    elif carrier not in CARRIER_EMISSION_FACTORS:
        why = " (its emission factor is the utility's: no default)"
    else:
        why = ""
    values = []
    if kept:
        oil = " and ".join(
            f"{key} {getattr(eco, key):g} {uses[key][0]} ({uses[key][1]})" for key in kept
        )
        values.append(f"heating oil's {oil}")
    if boiler:
        values.append(
            f"a boiler's system_efficiency {eco.system_efficiency:g} (the final energy)"
        )
    keys = kept + (["system_efficiency"] if boiler else [])
    target = "the heat pump's electricity" if carrier == "heat pump" else eco.energy_carrier
    return [
        f"economics: energy_carrier {eco.energy_carrier!r}{why} keeps {', and '.join(values)}; "
        f"set economics.{_listed(keys)} for {target}"
    ]


def _ambiguous_carrier_note(eco: EconomicsConfig, named: tuple[str, ...]) -> list[str]:
    """The note on an ``energy_carrier`` that names several carriers, or none.

    Parameters
    ----------
    eco : EconomicsConfig
    named : tuple of str
        The carriers the text names (:func:`energy_carrier_reading`).
    """
    if len(named) < 2:
        return []
    return [
        f"economics: energy_carrier {eco.energy_carrier!r} names several carriers "
        f"({', '.join(named)}): none of their defaults is taken. Name the one that supplies "
        "the heat (a hybrid's main one), or give economics.system_efficiency, emission_factor "
        "and energy_price for the mix"
    ]


def fuel_unit_note(
    heat_unit: str, carrier: str | None, energy_carrier: str, given: bool
) -> str | None:
    """The note on a fuel meter whose volume is not the carrier's: a gas meter's m3 beside
    heating oil, an oil meter's l beside natural gas.

    Parameters
    ----------
    heat_unit : str
        ``measurements.heat_unit`` of a fuel meter (``m3`` or ``l``; others: no note).
    carrier : str or None
        :func:`energy_carrier_name` of ``economics.energy_carrier``.
    energy_carrier : str
        ``economics.energy_carrier`` as written.
    given : bool
        The configuration gave ``energy_carrier`` (False: the default, heating oil).

    Returns
    -------
    str or None
        None when the volume fits the carrier, or the carrier has no volume of its own
        (:data:`CARRIER_FUEL_UNIT`; a heat pump or district heating replacing the boiler).
    """
    own = CARRIER_FUEL_UNIT.get(carrier)
    if own is None or heat_unit not in FUEL_VOLUME_UNITS or heat_unit == own:
        return None
    fuel = {"m3": "a gas (natural gas, biogas, propane)",
            "l": "a liquid fuel (heating oil, LPG)"}[heat_unit]  # fmt: skip
    volume = {"m3": "cubic metre", "l": "litre"}
    other = next(c for c, unit in CARRIER_FUEL_UNIT.items() if unit == heat_unit)
    return (
        f"measurements.heat_unit {heat_unit} is the volume of {fuel}, but "
        f"economics.energy_carrier is {energy_carrier!r}{'' if given else ' (the default)'}, "
        f"sold by the {volume[own]}: the final energy's CO2 and costs are {carrier}'s. Set "
        f"economics.energy_carrier to the fuel the meter measures (e.g. {other})"
    )


def _other_carriers_factor_note(eco: EconomicsConfig, carrier: str | None) -> list[str]:
    """The note on an emission factor given as another carrier's (the example configuration's
    heating-oil 0.310 kept beside ``energy_carrier: natural gas``), or none.

    Parameters
    ----------
    eco : EconomicsConfig
    carrier : str or None
        :func:`energy_carrier_name` of ``eco.energy_carrier``.
    """
    if carrier not in CARRIER_EMISSION_FACTORS or not eco.given("emission_factor"):
        return []  # (district heating's factor is its utility's: any value may be right)
    own = CARRIER_EMISSION_FACTORS[carrier]
    other = next(
        (name for name, factor in CARRIER_EMISSION_FACTORS.items()
         if factor != own and abs(factor - eco.emission_factor) < 1e-9),
        None,
    )  # fmt: skip
    if other is None:
        return []
    return [
        f"economics: emission_factor {eco.emission_factor:g} kg CO2-eq/kWh is {other}'s (GEG "
        f"2020), but energy_carrier is {eco.energy_carrier!r} ({own:g}): copied with another "
        f"carrier? leave emission_factor out to take {carrier}'s, or give your own"
    ]


class RetrofitConfig(_Strict):
    """The whole ``thermocal retrofit`` configuration."""

    building: Path | dict[str, Any]
    measurements: MeasurementsConfig
    weather: WeatherConfig
    periods: PeriodsConfig = Field(default_factory=PeriodsConfig)
    model: ModelConfig = Field(default_factory=ModelConfig)
    measures: dict[str, float | MeasureConfig] = Field(
        default_factory=lambda: dict(PAPER_MEASURE_U_VALUES), validate_default=True
    )
    strategies: dict[str, list[str]] | None = Field(
        None, description="code -> measures; default: every combination of the measures"
    )
    economics: EconomicsConfig = Field(default_factory=EconomicsConfig)
    uncertainty: UncertaintyConfig = Field(default_factory=UncertaintyConfig)
    reference: ReferenceConfig = Field(default_factory=ReferenceConfig)
    demand: DemandConfig = Field(default_factory=DemandConfig)
    validation: ValidationConfig = Field(default_factory=ValidationConfig)
    internal_gains: InternalGainsConfig = Field(default_factory=InternalGainsConfig)
    in_situ: dict[str, InSituConfig] = Field(
        default_factory=dict, description="component -> in-situ U-value (ISO 9869-1)"
    )
    base_dir: Path = Field(Path("."), description="folder relative paths refer to")

    @field_validator("measures")
    @classmethod
    def _measures(cls, value: dict) -> dict[str, MeasureConfig]:
        if not value:
            raise ValueError("give at least one measure")
        out: dict[str, MeasureConfig] = {}
        for name, spec in value.items():
            if not isinstance(spec, MeasureConfig):  # short form: the U-value of a component
                spec = _short_form_measure(name, spec)
            component = spec.component or name
            if component not in MEASURE_COMPONENTS:
                raise ValueError(
                    f"measure {name!r}: say what it acts on with 'component:' (one of "
                    f"{list(MEASURE_COMPONENTS)}); a bare number is the U-value of one of "
                    f"{list(MEASURE_ORDER)}"
                )
            if component in U_VALUE_COMPONENTS:
                if spec.u_value is None and spec.g_value is None:
                    raise ValueError(
                        f"measure {name!r} on {component}: give u_value (and/or "
                        "g_value for windows)"
                    )
                if spec.g_value is not None and component != "windows":
                    raise ValueError(f"measure {name!r}: g_value applies to windows only")
            elif spec.u_value is not None or spec.g_value is not None:
                raise ValueError(f"measure {name!r} on {component}: u_value / g_value do not apply")
            if component == "airtightness" and spec.air_change_rate_change == 0:
                raise ValueError(
                    f"measure {name!r}: give air_change_rate_change [1/h] "
                    "(negative: tighter envelope)"
                )
            if component == "airtightness" and spec.air_change_rate_change > 0:
                raise ValueError(
                    f"measure {name!r}: air_change_rate_change "
                    f"{spec.air_change_rate_change:g} 1/h makes the envelope leakier; a measure "
                    f"improves it: write {-spec.air_change_rate_change:g} (negative: tighter)"
                )
            if component == "heat_recovery" and not (
                spec.air_change_rate > 0 and spec.efficiency > 0
            ):
                raise ValueError(
                    f"measure {name!r}: give air_change_rate [1/h] and "
                    "efficiency [-] of the ventilation with heat recovery"
                )
            if spec.cost_per_m2 is None:
                # without a cost of its own a measure takes its component's indicative cost
                # per m2 (a "triple_glazing" on the windows the windows'): 0 made it free, with
                # a payback of 0 years that flipped the recommendation
                default = DEFAULT_COST_PER_M2.get(component)
                if spec.cost == 0 and default is None:
                    raise ValueError(
                        f"measure {name!r} ({component}) has no cost and its component no default "
                        "one: give cost [currency] (or cost_per_m2 [currency/m2])"
                    )
                spec = spec.model_copy(
                    update={"cost_per_m2": default if spec.cost == 0 else 0.0}
                )
            out[name] = spec.model_copy(update={"component": component})
        return out

    def measure_objects(self) -> dict[str, Measure]:
        """The configured measures as :class:`~thermocal.retrofit.strategies.Measure`."""
        return {
            name: Measure(
                name=name, component=m.component, u_value=m.u_value, g_value=m.g_value,
                air_change_rate_change=m.air_change_rate_change,
                heat_recovery_air_change_rate=m.air_change_rate,
                heat_recovery_efficiency=m.efficiency, cost_per_m2=float(m.cost_per_m2 or 0.0),
                cost=m.cost,
                description=m.description or (
                    PAPER_MEASURE_DESCRIPTIONS.get(name, "") if m.component == name else ""
                ),
            )
            for name, m in self.measures.items()
        }  # fmt: skip

    def strategy_list(self):
        """The strategies to analyse: listed ones, or every combination of the measures."""
        measures = self.measure_objects()
        if self.strategies is not None:
            return listed_strategies(self.strategies, measures)
        return all_strategies(tuple(measures), {n: m.component for n, m in measures.items()})

    @model_validator(mode="after")
    def _economics_of_the_measured_boiler(self) -> RetrofitConfig:
        """With a fuel meter, the measured boiler's efficiency is the default system efficiency
        (the calibration turned the fuel into useful heat with it); a known fuel's energy per
        m3 or l is checked against that fuel's range."""
        mc, eco = self.measurements, self.economics
        if mc is None or mc.heat_source != "fuel_meter":
            return self
        carrier = eco.carrier() if eco.given("energy_carrier") else None
        if not eco.given("system_efficiency") and carrier not in CARRIER_SYSTEM_EFFICIENCY:
            eco.system_efficiency = mc.boiler_efficiency
        if mc.fuel_kWh_per_unit is not None:
            why = fuel_energy_problem(mc.fuel_kWh_per_unit, mc.heat_unit, carrier)
            if why is not None:
                raise ValueError(f"measurements.fuel_kWh_per_unit {why}")
        return self

    def economics_notes(self) -> list[str]:
        """What the economics take from a default that may not fit the configured house.

        A carrier text naming several carriers; a carrier other than heating oil that keeps
        the oil price (or, without a known emission factor, the oil's; or, without a system
        efficiency of its own and no fuel meter, a boiler's 0.85); an emission factor given as
        another carrier's; a fuel meter's volume that is not the carrier's; the assumed system
        efficiency of a heat pump, direct electric heating or district heating; and, for a
        boiler (a carrier without a system efficiency of its own), a system efficiency other
        than the boiler efficiency the measurements or the reference use.

        Returns
        -------
        list of str
            One note per finding, each naming the keys to set.
        """
        eco = self.economics
        carrier, named = energy_carrier_reading(eco.energy_carrier)
        mc = self.measurements
        fuel_meter = mc is not None and mc.heat_source == "fuel_meter"
        notes = _ambiguous_carrier_note(eco, named)
        if carrier != "heating oil":
            notes += _oil_defaults_note(eco, carrier, named, fuel_meter)
        notes += _other_carriers_factor_note(eco, carrier)
        if fuel_meter:
            unit = fuel_unit_note(
                mc.heat_unit, carrier, eco.energy_carrier, eco.given("energy_carrier")
            )
            notes += [] if unit is None else [unit]
        if carrier in CARRIER_SYSTEM_EFFICIENCY and not eco.given("system_efficiency"):
            why = {
                "heat pump": "its seasonal COP: useful heat / electricity over the year, about "
                "2.5-3.5 air-water, 4 brine-water",
                "electricity": "direct electric heating; for a heat pump give its seasonal COP",
                "district heating": "the heat bought is the heat metered at the building's "
                "substation",
            }[carrier]
            notes.append(
                f"economics: system_efficiency {eco.system_efficiency:g} assumed for "
                f"{eco.energy_carrier!r} ({why}); set economics.system_efficiency"
            )
        if carrier in CARRIER_SYSTEM_EFFICIENCY:  # a new system: no boiler to agree with
            return notes
        if eco.given("system_efficiency"):
            used = "economics.system_efficiency"
        elif fuel_meter:
            used = "measurements.boiler_efficiency, the default of economics.system_efficiency"
        else:
            used = "the default of economics.system_efficiency"
        for key, value in (
            ("measurements.boiler_efficiency", mc.boiler_efficiency if fuel_meter else None),
            ("reference.boiler_efficiency", self.reference.boiler_efficiency),
        ):  # fmt: skip
            if value is not None and abs(value - eco.system_efficiency) > 0.005:
                notes.append(
                    f"{key} {value:g} differs from the system efficiency of the final energy, "
                    f"cost and CO2, {eco.system_efficiency:g} ({used}): right for a new heating "
                    f"system; for the same boiler set economics.system_efficiency: {value:g}"
                )
        return notes

    @model_validator(mode="after")
    def _strategies(self) -> RetrofitConfig:
        try:
            self.strategy_list()
        except ValueError as exc:
            raise ValueError(f"strategies: {exc}") from None
        return self

    @field_validator("in_situ")
    @classmethod
    def _in_situ(cls, value: dict) -> dict:
        for component in value:
            if component not in IN_SITU_COMPONENTS:
                raise ValueError(
                    f"{component!r}: a heat-flux meter measures one of "
                    f"{list(IN_SITU_COMPONENTS)} (windows have rated U-values; a floor on the "
                    "ground loses through the soil, not its construction alone)"
                )
        return value

    @model_validator(mode="after")
    def _resolve_paths(self) -> RetrofitConfig:
        base = self.base_dir
        if isinstance(self.building, Path) and not self.building.is_absolute():
            self.building = base / self.building
        if not self.measurements.file.is_absolute():
            self.measurements.file = base / self.measurements.file
        if not self.weather.file.is_absolute():
            self.weather.file = base / self.weather.file
        for spec in self.in_situ.values():
            if spec.file is not None and not spec.file.is_absolute():
                spec.file = base / spec.file
        return self


#: pydantic's label of a union member in an error location: a type (``float``,
#: ``dict[str,any]``, ``literal['C','K','F']``, ``lax-or-strict[...]``) or a model class name.
_UNION_LABEL = re.compile(r"^(?:float|int|str|bool|none|[a-z][a-z-]*\[.*\])$", re.DOTALL)


def _is_union_label(part, model_names: frozenset[str]) -> bool:
    """Whether one element of a pydantic error location names a union member (not a key)."""
    return isinstance(part, str) and (bool(_UNION_LABEL.match(part)) or part in model_names)


def _config_model_names() -> frozenset[str]:
    """Names of the configuration's pydantic models (union members in error locations)."""
    return frozenset(
        name for name, obj in globals().items()
        if isinstance(obj, type) and issubclass(obj, BaseModel)
    )  # fmt: skip


def _union_member_errors(members: dict[str, list[dict]], site: tuple, models) -> list[dict]:
    """The errors to show of one value checked against a union (``site``: its location).

    ``members``: union label -> that member's errors. The members that got past the value's
    type (errors deeper than the label) are the value's form: their errors, without labels.
    When none did, one error at ``site`` with every member's message ("...; or ...").
    """
    deep = [
        errors for errors in members.values()
        if any(len(err["loc"]) > len(site) + 1 for err in errors)
    ]  # fmt: skip
    if deep:
        return [
            {**err, "loc": tuple(p for p in err["loc"] if not _is_union_label(p, models))}
            for errors in deep
            for err in errors
        ]
    every = [err for errors in members.values() for err in errors]
    message = "; or ".join(dict.fromkeys(str(err["msg"]) for err in every))
    return [{**every[0], "loc": site, "msg": message}]


def _meaningful_errors(errors: list[dict]) -> list[dict]:
    """pydantic's errors without the noise of a union's other members, and locations without
    the members' labels.

    A value checked against ``float | MeasureConfig`` gets one error per member: a mapping
    with a bad ``u_value`` also reads "measures.walls.float: Input should be a valid number"
    (:func:`_union_member_errors` keeps the member the value's type fits).

    Parameters
    ----------
    errors : list of dict
        ``ValidationError.errors()``.

    Returns
    -------
    list of dict
        The errors to show, in pydantic's order, each with ``loc`` free of union labels.
    """
    models = _config_model_names()
    order: list = []  # errors outside unions, and union locations (tuples) where first seen
    sites: dict[tuple, dict[str, list[dict]]] = {}
    for err in errors:
        loc = tuple(err["loc"])
        at = next((i for i, p in enumerate(loc) if _is_union_label(p, models)), None)
        if at is None:
            order.append(err)
            continue
        if loc[:at] not in sites:
            order.append(loc[:at])
            sites[loc[:at]] = {}
        sites[loc[:at]].setdefault(loc[at], []).append(err)
    return [
        shown
        for item in order
        for shown in (
            _union_member_errors(sites[item], item, models) if isinstance(item, tuple) else [item]
        )
    ]


def _format_validation_error(exc: ValidationError, source: str) -> str:
    lines = [f"invalid retrofit configuration {source}:"]
    for err in _meaningful_errors(exc.errors()):
        where = ".".join(str(p) for p in err["loc"]) or "(top level)"
        value = err.get("input")
        if err["type"] != "missing" and not isinstance(value, dict | list):
            shown = repr(value)
            shown = shown if len(shown) <= 60 else shown[:57] + "..."
            where = f"{where} = {shown}"  # echo the bad value: which one is wrong
        message = str(err["msg"])
        # a validator's own message, without pydantic's "Value error, " in front of it
        message = message.removeprefix("Value error, ").removeprefix("Assertion failed, ")
        lines.append(f"  - {where}: {message}{_hint(err)}")
    return "\n".join(lines)


def _section_fields(loc) -> dict[str, Any]:
    """The fields of the configuration section at ``loc`` (a key path), name -> FieldInfo."""
    model: Any = RetrofitConfig
    for key in loc:
        fields = getattr(model, "model_fields", None)
        if not fields or key not in fields:
            return {}
        annotation = fields[key].annotation
        candidates = [annotation, *getattr(annotation, "__args__", ())]
        model = next((c for c in candidates if hasattr(c, "model_fields")), None)
        if model is None:
            return {}
    return dict(getattr(model, "model_fields", {}))


def _hint(err: dict) -> str:
    """What an unknown key or an out-of-range number probably meant (a close name, the section a
    key belongs to, a percentage where a fraction is asked)."""
    import difflib

    loc = [str(p) for p in err.get("loc", ())]
    if err.get("type") == "extra_forbidden" and loc:
        key, siblings = loc[-1], _section_fields(loc[:-1])
        close = difflib.get_close_matches(key, list(siblings), n=1, cutoff=0.75)
        if close:
            return f"; did you mean {close[0]!r}?"
        owners = [
            name
            for name in siblings
            if key in _section_fields([*loc[:-1], name])
        ]  # fmt: skip
        if owners:
            where = ".".join([*loc[:-1], owners[0]])
            return f"; {key!r} belongs under {where}:"
        return ""
    limit = (err.get("ctx") or {}).get("le", (err.get("ctx") or {}).get("lt"))
    value = err.get("input")
    if (
        err.get("type") in ("less_than_equal", "less_than")
        and isinstance(value, int | float)
        and not isinstance(value, bool)
        and isinstance(limit, int | float)
        # a fraction's limit (1) exceeded, or an efficiency's (a heat pump's COP up to 5) by a
        # percentage; not an air change rate's 3 1/h
        and (
            (limit <= 1 and 1 < value <= 100)
            or (loc and "efficiency" in loc[-1] and limit <= 5 and 10 <= value <= 100)
        )
    ):
        return f"; a percentage? write it as a fraction: {value / 100:g}"
    return ""


def parse_config(
    data: dict[str, Any], *, base_dir: Path | str = ".", source: str = ""
) -> RetrofitConfig:
    """Validate a configuration mapping.

    Parameters
    ----------
    data : dict
        Parsed YAML content.
    base_dir : path
        Folder that relative paths in the configuration refer to.
    source : str
        Name of the file, for error messages.

    Raises
    ------
    ThermocalInputError
        Listing every invalid or missing key with the reason.
    """
    if not isinstance(data, dict):
        raise ThermocalInputError(
            f"configuration {source} must be a YAML mapping, got {type(data)}"
        )
    try:
        return RetrofitConfig.model_validate({**data, "base_dir": Path(base_dir)})
    except ValidationError as exc:
        raise ThermocalInputError(_format_validation_error(exc, source)) from None


def load_config(path: Path | str) -> RetrofitConfig:
    """Read and validate a ``thermocal retrofit`` YAML configuration file.

    Raises
    ------
    ThermocalInputError
        When the file is missing, not YAML, or fails validation (the message lists the keys).
    """
    from thermocal.io.yamlfile import read_yaml

    path = Path(path)
    if not path.exists():
        raise ThermocalInputError(f"configuration file {path} not found")
    data = read_yaml(path, what="configuration file")
    return parse_config(data, base_dir=path.parent, source=str(path))
