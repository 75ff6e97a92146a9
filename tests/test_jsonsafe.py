"""The one JSON sanitiser: strict JSON out of nested numpy content."""

from __future__ import annotations

import json
import math

import numpy as np

from thermocal.jsonsafe import json_number, json_ready


def test_nested_numpy_content_becomes_strict_json_with_null_for_missing_values():
    content = {
        "hlc": np.float64(406.5),
        1: (np.int64(3), np.nan, -math.inf),
        "draws": np.array([[1.0, np.nan], [np.inf, 2.5]]),
        "flags": [np.bool_(True), False],
        "name": "house",
        "none": None,
        "f32": np.float32(0.5),
    }
    text = json.dumps(json_ready(content), allow_nan=False)  # raises on NaN or numpy types
    back = json.loads(text)
    assert back == {
        "hlc": 406.5,
        "1": [3, None, None],
        "draws": [[1.0, None], [None, 2.5]],
        "flags": [True, False],
        "name": "house",
        "none": None,
        "f32": 0.5,
    }
    assert type(back["1"][0]) is int


def test_numbers_keep_their_kind():
    assert json_number(np.int32(7)) == 7 and type(json_number(np.int32(7))) is int
    assert json_number(np.float32(np.nan)) is None
    assert json_number(None) is None
    assert json_number(True) is True
