"""What counts as converged, flagged or in agreement: the engine's tolerances, the agreement of
optimiser starts, and the one-thread context of small linear algebra.

Shared by the optimiser (:mod:`~thermocal.statespace.estimation`), the results
(:mod:`~thermocal.statespace.results`), the profiles and the diagnostics.
"""

from __future__ import annotations

import math

import numpy as np

#: |correlation| above which a pair of estimates is flagged (Madsen et al. 2016).
CORRELATION_LIMIT = 0.98


#: Relative distance to a bound below which an estimate is flagged.
BOUND_TOLERANCE = 1e-3


#: A fit has converged when a Newton step from its end point (gradient and Hessian of the
#: log-likelihood in theta, parameters at a bound and unidentifiable directions left out) would
#: gain less than this [log-likelihood units]; immaterial next to likelihood-ratio critical
#: values (1.92 log-units for one degree of freedom at 5 %).
CONVERGENCE_GAIN = 5e-2


#: Starts that end within this of the best log-likelihood reached the same optimum
#: [log-likelihood units]; 1/20 of the 5 % likelihood-ratio critical value for one degree of
#: freedom (1.92), far above the optimiser's stall tolerance (1e-3 over 10 iterations).
AGREEMENT_TOLERANCE = 0.1


def start_agreement(start_loglikes, tolerance: float = AGREEMENT_TOLERANCE) -> dict:
    """How many optimiser starts reached the best log-likelihood.

    Returns
    -------
    dict
        ``n_starts`` (starts with a finite end), ``n_best`` (ends within ``tolerance`` of the
        best), ``best`` and ``runner_up`` (the best end outside the tolerance, NaN when all
        agree) [log-likelihood units].
    """
    ends = np.asarray([v for v in start_loglikes if v is not None and math.isfinite(v)])
    if not ends.size:
        return {"n_starts": 0, "n_best": 0, "best": math.nan, "runner_up": math.nan}
    best = float(ends.max())
    near = ends >= best - tolerance
    others = ends[~near]
    return {
        "n_starts": int(ends.size),
        "n_best": int(near.sum()),
        "best": best,
        "runner_up": float(others.max()) if others.size else math.nan,
    }


def one_blas_thread():
    """A context limiting BLAS/LAPACK to one thread (``threadpoolctl``), restored on exit.

    The linear algebra of the optimisers is on matrices of 20 x 20 or smaller; OpenBLAS'
    threads only wait for each other there, and on a loaded machine they spin: scipy 1.17's
    SLSQP on 19 parameters took 18 ms per iteration with two BLAS threads against 1 ms with
    one (measured 2026-11-25, load ~7), the profile of a four-state model 16-18 CPU-s against
    3.7-4.7 s.
    """
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - threadpoolctl comes with scikit-learn
        from contextlib import nullcontext

        return nullcontext()
    return threadpool_limits(1)
