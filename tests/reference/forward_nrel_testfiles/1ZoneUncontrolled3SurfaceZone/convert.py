"""1ZoneUncontrolled3SurfaceZone (NREL, Version 24.1) -> ``1ZoneUncontrolled3SurfaceZone_v25.idf``.

Run from anywhere: ``python tests/reference/forward_nrel_testfiles/1ZoneUncontrolled3SurfaceZone/
convert.py``. Edits (README.md): Version 25.2; the weather-file run of the reference period
instead of the design days; hourly zone air temperature as the only output. No HVAC in the file.
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import idftools as T  # noqa: E402

objs = T.split_objects((HERE / "orig_v241_trimmed.idf").read_text())
objs = T.free_float_reference(objs)
T.write(objs, HERE / "1ZoneUncontrolled3SurfaceZone_v25.idf",
        "! NREL/EnergyPlus testfiles/1ZoneUncontrolled3SurfaceZone.idf -> 25.2 "
        "(convert.py)\n")  # fmt: skip
