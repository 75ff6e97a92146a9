"""The envelope-calibration workflow: campaign file -> campaign -> meta-model -> optimum.

:func:`calibrate` is the orchestrator: it builds the identification problem once (the zone
references from the sensors), evaluates the nominal model, samples the parameter space, runs the
campaign (local process pool or Dask) into the durable store, fits the meta-model, ranks the
parameters, optimises the reduced meta-model for the minimum and the maximum of the metric,
confirms both optima with the full model, optionally validates them on a second period, and
writes everything (:meth:`CalibrationResult.to_files`).
"""

from __future__ import annotations

import contextlib
import json
import os
import sqlite3
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.identification.metrics import guideline14
from thermocal.identification.occupancy import OccupancySchedule
from thermocal.identification.problem import METRIC, IdentificationProblem
from thermocal.identification.sensors import check_period_length
from thermocal.identification.workflow import jsonable

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


def load_inputs(campaign) -> CampaignInputs:
    """Building, weather, sensor log and mapping of a campaign file (or the built-in demo)."""
    if campaign.is_demo:
        name = campaign.building.split(":", 1)[1]
        if name != "clinic":
            raise ThermocalInputError(
                f"{campaign.path}: unknown demo building {campaign.building!r}; use demo:clinic"
            )
        from thermocal.identification.demo_data import load_demo

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
    from thermocal.io.weather import check_building_site, check_weather_clock, read_weather
    from thermocal.multizone.files import load_building

    if campaign.mapping is None:
        raise ThermocalInputError(
            f"{campaign.path}: 'mapping' is missing: the file assigning sensors to zones"
        )
    building = load_building(campaign.building_path)
    weather, site = read_weather(campaign.weather)
    check_building_site(
        building, site, building_source=str(campaign.building), weather_source=str(campaign.weather)
    )
    check_weather_clock(weather, site, source=str(campaign.weather))
    tz = campaign.identification.get("tz")
    raw, _ = read_measurements(campaign.sensors, tz=tz)
    mapping = load_mapping(campaign.mapping)
    start = end = None
    if campaign.period is not None:
        start = _localise(campaign.period.start, weather.index[0])
        end = _localise(campaign.period.end, weather.index[0])
    return CampaignInputs(
        building, weather, site, raw, mapping, start, end, log_name=str(campaign.sensors)
    )


def _localise(value, like) -> pd.Timestamp:
    stamp = pd.Timestamp(value)
    if stamp.tzinfo is None and getattr(like, "tzinfo", None) is not None:
        stamp = stamp.tz_localize(like.tzinfo)
    return stamp


def identification_options(campaign) -> dict:
    """The campaign's identification options with their defaults (unknown keys rejected)."""
    options = dict(IDENTIFICATION_KEYS)
    allowed = set(IDENTIFICATION_KEYS) | {"tz"}
    unknown = set(campaign.identification) - allowed
    if unknown:
        raise ThermocalInputError(
            f"{campaign.path}: identification: unknown keys {sorted(unknown)} (allowed: "
            f"{', '.join(sorted(allowed))})"
        )
    options.update({k: v for k, v in campaign.identification.items() if k != "tz"})
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


def build_problem(campaign, inputs: CampaignInputs, *, start=None, end=None, schedule=None):
    """The :class:`IdentificationProblem` of the campaign (references built once)."""
    from thermocal.identification.problem import problem_from_measurements

    options = identification_options(campaign)
    schedule = schedule or campaign_schedule(campaign)
    problem, report = problem_from_measurements(
        inputs.building,
        inputs.weather,
        inputs.metadata,
        inputs.sensor_log,
        inputs.mapping,
        start=inputs.start if start is None else start,
        end=inputs.end if end is None else end,
        step=campaign.step,
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


@dataclass
class CalibrationResult:
    """What the calibration found (see :func:`calibrate`)."""

    space: Any
    samples: Any
    store_frame: pd.DataFrame
    summary: Any
    surrogate: Any
    ranking: pd.Series
    sobol: pd.DataFrame | None
    critical: list
    optimisation: Any
    nominal_metric: float
    confirmed: dict
    heat: dict
    weather: pd.DataFrame
    validation: dict | None
    morris: pd.DataFrame | None
    truth_comparison: pd.DataFrame | None
    calibrated_building: Any
    timings: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    campaign_path: str = ""
    posterior: Any = None
    occupancy: dict = field(default_factory=dict)
    metric: str = "building"
    runs: dict = field(default_factory=dict)

    def table1(self) -> pd.DataFrame:
        """The paper's Table 1: nominal, min-variance and max-variance critical values."""
        return self.optimisation.table()

    def as_dict(self) -> dict:
        scores = {
            "cv_r2": float(self.surrogate.cv_r2_),
            "cv_rmse": float(self.surrogate.cv_rmse_),
            "kind": type(self.surrogate).__name__,
            "best_params": getattr(self.surrogate, "best_params_", None),
        }
        out = {
            "campaign": self.campaign_path,
            "metric": self.metric,
            "metric_description": METRIC_NAMES[self.metric],
            "metric_unit": "W^2",
            "model_runs": self.runs,
            "samples": {
                "total": int(self.summary.total),
                "successful": int(self.store_frame["error"].isna().sum()),
                "failed": int(self.store_frame["error"].notna().sum()),
                "backend": self.summary.backend,
                "wall_time_s": self.summary.wall_time_s,
            },
            "parameters": self.space.to_frame().reset_index().to_dict(orient="records"),
            "clipped_samples": self.samples.clip_counts.reset_index().to_dict(orient="records"),
            "metamodel": scores,
            "ranking": self.ranking.to_dict(),
            "sobol": None if self.sobol is None else self.sobol.reset_index().to_dict("records"),
            "critical": self.critical,
            "table1": self.table1().reset_index().to_dict(orient="records"),
            "nominal_metric": self.nominal_metric,
            "confirmation": self.confirmed,
            "validation": self.validation,
            "morris": None
            if self.morris is None
            else self.morris.reset_index().to_dict(orient="records"),
            "truth_comparison": None
            if self.truth_comparison is None
            else self.truth_comparison.reset_index().to_dict(orient="records"),
            "posterior": None if self.posterior is None else self.posterior.to_dict(),
            "occupancy": self.occupancy,
            "timings_s": self.timings,
            "notes": self.notes,
        }
        return jsonable(out)

    def calibrated_building_text(self) -> str:
        """The calibrated building as a thermocal YAML file, ready for ``thermocal simulate``."""
        import yaml

        from thermocal.calibration.space import parameter_unit
        from thermocal.multizone.elements import element_parameters
        from thermocal.multizone.files import building_to_dict

        source = self.confirmed.get("calibrated", {}).get("source", "meta-model minimum")
        lines = [
            "# thermocal building file: the nominal model with the envelope parameters of the",
            "# lowest confirmed unoccupied variance of the identified heat (calibrated),",
            f"# from the {source}.",
            f"# campaign: {self.campaign_path}",
        ]
        # the values of the body itself (the header and the body always agree)
        building = self.calibrated_building
        values = {**building.parameters(), **element_parameters(building)}
        nominal = self.space.nominal_dict()
        for name in self.space.names:
            if name in values and not np.isclose(values[name], nominal[name], rtol=1e-9):
                lines.append(
                    f"#   {name}: {nominal[name]:.6g} -> {values[name]:.6g} {parameter_unit(name)}"
                )
        body = yaml.safe_dump(
            building_to_dict(self.calibrated_building), sort_keys=False, allow_unicode=True
        )
        return "\n".join(lines) + "\n" + body

    def to_files(self, directory) -> list[Path]:
        """calibration.json, table1.csv, campaign export, calibrated building, figures, report."""
        from thermocal.calibration import figures
        from thermocal.calibration.report import write_report
        from thermocal.io.atomic import atomic_write

        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        written = [
            atomic_write(
                directory / "calibration.json",
                lambda p: p.write_text(json.dumps(self.as_dict(), indent=2)),
            ),
            atomic_write(directory / "table1.csv", lambda p: self.table1().to_csv(p)),
            atomic_write(directory / "samples.parquet", lambda p: self.store_frame.to_parquet(p)),
            atomic_write(directory / "samples.csv", lambda p: self.store_frame.to_csv(p)),
            atomic_write(
                directory / "calibrated_building.yaml",
                lambda p: p.write_text(self.calibrated_building_text()),
            ),
        ]
        pngs = {}
        from thermocal.report.figures import close, figure_to_png

        for name, fig in figures.calibration_figures(self).items():
            pngs[name] = figure_to_png(fig)
            close(fig)
            written.append(
                atomic_write(directory / f"{name}.png", lambda p, d=pngs[name]: p.write_bytes(d))
            )
        written.append(write_report(self, directory / "report.html", pngs=pngs))
        return written


def truth_comparison(
    names: list[str], space, truth: dict, calibrated: dict, critical=()
) -> pd.DataFrame:
    """Critical parameters vs the generator's truth: moved towards it, share recovered.

    ``recovered = (calibrated - nominal) / (true - nominal)``: 1 = the whole perturbation
    found, 0 = nothing, negative = moved away; NaN for parameters the truth did not perturb.

    Parameters
    ----------
    names : list of str
        Parameters to compare (the critical ones and those the truth perturbed).
    space : ParameterSpace
        Nominal values and units.
    truth : dict
        ``truth.json`` of the demo (``parameters``: name -> {"true": value, ...}).
    calibrated : dict
        Calibrated value per parameter [unit of each parameter].
    critical : sequence of str
        The critical parameters (flagged in the table).
    """
    true = {name: row["true"] for name, row in truth.get("parameters", {}).items()}
    from thermocal.calibration.space import parameter_unit

    nominal_values = space.nominal_dict()
    rows = []
    for name in names:
        nominal = nominal_values[name]
        calibrated_value = calibrated[name]
        target = true.get(name, nominal)
        perturbed = not np.isclose(target, nominal, rtol=1e-9)
        towards = abs(calibrated_value - target) < abs(nominal - target) if perturbed else None
        recovered = (calibrated_value - nominal) / (target - nominal) if perturbed else np.nan
        rows.append(
            {
                "parameter": name,
                "critical": name in critical,
                "unit": parameter_unit(name),
                "nominal": nominal,
                "calibrated": calibrated_value,
                "true": target,
                "perturbed_in_truth": perturbed,
                "moved_towards_truth": towards,
                "recovered_fraction": recovered,
            }
        )
    return pd.DataFrame(rows).set_index("parameter")


def calibrate(
    campaign,
    *,
    samples: int | None = None,
    workers: int | None = None,
    scheduler=None,
    resume: bool = False,
    store_path: str | Path | None = None,
    progress: bool = True,
    log=print,
    max_hours: float | None = 24.0,
) -> CalibrationResult:
    """Run a calibration campaign (see the module docstring).

    Parameters
    ----------
    campaign : CampaignFile
        From :func:`thermocal.calibration.config.load_campaign`.
    samples : int, optional
        Overrides ``sampling.samples`` [-].
    workers : int, optional
        Local processes (default: all cores); ignored with ``scheduler``.
    scheduler : str or distributed.Client, optional
        ``tcp://HOST:PORT`` of a Dask scheduler (or a client/cluster object).
    resume : bool
        Continue the campaign in an existing store (a store of another campaign is refused).
    store_path : path, optional
        The SQLite store (default: the campaign file's ``store``).
    progress : bool
        Show the campaign's progress: a bar on a terminal, otherwise a line through ``log``
        about every 5 % or minute (so that logs and CI show it).
    log : callable
        Receives one line per stage.
    max_hours : float or None
        Refuse a campaign estimated (pending samples x time of the nominal run / workers) to
        take longer [h]; None: no limit. Not applied with a Dask scheduler.

    Returns
    -------
    CalibrationResult
    """
    from thermocal.calibration.runner import run_campaign
    from thermocal.calibration.sampling import sample
    from thermocal.calibration.spatial import campaign_evaluator
    from thermocal.calibration.store import CampaignStore, campaign_definition

    timings: dict[str, float] = {}
    notes: list[str] = []
    n = int(samples if samples is not None else campaign.sampling.samples)
    path = Path(store_path or campaign.store or "campaign.sqlite")
    refuse_filled_store(path, resume, n)
    t0 = time.perf_counter()
    inputs = load_inputs(campaign)
    check_period_length(inputs.start, inputs.end, inputs.weather.index)
    problem, _ = build_problem(campaign, inputs)
    later = validation_problem(campaign, inputs)
    # every sample stores its unoccupied heat series, whatever the meta-model: the series
    # model and the posterior need it, and a campaign re-analysed with another meta-model kind
    # re-uses its simulations (the kind is an analysis setting, not part of the store)
    problem.series_outputs = True
    evaluator = campaign_evaluator(problem, inputs.building)
    timings["setup"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    nominal_run = problem.run({})
    problem.schedule, occupancy = choose_quiet_hours(campaign, nominal_run.heat.sum(axis=1), log)
    if later is not None:  # the validation period's metric uses the same hours
        later.schedule = problem.schedule
    nominal_outputs = evaluator.outputs(nominal_run.heat)
    timings["nominal_run"] = time.perf_counter() - t0
    log(
        f"nominal model: unoccupied std of building Q_ID "
        f"{nominal_outputs['unoccupied_std'] / 1000:.3f} kW ({timings['nominal_run']:.1f} s per "
        "identification)"
    )
    space = campaign_space(campaign, inputs.building)
    if n < 1:
        raise ThermocalInputError(f"--samples must be >= 1, got {n}")
    sample_set = sample(space, n, campaign.sampling.method, seed=campaign.sampling.seed)
    definition = campaign_definition(
        space,
        method=campaign.sampling.method,
        seed=campaign.sampling.seed,
        samples=n,
        problem=problem_settings(campaign, problem, evaluator),
    )
    log(f"campaign: {n} samples of {space.dimension} parameters -> {path}")
    t0 = time.perf_counter()
    with (
        _store_errors(path),
        CampaignStore.open(
            path,
            definition=definition,
            campaign_text=campaign.text,
            resume=resume,
            expected=sample_set.values,
        ) as store,
    ):
        store.record_run({}, nominal_outputs, nominal_run.heat.sum(axis=1))
        grid = problem.simulation().weather_on_grid
        store.set_info(
            "analysis",
            {
                "occupancy": {**occupancy, "schedule": problem.schedule.as_dict()},
                "groups": evaluator.groups,
                "group_labels": evaluator.labels,
                "weather": {
                    "start": grid.index[0].isoformat(),
                    "step_s": (grid.index[1] - grid.index[0]).total_seconds(),
                    "temp_air": grid["temp_air"].to_numpy().tolist(),
                    "ghi": (grid["ghi"] if "ghi" in grid else grid["dni"] + grid["dhi"])
                    .to_numpy()
                    .tolist(),
                },
            },
        )
        pending = len(store.pending(sample_set.values.index))
        check_campaign_time(
            pending,
            timings["nominal_run"],
            workers=workers,
            scheduler=scheduler,
            max_hours=max_hours,
            log=log,
        )
        interactive = progress and sys.stderr.isatty()
        summary = run_campaign(
            evaluator,
            sample_set.values,
            store,
            workers=workers,
            scheduler=scheduler,
            progress=interactive,
            on_result=None
            if interactive or not progress
            else ProgressLines(pending, n - pending, log),
        )
        timings["campaign"] = time.perf_counter() - t0
        log(
            f"campaign done: {summary.evaluated} evaluated, {summary.failed} failed, "
            f"{summary.backend}"
        )

        def morris():
            bar = progress and sys.stderr.isatty()  # a bar only where it is seen
            return _morris(campaign, problem, space, path, workers, scheduler, bar, log)

        return analyse(
            campaign,
            inputs,
            space,
            sample_set,
            summary,
            store,
            RunCache(
                store,
                evaluator,
                None if later is None else campaign_evaluator(later, inputs.building),
            ),
            timings=timings,
            notes=notes,
            log=log,
            morris=morris,
        )


def refuse_filled_store(path: Path, resume: bool, samples: int) -> None:
    """Refuse at once (before the set-up, which takes a while on a large building) a store that
    already holds samples when ``--resume`` is not given; the full check of the campaign's
    definition happens when the store is opened."""
    if resume or not path.is_file():
        return
    try:
        con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
        try:
            done = con.execute("SELECT COUNT(*) FROM results").fetchone()[0]
            row = con.execute("SELECT value FROM campaign WHERE key = 'definition'").fetchone()
        finally:
            con.close()
        stored = int(json.loads(row[0])["sampler"]["samples"])
    except (sqlite3.Error, TypeError, KeyError, ValueError):
        return  # not a readable campaign store: opening it says why
    if not done:
        return
    remedy = "use another --out (or store), or delete the file to start afresh"
    if stored != samples:
        raise ThermocalInputError(
            f"store {path} already holds {done} finished sample(s) of a campaign of {stored} "
            f"samples; pass --resume to extend it to {samples} (the same sampling sequence; "
            f"a store of another campaign is then refused, naming what differs), or {remedy}"
        )
    raise ThermocalInputError(
        f"store {path} already holds {done} finished sample(s); pass --resume to continue "
        f"the campaign (a store of another campaign is then refused, naming what differs), or "
        f"{remedy}"
    )


def campaign_space(campaign, building):
    """The campaign's parameter space on ``building`` (its ``parameters`` section)."""
    from thermocal.calibration.space import ParameterSpace

    p = campaign.parameters
    return ParameterSpace.from_parameters(
        candidate_parameters(building, p.level),
        include=p.include,
        exclude=p.exclude,
        default_range=p.default_range,
        ranges=p.ranges,
    )


@dataclass
class RunCache:
    """The analysis' model runs (nominal, confirmations, refinement), kept in the store.

    A run found in the store (same parameters, same problem) is read, not simulated; with no
    evaluator (a re-analysis) a run that is not stored is not simulated and :meth:`get` returns
    None.

    Attributes
    ----------
    store : CampaignStore
    evaluator : CampaignEvaluator or None
    validation : CampaignEvaluator or None
        The validation period's evaluator (its problem and zone groups).
    simulated : int
        Runs simulated by this cache [-].
    """

    store: Any
    evaluator: Any = None
    validation: Any = None
    simulated: int = 0
    reused: int = 0

    def get(self, parameters, *, tag: str = "", heat: bool = True):
        """Outputs [unit of each] and building-wide heat [W] of a run, or None (not stored
        and nothing may be simulated)."""
        parameters = dict(parameters)
        found = self.store.find_run(parameters, tag)
        if found is not None:
            self.reused += 1
            return found
        if self.evaluator is None:
            return None
        if tag == "validation":
            run = self.validation.problem.run(parameters)
            outputs = self.validation.outputs(run.heat)
        else:
            run = self.evaluator.problem.run(parameters)
            outputs = self.evaluator.outputs(run.heat)
        total = run.heat.sum(axis=1)
        self.simulated += 1
        self.store.record_run(parameters, outputs, total if heat else None, tag)
        return outputs, total


#: what each metric of the campaign file's ``metric`` key is, for calibration.json and the report
METRIC_NAMES = {
    "building": "unoccupied variance of the building-wide identified heat",
    "groups": "sum over the zone groups of the unoccupied variance of their hourly identified heat",
}


def metric_data(outputs: pd.DataFrame, metric: str):
    """The chosen metric of every sample, and the series of its series meta-model.

    Parameters
    ----------
    outputs : DataFrame
        The samples' stored outputs (:meth:`CampaignStore.outputs`).
    metric : {"building", "groups"}

    Returns
    -------
    y : ndarray [W^2]
    series : ndarray (samples, columns) [W] or None
    segments : list of (start, stop) or None
        Column range of each series (one per zone group; None: one series).
    """
    from thermocal.calibration.spatial import group_metric, group_segments

    if metric == "building":
        columns = sorted(c for c in outputs.columns if c.startswith("series/"))
        series = outputs[columns].to_numpy(dtype=float) if columns else None
        return outputs[METRIC].to_numpy(dtype=float), series, None
    columns, segments = group_segments(list(outputs.columns))
    if not columns:
        raise ThermocalInputError(
            "metric: groups needs the zone-group heat series of every sample, which this "
            "campaign's store does not hold (written before they were stored); use metric: "
            "building, or run the campaign again into a new store"
        )
    series = outputs[columns].to_numpy(dtype=float)
    return group_metric(series, segments), series, segments


def metric_value(outputs: dict, metric: str) -> float:
    """The chosen metric of one run's outputs [W^2]."""
    from thermocal.calibration.spatial import group_metric, group_segments

    if metric == "building":
        return float(outputs[METRIC])
    columns, segments = group_segments(list(outputs))
    return group_metric(np.array([outputs[c] for c in columns], dtype=float), segments)


def analyse(
    campaign,
    inputs,
    space,
    sample_set,
    summary,
    store,
    runs,
    *,
    timings,
    notes,
    log=print,
    morris=None,
) -> CalibrationResult:
    """Meta-model, ranking, optimisation, posterior and calibrated model of a stored campaign.

    Everything after the campaign's simulations: the samples come from ``store``; model runs
    (confirmations, posterior median, refinement, validation) go through ``runs`` (found in the
    store when they were run before with the same parameters; simulated only when ``runs`` has
    an evaluator).

    Parameters
    ----------
    campaign : CampaignFile
        Its analysis sections (``metric``, ``metamodel``, ``optimisation``) are used.
    inputs : CampaignInputs
        The building (and the demo's truth).
    space : ParameterSpace
    sample_set : SampleSet
    summary : CampaignSummary
    store : CampaignStore
    runs : RunCache
    timings, notes : dict, list
        Filled in.
    log : callable
    morris : callable, optional
        Returns the Morris screening (None: none).

    Returns
    -------
    CalibrationResult
    """
    from thermocal.calibration.optimise import optimise_reduced
    from thermocal.calibration.sensitivity import influence_ranking, top_k

    metric = campaign.metric
    clipped = sample_set.clip_counts[sample_set.clip_counts["total"] > 0]
    if len(clipped):
        notes.append(
            f"{len(clipped)} parameter(s) had samples clipped to their physical limits: "
            + ", ".join(f"{name} ({int(row['total'])})" for name, row in clipped.iterrows())
        )
    info = store.info("analysis") or {}
    occupancy = info.get("occupancy", {})
    if occupancy.get("source") == "data":
        notes.append(
            "Unoccupied hours from the data: "
            + occupancy.get("paper_schedule_check", "")
            + "; the metric uses the quiet hours of the nominal identified heat ("
            + occupancy["quiet_hours"]
            + ")."
        )
    nominal_found = runs.get({})
    if nominal_found is None:
        raise ThermocalInputError(
            f"store {store.path}: the nominal model's run is not stored (a store written before "
            "thermocal could re-analyse campaigns, without the zone-group series either); run "
            "the campaign again into a new store (another --out) to re-analyse it"
        )
    nominal_outputs, nominal_heat = nominal_found
    nominal_metric = metric_value(nominal_outputs, metric)
    t0 = time.perf_counter()
    frame = store.to_frame()
    X = store.parameters()[list(space.names)]
    outputs = store.outputs()
    y, series, segments = metric_data(outputs, metric)
    frame = frame.drop(
        columns=[c for c in frame.columns if c.startswith(("out:series/", "out:group/"))]
    )
    timings["read_store"] = time.perf_counter() - t0
    failed = int(frame["error"].notna().sum())
    if failed:
        notes.append(f"{failed} sample(s) failed (errors in the store); they are left out")
    if len(y) < max(10, campaign.metamodel.cv_folds + 2):
        raise ThermocalInputError(
            f"only {len(y)} successful samples: too few for a meta-model; use more --samples"
        )
    if metric != "building":
        notes.append(f"Metric: the {METRIC_NAMES[metric]} ({len(segments)} groups).")
    t0 = time.perf_counter()
    m = campaign.metamodel
    surrogate, kind, scores = choose_surrogate(
        X,
        y,
        m.kind,
        cv_folds=m.cv_folds,
        log_target=m.log_target,
        seed=campaign.sampling.seed,
        series=series,
        nominal=space.nominal_dict(),
        segments=segments,
    )
    if m.kind == "auto":
        notes.append(
            "Meta-model: "
            + ", ".join(f"{k.upper()} cross-validated R2 {r2:.3f}" for k, r2 in scores.items())
            + f"; the {kind.upper()} was used."
        )
    lower, upper = np.asarray(space.lower, float), np.asarray(space.upper, float)
    ranking = influence_ranking(surrogate.predict, X, lower, upper, names=space.names)
    sobol = _sobol_or_note(surrogate, space, lower, upper, campaign.sampling.seed, kind, notes)
    critical = top_k(ranking, m.top_k)
    optimisation = optimise_reduced(
        X,
        y,
        space,
        critical,
        surrogate=reduced_surrogate(kind, m, series, space, campaign.sampling.seed, segments),
        starts=campaign.optimisation.starts,
        seed=campaign.optimisation.seed,
        surrogate_options=reduced_options(kind, m),
    )
    timings["metamodel_sensitivity_optimisation"] = time.perf_counter() - t0
    screening = None
    if campaign.morris is not None and morris is not None:
        t0 = time.perf_counter()
        screening = morris()
        timings["morris"] = time.perf_counter() - t0
    log(f"meta-model cross-validated R2 {surrogate.cv_r2_:.3f}; critical: {', '.join(critical)}")
    t0 = time.perf_counter()
    confirmed, heat = {}, {"nominal": nominal_heat}
    unconfirmed = []
    for sense, optimum in (("min", optimisation.minimum), ("max", optimisation.maximum)):
        found = runs.get(optimisation.parameters(sense))
        if found is None:
            unconfirmed.append(sense)
            confirmed[sense] = {
                "predicted": float(optimum.value),
                "confirmed": float("nan"),
                "confirmed_std_W": float("nan"),
                "ratio_to_nominal": None,
                "simulated": False,
            }
            continue
        run_outputs, heat[sense] = found
        value = metric_value(run_outputs, metric)
        confirmed[sense] = {
            "predicted": float(optimum.value),
            "confirmed": value,
            "confirmed_std_W": float(np.sqrt(value)),
            "ratio_to_nominal": value / nominal_metric,
            "building_std_W": run_outputs["unoccupied_std"],
        }
    log(
        "confirmation of the minimum and maximum with the full model: "
        + (
            "done"
            if not unconfirmed
            else f"not simulated in a re-analysis ({', '.join(unconfirmed)})"
        )
    )
    if unconfirmed:
        notes.append(
            "Re-analysis without simulation: the meta-model's "
            + " and ".join(f"{s}imum" for s in unconfirmed)
            + " of this analysis differ from the runs in the store and are not confirmed with "
            "the full model (their values are the meta-model's); the calibrated model is the "
            "best confirmed one. Run thermocal calibrate with --resume to confirm them."
        )
    confirmed["nominal"] = {
        "confirmed": nominal_metric,
        "confirmed_std_W": float(np.sqrt(nominal_metric)),
        "building_std_W": nominal_outputs["unoccupied_std"],
    }
    timings["confirmation"] = time.perf_counter() - t0
    posterior = series_model = None
    if series is not None:
        t0 = time.perf_counter()
        posterior, series_model = _posterior_or_note(
            surrogate, kind, X, y, series, space, critical, campaign, notes, segments
        )
        timings["posterior"] = time.perf_counter() - t0
        if posterior is not None:
            for line in posterior.sentences():
                log(line)
    # the calibrated model: the best confirmed candidate among the reduced meta-model's minimum,
    # the joint posterior's median, the campaign's best sample (a meta-model fitted on few
    # samples can miss) and the trust-region refinement from the best of them
    # with ``optimisation.calibrate: determined`` (the default) the calibrated model changes
    # only the parameters the posterior says the data determine; the others stay nominal
    determined = None
    if posterior is not None and campaign.optimisation.calibrate == "determined":
        determined = [n for n in space.names if n in posterior.determined]
        if len(determined) < space.dimension:
            notes.append(
                f"Calibrated parameters: only the {len(determined)} the data determine"
                + (f" ({', '.join(determined)})" if determined else "")
                + "; the others stay nominal (optimisation.calibrate: all changes every one)."
            )
    movable = list(space.names) if determined is None else determined
    candidates = {}
    moves_only_movable = set(critical) <= set(movable)
    if "min" not in unconfirmed and moves_only_movable:
        candidates["meta-model minimum"] = (
            confirmed["min"]["confirmed"],
            optimisation.parameters("min"),
        )
    elif determined is not None and [c for c in critical if c in determined]:
        # the reduced meta-model's minimum over the determined critical parameters only
        restricted = optimise_reduced(
            X,
            y,
            space,
            [c for c in critical if c in determined],
            surrogate=reduced_surrogate(kind, m, series, space, campaign.sampling.seed, segments),
            starts=campaign.optimisation.starts,
            seed=campaign.optimisation.seed,
            surrogate_options=reduced_options(kind, m),
        )
        values = restricted.parameters("min")
        found = runs.get(values, heat=False)
        if found is not None:
            value = metric_value(found[0], metric)
            candidates["meta-model minimum of the determined parameters"] = (value, values)
            confirmed["min_determined"] = {
                "predicted": float(restricted.minimum.value),
                "confirmed": value,
            }
    # never return a building worse than the one the user gave
    candidates["nominal building (no change)"] = (nominal_metric, space.nominal_dict())
    if posterior is not None:
        # the joint posterior's median (all varied parameters at once, or the determined
        # ones), confirmed with the model
        median = {
            **space.nominal_dict(),
            **{n: v for n, v in posterior.summary["median"].items() if n in movable},
        }
        found = runs.get(median, heat=False)
        if found is not None:
            candidates["posterior median"] = (metric_value(found[0], metric), median)
            confirmed["posterior_median"] = {"confirmed": candidates["posterior median"][0]}
    best = int(np.argmin(y))
    if y[best] < min(c[0] for c in candidates.values()):
        if determined is None:
            candidates[f"campaign sample {int(X.index[best])}"] = (
                float(y[best]),
                {**space.nominal_dict(), **X.iloc[best].to_dict()},
            )
        else:
            notes.append(
                f"The best campaign sample ({int(X.index[best])}, "
                f"{np.sqrt(y[best]) / 1000:.2f} kW) changes parameters the data do not "
                "determine; it is not used as the calibrated model."
            )
    refinement = []
    if campaign.optimisation.refine > 0:
        t1 = time.perf_counter()
        start_name = min(candidates, key=lambda k: candidates[k][0])
        refined, refinement = refine_minimum(
            runs,
            space,
            X,
            y,
            series,
            kind,
            candidates[start_name],
            steps=campaign.optimisation.refine,
            seed=campaign.optimisation.seed,
            log=log,
            metric=metric,
            segments=segments,
            movable=movable,
        )
        if runs.evaluator is None and len(refinement) < campaign.optimisation.refine and movable:
            notes.append(
                f"Re-analysis without simulation: the trust-region refinement stopped after "
                f"{len(refinement)} of {campaign.optimisation.refine} steps (the next candidate "
                "is not in the store)."
            )
        if refined[0] < candidates[start_name][0]:
            candidates[f"trust-region refinement ({len(refinement)} runs)"] = refined
        timings["refinement"] = time.perf_counter() - t1
    confirmed["refinement"] = refinement
    calibrated_source = min(candidates, key=lambda k: candidates[k][0])
    calibrated_metric, calibrated_values = candidates[calibrated_source]
    if calibrated_source.startswith("nominal"):
        notes.append(
            "No candidate was confirmed better than the nominal building "
            f"({np.sqrt(calibrated_metric) / 1000:.2f} kW): the calibrated building is the "
            "nominal one. The metric cannot tell the parameters apart on these data; more "
            "samples, a narrower parameter selection or another period may."
        )
    if calibrated_source.startswith("campaign sample"):
        notes.append(
            f"The meta-model's minima were confirmed worse than the best simulated sample "
            f"({np.sqrt(calibrated_metric) / 1000:.2f} kW): the calibrated building takes "
            "that sample's parameters. More samples give a better meta-model."
        )
    confirmed["calibrated"] = {
        "source": calibrated_source,
        "confirmed": float(calibrated_metric),
        "confirmed_std_W": float(np.sqrt(calibrated_metric)),
    }
    flags = calibration_flags(
        space, calibrated_values, calibrated_metric, posterior, series_model, inputs.truth
    )
    notes.extend(flag["text"] for flag in flags)
    confirmed["flags"] = flags
    floor = model_error_floor(space, posterior, series_model)
    if floor is not None:
        confirmed["model_error_floor"] = floor
    confirmed["calibrated_parameters"] = movable
    validation = None
    if campaign.validation is not None:
        t0 = time.perf_counter()
        validation = _validate(campaign, calibrated_values, runs, metric)
        timings["validation"] = time.perf_counter() - t0
    comparison = None
    if inputs.truth is not None:
        perturbed = [
            n for n in inputs.truth.get("parameters", {}) if n in space.names and n not in critical
        ]
        comparison = truth_comparison(
            list(critical) + perturbed, space, inputs.truth, calibrated_values, critical
        )
        if inputs.true_loads is not None:
            confirmed["guideline14_vs_true_loads"] = _guideline14(heat, inputs.true_loads)
    calibrated = inputs.building.with_parameters(
        {name: calibrated_values[name] for name in space.names}
    )
    grid = info.get("weather")
    if grid:
        index = pd.date_range(
            pd.Timestamp(grid["start"]),
            periods=len(grid["temp_air"]),
            freq=pd.Timedelta(seconds=grid["step_s"]),
        )
        weather = pd.DataFrame({"temp_air": grid["temp_air"], "ghi": grid["ghi"]}, index=index)
    else:
        weather = pd.DataFrame({"temp_air": [], "ghi": []})
    return CalibrationResult(
        space=space,
        samples=sample_set,
        store_frame=frame,
        summary=summary,
        surrogate=surrogate,
        ranking=ranking,
        sobol=sobol,
        critical=critical,
        optimisation=optimisation,
        nominal_metric=nominal_metric,
        confirmed=confirmed,
        heat=heat,
        weather=weather,
        validation=validation,
        morris=screening,
        truth_comparison=comparison,
        calibrated_building=calibrated,
        timings=timings,
        notes=notes,
        campaign_path=str(campaign.path),
        posterior=posterior,
        occupancy=occupancy,
        metric=metric,
        runs={"simulated": runs.simulated, "from_store": runs.reused},
    )


def reanalyse(campaign, store_path, *, log=print) -> CalibrationResult:
    """Analyse a stored campaign again without simulating anything.

    Another metric (``metric``), meta-model (``metamodel``), reduction (``top_k``), optimiser or
    posterior settings re-use the campaign's samples as they are in the store. Model runs of
    the earlier analysis (nominal, confirmations, posterior median, refinement, validation)
    are read from the store when this analysis asks for the same parameters; the others are
    not simulated (said in the notes): with nothing changed the result equals the original.

    Parameters
    ----------
    campaign : CampaignFile
        The campaign file; its building, inputs, parameters and sampling must be those of the
        store (a mismatch is named); its analysis sections may differ.
    store_path : path
        The campaign's store (``OUT/campaign.sqlite`` of thermocal calibrate).
    log : callable

    Returns
    -------
    CalibrationResult
    """
    from thermocal.calibration.runner import CampaignSummary
    from thermocal.calibration.sampling import sample
    from thermocal.calibration.store import CampaignStore

    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    inputs = analysis_inputs(campaign)
    space = campaign_space(campaign, inputs.building)
    timings["setup"] = time.perf_counter() - t0
    path = Path(store_path)
    with _store_errors(path), CampaignStore.existing(path) as store:
        stored = store.definition()
        check_same_campaign(campaign, space, stored, path)
        n = int(stored["sampler"]["samples"])
        sample_set = sample(space, n, campaign.sampling.method, seed=campaign.sampling.seed)
        done = store.count(failed=False)
        log(
            f"re-analysis of {path}: {done} samples of {space.dimension} parameters, metric "
            f"{campaign.metric}, meta-model {campaign.metamodel.kind}; nothing is simulated"
        )
        summary = CampaignSummary(
            total=n,
            already_done=store.count(),
            evaluated=0,
            failed=0,
            wall_time_s=0.0,
            backend="store (re-analysis)",
        )
        notes: list[str] = []
        if done + store.count(failed=True) < n:
            notes.append(
                f"The store holds {done} of the campaign's {n} samples (interrupted "
                "campaign); the re-analysis uses those."
            )
        return analyse(
            campaign,
            inputs,
            space,
            sample_set,
            summary,
            store,
            RunCache(store),
            timings=timings,
            notes=notes,
            log=log,
            morris=lambda: _stored_morris(campaign, space, path, notes),
        )


def analysis_inputs(campaign) -> CampaignInputs:
    """What a re-analysis needs of the inputs: the building (and the demo's truth)."""
    if campaign.is_demo:
        return load_inputs(campaign)
    from thermocal.multizone.files import load_building

    building = load_building(campaign.building_path)
    return CampaignInputs(building, pd.DataFrame(), {}, pd.DataFrame(), None, None, None)


def check_same_campaign(campaign, space, stored: dict, path) -> None:
    """Refuse a re-analysis of a store written for other inputs, parameters or sampling."""
    from thermocal.calibration.store import _definition_differences

    settings = dict(stored.get("problem") or {})
    current = {
        "space": space.to_dict(),
        "sampler": {"method": campaign.sampling.method, "seed": campaign.sampling.seed},
        "problem": {k: v for k, v in campaign.problem_settings().items() if k in settings},
    }
    before = {
        "space": stored.get("space"),
        "sampler": {k: v for k, v in (stored.get("sampler") or {}).items() if k != "samples"},
        "problem": {k: settings[k] for k in current["problem"]},
    }
    diffs = _definition_differences(
        json.loads(json.dumps(before, default=str)), json.loads(json.dumps(current, default=str))
    )
    if diffs:
        raise ThermocalInputError(
            f"store {path} holds another campaign than {campaign.path}: "
            + "; ".join(diffs[:8])
            + ". A re-analysis may change the metric, meta-model, optimisation and posterior "
            "settings, not the inputs, parameters or sampling (run thermocal calibrate for those)"
        )


def _stored_morris(campaign, space, store_path, notes):
    """The Morris screening from its store, when all its runs are there (else None, noted)."""
    from thermocal.calibration.sensitivity import morris_analyze, morris_design
    from thermocal.calibration.store import CampaignStore

    m = campaign.morris
    lower, upper = np.asarray(space.lower, float), np.asarray(space.upper, float)
    design = morris_design(
        list(space.names), lower, upper, trajectories=m.trajectories, levels=m.levels, seed=m.seed
    )
    path = Path(store_path).with_name(Path(store_path).stem + "_morris.sqlite")
    outputs = None
    if path.is_file():
        with CampaignStore.existing(path) as store:
            outputs = store.outputs(successful=False)[METRIC].reindex(design.index)
    if outputs is None or outputs.isna().any():
        notes.append(
            "Morris screening not re-analysed: its runs are not all in its store "
            f"({path.name}); thermocal calibrate --resume runs them."
        )
        return None
    return morris_analyze(design, outputs.to_numpy(), lower, upper, levels=m.levels, seed=m.seed)


def candidate_parameters(building, level: str = "material") -> dict[str, float]:
    """The parameters a campaign may vary, by name, at the chosen level.

    Parameters
    ----------
    building : thermocal.multizone.Building
    level : {"material", "element"}
        ``"material"``: the material fields of :meth:`Building.parameters` (conductivity,
        density, specific heat, thickness of each material; the published method's choice).
        ``"element"``: what a building physicist names, per construction its thermal
        resistance [m2 K/W] and heat capacity [J/(m2 K)] with the layers scaled consistently
        (:mod:`thermocal.multizone.elements`); window U-value and SHGC and infiltration at both
        levels.

    Returns
    -------
    dict of str to float
        Nominal values [unit of each parameter].
    """
    from thermocal.multizone.elements import element_parameters

    params = building.parameters()
    if level == "material":
        return params
    if level != "element":
        raise ThermocalInputError(
            f"parameters.level must be 'material' or 'element', got {level!r}"
        )
    others = {k: v for k, v in params.items() if not k.startswith("material/")}
    return {**element_parameters(building), **others}


#: Largest campaign space whose joint posterior is sampled (else: the critical parameters).
POSTERIOR_MAX_PARAMETERS = 30


def _posterior_or_note(
    surrogate, kind, X, y, series, space, critical, campaign, notes, segments=None
):
    """Posterior of the critical parameters from the series meta-model, or a note why not."""
    from thermocal.calibration.posterior import calibration_posterior, emulator_variance

    model = surrogate
    if kind != "series":
        model = surrogate_for(
            "series", campaign.metamodel, series, space, campaign.sampling.seed, segments
        ).fit(X, y)
    # the joint posterior of every varied parameter (a parameter held at its nominal value
    # would make the others compensate for it); the critical ones only in large spaces
    names = list(space.names) if space.dimension <= POSTERIOR_MAX_PARAMETERS else list(critical)
    if len(names) < space.dimension:
        notes.append(
            f"The posterior covers the {len(names)} critical parameters (the others at their "
            f"nominal values): the space has more than {POSTERIOR_MAX_PARAMETERS} parameters."
        )
    idx = [space.index(n) for n in names]
    try:
        posterior = calibration_posterior(
            model,
            names,
            space.lower[idx],
            space.upper[idx],
            all_lower=space.lower,
            all_upper=space.upper,
            units=[space.units[i] for i in idx],
            seed=campaign.sampling.seed,
            emulator_error=emulator_variance(model, X, seed=campaign.sampling.seed),
            discrepancy=campaign.posterior.discrepancy,
        )
    except (ThermocalInputError, np.linalg.LinAlgError, ValueError) as exc:
        notes.append(f"No posterior of the calibrated parameters: {exc}")
        return None, model
    return posterior, model


#: a calibrated parameter within this share of its log-range of a sampling bound is "at" it
AT_BOUND = 0.02


def model_error_floor(space, posterior, series_model) -> float | None:
    """The lowest metric the model error allows: the 5 % quantile of the metric a model run
    would give over the posterior's draws [W^2]; None without a posterior.

    The series meta-model's prediction at each draw plus its out-of-fold bias (the mean of
    the simulated minus the predicted metric over the campaign's samples, each predicted by
    a fit that did not see it: the energy of the meta-model's own error, which a simulated
    metric holds and a prediction lacks). Without it the floor was too low by about that
    energy summed over the series, so more with the zone-group metric than with the building
    total (multifamily twin: 0.87x the true envelope's metric with ``groups``, 1.06x with
    ``building``), and a group calibration below the true envelope went unflagged.

    Parameters
    ----------
    space : ParameterSpace
    posterior : Posterior or None
    series_model : SeriesSurrogate or None
        Fitted on all the campaign's parameters.
    """
    if posterior is None or series_model is None or not len(posterior.samples):
        return None
    nominal = space.nominal_dict()
    draws = posterior.samples.iloc[:: max(1, len(posterior.samples) // 400)]
    frame = pd.DataFrame({n: np.full(len(draws), nominal[n]) for n in space.names})
    for n in draws.columns:
        frame[n] = draws[n].to_numpy()
    predicted = series_model.predict(frame[list(series_model.feature_names_in_)])
    return float(np.quantile(predicted, 0.05)) + float(getattr(series_model, "oof_bias_", 0.0))


def calibration_flags(space, values, metric, posterior, series_model, truth=None) -> list[dict]:
    """Warnings on a calibrated model: parameters at their bounds, a metric below the floor.

    * A parameter that ends within 2 % (of the logarithm of its range) of a sampling bound:
      either its range is too narrow or it absorbs an error of the model (the published
      method's failure mode: window U at its upper bound, SHGC at its lower one). Said with
      whether the posterior declares it determined and, with a known truth (the demo), whether
      the truth perturbed it at all.
    * A calibrated metric below what the model error allows (:func:`model_error_floor`: the
      5 % quantile of the metric a model run would give over the posterior's draws, the
      metric's spread that the noise and the model error leave): the calibration then fits
      the model's error, not the envelope.

    Parameters
    ----------
    space : ParameterSpace
    values : dict
        Calibrated parameters [unit of each].
    metric : float
        Its confirmed metric [W^2].
    posterior : Posterior or None
    series_model : SeriesSurrogate or None
        Fitted on all the campaign's parameters.
    truth : dict, optional
        The demo's ``truth.json``.

    Returns
    -------
    list of dict
        ``kind`` ("at bound" or "below model error"), ``text`` and the numbers.
    """
    flags = []
    nominal = space.nominal_dict()
    true = {n: row["true"] for n, row in (truth or {}).get("parameters", {}).items()}
    determined = set(posterior.determined) if posterior is not None else set()
    for i, name in enumerate(space.names):
        value = float(values[name])
        if np.isclose(value, nominal[name], rtol=1e-9):
            continue
        lo, hi = float(space.lower[i]), float(space.upper[i])
        span = np.log(hi / lo)
        for side, bound in (("lower", lo), ("upper", hi)):
            if abs(np.log(value / bound)) > AT_BOUND * span:
                continue
            why = (
                "the data determine it: its range may be too narrow"
                if name in determined
                else "the data do not determine it: it likely absorbs an error of the model"
            )
            if name in true or truth is not None:
                perturbed = not np.isclose(true.get(name, nominal[name]), nominal[name], rtol=1e-9)
                why += "; the truth " + ("perturbed" if perturbed else "did not perturb") + " it"
            flags.append(
                {
                    "kind": "at bound",
                    "parameter": name,
                    "side": side,
                    "value": value,
                    "bound": bound,
                    "determined": name in determined,
                    "text": f"{name} ends at its {side} sampling bound ({value:.4g} "
                    f"{space.units[i]}; nominal {nominal[name]:.4g}): {why}.",
                }
            )
    floor = model_error_floor(space, posterior, series_model)
    if floor is not None:
        if metric < floor:
            flags.append(
                {
                    "kind": "below model error",
                    "metric": float(metric),
                    "floor": floor,
                    "text": f"The calibrated metric ({np.sqrt(metric) / 1000:.3f} kW as a standard "
                    f"deviation) is below what the model error allows ({np.sqrt(floor) / 1000:.3f} "
                    "kW, the 5 % quantile of the metric over the posterior): the calibration fits "
                    "the model's error or the noise, not only the envelope; trust the posterior's "
                    "intervals more than the calibrated values.",
                }
            )
    return flags


def _sobol_or_note(surrogate, space, lower, upper, seed: int, kind: str, notes: list[str]):
    """Sobol indices of the meta-model; zeros and a note when it predicts a constant metric.

    A meta-model that found no influence of any parameter (e.g. a Gaussian process whose
    length scales all went to their upper bound on a few noisy samples) is a result, not an
    error: the campaign is kept and the report says so.
    """
    from thermocal.calibration.sensitivity import sobol_indices

    try:
        return sobol_indices(surrogate.predict, space.names, lower, upper, n=512, seed=seed)
    except ThermocalInputError as exc:
        if "constant over the bounds" not in str(exc):
            raise
    notes.append(
        f"The {kind.upper()} meta-model predicts the same metric everywhere in the parameter "
        f"space (cross-validated R2 {surrogate.cv_r2_:.2f}): it found no influence of any "
        "parameter, so its Sobol indices are zero and its optimum is the best sample. More "
        "samples or another meta-model kind may resolve the influences."
    )
    return pd.DataFrame(
        {"S1": 0.0, "S1_conf": np.nan, "ST": 0.0, "ST_conf": np.nan},
        index=pd.Index(list(space.names), name="parameter"),
    )


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


def _format_duration(seconds: float) -> str:
    seconds = max(0.0, float(seconds))
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def check_campaign_time(
    pending: int,
    seconds_per_sample: float,
    *,
    workers: int | None,
    scheduler=None,
    max_hours: float | None = 24.0,
    log=print,
) -> float:
    """Log the campaign's estimated duration; refuse one longer than ``max_hours``.

    Parameters
    ----------
    pending : int
        Samples still to evaluate [-].
    seconds_per_sample : float
        Measured time of one identification (the nominal run) [s].
    workers : int or None
        Local processes (None: all cores) [-].
    scheduler : optional
        A Dask scheduler: its workers are unknown, so the estimate is per worker and no limit
        applies.
    max_hours : float or None
        Limit [h]; None: none.
    log : callable

    Returns
    -------
    float
        The estimate [s].
    """
    if scheduler is not None:
        estimate = pending * seconds_per_sample
        log(
            f"estimate: {pending} samples x {seconds_per_sample:.1f} s = "
            f"{_format_duration(estimate)} of work, divided among the Dask workers"
        )
        return estimate
    n_workers = max(1, min(int(workers or os.cpu_count() or 1), max(pending, 1)))
    estimate = pending * seconds_per_sample / n_workers
    log(
        f"estimate: {pending} samples x {seconds_per_sample:.1f} s / {n_workers} worker(s) = "
        f"about {_format_duration(estimate)}"
    )
    if max_hours is not None and estimate > max_hours * 3600.0:
        raise ThermocalInputError(
            f"the campaign would take about {_format_duration(estimate)} ({pending} samples x "
            f"{seconds_per_sample:.1f} s per identification / {n_workers} worker(s)), more than "
            f"--max-hours {max_hours:g}; use fewer --samples, more --workers or a Dask "
            "--scheduler, or raise --max-hours (the campaign is resumable: --resume continues "
            "an interrupted one)"
        )
    return estimate


class ProgressLines:
    """``on_result`` callback that logs a progress line about every 5 % or every minute.

    For logs and CI, where a progress bar is invisible (it is drawn only on a terminal).
    """

    def __init__(self, pending: int, done: int, log, *, every_s: float = 60.0) -> None:
        self.pending, self.done, self.log = int(pending), int(done), log
        self.every = max(1, self.pending // 20)
        self.every_s = float(every_s)
        self.evaluated = self.failed = 0
        self.start = self.last = time.perf_counter()

    def __call__(self, result) -> None:
        self.evaluated += 1
        self.failed += result.error is not None
        now = time.perf_counter()
        if (
            self.evaluated % self.every
            and now - self.last < self.every_s
            and self.evaluated != self.pending
        ):
            return
        self.last = now
        elapsed = now - self.start
        left = elapsed / self.evaluated * (self.pending - self.evaluated)
        total = self.pending + self.done
        self.log(
            f"campaign: {self.done + self.evaluated}/{total} samples ({self.failed} failed), "
            f"{_format_duration(elapsed)} elapsed, about {_format_duration(left)} left"
        )


@contextlib.contextmanager
def _store_errors(path: Path):
    """SQLite's 'disk is full' / read-only errors of the store as one clear input error."""
    try:
        yield
    except sqlite3.OperationalError as exc:
        text = str(exc)
        if "full" in text:
            what = "the disk is full; free some space or choose another --out (or store)"
        elif "readonly" in text or "read-only" in text or "unable to open" in text:
            what = "it cannot be written (read-only folder or file); choose another --out"
        else:
            raise
        raise ThermocalInputError(
            f"store {path}: {what}; the samples recorded so far are kept, and --resume continues"
        ) from None


def refine_minimum(
    runs,
    space,
    X,
    y,
    series,
    kind,
    start,
    *,
    steps: int,
    seed: int,
    log=print,
    metric: str = "building",
    segments=None,
    movable=None,
):
    """Trust-region refinement of the minimum with the full model in the loop (beyond the paper).

    From the best confirmed point, each step fits the meta-model (the chosen kind, without
    cross-validation) on the campaign plus the points simulated so far, minimises it over all
    parameters within a box around the current best (in the logarithm of the parameters, half
    its width a quarter of the sampled range at first), simulates the candidate with the full
    model and the identification, and keeps it if it is better; the box grows by 1.5 after a
    success and halves after a failure. A meta-model fitted on few samples extrapolates badly
    to the corners of a 70-parameter box; the trust region keeps each step where it is
    informed, and every simulated point improves the next fit. The runs go through ``runs``
    (:class:`RunCache`): found in the store when run before; in a re-analysis the refinement
    stops at the first candidate that is not stored. Only the ``movable`` parameters (default
    all) change; the others keep the start's values.

    Returns
    -------
    best : (metric [W^2], parameters dict)
    history : list of dict
        One row per step: predicted and confirmed metric [W^2], accepted, box half-width.
    """
    from thermocal.calibration.optimise import optimise_box
    from thermocal.calibration.spatial import group_segments
    from thermocal.calibration.surrogate import SeriesSurrogate, make_surrogate

    names = list(space.names)
    lower = np.log(np.asarray(space.lower, float))
    upper = np.log(np.asarray(space.upper, float))
    best_metric, best_values = start
    best_z = np.log(np.array([best_values[n] for n in names], dtype=float))
    Xs, ys = X[names].to_numpy(dtype=float), np.asarray(y, dtype=float)
    Ss = None if series is None else np.asarray(series, dtype=float)
    radius = 0.25
    history = []
    moving = np.array([movable is None or n in movable for n in names])
    if not moving.any():
        return (float(best_metric), best_values), history
    for step in range(steps):
        frame = pd.DataFrame(Xs, columns=names)
        if kind == "series" and Ss is not None:
            model = SeriesSurrogate(
                series=Ss, nominal=space.nominal_dict(), cv_folds=0, segments=segments
            )
        else:
            model = make_surrogate(kind if kind != "series" else "gp", cv_folds=0, seed=seed)
        model.fit(frame, ys)
        half = radius * (upper - lower)
        lo = np.maximum(lower, best_z - half)[moving]
        hi = np.minimum(upper, best_z + half)[moving]
        hi = np.maximum(hi, lo + 1e-9)

        def predict(Zm, model=model, fixed=best_z):
            Zm = np.atleast_2d(Zm)
            Z = np.repeat(fixed[None, :], len(Zm), axis=0)
            Z[:, moving] = Zm
            return model.predict(np.exp(Z))

        reduced = optimise_box(
            predict,
            lo,
            hi,
            sense="min",
            starts=2,
            initial=[best_z[moving]],
            seed=seed + step,
            maxiter=100,
        )
        z = best_z.copy()
        z[moving] = reduced.x
        values = {**space.nominal_dict(), **dict(zip(names, np.exp(z), strict=True))}
        found = runs.get(values, heat=False)
        if found is None:  # a re-analysis: not simulated
            break
        metrics = found[0]
        value = metric_value(metrics, metric)
        accepted = value < best_metric
        history.append(
            {
                "step": step + 1,
                "predicted": float(reduced.value),
                "confirmed": float(value),
                "accepted": bool(accepted),
                "radius": radius,
            }
        )
        log(
            f"refinement {step + 1}/{steps}: unoccupied std {np.sqrt(value) / 1000:.2f} kW "
            f"({'better' if accepted else 'not better'}; best "
            f"{np.sqrt(min(value, best_metric)) / 1000:.2f} kW)"
        )
        Xs = np.vstack([Xs, np.exp(z)])
        ys = np.append(ys, value)
        if Ss is not None:
            columns = (
                [f"series/{i:05d}" for i in range(Ss.shape[1])]
                if segments is None
                else group_segments(list(metrics))[0]
            )
            Ss = np.vstack([Ss, [metrics.get(c, np.nan) for c in columns]])
        if accepted:
            best_metric, best_values, best_z = value, values, z
            radius = min(0.5, radius * 1.5)
        else:
            radius *= 0.5
    return (float(best_metric), best_values), history


def _morris(campaign, problem, space, store_path, workers, scheduler, progress, log):
    """Morris screening on the model itself, run like the campaign into its own store."""
    from thermocal.calibration.runner import run_campaign
    from thermocal.calibration.sensitivity import morris_analyze, morris_design
    from thermocal.calibration.store import CampaignStore

    m = campaign.morris
    lower, upper = np.asarray(space.lower, float), np.asarray(space.upper, float)
    design = morris_design(
        list(space.names),
        lower,
        upper,
        trajectories=m.trajectories,
        levels=m.levels,
        seed=m.seed,
    )
    log(f"Morris screening: {len(design)} runs of the model")
    path = Path(store_path).with_name(Path(store_path).stem + "_morris.sqlite")
    definition = {
        "morris": m.model_dump(),
        "problem": problem.fingerprint(),
        "space": space.to_dict(),
    }
    with CampaignStore.open(path, definition=definition, resume=True) as store:
        run_campaign(
            problem,
            design,
            store,
            workers=workers,
            scheduler=scheduler,
            progress=progress,
            description="Morris screening",
        )
        outputs = store.outputs(successful=False)[METRIC].reindex(design.index)
    return morris_analyze(design, outputs.to_numpy(), lower, upper, levels=m.levels, seed=m.seed)


#: above this many samples, ``kind="auto"`` does not try the Gaussian process (its fit grows
#: as the cube of the sample count, with one length scale per parameter)
AUTO_GP_MAX_SAMPLES = 400


def surrogate_for(kind: str, metamodel, series, space, seed: int, segments=None):
    """An unfitted meta-model of ``kind`` (a name, or the series model with its data)."""
    if kind != "series":
        return kind
    from thermocal.calibration.surrogate import SeriesSurrogate

    return SeriesSurrogate(
        series=series,
        nominal=space.nominal_dict(),
        cv_folds=metamodel.cv_folds,
        seed=seed,
        segments=segments,
    )


def reduced_surrogate(kind: str, metamodel, series, space, seed: int, segments=None):
    """The unfitted reduced meta-model (no out-of-fold scores: only its optimum is used)."""
    model = surrogate_for(kind, metamodel, series, space, seed, segments)
    if not isinstance(model, str):
        model.cv_folds = 0
    return model


def reduced_options(kind: str, metamodel) -> dict | None:
    """Options of the reduced SVR or GP: the SVR's grid search keeps the campaign's folds;
    the GP skips the out-of-fold scores (five more fits, unused)."""
    if kind == "series":
        return None
    return {
        "cv_folds": metamodel.cv_folds if kind == "svr" else 0,
        "log_target": metamodel.log_target,
    }


def choose_surrogate(
    X,
    y,
    kind: str,
    *,
    cv_folds: int,
    log_target: bool,
    seed: int,
    series=None,
    nominal=None,
    segments=None,
):
    """Fit the meta-model; with ``kind="auto"`` the SVR, the GP and the series model, keeping
    the best.

    The paper's SVR uses one RBF length for all (scaled) parameters; when only a few of many
    parameters matter, the Gaussian process with one length scale per parameter (automatic
    relevance determination) usually predicts far better from the same samples (e.g.
    cross-validated R2 0.998 against 0.03 on a 9-parameter, 48-sample campaign of the test
    suite). With each sample's unoccupied heat series (``series``), the series model
    (:class:`~thermocal.calibration.surrogate.SeriesSurrogate`) uses the metric's structure.
    "auto" fits all three (the GP up to :data:`AUTO_GP_MAX_SAMPLES` samples, the series model
    when series are given) and keeps the highest cross-validated R2.

    Returns
    -------
    surrogate : fitted meta-model
    kind : {"svr", "gp"}
    scores : dict of kind -> cross-validated R2 [-]
    """
    from thermocal.calibration.surrogate import SeriesSurrogate, make_surrogate

    kinds = [kind] if kind != "auto" else ["svr", "gp", "series"]
    if kind == "auto" and len(y) > AUTO_GP_MAX_SAMPLES:
        kinds.remove("gp")
    if series is None and "series" in kinds:
        if kind == "series":
            raise ThermocalInputError("the series meta-model needs the samples' heat series")
        kinds.remove("series")
    fitted = {}
    for k in kinds:
        if k == "series":
            model = SeriesSurrogate(
                series=series, nominal=nominal, cv_folds=cv_folds, seed=seed, segments=segments
            )
        else:
            model = make_surrogate(k, cv_folds=cv_folds, log_target=log_target, seed=seed)
        fitted[k] = model.fit(X, y)
    scores = {k: float(model.cv_r2_) for k, model in fitted.items()}
    best = max(scores, key=scores.get)
    return fitted[best], best, scores


def validation_problem(campaign, inputs: CampaignInputs):
    """The identification problem of the validation period, built (and so checked: weather,
    sensor coverage) before the campaign rather than after it; None without a validation."""
    if campaign.validation is None:
        return None
    start = _localise(campaign.validation.start, inputs.weather.index[0])
    end = _localise(campaign.validation.end, inputs.weather.index[0])
    try:
        problem, _ = build_problem(campaign, inputs, start=start, end=end)
    except ThermocalInputError as exc:
        raise ThermocalInputError(
            f"{campaign.path}: validation period [{start}, {end}): {exc} (checked before the "
            "campaign; correct 'validation:' or remove it)"
        ) from None
    return problem


def _validate(campaign, calibrated_values: dict, runs, metric: str) -> dict | None:
    """Nominal vs calibrated building's metric on the validation period (not seen by the
    calibration); None when its runs are not stored in a re-analysis.

    Parameters
    ----------
    campaign : CampaignFile
    calibrated_values : dict
        The calibrated building's parameters (the chosen candidate) [unit of each].
    runs : RunCache
    metric : str
        The campaign's metric (``building`` or ``groups``); the building total is reported
        too.

    Returns
    -------
    dict or None
        ``nominal`` and ``calibrated`` in the campaign's metric [W^2], their ``ratio``,
        ``keeps_lower_variance``, the building-total metrics and the period.
    """
    nominal = runs.get({}, tag="validation", heat=False)
    calibrated = runs.get(dict(calibrated_values), tag="validation", heat=False)
    if nominal is None or calibrated is None:
        return None
    out = {"start": str(campaign.validation.start), "end": str(campaign.validation.end)}
    try:
        values = [metric_value(run[0], metric) for run in (nominal, calibrated)]
    except (KeyError, ValueError):  # a store written before the group outputs were stored
        return None
    out.update(
        metric=metric,
        nominal=values[0],
        calibrated=values[1],
        ratio=values[1] / values[0] if values[0] > 0 else None,
        keeps_lower_variance=bool(values[1] < values[0]),
        building_nominal=float(nominal[0][METRIC]),
        building_calibrated=float(calibrated[0][METRIC]),
    )
    return out


def _guideline14(heat: dict, true_loads: pd.DataFrame) -> dict:
    """ASHRAE Guideline 14 statistics of the building Q_ID against the demo's true loads."""
    if "time" in true_loads.columns:
        true_loads = true_loads.set_index("time")
    column = "total" if "total" in true_loads else true_loads.columns[-1]
    truth = true_loads[column].reindex(heat["nominal"].index)
    out = {}
    for case, series in heat.items():
        out[case] = guideline14(series.to_numpy(), truth.to_numpy())
    return out


def evaluator_for(problem: IdentificationProblem) -> IdentificationProblem:
    """The runner's evaluator: the problem itself (picklable, built once per worker)."""
    return problem
