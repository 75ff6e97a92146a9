"""The envelope-calibration workflow: campaign file -> campaign -> meta-model -> optimum.

:func:`calibrate` is the orchestrator, a sequence of named stages each in its own module: the
inputs and identification problems (:mod:`~thermocal.calibration.inputs`), the guards of the
store and of the campaign's duration (:mod:`~thermocal.calibration.guards`), the nominal run and
the quiet hours of the metric, the sampling and the campaign (local process pool or Dask) into the
durable store, then the analysis (:func:`thermocal.calibration.analysis.analyse`: meta-model,
ranking, reduced optima confirmed with the full model, posterior, calibrated model, flags,
validation) and :meth:`CalibrationResult.to_files`. :func:`reanalyse` runs the same analysis on a
stored campaign without simulating.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from thermocal.calibration.analysis import (
    POSTERIOR_MAX_PARAMETERS,
    analyse,
    measure_in_situ,
    minimum_samples,
)
from thermocal.calibration.flags import AT_BOUND, calibration_flags, model_error_floor
from thermocal.calibration.guards import (
    ProgressLines,
    _seconds,
    check_campaign_time,
    check_same_campaign,
    refuse_filled_store,
    store_errors,
)
from thermocal.calibration.inputs import (
    IDENTIFICATION_KEYS,
    CampaignInputs,
    analysis_inputs,
    build_problem,
    campaign_schedule,
    check_campaign_period,
    check_unoccupied_steps,
    choose_quiet_hours,
    evaluator_for,
    identification_options,
    load_inputs,
    problem_settings,
    validation_problem,
)
from thermocal.calibration.metamodels import (
    AUTO_GP_MAX_SAMPLES,
    choose_surrogate,
    reduced_options,
    reduced_surrogate,
    surrogate_for,
)
from thermocal.calibration.metric import METRIC_NAMES, metric_data, metric_value
from thermocal.calibration.refine import refine_minimum
from thermocal.calibration.result import CalibrationResult, truth_comparison
from thermocal.errors import ThermocalInputError
from thermocal.identification.problem import METRIC

#: the workflow's own names and, for existing imports, those of the stages it calls (each
#: defined in its own module of :mod:`thermocal.calibration`)
__all__ = [
    "calibrate",
    "analyse",
    "reanalyse",
    "campaign_space",
    "RunCache",
    "candidate_parameters",
    "IDENTIFICATION_KEYS",
    "CampaignInputs",
    "load_inputs",
    "identification_options",
    "campaign_schedule",
    "choose_quiet_hours",
    "build_problem",
    "analysis_inputs",
    "validation_problem",
    "evaluator_for",
    "problem_settings",
    "CalibrationResult",
    "truth_comparison",
    "model_error_floor",
    "calibration_flags",
    "refuse_filled_store",
    "check_campaign_time",
    "ProgressLines",
    "check_same_campaign",
    "surrogate_for",
    "reduced_surrogate",
    "reduced_options",
    "choose_surrogate",
    "refine_minimum",
    "METRIC_NAMES",
    "metric_data",
    "metric_value",
    "AT_BOUND",
    "AUTO_GP_MAX_SAMPLES",
    "POSTERIOR_MAX_PARAMETERS",
]


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
    check_sample_count(campaign, n, from_option=samples is not None)
    path = Path(store_path or campaign.store or "campaign.sqlite")
    refuse_filled_store(path, resume, n)
    t0 = time.perf_counter()
    inputs = load_inputs(campaign)
    if inputs.period_from_log:
        log(
            f"period: [{inputs.start}, {inputs.end}), the span of {inputs.log_name} (the "
            "campaign file gives no period:; set period: {start: ..., end: ...} to choose "
            "another)"
        )
    check_campaign_period(campaign, inputs)
    notes.extend(inputs.notes)  # identification.site: weather (warned when loading)
    space = campaign_space(campaign, inputs.building)
    notes.extend(left_out_notes(space, log))
    measure_in_situ(campaign, space)  # a bad log stops here, before any simulation
    check_uncertain_inputs(campaign, inputs.building, space)  # as does a bad pattern
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
    check_unoccupied_steps(campaign, problem, "calibration period")
    if later is not None:  # the validation period's metric uses the same hours
        later.schedule = problem.schedule
        check_unoccupied_steps(campaign, later, "validation period")
    nominal_outputs = evaluator.outputs(nominal_run.heat)
    timings["nominal_run"] = time.perf_counter() - t0
    log(
        f"nominal model: unoccupied std of building Q_ID "
        f"{nominal_outputs['unoccupied_std'] / 1000:.3f} kW "
        f"({_seconds(timings['nominal_run'])} s per identification)"
    )
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
        store_errors(path),
        CampaignStore.open(
            path,
            definition=definition,
            campaign_text=campaign.text,
            resume=resume,
            expected=sample_set.values,
        ) as store,
    ):
        store.record_run({}, nominal_outputs, nominal_run.heat.sum(axis=1))
        if inputs.notes:  # for a re-analysis's notes
            store.set_info("input_notes", {"notes": list(inputs.notes)})
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
        step_check = _step_check(campaign, inputs, problem, sample_set.values, nominal_outputs,
                                 store, resume, timings, log)  # fmt: skip
        clock_check = _clock_check(campaign, inputs, problem, store, resume, timings, log)
        for check in (step_check, clock_check):
            if check is not None:
                if check["passed"]:  # a failed check is a warning (its own category)
                    log(check["note"])
                notes.append(check["note"])
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
                workers=workers,
                scheduler=scheduler,
            ),
            timings=timings,
            notes=notes,
            log=log,
            morris=morris,
        )


def check_sample_count(campaign, n: int, *, from_option: bool) -> None:
    """Refuse a campaign of fewer samples than its meta-model needs, before any simulation.

    Parameters
    ----------
    campaign : CampaignFile
    n : int
        The campaign's samples [-].
    from_option : bool
        ``n`` is the ``--samples`` option's (else the file's ``sampling.samples``).

    Raises
    ------
    ThermocalInputError
        Naming where ``n`` comes from and, when they set the minimum, the meta-model's
        cross-validation folds (``metamodel.cv_folds``).
    """
    minimum = minimum_samples(campaign)
    if n >= minimum:
        return
    given = (
        f"--samples {n}"
        if from_option
        else f"{campaign.path or 'the campaign file'}: sampling.samples is {n}"
    )
    folds = campaign.metamodel.cv_folds
    if minimum == folds + 2:  # the cross-validation's folds set the minimum
        why = (
            f"the meta-model's {folds}-fold cross-validation (metamodel.cv_folds: {folds}) "
            f"needs at least {minimum} successful samples"
        )
        remedy = f"give at least {minimum} samples or lower metamodel.cv_folds"
    else:
        why = (
            f"a meta-model needs at least {minimum} successful samples (a few dozen to "
            "determine anything)"
        )
        remedy = f"give at least {minimum} samples"
    raise ThermocalInputError(f"{given}: {why}; {remedy}; nothing was simulated")


def _step_check(campaign, inputs, problem, design, nominal_outputs, store, resume, timings, log):
    """The campaign step's check (:func:`thermocal.calibration.stepcheck.check_campaign_step`),
    kept in the store (:func:`_stored_check`). Returns the check's result or None (the campaign
    runs at the log's step)."""
    from thermocal.calibration import stepcheck

    return _stored_check(
        "step_check", "campaign step", store, resume, timings, log,
        run=lambda: stepcheck.check_campaign_step(campaign, inputs, problem, design, log,
                                                  nominal_outputs),
        warn=lambda result: stepcheck.warn_if_failed(result, campaign.path),
    )  # fmt: skip


def _clock_check(campaign, inputs, problem, store, resume, timings, log):
    """The sensor log's clock against the model's
    (:func:`thermocal.calibration.clockcheck.check_log_clock`), kept in the store. Returns the
    check's result (``passed`` None when it could not be made: its note says why)."""
    from thermocal.calibration import clockcheck
    from thermocal.calibration.spatial import campaign_evaluator

    return _stored_check(
        "log_clock", "sensor log's clock", store, resume, timings, log,
        run=lambda: clockcheck.check_log_clock(
            campaign, inputs, problem, lambda p: campaign_evaluator(p, inputs.building), log
        ),
        warn=lambda result: clockcheck.warn_if_clock_off(result, campaign.path),
    )  # fmt: skip


def _stored_check(name, what, store, resume, timings, log, *, run, warn):
    """A check made once per campaign before its samples, its result kept in the store under
    ``name``: a resumed campaign (the same definition: step, design and problem) takes the
    first run's instead of identifying models again, and warns again (``warn(result)``) when
    it failed. Returns ``run()``'s result (or the stored one); None when nothing was checked."""
    stored = store.info(name) if resume else None
    if stored is not None:
        log(f"{what}: checked when this campaign began (kept in its store)")
        warn(stored)
        return stored
    t0 = time.perf_counter()
    result = run()
    if result is not None:
        timings[name] = time.perf_counter() - t0
        store.set_info(name, result)
    return result


def check_uncertain_inputs(campaign, building, space) -> None:
    """Refuse a ``posterior.uncertain`` entry that names nothing, or a calibrated parameter,
    before any simulation (:func:`thermocal.calibration.uncertain.uncertain_inputs`)."""
    from thermocal.calibration.uncertain import model_refusal, nominal_values, uncertain_inputs

    where = f"{campaign.path or 'campaign file'}: posterior"
    uncertain_inputs(campaign.posterior.uncertain, nominal_values(building), space.names,
                     where=where, invalid=model_refusal(building))  # fmt: skip


def campaign_space(campaign, building):
    """The campaign's parameter space on ``building`` (its ``parameters`` section)."""
    from thermocal.calibration.space import ParameterSpace
    from thermocal.multizone.elements import element_limits, unused_parameters, window_limits

    p = campaign.parameters
    limits = window_limits(building)
    if p.level == "element":
        limits.update(element_limits(building))
    return ParameterSpace.from_parameters(
        candidate_parameters(building, p.level, infiltration=p.infiltration),
        include=p.include,
        exclude=p.exclude,
        default_range=p.default_range,
        ranges=p.ranges,
        unused=unused_parameters(building),
        limits=limits,
    )


def left_out_notes(space, log) -> list[str]:
    """The report's note (and the log's line) on the selected parameters the space left out."""
    if not space.skipped:
        return []
    left_out = "; ".join(f"{name} ({why})" for name, why in space.skipped.items())
    log(f"left out of the campaign: {left_out}")
    return [f"Parameters left out of the campaign: {left_out}."]


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
    reused : int
        Runs read from the store [-].
    workers, scheduler : int or None, str or object or None
        How a batch of runs (the zoom campaign) is simulated: local processes (None: all
        cores) or a Dask scheduler, as the campaign.
    """

    store: Any
    evaluator: Any = None
    validation: Any = None
    simulated: int = 0
    reused: int = 0
    workers: int | None = None
    scheduler: Any = None

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
    measure_in_situ(campaign, space)
    check_uncertain_inputs(campaign, inputs.building, space)
    timings["setup"] = time.perf_counter() - t0
    path = Path(store_path)
    with store_errors(path), CampaignStore.existing(path) as store:
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
        notes = list((store.info("input_notes") or {}).get("notes", []))  # the site's, ...
        notes += left_out_notes(space, log)
        # the checks made before the campaign's samples (their warnings were given then)
        notes.extend(
            check["note"]
            for check in (store.info("step_check"), store.info("log_clock"))
            if check is not None
        )
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


def candidate_parameters(
    building, level: str = "material", *, infiltration: str = "per_zone"
) -> dict[str, float]:
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
    infiltration : {"per_zone", "building"}
        ``"per_zone"``: each zone's air change rate ``zone/<name>/infiltration_ach`` [1/h] (one
        ``infiltration/<group>/ach`` per group of zones sharing an infiltration object).
        ``"building"``: one factor on every zone's rate, ``infiltration/building/factor``
        (nominal 1) [-], for a building whose file gives each zone its own infiltration
        object (e.g. a flow per exterior-wall area): one parameter the campaign can
        determine instead of one per zone that it cannot.

    Returns
    -------
    dict of str to float
        Nominal values [unit of each parameter].
    """
    from thermocal.multizone.elements import element_parameters
    from thermocal.multizone.parameters import INFILTRATION_FACTOR

    if infiltration not in ("per_zone", "building"):
        raise ThermocalInputError(
            f"parameters.infiltration must be 'per_zone' or 'building', got {infiltration!r}"
        )
    params = building.parameters()
    if infiltration == "building":
        params = {
            k: v
            for k, v in params.items()
            if not (k.endswith("/infiltration_ach") or k.startswith("infiltration/"))
        }
        if any(z.infiltration_ach > 0 for z in building.zones.values()):
            # 1 on a building as read; a calibrated building carries the factor it was given
            params[INFILTRATION_FACTOR] = float(getattr(building, "infiltration_factor", 1.0))
    if level == "material":
        return params
    if level != "element":
        raise ThermocalInputError(
            f"parameters.level must be 'material' or 'element', got {level!r}"
        )
    others = {k: v for k, v in params.items() if not k.startswith("material/")}
    return {**element_parameters(building), **others}


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
