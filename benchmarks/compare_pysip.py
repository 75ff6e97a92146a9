"""External-reference benchmark of thermocal's grey-box engine against pySIP's conventions.

Run:  /work/pysip-venv/bin/python benchmarks/compare_pysip.py      (or /work/venv/bin/python)

Data: ../shared/data/bacher_madsen_2011_prbs/inputPRBS1.csv (SYSLAB FlexHouse PRBS experiment,
Bacher & Madsen 2011; see its SOURCE.md): t [h], Ta [C], Ps [kW/m2], Ph [kW], yTi [C].
Models: examples/models/TiTe.yaml and TiTeTh.yaml (capacities kWh/K, resistances K/kW, time h).

pySIP (LOCIE, github.com/locie/pySIP) is not a project dependency. Note that the PyPI distribution
named ``pysip`` (1.1.0) is an unrelated HTTP client for the "Simple Intel Platform"; LOCIE's pySIP
is not published on PyPI. The script therefore first checks whether the importable ``pysip`` is
LOCIE's (it has ``pysip.statespace``) and says so. Whatever the outcome, it then compares thermocal
with an independent, dense re-implementation of the algorithm of pySIP's ``KalmanQR`` filter
(square-root Kalman filter by QR, update-then-predict, zero-order hold, Van Loan process noise,
Cholesky factors for Q, R and P0, negative log-likelihood with the 0.5 n log(2 pi) constant),
written here from the equations in numpy/scipy/numba, with the continuous matrices built by hand
from the physical parameters (not from thermocal). It reports:

1. the maximised log-likelihood each implementation reaches (thermocal ``fit``; the reference with
   plain scipy BFGS, numerical gradients, log-transformed positive parameters, no bounds);
2. each implementation's log-likelihood at the other's optimum (filter agreement);
3. the wall time of each fit (best of 3, warm: numba compiled, first call discarded).

Exit status 0 with a message if the data file is absent.
"""

from __future__ import annotations

import importlib
import math
import os
import platform
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.linalg import expm
from scipy.optimize import minimize

REPO = Path(__file__).resolve().parents[1]
DATA_DIR = (
    Path(os.environ.get("THERMOCAL_SHARED_DATA", REPO.parent / "shared" / "data"))
    / "bacher_madsen_2011_prbs"
)
DATA = DATA_DIR / "inputPRBS1.csv"
MODELS = ("TiTe", "TiTeTh")
REPEATS = 3


def pysip_status() -> tuple[bool, str]:
    """Whether LOCIE's pySIP is importable, and a message saying what was found."""
    try:
        pysip = importlib.import_module("pysip")
    except ImportError:
        return False, "pySIP is not importable (not a project dependency)."
    try:
        importlib.import_module("pysip.statespace")
    except ImportError:
        version = "unknown"
        try:
            from importlib.metadata import version as dist_version

            version = dist_version("pysip")
        except Exception:  # noqa: BLE001 - metadata is informative only
            pass
        return False, (
            f"the importable 'pysip' ({version}, {getattr(pysip, '__file__', '?')}) is not "
            "LOCIE's pySIP: it has no 'pysip.statespace' (PyPI 'pysip' is an unrelated HTTP "
            "client for the Simple Intel Platform; LOCIE's pySIP is not on PyPI)."
        )
    return True, "LOCIE's pySIP is importable (pysip.statespace found)."


# --------------------------------------------------------------------------------------------
# Independent reference: continuous matrices by hand (hours, kWh/K, K/kW, kW, kW/m2)
# --------------------------------------------------------------------------------------------
#: Free parameters of each model, in thermocal's names and declared units; input order Ta, Ps, Ph.
FREE = {
    "TiTe": ["Ci", "Ce", "Rie", "Rea", "Aw", "sigma_i", "sigma_e", "e_std", "Ti0", "Te0"],
    "TiTeTh": [
        "Ci", "Ce", "Ch", "Rih", "Rie", "Rea", "Aw",
        "sigma_i", "sigma_e", "sigma_h", "e_std", "Ti0", "Te0", "Th0",
    ],
}  # fmt: skip
#: Initial standard deviations of the states [K] (fixed numbers in the model files).
P0_STD = {"TiTe": [0.1, 1.0], "TiTeTh": [0.1, 1.0, 1.0]}


def continuous_system(name: str, p: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A [1/h], B [K/h per input unit], diffusion Cholesky factor [K/sqrt(h)] of the model.

    States: TiTe (Ti, Te); TiTeTh (Ti, Te, Th). Inputs: Ta [C], Ps [kW/m2], Ph [kW].
    """
    if name == "TiTe":
        ci, ce, rie, rea, aw = p["Ci"], p["Ce"], p["Rie"], p["Rea"], p["Aw"]
        a = np.array(
            [
                [-1 / (rie * ci), 1 / (rie * ci)],
                [1 / (rie * ce), -1 / (rie * ce) - 1 / (rea * ce)],
            ]
        )
        b = np.array([[0.0, aw / ci, 1 / ci], [1 / (rea * ce), 0.0, 0.0]])
        sig = np.diag([p["sigma_i"], p["sigma_e"]])
        return a, b, sig
    ci, ce, ch = p["Ci"], p["Ce"], p["Ch"]
    rih, rie, rea, aw = p["Rih"], p["Rie"], p["Rea"], p["Aw"]
    a = np.array(
        [
            [-1 / (rih * ci) - 1 / (rie * ci), 1 / (rie * ci), 1 / (rih * ci)],
            [1 / (rie * ce), -1 / (rie * ce) - 1 / (rea * ce), 0.0],
            [1 / (rih * ch), 0.0, -1 / (rih * ch)],
        ]
    )
    b = np.array([[0.0, aw / ci, 0.0], [1 / (rea * ce), 0.0, 0.0], [0.0, 0.0, 1 / ch]])
    sig = np.diag([p["sigma_i"], p["sigma_e"], p["sigma_h"]])
    return a, b, sig


def discretise_zoh(a, b, sig, dt: float):
    """Exact zero-order-hold discretisation; process noise by Van Loan (1978).

    Returns Ad, Bd and a square factor F with F'F = Qd = int_0^dt e^{As} S S' e^{A's} ds (from the
    eigen-decomposition, so that a vanishing diffusion gives a valid factor; the QR filter only
    needs F'F = Qd).
    """
    nx, nu = b.shape
    m = np.zeros((nx + nu, nx + nu))
    m[:nx, :nx], m[:nx, nx:] = a, b
    e = expm(m * dt)
    ad, bd = e[:nx, :nx], e[:nx, nx:]
    vl = np.zeros((2 * nx, 2 * nx))
    vl[:nx, :nx], vl[:nx, nx:], vl[nx:, nx:] = -a, sig @ sig.T, a.T
    f = expm(vl * dt)
    qd = f[nx:, nx:].T @ f[:nx, nx:]
    w, v = np.linalg.eigh(0.5 * (qd + qd.T))
    factor = np.sqrt(np.clip(w, 0.0, None))[:, None] * v.T
    return np.ascontiguousarray(ad), np.ascontiguousarray(bd), np.ascontiguousarray(factor)


def _neg_loglike_sqrt(ad, bd, qd_chol, c, r_std, x0, p0_chol, u, y):
    """Negative log-likelihood of a square-root (QR) Kalman filter, update then predict.

    P is carried as an upper Cholesky factor (P = U'U); scalar output. Includes 0.5 n log 2 pi.
    """
    nx = ad.shape[0]
    adt = np.ascontiguousarray(ad.T)
    x = x0.copy()
    pu = p0_chol.copy()
    nll = 0.0
    n = y.shape[0]
    arr = np.zeros((nx + 1, nx + 1))
    stack = np.zeros((2 * nx, nx))
    for k in range(n):
        if not np.isnan(y[k]):
            arr[:] = 0.0
            arr[0, 0] = r_std
            arr[1:, 0] = pu @ c
            arr[1:, 1:] = pu
            rf = np.linalg.qr(arr)[1]
            s = rf[0, 0]
            innov = (y[k] - c @ x) / s
            x = x + rf[0, 1:] * innov
            pu = rf[1:, 1:].copy()
            nll += math.log(abs(s)) + 0.5 * innov * innov + 0.5 * math.log(2.0 * math.pi)
        stack[:nx] = pu @ adt
        stack[nx:] = qd_chol
        pu = np.linalg.qr(stack)[1][:nx, :nx].copy()
        x = ad @ x + bd @ u[k]
    return nll


try:  # the reference filter is numba-compiled like pySIP's KalmanQR (jit_module there)
    from numba import njit

    _neg_loglike_sqrt = njit(cache=False)(_neg_loglike_sqrt)
except ImportError:  # pragma: no cover - numba is in both environments
    pass


class Reference:
    """Independent pySIP-convention likelihood of one model on uniformly sampled data."""

    def __init__(self, name: str, df: pd.DataFrame) -> None:
        self.name = name
        self.free = FREE[name]
        self.u = np.ascontiguousarray(df[["Ta", "Ps", "Ph"]].to_numpy(float))
        self.y = np.ascontiguousarray(df["yTi"].to_numpy(float))
        steps = np.diff(df["t"].to_numpy(float))
        if np.ptp(steps) > 1e-9:
            raise SystemExit("reference filter needs uniform sampling; inputPRBS1.csv is not")
        self.dt = float(steps[0])  # [h]
        self.p0_chol = np.diag(P0_STD[name])
        self.c = np.zeros(len(P0_STD[name]))
        self.c[0] = 1.0

    def neg_loglike(self, p: dict) -> float:
        a, b, sig = continuous_system(self.name, p)
        ad, bd, qc = discretise_zoh(a, b, sig, self.dt)
        x0 = np.array([p[k] for k in ("Ti0", "Te0", "Th0") if k in p])
        return float(
            _neg_loglike_sqrt(ad, bd, qc, self.c, p["e_std"], x0, self.p0_chol, self.u, self.y)
        )

    # plain scipy BFGS on log-transformed positive parameters, identity for the initial means
    def to_theta(self, p: dict) -> np.ndarray:
        return np.array([p[k] if k.endswith("0") else math.log(p[k]) for k in self.free])

    def from_theta(self, theta: np.ndarray) -> dict:
        return {
            k: float(v) if k.endswith("0") else float(math.exp(min(v, 50.0)))
            for k, v in zip(self.free, theta, strict=True)
        }

    def objective(self, theta: np.ndarray) -> float:
        try:
            value = self.neg_loglike(self.from_theta(theta))
        except (np.linalg.LinAlgError, ValueError, OverflowError):
            return 1e10
        return value if math.isfinite(value) else 1e10

    def fit(self, start: dict) -> tuple[dict, float, bool]:
        res = minimize(self.objective, self.to_theta(start), method="BFGS",
                       options={"gtol": 1e-6, "maxiter": 2000})  # fmt: skip
        return self.from_theta(res.x), -float(res.fun), bool(res.success)


def best_of(fn, repeats: int = REPEATS):
    """(best wall time [s], last result) of ``repeats`` calls after one warm-up call."""
    fn()
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def compare(name: str, df: pd.DataFrame) -> dict:
    from thermocal.statespace import RCModel

    model = RCModel.from_yaml(REPO / "examples" / "models" / f"{name}.yaml")
    ref = Reference(name, df)
    start = {k: model.parameters[k].value for k in ref.free}
    kw = {"time_column": "t", "time_unit": "h"}

    t_tc, res = best_of(lambda: model.fit(df, **kw))
    p_tc = {k: float(res.params[k]) for k in ref.free}
    ref.neg_loglike(start)  # compile the numba filter before timing
    t0 = time.perf_counter()
    p_ref, ll_ref, ok_ref = ref.fit(start)
    t_ref = time.perf_counter() - t0
    # the reference optimiser restarted from thermocal's optimum: does it find a higher point?
    _, ll_polish, _ = ref.fit(p_tc)
    # thermocal again with every estimated parameter's bounds widened (x0.1 / x10 and +-100 C for
    # the initial means), to see whether a bound, not the engine, limits thermocal's optimum
    spec = model.to_dict()
    for k in ref.free:
        q = spec["parameters"][k]
        if k.endswith("0"):
            q["lower"], q["upper"] = -100.0, 100.0
        else:
            if q.get("lower", 0.0) > 0:
                q["lower"] = q["lower"] / 10
            if "upper" in q:
                q["upper"] = q["upper"] * 10
    wide = RCModel.from_dict(spec).fit(df, **kw)

    ll_tc = float(res.loglike)
    ref_at_tc = -ref.neg_loglike(p_tc)
    tc_at_ref = float(model.loglike(df, p_ref, **kw))
    # the filters at identical parameters, at three points: thermocal's optimum, the reference's
    # optimum and the model file's start values
    start_tc = float(model.loglike(df, start, **kw))
    start_ref = -ref.neg_loglike(start)
    return {
        "name": name,
        "n_free": len(ref.free),
        "ll_tc": ll_tc,
        "ll_ref": ll_ref,
        "ref_at_tc": ref_at_tc,
        "tc_at_ref": tc_at_ref,
        "start_tc": start_tc,
        "start_ref": start_ref,
        "t_tc": t_tc,
        "t_ref": t_ref,
        "converged_tc": bool(res.converged),
        "converged_ref": ok_ref,
        "p_tc": p_tc,
        "p_ref": p_ref,
        "ll_polish": ll_polish,
        "ll_wide": float(wide.loglike),
        "p_wide": {k: float(wide.params[k]) for k in ref.free},
        "flags": list(res.flags),
        "units": {k: model.parameters[k].unit for k in ref.free},
    }


def rel(a: float, b: float) -> float:
    return abs(a - b) / max(abs(a), abs(b))


def main() -> int:
    found, message = pysip_status()
    print(f"pySIP check: {message}")
    if not found:
        print(
            "Running the comparison against the independent pySIP-convention reference filter "
            "instead (numpy/scipy/numba only; see the module docstring)."
        )
    else:
        print(
            "Driving LOCIE's pySIP directly is not implemented in this script (it could not be "
            "installed and tested here); running the pySIP-convention reference comparison."
        )
    if not DATA.is_file():
        print(f"data file {DATA} is absent (see ../shared/data/INDEX.md); nothing to compare.")
        return 0
    df = pd.read_csv(DATA, sep=";")

    import numba
    import scipy

    import thermocal

    print(
        f"date {datetime.now(UTC):%Y-%m-%d %H:%M} UTC; machine {platform.machine()}, "
        f"{os.cpu_count()} cores (shared); python {platform.python_version()}, "
        f"numpy {np.__version__}, scipy {scipy.__version__}, numba {numba.__version__}, "
        f"thermocal {getattr(thermocal, '__version__', '?')}"
    )
    rows = [compare(name, df) for name in MODELS]
    print()
    print("| model | free | logL thermocal fit | logL reference fit | ref. logL at thermocal opt. "
          "| thermocal logL at ref. opt. | rel. diff same params | fit s thermocal | "
          "fit s reference |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        d = max(rel(r["ll_tc"], r["ref_at_tc"]), rel(r["tc_at_ref"], r["ll_ref"]),
                rel(r["start_tc"], r["start_ref"]))  # fmt: skip
        print(
            f"| {r['name']} | {r['n_free']} | {r['ll_tc']:.4f} | {r['ll_ref']:.4f} | "
            f"{r['ref_at_tc']:.4f} | {r['tc_at_ref']:.4f} | {d:.1e} | {r['t_tc']:.3f} | "
            f"{r['t_ref']:.3f} |"
        )
    for r in rows:
        print(
            f"\n{r['name']}: reference BFGS restarted from thermocal's optimum reaches logL "
            f"{r['ll_polish']:.4f}; thermocal with bounds widened (x0.1/x10, initial means "
            f"+-100 C) reaches {r['ll_wide']:.4f}; thermocal flags: {r['flags']}"
        )
        print(f"\n{r['name']} (converged: thermocal {r['converged_tc']}, "
              f"reference {r['converged_ref']}); start values: thermocal logL "
              f"{r['start_tc']:.6f}, reference {r['start_ref']:.6f}")  # fmt: skip
        print(
            "| parameter | unit | thermocal | reference (pySIP conventions) | rel. diff "
            "| thermocal, wide bounds |"
        )
        print("|---|---|---|---|---|---|")
        for k in r["p_tc"]:
            a, b, w = r["p_tc"][k], r["p_ref"][k], r["p_wide"][k]
            print(f"| {k} | {r['units'][k]} | {a:.6g} | {b:.6g} | {rel(a, b):.1e} | {w:.6g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
