"""Cheap evaluators for the campaign tests (importable by worker processes), and a synthetic
two-element heat series for the meta-model's tests."""

from __future__ import annotations

import math
import os
import time

import numpy as np


def roof_and_wall_heat(X, truth, films: float) -> np.ndarray:
    """Identified heat left over in 200 unoccupied hours [W] of envelopes ``X`` (rows: roof
    and wall resistance [m2 K/W]): each element's conduction ``UA dT`` with ``U = 1 / (R +
    films)``, minus the ``truth``'s (the sensors), plus a small error common to every sample;
    zero (but for that error) at the truth, convex in log R like a real heat path.

    Parameters
    ----------
    X : array-like (n, 2) [m2 K/W]
    truth : array-like (2,) [m2 K/W]
    films : float
        Surface resistance added to both elements [m2 K/W].

    Returns
    -------
    ndarray (n, 200) [W]
    """
    rng = np.random.default_rng(7)
    hours = np.arange(200)
    roof_dt = 400.0 * (1.2 + np.sin(2 * np.pi * hours / 24.0)) + 50.0 * rng.standard_normal(200)
    wall_dt = 600.0 * (1.0 + 0.6 * np.cos(2 * np.pi * hours / 37.0))
    error = 2.0 * rng.standard_normal(200)
    u = 1.0 / (np.atleast_2d(X) + films) - 1.0 / (np.asarray(truth) + films)
    return u[:, :1] * roof_dt + u[:, 1:] * wall_dt + error


class QuadraticEvaluator:
    """``metric = sum((p_i - 1)^2)`` with an optional sleep and an evaluation log.

    State is built lazily on the first call (``builds`` counts how often, per process, in the
    log) to check that it happens once per worker.
    """

    def __init__(self, log: str | os.PathLike | None = None, sleep: float = 0.0,
                 fail_above: float | None = None) -> None:
        self.log = None if log is None else str(log)
        self.sleep = float(sleep)
        self.fail_above = fail_above
        self._state = None

    def _build(self) -> None:
        self._state = {"pid": os.getpid()}
        if self.log:
            with open(self.log, "a") as fh:
                fh.write(f"build {os.getpid()}\n")

    def evaluate(self, parameters: dict[str, float]) -> dict[str, float]:
        if self._state is None:
            self._build()
        if self.sleep:
            time.sleep(self.sleep)
        first = parameters[min(parameters)]
        if self.fail_above is not None and first > self.fail_above:
            raise RuntimeError(f"synthetic failure: {min(parameters)} = {first} is too large")
        metric = sum((v - 1.0) ** 2 for _, v in sorted(parameters.items()))
        out = {"metric": metric, "log_metric": math.log1p(metric)}
        if self.log:
            with open(self.log, "a") as fh:
                fh.write(f"eval {os.getpid()} {sorted(parameters.items())!r}\n")
        return out
