"""Results of a multi-zone simulation: zone temperatures, heat, surfaces and the identification's
tracking, and the files they are written to.

Returned by :class:`thermocal.multizone.simulation.Simulation` (``run`` and ``track``).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from thermocal.errors import ThermocalInputError


@dataclass
class SimulationResult:
    """Output of :meth:`Simulation.run` (frames indexed by step start, one column per zone).

    Attributes
    ----------
    air_temperature : DataFrame [C]
    operative_temperature : DataFrame [C]
        Mean of air and mean radiant (area-weighted interior surface) temperature.
    mean_radiant_temperature : DataFrame [C]
    heating, cooling : DataFrame [W]
        Ideal heating and cooling powers (>= 0), constant over each step.
    heat_input : DataFrame [W]
        Given heat delivered to the zone air.
    transmitted_solar : DataFrame [W]
        Solar radiation transmitted by the windows into each zone.
    infiltration : DataFrame [W]
        Heat brought by infiltration (negative when it cools the zone).
    surface_temperature : DataFrame or None [C]
        Interior surface temperatures (one column per face seen from a zone), if stored.
    step : pandas.Timedelta
    zone_multipliers : dict of str -> float
        An imported file's zone multipliers other than 1 (EnergyPlus' ``Zone`` field): each
        such zone is simulated once, its outputs are one zone's, and the building's totals in
        :meth:`summary` count it that many times, as EnergyPlus' facility totals do.
    """

    air_temperature: pd.DataFrame
    operative_temperature: pd.DataFrame
    mean_radiant_temperature: pd.DataFrame
    heating: pd.DataFrame
    cooling: pd.DataFrame
    heat_input: pd.DataFrame
    transmitted_solar: pd.DataFrame
    infiltration: pd.DataFrame
    surface_temperature: pd.DataFrame | None
    step: pd.Timedelta
    approximations: list = field(default_factory=list)
    zone_multipliers: dict = field(default_factory=dict)

    def summary(self) -> dict:
        """Per zone: min/max/mean air temperature [C], heating/cooling energy [kWh], peaks [kW].

        Peaks are the largest hourly-integrated loads (as ASHRAE Standard 140 reports them) when
        the step divides an hour, otherwise the largest step values.
        """
        hours = self.step.total_seconds() / 3600.0
        to_kwh = hours / 1000.0
        temp = self.air_temperature
        air_h = _hourly_mean(temp, self.step)
        columns = {
            "air_temperature_min_C": temp.min(),
            "air_temperature_max_C": temp.max(),
            "air_temperature_mean_C": temp.mean(),
            # hourly-integrated values, as ASHRAE Standard 140 defines them
            "air_temperature_hourly_min_C": air_h.min(),
            "air_temperature_hourly_max_C": air_h.max(),
            "air_temperature_hourly_mean_C": air_h.mean(),
            "heating_kWh": self.heating.sum() * to_kwh,
            "cooling_kWh": self.cooling.sum() * to_kwh,
            "heating_peak_kW": _hourly_mean(self.heating, self.step).max() / 1000.0,
            "cooling_peak_kW": _hourly_mean(self.cooling, self.step).max() / 1000.0,
            "heat_input_kWh": self.heat_input.sum() * to_kwh,
        }
        table = pd.DataFrame(columns).reindex(temp.columns)
        zones = {
            zone: {key: float(value) for key, value in row.items()}
            for zone, row in zip(table.index, table.to_dict("records"), strict=True)
        }
        # the building's totals count a zone with a multiplier that many times (EnergyPlus'
        # facility totals); the zones' own figures are one zone's
        weight = pd.Series(1.0, index=self.heating.columns)
        for zone, multiplier in self.zone_multipliers.items():
            if zone in weight.index:
                weight[zone] = float(multiplier)
        total_heat = self.heating.mul(weight, axis=1).sum(axis=1)
        total_cool = self.cooling.mul(weight, axis=1).sum(axis=1)
        return {
            "start": str(self.air_temperature.index[0]),
            "end": str(self.air_temperature.index[-1] + self.step),
            "step_seconds": self.step.total_seconds(),
            "zones": zones,
            "building": {
                **(
                    {"zone_multipliers": {k: float(v) for k, v in self.zone_multipliers.items()}}
                    if self.zone_multipliers
                    else {}
                ),
                "heating_kWh": float(total_heat.sum() * hours / 1000.0),
                "cooling_kWh": float(total_cool.sum() * hours / 1000.0),
                "heating_peak_kW": float(_hourly_mean(total_heat, self.step).max() / 1000.0),
                "cooling_peak_kW": float(_hourly_mean(total_cool, self.step).max() / 1000.0),
            },
            "approximations": list(self.approximations),
        }

    def to_files(
        self, directory: str | Path, *, format: str = "csv", quantities=None, report=None
    ) -> list[Path]:
        """Write zone temperatures, heat flows and ``summary.json`` into ``directory``.

        ``zone_temperatures`` rows are stamped with the instant they describe, the end of each
        step (a logger's readings, EnergyPlus' time stamps); ``zone_heat_flows`` rows with the
        start of the step whose mean power they hold (a logger's interval means, ``--rows
        interval_start`` in ``identify``). With a reporting interval, each row is the mean of
        the steps in one interval (EnergyPlus' reporting frequency): temperatures stamped at
        the interval's end, as EnergyPlus stamps its hourly means, heat flows at its start.

        Parameters
        ----------
        directory : str or Path
        format : {"csv", "parquet"}
        quantities : sequence of str, optional
            Which of :data:`OUTPUT_QUANTITIES` to write (default: all); a file whose
            quantities are all left out is not written.
        report : str, optional
            Reporting interval (:func:`report_rule`): None or ``"timestep"`` for every step,
            a duration that is a whole number of steps (``"1h"``, ``"1D"``), ``"hourly"``,
            ``"daily"`` or ``"monthly"`` (calendar months). ``summary.json`` is computed from
            every step whatever the interval.

        Returns
        -------
        list of Path
            The files written.
        """
        if format not in ("csv", "parquet"):
            raise ThermocalInputError(f"format must be 'csv' or 'parquet', got {format!r}")
        chosen = output_quantities(quantities)
        rule = report_rule(report, self.step)
        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        jobs = []
        for name in ("zone_temperatures", "zone_heat_flows"):
            parts = [q for q in chosen if OUTPUT_QUANTITIES[q][0] == name]
            if not parts:
                continue
            at_end = name == "zone_temperatures"

            def rows(frame, at_end=at_end):
                if rule is None:
                    return frame
                # the steps starting in an interval: their temperatures are the states at the
                # steps' ends, so the mean's instant is the interval's end (each quantity on
                # its own: resampling the frames side by side first copies them into one)
                return frame.resample(
                    rule, label="right" if at_end else "left", closed="left"
                ).mean()

            # the quantities side by side without copying them (the writers read a block of
            # rows at a time): a year of a large building is gigabytes per copy
            flat = pd.concat(
                [
                    rows(getattr(self, q)).set_axis(
                        [f"{zone}|{OUTPUT_QUANTITIES[q][1]}" for zone in getattr(self, q).columns],
                        axis=1,
                    )
                    for q in parts
                ],
                axis=1,
            )
            flat.index = flat.index.rename("time")
            if rule is None and at_end:
                # a temperature is the state at the end of its step: its row is stamped with
                # that instant, as a logger's reading (and EnergyPlus' outputs) would be; fed
                # back to identify as a sensor log (--rows reports) a start stamp put every
                # thermostat step one step early (heat spikes of 1-2 kW at each one)
                flat.index = flat.index + self.step
            jobs.append((flat, directory / f"{name}.{format}"))
        writer = _write_csv if format == "csv" else _write_parquet
        if len(jobs) > 1:
            # Arrow's writers release the GIL: the two files are written side by side
            from concurrent.futures import ThreadPoolExecutor

            with ThreadPoolExecutor(max_workers=len(jobs)) as pool:
                list(pool.map(lambda job: writer(*job), jobs))
        else:
            for job in jobs:
                writer(*job)
        written = [path for _, path in jobs]
        path = directory / "summary.json"
        summary = self.summary()
        if rule is not None:
            summary["report"] = _report_description(rule, self.air_temperature.index, self.step)
        path.write_text(json.dumps(summary, indent=2))
        written.append(path)
        return written


@dataclass
class TrackingResult:
    """Output of :meth:`Simulation.track` (frames indexed by step start).

    Attributes
    ----------
    air_temperature, operative_temperature : DataFrame [C]
        Model temperatures of every zone at the end of each step.
    heat : DataFrame [W]
        Heat delivered to each tracked zone over each step (constant over the step), into its
        air and, for a radiant fraction, its surfaces.
    reference : DataFrame [C]
        The tracked reference temperatures.
    feedback : {"air", "operative"}, float or ndarray
        The sensor model as given to :meth:`Simulation.track`.
    method : {"inverse", "pid"}
    step : pandas.Timedelta
    diverged : list of str
        Zones whose loop diverged (the run stopped there; the rest of every frame is NaN).
    sensed_temperature : DataFrame [C]
        The model temperature the sensor model reads, tracked zones only.
    """

    air_temperature: pd.DataFrame
    operative_temperature: pd.DataFrame
    heat: pd.DataFrame
    reference: pd.DataFrame
    feedback: str
    method: str
    step: pd.Timedelta
    diverged: list = field(default_factory=list)
    sensed_temperature: pd.DataFrame | None = None

    def tracked_temperature(self) -> pd.DataFrame:
        """The model temperature that was tracked (the sensor model) of the tracked zones [C]."""
        if self.sensed_temperature is not None:
            return self.sensed_temperature
        frame = self.air_temperature if self.feedback == "air" else self.operative_temperature
        return frame[self.heat.columns]


#: Quantities ``SimulationResult.to_files`` can write: name -> (file stem, column suffix).
OUTPUT_QUANTITIES = {
    "air_temperature": ("zone_temperatures", "air_temperature_C"),
    "operative_temperature": ("zone_temperatures", "operative_temperature_C"),
    "heating": ("zone_heat_flows", "heating_W"),
    "cooling": ("zone_heat_flows", "cooling_W"),
    "heat_input": ("zone_heat_flows", "heat_input_W"),
    "transmitted_solar": ("zone_heat_flows", "transmitted_solar_W"),
    "infiltration": ("zone_heat_flows", "infiltration_W"),
}


def output_quantities(quantities=None) -> list[str]:
    """The quantities to write, checked against :data:`OUTPUT_QUANTITIES` (None: all).

    Parameters
    ----------
    quantities : str or sequence of str, optional
        Names, or one comma-separated string (``"air_temperature,heating"``).
    """
    if quantities is None:
        return list(OUTPUT_QUANTITIES)
    if isinstance(quantities, str):
        quantities = [q.strip() for q in quantities.split(",") if q.strip()]
    unknown = [q for q in quantities if q not in OUTPUT_QUANTITIES]
    if unknown or not quantities:
        raise ThermocalInputError(
            f"output quantities {', '.join(map(repr, unknown)) or '(none given)'}: choose from "
            f"{', '.join(OUTPUT_QUANTITIES)} (comma-separated)"
        )
    return [q for q in OUTPUT_QUANTITIES if q in quantities]


#: Words of EnergyPlus' reporting frequencies -> pandas resampling rule (None: every step).
REPORT_WORDS = {"timestep": None, "hourly": "1h", "daily": "1D", "monthly": "MS"}


def report_rule(report, step: pd.Timedelta) -> str | None:
    """The resampling rule of a reporting interval, checked against the time step.

    Parameters
    ----------
    report : str or None
        None or ``"timestep"`` (every step), ``"hourly"``, ``"daily"``, ``"monthly"``, or a
        duration with its unit (``"30min"``, ``"1h"``, ``"1D"``) that is a whole number of
        steps.
    step : pandas.Timedelta
        The simulation's time step.

    Returns
    -------
    str or None
        A pandas resampling rule, None for every step.
    """
    if report is None:
        return None
    text = str(report).strip()
    word = text.lower()
    if word in REPORT_WORDS:
        rule = REPORT_WORDS[word]
        if rule is None or rule == "MS":
            return rule
        interval = pd.Timedelta(rule)
    else:
        from thermocal.textformat import unitless_duration

        try:
            if unitless_duration(text):
                raise ValueError
            interval = pd.Timedelta(text)
        except (ValueError, TypeError):
            raise ThermocalInputError(
                f"reporting interval {text!r}: give timestep, hourly, daily, monthly or a "
                "duration with its unit, e.g. 1h or 30min"
            ) from None
    ratio = interval / step
    if interval < step or not float(ratio).is_integer():
        raise ThermocalInputError(
            f"reporting interval {text!r} is not a whole number of the {_duration(step)} "
            f"time step: give a multiple of it (e.g. {_duration(step * max(1, math.ceil(ratio)))})"
        )
    # the duration as pandas' fixed frequency ("2 hours", "P1D" and "1W" read as durations are
    # not resampling rules; "1W" would be weeks anchored on Sundays)
    return None if ratio == 1 else pd.tseries.frequencies.to_offset(interval).freqstr


def _duration(value: pd.Timedelta) -> str:
    minutes = value.total_seconds() / 60.0
    return f"{minutes:g}min" if minutes < 60 else f"{minutes / 60.0:g}h"


def _report_description(rule: str, index: pd.DatetimeIndex, step: pd.Timedelta) -> dict:
    """What each row of the files holds, and the intervals the run covers only in part."""
    full = (
        pd.Series(1, index=index).resample(rule, closed="left", label="left").count()
    )
    expected = [
        (_interval_end(start, rule) - start) / step for start in full.index
    ]
    partial = [
        str(start)
        for start, count, whole in zip(full.index, full.to_numpy(), expected, strict=True)
        if count < whole
    ]
    return {
        "interval": "monthly"
        if rule == "MS"
        else _duration(pd.Timedelta(pd.tseries.frequencies.to_offset(rule))),
        "rows": "means over each interval of the steps starting in it; zone_temperatures "
        "stamped at the interval's end, zone_heat_flows at its start",
        "partial_intervals": partial,
    }


def _interval_end(start: pd.Timestamp, rule: str) -> pd.Timestamp:
    if rule == "MS":
        return start + pd.offsets.MonthBegin(1)
    return start + pd.tseries.frequencies.to_offset(rule)


def _write_parquet(frame: pd.DataFrame, path: Path) -> None:
    frame.to_parquet(path)


def _write_csv(frame: pd.DataFrame, path: Path) -> None:
    """Values rounded to 4 decimals (0.1 mK, 0.1 mW), time labels as pandas prints them."""
    from thermocal.io.csv_writer import write_frame_csv

    write_frame_csv(frame, path, decimals=4)


def _hourly_mean(frame, step: pd.Timedelta):
    per_hour = pd.Timedelta("1h") / step
    if per_hour >= 1 and float(per_hour).is_integer() and per_hour > 1:
        return frame.resample("1h").mean()
    return frame
