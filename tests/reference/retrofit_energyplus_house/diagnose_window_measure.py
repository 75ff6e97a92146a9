"""The windows measure split into its U part and its g part, in EnergyPlus and in thermocal.

The measure of ``config.yaml`` replaces the double clear glazing (described U 3.23 W/(m2 K),
g 0.76) by glazing of U 0.76 and g 0.50. Both programs run it whole, with the new U alone (g
as the old) and with the new g alone (U as the old), over the reference year (Zurich 2015,
20 C):

- EnergyPlus 25.2 on the reference house (``make_reference.house_idf``, the IDFs of
  ``reference.json``): the old layered glazing, ``WindowMaterial:SimpleGlazingSystem`` U 0.76
  with SHGC 0.76 (U part), U 0.76 with SHGC 0.50 (the whole measure, ``reference.json``'s
  windows), U 3.23 with SHGC 0.76 and 0.50 (the g part on the old glass; its base is the
  simple glazing of the old values, whose heating is within 1 % of the layered one's), with
  the living zone's balance (``diagnose_balance.paths``) and the glazing's absorbed sun;
- thermocal's retrofit on the twin as ``test_twin_with_the_plate_and_a_measured_air_change``
  runs it (the north wall's heat-flux plate, ``air_change_rate`` 0.08 1/h) with three measures
  on the windows: the whole measure, ``u_value`` 0.76 alone and ``g_value`` 0.50 alone
  (a measure's U or g left out stays the old one's).

The g part on the new glass is the whole measure's saving less the U part's. It also measures
the old and new windows' conductance in EnergyPlus with their films (the conduction loss of
the four windows regressed on A (Ti - Te) and the sun absorbed in the glazing, February 2 -
March 15 and October - April; and the mean over sunless hours with Ti - Te > 5 K), and where
the sun cut by the new g goes from October to April, in both programs: the transmitted sun
of the U-only run less the whole measure's, against the heating's rise and the fall of
each path's loss (EnergyPlus: the living zone's inside-face conduction per surface, the
windows' conduction, the infiltration; thermocal: ``thermocal.retrofit.balance.heat_balance``
of the estimate per path). thermocal's part is run again with the window sun all on the air
node and all on the internal mass (``model.solar_to_internal_mass`` 0 and 1; 0.5 by default).

Result (2026-11-30): U part 27.7 % in thermocal against 28.6 % in EnergyPlus, g part on the
new glass -12.0 % against -7.8 % (on the old glass -14.0 % against -8.8 %), the whole measure
15.6 % against 20.8 %. EnergyPlus's old windows conduct 2.35-2.41 W/(m2 K) with their films
(0.73-0.75 of the described 3.23; the calibration's window factor 0.797 is within one
posterior sd of it), the new ones 0.69-0.70. From October to April the new g cuts
EnergyPlus's transmitted sun by 2,219 kWh and raises its heating by 758 kWh (34 %); the rest,
absorbed by the room's surfaces, had left through the uninsulated walls (27 %, 28 % with the
wall to the garage), the slab (18 %), back out through the windows (12 %) and the ceiling
(5 %). thermocal's cut of 2,148 kWh raises its heating by 1,216 kWh (57 %; on the old glass
1,326 kWh, 62 %, against EnergyPlus's 35 %): the fifth-order network puts the window sun into
the air and internal-mass nodes (half each), from which it displaces heating; all on the
internal mass 56 %, all on the air 47 % (g part -9.8 %, and the validation gate fails). Reading:
docs/retrofit-twins.md, "The windows measure: U part and g part". Writes
``window_measure.json``, read by ``tests/retrofit/test_retrofit_energyplus_window_measure.py``.

    python tests/reference/retrofit_energyplus_house/diagnose_window_measure.py \\
        /work/shared/data/weather_switzerland/Zuerich-SMA_2015.epw [--no-energyplus]

``--no-energyplus`` keeps the EnergyPlus part of the committed ``window_measure.json`` and
reruns thermocal's part only (about 10 s). With EnergyPlus (five runs of the year, one at a
time): about 25 s.
"""

from __future__ import annotations

import datetime
import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
# other reference folders have a make_reference.py too (tests import this script)
sys.modules.pop("make_reference", None)
sys.modules.pop("diagnose_balance", None)

import diagnose_balance as db  # noqa: E402
import make_reference as mr  # noqa: E402

OUT = HERE / "window_measure.json"
#: the measure's new glazing (U 0.76, g 0.50) and the old one's described values
NEW_U, NEW_G = mr.MEASURES["windows"]["u_value"], mr.MEASURES["windows"]["g_value"]
OLD_U, OLD_G = mr.U_WINDOW, mr.G_WINDOW
WINDOW_AREA = len(mr.WINDOWS) * mr.WINDOW_AREA
HEATING_SEASON = (1, 2, 3, 4, 10, 11, 12)  # October to April
#: the natural air change of a blower-door test (EnergyPlus's 0.01 m3/s over 453 m3)
AIR_CHANGE_RATE = 0.08
#: thermocal's three measures on the windows: the whole one, its U alone, its g alone
THERMOCAL_MEASURES = {
    "windows": {"u_value": NEW_U, "g_value": NEW_G},
    "windows_u": {"component": "windows", "u_value": NEW_U},
    "windows_g": {"component": "windows", "g_value": NEW_G},
}
#: the heat-flux plate on the north wall (make_reference.py --heat-flux)
IN_SITU_WALLS = {
    "walls": {
        "file": str(HERE / "heat_flux_north_wall.csv"),
        "columns": {"heat_flux": "q_W_m2", "temp_in": "Ti", "temp_out": "Te"},
    }
}
WINDOW_OUTPUTS = "".join(
    f"Output:Variable, {w}, Surface Window Total Glazing Layers Absorbed Solar Radiation Rate, "
    "Hourly;\n"
    for w in db.WINDOWS
)
OUTER_WALLS = ("Living:North", "Living:East", "Living:South", "Living:West")


def glazing(u: float, g: float) -> str:
    """The reference house with the windows measure's ``SimpleGlazingSystem`` at U ``u`` and
    SHGC ``g`` (``make_reference.house_idf`` with the windows measure, its glazing's values
    changed)."""
    text = mr.house_idf(frozenset({"windows"}))
    line = f"WindowMaterial:SimpleGlazingSystem, TRIPLE GLAZING, {NEW_U}, {NEW_G};"
    if text.count(line) != 1:
        raise ValueError(f"make_reference's windows measure no longer reads {line!r}")
    return text.replace(line, f"WindowMaterial:SimpleGlazingSystem, TRIPLE GLAZING, {u}, {g};")


def energyplus_variants() -> dict[str, str]:
    """The five EnergyPlus houses: name -> IDF text."""
    return {
        "old": mr.house_idf(),  # the layered double clear glazing (reference.json's "none")
        "u_only": glazing(NEW_U, OLD_G),
        "whole": mr.house_idf(frozenset({"windows"})),  # reference.json's "windows"
        "old_simple": glazing(OLD_U, OLD_G),
        "g_only": glazing(OLD_U, NEW_G),
    }


def _hourly(df: pd.DataFrame) -> pd.DataFrame:
    """The balance paths (``diagnose_balance.paths``) with the windows' conduction loss, the
    glazing's absorbed sun and the air temperatures, hourly [W] / [C]."""
    h = db.paths(df)
    h["windows_conduction"] = sum(h[w] for w in db.WINDOWS) - h["transmitted_sun"]
    h["absorbed_sun"] = sum(
        mr._col(df, f"{w}:Surface Window Total Glazing Layers Absorbed Solar") for w in db.WINDOWS
    )
    h["Ti"] = mr._col(df, "LIVING ZONE:Zone Mean Air")
    h["Te"] = mr._col(df, "Site Outdoor Air Drybulb")
    return h


def window_conductance(h: pd.DataFrame) -> dict:
    """The four windows' conductance per area with their films [W/(m2 K)].

    ``regression``: their conduction loss regressed on ``A (Ti - Te)`` and the sun absorbed in
    the glazing (no intercept), with the share of that sun conducted inward; ``sunless``: the
    loss over ``A (Ti - Te)`` in the hours without sun and ``Ti - Te > 5 K``. February 2 -
    March 15 (the measurements) and October - April.
    """
    out = {}
    periods = {
        "feb2_mar15": (h.index >= mr.PERIOD[0]) & (h.index <= mr.PERIOD[1]),
        "oct_apr": h.index.month.isin(HEATING_SEASON),
    }
    for label, sel in periods.items():
        d = h.loc[sel]
        dt = d["Ti"] - d["Te"]
        x = np.column_stack([WINDOW_AREA * dt, d["absorbed_sun"]])
        coef = np.linalg.lstsq(x, d["windows_conduction"].to_numpy(), rcond=None)[0]
        dark = (d["transmitted_sun"] == 0) & (d["absorbed_sun"] < 1e-6) & (dt > 5.0)
        sunless = d.loc[dark, "windows_conduction"].sum() / (WINDOW_AREA * dt[dark].sum())
        out[label] = {
            "regression": float(coef[0]),
            "absorbed_sun_inward_share": float(-coef[1]),
            "sunless": float(sunless),
        }
    return out


def energyplus_sun_fate(before: pd.DataFrame, after: pd.DataFrame) -> dict:
    """October - April: the transmitted sun the new g cuts (``before`` less ``after``, the
    same U) [kWh], the heating's rise, and per path the fall of its loss, as shares of the
    cut (they add up to 1 with ``rest``: the zone air's and furniture's storage and the
    balance's closure)."""

    def season(h):
        s = h.loc[h.index.month.isin(HEATING_SEASON)].sum() / 1000.0
        loss = {  # heat out of the zone [kWh]
            "walls": -sum(s[w] for w in OUTER_WALLS),
            "wall_to_the_garage": -s["Living:Interior"],
            "floor": -s["Living:Floor"],
            "ceiling": -s["Living:Ceiling"],
            "windows": s["windows_conduction"],
            "infiltration": s["infiltration"],
        }
        return -s["transmitted_sun"], s["heating"], loss

    sun_b, heat_b, loss_b = season(before)
    sun_a, heat_a, loss_a = season(after)
    cut = sun_b - sun_a
    shares = {k: (loss_b[k] - loss_a[k]) / cut for k in loss_b}
    shares["rest"] = 1.0 - sum(shares.values()) - (heat_a - heat_b) / cut
    return {
        "transmitted_sun_cut_kWh": cut,
        "heating_rise_kWh": heat_a - heat_b,
        "utilisation": (heat_a - heat_b) / cut,
        "loss_fall_share_of_the_cut": shares,
    }


def energyplus(weather: Path, work: Path) -> dict:
    """EnergyPlus's part of ``window_measure.json`` (five runs of the year, one at a time)."""
    runs = {}
    for name, idf in energyplus_variants().items():
        df = mr._run(idf + db.OUTPUTS + WINDOW_OUTPUTS, weather, work / name)
        runs[name] = _hourly(df)
    heating = {k: float(h["heating"].sum() / 1000.0) for k, h in runs.items()}

    def saving(variant, base="old"):
        return 100.0 * (1.0 - heating[variant] / heating[base])

    return {
        "date": datetime.date.today().isoformat(),
        "energyplus": "25.2",
        "weather": weather.name,
        "annual_heating_kWh": heating,
        "saving_pct": {
            "u_only": saving("u_only"),
            "g_on_new_glass": saving("whole") - saving("u_only"),
            "whole": saving("whole"),
            "g_only_on_old_glass": saving("g_only", "old_simple"),
        },
        "window_conductance_W_per_m2K": {
            "old": window_conductance(runs["old"]),
            "new": window_conductance(runs["whole"]),
            "described": {"old": OLD_U, "new": NEW_U},
        },
        "sun_cut_oct_apr": {
            "new_glass": energyplus_sun_fate(runs["u_only"], runs["whole"]),
            "old_glass": energyplus_sun_fate(runs["old_simple"], runs["g_only"]),
        },
    }


def thermocal_config(weather: Path, solar_to_internal_mass: float | None = None):
    """The twin's retrofit configuration with the plate, the measured air change and the three
    window measures (:data:`THERMOCAL_MEASURES`); ``solar_to_internal_mass``: the model's share
    of the window sun on the internal mass instead of its default."""
    from thermocal.retrofit.config import parse_config

    cfg = yaml.safe_load((HERE / "config.yaml").read_text())
    building = yaml.safe_load((HERE / "building.yaml").read_text())
    building["air_change_rate"] = AIR_CHANGE_RATE
    cfg.update(building=building, measures=THERMOCAL_MEASURES, in_situ=IN_SITU_WALLS)
    cfg["measurements"]["file"] = str(HERE / "measurements.csv")
    cfg["weather"]["file"] = str(weather)
    if solar_to_internal_mass is not None:
        cfg["model"] = {"solar_to_internal_mass": solar_to_internal_mass}
    return parse_config(cfg, base_dir=HERE, source="diagnose_window_measure.py")


def thermocal(weather: Path, solar_to_internal_mass: float | None = None) -> dict:
    """thermocal's part of ``window_measure.json``: the savings of the three measures (the
    estimate's, as results.json's ``saving_pct``, with the 90 % interval), the window factor,
    the windows' U-values it simulates and the sun's fate (the estimate's heat balance)."""
    from thermocal.retrofit.balance import heat_balance
    from thermocal.retrofit.outputs import ESTIMATED_PARAMETERS
    from thermocal.retrofit.tables import scenario_table
    from thermocal.retrofit.workflow import run_retrofit

    an = run_retrofit(thermocal_config(weather, solar_to_internal_mass))
    table = scenario_table(an)
    by_measure = {"+".join(s.measures) or "none": i for i, s in enumerate(an.strategies)}
    rows = {k: table.iloc[i] for k, i in by_measure.items()}
    params = {k: float(np.atleast_1d(an.draws[k])[0]) for k in ESTIMATED_PARAMETERS}

    def envelope(key):
        env = an.envelopes[by_measure[key]]
        return env[0] if isinstance(env, list | tuple) else env

    def season(key):
        """October - April: the sun into the room, the heating, and what leaves by each path
        (and is stored) [kWh], the estimate's demand simulation."""
        bal = heat_balance(
            an.model, params, envelope(key), an.year_inputs, an.indoor_profile, gains=an.year_gains
        )
        s = bal.loc[list(HEATING_SEASON)].sum()
        paths = ("envelope", "windows", "air_change", "floor", "stored")
        return -s["sun"], s["heating"], {k: s[k] for k in paths}

    def sun_fate(before, after):
        sun_b, heat_b, loss_b = season(before)
        sun_a, heat_a, loss_a = season(after)
        cut = sun_b - sun_a
        return {
            "transmitted_sun_cut_kWh": float(cut),
            "heating_rise_kWh": float(heat_a - heat_b),
            "utilisation": float((heat_a - heat_b) / cut),
            "loss_fall_share_of_the_cut": {k: float((loss_b[k] - loss_a[k]) / cut) for k in loss_b},
        }

    saving = {k: float(rows[k]["saving_pct"]) for k in THERMOCAL_MEASURES}
    corr = an.calibration.correction
    conductances = an.model.conductances(envelope("none"))
    return {
        "date": datetime.date.today().isoformat(),
        "configuration": "config.yaml, building.yaml with air_change_rate 0.08, the north "
        "wall's plate (in_situ.walls), measures: " + json.dumps(THERMOCAL_MEASURES),
        "saving_pct": {
            "u_only": saving["windows_u"],
            "g_on_new_glass": saving["windows"] - saving["windows_u"],
            "whole": saving["windows"],
            "g_only_on_old_glass": saving["windows_g"],
        },
        "saving_pct_90": {
            k: [float(rows[m]["saving_pct_p05"]), float(rows[m]["saving_pct_p95"])]
            for k, m in (
                ("u_only", "windows_u"),
                ("whole", "windows"),
                ("g_only_on_old_glass", "windows_g"),
            )
        },
        "window_factor_k_win": float(corr.factors["k_win"]),
        "k_win_posterior_std_log": float(corr.posterior_std["k_win"]),
        "window_u_W_per_m2K": {
            "old": float(envelope("none").windows_u),
            "new": float(envelope("windows_u").windows_u),
        },
        "window_sun_to_internal_mass_f_im": float(conductances["f_im"]),
        "validation_gate_passed": bool(an.gate["passed"]),
        "sun_cut_oct_apr": {
            "new_glass": sun_fate("windows_u", "windows"),
            "old_glass": sun_fate("none", "windows_g"),
        },
    }


def main(weather: str, *options: str, work: str = "/tmp/retrofit_energyplus_house_windows") -> dict:
    """Runs both parts (``--no-energyplus``: thermocal's only), writes ``window_measure.json``
    and prints the comparison."""
    weather = Path(weather)
    if "--no-energyplus" in options:
        ep = json.loads(OUT.read_text())["energyplus"]
    else:
        ep = energyplus(weather, Path(work))
    tc = thermocal(weather)
    # the window sun all on the air node, or all on the internal mass
    f_im = {}
    for share in (0.0, 1.0):
        run = thermocal(weather, share)
        f_im[str(share)] = {
            "saving_pct": run["saving_pct"],
            "utilisation": {g: s["utilisation"] for g, s in run["sun_cut_oct_apr"].items()},
            "validation_gate_passed": run["validation_gate_passed"],
        }
    out = {
        "what": "the windows measure (U 3.23 -> 0.76, g 0.76 -> 0.50) split into its U part and "
        "its g part, EnergyPlus 25.2 and thermocal's retrofit on the twin (plate + air change "
        "0.08 1/h), Zurich 2015 at 20 C; g_on_new_glass = whole - u_only; sun_cut_oct_apr: the "
        "transmitted sun the new g cuts October - April (new glass: u_only - whole; old glass: "
        "the old U with g 0.76 - with g 0.50), the heating's rise and the fall of each path's "
        "loss as shares of the cut",
        "script": "diagnose_window_measure.py",
        "date": datetime.date.today().isoformat(),
        "energyplus": ep,
        "thermocal": tc,
        "thermocal_solar_to_internal_mass": f_im,
    }
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    for part in ("u_only", "g_on_new_glass", "whole", "g_only_on_old_glass"):
        print(f"{part:20s} thermocal {tc['saving_pct'][part]:6.1f} %   "
              f"EnergyPlus {ep['saving_pct'][part]:6.1f} %")  # fmt: skip
    g = ep["window_conductance_W_per_m2K"]
    print("EnergyPlus window conductance, old:", json.dumps(g["old"]), "new:", json.dumps(g["new"]))
    for glass in ("new_glass", "old_glass"):
        for name, side in (("thermocal", tc), ("EnergyPlus", ep)):
            s = side["sun_cut_oct_apr"][glass]
            shares = ", ".join(
                f"{k} {100 * v:.1f} %" for k, v in s["loss_fall_share_of_the_cut"].items()
            )
            print(f"{glass}, {name}: sun cut {s['transmitted_sun_cut_kWh']:,.0f} kWh, heating "
                  f"+{s['heating_rise_kWh']:,.0f} kWh ({100 * s['utilisation']:.0f} %); "
                  f"{shares}")  # fmt: skip
    for share, run in f_im.items():
        print(f"window sun on the internal mass {share}: utilisation "
              f"{run['utilisation']['new_glass']:.2f} (new glass), g part on the new glass "
              f"{run['saving_pct']['g_on_new_glass']:.1f} %, validation gate passed "
              f"{run['validation_gate_passed']}")  # fmt: skip
    return out


if __name__ == "__main__":
    main(*sys.argv[1:])
