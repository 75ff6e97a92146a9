"""Where the sun and the outside faces of the EnergyPlus house depart from EnergyPlus 25.2
(docs/retrofit.md, "Retrofit on the detailed model", issue 28 item 2 / issue 25 item 7).

The house with its floors adiabatic (``diagnose_detailed.adiabatic``), January to March of the
given weather at 15 minutes, run by EnergyPlus with per-surface outputs (incident sun and its
beam / sky / ground parts, outside face temperature, its convection coefficient) and by
thermocal's multi-zone model (the same IDF through ``load_detailed_building``), twice: with the
weather as it is and with its liquid precipitation set to 0. Prints per surface the incident sun
(kWh/m2 over the period), the outside face temperature difference (thermocal - EnergyPlus; all
hours, hours with more than 200 W/m2 on the south wall, the others) and the heating of both, and
the hours EnergyPlus treats as raining (outside convection coefficient 1000 W/(m2 K), the face
at the outdoor wet-bulb temperature).

    python tests/reference/retrofit_energyplus_house/diagnose_sun.py \\
        /work/shared/data/weather_switzerland/Zuerich-SMA_2015.epw

About 3 minutes on 2 cores.
"""

from __future__ import annotations

import re
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import diagnose_detailed as dd  # noqa: E402
import make_reference as mr  # noqa: E402

PERIOD = "RunPeriod, Year, 1, 1, 2015, 3, 31, 2015, , No, No, No, Yes, Yes;"
SURFACES = {  # name -> thermocal's solar input key (tilt, azimuth[, own name when shaded])
    "Living:South": (90.0, 180.0),
    "Living:East": (90.0, 90.0),
    "Living:West": (90.0, 270.0),
    "Living:North": (90.0, 0.0, "Living:North"),
    "SouthRoof": (22.62, 180.0),
    "EastRoof": (22.625, 90.0, "EastRoof"),
}
VARIABLES = (
    "Surface Outside Face Incident Solar Radiation Rate per Area",
    "Surface Outside Face Incident Beam Solar Radiation Rate per Area",
    "Surface Outside Face Incident Sky Diffuse Solar Radiation Rate per Area",
    "Surface Outside Face Incident Ground Diffuse Solar Radiation Rate per Area",
    "Surface Outside Face Temperature",
    "Surface Outside Face Convection Heat Transfer Coefficient",
)


def without_rain(weather: Path, out: Path) -> Path:
    """The weather file with its liquid precipitation depth (field 34) set to 0."""
    lines = weather.read_text().splitlines()
    body = []
    for ln in lines[8:]:
        f = ln.split(",")
        f[33] = "0"
        body.append(",".join(f))
    out.write_text("\n".join(lines[:8] + body) + "\n")
    return out


def energyplus(weather: Path, work: Path):
    text = re.sub(r"RunPeriod,[^;]*;", PERIOD, dd.adiabatic(mr.house_idf()))
    for surface in SURFACES:
        text += "".join(f"Output:Variable, {surface}, {v}, Hourly;\n" for v in VARIABLES)
    return mr._run(text, weather, work)


def thermocal(weather: Path, work: Path):
    """Hourly incident sun per surface [W/m2], outside face temperatures [C], heating [kWh]."""
    from thermocal.io.weather import read_weather
    from thermocal.multizone.simulation import Simulation
    from thermocal.retrofit.detailed import load_detailed_building

    work.mkdir(parents=True, exist_ok=True)
    (work / "in.idf").write_text(dd.adiabatic(mr.house_idf()))
    frame, meta = read_weather(weather)
    building = load_detailed_building(work / "in.idf")
    sim = Simulation(
        building, frame, meta, step="15min", store_surfaces=False,
        start="2015-01-01", end="2015-03-31 23:45",
    )  # fmt: skip
    net = sim.network
    u = sim._input_matrix()
    names = list(net.ext_names)
    nodes = np.asarray(net.ext_node)
    sim.reset(free_float=False)
    faces = np.empty((len(sim.times), len(nodes)))
    heating = 0.0
    for k in range(len(sim.times)):
        sim.step()
        faces[k] = sim._x[nodes]
        heating += float(sim.last_heating.sum()) * sim.dt / 3.6e6

    def hourly(a):  # the period ends a step early: repeat the last step
        a = np.concatenate([a, a[-1:]])
        return a.reshape(-1, 4, *a.shape[1:]).mean(axis=1)

    incident = {s: hourly(u[:, net.orientation_inputs[key]]) for s, key in SURFACES.items()}
    faces = hourly(faces)
    return incident, {s: faces[:, names.index(s)] for s in SURFACES}, heating


def main(weather: str, work: str = "/tmp/retrofit_energyplus_house_sun") -> None:
    weather, work = Path(weather), Path(work)
    work.mkdir(parents=True, exist_ok=True)
    dry = without_rain(weather, work / "no_rain.epw")
    with ThreadPoolExecutor(2) as pool:
        pairs = list(enumerate((weather, dry)))
        runs = {w: pool.submit(energyplus, w, work / f"eplus_{i}") for i, w in pairs}
        ours = {w: thermocal(w, work / f"thermocal_{i}") for i, w in pairs}
        eplus = {w: f.result() for w, f in runs.items()}
    df = eplus[weather]
    south = mr._col(df, "LIVING:SOUTH:Surface Outside Face Incident Solar").to_numpy()
    sunny = south > 200.0
    incident, faces, _ = ours[weather]
    print("| surface | incident E+ | thermocal | E+ beam, sky, ground | dT face | sunny | other |")
    for s in SURFACES:
        e_inc = mr._col(df, f"{s}:Surface Outside Face Incident Solar Radiation Rate").to_numpy()
        parts = [
            mr._col(df, f"{s}:Surface Outside Face Incident {p} Solar").sum() / 1000.0
            for p in ("Beam", "Sky Diffuse", "Ground Diffuse")
        ]
        diff = faces[s] - mr._col(df, f"{s}:Surface Outside Face Temperature").to_numpy()
        print(
            f"| {s} | {e_inc.sum() / 1000:.1f} | {incident[s].sum() / 1000:.1f} | "
            + " / ".join(f"{p:.1f}" for p in parts)
            + f" | {diff.mean():+.2f} K | {diff[sunny].mean():+.2f} K"
            + f" | {diff[~sunny].mean():+.2f} K |"
        )
    hc = mr._col(df, "LIVING:SOUTH:Surface Outside Face Convection Heat Transfer").to_numpy()
    print(f"hours with the outside coefficient at 1000 W/(m2 K) (raining): {(hc > 999).sum()}, "
          f"in part: {((hc > 100) & (hc <= 999)).sum()}")  # fmt: skip
    for w, label in ((weather, "weather as it is"), (dry, "liquid precipitation 0")):
        q = mr._col(eplus[w], "Zone Ideal Loads Zone Sensible Heating Rate").sum() / 1000.0
        print(f"heating January-March, {label}: EnergyPlus {q:,.0f} kWh, thermocal "
              f"{ours[w][2]:,.0f} kWh ({100 * (ours[w][2] / q - 1):+.1f} %)")  # fmt: skip


if __name__ == "__main__":
    main(*sys.argv[1:])
