"""Numbers written with a decimal comma, as European spreadsheets export them.

Such a file writes ``1.203,5`` for 1203.5 (``.`` groups thousands) and ``1 203,5`` in some locales
(a space, often a non-breaking one). Replacing the comma by a point alone read ``7.476`` (7,476 W)
as 7.476 W: a fit's heat loss coefficient went from 499 to 1,230 W/K without a word
(exploratory test, 2026-11-30). Here a point is read only as a thousands separator, in groups of
three digits; any other point (``7.5``, ``1.5e3``) is ambiguous in such a file and reported, for
the caller to refuse with the file, column and line.
"""

from __future__ import annotations

import re

import pandas as pd

#: a number with points grouping thousands: 7.476, -1.203,5, 12.345.678
_GROUPED = re.compile(r"[-+]?\d{1,3}(?:\.\d{3})+(?:,\d*)?")
#: a space grouping thousands between digits (plain, non-breaking, narrow non-breaking, thin)
_SPACE_GROUPS = re.compile("(?<=\\d)[ \u00a0\u202f\u2009](?=\\d{3}(?:\\D|$))")


def decimal_comma_numbers(values: pd.Series) -> tuple[pd.Series, pd.Series]:
    """Float values of a column written with a decimal comma, and where a point is ambiguous.

    Parameters
    ----------
    values : pandas.Series
        The column as read (strings, or numbers pandas already parsed).

    Returns
    -------
    numbers : pandas.Series of float
        NaN where an entry is empty, not a number, or ambiguous.
    ambiguous : pandas.Series of bool
        Entries with a point that does not group thousands (``7.5``): in a file with decimal
        commas their meaning is unknown.
    """
    if pd.api.types.is_numeric_dtype(values.dtype) and not pd.api.types.is_bool_dtype(
        values.dtype
    ):
        return values.astype(float), pd.Series(False, index=values.index)
    numeric = None
    if pd.api.types.infer_dtype(values, skipna=True) not in ("string", "empty"):
        # numbers among the text (an Excel column of both): those are already numbers
        numeric = values.map(
            lambda v: isinstance(v, int | float) and not isinstance(v, bool) and v == v
        ).astype(bool)
        if numeric.any():
            found = values[numeric].astype(float)
            values = values.where(~numeric, None).astype(object)
        else:
            numeric = None
    text = values.astype("string").str.strip().str.replace(_SPACE_GROUPS, "", regex=True)
    grouped = text.str.fullmatch(_GROUPED).fillna(False).astype(bool)
    ambiguous = (text.str.contains(".", regex=False).fillna(False).astype(bool)) & ~grouped
    cleaned = text.where(~grouped, text.str.replace(".", "", regex=False))
    cleaned = cleaned.str.replace(",", ".", regex=False).where(~ambiguous)
    numbers = pd.to_numeric(cleaned, errors="coerce").astype(float)
    if numeric is not None:
        numbers[numeric] = found
    return numbers, ambiguous
