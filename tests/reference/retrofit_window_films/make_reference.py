"""How a window's rated U-value compares with its conduction in EnergyPlus 25.2, before and after
the windows measure of the two EnergyPlus retrofit twins (issue 25).

Run from the repository root (EnergyPlus 25.2 and the shared Zurich weather; about 20 s)::

    PYTHONPATH=src python tests/reference/retrofit_window_films/make_reference.py \
        ../shared/data/weather_switzerland/Zuerich-SMA_2015.epw

A room of 5 x 5 x 3 m whose faces are adiabatic but the north wall, which holds one window of
2 x 1.5 m; ideal loads hold 20 C; the weather is the Zurich file made steady as for the twins'
heat loss coefficients (``retrofit_energyplus_house/make_reference.py: steady_weather``: 0 C
air, 3 m/s wind, 80 % RH, no sun, the sky at the air temperature), January 1-7 at 4 steps per
hour. The window's conductance is minus its mean ``Surface Window Net Heat Transfer Rate`` of
the last day over its area and the 20 K: its in-simulation U-value, with EnergyPlus's films
(TARP inside, DOE-2 outside at the window's wind), not the rating's. Glazings:

- ``nrel_double_clear``: the first twin's ``Dbl Clr 3mm/6mm Air`` (NREL SingleFamilyHouse,
  layered; the twin's building file describes it with 3.23 W/(m2 K), the file's comment);
- ``doe_simple_1_70``: the second twin's ``WindowMaterial:SimpleGlazingSystem`` U 1.70, SHGC
  0.334 (DOE/PNNL prototype);
- ``measure_0_76``: the measure of both twins, ``SimpleGlazingSystem`` U 0.76, SHGC 0.50.

Writes ``window_films.json``: the rated U-values (the simple glazings' input; for the layered
one the twin's description, 3.23) and per glazing the in-simulation U-value, the indoor
temperature and the outside convection coefficient [W/(m2 K)].
"""

from __future__ import annotations

import importlib.util
import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]

GLAZING = {
    "nrel_double_clear": (
        "WindowMaterial:Glazing, CLEAR 3MM, SpectralAverage, , 0.003, 0.837, 0.075, 0.075, "
        "0.898, 0.081, 0.081, 0.0, 0.84, 0.84, 0.9;\n"
        "WindowMaterial:Gas, AIR 6MM, AIR, 0.006;\n"
        "Construction, GLAZING, CLEAR 3MM, AIR 6MM, CLEAR 3MM;\n"
    ),
    "doe_simple_1_70": (
        "WindowMaterial:SimpleGlazingSystem, SIMPLE, 1.70358, 0.3344;\n"
        "Construction, GLAZING, SIMPLE;\n"
    ),
    "measure_0_76": (
        "WindowMaterial:SimpleGlazingSystem, SIMPLE, 0.76, 0.50;\nConstruction, GLAZING, SIMPLE;\n"
    ),
}
#: The rated U-values [W/(m2 K)] the twins' building files and measures give.
RATED = {"nrel_double_clear": 3.23, "doe_simple_1_70": 1.70358, "measure_0_76": 0.76}
AREA, INDOOR = 3.0, 20.0


def _house_script():
    path = ROOT / "tests" / "reference" / "retrofit_energyplus_house" / "make_reference.py"
    spec = importlib.util.spec_from_file_location("make_reference_house", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _surface(name, kind, construction, boundary, vertices, sun="NoSun", wind="NoWind"):
    coords = ", ".join(f"{x}, {y}, {z}" for x, y, z in vertices)
    return (
        f"BuildingSurface:Detailed, {name}, {kind}, {construction}, ROOM, , {boundary}, , "
        f"{sun}, {wind}, autocalculate, 4, {coords};\n"
    )


def room_idf(glazing: str) -> str:
    """The room with one north window of ``glazing`` (IDF text of its materials and a
    ``Construction, GLAZING``)."""
    b = "Adiabatic"
    surfaces = [
        _surface("N", "Wall", "WALL", "Outdoors", [(5, 5, 3), (5, 5, 0), (0, 5, 0), (0, 5, 3)],
                 "SunExposed", "WindExposed"),  # fmt: skip
        _surface("S", "Wall", "WALL", b, [(0, 0, 3), (0, 0, 0), (5, 0, 0), (5, 0, 3)]),
        _surface("E", "Wall", "WALL", b, [(5, 0, 3), (5, 0, 0), (5, 5, 0), (5, 5, 3)]),
        _surface("W", "Wall", "WALL", b, [(0, 5, 3), (0, 5, 0), (0, 0, 0), (0, 0, 3)]),
        _surface("F", "Floor", "WALL", b, [(0, 0, 0), (0, 5, 0), (5, 5, 0), (5, 0, 0)]),
        _surface("C", "Roof", "WALL", b, [(0, 5, 3), (0, 0, 3), (5, 0, 3), (5, 5, 3)]),
    ]
    return (
        "Version, 25.2;\n"
        "Building, ROOM, 0, Suburbs, 0.04, 0.4, FullExterior, 25, 6;\n"
        "Timestep, 4;\n"
        "SurfaceConvectionAlgorithm:Inside, TARP;\nSurfaceConvectionAlgorithm:Outside, DOE-2;\n"
        "HeatBalanceAlgorithm, ConductionTransferFunction;\n"
        "SimulationControl, No, No, No, No, Yes;\n"
        "RunPeriod, R, 1, 1, 2015, 1, 7, 2015, Thursday, No, No, No, No, No;\n"
        "Site:Location, Zurich, 47.378, 8.567, 1.0, 556.0;\n"
        "GlobalGeometryRules, UpperLeftCorner, Counterclockwise, Relative;\n"
        "Material, BOARD, MediumRough, 0.2, 0.5, 800, 1000;\n"
        "Construction, WALL, BOARD;\n"
        + glazing
        + "Zone, ROOM;\n"
        + "".join(surfaces)
        + "FenestrationSurface:Detailed, WIN, Window, GLAZING, N, , autocalculate, , 1, 4, "
        "3.5, 5, 2.25, 3.5, 5, 0.75, 1.5, 5, 0.75, 1.5, 5, 2.25;\n"
        "ScheduleTypeLimits, Temperature, -60, 200, CONTINUOUS, Temperature;\n"
        "ScheduleTypeLimits, Control Type, 0, 4, DISCRETE;\n"
        "Schedule:Compact, CONTROL, Control Type, Through: 12/31, For: AllDays, Until: 24:00, 1;\n"
        "Schedule:Compact, SETPOINT, Temperature, Through: 12/31, For: AllDays, Until: 24:00, "
        f"{INDOOR};\n"
        "ZoneControl:Thermostat, ROOM T, ROOM, CONTROL, ThermostatSetpoint:SingleHeating, HEAT;\n"
        "ThermostatSetpoint:SingleHeating, HEAT, SETPOINT;\n"
        "ZoneHVAC:EquipmentConnections, ROOM, ROOM EQ, ROOM INLETS, , ROOM AIR, ROOM RETURN;\n"
        "NodeList, ROOM INLETS, ROOM SUPPLY;\n"
        "ZoneHVAC:EquipmentList, ROOM EQ, SequentialLoad, ZoneHVAC:IdealLoadsAirSystem, "
        "ROOM IDEAL, 1, 1, , ;\n"
        "ZoneHVAC:IdealLoadsAirSystem, ROOM IDEAL, , ROOM SUPPLY, , , 50, 13, 0.015, 0.009, "
        "NoLimit, , , NoLimit, , , , , None, , None, , , None, NoEconomizer, None;\n"
        "Output:Variable, WIN, Surface Window Net Heat Transfer Rate, Timestep;\n"
        "Output:Variable, ROOM, Zone Mean Air Temperature, Timestep;\n"
        "Output:Variable, WIN, Surface Outside Face Convection Heat Transfer Coefficient, "
        "Timestep;\n"
    )


def main(weather: str) -> dict:
    from thermocal.multizone.energyplus import read_eso, run_energyplus

    house = _house_script()
    out = {"indoor_C": INDOOR, "window_area_m2": AREA, "rated_W_per_m2K": RATED, "glazings": {}}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        steady = house.steady_weather(Path(weather), tmp / "steady.epw")
        for name, glazing in GLAZING.items():
            work = tmp / name
            work.mkdir()
            (work / "in.idf").write_text(room_idf(glazing))
            eso = run_energyplus(work / "in.idf", steady, work)
            frame = read_eso(eso, year=2015, frequency="timestep")
            last = frame.iloc[-96:]
            keys = ("Window Net Heat", "Zone Mean Air", "Outside Face Convection")
            col = {k: next(c for c in frame.columns if k.lower() in c.lower()) for k in keys}
            net = float(last[col["Window Net Heat"]].mean())
            ti = float(last[col["Zone Mean Air"]].mean())
            out["glazings"][name] = {
                "in_simulation_W_per_m2K": -net / (AREA * (ti - 0.0)),
                "indoor_C": ti,
                "outside_convection_W_per_m2K": float(last[col["Outside Face Convection"]].mean()),
            }
    (HERE / "window_films.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1]), indent=1))
