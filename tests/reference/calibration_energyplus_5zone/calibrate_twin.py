"""``thermocal calibrate`` on the EnergyPlus twin of 5ZoneAirCooled: element table vs the truth.

Run from the repository root after ``make_reference.py`` (EnergyPlus 25.2 for its weather file
and ../shared/data for the nominal IDF)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_5zone/calibrate_twin.py \
        [--samples 32] [--write]

thermocal gets what a user has: the nominal IDF without its load objects, Chicago O'Hare's
TMY3 weather and the committed sensor log (``sensors.csv.gz``, EnergyPlus' zone air
temperatures of the hidden envelope). The campaign (:func:`campaign_text`) varies the
element-level parameters a building physicist names: the exterior wall's and the roof's
thermal resistance and each office's infiltration, +-75 % (the default range), Sobol'
samples, the default meta-model, posterior and metric; then the same samples are re-analysed
with the zone-group metric. Besides the campaign, the true envelope's metric (the model with
the truth's element values, identified the same way) is what the confirmed metric is compared
with. ``--write`` writes ``results.json`` and ``results.md`` beside this script.
"""

from __future__ import annotations

import argparse
import gzip
import json
import shutil
import sys
import tempfile
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
# other reference folders have a make_reference.py too: take this folder's, not a cached one
sys.modules.pop("make_reference", None)

from make_reference import SHARED, nominal_envelope, nominal_with_loads  # noqa: E402

WALL, ROOF = "construction/WALL-1/resistance", "construction/ROOF-1/resistance"
OFFICES = ("SPACE1-1", "SPACE2-1", "SPACE3-1", "SPACE4-1", "SPACE5-1")
INFILTRATION = tuple(f"zone/{z}/infiltration_ach" for z in OFFICES)
PERIOD = ("2023-01-04", "2023-02-01")


def campaign_text(
    samples: int, *, step: str = "15min", period=PERIOD, extra: str = "", zoom: int | None = None
) -> str:
    """The campaign file (building, weather, sensors and mapping beside it); ``zoom``: the
    local campaign's samples (None: the default)."""
    include = ", ".join(f'"{n}"' for n in (WALL, ROOF, "zone/SPACE*/infiltration_ach"))
    return f"""building: nominal.idf
weather: weather.epw
sensors: sensors.csv
mapping: mapping.yaml
period: {{start: {period[0]}, end: {period[1]}}}
step: {step}
identification: {{method: inverse, settle: 1D, warmup_days: 3}}
parameters:
  level: element
  include: [{include}]
sampling: {{method: sobol, samples: {samples}, seed: 1{"" if zoom is None else f", zoom: {zoom}"}}}
optimisation: {{starts: 4, seed: 1, refine: 4}}
{extra}"""


def prepare(
    folder: Path, samples: int, *, shared: Path = SHARED, declared: bool = False, **kwargs
) -> Path:
    """Write the user's inputs and the campaign file into ``folder``; return its path.

    ``shared``: the folder of ``5ZoneAirCooled_FF_v25.idf``; ``kwargs`` go to
    :func:`campaign_text`."""
    from thermocal.multizone.energyplus import energyplus_weather_folder

    folder = Path(folder)
    if declared:
        # the nominal file as the user has it, with its People/Lights/equipment objects, and the
        # identified heat in the form they declare step by step (the objects not simulated)
        nominal_with_loads(folder / "nominal.idf", shared)
    else:
        nominal_envelope(folder / "nominal.idf", shared)
    weather = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    shutil.copy(weather, folder / "weather.epw")
    with gzip.open(HERE / "sensors.csv.gz", "rb") as fh:
        (folder / "sensors.csv").write_bytes(fh.read())
    shutil.copy(HERE / "mapping.yaml", folder / "mapping.yaml")
    if declared:
        with (folder / "mapping.yaml").open("a") as fh:
            fh.write("identified_heat: {radiant_fraction: declared}\n")
    (folder / "campaign.yaml").write_text(campaign_text(samples, **kwargs))
    return folder / "campaign.yaml"


def true_metric(campaign, truth: dict, metric: str) -> float:
    """The campaign's metric of the model with the true element values [W^2]."""
    from thermocal.calibration.spatial import campaign_evaluator
    from thermocal.calibration.workflow import build_problem, choose_quiet_hours, load_inputs

    inputs = load_inputs(campaign)
    problem, _ = build_problem(campaign, inputs)
    problem.series_outputs = True
    evaluator = campaign_evaluator(problem, inputs.building)
    nominal = problem.run({})
    problem.schedule, _ = choose_quiet_hours(campaign, nominal.heat.sum(axis=1), log=lambda s: 0)
    outputs = evaluator.outputs(problem.run(truth).heat)
    from thermocal.calibration.workflow import metric_value

    return float(metric_value(outputs, metric))


def element_rows(result, nominal: dict, truth: dict) -> list[dict]:
    """Nominal, calibrated, posterior median and 90 % interval, truth per varied parameter."""
    from thermocal.calibration.workflow import candidate_parameters

    factor = "infiltration/building/factor" in result.space.names
    calibrated = candidate_parameters(
        result.calibrated_building, "element", infiltration="building" if factor else "per_zone"
    )
    post = result.posterior.summary
    rows = []
    for name in result.space.names:
        row = {
            "parameter": name,
            "nominal": nominal[name],
            "calibrated": calibrated[name],
            "truth": truth[name],
        }
        if name in post.index:
            row.update(
                median=float(post.at[name, "median"]),
                q05=float(post.at[name, "q05"]),
                q95=float(post.at[name, "q95"]),
                determined=bool(post.at[name, "determined"]),
            )
            if "q05_mcse" in post.columns:  # the Monte Carlo standard errors of the ends
                row.update(
                    q05_mcse=float(post.at[name, "q05_mcse"]),
                    q95_mcse=float(post.at[name, "q95_mcse"]),
                )
            row["covers"] = row["q05"] <= row["truth"] <= row["q95"]
        row["error"] = row["calibrated"] / row["truth"] - 1.0
        rows.append(row)
    return rows


def track_record_figures(summary: dict) -> dict:
    """The figures ``thermocal.calibration.track_record`` states for a twin, from its summary:
    the determined element resistances, their largest error [%], the intervals covering the
    truth of the parameters in the posterior (all, and those declared determined), the confirmed
    metric against the true envelope's [%], the element totals covering the truth's."""
    rows = [r for r in summary["rows"] if "q05" in r]
    resistances = [
        r for r in rows
        if r["parameter"].startswith("construction/") and r["parameter"].endswith("/resistance")
        and r.get("determined")
    ]  # fmt: skip
    determined = [r for r in rows if r.get("determined")]
    totals = [t for t in summary["envelope_total"].values() if "truth_W_per_K" in t]
    return {
        "determined_resistances": len(resistances),
        "max_resistance_error_pct": max(
            (100.0 * abs(r["error"]) for r in resistances), default=0.0
        ),
        "covered": sum(bool(r["covers"]) for r in rows),
        "parameters": len(rows),
        "determined_covered": sum(bool(r["covers"]) for r in determined),
        "determined": len(determined),
        "metric_vs_truth_pct": 100.0 * (summary["calibrated_metric"] / summary["true_metric"] - 1),
        "totals_covered": sum(
            t["q05_W_per_K"] <= t["truth_W_per_K"] <= t["q95_W_per_K"] for t in totals
        ),
        "totals": len(totals),
    }


def check_track_record(summary: dict, key: str) -> None:
    """Assert that ``thermocal.calibration.track_record`` states this twin's figures (the
    report's record of the reference folder ``key``), each within its rounding."""
    from thermocal.calibration.track_record import INDEPENDENT_CALIBRATIONS, differs_from

    measured = track_record_figures(summary)
    assert not differs_from(INDEPENDENT_CALIBRATIONS[key], measured), measured


def summarise(result, campaign, truth_file: dict, metric: str) -> dict:
    """Element rows, metrics (nominal, true envelope, calibrated), flags and timings of a
    calibration result."""
    from thermocal.calibration.workflow import load_inputs

    nominal, truth = truth_file["nominal"], truth_file["truth"]
    varied = {n: truth[n] for n in result.space.names}
    envelope = true_metric(campaign, varied, metric)
    confirmed = result.confirmed["calibrated"]
    return {
        "rows": element_rows(result, nominal, truth),
        "nominal_metric": float(result.nominal_metric),
        "true_metric": envelope,
        "calibrated_metric": float(confirmed["confirmed"]),
        "calibrated_source": str(confirmed.get("source")),
        "flags": result.confirmed.get("flags", []),
        "model_error_floor": result.confirmed.get("model_error_floor"),
        "cv_r2": float(result.surrogate.cv_r2_),
        "surrogate": type(result.surrogate).__name__,
        "runs": result.runs,
        "timings": result.timings,
        "notes": result.notes,
        "noise_std_W": float(result.posterior.noise_std),
        "emulator_std_W": float(result.posterior.emulator_std),
        "correlation_wall_roof": float(result.posterior.correlation.loc[WALL, ROOF]),
        "zoom": result.zoom,
        "envelope_total": envelope_total(result, truth, load_inputs(campaign).building),
    }


def envelope_total(result, truth: dict, building) -> dict:
    """The posterior's total conductances of the varied elements and air changes
    (:mod:`thermocal.calibration.envelope_total`) with the truth's, per part, when the truth
    gives every one of their parameters [W/K]; ``building``: the nominal one (areas, volumes)."""
    from thermocal.calibration.coordinates import FILM_RESISTANCE
    from thermocal.calibration.envelope_total import conductance_terms

    totals = {part: dict(total) for part, total in result.posterior.envelope_total.items()}
    for total in totals.values():
        keys = total["parameters"]
        if all(k in truth for k in keys):
            terms = conductance_terms(keys, building)
            total["truth_W_per_K"] = sum(
                terms[k][3] / (truth[k] + FILM_RESISTANCE) if k.endswith("/resistance")
                else terms[k][3] * truth[k]
                for k in keys
            )  # fmt: skip
    return totals


def run(
    folder: Path,
    samples: int,
    *,
    metrics=("building", "groups"),
    workers=1,
    log=None,
    declared: bool = False,
    zoom: int | None = None,
):
    """The campaign with the first metric, then the same samples with the others (``--resume``:
    nothing sampled again, their optima confirmed with the model).

    Returns a dict per metric (:func:`summarise`) with the seconds it took."""
    truth_file = json.loads((HERE / "truth.json").read_text())
    path = prepare(folder, samples, declared=declared, zoom=zoom)
    return calibrate_each_metric(
        path,
        lambda metric: campaign_text(samples, extra=f"metric: {metric}\n", zoom=zoom),
        truth_file,
        metrics=metrics,
        workers=workers,
        log=log,
    )


def calibrate_each_metric(path: Path, text_for, truth_file: dict, *, metrics, workers, log,
                          extra=None) -> dict:  # fmt: skip
    """``thermocal calibrate`` of the campaign file ``path`` (its text ``text_for(metric)``)
    with the first metric, then the same samples with the others (``--resume``: nothing
    sampled again), the store beside ``path``. Returns a dict per metric (:func:`summarise`,
    updated by ``extra(result, truth_file)`` when given) with the seconds it took."""
    from thermocal.calibration.config import load_campaign

    out = {}
    for i, metric in enumerate(metrics):
        path.write_text(text_for(metric))
        campaign = load_campaign(path)
        result, elapsed = timed_calibration(campaign, path.parent, workers=workers,
                                            resume=bool(i), log=log)  # fmt: skip
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out[metric] = summarise(result, campaign, truth_file, metric)
            if extra is not None:
                out[metric].update(extra(result, truth_file))
        out[metric]["seconds"] = elapsed
    return out


def timed_calibration(campaign, folder: Path, *, workers: int, resume: bool, log=None):
    """``thermocal calibrate`` of a loaded campaign with its store in ``folder``, quiet
    (warnings and progress off); returns the result and the seconds it took."""
    from thermocal.calibration.workflow import calibrate

    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = calibrate(
            campaign,
            workers=workers,
            store_path=folder / "campaign.sqlite",
            resume=resume,
            progress=False,
            log=log or (lambda line: None),
        )
    return result, time.perf_counter() - t0


def interval_cell(row: dict) -> str:
    """A parameter's row as a table cell: calibrated / truth - 1 [posterior 90 % interval]
    and whether it covers the truth."""
    return (
        f"{100 * row['error']:+.1f} % [{row['q05']:.3f}, {row['q95']:.3f}] "
        f"{'yes' if row['covers'] else 'no'}"
    )


def markdown(results: dict, samples: int) -> str:
    lines = [
        "# thermocal calibrate on the EnergyPlus twin of 5ZoneAirCooled\n",
        f"Generated by `calibrate_twin.py` ({samples} samples; hidden truth in `truth.json`).\n",
        "| metric | parameter | nominal | calibrated | posterior median [90 % interval] | truth "
        "| calibrated / truth | determined | interval covers truth |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for metric, r in results.items():
        for row in r["rows"]:
            interval = "-"
            if "median" in row:
                interval = f"{row['median']:.3f} [{row['q05']:.3f}, {row['q95']:.3f}]"
            lines.append(
                f"| {metric} | {row['parameter']} | {row['nominal']:.3f} | {row['calibrated']:.3f} "
                f"| {interval} | {row['truth']:.3f} | {100 * row['error']:+.1f} % | "
                f"{row.get('determined', '-')} | {row.get('covers', '-')} |"
            )
    lines.append("")
    for metric, r in results.items():
        ratio = r["calibrated_metric"] / r["true_metric"]
        lines.append(
            f"- {metric}: metric nominal {r['nominal_metric']:.4g}, true envelope "
            f"{r['true_metric']:.4g}, calibrated {r['calibrated_metric']:.4g} W^2 "
            f"(x{ratio:.3f} the true envelope's; from the {r['calibrated_source']}); "
            f"{r['surrogate']} CV R2 {r['cv_r2']:.3f}; flags: "
            + ("; ".join(f.get("text", str(f)) for f in r["flags"]) or "none")
            + f"; noise {r['noise_std_W']:.0f} W per hour (meta-model {r['emulator_std_W']:.0f} W);"
            + f" posterior correlation wall/roof {r['correlation_wall_roof']:+.2f}"
            + f"; {r['seconds']:.0f} s"
            + zoom_text(r.get("zoom"))
        )
    return "\n".join(lines) + "\n"


def zoom_text(zoom: dict | None) -> str:
    """The zoom stage in one clause (empty when none ran)."""
    if not zoom:
        return ""
    box = "; ".join(
        f"{name.split('/')[1]} [{b['lower']:.3g}, {b['upper']:.3g}]"
        for name, b in zoom["box"].items()
        if b["upper"] / b["lower"] < 4.0  # the narrowed ones; the others span the whole range
    )
    return (
        f"; zoom stage: {zoom['local_samples']} local samples ({zoom['runs']['simulated']} "
        f"simulated), box {box or 'the whole range'}, local meta-model CV R2 "
        f"{zoom['cv_r2']:.3f}, first stage's answer {zoom['first_stage']['confirmed']:.4g} W^2 "
        f"({zoom['first_stage']['source']})"
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=32)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument(
        "--zoom", type=int, default=None, help="sampling.zoom (default: the campaign default)"
    )
    parser.add_argument("--write", action="store_true")
    parser.add_argument(
        "--declared",
        action="store_true",
        help="the nominal file with its load objects and the identified heat in the form they "
        "declare step by step (writes results_declared.*)",
    )
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        results = run(
            Path(tmp),
            args.samples,
            workers=args.workers,
            log=print,
            declared=args.declared,
            zoom=args.zoom,
        )
    text = markdown(results, args.samples)
    print(text)
    if args.write:
        name = "results_declared" if args.declared else "results"
        (HERE / f"{name}.md").write_text(text)
        (HERE / f"{name}.json").write_text(json.dumps(results, indent=2, default=str) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
