"""JSON-ready values: the one place that turns numpy and non-finite numbers into JSON content.

JSON has no NaN or infinity and does not know numpy types. Every ``*.json`` thermocal writes
(results, summaries, campaign records) goes through :func:`json_ready`, so a missing value is
``null`` everywhere and a reader in any language gets plain numbers.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["json_number", "json_ready"]


def json_number(value: Any) -> int | float | None:
    """A number as JSON holds it: int stays int, NaN and infinities become None.

    Parameters
    ----------
    value : number or None
        Python or numpy scalar (any unit; returned unchanged apart from the type).
    """
    if value is None:
        return None
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, int | np.integer):
        return int(value)
    value = float(value)
    return value if math.isfinite(value) else None


def json_ready(obj: Any) -> Any:
    """``obj`` with mappings' keys as strings, tuples and arrays as lists, numpy scalars as
    Python values and non-finite numbers as None; other values unchanged.

    Parameters
    ----------
    obj : Any
        Nested dicts, lists, tuples, numpy arrays and scalars.
    """
    if isinstance(obj, dict):
        return {str(k): json_ready(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [json_ready(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [json_ready(v) for v in obj.tolist()]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float | int) and not isinstance(obj, bool):
        return json_number(obj)
    return obj
