"""Benchmark of the retrofit workflow (issue 4).

Targets (2 cores, 24 GiB, no GPU):
- whole ``thermocal retrofit`` on the demo data (calibration, validation, 16 scenarios with
  200 uncertainty draws, figures, report): <= 15 s;
- ``thermocal demo`` from a fresh install (empty numba cache, new output folder): <= 60 s;
  also measured with ``--regenerate`` (the multi-zone simulation of the demo house included).

Each case runs as a separate ``thermocal`` process (interpreter start and imports included),
repeated; the best and the median are reported.

    /work/venv/bin/python benchmarks/bench_retrofit.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
THERMOCAL = [sys.executable, "-c", "from thermocal.cli import main; main()"]


def timed(args: list[str], env: dict | None = None) -> float:
    t0 = time.perf_counter()
    proc = subprocess.run(THERMOCAL + args, capture_output=True, text=True, env=env)
    elapsed = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"thermocal {' '.join(args)} failed:\n{proc.stderr}")
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=3)
    opts = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        # the demo's own configuration (200 draws) for the retrofit command
        timed(["demo", "--out", str(tmp / "prep")])
        config = tmp / "prep" / "data" / "config.yaml"
        retro = [
            timed(["retrofit", str(config), "--out", str(tmp / f"r{i}")])
            for i in range(opts.repeats)
        ]
        rows.append(("thermocal retrofit (demo data, 200 draws, report)", retro, 15.0))
        fresh = []
        fresh_regen = []
        for i in range(opts.repeats):
            env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp / f"numba{i}"))
            fresh.append(timed(["demo", "--out", str(tmp / f"d{i}")], env=env))
            env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp / f"numba_r{i}"))
            fresh_regen.append(
                timed(["demo", "--regenerate", "--out", str(tmp / f"g{i}")], env=env)
            )
        rows.append(("thermocal demo, fresh (empty numba cache)", fresh, 60.0))
        rows.append(
            ("thermocal demo --regenerate, fresh (multi-zone simulation)", fresh_regen, 60.0)
        )
    stamp = dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    print(
        f"# retrofit benchmark, {stamp}, {platform.node()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}"
    )
    print("| case | best [s] | median [s] | target [s] | pass |")
    print("|---|---|---|---|---|")
    for name, times, target in rows:
        best, med = min(times), statistics.median(times)
        print(
            f"| {name} | {best:.1f} | {med:.1f} | <= {target:.0f} | "
            f"{'pass' if med <= target else 'FAIL'} |"
        )


if __name__ == "__main__":
    main()
