"""Re-analysis of a stored campaign on the clinic demo, without simulating (issue 26, item 8).

Target: a re-analysis of a stored campaign (another metric, meta-model, reduction or posterior)
<= 30 s. The script runs the demo campaign (``thermocal calibrate --demo``'s campaign file,
``--samples`` Sobol samples of its 70 parameters, 2 workers) into a store once, then times
``reanalyse`` on it: with nothing changed (must reproduce the results), with the zone-group
metric, with the SVR and with ``top_k: 5``. Each re-analysis must simulate nothing (counted).
The peer of the same run: one identification of the month (the campaign's nominal run; 1.35 s
on the idle machine, 2026-11-23), whose ratio gives an idle-equivalent of each wall time; the
process's CPU time (all its threads; a re-analysis runs in this process only) is the second,
load-independent measure: on an idle machine the wall time is at most about this. Posterior
and identifiability (series meta-model, emulator errors, MCMC, Fisher information, verdicts)
are timed on their own (``timings["posterior"]`` of each analysis; target <= 30 s).

Run: python benchmarks/bench_calibration_reanalyse.py [--samples 64] [--store DIR] [--write F]
(``--store DIR`` re-uses DIR/campaign.sqlite from an earlier run of this script).
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import tempfile
import time
import warnings
from pathlib import Path

#: One identification of the clinic demo's month on the idle machine (2026-11-23) [s].
IDLE_PEER = 1.35


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=64)
    parser.add_argument("--store", type=Path)
    parser.add_argument("--write", type=Path)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate, reanalyse
    from thermocal.commands.calibrate import DEMO_CAMPAIGN
    from thermocal.identification.problem import IdentificationProblem

    calls = []
    original_run = IdentificationProblem.run

    def counted(self, parameters=None):
        calls.append(1)
        return original_run(self, parameters)

    IdentificationProblem.run = counted
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.store or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / "demo_campaign.yaml"
        if not path.exists():
            path.write_text(DEMO_CAMPAIGN)
        store = folder / "campaign.sqlite"
        rows = []
        fresh = not store.exists()
        t0, c0 = time.perf_counter(), time.process_time()
        base = calibrate(
            load_campaign(path),
            samples=args.samples,
            workers=2,
            resume=not fresh,
            store_path=store,
            progress=False,
            log=lambda line: None,
        )
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        peer = base.timings["nominal_run"]
        what = "campaign" if fresh else "calibrate --resume of the stored campaign"
        rows.append(
            (
                f"{what}, {args.samples} samples + analysis (context)",
                wall,
                cpu,
                base.timings.get("posterior", float("nan")),
                len(calls),
                f"{base.summary.evaluated} samples evaluated",
            )
        )
        variants = {
            "nothing changed": "",
            "metric: groups": "metric: groups\n",
            "meta-model SVR": None,
            "top_k: 5": None,
        }
        text = path.read_text()
        for label, extra in variants.items():
            if label == "meta-model SVR":
                changed = text.replace("kind: auto", "kind: svr")
            elif label == "top_k: 5":
                changed = text.replace("top_k: 10", "top_k: 5")
            else:
                changed = text + extra
            other = folder / "variant.yaml"
            other.write_text(changed)
            before = len(calls)
            t0, c0 = time.perf_counter(), time.process_time()
            result = reanalyse(load_campaign(other), store, log=lambda line: None)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            same = ""
            if label == "nothing changed" and base is not None:
                differences = _differences(result, base)
                same = (
                    "same results"
                    if not differences
                    else "DIFFERENT: " + ", ".join(differences[:5])
                )
            posterior = result.timings.get("posterior", float("nan"))
            rows.append((f"re-analysis, {label}", wall, cpu, posterior, len(calls) - before, same))
    lines = [
        f"Date: {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC. Machine: "
        f"{platform.machine()}, 2 cores shared with other agents; Python "
        f"{platform.python_version()}. Script: `benchmarks/bench_calibration_reanalyse.py "
        f"--samples {args.samples}`. Peer (one identification of the clinic month, same run): "
        + f"{peer:.2f} s against {IDLE_PEER:.2f} s idle (ratio {peer / IDLE_PEER:.1f}); load "
        + f"average at the end {os.getloadavg()[0]:.1f}.",
        "",
        "| case | wall [s] | idle-equivalent [s] | CPU [s] | of which posterior + "
        "identifiability, wall [s] | model runs | target | pass (CPU and idle-eq.) | note |",
        "|---|---:|---:|---:|---:|---:|---:|---|---|",
    ]
    ratio = max(peer / IDLE_PEER, 1.0)
    for label, wall, cpu, posterior, runs, note in rows:
        target = "<= 30" if label.startswith("re-analysis") else ""
        ok = ""
        if target:
            ok = "pass" if max(cpu, wall / ratio) <= 30 and runs == 0 else "FAIL"
        lines.append(
            f"| {label} | {wall:.1f} | {wall / ratio:.1f} | {cpu:.1f} | {posterior:.1f} | {runs} "
            f"| {target} | {ok} | {note} |"
        )
    text = "\n".join(lines) + "\n"
    print(text)
    if args.write:
        args.write.write_text(text)
    return 0


def _differences(a, b) -> list[str]:
    """Paths where two results' calibration.json differ (timings and run counts aside)."""
    import json

    x, y = (json.loads(json.dumps(r.as_dict())) for r in (a, b))
    for d in (x, y):
        d.pop("campaign")  # the variant's file name
        d.pop("timings_s")
        d.pop("model_runs")
        d["samples"].pop("wall_time_s")
        d["samples"].pop("backend")
    out: list[str] = []

    def walk(path, u, v):
        if isinstance(u, dict) and isinstance(v, dict):
            for k in sorted(set(u) | set(v), key=str):
                walk(f"{path}.{k}", u.get(k), v.get(k))
        elif isinstance(u, list) and isinstance(v, list) and len(u) == len(v):
            for i, (p, q) in enumerate(zip(u, v, strict=True)):
                walk(f"{path}[{i}]", p, q)
        elif u != v and not (u != u and v != v):  # NaN equals NaN here
            out.append(path)

    walk("", x, y)
    return out


if __name__ == "__main__":
    raise SystemExit(main())
