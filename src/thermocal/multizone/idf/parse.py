"""IDF text -> objects -> named-field records.

:func:`parse_idf` / :func:`read_idf_objects` split an IDF file into :class:`IdfObject` (class name
as written, raw string fields, the ``!-`` field comments, file and line for messages); class names
are matched case-insensitively everywhere. :func:`record` names the fields of an object with the
layout of :mod:`thermocal.multizone.idf.fields` for the file's EnergyPlus version (the ``Version``
object, :func:`_version_tuple`). ``_number`` and friends read a field with an error naming the
object and the field; ``_Names`` is the case-insensitive registry of one kind of object.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.fields import SCHEMA, layout


@dataclass(frozen=True)
class IdfObject:
    """One object of an IDF file.

    Attributes
    ----------
    class_name : str
        Class as written in the file (e.g. ``"BuildingSurface:Detailed"``).
    fields : tuple of str
        Raw field values after the class name, stripped of whitespace ("" for blank fields).
    comments : tuple of str
        The ``!-`` (or ``!``) comment written after each field on its line, "" where none.
    line : int
        1-based line number of the class name in the file.
    source : str
        File name (or ``"<string>"``) for messages.
    """

    class_name: str
    fields: tuple[str, ...]
    comments: tuple[str, ...]
    line: int
    source: str = "<string>"

    @property
    def key(self) -> str:
        """Upper-case class name, the case-insensitive identity of the class."""
        return self.class_name.upper()

    @property
    def name(self) -> str:
        """First field (the object name for nearly every class), "" when absent."""
        return self.fields[0] if self.fields else ""

    def where(self) -> str:
        """``"<class> '<name>' (file line n)"`` for error messages."""
        label = f"{self.class_name} '{self.name}'" if self.name else self.class_name
        return f"{label} ({self.source} line {self.line})"


def parse_idf(text: str, *, source: str = "<string>") -> list[IdfObject]:
    """Split IDF text into objects.

    Commas separate fields, a semicolon ends an object, ``!`` starts a comment that runs to the
    end of the line. The comment text (without the ``!-`` marker) is kept for the last field
    completed on that line, which is how IDF editors label fields.

    Parameters
    ----------
    text : str
        Content of an IDF file.
    source : str
        Name used in messages.

    Returns
    -------
    list of IdfObject
        In file order.

    Raises
    ------
    ThermocalInputError
        When the file ends inside an object (missing ``;``).
    """
    finished: list[tuple[list[str], list[str], int]] = []
    tokens: list[str] = []
    comments: list[str] = []
    current: list[str] = []
    start_line = 0
    for line_number, raw_line in enumerate(text.splitlines(), start=1):
        code, bang, comment = raw_line.partition("!")
        comment = comment.lstrip("-").strip() if bang else ""
        last_comments: list[str] | None = None
        last_index = -1
        for char in code:
            if char in ",;":
                value = "".join(current).strip()
                current = []
                if not tokens and value == "":
                    continue  # a stray separator outside any object
                tokens.append(value)
                comments.append("")
                last_comments, last_index = comments, len(comments) - 1
                if char == ";":
                    finished.append((tokens, comments, start_line))
                    tokens, comments = [], []
            else:
                if not tokens and not current and char.isspace():
                    continue
                if not tokens and not current:
                    start_line = line_number
                current.append(char)
        if comment and last_comments is not None:
            last_comments[last_index] = comment
        if current:
            current.append(" ")  # a line break inside a field is whitespace
    if tokens or "".join(current).strip():
        name = tokens[0] if tokens else "".join(current).strip()
        raise ThermocalInputError(
            f"{source}: the object '{name}' starting at line {start_line} is not terminated by "
            "';' before the end of the file; add the missing semicolon."
        )
    return [
        IdfObject(
            class_name=toks[0],
            fields=tuple(toks[1:]),
            comments=tuple(coms[1:]),
            line=line,
            source=source,
        )
        for toks, coms, line in finished
    ]


def read_idf_objects(path: str | Path) -> list[IdfObject]:
    """Read an IDF file into a list of :class:`IdfObject` (see :func:`parse_idf`).

    Parameters
    ----------
    path : str or Path
        IDF file (UTF-8; Latin-1 accepted as a fallback).
    """
    path = Path(path)
    if not path.exists():
        raise ThermocalInputError(f"IDF file {path} does not exist; check the path.")
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    return parse_idf(text, source=path.name)


def _version_tuple(objects: Iterable[IdfObject]) -> tuple[int, int]:
    for obj in objects:
        if obj.key == "VERSION" and obj.fields:
            parts = obj.fields[0].split(".")
            try:
                major = int(parts[0])
                minor = int(parts[1]) if len(parts) > 1 and parts[1] else 0
            except ValueError:
                break
            return major, minor
    return (9, 3)


def record(obj: IdfObject, *, version: tuple[int, int] = (9, 3)) -> dict:
    """Name the fields of a supported object.

    Parameters
    ----------
    obj : IdfObject
        Object of a class listed in :data:`SCHEMA`.
    version : tuple of int
        EnergyPlus version of the file (``Version`` object), used where field layouts changed.

    Returns
    -------
    dict
        ``{field_name: raw string}`` for the fixed fields present (blank fields as ""), plus the
        repeated group under its name as a list of tuples (e.g. ``"vertices"`` -> list of 3-tuples
        of strings, ``"layers"`` -> list of 1-tuples), ``"_object"`` -> the object itself.

    Notes
    -----
    The layout is :data:`SCHEMA`'s (EnergyPlus' own, see :mod:`thermocal.multizone.idf.fields`)
    adjusted for older files by :func:`thermocal.multizone.idf.fields.layout`: the ``Space Name``
    field of surfaces and ``InternalMass`` (9.6 and later, detected from the content), the
    ``Shading Control Name`` field of ``FenestrationSurface:Detailed`` before version 9.0,
    ``OtherEquipment`` written before the ``Fuel Type`` field existed (detected from the
    content).
    """
    key = obj.key
    if key not in SCHEMA:
        raise KeyError(f"no schema for class {obj.class_name}")
    fields = obj.fields
    names, group_name, group_size = layout(key, fields, version)
    if group_name is None:
        _refuse_swallowed_object(obj, len(names))
    out: dict = {"_object": obj}
    n_fields = len(fields)
    for index, name in enumerate(names):
        out[name] = fields[index] if index < n_fields else ""
    if group_name is not None:
        rest = list(fields[len(names) :])
        # drop trailing blank fields (IDF editors pad extensible groups)
        while rest and rest[-1] == "":
            rest.pop()
        groups = [tuple(rest[i : i + group_size]) for i in range(0, len(rest), group_size)]
        out[group_name] = groups
    return out


def _looks_like_a_class(value: str) -> bool:
    """Whether a field's value is the name of an IDF class (one the importer knows, or a
    ``Word:Word`` name without blanks, as every EnergyPlus class with a colon is written)."""
    text = value.strip()
    if text.upper() in SCHEMA:
        return True
    parts = text.split(":")
    return len(parts) > 1 and all(part.isalnum() for part in parts)


def _refuse_swallowed_object(obj: IdfObject, n_names: int) -> None:
    """Refuse an object with more (non-blank) fields than its class has.

    EnergyPlus refuses such an object too. The usual cause is a ';' missing at the object's
    end: the next object is read into it and would otherwise be lost without a word (a
    ``Site:Location`` eating the next ``Site:GroundTemperature:...``); its class name, among
    the fields, is named.
    """
    extra = [value for value in obj.fields[n_names:] if value != ""]
    if not extra:
        return
    # a class the importer knows first (a zone may be named 'Block1:Office'), else one that
    # is written like a class; a ';' deleted rather than replaced by ',' joins the last field
    # and the next class name into one field ('No ElectricEquipment')
    def last_word(value: str) -> str:
        words = value.split()
        return words[-1] if words else ""

    candidates = [(i, last_word(v)) for i, v in enumerate(obj.fields) if i > 0]
    swallowed = next(((i, w) for i, w in candidates if w.upper() in SCHEMA), None) or next(
        ((i, w) for i, w in candidates if _looks_like_a_class(w)), None
    )
    cause = (
        f"field {swallowed[0] + 1} is '{swallowed[1]}': the ';' at the end of the object is "
        "missing, so the next object was read into it; end the object's last field with ';'"
        if swallowed is not None
        else "a ';' missing at its end, or fields of another EnergyPlus version? Remove them"
    )
    raise ThermocalInputError(
        f"{obj.where()}: {len(obj.fields)} fields where a {obj.class_name} has {n_names}; "
        + cause
    )


def _number(rec: dict, name: str, *, default: float | None = None, required: bool = True) -> float:
    """Float value of a named field, with an error naming the object and field when invalid."""
    obj: IdfObject = rec["_object"]
    raw = rec.get(name, "")
    if raw == "" or raw.upper() in ("AUTOCALCULATE", "AUTOSIZE"):
        if default is not None or not required:
            return default  # type: ignore[return-value]
        raise ThermocalInputError(
            f"{obj.where()}: field '{_label(name)}' is blank but required; give a number."
        )
    try:
        value = float(raw)
    except ValueError:
        raise ThermocalInputError(
            f"{obj.where()}: field '{_label(name)}' = '{raw}' is not a number."
        ) from None
    if not math.isfinite(value):
        raise ThermocalInputError(f"{obj.where()}: field '{_label(name)}' = '{raw}' is not finite.")
    return value


def _is_auto(rec: dict, name: str) -> bool:
    raw = rec.get(name, "")
    return raw == "" or raw.upper() in ("AUTOCALCULATE", "AUTOSIZE")


def _label(name: str) -> str:
    return name.replace("_", " ").title()


def _field_float(raw: str, obj: IdfObject, label: str) -> float:
    """Float of a raw field of an extensible group, with an error naming the object."""
    try:
        return float(raw)
    except ValueError:
        raise ThermocalInputError(f"{obj.where()}: {label} '{raw}' is not a number.") from None


class _Names:
    """Case-insensitive name registry of one kind of object (EnergyPlus names ignore case)."""

    def __init__(self, kind: str):
        self.kind = kind
        self.items: dict[str, tuple[str, IdfObject, dict]] = {}

    def add(self, rec: dict) -> None:
        obj: IdfObject = rec["_object"]
        name = rec.get("name", obj.name)
        if not name:
            raise ThermocalInputError(f"{obj.where()}: the Name field is blank.")
        key = name.upper()
        if key in self.items:
            first = self.items[key][1]
            raise ThermocalInputError(
                f"{obj.where()}: the name '{name}' is already used by {first.where()}; "
                f"{self.kind} names must be unique (EnergyPlus ignores case)."
            )
        self.items[key] = (name, obj, rec)

    def get(self, name: str):
        return self.items.get(name.upper())

    def __contains__(self, name: str) -> bool:
        return name.upper() in self.items

    def values(self):
        return self.items.values()


def _wrap(obj: IdfObject, factory, *args, **kwargs):
    """Build a model object; prefix its validation error with the IDF object's identity."""
    try:
        return factory(*args, **kwargs)
    except ThermocalInputError as exc:
        raise ThermocalInputError(f"{obj.where()}: {exc}") from None


#: Mean glazing temperatures [C] at which the glass-to-glass conductance of layered glazing is
