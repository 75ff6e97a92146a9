"""Element-level (construction) parameters: roles, consistent layer scaling, own copies."""

from __future__ import annotations

import pytest

from thermocal.demos import buildings as generators
from thermocal.errors import ThermocalInputError
from thermocal.multizone.elements import (
    construction_roles,
    element_parameters,
    is_element_parameter,
)
from thermocal.multizone.model import construction_u_value


@pytest.fixture(scope="module")
def house():
    return generators.single_family_house()


def test_roles_follow_the_surfaces(house):
    roles = construction_roles(house)
    assert roles["external wall"] == "exterior_wall"
    assert roles["roof"] == "roof"
    assert roles["cellar floor"] == "ground_floor"
    assert roles["cellar wall"] == "ground_wall"
    assert roles["interior wall"] == "partition"
    assert roles["furniture"] == "internal_mass"


def test_resistance_and_capacity_are_the_layer_sums(house):
    params = element_parameters(house)
    layers = house.construction_layers("external wall")
    assert params["construction/external wall/resistance"] == pytest.approx(
        sum(m.thickness / m.conductivity for m in layers)
    )
    assert params["construction/external wall/heat_capacity"] == pytest.approx(
        sum(m.density * m.specific_heat * m.thickness for m in layers)
    )
    assert all(is_element_parameter(n) for n in params)


def test_a_new_roof_resistance_scales_only_the_roof(house):
    """The roof shares its plaster with the walls and floors: they keep theirs."""
    before = element_parameters(house)
    r_new = 2.5 * before["construction/roof/resistance"]
    changed = house.with_parameters({"construction/roof/resistance": r_new})
    after = element_parameters(changed)
    assert after["construction/roof/resistance"] == pytest.approx(r_new)
    assert after["construction/roof/heat_capacity"] == pytest.approx(
        before["construction/roof/heat_capacity"]
    )
    for name, value in before.items():
        if not name.startswith("construction/roof/"):
            assert after[name] == pytest.approx(value), name
    assert "lime plaster" in changed.constructions["external wall"].layers
    assert "lime plaster (roof)" in changed.constructions["roof"].layers
    # the U-value (ISO 6946 films 0.10 up + 0.04) follows the new resistance
    u = construction_u_value(changed.construction_layers("roof"), inside_resistance=0.10)
    assert u == pytest.approx(1.0 / (0.10 + r_new + 0.04))


def test_material_then_element_level_in_one_mapping(house):
    mapping = {
        "material/hollow clay brick/conductivity": 0.3,
        "construction/external wall/heat_capacity": 2.0e5,
    }
    changed = house.with_parameters(mapping)
    layers = changed.construction_layers("external wall")
    assert sum(m.density * m.specific_heat * m.thickness for m in layers) == pytest.approx(2.0e5)
    brick = next(m for m in layers if m.name.startswith("hollow clay brick"))
    assert brick.conductivity == pytest.approx(0.3)  # capacity scaling leaves resistance alone


@pytest.mark.parametrize(
    ("mapping", "words"),
    [
        ({"construction/attic/resistance": 1.0}, "no construction 'attic'"),
        ({"construction/roof/resistance": -1.0}, "must be > 0"),
    ],
)
def test_bad_element_parameters_are_named(house, mapping, words):
    with pytest.raises(ThermocalInputError, match=words):
        house.with_parameters(mapping)
