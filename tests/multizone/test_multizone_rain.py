"""Rain as EnergyPlus 25.2 treats it: which steps are wet, and what a wet step does.

EnergyPlus (RunPeriod 'Use Weather File Rain Indicators', Yes by default) flags a step wet when
the weather file's liquid precipitation, placed at the end of its hour and interpolated to the
step's end, reaches 0.8 mm/h (or present weather says rain); its wind-exposed outside faces
then exchange 1000 W/(m2 K) with the outdoor wet bulb. The flags are checked here against
EnergyPlus' own ``Site Rain Status`` on NREL's 1ZoneUncontrolled_win_1 (Denver TMY3, July 1-15,
15-minute steps: 31 wet steps, measured 2026-11-30); what rain does to the zones is checked
against EnergyPlus by the forward references of ``test_multizone_nrel_testfiles.py``
(InternalMass_wZoneList in July: +0.19..+0.26 K without rain, -0.08..-0.01 K with it).
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from conftest import requires_energyplus, shared_data_path
from thermocal.io.weather import read_weather
from thermocal.multizone.energyplus import read_eso, run_energyplus
from thermocal.multizone.idf import read_idf
from thermocal.multizone.simulation import Simulation

SOURCE = (
    Path(__file__).resolve().parents[1]
    / "reference"
    / "forward_nrel_testfiles"
    / "1ZoneUncontrolled_win_1"
    / "1ZoneUncontrolled_win_1_layered_v25.idf"
)
YEAR = 2023


def _july(folder: Path, rain: str = "Yes") -> Path:
    text = SOURCE.read_text()
    run_period = f"RunPeriod,july,7,1,{YEAR},7,15,{YEAR},,Yes,Yes,No,{rain},Yes;"
    text, count = re.subn(r"RunPeriod,[^;]*;", run_period, text)
    assert count == 1
    text += "\nOutput:Variable,*,Site Rain Status,Timestep;\n"
    path = folder / f"july_rain_{rain}.idf"
    path.write_text(text)
    return path


def _simulation(idf: Path, weather_path: Path) -> Simulation:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
        weather, meta = read_weather(weather_path, coerce_year=YEAR)
    tz = weather.index.tz
    start = pd.Timestamp(YEAR, 7, 1, tz=tz)
    return Simulation(
        building, weather, meta, step="15min", start=start, end=start + pd.Timedelta(days=15),
        store_surfaces=False,
    )  # fmt: skip


@pytest.mark.slow
@requires_energyplus
def test_wet_steps_are_energyplus_site_rain_status(tmp_path):
    weather_path = shared_data_path("ashrae140_bestest", "725650TYCST.epw")
    idf = _july(tmp_path)
    status = read_eso(
        run_energyplus(idf, weather_path, tmp_path / "energyplus"), year=YEAR, frequency="timestep"
    )["Environment:Site Rain Status []"]
    simulation = _simulation(idf, weather_path)
    ours = pd.Series(np.zeros(len(simulation.times)), index=simulation.times.tz_localize(None))
    if len(simulation._rain_flags):
        ours[:] = simulation._rain_flags
    theirs = status.reindex(ours.index)
    assert theirs.notna().all()
    assert int(theirs.sum()) >= 20  # not vacuous: July 2's evening storm and three showers
    np.testing.assert_array_equal(ours.to_numpy(), theirs.to_numpy())
    assert any(note.startswith(f"rain on {int(theirs.sum())} of") for note in
               simulation.approximations())  # fmt: skip


def test_rain_indicators_off_keep_the_run_dry(tmp_path):
    weather_path = shared_data_path("ashrae140_bestest", "725650TYCST.epw")
    wet = _simulation(_july(tmp_path), weather_path)
    dry = _simulation(_july(tmp_path, rain="No"), weather_path)
    assert wet.rain and np.count_nonzero(wet._rain_flags) > 0
    assert not dry.rain and len(dry._rain_flags) == 0
    assert "rain indicators off" in " ".join(dry.approximations())


def test_a_wet_step_cools_the_exposed_envelope_and_nothing_before_it(tmp_path):
    """A July afternoon storm: the zone is bit-identical until the first wet step, then colder
    (the faces at the wet bulb, several kelvin below the dry bulb, take the sun's heat away)."""
    weather_path = shared_data_path("ashrae140_bestest", "725650TYCST.epw")
    idf = _july(tmp_path)
    wet = _simulation(idf, weather_path)
    first = int(np.flatnonzero(wet._rain_flags)[0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
        weather, meta = read_weather(weather_path, coerce_year=YEAR)
    dry = Simulation(
        building, weather, meta, step="15min", start=wet.times[0], end=wet.times[-1]
        + pd.Timedelta("15min"), store_surfaces=False, rain=False,
    )  # fmt: skip
    a = wet.run().air_temperature.iloc[:, 0].to_numpy()
    b = dry.run().air_temperature.iloc[:, 0].to_numpy()
    assert np.array_equal(a[:first], b[:first])
    assert (a[first : first + 8] < b[first : first + 8]).all()
    assert (b - a)[first : first + 16].max() > 0.2


def test_the_identification_sees_the_rain_whatever_its_heat_form(tmp_path):
    """The exact inverse of a rainy free run (no heat) finds no heat on the wet steps, with the
    heat into the air (the air held: the Dirichlet response of the wet faces) and with a radiant
    share (the general inverse: the free system's response). Before, the general inverse ran
    dry: about -930 W on the wet steps with a radiant fraction of 0.6 (review, 2026-11-30)."""
    weather_path = shared_data_path("ashrae140_bestest", "725650TYCST.epw")
    sim = _simulation(_july(tmp_path), weather_path)
    air = sim.run().air_temperature
    wet = np.flatnonzero(sim._rain_flags)
    for fraction in (0.0, 0.6):
        heat = sim.track_heat(air.to_numpy(), method="inverse", radiant_fraction=fraction).heat
        assert np.abs(np.asarray(heat)[wet]).mean() < 60.0, (fraction, np.asarray(heat)[wet])


def test_sub_hourly_weather_is_wet_at_the_same_rate():
    """A 15-minute weather file's precipitation is a rate [mm/h] like an hourly one's: 1 mm/h
    is wet (EnergyPlus: 0.8 mm/h), 0.5 mm/h is not, at 15-minute and 5-minute steps."""
    from thermocal.multizone.forcing import rain_steps

    for rate, expected in ((1.0, True), (0.5, False)):
        index = pd.date_range("2023-07-01", periods=16, freq="15min", tz="UTC")
        weather = pd.DataFrame({"precipitation": np.r_[np.zeros(4), np.full(8, rate), np.zeros(4)]},
                               index=index)  # fmt: skip
        for step in ("15min", "5min"):
            grid = pd.DataFrame(index=pd.date_range(index[0], index[-1], freq=step))
            wet = rain_steps(weather, grid, pd.Timedelta(step), "energyplus")
            assert wet.any() == expected, (rate, step)


def test_dew_point_from_relative_humidity():
    from thermocal.multizone.forcing import dew_point_temperature

    # psychrometric tables (ASHRAE): 20 C at 50 % -> 9.3 C; at 100 % the air temperature
    assert dew_point_temperature(20.0, 50.0) == pytest.approx(9.27, abs=0.05)
    assert dew_point_temperature(10.0, 100.0) == pytest.approx(10.0, abs=1e-6)
    assert np.isnan(dew_point_temperature(10.0, np.nan))
