"""Post-retrofit verification of an EnergyPlus house (issue 21, evidence beyond the demo).

The measurements are those of ``tests/reference/verify_energyplus_house/make_reference.py``:
EnergyPlus 25.2 runs the generated two-storey house of ``tests/multizone/energyplus_house.py``
as it is and with the walls' mineral wool thickened from 12 to 30 cm (January 8 to March 18,
retrofit February 12, Chicago O'Hare TMY3), at a constant 20 C (``constant_20``) and with the
house's own 4 K night set-back (``setback``). This script verifies both with the full 200
draws and prints the verified against the true savings.

Run: ``python benchmarks/verify_energyplus.py [--regenerate [WORK_DIR]]`` (verify about 15 s
per variant; ``--regenerate`` re-runs EnergyPlus first, about a minute, and rewrites the
committed reference files).

Measured 2026-11-25 (docs/verify.md, "EnergyPlus house"):

=========== ============= ============================ ========== ==============
variant     true annual   verified (90 % interval)     baseline   verdict
=========== ============= ============================ ========== ==============
constant_20 30.1 %        29.4 % (21.4-36.0)           meets G14  delivered
setback     32.7 %        40.9 % (33.5-47.8)           NMBE 11 %  inconclusive
=========== ============= ============================ ========== ==============
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
REF = ROOT / "tests" / "reference" / "verify_energyplus_house"


def verify(variant: str, draws: int = 200) -> dict:
    """Verify one committed variant; the verified and the true numbers."""
    from thermocal.multizone.energyplus import energyplus_weather_folder
    from thermocal.retrofit.verify import parse_verify_config, run_verify

    ref = REF / variant
    cfg = yaml.safe_load((ref / "config.yaml").read_text())
    cfg["weather"]["file"] = str(energyplus_weather_folder() / cfg["weather"]["file"])
    cfg["uncertainty"] = {"draws": draws}
    t0 = time.perf_counter()
    ver = run_verify(parse_verify_config(cfg, base_dir=ref, source=str(ref / "config.yaml")))
    truth = json.loads((ref / "truth.json").read_text())
    av = ver.avoided
    return {
        "truth": {k: truth[k] for k in ("annual_saving_pct", "post_period_saving_pct")},
        "true_post_period_baseline_kWh": truth["post_period_heating_kWh"]["without_retrofit"],
        "verified_saving_pct": av["normalised_saving_pct"],
        "avoided_post_period_pct": [av["saving_pct"], av["saving_pct_lo"], av["saving_pct_hi"]],
        "baseline_kWh": av["baseline_kWh"],
        "calibration": av["calibration"],
        "indoor_control": av["indoor_control"],
        "adjustment": av["adjustment"],
        "baseline_nmbe_pct": av["baseline_nmbe_pct"],
        "baseline_cv_rmse_pct": av["baseline_cv_rmse_pct"],
        "predicted_saving_pct": ver.comparison["predicted_saving_pct"]["value"],
        "hlc_W_per_K": {
            k: v["value"] for k, v in ver.physical["heat_loss_coefficient_W_per_K"].items()
        },
        "verdict": ver.comparison["verdict"],
        "verify_s": time.perf_counter() - t0,
    }


def main() -> None:
    if "--regenerate" in sys.argv:
        sys.path.insert(0, str(REF))
        import make_reference  # noqa: PLC0415

        rest = [a for a in sys.argv[1:] if not a.startswith("--")]
        make_reference.main(*rest)
    out = {v: verify(v) for v in ("constant_20", "setback")}
    print(json.dumps(out, indent=2, default=float))


if __name__ == "__main__":
    main()
