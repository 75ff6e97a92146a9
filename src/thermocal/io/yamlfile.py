"""Safe YAML reading for every thermocal file (mapping, identification, campaign files).

Safe loading only (no Python objects), UTF-8 with a clear message otherwise, duplicate keys
rejected with their line (PyYAML lets the last one win silently), an empty file rejected.
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
        Missing file, a folder, not UTF-8, not valid YAML (with line and column), duplicate
        keys, or empty.
    """
    path = Path(path)
    if not path.exists():
        raise ThermocalInputError(f"{what} {path} does not exist")
    if not path.is_file():
        raise ThermocalInputError(f"{what} {path} is a folder, not a file")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ThermocalInputError(
            f"{path}: not a UTF-8 text file (byte {exc.start}); save the {what} as UTF-8 YAML"
        ) from None
    try:
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader subclass
    except RecursionError:
        raise ThermocalInputError(f"{path}: the YAML is nested too deeply") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc)
        raise ThermocalInputError(f"{path}: not valid YAML{where}: {problem}") from None
    if data is None:
        raise ThermocalInputError(f"{path}: the {what} is empty")
    return data
