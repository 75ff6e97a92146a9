"""EnergyPlus 25.2 twin of the DOE outpatient prototype with a hidden envelope, for calibration.

Run from the repository root (EnergyPlus 25.2 needed, about two minutes)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_outpatient/make_reference.py

The large building thermocal did not write (``tests/reference/identification_outpatient``: 118
zones on three storeys), with the hidden envelope of issue 26's measurement
(:func:`perturbation`): the wall insulation's resistance / 1.5 (``Steel Frame NonRes Wall
Insulation`` conductivity x1.5), the roof insulation's / 0.6 (``IEAD NonRes Roof Insulation``
conductivity x0.6, its R x1.67) and every infiltration object's design level x1.4 (52
``Flow/ExteriorWallArea``, 4 shafts' ``AirChanges/Hour``). EnergyPlus runs January free float
with the file's loads at 5-minute steps; its zone air temperatures at every second step (10
minutes), rounded to 0.01 K, are the sensor log of 87 of the 118 zones (drawn with seed 1, as
``measure_identification.py``); the other 31 float. Writes beside this script, like
``../calibration_energyplus_5zone``:

- ``sensors.csv.gz``: the log (``time`` = end of each 10-minute step, ``T000``... by the
  zone's place in the file);
- ``mapping.yaml``: sensors -> zones, the hot rooms' own plausible range (mean +- 15 K; the MRI
  room reaches 95 C) and ``identified_heat: {radiant_fraction: declared}`` (the identified heat
  in the form the file's load objects declare; the floating zones keep them);
- ``truth.json``: the element-level parameters thermocal reads from the nominal and from the
  perturbed file (``construction/<name>/resistance`` [m2 K/W], ``zone/<name>/infiltration_ach``
  [1/h], ...).
"""

from __future__ import annotations

import gzip
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))
sys.path.insert(0, str(HERE.parent / "calibration_energyplus_5zone"))

from energyplus_twin import _class, _objects, make_twin_of  # noqa: E402
from make_reference import element_values, perturbed  # noqa: E402

IDF = ROOT / "tests" / "reference" / "identification_outpatient" / "outpatient_FF_v25.idf"
DAYS = 31
ENERGYPLUS_STEPS_PER_HOUR = 12
STEPS_PER_HOUR = 6  # the log's step, 10 minutes
SENSED = 87
INFILTRATION = 1.4
#: (IDF class, object name, field index, factor); the infiltration entries are per object
#: (:func:`perturbation`): 52 give a flow per exterior wall area (field 7), the 4 stair and
#: elevator shafts air changes per hour (field 8)
ENVELOPE = (
    ("material", "Steel Frame NonRes Wall Insulation", 4, 1.5),  # wall insulation: R / 1.5
    ("material", "IEAD NonRes Roof Insulation", 4, 0.6),  # roof insulation: R / 0.6
)


def perturbation(source: str) -> tuple:
    """:data:`ENVELOPE` and every infiltration object's design level x :data:`INFILTRATION`."""
    out = list(ENVELOPE)
    for obj in _objects(source):
        if _class(obj) == "zoneinfiltration:designflowrate":
            fields = [f.strip() for f in obj.split(",")]
            index = {"flow/exteriorwallarea": 7, "airchanges/hour": 8}[fields[4].lower()]
            out.append(("zoneinfiltration:designflowrate", fields[1], index, INFILTRATION))
    return tuple(out)


def main() -> None:
    source = IDF.read_text()
    hidden = perturbed(source, perturbation(source))
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        nominal = element_values(source, tmp)
        truth = element_values(hidden, tmp)
        twin = make_twin_of(
            hidden,
            tmp,
            DAYS,
            envelope=source,
            timesteps_per_hour=STEPS_PER_HOUR,
            energyplus_steps_per_hour=ENERGYPLUS_STEPS_PER_HOUR,
        )
    zones = list(twin.temperature.columns)
    rng = np.random.default_rng(1)
    sensed = set(rng.choice(zones, size=SENSED, replace=False).tolist())
    names = {z: f"T{i:03d}" for i, z in enumerate(zones) if z in sensed}
    log = twin.temperature[list(names)].round(2)
    log.index = log.index + (log.index[1] - log.index[0])  # stamped at the step's end
    log.index.name = "time"
    log = log.rename(columns=names)
    with gzip.open(HERE / "sensors.csv.gz", "wt", compresslevel=9) as fh:
        log.to_csv(fh, date_format="%Y-%m-%dT%H:%M:%S%z")
    hot = {}
    for zone in names:  # the hot rooms' own plausible range (as measure_identification.py)
        mean = float(twin.temperature[zone].mean())
        if not 5.0 < mean < 30.0:
            hot[zone] = [round(mean - 15, 1), round(mean + 15, 1)]
    (HERE / "mapping.yaml").write_text(
        "sensors:\n"
        + "".join(f'  {s}: "{z}"\n' for z, s in names.items())
        + ("zones:\n" + "".join(f'  "{z}": {{plausible: {r}}}\n' for z, r in hot.items()))
        + "identified_heat: {radiant_fraction: declared}\n"
    )
    changed = {k: truth[k] / nominal[k] for k in nominal if abs(truth[k] - nominal[k]) > 1e-9}
    (HERE / "truth.json").write_text(
        json.dumps(
            {
                "description": "DOE outpatient prototype, hidden envelope: "
                + ", ".join(f"{k} {n} field {i} x{f:.4g}" for k, n, i, f in ENVELOPE)
                + f", every ZoneInfiltration:DesignFlowRate's design level x{INFILTRATION:g}",
                "energyplus_steps_per_hour": ENERGYPLUS_STEPS_PER_HOUR,
                "sensor_step": "10min",
                "sensed": SENSED,
                "nominal": nominal,
                "truth": truth,
                "changed_ratio": changed,
            },
            indent=2,
        )
        + "\n"
    )
    print(json.dumps({k: round(v, 4) for k, v in changed.items()}, indent=1))


if __name__ == "__main__":
    main()
