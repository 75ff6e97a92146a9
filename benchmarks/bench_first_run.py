"""A fresh install's first run against its second: what numba's compilation costs a user.

numba compiles the kernels on their first call and caches the machine code next to the
sources (``__pycache__``, keyed on the source files' paths and times), so a fresh install's
first ``thermocal demo`` or ``thermocal identify --demo`` pays for the compilation once and
every later run reads the cache. This copies ``src/thermocal`` into a temporary folder (a cold
cache, as after ``pip install``), runs each command there twice as whole processes, and prints
the first run, the second (the warm peer, same machine, same minute) and their ratio, with the
compilation time per kernel of the first run (numba's compile events, exclusive of the kernels
each one compiled inside it).

Run: python benchmarks/bench_first_run.py [--commands demo identify]
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
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

_RUN = """
import atexit, collections, sys, time
from numba.core import event
own = collections.defaultdict(float)
stack = []
class Listener(event.Listener):
    def on_start(self, ev):
        stack.append([time.perf_counter(), 0.0])
    def on_end(self, ev):
        start, inner = stack.pop()
        took = time.perf_counter() - start
        f = ev.data['dispatcher'].py_func
        name = f.__module__ + '.' + f.__qualname__
        own[name if name.startswith('thermocal') else 'numba internals'] += took - inner
        if stack:
            stack[-1][1] += took
event.register('numba:compile', Listener())
def _report():
    for name, took in own.items():
        print(f'COMPILE {{took:.3f}} {{name}}', file=sys.stderr)
atexit.register(_report)
sys.argv = ['thermocal'] + {args!r}
from thermocal.cli import main
main()
"""

COMMANDS = {
    "demo": ["demo", "--draws", "0"],
    "identify": ["identify", "--demo"],
}


def run_once(src: Path, args: list[str], out: Path) -> tuple[float, dict[str, float]]:
    """Wall time [s] of one process running ``thermocal ARGS --out OUT`` from ``src`` and the
    compilation time per kernel [s]."""
    env = {**os.environ, "PYTHONPATH": str(src)}
    code = _RUN.format(args=[*args, "--out", str(out)])
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=False
    )
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"thermocal {' '.join(args)} failed:\n{done.stderr[-2000:]}")
    compiled = {}
    for line in done.stderr.splitlines():
        if line.startswith("COMPILE "):
            _, took, name = line.split(" ", 2)
            compiled[name] = compiled.get(name, 0.0) + float(took)
    return wall, compiled


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--commands", nargs="+", default=list(COMMANDS), choices=list(COMMANDS))
    args = parser.parse_args()
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    print(f"{stamp}, {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.1f}")  # fmt: skip
    print("| command | first run [s] | second run [s] | first / second | compiling [s] |")
    print("|---|---:|---:|---:|---:|")
    details = {}
    for name in args.commands:
        with tempfile.TemporaryDirectory() as tmp:
            src = Path(tmp) / "src"
            shutil.copytree(ROOT / "src" / "thermocal", src / "thermocal",
                            ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
            first, compiled = run_once(src, COMMANDS[name], Path(tmp) / "out1")
            second, _ = run_once(src, COMMANDS[name], Path(tmp) / "out2")
        total = sum(compiled.values())
        print(f"| `thermocal {' '.join(COMMANDS[name])}` | {first:.1f} | {second:.1f} | "
              f"{first / second:.1f} | {total:.1f} |")  # fmt: skip
        details[name] = compiled
    for name, compiled in details.items():
        print(f"\n{name}: the first run's compilation by kernel (own time, >= 0.5 s)")
        for kernel, took in sorted(compiled.items(), key=lambda kv: -kv[1]):
            if took >= 0.5:
                print(f"  {took:6.1f} s  {kernel}")


if __name__ == "__main__":
    main()
