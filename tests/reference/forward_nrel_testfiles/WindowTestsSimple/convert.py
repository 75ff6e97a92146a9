"""WindowTestsSimple (NREL, Version 9.6) -> ``WindowTestsSimple_noShadingControl_v25.idf``.

Run from anywhere: ``python tests/reference/forward_nrel_testfiles/WindowTestsSimple/
convert.py``. Source: NREL/EnergyPlus ``testfiles/WindowTestsSimple.idf`` as vendored in
NREL/Spawn (commit ab07bde9bbd6913d755fc3e429c660bdc4aecc0d, ``energyplus/testfiles/``);
transcription ``orig_v96_trimmed.idf``. Edits (README.md): Version 25.2; the shading devices
removed, in both engines: the three ``WindowShadingControl`` (exterior screen on a schedule,
interior drapes and roller shade on high solar), the ``WindowMaterial:Screen``, the two
``WindowMaterial:Shade`` and the three shaded constructions that use them (thermocal refuses
window shading devices; the windows keep their bare ``...:no-shade`` SimpleGlazingSystem
constructions, which they name already); the weather-file run of the reference period instead
of the design days and the file's two month-long RunPeriods; hourly zone air temperature as the
only output (the file's tables, meters, dxf and variables dropped). No HVAC in the file.
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import idftools as T  # noqa: E402

SHADED = ("DOUBLE PANE WITH SCREEN", "DOUBLE PANE WITH DRAPES", "DOUBLE PANE WITH SHADE")

objs = T.split_objects((HERE / "orig_v96_trimmed.idf").read_text())
objs = T.free_float_reference(objs)
objs, n = T.drop(objs, ["WindowShadingControl", "WindowMaterial:Screen", "WindowMaterial:Shade"])
assert n == 6
before = len(objs)
objs = T.replace_fields(objs, "Construction", lambda f: None if f[1] in SHADED else f)
assert before - len(objs) == 3
T.write(objs, HERE / "WindowTestsSimple_noShadingControl_v25.idf",
        "! NREL/EnergyPlus testfiles/WindowTestsSimple.idf (via NREL/Spawn ab07bde9) -> 25.2, "
        "shading devices removed (convert.py)\n")  # fmt: skip
