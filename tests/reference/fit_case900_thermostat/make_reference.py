"""EnergyPlus 25.2 data of ASHRAE 140 Case 600 / 900 for thermocal fit / select, and the truth.

Written by an exploratory test (2026-12-01); the committed fixture is
``python make_reference.py 900 thermo winter 28`` (data_900_thermo_winter_28d_1h.csv, gzipped as
case900_thermostat_january_1h.csv.gz: Case 900 with heavy constructions, ideal-loads heating at
20 C, Denver TMY3, 4 January weeks, hourly means of the 10-min run) and
``python make_reference.py truth 900 3.8`` (truth.json: the heat loss coefficient from steady
EnergyPlus runs, dQ/dTa at a room of 20 C and a wind of 3.8 m/s: 87.4 W/K).

python make_reference.py CASE MODE SEASON DAYS   (600|900, prbs|thermo|ff, winter|shoulder)
python make_reference.py truth CASE WIND
Outputs go to this script's folder (runs/ holds EnergyPlus' files: not committed).
"""

import json
import os
import re
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.multizone.energyplus import read_eso, run_energyplus

HERE = Path(__file__).resolve().parent
_DATA = Path(os.environ.get("THERMOCAL_SHARED_DATA", HERE.parents[3] / "shared" / "data"))
SRC = _DATA / "energyplus_reference"
EPW = _DATA / "ashrae140_bestest" / "725650TYCST.epw"
STEPS = 6


def objects(text):
    lines = [l.split("!", 1)[0] for l in text.splitlines()]
    return [o.strip() for o in "\n".join(lines).split(";") if o.strip()]


def cls(o):
    return o.split(",", 1)[0].strip().lower()


def fields(o):
    return [f.strip() for f in o.split(",")]


HEAVY = """
Material, HW WOOD SIDING, Rough, 0.009, 0.14, 530, 900, 0.9, 0.6, 0.6;
Material, HW FOAM INSULATION, Rough, 0.0615, 0.04, 10, 1400, 0.9, 0.6, 0.6;
Material, HW CONCRETE BLOCK, Rough, 0.100, 0.51, 1400, 1000, 0.9, 0.6, 0.6;
Material, HW CONCRETE SLAB, Rough, 0.080, 1.13, 1400, 1000, 0.9, 0.6, 0.6;
"""


def build_idf(case, mode, month, day, days, cool=60.0, extra=""):
    base = SRC / (
        "case_600_v25.idf" if mode == "thermo" or mode == "truth" else "case_600FF_v25.idf"
    )
    out = []
    for o in objects(base.read_text()):
        k = cls(o)
        f = fields(o)
        if k == "runperiod":
            f[2:8] = [str(month), str(day), "2009", "12", "31", "2009"]
            # end date computed below
            end = pd.Timestamp(2009, month, day) + pd.Timedelta(days=days - 1)
            f[5], f[6] = str(end.month), str(end.day)
            f[8] = ""  # day of week from the year
            o = ",\n ".join(f)
        elif k == "timestep":
            o = f"Timestep, {STEPS}"
        elif k in (
            "output:variable",
            "output:meter",
            "output:table:summaryreports",
            "outputcontrol:table:style",
        ):
            continue
        elif k == "construction" and case == "900" and f[1].upper() == "LTWALL":
            o = "Construction, LTWALL, HW WOOD SIDING, HW FOAM INSULATION, HW CONCRETE BLOCK"
        elif k == "construction" and case == "900" and f[1].upper() == "LTFLOOR":
            o = "Construction, LTFLOOR, R-25 INSULATION, HW CONCRETE SLAB"
        elif k == "thermostatsetpoint:dualsetpoint":
            o = f"ThermostatSetpoint:DualSetpoint, {f[1]}, HEATSP, COOL60"
        out.append(o)
    text = ";\n\n".join(out) + ";\n"
    if case == "900":
        text += HEAVY
    text += f"\nSchedule:Constant, COOL60, , {cool};\n"
    for var in (
        "Zone Mean Air Temperature",
        "Site Outdoor Air Drybulb Temperature",
        "Zone Ideal Loads Zone Sensible Heating Rate",
        "Zone Ideal Loads Zone Sensible Cooling Rate",
        "Other Equipment Total Heating Rate",
        "Surface Outside Face Incident Solar Radiation Rate per Area",
        "Site Wind Speed",
        "Zone Windows Total Transmitted Solar Radiation Rate",
    ):
        text += f"\nOutput:Variable, *, {var}, Timestep;\n"
    return text + extra


def prbs(n_steps, seed, hold_steps=STEPS):
    np.random.default_rng(seed)
    # maximum-length LFSR of order 7 (x^7 + x^6 + 1), each bit held hold_steps
    reg = [1] * 7
    bits = []
    while len(bits) * hold_steps < n_steps:
        new = reg[6] ^ reg[5]
        bits.append(reg[6])
        reg = [new] + reg[:6]
    u = np.repeat(bits, hold_steps)[:n_steps].astype(float)
    return u


def gen(case, mode, season, days, power=2000.0, tag=""):
    month, day = (1, 4) if season == "winter" else (4, 1)
    extra = ""
    if mode == "thermo":
        extra += "\nSchedule:Constant, HEATSP, , 20.0;\n"
    if mode == "prbs":
        n = 8760 * STEPS
        u = prbs(n, 1)
        csv = HERE / f"prbs_sched{tag}.csv"
        np.savetxt(csv, u, fmt="%.0f")
        extra += f"""
Schedule:File, HEATER SCHED, , {csv}, 1, 0, 8760, Comma, No, {60 // STEPS};
OtherEquipment, PRBS HEATER, None, ZONE ONE, HEATER SCHED, EquipmentLevel, {power}, , , 0, 0.3, 0;
"""
    name = f"{case}_{mode}_{season}_{days}d{tag}"
    d = HERE / "runs" / name
    d.mkdir(parents=True, exist_ok=True)
    (d / "in.idf").write_text(build_idf(case, mode, month, day, days, extra=extra))
    eso = run_energyplus(d / "in.idf", EPW, d)
    df = read_eso(eso, frequency="timestep")

    def col(pat):
        return [c for c in df.columns if re.search(pat, c, re.I)]

    Ti_end = df[col(r"ZONE ONE:Zone Mean Air Temperature")[0]]
    Ta = df[col("Outdoor Air Drybulb")[0]]
    ph = pd.Series(200.0, index=df.index)  # the case's constant internal gain (known, logged)
    if mode == "thermo":
        ph = ph + df[col("Sensible Heating Rate")[0]]
        ph = ph - df[col("Sensible Cooling Rate")[0]]
    if mode == "prbs":
        ph = ph + df[col("PRBS HEATER:Other Equipment Total Heating Rate")[0]]
    ghi = df[col("ZONE SURFACE ROOF:Surface Outside Face Incident Solar")[0]]
    gv = df[col("ZONE SUBSURFACE 1:Surface Outside Face Incident Solar")[0]]
    wind = df[col("Wind Speed")[0]]
    # inputs labelled by interval start (zoh); Ti at the START of each interval = end of previous
    out = pd.DataFrame(
        {"Ta": Ta, "Ph": ph / 1000.0, "Ps": ghi / 1000.0, "Psv": gv / 1000.0, "wind": wind}
    )
    out["yTi"] = Ti_end.shift(1)
    out = out.iloc[1:]
    out.index.name = "time"
    f10 = HERE / f"data_{name}_10min.csv"
    out.to_csv(f10)
    # hourly: inputs hourly means (labelled start), Ti instantaneous at the hour
    h = out[["Ta", "Ph", "Ps", "Psv", "wind"]].resample("1h").mean()
    h["yTi"] = out["yTi"].reindex(h.index)
    h = h.dropna()
    h.to_csv(HERE / f"data_{name}_1h.csv")
    print(
        name,
        "mean wind",
        wind.mean(),
        "mean Ta",
        Ta.mean(),
        "mean Ti",
        Ti_end.mean(),
        "mean Ph",
        ph.mean(),
        "cool kWh",
        (df[col("Sensible Cooling Rate")[0]].sum() / STEPS / 1000) if mode == "thermo" else 0,
    )


def steady_epw(path, T, wind, dew=None):
    lines = EPW.read_text().splitlines()
    sigma = 5.670374e-8
    out = lines[:8]
    for l in lines[8:]:
        f = l.split(",")
        f[6] = f"{T:.1f}"
        f[7] = f"{(T - 3 if dew is None else dew):.1f}"
        f[8] = "80"
        f[9] = "83700"
        for i in (10, 11, 13, 14, 15, 16, 17, 18, 19):
            f[i] = "0"
        f[12] = f"{sigma * (T + 273.15) ** 4:.0f}"  # sky at air temperature: pure conductance
        f[21] = f"{wind:.1f}"
        f[22] = "10"
        f[23] = "10"
        out.append(",".join(f))
    Path(path).write_text("\n".join(out) + "\n")


def truth(case, wind):
    res = {}
    for Tout, sp in ((-5.0, 20.0), (5.0, 20.0), (-5.0, 30.0)):
        d = HERE / "runs" / f"truth_{case}_w{wind}_{Tout}_{sp}"
        d.mkdir(parents=True, exist_ok=True)
        epw = d / "w.epw"
        steady_epw(epw, Tout, wind)
        (d / "in.idf").write_text(
            build_idf(case, "truth", 1, 1, 20, extra=f"\nSchedule:Constant, HEATSP, , {sp};\n")
        )
        eso = run_energyplus(d / "in.idf", epw, d)
        df = read_eso(eso, frequency="timestep")
        q = (
            df[[c for c in df.columns if "Sensible Heating Rate" in c][0]]
            .iloc[-STEPS * 24 :]
            .mean()
        )
        res[(Tout, sp)] = q
        print(
            case,
            wind,
            Tout,
            sp,
            q,
            df[[c for c in df.columns if "ZONE ONE:Zone Mean Air" in c][0]].iloc[-1],
        )
    h_out = (res[(-5.0, 20.0)] - res[(5.0, 20.0)]) / 10
    h_tot = (res[(-5.0, 30.0)] - res[(-5.0, 20.0)]) / 10
    r = {
        "case": case,
        "wind": wind,
        "H_outdoor_dQ_dTa": h_out,
        "H_total_dQ_dTi": h_tot,
        "Q": {f"{k}": v for k, v in res.items()},
    }
    print(json.dumps(r))
    (HERE / f"truth_{case}_w{wind}.json").write_text(json.dumps(r, indent=1))


if __name__ == "__main__":
    if sys.argv[1] == "truth":
        truth(sys.argv[2], float(sys.argv[3]))
    else:
        gen(sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]))
