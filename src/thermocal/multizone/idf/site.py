"""Site, geometry rules, building, time step, run period and ground of an IDF file.

Stages of the import (:class:`SiteStages`, mixed into the builder of
:func:`thermocal.multizone.idf.read_idf`): ``Building`` (name, north axis), ``GlobalGeometryRules``,
``Site:Location``, ``Timestep``, ``RunPeriod`` (period, calendar year of the schedules, the use
of the weather file's holidays and daylight saving period and the weekend holiday rule), the
:class:`ScheduleEvaluator` of the file, and ``Site:GroundTemperature:BuildingSurface``.
"""

from __future__ import annotations

import calendar
import datetime as _dt
from typing import NamedTuple

from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.fields import SCHEMA
from thermocal.multizone.idf.geometry import GeometryRules
from thermocal.multizone.idf.parse import _number, _wrap
from thermocal.multizone.idf.report import EP_CHECK
from thermocal.multizone.idf.schedules import ScheduleEvaluator, year_for_start_day

#: EnergyPlus default ground temperature [C] when Site:GroundTemperature:BuildingSurface is absent.
ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE = 18.0
#: EnergyPlus default ground reflectance [-] when Site:GroundReflectance is absent (not the
#: weather file's albedo, which EnergyPlus does not use).
ENERGYPLUS_DEFAULT_GROUND_REFLECTANCE = 0.2


class RunPeriod(NamedTuple):
    """The first ``RunPeriod`` of an IDF as written (a blank year is None)."""

    name: str
    begin_month: int
    begin_day: int
    end_month: int
    end_day: int
    begin_year: int | None
    end_year: int | None
    #: the object and its file line, for messages
    where: str = "RunPeriod"


def _run_period_date(
    period: RunPeriod, which: str, year: int, month: int, day: int
) -> _dt.date | None:
    """``month/day`` of ``year`` for the RunPeriod's ``which`` ("Begin" or "End") date, None
    for 2/29 of a common year (the caller says what follows); a date no year has (13/1, 4/31,
    2/30) is refused naming the fields."""
    if not 1 <= month <= 12 or not 1 <= day <= calendar.monthrange(2000, month)[1]:
        raise ThermocalInputError(
            f"{period.where}: fields '{which} Month' = {month} and '{which} Day of Month' = "
            f"{day} are not a date: give a month 1-12 and a day of that month"
        )
    return _dt.date(year, month, day) if calendar.isleap(year) or (month, day) != (2, 29) else None


def run_period_dates(period: RunPeriod, weather_year: int) -> tuple[_dt.date, _dt.date, list[str]]:
    """The first and last day of a RunPeriod's run, as EnergyPlus (9.0 and later) dates it.

    A blank ``Begin Year`` is the weather's (the run follows the weather file's calendar). A
    blank ``End Year`` is the begin year, or the next one when the end's month and day come
    before the begin's: the period crosses new year (12/1 to 1/31 runs into January of the
    next year). An end on 29 February in a common year with a blank ``End Year`` ends on 28
    February (noted: EnergyPlus would run on to the next leap year's); with the year given it
    is refused, as EnergyPlus refuses it.

    Parameters
    ----------
    period : RunPeriod
        As read from the IDF.
    weather_year : int
        The (first) year of the weather file's calendar [a.d.].

    Returns
    -------
    begin, last : datetime.date
        The first and the last day of the run (both whole days).
    notes : list of str
        What was assumed.

    Raises
    ------
    ThermocalInputError
        Month and day that are no date, 29 February of a common begin year or given end year,
        and a given end year that puts the end before the begin: named by the RunPeriod, its
        line and the fields.
    """
    notes: list[str] = []
    begin_year = weather_year if period.begin_year is None else period.begin_year
    begin = _run_period_date(period, "Begin", begin_year, period.begin_month, period.begin_day)
    if begin is None:
        given = period.begin_year is not None
        raise ThermocalInputError(
            f"{period.where}: the begin date 2/29 does not exist in {begin_year} ("
            + ("field 'Begin Year'" if given else "the weather file's year, as 'Begin Year' is "
               "blank")
            + "), a common year: begin on 2/28 or 3/1"
            + (", or give a leap year" if given else ", or use a weather file of a leap year")
        )  # fmt: skip
    end_month, end_day = period.end_month, period.end_day
    if period.end_year is not None:
        end = _run_period_date(period, "End", period.end_year, end_month, end_day)
        if end is None:  # EnergyPlus: severe error, "end year is not a leap year"
            raise ThermocalInputError(
                f"{period.where}: field 'End Year' = {period.end_year} is a common year, but the "
                "end date is 2/29: end on 2/28, or give a leap 'End Year'"
            )
        if end < begin:
            raise ThermocalInputError(
                f"{period.where}: the run would end on {end} (fields 'End Month', 'End Day of "
                f"Month', 'End Year') before it begins on {begin}: check 'End Year' (or leave "
                "it blank: an end before the begin in the year then runs into the next year)"
            )
        return begin, end, notes
    crosses = (end_month, end_day) < (period.begin_month, period.begin_day)
    end_year = begin_year + 1 if crosses else begin_year
    end = _run_period_date(period, "End", end_year, end_month, end_day)
    if end is None:
        end = _dt.date(end_year, 2, 28)
        notes.append(
            f"{period.where}: the end date 2/29 does not exist in {end_year} ('End Year' "
            "blank), a common year: the run ends on 2/28, the end of February (EnergyPlus "
            "would run on to 2/29 of the next leap year; give 'End Year' or end on 2/28 to say "
            "which)"
        )
    return begin, end, notes


class SiteStages:
    """Stages ``_site`` and ``_ground`` of the builder.

    ``_site`` sets ``building_name``, ``north_axis``, ``rules``, ``location``, ``year`` and
    ``schedules`` (and ``info.timesteps_per_hour``, ``info.run_period``, ``info.schedules``);
    ``_ground`` sets ``ground``.
    """

    def _site(self) -> None:
        """Stage: site, rules, building."""
        building_rec = self.single("BUILDING")
        self.building_name = self.path.stem
        self.north_axis = 0.0
        if building_rec is not None:
            self.building_name = building_rec["name"] or self.building_name
            self.north_axis = _number(building_rec, "north_axis", default=0.0)
            self.info.warmup = {
                "tolerance_K": _number(
                    building_rec, "temperature_convergence_tolerance_value", default=0.4
                ),
                "maximum_days": int(
                    _number(building_rec, "maximum_number_of_warmup_days", default=25)
                ),
                "minimum_days": int(
                    _number(building_rec, "minimum_number_of_warmup_days", default=1)
                ),
            }
        rules_rec = self.single("GLOBALGEOMETRYRULES")
        self.rules = GeometryRules()
        if rules_rec is None:
            self.info.notes.append(
                f"{EP_CHECK}{self.path.name}: no GlobalGeometryRules object; EnergyPlus refuses "
                "the file (\"Missing required property 'GlobalGeometryRules'\"); read with "
                "UpperLeftCorner, Counterclockwise, Relative coordinates (zone origins and "
                "north axes applied); add e.g. 'GlobalGeometryRules,UpperLeftCorner,"
                "Counterclockwise,Relative;' (or World if the coordinates are absolute)"
            )
        else:
            self.rules = GeometryRules(
                rules_rec["starting_vertex_position"] or "UpperLeftCorner",
                rules_rec["vertex_entry_direction"] or "Counterclockwise",
                rules_rec["coordinate_system"] or "Relative",
                rules_rec["rectangular_surface_coordinate_system"] or "Relative",
            )
            if self.rules.vertex_entry_direction.upper() not in ("COUNTERCLOCKWISE", "CLOCKWISE"):
                raise ThermocalInputError(
                    f"{rules_rec['_object'].where()}: field 'Vertex Entry Direction' = "
                    f"'{self.rules.vertex_entry_direction}' must be Counterclockwise or Clockwise."
                )
            if self.rules.coordinate_system.upper() not in ("RELATIVE", "WORLD", "ABSOLUTE"):
                raise ThermocalInputError(
                    f"{rules_rec['_object'].where()}: field 'Coordinate System' = "
                    f"'{self.rules.coordinate_system}' must be Relative, World or Absolute."
                )
            if self.rules.rectangular_surface_coordinate_system.upper() not in (
                "RELATIVE",
                "WORLD",
                "ABSOLUTE",
            ):
                raise ThermocalInputError(
                    f"{rules_rec['_object'].where()}: field 'Rectangular Surface Coordinate "
                    f"System' = '{self.rules.rectangular_surface_coordinate_system}' must be "
                    "Relative, World or Absolute."
                )
            self.info.notes.extend(_absolute_notes(rules_rec))
        self.location = self.mz.Location()
        loc_rec = self.single("SITE:LOCATION")
        if loc_rec is not None:
            self.location = _wrap(
                loc_rec["_object"],
                self.mz.Location,
                latitude=_number(loc_rec, "latitude", default=0.0),
                longitude=_number(loc_rec, "longitude", default=0.0),
                altitude=_number(loc_rec, "elevation", default=0.0),
                timezone=_number(loc_rec, "time_zone", default=0.0),
            )
        else:
            self.info.notes.append("no Site:Location: the model's default location is used")
        timestep = self.single("TIMESTEP")
        if timestep is not None:
            per_hour = _number(timestep, "number_of_timesteps_per_hour", default=6.0)
            divisors = (1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30, 60)
            if not 1 <= per_hour <= 60:
                raise ThermocalInputError(
                    f"{timestep['_object'].where()}: field 'Number of Timesteps per Hour' = "
                    f"{per_hour:g}: give 1 to 60 (a divisor of 60: 1, 2, 3, 4, 5, 6, 10, 12, "
                    "15, 20, 30 or 60)"
                )
            if per_hour not in divisors:
                chosen = min(d for d in divisors if d >= per_hour)
                self.info.notes.append(
                    f"{timestep['_object'].where()}: {per_hour:g} timesteps per hour do not "
                    f"divide an hour; {chosen} per hour used"
                )
                per_hour = chosen
            self.info.timesteps_per_hour = int(per_hour)
        for rp in self.by_key.get("RUNPERIOD", [])[:1]:
            # Name, Begin Month, Begin Day, Begin Year, End Month, End Day (9.x and later);
            # before 9.0: Name, Begin Month, Begin Day, End Month, End Day (no begin year)
            f = [x.strip() for x in rp.fields] + [""] * 6
            if self.version < (9, 0):
                f = [*f[:3], "", *f[3:]]
            try:
                begin_year = int(float(f[3])) if f[3] else None
                # End Year: 9.x and later (before, the end is in the begin year or the next)
                end_year = int(float(f[6])) if f[6] and self.version >= (9, 0) else None
                self.info.run_period = RunPeriod(
                    f[0],
                    int(float(f[1])),
                    int(float(f[2])),
                    int(float(f[4])),
                    int(float(f[5])),
                    begin_year,
                    end_year,
                    rp.where(),
                )
            except ValueError:
                raise ThermocalInputError(
                    f"{rp.where()}: the begin/end month, day and year fields must be numbers."
                ) from None
        self._other_run_periods()
        if self.year is None:
            self.year = 2006
            for rp in self.by_key.get("RUNPERIOD", [])[:1]:
                # 9.x layout: Name, Begin Month, Begin Day, Begin Year, End Month, End Day,
                # End Year, Day of Week for Start Day, ...
                f = [x.strip() for x in rp.fields] + [""] * 8
                if f[3] and self.version >= (9, 0):
                    try:
                        self.year = int(float(f[3]))
                    except ValueError:
                        pass
                elif self.version >= (9, 0) and f[7].upper() != "USEWEATHERFILE":
                    # no year: EnergyPlus starts on the given day of week (Sunday when blank)
                    self.year = year_for_start_day(
                        int(float(f[1] or 1)), int(float(f[2] or 1)), f[7] or "Sunday", rp.where()
                    )
                elif self.version >= (9, 0) and f[7]:
                    self.info.notes.append(
                        f"{rp.where()}: 'Day of Week for Start Day' = {f[7]}: weekdays of 2006 used"
                    )
        # RunPeriod: Use Weather File Holidays and Special Days, Use Weather File Daylight Saving
        # Period (both Yes when blank), Apply Weekend Holiday Rule (No when blank); applied by
        # the evaluator, the weather file's calendar once the simulation reads it
        calendar_flags = {}
        for rp in self.by_key.get("RUNPERIOD", [])[:1] if self.version >= (9, 0) else []:
            f = [x.strip().upper() for x in rp.fields] + [""] * 11
            # 'Use Weather File Rain Indicators' (field 12, Yes when blank)
            self.info.use_weather_rain = f[11] != "NO"
            calendar_flags = {
                "weather_holidays": f[8] != "NO",
                "weather_daylight_saving": f[9] != "NO",
                "weekend_rule": f[10] == "YES",
            }
        self.schedules = ScheduleEvaluator(
            self.objects,
            year=self.year,
            version=self.version,
            base_dir=self.path.parent,
            notes=self.info.notes,
            **calendar_flags,
        )
        self.info.schedules = self.schedules

    def _other_run_periods(self) -> None:
        """Notes on what EnergyPlus would run that ``simulate`` does not: the RunPeriods after
        the first (EnergyPlus runs each in turn; NREL's test files often give two), and a
        ``SimulationControl`` that runs no weather-file period at all."""
        periods = self.by_key.get("RUNPERIOD", [])
        for rp in periods[1:]:
            f = [x.strip() for x in rp.fields] + [""] * 7
            if self.version < (9, 0):
                f = [*f[:3], "", *f[3:]]
            span = f"{f[1]}/{f[2]} to {f[4]}/{f[5]}"
            self.info.notes.append(
                f"{rp.where()} ({span}, month/day) is not simulated: thermocal runs the file's "
                f"first RunPeriod ({periods[0].where()}) where EnergyPlus runs each in turn; "
                "simulate it with --start and --end"
            )
        for control in self.by_key.get("SIMULATIONCONTROL", [])[:1]:
            fields = [x.strip().upper() for x in control.fields] + [""] * 5
            if periods and fields[4] == "NO":
                self.info.notes.append(
                    f"{control.where()}: 'Run Simulation for Weather File Run Periods' is No, "
                    "so EnergyPlus runs only the sizing periods (design days) of this file; "
                    "thermocal simulates its RunPeriod with the weather given"
                )

    def _ground_reflectance(self) -> None:
        """Stage: ground reflectance, as EnergyPlus takes it.

        ``Site:GroundReflectance`` (12 monthly values) or, when absent, EnergyPlus' constant 0.2;
        EnergyPlus never uses the weather file's albedo, so neither does the imported model.
        ``Site:GroundReflectance:SnowModifier`` (a factor on snow days) is noted, not applied.
        """
        rec = self.single("SITE:GROUNDREFLECTANCE")
        names = SCHEMA["SITE:GROUNDREFLECTANCE"][0]
        self.ground_reflectance = tuple(
            _number(rec, n, default=ENERGYPLUS_DEFAULT_GROUND_REFLECTANCE)
            if rec is not None
            else ENERGYPLUS_DEFAULT_GROUND_REFLECTANCE
            for n in names
        )
        snow = self.single("SITE:GROUNDREFLECTANCE:SNOWMODIFIER")
        modifier = 1.0
        if snow is not None:
            modifier = _number(snow, "ground_reflected_solar_modifier", default=1.0)
        if modifier != 1.0:
            self.info.notes.append(
                "Site:GroundReflectance:SnowModifier: the factor on days with snow is not applied "
                "(the model keeps the monthly ground reflectance on snow days)"
            )

    def _ground(self) -> None:
        """Stage: ground.

        Surfaces with the ``Ground`` boundary face ``Site:GroundTemperature:BuildingSurface``
        (EnergyPlus' default 18 C when absent), those with ``GroundFCfactorMethod`` (the C- and
        F-factor constructions) face ``Site:GroundTemperature:FCfactorMethod`` (when absent,
        EnergyPlus takes the weather file's ground temperatures at 0.5 m; the model then takes
        the weather file's ground temperatures at the depth nearest 2 m, noted). The model has
        one ground temperature per building: when both kinds of surfaces are present with
        different temperatures, the BuildingSurface values serve both (noted).
        """
        kinds = {"GROUND": 0, "GROUNDFCFACTORMETHOD": 0}
        preprocessor: dict[str, int] = {}
        for _name, _obj, rec in self.surfaces.values():  # simple-geometry ones included
            key = (rec.get("outside_boundary_condition") or "").upper()
            if key in kinds:
                kinds[key] += 1
            elif key.startswith("GROUND"):
                preprocessor[rec["outside_boundary_condition"]] = (
                    preprocessor.get(rec["outside_boundary_condition"], 0) + 1
                )
        for condition, count in preprocessor.items():
            self.info.notes.append(
                f"{count} surface(s) with the boundary {condition}: they see the building's one "
                "ground temperature (Site:GroundTemperature:BuildingSurface) instead of the "
                "slab/basement preprocessor's temperatures"
            )
        ground_rec = self.single("SITE:GROUNDTEMPERATURE:BUILDINGSURFACE")
        fc_rec = self.single("SITE:GROUNDTEMPERATURE:FCFACTORMETHOD")
        fc = None
        if fc_rec is not None:
            fc = tuple(
                _number(fc_rec, n, default=13.0)
                for n in SCHEMA["SITE:GROUNDTEMPERATURE:FCFACTORMETHOD"][0]
            )
        self._ground_reflectance()
        self.ground = None
        if ground_rec is not None:
            self.ground = tuple(
                _number(ground_rec, n, default=ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE)
                for n in SCHEMA["SITE:GROUNDTEMPERATURE:BUILDINGSURFACE"][0]
            )
        n_plain, n_fc = kinds["GROUND"], kinds["GROUNDFCFACTORMETHOD"]
        if n_fc and not n_plain:
            self.ground = fc
            if fc is None:
                self.info.notes.append(
                    f"no Site:GroundTemperature:FCfactorMethod: the {n_fc} GroundFCfactorMethod "
                    "surface(s) see the weather file's ground temperatures at the depth nearest "
                    "2 m (EnergyPlus takes those at 0.5 m)"
                )
            return
        if n_fc and n_plain:
            plain = self.ground or (ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE,) * 12
            if fc is None or fc != plain:
                self.info.notes.append(
                    f"{n_fc} GroundFCfactorMethod and {n_plain} Ground surface(s): the model has "
                    "one ground temperature per building, the C/F-factor surfaces see "
                    "Site:GroundTemperature:BuildingSurface instead of "
                    + (
                        "Site:GroundTemperature:FCfactorMethod"
                        if fc is not None
                        else "the weather file's 0.5 m ground temperatures"
                    )
                )
        on_ground = [
            s for s in self.model_surfaces
            if s.boundary == "ground" and s.name not in getattr(self, "foundations", {})
        ]  # fmt: skip
        if self.ground is None and on_ground:
            self.ground = (ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE,) * 12
            self.info.notes.append(
                "no Site:GroundTemperature:BuildingSurface: ground surfaces see the EnergyPlus "
                f"default {ENERGYPLUS_DEFAULT_GROUND_TEMPERATURE:g} C"
            )


def _absolute_notes(rules_rec: dict) -> list[str]:
    """Notes on ``Absolute`` in the coordinate-system fields of ``GlobalGeometryRules``: read as
    ``World`` (its meaning in older EnergyPlus input), but EnergyPlus 25.2 accepts only
    ``Relative`` or ``World`` and refuses the file ("Failed to match against any enum
    values")."""
    fields = {
        "coordinate_system": "Coordinate System",
        "rectangular_surface_coordinate_system": "Rectangular Surface Coordinate System",
    }
    return [
        f"{EP_CHECK}{rules_rec['_object'].where()}: field '{label}' = 'Absolute' is read as "
        "World; EnergyPlus 25.2 refuses it (its choices are Relative and World): write World"
        for key, label in fields.items()
        if (rules_rec.get(key) or "").upper() == "ABSOLUTE"
    ]
