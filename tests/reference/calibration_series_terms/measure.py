"""The series meta-model affine in log p (published) against the same with a curvature term.

On the three twins (the clinic twin of ``tests/calibration/test_calibration_workflow.py``, the
EnergyPlus twins of 5ZoneAirCooled and of the multifamily prototype), one campaign each (the
twins' own scripts and sample counts, built by ``../calibration_discrepancy/measure.py``), then
the same samples analysed again with the building and the zone-group metric and
``metamodel: {kind: series, series_terms: affine | auto}``: nothing is sampled again, only the
new optima and posterior medians are confirmed with the model (``--resume``). Each analysis
gives the calibrated element values, the posterior's medians and 90 % intervals against the
hidden truth, and the out-of-fold hourly error of both forms.

Run: PYTHONPATH=src python tests/reference/calibration_series_terms/measure.py 5zone
multifamily clinic [--keep FOLDER]; writes ``<twin>.json`` and ``results.md`` beside this script.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import tempfile
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
REF = HERE.parent
TERMS = ("affine", "auto")


def _twin(name: str, folder: Path):
    """The twin's campaign file (``kind: series``) and its truth (element values)."""
    spec = importlib.util.spec_from_file_location(
        "measure_discrepancy", REF / "calibration_discrepancy" / "measure.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    if name == "clinic":
        return module._clinic(folder)
    if name == "5zone":
        return module._energyplus("calibration_energyplus_5zone", folder, 48)
    return module._energyplus("calibration_energyplus_multifamily", folder, 32)


def _rows(result, truth: dict) -> dict:
    """Calibrated value, posterior median and 90 % interval against the truth, per parameter."""
    from thermocal.calibration.workflow import candidate_parameters

    calibrated = candidate_parameters(result.calibrated_building, "element")
    post = result.posterior.summary
    rows = {}
    for n in post.index:
        t = float(truth[n])
        lo, hi = float(post.at[n, "q05"]), float(post.at[n, "q95"])
        rows[n] = {
            "nominal": float(post.at[n, "nominal"]),
            "calibrated": float(calibrated[n]),
            "median": float(post.at[n, "median"]),
            "q05": lo,
            "q95": hi,
            "truth": t,
            "error": float(calibrated[n]) / t - 1.0,
            "median_error": float(post.at[n, "median"]) / t - 1.0,
            "covers": lo <= t <= hi,
            "determined": bool(post.at[n, "determined"]),
        }
    return rows


def measure(twin: str, workers: int = 1, keep=None) -> dict:
    """One campaign of ``twin``, then each metric with each form of the series meta-model."""
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate

    out = {}
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = Path(keep) / twin if keep else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        path, truth = _twin(twin, folder)
        base = path.read_text()
        t0 = time.perf_counter()
        calibrate(
            load_campaign(path),
            workers=workers,
            store_path=folder / "s.sqlite",
            resume=True,
            progress=False,
            log=lambda s: None,
        )
        out["campaign_s"] = time.perf_counter() - t0
        for metric in ("building", "groups"):
            for terms in TERMS:
                other = folder / f"{metric}_{terms}.yaml"
                other.write_text(
                    base.replace("kind: series", f"kind: series, series_terms: {terms}")
                    + f"metric: {metric}\n"
                )
                t0 = time.perf_counter()
                result = calibrate(
                    load_campaign(other),
                    workers=workers,
                    store_path=folder / "s.sqlite",
                    resume=True,
                    progress=False,
                    log=lambda s: None,
                )
                confirmed = result.confirmed
                out[f"{metric}/{terms}"] = {
                    "rows": _rows(result, truth),
                    "series_metamodel": confirmed.get("series_metamodel"),
                    "calibrated_source": confirmed["calibrated"]["source"],
                    "calibrated_metric": float(confirmed["calibrated"]["confirmed"]),
                    "nominal_metric": float(result.nominal_metric),
                    "flags": [f.get("kind") for f in confirmed.get("flags", [])],
                    "runs": result.runs,
                    "seconds": time.perf_counter() - t0,
                }
    return out


def markdown(twin: str, res: dict) -> str:
    """The element table of one twin: each metric and form, each parameter."""
    lines = [
        f"\n## {twin} (campaign {res['campaign_s']:.0f} s)\n",
        "| metric / series terms | parameter | nominal | calibrated | median [90 % interval] "
        "| truth | calibrated / truth | covers | determined |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for key, r in res.items():
        if key == "campaign_s":
            continue
        used = (r["series_metamodel"] or {}).get("terms", "?")
        for n, row in r["rows"].items():
            lines.append(
                f"| {key} ({used}) | {n} | {row['nominal']:.4g} | {row['calibrated']:.4g} | "
                f"{row['median']:.4g} [{row['q05']:.4g}, {row['q95']:.4g}] | {row['truth']:.4g} "
                f"| {100 * row['error']:+.1f} % | {row['covers']} | {row['determined']} |"
            )
    lines.append("")
    for key, r in res.items():
        if key == "campaign_s":
            continue
        errors = (r["series_metamodel"] or {}).get("oof_hourly_rms_W")
        lines.append(
            f"- {key}: calibrated from the {r['calibrated_source']}, metric "
            f"{r['calibrated_metric']:.4g} W^2 (nominal {r['nominal_metric']:.4g}); flags "
            f"{r['flags'] or 'none'}; out-of-fold hourly error "
            + (
                f"{errors['affine']:.0f} W affine, {errors['quadratic']:.0f} W with curvature"
                if errors
                else "-"
            )
            + f"; {r['runs'].get('simulated', 0)} runs simulated; {r['seconds']:.0f} s"
        )
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("twins", nargs="+", choices=["clinic", "5zone", "multifamily"])
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--keep", type=Path, default=None, help="folder keeping the stores")
    args = parser.parse_args(argv)
    for twin in args.twins:
        res = measure(twin, args.workers, args.keep)
        (HERE / f"{twin}.json").write_text(json.dumps(res, indent=2, default=str) + "\n")
        text = markdown(twin, res)
        print(text, flush=True)
        with open(HERE / "results.md", "a") as fh:
            fh.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
