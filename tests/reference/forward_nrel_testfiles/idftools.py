"""Small IDF text tools of the conversion scripts, independent of thermocal's importer.

Copied from the survey of 2026-11-30 (``/tmp/idfsurvey/idftools.py``) and reduced to what the
conversions use. An IDF is split into objects ``(class in lower case, fields, raw text)``;
edited objects are rewritten one field per line, the others keep their raw text.
"""

from __future__ import annotations

from pathlib import Path

#: the reference period written into the files; the test replaces it for each of its periods
RUN_PERIOD = ["RunPeriod", "winter", "1", "1", "2023", "1", "15", "2023", "", "Yes", "Yes", "No",
              "Yes", "Yes"]  # fmt: skip

#: output objects of the NREL files (replaced by the hourly zone air temperature)
OUTPUT_CLASSES = [
    "Output:Variable", "Output:Meter", "Output:Meter:MeterFileOnly", "Output:Table:Monthly",
    "Output:Table:SummaryReports", "OutputControl:Table:Style", "Output:SQLite",
    "Output:Surfaces:Drawing", "Output:VariableDictionary", "Output:Constructions",
    "Output:Surfaces:List",
]  # fmt: skip


def split_objects(text: str) -> list[tuple[str, list[str], str]]:
    """Objects of an IDF text: ``(class in lower case, stripped fields, raw text)``.

    Comments (``!``) stay in the raw text; several objects on one line are split.
    """
    objs, buf = [], []
    for line in text.splitlines(keepends=True):
        buf.append(line)
        if ";" not in line.split("!", 1)[0]:
            continue
        raw, buf = "".join(buf), []
        code = "".join(part.split("!", 1)[0] for part in raw.splitlines())
        chunks = code.split(";")[:-1]
        for chunk in chunks:
            fields = [f.strip() for f in chunk.split(",")]
            text_of = raw if len(chunks) == 1 else "  " + ",".join(fields) + ";\n"
            objs.append((fields[0].lower(), fields, text_of))
    return objs


def fmt(fields: list[str]) -> str:
    """An object written one field per line."""
    return "  " + fields[0] + ",\n" + ",\n".join("    " + f for f in fields[1:]) + ";\n\n"


def write(objs, path, header: str = "") -> None:
    """Write the objects (raw text) after ``header``."""
    body = "".join(o[2] if o[2].endswith("\n") else o[2] + "\n" for o in objs)
    Path(path).write_text(header + body)


def drop(objs, classes):
    """The objects without those of ``classes``, and how many were dropped."""
    classes = {c.lower() for c in classes}
    kept = [o for o in objs if o[0] not in classes]
    return kept, len(objs) - len(kept)


def replace_fields(objs, cls: str, fn):
    """Objects of class ``cls`` with their fields replaced by ``fn(fields)`` (None drops it)."""
    out = []
    for o in objs:
        if o[0] == cls.lower():
            fields = fn(list(o[1]))
            if fields is not None:
                out.append((o[0], fields, fmt(fields)))
        else:
            out.append(o)
    return out


def add(objs, fields):
    """The objects with one more, written from its fields."""
    return [*objs, (fields[0].lower(), fields, fmt(fields))]


def free_float_reference(objs):
    """Version 25.2, a weather-file run of :data:`RUN_PERIOD` and hourly zone air temperatures.

    The file's ``SimulationControl`` (sizing periods only, in most NREL test files), its
    ``RunPeriod`` and its outputs are replaced; nothing else changes.
    """
    objs = replace_fields(objs, "Version", lambda f: ["Version", "25.2"])
    objs, _ = drop(objs, ["SimulationControl", "RunPeriod", *OUTPUT_CLASSES])
    objs = add(objs, ["SimulationControl", "No", "No", "No", "No", "Yes", "No", "1"])
    objs = add(objs, RUN_PERIOD)
    return add(objs, ["Output:Variable", "*", "Zone Mean Air Temperature", "Hourly"])
