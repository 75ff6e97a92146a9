"""The form of the identified heat declared by the file, step by step, against EnergyPlus 25.2 on
both twins: writes results.json.

Run from the repository root (EnergyPlus 25.2 and ../shared/data needed, about five minutes)::

    python tests/reference/identification_declared_form/measure.py

The twins of ``tests/identification/energyplus_twin.py`` for January: NREL's 5ZoneAirCooled
(EnergyPlus at 1-minute steps sampled at 5 minutes) and the PNNL/DOE multifamily prototype (10
minutes). thermocal gets the file without its load objects and EnergyPlus' zone air
temperatures as perfect sensors, and identifies the heat with the exact inverse in three forms:
the default (60 % radiant in every zone), each zone's declared mean over January, and the
declared form step by step (:func:`thermocal.multizone.idf.loads.declared_radiant_fraction` on
the file with its loads). Hourly NMBE / CV(RMSE) / r of the building's identified heat against
the sensible gains EnergyPlus reports entering the zones, first day left out, in all hours and
in the identification's unoccupied hours.
"""

from __future__ import annotations

import json
import sys
import tempfile
import warnings
from pathlib import Path

import pandas as pd

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))

from energyplus_twin import IDF_NAME, fidelity, make_twin, make_twin_of, sensor_log  # noqa: E402

from thermocal.identification.workflow import identify  # noqa: E402
from thermocal.multizone.idf import read_idf  # noqa: E402
from thermocal.multizone.idf.loads import declared_radiant_fraction  # noqa: E402

SHARED = ROOT.parent / "shared" / "data" / "energyplus_reference"
MULTIFAMILY = (
    ROOT / "tests" / "reference" / "identification_multifamily" / "multifamily_5A_FF_v25.idf"
)
FLATS_UNSENSED = (
    "attic",
    "Breezeway",
    "living_unit3_BackRow_BottomFloor",
    "living_unit2_FrontRow_MiddleFloor",
    "living_unit1_BackRow_TopFloor",
)
DAYS = 31


def _rounded(metrics: dict) -> dict:
    return {k: round(float(v), 4) for k, v in metrics.items() if k in ("nmbe", "cvrmse", "r")}


def measure(twin, source: Path, steps_per_hour: int, sensing: dict) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        declared_file = read_idf(source)
    zones = list(twin.temperature.columns)
    step = pd.Timedelta(minutes=60 // steps_per_hour)
    times = pd.date_range(twin.start, twin.end, freq=step, inclusive="left")
    per_step = pd.DataFrame(
        declared_radiant_fraction(declared_file.idf_info, zones, times, step, fallback=0.6),
        index=times,
        columns=zones,
    )
    forms = {
        "default: 0.6": None,
        "declared, January mean per zone": per_step.mean().to_dict(),
        "declared, step by step": per_step,
    }
    out = {
        "declared_fraction": {
            "min": round(float(per_step.min().min()), 3),
            "max": round(float(per_step.max().max()), 3),
            "distinct_rows": int(len(per_step.drop_duplicates())),
        }
    }
    for sensing_label, sensed in sensing.items():
        log, mapping = sensor_log(twin, sensed)
        for label, form in forms.items():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = identify(
                    twin.building,
                    twin.weather,
                    twin.metadata,
                    log,
                    mapping,
                    start=twin.start + step,
                    end=twin.end,
                    step=step,
                    method="inverse",
                    radiant_fraction=form,
                )
            q = result.q_id
            truth = twin.gains.reindex(q.index)
            keep = q.index >= q.index[0] + pd.Timedelta("1D")
            unoccupied = result.unoccupied_mask()[keep]
            row = {
                "all_hours": _rounded(fidelity(q[keep], truth[keep])),
                "unoccupied_hours": _rounded(fidelity(q[keep], truth[keep], unoccupied)),
            }
            out.setdefault(sensing_label, {})[label] = row
            print(
                f"{source.name[:24]:24s} {sensing_label:28s} {label:32s} "
                f"all {row['all_hours']['nmbe']:+.3f} / {row['all_hours']['cvrmse']:.3f}  "
                f"unoccupied {row['unoccupied_hours']['nmbe']:+.3f} / "
                f"{row['unoccupied_hours']['cvrmse']:.3f}",
                flush=True,
            )
    return out


def main() -> None:
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        office = make_twin(SHARED, Path(tmp), DAYS)
        zones = list(office.temperature.columns)
        results["5ZoneAirCooled"] = measure(
            office,
            SHARED / IDF_NAME,
            12,
            {
                "all 6 sensed": zones,
                "5 of 6, plenum floats": [z for z in zones if z != "PLENUM-1"],
            },
        )
    with tempfile.TemporaryDirectory() as tmp:
        flats = make_twin_of(MULTIFAMILY.read_text(), Path(tmp), DAYS, timesteps_per_hour=6)
        zones = list(flats.temperature.columns)
        results["multifamily"] = measure(
            flats,
            MULTIFAMILY,
            6,
            {
                "all 20 sensed": zones,
                "15 of 20 sensed": [z for z in zones if z not in FLATS_UNSENSED],
            },
        )
    (HERE / "results.json").write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
