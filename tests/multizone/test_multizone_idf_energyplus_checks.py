"""IDF inputs EnergyPlus ignores, refuses or warns about: thermocal does as EnergyPlus and says
so in the import warning, naming the object (fuzzing round 6), and the interzone partner refusal
in the file's terms.

Reference: ``tests/reference/idf_simple_geometry`` (NREL 4ZoneWithShading_Simple_1, EnergyPlus
25.2), each test changing one object as the fuzz case did.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import IdfImportWarning, read_idf

REFERENCE = Path(__file__).resolve().parents[1] / "reference" / "idf_simple_geometry"
SIMPLE = REFERENCE / "4ZoneWithShading_Simple_1_FF_v25.idf"
RULES = "GlobalGeometryRules,UpperLeftCorner,CounterClockWise,World,,World;"


def _variant(tmp_path, old, new):
    text = SIMPLE.read_text()
    assert text.count(old) == 1, old
    path = tmp_path / "variant.idf"
    path.write_text(text.replace(old, new))
    return path


def _read_warning(path):
    """The building and the text of its import warning."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        building = read_idf(path)
    text = "\n".join(str(w.message) for w in caught if w.category is IdfImportWarning)
    return building, text


def test_simple_window_multiplier_is_not_applied_as_in_energyplus(tmp_path):
    """EnergyPlus 25.2 does not apply a simple Window's Multiplier (its eio: the 3 x 5 m window
    at 15 m2, its wall at 200 - 15 - 15 = 170 m2 net; a FenestrationSurface:Detailed's it
    applies: 45 m2, 140 m2). Before: thermocal applied it, 45 m2 of glass, zone 2 +1.0 K against
    EnergyPlus (hourly MAE 0.97 K, January), no message (``06_window_multiplier3``); after:
    0.02-0.05 K."""
    old = "Window,Zn002:Wall001:Win001,SINGLE PANE HW WINDOW,Zn002:Wall001,,1,4,3,3,5;"
    path = _variant(tmp_path, old, old.replace(",,1,4,", ",,3,4,"))
    building, text = _read_warning(path)
    window = building.windows["Zn002:Wall001:Win001"]
    assert window.area == pytest.approx(15.0)
    assert building.net_area("Zn002:Wall001") == pytest.approx(170.0)
    assert "Window 'Zn002:Wall001:Win001'" in text
    assert "field 'Multiplier' = 3 is not applied" in text
    assert "FenestrationSurface:Detailed" in text
    # identify prints such notes in full, as simulate does (it counted them only)
    from thermocal.commands.identify import energyplus_check_notes

    (line,) = [n for n in energyplus_check_notes(building.idf_info.notes) if "Multiplier" in n]
    assert "Zn002:Wall001:Win001" in line


def test_mismatched_interzone_partner_in_idf_terms(tmp_path):
    """Before: "surface 'Zn003:Wall004' (zone 'ZONE 3', boundary zone): partner ... set its
    boundary: zone and other_surface: ..." (building-file keys, no class, no line)."""
    old = "Wall:Interzone,Zn004:Wall004,INTERIOR,ZONE 4,,Zn003:Wall004,"
    path = _variant(tmp_path, old, old.replace(",Zn003:Wall004,", ",Zn003:Wall003,"))
    with pytest.raises(ThermocalInputError) as caught:
        read_idf(path)
    message = str(caught.value)
    assert "Wall:Interzone 'Zn003:Wall004' (variant.idf line" in message
    assert "Wall:Interzone 'Zn004:Wall004' (variant.idf line" in message
    assert "'Outside Boundary Condition Object'" in message
    assert "other_surface" not in message and "boundary:" not in message


def test_window_beyond_its_wall_is_noted(tmp_path):
    """EnergyPlus warns "Base surface does not surround subsurface (CHKSBS)" and runs it.
    Before: silent (``08_window_outside_wall``)."""
    old = "Window,Zn003:Wall001:Win001,SINGLE PANE HW WINDOW,Zn003:Wall001,,1,8,3,3,5;"
    _, text = _read_warning(_variant(tmp_path, old, old.replace(",1,8,", ",1,30,")))
    assert "Window 'Zn003:Wall001:Win001'" in text
    assert "13.00 m beyond its base surface 'Zn003:Wall001'" in text


def test_interzone_surfaces_not_facing_each_other_are_noted(tmp_path):
    """A Floor:Interzone of tilt 0: EnergyPlus warns "InterZone Surface Tilts do not match as
    expected" and runs it. Before: silent (``10_floor_tilt0``)."""
    old = "Floor:Interzone,Zn003:Flr001,FLOOR34,ZONE 3,,Zn001:Roof001,90,180,"
    _, text = _read_warning(_variant(tmp_path, old, old.replace(",90,180,", ",90,0,")))
    assert "Floor:Interzone 'Zn003:Flr001'" in text and "Ceiling:Interzone 'Zn001:Roof001'" in text
    assert "do not face each other" in text


def test_missing_global_geometry_rules_is_noted(tmp_path):
    """EnergyPlus refuses the file. Before: read with the Relative defaults, no note
    (``29_no_globalgeometryrules``)."""
    _, text = _read_warning(_variant(tmp_path, RULES, ""))
    assert "no GlobalGeometryRules object; EnergyPlus refuses the file" in text


def test_absolute_rectangular_coordinates_are_noted(tmp_path):
    """EnergyPlus 25.2 refuses 'Absolute' ("Failed to match against any enum values"); read as
    World. Before: accepted silently (``05_rect_absolute_coordrel``)."""
    path = _variant(tmp_path, RULES, RULES.replace(",,World;", ",,Absolute;"))
    building, text = _read_warning(path)
    assert "'Rectangular Surface Coordinate System' = 'Absolute' is read as World" in text
    reference, _ = _read_warning(SIMPLE)
    for name, surface in reference.surfaces.items():
        assert building.surfaces[name].area == pytest.approx(surface.area)


def test_clean_file_has_no_energyplus_notes():
    _, text = _read_warning(SIMPLE)
    assert "EnergyPlus check" not in text
