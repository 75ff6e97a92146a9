"""The inputs of a calibration campaign, loaded once: building, weather, sensor log and
mapping (or the built-in demo), the identification options, the unoccupied hours of the metric,
and the identification problems of the calibration and validation periods.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.identification.occupancy import OccupancySchedule
from thermocal.identification.problem import IdentificationProblem

#: identification options a campaign file may set (its ``identification`` section)
IDENTIFICATION_KEYS = {
    "method": "inverse",
    "feedback": "air",
    "settle": "1D",
    "max_gap": "1h",
    "silence": "15min",
    "warmup_days": 7,
    "tuning_zone": None,
}
#: keys of the ``identification`` section that say how the sensor log is read (as identify's
#: --tz, --decimal, --time-format and --rows)
LOG_KEYS = {"tz": None, "decimal": ".", "time_format": None, "rows": "reports"}
#: The sensor-log reader's remedies name its Python options; a campaign has these keys.
_READER_REMEDIES = (
    ("pass tz= (", "set identification.tz in the campaign file ("),
    ("or pass tz=", "or set identification.tz in the campaign file"),
    ("pass the time zone (--tz Europe/Zurich)", "set identification.tz (e.g. Europe/Zurich)"),
    ("pass a fixed offset, e.g. tz=1.0", "set identification.tz to an offset, e.g. 1.0"),
    ("(a decimal comma: pass decimal=',')", "(a decimal comma: set identification.decimal: ',')"),
    ("pass time_format=", "set identification.time_format"),
    (": sort it, or pass sort=True", ": sort it by time"),
    (", or pass duplicates='first' or 'last'", ""),
    ("; pass interval=", "; log more than one row per sensor"),
)


@dataclass
class CampaignInputs:
    """Everything a campaign needs, loaded once."""

    building: Any
    weather: pd.DataFrame
    metadata: dict
    sensor_log: pd.DataFrame
    mapping: Any
    start: Any
    end: Any
    truth: dict | None = None
    true_loads: pd.DataFrame | None = None
    log_name: str = "sensor log"
    #: True when the campaign file gives no ``period:`` and the period is the log's span
    period_from_log: bool = False
    #: what loading changed, for calibration.json and the report (``identification.site:
    #: weather``: the weather file's site replaced the building's)
    notes: list = field(default_factory=list)


def load_inputs(campaign) -> CampaignInputs:
    """Building, weather, sensor log and mapping of a campaign file (or the built-in demo)."""
    if campaign.is_demo:
        name = campaign.building.split(":", 1)[1]
        if name != "clinic":
            raise ThermocalInputError(
                f"{campaign.path}: unknown demo building {campaign.building!r}; use demo:clinic"
            )
        from thermocal.demos.identification import load_demo

        building, weather, meta, raw, mapping, truth = load_demo()
        start, end = meta["period"]
        if campaign.period is not None:
            start, end = (
                _localise(campaign.period.start, start),
                _localise(campaign.period.end, start),
            )
        loads = None
        path = meta["files"].get("true_loads.parquet")
        if path is not None and Path(path).is_file():
            loads = pd.read_parquet(path)
        return CampaignInputs(
            building,
            weather,
            meta["weather"],
            raw,
            mapping,
            start,
            end,
            truth,
            loads,
            str(meta["files"]["sensors.parquet"]),
        )
    from thermocal.identification.sensors import load_mapping
    from thermocal.io.measurements import read_measurements
    from thermocal.io.weather import building_site_or_weather, check_weather_clock, read_weather
    from thermocal.multizone.files import load_building

    if campaign.mapping is None:
        raise ThermocalInputError(
            f"{campaign.path}: 'mapping' is missing: the file assigning sensors to zones"
        )
    building = load_building(campaign.building_path)
    weather, site = read_weather(campaign.weather)
    site_note = building_site_or_weather(
        building,
        site,
        campaign.identification.get("site", "building"),
        building_source=str(campaign.building),
        weather_source=str(campaign.weather),
        option="identification.site",
        opt_in="identification.site: weather in the campaign file",
    )
    if site_note:
        import warnings

        warnings.warn(site_note, stacklevel=2)
    check_weather_clock(weather, site, source=str(campaign.weather))
    log = {key: campaign.identification.get(key, default) for key, default in LOG_KEYS.items()}
    if log["decimal"] not in (".", ","):
        raise ThermocalInputError(
            f"{campaign.path}: identification.decimal {log['decimal']!r}: use '.' or ','"
        )
    if log["rows"] not in ("reports", "interval_start", "interval_end"):
        raise ThermocalInputError(
            f"{campaign.path}: identification.rows {log['rows']!r}: use reports, interval_start "
            "or interval_end"
        )
    try:
        raw, _ = read_measurements(campaign.sensors, **log)
    except ThermocalInputError as exc:  # the reader's remedies in the campaign file's terms
        text = str(exc)
        for option, remedy in _READER_REMEDIES:
            text = text.replace(option, remedy)
        raise ThermocalInputError(text) from None
    mapping = load_mapping(campaign.mapping)
    if campaign.period is not None:
        start = _localise(campaign.period.start, weather.index[0])
        end = _localise(campaign.period.end, weather.index[0])
    else:  # as identify without --start/--end: the log's span, not the whole weather file
        from thermocal.identification.sensors import log_span_on_grid

        start, end = log_span_on_grid(raw, weather.index, campaign.step_timedelta())
    return CampaignInputs(
        building,
        weather,
        site,
        raw,
        mapping,
        start,
        end,
        log_name=str(campaign.sensors),
        period_from_log=campaign.period is None and start is not None,
        notes=[site_note] if site_note else [],
    )


def _localise(value, like) -> pd.Timestamp:
    stamp = pd.Timestamp(value)
    if stamp.tzinfo is None and getattr(like, "tzinfo", None) is not None:
        stamp = stamp.tz_localize(like.tzinfo)
    return stamp


def identification_options(campaign) -> dict:
    """The campaign's identification options with their defaults (unknown keys rejected)."""
    options = dict(IDENTIFICATION_KEYS)
    allowed = set(IDENTIFICATION_KEYS) | set(LOG_KEYS) | {"site"}
    unknown = set(campaign.identification) - allowed
    if unknown:
        raise ThermocalInputError(
            f"{campaign.path}: identification: unknown keys {sorted(unknown)} (allowed: "
            f"{', '.join(sorted(allowed))})"
        )
    options.update(
        {k: v for k, v in campaign.identification.items() if k not in LOG_KEYS and k != "site"}
    )
    return options


def campaign_schedule(campaign) -> OccupancySchedule:
    """The occupancy schedule the campaign file declares (the published one by default)."""
    if isinstance(campaign.occupancy, str) or campaign.occupancy is None:
        return OccupancySchedule.paper()
    return OccupancySchedule.from_dict(campaign.occupancy, source=f"{campaign.path}: occupancy")


def choose_quiet_hours(campaign, heat: pd.Series, log=print) -> tuple[OccupancySchedule, dict]:
    """The schedule of the metric: declared, or the quiet hours of the nominal identified heat.

    ``occupancy`` in the campaign file: a schedule (used as given), ``"paper"`` (the published
    method's schedule, used as given), ``"data"`` (the quiet hours found in the identified
    heat, :func:`thermocal.identification.quiet.quiet_hours`) or absent (``"auto"``: the
    published schedule, unless the data show that its hours are demonstrably not quiet; then
    the quiet hours).

    Parameters
    ----------
    campaign : Campaign
    heat : Series
        Building-wide identified heat of the nominal model per step [W].
    log : callable

    Returns
    -------
    (OccupancySchedule, dict)
        The schedule and what was found (for calibration.json and the report).
    """
    from thermocal.identification.quiet import check_schedule, quiet_hours

    declared = campaign.occupancy
    schedule = campaign_schedule(campaign)
    if isinstance(declared, dict) or declared == "paper":
        return schedule, {"source": "declared" if isinstance(declared, dict) else "paper"}
    try:
        quiet = quiet_hours(heat)
    except ThermocalInputError as exc:
        if declared == "data":
            raise ThermocalInputError(f"{campaign.path}: occupancy: data: {exc}") from None
        return schedule, {"source": "paper", "check": f"not checked: {exc}"}
    check = check_schedule(quiet, schedule)
    info = {
        "quiet_hours": quiet.describe(),
        "quiet_hours_per_week": quiet.hours_per_week,
        "paper_schedule_check": check.describe(),
        "paper_schedule_quiet": check.quiet,
    }
    if declared == "data" or not check.quiet:
        log(
            f"occupancy: the published schedule is not quiet here ({check.describe()}); the "
            f"metric uses the quiet hours found in the identified heat: {quiet.describe()}"
        )
        return quiet.schedule, {"source": "data", **info}
    return schedule, {"source": "paper", **info}


#: the identification's remedies name identify's options: a campaign sets its file's keys
#: (``{key}``: the period's key, ``{file}``: the campaign file)
PERIOD_REMEDIES = (
    ("(--start/--end)", "({key}: {{start: ..., end: ...}} in {file})"),
    ("(--start)", "({key}: {{start: ...}} in {file})"),
    ("(--end)", "({key}: {{end: ...}} in {file})"),
)


def in_campaign_terms(exc: ThermocalInputError, campaign, key: str = "period"):
    """The error with identify's ``--start``/``--end`` remedies said as the campaign file's key.

    Parameters
    ----------
    exc : ThermocalInputError
        An error of the identification's checks.
    campaign : CampaignFile
    key : str
        The campaign file's key of the period concerned (``period`` or ``validation``).

    Returns
    -------
    ThermocalInputError
        ``exc`` itself when it names no such option.
    """
    text = str(exc)
    where = campaign.path or "the campaign file"
    for option, remedy in PERIOD_REMEDIES:
        text = text.replace(option, remedy.format(key=key, file=where))
    return exc if text == str(exc) else ThermocalInputError(text)


def check_campaign_period(campaign, inputs: CampaignInputs) -> None:
    """Refuse a period too short for the metric
    (:func:`thermocal.identification.sensors.check_period_length`), in the file's terms."""
    from thermocal.identification.sensors import check_period_length

    try:
        check_period_length(inputs.start, inputs.end, inputs.weather.index)
    except ThermocalInputError as exc:
        raise in_campaign_terms(exc, campaign) from None


def build_problem(
    campaign,
    inputs: CampaignInputs,
    *,
    start=None,
    end=None,
    schedule=None,
    step=None,
    period_key: str = "period",
):
    """The :class:`IdentificationProblem` of the campaign (references built once); ``step``
    (a Timedelta) instead of the campaign's for :mod:`thermocal.calibration.stepcheck`;
    ``period_key``: the campaign file's key of the period (``validation`` for
    :func:`validation_problem`), named in the remedies of a period the log does not cover."""
    try:
        return _identification_problem(campaign, inputs, start, end, schedule, step)
    except ThermocalInputError as exc:
        raise in_campaign_terms(exc, campaign, period_key) from None


def _identification_problem(campaign, inputs: CampaignInputs, start, end, schedule, step):
    """:func:`build_problem` without its remedies translated."""
    from thermocal.identification.problem import problem_from_measurements
    from thermocal.identification.workflow import check_pid_only_options

    options = identification_options(campaign)
    check_pid_only_options(  # in the campaign file's terms (the problem would say 'method')
        options["method"],
        {f"{campaign.path}: identification.tuning_zone": options["tuning_zone"]},
        method_option="identification.method",
    )
    schedule = schedule or campaign_schedule(campaign)
    problem, report = problem_from_measurements(
        inputs.building,
        inputs.weather,
        inputs.metadata,
        inputs.sensor_log,
        inputs.mapping,
        start=inputs.start if start is None else start,
        end=inputs.end if end is None else end,
        step=campaign.step if step is None else f"{int(pd.Timedelta(step).total_seconds())}s",
        method=options["method"],
        feedback=options["feedback"],
        tuning_zone=options["tuning_zone"],
        schedule=schedule,
        settle=options["settle"],
        max_gap=options["max_gap"],
        silence=options["silence"],
        warmup_days=int(options["warmup_days"]),
        log_name=inputs.log_name,
    )
    return problem, report


def analysis_inputs(campaign) -> CampaignInputs:
    """What a re-analysis needs of the inputs: the building (and the demo's truth)."""
    if campaign.is_demo:
        return load_inputs(campaign)
    from thermocal.multizone.files import load_building

    building = load_building(campaign.building_path)
    return CampaignInputs(building, pd.DataFrame(), {}, pd.DataFrame(), None, None, None)


def problem_settings(campaign, problem: IdentificationProblem, evaluator=None) -> dict:
    """What determines a sample's outputs besides its parameters, by name (for the store).

    The campaign file's settings (input files by content, period, step, options), whether each
    sample's unoccupied-heat series is stored (the series meta-model needs it), the zone groups
    whose series are stored (the spatial metric) and a digest of the identification problem
    built from them.
    """
    series = problem.series_outputs
    try:  # the digest without the series switch, which is named on its own line
        problem.series_outputs = False
        digest = problem.fingerprint()
    finally:
        problem.series_outputs = series
    extra = {}
    if evaluator is not None:
        extra["zone-group heat series stored per sample"] = list(evaluator.labels)
    return {
        **campaign.problem_settings(),
        "heat series stored per sample": bool(series),
        **extra,
        "identification problem": digest,
    }


def validation_problem(campaign, inputs: CampaignInputs):
    """The identification problem of the validation period, built (and so checked: weather,
    sensor coverage) before the campaign rather than after it; None without a validation."""
    if campaign.validation is None:
        return None
    start = _localise(campaign.validation.start, inputs.weather.index[0])
    end = _localise(campaign.validation.end, inputs.weather.index[0])
    check_validation_apart(
        (inputs.start, inputs.end),
        (start, end),
        source=str(campaign.path or "campaign file"),
        calibration_from_log=inputs.period_from_log,
    )
    try:
        problem, _ = build_problem(
            campaign, inputs, start=start, end=end, period_key="validation"
        )
    except ThermocalInputError as exc:
        raise ThermocalInputError(
            f"{campaign.path}: validation period [{start}, {end}): {exc} (checked before the "
            "campaign; correct 'validation:' or remove it)"
        ) from None
    return problem


def check_validation_apart(
    calibration: tuple, validation: tuple, *, source: str, calibration_from_log: bool = False
) -> None:
    """Refuse a validation period that overlaps the calibration period: the validation is
    meant to be on data the calibration did not see.

    Parameters
    ----------
    calibration, validation : (Timestamp, Timestamp)
        The periods ``[start, end)`` (local time of the data); a calibration period of None
        (the whole weather file) is not checked here.
    source : str
        The campaign file, for the message.
    calibration_from_log : bool
        The calibration period is the sensor log's span (the file gives no ``period:``).

    Raises
    ------
    ThermocalInputError
        Naming both periods, the overlap [h] and what to do.
    """
    (c0, c1), (v0, v1) = calibration, validation
    if c0 is None or c1 is None or not (v0 < c1 and c0 < v1):
        return
    overlap = (min(c1, v1) - max(c0, v0)) / pd.Timedelta("1h")
    if calibration_from_log:
        why = " (the sensor log's span: the file gives no period:)"
        remedy = "give a period: {start: ..., end: ...} on the log's other days"
    else:
        why = ""
        remedy = (
            "move 'validation:' outside 'period:' (e.g. the days after it), shortening "
            "'period:' if the log holds no other days"
        )
    raise ThermocalInputError(
        f"{source}: the validation period [{v0}, {v1}) overlaps the calibration period "
        f"[{c0}, {c1}){why} by {overlap:.1f} h; the validation must be on data the "
        f"calibration did not see: {remedy}, or remove 'validation:'"
    )


def check_unoccupied_steps(campaign, problem: IdentificationProblem, period: str) -> None:
    """Refuse a schedule that leaves the metric no unoccupied steps in a period, before the
    campaign: identify's check (:func:`thermocal.identification.metrics.unoccupied_variance`
    refuses fewer than two) in the campaign file's terms.

    Parameters
    ----------
    campaign : CampaignFile
    problem : IdentificationProblem
        With the metric's schedule (``problem.schedule``) set.
    period : str
        Which period it is, for the message (``calibration period``, ``validation period``).

    Raises
    ------
    ThermocalInputError
        Naming the campaign file's ``occupancy`` key, the period and what to do.
    """
    from thermocal.identification.metrics import unoccupied_variance

    times = problem.reference.index
    try:  # the metric's own check on the period's steps (the heat does not matter here)
        unoccupied_variance(pd.Series(0.0, index=times), problem.schedule, settle=problem.settle)
    except ThermocalInputError:
        settle = "" if problem.settle is None else f" after its first {problem.settle} (settling)"
        raise ThermocalInputError(
            f"{campaign.path or 'campaign file'}: occupancy: the schedule of the metric leaves "
            f"fewer than two unoccupied steps in the {period} [{times[0]}, "
            f"{times[-1] + pd.Timedelta(problem.step)}){settle}; the metric is the variance of "
            "the identified heat over the unoccupied hours: list the hours the building is "
            "empty under occupancy: unoccupied: (e.g. - {days: all, from: '20:00', to: "
            "'04:00'}), use occupancy: data (the quiet hours found in the identified heat), "
            "or remove occupancy: (the published schedule)"
        ) from None


def evaluator_for(problem: IdentificationProblem) -> IdentificationProblem:
    """The runner's evaluator: the problem itself (picklable, built once per worker)."""
    return problem
