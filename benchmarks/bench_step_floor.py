"""Where a time step of the detailed model goes, against the machine's memory bandwidth (issue 22
item 2).

On the clinic of the identification demo (186 zones, 7,083 nodes, January at 5 min; the building
of ``benchmarks/bench_identification.py``), for each mode of the time loop (exact inverse on
the air temperatures, PID, free run with given heat):

- the time of one step of the compiled loop (``_kernel.run_steps`` on the month's first chunk of
  2,048 steps, the arguments captured from the real call), best of the repeats;
- the substitutions per step and their time measured alone (the same factors, 2,000 solves);
- the same loop with every substitution replaced by a diagonal scaling (what the step costs
  without its solves);
- bytes touched per step (factor values, indices, pointers, permutations and vectors; the
  loop's other arrays) and floating-point operations;
- the machine's achievable bandwidth: a STREAM-like triad ``a = b + s c`` in numba in the same
  run, with a working set the size of the step's data (it stays in the last-level cache) and one
  of 96 MB (main memory).

The floor of a step is its bytes divided by the triad bandwidth at the same working-set size.

With ``--peer COMMIT`` the kernel module of that commit (``git show
COMMIT:src/thermocal/multizone/_kernel.py``) runs the same captured arguments in turn with this
one (A B A B ...): the step times' ratio, and whether the outputs (zone air and mean radiant
temperatures, identified heat, final state) are bit-identical.

Run: /work/venv/bin/python benchmarks/bench_step_floor.py [--repeats 5] [--peer de53112]
     [--write results.md]
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import inspect
import os
import platform
import subprocess
import tempfile
import time
import types
import warnings
from pathlib import Path

import numpy as np
from numba import njit

FACTOR_NAMES = [
    "l_row", "l_col", "l_val", "u_row", "u_col", "u_val", "inv_diag", "inverse_r", "perm_c"
]  # fmt: skip
DIRICHLET_NAMES = [
    "dl_row",
    "dl_col",
    "dl_val",
    "du_row",
    "du_col",
    "du_val",
    "d_inv_diag",
    "d_inverse_r",
    "d_perm_c",
]


@njit(fastmath=True)
def triad(a, b, c, s, repeats):
    """STREAM triad ``a = b + s c`` repeated (24 bytes per element: two reads, one write)."""
    for _ in range(repeats):
        for i in range(a.shape[0]):
            a[i] = b[i] + s * c[i]


def triad_bandwidth(n_bytes: float, seconds: float = 0.3) -> float:
    """Best triad bandwidth [B/s] over a working set of about ``n_bytes``."""
    n = max(1024, int(n_bytes / 24))
    a, b, c = np.zeros(n), np.ones(n), np.full(n, 2.0)
    triad(a, b, c, 3.0, 1)
    repeats = max(1, int(2e7 / n))
    best_rate = 0.0
    end = time.perf_counter() + seconds
    while time.perf_counter() < end or best_rate == 0.0:
        t0 = time.perf_counter()
        triad(a, b, c, 3.0, repeats)
        best_rate = max(best_rate, 24.0 * n * repeats / (time.perf_counter() - t0))
    return best_rate


@njit
def repeated_solves(
    solve, n_rep, l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c, b
):
    n = b.shape[0]
    work = np.empty(n)
    out = np.empty(n)
    for _ in range(n_rep):
        solve(l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c, b, work, out)
    return out


@njit(fastmath=True)
def diagonal_only(
    l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c, b, work, out
):
    """Stand-in for a substitution: a diagonal scaling, clipped (keeps the state bounded)."""
    for i in range(b.shape[0]):
        out[i] = min(max(b[i] * inv_diag[i], -50.0), 80.0)


def factor_bytes(factors) -> tuple[int, int]:
    """Bytes of one substitution (arrays read once, vectors b, out and work) and its flops."""
    n = factors[6].shape[0]
    nnz = factors[2].shape[0] + factors[5].shape[0]
    matrix = sum(a.nbytes for a in factors)
    vectors = 8 * n * 4  # b read, out written, work written and read once
    return matrix + vectors, 2 * nnz + n


def loop_bytes(args: dict, n_nodes: int) -> int:
    """Bytes the step touches outside its substitutions (per-step rows of the input tables)."""
    n_steps = args["n_steps"]
    per_step_tables = ("u", "ext_dh", "inf_ratio", "inf_scheduled", "heat_extra", "track_ref")
    total = 0
    for name, value in args.items():
        if not isinstance(value, np.ndarray) or name in FACTOR_NAMES + DIRICHLET_NAMES:
            continue
        if name in ("out_air", "out_mrt", "out_heat", "out_cool", "out_q", "out_face"):
            total += value.nbytes // max(1, value.shape[0])
        elif name in per_step_tables and value.ndim >= 1 and value.shape[0] >= n_steps:
            total += value.nbytes // value.shape[0]
        elif value.ndim == 2 and value.shape[0] > 1000:  # per-step tables not read in this mode
            continue
        else:
            total += value.nbytes
    return total + 8 * n_nodes * 4  # rhs, x_new, rhs_d, copies of the state


def capture_clinic():
    """The clinic demo's identification problem and the kernel arguments of three modes."""
    from thermocal.demos.identification import load_demo
    from thermocal.identification.pid import kernel_coefficients
    from thermocal.identification.problem import problem_from_measurements
    from thermocal.identification.tuning import tune_zone, volume_scaled_gains
    from thermocal.multizone import _kernel

    building, weather, meta, raw, mapping, _ = load_demo()
    start, end = meta["period"]
    problem, _ = problem_from_measurements(
        building, weather, meta["weather"], raw, mapping, start=start, end=end
    )
    sim = problem.simulation()
    reference = problem.reference[list(building.zones)].to_numpy()
    tuning = tune_zone(building, outdoor_temperature=float(weather["temp_air"].mean()))
    gains = volume_scaled_gains(building, tuning)
    pid = kernel_coefficients([gains[z] for z in building.zones])
    heat = np.full((len(sim.times), len(building.zones)), 300.0)
    original = _kernel.run_steps
    names = list(inspect.signature(original.py_func).parameters)
    calls = []

    def recorder(*args):
        calls.append([a.copy() if isinstance(a, np.ndarray) else a for a in args])
        return original(*args)

    cases = {}
    _kernel.run_steps = recorder
    try:
        for mode, run in (
            ("exact inverse (air)", lambda: sim.track(reference, method="inverse")),
            ("PID", lambda: sim.track(reference, method="pid", pid=pid)),
            ("free run, given heat", lambda: sim.run(free_float=True, heat_input=heat)),
        ):
            calls.clear()
            run()
            first = next(c for c in calls if c[1] == 2048)
            cases[mode] = dict(zip(names, first, strict=True))
    finally:
        _kernel.run_steps = original
    calls = {
        "identification, exact inverse (air), warm-up + month": lambda: sim.track(
            reference, method="inverse"
        ).heat.to_numpy(),
        "identification, PID, warm-up + month": lambda: sim.track(
            reference, method="pid", pid=pid
        ).heat.to_numpy(),
        "identification, exact inverse (operative), warm-up + month": lambda: sim.track(
            reference, method="inverse", feedback="operative"
        ).heat.to_numpy(),
        "campaign sample: set 1 parameter + inverse + metric": lambda: np.array(
            [problem.evaluate({"material/R16 insulation/resistance": 2.0})["unoccupied_variance"]]
        ),
    }
    return sim, cases, calls


def solves_per_step(args: dict) -> dict:
    """Which factors the step substitutes with, and how often (the kernel's code paths)."""
    m_imp = args["imp_zone"].shape[0]
    mode = args["track_mode"]
    if mode == 1 and not args["track_general"]:
        count = {"dirichlet": 1}
    elif mode == 1:
        count = {"system": 2}
    elif mode == 2:
        count = {"system": 1}
    else:
        count = {"system": 1}  # free run; ideal loads add up to two (not timed here)
    if m_imp > 0:
        key = "dirichlet" if (mode == 1 and not args["track_general"]) else "system"
        count[key] = count.get(key, 0) + 1
    return count


def peer_kernel(commit: str, module: str = "_kernel"):
    """A module of ``thermocal.multizone`` at another commit of this repository (numba functions
    compiled here, not cached)."""
    import sys

    root = Path(__file__).resolve().parents[1]
    source = subprocess.run(
        ["git", "show", f"{commit}:src/thermocal/multizone/{module}.py"],
        cwd=root,
        check=True,
        capture_output=True,
        text=True,
    ).stdout.replace("cache=True", "cache=False")
    folder = Path(tempfile.mkdtemp(prefix="thermocal_peer_kernel_"))
    path = folder / f"peer_{module}_{commit}.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location(f"thermocal.multizone.{path.stem}", path)
    loaded = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = loaded
    spec.loader.exec_module(loaded)
    return loaded


OUTPUTS = ("x", "out_air", "out_mrt", "out_q", "out_heat", "out_cool", "face_root")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--write", type=Path)
    parser.add_argument("--peer", help="a commit whose kernel to time alongside (e.g. de53112)")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    from thermocal.multizone import _kernel

    sim, cases, whole_calls = capture_clinic()
    n_nodes = sim.network.n_nodes
    no_solve = njit(fastmath=True)(
        types.FunctionType(
            _kernel.run_steps.py_func.__code__,
            {**_kernel.__dict__, "lu_solve": diagonal_only},
            "run_steps_without_solves",
        )
    )

    def step_time(kernel, case) -> float:
        values = list(case.values())
        best_time = np.inf
        for _ in range(args.repeats):
            fresh = [a.copy() if isinstance(a, np.ndarray) else a for a in values]
            t0 = time.perf_counter()
            kernel(*fresh)
            best_time = min(best_time, time.perf_counter() - t0)
        return best_time / case["n_steps"]

    def solve_time(factors) -> float:
        b = np.linspace(10.0, 30.0, factors[6].shape[0])
        repeated_solves(_kernel.lu_solve, 1, *factors, b)
        best_time = np.inf
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            repeated_solves(_kernel.lu_solve, 2000, *factors, b)
            best_time = min(best_time, (time.perf_counter() - t0) / 2000)
        return best_time

    rows = []
    step_bytes_max = 0
    for mode, case in cases.items():
        _kernel.run_steps(*[a.copy() if isinstance(a, np.ndarray) else a for a in case.values()])
        no_solve(*[a.copy() if isinstance(a, np.ndarray) else a for a in case.values()])
        t_step = step_time(_kernel.run_steps, case)
        t_rest = step_time(no_solve, case)
        counts = solves_per_step(case)
        solve_bytes = solve_flops = 0
        t_solves = 0.0
        detail = []
        for which, count in counts.items():
            names = DIRICHLET_NAMES if which == "dirichlet" else FACTOR_NAMES
            factors = [case[k] for k in names]
            nbytes, flops = factor_bytes(factors)
            t_one = solve_time(factors)
            solve_bytes += count * nbytes
            solve_flops += count * flops
            t_solves += count * t_one
            nnz = factors[1].shape[0] + factors[4].shape[0]
            detail.append(
                f"{count} x {which} (strict nnz(L)+nnz(U) {nnz:,}, {nbytes / 1e3:.0f} kB, "
                f"{t_one * 1e6:.1f} us)"
            )
        rest_bytes = loop_bytes(case, n_nodes)
        step_bytes_max = max(step_bytes_max, solve_bytes + rest_bytes)
        rows.append(
            dict(
                mode=mode,
                solves="; ".join(detail),
                step=t_step,
                rest=t_rest,
                solves_time=t_solves,
                solve_bytes=solve_bytes,
                rest_bytes=rest_bytes,
                flops=solve_flops,
            )
        )
    peer_lines = []
    if args.peer:
        peer = peer_kernel(args.peer)
        peer_lines = [
            "",
            f"This kernel against the kernel of {args.peer}, the same captured arguments in turn "
            f"(best of {args.repeats} pairs):",
            "",
            f"| mode | peer {args.peer} [us/step] | this [us/step] | speed-up | outputs |",
            "|---|---:|---:|---:|---|",
        ]
        for mode, case in cases.items():
            values = list(case.values())
            runs = {}
            for name, kernel in (("peer", peer.run_steps), ("this", _kernel.run_steps)):
                fresh = [a.copy() if isinstance(a, np.ndarray) else a for a in values]
                kernel(*fresh)
                runs[name] = dict(zip(case, fresh, strict=True))
            same = all(np.array_equal(runs["peer"][k], runs["this"][k]) for k in OUTPUTS)
            worst = max(
                float(np.max(np.abs(runs["peer"][k] - runs["this"][k]), initial=0.0))
                for k in OUTPUTS
            )
            times = {"peer": np.inf, "this": np.inf}
            for _ in range(args.repeats):
                for name, kernel in (("peer", peer.run_steps), ("this", _kernel.run_steps)):
                    fresh = [a.copy() if isinstance(a, np.ndarray) else a for a in values]
                    t0 = time.perf_counter()
                    kernel(*fresh)
                    times[name] = min(times[name], time.perf_counter() - t0)
            n = case["n_steps"]
            peer_lines.append(
                f"| {mode} | {times['peer'] / n * 1e6:.1f} | {times['this'] / n * 1e6:.1f} | "
                f"{times['peer'] / times['this']:.2f}x | "
                + ("bit-identical" if same else f"differ, largest {worst:.3g}")
                + " |"
            )
    if args.peer:
        peer_lines += [
            "",
            "Whole calls with either kernel (the module attribute swapped, A B A B ...; "
            "identified heat compared):",
            "",
            f"| call | peer {args.peer} [s] | this [s] | speed-up | identified heat |",
            "|---|---:|---:|---:|---|",
        ]
        this_kernel = _kernel.run_steps
        try:
            for label, call in whole_calls.items():
                times = {"peer": np.inf, "this": np.inf}
                values = {}
                for _ in range(max(2, args.repeats // 2)):
                    for name, kernel in (("peer", peer.run_steps), ("this", this_kernel)):
                        _kernel.run_steps = kernel
                        t0 = time.perf_counter()
                        values[name] = call()
                        times[name] = min(times[name], time.perf_counter() - t0)
                same = np.array_equal(values["peer"], values["this"])
                scale = float(np.max(np.abs(values["peer"])))
                worst = float(np.max(np.abs(values["peer"] - values["this"])))
                peer_lines.append(
                    f"| {label} | {times['peer']:.3f} | {times['this']:.3f} | "
                    f"{times['peer'] / times['this']:.2f}x | "
                    + ("bit-identical" if same else f"largest difference {worst / scale:.2g} rel.")
                    + " |"
                )
        finally:
            _kernel.run_steps = this_kernel
        # set_parameters with either network assembly (simulation.assemble swapped)
        from thermocal.multizone import simulation as simulation_module

        peer_network = peer_kernel(args.peer, "network")
        this_assemble = simulation_module.assemble
        times = {"peer": np.inf, "this": np.inf}
        matrices = {}
        try:
            for r in range(max(2, args.repeats)):
                for name, function in (("peer", peer_network.assemble), ("this", this_assemble)):
                    simulation_module.assemble = function
                    value = 2.0 + 0.1 * r
                    t0 = time.perf_counter()
                    sim.set_parameters({"material/R16 insulation/resistance": value})
                    times[name] = min(times[name], time.perf_counter() - t0)
                    matrices[name] = sim.network.system_matrix(sim.dt)
        finally:
            simulation_module.assemble = this_assemble
        same = (matrices["peer"] != matrices["this"]).nnz == 0
        peer_lines.append(
            f"| set_parameters (1 parameter), network assembly of {args.peer} / this | "
            f"{times['peer']:.3f} | {times['this']:.3f} | {times['peer'] / times['this']:.2f}x | "
            + ("system matrix identical" if same else "system matrix DIFFERS")
            + " |"
        )
    bw_cache = triad_bandwidth(step_bytes_max)
    bw_l2 = triad_bandwidth(256e3)
    bw_dram = triad_bandwidth(96e6)
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()[0]
    lines = [
        f"Date: {stamp}. Machine: {platform.machine()}, 2 cores (shared, load average "
        f"{load:.1f}); Python {platform.python_version()}. Clinic demo: {n_nodes:,} nodes, "
        f"best of {args.repeats}.",
        "",
        f"Triad bandwidth in this run: {bw_l2 / 1e9:.1f} GB/s at 256 kB (L2), "
        f"{bw_cache / 1e9:.1f} GB/s at {step_bytes_max / 1e6:.2f} MB (a step's data, last-level "
        f"cache), {bw_dram / 1e9:.1f} GB/s at 96 MB (main memory).",
        "",
        "| mode | substitutions per step | step [us] | without the solves [us] | solves alone "
        "[us] | bytes per step [kB] (solves + rest) | flops per step (solves) | floor at "
        "cache bandwidth [us] | step / floor |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        total = r["solve_bytes"] + r["rest_bytes"]
        floor = total / bw_cache
        lines.append(
            f"| {r['mode']} | {r['solves']} | {r['step'] * 1e6:.1f} | {r['rest'] * 1e6:.1f} | "
            f"{r['solves_time'] * 1e6:.1f} | {total / 1e3:.0f} ({r['solve_bytes'] / 1e3:.0f} + "
            f"{r['rest_bytes'] / 1e3:.0f}) | {r['flops']:,} | {floor * 1e6:.1f} | "
            f"{r['step'] / floor:.1f}x |"
        )
    text = "\n".join(lines + peer_lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
