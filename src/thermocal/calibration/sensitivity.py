"""Sensitivity of the campaign metric to the parameters, and selection of the critical ones.

* :func:`influence_ranking`: the ranking of the paper's Fig. 6, computed on the meta-model as the
  mean absolute elementary effect over the campaign's own samples (a Morris-type mu* evaluated at
  the sampled points rather than along trajectories), normalised to sum to 1.  For parameter
  ``i`` and sample ``x``: ``|f(x + h e_i) - f(x)| / h`` with ``h = step * (upper_i - lower_i)``
  (the step is taken downwards when ``x_i + h`` would leave the bounds), multiplied by the
  range width ``upper_i - lower_i`` so that effects are in metric units per full range and
  comparable between parameters.  The paper does not state its exact formula; this one is cheap
  (``n (d + 1)`` meta-model calls), local to where the samples are, and ranks like mu* of Morris.
* :func:`sobol_indices`: first-order and total Sobol indices with bootstrap confidence intervals
  (SALib, Saltelli/Jansen estimators), evaluated on the meta-model with every parameter uniform in
  its (clipped) bounds, the region the meta-model was trained on.
* :func:`morris_design` / :func:`morris_analyze` / :func:`morris_screening`: Morris elementary
  effects evaluated directly on the model (the evaluator), a cheap screening alternative that
  needs ``r (d + 1)`` model runs and no meta-model.  The design can be run through
  :func:`~thermocal.calibration.runner.run_campaign` like any sample set.
* :func:`top_k`: the ``k`` most influential parameters.

References
----------
.. [1] Saltelli, A., et al. (2010). Variance based sensitivity analysis of model output. Design
   and estimator for the total sensitivity index. Computer Physics Communications 181, 259-270.
.. [2] Morris, M. D. (1991). Factorial sampling plans for preliminary computational experiments.
   Technometrics 33, 161-174; Campolongo, F., et al. (2007), mu*.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
from SALib.analyze import morris as morris_analyzer
from SALib.analyze import sobol as sobol_analyzer
from SALib.sample import morris as morris_sampler
from SALib.sample import sobol as sobol_sampler

from thermocal.errors import ThermocalInputError

__all__ = [
    "influence_ranking",
    "morris_analyze",
    "morris_design",
    "morris_screening",
    "sobol_indices",
    "top_k",
]

Predict = Callable[[np.ndarray], np.ndarray]


def _bounds(names: Sequence[str], lower: Any, upper: Any) -> tuple[list[str], np.ndarray,
                                                                    np.ndarray]:
    names = [str(n) for n in names]
    lo = np.asarray(lower, dtype=float).ravel()
    hi = np.asarray(upper, dtype=float).ravel()
    if not (lo.size == hi.size == len(names)):
        raise ThermocalInputError(
            f"{len(names)} parameter names but {lo.size} lower and {hi.size} upper bounds"
        )
    bad = [n for n, a, b in zip(names, lo, hi, strict=True)
           if not (np.isfinite(a) and np.isfinite(b) and b > a)]
    if bad:
        raise ThermocalInputError(
            f"parameters {bad[:5]} have empty or infinite bounds (need lower < upper, finite)"
        )
    return names, lo, hi


def _problem(names: Sequence[str], lo: np.ndarray, hi: np.ndarray) -> dict[str, Any]:
    return {
        "num_vars": len(names),
        "names": list(names),
        "bounds": [[float(a), float(b)] for a, b in zip(lo, hi, strict=True)],
    }


def influence_ranking(
    predict: Predict,
    X: Any,
    lower: Any,
    upper: Any,
    *,
    names: Sequence[str] | None = None,
    step: float = 0.1,
) -> pd.Series:
    """Influence of each parameter on the meta-model: mean absolute elementary effect.

    Parameters
    ----------
    predict : callable
        ``predict(X) -> y`` of the meta-model, X of shape (m, d) [unit of each parameter] to
        y [unit of the metric].
    X : DataFrame or ndarray, shape (n, d)
        Points where the effects are taken (the campaign's samples) [unit of each parameter].
    lower, upper : array-like, shape (d,)
        Bounds of each parameter [unit of each parameter].
    names : sequence of str, optional
        Parameter names (default: the DataFrame's columns).
    step : float
        Finite-difference step as a fraction of each range [-].

    Returns
    -------
    Series
        Normalised influence (sums to 1) [-], indexed by name, sorted in decreasing order; its
        ``attrs["absolute"]`` holds the unnormalised values [unit of the metric].
    """
    if names is None:
        if not isinstance(X, pd.DataFrame):
            raise ThermocalInputError("influence_ranking: give names= or a DataFrame X")
        names = list(X.columns)
    Xa = X.to_numpy(dtype=float) if isinstance(X, pd.DataFrame) else np.asarray(X, float)
    names, lo, hi = _bounds(names, lower, upper)
    if Xa.ndim != 2 or Xa.shape[1] != len(names):
        raise ThermocalInputError(f"X must have {len(names)} columns, got shape {Xa.shape}")
    if not 0.0 < step <= 0.5:
        raise ThermocalInputError(f"step must be in (0, 0.5], got {step}")
    width = hi - lo
    base = np.asarray(predict(Xa), dtype=float)
    effects = np.empty(len(names))
    for i in range(len(names)):
        h = step * width[i]
        moved = Xa.copy()
        up = moved[:, i] + h <= hi[i]
        moved[:, i] = np.where(up, moved[:, i] + h, moved[:, i] - h)
        delta = np.asarray(predict(moved), dtype=float) - base
        effects[i] = np.mean(np.abs(delta)) / step  # per full range width
    total = effects.sum()
    rel = effects / total if total > 0 else np.zeros_like(effects)
    out = pd.Series(rel, index=pd.Index(names, name="parameter"), name="influence")
    order = np.argsort(-rel, kind="stable")
    out = out.iloc[order]
    out.attrs["absolute"] = dict(zip(out.index, effects[order].tolist(), strict=True))
    return out


def sobol_indices(
    predict: Predict,
    names: Sequence[str],
    lower: Any,
    upper: Any,
    *,
    n: int = 1024,
    num_resamples: int = 100,
    conf_level: float = 0.95,
    seed: int = 0,
) -> pd.DataFrame:
    """First-order and total Sobol indices of a (cheap) function, e.g. the meta-model.

    Parameters
    ----------
    predict : callable
        ``predict(X) -> y``, X of shape (m, d) [unit of each parameter].
    names : sequence of str
        Parameter names.
    lower, upper : array-like, shape (d,)
        Bounds; every parameter is uniform between them [unit of each parameter].
    n : int
        Base sample size [-]; ``n (d + 2)`` calls (a power of two keeps the Sobol' design
        balanced).
    num_resamples : int
        Bootstrap resamples for the confidence intervals [-].
    conf_level : float
        Confidence level of the intervals [-].
    seed : int
        Seed of the design and the bootstrap [-].

    Returns
    -------
    DataFrame
        Index: names; columns ``S1``, ``S1_conf``, ``ST``, ``ST_conf`` [-] (``*_conf`` is the
        half-width of the interval), sorted by ``ST`` descending.
    """
    names, lo, hi = _bounds(names, lower, upper)
    if int(n) < 2:
        raise ThermocalInputError(f"sobol_indices: n must be at least 2, got {n}")
    problem = _problem(names, lo, hi)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*balance properties.*")
        warnings.filterwarnings("ignore", message=".*power of 2.*")
        design = sobol_sampler.sample(problem, int(n), calc_second_order=False, seed=int(seed))
    y = np.asarray(predict(design), dtype=float).ravel()
    # constant up to round-off: a GP meta-model that predicts its mean everywhere varies by
    # 1e-12 of it, which SALib analysed into indices of 0 +- 0 (and printed its own warning)
    scale = max(float(np.max(np.abs(y))) if y.size else 0.0, 1e-300)
    if not np.std(y) > CONSTANT_RELATIVE_SPREAD * scale:
        raise ThermocalInputError(
            "sobol_indices: the function is constant over the bounds; no sensitivity to rank"
        )
    res = sobol_analyzer.analyze(problem, y, calc_second_order=False,
                                 num_resamples=int(num_resamples), conf_level=float(conf_level),
                                 seed=int(seed))
    frame = pd.DataFrame(
        {"S1": res["S1"], "S1_conf": res["S1_conf"], "ST": res["ST"], "ST_conf": res["ST_conf"]},
        index=pd.Index(names, name="parameter"),
    )
    return frame.sort_values("ST", ascending=False, kind="stable")


#: A meta-model whose predictions spread by less than this fraction of their magnitude over the
#: design is constant for the Sobol' indices [-].
CONSTANT_RELATIVE_SPREAD = 1e-9


def morris_design(
    names: Sequence[str],
    lower: Any,
    upper: Any,
    *,
    trajectories: int = 10,
    levels: int = 4,
    seed: int = 0,
) -> pd.DataFrame:
    """Morris one-at-a-time design: ``trajectories * (d + 1)`` parameter sets.

    Parameters
    ----------
    names : sequence of str
        Parameter names.
    lower, upper : array-like, shape (d,)
        Bounds [unit of each parameter].
    trajectories : int
        Number of trajectories ``r`` [-].
    levels : int
        Grid levels ``p`` (even) [-].
    seed : int
        Seed [-].

    Returns
    -------
    DataFrame
        Rows: design points (index ``sample``), columns: names [unit of each parameter].
    """
    names, lo, hi = _bounds(names, lower, upper)
    if int(trajectories) < 2:
        raise ThermocalInputError(f"Morris needs at least 2 trajectories, got {trajectories}")
    design = morris_sampler.sample(_problem(names, lo, hi), int(trajectories),
                                   num_levels=int(levels), seed=int(seed))
    frame = pd.DataFrame(design, columns=names)
    frame.index.name = "sample"
    return frame


def morris_analyze(
    design: pd.DataFrame,
    y: Any,
    lower: Any,
    upper: Any,
    *,
    levels: int = 4,
    num_resamples: int = 100,
    conf_level: float = 0.95,
    seed: int = 0,
) -> pd.DataFrame:
    """Morris elementary-effect statistics of model outputs on a :func:`morris_design`.

    Parameters
    ----------
    design : DataFrame
        The design (columns: names) [unit of each parameter].
    y : array-like
        Model output at each design point, in design order [unit of the metric].
    lower, upper : array-like
        Bounds used for the design [unit of each parameter].
    levels : int
        Grid levels of the design [-].
    num_resamples : int
        Bootstrap resamples for ``mu_star_conf`` [-].
    conf_level : float
        Confidence level [-].
    seed : int
        Seed of the bootstrap [-].

    Returns
    -------
    DataFrame
        Index: names; ``mu``, ``mu_star``, ``sigma``, ``mu_star_conf`` [unit of the metric]
        (effects over a full range), sorted by ``mu_star`` descending.
    """
    names, lo, hi = _bounds(list(design.columns), lower, upper)
    ya = np.asarray(y, dtype=float).ravel()
    if ya.size != len(design):
        raise ThermocalInputError(
            f"Morris: {ya.size} outputs for {len(design)} design points"
        )
    if not np.isfinite(ya).all():
        raise ThermocalInputError(
            "Morris: some outputs are NaN (failed runs); a trajectory with a failed run cannot "
            "be analysed, rerun the failed points"
        )
    res = morris_analyzer.analyze(_problem(names, lo, hi), design.to_numpy(dtype=float), ya,
                                  num_resamples=int(num_resamples), conf_level=float(conf_level),
                                  num_levels=int(levels), seed=int(seed))
    frame = pd.DataFrame(
        {k: np.asarray(res[k], dtype=float) for k in ("mu", "mu_star", "sigma", "mu_star_conf")},
        index=pd.Index(names, name="parameter"),
    )
    return frame.sort_values("mu_star", ascending=False, kind="stable")


def morris_screening(
    function: Any,
    names: Sequence[str],
    lower: Any,
    upper: Any,
    *,
    output: str | None = None,
    trajectories: int = 10,
    levels: int = 4,
    seed: int = 0,
) -> pd.DataFrame:
    """Morris screening run serially on a model function (cheap alternative to the meta-model).

    Parameters
    ----------
    function : callable or Evaluator
        ``function(parameters: dict) -> float | dict`` or an object with
        ``evaluate(parameters) -> dict``.
    names, lower, upper
        As :func:`morris_design` [unit of each parameter].
    output : str, optional
        Output to analyse when the function returns a dict.
    trajectories, levels, seed
        As :func:`morris_design`.

    Returns
    -------
    DataFrame
        As :func:`morris_analyze`.  For an expensive model, run :func:`morris_design` through
        :func:`~thermocal.calibration.runner.run_campaign` instead and call
        :func:`morris_analyze` on the stored outputs.
    """
    design = morris_design(names, lower, upper, trajectories=trajectories, levels=levels,
                           seed=seed)
    call = function.evaluate if hasattr(function, "evaluate") else function
    y = []
    for _, row in design.iterrows():
        value = call({str(k): float(v) for k, v in row.items()})
        if isinstance(value, Mapping):
            if output is None:
                if len(value) != 1:
                    raise ThermocalInputError(
                        f"morris_screening: the model returns outputs {sorted(value)}; name one "
                        "with output="
                    )
                (value,) = value.values()
            else:
                if output not in value:
                    raise ThermocalInputError(
                        f"morris_screening: output {output!r} not among {sorted(value)}"
                    )
                value = value[output]
        y.append(float(value))
    return morris_analyze(design, y, lower, upper, levels=levels, seed=seed)


def top_k(ranking: pd.Series | pd.DataFrame, k: int = 10, *, column: str | None = None
          ) -> list[str]:
    """The ``k`` most influential parameters.

    Parameters
    ----------
    ranking : Series or DataFrame
        Influence by parameter name (:func:`influence_ranking`), or a table from
        :func:`sobol_indices` (``column="ST"`` by default) or :func:`morris_analyze`
        (``"mu_star"``).
    k : int
        Number of parameters [-] (the paper: 10); capped at the number available.
    column : str, optional
        Column of a DataFrame to rank by.

    Returns
    -------
    list of str
        Names in decreasing influence.
    """
    if int(k) < 1:
        raise ThermocalInputError(f"metamodel.top_k must be at least 1, got {k}")
    if isinstance(ranking, pd.DataFrame):
        if column is None:
            column = "ST" if "ST" in ranking else "mu_star" if "mu_star" in ranking else None
        if column is None or column not in ranking:
            raise ThermocalInputError(
                f"top_k: say which column to rank by (columns: {list(ranking.columns)})"
            )
        ranking = ranking[column]
    order = ranking.sort_values(ascending=False, kind="stable")
    return [str(n) for n in order.index[: int(k)]]
