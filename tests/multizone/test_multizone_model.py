"""Data model of the multi-zone building: validation messages and parameter names."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.multizone.model import (
    Building,
    Construction,
    Material,
    NoMassMaterial,
    Surface,
    Window,
    WindowType,
    Zone,
    construction_u_value,
)


def _parts():
    materials = [
        Material("brick", 0.8, 1800, 900, 0.25),
        NoMassMaterial("air gap", 0.18),
        Material("plaster", 0.7, 1400, 1000, 0.015),
    ]
    constructions = [Construction("wall", ("brick", "air gap", "plaster"))]
    window_types = [WindowType("double", 2.7, 0.6)]
    zones = [Zone("living", 60.0, 24.0, infiltration_ach=0.5), Zone("kitchen", 30.0, 12.0)]
    surfaces = [
        Surface("living south", "living", "wall", 20.0, 90, 180),
        Surface("partition a", "living", "wall", 10.0, 90, 90, "zone", "kitchen", "partition b"),
        Surface("partition b", "kitchen", "wall", 10.0, 90, 270, "zone", "living", "partition a"),
    ]
    windows = [Window("w1", "living south", "double", 4.0, frame_fraction=0.2)]
    return materials, constructions, window_types, zones, surfaces, windows


def _building(**changes):
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    kwargs = dict(
        name="test",
        materials=materials,
        constructions=constructions,
        window_types=window_types,
        zones=zones,
        surfaces=surfaces,
        windows=windows,
    )
    kwargs.update(changes)
    return Building(**kwargs)


def test_valid_building_and_net_area():
    building = _building()
    assert building.net_area("living south") == pytest.approx(16.0)
    assert building.windows["w1"].glazed_area == pytest.approx(3.2)


def test_unknown_material_names_construction():
    constructions = [Construction("wall", ("brick", "concrete", "plaster"))]
    with pytest.raises(ThermocalInputError, match=r"construction 'wall'.*material 'concrete'"):
        _building(constructions=constructions)


def test_unknown_construction_names_surface():
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    surfaces[0] = Surface("living south", "living", "wal", 20.0, 90, 180)
    with pytest.raises(ThermocalInputError, match=r"surface 'living south'.*construction 'wal'"):
        _building(surfaces=surfaces)


def test_zero_thickness_names_material():
    with pytest.raises(ThermocalInputError, match=r"material 'brick': thickness"):
        Material("brick", 0.8, 1800, 900, 0.0)


def test_missing_zone_names_surface():
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    surfaces[0] = Surface("living south", "lounge", "wall", 20.0, 90, 180)
    with pytest.raises(ThermocalInputError, match=r"surface 'living south'.*zone 'lounge'"):
        _building(surfaces=surfaces)


def test_interzone_surface_without_partner():
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    surfaces = surfaces[:2]  # partition b missing
    with pytest.raises(ThermocalInputError, match=r"surface 'partition a'.*'partition b'"):
        _building(surfaces=surfaces)
    lonely = Surface("partition a", "living", "wall", 10.0, 90, 90, "zone", "kitchen", None)
    with pytest.raises(ThermocalInputError, match=r"surface 'partition a'.*no partner"):
        _building(surfaces=[surfaces[0], lonely])


def test_negative_area_names_surface_and_window():
    with pytest.raises(ThermocalInputError, match=r"surface 'x' \(zone 'living'\): area"):
        Surface("x", "living", "wall", -3.0)
    with pytest.raises(ThermocalInputError, match=r"window 'w': area"):
        Window("w", "living south", "double", -1.0)


def test_windows_larger_than_host():
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    windows = [Window("w1", "living south", "double", 25.0)]
    with pytest.raises(ThermocalInputError, match=r"surface 'living south'.*gross area"):
        _building(windows=windows)


def test_duplicate_names():
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    with pytest.raises(ThermocalInputError, match=r"zone 'living' is defined twice"):
        _building(zones=zones + [Zone("living", 10.0, 4.0)])


def test_parameters_roundtrip_and_unknown_name():
    building = _building()
    params = building.parameters()
    assert params["material/brick/conductivity"] == 0.8
    assert params["material/air gap/resistance"] == 0.18
    assert params["window/double/shgc"] == 0.6
    assert params["zone/living/infiltration_ach"] == 0.5
    changed = building.with_parameters(
        {"material/brick/thickness": 0.3, "window/double/u_value": 1.1}
    )
    assert changed.materials["brick"].thickness == 0.3
    assert building.materials["brick"].thickness == 0.25  # original untouched
    assert changed.window_types["double"].u_value == 1.1
    with pytest.raises(ThermocalInputError, match="did you mean 'material/brick/conductivity'"):
        building.with_parameters({"material/brick/conductivty": 1.0})
    with pytest.raises(ThermocalInputError, match=r"material 'brick': thickness"):
        building.with_parameters({"material/brick/thickness": 0.0})


def test_infiltration_groups():
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    zones = [
        Zone("living", 60.0, 24.0, infiltration_ach=0.5, infiltration_group="east"),
        Zone("kitchen", 30.0, 12.0, infiltration_ach=0.3, infiltration_group="east"),
    ]
    building = _building(zones=zones)
    params = building.parameters()
    assert "infiltration/east/ach" in params and "zone/living/infiltration_ach" not in params
    assert params["infiltration/east/ach"] == pytest.approx(0.4)
    # the group's mean rate: members scaled in proportion (before: both set to 0.8, so the
    # group's own nominal value changed a building whose members differ)
    changed = building.with_parameters({"infiltration/east/ach": 0.8})
    assert [z.infiltration_ach for z in changed.zones.values()] == pytest.approx([1.0, 0.6])
    same = building.with_parameters({"infiltration/east/ach": params["infiltration/east/ach"]})
    assert [z.infiltration_ach for z in same.zones.values()] == pytest.approx([0.5, 0.3])


def test_infiltration_group_rates_do_not_depend_on_the_samples_before():
    """A campaign sets a group sample after sample on one building: a sample's rates must be
    those of the sample alone, bit for bit (scaling the last rates by a ratio drifted by
    round-off, so the same sample's identified heat depended on its worker's history), and
    the nominal value gives the nominal rates back exactly."""
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    zones = [
        Zone("living", 60.0, 24.0, infiltration_ach=0.5, infiltration_group="east"),
        Zone("kitchen", 30.0, 12.0, infiltration_ach=0.3, infiltration_group="east"),
        Zone("bath", 10.0, 4.0, infiltration_ach=0.7, infiltration_group="east"),
    ]
    building = _building(zones=zones)
    name = "infiltration/east/ach"
    nominal = building.parameters()[name]

    def rates(b):
        return [z.infiltration_ach for z in b.zones.values()]

    direct = rates(building.with_parameters({name: 0.37}))
    walked = building
    for value in (0.81, 0.2, 0.613, 0.37):
        walked = walked.with_parameters({name: value})
    assert rates(walked) == direct
    assert rates(walked.with_parameters({name: nominal})) == rates(building)
    # a member changed by its own name since starts a new base: its new rate is scaled
    moved = walked.with_parameters({"zone/bath/infiltration_ach": 1.0})
    again = moved.with_parameters({name: 0.4})
    expected = np.array(rates(moved)) * 0.4 / np.mean(rates(moved))
    assert rates(again) == pytest.approx(expected, rel=1e-14)


def test_u_value_hand_computed():
    layers = [Material("brick", 0.8, 1800, 900, 0.24), NoMassMaterial("gap", 0.18)]
    expected = 1.0 / (0.13 + 0.04 + 0.24 / 0.8 + 0.18)
    assert construction_u_value(layers) == pytest.approx(expected, rel=1e-12)


def test_window_type_layered_optics_and_shgc_scaling():
    wt = WindowType(
        "layered",
        2.7,
        0.79,
        solar_transmittance=0.75,
        pane_absorptances=(0.064, 0.052),
        incidence_angles=(0.0, 30.0, 60.0, 90.0),
        relative_transmittance=(1.0, 0.98, 0.83, 0.0),
    )
    assert wt.transmittance(60.0) == pytest.approx(0.75 * 0.83)
    assert wt.transmittance(90.0) == 0.0
    # hemispherical transmittance: 2 * integral of tau(theta) cos sin, below the normal value
    assert 0.5 < wt.diffuse_transmittance_value < 0.75
    scaled = wt.with_shgc(0.395)
    assert scaled.solar_transmittance == pytest.approx(0.375)
    assert np.allclose(scaled.pane_absorptances, (0.032, 0.026))
    with pytest.raises(ThermocalInputError, match="exceed 1"):
        WindowType("bad", 2.7, 0.8, solar_transmittance=0.9, pane_absorptances=(0.1, 0.1))


def test_default_angular_transmittance_is_fresnel():
    wt = WindowType("simple", 2.8, 0.7)
    rel = wt.relative_transmittance_at(np.array([0.0, 40.0, 60.0, 80.0, 90.0]))
    assert rel[0] == pytest.approx(1.0)
    assert np.all(np.diff(rel) < 0)
    # clear double glazing keeps ~0.95 at 40 deg and ~0.8 at 60 deg (Duffie & Beckman fig. 5.3.1)
    assert 0.93 < rel[1] < 0.99
    assert 0.75 < rel[2] < 0.9


def test_a_zone_without_surfaces_or_infiltration_is_refused():
    """Before: accepted, and reported at 20.0 C with 0 kWh of heat for the whole run."""
    materials, constructions, window_types, zones, surfaces, windows = _parts()
    zones = [*zones, Zone("store", 20.0, 8.0)]
    with pytest.raises(ThermocalInputError, match=r"zone\(s\) \['store'\] have no surfaces"):
        _building(zones=zones)
    _building(zones=[*zones[:-1], Zone("store", 20.0, 8.0, infiltration_ach=0.5)])  # air: fine


def test_zone_gains_written_in_kilowatts_are_named():
    """Before: 0.3 in a building file was taken as 0.3 W (the heating unchanged). A Zone made in
    code (an IDF's annual mean of a small scheduled gain) may be below 1 W."""
    from thermocal.multizone.files import building_from_dict, building_to_dict

    materials, constructions, window_types, zones, surfaces, windows = _parts()
    data = building_to_dict(_building())
    data["zones"][0]["internal_gains"] = 0.3
    with pytest.raises(ThermocalInputError, match=r"0.3 W .* in kW\? then write 300"):
        building_from_dict(data)
    assert Zone("shaft", 10.0, 4.0, internal_gains=0.4).internal_gains == 0.4


def test_an_shgc_beyond_what_layered_glazing_can_give_is_refused_and_a_campaign_stops_there():
    """Found on the EnergyPlus twin with a low-e pane: an SHGC above the layered optics'
    reach (transmittance + pane absorptances scaled to 1) was simulated at that reach while the
    window type, the campaign's samples and the calibrated file said the value asked for."""
    wt = WindowType(
        "layered",
        2.7,
        0.79,
        solar_transmittance=0.75,
        pane_absorptances=(0.064, 0.052),
    )
    assert wt.shgc_limit == pytest.approx(0.79 / 0.866)
    assert wt.with_shgc(wt.shgc_limit).solar_transmittance == pytest.approx(0.75 / 0.866)
    with pytest.raises(ThermocalInputError, match=r"shgc 0\.95 is beyond .* at most 0\.9122"):
        wt.with_shgc(0.95)
    assert WindowType("simple", 2.7, 0.79).shgc_limit == 1.0
    from thermocal.multizone.elements import window_limits

    building = SimpleNamespace(window_types={"layered": wt, "simple": WindowType("s", 1.0, 0.5)})
    limits = window_limits(building)
    assert limits["window/layered/shgc"][1] == pytest.approx(wt.shgc_limit, rel=1e-8)
    assert limits["window/simple/shgc"][1] == pytest.approx(1.0, rel=1e-8)
