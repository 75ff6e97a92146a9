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


def test_report_tables_print_no_negative_zero():
    """A value rounded to zero in a report table had a sign ("-0" in the calibration demo's
    "share recovered"; exploratory test, 2026-11-30)."""
    import pandas as pd

    from thermocal.report.html import HtmlReport

    report = HtmlReport("t")
    report.table(pd.DataFrame({"x": [-1e-9, -0.5, 2.0]}), number_format="{:.0f}")
    text = report.html() if hasattr(report, "html") else str(report._current)
    assert "<td class=\"num\">0</td>" in text and "-0<" not in text
    assert "<td class=\"num\">-0</td>" not in text and "<td class=\"num\">2</td>" in text


def test_report_table_with_an_unnamed_index_heads_it_with_nothing():
    """The identify report's tuning table lost its row names (index not shown), and the
    calibrate report's confirmation table showed pandas' 'index' header (2026-11-30)."""
    import pandas as pd

    from thermocal.report.html import HtmlReport

    report = HtmlReport("t")
    frame = pd.DataFrame({"exact": [1.0, 2.0]}, index=["ultimate gain Ku [W/K]", "period"])
    report.table(frame, index=True)
    text = report.html() if hasattr(report, "html") else str(report._current)
    assert "ultimate gain Ku [W/K]" in text
    assert ">index<" not in text
