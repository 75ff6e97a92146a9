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
import datetime as _dt
import json
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
from thermocal.retrofit.calibration import calibrate_to_heat, heating_setpoint
from thermocal.retrofit.config import (
    MIN_TRAINING_DAYS,
    RetrofitConfig,
    _format_validation_error,
    _Strict,
    parse_config,
)
from thermocal.retrofit.references import Reference

#: Shortest pre and post period [days] by default: twice the shortest calibration period of the
#: fifth-order model (7 days separate the heat loss from the capacities; the method uses 21).
DEFAULT_MIN_DAYS = 14.0
#: Fewest heating days (daily mean outdoor temperature below 12 C, the heating limit of the
#: 20/12 heating degree days) the post period must hold.
MIN_HEATING_DAYS = 7
#: Heating limit [C] of a heating day.
HEATING_LIMIT_C = 12.0
#: Empirical factor of the fractional savings uncertainty (Guideline 14-2014 Annex B).
FSU_FACTOR = 1.26
#: Verdict "inconclusive" when the measured saving's interval is wider than this either side [pp].
DEFAULT_INCONCLUSIVE_PP = 10.0
#: Standard errors by which the first days of the reporting period must look more like the
#: baseline than the rest does (:func:`baseline_days_after_retrofit`).
BASELINE_DAYS_Z = 3.0
#: Files that identify a verify output folder.
VERIFY_SIGNATURE = ("verify.json", "report.html")

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
    prediction: PredictionConfig

    @field_validator(
        "retrofit_date", "pre_start", "pre_end", "post_start", "post_end", mode="before"
    )
    @classmethod
    def _yaml_date(cls, value: Any) -> Any:
        if isinstance(value, _dt.date):
            return value.isoformat()
        return value


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


def _stamp(text: str | None, tz, default: pd.Timestamp) -> pd.Timestamp:
    if text is None:
        return default
    t = pd.Timestamp(text)
    return t.tz_localize(tz) if t.tz is None else t.tz_convert(tz)


def split_periods(index: pd.DatetimeIndex, sec: VerifySection, source: str):
    """Pre and post periods [start, end) from the ``verify:`` section; refuses overlaps."""
    tz = index.tz
    step = index[1] - index[0]
    first, end_data = index[0], index[-1] + step
    date = _stamp(sec.retrofit_date, tz, first)
    if not first < date < end_data:
        raise ThermocalInputError(
            f"verify.retrofit_date {sec.retrofit_date}: the measurements in {source} run from "
            f"{first} to {end_data}; the retrofit date must lie inside them (data before and "
            "after it)"
        )
    pre = (_stamp(sec.pre_start, tz, first), _stamp(sec.pre_end, tz, date))
    post = (_stamp(sec.post_start, tz, date), _stamp(sec.post_end, tz, end_data))
    if pre[1] > post[0]:
        relation = "come in the wrong order" if post[1] <= pre[0] else "overlap"
        raise ThermocalInputError(
            f"the pre-retrofit period ({pre[0]} - {pre[1]}) and the post-retrofit period "
            f"({post[0]} - {post[1]}) {relation}; the pre period must end before the post "
            "period starts (verify.pre_end, verify.post_start)"
        )
    if pre[1] > date or post[0] < date:
        raise ThermocalInputError(
            f"the periods must lie on either side of the retrofit (verify.retrofit_date "
            f"{date}): pre ends {pre[1]}, post starts {post[0]}"
        )
    for name, (a, b) in (("pre", pre), ("post", post)):
        if not a < b:
            raise ThermocalInputError(f"verify.{name}_start must be before verify.{name}_end")
    return pre, post, date


def check_period(frame: pd.DataFrame, name: str, min_days: float, source: str) -> None:
    """Refuse a period too short (measured days) or, for the post period, without heating."""
    step_h = (frame.index[1] - frame.index[0]) / pd.Timedelta(hours=1) if len(frame) > 1 else 1
    ok = frame[["phi_h_measured", "Ti_measured", "Te"]].notna().all(axis=1)
    days = float(ok.sum() * step_h / 24.0)
    if days < min_days:
        raise ThermocalInputError(
            f"{source}: the {name}-retrofit period has {days:.1f} days of measurements "
            f"(heat, indoor and outdoor temperature); a verification needs at least "
            f"{min_days:g} days in each period (verify.min_days): the fifth-order model needs "
            f"{MIN_TRAINING_DAYS:g} days to tell the heat loss from the capacities and the "
            "method calibrates on 21; measure longer"
        )
    if name == "post":
        daily_te = frame["Te"].groupby(frame.index.normalize()).mean()
        heating = int((daily_te < HEATING_LIMIT_C).sum())
        if heating < MIN_HEATING_DAYS:
            raise ThermocalInputError(
                f"{source}: the post-retrofit period {frame.index[0]:%Y-%m-%d} - "
                f"{frame.index[-1]:%Y-%m-%d} has {heating} heating days (daily mean outdoor "
                f"temperature below {HEATING_LIMIT_C:g} C), at least {MIN_HEATING_DAYS} are "
                "needed: a heating-demand saving can only be measured in the heating season; "
                "measure in the next heating season"
            )


def baseline_days_after_retrofit(
    measured: np.ndarray, baseline: np.ndarray, rho: float, z: float = BASELINE_DAYS_Z
) -> dict:
    """Leading days of the reporting period that behave like the baseline (a late retrofit).

    After the retrofit the measured daily heat is a roughly constant fraction ``m`` of the
    baseline model's. Days before the works were finished, counted in the reporting period
    because the stated retrofit date is too early, follow the baseline itself (``m = 1``)
    and lower the measured saving. The change point ``k`` is fitted by least squares:
    ``measured = baseline`` on the first ``k`` days, ``m x baseline`` (``m`` fitted) on the
    rest, for ``k = 0 .. n // 2``; the daily errors are taken equal in kWh (the baseline
    model's day-to-day error). A step is reported when ``k >= 2`` (one day is an outlier, not
    a period) and the fit improves on ``k = 0`` by more than ``z^2`` error variances, the
    variance widened for the lag-1 autocorrelation ``rho`` of the daily residuals by
    ``(1 + rho) / (1 - rho)``. ``z`` is 3, not 2, because the change point is searched for:
    on simulated reporting periods without a step (the verify demo's daily error and
    autocorrelation, savings 0-60 %) 2 gave up to 9 % false alarms, 3 at most 1.2 %, and
    still finds 2, 4 and 7 baseline days in about 60, 90 and 97 % of the cases.

    Parameters
    ----------
    measured, baseline : ndarray [kWh]
        Daily measured heat and the (adjusted) baseline model's of the reporting period's
        days, in order.
    rho : float [-]
        Lag-1 autocorrelation of the baseline period's daily residuals (clipped to 0-0.9).
    z : float [-]
        Standard errors the step must exceed.

    Returns
    -------
    dict
        ``days`` (leading days that behave like the baseline, 0 when no step is found;
        counted in the input's order, days without data included), ``candidate_days`` (the
        fitted change point, likewise), ``ratio_first`` and ``ratio_rest`` (measured over
        baseline heat of the first ``candidate_days`` days and of the rest [-]),
        ``statistic`` (the fit's improvement in error variances) and ``threshold`` (``z^2``).
    """
    out = {"days": 0, "candidate_days": 0, "ratio_first": float("nan"),
           "ratio_rest": float("nan"), "statistic": 0.0, "threshold": float(z * z)}  # fmt: skip
    step = _leading_step(measured, baseline, rho, fitted="rest")
    if step is None:
        return out
    out.update(
        candidate_days=step["span"], ratio_rest=step["ratio"], statistic=step["statistic"],
        ratio_first=step["leading_ratio"],
        days=step["span"] if step["k"] >= 2 and step["statistic"] > z * z else 0,
    )  # fmt: skip
    return out


def _leading_step(measured, baseline, rho: float, *, fitted: str) -> dict | None:
    """The least-squares change point of the daily heat after its leading days, shared by
    :func:`baseline_days_after_retrofit` and (on the reversed days)
    :func:`retrofitted_days_before_the_date`.

    On the first ``k`` days and on the rest, the measured heat is the baseline model's or a
    fitted fraction ``m`` of it: ``fitted`` says which part has the fraction ("rest" or
    "leading"); ``k = 0 .. n // 2``. Days without heat data (or a baseline of 0) are skipped.

    Parameters
    ----------
    measured, baseline : array-like [kWh]
        Daily measured heat and the baseline model's, in order.
    rho : float [-]
        Lag-1 autocorrelation of the daily residuals (clipped to 0-0.9).
    fitted : {"rest", "leading"}

    Returns
    -------
    dict or None
        ``k`` (leading days with data), ``span`` (the days they cover, skipped ones
        included), ``ratio`` (the fitted ``m``; 1 for ``k = 0`` with "leading"),
        ``leading_ratio`` and ``rest_ratio`` (measured over baseline heat of the two parts;
        NaN for no leading day), ``statistic`` (the fit's improvement on ``k = 0`` in error
        variances widened for ``rho``); None with fewer than 6 days.
    """
    y = np.asarray(measured, float)
    b = np.asarray(baseline, float)
    ok = np.isfinite(y) & np.isfinite(b) & (b > 0)  # days without heat data are skipped
    where = np.flatnonzero(ok)
    y, b = y[ok], b[ok]
    n = len(y)
    if n < 6:
        return None
    sse, ratios = [], []
    for k in range(n // 2 + 1):
        if fitted == "rest":
            m = float(np.dot(y[k:], b[k:]) / np.dot(b[k:], b[k:]))
            lead, rest = 1.0, m
        else:
            m = float(np.dot(y[:k], b[:k]) / np.dot(b[:k], b[:k])) if k else 1.0
            lead, rest = m, 1.0
        sse.append(float(np.sum((y[:k] - lead * b[:k]) ** 2) + np.sum((y[k:] - rest * b[k:]) ** 2)))
        ratios.append(m)
    k = int(np.argmin(sse))
    r = min(max(float(rho), 0.0), 0.9) if np.isfinite(rho) else 0.0
    var = sse[k] / (n - 2) * (1.0 + r) / (1.0 - r)
    return {
        "k": k,
        "span": int(where[k - 1]) + 1 if k else 0,  # up to the last such day
        "ratio": ratios[k],
        "leading_ratio": float(y[:k].sum() / b[:k].sum()) if k else float("nan"),
        "rest_ratio": float(y[k:].sum() / b[k:].sum()),
        "statistic": float((sse[0] - sse[k]) / var) if var > 0 else 0.0,
    }


def retrofitted_days_before_the_date(
    measured: np.ndarray, baseline: np.ndarray, rho: float, z: float = BASELINE_DAYS_Z
) -> dict:
    """Trailing days of the baseline period that behave unlike the baseline (a retrofit
    finished before the stated date).

    The mirror of :func:`baseline_days_after_retrofit`: on the last ``k`` days of the
    baseline period the measured daily heat is a fitted fraction ``m`` of the baseline
    model's, on the days before it the model's (``m = 1``); ``k = 0 .. n // 2`` by least
    squares, reported when ``k >= 2``, ``m < 1`` (the house needed less: retrofitted) and the
    fit improves on ``k = 0`` by more than ``z^2`` error variances (widened for the lag-1
    autocorrelation ``rho``). The baseline model was calibrated on those days too, so the
    contrast is smaller than after the date, and the test conservative.

    Parameters
    ----------
    measured, baseline : ndarray [kWh]
        Daily measured heat and the baseline model's of the baseline period's days, in order.
    rho : float [-]
        Lag-1 autocorrelation of the daily residuals (clipped to 0-0.9).
    z : float [-]
        Standard errors the step must exceed.

    Returns
    -------
    dict
        ``days`` (trailing days that behave like a retrofitted house, 0 when no step is
        found; counted back from the last day, days without data included),
        ``candidate_days``, ``ratio_last`` and ``ratio_before`` (measured over baseline heat of
        the last ``candidate_days`` days and of the days before [-]), ``statistic`` and
        ``threshold``.
    """
    out = {"days": 0, "candidate_days": 0, "ratio_last": float("nan"),
           "ratio_before": float("nan"), "statistic": 0.0, "threshold": float(z * z)}  # fmt: skip
    step = _leading_step(
        np.asarray(measured, float)[::-1], np.asarray(baseline, float)[::-1], rho,
        fitted="leading",
    )  # fmt: skip
    if step is None:
        return out
    k = step["k"]
    out.update(
        candidate_days=step["span"], ratio_last=step["ratio"] if k else float("nan"),
        ratio_before=step["rest_ratio"], statistic=step["statistic"],
        days=step["span"] if k >= 2 and step["ratio"] < 1.0 and step["statistic"] > z * z
        else 0,
    )  # fmt: skip
    return out


def retrofitted_days_note(step: dict, days: pd.DatetimeIndex) -> str | None:
    """The warning of :func:`retrofitted_days_before_the_date`, None without a step.

    Parameters
    ----------
    step : dict
        Its result.
    days : pd.DatetimeIndex
        The baseline period's days, in order (the last ``step["days"]`` are named).
    """
    k = step["days"]
    if not k:
        return None
    first, last = days[len(days) - k], days[-1]
    return (
        f"the last {k} days of the baseline period ({first:%Y-%m-%d} to {last:%Y-%m-%d}) "
        f"behave like a retrofitted house: it used {100 * step['ratio_last']:.0f} % of the "
        f"baseline model's heat on them, {100 * step['ratio_before']:.0f} % before (a step of "
        f"{np.sqrt(step['statistic']):.1f} standard errors, {np.sqrt(step['threshold']):g} "
        "needed). Was the retrofit finished earlier? Then set verify.retrofit_date (or "
        f"verify.pre_end) to {first:%Y-%m-%d}: days of the new house in the baseline lower "
        "the baseline and the measured saving, and spoil the baseline's fit"
    )


def baseline_days_note(step: dict, days: pd.DatetimeIndex) -> str | None:
    """The warning of :func:`baseline_days_after_retrofit`, None without a step.

    Parameters
    ----------
    step : dict
        Its result.
    days : pd.DatetimeIndex
        The reporting period's days, in order (the first ``step["days"]`` are named).
    """
    k = step["days"]
    if not k:
        return None
    first, last = days[0], days[k - 1]
    return (
        f"the first {k} days of the reporting period ({first:%Y-%m-%d} to {last:%Y-%m-%d}) "
        f"behave like the baseline: the house used {100 * step['ratio_first']:.0f} % of the "
        f"baseline model's heat on them, {100 * step['ratio_rest']:.0f} % on the rest (a step "
        f"of {np.sqrt(step['statistic']):.1f} standard errors, {np.sqrt(step['threshold']):g} "
        "needed). Was the retrofit finished later? Then set verify.retrofit_date (or "
        f"verify.post_start) to {last + pd.Timedelta(days=1):%Y-%m-%d}: days of the old house "
        "counted after the retrofit lower the measured saving"
    )


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
    from thermocal.retrofit.gains import check_metered_electricity, internal_gains
    from thermocal.retrofit.model import build_fifth_order_model
    from thermocal.retrofit.workflow import (
        IRRADIANCE_SPLIT_NOTE,
        _location_tz,
        interior_for,
        load_building,
        load_weather_year,
        model_inputs,
    )

    building = load_building(cfg.building, config_source=source)
    mc, ig = cfg.measurements, cfg.internal_gains
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
        electricity_cumulative=ig.electricity_cumulative,
    )  # fmt: skip
    # the clock first: a wrong time zone also puts sunlight where the sun is low
    clock = clock_notes(raw, mc, building.location)
    check_irradiance_limits(grid, mc, building.location, str(mc.file))
    grid = with_beam_and_diffuse(grid, mc, building.location)
    notes = list(removed_values_notes(quality, mc.columns))
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


def _calibrate(
    cfg: RetrofitConfig, model, data: pd.DataFrame, source: str, log_interval=None
):
    from thermocal.retrofit.calibration import calibrate, check_training_data

    check_training_data(data, source, heat_source=cfg.measurements.heat_source)
    return calibrate(
        model, data, n_starts=cfg.model.n_starts, seed=cfg.model.seed,
        max_correlation=cfg.model.max_correlation,
        correction=cfg.model.correction == "groups" and cfg.uncertainty.u_value_rel_std > 0,
        fixed_noise=cfg.model.fixed_diffusions(), heat_rel_std=cfg.uncertainty.heat_rel_std,
        u_value_rel_std=cfg.uncertainty.u_value_rel_std, log_interval=log_interval,
    )  # fmt: skip


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
    half = t * FSU_FACTOR * cv_rmse_pct / 100.0 * np.sqrt((n / n_eff) * (1.0 + 2.0 / n) / m)
    return {
        "half_width": float(half),
        "fsu": float(half / fraction) if fraction else float("inf"),
        "t": t,
        "n_eff": float(n_eff),
    }


#: reading steps a sensor or meter may have [unit of its values]
_READING_STEPS = (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.25, 0.5, 1, 2, 5, 10, 20, 50)


def _resolution(values: np.ndarray) -> float:
    """The sensor's reading step [unit of the values]: the largest of the usual steps of
    which at least 99 % of its non-zero readings are multiples; NaN when there are fewer than
    20 non-zero readings or none fits (continuous readings)."""
    values = values[np.isfinite(values) & (values != 0)]
    if len(values) < 20:
        return float("nan")
    for step in reversed(_READING_STEPS):
        ratio = values / step
        if np.mean(np.abs(ratio - np.round(ratio)) < 1e-6 * np.maximum(1.0, np.abs(ratio))) >= 0.99:
            return float(step)
    return float("nan")


def _logging_interval(times: pd.DatetimeIndex) -> pd.Timedelta | None:
    """Median time between a column's readings, None with fewer than 3 readings."""
    if len(times) < 3:
        return None
    return pd.Series(times).diff().median()


def sensor_change_notes(
    raw: pd.DataFrame, pre: tuple, post: tuple, columns: dict, source: str
) -> list[str]:
    """Signs that a sensor or meter was exchanged between the periods.

    A replaced sensor usually reads with another resolution (e.g. 0.1 K -> 0.5 K, a heat
    meter's 1 kWh -> 0.1 kWh) or logs at another interval; its readings before and after are
    then not the same measurement and the verified saving can move with the change (ASHRAE
    Guideline 14 asks for the same metering in both periods). Each column whose reading step
    or logging interval differs by a factor of 2 or more between the periods is named.

    Parameters
    ----------
    raw : DataFrame
        Measurements as read (standard column names, original time stamps).
    pre, post : tuple of Timestamp
        Start and end of the pre- and post-retrofit periods.
    columns : dict
        Standard name -> the file's column name (for the messages).
    source : str
        Measurement file (for the messages).

    Returns
    -------
    list of str
        One note per changed column (empty when nothing changed).
    """
    out = []
    for name in raw.columns:
        series = raw[name].dropna()
        before = series[(series.index >= pre[0]) & (series.index < pre[1])]
        after = series[(series.index >= post[0]) & (series.index < post[1])]
        if before.empty or after.empty:
            continue
        label = f"{source}, column {columns.get(name, name)!r}"
        r0 = _resolution(before.to_numpy(float))
        r1 = _resolution(after.to_numpy(float))
        if np.isfinite(r0) and np.isfinite(r1) and max(r0, r1) >= 2.0 * min(r0, r1):
            out.append(
                f"{label}: the readings change resolution at the retrofit ({r0:g} before, "
                f"{r1:g} after): a sensor or meter was probably exchanged; check that both "
                "measure the same quantity in the same place, else the verified saving carries "
                "the difference"
            )
        i0, i1 = _logging_interval(before.index), _logging_interval(after.index)
        if i0 is not None and i1 is not None and max(i0, i1) >= 2 * min(i0, i1):
            out.append(
                f"{label}: the logging interval changes at the retrofit "
                f"({i0 / pd.Timedelta('1min'):g} min before, {i1 / pd.Timedelta('1min'):g} min "
                "after): a sensor or logger was probably exchanged; check that both measure the "
                "same quantity in the same place"
            )
    return out


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
    from thermocal.retrofit.data import log_interval
    from thermocal.retrofit.demand import DEMAND_INPUTS, simulate_demand
    from thermocal.retrofit.gate import ashrae14_statistics, heat_to_follow_measured
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
    pre, post, date = split_periods(inputs.index, sec, source)
    notes += sensor_change_notes(quality["raw"], pre, post, cfg.measurements.columns, source)
    sel_pre = (inputs.index >= pre[0]) & (inputs.index < pre[1])
    sel_post = (inputs.index >= post[0]) & (inputs.index < post[1])
    check_period(inputs.loc[sel_pre], "pre", sec.min_days, source)
    check_period(inputs.loc[sel_post], "post", sec.min_days, source)
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
        what = f"{source} ({name}-retrofit period)"
        if method == "heat":
            from thermocal.retrofit.calibration import check_training_data

            check_training_data(inputs.loc[sel], what, heat_source=cfg.measurements.heat_source)
            cal = calibrate_to_heat(mdl, inputs.loc[sel], setpoint_all[sel], gains=has_gains)
        else:
            cal = _calibrate(cfg, mdl, inputs.loc[sel], what, log_interval(quality["raw"]))
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
    for col in ("baseline", "baseline_old_comfort"):
        daily.loc[d_post.index, col] = d_post[col] + adj["per_day"]
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
    for d in range(a_pre.shape[1]):
        sums = []
        for k in (0, 1):
            q = heat_to_follow_measured(
                model, {n: float(draws_pre[n][d]) for n in ESTIMATED_PARAMETERS},
                _envelope_of(env_pre[k], d), cal_pre.x0, frame[list(DEMAND_INPUTS)],
                setpoint, frame["phi_int"] if has_gains else None,
            )  # fmt: skip
            sums.append(float(q[post_days].sum()))
        post_ratio_d[d] = sums[1] / sums[0] if sums[0] > 0 else float("nan")
    post_ratio_d[0] = e_ret_model / e_base_model if e_base_model > 0 else float("nan")
    rng = np.random.default_rng(cfg.uncertainty.seed + 2161)
    sigma_r = fsu["half_width"] / fsu["t"]  # relative standard uncertainty of a post sum
    r_d = e_meas / e_base * np.exp(rng.normal(0.0, sigma_r, a_pre.shape[1]))
    r_d[0] = e_meas / e_base
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
    )  # fmt: skip
    comparison["model_prediction_from_pre_period"] = summary(s_model)
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
        why = (
            f"the interval of the measured saving ({m_lo:.1f} to {m_hi:.1f} %) is wider than "
            f"+/- {inconclusive_pp:g} pp: measure longer before and after the retrofit"
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
    if physical_pct is not None:
        lo, hi = _quantiles(physical_pct[1:] if len(physical_pct) > 1 else physical_pct, interval)
        why += (
            f". Second answer, the models calibrated before and after: "
            f"{float(physical_pct[0]):.1f} % ({lo:.1f} to {hi:.1f} %)"
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


def make_figures(ver: Verification) -> dict:
    """Figures of the report: daily heat measured vs baseline; HLC before / after."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figs = {}
    d = ver.daily
    fig, ax = plt.subplots(figsize=(9, 3.6))
    ax.plot(d.index, d["measured"], "o-", ms=3, color="k", label="measured")
    ax.plot(d.index, d["baseline"], "s-", ms=3, color="tab:red",
            label="baseline model (calibrated before the retrofit)")  # fmt: skip
    ax.axvline(ver.retrofit_date, color="grey", ls="--", label="retrofit")
    post = d["period"] == "post"
    ax.fill_between(d.index[post], d["measured"][post], d["baseline"][post], color="tab:green",
                    alpha=0.25, label="avoided energy")  # fmt: skip
    ax.set_ylabel("heat per day [kWh]")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    fig.autofmt_xdate()
    fig.tight_layout()
    figs["daily_heat"] = fig

    from thermocal.report.figures import plot_bars_with_intervals

    hlc = ver.physical["heat_loss_coefficient_W_per_K"]
    labels, vals, lo, hi = [], [], [], []
    for key, name in (("pre", "HLC before"), ("post", "HLC after")):
        labels.append(name)
        vals.append(hlc[key]["value"])
        lo.append(hlc[key]["lo"])
        hi.append(hlc[key]["hi"])
    for v in ver.physical["groups"].values():
        for key, name in (("pre", "before"), ("post", "after")):
            labels.append(f"{v['label']} {name}")
            vals.append(v[key]["value"])
            lo.append(v[key]["lo"])
            hi.append(v[key]["hi"])
    figs["conductances"] = plot_bars_with_intervals(
        labels, vals, lo, hi, ylabel="W/K", title="Calibrated conductances before and after",
        interval_label=f"{100 * ver.config.retrofit.uncertainty.interval:.0f} % interval",
    )  # fmt: skip
    return figs


def _pct(v: dict, digits: int = 1) -> str:
    if v.get("lo") is None:
        return f"{v['value']:.{digits}f} %"
    return f"{v['value']:.{digits}f} % ({v['lo']:.{digits}f} to {v['hi']:.{digits}f} %)"


def write_report(ver: Verification, results: dict, figures: dict, path: Path) -> Path:
    """The self-contained report.html (same builder and style as the retrofit report)."""
    from thermocal.report import HtmlReport

    cfg = ver.config.retrofit
    pct = f"{100 * cfg.uncertainty.interval:.0f} %"
    comp, av, ph = ver.comparison, ver.avoided, ver.physical
    rep = HtmlReport(
        f"Retrofit verification: {ver.building.name}",
        subtitle="Measured against predicted saving (IPMVP Option D, ASHRAE Guideline "
        "14-2014) with calibrated fifth-order RC models before and after the retrofit",
    )
    rep.section("Verdict")
    rep.paragraph(f"{comp['verdict'].upper()}: {comp['explanation']}.", css_class="lead")
    for key in ("baseline_days_after_retrofit", "retrofitted_days_before_the_date"):
        warning = av.get(key, {}).get("warning")
        if warning:
            rep.flags([warning[0].upper() + warning[1:] + "."])
    m, p, dd = comp["measured_saving_pct"], comp["predicted_saving_pct"], comp["difference_pp"]
    rep.key_values({
        "measured saving (reference year, normalised)": _pct(m),
        "predicted saving": _pct(p) + f" - {p['source']}",
        "difference": f"{dd['value']:+.1f} pp ({pct} interval {dd['lo']:+.1f} to "
        f"{dd['hi']:+.1f} pp)",
        "avoided energy, post period": f"{av['avoided_kWh']:,.0f} kWh of "
        f"{av['baseline_kWh']:,.0f} kWh ({av['saving_pct']:.1f} %, {pct} interval "
        f"{av['saving_pct_lo']:.1f} to {av['saving_pct_hi']:.1f} %)",
        "retrofit": f"{', '.join(ver.prediction.measures)} on {ver.retrofit_date:%Y-%m-%d}",
        "periods": f"before {ver.pre[0]:%Y-%m-%d} to {ver.pre[1]:%Y-%m-%d}, after "
        f"{ver.post[0]:%Y-%m-%d} to {ver.post[1]:%Y-%m-%d}",
    })  # fmt: skip
    _verification_track_record(rep)
    rep.paragraph(
        "Delivered: the measured saving agrees with the prediction within the uncertainty. "
        "Rebound: the house saves less than predicted (higher indoor temperatures after the "
        "retrofit, or a performance gap of the measures). Prebound: it saves more, typically "
        "because the house used less energy before the retrofit than its description said "
        "(Sunikka-Blank and Galvin 2012). Inconclusive: the data cannot tell."
    )
    rep.section("Avoided energy (IPMVP Option D, ASHRAE Guideline 14-2014)")
    rep.paragraph(
        "The fifth-order model calibrated on the pre-retrofit period is driven by the "
        "post-retrofit period's measured weather and follows the indoor temperature its "
        "heating held (the measured one while heated; at most the thermostat's hour-of-day "
        "profile while the house floated above it): the heat it needs is what the house "
        "would have used without the retrofit. Avoided energy = that baseline minus the "
        "measured heat. "
        + (
            "The indoor temperature was held by a thermostat (median deviation "
            f"{av['indoor_control']['mad_K']:.2f} K), so the model was fitted to the metered "
            "heat, not to the indoor temperature (closed loop). "
            if av["calibration"] == "heat"
            else "The model was fitted to the measured indoor temperature (the retrofit "
            "method's maximum-likelihood calibration). "
        )
        + (
            "The daily residuals of the pre period grow with the indoor-outdoor difference "
            f"({av['adjustment']['slope_kWh_per_day_K']:.2f} +/- "
            f"{av['adjustment']['slope_se']:.2f} kWh/day per K, e.g. air change rising with "
            "the stack effect and the wind): the baseline of the post period (mean "
            f"difference {av['adjustment']['mean_dT_K']['post']:.1f} K against "
            f"{av['adjustment']['mean_dT_K']['pre']:.1f} K) is adjusted by "
            f"{av['adjustment']['post_period_kWh']:+,.0f} kWh."
            if av["adjustment"]["applied"]
            else ""
        )
    )
    if "daily_heat" in figures:
        rep.figure(
            figures["daily_heat"],
            caption="Daily heat measured and of the baseline model; shaded: avoided energy.",
        )
    ok = "meets" if av["baseline_meets_criteria"] else "does NOT meet"
    rep.key_values({
        "baseline model, pre period (daily)": f"NMBE {av['baseline_nmbe_pct']:+.1f} %, "
        f"CV(RMSE) {av['baseline_cv_rmse_pct']:.1f} % over {av['days_pre']} days: {ok} the "
        f"criteria (|NMBE| <= {av['criteria']['max_abs_nmbe_pct']:g} %, CV(RMSE) <= "
        f"{av['criteria']['max_cv_rmse_pct']:g} %)",
        "post period": f"{av['days_post']} days: baseline {av['baseline_kWh']:,.0f} kWh, "
        f"measured {av['measured_kWh']:,.0f} kWh",
        "fractional savings uncertainty": f"{100 * av['fsu']:.0f} % at {pct} confidence, "
        f"{100 * av['fsu_at_68pct']:.0f} % at 68 % (Guideline 14 asks below 50 % at 68 %)",
        "formula": av["fsu_formula"] + f"; lag-1 autocorrelation of the daily residuals "
        f"{av['residual_lag1_autocorrelation']:.2f}, n' = {av['n_eff']:.1f}",
        "comfort take-back": f"mean indoor temperature {av['mean_indoor_C']['pre']:.1f} C "
        f"before, {av['mean_indoor_C']['post']:.1f} C after; at the old indoor profile the "
        f"baseline is {av['baseline_at_pre_comfort_kWh']:,.0f} kWh and the saving "
        f"{av['saving_with_take_back_pct']:.1f} % ({av['take_back_pp']:+.1f} pp taken back)",
        "normalised to the reference year": f"{_pct(av['normalised_saving_pct'])}, "
        f"{av['normalised_avoided_kWh']:,.0f} kWh/a: the measured fraction of the baseline "
        "over the post period carried to the reference year by the model's ratio of "
        "retrofitted to baseline demand over the year divided by the same ratio over the "
        f"post period (measured-to-expected {av['measured_to_expected_ratio']:.3f})",
    })  # fmt: skip
    rep.section("Physical change: the model calibrated on each period")
    hl = ph["heat_loss_coefficient_W_per_K"]
    rows = [["heat loss coefficient [W/K]", *(_iv(hl[k]) for k in ("pre", "post", "change"))]]
    for g in ph["groups"].values():
        rows.append([f"{g['label']} [W/K]", *(_iv(g[k]) for k in ("pre", "post", "change"))])
    ak = ph["annual_kWh"]
    rows.append(["annual heating demand [kWh]", _iv(ak["pre"], ",.0f"),
                 _iv(ak["post"], ",.0f"), ""])  # fmt: skip
    rep.table(
        pd.DataFrame(rows, columns=["", "before", "after", "change"]),
        caption=f"Estimates with {pct} intervals (posterior draws); annual demand over the "
        f"reference year ({ph['weather']}) at the "
        + {"measured": "pre period's measured", "the prediction's": "prediction's"}.get(
            ph["indoor_profile"], "constant"
        )
        + f" indoor profile (mean {np.mean(ph['indoor_profile_C']):.1f} C).",
    )
    mi = ph["mean_indoor_C"]
    with_post = (
        f"; with the post period's indoor profile for the retrofitted house: "
        f"{_pct(ph['normalised_saving_pct'])}"
        if ph["normalised_saving_pct"] != ph["saving_pct"]
        else ""
    )
    rep.paragraph(
        f"Saving of the envelope alone (both models at the same indoor profile): "
        f"{_pct(ph['saving_pct'])}{with_post}. Mean measured indoor temperature "
        f"{mi['pre']:.1f} C before, {mi['post']:.1f} C after."
    )
    if "conductances" in figures:
        rep.figure(
            figures["conductances"],
            caption="Heat loss coefficient and the retrofitted element groups, before and after.",
        )
    if ver.truth is not None:
        tc = results["truth_check"]
        a = tc["annual_saving_pct"]
        rep.section("Demo: check against the generator")
        rep.paragraph(
            f"The demo house was simulated by the detailed multi-zone model with roof and walls "
            f"retrofitted on {ver.retrofit_date:%Y-%m-%d}. True annual saving at 20 C "
            f"{a['true']:.1f} %, verified {a['verified']:.1f} % ({a['lo']:.1f} to "
            f"{a['hi']:.1f} %, error {a['error_pp']:+.1f} pp, "
            f"{'covered' if a['covered'] else 'NOT covered'}). True heat loss coefficient "
            f"{tc['heat_loss_coefficient_W_per_K']['pre']['true']:.0f} W/K before, "
            f"{tc['heat_loss_coefficient_W_per_K']['post']['true']:.0f} W/K after. "
            "In the post period, the same house without the retrofit under the same controls "
            f"would have used {ver.truth['post_period_heat_kWh']['without_retrofit']:,.0f} kWh "
            f"({tc['post_period_saving_pct_same_controls']['true']:.1f} % saved, the warmer "
            "rooms of the insulated house included); verified with the take-back: "
            f"{av['saving_with_take_back_pct']:.1f} %. The avoided energy of IPMVP "
            f"({av['saving_pct']:.1f} %) counts the warmer rooms as a condition of the post "
            "period."
        )
    rep.section("Calibrations")
    for name, cal in (("before", ver.calibration_pre), ("after", ver.calibration_post)):
        rep.heading(f"Model calibrated {name} the retrofit")
        if cal.correction is not None:
            rep.paragraph(cal.correction.summary())
        if cal.flags:
            rep.flags(cal.flags)
    if ver.notes:
        rep.bullets(ver.notes, intro="Notes")
    rep.section("References")
    rep.references([r.entry() for r in (IPMVP, ASHRAE_14, REDDY_CLARIDGE_2000,
                                         SUNIKKA_BLANK_2012, FORSSELL_LJUNG_1999)])  # fmt: skip
    return rep.write(path)


def _verification_track_record(rep) -> None:
    """How the same verification held on a house thermocal did not write (EnergyPlus 25.2)."""
    from thermocal.retrofit.track_record import INDEPENDENT_VERIFICATIONS

    rows = [
        {
            "case": c.case,
            "verified - EnergyPlus's annual saving": f"{c.error_pp:+.1f} pp",
            "90 % interval covers it": "yes" if c.covered else "no",
            "post period's avoided energy - EnergyPlus's": f"{c.post_period_error_pp:+.1f} pp",
            "verdict": c.verdict,
        }
        for c in INDEPENDENT_VERIFICATIONS.values()
    ]
    rep.paragraph(
        "How far such a verification can be off: the same analysis on a house thermocal did "
        "not write, measured by EnergyPlus 25.2 before and after a wall retrofit, against "
        "EnergyPlus's own annual saving and its run without the retrofit over the same weeks "
        "(pp: percentage points):"
    )
    rep.table(pd.DataFrame(rows), caption="The verification against EnergyPlus")


def _iv(v: dict, spec: str = ".0f") -> str:
    return f"{v['value']:{spec}} ({v['lo']:{spec}} to {v['hi']:{spec}})"


def write_verify_outputs(ver: Verification, out_dir: Path | str) -> dict:
    """Write verify.json, daily_heat.csv, figures/*.png and report.html into ``out_dir``."""
    from thermocal.report.figures import close, figure_to_png

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    results = results_dict(ver)
    (out / "verify.json").write_text(json.dumps(results, indent=2))
    daily = ver.daily.copy()
    daily.index = daily.index.tz_localize(None) if daily.index.tz is not None else daily.index
    daily.rename(columns={"measured": "measured_kWh", "baseline": "baseline_kWh"}).to_csv(
        out / "daily_heat.csv", index_label="date", float_format="%.3f"
    )
    fig_dir = out / "figures"
    fig_dir.mkdir(exist_ok=True)
    figures = {}
    for name, fig in make_figures(ver).items():
        figures[name] = figure_to_png(fig)
        close(fig)
        (fig_dir / f"{name}.png").write_bytes(figures[name])
    write_report(ver, results, figures, out / "report.html")
    return results


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


def __getattr__(name: str):
    if name in _MOVED_TO_DEMOS:
        from thermocal.demos import verify as demo

        return getattr(demo, name)
    raise AttributeError(f"module 'thermocal.retrofit.verify' has no attribute {name!r}")


if __name__ == "__main__":  # pragma: no cover - python -m thermocal.retrofit.verify
    from thermocal.demos.verify import main

    main()
