"""Is it the window model? The solar and heat paths of each office window, EnergyPlus against
thermocal, and what the calibration's representation of the hidden glazing does to the offices.

Run from the repository root after ``make_reference.py`` (EnergyPlus 25.2 and ../shared/data
needed; about 5 s on two cores)::

    PYTHONPATH=src python \
        tests/reference/calibration_energyplus_5zone_windows/diagnose_window_paths.py

Both programs run ``5ZoneAirCooled_FF_v25.idf`` with its loads, free floating, for January
(EnergyPlus at 4 steps per hour, thermocal at 15 minutes, hourly values compared January 4-31),
in a temporary folder. Two measurements, written to ``window_paths.json`` beside this script:

- ``window_paths``: for the file's clear double glazing ``Dbl Clr 3mm/13mm Air`` and for the same
  construction with the hidden low-e inner pane (``make_reference.with_coated_inner_pane``),
  per office window (WF-1, WR-1, WB-1, WL-1) the month's sums [kWh] of the incident, transmitted
  and pane-absorbed solar radiation, the share of the absorbed solar that flows inward (hourly
  regression), the heat from the glass's inside face into the room (convection and long-wave
  to the other faces; negative: the room loses heat through the glass) by day and by night, the
  net daytime gain (the month's transmitted solar + the face heat by day) and the inside glass
  temperature by day and by night [C]: each as ``[EnergyPlus, thermocal]``, with the ratios
  thermocal / EnergyPlus.
- ``office_bias``: thermocal on the *nominal* (clear) file with the calibration's truth for the
  glazing (``window/<type>/u_value`` and ``shgc`` of ``truth.json``; SHGC also 0.80 and 0.85),
  and on the low-e file with parts of its window type swapped for the truth point's (the glass
  conductance's temperature table, or the SHGC-scaled clear optics), against EnergyPlus on the
  low-e file: the office air temperature bias [K] (mean of the five offices; day, night) and
  the error of the windows' inside glass temperature [K]. ``glass_conductance``: the two
  temperature tables at the month's mean glazing temperature.

"Day": for a window, the hours in which more than 5 W of solar radiation fall on it; for the
offices, the hours in which the south window WF-1 receives more than 5 W/m2.
thermocal's per-window values are read from the stepped simulation (its input columns and node
temperatures; the long-wave exchange linearised at the network's radiant temperature).
"""

from __future__ import annotations

import dataclasses
import json
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
from calibrate_twin import (  # this folder's script (run as a script: its folder is on the path)
    HERE,
    WINDOW_SHGC,
    WINDOW_U,
    folder_make_reference,
    truth_file,
)

sys.path.insert(0, str(HERE.parents[1] / "identification"))

from energyplus_twin import WEATHER_NAME, _class, _join, _objects, twin_idf  # noqa: E402

mr = folder_make_reference()
GLAZING = mr.WINDOW
#: office window -> its zone
WINDOWS = {"WF-1": "SPACE1-1", "WR-1": "SPACE2-1", "WB-1": "SPACE3-1", "WL-1": "SPACE4-1"}
OFFICES = ("SPACE1-1", "SPACE2-1", "SPACE3-1", "SPACE4-1", "SPACE5-1")
#: the south window, whose sunlit hours are the offices' "day"
SUN_WINDOW = "WF-1"
DAY_THRESHOLD = 5.0  # [W/m2] incident on SUN_WINDOW
WINDOW_DAY_THRESHOLD = 5.0  # [W] incident on a window: its "day"
ENERGYPLUS_STEPS = 4  # per hour
STEP = "15min"  # thermocal
START = "2023-01-04"  # first day compared (the first three settle)
#: window-type fields of the optics and of the glass conductance's temperature table
OPTICS = (
    "shgc",
    "solar_transmittance",
    "pane_absorptances",
    "relative_transmittance",
    "pane_absorptances_angular",
    "diffuse_transmittance",
    "diffuse_pane_absorptances",
)
TABLE = ("glass_conductance_temperatures", "glass_conductance_ratio")
#: EnergyPlus hourly outputs read
VARIABLES = (
    "Surface Window Transmitted Solar Radiation Rate",
    "Surface Window Total Glazing Layers Absorbed Solar Radiation Rate",
    "Surface Window Inside Face Glazing Zone Convection Heat Gain Rate",
    "Surface Window Inside Face Glazing Net Infrared Heat Transfer Rate",
    "Surface Inside Face Temperature",
    "Surface Outside Face Incident Solar Radiation Rate per Area",
    "Zone Mean Air Temperature",
)


# ---------------------------------------------------------------------------------------------
# the two programs
# ---------------------------------------------------------------------------------------------
def energyplus_input(text: str) -> str:
    """The IDF text for January with its loads and hourly outputs of :data:`VARIABLES`.

    Parameters
    ----------
    text : str
        IDF text (``5ZoneAirCooled_FF_v25.idf`` or a variant).

    Returns
    -------
    str
        ``energyplus_twin.twin_idf`` at :data:`ENERGYPLUS_STEPS` steps per hour, its timestep
        outputs replaced by hourly ones (with the advanced report variables enabled).
    """
    objects = [
        obj
        for obj in _objects(twin_idf(text, mr.DAYS, timesteps_per_hour=ENERGYPLUS_STEPS))
        if _class(obj) != "output:variable"
    ]
    objects.append("Output:Diagnostics,\n  DisplayAdvancedReportVariables")
    objects += [f"Output:Variable,\n  *,\n  {v},\n  Hourly" for v in VARIABLES]
    return _join(objects)


def run_energyplus_hourly(text: str, folder: Path):
    """EnergyPlus on an IDF text; the building thermocal reads from the same file.

    Parameters
    ----------
    text : str
        IDF text (loads included).
    folder : Path
        Working folder (``in.idf`` and EnergyPlus' outputs are written there).

    Returns
    -------
    energyplus : pandas.DataFrame
        Hourly outputs (``"KEY:Variable [unit]"``: W, W/m2, C), indexed by the hour's start in
        the weather's time zone.
    building : thermocal.multizone.model.Building
        ``read_idf`` of the same file.
    """
    from thermocal.multizone.energyplus import energyplus_weather_folder, read_eso, run_energyplus
    from thermocal.multizone.idf import read_idf

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    idf = folder / "in.idf"
    idf.write_text(energyplus_input(text))
    weather, _ = weather_and_metadata()
    eso = run_energyplus(idf, energyplus_weather_folder() / WEATHER_NAME, folder / "energyplus")
    energyplus = read_eso(eso, year=int(weather.index[0].year))
    if weather.index.tz is not None:
        energyplus.index = energyplus.index.tz_localize(weather.index.tz)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
    return energyplus, building


def weather_and_metadata():
    """Chicago O'Hare's TMY3 as thermocal reads it: (weather frame, metadata)."""
    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import energyplus_weather_folder

    return read_weather(energyplus_weather_folder() / WEATHER_NAME)


def simulation(building, energyplus: pd.DataFrame):
    """thermocal's simulation of ``building`` over EnergyPlus' hours, at :data:`STEP`."""
    from thermocal.multizone.simulation import Simulation

    weather, metadata = weather_and_metadata()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Simulation(
            building,
            weather,
            metadata,
            step=STEP,
            start=energyplus.index[0],
            end=energyplus.index[-1] + pd.Timedelta("1h"),
        )


def solar_columns(network, building, name: str) -> tuple[int, int, int, int]:
    """The simulation's input columns of the window ``name``: transmitted beam and diffuse,
    absorbed in the outer and in the inner pane [W/m2 of glazed area].

    The network shares the columns of a window type's windows with one orientation (the key
    ``(type, tilt, azimuth)``) unless the window has its own (``(type, tilt, azimuth, name)``).
    """
    window = building.windows[name]
    host = building.surfaces[window.surface]
    shared = (window.window_type, round(host.tilt, 3), round(host.azimuth % 360, 3))
    own = next((k for k in network.window_inputs if len(k) == 4 and k[3] == name), None)
    return network.window_inputs[own if own is not None else shared]


def thermocal_windows(building, energyplus: pd.DataFrame) -> dict[str, pd.DataFrame]:
    """thermocal's paths through each office window, hourly means.

    Parameters
    ----------
    building : Building
        The file as thermocal reads it (loads included).
    energyplus : pandas.DataFrame
        EnergyPlus' hourly outputs (for the period).

    Returns
    -------
    dict of str to pandas.DataFrame
        Per window of :data:`WINDOWS`, hourly: ``transmitted`` and ``absorbed`` solar [W] (beam
        and diffuse; both panes), ``face_heat`` [W] from the glass's inside face into the room
        (convection to the zone air at the face's matrix coefficient plus linearised long-wave
        to the other faces), ``inside`` and ``glazing`` temperatures [C] (inner glass face;
        mean of the two glass faces) and the zone ``air`` temperature [C].
    """
    sim = simulation(building, energyplus)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim.reset(free_float=True)
        states, air = [], []
        for _ in range(len(sim.times)):
            air.append(sim.step())
            states.append(sim._x.copy())
    states, air = np.array(states), np.array(air)
    net, inputs, zones = sim.network, sim._inputs, list(building.zones)
    out = {}
    for name, zone in WINDOWS.items():
        window = building.windows[name]
        beam, diffuse, outer, inner = solar_columns(net, building, name)
        area = window.glazed_area * window.shading_factor
        face = net.face_names.index(name)
        node = net.face_node[face]
        j = int(np.flatnonzero(net.window_inner == node)[0])
        inside = states[:, node]
        longwave = np.zeros(len(sim.times))
        for a, b, g in zip(net.lw_pair_a, net.lw_pair_b, net.lw_pair_g, strict=True):
            if node in (a, b):
                longwave += g * (inside - states[:, b if a == node else a])
        zone_air = air[:, zones.index(zone)]
        frame = pd.DataFrame(
            {
                "transmitted": (inputs[:, beam] + inputs[:, diffuse]) * area,
                "absorbed": (inputs[:, outer] + inputs[:, inner]) * area,
                "face_heat": net.face_h0[face] * net.face_area[face] * (inside - zone_air)
                + longwave,
                "inside": inside,
                "glazing": 0.5 * (states[:, net.window_outer[j]] + inside),
                "air": zone_air,
            },
            index=sim.times,
        )
        out[name] = frame.resample("1h").mean()
    return out


# ---------------------------------------------------------------------------------------------
# per-window paths
# ---------------------------------------------------------------------------------------------
def energyplus_window(energyplus: pd.DataFrame, name: str, area: float) -> pd.DataFrame:
    """EnergyPlus' hourly values of the window ``name`` (glazed area ``area`` [m2]) under
    thermocal's column names (W, C)."""
    ep = energyplus
    zone = WINDOWS[name]
    return pd.DataFrame(
        {
            "incident": ep[
                f"{name}:Surface Outside Face Incident Solar Radiation Rate per Area [W/m2]"
            ]
            * area,
            "transmitted": ep[f"{name}:Surface Window Transmitted Solar Radiation Rate [W]"],
            "absorbed": ep[
                f"{name}:Surface Window Total Glazing Layers Absorbed Solar Radiation Rate [W]"
            ],
            "face_heat": ep[
                f"{name}:Surface Window Inside Face Glazing Zone Convection Heat Gain Rate [W]"
            ]
            + ep[f"{name}:Surface Window Inside Face Glazing Net Infrared Heat Transfer Rate [W]"],
            "inside": ep[f"{name}:Surface Inside Face Temperature [C]"],
            "air": ep[f"{zone}:Zone Mean Air Temperature [C]"],
        }
    )


def daytime(energyplus: pd.DataFrame) -> pd.Series:
    """True in the hours in which :data:`SUN_WINDOW` receives > :data:`DAY_THRESHOLD` W/m2."""
    incident = energyplus[
        f"{SUN_WINDOW}:Surface Outside Face Incident Solar Radiation Rate per Area [W/m2]"
    ]
    return incident > DAY_THRESHOLD


def inward_share(frame: pd.DataFrame, outdoor: np.ndarray) -> float:
    """Share [-] of the pane-absorbed solar that reaches the room through the glass's face.

    The coefficient of ``absorbed`` in the hourly least-squares fit
    ``face_heat = a * absorbed + b * (T_outdoor - T_air) + c``.

    Parameters
    ----------
    frame : pandas.DataFrame
        Hourly ``face_heat``, ``absorbed`` [W] and ``air`` [C].
    outdoor : numpy.ndarray
        Hourly outdoor air temperature [C] on ``frame``'s index.
    """
    x = np.column_stack([frame["absorbed"], outdoor - frame["air"].to_numpy(), np.ones(len(frame))])
    coef, *_ = np.linalg.lstsq(x, frame["face_heat"].to_numpy(), rcond=None)
    return float(coef[0])


def window_paths(energyplus: pd.DataFrame, building) -> dict:
    """EnergyPlus and thermocal on the same file: each office window's month, January 4-31.

    Parameters
    ----------
    energyplus : pandas.DataFrame
        EnergyPlus' hourly outputs.
    building : Building
        The same file as thermocal reads it.

    Returns
    -------
    dict
        Per window: ``[EnergyPlus, thermocal]`` sums [kWh] (``incident``: EnergyPlus' only),
        the inward share [-], mean temperatures [C] and the ratios thermocal / EnergyPlus [-];
        and ``mean_glazing_temperature_C``, thermocal's mean over the four windows.
    """
    thermocal = thermocal_windows(building, energyplus)
    weather, _ = weather_and_metadata()
    index = energyplus[START:].index
    outdoor = weather["temp_air"].reindex(index, method="nearest").to_numpy()
    out = {}
    for name in WINDOWS:
        window = building.windows[name]
        area = window.glazed_area * window.shading_factor
        ep = energyplus_window(energyplus, name, area)[START:]
        tc = thermocal[name].reindex(ep.index)
        day = (ep["incident"] > WINDOW_DAY_THRESHOLD).to_numpy()

        def kwh(column, mask=slice(None), ep=ep, tc=tc):
            return [float(f[column][mask].sum()) / 1000.0 for f in (ep, tc)]

        def mean(column, mask, ep=ep, tc=tc):
            return [float(f[column][mask].mean()) for f in (ep, tc)]

        row = {
            "incident_kWh": float(ep["incident"].sum()) / 1000.0,
            "transmitted_kWh": kwh("transmitted"),
            "absorbed_kWh": kwh("absorbed"),
            "inward_share": [inward_share(f, outdoor) for f in (ep, tc)],
            "face_heat_day_kWh": kwh("face_heat", day),
            "face_heat_night_kWh": kwh("face_heat", ~day),
            "net_day_gain_kWh": [
                t + f for t, f in zip(kwh("transmitted"), kwh("face_heat", day), strict=True)
            ],
            "inside_glass_day_C": mean("inside", day),
            "inside_glass_night_C": mean("inside", ~day),
        }
        for key in ("transmitted_kWh", "absorbed_kWh", "net_day_gain_kWh"):
            row[key.replace("_kWh", "_ratio")] = row[key][1] / row[key][0]
        out[name] = row
    out["mean_glazing_temperature_C"] = float(
        np.mean([thermocal[name]["glazing"][START:].mean() for name in WINDOWS])
    )
    return out


# ---------------------------------------------------------------------------------------------
# office bias: the calibration's truth point, and its two parts swapped one at a time
# ---------------------------------------------------------------------------------------------
def office_bias(building, energyplus: pd.DataFrame) -> dict:
    """thermocal's office air and window glass temperatures against EnergyPlus'.

    Parameters
    ----------
    building : Building
        What thermocal simulates (free floating, loads included).
    energyplus : pandas.DataFrame
        EnergyPlus' hourly outputs of the file it is compared with (the low-e one).

    Returns
    -------
    dict
        The window type's normal-incidence ``transmittance`` and ``pane_absorptances`` [-];
        the office air bias [K] (mean over the five offices of the hourly error, all hours,
        day, night) and RMSE [K] (mean of the offices'); the inside glass temperature error
        [K] of the four windows (mean), day and night.
    """
    result = simulation(building, energyplus).run(free_float=True)
    air = result.air_temperature.resample("1h").mean()[START:]
    glass = result.surface_temperature.resample("1h").mean()[START:]
    ep = energyplus[START:]
    day = daytime(ep)
    error = pd.DataFrame({z: air[z] - ep[f"{z}:Zone Mean Air Temperature [C]"] for z in OFFICES})
    glass_error = pd.DataFrame(
        {w: glass[w] - ep[f"{w}:Surface Inside Face Temperature [C]"] for w in WINDOWS}
    )
    window = building.window_types[GLAZING]
    return {
        "transmittance": float(window.solar_transmittance),
        "pane_absorptances": [float(a) for a in window.pane_absorptances],
        "bias_K": float(error.mean().mean()),
        "bias_day_K": float(error[day].mean().mean()),
        "bias_night_K": float(error[~day].mean().mean()),
        "rmse_K": float(np.sqrt((error**2).mean()).mean()),
        "glass_error_day_K": float(glass_error[day].mean().mean()),
        "glass_error_night_K": float(glass_error[~day].mean().mean()),
    }


def with_window_fields(building, donor, fields):
    """``building`` with :data:`GLAZING`'s ``fields`` taken from the window type ``donor``."""
    window = building.window_types[GLAZING]
    swapped = dataclasses.replace(window, **{f: getattr(donor, f) for f in fields})
    return building.replaced(window_types={**building.window_types, GLAZING: swapped})


def bias_cases(nominal, low_e, truth: dict) -> dict:
    """The buildings of the office-bias table.

    Parameters
    ----------
    nominal, low_e : Building
        thermocal's reading of the clear and of the low-e file.
    truth : dict
        ``truth.json``'s element values (the window's U-value [W/(m2 K)] and SHGC [-]).

    Returns
    -------
    dict of str to Building
        The low-e file as read; the clear file at the truth's U-value with the truth's SHGC,
        0.80 and 0.85 (the calibration's representation: since 2026-11-30 the new U-value
        brings the coated glazing's temperature table, ``WindowType.with_u_value``); the same
        with the clear gap's table kept (the representation before); the low-e file with the
        clear gap's table, and with the truth point's scaled clear optics.
    """
    u_value, shgc = truth[WINDOW_U], truth[WINDOW_SHGC]
    cases = {"low-e glazing as read": low_e}
    for value in (shgc, 0.80, 0.85):
        label = f"clear glazing, U {u_value:.3f}, SHGC {value:.3g}"
        cases[label] = nominal.with_parameters({WINDOW_U: u_value, WINDOW_SHGC: value})
    donor = nominal.with_parameters({WINDOW_U: u_value, WINDOW_SHGC: shgc}).window_types[GLAZING]
    clear_gap = nominal.window_types[GLAZING]
    label = f"clear glazing, U {u_value:.3f}, SHGC {shgc:.3g}, the clear gap's table kept"
    cases[label] = with_window_fields(
        nominal.with_parameters({WINDOW_U: u_value, WINDOW_SHGC: shgc}), clear_gap, TABLE
    )
    cases["low-e optics + clear glazing's temperature table"] = with_window_fields(
        low_e, clear_gap, TABLE
    )
    cases["scaled clear optics + low-e temperature table"] = with_window_fields(
        low_e, donor, OPTICS
    )
    return cases


def conductance_ratios(cases: dict, temperature: float) -> dict:
    """The glass conductance's temperature factor [-] at ``temperature`` [C] of the low-e
    glazing as read, of the calibration's truth point and of the clear gap's table."""
    out = {"mean_glazing_temperature_C": temperature}
    for label, key in (("low_e", 0), ("truth_point", 1), ("clear_gap", 4)):
        window = list(cases.values())[key].window_types[GLAZING]
        out[f"ratio_{label}"] = float(
            np.interp(
                temperature, window.glass_conductance_temperatures, window.glass_conductance_ratio
            )
        )
    out["truth_point_over_low_e"] = out["ratio_truth_point"] / out["ratio_low_e"]
    return out


# ---------------------------------------------------------------------------------------------
def _rounded(value, digits: int = 4):
    """``value`` with floats rounded to ``digits`` decimals (lists, dicts too)."""
    if isinstance(value, dict):
        return {k: _rounded(v, digits) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_rounded(v, digits) for v in value]
    if isinstance(value, float):
        return round(value, digits)
    return value


def _compact_json(value, indent: str = "") -> str:
    """JSON with one line per dict whose values are all numbers or lists of numbers."""
    if isinstance(value, dict) and any(isinstance(v, dict) for v in value.values()):
        inner = indent + "  "
        items = [f"{inner}{json.dumps(k)}: {_compact_json(v, inner)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + indent + "}"
    return json.dumps(value)


def run() -> dict:
    """Both measurements; writes ``window_paths.json``."""
    source = (mr.SHARED / mr.IDF_NAME).read_text()
    texts = {"clear": source, "low_e": mr.with_coated_inner_pane(source)}
    out = {
        "description": (
            f"5ZoneAirCooled with loads, free float, January 4-31; EnergyPlus 25.2 at "
            f"{ENERGYPLUS_STEPS} steps/h, thermocal at {STEP}; pairs are [EnergyPlus, thermocal]; "
            f"day: the window receives > {WINDOW_DAY_THRESHOLD:g} W (window paths), "
            f"{SUN_WINDOW} > {DAY_THRESHOLD:g} W/m2 (offices)"
        ),
        "window_paths": {},
    }
    buildings, energyplus = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, text in texts.items():
            energyplus[name], buildings[name] = run_energyplus_hourly(text, Path(tmp) / name)
            out["window_paths"][name] = window_paths(energyplus[name], buildings[name])
    cases = bias_cases(buildings["clear"], buildings["low_e"], truth_file()["truth"])
    out["office_bias"] = {
        label: office_bias(building, energyplus["low_e"]) for label, building in cases.items()
    }
    temperature = out["window_paths"]["low_e"].pop("mean_glazing_temperature_C")
    out["window_paths"]["clear"].pop("mean_glazing_temperature_C")
    out["glass_conductance"] = conductance_ratios(cases, temperature)
    rows = list(out["office_bias"].values())
    as_read, point, before, table, optics = rows[0], rows[1], rows[4], rows[5], rows[6]
    out["bias_split_K"] = {
        "total": point["bias_K"] - as_read["bias_K"],
        "total_with_the_clear_gap_table": before["bias_K"] - as_read["bias_K"],
        "clear_gap_table": table["bias_K"] - as_read["bias_K"],
        "optics": optics["bias_K"] - as_read["bias_K"],
        "optics_day": optics["bias_day_K"] - as_read["bias_day_K"],
    }
    out = _rounded(out)
    (HERE / "window_paths.json").write_text(_compact_json(out) + "\n")
    return out


if __name__ == "__main__":
    print(_compact_json(run()))
