"""The compiled time loop reproduces the outputs stored before its speed-ups (issue 22).

``tests/reference/kernel_outputs/kernel_outputs.npz`` was written by the kernel of commit
de53112 (``make_reference.py`` next to it; regenerated on 2026-11-30 for the windows' ISO 15099
room-side convection and on 2026-11-30 for its bound in the time loop): free run, ideal
heating and cooling, exact inverse on air and on operative temperature, PID, on the generated
single-family house. A faster kernel must give the same numbers: every array within 1e-9 of
its largest magnitude (bit for bit on the machine that generated it; another CPU may round
fused multiply-adds differently).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from conftest import load_script

REFERENCE = Path(__file__).resolve().parents[1] / "reference" / "kernel_outputs"


def _maker():
    return load_script(REFERENCE / "make_reference.py")


@pytest.fixture(scope="module")
def outputs():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return _maker().kernel_outputs()


@pytest.mark.parametrize(
    "key",
    [
        "free/air",
        "free/mrt",
        "ideal/air",
        "ideal/heating",
        "ideal/cooling",
        "inverse/heat",
        "inverse/air",
        "operative/heat",
        "operative/air",
        "pid/heat",
        "pid/air",
    ],
)
def test_kernel_reproduces_stored_outputs(outputs, key):
    stored = np.load(REFERENCE / "kernel_outputs.npz")[key]
    now = outputs[key]
    assert now.shape == stored.shape
    scale = np.abs(stored).max()
    assert scale > 0.0  # not an all-zero case (e.g. the cooling happens)
    assert np.abs(now - stored).max() <= 1e-9 * scale, (key, np.abs(now - stored).max(), scale)
