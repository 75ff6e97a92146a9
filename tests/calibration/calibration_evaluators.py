"""Cheap evaluators for the campaign tests (importable by worker processes)."""

from __future__ import annotations

import math
import os
import time


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
