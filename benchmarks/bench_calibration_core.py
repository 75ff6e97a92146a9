"""Benchmark of the calibration core after the campaign: meta-model, sensitivity, optimisation.

500 samples x 70 parameters with a synthetic metric (10 influential parameters with decreasing
weights, curvature and interactions, 60 nearly inert ones), as the paper's 500 x 69 campaign.
Steps timed: SVR fit with grid search and 5-fold cross-validation, Sobol indices on the
meta-model (SALib, n = 1024, 73 728 meta-model calls), the influence ranking (Fig. 6) and top-10,
the reduced meta-model with min/max optimisation (8 starts each).  Target: <= 30 s on 2 cores.

Run: ``python benchmarks/bench_calibration_core.py``; prints a markdown table.
"""

from __future__ import annotations

import time

import numpy as np

from thermocal.calibration.optimise import optimise_reduced
from thermocal.calibration.sampling import sample
from thermocal.calibration.sensitivity import influence_ranking, sobol_indices, top_k
from thermocal.calibration.space import ParameterSpace
from thermocal.calibration.surrogate import SVRSurrogate

N_SAMPLES, N_PARAMS, TOP_K = 500, 70, 10


def synthetic_metric(u: np.ndarray) -> np.ndarray:
    """Variance-like metric of unit-scaled parameters u in [0, 1] [W^2]."""
    z = u - 0.5
    w = np.r_[np.geomspace(4.0, 0.4, 10), np.full(u.shape[1] - 10, 0.02)]
    return (50.0 + 3.0 * (w * z).sum(axis=1) + 2.0 * np.sin(3.0 * z[:, 0]) * z[:, 1]
            + 4.0 * z[:, 2] ** 2 + 0.5 * z[:, 3] * z[:, 4])


def main() -> None:
    params = {f"material/m{i:02d}/conductivity": 0.5 + 0.01 * i for i in range(N_PARAMS)}
    space = ParameterSpace.from_parameters(params)
    X = sample(space, N_SAMPLES, "sobol", seed=1).values
    y = synthetic_metric((X.to_numpy() - space.lower) / (space.upper - space.lower))
    rows = []

    t = time.perf_counter()
    svr = SVRSurrogate(cv_folds=5, seed=0).fit(X, y)
    rows.append(("SVR fit (grid 24 x 5 folds) + out-of-fold R2", time.perf_counter() - t,
                 f"cv R2 {svr.cv_r2_:.3f}"))

    t = time.perf_counter()
    sob = sobol_indices(svr.predict, space.names, space.lower, space.upper, n=1024, seed=0)
    rows.append(("Sobol S1/ST on the meta-model (n=1024)", time.perf_counter() - t,
                 f"top ST {sob.index[0]}"))

    t = time.perf_counter()
    rank = influence_ranking(svr.predict, X, space.lower, space.upper)
    critical = top_k(rank, TOP_K)
    truth = [space.names[i] for i in range(TOP_K)]
    rows.append(("influence ranking (Fig. 6) + top-10", time.perf_counter() - t,
                 f"{len(set(critical) & set(truth))}/10 true critical found"))

    t = time.perf_counter()
    opt = optimise_reduced(X, y, space, critical, starts=8, seed=0)
    rows.append(("reduced SVR on top-10 + trust-constr min & max (8 starts)",
                 time.perf_counter() - t,
                 f"min {opt.minimum.value:.2f}, max {opt.maximum.value:.2f}"))

    total = sum(r[1] for r in rows)
    print(f"| step ({N_SAMPLES} samples x {N_PARAMS} parameters) | time [s] | note |")
    print("|---|---:|---|")
    for name, seconds, note in rows:
        print(f"| {name} | {seconds:.1f} | {note} |")
    print(f"| **total** (target <= 30 s) | **{total:.1f}** | y range {y.min():.1f}-{y.max():.1f} |")


if __name__ == "__main__":
    main()
