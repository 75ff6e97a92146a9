"""Identified heat against EnergyPlus 25.2 on the DOE outpatient prototype (118 zones, a
building thermocal did not write): writes identification_results.json.

Run from the repository root (EnergyPlus 25.2 needed, about four minutes)::

    python tests/reference/identification_outpatient/measure_identification.py [DAYS] [LABEL]

EnergyPlus runs ``outpatient_FF_v25.idf`` (beside this script) free float with its loads from
January 1 for ``DAYS`` days (default 8) at 5-minute steps, Chicago O'Hare TMY3: the "real"
building. thermocal gets its zone temperatures as a sensor log (every zone, or 87 of 118 drawn
with seed 1 as in the method's case study; the unsensed zones float) and
identifies the heat by the exact inverse with the true envelope, once with the default form
(radiant fraction 0.6, the file's loads left out of the model) and once with the form the file
declares (``radiant_fraction="declared"``). Compared with the gains EnergyPlus puts into the
zones (first day left out): NMBE, CV(RMSE) and correlation over all hours and over the
method's unoccupied hours, for the building (the floating zones' gains included in the truth:
nobody identifies them) and for the sensed zones alone (their identified heat against their own
gains). With the declared form the floating zones keep the file's load objects. ``LABEL``
(default "after") names the entry in the JSON file.
"""

from __future__ import annotations

import json
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))

from energyplus_twin import make_twin_of, sensor_log, zone_fidelity  # noqa: E402

IDF = HERE / "outpatient_FF_v25.idf"
RESULTS = HERE / "identification_results.json"


def main() -> None:
    from thermocal.identification.workflow import identify
    from thermocal.multizone.idf import read_idf

    days = int(sys.argv[1]) if len(sys.argv) > 1 else 8
    label = sys.argv[2] if len(sys.argv) > 2 else "after"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        twin = make_twin_of(IDF.read_text(), folder, days, timesteps_per_hour=12)
        zones = list(twin.temperature.columns)
        rng = np.random.default_rng(1)
        sensed_sets = {
            "all": zones,
            "87 of 118": sorted(rng.choice(zones, size=87, replace=False).tolist()),
        }
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            loaded = read_idf(folder / "twin.idf")
        for sensed_label, sensed in sensed_sets.items():
            log, mapping = sensor_log(twin, sensed)
            for zone in sensed:  # the hot rooms' own plausible range (the MRI room reaches 95 C)
                mean = float(twin.temperature[zone].mean())
                if not 5.0 < mean < 30.0:
                    mapping.setdefault("zones", {})[zone] = {"plausible": [mean - 15, mean + 15]}
            for form, fraction, building in (
                ("default 0.6", None, twin.building),
                ("declared", "declared", loaded),
            ):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = identify(
                        building, twin.weather, twin.metadata, log, mapping,
                        start=twin.start + pd.Timedelta("5min"), end=twin.end, step="5min",
                        method="inverse", radiant_fraction=fraction,
                    )  # fmt: skip
                every, unoccupied = zone_fidelity(res, twin)
                own, own_quiet = zone_fidelity(res, twin, sensed)
                row = {
                    "sensed": sensed_label,
                    "form": form,
                    "nmbe_pct": round(100 * every["nmbe"], 1),
                    "cvrmse_pct": round(100 * every["cvrmse"], 1),
                    "r": round(every["r"], 3),
                    "unoccupied_nmbe_pct": round(100 * unoccupied["nmbe"], 1),
                    "unoccupied_cvrmse_pct": round(100 * unoccupied["cvrmse"], 1),
                    "sensed_zones_nmbe_pct": round(100 * own["nmbe"], 1),
                    "sensed_zones_cvrmse_pct": round(100 * own["cvrmse"], 1),
                    "sensed_zones_unoccupied_nmbe_pct": round(100 * own_quiet["nmbe"], 1),
                    "sensed_zones_unoccupied_cvrmse_pct": round(100 * own_quiet["cvrmse"], 1),
                }
                print(row, flush=True)
                rows.append(row)
    results = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    results[label] = {"days": days, "rows": rows}
    RESULTS.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
