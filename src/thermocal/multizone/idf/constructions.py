"""Materials, constructions and glazing of an IDF file.

Stages of the import (:class:`ConstructionStages`, mixed into the builder of
:func:`thermocal.multizone.idf.read_idf`): ``Material``, ``Material:NoMass``, ``Material:AirGap``,
``WindowMaterial:Glazing`` / ``WindowMaterial:Gas`` (layered glazing, optics by
:mod:`thermocal.multizone.glazing`), ``WindowMaterial:SimpleGlazingSystem`` and ``Construction``;
:func:`window_type_from_glazing` turns a window construction into the model's WindowType.
"""

from __future__ import annotations

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.parse import _Names, _number, _wrap

#: Layer classes of a ``Construction`` the model reads.
SUPPORTED_LAYER_CLASSES = (
    "Material",
    "Material:NoMass",
    "Material:AirGap",
    "WindowMaterial:Glazing",
    "WindowMaterial:Gas",
    "WindowMaterial:SimpleGlazingSystem",
)

#: Window shading materials (class -> what it is), which the model does not have: a
#: construction with one of them as a layer is refused (``WindowShadingControl`` is listed as
#: not simulated). Written as EnergyPlus spells them: the importer reads none of these classes.
WINDOW_SHADING_MATERIALS = {
    "WindowMaterial:Screen": "screen",
    "WindowMaterial:Shade": "shade",
    "WindowMaterial:Blind": "blind",
    "WindowMaterial:ComplexShade": "shade (complex fenestration)",
    "WindowMaterial:Screen:EquivalentLayer": "screen (equivalent layer)",
    "WindowMaterial:Shade:EquivalentLayer": "shade (equivalent layer)",
    "WindowMaterial:Drape:EquivalentLayer": "drape (equivalent layer)",
    "WindowMaterial:Blind:EquivalentLayer": "blind (equivalent layer)",
}
_SHADING_BY_KEY = {k.upper(): v for k, v in WINDOW_SHADING_MATERIALS.items()}

#: Angles [deg] of the angular optics tables handed to the WindowType.
WINDOW_TABLE_ANGLES = tuple(float(a) for a in range(0, 91, 5))

#: tabulated (the simulation interpolates, and holds the end values outside).
GLASS_CONDUCTANCE_TEMPERATURES = tuple(float(t) for t in range(-40, 101, 10))

#: The concrete layer of EnergyPlus' C- and F-factor constructions: thickness [m], conductivity
#: [W/(m K)], density [kg/m3], specific heat [J/(kg K)] (Engineering Reference, "Ground Heat
#: Transfer Calculations using C and F Factor Constructions").
FC_FACTOR_CONCRETE = (0.15, 1.95, 2240.0, 900.0)

#: Film resistances [m2 K/W] an F-factor includes (inside: mean of heat flow up and down; outside)
F_FACTOR_FILMS = (0.135, 0.03)

#: Effective resistance [m2 K/W] of an F-factor floor without exposed perimeter (EnergyPlus)
F_FACTOR_NO_PERIMETER_RESISTANCE = 177.0


def f_factor_resistance(f_factor, area, perimeter_exposed):
    """Resistance [m2 K/W] of the fictitious insulation layer of an F-factor ground floor.

    ``R_eff = A / (P_exp F) - R_film,in - R_film,out`` (the soil and the floor), less the
    0.15 m concrete layer that carries the floor's heat capacity; EnergyPlus' equivalent
    construction is the fictitious layer (outside, no mass) and the concrete (inside).

    Parameters
    ----------
    f_factor : float [W/(m K)]
        Heat flow per metre of exposed perimeter and kelvin between outdoor and indoor air.
    area : float [m2]
        The floor area the F-factor applies to.
    perimeter_exposed : float [m]
        Exposed perimeter; 0 for a floor below grade without one (``R_eff`` = 177 m2 K/W).

    Returns
    -------
    float [m2 K/W]

    References
    ----------
    EnergyPlus Engineering Reference, "Ground Heat Transfer Calculations using C and F Factor
    Constructions", slab-on-grade and underground floors defined with F-factors.
    """
    if perimeter_exposed > 0:
        effective = area / (perimeter_exposed * f_factor) - sum(F_FACTOR_FILMS)
    else:
        effective = F_FACTOR_NO_PERIMETER_RESISTANCE
    return effective - FC_FACTOR_CONCRETE[0] / FC_FACTOR_CONCRETE[1]


def c_factor_resistance(c_factor, height):
    """Resistance [m2 K/W] of the fictitious insulation layer of a C-factor underground wall.

    ``R_eff = 1 / C + R_soil`` with the soil's effective resistance
    ``R_soil = 0.0607 + 0.3479 depth`` (regression of ASHRAE 90.1-2010 Table C6.10.1), held
    at the table's ends as EnergyPlus 25.2 does (0.12 m2 K/W up to 0.25 m, 0.92 m2 K/W from
    2.5 m: the resistances it reports in its eio file), less the 0.15 m concrete layer.

    Parameters
    ----------
    c_factor : float [W/(m2 K)]
        Wall conductance without soil and films.
    height : float [m]
        Depth of the wall below grade.

    Returns
    -------
    float [m2 K/W]

    References
    ----------
    EnergyPlus Engineering Reference, "Ground Heat Transfer Calculations using C and F Factor
    Constructions", underground walls defined with C-factors.
    """
    if height <= 0.25:
        soil = 0.12
    elif height >= 2.5:
        soil = 0.92
    else:
        soil = 0.0607 + 0.3479 * height
    return 1.0 / c_factor + soil - FC_FACTOR_CONCRETE[0] / FC_FACTOR_CONCRETE[1]


def window_type_from_glazing(name: str, glazing, *, angles=WINDOW_TABLE_ANGLES):
    """:class:`~thermocal.multizone.model.WindowType` from layered or simple glazing.

    Parameters
    ----------
    name : str
        Window type (construction) name.
    glazing : LayeredGlazing or SimpleGlazing
    angles : sequence of float [deg]
        Incidence angles of the angular tables.

    Notes
    -----
    ``u_value`` is the NFRC winter centre-of-glass U-factor incl. films (EnergyPlus reports the
    same quantity; its film resistances, about 0.034 + 0.136 m2 K/W, are what the model removes
    to get the glass-to-glass resistance: EnergyPlus' simple-glazing films,
    :func:`thermocal.multizone.network.window_film_resistance`). With gas gaps, the
    glass-to-glass conductance relative to its NFRC winter value is tabulated against the mean
    glazing temperature (:meth:`LayeredGlazing.glass_conductance_ratio`), so the simulation
    follows the temperature dependence of the gap as EnergyPlus' window heat balance does; the
    same table for the panes and gaps with coated gap faces
    (:meth:`LayeredGlazing.coated_conductance_family`) lets a new U-value
    (:meth:`WindowType.with_u_value`) bring the dependence of the glazing that has it.
    ``shgc`` is the NFRC
    summer SHGC at normal incidence. Transmittance and per-pane absorptances are tabulated
    against the angle of incidence; their hemispherical averages give the diffuse values.
    For simple glazing the equivalent layer follows the EnergyPlus angular curves (A-J, chosen
    by U-factor and SHGC).
    """
    from thermocal.multizone import glazing as gz
    from thermocal.multizone.model import WindowType

    if isinstance(glazing, gz.SimpleGlazing):
        system = gz.LayeredGlazing([glazing.as_pane(name)], [], name=name)
        u_value, shgc = glazing.u_factor, glazing.shgc
    else:
        system = glazing
        u_value, shgc = system.u_value(), system.shgc(0.0)
    angles = np.asarray(angles, dtype=float)
    coated_u, coated_ratio = (
        system.coated_conductance_family(GLASS_CONDUCTANCE_TEMPERATURES)
        if system.gaps
        else (None, None)
    )
    tau, _, absorbed = system.optics(angles)
    tau0 = float(tau[0])
    relative = tau / tau0 if tau0 > 0 else np.zeros_like(tau)
    return WindowType(
        name=name,
        u_value=float(u_value),
        shgc=float(shgc),
        solar_transmittance=tau0,
        pane_absorptances=tuple(float(a) for a in absorbed[0]),
        incidence_angles=tuple(angles),
        relative_transmittance=tuple(float(r) for r in relative),
        pane_absorptances_angular=absorbed,
        diffuse_transmittance=float(system.diffuse_transmittance),
        diffuse_pane_absorptances=tuple(float(a) for a in system.diffuse_absorptance),
        n_panes=len(system.panes),
        emissivity_outside=system.panes[0].front_emissivity,
        emissivity_inside=system.panes[-1].back_emissivity,
        glass_conductance_temperatures=GLASS_CONDUCTANCE_TEMPERATURES if system.gaps else None,
        glass_conductance_ratio=tuple(
            float(r) for r in system.glass_conductance_ratio(GLASS_CONDUCTANCE_TEMPERATURES)
        )
        if system.gaps
        else None,
        coated_u_values=None if coated_u is None else tuple(float(u) for u in coated_u),
        coated_glass_conductance_ratio=coated_ratio,
    )


def _reversed_construction(name, constructions, model_constructions, mz) -> str:
    """Name of the construction with reversed layers (created when needed)."""
    cons = next(c for c in model_constructions if c.name == name)
    if tuple(reversed(cons.layers)) == cons.layers:
        return name
    reversed_name = f"{name} (reversed)"
    if not any(c.name == reversed_name for c in model_constructions):
        model_constructions.append(mz.Construction(reversed_name, tuple(reversed(cons.layers))))
    return reversed_name


class ConstructionStages:
    """Stages ``_materials`` and ``_constructions`` of the builder.

    Sets ``materials``, ``model_materials``, ``glass_layers``, ``constructions``,
    ``model_constructions``, ``window_types`` and ``opaque_constructions``; fills
    ``info.glazing``.
    """

    def _materials(self) -> None:
        """Stage: materials."""
        self.materials = _Names("material")
        for rec in self.records(
            "MATERIAL",
            "MATERIAL:NOMASS",
            "MATERIAL:AIRGAP",
            "WINDOWMATERIAL:GLAZING",
            "WINDOWMATERIAL:GAS",
            "WINDOWMATERIAL:SIMPLEGLAZINGSYSTEM",
        ):
            self.materials.add(rec)
        self.model_materials = []
        self.glass_layers: dict[str, object] = {}
        for name, obj, rec in self.materials.values():
            key = obj.key
            if key == "MATERIAL":
                self.model_materials.append(
                    _wrap(
                        obj,
                        self.mz.Material,
                        name=name,
                        conductivity=_number(rec, "conductivity"),
                        density=_number(rec, "density"),
                        specific_heat=_number(rec, "specific_heat"),
                        thickness=_number(rec, "thickness"),
                        thermal_absorptance=_number(rec, "thermal_absorptance", default=0.9),
                        solar_absorptance=_number(rec, "solar_absorptance", default=0.7),
                        roughness=rec["roughness"] or None,
                    )
                )
            elif key == "MATERIAL:NOMASS":
                self.model_materials.append(
                    _wrap(
                        obj,
                        self.mz.NoMassMaterial,
                        name=name,
                        resistance=_number(rec, "thermal_resistance"),
                        thermal_absorptance=_number(rec, "thermal_absorptance", default=0.9),
                        solar_absorptance=_number(rec, "solar_absorptance", default=0.7),
                        roughness=rec["roughness"] or None,
                    )
                )
            elif key == "MATERIAL:AIRGAP":
                self.model_materials.append(
                    _wrap(
                        obj,
                        self.mz.NoMassMaterial,
                        name=name,
                        resistance=_number(rec, "thermal_resistance"),
                    )
                )
            elif key == "WINDOWMATERIAL:GLAZING":
                optical = (rec["optical_data_type"] or "SpectralAverage").upper()
                if optical != "SPECTRALAVERAGE":
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Optical Data "
                        f"Type' = '{rec['optical_data_type']}' is "
                        "not supported; give SpectralAverage data."
                    )
                dirt = _number(rec, "dirt_correction_factor", default=1.0) or 1.0
                self.glass_layers[name.upper()] = _wrap(
                    obj,
                    self.gz.GlassPane,
                    thickness=_number(rec, "thickness"),
                    solar_transmittance=_number(rec, "solar_transmittance") * dirt,
                    front_solar_reflectance=_number(rec, "front_solar_reflectance"),
                    back_solar_reflectance=_number(rec, "back_solar_reflectance"),
                    front_emissivity=_number(rec, "front_infrared_emissivity", default=0.84),
                    back_emissivity=_number(rec, "back_infrared_emissivity", default=0.84),
                    conductivity=_number(rec, "conductivity", default=0.9),
                    infrared_transmittance=_number(rec, "infrared_transmittance", default=0.0),
                    name=name,
                )
            elif key == "WINDOWMATERIAL:GAS":
                gas_type = rec["gas_type"] or "Air"
                if gas_type.upper() == "CUSTOM":
                    fill = self.gz.Gas(
                        name,
                        tuple(
                            _number(rec, f"conductivity_coefficient_{c}", default=0.0)
                            for c in "abc"
                        ),
                        tuple(
                            _number(rec, f"viscosity_coefficient_{c}", default=0.0) for c in "abc"
                        ),
                        tuple(
                            _number(rec, f"specific_heat_coefficient_{c}", default=0.0)
                            for c in "abc"
                        ),
                        _number(rec, "molecular_weight"),
                    )
                else:
                    fill = _wrap(obj, self.gz.gas, gas_type)
                self.glass_layers[name.upper()] = _wrap(
                    obj, self.gz.GasGap, thickness=_number(rec, "thickness"), fill=fill, name=name
                )
            else:  # simple glazing
                self.glass_layers[name.upper()] = _wrap(
                    obj,
                    self.gz.simple_glazing_system,
                    _number(rec, "u_factor"),
                    _number(rec, "solar_heat_gain_coefficient"),
                    _number(rec, "visible_transmittance", required=False),
                    name=name,
                )

    def _constructions(self) -> None:
        """Stage: constructions."""
        self.constructions = _Names("construction")
        for rec in self.records("CONSTRUCTION"):
            self.constructions.add(rec)
        self.model_constructions = []
        self.window_types: dict[str, object] = {}
        self.opaque_constructions: set[str] = set()
        self._fc_factor_constructions()
        for name, obj, rec in self.constructions.values():
            if obj.key != "CONSTRUCTION":
                continue
            layer_names = [g[0] for g in rec["layers"] if g and g[0]]
            if not layer_names:
                raise ThermocalInputError(f"{obj.where()}: the construction has no layers.")
            resolved = []
            for index, layer in enumerate(layer_names, start=1):
                entry = self.materials.get(layer)
                if entry is None:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Layer {index}' = '{layer}' "
                        + self._unsupported_layer(name, layer)
                    )
                resolved.append(entry)
            kinds = {entry[1].key.startswith("WINDOWMATERIAL") for entry in resolved}
            if kinds == {False}:
                self.model_constructions.append(
                    _wrap(
                        obj, self.mz.Construction, name=name, layers=tuple(e[0] for e in resolved)
                    )
                )
                self.opaque_constructions.add(name.upper())
                continue
            if kinds != {True}:
                raise ThermocalInputError(
                    f"{obj.where()}: mixes opaque materials and window materials; a window "
                    "construction must contain only WindowMaterial layers."
                )
            layers = [self.glass_layers[e[0].upper()] for e in resolved]
            if len(layers) == 1 and isinstance(layers[0], self.gz.SimpleGlazing):
                glazing = layers[0]
            else:
                panes = layers[0::2]
                gaps = layers[1::2]
                if not all(isinstance(p, self.gz.GlassPane) for p in panes) or not all(
                    isinstance(g, self.gz.GasGap) for g in gaps
                ):
                    raise ThermocalInputError(
                        f"{obj.where()}: window layers must alternate WindowMaterial:Glazing and "
                        "WindowMaterial:Gas, starting and ending with glazing (shades, blinds and "
                        "simple glazing inside layered constructions are not supported)."
                    )
                glazing = _wrap(obj, self.gz.LayeredGlazing, panes, gaps, name=name)
            self.info.glazing[name] = glazing
            self.window_types[name.upper()] = (name, obj, glazing)

    def _unsupported_layer(self, construction: str, layer: str) -> str:
        """The end of the refusal of a construction layer that is no material the model reads:
        the class of the object of that name (a window screen, shade or blind, which thermocal
        does not model, with what to do), or that none is defined."""
        other = next(
            (
                o
                for o in self.objects
                if o.key.startswith(("MATERIAL", "WINDOWMATERIAL"))
                and o.name.upper() == layer.upper()
            ),
            None,
        )
        if other is None:
            return (
                "is not defined (no Material, Material:NoMass, Material:AirGap or WindowMaterial "
                "of that name)."
            )
        if other.key not in _SHADING_BY_KEY:
            return (
                f"is a {other.class_name} ({other.source} line {other.line}), which thermocal "
                f"does not support; layers can be {', '.join(SUPPORTED_LAYER_CLASSES)}."
            )
        controls = [
            o.name
            for o in self.objects
            if o.key == "WINDOWSHADINGCONTROL"
            and any(f.upper() == construction.upper() for f in o.fields[1:])
        ]
        if controls:
            names = ", ".join(f"'{c}'" for c in controls)
            control = "WindowShadingControl" if len(controls) == 1 else "WindowShadingControls"
            todo = (
                f"remove the {control} {names} and this construction (its windows "
                "keep their unshaded construction)"
            )
        else:
            todo = "remove the layer (or the construction, where nothing uses it)"
        return (
            f"is a {other.class_name} ({other.source} line {other.line}), a window "
            f"{_SHADING_BY_KEY[other.key]}; thermocal does not model window screens, "
            f"shades or blinds. For an unshaded comparison {todo}."
        )

    def _fc_factor_constructions(self) -> None:
        """``Construction:FfactorGroundFloor`` / ``Construction:CfactorUndergroundWall`` as
        EnergyPlus builds them: a fictitious insulation layer without mass (outside) and
        0.15 m of concrete (inside); their surfaces face ``Site:GroundTemperature:FCfactorMethod``
        (see the ground stage)."""
        #: names (upper case) of the F/C-factor constructions
        self.fc_factor_constructions: set[str] = set()
        concrete = None
        for rec in self.records(
            "CONSTRUCTION:FFACTORGROUNDFLOOR", "CONSTRUCTION:CFACTORUNDERGROUNDWALL"
        ):
            self.constructions.add(rec)
            obj = rec["_object"]
            name = rec["name"]
            if obj.key == "CONSTRUCTION:FFACTORGROUNDFLOOR":
                f_factor = _number(rec, "f_factor")
                area = _number(rec, "area")
                perimeter = _number(rec, "perimeterexposed")
                for label, value in (("F-Factor", f_factor), ("Area", area)):
                    if value <= 0:
                        raise ThermocalInputError(
                            f"{obj.where()}: field '{label}' = {value:g} must be positive."
                        )
                if perimeter < 0:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'PerimeterExposed' = {perimeter:g} must be 0 or "
                        "more."
                    )
                resistance = f_factor_resistance(f_factor, area, perimeter)
                what = f"F-factor {f_factor:g} W/(m K), area {area:g} m2, perimeter {perimeter:g} m"
            else:
                c_factor = _number(rec, "c_factor")
                height = _number(rec, "height")
                if c_factor <= 0 or height < 0:
                    raise ThermocalInputError(
                        f"{obj.where()}: fields 'C-Factor' = {c_factor:g} and 'Height' = "
                        f"{height:g} must be positive (height 0 or more)."
                    )
                resistance = c_factor_resistance(c_factor, height)
                what = f"C-factor {c_factor:g} W/(m2 K), height {height:g} m"
            if resistance <= 0:
                raise ThermocalInputError(
                    f"{obj.where()}: {what} give a fictitious insulation resistance of "
                    f"{resistance:.3f} m2 K/W <= 0 (the floor or wall conducts more than 0.15 m "
                    "of concrete alone); check the fields, as EnergyPlus refuses it too."
                )
            if concrete is None:
                thickness, conductivity, density, specific_heat = FC_FACTOR_CONCRETE
                concrete = self.mz.Material(
                    name="C/F-factor concrete 0.15 m",
                    conductivity=conductivity,
                    density=density,
                    specific_heat=specific_heat,
                    thickness=thickness,
                    thermal_absorptance=0.9,
                    solar_absorptance=0.7,
                    roughness="MediumRough",
                )
                self.model_materials.append(concrete)
            insulation = self.mz.NoMassMaterial(
                name=f"{name} fictitious insulation", resistance=resistance
            )
            self.model_materials.append(insulation)
            self.model_constructions.append(
                _wrap(obj, self.mz.Construction, name=name, layers=(insulation.name, concrete.name))
            )
            self.opaque_constructions.add(name.upper())
            self.fc_factor_constructions.add(name.upper())
