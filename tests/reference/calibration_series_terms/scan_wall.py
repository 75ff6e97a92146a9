"""The multifamily twin's metric with the detailed model along one parameter, the others at
their truth (no meta-model): where the model's own minimum is.

Run after ``measure.py multifamily --keep FOLDER`` (its campaign files)::

    PYTHONPATH=src python tests/reference/calibration_series_terms/scan_wall.py \
        FOLDER/multifamily groups "construction/Exterior Wall/resistance" 0.8,0.85,0.9,0.95,1.0

Prints the parameter's ratio to the truth and the metric [W^2] per line (2026-11-28, groups:
0.80 2.970e5, 0.85 2.952e5, 0.90 3.003e5, 0.95 3.101e5, 1.00 3.231e5, 1.05 3.380e5).
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
TRUTH = HERE.parent / "calibration_energyplus_multifamily" / "truth.json"
NAMES = (
    "construction/Exterior Wall/resistance",
    "construction/Interior Ceiling/resistance",
    "construction/Interior Ceiling (reversed)/resistance",
    "zone/attic/infiltration_ach",
)


def main(argv=None) -> int:
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.spatial import campaign_evaluator
    from thermocal.calibration.workflow import (
        build_problem,
        choose_quiet_hours,
        load_inputs,
        metric_value,
    )

    folder, metric, name, ratios = (argv or sys.argv[1:])[:4]
    warnings.simplefilter("ignore")
    truth = json.loads(TRUTH.read_text())["truth"]
    campaign = load_campaign(Path(folder) / f"{metric}_auto.yaml")
    inputs = load_inputs(campaign)
    problem, _ = build_problem(campaign, inputs)
    problem.series_outputs = True
    evaluator = campaign_evaluator(problem, inputs.building)
    nominal = problem.run({})
    problem.schedule, _ = choose_quiet_hours(campaign, nominal.heat.sum(axis=1), log=lambda s: 0)
    base = {n: truth[n] for n in NAMES}
    for q in (float(v) for v in ratios.split(",")):
        values = {**base, name: truth[name] * q}
        outputs = evaluator.outputs(problem.run(values).heat)
        print(f"{name} {q:.3f} {metric_value(outputs, metric):.4e}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
