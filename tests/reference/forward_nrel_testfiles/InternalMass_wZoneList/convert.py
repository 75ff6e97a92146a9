"""InternalMass_wZoneList (NREL, Version 9.6) -> ``InternalMass_wZoneList_v25.idf``.

Run from anywhere: ``python tests/reference/forward_nrel_testfiles/InternalMass_wZoneList/
convert.py``. Source: NREL/EnergyPlus ``testfiles/InternalMass_wZoneList.idf`` as vendored in
NREL/Spawn (commit ab07bde9bbd6913d755fc3e429c660bdc4aecc0d, ``energyplus/testfiles/``);
transcription ``orig_v96_trimmed.idf``. Edits (README.md): Version 25.2; People *Mean Radiant
Temperature Calculation Type* ``zoneaveraged`` -> ``EnclosureAveraged`` (the key was renamed in
22.1; 25.2 refuses the old one); the weather-file run of the reference period instead of the
design days (the file's two one-day RunPeriods dropped, ``RunPeriodControl:DaylightSavingTime``
kept); hourly zone air temperature as the only output. No HVAC in the file: it is already free
floating. Nothing else changes (BuildingSurface:Detailed of 9.6 already has ``Space Name``).
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import idftools as T  # noqa: E402

objs = T.split_objects((HERE / "orig_v96_trimmed.idf").read_text())
objs = T.free_float_reference(objs)
renamed = []


def _mrt(fields):
    """25.2: 'Mean Radiant Temperature Calculation Type' ZoneAveraged -> EnclosureAveraged."""
    assert fields[13].lower() == "zoneaveraged"
    renamed.append(fields[1])
    return fields[:13] + ["EnclosureAveraged"] + fields[14:]


objs = T.replace_fields(objs, "People", _mrt)
assert len(renamed) == 3
T.write(objs, HERE / "InternalMass_wZoneList_v25.idf",
        "! NREL/EnergyPlus testfiles/InternalMass_wZoneList.idf (via NREL/Spawn ab07bde9) -> 25.2 "
        "(convert.py)\n")  # fmt: skip
