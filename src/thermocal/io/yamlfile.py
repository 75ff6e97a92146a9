"""Safe YAML reading for every thermocal file (building, model, retrofit configuration,
mapping, campaign files).

Safe loading only (no Python objects), UTF-8 with a clear message otherwise, duplicate keys
rejected with both lines (PyYAML lets the last one win silently), an empty file rejected, and
limits checked on the node tree before anything walks it: file size, nesting depth and the
size of the document once aliases are expanded (a "billion laughs" file is refused instead of
filling the memory).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from thermocal.errors import ThermocalInputError


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses a key repeated in one mapping."""


def _construct_mapping(loader: _UniqueKeyLoader, node: yaml.MappingNode, deep: bool = False):
    seen: dict[Any, int] = {}
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        try:
            hash(key)
        except TypeError:
            continue
        if key in seen:
            raise yaml.constructor.ConstructorError(
                None,
                None,
                f"key {key!r} appears twice (lines {seen[key] + 1} and "
                f"{key_node.start_mark.line + 1}); keep one",
                key_node.start_mark,
            )
        seen[key] = key_node.start_mark.line
    return loader.construct_mapping_default(node, deep=deep)


_UniqueKeyLoader.construct_mapping_default = yaml.SafeLoader.construct_mapping
_UniqueKeyLoader.add_constructor(
    yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG,
    lambda loader, node: _construct_mapping(loader, node, deep=True),
)


def _construct_timestamp(loader: _UniqueKeyLoader, node: yaml.ScalarNode):
    """A date or date-time; a scalar shaped like one that is no calendar date (``2023-02-30``,
    ``2001-13-01``) stays text, as if quoted, for the reader of its key to refuse by name
    (PyYAML raises a bare ValueError from ``datetime.date``)."""
    try:
        return yaml.SafeLoader.construct_yaml_timestamp(loader, node)
    except ValueError:
        return loader.construct_scalar(node)


_UniqueKeyLoader.add_constructor("tag:yaml.org,2002:timestamp", _construct_timestamp)


#: Largest YAML file read [bytes].
MAX_BYTES = 20_000_000
#: Deepest nesting of mappings and sequences.
MAX_DEPTH = 100
#: Most nodes of the document with every alias expanded.
MAX_NODES = 1_000_000


def _check_tree(root: yaml.Node, path: Path, what: str) -> None:
    """Refuse a node tree that is too deep, recursive or too large once aliases expand."""
    sizes: dict[int, int] = {}
    active: set[int] = set()

    def size(node: yaml.Node, depth: int) -> int:
        key = id(node)
        if depth > MAX_DEPTH:
            raise ThermocalInputError(
                f"{path}: the {what} is nested more than {MAX_DEPTH} levels deep (line "
                f"{node.start_mark.line + 1}); flatten it"
            )
        if key in sizes:
            return sizes[key]
        if key in active:
            raise ThermocalInputError(
                f"{path}: the {what} has an alias that contains itself (line "
                f"{node.start_mark.line + 1}); remove the anchor/alias"
            )
        total = 1
        if isinstance(node, (yaml.MappingNode, yaml.SequenceNode)):
            active.add(key)
            children = (
                [n for pair in node.value for n in pair]
                if isinstance(node, yaml.MappingNode)
                else node.value
            )
            for child in children:
                total += size(child, depth + 1)
                if total > MAX_NODES:
                    raise ThermocalInputError(
                        f"{path}: the {what} expands to more than {MAX_NODES:,} values through "
                        f"its aliases (&anchor / *alias, line {node.start_mark.line + 1}); "
                        "write the values out or use fewer aliases"
                    )
            active.discard(key)
        sizes[key] = total
        return total

    size(root, 0)


def read_yaml(path: str | Path, *, what: str = "file") -> Any:
    """Parse a YAML file safely.

    Parameters
    ----------
    path : str or Path
    what : str
        What the file is, for messages ("mapping file", "campaign file").

    Returns
    -------
    object
        The parsed document (not None).

    Raises
    ------
    ThermocalInputError
        Missing file, a folder, too large, not UTF-8, not valid YAML (with line and column),
        duplicate keys, nested too deeply, too large once aliases expand, or empty.
    """
    return read_yaml_text(path, what=what)[0]


def read_yaml_text(path: str | Path, *, what: str = "file") -> tuple[Any, str]:
    """:func:`read_yaml` that also returns the file's text (for line numbers in messages)."""
    path = Path(path)
    if not path.exists():
        raise ThermocalInputError(f"{what} {path} does not exist")
    if not path.is_file():
        raise ThermocalInputError(f"{what} {path} is a folder, not a file")
    try:
        n_bytes = path.stat().st_size
        if n_bytes > MAX_BYTES:
            raise ThermocalInputError(
                f"{path}: the {what} has {n_bytes / 1e6:.0f} MB, more than the "
                f"{MAX_BYTES / 1e6:.0f} MB a YAML {what} may have; is it the right file?"
            )
        raw = path.read_bytes()
    except OSError as exc:
        raise ThermocalInputError(f"{what} {path} cannot be read: {exc.strerror}") from None
    if b"\x00" in raw[:8192]:
        raise ThermocalInputError(
            f"{path}: a binary file, not YAML text; give the {what} (a UTF-8 text file)"
        )
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ThermocalInputError(
            f"{path}: not a UTF-8 text file (byte {exc.start}); save the {what} as UTF-8 YAML"
        ) from None
    try:
        loader = _UniqueKeyLoader(text)
        try:
            root = loader.get_single_node()
            if root is None:
                data = None
            else:
                _check_tree(root, path, what)
                data = loader.construct_document(root)
        finally:
            loader.dispose()
    except RecursionError:
        raise ThermocalInputError(
            f"{path}: the YAML of the {what} is nested too deeply (more than a few hundred "
            "levels); flatten it"
        ) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc)
        raise ThermocalInputError(f"{path}: not valid YAML{where}: {problem}") from None
    if data is None:
        raise ThermocalInputError(f"{path}: the {what} is empty")
    return data, text
