"""EnergyPlus 25.2 twin of NREL's 5ZoneAirCooled with a hidden envelope, for calibration.

Run from the repository root (EnergyPlus 25.2 and ../shared/data needed, about 2 minutes)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_5zone/make_reference.py

The building thermocal did not write: ``5ZoneAirCooled_FF_v25.idf`` (NREL's example file,
converted to 25.2 and run free floating with its People/Lights/ElectricEquipment schedules;
``tests/identification/energyplus_twin.py``). EnergyPlus runs it for January at 1-minute steps
with a hidden envelope (:data:`PERTURBATION`): the wall insulation's resistance x0.6 (IN02
conductivity / 0.6), the roof insulation's x1.5 (IN46 conductivity / 1.5) and every zone's
infiltration design flow x1.4. Its zone air temperatures, sampled at 5 minutes and rounded
to 0.01 K (a logger's resolution), are the sensor log a user would have; thermocal gets the
*nominal* file without its load objects (the identified heat stands for them), the weather and
this log.

Writes beside this script:

- ``sensors.csv.gz``: the sensor log (``time`` = end of each 5-minute step, local standard
  time with its UTC offset, one column per zone ``T_<zone>`` [C]);
- ``mapping.yaml``: sensors -> zones;
- ``truth.json``: the element-level parameters thermocal reads from the nominal and from the
  perturbed file (``construction/<name>/resistance`` [m2 K/W], ``.../heat_capacity``
  [J/(m2 K)], ``zone/<name>/infiltration_ach`` [1/h]), and the perturbation applied.

The nominal envelope file is not committed (it is derived from the shared data):
:func:`nominal_envelope` writes it.
"""

from __future__ import annotations

import gzip
import json
import sys
import tempfile
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))

from energyplus_twin import (  # noqa: E402
    IDF_NAME,
    WEATHER_NAME,
    ZONES,
    _class,
    _join,
    _objects,
    make_twin_of,
    twin_idf,
    without_loads,
)

SHARED = ROOT.parent / "shared" / "data" / "energyplus_reference"
DAYS = 31
#: (IDF class, object name or None for every object of the class, field index, factor)
PERTURBATION = (
    ("material", "IN02", 4, 1 / 0.6),  # wall insulation conductivity: its R x0.6
    ("material", "IN46", 4, 1 / 1.5),  # roof insulation conductivity: its R x1.5
    ("zoneinfiltration:designflowrate", None, 5, 1.4),  # every zone's design flow x1.4
)


def perturbed(source: str, perturbation=PERTURBATION) -> str:
    """The IDF text with each listed numeric field multiplied by its factor.

    Parameters
    ----------
    source : str
        IDF text.
    perturbation : sequence of (class, name or None, field index, factor)
        Field index counts the class name as 0; factor [-] > 0.
    """
    out, used = [], set()
    for obj in _objects(source):
        fields = [f.strip() for f in obj.split(",")]
        for i, (kind, name, index, factor) in enumerate(perturbation):
            if _class(obj) == kind and (name is None or fields[1].upper() == name.upper()):
                fields[index] = repr(float(fields[index]) * factor)
                obj = ",\n  ".join(fields)
                used.add(i)
        out.append(obj)
    missing = [p for i, p in enumerate(perturbation) if i not in used]
    if missing:
        raise ValueError(f"perturbation not applied (object not found): {missing}")
    return _join(out)


def nominal_envelope(path: Path, shared: Path = SHARED) -> Path:
    """Write the nominal file thermocal gets (no load objects, January) to ``path``."""
    source = (Path(shared) / IDF_NAME).read_text()
    Path(path).write_text(twin_idf(without_loads(source), DAYS))
    return Path(path)


def nominal_with_loads(path: Path, shared: Path = SHARED) -> Path:
    """Write the nominal file as a user has it (with its load objects, January) to ``path``."""
    source = (Path(shared) / IDF_NAME).read_text()
    Path(path).write_text(twin_idf(source, DAYS))
    return Path(path)


def element_values(idf_text: str, folder: Path) -> dict[str, float]:
    """The element-level parameters thermocal reads from an IDF text (without its loads)."""
    from thermocal.calibration.workflow import candidate_parameters
    from thermocal.multizone.idf import read_idf

    path = Path(folder) / "read.idf"
    path.write_text(twin_idf(without_loads(idf_text), DAYS))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(path)
    return {k: float(v) for k, v in candidate_parameters(building, "element").items()}


def main() -> None:
    source = (SHARED / IDF_NAME).read_text()
    hidden = perturbed(source)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        nominal = element_values(source, tmp)
        truth = element_values(hidden, tmp)
        twin = make_twin_of(
            hidden,
            tmp,
            DAYS,
            zones=ZONES,
            envelope=without_loads(source),
            energyplus_steps_per_hour=60,
        )
    description = "5ZoneAirCooled, hidden envelope: " + ", ".join(
        f"{k} {n or 'all'} field {i} x{f:.4g}" for k, n, i, f in PERTURBATION
    )
    write_reference(HERE, twin.temperature[list(ZONES)], nominal, truth, description)


def write_reference(folder: Path, temperatures, nominal: dict, truth: dict, description: str):
    """Write a twin's reference files into ``folder``: ``sensors.csv.gz`` (the zones' air
    temperatures [C] rounded to 0.01 K, stamped at each step's end with the UTC offset),
    ``mapping.yaml`` and ``truth.json`` (``nominal`` and ``truth`` element values [unit of
    each], their changed ratios and ``description``); prints the changed ratios.

    Parameters
    ----------
    folder : Path
    temperatures : DataFrame
        EnergyPlus' zone air temperatures at 5 minutes, one column per zone of ``ZONES``,
        labelled by the start of each step [C].
    nominal, truth : dict
        Element-level parameters thermocal reads from the nominal and the hidden file.
    description : str
        What was hidden.
    """
    log = temperatures.round(2)
    log.index = log.index + (log.index[1] - log.index[0])  # stamped at the step's end
    log.index.name = "time"
    log = log.rename(columns={z: f"T_{z}" for z in ZONES})
    with gzip.open(folder / "sensors.csv.gz", "wt", compresslevel=9) as fh:
        log.to_csv(fh, date_format="%Y-%m-%dT%H:%M:%S%z")
    (folder / "mapping.yaml").write_text(
        "sensors:\n" + "".join(f"  T_{z}: {z}\n" for z in ZONES)
    )
    changed = {k: truth[k] / nominal[k] for k in nominal if abs(truth[k] - nominal[k]) > 1e-9}
    (folder / "truth.json").write_text(
        json.dumps(
            {
                "description": description,
                "energyplus_steps_per_hour": 60,
                "sensor_step": "5min",
                "nominal": nominal,
                "truth": truth,
                "changed_ratio": changed,
            },
            indent=2,
        )
        + "\n"
    )
    print(json.dumps(changed, indent=2))


#: The heat-flux plate of :func:`heat_flux_study`: on the inside face of the roof (over the
#: plenum), with the roof's inside and outside surface temperatures, January 4-17 (days 3 to
#: 17 after the run's start).
PLATE_SURFACE, PLATE_DAYS = "TOP-1", (3, 17)


def plate_log(hidden: str, surface: str, days=PLATE_DAYS, seed: int = 98693):
    """An ISO 9869-1 heat-flux plate with surface thermometers on ``surface`` of the building
    ``hidden`` (IDF text, loads included): EnergyPlus runs it free floating at 1-minute steps
    with the surface's inside-face conduction and its two face temperatures as outputs; their
    hourly means over ``days`` (days after the run's start, end excluded), the plate reading 3 %
    high with 2 % noise per hour, the thermometers with 0.1 K noise (``seed``).

    Returns
    -------
    log : DataFrame
        ``time`` (start of each hour), ``q_W_m2`` (outward), ``Tsi``, ``Tse`` [C].
    period : list of str
        The first and last hour.
    """
    import numpy as np
    import pandas as pd

    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import (
        energyplus_weather_folder,
        read_eso,
        run_energyplus,
    )

    variables = {
        "q": "Surface Inside Face Conduction Heat Transfer Rate per Area",
        "Tsi": "Surface Inside Face Temperature",
        "Tse": "Surface Outside Face Temperature",
    }
    text = twin_idf(hidden, DAYS, timesteps_per_hour=60) + "".join(
        f"Output:Variable, {surface}, {v}, Timestep;\n" for v in variables.values()
    )
    weather_path = energyplus_weather_folder() / WEATHER_NAME
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        weather, _ = read_weather(weather_path)
    with tempfile.TemporaryDirectory() as tmp:
        idf = Path(tmp) / "in.idf"
        idf.write_text(text)
        eso = run_energyplus(idf, weather_path, Path(tmp) / "energyplus")
        frame = read_eso(eso, year=int(weather.index[0].year), frequency="timestep")
    columns = {
        k: next(c for c in frame.columns if c.upper().startswith(f"{surface}:{v}".upper()))
        for k, v in variables.items()
    }
    # hourly means labelled by the hour's start (read_eso labels each step by its start)
    minute = frame[list(columns.values())].rename(columns={c: k for k, c in columns.items()})
    hourly = minute.groupby(minute.index.floor("1h")).mean()
    first = hourly.index[0].normalize()
    elapsed = (hourly.index - first) / pd.Timedelta(days=1)
    hourly = hourly[(elapsed >= days[0]) & (elapsed < days[1])]
    rng = np.random.default_rng(seed)
    n = len(hourly)
    log = pd.DataFrame(
        {
            "time": hourly.index.strftime("%Y-%m-%d %H:%M"),
            # EnergyPlus's inside-face conduction is positive into the zone
            "q_W_m2": -hourly["q"].to_numpy() * 1.03 * (1 + rng.normal(0, 0.02, n)),
            "Tsi": hourly["Tsi"].to_numpy() + rng.normal(0, 0.1, n),
            "Tse": hourly["Tse"].to_numpy() + rng.normal(0, 0.1, n),
        }
    )
    return log.round(3), [str(hourly.index[0]), str(hourly.index[-1])]


def plate_record(file: str, surface: str, construction: str, period, seed: int) -> dict:
    """What ``truth.json`` keeps of a plate of :func:`plate_log`."""
    return {
        "file": file,
        "surface": surface,
        "construction": construction,
        "period": period,
        "temperatures": "surface",
        "plate_bias": 1.03,
        "plate_noise_rel": 0.02,
        "temperature_noise_K": 0.1,
        "seed": seed,
        "truth": f"truth['construction/{construction}/resistance']",
    }


def heat_flux_study() -> dict:
    """An in-situ measurement of the roof as a building physicist makes it (ISO 9869-1 with
    surface temperatures: the construction's thermal resistance), :func:`plate_log` on the
    roof (:data:`PLATE_SURFACE`) of the hidden building, January 4-17.

    Writes ``heat_flux_roof.csv`` (time = start of each hour, ``q_W_m2`` outward, ``Tsi``,
    ``Tse`` [C]) and adds ``heat_flux`` (the plate and its seed) to ``truth.json``: the truth it
    estimates is the hidden roof's ``construction/ROOF-1/resistance`` already there.
    """
    hidden = perturbed((SHARED / IDF_NAME).read_text())
    log, period = plate_log(hidden, PLATE_SURFACE, PLATE_DAYS, seed=98693)
    log.to_csv(HERE / "heat_flux_roof.csv", index=False)
    truth = json.loads((HERE / "truth.json").read_text())
    truth["heat_flux"] = plate_record("heat_flux_roof.csv", PLATE_SURFACE, "ROOF-1", period, 98693)
    (HERE / "truth.json").write_text(json.dumps(truth, indent=2) + "\n")
    return truth["heat_flux"]


if __name__ == "__main__":
    if "--heat-flux" in sys.argv:
        print(json.dumps(heat_flux_study(), indent=1))
    else:
        main()
