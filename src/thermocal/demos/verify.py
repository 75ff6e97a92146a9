"""The verify demo: the multi-zone demo house retrofitted (roof + walls) at a known date, for
``thermocal verify --demo`` (post-retrofit verification, :mod:`thermocal.retrofit.verify`).

Regenerate the shipped data (``src/thermocal/data/verify_demo``)::

    python -m thermocal.demos.verify
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

# ------------------------------------------------------------------------------------------
# the demo: the multi-zone house, retrofitted (roof + walls) at a known date
# ------------------------------------------------------------------------------------------
#: Measured period (MM-DD of the weather file's year) and retrofit date of the demo.
DEMO_PERIOD = ("01-29", "03-12")
DEMO_RETROFIT_DATE = "02-19"
#: Strategy the demo carries out: roof + walls (code 2a of the method's 16).
DEMO_STRATEGY = ("2a", ("roof", "walls"))
#: Package folder of the shipped verify demo data (``python -m thermocal.demos.verify``).
SHIPPED_VERIFY_DATA = Path(__file__).resolve().parents[1] / "data" / "verify_demo"


def generate_verify_demo_data(seed: int = 2019) -> dict:
    """Measurements of the demo house with roof and walls retrofitted at a known date.

    The multi-zone generator of :mod:`thermocal.demos.retrofit` simulates the house twice
    over the same weather, controls and sensor noise: as it was and with the measures (the
    Table 1 U-values of the fifth-order RC method, radiators unchanged). The measurements are
    the first run before the retrofit date and the second after it; the first run after the
    date is the counterfactual (the heat the house would have used), so the true avoided
    energy of the post period is known. The true annual saving is the generator's ideal
    heating at 20 C over the whole weather year (the retrofit demo's truth, strategy 2a).

    Returns
    -------
    dict with ``measurements`` (DataFrame), ``building`` (mapping, the house before the
    retrofit), ``truth`` (dict).
    """
    from thermocal.demos.retrofit import SHIPPED_DATA, generate_demo_data
    from thermocal.retrofit.strategies import PAPER_MEASURE_U_VALUES

    code, names = DEMO_STRATEGY
    measures = {m: PAPER_MEASURE_U_VALUES[m] for m in names}
    before = generate_demo_data(period=DEMO_PERIOD, annual=False, seed=seed)
    after = generate_demo_data(period=DEMO_PERIOD, annual=False, seed=seed, measures=measures)
    mb, ma = before["measurements"], after["measurements"]
    year = pd.Timestamp(mb["time"].iloc[0]).year
    date = pd.Timestamp(f"{year}-{DEMO_RETROFIT_DATE}")
    meas = pd.concat([mb[mb["time"] < date], ma[ma["time"] >= date]], ignore_index=True)

    def heat(frame):  # [kWh] the sensors' heat, the way the verification reads it
        from thermocal.physics.hydronics import heating_power

        q = heating_power(
            frame["V_dot"].to_numpy(float) / 3.6e6, frame["T_supply"].to_numpy(float),
            frame["T_return"].to_numpy(float),
        )  # fmt: skip
        return float(np.nansum(q) / 1000.0)

    post_b, post_a = mb[mb["time"] >= date], ma[ma["time"] >= date]
    annual = json.loads((SHIPPED_DATA / "truth.json").read_text())["annual_heating_demand_20C_kWh"]
    truth = {
        "strategy": code,
        "measures": measures,
        "retrofit_date": str(date.date()),
        "heat_loss_coefficient_W_per_K": {
            "pre": before["truth"]["heat_loss_coefficient_W_per_K"],
            "post": after["truth"]["heat_loss_coefficient_W_per_K"],
        },
        "post_period_heat_kWh": {"without_retrofit": heat(post_b), "measured": heat(post_a)},
        "post_period_saving_pct": 100.0 * (1.0 - heat(post_a) / heat(post_b)),
        "annual_heating_demand_20C_kWh": {"0": annual["0"], code: annual[code]},
        "annual_saving_pct": 100.0 * (1.0 - annual[code] / annual["0"]),
        "note": "generator: thermocal.multizone single_family_house with radiator loop "
        "(thermocal.demos.retrofit), run twice (as it was / retrofitted) over the same "
        "weather and sensor noise; annual: ideal heating at 20 C over the weather year",
        "weather_file": before["truth"]["weather_file"],
        "seed": seed,
    }
    return {"measurements": meas, "building": before["building"], "truth": truth}


def write_verify_demo_data(data: dict, folder: Path | str) -> Path:
    """Write measurements.csv, building.yaml and truth.json of the verify demo."""
    from thermocal.demos.retrofit import write_demo_data

    return write_demo_data(data, folder)


def verify_demo_config(data_dir: Path | str = SHIPPED_VERIFY_DATA, draws: int = 200) -> dict:
    """The verification configuration of the demo (paths relative to its data folder)."""
    from thermocal.demos.retrofit import DEMO_MODEL_OPTIONS, demo_config

    data_dir = Path(data_dir)
    cfg = demo_config(data_dir, "pvlib:723170TYA.CSV", draws=draws)
    for key in ("periods", "reference"):
        cfg.pop(key, None)
    cfg["model"] = dict(DEMO_MODEL_OPTIONS)
    cfg["demand"] = {"indoor_profile": 20.0}  # the generator's truth: ideal heating at 20 C
    code, names = DEMO_STRATEGY
    cfg["verify"] = {
        "retrofit_date": json.loads((data_dir / "truth.json").read_text())["retrofit_date"],
        "prediction": {"measures": list(names)},
    }
    return cfg


def prepare_verify_demo(out: Path | str, *, regenerate: bool = False, draws: int = 200):
    """Put the verify demo's data and configuration into ``out/data``.

    Returns
    -------
    config_path, truth (dict)
    """
    import shutil

    import yaml

    data_dir = Path(out) / "data"
    data_dir.mkdir(parents=True, exist_ok=True)
    if regenerate or not (SHIPPED_VERIFY_DATA / "measurements.csv").is_file():
        write_verify_demo_data(generate_verify_demo_data(), data_dir)
    else:
        for name in ("measurements.csv", "building.yaml", "truth.json"):
            shutil.copyfile(SHIPPED_VERIFY_DATA / name, data_dir / name)
    truth = json.loads((data_dir / "truth.json").read_text())
    cfg = verify_demo_config(data_dir, draws)
    cfg["verify"]["retrofit_date"] = truth["retrofit_date"]
    path = data_dir / "config.yaml"
    path.write_text(
        "# thermocal verify demo: the multi-zone house, roof + walls retrofitted on "
        f"{truth['retrofit_date']}.\n"
        "# No prediction file: the prediction is the fifth-order RC method's, from the\n"
        "# pre-retrofit calibration (verify.prediction.measures).\n"
        + yaml.safe_dump(cfg, sort_keys=False)
    )
    return path, truth


def main() -> None:  # pragma: no cover - the script that made the shipped data
    """Regenerate the shipped verify demo data: ``python -m thermocal.demos.verify``."""
    write_verify_demo_data(generate_verify_demo_data(), SHIPPED_VERIFY_DATA)
    print(f"verify demo data written to {SHIPPED_VERIFY_DATA}")


if __name__ == "__main__":  # pragma: no cover
    main()
