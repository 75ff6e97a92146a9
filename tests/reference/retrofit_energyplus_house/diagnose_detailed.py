"""Where the detailed-model retrofit departs from EnergyPlus 25.2 (docs/retrofit.md, "Retrofit
on the detailed model").

The same house (``make_reference.house_idf``) run by EnergyPlus and by thermocal's detailed
model (``thermocal.retrofit.detailed.simulate_strategies``) in variants that switch parts of the
physics off: floors adiabatic (Kiva removed), no sun, the sky at the air temperature, all beam
on the floor (MinimalShadowing), walls and roof without solar absorptance, windows without
solar transmission; and the steady state (constant 0 C, 3 m/s, no sun, no gains) with and
without the ground, with the walls measure. Prints one line per case: EnergyPlus, thermocal.
About 4 minutes on 2 cores (EnergyPlus two runs at a time).

    python tests/reference/retrofit_energyplus_house/diagnose_detailed.py \\
        /work/shared/data/weather_switzerland/Zuerich-SMA_2015.epw
"""

from __future__ import annotations

import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import make_reference as mr  # noqa: E402

STUCCO = (
    "Material, A1 - 1 IN STUCCO, Smooth, 2.5389841E-02, 0.6918309, 1858.142, 836.8, 0.9, 0.92, "
    "0.92;"
)
ROOF = "Material:NoMass, AR02, VeryRough, 7.8000002E-02, 0.9, 0.7, 0.7;"
GLAZING = "Construction, Dbl Clr 3mm/6mm Air, CLEAR 3MM, AIR 6MM, CLEAR 3MM;"


def adiabatic(text: str) -> str:
    """Floors adiabatic: the Foundation boundary, Kiva and the exposed perimeters removed."""
    text = text.replace("Foundation, Slab Foundation,", "Adiabatic, ,")
    keep = [
        ln
        for ln in text.splitlines()
        if not ln.startswith(("Foundation:Kiva", "SurfaceProperty:ExposedFoundationPerimeter"))
    ]
    return "\n".join(keep) + "\n"


def weather_variant(weather: Path, out: Path, *, no_sun=False, sky_at_air=False) -> Path:
    lines = weather.read_text().splitlines()
    body = []
    for ln in lines[8:]:
        f = ln.split(",")
        if no_sun:
            for i in (13, 14, 15, 16, 17, 18):
                f[i] = "0"
        if sky_at_air:
            f[12] = f"{5.67e-8 * (float(f[6]) + 273.15) ** 4:.1f}"
        body.append(",".join(f))
    out.write_text("\n".join(lines[:8] + body) + "\n")
    return out


def cases(weather: Path, work: Path) -> dict:
    """name -> (IDF text, weather file, steady: bool[, thermocal's albedo])."""
    base = adiabatic(mr.house_idf())
    assert STUCCO in base and ROOF in base and GLAZING in base
    steady = mr.steady_weather(weather, work / "steady.epw")
    return {
        "adiabatic floors": (base, weather, False),
        "adiabatic, no sun": (base, weather_variant(weather, work / "nosun.epw", no_sun=True),
                              False),
        "adiabatic, sky at air temperature": (
            base, weather_variant(weather, work / "skyair.epw", sky_at_air=True), False),
        "adiabatic, MinimalShadowing": (
            base.replace("FullInteriorAndExterior", "MinimalShadowing"), weather, False),
        "adiabatic, walls and roof absorptance 0.01": (
            base.replace(STUCCO, STUCCO.replace("0.9, 0.92, 0.92;", "0.9, 0.01, 0.01;"))
            .replace(ROOF, ROOF.replace("0.9, 0.7, 0.7;", "0.9, 0.01, 0.01;")), weather, False),
        "adiabatic, glazing SHGC 0.05": (
            base.replace(GLAZING, "WindowMaterial:SimpleGlazingSystem, DARK GLAZING, 3.1, 0.05;\n"
                         "Construction, Dbl Clr 3mm/6mm Air, DARK GLAZING;"), weather, False),
        # thermocal takes the EPW's albedo (snow: up to 0.73), EnergyPlus its
        # Site:GroundReflectance (default 0.2): the same albedo in both
        "adiabatic, albedo 0.2 in thermocal too": (base, weather, False, 0.2),
        "steady, adiabatic floors": (adiabatic(mr.house_idf(gains=False)), steady, True),
        "steady, with the ground": (mr.house_idf(gains=False), steady, True),
        "steady, with the ground, walls measure": (
            mr.house_idf(frozenset({"walls"}), gains=False), steady, True),
    }  # fmt: skip


def energyplus(text: str, weather: Path, work: Path, steady: bool) -> float:
    df = mr._run(text, weather, work)
    q = mr._col(df, "Zone Ideal Loads Zone Sensible Heating Rate")
    return float(q.iloc[-168:].mean() / 20.0) if steady else float(q.sum() / 1000.0)


def thermocal(text: str, weather: Path, work: Path, steady: bool, albedo=None) -> float:
    from thermocal.io.weather import read_weather
    from thermocal.retrofit.detailed import load_detailed_building, simulate_strategies
    from thermocal.retrofit.strategies import Strategy

    work.mkdir(parents=True, exist_ok=True)
    (work / "in.idf").write_text(text)
    frame, meta = read_weather(weather)
    if albedo is not None:
        frame = frame.assign(albedo=albedo)
    building = load_detailed_building(work / "in.idf")
    result = simulate_strategies(
        building, frame, meta, [Strategy("0", ())], {}, source=work / "in.idf"
    )
    if steady:
        return float(result.monthly_kwh["0"].loc[12] * 1000.0 / (31 * 24) / 20.0)
    return float(result.annual_kwh[0])


def main(weather: str, work: str = "/tmp/retrofit_energyplus_house_diagnosis") -> None:
    weather, work = Path(weather), Path(work)
    work.mkdir(parents=True, exist_ok=True)
    jobs = cases(weather, work)
    with ThreadPoolExecutor(2) as pool:
        eplus = {
            k: pool.submit(energyplus, *job[:2], work / f"eplus_{i}", job[2])
            for i, (k, job) in enumerate(jobs.items())
        }
        ours = {k: thermocal(*job[:2], work / f"thermocal_{i}", *job[2:])
                for i, (k, job) in enumerate(jobs.items())}  # fmt: skip
        for k, f in eplus.items():
            unit = "W/K" if jobs[k][2] else "kWh"
            e = f.result()
            diff = 100.0 * (ours[k] / e - 1.0)
            print(f"| {k} | {e:,.1f} {unit} | {ours[k]:,.1f} {unit} | {diff:+.1f} % |")


if __name__ == "__main__":
    main(*sys.argv[1:])
