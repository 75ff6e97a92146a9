"""Peak memory of the clinic month and of ``thermocal simulate`` (issue 22 item 4: the clinic
month <= 0.5 GB), this tree against a peer commit.

Every case runs in a fresh process on one source (this tree's ``src`` or, with ``--peer
COMMIT``, the peer's, extracted once with ``git archive``) and reports the peak resident memory
of the process (``VmHWM``) and, for the campaign, of each worker of its pool (sampled from
``/proc`` every 0.2 s). Each case runs ``--repeats`` times per source, in turn (A B A B), after
one untimed run that fills numba's cache for that source; memory does not depend on the load,
so the best and the worst repeat are reported.

Cases:

- ``free run``: the generated clinic (186 zones, 7,083 nodes), January at 5 minutes with given
  heat (``Simulation.run``), ASHRAE 140's Denver TMY3;
- ``identification``: the identification demo as a user runs it (its month-long sensor log of
  810,893 rows read, the problem set up, the exact inverse of the month with its data frames);
- ``campaign worker``: ``run_campaign`` with a local pool of 2 workers over the demo
  campaign's first ``--samples`` Sobol samples (70 parameters); the larger worker;
- ``identify``: ``thermocal identify --demo --method inverse`` (the whole command: the same
  month as ``identification``, its files, figures and report written; the command's allocator
  setting, ``thermocal.cli._return_freed_arrays_to_the_system``, applies);
- ``simulate``: ``thermocal simulate`` of the 180-zone grid IDF for January at 5 minutes (the
  whole command, its CSV files written); the files of the two sources are compared byte for
  byte.

Run::

    python benchmarks/bench_memory.py [--peer COMMIT] [--repeats 2] [--samples 8]
        [--only NAME ...] [--write results.md]

Needs ``../shared/data`` (the weather files and the grid IDF); a case whose data are absent is
skipped with the reason.
"""

from __future__ import annotations

import argparse
import datetime
import filecmp
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

from _peer import peer_source  # benchmarks/ is the script's folder

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data"
DENVER = DATA / "ashrae140_bestest" / "725650TYCST.epw"
GRID = DATA / "energyplus_reference" / "grid_180_zones_5min_january_v25.idf"

#: What each case runs in its process (``OUT``: a folder for its files; ``SAMPLES``).
CASES = {
    "free run": """
import numpy as np
from thermocal.demos.buildings import clinic
from thermocal.io.weather import read_weather
from thermocal.multizone.simulation import Simulation
weather, meta = read_weather(DENVER)
building = clinic()
sim = Simulation(building, weather, meta, step="5min", start="2023-01-01", end="2023-02-01",
                 store_surfaces=False)
result = sim.run(free_float=True, heat_input=np.full((len(sim.times), len(building.zones)), 300.0))
""",
    "identification": """
from thermocal.demos.identification import load_demo
from thermocal.identification.problem import problem_from_measurements
building, weather, meta, raw, mapping, _ = load_demo()
start, end = meta["period"]
problem, _ = problem_from_measurements(building, weather, meta["weather"], raw, mapping,
                                       start=start, end=end)
result = problem.run()
""",
    "campaign worker": """
from pathlib import Path
from thermocal.calibration.runner import run_campaign
from thermocal.calibration.sampling import sample
from thermocal.calibration.space import ParameterSpace
from thermocal.calibration.store import CampaignStore
from thermocal.demos.identification import load_demo
from thermocal.identification.problem import problem_from_measurements
if __name__ == "__main__":
    building, weather, meta, raw, mapping, _ = load_demo()
    start, end = meta["period"]
    problem, _ = problem_from_measurements(building, weather, meta["weather"], raw, mapping,
                                           start=start, end=end)
    space = ParameterSpace.from_parameters(
        building.parameters(), include=["material/*", "window/*", "infiltration/*"],
        default_range=0.5)
    values = sample(space, SAMPLES, "sobol", seed=1).values
    store = CampaignStore.open(Path(OUT) / "campaign.sqlite", definition={"label": "memory"})
    run_campaign(problem, values, store, progress=False, workers=2)
    FAILED = int(store.to_frame()["error"].notna().sum())
    store.close()
""",
    "identify": """
import sys
from thermocal.cli import main
sys.argv = ["thermocal", "identify", "--demo", "--method", "inverse", "--out",
            str(Path(OUT) / "identify")]
try:
    main()
except SystemExit as stop:
    assert not stop.code, stop.code
""",
    "simulate": """
import sys
from thermocal.cli import main
sys.argv = ["thermocal", "simulate", str(GRID), str(DENVER), "--out", str(Path(OUT) / "sim")]
try:
    main()
except SystemExit as stop:
    assert not stop.code, stop.code
""",
}

#: Shared data each case needs.
NEEDS = {
    "free run": [DENVER],
    "identification": [],
    "campaign worker": [],
    "identify": [],
    "simulate": [GRID, DENVER],
}

#: Wraps a case: the workers' peaks sampled from /proc, the process's own at the end.
HARNESS = """
import json, os, threading, time, warnings
from pathlib import Path

warnings.simplefilter("ignore")
DENVER, GRID, OUT, SAMPLES = Path({denver!r}), Path({grid!r}), {out!r}, {samples}
FAILED = 0
WORKERS = {{}}

def _status(pid):
    try:
        text = Path(f"/proc/{{pid}}/status").read_text()
    except OSError:
        return None
    return dict(line.split(":", 1) for line in text.splitlines() if ":" in line)

def _watch(stop):
    me = os.getpid()
    while not stop.is_set():
        family, table = {{me}}, {{}}
        for entry in os.listdir("/proc"):
            if entry.isdigit() and (status := _status(entry)) is not None:
                table[int(entry)] = status
        grown = True
        while grown:
            grown = False
            for pid, status in table.items():
                if pid not in family and int(status.get("PPid", "0")) in family:
                    family.add(pid)
                    grown = True
        for pid in family - {{me}}:
            hwm = table[pid].get("VmHWM")
            if hwm:
                WORKERS[pid] = max(WORKERS.get(pid, 0.0), int(hwm.split()[0]) / 1024**2)
        time.sleep(0.2)

if __name__ == "__main__":
    _stop = threading.Event()
    _thread = threading.Thread(target=_watch, args=(_stop,), daemon=True)
    _thread.start()
{case}
if __name__ == "__main__":
    _stop.set()
    _thread.join()
    own = int(_status("self")["VmHWM"].split()[0]) / 1024**2
    # the pool's workers are the processes that grew beyond start-up (the fork server and the
    # resource tracker stay small)
    workers = sorted(v for v in WORKERS.values() if v > 0.1)
    print("MEMORY " + json.dumps({{"process_GiB": own, "workers_GiB": workers,
                                  "failed": FAILED}}))
"""



def run_case(name: str, source: Path, out: Path, samples: int) -> dict:
    """One fresh process of ``name`` on ``source``; its memory report."""
    out.mkdir(parents=True, exist_ok=True)
    script = out / "case.py"
    case = "\n".join(
        ("    " + line if name == "campaign worker" and line else line)
        for line in CASES[name].strip("\n").splitlines()
    )
    if name == "campaign worker":  # its own main guard: the pool's processes import the script
        case = "\n".join(line[4:] for line in case.splitlines())
    script.write_text(HARNESS.format(denver=str(DENVER), grid=str(GRID), out=str(out),
                                     samples=samples, case=case))  # fmt: skip
    env = dict(os.environ, PYTHONPATH=str(source))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env,
                          cwd=str(out))  # fmt: skip
    lines = [line for line in done.stdout.splitlines() if line.startswith("MEMORY ")]
    if done.returncode != 0 or not lines:
        raise RuntimeError(f"{name} on {source} failed:\n{done.stderr[-3000:]}")
    return json.loads(lines[-1][len("MEMORY ") :])


def headline(report: dict, name: str) -> float:
    """The figure that counts: the larger worker for the campaign, else the process."""
    if name == "campaign worker":
        return max(report["workers_GiB"]) if report["workers_GiB"] else float("nan")
    return report["process_GiB"]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--peer", default=None, help="commit to compare with (its src)")
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--samples", type=int, default=8, help="campaign samples (2 workers)")
    parser.add_argument("--only", nargs="*", default=None, choices=list(CASES))
    parser.add_argument("--write", type=Path, default=None)
    args = parser.parse_args(argv)
    sources = {"this": REPO / "src"}
    if args.peer:
        sources = {f"peer {args.peer[:7]}": peer_source(args.peer), **sources}
    rows, notes = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.only or list(CASES):
            missing = [str(p) for p in NEEDS[name] if not p.exists()]
            if missing:
                notes.append(f"{name}: skipped, missing {', '.join(missing)}")
                continue
            figures: dict[str, list[float]] = {label: [] for label in sources}
            folders: dict[str, Path] = {}
            for label, source in sources.items():  # fills numba's cache for this source
                run_case(name, source, Path(tmp) / "warm" / label.replace(" ", "_"), 2)
            for repeat in range(args.repeats):
                for label, source in sources.items():
                    folder = Path(tmp) / f"{name}_{label}_{repeat}".replace(" ", "_")
                    report = run_case(name, source, folder, args.samples)
                    if report["failed"]:
                        notes.append(f"{name} on {label}: {report['failed']} samples failed")
                    figures[label].append(headline(report, name))
                    folders[label] = folder
                    print(f"{name:16s} {label:14s} {figures[label][-1]:.3f} GiB", flush=True)
            if name == "simulate" and len(folders) == 2:
                a, b = (folders[label] / "sim" for label in sources)
                same = all(filecmp.cmp(a / f, b / f, shallow=False)
                           for f in ("zone_temperatures.csv", "zone_heat_flows.csv"))  # fmt: skip
                notes.append(f"simulate: the two sources' CSV files are "
                             f"{'byte-identical' if same else 'DIFFERENT'}")  # fmt: skip
            rows.append((name, figures))
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()[0]
    lines = [
        f"Run {stamp}, {platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}, load average {load:.1f}; `python "
        f"benchmarks/bench_memory.py{' --peer ' + args.peer if args.peer else ''} --repeats "
        f"{args.repeats} --samples {args.samples}`; peak resident memory [GiB], best / worst "
        "of the repeats (the campaign: its larger worker):",
        "",
        "| case | " + " | ".join(sources) + " | target |",
        "|---|" + "---:|" * len(sources) + "---|",
    ]
    for name, figures in rows:
        cells = [f"{min(v):.3f} / {max(v):.3f}" for v in figures.values()]
        target = "-" if name == "simulate" else "<= 0.5 GB (0.466 GiB)"
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {target} |")
    lines += [""] + [f"- {note}" for note in notes]
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
