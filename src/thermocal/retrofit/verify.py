"""Post-retrofit verification: did the retrofit deliver the predicted saving?

Measurements before and after a retrofit (the same kinds of data and configuration keys as
``thermocal retrofit``) give two independent answers:

- **avoided energy** (IPMVP Option D, calibrated simulation; ASHRAE Guideline 14-2014): the
  fifth-order model calibrated on the pre-retrofit period predicts the heat the house *would
  have needed* in the post-retrofit period, under that period's real weather and measured
  indoor temperatures (:func:`thermocal.retrofit.gate.heat_to_follow_measured`); avoided
  energy = predicted minus measured. The baseline model's Guideline 14 statistics (CV(RMSE),
  NMBE of daily heat over the pre period) and its fractional savings uncertainty (Guideline
  14-2014 Annex B, Reddy and Claridge 2000) give the interval. Normalised to the reference
  year: the measured-to-expected ratio of the post period (the same calibration with the
  measures applied) scales the predicted annual demand of the retrofitted house, per
  posterior draw; this is the measured saving compared with the prediction. The baseline
  once more at the pre period's indoor profile gives the comfort take-back;
- **physical change**: the model calibrated separately on each period (post: the building
  file with the measures' U-values as the prior description); heat loss coefficient and the
  conductances of the retrofitted element groups before and after, with intervals, and the
  annual heating demand of both models over the reference year (a second, independent
  saving, reported beside the first).

The comparison: measured (normalised) saving minus predicted saving in percentage points with
its interval, and a verdict: delivered, rebound (less saving than predicted, or warmer rooms
taking back more than 5 pp), prebound (more) or inconclusive.

References
----------
ASHRAE Guideline 14-2014, Measurement of Energy, Demand, and Water Savings, clause 4.3.2.4
(NMBE, CV(RMSE)) and Annex B (fractional savings uncertainty).
EVO (2012), International Performance Measurement and Verification Protocol (IPMVP), Vol. 1,
Option D (calibrated simulation), avoided energy and normalised savings.
Reddy, T. A., Claridge, D. E. (2000). Uncertainty of "measured" energy savings from
statistical baseline models. HVAC&R Research 6(1), 3-20.
Ljung, L. (1999). System Identification: Theory for the User, 2nd ed., Prentice Hall,
section 13.4 (identification in closed loop).
Forssell, U., Ljung, L. (1999). Closed-loop identification revisited. Automatica 35(7),
1215-1241.
"""

from __future__ import annotations

import dataclasses
import json
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd
from pydantic import Field, ValidationError, ValidationInfo, field_validator

from thermocal.errors import ThermocalInputError
from thermocal.jsonsafe import json_ready as _clean
from thermocal.retrofit.airchange import (  # noqa: F401 - re-exported
    MIN_SLOPE_T,
    daily_energy,
    residual_adjustment,
)
from thermocal.retrofit.calibration import (
    HEAT_BALANCE_RANGE,
    calibrate_to_heat,
    heat_unit_keys,
    heating_setpoint,
)
from thermocal.retrofit.config import (
    MIN_TRAINING_DAYS,
    RetrofitConfig,
    _format_validation_error,
    _Strict,
    date_text,
    parse_config,
)
from thermocal.retrofit.references import Reference
from thermocal.retrofit.verify_periods import (
    BASELINE_DAYS_Z,
    baseline_days_after_retrofit,
    baseline_days_note,
    check_period,
    meter_gap_message,
    missing_heat_message,
    retrofitted_days_before_the_date,
    retrofitted_days_note,
    sensor_change_notes,
    split_periods,
    unmetered_heat_runs,
    weather_extrapolation,
)

#: Shortest pre and post period [days] by default: twice the shortest calibration period of the
#: fifth-order model (7 days separate the heat loss from the capacities; the method uses 21).
DEFAULT_MIN_DAYS = 14.0
#: Empirical factor of the fractional savings uncertainty (Guideline 14-2014 Annex B).
FSU_FACTOR = 1.26
#: Verdict "inconclusive" when the measured saving's interval is wider than this either side [pp].
DEFAULT_INCONCLUSIVE_PP = 10.0
#: Files that identify a verify output folder.
VERIFY_SIGNATURE = ("verify.json", "report.html")
#: How a verification configuration asks for the weather file's site (a building far from its
#: weather; :func:`thermocal.retrofit.workflow.building_at_weather_site`).
VERIFY_SITE_OPT_IN = "weather.site: weather in the verification configuration"

ASHRAE_14 = Reference(
    key="ASHRAE Guideline 14-2014",
    text=(
        "ASHRAE (2014). Guideline 14-2014: Measurement of Energy, Demand, and Water Savings. "
        "Clause 4.3.2.4 (NMBE, CV(RMSE)), Annex B (fractional savings uncertainty)."
    ),
)
IPMVP = Reference(
    key="IPMVP Option D",
    text=(
        "EVO (2012). International Performance Measurement and Verification Protocol, Core "
        "Concepts, Vol. 1: Option D (calibrated simulation), avoided energy and normalised "
        "savings."
    ),
)
REDDY_CLARIDGE_2000 = Reference(
    key="Reddy and Claridge (2000)",
    text=(
        'Reddy, T. A., Claridge, D. E. (2000). Uncertainty of "measured" energy savings from '
        "statistical baseline models. HVAC&R Research 6(1), 3-20."
    ),
)
FORSSELL_LJUNG_1999 = Reference(
    key="Forssell and Ljung (1999)",
    text=(
        "Forssell, U., Ljung, L. (1999). Closed-loop identification revisited. Automatica "
        "35(7), 1215-1241. Ljung, L. (1999). System Identification: Theory for the User, 2nd "
        "ed., Prentice Hall, section 13.4."
    ),
)
SUNIKKA_BLANK_2012 = Reference(
    key="Sunikka-Blank and Galvin (2012)",
    text=(
        "Sunikka-Blank, M., Galvin, R. (2012). Introducing the prebound effect: the gap between "
        "performance and actual energy consumption. Building Research & Information 40(3), "
        "260-273."
    ),
)


# ------------------------------------------------------------------------------------------
# configuration
# ------------------------------------------------------------------------------------------
class PredictionConfig(_Strict):
    """What the measured saving is checked against."""

    results: Path | None = Field(None, description="results.json of thermocal retrofit")
    strategy: str | None = Field(None, description="strategy code in results.json (e.g. 2a)")
    saving_pct: float | None = Field(None, ge=-100, le=100, description="predicted saving [%]")
    saving_pct_interval: tuple[float, float] | None = None
    measures: list[str] | None = Field(
        None, description="measures carried out (names under measures:), with saving_pct"
    )

    @field_validator("saving_pct")
    @classmethod
    def _percent_not_fraction(cls, value):
        if value is not None and 0.0 < abs(value) < 1.0:
            raise ValueError(
                f"saving_pct {value:g} is in percent of the annual heating demand (35 for 35 %), "
                f"not a fraction: write {100 * value:g} if you meant {100 * value:g} %; a "
                "saving below 1 % cannot be told from the weather's and the occupants' spread "
                f"(a verdict is inconclusive within {DEFAULT_INCONCLUSIVE_PP:g} pp by default)"
            )
        return value

    @field_validator("saving_pct_interval")
    @classmethod
    def _interval_around_the_saving(cls, value, info: ValidationInfo):
        if value is None:
            return value
        if "saving_pct" not in info.data:  # saving_pct itself refused: its message says why
            return value
        why = saving_interval_problem(info.data["saving_pct"], value)
        if why is not None:
            raise ValueError(why)
        return value


def saving_interval_problem(
    saving_pct: float | None, interval: tuple[float, float]
) -> str | None:
    """Why ``verify.prediction.saving_pct_interval`` cannot be the prediction's interval.

    Parameters
    ----------
    saving_pct : float or None [%]
        The predicted saving (``verify.prediction.saving_pct``); None: not given.
    interval : tuple of float [%]
        Its interval, lower and upper end, in percent like the saving.

    Returns
    -------
    str or None
        The reason with what to write instead; None when the interval is usable.
    """
    lo, hi = (float(v) for v in interval)
    shown = f"[{lo:g}, {hi:g}]"
    if saving_pct is None:
        return (
            f"{shown} without saving_pct: the interval is that of a predicted saving given "
            "here; give verify.prediction.saving_pct (the predicted saving in %) with it, or "
            "remove saving_pct_interval to check against the fifth-order RC method's own "
            "prediction and interval"
        )
    if saving_pct > 1.0 and all(0.0 <= v <= 1.0 for v in (lo, hi)):
        return (
            f"{shown} is in fractions, saving_pct {saving_pct:g} in percent: write "
            f"[{100 * lo:g}, {100 * hi:g}] if you meant percent"
        )
    if not all(-100.0 <= v <= 100.0 for v in (lo, hi)):
        return (
            f"{shown}: the ends are savings in percent of the annual heating demand, between "
            "-100 and 100"
        )
    if lo == hi:
        return (
            f"{shown} has no width: give the lower and the upper end of the prediction's "
            "interval, or remove saving_pct_interval to take the saving as exact"
        )
    if lo > hi:
        return f"{shown} is reversed: the lower end comes first; write [{hi:g}, {lo:g}]"
    if not lo <= saving_pct <= hi:
        return (
            f"{shown} does not contain saving_pct {saving_pct:g}: the interval must contain "
            "the predicted saving; check both (e.g. the interval of another strategy, or a "
            "saving in another unit)"
        )
    return None


class VerifySection(_Strict):
    """The ``verify:`` section of the configuration."""

    retrofit_date: str
    pre_start: str | None = None
    pre_end: str | None = None
    post_start: str | None = None
    post_end: str | None = None
    min_days: float = Field(DEFAULT_MIN_DAYS, ge=MIN_TRAINING_DAYS, le=3660)
    inconclusive_pp: float = Field(DEFAULT_INCONCLUSIVE_PP, gt=0, le=100)
    calibration: Literal["auto", "heat", "temperature"] = Field(
        "auto",
        description="heat: the model fitted to the metered heat it needs to follow the "
        "indoor temperature (calibrate_to_heat); temperature: the retrofit method's "
        "maximum-likelihood fit of the indoor temperature; auto: heat when a thermostat "
        "holds the indoor temperature (tight_control), else temperature",
    )
    boiler_efficiency_after: float | None = Field(
        None,
        gt=0.3,
        le=1.1,
        description="a fuel meter's boiler efficiency from the retrofit date on (useful heat / "
        "fuel energy [-]; a boiler replaced with the retrofit); before it "
        "measurements.boiler_efficiency",
    )
    prediction: PredictionConfig

    @field_validator(
        "retrofit_date", "pre_start", "pre_end", "post_start", "post_end", mode="before"
    )
    @classmethod
    def _yaml_date(cls, value: Any) -> Any:
        return date_text(value)


@dataclass
class VerifyConfig:
    """A verification: the retrofit configuration of the house plus the ``verify:`` section."""

    retrofit: RetrofitConfig
    verify: VerifySection
    source: str = ""


def parse_verify_config(
    data: dict, *, base_dir: Path | str = ".", source: str = ""
) -> VerifyConfig:
    """Validate a verification configuration mapping.

    Parameters
    ----------
    data : dict
        Parsed YAML: the keys of a retrofit configuration (``building``, ``measurements``,
        ``weather``, ``model``, ``uncertainty``, ``measures``, ``demand``, ...) and ``verify:``.
    base_dir : path
        Folder relative paths refer to.
    source : str
        File name for messages.
    """
    if not isinstance(data, dict):
        raise ThermocalInputError(f"configuration {source} must be a YAML mapping")
    data = dict(data)
    section = data.pop("verify", None)
    if section is None:
        raise ThermocalInputError(
            f"configuration {source}: no 'verify:' section; give at least verify.retrofit_date "
            "and verify.prediction (see docs/verify.md)"
        )
    for key in ("periods", "strategies", "economics"):
        if key in data:
            raise ThermocalInputError(
                f"configuration {source}: {key!r} does not apply to a verification (the periods "
                "are verify.pre_* / verify.post_*, the strategy is verify.prediction)"
            )
    if data.get("in_situ"):
        raise ThermocalInputError(
            f"configuration {source}: 'in_situ' does not apply to a verification: in-situ "
            "U-values inform the prediction (thermocal retrofit), while the verification "
            "measures the saving from the heat before and after the retrofit, when the measured "
            "construction has changed; remove the in_situ section here"
        )
    cfg = parse_config(data, base_dir=base_dir, source=source)
    try:
        sec = VerifySection.model_validate(section)
    except ValidationError as exc:
        msg = _format_validation_error(exc, source).replace(
            "invalid retrofit configuration", "invalid verify section of"
        )
        raise ThermocalInputError(msg.replace("  - ", "  - verify.")) from None
    if sec.boiler_efficiency_after is not None and cfg.measurements.heat_source != "fuel_meter":
        raise ThermocalInputError(
            f"configuration {source}: verify.boiler_efficiency_after applies to a fuel meter "
            "(measurements.heat_source: fuel_meter, now "
            f"{cfg.measurements.heat_source}): a heat meter or the flow and temperatures "
            "measure the useful heat, whatever the boiler; remove it"
        )
    pred = sec.prediction
    if pred.results is None and pred.saving_pct is None and not pred.measures:
        raise ThermocalInputError(
            f"configuration {source}: verify.prediction needs 'results' (results.json of "
            "thermocal retrofit) and 'strategy', or 'measures' (those carried out) with "
            "'saving_pct' (the predicted saving; without it the fifth-order RC method's "
            "prediction from the pre-retrofit calibration)"
        )
    if pred.results is not None:
        beside = [
            key for key in ("saving_pct", "saving_pct_interval", "measures")
            if getattr(pred, key) is not None
        ]  # fmt: skip
        if beside:
            raise ThermocalInputError(
                f"configuration {source}: verify.prediction.results (the strategy's saving and "
                f"interval in results.json) and verify.prediction.{beside[0]} are two "
                "predictions; the second would be ignored: keep one (results with strategy, or "
                "measures with saving_pct)"
            )
        if pred.strategy is None:
            raise ThermocalInputError(
                f"configuration {source}: verify.prediction.results needs "
                "verify.prediction.strategy (the code of the strategy carried out, e.g. 2a)"
            )
        if not pred.results.is_absolute():
            pred.results = Path(base_dir) / pred.results
    elif not pred.measures:
        raise ThermocalInputError(  # (saving_pct given alone)
            f"configuration {source}: verify.prediction.saving_pct needs "
            f"verify.prediction.measures (those carried out, of {list(cfg.measures)})"
        )
    else:
        unknown = [m for m in pred.measures if m not in cfg.measures]
        if unknown:
            raise ThermocalInputError(
                f"configuration {source}: verify.prediction.measures {unknown} are not among "
                f"the configured measures {list(cfg.measures)}"
            )
    return VerifyConfig(retrofit=cfg, verify=sec, source=source)


def load_verify_config(path: Path | str) -> VerifyConfig:
    """Read and validate a ``thermocal verify`` YAML configuration file."""
    from thermocal.io.yamlfile import read_yaml

    path = Path(path)
    if not path.exists():
        raise ThermocalInputError(f"configuration file {path} not found")
    data = read_yaml(path, what="configuration file")
    return parse_verify_config(data, base_dir=path.parent, source=str(path))


# ------------------------------------------------------------------------------------------
# the prediction
# ------------------------------------------------------------------------------------------
@dataclass
class Prediction:
    """The predicted saving the measurement is checked against."""

    measures: dict[str, Any]  # name -> Measure carried out
    saving_pct: float | None  # [%] of the annual heating demand
    p_lo: float | None
    p_hi: float | None
    source: str
    code: str | None = None
    draws: np.ndarray | None = None  # [%] per draw when computed here (paired with ours)
    profile: np.ndarray | None = None  # [C] 24-h indoor profile the prediction assumed
    weather: str | None = None  # name of the prediction's reference-year weather


def _prediction_interior(vcfg: VerifyConfig) -> str | None:
    """The room's inside (``calibration.interior``) of the prediction's results.json, or None
    (no results file, or one :func:`read_prediction` refuses with its reason)."""
    path = vcfg.verify.prediction.results
    if path is None or not path.is_file():
        return None
    try:
        res = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError):
        return None
    calibration = res.get("calibration") if isinstance(res, dict) else None
    interior = calibration.get("interior", "combined") if isinstance(calibration, dict) else None
    return interior if interior in ("combined", "split") else None


def read_prediction(vcfg: VerifyConfig, model) -> Prediction:
    """The prediction of the configuration (results.json + strategy, or given directly).

    A results.json of another building (name or calculated conductances) or an unknown
    strategy code is refused.
    """
    from thermocal.retrofit.model import calculated_hlc
    from thermocal.retrofit.strategies import Measure

    cfg = vcfg.retrofit
    pred = vcfg.verify.prediction
    measures_all = cfg.measure_objects()
    if pred.results is None:
        lo, hi = pred.saving_pct_interval or (None, None)
        return Prediction(
            {m: measures_all[m] for m in pred.measures}, pred.saving_pct, lo, hi,
            source="given in the configuration (verify.prediction.saving_pct)"
            if pred.saving_pct is not None
            else "the fifth-order RC method, calibrated on the pre-retrofit period",
        )  # fmt: skip
    path = pred.results
    if not path.is_file():
        raise ThermocalInputError(f"verify.prediction.results: {path} not found")
    try:
        res = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ThermocalInputError(
            f"verify.prediction.results: {path} is not JSON ({exc}); give the results.json "
            "written by thermocal retrofit"
        ) from None
    if not isinstance(res, dict) or "scenarios" not in res or "calibration" not in res:
        raise ThermocalInputError(
            f"verify.prediction.results: {path} is not a results.json of thermocal retrofit "
            "(no 'scenarios' / 'calibration')"
        )
    from thermocal.retrofit.workflow import load_building

    building = load_building(cfg.building, config_source=vcfg.source)
    if res.get("building") != building.name:
        raise ThermocalInputError(
            f"verify.prediction.results: {path} is the analysis of building "
            f"{res.get('building')!r}, this verification is of {building.name!r}; give the "
            "results.json of this building"
        )
    theirs_interior = res["calibration"].get("interior", "combined")
    if theirs_interior != model.interior:
        raise ThermocalInputError(
            f"verify.prediction.results: {path} was computed with model.interior: "
            f"{theirs_interior}, this verification uses {model.interior}; set model.interior: "
            f"{theirs_interior} in the verification's retrofit configuration (or re-run the "
            "prediction with the same model)"
        )
    theirs = res["calibration"].get("calculated_conductances_W_per_K") or {}
    ours = model.conductances()
    try:
        h_theirs = calculated_hlc(theirs)
    except KeyError:
        h_theirs = None
    h_ours = calculated_hlc(ours)
    if h_theirs is None or abs(h_theirs - h_ours) > 0.01 * h_ours:
        raise ThermocalInputError(
            f"verify.prediction.results: {path} was computed from another building "
            f"description (calculated conductances "
            f"{'unknown' if h_theirs is None else format(h_theirs, '.1f')} W/K vs "
            f"{h_ours:.1f} W/K of {building.name!r} here); use the building file of "
            "that analysis"
        )
    codes = {s["code"]: s for s in res["scenarios"]}
    if pred.strategy not in codes:
        raise ThermocalInputError(
            f"verify.prediction.strategy = {pred.strategy!r} is not a strategy of {path} "
            f"(codes: {', '.join(codes)})"
        )
    s = codes[pred.strategy]
    if not s["measures"]:
        raise ThermocalInputError(
            f"verify.prediction.strategy = {pred.strategy!r} applies no measure; give the code "
            "of the strategy carried out"
        )
    measures = {}
    for name in s["measures"]:
        u = (s.get("u_values") or {}).get(name)
        if name in measures_all:
            m = measures_all[name]
            measures[name] = dataclasses.replace(m, u_value=u) if u is not None else m
        elif u is not None:
            measures[name] = Measure(name, name, u_value=float(u))
        else:
            raise ThermocalInputError(
                f"verify.prediction.strategy {pred.strategy!r}: measure {name!r} of {path} "
                "is not configured here (measures:)"
            )
    demand = res.get("annual_heating_demand_kWh") or {}
    profile = demand.get("indoor_profile_C")
    return Prediction(
        measures, float(s["saving_pct"]), s.get("saving_pct_p05"), s.get("saving_pct_p95"),
        source=f"thermocal retrofit, {path.name}, strategy {pred.strategy}", code=pred.strategy,
        profile=np.asarray(profile, float) if profile and len(profile) == 24 else None,
        weather=(demand.get("weather") or {}).get("name"),
    )  # fmt: skip


# ------------------------------------------------------------------------------------------
# the computation
# ------------------------------------------------------------------------------------------
@dataclass
class Verification:
    """Everything :func:`run_verify` computed."""

    config: VerifyConfig
    building: Any
    pre: tuple[pd.Timestamp, pd.Timestamp]
    post: tuple[pd.Timestamp, pd.Timestamp]
    retrofit_date: pd.Timestamp
    calibration_pre: Any
    calibration_post: Any
    prediction: Prediction
    daily: pd.DataFrame  # daily heat [kWh]: measured, baseline model; column period
    avoided: dict
    physical: dict
    comparison: dict
    timings: dict = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    truth: dict | None = None


def prepare_inputs(cfg: RetrofitConfig, source: str):
    """Building, model, measured model inputs and reference-year inputs of a configuration.

    The same readers and conversions as :func:`thermocal.retrofit.workflow.run_retrofit`.

    Returns
    -------
    building, model, inputs (DataFrame: model inputs [C, W], ``phi_h_measured``, ``phi_int``,
    ``Ti_measured``), year (DataFrame of the reference year's demand inputs), gains (bool),
    quality, notes, weather_meta
    """
    from thermocal.physics.ground import ground_temperature_parameters
    from thermocal.retrofit.calibration import OUTPUT_COLUMN
    from thermocal.retrofit.data import (
        check_irradiance_limits,
        check_temperature_units,
        clock_notes,
        prepare_measurements,
        read_raw_measurements,
        removed_values_notes,
        with_beam_and_diffuse,
    )
    from thermocal.retrofit.demand import DEMAND_INPUTS
    from thermocal.retrofit.gains import (
        check_configured_gains,
        check_metered_electricity,
        internal_gains,
    )
    from thermocal.retrofit.model import build_fifth_order_model
    from thermocal.retrofit.workflow import (
        IRRADIANCE_SPLIT_NOTE,
        _location_tz,
        building_at_weather_site,
        building_name,
        interior_for,
        load_building,
        load_weather_year,
        model_inputs,
    )

    building = load_building(cfg.building, config_source=source)
    site_note = None
    if cfg.weather.site == "weather":  # the default's refusal: the command, before computing
        building, site_note = building_at_weather_site(
            building, cfg, building_source=building_name(cfg), opt_in=VERIFY_SITE_OPT_IN
        )
        if site_note:  # at once; and in verify.json's notes and the report
            logging.getLogger("thermocal.retrofit").warning("%s", site_note)
    mc, ig = cfg.measurements, cfg.internal_gains
    check_configured_gains(ig, float(building.heated_floor_area), building.name)
    metered = ig.source == "electricity"
    raw = read_raw_measurements(
        mc, default_tz=_location_tz(building),
        electricity_unit=ig.electricity_unit if metered else None,
    )  # fmt: skip
    grid, quality = prepare_measurements(
        raw, mc.step, heat_source=mc.heat_source,
        heat_energy=mc.heat_unit not in ("W", "kW"), heat_cumulative=mc.heat_cumulative,
        boiler_efficiency=mc.boiler_efficiency,
        electricity_energy=ig.electricity_unit not in ("W", "kW"),
        electricity_cumulative=ig.electricity_cumulative, columns=mc.columns,
    )  # fmt: skip
    # the clock first: a wrong time zone also puts sunlight where the sun is low
    clock = clock_notes(raw, mc, building.location)
    check_irradiance_limits(grid, mc, building.location, str(mc.file))
    grid = with_beam_and_diffuse(grid, mc, building.location)
    notes = ([site_note] if site_note else []) + list(removed_values_notes(quality, mc.columns))
    if mc.irradiance == "ghi":
        notes.append(IRRADIANCE_SPLIT_NOTE)
    quality = {"quality": quality, "raw": raw}
    step = grid.index[1] - grid.index[0]
    weather, meta = load_weather_year(cfg, step)
    notes += clock
    notes += check_temperature_units(grid, weather, mc, str(mc.file))
    ground = ground_temperature_parameters(weather)
    model = build_fifth_order_model(
        building, solar_to_internal_mass=cfg.model.solar_to_internal_mass,
        bounds=cfg.model.bounds, fixed=cfg.model.fixed,
        # auto: settled in run_verify (the prediction's inside, or the calibration method's)
        interior=interior_for(cfg.model.interior),
    )  # fmt: skip
    inputs = model_inputs(
        grid, building, ground, temp_col="temp_out", solar=cfg.model.solar_gains,
        depth=cfg.model.ground_depth,
    )  # fmt: skip
    check_metered_electricity(
        grid, ig, float(building.heated_floor_area), str(mc.file),
        mc.columns.get("electricity", "electricity"),
    )  # fmt: skip
    gains = internal_gains(grid, ig)
    inputs["phi_h_measured"] = grid["phi_h"].to_numpy(float)
    inputs["phi_int"] = 0.0 if gains is None else gains.to_numpy(float)
    inputs["phi_h"] = inputs["phi_h_measured"] + inputs["phi_int"]
    inputs[OUTPUT_COLUMN] = grid["temp_in"].to_numpy(float)
    year = model_inputs(
        weather, building, ground, temp_col="temp_air_mean", solar=cfg.model.solar_gains,
        depth=cfg.model.ground_depth,
    )[list(DEMAND_INPUTS)]  # fmt: skip
    return building, model, inputs, year, gains is not None, quality, notes, meta


def _calibrate(cfg: RetrofitConfig, model, data: pd.DataFrame, log_interval=None):
    from thermocal.retrofit.calibration import calibrate

    return calibrate(
        model, data, n_starts=cfg.model.n_starts, seed=cfg.model.seed,
        max_correlation=cfg.model.max_correlation,
        correction=cfg.model.correction == "groups" and cfg.uncertainty.u_value_rel_std > 0,
        fixed_noise=cfg.model.fixed_diffusions(), heat_rel_std=cfg.uncertainty.heat_rel_std,
        u_value_rel_std=cfg.uncertainty.u_value_rel_std, log_interval=log_interval,
    )  # fmt: skip


#: Ratio of the mean heating power to the building file's transmission losses accepted in
#: each period (:func:`~thermocal.retrofit.calibration.check_heating_power_magnitude`). The
#: building file describes the house before the retrofit: after it, a deep retrofit (an
#: EnerPHit-like one needs a tenth of the heat) or a mild period needs a small fraction of
#: those losses, so the post period is checked for the upward slips alone (a cumulative
#: reading, kWh read as W). A downward slip of the configuration shows in the pre period; a
#: meter exchanged at the retrofit that reads too little after it shows only as a saving far
#: above the prediction (prebound), one that reads too much in :func:`hlc_rise_warning`.
PERIOD_HEAT_BALANCE_RANGE: dict[str, tuple[float, float]] = {
    "pre": HEAT_BALANCE_RANGE,
    "post": (0.0, HEAT_BALANCE_RANGE[1]),
}


def check_period_data(
    cfg: RetrofitConfig, data: pd.DataFrame, name: str, source: str, transmission: float
) -> None:
    """The calibration's data checks on one period, in the verification's terms.

    Complete inputs and a positive heating power
    (:func:`thermocal.retrofit.calibration.check_training_data`; missing metered heat first,
    with how to mark and leave out a meter's gap,
    :func:`~.verify_periods.missing_heat_message`), and a heating power of the order of the
    building file's transmission losses
    (:func:`~thermocal.retrofit.calibration.check_heating_power_magnitude`: a factor 20
    either way is a unit, not a house; after the retrofit only upwards,
    :data:`PERIOD_HEAT_BALANCE_RANGE`), the checks ``thermocal retrofit`` makes, their
    messages naming the period and its ``verify.`` keys.

    Parameters
    ----------
    cfg : RetrofitConfig
    data : pd.DataFrame
        The period's model inputs with ``phi_h`` [W], ``Te`` and the measured indoor
        temperature [C].
    name : {"pre", "post"}
    source : str
        The measurement file, for the messages.
    transmission : float [W/K]
        The building file's transmission heat transfer coefficient H_T.

    Raises
    ------
    ThermocalInputError
    """
    from thermocal.retrofit.calibration import (
        check_heating_power_magnitude,
        check_training_data,
    )

    mc = cfg.measurements
    period = f"{name}-retrofit period"
    what = f"{source} ({period})"
    keys = f"verify.{name}_start / verify.{name}_end"
    if "phi_h" in data:  # how to mark and leave out a meter's gap (never zeros)
        gap = missing_heat_message(
            data["phi_h"], name, source, cumulative=bool(getattr(mc, "heat_cumulative", False))
        )
        if gap is not None:
            raise ThermocalInputError(gap)
    check_training_data(data, what, heat_source=mc.heat_source, period=period, period_keys=keys)
    check_heating_power_magnitude(
        data, transmission, what, unit_hint=heat_unit_keys(mc), period=period,
        bounds=PERIOD_HEAT_BALANCE_RANGE[name],
    )  # fmt: skip


def with_boiler_after(
    inputs: pd.DataFrame, date: pd.Timestamp, before: float, after: float
) -> pd.DataFrame:
    """A fuel meter's useful heat with the boiler replaced at the retrofit date.

    Parameters
    ----------
    inputs : pd.DataFrame
        Model inputs with ``phi_h_measured`` (fuel power times ``before``) and ``phi_int``
        [W].
    date : pd.Timestamp
        The retrofit date: the new boiler from it on.
    before, after : float [-]
        Boiler efficiency (useful heat / fuel energy) before the date
        (``measurements.boiler_efficiency``) and from it on
        (``verify.boiler_efficiency_after``).

    Returns
    -------
    pd.DataFrame
        A copy with ``phi_h_measured`` and ``phi_h`` (measured plus internal gains) from the
        date on at the new boiler's efficiency.
    """
    out = inputs.copy()
    later = out.index >= date
    out.loc[later, "phi_h_measured"] = out.loc[later, "phi_h_measured"] * (after / before)
    out["phi_h"] = out["phi_h_measured"] + out["phi_int"]
    return out


def fuel_meter_note(mc) -> str:
    """The note of a fuel meter verified without ``verify.boiler_efficiency_after``.

    A fuel meter measures the fuel; the heat is the fuel times the boiler's efficiency. One
    ``measurements.boiler_efficiency`` for both periods credits a boiler replaced with the
    retrofit to the envelope. ``verify.boiler_efficiency_after`` gives the boiler's efficiency
    from the retrofit date on; equal to ``measurements.boiler_efficiency`` it says the boiler
    is the same one, and either way the note is not given.

    Parameters
    ----------
    mc : thermocal.retrofit.config.MeasurementsConfig
        ``measurements:`` of the configuration (a fuel meter).

    Returns
    -------
    str
        The note, naming both ways of answering it.
    """
    eff = float(mc.boiler_efficiency)
    return (
        "a fuel meter measures the fuel, not the heat: the heat is the fuel times "
        f"measurements.boiler_efficiency {eff:g}, before and after the retrofit alike. If the "
        "boiler was replaced with the retrofit, set verify.boiler_efficiency_after to the new "
        "one's: else its saving is counted as the envelope's (a boiler going from 0.80 to "
        "0.95 alone saves 16 % of the fuel); if it is the same boiler, say so with "
        f"verify.boiler_efficiency_after: {eff:g} (this note is then left out)"
    )


#: The heat loss coefficient calibrated before the retrofit this many times the building
#: file's calculated one (or its inverse) is warned about: old houses' descriptions miss by
#: 20-50 %.
DESCRIBED_HLC_RATIO = 1.7
#: A baseline whose daily heat misses the meter's by more than this on average (NMBE [%],
#: Guideline 14 allows 10) is warned about.
UNIT_NMBE_PCT = 25.0
#: The factors a unit slip of the metered heat gives (either way), as the ranges of a ratio
#: "near" them [-], with the slip, per ``measurements.heat_source``. Between
#: :data:`DESCRIBED_HLC_RATIO` and the lowest range the building file's description is the
#: likely cause, elsewhere unmodelled internal gains (:func:`heat_scale_causes`).
UNIT_SLIP_RATIOS: dict[str, tuple[tuple[float, float, float, str], ...]] = {
    "meter": (
        (2.0, 1.9, 2.25, "kWh per half-hourly row read as kW, or the reverse"),
        (3.6, 3.2, 3.8, "MJ read as kWh, or kWh as MJ"),
        (4.0, 3.8, 4.5, "kWh per 15-minute row read as kW, or the reverse"),
        (1000.0, 300.0, 3000.0, "W read as kW or Wh as kWh, or the reverse"),
    ),
    "hydronic": (
        (3.6, 3.2, 4.0, "l/s read as m3/h, or the reverse"),
        (60.0, 45.0, 80.0, "l/min read as l/h, or the reverse"),
        (1000.0, 300.0, 3000.0, "m3/h read as l/h, or the reverse"),
    ),
}


def described_hlc(model) -> float:
    """The building file's calculated heat loss coefficient [W/K]: its conductances plus
    the prior of ``H_est`` (air change, thermal bridges, doors).

    Parameters
    ----------
    model : thermocal.retrofit.model.FifthOrderModel
    """
    from thermocal.retrofit.model import calculated_hlc

    return calculated_hlc(model.conductances()) + float(model.audit_h_est)


def internal_gains_text(cfg) -> str:
    """What ``internal_gains:`` gives, for the warnings that name it.

    Parameters
    ----------
    cfg : thermocal.retrofit.config.InternalGainsConfig

    Returns
    -------
    str
        E.g. ``"not set"``, ``"constant_W 400 W"``, ``"the electricity meter, 3 occupants"``.
    """
    parts = []
    if cfg.source == "constant":
        parts.append(f"constant_W {float(cfg.constant_W):,.0f} W")
    elif cfg.source == "schedule":
        parts.append(f"schedule_W {float(np.mean(cfg.schedule_W)):,.0f} W on average")
    elif cfg.source == "electricity":
        parts.append("the electricity meter")
    if cfg.occupants:
        parts.append(f"{float(cfg.occupants):g} occupants")
    return ", ".join(parts) or "not set"


def unit_slip_near(ratio: float, heat_source: str) -> tuple[float, str] | None:
    """The unit slip whose factor a ratio of the metered heat's scale is near, or None.

    Parameters
    ----------
    ratio : float [-]
        Metered heat over what the house needs (either way round: 0.5 and 2 alike).
    heat_source : str
        ``measurements.heat_source``: the flow's units (hydronic) or a meter's
        (:data:`UNIT_SLIP_RATIOS`).

    Returns
    -------
    tuple of (float, str) or None
        The slip's factor (e.g. 2, 3.6, 1000) and the slip.
    """
    if not (np.isfinite(ratio) and ratio > 0):
        return None
    factor = max(ratio, 1.0 / ratio)
    slips = UNIT_SLIP_RATIOS["hydronic" if heat_source == "hydronic" else "meter"]
    for nominal, low, high, slip in slips:
        if low <= factor <= high:
            return nominal, slip
    return None


def heat_scale_causes(ratio: float, keys: str, gains: str, heat_source: str) -> str:
    """The likely causes of metered heat out of scale with the house, most likely first.

    Unmodelled internal gains first (a shop, a server room, ``internal_gains`` unset), then
    the building file's description, except between :data:`DESCRIBED_HLC_RATIO` and the
    lowest factor of a unit slip, where old houses' descriptions miss; a unit only when the
    ratio is near the factor of a unit slip (:func:`unit_slip_near`), first when it is near
    1000.

    Parameters
    ----------
    ratio : float [-]
        Metered heat over what the house needs or is described to lose (above 1: more heat
        metered; infinite: the house needs none).
    keys : str
        The keys of the heat's unit (:func:`heat_unit_keys`).
    gains : str
        What ``internal_gains`` gives (:func:`internal_gains_text`).
    heat_source : str
        ``measurements.heat_source``.

    Returns
    -------
    str
        Sentences starting "Likely ...".
    """
    slip = unit_slip_near(ratio, heat_source)
    factor = max(ratio, 1.0 / ratio) if ratio > 0 else float("inf")
    shown = f"{factor:,.0f}" if factor >= 100.0 else f"{factor:.3g}"
    unit = (
        f"the factor {shown} is near {slip[0]:,g}, a unit slip ({slip[1]}): check {keys}"
        if slip is not None
        else None
    )
    if slip is not None and slip[0] >= 1000.0:
        return f"Likely a unit: {unit}."
    gains_cause = (
        f"heat the model is not told of: internal gains missing from internal_gains (now "
        f"{gains}; a shop, a server room, more people, a stove)"
        if ratio < 1.0
        else f"heat metered that the rooms do not lose: internal_gains (now {gains}) larger than "
        "the house's, or domestic hot water on the same meter"
        if gains != "not set"
        else "heat metered that the rooms do not lose: domestic hot water, or another dwelling, "
        "on the same meter"
    )
    description = (
        "the building file's description (old houses' areas, U-values and air change miss by "
        "20-50 %)"
    )
    described_band = DESCRIBED_HLC_RATIO <= factor < UNIT_SLIP_RATIOS["meter"][0][1]
    first, second = (description, gains_cause) if described_band else (gains_cause, description)
    text = f"Likely {first}; else {second}."
    return text + (f" Also, {unit}." if unit is not None else "")


def described_hlc_warning(
    calibrated: float, described: float, keys: str, gains: str, heat_source: str
) -> str | None:
    """Warning when the calibrated heat loss coefficient is far from the building file's.

    Parameters
    ----------
    calibrated : float [W/K]
        Calibrated on the pre-retrofit period.
    described : float [W/K]
        The building file's (:func:`described_hlc`).
    keys : str
        The keys of the heat's unit (:func:`heat_unit_keys`).
    gains : str
        What ``internal_gains`` gives (:func:`internal_gains_text`).
    heat_source : str
        ``measurements.heat_source``.

    Returns
    -------
    str or None
        None within :data:`DESCRIBED_HLC_RATIO` either way; else the likely causes
        (:func:`heat_scale_causes`).
    """
    if not (calibrated > 0 and described > 0):
        return None
    ratio = calibrated / described
    if 1.0 / DESCRIBED_HLC_RATIO <= ratio <= DESCRIBED_HLC_RATIO:
        return None
    return (
        f"the heat loss coefficient calibrated before the retrofit, {calibrated:,.0f} W/K, is "
        f"{ratio:.3g} times the building file's calculated {described:,.0f} W/K (its U-values, "
        f"air change and thermal bridges), beyond {DESCRIBED_HLC_RATIO:g} times either way. "
        + heat_scale_causes(ratio, keys, gains, heat_source)
    )


def hlc_rise_warning(pre: dict, post: dict, keys: str) -> str | None:
    """Warning when the heat loss coefficient after the retrofit is clearly above the one
    before (their intervals apart): the measures can only lower it.

    Parameters
    ----------
    pre, post : dict
        ``value``, ``lo``, ``hi`` [W/K] of each period's calibration.
    keys : str
        The keys of the heat's unit (:func:`heat_unit_keys`).

    Returns
    -------
    str or None
    """
    if not post["lo"] > pre["hi"]:
        return None
    return (
        f"the heat loss coefficient after the retrofit, {post['value']:,.0f} W/K "
        f"({post['lo']:,.0f} to {post['hi']:,.0f}), is above the one before, "
        f"{pre['value']:,.0f} W/K ({pre['lo']:,.0f} to {pre['hi']:,.0f}), although the measures "
        "can only lower it: check that the heat was metered the same way in both periods (a "
        f"meter exchanged at the retrofit may read in another unit; {keys}), and the "
        "retrofit date"
    )


def baseline_bias_warning(
    nmbe_pct: float, keys: str, gains: str, heat_source: str
) -> str | None:
    """Warning when the baseline's daily heat misses the metered heat by far on average.

    Parameters
    ----------
    nmbe_pct : float [%]
        The baseline's NMBE over the pre-retrofit period (measured minus model over the
        measured; negative: the model needs more heat than metered).
    keys : str
        The keys of the heat's unit (:func:`heat_unit_keys`).
    gains : str
        What ``internal_gains`` gives (:func:`internal_gains_text`).
    heat_source : str
        ``measurements.heat_source``.

    Returns
    -------
    str or None
        None within :data:`UNIT_NMBE_PCT`; else the likely causes
        (:func:`heat_scale_causes`, with metered over model heat ``1 / (1 - NMBE)``).
    """
    if not abs(nmbe_pct) > UNIT_NMBE_PCT:
        return None
    model_share = 1.0 - nmbe_pct / 100.0  # the model's heat over the metered
    ratio = 1.0 / model_share if model_share > 0 else float("inf")
    need = (
        f"{abs(nmbe_pct):.0f} % {'more' if nmbe_pct < 0 else 'less'} heat than was metered"
        if model_share > 0
        else "no heat, where heat was metered,"
    )
    return (
        f"the baseline model needs {need} over the pre-retrofit period (NMBE {nmbe_pct:+.0f} "
        "%; Guideline 14 allows 10 %) to hold the measured indoor temperatures. "
        + heat_scale_causes(ratio, keys, gains, heat_source)
    )


def scenario_draws(cfg: RetrofitConfig, model, cal, strategies, measures: dict):
    """Parameter draws and per-draw envelopes of strategies, as the retrofit workflow makes
    them (posterior of the group corrections, or the published topology's draws)."""
    from thermocal.retrofit.calibration import draw_parameters
    from thermocal.retrofit.workflow import corrected_scenarios, scenario_envelopes

    n, seed = cfg.uncertainty.draws, cfg.uncertainty.seed
    if cal.correction is not None:
        return corrected_scenarios(model, cal, strategies, measures, n, seed=seed)
    draws = draw_parameters(cal, model, n, seed=seed)
    envelopes = scenario_envelopes(
        model, strategies, measures, draws, cfg.uncertainty.u_value_rel_std, seed=seed
    )
    return draws, envelopes


#: Envelope groups of the measures' components (:data:`thermocal.retrofit.correction.GROUPS`).
def _group_of(component: str) -> str | None:
    from thermocal.retrofit.correction import GROUPS

    for g, comps in GROUPS.items():
        if component in comps:
            return g
    return "k_floor" if component == "ground_floor" else None


def group_conductances(model, envelope) -> dict[str, float]:
    """Steady-state conductance [W/K] of each envelope group (roof + walls, windows, floor)."""
    from thermocal.retrofit.model import _series

    h = model.conductances(envelope)
    return {
        "k_env": _series(h["H_env_in"], h["H_env_out"]) if h["H_env_in"] > 0 else 0.0,
        "k_win": h["H_win"],
        "k_floor": _series(h["H_gf_in"], h["H_gf_gr"] + h["H_gf_e"]),
    }


def _quantiles(x: np.ndarray, interval: float) -> tuple[float, float]:
    lo = 0.5 * (1.0 - interval)
    x = np.asarray(x, float)
    return float(np.quantile(x, lo)), float(np.quantile(x, 1.0 - lo))


def _envelope_of(draw_env, d: int):
    return draw_env[d] if isinstance(draw_env, list | tuple) else draw_env


def fractional_savings_uncertainty(
    cv_rmse_pct: float, n: int, m: int, rho: float, fraction: float, interval: float, p: int = 1
) -> dict[str, float]:
    """Fractional savings uncertainty of ASHRAE Guideline 14-2014 Annex B.

    ``FSU = t 1.26 CV sqrt((n / n') (1 + 2/n) / m) / F`` (Reddy and Claridge 2000), with the
    baseline model's CV(RMSE) ``CV`` [-], ``n`` baseline and ``m`` reporting-period points,
    the effective number of baseline points ``n' = n (1 - rho) / (1 + rho)`` for lag-1
    autocorrelated residuals, the savings fraction ``F`` and Student's ``t`` at the
    two-sided confidence level with ``n - p`` degrees of freedom.

    Parameters
    ----------
    cv_rmse_pct : float [%]
    n, m : int [-]
    rho : float [-], lag-1 autocorrelation of the baseline residuals (negative: 0)
    fraction : float [-], savings fraction F
    interval : float [-], confidence level (e.g. 0.9)
    p : int, parameters of the baseline model

    Returns
    -------
    dict: ``half_width`` [-] of F (absolute), ``fsu`` [-] relative to F, ``t``, ``n_eff``.
    """
    from scipy.stats import t as student

    rho = max(float(rho), 0.0) if np.isfinite(rho) else 0.0
    n_eff = n * (1.0 - rho) / (1.0 + rho)
    t = float(student.ppf(0.5 + 0.5 * interval, max(n - p, 1)))
    # residuals correlated throughout (rho 1) leave no independent point: no interval
    inflation = n / n_eff if n_eff > 0 else float("inf")
    half = t * FSU_FACTOR * cv_rmse_pct / 100.0 * np.sqrt(inflation * (1.0 + 2.0 / n) / m)
    return {
        "half_width": float(half),
        "fsu": float(half / fraction) if fraction else float("inf"),
        "t": t,
        "n_eff": float(n_eff),
    }


def adjustment_at(adj: dict, dt_post: np.ndarray, dt_pre_mean: float) -> np.ndarray:
    """The baseline period's residual adjustment evaluated at other indoor-outdoor differences.

    :func:`~thermocal.retrofit.airchange.residual_adjustment` fits the baseline period's daily
    residuals as ``c + b (dT - mean dT_pre)``; a baseline that follows other indoor
    temperatures over the reporting days (the comfort take-back's, at the pre period's indoor
    profile) takes the same line at its own ``dT``, not the reporting period's adjustment.

    Parameters
    ----------
    adj : dict
        :func:`~thermocal.retrofit.airchange.residual_adjustment`'s result.
    dt_post : ndarray [K]
        Daily mean indoor minus outdoor temperature of the reporting days, at the indoor
        temperatures the baseline follows.
    dt_pre_mean : float [K]
        Mean daily indoor-outdoor difference of the baseline period.

    Returns
    -------
    ndarray [kWh/day]
        The adjustment per reporting day; zeros when the adjustment was not applied.
    """
    dt_post = np.asarray(dt_post, float)
    if not adj["applied"]:
        return np.zeros(len(dt_post))
    return adj["intercept"] + adj["slope"] * (dt_post - dt_pre_mean)


def measured_ratio_draws(
    measured: float, baseline: float, half_width: float, t: float, n: int, rng
) -> np.ndarray:
    """Draws of the measured-to-baseline ratio ``r = E_measured / E_baseline`` of a period.

    The Guideline 14 half-width ``FSU x F`` (:func:`fractional_savings_uncertainty`) is the
    baseline sum's relative error at Student's ``t`` (Reddy and Claridge 2000: the savings'
    error is the baseline's, ``Delta E_save = Delta E_baseline``, and ``FSU x F = Delta
    E_save / E_baseline``); the metered heat is exact. So ``half_width / t`` is the relative
    standard uncertainty of ``r``, drawn log-normally, and ``1 - r`` has an absolute standard
    uncertainty of ``r half_width / t``: narrower by ``1 - F`` than the Guideline's
    ``F (1 +/- FSU)``, which keeps the baseline in ``F``'s denominator fixed.

    Parameters
    ----------
    measured, baseline : float [kWh]
        Metered and (adjusted) baseline heat of the post period.
    half_width : float [-]
        ``FSU x F`` at the interval's level.
    t : float [-]
        Student's t of that level.
    n : int
        Number of draws; the first is the point estimate.
    rng : numpy.random.Generator

    Returns
    -------
    ndarray [-], ``(n,)``
    """
    r = measured / baseline
    draws = r * np.exp(rng.normal(0.0, half_width / t, n))
    draws[0] = r
    return draws


def check_baseline_heat(
    baseline: float,
    baseline_old_comfort: float,
    measured: float,
    post: tuple[pd.Timestamp, pd.Timestamp],
    source: str,
    gains: str,
    *,
    adjustment: tuple[float, float] = (0.0, 0.0),
    indoor: tuple[float, float] | None = None,
) -> None:
    """Refuse a post period over which a baseline needs no heat, naming which and why.

    The saving is measured against the baseline's heat (the fraction saved, the normalised
    saving), the comfort take-back against the baseline at the pre period's indoor
    temperatures: a baseline that needs none, while heat was metered, leaves nothing to
    measure against (it divided by zero). Internal gains that cover the model's losses
    (``internal_gains`` in kW, or the heating's power) or a post period out of the heating
    season are the causes for the baseline; for the comfort baseline alone, a pre period held
    much cooler (an undersized heater, rooms left cold) whose linear residual adjustment
    (:func:`adjustment_at`) outweighs the little heat the model needs there.

    Parameters
    ----------
    baseline, baseline_old_comfort : float [kWh]
        The baseline model's heat over the post period, at the measured indoor temperatures
        and at the pre period's (both adjusted).
    measured : float [kWh]
        The metered heat of the post period.
    post : tuple of pd.Timestamp
        The post-retrofit period.
    source : str
        The measurement file, for the message.
    gains : str
        What ``internal_gains`` gives (:func:`internal_gains_text`).
    adjustment : tuple of float [kWh]
        The residual adjustment summed over the post period, of the baseline and of the
        comfort baseline (included in the two heats).
    indoor : tuple of float [C], optional
        Mean indoor temperature the comfort baseline and the baseline follow over the post
        period.

    Raises
    ------
    ThermocalInputError
    """
    if baseline > 0 and baseline_old_comfort > 0:
        return
    where = f"over the post-retrofit period ({post[0]} - {post[1]}), where {measured:,.0f} kWh "
    if baseline <= 0:
        raise ThermocalInputError(
            f"{source}: the baseline model (calibrated on the pre-retrofit period) needs "
            f"{max(baseline, 0.0):,.0f} kWh of heat {where}were metered ({adjustment[0]:+,.0f} "
            "kWh of it the adjustment for the weather of the post period): there is no heat to "
            "measure the saving against. Check internal_gains (now "
            f"{gains}: gains that cover the house's losses in the model, in W and without the "
            "heating), then that the post period lies in the heating season (verify.post_start "
            "/ verify.post_end)"
        )
    temps = (
        f" at {indoor[0]:.1f} C instead of the {indoor[1]:.1f} C held after the retrofit"
        if indoor is not None
        else ""
    )
    raise ThermocalInputError(
        f"{source}: the comfort take-back's baseline (the baseline model following the pre "
        f"period's daily indoor profile{temps}) needs {baseline_old_comfort:,.0f} kWh {where}"
        f"were metered, {adjustment[1]:+,.0f} kWh of it the residual adjustment of the "
        "baseline period (linear in the indoor-outdoor difference): the model's heat at the "
        "old indoor temperatures is too small to carry it, so the take-back cannot be measured "
        f"(the baseline at the measured indoor temperatures needs {baseline:,.0f} kWh). A pre "
        "period held much cooler than the post period (an undersized heater, rooms left cold) "
        "does this: check the pre period's indoor temperatures (temp_in) and the heating's "
        "power, or move verify.pre_start / verify.pre_end to days the heating held its set point"
    )


def run_verify(vcfg: VerifyConfig, *, progress=None, truth: dict | None = None) -> Verification:
    """Run the verification: both calibrations, avoided energy, physical change, comparison.

    Parameters
    ----------
    vcfg : VerifyConfig
    progress : callable(str), optional
    truth : dict, optional
        Known answers (the demo), copied into the results for the comparison.
    """
    from thermocal.retrofit.calibration import OUTPUT_COLUMN
    from thermocal.retrofit.data import log_interval, values_in_file_units
    from thermocal.retrofit.demand import DEMAND_INPUTS, simulate_demand
    from thermocal.retrofit.gate import (
        ashrae14_statistics,
        follow_inputs,
        heat_to_follow,
        heat_to_follow_measured,
    )
    from thermocal.retrofit.metrics import daily_profile
    from thermocal.retrofit.strategies import Strategy
    from thermocal.retrofit.workflow import calibration_method, interior_for

    def say(msg: str) -> None:
        if progress is not None:
            progress(msg)

    cfg, sec = vcfg.retrofit, vcfg.verify
    interval = cfg.uncertainty.interval
    source = str(cfg.measurements.file)
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    say("reading building, measurements and weather")
    building, model, inputs, year, has_gains, quality, notes, meta = prepare_inputs(
        cfg, vcfg.source
    )
    mc = cfg.measurements
    pre, post, date, period_notes = split_periods(
        inputs.index, sec, source, inputs["phi_h_measured"]
    )
    notes += period_notes
    in_file_units = values_in_file_units(quality["raw"], mc.fuel_kWh_per_unit)
    notes += sensor_change_notes(in_file_units, pre, post, mc.columns, source)
    if mc.heat_source == "fuel_meter":
        if sec.boiler_efficiency_after is None:
            notes.append(fuel_meter_note(mc))
        else:
            inputs = with_boiler_after(
                inputs, date, float(mc.boiler_efficiency), float(sec.boiler_efficiency_after)
            )
    sel_pre = (inputs.index >= pre[0]) & (inputs.index < pre[1])
    sel_post = (inputs.index >= post[0]) & (inputs.index < post[1])
    for name, sel in (("pre", sel_pre), ("post", sel_post)):
        check_period(inputs.loc[sel], name, sec.min_days, source)
        check_period_data(
            cfg, inputs.loc[sel], name, source,
            float(building.transmission_heat_transfer_coefficient),
        )  # fmt: skip
    # the fit the retrofit analysis would choose on the pre period (one rule for both)
    chosen = calibration_method(sec.calibration, inputs.loc[sel_pre])
    control, method = chosen["tight_control"], chosen["method"]
    if cfg.model.interior == "auto":
        # the inside the prediction was computed with, else the calibration method's
        own = interior_for("auto", method)
        theirs = _prediction_interior(vcfg)
        if theirs is not None and theirs != own:
            notes.append(
                f"the prediction was computed with the {theirs} room inside; the verification "
                f"takes it (model.interior: auto), although its own {method} fit would take the "
                f"{own} one"
            )
        model = dataclasses.replace(model, interior=theirs or own)
    prediction = read_prediction(vcfg, model)
    measures = prediction.measures
    from thermocal.retrofit.model import check_measures

    check_measures(model.envelope, measures, building.name)
    timings["inputs"] = time.perf_counter() - t0

    # what the heating held: the set point the models follow (not free-floating excursions)
    setpoint_all = heating_setpoint(inputs[OUTPUT_COLUMN], inputs["phi_h_measured"], (pre, post))
    model_post = dataclasses.replace(model, envelope=model.apply_measures(list(measures.values())))
    for name, mdl, sel in (("pre", model, sel_pre), ("post", model_post, sel_post)):
        say(f"calibrating the fifth-order model on the {name}-retrofit period")
        t1 = time.perf_counter()
        if method == "heat":
            cal = calibrate_to_heat(mdl, inputs.loc[sel], setpoint_all[sel], gains=has_gains)
        else:
            cal = _calibrate(cfg, mdl, inputs.loc[sel], log_interval(quality["raw"]))
        if name == "pre":
            cal_pre = cal
        else:
            cal_post = cal
        timings[f"calibration_{name}"] = time.perf_counter() - t1

    # ---------------------------------------------------------------- avoided energy
    say("avoided energy: the baseline model over the post-retrofit period")
    t2 = time.perf_counter()
    span = (inputs.index >= pre[0]) & (inputs.index < post[1])
    frame = inputs.loc[span]
    setpoint = setpoint_all[span]
    q_base = heat_to_follow_measured(
        model, cal_pre.estimates_si, cal_pre.envelope, cal_pre.x0, frame[list(DEMAND_INPUTS)],
        setpoint, frame["phi_int"] if has_gains else None,
    )  # fmt: skip
    # the pre-retrofit calibration with the measures applied (the method's prediction of the
    # retrofitted house) over the same span: its post-period heat is what the prediction
    # expected; the measured-to-expected ratio carries the measurement to the reference year
    env_ret = model.apply_measures(list(measures.values()), cal_pre.envelope)
    q_ret = heat_to_follow_measured(
        model, cal_pre.estimates_si, env_ret, cal_pre.x0, frame[list(DEMAND_INPUTS)],
        setpoint, frame["phi_int"] if has_gains else None,
    )  # fmt: skip
    # comfort take-back: the baseline following the pre period's daily indoor profile instead
    # of the measured post-period temperatures (what the house would have used at the old
    # comfort); the difference is the heat the rooms' temperature change costs
    ti_old = pd.Series(
        daily_profile(setpoint[frame.index < pre[1]])[np.asarray(frame.index.hour)],
        index=frame.index,
    ).where(frame.index >= post[0], setpoint)
    q_base_old = heat_to_follow_measured(
        model, cal_pre.estimates_si, cal_pre.envelope, cal_pre.x0, frame[list(DEMAND_INPUTS)],
        ti_old, frame["phi_int"] if has_gains else None,
    )  # fmt: skip
    # a meter's gap exported as zeros while the rooms were held warm: not heat saved
    for name, (a, b) in (("pre", pre), ("post", post)):
        in_period = (frame.index >= a) & (frame.index < b)
        runs = unmetered_heat_runs(
            frame.loc[in_period, "phi_h_measured"], q_base[in_period],
            frame.loc[in_period, OUTPUT_COLUMN],
        )  # fmt: skip
        if runs:
            raise ThermocalInputError(meter_gap_message(runs, name, source))
    daily = daily_energy(
        pd.DataFrame({"measured": frame["phi_h_measured"], "baseline": q_base, "expected": q_ret,
                      "baseline_old_comfort": q_base_old})
    )  # fmt: skip
    day_index = daily.index
    daily["period"] = np.where(
        (day_index >= pre[0].normalize()) & (day_index + pd.Timedelta(days=1) <= pre[1]),
        "pre",
        np.where((day_index >= post[0]) & (day_index < post[1]), "post", "between"),
    )
    d_pre = daily[daily["period"] == "pre"]
    d_post = daily[daily["period"] == "post"]
    stats = ashrae14_statistics(d_pre["baseline"], d_pre["measured"], p=1)
    resid = (d_pre["measured"] - d_pre["baseline"]).to_numpy(float)
    rho = float(np.corrcoef(resid[:-1], resid[1:])[0, 1]) if len(resid) > 2 else 0.0
    # the model's linearisation of the air change at the baseline period's conditions,
    # corrected for the reporting period's (residual_adjustment): the same absolute heat for
    # the baseline and the expected (retrofitted) model, the air change is not retrofitted
    dt_day = (setpoint - frame["Te"]).groupby(frame.index.normalize()).mean()
    adj = residual_adjustment(
        resid, dt_day.reindex(d_pre.index).to_numpy(float),
        dt_day.reindex(d_post.index).to_numpy(float), rho,
    )  # fmt: skip
    adj_sum = float(np.sum(adj["per_day"]))
    # the model's own ratio of retrofitted to baseline heat over the post period (unadjusted)
    e_base_model = float(d_post["baseline"].sum())
    e_ret_model = float(d_post["expected"].sum())
    # the comfort baseline's own indoor-outdoor difference: the adjustment is linear in it, and
    # the main baseline's (at the post period's warmer or cooler rooms) would be applied to a
    # house held at other temperatures (a pre period at 17 C, a post period at 20 C: -50 kWh)
    dt_old_day = (ti_old - frame["Te"]).groupby(frame.index.normalize()).mean()
    adj_old = adjustment_at(
        adj, dt_old_day.reindex(d_post.index).to_numpy(float),
        float(dt_day.reindex(d_pre.index).mean()),
    )  # fmt: skip
    for col, per_day in (("baseline", adj["per_day"]), ("baseline_old_comfort", adj_old)):
        daily.loc[d_post.index, col] = d_post[col] + per_day
        daily.loc[d_pre.index, col] = d_pre[col] + (resid - adj["residual"])
    # what the prediction expected the meter to show: the adjusted baseline times that ratio
    scale = (e_base_model + adj_sum) / e_base_model if e_base_model > 0 else 1.0
    daily.loc[d_post.index, "expected"] = d_post["expected"] * scale
    d_pre = daily[daily["period"] == "pre"]
    d_post = daily[daily["period"] == "post"]
    n_par = 3 if adj["applied"] else 1
    stats_adj = ashrae14_statistics(d_pre["baseline"], d_pre["measured"], p=n_par)
    rho_adj = (
        float(np.corrcoef(adj["residual"][:-1], adj["residual"][1:])[0, 1])
        if len(resid) > 2 else 0.0
    )  # fmt: skip
    # days of the old house after the stated retrofit date: a step back to the baseline
    late = baseline_days_after_retrofit(
        d_post["measured"].to_numpy(float), d_post["baseline"].to_numpy(float), rho_adj
    )
    late_note = baseline_days_note(late, d_post.index)
    if late_note is not None:
        notes.append(late_note)
    # days of the new house before the stated retrofit date: a step down at the baseline's end
    early = retrofitted_days_before_the_date(
        d_pre["measured"].to_numpy(float), d_pre["baseline"].to_numpy(float), rho_adj
    )
    early_note = retrofitted_days_note(early, d_pre.index)
    if early_note is not None:
        notes.append(early_note)
    e_base = float(d_post["baseline"].sum())
    e_meas = float(d_post["measured"].sum())
    e_save = e_base - e_meas
    e_base_old = float(d_post["baseline_old_comfort"].sum())
    te_day = frame["Te"].groupby(frame.index.normalize()).mean()
    extrapolated = weather_extrapolation(
        te_day.reindex(d_pre.index).to_numpy(float), te_day.reindex(d_post.index).to_numpy(float),
        dt_day.reindex(d_pre.index).to_numpy(float), dt_day.reindex(d_post.index).to_numpy(float),
        adj_sum, e_base, bool(adj["applied"]),
    )  # fmt: skip
    check_baseline_heat(
        e_base, e_base_old, e_meas, post, source, internal_gains_text(cfg.internal_gains),
        adjustment=(adj_sum, float(np.sum(adj_old))),
        indoor=(float(ti_old[frame.index >= post[0]].mean()),
                float(setpoint[frame.index >= post[0]].mean())),
    )  # fmt: skip
    frac = e_save / e_base if e_base > 0 else float("nan")

    def _fsu(level):
        f = fractional_savings_uncertainty(
            stats_adj["cv_rmse_pct"], len(d_pre), len(d_post), rho_adj, frac, level, p=n_par
        )
        # plus the extrapolation of the adjustment's slope to the reporting period
        slope_part = f["t"] * adj["sum_se"] / e_base if e_base > 0 else 0.0
        f["half_width"] = float(np.hypot(f["half_width"], slope_part))
        f["fsu"] = f["half_width"] / frac if frac else float("inf")
        return f

    fsu, fsu68 = _fsu(interval), _fsu(0.68)
    crit = cfg.validation
    baseline_ok = bool(
        abs(stats["nmbe_pct"]) <= crit.max_abs_nmbe_pct
        and stats["cv_rmse_pct"] <= crit.max_cv_rmse_pct
    )

    # ---------------------------------------------------------------- reference year
    say("normalising to the reference year")
    profile_mode = cfg.demand.indoor_profile
    if profile_mode == "measured":  # the thermostat's profile (heating_setpoint)
        prof_pre = daily_profile(setpoint[(frame.index >= pre[0]) & (frame.index < pre[1])])
        prof_post = daily_profile(setpoint[(frame.index >= post[0]) & (frame.index < post[1])])
    else:
        prof_pre = prof_post = np.full(24, float(profile_mode))
    if prediction.profile is not None:  # measured and predicted at the same indoor profile
        prof_pre = prediction.profile
        profile_mode = "the prediction's"
    if prediction.weather is not None and prediction.weather != meta.get("name"):
        notes.append(
            f"the prediction used the reference weather {prediction.weather!r}, this "
            f"verification {meta.get('name')!r}: the savings are normalised to different years"
        )
    codes = ("0", prediction.code or "measures")
    strategies = [Strategy(codes[0], ()), Strategy(codes[1], tuple(measures))]
    draws_pre, env_pre = scenario_draws(cfg, model, cal_pre, strategies, measures)
    draws_post, env_post = scenario_draws(cfg, model_post, cal_post, strategies[:1], {})
    year_gains = None
    if has_gains:
        from thermocal.retrofit.gains import gains_day_profile

        day = gains_day_profile(inputs.loc[sel_pre, "phi_int"], cfg.internal_gains)
        year_gains = day[np.asarray(year.index.hour)]
    a_pre = simulate_demand(model, draws_pre, env_pre, year, prof_pre, gains=year_gains)
    a_pre = a_pre.annual_kwh()  # (2, D+1): as it was, with the measures (model prediction)
    a_post = simulate_demand(model_post, draws_post, env_post, year, prof_pre, gains=year_gains)
    a_post = a_post.annual_kwh()[0]
    if profile_mode == "measured":
        a_post_use = simulate_demand(
            model_post, draws_post, env_post, year, prof_post, gains=year_gains
        ).annual_kwh()[0]
    else:
        a_post_use = a_post
    s_phys = 100.0 * (1.0 - a_post / a_pre[0])
    # avoided energy normalised to the reference year: the measured fraction of the baseline
    # (measured over adjusted baseline heat of the post period) carried to the reference year
    # by the calibrated model's own weather dependence of that fraction, the ratio of its
    # retrofitted to baseline demand over the year divided by the same ratio over the post
    # period. The model's prediction of the retrofit's size cancels; the measurement carries
    # the baseline's Guideline 14 uncertainty
    e_exp = float(d_post["expected"].sum())
    ratio = e_meas / e_exp if e_exp > 0 else float("nan")
    # per draw: each parameter set's own ratio over the post period and over the year
    from thermocal.retrofit.model import ESTIMATED_PARAMETERS

    post_rows = frame.index >= post[0]
    post_days = frame.index.normalize().isin(d_post.index) & post_rows
    post_ratio_d = np.empty(a_pre.shape[1])
    follow = follow_inputs(
        frame[list(DEMAND_INPUTS)], setpoint, frame["phi_int"] if has_gains else None
    )
    for d in range(a_pre.shape[1]):
        sums = []
        for k in (0, 1):
            q = heat_to_follow(
                model, {n: float(draws_pre[n][d]) for n in ESTIMATED_PARAMETERS},
                _envelope_of(env_pre[k], d), cal_pre.x0, follow,
            )  # fmt: skip
            sums.append(float(np.nansum(q[post_days])))  # as a Series' sum
        post_ratio_d[d] = sums[1] / sums[0] if sums[0] > 0 else float("nan")
    post_ratio_d[0] = e_ret_model / e_base_model if e_base_model > 0 else float("nan")
    rng = np.random.default_rng(cfg.uncertainty.seed + 2161)
    r_d = measured_ratio_draws(e_meas, e_base, fsu["half_width"], fsu["t"], a_pre.shape[1], rng)
    s_avoided_year = 100.0 * (1.0 - r_d * (a_pre[1] / a_pre[0]) / post_ratio_d)
    s_norm = 100.0 * (1.0 - a_post_use / a_pre[0])
    s_model = 100.0 * (1.0 - a_pre[1] / a_pre[0])
    timings["avoided_and_normalised"] = time.perf_counter() - t2

    avoided = {
        "calibration": method,
        "interior": model.interior,
        "indoor_control": control,
        "method": "IPMVP Option D: baseline model (calibrated on the pre period) follows the "
        "indoor temperature the heating held under the post period's weather",
        "baseline_kWh": e_base,
        "measured_kWh": e_meas,
        "avoided_kWh": e_save,
        "saving_pct": 100.0 * frac,
        "saving_pct_lo": 100.0 * (frac - fsu["half_width"]),
        "saving_pct_hi": 100.0 * (frac + fsu["half_width"]),
        "baseline_at_pre_comfort_kWh": e_base_old,
        "saving_with_take_back_pct": 100.0 * (1.0 - e_meas / e_base_old),
        "take_back_pp": 100.0 * frac - 100.0 * (1.0 - e_meas / e_base_old),
        "mean_indoor_C": {"pre": float(inputs.loc[sel_pre, OUTPUT_COLUMN].mean()),
                          "post": float(inputs.loc[sel_post, OUTPUT_COLUMN].mean())},
        "expected_kWh": e_exp,
        "measured_to_expected_ratio": ratio,
        "normalised_saving_pct": {
            "value": float(s_avoided_year[0]),
            **dict(zip(("lo", "hi"), _quantiles(s_avoided_year[1:], interval), strict=True)),
        },
        "normalised_avoided_kWh": float(a_pre[0, 0] * s_avoided_year[0] / 100.0),
        "normalised_note": "reference year: 1 - (measured / adjusted baseline heat of the "
        "post period) x (the model's retrofitted / baseline annual demand) / (the same "
        "model's retrofitted / baseline heat over the post period)",
        "days_pre": len(d_pre),
        "days_post": len(d_post),
        "baseline_nmbe_pct": stats["nmbe_pct"],
        "baseline_cv_rmse_pct": stats["cv_rmse_pct"],
        "baseline_meets_criteria": baseline_ok,
        "criteria": {"max_abs_nmbe_pct": crit.max_abs_nmbe_pct,
                     "max_cv_rmse_pct": crit.max_cv_rmse_pct, "resolution": "daily"},
        "residual_lag1_autocorrelation": rho,
        "baseline_days_after_retrofit": {
            **late, "warning": late_note,
            "method": "change point of the reporting period's daily heat: measured = "
            "baseline on the first days, a fitted fraction of it on the rest (least squares); "
            f"reported from 2 days at {BASELINE_DAYS_Z:g} standard errors (lag-1 "
            "autocorrelation of the baseline's daily residuals allowed for)",
        },
        "retrofitted_days_before_the_date": {
            **early, "warning": early_note,
            "method": "change point of the baseline period's daily heat: a fitted fraction of "
            "the baseline model's on the last days, the model's before (least squares); "
            f"reported from 2 days at {BASELINE_DAYS_Z:g} standard errors",
        },
        "adjustment": {
            "method": "daily residuals of the baseline period (measured minus model) regressed "
            "on the daily mean indoor-outdoor difference, applied to the reporting days",
            "applied": adj["applied"],
            "intercept_kWh_per_day": adj["intercept"],
            "slope_kWh_per_day_K": adj["slope"], "slope_se": adj["slope_se"],
            "post_period_kWh": adj_sum, "post_period_se_kWh": adj["sum_se"],
            "mean_dT_K": {"pre": float(dt_day.reindex(d_pre.index).mean()),
                          "post": float(dt_day.reindex(d_post.index).mean())},
            "extrapolated": extrapolated is not None,
            "adjusted_nmbe_pct": stats_adj["nmbe_pct"],
            "adjusted_cv_rmse_pct": stats_adj["cv_rmse_pct"],
        },
        "fsu": fsu["fsu"],
        "fsu_at_68pct": fsu68["fsu"],
        "fsu_below_50pct_at_68pct": bool(fsu68["fsu"] < 0.5),
        "t": fsu["t"],
        "n_eff": fsu["n_eff"],
        "fsu_formula": "FSU = t x 1.26 x CV(RMSE) x sqrt((n/n') (1 + 2/n) / m) / F "
        "(ASHRAE Guideline 14-2014 Annex B; Reddy and Claridge 2000)",
    }  # fmt: skip

    # ---------------------------------------------------------------- physical change
    def hlc_draws(mdl, draws, env0):
        from thermocal.retrofit.model import calculated_hlc

        n = len(draws["H_est"])
        hlc = np.empty(n)
        groups = {g: np.empty(n) for g in ("k_env", "k_win", "k_floor")}
        for d in range(n):
            env = _envelope_of(env0, d)
            h = mdl.conductances(env)
            # the ventilation measures cannot remove more than the loss there is (as the
            # demand simulation: thermocal.retrofit.model._parameter_sets)
            hlc[d] = calculated_hlc(h) + max(draws["H_est"][d] + h["H_est_change"], 0.0)
            for g, v in group_conductances(mdl, env).items():
                groups[g][d] = v
        return hlc, groups

    hlc_pre, g_pre = hlc_draws(model, draws_pre, env_pre[0])
    hlc_post, g_post = hlc_draws(model_post, draws_post, env_post[0])
    touched = sorted({g for m in measures.values() if (g := _group_of(m.component))})
    from thermocal.retrofit.correction import GROUP_LABELS

    def summary(values):
        lo, hi = _quantiles(values[1:] if len(values) > 1 else values, interval)
        return {"value": float(values[0]), "lo": lo, "hi": hi}

    physical = {
        "heat_loss_coefficient_W_per_K": {
            "pre": summary(hlc_pre),
            "post": summary(hlc_post),
            "change": summary(hlc_post - hlc_pre),
        },
        "groups": {
            g: {
                "label": GROUP_LABELS[g],
                "pre": summary(g_pre[g]),
                "post": summary(g_post[g]),
                "change": summary(g_post[g] - g_pre[g]),
            }
            for g in touched
        },
        "annual_kWh": {"pre": summary(a_pre[0]), "post": summary(a_post),
                       "post_with_post_indoor_profile": summary(a_post_use)},
        "saving_pct": summary(s_phys),
        "normalised_saving_pct": summary(s_norm),
        "indoor_profile": profile_mode if isinstance(profile_mode, str) else float(profile_mode),
        "indoor_profile_C": [float(v) for v in prof_pre],
        "mean_indoor_C": {"pre": float(inputs.loc[sel_pre, OUTPUT_COLUMN].mean()),
                          "post": float(inputs.loc[sel_post, OUTPUT_COLUMN].mean())},
        "weather": meta.get("name"),
    }  # fmt: skip

    # ---------------------------------------------------------------- comparison
    if prediction.saving_pct is None:
        prediction.saving_pct = float(s_model[0])
        prediction.p_lo, prediction.p_hi = _quantiles(s_model[1:], interval)
        prediction.draws = s_model
    comparison = compare(
        s_avoided_year, prediction, interval, sec.inconclusive_pp, baseline_ok,
        take_back_pp=avoided["take_back_pp"], physical_pct=s_norm,
        extrapolated=None if extrapolated is None else extrapolated["short"],
    )  # fmt: skip
    comparison["model_prediction_from_pre_period"] = summary(s_model)
    # the metered heat's scale against the building file and between the periods
    keys = heat_unit_keys(mc)
    gains_now = internal_gains_text(cfg.internal_gains)
    hl = physical["heat_loss_coefficient_W_per_K"]
    comparison["warnings"] = [
        w for w in (
            described_hlc_warning(
                hl["pre"]["value"], described_hlc(model), keys, gains_now, mc.heat_source
            ),
            baseline_bias_warning(stats["nmbe_pct"], keys, gains_now, mc.heat_source),
            hlc_rise_warning(hl["pre"], hl["post"], keys),
            None if extrapolated is None else extrapolated["warning"],
        )
        if w is not None
    ]  # fmt: skip
    timings["total"] = time.perf_counter() - t0
    ver = Verification(
        config=vcfg, building=building, pre=pre, post=post, retrofit_date=date,
        calibration_pre=cal_pre, calibration_post=cal_post, prediction=prediction,
        daily=daily, avoided=avoided, physical=physical, comparison=comparison,
        timings=timings, notes=notes, truth=truth,
    )  # fmt: skip
    return ver


def compare(
    measured: np.ndarray,
    prediction: Prediction,
    interval: float,
    inconclusive_pp: float,
    baseline_ok: bool,
    *,
    take_back_pp: float = 0.0,
    take_back_limit_pp: float = 5.0,
    physical_pct: np.ndarray | None = None,
    extrapolated: str | None = None,
) -> dict:
    """Measured minus predicted saving [pp] with its interval, and the verdict.

    Parameters
    ----------
    measured : ndarray [%]
        Measured saving normalised to the reference year at the prediction's indoor profile,
        first the estimate, then draws.
    prediction : Prediction
        With its own draws (paired) or an interval (independent: half-widths combined in
        quadrature, each side separately).
    interval : float [-]
    inconclusive_pp : float [pp]
        A measured-saving interval wider than this either side makes the verdict inconclusive
        (a vague prediction alone does not: the measurement can still fall inside it).
    baseline_ok : bool
        The baseline model meets the Guideline 14 criteria.
    take_back_pp : float [pp]
        Saving of the post period lost to its changed indoor temperatures (positive: warmer
        rooms after the retrofit).
    take_back_limit_pp : float [pp]
        A take-back beyond this makes a delivered retrofit a rebound.
    physical_pct : ndarray [%], optional
        The second answer (models calibrated on each period), quoted in the explanation.
    extrapolated : str, optional
        The two periods' weather when the post period's lies outside the pre period's or the
        residual adjustment carries much of the baseline
        (:func:`~.verify_periods.weather_extrapolation`): said in the explanation, and an
        interval too wide is then not cured by measuring longer.

    Returns
    -------
    dict: measured, predicted, difference (value, lo, hi), verdict, explanation.
    """
    m0 = float(measured[0])
    m_lo, m_hi = _quantiles(measured[1:] if len(measured) > 1 else measured, interval)
    p0 = float(prediction.saving_pct)
    if prediction.draws is not None and len(prediction.draws) == len(measured):
        d = measured - prediction.draws
        d0 = float(d[0])
        d_lo, d_hi = _quantiles(d[1:], interval)
    else:
        d0 = m0 - p0
        p_lo = p0 if prediction.p_lo is None else float(prediction.p_lo)
        p_hi = p0 if prediction.p_hi is None else float(prediction.p_hi)
        d_lo = d0 - float(np.hypot(m0 - m_lo, p_hi - p0))
        d_hi = d0 + float(np.hypot(m_hi - m0, p0 - p_lo))
    pct = f"{100 * interval:.0f} %"
    diff = f"{d0:+.1f} pp, {pct} interval {d_lo:+.1f} to {d_hi:+.1f} pp"
    take_back = (
        f"; warmer rooms after the retrofit take back {take_back_pp:.1f} pp of the post "
        "period's saving (comfort take-back)"
        if take_back_pp > 1.0
        else ""
    )
    if not baseline_ok:
        verdict = "inconclusive"
        why = (
            "the baseline model does not meet the ASHRAE Guideline 14-2014 criteria on the "
            "pre-retrofit period, so the measured saving is not reliable"
        )
    elif max(m0 - m_lo, m_hi - m0) > inconclusive_pp:
        verdict = "inconclusive"
        remedy = (
            "measure longer before and after the retrofit"
            if extrapolated is None
            else f"the post period's weather {extrapolated}, and the baseline is extrapolated; "
            "measuring longer in this weather does not help, a pre period reaching the post "
            "period's weather does"
        )
        why = (
            f"the interval of the measured saving ({m_lo:.1f} to {m_hi:.1f} %) is wider than "
            f"+/- {inconclusive_pp:g} pp: {remedy}"
        )
    elif d_hi < 0.0:
        verdict = "rebound"
        why = (
            f"the house saves less than predicted: {m0:.1f} % measured vs {p0:.1f} % "
            f"predicted at the same indoor temperatures ({diff})"
            + (take_back or "; the measures perform worse than described (performance gap)")
        )
    elif d_lo > 0.0:
        verdict = "prebound"
        why = (
            f"the house saves more than predicted: {m0:.1f} % measured vs {p0:.1f} % predicted "
            f"({diff}); the prediction started from higher losses than the house really had"
            + take_back
        )
    elif take_back_pp > take_back_limit_pp:
        verdict = "rebound"
        why = (
            f"the retrofit delivers its saving at equal indoor temperatures ({m0:.1f} % "
            f"measured vs {p0:.1f} % predicted, {diff}), but the rooms are warmer after it: "
            f"{take_back_pp:.1f} pp of the post period's saving are taken back as comfort"
        )
    else:
        verdict = "delivered"
        why = (
            f"the measured saving {m0:.1f} % agrees with the predicted {p0:.1f} % within the "
            f"uncertainty ({diff})" + take_back
        )
    if extrapolated is not None and verdict != "inconclusive":
        why += (
            f"; but the post period's weather {extrapolated}: the saving rests on the "
            "baseline's extrapolation"
        )
    if physical_pct is not None:
        lo, hi = _quantiles(physical_pct[1:] if len(physical_pct) > 1 else physical_pct, interval)
        why += (
            f". Second answer, the models calibrated before and after: "
            f"{float(physical_pct[0]):.1f} % ({lo:.1f} to {hi:.1f} %), not the verdict's basis: "
            "its interval holds the parameters' spread, not the post model's bias (outside "
            "EnergyPlus' true saving in 10 of 16 runs; docs/verify.md, Known limits)"
        )
    return {
        "measured_saving_pct": {"value": m0, "lo": m_lo, "hi": m_hi},
        "predicted_saving_pct": {"value": p0, "lo": prediction.p_lo, "hi": prediction.p_hi,
                                 "source": prediction.source, "strategy": prediction.code},
        "difference_pp": {"value": d0, "lo": d_lo, "hi": d_hi},
        "take_back_pp": take_back_pp,
        "interval": interval,
        "verdict": verdict,
        "explanation": why,
    }  # fmt: skip


# ------------------------------------------------------------------------------------------
# outputs
# ------------------------------------------------------------------------------------------


def results_dict(ver: Verification) -> dict:
    """The content of verify.json."""
    from types import SimpleNamespace

    from thermocal.retrofit.outputs import provenance

    cfg = ver.config.retrofit

    def cal_dict(cal):
        out = {
            "heat_loss_coefficient_W_per_K": cal.heat_loss_coefficient,
            "heat_loss_coefficient_std": cal.heat_loss_coefficient_std,
            "estimates_SI": cal.estimates_si,
            "flags": cal.flags,
            "loglike": cal.loglike,
        }
        if cal.correction is not None:
            out["correction"] = {"factors": cal.correction.factors,
                                 "summary": cal.correction.summary()}  # fmt: skip
        return out

    res = {
        "thermocal_workflow": "verify (post-retrofit verification, IPMVP Option D / "
        "ASHRAE Guideline 14-2014)",
        "building": ver.building.name,
        "retrofit_date": str(ver.retrofit_date),
        "periods": {"pre": [str(t) for t in ver.pre], "post": [str(t) for t in ver.post]},
        "measures": {n: {"component": m.component, "u_value": m.u_value}
                     for n, m in ver.prediction.measures.items()},
        "avoided_energy": ver.avoided,
        "physical_change": ver.physical,
        "comparison": ver.comparison,
        "verdict": ver.comparison["verdict"],
        "calibration": {"pre": cal_dict(ver.calibration_pre),
                        "post": cal_dict(ver.calibration_post)},
        "uncertainty": {"draws": cfg.uncertainty.draws, "interval": cfg.uncertainty.interval},
        "notes": ver.notes,
        "timings_s": ver.timings,
        "references": [r.entry() for r in (IPMVP, ASHRAE_14, REDDY_CLARIDGE_2000,
                                           SUNIKKA_BLANK_2012, FORSSELL_LJUNG_1999)],
        "provenance": provenance(SimpleNamespace(config=cfg)),
    }  # fmt: skip
    if ver.truth is not None:
        res["truth"] = ver.truth
        res["truth_check"] = truth_check(ver)
    return _clean(res)


def truth_check(ver: Verification) -> dict:
    """The verification against the demo generator's known answers."""
    t = ver.truth
    annual = ver.comparison["measured_saving_pct"]
    hlc = ver.physical["heat_loss_coefficient_W_per_K"]
    return {
        "annual_saving_pct": {
            "true": t["annual_saving_pct"], "verified": annual["value"],
            "lo": annual["lo"], "hi": annual["hi"],
            "error_pp": annual["value"] - t["annual_saving_pct"],
            "covered": bool(annual["lo"] <= t["annual_saving_pct"] <= annual["hi"]),
        },
        "post_period_saving_pct_same_controls": {
            "true": t["post_period_saving_pct"],
            "verified_with_take_back": ver.avoided["saving_with_take_back_pct"],
            "error_pp": ver.avoided["saving_with_take_back_pct"] - t["post_period_saving_pct"],
        },
        "heat_loss_coefficient_W_per_K": {
            k: {"true": t["heat_loss_coefficient_W_per_K"][k], **hlc[k]} for k in ("pre", "post")
        },
    }  # fmt: skip


#: The verify demo's generator moved to :mod:`thermocal.demos.verify`; these names still
#: resolve here (lazily: the demos package sits above the retrofit analysis).
_MOVED_TO_DEMOS = (
    "DEMO_PERIOD",
    "DEMO_RETROFIT_DATE",
    "DEMO_STRATEGY",
    "SHIPPED_VERIFY_DATA",
    "generate_verify_demo_data",
    "write_verify_demo_data",
    "verify_demo_config",
    "prepare_verify_demo",
    "main",
)
#: The outputs' writers live in :mod:`thermocal.retrofit.verify_report`; docs/verify.md lists
#: them with this module's API, so they resolve here too.
_IN_VERIFY_REPORT = ("write_verify_outputs", "write_report", "make_figures")


def __getattr__(name: str):
    if name in _MOVED_TO_DEMOS:
        from thermocal.demos import verify as demo

        return getattr(demo, name)
    if name in _IN_VERIFY_REPORT:  # verify_report imports this module: resolved lazily
        from thermocal.retrofit import verify_report

        return getattr(verify_report, name)
    raise AttributeError(f"module 'thermocal.retrofit.verify' has no attribute {name!r}")


if __name__ == "__main__":  # pragma: no cover - python -m thermocal.retrofit.verify
    from thermocal.demos.verify import main

    main()
