"""The ``Building`` object's Solar Distribution (issue 28): ``MinimalShadowing`` casts no shadow
from the shading surfaces (as EnergyPlus); the interior distribution of
``FullInteriorAndExterior`` and the exterior reflections are approximated and said so.

Measured 2026-11-25, ASHRAE 140 Case 600FF with Case 610's 1 m overhang, July 1-10, both engines
at 15 min, hourly air temperature thermocal - EnergyPlus (RMSE / bias): MinimalShadowing
2.89 / -2.44 K before (the overhang still shaded the window), 0.43 / -0.07 K now (bound 0.6 /
0.3 K); FullExterior 0.60 / +0.13 K, unchanged. About 3 s.
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
from test_multizone_energyplus import CASE_610_OVERHANG
from test_multizone_idf import _box

from conftest import requires_energyplus
from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import IdfImportWarning, read_idf

SHADE = "Shading:Site:Detailed,S,,4,0,-1,2.5,4,-1,2.5,4,0,2.5,0,0,2.5;"


def _read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        return read_idf(path)


@pytest.mark.parametrize(
    "option, shaders, note",
    [
        ("MinimalShadowing", 0, "cast no shadow"),
        ("FullExterior", 1, None),
        ("fullinteriorandexterior", 1, "lands on its floor"),
        ("FullExteriorWithReflections", 1, "reflected by exterior surfaces"),
    ],
)
def test_solar_distribution_options(tmp_path, option, shaders, note):
    extra = SHADE + "SurfaceConvectionAlgorithm:Inside,Simple;ShadowCalculation,Timestep;"
    building = _read(_box(tmp_path, extra=extra, north=f"0,Suburbs,,,{option}"))
    info = building.idf_info
    # the rest of the shading stage still runs (convection, shadow calculation)
    assert info.convection == {"inside": "Simple"} and info.shadow_update_days == 0
    assert info.solar_distribution == option
    assert len(info.shading_surfaces) == shaders
    notes = [n for n in info.notes if n.startswith("Solar Distribution")]
    assert (note is None and not notes) or (note is not None and note in notes[0])


def test_unknown_solar_distribution_is_refused(tmp_path):
    with pytest.raises(ThermocalInputError, match=r"Building 'Box'.*'Solar Distribution' = 'Some'"):
        read_idf(_box(tmp_path, north="0,Suburbs,,,Some"))


@requires_energyplus
def test_minimal_shadowing_against_energyplus(tmp_path):
    from conftest import shared_data_path
    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import read_eso, run_energyplus
    from thermocal.multizone.simulation import Simulation

    text = shared_data_path("energyplus_reference", "case_600FF_v25.idf").read_text()
    edits = {
        "  1,                                    !- Begin Month": "  7,",
        "  12,                                   !- End Month\n  31,": "  7,\n  10,",
        "FullInteriorAndExterior,              !- Solar Distribution": "MinimalShadowing,",
    }
    for old, new in edits.items():
        assert old in text
        text = text.replace(old, new, 1)
    idf = tmp_path / "case610_minimal.idf"
    idf.write_text(text + CASE_610_OVERHANG)
    weather_path = shared_data_path("ashrae140_bestest", "725650TYCST.epw")
    reference = read_eso(run_energyplus(idf, weather_path, tmp_path / "out"), year=2009)
    building = _read(idf)
    assert building.idf_info.shading_surfaces == []
    weather, meta = read_weather(weather_path, coerce_year=2009)
    start = pd.Timestamp("2009-07-01", tz=weather.index.tz)
    result = Simulation(
        building,
        weather,
        meta,
        step="15min",
        start=start,
        end=start + pd.Timedelta(days=10),
        store_surfaces=False,
    ).run()
    ours = result.air_temperature["ZONE ONE"].resample("1h").mean().to_numpy()
    theirs = reference["ZONE ONE:Zone Mean Air Temperature [C]"].to_numpy()
    assert len(ours) == len(theirs) == 240
    diff = ours - theirs
    rmse, bias = float(np.sqrt(np.mean(diff**2))), float(diff.mean())
    assert rmse < 0.6 and abs(bias) < 0.3, (rmse, bias)
