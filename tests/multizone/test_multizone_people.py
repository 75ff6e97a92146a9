"""People's sensible heat in the time loop: EnergyPlus' polynomial clipped to [0, activity]."""

from __future__ import annotations

import warnings

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


def test_hot_zone_gets_nothing_from_its_occupants_wherever_their_heat_would_go(tmp_path):
    """Above ~45 C EnergyPlus' sensible heat per person is clipped to zero, radiant share and
    convective share alike: a box held hot by a heater must then have the temperature it has
    without occupants. Before, the 22 C value's radiant share (30 %) stayed on the faces while
    the correction took it out of the air: the same energy, in the wrong place (the
    5ZoneAirCooled offices at eight times their loads ran 0.5 K cold against EnergyPlus)."""
    from test_multizone_idf import _box
    from test_multizone_network import constant_weather

    from thermocal.multizone.idf import IdfImportWarning, read_idf
    from thermocal.multizone.simulation import Simulation

    weather, meta = constant_weather(days=12)  # the box's slab settles over days
    hot = {}
    for label, extra in (
        ("occupied", "People,P,Z1,,People,30,,,0.3,,Act;\nSchedule:Constant,Act,,120;"),
        ("empty", ""),
    ):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", IdfImportWarning)
            building = read_idf(_box(tmp_path, extra=extra, name=f"{label}.idf"))
        sim = Simulation(building, weather, meta, step="15min", store_surfaces=False)
        heat = np.full((len(sim.times), 1), 5000.0)
        hot[label] = sim.run(heat_input=heat).air_temperature["Z1"].iloc[-96:]
    assert hot["empty"].min() > 50.0, hot["empty"].describe()
    assert np.abs(hot["occupied"] - hot["empty"]).max() < 0.02, (
        hot["occupied"].mean(),
        hot["empty"].mean(),
    )
    # the radiant share of the correction goes onto the faces (by area x absorptance)
    assert sim._people_face_w.sum() == pytest.approx(0.0)  # the empty box: nothing
