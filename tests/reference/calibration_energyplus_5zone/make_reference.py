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
    log = twin.temperature[list(ZONES)].round(2)
    log.index = log.index + (log.index[1] - log.index[0])  # stamped at the step's end
    log.index.name = "time"
    log = log.rename(columns={z: f"T_{z}" for z in ZONES})
    with gzip.open(HERE / "sensors.csv.gz", "wt", compresslevel=9) as fh:
        log.to_csv(fh, date_format="%Y-%m-%dT%H:%M:%S%z")
    (HERE / "mapping.yaml").write_text("sensors:\n" + "".join(f"  T_{z}: {z}\n" for z in ZONES))
    changed = {k: truth[k] / nominal[k] for k in nominal if abs(truth[k] - nominal[k]) > 1e-9}
    (HERE / "truth.json").write_text(
        json.dumps(
            {
                "description": "5ZoneAirCooled, hidden envelope: "
                + ", ".join(f"{k} {n or 'all'} field {i} x{f:.4g}" for k, n, i, f in PERTURBATION),
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


if __name__ == "__main__":
    main()
