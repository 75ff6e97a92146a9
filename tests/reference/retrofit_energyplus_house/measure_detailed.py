"""Detailed-model retrofit of the EnergyPlus house against EnergyPlus 25.2 (issue 25, item 7).

Runs ``thermocal.retrofit.detailed.simulate_strategies`` on ``house_v25.idf`` (the file
EnergyPlus ran) with the measures of ``reference.json`` (the same U-values and g-value; the
detailed model adds lambda 0.035 layers exactly as ``make_reference.py`` did) and prints the
16-strategy table: EnergyPlus / thermocal detailed / difference.

    python tests/reference/retrofit_energyplus_house/measure_detailed.py \\
        /work/shared/data/weather_switzerland/Zuerich-SMA_2015.epw [REFERENCE_FOLDER]

``REFERENCE_FOLDER`` another reference with the same files (``house_v25.idf``,
``reference.json``), e.g. ``tests/reference/retrofit_energyplus_basement``.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(weather_path: str, folder: Path = HERE) -> dict:
    """The table for the reference in ``folder`` (this house's; the basement house's folder,
    ``../retrofit_energyplus_basement``, has the same files)."""
    from thermocal.io.weather import read_weather
    from thermocal.retrofit.detailed import load_detailed_building, simulate_strategies
    from thermocal.retrofit.strategies import Measure, all_strategies

    folder = Path(folder)
    ref = json.loads((folder / "reference.json").read_text())
    measures = {
        name: Measure(name=name, component=name, u_value=m["u_value"], g_value=m.get("g_value"),
                      cost_per_m2=m["cost_per_m2"])
        for name, m in ref["measures"].items()
    }  # fmt: skip
    strategies = all_strategies(tuple(measures))
    weather, meta = read_weather(weather_path)
    t0 = time.perf_counter()
    building = load_detailed_building(folder / "house_v25.idf")
    result = simulate_strategies(
        building, weather, meta, strategies, measures, source=folder / "house_v25.idf"
    )
    elapsed = time.perf_counter() - t0
    rows = []
    print("| code | measures | EnergyPlus kWh | thermocal kWh | EnergyPlus saving % | "
          "thermocal saving % | difference pp |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    for s, kwh, sav in zip(strategies, result.annual_kwh, result.saving_pct, strict=True):
        key = "+".join(s.measures) or "none"
        e_kwh, e_sav = ref["annual_heating_kWh"][key], ref["saving_pct"][key]
        rows.append({"code": s.code, "key": key, "energyplus_kWh": e_kwh, "thermocal_kWh": kwh,
                     "energyplus_saving_pct": e_sav, "thermocal_saving_pct": sav})  # fmt: skip
        diff = "" if not s.measures else f"{sav - e_sav:+.1f}"
        print(f"| {s.code} | {' + '.join(s.measures) or '-'} | {e_kwh:,.0f} | {kwh:,.0f} | "
              f"{e_sav:.1f} | {sav:.1f} | {diff} |")  # fmt: skip
    base = rows[0]
    diffs = [abs(r["thermocal_saving_pct"] - r["energyplus_saving_pct"]) for r in rows[1:]]
    print(f"baseline {base['thermocal_kWh']:,.0f} vs {base['energyplus_kWh']:,.0f} kWh "
          f"({100 * (base['thermocal_kWh'] / base['energyplus_kWh'] - 1):+.1f} %); savings: "
          f"max |diff| {max(diffs):.1f} pp, mean {sum(diffs) / len(diffs):.1f} pp; "
          f"{elapsed:.1f} s for {len(strategies)} strategies")  # fmt: skip
    for note in result.notes:
        print("note:", note)
    return {"rows": rows, "seconds": elapsed}


if __name__ == "__main__":
    main(sys.argv[1], *(Path(a) for a in sys.argv[2:3]))
