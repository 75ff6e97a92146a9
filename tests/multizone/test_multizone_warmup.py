"""The warm-up of a building imported from an IDF file follows the file's ``Building`` object as
EnergyPlus does: from 23 C, the first day repeated until no zone's daily maximum and minimum air
temperature moves by more than the Temperature Convergence Tolerance Value, at least
``warmup_days`` and at most the Maximum Number of Warmup Days times."""

from __future__ import annotations

import warnings

from test_multizone_idf import BOX
from test_multizone_network import constant_weather

from thermocal.multizone.idf import IdfImportWarning, read_idf
from thermocal.multizone.simulation import ENERGYPLUS_INITIAL_TEMPERATURE, Simulation

#: a heavy room (40 m2 of 0.3 m concrete inside) losing through one wall only: days to settle
HEAVY = """
Material,Heavy,Rough,0.3,1.4,2300,900,0.9,0.6,0.6;
Construction,Mass,Heavy;
InternalMass,IM,Mass,Z1,,40;
"""


def _box(tmp_path, building_fields: str, name: str):
    text = BOX.format(extra=HEAVY, north=0, zone_north=0, ox=0, oy=0, volume="autocalculate")
    text = text.replace("Building,Box,0;", f"Building,Box,0{building_fields};")
    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        return read_idf(path)


def test_warm_up_follows_the_building_objects_rule(tmp_path):
    weather, meta = constant_weather(days=3)
    loose = _box(tmp_path, ",City,0.04,0.4,FullExterior,25,1", "loose.idf")
    tight = _box(tmp_path, ",City,0.04,0.001,FullExterior,40,1", "tight.idf")
    capped = _box(tmp_path, ",City,0.04,0.001,FullExterior,12,1", "capped.idf")
    assert loose.idf_info.warmup == {"tolerance_K": 0.4, "maximum_days": 25, "minimum_days": 1}
    runs, state = {}, {}
    for label, building in (("loose", loose), ("tight", tight), ("capped", capped)):
        sim = Simulation(building, weather, meta, step="1h", store_surfaces=False)
        assert sim.initial_temperature == ENERGYPLUS_INITIAL_TEMPERATURE
        runs[label] = sim.warmup_days_run
        state[label] = sim.run(free_float=True).air_temperature["Z1"].iloc[0]
    # 0.4 K a day is met after the least number of days (7) or a few more; 0.001 K later, and
    # not before a maximum of 12 days
    assert 7 <= runs["loose"] < runs["tight"] <= 40, runs
    assert runs["capped"] == 12, runs
    # the longer warm-up moved the heavy room further from its 23 C start
    assert abs(state["tight"] - state["loose"]) > 0.1, state


def test_defaults_when_the_building_object_leaves_them_blank(tmp_path):
    building = _box(tmp_path, "", "blank.idf")
    assert building.idf_info.warmup == {"tolerance_K": 0.4, "maximum_days": 25, "minimum_days": 1}
