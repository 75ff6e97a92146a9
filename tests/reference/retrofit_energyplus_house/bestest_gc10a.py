"""IEA BESTEST ground coupling, case GC10a (the analytical one), on ``diagnose_floor_section.py``.

Run from the repository root (about 80 s, 1.8 GB, no EnergyPlus)::

    PYTHONPATH=src python tests/reference/retrofit_energyplus_house/bestest_gc10a.py

Writes ``gc10a.json``: the steady floor heat flow of GC10a from ``diagnose_floor_section``'s
``kiva_section`` (reused, not copied) on a sequence of meshes and of domains, its mesh-converged
value, the case's analytical solution evaluated here (``rectangle_flow``) and its counterpart for
the two-dimensional section (``strip_flow``), and the published results it is checked against
(``tests/multizone/test_multizone_foundation.py::test_the_independent_section_meets_bestest_gc10a``).

The case: Neymark, Judkoff et al. (2008), IEA BESTEST In-Depth Diagnostic Cases for Ground
Coupled Heat Transfer Related to Slab-on-Grade Construction, NREL/TP-550-43388
(http://www.nrel.gov/docs/fy08osti/43388.pdf), case GC10a, as Kiva's own unit test builds it
(bigladder/kiva, commit 0fc63cf812a4b349751f0a66c4bc50a820eb2730: ``GC10aFixture`` on
``BESTESTFixture`` in ``test/unit/fixtures/bestest-fixture.hpp``, ``TEST_F(GC10aFixture, GC10a)``
in ``test/unit/foundation.unit.cpp``, added in 3c962744, 2017; the same boundaries in
``test/bestest/GC10a.yaml``). What GC30a has
(``bestest_gc30a.py``): a 12 m x 12 m floor at the grade (no slab layers) held at 30 C, the grade
held at 10 C (convective coefficients of 99,999 W/(m2 K)), soil 1.9 W/(m K), a 0.24 m wall
footprint of soil, the deep ground fixed at 10 C, Kiva's two-dimensional ``A / P`` section
(``RS_AP``, 3 m half-width; flow per metre x 48 m of perimeter; the fixture also sets
``numberOfDimensions = 2``). What differs:

* the wall's top is not adiabatic but held at a temperature linear across it, from the room's
  30 C at its inside face to the grade's 10 C at its outside face (fixture:
  ``wallTopBoundary = WTB_LINEAR_DT``, ``wallTopInteriorTemperature = 303.15``,
  ``wallTopExteriorTemperature = 283.15``; ``docs/input-def/boundaries.rst``: "used only to
  represent the constraints of the IEA BESTEST analytical solution in case GC10a";
  ``src/libkiva/Foundation.cpp`` meshes it as ``minCellDim``-wide strips at their mid-point
  temperatures; here each wall-top cell at the temperature of its centre,
  ``diagnose_floor_section.wall_top_temperature``);
* the domain is Kiva's default: the deep ground 40 m below the grade, the far field 40 m beyond
  ``A / P`` (the test sets neither; ``Foundation::Foundation()`` in ``Foundation.cpp``:
  ``deepGroundDepth(40.0), farFieldWidth(40.0)``; ``GC10a.yaml``: 40 and 40), where GC30a has 30
  and 20 m.

The analytical solution, 2,432.597 W (``double analyticalQ = 2432.597;`` in that test, the
verified numerical models' 2,427 (TRNSYS), 2,425 (FLUENT) and 2,432 W (MATLAB) commented beside
it; Kiva's own two-dimensional result 2,480.2 W, a comment there; Kiva asserts within 3 %), is
the steady heat flow from a rectangular surface region into a semi-infinite solid (Delsante,
Stokes & Walsh 1983, "Application of Fourier transforms to periodic heat flow into the ground
under a building", abstract at
https://paperexplained.cn/articles/paper/detail/694d3523d95131b51897bf46d0b3aaf5a7348724: "an
explicit exact expression for the 3-dim. steady-state heat flux from a rectangular surface
region"): the whole ground surface at given temperatures, no deep ground, no far field.
``rectangle_flow`` evaluates that problem here from its definition (not from the paper's
formula, which was not read): it gives 2,432.5966 W, the published value within 0.2 ppm, when
the wall top's temperature is linear in the distance from the floor up to the corners (contours
parallel to the walls, mitred at the corners); the product of the two linear profiles in the
corners would give 2,433.26 W. ``strip_flow`` is the same boundary for the two-dimensional ``A /
P`` section (an infinitely long strip ``2 A / P`` wide in a half-plane, per metre of one edge x
the perimeter), in closed form: 2,460.93 W. The ``A / P`` section itself therefore costs
+1.165 % over the three-dimensional floor, exactly.

Results (``gc10a.json``): 2,465.8 W mesh-converged on Kiva's domain (Richardson over first cells
of 2.5, 1.25 and 0.625 mm at growth 1.05, order 1.08; growth 1.025 adds +0.016 %), +1.37 % above
the analytical 2,432.6 W: the ``A / P`` section's +1.165 % and Kiva's 40 m domain's +0.22 % (on
the test mesh, 2,465.7 W at 40 m, 2,460.3 at 1,000 m), less the growth's 0.02 %. At 1,000 m and
growth 1.025 the section gives 2,460.75 W, -0.007 % from the exact two-dimensional 2,460.93: the
solver meets the closed form. 2,424.7 W on 2 cm cells growing by 1.5; Kiva's own 2,480.2 W
(its fixture's near field does not grow, ``maxNearGrowthCoeff = 1.0``).

Both analytical flows, derived for this script: with the ground surface at ``dT theta`` above the
outdoor temperature (``theta`` 1 on the floor ``F``, falling linearly to 0 across the wall's
width ``w``, 0 beyond), the flux into the half-space is ``k dT (-Laplacian)^(1/2) theta`` on the
surface. In two dimensions that is the Hilbert transform of ``theta'``,
``q(x) = k dT / pi p.v. int theta'(s) / (x - s) ds``; integrated over a strip of half-width
``b``: ``2 k dT / (pi w) [(2b + w) ln(2b + w) - w ln w - 2b ln 2b]`` per metre, half of it per
edge. In three dimensions, ``(-Laplacian)^(1/2) = 1 / (2 sqrt(pi)) int_0^inf (1 - e^(t
Laplacian)) t^(-3/2) dt``, so ``Q = k dT / (2 sqrt(pi)) int_0^inf t^(-3/2) (|F| - int_F e^(t
Laplacian) theta) dt``; with ``theta = f(x) f(y)`` (one trapezoid profile each way) the inner
integral is the product of two one-dimensional ones, in closed form with ``erf``; the mitred
corners differ from that product only in the four ``w x w`` corner squares, which adds
``-k dT / (2 pi) int_F int_corners (theta_mitred - theta_product)(s) / |x - s|^3 ds dx`` (the
hypersingular form of the same operator; the integral over ``F`` in closed form, over the
corners by Gauss-Legendre).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
from scipy.special import erfcx

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parents[2] / "src"))

from bestest_gc30a import (  # noqa: E402
    MESHES,  # noqa: F401  (this case's meshes too: its test reads them here)
    TEST_MESH,
    mesh_study,
    section_cells,
    section_flow,
)

KIVA = "bigladder/kiva, commit 0fc63cf812a4b349751f0a66c4bc50a820eb2730"
#: GC10a as Kiva's unit test sets it up (module docstring).
CASE = {
    "floor_m": [12.0, 12.0],
    "area_m2": 144.0,
    "perimeter_m": 48.0,
    "soil_W_per_mK": 1.9,
    "wall_footprint_m": 0.24,
    "interior_surface_C": 30.0,
    "grade_surface_C": 10.0,
    "wall_top": "linear across the wall from 30 C (inside face) to 10 C (outside face)",
    "deep_ground_C": 10.0,
    "deep_ground_depth_m": 40.0,
    "far_field_beyond_A_over_P_m": 40.0,
    "source": f"{KIVA}: test/unit/fixtures/bestest-fixture.hpp (BESTESTFixture, GC10aFixture), "
    "test/unit/foundation.unit.cpp (TEST_F(GC10aFixture, GC10a)), src/libkiva/Foundation.cpp "
    "(Foundation::Foundation(): deepGroundDepth(40.0), farFieldWidth(40.0); WTB_LINEAR_DT), "
    "docs/input-def/boundaries.rst (Wall Top Boundary Condition), test/bestest/GC10a.yaml",
}
#: Steady floor heat flow of GC10a [W], published (module docstring).
PUBLISHED = {
    "analytical": 2432.597,
    "source": "IEA BESTEST GC In-Depth (Neymark, Judkoff et al. 2008, NREL/TP-550-43388, "
    "http://www.nrel.gov/docs/fy08osti/43388.pdf), case GC10a's analytical solution (Delsante, "
    "Stokes & Walsh 1983), as transcribed in "
    f"{KIVA}: test/unit/foundation.unit.cpp, TEST_F(GC10aFixture, GC10a), "
    "'double analyticalQ = 2432.597;'",
    "TRNSYS": 2427.0,
    "FLUENT": 2425.0,
    "MATLAB": 2432.0,
    "verified_source": f"{KIVA}: test/unit/foundation.unit.cpp, TEST_F(GC10aFixture, GC10a), "
    "commented out beside the analytical value ('//double trnsysQ = 2427;' ...)",
    "kiva_2d": 2480.2,
    "kiva_2d_source": f"{KIVA}: test/unit/foundation.unit.cpp, comment '// kiva: 2480.2'",
}
#: Meshes and the test's mesh: ``bestest_gc30a.py``'s (``MESHES``, ``TEST_MESH``).
#: Domains (far field beyond ``A / P`` = deep ground depth [m], the deep ground fixed) and
#: meshes (first cell [m], growth): Kiva's 40 m on the test mesh, then towards the analytical
#: solution's half-space, the largest also with the gentler growth (680,000 cells, about 30 s).
DOMAINS = [
    (40.0, *TEST_MESH),
    (100.0, *TEST_MESH),
    (400.0, *TEST_MESH),
    (1000.0, *TEST_MESH),
    (1000.0, 0.0025, 1.025),
]
SQRT_PI = math.sqrt(math.pi)


def gc10a_flow(first=0.02, growth=1.5, soil_k=CASE["soil_W_per_mK"], domain=None) -> float:
    """GC10a's steady floor heat flow [W] on ``diagnose_floor_section``'s section; ``domain``
    [m]: the far field and the deep ground both that far instead of Kiva's 40 and 40 m."""
    return section_flow(CASE, first, growth, soil_k, domain=domain, wall_top_linear=True)


def strip_flow(soil_k=CASE["soil_W_per_mK"]) -> float:
    """GC10a's boundary on the ``A / P`` section in a half-plane [W], in closed form (module
    docstring): per metre of one edge of a strip ``2 A / P`` wide x the perimeter."""
    b = CASE["area_m2"] / CASE["perimeter_m"]
    w = CASE["wall_footprint_m"]
    dt = CASE["interior_surface_C"] - CASE["grade_surface_C"]
    bracket = (2 * b + w) * math.log(2 * b + w) - w * math.log(w) - 2 * b * math.log(2 * b)
    return CASE["perimeter_m"] * soil_k * dt / (math.pi * w) * bracket


def _tail(z):
    """What ``int_0^z int_0^u erf`` lacks of its large-``z`` form ``z^2/2 + 1/4 - z/sqrt(pi)``."""
    return np.exp(-z * z) * (z / (2 * SQRT_PI) - (z * z / 2 + 0.25) * erfcx(z))


def _small(z, terms=30):
    """``int_0^z int_0^u erf`` by its power series (for ``z`` below 1: no cancellation)."""
    out, term = np.zeros_like(z), 2.0 / SQRT_PI * z**3
    for n in range(terms):
        out = out + term / ((2 * n + 1) * (2 * n + 2) * (2 * n + 3))
        term = -term * z * z / (n + 1)
    return out


def _deficit(half, w, t):
    """``2 half - int g e^(t d2/dx2) f dx`` for the floor's indicator ``g`` (``|x| < half``)
    and the trapezoid ``f`` (1 on the floor, to 0 across ``w``): from the large-argument form
    while ``2 half + w`` exceeds the kernel's width ``2 sqrt(t)``, else from the series."""
    s = 2.0 * np.sqrt(t)
    z1, z2, z3 = (2 * half + w) / s, 2 * half / s, w / s
    large = s * s / w * (0.25 - _tail(z1) + _tail(z2) + _tail(z3))
    z1s, z2s, z3s = (np.minimum(z, 1.0) for z in (z1, z2, z3))  # the series' range only
    small = 2 * half - s * s / w * (_small(z1s) - _small(z2s) - _small(z3s))
    return np.where(z1 > 1.0, large, small)


def _corner_kernel(u, v, length, width):
    """``int_F |x - s|^-3 dx`` for ``s`` at (``u``, ``v``) beyond a corner of the ``length`` x
    ``width`` floor ``F``."""

    def g(x, y):  # d2 g / dx dy = (x^2 + y^2)^(-3/2)
        return -np.hypot(x, y) / (x * y)

    x1, x2, y1, y2 = -length - u, -u, -width - v, -v
    return g(x2, y2) - g(x1, y2) - g(x2, y1) + g(x1, y1)


def rectangle_flow(soil_k=CASE["soil_W_per_mK"], corners="mitred") -> float:
    """GC10a's analytical steady floor heat flow [W] (module docstring): the three-dimensional
    floor in a half-space, the wall top's temperature linear in the distance from the floor
    (``corners="mitred"``) or the product of the two profiles in the corners (``"product"``)."""
    length, width = CASE["floor_m"]
    w = CASE["wall_footprint_m"]
    dt = CASE["interior_surface_C"] - CASE["grade_surface_C"]
    # t = e^x: the integrand decays like e^(-|x| / 2) both ways (below 1e-17 of its peak at
    # |x| = 80); the trapezoid rule converges exponentially on it (the same to 1e-15 on 4,001
    # points as on 64,001)
    x = np.linspace(-80.0, 80.0, 8001)
    t = np.exp(x)
    da, db = _deficit(length / 2, w, t), _deficit(width / 2, w, t)
    inner = length * db + width * da - da * db  # |F| - I_a(t) I_b(t)
    flow = soil_k * dt / (2 * SQRT_PI) * np.trapezoid(inner * np.exp(-0.5 * x), x)
    if corners == "product":
        return float(flow)
    # mitred minus product in a corner square, (u, v) from the floor's corner: for v < u,
    # (1 - u / w) v / w; each triangle mapped onto a square (v = u s, or u = v s), Gauss-Legendre
    nodes, weights = np.polynomial.legendre.leggauss(60)
    r, s = 0.5 * w * (nodes + 1.0), 0.5 * (nodes + 1.0)
    rr, ss = np.meshgrid(r, s, indexing="ij")
    ww = np.outer(weights, weights) * 0.25 * w
    excess = (1.0 - rr / w) * (rr * ss / w) * rr  # the difference x the Jacobian r
    both = _corner_kernel(rr, rr * ss, length, width) + _corner_kernel(rr * ss, rr, length, width)
    correction = -soil_k * dt / (2 * math.pi) * 4.0 * float(np.sum(ww * excess * both))
    return float(flow) + correction


def main() -> dict:
    study = mesh_study(CASE, gc10a_flow)
    by_mesh, converged = study["by_mesh"], study["converged_W"]
    analytical = PUBLISHED["analytical"]
    strip = strip_flow()
    domains = []
    for d, f, g in DOMAINS:
        kiva_domain = d == CASE["deep_ground_depth_m"] == CASE["far_field_beyond_A_over_P_m"]
        flow = by_mesh[(f, g)] if kiva_domain else gc10a_flow(f, g, domain=d)
        domains.append(
            {
                "far_field_and_deep_ground_m": d,
                "first_cell_m": f,
                "growth": g,
                "cells": section_cells(CASE, f, g, domain=d),
                "floor_W": flow,
                "against_strip": flow / strip - 1.0,
            }
        )
    out = {
        "case": CASE,
        "published_W": PUBLISHED,
        "analytical_evaluated_W": {
            "rectangle_mitred_corners": rectangle_flow(),
            "rectangle_product_corners": rectangle_flow(corners="product"),
            "strip_A_over_P_section": strip,
        },
        "a_over_p_section_cost": strip / analytical - 1.0,
        **{k: study[k] for k in ("meshes", "converged_W", "observed_order")},
        "converged_against_analytical": converged / analytical - 1.0,
        "converged_against_strip": converged / strip - 1.0,
        **{k: study[k] for k in ("kiva_default_mesh_W", "test_mesh")},
        "domains": domains,
    }
    (HERE / "gc10a.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
