"""``thermocal calibrate`` on the EnergyPlus twin of the DOE outpatient prototype: element table.

Run from the repository root after ``make_reference.py`` (EnergyPlus 25.2 for its weather)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_outpatient/calibrate_twin.py \
        [--samples 32] [--workers 2] [--terms affine] [--write]

As ``../calibration_energyplus_5zone/calibrate_twin.py`` (same functions), on the large
building: the nominal IDF *with* its load objects and the identified heat in the form they
declare (``identified_heat: {radiant_fraction: declared}`` in the committed mapping: the 31
unsensed zones float with the file's loads), Chicago O'Hare's TMY3, the committed log of 87
zones, a campaign over the exterior wall's and the roof's resistance and the infiltration
(:data:`INCLUDE`), :data:`STEP` steps, January 4-31, first with the building-total metric, then
the zone-group metric on the same samples (``--resume``: nothing sampled again). ``--terms``
chooses the series meta-model's form (``affine``, the default, or ``auto``). ``--write``
writes ``results.md`` / ``results.json`` (``results_<terms>.*`` for another form).
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
from energyplus_twin import twin_idf  # noqa: E402

IDF = ROOT / "tests" / "reference" / "identification_outpatient" / "outpatient_FF_v25.idf"
WALL = "construction/Steel Frame Non-res Ext Wall/resistance"
ROOF = "construction/IEAD Non-res Roof/resistance"
#: every zone's infiltration (one parameter per zone; ``--building-infiltration`` varies one factor
#: on all of them instead; zones without infiltration are skipped by the campaign)
INFILTRATION = ("zone/*/infiltration_ach",)
INCLUDE = (WALL, ROOF, *INFILTRATION)
#: one factor on every zone's infiltration (``parameters: {infiltration: building}``)
FACTOR = "infiltration/building/factor"
STEP = "10min"
AIR = 1.2 * 1006.0 / 3600.0  # volumetric heat capacity of air per ACH [W h/(m3 K s)] -> W/K


def campaign_text(samples: int, *, extra: str = "", include=INCLUDE, step: str = STEP) -> str:
    names = ", ".join(f'"{n}"' for n in include)
    infiltration = "building" if FACTOR in include else "per_zone"
    return f"""building: nominal.idf
weather: weather.epw
sensors: sensors.csv
mapping: mapping.yaml
period: {{start: 2023-01-04, end: 2023-02-01}}
step: {step}
identification: {{method: inverse, settle: 1D, warmup_days: 3}}
parameters:
  level: element
  infiltration: {infiltration}
  include: [{names}]
sampling: {{method: sobol, samples: {samples}, seed: 1}}
optimisation: {{starts: 4, seed: 1, refine: 4}}
{extra}"""


def prepare(folder: Path, samples: int, **kwargs) -> Path:
    """The user's inputs (the nominal file with its loads) and the campaign file in ``folder``."""
    from thermocal.multizone.energyplus import energyplus_weather_folder

    folder = Path(folder)
    (folder / "nominal.idf").write_text(twin_idf(IDF.read_text(), 31))
    weather = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    shutil.copy(weather, folder / "weather.epw")
    with gzip.open(HERE / "sensors.csv.gz", "rb") as fh:
        (folder / "sensors.csv").write_bytes(fh.read())
    shutil.copy(HERE / "mapping.yaml", folder / "mapping.yaml")
    (folder / "campaign.yaml").write_text(campaign_text(samples, **kwargs))
    return folder / "campaign.yaml"


def infiltration_row(result, truth_file: dict) -> dict | None:
    """The varied zones' infiltration as one number, the heat-loss coefficient
    ``sum_z ach_z V_z rho c / 3600`` [W/K]: nominal, calibrated, posterior median and 90 %
    interval (from the posterior's draws; zones outside the posterior at their calibrated
    value), truth."""
    import numpy as np

    names = [n for n in result.space.names if n.endswith("/infiltration_ach")]
    if not names:
        return None
    zones = result.calibrated_building.zones
    volume = {n: zones[n.split("/")[1]].volume * AIR for n in names}
    from thermocal.calibration.workflow import candidate_parameters

    calibrated = candidate_parameters(result.calibrated_building, "element")

    def total(values) -> float:
        return float(sum(values[n] * volume[n] for n in names))

    row = {
        "parameter": f"infiltration of {len(names)} zones [W/K]",
        "nominal": total(truth_file["nominal"]),
        "calibrated": total(calibrated),
        "truth": total(truth_file["truth"]),
    }
    draws = result.posterior.samples
    if len(draws):
        h = sum((draws[n] if n in draws else calibrated[n]) * volume[n] for n in names)
        h = np.asarray(h, float)
        row.update(
            median=float(np.median(h)),
            q05=float(np.quantile(h, 0.05)),
            q95=float(np.quantile(h, 0.95)),
            determined="-",
        )
        row["covers"] = row["q05"] <= row["truth"] <= row["q95"]
    row["error"] = row["calibrated"] / row["truth"] - 1.0
    return row


def run(
    folder: Path,
    samples: int,
    *,
    metrics=("building", "groups"),
    workers=1,
    terms="affine",
    include=INCLUDE,
    log=None,
):
    base.WALL, base.ROOF = WALL, ROOF  # the pair whose posterior correlation is reported
    truth_file = with_factor(json.loads((HERE / "truth.json").read_text()))
    path = prepare(folder, samples, include=include)
    form = f"metamodel: {{kind: series, series_terms: {terms}}}\n"

    def infiltration_total(result, truth_file) -> dict:
        total = infiltration_row(result, truth_file)
        return {} if total is None else {"infiltration_total": total}

    return base.calibrate_each_metric(
        path,
        lambda metric: campaign_text(samples, include=include, extra=form + f"metric: {metric}\n"),
        truth_file,
        metrics=metrics,
        workers=workers,
        log=log,
        extra=infiltration_total,
    )


def with_factor(truth_file: dict) -> dict:
    """``truth_file`` with the building-wide infiltration factor: nominal 1, truth the common
    ratio of every zone's true to nominal rate (the hidden envelope scales every infiltration
    object by the same factor; checked)."""
    import numpy as np

    nominal, truth = truth_file["nominal"], truth_file["truth"]
    ratios = [
        truth[n] / nominal[n]
        for n in nominal
        if n.endswith("/infiltration_ach") and nominal[n] > 0
    ]
    if not ratios or np.ptp(ratios) > 1e-6 * np.mean(ratios):
        raise ValueError(f"the zones' infiltration ratios differ: {sorted(set(ratios))[:5]}")
    return {
        **truth_file,
        "nominal": {**nominal, FACTOR: 1.0},
        "truth": {**truth, FACTOR: float(np.mean(ratios))},
    }


def markdown(results: dict, samples: int, terms: str) -> str:
    """The 5-zone script's table with the zone infiltration rows folded into one (their
    heat-loss coefficient) when more than two."""
    folded = {}
    for metric, r in results.items():
        rows = r["rows"]
        zones = [row for row in rows if row["parameter"].endswith("/infiltration_ach")]
        if len(zones) > 2 and "infiltration_total" in r:
            posterior = sum("median" in row for row in zones)
            determined = sum(bool(row.get("determined")) for row in zones)
            missed = sum(not row.get("covers", True) for row in zones)
            total = dict(r["infiltration_total"])
            total["parameter"] += (
                f" ({posterior} zones in the posterior, the others at their calibrated value; "
                f"{determined} determined; {missed} zone intervals miss)"
            )
            rows = [row for row in rows if row not in zones] + [total]
        folded[metric] = {**r, "rows": rows}
    return base.markdown(folded, samples).replace(
        "5ZoneAirCooled", f"the DOE outpatient prototype (series terms {terms})"
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=32)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--terms", default="affine", choices=("affine", "auto", "quadratic"))
    parser.add_argument(
        "--fixed-infiltration",
        action="store_true",
        help="vary the wall and the roof only (the infiltration, x1.4 in the truth, left "
        "nominal: a model error; writes results_fixed_infiltration.*)",
    )
    parser.add_argument(
        "--building-infiltration",
        action="store_true",
        help="vary the wall, the roof and one factor on every zone's infiltration "
        "(parameters: {infiltration: building}; writes results_building_infiltration.*)",
    )
    parser.add_argument("--write", action="store_true")
    args = parser.parse_args(argv)
    include = (WALL, ROOF) if args.fixed_infiltration else INCLUDE
    if args.building_infiltration:
        include = (WALL, ROOF, FACTOR)
    with tempfile.TemporaryDirectory() as tmp:
        results = run(
            Path(tmp),
            args.samples,
            workers=args.workers,
            terms=args.terms,
            include=include,
            log=print,
        )
    text = markdown(results, args.samples, args.terms)
    print(text)
    if args.write:
        name = "results" if args.terms == "affine" else f"results_{args.terms}"
        if args.fixed_infiltration:
            name += "_fixed_infiltration"
        if args.building_infiltration:
            name += "_building_infiltration"
        (HERE / f"{name}.md").write_text(text)
        (HERE / f"{name}.json").write_text(json.dumps(results, indent=2, default=str) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
