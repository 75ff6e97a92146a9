"""Numbers, lists and durations as text: the one formatter of a number that may be missing, of
a list shortened to its first items, and of a duration as a configuration writes it.

Reports, tables and console summaries print values that can be absent (``None`` in a results
dict cleaned by :func:`thermocal.jsonsafe.json_ready`, NaN in a table, infinity for a payback
that never comes). :func:`format_number` formats such a value with a format spec, or puts a
placeholder in its place, so every table says "n/a" (or the caller's word) the same way.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["duration_text", "format_number", "shortened_list"]


def format_number(value: Any, spec: str = "g", missing: str = "n/a") -> str:
    """``format(value, spec)``, or ``missing`` for a value that is not a finite number.

    Parameters
    ----------
    value : number or None
        Python or numpy scalar, any unit (formatted as given).
    spec : str
        Format specification, e.g. ``".0f"``, ``",.4g"``.
    missing : str
        Text for None, NaN, +-infinity and values that are not numbers.

    Examples
    --------
    >>> format_number(1234.5, ",.0f"), format_number(None, ".1f")
    ('1,234', 'n/a')
    >>> format_number(float("inf"), ".0f", missing="∞")
    '∞'
    """
    if value is None:
        return missing
    try:
        if not np.isfinite(value):
            return missing
    except TypeError:
        return missing
    return format(value, spec)


def shortened_list(items, shown: int = 6) -> str:
    """The first ``shown`` items joined by commas, then `` and K more`` when there are more.

    Parameters
    ----------
    items : sequence of str
    shown : int
        How many items are written out [-].

    Examples
    --------
    >>> shortened_list(["a", "b", "c"], 2)
    'a, b and 1 more'
    """
    items = list(items)
    more = f" and {len(items) - shown} more" if len(items) > shown else ""
    return ", ".join(items[:shown]) + more


def duration_text(td) -> str:
    """A duration as a configuration would write it: ``15min``, ``1h``, ``2h30min``, ``90s``.

    Parameters
    ----------
    td : pandas.Timedelta
        The duration.

    Returns
    -------
    str
    """
    import pandas as pd

    minutes = td / pd.Timedelta(minutes=1)
    if minutes != int(minutes):
        return f"{td.total_seconds():g}s"
    hours, rest = divmod(int(minutes), 60)
    return (f"{hours}h" if hours else "") + (f"{rest}min" if rest or not hours else "")


def unitless_duration(value: Any) -> bool:
    """Whether ``value`` is a duration written as a bare non-zero number (``1``, ``"15"``).

    pandas reads such a number as nanoseconds, so ``--step 1`` meant one nanosecond (a grid
    of 2.7e15 steps, a MemoryError) and ``--silence 1`` a silence of 1 ns. A number needs its
    unit ("1h", "15min"); zero is zero in every unit.

    Parameters
    ----------
    value : str, number or Timedelta
        As given for a duration option or key.

    Returns
    -------
    bool
    """
    import datetime

    if isinstance(value, bool | np.timedelta64 | datetime.timedelta):
        return False  # a Timedelta (a datetime.timedelta) or numpy's: it has its unit
    if isinstance(value, (int, float, np.integer, np.floating)):
        return float(value) != 0.0
    if isinstance(value, str):
        text = value.strip()
        try:
            return float(text) != 0.0
        except ValueError:
            return False
    return False

