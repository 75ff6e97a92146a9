"""EnergyPlus-style sub-hourly weather (Simulation(weather_interpolation="energyplus")) against
hand-computed values, and the default: EnergyPlus for IDF buildings, hold for the others."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
from test_multizone_idf import BOX
from test_multizone_network import box_building, constant_weather

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import IdfImportWarning, read_idf
from thermocal.multizone.model import Material
from thermocal.multizone.simulation import Simulation, _energyplus_weather


def _ramp_weather():
    weather, meta = constant_weather(days=2)
    n = len(weather)
    weather["dni"] = 0.0
    weather.iloc[:6, weather.columns.get_loc("dni")] = [0.0, 400.0, 800.0, 400.0, 0.0, 0.0]
    weather["dhi"] = weather["dni"] / 4
    weather["temp_air"] = np.arange(n) * 4.0
    weather["wind_speed"] = np.arange(n) * 1.0
    return weather, meta


def test_energyplus_weather_values_at_the_step_end():
    weather, _ = _ramp_weather()
    grid = _energyplus_weather(weather, pd.Timedelta("15min"))
    t0 = weather.index[0]
    at = grid.loc[[t0 + pd.Timedelta(minutes=m) for m in (0, 15, 45, 60, 75, 90, 105)]]
    # hourly means placed at the half hours (00:30 -> 0, 01:30 -> 400, 02:30 -> 800), linear
    # between them, read at each step's end; held before the first half hour
    assert at["dni"].tolist() == pytest.approx([0.0, 0.0, 200.0, 300.0, 400.0, 500.0, 600.0])
    assert at["dhi"].tolist() == pytest.approx([0.0, 0.0, 50.0, 75.0, 100.0, 125.0, 150.0])
    # instants (wind at the labels 0, 1, 2 m/s per hour) at the step end
    assert at["wind_speed"].tolist() == pytest.approx([0.25, 0.5, 1.0, 1.25, 1.5, 1.75, 2.0])
    # the hourly mean of the irradiance is kept over whole days (triangles between half hours)
    assert grid["dni"].iloc[:96].mean() == pytest.approx(weather["dni"].iloc[:24].mean())


def _simulation(mode=None, step="15min"):
    weather, meta = _ramp_weather()
    building = box_building([Material("timber", 0.14, 650.0, 1200.0, 0.05)])
    return Simulation(building, weather, meta, step=step, warmup_days=0, weather_interpolation=mode)


def test_air_temperature_of_a_step_hold_and_energyplus():
    hold = _simulation().weather_on_grid  # generated building: hold by default
    eplus = _simulation("energyplus").weather_on_grid
    # temp_air 0, 4, 8 C at 00:00, 01:00, 02:00: step [01:00, 01:15) holds 4.5 C (mean of its
    # end values) or 5 C (its end value, as EnergyPlus)
    t = hold.index[4]
    assert (hold.loc[t, "temp_air_mean"], eplus.loc[t, "temp_air_mean"]) == pytest.approx(
        (4.5, 5.0)
    )
    assert hold.loc[t, "dni"] == pytest.approx(400.0) and eplus.loc[t, "dni"] == pytest.approx(
        300.0
    )


def test_weather_interpolation_errors():
    with pytest.raises(ThermocalInputError, match="weather_interpolation must be 'hold' or"):
        _simulation("linear")
    weather, meta = _ramp_weather()
    from thermocal.io.weather import resample_weather

    fine = resample_weather(weather, "30min")
    building = box_building([Material("timber", 0.14, 650.0, 1200.0, 0.05)])
    with pytest.raises(ThermocalInputError, match="'energyplus' needs hourly weather"):
        Simulation(building, fine, meta, step="15min", weather_interpolation="energyplus")


def test_default_is_energyplus_for_idf_buildings_only(tmp_path):
    path = tmp_path / "box.idf"
    path.write_text(BOX.format(extra="", north=0, zone_north=0, ox=0, oy=0, volume="autocalculate"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        building = read_idf(path)
    weather, meta = _ramp_weather()
    sim = Simulation(building, weather, meta, step="15min", warmup_days=0)
    assert sim.weather_interpolation == "energyplus"
    assert any("interpolated as EnergyPlus" in line for line in sim.approximations())
    held = Simulation(
        building, weather, meta, step="15min", warmup_days=0, weather_interpolation="hold"
    )
    assert any("weather held over each hour" in line for line in held.approximations())
    assert _simulation().weather_interpolation == "hold"
