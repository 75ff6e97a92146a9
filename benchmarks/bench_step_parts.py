"""What each part of a time step costs, by leaving it out (issue 22 item 2).

On the clinic's captured kernel arguments (``benchmarks/bench_step_floor.py``: 186 zones, 7,083
nodes, the month's first chunk of 2,048 steps at 5 min), the compiled loop
(``thermocal.multizone._kernel.run_steps``) is compiled again from its source with one part
left out at a time, and every variant runs the same arguments in turn (A B C ... A B C ...).
A part's cost is the full step's time minus the variant's: an ablation, so the parts need not
add up (a left-out correction also changes the states the other parts see, and the processor
overlaps neighbouring loops), but it ranks them. The parts:

- the substitutions (replaced by a diagonal scaling, as in ``bench_step_floor.py``);
- TARP interior convection of the 1,908 faces (with its zone sums and corrections);
- the exterior faces' convection and exact long-wave corrections (348 faces);
- the exact interior long-wave corrections;
- the zones' mean radiant temperature output;
- ``B u``, the inputs' part of the right-hand side;
- the windows' temperature-dependent gas-gap conductance;
- People's temperature-dependent sensible heat.

Run: /work/venv/bin/python benchmarks/bench_step_parts.py [--repeats 4]
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_step_floor  # noqa: E402

KERNEL = Path(__file__).resolve().parents[1] / "src" / "thermocal" / "multizone" / "_kernel.py"

#: variant -> (text of the kernel, its replacement): each leaves one part out
LEFT_OUT = {
    "the substitutions": [
        ("lu_solve(*factors, rhs, work, x_new)", "_diagonal(rhs, inv_diag, x_new)"),
        ("lu_solve(*d_factors, rhs_d, work, x_new)", "_diagonal(rhs_d, d_inv_diag, x_new)"),
    ],
    "TARP interior convection": [
        ("        if tarp_on == 1:\n", "        if tarp_on == 1 and k < 0:\n"),
        ("        if tarp_on:\n", "        if tarp_on and k < 0:\n"),
    ],
    "exterior faces": [
        (
            "        for e in range(ext_node.shape[0]):\n            node = ext_node[e]",
            "        for e in range(0):\n            node = ext_node[e]",
        )
    ],
    "exact interior long-wave": [
        ("        if exact_interior:\n", "        if exact_interior and k < 0:\n")
    ],
    "mean radiant output": [
        (
            "        for f in range(face_node.shape[0]):\n            out_mrt[s, face_zone[f]]",
            "        for f in range(0):\n            out_mrt[s, face_zone[f]]",
        )
    ],
    "B u": [("        for p in range(b_val.shape[0]):", "        for p in range(0):")],
    "window gas gaps": [
        ("        for j in range(win_outer.shape[0]):\n", "        for j in range(0):\n")
    ],
    "People's heat": [("        if people_rows > 0:\n", "        if people_rows > 0 and k < 0:\n")],
}

DIAGONAL = '''

@njit(cache=False, fastmath=True)
def _diagonal(b, inv_diag, out):
    for i in range(b.shape[0]):
        out[i] = min(max(b[i] * inv_diag[i], -50.0), 80.0)
'''


def variant_source(source: str, edits) -> str:
    """The kernel's source with ``edits`` applied; each text must be in it."""
    for old, new in edits:
        if old not in source:
            raise SystemExit(f"the kernel no longer contains {old!r}: update LEFT_OUT")
        source = source.replace(old, new)
    return source + DIAGONAL


def load(name: str, source: str):
    """A module compiled from ``source`` (numba functions not cached)."""
    folder = Path(tempfile.mkdtemp(prefix="thermocal_step_parts_"))
    path = folder / f"step_parts_{name}.py"
    path.write_text(source.replace("cache=True", "cache=False"))
    spec = importlib.util.spec_from_file_location(f"thermocal.multizone.{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=4)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    source = KERNEL.read_text()
    modules = {"full step": load("full", source + DIAGONAL)}
    for i, (part, edits) in enumerate(LEFT_OUT.items()):
        modules[part] = load(f"part{i}", variant_source(source, edits))
    _, cases, _ = bench_step_floor.capture_clinic()
    print(
        f"Date: {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC; {os.cpu_count()} cores, "
        f"load average {os.getloadavg()[0]:.1f}; best of {args.repeats} (the first run compiles)."
    )
    modes = ("exact inverse (air)", "PID", "free run, given heat")
    best = {mode: {} for mode in modes}
    for mode in modes:
        case = cases[mode]
        for repeat in range(args.repeats + 1):
            for name, module in modules.items():
                call = [v.copy() if isinstance(v, np.ndarray) else v for v in case.values()]
                start = time.perf_counter()
                module.run_steps(*call)
                per_step = (time.perf_counter() - start) / case["n_steps"] * 1e6
                if repeat:
                    best[mode][name] = min(best[mode].get(name, np.inf), per_step)
    print("\n| left out | " + " | ".join(f"{m} [us/step]" for m in modes) + " |")
    print("|---|" + "---:|" * len(modes))
    for name in modules:
        cells = []
        for mode in modes:
            full = best[mode]["full step"]
            cells.append(
                f"{full:.1f}"
                if name == "full step"
                else f"{best[mode][name]:.1f} ({full - best[mode][name]:+.1f})"
            )
        print(f"| {'nothing (the full step)' if name == 'full step' else name} | "
              + " | ".join(cells) + " |")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
