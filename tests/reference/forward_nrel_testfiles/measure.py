"""thermocal against EnergyPlus 25.2 on the converted NREL test files: writes results.json.

Run from the repository root (EnergyPlus 25.2 and ../shared/data needed, about a minute)::

    python tests/reference/forward_nrel_testfiles/measure.py [--step 15min] [--break NAME]

Uses the functions of ``tests/multizone/test_multizone_nrel_testfiles.py`` (same files, periods,
weather and statistics), one engine at a time. ``--step 3min`` runs both engines at 3 minutes
(EnergyPlus on a copy with ``Timestep`` 20). ``--break NAME`` changes thermocal's building after
import (:data:`BREAKS`: the check that the test's bounds catch broken physics). The entry is
written under ``"<step>"`` or ``"<step> break <NAME>"`` of results.json.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import re
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path[:0] = [str(ROOT / "tests"), str(ROOT / "tests" / "multizone")]

import test_multizone_nrel_testfiles as T  # noqa: E402

from conftest import SHARED_DATA  # noqa: E402


def _windows_u_x15(building):
    for name, wt in building.window_types.items():
        building.window_types[name] = dataclasses.replace(wt, u_value=1.5 * wt.u_value)


def _no_internal_gains(building):
    building.idf_info.internal_gains = type(building.idf_info.internal_gains)()
    for zone in building.zones.values():
        zone.internal_gains = 0.0


def _walls_r13_u_x15(building):
    layer = building.materials.get("R13LAYER")
    if layer is not None:
        smaller = dataclasses.replace(layer, resistance=layer.resistance / 1.5)
        building.materials["R13LAYER"] = smaller


def _ventilation_x067(building):
    info = building.idf_info
    info.infiltration = [
        dataclasses.replace(i, design_flow=i.design_flow / 1.5) for i in info.infiltration
    ]


def _no_shading_surfaces(building):
    building.idf_info.shading_surfaces = []


#: changes of thermocal's building after import; the test must fail with each
BREAKS = {
    "window_u_x1.5": _windows_u_x15,
    "no_internal_gains": _no_internal_gains,
    "r13_wall_u_x1.5": _walls_r13_u_x15,
    "ventilation_x0.67": _ventilation_x067,
    "no_shading_surfaces": _no_shading_surfaces,
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--step", default="15min")
    parser.add_argument("--break", dest="broken", choices=sorted(BREAKS))
    parser.add_argument("--cases", nargs="*", default=list(T.CASES))
    args = parser.parse_args()
    weather = SHARED_DATA.joinpath(*T.WEATHER)
    if args.broken:
        read = T.read_idf

        def broken_read(path):
            building = read(path)
            BREAKS[args.broken](building)
            return building

        T.read_idf = broken_read
    per_hour = 3600 // int(args.step.removesuffix("min")) // 60
    out: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        for case in args.cases:
            for period in T.PERIODS:
                idf = T.period_idf(case, period, Path(tmp))
                text, n = re.subn(r"Timestep,\s*4;", f"Timestep,{per_hour};", idf.read_text())
                assert n == 1
                idf.write_text(text)
                t0 = time.time()
                reference = T.energyplus(idf, weather, Path(tmp) / f"{case}_{period}")
                t1 = time.time()
                result = T.thermocal(idf, weather, period, step=args.step)
                t2 = time.time()
                zones = {
                    z: T.hourly_errors(reference, result, z, period) for z in T.CASES[case].zones
                }
                start, end = T.period_bounds(period)
                compared = reference.loc[start + T.pd.Timedelta(days=1) : end]
                ranges = {
                    z: [round(float(f(compared[f"{z.upper()}:Zone Mean Air Temperature [C]"])), 2)
                        for f in (T.np.min, T.np.mean, T.np.max)]
                    for z in zones
                }  # fmt: skip
                out.setdefault(case, {})[period] = {
                    "zones": {z: {k: round(v, 4) for k, v in e.items()} for z, e in zones.items()},
                    "energyplus_min_mean_max": ranges,
                    "seconds": {"energyplus": round(t1 - t0, 1), "thermocal": round(t2 - t1, 1)},
                }
                print(case, period, out[case][period], flush=True)
    label = args.step + (f" break {args.broken}" if args.broken else "")
    path = HERE / "results.json"
    results = json.loads(path.read_text()) if path.exists() else {}
    entry = results.setdefault(label, {})
    entry.update(out)
    entry["measured"] = time.strftime("%Y-%m-%d")
    path.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
