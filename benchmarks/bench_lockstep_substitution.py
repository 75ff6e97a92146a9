"""Would a time loop that steps several campaign samples together reach issue 22's targets?

A campaign's samples share the network's pattern: the same nodes, faces and, with one fill-reducing
ordering and no pivoting (the implicit step's matrix ``C / dt + K`` is diagonally dominant), the
same sparsity of the LU factors. Only the values differ. A loop that advances ``K`` samples in
lockstep reads each entry's row and column index once for ``K`` multiply-adds, and the ``K``
values of an entry sit side by side, so the processor's vector units can apply them together.
That is the rewrite of the 190-argument kernel the issue's remaining targets would need
("The substitutions as one flat loop", benchmarks/README.md); this measures its best case on the
part of the step where it matters most, the sparse substitutions (30-36 of the step's 78-86 us).

On the clinic's factors (``bench_step_floor.py``'s capture: 7,083 nodes, 27,602 entries, free
run), each sample's factor values scaled by its own factor (1 + 1e-3 k: other numbers, the same
work), per variant and repeat, alternating:

- ``K = 1``: :func:`thermocal.multizone._kernel_parts.lu_solve` as the loop calls it;
- ``K = 2, 4, 8``: the same flat substitution over ``(entries, K)`` values, the ``K`` updates of
  an entry written out one by one (generated source: with ``K`` a run-time loop bound numba's
  code was slower per sample than ``K = 1`` for ``K`` of 2 and 4, measured 2026-11-30).

Each variant's solutions are checked against ``K`` separate solves of :func:`lu_solve` (1e-12).
Printed: microseconds per sample and solve (best of the repeats) and the speed-up per sample.

Run: /work/venv/bin/python benchmarks/bench_lockstep_substitution.py [--repeats 5] [--solves 2000]
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_step_floor  # noqa: E402

from thermocal.multizone._kernel_parts import lu_solve  # noqa: E402

LOCKSTEP_SIZES = (2, 4, 8)


def lockstep_source(k: int) -> str:
    """Source of a ``k``-sample substitution, its per-sample updates written out.

    Parameters
    ----------
    k : int
        Samples stepped together [-].

    Returns
    -------
    str
        A function ``lu_solve_<k>`` with :func:`lu_solve`'s arguments, its values, diagonals,
        right-hand sides and outputs of shape ``(..., k)``.
    """
    name = f"lu_solve_{k}"
    body = [
        f"def {name}(l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c, "
        "b, work, out):",
        "    n = b.shape[0]",
        "    for j in range(n):",
        "        r = inverse_r[j]",
        *[f"        work[j, {s}] = b[r, {s}]" for s in range(k)],
        "    for p in range(l_val.shape[0]):",
        "        i = l_row[p]",
        "        j = l_col[p]",
        *[f"        work[i, {s}] -= l_val[p, {s}] * work[j, {s}]" for s in range(k)],
        "    for p in range(u_val.shape[0]):",
        "        i = u_row[p]",
        "        j = u_col[p]",
        *[
            f"        work[i, {s}] -= u_val[p, {s}] * (work[j, {s}] * inv_diag[j, {s}])"
            for s in range(k)
        ],
        "    for i in range(n):",
        "        j = perm_c[i]",
        *[f"        out[i, {s}] = work[j, {s}] * inv_diag[j, {s}]" for s in range(k)],
    ]
    return "\n".join(body)


def lockstep_solver(k: int):
    """The compiled ``k``-sample substitution and a driver that repeats it ``n_rep`` times."""
    namespace: dict = {}
    exec(lockstep_source(k), namespace)  # noqa: S102 - generated above, no input
    solve = njit(fastmath=True, error_model="numpy")(namespace[f"lu_solve_{k}"])

    @njit
    def repeated(n_rep, a0, a1, a2, a3, a4, a5, a6, a7, a8, b, work, out):
        for _ in range(n_rep):
            solve(a0, a1, a2, a3, a4, a5, a6, a7, a8, b, work, out)

    return repeated


@njit
def repeated_single(n_rep, a0, a1, a2, a3, a4, a5, a6, a7, a8, b, work, out):
    for _ in range(n_rep):
        lu_solve(a0, a1, a2, a3, a4, a5, a6, a7, a8, b, work, out)


def sample_factors(flat, k: int):
    """``k`` samples' factors: the values of sample ``s`` scaled by ``1 + 1e-3 s``."""
    l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c = flat
    scale = 1.0 + 1e-3 * np.arange(k)
    return (
        l_row, l_col, np.ascontiguousarray(l_val[:, None] * scale),
        u_row, u_col, np.ascontiguousarray(u_val[:, None] * scale),
        np.ascontiguousarray(inv_diag[:, None] / scale), inverse_r, perm_c,
    )  # fmt: skip


def check(flat, factors, k: int, b: np.ndarray, solver) -> None:
    """The lockstep solutions against ``k`` separate solves of :func:`lu_solve`."""
    n = len(b)
    rhs = np.ascontiguousarray(np.repeat(b[:, None], k, axis=1))
    out = np.empty((n, k))
    solver(1, *factors, rhs, np.empty((n, k)), out)
    for s in range(k):
        single = (
            factors[0], factors[1], np.ascontiguousarray(factors[2][:, s]),
            factors[3], factors[4], np.ascontiguousarray(factors[5][:, s]),
            np.ascontiguousarray(factors[6][:, s]), factors[7], factors[8],
        )  # fmt: skip
        reference = np.empty(n)
        lu_solve(*single, b, np.empty(n), reference)
        scale = np.abs(reference).max()
        assert np.allclose(out[:, s], reference, rtol=1e-12, atol=1e-12 * scale), (k, s)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--solves", type=int, default=2000)
    parser.add_argument("--write", type=Path)
    args = parser.parse_args(argv)
    start = datetime.datetime.now(datetime.UTC)
    _, cases, _ = bench_step_floor.capture_clinic()
    case = cases["free run, given heat"]
    flat = tuple(case[name] for name in bench_step_floor.FACTOR_NAMES)
    n = len(flat[6])
    b = np.random.default_rng(0).normal(size=n)
    variants = {1: (repeated_single, flat, b, np.empty(n), np.empty(n))}
    for k in LOCKSTEP_SIZES:
        factors = sample_factors(flat, k)
        solver = lockstep_solver(k)
        check(flat, factors, k, b, solver)
        rhs = np.ascontiguousarray(np.repeat(b[:, None], k, axis=1))
        variants[k] = (solver, factors, rhs, np.empty((n, k)), np.empty((n, k)))
    repeated_single(2, *flat, b, np.empty(n), np.empty(n))
    times: dict[int, list[float]] = {k: [] for k in variants}
    for _ in range(args.repeats):
        for k, (solver, factors, rhs, work, out) in variants.items():
            t0 = time.perf_counter()
            solver(args.solves, *factors, rhs, work, out)
            times[k].append((time.perf_counter() - t0) / args.solves / k * 1e6)
    load = os.getloadavg()
    entries = len(flat[2]) + len(flat[5])
    lines = [
        f"Run {start:%Y-%m-%d %H:%M} UTC, {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores, load average at the end {load[0]:.1f}; {n} columns, "
        f"{entries} entries; `python benchmarks/bench_lockstep_substitution.py --repeats "
        f"{args.repeats} --solves {args.solves}`",
        "",
        "| samples in lockstep | per sample and solve, best [us] | median [us] | speed-up per "
        "sample (best) |",
        "|---:|---:|---:|---:|",
    ]
    single = min(times[1])
    for k, values in times.items():
        lines.append(
            f"| {k} | {min(values):.1f} | {np.median(values):.1f} | {single / min(values):.2f}x |"
        )
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
