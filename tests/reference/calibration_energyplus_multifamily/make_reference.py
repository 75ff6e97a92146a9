"""EnergyPlus 25.2 twin of the PNNL/DOE multifamily prototype with a hidden envelope.

Run from the repository root (EnergyPlus 25.2 needed, about a minute)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_multifamily/make_reference.py

The second building thermocal did not write (``tests/reference/identification_multifamily``:
20 zones, 18 flats on three storeys, a breezeway and a vented attic), with a second set of
hidden perturbations (:data:`PERTURBATION`): the wall insulation's resistance x1.5
(``wall_consol_layer`` conductivity / 1.5), the attic-floor insulation's x0.6
(``ceil_consol_layer`` conductivity / 0.6: the ceilings of the top flats) and every flat's
effective leakage area x1.4. EnergyPlus runs January at 10-minute steps (the identification
twin's step); its zone air temperatures, rounded to 0.01 K, are the sensor log (every zone
sensed). Writes ``sensors.csv.gz``, ``mapping.yaml`` and ``truth.json`` beside this script,
like ``../calibration_energyplus_5zone/make_reference.py``.
"""

from __future__ import annotations

import gzip
import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))
sys.path.insert(0, str(HERE.parent / "calibration_energyplus_5zone"))

from energyplus_twin import make_twin_of, without_loads  # noqa: E402
from make_reference import element_values, perturbed  # noqa: E402

IDF = ROOT / "tests" / "reference" / "identification_multifamily" / "multifamily_5A_FF_v25.idf"
DAYS = 31
STEPS_PER_HOUR = 6
PERTURBATION = (
    ("material", "wall_consol_layer", 4, 1 / 1.5),  # wall insulation: R x1.5
    ("material", "ceil_consol_layer", 4, 1 / 0.6),  # attic-floor insulation: R x0.6
    ("zoneinfiltration:effectiveleakagearea", None, 4, 1.4),  # leakage area x1.4
)


def main() -> None:
    source = IDF.read_text()
    hidden = perturbed(source, PERTURBATION)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        nominal = element_values(source, tmp)
        truth = element_values(hidden, tmp)
        twin = make_twin_of(
            hidden, tmp, DAYS, envelope=without_loads(source), timesteps_per_hour=STEPS_PER_HOUR
        )
    zones = list(twin.temperature.columns)
    log = twin.temperature.round(2)
    log.index = log.index + (log.index[1] - log.index[0])  # stamped at the step's end
    log.index.name = "time"
    names = {z: f"T{i:02d}" for i, z in enumerate(zones)}
    log = log.rename(columns=names)
    with gzip.open(HERE / "sensors.csv.gz", "wt", compresslevel=9) as fh:
        log.to_csv(fh, date_format="%Y-%m-%dT%H:%M:%S%z")
    (HERE / "mapping.yaml").write_text(
        "sensors:\n" + "".join(f"  {s}: {z}\n" for z, s in names.items())
    )
    changed = {k: truth[k] / nominal[k] for k in nominal if abs(truth[k] - nominal[k]) > 1e-9}
    (HERE / "truth.json").write_text(
        json.dumps(
            {
                "description": "multifamily prototype, hidden envelope: "
                + ", ".join(f"{k} {n or 'all'} field {i} x{f:.4g}" for k, n, i, f in PERTURBATION),
                "energyplus_steps_per_hour": STEPS_PER_HOUR,
                "sensor_step": "10min",
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
