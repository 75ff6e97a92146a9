"""EnergyPlus's own annual heat balance of the living zone (issue 25, the first twin's demand).

Runs the reference house (``make_reference.house_idf()``: heating at a constant 20 C, the
year 2015) with the outputs of the living zone's heat balance and prints it by month and for
the year [kWh]: the inside-face conduction of every surface (positive out of the zone), the
windows' net heat loss, the infiltration, the transmitted sun, the internal gains by kind and
the ideal-loads heating, and the attic's and the garage's mean temperatures with the ISO 13789
adjustment factor they imply, ``b = (Ti - Tu) / (Ti - Te)``. Writes ``balance.json`` beside
the reference (monthly [kWh] and mean temperatures [C]; read by
``tests/retrofit/test_retrofit_energyplus_twin.py``, docs/retrofit-twins.md "Where the first twin's
demand goes"). About 30 s.

    python tests/reference/retrofit_energyplus_house/diagnose_balance.py \\
        /work/shared/data/weather_switzerland/Zuerich-SMA_2015.epw
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pandas as pd

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import make_reference as mr  # noqa: E402

SURFACES = (
    "Living:North", "Living:East", "Living:South", "Living:West", "Living:Interior",
    "Living:Floor", "Living:Ceiling",
)  # fmt: skip
WINDOWS = ("NorthWindow", "EastWindow", "SouthWindow", "WestWindow")

OUTPUTS = (
    "".join(
        f"Output:Variable, {s}, Surface Inside Face Conduction Heat Transfer Rate, Hourly;\n"
        for s in SURFACES
    )
    + "".join(
        f"Output:Variable, {w}, Surface Window Net Heat Transfer Rate, Hourly;\n" for w in WINDOWS
    )
    + "Output:Variable, LIVING ZONE, Zone Infiltration Sensible Heat Loss Energy, Hourly;\n"
    "Output:Variable, LIVING ZONE, Zone Infiltration Sensible Heat Gain Energy, Hourly;\n"
    + "".join(
        f"Output:Variable, {w}, Surface Window Transmitted Solar Radiation Rate, Hourly;\n"
        for w in WINDOWS
    )
    + "".join(
        f"Output:Variable, {s}, Surface Outside Face Solar Radiation Heat Gain Rate, Hourly;\n"
        for s in SURFACES[:4]
    )
    + "Output:Variable, LIVING ZONE, Zone Air Heat Balance Internal Convective Heat Gain Rate, "
    "Hourly;\n"
    "Output:Variable, LIVING ZONE, Zone Air Heat Balance Surface Convection Rate, Hourly;\n"
    "Output:Variable, LIVING ZONE, Zone Total Internal Radiant Heating Rate, Hourly;\n"
    "Output:Variable, LIVING ZONE, Zone Total Internal Visible Radiation Heating Rate, Hourly;\n"
)


def paths(df: pd.DataFrame) -> pd.DataFrame:
    """The living zone's balance, hourly [W], from a run with :data:`OUTPUTS`: the columns and
    signs of ``balance.json`` (surfaces: inside-face conduction, positive into the zone;
    windows: net heat out of the zone incl. the transmitted sun; infiltration: loss;
    transmitted sun and gains: negative; heating: delivered)."""
    out = pd.DataFrame(index=df.index)
    for s in SURFACES:
        # EnergyPlus: positive from the inside face into the zone (negative: a loss)
        out[s] = mr._col(df, f"{s}:Surface Inside Face Conduction")
    for w in WINDOWS:
        # net heat transfer: positive into the zone
        out[w] = -mr._col(df, f"{w}:Surface Window Net Heat Transfer Rate")
    j_per_h = 3600.0
    out["infiltration"] = (
        mr._col(df, "Infiltration Sensible Heat Loss Energy")
        - mr._col(df, "Infiltration Sensible Heat Gain Energy")
    ) / j_per_h
    out["transmitted_sun"] = -sum(
        mr._col(df, f"{w}:Surface Window Transmitted Solar") for w in WINDOWS
    )
    # outside faces of the walls: the sun they absorb
    out["walls_outside_sun"] = sum(
        mr._col(df, f"{s}:Surface Outside Face Solar Radiation") for s in SURFACES[:4]
    )
    out["gains_convective"] = -mr._col(df, "Internal Convective Heat Gain Rate")
    out["gains_radiant"] = -mr._col(df, "Zone Total Internal Radiant Heating Rate")
    out["gains_visible"] = -mr._col(df, "Zone Total Internal Visible Radiation Heating Rate")
    out["heating"] = mr._col(df, "Zone Ideal Loads Zone Sensible Heating Rate")
    return out


def balance(weather: Path, work: Path) -> pd.DataFrame:
    """Monthly living-zone balance [kWh] of the reference house (hourly means summed)."""
    df = mr._run(mr.house_idf() + OUTPUTS, weather, work)
    monthly = paths(df).resample("MS").sum() / 1000.0
    temps = pd.DataFrame(
        {
            "Ti": mr._col(df, "LIVING ZONE:Zone Mean Air"),
            "Te": mr._col(df, "Site Outdoor Air Drybulb"),
            "T_attic": mr._col(df, "ATTIC ZONE:Zone Mean Air"),
            "T_garage": mr._col(df, "GARAGE ZONE:Zone Mean Air"),
        }
    )
    return monthly, temps


def main(weather: str, work: str = "/tmp/retrofit_energyplus_house_balance") -> None:
    monthly, temps = balance(Path(weather), Path(work))
    means = temps.resample("MS").mean()
    out = {
        "source": "diagnose_balance.py: make_reference.house_idf(), EnergyPlus 25.2, "
        + Path(weather).name,
        "sign": "kWh per month; surfaces: inside-face conduction into the zone (negative: loss); "
        "windows: net heat transfer out of the zone incl. the transmitted sun; infiltration: "
        "loss; transmitted_sun, gains: negative (into the zone); heating: delivered",
        "monthly_kWh": {c: [round(float(v), 2) for v in monthly[c]] for c in monthly},
        "monthly_mean_C": {c: [round(float(v), 3) for v in means[c]] for c in means},
    }
    (HERE / "balance.json").write_text(json.dumps(out, indent=1) + "\n")
    monthly.loc["year"] = monthly.sum()
    pd.set_option("display.width", 250)
    print(monthly.round(0).T)
    heated = temps["Ti"] - temps["Te"] > 0.5
    for zone in ("attic", "garage"):
        t = temps.loc[heated]
        b = (t["Ti"] - t[f"T_{zone}"]).sum() / (t["Ti"] - t["Te"]).sum()
        print(f"b factor of the {zone} (hours with Ti - Te > 0.5 K, degree-hour weighted): {b:.3f}")


if __name__ == "__main__":
    main(*sys.argv[1:])
