"""How a file's zone equipment delivers its heat: the radiant share of the heat each zone's
declared HVAC equipment puts into the zone.

thermocal does not simulate a file's HVAC (a thermostatted zone gets ideal heating and cooling
in ``simulate``; ``identify`` ignores set points and identifies the heat). What the equipment
says is still worth reading: the heat an air system (an ideal-loads system, an air terminal, a
fan coil, a packaged terminal unit, a convective baseboard) delivers enters the zone air, while
a radiant-convective baseboard or a high-temperature radiant heater puts its stated fraction on
the zone's surfaces. The identification's default heat form takes it from here
(:func:`thermocal.identification.workflow.identified_heat_form`).

The equipment of a zone is found as EnergyPlus finds it: ``ZoneHVAC:EquipmentConnections``
names the zone's ``ZoneHVAC:EquipmentList``, whose extensible groups name each equipment's class
and object; ``HVACTemplate:Zone:*`` objects name their zone directly (their expansion makes air
systems and convective baseboards). Fields are read by position from EnergyPlus 25.2's IDD
(``Energy+.schema.epJSON``, ``legacy_idd``); a value that is not a fraction is reported, not used.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "AIR_EQUIPMENT_PREFIXES",
    "EQUIPMENT_AVAILABILITY_FIELD",
    "availability_field",
    "equipment_availability",
    "AIR_LOOP_EQUIPMENT",
    "COOLING_ONLY",
    "HEATING_ONLY",
    "IDEAL_LOADS_CLASS",
    "IDEAL_LOADS_NOT_APPLIED",
    "SURFACE_SOURCE_PREFIXES",
    "EquipmentHeat",
    "ZoneHeatDelivery",
    "return_air_stays_in_zone",
    "zone_heat_delivery",
]

#: Equipment whose heat enters the zone air (convective): air systems, air terminals, fan
#: coils, terminal units, unit heaters and ventilators, convective baseboards (EnergyPlus'
#: spelling, matched case-insensitively as prefixes of the class name).
AIR_EQUIPMENT_PREFIXES = (
    "ZoneHVAC:IdealLoadsAirSystem",
    "ZoneHVAC:FourPipeFanCoil",
    "ZoneHVAC:WindowAirConditioner",
    "ZoneHVAC:PackagedTerminalAirConditioner",
    "ZoneHVAC:PackagedTerminalHeatPump",
    "ZoneHVAC:WaterToAirHeatPump",
    "ZoneHVAC:Dehumidifier:DX",
    "ZoneHVAC:EnergyRecoveryVentilator",
    "ZoneHVAC:UnitVentilator",
    "ZoneHVAC:UnitHeater",
    "ZoneHVAC:EvaporativeCoolerUnit",
    "ZoneHVAC:HybridUnitaryHVAC",
    "ZoneHVAC:OutdoorAirUnit",
    "ZoneHVAC:TerminalUnit:VariableRefrigerantFlow",
    "ZoneHVAC:Baseboard:Convective:",
    "ZoneHVAC:AirDistributionUnit",
    "ZoneHVAC:ForcedAir:UserDefined",
    "ZoneHVAC:RefrigerationChillerSet",
    "AirTerminal:",
    "AirLoopHVAC:UnitarySystem",
    "HVACTemplate:Zone:",
)
_AIR = tuple(p.upper() for p in AIR_EQUIPMENT_PREFIXES)

#: Equipment whose heat enters a construction's source layer (radiant floors and ceilings,
#: ventilated slabs): no split between the air and the surfaces' faces describes it.
SURFACE_SOURCE_PREFIXES = ("ZoneHVAC:LowTemperatureRadiant:", "ZoneHVAC:VentilatedSlab")
_SURFACE_SOURCE = tuple(p.upper() for p in SURFACE_SOURCE_PREFIXES)

#: Radiant-convective equipment: (position of its fraction radiant, or of the name of the
#: design object holding it; that design object's class; the fraction's position there;
#: positions of the latent and lost fractions of the input, for the high-temperature heater).
_RADIANT_CONVECTIVE = {
    key.upper(): (position, design and design.upper(), design_position, losses)
    for key, position, design, design_position, losses in (
        ("ZoneHVAC:Baseboard:RadiantConvective:Electric", 7, None, None, ()),
        ("ZoneHVAC:Baseboard:RadiantConvective:Water", 1,
         "ZoneHVAC:Baseboard:RadiantConvective:Water:Design", 5, ()),
        ("ZoneHVAC:Baseboard:RadiantConvective:Steam", 1,
         "ZoneHVAC:Baseboard:RadiantConvective:Steam:Design", 5, ()),
        ("ZoneHVAC:HighTemperatureRadiant", 9, None, None, (10, 11)),
        ("ZoneHVAC:CoolingPanel:RadiantConvective:Water", 17, None, None, ()),
    )
}  # fmt: skip
_EQUIPMENT_LIST = "ZoneHVAC:EquipmentList".upper()
_CONNECTIONS = "ZoneHVAC:EquipmentConnections".upper()
_TEMPLATE_ZONE = "HVACTemplate:Zone:".upper()


@dataclass(frozen=True)
class EquipmentHeat:
    """One piece of zone equipment and how its heat enters the zone.

    Attributes
    ----------
    class_name : str
        The equipment's class as written (e.g. ``ZoneHVAC:IdealLoadsAirSystem``).
    name : str
        Its object name.
    radiant_fraction : float or None
        Share of its sensible heat onto the zone's surfaces [-] (0 for air systems); None when
        no constant split describes it (a construction's source layer, a class not known here,
        or a field that is not a fraction).
    how : str
        How the fraction was found, for notes.
    """

    class_name: str
    name: str
    radiant_fraction: float | None
    how: str


@dataclass(frozen=True)
class ZoneHeatDelivery:
    """The declared equipment of one zone and the radiant share of its heat.

    Attributes
    ----------
    equipment : tuple of EquipmentHeat
    radiant_fraction : float or None
        The equipment's radiant share [-] when every piece states one and they agree (several
        with different shares: their mean, the split of the heat between them being unknown);
        None when a piece states none.
    """

    equipment: tuple[EquipmentHeat, ...]
    radiant_fraction: float | None

    def describe(self) -> str:
        """The equipment as a short phrase, e.g. ``ZoneHVAC:IdealLoadsAirSystem 'Z1 Ideal'``."""
        return ", ".join(f"{e.class_name} '{e.name}'" for e in self.equipment)


def _fraction(fields: tuple, position: int) -> float | None:
    try:
        value = float(fields[position])
    except (IndexError, ValueError):
        return None
    return value if 0.0 <= value <= 1.0 else None


def _equipment_heat(class_name: str, name: str, objects: dict) -> EquipmentHeat:
    """How one equipment object delivers its heat (``objects``: upper-case class -> {upper
    name: IdfObject})."""
    key = class_name.upper()
    if key.startswith(_AIR):
        return EquipmentHeat(class_name, name, 0.0, "an air system: convective")
    if key.startswith(_SURFACE_SOURCE):
        return EquipmentHeat(
            class_name, name, None, "heat in a construction's source layer, not a split"
        )
    spec = _RADIANT_CONVECTIVE.get(key)
    if spec is None:
        return EquipmentHeat(class_name, name, None, "a class whose heat split is not known here")
    position, design_class, design_position, losses = spec
    obj = objects.get(key, {}).get(name.upper())
    if obj is None:
        return EquipmentHeat(class_name, name, None, "the object is not in the file")
    where = f"its field {position + 1}"
    if design_class is not None:
        design_name = obj.fields[position] if position < len(obj.fields) else ""
        design = objects.get(design_class, {}).get(design_name.upper())
        if design is None:
            return EquipmentHeat(class_name, name, None, f"its design object '{design_name}' is "
                                 "not in the file")  # fmt: skip
        obj, position, where = design, design_position, f"its design object '{design_name}'"
    radiant = _fraction(obj.fields, position)
    if radiant is None:
        return EquipmentHeat(class_name, name, None, f"{where} is not a fraction")
    lost = sum(_fraction(obj.fields, p) or 0.0 for p in losses)
    if losses and lost < 1.0:  # a heater's radiant share of its input, of the heat it delivers
        radiant = min(radiant / (1.0 - lost), 1.0)
    return EquipmentHeat(class_name, name, radiant, f"fraction radiant {radiant:g} ({where})")


def zone_heat_delivery(by_key: dict, zone_names: dict) -> dict[str, ZoneHeatDelivery]:
    """The declared zone equipment of a file and the radiant share of its heat, per zone.

    Parameters
    ----------
    by_key : dict
        Upper-case class name -> list of the file's objects (``IdfObject``).
    zone_names : dict
        Upper-case zone name -> the zone's name as the model spells it.

    Returns
    -------
    dict
        Zone name -> :class:`ZoneHeatDelivery`, for the zones with declared equipment only.
    """
    objects = {
        key: {obj.name.upper(): obj for obj in found}
        for key, found in by_key.items()
        if key.startswith(("ZONEHVAC:", "AIRTERMINAL:"))
    }
    lists = objects.get(_EQUIPMENT_LIST, {})
    found: dict[str, list[EquipmentHeat]] = {}
    for obj in by_key.get(_CONNECTIONS, []):
        zone = zone_names.get(obj.fields[0].upper()) if obj.fields else None
        listed = lists.get(obj.fields[1].upper()) if zone and len(obj.fields) > 1 else None
        if listed is None:
            continue
        fields = listed.fields
        # extensible groups after the Name (and the Load Distribution Scheme, since 9.2):
        # class, name, sequences, ... (six fields in 25.2, four before): a class field is
        # recognised by what it names
        for i in range(1, len(fields) - 1):
            key = fields[i].upper()
            if key.startswith(("ZONEHVAC:", "AIRTERMINAL:", "AIRLOOPHVAC:")) and fields[i + 1]:
                found.setdefault(zone, []).append(
                    _equipment_heat(fields[i], fields[i + 1], objects)
                )
    for key, templates in by_key.items():
        if key.startswith(_TEMPLATE_ZONE):
            for obj in templates:
                zone = zone_names.get(obj.fields[0].upper()) if obj.fields else None
                if zone is not None:
                    found.setdefault(zone, []).append(
                        EquipmentHeat(obj.class_name, obj.fields[0], 0.0,
                                      "an air system or convective baseboard: convective")
                    )  # fmt: skip
    out = {}
    for zone, equipment in found.items():
        shares = [e.radiant_fraction for e in equipment]
        share = None if any(s is None for s in shares) else sum(shares) / len(shares)
        out[zone] = ZoneHeatDelivery(tuple(equipment), share)
    return out


#: Equipment (prefixes, upper case) that serves its zone from an air loop: the zone's return
#: air flows back to the loop, carrying the lights' return-air heat away from the zone.
AIR_LOOP_EQUIPMENT = tuple(
    c.upper()
    for c in (
        "AirTerminal:",
        "ZoneHVAC:AirDistributionUnit",
        "AirLoopHVAC:",
        "HVACTemplate:Zone:VAV",
        "HVACTemplate:Zone:ConstantVolume",
        "HVACTemplate:Zone:DualDuct",
        "HVACTemplate:Zone:Unitary",
    )
)


def return_air_stays_in_zone(delivery: ZoneHeatDelivery | None) -> bool:
    """Whether EnergyPlus adds a zone's return-air heat (the lights' *Return Air Fraction*) to
    the zone air: the zone has equipment and none of it is on an air loop.

    EnergyPlus sets a zone's ``NoHeatToReturnAir`` for a zonal system (no return air flow: an
    ideal-loads system, a baseboard, a packaged terminal unit) and then adds the return-air
    gains to the zone's convective gains (ZoneTempPredictorCorrector, ``CalcZoneSums``). With an
    air loop the heat leaves with the return air; without any equipment it is lost as well
    (Case 600FF with 1,500 W of lights at a return-air fraction of 0.5: January 32.8 C against
    41.3 C at 0; with its ideal loads the two are identical).

    Parameters
    ----------
    delivery : ZoneHeatDelivery or None
        The zone's declared equipment (:func:`zone_heat_delivery`); None: none declared.
    """
    if delivery is None or not delivery.equipment:
        return False
    return not any(e.class_name.upper().startswith(AIR_LOOP_EQUIPMENT) for e in delivery.equipment)


#: Position of the availability schedule's field of zone equipment classes (upper-case
#: prefixes, the first that matches; EnergyPlus 25.2's IDD): None where the class has none, or
#: where its availability is read elsewhere (ideal loads: :func:`ideal_loads_records`).
EQUIPMENT_AVAILABILITY_FIELD = tuple(
    (prefix.upper(), position)
    for prefix, position in (
        ("HVACTemplate:Zone:BaseboardHeat", 4),
        ("HVACTemplate:Zone:FanCoil", 9),
        ("HVACTemplate:Zone:PTAC", 11),
        ("HVACTemplate:Zone:PTHP", 11),
        ("HVACTemplate:Zone:WaterToAirHeatPump", 11),
        ("HVACTemplate:Zone:VRF", 19),
        ("HVACTemplate:Zone:", None),
        ("ZoneHVAC:Baseboard:RadiantConvective:Water", 2),
        ("ZoneHVAC:Baseboard:RadiantConvective:Steam", 2),
        ("ZoneHVAC:LowTemperatureRadiant:VariableFlow", 2),
        ("ZoneHVAC:LowTemperatureRadiant:ConstantFlow", 2),
        ("ZoneHVAC:IdealLoadsAirSystem", None),
        ("ZoneHVAC:AirDistributionUnit", None),
        ("ZoneHVAC:", 1),
        ("AirTerminal:SingleDuct:Mixer", None),
        ("AirTerminal:SingleDuct:UserDefined", None),
        ("AirTerminal:", 1),
    )
)


def availability_field(class_name: str) -> int | None:
    """The field holding an equipment class's availability schedule
    (:data:`EQUIPMENT_AVAILABILITY_FIELD`); None: none read."""
    key = class_name.upper()
    for prefix, position in EQUIPMENT_AVAILABILITY_FIELD:
        if key.startswith(prefix):
            return position
    return None


def equipment_availability(delivery: ZoneHeatDelivery, by_key: dict) -> str | None:
    """The one availability schedule that switches all of a zone's equipment off, or None.

    EnergyPlus runs a piece of zone equipment only where its availability schedule is above 0;
    a zone whose every piece is off floats whatever its thermostat says. The model holds a
    zone's set points through a per-step availability mask with AND semantics, so a schedule is
    returned only when every piece names the same one (one baseboard, one terminal unit: the
    common case); an ideal-loads system (read by :func:`ideal_loads_records`), a piece without a
    schedule or with another one gives None (taken as always available).

    Parameters
    ----------
    delivery : ZoneHeatDelivery
        The zone's declared equipment (:func:`zone_heat_delivery`).
    by_key : dict
        Upper-case class name -> list of the file's objects.
    """
    names: dict[str, str] = {}
    for piece in delivery.equipment:
        key = piece.class_name.upper()
        if key.startswith((IDEAL_LOADS_CLASS.upper(), _TEMPLATE_ZONE + "IDEALLOADSAIRSYSTEM")):
            return None
        position = availability_field(key)
        found = next(
            (o for o in by_key.get(key, ())
             if (o.fields[0] if o.fields else "").upper() == str(piece.name).upper()),
            None,
        )  # fmt: skip
        name = (
            found.fields[position].strip()
            if position is not None and found is not None and position < len(found.fields)
            else ""
        )
        if not name:
            return None
        names[name.upper()] = name
    return next(iter(names.values())) if len(names) == 1 else None


#: Equipment classes (upper case, prefixes) that can only heat, and only cool: a zone served by
#: such equipment alone gets no cooling (heating) set point.
HEATING_ONLY = tuple(
    c.upper()
    for c in (
        "ZoneHVAC:Baseboard:",
        "ZoneHVAC:HighTemperatureRadiant",
        "HVACTemplate:Zone:BaseboardHeat",
    )
)
COOLING_ONLY = ("ZoneHVAC:CoolingPanel:".upper(),)

#: How a note on an ideal-loads system's settings that the model does not apply begins.
IDEAL_LOADS_NOT_APPLIED = "Ideal loads settings not applied"

#: The ideal-loads class (read by position, as the other equipment here: it is HVAC the model
#: replaces, not an imported class) and its fields read, 0-based after the class name
#: (EnergyPlus 25.2's IDD).
IDEAL_LOADS_CLASS = "ZoneHVAC:IdealLoadsAirSystem"
_IDEAL_LOADS_FIELDS = (
    "name",
    "availability_schedule_name",
    "zone_supply_air_node_name",
    "zone_exhaust_air_node_name",
    "system_inlet_air_node_name",
    "maximum_heating_supply_air_temperature",
    "minimum_cooling_supply_air_temperature",
    "maximum_heating_supply_air_humidity_ratio",
    "minimum_cooling_supply_air_humidity_ratio",
    "heating_limit",
    "maximum_heating_air_flow_rate",
    "maximum_sensible_heating_capacity",
    "cooling_limit",
    "maximum_cooling_air_flow_rate",
    "maximum_total_cooling_capacity",
    "heating_availability_schedule_name",
    "cooling_availability_schedule_name",
    "dehumidification_control_type",
    "cooling_sensible_heat_ratio",
    "humidification_control_type",
    "design_specification_outdoor_air_object_name",
)


#: ``HVACTemplate:Zone:IdealLoadsAirSystem``'s fields read, 0-based after the class name
#: (EnergyPlus 25.2's IDD): its zone, then the settings of the system EnergyPlus expands it
#: into, under the names of :data:`_IDEAL_LOADS_FIELDS`.
IDEAL_LOADS_TEMPLATE = "HVACTemplate:Zone:IdealLoadsAirSystem"
_IDEAL_LOADS_TEMPLATE_FIELDS = (
    "zone_name",
    "template_thermostat_name",
    "availability_schedule_name",
    "maximum_heating_supply_air_temperature",
    "minimum_cooling_supply_air_temperature",
    "maximum_heating_supply_air_humidity_ratio",
    "minimum_cooling_supply_air_humidity_ratio",
    "heating_limit",
    "maximum_heating_air_flow_rate",
    "maximum_sensible_heating_capacity",
    "cooling_limit",
    "maximum_cooling_air_flow_rate",
    "maximum_total_cooling_capacity",
    "heating_availability_schedule_name",
    "cooling_availability_schedule_name",
    "dehumidification_control_type",
    "cooling_sensible_heat_ratio",
    "dehumidification_setpoint",
    "humidification_control_type",
    "humidification_setpoint",
    "outdoor_air_method",
    "outdoor_air_flow_rate_per_person",
    "outdoor_air_flow_rate_per_zone_floor_area",
    "outdoor_air_flow_rate_per_zone",
    "design_specification_outdoor_air_object_name",
)


def ideal_loads_records(by_key: dict, version: tuple[int, int] = (25, 2)) -> list[dict]:
    """The file's ideal-loads systems as records (field name -> text, ``_object``).

    ``version``: the file's EnergyPlus version; before 8.8 the class had no System Inlet Air
    Node Name (EnergyPlus 8.8, 2017), so the later fields sit one position earlier. The
    ``HVACTemplate:Zone:IdealLoadsAirSystem`` objects are included with the same field names
    and their ``zone_name`` (the template's availability schedules and limits were ignored without
    a note: a system off all January heated 698 kWh where EnergyPlus floated).
    """
    names = _IDEAL_LOADS_FIELDS
    if tuple(version) < (8, 8):
        names = tuple(n for n in names if n != "system_inlet_air_node_name")
    out = []
    for obj in by_key.get(IDEAL_LOADS_CLASS.upper(), []):
        rec = dict(zip(names, obj.fields, strict=False))
        rec["_object"] = obj
        out.append(rec)
    for obj in by_key.get(IDEAL_LOADS_TEMPLATE.upper(), []):
        rec = dict(zip(_IDEAL_LOADS_TEMPLATE_FIELDS, obj.fields, strict=False))
        rec["_object"] = obj
        out.append(rec)
    return out


def ideal_loads_notes(records, schedule_mean) -> list[str]:
    """Notes on the ``ZoneHVAC:IdealLoadsAirSystem`` settings the model does not apply.

    The model's ideal heating and cooling are unlimited and always available at the thermostat's
    set points. EnergyPlus' ideal-loads system can be switched off by its availability schedules
    and limited in flow or capacity: Case 600 with its system always off is a free float in
    EnergyPlus (0 kWh) and was heated and cooled as usual in thermocal (4,244 kWh), without a word.

    Parameters
    ----------
    records : iterable of dict
        The file's ``ZoneHVAC:IdealLoadsAirSystem`` records (field name -> text, ``_object``).
    schedule_mean : callable
        A schedule's name -> its mean over the year [-] (raises for an unknown schedule).

    Returns
    -------
    list of str
        One note per system with such a setting, naming the system, its fields and values.
    """
    notes = []
    for rec in records:
        obj = rec["_object"]

        def field(name: str, rec=rec) -> str:
            return str(rec.get(name) or "").strip()

        found = []
        switched = []
        for key, label in (
            ("availability_schedule_name", "Availability Schedule Name"),
            ("heating_availability_schedule_name", "Heating Availability Schedule Name"),
            ("cooling_availability_schedule_name", "Cooling Availability Schedule Name"),
        ):
            name = field(key)
            if not name:
                continue
            try:
                mean = float(schedule_mean(name))
            except Exception:  # noqa: BLE001 - an unreadable schedule is named as such
                found.append(f"{label} '{name}' (not read)")
                continue
            if 0.0 < mean < 0.999:  # never available: applied (the zone floats), noted there
                switched.append(f"{label} '{name}' (on {100 * mean:.0f} % of the year)")
        if switched:
            notes.append(
                f"{IDEAL_LOADS_NOT_APPLIED.replace('not applied', 'applied')}: {obj.where()} "
                f"has {'; '.join(switched)}: where a schedule is 0 its zone has no such set "
                "point and floats, as EnergyPlus switches the system off (simulated step by "
                "step with the file's schedules; with constant schedules the set points stay on)"
            )
        for limit, flow, capacity, what in (
            (
                "heating_limit",
                "maximum_heating_air_flow_rate",
                "maximum_sensible_heating_capacity",
                "Heating Limit",
            ),
            (
                "cooling_limit",
                "maximum_cooling_air_flow_rate",
                "maximum_total_cooling_capacity",
                "Cooling Limit",
            ),
        ):
            value = field(limit)
            if value and value.upper() != "NOLIMIT":
                details = [
                    f"{label} {field(key)}"
                    for key, label in ((flow, "flow m3/s"), (capacity, "capacity W"))
                    if field(key)
                ]
                found.append(f"{what} '{value}'" + (f" ({', '.join(details)})" if details else ""))
        outdoor = field("design_specification_outdoor_air_object_name")
        method = field("outdoor_air_method")
        if outdoor or method.upper() not in ("", "NONE"):
            what = (
                f"DesignSpecification:OutdoorAir '{outdoor}'"
                if outdoor and method.upper() in ("", "DETAILEDSPECIFICATION")
                else f"Outdoor Air Method '{method}'"
            )
            notes.append(
                f"{IDEAL_LOADS_NOT_APPLIED}: {obj.where()} supplies outdoor air ({what}), which "
                "the model leaves out: EnergyPlus brings it into the zone whenever the system "
                "runs, cooling or warming a zone that floats between its set points (Case 600 "
                "with 0.05 m3/s: 0.6 K colder in July, its zone heating 3.5 % and cooling 9 % "
                "higher in January), and conditions it at the system"
            )
        if found:
            notes.append(
                f"{IDEAL_LOADS_NOT_APPLIED}: {obj.where()} "
                f"has {'; '.join(found)}: the model's ideal heating and cooling are unlimited and "
                "always available at the set points, so its loads and temperatures differ from "
                "EnergyPlus' where these apply (a system always off: simulate --free-float)"
            )
    return notes

