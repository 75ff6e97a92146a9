"""Identified heat vs EnergyPlus on the 5ZoneAirCooled twin, every option: writes results.json.

Run from the repository root (EnergyPlus 25.2 and ../shared/data needed, a few minutes)::

    python tests/reference/identification_5zone/measure.py

EnergyPlus runs ``5ZoneAirCooled_FF_v25.idf`` (free float, its People/Lights/ElectricEquipment
schedules) for January at 1-minute steps, sampled at 5 minutes
(``tests/identification/energyplus_twin.py``: EnergyPlus' own 5-minute result is not converged
in the plenum); its zone air temperatures are perfect sensors; thermocal gets the file without
the loads and identifies the heat with the exact inverse at 5 minutes. Hourly NMBE and CV(RMSE)
of the building's identified heat against the sensible gains EnergyPlus reports entering the
zones, after the first day, in all hours and in the method's unoccupied hours (20:00-04:00,
Saturday from 11:00, Sunday).
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

from energyplus_twin import ZONES, fidelity, make_twin, sensor_log  # noqa: E402

from thermocal.identification.workflow import identify  # noqa: E402

SHARED = ROOT.parent / "shared" / "data" / "energyplus_reference"

#: (label, feedback, radiant fraction); None = the default
FORMS = [
    ("paper: all into the air, air sensor", "air", 0.0),
    ("operative sensor, all into the air", "operative", 0.0),
    ("radiant fraction 0.5, air sensor", "air", 0.5),
    ("default: radiant fraction 0.6, air sensor", None, None),
    ("radiant fraction 0.6, operative sensor", "operative", None),
    ("radiant fraction 0.7, air sensor", "air", 0.7),
]
#: (label, sensed zones, mapping extras)
SENSING = [
    ("all 6 zones sensed", list(ZONES), {}),
    ("5 of 6 sensed, plenum floats (default)", [z for z in ZONES if z != "PLENUM-1"], {}),
    (
        "5 of 6 sensed, plenum by the neighbour rule",
        [z for z in ZONES if z != "PLENUM-1"],
        {"unsensed": "neighbour"},
    ),
]


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        twin = make_twin(SHARED, Path(tmp), days=31)
    rows = []
    for sensing, zones, extra in SENSING:
        log, mapping = sensor_log(twin, zones)
        mapping.update(extra)
        for label, feedback, fraction in FORMS:
            if extra and feedback is not None:
                continue  # the neighbour rule only with the default form
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = identify(
                    twin.building,
                    twin.weather,
                    twin.metadata,
                    log,
                    mapping,
                    start=twin.start,
                    end=twin.end,
                    method="inverse",
                    feedback=feedback,
                    radiant_fraction=fraction,
                )
            q = result.q_id
            truth = twin.gains.reindex(q.index)
            keep = q.index >= q.index[0] + pd.Timedelta("1D")
            unoccupied = result.unoccupied_mask()[keep]
            every = fidelity(q[keep], truth[keep])
            empty = fidelity(q[keep], truth[keep], unoccupied)
            per_zone = {zone: float((q[zone][keep] - truth[zone][keep]).mean()) for zone in ZONES}
            rows.append(
                {
                    "sensing": sensing,
                    "form": label,
                    "all_hours": every,
                    "unoccupied_hours": empty,
                    "zone_mean_error_W": per_zone,
                }
            )
            print(
                f"{sensing:45s} {label:45s} all {every['nmbe']:+.3f} / {every['cvrmse']:.3f}  "
                f"unoccupied {empty['nmbe']:+.3f} / {empty['cvrmse']:.3f}",
                flush=True,
            )
    gains = twin.gains[twin.gains.index >= twin.gains.index[0] + pd.Timedelta("1D")]
    out = {
        "description": __doc__.strip().splitlines()[0],
        "energyplus_gains_mean_W": float(gains.sum(axis=1).mean()),
        "rows": rows,
    }
    (HERE / "results.json").write_text(json.dumps(out, indent=2, default=float) + "\n")
    assert np.isfinite([r["all_hours"]["nmbe"] for r in rows]).all()


if __name__ == "__main__":
    main()
