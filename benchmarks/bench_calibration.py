"""Campaign time of the envelope calibration on the clinic (thermocal.calibration, issue 9).

Target: a 500-sample campaign on the ~180-zone clinic, one month at 5-minute steps, on a 2-core
machine <= 6 minutes (the paper: 8 hours on a 16-core workstation); meta-model + sensitivity +
optimisation <= 30 s (``bench_calibration_core.py``). Records how the campaign time scales with
workers (1, 2) and with a Dask LocalCluster of 2 workers.

Run: python benchmarks/bench_calibration.py [--samples 16] [--write results.md]
Each configuration runs the same ``--samples`` Sobol samples of the demo campaign's 70
parameters into a fresh store; the 500-sample time is extrapolated from the per-sample wall time
(``--samples 500`` runs the full campaign).
"""

from __future__ import annotations

import argparse
import datetime
import platform
import tempfile
import time
import warnings
from pathlib import Path

import pandas as pd


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--write", type=Path)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    from distributed import LocalCluster

    from thermocal.calibration.runner import run_campaign
    from thermocal.calibration.sampling import sample
    from thermocal.calibration.space import ParameterSpace
    from thermocal.calibration.store import CampaignStore
    from thermocal.demos.identification import load_demo
    from thermocal.identification.problem import problem_from_measurements

    building, weather, meta, raw, mapping, _ = load_demo()
    start, end = meta["period"]
    problem, _ = problem_from_measurements(
        building, weather, meta["weather"], raw, mapping, start=start, end=end
    )
    space = ParameterSpace.from_parameters(
        building.parameters(), include=["material/*", "window/*", "infiltration/*"],
        default_range=0.5,
    )
    values = sample(space, args.samples, "sobol", seed=1).values
    problem.evaluate({})  # compile and build once in this process
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for label, kwargs in (
            ("local, 1 worker (in-process)", {"workers": 1}),
            ("local process pool, 2 workers", {"workers": 2}),
            ("Dask LocalCluster, 2 workers", {"scheduler": "local"}),
        ):
            store = CampaignStore.open(Path(folder) / f"{len(rows)}.sqlite",
                                       definition={"label": label})
            t0 = time.perf_counter()
            if kwargs.get("scheduler") == "local":
                with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
                    t0 = time.perf_counter()
                    run_campaign(problem, values, store, scheduler=cluster, progress=False)
            else:
                run_campaign(problem, values, store, progress=False, **kwargs)
            wall = time.perf_counter() - t0
            frame = store.to_frame()
            ok = int(frame["error"].isna().sum())
            store.close()
            # steady state: the spacing of finish times once every worker is running (the
            # first result of each worker includes building its model)
            finished = pd.to_datetime(frame["finished_at"]).sort_values()
            n_workers = max(1, frame["worker"].nunique())
            span = (finished.iloc[-1] - finished.iloc[n_workers - 1]).total_seconds()
            per = span / max(1, len(finished) - n_workers)
            startup = wall - per * len(finished)
            full = (max(startup, 0.0) + 500 * per) / 60
            rows.append((label, args.samples, ok, wall, per, max(startup, 0.0), full))
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"Date: {stamp}. Machine: {platform.machine()}, 2 cores, 24 GiB; Python "
        f"{platform.python_version()}. Clinic demo: 186 zones, 8,928 steps of 5 min, exact "
        "inverse, 70 parameters (+-50 %).",
        "",
        "| configuration | samples | ok | wall [s] | steady wall per sample [s] | start-up [s] "
        "| 500 samples [min] | target | pass |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for label, n, ok, wall, per, startup, full in rows:
        target = "<= 6" if "2 workers" in label else ""
        verdict = ("pass" if full <= 6 else "FAIL") if target else ""
        lines.append(
            f"| {label} | {n} | {ok} | {wall:.1f} | {per:.2f} | {startup:.1f} | {full:.1f} | "
            f"{target} | {verdict} |"
        )
    lines.append("")
    lines.append(
        "500-sample time = start-up + 500 x the steady wall time per sample (finish-time "
        "spacing once every worker runs); the machine is shared, see the date."
    )
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
