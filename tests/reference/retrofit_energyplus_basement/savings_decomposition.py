"""Where the retrofit analysis's savings differ from EnergyPlus's on the basement house (issue 25).

For the baseline and four strategies (walls, windows, walls + windows, all four), the annual
heating ``Q`` at 22.2 C (Zurich 2015) with the house's internal gains and sun, and ``L`` without
either (the long-wave loss to the sky kept), in EnergyPlus 25.2 (``house_v25.idf`` with the
measures' layers, as ``make_reference.py`` adds them) and in the calibrated RC model of the
default analysis (:func:`thermocal.retrofit.balance.heat_balance` with the estimate). With ``U = L
- Q`` the gains used, a saving is exactly ``s = (dL / L0) (L0 / Q0) - dU / Q0``, so the model's
error splits into three terms that add up:

- (a) conductance share: ``(dL/L0 model - dL/L0 EnergyPlus) L0/Q0 EnergyPlus``, what the
  measure removes of the loss;
- (b) utilisation: ``-(dU/Q0 model - dU/Q0 EnergyPlus)``, how the gains used change;
- (c) baseline: ``dL/L0 model (L0/Q0 model - L0/Q0 EnergyPlus)``, how much of the loss the gains
  cover before the measure.

The model's balance leaves out the air change's temperature slope, so its savings here differ
from the report's by 0.2 pp or less. Writes ``savings_decomposition.json`` beside this script.
Run (about 5 minutes on 2 cores)::

    python tests/reference/retrofit_energyplus_basement/savings_decomposition.py \
        /work/shared/data/weather_switzerland/Zuerich-SMA_2015.epw
"""

from __future__ import annotations

import json
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import make_reference as reference  # noqa: E402

STRATEGIES = {
    "baseline": frozenset(),
    "1b walls": frozenset({"walls"}),
    "1c windows": frozenset({"windows"}),
    "2d walls + windows": frozenset({"walls", "windows"}),
    "4 all four": frozenset({"attic_ceiling", "walls", "windows", "cellar_ceiling"}),
}
#: EPW fields of the sun (radiation and illuminance), zeroed for the runs without it
SUN_FIELDS = (10, 11, 13, 14, 15, 16, 17, 18)


def dark_weather(weather: Path, out: Path) -> Path:
    """The EPW file with its solar radiation and illuminance set to zero."""
    lines = weather.read_text().splitlines()
    body = []
    for line in lines[8:]:
        fields = line.split(",")
        for i in SUN_FIELDS:
            fields[i] = "0"
        body.append(",".join(fields))
    out.write_text("\n".join(lines[:8] + body) + "\n")
    return out


def energyplus_heating(weather: Path, work: Path) -> dict:
    """Annual heating [kWh] per strategy, with gains and sun (``Q``) and without (``L``)."""
    from thermocal.multizone.idf.parse import parse_idf

    objects = parse_idf((HERE / "house_v25.idf").read_text(), source="house_v25.idf")
    u_nominal = reference.nominal_u_values(objects)
    dark = dark_weather(weather, work / "dark.epw")

    def idf(measures, gains: bool) -> str:
        pairs = [(o.class_name, list(o.fields)) for o in objects
                 if gains or o.key not in reference.GAIN_CLASSES]  # fmt: skip
        pairs = reference.with_measures(pairs, measures, u_nominal)
        return "".join(reference._text(c, f) for c, f in pairs)

    jobs = {}
    for name, measures in STRATEGIES.items():
        jobs[(name, "Q")] = (idf(measures, True), weather)
        jobs[(name, "L")] = (idf(measures, False), dark)
    out: dict = {name: {} for name in STRATEGIES}
    with ThreadPoolExecutor(2) as pool:
        futures = {
            key: pool.submit(reference.house1._run, text, w, work / _folder(*key))
            for key, (text, w) in jobs.items()
        }
        for (name, kind), future in futures.items():
            frame = future.result()
            heat = reference.house1._col(frame, "Zone Ideal Loads Zone Sensible Heating Rate")
            out[name][kind] = float(heat.sum()) / 1000.0
    return out


def _folder(name: str, kind: str) -> str:
    return f"{name}_{kind}".replace(" ", "_").replace("+", "and")


def model_heating(weather: Path, work: Path) -> dict:
    """The same for the calibrated RC model of the default analysis [kWh]."""
    from thermocal.retrofit.balance import heat_balance
    from thermocal.retrofit.config import load_config
    from thermocal.retrofit.model import ESTIMATED_PARAMETERS
    from thermocal.retrofit.workflow import run_retrofit

    config = yaml.safe_load((HERE / "config.yaml").read_text())
    config["building"] = str(HERE / "building.yaml")
    config["measurements"]["file"] = str(HERE / "measurements.csv")
    config["weather"]["file"] = str(weather)
    path = work / "config.yaml"
    path.write_text(yaml.safe_dump(config, sort_keys=False))
    analysis = run_retrofit(load_config(path))
    draws = analysis.draws or analysis.calibration.estimates_si
    params = {k: float(np.atleast_1d(draws[k])[0]) for k in ESTIMATED_PARAMETERS}
    inputs = analysis.year_inputs
    dark = inputs.copy()
    dark["phi_sol"] = 0.0
    night = inputs["phi_sol"].to_numpy() <= 0
    for column in ("phi_abs_roof", "phi_abs_walls"):  # the long-wave loss to the sky alone
        dark[column] = float(np.median(inputs[column].to_numpy()[night]))
    out = {}
    for name, measures in STRATEGIES.items():
        (i,) = [j for j, s in enumerate(analysis.strategies) if frozenset(s.measures) == measures]
        envelope = analysis.envelopes[i]
        envelope = envelope[0] if isinstance(envelope, list | tuple) else envelope
        gains = analysis.year_gains
        full = heat_balance(analysis.model, params, envelope, inputs, analysis.indoor_profile,
                            gains=gains)  # fmt: skip
        bare = heat_balance(analysis.model, params, envelope, dark, analysis.indoor_profile,
                            gains=np.zeros_like(gains))  # fmt: skip
        out[name] = {"Q": float(full["heating"].sum()), "L": float(bare["heating"].sum())}
    return out


def decomposition(ep: dict, model: dict) -> list[dict]:
    """The saving error's three terms per strategy [percentage points]."""
    q0e, l0e = ep["baseline"]["Q"], ep["baseline"]["L"]
    q0m, l0m = model["baseline"]["Q"], model["baseline"]["L"]
    rows = []
    for name in list(STRATEGIES)[1:]:
        qe, le = ep[name]["Q"], ep[name]["L"]
        qm, lm = model[name]["Q"], model[name]["L"]
        dle, dlm = l0e - le, l0m - lm
        due, dum = (l0e - q0e) - (le - qe), (l0m - q0m) - (lm - qm)
        se, sm = 100 * (1 - qe / q0e), 100 * (1 - qm / q0m)
        rows.append({
            "strategy": name,
            "removed_loss_energyplus_pct": 100 * dle / l0e,
            "removed_loss_model_pct": 100 * dlm / l0m,
            "saving_energyplus_pct": se,
            "saving_model_pct": sm,
            "difference_pp": sm - se,
            "a_conductance_pp": 100 * (dlm / l0m - dle / l0e) * l0e / q0e,
            "b_utilisation_pp": -100 * (dum / q0m - due / q0e),
            "c_baseline_pp": 100 * (dlm / l0m) * (l0m / q0m - l0e / q0e),
        })  # fmt: skip
    return rows


def main(weather: str) -> None:
    with tempfile.TemporaryDirectory(prefix="savings_decomposition_") as folder:
        work = Path(folder)
        ep = energyplus_heating(Path(weather), work)
        model = model_heating(Path(weather), work)
    result = {"energyplus_kWh": ep, "model_kWh": model, "rows": decomposition(ep, model)}
    (HERE / "savings_decomposition.json").write_text(json.dumps(result, indent=1) + "\n")
    for row in result["rows"]:
        print({k: round(v, 2) if isinstance(v, float) else v for k, v in row.items()})


if __name__ == "__main__":
    main(sys.argv[1])
