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

from pathlib import Path
from typing import Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from thermocal.errors import ThermocalInputError
from thermocal.retrofit.strategies import MEASURE_ORDER, PAPER_MEASURE_U_VALUES

#: Standard measurement names used by the workflow, with their meaning and unit.
MEASUREMENT_COLUMNS: dict[str, str] = {
    "temp_out": "external air temperature Te [C]",
    "flow": "heating water volume flow V_dot",
    "temp_supply": "heating supply water temperature [C]",
    "temp_return": "heating return water temperature [C]",
    "dni": "direct normal irradiance [W/m2] (hourly Wh/m2 is the same number)",
    "dhi": "diffuse horizontal irradiance [W/m2]",
    "temp_in": "internal air temperature Ti [C]",
}

#: Conversion factors of supported flow units to m3/s.
FLOW_UNITS: dict[str, float] = {
    "m3/s": 1.0,
    "m3/h": 1.0 / 3600.0,
    "l/s": 1e-3,
    "l/min": 1e-3 / 60.0,
    "l/h": 1e-3 / 3600.0,
}


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class MeasurementsConfig(_Strict):
    """Where the measurements are and how their columns are named."""

    file: Path
    time_column: str = "time"
    columns: dict[str, str] = Field(
        default_factory=lambda: {name: name for name in MEASUREMENT_COLUMNS},
        description="mapping standard name -> column in the file",
    )
    flow_unit: Literal["m3/s", "m3/h", "l/s", "l/min", "l/h"] = "m3/s"
    timezone: str | float | None = Field(
        None, description="time zone of naive timestamps (name or hours from UTC)"
    )
    step: str = Field("1h", description="resampling step of the calibration data")

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
        return full


class WeatherConfig(_Strict):
    """The typical-year weather file for the annual demand (EPW, TMY3 or CSV)."""

    file: Path
    format: Literal["epw", "tmy3", "csv"] | None = None
    columns: dict[str, str] | None = None


class PeriodsConfig(_Strict):
    """Training and test periods: explicit dates, or lengths from the first measurement."""

    training_start: str | None = None
    training_days: float = Field(21.0, gt=0)
    test_days: float = Field(21.0, ge=0)


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


class UncertaintyConfig(_Strict):
    """Propagation of the parameter uncertainty into demands and savings."""

    draws: int = Field(200, ge=0)
    interval: float = Field(0.90, gt=0, lt=1)
    u_value_rel_std: float = Field(
        0.0,
        ge=0,
        le=0.5,
        description="relative standard deviation of the audit U-values of roof, walls, windows "
        "and floor (0: only the estimation uncertainty, as in paper 000)",
    )
    seed: int = 0


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

    @field_validator("rating_monthly_kWh")
    @classmethod
    def _twelve(cls, value: list[float] | None) -> list[float] | None:
        if value is not None and len(value) != 12:
            raise ValueError(f"needs 12 monthly values, got {len(value)}")
        return value


class DemandConfig(_Strict):
    """Annual demand simulation."""

    indoor_profile: Literal["measured"] | float = Field(
        "measured", description="'measured' (24-h profile of the measured Ti) or a constant [C]"
    )
    profile_period: Literal["all", "training"] = "all"


class RetrofitConfig(_Strict):
    """The whole ``thermocal retrofit`` configuration."""

    building: Path | dict[str, Any]
    measurements: MeasurementsConfig
    weather: WeatherConfig
    periods: PeriodsConfig = Field(default_factory=PeriodsConfig)
    model: ModelConfig = Field(default_factory=ModelConfig)
    measures: dict[str, float] = Field(default_factory=lambda: dict(PAPER_MEASURE_U_VALUES))
    uncertainty: UncertaintyConfig = Field(default_factory=UncertaintyConfig)
    reference: ReferenceConfig = Field(default_factory=ReferenceConfig)
    demand: DemandConfig = Field(default_factory=DemandConfig)
    base_dir: Path = Field(Path("."), description="folder relative paths refer to")

    @field_validator("measures")
    @classmethod
    def _measures(cls, value: dict[str, float]) -> dict[str, float]:
        unknown = sorted(set(value) - set(MEASURE_ORDER))
        if unknown:
            raise ValueError(f"unknown measures {unknown}; allowed: {list(MEASURE_ORDER)}")
        for name, u in value.items():
            if not 0.05 <= u <= 6.0:
                raise ValueError(f"U-value of measure {name!r} is {u} W/(m2 K); expected 0.05 .. 6")
        missing = [m for m in MEASURE_ORDER if m not in value]
        if missing:
            raise ValueError(f"measures {missing} missing: give all four U-values [W/(m2 K)]")
        return {m: value[m] for m in MEASURE_ORDER}

    @model_validator(mode="after")
    def _resolve_paths(self) -> RetrofitConfig:
        base = self.base_dir
        if isinstance(self.building, Path) and not self.building.is_absolute():
            self.building = base / self.building
        if not self.measurements.file.is_absolute():
            self.measurements.file = base / self.measurements.file
        if not self.weather.file.is_absolute():
            self.weather.file = base / self.weather.file
        return self


def _format_validation_error(exc: ValidationError, source: str) -> str:
    lines = [f"invalid retrofit configuration {source}:"]
    for err in exc.errors():
        where = ".".join(str(p) for p in err["loc"]) or "(top level)"
        lines.append(f"  - {where}: {err['msg']}")
    return "\n".join(lines)


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
    path = Path(path)
    if not path.is_file():
        raise ThermocalInputError(f"configuration file {path} not found")
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        raise ThermocalInputError(f"configuration file {path} is not valid YAML: {exc}") from None
    return parse_config(data, base_dir=path.parent, source=str(path))
