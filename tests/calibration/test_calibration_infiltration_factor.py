"""One factor on every zone's infiltration (``parameters: {infiltration: building}``): the
element a campaign can determine in a building whose file gives each zone its own
infiltration object (the DOE prototypes), where 56 separate rates are not determined."""

from __future__ import annotations

import numpy as np
import pytest

from thermocal.calibration.space import ParameterSpace
from thermocal.calibration.workflow import candidate_parameters
from thermocal.demos import buildings
from thermocal.errors import ThermocalInputError
from thermocal.multizone.parameters import INFILTRATION_FACTOR, parameter_unit


@pytest.fixture(scope="module")
def house():
    return buildings.single_family_house()


def test_factor_scales_every_zone_and_follows_other_changes(house):
    nominal = {name: z.infiltration_ach for name, z in house.zones.items()}
    assert sum(v > 0 for v in nominal.values()) >= 2
    scaled = house.with_parameters({INFILTRATION_FACTOR: 1.4})
    for name, zone in scaled.zones.items():
        assert zone.infiltration_ach == pytest.approx(1.4 * nominal[name], rel=1e-12)
    # a zone's own rate is set first, then the factor applies to it
    zone = next(n for n, v in nominal.items() if v > 0)
    both = house.with_parameters({f"zone/{zone}/infiltration_ach": 2.0, INFILTRATION_FACTOR: 0.5})
    assert both.zones[zone].infiltration_ach == pytest.approx(1.0)
    # the envelope is untouched
    assert both.parameters().keys() == house.parameters().keys()
    assert house.with_parameters({INFILTRATION_FACTOR: 1.0}).parameters() == house.parameters()
    with pytest.raises(ThermocalInputError, match="non-negative"):
        house.with_parameters({INFILTRATION_FACTOR: -1.0})


def test_candidates_trade_the_zone_rates_for_one_factor(house):
    per_zone = candidate_parameters(house, "element")
    factor = candidate_parameters(house, "element", infiltration="building")
    zone_rates = [
        n for n in per_zone if n.endswith("/infiltration_ach") or n.startswith("infiltration/")
    ]
    assert zone_rates
    assert not [n for n in factor if n.endswith("/infiltration_ach")]
    assert factor[INFILTRATION_FACTOR] == 1.0
    assert set(factor) - {INFILTRATION_FACTOR} == set(per_zone) - set(zone_rates)
    assert parameter_unit(INFILTRATION_FACTOR) == "-"
    space = ParameterSpace.from_parameters(factor, include=["infiltration/*"])
    assert space.names == (INFILTRATION_FACTOR,)
    np.testing.assert_allclose([space.lower[0], space.upper[0]], [0.25, 1.75])
    with pytest.raises(ThermocalInputError, match="'per_zone' or 'building'"):
        candidate_parameters(house, "element", infiltration="zones")


def test_factor_replaces_an_earlier_factor_instead_of_compounding(house):
    """A campaign changes one simulation's parameters sample after sample
    (``Simulation.set_parameters`` on the building as last changed): the factor applies to
    the rates before any factor, and 1 restores the nominal building."""
    nominal = {name: z.infiltration_ach for name, z in house.zones.items()}
    first = house.with_parameters({INFILTRATION_FACTOR: 1.4})
    second = first.with_parameters({INFILTRATION_FACTOR: 0.8})
    back = second.with_parameters({INFILTRATION_FACTOR: 1.0})
    for name in nominal:
        assert second.zones[name].infiltration_ach == pytest.approx(0.8 * nominal[name])
        assert back.zones[name].infiltration_ach == pytest.approx(nominal[name])
    # other changes keep the factor's base: the envelope changes, the rates stay nominal x 0.8
    other = second.with_parameters({"window/" + next(iter(house.window_types)) + "/u_value": 1.0})
    assert [z.infiltration_ach for z in other.zones.values()] == pytest.approx(
        [0.8 * v for v in nominal.values()]
    )
    again = other.with_parameters({INFILTRATION_FACTOR: 0.5})
    assert [z.infiltration_ach for z in again.zones.values()] == pytest.approx(
        [0.5 * v for v in nominal.values()]
    )


def test_a_calibrated_building_reports_the_factor_it_was_given(house):
    calibrated = house.with_parameters({INFILTRATION_FACTOR: 1.3})
    values = candidate_parameters(calibrated, "element", infiltration="building")
    assert values[INFILTRATION_FACTOR] == pytest.approx(1.3)
    assert candidate_parameters(house, "element", infiltration="building")[
        INFILTRATION_FACTOR
    ] == pytest.approx(1.0)
