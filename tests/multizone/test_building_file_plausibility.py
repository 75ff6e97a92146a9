"""Plausibility of a zone's numbers in thermocal's own building file (YAML).

A user's slips that used to load silently and give a wrong demand: a heating set point in
Fahrenheit (68) or with a stray minus sign (-20), an infiltration rate typed as a percentage
(45 for 0.45 1/h), a volume that cannot hold a room (0.001 m3 over 20 m2), and the two faces of
an inter-zone wall given different constructions (the first listed is built, the other not
read). The strict limits hold for the YAML a user writes; a :class:`Zone` made in code (the IDF
import, whose schedules use values such as -50 or 100 C for "off") keeps the broad checks.
"""

from __future__ import annotations

import copy
import dataclasses
import warnings
from pathlib import Path

import pytest
import yaml

from thermocal.errors import ThermocalInputError
from thermocal.multizone.files import building_from_dict, building_to_dict, load_building
from thermocal.multizone.model import Zone

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples" / "buildings").glob("multizone_*.yaml"))
FIVE_ZONE_IDF = Path("/work/shared/data/energyplus_reference/5ZoneAirCooled_FF_v25.idf")

TWO_ROOMS = {
    "name": "two rooms",
    "materials": [
        {"name": "brick", "conductivity": 0.8, "density": 1800, "specific_heat": 900,
         "thickness": 0.2},
        {"name": "plaster", "conductivity": 0.7, "density": 1400, "specific_heat": 1000,
         "thickness": 0.015},
    ],
    "constructions": [
        {"name": "wall", "layers": ["brick", "plaster"]},
        {"name": "wall reversed", "layers": ["plaster", "brick"]},
        {"name": "partition", "layers": ["plaster", "brick", "plaster"]},
    ],
    "zones": [
        {"name": "living", "volume": 75, "floor_area": 30, "infiltration_ach": 0.5,
         "heating_setpoint": 20},
        {"name": "kitchen", "volume": 37.5, "floor_area": 15, "infiltration_ach": 0.5,
         "heating_setpoint": 20},
    ],
    "surfaces": [
        {"name": "living south", "zone": "living", "construction": "wall", "area": 15,
         "azimuth": 180},
        {"name": "kitchen north", "zone": "kitchen", "construction": "wall", "area": 15},
        {"name": "living|kitchen", "zone": "living", "construction": "partition",
         "area": 12.5, "boundary": "zone", "other_surface": "kitchen|living"},
        {"name": "kitchen|living", "zone": "kitchen", "construction": "partition",
         "area": 12.5, "azimuth": 180, "boundary": "zone", "other_surface": "living|kitchen"},
    ],
}  # fmt: skip


def _changed(zone: str | None = None, **fields) -> dict:
    """The two rooms with some fields of one zone changed (all zones when ``zone`` is None)."""
    data = copy.deepcopy(TWO_ROOMS)
    for entry in data["zones"]:
        if zone is None or entry["name"] == zone:
            entry.update(fields)
    return data


def _write(tmp_path, data) -> Path:
    path = tmp_path / "building.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def _file_warnings(function, *args) -> list[str]:
    """thermocal's warnings from ``function(*args)`` (the ones the command line shows as
    ``warning:`` lines; other libraries' ignored)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        function(*args)
    return [str(w.message) for w in caught if w.category.__module__.startswith("thermocal")]


# ------------------------------------------------------------------------------ set points
def test_heating_set_points_in_fahrenheit_are_refused_with_the_conversion(tmp_path):
    """Before: 68 (F) was taken as 68 C and the house's heating demand came out 7.8 times too
    high (/tmp/fuzz4/h02_setpoint_fahrenheit)."""
    path = _write(tmp_path, _changed(heating_setpoint=68))
    with pytest.raises(ThermocalInputError) as err:
        load_building(path)
    message = str(err.value)
    for words in ("building.yaml", "zone 'living'", "heating_setpoint", "68", "Fahrenheit",
                  "write 20.0", "0-35 C"):  # fmt: skip
        assert words in message, message


def test_one_zone_in_fahrenheit_among_celsius_ones_is_named(tmp_path):
    """/tmp/fuzz4/h05_one_zone_fahrenheit: only the kitchen at 68."""
    with pytest.raises(ThermocalInputError, match=r"zone 'kitchen': heating_setpoint 68 C"):
        load_building(_write(tmp_path, _changed("kitchen", heating_setpoint=68)))


def test_a_negative_heating_set_point_is_refused(tmp_path):
    """/tmp/fuzz4/h07_setpoint_negative: -20 C heated nothing and loaded silently."""
    with pytest.raises(
        ThermocalInputError, match=r"zone 'living': heating_setpoint -20 C.*minus sign.* 20\b"
    ):
        load_building(_write(tmp_path, _changed("living", heating_setpoint=-20)))


def test_kelvin_set_points_keep_their_message(tmp_path):
    with pytest.raises(ThermocalInputError, match=r"heating_setpoint 293.15 looks like Kelvin"):
        load_building(_write(tmp_path, _changed("living", heating_setpoint=293.15)))


@pytest.mark.parametrize(
    ("fields", "words"),
    [
        ({"cooling_setpoint": 77}, r"zone 'living': cooling_setpoint 77 C.*Fahrenheit.* 25\.0"),
        ({"cooling_setpoint": 120}, r"cooling_setpoint 120 C.*leaves the key out"),
        ({"heating_setpoint": -50}, r"heating_setpoint -50 C.*leaves the key out"),
        ({"heating_setpoint": 40}, r"heating_setpoint 40 C is not"),
    ],
)
def test_implausible_set_points_are_refused(tmp_path, fields, words):
    with pytest.raises(ThermocalInputError, match=words):
        load_building(_write(tmp_path, _changed("living", **fields)))


@pytest.mark.parametrize(
    "fields",
    [
        {"heating_setpoint": 5},  # frost protection
        {"heating_setpoint": 2},  # frost protection of an unheated garage
        {"heating_setpoint": 35},
        {"heating_setpoint": 12, "cooling_setpoint": 40},  # set-back and set-up
        {"heating_setpoint": None, "cooling_setpoint": 26},
    ],
)
def test_plausible_set_points_load(tmp_path, fields):
    building = load_building(_write(tmp_path, _changed("living", **fields)))
    assert building.zones["living"].heating_setpoint == fields["heating_setpoint"]


def test_a_zone_made_in_code_keeps_the_broad_set_point_check():
    """The IDF import stores the value a schedule holds most of the year: EnergyPlus files
    use -50 or 100 C for 'off', which stays accepted there."""
    zone = Zone("plenum", 60.0, 100.0, heating_setpoint=-50.0, cooling_setpoint=100.0)
    assert (zone.heating_setpoint, zone.cooling_setpoint) == (-50.0, 100.0)


# ------------------------------------------------------------------------------ infiltration
def test_an_infiltration_rate_typed_as_a_percentage_is_named(tmp_path):
    """/tmp/fuzz4/h06_infil_percent: 45 1/h (0.45 meant) gave 842 MWh without a word."""
    path = _write(tmp_path, _changed("kitchen", infiltration_ach=45))
    messages = _file_warnings(load_building, path)
    assert len(messages) == 1, messages
    for words in ("building.yaml", "infiltration_ach of zone(s) 'kitchen' 45 1/h", "write 0.45"):
        assert words in messages[0], messages[0]


def test_a_percentage_in_every_zone_gives_one_warning(tmp_path):
    """The house of h06 has it in its eight heated zones: one line, not eight."""
    messages = _file_warnings(load_building, _write(tmp_path, _changed(infiltration_ach=45)))
    assert len(messages) == 1 and "'living' 45 1/h, 'kitchen' 45 1/h" in messages[0], messages


@pytest.mark.parametrize("ach", [0.0, 0.45, 3.0, 10.0])
def test_infiltration_rates_of_envelopes_load_quietly(tmp_path, ach):
    assert not _file_warnings(load_building, _write(tmp_path, _changed(infiltration_ach=ach)))


# ------------------------------------------------------------------------------ volume
def test_a_volume_too_small_for_the_floor_is_refused(tmp_path):
    """/tmp/fuzz4/b05_tiny_volume: 0.001 m3 over 20 m2 was simulated."""
    path = _write(tmp_path, _changed("kitchen", volume=0.001, floor_area=20))
    with pytest.raises(ThermocalInputError) as err:
        load_building(path)
    message = str(err.value)
    for words in ("building.yaml", "zone 'kitchen'", "volume 0.001 m3", "floor_area 20 m2"):
        assert words in message, message


@pytest.mark.parametrize(
    ("volume", "floor_area"),
    [
        (18.0, 30.0),  # a 0.6 m ceiling plenum (5ZoneAirCooled's PLENUM-1: 0.61 m)
        (6.0, 30.0),  # a 0.2 m raised-floor plenum
        (5.0, 0.0),  # a zone without floor (a shaft)
    ],
)
def test_shallow_air_spaces_load(tmp_path, volume, floor_area):
    path = _write(tmp_path, _changed("kitchen", volume=volume, floor_area=floor_area))
    assert load_building(path).zones["kitchen"].volume == volume


# ------------------------------------------------------------------------------ partners
def _partition(first: str, second: str) -> dict:
    data = copy.deepcopy(TWO_ROOMS)
    data["surfaces"][2]["construction"] = first
    data["surfaces"][3]["construction"] = second
    return data


def test_partner_faces_with_different_constructions_are_noted(tmp_path):
    """/tmp/fuzz4/b15_partner_construction_mismatch: the wall was built from the first
    surface's construction and the other one not read, without a word (the IDF import notes
    such a pair)."""
    messages = _file_warnings(load_building, _write(tmp_path, _partition("partition", "wall")))
    assert len(messages) == 1, messages
    for words in ("building.yaml", "'partition'", "'wall'", "'living|kitchen'",
                  "'kitchen|living'", "from 'partition'"):  # fmt: skip
        assert words in messages[0], messages[0]


@pytest.mark.parametrize(
    ("first", "second"),
    [
        ("partition", "partition"),  # the same construction named from both sides
        ("wall", "wall"),  # the same, not symmetric (the demo house's floors)
        ("wall", "wall reversed"),  # the mirror, as EnergyPlus wants it
    ],
)
def test_mirrored_or_identical_partner_constructions_load_quietly(tmp_path, first, second):
    assert not _file_warnings(load_building, _write(tmp_path, _partition(first, second)))


# ------------------------------------------------------------------------------ the project's own
@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_the_example_buildings_load_quietly(path):
    assert not _file_warnings(load_building, path)


def test_the_demo_buildings_load_quietly_from_their_files():
    from thermocal.demos import buildings as generators

    for building in (
        generators.single_family_house(),
        generators.single_family_house(heating_setpoint=None),
        generators.clinic(12, n_corridors=1, corridor_sections=2, heating_setpoint=20.0),
    ):
        assert not _file_warnings(building_from_dict, building_to_dict(building))


@pytest.mark.skipif(not FIVE_ZONE_IDF.is_file(), reason="EnergyPlus reference not available")
def test_an_energyplus_building_saved_as_yaml_loads_quietly():
    """The calibrated building of an IDF is written as YAML (its plenum 0.61 m high)."""
    from thermocal.multizone.idf import read_idf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(FIVE_ZONE_IDF)
    assert not _file_warnings(building_from_dict, building_to_dict(building))


def test_an_off_set_point_is_left_out_of_a_written_file(tmp_path):
    """An IDF schedule's "off" value (heating -50 C, cooling 100 C) is a set point a zone made
    in code may hold; the file thermocal writes leaves it out (no heating or cooling, what it
    means), so that thermocal reads every file it writes (before: calibrate's
    calibrated_building.yaml of such a file would be refused when read back)."""
    from thermocal.multizone.files import BuildingFileWarning, save_building

    building = load_building(_write(tmp_path, _changed("living", heating_setpoint=20)))
    off = dataclasses.replace(building.zones["living"], heating_setpoint=-50.0,
                              cooling_setpoint=100.0)  # fmt: skip
    building.zones["living"] = off
    with pytest.warns(BuildingFileWarning, match=r"zone 'living': heating_setpoint -50 C"):
        path = save_building(building, tmp_path / "written.yaml")
    again = load_building(path)
    assert again.zones["living"].heating_setpoint is None
    assert again.zones["living"].cooling_setpoint is None


def test_a_building_file_naming_an_idf_and_parameters(tmp_path):
    """The calibrated building of an IDF (``thermocal calibrate`` writes it so): the IDF as
    imported with the parameters applied, its importer's schedules and loads kept; bad entries
    named with the file; an IDF that changed since the calibration warned about."""
    import shutil

    from conftest import shared_data_path
    from thermocal.io.digest import file_sha256
    from thermocal.multizone.files import BuildingFileWarning
    from thermocal.multizone.idf import read_idf

    idf = tmp_path / "nominal.idf"
    shutil.copy(shared_data_path("energyplus_reference", "5ZoneAirCooled_FF_v25.idf"), idf)
    values = {"construction/ROOF-1/resistance": 3.0, "window/Dbl Clr 3mm/13mm Air/u_value": 1.9}
    path = tmp_path / "calibrated.yaml"

    def write(**content):
        path.write_text(yaml.safe_dump(content))
        return path

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        digest = file_sha256(idf)
        back = load_building(write(idf="nominal.idf", idf_sha256=digest, parameters=values))
        expected = read_idf(idf).with_parameters(values)
    assert not [w for w in caught if issubclass(w.category, BuildingFileWarning)]
    assert back.idf_info is not None
    assert back.parameters() == pytest.approx(expected.parameters(), rel=1e-12)
    with pytest.raises(ThermocalInputError, match="calibrated.yaml.*unknown keys \\['zones'\\]"):
        load_building(write(idf="nominal.idf", zones=[]))
    with pytest.raises(ThermocalInputError, match="calibrated.yaml.*'other.idf'.*does not exist"):
        load_building(write(idf="other.idf"))
    with pytest.raises(ThermocalInputError, match="calibrated.yaml.*ROOF-2"):
        load_building(write(idf="nominal.idf", parameters={"construction/ROOF-2/resistance": 3}))
    with pytest.raises(ThermocalInputError, match="'parameters' must map"):
        load_building(write(idf="nominal.idf", parameters={"construction/ROOF-1/resistance": "x"}))
    with pytest.warns(BuildingFileWarning, match="not the IDF the parameters were calibrated on"):
        load_building(write(idf="nominal.idf", idf_sha256="0" * 64, parameters=values))


def test_a_calibration_of_a_file_naming_an_idf_names_the_idf_again(tmp_path):
    """Calibrating on a calibrated file (``idf`` + ``parameters``) writes the IDF and its
    parameters with the calibrated ones over them, not the building written whole (which
    lost the IDF's schedules, loads, airflows and shading: 1.6-2.9 K colder); the campaign's
    fingerprint follows the IDF the file names; the detailed retrofit finds the IDF too."""
    import shutil

    from conftest import shared_data_path
    from thermocal.calibration.result import CalibrationResult
    from thermocal.multizone.files import imported_idf

    idf = tmp_path / "nominal.idf"
    shutil.copy(shared_data_path("energyplus_reference", "5ZoneAirCooled_FF_v25.idf"), idf)
    named = tmp_path / "calibrated.yaml"
    named.write_text(yaml.safe_dump({"idf": "nominal.idf", "parameters": {
        "construction/ROOF-1/resistance": 3.0, "infiltration/building/factor": 1.2}}))  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = load_building(named)
    assert imported_idf(building) == idf.resolve()
    result = object.__new__(CalibrationResult)  # only what the file's form needs
    result.calibrated_building = building.with_parameters({"construction/WALL-1/resistance": 2})
    result.building_path = str(named)
    result.calibrated_parameters = {"construction/WALL-1/resistance": 2.0,
                                    "infiltration/building/factor": 1.1}  # fmt: skip
    form = result._idf_with_parameters(tmp_path / "out")
    assert form["idf"] == "../nominal.idf"
    assert form["parameters"] == {
        "construction/ROOF-1/resistance": 3.0,
        "infiltration/building/factor": 1.1,
        "construction/WALL-1/resistance": 2.0,
    }


def test_a_campaign_on_a_file_naming_an_idf_follows_the_idf(tmp_path):
    from thermocal.calibration.config import load_campaign

    (tmp_path / "nominal.idf").write_text("Version, 25.2;\n")
    (tmp_path / "calibrated.yaml").write_text(yaml.safe_dump({"idf": "nominal.idf"}))
    for name in ("weather.epw", "sensors.csv", "mapping.yaml"):
        (tmp_path / name).write_text("x\n")
    campaign = tmp_path / "campaign.yaml"
    campaign.write_text(
        "building: calibrated.yaml\nweather: weather.epw\nsensors: sensors.csv\n"
        "mapping: mapping.yaml\n"
    )
    before = load_campaign(campaign).problem_fingerprint()
    (tmp_path / "nominal.idf").write_text("Version, 25.2;\n! another building\n")
    assert load_campaign(campaign).problem_fingerprint() != before
