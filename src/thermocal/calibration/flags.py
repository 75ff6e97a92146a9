"""Warnings on a calibrated model: parameters at bounds that were not perturbed, a metric
below what the model error allows (:func:`model_error_floor`), differences from a known truth.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

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


#: The curvature's out-of-fold hourly error at most this fraction of the affine form's: the
#: straight line in log p is flagged (:func:`linearisation_flag`).
LINEARISATION_ERROR_RATIO = 0.5
#: ... and the curvature moves a posterior parameter's optimum by more than this fraction of the
#: half-width of its 90 % interval (in log p): the straight line changes the answer, not only
#: the meta-model's error.
LINEARISATION_SHIFT_FRACTION = 0.5


def curvature_shifts(series_model, space, posterior=None) -> dict[str, float]:
    """How far the curvature moves each parameter's optimum: the minimum of the predicted
    metric over the box with the per-parameter quadratic form, fitted on the same samples,
    against the affine form's, ``x_quadratic / x_affine - 1`` [-].

    Parameters
    ----------
    series_model : SeriesSurrogate
        Fitted, affine.
    space : ParameterSpace
        The campaign's (its bounds).
    posterior : Posterior, optional
        Its parameters' prior bounds replace the space's (a zoom stage's box).

    Returns
    -------
    dict of str to float
    """
    from thermocal.calibration.surrogate import SeriesSurrogate

    names = [str(n) for n in series_model.feature_names_in_]
    idx = [list(space.names).index(n) for n in names]
    lower = np.asarray(space.lower, dtype=float)[idx]
    upper = np.asarray(space.upper, dtype=float)[idx]
    if posterior is not None:
        summary = posterior.summary
        for k, name in enumerate(names):
            if name in summary.index:
                lower[k] = float(summary.at[name, "prior_lower"])
                upper[k] = float(summary.at[name, "prior_upper"])
    X = pd.DataFrame(series_model._from_coordinates(series_model.log_parameters_), columns=names)
    curved = SeriesSurrogate(
        series=series_model.series,
        nominal=series_model.nominal,
        alphas=series_model.alphas,
        cv_folds=0,
        seed=series_model.seed,
        segments=series_model.segments,
        terms="quadratic",
        coordinates=series_model.coordinates,
    )
    curved.fit(X, curved.series_variance(curved.series))
    straight, _ = series_model.box_optimum("min", lower, upper)
    bent, _ = curved.box_optimum("min", lower, upper)
    return {n: float(b / a - 1.0) for n, a, b in zip(names, straight, bent, strict=True)}


def linearisation_flag(series_model, space=None, posterior=None) -> dict | None:
    """A flag when the series meta-model is affine in its coordinates but one with a curvature
    term per parameter reproduces the campaign's hourly heat at most
    :data:`LINEARISATION_ERROR_RATIO` times the error out of fold (None otherwise).

    The heat through an element goes as ``1 / (R + films)``: over a wide range a straight line
    in ``log R`` (the published coordinates) crosses zero away from the truth, and the
    calibrated resistance and its interval move with it (the EnergyPlus twin of 5ZoneAirCooled
    with other windows: roof +21 % with the straight line in ``log R``, +3 % with the
    curvature or in the conductance, on the same 48 samples; docs/calibration.md, "Curvature
    of the series meta-model"). The default physical coordinates
    (:mod:`thermocal.calibration.coordinates`) remove that; what curvature remains there
    (a layer property's logarithm, a film resistance far from ISO 6946's) is flagged the
    same way. The remedy costs no simulation: a re-analysis with the physical coordinates or
    ``metamodel.series_terms: auto``.

    With the campaign's ``space`` and a ``posterior``, only a straight line that changes the
    answer is flagged: the curvature must move the optimum of some parameter the posterior
    declares determined (:func:`curvature_shifts`) by more than
    :data:`LINEARISATION_SHIFT_FRACTION` of its 90 % interval's half-width in ``log p`` (an
    undetermined parameter's optimum is wherever the flat metric leaves it). In the physical
    coordinates what curvature remains on the twins is mostly too small for that (the 5-zone
    twin: 10 W affine, 4 W curved, against a residual of about 140 W).

    Parameters
    ----------
    series_model : SeriesSurrogate or None
        Fitted; anything without ``terms_`` gives None.
    space : ParameterSpace, optional
    posterior : Posterior, optional

    Returns
    -------
    dict or None
        ``kind`` "linearisation", ``text``, ``affine_W`` and ``quadratic_W`` (the out-of-fold
        hourly errors [W]), ``shifts`` (parameter -> the curvature's relative move of its
        optimum, with a posterior: those beyond the threshold) [-].
    """
    if getattr(series_model, "terms_", None) != "affine":
        return None
    errors = series_model.compare_terms()
    affine, quadratic = float(errors["affine"]), float(errors["quadratic"])
    if not quadratic <= LINEARISATION_ERROR_RATIO * affine:
        return None
    shifts, moved = {}, ""
    if space is not None and posterior is not None and len(posterior.summary):
        summary = posterior.summary
        all_shifts = curvature_shifts(series_model, space, posterior)
        for name in summary.index[summary["determined"].astype(bool)]:
            half = 0.5 * np.log(float(summary.at[name, "q95"]) / float(summary.at[name, "q05"]))
            shift = all_shifts.get(str(name), 0.0)
            if abs(np.log1p(shift)) > LINEARISATION_SHIFT_FRACTION * half:
                shifts[str(name)] = shift
        if not shifts:
            return None
        moved = " It would move " + ", ".join(
            f"{name} by {100 * shift:+.1f} %" for name, shift in shifts.items()
        ) + " (more than half its 90 % interval's half-width)."
    if getattr(series_model, "coordinates", "log") == "physical":
        where, remedy = "its physical coordinates", "metamodel.series_terms: auto"
    else:
        where = "log p"
        remedy = "metamodel.series_coordinates: physical (the default) or series_terms: auto"
    return {
        "kind": "linearisation",
        "affine_W": affine,
        "quadratic_W": quadratic,
        "shifts": shifts,
        "text": f"The series meta-model's straight line in {where} misses the detailed model's "
        f"hourly heat by {affine:.0f} W out of fold, one with a curvature term per parameter by "
        f"{quadratic:.0f} W: the calibrated parameters and their intervals can be biased by "
        "several per cent (a resistance's heat goes as 1 / (R + films); an EnergyPlus twin's "
        "roof, posterior median: +21 % with the straight line in log R, +3 % with the "
        f"curvature or in its conductance).{moved} Re-analyse with {remedy} (thermocal "
        "calibrate CAMPAIGN --reanalyse: no new simulation).",
    }


def outside_interval_flags(values, posterior) -> list[dict]:
    """Flags of the determined parameters whose calibrated value lies outside their own 90 %
    credible interval.

    The calibrated building is the best confirmed candidate (the lowest metric simulated: an
    optimum of the meta-model, the trust-region refinement, the posterior's median); the
    interval is the posterior's over the same samples. When they disagree the metric's minimum
    rests on something the meta-model does not reproduce (what curvature or interaction is
    left, or a model error the best run fits), and the interval, not the single value, is the
    answer to "how sure" (the multifamily twin's top-floor ceiling, 2026-11-30: calibrated
    4.566 m2 K/W, the interval [3.61, 4.56], the truth 4.737).

    Parameters
    ----------
    values : dict
        Calibrated parameters [unit of each].
    posterior : Posterior or None

    Returns
    -------
    list of dict
        ``kind`` "outside interval", ``parameter``, ``value``, ``q05``, ``q95``, ``text``.
    """
    if posterior is None or not len(posterior.summary):
        return []
    summary = posterior.summary
    flags = []
    for name in summary.index[summary["determined"].astype(bool)]:
        if name not in values:
            continue
        value = float(values[name])
        low, high = float(summary.at[name, "q05"]), float(summary.at[name, "q95"])
        if low <= value <= high:
            continue
        median = float(summary.at[name, "median"])
        flags.append(
            {
                "kind": "outside interval",
                "parameter": str(name),
                "value": value,
                "q05": low,
                "q95": high,
                "text": f"{name}: the calibrated value {value:.4g} lies outside its 90 % "
                f"credible interval [{low:.4g}, {high:.4g}] (median {median:.4g}): the best "
                "confirmed run and the posterior disagree; the metric's minimum rests on what "
                "the meta-model does not reproduce or on a model error it fits. Take the "
                "interval as the answer, not the single value.",
            }
        )
    return flags


def calibration_flags(
    space, values, metric, posterior, series_model, truth=None, *, floor_from=None
) -> list[dict]:
    """Warnings on a calibrated model: parameters at their bounds, a metric below the floor.

    * A parameter that ends within 2 % (of the logarithm of its range) of a sampling bound:
      either its range is too narrow or it absorbs an error of the model (the published
      method's failure mode: window U at its upper bound, SHGC at its lower one). Said with
      whether the posterior declares it determined and, with a known truth (the demo), whether
      the truth perturbed it at all.
    * The series meta-model's straight line in its coordinates where the curvature reproduces
      the detailed model much better out of fold and would change the answer
      (:func:`linearisation_flag`).
    * A determined parameter whose calibrated value lies outside its own 90 % credible
      interval (:func:`outside_interval_flags`; not again for one flagged at a bound).
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
    floor_from : (Posterior, SeriesSurrogate), optional
        The stage whose posterior and meta-model give the model-error floor (default
        ``posterior`` and ``series_model``): the first stage's, when the calibrated model
        comes from the zoom stage, whose posterior is confined to a small box around the first
        answer, so that its 5 % quantile is the box's minimum (measured on the EnergyPlus
        twin with low-e glazing: 0.768x the true envelope's metric, 0.04 % above that floor,
        unflagged).

    Returns
    -------
    list of dict
        ``kind`` ("at bound", "linearisation" or "below model error"), ``text`` and the
        numbers.
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
            limit = space.limit_lower[i] if side == "lower" else space.limit_upper[i]
            at_limit = np.isclose(bound, float(limit), rtol=1e-6)
            if at_limit:  # the range was clipped there: a wider one cannot help
                why = (
                    "the model's physical limit for it (its range reaches beyond): it likely "
                    "absorbs an error of the model"
                )
            elif name in determined:
                why = "the data determine it: its range may be too narrow"
            else:
                why = "the data do not determine it: it likely absorbs an error of the model"
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
                    f"{space.units[i]}, the bound {bound:.4g}; nominal {nominal[name]:.4g}): "
                    f"{why}.",
                    "at_limit": bool(at_limit),
                }
            )
    at_bound = {f["parameter"] for f in flags if f["kind"] == "at bound"}
    flags.extend(f for f in outside_interval_flags(values, posterior)
                 if f["parameter"] not in at_bound)  # fmt: skip
    curvature = linearisation_flag(series_model, space, posterior)
    if curvature is not None:
        flags.append(curvature)
    floor = model_error_floor(space, *(floor_from or (posterior, series_model)))
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
