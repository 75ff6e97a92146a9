"""Reduced-order conduction (``NetworkOptions.conduction = "reduced"``, issue 22 item 1) against
the finite-difference model, side by side in one run.

For each building: nodes, non-zeros of the system matrix and of its LU factors, set-up time
(assembly with the reductions, solar, factorisation), time of the month's run (full and
reduced in turn, best and median of the repeats), and the largest / RMS difference of the zone
air and interior surface temperatures, reduced minus full, over the month.

Buildings: the generated clinic (``generators.clinic()``, 186 zones, January at 5 min, given
heat 300 W per zone, free floating); the 180-zone grid and NREL's 5ZoneAirCooled (EnergyPlus
reference IDF files, ../shared/data/energyplus_reference, January at 5 min / the file's 15 min,
the file's schedules and controls); and the identification of the clinic demo (exact inverse,
warm-up + month). Needs ../shared/data for the IDF files (skipped when absent).

Run: /work/venv/bin/python benchmarks/bench_conduction_reduction.py [--repeats 3]
     [--tolerance 1e-3] [--write results.md]
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import platform
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"
WEATHER = DATA / "ashrae140_bestest" / "725650TYCST.epw"
IDF = DATA / "energyplus_reference"


def _options(building, conduction: str, tolerance: float):
    """The options a Simulation would take, with the conduction model set."""
    from thermocal.multizone.network import NetworkOptions

    info = getattr(building, "idf_info", None)
    if info is not None and hasattr(info, "network_options"):
        options, _ = info.network_options()
        options = dataclasses.replace(options, interior_longwave_exchange="view_factors")
    else:
        options = NetworkOptions()
    return dataclasses.replace(options, conduction=conduction, conduction_tolerance=tolerance)


def _timed(function):
    start = time.perf_counter()
    out = function()
    return time.perf_counter() - start, out


def _lu_nonzeros(sim) -> int:
    from scipy.sparse.linalg import splu

    lu = splu(
        sim.network.system_matrix(sim.dt),
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )
    return int(lu.L.nnz + lu.U.nnz)


def compare(label, make_sim, run, repeats, tolerance):
    """Rows of one building: full vs reduced."""
    sims, setups = {}, {"full": [], "reduced": []}
    for _ in range(max(2, repeats // 2)):  # set-up in turn; a new Simulation reduces again
        for conduction in ("full", "reduced"):
            seconds, sims[conduction] = _timed(lambda c=conduction: make_sim(c, tolerance))
            setups[conduction].append(seconds)
    setups = {c: min(v) for c, v in setups.items()}
    results = {c: run(sims[c]) for c in sims}  # also compiles
    times = {c: [] for c in sims}
    for _ in range(repeats):
        for c in sims:
            times[c].append(_timed(lambda c=c: run(sims[c]))[0])
    full, red = results["full"], results["reduced"]
    air = (red.air_temperature - full.air_temperature).to_numpy()
    rows = []
    stats = {
        "nodes": (sims["full"].network.n_nodes, sims["reduced"].network.n_nodes),
        "system matrix non-zeros": (
            sims["full"].network.conductance.nnz,
            sims["reduced"].network.conductance.nnz,
        ),
        "LU non-zeros": (_lu_nonzeros(sims["full"]), _lu_nonzeros(sims["reduced"])),
        "set-up, best [s]": (setups["full"], setups["reduced"]),
        "run, best [s]": (min(times["full"]), min(times["reduced"])),
        "run, median [s]": (float(np.median(times["full"])), float(np.median(times["reduced"]))),
    }
    for name, (a, b) in stats.items():
        rows.append((label, name, a, b, b / a if a else float("nan")))
    rows.append(
        (
            label,
            "zone air: max / RMS |reduced - full| [K]",
            float(np.max(np.abs(air))),
            float(np.sqrt(np.mean(air**2))),
            None,
        )
    )
    if full.surface_temperature is not None:
        surf = (red.surface_temperature - full.surface_temperature).to_numpy(dtype=float)
        rows.append(
            (
                label,
                "interior surfaces: max / RMS |reduced - full| [K]",
                float(np.max(np.abs(surf))),
                float(np.sqrt(np.mean(surf**2))),
                None,
            )
        )
    for kind in ("heating", "cooling"):
        total_full = float(getattr(full, kind).to_numpy().sum())
        if total_full > 0:
            total_red = float(getattr(red, kind).to_numpy().sum())
            rows.append(
                (
                    label,
                    f"{kind} energy, reduced / full - 1",
                    total_red / total_full - 1,
                    None,
                    None,
                )
            )
    return rows


def clinic_rows(repeats, tolerance):
    from thermocal.demos.buildings import clinic
    from thermocal.io.weather import read_weather
    from thermocal.multizone.simulation import Simulation

    weather, meta = read_weather(WEATHER)
    building = clinic()

    def make(conduction, tol):
        return Simulation(
            building,
            weather,
            meta,
            step="5min",
            start="2023-01-01",
            end="2023-02-01",
            options=_options(building, conduction, tol),
        )

    def run(sim):
        heat = np.full((len(sim.times), len(building.zones)), 300.0)
        return sim.run(free_float=True, heat_input=heat)

    label = "clinic, 186 zones, Jan 5 min"
    rows = compare(label, make, run, repeats, tolerance)
    # a calibration sample: 10 envelope parameters, new values every call (no cache hit)
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_multizone import PARAMETERS

    sims = {c: make(c, tolerance) for c in ("full", "reduced")}
    times = {c: [] for c in sims}
    for j in range(repeats):
        values = {k: v * (1.0 + 0.01 * (j + 1)) for k, v in PARAMETERS.items()}
        for c, sim in sims.items():
            times[c].append(_timed(lambda s=sim, v=values: s.set_parameters(v))[0])
    best = (min(times["full"]), min(times["reduced"]))
    rows.append((label, "set_parameters, 10 new values, best [s]", *best, best[1] / best[0]))
    return rows


def idf_rows(name, label, start, end, step, year, repeats, tolerance):
    from thermocal.io.weather import read_weather
    from thermocal.multizone.files import load_building
    from thermocal.multizone.simulation import Simulation

    path = IDF / name
    if not path.exists():
        return [(label, f"skipped: {path} absent", None, None, None)]
    building = load_building(path)
    weather, meta = read_weather(WEATHER, coerce_year=year)

    def make(conduction, tol):
        return Simulation(
            building,
            weather,
            meta,
            step=step,
            start=start,
            end=end,
            options=_options(building, conduction, tol),
        )

    return compare(label, make, lambda sim: sim.run(), repeats, tolerance)


def identification_rows(repeats, tolerance):
    from thermocal.demos.identification import load_demo
    from thermocal.identification.problem import problem_from_measurements

    building, weather, meta, raw, mapping, _ = load_demo()
    start, end = meta["period"]
    sims, heat, times = {}, {}, {}
    for conduction in ("full", "reduced"):
        problem, _ = problem_from_measurements(
            building,
            weather,
            meta["weather"],
            raw,
            mapping,
            start=start,
            end=end,
            options=_options(building, conduction, tolerance),
        )
        reference = problem.reference[list(building.zones)].to_numpy()
        sims[conduction] = (problem.simulation(), reference)
        heat[conduction] = sims[conduction][0].track(reference, method="inverse")  # compile
        times[conduction] = []
    for _ in range(repeats):  # full and reduced in turn
        for conduction, (sim, reference) in sims.items():
            seconds, _ = _timed(lambda s=sim, r=reference: s.track(r, method="inverse"))
            times[conduction].append(seconds)
    label = "identification, clinic demo (exact inverse, warm-up + month)"
    nodes = tuple(sims[c][0].network.n_nodes for c in ("full", "reduced"))
    best = tuple(min(times[c]) for c in ("full", "reduced"))
    median = tuple(float(np.median(times[c])) for c in ("full", "reduced"))
    a, b = (np.asarray(_heat_of(heat[c])) for c in ("full", "reduced"))
    return [
        (label, "nodes", *nodes, nodes[1] / nodes[0]),
        (label, "best [s]", *best, best[1] / best[0]),
        (label, "median [s]", *median, median[1] / median[0]),
        (
            label,
            "identified heat: max |reduced - full| [W]; over the largest zone heat",
            float(np.max(np.abs(b - a))),
            float(np.max(np.abs(b - a)) / np.max(np.abs(a))),
            None,
        ),
    ]


def _heat_of(out):
    """The identified heat array of a ``track`` result."""
    for name in ("heat", "heat_input"):
        value = getattr(out, name, None)
        if value is not None:
            return np.asarray(value, dtype=float)
    if isinstance(out, tuple):
        return np.asarray(out[0], dtype=float)
    return np.asarray(out, dtype=float)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--tolerance", type=float, default=1e-3)
    parser.add_argument("--only", choices=("clinic", "grid", "5zone", "identification"))
    parser.add_argument("--write", type=Path)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    rows = []
    parts = {
        "clinic": lambda: clinic_rows(args.repeats, args.tolerance),
        "grid": lambda: idf_rows(
            "grid_180_zones_5min_january_v25.idf",
            "180-zone grid, Jan 5 min",
            "2009-01-01",
            "2009-02-01",
            "5min",
            2009,
            args.repeats,
            args.tolerance,
        ),
        "5zone": lambda: idf_rows(
            "5ZoneAirCooled_FF_v25.idf",
            "5ZoneAirCooled FF, Jan 15 min",
            "2009-01-01",
            "2009-02-01",
            "15min",
            2009,
            args.repeats,
            args.tolerance,
        ),
        "identification": lambda: identification_rows(args.repeats, args.tolerance),
    }
    for name, part in parts.items():
        if args.only is None or args.only == name:
            rows += part()
            print(f"{name} done", flush=True)
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"Date: {stamp}. Machine: {platform.machine()}, 2 cores shared with other jobs; Python "
        f"{platform.python_version()}. Tolerance {args.tolerance:g} K/K; {args.repeats} repeats, "
        "full and reduced in turn.",
        "",
        "| building | quantity | full | reduced | reduced / full |",
        "|---|---|---:|---:|---:|",
    ]
    for label, name, a, b, ratio in rows:
        cells = [
            f"{v:.4g}" if isinstance(v, float) else ("" if v is None else str(v))
            for v in (a, b, ratio)
        ]
        lines.append(f"| {label} | {name} | " + " | ".join(cells) + " |")
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
