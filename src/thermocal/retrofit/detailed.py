"""Retrofit strategies simulated with the detailed multi-zone model.

The fifth-order RC method (:mod:`thermocal.retrofit.workflow`) estimates a few lumped
parameters from measurements; a detailed model (a thermocal building YAML, an EnergyPlus IDF, or
the ``calibrated_building.yaml`` that ``thermocal calibrate`` writes) already knows every
construction, window and zone. This module applies the same retrofit measures to it and
simulates each strategy for the weather year under the same heating:

* **Measures -> constructions and windows.** Each U-value measure acts on the surfaces of the
  heated zones (zones with a heating or cooling set point) that form the component it names,
  chosen by boundary and orientation (:func:`measure_surfaces`): ``walls`` the walls to
  outdoors (doors excluded), ``roof`` the roofs to outdoors, ``attic_ceiling`` ceilings to an
  unheated zone above, ``cellar_ceiling`` floors over an unheated zone, ``wall_to_unheated``
  walls to an unheated zone, ``ground_floor`` floors on the ground; ``windows`` every window of
  a heated zone. An opaque measure adds a layer of insulation (lambda 0.035 W/(m K)) whose
  thickness takes the construction's ISO 6946 U-value (surface resistances of its position) to
  the measure's target, ``d = lambda (1/U_target - 1/U_now)``: outside the structure (behind a
  render or cladding thinner than 3 cm) for walls and roofs, on the unheated side for ceilings
  and walls to unheated zones, under the slab for floors on the ground. The partner surface
  in the unheated zone gets the mirrored construction. A window measure replaces the glazing
  by EnergyPlus's simple glazing model with the target U and g (the existing g when none is
  given). A target that does not improve a construction is refused.
* **Slab on ground.** A floor on EnergyPlus's ``Foundation`` boundary (Kiva) keeps the
  two-dimensional ground section the IDF import gives it (:mod:`thermocal.multizone.foundation`:
  the foundation wall, the soil of the file's ``Foundation:Kiva:Settings`` or EnergyPlus's
  defaults, 40 m of it); a preceding year of the same weather brings that ground to its
  periodic state. Insulation under the slab is a layer of the floor's construction below its
  slab, whose edge still meets the foundation wall, as in Kiva.
* **Heating.** Ideal heating at each zone's set point (the file's thermostat schedules for an
  IDF, the zone's ``heating_setpoint`` otherwise), the annual demand the heating delivered to
  the heated zones over the weather year.

The economics, CO2 and recommendation are those of the RC workflow
(:mod:`thermocal.retrofit.economics`). Beside the RC analysis, the detailed model must be the
RC building file's building (:func:`check_same_building`: heated floor area, external-wall and
window area within 25 %), and the weather one whole year for both
(:func:`thermocal.io.weather.check_full_year`).

References
----------
.. [1] ISO 6946:2017, Building components and building elements -- Thermal resistance and
   thermal transmittance -- Calculation methods (surface resistances, Table 7).
.. [2] Kruis, N. and Krarti, M. (2015), "Kiva: a numerical framework for foundation heat
   transfer simulation", Proceedings of Building Simulation 2015 (EnergyPlus's Foundation).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.retrofit.strategies import Measure, Strategy

__all__ = [
    "INSULATION_CONDUCTIVITY",
    "DetailedRetrofitResult",
    "apply_measures",
    "check_same_building",
    "load_detailed_building",
    "measure_surfaces",
    "simulate_strategies",
    "with_heating_setpoint",
]

#: Conductivity of the added insulation [W/(m K)] (EPS, XPS, mineral wool).
INSULATION_CONDUCTIVITY = 0.035
#: Density [kg/m3] and specific heat [J/(kg K)] of the added insulation (EPS).
INSULATION_DENSITY, INSULATION_SPECIFIC_HEAT = 30.0, 1450.0
#: A render or cladding thinner than this [m] stays outside added wall / roof insulation.
FINISH_MAX_THICKNESS = 0.03

#: ISO 6946 surface resistances (inside, outside) [m2 K/W] by component.
SURFACE_RESISTANCES: dict[str, tuple[float, float]] = {
    "walls": (0.13, 0.04),
    "roof": (0.10, 0.04),
    "attic_ceiling": (0.10, 0.10),  # heat flow up, unheated attic on the other side
    "cellar_ceiling": (0.17, 0.17),  # heat flow down, unheated cellar below
    "wall_to_unheated": (0.13, 0.13),
    "ground_floor": (0.17, 0.04),  # the construction's U; the ground section adds the ground
}

#: Where the insulation goes: "outside" (behind a thin finish) or "outermost".
_POSITION = {
    "walls": "outside",
    "roof": "outside",
    "attic_ceiling": "outermost",
    "cellar_ceiling": "outermost",
    "wall_to_unheated": "outermost",
    "ground_floor": "outermost",
}


# ----------------------------------------------------------------------------------------------
# the building
# ----------------------------------------------------------------------------------------------
def load_detailed_building(path: str | Path):
    """Read a multi-zone building (thermocal YAML or EnergyPlus IDF).

    Parameters
    ----------
    path : str or Path
        ``.yaml``/``.yml`` (``thermocal calibrate`` writes ``calibrated_building.yaml``) or
        ``.idf``.

    Returns
    -------
    thermocal.multizone.model.Building
    """
    import warnings

    from thermocal.multizone import load_building

    path = Path(path)
    if not path.exists():
        raise ThermocalInputError(
            f"detailed building {path} not found (give a thermocal building YAML or an "
            "EnergyPlus IDF)"
        )
    from thermocal.multizone.idf import IdfImportWarning

    with warnings.catch_warnings():
        # the import's list of unsupported objects: summarised by the simulation's notes; a
        # building file's warnings (an infiltration typed as a percentage...) are shown
        warnings.simplefilter("ignore", IdfImportWarning)
        return load_building(path)


def _heated(building) -> set[str]:
    return {name for name, zone in building.zones.items() if zone.conditioned}


def _is_door(building, surface) -> bool:
    info = getattr(building, "idf_info", None)
    kind = (getattr(info, "surface_types", {}) or {}).get(surface.name, "")
    return str(kind).upper() in ("DOOR", "GLASSDOOR")


def _surface_component(building, surface, heated: set[str]) -> str | None:
    """The measure component an opaque surface of a heated zone belongs to (None: none)."""
    if surface.zone not in heated:
        return None
    tilt = float(surface.tilt)
    vertical = 45.0 <= tilt <= 135.0
    if surface.boundary == "outdoors":
        if _is_door(building, surface):
            return None
        if vertical:
            return "walls"
        return "roof" if tilt < 45.0 else None
    if surface.boundary == "ground":
        return "ground_floor" if tilt > 135.0 else None
    if surface.boundary == "zone" and surface.other_zone not in heated:
        if vertical:
            return "wall_to_unheated"
        return "attic_ceiling" if tilt < 45.0 else "cellar_ceiling"
    return None


def measure_surfaces(building, component: str) -> list[str]:
    """Opaque surfaces (of heated zones) a U-value measure on ``component`` acts on.

    Parameters
    ----------
    building : thermocal.multizone.model.Building
    component : str
        ``walls``, ``roof``, ``attic_ceiling``, ``cellar_ceiling``, ``wall_to_unheated`` or
        ``ground_floor``.

    Returns
    -------
    list of str
        Surface names, in the building's order.
    """
    heated = _heated(building)
    return [
        s.name
        for s in building.surfaces.values()
        if _surface_component(building, s, heated) == component
    ]


def _measure_windows(building) -> list[str]:
    heated = _heated(building)
    return [
        w.name for w in building.windows.values() if building.surfaces[w.surface].zone in heated
    ]


def _components_found(building) -> dict[str, int]:
    heated = _heated(building)
    found: dict[str, int] = {}
    for s in building.surfaces.values():
        comp = _surface_component(building, s, heated)
        if comp:
            found[comp] = found.get(comp, 0) + 1
    if _measure_windows(building):
        found["windows"] = len(_measure_windows(building))
    return found


def _no_surfaces(building, measure: Measure) -> ThermocalInputError:
    found = _components_found(building)
    listing = ", ".join(f"{k} ({n})" for k, n in found.items()) or "none"
    return ThermocalInputError(
        f"measure '{measure.name}' acts on '{measure.component}', but building "
        f"'{building.name}' has no such surface of a heated zone (components found: {listing}); "
        "set the measure's 'component:' to one of them or remove the measure"
    )


def _insulation_layer(name: str, thickness: float, covered):
    """Insulation [m thick] that takes over the face properties of the layer it covers."""
    from thermocal.multizone.model import Material

    return Material(
        name=name,
        conductivity=INSULATION_CONDUCTIVITY,
        density=INSULATION_DENSITY,
        specific_heat=INSULATION_SPECIFIC_HEAT,
        thickness=thickness,
        thermal_absorptance=covered.thermal_absorptance,
        solar_absorptance=covered.solar_absorptance,
        roughness=covered.roughness,
    )


def _insulated_layers(building, construction: str, measure: Measure):
    """(new layer tuple outside -> inside, insulation Material, U before [W/(m2 K)])."""
    layers = list(building.constructions[construction].layers)
    mats = [building.materials[n] for n in layers]
    own = mats
    rsi, rse = SURFACE_RESISTANCES[measure.component]
    u_now = 1.0 / (rsi + rse + sum(m.resistance for m in own))
    if measure.u_value >= u_now - 1e-9:
        raise ThermocalInputError(
            f"measure '{measure.name}': target U {measure.u_value:g} W/(m2 K) does not improve "
            f"construction '{construction}' (U {u_now:.3f} W/(m2 K) with ISO 6946 surface "
            "resistances); lower the target or remove the measure"
        )
    thickness = INSULATION_CONDUCTIVITY * (1.0 / measure.u_value - 1.0 / u_now)
    at = 0
    if (
        _POSITION[measure.component] == "outside"
        and len(own) > 1
        and getattr(own[0], "thickness", 0.0) < FINISH_MAX_THICKNESS
    ):
        at += 1  # behind the render / cladding
    covered = mats[at] if at < len(mats) else mats[-1]
    layer = _insulation_layer(f"{measure.name} insulation ({construction})", thickness, covered)
    return tuple(layers[:at] + [layer.name] + layers[at:]), layer, u_now


def apply_measures(building, measures: Sequence[Measure]):
    """Copy of the building with U-value and window measures applied.

    Parameters
    ----------
    building : thermocal.multizone.model.Building
    measures : sequence of Measure
        ``u_value`` [W/(m2 K)] (and ``g_value`` [-] for windows) after the retrofit.

    Returns
    -------
    building : Building
    changes : list of dict
        Per measure and construction (or window type): ``measure``, ``construction``,
        ``u_before`` and ``u_after`` [W/(m2 K)], ``insulation_m`` [m] (opaque measures),
        ``surfaces``.

    Raises
    ------
    ThermocalInputError
        A ventilation measure, a component without surfaces, or a target that is no better.
    """
    from thermocal.multizone.model import Construction

    materials = dict(building.materials)
    constructions = dict(building.constructions)
    surfaces = dict(building.surfaces)
    window_types = dict(building.window_types)
    windows = dict(building.windows)
    changes: list[dict] = []
    for measure in measures:
        if measure.component in ("airtightness", "heat_recovery"):
            raise ThermocalInputError(
                f"measure '{measure.name}' ({measure.component}) is not available with the "
                "detailed model (its infiltration and ventilation come from the building file); "
                "leave it to the RC analysis or remove it"
            )
        if measure.component == "windows":
            changes.extend(_apply_window_measure(building, measure, window_types, windows))
            continue
        names = measure_surfaces(building, measure.component)
        if not names:
            raise _no_surfaces(building, measure)
        by_construction: dict[str, list[str]] = {}
        for name in names:
            by_construction.setdefault(building.surfaces[name].construction, []).append(name)
        for cname, on in by_construction.items():
            layers, layer, u_now = _insulated_layers(building, cname, measure)
            materials[layer.name] = layer
            new = f"{cname} + {measure.name}"
            constructions[new] = Construction(new, layers)
            for name in on:
                surface = surfaces[name]
                surfaces[name] = dataclasses.replace(surface, construction=new)
                if surface.boundary == "zone":  # the other side: the mirrored construction
                    partner = surfaces[surface.other_surface]
                    mirrored = f"{new} (reversed)"
                    constructions[mirrored] = Construction(mirrored, tuple(reversed(layers)))
                    surfaces[partner.name] = dataclasses.replace(partner, construction=mirrored)
            changes.append({
                "measure": measure.name, "component": measure.component,
                "construction": cname, "u_before": u_now, "u_after": float(measure.u_value),
                "insulation_m": layer.thickness, "surfaces": on,
                "area_m2": float(sum(building.net_area(n) for n in on)),
            })  # fmt: skip
    changed = building.replaced(
        materials=materials,
        constructions=constructions,
        surfaces=surfaces,
        window_types=window_types,
        windows=windows,
    )
    return changed, changes


def _apply_window_measure(building, measure: Measure, window_types: dict, windows: dict):
    """New glazing (EnergyPlus simple glazing model, target U and g) for the heated zones."""
    from thermocal.multizone.glazing import simple_glazing_system
    from thermocal.multizone.idf.constructions import window_type_from_glazing

    names = _measure_windows(building)
    if not names:
        raise _no_surfaces(building, measure)
    changes = []
    by_type: dict[str, list[str]] = {}
    for name in names:
        by_type.setdefault(building.windows[name].window_type, []).append(name)
    for tname, on in by_type.items():
        old = building.window_types[tname]
        u_target = float(measure.u_value) if measure.u_value is not None else old.u_value
        if measure.u_value is not None and u_target >= old.u_value - 1e-9:
            raise ThermocalInputError(
                f"measure '{measure.name}': target U {u_target:g} W/(m2 K) does not improve "
                f"window type '{tname}' (U {old.u_value:.3f} W/(m2 K)); lower the target or "
                "remove the measure"
            )
        g = float(measure.g_value) if measure.g_value is not None else old.shgc
        new = f"{tname} + {measure.name}"
        glazing = simple_glazing_system(u_target, g, name=new)
        window_types[new] = window_type_from_glazing(new, glazing)
        for name in on:
            windows[name] = dataclasses.replace(windows[name], window_type=new)
        changes.append({
            "measure": measure.name, "component": "windows", "construction": tname,
            "u_before": float(old.u_value), "u_after": u_target, "g_before": float(old.shgc),
            "g_after": g, "windows": on,
            "area_m2": float(sum(building.windows[n].area for n in on)),
        })  # fmt: skip
    return changes


def measure_areas(building, measures: Mapping[str, Measure]) -> dict[str, float]:
    """Area [m2] each measure's ``cost_per_m2`` applies to, per component (net opaque area of
    the surfaces it insulates, window area, heated floor area for ventilation measures)."""
    areas = {"airtightness": float(building.conditioned_floor_area)}
    areas["heat_recovery"] = areas["airtightness"]
    for measure in measures.values():
        if measure.component == "windows":
            names = _measure_windows(building)
            areas["windows"] = float(sum(building.windows[n].area for n in names))
        elif measure.component not in areas:
            names = measure_surfaces(building, measure.component)
            areas[measure.component] = float(sum(building.net_area(n) for n in names))
    return areas


# ----------------------------------------------------------------------------------------------
# simulation of the strategies
# ----------------------------------------------------------------------------------------------
@dataclass
class DetailedRetrofitResult:
    """Annual heating of each strategy simulated with the detailed model.

    Attributes
    ----------
    strategies : list of Strategy
    annual_kwh : ndarray [kWh]
        Heating delivered to the heated zones over the year, per strategy.
    monthly_kwh : DataFrame [kWh]
        Months x strategy codes.
    changes : dict
        Strategy code -> what :func:`apply_measures` changed.
    areas : dict [m2]
        Areas the measures' costs apply to.
    building_name, source : str
    heated_zones : list of str
    step : str
    notes : list of str
    timings : dict [s]
    """

    strategies: list[Strategy]
    annual_kwh: np.ndarray
    monthly_kwh: pd.DataFrame
    changes: dict[str, list[dict]]
    areas: dict[str, float]
    building_name: str
    source: str
    heated_zones: list[str]
    step: str
    notes: list[str] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def saving_pct(self) -> np.ndarray:
        """Saving of each strategy against the first (no retrofit) [%]."""
        return 100.0 * (1.0 - self.annual_kwh / self.annual_kwh[0])


def _variant_simulation():
    """:class:`~thermocal.multizone.simulation.Simulation` whose envelope can be swapped.

    The strategies share zones, geometry, schedules and weather: only constructions and window
    types change, so the sun, the irradiance on each orientation and the exterior convection
    computed for the first strategy serve all (the simulation's own caches, as
    ``Simulation.set_parameters`` uses them); the network is re-assembled and refactorised.
    """
    from thermocal.multizone.simulation import Simulation

    class VariantSimulation(Simulation):
        def use_building(self, building) -> None:
            """Simulate ``building`` next (same zones, surfaces and windows; other layers)."""
            self.building = building
            self._build()

    return VariantSimulation


def _default_step(building) -> str:
    info = getattr(building, "idf_info", None)
    per_hour = getattr(info, "timesteps_per_hour", None) if info is not None else None
    if per_hour:
        return f"{60 // int(per_hour)}min"
    return "15min"


def _with_year_before(weather: pd.DataFrame) -> tuple[pd.DataFrame, pd.Timestamp]:
    """The weather year preceded by a copy of itself (one year earlier) as warm-up."""
    index = pd.DatetimeIndex(weather.index)
    start = index[0]
    before = weather.copy()
    before.index = index - pd.DateOffset(years=1)
    before = before[before.index < start]
    return pd.concat([before, weather]), start


def simulate_strategies(
    building,
    weather: pd.DataFrame,
    metadata: Mapping | None,
    strategies: Sequence[Strategy],
    measures: Mapping[str, Measure],
    *,
    source: str | Path | None = None,
    step: str | None = None,
    warmup_year: bool | None = None,
    start=None,
    end=None,
    progress: Callable[[str], None] | None = None,
) -> DetailedRetrofitResult:
    """Annual heating of each strategy, simulated with the detailed model.

    Parameters
    ----------
    building : thermocal.multizone.model.Building
    weather : pandas.DataFrame
        Standard weather frame of the year (``temp_air`` [C], ``dni``, ``dhi`` [W/m2], ...).
    metadata : mapping
        Weather metadata (site, holidays).
    strategies : sequence of Strategy
        The first one must be "no retrofit".
    measures : mapping name -> Measure
    source : str or Path, optional
        The building file (recorded in the result).
    step : str, optional
        Time step; default the IDF's ``Timestep``, else 15 min.
    warmup_year : bool or None
        Simulate the year before (the same weather) first, so that slow parts (soil under a
        slab, time constants of months) start in their periodic state; else (or when the
        weather is shorter than a year) the model's week of warm-up. None (default): a warm-up
        year when the building has a ground section under a floor (``Building.foundations``).
    start, end : timestamp-like, optional
        A shorter period ``[start, end)`` (tests); default the whole weather frame.
    progress : callable, optional
        Called with a message before each strategy.

    Returns
    -------
    DetailedRetrofitResult
    """

    if not strategies or strategies[0].measures:
        raise ThermocalInputError("the first strategy must be '0' (no retrofit)")
    t0 = time.perf_counter()
    notes: list[str] = []
    heated = sorted(_heated(building), key=list(building.zones).index)
    if not any(building.zones[z].heating_setpoint is not None for z in heated):
        raise ThermocalInputError(
            f"building '{building.name}' has no zone with a heating set point: nothing to heat "
            "(set heating_setpoint on the heated zones, or give --setpoint C to heat every zone)"
        )
    step = step or _default_step(building)
    sim_weather, year_start = weather, None
    span = pd.DatetimeIndex(weather.index)[-1] - pd.DatetimeIndex(weather.index)[0]
    if warmup_year is None:
        warmup_year = bool(building.foundations)
    if warmup_year and start is None and end is None:
        if span >= pd.Timedelta(days=364):
            sim_weather, year_start = _with_year_before(weather)
        else:
            notes.append(
                f"weather of {span.days + 1} days (not a year): a week of warm-up, no warm-up year"
            )
    kwargs = {"step": step, "store_surfaces": False, "start": start, "end": end}
    timings: dict[str, float] = {"prepare": time.perf_counter() - t0}
    annual, monthly, changes = [], {}, {}
    variants = {}
    for strategy in strategies:
        variant, done = apply_measures(building, [measures[m] for m in strategy.measures])
        variants[strategy.code] = variant
        changes[strategy.code] = done
    sim = None
    for strategy in strategies:
        if progress is not None:
            progress(f"detailed model: strategy {strategy.label}")
        t1 = time.perf_counter()
        if sim is None:
            sim = _variant_simulation()(variants[strategy.code], sim_weather, metadata, **kwargs)
        else:
            sim.use_building(variants[strategy.code])
        result = sim.run()
        heating = result.heating[heated].sum(axis=1)
        if year_start is not None:
            heating = heating[heating.index >= year_start]
        hours = pd.Timedelta(step).total_seconds() / 3600.0
        kwh = heating * hours / 1000.0
        annual.append(float(kwh.sum()))
        monthly[strategy.code] = kwh.groupby(kwh.index.month).sum()
        timings[strategy.code] = time.perf_counter() - t1
        if strategy is strategies[0]:
            notes += list(sim.approximations())
    timings["total"] = time.perf_counter() - t0
    return DetailedRetrofitResult(
        strategies=list(strategies),
        annual_kwh=np.asarray(annual),
        monthly_kwh=pd.DataFrame(monthly),
        changes=changes,
        areas=measure_areas(building, measures),
        building_name=building.name,
        source=str(source) if source is not None else "",
        heated_zones=heated,
        step=str(step),
        notes=notes,
        timings=timings,
    )


# ----------------------------------------------------------------------------------------------
# configuration, economics and outputs (shared with the RC workflow)
# ----------------------------------------------------------------------------------------------
def load_detailed_config(path: str | Path):
    """A retrofit configuration for the detailed model alone (no measurements needed).

    The file is a ``thermocal retrofit`` configuration; ``weather``, ``measures``,
    ``strategies`` and ``economics`` are used, ``building`` and ``measurements`` may be left
    out.
    """
    from pydantic import ValidationError, model_validator

    from thermocal.io.yamlfile import read_yaml
    from thermocal.retrofit.config import (
        MeasurementsConfig,
        RetrofitConfig,
        _format_validation_error,
    )

    class DetailedRetrofitConfig(RetrofitConfig):
        building: Path | dict | None = None
        measurements: MeasurementsConfig | None = None

        @model_validator(mode="after")
        def _resolve_paths(self):
            base = self.base_dir
            if isinstance(self.building, Path) and not self.building.is_absolute():
                self.building = base / self.building
            if self.measurements is not None and not self.measurements.file.is_absolute():
                self.measurements.file = base / self.measurements.file
            if not self.weather.file.is_absolute():
                self.weather.file = base / self.weather.file
            return self

    path = Path(path)
    if not path.exists():
        raise ThermocalInputError(f"configuration file {path} not found")
    data = read_yaml(path, what="configuration file")
    if not isinstance(data, dict):
        raise ThermocalInputError(f"configuration {path} must be a YAML mapping")
    try:
        return DetailedRetrofitConfig.model_validate({**data, "base_dir": path.parent})
    except ValidationError as exc:
        raise ThermocalInputError(_format_validation_error(exc, str(path))) from None


def with_heating_setpoint(building, setpoint: float):
    """Copy of a building without set points whose zones are all heated at ``setpoint`` [C].

    For a building calibrated from temperatures alone (``thermocal calibrate`` identifies the
    heat, so its zones carry no set point) or a file without thermostats. A building that
    already heats some zones is refused (its unheated zones stay unheated).
    """
    from thermocal.retrofit.config import INDOOR_PROFILE_RANGE

    low, high = INDOOR_PROFILE_RANGE
    if not low <= float(setpoint) <= high:
        raise ThermocalInputError(
            f"--setpoint {setpoint:g} C is not an indoor temperature (expected {low:g}-{high:g} C)"
        )
    heated = [name for name, zone in building.zones.items() if zone.conditioned]
    if heated:
        raise ThermocalInputError(
            f"--setpoint is for a building without set points, but '{building.name}' already "
            f"heats {len(heated)} zone(s) ({', '.join(heated[:3])}): leave --setpoint out"
        )
    zones = {
        name: dataclasses.replace(zone, heating_setpoint=float(setpoint))
        for name, zone in building.zones.items()
    }
    return building.replaced(zones=zones)


def heated_detailed_building(building_path: str | Path, setpoint: float | None = None):
    """The detailed building of ``--detailed``, its zones heated at ``setpoint`` [C] when
    given (:func:`load_detailed_building`, :func:`with_heating_setpoint`)."""
    building = load_detailed_building(building_path)
    if setpoint is not None:
        building = with_heating_setpoint(building, setpoint)
    return building


#: Largest relative difference [-] between the RC building file's and the detailed model's
#: heated floor area, external-wall and window area still read as one building: the
#: project's own pairs agree within 0.1 % (the EnergyPlus house twin: 185.8 m2, walls 91.9 m2,
#: windows 27.9 m2; the demo house: 220 m2, 214.7 m2, 40.1 m2), a detailed model heated by
#: ``--setpoint`` counts its cellar too (demo house: 300 m2 against 220 m2, +36 %).
SAME_BUILDING_TOLERANCE = 0.25


def building_sizes(envelope, building) -> dict[str, tuple[float, float]]:
    """What the RC building file and the detailed model each say of the building's size.

    Parameters
    ----------
    envelope : thermocal.io.envelope.EnvelopeDescription
        The RC analysis's building file.
    building : thermocal.multizone.model.Building
        The detailed model (its heated zones: those with a set point).

    Returns
    -------
    dict
        ``"heated floor area"``, ``"external walls"`` (net of windows), ``"windows"`` ->
        (RC file, detailed model) [m2].
    """
    walls = measure_surfaces(building, "walls")
    return {
        "heated floor area": (
            float(envelope.heated_floor_area), float(building.conditioned_floor_area)
        ),
        "external walls": (
            envelope.area("external_wall"), float(sum(building.net_area(n) for n in walls))
        ),
        "windows": (
            envelope.area("window"),
            float(sum(building.windows[n].area for n in _measure_windows(building))),
        ),
    }


def _beyond(rc: float, detailed: float, tolerance: float) -> bool:
    """Whether two areas [m2] differ by more than ``tolerance`` (relative, either way)."""
    if rc <= 0.0 or detailed <= 0.0:
        return max(rc, detailed) > 0.0
    return max(rc, detailed) / min(rc, detailed) > 1.0 + tolerance


def check_same_building(
    envelope,
    building,
    *,
    rc_source: str,
    detailed_source: str,
    tolerance: float = SAME_BUILDING_TOLERANCE,
    heated_by_setpoint: bool = False,
) -> list[str]:
    """Refuse an RC building file and a detailed model of two different buildings.

    Their savings are printed side by side ("RC %"): they must describe one building. Compared
    (:func:`building_sizes`): heated floor area, external-wall area and window area. Two or
    three of them beyond the tolerance: two buildings (refused); one: a warning (a detailed
    model whose cellar ``--setpoint`` heats, a window the RC file left out).

    Parameters
    ----------
    envelope : thermocal.io.envelope.EnvelopeDescription
        The RC analysis's building file.
    building : thermocal.multizone.model.Building
        The detailed model, heated as it will be simulated.
    rc_source, detailed_source : str
        The two files, for the messages.
    tolerance : float
        Largest relative difference [-] of one quantity (:data:`SAME_BUILDING_TOLERANCE`).
    heated_by_setpoint : bool
        Whether ``--setpoint`` heated every zone of the detailed model (a calibrated building
        has no set points): its garage, attic or cellar then count as heated, so differences
        are a warning that says so, never a refusal.

    Returns
    -------
    list of str
        The warning when one quantity differs beyond the tolerance; empty when all agree.

    Raises
    ------
    ThermocalInputError
        When two or three quantities differ beyond the tolerance: the numbers of both files.
    """
    sizes = building_sizes(envelope, building)
    off = [name for name, pair in sizes.items() if _beyond(*pair, tolerance)]
    if not off:
        return []
    if heated_by_setpoint:
        listing = "; ".join(
            f"{name} {rc:,.1f} m2 in the RC file, {detailed:,.1f} m2 in the detailed model"
            for name, (rc, detailed) in sizes.items()
        )
        return [
            f"the detailed model {detailed_source} and the RC building file {rc_source} differ "
            f"in {' and '.join(off)} by more than {100 * tolerance:.0f} % ({listing}): "
            f"--setpoint heats all {len(building.zones)} zones of the detailed model, an "
            "unheated garage, attic or cellar too; give heating_setpoint to the heated zones in "
            "the building file instead of --setpoint, or check that the two files describe the "
            "same building, before comparing their savings"
        ]
    if len(off) >= 2:
        listing = "; ".join(
            f"{name} {rc:,.1f} m2 in the RC file, {detailed:,.1f} m2 in the detailed model"
            for name, (rc, detailed) in sizes.items()
        )
        raise ThermocalInputError(
            f"the RC building file {rc_source} and the detailed model {detailed_source} "
            f"describe different buildings: {listing} ({', '.join(off[:-1])} and {off[-1]} "
            f"differ by more than {100 * tolerance:.0f} %); their savings side by side would "
            "compare two buildings. "
            "Give the detailed model of the RC file's building, or run it alone with "
            "--detailed-only"
        )
    name = off[0]
    rc, detailed = sizes[name]
    return [
        f"the detailed model {detailed_source} and the RC building file {rc_source} differ in "
        f"{name} by more than {100 * tolerance:.0f} % ({rc:,.1f} m2 in the RC file, "
        f"{detailed:,.1f} m2 in the detailed model): check that they describe the same "
        "building and heat the same zones (--setpoint heats every zone, an unheated cellar "
        "too) before comparing their savings"
    ]


def run_detailed_retrofit(
    cfg, building_path: str | Path, *, setpoint: float | None = None, progress=None
):
    """The strategies of a retrofit configuration simulated with a detailed building.

    Parameters
    ----------
    cfg : RetrofitConfig
        Weather (the demand year), measures, strategies.
    building_path : str or Path
        Multi-zone building (YAML or IDF).
    setpoint : float or None [C]
        Heating set point of the zones that have none (:func:`with_heating_setpoint`).

    Returns
    -------
    DetailedRetrofitResult

    Raises
    ------
    ThermocalInputError
        Weather that is not one whole year (:func:`thermocal.io.weather.check_full_year`, the
        check of the RC analysis) or of another site than the building's (unless
        ``weather.site: weather``: then the weather file's site replaces the building's, with
        a warning and a note).
    """
    import logging

    from thermocal.io.weather import check_full_year, read_weather
    from thermocal.retrofit.workflow import building_at_weather_site, resolve_weather_path

    building = heated_detailed_building(building_path, setpoint)
    weather_path = resolve_weather_path(cfg.weather.file)
    weather, meta = read_weather(
        weather_path, format=cfg.weather.format, columns=cfg.weather.columns
    )
    check_full_year(weather, meta, source=str(cfg.weather.file))
    building, site_note = building_at_weather_site(
        building, cfg, building_source=str(building_path), weather_meta=meta
    )
    if site_note:  # at once; and in the detailed model's notes (results.json, the report)
        logging.getLogger("thermocal.retrofit").warning("%s", site_note)
    result = simulate_strategies(
        building,
        weather,
        meta,
        cfg.strategy_list(),
        cfg.measure_objects(),
        source=building_path,
        progress=progress,
    )
    if site_note:
        result.notes.insert(0, site_note)
    return result


def _detailed_track_record() -> list[dict]:
    """The detailed model's record on the EnergyPlus houses
    (:data:`thermocal.retrofit.track_record.DETAILED_CHECKS`), JSON-ready."""
    from thermocal.retrofit.track_record import DETAILED_CHECKS

    return [
        dataclasses.asdict(check) | {"reference": key} for key, check in DETAILED_CHECKS.items()
    ]


def detailed_results(result: DetailedRetrofitResult, cfg) -> dict:
    """Strategies, economics, CO2 and the recommendation of the detailed model (JSON-ready).

    The economics are :func:`thermocal.retrofit.economics.strategy_economics` and
    :func:`~thermocal.retrofit.economics.recommend` with the configuration's prices, the areas
    of the detailed model's surfaces and windows, and no interval (one simulation per strategy).
    """
    from thermocal.retrofit.economics import recommend, strategy_economics

    eco = cfg.economics
    table = strategy_economics(
        result.annual_kwh[:, None],
        result.strategies,
        cfg.measure_objects(),
        result.areas,
        system_efficiency=eco.system_efficiency,
        energy_price=eco.energy_price,
        emission_factor=eco.emission_factor,
    )
    savings = result.saving_pct
    best = recommend(table, savings)
    scenarios = []
    for i, s in enumerate(result.strategies):
        row = table.iloc[i]
        payback = float(row["payback_years"])
        scenarios.append({
            "code": s.code,
            "measures": list(s.measures),
            "annual_kWh": float(result.annual_kwh[i]),
            "saving_pct": float(savings[i]),
            "economics": {
                "investment": float(row["investment"]),
                "final_energy_kWh": float(row["final_energy_kWh"]),
                "cost_per_year": float(row["cost_per_year"]),
                "co2_kg_per_year": float(row["co2_kg_per_year"]),
                "cost_saving_per_year": float(row["cost_saving_per_year"]),
                "co2_saving_kg_per_year": float(row["co2_saving_kg_per_year"]),
                "payback_years": payback if np.isfinite(payback) else None,
            },
            "changes": result.changes[s.code],
        })  # fmt: skip
    return {
        "method": "detailed multi-zone model, ideal heating at the zones' set points, "
        "measures as added insulation layers and new glazing (thermocal.retrofit.detailed)",
        "building": result.building_name,
        "source": result.source,
        "heated_zones": result.heated_zones,
        "step": result.step,
        "annual_heating_demand_kWh": float(result.annual_kwh[0]),
        "monthly_heating_kWh": {
            str(code): [
                float(v) for v in result.monthly_kwh[code].reindex(range(1, 13), fill_value=0)
            ]
            for code in result.monthly_kwh.columns
        },
        "areas_m2": result.areas,
        "track_record": _detailed_track_record(),
        "scenarios": scenarios,
        "recommendation": None if best is None else best["code"],
        "recommendation_rule": None if best is None else best["rule"],
        "economics": {
            "currency": eco.currency,
            "energy_carrier": eco.energy_carrier,
            "system_efficiency": eco.system_efficiency,
            "energy_price": eco.energy_price,
            "emission_factor": eco.emission_factor,
        },
        "notes": result.notes,
        "timings_s": result.timings,
    }


def write_detailed_outputs(results: dict, out: Path) -> None:
    """``strategies_detailed.csv`` (one row per strategy) in ``out``."""
    rows = [
        {
            "code": s["code"],
            "measures": " + ".join(s["measures"]) or "-",
            "annual_kWh": s["annual_kWh"],
            "saving_pct": s["saving_pct"],
            **{k: v for k, v in s["economics"].items()},
        }
        for s in results["scenarios"]
    ]
    pd.DataFrame(rows).to_csv(Path(out) / "strategies_detailed.csv", index=False)
