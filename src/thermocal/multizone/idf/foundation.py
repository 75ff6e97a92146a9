"""EnergyPlus's ``Foundation`` boundary (Kiva) read into a ground section.

A floor whose ``Outside Boundary Condition`` is ``Foundation`` gets the two-dimensional section
of :mod:`thermocal.multizone.foundation` from its ``Foundation:Kiva`` object (the foundation
wall's construction, its height above grade and depth below the slab), its
``SurfaceProperty:ExposedFoundationPerimeter`` and the file's ``Foundation:Kiva:Settings``
(soil, far field, deep ground), with EnergyPlus's own defaults for what the file leaves out.
Walls on a ``Foundation`` boundary (a basement's) stay adiabatic, with a note.
"""

from __future__ import annotations

import numpy as np

from thermocal.errors import ThermocalInputError

__all__ = ["exposed_perimeter", "foundation_ground", "kiva_settings"]

#: Foundation:Kiva fields (0-based) the section takes, and the insulation and footing fields it
#: does not model.
_WALL_HEIGHT, _WALL_DEPTH, _WALL_CONSTRUCTION = 12, 13, 14
_NOT_MODELLED = {15: "footing"}
#: Foundation:Kiva's insulation: kind, (material, depth, width) field positions (None: no
#: width field).
_INSULATION_FIELDS = {
    "interior_horizontal": (2, 3, 4),
    "interior_vertical": (5, 6, None),
    "exterior_horizontal": (7, 8, 9),
    "exterior_vertical": (10, 11, None),
}
#: EnergyPlus's defaults of Foundation:Kiva's wall (Input Output Reference).
_DEFAULT_HEIGHT_ABOVE_GRADE, _DEFAULT_DEPTH_BELOW_SLAB = 0.2, 0.0
#: Kiva's default foundation wall without a Footing Wall Construction: 0.3 m of concrete
#: (``KivaManager::defineDefaultFoundation``): thickness [m], conductivity [W/(m K)], density
#: [kg/m3], specific heat [J/(kg K)].
_DEFAULT_WALL = ((0.3, 1.95, 2400.0, 900.0),)
#: The water table's depth per metre of the site's elevation (Kiva's ``Autoselect``).
_WATER_TABLE_PER_ELEVATION = 0.1022


def _number(obj, index: int, default: float, what: str) -> float:
    fields = obj.fields
    raw = fields[index].strip() if index < len(fields) else ""
    if not raw or raw.upper() == "AUTOCALCULATE":
        return default
    try:
        return float(raw)
    except ValueError:
        raise ThermocalInputError(
            f"{obj.where()}: field '{what}' = '{raw}' is not a number"
        ) from None


def kiva_settings(objects, elevation: float) -> tuple[dict, list[str]]:
    """The soil and the domain of the file's ``Foundation:Kiva:Settings`` (EnergyPlus's code
    defaults for what it leaves blank or when it has none).

    Parameters
    ----------
    objects : list of IdfObject
    elevation : float [m]
        The site's elevation (Kiva puts the water table at 0.1022 m per metre of it).

    Returns
    -------
    settings : dict
        ``soil`` (conductivity [W/(m K)], density [kg/m3], specific heat [J/(kg K)]),
        ``far_field_width``, ``deep_ground_depth`` and ``grade_roughness`` [m].
    notes : list of str
    """
    from thermocal.multizone.foundation import KIVA_DEFAULT_ROUGHNESS, KIVA_DEFAULT_SOIL

    found = [o for o in objects if o.key == "FOUNDATION:KIVA:SETTINGS"]
    notes = []
    k, rho, cp = KIVA_DEFAULT_SOIL
    far, deep, boundary = 40.0, 40.0, "AUTOSELECT"
    roughness = KIVA_DEFAULT_ROUGHNESS
    if found:
        obj = found[0]
        k = _number(obj, 0, k, "Soil Conductivity")
        rho = _number(obj, 1, rho, "Soil Density")
        cp = _number(obj, 2, cp, "Soil Specific Heat")
        roughness = _number(obj, 5, roughness, "Ground Surface Roughness")
        far = _number(obj, 6, far, "Far-Field Width")
        boundary = (obj.fields[7].strip().upper() if len(obj.fields) > 7 else "") or boundary
        deep = _number(obj, 8, deep, "Deep-Ground Depth")
    else:
        notes.append(
            "Foundation floors: no Foundation:Kiva:Settings, so EnergyPlus's own soil "
            f"(conductivity {k} W/(m K), density {rho:.0f} kg/m3, specific heat {cp:.0f} "
            "J/(kg K); not the 1.73 W/(m K) its Input Output Reference documents)"
        )
    water_table = _WATER_TABLE_PER_ELEVATION * max(float(elevation), 0.0)
    if boundary == "GROUNDWATER" or (boundary == "AUTOSELECT" and water_table <= 40.0):
        depth = water_table if boundary == "AUTOSELECT" else deep
        notes.append(
            "Foundation floors: Kiva holds the deep ground at the annual mean air temperature "
            f"at {depth:.1f} m (a water table); thermocal's section has no heat flow across "
            f"its bottom at {max(deep, 40.0):.0f} m instead (a shallow zero-flux bottom would "
            "insulate the slab: 45.7 against 59.9 W/K at 1 m on NREL's SingleFamilyHouse)"
        )
        deep = max(deep, 40.0)
    return {
        "soil": (k, rho, cp),
        "far_field_width": far,
        "deep_ground_depth": deep,
        "grade_roughness": roughness,
    }, notes


def exposed_perimeter(name: str, vertices, objects) -> float:
    """Exposed perimeter [m] of a floor from its ``SurfaceProperty:ExposedFoundationPerimeter``
    (the whole polygon's when it has none: EnergyPlus 25.2 refuses such a file, see
    :func:`foundation_ground`'s note)."""
    pts = np.asarray(vertices, dtype=float)
    sides = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
    for obj in objects:
        if obj.key != "SURFACEPROPERTY:EXPOSEDFOUNDATIONPERIMETER":
            continue
        if not obj.fields or obj.fields[0].strip().upper() != name.upper():
            continue
        method = (obj.fields[1] if len(obj.fields) > 1 else "").strip().upper()
        values = list(obj.fields[2:])
        try:
            if method == "TOTALEXPOSEDPERIMETER":
                return float(values[0])
            if method == "EXPOSEDPERIMETERFRACTION":
                return float(sides.sum()) * float(values[1])
            if method == "BYSEGMENT":
                flags = [v.strip().upper() == "YES" for v in values[2 : 2 + len(sides)]]
                return float(sum(s for s, f in zip(sides, flags, strict=False) if f))
        except (IndexError, ValueError) as exc:
            raise ThermocalInputError(
                f"{obj.where()}: cannot read the exposed perimeter ({exc})"
            ) from None
        raise ThermocalInputError(f"{obj.where()}: unknown calculation method {method!r}")
    return float(sides.sum())


def _construction_layers(construction_name: str, where: str, materials, constructions):
    """A construction's layers, inside first, as (thickness, conductivity, density, specific
    heat) tuples (EnergyPlus's Kiva refuses a layer without mass too)."""
    from thermocal.multizone.model import Material

    construction = constructions.get(construction_name.upper())
    if construction is None:
        raise ThermocalInputError(
            f"{where}: construction '{construction_name}' is not a construction of the file"
        )
    layers = []
    for layer_name in reversed(construction.layers):
        layer = materials.get(layer_name.upper())
        if not isinstance(layer, Material):
            raise ThermocalInputError(
                f"{where}: layer '{layer_name}' of construction '{construction_name}' is not a "
                "Material with thickness, conductivity, density and specific heat (EnergyPlus's "
                "Kiva refuses it too)"
            )
        layers.append((layer.thickness, layer.conductivity, layer.density, layer.specific_heat))
    return tuple(layers)


def _outside_surface(construction_name: str, materials, constructions) -> tuple[float, float]:
    """A construction's outside layer's solar absorptance and thermal emissivity [-] (Kiva's
    foundation wall above the grade: ``OutsideAbsorpSolar``, ``OutsideAbsorpThermal``)."""
    from thermocal.multizone.foundation import WALL_ABSORPTANCE, WALL_EMISSIVITY

    construction = constructions.get(construction_name.upper())
    outer = materials.get(construction.layers[0].upper()) if construction else None
    alpha = getattr(outer, "solar_absorptance", None)
    eps = getattr(outer, "thermal_absorptance", None)
    return (
        WALL_ABSORPTANCE if alpha is None else float(alpha),
        WALL_EMISSIVITY if eps is None else float(eps),
    )


def _insulation_blocks(kiva, materials) -> tuple:
    """``Foundation:Kiva``'s insulation blocks as
    :attr:`thermocal.multizone.foundation.FoundationGround.insulation` (a block's thickness is
    its material's; a depth or width left blank is 0, and a block of no extent is none)."""
    from thermocal.multizone.model import Material

    out = []
    fields = kiva.fields
    for kind, (mat_at, depth_at, width_at) in _INSULATION_FIELDS.items():
        name = fields[mat_at].strip() if mat_at < len(fields) else ""
        if not name:
            continue
        material = materials.get(name.upper())
        if not isinstance(material, Material):
            raise ThermocalInputError(
                f"{kiva.where()}: insulation material '{name}' is not a Material with thickness, "
                "conductivity, density and specific heat (EnergyPlus's Kiva refuses it too)"
            )
        depth = _number(kiva, depth_at, 0.0, f"{kind.replace('_', ' ')} depth")
        width = 0.0 if width_at is None else _number(kiva, width_at, 0.0, "insulation width")
        if (width if kind.endswith("horizontal") else depth) <= 0.0:
            continue  # a block of no extent is none
        out.append((
            kind, material.thickness, material.conductivity, material.density,
            material.specific_heat, depth, width,
        ))  # fmt: skip
    return tuple(out)


def foundation_ground(
    name, vertices, foundation_name, objects, materials, constructions, settings, walls=(),
    floor_construction=None,
):  # fmt: skip
    """The ground section of one floor on a ``Foundation`` boundary.

    Parameters
    ----------
    name : str
        The floor surface.
    vertices : array (n, 3) [m]
        Its vertices.
    foundation_name : str
        Its ``Outside Boundary Condition Object`` (the ``Foundation:Kiva``).
    objects : list of IdfObject
    materials : dict
        thermocal materials by upper-case name (for the foundation wall's layers).
    constructions : dict
        thermocal constructions by upper-case name.
    settings : dict
        :func:`kiva_settings`'s.
    walls : sequence of (name, vertices (n, 3) [m], construction name)
        The walls of the same zone on the same ``Foundation:Kiva`` (a basement): EnergyPlus
        takes their height as the foundation's depth and their construction as its wall.
    floor_construction : str, optional
        The floor's construction: its outside layer's roughness is DOE-2's multiplier of the
        grade's convection in Kiva (medium rough, 1.52, without it).

    Returns
    -------
    ground : FoundationGround or None
        None when the floor has no exposed perimeter (no heat to the outside through it).
    notes : list of str
    """
    from thermocal.multizone.foundation import FoundationGround

    notes = []
    kiva = next(
        (
            o
            for o in objects
            if o.key == "FOUNDATION:KIVA" and o.fields and o.fields[0].strip().upper()
            == foundation_name.strip().upper()
        ),
        None,
    )
    insulation = ()
    from thermocal.multizone.foundation import WALL_ABSORPTANCE, WALL_EMISSIVITY

    wall_surface = (WALL_ABSORPTANCE, WALL_EMISSIVITY)  # Kiva's default wall's
    height, depth, wall_layers = (
        _DEFAULT_HEIGHT_ABOVE_GRADE,
        _DEFAULT_DEPTH_BELOW_SLAB,
        _DEFAULT_WALL,
    )
    if kiva is not None:
        height = _number(kiva, _WALL_HEIGHT, height, "Wall Height Above Grade")
        depth = _number(kiva, _WALL_DEPTH, depth, "Wall Depth Below Slab")
        missing = [
            what
            for index, what in _NOT_MODELLED.items()
            if index < len(kiva.fields) and kiva.fields[index].strip()
        ]
        if missing:
            notes.append(
                f"floor '{name}': the {', '.join(missing)} of {kiva.where()} is not modelled "
                "(the ground section has the wall, its insulation and the soil)"
            )
        insulation = _insulation_blocks(kiva, materials)
        wall = kiva.fields[_WALL_CONSTRUCTION].strip() if len(kiva.fields) > 14 else ""
        if wall:
            wall_layers = _construction_layers(
                wall, f"{kiva.where()} (Footing Wall Construction Name)", materials, constructions
            )
            wall_surface = _outside_surface(wall, materials, constructions)
    perimeter = exposed_perimeter(name, vertices, objects)
    if not any(
        o.key == "SURFACEPROPERTY:EXPOSEDFOUNDATIONPERIMETER"
        and o.fields and o.fields[0].strip().upper() == name.upper()
        for o in objects
    ):
        notes.append(
            f"floor '{name}': no SurfaceProperty:ExposedFoundationPerimeter (EnergyPlus needs "
            f"one): its whole perimeter, {perimeter:.1f} m, taken as exposed"
        )
    if perimeter <= 0.0:
        notes.append(f"floor '{name}': no exposed perimeter; treated as adiabatic")
        return None, notes
    basement_depth, shares = 0.0, ()
    if walls:
        lengths, heights = [], []
        for _, wall_vertices, _ in walls:
            pts = np.asarray(wall_vertices, dtype=float)
            heights.append(float(np.ptp(pts[:, 2])))
            lengths.append(float(np.ptp(pts[:, 0]) ** 2 + np.ptp(pts[:, 1]) ** 2) ** 0.5)
        total = sum(lengths)
        basement_depth = float(np.average(heights, weights=lengths))
        shares = tuple((w[0], length / total) for w, length in zip(walls, lengths, strict=True))
        wall_layers = _construction_layers(
            walls[0][2], f"wall '{walls[0][0]}'", materials, constructions
        )
        wall_surface = _outside_surface(walls[0][2], materials, constructions)
        notes.append(
            f"floor '{name}': a basement on {foundation_name} ({len(walls)} walls "
            f"{basement_depth:.2f} m high, {total:.1f} m of the exposed perimeter's "
            f"{perimeter:.1f} m): one ground section under the floor and beside the walls, whose "
            "outside faces meet the soil below the grade and the outdoor air above it"
            + (
                "; the walls' constructions differ, the section takes the first's"
                if len({w[2].upper() for w in walls}) > 1
                else ""
            )
        )
    # Kiva's grade takes DOE-2's roughness multiplier of the floor surface (its outside layer)
    from thermocal.multizone.model import ROUGHNESS_FACTORS

    roughness_factor = 1.52
    floor = constructions.get(str(floor_construction or "").upper())
    if floor is not None and floor.layers:
        outer = materials.get(floor.layers[0].upper())
        roughness_factor = ROUGHNESS_FACTORS.get(getattr(outer, "roughness", None), 1.52)
    ground = FoundationGround(
        exposed_perimeter=perimeter,
        soil=settings["soil"],
        wall_layers=wall_layers,
        wall_height_above_grade=height,
        wall_depth_below_slab=depth,
        deep_ground_depth=settings["deep_ground_depth"],
        far_field_width=settings["far_field_width"],
        grade_roughness=settings.get("grade_roughness", 0.9),
        grade_roughness_factor=roughness_factor,
        insulation=insulation,
        basement_depth=basement_depth,
        walls=shares,
        wall_absorptance=wall_surface[0],
        wall_emissivity=wall_surface[1],
    )
    return ground, notes
