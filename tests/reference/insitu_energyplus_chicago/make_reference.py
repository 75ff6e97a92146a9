"""Short heat-flux meter logs cut from the EnergyPlus 25.2 run of ``winter.idf`` (a box in
Chicago: a heavy wall of 365 mm brick and a light timber-frame wall, each facing north and
south; 10-min steps, averaged here to hourly interval means, which keeps the whole days' sums).

Run ``run_energyplus.sh`` first (it writes ``winter.parquet``), then
``python make_reference.py /tmp/insitu_energyplus_chicago/winter.parquet``.

The heat flux is EnergyPlus' conduction at the inside face (outward positive); the
temperatures either the zone's air and the site's outdoor dry-bulb (``*_air.csv``) or the
wall's inside and outside face temperatures (``*_surface.csv``). Truth (truth.json): each
wall's surface-to-surface conductance from the eio's CTF conductance, U with ISO 6946's films
(0.13 + 0.04 m2 K/W), and its areal heat capacity from its layers.
"""

import sys

import pandas as pd

Q = "Surface Inside Face Conduction Heat Transfer Rate per Area"
#: name -> (zone, wall, first day, days, temperatures)
LOGS = {
    "north_heavy_3d_surface": ("A", "N_HEAVY", "2006-01-25", 3, "surface"),
    "north_heavy_4d_surface": ("A", "N_HEAVY", "2006-02-08", 4, "surface"),
    "north_light_14d_air": ("B", "N_LIGHT", "2006-01-15", 14, "air"),
    "north_heavy_14d_air": ("A", "N_HEAVY", "2006-01-15", 14, "air"),
    "south_heavy_14d_air": ("A", "S_HEAVY", "2006-01-15", 14, "air"),
    "south_light_14d_air": ("A", "S_LIGHT", "2006-02-01", 14, "air"),
    "south_light_14d_surface": ("A", "S_LIGHT", "2006-02-01", 14, "surface"),
    "mild_north_light_3d_air": ("A", "N_LIGHT", "2006-04-18", 3, "air"),
}


def make_log(df, zone, wall, start, days, temps):
    s = f"{zone}_{wall}"
    t0 = pd.Timestamp(start)
    rows = slice(t0, t0 + pd.Timedelta(days=days) - pd.Timedelta(minutes=1))
    if temps == "air":
        ti, te = df[f"{zone}:Zone Mean Air Temperature"], df[
            "Environment:Site Outdoor Air Drybulb Temperature"]
    else:
        ti, te = df[f"{s}:Surface Inside Face Temperature"], df[
            f"{s}:Surface Outside Face Temperature"]
    log = pd.DataFrame({"q": -df[f"{s}:{Q}"][rows], "Ti": ti[rows], "Te": te[rows]})
    log = log.resample("1h").mean().round(4)
    log.index.name = "time"
    return log


if __name__ == "__main__":
    df = pd.read_parquet(sys.argv[1])
    for name, spec in LOGS.items():
        make_log(df, *spec).to_csv(f"{name}.csv")
