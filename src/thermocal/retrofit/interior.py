"""The room's inside: convection to the air and long-wave exchange among the surfaces.

The published fifth-order model couples each element's inner surface to the indoor air ``Ti``
through the combined surface resistance ``Rsi`` (ISO 6946): convection and radiation both to
the air, as if the air were at the room's operative temperature. A room heated by convectors
or ideal air heating and controlled on its air temperature is not like that: the heat reaches
the surfaces only by convection, and the cold surfaces (windows, outer walls) receive their
radiation from the warm ones (partitions, furniture, floors), which the air warms in turn. The
air-referenced loss of a cold element is then smaller than ``U A`` (ISO 13790:2008, 12.2.2 and
ISO 52016-1:2017, 6.5.6: the air node and the surface "star" node joined by ``h_is A_t``).

``model.interior: split`` models that inside. Each element's inner surface is a massless node
joined to the air by its convective coefficient ``h_c A`` and to a radiant star node by
``h_r A`` with ``h_r = 1/Rsi - h_c`` (so an element in an isothermal room still carries exactly
``U A``); the internal mass's surface is its node ``Tim`` (convection to the air, radiation to
the star). The windows, the roof + walls and the floor have one surface each, joined to their
mass node (or to ``Te`` for the massless windows) by the construction without ``Rsi``. The
massless nodes are eliminated (Kron reduction, the star-delta transformation of the model's
cellar node generalised), which leaves a network among ``Ti, Tenv, Tgf, Tim, Te`` with the same
five states: :data:`PAIRS`, each conductance named ``G_<node>_<node>``.

References
----------
ISO 6946:2017, Table 7 and Annex C (surface resistances; convective and radiative parts).
ISO 52016-1:2017, 6.5.6 and Table 25 (convective coefficients by heat-flow direction).
ISO 13790:2008, 12.2.2 (the air and star nodes, ``H_tr,is = h_is A_t``).
Seem J.E. (1987), Modeling of heat transfer in buildings, PhD thesis, University of Wisconsin
(star network for long-wave exchange among room surfaces).
Kron G. (1939), Tensor analysis of networks, Wiley (elimination of internal nodes).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: The nodes the reduced inside connects, in this order.
NODES: tuple[str, ...] = ("Ti", "Tenv", "Tgf", "Tim", "Te")
#: Every pair of :data:`NODES`, in the order of the conductances ``G_<a>_<b>``.
PAIRS: tuple[tuple[str, str], ...] = tuple(
    (a, b) for i, a in enumerate(NODES) for b in NODES[i + 1 :]
)
#: Names of the pair conductances [W/K].
PAIR_NAMES: tuple[str, ...] = tuple(f"G_{a}_{b}" for a, b in PAIRS)
#: The interior forms of ``model.interior``.
INTERIOR_FORMS: tuple[str, ...] = ("combined", "split")


@dataclass(frozen=True)
class InteriorSurface:
    """One component's inner surface: to the air by convection, to the star by radiation, to
    its node through the construction without ``Rsi`` (all [W/K]).

    Attributes
    ----------
    node : {"Tenv", "Te", "Tgf"}
        The mass node of its element (``Te`` for the massless windows).
    convection, radiation, conduction : float [W/K]
    """

    node: str
    convection: float
    radiation: float
    conduction: float


@dataclass(frozen=True)
class ReducedInterior:
    """The inside after eliminating its massless nodes.

    Attributes
    ----------
    pairs : dict name -> float [W/K]
        ``G_<a>_<b>`` between the nodes of :data:`NODES` (0 when not connected).
    surface_weights : ndarray (n_surfaces, 5) [-]
        Temperature of each given surface as a weighted sum of the temperatures of
        :data:`NODES` (rows sum to 1).
    surfaces : tuple of InteriorSurface
        The surfaces, in the order of ``surface_weights``; the inside-face heat flow of one
        is ``conduction * (T_surface - T_node)``.
    """

    pairs: dict
    surface_weights: np.ndarray
    surfaces: tuple

    def inside_face_flows(self, temperatures: dict) -> dict:
        """Heat [W] conducted from the inner surfaces into each node (``Tenv``, ``Te``,
        ``Tgf``) at the given node temperatures [C] (floats or arrays of equal shape)."""
        t = np.stack([np.asarray(temperatures[n], dtype=float) for n in NODES])
        out = {"Tenv": 0.0, "Te": 0.0, "Tgf": 0.0}
        for s, w in zip(self.surfaces, self.surface_weights, strict=True):
            surface = np.tensordot(w, t, axes=1)
            out[s.node] = out[s.node] + s.conduction * (surface - t[NODES.index(s.node)])
        return out


def _link(g: np.ndarray, a: int, b: int, value: float) -> None:
    """Add a conductance [W/K] between nodes ``a`` and ``b`` to the conductance matrix ``g``."""
    g[a, b] -= value
    g[b, a] -= value
    g[a, a] += value
    g[b, b] += value


def inner_conduction(combined: float, area: float, r_si: float) -> float:
    """The construction part [W/K] of an inner conductance ``A/Rsi (+) K``.

    Parameters
    ----------
    combined : float [W/K]
        Conductance from the air to the node, surface resistance included.
    area : float [m2]
    r_si : float [m2 K/W]
        Internal surface resistance inside ``combined``.

    Returns
    -------
    float [W/K]
        ``K = 1 / (1/combined - Rsi/A)``; very large (1e3 A/Rsi) when the construction part
        is negligible.
    """
    film = area / r_si
    if combined <= 0 or area <= 0:
        return 0.0
    rest = 1.0 / combined - 1.0 / film
    return 1.0 / rest if rest > 1e-3 / film else 1e3 * film


def reduce_interior(surfaces, mass_convection: float, mass_radiation: float) -> ReducedInterior:
    """Eliminate the massless surface and star nodes of the room's inside.

    Parameters
    ----------
    surfaces : sequence of InteriorSurface
        Every component's inner surface (one without any coupling is left out).
    mass_convection, mass_radiation : float [W/K]
        The internal mass surface's convective coupling to the air and radiative coupling to
        the star node.

    Returns
    -------
    ReducedInterior
    """
    index = {name: i for i, name in enumerate(NODES)}
    kept_surfaces = tuple(s for s in surfaces if s.convection + s.radiation > 0)
    n_m = len(NODES)
    star = n_m + len(kept_surfaces)
    g = np.zeros((star + 1, star + 1))

    for k, s in enumerate(kept_surfaces):
        _link(g, n_m + k, index["Ti"], s.convection)
        _link(g, n_m + k, star, s.radiation)
        _link(g, n_m + k, index[s.node], s.conduction)
    _link(g, index["Tim"], index["Ti"], mass_convection)
    _link(g, index["Tim"], star, mass_radiation)
    if g[star, star] <= 0:
        g[star, star] = 1.0  # no radiation at all: the star is an isolated node
    g_ms = g[:n_m, n_m:]
    solve = np.linalg.solve(g[n_m:, n_m:], g_ms.T)  # G_SS^-1 G_SM
    reduced = g[:n_m, :n_m] - g_ms @ solve
    pairs = {f"G_{a}_{b}": float(max(-reduced[index[a], index[b]], 0.0)) for a, b in PAIRS}
    return ReducedInterior(pairs=pairs, surface_weights=-solve[:-1], surfaces=kept_surfaces)


def steady_temperatures(h: dict, ti: float, te: float, tgr: float) -> dict[str, float]:
    """Steady temperatures [C] of ``Tenv``, ``Tgf`` and ``Tim`` in the split inside's network
    (:data:`PAIR_NAMES` plus ``H_env_out``, ``H_gf_gr``, ``H_gf_e``) with the air, the outdoor
    air and the ground held at ``ti``, ``te``, ``tgr`` [C] (no sun, no gains).

    Parameters
    ----------
    h : dict
        Conductances [W/K] of :meth:`thermocal.retrofit.model.FifthOrderModel.conductances`.
    ti, te, tgr : float [C]

    Returns
    -------
    dict
        ``Tenv``, ``Tgf``, ``Tim`` [C] and ``heat`` [W], the heat the air needs to stay at
        ``ti``.
    """
    nodes = ("Ti", "Tenv", "Tgf", "Tim", "Te", "Tgr")
    index = {name: i for i, name in enumerate(nodes)}
    g = np.zeros((len(nodes), len(nodes)))
    links = [(a, b, float(h[f"G_{a}_{b}"])) for a, b in PAIRS]
    links += [
        ("Tenv", "Te", float(h["H_env_out"])),
        ("Tgf", "Tgr", float(h["H_gf_gr"])),
        ("Tgf", "Te", float(h["H_gf_e"])),
    ]
    for a, b, value in links:
        _link(g, index[a], index[b], value)
    free = [index["Tenv"], index["Tgf"], index["Tim"]]
    temps = np.zeros(len(nodes))
    temps[[index["Ti"], index["Te"], index["Tgr"]]] = (ti, te, tgr)
    # a free node without any link (no roof/walls, no floor) keeps the air's temperature
    isolated = np.diag(g)[free] <= 0
    g_ff = g[np.ix_(free, free)] + np.diag(np.where(isolated, 1.0, 0.0))
    fixed = temps.copy()
    rhs = -g[free] @ fixed + np.where(isolated, ti, 0.0)
    temps[free] = np.linalg.solve(g_ff, rhs)
    return {"Tenv": float(temps[1]), "Tgf": float(temps[2]), "Tim": float(temps[3]),
            "heat": float(g[index["Ti"]] @ temps)}  # fmt: skip


def steady_heat_loss(h: dict) -> float:
    """Steady-state heat [W] that holds ``Ti`` 1 K above ``Te`` and ``Tgr`` in the split
    inside's network, i.e. its calculated heat loss coefficient [W/K] without ``H_est``
    (:func:`steady_temperatures`).

    Parameters
    ----------
    h : dict
        Conductances [W/K] of :meth:`thermocal.retrofit.model.FifthOrderModel.conductances`.
    """
    return steady_temperatures(h, 1.0, 0.0, 0.0)["heat"]
