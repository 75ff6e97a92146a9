"""The EnergyPlus twin of ``tests/test_identification_clockcheck.py``'s daylight-saving case.

NREL's ``InternalMass_wZoneList_v25.idf`` (``tests/reference/forward_nrel_testfiles``; three
zones) with an ideal-loads thermostat in every zone (21/24 C weekdays 7-18 h, 16/29 C else),
run by EnergyPlus 25.2 on Golden, CO (``USA_CO_Golden-NREL.724666_TMY3.epw``) from 9 July 2023
for 14 days at 5-minute steps. Writes, next to this file:

* ``user.idf``: what the user gives thermocal (the file, its thermostats and ideal loads, its
  RunPeriod);
* ``sensors.csv.gz``: the zone mean air temperatures EnergyPlus reports (the value at each
  step's end), stamped in local STANDARD time without a UTC offset (mountain standard time,
  the weather file's clock; a logger kept on standard time all year). Read with
  ``--tz America/Denver`` in July, every stamp is an hour early (found by an exploratory run,
  2026-12-01: the clock check's note contradicted itself and advised correcting a jump that
  was not there);
* ``mapping.yaml``: one sensor per zone.

python make_reference.py  (about a minute)
"""

from __future__ import annotations

import gzip
import sys
import tempfile
from pathlib import Path

import pandas as pd

HERE = Path(__file__).resolve().parent
TESTS = HERE.parents[1]
SOURCE = TESTS / "reference" / "forward_nrel_testfiles" / "InternalMass_wZoneList"
IDF_NAME = "InternalMass_wZoneList_v25.idf"
WEATHER_NAME = "USA_CO_Golden-NREL.724666_TMY3.epw"
BEGIN, DAYS, STEPS, YEAR = pd.Timestamp("2023-07-09"), 14, 12, 2023
HEAT, COOL, SETBACK = 21.0, 24.0, (16.0, 29.0)


def ideal_loads(zone: str, i: int) -> list[str]:
    """A dual-set-point thermostat and an ideal-loads system for ``zone``."""
    return [
        f"ZoneControl:Thermostat, Tstat {i}, {zone}, Dual SP Control, "
        f"ThermostatSetpoint:DualSetpoint, DualSP {i}",
        f"ThermostatSetpoint:DualSetpoint, DualSP {i}, HtgSP, ClgSP",
        f"ZoneHVAC:EquipmentConnections, {zone}, Equip {i}, Inlets {i}, , Zone Air Node {i}, "
        f"Zone Return {i}",
        f"ZoneHVAC:EquipmentList, Equip {i}, SequentialLoad, ZoneHVAC:IdealLoadsAirSystem, "
        f"Ideal {i}, 1, 1, , ",
        f"ZoneHVAC:IdealLoadsAirSystem, Ideal {i}, , Inlet {i}, , , 50, 13, 0.015, 0.009, "
        "NoLimit, , , NoLimit, , , , , ConstantSupplyHumidityRatio, , "
        "ConstantSupplyHumidityRatio",
        f"NodeList, Inlets {i}, Inlet {i}",
    ]


def user_idf(source: str) -> str:
    """The source IDF with its run period, steps and thermostats replaced."""
    sys.path.insert(0, str(TESTS / "identification"))
    try:
        from energyplus_twin import _class, _join, _objects, zone_names
    finally:
        sys.path.pop(0)
    drop = ("runperiod", "timestep", "output:variable", "output:meter", "simulationcontrol",
            "zonecontrol:thermostat", "thermostatsetpoint:dualsetpoint")  # fmt: skip
    objs = [obj for obj in _objects(source) if _class(obj) not in drop]
    end = BEGIN + pd.Timedelta(days=DAYS - 1)
    lo, hi = SETBACK
    objs += [
        "SimulationControl, No, No, No, No, Yes",
        f"RunPeriod, twin, {BEGIN.month}, {BEGIN.day}, {YEAR}, {end.month}, {end.day}, {YEAR}, "
        ", Yes, Yes, No, Yes, Yes",
        f"Timestep, {STEPS}",
        f"Schedule:Compact, HtgSP, Any Number, Through: 12/31, For: Weekdays, Until: 07:00, "
        f"{lo}, Until: 18:00, {HEAT}, Until: 24:00, {lo}, For: AllOtherDays, Until: 24:00, {lo}",
        f"Schedule:Compact, ClgSP, Any Number, Through: 12/31, For: Weekdays, Until: 07:00, "
        f"{hi}, Until: 18:00, {COOL}, Until: 24:00, {hi}, For: AllOtherDays, Until: 24:00, {hi}",
        "Schedule:Compact, Dual SP Control, Any Number, Through: 12/31, For: AllDays, "
        "Until: 24:00, 4",
    ]
    if not any(_class(o) == "scheduletypelimits" and o.split(",")[1].strip().lower()
               == "any number" for o in objs):  # fmt: skip
        objs.append("ScheduleTypeLimits, Any Number")
    for i, zone in enumerate(zone_names(source)):
        objs += ideal_loads(zone, i)
    return _join(objs)


def main() -> None:
    from thermocal.multizone.energyplus import energyplus_weather_folder, read_eso, run_energyplus

    sys.path.insert(0, str(TESTS / "identification"))
    try:
        from energyplus_twin import zone_names
    finally:
        sys.path.pop(0)
    source = (SOURCE / IDF_NAME).read_text()
    user = user_idf(source)
    (HERE / "user.idf").write_text(user)
    weather = energyplus_weather_folder() / WEATHER_NAME
    with tempfile.TemporaryDirectory() as tmp:
        twin = Path(tmp) / "twin.idf"
        twin.write_text(user + "Output:Variable, *, Zone Mean Air Temperature, Timestep;\n")
        frame = read_eso(run_energyplus(twin, weather, Path(tmp) / "eplus"), year=YEAR,
                         frequency="timestep")  # fmt: skip
    zones = zone_names(source)
    temp = pd.DataFrame({z: frame[f"{z.upper()}:Zone Mean Air Temperature [C]"] for z in zones})
    temp.index = temp.index + pd.Timedelta(hours=1) / STEPS  # the value at the step's end
    names = {z: "T_" + z.replace(" ", "_") for z in zones}
    log = temp.rename(columns=names).round(3)
    stamps = temp.index.tz_localize(None) if temp.index.tz is not None else temp.index
    log.insert(0, "time", [t.isoformat(sep=" ") for t in stamps])  # standard time, no offset
    with gzip.open(HERE / "sensors.csv.gz", "wt", newline="") as fh:
        log.to_csv(fh, index=False)
    (HERE / "mapping.yaml").write_text(
        "sensors:\n" + "".join(f"  {s}: {z}\n" for z, s in names.items())
    )


if __name__ == "__main__":
    main()
