"""IEA BESTEST ground coupling, case GC30a, on ``diagnose_floor_section.py``'s independent section.

Run from the repository root (about 30 s, no EnergyPlus)::

    PYTHONPATH=src python tests/reference/retrofit_energyplus_house/bestest_gc30a.py

Writes ``gc30a.json``: the steady floor heat flow of GC30a from ``diagnose_floor_section``'s
``kiva_section`` (reused, not copied) on a sequence of meshes, its mesh-converged value, and the
published results it is checked against (``tests/multizone/test_multizone_foundation.py::
test_the_independent_section_meets_bestest_gc30a``).

The case: Neymark, Judkoff et al. (2008), IEA BESTEST In-Depth Diagnostic Cases for Ground
Coupled Heat Transfer Related to Slab-on-Grade Construction, NREL/TP-550-43388, as Kiva's own
unit test builds it (bigladder/kiva, ``test/unit/fixtures/bestest-fixture.hpp`` and
``test/unit/foundation.unit.cpp``, commit 0fc63cf812a4b349751f0a66c4bc50a820eb2730; the same in
``test/bestest/GC30a.yaml``): a 12 m x 12 m floor at the grade (no slab layers) held at 30 C, a
0.24 m wall footprint of soil with an adiabatic top, the grade held at 10 C (GC30a: surface
temperatures given directly, in Kiva convective coefficients of 99,999 W/(m2 K); GC30b has 100
W/(m2 K) and a 15 m x 15 m domain), soil 1.9 W/(m K), the deep ground 30 m below the grade at
10 C, the far field 20 m beyond ``A / P`` adiabatic (Kiva: ``xMax = A / P + farFieldWidth``),
Kiva's two-dimensional ``A / P`` section (3 m half-width; flow per metre x 48 m of perimeter).
All boundaries are fixed temperatures or adiabatic, so the flow is 20 K x the section's
conductance with the grade and the deep ground at the outdoor temperature.

Published steady floor heat flows of GC30a, the three verified numerical models (3-D):
TRNSYS 2,642 W, FLUENT 2,585 W, MATLAB 2,695 W, as transcribed in Kiva's unit test
``TEST_F(BESTESTFixture, GC30a)`` (``foundation.unit.cpp`` at the commit above, added in
3c962744, 2017: "Add all SS BESTEST cases to unit tests"), which in 2014 plotted them from the
report's accompanying results spreadsheet ``GC-InDepth-Results.XLS`` (Kiva's
``BESTEST/scripts/gen_bestest.py`` and ``bestest_ss.py``, commit c595eb88: row 59, column E,
``qfloor``; that spreadsheet itself is not in Kiva's public history) into
``docs/images/bestest-ss.png``, whose bars agree. Kiva's own two-dimensional result: 2,665.0 W
(a comment in the same test; it asserted 2,650 +- 100 W before 3c962744).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parents[2] / "src"))

import diagnose_floor_section as dfs  # noqa: E402

from thermocal.multizone.foundation import _edges  # noqa: E402

KIVA = "bigladder/kiva, commit 0fc63cf812a4b349751f0a66c4bc50a820eb2730"
#: GC30a as Kiva's unit test sets it up (module docstring).
CASE = {
    "floor_m": [12.0, 12.0],
    "area_m2": 144.0,
    "perimeter_m": 48.0,
    "soil_W_per_mK": 1.9,
    "wall_footprint_m": 0.24,
    "interior_surface_C": 30.0,
    "grade_surface_C": 10.0,
    "deep_ground_C": 10.0,
    "deep_ground_depth_m": 30.0,
    "far_field_beyond_A_over_P_m": 20.0,
    "source": f"{KIVA}: test/unit/fixtures/bestest-fixture.hpp (BESTESTFixture), "
    "test/unit/foundation.unit.cpp (TEST_F(BESTESTFixture, GC30a)), test/bestest/GC30a.yaml",
}
#: Steady floor heat flow of GC30a [W], published (module docstring).
PUBLISHED = {
    "TRNSYS": 2642.0,
    "FLUENT": 2585.0,
    "MATLAB": 2695.0,
    "source": "IEA BESTEST GC In-Depth (Neymark, Judkoff et al. 2008, NREL/TP-550-43388), "
    "verified numerical models, as transcribed in "
    f"{KIVA}: test/unit/foundation.unit.cpp, TEST_F(BESTESTFixture, GC30a) "
    "(plotted from the report's GC-InDepth-Results.XLS in docs/images/bestest-ss.png)",
    "kiva_2d": 2665.0,
    "kiva_2d_source": f"{KIVA}: test/unit/foundation.unit.cpp, comment '// kiva: 2665.0'",
}
VERIFIED = ("TRNSYS", "FLUENT", "MATLAB")
#: Meshes (first cell [m], growth): Kiva's defaults, then the first cell halved at growth 1.05
#: (the last three extrapolated), and a gentler growth at the finest-but-one.
MESHES = [
    (0.02, 1.5),
    (0.01, 1.05),
    (0.005, 1.05),
    (0.0025, 1.05),
    (0.00125, 1.05),
    (0.000625, 1.05),
    (0.00125, 1.025),
]
#: The mesh the test solves (about 3 s).
TEST_MESH = (0.0025, 1.05)


def section_flow(case, first, growth, soil_k, *, domain=None, wall_top_linear=False) -> float:
    """A BESTEST ground-coupling case's steady floor heat flow [W] on
    ``diagnose_floor_section``'s section: the bare floor and a wall of soil at fixed surface
    temperatures, the deep ground fixed; ``domain`` [m]: the far field and the deep ground
    both that far instead of the case's; ``wall_top_linear``: the wall's top held linear
    between the two surface temperatures (GC10a) instead of adiabatic."""
    wall = ((case["wall_footprint_m"], soil_k, 1490.0, 1800.0),)  # Kiva: a wall of soil
    conductance = dfs.kiva_section(
        [],
        soil_k=soil_k,
        wall=wall,
        height=0.0,
        first=first,
        growth=growth,
        area=case["area_m2"],
        perimeter=case["perimeter_m"],
        far_field=domain or case["far_field_beyond_A_over_P_m"],
        deep=domain or case["deep_ground_depth_m"],
        deep_fixed=True,
        h_out=None,
        wall_top_linear=wall_top_linear,
    )
    return conductance * (case["interior_surface_C"] - case["grade_surface_C"])


def section_cells(case, first, growth, domain=None) -> int:
    """The section's cell count on a mesh (``domain`` as :func:`section_flow`'s)."""
    half = case["area_m2"] / case["perimeter_m"]
    far = domain or case["far_field_beyond_A_over_P_m"]
    deep = domain or case["deep_ground_depth_m"]
    xe = _edges(0.0, half + far, [half, half + case["wall_footprint_m"]], first, growth)
    ze = _edges(-deep, 0.0, [0.0], first, growth)
    return (len(xe) - 1) * (len(ze) - 1)


def gc30a_flow(first=0.02, growth=1.5, soil_k=CASE["soil_W_per_mK"]) -> float:
    """GC30a's steady floor heat flow [W] on ``diagnose_floor_section``'s section."""
    return section_flow(CASE, first, growth, soil_k)


def richardson(coarse, medium, fine, ratio=2.0) -> tuple[float, float]:
    """The limit and the observed order of three solutions on meshes refined by ``ratio``."""
    order = math.log((medium - coarse) / (fine - medium)) / math.log(ratio)
    return fine + (fine - medium) / (ratio**order - 1.0), order


def mesh_study(case, flow) -> dict:
    """``flow(first, growth)`` [W] on every mesh of :data:`MESHES`, extrapolated (Richardson)
    from the three finest at growth 1.05.

    Returns
    -------
    dict
        ``meshes`` (first cell, growth, cells, floor flow each), ``converged_W``,
        ``observed_order``, ``kiva_default_mesh_W``, ``test_mesh`` (on :data:`TEST_MESH`, with
        its error against the converged value) and ``by_mesh`` ((first, growth) -> flow [W]).
    """
    meshes = [
        {
            "first_cell_m": f,
            "growth": g,
            "cells": section_cells(case, f, g),
            "floor_W": flow(f, g),
        }
        for f, g in MESHES
    ]
    halved = [m["floor_W"] for m in meshes if m["growth"] == 1.05][-3:]
    converged, order = richardson(*halved)
    by_mesh = {(m["first_cell_m"], m["growth"]): m["floor_W"] for m in meshes}
    return {
        "meshes": meshes,
        "converged_W": converged,
        "observed_order": order,
        "kiva_default_mesh_W": by_mesh[(0.02, 1.5)],
        "test_mesh": {
            "first_cell_m": TEST_MESH[0],
            "growth": TEST_MESH[1],
            "floor_W": by_mesh[TEST_MESH],
            "error_against_converged": by_mesh[TEST_MESH] / converged - 1.0,
        },
        "by_mesh": by_mesh,
    }


def main() -> dict:
    study = mesh_study(CASE, gc30a_flow)
    verified = [PUBLISHED[name] for name in VERIFIED]
    out = {
        "case": CASE,
        "published_W": PUBLISHED,
        "verified_range_W": [min(verified), max(verified)],
        **{k: study[k] for k in ("meshes", "converged_W", "observed_order")},
        **{k: study[k] for k in ("kiva_default_mesh_W", "test_mesh")},
    }
    (HERE / "gc30a.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
