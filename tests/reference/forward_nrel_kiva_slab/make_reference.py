"""EnergyPlus 25.2 results of NREL's ZoneCoupledKivaSlab variants: ``energyplus_results.json``.

Run from the repository root (EnergyPlus 25.2 and ../shared/data needed, about 10 s)::

    python tests/reference/forward_nrel_kiva_slab/make_reference.py

Each variant (``convert.py``) runs two years, 2022 and 2023, on Denver's TMY3 (the weather year
repeated; ``Begin Year`` 2022, ``End Year`` 2023), so that the second year starts from a ground
that has forgotten Kiva's initialisation (a steady state at the weather of 120 days before the
start at midnight, without sun, then three 30-day steps); only 2023 is kept. Written:

- ``monthly`` (zone held at 20 C: ``noins``, ``adiabatic``, ``asis``): the ideal loads' sensible
  heating and cooling and the floor's heat loss (``-`` its ``Surface Inside Face Conduction Heat
  Transfer Rate``: positive out of the zone) [kWh per month];
- ``hourly_air`` (free float: ``ff_noins``, ``ff_adiabatic``): the zone's hourly mean
  air temperature over 2023 [C, 0.01 K], hour 0 = 1 January 00:00-01:00.
"""

from __future__ import annotations

import json
import re
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path[:0] = [str(ROOT / "src"), str(ROOT / "tests")]

from conftest import SHARED_DATA  # noqa: E402
from thermocal.multizone.energyplus import read_eso, run_energyplus  # noqa: E402

WEATHER = ("ashrae140_bestest", "725650TYCST.epw")
HELD = ("noins", "adiabatic", "asis")
FREE = ("ff_noins", "ff_adiabatic")
RUN_PERIOD = "RunPeriod,spun_up,1,1,2022,12,31,2023,,Yes,Yes,No,Yes,Yes;"


def idf_text(variant: str) -> str:
    return (HERE / f"ZoneCoupledKivaSlab_{variant}_v25.idf").read_text()


def main() -> None:
    weather = SHARED_DATA.joinpath(*WEATHER)
    out = {"monthly": {}, "hourly_air": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for variant in (*HELD, *FREE):
            text, n = re.subn(r"RunPeriod,[^;]*;", RUN_PERIOD, idf_text(variant))
            assert n == 1
            idf = Path(tmp) / f"{variant}.idf"
            idf.write_text(text)
            df = read_eso(run_energyplus(idf, weather, Path(tmp) / variant), year=2023)
            df = df.iloc[len(df) // 2 :]  # 2023 (the labels repeat: month, day and hour only)
            assert len(df) == 8760

            def col(pattern, frame=df):
                return frame[[c for c in frame.columns if pattern.upper() in c.upper()][0]]

            if variant in HELD:
                month = df.index.month
                out["monthly"][variant] = {
                    "heating_kWh": [round(v / 1000, 2) for v in
                                    col("Sensible Heating Rate").groupby(month).sum()],
                    "cooling_kWh": [round(v / 1000, 2) for v in
                                    col("Sensible Cooling Rate").groupby(month).sum()],
                    "floor_loss_kWh": [round(-v / 1000, 2) for v in
                                       col("ZONE FLOOR:Surface Inside Face Conduction")
                                       .groupby(month).sum()],
                }  # fmt: skip
            else:
                out["hourly_air"][variant] = [
                    round(v, 2) for v in col("MAIN FLOOR:Zone Mean Air Temperature")
                ]
            print(variant, flush=True)
    out["measured"] = time.strftime("%Y-%m-%d")
    out["energyplus"] = "25.2.0-cf7368216c"
    (HERE / "energyplus_results.json").write_text(json.dumps(out, separators=(",", ":")) + "\n")


if __name__ == "__main__":
    main()
