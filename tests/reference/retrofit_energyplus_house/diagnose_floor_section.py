"""The living floor's section below its surface, meshed as Kiva meshes it: a diagnosis.

Run from the repository root (about 2 s, no EnergyPlus)::

    PYTHONPATH=src python tests/reference/retrofit_energyplus_house/diagnose_floor_section.py

An independent steady finite-volume solution of Kiva's two-dimensional "area over perimeter"
section as ``Foundation.cpp`` builds it for ``house_v25.idf`` (bigladder/kiva, read 2026):
the floor's layers meshed in two dimensions from the symmetry plane to ``A / P`` (concrete, the
carpet on top), the footing wall (EXTWALL:GARAGE, inside layer at ``A / P``) from the slab's
bottom to its top, its top adiabatic, its face above the grade and the grade to the outdoor air
(thermocal's DOE-2 coefficient at 3 m/s plus the long-wave at 10 C), soil 0.864 W/(m K), the
far field 40 m beyond ``A / P`` and the deep ground 40 m down both adiabatic (Kiva's
``Autoselect`` at 556 m: 0.1022 x 556 = 56.8 m of water table, deeper than 40), cells from
2 cm growing by 1.5 (Kiva's defaults in EnergyPlus). It prints the conductance from the floor's
surface to the outdoor air [W/K], isothermal surface and with a film of 1.3 W/(m2 K) (what
EnergyPlus's floor had, 1,237 W over 5.24 K on 185.8 m2: then the flow over the mean surface
temperature, as ``floor_surface.json``), against ``floor_surface.json`` and thermocal's section.

The solver's checks: a floor without slab or wall above the grade gives 59.8 W/K against
ISO 13370's 60.3 (same soil, B' = 2 A / P; kept as
``test_the_independent_section_meets_iso_13370_without_a_slab``), and IEA BESTEST GC30a as
Kiva's own unit test sets it up (fixed surface temperatures, deep ground at 10 C 30 m down;
``bestest_gc30a.py`` -> ``gc30a.json``) gives 2,704 W mesh-converged against the three verified
numerical models' 2,585-2,695 W (within their range widened by 2 %:
``test_the_independent_section_meets_bestest_gc30a``), and GC10a, the analytical case (the
wall's top held linear from the room's temperature to the outdoor's, Kiva's 40 m domain;
``bestest_gc10a.py`` -> ``gc10a.json``), 2,465.8 W mesh-converged against the analytical
2,432.6 W, +1.37 %: the ``A / P`` section's own +1.165 % and the domain's +0.22 %; at 1,000 m it
meets the same boundary's closed-form 2-D solution within 0.007 %
(``test_the_independent_section_meets_bestest_gc10a``). The keywords ``area``, ``perimeter``,
``far_field``, ``deep``, ``deep_fixed``, ``h_out`` (``None``: the grade held at the outdoor
temperature) and ``wall_top_linear`` (``wall_top_temperature``) are for those cases; their
defaults are the house's section above.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2] / "src"))

from thermocal.multizone.foundation import (  # noqa: E402
    KIVA_DEFAULT_SOIL,
    FoundationGround,
    _edges,
    grade_convection,
    grade_longwave_coefficient,
    steady_floor_conductance,
)

WALL = ((0.2032, 1.048, 1105.0, 837.0), (0.0254, 0.6918, 1858.1, 836.8))  # inside first
FLOOR = [(0.1016, 1.31, 2243.0, 837.0), (0.0127, 0.0585, 200.0, 1300.0)]  # outside first
AREA, PERIMETER = 185.8, 49.121
#: The grade's and the wall's outdoor coefficient [W/(m2 K)]: DOE-2 convection at 3 m/s plus
#: the long-wave at 10 C (thermocal's).
H_GRADE = grade_convection(3.0) + grade_longwave_coefficient()


def boundary_conductance(face, half_cell, k, h=None):
    """Conductance [W/K per m of section] from a cell's centre to a boundary of the cell:
    ``face`` [m] wide, ``half_cell`` [m] from the centre, conductivity ``k`` [W/(m K)], then a
    surface coefficient ``h`` [W/(m2 K)]; ``h=None``: the boundary's temperature is fixed at
    the face itself (a Dirichlet boundary)."""
    return face / (half_cell / k + (1.0 / h if h else 0.0))


def wall_top_temperature(x, inner, outer):
    """The wall top's temperature at ``x`` [m] when it is held linear across the wall (IEA
    BESTEST GC10a's boundary): from the room's (1) at the wall's inside face ``inner`` [m] to
    the outdoor's (0) at its outside face ``outer`` [m], as a fraction of the difference."""
    return (outer - x) / (outer - inner)


def kiva_section(
    floor,
    soil_k=0.864,
    h_in=None,
    wall=WALL,
    height=0.2,
    first=0.02,
    growth=1.5,
    *,
    area=None,
    perimeter=None,
    far_field=40.0,
    deep=40.0,
    deep_fixed=False,
    h_out=H_GRADE,
    wall_top_linear=False,
):
    """Steady conductance [W/K] from the floor's surface (or, with ``h_in`` [W/(m2 K)], from
    its mean surface temperature) to the outdoor air of Kiva's section (module docstring):
    ``area`` [m2] and ``perimeter`` [m] (default the house's), the far field ``far_field`` [m]
    beyond ``A / P``, the deep ground ``deep`` [m] below the grade, adiabatic or with
    ``deep_fixed`` at the outdoor temperature, the grade's coefficient ``h_out`` (``None``:
    the grade at the outdoor temperature), the wall's top adiabatic or, with
    ``wall_top_linear``, held at ``wall_top_temperature`` across the wall."""
    area = AREA if area is None else area
    perimeter = PERIMETER if perimeter is None else perimeter
    half, t = area / perimeter, sum(w[0] for w in wall)
    s_bot = height - sum(layer[0] for layer in floor)
    wall_x = half + np.cumsum([0.0] + [w[0] for w in wall])
    floor_z = s_bot + np.cumsum([0.0] + [layer[0] for layer in floor])
    xe = _edges(0.0, half + far_field, [*wall_x], first, growth)
    ze = _edges(-deep, height, [0.0, *floor_z], first, growth)
    xc, zc, dx, dz = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ze[1:] + ze[:-1]), np.diff(xe), np.diff(ze)
    k = np.zeros((len(xc), len(zc)))
    for i, x in enumerate(xc):
        for j, z in enumerate(zc):
            if z < s_bot:
                k[i, j] = soil_k if (x < half + t or z < 0.0) else 0.0
            elif x < half:
                k[i, j] = floor[int(np.searchsorted(floor_z, z)) - 1][1]
            elif x < half + t:
                k[i, j] = wall[int(np.searchsorted(wall_x, x)) - 1][1]
            elif z < 0.0:
                k[i, j] = soil_k
    active = k > 0
    index = -np.ones(k.shape, dtype=int)
    index[active] = np.arange(int(active.sum()))
    a = sp.lil_matrix((int(active.sum()),) * 2)
    rhs = np.zeros(a.shape[0])

    def link(p, q, g):
        a[p, p] += g
        a[q, q] += g
        a[p, q] -= g
        a[q, p] -= g

    top = []
    for i in range(len(xc)):
        for j in range(len(zc)):
            if not active[i, j]:
                continue
            c = index[i, j]
            if j == 0 and deep_fixed:  # the deep ground at the outdoor temperature
                a[c, c] += boundary_conductance(dx[i], 0.5 * dz[j], k[i, j])
            if i + 1 < len(xc) and active[i + 1, j]:
                link(
                    c,
                    index[i + 1, j],
                    dz[j] / (0.5 * dx[i] / k[i, j] + 0.5 * dx[i + 1] / k[i + 1, j]),
                )
            elif i + 1 < len(xc) and zc[j] > 0.0:  # the wall's face above the grade
                a[c, c] += boundary_conductance(dz[j], 0.5 * dx[i], k[i, j], h_out)
            if j + 1 < len(zc) and active[i, j + 1]:
                link(
                    c,
                    index[i, j + 1],
                    dx[i] / (0.5 * dz[j] / k[i, j] + 0.5 * dz[j + 1] / k[i, j + 1]),
                )
            elif xc[i] < half:  # the floor's surface (room at 1)
                g = boundary_conductance(dx[i], 0.5 * dz[j], k[i, j], h_in)
                a[c, c] += g
                rhs[c] += g
                top.append((c, g, dx[i]))
            elif xc[i] > half + t:  # the grade
                a[c, c] += boundary_conductance(dx[i], 0.5 * dz[j], k[i, j], h_out)
            elif wall_top_linear:  # the wall's top held linear (else adiabatic)
                g = boundary_conductance(dx[i], 0.5 * dz[j], k[i, j])
                a[c, c] += g
                rhs[c] += g * wall_top_temperature(xc[i], half, half + t)
    temperature = spl.spsolve(a.tocsr(), rhs)
    flow = np.array([g * (1.0 - temperature[c]) for c, g, _ in top])
    width = np.array([w for *_, w in top])
    if not h_in:
        return float(flow.sum() * perimeter)
    surface = 1.0 - flow / (h_in * width)
    return float(flow.sum() * perimeter / (surface @ width / width.sum()))


def main() -> dict:
    kiva = json.loads((HERE / "floor_surface.json").read_text())
    ground = FoundationGround(PERIMETER, soil=KIVA_DEFAULT_SOIL, wall_layers=WALL)
    out = {}
    for case, floor in (("with_carpet", FLOOR), ("without_carpet", FLOOR[:1])):
        out[case] = {
            "energyplus_kiva": kiva[case]["below_surface_W_per_K"],
            "thermocal_section": steady_floor_conductance(
                ground, AREA, floor, inside_resistance=1e-9
            ),
            "kiva_like_isothermal": kiva_section(floor),
            "kiva_like_film_1.3": kiva_section(floor, h_in=1.3),
        }
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
