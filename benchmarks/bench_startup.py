"""What a command imports before any work, and what each import costs (issue 22, item 3).

Runs ``thermocal simulate`` (the multi-zone example, two days hourly with pvlib's TMY3 file) and
``thermocal identify --demo`` (which writes figures: matplotlib is its one heavy import by
need) as whole processes under ``python -X importtime`` and
lists, per command: the total import time, the cost of each third-party package as it was
first imported (cumulative, its own dependencies included when they came with it), and which
of the heavy packages a command must not need (matplotlib, scikit-learn, dask/distributed,
SALib, emcee, statsmodels, scipy.stats) were imported.

Run: python benchmarks/bench_startup.py [--repeats 3]
The import times are the medians over the repeats (each a fresh process; the machine is shared,
so the table also gives the load average).
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("matplotlib", "sklearn", "dask", "distributed", "SALib", "emcee", "statsmodels")

_RUN = """
import atexit, sys
def _report():
    names = sorted(m for m in sys.modules
                   if m.split('.')[0] in {heavy!r} or m == 'scipy.stats')
    print('HEAVY ' + ' '.join(sorted({{n.split('.')[0] if n != 'scipy.stats' else n
                                      for n in names}})), file=sys.stderr)
atexit.register(_report)
sys.argv = ['thermocal'] + {args!r}
from thermocal.cli import main
main()
"""


def command_args(name: str, out: Path) -> list[str]:
    """The command line of ``name`` writing into ``out``."""
    import pvlib

    weather = Path(pvlib.__file__).parent / "data" / "723170TYA.CSV"
    if name == "simulate":
        building = ROOT / "examples" / "buildings" / "multizone_single_family_house.yaml"
        return ["simulate", str(building), str(weather), "--start", "2001-01-10", "--end",
                "2001-01-12", "--step", "1h", "--warmup-days", "1", "--out", str(out)]  # fmt: skip
    return ["identify", "--demo", "--out", str(out)]


def parse_importtime(text: str) -> tuple[float, dict[str, float], list[str]]:
    """Total import time [s], cumulative time of each top-level package at its first import
    [s], and the heavy packages the process imported."""
    total, first = 0.0, {}
    heavy: list[str] = []
    for line in text.splitlines():
        if line.startswith("HEAVY"):
            heavy = line.split()[1:]
            continue
        if not line.startswith("import time:") or "self [us]" in line:
            continue
        _, cumulative, name = line.split("|", 2)
        depth = (len(name) - len(name.lstrip(" "))) // 2
        if depth != 1:  # the modules imported directly by the running code
            continue
        seconds = int(cumulative) / 1e6
        total += seconds
        package = name.strip().split(".")[0]
        first[package] = first.get(package, 0.0) + seconds
    return total, first, heavy


def measure(name: str, repeats: int) -> dict:
    """Median import times of ``repeats`` fresh processes of command ``name``."""
    totals, packages, heavy = [], {}, []
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as tmp:
            script = _RUN.format(heavy=set(HEAVY), args=command_args(name, Path(tmp) / "out"))
            done = subprocess.run([sys.executable, "-X", "importtime", "-c", script],
                                  capture_output=True, text=True, env=env)  # fmt: skip
        if done.returncode != 0:
            raise SystemExit(f"{name} failed: {done.stderr[-2000:]}")
        total, first, heavy = parse_importtime(done.stderr)
        totals.append(total)
        for package, seconds in first.items():
            packages.setdefault(package, []).append(seconds)
    medians = {p: statistics.median(v) for p, v in packages.items()}
    return {"total": statistics.median(totals), "packages": medians, "heavy": heavy}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    load = os.getloadavg()[0]
    print(f"# start-up imports, {datetime.date.today()}, {platform.machine()}, "
          f"{os.cpu_count()} cores, load average {load:.1f}\n")  # fmt: skip
    for name in ("simulate", "identify"):
        result = measure(name, args.repeats)
        print(f"## thermocal {name}: imports {result['total']:.2f} s (median of {args.repeats})")
        print(f"heavy packages imported: {', '.join(result['heavy']) or 'none'}\n")
        print("| package (first imported by) | cumulative import time [s] |")
        print("|---|---:|")
        for package, seconds in sorted(result["packages"].items(), key=lambda kv: -kv[1])[:12]:
            print(f"| {package} | {seconds:.3f} |")
        print()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
