"""Reduced meta-model and interior-point optimisation of the metric (the paper's last step).

The reduced meta-model is refitted on the ``k`` critical parameters only (the other parameters
stay at their nominal values).  Its minimum and maximum within the bounds are searched with
:func:`scipy.optimize.minimize` (``method="trust-constr"``, an interior-point method for bound
constraints) from several starts: the best sample of the campaign (lowest metric for the minimum,
highest for the maximum) and seeded Sobol' points.  The optimiser works in the unit box
``u = (x - lower) / (upper - lower)`` so that parameters of very different magnitudes are equally
scaled; gradients are central finite differences of the meta-model, evaluated in one batched
call.  The barrier keeps the iterates strictly inside the box, so an end point within 0.1 % of the
range from a bound is put on the bound when that does not worsen the objective.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import pandas as pd
from scipy.optimize import Bounds, minimize
from scipy.stats import qmc

from thermocal.calibration.space import ParameterSpace
from thermocal.calibration.surrogate import make_surrogate
from thermocal.errors import ThermocalInputError

__all__ = ["Optimum", "ReducedOptimisation", "optimise_box", "optimise_reduced"]


@dataclass(frozen=True)
class Optimum:
    """The result of one optimisation (``sense`` ``"min"`` or ``"max"``).

    Attributes
    ----------
    sense : str
        ``"min"`` or ``"max"``.
    x : ndarray
        Optimal values of the optimised parameters [unit of each parameter].
    value : float
        Predicted metric at ``x`` [unit of the metric].
    starts : DataFrame
        One row per start: ``start`` (``"best sample"`` or ``"sobol k"``), the start and end
        points (``start:<name>``, ``end:<name>``), ``value`` [unit of the metric], ``success``,
        ``iterations``, ``message``.
    """

    sense: str
    x: np.ndarray
    value: float
    starts: pd.DataFrame


def optimise_box(
    function: Callable[[np.ndarray], np.ndarray],
    lower: Any,
    upper: Any,
    *,
    sense: Literal["min", "max"] = "min",
    starts: int = 8,
    initial: Sequence[Any] = (),
    names: Sequence[str] | None = None,
    seed: int = 0,
    maxiter: int = 200,
) -> Optimum:
    """Minimise or maximise a cheap vectorised function within bounds, from several starts.

    Parameters
    ----------
    function : callable
        ``function(X) -> y`` for X of shape (m, d) [unit of each parameter] (a meta-model's
        ``predict``).
    lower, upper : array-like, shape (d,)
        Bounds [unit of each parameter].
    sense : {"min", "max"}
        Minimise or maximise.
    starts : int
        Total number of starts [-] (``initial`` points first, then seeded Sobol' points).
    initial : sequence of array-like
        Explicit start points, e.g. the best sample [unit of each parameter].
    names : sequence of str, optional
        Parameter names for the ``starts`` table.
    seed : int
        Seed of the Sobol' start points [-].
    maxiter : int
        Iteration limit of each ``trust-constr`` run [-].

    Returns
    -------
    Optimum
    """
    lo = np.asarray(lower, dtype=float).ravel()
    hi = np.asarray(upper, dtype=float).ravel()
    d = lo.size
    if hi.size != d or not np.all(np.isfinite(lo) & np.isfinite(hi)) or np.any(hi <= lo):
        raise ThermocalInputError("optimise: bounds must be finite with lower < upper")
    if sense not in ("min", "max"):
        raise ThermocalInputError(f"optimise: sense must be 'min' or 'max', got {sense!r}")
    if int(starts) < 1:
        raise ThermocalInputError(f"optimisation.starts must be at least 1, got {starts}")
    names = [f"x{i}" for i in range(d)] if names is None else [str(n) for n in names]
    width = hi - lo
    sign = 1.0 if sense == "min" else -1.0

    def objective(u: np.ndarray) -> float:
        # trust-constr may step a hair outside the box: never evaluate outside the bounds
        u = np.clip(u, 0.0, 1.0)
        return sign * float(np.asarray(function((lo + u * width)[None, :])).ravel()[0])

    step = 1e-5

    def objective_and_gradient(u: np.ndarray) -> tuple[float, np.ndarray]:
        # one batched call: the point and central differences (one-sided at the bounds)
        u = np.clip(u, 0.0, 1.0)
        up = np.minimum(u + step, 1.0)
        down = np.maximum(u - step, 0.0)
        pts = np.vstack([u[None, :], np.tile(u, (d, 1)), np.tile(u, (d, 1))])
        pts[1 + np.arange(d), np.arange(d)] = up
        pts[1 + d + np.arange(d), np.arange(d)] = down
        values = sign * np.asarray(function(lo + pts * width), dtype=float).ravel()
        grad = (values[1 : 1 + d] - values[1 + d :]) / (up - down)
        return float(values[0]), grad

    start_points: list[tuple[str, np.ndarray]] = []
    for i, p in enumerate(initial):
        u0 = (np.asarray(p, dtype=float).ravel() - lo) / width
        start_points.append((f"initial {i}" if i else "best sample", np.clip(u0, 0.0, 1.0)))
    n_random = max(int(starts) - len(start_points), 0)
    if n_random:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*balance properties.*")
            pts = qmc.Sobol(d, scramble=True, rng=np.random.default_rng(int(seed))).random(n_random)
        start_points += [(f"sobol {k}", p) for k, p in enumerate(pts)]

    rows = []
    best: tuple[float, np.ndarray] | None = None
    for label, u0 in start_points:
        # keep the start strictly inside for the interior-point barrier
        u0 = np.clip(u0, 1e-6, 1.0 - 1e-6)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = minimize(
                objective_and_gradient,
                u0,
                method="trust-constr",
                jac=True,
                bounds=Bounds(np.zeros(d), np.ones(d)),
                options={"maxiter": int(maxiter), "gtol": 1e-8, "xtol": 1e-10},
            )
        u = _snap_to_bounds(objective, np.clip(res.x, 0.0, 1.0))
        value = sign * objective(u)
        row = {"start": label}
        row.update({f"start:{n}": float(v) for n, v in zip(names, lo + u0 * width, strict=True)})
        row.update({f"end:{n}": float(v) for n, v in zip(names, lo + u * width, strict=True)})
        row.update(
            value=value,
            success=bool(res.success),
            iterations=int(res.nit),
            message=str(res.message),
        )
        rows.append(row)
        if best is None or sign * value < sign * best[0]:
            best = (value, lo + u * width)
    assert best is not None
    return Optimum(sense=sense, x=best[1], value=float(best[0]), starts=pd.DataFrame(rows))


def _snap_to_bounds(
    objective: Callable[[np.ndarray], float], u: np.ndarray, tol: float = 1e-3
) -> np.ndarray:
    """Put coordinates that the barrier left just inside a bound onto it, when that helps."""
    u = u.copy()
    best = objective(u)
    for i in np.flatnonzero((u < tol) | (u > 1.0 - tol)):
        trial = u.copy()
        trial[i] = 0.0 if u[i] < tol else 1.0
        value = objective(trial)
        if value <= best:
            u, best = trial, value
    return u


@dataclass(frozen=True)
class ReducedOptimisation:
    """Reduced meta-model and its minimum and maximum.

    Attributes
    ----------
    names : list of str
        The critical parameters that were optimised.
    surrogate : SVRSurrogate or GPSurrogate
        The reduced meta-model (fitted on ``names`` only).
    minimum, maximum : Optimum
        Optimisation results (``x`` in the order of ``names``).
    nominal : dict
        Nominal values of every parameter of the space [unit of each parameter].
    """

    names: list[str]
    surrogate: Any
    minimum: Optimum
    maximum: Optimum
    nominal: dict[str, float] = field(default_factory=dict)

    def parameters(self, sense: Literal["min", "max"] = "min") -> dict[str, float]:
        """Full parameter set: optimised critical parameters, the others at nominal [unit]."""
        opt = self.minimum if sense == "min" else self.maximum
        out = dict(self.nominal)
        out.update({n: float(v) for n, v in zip(self.names, opt.x, strict=True)})
        return out

    def table(self) -> pd.DataFrame:
        """The paper's Table 1: nominal, min-metric and max-metric values with units."""
        from thermocal.calibration.space import parameter_unit

        return pd.DataFrame(
            {
                "unit": [parameter_unit(n) for n in self.names],
                "nominal": [self.nominal.get(n, np.nan) for n in self.names],
                "min_metric": self.minimum.x,
                "max_metric": self.maximum.x,
            },
            index=pd.Index(self.names, name="parameter"),
        )


def optimise_reduced(
    X: pd.DataFrame,
    y: Any,
    space: ParameterSpace,
    critical: Sequence[str],
    *,
    surrogate: Any = "svr",
    starts: int = 8,
    seed: int = 0,
    surrogate_options: dict[str, Any] | None = None,
) -> ReducedOptimisation:
    """Refit the meta-model on the critical parameters and find its minimum and maximum.

    Parameters
    ----------
    X : DataFrame
        Parameter values of the successful samples (columns include ``critical``) [unit of
        each parameter].
    y : array-like
        Metric of each sample [unit of the metric].
    space : ParameterSpace
        Gives the bounds (:attr:`ParameterSpace.lower`/``upper``, i.e. the sampling range
        clipped to the physical limits) and the nominal values.
    critical : sequence of str
        Parameters to optimise (e.g. :func:`~thermocal.calibration.sensitivity.top_k`).
    surrogate : {"svr", "gp"} or unfitted surrogate object
        Kind of reduced meta-model, or an object with ``fit``/``predict``.
    starts : int
        Starts per optimisation [-] (the best sample plus ``starts - 1`` Sobol' points).
    seed : int
        Seed of the start points and of the meta-model's cross-validation [-].
    surrogate_options : dict, optional
        Keyword arguments of the meta-model when ``surrogate`` is a kind.

    Returns
    -------
    ReducedOptimisation
    """
    critical = [str(n) for n in critical]
    if not critical:
        raise ThermocalInputError("optimise_reduced: no critical parameters given")
    missing = [n for n in critical if n not in X.columns]
    if missing:
        raise ThermocalInputError(f"optimise_reduced: parameters {missing[:5]} not in the samples")
    idx = [space.index(n) for n in critical]
    ya = np.asarray(y, dtype=float).ravel()
    if isinstance(surrogate, str):
        options = {"seed": seed, **(surrogate_options or {})}
        model = make_surrogate(surrogate, **options)  # type: ignore[arg-type]
    else:
        model = surrogate
    model.fit(X[critical], ya)
    lo, hi = space.lower[idx], space.upper[idx]
    Xc = X[critical].to_numpy(dtype=float)

    def predict(Z: np.ndarray) -> np.ndarray:
        return np.asarray(model.predict(Z), dtype=float)

    results = {}
    for sense, pick in (("min", np.argmin), ("max", np.argmax)):
        # the series meta-model's minimum is a bounded least-squares problem (exact when it is
        # affine in log p), its maximum at a vertex (with curvature, polished from the best one)
        exact = model.box_optimum(sense, lo, hi) if hasattr(model, "box_optimum") else None
        if exact is not None:
            x, value = exact
            how = "bounded least squares" if sense == "min" else "every vertex of the box"
            results[sense] = Optimum(
                sense=sense,
                x=np.asarray(x, dtype=float),
                value=float(value),
                starts=pd.DataFrame(
                    [
                        {
                            "start": f"exact ({how})",
                            "value": float(value),
                            **{f"end:{n}": float(v) for n, v in zip(critical, x, strict=True)},
                            "success": True,
                        }
                    ]
                ),
            )
            continue
        results[sense] = optimise_box(
            predict,
            lo,
            hi,
            sense=sense,
            starts=starts,
            initial=[Xc[int(pick(ya))]],
            names=critical,
            seed=seed,
        )
    return ReducedOptimisation(
        names=critical,
        surrogate=model,
        minimum=results["min"],
        maximum=results["max"],
        nominal=space.nominal_dict(),
    )
