"""The model set-up of two source trees in the same run (issue 28, item 8).

Each round runs one child process per tree (alternating A B A B ...), which times, best of
``--repeats`` after one warm call: ``Simulation(...)`` of the clinic demo month (the set-up
``identify`` does), of ``generators.clinic()`` on the same weather, of the multifamily prototype
(January at 10 minutes), ``assemble`` of the clinic alone, and the peer: the free-running
simulation of the clinic month. The best over rounds is reported per tree with its ratio to the
peer of the same tree.

Run: python benchmarks/bench_setup_compare.py --tree before=/work/main/src \
         --tree after=src [--rounds 3] [--repeats 3] [--write results.md]
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MULTIFAMILY = ROOT / "tests" / "reference" / "identification_multifamily"

CHILD = r"""
import json, sys, time, warnings
warnings.simplefilter("ignore")
import pandas as pd
from thermocal.demos.identification import load_demo
from thermocal.io.weather import read_weather
from thermocal.demos import buildings as generators
from thermocal.multizone.energyplus import energyplus_weather_folder
from thermocal.multizone.idf import read_idf
from thermocal.multizone.network import assemble
from thermocal.multizone.simulation import Simulation

repeats, idf = int(sys.argv[1]), sys.argv[2]

def best(function):
    function()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)

building, weather, meta, _, _, _ = load_demo()
start, end = meta["period"]
def demo():
    return Simulation(building, weather, meta["weather"], start=start, end=end,
                      store_surfaces=False)
clinic = generators.clinic()
out = {}
out["clinic demo: Simulation set-up"] = best(demo)
out["generators.clinic(): Simulation set-up"] = best(
    lambda: Simulation(clinic, weather, meta["weather"], start=start, end=end,
                       store_surfaces=False))
sim = demo()
out["clinic: assemble alone"] = best(
    lambda: assemble(building, sim.dt, options=sim.options, mean_wind_speed=sim._mean_wind,
                     mean_outdoor_temperature=sim._mean_tout, pressure=sim._pressure))
epw = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
mf_weather, mf_meta = read_weather(epw)
tz = mf_weather.index.tz
mf = read_idf(idf)
out["multifamily: Simulation set-up, January at 10 min"] = best(
    lambda: Simulation(mf, mf_weather, mf_meta, step="10min",
                       start=pd.Timestamp("2023-01-01", tz=tz),
                       end=pd.Timestamp("2023-02-01", tz=tz), store_surfaces=False))
out["peer: free-running simulation of the clinic month"] = best(
    lambda: sim.run(free_float=True))
print(json.dumps(out))
"""


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--tree", action="append", required=True, help="label=path/to/src")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--write", type=Path)
    args = parser.parse_args(argv)
    trees = dict(item.split("=", 1) for item in args.tree)
    idf = str(MULTIFAMILY / "multifamily_5A_FF_v25.idf")
    results: dict[str, dict[str, float]] = {label: {} for label in trees}
    for _ in range(args.rounds):
        for label, src in trees.items():
            env = dict(os.environ, PYTHONPATH=str(Path(src).resolve()))
            run = subprocess.run(
                [sys.executable, "-c", CHILD, str(args.repeats), idf],
                env=env,
                check=True,
                capture_output=True,
                text=True,
            )
            for case, value in json.loads(run.stdout.strip().splitlines()[-1]).items():
                results[label][case] = min(results[label].get(case, float("inf")), value)
    peer = "peer: free-running simulation of the clinic month"
    labels = list(trees)
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"Date: {stamp}. Machine: {platform.machine()}, 2 cores shared; Python "
        f"{platform.python_version()}. Best of {args.rounds} rounds x {args.repeats} repeats.",
        "",
        "| case | "
        + " | ".join(f"{label} [s]" for label in labels)
        + " | "
        + " | ".join(f"{label} / peer" for label in labels)
        + " | "
        + f"{labels[0]} / {labels[-1]} |",
        "|---|" + "---:|" * (2 * len(labels) + 1),
    ]
    for case in results[labels[0]]:
        walls = [results[label][case] for label in labels]
        ratios = [results[label][case] / results[label][peer] for label in labels]
        lines.append(
            f"| {case} | "
            + " | ".join(f"{w:.3f}" for w in walls)
            + " | "
            + " | ".join(f"{r:.3f}" for r in ratios)
            + f" | {walls[0] / walls[-1]:.2f} |"
        )
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
