"""Internal gains, infiltration and thermostats of an IDF file.

Stages of the import (:class:`LoadStages`, mixed into the builder of
:func:`thermocal.multizone.idf.read_idf`): ``ZoneInfiltration:DesignFlowRate`` (constant
air-change rate at :data:`INFILTRATION_REFERENCE_WIND_SPEED`, plus the per-step terms in
:class:`InfiltrationInfo`), ``People`` / ``Lights`` / ``ElectricEquipment`` / ``OtherEquipment``
(:class:`InternalGainInfo`) and the set points of ``ZoneControl:Thermostat`` with
``ThermostatSetpoint:*`` and of ``HVACTemplate:Thermostat``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.hvac import (
    COOLING_ONLY,
    HEATING_ONLY,
    IDEAL_LOADS_CLASS,
    IDEAL_LOADS_NOT_APPLIED,
    equipment_availability,
    ideal_loads_notes,
    ideal_loads_records,
    return_air_stays_in_zone,
    zone_heat_delivery,
)
from thermocal.multizone.idf.parse import IdfObject, _is_auto, _number
from thermocal.multizone.idf.schedules import UnsupportedScheduleError

#: Reference wind speed [m/s] at which the wind terms of ZoneInfiltration:DesignFlowRate are
#: evaluated when converting to a constant air-change rate: 4.47 m/s (10 mph), the speed at which
#: the DOE-2 coefficient set (A, B, C, D) = (0, 0, 0.224, 0) gives the design flow.
INFILTRATION_REFERENCE_WIND_SPEED = 4.47


#: Sensible heat per person [-] of People objects with an autocalculated sensible fraction.
DEFAULT_PEOPLE_SENSIBLE_FRACTION = 0.6

#: Zone temperature [C] at which the autocalculated People sensible heat is evaluated.
PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE = 22.0


@dataclass
class InternalGainInfo:
    """One internal-gain object of the file, resolved for one zone.

    Attributes
    ----------
    object_class, name, zone : str
    design_level : float [W]
        Sensible design level (latent and lost fractions removed).
    radiant_fraction : float [-]
        Radiant (long-wave + visible) share of the sensible gain.
    schedule : str or None
        Fraction schedule (People: number-of-people schedule).
    annual_mean : float [W]
        ``design_level`` x time-weighted annual mean of the schedule.
    """

    object_class: str
    name: str
    zone: str
    design_level: float
    radiant_fraction: float
    schedule: str | None
    annual_mean: float
    people_count: float = 0.0
    activity_schedule: str | None = None
    sensible_fraction: float | None = None
    latent_level: float = 0.0


def people_sensible_coefficients(activity):
    """Coefficients ``(a, b, c)`` of the sensible heat per person ``a + b T + c T^2`` [W] at
    the zone air temperature ``T`` [C] (EnergyPlus' autocalculated People sensible fraction).

    Parameters
    ----------
    activity : float or ndarray [W/person]
        Total metabolic heat (the Activity Level schedule).

    References
    ----------
    EnergyPlus Engineering Reference, "People" (sensible heat gain from occupants, polynomial
    fit of the ASHRAE Handbook table).
    """
    m = np.asarray(activity, dtype=float)
    a = 6.461927 + 0.946892 * m + 0.0000255737 * m**2
    b = 7.139322 - 0.0627909 * m + 0.0000589172 * m**2
    c = -0.198550 + 0.000940018 * m - 0.00000149532 * m**2
    return a, b, c


def people_sensible_heat(activity, temperature=PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE):
    """Sensible heat per person [W] of EnergyPlus' autocalculated People sensible fraction.

    Parameters
    ----------
    activity : float or ndarray [W/person]
        Total metabolic heat (the Activity Level schedule).
    temperature : float or ndarray [C]
        Zone air temperature.

    See :func:`people_sensible_coefficients` (clipped to ``[0, activity]``).
    """
    a, b, c = people_sensible_coefficients(activity)
    t = np.asarray(temperature, dtype=float)
    return np.clip(a + b * t + c * t**2, 0.0, np.asarray(activity, dtype=float))


@dataclass
class InfiltrationInfo:
    """One ``ZoneInfiltration:DesignFlowRate`` or ``ZoneVentilation:DesignFlowRate`` object
    resolved for one zone: outdoor air entering the zone at the outdoor temperature.

    The flow is ``design_flow x schedule x (A + B |T_zone - T_out| + C v + D v^2)`` with ``v``
    the wind speed at the zone's centroid height (EnergyPlus' zone local wind speed). A
    ventilation object's flow is zero at the steps where the outdoor temperature is outside
    ``outdoor_limits`` or the zone's local wind speed exceeds ``max_wind_speed``
    (EnergyPlus' limits of ``ZoneVentilation:DesignFlowRate``).

    Attributes
    ----------
    name, zone : str
    design_flow : float [m3/s]
    schedule : str or None
    coefficients : tuple of float
        ``(A, B, C, D)``: constant [-], temperature [1/K], wind [s/m], wind squared [s2/m2].
    object_class : str
        The IDF class (``ZoneInfiltration:DesignFlowRate`` or ``ZoneVentilation:DesignFlowRate``).
    outdoor_limits : tuple
        ``((minimum [C], schedule or None), (maximum [C], schedule or None))`` of the outdoor
        temperature; a schedule overrides the value.
    max_wind_speed : float [m/s]
    fan_heat_per_flow : float [J/m3]
        Heat of the fan per volume of air, ``pressure rise / total efficiency``, added to the
        zone with the air (EnergyPlus: ``Intake`` and ``Balanced`` ventilation fans).
    indoor_limits : tuple or None
        Ventilation switched by the zone temperature: ``((minimum indoor [C], schedule or None),
        (maximum indoor [C], schedule or None), (delta [K], schedule or None))``; open when
        ``minimum <= T_zone <= maximum`` and ``T_zone - T_out >= delta`` with the zone
        temperature of the previous step (EnergyPlus); None: no indoor limit.
    leakage : tuple or None
        ``ZoneInfiltration:EffectiveLeakageArea`` (Sherman and Grimsrud, 1980):
        ``(effective leakage area [cm2], stack coefficient [(L/s)2/(cm4 K)], wind coefficient
        [(L/s)2/(cm4 (m/s)2)])``; the flow is ``schedule x area / 1000 x sqrt(Cs |T_zone - T_out|
        + Cw v^2)`` [m3/s] with ``v`` the weather file's wind speed (EnergyPlus); ``design_flow``
        and ``coefficients`` are then unused. See :func:`leakage_flow_linearised`.
    """

    name: str
    zone: str
    design_flow: float
    schedule: str | None
    coefficients: tuple[float, float, float, float]
    object_class: str = "ZoneInfiltration:DesignFlowRate"
    outdoor_limits: tuple = ((-100.0, None), (100.0, None))
    max_wind_speed: float = 40.0
    fan_heat_per_flow: float = 0.0
    indoor_limits: tuple | None = None
    leakage: tuple | None = None

    def outdoor_gate(self, schedules, times, step, temp_air, wind_speed) -> np.ndarray | None:
        """1 where the outdoor limits let the air flow, 0 elsewhere (None: no limits bind).

        Parameters
        ----------
        schedules : ScheduleEvaluator
        times : pandas.DatetimeIndex
            Step starts.
        step : pandas.Timedelta
        temp_air, wind_speed : ndarray [C], [m/s]
            Outdoor temperature and the zone's local wind speed on the grid (EnergyPlus
            compares the zone's wind speed with the limit).
        """
        (low, low_schedule), (high, high_schedule) = self.outdoor_limits
        if low_schedule is None and high_schedule is None and low <= -100.0 and high >= 100.0:
            if self.max_wind_speed >= 40.0:
                return None
        lower = schedules.on_grid(low_schedule, times, step) if low_schedule else low
        upper = schedules.on_grid(high_schedule, times, step) if high_schedule else high
        open_ = (temp_air >= lower) & (temp_air <= upper) & (wind_speed <= self.max_wind_speed)
        return open_.astype(float)


#: Indoor temperature [C] about which the Sherman-Grimsrud flow of
#: ``ZoneInfiltration:EffectiveLeakageArea`` is linearised in |T_zone - T_out| at each step.
LEAKAGE_REFERENCE_INDOOR = 18.0


def leakage_flow_linearised(leakage, temp_air, wind_speed, reference=LEAKAGE_REFERENCE_INDOOR):
    """Sherman-Grimsrud flow as ``q0 + q1 |T_zone - T_out|`` per step (its tangent).

    EnergyPlus' ``ZoneInfiltration:EffectiveLeakageArea``: ``q = A / 1000 x sqrt(Cs dT + Cw
    v^2)`` [m3/s] (ASHRAE Handbook of Fundamentals; Sherman and Grimsrud, 1980). The model's
    outdoor air is linear in ``dT = |T_zone - T_out|`` (with the zone temperature of the
    previous step), so the square root is replaced by its tangent at ``dT0 = |reference -
    T_out|``: exact at ``dT0``, above the square root elsewhere by ``(dT - dT0)^2 Cs^2 / (8
    f0^3)`` to second order (``f0`` its value at ``dT0``): ``(dT - dT0)^2 / (8 dT0^2)`` of the
    flow in still air, 3 % for 10 K off at ``dT0`` = 20 K, less with wind.

    Parameters
    ----------
    leakage : tuple
        ``(area [cm2], Cs [(L/s)2/(cm4 K)], Cw [(L/s)2/(cm4 (m/s)2)])``.
    temp_air, wind_speed : ndarray [C], [m/s]
        Outdoor temperature and the weather file's wind speed per step.
    reference : float [C]
        Indoor temperature of the tangent.

    Returns
    -------
    q0, q1 : ndarray [m3/s], [m3/(s K)]
    """
    area, stack, wind = leakage
    dt0 = np.abs(reference - np.asarray(temp_air, dtype=float))
    f0 = np.sqrt(stack * dt0 + wind * np.asarray(wind_speed, dtype=float) ** 2)
    f0 = np.maximum(f0, 1e-12)
    slope = stack / (2.0 * f0)
    return area / 1000.0 * (f0 - slope * dt0), area / 1000.0 * slope


#: Wind boundary-layer exponent and thickness [m] per terrain (EnergyPlus ``Building`` field
#: Terrain; ASHRAE Handbook of Fundamentals 2005, ch. 16, Table 1).
TERRAIN_WIND_PROFILE = {
    "COUNTRY": (0.14, 270.0),
    "SUBURBS": (0.22, 370.0),
    "CITY": (0.33, 460.0),
    "OCEAN": (0.10, 210.0),
    "URBAN": (0.22, 370.0),
}
#: Weather station: exponent, boundary-layer thickness [m], anemometer height [m].
WEATHER_STATION_WIND_PROFILE = (0.14, 270.0, 10.0)


def local_wind_factor(height: float, terrain: str = "Suburbs") -> float:
    """Ratio of the wind speed at ``height`` [m] to the weather station's [-] (EnergyPlus).

    ``(delta_met / z_met)^a_met x (z / delta)^a`` with the terrain's exponent ``a`` and
    boundary-layer thickness ``delta``; 0 at or below the ground.
    """
    a, delta = TERRAIN_WIND_PROFILE.get(terrain.upper(), TERRAIN_WIND_PROFILE["SUBURBS"])
    a_met, delta_met, z_met = WEATHER_STATION_WIND_PROFILE
    if height <= 0.0:
        return 0.0
    return (delta_met / z_met) ** a_met * (height / delta) ** a


class LoadStages:
    """Stages ``_infiltration``, ``_internal_gains`` and ``_setpoints`` of the builder.

    They set ``zone_ach``, ``zone_infiltration_group``, ``zone_gains``, ``zone_radiant`` and
    ``setpoints``; they fill ``info.infiltration``, ``info.internal_gains``,
    ``info.setpoint_schedules`` and the wind and volume tables of ``info``.
    """

    def terrain(self) -> str:
        """The ``Building`` object's Terrain (EnergyPlus' default Suburbs when absent)."""
        building_rec = self.single("BUILDING")
        terrain = (building_rec["terrain"] if building_rec is not None else "") or "Suburbs"
        if terrain.upper() not in TERRAIN_WIND_PROFILE:
            raise ThermocalInputError(
                f"{building_rec['_object'].where()}: field 'Terrain' = '{terrain}' is not one of "
                "Country, Suburbs, City, Ocean, Urban."
            )
        return terrain

    def _infiltration(self) -> None:
        """Stage: infiltration."""
        terrain = self.terrain()
        moments: dict[str, list[float]] = {}
        for data in self.surface_data.values():
            m = moments.setdefault(data["zone"], [0.0, 0.0])
            m[0] += data["area"] * float(np.mean(data["world"][:, 2]))
            m[1] += data["area"]
        for zone_name, (za, area) in moments.items():
            height = za / area if area > 0 else 0.0
            self.info.zone_wind_factor[zone_name] = local_wind_factor(height, terrain)
        self.info.zone_volume = dict(self.zone_volume)
        self.zone_ach: dict[str, float] = {}
        self.zone_infiltration_group: dict[str, str] = {}
        exterior_area: dict[str, float] = {}
        exterior_wall_area: dict[str, float] = {}
        for data in self.surface_data.values():
            if data["boundary"] == "outdoors":
                exterior_area[data["zone"]] = exterior_area.get(data["zone"], 0.0) + data["area"]
                if data["type"].upper() == "WALL":
                    exterior_wall_area[data["zone"]] = (
                        exterior_wall_area.get(data["zone"], 0.0) + data["area"]
                    )
        coefficient_notes = []
        for rec in self.records("ZONEINFILTRATION:DESIGNFLOWRATE"):
            obj = rec["_object"]
            note = _density_basis_note(rec)
            if note:
                self.info.notes.append(note)
            method = (rec["design_flow_rate_calculation_method"] or "Flow/Zone").upper()
            coefficients = [
                _number(rec, "constant_term_coefficient", default=1.0 if _all_blank(rec) else 0.0),
                _number(rec, "temperature_term_coefficient", default=0.0),
                _number(rec, "velocity_term_coefficient", default=0.0),
                _number(rec, "velocity_squared_term_coefficient", default=0.0),
            ]
            v = INFILTRATION_REFERENCE_WIND_SPEED
            factor = coefficients[0] + coefficients[2] * v + coefficients[3] * v * v
            if coefficients != [1.0, 0.0, 0.0, 0.0]:
                coefficient_notes.append(
                    f"infiltration '{rec['name']}': coefficients (A, B, C, D) = "
                    f"{tuple(coefficients)} evaluated at wind {v} m/s and dT = 0 (factor "
                    f"{factor:.3f}) for the constant zone rate (schedules='constant')"
                )
            targets = self.zone_targets(rec)
            for zone_name in targets:
                volume = self.zone_volume[zone_name]
                if method in ("FLOW/ZONE",):
                    flow = _number(rec, "design_flow_rate")
                elif method == "FLOW/AREA":
                    flow = _number(rec, "flow_per_zone_floor_area") * self.zone_area[zone_name]
                elif method == "FLOW/EXTERIORAREA":
                    flow = _number(rec, "flow_per_exterior_surface_area") * exterior_area.get(
                        zone_name, 0.0
                    )
                elif method == "FLOW/EXTERIORWALLAREA":
                    flow = _number(rec, "flow_per_exterior_surface_area") * exterior_wall_area.get(
                        zone_name, 0.0
                    )
                elif method in ("AIRCHANGES/HOUR", "AIRCHANGESPERHOUR"):
                    flow = _number(rec, "air_changes_per_hour") * volume / 3600.0
                else:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Design Flow Rate Calculation Method' = "
                        f"'{rec['design_flow_rate_calculation_method']}' is not one of Flow/Zone, "
                        "Flow/Area, Flow/ExteriorArea, Flow/ExteriorWallArea, AirChanges/Hour."
                    )
                if flow < 0:
                    raise ThermocalInputError(f"{obj.where()}: the design flow rate is negative.")
                self.zone_ach[zone_name] = (
                    self.zone_ach.get(zone_name, 0.0) + flow * 3600.0 / volume * factor
                )
                self.info.infiltration.append(
                    InfiltrationInfo(
                        rec["name"],
                        zone_name,
                        flow,
                        rec["schedule_name"] or None,
                        tuple(coefficients),
                    )
                )
                if len(targets) > 1:
                    self.zone_infiltration_group[zone_name] = rec["name"]
                schedule = rec["schedule_name"]
                if schedule:
                    self.info.infiltration_schedules.setdefault(zone_name, []).append(schedule)
                    try:
                        low, high = self.schedules.value_range(schedule)
                    except UnsupportedScheduleError:
                        low, high = (math.nan, math.nan)
                    if not (low == high == 1.0):
                        self.info.notes.append(
                            f"infiltration '{rec['name']}' (zone "
                            f"{zone_name}): schedule '{schedule}' "
                            f"(range {low:g}..{high:g}): the constant zone rate "
                            "(schedules='constant') ignores it"
                        )
        self._leakage_infiltration()
        self.info.zone_nominal_ach = dict(self.zone_ach)
        self.info.notes.extend(coefficient_notes)

    def _leakage_infiltration(self) -> None:
        """``ZoneInfiltration:EffectiveLeakageArea`` (Sherman-Grimsrud): per step in the
        simulation (:func:`leakage_flow_linearised`); the constant zone rate at the reference
        wind speed and no indoor-outdoor difference."""
        for rec in self.records("ZONEINFILTRATION:EFFECTIVELEAKAGEAREA"):
            obj = rec["_object"]
            values = []
            for field, label in (
                ("effective_air_leakage_area", "Effective Air Leakage Area"),
                ("stack_coefficient", "Stack Coefficient"),
                ("wind_coefficient", "Wind Coefficient"),
            ):
                value = _number(rec, field)
                if not value >= 0.0:
                    raise ThermocalInputError(
                        f"{obj.where()}: field '{label}' = {value:g} must be zero or positive."
                    )
                values.append(value)
            area, stack, wind = values
            schedule = rec["schedule_name"] or None
            v = INFILTRATION_REFERENCE_WIND_SPEED
            for zone_name in self.zone_targets(rec):
                volume = self.zone_volume[zone_name]
                nominal = area / 1000.0 * math.sqrt(wind) * v
                self.zone_ach[zone_name] = (
                    self.zone_ach.get(zone_name, 0.0) + nominal * 3600.0 / volume
                )
                self.info.infiltration.append(
                    InfiltrationInfo(
                        rec["name"],
                        zone_name,
                        nominal,
                        schedule,
                        (1.0, 0.0, 0.0, 0.0),
                        object_class="ZoneInfiltration:EffectiveLeakageArea",
                        leakage=(area, stack, wind),
                    )
                )
                if schedule:
                    self.info.infiltration_schedules.setdefault(zone_name, []).append(schedule)
                self.info.notes.append(
                    f"ZoneInfiltration:EffectiveLeakageArea '{rec['name']}' (zone {zone_name}): "
                    f"{area:g} cm2, Cs {stack:g}, Cw {wind:g}: the Sherman-Grimsrud flow per "
                    "step, linear in |T_zone - T_out| about an indoor "
                    f"{LEAKAGE_REFERENCE_INDOOR:g} C (3 % high in still air 10 K away from it)"
                )

    def _ventilation(self) -> None:
        """Stage: ``ZoneVentilation:DesignFlowRate`` as outdoor air like infiltration (its
        schedule, coefficients and outdoor-temperature and wind limits per step); the
        indoor-temperature limits (minimum, maximum, delta and their schedules) switch it in the
        time loop on the zone temperature of the previous step, as EnergyPlus does; refuses
        ``ZoneVentilation:WindandStackOpenArea`` (its stack flow grows with the square root of
        the indoor-outdoor difference). The fan heat of ``Intake`` and ``Balanced`` fans
        (``flow x pressure rise / efficiency``) enters the zone air with the flow, as
        EnergyPlus adds it to the incoming air."""
        for rec in self.records("ZONEVENTILATION:WINDANDSTACKOPENAREA"):
            raise ThermocalInputError(
                f"{rec['_object'].where()}: ZoneVentilation:WindandStackOpenArea is not "
                "simulated (its stack flow, proportional to the square root of the indoor-outdoor "
                "temperature difference, needs the zone temperature at every step); replace it "
                "by a ZoneVentilation:DesignFlowRate with the flow you expect, or remove it."
            )
        people: dict[str, float] | None = None
        #: zone -> annual mean fan heat of Intake/Balanced ventilation [W] (constant gains)
        self.fan_heat_mean: dict[str, float] = {}
        for rec in self.records("ZONEVENTILATION:DESIGNFLOWRATE"):
            obj = rec["_object"]
            where = obj.where()
            indoor = _indoor_limits(rec, self.schedules)
            note = _density_basis_note(rec)
            if note:
                self.info.notes.append(note)
            method = (rec["design_flow_rate_calculation_method"] or "Flow/Zone").upper()
            coefficients = (
                _number(rec, "constant_term_coefficient", default=1.0),
                _number(rec, "temperature_term_coefficient", default=0.0),
                _number(rec, "velocity_term_coefficient", default=0.0),
                _number(rec, "velocity_squared_term_coefficient", default=0.0),
            )
            limits = (
                (
                    _number(rec, "minimum_outdoor_temperature", default=-100.0),
                    rec["minimum_outdoor_temperature_schedule_name"] or None,
                ),
                (
                    _number(rec, "maximum_outdoor_temperature", default=100.0),
                    rec["maximum_outdoor_temperature_schedule_name"] or None,
                ),
            )
            for label, (_, name) in zip(("Minimum", "Maximum"), limits, strict=True):
                if name is not None and name not in self.schedules:
                    raise ThermocalInputError(
                        f"{where}: field '{label} Outdoor Temperature Schedule Name' = '{name}' "
                        "is not a schedule of the file."
                    )
            max_wind = _number(rec, "maximum_wind_speed", default=40.0)
            kind = (rec["ventilation_type"] or "Natural").upper()
            if kind not in ("NATURAL", "EXHAUST", "INTAKE", "BALANCED"):
                raise ThermocalInputError(
                    f"{where}: field 'Ventilation Type' = '{rec['ventilation_type']}' is not "
                    "Natural, Exhaust, Intake or Balanced."
                )
            pressure = _number(rec, "fan_pressure_rise", default=0.0)
            efficiency = _number(rec, "fan_total_efficiency", default=1.0)
            if efficiency <= 0:
                raise ThermocalInputError(
                    f"{where}: field 'Fan Total Efficiency' = {efficiency:g} must be positive."
                )
            schedule = rec["schedule_name"] or None
            try:
                mean = self.schedules.annual_mean(schedule) if schedule else 1.0
            except UnsupportedScheduleError as exc:
                raise ThermocalInputError(f"{where}: field 'Schedule Name': {exc}") from None
            for zone_name in self.zone_targets(rec):
                volume = self.zone_volume[zone_name]
                if method == "FLOW/ZONE":
                    flow = _number(rec, "design_flow_rate")
                elif method == "FLOW/AREA":
                    flow = _number(rec, "flow_rate_per_floor_area") * self.zone_area[zone_name]
                elif method == "FLOW/PERSON":
                    if people is None:
                        people = {}
                        for prec in self.records("PEOPLE"):
                            for z in self.zone_targets(prec):
                                people[z] = people.get(z, 0.0) + _people_number(
                                    prec, self.zone_area[z]
                                )
                    flow = _number(rec, "flow_rate_per_person") * people.get(zone_name, 0.0)
                elif method in ("AIRCHANGES/HOUR", "AIRCHANGESPERHOUR"):
                    flow = _number(rec, "air_changes_per_hour") * volume / 3600.0
                else:
                    raise ThermocalInputError(
                        f"{where}: field 'Design Flow Rate Calculation Method' = "
                        f"'{rec['design_flow_rate_calculation_method']}' is not one of "
                        "Flow/Zone, Flow/Area, Flow/Person, AirChanges/Hour."
                    )
                if flow < 0:
                    raise ThermocalInputError(f"{where}: the design flow rate is negative.")
                fan_heat = pressure / efficiency if kind in ("INTAKE", "BALANCED") else 0.0
                info = InfiltrationInfo(
                    rec["name"],
                    zone_name,
                    flow,
                    schedule,
                    coefficients,
                    object_class=obj.class_name,
                    outdoor_limits=limits,
                    max_wind_speed=max_wind,
                    fan_heat_per_flow=fan_heat,
                    indoor_limits=indoor,
                )
                self.info.infiltration.append(info)
                # the constant rate (schedules='constant'): the design flow at the reference
                # wind, weighted by the schedule's annual mean (limits not applied)
                v = INFILTRATION_REFERENCE_WIND_SPEED
                factor = coefficients[0] + coefficients[2] * v + coefficients[3] * v * v
                ach = flow * 3600.0 / volume * factor * mean
                self.zone_ach[zone_name] = self.zone_ach.get(zone_name, 0.0) + ach
                self.info.zone_nominal_ach[zone_name] = (
                    self.info.zone_nominal_ach.get(zone_name, 0.0) + ach
                )
                if fan_heat > 0:
                    self.fan_heat_mean[zone_name] = (
                        self.fan_heat_mean.get(zone_name, 0.0) + flow * factor * mean * fan_heat
                    )
                if schedule:
                    self.info.infiltration_schedules.setdefault(zone_name, []).append(schedule)
                self.info.notes.append(
                    f"ZoneVentilation:DesignFlowRate '{rec['name']}' (zone {zone_name}): "
                    f"{flow:.4g} m3/s ({flow * 3600.0 / volume:.2f} 1/h) of outdoor air"
                    + (f" on schedule '{schedule}'" if schedule else "")
                    + "; a calibrated infiltration rate of the zone scales it too"
                )

    def _internal_gains(self) -> None:
        """Stage: internal gains."""
        people_count: dict[str, float] = {}
        for rec in self.records("PEOPLE"):
            for zone_name in self.zone_targets(rec):
                people_count[zone_name] = people_count.get(zone_name, 0.0) + _people_number(
                    rec, self.zone_area[zone_name]
                )
        # the zones' declared equipment, read once: where the lights' return air goes here, the
        # thermostats and the identification's heat form later (info.zone_heat_delivery)
        delivery = self.info.zone_heat_delivery = zone_heat_delivery(
            self.by_key, {key: entry[0] for key, entry in self.zones.items.items()}
        )
        for key in ("OTHEREQUIPMENT", "ELECTRICEQUIPMENT", "GASEQUIPMENT", "LIGHTS", "PEOPLE"):
            for rec in self.records(key):
                for zone_name in self.zone_targets(rec):
                    stays = return_air_stays_in_zone(delivery.get(zone_name))
                    gain = _internal_gain(
                        rec,
                        zone_name,
                        self.zone_area[zone_name],
                        people_count.get(zone_name, 0.0),
                        self.schedules,
                        return_air_stays=stays,
                    )
                    self.info.internal_gains.append(gain)
                    note = _return_air_note(rec, zone_name, delivery.get(zone_name), stays)
                    if note:
                        self.info.notes.append(note)
        self.zone_gains: dict[str, float] = {}
        self.zone_radiant: dict[str, float] = {}
        for zone, heat in getattr(self, "fan_heat_mean", {}).items():
            # ventilation fan heat with the air: convective (its per-step value in
            # IdfImportInfo.scheduled_inputs)
            self.zone_gains[zone] = self.zone_gains.get(zone, 0.0) + heat
        for gain in self.info.internal_gains:
            self.zone_gains[gain.zone] = self.zone_gains.get(gain.zone, 0.0) + gain.annual_mean
            self.zone_radiant[gain.zone] = (
                self.zone_radiant.get(gain.zone, 0.0) + gain.annual_mean * gain.radiant_fraction
            )
            if gain.schedule is not None:
                try:
                    low, high = self.schedules.value_range(gain.schedule)
                except UnsupportedScheduleError:
                    low, high = math.nan, math.nan
                if low != high:
                    self.info.notes.append(
                        f"{gain.object_class} '{gain.name}' (zone {gain.zone}): schedule "
                        f"'{gain.schedule}' varies ({low:g}..{high:g}); its annual mean gives the "
                        "constant internal gain of schedules='constant'"
                    )

    def _setpoints(self) -> None:
        """Stage: thermostats."""
        self.setpoints = _thermostats(
            self.records, self.zones, self.zone_lists, self.schedules, self.info, self.by_key
        )
        hvac = sorted(
            cls
            for cls in self.info.unsupported
            if cls.upper().startswith(("ZONEHVAC:", "AIRLOOPHVAC", "AIRTERMINAL:", "PLANTLOOP"))
        )
        if self.setpoints and hvac:
            self.info.notes.append(
                f"HVAC equipment ({', '.join(hvac[:3])}{', ...' if len(hvac) > 3 else ''}) is not "
                "modelled: thermostatted zones get ideal heating/cooling at their set points "
                "when simulated (an identification ignores set points: its identified heat "
                "stands for the equipment's)"
            )
        self._one_sided_equipment()
        self._plenums()
        self._operative_thermostats()
        records = ideal_loads_records(self.by_key, getattr(self, "version", (25, 2)))
        self._switch_off_ideal_loads(records)
        self.info.notes.extend(ideal_loads_notes(records, self.schedules.annual_mean))
        self._equipment_availability()

    def _equipment_availability(self) -> None:
        """Zone equipment other than ideal loads switched off by its availability schedule (a
        baseboard off in summer, a terminal unit off at night): the zone floats on those steps,
        as in EnergyPlus, through the same per-step mask as an ideal-loads system's
        (``info.ideal_loads_availability``; :func:`~thermocal.multizone.idf.hvac.
        equipment_availability`)."""
        for zone, delivery in self.info.zone_heat_delivery.items():
            if zone in self.info.ideal_loads_availability or zone not in self.setpoints:
                continue
            name = equipment_availability(delivery, self.by_key)
            if name is None:
                continue
            try:
                low, high = self.schedules.value_range(name)
            except Exception:  # noqa: BLE001 - an unreadable schedule: always available
                self.info.notes.append(
                    f"zone {zone}: the availability schedule '{name}' of its equipment "
                    f"({delivery.describe()}) could not be read: taken as always available"
                )
                continue
            if low > 0.0:
                continue
            self.info.ideal_loads_availability[zone] = ((name,), (name,))
            when = "always" if high <= 0.0 else "part of the time"
            self.info.notes.append(
                f"zone {zone}: its equipment ({delivery.describe()}) is switched off where its "
                f"availability schedule '{name}' is 0 ({when}): the zone floats there, as in "
                "EnergyPlus"
            )

    def _operative_thermostats(self) -> None:
        """``ZoneControl:Thermostat:OperativeTemperature``: its zones' ideal loads hold
        ``(1 - f) T_air + f T_mrt`` at the set points, ``f`` the radiative fraction
        (``info.operative_fraction``). A scheduled fraction takes its mean over the year (said);
        an adaptive comfort model is not applied (said)."""
        key = "ZoneControl:Thermostat:OperativeTemperature"
        found = self.by_key.get(key.upper(), [])
        if not found:
            return
        thermostats = {
            rec["name"].upper(): rec for rec in self.records("ZONECONTROL:THERMOSTAT")
        }
        for obj in found:
            fields = [f.strip() for f in obj.fields] + [""] * 5
            thermostat = thermostats.get(fields[0].upper())
            only = None
            if thermostat is None:  # "<Zone Name> <thermostat>" of a ZoneList's thermostat
                for rec in thermostats.values():
                    for zone in self.zone_targets(rec):
                        if f"{zone} {rec['name']}".upper() == fields[0].upper():
                            thermostat, only = rec, zone
            if thermostat is None:
                self.info.notes.append(
                    f"{obj.where()}: field 'Thermostat Name' = '{fields[0]}' names no "
                    "ZoneControl:Thermostat of the file: not applied (air temperature held)"
                )
                continue
            mode = fields[1].upper() or "CONSTANT"
            if mode == "SCHEDULED" and fields[3]:
                try:
                    fraction = float(self.schedules.annual_mean(fields[3]))
                except Exception as exc:  # noqa: BLE001 - named with the object
                    raise ThermocalInputError(f"{obj.where()}: {exc}") from None
                self.info.notes.append(
                    f"{obj.where()}: the scheduled radiative fraction '{fields[3]}' is taken at "
                    f"its mean over the year, {fraction:.3g}"
                )
            else:
                try:
                    fraction = float(fields[2]) if fields[2] else 0.0
                except ValueError:
                    raise ThermocalInputError(
                        f"{obj.where()}: field 'Fixed Radiative Fraction' = '{fields[2]}' is "
                        "not a number."
                    ) from None
            if not 0.0 <= fraction < 0.9:
                raise ThermocalInputError(
                    f"{obj.where()}: the radiative fraction {fraction:g} is outside [0, 0.9) "
                    "(EnergyPlus' limits)."
                )
            if fields[4] and fields[4].upper() != "NONE":
                self.info.notes.append(
                    f"{obj.where()}: the adaptive comfort model '{fields[4]}' is not applied: "
                    "the thermostat's own set points are used"
                )
            for zone in [only] if only else self.zone_targets(thermostat):
                if fraction > 0.0:
                    self.info.operative_fraction[zone] = fraction
        count = self.info.unsupported.pop(key, None) or self.info.unsupported.pop(
            next((k for k in self.info.unsupported if k.upper() == key.upper()), ""), None
        )
        if count and self.info.operative_fraction:
            zones = ", ".join(f"'{z}'" for z in list(self.info.operative_fraction)[:6])
            self.info.notes.append(
                f"{IDEAL_LOADS_NOT_APPLIED.replace('not applied', 'applied')}: {key}: the "
                f"ideal loads of zone(s) {zones} hold the operative temperature "
                "(1 - f) T_air + f T_mrt at the set points, f the radiative fraction, as "
                "EnergyPlus does"
            )

    def _plenums(self) -> None:
        """A note per air-loop plenum: the air the loop draws or pushes through its zone is not
        modelled (NREL's 5Zone_IdealLoadsAirSystems_ReturnPlenum: the plenum 0.84 K colder
        than in EnergyPlus, the zones' heating 3-4 % higher)."""
        for cls in ("AirLoopHVAC:ReturnPlenum", "AirLoopHVAC:SupplyPlenum"):
            for obj in self.by_key.get(cls.upper(), []):
                zone = obj.fields[1].strip() if len(obj.fields) > 1 else ""
                air = "return air of the zones it serves" if "Return" in cls else "supply air"
                self.info.notes.append(
                    f"HVAC equipment not modelled: {obj.where()} carries the {air} through "
                    f"zone '{zone}', which the model leaves out (NREL's "
                    "5Zone_IdealLoadsAirSystems_ReturnPlenum: the plenum 0.84 K colder than in "
                    "EnergyPlus, the zones' heating 3-4 % higher)"
                )

    def _one_sided_equipment(self) -> None:
        """A zone whose every piece of equipment only heats (baseboards, high-temperature
        radiant heaters, the baseboard template) gets no cooling set point, and one whose
        equipment only cools (cooling panels) no heating set point: EnergyPlus cannot cool or
        heat it (a baseboard zone with a dual-setpoint thermostat got 558 kWh of ideal cooling
        in January and ran 6 K colder than in EnergyPlus)."""
        dropped: dict[str, list[str]] = {"cooling": [], "heating": []}
        classes: dict[str, set] = {"cooling": set(), "heating": set()}
        for zone, delivery in self.info.zone_heat_delivery.items():
            kinds = [e.class_name.upper() for e in delivery.equipment]
            if not kinds or zone not in self.setpoints:
                continue
            for side, only in (("cooling", HEATING_ONLY), ("heating", COOLING_ONLY)):
                if not all(k.startswith(only) for k in kinds):
                    continue
                heating, cooling = self.setpoints[zone]
                h_schedule, c_schedule = self.info.setpoint_schedules.get(zone, (None, None))
                if (cooling if side == "cooling" else heating) is None:
                    continue
                if side == "cooling":
                    cooling = c_schedule = None
                else:
                    heating = h_schedule = None
                self.setpoints[zone] = (heating, cooling)
                if zone in self.info.setpoint_schedules:
                    self.info.setpoint_schedules[zone] = (h_schedule, c_schedule)
                if zone in self.info.setpoint_control:
                    # a varying control type keeps switching the side that remains (on a step
                    # with control type 0 the zone floats, as before)
                    control_schedule, by_type = self.info.setpoint_control[zone]
                    self.info.setpoint_control[zone] = (
                        control_schedule,
                        {
                            kind: (h, None) if side == "cooling" else (None, c)
                            for kind, (h, c) in by_type.items()
                        },
                    )
                dropped[side].append(zone)
                classes[side].update(e.class_name for e in delivery.equipment)
        for side, zones in dropped.items():
            if not zones:
                continue
            does = "heats" if side == "cooling" else "cools"
            names = ", ".join(f"'{z}'" for z in zones[:8]) + (", ..." if len(zones) > 8 else "")
            self.info.notes.append(
                f"HVAC equipment that only {does[:-1]}s ({', '.join(sorted(classes[side]))}) "
                f"serves {len(zones)} zone(s) ({names}): no {side} set point there, as "
                f"EnergyPlus cannot {side[:-3]} them"
            )

    def _switch_off_ideal_loads(self, records) -> None:
        """A zone whose ideal-loads system is never available (its availability schedule, or
        its heating or cooling one, zero all year) loses that set point: EnergyPlus lets it
        float (Case 600 with its system always off: 0 kWh, where thermocal heated 4,244)."""
        owner = {
            e.name.upper(): zone
            for zone, delivery in self.info.zone_heat_delivery.items()
            for e in delivery.equipment
            if e.class_name.upper() == IDEAL_LOADS_CLASS.upper()
        }
        for rec in records:
            if "zone_name" in rec:  # an HVACTemplate: its own Zone Name
                entry = self.zones.get(str(rec["zone_name"]))
                zone = entry[0] if entry is not None else None
            else:
                zone = owner.get(str(rec.get("name") or "").upper())
            if zone is None:
                continue

            def readable(key: str, rec=rec) -> tuple[str, tuple[float, float]] | None:
                name = str(rec.get(key) or "").strip()
                try:
                    return (name, self.schedules.value_range(name)) if name else None
                except Exception:  # noqa: BLE001 - an unreadable schedule is noted elsewhere
                    return None

            system, heating, cooling = (
                readable(f"{kind}availability_schedule_name")
                for kind in ("", "heating_", "cooling_")
            )
            # available part of the time: switched off step by step where a schedule is 0
            partial = {
                kind: tuple(
                    s[0] for s in (system, own) if s is not None and s[1][0] <= 0.0 < s[1][1]
                )
                for kind, own in (("heating", heating), ("cooling", cooling))
            }
            if partial["heating"] or partial["cooling"]:
                self.info.ideal_loads_availability[zone] = (partial["heating"], partial["cooling"])
            off = system is not None and system[1][1] <= 0.0
            heating_off = off or (heating is not None and heating[1][1] <= 0.0)
            cooling_off = off or (cooling is not None and cooling[1][1] <= 0.0)
            if not (heating_off or cooling_off):
                continue
            heating, cooling = self.setpoints.get(zone, (None, None))
            h_schedule, c_schedule = self.info.setpoint_schedules.get(zone, (None, None))
            if heating_off:
                heating = h_schedule = None
            if cooling_off:
                cooling = c_schedule = None
            self.setpoints[zone] = (heating, cooling)
            if zone in self.info.setpoint_schedules:
                self.info.setpoint_schedules[zone] = (h_schedule, c_schedule)
            what = "heating and cooling" if heating_off and cooling_off else (
                "heating" if heating_off else "cooling"
            )
            self.info.notes.append(
                f"{IDEAL_LOADS_NOT_APPLIED.replace('not applied', 'applied')}: "
                f"{rec['_object'].where()} is never available for {what} (its availability "
                f"schedule is zero all year): zone '{zone}' has no {what} set point, as "
                "EnergyPlus lets it float"
            )


#: Indoor-temperature limits of ZoneVentilation:DesignFlowRate and their "no limit" defaults
_INDOOR_LIMITS = (
    ("minimum_indoor_temperature", "Minimum Indoor Temperature", -100.0, lambda v: v <= -100.0),
    ("maximum_indoor_temperature", "Maximum Indoor Temperature", 100.0, lambda v: v >= 100.0),
    ("delta_temperature", "Delta Temperature", -100.0, lambda v: v <= -100.0),
)


def _indoor_limits(rec: dict, schedules) -> tuple | None:
    """The indoor-temperature limits of a ZoneVentilation:DesignFlowRate (None: none binds).

    Returns ``((minimum [C], schedule), (maximum [C], schedule), (delta [K], schedule))``; a
    schedule named in ``<field> Schedule Name`` overrides the number (EnergyPlus).
    """
    where = rec["_object"].where()
    out = []
    bound = False
    for name, label, default, free in _INDOOR_LIMITS:
        value = _number(rec, name, default=default)
        schedule = rec.get(f"{name}_schedule_name", "") or None
        if schedule is not None and schedule not in schedules:
            raise ThermocalInputError(
                f"{where}: field '{label} Schedule Name' = '{schedule}' is not a schedule of the "
                "file."
            )
        if schedule is not None or not free(value):
            bound = True
        out.append((value, schedule))
    return tuple(out) if bound else None


def _density_basis_note(rec: dict) -> str | None:
    """A note when 'Density Basis' is not Outdoor (the model's mass flow is the volume flow at
    the outdoor air density, EnergyPlus' default)."""
    basis = rec.get("density_basis", "") or "Outdoor"
    if basis.upper() == "OUTDOOR":
        return None
    return (
        f"{rec['_object'].class_name} '{rec['name']}': 'Density Basis' = {basis} approximated by "
        "Outdoor (the volume flow at the outdoor air density)"
    )


def _all_blank(rec: dict) -> bool:
    return all(
        rec.get(n, "") == ""
        for n in (
            "constant_term_coefficient",
            "temperature_term_coefficient",
            "velocity_term_coefficient",
            "velocity_squared_term_coefficient",
        )
    )


def _people_number(rec: dict, floor_area: float) -> float:
    obj = rec["_object"]
    method = (rec["number_of_people_calculation_method"] or "People").upper()
    if method == "PEOPLE":
        return _number(rec, "number_of_people")
    if method == "PEOPLE/AREA":
        return _number(rec, "people_per_zone_floor_area") * floor_area
    if method == "AREA/PERSON":
        per = _number(rec, "zone_floor_area_per_person")
        return floor_area / per if per > 0 else 0.0
    raise ThermocalInputError(
        f"{obj.where()}: field 'Number of People Calculation Method' = "
        f"'{rec['number_of_people_calculation_method']}' is not People, People/Area or Area/Person."
    )


def _return_air_note(rec, zone_name, delivery, stays: bool) -> str | None:
    """Where a ``Lights`` object's return-air fraction goes, for the import notes (None for
    other gains or a fraction of 0)."""
    obj: IdfObject = rec["_object"]
    if obj.key != "LIGHTS":
        return None
    fraction = _number(rec, "return_air_fraction", default=0.0)
    if not fraction > 0:
        return None
    where = f"Lights '{rec['name']}' (zone {zone_name}): its return-air fraction {fraction:g}"
    if stays:
        return (
            f"{where} enters the zone air, as EnergyPlus adds it to a zone whose equipment is "
            f"not on an air loop ({delivery.describe()})"
        )
    why = "its equipment is on an air loop" if delivery is not None else "it has no equipment"
    return f"{where} leaves the zone, as in EnergyPlus when {why}"


def _internal_gain(
    rec, zone_name, floor_area, people, schedules, *, return_air_stays: bool = False
) -> InternalGainInfo:
    obj: IdfObject = rec["_object"]
    if obj.key == "PEOPLE":
        count = _people_number(rec, floor_area)
        activity_schedule = rec["activity_level_schedule_name"] or None
        try:
            activity = schedules.annual_mean(activity_schedule) if activity_schedule else 120.0
        except UnsupportedScheduleError as exc:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Activity Level Schedule Name': {exc}"
            ) from None
        if _is_auto(rec, "sensible_heat_fraction"):
            sensible_fraction = None
            sensible = float(people_sensible_heat(activity)) / activity if activity > 0 else 0.0
        else:
            sensible_fraction = sensible = _number(rec, "sensible_heat_fraction")
        design = count * activity * sensible
        latent_level = count * activity * (1.0 - sensible)
        radiant = _number(rec, "fraction_radiant", default=0.3)
        schedule = rec["number_of_people_schedule_name"] or None
    else:
        method = (rec["design_level_calculation_method"] or "").upper()
        if method in ("EQUIPMENTLEVEL", "LIGHTINGLEVEL"):
            level = _number(rec, "design_level")
        elif method in ("WATTS/AREA", "POWER/AREA"):
            level = _number(rec, "power_per_zone_floor_area") * floor_area
        elif method in ("WATTS/PERSON", "POWER/PERSON"):
            level = _number(rec, "power_per_person") * people
        else:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Design Level Calculation Method' = "
                f"'{rec['design_level_calculation_method']}' is not supported."
            )
        if obj.key == "LIGHTS":
            # the return-air fraction goes to the zone's return air path (an air loop or a
            # return plenum, which thermocal does not model, so it leaves the zones); in a
            # zone without HVAC connections EnergyPlus adds it to no zone either; in a zone
            # whose equipment is not on an air loop it enters the zone air
            # (:func:`~thermocal.multizone.idf.hvac.return_air_stays_in_zone`)
            lost = (
                0.0
                if return_air_stays
                else min(_number(rec, "return_air_fraction", default=0.0), 1.0)
            )
            radiant_total = _number(rec, "fraction_radiant", default=0.0) + _number(
                rec, "fraction_visible", default=0.0
            )
        else:
            lost = _number(rec, "fraction_latent", default=0.0) + _number(
                rec, "fraction_lost", default=0.0
            )
            radiant_total = _number(rec, "fraction_radiant", default=0.0)
        sensible_share = max(1.0 - lost, 0.0)
        design = level * sensible_share
        radiant = min(radiant_total / sensible_share, 1.0) if sensible_share > 0 else 0.0
        schedule = rec["schedule_name"] or None
        count = 0.0
        activity_schedule = sensible_fraction = None
        latent_level = level * (
            _number(rec, "fraction_latent", default=0.0) if obj.key != "LIGHTS" else 0.0
        )
    mean_factor = 1.0
    if schedule is not None:
        try:
            mean_factor = schedules.annual_mean(schedule)
        except UnsupportedScheduleError as exc:
            raise ThermocalInputError(f"{obj.where()}: {exc}") from None
    return InternalGainInfo(
        object_class=obj.class_name,
        name=rec["name"],
        zone=zone_name,
        design_level=design,
        radiant_fraction=radiant,
        schedule=schedule,
        annual_mean=design * mean_factor,
        people_count=count,
        activity_schedule=activity_schedule,
        sensible_fraction=sensible_fraction,
        latent_level=latent_level,
    )


def declared_radiant_fraction(info, zones, times, step, fallback: float) -> np.ndarray:
    """Radiant share of the sensible internal gains an IDF declares, per step and zone [-].

    The form of gains whose composition changes hour by hour (office equipment at night, lights
    in the evening, convective occupants at home): at each step, the zone's scheduled radiant
    (long-wave + visible) heat over its scheduled sensible heat, from its People, Lights and
    equipment objects (People at their 22 C sensible heat).

    Parameters
    ----------
    info : IdfImportInfo
        ``building.idf_info`` of a file read with its load objects.
    zones : sequence of str
        Zone names (columns of the result).
    times : pandas.DatetimeIndex
        Step starts (local standard time).
    step : str or Timedelta
        Step length.
    fallback : float [-]
        The fraction of a zone that declares no gains at all. Steps without gains in a zone
        that has some take that zone's gain-weighted mean over the period.

    Returns
    -------
    ndarray (n_steps, n_zones) [-]
    """
    n, names = len(times), list(zones)
    radiant = np.zeros((n, len(names)))
    total = np.zeros((n, len(names)))
    for gain in info.internal_gains:
        if gain.zone not in names or gain.design_level <= 0:
            continue
        z = names.index(gain.zone)
        fraction = (
            np.ones(n)
            if gain.schedule is None
            else info.schedules.on_grid(gain.schedule, times, step)
        )
        level = gain.design_level * fraction
        total[:, z] += level
        radiant[:, z] += level * gain.radiant_fraction
    period_total = total.sum(axis=0)
    mean = np.divide(
        radiant.sum(axis=0),
        period_total,
        out=np.full(len(names), float(fallback)),
        where=period_total > 0,
    )
    out = np.broadcast_to(mean, total.shape).copy()
    np.divide(radiant, total, out=out, where=total > 0)
    return np.clip(out, 0.0, 1.0)


#: ZoneControl:Thermostat control types (the values of its Control Type Schedule)
_CONTROL_CLASSES = {
    1: "THERMOSTATSETPOINT:SINGLEHEATING",
    2: "THERMOSTATSETPOINT:SINGLECOOLING",
    3: "THERMOSTATSETPOINT:SINGLEHEATINGORCOOLING",
    4: "THERMOSTATSETPOINT:DUALSETPOINT",
}


def _setpoint_schedule_names(cls: str, sp: dict) -> tuple[str | None, str | None]:
    """(heating, cooling) set-point schedule names of a ThermostatSetpoint:* record."""
    if cls == "THERMOSTATSETPOINT:DUALSETPOINT":
        return (
            sp["heating_setpoint_temperature_schedule_name"] or None,
            sp["cooling_setpoint_temperature_schedule_name"] or None,
        )
    name = sp["setpoint_temperature_schedule_name"] or None
    if cls == "THERMOSTATSETPOINT:SINGLEHEATING":
        return name, None
    if cls == "THERMOSTATSETPOINT:SINGLECOOLING":
        return None, name
    return name, name


#: The zone templates other than ideal loads (read by position, not imported) and the position
#: of their Template Thermostat Name after the Zone Name (EnergyPlus 25.2's IDD): EnergyPlus
#: expands each into its equipment and the zone's thermostat.
_ZONE_TEMPLATE_THERMOSTAT = {
    "HVACTemplate:Zone:BaseboardHeat": 1,
    "HVACTemplate:Zone:FanCoil": 1,
    "HVACTemplate:Zone:PTAC": 1,
    "HVACTemplate:Zone:PTHP": 1,
    "HVACTemplate:Zone:WaterToAirHeatPump": 1,
    "HVACTemplate:Zone:VRF": 2,
    "HVACTemplate:Zone:Unitary": 2,
    "HVACTemplate:Zone:VAV": 2,
    "HVACTemplate:Zone:VAV:FanPowered": 2,
    "HVACTemplate:Zone:VAV:HeatAndCool": 2,
    "HVACTemplate:Zone:ConstantVolume": 2,
    "HVACTemplate:Zone:DualDuct": 2,
}


def _template_thermostat_records(records, by_key) -> list[tuple[dict, IdfObject]]:
    """``(zone name, template thermostat name)`` records of every HVACTemplate:Zone object with
    the object: the ideal-loads template read by name, the others by position (a zone with a
    baseboard template lost its thermostat and floated: 0 kWh where EnergyPlus heated 564)."""
    out = [
        ({"zone_name": rec["zone_name"], "template_thermostat_name":
          rec["template_thermostat_name"]}, rec["_object"])
        for rec in records("HVACTEMPLATE:ZONE:IDEALLOADSAIRSYSTEM")
    ]  # fmt: skip
    for cls, position in _ZONE_TEMPLATE_THERMOSTAT.items():
        for obj in (by_key or {}).get(cls.upper(), []):
            fields = [f.strip() for f in obj.fields] + [""] * (position + 1)
            out.append(
                ({"zone_name": fields[0], "template_thermostat_name": fields[position]}, obj)
            )
    return out


def _thermostats(records, zones, zone_lists, schedules, info, by_key=None) -> dict:
    """Zone -> (heating set point, cooling set point) from the thermostat objects."""
    setpoint_objects: dict[str, dict] = {}
    for rec in records(
        "THERMOSTATSETPOINT:DUALSETPOINT",
        "THERMOSTATSETPOINT:SINGLEHEATING",
        "THERMOSTATSETPOINT:SINGLECOOLING",
        "THERMOSTATSETPOINT:SINGLEHEATINGORCOOLING",
    ):
        setpoint_objects[rec["name"].upper()] = rec
    result: dict[str, tuple[float | None, float | None]] = {}

    def constant(schedule: str | None, obj: IdfObject, what: str) -> float | None:
        if not schedule:
            return None
        try:
            low, high = schedules.value_range(schedule)
            value = schedules.mode(schedule)
        except UnsupportedScheduleError as exc:
            raise ThermocalInputError(f"{obj.where()}: {exc}") from None
        if low != high:
            info.notes.append(
                f"{obj.where()}: {what} schedule '{schedule}' varies ({low:g}..{high:g} C); the "
                f"value in effect most of the year ({value:g} C) is the constant set point of "
                "schedules='constant'"
            )
        return value

    for rec in records("ZONECONTROL:THERMOSTAT"):
        obj = rec["_object"]
        target = rec["zone_name"]
        entry = zones.get(target)
        targets = [entry[0]] if entry is not None else zone_lists.get(target.upper())
        if not targets:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Zone or ZoneList Name' = '{target}' is not a zone."
            )
        control_types = {}
        for group in rec["controls"]:
            if len(group) == 2 and group[1]:
                control_types[group[0].upper()] = group[1]
        control_schedule = rec["control_type_schedule_name"]
        try:
            mode = int(round(schedules.mode(control_schedule))) if control_schedule else 4
        except UnsupportedScheduleError as exc:
            raise ThermocalInputError(f"{obj.where()}: {exc}") from None
        wanted = _CONTROL_CLASSES.get(mode)
        low, high = schedules.value_range(control_schedule) if control_schedule else (4, 4)
        varying = low != high
        name = control_types.get(wanted or "")
        if varying:
            by_type = {}
            for kind, cls in _CONTROL_CLASSES.items():
                sp_name = control_types.get(cls)
                if not sp_name:
                    continue
                sp_rec = setpoint_objects.get(sp_name.upper())
                if sp_rec is None:
                    raise ThermocalInputError(
                        f"{obj.where()}: the set-point object '{sp_name}' ({cls.title()}) is not "
                        "defined."
                    )
                by_type[kind] = _setpoint_schedule_names(cls, sp_rec)
            for zone_name in targets:
                info.setpoint_control[zone_name] = (control_schedule, by_type)
            if name is None and by_type:
                # the most frequent control type has no set-point object: the zone floats on
                # its steps and is controlled on the others; the constant set points are those
                # of the most frequent type that has one
                hours = np.rint(schedules.hourly(control_schedule)).astype(int)
                kind = max(by_type, key=lambda k: int(np.sum(hours == k)))
                info.notes.append(
                    f"{obj.where()}: no set-point object for control type {mode} (in effect "
                    f"most of the year): the zone floats on its steps"
                )
                mode, wanted = kind, _CONTROL_CLASSES[kind]
                name = control_types[wanted]
            info.notes.append(
                f"{obj.where()}: control type schedule '{control_schedule}' varies "
                f"({low:g}..{high:g}); the set points follow it step by step (control type "
                f"{mode} gives the constant set points of schedules='constant')"
            )
        if name is None:
            info.notes.append(f"{obj.where()}: no set-point object for control type {mode}")
            continue
        sp = setpoint_objects.get(name.upper())
        if sp is None:
            raise ThermocalInputError(
                f"{obj.where()}: the set-point object '{name}' ({wanted.title()}) is not defined."
            )
        sp_obj = sp["_object"]
        heating_schedule, cooling_schedule = _setpoint_schedule_names(wanted, sp)
        heating = constant(heating_schedule, sp_obj, "heating set-point")
        cooling = constant(cooling_schedule, sp_obj, "cooling set-point")
        for zone_name in targets:
            result[zone_name] = (heating, cooling)
            info.setpoint_schedules[zone_name] = (
                heating_schedule or None,
                cooling_schedule or None,
            )

    templates = {rec["name"].upper(): rec for rec in records("HVACTEMPLATE:THERMOSTAT")}
    for rec, obj in _template_thermostat_records(records, by_key):
        if not rec["template_thermostat_name"]:
            continue  # a template without a thermostat: the zone's own ZoneControl, if any
        entry = zones.get(rec["zone_name"])
        if entry is None:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Zone Name' = '{rec['zone_name']}' is not a zone."
            )
        template = templates.get(rec["template_thermostat_name"].upper())
        if template is None:
            raise ThermocalInputError(
                f"{obj.where()}: field 'Template Thermostat Name' = "
                f"'{rec['template_thermostat_name']}' is not an HVACTemplate:Thermostat."
            )
        t_obj = template["_object"]
        if template["heating_setpoint_schedule_name"]:
            heating = constant(template["heating_setpoint_schedule_name"], t_obj, "heating")
        else:
            heating = _number(template, "constant_heating_setpoint", required=False)
        if template["cooling_setpoint_schedule_name"]:
            cooling = constant(template["cooling_setpoint_schedule_name"], t_obj, "cooling")
        else:
            cooling = _number(template, "constant_cooling_setpoint", required=False)
        result[entry[0]] = (heating, cooling)
        info.setpoint_schedules[entry[0]] = (
            template["heating_setpoint_schedule_name"] or None,
            template["cooling_setpoint_schedule_name"] or None,
        )
    return result
