"""People's sensible heat in the time loop: EnergyPlus' polynomial clipped to [0, activity]."""

from __future__ import annotations

import numpy as np
import pytest

from thermocal.multizone._kernel import PEOPLE_T0, people_excess
from thermocal.multizone.idf.loads import (
    PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE,
    people_sensible_coefficients,
    people_sensible_heat,
)


def test_kernel_reference_temperature_is_the_import_one():
    assert PEOPLE_T0 == PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE


@pytest.mark.parametrize("activity", [70.0, 117.24, 200.0, 400.0])
def test_people_correction_is_the_clipped_sensible_heat(activity):
    """The kernel's correction plus the scheduled value at 22 C is EnergyPlus' clipped sensible
    heat at every temperature: occupants never become heat sinks (unclipped, 11 people at
    117 W give -0.4 kW at 44 C) nor give more than their metabolic heat."""
    number = 11.0
    a, b, c = (number * v for v in people_sensible_coefficients(activity))
    for t in np.linspace(-5.0, 60.0, 131):
        expected = number * (
            people_sensible_heat(activity, t) - people_sensible_heat(activity, PEOPLE_T0)
        )
        got = people_excess(t, a, b, c, number * activity)
        assert got == pytest.approx(expected, abs=1e-9 * number * activity)
    # above ~35-45 C the polynomial is negative: the clip is what the correction relies on
    hot = 60.0
    assert a + b * hot + c * hot * hot < 0.0
    assert people_excess(hot, a, b, c, number * activity) == pytest.approx(
        -number * float(people_sensible_heat(activity, PEOPLE_T0))
    )
