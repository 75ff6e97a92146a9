"""Calibrate on one half of January, validate on the other (the method's open question).

The 5ZoneAirCooled twin (committed sensor log): the campaign of ``calibrate_twin.py`` with the
zone-group metric on January 4-17, and ``validation: {start: 2023-01-18, end: 2023-02-01}``:
the nominal and the calibrated building identified on the second half, which the calibration
did not see, their metrics compared (and the true envelope's on that half, for reference).

Run: PYTHONPATH=src python tests/reference/calibration_energyplus_5zone/validate_halves.py
[--samples 48]; prints and writes ``validate_halves.md`` beside this script.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import calibrate_twin as ct  # noqa: E402

FIRST = ("2023-01-04", "2023-01-18")
SECOND = ("2023-01-18", "2023-02-01")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=48)
    args = parser.parse_args(argv)
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate

    truth = json.loads((HERE / "truth.json").read_text())
    lines = []
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = Path(tmp)
        extra = f"metric: groups\nvalidation: {{start: {SECOND[0]}, end: {SECOND[1]}}}\n"
        path = ct.prepare(folder, args.samples, period=FIRST, extra=extra)
        campaign = load_campaign(path)
        result = calibrate(
            campaign, workers=1, store_path=folder / "s.sqlite", progress=False, log=print
        )
        summary = ct.summarise(result, campaign, truth, "groups")
        # the true envelope's metric on the second half (the same campaign on that period)
        later = folder / "later.yaml"
        later.write_text(ct.campaign_text(args.samples, period=SECOND, extra="metric: groups\n"))
        varied = {n: truth["truth"][n] for n in result.space.names}
        true_later = ct.true_metric(load_campaign(later), varied, "groups")
        v = result.validation
        lines += [
            "# Calibrate on January 4-17, validate on January 18-31 (5ZoneAirCooled twin)\n",
            f"{args.samples} samples, zone-group metric [W^2].\n",
            "| period | nominal | calibrated | true envelope | calibrated / nominal "
            "| calibrated / true |",
            "|---|---|---|---|---|---|",
            f"| calibration (Jan 4-17) | {summary['nominal_metric']:.4g} | "
            f"{summary['calibrated_metric']:.4g} | {summary['true_metric']:.4g} | "
            f"{summary['calibrated_metric'] / summary['nominal_metric']:.3f} | "
            f"{summary['calibrated_metric'] / summary['true_metric']:.3f} |",
            f"| validation (Jan 18-31) | {v['nominal']:.4g} | {v['calibrated']:.4g} | "
            f"{true_later:.4g} | {v['ratio']:.3f} | {v['calibrated'] / true_later:.3f} |",
            "",
            "| element | nominal | calibrated | posterior median [90 % interval] | truth |",
            "|---|---|---|---|---|",
        ]
        for row in summary["rows"]:
            interval = (
                f"{row['median']:.3f} [{row['q05']:.3f}, {row['q95']:.3f}]"
                if "median" in row
                else "-"
            )
            lines.append(
                f"| {row['parameter']} | {row['nominal']:.3f} | {row['calibrated']:.3f} | "
                f"{interval} | {row['truth']:.3f} |"
            )
        lines.append(
            f"\nbuilding total on the validation half: nominal {v['building_nominal']:.4g}, "
            f"calibrated {v['building_calibrated']:.4g} W^2; flags: "
            + ("; ".join(f["kind"] for f in summary["flags"]) or "none")
        )
    text = "\n".join(lines) + "\n"
    print(text)
    (HERE / "validate_halves.md").write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
