"""What an IDF import read, derived, approximated and skipped.

:class:`IdfImportInfo` is attached to the imported Building as ``idf_info``: geometry, schedules,
gains, infiltration, set points and the list of approximations (``notes``) and of the classes not
represented (``unsupported``), which :func:`_warn_unsupported` summarises in ONE short
:class:`IdfImportWarning` (counts per kind; the classes that change the heat balance by name);
:func:`import_report` groups the full lists by kind (:func:`unsupported_kind`,
:func:`note_kind`). :meth:`IdfImportInfo.scheduled_inputs` evaluates the file's schedules
on a simulation grid (:class:`ScheduledInputs`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from thermocal.multizone.idf.loads import (
    InfiltrationInfo,
    InternalGainInfo,
    leakage_flow_linearised,
    people_sensible_coefficients,
    people_sensible_heat,
)
from thermocal.multizone.idf.schedules import ScheduleEvaluator


class IdfImportWarning(UserWarning):
    """IDF objects the importer does not represent (listed, never silently dropped)."""


def _constant_as_view(values: np.ndarray) -> np.ndarray:
    """``values`` in C order, or, when every entry is the same (all zero, all NaN), a read-only
    view of that one value in the same shape (no memory per step and zone)."""
    if values.size == 0:
        return np.ascontiguousarray(values)
    first = values.flat[0]
    same = np.isnan(values).all() if np.isnan(first) else (values == first).all()
    return np.broadcast_to(np.array(first), values.shape) if same else np.ascontiguousarray(values)


@dataclass
class ScheduledInputs:
    """The file's schedules evaluated on a simulation grid (rows = steps, columns = zones).

    An array whose entries are all the same (no gains, no set point) is a read-only view of that
    value: read it, index it or copy it, never write into it.

    Attributes
    ----------
    heating_setpoint, cooling_setpoint : ndarray [C]
        NaN where a zone has no such set point.
    gains_convective, gains_radiant : ndarray [W]
        Sensible internal gains entering the zone air / the zone's surfaces (the convective
        part includes the fan heat of Intake/Balanced ventilation).
    gains_latent : ndarray [W]
        Latent gains (reported, not part of the sensible balance).
    infiltration_ach : ndarray [1/h]
        Air changes from the schedule and the constant and wind terms (infiltration and
        ``ZoneVentilation:DesignFlowRate``, the latter zero where its outdoor limits close it).
    infiltration_ach_per_kelvin : ndarray [1/(h K)]
        Temperature term: air changes per kelvin of ``|T_zone - T_out|`` (applied in the time
        loop with the zone temperature of the previous step, as EnergyPlus does).
    people_per_kelvin, people_per_kelvin2 : ndarray [W/K], [W/K^2]
        Zone-temperature dependence of the sensible heat of People with an autocalculated
        sensible fraction: the gains above hold it at 22 C; the time loop adds
        ``b (T - 22) + c (T^2 - 22^2)`` with the zone air temperature of the previous step
        (EnergyPlus evaluates it at the zone's temperature), convective.
    ventilation : dict or None
        ``ZoneVentilation:DesignFlowRate`` objects with indoor-temperature limits, switched in the
        time loop on the zone temperature of the previous step (not part of the arrays above):
        ``zone`` (j,) column indices; per step and object ``ach`` [1/h] and ``ach_per_kelvin``
        [1/(h K)] when open (schedule, wind terms and outdoor limits applied), ``fan_heat`` [W]
        when open, ``minimum``, ``maximum`` [C] and ``delta`` [K] (open when
        ``minimum <= T_zone <= maximum`` and ``T_zone - T_out >= delta``); ``names`` (j,).
    """

    heating_setpoint: np.ndarray
    cooling_setpoint: np.ndarray
    gains_convective: np.ndarray
    gains_radiant: np.ndarray
    gains_latent: np.ndarray
    infiltration_ach: np.ndarray
    infiltration_ach_per_kelvin: np.ndarray
    people_per_kelvin: np.ndarray | None = None
    people_per_kelvin2: np.ndarray | None = None
    ventilation: dict | None = None
    #: (n_zones,) bool: zones whose thermostat's control type varies; a NaN set point there is
    #: "no such control on this step", not "use the zone's constant set point"
    setpoint_switched: np.ndarray | None = None
    #: (steps, zones) [-]: 0 where the zone's ideal-loads system is off for heating / cooling
    #: (its availability schedules), 1 elsewhere; the zone has no such set point there
    heating_available: np.ndarray | None = None
    cooling_available: np.ndarray | None = None


@dataclass
class IdfImportInfo:
    """What the importer read, derived or approximated; attached to the Building as ``idf_info``.

    Attributes
    ----------
    source : str
        File path.
    version : tuple of int
    unsupported : dict
        ``{class name: count}`` of the objects not represented (also in the warning).
    notes : list of str
        Approximations made (time-varying schedules reduced to constants, ...).
    surface_vertices : dict
        ``{surface or window name: (n, 3) array}`` world coordinates [m] (x east, y north, z up).
    surface_types : dict
        ``{surface name: EnergyPlus surface type}`` (Wall, Floor, Roof, Ceiling, Door, Window, ...).
    glazing : dict
        ``{window construction name: LayeredGlazing or SimpleGlazing}``.
    internal_gains : list of InternalGainInfo
    setpoint_schedules : dict
        ``{zone: (heating schedule or None, cooling schedule or None)}``.
    infiltration_schedules : dict
        ``{zone: [schedule names]}``.
    zone_multipliers : dict
        ``{zone: multiplier}`` (EnergyPlus zone multiplier; not applied by the model).
    schedules : ScheduleEvaluator
    """

    source: str
    version: tuple[int, int]
    unsupported: dict[str, int] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    surface_vertices: dict[str, np.ndarray] = field(default_factory=dict)
    surface_types: dict[str, str] = field(default_factory=dict)
    glazing: dict = field(default_factory=dict)
    internal_gains: list[InternalGainInfo] = field(default_factory=list)
    setpoint_schedules: dict[str, tuple[str | None, str | None]] = field(default_factory=dict)
    #: zones whose ZoneControl:Thermostat has a varying Control Type Schedule: ``{zone:
    #: (control type schedule, {control type: (heating schedule or None, cooling schedule or
    #: None)})}``; on a step whose control type has no entry (0: uncontrolled) the zone floats.
    #: ``setpoint_schedules`` then holds the most frequent control type's (schedules='constant')
    setpoint_control: dict[str, tuple[str, dict]] = field(default_factory=dict)
    #: zones whose ideal-loads system is available only part of the time: ``{zone: (schedules
    #: switching its heating, schedules switching its cooling)}`` (its Availability Schedule
    #: and its Heating / Cooling Availability Schedule); off where any is 0
    ideal_loads_availability: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = field(
        default_factory=dict
    )
    #: zones whose thermostat holds the operative temperature: ``{zone: radiative fraction f}``
    #: (``ZoneControl:Thermostat:OperativeTemperature``; the ideal loads hold
    #: ``(1 - f) T_air + f T_mrt`` at the set points)
    operative_fraction: dict[str, float] = field(default_factory=dict)
    infiltration_schedules: dict[str, list[str]] = field(default_factory=dict)
    zone_multipliers: dict[str, float] = field(default_factory=dict)
    schedules: ScheduleEvaluator | None = None
    infiltration: list[InfiltrationInfo] = field(default_factory=list)
    zone_wind_factor: dict[str, float] = field(default_factory=dict)
    zone_nominal_ach: dict[str, float] = field(default_factory=dict)
    zone_volume: dict[str, float] = field(default_factory=dict)
    #: RunPeriod 'Use Weather File Rain Indicators' (Yes when blank): wet outside faces on rain
    #: steps
    use_weather_rain: bool = True
    run_period: tuple | None = None  # site.RunPeriod: name, begin/end month, day, year, where
    #: ``Timestep``: steps per hour of the file (EnergyPlus' default 6 when absent)
    timesteps_per_hour: int | None = None
    shading_surfaces: list = field(default_factory=list)  # shading.ShadingSurface
    subsurfaces_of: dict[str, list[str]] = field(default_factory=dict)  # host -> windows, doors
    #: ShadowCalculation: sunlit fractions of the first day reused for this many days (EnergyPlus'
    #: "Periodic" default 20); 0 = every time step ("Timestep")
    shadow_update_days: int = 20
    #: SurfaceConvectionAlgorithm:Inside / :Outside as written ({"inside": "TARP", ...})
    convection: dict[str, str] = field(default_factory=dict)
    #: the Zone objects' non-blank Zone Inside / Outside Convection Algorithm as written
    #: ({"inside": {zone: "TrombeWall"}, "outside": {...}}); the model's algorithms are
    #: building-wide, so these are only noted (:meth:`network_options`)
    zone_convection: dict[str, dict[str, str]] = field(default_factory=dict)
    #: zone -> its declared HVAC equipment and the radiant share of their heat
    #: (:func:`thermocal.multizone.idf.hvac.zone_heat_delivery`); the identification's default
    #: heat form uses it
    zone_heat_delivery: dict = field(default_factory=dict)
    #: the Building object's Solar Distribution as written (EnergyPlus' default FullExterior)
    solar_distribution: str = "FullExterior"
    #: the Building object's warm-up: Temperature Convergence Tolerance Value [K], Maximum and
    #: Minimum Number of Warmup Days (EnergyPlus 25.2's defaults 0.4, 25, 1)
    warmup: dict = field(
        default_factory=lambda: {"tolerance_K": 0.4, "maximum_days": 25, "minimum_days": 1}
    )

    def report(self) -> dict:
        """What was not simulated and what was approximated, by kind (see
        :func:`import_report`)."""
        return import_report(self)

    def network_options(self):
        """NetworkOptions honouring the file's convection algorithms, and notes on fallbacks."""
        from thermocal.multizone.network import NetworkOptions

        notes = []
        inside = self.convection.get("inside", "TARP")
        outside = self.convection.get("outside", "DOE-2")
        interior = {"TARP": "tarp", "SIMPLE": "simple"}.get(inside.upper())
        if inside.upper() == "ADAPTIVECONVECTIONALGORITHM":
            interior = "tarp"
            notes.append(
                "SurfaceConvectionAlgorithm:Inside AdaptiveConvectionAlgorithm approximated by "
                "TARP (its selections for a zone without HVAC are other natural-convection "
                "correlations: Fohanno-Polidori walls, Alamdari-Hammond horizontal faces)"
            )
        elif interior is None:
            interior = "tarp"
            notes.append(f"SurfaceConvectionAlgorithm:Inside {inside} is not available: TARP used")
        exterior = {
            "DOE-2": "doe2",
            "TARP": "tarp",
            "MOWITT": "mowitt",
            "SIMPLECOMBINED": "simple_combined",
        }.get(outside.upper())
        if outside.upper() == "ADAPTIVECONVECTIONALGORITHM":
            exterior = "tarp"
            notes.append(
                "SurfaceConvectionAlgorithm:Outside AdaptiveConvectionAlgorithm approximated by "
                "TARP (its default selections: TARP windward/leeward walls; roofs by the "
                "ClearRoof correlation)"
            )
        elif exterior is None:
            exterior = "doe2"
            notes.append(
                f"SurfaceConvectionAlgorithm:Outside {outside} is not available: DOE-2 used"
            )
        notes += self._zone_convection_notes("inside", inside, interior)
        notes += self._zone_convection_notes("outside", outside, exterior)
        return NetworkOptions(interior_convection=interior, exterior_convection=exterior), notes

    def _zone_convection_notes(self, side: str, written: str, used: str) -> list[str]:
        """Notes on the Zone objects' own convection algorithm of one side (``"inside"`` or
        ``"outside"``) where it differs from the building-wide one the model uses (``used``, a
        NetworkOptions key; ``written``: the file's SurfaceConvectionAlgorithm:<Side>), zones of
        the same algorithm grouped in one note."""
        asked = self.zone_convection.get(side, {})
        if not asked:
            return []
        keys = ZONE_CONVECTION_KEYS[side]
        label = f"Zone {side.capitalize()} Convection Algorithm"
        building = f"SurfaceConvectionAlgorithm:{side.capitalize()}"
        name = CONVECTION_NAMES[used]
        if side not in self.convection:
            used_text = f"{name} (EnergyPlus' default {building})"
        elif keys.get(written.upper()) == used:
            used_text = f"the file's {name} ({building})"
        else:
            used_text = f"{name} (in place of the file's {building} {written})"
        by_algorithm: dict[str, tuple[str, list[str]]] = {}  # upper case: (as first written, zones)
        for zone, algorithm in self.zone_convection[side].items():
            if keys.get(algorithm.upper()) != used:
                by_algorithm.setdefault(algorithm.upper(), (algorithm, []))[1].append(zone)
        notes = []
        for algorithm, zones in by_algorithm.values():
            names = ", ".join(f"'{z}'" for z in zones)
            head = f"Zone {names}" if len(zones) == 1 else f"Zones {names}"
            if algorithm.upper() in keys:
                note = (
                    f"{head}: {label} {algorithm} is not applied per zone (the model's convection "
                    f"algorithms are building-wide): {used_text} used for every zone"
                )
            else:
                note = (
                    f"{head}: {label} {algorithm} is not available: {used_text} used for its "
                    "surfaces"
                )
            if side == "inside" and algorithm.upper() == "TROMBEWALL":
                note += (
                    "; TrombeWall is EnergyPlus' correlation for a narrow glazed cavity (ISO "
                    "15099, the cavity's two large faces): without it thermocal ran 5-7 K warmer "
                    "than EnergyPlus in the cavity and in the room behind the wall in January "
                    "(about 2 K in July; NREL's PassiveTrombeWall, hourly mean bias)"
                )
            notes.append(note)
        return notes

    def scheduled_inputs(self, zones, times, step, weather) -> ScheduledInputs:
        """Set points, internal gains and infiltration of every zone on a simulation grid.

        Parameters
        ----------
        zones : sequence of str
            Column order.
        times : pandas.DatetimeIndex
            Step starts.
        step : pandas.Timedelta
        weather : pandas.DataFrame
            The weather on the grid (``wind_speed`` [m/s] used when present).

        Returns
        -------
        ScheduledInputs
        """
        n, nz = len(times), len(zones)
        column = {z: i for i, z in enumerate(zones)}
        sched = self.schedules

        def values(name):
            return np.ones(n) if name is None else sched.on_grid(name, times, step)

        heating = np.full((nz, n), np.nan)
        cooling = np.full((nz, n), np.nan)
        switched = np.zeros(nz, dtype=bool)
        zone_setpoints = {z: (None, None) for z in self.setpoint_control}
        zone_setpoints.update(self.setpoint_schedules)
        for zone, (heat_name, cool_name) in zone_setpoints.items():
            if zone not in column:
                continue
            if zone in self.setpoint_control:
                heat, cool = self._controlled_setpoints(zone, values)
                heating[column[zone]], cooling[column[zone]] = heat, cool
                switched[column[zone]] = True
                continue
            if heat_name:
                heating[column[zone]] = values(heat_name)
            if cool_name:
                cooling[column[zone]] = values(cool_name)
        available = {"heating": np.ones((nz, n)), "cooling": np.ones((nz, n))}
        for zone, switches in self.ideal_loads_availability.items():
            if zone not in column:
                continue
            for kind, names in zip(("heating", "cooling"), switches, strict=True):
                for name in names:
                    available[kind][column[zone]] *= values(name) > 0.0
        convective = np.zeros((nz, n))
        radiant = np.zeros((nz, n))
        latent = np.zeros((nz, n))
        people_b = np.zeros((nz, n))
        people_c = np.zeros((nz, n))
        for gain in self.internal_gains:
            if gain.zone not in column:
                continue
            fraction = values(gain.schedule)
            if gain.people_count > 0 and gain.activity_schedule is not None:
                # People: number x (sensible heat per person at the step's activity)
                activity = sched.on_grid(gain.activity_schedule, times, step)
                if gain.sensible_fraction is None:
                    sensible = people_sensible_heat(activity)
                    _, b, c = people_sensible_coefficients(activity)
                    people_b[column[gain.zone]] += gain.people_count * fraction * b
                    people_c[column[gain.zone]] += gain.people_count * fraction * c
                else:
                    sensible = activity * gain.sensible_fraction
                level = gain.people_count * fraction * sensible
                lat = gain.people_count * fraction * (activity - sensible)
            else:
                level = gain.design_level * fraction
                lat = gain.latent_level * fraction
            c = column[gain.zone]
            radiant[c] += level * gain.radiant_fraction
            convective[c] += level * (1.0 - gain.radiant_fraction)
            latent[c] += lat
        wind = (
            np.nan_to_num(weather["wind_speed"].to_numpy(dtype=float))
            if "wind_speed" in weather
            else np.zeros(n)
        )
        ach = np.zeros((nz, n))
        ach_dt = np.zeros((nz, n))
        temp_air = (
            weather["temp_air"].to_numpy(dtype=float) if "temp_air" in weather else np.zeros(n)
        )
        gated = []
        for inf in self.infiltration:
            if inf.zone not in column:
                continue
            c = column[inf.zone]
            if inf.leakage is not None:
                # Sherman-Grimsrud with the weather file's wind speed (EnergyPlus)
                q0, q1 = leakage_flow_linearised(inf.leakage, temp_air, wind)
                per = 3600.0 / self.zone_volume[inf.zone] * values(inf.schedule)
                ach[c] += q0 * per
                ach_dt[c] += q1 * per
                continue
            a, b, c_wind, d = inf.coefficients
            v = wind * self.zone_wind_factor.get(inf.zone, 1.0)
            base = inf.design_flow * 3600.0 / self.zone_volume[inf.zone] * values(inf.schedule)
            gate = inf.outdoor_gate(sched, times, step, temp_air, v)
            if gate is not None:
                base = base * gate
            # fan heat with the air [W]: flow [m3/s] x pressure rise / efficiency (the
            # temperature term of the flow left out: it needs the zone temperature)
            open_ach = base * (a + c_wind * v + d * v * v)
            fan = open_ach * self.zone_volume[inf.zone] / 3600.0 * inf.fan_heat_per_flow
            if inf.indoor_limits is not None:
                limits = [
                    values(name) * 0.0 + value if name is None else values(name)
                    for value, name in inf.indoor_limits
                ]
                gated.append((c, open_ach, base * b, fan, *limits, inf.name))
                continue
            ach[c] += open_ach
            ach_dt[c] += base * b
            if inf.fan_heat_per_flow > 0:
                convective[c] += fan
        ventilation = None
        if gated:
            ventilation = {
                "zone": np.array([g[0] for g in gated], dtype=np.int64),
                "names": [g[7] for g in gated],
            }
            for i, key in enumerate(
                ("ach", "ach_per_kelvin", "fan_heat", "minimum", "maximum", "delta"), start=1
            ):
                ventilation[key] = np.ascontiguousarray(
                    np.stack([np.broadcast_to(g[i], (n,)) for g in gated], axis=1), dtype=float
                )
        # built zone by zone (each zone's series contiguous; a column of a steps x zones array
        # is strided: the grid's January took 0.095 s, now 0.06 s), handed over steps x zones
        return ScheduledInputs(
            *(
                _constant_as_view(a.T)
                for a in (heating, cooling, convective, radiant, latent, ach, ach_dt)
            ),
            _constant_as_view(people_b.T),
            _constant_as_view(people_c.T),
            ventilation,
            switched,
            _constant_as_view(available["heating"].T),
            _constant_as_view(available["cooling"].T),
        )

    def internal_gains_profile(self, times) -> pd.DataFrame:  # noqa: F821 (pandas lazily)
        """Hourly internal sensible gains per zone [W] from the file's schedules.

        Parameters
        ----------
        times : pandas.DatetimeIndex
            Evaluation times; each takes the value of the hour of the year it falls in (the
            schedule calendar year is reused for every year).

        Returns
        -------
        pandas.DataFrame [W], one column per zone with gains.

        Notes
        -----
        The imported zones already carry the annual mean of these gains as the constant
        ``Zone.internal_gains``; to simulate the hourly profile instead, set those to 0 and pass
        the profile as heat input (otherwise the gains are counted twice).
        """
        import pandas as pd

        hour_of_year = _hour_of_year(times, self.schedules.n_days)
        out = {}
        for gain in self.internal_gains:
            values = (
                np.ones(self.schedules.n_days * 24)
                if gain.schedule is None
                else self.schedules.hourly(gain.schedule)
            )
            series = gain.design_level * values[hour_of_year]
            out[gain.zone] = out.get(gain.zone, 0.0) + series
        return pd.DataFrame(out, index=times)

    def _controlled_setpoints(self, zone: str, values) -> tuple[np.ndarray, np.ndarray]:
        """Heating and cooling set points [C] (NaN: none) of a zone whose thermostat's control
        type varies, with ``values(schedule name)`` evaluating a schedule on the grid."""
        control_schedule, by_type = self.setpoint_control[zone]
        control = np.rint(values(control_schedule)).astype(int)
        heat = np.full(control.shape, np.nan)
        cool = np.full(control.shape, np.nan)
        for kind, (heat_name, cool_name) in by_type.items():
            on = control == kind
            if not on.any():
                continue
            if heat_name:
                heat[on] = values(heat_name)[on]
            if cool_name:
                cool[on] = values(cool_name)[on]
        return heat, cool

    def setpoint_profile(self, times) -> pd.DataFrame:  # noqa: F821
        """Hourly heating and cooling set points [C], columns ``(zone, "heating"|"cooling")``."""
        import pandas as pd

        hour_of_year = _hour_of_year(times, self.schedules.n_days)
        out = {}
        for zone in self.setpoint_control:
            heat, cool = self._controlled_setpoints(
                zone, lambda name: self.schedules.hourly(name)[hour_of_year]
            )
            for kind, series in (("heating", heat), ("cooling", cool)):
                if np.isfinite(series).any():
                    out[(zone, kind)] = series
        for zone, (heating, cooling) in self.setpoint_schedules.items():
            if zone in self.setpoint_control:
                continue
            for kind, name in (("heating", heating), ("cooling", cooling)):
                if name is not None:
                    out[(zone, kind)] = self.schedules.hourly(name)[hour_of_year]
        # no set point where the zone's ideal-loads system is switched off
        for zone, switches in self.ideal_loads_availability.items():
            for kind, names in zip(("heating", "cooling"), switches, strict=True):
                if (zone, kind) not in out:
                    continue
                series = np.array(out[(zone, kind)], dtype=float)
                for name in names:
                    series[self.schedules.hourly(name)[hour_of_year] <= 0.0] = np.nan
                out[(zone, kind)] = series
        return pd.DataFrame(out, index=times)


def _hour_of_year(times, n_days: int) -> np.ndarray:
    import pandas as pd

    times = pd.DatetimeIndex(times)
    hours = (times.day_of_year.to_numpy() - 1) * 24 + times.hour.to_numpy()
    return np.minimum(hours, n_days * 24 - 1)


#: Classes the importer does not read because they do not change the heat balance of the zones:
#: outputs, reporting, sizing, costs, simulation control (prefixes of class names, any case).
HARMLESS_CLASS_PREFIXES = (
    "Output",
    "Meter:",
    "Sizing:",
    "SizingPeriod:",
    "LifeCycleCost:",
    "UtilityCost:",
    "ComponentCost:",
    "CurrencyType",
    "SimulationControl",
    "ScheduleTypeLimits",
    "ConvergenceLimits",
    "HeatBalanceAlgorithm",
    "ZoneAirHeatBalanceAlgorithm",
    "ZoneAirContaminantBalance",
    "PerformancePrecisionTradeoffs",
    "EnvironmentalImpactFactors",
    "FuelFactors",
    "Parametric:",
    "Site:Precipitation",
    "Site:WaterMainsTemperature",
    "Site:GroundTemperature:Shallow",
    "Site:GroundTemperature:Deep",
    "Site:GroundTemperature:Undisturbed",
    "Exterior:Lights",
    "Exterior:FuelEquipment",
    "Exterior:WaterEquipment",
)

#: HVAC and plant classes: the model replaces the file's systems by ideal heating and cooling at
#: the thermostat set points (free float without them), so these are not simulated by design.
HVAC_CLASS_PREFIXES = (
    "ZoneHVAC:",
    "AirLoopHVAC",
    "AirTerminal:",
    "PlantLoop",
    "CondenserLoop",
    "PlantEquipment",
    "CondenserEquipment",
    "PlantComponent:",
    "Coil:",
    "CoilSystem:",
    "Fan:",
    "Pump:",
    "HeaderedPumps:",
    "Boiler:",
    "Chiller:",
    "ChillerHeater:",
    "CoolingTower:",
    "EvaporativeFluidCooler:",
    "FluidCooler:",
    "EvaporativeCooler:",
    "HeatPump:",
    "HeatExchanger:",
    "Humidifier:",
    "Dehumidifier:",
    "WaterHeater:",
    "ThermalStorage:",
    "DistrictHeating",
    "DistrictCooling",
    "Branch",
    "Connector",
    "Pipe:",
    "Duct",
    "NodeList",
    "OutdoorAir:",
    "Controller:",
    "SetpointManager:",
    "AvailabilityManager",
    "HVACTemplate:",
    "DesignSpecification:",
    "UnitarySystemPerformance:",
    "ZoneTerminalUnitList",
    "SpaceHVAC:",
    "ZoneControl:Humidistat",
    "Curve:",
    "Table:",
    "FluidProperties:",
    "DemandManager",
    "LoadProfile:Plant",
    "TemperingValve",
    "ElectricLoadCenter:",
    "Generator:",
)

_HARMLESS_UPPER = tuple(p.upper() for p in HARMLESS_CLASS_PREFIXES)
_HVAC_UPPER = tuple(p.upper() for p in HVAC_CLASS_PREFIXES)

#: Kinds of unsupported classes, in report order, with what the kind means for the result.
UNSUPPORTED_KINDS = {
    "physics": "not simulated although they change the heat balance: the result differs from "
    "EnergyPlus' by their effect",
    "hvac": "HVAC and plant: replaced by ideal heating/cooling at the set points (free float "
    "without them)",
    "harmless": "outputs, sizing, costs and simulation control: no effect on the heat balance",
}


def unsupported_kind(class_name: str) -> str:
    """``"harmless"``, ``"hvac"`` or ``"physics"`` for a class the importer does not read.

    Every class that is neither an output/sizing/control class (:data:`HARMLESS_CLASS_PREFIXES`)
    nor HVAC equipment (:data:`HVAC_CLASS_PREFIXES`) counts as changing the physics.
    """
    key = class_name.upper()
    if key.startswith(_HARMLESS_UPPER):
        return "harmless"
    if key.startswith(_HVAC_UPPER):
        return "hvac"
    return "physics"


#: The model's convection algorithms (NetworkOptions keys) as EnergyPlus names them.
CONVECTION_NAMES = {
    "tarp": "TARP",
    "simple": "Simple",
    "doe2": "DOE-2",
    "mowitt": "MoWiTT",
    "simple_combined": "SimpleCombined",
}

#: EnergyPlus' per-zone algorithms the model has (upper case -> NetworkOptions key), by side.
ZONE_CONVECTION_KEYS = {
    "inside": {"TARP": "tarp", "SIMPLE": "simple"},
    "outside": {
        "DOE-2": "doe2",
        "TARP": "tarp",
        "MOWITT": "mowitt",
        "SIMPLECOMBINED": "simple_combined",
    },
}

#: How a note on an input EnergyPlus ignores, refuses or warns about begins: such notes name
#: their object and are repeated in full in the import warning (:func:`import_summary`).
EP_CHECK = "EnergyPlus check: "

#: Kinds of import notes, in report order: (kind, label, test on the note's text).
NOTE_KINDS = (
    (
        "constant_schedules",
        "for schedules='constant' only (identify/calibrate's constant mode)",
        lambda n: "schedules='constant'" in n or " varies (" in n,
    ),
    ("hvac", "HVAC replaced", lambda n: n.startswith("HVAC equipment")),
    (
        "ideal_loads",
        "ideal loads settings",
        lambda n: n.startswith("Ideal loads settings"),
    ),
    (
        "period",
        "simulated period",
        lambda n: "first RunPeriod" in n or "Weather File Run Periods" in n,
    ),
    ("calendar", "schedule calendar", lambda n: n.startswith("schedule calendar")),
    ("ventilation", "ventilation", lambda n: "ZoneVentilation" in n),
    ("solar", "solar distribution", lambda n: n.startswith("Solar Distribution")),
    ("convection", "convection algorithms", lambda n: "ConvectionAlgorithm" in n),
    ("energyplus", "inputs EnergyPlus ignores or warns about", lambda n: n.startswith(EP_CHECK)),
    ("ground", "ground", lambda n: "ground" in n.lower()),
    ("other", "other", lambda n: True),
)


def note_kind(note: str) -> str:
    """The kind (first of :data:`NOTE_KINDS` that matches) of an import note."""
    return next(kind for kind, _, test in NOTE_KINDS if test(note))


def import_report(info: IdfImportInfo) -> dict:
    """What the import did not simulate and approximated, grouped for reports (JSON-ready).

    Returns
    -------
    dict
        ``unsupported``: ``{kind: {class: count}}`` for the kinds of :data:`UNSUPPORTED_KINDS`;
        ``unsupported_meaning``: the meaning of each kind; ``notes``: ``{kind: [note, ...]}``
        for the kinds of :data:`NOTE_KINDS`; ``solar_distribution``.
    """
    unsupported: dict[str, dict[str, int]] = {kind: {} for kind in UNSUPPORTED_KINDS}
    for cls, count in info.unsupported.items():
        unsupported[unsupported_kind(cls)][cls] = count
    notes: dict[str, list[str]] = {kind: [] for kind, _, _ in NOTE_KINDS}
    for note in info.notes:
        notes[note_kind(note)].append(note)
    return {
        "source": info.source,
        "unsupported": unsupported,
        "unsupported_meaning": dict(UNSUPPORTED_KINDS),
        "notes": {k: v for k, v in notes.items() if v},
        "solar_distribution": info.solar_distribution,
    }


def import_summary(source: str, info: IdfImportInfo) -> str:
    """A few lines for the terminal: counts per kind of note, the classes that change the physics
    by name, the HVAC classes by count; the harmless ones (outputs, sizing, ...) are left out
    (the full lists: :func:`import_report`)."""
    report = import_report(info)
    lines = []
    labels = {kind: label for kind, label, _ in NOTE_KINDS}
    notes = report["notes"]
    constant = len(notes.get("constant_schedules", []))
    if len(info.notes) > constant:
        counts = ", ".join(
            f"{len(v)} {labels[k]}" for k, v in notes.items() if k != "constant_schedules"
        )
        lines.append(f"{source}: {len(info.notes) - constant} import notes ({counts}).")
        lines.extend(notes.get("hvac", []))
        lines.extend(notes.get("ideal_loads", []))
        lines.extend(notes.get("period", []))
        lines.extend(notes.get("energyplus", []))
    if constant:
        lines.append(
            f"{source}: {constant} more notes apply only where the file's schedules are "
            "replaced by constants (schedules='constant')."
        )
    physics = report["unsupported"]["physics"]
    if physics:
        listing = ", ".join(f"{cls} ({n})" for cls, n in physics.items())
        lines.append(
            f"NOT SIMULATED although they change the heat balance ({sum(physics.values())} "
            f"objects): {listing}."
        )
    group = report["unsupported"]["hvac"]
    if group:
        lines.append(
            f"{sum(group.values())} objects of {len(group)} classes not represented, "
            f"{UNSUPPORTED_KINDS['hvac']}."
        )
    # the harmless classes (outputs, sizing, ...) stay quiet: listed in the report only
    if lines:
        lines.append(
            "Full lists: summary.json 'idf_import' (thermocal simulate) or "
            "building.idf_info.report()."
        )
    return "\n".join(lines)


def _warn_unsupported(source: str, info: IdfImportInfo) -> None:
    message = import_summary(source, info)
    if message:
        warnings.warn(message, IdfImportWarning, stacklevel=5)
