"""The analysis of a stored calibration campaign, stage by stage: the samples' metric, the
meta-model with its ranking and reduced optima, the confirmation of the optima with the full
model, the posterior, the candidate calibrated models, the trust-region refinement, the choice of
the calibrated model with its flags, the validation period and the comparison with a truth.
The stages from the meta-model to the choice (:func:`_calibration_stage`) run once on the
campaign's samples and, with ``sampling.zoom``, again on a local campaign around the first
answer (:func:`_zoom_stage`, :mod:`thermocal.calibration.zoom`).

:func:`analyse` runs the stages in order; :func:`thermocal.calibration.workflow.calibrate` calls
it after a campaign and :func:`thermocal.calibration.workflow.reanalyse` on a stored one.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import pandas as pd

from thermocal.calibration.flags import calibration_flags, model_error_floor
from thermocal.calibration.metamodels import (
    choose_surrogate,
    reduced_options,
    reduced_surrogate,
    series_terms_note,
    sobol_or_note,
    surrogate_for,
)
from thermocal.calibration.metric import METRIC_NAMES, metric_data, metric_value
from thermocal.calibration.refine import refine_minimum
from thermocal.calibration.result import CalibrationResult, truth_comparison
from thermocal.errors import ThermocalInputError
from thermocal.identification.metrics import guideline14
from thermocal.identification.problem import METRIC

#: Largest campaign space whose joint posterior is sampled (else: the critical parameters).
POSTERIOR_MAX_PARAMETERS = 30
#: whether the zoom stage's meta-model also uses the first campaign's samples inside its box
#: (False: the zoom campaign's samples only; measured on the 5ZoneAirCooled twin, see
#: docs/calibration.md)
ZOOM_WITH_FIRST_INSIDE = False



#: Below this cross-validated R2 (and above 0) the meta-model's ranking and optima are called
#: rough in a note: at 0.04 the report listed ten critical parameters and Sobol' indices to four
#: digits without a word (exploratory test, 2026-11-30) [-].
WEAK_METAMODEL_R2 = 0.5

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
    an evaluator). The stages, in order: the campaign's notes, the nominal run, the samples'
    metric, the meta-model with its ranking and reduced optima, the Morris screening, the
    confirmation of the optima, the posterior, the candidate calibrated models, the
    trust-region refinement, the zoom stage (the same stages on a local campaign around the
    first answer, ``sampling.zoom``), the choice of the calibrated model with its flags, the
    validation period and the comparison with a known truth.

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
    metric = campaign.metric
    info = store.info("analysis") or {}
    occupancy = info.get("occupancy", {})
    notes.extend(_campaign_notes(sample_set, occupancy, _range_hint(campaign)))
    nominal_outputs, nominal_heat = _nominal_run(runs, store)
    nominal_metric = metric_value(nominal_outputs, metric)
    samples = _read_samples(campaign, space, store, timings, notes)
    screening = None
    if campaign.morris is not None and morris is not None:
        t0 = time.perf_counter()
        screening = morris()
        timings["morris"] = time.perf_counter() - t0
    nominal = (nominal_outputs, nominal_heat, nominal_metric)
    t0 = time.perf_counter()
    uncertain = []
    if samples.series is not None:  # the posterior needs the series
        uncertain = _uncertain_inputs(campaign, inputs, space, runs, nominal_outputs, notes, log)
    if uncertain:
        timings["uncertain_inputs"] = time.perf_counter() - t0
    first = _calibration_stage(
        campaign, space, samples, runs, nominal, prior_space=space, timings=timings, notes=notes,
        log=log, uncertain=uncertain,
    )  # fmt: skip
    fitted, confirmed, heat = first.fitted, first.confirmed, first.heat
    confirmed["refinement"] = first.refinement
    final = first
    zoom_info = None
    if campaign.sampling.zoom > 0:
        t0 = time.perf_counter()
        zoomed = _zoom_stage(
            campaign, space, samples, first, runs, nominal, notes=notes, log=log,
            uncertain=uncertain,
        )  # fmt: skip
        timings["zoom"] = time.perf_counter() - t0
        if zoomed is not None:
            final, zoom_info = zoomed
            timings.update({f"zoom_{k}": v for k, v in zoom_info.pop("timings_s").items()})
    posterior, series_model, movable = final.posterior, final.series_model, final.movable
    if posterior is not None:
        posterior = _with_envelope_total(posterior, space, inputs.building, campaign, log)
    calibrated_source, calibrated_metric, calibrated_values = (
        final.source,
        final.metric,
        final.values,
    )
    confirmed["calibrated"] = {
        "source": calibrated_source,
        "confirmed": float(calibrated_metric),
        "confirmed_std_W": float(np.sqrt(calibrated_metric)),
    }
    # the model-error floor is the campaign's (the first stage's posterior over its prior), not
    # the zoom box's, whose 5 % quantile is about its own minimum
    floor_from = (first.posterior, first.series_model)
    flags = calibration_flags(
        space, calibrated_values, calibrated_metric, posterior, series_model, inputs.truth,
        floor_from=floor_from,
    )  # fmt: skip
    notes.extend(flag["text"] for flag in flags)
    confirmed["flags"] = flags
    floor = model_error_floor(space, *floor_from)
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
            n
            for n in inputs.truth.get("parameters", {})
            if n in space.names and n not in fitted.critical
        ]
        comparison = truth_comparison(
            list(fitted.critical) + perturbed,
            space,
            inputs.truth,
            calibrated_values,
            fitted.critical,
        )
        if inputs.true_loads is not None:
            confirmed["guideline14_vs_true_loads"] = _guideline14(heat, inputs.true_loads)
    calibrated_parameters = {name: float(calibrated_values[name]) for name in space.names}
    calibrated = inputs.building.with_parameters(calibrated_parameters)
    return CalibrationResult(
        space=space,
        samples=sample_set,
        store_frame=samples.frame,
        summary=summary,
        surrogate=fitted.surrogate,
        ranking=fitted.ranking,
        sobol=fitted.sobol,
        critical=fitted.critical,
        optimisation=fitted.optimisation,
        nominal_metric=nominal_metric,
        confirmed=confirmed,
        heat=heat,
        weather=_stored_weather(info),
        validation=validation,
        morris=screening,
        truth_comparison=comparison,
        calibrated_building=calibrated,
        calibrated_parameters=calibrated_parameters,
        building_path="" if campaign.building_path is None else str(campaign.building_path),
        timings=timings,
        notes=notes,
        campaign_path=str(campaign.path),
        posterior=posterior,
        occupancy=occupancy,
        metric=metric,
        runs={"simulated": runs.simulated, "from_store": runs.reused},
        zoom=zoom_info,
    )


@dataclass
class Stage:
    """One calibration stage on one set of samples (the campaign's, or the zoom campaign's).

    Attributes
    ----------
    fitted : FittedMetamodel
    confirmed : dict
        The optima's predicted and confirmed metric [W^2] (see :func:`_confirm_optima`).
    heat : dict of str to Series
        Building-wide identified heat of the nominal model and the confirmed optima [W].
    unconfirmed : list of str
    posterior : Posterior or None
    series_model : SeriesSurrogate or None
    movable : list of str
        The parameters the calibrated model may change.
    candidates : dict
        Name -> (confirmed metric [W^2], parameters [unit of each]).
    refinement : list of dict
        The trust-region refinement's steps.
    source, metric, values : str, float, dict
        The best candidate: its name, metric [W^2] and parameters [unit of each].
    """

    fitted: Any
    confirmed: dict
    heat: dict
    unconfirmed: list
    posterior: Any
    series_model: Any
    movable: list
    candidates: dict
    refinement: list
    source: str
    metric: float
    values: dict


def _calibration_stage(
    campaign, space, samples, runs, nominal, *, prior_space, timings, notes, log,
    extra_candidates=None, critical=None, uncertain=(),
) -> Stage:  # fmt: skip
    """Meta-model, confirmed optima, posterior, candidates, refinement and choice on ``samples``.

    ``space``: the bounds of the meta-model's optimisation and refinement (the campaign's, or
    the zoom box); ``prior_space``: the posterior's uniform prior (always the campaign's
    range, so that "determined" keeps its meaning). ``nominal``: the nominal run's outputs,
    heat [W] and metric [W^2]. ``extra_candidates`` (name -> (metric [W^2], parameters)) join
    the stage's own before the refinement starts from the best; ``critical``: the parameters
    the reduced meta-model optimises (and the posterior covers in spaces of more than
    :data:`POSTERIOR_MAX_PARAMETERS`), None: the stage's own ``top_k`` ranking;
    ``uncertain``: the uncertain inputs' signatures the posterior marginalises
    (:func:`_uncertain_inputs`).
    """
    nominal_outputs, nominal_heat, nominal_metric = nominal
    metric = campaign.metric
    t0 = time.perf_counter()
    fitted = _fit_metamodel(campaign, space, samples, notes, critical)
    timings["metamodel_sensitivity_optimisation"] = time.perf_counter() - t0
    log(
        f"meta-model cross-validated R2 {fitted.surrogate.cv_r2_:.3f}; critical: "
        f"{', '.join(fitted.critical)}"
    )
    if fitted.surrogate.cv_r2_ < 0.0:
        worse = (
            f"The meta-model predicts the samples it did not see worse than their mean does "
            f"(cross-validated R2 {fitted.surrogate.cv_r2_:.2f}, {len(samples.y)} samples of "
            f"{space.dimension} parameters): its ranking of the parameters, the reduction to "
            "the critical ones and its optima are not informative; run more samples (--resume "
            "--samples N adds them) or vary fewer parameters."
        )
        notes.append(worse)
        log(worse)
    elif fitted.surrogate.cv_r2_ < WEAK_METAMODEL_R2:
        weak = (
            f"The meta-model explains {100 * max(fitted.surrogate.cv_r2_, 0.0):.0f} % of the "
            f"variance of the samples it did not see (cross-validated R2 "
            f"{fitted.surrogate.cv_r2_:.2f}, {len(samples.y)} samples of {space.dimension} "
            "parameters): its ranking of the parameters (the critical ones and the Sobol' "
            "indices, whose intervals are as wide as the indices) and its optima are rough; "
            "read them with the posterior's intervals and the confirmed runs, and run more "
            "samples (--resume --samples N adds them) or vary fewer parameters for more."
        )
        notes.append(weak)
        log(weak)
    t0 = time.perf_counter()
    confirmed, heat, unconfirmed = _confirm_optima(
        runs, fitted.optimisation, metric, nominal_outputs, nominal_heat, nominal_metric
    )
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
    if samples.series is not None:
        t0 = time.perf_counter()
        posterior, series_model = _posterior_or_note(
            fitted.surrogate,
            fitted.kind,
            samples.X,
            samples.y,
            samples.series,
            prior_space,
            fitted.critical,
            campaign,
            notes,
            samples.segments,
            uncertain,
        )
        timings["posterior"] = time.perf_counter() - t0
        note = series_terms_note(series_model, optimum=fitted.kind == "series")
        if note:
            notes.append(note)
            confirmed["series_metamodel"] = series_model.hyperparameters_()
        if posterior is not None:
            for line in posterior.sentences():
                log(line)
    movable = _movable_parameters(campaign, space, posterior, notes)
    candidates = _candidates(
        campaign,
        space,
        samples,
        fitted,
        runs,
        confirmed,
        unconfirmed,
        posterior,
        movable,
        nominal_metric,
        notes,
    )
    candidates.update(extra_candidates or {})
    refinement = []
    # with in-situ measurements in the posterior the calibrated building is its median: no
    # refinement of the metric's minimum
    by_median = bool(posterior is not None and posterior.in_situ) and (
        "posterior median" in candidates
    )
    if campaign.in_situ and not by_median:
        notes.append(
            "The in-situ measurements did not enter a confirmed posterior median (no posterior, "
            "the measured parameters not among its parameters, or the median not in the store "
            "of a re-analysis): the calibrated building is the best confirmed candidate."
        )
    if campaign.optimisation.refine > 0 and not by_median:
        t1 = time.perf_counter()
        terms = getattr(series_model, "terms_", campaign.metamodel.series_terms)
        refinement = _refine(
            campaign, space, samples, fitted.kind, runs, candidates, movable, log, terms
        )
        if runs.evaluator is None and len(refinement) < campaign.optimisation.refine and movable:
            notes.append(
                f"Re-analysis without simulation: the trust-region refinement stopped after "
                f"{len(refinement)} of {campaign.optimisation.refine} steps (the next candidate "
                "is not in the store)."
            )
        timings["refinement"] = time.perf_counter() - t1
    source, value, values = _choose_calibrated(
        candidates, notes, prefer="posterior median" if by_median else None
    )
    if by_median:
        notes.append(
            "The calibrated building is the posterior's median: it weighs the in-situ "
            "measurements, which the metric alone cannot."
        )
    return Stage(
        fitted, confirmed, heat, unconfirmed, posterior, series_model, movable, candidates,
        refinement, source, value, values,
    )  # fmt: skip


def _zoom_stage(
    campaign, space, samples, first: Stage, runs, nominal, *, notes, log, uncertain=()
):
    """The zoom campaign and the calibration stage on its samples (see
    :mod:`thermocal.calibration.zoom`); None (noted) when it cannot run.

    Returns
    -------
    stage : Stage
    info : dict
        The box (per parameter ``lower``, ``upper``, ``center`` [unit of each] and the
        first posterior's ``log_sd`` [-]), the design's size and seed, the runs simulated and
        read from the store, the local samples used, the local meta-model's cross-validated
        R2, its confirmed minimum and the stage's choice, refinement and timings [s].
    """
    from thermocal.calibration.zoom import (
        ZOOM_MIN_HALF_WIDTH,
        ZOOM_STANDARD_DEVIATIONS,
        box_space,
        inside_box,
        narrowed,
        posterior_log_sd,
        run_zoom,
        zoom_box,
        zoom_design,
    )

    if first.posterior is None:
        notes.append(
            "No zoom campaign: it is sized by the first stage's posterior, which could not be "
            "computed."
        )
        return None
    names = list(space.names)
    n = campaign.sampling.zoom
    if n < space.dimension + 2:
        notes.append(
            f"No zoom campaign: its {n} samples are fewer than the {space.dimension + 2} the "
            f"affine meta-model needs ({space.dimension} parameters, an intercept and one more "
            "for its error); measured on the outpatient twin (58 parameters, 32 samples): the "
            "local fit determined nothing. Give sampling.zoom at least that, or fewer "
            "parameters."
        )
        return None
    center = np.array([first.values[name] for name in names], dtype=float)
    log_sd = posterior_log_sd(first.posterior.samples, names)
    lower, upper = zoom_box(space.lower, space.upper, center, log_sd)
    if not narrowed(space.lower, space.upper, lower, upper).any():
        notes.append(
            "No zoom campaign: the first posterior narrows no parameter to less than half its "
            "range (+-3 sd of log p), so a local box would be the whole range; more samples in "
            "the first campaign, or fewer parameters, are what would help."
        )
        return None
    seed = campaign.sampling.seed + 1
    design = zoom_design(names, lower, upper, n, method=campaign.sampling.method, seed=seed)
    t0 = time.perf_counter()
    X, outputs, counts = run_zoom(runs, design)
    campaign_s = time.perf_counter() - t0
    log(
        f"zoom campaign: {n} samples in a box of +-{ZOOM_STANDARD_DEVIATIONS:g} posterior sd "
        f"(at least +-{100 * ZOOM_MIN_HALF_WIDTH:.0f} %) around the first answer: "
        f"{counts['simulated']} simulated, {counts['from_store']} from the store"
        + (f", {counts['failed']} failed" if counts["failed"] else "")
    )
    if len(X):
        y, series, segments = metric_data(outputs, campaign.metric)
        X = X[names]
    else:
        y, series, segments = np.zeros(0), None, None
    keep = inside_box(samples.X[names], lower, upper) if ZOOM_WITH_FIRST_INSIDE else None
    if keep is not None and keep.any() and series is not None:
        X = pd.concat([X, samples.X[names][keep]])
        y = np.concatenate([y, samples.y[keep]])
        series = np.vstack([series, samples.series[keep]])
    needed = max(10, campaign.metamodel.cv_folds + 2)
    if len(y) < needed:
        missing = counts["missing"]
        notes.append(
            f"No zoom stage: {len(y)} of its {n} samples are available (at least {needed} "
            "needed)"
            + (
                f"; {missing} are not in the store (a re-analysis does not simulate; "
                "thermocal calibrate --resume runs them)."
                if missing
                else "."
            )
        )
        return None
    local = CampaignSamples(frame=X, X=X, y=y, series=series, segments=segments)
    extra = {
        f"first stage: {k}": v for k, v in first.candidates.items() if not k.startswith("nominal")
    }
    stage_notes: list[str] = []
    stage_timings: dict[str, float] = {"zoom_campaign": campaign_s}
    stage = _calibration_stage(
        campaign, box_space(space, lower, upper), local, runs, nominal, prior_space=space,
        timings=stage_timings, notes=stage_notes, log=lambda line: log(f"zoom: {line}"),
        extra_candidates=extra, critical=first.fitted.critical, uncertain=uncertain,
    )  # fmt: skip
    notes.extend(f"Zoom stage: {note}" for note in stage_notes)
    if counts["missing"]:
        notes.append(
            f"Zoom stage: {counts['missing']} of its {n} samples are not in the store (a "
            "re-analysis does not simulate); the local meta-model uses the others."
        )
    notes.append(
        f"Zoom stage: a second campaign of {n} samples (Sobol' design, seed {seed}) uniform in "
        f"log p over +-{ZOOM_STANDARD_DEVIATIONS:g} posterior standard deviations (at least "
        f"+-{100 * ZOOM_MIN_HALF_WIDTH:.0f} %) around the first answer ({first.source}); the "
        f"meta-model refitted on its {len(y)} local samples (cross-validated R2 "
        f"{stage.fitted.surrogate.cv_r2_:.3f}), its minimum confirmed, the posterior "
        f"recomputed from it; calibrated model from {stage.source} (sequential design: "
        "Kennedy and O'Hagan 2001)."
    )
    box = {
        name: {
            "lower": float(lower[i]),
            "upper": float(upper[i]),
            "center": float(center[i]),
            "log_sd": float(log_sd[i]),
        }
        for i, name in enumerate(names)
    }
    info = {
        "samples": int(n),
        "seed": int(seed),
        "method": campaign.sampling.method,
        "standard_deviations": ZOOM_STANDARD_DEVIATIONS,
        "min_half_width_log": ZOOM_MIN_HALF_WIDTH,
        "first_stage": {"source": first.source, "confirmed": float(first.metric)},
        "box": box,
        "runs": counts,
        "local_samples": int(len(y)),
        "first_batch_samples_in_box": int(keep.sum()) if keep is not None else 0,
        "cv_r2": float(stage.fitted.surrogate.cv_r2_),
        "min": stage.confirmed.get("min"),
        "posterior_median": stage.confirmed.get("posterior_median"),
        "refinement": stage.refinement,
        "source": stage.source,
        "confirmed": float(stage.metric),
        "timings_s": stage_timings,
    }
    return stage, info


#: Share of a parameter's samples clipped to a physical limit above which the note says what
#: that does: the meta-model then sees the parameter at the limit in many samples (a
#: ``default_range: 50`` meant as +-50 % clipped half the wall insulation's samples to the floor
#: and gave a "determined" conductivity 7 times too good; exploratory test, 2026-11-30).
MOSTLY_CLIPPED = 0.25


def _campaign_notes(sample_set, occupancy: dict, range_hint: str = "") -> list[str]:
    """Notes on the campaign itself: samples clipped to physical limits, quiet hours from data.

    ``range_hint``: :func:`_range_hint`, said when a parameter's samples are mostly clipped."""
    notes = []
    clipped = sample_set.clip_counts[sample_set.clip_counts["total"] > 0]
    if len(clipped):
        note = f"{len(clipped)} parameter(s) had samples clipped to their physical limits: " + (
            ", ".join(f"{name} ({int(row['total'])})" for name, row in clipped.iterrows())
        )
        mostly = clipped[clipped["fraction"] > MOSTLY_CLIPPED]
        if len(mostly):
            note += (
                f"; {', '.join(mostly.index[:5])}{', ...' if len(mostly) > 5 else ''}: more than "
                f"{100 * MOSTLY_CLIPPED:g} % of the samples at a limit, so the meta-model and the "
                "posterior see those parameters mostly at their limits, and an interval near a "
                "limit says more about the range than about the building: narrow the range"
                + range_hint
            )
        notes.append(note)
    if occupancy.get("source") == "data":
        notes.append(
            "Unoccupied hours from the data: "
            + occupancy.get("paper_schedule_check", "")
            + "; the metric uses the quiet hours of the nominal identified heat ("
            + occupancy["quiet_hours"]
            + ")."
        )
    return notes


def _uncertain_inputs(campaign, inputs, space, runs, nominal_outputs, notes, log):
    """The signatures of the inputs the campaign holds nominal but does not know
    (``posterior.uncertain``, :mod:`thermocal.calibration.uncertain`): one model run each,
    through ``runs`` (stored; a re-analysis reads them and notes those it lacks; a run the
    model fails is noted and its input left out)."""
    from thermocal.calibration.uncertain import (
        model_refusal,
        nominal_values,
        uncertain_inputs,
        uncertain_signatures,
    )

    setting = campaign.posterior.uncertain
    items = uncertain_inputs(
        setting,
        nominal_values(inputs.building),
        space.names,
        where=f"{campaign.path or 'campaign file'}: posterior",
        invalid=model_refusal(inputs.building),
    )
    if not items:
        if setting == "auto":
            log("posterior.uncertain auto: the campaign varies the infiltration, or the "
                "building has none; nothing to integrate out")  # fmt: skip
        return []
    failed: dict[str, str] = {}

    def run(item):
        try:
            found = runs.get(item.perturbed(), heat=False)
        except (ThermocalInputError, ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            failed[item.label] = str(exc)
            return None
        return None if found is None else found[0]

    signatures, missing = uncertain_signatures(items, run, nominal_outputs, campaign.metric)
    for description, _, _ in signatures:
        log(
            f"uncertain input {description['label']} (+-{100 * description['rel_std']:.0f} %, "
            "not varied): marginalised in the posterior"
        )
    for label, why in failed.items():
        notes.append(
            f"The uncertain input {label} is not integrated out of the posterior: its model run "
            f"failed ({why})."
        )
    unstored = [label for label in missing if label not in failed]
    if unstored:
        notes.append(
            "Not marginalised in the posterior (their runs are not in the store and a "
            "re-analysis does not simulate; thermocal calibrate --resume runs them): "
            + ", ".join(unstored)
            + "."
        )
    return signatures


def _nominal_run(runs, store):
    """The nominal model's outputs [unit of each] and building-wide heat [W], from the store."""
    found = runs.get({})
    if found is None:
        raise ThermocalInputError(
            f"store {store.path}: the nominal model's run is not stored (a store written before "
            "thermocal could re-analyse campaigns, without the zone-group series either); run "
            "the campaign again into a new store (another --out) to re-analyse it"
        )
    return found


@dataclass
class CampaignSamples:
    """The successful samples of a campaign and their metric.

    Attributes
    ----------
    frame : DataFrame
        The store's table without the heat series (for the report and ``samples.csv``).
    X : DataFrame
        Parameter values of the successful samples [unit of each].
    y : ndarray
        Their metric [W^2].
    series, segments : ndarray or None, list or None
        Their unoccupied heat series [W] and each zone group's column range (see
        :func:`thermocal.calibration.metric.metric_data`).
    """

    frame: pd.DataFrame
    X: pd.DataFrame
    y: np.ndarray
    series: np.ndarray | None
    segments: list | None


def minimum_samples(campaign) -> int:
    """The fewest successful samples a campaign's meta-model is fitted to [-]."""
    return max(10, campaign.metamodel.cv_folds + 2)


def _range_hint(campaign) -> str:
    """A hint for a relative range written as a percentage (50 for +-50 %)."""
    p = campaign.parameters
    if p.default_range <= 1.0:
        return ""
    return (
        f" (parameters.default_range {p.default_range:g} is a relative half-width: "
        f"+-{100 * p.default_range:g} %, clipped to the physical limits; did you mean "
        f"{p.default_range / 100:g}?)"
    )


def _read_samples(campaign, space, store, timings: dict, notes: list) -> CampaignSamples:
    """The samples of the store and their metric; failed samples and too few samples noted."""
    metric = campaign.metric
    t0 = time.perf_counter()
    frame = store.to_frame()
    errors = frame["error"].dropna()
    minimum = minimum_samples(campaign)
    if len(frame) - len(errors) < minimum:
        raise ThermocalInputError(
            f"only {len(frame) - len(errors)} successful samples of {len(frame)}: too few for "
            f"a meta-model (at least {minimum})"
            + (
                f"; {len(errors)} failed, the first (sample {errors.index[0]}) with: "
                f"{errors.iloc[0]}"
                if len(errors)
                else ""
            )
            + _range_hint(campaign)
            + "; use more --samples"
            + (" or narrower parameter ranges" if len(errors) else "")
        )
    X = store.parameters()[list(space.names)]
    y, series, segments = metric_data(store.outputs(), metric)
    frame = frame.drop(
        columns=[c for c in frame.columns if c.startswith(("out:series/", "out:group/"))]
    )
    timings["read_store"] = time.perf_counter() - t0
    failed = int(frame["error"].notna().sum())
    if failed:
        notes.append(f"{failed} sample(s) failed (errors in the store); they are left out")
    if metric != "building":
        notes.append(f"Metric: the {METRIC_NAMES[metric]} ({len(segments)} groups).")
    return CampaignSamples(frame, X, y, series, segments)


@dataclass
class FittedMetamodel:
    """The meta-model of a campaign, its parameter ranking and its reduced optima.

    Attributes
    ----------
    surrogate : object
        The fitted meta-model (``predict``, ``cv_r2_``).
    kind : str
        Its kind (``"svr"``, ``"gp"`` or ``"series"``).
    ranking, sobol : DataFrame, DataFrame or None
        Influence ranking and Sobol indices of the parameters.
    critical : list of str
        The parameters the reduced meta-model optimises.
    optimisation : ReducedOptimisation
        The reduced meta-model's minimum and maximum.
    """

    surrogate: Any
    kind: str
    ranking: Any
    sobol: Any
    critical: list
    optimisation: Any

    def reduced_optimum(self, campaign, space, samples: CampaignSamples, parameters: list):
        """The reduced meta-model's optima over ``parameters`` (a subset of the space)."""
        from thermocal.calibration.optimise import optimise_reduced

        m = campaign.metamodel
        seed = campaign.sampling.seed
        return optimise_reduced(
            samples.X,
            samples.y,
            space,
            parameters,
            surrogate=reduced_surrogate(
                self.kind,
                m,
                samples.series,
                space,
                seed,
                samples.segments,
                getattr(self.surrogate, "terms_", None),
            ),
            starts=campaign.optimisation.starts,
            seed=campaign.optimisation.seed,
            surrogate_options=reduced_options(self.kind, m),
        )


def _fit_metamodel(
    campaign, space, samples: CampaignSamples, notes: list, critical=None
) -> FittedMetamodel:
    """Meta-model (chosen by cross-validation with ``kind: auto``), ranking, Sobol indices and
    the reduced meta-model's optima over the ``top_k`` critical parameters (or the given
    ``critical`` ones: the zoom stage keeps the first stage's, whose influence over the whole
    range is what the box narrows; within the box their influence is small by design)."""
    from thermocal.calibration.sensitivity import influence_ranking, top_k

    m = campaign.metamodel
    surrogate, kind, scores = choose_surrogate(
        samples.X,
        samples.y,
        m.kind,
        cv_folds=m.cv_folds,
        log_target=m.log_target,
        seed=campaign.sampling.seed,
        series=samples.series,
        nominal=space.nominal_dict(),
        segments=samples.segments,
        series_terms=m.series_terms,
        series_coordinates=m.series_coordinates,
    )
    if m.kind == "auto":
        notes.append(
            "Meta-model: "
            + ", ".join(f"{k.upper()} cross-validated R2 {r2:.3f}" for k, r2 in scores.items())
            + f"; the {kind.upper()} was used."
        )
    lower, upper = np.asarray(space.lower, float), np.asarray(space.upper, float)
    ranking = influence_ranking(surrogate.predict, samples.X, lower, upper, names=space.names)
    sobol = sobol_or_note(surrogate, space, lower, upper, campaign.sampling.seed, kind, notes)
    critical = top_k(ranking, m.top_k) if critical is None else list(critical)
    fitted = FittedMetamodel(surrogate, kind, ranking, sobol, critical, None)
    fitted.optimisation = fitted.reduced_optimum(campaign, space, samples, critical)
    return fitted


def _confirm_optima(runs, optimisation, metric, nominal_outputs, nominal_heat, nominal_metric):
    """The reduced meta-model's minimum and maximum run with the full model.

    Returns
    -------
    confirmed : dict
        Per optimum (``"min"``, ``"max"``) its predicted and confirmed metric [W^2].
    heat : dict of str to Series
        Building-wide identified heat of the nominal model and of each confirmed optimum [W].
    unconfirmed : list of str
        The optima not in the store of a re-analysis (not simulated).
    """
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
    return confirmed, heat, unconfirmed


def _determined_only(campaign, posterior) -> bool:
    """Whether the calibrated model may change only what the posterior says the data determine
    (``optimisation.calibrate: determined``, the default, and a posterior to say it)."""
    return posterior is not None and campaign.optimisation.calibrate == "determined"


def _movable_parameters(campaign, space, posterior, notes: list) -> list[str]:
    """The parameters the calibrated model may change.

    With ``optimisation.calibrate: determined`` (the default) only those the posterior says the
    data determine, and those measured in situ; the others stay nominal. Without a posterior,
    or with ``all``, every one.
    """
    if not _determined_only(campaign, posterior):
        return list(space.names)
    # a parameter measured in situ moves with its posterior whatever its width
    measured = set(getattr(posterior, "in_situ", {}) or {})
    determined = [n for n in space.names if n in posterior.determined or n in measured]
    if len(determined) < space.dimension:
        notes.append(
            (
                f"Calibrated parameters: only the {len(determined)} the data determine "
                f"({', '.join(determined)}); the others stay nominal"
                if determined
                else "Calibrated parameters: none, the data determine none of them; every one "
                "stays nominal"
            )
            + " (optimisation.calibrate: all changes every one)."
        )
    return determined


def _candidates(
    campaign,
    space,
    samples: CampaignSamples,
    fitted: FittedMetamodel,
    runs,
    confirmed: dict,
    unconfirmed: list,
    posterior,
    movable: list,
    nominal_metric: float,
    notes: list,
) -> dict:
    """The candidate calibrated models, each with its confirmed metric [W^2] and parameters.

    The reduced meta-model's minimum (or, when it moves parameters the data do not determine,
    its minimum over the determined critical ones), the nominal building (never return a
    building worse than the one the user gave), the joint posterior's median and the campaign's
    best sample (a meta-model fitted on few samples can miss), each confirmed with the model.
    """
    metric = campaign.metric
    determined_only = _determined_only(campaign, posterior)
    candidates = {}
    if "min" not in unconfirmed and set(fitted.critical) <= set(movable):
        candidates["meta-model minimum"] = (
            confirmed["min"]["confirmed"],
            fitted.optimisation.parameters("min"),
        )
    elif determined_only and [c for c in fitted.critical if c in movable]:
        restricted = fitted.reduced_optimum(
            campaign, space, samples, [c for c in fitted.critical if c in movable]
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
    moved = [c for c in fitted.critical if c not in movable]
    if "min" not in unconfirmed and moved and "min" in confirmed:
        # confirmed, but not a candidate: said, or the nominal's note reads as if nothing
        # confirmed better (the demo's minimum at 3.67 kW against the nominal 7.35)
        notes.append(
            f"The meta-model's minimum was confirmed at "
            f"{np.sqrt(confirmed['min']['confirmed']) / 1000:.2f} kW (the nominal building "
            f"{np.sqrt(nominal_metric) / 1000:.2f} kW), but it changes parameters the data do "
            f"not determine ({', '.join(moved[:4])}{', ...' if len(moved) > 4 else ''}): it is "
            "not a candidate for the calibrated building"
        )
    candidates["nominal building (no change)"] = (nominal_metric, space.nominal_dict())
    if posterior is not None:
        median = {
            **space.nominal_dict(),
            **{n: v for n, v in posterior.summary["median"].items() if n in movable},
        }
        found = runs.get(median, heat=False)
        if found is not None:
            candidates["posterior median"] = (metric_value(found[0], metric), median)
            confirmed["posterior_median"] = {"confirmed": candidates["posterior median"][0]}
    X, y = samples.X, samples.y
    best = int(np.argmin(y))
    if y[best] < min(c[0] for c in candidates.values()):
        if not determined_only:
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
    return candidates


def _refine(
    campaign, space, samples, kind, runs, candidates: dict, movable, log, terms="affine"
) -> list:
    """The trust-region refinement from the best candidate (added to ``candidates`` when it
    improves on it); the refinement's runs. ``terms``: the series meta-model's form (the one
    chosen on the campaign, so that each step does not choose again)."""
    start_name = min(candidates, key=lambda k: candidates[k][0])
    refined, refinement = refine_minimum(
        runs,
        space,
        samples.X,
        samples.y,
        samples.series,
        kind,
        candidates[start_name],
        steps=campaign.optimisation.refine,
        seed=campaign.optimisation.seed,
        log=log,
        metric=campaign.metric,
        segments=samples.segments,
        movable=movable,
        series_terms=terms,
        series_coordinates=campaign.metamodel.series_coordinates,
    )
    if refined[0] < candidates[start_name][0]:
        candidates[f"trust-region refinement ({len(refinement)} runs)"] = refined
    return refinement


def _choose_calibrated(
    candidates: dict, notes: list, prefer: str | None = None
) -> tuple[str, float, dict]:
    """The best confirmed candidate: its name, metric [W^2] and parameters (noted when it is
    the nominal building or a campaign sample); ``prefer``: that candidate when it exists (the
    posterior's median with in-situ measurements, which the metric alone cannot weigh)."""
    source = min(candidates, key=lambda k: candidates[k][0])
    if prefer in candidates:
        source = prefer
    value, parameters = candidates[source]
    if source.startswith("nominal"):
        notes.append(
            "No candidate that changes only what the data determine was confirmed better "
            "than the nominal building "
            f"({np.sqrt(value) / 1000:.2f} kW): the calibrated building is the "
            "nominal one. The metric cannot tell the parameters apart on these data; more "
            "samples, a narrower parameter selection or another period may."
        )
    if source.startswith("campaign sample"):
        notes.append(
            f"The meta-model's minima were confirmed worse than the best simulated sample "
            f"({np.sqrt(value) / 1000:.2f} kW): the calibrated building takes "
            "that sample's parameters. More samples give a better meta-model."
        )
    return source, value, parameters


def _stored_weather(info: dict) -> pd.DataFrame:
    """The campaign period's outdoor temperature [C] and global horizontal irradiance [W/m2],
    as stored with the campaign (for the report's figures; empty when not stored)."""
    grid = info.get("weather")
    if not grid:
        return pd.DataFrame({"temp_air": [], "ghi": []})
    index = pd.date_range(
        pd.Timestamp(grid["start"]),
        periods=len(grid["temp_air"]),
        freq=pd.Timedelta(seconds=grid["step_s"]),
    )
    return pd.DataFrame({"temp_air": grid["temp_air"], "ghi": grid["ghi"]}, index=index)


def _with_envelope_total(posterior, space, building, campaign, log):
    """The posterior with the varied elements' and air changes' total conductances
    (:mod:`thermocal.calibration.envelope_total`), said in the log when they add to the single
    verdicts."""
    from thermocal.calibration.envelope_total import (
        total_conductance,
        total_conductance_sentences,
    )

    total = total_conductance(posterior, space, building, seed=campaign.sampling.seed)
    for sentence in total_conductance_sentences(total):
        log(sentence)
    return replace(posterior, envelope_total=total)


def _posterior_or_note(
    surrogate, kind, X, y, series, space, critical, campaign, notes, segments=None, uncertain=()
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
    # a parameter measured in situ is in the posterior whether or not it is critical
    names += [n for n in campaign.in_situ if n in space.names and n not in names]
    if len(names) < space.dimension:
        notes.append(
            f"The posterior covers the {len(names)} critical "
            + ("and measured " if campaign.in_situ else "")
            + "parameters (the others at their nominal values): the space has more than "
            f"{POSTERIOR_MAX_PARAMETERS} parameters."
        )
    idx = [space.index(n) for n in names]
    measured, details = _in_situ_values(campaign, space, notes)
    arguments = {
        "all_lower": space.lower,
        "all_upper": space.upper,
        "units": [space.units[i] for i in idx],
        "seed": campaign.sampling.seed,
        "emulator_error": emulator_variance(model, X, seed=campaign.sampling.seed),
        "discrepancy": campaign.posterior.discrepancy,
        "uncertain": uncertain,
    }
    try:
        posterior = calibration_posterior(
            model, names, space.lower[idx], space.upper[idx], measured=measured, **arguments
        )
    except (ThermocalInputError, np.linalg.LinAlgError, ValueError) as exc:
        notes.append(f"No posterior of the calibrated parameters: {exc}")
        return None, model
    if campaign.posterior.advise:
        from thermocal.calibration.advice import advise_measurements

        try:
            advice = advise_measurements(
                model, names, space.lower[idx], space.upper[idx], posterior,
                measured=measured, **arguments,
            )  # fmt: skip
        except (ThermocalInputError, np.linalg.LinAlgError, ValueError) as exc:
            notes.append(f"No measurement advice: {exc}")
        else:
            posterior = replace(posterior, advice=advice)
    if details:
        posterior = replace(posterior, in_situ=details)
    return posterior, model


def measure_in_situ(campaign, space) -> dict:
    """The campaign's in-situ measurements (``in_situ:``), read, reduced and checked.

    Called before the campaign runs (a bad log stops it before any simulation) and by the
    analysis.

    Returns
    -------
    dict
        name -> (:class:`~thermocal.physics.heat_flux.InSituUValue`, source).

    Raises
    ------
    ThermocalInputError
        A measured name that is not a parameter of the campaign, a log that cannot be read or
        has not converged (:func:`thermocal.io.heat_flux_log.measure_in_situ_value`), or a
        resistance that comes out not positive.
    """
    from thermocal.io.heat_flux_log import measure_in_situ_value

    out = {}
    for name, spec in campaign.in_situ.items():
        where = f"in_situ.{name}"
        if name not in space.names:
            raise ThermocalInputError(
                f"campaign {where}: {name!r} is not a parameter of the campaign (its "
                "resistances: "
                + (", ".join(n for n in space.names if n.endswith("/resistance")) or "none")
                + "; check parameters.include)"
            )
        result, source = measure_in_situ_value(spec, where, flow=spec.flow or "horizontal")
        if not (result.resistance > 0 and result.resistance_rel_std > 0):
            raise ThermocalInputError(
                f"campaign {where}: U {result.u_value:.3g} W/(m2 K) leaves no resistance "
                f"({result.resistance:.3g} m2 K/W) beyond ISO 6946's surface resistances "
                f"{result.surface_resistances}: check the value and flow"
            )
        i = space.index(name)
        low, high = float(space.lower[i]), float(space.upper[i])
        if not low <= result.resistance <= high:
            raise ThermocalInputError(
                f"campaign {where}: the measured resistance {result.resistance:.3g} m2 K/W lies "
                f"outside the campaign's range for it ({low:.3g} to {high:.3g}): widen "
                "parameters.ranges for it, or check the log (plate position, the temperatures' "
                "sides, other_side)"
            )
        out[name] = (result, source)
    return out


def _in_situ_values(campaign, space, notes) -> tuple[dict, dict]:
    """The campaign's in-situ measurements (:func:`measure_in_situ`) for the posterior, whose
    parameters include every measured one.

    Returns
    -------
    measured : dict
        name -> (resistance [m2 K/W], relative standard uncertainty [-]), for
        :func:`~thermocal.calibration.posterior.calibration_posterior`.
    details : dict
        name -> the measurement (JSON-ready) with its source.
    """
    measured, details = {}, {}
    for name, (result, source) in measure_in_situ(campaign, space).items():
        measured[name] = (result.resistance, result.resistance_rel_std)
        details[name] = {"source": source, **result.as_dict()}
        notes.append(
            f"{name} measured in situ: {result.resistance:.3g} m2 K/W +- "
            f"{100 * result.resistance_rel_std:.0f} % ({source}); a prior with the measurement's "
            "90 % interval replaces the campaign's uniform one in the posterior."
        )
        notes += [f"in_situ.{name}: {line}" for line in result.warnings + result.notes]
    return measured, details


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
