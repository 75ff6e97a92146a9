"""Post-retrofit verification of an EnergyPlus house (issue 21, evidence beyond the demo).

EnergyPlus 25.2 simulates the generated two-storey house of
``tests/multizone/energyplus_house.py`` (4 heated zones, unheated attic, slab on ground, night
set-back, People/Lights/Equipment, scheduled infiltration, ideal loads; Chicago O'Hare TMY3)
from January 1 to March 31 twice: as it is and with the walls' mineral wool thickened from
12 to 30 cm. The measurements are the first run before the retrofit date and the second after
it (hourly heat of the ideal loads, volume-weighted air temperature, outdoor air temperature,
DNI and DHI of the weather file). The building file is the audit of the house
(:func:`thermocal.retrofit.demo_data.audit_building` of the IDF read by thermocal). Truth:
EnergyPlus' annual heating of both variants over the whole weather year.

Run: ``python benchmarks/verify_energyplus.py [OUT_DIR]`` (EnergyPlus 13 s, verify 6 s).

Status (2026-11-25): the verification does NOT work on this house yet. True annual saving
32.7 % (EnergyPlus 3,858 -> 2,598 kWh), post period 38.7 %; the pre-period calibration puts
every capacity on its upper bound, the HLC at 294 W/K (steady state of the same IDF in
thermocal's multi-zone model: 157 W/K; audit prior 182 W/K) and the baseline fails ASHRAE
Guideline 14 (daily NMBE -160 %, CV(RMSE) 165 %), so the verdict is "inconclusive" and the
normalised saving (88 %) is meaningless. Suspects: the 4 K night set-back of a lightweight
house heated by ideal air loads (the fifth-order model's heating node and lumped masses),
internal gains of the same order as the heating. With ``--constant-20`` (both heating
schedules at 20 C) the baseline meets Guideline 14 (NMBE -5.6 %, CV(RMSE) 16.7 %), the pre HLC
is 175 W/K (159-189) and the prediction 33.3 % against a true 30.1 %, but the baseline
over-predicts the post period (February-March) by about a third: verified 50.8 % (40-61), post
period 51.9 % against a true 34.4 %, and the post calibration is unusable (HLC 458 W/K).
The ground is not the cause: with the fifth-order model's ground temperature replaced by
EnergyPlus' monthly values under the slab (an experiment, monkeypatched) the post HLC becomes
164 W/K (pre 176) but the verified saving stays at 47.4 % (35-56) against 30.1 %: the
baseline calibrated on January over-predicts February-March (more sun, internal gains of
the order of the heating). Kept as the starting point of the EnergyPlus evidence of issue 21.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "multizone"))

RETROFIT_DATE = "02-12"
PERIOD = ("01-08", "03-19")
WALL_OLD = "Material, MINERAL WOOL 120, MediumRough, 0.12, 0.04,"
WALL_NEW = "Material, MINERAL WOOL 120, MediumRough, 0.30, 0.04,"


def run(idf_text: str, folder: Path, weather: Path):
    from thermocal.multizone.energyplus import read_eso, run_energyplus

    folder.mkdir(parents=True, exist_ok=True)
    (folder / "in.idf").write_text(idf_text)
    eso = run_energyplus(folder / "in.idf", weather, folder)
    return read_eso(eso, year=2006)


def constant_heating(idf_text: str, setpoint: float = 20.0) -> str:
    """The IDF with both heating schedules replaced by a constant set point [C]."""
    import re

    for name in ("HEATING DAY ZONES", "HEATING BEDROOMS"):
        idf_text = re.sub(
            rf"Schedule:Compact, {name}, TEMPERATURE,[^;]*;",
            f"Schedule:Compact, {name}, TEMPERATURE, Through: 12/31, For: AllDays, "
            f"Until: 24:00, {setpoint:g};",
            idf_text,
        )
    return idf_text


def main(out: Path, *, setback: bool = True) -> dict:
    from energyplus_house import CONDITIONED, WEATHER_FILE, house_idf

    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import energyplus_weather_folder
    from thermocal.multizone.idf import read_idf
    from thermocal.retrofit.demo_data import audit_building
    from thermocal.retrofit.verify import (
        load_verify_config,
        run_verify,
        write_verify_outputs,
    )

    t0 = time.perf_counter()
    weather = energyplus_weather_folder() / WEATHER_FILE
    out.mkdir(parents=True, exist_ok=True)
    edit = (lambda t: t) if setback else constant_heating
    pre_text = edit(house_idf(run_period=((1, 1), (3, 31))))
    assert WALL_OLD in pre_text
    post_text = pre_text.replace(WALL_OLD, WALL_NEW)
    runs = {
        "pre": run(pre_text, out / "ep-pre", weather),
        "post": run(post_text, out / "ep-post", weather),
        "pre_year": run(edit(house_idf()), out / "ep-pre-year", weather),
        "post_year": run(
            edit(house_idf()).replace(WALL_OLD, WALL_NEW), out / "ep-post-year", weather
        ),
    }
    (out / "pre.idf").write_text(pre_text)
    (out / "post.idf").write_text(post_text)
    mz_pre = read_idf(out / "pre.idf")
    mz_post = read_idf(out / "post.idf")
    building = audit_building(mz_pre, name="EnergyPlus house", floors=2)
    walls_after = audit_building(mz_post, name="x", floors=2)
    u_walls = [c["u_value"] for c in walls_after["components"] if c["type"] == "external_wall"]
    u_new = float(np.median(u_walls))

    def heat(frame):
        cols = [
            f"{z} IDEAL LOADS:Zone Ideal Loads Zone Sensible Heating Energy [J]"
            for z in CONDITIONED
        ]
        return frame[cols].sum(axis=1) / 3.6e6  # kWh per hour

    volumes = np.array([mz_pre.zones[z].volume for z in CONDITIONED])
    w = volumes / volumes.sum()

    def measurements(frame):
        ti = frame[[f"{z}:Zone Mean Air Temperature [C]" for z in CONDITIONED]].to_numpy() @ w
        te = frame["Environment:Site Outdoor Air Drybulb Temperature [C]"]
        # People, Lights and Equipment: their sensible heat as an electricity meter would
        # see it (kWh per hour), so the model gets them as internal gains
        gains = sum(
            frame[f"{z}:Zone Total Internal {kind} Heating Energy [J]"]
            for z in CONDITIONED for kind in ("Convective", "Radiant")
        ) / 3.6e6  # fmt: skip
        return pd.DataFrame({"time": frame.index, "Te": te.to_numpy(), "heat_kWh":
                             heat(frame).to_numpy(), "Ti": ti, "el_kWh": gains.to_numpy()},
                            index=frame.index)  # fmt: skip

    wx, _ = read_weather(weather)
    wx = wx.copy()
    wx.index = wx.index.tz_localize(None).map(lambda t: t.replace(year=2006))
    date = pd.Timestamp(f"2006-{RETROFIT_DATE}")
    start, end = pd.Timestamp(f"2006-{PERIOD[0]}"), pd.Timestamp(f"2006-{PERIOD[1]}")
    pre, post = measurements(runs["pre"]), measurements(runs["post"])
    meas = pd.concat([pre[pre.index < date], post[post.index >= date]])
    meas = meas[(meas.index >= start) & (meas.index < end)]
    # irradiance of the weather file's hour (labelled by its end in EPW: interval start here)
    irr = wx[["dni", "dhi"]].copy()
    irr.index = irr.index - pd.Timedelta(hours=1)
    meas["DNI"] = irr["dni"].reindex(meas.index).to_numpy()
    meas["DHI"] = irr["dhi"].reindex(meas.index).to_numpy()
    meas["time"] = meas.index.strftime("%Y-%m-%d %H:%M")
    data = out / "data"
    data.mkdir(exist_ok=True)
    meas.to_csv(data / "measurements.csv", index=False)
    (data / "building.yaml").write_text(yaml.safe_dump(building, sort_keys=False))
    annual = {k: float(heat(runs[k]).sum()) for k in ("pre_year", "post_year")}
    post_b = heat(runs["pre"])[(runs["pre"].index >= date) & (runs["pre"].index < end)].sum()
    post_a = heat(runs["post"])[(runs["post"].index >= date) & (runs["post"].index < end)].sum()
    truth = {
        "annual_heating_kWh": annual,
        "annual_saving_pct": 100.0 * (1.0 - annual["post_year"] / annual["pre_year"]),
        "post_period_saving_pct": 100.0 * (1.0 - post_a / post_b),
        "walls_u_after": u_new,
    }
    cfg = {
        "building": "building.yaml",
        "measurements": {
            "file": "measurements.csv", "time_column": "time", "heat_source": "heat_meter",
            "heat_unit": "kWh",
            "columns": {"temp_out": "Te", "heat": "heat_kWh", "dni": "DNI", "dhi": "DHI",
                        "temp_in": "Ti", "electricity": "el_kWh"},
        },
        "internal_gains": {"source": "electricity", "electricity_unit": "kWh"},
        "weather": {"file": str(weather)},
        # wider capacity ranges than the building-file defaults (as the retrofit demo): with
        # the defaults C_im's estimate lands on its upper bound and the group-correction step
        # of the calibration stops ("initial value outside its bounds")
        "model": {"bounds": {"C_im": [1.6, 300.0], "C_env": [6.0, 300.0], "C_i": [0.75, 30.0],
                            "C_gf": [1.6, 300.0]},
                  # ideal loads heat the air directly: no heating-system capacity to estimate
                  "fixed": {"C_h": 0.1}},
        "measures": {"walls": u_new},
        "verify": {"retrofit_date": f"2006-{RETROFIT_DATE}",
                   "prediction": {"measures": ["walls"]}},
    }  # fmt: skip
    (data / "config.yaml").write_text(yaml.safe_dump(cfg, sort_keys=False))
    t1 = time.perf_counter()
    ver = run_verify(load_verify_config(data / "config.yaml"))
    results = write_verify_outputs(ver, out / "verify")
    summary = {
        "truth": truth,
        "verified_saving_pct": results["comparison"]["measured_saving_pct"],
        "predicted_saving_pct": results["comparison"]["predicted_saving_pct"]["value"],
        "avoided_post_period_pct": results["avoided_energy"]["saving_pct"],
        "with_take_back_pct": results["avoided_energy"]["saving_with_take_back_pct"],
        "physical_saving_pct": results["physical_change"]["saving_pct"],
        "baseline_nmbe_pct": results["avoided_energy"]["baseline_nmbe_pct"],
        "baseline_cv_rmse_pct": results["avoided_energy"]["baseline_cv_rmse_pct"],
        "hlc": results["physical_change"]["heat_loss_coefficient_W_per_K"],
        "verdict": results["verdict"],
        "energyplus_s": t1 - t0,
        "verify_s": time.perf_counter() - t1,
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    folder = Path(args[0]) if args else Path("verify-energyplus")
    print(json.dumps(main(folder, setback="--constant-20" not in sys.argv), indent=2))
