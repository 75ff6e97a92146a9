"""Two-dimensional ground under a slab floor, as EnergyPlus's ``Foundation`` boundary (Kiva).

EnergyPlus couples a floor on a ``Foundation`` boundary to Kiva, a finite-volume model of the
ground around the foundation. By default it reduces the three-dimensional foundation to a
two-dimensional section (Kruis and Krarti 2017, the "area over perimeter" reduction): the slab
extends from a symmetry plane to ``A / P`` (floor area over exposed perimeter), the foundation wall
stands at its edge, ``Wall Height Above Grade`` (0.2 m) of it exposed to the outdoor air, and the
soil reaches 40 m beyond the wall and 40 m down; the results per metre of section times ``P``
give the floor's heat flow. This module builds that section as a grid of cells
(:func:`foundation_grid`) and reduces it by balanced truncation (:func:`reduced_section`) to a
few states that the multi-zone network (:func:`thermocal.multizone.network.assemble`) adds as
linear nodes: the floor's own construction stays the one-dimensional chain of every surface and
its outside node lies on the soil under the slab; the slab's edge touches the foundation wall.

The section, ``x`` from the slab's centre, ``z`` up from the grade:

* the floor's construction occupies ``0 <= x <= A/P`` between the top of the wall ``h`` and
  ``h - t_floor``; soil below it (the fill inside the wall included);
* the foundation wall (the ``Footing Wall Construction``, inside layer first) occupies
  ``A/P <= x <= A/P + t_wall`` from ``h`` down to ``Wall Depth Below Slab`` under the floor;
* outside the wall the soil's surface is the grade at ``z = 0``, exposed to the sky, the outdoor
  air and the sun (absorptance 0.9, Kiva's default); the wall's outside face above the grade
  to the outdoor air, 0.354 of its long-wave to the sky (Kiva's ``F_sky cos(tilt / 2)``) and
  Kiva's two-dimensional sun (the beam on a vertical cylinder, half the sky's diffuse and
  half the grade's reflection, times the wall construction's outside absorptance);
* zero heat flow across the symmetry plane, the far field and the deep-ground boundary (Kiva's
  ``Autoselect`` for a water table deeper than 40 m).

The section's matrix holds the grade's and the wall's convection at one coefficient (DOE-2 at the
period's mean wind, :func:`grade_convection`) and their long-wave linearised at 10 C; the time
loop corrects both each step as Kiva evaluates them (DOE-2 with TARP's natural part at the
face's own difference from the air, the forced term at the step's wind at the grade's roughness
height, the exact ``sigma T^4``), lagged by a step: the faces' mean temperatures are outputs of
the section and the corrections enter as heat fluxes spread over their cells as their sun
(:class:`thermocal.multizone.network.GroundFaces`; one mean temperature for the whole grade,
Kiva takes each cell's).

What the section leaves out (stated in the import's notes): a floor with
insulation added under it keeps its one-dimensional chain (Kiva meshes the slab in the section,
so the slab's edge meets the wall across its whole thickness; here the chain's node above any
insulation touches the wall's cells beside the slab).

References
----------
.. [1] Kruis, N. and Krarti, M. (2017), "Three-dimensional accuracy of two-dimensional
   approximations of foundation heat transfer", Journal of Building Performance Simulation
   10(3).
.. [2] Moore, B.C. (1981), "Principal component analysis in linear systems"; Fernando, K.V.
   and Nicholson, H. (1982), "Singular perturbational model reduction of balanced systems"
   (as :mod:`thermocal.multizone.conduction_reduction`).
.. [3] EnergyPlus 25.2 Input Output Reference, ``Foundation:Kiva``, ``Foundation:Kiva:Settings``
   and ``SurfaceProperty:ExposedFoundationPerimeter``; the settings' defaults when the file has
   none are those of ``KivaManager::Settings`` (soil 0.864 W/(m K), 1510 kg/m3, 1260 J/(kg K)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermocal.errors import ThermocalInputError

__all__ = [
    "KIVA_DEFAULT_ROUGHNESS",
    "KIVA_DEFAULT_SOIL",
    "FoundationGround",
    "FoundationGrid",
    "ReducedSection",
    "foundation_grid",
    "grade_convection",
    "grade_wind_factor",
    "reduced_section",
    "steady_floor_conductance",
]

#: EnergyPlus's Kiva soil when the file has no ``Foundation:Kiva:Settings`` or leaves a field
#: blank: conductivity [W/(m K)], density [kg/m3], specific heat [J/(kg K)]
#: (``KivaManager::Settings``; the Input Output Reference documents 1.73, 1842 and 419, which an
#: object with blank fields does not give: checked with EnergyPlus 25.2).
KIVA_DEFAULT_SOIL = (0.864, 1510.0, 1260.0)
#: Kiva's grade roughness height without a ``Foundation:Kiva:Settings`` [m]
#: (``KivaManager::Settings``; the Input Output Reference documents 0.03 m).
KIVA_DEFAULT_ROUGHNESS = 0.9


def grade_wind_factor(roughness: float = KIVA_DEFAULT_ROUGHNESS) -> float:
    """Kiva's wind at the grade per m/s at the weather station [-]: EnergyPlus's weather-file
    modifier ``(270 / 10)^0.14`` times the default (suburbs) boundary layer at the grade's
    roughness height [m], ``(roughness / 370)^0.22``."""
    return (270.0 / 10.0) ** 0.14 * (float(roughness) / 370.0) ** 0.22
#: The grade's long-wave emissivity and solar absorptance [-] (Kiva's defaults).
GRADE_EMISSIVITY, GRADE_ABSORPTANCE = 0.9, 0.9
#: The foundation wall's outside solar absorptance and emissivity [-] without a construction:
#: Kiva's default footing wall's (``KivaManager::defineDefaultFoundation``); a footing wall
#: construction (a basement: its walls' construction) gives its outside layer's.
WALL_ABSORPTANCE, WALL_EMISSIVITY = 0.9, 0.9
#: The long-wave share of a vertical face above the grade that sees the sky [-]: Kiva's
#: ``getEffectiveExteriorViewFactor``, ``F_sky cos(tilt / 2)`` = 0.5 cos(45 deg), the rest the
#: outdoor air (``getExteriorIRCoeff``: ``F = F_sky cos(tilt/2) (e_sky - 1) + 1`` on ``T_air^4``).
WALL_SKY_SHARE = 0.5 * 0.5**0.5
#: ``Foundation:Kiva``'s insulation blocks, in the order of its fields.
INSULATION_KINDS = (
    "interior_horizontal",
    "interior_vertical",
    "exterior_horizontal",
    "exterior_vertical",
)
#: Largest cell of the section [m] (the far field and the deep ground).
MAX_CELL = 10.0
#: The floor's inside surface resistance, heat flow down [m2 K/W] (ISO 6946), for the fin.
FLOOR_INSIDE_RESISTANCE = 0.17


#: Temperature at which the section's long-wave exchange is linearised [K] (the time loop
#: corrects the rest with the exact ``sigma T^4``).
LONGWAVE_LINEARISATION = 283.15


def grade_longwave_coefficient(emissivity: float = GRADE_EMISSIVITY) -> float:
    """The grade's (and a foundation wall's) long-wave coefficient, linearised at 10 C
    (:data:`LONGWAVE_LINEARISATION`).

    Parameters
    ----------
    emissivity : float [-]
        The surface's long-wave emissivity.

    Returns
    -------
    float [W/(m2 K)]
    """
    return 4.0 * 5.670374419e-8 * float(emissivity) * LONGWAVE_LINEARISATION**3


def grade_convection(
    mean_wind_speed: float,
    roughness: float = KIVA_DEFAULT_ROUGHNESS,
    roughness_factor: float = 1.52,
) -> float:
    """Convection coefficient of the grade and of a foundation wall above it [W/(m2 K)].

    Kiva takes the floor's outside algorithm (EnergyPlus's default DOE-2) at the wind at the
    grade (:func:`grade_wind_factor`) each step; here it is taken once at the period's mean
    wind, with TARP's natural part at a grade 3 K warmer than the air and a medium-rough
    surface.

    Parameters
    ----------
    mean_wind_speed : float [m/s]
        The weather station's mean wind speed.
    roughness : float [m]
        The grade's roughness height (``Foundation:Kiva:Settings``).
    roughness_factor : float [-]
        DOE-2's roughness multiplier: Kiva passes the floor surface's (its construction's
        outside layer, ``CalcDOE2Forced``): 1.52 medium rough, 1.11 smooth.
    """
    from thermocal.multizone.network import doe2_exterior_convection, tarp_natural_convection

    h_natural = tarp_natural_convection(3.0, 1.0)
    wind = grade_wind_factor(roughness) * max(float(mean_wind_speed), 0.0)
    return float(
        doe2_exterior_convection(
            wind, True, h_natural=h_natural, roughness_factor=float(roughness_factor)
        )
    )


@dataclass(frozen=True)
class FoundationGround:
    """The ground section under one floor on a ``Foundation`` boundary.

    Attributes
    ----------
    exposed_perimeter : float [m]
        Perimeter of the floor next to the outside (``SurfaceProperty:ExposedFoundationPerimeter``).
    soil : tuple of float
        Conductivity [W/(m K)], density [kg/m3] and specific heat [J/(kg K)] of the soil.
    wall_layers : tuple of (thickness [m], conductivity [W/(m K)], density [kg/m3],
        specific heat [J/(kg K)])
        The foundation wall from the inside to the outside; empty: no wall (soil at the slab's
        edge).
    wall_height_above_grade : float [m]
        Top of the wall (and of the floor) above the grade.
    wall_depth_below_slab : float [m]
        Bottom of the wall below the floor's construction.
    deep_ground_depth, far_field_width : float [m]
        Depth of the zero-flux bottom below the grade and width of the soil beyond the wall.
    basement_depth : float [m]
        Depth of the floor's top below the top of the wall (Kiva's foundation depth: the
        height of the walls on the same foundation; 0 for a slab).
    walls : tuple of (str, float)
        A basement's walls on the same foundation (surface name, share of the exposed
        perimeter [-]): their own constructions are their one-dimensional chains, whose outside
        nodes meet the soil beside them below the grade and the outdoor air above it.
    grade_roughness : float [m]
        The grade's roughness height, which sets the wind at the grade
        (:func:`grade_convection`).
    insulation : tuple of (kind, thickness [m], conductivity [W/(m K)], density [kg/m3],
        specific heat [J/(kg K)], depth [m], width [m])
        ``Foundation:Kiva``'s insulation: ``interior_horizontal`` (under the slab, ``depth``
        below the slab's bottom, ``width`` from the wall inwards), ``interior_vertical`` (on
        the wall's inside face, from its top down to ``depth``), ``exterior_horizontal``
        (``depth`` below the grade, ``width`` from the wall outwards), ``exterior_vertical``
        (on the wall's outside face, from its top down to ``depth``).
    grade_roughness_factor : float [-]
        DOE-2's roughness multiplier of the grade's forced convection: Kiva's is the floor's
        outside layer's (1.52 medium rough, 1.11 smooth).
    wall_absorptance, wall_emissivity : float [-]
        The foundation wall's outside solar absorptance and long-wave emissivity above the
        grade (Kiva: the wall construction's outside layer's; its default wall's 0.9).
    """

    exposed_perimeter: float
    soil: tuple[float, float, float] = KIVA_DEFAULT_SOIL
    wall_layers: tuple[tuple[float, float, float, float], ...] = ()
    wall_height_above_grade: float = 0.2
    wall_depth_below_slab: float = 0.0
    deep_ground_depth: float = 40.0
    far_field_width: float = 40.0
    basement_depth: float = 0.0
    walls: tuple[tuple[str, float], ...] = ()
    grade_roughness: float = KIVA_DEFAULT_ROUGHNESS
    grade_roughness_factor: float = 1.52
    insulation: tuple[tuple, ...] = ()
    wall_absorptance: float = WALL_ABSORPTANCE
    wall_emissivity: float = WALL_EMISSIVITY

    def __post_init__(self) -> None:
        # tuples, so that a section can be cached by its ground (lists from Python or YAML)
        object.__setattr__(self, "soil", tuple(float(v) for v in self.soil))
        object.__setattr__(
            self, "wall_layers", tuple(tuple(float(v) for v in w) for w in self.wall_layers)
        )
        object.__setattr__(self, "walls", tuple((str(w[0]), float(w[1])) for w in self.walls))
        object.__setattr__(
            self,
            "insulation",
            tuple((str(b[0]), *(float(v) for v in b[1:])) for b in self.insulation),
        )
        for block in self.insulation:
            if block[0] not in INSULATION_KINDS or len(block) != 7 or min(block[1:5]) <= 0:
                raise ThermocalInputError(
                    f"foundation: insulation is (kind in {', '.join(INSULATION_KINDS)}, "
                    "thickness [m], conductivity, density, specific heat > 0, depth [m], width "
                    f"[m]), got {block!r}"
                )
        checks = {
            "exposed_perimeter [m]": self.exposed_perimeter,
            "soil conductivity [W/(m K)]": self.soil[0],
            "soil density [kg/m3]": self.soil[1],
            "soil specific heat [J/(kg K)]": self.soil[2],
            "deep_ground_depth [m]": self.deep_ground_depth,
            "far_field_width [m]": self.far_field_width,
            "grade_roughness [m]": self.grade_roughness,
            "grade_roughness_factor [-]": self.grade_roughness_factor,
        }
        for name, value in checks.items():
            if not np.isfinite(value) or value <= 0:
                raise ThermocalInputError(f"foundation: {name} must be > 0, got {value!r}")
        if not (0.0 <= self.wall_absorptance <= 1.0 and 0.0 <= self.wall_emissivity <= 1.0):
            raise ThermocalInputError(
                "foundation: wall_absorptance and wall_emissivity must be in [0, 1], got "
                f"{self.wall_absorptance!r}, {self.wall_emissivity!r}"
            )
        if min(self.wall_height_above_grade, self.wall_depth_below_slab, self.basement_depth) < 0:
            raise ThermocalInputError(
                "foundation: wall_height_above_grade, wall_depth_below_slab and basement_depth "
                "[m] must be >= 0"
            )
        if self.basement_depth > 0 and not self.walls:
            raise ThermocalInputError(
                "foundation: a basement (basement_depth > 0) needs its walls (surface name, share "
                "of the exposed perimeter)"
            )
        for wall in self.walls:
            if len(wall) != 2 or not 0 < float(wall[1]) <= 1.0:
                raise ThermocalInputError(
                    f"foundation: a wall is (surface name, share of the perimeter in (0, 1]), "
                    f"got {wall!r}"
                )
        for layer in self.wall_layers:
            if len(layer) != 4 or min(layer) <= 0:
                raise ThermocalInputError(
                    f"foundation: a wall layer needs thickness [m], conductivity [W/(m K)], "
                    f"density [kg/m3] and specific heat [J/(kg K)] > 0, got {layer!r}"
                )

    @property
    def wall_thickness(self) -> float:
        """Thickness of the foundation wall [m]."""
        return float(sum(layer[0] for layer in self.wall_layers))


@dataclass(frozen=True)
class FoundationGrid:
    """The section's cells as network nodes (every value already times the exposed perimeter).

    The last node is the slab's edge: the band of the floor's slab within a fin length of the
    wall (``sqrt(k t / h)``, with ``k t`` the slab's in-plane conductance and ``h`` its
    exchange with the room and through any insulation below it), linked to the slab's node of
    the floor's chain by the fin's conductance and to the wall's cells beside the floor.

    Attributes
    ----------
    capacity : ndarray (n,) [J/K]
    links : ndarray (m, 3)
        Node ``i``, node ``j`` (as floats) and their conductance [W/K].
    under_floor : ndarray (k, 2)
        Cell and its conductance [W/K] to the floor's outside node (the top of the soil under
        the slab, half a cell's resistance).
    edge_node : int
        Index of the slab's edge node.
    fin_conductance : float [W/K]
        Between the slab's node of the floor's chain and the edge node.
    slab_interface : int
        Layer interface of the floor's chain that is the slab's node: the number of its outside
        layers below 0.1 W/(m K) (0: the outside node).
    outdoor : ndarray (g, 3)
        Cell, its exposed area [m2] and whether it is the grade (1.0, sees the sky and the sun)
        or the wall's face above it (0.0).
    wall_face : ndarray (w, 2)
        A basement's soil cells beside its walls' outside faces, below the grade, and their
        conductance [W/K] to those faces (empty for a slab).
    wall_above_grade : float [m2]
        A basement's walls' outside area above the grade (0 for a slab).
    wall_emissivity : float [-]
        The wall's outside long-wave emissivity above the grade.
    """

    capacity: np.ndarray
    links: np.ndarray
    under_floor: np.ndarray
    edge_node: int
    fin_conductance: float
    slab_interface: int
    outdoor: np.ndarray
    wall_face: np.ndarray
    wall_above_grade: float
    wall_emissivity: float = WALL_EMISSIVITY


def _edges(start: float, end: float, fine: list[float], first: float, growth: float) -> np.ndarray:
    """Cell edges from ``start`` to ``end`` [m]: ``first``-sized cells at each point of
    ``fine``, growing geometrically by ``growth`` away from them (at most ``MAX_CELL``)."""
    points = sorted({start, end, *[p for p in fine if start < p < end]})
    edges = [start]
    for a, b in zip(points[:-1], points[1:], strict=True):
        # grow from both ends of [a, b] towards its middle
        left, right, size = [a], [b], first
        while left[-1] + size < right[-1] - size:
            left.append(left[-1] + size)
            right.append(right[-1] - size)
            size = min(size * growth, MAX_CELL)
        segment = left + right[::-1]
        edges.extend(segment[1:])
    out = np.unique(np.round(np.asarray(edges), 9))
    return out


def foundation_grid(
    ground: FoundationGround,
    floor_area: float,
    floor_layers,
    *,
    first_cell: float = 0.1,
    growth: float = 2.5,
) -> FoundationGrid:
    """Cells of the two-dimensional section under a floor (see the module's description).

    Parameters
    ----------
    ground : FoundationGround
    floor_area : float [m2]
        Area of the floor.
    floor_layers : sequence of (thickness [m], conductivity [W/(m K)], density [kg/m3],
        specific heat [J/(kg K)])
        The floor's construction from the outside (the soil's side) to the inside: its chain
        lies above the section's soil, and its layers above any insulation (layers below 0.1
        W/(m K) at its outside) form the slab whose edge meets the wall.
    first_cell : float [m]
        Cell size at the slab's edge, the wall's faces and the grade.
    growth : float [-]
        Growth factor of the cells away from those.

    Returns
    -------
    FoundationGrid
    """
    p = float(ground.exposed_perimeter)
    half = float(floor_area) / p  # the section's slab half-width A / P [m]
    t_wall = ground.wall_thickness
    h = float(ground.wall_height_above_grade)
    floor_thickness = sum(layer[0] for layer in floor_layers)
    basement = float(ground.basement_depth) > 0.0
    slab_top = h - float(ground.basement_depth)
    slab_bottom = slab_top - float(floor_thickness)
    wall_bottom = slab_bottom - float(ground.wall_depth_below_slab)
    x_far = half + t_wall + float(ground.far_field_width)
    z_deep = -float(ground.deep_ground_depth)
    wall_faces = [half, half + t_wall]
    blocks = _insulation_rectangles(ground.insulation, half, t_wall, h, slab_bottom)
    x_fine = [*wall_faces, *(b[0] for b in blocks), *(b[1] for b in blocks)]
    acc = half
    for layer in ground.wall_layers:
        acc += layer[0]
        x_fine.append(acc)
    xe = _edges(0.0, x_far, x_fine, first_cell, growth)
    ze = _edges(
        z_deep,
        max(h, 0.0),
        [0.0, slab_top, slab_bottom, wall_bottom, h, *(b[2] for b in blocks)]
        + [b[3] for b in blocks],
        first_cell,
        growth,
    )
    xc, zc = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ze[1:] + ze[:-1])
    dx, dz = np.diff(xe), np.diff(ze)
    soil_k, soil_rho, soil_cp = ground.soil
    # material of each cell: conductivity, volumetric capacity; 0 = not part of the section
    k = np.zeros((len(xc), len(zc)))
    rc = np.zeros_like(k)
    layer_edges = half + np.cumsum([0.0] + [layer[0] for layer in ground.wall_layers])
    for i, x in enumerate(xc):
        for j, z in enumerate(zc):
            if x < half:
                inside = z < slab_bottom
                material = (soil_k, soil_rho * soil_cp) if inside else None
            elif x < half + t_wall:
                if z < wall_bottom:
                    material = (soil_k, soil_rho * soil_cp)
                elif z < (slab_top if basement else h):  # a basement's wall above: its chain
                    n = int(np.searchsorted(layer_edges, x, side="right")) - 1
                    layer = ground.wall_layers[min(n, len(ground.wall_layers) - 1)]
                    material = (layer[1], layer[2] * layer[3])
                else:
                    material = None
            else:
                material = (soil_k, soil_rho * soil_cp) if z < 0.0 else None
            for x0, x1, z0, z1, lam, vol in blocks:
                inside_block = x0 <= x < x1 and z0 <= z < z1
                # a block replaces soil or wall; outside the wall above the grade it stands in
                # the air (exterior vertical insulation up to the wall's top)
                outside = x > half + t_wall and 0.0 <= z < h
                if inside_block and (material is not None or outside):
                    material = (lam, vol)
            if material is not None:
                k[i, j], rc[i, j] = material
    active = k > 0
    index = -np.ones(k.shape, dtype=np.int64)
    index[active] = np.arange(int(active.sum()))
    capacity = (rc * dx[:, None] * dz[None, :] * p)[active]
    links = []
    for i in range(len(xc) - 1):  # horizontal neighbours
        for j in range(len(zc)):
            if active[i, j] and active[i + 1, j]:
                r = 0.5 * dx[i] / k[i, j] + 0.5 * dx[i + 1] / k[i + 1, j]
                links.append((index[i, j], index[i + 1, j], dz[j] * p / r))
    for i in range(len(xc)):  # vertical neighbours
        for j in range(len(zc) - 1):
            if active[i, j] and active[i, j + 1]:
                r = 0.5 * dz[j] / k[i, j] + 0.5 * dz[j + 1] / k[i, j + 1]
                links.append((index[i, j], index[i, j + 1], dx[i] * p / r))
    under, edge, outdoor, wall_face = [], [], [], []
    for i in range(len(xc)):
        for j in range(len(zc)):
            if not active[i, j]:
                continue
            top_open = not (j + 1 < len(zc) and active[i, j + 1])
            if xc[i] < half and top_open:  # the top of the soil under the floor
                under.append((index[i, j], dx[i] * p / (0.5 * dz[j] / k[i, j])))
            elif top_open and xc[i] > half + t_wall:  # the grade
                outdoor.append((index[i, j], dx[i] * p, 1.0))
            if half <= xc[i] < half + t_wall and i > 0 and not active[i - 1, j]:
                # the wall's inside face beside the floor: the slab's edge
                edge.append((index[i, j], dz[j] * p / (0.5 * dx[i] / k[i, j])))
            if i + 1 < len(xc) and not active[i + 1, j] and zc[j] > 0.0:
                outdoor.append((index[i, j], dz[j] * p, 0.0))  # the wall's face above the grade
            if basement and xc[i] > half + t_wall and i > 0 and not active[i - 1, j]:
                # the soil beside a basement wall's outside face (its chain)
                wall_face.append((index[i, j], dz[j] * p / (0.5 * dx[i] / k[i, j])))
    if not under:
        raise ThermocalInputError("foundation: the section has no soil under the floor")
    # the slab's edge band (a fin of the slab's layers above any insulation)
    insulated = _insulated_layers([(layer[0], layer[1]) for layer in floor_layers])
    if insulated >= len(floor_layers):  # no layer but insulation: the whole floor is the slab
        insulated = 0
    slab = floor_layers[insulated:]
    kt = sum(layer[0] * layer[1] for layer in slab)
    r_up = FLOOR_INSIDE_RESISTANCE + 0.5 * sum(layer[0] / layer[1] for layer in slab)
    r_down = sum(layer[0] / layer[1] for layer in floor_layers[:insulated])
    h_fin = 1.0 / r_up + (1.0 / r_down if r_down > 0 else 0.0)
    fin_length = float(np.sqrt(kt / h_fin)) if kt > 0 else 0.0
    n_cells = int(active.sum())
    edge_node = n_cells
    capacity = np.append(
        capacity, fin_length * p * sum(layer[0] * layer[2] * layer[3] for layer in slab)
    )
    links.extend((edge_node, c, g) for c, g in edge)
    return FoundationGrid(
        capacity=np.asarray(capacity, float),
        links=np.asarray(links, float).reshape(-1, 3),
        under_floor=np.asarray(under, float).reshape(-1, 2),
        edge_node=edge_node,
        fin_conductance=float(np.sqrt(kt * h_fin)) * p if kt > 0 else 0.0,
        slab_interface=insulated,
        outdoor=np.asarray(outdoor, float).reshape(-1, 3),
        wall_face=np.asarray(wall_face, float).reshape(-1, 2),
        wall_above_grade=max(h, 0.0) * p if basement else 0.0,
        wall_emissivity=float(ground.wall_emissivity),
    )


@dataclass(frozen=True)
class ReducedSection:
    """A ground section reduced by balanced truncation with singular perturbation.

    The section's cells obey ``C dT/dt = -A T + H v``, ``v`` the ports of :data:`PORTS` (the
    floor's outside node, the slab's node, a basement's walls, the outdoor air, the sky, the
    horizontal irradiance) and ``H`` their couplings; the node ports receive
    ``H[:, :3]^T T - diag(sum H[:, :3]) v[:3]``. In ``x = C^1/2 T`` the system is
    symmetric (its port flows are the transpose of its inputs), so its two Gramians are equal
    and balancing is the eigenbasis of one (Moore 1981; Liu, Sreeram and Teo 1998); the weakest
    balanced states follow the others quasi-statically (Fernando and Nicholson 1982), which keeps
    every steady state exact; the kept ones are rotated onto the eigenvectors of their block:
    ``dq/dt = -rates q + coupling v``, the ports seeing ``coupling^T q + feedthrough v``.
    Symmetric, so it enters the network as nodes of unit capacity.

    Attributes
    ----------
    rates : ndarray (m,) [1/s]
    coupling : ndarray (m, 6)
        Per port of :data:`PORTS` [W/K per unit of q; the irradiance's column in m2].
    feedthrough : ndarray (6, 6) [W/K; m2]
        The quasi-static states' direct coupling of the ports.
    node_conductance : ndarray (3,) [W/K]
        ``sum H[:, :3]``: the node ports' (floor, slab, walls) own coupling to the section.
    """

    rates: np.ndarray
    coupling: np.ndarray
    feedthrough: np.ndarray
    node_conductance: np.ndarray


#: The irradiance's column is divided by ``1 / SUN_WEIGHT`` in the Gramian that ranks the states,
#: so that the temperatures rank them (a unit of the weighted column is 0.02 W/m2): measured on
#: NREL's SingleFamilyHouse, the floor's response at a one-day period is then within 11 % for
#: the air and 76 % for the sun (32 % and 64 % with the column weighted the other way,
#: 50 W/m2 a unit), annual periods within 1 % either way; the slab's sun is a small input.
SUN_WEIGHT = 1.0 / 50.0


#: Columns of a section's couplings ``H``: the floor's outside node, the slab's node and a
#: basement's walls (nodes), the outdoor air and the sky (temperatures), and two heat fluxes
#: [W/m2] on the grade and on the wall's face above it (their cells' exposed areas [m2]): the
#: absorbed sun, and the time loop's lagged correction of the convection and long-wave.
PORTS = ("floor", "slab", "walls", "outdoor", "sky", "grade", "wall_face")
#: The flux ports' columns in :data:`PORTS`.
GRADE_PORT, WALL_FACE_PORT = 5, 6


def _insulation_rectangles(insulation, half, t_wall, h, slab_bottom) -> list[tuple]:
    """``(x0, x1, z0, z1, conductivity, volumetric capacity)`` of each insulation block in the
    section's coordinates [m; W/(m K); J/(m3 K)] (see :class:`FoundationGround`)."""
    out = []
    for kind, thickness, lam, rho, cp, depth, width in insulation:
        if kind == "interior_horizontal":
            top = slab_bottom - depth
            box = (max(half - width, 0.0), half, top - thickness, top)
        elif kind == "interior_vertical":
            box = (half - thickness, half, h - depth, h)
        elif kind == "exterior_horizontal":
            box = (half + t_wall, half + t_wall + width, -depth - thickness, -depth)
        else:  # exterior_vertical
            box = (half + t_wall, half + t_wall + thickness, h - depth, h)
        out.append((*box, lam, rho * cp))
    return out


def section_matrices(
    grid: FoundationGrid, grade_h: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The section's ``A`` (n, n) [W/K], ``C`` (n,) [J/K] and couplings ``H`` (n, 6) in the
    order of :data:`PORTS` ([W/K]; the irradiance's column [m2]); ``grade_h`` the grade's
    convection coefficient [W/(m2 K)] (:func:`grade_convection`)."""
    n = len(grid.capacity)
    a = np.zeros((n, n))
    i, j, g = grid.links[:, 0].astype(int), grid.links[:, 1].astype(int), grid.links[:, 2]
    np.add.at(a, (i, j), -g)
    np.add.at(a, (j, i), -g)
    np.add.at(a, (i, i), g)
    np.add.at(a, (j, j), g)
    h = np.zeros((n, len(PORTS)))
    np.add.at(h[:, 0], grid.under_floor[:, 0].astype(int), grid.under_floor[:, 1])
    h[grid.edge_node, 1] = grid.fin_conductance
    if len(grid.wall_face):
        np.add.at(h[:, 2], grid.wall_face[:, 0].astype(int), grid.wall_face[:, 1])
    hr = grade_longwave_coefficient()
    hr_wall = grade_longwave_coefficient(grid.wall_emissivity)
    for c, area, is_grade in grid.outdoor:
        c = int(c)
        if is_grade:
            h[c, 3] += grade_h * area
            h[c, 4] += hr * area
            h[c, GRADE_PORT] += area
        else:  # the wall's face above the grade: Kiva's sky share (WALL_SKY_SHARE)
            h[c, 3] += (grade_h + (1.0 - WALL_SKY_SHARE) * hr_wall) * area
            h[c, 4] += WALL_SKY_SHARE * hr_wall * area
            h[c, WALL_FACE_PORT] += area
    a[np.diag_indices(n)] += h[:, :5].sum(axis=1)
    return a, np.asarray(grid.capacity, float), h


def reduced_section(grid: FoundationGrid, n_states: int, grade_h: float) -> ReducedSection:
    """The section reduced to ``n_states`` balanced states (:class:`ReducedSection`).

    Parameters
    ----------
    grid : FoundationGrid
    n_states : int
        States kept (fewer than the section's nodes).
    grade_h : float [W/(m2 K)]
        The grade's convection coefficient (:func:`grade_convection`).
    """
    import scipy.linalg

    a, c, h = section_matrices(grid, grade_h)
    m = int(min(n_states, len(c) - 1))
    scale = 1.0 / np.sqrt(c)
    a_x = -(a * scale[:, None] * scale[None, :])  # dx/dt = a_x x + b_x v
    b_x = h * scale[:, None]
    weights = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0 / SUN_WEIGHT, 1.0 / SUN_WEIGHT])
    b_w = b_x / weights[None, :]
    gramian = scipy.linalg.solve_continuous_lyapunov(a_x, -b_w @ b_w.T)
    _, v = np.linalg.eigh(0.5 * (gramian + gramian.T))
    v = v[:, ::-1]  # largest Hankel singular value first
    a_t, b_t = v.T @ a_x @ v, v.T @ b_x
    a11, a12, a22 = a_t[:m, :m], a_t[:m, m:], a_t[m:, m:]
    b1, b2 = b_t[:m], b_t[m:]
    a_r = a11 - a12 @ np.linalg.solve(a22, a12.T)
    b_r = b1 - a12 @ np.linalg.solve(a22, b2)
    feedthrough = -b2.T @ np.linalg.solve(a22, b2)
    rates, w = np.linalg.eigh(-0.5 * (a_r + a_r.T))
    return ReducedSection(
        rates=rates,
        coupling=w.T @ b_r,
        feedthrough=0.5 * (feedthrough + feedthrough.T),
        node_conductance=h[:, :3].sum(axis=0),
    )


def steady_floor_conductance(
    ground: FoundationGround,
    floor_area: float,
    floor_layers,
    inside_resistance: float = FLOOR_INSIDE_RESISTANCE,
    *,
    wind_speed: float = 3.0,
    **grid_options,
) -> float:
    """Steady heat flow [W/K] from the room's air through a slab's floor and the section to
    the outdoor air, per kelvin of their difference (the sky at the air's temperature, no sun).

    Parameters
    ----------
    ground : FoundationGround
        A slab's (no basement walls).
    floor_area : float [m2]
    floor_layers : sequence of (thickness [m], conductivity [W/(m K)], density [kg/m3],
        specific heat [J/(kg K)])
        The floor's construction from the outside (the soil's side) to the inside.
    inside_resistance : float [m2 K/W]
        The floor's inside surface resistance (ISO 6946, heat flow down: 0.17).
    wind_speed : float [m/s]
        The weather station's wind (:func:`grade_convection`).
    **grid_options
        Passed to :func:`foundation_grid`.
    """
    import scipy.linalg

    grid = foundation_grid(ground, floor_area, floor_layers, **grid_options)
    h_grade = grade_convection(wind_speed, ground.grade_roughness, ground.grade_roughness_factor)
    a, _, h = section_matrices(grid, h_grade)
    n = len(a)
    r_below = sum(layer[0] / layer[1] for layer in floor_layers[: grid.slab_interface])
    r_above = sum(layer[0] / layer[1] for layer in floor_layers[grid.slab_interface :])
    # nodes: the section's, the floor's outside node, its slab node; the room at 1 K, the
    # outdoor air and the sky at 0
    full = np.zeros((n + 2, n + 2))
    full[:n, :n] = a
    for k, node in ((0, n), (1, n + 1)):
        full[:n, node] -= h[:, k]
        full[node, :n] -= h[:, k]
        full[node, node] += h[:, k].sum()
    g_below = floor_area / r_below if r_below > 0 else 1e9
    g_room = floor_area / (r_above + inside_resistance)
    full[n, n] += g_below
    full[n + 1, n + 1] += g_below + g_room
    full[n, n + 1] -= g_below
    full[n + 1, n] -= g_below
    rhs = np.zeros(n + 2)
    rhs[n + 1] = g_room
    t = scipy.linalg.solve(full, rhs, assume_a="sym")
    return float(g_room * (1.0 - t[n + 1]))


def _insulated_layers(floor_layers) -> int:
    """Number of the floor's outermost layers below 0.1 W/(m K) (insulation under the slab)."""
    count = 0
    for _, conductivity in floor_layers:
        if conductivity >= 0.1:
            break
        count += 1
    return count
