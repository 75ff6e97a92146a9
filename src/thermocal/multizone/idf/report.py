"""What an IDF import read, derived, approximated and skipped.

:class:`IdfImportInfo` is attached to the imported Building as ``idf_info``: geometry, schedules,
gains, infiltration, set points and the list of approximations (``notes``) and of the classes not
represented (``unsupported``), which :func:`_warn_unsupported` reports in ONE
:class:`IdfImportWarning`. :meth:`IdfImportInfo.scheduled_inputs` evaluates the file's schedules
on a simulation grid (:class:`ScheduledInputs`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from thermocal.multizone.idf.loads import (
    InfiltrationInfo,
    InternalGainInfo,
    people_sensible_coefficients,
    people_sensible_heat,
)
from thermocal.multizone.idf.schedules import ScheduleEvaluator


class IdfImportWarning(UserWarning):
    """IDF objects the importer does not represent (listed, never silently dropped)."""


@dataclass
class ScheduledInputs:
    """The file's schedules evaluated on a simulation grid (rows = steps, columns = zones).

    Attributes
    ----------
    heating_setpoint, cooling_setpoint : ndarray [C]
        NaN where a zone has no such set point.
    gains_convective, gains_radiant : ndarray [W]
        Sensible internal gains entering the zone air / the zone's surfaces.
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
    infiltration_schedules: dict[str, list[str]] = field(default_factory=dict)
    zone_multipliers: dict[str, float] = field(default_factory=dict)
    schedules: ScheduleEvaluator | None = None
    infiltration: list[InfiltrationInfo] = field(default_factory=list)
    zone_wind_factor: dict[str, float] = field(default_factory=dict)
    zone_nominal_ach: dict[str, float] = field(default_factory=dict)
    zone_volume: dict[str, float] = field(default_factory=dict)
    run_period: tuple | None = None  # (name, begin month, day, end month, day, begin year|None)
    #: ``Timestep``: steps per hour of the file (EnergyPlus' default 6 when absent)
    timesteps_per_hour: int | None = None
    shading_surfaces: list = field(default_factory=list)  # shading.ShadingSurface
    subsurfaces_of: dict[str, list[str]] = field(default_factory=dict)  # host -> windows, doors
    #: ShadowCalculation: sunlit fractions of the first day reused for this many days (EnergyPlus'
    #: "Periodic" default 20); 0 = every time step ("Timestep")
    shadow_update_days: int = 20
    #: SurfaceConvectionAlgorithm:Inside / :Outside as written ({"inside": "TARP", ...})
    convection: dict[str, str] = field(default_factory=dict)
    #: the Building object's Solar Distribution as written (EnergyPlus' default FullExterior)
    solar_distribution: str = "FullExterior"

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
        return NetworkOptions(interior_convection=interior, exterior_convection=exterior), notes

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

        heating = np.full((n, nz), np.nan)
        cooling = np.full((n, nz), np.nan)
        for zone, (heat_name, cool_name) in self.setpoint_schedules.items():
            if zone not in column:
                continue
            if heat_name:
                heating[:, column[zone]] = values(heat_name)
            if cool_name:
                cooling[:, column[zone]] = values(cool_name)
        convective = np.zeros((n, nz))
        radiant = np.zeros((n, nz))
        latent = np.zeros((n, nz))
        people_b = np.zeros((n, nz))
        people_c = np.zeros((n, nz))
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
                    people_b[:, column[gain.zone]] += gain.people_count * fraction * b
                    people_c[:, column[gain.zone]] += gain.people_count * fraction * c
                else:
                    sensible = activity * gain.sensible_fraction
                level = gain.people_count * fraction * sensible
                lat = gain.people_count * fraction * (activity - sensible)
            else:
                level = gain.design_level * fraction
                lat = gain.latent_level * fraction
            c = column[gain.zone]
            radiant[:, c] += level * gain.radiant_fraction
            convective[:, c] += level * (1.0 - gain.radiant_fraction)
            latent[:, c] += lat
        wind = (
            np.nan_to_num(weather["wind_speed"].to_numpy(dtype=float))
            if "wind_speed" in weather
            else np.zeros(n)
        )
        ach = np.zeros((n, nz))
        ach_dt = np.zeros((n, nz))
        temp_air = (
            weather["temp_air"].to_numpy(dtype=float) if "temp_air" in weather else np.zeros(n)
        )
        for inf in self.infiltration:
            if inf.zone not in column:
                continue
            c = column[inf.zone]
            a, b, c_wind, d = inf.coefficients
            v = wind * self.zone_wind_factor.get(inf.zone, 1.0)
            base = inf.design_flow * 3600.0 / self.zone_volume[inf.zone] * values(inf.schedule)
            gate = inf.outdoor_gate(sched, times, step, temp_air, v)
            if gate is not None:
                base = base * gate
            ach[:, c] += base * (a + c_wind * v + d * v * v)
            ach_dt[:, c] += base * b
        return ScheduledInputs(
            heating, cooling, convective, radiant, latent, ach, ach_dt, people_b, people_c
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

    def setpoint_profile(self, times) -> pd.DataFrame:  # noqa: F821
        """Hourly heating and cooling set points [C], columns ``(zone, "heating"|"cooling")``."""
        import pandas as pd

        hour_of_year = _hour_of_year(times, self.schedules.n_days)
        out = {}
        for zone, (heating, cooling) in self.setpoint_schedules.items():
            for kind, name in (("heating", heating), ("cooling", cooling)):
                if name is not None:
                    out[(zone, kind)] = self.schedules.hourly(name)[hour_of_year]
        return pd.DataFrame(out, index=times)


def _hour_of_year(times, n_days: int) -> np.ndarray:
    import pandas as pd

    times = pd.DatetimeIndex(times)
    hours = (times.day_of_year.to_numpy() - 1) * 24 + times.hour.to_numpy()
    return np.minimum(hours, n_days * 24 - 1)


def _warn_unsupported(source: str, info: IdfImportInfo) -> None:
    parts = []
    if info.unsupported:
        listing = ", ".join(f"{cls} ({count})" for cls, count in info.unsupported.items())
        parts.append(
            f"{source}: {sum(info.unsupported.values())} objects of {len(info.unsupported)} "
            f"classes are not represented by the multi-zone model and were skipped: {listing}."
        )
    if info.notes:
        parts.append("Approximations: " + "; ".join(info.notes) + ".")
    if parts:
        warnings.warn(" ".join(parts), IdfImportWarning, stacklevel=5)
