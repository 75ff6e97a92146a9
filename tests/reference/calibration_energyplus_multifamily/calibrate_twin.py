"""``thermocal calibrate`` on the EnergyPlus twin of the multifamily prototype: element table.

Run from the repository root after ``make_reference.py`` (EnergyPlus 25.2 for its weather)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_multifamily/calibrate_twin.py \
        [--samples 32] [--write]

As ``../calibration_energyplus_5zone/calibrate_twin.py`` (same functions), on the second
building: the nominal IDF without its loads, Chicago O'Hare's TMY3, the committed log, a
campaign over the exterior wall's resistance, the top flats' ceiling to the attic
(``Interior Ceiling``; its attic side, ``Interior Ceiling (reversed)``, is the same wall and
no parameter: ``thermocal.multizone.elements.built_surfaces``) and the attic's infiltration
(the flats' infiltration, whose truth changes by x1.04-1.10 only, is not varied), 10-minute
steps, January 4-31, first with the building-total metric, then the
zone-group metric on the same samples. ``--write`` writes ``results.md`` / ``results.json``.
"""

from __future__ import annotations

import argparse
import gzip
import json
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))
sys.path.insert(0, str(HERE.parent / "calibration_energyplus_5zone"))

import calibrate_twin as base  # noqa: E402
from energyplus_twin import twin_idf, without_loads  # noqa: E402

IDF = ROOT / "tests" / "reference" / "identification_multifamily" / "multifamily_5A_FF_v25.idf"
WALL = "construction/Exterior Wall/resistance"
CEILING = "construction/Interior Ceiling/resistance"
INCLUDE = (WALL, CEILING, "zone/attic/infiltration_ach")


def campaign_text(samples: int, *, extra: str = "") -> str:
    include = ", ".join(f'"{n}"' for n in INCLUDE)
    return f"""building: nominal.idf
weather: weather.epw
sensors: sensors.csv
mapping: mapping.yaml
period: {{start: 2023-01-04, end: 2023-02-01}}
step: 10min
identification: {{method: inverse, settle: 1D, warmup_days: 3}}
parameters:
  level: element
  include: [{include}]
sampling: {{method: sobol, samples: {samples}, seed: 1}}
optimisation: {{starts: 4, seed: 1, refine: 4}}
{extra}"""


def prepare(folder: Path, samples: int, **kwargs) -> Path:
    from thermocal.multizone.energyplus import energyplus_weather_folder

    folder = Path(folder)
    (folder / "nominal.idf").write_text(twin_idf(without_loads(IDF.read_text()), 31))
    weather = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    shutil.copy(weather, folder / "weather.epw")
    with gzip.open(HERE / "sensors.csv.gz", "rb") as fh:
        (folder / "sensors.csv").write_bytes(fh.read())
    shutil.copy(HERE / "mapping.yaml", folder / "mapping.yaml")
    (folder / "campaign.yaml").write_text(campaign_text(samples, **kwargs))
    return folder / "campaign.yaml"


def run(folder: Path, samples: int, *, metrics=("building", "groups"), workers=1, log=None):
    base.WALL, base.ROOF = WALL, CEILING  # the pair whose posterior correlation is reported
    truth_file = json.loads((HERE / "truth.json").read_text())
    path = prepare(folder, samples)
    return base.calibrate_each_metric(
        path,
        lambda metric: campaign_text(samples, extra=f"metric: {metric}\n"),
        truth_file,
        metrics=metrics,
        workers=workers,
        log=log,
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=32)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--write", action="store_true")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        results = run(Path(tmp), args.samples, workers=args.workers, log=print)
    text = base.markdown(results, args.samples).replace(
        "5ZoneAirCooled", "the multifamily prototype (wall/roof correlation: wall/ceiling)"
    )
    print(text)
    if args.write:
        (HERE / "results.md").write_text(text)
        (HERE / "results.json").write_text(json.dumps(results, indent=2, default=str) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
