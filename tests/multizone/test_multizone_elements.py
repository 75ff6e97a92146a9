"""Element-level (construction) parameters: roles, consistent layer scaling, own copies."""

from __future__ import annotations

import dataclasses
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from thermocal.demos import buildings as generators
from thermocal.errors import ThermocalInputError
from thermocal.multizone.elements import (
    construction_roles,
    element_parameters,
    far_side_constructions,
    is_element_parameter,
    unused_parameters,
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


# ------------------------------------------------------------ the far side of inter-zone walls
REFERENCE = Path(__file__).resolve().parents[1] / "reference"
HOUSE_IDF = REFERENCE / "retrofit_energyplus_house" / "house_v25.idf"
MULTIFAMILY_IDF = REFERENCE / "identification_multifamily" / "multifamily_5A_FF_v25.idf"


def _read(path):
    from thermocal.multizone.idf import read_idf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_idf(path)


@pytest.mark.parametrize(
    ("path", "far", "built"),
    [
        # NREL's house: the attic floor's own construction, the living ceiling's mirror
        (HOUSE_IDF, "reverseCEILING:LIVING", "CEILING:LIVING"),
        # the multifamily prototype: ceilings whose boundary is the attic zone, their partners
        # made by the import
        (MULTIFAMILY_IDF, "Interior Ceiling (reversed)", "Interior Ceiling"),
    ],
)
def test_the_far_side_of_an_inter_zone_wall_is_not_a_parameter(path, far, built):
    """The model builds an inter-zone wall once, from the first surface of the pair: a
    construction only on far sides changes nothing, so it is no parameter to calibrate or to
    measure, and naming it says which construction to set."""
    building = _read(path)
    assert far in building.constructions
    assert far_side_constructions(building) == {far: built}
    params = element_parameters(building)
    assert f"construction/{built}/resistance" in params
    assert not any(f"/{far}/" in name for name in params)
    assert not any(f"/{far}/" in name for name in building.parameters())
    instead = rf"set 'construction/{re.escape(built)}/resistance' instead"
    with pytest.raises(ThermocalInputError, match=instead):
        building.with_parameters({f"construction/{far}/resistance": 1.0})
    # the far side's layers are never read: another layer list there leaves the network as it
    # is; the built side's resistance moves it
    from thermocal.multizone.network import assemble

    def system(b):
        network = assemble(b, 300.0)
        return network.system_matrix(300.0), network.capacity

    matrix, capacity = system(building)
    construction = building.constructions[far]
    thinner = building.replaced(
        constructions={
            **building.constructions,
            far: dataclasses.replace(construction, layers=construction.layers[:1]),
        }
    )
    other_matrix, other_capacity = system(thinner)
    assert abs(other_matrix - matrix).max() == 0.0
    np.testing.assert_array_equal(other_capacity, capacity)
    value = params[f"construction/{built}/resistance"]
    built_changed = building.with_parameters({f"construction/{built}/resistance": 2.0 * value})
    # the far side follows as the mirror of the changed wall, as it was of the nominal one
    assert built_changed.constructions[far].layers == tuple(
        reversed(built_changed.constructions[built].layers)
    )
    assert built_changed.constructions[far].layers != building.constructions[far].layers
    changed_matrix, _ = system(built_changed)
    assert changed_matrix.shape != matrix.shape or abs(changed_matrix - matrix).max() > 0.0


def test_a_pair_of_constructions_that_are_not_mirrors_is_noted(tmp_path):
    text = HOUSE_IDF.read_text()
    mirrored = "Construction, reverseCEILING:LIVING, GP01, IN05;"
    assert mirrored in text
    path = tmp_path / "house.idf"
    path.write_text(text.replace(mirrored, "Construction, reverseCEILING:LIVING, GP01;"))
    notes = [n for n in _read(path).idf_info.notes if "inter-zone wall" in n]
    assert len(notes) == 1 and "from 'CEILING:LIVING'" in notes[0], notes
    assert not [n for n in _read(HOUSE_IDF).idf_info.notes if "inter-zone wall" in n]


def test_the_parameters_the_model_does_not_read_change_nothing():
    """The multifamily prototype's file carries a library of materials its constructions do
    not use, and the far side of its attic floor has its own: every such parameter leaves the
    assembled network as it is, a used one moves it."""
    from thermocal.multizone.network import assemble

    building = _read(MULTIFAMILY_IDF)
    unused = unused_parameters(building)
    materials = {name.split("/")[1] for name in unused}
    assert len(materials) >= 20 and "Batt_R19" in materials, sorted(materials)
    assert all(reason.startswith("material '") for reason in unused.values())

    def system(b):
        network = assemble(b, 300.0)
        return network.system_matrix(300.0), network.capacity

    nominal = building.parameters()
    matrix, capacity = system(building)
    for name in list(unused)[::7]:  # a spread of them: each assembly takes ~0.1 s
        other_matrix, other_capacity = system(building.with_parameters({name: 1.7 * nominal[name]}))
        assert abs(other_matrix - matrix).max() == 0.0, name
        np.testing.assert_array_equal(other_capacity, capacity)
    used = next(n for n in nominal if n.endswith("/conductivity") and n not in unused)
    other_matrix, _ = system(building.with_parameters({used: 1.7 * nominal[used]}))
    assert other_matrix.shape != matrix.shape or abs(other_matrix - matrix).max() > 0.0
