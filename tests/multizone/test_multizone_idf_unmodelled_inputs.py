"""IDF inputs the model does not have, and what the import says about them (survey of NREL test
files, 2026-11-30):

- the ``Zone`` fields *Zone Inside / Outside Convection Algorithm*: the model's convection
  algorithms are building-wide, so a zone's own algorithm is named in the notes of
  ``IdfImportInfo.network_options()`` (``Simulation.approximations()``, summary.json's
  ``approximations``) with the one used; before, it was dropped silently (NREL's
  PassiveTrombeWall: ``TrombeWall`` in the cavity zone, 5-7 K off EnergyPlus, no note);
- a construction layer that is a window screen, shade or blind (``WindowMaterial:Screen``,
  ...) is refused naming its class and what to do (before: "is not defined");
- a ``SurfaceProperty:OtherSideCoefficients`` boundary, treated as adiabatic, is noted with the
  error measured on NREL's test file.
"""

from __future__ import annotations

import warnings

import pytest

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf import IdfImportWarning, read_idf

HEAD = """
Version,25.2;
Building,B,0,Suburbs,,,FullExterior;
GlobalGeometryRules,UpperLeftCorner,Counterclockwise,Relative;
Material,M1,Rough,0.2,1.0,2000,1000,0.9,0.6,0.6;
Construction,C1,M1;
WindowMaterial:SimpleGlazingSystem,SG,2.7,0.7;
Construction,WIN,SG;
{extra}
"""

#: a 4 x 3 x 2.5 m box zone at x offset {x} (relative coordinates); its south wall {boundary}
ZONE = """
Zone,{name},0,{x},0,0,,1,,autocalculate,autocalculate,{inside},{outside};
BuildingSurface:Detailed,{name} Floor,Floor,C1,{name},,Ground,,NoSun,NoWind,0,4,
  4,3,0,4,0,0,0,0,0,0,3,0;
BuildingSurface:Detailed,{name} Roof,Roof,C1,{name},,Outdoors,,SunExposed,WindExposed,0,4,
  4,0,2.5,4,3,2.5,0,3,2.5,0,0,2.5;
BuildingSurface:Detailed,{name} South,Wall,C1,{name},,{boundary},SunExposed,WindExposed,0.5,4,
  0,0,2.5,0,0,0,4,0,0,4,0,2.5;
BuildingSurface:Detailed,{name} North,Wall,C1,{name},,Outdoors,,SunExposed,WindExposed,0.5,4,
  4,3,2.5,4,3,0,0,3,0,0,3,2.5;
BuildingSurface:Detailed,{name} East,Wall,C1,{name},,Outdoors,,SunExposed,WindExposed,0.5,4,
  4,0,2.5,4,0,0,4,3,0,4,3,2.5;
BuildingSurface:Detailed,{name} West,Wall,C1,{name},,Outdoors,,SunExposed,WindExposed,0.5,4,
  0,3,2.5,0,3,0,0,0,0,0,0,2.5;
FenestrationSurface:Detailed,{name} Win,Window,{window},{name} North,,0.5,,1,4,
  3,3,2,3,3,1,1,3,1,1,3,2;
"""


def _zone(name, x=0, inside="", outside="", boundary="Outdoors,", window="WIN"):
    return ZONE.format(
        name=name, x=x, inside=inside, outside=outside, boundary=boundary, window=window
    )


def _read(tmp_path, text):
    path = tmp_path / "t.idf"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        return read_idf(path)


def _notes(tmp_path, zones, extra=""):
    building = _read(tmp_path, HEAD.format(extra=extra) + "".join(zones))
    options, notes = building.idf_info.network_options()
    return building, options, notes


# ------------------------------------------------------------------------------------------------
# Zone Inside / Outside Convection Algorithm


def test_zone_convection_algorithm_not_available_is_noted_with_the_one_used(tmp_path):
    zones = [
        _zone("Z1", inside="TrombeWall"),
        _zone("Z2", x=10, inside="trombewall"),
        _zone("Z3", x=20, inside="CeilingDiffuser"),
        _zone("Z4", x=30),  # blank: the building's algorithm, no note
    ]
    building, options, notes = _notes(tmp_path, zones)
    assert building.idf_info.zone_convection == {
        "inside": {"Z1": "TrombeWall", "Z2": "trombewall", "Z3": "CeilingDiffuser"}
    }
    assert options.interior_convection == "tarp"
    trombe = [n for n in notes if "TrombeWall" in n]
    # one note for the two TrombeWall zones (the first spelling named), the measured magnitude
    assert len(trombe) == 1 and trombe[0].startswith(
        "Zones 'Z1', 'Z2': Zone Inside Convection Algorithm TrombeWall is not available: TARP "
        "(EnergyPlus' default SurfaceConvectionAlgorithm:Inside) used for its surfaces; "
    )
    assert "5-7 K warmer than EnergyPlus" in trombe[0]
    assert (
        "Zone 'Z3': Zone Inside Convection Algorithm CeilingDiffuser is not available: TARP "
        "(EnergyPlus' default SurfaceConvectionAlgorithm:Inside) used for its surfaces"
    ) in notes
    assert not any("Z4" in n for n in notes)


def test_zone_convection_algorithm_the_model_has_is_building_wide(tmp_path):
    extra = "SurfaceConvectionAlgorithm:Inside,TARP;SurfaceConvectionAlgorithm:Outside,DOE-2;"
    zones = [
        _zone("Z1", inside="Simple", outside="MoWiTT"),
        _zone("Z2", x=10, inside="TARP", outside="DOE-2"),  # = the building's: no note
        _zone("Z3", x=20, outside="AdaptiveConvectionAlgorithm"),
    ]
    _, options, notes = _notes(tmp_path, zones, extra)
    assert (options.interior_convection, options.exterior_convection) == ("tarp", "doe2")
    assert notes == [
        "Zone 'Z1': Zone Inside Convection Algorithm Simple is not applied per zone (the model's "
        "convection algorithms are building-wide): the file's TARP "
        "(SurfaceConvectionAlgorithm:Inside) used for every zone",
        "Zone 'Z1': Zone Outside Convection Algorithm MoWiTT is not applied per zone (the "
        "model's convection algorithms are building-wide): the file's DOE-2 "
        "(SurfaceConvectionAlgorithm:Outside) used for every zone",
        "Zone 'Z3': Zone Outside Convection Algorithm AdaptiveConvectionAlgorithm is not "
        "available: the file's DOE-2 (SurfaceConvectionAlgorithm:Outside) used for its surfaces",
    ]


def test_zone_convection_note_names_the_fallback_of_the_building_algorithm(tmp_path):
    extra = "SurfaceConvectionAlgorithm:Inside,ASTMC1340;"
    _, options, notes = _notes(tmp_path, [_zone("Z1", inside="Simple")], extra)
    assert options.interior_convection == "tarp"
    assert notes == [
        "SurfaceConvectionAlgorithm:Inside ASTMC1340 is not available: TARP used",
        "Zone 'Z1': Zone Inside Convection Algorithm Simple is not applied per zone (the model's "
        "convection algorithms are building-wide): TARP (in place of the file's "
        "SurfaceConvectionAlgorithm:Inside ASTMC1340) used for every zone",
    ]


def test_zone_convection_notes_reach_the_simulation_approximations(tmp_path):
    from test_multizone_network import constant_weather

    from thermocal.multizone.simulation import Simulation

    building = _read(tmp_path, HEAD.format(extra="") + _zone("Z1", inside="TrombeWall"))
    weather, meta = constant_weather(days=1)
    sim = Simulation(building, weather, meta, step="1h", warmup_days=0)
    head = "Zone 'Z1': Zone Inside Convection Algorithm TrombeWall is not available"
    assert any(n.startswith(head) for n in sim.approximations())


# ------------------------------------------------------------------------------------------------
# window screens, shades and blinds


SHADED = """
WindowMaterial:Glazing,GL,SpectralAverage,,0.003,0.83,0.07,0.07,0.89,0.08,0.08,
  0,0.84,0.84,0.9;
{shading}
Construction,SHADED,{layer},GL;
"""

SCREEN = "WindowMaterial:Screen,SCR1,DoNotModel,0.08,0.08,0.08,0.9,0.00025,0.0008,0.025;"
SHADE = "WindowMaterial:Shade,SHD1,0.3,0.5,0.3,0.5,0.9,0,0.003,0.1,0.1,0,0,0,0,0;"
CONTROL = (
    "WindowShadingControl,WSC1,Z1,1,ExteriorScreen,SHADED,AlwaysOn,,,No,No,,,,,,Sequential,Z1 Win;"
)


@pytest.mark.parametrize(
    "shading, layer, kind", [(SCREEN, "SCR1", "Screen"), (SHADE, "SHD1", "Shade")]
)
def test_window_shading_layer_is_refused_naming_its_class(tmp_path, shading, layer, kind):
    extra = SHADED.format(shading=shading, layer=layer) + CONTROL
    with pytest.raises(
        ThermocalInputError,
        match=(
            rf"Construction 'SHADED' \(t.idf line \d+\): field 'Layer 1' = '{layer}' is a "
            rf"WindowMaterial:{kind} \(t.idf line \d+\), a window {kind.lower()}; thermocal does "
            r"not model window screens, shades or blinds. For an unshaded comparison remove the "
            r"WindowShadingControl 'WSC1' and this construction \(its windows keep their "
            r"unshaded construction\)\."
        ),
    ):
        _read(tmp_path, HEAD.format(extra=extra) + _zone("Z1"))


def test_window_shading_layer_without_control_and_unknown_layers(tmp_path):
    extra = SHADED.format(shading=SCREEN, layer="SCR1")
    with pytest.raises(
        ThermocalInputError,
        match=r"a window screen; .* For an unshaded comparison remove the layer \(or the "
        r"construction, where nothing uses it\)\.",
    ):
        _read(tmp_path, HEAD.format(extra=extra) + _zone("Z1"))
    extra = "Material:InfraredTransparent,IRT;Construction,C2,IRT;"
    with pytest.raises(
        ThermocalInputError,
        match=r"field 'Layer 1' = 'IRT' is a Material:InfraredTransparent \(t.idf line \d+\), "
        r"which thermocal does not support; layers can be Material, Material:NoMass, ",
    ):
        _read(tmp_path, HEAD.format(extra=extra) + _zone("Z1"))
    extra = "Construction,C2,NOSUCH;"
    with pytest.raises(ThermocalInputError, match=r"'NOSUCH' is not defined \(no Material,"):
        _read(tmp_path, HEAD.format(extra=extra) + _zone("Z1"))


# ------------------------------------------------------------------------------------------------
# SurfaceProperty:OtherSideCoefficients


def test_other_side_coefficients_note_states_the_error_measured(tmp_path):
    extra = "SurfaceProperty:OtherSideCoefficients,OSC1,0,16,1,0,0,0,0;"
    building = _read(
        tmp_path,
        HEAD.format(extra=extra) + _zone("Z1", boundary="OtherSideCoefficients,OSC1"),
    )
    info = building.idf_info
    note = next(n for n in info.notes if n.startswith("surface 'Z1 South'"))
    assert note.startswith(
        "surface 'Z1 South': boundary OtherSideCoefficients is not modelled; treated as "
        "adiabatic (no heat crosses it); the error grows with the difference between the zone "
        "and the other side's temperature"
    )
    assert "0.4-0.7 K warmer than in EnergyPlus" in note
    assert building.surfaces["Z1 South"].boundary == "adiabatic"
    # counted among the other notes, not the ground ones
    assert note in info.report()["notes"]["other"]
