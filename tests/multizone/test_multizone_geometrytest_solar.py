"""NREL GeometryTest against EnergyPlus 25.2 numbers stored in ``tests/reference/
geometrytest_solar/reference.json`` (``measure.py`` there wrote them; no EnergyPlus needed).

Two findings of a survey (2026-11-30) on this file, whose windows' vertices are written to
five decimals on walls that are not aligned with the axes:

- the beam entering a window landed partly on its own host wall (the window's cells lie a few
  micrometres outside the host's plane, so the rays met the host at once): in zone RIGHT FORK,
  July 1-31, 456 kWh of the 1,452 kWh of beam through its large ENE window went onto that wall
  (EnergyPlus 0.9) and 179 kWh onto the SSE wall of the small windows (EnergyPlus 18), the
  floor got 564 kWh against EnergyPlus's 1,102; the zone's July cooling was +9.6 % of
  EnergyPlus's, +0.4 % since;
- the room side of the PSI FOYER's sloped skylight (36.9 deg, 107 m2; ISO 15099 gives
  3.4-3.8 W/(m2 K) on cold nights) was clipped to 2.9 W/(m2 K) by the time loop's bound for
  lagged corrections (2 h0 of the massless pane): January heating -25 % of EnergyPlus's with
  the skylight single-glazed, +0.6 % since (double-glazed as in the file -34 % -> -25 %).
"""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from conftest import load_script, shared_data_path
from thermocal.io.weather import read_weather
from thermocal.multizone.idf import read_idf
from thermocal.multizone.simulation import Simulation

REF = Path(__file__).resolve().parents[1] / "reference" / "geometrytest_solar"


def _measure():
    return load_script(REF / "measure.py", "geometrytest_measure")


def _simulation(tmp_path, text, begin, end, **kwargs):
    path = tmp_path / "geometrytest.idf"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(path)
    weather, meta = read_weather(
        shared_data_path("ashrae140_bestest", "725650TYCST.epw"), coerce_year=2023
    )
    start, stop = pd.Timestamp(begin), pd.Timestamp(end)
    if weather.index.tz is not None:
        start, stop = start.tz_localize(weather.index.tz), stop.tz_localize(weather.index.tz)
    return building, Simulation(
        building, weather, meta, step="15min", start=start, end=stop, store_surfaces=False, **kwargs
    )


def test_interior_beam_of_geometrytest_forks(tmp_path):
    measure = _measure()
    reference = json.loads((REF / "reference.json").read_text())["interior_beam"]
    text = measure.period(measure.IDF.read_text(), (7, 1), (7, 10))
    _, sim = _simulation(tmp_path, text, "2023-07-01", "2023-07-11")
    hours = sim.dt / 3600.0
    landed: dict[str, float] = {}
    for _, _, on_faces in sim.network.window_beam_targets.values():
        for face, col in on_faces:
            landed[face.upper()] = landed.get(face.upper(), 0.0) + sim._inputs[:, col].sum()
    for zone in ("ZN005", "ZN003"):
        theirs = reference[zone]["faces_kWh"]
        ours = {f: landed.get(f, 0.0) * hours / 1000.0 for f in theirs}
        total = reference[zone]["transmitted_kWh"]
        # no face takes the beam of a window in its own plane: every face within 2 % of the
        # zone's beam of EnergyPlus's (before: RIGHT FORK's ENE wall 31 %, its SSE wall 12 %)
        for face, value in theirs.items():
            assert abs(ours[face] - value) < 0.02 * total + 0.1 * value, (face, ours[face], value)
        assert sum(ours.values()) == pytest.approx(sum(theirs.values()), rel=0.03), zone
    floor = landed["ZN005:FLR001"] * hours / 1000.0
    assert floor == pytest.approx(reference["ZN005"]["faces_kWh"]["ZN005:FLR001"], rel=0.05)


def test_sloped_skylight_room_side_not_clipped(tmp_path):
    measure = _measure()
    reference = json.loads((REF / "reference.json").read_text())["skylight_heating"]
    text = measure.single_pane_skylight(measure.period(measure.IDF.read_text(), (1, 1), (1, 10)))
    building, sim = _simulation(tmp_path, text, "2023-01-01", "2023-01-11")
    result = sim.run()
    heating = result.heating["PSI FOYER"]
    if heating.index.tz is not None:
        heating.index = heating.index.tz_localize(None)
    ours = float(heating[heating.index >= "2023-01-04"].sum()) * sim.dt / 3.6e6
    # 199 kWh (-25 %) with the skylight's room side clipped to 2.9 W/(m2 K)
    assert ours == pytest.approx(reference["PSI FOYER_kWh"], rel=0.05)
    # the bound of the lagged correction leaves ISO 15099's coefficient of the skylight
    k = list(sim.network.face_names).index(measure.SKYLIGHT)
    context = sim._context(sim.dt, sim._inputs, sim._ext_dh_raw, sim._inf_dh)
    assert context.face_hmax[k] > 4.0
    assert re.search("SINGLE PANE SKY", text)
    assert np.isfinite(result.air_temperature.to_numpy()).all()
