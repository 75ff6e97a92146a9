"""The small generated clinic's inputs for calibration tests: its nominal building file, the
sensor log of a hidden true building and the sensor-to-zone mapping (importable by the test
modules that share them)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd


def weather_path() -> Path:
    """The pvlib TMY3 weather file the clinic's tests run under."""
    from thermocal.demos.retrofit import pvlib_weather_path

    return pvlib_weather_path()


def small_clinic():
    """The 12-zone clinic, standing where its weather was measured (300 km off is refused)."""
    from thermocal.demos import buildings as generators
    from thermocal.io.weather import read_weather
    from thermocal.multizone.model import Location

    _, meta = read_weather(weather_path())
    site = Location(meta["latitude"], meta["longitude"], meta.get("altitude") or 0.0)
    return generators.clinic(12, n_corridors=1, corridor_sections=2, location=site)


def write_clinic_inputs(folder, truth: dict, *, step: str, start: str, end: str,
                        warmup_days: int | None = None):  # fmt: skip
    """Write ``building.yaml`` (the nominal clinic), ``sensors.csv`` (the air temperatures of
    the clinic with the ``truth`` parameters, free floating, every ``step``, stamped at each
    step's end) and ``mapping.yaml`` (sensor ``Snn`` -> zone) into ``folder``.

    Parameters
    ----------
    folder : path
        Where the files go.
    truth : dict
        The hidden building's parameters (name -> value in its unit).
    step : str
        The log's step (pandas offset, e.g. ``"5min"``).
    start, end : str
        The log's period (dates).
    warmup_days : int, optional
        The simulation's warm-up [days] (None: its default).

    Returns
    -------
    Building
        The nominal clinic.
    """
    from thermocal.io.weather import read_weather
    from thermocal.multizone import Simulation
    from thermocal.multizone.files import save_building

    folder = Path(folder)
    weather, meta = read_weather(weather_path())
    nominal = small_clinic()
    options = {} if warmup_days is None else {"warmup_days": warmup_days}
    air = (
        Simulation(nominal.with_parameters(truth), weather, meta, step=step, start=start,
                   end=end, store_surfaces=False, **options)  # fmt: skip
        .run(free_float=True)
        .air_temperature
    )
    air.index = air.index + pd.Timedelta(step)  # sensors see the end-of-step state
    names = {zone: f"S{i:02d}" for i, zone in enumerate(air.columns)}
    log = air.rename(columns=names)
    log.index.name = "time"
    log.to_csv(folder / "sensors.csv", date_format="%Y-%m-%dT%H:%M:%S%z")
    (folder / "mapping.yaml").write_text(
        "sensors:\n" + "".join(f"  {s}: {z}\n" for z, s in names.items())
    )
    save_building(nominal, folder / "building.yaml")
    return nominal
