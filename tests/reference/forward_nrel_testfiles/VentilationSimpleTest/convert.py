# ruff: noqa: E501 (transcribed IDF data, one object a line)
"""VentilationSimpleTest (NREL, Version 24.1) -> ``VentilationSimpleTest_FF_v25.idf``.

Run from anywhere: ``python tests/reference/forward_nrel_testfiles/VentilationSimpleTest/
convert.py``. The transcription of NREL/EnergyPlus ``testfiles/VentilationSimpleTest.idf``
(commit df504cf5ec0f9be8a280e18165e8e3c23260fe7e) is this script (survey of 2026-11-30,
``build_v25.py`` there): header, materials, schedules and zone objects with the file's values
(field comments and the three design days left out); ZONE 1's 16 walls, 8 windows, 7 zone shades,
floor and roof transcribed; ZONE 2 and ZONE 3 generated as ZONE 1 shifted by +100 m / +200 m in x,
which is what the file contains (checked on ZONE 2 walls 001-007, ZONE 3 walls 013-016, floor and
roof). Edits (README.md): Version 25.2 (the file already has ``Space Name``);
``ZoneVentilation:WindandStackOpenArea 'ZONE 3 Ventl 2'`` removed (thermocal refuses it, by name);
the weather-file run of the reference period instead of the design days; hourly zone air
temperature as the only output. No HVAC in the file: it is already free floating.
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import idftools as T  # noqa: E402

# fmt: off

head = """Version,25.2;
Timestep,4;
Building,BUILDING #1,0.0000000E+00,Suburbs,3.9999999E-02,0.4000000,FullExterior,25,6;
SurfaceConvectionAlgorithm:Inside,Simple;
SurfaceConvectionAlgorithm:Outside,SimpleCombined;
SimulationControl,No,No,No,Yes,No,No,1;
RunPeriod,Run Period 1,1,1,,12,31,,Tuesday,Yes,Yes,No,Yes,Yes;
Site:Location,HILO_HI_USA TMY2-21504,19.72,-155.07,-10.00,11.00;
Material,A2 - 4 IN DENSE FACE BRICK,Rough,0.1014984,1.245296,2082.400,920.4800,0.9000000,0.9300000,0.9300000;
Material,B3 - 2 IN INSULATION,VeryRough,5.0901599E-02,4.3239430E-02,32.03693,836.8000,0.9000000,0.5000000,0.5000000;
Material,C2 - 4 IN LW CONCRETE BLOCK,MediumRough,0.1014984,0.3805070,608.7016,836.8000,0.9000000,0.6500000,0.6500000;
Material,E1 - 3 / 4 IN PLASTER OR GYP BOARD,Smooth,1.9050000E-02,0.7264224,1601.846,836.8000,0.9000000,0.9200000,0.9200000;
WindowMaterial:Glazing,GLASS - CLEAR PLATE 1 / 4 IN,SpectralAverage,,6.0000001E-03,0.7750000,7.1000002E-02,7.1000002E-02,0.8810000,7.9999998E-02,7.9999998E-02,0.0000000E+00,0.8400000,0.8400000,0.9000000;
Material,DIRT 12 IN,Rough,0.3048000,0.1729577,1041.200,836.8000,0.9000000,0.7000000,0.7000000;
Material,CONCRETE - SAND AND GRAVEL 4 IN,MediumRough,0.1014984,1.729577,2242.585,836.8000,0.9000000,0.6000000,0.6000000;
Material,E2 - 1 / 2 IN SLAG OR STONE,Rough,1.2710161E-02,1.435549,881.0155,1673.600,0.9000000,0.5500000,0.5500000;
Material,E3 - 3 / 8 IN FELT AND MEMBRANE,Rough,9.5402403E-03,0.1902535,1121.292,1673.600,0.9000000,0.7500000,0.7500000;
Material,B6 - 2 IN DENSE INSULATION,VeryRough,5.0901599E-02,4.3239430E-02,91.30524,836.8000,0.9000000,0.5000000,0.5000000;
Material,C12 - 2 IN HW CONCRETE,MediumRough,5.0901599E-02,1.729577,2242.585,836.8000,0.9000000,0.6500000,0.6500000;
Construction,EXTERIOR,A2 - 4 IN DENSE FACE BRICK,B3 - 2 IN INSULATION,C2 - 4 IN LW CONCRETE BLOCK,E1 - 3 / 4 IN PLASTER OR GYP BOARD;
Construction,SINGLE PANE HW WINDOW,GLASS - CLEAR PLATE 1 / 4 IN;
Construction,SLAB FLOOR,DIRT 12 IN,CONCRETE - SAND AND GRAVEL 4 IN;
Construction,ROOF31,E2 - 1 / 2 IN SLAG OR STONE,E3 - 3 / 8 IN FELT AND MEMBRANE,B6 - 2 IN DENSE INSULATION,C12 - 2 IN HW CONCRETE;
ScheduleTypeLimits,Any Number;
ScheduleTypeLimits,Fraction,0.0,1.0,CONTINUOUS;
Schedule:Compact,Residence Occupancy,ANY NUMBER,Through: 12/31,For: Weekdays SummerDesignDay WinterDesignDay,Until: 7:00,1.00,Until: 8:00,0.50,Until: 15:00,0.30,Until: 16:00,0.40,Until: 17:00,0.70,Until: 24:00,1.00,For: Weekends Holidays CustomDay1 CustomDay2,Until: 9:00,1.00,Until: 16:00,0.30,Until: 23:00,0.70,Until: 24:00,1.00;
Schedule:Compact,Residence Lighting,ANY NUMBER,Through: 12/31,For: Weekdays SummerDesignDay WinterDesignDay,Until: 6:00,0.10,Until: 8:00,0.20,Until: 16:00,0.10,Until: 17:00,0.20,Until: 19:00,0.50,Until: 22:00,1.00,Until: 23:00,0.50,Until: 24:00,0.30,For: Weekends Holidays CustomDay1 CustomDay2,Until: 16:00,0.10,Until: 18:00,0.50,Until: 22:00,1.00,Until: 23:00,0.50,Until: 24:00,0.30;
Schedule:Compact,Constant,ANY NUMBER,Through: 12/31,For: Alldays,Until: 24:00,1.00;
Schedule:Compact,ACTIVITY LVL   1,ANY NUMBER,Through: 12/31,For: Alldays,Until: 24:00,130.00;
Schedule:Compact,SHADINGTRANSMITTANCE:0001,FRACTION,Through: 12/31,For: Alldays,Until: 24:00,0.00;
Site:GroundTemperature:BuildingSurface,1.90000000E+01,1.90000000E+01,1.90000000E+01,2.00000000E+01,2.20000000E+01,2.30000000E+01,2.40000000E+01,2.30000000E+01,2.20000000E+01,2.10000000E+01,2.00000000E+01,1.90000000E+01;
GlobalGeometryRules,UpperLeftCorner,CounterClockWise,World,,World;
"""
def gains(z):
    return f"""People,ZONE {z} People 1,ZONE {z},Residence Occupancy,people,4.000000,,,0.6000000,,Activity Lvl   1;
Lights,ZONE {z} Lights 1,ZONE {z},Residence Lighting,LightingLevel,950.0000,,,0.0000000E+00,0.4000000,0.2000000,0.0000000E+00,GeneralLights;
ElectricEquipment,ZONE {z} ElecEq 1,ZONE {z},Residence Lighting,EquipmentLevel,480.0000,,,0.0000000E+00,0.3000000,0.0000000E+00;
"""
zones = {
 1: ("1.980000", "ZoneVentilation:DesignFlowRate,ZONE 1 Ventl 1,ZONE 1,Constant,flow/zone,6.131944,,,,NATURAL,0.0,1.0,0.6060000,0.03636,0.1177,0,18.0,,,,1.0;\n"),
 2: ("101.980000", "ZoneVentilation:DesignFlowRate,ZONE 2 Ventl 1,ZONE 2,Constant,flow/zone,6.131944,,,,INTAKE,400.0,0.9,0,0,0.224,0,18.0,,,,1.0;\n"),
 3: ("201.980000", "ZoneVentilation:DesignFlowRate,ZONE 3 Ventl 1,ZONE 3,Constant,flow/zone,6.131944,,,,EXHAUST,400.0,0.8,1,0,0,0,18.0,,,,1.0;\n"
                  "ZoneVentilation:WindandStackOpenArea,ZONE 3 Ventl 2,ZONE 3,0.5,Constant,0.2,0.0,1.0,0.5,18.0,,,,1.0;\n"),
}
# ZONE 1 walls: (x1,y1)->(x2,y2), height 0..10; window on it: (xa, xb, zbot, ztop) [all on x-parallel walls]; shade (list of 4 xyz)
walls = [
 ((1.98,5.98),(7.28,5.98),(3.08,6.08,2.6,7.6),[(3.08,2.98,8.0),(3.08,5.98,8.0),(6.08,5.98,8.0),(6.08,2.98,8.0)]),
 ((7.28,5.98),(7.28,8.98),None,None),
 ((7.28,8.98),(12.88,8.98),(8.58,11.58,2.5,7.5),[(8.58,5.98,7.9),(8.58,8.98,7.9),(11.58,8.98,7.9),(11.58,5.98,7.9)]),
 ((12.88,8.98),(12.88,4.58),None,None),
 ((12.88,4.58),(18.18,4.58),(14.08,17.08,2.1,7.1),[(14.08,1.58,7.5),(14.08,4.58,7.5),(17.08,4.58,7.5),(17.08,1.58,7.5)]),
 ((18.18,4.58),(18.18,8.08),None,None),
 ((18.18,8.08),(24.08,8.08),(19.58,22.58,2.2,7.2),[(19.58,5.08,7.6),(19.58,8.08,7.6),(22.58,8.08,7.6),(22.58,5.08,7.6)]),
 ((24.08,8.08),(24.08,5.08),None,None),
 ((24.08,5.08),(30.08,5.08),(25.58,28.58,2.2,7.2),[(25.58,2.08,7.7),(25.58,5.08,7.7),(28.58,5.08,7.7),(28.58,2.08,7.7)]),
 ((30.08,5.08),(30.08,10.28),None,None),
 ((30.08,10.28),(35.38,10.28),(30.98,33.98,2.2,7.2),[(30.98,7.28,7.6),(30.98,10.28,7.6),(33.98,10.28,7.6),(33.98,7.28,7.6)]),
 ((35.38,10.28),(35.38,7.48),None,None),
 ((35.38,7.48),(41.48,7.48),(36.88,39.88,2.2,7.2),[(36.88,4.48,7.6),(36.88,7.48,7.6),(39.88,7.48,7.6),(39.88,4.48,7.6)]),
 ((41.48,7.48),(41.48,18.38),None,None),
 ((41.48,18.38),(1.98,18.38),(40.88,4.88,4.5,7.5),None),
 ((1.98,18.38),(1.98,5.98),None,None),
]
floor = [(1.98,5.98),(1.98,18.38),(41.48,18.38),(41.48,7.48),(35.38,7.48),(35.38,10.28),(30.08,10.28),(30.08,5.08),(24.08,5.08),(24.08,8.08),(18.18,8.08),(18.18,4.58),(12.88,4.58),(12.88,8.98),(7.28,8.98),(7.28,5.98)]
roof = [(1.98,5.98),(7.28,5.98),(7.28,8.98),(12.88,8.98),(12.88,4.58),(18.18,4.58),(18.18,8.08),(24.08,8.08),(24.08,5.08),(30.08,5.08),(30.08,10.28),(35.38,10.28),(35.38,7.48),(41.48,7.48),(41.48,18.38),(1.98,18.38)]
def v(*p): return ",".join(f"{c:.6f}" for c in p)
out = [head]
for z, (xo, vent) in zones.items():
    dx = 100.0 * (z - 1)
    out.append(f"Zone,ZONE {z},0.0000000E+00,{xo},4.580000,0.0000000E+00,1,1,autocalculate,autocalculate;\n")
    out.append(gains(z))
    out.append(vent)
    for i, ((x1, y1), (x2, y2), win, shade) in enumerate(walls, 1):
        w = f"Zn00{z}:Wall{i:03d}"
        out.append(f"BuildingSurface:Detailed,{w},Wall,EXTERIOR,ZONE {z},,Outdoors,,SunExposed,WindExposed,0.5000000,4,"
                   f"{v(x1+dx,y1,10)},{v(x1+dx,y1,0)},{v(x2+dx,y2,0)},{v(x2+dx,y2,10)};\n")
        if win:
            xa, xb, zb, zt = win
            out.append(f"FenestrationSurface:Detailed,{w}:Win001,Window,SINGLE PANE HW WINDOW,{w},,0.5000000,,1.000000,4,"
                       f"{v(xa+dx,y1,zt)},{v(xa+dx,y1,zb)},{v(xb+dx,y1,zb)},{v(xb+dx,y1,zt)};\n")
        if shade:
            out.append(f"Shading:Zone:Detailed,{w}:Shade001,{w},ShadingTransmittance:0001,4," + ",".join(v(x+dx, y, zz) for x, y, zz in shade) + ";\n")
    out.append(f"BuildingSurface:Detailed,Zn00{z}:Flr001,Floor,SLAB FLOOR,ZONE {z},,Ground,,NoSun,NoWind,1.000000,autocalculate," + ",".join(v(x+dx, y, 0.0) for x, y in floor) + ";\n")
    out.append(f"BuildingSurface:Detailed,Zn00{z}:Roof001,Roof,ROOF31,ZONE {z},,Outdoors,,SunExposed,WindExposed,0.0000000E+00,autocalculate," + ",".join(v(x+dx, y, 10.0) for x, y in roof) + ";\n")
objs = T.split_objects("".join(out))
# thermocal refuses the stack and wind flow (it needs the zone temperature at every step)
objs, n = T.drop(objs, ["ZoneVentilation:WindandStackOpenArea"])
assert n == 1
objs = T.free_float_reference(objs)
T.write(objs, HERE / "VentilationSimpleTest_FF_v25.idf",
        "! NREL/EnergyPlus testfiles/VentilationSimpleTest.idf -> 25.2 (convert.py)\n")  # fmt: skip
