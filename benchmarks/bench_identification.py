"""Speed and memory of the heat-balance identification (thermocal.identification, issue 8).

Targets: PID identification of the ~180-zone clinic over one month at 5-minute steps <= 1.5 s
on one core (the paper: about 4 minutes per EnergyPlus co-simulation), memory <= 1 GB; the exact
inverse no slower than the PID.

Run: python benchmarks/bench_identification.py [--repeats 3] [--write results.md]
Times are the best of the repeats of the closed loop (``Simulation.track``: warm-up and the
month), numba compilation excluded; the free-running simulation of the same month is timed in
the same run as the peer (ratio), since the machine is shared.
"""

from __future__ import annotations

import argparse
import datetime
import platform
import resource
import time
import warnings
from pathlib import Path

import numpy as np


def best(function, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times), float(np.median(times))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--write", type=Path)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    from thermocal.demos.identification import load_demo
    from thermocal.identification.pid import kernel_coefficients
    from thermocal.identification.problem import problem_from_measurements
    from thermocal.identification.tuning import tune_zone, volume_scaled_gains

    building, weather, meta, raw, mapping, _ = load_demo()
    start, end = meta["period"]
    t0 = time.perf_counter()
    problem, _ = problem_from_measurements(
        building, weather, meta["weather"], raw, mapping, start=start, end=end
    )
    setup = time.perf_counter() - t0
    sim = problem.simulation()
    reference = problem.reference[list(building.zones)].to_numpy()
    t0 = time.perf_counter()
    tuning = tune_zone(building, outdoor_temperature=float(weather["temp_air"].mean()))
    tuning_time = time.perf_counter() - t0
    gains = volume_scaled_gains(building, tuning)
    pid = kernel_coefficients([gains[z] for z in building.zones])
    # warm the kernels
    sim.track(reference, method="inverse")
    sim.track(reference, method="pid", pid=pid)
    sim.run(free_float=True)
    rows = []
    free = best(lambda: sim.run(free_float=True), args.repeats)
    inverse = best(lambda: sim.track(reference, method="inverse"), args.repeats)
    pid_time = best(lambda: sim.track(reference, method="pid", pid=pid), args.repeats)
    operative = best(
        lambda: sim.track(reference, method="inverse", feedback="operative"), args.repeats
    )
    sample = best(lambda: problem.evaluate({"material/R16 insulation/resistance": 2.0}),
                  args.repeats)
    memory = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
    n_steps, n_zones = reference.shape
    rows.append(("free-running simulation of the month (peer)", *free, "s", "", ""))
    rows.append(("PID identification (ZN gains), warm-up + month", *pid_time, "s", "<= 1.5",
                 "pass" if pid_time[0] <= 1.5 else "FAIL"))
    rows.append(("exact inverse (air), warm-up + month", *inverse, "s", "<= PID",
                 "pass" if inverse[0] <= 1.05 * pid_time[0] else "FAIL"))
    rows.append(("exact inverse (operative), warm-up + month", *operative, "s", "", ""))
    rows.append(("one campaign sample: set 1 parameter + inverse + metric", *sample, "s", "", ""))
    rows.append(("Ziegler-Nichols tuning (exact + experiment)", tuning_time, tuning_time, "s",
                 "", ""))
    rows.append(("references from the sensor log (82 sensors -> 186 zones)", setup, setup, "s",
                 "", ""))
    rows.append(("peak memory of the process", memory, memory, "GB", "<= 1",
                 "pass" if memory <= 1 else "FAIL"))
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"Date: {stamp}. Machine: {platform.machine()}, 2 cores, 24 GiB; Python "
        f"{platform.python_version()}. {n_zones} zones, {n_steps} steps of 5 min, "
        f"{sim.network.n_nodes} nodes.",
        "",
        "| case | best | median | unit | target | pass |",
        "|---|---:|---:|---|---:|---|",
    ]
    for name, b, m, unit, target, ok in rows:
        lines.append(f"| {name} | {b:.3g} | {m:.3g} | {unit} | {target} | {ok} |")
    lines.append("")
    lines.append(
        f"Ratios in this run: PID / free run {pid_time[0] / free[0]:.2f}, inverse / PID "
        f"{inverse[0] / pid_time[0]:.2f}; the paper's EnergyPlus co-simulation: about 240 s "
        f"(PID here {240 / pid_time[0]:.0f}x faster)."
    )
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
