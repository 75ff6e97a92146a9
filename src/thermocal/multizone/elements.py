"""Element-level envelope parameters: what a building physicist names and checks.

A calibration that moves ``material/<name>/conductivity`` and ``material/<name>/density`` answers
in the terms of a material database; a facility manager asks "is it the roof or the walls?".
This module names each opaque construction by its *role* in the envelope and gives it two
parameters, with the layers scaled consistently:

``construction/<name>/resistance`` [m2 K/W]
    Thermal resistance of the layers (surface films excluded, ISO 6946). A new value scales the
    resistance of every layer by the same factor: conductivities of massive layers are divided
    by it, no-mass resistances multiplied, thicknesses and heat capacities unchanged.
``construction/<name>/heat_capacity`` [J/(m2 K)]
    Areal heat capacity ``sum(rho c d)`` of the massive layers. A new value scales every massive
    layer's density by the same factor (resistances unchanged).

A construction whose layers share a material with another construction gets its own copies of
those materials (named ``"<material> (<construction>)"``), so that changing the roof does not
change the wall. Window types (``window/<name>/{u_value,shgc}``) and infiltration
(``zone/<name>/infiltration_ach``, ``infiltration/<group>/ach``) are already element-level.

Roles follow each construction's surfaces (the role of the largest area when several):
``exterior_wall``, ``roof``, ``exposed_floor`` (outdoors), ``ground_floor``, ``ground_wall``
(ground), ``partition``, ``interzone_floor`` (between zones), ``internal_mass`` (adiabatic).

An inter-zone wall is described from both sides (two surfaces, each with a construction), but the
model builds it once, from the first surface of the pair in the building's order
(:func:`built_surfaces`); the partner's side is that construction's other face. A construction
found only on such far sides (an IDF's ``reverseCEILING``, or the ``"<name> (reversed)"`` the
IDF import makes for a surface whose boundary is a zone) changes nothing in the model, so it has
no element parameters, and naming one is an error that says which construction to set instead.
Likewise a material in no construction the model builds and a window type no window uses are
listed by :meth:`Building.parameters` but change nothing (:func:`unused_parameters`): a
calibration leaves them out rather than spend its samples on them.

The functions take the multi-zone model's ``Building`` and ``Surface`` (named in their
docstrings; not imported here: the model applies these parameters, so importing it back would
tie the two modules in a circle).

References
----------
.. [1] ISO 6946:2017, Building components and building elements -- Thermal resistance and
   thermal transmittance -- Calculation methods.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from thermocal.errors import ThermocalInputError

__all__ = [
    "ELEMENT_KINDS",
    "apply_element_parameters",
    "built_surfaces",
    "construction_roles",
    "far_side_constructions",
    "element_parameters",
    "is_element_parameter",
    "surface_role",
    "unmirrored_partners",
    "unmirrored_partners_note",
    "unused_parameters",
]

#: Kinds of the construction-level parameters and their units.
ELEMENT_KINDS: dict[str, str] = {"resistance": "m2 K/W", "heat_capacity": "J/(m2 K)"}


def is_element_parameter(name: str) -> bool:
    """Whether ``name`` is a construction-level parameter (``construction/<name>/<kind>``)."""
    parts = str(name).split("/")
    return len(parts) >= 3 and parts[0] == "construction" and parts[-1] in ELEMENT_KINDS


def surface_role(surface) -> str:
    """Role of an opaque surface in the envelope, from its boundary and tilt.

    Parameters
    ----------
    surface : thermocal.multizone.model.Surface
        The surface (tilt [deg] of the outward normal: 0 facing up, 90 vertical, 180 down).

    Returns
    -------
    str
        One of ``exterior_wall``, ``roof``, ``exposed_floor``, ``ground_floor``,
        ``ground_wall``, ``partition``, ``interzone_floor``, ``internal_mass``.
    """
    tilt = float(surface.tilt)
    if surface.boundary == "adiabatic":
        return "internal_mass"
    if surface.boundary == "ground":
        return "ground_wall" if 45.0 <= tilt <= 135.0 else "ground_floor"
    if surface.boundary == "zone":
        return "partition" if 45.0 <= tilt <= 135.0 else "interzone_floor"
    if tilt < 45.0:
        return "roof"
    if tilt > 135.0:
        return "exposed_floor"
    return "exterior_wall"


def built_surfaces(surfaces) -> list:
    """The surfaces whose construction the model builds, in their order.

    Every surface but the second of each inter-zone pair (``boundary="zone"``): the network
    (:func:`thermocal.multizone.network.assemble`) builds an inter-zone wall once, from the
    first surface of the pair, and its partner's inside face is that wall's outside face.

    Parameters
    ----------
    surfaces : iterable of thermocal.multizone.model.Surface
        A building's surfaces in its order (``building.surfaces.values()``).

    Returns
    -------
    list of thermocal.multizone.model.Surface
    """
    built, far_sides = [], set()
    for surface in surfaces:
        if surface.name in far_sides:
            continue
        built.append(surface)
        if surface.boundary == "zone" and surface.other_surface is not None:
            far_sides.add(surface.other_surface)
    return built


def unmirrored_partners(
    surfaces, layers: Mapping, *, identical_is_mirror: bool = False
) -> dict[tuple[str, str], list[tuple[str, str]]]:
    """Inter-zone walls whose far side's construction is not the mirror of the built side's.

    The model builds an inter-zone wall once, from the first surface of the pair
    (:func:`built_surfaces`), and does not read its partner's construction: a partner whose
    layers are not the first's reversed describes another wall than the one built.

    Parameters
    ----------
    surfaces : iterable of thermocal.multizone.model.Surface
        A building's surfaces in its order.
    layers : mapping of str to sequence of str
        Construction name -> its layer names, outside -> inside.
    identical_is_mirror : bool
        Take the same layers on both sides for a mirror too (thermocal's building file names
        one construction from both sides, as its documented example does; EnergyPlus gives
        each side its own and warns).

    Returns
    -------
    dict of (str, str) to list of (str, str)
        (built construction, far construction) -> the walls as (built surface, far surface),
        in the building's order.
    """
    surfaces = list(surfaces)
    by_name = {surface.name: surface for surface in surfaces}
    pairs: dict[tuple[str, str], list[tuple[str, str]]] = {}
    for surface in built_surfaces(surfaces):
        if surface.boundary != "zone" or surface.other_surface not in by_name:
            continue
        partner = by_name[surface.other_surface]
        built = tuple(layers.get(surface.construction, ()))
        far = layers.get(partner.construction)
        mirrors = {tuple(reversed(built)), *([built] if identical_is_mirror else [])}
        if far is None or tuple(far) not in mirrors:
            key = (surface.construction, partner.construction)
            pairs.setdefault(key, []).append((surface.name, partner.name))
    return pairs


def unmirrored_partners_note(built: str, far: str, walls: list[tuple[str, str]]) -> str:
    """The note on inter-zone walls whose two sides are not each other's mirror.

    Parameters
    ----------
    built, far : str
        The construction the model builds (the first surface's of each pair) and the one on
        the far side, which it does not read.
    walls : list of (str, str)
        The walls as (built surface, far surface), from :func:`unmirrored_partners`.

    Returns
    -------
    str
    """
    first, partner = walls[0]
    more = f", and {len(walls) - 1} more" if len(walls) > 1 else ""
    return (
        f"{len(walls)} inter-zone wall(s) with construction '{built}' on one side and '{far}' "
        f"on the other (surface '{first}' and its partner '{partner}'{more}), whose layers are "
        f"not the first's reversed: EnergyPlus gives each side its own; thermocal builds each "
        f"wall once, from '{built}' (the first surface of the pair in the file), and does not "
        f"read '{far}'"
    )


def far_side_constructions(building) -> dict[str, str]:
    """Constructions found only on the far side of inter-zone walls, and the one built there.

    Parameters
    ----------
    building : thermocal.multizone.model.Building

    Returns
    -------
    dict of str to str
        Construction name -> the construction the model builds for those walls (of the first
        such wall, in the building's order).
    """
    built = built_surfaces(building.surfaces.values())
    built_constructions = {surface.construction for surface in built}
    opposite: dict[str, str] = {}
    for surface in built:
        if surface.boundary != "zone" or surface.other_surface is None:
            continue
        partner = building.surfaces[surface.other_surface]
        if partner.construction not in built_constructions:
            opposite.setdefault(partner.construction, surface.construction)
    return opposite


def unused_parameters(building) -> dict[str, str]:
    """The names of :meth:`Building.parameters` that change nothing in the model, and why.

    A material in no construction of a surface the model builds (:func:`built_surfaces`:
    e.g. a file's library material, or one only in a construction on the far side of
    inter-zone walls), and a window type no window uses.

    Parameters
    ----------
    building : thermocal.multizone.model.Building

    Returns
    -------
    dict of str to str
        Parameter name -> the reason, in the order of :meth:`Building.parameters`.
    """
    built = {s.construction for s in built_surfaces(building.surfaces.values())}
    in_use = {layer for name in built for layer in building.constructions[name].layers}
    window_types = {window.window_type for window in building.windows.values()}
    unused: dict[str, str] = {}
    for name in building.parameters():
        parts = str(name).split("/")
        owner = "/".join(parts[1:-1])
        if parts[0] == "material" and owner not in in_use:
            unused[name] = f"material '{owner}' is in no construction of a surface the model builds"
        elif parts[0] == "window" and owner not in window_types:
            unused[name] = f"window type '{owner}' is used by no window"
    return unused


def construction_roles(building) -> dict[str, str]:
    """Role of each construction the model builds (the role of its largest total area).

    The far side of an inter-zone wall counts for the construction built there, not for its own
    (:func:`built_surfaces`).

    Parameters
    ----------
    building : thermocal.multizone.model.Building

    Returns
    -------
    dict of str to str
        Construction name -> role (see :func:`surface_role`), in the building's order.
    """
    areas: dict[str, dict[str, float]] = {}
    for surface in built_surfaces(building.surfaces.values()):
        by_role = areas.setdefault(surface.construction, {})
        role = surface_role(surface)
        by_role[role] = by_role.get(role, 0.0) + float(surface.area)
    return {
        name: max(areas[name].items(), key=lambda item: item[1])[0]
        for name in building.constructions
        if name in areas
    }


def _layer_totals(building, construction: str) -> tuple[float, float]:
    """Resistance [m2 K/W] and areal heat capacity [J/(m2 K)] of a construction's layers."""
    layers = building.construction_layers(construction)
    resistance = float(sum(layer.resistance for layer in layers))
    capacity = float(sum(getattr(layer, "heat_capacity", 0.0) for layer in layers))
    return resistance, capacity


def element_parameters(building) -> dict[str, float]:
    """Construction-level parameters of every construction used by a surface.

    Parameters
    ----------
    building : thermocal.multizone.model.Building

    Returns
    -------
    dict of str to float
        ``construction/<name>/resistance`` [m2 K/W] and, for constructions with massive layers,
        ``construction/<name>/heat_capacity`` [J/(m2 K)].
    """
    params: dict[str, float] = {}
    for name in construction_roles(building):
        resistance, capacity = _layer_totals(building, name)
        params[f"construction/{name}/resistance"] = resistance
        if capacity > 0.0:
            params[f"construction/{name}/heat_capacity"] = capacity
    return params


def element_limits(building) -> dict[str, tuple[float, float]]:
    """The values of each element parameter whose scaled layers the model accepts.

    A new resistance divides every massive layer's conductivity by one factor and a new heat
    capacity multiplies every massive layer's density by one factor; each scaled property must
    stay inside the model's plausible range (:data:`thermocal.multizone.model.PLAUSIBLE`, e.g.
    a density of at least 5 kg/m3), so the factor is bounded by the layer nearest to a limit.

    Parameters
    ----------
    building : thermocal.multizone.model.Building

    Returns
    -------
    dict of str to (float, float)
        ``construction/<name>/resistance`` [m2 K/W] and ``.../heat_capacity`` [J/(m2 K)] ->
        lower and upper limit (``inf`` when unbounded).
    """
    from thermocal.multizone.model import PLAUSIBLE

    k_low, k_high = PLAUSIBLE["conductivity"][:2]
    rho_low, rho_high = PLAUSIBLE["density"][:2]
    limits: dict[str, tuple[float, float]] = {}
    for name, value in element_parameters(building).items():
        parts = name.split("/")
        construction, kind = "/".join(parts[1:-1]), parts[-1]
        massive = [m for m in building.construction_layers(construction) if hasattr(m, "density")]
        if kind == "resistance":  # conductivity / f in [k_low, k_high]
            low = max((m.conductivity / k_high for m in massive), default=0.0)
            high = min((m.conductivity / k_low for m in massive), default=np.inf)
        else:  # density * f in [rho_low, rho_high]
            low = max(rho_low / m.density for m in massive)
            high = min(rho_high / m.density for m in massive)
        # a hair inside, so that a sample on the limit is not refused by round-off
        limits[name] = (float(low * value * (1.0 + 1e-9)), float(high * value * (1.0 - 1e-9)))
    return limits


def window_limits(building) -> dict[str, tuple[float, float]]:
    """The SHGC each window type of the building can take (:attr:`WindowType.shgc_limit`).

    Parameters
    ----------
    building : thermocal.multizone.model.Building

    Returns
    -------
    dict of str to (float, float)
        ``window/<type>/shgc`` -> lower and upper limit [-] (a hair inside the upper, so that
        a sample on it is not refused by round-off).
    """
    return {
        f"window/{name}/shgc": (0.0, float(wt.shgc_limit) * (1.0 - 1e-9))
        for name, wt in building.window_types.items()
    }


def _scaled_layer(layer, resistance_factor: float, capacity_factor: float):
    """A layer with its resistance and heat capacity scaled [-]."""
    if hasattr(layer, "conductivity"):
        return dataclasses.replace(
            layer,
            conductivity=layer.conductivity / resistance_factor,
            density=layer.density * capacity_factor,
        )
    return dataclasses.replace(layer, resistance=layer.resistance * resistance_factor)


def apply_element_parameters(building, mapping: Mapping[str, float]):
    """Copy of the building with construction-level parameters set.

    Parameters
    ----------
    building : thermocal.multizone.model.Building
    mapping : mapping of str to float
        ``construction/<name>/resistance`` [m2 K/W] and/or
        ``construction/<name>/heat_capacity`` [J/(m2 K)]; relative to the building's current
        layers (apply material-level changes first).

    Returns
    -------
    thermocal.multizone.model.Building
        The layers of each named construction scaled (its own copies of shared materials).

    Raises
    ------
    ThermocalInputError
        An unknown construction, a non-positive value, or a heat capacity for a construction
        without massive layers.
    """
    wanted: dict[str, dict[str, float]] = {}
    far_side = far_side_constructions(building)
    for key, value in mapping.items():
        if not is_element_parameter(key):
            raise ThermocalInputError(f"'{key}' is not a construction-level parameter")
        parts = str(key).split("/")
        name, kind = "/".join(parts[1:-1]), parts[-1]
        if name not in building.constructions:
            raise ThermocalInputError(
                f"unknown building parameter '{key}': no construction '{name}' (see "
                "thermocal.multizone.elements.element_parameters)"
            )
        if name in far_side:
            raise ThermocalInputError(
                f"building parameter '{key}': construction '{name}' is only the far side of "
                f"inter-zone walls that the model builds from '{far_side[name]}' (one wall per "
                f"pair of surfaces, from the first); set 'construction/{far_side[name]}/{kind}' "
                "instead"
            )
        number = float(value)
        if not np.isfinite(number) or number <= 0.0:
            raise ThermocalInputError(f"building parameter '{key}' must be > 0, got {value!r}")
        wanted.setdefault(name, {})[kind] = number
    if not wanted:
        return building
    usage: dict[str, set[str]] = {}
    for cname, construction in building.constructions.items():
        for layer in construction.layers:
            usage.setdefault(layer, set()).add(cname)
    materials = dict(building.materials)
    constructions = dict(building.constructions)
    for cname, values in wanted.items():
        resistance, capacity = _layer_totals(building, cname)
        r_factor = values.get("resistance", resistance) / resistance
        if "heat_capacity" in values and capacity <= 0.0:
            raise ThermocalInputError(
                f"building parameter 'construction/{cname}/heat_capacity': the construction "
                "has no massive layer to scale"
            )
        c_factor = values["heat_capacity"] / capacity if "heat_capacity" in values else 1.0
        layers = []
        for layer_name in constructions[cname].layers:
            own = layer_name if usage[layer_name] == {cname} else f"{layer_name} ({cname})"
            if own not in materials or own == layer_name:
                scaled = _scaled_layer(building.materials[layer_name], r_factor, c_factor)
                materials[own] = dataclasses.replace(scaled, name=own)
            layers.append(own)
        constructions[cname] = dataclasses.replace(constructions[cname], layers=tuple(layers))
    # the far side of a changed inter-zone wall stays its mirror (the model does not read it,
    # but a calibrated building file should not describe the two faces of one wall differently)
    for far, built in far_side.items():
        before = building.constructions
        if built in wanted and tuple(before[far].layers) == tuple(reversed(before[built].layers)):
            mirrored = tuple(reversed(constructions[built].layers))
            constructions[far] = dataclasses.replace(constructions[far], layers=mirrored)
    return building.replaced(materials=materials, constructions=constructions)
