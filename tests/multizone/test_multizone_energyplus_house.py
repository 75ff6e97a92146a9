"""thermocal against EnergyPlus 25.2 on a generated two-storey house with schedules.

The house is written by :func:`energyplus_house.house_idf` (next to this file; see its docstring):
LIVING and KITCHEN on a slab on ground, BED1 and BED2 upstairs, an unconditioned gable ATTIC;
inter-zone walls and floors; 13 simple-glazing windows on the four orientations;
``Schedule:Compact`` set points with night set-back (weekday/weekend rules, ``Until:`` times off
the hour), People/Lights/ElectricEquipment and scheduled infiltration with wind and temperature
terms; Timestep 4; Chicago O'Hare TMY3 shipped with EnergyPlus; a full year (2006). EnergyPlus runs
once per module on the thermostatted (ideal loads) and the free-float variants, side by side;
thermocal simulates both at 15 min (the file's schedules step by step, EnergyPlus-style weather
interpolation, the file's TARP / DOE-2 convection); the tests skip when EnergyPlus is absent.

Measured 2026-11-23 (EnergyPlus 25.2.0), thermocal vs EnergyPlus, first (thermocal at 263a816)
and now. Four changes closed the gap: the interior solar distributed as EnergyPlus does; the
exterior convection at each surface's own wind speed (centroid height, the file's Terrain)
instead of a fixed 0.845 of the station's wind (free-float bias -0.9 -> -0.6 K, attic RMSE
1.05 -> 0.33 K); the solar absorbed by a single-layer window (the simple-glazing equivalent
layer, whose resistance is most of the window's) put at the middle of the layer, half on each
face, instead of all on its outer face, which had sent nearly all of it outdoors (EnergyPlus'
inward-flowing fraction is (R_out + R_layer / 2) / R_total): bias -0.6 -> +0.2 K, loads +2 % /
+4 %; and People's sensible heat at the zone's air temperature instead of 22 C: bias +0.04 K.

| zone | heating tc / E+ [kWh] | first | now | cooling tc / E+ [kWh] | first | now |
|---|---|---|---|---|---|---|
| LIVING | 1186 / 1202 | +17.4 % | -1.3 % | 1228 / 1213 | -18.2 % | +1.2 % |
| KITCHEN | 1151 / 1159 | +10.7 % | -0.7 % | 748 / 744 | -15.5 % | +0.5 % |
| BED1 | 716 / 712 | +17.8 % | +0.5 % | 793 / 796 | -16.7 % | -0.4 % |
| BED2 | 795 / 785 | +14.6 % | +1.3 % | 727 / 727 | -18.6 % | -0.0 % |
| building | 3847 / 3858 | +14.9 % | -0.3 % | 3495 / 3480 | -17.4 % | +0.4 % |

| free float, hourly air temperature | RMSE first | RMSE now | bias first | bias now [K] |
|---|---|---|---|---|
| LIVING | 1.04 | 0.15 | -0.94 | +0.05 |
| KITCHEN | 0.92 | 0.13 | -0.85 | +0.04 |
| BED1 | 1.04 | 0.13 | -0.90 | +0.04 |
| BED2 | 0.98 | 0.11 | -0.91 | +0.04 |
| ATTIC | 1.05 | 0.33 | -0.45 | +0.03 |

The bounds encode this agreement (about 1.3 x the measured differences, at least 1 % on
energies) so that a regression fails.

| quantity | measured | bound |
|---|---|---|
| per-zone annual heating, abs diff | <= 1.3 % | 2 % |
| per-zone annual cooling, abs diff | <= 1.2 % | 2 % |
| building annual heating / cooling, abs diff | 0.3 % / 0.4 % | 1 % / 1 % |
| free float RMSE, conditioned zones: worst / mean [K] | 0.15 / 0.13 | 0.2 / 0.17 |
| free float RMSE attic [K] | 0.33 | 0.42 |
| free float abs bias, worst zone [K] | 0.05 | 0.07 |
| thermostatted hourly air temperature RMSE, worst zone [K] | 0.44 (first) | 0.55 |
| set-back: weekday night / day heating, LIVING and KITCHEN, Jan-Feb | 0.18-0.19 | < 0.25 |
| set-back: weekday / weekend heating 07-08 h, LIVING and KITCHEN | 3.9-5.6 | > 3 |

Time of the module (2 cores): about 10 s (EnergyPlus about 4-6 s per variant, run side by side).
"""

from __future__ import annotations

import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest
from energyplus_house import ATTIC, CONDITIONED, WEATHER_FILE, YEAR, house_idf

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

HEATING = "Zone Ideal Loads Zone Sensible Heating Energy [J]"
COOLING = "Zone Ideal Loads Zone Sensible Cooling Energy [J]"


@pytest.fixture(scope="module")
def house(tmp_path_factory):
    """Both variants through both engines: {variant: (EnergyPlus hourly, result, building)}."""
    folder = energyplus_weather_folder()
    weather_path = None if folder is None else folder / WEATHER_FILE
    if weather_path is None or not weather_path.is_file():
        pytest.skip(f"{WEATHER_FILE} is not in the EnergyPlus installation")
    root = tmp_path_factory.mktemp("house")
    idfs = {}
    for variant, free_float in (("hvac", False), ("free_float", True)):
        idfs[variant] = root / f"house_{variant}.idf"
        idfs[variant].write_text(house_idf(free_float=free_float))
    with ThreadPoolExecutor(max_workers=2) as pool:  # two EnergyPlus processes side by side
        futures = {
            v: pool.submit(run_energyplus, idf, weather_path, root / f"out_{v}")
            for v, idf in idfs.items()
        }
        eso = {v: f.result() for v, f in futures.items()}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        weather, meta = read_weather(weather_path)
        out = {}
        for variant, idf in idfs.items():
            building = read_idf(idf)
            result = Simulation(building, weather, meta, step="15min", store_surfaces=False).run()
            out[variant] = (read_eso(eso[variant], year=YEAR), result, building)
    return out


def _hourly(series: pd.Series, index: pd.DatetimeIndex) -> np.ndarray:
    values = series.resample("1h").mean().to_numpy()
    assert len(values) == len(index) == 8760
    return values


def test_house_import_is_complete(house):
    """Everything physical of the file is read: only output/control objects are left out."""
    for _, _, building in house.values():
        assert set(building.zones) == {*CONDITIONED, ATTIC}
        assert len(building.windows) == 13
        skipped = set(building.idf_info.unsupported)
        assert skipped <= {
            "HeatBalanceAlgorithm",
            "Output:Variable",
            "ScheduleTypeLimits",
            "SimulationControl",
            "NodeList",
            "ZoneHVAC:EquipmentConnections",
            "ZoneHVAC:EquipmentList",
            "ZoneHVAC:IdealLoadsAirSystem",
        }, skipped
    info = house["hvac"][2].idf_info
    assert info.timesteps_per_hour == 4
    assert set(info.setpoint_schedules) == set(CONDITIONED)


def test_house_annual_loads_against_energyplus(house):
    reference, result, _ = house["hvac"]
    zones = result.summary()["zones"]
    found = {}
    for zone in CONDITIONED:
        heating_ep = reference[f"{zone} IDEAL LOADS:{HEATING}"].sum() / 3.6e6  # J -> kWh
        cooling_ep = reference[f"{zone} IDEAL LOADS:{COOLING}"].sum() / 3.6e6
        found[zone] = (
            zones[zone]["heating_kWh"],
            heating_ep,
            zones[zone]["cooling_kWh"],
            cooling_ep,
        )
    for zone, (heating, heating_ep, cooling, cooling_ep) in found.items():
        assert abs(heating / heating_ep - 1) < 0.02, (zone, found[zone])
        assert abs(cooling / cooling_ep - 1) < 0.02, (zone, found[zone])
    total = np.sum(list(found.values()), axis=0)
    assert abs(total[0] / total[1] - 1) < 0.01, total
    assert abs(total[2] / total[3] - 1) < 0.01, total
    # the thermostatted zones follow the same set points: hourly air temperatures agree closely
    for zone in CONDITIONED:
        theirs = reference[f"{zone}:Zone Mean Air Temperature [C]"].to_numpy()
        diff = _hourly(result.air_temperature[zone], reference.index) - theirs
        assert np.sqrt(np.mean(diff**2)) < 0.55, zone


def test_house_free_float_hourly_temperatures_against_energyplus(house):
    reference, result, _ = house["free_float"]
    found = {}
    for zone in (*CONDITIONED, ATTIC):
        theirs = reference[f"{zone}:Zone Mean Air Temperature [C]"].to_numpy()
        diff = _hourly(result.air_temperature[zone], reference.index) - theirs
        found[zone] = (float(np.sqrt(np.mean(diff**2))), float(diff.mean()))
    rmse = [found[zone][0] for zone in CONDITIONED]
    assert max(rmse) < 0.2, found
    assert np.mean(rmse) < 0.17, found
    assert found[ATTIC][0] < 0.42, found
    assert max(abs(bias) for _, bias in found.values()) < 0.07, found


def test_house_schedules_act_in_both_engines(house):
    """The set points as EnergyPlus has them hour by hour, and the night set-back and the later
    weekend start lowering the heating in both engines."""
    reference, result, building = house["hvac"]
    info = building.idf_info
    index = reference.index
    step = pd.Timedelta("15min")
    grid = pd.date_range(index[0], periods=len(index) * 4, freq=step)
    for zone in CONDITIONED:
        heating_schedule = info.setpoint_schedules[zone][0]
        ours = info.schedules.on_grid(heating_schedule, grid, step).reshape(-1, 4).mean(axis=1)
        theirs = reference[f"{zone}:Zone Thermostat Heating Setpoint Temperature [C]"].to_numpy()
        np.testing.assert_allclose(ours, theirs, atol=1e-9, err_msg=zone)
    winter = index.month <= 2
    weekday = index.day_of_week < 5
    hour = index.hour
    for zone in ("LIVING", "KITCHEN"):
        engines = {
            "EnergyPlus": reference[f"{zone} IDEAL LOADS:{HEATING}"].to_numpy() / 3600.0,
            "thermocal": _hourly(result.heating[zone], index),
        }
        for engine, heating in engines.items():
            night = heating[winter & weekday & (hour < 6)].mean()  # set back to 16 C
            day = heating[winter & weekday & (hour >= 8) & (hour < 22)].mean()  # 20 C
            assert night < 0.25 * day, (zone, engine, night, day)
            # 07-08 h: 20 C on weekdays (from 06:30), still 16 C on weekends (until 08:00)
            early = heating[winter & weekday & (hour == 7)].mean()
            late = heating[winter & ~weekday & (hour == 7)].mean()
            assert early > 3.0 * late, (zone, engine, early, late)
