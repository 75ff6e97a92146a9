"""C- and F-factor ground constructions of IDF files against EnergyPlus 25.2 (issue 28):
``Construction:FfactorGroundFloor`` and ``Construction:CfactorUndergroundWall`` become EnergyPlus'
equivalent constructions (a fictitious insulation layer without mass outside, 0.15 m of concrete
inside) facing ``Site:GroundTemperature:FCfactorMethod``.

Measured 2026-11-25 on the box below (10 x 10 x 3 m, F-factor slab, two C-factor walls, two
R-2.29 walls, 1.5 kW of gains, free float, Denver, January 1-14 at 15 min): before, the file was
refused ("Construction:CfactorUndergroundWall is not supported"); now hourly air temperature
RMSE 0.19 K, bias +0.16 K against EnergyPlus (bound 0.3 / 0.25 K); the fictitious resistances
equal those of EnergyPlus' eio file to its 4 digits. About 2 s.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pandas as pd
import pytest

from conftest import requires_energyplus
from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import IdfImportWarning, read_idf
from thermocal.multizone.idf.constructions import c_factor_resistance, f_factor_resistance

FC_BOX = """
Version,25.2;
Timestep,4;
Building,FC box,0,Suburbs,,,FullExterior,,6;
SimulationControl,No,No,No,No,Yes;
RunPeriod,Jan,1,1,2009,1,14,2009,Thursday,No,No,No,Yes,Yes;
Site:Location,Denver,39.76,-104.86,-7,1611;
SurfaceConvectionAlgorithm:Inside,TARP;
SurfaceConvectionAlgorithm:Outside,DOE-2;
GlobalGeometryRules,UpperLeftCorner,CounterClockWise,World;
Material:NoMass,R13,Rough,2.29,0.9,0.75,0.75;
Material:NoMass,R31,Rough,5.456,0.9,0.75,0.75;
Construction,R13WALL,R13;
Construction,ROOF31,R31;
Construction:CfactorUndergroundWall,UGWall1,0.436,3.0;
Construction:CfactorUndergroundWall,UGWall2,1.14,1.2;
Construction:FfactorGroundFloor,Slab,0.9,100,40;
Site:GroundTemperature:FCfactorMethod,0.5,-1.0,1.5,5.0,9.0,13.0,16.0,17.0,15.0,11.0,6.0,2.0;
{building_surface_ground}
Zone,Z,0,0,0,0,1,1,autocalculate,autocalculate;
BuildingSurface:Detailed,W1,Wall,UGWall1,Z,,GroundFCfactorMethod,,NoSun,NoWind,0,4,
  0,0,3,0,0,0,10,0,0,10,0,3;
BuildingSurface:Detailed,W2,Wall,UGWall2,Z,,GroundFCfactorMethod,,NoSun,NoWind,0,4,
  10,0,3,10,0,0,10,10,0,10,10,3;
BuildingSurface:Detailed,W3,Wall,R13WALL,Z,,Outdoors,,SunExposed,WindExposed,0.5,4,
  10,10,3,10,10,0,0,10,0,0,10,3;
BuildingSurface:Detailed,W4,Wall,R13WALL,Z,,{w4_boundary},,SunExposed,WindExposed,0.5,4,
  0,10,3,0,10,0,0,0,0,0,0,3;
BuildingSurface:Detailed,F,Floor,Slab,Z,,GroundFCfactorMethod,,NoSun,NoWind,0,4,
  10,0,0,0,0,0,0,10,0,10,10,0;
BuildingSurface:Detailed,R,Roof,ROOF31,Z,,Outdoors,,SunExposed,WindExposed,0,4,
  0,10,3,0,0,3,10,0,3,10,10,3;
OtherEquipment,Heat,None,Z,AlwaysOn,EquipmentLevel,1500,,,0,0.5,0;
Schedule:Constant,AlwaysOn,,1;
Output:Variable,*,Zone Mean Air Temperature,Hourly;
Output:Constructions,Constructions;
"""


def _box(tmp_path, building_surface_ground="", w4_boundary="Outdoors", name="fc.idf"):
    path = tmp_path / name
    path.write_text(
        FC_BOX.format(building_surface_ground=building_surface_ground, w4_boundary=w4_boundary)
    )
    return path


def _read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        return read_idf(path)


def test_fc_factor_resistances_as_energyplus():
    # EnergyPlus 25.2 eio, fictitious insulation of C = 1 W/(m2 K) walls by height, and of the
    # F-factor slab of FC_BOX [m2 K/W]
    for height, theirs in ((0.1, 1.043), (0.3, 1.088), (1.5, 1.506), (2.4, 1.819), (3.5, 1.843)):
        assert c_factor_resistance(1.0, height) == pytest.approx(theirs, abs=6e-4), height
    assert f_factor_resistance(0.9, 100.0, 40.0) == pytest.approx(2.536, abs=6e-4)
    assert f_factor_resistance(0.9, 100.0, 0.0) == pytest.approx(177.0 - 0.15 / 1.95)


def test_fc_factor_constructions_and_ground(tmp_path):
    building = _read(_box(tmp_path))
    slab = building.constructions["Slab"]
    assert slab.layers == ("Slab fictitious insulation", "C/F-factor concrete 0.15 m")
    assert building.materials["Slab fictitious insulation"].resistance == pytest.approx(
        f_factor_resistance(0.9, 100.0, 40.0)
    )
    concrete = building.materials["C/F-factor concrete 0.15 m"]
    assert (concrete.thickness, concrete.conductivity, concrete.density) == (0.15, 1.95, 2240.0)
    assert building.ground_temperatures[0] == 0.5 and building.ground_temperatures[7] == 17.0
    # a plain Ground surface beside them: one ground temperature per building, flagged
    mixed = _read(
        _box(
            tmp_path,
            "Site:GroundTemperature:BuildingSurface,18,18,18,18,18,18,18,18,18,18,18,18;",
            "Ground",
            name="mixed.idf",
        )
    )
    assert mixed.ground_temperatures == (18.0,) * 12
    assert any("one ground temperature per building" in n for n in mixed.idf_info.notes)


def test_f_factor_that_conducts_more_than_concrete_is_refused(tmp_path):
    path = _box(tmp_path)
    path.write_text(path.read_text().replace("Slab,0.9,100,40", "Slab,20,100,40"))
    with pytest.raises(ThermocalInputError, match=r"FfactorGroundFloor 'Slab'.*<= 0"):
        read_idf(path)


@requires_energyplus
def test_fc_factor_box_against_energyplus(tmp_path):
    from conftest import shared_data_path
    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import read_eso, run_energyplus
    from thermocal.multizone.simulation import Simulation

    weather_path = shared_data_path("ashrae140_bestest", "725650TYCST.epw")
    idf = _box(tmp_path)
    reference = read_eso(run_energyplus(idf, weather_path, tmp_path / "out"), year=2009)
    eio = (tmp_path / "out" / "eplusout.eio").read_text()
    theirs_r = [
        float(r) for r in re.findall(r"Material CTF Summary,~FC_Insulation_\d+,.*,(.*)", eio)
    ]
    building = _read(idf)
    ours_r = [
        building.materials[f"{c} fictitious insulation"].resistance
        for c in ("Slab", "UGWall1", "UGWall2")
    ]
    assert sorted(theirs_r) == pytest.approx(sorted(ours_r), abs=6e-4)
    weather, meta = read_weather(weather_path, coerce_year=2009)
    start = weather.index[0].normalize()
    result = Simulation(
        building,
        weather,
        meta,
        step="15min",
        end=start + np.timedelta64(14, "D"),
        store_surfaces=False,
    ).run()
    ours = result.air_temperature["Z"].resample("1h").mean().to_numpy()
    theirs = reference["Z:Zone Mean Air Temperature [C]"].to_numpy()
    assert len(ours) == len(theirs) == 336
    diff = ours - theirs
    rmse, bias = float(np.sqrt(np.mean(diff**2))), float(diff.mean())
    assert rmse < 0.3 and abs(bias) < 0.25, (rmse, bias)


def test_preprocessor_ground_boundary_is_noted(tmp_path):
    path = _box(tmp_path)
    path.write_text(
        path.read_text().replace(
            "Floor,Slab,Z,,GroundFCfactorMethod", "Floor,R13WALL,Z,,GroundSlabPreprocessorAverage"
        )
    )
    building = _read(path)
    notes = building.idf_info.report()["notes"]["ground"]
    assert any("1 surface(s) with the boundary GroundSlabPreprocessorAverage" in n for n in notes)
    assert building.surfaces["F"].boundary == "ground"


def test_ground_reflectance_as_energyplus_takes_it(tmp_path):
    """EnergyPlus reflects the sun off the ground with Site:GroundReflectance or 0.2, never with
    the weather file's albedo (Zurich 2015: up to 0.73 with snow): so does the imported model."""
    building = _read(_box(tmp_path))
    assert building.ground_reflectance == (0.2,) * 12
    monthly = ",".join(f"{0.1 + 0.05 * m:.2f}" for m in range(12))
    given = _read(_box(tmp_path, f"Site:GroundReflectance,{monthly};", name="r.idf"))
    assert given.ground_reflectance == pytest.approx([0.1 + 0.05 * m for m in range(12)])
    # kept in the building file (e.g. the calibrated building a retrofit runs on)
    from thermocal.multizone.files import building_from_dict, building_to_dict

    again = building_from_dict(building_to_dict(given))
    assert again.ground_reflectance == given.ground_reflectance
    bad = _box(tmp_path, "Site:GroundReflectance,0.2,0.2,1.4,0.2,0.2,0.2,0.2,0.2,0.2,0.2,0.2,0.2;")
    with pytest.raises(ThermocalInputError, match=r"ground_reflectance must be 12 monthly"):
        _read(bad)


def test_simulation_reflects_the_building_s_ground_reflectance(tmp_path):
    """The irradiance on a wall carries the building's ground reflectance, not the weather's
    albedo: on a vertical surface the ground-reflected part is rho * GHI / 2."""
    from thermocal.multizone.simulation import _ground_reflectance, _irradiance

    index = pd.date_range("2015-01-05 10:00", periods=4, freq="1h", tz="Etc/GMT-1")
    grid = pd.DataFrame(
        {
            "ghi": [300.0, 400.0, 350.0, 200.0],
            "dni": [500.0, 600.0, 550.0, 300.0],
            "dhi": [100.0, 120.0, 110.0, 90.0],
            "albedo": [0.73] * 4,
            "temp_air": [0.0] * 4,
        },
        index=index,
    )
    site = {"latitude": 47.4, "longitude": 8.5, "altitude": 556.0}
    orientation = (90.0, 180.0)
    monthly = (0.2,) * 12
    ours = _irradiance(
        grid, site, [orientation], "isotropic", albedo=_ground_reflectance(grid, monthly)
    )[orientation]
    weather = _irradiance(
        grid, site, [orientation], "isotropic", albedo=_ground_reflectance(grid, None)
    )[orientation]
    ghi = grid["ghi"].to_numpy()
    assert ours["poa_ground_diffuse"] == pytest.approx(0.2 * ghi / 2, rel=1e-6)
    assert weather["poa_ground_diffuse"] == pytest.approx(0.73 * ghi / 2, rel=1e-6)


@requires_energyplus
def test_entered_ceiling_height_gives_the_volume_as_in_energyplus(tmp_path):
    """A Zone with its Ceiling Height entered and its Volume blank: EnergyPlus takes floor area
    x height (Case 600, 48 m2, 4.0 m: 192 m3 in its eio), not the volume the surfaces enclose
    (129.6 m3, which thermocal kept: heating 12 % below EnergyPlus'; exploratory test,
    2026-11-30). The volume is read back from EnergyPlus' own eio on the same file."""
    from conftest import shared_data_path
    from thermocal.multizone.energyplus import run_energyplus

    text = shared_data_path("energyplus_reference", "case_600_v25.idf").read_text()
    height = "  2.7,                                  !- Ceiling Height {m}"
    volume = "  129.6,                                !- Volume {m3}"
    assert height in text and volume in text
    text = text.replace(height, "  4.0,  !- Ceiling Height {m}", 1)
    text = text.replace(volume, "  ,  !- Volume {m3}", 1)
    begin, end = "  12,                                   !- End Month", "  1,  !- End Month"
    path = tmp_path / "tall.idf"
    path.write_text(text.replace(begin, end, 1) if begin in text else text)
    run_energyplus(path, shared_data_path("ashrae140_bestest", "725650TYCST.epw"), tmp_path / "o")
    eio = (tmp_path / "o" / "eplusout.eio").read_text()
    line = next(x for x in eio.splitlines() if x.startswith(" Zone Information, ZONE ONE"))
    header = next(
        x for x in eio.splitlines() if x.startswith("! <Zone Information>")
    ).split(",")
    theirs = float(line.split(",")[next(i for i, h in enumerate(header) if "Volume" in h)])
    assert theirs == pytest.approx(192.0, rel=1e-3)
    building = _read(path)
    assert building.zones["ZONE ONE"].volume == pytest.approx(theirs, rel=1e-6)
