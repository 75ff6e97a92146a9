"""Exceptions shown to users.

Every user-facing entry point validates its input and raises :class:`ThermocalInputError`
with a message that names the file, column, row or parameter at fault and says what to do.
The command line prints these messages without a traceback.
"""

from __future__ import annotations


class ThermocalInputError(ValueError):
    """Bad user input: the message names the culprit and the remedy."""
