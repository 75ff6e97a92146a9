"""Deterministic sampling of a :class:`~thermocal.calibration.space.ParameterSpace`.

Points come from :mod:`scipy.stats.qmc` (scrambled Sobol', Latin hypercube or scrambled Halton,
seeded), are scaled onto the *unclipped* sampling range and then clipped to the physical limits,
counting the clipped values per parameter (the paper samples +-10000 % and then constrains).

Sobol' points have their balance properties only for a power-of-two number of samples (64, 128,
256, 512, ...); other counts are accepted silently (scipy's warning is suppressed) and remain a
good low-discrepancy design, just not a perfectly balanced one.  The first ``m`` points of a
Sobol' or Halton design of ``n > m`` points equal the design of ``m`` points with the same seed.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Literal

import numpy as np
import pandas as pd
from scipy.stats import qmc

from thermocal.calibration.space import ParameterSpace
from thermocal.errors import ThermocalInputError

__all__ = ["METHODS", "SampleSet", "sample", "unit_sample"]

METHODS = ("sobol", "lhs", "halton")


@dataclass(frozen=True)
class SampleSet:
    """Samples of a parameter space.

    Attributes
    ----------
    values : DataFrame
        Rows: samples (index ``sample`` = 0..n-1), columns: parameter names; physical values
        after clipping [unit of each parameter].
    clip_counts : DataFrame
        Per parameter: ``lower``, ``upper``, ``total`` clipped values and their ``fraction`` [-].
    method : str
        Sampler name.
    seed : int
        Seed of the sampler.
    """

    values: pd.DataFrame
    clip_counts: pd.DataFrame
    method: str
    seed: int

    def __len__(self) -> int:
        return len(self.values)


def unit_sample(
    dimension: int,
    n: int,
    *,
    method: Literal["sobol", "lhs", "halton"] = "sobol",
    seed: int = 0,
) -> np.ndarray:
    """Seeded low-discrepancy points in the unit hypercube.

    Parameters
    ----------
    dimension : int
        Number of parameters [-].
    n : int
        Number of points [-] (powers of two preferred for Sobol').
    method : {"sobol", "lhs", "halton"}
        Scrambled Sobol', Latin hypercube or scrambled Halton.
    seed : int
        Seed [-]; the same seed gives the same points.

    Returns
    -------
    ndarray, shape (n, dimension)
        Points in [0, 1) [-].
    """
    n = _check_count(n)
    if int(dimension) < 1:
        raise ThermocalInputError(f"dimension must be at least 1, got {dimension!r}")
    if method not in METHODS:
        raise ThermocalInputError(
            f"sampling.method {method!r} is unknown; use one of {', '.join(METHODS)}"
        )
    rng = np.random.default_rng(int(seed))
    if method == "sobol":
        engine = qmc.Sobol(int(dimension), scramble=True, rng=rng)
    elif method == "lhs":
        engine = qmc.LatinHypercube(int(dimension), scramble=True, rng=rng)
    else:
        engine = qmc.Halton(int(dimension), scramble=True, rng=rng)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*balance properties.*")
        return engine.random(n)


def sample(
    space: ParameterSpace,
    n: int,
    method: Literal["sobol", "lhs", "halton"] = "sobol",
    *,
    seed: int = 0,
) -> SampleSet:
    """Sample a parameter space: uniform in the unclipped range, then clipped to the limits.

    Parameters
    ----------
    space : ParameterSpace
        The parameters, ranges and limits.
    n : int
        Number of samples [-] (the paper: 500; Sobol' is best balanced at powers of two).
    method : {"sobol", "lhs", "halton"}
        Sampler.
    seed : int
        Seed [-]; same space, ``n``, method and seed give identical samples.

    Returns
    -------
    SampleSet
        ``values`` (physical values [unit of each parameter]) and ``clip_counts``.
    """
    u = unit_sample(space.dimension, n, method=method, seed=seed)
    values, counts = space.clip(space.scale(u))
    frame = pd.DataFrame(values, columns=list(space.names))
    frame.index.name = "sample"
    return SampleSet(values=frame, clip_counts=counts, method=method, seed=int(seed))


def _check_count(n: object) -> int:
    try:
        value = int(n)  # type: ignore[call-overload]
    except (TypeError, ValueError):
        raise ThermocalInputError(f"sampling.samples must be a whole number, got {n!r}") from None
    if value != n or value < 1:
        raise ThermocalInputError(
            f"sampling.samples must be a positive whole number (e.g. 500), got {n!r}"
        )
    return value
