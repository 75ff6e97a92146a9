"""The trust-region refinement of the calibrated minimum with the full model."""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.calibration.metric import metric_value


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
    series_terms: str = "affine",
    series_coordinates: str = "physical",
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
    (:class:`thermocal.calibration.workflow.RunCache`): found in the store when run before; in
    a re-analysis the refinement stops at the first candidate that is not stored. Only the
    ``movable`` parameters (default all) change; the others keep the start's values.
    ``series_terms``, ``series_coordinates``: the series meta-model's form and coordinates
    (the campaign's, see :class:`~thermocal.calibration.surrogate.SeriesSurrogate`).

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
                series=Ss,
                nominal=space.nominal_dict(),
                cv_folds=0,
                segments=segments,
                terms=series_terms,
                coordinates=series_coordinates,
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
        # exp(log(bound)) can exceed the bound by a rounding error the model refuses (a window
        # U-value of 10.000000000000002 W/(m2 K))
        point = np.clip(np.exp(z), space.lower, space.upper)
        values = {**space.nominal_dict(), **dict(zip(names, point, strict=True))}
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
        Xs = np.vstack([Xs, point])
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
