"""Coverage of the posterior's 90 % intervals with and without the model-discrepancy term.

On the three twins (the clinic twin of ``tests/calibration/test_calibration_workflow.py``, the
EnergyPlus twins of 5ZoneAirCooled and of the multifamily prototype), one campaign each (the
twins' own scripts and sample counts), then the same samples re-analysed (nothing simulated)
with the building and the zone-group metric, each with ``posterior: {discrepancy: false}`` and
``true``. The posterior is the same whatever the meta-model kind (it always uses the series
model), so the analyses use ``kind: series`` to save time.

Run: PYTHONPATH=src python tests/reference/calibration_discrepancy/measure.py clinic 5zone
multifamily [--workers 2]; writes ``<twin>.json`` and appends to ``results.md`` beside this
script.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
REF = HERE.parent


def _clinic(folder: Path):
    sys.path.insert(0, str(REF.parent / "calibration"))
    from test_calibration_workflow import _campaign, _clinic

    from thermocal.calibration.workflow import candidate_parameters

    start = candidate_parameters(_clinic(), "element")
    wall, roof = "construction/Exterior wall/resistance", "construction/Roof/resistance"
    truth = {wall: 0.6 * start[wall], roof: 1.5 * start[roof]}
    parameters = """parameters:
  level: element
  include: ["construction/Exterior wall/*", "construction/Roof/resistance",
            "window/Exterior window/u_value", "infiltration/corridor 1/ach"]
  default_range: 0.6"""
    path = _campaign(folder, samples=48, truth=truth, parameters=parameters)
    path.write_text(path.read_text().replace("kind: auto", "kind: series"))
    return path, {**start, **truth}


def _energyplus(name: str, folder: Path, samples: int):
    import importlib.util

    # the twins' scripts share a module name: load each from its file (the multifamily one
    # imports the 5-zone one as ``calibrate_twin``)
    sys.path.insert(0, str(REF / "calibration_energyplus_5zone"))
    spec = importlib.util.spec_from_file_location(f"twin_{name}", REF / name / "calibrate_twin.py")
    ct = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ct)

    path = ct.prepare(folder, samples, extra="metamodel: {kind: series}\n")
    return path, json.loads((REF / name / "truth.json").read_text())["truth"]


def measure(twin: str, workers: int, modes=("none", "neighbours", "floor"), keep=None) -> dict:
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate, reanalyse

    out = {}
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = Path(keep) / twin if keep else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        stored = (folder / "s.sqlite").exists()
        if twin == "clinic":
            path, truth = _clinic(folder)
        elif twin == "5zone":
            path, truth = _energyplus("calibration_energyplus_5zone", folder, 48)
        else:
            path, truth = _energyplus("calibration_energyplus_multifamily", folder, 32)
        t0 = time.perf_counter()
        if not stored:
            calibrate(
                load_campaign(path),
                workers=workers,
                store_path=folder / "s.sqlite",
                progress=False,
                log=lambda s: None,
            )
        out["campaign_s"] = time.perf_counter() - t0
        base = path.read_text()
        for metric in ("building", "groups"):
            for discrepancy in modes:
                other = folder / f"{metric}_{discrepancy}.yaml"
                other.write_text(
                    base + f"metric: {metric}\nposterior: {{discrepancy: {discrepancy}}}\n"
                )
                result = reanalyse(load_campaign(other), folder / "s.sqlite", log=lambda s: None)
                post = result.posterior.summary
                rows = {}
                for n in post.index:
                    t = float(truth[n])
                    lo, hi = float(post.at[n, "q05"]), float(post.at[n, "q95"])
                    rows[n] = {
                        "median": float(post.at[n, "median"]),
                        "q05": lo,
                        "q95": hi,
                        "truth": t,
                        "covers": lo <= t <= hi,
                        "width_to_truth": (hi - lo) / t,
                        "width_fraction": float(post.at[n, "width_fraction"]),
                        "determined": bool(post.at[n, "determined"]),
                    }
                out[f"{metric}/{discrepancy}"] = {
                    "rows": rows,
                    "noise_std_W": float(result.posterior.noise_std),
                    "flags": result.confirmed.get("flags", []),
                    "floor": result.confirmed.get("model_error_floor"),
                    "calibrated_metric": float(result.confirmed["calibrated"]["confirmed"]),
                }
    return out


def markdown(twin: str, res: dict) -> str:
    lines = [
        f"\n## {twin} (campaign {res['campaign_s']:.0f} s)\n",
        "| metric / discrepancy | parameter | median [90 % interval] | truth | covers | "
        "width / truth | determined |",
        "|---|---|---|---|---|---|---|",
    ]
    for key, r in res.items():
        if key == "campaign_s":
            continue
        for n, row in r["rows"].items():
            lines.append(
                f"| {key} | {n} | {row['median']:.4g} [{row['q05']:.4g}, {row['q95']:.4g}] | "
                f"{row['truth']:.4g} | {row['covers']} | {100 * row['width_to_truth']:.1f} % | "
                f"{row['determined']} |"
            )
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("twins", nargs="+", choices=["clinic", "5zone", "multifamily"])
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--modes", nargs="+", default=["none", "neighbours", "floor"])
    parser.add_argument("--keep", type=Path, default=None, help="folder keeping the stores")
    args = parser.parse_args(argv)
    for twin in args.twins:
        res = measure(twin, args.workers, tuple(args.modes), args.keep)
        (HERE / f"{twin}.json").write_text(json.dumps(res, indent=2, default=str) + "\n")
        text = markdown(twin, res)
        print(text, flush=True)
        with open(HERE / "results.md", "a") as fh:
            fh.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
