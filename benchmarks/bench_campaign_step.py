"""The clinic demo's calibration campaign at the sensor log's step and at a coarser one
(issue 22 item 4; ``thermocal.calibration.stepcheck``).

Runs ``thermocal calibrate`` on the demo's campaign file with ``step`` 5 minutes (the log's) and
the coarser ``--step`` (default 15 minutes), in turn (A B A B ... for ``--rounds``), each into a
fresh folder, ``--samples`` Sobol samples on ``--workers`` local workers, and reports per step:
the campaign's wall time (``timings_s.campaign`` of calibration.json) and its ratio in the same
round, the step check's largest response difference, and the posterior of the critical
parameters (median and 90 % interval) side by side.

Run::

    python benchmarks/bench_campaign_step.py [--samples 500] [--step 15min] [--rounds 1]
        [--workers 2] [--write results.md]
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
from pathlib import Path


def _campaign_file(folder: Path, step: str) -> Path:
    """The demo's campaign file with ``step`` (written by ``calibrate --demo`` itself)."""
    from thermocal.commands.calibrate import DEMO_CAMPAIGN

    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "demo_campaign.yaml"
    text = DEMO_CAMPAIGN.replace("\nstep: 5min\n", f"\nstep: {step}\n")
    if f"step: {step}" not in text:
        raise SystemExit("the demo campaign's step line was not found")
    path.write_text(text)
    return path


def run(step: str, folder: Path, samples: int, workers: int) -> dict:
    """One ``thermocal calibrate`` of the demo campaign at ``step``; its calibration.json."""
    campaign = _campaign_file(folder, step)
    done = subprocess.run(
        [sys.executable, "-m", "thermocal", "calibrate", str(campaign), "--out", str(folder),
         "--samples", str(samples), "--workers", str(workers)],
        capture_output=True, text=True,
    )  # fmt: skip
    if done.returncode != 0:
        raise SystemExit(f"calibrate at {step} failed:\n{done.stderr[-3000:]}")
    return json.loads((folder / "calibration.json").read_text())


def _step_note(result: dict) -> str:
    for note in result.get("notes", []):
        if note.startswith("Campaign step"):
            return note
    return "-"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--samples", type=int, default=500)
    parser.add_argument("--step", default="15min")
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--write", type=Path)
    args = parser.parse_args(argv)
    start = datetime.datetime.now(datetime.UTC)
    rows, results = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.rounds):
            times = {}
            for step in ("5min", args.step):
                result = run(step, Path(tmp) / f"{step}_{k}", args.samples, args.workers)
                times[step] = result["timings_s"]["campaign"]
                results[step] = result
                print(f"round {k + 1}: {step}: campaign {times[step]:.1f} s", flush=True)
            rows.append(times)
    load = os.getloadavg()
    lines = [
        f"Run {start:%Y-%m-%d %H:%M} UTC, {platform.machine()}, {os.cpu_count()} cores, load "
        f"average at the end {load[0]:.1f}; `python benchmarks/bench_campaign_step.py "
        f"--samples {args.samples} --step {args.step} --rounds {args.rounds} --workers "
        f"{args.workers}`",
        "",
        f"| round | campaign at 5 min [s] | at {args.step} [s] | ratio |",
        "|---|---:|---:|---:|",
    ]
    for k, times in enumerate(rows):
        ratio = times["5min"] / times[args.step]
        lines.append(
            f"| {k + 1} | {times['5min']:.1f} | {times[args.step]:.1f} | {ratio:.2f} |"
        )
    lines += ["", f"Step check at {args.step}: {_step_note(results[args.step])}", ""]
    lines += [f"| parameter | 5 min | {args.step} |", "|---|---|---|"]
    fine = results["5min"]["posterior"]["parameters"]
    coarse = results[args.step]["posterior"]["parameters"]
    for name, p in fine.items():
        q = coarse.get(name)
        if q is None:
            continue

        def cell(x):
            return f"{x['median']:.4g} [{x['q05']:.4g}, {x['q95']:.4g}]" + (
                " (determined)" if x.get("determined") else ""
            )

        lines.append(f"| {name} | {cell(p)} | {cell(q)} |")
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
