"""Which zones' identified heat takes its form from the IDF's equipment, and what the note says
(``thermocal.identification.workflow.identified_heat_form`` / ``equipment_form_note``): a value
given for a zone, in any way, is the user's; the rest take their equipment's share, 0.6 without
equipment or when the equipment states no split (review of 2026-11-30)."""

from __future__ import annotations

from types import SimpleNamespace

import pandas as pd

from thermocal.identification.sensors import mapping_from_dict
from thermocal.identification.workflow import equipment_form_note, identified_heat_form
from thermocal.multizone.idf.hvac import EquipmentHeat, ZoneHeatDelivery

ZONES = ("Air", "Floor heat", "Plain", "Mine")


def _building():
    air = EquipmentHeat("ZoneHVAC:IdealLoadsAirSystem", "ideal", 0.0, "an air system")
    slab = EquipmentHeat("ZoneHVAC:LowTemperatureRadiant:Electric", "slab", None, "source layer")
    delivery = {
        "Air": ZoneHeatDelivery((air,), 0.0),
        "Floor heat": ZoneHeatDelivery((slab,), None),
        "Mine": ZoneHeatDelivery((air,), 0.0),
    }
    return SimpleNamespace(
        zones={z: None for z in ZONES}, idf_info=SimpleNamespace(zone_heat_delivery=delivery)
    )


def test_defaults_follow_the_equipment_and_the_note_names_each_group():
    building = _building()
    mapping = mapping_from_dict(
        {"sensors": {"S1": "Air"}, "zones": {"Mine": {"radiant_fraction": 0.2}}}
    )
    form = identified_heat_form(building, mapping)
    assert form["radiant_fraction"].to_dict() == {
        "Air": 0.0, "Floor heat": 0.6, "Plain": 0.6, "Mine": 0.2,
    }  # fmt: skip
    note = equipment_form_note(building, form, mapping, None)
    assert "0 for zone 'Air' (ZoneHVAC:IdealLoadsAirSystem)" in note
    assert "0.6 for zone 'Floor heat', whose equipment states no split" in note
    assert "zone 'Plain' without equipment take 0.6" in note
    # the user's own 0.2 for an air system's zone: not announced as a default, but named
    assert "'Mine' without" not in note and "0.6 for zone 'Mine'" not in note
    assert "Zone 'Mine' is heated or cooled by an air system" in note


def test_a_dict_for_some_zones_leaves_the_others_to_their_equipment():
    building = _building()
    given = {"Plain": 0.3}
    form = identified_heat_form(building, None, radiant_fraction=given)
    assert form.loc["Air", "radiant_fraction"] == 0.0
    assert form.loc["Plain", "radiant_fraction"] == 0.3
    note = equipment_form_note(building, form, None, given)
    assert "0 for zones 'Air', 'Mine'" in note and "'Plain' without" not in note


def test_a_per_step_form_is_said_as_what_it_is():
    building = _building()
    times = pd.date_range("2023-01-01", periods=4, freq="1h")
    frame = pd.DataFrame(0.5, index=times, columns=list(ZONES))
    form = identified_heat_form(building, None, radiant_fraction=frame)
    given = equipment_form_note(building, form, None, frame)
    assert "is given a radiant fraction above 0" in given and "declared" not in given
    declared = equipment_form_note(building, form, None, frame, declared=True)
    assert "composition of the file's internal loads" in declared
    assert "comes from the zones' equipment" not in declared
