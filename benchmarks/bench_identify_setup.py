"""Set-up, speed and memory of the whole ``identify`` call (issue 28, item 8).

Targets: the clinic month (186 zones, 5-minute steps) identified in <= 1.5 s per method in
process (the closed loop; ``bench_identification.py`` times it alone), and the set-up around it
(building the model, references from the sensor log) and its memory in line with it. Also the
largest IDF building at hand, the PNNL/DOE multifamily prototype (20 zones, its own shadows;
``tests/reference/identification_multifamily``): IDF import and model set-up for January at
10 minutes.

Run: python benchmarks/bench_identify_setup.py [--repeats 2] [--write results.md]
Times are the best of the repeats, numba compiled beforehand (one warm call); memory is the
peak of Python and numpy allocations during one more, traced call (tracemalloc) and the
process's peak RSS.
The free-running simulation of the clinic month is timed in the same run as the peer (ratio),
since the machine is shared.
"""

from __future__ import annotations

import argparse
import datetime
import platform
import resource
import time
import tracemalloc
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MULTIFAMILY = ROOT / "tests" / "reference" / "identification_multifamily"


def timed(function, repeats):
    """Best wall time [s] of ``function()`` over ``repeats`` untraced calls, that call's result,
    and the peak of Python and numpy allocations [GB] of one more, traced call."""
    best, result = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        value = function()
        wall = time.perf_counter() - start
        if wall < best:
            best, result = wall, value
    tracemalloc.start()
    function()
    peak = tracemalloc.get_traced_memory()[1] / 1024**3
    tracemalloc.stop()
    return best, result, peak


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--write", type=Path)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    import pandas as pd

    from thermocal.demos.identification import load_demo
    from thermocal.identification.workflow import identify
    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import energyplus_weather_folder
    from thermocal.multizone.idf import read_idf
    from thermocal.multizone.simulation import Simulation

    building, weather, meta, raw, mapping, _ = load_demo()
    start, end = meta["period"]
    rows = []

    def run(method):
        return identify(
            building, weather, meta["weather"], raw, mapping, start=start, end=end, method=method
        )

    run("inverse")  # compile
    for method in ("inverse", "pid"):
        wall, result, peak = timed(lambda m=method: run(m), args.repeats)
        t = result.timings
        rows.append(
            (
                f"identify(method={method}), clinic month: whole call",
                f"{wall:.2f} s",
                f"model set-up {t['model_setup']:.2f} s, references {t['references']:.2f} s, "
                + (
                    f"inverse {t['inverse']:.2f} s"
                    if method == "inverse"
                    else f"tuning {t.get('tuning', 0):.2f} s, PID {t['pid']:.2f} s"
                ),
                f"{peak:.2f} GB traced",
            )
        )
    sim = Simulation(building, weather, meta["weather"], start=start, end=end, store_surfaces=False)
    sim.run(free_float=True)
    free, _, _ = timed(lambda: sim.run(free_float=True), args.repeats)
    rows.append(("peer: free-running simulation of the clinic month", f"{free:.2f} s", "", ""))

    idf = MULTIFAMILY / "multifamily_5A_FF_v25.idf"
    epw = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    if idf.exists() and epw.exists():
        mf_weather, mf_meta = read_weather(epw)
        tz = mf_weather.index.tz
        read, mf, read_peak = timed(lambda: read_idf(idf), args.repeats)

        def setup():
            return Simulation(
                mf,
                mf_weather,
                mf_meta,
                step="10min",
                start=pd.Timestamp("2023-01-01", tz=tz),
                end=pd.Timestamp("2023-02-01", tz=tz),
                store_surfaces=False,
            )

        build, mf_sim, build_peak = timed(setup, args.repeats)
        shaded = len(mf_sim._shadows["beam"]) if mf_sim._shadows else 0
        rows.append(
            (
                "multifamily prototype (20 zones): read_idf",
                f"{read:.2f} s",
                "",
                f"{read_peak:.2f} GB",
            )
        )
        rows.append(
            (
                "multifamily prototype: Simulation set-up, January at 10 min",
                f"{build:.2f} s",
                f"{mf_sim.network.n_nodes} nodes, {shaded} shaded receivers",
                f"{build_peak:.2f} GB traced",
            )
        )
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
    rows.append(("peak RSS of the process", f"{rss:.2f} GB", "", ""))
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"Date: {stamp}. Machine: {platform.machine()}, 2 cores shared; Python "
        f"{platform.python_version()}. Best of {args.repeats}.",
        "",
        "| case | wall | parts | memory |",
        "|---|---:|---|---|",
        *(f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows),
    ]
    text = "\n".join(lines)
    print(text)
    if args.write:
        args.write.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
