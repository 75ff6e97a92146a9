"""Benchmarks of the grey-box engine (thermocal.statespace); prints the results table.

Run:  /work/venv/bin/python benchmarks/bench_statespace.py

Run with a peer:  python benchmarks/bench_statespace.py --peer <commit>  (the Bacher & Madsen
cases of that commit timed in the same run, e.g. the previous main).

Targets (issue 2):
- one log-likelihood evaluation, 2 states, 2 inputs, 230 samples: <= 100 microseconds;
- a full fit of that model (7 free parameters incl. noise and initial state): <= 0.15 s warm;
- the fifth-order retrofit model (14 free parameters) on 504 hourly samples: <= 2 s warm.
Targets (issue 29): the Bacher & Madsen TiTe fit <= 0.15 s warm per start; ``select`` on the
PRBS data (with the heat loss coefficient's profile intervals of the path) <= 30 s on 2 cores.
"Warm" = numba kernels compiled and cached (the first call in a fresh process loads them).
Synthetic data are simulated from the model itself (exact discretisation, fixed seeds); the fits
start from perturbed values.
"""

from __future__ import annotations

import os
import platform
import statistics
import time
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.linalg import expm

from thermocal.statespace import RCModel
from thermocal.statespace.data import prepare_data
from thermocal.statespace.estimation import LikelihoodProblem, simulate_stochastic

REPO = Path(__file__).resolve().parents[1]


def two_state_model() -> RCModel:
    m = RCModel("two_state")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.5)
    m.add_state("Te", capacity="Ce", noise=0.0, initial_mean=10.0, initial_std=2.0)
    m.add_conductance("Ti", "Te", conductance="Hie")
    m.add_conductance("Te", "Ta", conductance="Hea")
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    for name, value, unit in [("Ci", 2.0, "MJ/K"), ("Ce", 20.0, "MJ/K"), ("Hie", 300.0, "W/K"),
                              ("Hea", 200.0, "W/K"), ("si", 0.1, "K/sqrt(h)"), ("e", 0.1, "K"),
                              ("Ti0", 20.0, "C")]:  # fmt: skip
        m.add_parameter(name, value, unit=unit)
    return m


def two_state_data(model: RCModel, n: int = 230) -> pd.DataFrame:
    rng = np.random.default_rng(0)
    t = pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC")
    hours = np.arange(n)
    df = pd.DataFrame(
        {
            "Ta": 5 + 3 * np.sin(hours / 24 * 2 * np.pi) + rng.normal(0, 0.5, n),
            "Ph": 3000.0 * (rng.uniform(size=n) > 0.5),
        },
        index=t,
    )
    df["y"] = simulate_stochastic(model, df, seed=1)["y"]
    return df


def fifth_order_data(model: RCModel, n: int = 504) -> pd.DataFrame:
    rng = np.random.default_rng(0)
    t = pd.date_range("2019-02-02", periods=n, freq="h", tz="Europe/Zurich")
    h = np.arange(n)
    day = np.clip(np.sin(2 * np.pi * (h % 24 - 6) / 24), 0, None)
    df = pd.DataFrame(
        {
            "Te": 2 + 4 * np.sin(2 * np.pi * h / 24) + rng.normal(0, 1, n),
            "Tgr": 8.0,
            "phi_h": np.clip(8000 + 3000 * rng.normal(size=n), 0, None),
            "phi_sol": 800 * day,
            "phi_re": 1500 * day,
        },
        index=t,
    )
    df["Ti"] = simulate_stochastic(model, df, seed=1)["Ti"]
    return df


def timeit(fn, *, repeats: int, number: int = 1) -> tuple[float, float]:
    """Best and median time per call [s] over ``repeats`` batches of ``number`` calls."""
    fn()  # warm up (compilation / cache load)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        times.append((time.perf_counter() - t0) / number)
    return min(times), statistics.median(times)


BM = REPO.parent / "shared" / "data" / "bacher_madsen_2011_prbs" / "inputPRBS1.csv"
#: (key of bm_cases, row label, target [s])
BM_ROWS = [
    ("tite_one", "TiTe on the Bacher & Madsen data, 10 free, 1691 samples, one start", 0.15),
    ("tite_per_start", "TiTe, default starts ({tite_starts}, serial), per start", 0.15),
    ("tite_multi", "(context) TiTe, default starts ({tite_starts}, serial), whole fit", None),
    (
        "select",
        "select on the PRBS data (API: forward selection, default starts, 2 processes, "
        "+ HLC profile intervals of the path {path})",
        30.0,
    ),
]


def bm_cases() -> dict:
    """Times [s] and results of the Bacher & Madsen cases with the thermocal on sys.path."""
    from thermocal.statespace.families import bacher_madsen_family
    from thermocal.statespace.selection import forward_selection

    df_bm = pd.read_csv(BM, sep=";")
    tite = RCModel.from_yaml(REPO / "examples" / "models" / "TiTe.yaml")
    kw = {"time_column": "t", "time_unit": "h", "n_starts": 1}
    one = tite.fit(df_bm, **kw)
    out = {"tite_loglike": one.loglike}
    out["tite_one"], out["tite_one_median"] = timeit(lambda: tite.fit(df_bm, **kw), repeats=5)
    # the default multi-start (issue 29): max(3, ceil(k/2)) starts + the energy-balance start
    # (+ one more batch when the best is reached once), serial
    kw = {"time_column": "t", "time_unit": "h", "n_jobs": 1, "seed": 1}
    n_run = len(tite.fit(df_bm, **kw).start_loglikes)
    best, med = timeit(lambda: tite.fit(df_bm, **kw), repeats=3)
    out |= {"tite_starts": n_run, "tite_multi": best, "tite_multi_median": med,
            "tite_per_start": best / n_run, "tite_per_start_median": med / n_run}  # fmt: skip
    # forward selection on the PRBS data plus the HLC profile intervals along the path, as
    # `thermocal select` computes them
    models, ext, first = bacher_madsen_family()
    t0 = time.perf_counter()
    sel = forward_selection(models, ext, df_bm, start=first, time_column="t", time_unit="h",
                            seed=1)  # fmt: skip
    try:  # the profiles of the path in parallel, as `thermocal select` (after issue 29)
        from thermocal.statespace.results import heat_loss_coefficients

        hlc = heat_loss_coefficients(sel.fits, profile=sel.path)
        hlc = {name: hlc[name] for name in sel.path}
    except ImportError:  # an older commit (peer): one after the other
        hlc = {name: sel.fits[name].heat_loss_coefficient() for name in sel.path}
    out["select"] = time.perf_counter() - t0
    out["path"] = " -> ".join(sel.path)
    out["path_loglikes"] = ", ".join(f"{sel.fits[n].loglike:.3f}" for n in sel.path)
    out["path_hlc"] = ", ".join(
        f"{n} {h['value']:.1f} [{h.get('lower', float('nan')):.1f}, "
        f"{h.get('upper', float('nan')):.1f}]"
        for n, h in hlc.items()
    )
    return out


def peer_cases(commit: str, src: Path | None = None) -> dict:
    """:func:`bm_cases` of another commit of this repository (``git archive`` of its ``src``
    into a temporary folder, or ``src`` when given, e.g. an extraction whose numba cache is
    warm; run in a subprocess with that source first on the path)."""
    import json
    import subprocess
    import sys
    import tempfile

    if src is not None:
        env = dict(os.environ, PYTHONPATH=str(src))
        done = subprocess.run([sys.executable, __file__, "--bm-json"], env=env, check=True,
                              capture_output=True, text=True)  # fmt: skip
        return json.loads(done.stdout.strip().splitlines()[-1])
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "-C", str(REPO), "archive", commit, "src"],
                                 check=True, capture_output=True).stdout  # fmt: skip
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        env = dict(os.environ, PYTHONPATH=str(Path(tmp) / "src"))
        done = subprocess.run([sys.executable, __file__, "--bm-json"], env=env, check=True,
                              capture_output=True, text=True)  # fmt: skip
        return json.loads(done.stdout.strip().splitlines()[-1])


def synthetic_cases() -> tuple[list, str]:
    """Rows of the synthetic cases (issue 2 targets) and a line with their fit results."""
    rows = []
    model = two_state_model()
    data = two_state_data(model)
    prep = prepare_data(model, data)
    problem = LikelihoodProblem(model, prep, False)
    theta = model.theta0()
    best, med = timeit(lambda: problem.loglike(theta), repeats=15, number=2000)
    rows.append(("log-likelihood, 2 states, 2 inputs, 230 samples", best * 1e6, med * 1e6, "us",
                 100.0))  # fmt: skip
    A = model.continuous_matrices()[0] * 3600.0
    best_e, med_e = timeit(lambda: expm(A), repeats=7, number=2000)
    rows.append(("(context) scipy.linalg.expm of one 2x2 matrix", best_e * 1e6, med_e * 1e6, "us",
                 None))  # fmt: skip

    start = model.with_parameters({"Ci": 1, "Ce": 10, "Hie": 200, "Hea": 100, "si": 0.3,
                                   "e": 0.3, "Ti0": 18})  # fmt: skip
    res = start.fit(data, n_starts=1)
    assert res.converged, res.message
    best, med = timeit(lambda: start.fit(data, n_starts=1), repeats=15)
    rows.append((f"full fit incl. Hessian, same model, {start.n_free} free parameters, one start",
                 best, med, "s", 0.15))  # fmt: skip

    five = RCModel.from_yaml(REPO / "examples" / "models" / "fifth_order_retrofit.yaml")
    data5 = fifth_order_data(five)
    start5 = five.with_parameters({"H_est": 150, "Ci": 5, "Cenv": 20, "Cgf": 40, "Ch": 2,
                                   "Cim": 10})  # fmt: skip
    res5 = start5.fit(data5, n_starts=1)
    best, med = timeit(lambda: start5.fit(data5, n_starts=1), repeats=5)
    rows.append((f"fifth-order retrofit model, {start5.n_free} free parameters, 504 hourly "
                 "samples", best, med, "s", 2.0))  # fmt: skip
    prep5 = prepare_data(five, data5)
    p5 = LikelihoodProblem(five, prep5, False)
    th5 = five.theta0()
    best_l, med_l = timeit(lambda: p5.loglike(th5), repeats=7, number=200)
    rows.append(("(context) log-likelihood of the fifth-order model, 504 samples", best_l * 1e6,
                 med_l * 1e6, "us", None))  # fmt: skip
    fit_line = (
        f"Fit results: two-state loglike {res.loglike:.3f} ({res.n_free} free); fifth-order "
        f"loglike {res5.loglike:.3f} ({res5.n_free} free), flags: {len(res5.flags)}."
    )
    return rows, fit_line


def main() -> None:
    import argparse
    import json

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--peer", help="a commit of this repository to time alongside (e.g. "
                        "the previous main), Bacher & Madsen cases only")  # fmt: skip
    parser.add_argument("--peer-src", type=Path, help="an extracted `src` of the peer "
                        "(numba cache warm) instead of a fresh `git archive`")  # fmt: skip
    parser.add_argument("--bm-json", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--bm-only", action="store_true", help="only the Bacher & Madsen cases")
    args = parser.parse_args()
    if args.bm_json:
        print(json.dumps(bm_cases()))
        return
    rows, fit_line = ([], "") if args.bm_only else synthetic_cases()

    peer = None
    if BM.exists():
        if args.peer:
            peer = peer_cases(args.peer, args.peer_src)
        cur = bm_cases()
        for key, label, target in BM_ROWS:
            label = label.format(**cur)
            if peer is not None and key in peer:
                ratio = peer[key] / cur[key] if cur[key] > 0 else float("nan")
                label += f" (peer {args.peer}: {peer[key]:.3g} s, {ratio:.2f}x)"
            rows.append((label, cur[key], cur.get(key + "_median", cur[key]), "s", target))
        extra = [
            "Bacher & Madsen results (this code): TiTe one start loglike "
            f"{cur['tite_loglike']:.4f}; select path {cur['path']}, loglikes "
            f"{cur['path_loglikes']}, HLC [W/K] {cur['path_hlc']}.",
        ]
        if peer is not None:
            extra.append(
                f"Peer {args.peer}: TiTe loglike {peer['tite_loglike']:.4f}; select path "
                f"{peer['path']}, loglikes {peer['path_loglikes']}, HLC [W/K] {peer['path_hlc']}."
            )
    else:
        extra = [f"(no Bacher & Madsen data at {BM}: those rows skipped)"]

    lines = [
        "# Benchmarks: thermocal.statespace",
        "",
        f"Date: {datetime.now(UTC):%Y-%m-%d %H:%M} UTC. Machine: {platform.machine()}, "
        f"{os.cpu_count()} cores, 24 GiB, no GPU; Python {platform.python_version()}; other "
        "engineers' jobs were running, so the best of the repeats is the fairer figure.",
        "Script: `benchmarks/bench_statespace.py` (best and median over repeats, warm kernels).",
        "",
        "| case | best | median | unit | target | pass |",
        "|---|---:|---:|---|---:|---|",
    ]
    for name, best, med, unit, target in rows:
        verdict = "" if target is None else ("pass" if best <= target else "FAIL")
        tgt = "" if target is None else f"<= {target:g}"
        lines.append(f"| {name} | {best:.3g} | {med:.3g} | {unit} | {tgt} | {verdict} |")
    lines += [
        "",
        fit_line,
        "",
        *extra,
        "",
    ]
    text = "\n".join(lines)
    print(text)


if __name__ == "__main__":
    main()
