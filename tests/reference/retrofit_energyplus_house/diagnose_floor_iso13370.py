"""The first twin's floor with ISO 13370's monthly method instead of the ground wave at 2 m
(docs/retrofit-twins.md, "The floor with ISO 13370's periodic coefficients", issue 25).

thermocal couples the slab through the ISO 13370 steady conductance to the undisturbed ground
temperature at 2 m (Kusuda's wave). Its floor therefore follows the indoor temperature's annual
swing with the steady coefficient ``H_g`` and no phase. ISO 13370's monthly method (Annex C)
gives that swing its own coefficient ``H_pi`` (Annex H, H.2) and a time lead ``alpha``, and the
outdoor swing ``H_pe`` (H.3) with a lag ``beta``; a dynamic model meets it through the virtual
ground temperature ``theta_vi,m = Ti_m - Phi_m / (A U)`` (Annex F, F.2).

This script runs the twin's retrofit analysis (the test's configuration) with the demand year's
ground temperature replaced by that virtual temperature, the calibration left as it is (its
training weeks keep the 2 m wave), and iterates on the demand year's monthly indoor temperature
(the heating-only controller lets it float to 31 C in July):

- ``iso``: ``H_pi``, ``alpha = 0``, ``H_pe``, ``beta = 1`` month (ISO 52016-1's values);
- ``hg``: the same with the internal term as thermocal has it implicitly (``H_g``, no lead), so
  ``iso - hg`` is the effect of ``H_pi`` alone;
- ``lead1``: ``iso`` with ``alpha = 1`` month (a sensitivity; a semi-infinite ground's flow
  leads its surface temperature by 1.5 months).

    python tests/reference/retrofit_energyplus_house/diagnose_floor_iso13370.py OUT_DIR

About 15-30 s per run, three runs per variant. Prints per variant the floor path by month, the
demand and the savings against ``reference.json`` and EnergyPlus's ``balance.json``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
TESTS = HERE.parents[1]
sys.path[:0] = [str(TESTS), str(TESTS / "retrofit")]

import test_retrofit_energyplus_twin as twin  # noqa: E402

import thermocal.retrofit.workflow as wf  # noqa: E402
from thermocal.io.envelope import read_envelope  # noqa: E402
from thermocal.physics import ground  # noqa: E402
from thermocal.retrofit.model import R_SE, R_SI  # noqa: E402

HEATING_SEASON = [9, 10, 11, 0, 1, 2, 3]  # October to April (0-based months)
VARIANTS = {"iso": (True, 0), "hg": (False, 0), "lead1": (True, 1)}


def slab_coefficients() -> dict[str, float]:
    """``H_g = A U`` (ISO 13370 9.1), ``H_pi``, ``H_pe`` of the first twin's slab [W/K]."""
    building = read_envelope(HERE / "building.yaml")
    slab = [c for c in building.components if c.type == "ground_floor"]
    area = sum(float(c.area) for c in slab)
    u_slab = sum(float(c.area) * float(c.u_value) for c in slab) / area
    r_f = max(1.0 / u_slab - R_SI["downward"] - R_SE, 0.0)
    g = building.ground
    lam = float(g.soil_conductivity)
    kw = {"wall_thickness": float(g.wall_thickness), "floor_resistance": r_f,
          "soil_conductivity": lam}  # fmt: skip
    h_g = area * ground.iso13370_slab_on_ground(area, float(g.perimeter), **kw)
    periodic = ground.iso13370_slab_periodic_coefficients(area, float(g.perimeter), **kw)
    return {"h_g": float(h_g), **periodic}


def run(out: Path, ti_monthly, *, with_h_pi: bool, lead: int) -> dict:
    """The twin with the demand year's Tgr = ISO 13370's virtual ground temperature."""
    c = slab_coefficients()
    original = wf.model_inputs

    def patched(frame, *args, **kwargs):
        res = original(frame, *args, **kwargs)
        step = (res.index[1] - res.index[0]).total_seconds()
        if len(res) * step > 300 * 86400:  # the demand year, not the measurements
            te = res["Te"].groupby(res.index.month).mean().to_numpy()
            h_pi = c["h_pi"] if with_h_pi else c["h_g"]
            phi = ground.iso13370_monthly_heat_flow(
                c["h_g"], h_pi, c["h_pe"], ti_monthly, te, lead_months=lead, lag_months=1
            )
            theta = ground.virtual_ground_temperature(ti_monthly, phi, c["h_g"])
            res["Tgr"] = theta[res.index.month - 1]
        return res

    wf.model_inputs = patched
    try:
        out.mkdir(parents=True, exist_ok=True)
        return twin._run_twin(out)
    finally:
        wf.model_inputs = original


def summary(results: dict) -> dict:
    """Floor by month, demand and savings against EnergyPlus."""
    ref = twin._reference()["saving_pct"]
    floor = np.asarray(results["heat_balance_kWh"]["monthly"]["floor"], float)
    diff = np.array([s["saving_pct"] - ref[twin._key(s["measures"])]
                     for s in results["scenarios"] if s["measures"]])  # fmt: skip
    return {
        "demand_kWh": round(results["annual_heating_demand_kWh"]["value"]),
        "floor_monthly_kWh": floor.round().astype(int).tolist(),
        "floor_oct_apr_kWh": round(float(floor[HEATING_SEASON].sum())),
        "savings_pct": {s["code"]: round(s["saving_pct"], 1) for s in results["scenarios"]},
        "savings_within_3pp": int((np.abs(diff) <= 3.0).sum()),
        "savings_mean_abs_pp": round(float(np.abs(diff).mean()), 2),
        "ti_monthly_C": np.round(results["heat_balance_kWh"]["monthly_mean_Ti_C"], 1).tolist(),
    }


def main(out: Path) -> None:
    print("slab coefficients [W/K, m]:", {k: round(v, 2) for k, v in slab_coefficients().items()})
    (out / "base").mkdir(parents=True, exist_ok=True)
    base = twin._run_twin(out / "base")
    report = {"base": summary(base)}
    for name, (with_h_pi, lead) in VARIANTS.items():
        ti = base["heat_balance_kWh"]["monthly_mean_Ti_C"]
        for i in range(3):  # fixed point on the demand year's monthly indoor temperature
            res = run(out / f"{name}{i}", ti, with_h_pi=with_h_pi, lead=lead)
            ti = res["heat_balance_kWh"]["monthly_mean_Ti_C"]
        report[name] = summary(res)
    report["energyplus_floor_monthly_kWh"] = [
        -round(v) for v in json.loads((HERE / "balance.json").read_text())
        ["monthly_kWh"]["Living:Floor"]
    ]  # fmt: skip
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main(Path(sys.argv[1]))
