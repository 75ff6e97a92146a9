"""EnergyPlus twins of buildings thermocal did not write, for the forward model and the
heat-balance identification.

EnergyPlus 25.2 runs a free-floating IDF (HVAC removed: its People/Lights/equipment schedules
and its infiltration and ventilation) from January 1 for ``days`` days at its own steps (the
5ZoneAirCooled twin at 1-minute steps, sampled at 5 minutes). Its zone air temperatures are
perfect sensors; the heat entering each zone (convective + long-wave radiant + visible, the
sensible internal gains EnergyPlus reports) is the truth the identified heat should equal.
thermocal gets the same file without the load objects: the true
envelope, no loads.

Two buildings: NREL's 5ZoneAirCooled (``5ZoneAirCooled_FF_v25.idf`` in
../shared/data/energyplus_reference; :func:`make_twin`) and the PNNL/DOE multifamily prototype
(``tests/reference/identification_multifamily/multifamily_5A_FF_v25.idf``; :func:`make_twin_of`
with any 25.2 IDF). Used by ``test_identification_energyplus.py``,
``test_identification_multifamily.py`` (lean periods) and the measure scripts of
``tests/reference/identification_5zone`` and ``identification_multifamily`` (January, every
option; their results next to them).
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
#: the load objects thermocal does not get (the identified heat stands for them)
LOAD_CLASSES = ("people", "lights", "electricequipment", "gasequipment", "otherequipment")
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


def _join(objects: list[str]) -> str:
    return ";\n\n".join(objects) + ";\n"


def twin_idf(
    source: str, days: int, *, timesteps_per_hour: int = 12, variables: tuple[str, ...] = ()
) -> str:
    """The reference file: January 1 to ``days``, ``timesteps_per_hour`` steps, timestep
    outputs of the zone temperature and gains and of ``variables`` (the file's own
    Output:Variable objects dropped)."""
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
    for variable in ("Zone Mean Air Temperature", *GAIN_VARIABLES, *variables):
        out.append(f"Output:Variable,\n  *,\n  {variable},\n  Timestep")
    return _join(out)


def without_loads(source: str) -> str:
    """The file without its load objects (:data:`LOAD_CLASSES`): the envelope."""
    return _join([obj for obj in _objects(source) if _class(obj) not in LOAD_CLASSES])


#: Design-level fields of the load objects (index in the object, class name at 0) and whether
#: the field scales with the load (True) or inversely (floor area per person)
_LEVEL_FIELDS = {5: True, 6: True, 7: True}
_LEVEL_FIELDS_PEOPLE = {5: True, 6: True, 7: False}


def scaled_loads(source: str, factor: float) -> str:
    """The file with every load object's design level (number of people, W, W/m2, W/person)
    multiplied by ``factor`` (> 0); schedules, fractions and everything else unchanged."""
    if not factor > 0:
        raise ValueError(f"factor must be positive, got {factor}")
    out = []
    for obj in _objects(source):
        kind = _class(obj)
        if kind in LOAD_CLASSES:
            fields = [f.strip() for f in obj.split(",")]
            levels = _LEVEL_FIELDS_PEOPLE if kind == "people" else _LEVEL_FIELDS
            for i, scales in levels.items():
                if i < len(fields) and fields[i] and fields[i].lower() != "autocalculate":
                    value = float(fields[i])
                    fields[i] = repr(value * factor if scales else value / factor)
            obj = ",\n  ".join(fields)
        out.append(obj)
    return _join(out)


def zone_names(source: str) -> list[str]:
    """The Zone names of an IDF, in file order."""
    return [obj.split(",")[1].strip() for obj in _objects(source) if _class(obj) == "zone"]


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
    """The 5ZoneAirCooled twin (thermocal at 5-minute steps), run in ``directory``.

    ``weather_path``: an EPW file instead of Chicago O'Hare's TMY3 (the installation's).
    ``energyplus_steps_per_hour``: EnergyPlus' own step (default 60, one minute), its results
    sampled on 5-minute steps (temperature at each step's end, gains averaged over it).
    EnergyPlus' inside-surface heat balance takes the zone air temperature of its previous
    step, so at its 5-minute step the plenum's surfaces exchange about 60 W with an air
    temperature 0.015 K out of date at night: the 5-minute plenum lags the 1-minute one by
    0.07 K at night and 0.17 K in the afternoon (measured on this twin), a time-step error of
    the reference, not physics.
    """
    source = (Path(shared_folder) / IDF_NAME).read_text()
    return make_twin_of(
        source,
        directory,
        days,
        weather_path=weather_path,
        zones=ZONES,
        energyplus_steps_per_hour=energyplus_steps_per_hour,
    )


def make_twin_of(
    source: str,
    directory: Path,
    days: int,
    *,
    weather_path=None,
    zones=None,
    timesteps_per_hour: int = 12,
    envelope: str | None = None,
    energyplus_steps_per_hour: int | None = None,
    variables: tuple[str, ...] = (),
) -> Twin:
    """Run EnergyPlus on the twin of an IDF text (in ``directory``) and read what thermocal
    needs (``variables``: more timestep outputs EnergyPlus writes, read from
    ``directory / "energyplus" / "eplusout.eso"``).

    Parameters
    ----------
    source : str
        EnergyPlus 25.2 IDF text, free float, with its loads (what EnergyPlus runs).
    directory : Path
        Work folder (twin.idf, envelope.idf, energyplus/).
    days : int
        Days from January 1.
    weather_path : path, optional
        EPW file; default Chicago O'Hare's TMY3 of the EnergyPlus installation.
    zones : sequence of str, optional
        Zones to read (EnergyPlus' upper-case names); default every Zone of the file.
    timesteps_per_hour : int
        Steps per hour of the twin (thermocal's step; the sensors' and gains' sampling).
    envelope : str, optional
        The IDF text thermocal reads; default ``source`` without its loads.
    energyplus_steps_per_hour : int, optional
        EnergyPlus' own steps per hour (default ``timesteps_per_hour``); its results are
        sampled on the twin's steps (temperature at each step's end, gains averaged over it).
    """
    directory = Path(directory)
    zones = [z.upper() for z in (zones or zone_names(source))]
    reference_idf = directory / "twin.idf"
    energyplus_steps_per_hour = energyplus_steps_per_hour or timesteps_per_hour
    reference_idf.write_text(
        twin_idf(source, days, timesteps_per_hour=energyplus_steps_per_hour, variables=variables)
    )
    envelope_idf = directory / "envelope.idf"
    envelope_text = without_loads(source) if envelope is None else envelope
    envelope_idf.write_text(twin_idf(envelope_text, days, timesteps_per_hour=timesteps_per_hour))
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
    # thermocal's zone names (the file's spelling) for EnergyPlus' upper-case ones
    spelled = {name.upper(): name for name in building.zones}
    temperature = pd.DataFrame(
        {spelled.get(z, z): frame[f"{z}:Zone Mean Air Temperature [C]"] for z in zones}
    )
    gains = pd.DataFrame(
        {
            spelled.get(z, z): sum(
                frame[f"{z}:{name} [W]"] if f"{z}:{name} [W]" in frame else 0.0
                for name in GAIN_VARIABLES
            )
            for z in zones
        }
    )
    start = frame.index[0]
    end = frame.index[-1] + (frame.index[1] - frame.index[0])
    if energyplus_steps_per_hour != timesteps_per_hour:
        step = pd.Timedelta(hours=1) / timesteps_per_hour
        temperature = temperature.groupby(temperature.index.floor(step)).last()
        gains = gains.groupby(gains.index.floor(step)).mean()
    return Twin(building, weather, metadata, temperature, gains, start, end)


def forward_on_the_same_file(text: str, directory: Path, days: int, steps_per_hour: int):
    """EnergyPlus and thermocal on the same IDF text (loads included), free float from January
    1: ``(twin, table)`` with the per-zone hourly RMSE and bias [K] of thermocal's air
    temperature against EnergyPlus' (first day left out)."""
    from thermocal.multizone.simulation import Simulation

    twin = make_twin_of(text, directory, days, timesteps_per_hour=steps_per_hour, envelope=text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = Simulation(
            twin.building,
            twin.weather,
            twin.metadata,
            step=f"{60 // steps_per_hour}min",
            start=twin.start,
            end=twin.end,
            store_surfaces=False,
        ).run(free_float=True)
    return twin, hourly_rmse_bias(result.air_temperature, twin.temperature)


def hourly_rmse_bias(simulated: pd.DataFrame, reference: pd.DataFrame, skip="1D") -> pd.DataFrame:
    """Per zone hourly RMSE and bias [K] of ``simulated`` - ``reference`` (zone air
    temperatures [C] per step on the same step-start index), after ``skip``."""
    keep = reference.index >= reference.index[0] + pd.Timedelta(skip)
    diff = (simulated.reindex(reference.index) - reference)[keep]
    hourly = diff.groupby(diff.index.floor("1h")).mean()
    return pd.DataFrame({"rmse": np.sqrt((hourly**2).mean()), "bias": hourly.mean()})


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
    if truth.isna().any().any() or identified.isna().any().any():
        raise ValueError("fidelity: identified heat and truth must share their steps (NaN found)")
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


def zone_fidelity(result, twin: Twin, zones=None, skip: str = "1D"):
    """Fidelity (:func:`fidelity`) of the identified heat of ``zones`` (default every zone)
    against their own gains, in all hours and in the identification's unoccupied hours, the
    first ``skip`` left out: ``(every, unoccupied)``."""
    q = result.q_id if zones is None else result.q_id[list(zones)]
    truth = twin.gains.reindex(q.index)[list(q.columns)]
    keep = q.index >= q.index[0] + pd.Timedelta(skip)
    quiet = result.unoccupied_mask()[keep]
    return fidelity(q[keep], truth[keep]), fidelity(q[keep], truth[keep], quiet)
