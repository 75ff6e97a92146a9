"""`thermocal select` on the Bacher & Madsen PRBS data, timed against a peer commit.

Run:  /work/venv/bin/python benchmarks/bench_select.py --peer <commit> [--rounds 2] [--seed S]

Each round runs the command of the peer and of this tree one after the other (the order
alternates between rounds), each in a fresh process, so both see the same machine load; the
first call of a source tree compiles numba's kernels into its cache, so a warm-up run of each
precedes the timed rounds. Reported per run: wall time, CPU time of the command and its
worker processes (user + system, from ``resource.getrusage``; on a shared machine the wall
time grows with the other users' load, the CPU time much less), the selected path, the
log-likelihoods of its models and their heat loss coefficients with the 95 % profile
interval. The peer's source is extracted once (``git archive``) to
``~/.cache/thermocal-bench/<commit>`` so that its numba cache survives between runs.

Target (issue 29): `select` on the PRBS data <= 30 s on 2 cores.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _peer import peer_source  # benchmarks/ is the script's folder

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data" / "bacher_madsen_2011_prbs" / "inputPRBS1.csv"



def run_select(src: Path, out: Path, seed: int | None) -> dict:
    """One `thermocal select` in a subprocess with ``src`` first on the path."""
    cmd = [sys.executable, "-c", "from thermocal.cli import main; main()", "select", str(DATA),
           "--time-column", "t", "--time-unit", "h", "--out", str(out)]  # fmt: skip
    if seed is not None:
        cmd += ["--seed", str(seed)]
    env = dict(os.environ, PYTHONPATH=str(src))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"select failed ({src}):\n{done.stdout}\n{done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    sel = json.loads((out / "selection.json").read_text())
    rows = {r["model"]: r for r in sel["table"]}
    path = sel["path"]
    hlc = sel["heat_loss_coefficient"]
    return {
        "wall": wall,
        "cpu": cpu,
        "load": os.getloadavg()[0],
        "path": " -> ".join(path),
        "loglikes": ", ".join(f"{rows[n]['loglike']:.3f}" for n in path),
        "converged": ", ".join(str(rows[n]["converged"]) for n in path),
        "starts_at_best": ", ".join(str(rows[n]["starts_at_best"]) for n in path),
        "hlc": ", ".join(
            f"{n} {hlc[n]['value']:.1f} [{hlc[n].get('lower', float('nan')):.1f}, "
            f"{hlc[n].get('upper', float('nan')):.1f}]"
            for n in path
        ),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--peer", required=True, help="commit to time alongside")
    parser.add_argument("--peer-src", type=Path, help="an extracted `src` of the peer to use "
                        "instead (its numba cache already warm)")  # fmt: skip
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--seed", type=int, default=None, help="--seed of select (default: "
                        "select's own default)")  # fmt: skip
    parser.add_argument("--no-warmup", action="store_true")
    parser.add_argument("--keep", type=Path, help="write the selections here (else a "
                        "temporary folder)")  # fmt: skip
    args = parser.parse_args()
    sources = {"peer": args.peer_src or peer_source(args.peer), "this": REPO / "src"}
    with tempfile.TemporaryDirectory() as tmp:
        if args.keep is not None:
            tmp = args.keep
            Path(tmp).mkdir(parents=True, exist_ok=True)
        if not args.no_warmup:
            for name, src in sources.items():
                run_select(src, Path(tmp) / f"warm_{name}", args.seed)
        results = {"peer": [], "this": []}
        for k in range(args.rounds):
            order = ["peer", "this"] if k % 2 == 0 else ["this", "peer"]
            for name in order:
                r = run_select(sources[name], Path(tmp) / f"{name}_{k}", args.seed)
                results[name].append(r)
                print(f"round {k} {name}: wall {r['wall']:.1f} s, CPU {r['cpu']:.1f} s, load "
                      f"{r['load']:.1f}", flush=True)  # fmt: skip
    print()
    print("| run | wall [s] | CPU [s] | load | path | log-likelihoods | converged | starts at "
          "best | HLC [W/K] (95 % profile) |")  # fmt: skip
    print("|---|---:|---:|---:|---|---|---|---|---|")
    for name, runs in results.items():
        label = f"peer {args.peer}" if name == "peer" else "this code"
        for k, r in enumerate(runs):
            print(f"| {label} #{k} | {r['wall']:.1f} | {r['cpu']:.1f} | {r['load']:.1f} | "
                  f"{r['path']} | {r['loglikes']} | {r['converged']} | {r['starts_at_best']} "
                  f"| {r['hlc']} |")  # fmt: skip
    for key in ("wall", "cpu"):
        ratios = [p[key] / t[key] for p, t in zip(results["peer"], results["this"], strict=True)]
        print(f"peer / this, {key}: " + ", ".join(f"{x:.2f}x" for x in ratios))


if __name__ == "__main__":
    main()
