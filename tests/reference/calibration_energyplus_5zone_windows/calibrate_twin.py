"""``thermocal calibrate`` on the 5ZoneAirCooled twin with other windows: element table vs truth.

Run from the repository root after ``make_reference.py`` (EnergyPlus 25.2 for its weather file
and ../shared/data for the nominal IDF)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_5zone_windows/calibrate_twin.py \
        [--samples 48] [--step 15min] [--zoom 0] [--write]

As ``../calibration_energyplus_5zone/calibrate_twin.py`` (its functions, imported), on this
folder's log: thermocal gets the nominal IDF without its load objects, Chicago O'Hare's TMY3 and
``sensors.csv.gz``; the campaign varies the element-level parameters a building physicist would
name for this building (:data:`INCLUDE`: exterior wall, roof and ground floor resistance, the
double glazing's U-value and SHGC, one factor on every zone's infiltration; +-75 %, the SHGC at
most 1), Sobol' samples, the default meta-model, posterior and metric (the zone groups), January
4-31. The truth is what thermocal reads from the hidden file (``truth.json``); the confirmed
metric is compared with the true envelope's (the model with the truth's values of the varied
parameters, identified the same way). ``--write`` writes ``results.md`` / ``results.json``
(``results_<tag>.*`` with ``--tag``).
"""

from __future__ import annotations

import argparse
import gzip
import importlib.util
import json
import shutil
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _five_zone_script():
    """The 5-zone twin's ``calibrate_twin`` module, loaded from its file under its own name
    (this script has the same file name; the 5-zone script imports its folder's
    ``make_reference``, whose name this folder's script shares too)."""
    path = HERE.parent / "calibration_energyplus_5zone" / "calibrate_twin.py"
    spec = importlib.util.spec_from_file_location("calibrate_twin_5zone", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


base = _five_zone_script()


def folder_make_reference():
    """This folder's ``make_reference.py``, loaded from its file under its own name (the 5-zone
    folder's script has the same file name and is imported by the 5-zone ``calibrate_twin``)."""
    spec = importlib.util.spec_from_file_location(
        "make_reference_windows", HERE / "make_reference.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module

WALL, ROOF = base.WALL, base.ROOF
FLOOR = "construction/FLOOR-SLAB-1/resistance"
WINDOW_U = "window/Dbl Clr 3mm/13mm Air/u_value"
WINDOW_SHGC = "window/Dbl Clr 3mm/13mm Air/shgc"
FACTOR = "infiltration/building/factor"
INCLUDE = (WALL, ROOF, FLOOR, WINDOW_U, WINDOW_SHGC, FACTOR)
PERIOD = base.PERIOD
SAMPLES, STEP = 48, "15min"


def campaign_text(
    samples: int = SAMPLES,
    *,
    step: str = STEP,
    include=INCLUDE,
    zoom: int | None = None,
    ranges: dict | None = None,
    coordinates: str | None = None,
    extra: str = "",
) -> str:
    """The campaign file (building, weather, sensors and mapping beside it).

    Parameters
    ----------
    samples : int
        Sobol' samples of the campaign.
    step : str
        The model's and the metric's step (pandas offset, e.g. ``"15min"``).
    include : sequence of str
        The varied element-level parameters.
    zoom : int, optional
        ``sampling.zoom``, the local campaign's samples (None: the default, off).
    ranges : dict, optional
        ``parameters.ranges``: relative half-widths [-] by name pattern (None: the default
        +-75 % for every parameter, the SHGC at most 1).
    coordinates : str, optional
        ``metamodel.series_coordinates`` (None: the default, ``physical``).
    extra : str
        Further YAML lines appended (``metric: ...``, ``metamodel: ...``).
    """
    names = ", ".join(f'"{n}"' for n in include)
    metamodel_text = f"metamodel: {{series_coordinates: {coordinates}}}\n" if coordinates else ""
    infiltration = "building" if FACTOR in include else "per_zone"
    zoom_text = "" if zoom is None else f", zoom: {zoom}"
    range_text = ""
    if ranges:
        range_text = "  ranges: {" + ", ".join(f'"{k}": {v}' for k, v in ranges.items()) + "}\n"
    return f"""building: nominal.idf
weather: weather.epw
sensors: sensors.csv
mapping: mapping.yaml
period: {{start: {PERIOD[0]}, end: {PERIOD[1]}}}
step: {step}
identification: {{method: inverse, settle: 1D, warmup_days: 3}}
parameters:
  level: element
  infiltration: {infiltration}
  include: [{names}]
{range_text}sampling: {{method: sobol, samples: {samples}, seed: 1{zoom_text}}}
optimisation: {{starts: 4, seed: 1, refine: 4}}
{metamodel_text}{extra}"""


def prepare(folder: Path, samples: int = SAMPLES, *, shared: Path = base.SHARED, **kwargs) -> Path:
    """Write the user's inputs (the nominal file without its loads, the weather, this folder's
    log and mapping) and the campaign file into ``folder``; return the campaign's path.

    ``shared``: the folder of ``5ZoneAirCooled_FF_v25.idf``; ``kwargs`` go to
    :func:`campaign_text`."""
    from thermocal.multizone.energyplus import energyplus_weather_folder

    folder = Path(folder)
    base.nominal_envelope(folder / "nominal.idf", shared)
    weather = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    shutil.copy(weather, folder / "weather.epw")
    with gzip.open(HERE / "sensors.csv.gz", "rb") as fh:
        (folder / "sensors.csv").write_bytes(fh.read())
    shutil.copy(HERE / "mapping.yaml", folder / "mapping.yaml")
    (folder / "campaign.yaml").write_text(campaign_text(samples, **kwargs))
    return folder / "campaign.yaml"


def truth_file() -> dict:
    """This folder's ``truth.json``: nominal and hidden element values, the changes applied."""
    return json.loads((HERE / "truth.json").read_text())


def run(folder: Path, samples: int = SAMPLES, *, metrics=("groups",), workers=1, log=None,
        **kwargs) -> dict:  # fmt: skip
    """The campaign with the first metric, then the same samples with the others (nothing
    sampled again). Returns a dict per metric (the 5-zone script's ``summarise``, with the
    seconds it took); ``kwargs`` go to :func:`campaign_text`."""
    path = prepare(folder, samples, **kwargs)
    return base.calibrate_each_metric(
        path,
        lambda metric: campaign_text(samples, extra=f"metric: {metric}\n", **kwargs),
        truth_file(),
        metrics=metrics,
        workers=workers,
        log=log,
    )


def markdown(
    results: dict, samples: int, step: str, zoom: int | None, ranges=None, coordinates=None
) -> str:
    """The 5-zone script's table and metric lines under this twin's title."""
    text = base.markdown(results, samples)
    title = (
        "# thermocal calibrate on the 5ZoneAirCooled twin with other windows\n\n"
        f"Generated by `calibrate_twin.py` ({samples} samples, {step} steps, zoom "
        f"{zoom or 0}, ranges {ranges or 'default (+-75 %)'}, series meta-model coordinates "
        f"{coordinates or 'physical (the default)'}; hidden truth in `truth.json`: "
        f"{truth_file()['description']}).\n"
    )
    return title + text.split("\n", 3)[3]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=SAMPLES)
    parser.add_argument("--step", default=STEP)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--zoom", type=int, default=None, help="sampling.zoom (default: off)")
    parser.add_argument("--metrics", default="groups", help="comma-separated, first sampled")
    parser.add_argument(
        "--range",
        action="append",
        default=[],
        metavar="PATTERN=HALF_WIDTH",
        help="parameters.ranges entry (relative half-width, e.g. '*FLOOR*=1.5'); repeatable",
    )
    parser.add_argument(
        "--without",
        action="append",
        default=[],
        metavar="NAME",
        help="leave this parameter of INCLUDE at its nominal value; repeatable",
    )
    parser.add_argument(
        "--coordinates",
        default=None,
        choices=("physical", "log"),
        help="metamodel.series_coordinates (default: the campaign's default, physical)",
    )
    parser.add_argument("--write", action="store_true")
    parser.add_argument("--tag", default="", help="results_<tag>.* instead of results.*")
    args = parser.parse_args(argv)
    ranges = {k: float(v) for k, v in (item.rsplit("=", 1) for item in args.range)} or None
    with tempfile.TemporaryDirectory() as tmp:
        results = run(
            Path(tmp),
            args.samples,
            metrics=tuple(args.metrics.split(",")),
            workers=args.workers,
            log=print,
            step=args.step,
            zoom=args.zoom,
            ranges=ranges,
            coordinates=args.coordinates,
            include=tuple(n for n in INCLUDE if n not in args.without),
        )
    text = markdown(results, args.samples, args.step, args.zoom, ranges, args.coordinates)
    print(text)
    if args.write:
        name = f"results_{args.tag}" if args.tag else "results"
        (HERE / f"{name}.md").write_text(text)
        (HERE / f"{name}.json").write_text(json.dumps(results, indent=2, default=str) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
