"""The local ("zoom") campaign: a second batch of samples around the first calibration's answer.

A meta-model fitted over the whole sampled range (+-75 % by default) is biased where the metric
is curved: the series meta-model writes each hour's identified heat as affine in
``log(p / p_nominal)``, and the heat through an element goes as ``1 / (R + films)``, convex in
``log R``; a straight line fitted over ``[0.25, 1.75] x nominal`` crosses zero several per cent
from where the curve does (tests/reference/calibration_energyplus_5zone/diagnose_roof.md). The
bias of a linear fit to a curve grows with the square of the interval it is fitted over, so
the same meta-model refitted on samples in a box a few posterior standard deviations wide
around the first answer is nearly unbiased there. This is the sequential design of Bayesian
calibration (Kennedy and O'Hagan 2001; the local refinement of the design around the posterior
mode, e.g. Higdon et al. 2008): a cheap global batch finds the region, a second batch resolves
it.

The functions here are the stage's pure parts: the box (:func:`zoom_box`), its Sobol' design
(:func:`zoom_design`), the campaign space restricted to it (:func:`box_space`) and which of the
first batch's samples fall in it (:func:`inside_box`). :func:`run_zoom` simulates the design
through the campaign's store (the ``runs`` table, like every analysis run), so a resumed
campaign or a re-analysis reads the samples instead of simulating them again.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import pandas as pd

from thermocal.calibration.sampling import unit_sample

__all__ = [
    "ZOOM_MIN_HALF_WIDTH",
    "ZOOM_STANDARD_DEVIATIONS",
    "box_space",
    "inside_box",
    "narrowed",
    "run_zoom",
    "zoom_box",
    "zoom_design",
]

#: half-width of the box in posterior standard deviations of log(p) [-]: a first posterior
#: that is too narrow by a factor of 1.8 (its 90 % interval, +-1.64 sd, missing the truth by
#: 3 sd) still has the truth inside
ZOOM_STANDARD_DEVIATIONS = 3.0
#: smallest half-width of the box in log(p) [-] (+-10 %): the bias of an affine-in-log fit over
#: the whole +-75 % range of a 1/(R + films) heat path is about 7 % (diagnose_roof.md), so the
#: box always covers the first stage's own curvature bias however narrow its posterior is
ZOOM_MIN_HALF_WIDTH = 0.1


def zoom_box(
    lower,
    upper,
    center,
    log_sd=None,
    *,
    standard_deviations: float = ZOOM_STANDARD_DEVIATIONS,
    min_half_width: float = ZOOM_MIN_HALF_WIDTH,
) -> tuple[np.ndarray, np.ndarray]:
    """The local box around the first answer, in each parameter's own unit.

    Half-width in ``log(p)``: ``standard_deviations`` times the first posterior's standard
    deviation of ``log(p)``, at least ``min_half_width``; the box is then clipped to the
    campaign's bounds (a parameter the data do not determine keeps its whole range).

    Parameters
    ----------
    lower, upper : array-like, shape (d,)
        The campaign's bounds [unit of each parameter], positive.
    center : array-like, shape (d,)
        The first answer [unit of each parameter], positive.
    log_sd : array-like, shape (d,), optional
        Posterior standard deviation of ``log(p)`` [-]; None or NaN: the whole range.
    standard_deviations : float
        Half-width in posterior standard deviations [-].
    min_half_width : float
        Smallest half-width in ``log(p)`` [-].

    Returns
    -------
    box_lower, box_upper : ndarray, shape (d,)
        [unit of each parameter]
    """
    lo, hi = np.log(np.asarray(lower, float)), np.log(np.asarray(upper, float))
    c = np.clip(np.log(np.asarray(center, float)), lo, hi)
    sd = np.full(c.shape, np.inf) if log_sd is None else np.asarray(log_sd, float)
    half = np.where(np.isfinite(sd), np.maximum(standard_deviations * sd, min_half_width), np.inf)
    return np.exp(np.maximum(lo, c - half)), np.exp(np.minimum(hi, c + half))


#: a box narrower than this fraction of the sampled range (in log p) narrows the parameter [-]
NARROWED_FRACTION = 0.5


def narrowed(lower, upper, box_lower, box_upper, fraction: float = NARROWED_FRACTION):
    """Which parameters the box narrows to less than ``fraction`` of the campaign's range in
    ``log(p)`` (bool array). With none, the zoom campaign would only be more samples over the
    whole range: the first posterior determined nothing to zoom on."""
    whole = np.log(np.asarray(upper, float) / np.asarray(lower, float))
    width = np.log(np.asarray(box_upper, float) / np.asarray(box_lower, float))
    return width < fraction * whole


def posterior_log_sd(draws: pd.DataFrame, names) -> np.ndarray:
    """Standard deviation of ``log(p)`` of each name over posterior draws (NaN: not drawn) [-]."""
    return np.array(
        [float(np.std(np.log(draws[n].to_numpy(float)))) if n in draws else np.nan for n in names]
    )


def zoom_design(
    names, box_lower, box_upper, n: int, *, method: str = "sobol", seed: int = 0
) -> pd.DataFrame:
    """A seeded low-discrepancy design of ``n`` points, uniform in ``log(p)`` over the box.

    Parameters
    ----------
    names : sequence of str
    box_lower, box_upper : array-like, shape (d,)
        [unit of each parameter], positive.
    n : int
        Points [-].
    method : {"sobol", "lhs", "halton"}
    seed : int

    Returns
    -------
    DataFrame
        Rows: points (index ``sample`` 0..n-1), columns ``names`` [unit of each parameter].
    """
    lo, hi = np.log(np.asarray(box_lower, float)), np.log(np.asarray(box_upper, float))
    u = unit_sample(len(lo), n, method=method, seed=seed)
    frame = pd.DataFrame(np.exp(lo + u * (hi - lo)), columns=list(names))
    frame.index.name = "sample"
    return frame


def box_space(space, box_lower, box_upper):
    """The campaign's space with its sampling range replaced by the box (same names, nominal
    values and physical limits), for the local meta-model's optimisation and refinement."""
    return dataclasses.replace(
        space,
        range_lower=np.asarray(box_lower, float).copy(),
        range_upper=np.asarray(box_upper, float).copy(),
    )


def inside_box(X: pd.DataFrame, box_lower, box_upper) -> np.ndarray:
    """Which rows of ``X`` [unit of each parameter] lie in the box (bool array)."""
    values = X.to_numpy(float)
    return np.all((values >= np.asarray(box_lower)) & (values <= np.asarray(box_upper)), axis=1)


@dataclass
class _RunsTable:
    """The store's ``runs`` table seen as a campaign store by
    :func:`thermocal.calibration.runner.run_campaign` (``pending`` and ``record``): a design
    point is done when a run with its parameters is stored."""

    store: object
    design: pd.DataFrame
    failed: int = 0

    def _parameters(self, i) -> dict:
        return {str(k): float(v) for k, v in self.design.loc[i].items()}

    def pending(self, indices, *, retry_failed: bool = False) -> list[int]:
        return [int(i) for i in indices if self.store.find_run(self._parameters(i)) is None]

    def record(self, result) -> bool:
        if result.error is not None:
            self.failed += 1
            return False
        self.store.record_run(result.parameters, result.outputs)
        return True


def run_zoom(runs, design: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame, dict]:
    """The zoom design's runs: read from the store, the missing ones simulated (in parallel like
    the campaign, with ``runs.workers`` processes or ``runs.scheduler``) and stored.

    Parameters
    ----------
    runs : RunCache
        The analysis' runs; without an evaluator (a re-analysis) nothing is simulated.
    design : DataFrame
        From :func:`zoom_design` [unit of each parameter].

    Returns
    -------
    X : DataFrame
        The points with a successful run [unit of each parameter].
    outputs : DataFrame
        Their outputs, one row each (columns as the store's samples') [unit of each].
    counts : dict
        ``simulated``, ``from_store``, ``failed`` and ``missing`` (not stored in a
        re-analysis) [-].
    """
    from thermocal.calibration.runner import run_campaign

    table = _RunsTable(runs.store, design)
    pending = table.pending(design.index)
    simulated = 0
    if pending and runs.evaluator is not None:
        summary = run_campaign(
            runs.evaluator,
            design,
            table,
            workers=getattr(runs, "workers", 1),
            scheduler=getattr(runs, "scheduler", None),
            progress=False,
            description="zoom campaign",
        )
        simulated = summary.evaluated - summary.failed
        runs.simulated += simulated
    rows, outputs = [], []
    for i in design.index:
        found = runs.store.find_run(table._parameters(i))
        if found is not None:
            rows.append(i)
            outputs.append(found[0])
    counts = {
        "simulated": int(simulated),
        "from_store": int(len(rows) - simulated),
        "failed": int(table.failed),
        "missing": int(len(design) - len(rows) - table.failed),
    }
    runs.reused += counts["from_store"]
    return design.loc[rows], pd.DataFrame(outputs, index=pd.Index(rows, name="sample")), counts
