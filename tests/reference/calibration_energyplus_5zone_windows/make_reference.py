"""EnergyPlus 25.2 twin of NREL's 5ZoneAirCooled with other windows, for calibration.

Run from the repository root (EnergyPlus 25.2 and ../shared/data needed, about 30 s)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_5zone_windows/make_reference.py \
        [--screen]

The second hidden envelope on the building of ``../calibration_energyplus_5zone`` (same file,
same machinery: that folder's ``make_reference.py`` functions, imported). EnergyPlus runs
``5ZoneAirCooled_FF_v25.idf`` for January at 1-minute steps with its loads and

- the double glazing ``Dbl Clr 3mm/13mm Air`` (the four offices' windows) given a low-e inner
  pane (:data:`LOW_E`): the inner pane's face towards the gap (surface 3) with an infrared
  emissivity of 0.1 instead of 0.84 and a solar transmittance of 0.70 instead of 0.837, as a
  coated pane has; the construction keeps its name, so the user's nominal file still says clear
  double glazing;
- the ground floor slab's concrete (``CC03``, only in ``FLOOR-SLAB-1``) with half its
  conductivity: the slab's resistance x2;
- the roof insulation (``IN46``) with its conductivity / 0.7: its resistance x0.7.

Walls and infiltration are as in the file. The zone air temperatures, sampled at 5 minutes and
rounded to 0.01 K, are the sensor log; thermocal gets the *nominal* file without its loads.

Writes beside this script ``sensors.csv.gz``, ``mapping.yaml`` and ``truth.json`` (as the 5-zone
folder does: the element-level parameters thermocal reads from the nominal and from the hidden
file, ``window/<type>/{u_value,shgc}`` included, plus ``infiltration/building/factor`` = 1).

``--screen`` (:func:`screen`) measures, before anything is kept, how much each hidden change
alone moves the zone air temperatures (EnergyPlus at 12 steps per hour): the file's
``Site:GroundTemperature:BuildingSurface`` of about 20 C could make the floor nearly adiabatic;
it does not, because the free-floating offices sit below it (``screen.json``).
"""

from __future__ import annotations

import importlib.util
import json
import sys
import tempfile
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))

from energyplus_twin import (  # noqa: E402
    IDF_NAME,
    ZONES,
    _class,
    _join,
    _objects,
    make_twin_of,
    without_loads,
)


def _five_zone_script():
    """The 5-zone twin's ``make_reference`` module, loaded from its file under its own name
    (this folder's script has the same file name)."""
    path = HERE.parent / "calibration_energyplus_5zone" / "make_reference.py"
    spec = importlib.util.spec_from_file_location("make_reference_5zone", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


base = _five_zone_script()
SHARED, DAYS = base.SHARED, base.DAYS
nominal_envelope, element_values, perturbed = (
    base.nominal_envelope,
    base.element_values,
    base.perturbed,
)

WINDOW = "Dbl Clr 3mm/13mm Air"
#: The inner pane of :data:`WINDOW`: a copy of ``CLEAR 3MM`` named ``name`` with these fields
#: (index counts the class name as 0): 5 solar transmittance [-], 12 front-side (towards the gap,
#: surface 3) infrared hemispherical emissivity [-].
LOW_E = {"name": "CLEAR 3MM LOW-E", "fields": {5: 0.70, 12: 0.10}}
#: (IDF class, object name, field index, factor) of the opaque changes (:func:`perturbed`)
OPAQUE = (
    ("material", "CC03", 4, 1 / 2.0),  # floor slab concrete conductivity: its R x2
    ("material", "IN46", 4, 1 / 0.7),  # roof insulation conductivity: its R x0.7
)
FACTOR = "infiltration/building/factor"


def with_coated_inner_pane(source: str, window: str = WINDOW, low_e: dict = LOW_E) -> str:
    """The IDF text with the inner pane of the construction ``window`` replaced by a coated
    copy of its glass.

    Parameters
    ----------
    source : str
        IDF text.
    window : str
        Name of a ``Construction`` of glazing layers (outside first); its last layer is the
        inner pane. The construction keeps its name.
    low_e : dict
        ``name`` of the new ``WindowMaterial:Glazing`` and ``fields``: {field index (class
        name at 0): value} changed from the copied glass (transmittances, reflectances,
        emissivities [-]).
    """
    objects = _objects(source)
    layers = next(
        [f.strip() for f in obj.split(",")]
        for obj in objects
        if _class(obj) == "construction" and obj.split(",")[1].strip() == window
    )
    glass = layers[-1].upper()
    out = []
    for obj in objects:
        fields = [f.strip() for f in obj.split(",")]
        if _class(obj) == "construction" and fields[1] == window:
            fields[-1] = low_e["name"]
            obj = ",\n  ".join(fields)
        out.append(obj)
        if _class(obj) == "windowmaterial:glazing" and fields[1].upper() == glass:
            coated = list(fields)
            coated[1] = low_e["name"]
            for index, value in low_e["fields"].items():
                coated[index] = repr(float(value))
            out.append(",\n  ".join(coated))
    return _join(out)


def hidden(source: str) -> str:
    """The hidden building: the coated inner pane and the opaque changes of :data:`OPAQUE`."""
    return perturbed(with_coated_inner_pane(source), OPAQUE)


def with_factor(values: dict) -> dict:
    """Element values with the building's infiltration factor (1: the file's infiltration)."""
    return {**values, FACTOR: 1.0}


def zone_temperatures(text: str, folder: Path, steps_per_hour: int):
    """EnergyPlus' zone air temperatures [C] of an IDF text (with its loads) for January."""
    Path(folder).mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        twin = make_twin_of(
            text,
            folder,
            DAYS,
            zones=ZONES,
            envelope=without_loads(text),
            energyplus_steps_per_hour=steps_per_hour,
        )
    return twin.temperature[list(ZONES)]


def screen(steps_per_hour: int = 12) -> dict:
    """How far each hidden change alone moves the zone air temperatures from the nominal file's
    (January 4-31, EnergyPlus at ``steps_per_hour``): mean and largest difference per zone
    [K]. Writes ``screen.json``."""
    source = (SHARED / IDF_NAME).read_text()
    cases = {
        "window (coated inner pane)": with_coated_inner_pane(source),
        "floor R x2": perturbed(source, OPAQUE[:1]),
        "roof insulation R x0.7": perturbed(source, OPAQUE[1:]),
        "all (the hidden building)": hidden(source),
    }
    with tempfile.TemporaryDirectory() as tmp:
        nominal = zone_temperatures(source, Path(tmp) / "nominal", steps_per_hour)
        out = {"steps_per_hour": steps_per_hour, "nominal_mean_C": {}, "cases": {}}
        out["nominal_mean_C"] = nominal["2023-01-04":].mean().round(2).to_dict()
        for name, text in cases.items():
            diff = (zone_temperatures(text, Path(tmp) / name[:5], steps_per_hour) - nominal)[
                "2023-01-04":
            ]
            out["cases"][name] = {
                "mean_dT_K": diff.mean().round(3).to_dict(),
                "max_abs_dT_K": diff.abs().max().round(3).to_dict(),
            }
    (HERE / "screen.json").write_text(json.dumps(out, indent=2) + "\n")
    return out


def main() -> None:
    source = (SHARED / IDF_NAME).read_text()
    secret = hidden(source)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        nominal = with_factor(element_values(source, tmp))
        truth = with_factor(element_values(secret, tmp))
        temperatures = zone_temperatures(secret, tmp / "twin", 60)
    description = (
        f"5ZoneAirCooled, hidden envelope: {WINDOW}'s inner pane {LOW_E['name']} (fields "
        + ", ".join(f"{i}={v}" for i, v in LOW_E["fields"].items())
        + "), "
        + ", ".join(f"{k} {n} field {i} x{f:.4g}" for k, n, i, f in OPAQUE)
    )
    base.write_reference(HERE, temperatures, nominal, truth, description)


#: The heat-flux plate of :func:`heat_flux_study`: on the inside face of the north office's
#: exterior wall (``BACK-1``, construction ``WALL-1``: the plate away from the sun, as ISO
#: 9869-1 asks), January 4-17; the element the calibration's advice and the wall/window trade
#: leave open.
PLATE_SURFACE, PLATE_CONSTRUCTION, PLATE_SEED = "BACK-1", "WALL-1", 98694


def heat_flux_study() -> dict:
    """An in-situ measurement of the exterior wall as a building physicist makes it (ISO 9869-1
    with surface temperatures: the construction's resistance), the 5-zone folder's
    ``plate_log`` on :data:`PLATE_SURFACE` of the hidden building, January 4-17.

    Writes ``heat_flux_wall.csv`` (time = start of each hour, ``q_W_m2`` outward, ``Tsi``,
    ``Tse`` [C]) and adds ``heat_flux`` to ``truth.json``: the truth it estimates is the hidden
    wall's ``construction/WALL-1/resistance`` (unchanged from the file's) already there.
    """
    text = hidden((SHARED / IDF_NAME).read_text())
    log, period = base.plate_log(text, PLATE_SURFACE, base.PLATE_DAYS, seed=PLATE_SEED)
    log.to_csv(HERE / "heat_flux_wall.csv", index=False)
    truth = json.loads((HERE / "truth.json").read_text())
    truth["heat_flux"] = base.plate_record(
        "heat_flux_wall.csv", PLATE_SURFACE, PLATE_CONSTRUCTION, period, PLATE_SEED
    )
    (HERE / "truth.json").write_text(json.dumps(truth, indent=2) + "\n")
    return truth["heat_flux"]


if __name__ == "__main__":
    if "--screen" in sys.argv:
        print(json.dumps(screen(), indent=1))
    elif "--heat-flux" in sys.argv:
        print(json.dumps(heat_flux_study(), indent=1))
    else:
        main()
