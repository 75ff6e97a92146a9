"""Forward fidelity against EnergyPlus 25.2 on the DOE outpatient prototype (118 zones, a
building thermocal did not write): writes results.json.

Run from the repository root (EnergyPlus 25.2 needed, about two minutes)::

    python tests/reference/identification_outpatient/measure.py [DAYS] [LABEL]

Both engines run ``outpatient_FF_v25.idf`` (beside this script) free float from January 1 for
``DAYS`` days (default 8) at 5-minute steps, Chicago O'Hare TMY3, in three load variants (the
file's, none, x 0.3); hourly RMSE and bias of each zone's air temperature, first day left out.
``LABEL`` (default "after") names the entry in results.json.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))

from energyplus_twin import (  # noqa: E402
    forward_on_the_same_file,
    scaled_loads,
    without_loads,
)

IDF = HERE / "outpatient_FF_v25.idf"


def main() -> None:
    days = int(sys.argv[1]) if len(sys.argv) > 1 else 8
    label = sys.argv[2] if len(sys.argv) > 2 else "after"
    text = IDF.read_text()
    variants = {
        "with loads": text,
        "without loads": without_loads(text),
        "loads x 0.3": scaled_loads(text, 0.3),
    }
    entry = {"days": days}
    with tempfile.TemporaryDirectory() as tmp:
        for i, (name, variant) in enumerate(variants.items()):
            folder = Path(tmp) / str(i)
            folder.mkdir()
            twin, table = forward_on_the_same_file(variant, folder, days, 12)
            entry[name] = {
                "energyplus_min_C": round(float(twin.temperature.min().min()), 2),
                "energyplus_max_C": round(float(twin.temperature.max().max()), 2),
                "mean_rmse_K": round(float(table["rmse"].mean()), 3),
                "mean_bias_K": round(float(table["bias"].mean()), 3),
                "worst_rmse_K": round(float(table["rmse"].max()), 3),
                "worst_zone": str(table["rmse"].idxmax()),
                "zones_over_1K": int((table["rmse"] > 1.0).sum()),
            }
            print(name, entry[name], flush=True)
    path = HERE / "results.json"
    results = json.loads(path.read_text()) if path.exists() else {}
    results[label] = entry
    path.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
