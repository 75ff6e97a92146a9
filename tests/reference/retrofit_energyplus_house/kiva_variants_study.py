"""What EnergyPlus 25.2's Kiva simulates below the living floor: single-change variants.

Run from the repository root (EnergyPlus 25.2; a few seconds a run, one run at a time)::

    PYTHONPATH=src python tests/reference/retrofit_energyplus_house/kiva_variants_study.py \
        ../shared/data/weather_switzerland/Zuerich-SMA_2015.epw

The steady year of ``floor_surface_study.py`` (house at 20 C, 0 C outdoors, no sun, sky at the
air temperature) with ``Output:Diagnostics, DisplayExtraWarnings``, one change at a time to the
Kiva input, each giving the living floor's conductance below its surface [W/K] (inside-face
conduction over inside-face temperature, last week) and the Kiva line of the ``.eio`` (cells,
exposed perimeter, wall construction), next to what ``diagnose_floor_section.py``'s independent
section predicts for the same change (its isothermal surface). Two more hold the floor's surface
at the room's air (inside convection 1000 W/(m2 K)): with the house's ground, and with no ground
nor edge left (soil 0.01 W/(m K), an insulating footing wall), where EnergyPlus still reports
28 W/K below the surface, with or without the carpet. Writes ``kiva_variants.json``.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import diagnose_floor_section as dfs  # noqa: E402
import make_reference as mr  # noqa: E402

OUTPUTS = (
    "Output:Diagnostics, DisplayExtraWarnings;\n"
    "Output:Variable, Living:Floor, Surface Inside Face Conduction Heat Transfer Rate, Hourly;\n"
    "Output:Variable, Living:Floor, Surface Inside Face Temperature, Hourly;\n"
)
FOUNDATION = mr.FOUNDATION.strip()
#: Foundation:Kiva with field N8 (wall height above grade) and A6 (footing wall) set
KIVA = "Foundation:Kiva, Slab Foundation, , , , , , , , , , , , {height}, , {wall};\n"
#: Foundation:Kiva:Settings: soil k, rho, cp, absorptivities, roughness, far field, deep ground
SETTINGS = (
    "Foundation:Kiva:Settings, {k}, 1510, 1260, 0.9, 0.9, 0.03, 40, {deep}, {depth}, 0.02, "
    "1.5, Hourly;\n"
)
FULL_PERIMETER = 2 * (mr.LENGTH + mr.DEPTH)
LIVING_PERIMETER = (
    "SurfaceProperty:ExposedFoundationPerimeter, Living:Floor, TotalExposedPerimeter, "
    f"{mr.EXPOSED_PERIMETER_LIVING:.3f};"
)
DEFAULT_WALL = ((0.3, 1.95, 2400.0, 900.0),)  # Kiva's default footing wall in EnergyPlus
BLANK_SETTINGS = "Foundation:Kiva:Settings, , , , , , , , , , , ;\n"
#: the floor's surface held at the room's air (inside convection 1000 W/(m2 K))
ISOTHERMAL = "SurfaceProperty:ConvectionCoefficients, Living:Floor, Inside, Value, 1000;\n"
#: an insulating footing wall (k 0.005 W/(m K)), to cut the edge path
INSULATING_WALL = (
    "Material, FOOTING INSULATION, Rough, 0.2286, 0.005, 30, 1000, 0.9, 0.7, 0.7;\n"
    "Construction, FOOTING INSULATION, FOOTING INSULATION;\n"
)


def variants(house: str) -> dict[str, tuple[str, dict]]:
    """name: (IDF text, keyword arguments of ``dfs.kiva_section`` for the same change)."""
    assert FOUNDATION in house and LIVING_PERIMETER in house

    def kiva(height="", wall="EXTWALL:GARAGE"):
        return house.replace(FOUNDATION + "\n", KIVA.format(height=height, wall=wall))

    def settings(k="0.864", deep="ZeroFlux", depth="40"):
        return house + SETTINGS.format(k=k, deep=deep, depth=depth)

    return {
        "base": (house, {}),
        "settings_explicit": (settings(), {}),
        # blank fields act as no object (soil 0.864, not the IDD's 1.73)
        "settings_all_blank": (house + BLANK_SETTINGS, {}),
        "height_above_grade_0": (kiva(height="0"), {"height": 0.0}),
        "height_above_grade_0.2_explicit": (kiva(height="0.2"), {}),
        "no_footing_wall_construction": (kiva(wall=""), {"wall": DEFAULT_WALL}),
        "full_perimeter": (
            house.replace(
                LIVING_PERIMETER,
                LIVING_PERIMETER.replace(
                    f"{mr.EXPOSED_PERIMETER_LIVING:.3f}", f"{FULL_PERIMETER:.3f}"
                ),
            ),
            {"perimeter": FULL_PERIMETER},
        ),
        "soil_2.0": (settings(k="2.0"), {"soil_k": 2.0}),
        # the floor's surface isothermal at 20 C: against the section's isothermal value
        "isothermal": (house + ISOTHERMAL, {}),
        # no ground and no edge left (soil 0.01, insulating footing wall), surface isothermal:
        # what EnergyPlus still reports below the floor's surface
        "isothermal_soil_0.01_insulating_wall": (
            kiva(wall="FOOTING INSULATION")
            + INSULATING_WALL
            + ISOTHERMAL
            + SETTINGS.format(k="0.01", deep="ZeroFlux", depth="40"),
            {"soil_k": 0.01, "wall": ((0.2286, 0.005, 30.0, 1000.0),)},
        ),
    }


def section(floor, perimeter=dfs.PERIMETER, **kw) -> float:
    """``dfs.kiva_section`` with another exposed perimeter (module constant) if asked."""
    saved = dfs.PERIMETER
    dfs.PERIMETER = perimeter
    try:
        return dfs.kiva_section(floor, **kw)
    finally:
        dfs.PERIMETER = saved


def main(weather: str) -> dict:
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        steady = mr.steady_weather(Path(weather), tmp / "steady.epw")
        house = mr.house_idf(gains=False)
        for carpet, text in (
            ("with_carpet", house),
            (
                "without_carpet",
                house.replace(
                    "Construction, FLOOR:LIVING, CC03, CP02;", "Construction, FLOOR:LIVING, CC03;"
                ),
            ),
        ):
            floor = dfs.FLOOR if carpet == "with_carpet" else dfs.FLOOR[:1]
            for name, (idf, change) in variants(text).items():
                work = tmp / f"{carpet}_{name}"
                frame = mr._run(idf + OUTPUTS, steady, work)
                last = frame.iloc[-168:]
                loss = -float(mr._col(last, "Living:Floor:Surface Inside Face Conduction").mean())
                face = float(mr._col(last, "Living:Floor:Surface Inside Face Temperature").mean())
                eio = (work / "eplusout.eio").read_text().splitlines()
                kiva = [ln for ln in eio if ln.startswith("SLAB FOUNDATION") and "LIVING" in ln]
                err = (work / "eplusout.err").read_text().splitlines()
                out.setdefault(carpet, {})[name] = {
                    "energyplus_W_per_K": loss / face,
                    "floor_loss_W": loss,
                    "floor_face_C": face,
                    "kiva_eio": kiva[0] if kiva else "",
                    "warnings": [ln.strip() for ln in err if "Warning" in ln or "Severe" in ln],
                    "section_isothermal_W_per_K": section(floor, **change),
                }
    (HERE / "kiva_variants.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1]), indent=1))
