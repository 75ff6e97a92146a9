"""The heat-balance identification workflow: sensors -> references -> tuning -> closed loop.

:func:`identify` is the orchestrator; :class:`IdentificationResult` carries what came out and
writes it (``identification.json``, ``q_id.parquet``, figures, an HTML report section).
"""

from __future__ import annotations

import json
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.identification.form import (
    building_to_simulate,
    declared_form,
    declared_form_requested,
    loads_note,
)
from thermocal.identification.metrics import (
    tracking_metrics,
    unoccupied_steps,
    unoccupied_variance,
)
from thermocal.identification.occupancy import OccupancySchedule
from thermocal.identification.pid import PIDGains, kernel_coefficients
from thermocal.identification.sensor_accuracy import (
    DEFAULT_SENSOR_ACCURACY_K,
    held_zone_conductance,
    sensor_heat_uncertainty,
    uncertainty_note,
)
from thermocal.identification.sensors import (
    SensorMapping,
    frame_over_own_array,
    in_building_spelling,
    mapping_from_dict,
    zone_references,
)
from thermocal.identification.tuning import (
    TuningResult,
    check_tuning_zone,
    tune_zone,
    volume_scaled_gains,
)
from thermocal.io.atomic import atomic_parquet, atomic_write

METHODS = ("inverse", "pid", "both")

#: Times the gains of a zone whose PID loop diverges are halved before giving up [-]
RETUNE_ATTEMPTS = 4

#: Default radiant fraction of the identified heat [-]: the share of typical sensible internal
#: gains that reaches a zone as radiation (long-wave and visible); argued in
#: docs/identification.md ("The form of the identified heat").
DEFAULT_RADIANT_FRACTION = 0.6


@dataclass
class IdentificationResult:
    """What the identification found.

    Attributes
    ----------
    q_id : DataFrame (steps x zones) [W]
        Identified heat of the metric source (``metric_source``), per zone and step.
    q_inverse, q_pid : DataFrame or None [W]
        Identified heat of each method that ran.
    reference : DataFrame [C]
        Zone reference temperatures (sensors mapped to zones).
    model_temperature : dict of method -> DataFrame [C]
        The tracked model temperature (air or operative) per method.
    tracking : dict of method -> DataFrame
        Per-zone tracking metrics (:func:`~thermocal.identification.metrics.tracking_metrics`).
    sources : DataFrame
        Every zone with the source of its reference (own sensor, named, neighbour).
    gains : dict of zone -> PIDGains or None
    tuning : TuningResult or None
    weather : DataFrame
        ``temp_air`` [C] and ``ghi`` [W/m2] on the grid.
    schedule : OccupancySchedule
    settle : str or None
    metric_source : {"inverse", "pid"}
    feedback : str
        The sensor model: "air", "operative", "air weight 0.7" or "per zone".
    timings : dict [s]
    notes : list of str
    interpolated, substituted : DataFrame or None
        Gaps of the references filled by interpolation / another zone's data.
    form : DataFrame or None
        Per zone: ``treatment`` (tracked or floating), ``radiant_fraction`` [-] and
        ``sensor_air_weight`` [-] of the identified heat.
    floating_temperature : DataFrame or None [C]
        Air temperature of the floating zones (no reference, ``Q_ID = 0``).
    import_notes : list of str
        What the building import and the simulation flattened, skipped or approximated
        (:meth:`~thermocal.multizone.Simulation.approximations`).
    weather_year : dict or None
        How the weather file's year met the measurements (``kind`` typical/actual, ``years``,
        ``statement`` with the weekday alignment; :func:`thermocal.io.weather.weather_for_period`).
    accepted_constant_readings : list of dict
        Long constant sensor readings accepted as a controlled room rather than refused as a
        stuck sensor (a set point, the log's resolution, the mapping's ``constant_readings``):
        ``sensor``, ``zone``, ``value_C``, ``start``, ``end``, ``duration_h``, ``why``
        (:func:`thermocal.identification.sensors.check_sensor_plausibility`).
    log_clock : dict or None
        The sensor log's clock check (:func:`check_identified_log_clock`): ``std`` (shift [h]
        -> unoccupied standard deviation of the exact inverse's building heat [W]), ``best``
        [h], ``gain`` [-], ``tolerance`` [-], ``passed``, ``note`` (and ``halves`` when a shift
        fits better); with ``checked: false``, ``passed: None`` and a ``reason`` when the check
        could not run (a period too short to shift); None when switched off.
    removed_readings : list of dict
        Sensor readings removed before the identification as physically impossible or as
        isolated spikes, bridged as gaps: ``sensor``, ``zone``, ``time``, ``value_C``,
        ``flag``, ``reason`` (:func:`thermocal.identification.sensors.removed_readings`).
    setpoint_excursions : list of dict
        Zones whose reading stays beyond a set point the building file holds them at, one
        record per zone and side (:func:`thermocal.identification.sensors.setpoint_excursions`).
    sensor_uncertainty : dict or None
        The identified heat's standard uncertainty from the sensors' accuracy, per zone and for
        the building, offsets independent and shared
        (:func:`thermocal.identification.sensor_accuracy.sensor_heat_uncertainty`).
    """

    q_id: pd.DataFrame
    q_inverse: pd.DataFrame | None
    q_pid: pd.DataFrame | None
    reference: pd.DataFrame
    model_temperature: dict
    tracking: dict
    sources: pd.DataFrame
    gains: dict | None
    tuning: TuningResult | None
    weather: pd.DataFrame
    schedule: OccupancySchedule
    settle: str | None
    metric_source: str
    feedback: str
    timings: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    interpolated: pd.DataFrame | None = None
    substituted: pd.DataFrame | None = None
    form: pd.DataFrame | None = None
    floating_temperature: pd.DataFrame | None = None
    import_notes: list = field(default_factory=list)
    weather_year: dict | None = None
    log_clock: dict | None = None
    accepted_constant_readings: list = field(default_factory=list)
    removed_readings: list = field(default_factory=list)
    setpoint_excursions: list = field(default_factory=list)
    sensor_uncertainty: dict | None = None

    @property
    def building_heat(self) -> pd.Series:
        """Building-wide identified heat per step (sum over the zones) [W]."""
        return self.q_id.sum(axis=1)

    def unoccupied_variance(self) -> float:
        """The calibration metric: variance of the building total over unoccupied steps [W^2]."""
        return unoccupied_variance(self.q_id, self.schedule, settle=self.settle)

    def unoccupied_mask(self) -> np.ndarray:
        return unoccupied_steps(self.q_id.index, self.schedule, settle=self.settle)

    def method_difference(self) -> dict | None:
        """PID minus inverse: RMS and max of the building total, worst zone RMS [W]."""
        if self.q_pid is None or self.q_inverse is None:
            return None
        diff = self.q_pid - self.q_inverse
        total = diff.sum(axis=1)
        per_zone = np.sqrt((diff**2).mean(axis=0))
        return {
            "building_rms_W": float(np.sqrt((total**2).mean())),
            "building_max_abs_W": float(total.abs().max()),
            "building_inverse_std_W": float(self.q_inverse.sum(axis=1).std()),
            "worst_zone": str(per_zone.idxmax()),
            "worst_zone_rms_W": float(per_zone.max()),
            "unoccupied_variance_pid_W2": unoccupied_variance(
                self.q_pid, self.schedule, settle=self.settle
            ),
            "unoccupied_variance_inverse_W2": unoccupied_variance(
                self.q_inverse, self.schedule, settle=self.settle
            ),
        }

    def worst_tracked(self, n: int = 10) -> pd.DataFrame:
        """The ``n`` zones with the largest tracking RMSE of the PID (or the metric source)."""
        table = self.tracking.get("pid", self.tracking.get(self.metric_source))
        return table.sort_values("rmse_K", ascending=False).head(n)

    def as_dict(self) -> dict:
        """The content of ``identification.json``."""
        mask = self.unoccupied_mask()
        total = self.building_heat
        out = {
            "metric_source": self.metric_source,
            "feedback": self.feedback,
            "period": {
                "start": str(self.q_id.index[0]),
                "end": str(self.q_id.index[-1] + (self.q_id.index[1] - self.q_id.index[0])),
                "steps": len(self.q_id),
                "step_seconds": (self.q_id.index[1] - self.q_id.index[0]).total_seconds(),
            },
            "unoccupied_variance_W2": self.unoccupied_variance(),
            "unoccupied_std_W": float(np.sqrt(self.unoccupied_variance())),
            "unoccupied_mean_W": float(total.to_numpy()[mask].mean()),
            "occupied_mean_W": float(total.to_numpy()[~self.unoccupied_mask_all()].mean())
            if (~self.unoccupied_mask_all()).any()
            else None,
            "unoccupied_steps": int(mask.sum()),
            "schedule": self.schedule.as_dict(),
            "settle": self.settle,
            "tuning": None if self.tuning is None else self.tuning.as_dict(),
            "gains": None
            if self.gains is None
            else {zone: g.as_dict() for zone, g in self.gains.items()},
            "pid_vs_inverse": self.method_difference(),
            "tracking": {
                method: table.round(6).reset_index().to_dict(orient="records")
                for method, table in self.tracking.items()
            },
            "zones": self.zone_table().to_dict(orient="records"),
            "interpolated_gaps": _records(self.interpolated),
            "substituted_gaps": _records(self.substituted),
            "timings_s": self.timings,
            "notes": self.notes,
            "import_notes": self.import_notes,
            "weather_year": self.weather_year,
            "log_clock": self.log_clock,
            "accepted_constant_readings": self.accepted_constant_readings,
            "removed_readings": self.removed_readings,
            "setpoint_excursions": self.setpoint_excursions,
            "sensor_uncertainty": self.sensor_uncertainty,
        }
        return jsonable(out)

    def zone_table(self) -> pd.DataFrame:
        """Every zone: source of its reference, treatment and the form of its identified heat."""
        table = self.sources.copy()
        if self.form is not None:
            table = table.merge(self.form, left_on="zone", right_index=True, how="left")
        if self.floating_temperature is not None and len(self.floating_temperature.columns):
            mean = self.floating_temperature.mean()
            table["mean_temperature_C"] = table["zone"].map(mean)
        return table

    def unoccupied_mask_all(self) -> np.ndarray:
        return unoccupied_steps(self.q_id.index, self.schedule, settle=None)

    def q_frame(self) -> pd.DataFrame:
        """Per-zone and total Q_ID of every method that ran, columns ``method|zone`` [W]."""
        parts = {}
        for method, frame in (("inverse", self.q_inverse), ("pid", self.q_pid)):
            if frame is not None:
                parts[method] = frame.assign(total=frame.sum(axis=1))
        flat = pd.concat(parts, axis=1)
        flat.columns = [f"{method}|{zone}" for method, zone in flat.columns]
        flat.index.name = "time"
        return flat

    def to_files(self, directory: str | Path, *, report: bool = True) -> list[Path]:
        """Write identification.json, q_id.parquet, figures and report.html into ``directory``.

        Every file is written to a temporary name and renamed when complete, so that an
        interrupted run never leaves a half-written file.
        """
        from thermocal.identification import figures

        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        written = [
            _atomic_text(directory / "identification.json", json.dumps(self.as_dict(), indent=2)),
            _atomic_parquet(directory / "q_id.parquet", self.q_frame()),
        ]
        pngs = {}
        for name, fig in figures.identification_figures(self).items():
            pngs[name] = _png(fig)
            written.append(_atomic_bytes(directory / f"{name}.png", pngs[name]))
        if report:
            from thermocal.identification.report import write_report

            written.append(write_report(self, directory / "report.html", pngs=pngs))
        return written


def _records(frame):
    if frame is None or frame.empty:
        return []
    return frame.astype({c: str for c in ("start", "end") if c in frame}).to_dict(orient="records")


def jsonable(value):
    """``value`` with numpy scalars, timestamps and non-finite floats made JSON-ready."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    if isinstance(value, pd.Timestamp):
        return str(value)
    return value


def _atomic_text(path: Path, text: str) -> Path:
    return atomic_write(path, lambda tmp: tmp.write_text(text))


def _atomic_parquet(path: Path, frame: pd.DataFrame) -> Path:
    return atomic_parquet(path, frame)


def _png(fig) -> bytes:
    from thermocal.report.figures import close, figure_to_png

    data = figure_to_png(fig)
    close(fig)
    return data


def _atomic_bytes(path: Path, data: bytes) -> Path:
    return atomic_write(path, lambda tmp: tmp.write_bytes(data))


def pid_gains_for(
    building,
    *,
    gains: PIDGains | Mapping | None,
    step,
    feedback="air",
    radiant_fraction=0.0,
    options=None,
    metadata=None,
    outdoor_temperature: float = 0.0,
    wind_speed: float = 0.0,
    tuning_zone: str | None = None,
    tracked=None,
) -> tuple[dict[str, PIDGains], TuningResult | None]:
    """Gains of every zone: given (one set scaled by volume, or per zone) or Ziegler-Nichols.

    ``feedback`` and ``radiant_fraction``: one value or per zone (Series or dict), the form of
    the identified heat the tuned loop uses; ``tracked``: the zones with a loop (default all;
    given per-zone gains must cover them).
    """
    tracked = list(building.zones) if tracked is None else list(tracked)
    if tuning_zone is not None:
        check_tuning_zone(building, tuning_zone)
    if gains is None:
        from thermocal.identification.tuning import median_volume_zone

        zone = tuning_zone or median_volume_zone(building)

        def at(value):
            return value[zone] if isinstance(value, Mapping | pd.Series) else value

        tuning = tune_zone(
            building,
            zone=zone,
            step=step,
            outdoor_temperature=outdoor_temperature,
            wind_speed=wind_speed,
            feedback=at(feedback),
            radiant_fraction=float(at(radiant_fraction)),
            options=options,
            metadata=metadata,
        )
        return volume_scaled_gains(building, tuning), tuning
    if isinstance(gains, PIDGains):
        reference_zone = tuning_zone or list(building.zones)[0]
        volume = building.zones[reference_zone].volume
        return {
            name: gains.scaled(zone.volume / volume) for name, zone in building.zones.items()
        }, None
    missing = [z for z in tracked if z not in gains]
    if missing:
        raise ThermocalInputError(f"PID gains: zones {missing[:5]} have no gains")
    return {z: gains[z] for z in tracked if z in gains}, None


def check_pid_only_options(
    method: str, given: Mapping[str, object], *, method_option: str = "method"
) -> None:
    """Refuse options only the PID loop reads when the method runs no PID loop.

    The exact inverse has no Ziegler-Nichols tuning, no gains and no output to limit: a
    tuning zone, gains or limits given with ``method="inverse"`` would be silently ignored.

    Parameters
    ----------
    method : {"both", "inverse", "pid"}
        The identification method.
    given : mapping of str to object
        The PID-only options as the caller spells them (``{"--tuning-zone": value, "--limits":
        value}`` on the command line, ``{"tuning_zone": ..., "limits": ...}`` in Python);
        None means not given.
    method_option : str
        How the caller spells the method option ("--method", "method").

    Raises
    ------
    thermocal.errors.ThermocalInputError
        ``method`` is "inverse" and an option of ``given`` is not None; the message names the
        options and the two ways out.
    """
    used = [name for name, value in given.items() if value is not None]
    if method != "inverse" or not used:
        return
    one = len(used) == 1
    raise ThermocalInputError(
        f"{', '.join(used)} only appl{'ies' if one else 'y'} to the PID loop, which "
        f"{method_option} inverse does not run (the exact inverse has no tuning, no gains and no "
        f"output to limit): drop {'it' if one else 'them'}, or use {method_option} pid or both"
    )


def gap_duration(value, name: str, *, zero_allowed: bool) -> pd.Timedelta:
    """A zone-data gap option (``max_gap``, ``silence``) as a Timedelta, checked.

    Parameters
    ----------
    value : str or Timedelta
        The duration, e.g. "1h" or "15min" [time].
    name : str
        How the caller spells the option, for the message ("--max-gap", "max_gap").
    zero_allowed : bool
        Whether zero means something: a ``max_gap`` of 0 interpolates no gap (every gap takes
        another zone's data); a ``silence`` of 0 would make every instant after a report a gap.

    Returns
    -------
    pandas.Timedelta

    Raises
    ------
    thermocal.errors.ThermocalInputError
        ``value`` is not a duration, is negative, or is zero where ``zero_allowed`` is False.
    """
    from thermocal.textformat import unitless_duration

    if unitless_duration(value):
        raise ThermocalInputError(
            f"{name} {value!r} has no unit (it would be read as nanoseconds); write it with "
            f"one, e.g. '{value}min' or '{value}h'"
        )
    try:
        delta = pd.Timedelta(value)
    except (ValueError, TypeError):
        delta = pd.NaT
    if pd.isna(delta):
        raise ThermocalInputError(
            f"{name} {value!r} is not a duration; write one such as '1h' or '15min'"
        )
    if delta < pd.Timedelta(0):
        raise ThermocalInputError(
            f"{name} {value!r} must not be negative; write a duration such as '1h'"
            + (" (0 interpolates no gap)" if zero_allowed else "")
        )
    if delta == pd.Timedelta(0) and not zero_allowed:
        raise ThermocalInputError(
            f"{name} {value!r} must be positive; write a duration such as '15min'"
        )
    return delta


#: How many times the other zones' median hourly variation per floor area a zone's identified
#: heat may vary before it is named (a swapped pair of sensors in the 5ZoneAirCooled twin: 20-30
#: times, about 1.1 kW against 20-50 W; exploratory test, 2026-11-30; SPACE1-1 and SPACE3-1
#: swapped in its 7-day twin without loads: 29-40 times with five or six zones sensed, 34-121
#: times against the zones outside the pair with three or four).
UNUSUAL_ZONE_FACTOR = 10.0
#: ... and by at least this much [W], so that quiet buildings do not flag noise.
UNUSUAL_ZONE_FLOOR = 200.0
#: Two zones of a building of three or four that vary that much are named together only if
#: their hourly heats move against each other at least this much (correlation): a swapped pair's
#: extra heats mirror each other (-1.00 in the 5ZoneAirCooled twin: three pairs with its loads,
#: one without), two busy offices next to a still plenum move together.
UNUSUAL_PAIR_CORRELATION = -0.5


def unusual_zones(q_id: pd.DataFrame, building) -> str | None:
    """A note on the zones whose identified heat varies far more, per floor area, than the
    other zones' (a sensor mapped to another zone, swapped with one, in the sun or by a
    heater), or None.

    The measure is the standard deviation of a zone's hourly identified heat per floor area.
    A zone is named when it is more than ``UNUSUAL_ZONE_FACTOR`` times the median of the OTHER
    zones' (leave-one-out) and above ``UNUSUAL_ZONE_FLOOR`` [W], provided the zones so named
    are fewer than half of them (otherwise they are the building, not its outliers).

    In a building of three or four zones a swapped pair is not fewer than half: against the
    median of all zones, which the pair itself raised, it was never named. Two zones are then
    named together when each is more than the factor times the median of the zones outside
    the pair, above the floor, and their hourly heats move against each other (correlation
    below ``UNUSUAL_PAIR_CORRELATION``), as a swapped pair's do: the same split with the two
    moving together is two busy zones next to still ones (offices and a plenum), not named.

    Parameters
    ----------
    q_id : DataFrame [W]
        Identified heat per zone (floating zones are all zero).
    building : Building
        For the zones' floor areas [m2].

    Returns
    -------
    str or None
    """
    hourly = q_id.resample("1h").mean()
    spread = hourly.std()
    spread = spread[spread > 0]
    if len(spread) < 3:
        return None
    area = pd.Series(
        {z: max(float(building.zones[z].floor_area), 1.0) for z in spread.index if z in
         building.zones}  # fmt: skip
    )
    per_area = (spread[area.index] / area).dropna()
    if len(per_area) < 3:
        return None
    loud = spread[per_area.index] > UNUSUAL_ZONE_FLOOR
    # each zone against the median of the others
    ordered = np.sort(per_area.to_numpy(dtype=float))
    reference = pd.Series(
        [float(np.median(np.delete(ordered, np.searchsorted(ordered, v)))) for v in per_area],
        index=per_area.index,
    )
    ratio = per_area / reference.where(reference > 0)
    odd = list(per_area.index[(ratio > UNUSUAL_ZONE_FACTOR) & loud])
    if 2 * len(odd) >= len(per_area):
        odd = []
    # a pair that is half of the building or more: against the zones outside it
    pairs = []
    if len(per_area) <= 4:
        zones = list(per_area.index)
        for i, a in enumerate(zones):
            for b in zones[i + 1 :]:
                outside = float(per_area.drop([a, b]).median())
                if not (outside > 0 and loud[a] and loud[b]):
                    continue
                if min(per_area[a], per_area[b]) <= UNUSUAL_ZONE_FACTOR * outside:
                    continue
                r = float(hourly[a].corr(hourly[b]))
                if r < UNUSUAL_PAIR_CORRELATION:
                    pairs.append((a, b, r))
                    for z in (a, b):
                        reference[z], ratio[z] = outside, per_area[z] / outside
                        if z not in odd:
                            odd.append(z)
    if not odd:
        return None
    listed = ", ".join(f"'{z}' ({spread[z]:,.0f} W, {ratio[z]:.0f} times)" for z in odd[:5])
    low, high = f"{reference[odd].min():.2g}", f"{reference[odd].max():.2g}"
    others = low if low == high else f"{low}-{high}"
    moving = "".join(
        f"; '{a}' and '{b}' move against each other hour by hour (correlation {r:.2f})"
        for a, b, r in pairs
    )
    return (
        f"The identified heat of zone(s) {listed} varies far more per floor area, hour by hour, "
        f"than the other zones' median ({others} W/m2 standard deviation){moving}: a sensor "
        "mapped to another zone (two swapped?), a sensor in the sun or by a heater, or a model "
        "far from that zone; check the mapping and the sensor's place before trusting its heat"
    )


def _refuse_non_finite_heat(heat: pd.DataFrame, reference: pd.DataFrame, method: str) -> None:
    """Refuse an identified heat that is not finite (the tracking ran away): a total that skips
    the missing values, and a metric that drops them, would look better than a clean log's."""
    values = heat.to_numpy(dtype=float)
    bad = ~np.isfinite(values)
    if not bad.any():
        return
    row, column = np.argwhere(bad)[0]
    zone = heat.columns[column]
    near = reference[zone].iloc[max(0, row - 12) : row + 1] if zone in reference else None
    seen = (
        f"; its reference there ranges {near.min():.1f} to {near.max():.1f} C"
        if near is not None and np.isfinite(near.to_numpy(float)).any()
        else ""
    )
    raise ThermocalInputError(
        f"the {method} identification of zone {zone!r} is not finite from {heat.index[row]} "
        f"({int(bad.any(axis=0).sum())} zone(s), {int(bad.any(axis=1).sum())} step(s)): the "
        f"tracking of its reference ran away{seen}; check that zone's sensors around that time "
        "(a jump or an impossible reading) and the building's description"
    )


def identify(
    building,
    weather: pd.DataFrame,
    metadata: Mapping | None,
    sensor_log: pd.DataFrame,
    mapping: SensorMapping | Mapping,
    *,
    start=None,
    end=None,
    step: str = "5min",
    method: str = "both",
    feedback="air",
    radiant_fraction=None,
    gains: PIDGains | Mapping | None = None,
    tuning_zone: str | None = None,
    limits: tuple[float, float] | None = None,
    schedule: OccupancySchedule | None = None,
    settle: str | None = "1D",
    max_gap: str = "1h",
    silence: str = "15min",
    options=None,
    warmup_days: int = 7,
    known_heat: pd.DataFrame | None = None,
    metric_source: str | None = None,
    progress: bool = False,
    log_name: str = "sensor log",
    clock_check: bool = True,
    sensor_accuracy: float = DEFAULT_SENSOR_ACCURACY_K,
    log_tz: str | None = None,
) -> IdentificationResult:
    """Identify the heat every zone needs to track the measured temperatures.

    Parameters
    ----------
    building : thermocal.multizone.Building
        The detailed model (no HVAC and no internal loads in it: set points are ignored).
    weather : DataFrame
        From :func:`thermocal.io.weather.read_weather`.
    metadata : dict
        Weather metadata (site).
    sensor_log : DataFrame
        From :func:`thermocal.io.measurements.read_measurements` [C].
    mapping : SensorMapping or dict
        Sensors -> zones (:mod:`thermocal.identification.sensors`).
    start, end : timestamp-like, optional
        Period ``[start, end)`` (default: the weather's).
    step : str
        Model and controller step, e.g. "5min".
    method : {"both", "inverse", "pid"}
        "inverse": the exact heat that puts the model on the references at every step; "pid":
        the paper's per-zone PID loop; "both": both, compared.
    feedback : {"air", "operative"}, float or dict, optional
        The sensor model, the model temperature that tracks the sensors: "air", "operative"
        or the air weight [-] of ``w T_air + (1 - w) T_surf``; a dict zone -> one of these for
        some zones. Default: the mapping's (``identified_heat.sensor``, per zone ``sensor``),
        else "air".
    radiant_fraction : float, dict, DataFrame or "declared", optional [-]
        Where the identified heat goes: ``1 - f`` into the zone air, ``f`` over its surfaces as
        EnergyPlus distributes radiant internal gains; one value, a dict zone -> value, a
        DataFrame (the steps x the tracked zones) for a form that follows the composition of
        the gains step by step, or "declared": that form from the building file's own People,
        Lights and equipment objects, which are then not simulated (the identified heat stands
        for them; :mod:`thermocal.identification.form`). Without "declared" a file's load
        objects are simulated as known heat and the identified heat is the heat beyond them.
        Default: the mapping's (``identified_heat.radiant_fraction``, per zone
        ``radiant_fraction``), else the radiant share of the heat the zone's HVAC equipment
        declared in the IDF delivers (:func:`equipment_radiant_fractions`: 0 for an air
        system), else :data:`DEFAULT_RADIANT_FRACTION`. The method's paper puts
        all of it into the air (``radiant_fraction=0, feedback="air"``).
    gains : PIDGains or dict of zone -> PIDGains, optional
        Discrete PID gains [W/K]: one set (scaled by zone volume relative to ``tuning_zone``,
        default the first zone) or one per zone; None = Ziegler-Nichols on ``tuning_zone``
        (default the median-volume zone), scaled by volume.
    tuning_zone : str, optional
        Zone of the Ziegler-Nichols tuning (a zone of ``building``; PID methods only).
    limits : (float, float), optional [W]
        Lower and upper limit of every zone's PID output (conditional integration while
        limited); None = unlimited, as in the paper. ``gains``, ``tuning_zone`` and ``limits``
        are refused with ``method="inverse"``, which runs no PID loop.
    schedule : OccupancySchedule, optional
        Unoccupied steps for the metric (default: the paper's).
    settle : str or None
        First part of the period left out of the metric (default one day).
    max_gap, silence : str
        See :func:`thermocal.identification.sensors.zone_references`; ``max_gap`` at least 0,
        ``silence`` positive (:func:`gap_duration`).
    options : NetworkOptions, optional
    warmup_days : int
        Repetitions of the first day tracked before the period (exact inverse, hourly).
    known_heat : DataFrame, optional [W]
        Heat known to enter zones (e.g. metered), added to the model so that Q_ID excludes it.
    metric_source : {"inverse", "pid"}, optional
        Which Q_ID feeds the metric; default the inverse when it ran (exact and as fast, see the
        docs), else the PID.
    progress : bool
    log_name : str
        Name of the sensor log for messages.
    clock_check : bool
        Check the sensor log's clock against the model's (:func:`check_identified_log_clock`:
        two to four more exact inverses over the period; a :class:`~thermocal.calibration.
        clockcheck.LogClockWarning` when the log shifted by an hour or more fits much better).
    sensor_accuracy : float [K]
        Standard uncertainty of each sensor's calibration offset, passed through the model's
        steady-state conductances into the identified heat's uncertainty
        (:mod:`thermocal.identification.sensor_accuracy`; a note and ``sensor_uncertainty``).
    log_tz : str, optional
        The time zone the sensor log's stamps were read in (the clock check's wording).

    Returns
    -------
    IdentificationResult

    Warns
    -----
    LogClockWarning
        The model's unoccupied heat is much smoother with the log's time stamps shifted.
    """
    from thermocal.multizone.simulation import Simulation

    if method not in METHODS:
        raise ThermocalInputError(f"method must be one of {METHODS}, got {method!r}")
    check_pid_only_options(method, {"tuning_zone": tuning_zone, "gains": gains, "limits": limits})
    if tuning_zone is not None:
        check_tuning_zone(building, tuning_zone)
    gap_duration(max_gap, "max_gap", zero_allowed=True)
    gap_duration(silence, "silence", zero_allowed=False)
    if not isinstance(mapping, SensorMapping):
        mapping = mapping_from_dict(mapping)
    schedule = schedule or OccupancySchedule()
    timings: dict[str, float] = {}
    notes: list[str] = []
    mapping, spelling = in_building_spelling(mapping, building)
    notes.extend(spelling)
    weather, metadata = _weather_for_log(weather, metadata, sensor_log, start, end)
    weather_year = metadata.get("weather_year")
    if weather_year:
        notes.append(weather_year["statement"])
    declared = declared_form_requested(mapping, radiant_fraction)
    t0 = time.perf_counter()
    simulated, kept = building_to_simulate(building, mapping, declared)
    sim = Simulation(
        simulated,
        weather,
        metadata,
        step=step,
        start=start,
        end=end,
        options=options,
        warmup_days=warmup_days,
        store_surfaces=False,
    )
    if declared:
        radiant_fraction = declared_form(
            building, mapping, sim.times, sim.step_size, DEFAULT_RADIANT_FRACTION
        )
    note = loads_note(building, declared, radiant_fraction if declared else None, kept)
    if note:
        notes.append(note)
    timings["model_setup"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    reference, ref_report = zone_references(
        sensor_log,
        building,
        mapping,
        sim.times,
        sim.step_size,
        max_gap=max_gap,
        silence=silence,
        source=log_name,
    )
    timings["references"] = time.perf_counter() - t0
    notes += ref_report.constant_notes()  # accepted long constant readings, with the results
    notes += ref_report.removed_notes()  # readings removed as impossible or spikes
    notes += ref_report.setpoint_notes()  # zones read beyond the set points the file holds
    all_zones = list(building.zones)
    zones = [z for z in all_zones if z in reference.columns]
    floating = [z for z in all_zones if z not in reference.columns]
    if not zones:
        raise ThermocalInputError(
            f"{mapping.source}: no zone has a sensor or takes another zone's data; map at least "
            "one sensor to a zone"
        )
    form = identified_heat_form(building, mapping, feedback, radiant_fraction)
    note = equipment_form_note(
        building, form.loc[zones], mapping, radiant_fraction, declared=declared
    )
    if note:
        notes.append(note)
    weights = form.loc[zones, "sensor_air_weight"].to_numpy()
    fractions = form.loc[zones, "radiant_fraction"].to_numpy()
    if isinstance(radiant_fraction, pd.DataFrame):
        fractions = per_step_fraction(radiant_fraction, zones, sim.times)
    form.insert(0, "treatment", [_treatment(z, floating, kept) for z in all_zones])
    feedback_name = _sensor_name(weights)
    track_form = dict(zones=zones, feedback=weights, radiant_fraction=fractions)
    # the tracked zones' references in building order, one array the loops read and the
    # frames the metrics and the result show are views of
    reference, ref = frame_over_own_array(reference[zones])
    q_inverse = q_pid = None
    floating_temperature = None
    model_temperature, tracking = {}, {}
    if method in ("inverse", "both"):
        t0 = time.perf_counter()
        result = sim.track(
            ref, method="inverse", heat_input=known_heat, progress=progress, **track_form
        )
        timings["inverse"] = time.perf_counter() - t0
        _refuse_non_finite_heat(result.heat, reference, "exact inverse")
        q_inverse = _with_floating(result.heat, all_zones)
        floating_temperature = result.air_temperature[floating]
        model_temperature["inverse"] = result.tracked_temperature()
        tracking["inverse"] = tracking_metrics(model_temperature["inverse"], reference)
        result = None  # its other month-long frames are not kept (the PID's come next)
    zone_gains, tuning = None, None
    if method in ("pid", "both"):
        grid = sim.weather_on_grid
        t0 = time.perf_counter()
        zone_gains, tuning = pid_gains_for(
            building,
            gains=gains,
            step=step,
            feedback=form["sensor_air_weight"],
            radiant_fraction=form["radiant_fraction"],
            options=options,
            metadata=metadata,
            outdoor_temperature=float(grid["temp_air"].mean()),
            wind_speed=float(grid["wind_speed"].mean()) if "wind_speed" in grid else 0.0,
            tuning_zone=tuning_zone,
            tracked=zones,
        )
        timings["tuning"] = time.perf_counter() - t0
        if tuning is not None and tuning.paper_gain_margin < tuning.gain_margin:
            notes.append(
                f"The Ziegler-Nichols gains of the paper's rule give the tuned zone's loop a gain "
                f"margin of {tuning.paper_gain_margin:.2f} (below 1: it diverges at the Nyquist "
                f"frequency, the ultimate period being two steps); all gains were scaled by "
                f"{tuning.gains.kp / tuning.paper_gains.kp:.3f} to a margin of "
                f"{tuning.gain_margin:.2f}."
            )
        pid_limits = (
            None
            if limits is None
            else (np.full(len(zones), limits[0]), np.full(len(zones), limits[1]))
        )
        t0 = time.perf_counter()
        scale = np.ones(len(zones))
        for attempt in range(RETUNE_ATTEMPTS + 1):
            coefficients = kernel_coefficients(
                [zone_gains[z].scaled(f) for z, f in zip(zones, scale, strict=True)]
            )
            result = sim.track(
                ref,
                method="pid",
                pid=coefficients,
                limits=pid_limits,
                heat_input=known_heat,
                progress=progress,
                **track_form,
            )
            if not result.diverged or attempt == RETUNE_ATTEMPTS:
                break
            # retune: halve the gains of the zones whose loop diverged and run again
            for zone in result.diverged:
                scale[zones.index(zone)] *= 0.5
        timings["pid"] = time.perf_counter() - t0
        retuned = {z: float(f) for z, f in zip(zones, scale, strict=True) if f < 1.0}
        if retuned and not result.diverged:
            notes.append(
                f"The PID loop diverged in {len(retuned)} zone(s); their gains were retuned "
                "(halved until stable): "
                + ", ".join(f"{z} x{f:g}" for z, f in list(retuned.items())[:10])
                + (", ..." if len(retuned) > 10 else "")
                + "."
            )
            for zone, factor in retuned.items():
                zone_gains[zone] = zone_gains[zone].scaled(factor)
        if result.diverged and method == "both":
            bad = result.diverged
            notes.append(
                f"The PID loop diverges in {len(bad)} zone(s) ({', '.join(bad[:5])}"
                f"{', ...' if len(bad) > 5 else ''}) even with its gains divided by "
                f"{2**RETUNE_ATTEMPTS}: the PID result is left out; the identified heat is the "
                "exact inverse's."
            )
        elif result.diverged:
            bad = result.diverged
            raise ThermocalInputError(
                f"the PID loop diverges in {len(bad)} zone(s) ({', '.join(bad[:5])}"
                f"{', ...' if len(bad) > 5 else ''}) even with its gains divided by "
                f"{2**RETUNE_ATTEMPTS}: the gains are too high for the model's step; leave the "
                "gains out to use the stabilised Ziegler-Nichols gains, lower them, or use "
                "method 'inverse' or 'both'"
            )
    if method in ("pid", "both") and not result.diverged:
        _refuse_non_finite_heat(result.heat, reference, "PID")
        q_pid = _with_floating(result.heat, all_zones)
        if floating_temperature is None:
            floating_temperature = result.air_temperature[floating]
        model_temperature["pid"] = result.tracked_temperature()
        tracking["pid"] = tracking_metrics(model_temperature["pid"], reference)
    log_clock = None
    if clock_check:
        t0 = time.perf_counter()
        log_clock = check_identified_log_clock(
            sim, reference, track_form, schedule=schedule, settle=settle,
            known_heat=known_heat, inverse_heat=q_inverse, log_name=log_name, log_tz=log_tz,
        )  # fmt: skip
        timings["clock_check"] = time.perf_counter() - t0
    source = metric_source or ("inverse" if q_inverse is not None else "pid")
    q_id = q_inverse if source == "inverse" else q_pid
    if q_id is None:
        raise ThermocalInputError(f"metric_source {source!r} did not run (method {method!r})")
    sources = ref_report.zone_table()
    zone_sensors = dict(zip(sources["zone"], sources["sensors"], strict=True))
    sensor_uncertainty = _sensor_uncertainty(sim, q_id, zones, sensor_accuracy, zone_sensors)
    notes.append(uncertainty_note(sensor_uncertainty))
    unusual = unusual_zones(q_id, building)
    if unusual:
        import warnings

        warnings.warn(unusual, stacklevel=2)
        notes.append(unusual)
    grid = sim.weather_on_grid
    weather_cols = {"temp_air": grid["temp_air"].to_numpy()}
    weather_cols["ghi"] = (
        grid["ghi"].to_numpy() if "ghi" in grid else (grid["dni"] + grid["dhi"]).to_numpy()
    )
    return IdentificationResult(
        q_id=q_id,
        q_inverse=q_inverse,
        q_pid=q_pid,
        reference=reference,
        model_temperature=model_temperature,
        tracking=tracking,
        sources=sources,
        gains=zone_gains,
        tuning=tuning,
        weather=pd.DataFrame(weather_cols, index=sim.times),
        schedule=schedule,
        settle=settle,
        metric_source=source,
        feedback=feedback_name,
        timings=timings,
        notes=notes,
        interpolated=ref_report.interpolated,
        substituted=ref_report.substituted,
        form=form,
        floating_temperature=floating_temperature,
        import_notes=list(sim.approximations()),
        weather_year=weather_year,
        log_clock=log_clock,
        accepted_constant_readings=ref_report.accepted_constant_readings,
        removed_readings=ref_report.removed_readings(),
        setpoint_excursions=ref_report.setpoint_excursions,
        sensor_uncertainty=sensor_uncertainty,
    )


def _sensor_uncertainty(
    sim, q_id: pd.DataFrame, zones: list[str], accuracy: float, zone_sensors: dict
) -> dict:
    """:func:`~thermocal.identification.sensor_accuracy.sensor_heat_uncertainty` of the
    tracked zones, with the model's conductances and the identified period."""
    net = sim.network
    index = {name: i for i, name in enumerate(net.zone_names)}
    held = net.air_node[[index[z] for z in zones]]
    step_h = sim.dt / 3600.0
    identified = q_id[zones].abs().sum().to_numpy() * step_h / 1000.0
    return sensor_heat_uncertainty(
        held_zone_conductance(net.conductance, held), zones, len(q_id) * step_h, identified,
        accuracy=accuracy, zone_sensors=zone_sensors,
    )  # fmt: skip


#: What a log an hour off does to identified heat, and its remedy (the clock warning's middle;
#: :func:`thermocal.calibration.clockcheck.clock_result`).
IDENTIFY_CONSEQUENCE = (
    "Heat identified with a log an hour off is the heat a wrong timing needs, not the "
    "building's; correct the log's time stamps (or the time zone they are read in, --tz) and "
    "identify again."
)


def check_identified_log_clock(
    sim, reference: pd.DataFrame, track_form: dict, *, schedule, settle, known_heat=None,
    inverse_heat: pd.DataFrame | None = None, log_name: str = "sensor log",
    log_tz: str | None = None,
) -> dict:  # fmt: skip
    """The sensor log's clock against the model's, as ``thermocal calibrate`` checks it.

    The exact inverse is run with the zone references as a log with its time stamps moved by
    an hour either way would give them (:func:`shifted_values`; a better shift followed up
    to 3 h), and the building's identified heat compared over the same quiet hours (the
    identification's unoccupied steps in the period less 3 h at each end, after ``settle``):
    the search, tolerance and messages are :mod:`thermocal.calibration.clockcheck`'s.

    Parameters
    ----------
    sim : Simulation
        The identification's simulation (its period, step and warm-up).
    reference : DataFrame (steps x tracked zones) [C]
        The zone references of the log as written, on ``sim.times``.
    track_form : dict
        The tracked ``zones``, ``feedback`` and ``radiant_fraction`` of the identification.
    schedule : OccupancySchedule
        The identification's unoccupied hours.
    settle : str or None
        Left out at the start of the compared hours (time).
    known_heat : DataFrame, optional [W]
        Known heat (on the model's clock: not shifted).
    inverse_heat : DataFrame, optional [W]
        The exact inverse's heat of the log as written when it ran already (saves one run).
    log_name : str
        The sensor log, named in the warning.
    log_tz : str, optional
        The time zone the log's stamps were read in (``--tz``): a one-hour shift is put down
        to daylight saving only while it is in force there.

    Returns
    -------
    dict
        :func:`~thermocal.calibration.clockcheck.clock_result`'s figures and note (a failed
        check's two halves compared on the same runs: no extra inverse);
        :func:`~thermocal.calibration.clockcheck.clock_skipped`'s (``passed`` None, the reason
        in ``reason`` and ``note``) when the period is too short to shift or the log as written
        gives no quiet heat to compare.

    Warns
    -----
    LogClockWarning
        A shift lowers the unoccupied standard deviation by more than
        :data:`~thermocal.calibration.clockcheck.CLOCK_TOLERANCE`.
    """
    from thermocal.calibration.clockcheck import (
        clock_check_window,
        clock_halves,
        clock_skipped,
        run_clock_check,
        too_short_reason,
    )

    end = sim.times[-1] + sim.step_size
    window = clock_check_window(sim.times[0], end, sim.step_size)
    if window is None:
        return clock_skipped(too_short_reason(sim.times[0], end))
    quiet = clock_check_steps(sim.times, schedule, settle, window)

    values = reference.to_numpy(dtype=float)
    elapsed = ((reference.index - reference.index[0]) / pd.Timedelta(hours=1)).to_numpy(float)
    heat = {}  # shift [h] -> building heat per step [W]: the halves reuse the whole's runs

    def building_heat(hours: float) -> np.ndarray:
        if hours not in heat:
            if hours == 0.0 and inverse_heat is not None:
                heat[hours] = inverse_heat.to_numpy().sum(axis=1)
            else:
                heat[hours] = np.asarray(sim.track_heat(
                    shifted_values(values, elapsed, hours), method="inverse",
                    heat_input=known_heat, **track_form,
                ).heat.sum(axis=1))  # fmt: skip
        return heat[hours]

    def half_std(hours: float, half) -> float:
        inside = quiet & np.asarray((sim.times >= half[0]) & (sim.times < half[1]))
        return quiet_heat_std(building_heat(hours), inside)

    return run_clock_check(
        lambda hours: quiet_heat_std(building_heat(hours), quiet), half_std,
        clock_halves(window, sim.step_size), consequence=IDENTIFY_CONSEQUENCE, path=log_name,
        halves_always=True,  # the heat of each shift is at hand: the halves cost nothing
        tz=log_tz,
    )  # fmt: skip


def shifted_values(values: np.ndarray, elapsed: np.ndarray, hours: float) -> np.ndarray:
    """The zone references a log with every time stamp moved by ``hours`` [h] gives.

    Each column's value at step ``t`` is the references' at ``t - hours``, linearly
    interpolated between steps and held at the first or last value beyond the period's ends
    (the clock check leaves those hours out); one C-ordered array, by row index when the shift
    is a whole number of equal steps (one allocation: the clock check's extra memory).

    Parameters
    ----------
    values : ndarray (steps, zones) [C]
    elapsed : ndarray (steps,) [h]
        Each step's time since the first.
    hours : float
        The shift [h].

    Returns
    -------
    ndarray (steps, zones) [C]
    """
    n = len(elapsed)
    if n > 1:
        step = elapsed[1] - elapsed[0]
        whole = hours / step
        if np.allclose(np.diff(elapsed), step) and abs(whole - round(whole)) < 1e-9:
            rows = np.clip(np.arange(n) - int(round(whole)), 0, n - 1)
            return np.ascontiguousarray(values[rows])
    moved = np.empty_like(values, dtype=float, order="C")
    for j in range(values.shape[1]):
        moved[:, j] = np.interp(elapsed - hours, elapsed, values[:, j])
    return moved


def clock_check_steps(times: pd.DatetimeIndex, schedule, settle, window) -> np.ndarray:
    """The steps the clock check compares: unoccupied, inside ``window`` and after ``settle``
    counted from the window's start.

    Parameters
    ----------
    times : DatetimeIndex
        Step starts.
    schedule : OccupancySchedule
    settle : str, Timedelta or None
        Left out at the start of the window (time).
    window : (Timestamp, Timestamp)
        ``[first, last)`` (:func:`~thermocal.calibration.clockcheck.clock_check_window`).

    Returns
    -------
    ndarray of bool
    """
    first, last = window
    keep = (times >= first) & (times < last)
    if settle is not None:
        keep &= times >= first + pd.Timedelta(settle)
    return np.asarray(keep) & unoccupied_steps(times, schedule, settle=None)


def quiet_heat_std(total: np.ndarray, quiet: np.ndarray) -> float:
    """Population standard deviation [W] of the building heat ``total`` [W] over the steps
    ``quiet``; NaN with fewer than two steps or a non-finite value."""
    values = total[quiet]
    if len(values) < 2 or not np.isfinite(values).all():
        return float("nan")
    return float(np.std(values))


def _weather_for_log(weather, metadata, sensor_log, start, end):
    """The weather on the calendar of the measured period (:func:`~thermocal.io.weather.
    weather_for_period`; the period's open ends from the sensor log's span)."""
    from thermocal.identification.sensors import log_span
    from thermocal.io.weather import weather_for_period

    if (metadata or {}).get("coerced_year") is None and (start is None or end is None):
        return weather, dict(metadata or {})  # an actual year: the simulation checks the period
    if start is None or end is None:
        try:
            first, last = log_span(sensor_log)
        except (TypeError, ValueError):
            return weather, dict(metadata or {})
        start = first if start is None else start
        end = last if end is None else end
    if pd.isna(pd.Timestamp(start)) or pd.isna(pd.Timestamp(end)):
        return weather, dict(metadata or {})
    return weather_for_period(weather, metadata, start, end)


def identified_heat_form(
    building, mapping: SensorMapping | None, feedback=None, radiant_fraction=None
):
    """Radiant fraction [-] and sensor air weight [-] of every zone's identified heat.

    Precedence: the arguments (one value or a dict zone -> value; a per-step DataFrame of
    radiant fractions counts with each zone's mean over the period), then the mapping's
    per-zone and global entries (``mapping`` may be None), then the defaults: the radiant share
    of the heat the zone's equipment declared in the building's IDF delivers
    (:func:`equipment_radiant_fractions`: 0 for an air system), else
    :data:`DEFAULT_RADIANT_FRACTION`; air sensors.

    Returns
    -------
    DataFrame indexed by zone with columns ``radiant_fraction`` and ``sensor_air_weight``.
    """
    from thermocal.identification.sensors import _fraction, sensor_weight

    zones = list(building.zones)
    mapping = mapping if mapping is not None else SensorMapping({})
    if isinstance(radiant_fraction, pd.DataFrame):  # a per-step form: its means per zone
        radiant_fraction = radiant_fraction.mean().to_dict()

    def resolve(argument, per_zone, global_value, default, check, what):
        if isinstance(argument, Mapping):
            unknown = [z for z in argument if z not in building.zones]
            if unknown:
                raise ThermocalInputError(f"{what}: {unknown[0]!r} is not a zone of the building")
        values = {}
        for zone in zones:
            if isinstance(argument, Mapping) and zone in argument:
                value = argument[zone]
            elif argument is not None and not isinstance(argument, Mapping):
                value = argument
            elif zone in per_zone:
                value = per_zone[zone]
            elif global_value is not None:
                value = global_value
            else:
                value = default.get(zone, fallback) if isinstance(default, Mapping) else default
            values[zone] = check(value, what)
        return values

    fallback = DEFAULT_RADIANT_FRACTION
    fractions = resolve(
        radiant_fraction,
        mapping.zone_radiant_fraction,
        mapping.radiant_fraction,
        equipment_radiant_fractions(building),
        _fraction,
        "radiant_fraction",
    )
    weights = resolve(
        feedback, mapping.zone_sensor, mapping.sensor, "air", sensor_weight, "feedback"
    )
    return pd.DataFrame(
        {"radiant_fraction": fractions, "sensor_air_weight": weights}, index=pd.Index(zones)
    )


class EquipmentFormWarning(UserWarning):
    """The identified heat's form taken from (or set against) the IDF's zone equipment, in a
    calibration campaign's identification (``identify`` gives it as a note)."""


def _declared_equipment(building) -> dict:
    """Zone -> :class:`~thermocal.multizone.idf.hvac.ZoneHeatDelivery` of the building's IDF
    (empty for a building not imported from one)."""
    return getattr(getattr(building, "idf_info", None), "zone_heat_delivery", None) or {}


def equipment_radiant_fractions(building) -> dict[str, float]:
    """The radiant share [-] of the heat each zone's declared HVAC equipment delivers.

    From the building's IDF (``idf_info.zone_heat_delivery``,
    :func:`thermocal.multizone.idf.hvac.zone_heat_delivery`): 0 for a zone heated or cooled by
    an air system (an ideal-loads system, air terminals, fan coils, terminal units, convective
    baseboards), a radiant-convective baseboard's or radiant heater's stated fraction. Zones
    without declared equipment, or whose equipment states no split (a radiant floor), are not
    in the result. A building not imported from an IDF has none.

    Returns
    -------
    dict
        Zone name -> radiant fraction [-].
    """
    delivery = _declared_equipment(building)
    return {
        zone: d.radiant_fraction
        for zone, d in delivery.items()
        if zone in building.zones and d.radiant_fraction is not None
    }


def equipment_form_note(
    building, form: pd.DataFrame, mapping, radiant_fraction, *, declared: bool = False
) -> str | None:
    """A note naming the zones whose identified heat takes its form from their equipment, or
    whose form (given or declared) contradicts an air system's convective heat.

    Parameters
    ----------
    building : Building
    form : DataFrame
        :func:`identified_heat_form`'s (per zone ``radiant_fraction``), for the tracked zones.
    mapping : SensorMapping
    radiant_fraction : float, dict, DataFrame or None
        The form as asked for (None: not given as an argument; a DataFrame: per step).
    declared : bool
        The per-step form is the file's own loads' composition (``"declared"``).

    Returns
    -------
    str or None
    """
    delivery = _declared_equipment(building)
    if not any(z in form.index for z in delivery):
        return None
    mapping = mapping if mapping is not None else SensorMapping({})
    per_step = isinstance(radiant_fraction, pd.DataFrame)

    def chosen(zone) -> bool:  # the zone's form given by the user or declared, not defaulted
        if per_step:
            return zone in radiant_fraction.columns
        if isinstance(radiant_fraction, Mapping):
            if zone in radiant_fraction:
                return True
        elif radiant_fraction is not None:
            return True
        return zone in mapping.zone_radiant_fraction or mapping.radiant_fraction is not None

    defaulted = [z for z in form.index if not chosen(z)]
    by_share: dict = {}
    unsplit, without = [], []
    for zone in defaulted:
        d = delivery.get(zone)
        if d is None:
            without.append(zone)
        elif d.radiant_fraction is None:
            unsplit.append(zone)
        else:
            by_share.setdefault(d.radiant_fraction, []).append(zone)
    text = []
    if by_share or unsplit:
        parts = []
        for share, zones in sorted(by_share.items()):
            kinds = sorted({e.class_name for z in zones for e in delivery[z].equipment})
            parts.append(
                f"{share:g} for {_zone_list(zones)} ({', '.join(kinds[:3])}"
                f"{', ...' if len(kinds) > 3 else ''})"
            )
        if unsplit:
            parts.append(
                f"{DEFAULT_RADIANT_FRACTION:g} for {_zone_list(unsplit)}, whose equipment states "
                f"no split ({delivery[unsplit[0]].equipment[0].class_name}: "
                f"{delivery[unsplit[0]].equipment[0].how})"
            )
        rest = (
            f"; {_zone_list(without)} without equipment take {DEFAULT_RADIANT_FRACTION:g} "
            "(internal gains)"
            if without
            else ""
        )
        text.append(
            "The identified heat's radiant fraction comes from the zones' equipment declared "
            f"in the IDF (an air system's heat enters the air): {'; '.join(parts)}{rest}. Give "
            "--radiant-fraction or the mapping's radiant_fraction to override."
        )
    air = [z for z, d in delivery.items() if z in form.index and d.radiant_fraction == 0.0]
    if per_step:
        above = [z for z in air if z in radiant_fraction.columns and radiant_fraction[z].max() > 0]
    else:
        above = [z for z in air if float(form.loc[z, "radiant_fraction"]) > 0.0]
    if above:
        how = (
            "the declared form gives the heat the composition of the file's internal loads"
            if declared
            else "the identified heat is given a radiant fraction above 0"
        )
        named = _zone_list(above)
        verb = "are" if len(above) > 1 else "is"
        text.append(
            f"{named[0].upper()}{named[1:]} {verb} heated or cooled by an air system in the IDF, "
            f"whose heat enters the air, but {how}: on EnergyPlus twins with ideal loads this put "
            "5-25 % of the month's heat and up to 40-110 % of the hour's in error (and heating "
            "identified in a cooling month); leave the form out (or give radiant_fraction 0) "
            "for the equipment's heat alone, the loads being simulated as known heat."
        )
    return " ".join(text) or None


def _zone_list(zones: list, shown: int = 4) -> str:
    names = ", ".join(f"'{z}'" for z in zones[:shown])
    more = f" and {len(zones) - shown} more" if len(zones) > shown else ""
    return f"zone{'s' if len(zones) > 1 else ''} {names}{more}"


def per_step_fraction(per_step: pd.DataFrame, zones: list, times: pd.DatetimeIndex):
    """A per-step radiant fraction [-] on the simulation's steps and tracked zones."""
    missing = [z for z in zones if z not in per_step.columns]
    if missing:
        raise ThermocalInputError(
            f"radiant_fraction: the per-step form has no column for zone {missing[0]!r}; give "
            "one column per tracked zone"
        )
    aligned = per_step[zones].reindex(times)
    if aligned.isna().any().any():
        first = aligned.index[aligned.isna().any(axis=1)][0]
        raise ThermocalInputError(
            f"radiant_fraction: the per-step form has no value at {first} (the identification "
            f"runs {times[0]} .. {times[-1]}); give a value at every step"
        )
    return aligned.to_numpy(dtype=float)


def _sensor_name(weights: np.ndarray) -> str:
    unique = np.unique(weights)
    if len(unique) > 1:
        return "per zone"
    return {1.0: "air", 0.5: "operative"}.get(float(unique[0]), f"air weight {unique[0]:g}")


def _treatment(zone: str, floating: list[str], kept: list[str]) -> str:
    """The zone table's treatment: tracked, floating, or floating with the file's loads."""
    if zone not in floating:
        return "tracked"
    return "floating, the file's loads simulated" if zone in kept else "floating"


def _with_floating(heat: pd.DataFrame, zones: list[str]) -> pd.DataFrame:
    """Q_ID of every zone in building order, 0 for the floating ones [W]."""
    return heat.reindex(columns=zones, fill_value=0.0)
