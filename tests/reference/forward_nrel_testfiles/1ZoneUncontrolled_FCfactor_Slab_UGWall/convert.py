"""1ZoneUncontrolled_FCfactor_Slab_UGWall (NREL, Version 24.1) -> ``..._FCfactor_v25.idf``.

Run from anywhere: ``python tests/reference/forward_nrel_testfiles/
1ZoneUncontrolled_FCfactor_Slab_UGWall/convert.py``. Edits (README.md): Version 25.2; the
weather-file run of the reference period instead of the file's own settings; hourly zone air
temperature as the only output. No HVAC in the file (already free floating).
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import idftools as T  # noqa: E402

objs = T.split_objects((HERE / "orig_v241_trimmed.idf").read_text())
objs = T.free_float_reference(objs)
T.write(objs, HERE / "1ZoneUncontrolled_FCfactor_v25.idf",
        "! NREL/EnergyPlus testfiles/1ZoneUncontrolled_FCfactor_Slab_UGWall.idf -> 25.2 "
        "(convert.py)\n")  # fmt: skip
