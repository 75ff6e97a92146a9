"""Tests of thermocal.io.envelope: schema, plausibility messages, conveniences, file reading."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest
from pydantic import ValidationError

from thermocal.errors import ThermocalInputError
from thermocal.io.envelope import (
    EnvelopeDescription,
    envelope_from_dict,
    read_envelope,
    write_envelope,
)

REPO_ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = REPO_ROOT / "examples" / "buildings" / "single_family_house_1953.yaml"


def minimal() -> dict:
    """A small, valid building description (a box with one wall per orientation)."""
    walls = [
        {"name": f"wall {o}", "type": "external_wall", "area": 20.0, "u_value": 0.3, "azimuth": a}
        for o, a in (("N", 0), ("E", 90), ("S", 180), ("W", 270))
    ]
    return {
        "name": "box",
        "location": {"latitude": 47.38, "longitude": 8.54, "timezone": "Europe/Zurich"},
        "floors": 1,
        "heated_floor_area": 100.0,
        "volume": 250.0,
        "emitter": "floor_heating",
        "components": [
            *walls,
            {"name": "roof", "type": "roof", "area": 100.0, "u_value": 0.2, "tilt": 0},
            {
                "name": "window S",
                "type": "window",
                "area": 10.0,
                "u_value": 1.0,
                "azimuth": "S",
                "g_value": 0.5,
            },
            {"name": "slab", "type": "ground_floor", "area": 100.0, "u_value": 0.25},
        ],
    }


def error_text(data: dict) -> str:
    with pytest.raises(ThermocalInputError) as info:
        envelope_from_dict(data, source="house.yaml")
    return str(info.value)


# ------------------------------------------------------------------------------ valid input
def test_defaults_by_component_type():
    building = EnvelopeDescription.model_validate(minimal())
    wall = building.component("wall E")
    assert wall.tilt == 90.0 and wall.azimuth == 90.0 and wall.absorptance == 0.6
    assert wall.g_value is None and wall.frame_fraction is None
    window = building.windows[0]
    assert window.azimuth == 180.0  # compass name "S"
    assert window.frame_fraction == 0.3 and window.shading_factor == 1.0
    assert window.absorptance is None
    slab = building.component("slab")
    assert slab.tilt == 180.0  # floors face down
    assert building.thermal_bridge_allowance == 0.05
    assert building.ground is None and building.construction_year is None


def test_transmission_coefficient_is_sum_ua_plus_thermal_bridges():
    building = EnvelopeDescription.model_validate(minimal())
    sum_ua = 4 * 20 * 0.3 + 100 * 0.2 + 10 * 1.0 + 100 * 0.25
    opaque = 4 * 20 + 100 + 100
    assert building.opaque_area == pytest.approx(opaque)
    assert building.envelope_area == pytest.approx(opaque + 10)
    assert building.thermal_bridge_heat_transfer_coefficient == pytest.approx(0.05 * opaque)
    assert building.transmission_heat_transfer_coefficient == pytest.approx(sum_ua + 0.05 * opaque)
    per_type = building.heat_transfer_coefficients()
    assert per_type["external_wall"] == pytest.approx(24.0)
    assert per_type["door"] == 0.0 and per_type["cellar_ceiling"] == 0.0


def test_area_and_components_of_type():
    building = EnvelopeDescription.model_validate(minimal())
    assert building.area("external_wall") == pytest.approx(80.0)
    assert building.area("window") == pytest.approx(10.0)
    assert building.area("door") == 0.0
    assert building.area() == pytest.approx(building.envelope_area)
    assert [c.name for c in building.components_of_type("external_wall")] == [
        "wall N",
        "wall E",
        "wall S",
        "wall W",
    ]
    with pytest.raises(ThermocalInputError, match="did you mean 'external_wall'"):
        building.components_of_type("external_walls")
    with pytest.raises(ThermocalInputError, match="did you mean 'wall S'"):
        building.component("wall s")


def test_example_building_file_is_valid_and_matches_paper_000_audit():
    building = read_envelope(EXAMPLE)
    assert building.floors == 3 and building.construction_year == 1953
    assert building.emitter == "radiators"
    assert building.ground is not None and building.ground.basement == "unheated"
    kinds = {c.type for c in building.components}
    assert kinds == {"roof", "external_wall", "window", "door", "cellar_ceiling", "ground_floor"}
    # windows in all four orientations
    assert sorted(w.azimuth for w in building.windows) == [0.0, 90.0, 180.0, 270.0]
    # H_T + ventilation 0.34 Wh/(m3 K) x 0.3 1/h x V reproduces the audit HLC of 512 W/K
    ventilation = 0.34 * 0.3 * building.volume
    assert building.transmission_heat_transfer_coefficient + ventilation == pytest.approx(
        512, abs=2
    )
    # the computed conveniences agree with a hand sum over the file
    hand = sum(c.u_value * c.area for c in building.components)
    hand += 0.05 * sum(c.area for c in building.components if c.type != "window")
    assert building.transmission_heat_transfer_coefficient == pytest.approx(hand)


def test_toml_and_yaml_give_the_same_building(tmp_path):
    import yaml

    data = minimal()
    yaml_path = tmp_path / "b.yaml"
    yaml_path.write_text(yaml.safe_dump(data))
    toml_lines = [
        'name = "box"',
        "floors = 1",
        "heated_floor_area = 100.0",
        "volume = 250.0",
        'emitter = "floor_heating"',
        "[location]",
        "latitude = 47.38",
        "longitude = 8.54",
        'timezone = "Europe/Zurich"',
    ]
    for component in data["components"]:
        toml_lines.append("[[components]]")
        for key, value in component.items():
            toml_lines.append(f"{key} = {value!r}".replace("'", '"'))
    toml_path = tmp_path / "b.toml"
    toml_path.write_text("\n".join(toml_lines) + "\n")
    assert read_envelope(toml_path) == read_envelope(yaml_path)


def test_model_dump_round_trips():
    building = EnvelopeDescription.model_validate(minimal())
    assert EnvelopeDescription.model_validate(building.model_dump()) == building


def test_timezone_as_offset_in_hours():
    data = minimal()
    data["location"]["timezone"] = 1
    assert EnvelopeDescription.model_validate(data).location.timezone == 1.0


# ------------------------------------------------------------------------------ bad input
def test_wall_u_value_of_19_is_reported_as_typo_for_0_19():
    data = minimal()
    data["components"][2]["u_value"] = 19
    message = error_text(data)
    assert "house.yaml" in message
    assert "components[2] ('wall S')" in message
    assert "u_value = 19 W/(m2 K)" in message
    assert "0.08 to 4 W/(m2 K)" in message
    assert "external wall" in message
    assert "did you mean 0.19" in message


def test_window_u_value_range_differs_from_opaque():
    data = minimal()
    data["components"][5]["u_value"] = 5.5  # single glazing: plausible for a window
    EnvelopeDescription.model_validate(data)
    data["components"][0]["u_value"] = 5.5  # not for a wall
    message = error_text(data)
    assert "wall N" in message and "0.08 to 4 W/(m2 K)" in message
    data = minimal()
    data["components"][5]["u_value"] = 0.3  # below the best windows
    assert "0.5 to 6 W/(m2 K)" in error_text(data)


@pytest.mark.parametrize(
    ("index", "field", "value", "expected"),
    [
        (5, "g_value", 60, ["g_value = 60", "0.1 to 0.9", "did you mean 0.6", "percentage"]),
        (5, "frame_fraction", 30, ["frame_fraction = 30", "0 to 0.6", "did you mean 0.3"]),
        (5, "shading_factor", 1.5, ["shading_factor = 1.5", "0 to 1"]),
        (0, "area", -3, ["area = -3 m2", "> 0 m2"]),
        (0, "area", 0, ["area = 0 m2"]),
        (0, "tilt", 200, ["tilt = 200 deg", "0 to 180 deg"]),
        (0, "azimuth", 400, ["azimuth = 400 deg", "0 to 360 deg"]),
        (0, "azimuth", -90, ["azimuth = -90 deg", "did you mean 270"]),
        (0, "absorptance", 1.2, ["absorptance = 1.2", "0 to 1"]),
    ],
)
def test_component_range_messages(index, field, value, expected):
    data = minimal()
    data["components"][index][field] = value
    message = error_text(data)
    for part in expected:
        assert part in message, (part, message)


def test_window_needs_g_value_and_opaque_rejects_window_fields():
    data = minimal()
    del data["components"][5]["g_value"]
    assert "g_value [-] is required for a window" in error_text(data)
    data = minimal()
    data["components"][0]["g_value"] = 0.5
    assert "g_value applies to windows only" in error_text(data)
    data = minimal()
    data["components"][5]["absorptance"] = 0.5
    assert "absorptance applies to opaque components only" in error_text(data)


def test_tilted_roof_needs_azimuth_flat_roof_does_not():
    data = minimal()
    del data["components"][4]["tilt"]  # default 35 deg: pitched
    message = error_text(data)
    assert "azimuth is required for a roof with tilt 35 deg" in message
    assert "tilt: 0 for a flat roof" in message


def test_unknown_field_and_bad_literal_named():
    data = minimal()
    data["components"][1]["u-value"] = 0.3
    message = error_text(data)
    assert "unknown field 'u-value'" in message and "did you mean 'u_value'" in message
    data = minimal()
    data["emitter"] = "radiator"
    message = error_text(data)
    assert "emitter" in message and "'radiator'" in message and "radiators" in message
    data = minimal()
    data["components"][0]["type"] = "wall"
    assert "components[0] ('wall N').type" in error_text(data)


def test_missing_required_field_named():
    data = minimal()
    del data["volume"]
    assert "required field 'volume' is missing" in error_text(data)


def test_building_level_consistency():
    data = minimal()
    data["volume"] = 25.0  # 0.25 m rooms: litres? a typo
    message = error_text(data)
    assert "volume / heated_floor_area" in message and "0.25 m" in message
    data = minimal()
    data["floors"] = 12
    assert "floors = 12 is outside the plausible range 1 to 10" in error_text(data)
    data = minimal()
    data["components"][1]["name"] = "wall N"
    assert "already used by components[0]" in error_text(data)
    data = minimal()
    data["thermal_bridge_allowance"] = 5
    assert "did you mean 0.05" in error_text(data)


def test_location_and_ground_ranges():
    data = minimal()
    data["location"]["latitude"] = 147.4
    assert "latitude = 147.4 deg N is outside the plausible range -90 to 90" in error_text(data)
    data = minimal()
    data["location"]["timezone"] = "Europe/Zurch"
    assert "not a known time-zone name" in error_text(data)
    data = minimal()
    data["ground"] = {"perimeter": 40, "wall_thickness": 30}
    message = error_text(data)
    assert "wall_thickness = 30 m" in message and "did you mean 0.3 (centimetres" in message
    data = minimal()
    data["ground"] = {"perimeter": 40, "wall_thickness": 0.3, "basement_depth": 2.0}
    assert "basement = 'none'" in error_text(data)
    data = minimal()
    data["components"][6]["type"] = "cellar_ceiling"
    data["ground"] = {"perimeter": 40, "wall_thickness": 0.3}
    assert "floor over an unheated cellar, but ground.basement = 'none'" in error_text(data)
    data["ground"]["basement"] = "heated"
    assert "ground.basement = 'heated'" in error_text(data)
    data["ground"]["basement"] = "unheated"
    EnvelopeDescription.model_validate(data)


def test_all_problems_listed_at_once():
    data = minimal()
    data["components"][0]["u_value"] = 30
    data["components"][5]["g_value"] = 65
    message = error_text(data)
    assert "(2 problems)" in message
    assert "did you mean 0.3" in message and "did you mean 0.65" in message


def test_model_validate_raises_pydantic_error_with_the_same_text():
    data = minimal()
    data["components"][2]["u_value"] = 19
    with pytest.raises(ValidationError, match="did you mean 0.19"):
        EnvelopeDescription.model_validate(data)


def test_yaml_errors_carry_line_numbers(tmp_path):
    text = EXAMPLE.read_text().replace(
        "u_value: 0.80\n    azimuth: 90.0", "u_value: 80\n    azimuth: 90.0"
    )
    path = tmp_path / "house.yaml"
    path.write_text(text)
    with pytest.raises(ThermocalInputError) as info:
        read_envelope(path)
    message = str(info.value)
    lines = text.splitlines()
    start = lines.index("  - name: wall east")
    line = next(i + 1 for i in range(start, len(lines)) if "u_value: 80" in lines[i])
    assert f"components[3] ('wall east') (line {line})" in message
    assert "did you mean 0.8" in message


def test_file_level_errors(tmp_path):
    with pytest.raises(ThermocalInputError, match="does not exist"):
        read_envelope(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: [unclosed\n")
    with pytest.raises(ThermocalInputError, match="not valid YAML at line"):
        read_envelope(bad)
    bad_toml = tmp_path / "bad.toml"
    bad_toml.write_text("name = \n")
    with pytest.raises(ThermocalInputError, match="not valid TOML"):
        read_envelope(bad_toml)
    other = tmp_path / "b.json"
    other.write_text("{}")
    with pytest.raises(ThermocalInputError, match="use .yaml, .yml or .toml"):
        read_envelope(other)
    empty = tmp_path / "e.yaml"
    empty.write_text("")
    with pytest.raises(ThermocalInputError, match="empty"):
        read_envelope(empty)


def test_building_is_immutable():
    building = EnvelopeDescription.model_validate(minimal())
    with pytest.raises(ValidationError):
        building.floors = 2
    changed = building.model_copy(update={"floors": 2})
    assert changed.floors == 2 and building.floors == 1
    data = copy.deepcopy(minimal())
    assert EnvelopeDescription.model_validate(data) == building


def test_write_building_round_trips(tmp_path):
    building = read_envelope(EXAMPLE)
    path = write_envelope(building, tmp_path / "copy.yaml")
    assert read_envelope(path) == building
    with pytest.raises(ThermocalInputError, match="writes YAML"):
        write_envelope(building, tmp_path / "copy.toml")


# ----------------------------------------------------------------------------------------------
# the two kinds of building file, and the old names
# ----------------------------------------------------------------------------------------------
MULTIZONE_EXAMPLE = (
    Path(__file__).parents[2] / "examples/buildings/multizone_single_family_house.yaml"
)


def test_the_envelope_reader_names_a_multizone_file_and_where_it_belongs():
    with pytest.raises(ThermocalInputError) as error:
        read_envelope(MULTIZONE_EXAMPLE)
    text = str(error.value)
    assert "is a multi-zone building file" in text and "single_family_house_1953.yaml" in text


def test_the_envelope_reader_names_a_calibrated_idf_file(tmp_path):
    """``calibrate``'s calibrated building of an IDF (``idf`` + ``parameters``) given as the
    retrofit analysis' envelope: named as a multi-zone file (before: "unknown field 'idf'")."""
    path = tmp_path / "calibrated_building.yaml"
    path.write_text("idf: nominal.idf\nparameters: {}\n")
    with pytest.raises(ThermocalInputError, match="is a multi-zone building file"):
        read_envelope(path)


def test_the_multizone_reader_names_an_envelope_description():
    from thermocal.multizone.files import load_building

    with pytest.raises(ThermocalInputError) as error:
        load_building(EXAMPLE)
    text = str(error.value)
    assert "is an envelope description" in text and "multizone_single_family_house" in text


def test_the_old_names_still_work_and_warn():
    import thermocal.io
    import thermocal.io.building as old
    from thermocal.io.envelope import Site

    with pytest.warns(DeprecationWarning, match="EnvelopeDescription"):
        assert old.Building is EnvelopeDescription
    with pytest.warns(DeprecationWarning, match="Site"):
        assert old.Location is Site
    with pytest.warns(DeprecationWarning, match="EnvelopeDescription"):
        assert thermocal.io.Building is EnvelopeDescription
    assert old.read_building is read_envelope and old.building_from_dict is envelope_from_dict
    assert old.write_building is write_envelope


def test_odd_values_found_by_fuzzing_get_messages_that_fit_them():
    """Tilts in radians (1.5708 for a wall) were accepted (the validation failed later, far
    from the cause); a window frame fraction of 1 was 'did you mean 0.01 (a percentage)?'; a
    perimeter of 0 was 'outside the plausible range 0 to 10000 m'."""
    data = minimal()
    wall = next(c for c in data["components"] if c["type"] == "external_wall")
    wall["tilt"] = 1.5708
    message = error_text(data)
    assert "tilt = 1.5708 deg for an external wall" in message
    assert "1.5708 rad is 90 deg: write degrees" in message
    data = minimal()
    window = next(c for c in data["components"] if c["type"] == "window")
    window["frame_fraction"] = 1.0
    message = error_text(data)
    assert "frame_fraction = 1 is outside the plausible range 0 to 0.6" in message
    assert "did you mean" not in message
    data = minimal()
    data["ground"] = {"perimeter": 0.0, "wall_thickness": 0.3}
    assert "range above 0 up to 10000 m" in error_text(data)


def test_a_repeated_component_name_is_located_at_the_repeat(tmp_path):
    """Before: '(top level) (line 1): components[3] name ...' (the file's first line). Now the
    repeat's own location and line, and the line of the component that has the name first."""
    text = EXAMPLE.read_text().replace("  - name: wall east\n", "  - name: roof north\n")
    path = tmp_path / "house.yaml"
    path.write_text(text)
    with pytest.raises(ThermocalInputError) as info:
        read_envelope(path)
    message = str(info.value)
    lines = text.splitlines()
    first, repeat = (i + 1 for i, line in enumerate(lines) if line == "  - name: roof north")
    assert f"components[3] ('roof north').name (line {repeat}): name 'roof north'" in message
    assert f"already used by components[1] (line {first}); component names must be" in message
    assert "top level" not in message and "(line 1)" not in message
    # without a YAML file (an inline building): the positions alone
    data = minimal()
    data["components"][4]["name"] = "wall E"
    message = error_text(data)
    assert "components[4] ('wall E').name: name 'wall E' is already used by components[1];" in (
        message
    )
