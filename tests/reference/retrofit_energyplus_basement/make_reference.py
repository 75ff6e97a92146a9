"""EnergyPlus twin of the DOE/PNNL residential prototype with an unheated basement (issue 25).

The second independent house of the retrofit analysis (the first:
``tests/reference/retrofit_energyplus_house``, whose EnergyPlus helpers this script imports:
``_run``, ``_col``, ``steady_weather``, ``insulation_thickness``). Writes, beside this script:

- ``house_v25.idf``: the prototype converted to EnergyPlus 25.2 (README.md lists every edit);
- ``measurements.csv``: six weeks (2015-02-02 .. 2015-03-15, hourly, interval START labels,
  local standard time): outdoor and indoor air temperature with 0.1 K noise, the heating from a
  heat meter with 2 % noise, DNI/DHI, and the electricity of lights and appliances as a meter
  shows it (2 % noise); ordinary thermostat (22.2 C, 19 C from 22:00 to 06:00);
- ``building.yaml`` and ``config.yaml``: what a user knows (areas, nominal ISO 6946 U-values of
  the constructions, the basement's depth, walls and floor; nothing from EnergyPlus results);
- ``reference.json``: the steady-state heat loss coefficient, the annual heating at a constant
  22.2 C (Zurich 2015) of the house and of the 16 strategies (layers added in EnergyPlus to
  reach the measures' U-values), and the basement's temperature and ground heat flows.

Source: ``buildings/single_5A_gas_unheated.idf`` of sustainable-computing/COBS (commit
bd134e490d172ad014020f38f8e813ceac77b76d, MIT licence), the DOE/PNNL residential single-family
prototype (IECC 2018, climate zone 5A, gas furnace, unheated basement), EnergyPlus 8.6. Run::

    python tests/reference/retrofit_energyplus_basement/make_reference.py SOURCE.idf \
        /work/shared/data/weather_switzerland/Zuerich-SMA_2015.epw

where SOURCE.idf is ``git -C COBS show bd134e4:buildings/single_5A_gas_unheated.idf``
(about 5 minutes on 2 cores). ``--ground`` adds the basement study (``ground_study.json``).
``WEATHER.epw --config-only`` rewrites ``config.yaml`` alone from the committed ``house_v25.idf``
(no EnergyPlus run): the retrofit configuration, with the occupants the file's ``People`` object
counts.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from concurrent.futures import ThreadPoolExecutor
from itertools import combinations
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from thermocal.multizone.idf.parse import parse_idf

HERE = Path(__file__).resolve().parent


def _first_twin():
    """The first twin's script (its EnergyPlus helpers), loaded from its file."""
    path = HERE.parent / "retrofit_energyplus_house" / "make_reference.py"
    spec = importlib.util.spec_from_file_location("retrofit_energyplus_house_reference", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


house1 = _first_twin()

YEAR = 2015
SETPOINT = 22.22  # the file's heating set point (IECC 2009), C
SETBACK = 19.0
PERIOD = ("2015-02-02 00:00", "2015-03-15 23:00")
LIVING, ATTIC, BASEMENT = "living_unit1", "attic_unit1", "unheatedbsmt_unit1"
FOUNDATION_NAME = "Basement Foundation"

# ---------------------------------------------------------------------------------------------
# conversion 8.6 -> 25.2: explicit field edits, checked against the payload's Energy+.idd
# ---------------------------------------------------------------------------------------------
#: classes kept (with the edits of :func:`_convert`); everything else (HVAC, DHW, sizing, design
#: days, ground preprocessors, outputs, curves, exterior lights) is dropped
KEEP = {
    "ZONE", "BUILDINGSURFACE:DETAILED", "WINDOW", "DOOR", "SHADING:OVERHANG", "INTERNALMASS",
    "PEOPLE", "LIGHTS", "ELECTRICEQUIPMENT", "GASEQUIPMENT",
    "ZONEINFILTRATION:EFFECTIVELEAKAGEAREA", "ZONEVENTILATION:DESIGNFLOWRATE",
    "GLOBALGEOMETRYRULES", "SURFACECONVECTIONALGORITHM:INSIDE", "TIMESTEP", "SCHEDULETYPELIMITS",
}  # fmt: skip
#: kept only when referenced by a kept object (transitively)
REFERENCED = {
    "MATERIAL", "MATERIAL:NOMASS", "MATERIAL:AIRGAP", "WINDOWMATERIAL:SIMPLEGLAZINGSYSTEM",
    "CONSTRUCTION", "SCHEDULE:COMPACT", "SCHEDULE:CONSTANT", "SCHEDULE:YEAR",
    "SCHEDULE:WEEK:COMPACT", "SCHEDULE:DAY:HOURLY",
}  # fmt: skip
GAIN_CLASSES = {"PEOPLE", "LIGHTS", "ELECTRICEQUIPMENT", "GASEQUIPMENT"}
#: below-grade surfaces: "Ground" (the 8.6 preprocessors) -> Kiva
BELOW_GRADE = {
    "BGWall_lower_ldf", "BGWall_lower_sdr", "BGWall_lower_ldb", "BGWall_lower_sdl",
    "Extfloor_unit1",
}  # fmt: skip
#: the file's 1 mm walls between grade (z = 0) and the living floor (z = 0.001): degenerate
#: for 25.2 (collinear vertices); the below-grade walls are extended to z = 0.001 instead
ABOVE_GRADE_STRIPS = {
    "BGWall_upper_ldf",
    "BGWall_upper_sdr",
    "BGWall_upper_ldb",
    "BGWall_upper_sdl",
}


def _convert(obj) -> tuple[str, list[str]] | None:
    """One 8.6 object as (class, 25.2 fields), None when dropped."""
    f = list(obj.fields)
    key = obj.key
    if key == "BUILDINGSURFACE:DETAILED":
        if f[0] in ABOVE_GRADE_STRIPS:
            return None
        f.insert(4, "")  # 25.2: Space Name after Zone Name
        if f[0] in BELOW_GRADE:
            f[5], f[6] = "Foundation", FOUNDATION_NAME  # was Ground (+ preprocessor)
            if f[1] == "Wall":  # up to the living floor (z = 0.001) instead of z = 0
                f[11:] = ["0.001" if abs(float(v)) < 1e-9 and i % 3 == 2 else v
                          for i, v in enumerate(f[11:])]  # fmt: skip
    elif key in ("WINDOW",):
        del f[3]  # 8.6 Shading Control Name (interior blinds, schedule 0 all year) -> gone
    elif key == "INTERNALMASS":
        f.insert(3, "")  # 25.2: Space or SpaceList Name
    elif key == "PEOPLE":
        f[12] = "EnclosureAveraged" if f[12].lower() == "zoneaveraged" else f[12]
    return obj.class_name, f


def _text(cls: str, fields: list[str]) -> str:
    return f"{cls},\n  " + ",\n  ".join(fields) + ";\n"


def source_objects(source: Path):
    return parse_idf(Path(source).read_text(), source=str(source))


def converted(objects, *, gains: bool = True) -> list[tuple[str, list[str]]]:
    """The kept objects converted to 25.2 (and the materials, constructions, schedules they use)."""
    kept = [
        c
        for o in objects
        if o.key in KEEP and (gains or o.key not in GAIN_CLASSES)
        if (c := _convert(o)) is not None
    ]
    by_name = {}
    for o in objects:
        if o.key in REFERENCED:
            by_name.setdefault(o.name.upper(), o)
    refs = {v.upper() for _, fields in kept for v in fields}
    refs |= {"INTERIOR FLOOR", "EXTERIOR FLOOR", "INTERIOR CEILING", "EXTERIOR WALL", "GLASS"}
    chosen: dict[str, object] = {}
    while True:
        new = {n for n in refs if n in by_name and n not in chosen}
        if not new:
            break
        for n in new:
            chosen[n] = by_name[n]
            refs |= {v.upper() for v in by_name[n].fields[1:]}
    order = [o for o in objects if o.name.upper() in chosen and chosen[o.name.upper()] is o]
    return [(o.class_name, list(o.fields)) for o in order] + kept


# ---------------------------------------------------------------------------------------------
# nominal ISO 6946 U-values (what the user knows) from the file's layers
# ---------------------------------------------------------------------------------------------
RSI_HORIZONTAL, RSI_UP, RSI_DOWN, RSE = 0.13, 0.10, 0.17, 0.04


def layer_resistances(objects) -> dict[str, float]:
    out = {}
    for o in objects:
        if o.key == "MATERIAL":
            out[o.name] = float(o.fields[2]) / float(o.fields[3])
        elif o.key == "MATERIAL:NOMASS":
            out[o.name] = float(o.fields[2])
    return out


def constructions_of(objects) -> dict[str, list[str]]:
    return {o.name: list(o.fields[1:]) for o in objects if o.key == "CONSTRUCTION"}


def nominal_u_values(objects) -> dict[str, float]:
    r = layer_resistances(objects)
    cons = constructions_of(objects)

    def rl(name):
        return sum(r[m] for m in cons[name])

    glass = next(o for o in objects if o.key == "WINDOWMATERIAL:SIMPLEGLAZINGSYSTEM")
    return {
        "wall": 1.0 / (RSI_HORIZONTAL + rl("Exterior Wall") + RSE),
        # towards unheated spaces: Rsi on both sides (ISO 6946 Table 7 note)
        "attic_ceiling": 1.0 / (2 * RSI_UP + rl("Interior Ceiling")),
        "cellar_ceiling": 1.0 / (2 * RSI_DOWN + rl("Exterior Floor")),
        "door": 1.0 / (RSI_HORIZONTAL + rl("Exterior Door") + RSE),
        "basement_wall": 1.0 / (RSI_HORIZONTAL + rl("Basement Wall") + RSE),
        "basement_floor": 1.0 / (RSI_DOWN + rl("Interior Floor") + RSE),
        "window": float(glass.fields[1]),
        "window_g": float(glass.fields[2]),
    }


#: the measures: target U-values and the new glazing's g-value
MEASURES = {
    "attic_ceiling": {"u_value": 0.10, "cost_per_m2": 60},
    "walls": {"u_value": 0.19, "cost_per_m2": 250},
    "windows": {"u_value": 0.76, "g_value": 0.50, "cost_per_m2": 800},
    "cellar_ceiling": {"u_value": 0.12, "cost_per_m2": 80},
}
#: construction, position of the added layer (0 = outside / attic side / basement side)
MEASURE_LAYER = {
    "walls": ("Exterior Wall", 1, "wall"),  # behind the stucco (external insulation)
    "attic_ceiling": ("Interior Ceiling", 0, "attic_ceiling"),  # on the attic side
    "cellar_ceiling": ("Exterior Floor", 0, "cellar_ceiling"),  # under the floor
}


def with_measures(objs: list[tuple[str, list[str]]], measures, u_nominal) -> list:
    """Constructions with insulation layers (lambda 0.035) reaching the measures' U-values."""
    out = [(c, list(f)) for c, f in objs]
    extra = []
    for m in sorted(measures):
        if m == "windows":
            for c, f in out:
                if c.upper() == "WINDOWMATERIAL:SIMPLEGLAZINGSYSTEM" and f[0] == "Glass":
                    f[1], f[2] = str(MEASURES[m]["u_value"]), str(MEASURES[m]["g_value"])
            continue
        cons, pos, nominal = MEASURE_LAYER[m]
        d = house1.insulation_thickness(u_nominal[nominal], MEASURES[m]["u_value"])
        layer = f"{m.upper()} INSULATION"
        extra.append(("Material", [layer, "MediumRough", f"{d:.5f}", "0.035", "30", "1450",
                                   "0.9", "0.7", "0.7"]))  # fmt: skip
        for c, f in out:
            if c.upper() == "CONSTRUCTION" and f[0] == cons:
                f.insert(1 + pos, layer)
    return extra + out


def house_idf(
    source_objs,
    measures=frozenset(),
    *,
    setback: bool = False,
    gains: bool = True,
    foundation: str | None = None,
    extra: str = "",
) -> str:
    """The house as EnergyPlus 25.2 text (Zurich, 2015), with the measures applied."""
    u_nominal = nominal_u_values(source_objs)
    objs = with_measures(converted(source_objs, gains=gains), measures, u_nominal)
    if setback:
        heating = (
            "Schedule:Compact, HEATING SETPOINT 25, Temperature, Through: 12/31, For: AllDays, "
            f"Until: 6:00, {SETBACK}, Until: 22:00, {SETPOINT}, Until: 24:00, {SETBACK};\n"
        )
    else:
        heating = (
            "Schedule:Compact, HEATING SETPOINT 25, Temperature, Through: 12/31, For: AllDays, "
            f"Until: 24:00, {SETPOINT};\n"
        )
    if foundation is None:
        # the basement walls are the Foundation surfaces (their construction is Kiva's wall);
        # the file's walls reach grade (z = 0): no wall above grade; a basement without
        # thermostat needs an initial temperature. Fields: name, initial indoor temperature, the
        # ten insulation fields (blank: none), Wall Height Above Grade (the 13th field)
        foundation = f"Foundation:Kiva, {FOUNDATION_NAME}, 15, {', ' * 10}0.0;\n"
    text = [
        "Version, 25.2;\n",
        "Building, SF+CZ5A+gasfurnace+unheatedbsmt+IECC_2018 (COBS), 0, Suburbs, 0.04, 0.4, "
        "FullExterior, 25, 6;\n",
        "SurfaceConvectionAlgorithm:Outside, DOE-2;\n",
        "HeatBalanceAlgorithm, ConductionTransferFunction;\n",
        "SimulationControl, No, No, No, No, Yes;\n",
        f"RunPeriod, Year, 1, 1, {YEAR}, 12, 31, {YEAR}, , No, No, No, Yes, Yes;\n",
        "Site:Location, Zuerich-SMA, 47.378, 8.567, 1.0, 556.0;\n",
        "".join(_text(c, f) for c, f in objs),
        foundation,
        "SurfaceProperty:ExposedFoundationPerimeter, Extfloor_unit1, ExposedPerimeterFraction, "
        ", 1.0;\n",
        "ScheduleTypeLimits, Temperature 25, -60, 200, Continuous, Temperature;\n",
        "ScheduleTypeLimits, Control Type 25, 0, 4, Discrete;\n",
        heating,
        "Schedule:Compact, HEATING CONTROL 25, Control Type 25, Through: 12/31, For: AllDays, "
        "Until: 24:00, 1;\n",
        HVAC,
        OUTPUTS,
        extra,
    ]
    return "".join(text)


HVAC = f"""
ZoneControl:Thermostat, Living Thermostat, {LIVING}, HEATING CONTROL 25,
  ThermostatSetpoint:SingleHeating, Living Heating Setpoint;
ThermostatSetpoint:SingleHeating, Living Heating Setpoint, HEATING SETPOINT 25;
ZoneHVAC:EquipmentConnections, {LIVING}, Living Equipment, Living Inlets, , Living Air Node,
  Living Return Node;
NodeList, Living Inlets, Living Ideal Loads Supply Node;
ZoneHVAC:EquipmentList, Living Equipment, SequentialLoad, ZoneHVAC:IdealLoadsAirSystem,
  LIVING IDEAL LOADS, 1, 1, , ;
ZoneHVAC:IdealLoadsAirSystem, LIVING IDEAL LOADS, , Living Ideal Loads Supply Node, , , 50, 13,
  0.015, 0.009, NoLimit, , , NoLimit, , , , , None, , None, , , None, NoEconomizer, None;
"""

OUTPUTS = f"""
Output:Variable, {LIVING}, Zone Mean Air Temperature, Hourly;
Output:Variable, {ATTIC}, Zone Mean Air Temperature, Hourly;
Output:Variable, {BASEMENT}, Zone Mean Air Temperature, Hourly;
Output:Variable, LIVING IDEAL LOADS, Zone Ideal Loads Zone Sensible Heating Rate, Hourly;
Output:Variable, Environment, Site Outdoor Air Drybulb Temperature, Hourly;
Output:Variable, Environment, Site Direct Solar Radiation Rate per Area, Hourly;
Output:Variable, Environment, Site Diffuse Solar Radiation Rate per Area, Hourly;
Output:Variable, {LIVING}, Zone Lights Electricity Rate, Hourly;
Output:Variable, {LIVING}, Zone Electric Equipment Electricity Rate, Hourly;
Output:Variable, {LIVING}, Zone Gas Equipment Convective Heating Rate, Hourly;
Output:Variable, {LIVING}, Zone Gas Equipment Radiant Heating Rate, Hourly;
Output:Variable, {LIVING}, Zone People Sensible Heating Rate, Hourly;
Output:Variable, Floor_unit1, Surface Inside Face Conduction Heat Transfer Rate, Hourly;
"""

# geometry of the file (m): footprint, storey heights, windows, door
LENGTH, DEPTH = 12.1330909462833, 9.09981820971244
WALL_HEIGHT = 5.18392682926829 - 0.001  # two storeys, from z = 0.001
BASEMENT_DEPTH = 2.13314634146341
WINDOW_AREA = 2.24499173637174 * 1.52439024390244
DOOR_AREA = 1.74190122145513 * 2.13414634146341
BASEMENT_WALL_THICKNESS = 0.01905 * 2 + 0.1397


def building_description(source_objs) -> dict:
    """The building file a user would write: areas, orientations, nominal U-values."""
    u = nominal_u_values(source_objs)
    # facades: front (y = 0) faces south (north axis 0), right (x = L) east, back north, left west
    facades = {
        "south": (LENGTH, 180.0, 2, 0.0),
        "east": (DEPTH, 90.0, 2, 0.0),
        "north": (LENGTH, 0.0, 2, DOOR_AREA),
        "west": (DEPTH, 270.0, 2, 0.0),
    }
    comps = []
    for name, (length, az, n_win, door) in facades.items():
        comps.append({
            "name": f"{name} wall", "type": "external_wall",
            "area": round(length * WALL_HEIGHT - n_win * WINDOW_AREA - door, 2),
            "u_value": round(u["wall"], 4), "tilt": 90.0, "azimuth": az, "absorptance": 0.9,
        })  # fmt: skip
        comps.append({
            "name": f"{name} windows", "type": "window", "area": round(n_win * WINDOW_AREA, 2),
            "u_value": round(u["window"], 4), "tilt": 90.0, "azimuth": az,
            "g_value": round(u["window_g"], 4), "frame_fraction": 0.0, "shading_factor": 1.0,
        })  # fmt: skip
    comps.append({
        "name": "front door", "type": "door", "area": round(DOOR_AREA, 2),
        "u_value": round(u["door"], 4), "tilt": 90.0, "azimuth": 0.0,
    })  # fmt: skip
    comps.append({
        "name": "ceiling under the attic", "type": "attic_ceiling",
        "area": round(LENGTH * DEPTH, 2), "u_value": round(u["attic_ceiling"], 4),
    })  # fmt: skip
    comps.append({
        "name": "floor over the unheated basement", "type": "cellar_ceiling",
        "area": round(LENGTH * DEPTH, 2), "u_value": round(u["cellar_ceiling"], 4),
    })  # fmt: skip
    return {
        "name": "DOE/PNNL single-family prototype, 5A, unheated basement (EnergyPlus twin, Zurich)",
        "location": {"latitude": 47.378, "longitude": 8.567, "altitude": 556.0, "timezone": 1.0},
        "floors": 2,
        "heated_floor_area": round(2 * LENGTH * DEPTH, 2),
        "volume": round(LENGTH * DEPTH * WALL_HEIGHT, 1),
        "emitter": "convectors",
        "components": comps,
        "ground": {
            "perimeter": round(2 * (LENGTH + DEPTH), 2),
            "wall_thickness": round(BASEMENT_WALL_THICKNESS, 3),
            "basement": "unheated",
            "basement_depth": round(BASEMENT_DEPTH, 3),
            "basement_wall_height_above_ground": 0.0,
            "basement_wall_u_value": round(u["basement_wall"], 4),
            "basement_floor_u_value": round(u["basement_floor"], 4),
            "basement_volume": round(LENGTH * DEPTH * BASEMENT_DEPTH, 1),
        },
    }


def occupants(objects) -> int:
    """The number of people living in the house: the ``People`` object's count.

    What a user knows (not the file's schedule or activity level: thermocal's defaults, SIA
    380/1, stand for those); the file gives them as ``Number of People`` (method ``People``).
    """
    people = [o for o in objects if o.key == "PEOPLE"]
    if len(people) != 1 or people[0].fields[3].lower() != "people":
        raise ValueError("expected one People object with a number of people")
    return int(round(float(people[0].fields[4])))


def retrofit_config(weather: str, n_occupants: int) -> dict:
    """The retrofit configuration: the first twin's, with this house's measures, set point and
    occupants (the electricity meter as there; people and gas appliances are on no meter)."""
    cfg = house1.retrofit_config(weather)
    cfg["measures"] = MEASURES
    cfg["internal_gains"] = {
        "source": "electricity", "electricity_unit": "W", "occupants": n_occupants,
    }  # fmt: skip
    cfg["demand"] = {"indoor_profile": SETPOINT}
    return cfg


def write_config(weather: str, objects) -> None:
    """``config.yaml`` alone (the EnergyPlus results do not depend on it)."""
    (HERE / "config.yaml").write_text(
        "# written by make_reference.py; weather: the Zurich 2015 EPW of the shared test data\n"
        + yaml.safe_dump(retrofit_config(Path(weather).name, occupants(objects)), sort_keys=False)
    )


# ---------------------------------------------------------------------------------------------
# runs
# ---------------------------------------------------------------------------------------------
def strategy_keys() -> dict[str, frozenset]:
    names = list(MEASURES)
    combos = [frozenset()]
    for k in range(1, len(names) + 1):
        combos += [frozenset(c) for c in combinations(names, k)]
    return {("+".join(m for m in names if m in c) or "none"): c for c in combos}


def main(source: str, weather: str, work: str = "/tmp/retrofit_energyplus_basement") -> None:
    objs = source_objects(Path(source))
    weather, work = Path(weather), Path(work)
    rng = np.random.default_rng(20152)
    (HERE / "house_v25.idf").write_text(house_idf(objs))
    jobs = {"measurements": (house_idf(objs, setback=True), weather)}
    for key, c in strategy_keys().items():
        jobs[key] = (house_idf(objs, c), weather)
    work.mkdir(parents=True, exist_ok=True)
    steady = house1.steady_weather(weather, work / "steady.epw")
    jobs["steady"] = (house_idf(objs, gains=False), steady)
    with ThreadPoolExecutor(2) as pool:
        futures = {k: pool.submit(house1._run, idf, w, work / k) for k, (idf, w) in jobs.items()}
        results = {k: f.result() for k, f in futures.items()}
    col = house1._col

    df = results["measurements"].loc[PERIOD[0] : PERIOD[1]]
    n = len(df)
    heat = col(df, "Zone Ideal Loads Zone Sensible Heating Rate").to_numpy()
    elec = col(df, "Zone Lights Electricity Rate") + col(df, "Zone Electric Equipment Electricity")
    meas = pd.DataFrame(
        {
            "time": df.index.strftime("%Y-%m-%d %H:%M"),
            "Te": col(df, "Site Outdoor Air Drybulb").to_numpy() + rng.normal(0, 0.1, n),
            "Ti": col(df, f"{LIVING}:Zone Mean Air").to_numpy() + rng.normal(0, 0.1, n),
            "heat_W": heat * (1 + rng.normal(0, 0.02, n)),
            "DNI": col(df, "Direct Solar").to_numpy(),
            "DHI": col(df, "Diffuse Solar").to_numpy(),
            "electricity_W": elec.to_numpy() * (1 + rng.normal(0, 0.02, n)),
        }
    )
    meas.round(3).to_csv(HERE / "measurements.csv", index=False)

    annual = {}
    for key in strategy_keys():
        q = col(results[key], "Zone Ideal Loads Zone Sensible Heating Rate")
        annual[key] = float(q.sum() / 1000.0)
    st = results["steady"]
    q_last = col(st, "Zone Ideal Loads Zone Sensible Heating Rate").iloc[-24 * 7 :].mean()
    ti_last = col(st, f"{LIVING}:Zone Mean Air").iloc[-24 * 7 :].mean()
    tb_last = col(st, f"{BASEMENT}:Zone Mean Air").iloc[-24 * 7 :].mean()
    floor_last = -col(st, "FLOOR_UNIT1:Surface Inside Face Conduction").iloc[-24 * 7 :].mean()
    base = annual["none"]
    none = results["none"]
    heating_months = none.index.month.isin([1, 2, 3, 4, 10, 11, 12])

    def basement(df):
        tb = col(df, f"{BASEMENT}:Zone Mean Air")
        floor = -col(df, "FLOOR_UNIT1:Surface Inside Face Conduction")
        return {
            "basement_C_monthly": [round(float(v), 2) for v in tb.resample("MS").mean()],
            "cellar_ceiling_loss_kWh_oct_apr": float(floor[heating_months].sum() / 1000),
        }

    gas = col(none, "Gas Equipment Convective") + col(none, "Gas Equipment Radiant")
    reference = {
        "source": "sustainable-computing/COBS buildings/single_5A_gas_unheated.idf "
        "(bd134e490d172ad014020f38f8e813ceac77b76d, DOE/PNNL residential prototype, "
        "EnergyPlus 8.6), converted to 25.2 by make_reference.py",
        "weather": weather.name,
        "setpoint_C": SETPOINT,
        "heat_loss_coefficient_W_per_K": float(q_last / ti_last),
        "steady_state_run": {
            "outdoor_and_ground_C": 0.0,
            "indoor_C": float(ti_last),
            "heating_W": float(q_last),
            "basement_C": float(tb_last),
            "cellar_ceiling_W": float(floor_last),
        },
        "annual_heating_kWh": annual,
        "saving_pct": {k: 100.0 * (1 - v / base) for k, v in annual.items()},
        "basement": {k: basement(results[k]) for k in ("none", "cellar_ceiling")},
        "internal_gains_kWh": {
            "people_sensible": float(col(none, "People Sensible Heating").sum() / 1000),
            "lights": float(col(none, "Zone Lights Electricity").sum() / 1000),
            "electric_equipment": float(
                col(none, "Zone Electric Equipment Electricity").sum() / 1000
            ),
            "gas_equipment": float(gas.sum() / 1000),
        },  # fmt: skip
        "measures": MEASURES,
        "nominal_u_values": nominal_u_values(objs),
        "energyplus": "25.2",
    }
    (HERE / "reference.json").write_text(json.dumps(reference, indent=1) + "\n")
    (HERE / "building.yaml").write_text(
        "# written by make_reference.py: the house as a user describes it\n"
        + yaml.safe_dump(building_description(objs), sort_keys=False)
    )
    write_config(weather.name, objs)
    print(json.dumps({"hlc": reference["heat_loss_coefficient_W_per_K"], "annual": annual}))


def ground_study(source: str, weather: str, work: str = "/tmp/retrofit_energyplus_basement_g"):
    """Item 5 for a cellar: the cellar-ceiling path in Kiva against ISO 13370 (clause 9.4).

    Also each measure's steady change of the heat loss coefficient in EnergyPlus
    (``measure_delta_hlc_W_per_K``), to set beside the description's ``U A`` change.

    Steady state (a year of constant 0 C air and ground, no sun, no gains, 22.2 C inside) with
    Kiva's defaults (as the reference runs) and with a ``Foundation:Kiva:Settings`` object of
    soil 2.0 W/(m K) (ISO 13370's default), without and with the cellar-ceiling measure: the
    heat through the floor over the unheated basement (``Floor_unit1``'s inside-face
    conduction) and the basement temperature. Writes ``ground_study.json``.
    """
    objs = source_objects(Path(source))
    weather, work = Path(weather), Path(work)
    work.mkdir(parents=True, exist_ok=True)
    steady = house1.steady_weather(weather, work / "steady.epw")
    soil2 = "Foundation:Kiva:Settings, 2.0;\n"
    cellar = frozenset({"cellar_ceiling"})
    jobs = {
        "kiva_defaults": house_idf(objs, gains=False),
        "kiva_defaults_cellar_ceiling": house_idf(objs, cellar, gains=False),
        "soil2": house_idf(objs, gains=False, extra=soil2),
        "soil2_cellar_ceiling": house_idf(objs, cellar, gains=False, extra=soil2),
    }
    # each measure's steady effect on the heat loss coefficient (Kiva defaults, as the
    # reference runs), against the description's U A change
    for m in ("attic_ceiling", "walls", "windows"):
        jobs[f"kiva_defaults_{m}"] = house_idf(objs, frozenset({m}), gains=False)
    with ThreadPoolExecutor(2) as pool:
        futures = {k: pool.submit(house1._run, idf, steady, work / k) for k, idf in jobs.items()}
        res = {k: f.result() for k, f in futures.items()}
    col = house1._col
    out: dict = {"steady_state": {}}
    for k, df in res.items():
        last = df.iloc[-24 * 7 :]
        ti = col(last, f"{LIVING}:Zone Mean Air").mean()
        tb = col(last, f"{BASEMENT}:Zone Mean Air").mean()
        floor = -col(last, "FLOOR_UNIT1:Surface Inside Face Conduction").mean()
        out["steady_state"][k] = {
            "indoor_C": float(ti),
            "basement_C": float(tb),
            "cellar_ceiling_W": float(floor),
            "cellar_path_W_per_K": float(floor / ti),
            "heating_W": float(col(last, "Zone Ideal Loads Zone Sensible Heating").mean()),
        }
    hlc = {k: v["heating_W"] / v["indoor_C"] for k, v in out["steady_state"].items()}
    out["measure_delta_hlc_W_per_K"] = {
        m: hlc["kiva_defaults"] - hlc[f"kiva_defaults_{m}"]
        for m in ("attic_ceiling", "walls", "windows", "cellar_ceiling")
    }
    (HERE / "ground_study.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


#: The heat-flux plate: the back (north) wall of the ground floor, as on the first twin.
PLATE_SURFACE = "Wall_ldb_1.unit1"


def heat_flux_study(
    source: str, weather: str, work: str = "/tmp/retrofit_energyplus_basement_hfm"
) -> dict:
    """The first twin's in-situ wall measurement (``house1.heat_flux_study``) on this house:
    a plate on the north wall of the ground floor for the first two weeks of the measurement
    run, and the wall's air-to-air U in EnergyPlus at steady state. Writes
    ``heat_flux_north_wall.csv`` and ``heat_flux_reference.json``."""
    objs = source_objects(Path(source))
    weather, work = Path(weather), Path(work)
    work.mkdir(parents=True, exist_ok=True)
    steady = house1.steady_weather(weather, work / "steady.epw")
    outputs = house1.wall_outputs(PLATE_SURFACE)
    jobs = {
        "measurements": (house_idf(objs, setback=True, extra=outputs), weather),
        "steady": (house_idf(objs, gains=False, extra=outputs), steady),
    }
    with ThreadPoolExecutor(2) as pool:
        futures = {k: pool.submit(house1._run, idf, w, work / k) for k, (idf, w) in jobs.items()}
        res = {k: f.result() for k, f in futures.items()}
    wall_u = nominal_u_values(objs)["wall"]
    return house1.plate_study(res, PLATE_SURFACE, LIVING, 98692, wall_u, HERE)


if __name__ == "__main__":
    if "--config-only" in sys.argv:
        # the committed 25.2 house carries the source's People object unchanged
        write_config(sys.argv[1], source_objects(HERE / "house_v25.idf"))
    elif "--heat-flux" in sys.argv:
        args = [a for a in sys.argv[1:] if a != "--heat-flux"]
        print(json.dumps(heat_flux_study(*args), indent=1))
    elif "--ground" in sys.argv:
        args = [a for a in sys.argv[1:] if a != "--ground"]
        print(json.dumps(ground_study(*args), indent=1))
    else:
        main(*sys.argv[1:])
