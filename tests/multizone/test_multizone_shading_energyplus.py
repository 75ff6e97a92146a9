"""Sunlit fractions and shaded sky diffuse against EnergyPlus 25.2 on NREL's 5ZoneAirCooled
(a building thermocal did not write: a south facade rotated 30 deg with a long overhang over its
window and a deeper one over its glass door).

EnergyPlus runs the file for January 1-25 at 5-minute steps (about 8 s) with its default
periodic shadow calculation (every 20 days: one day of sunlit fractions per period, computed with
the period's mean declination and equation of time); thermocal reads the same file. Measured
2026-11-25, 9:00-15:00, mean |thermocal - EnergyPlus| of the sunlit fraction: WF-1 0.003,
DF-1 0.002, FRONT-1 (the wall minus its window and door) 0.003; with the sun of each period's
first day (before) WF-1 was 0.02 off on the first period and 0.1-0.4 on the second. Incident
sky diffuse on the shaded window WF-1 over the period: 1.03 x EnergyPlus' (0.84 x before, when
the whole Perez sky was scaled by the dome's shading ratio).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest

from conftest import requires_energyplus, shared_data_path
from thermocal.io.weather import read_weather
from thermocal.multizone.energyplus import energyplus_weather_folder, read_eso, run_energyplus
from thermocal.multizone.idf import read_idf
from thermocal.multizone.simulation import Simulation

pytestmark = [pytest.mark.slow, requires_energyplus]

DAYS = 25
RECEIVERS = ("WF-1", "DF-1", "FRONT-1")


def _reference_idf(source: str) -> str:
    """January 1 to DAYS at 12 steps per hour, the sunlit fractions and incident sky diffuse of
    the receivers as outputs (the file's own outputs dropped)."""
    lines = [line.split("!", 1)[0] for line in source.splitlines()]
    objects = [obj.strip() for obj in "\n".join(lines).split(";") if obj.strip()]
    out = []
    for obj in objects:
        kind = obj.split(",", 1)[0].strip().lower()
        if kind == "output:variable":
            continue
        if kind == "timestep":
            obj = "Timestep, 12"
        elif kind == "runperiod":
            fields = [f.strip() for f in obj.split(",")]
            fields[2:7] = ["1", "1", "", "1", str(DAYS)]
            obj = ", ".join(fields)
        out.append(obj)
    for name in RECEIVERS:
        for variable in (
            "Surface Outside Face Sunlit Fraction",
            "Surface Outside Face Incident Sky Diffuse Solar Radiation Rate per Area",
        ):
            out.append(f"Output:Variable, {name}, {variable}, Timestep")
    return ";\n".join(out) + ";\n"


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    source = shared_data_path("energyplus_reference", "5ZoneAirCooled_FF_v25.idf").read_text()
    folder = tmp_path_factory.mktemp("shading5zone")
    idf = folder / "reference.idf"
    idf.write_text(_reference_idf(source))
    epw = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
        weather, metadata = read_weather(epw)
    frame = read_eso(
        run_energyplus(idf, epw, folder / "energyplus"),
        year=int(weather.index[0].year),
        frequency="timestep",
    )
    frame.index = frame.index.tz_localize(weather.index.tz)
    assert len(frame) == DAYS * 288
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(
            building,
            weather,
            metadata,
            step="5min",
            start=frame.index[0],
            end=frame.index[-1] + pd.Timedelta("5min"),
            store_surfaces=False,
        )
    return sim, frame


def test_periodic_sunlit_fractions_are_energyplus_ones(runs):
    sim, frame = runs
    day = (frame.index.hour >= 9) & (frame.index.hour < 15)
    for name in RECEIVERS:
        ours = sim._shadows["beam"][name][day]
        theirs = frame[f"{name}:Surface Outside Face Sunlit Fraction []"].to_numpy()[day]
        assert np.mean(np.abs(ours - theirs)) < 0.01, name
    # the second period (from January 21) is computed with its own mean sun, not January 1's
    late = day & (frame.index.day >= 21)
    ours = sim._shadows["beam"]["WF-1"][late]
    theirs = frame["WF-1:Surface Outside Face Sunlit Fraction []"].to_numpy()[late]
    assert np.max(np.abs(ours - theirs)) < 0.05


def test_shaded_sky_diffuse_is_energyplus_one(runs):
    sim, frame = runs
    window = sim.building.windows["WF-1"]
    surface = sim.building.surfaces[window.surface]
    key = next(
        k
        for k in sim._irradiance_cache
        if abs(k[0] - surface.tilt) < 1e-3
        and abs((k[1] - surface.azimuth + 180) % 360 - 180) < 1e-3
    )
    ours = sim._shaded(sim._irradiance_cache[key], "WF-1")["poa_sky_diffuse"].copy()
    ours[1:] = 0.5 * (ours[1:] + ours[:-1])  # the step's mean of its start and end values
    theirs = frame[
        "WF-1:Surface Outside Face Incident Sky Diffuse Solar Radiation Rate per Area [W/m2]"
    ].to_numpy()
    assert ours.sum() / theirs.sum() == pytest.approx(1.0, abs=0.05)
