"""Forward and identification fidelity against EnergyPlus 25.2 on the PNNL/DOE multifamily
prototype (20 zones; a building thermocal did not write): writes results.json.

Run from the repository root (EnergyPlus 25.2 needed, a few minutes on 2 cores)::

    python tests/reference/identification_multifamily/measure.py [DAYS]

The file is ``multifamily_5A_FF_v25.idf`` beside this script (``convert.py`` made it from the
COBS repository's EnergyPlus 8.6 file; README.md). EnergyPlus and thermocal run January
(``DAYS`` = 31) at 10-minute steps, free float, Chicago O'Hare TMY3
(``tests/identification/energyplus_twin.py``); the first day is left out of every metric.

* Forward: the same IDF in both engines, three load variants (the file's loads, none, loads x
  0.3): hourly RMSE and bias of each zone's air temperature.
* Identification: EnergyPlus runs the file with its loads; thermocal gets the file without the
  load objects (the true envelope) and EnergyPlus' zone air temperatures as perfect sensors,
  and identifies the heat with the exact inverse in its default form; hourly NMBE and
  CV(RMSE) of the identified heat against the sensible gains EnergyPlus reports entering the
  zones (building and per zone), in all hours and in the identification's unoccupied hours,
  with every zone sensed and with 15 of 20 (75 %) sensed, the others floating.
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))

from energyplus_twin import (  # noqa: E402
    fidelity,
    forward_on_the_same_file,
    hourly_rmse_bias,
    make_twin_of,
    scaled_loads,
    sensor_log,
    without_loads,
)

from thermocal.identification.workflow import identify  # noqa: E402

IDF = HERE / "multifamily_5A_FF_v25.idf"
STEPS_PER_HOUR = 6
#: the zones left without a sensor in the 75 % case (they float): the attic, the breezeway and
#: three flats, one per floor
UNSENSED = (
    "attic",
    "Breezeway",
    "living_unit3_BackRow_BottomFloor",
    "living_unit2_FrontRow_MiddleFloor",
    "living_unit1_BackRow_TopFloor",
)
VARIANTS = {
    "with loads": lambda text: text,
    "without loads": without_loads,
    "loads x 0.3": lambda text: scaled_loads(text, 0.3),
}


def forward(text: str, directory: Path, days: int) -> tuple[pd.DataFrame, dict]:
    """EnergyPlus and thermocal on the same file: per-zone hourly RMSE and bias [K]."""
    started = time.perf_counter()
    twin, table = forward_on_the_same_file(text, directory, days, STEPS_PER_HOUR)
    ranges = {
        "energyplus_min_C": float(twin.temperature.min().min()),
        "energyplus_max_C": float(twin.temperature.max().max()),
        "seconds_both_engines": time.perf_counter() - started,
    }
    return table, ranges


def identification(twin, zones, extra=None) -> dict:
    """Identified heat against EnergyPlus' gains with ``zones`` sensed (the others float, or
    as ``extra`` of the mapping says)."""
    log, mapping = sensor_log(twin, zones)
    mapping.update(extra or {})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = identify(
            twin.building,
            twin.weather,
            twin.metadata,
            log,
            mapping,
            # the sensors report each step's end: the first full step starts one step in
            start=twin.start + (twin.temperature.index[1] - twin.temperature.index[0]),
            end=twin.end,
            step=f"{60 // STEPS_PER_HOUR}min",
            method="inverse",
        )
    q = result.q_id
    truth = twin.gains.reindex(q.index)
    keep = q.index >= q.index[0] + pd.Timedelta("1D")
    unoccupied = result.unoccupied_mask()[keep]
    per_zone = {}
    for zone in q.columns:
        one_q, one_t = q[[zone]][keep], truth[[zone]][keep]
        row = {"mean_error_W": float((one_q - one_t).mean().iloc[0])}
        if float(one_t.mean().iloc[0]) > 1.0:
            row["all_hours"] = fidelity(one_q, one_t)
            row["unoccupied_hours"] = fidelity(one_q, one_t, unoccupied)
        per_zone[zone] = row
    floating = {}
    for zone in result.floating_temperature.columns:
        sim = result.floating_temperature[[zone]]
        floating[zone] = hourly_rmse_bias(sim, twin.temperature[[zone]]).iloc[0].to_dict()
    sensed = list(zones)
    return {
        "sensed": len(zones),
        "all_hours": fidelity(q[keep], truth[keep]),
        "unoccupied_hours": fidelity(q[keep], truth[keep], unoccupied),
        # against the gains of the sensed zones only (what the sensors can see)
        "sensed_zones_all_hours": fidelity(q[sensed][keep], truth[sensed][keep]),
        "sensed_zones_unoccupied_hours": fidelity(q[sensed][keep], truth[sensed][keep], unoccupied),
        "per_zone": per_zone,
        "floating_zones_K": floating,
    }


def main() -> None:
    days = int(sys.argv[1]) if len(sys.argv) > 1 else 31
    text = IDF.read_text()
    out = {
        "description": __doc__.strip().splitlines()[0],
        "days": days,
        "steps_per_hour": STEPS_PER_HOUR,
        "forward": {},
        "identification": {},
    }
    with tempfile.TemporaryDirectory() as tmp:
        for label, make in VARIANTS.items():
            folder = Path(tmp) / label.replace(" ", "_")
            folder.mkdir()
            table, ranges = forward(make(text), folder, days)
            out["forward"][label] = {
                "mean_rmse_K": float(table["rmse"].mean()),
                "mean_bias_K": float(table["bias"].mean()),
                "worst_rmse_K": float(table["rmse"].max()),
                "worst_zone": str(table["rmse"].idxmax()),
                **ranges,
                "per_zone": table.round(4).to_dict(orient="index"),
            }
            f = out["forward"][label]
            print(
                f"forward {label:14s} RMSE {f['mean_rmse_K']:.3f} K (worst {f['worst_rmse_K']:.3f}"
                f" {f['worst_zone']}), bias {f['mean_bias_K']:+.3f} K, EnergyPlus "
                f"{f['energyplus_min_C']:.1f}..{f['energyplus_max_C']:.1f} C",
                flush=True,
            )
        folder = Path(tmp) / "identification"
        folder.mkdir()
        twin = make_twin_of(text, folder, days, timesteps_per_hour=STEPS_PER_HOUR)
    zones = list(twin.temperature.columns)
    gains = twin.gains[twin.gains.index >= twin.gains.index[0] + pd.Timedelta("1D")]
    out["energyplus_gains_mean_W"] = float(gains.sum(axis=1).mean())
    partial = [z for z in zones if z not in UNSENSED]
    for label, sensed, extra in (
        ("all 20 zones sensed", zones, None),
        ("15 of 20 sensed, 5 float (default)", partial, None),
        ("15 of 20 sensed, neighbour rule", partial, {"unsensed": "neighbour"}),
    ):
        row = identification(twin, sensed, extra)
        out["identification"][label] = row
        a, u = row["all_hours"], row["unoccupied_hours"]
        print(
            f"identify {label:36s} all {a['nmbe']:+.3f} / {a['cvrmse']:.3f}  unoccupied "
            f"{u['nmbe']:+.3f} / {u['cvrmse']:.3f}  sensed zones' gains "
            f"{row['sensed_zones_all_hours']['nmbe']:+.3f} / "
            f"{row['sensed_zones_all_hours']['cvrmse']:.3f}",
            flush=True,
        )
    (HERE / "results.json").write_text(json.dumps(out, indent=1, default=float) + "\n")
    assert np.isfinite(out["forward"]["with loads"]["mean_rmse_K"])


if __name__ == "__main__":
    main()
