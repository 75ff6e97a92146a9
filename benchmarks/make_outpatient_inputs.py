"""Inputs a user would have for the DOE outpatient prototype (118 zones), for
``bench_identify_outpatient.py``: an EnergyPlus 25.2 free-float run of January at 5-minute steps
gives a sensor log of 87 of the 118 zones (drawn with seed 1 as in
``tests/reference/identification_outpatient/measure_identification.py``; the hot rooms get a
``plausible`` range in the mapping as there), a mapping YAML, the EPW and the IDF.

Run (EnergyPlus 25.2 needed, about a minute)::

    python benchmarks/make_outpatient_inputs.py [FOLDER] [--days 31]

Writes into FOLDER (default ``$TMPDIR/thermocal-bench-outpatient``): ``outpatient.idf`` (the
file without its loads: the envelope thermocal gets), ``outpatient_loads.idf`` (with them, for
``--radiant-fraction declared``), ``weather.epw``, ``sensors.csv``, ``mapping.yaml``,
``period.txt`` (start and end instants). Generated data: never committed.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

ROOT = Path(__file__).resolve().parents[1]
HERE = ROOT / "tests" / "reference" / "identification_outpatient"
sys.path.insert(0, str(ROOT / "tests" / "identification"))
DEFAULT = Path(tempfile.gettempdir()) / "thermocal-bench-outpatient"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("folder", nargs="?", type=Path, default=DEFAULT)
    parser.add_argument("--days", type=int, default=31)
    args = parser.parse_args(argv)
    from energyplus_twin import WEATHER_NAME, make_twin_of, sensor_log, twin_idf

    from thermocal.multizone.energyplus import energyplus_weather_folder

    folder = args.folder
    folder.mkdir(parents=True, exist_ok=True)
    source = (HERE / "outpatient_FF_v25.idf").read_text()
    (folder / "twin").mkdir(exist_ok=True)
    twin = make_twin_of(source, folder / "twin", args.days, timesteps_per_hour=12)
    zones = list(twin.temperature.columns)
    rng = np.random.default_rng(1)
    sensed = sorted(rng.choice(zones, size=87, replace=False).tolist())
    log, mapping = sensor_log(twin, sensed)
    for zone in sensed:  # the hot rooms' own plausible range (as measure_identification.py)
        mean = float(twin.temperature[zone].mean())
        if not 5.0 < mean < 30.0:
            mapping.setdefault("zones", {})[zone] = {"plausible": [mean - 15, mean + 15]}
    log.index.name = "time"
    log.to_csv(folder / "sensors.csv")
    (folder / "mapping.yaml").write_text(yaml.safe_dump(mapping, sort_keys=False))
    shutil.copy(folder / "twin" / "envelope.idf", folder / "outpatient.idf")
    (folder / "outpatient_loads.idf").write_text(twin_idf(source, args.days))
    shutil.copy(energyplus_weather_folder() / WEATHER_NAME, folder / "weather.epw")
    start = twin.start + pd.Timedelta("5min")  # as measure_identification.py
    (folder / "period.txt").write_text(f"{start.isoformat()}\n{twin.end.isoformat()}\n")
    print(f"wrote {folder}: {len(sensed)} sensors, {len(log)} steps, {twin.start} .. {twin.end}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
