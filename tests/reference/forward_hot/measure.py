"""The forward model against EnergyPlus 25.2 when the zones run hot: writes results.json.

Run from the repository root (EnergyPlus 25.2 and ../shared/data needed, about two minutes)::

    python tests/reference/forward_hot/measure.py [LABEL]

Both engines run the same free-floating IDF with every load object's design level multiplied by
a factor (``tests/identification/energyplus_twin.py::scaled_loads``; schedules unchanged), the
first 15 days of January, Chicago O'Hare TMY3: NREL's 5ZoneAirCooled at 5-minute steps (x 1, 4,
8, 14: zones up to about 73 C) and the PNNL/DOE multifamily prototype at 10-minute steps (x 1,
3, 6: up to about 48 C), plus two 5ZoneAirCooled variants at x 14 that isolate the People (their
``Fraction Radiant`` 0.3 -> 0, and no People at all). Hourly RMSE and bias [K] of each zone's air
temperature, first day left out. ``LABEL`` (default "after") names the entry written into
results.json, so a run on another commit can be kept beside it.
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
    IDF_NAME,
    _class,
    _join,
    _objects,
    forward_on_the_same_file,
    scaled_loads,
)

SHARED = ROOT.parent / "shared" / "data" / "energyplus_reference"
MULTIFAMILY = ROOT / "tests" / "reference" / "identification_multifamily"
DAYS = 15


def convective_people(text: str) -> str:
    """People objects with ``Fraction Radiant`` 0 (all their sensible heat into the air)."""
    out = []
    for obj in _objects(text):
        if _class(obj) == "people":
            fields = [f.strip() for f in obj.split(",")]
            fields[8] = "0"
            obj = ",\n  ".join(fields)
        out.append(obj)
    return _join(out)


def without_people(text: str) -> str:
    return _join([obj for obj in _objects(text) if _class(obj) != "people"])


def cases():
    office = (SHARED / IDF_NAME).read_text()
    flats = (MULTIFAMILY / "multifamily_5A_FF_v25.idf").read_text()
    for factor in (1, 4, 8, 14):
        yield "5ZoneAirCooled", f"loads x {factor}", scaled_loads(office, factor), 12
    yield (
        "5ZoneAirCooled",
        "loads x 14, People convective",
        convective_people(scaled_loads(office, 14)),
        12,
    )
    yield (
        "5ZoneAirCooled",
        "loads x 14 without People",
        without_people(scaled_loads(office, 14)),
        12,
    )
    for factor in (1, 3, 6):
        yield "multifamily", f"loads x {factor}", scaled_loads(flats, factor), 6


def forward(text: str, steps_per_hour: int, directory: Path) -> dict:
    """Both engines on ``text``: per-zone hourly RMSE / bias [K] and EnergyPlus' range [C]."""
    twin, table = forward_on_the_same_file(text, directory, DAYS, steps_per_hour)
    return {
        "energyplus_min_C": round(float(twin.temperature.min().min()), 2),
        "energyplus_max_C": round(float(twin.temperature.max().max()), 2),
        "mean_rmse_K": round(float(table["rmse"].mean()), 3),
        "mean_bias_K": round(float(table["bias"].mean()), 3),
        "worst_rmse_K": round(float(table["rmse"].max()), 3),
        "worst_zone": str(table["rmse"].idxmax()),
        "per_zone": {
            zone: {"rmse_K": round(float(r), 3), "bias_K": round(float(b), 3)}
            for zone, r, b in zip(table.index, table["rmse"], table["bias"], strict=True)
        },
    }


def main() -> None:
    label = sys.argv[1] if len(sys.argv) > 1 else "after"
    path = HERE / "results.json"
    results = json.loads(path.read_text()) if path.exists() else {}
    entry = {}
    with tempfile.TemporaryDirectory() as tmp:
        for i, (building, variant, text, steps) in enumerate(cases()):
            folder = Path(tmp) / str(i)
            folder.mkdir()
            found = forward(text, steps, folder)
            entry.setdefault(building, {})[variant] = found
            print(
                f"{building:15s} {variant:32s} EnergyPlus {found['energyplus_min_C']:6.1f}.."
                f"{found['energyplus_max_C']:5.1f} C  RMSE {found['mean_rmse_K']:.3f} K "
                f"(worst {found['worst_rmse_K']:.3f}, {found['worst_zone']})  "
                f"bias {found['mean_bias_K']:+.3f} K",
                flush=True,
            )
    results[label] = entry
    path.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
