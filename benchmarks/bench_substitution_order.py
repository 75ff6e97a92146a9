"""Is the sparse substitution of the time loop bound by its dependency chains? (issue 22 item 2)

The clinic's factors (``benchmarks/bench_step_floor.py``'s capture: 7,083 nodes, free run)
substituted 3,000 times per variant, alternating, on one random right-hand side:

- ``current``: :func:`thermocal.multizone._kernel_parts.lu_solve` as the loop calls it (since
  2026-11-30 one flat loop over the entries, row, column and value each);
- ``per column``: the loop until 2026-11-30, a loop per column over its entries (CSC), the
  factors rebuilt as CSC from the flat ones; the variants below are variants of it;
- ``levels``: the same factors renumbered so that the columns run level by level of the
  substitution's dependency graph (a topological order: every column's predecessors in an
  earlier level), so that consecutive columns are independent and the processor could overlap
  them; the fill and the arithmetic are the same, only the order of the updates differs;
- ``no zero test``: without the skip of zero entries;
- ``64-bit indices``: row indices as int64 instead of int32;
- ``rows (gather)``: the factors as CSR, each row gathering from the solved entries.

All give the same solution to round-off (checked). Run: /work/venv/bin/python
benchmarks/bench_substitution_order.py [--repeats 5] [--solves 3000]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_step_floor  # noqa: E402

from thermocal.multizone._kernel_parts import lu_solve  # noqa: E402


@njit(cache=True)
def dependency_levels(lp, li, up, ui, n):
    """Level of each column in the substitutions' dependency graph (longest path from a
    column without predecessors): ``L[i, j]`` puts ``j`` before ``i``, ``U[i, j]`` ``i``
    before ``j``."""
    level = np.zeros(n, dtype=np.int64)
    for j in range(n):
        for p in range(up[j], up[j + 1]):
            if level[ui[p]] + 1 > level[j]:
                level[j] = level[ui[p]] + 1
        for p in range(lp[j], lp[j + 1]):
            if level[j] + 1 > level[li[p]]:
                level[li[p]] = level[j] + 1
    return level


def level_ordered(factors):
    """The factors of :func:`prepare_factors` renumbered level by level."""
    lp, li, lx, up, ui, ux, inv_diag, inverse_r, perm_c = factors
    n = len(inv_diag)
    order = np.argsort(dependency_levels(lp, li, up, ui, n), kind="stable")
    position = np.empty(n, dtype=np.int64)
    position[order] = np.arange(n)
    p = sp.csc_matrix((np.ones(n), (position, np.arange(n))), shape=(n, n))
    lower = (p @ sp.csc_matrix((lx, li, lp), shape=(n, n)) @ p.T).tocsc()
    upper = (p @ sp.csc_matrix((ux, ui, up), shape=(n, n)) @ p.T).tocsc()
    assert sp.tril(lower, -1).nnz == lower.nnz and sp.triu(upper, 1).nnz == upper.nnz
    lower.sort_indices()
    upper.sort_indices()
    return (
        lower.indptr.astype(np.int64), lower.indices.astype(np.int32), lower.data.copy(),
        upper.indptr.astype(np.int64), upper.indices.astype(np.int32), upper.data.copy(),
        inv_diag[order], inverse_r[order].astype(np.int64), position[perm_c].astype(np.int64),
    )  # fmt: skip


@njit(fastmath=True)
def solve_per_column(lp, li, lx, up, ui, ux, inv_diag, inverse_r, perm_c, b, work, out):
    """The substitution of the loop until 2026-11-30 (CSC factors, a loop per column)."""
    n = b.shape[0]
    for j in range(n):
        work[j] = b[inverse_r[j]]
    for j in range(n):
        zj = work[j]
        if zj != 0.0:
            for p in range(lp[j], lp[j + 1]):
                work[li[p]] -= lx[p] * zj
    for j in range(n - 1, -1, -1):
        yj = work[j] * inv_diag[j]
        work[j] = yj
        if yj != 0.0:
            for p in range(up[j], up[j + 1]):
                work[ui[p]] -= ux[p] * yj
    for i in range(n):
        out[i] = work[perm_c[i]]


def per_column(flat):
    """The flat factors of :func:`prepare_factors` as CSC (:func:`solve_per_column`)."""
    l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c = flat
    n = len(inv_diag)
    lower = sp.csc_matrix((l_val, (l_row, l_col)), shape=(n, n))
    upper = sp.csc_matrix((u_val, (u_row, u_col)), shape=(n, n))
    lower.sort_indices()
    upper.sort_indices()
    return (
        lower.indptr.astype(np.int64), lower.indices.astype(np.int32), lower.data.copy(),
        upper.indptr.astype(np.int64), upper.indices.astype(np.int32), upper.data.copy(),
        inv_diag, inverse_r, perm_c,
    )  # fmt: skip


@njit(fastmath=True)
def solve_without_zero_test(lp, li, lx, up, ui, ux, inv_diag, inverse_r, perm_c, b, work, out):
    n = b.shape[0]
    for j in range(n):
        work[j] = b[inverse_r[j]]
    for j in range(n):
        zj = work[j]
        for p in range(lp[j], lp[j + 1]):
            work[li[p]] -= lx[p] * zj
    for j in range(n - 1, -1, -1):
        yj = work[j] * inv_diag[j]
        work[j] = yj
        for p in range(up[j], up[j + 1]):
            work[ui[p]] -= ux[p] * yj
    for i in range(n):
        out[i] = work[perm_c[i]]


@njit(fastmath=True)
def solve_by_rows(rp, rj, rx, cp, cj, cx, inv_diag, inverse_r, perm_c, b, work, out):
    n = b.shape[0]
    for i in range(n):
        s = b[inverse_r[i]]
        for p in range(rp[i], rp[i + 1]):
            s -= rx[p] * work[rj[p]]
        work[i] = s
    for i in range(n - 1, -1, -1):
        s = work[i]
        for p in range(cp[i], cp[i + 1]):
            s -= cx[p] * work[cj[p]]
        work[i] = s * inv_diag[i]
    for i in range(n):
        out[i] = work[perm_c[i]]


def repeated(fn):
    @njit
    def run(n_rep, a0, a1, a2, a3, a4, a5, a6, a7, a8, b, work, out):
        for _ in range(n_rep):
            fn(a0, a1, a2, a3, a4, a5, a6, a7, a8, b, work, out)

    return run


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--solves", type=int, default=3000)
    args = parser.parse_args()
    _, cases, _ = bench_step_floor.capture_clinic()
    case = cases["free run, given heat"]
    flat = tuple(case[name] for name in bench_step_floor.FACTOR_NAMES)
    factors = per_column(flat)
    lp, li, lx, up, ui, ux, inv_diag, inverse_r, perm_c = factors
    n = len(inv_diag)
    lower = sp.csc_matrix((lx, li, lp), shape=(n, n)).tocsr()
    upper = sp.csc_matrix((ux, ui, up), shape=(n, n)).tocsr()
    lower.sort_indices()
    upper.sort_indices()
    by_rows = (
        lower.indptr.astype(np.int64), lower.indices.astype(np.int64), lower.data.copy(),
        upper.indptr.astype(np.int64), upper.indices.astype(np.int64), upper.data.copy(),
        inv_diag, inverse_r, perm_c,
    )  # fmt: skip
    wide = (lp, li.astype(np.int64), lx, up, ui.astype(np.int64), ux, inv_diag, inverse_r, perm_c)
    variants = {
        "current": (repeated(lu_solve), flat),
        "per column": (repeated(solve_per_column), factors),
        "levels": (repeated(solve_per_column), level_ordered(factors)),
        "no zero test": (repeated(solve_without_zero_test), factors),
        "64-bit indices": (repeated(solve_per_column), wide),
        "rows (gather)": (repeated(solve_by_rows), by_rows),
    }
    levels = dependency_levels(lp, li, up, ui, n)
    print(f"{n} columns, {len(lx) + len(ux)} off-diagonal entries, {levels.max() + 1} levels")
    b = np.random.default_rng(0).normal(size=n)
    work, out, reference = np.empty(n), np.empty(n), np.empty(n)
    lu_solve(*flat, b, work, reference)
    times: dict[str, list[float]] = {name: [] for name in variants}
    for run, fac in variants.values():
        run(2, *fac, b, work, out)
        assert np.allclose(out, reference, rtol=1e-12, atol=1e-12 * np.abs(reference).max())
    for _ in range(args.repeats):
        for name, (run, fac) in variants.items():
            start = time.perf_counter()
            run(args.solves, *fac, b, work, out)
            times[name].append((time.perf_counter() - start) / args.solves * 1e6)
    print("| variant | median [us] | min [us] |\n|---|---:|---:|")
    for name, values in times.items():
        print(f"| {name} | {np.median(values):.1f} | {min(values):.1f} |")


if __name__ == "__main__":
    main()
