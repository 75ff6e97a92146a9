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

#: Angles [deg] of the angular optics tables handed to the WindowType.
WINDOW_TABLE_ANGLES = tuple(float(a) for a in range(0, 91, 5))

#: tabulated (the simulation interpolates, and holds the end values outside).
GLASS_CONDUCTANCE_TEMPERATURES = tuple(float(t) for t in range(-40, 101, 10))


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
    same quantity; its film resistances, about 0.034 + 0.136 m2 K/W, are close to the ISO 6946
    0.04 + 0.13 the model removes to get the glass-to-glass resistance). With gas gaps, the
    glass-to-glass conductance relative to its NFRC winter value is tabulated against the mean
    glazing temperature (:meth:`LayeredGlazing.glass_conductance_ratio`), so the simulation
    follows the temperature dependence of the gap as EnergyPlus' window heat balance does.
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
        for name, obj, rec in self.constructions.values():
            layer_names = [g[0] for g in rec["layers"] if g and g[0]]
            if not layer_names:
                raise ThermocalInputError(f"{obj.where()}: the construction has no layers.")
            resolved = []
            for index, layer in enumerate(layer_names, start=1):
                entry = self.materials.get(layer)
                if entry is None:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Layer {index}' = '{layer}' is not defined (no "
                        "Material, Material:NoMass, Material:AirGap "
                        "or WindowMaterial of that name)."
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
