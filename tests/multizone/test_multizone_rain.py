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
