"""How a file's zone equipment delivers its heat (``thermocal.multizone.idf.hvac``): the radiant
share the identification's default heat form takes from it. Field positions are EnergyPlus
25.2's (``Energy+.schema.epJSON``)."""

from __future__ import annotations

import pytest

from thermocal.multizone.idf.hvac import zone_heat_delivery
from thermocal.multizone.idf.parse import parse_idf


def _delivery(text: str, zones=("Z1", "Z2")):
    by_key: dict = {}
    for obj in parse_idf(text):
        by_key.setdefault(obj.key, []).append(obj)
    return zone_heat_delivery(by_key, {z.upper(): z for z in zones})


def test_an_air_system_delivers_convective_heat():
    found = _delivery(
        """
        ZoneHVAC:EquipmentConnections, z1, Z1 Equipment, Z1 Inlets, , Z1 Node, Z1 Return;
        ZoneHVAC:EquipmentList, Z1 Equipment, SequentialLoad,
            ZoneHVAC:IdealLoadsAirSystem, Z1 Ideal, 1, 1, , ;
        ZoneHVAC:IdealLoadsAirSystem, Z1 Ideal, , Z1 Inlet;
        """
    )
    assert list(found) == ["Z1"]  # the zone's spelling, whatever the file's case
    assert found["Z1"].radiant_fraction == 0.0
    assert "ZoneHVAC:IdealLoadsAirSystem 'Z1 Ideal'" in found["Z1"].describe()


def test_a_radiant_convective_baseboard_states_its_fraction():
    found = _delivery(
        """
        ZoneHVAC:EquipmentConnections, Z1, L1, , , Z1 Node, ;
        ZoneHVAC:EquipmentList, L1, SequentialLoad,
            ZoneHVAC:Baseboard:RadiantConvective:Electric, BB1, 1, 1, , ;
        ZoneHVAC:Baseboard:RadiantConvective:Electric, BB1, , HeatingDesignCapacity, 1000, ,
            , 0.97, 0.3, 0.0, Wall 1, 0.7;
        ZoneHVAC:EquipmentConnections, Z2, L2, , , Z2 Node, ;
        ZoneHVAC:EquipmentList, L2, SequentialLoad,
            ZoneHVAC:Baseboard:RadiantConvective:Water, BB2, 1, 1, , ;
        ZoneHVAC:Baseboard:RadiantConvective:Water, BB2, BB Design, , In, Out, 87.78, 0.063;
        ZoneHVAC:Baseboard:RadiantConvective:Water:Design, BB Design, HeatingDesignCapacity,
            , , 0.001, 0.35, 0.2;
        """
    )
    assert found["Z1"].radiant_fraction == pytest.approx(0.3)
    assert found["Z2"].radiant_fraction == pytest.approx(0.35)


def test_a_radiant_heaters_share_is_of_the_heat_it_delivers():
    """ZoneHVAC:HighTemperatureRadiant states its radiant share of the input, besides latent
    and lost fractions: of the heat it delivers, 0.6 / (1 - 0.2) = 0.75 is radiant."""
    found = _delivery(
        """
        ZoneHVAC:EquipmentConnections, Z1, L1, , , Z1 Node, ;
        ZoneHVAC:EquipmentList, L1, SequentialLoad, ZoneHVAC:HighTemperatureRadiant, H1, 1, 1;
        ZoneHVAC:HighTemperatureRadiant, H1, , Z1, HeatingDesignCapacity, 5000, , , NaturalGas,
            0.85, 0.6, 0.0, 0.2, OperativeTemperature, 2.0, Set Points, 0.04, Ceiling, 1.0;
        """
    )
    assert found["Z1"].radiant_fraction == pytest.approx(0.75)


def test_equipment_without_a_split_or_with_an_unreadable_one_states_none():
    found = _delivery(
        """
        ZoneHVAC:EquipmentConnections, Z1, L1, , , Z1 Node, ;
        ZoneHVAC:EquipmentList, L1, SequentialLoad,
            ZoneHVAC:LowTemperatureRadiant:Electric, Floor Heat, 1, 1, , ;
        ZoneHVAC:EquipmentConnections, Z2, L2, , , Z2 Node, ;
        ZoneHVAC:EquipmentList, L2, SequentialLoad,
            ZoneHVAC:Baseboard:RadiantConvective:Electric, BB2, 1, 1, , ;
        ZoneHVAC:Baseboard:RadiantConvective:Electric, BB2, , HeatingDesignCapacity, 1000, ,
            , 0.97, autosize;
        """
    )
    assert found["Z1"].radiant_fraction is None
    assert "source layer" in found["Z1"].equipment[0].how
    assert found["Z2"].radiant_fraction is None
    assert "not a fraction" in found["Z2"].equipment[0].how


def test_older_lists_templates_and_several_pieces_of_equipment():
    """Lists written before 9.2 (four fields per piece), HVACTemplate zones (their expansion:
    air systems and convective baseboards) and a zone with an air terminal and a radiant
    baseboard (the split of the heat between them unknown: the mean, 0.15)."""
    found = _delivery(
        """
        ZoneHVAC:EquipmentConnections, Z1, L1, , , Z1 Node, ;
        ZoneHVAC:EquipmentList, L1, ZoneHVAC:AirDistributionUnit, ADU1, 1, 1,
            ZoneHVAC:Baseboard:RadiantConvective:Electric, BB1, 2, 2;
        ZoneHVAC:Baseboard:RadiantConvective:Electric, BB1, , HeatingDesignCapacity, 1000, ,
            , 0.97, 0.3;
        HVACTemplate:Zone:VAV, Z2, VAV System;
        """
    )
    assert found["Z1"].radiant_fraction == pytest.approx(0.15)
    assert [e.class_name for e in found["Z1"].equipment] == [
        "ZoneHVAC:AirDistributionUnit",
        "ZoneHVAC:Baseboard:RadiantConvective:Electric",
    ]
    assert found["Z2"].radiant_fraction == 0.0


def test_a_file_without_zone_equipment_declares_none():
    assert _delivery("ZoneHVAC:EquipmentList, L1, SequentialLoad;") == {}
