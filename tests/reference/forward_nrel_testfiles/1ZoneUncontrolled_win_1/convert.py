"""1ZoneUncontrolled_win_1 (NREL, Version 9.3) -> ``1ZoneUncontrolled_win_1_layered_v25.idf``.

Run from anywhere: ``python tests/reference/forward_nrel_testfiles/1ZoneUncontrolled_win_1/
convert.py``. Edits (README.md): Version 25.2; a blank ``Space Name`` after ``Zone Name`` in the
``BuildingSurface:Detailed`` (new field since 9.6); ``Construction:WindowDataFile DoubleClear``
(thermocal refuses the class) replaced, for both engines, by the layered glazing its Window5 entry
describes: two 2.97 mm clear panes (Tsol 0.85, Rsol 0.08, Tvis 0.90, Rvis 0.08, IR emissivity 0.84,
conductivity 0.9 W/(m K)) around 12.7 mm of air, no frame or divider; the weather-file run of the
reference period instead of the design days; hourly zone air temperature as the only output.
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import idftools as T  # noqa: E402

objs = T.split_objects((HERE / "orig_v93_trimmed.idf").read_text())
objs = T.free_float_reference(objs)
# 25.2 BuildingSurface:Detailed has 'Space Name' after 'Zone Name'
objs = T.replace_fields(objs, "BuildingSurface:Detailed", lambda f: f[:5] + [""] + f[5:])
objs, n = T.drop(objs, ["Construction:WindowDataFile"])
assert n == 1
CLR_3 = ["CLR-3", "SpectralAverage", "", "0.00297", "0.85", "0.08", "0.08", "0.90", "0.08", "0.08",
         "0.0", "0.84", "0.84", "0.9"]  # fmt: skip
objs = T.add(objs, ["WindowMaterial:Glazing", *CLR_3])
objs = T.add(objs, ["WindowMaterial:Gas", "AIR-12.7", "Air", "0.0127"])
objs = T.add(objs, ["Construction", "DoubleClear", "CLR-3", "AIR-12.7", "CLR-3"])
T.write(objs, HERE / "1ZoneUncontrolled_win_1_layered_v25.idf",
        "! NREL/EnergyPlus testfiles/1ZoneUncontrolled_win_1.idf -> 25.2, DoubleClear layered "
        "(convert.py)\n")  # fmt: skip
