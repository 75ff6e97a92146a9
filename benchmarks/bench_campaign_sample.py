"""One sample of the clinic's calibration campaign, against a peer commit (issue 22: the
per-sample overhead besides the compiled time loop).

A sample is what :func:`thermocal.calibration.runner.run_campaign` asks of each worker:
``IdentificationProblem.evaluate`` with a set of envelope parameters, i.e. ``set_parameters``
(the network re-assembled and refactorised), the exact-inverse identification of the month
(warm-up + 8,928 five-minute steps, 186 zones) and the unoccupied-variance metric. The samples
are the demo campaign's (70 parameters of ``material/*``, ``window/*``, ``infiltration/*`` at
+-50 %, Sobol, seed 1), as ``benchmarks/bench_calibration.py``.

Two long-lived child processes, one per source (this tree and, with ``--peer COMMIT``, the
peer's ``src`` extracted once with ``git archive``), build the problem once and then evaluate
the same samples in turn (A B A B ...), so both see the same machine load. Per sample and
source: the whole ``evaluate`` wall time and its parts (the compiled time loop,
``_kernel.run_steps``, and everything outside it; ``set_parameters``; the network assembly
alone; the identification and metric), each best over the rounds. The identified heat and
the metric of every sample are compared between the sources (bit-identical, or the largest
difference relative to the largest heat). Then, in this tree's child, the network assembly of
every sample by this ``network.py`` and the peer's, in turn in one process (every field of the
networks compared), and each child's peak memory.

Run::

    python benchmarks/bench_campaign_sample.py [--peer COMMIT] [--samples 4] [--rounds 2]
        [--write results.md]

Without ``--peer`` only this tree is timed.
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _peer import peer_source  # benchmarks/ is the script's folder

REPO = Path(__file__).resolve().parents[1]



# ----------------------------------------------------------------------------------------------
# the child: one source, commands on stdin, one JSON line per answer on stdout
# ----------------------------------------------------------------------------------------------


def _clinic_problem(n_samples: int):
    """The demo's clinic problem and ``n_samples`` campaign samples (as bench_calibration)."""
    from thermocal.calibration.sampling import sample
    from thermocal.calibration.space import ParameterSpace
    from thermocal.demos.identification import load_demo
    from thermocal.identification.problem import problem_from_measurements

    building, weather, meta, raw, mapping, _ = load_demo()
    start, end = meta["period"]
    problem, _ = problem_from_measurements(
        building, weather, meta["weather"], raw, mapping, start=start, end=end
    )
    space = ParameterSpace.from_parameters(
        building.parameters(),
        include=["material/*", "window/*", "infiltration/*"],
        default_range=0.5,
    )
    values = sample(space, n_samples, "sobol", seed=1).values
    return problem, [values.iloc[i].to_dict() for i in range(n_samples)]


def _identified_heat(problem, parameters) -> np.ndarray:
    """The identified heat of one sample (steps x tracked zones) [W], by the lean path where
    the source has one, else from the whole tracking result."""
    if hasattr(problem, "identified_heat"):
        return problem.identified_heat(parameters)
    return problem.run(parameters).heat.to_numpy()


def _timed_parts(problem, parameters) -> dict:
    """``set_parameters`` (and the network assembly inside it) and the compiled loop
    (``_kernel.run_steps``) timed by wrapping them."""
    from thermocal.multizone import _kernel, _network_setup

    sim = problem.simulation()
    spent = {"set_parameters": 0.0, "assemble": 0.0, "compiled loop": 0.0}
    original_set = sim.set_parameters
    original_assemble = _network_setup.assemble
    original_kernel = _kernel.run_steps

    def run_steps(*args):
        t0 = time.perf_counter()
        original_kernel(*args)
        spent["compiled loop"] += time.perf_counter() - t0

    def set_parameters(mapping):
        t0 = time.perf_counter()
        original_set(mapping)
        spent["set_parameters"] += time.perf_counter() - t0

    def assemble(*args, **kwargs):
        t0 = time.perf_counter()
        out = original_assemble(*args, **kwargs)
        spent["assemble"] += time.perf_counter() - t0
        return out

    sim.set_parameters = set_parameters
    _network_setup.assemble = assemble
    _kernel.run_steps = run_steps
    try:
        t0 = time.perf_counter()
        metric = problem.evaluate(parameters)
        spent["sample"] = time.perf_counter() - t0
    finally:
        del sim.set_parameters
        _network_setup.assemble = original_assemble
        _kernel.run_steps = original_kernel
    spent["identification + metric"] = spent["sample"] - spent["set_parameters"]
    spent["outside the compiled loop"] = spent["sample"] - spent["compiled loop"]
    spent["metric"] = metric
    return spent


def _same_network(a, b) -> bool:
    """Whether two assembled networks have identical fields (sparse matrices entry by entry)."""
    import dataclasses

    import scipy.sparse as sp

    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if sp.issparse(x):
            same = (
                x.format == y.format
                and np.array_equal(x.indptr, y.indptr)
                and np.array_equal(x.indices, y.indices)
                and np.array_equal(x.data, y.data)
            )
        elif isinstance(x, np.ndarray):
            same = x.dtype == y.dtype and np.array_equal(x, y)
        else:
            same = x == y
        if not same:
            return False
    return True


def _assembly_against(problem, samples, peer_network: Path, repeats: int = 3) -> dict:
    """The network assembly of each sample by this source and by the peer's ``network.py``
    (loaded from its file), in turn: best times [s] and whether every field is identical."""
    import importlib.util

    from thermocal.multizone import _network_setup

    spec = importlib.util.spec_from_file_location("thermocal.multizone.peer_network", peer_network)
    peer = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = peer
    spec.loader.exec_module(peer)
    sim = problem.simulation()
    captured = []
    original = _network_setup.assemble

    def record(*args, **kwargs):
        captured.append((args, {k: v for k, v in kwargs.items() if k != "cache"}))
        return original(*args, **kwargs)

    _network_setup.assemble = record
    try:
        for parameters in samples:  # behind the problem's back: the child's last command
            sim.set_parameters(parameters)
    finally:
        _network_setup.assemble = original
    times = {"peer": float("inf"), "this": float("inf")}
    identical = True
    for args, kwargs in captured:
        caches = {"peer": {}, "this": {}}
        built = {}
        for _ in range(repeats):
            for label, assemble in (("peer", peer.assemble), ("this", original)):
                t0 = time.perf_counter()
                built[label] = assemble(*args, cache=caches[label], **kwargs)
                times[label] = min(times[label], time.perf_counter() - t0)
        identical &= _same_network(built["peer"], built["this"])
    return {"peer": times["peer"], "this": times["this"], "identical": identical}


def child(n_samples: int) -> None:
    """Answer ``sample I`` (timings and metric), ``heat I PATH`` (the identified heat saved,
    its digest), ``assemble PEER_NETWORK_PY`` (the assembly against the peer's) and ``rss``
    (peak resident memory [GB]) commands, one JSON line each."""
    import resource
    import warnings

    warnings.simplefilter("ignore")
    problem, samples = _clinic_problem(n_samples)
    problem.evaluate({})  # compile and build once
    print(json.dumps({"ready": True}), flush=True)
    for line in sys.stdin:
        command, _, argument = line.strip().partition(" ")
        if command == "sample":
            parts = _timed_parts(problem, samples[int(argument)])
            metric = parts.pop("metric")
            parts["metric_hex"] = {k: float(v).hex() for k, v in metric.items()}
            print(json.dumps(parts), flush=True)
        elif command == "heat":
            index, path = argument.split()
            heat = np.ascontiguousarray(_identified_heat(problem, samples[int(index)]))
            np.save(path, heat)
            digest = hashlib.sha256(heat.tobytes()).hexdigest()
            print(json.dumps({"sha256": digest}), flush=True)
        elif command == "assemble":
            result = _assembly_against(problem, samples, Path(argument.strip()))
            print(json.dumps(result), flush=True)
        elif command == "rss":
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
            print(json.dumps({"rss_GB": peak}), flush=True)
        else:
            raise SystemExit(f"unknown command {command!r}")


# ----------------------------------------------------------------------------------------------
# the driver
# ----------------------------------------------------------------------------------------------


class Worker:
    """A child process on one source."""

    def __init__(self, label: str, src: Path, n_samples: int) -> None:
        self.label = label
        env = dict(os.environ, PYTHONPATH=str(src))
        self.process = subprocess.Popen(
            [sys.executable, __file__, "--child", str(n_samples)],
            env=env,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )

    def ask(self, command: str) -> dict:
        if command:
            self.process.stdin.write(command + "\n")
            self.process.stdin.flush()
        line = self.process.stdout.readline()
        if not line:
            raise RuntimeError(f"the {self.label} child stopped")
        return json.loads(line)

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait(timeout=60)


PARTS = (
    "sample",
    "compiled loop",
    "outside the compiled loop",
    "set_parameters",
    "assemble",
    "identification + metric",
)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--peer", help="a commit to time alongside (e.g. d094095)")
    parser.add_argument("--samples", type=int, default=4)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--write", type=Path)
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child is not None:
        child(args.child)
        return 0
    sources = {"this": REPO / "src"}
    if args.peer:
        sources = {"peer": peer_source(args.peer), **sources}
    workers = {label: Worker(label, src, args.samples) for label, src in sources.items()}
    started = time.perf_counter()
    for worker in workers.values():
        worker.ask("")  # ready
    load = [os.getloadavg()[0]]
    best = {label: {i: {} for i in range(args.samples)} for label in workers}
    metrics = {label: {} for label in workers}
    for r in range(args.rounds):
        for i in range(args.samples):
            order = list(workers) if (r + i) % 2 == 0 else list(workers)[::-1]
            for label in order:
                answer = workers[label].ask(f"sample {i}")
                metrics[label][i] = answer.pop("metric_hex")
                for part in PARTS:
                    previous = best[label][i].get(part, float("inf"))
                    best[label][i][part] = min(previous, answer[part])
            load.append(os.getloadavg()[0])
    same_heat, worst = True, 0.0
    if args.peer:
        folder = Path(tempfile.mkdtemp(prefix="thermocal_bench_sample_"))
        for i in range(args.samples):
            heat = {}
            for label, worker in workers.items():
                path = folder / f"{label}_{i}.npy"
                worker.ask(f"heat {i} {path}")
                heat[label] = np.load(path)
            if not np.array_equal(heat["peer"], heat["this"]):
                same_heat = False
                scale = float(np.max(np.abs(heat["peer"])))
                worst = max(worst, float(np.max(np.abs(heat["peer"] - heat["this"]))) / scale)
    assembly = None
    if args.peer:
        network_py = sources["peer"] / "thermocal" / "multizone" / "network.py"
        assembly = workers["this"].ask(f"assemble {network_py}")
    rss = {label: worker.ask("rss")["rss_GB"] for label, worker in workers.items()}
    for worker in workers.values():
        worker.close()
    wall = time.perf_counter() - started

    def mean(label, part):
        return sum(best[label][i][part] for i in range(args.samples)) / args.samples

    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"Date: {stamp}. Machine: {platform.machine()}, {os.cpu_count()} cores (shared, load "
        f"average {min(load):.1f}-{max(load):.1f} during the run); Python "
        f"{platform.python_version()}. Clinic demo (186 zones, 8,928 steps of 5 min, exact "
        f"inverse), {args.samples} campaign samples x {args.rounds} rounds, each source in its "
        f"own process, in turn; best per sample, mean over the samples; {wall:.0f} s in all.",
        "",
    ]
    if args.peer:
        lines += [
            f"| part of a sample [s] | peer {args.peer} | this | saved | speed-up |",
            "|---|---:|---:|---:|---:|",
        ]
        for part in PARTS:
            before, after = mean("peer", part), mean("this", part)
            lines.append(
                f"| {part} | {before:.3f} | {after:.3f} | {before - after:.3f} | "
                f"{before / after:.2f}x |"
            )
        lines.append(
            f"| network assembly alone, both in one process in turn | {assembly['peer']:.3f} | "
            f"{assembly['this']:.3f} | {assembly['peer'] - assembly['this']:.3f} | "
            f"{assembly['peer'] / assembly['this']:.2f}x |"
        )
        lines.append(
            f"| peak memory of the child after the run [GB] | {rss['peer']:.2f} | "
            f"{rss['this']:.2f} | | |"
        )
        same_metric = metrics["peer"] == metrics["this"]
        lines += [
            "",
            "Identified heat of every sample: "
            + ("bit-identical" if same_heat else f"differs, largest {worst:.2g} relative")
            + "; metrics (variance, std, mean): "
            + ("bit-identical" if same_metric else "DIFFER")
            + "; assembled networks (every field, every sample): "
            + ("identical" if assembly["identical"] else "DIFFER")
            + ".",
        ]
    else:
        lines += ["| part of a sample [s] | this |", "|---|---:|"]
        lines += [f"| {part} | {mean('this', part):.3f} |" for part in PARTS]
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
