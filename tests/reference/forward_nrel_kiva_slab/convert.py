"""ZoneCoupledKivaSlab (NREL, Version 24.1) -> EnergyPlus 25.2 variants.

Run from anywhere: ``python tests/reference/forward_nrel_kiva_slab/convert.py [OUTDIR]``
(default: this folder). Writes ``ZoneCoupledKivaSlab_<variant>_v25.idf`` for every variant of
:data:`VARIANTS` (the folder keeps those the test uses: noins, ff_noins, adiabatic,
ff_adiabatic, and the file as it is, asis).

Edits common to all (no physical property changed in ``asis``):
- ``Version`` 24.1 -> 25.2 (the 24.1 file already has ``Space Name``; no field of its objects
  moved between 24.1 and 25.2, checked against the 25.2 Energy+.idd);
- ``SimulationControl`` for a weather-file run, one ``RunPeriod`` (January 1-31, 2023; the
  measurement script writes its own for each period; Begin Year 2023 in both engines);
- outputs replaced by hourly: zone air temperature, ideal-loads sensible heating and cooling
  rates, the floor's inside face temperature and inside face conduction rate, outdoor dry bulb.

Variants (the edits that define them):
- ``asis``: the file (ideal loads holding 20 C heating and 20 C cooling; 1" of insulation
  under the slab; 1" of exterior vertical insulation to 1.5 m on Kiva's default footing wall).
- ``noins``: the Foundation:Kiva's exterior vertical insulation removed (the block thermocal
  does not model).
- ``noins_wall``: ``noins`` with Kiva's default footing wall written out as a construction
  (0.3 m of concrete 1.95 W/(m K), 2400 kg/m3, 900 J/(kg K): KivaManager::defineDefaultFoundation);
  EnergyPlus must give ``noins``'s results.
- ``adiabatic``: the floor's boundary Adiabatic (Foundation:Kiva, its settings and the exposed
  perimeter removed).
- ``ff_*``: the same with the thermostat and the ideal loads removed (free float).
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "forward_nrel_testfiles"))  # idftools.py

import idftools as T  # noqa: E402

OUTPUTS = [
    ["Output:Variable", "*", "Zone Mean Air Temperature", "Hourly"],
    ["Output:Variable", "*", "Site Outdoor Air Drybulb Temperature", "Hourly"],
    ["Output:Variable", "*", "Zone Ideal Loads Zone Sensible Heating Rate", "Hourly"],
    ["Output:Variable", "*", "Zone Ideal Loads Zone Sensible Cooling Rate", "Hourly"],
    ["Output:Variable", "Zone Floor", "Surface Inside Face Temperature", "Hourly"],
    ["Output:Variable", "Zone Floor", "Surface Inside Face Conduction Heat Transfer Rate",
     "Hourly"],
]  # fmt: skip
HVAC = ["ZoneControl:Thermostat", "ThermostatSetpoint:DualSetpoint",
        "ZoneHVAC:EquipmentConnections", "ZoneHVAC:EquipmentList",
        "ZoneHVAC:IdealLoadsAirSystem"]  # fmt: skip
WALL = [
    ["Material", "Kiva Default Footing Wall Concrete", "MediumRough", "0.3", "1.95", "2400", "900",
     "0.9", "0.9", "0.9"],
    ["Construction", "Kiva Default Footing Wall", "Kiva Default Footing Wall Concrete"],
]  # fmt: skip


def base():
    objs = T.split_objects((HERE / "orig_v241_trimmed.idf").read_text())
    objs = T.replace_fields(objs, "Version", lambda f: ["Version", "25.2"])
    objs, _ = T.drop(objs, ["SimulationControl", "RunPeriod", *T.OUTPUT_CLASSES])
    objs = T.add(objs, ["SimulationControl", "No", "No", "No", "No", "Yes", "No", "1"])
    objs = T.add(objs, T.RUN_PERIOD[:1] + ["jan", "1", "1", "2023", "1", "31", "2023", "", "Yes",
                                           "Yes", "No", "Yes", "Yes"])  # fmt: skip
    for o in OUTPUTS:
        objs = T.add(objs, o)
    return objs


def no_ext_insulation(objs):
    def edit(f):
        f = f + [""] * (16 - len(f))
        f[11], f[12] = "", ""  # fields 10, 11 after the class name: material, depth
        return f

    return T.replace_fields(objs, "Foundation:Kiva", edit)


def explicit_wall(objs):
    def edit(f):
        f = f + [""] * (16 - len(f))
        f[15] = "Kiva Default Footing Wall"
        return f

    objs = T.replace_fields(objs, "Foundation:Kiva", edit)
    for w in WALL:
        objs = T.add(objs, w)
    return objs


def adiabatic(objs):
    def edit(f):
        if f[1].upper() == "ZONE FLOOR":
            f[6], f[7] = "Adiabatic", ""
        return f

    objs = T.replace_fields(objs, "BuildingSurface:Detailed", edit)
    objs, n = T.drop(objs, ["Foundation:Kiva", "Foundation:Kiva:Settings",
                            "SurfaceProperty:ExposedFoundationPerimeter"])  # fmt: skip
    assert n == 3
    return objs


def free_float(objs):
    objs, n = T.drop(objs, HVAC)
    assert n == len(HVAC)
    return objs


VARIANTS = {
    "asis": lambda o: o,
    "noins": no_ext_insulation,
    "noins_wall": lambda o: explicit_wall(no_ext_insulation(o)),
    "adiabatic": adiabatic,
}

def _free(fn):
    return lambda objs: free_float(fn(objs))


VARIANTS.update({f"ff_{k}": _free(v) for k, v in list(VARIANTS.items())})


def main(out: Path = HERE) -> dict:
    paths = {}
    for name, fn in VARIANTS.items():
        path = Path(out) / f"ZoneCoupledKivaSlab_{name}_v25.idf"
        T.write(fn(base()), path, "! NREL/EnergyPlus testfiles/ZoneCoupledKivaSlab.idf (commit "
                "0db13e02) -> 25.2, variant " + name + " (convert.py)\n")  # fmt: skip
        paths[name] = path
    return paths


if __name__ == "__main__":
    print(main(Path(sys.argv[1]) if len(sys.argv) > 1 else HERE))
