"""The whole ``identify`` on the 118-zone DOE outpatient prototype, against a peer commit
(issue 28, item 8: set-up and memory in line with the kernel).

The inputs are what a user has: the IDF (with its loads, ``--radiant-fraction declared``), the
EPW, a sensor log of 87 of the 118 zones (January at 5 minutes from an EnergyPlus 25.2 free
float) and its mapping, made once by ``benchmarks/make_outpatient_inputs.py`` (generated data,
never committed).

Run::

    python benchmarks/make_outpatient_inputs.py            # once, about a minute
    python benchmarks/bench_identify_outpatient.py --peer <commit> [--rounds 2] [--write F]

Each round times, for the peer's source (extracted once with ``git archive``, as
``bench_select.py`` does) and for this tree, one after the other (order alternating):

* the CLI as a process, ``thermocal identify IDF EPW CSV --mapping M --method inverse
  --radiant-fraction declared``: wall time and the process's peak RSS;
* the same steps in process (a child process per source): imports, IDF import, weather, sensor
  log, the ``identify`` call broken down (model set-up with the simulation's parts: network and
  input matrix, exterior shadows, interior beam, schedules, warm-up; references; the kernel
  loop) and the files (JSON, parquet, figures, report); process peak RSS.

Times are the best of the rounds; numba's caches of both sources are filled by an untimed run
first. Memory: one more in-process run per source under ``tracemalloc`` (peak of Python and
numpy allocations; slower, its times are not used). The identified heat of both sources is
compared element by element (bit-identical, or the largest difference relative to the
largest identified heat).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _peer import peer_source  # benchmarks/ is the script's folder

REPO = Path(__file__).resolve().parents[1]
INPUTS = Path(tempfile.gettempdir()) / "thermocal-bench-outpatient"
#: Simulation methods timed inside the model set-up (those present in the source)
SETUP_PARTS = {
    "_build": "network + input matrix",
    "_shadow_setup": "exterior shadows",
    "_interior_beam_setup": "interior beam",
    "_evaluate_schedules": "schedules",
    "reset": "warm-up",
}



def cli_args(inputs: Path, out: Path) -> list[str]:
    return [
        "identify",
        str(inputs / "outpatient_loads.idf"),
        str(inputs / "weather.epw"),
        str(inputs / "sensors.csv"),
        "--mapping",
        str(inputs / "mapping.yaml"),
        "--method",
        "inverse",
        "--radiant-fraction",
        "declared",
        "--out",
        str(out),
    ]


#: run the CLI, then print the process's peak RSS [kB] on stderr's last line
_CLI = (
    "import atexit, resource, sys\n"
    "atexit.register(lambda: print('MAXRSS', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,"
    " file=sys.stderr))\n"
    "from thermocal.cli import main\n"
    "sys.argv = ['thermocal'] + sys.argv[1:]\n"
    "main()\n"
)


def run_cli(src: Path, inputs: Path, work: Path) -> dict:
    """One ``thermocal identify`` process with ``src`` first on the path."""
    out = work / f"cli-{time.monotonic_ns()}"
    env = dict(os.environ, PYTHONPATH=str(src))
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", _CLI, *cli_args(inputs, out)], env=env,
                          capture_output=True, text=True)  # fmt: skip
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(
            f"identify failed ({src}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
        )
    rss = [line for line in done.stderr.splitlines() if line.startswith("MAXRSS")][-1]
    timings = json.loads((out / "identification.json").read_text())["timings_s"]
    return {"wall": wall, "rss_GB": int(rss.split()[1]) / 1024**2, **timings}


def run_child(src: Path, inputs: Path, work: Path, trace: bool) -> dict:
    """The in-process breakdown in a child process with ``src`` first on the path."""
    env = dict(os.environ, PYTHONPATH=str(src))
    out = work / f"child-{time.monotonic_ns()}"
    cmd = [sys.executable, __file__, "--child", str(inputs), str(out)] + (
        ["--trace"] if trace else []
    )
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"child failed ({src}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}")
    times = json.loads(done.stdout.strip().splitlines()[-1])
    times["q_id"] = str(out / "q_id.npy")
    return times


def child(inputs: Path, out: Path, trace: bool) -> None:
    """In process: each step timed; prints a JSON line; saves q_id as out/q_id.npy."""
    import resource
    import tracemalloc
    import warnings

    warnings.simplefilter("ignore")
    times: dict[str, float] = {}
    if trace:
        tracemalloc.start()
    t0 = time.perf_counter()
    import numpy as np

    from thermocal.identification.sensors import load_mapping
    from thermocal.identification.workflow import identify
    from thermocal.io.measurements import read_measurements
    from thermocal.io.weather import read_weather
    from thermocal.multizone.files import load_building
    from thermocal.multizone.simulation import Simulation

    times["imports"] = time.perf_counter() - t0
    for name in SETUP_PARTS:
        method = getattr(Simulation, name, None)
        if method is None:
            continue

        def timed(*args, _method=method, _name=name, **kwargs):
            start = time.perf_counter()
            try:
                return _method(*args, **kwargs)
            finally:
                key = f"setup: {SETUP_PARTS[_name]}"
                times[key] = times.get(key, 0.0) + time.perf_counter() - start

        setattr(Simulation, name, timed)
    start, end = (inputs / "period.txt").read_text().split()
    t0 = time.perf_counter()
    building = load_building(inputs / "outpatient_loads.idf")
    times["IDF import"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    weather, site = read_weather(inputs / "weather.epw")
    times["weather"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    raw, _ = read_measurements(inputs / "sensors.csv")
    mapping = load_mapping(inputs / "mapping.yaml")
    times["sensor log + mapping"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    result = identify(building, weather, site, raw, mapping, start=start, end=end,
                      method="inverse", radiant_fraction="declared")  # fmt: skip
    times["identify call"] = time.perf_counter() - t0
    for key, value in result.timings.items():
        times[f"identify: {key}"] = value
    t0 = time.perf_counter()
    result.to_files(out)
    times["files (json, parquet, figures, report)"] = time.perf_counter() - t0
    if trace:
        times["traced_peak_GB"] = tracemalloc.get_traced_memory()[1] / 1024**3
        tracemalloc.stop()
    times["rss_GB"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
    np.save(out / "q_id.npy", result.q_id.to_numpy())
    print(json.dumps(times))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--peer", required=False, help="commit to time alongside")
    parser.add_argument("--peer-src", type=Path, help="an extracted `src` of the peer to use")
    parser.add_argument("--inputs", type=Path, default=INPUTS)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--write", type=Path)
    parser.add_argument("--child", nargs=2, type=Path, help=argparse.SUPPRESS)
    parser.add_argument("--trace", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child(*args.child, args.trace)
        return 0
    import numpy as np

    if not (args.inputs / "period.txt").exists():
        parser.error(f"no inputs in {args.inputs}: run benchmarks/make_outpatient_inputs.py")
    sources = {"this": REPO / "src"}
    if args.peer or args.peer_src:
        sources = {"peer": args.peer_src or peer_source(args.peer), **sources}
    load = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for src in sources.values():  # numba caches
            run_cli(src, args.inputs, work)
        cli = {name: [] for name in sources}
        inproc = {name: [] for name in sources}
        for k in range(args.rounds):
            order = list(sources) if k % 2 == 0 else list(sources)[::-1]
            for name in order:
                cli[name].append(run_cli(sources[name], args.inputs, work))
                print(f"round {k}, {name}: CLI {cli[name][-1]['wall']:.2f} s", flush=True)
            for name in order:
                inproc[name].append(run_child(sources[name], args.inputs, work, trace=False))
                print(f"round {k}, {name}: in process {inproc[name][-1]['identify call']:.2f} s",
                      flush=True)  # fmt: skip
        traced = {
            name: run_child(src, args.inputs, work, trace=True) for name, src in sources.items()
        }
        q = {name: np.load(traced[name]["q_id"]) for name in sources}
        identical = None
        if "peer" in q:
            difference = np.nanmax(np.abs(q["peer"] - q["this"])) / np.nanmax(np.abs(q["peer"]))
            identical = (
                "bit-identical"
                if np.array_equal(q["peer"], q["this"], equal_nan=True)
                else f"largest difference {difference:.1e} of the largest |q_id|"
            )
    load_after = os.getloadavg()

    def best(rows, key):
        values = [r[key] for r in rows if key in r]
        return min(values) if values else float("nan")

    names = list(sources)
    header = "| step | " + " | ".join(names) + (" | peer / this |" if "peer" in sources else " |")
    lines = [header, "|---|" + "---:|" * (len(names) + ("peer" in sources))]

    def row(label, values, unit):
        cells = [f"{v:.2f} {unit}" for v in values]
        ratio = f" {values[0] / values[1]:.2f}x |" if len(values) == 2 and values[1] else ""
        lines.append(f"| {label} | " + " | ".join(cells) + " |" + ratio)

    row("CLI `thermocal identify` (process, wall)", [best(cli[n], "wall") for n in names], "s")
    for key in ("model_setup", "references", "inverse"):
        row(f"CLI: identify {key}", [best(cli[n], key) for n in names], "s")
    row("CLI peak RSS", [best(cli[n], "rss_GB") for n in names], "GB")
    keys = [k for k in inproc[names[-1]][0] if k not in ("rss_GB", "q_id")]
    for key in keys:
        row(f"in process: {key}", [best(inproc[n], key) for n in names], "s")
    row("in process: tracemalloc peak", [traced[n]["traced_peak_GB"] for n in names], "GB")
    row("in process: peak RSS (traced run)", [traced[n]["rss_GB"] for n in names], "GB")
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    text = "\n".join(
        [
            f"Date: {stamp}. Machine: {platform.machine()}, 2 cores shared, load "
            f"{load[0]:.1f} before / {load_after[0]:.1f} after; Python "
            f"{platform.python_version()}. Best of {args.rounds} rounds"
            + (f"; peer {args.peer or args.peer_src}" if "peer" in sources else "")
            + (f"; q_id peer vs this: {identical}" if identical is not None else "")
            + ".",
            "",
            *lines,
        ]
    )
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
