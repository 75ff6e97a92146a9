"""The choice of the meta-model (cross-validated, ``kind: auto``), its reduced form for the
optimiser, and the Sobol indices it gives (or a note saying why not).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

#: above this many samples, ``kind="auto"`` does not try the Gaussian process (its fit grows
#: as the cube of the sample count, with one length scale per parameter)
AUTO_GP_MAX_SAMPLES = 400


def sobol_or_note(surrogate, space, lower, upper, seed: int, kind: str, notes: list[str]):
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


def series_terms_note(model, optimum: bool = False) -> str | None:
    """The series meta-model's form in words, for the report's notes (None: not a series
    meta-model).

    Parameters
    ----------
    model : SeriesSurrogate or other
        Fitted (its out-of-fold comparison of the two forms is computed when missing).
    optimum : bool
        Whether it also gives the optimum (the campaign's meta-model is the series one).

    Returns
    -------
    str or None
    """
    terms = getattr(model, "terms_", None)
    if terms is None:
        return None
    physical = getattr(model, "coordinates", "log") == "physical"
    coordinates = (
        "each construction's conductance 1 / (R + films), window U, SHGC and air change "
        "rates, the logarithm of the rest"
        if physical
        else "log p, the published form"
    )
    form = (
        "with a curvature term per parameter (quadratic)" if terms == "quadratic" else "affine"
    )
    errors = model.compare_terms()
    return (
        f"Series meta-model (posterior{' and optimum' if optimum else ''}): "
        f"the hourly heat {form} in {coordinates} (metamodel.series_coordinates: "
        f"{'physical' if physical else 'log'}); out-of-fold hourly error "
        f"{errors['affine']:.0f} W affine, {errors['quadratic']:.0f} W with curvature "
        f"(metamodel.series_terms: {model.terms}). A straight line in log p over a wide prior "
        "biases the optimum of the resistances (their heat goes as 1 / (R + films)); the "
        "physical coordinates or the curvature remove that bias."
    )


def surrogate_for(kind: str, metamodel, series, space, seed: int, segments=None, terms=None):
    """An unfitted meta-model of ``kind`` (a name, or the series model with its data; its form
    ``terms``, default the campaign's ``metamodel.series_terms``)."""
    if kind != "series":
        return kind
    from thermocal.calibration.surrogate import SeriesSurrogate

    return SeriesSurrogate(
        series=series,
        nominal=space.nominal_dict(),
        cv_folds=metamodel.cv_folds,
        seed=seed,
        segments=segments,
        terms=terms or getattr(metamodel, "series_terms", "affine"),
        coordinates=getattr(metamodel, "series_coordinates", "physical"),
    )


def reduced_surrogate(kind: str, metamodel, series, space, seed: int, segments=None, terms=None):
    """The unfitted reduced meta-model (no out-of-fold scores: only its optimum is used; a
    series model takes the form ``terms`` the campaign's model chose)."""
    model = surrogate_for(kind, metamodel, series, space, seed, segments, terms)
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
    series_terms: str = "affine",
    series_coordinates: str = "physical",
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
    when series are given) and keeps the highest cross-validated R2. ``series_terms`` is the
    series model's form (``"auto"``, ``"affine"`` or ``"quadratic"``) and
    ``series_coordinates`` what it is affine in (``"physical"`` or ``"log"``,
    :mod:`thermocal.calibration.coordinates`).

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
                series=series,
                nominal=nominal,
                cv_folds=cv_folds,
                seed=seed,
                segments=segments,
                terms=series_terms,
                coordinates=series_coordinates,
            )
        else:
            model = make_surrogate(k, cv_folds=cv_folds, log_target=log_target, seed=seed)
        fitted[k] = model.fit(X, y)
    scores = {k: float(model.cv_r2_) for k, model in fitted.items()}
    best = max(scores, key=scores.get)
    return fitted[best], best, scores
