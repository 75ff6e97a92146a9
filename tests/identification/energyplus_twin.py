"""EnergyPlus twin of NREL's 5ZoneAirCooled for the heat-balance identification.

EnergyPlus 25.2 runs ``5ZoneAirCooled_FF_v25.idf`` (../shared/data/energyplus_reference, its HVAC
removed: free float with its People/Lights/ElectricEquipment schedules and scheduled, wind-driven
infiltration) from January 1 for ``days`` days at 1-minute steps, sampled at 5 minutes. Its zone
air temperatures are perfect sensors; the heat entering each zone (convective + long-wave
radiant + visible, the sensible internal gains EnergyPlus reports) is the truth the identified
heat should equal.
thermocal gets the same file without the People/Lights/ElectricEquipment objects: the true
envelope, no loads.

Used by ``test_identification_energyplus.py`` (a lean period) and by
``tests/reference/identification_5zone/measure.py`` (January, every option; its results next to
it).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.io.weather import read_weather
from thermocal.multizone.energyplus import energyplus_weather_folder, read_eso, run_energyplus
from thermocal.multizone.idf import read_idf

IDF_NAME = "5ZoneAirCooled_FF_v25.idf"
WEATHER_NAME = "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"
LOAD_CLASSES = ("people", "lights", "electricequipment")
GAIN_VARIABLES = (
    "Zone Total Internal Convective Heating Rate",
    "Zone Total Internal Radiant Heating Rate",
    "Zone Total Internal Visible Radiation Heating Rate",
)
#: thermocal's step (the sensors' and the gains' resolution)
STEP = "5min"
#: the five offices and the return plenum
ZONES = ("SPACE1-1", "SPACE2-1", "SPACE3-1", "SPACE4-1", "SPACE5-1", "PLENUM-1")


def _objects(text: str) -> list[str]:
    """The IDF's objects without comments, one string each (without the final ';')."""
    lines = [line.split("!", 1)[0] for line in text.splitlines()]
    return [obj.strip() for obj in "\n".join(lines).split(";") if obj.strip()]


def _class(obj: str) -> str:
    return obj.split(",", 1)[0].strip().lower()


def twin_idf(source: str, days: int, *, timesteps_per_hour: int = 12) -> str:
    """The reference file: January 1 to ``days``, 5-minute steps, timestep gain outputs."""
    out = []
    for obj in _objects(source):
        kind = _class(obj)
        if kind == "runperiod":
            fields = [f.strip() for f in obj.split(",")]
            fields[2:7] = ["1", "1", "", "1", str(days)]
            obj = ",\n  ".join(fields)
        elif kind == "timestep":
            obj = f"Timestep,\n  {timesteps_per_hour}"
        elif kind == "output:variable":
            continue
        out.append(obj)
    for variable in ("Zone Mean Air Temperature", *GAIN_VARIABLES):
        out.append(f"Output:Variable,\n  *,\n  {variable},\n  Timestep")
    return ";\n\n".join(out) + ";\n"


def without_loads(source: str) -> str:
    """The file without its People, Lights and ElectricEquipment objects (the envelope)."""
    kept = [obj for obj in _objects(source) if _class(obj) not in LOAD_CLASSES]
    return ";\n\n".join(kept) + ";\n"


@dataclass
class Twin:
    """What EnergyPlus made and what thermocal gets."""

    building: object  # thermocal Building of the file without loads
    weather: pd.DataFrame
    metadata: dict
    temperature: pd.DataFrame  # zone air temperature [C] at each step's end, by step start
    gains: pd.DataFrame  # sensible heat entering each zone over each step [W], by step start
    start: pd.Timestamp
    end: pd.Timestamp


def make_twin(
    shared_folder: Path,
    directory: Path,
    days: int,
    weather_path=None,
    *,
    energyplus_steps_per_hour: int = 60,
) -> Twin:
    """Run EnergyPlus on the twin (in ``directory``) and read what thermocal needs.

    ``weather_path``: an EPW file instead of Chicago O'Hare's TMY3 (the installation's).
    ``energyplus_steps_per_hour``: EnergyPlus' own step (default 60, one minute), its results
    sampled on 5-minute steps (temperature at each step's end, gains averaged over it).
    EnergyPlus' inside-surface heat balance takes the zone air temperature of its previous
    step, so at its 5-minute step the plenum's surfaces exchange about 60 W with an air
    temperature 0.015 K out of date at night: the 5-minute plenum lags the 1-minute one by
    0.07 K at night and 0.17 K in the afternoon (measured on this twin), a time-step error of
    the reference, not physics.
    """
    directory = Path(directory)
    source = (Path(shared_folder) / IDF_NAME).read_text()
    reference_idf = directory / "twin.idf"
    reference_idf.write_text(twin_idf(source, days, timesteps_per_hour=energyplus_steps_per_hour))
    envelope_idf = directory / "envelope.idf"
    envelope_idf.write_text(without_loads(twin_idf(source, days)))
    weather_path = weather_path or energyplus_weather_folder() / WEATHER_NAME
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(envelope_idf)
        weather, metadata = read_weather(weather_path)
    year = int(weather.index[0].year)
    eso = run_energyplus(reference_idf, weather_path, directory / "energyplus")
    frame = read_eso(eso, year=year, frequency="timestep")
    if frame.index.tz is None and weather.index.tz is not None:
        frame.index = frame.index.tz_localize(weather.index.tz)
    temperature = pd.DataFrame(
        {zone: frame[f"{zone}:Zone Mean Air Temperature [C]"] for zone in ZONES}
    )
    gains = pd.DataFrame(
        {
            zone: sum(
                frame[f"{zone}:{name} [W]"] if f"{zone}:{name} [W]" in frame else 0.0
                for name in GAIN_VARIABLES
            )
            for zone in ZONES
        }
    )
    start = frame.index[0]
    end = frame.index[-1] + (frame.index[1] - frame.index[0])
    if energyplus_steps_per_hour != 12:
        step = pd.Timedelta(STEP)
        temperature = temperature.groupby(temperature.index.floor(step)).last()
        gains = gains.groupby(gains.index.floor(step)).mean()
    return Twin(building, weather, metadata, temperature, gains, start, end)


def sensor_log(twin: Twin, zones) -> tuple[pd.DataFrame, dict]:
    """Perfect sensors in ``zones``: EnergyPlus' value at each step's end, stamped there."""
    log = twin.temperature[list(zones)].copy()
    log.index = log.index + (log.index[1] - log.index[0])
    names = {zone: f"T_{zone}" for zone in zones}
    return log.rename(columns=names), {"sensors": {s: z for z, s in names.items()}}


def fidelity(identified: pd.DataFrame, truth: pd.DataFrame, mask: np.ndarray | None = None):
    """Hourly NMBE and CV(RMSE) [-] of the building's identified heat against the truth.

    ``identified`` and ``truth`` per step [W] (same index); ``mask`` selects steps (e.g. the
    unoccupied ones) before the hourly means. NMBE = sum(id - true) / sum(true), CV(RMSE) =
    RMS(id - true) / mean(true), over the hours (ASHRAE Guideline 14 without its degrees-of-
    freedom correction).
    """
    pair = pd.DataFrame(
        {"identified": identified.sum(axis=1), "truth": truth.sum(axis=1)}, index=truth.index
    )
    if mask is not None:
        pair = pair[np.asarray(mask, dtype=bool)]
    hourly = pair.groupby(pair.index.floor("1h")).mean()
    diff = hourly["identified"] - hourly["truth"]
    mean = float(hourly["truth"].mean())
    return {
        "nmbe": float(diff.sum() / hourly["truth"].sum()),
        "cvrmse": float(np.sqrt((diff**2).mean()) / mean),
        "r": float(np.corrcoef(hourly["identified"], hourly["truth"])[0, 1]),
        "hours": int(len(hourly)),
        "truth_mean_W": mean,
    }
