"""The one number formatter (issue 23 item 5): a number, or a placeholder when it is missing."""

from __future__ import annotations

import numpy as np

from thermocal.textformat import format_number


def test_numbers_are_formatted_with_the_spec():
    assert format_number(1234.5, ",.0f") == "1,234"
    assert format_number(np.float64(0.12345), ".3f") == "0.123"
    assert format_number(3, ".1f") == "3.0"
    assert format_number(2.5e-7) == "2.5e-07"


def test_missing_values_get_the_placeholder():
    for value in (None, float("nan"), np.inf, -np.inf, "12", object()):
        assert format_number(value, ".0f") == "n/a"
    assert format_number(np.inf, ".0f", missing="∞") == "∞"
    assert format_number(None, ".0f", missing="") == ""
