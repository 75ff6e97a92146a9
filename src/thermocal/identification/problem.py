"""The identification as a function of envelope parameters, for calibration campaigns.

:class:`IdentificationProblem` holds what does not change between the samples of a campaign
(the model, the weather, the zone references built once from the sensors, the method and the
schedule) and evaluates the unoccupied-variance metric for a set of envelope parameters. It is
picklable; the simulation is built lazily, once per worker process, and every sample only
changes parameters (:meth:`thermocal.multizone.Simulation.set_parameters`).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.identification.metrics import unoccupied_steps
from thermocal.identification.occupancy import OccupancySchedule
from thermocal.identification.pid import PIDGains, kernel_coefficients

#: names of the outputs of :meth:`IdentificationProblem.evaluate`
METRIC = "unoccupied_variance"



def element_nominal_values(building) -> dict[str, float]:
    """The names a problem accepts beside :meth:`Building.parameters`, with nominal values.

    The construction-level resistance and heat capacity of
    :func:`thermocal.multizone.elements.element_parameters` [m2 K/W], [J/(m2 K)] and the
    building-wide infiltration factor ``infiltration/building/factor`` (nominal 1) [-].

    Parameters
    ----------
    building : thermocal.multizone.Building

    Returns
    -------
    dict of str to float
    """
    from thermocal.multizone.elements import element_parameters
    from thermocal.multizone.parameters import INFILTRATION_FACTOR

    return {**element_parameters(building), INFILTRATION_FACTOR: 1.0}

@dataclass
class IdentificationProblem:
    """Envelope parameters -> identified heat -> unoccupied-variance metric.

    Parameters
    ----------
    building : thermocal.multizone.Building
        The nominal model.
    weather : DataFrame
    metadata : dict
    reference : DataFrame (steps x zones) [C]
        Zone references on the simulation grid (:func:`~thermocal.identification.sensors.
        zone_references`): one column per tracked zone; zones without a column float
        (simulated, ``Q_ID = 0``).
    step : str
    start, end : timestamp-like
    method : {"inverse", "pid"}
    feedback : {"air", "operative"}, float or dict
        Sensor model (:meth:`~thermocal.multizone.Simulation.track`), one or per zone.
    radiant_fraction : float, dict or DataFrame [-]
        Share of the identified heat on the zone's surfaces, one or per zone (default
        :data:`~thermocal.identification.workflow.DEFAULT_RADIANT_FRACTION`), or per step and
        zone (a DataFrame on the simulation's steps: the file's declared form,
        :mod:`thermocal.identification.form`).
    gains : dict of zone -> PIDGains, optional
        Required for the PID.
    schedule : OccupancySchedule
    settle : str or None
    warmup_days : int
    options : NetworkOptions, optional
    zone_outputs : bool
        Also return each zone's unoccupied variance (``zone_variance/<zone>`` [W^2]).
    series_outputs : bool
        Also return the hourly means of the building-wide Q_ID over the unoccupied steps
        (``series/<hour>`` [W], hours numbered in time order), for the series meta-model of
        :mod:`thermocal.calibration.surrogate`.
    """

    building: object
    weather: pd.DataFrame
    metadata: dict
    reference: pd.DataFrame
    step: str = "5min"
    start: object = None
    end: object = None
    method: str = "inverse"
    feedback: object = "air"
    radiant_fraction: object = None
    gains: dict | None = None
    schedule: OccupancySchedule = field(default_factory=OccupancySchedule)
    settle: str | None = "1D"
    warmup_days: int = 7
    options: object = None
    zone_outputs: bool = False
    series_outputs: bool = False
    _sim: object = field(default=None, repr=False, compare=False)
    _touched: set = field(default_factory=set, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.method not in ("inverse", "pid"):
            raise ThermocalInputError(f"method must be 'inverse' or 'pid', got {self.method!r}")
        if self.method == "pid" and not self.gains:
            raise ThermocalInputError("the PID method needs gains for every zone")
        self.nominal = dict(self.building.parameters())
        # construction-level names (resistance, heat capacity) and the building-wide
        # infiltration factor are accepted beside the material-level ones; they are not part
        # of the fingerprint (the same building)
        self.element_nominal = element_nominal_values(self.building)

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_sim"] = None
        state["_touched"] = set()
        state["_reference"] = None
        state["_mask"] = None
        state.pop("_form", None)
        state.pop("_zones", None)
        return state

    # ------------------------------------------------------------------------------------------
    def simulation(self):
        """The simulation of this process (built on first use)."""
        if self._sim is None:
            from thermocal.multizone.simulation import Simulation

            self._sim = Simulation(
                self.building,
                self.weather,
                self.metadata,
                step=self.step,
                start=self.start,
                end=self.end,
                options=self.options,
                warmup_days=self.warmup_days,
                store_surfaces=False,
            )
        if getattr(self, "_zones", None) is None:
            from thermocal.identification.workflow import (
                identified_heat_form,
                per_step_fraction,
            )

            zones = [z for z in self.building.zones if z in self.reference.columns]
            unknown = [z for z in self.reference.columns if z not in self.building.zones]
            if unknown or not zones or len(self.reference) != len(self._sim.times):
                raise ThermocalInputError(
                    "IdentificationProblem: the reference must have one column per tracked zone "
                    f"and one row per step ({len(self._sim.times)}); not zones: {unknown[:5]}"
                )
            self._zones = zones
            if not _holds_reference(getattr(self, "_reference", None), self.reference, zones):
                self._reference = np.ascontiguousarray(self.reference[zones].to_numpy(dtype=float))
            form = identified_heat_form(
                self.building, None, self.feedback, self.radiant_fraction
            ).loc[zones]
            self._form = {
                "feedback": form["sensor_air_weight"].to_numpy(),
                "radiant_fraction": per_step_fraction(self.radiant_fraction, zones, self._sim.times)
                if _is_per_step(self.radiant_fraction)
                else form["radiant_fraction"].to_numpy(),
            }
            if self.method == "pid":
                self._pid = kernel_coefficients([self.gains[z] for z in zones])
        return self._sim

    def run(self, parameters: Mapping[str, float] | None = None):
        """Track the references with the given parameters (others nominal).

        Returns
        -------
        thermocal.multizone.simulation.TrackingResult
        """
        sim = self._with_parameters(parameters)
        result = sim.track(self._reference, zones=self._zones, **self._track_options())
        _refuse_diverged(result.diverged)
        return result

    def identified_heat(self, parameters: Mapping[str, float] | None = None) -> np.ndarray:
        """The identified heat alone for the given parameters (others nominal): what a
        campaign sample needs, without the temperature frames of :meth:`run`.

        Returns
        -------
        ndarray (n_steps, n_tracked) [W]
            Bit-identical to ``run(parameters).heat.to_numpy()``; columns in the order of the
            tracked zones (``building.zones`` order).
        """
        sim = self._with_parameters(parameters)
        result = sim.track_heat(self._reference, zones=self._zones, **self._track_options())
        _refuse_diverged(result.diverged)
        return result.heat

    def identified_heat_frame(self, parameters: Mapping[str, float] | None = None) -> pd.DataFrame:
        """:meth:`identified_heat` labelled as ``run(parameters).heat`` (steps x tracked
        zones) [W], without the temperature frames of :meth:`run`."""
        heat = self.identified_heat(parameters)
        return pd.DataFrame(heat, index=self._sim.times, columns=list(self._zones))

    def _with_parameters(self, parameters: Mapping[str, float] | None):
        """The simulation with ``parameters`` set and every other parameter nominal."""
        sim = self.simulation()
        parameters = dict(parameters or {})
        nominal = {**self.nominal, **self.element_nominal}
        unknown = [name for name in parameters if name not in nominal]
        if unknown:
            import difflib

            close = difflib.get_close_matches(unknown[0], list(nominal), n=3)
            hint = f" (did you mean {', '.join(map(repr, close))}?)" if close else ""
            raise ThermocalInputError(f"unknown envelope parameter {unknown[0]!r}{hint}")
        change = {name: nominal[name] for name in self._touched - set(parameters)}
        change.update(parameters)
        if change:
            sim.set_parameters(change)
        self._touched = set(parameters)
        return sim

    def _track_options(self) -> dict:
        """Keyword arguments of the tracking call: method, sensor model, form, PID."""
        kwargs = {"pid": self._pid} if self.method == "pid" else {}
        return {"method": self.method, **self._form, **kwargs}

    def evaluate(self, parameters: Mapping[str, float]) -> dict[str, float]:
        """The metric for one parameter set.

        Returns
        -------
        dict
            ``unoccupied_variance`` [W^2], ``unoccupied_std`` [W], ``unoccupied_mean`` [W] of
            the building-wide Q_ID, and ``zone_variance/<zone>`` [W^2] when ``zone_outputs``.
        """
        heat = self.identified_heat(parameters)
        times = self._sim.times
        key = (repr(self.schedule.as_dict()), self.settle)
        if getattr(self, "_mask", None) is None or self._mask[0] != key:
            self._mask = (key, unoccupied_steps(times, self.schedule, settle=self.settle))
        return self._metric_values(heat, times, self._zones, self._mask[1])

    def metrics(self, heat: pd.DataFrame) -> dict[str, float]:
        """The outputs of :meth:`evaluate` from identified heat per zone [W]."""
        mask = unoccupied_steps(heat.index, self.schedule, settle=self.settle)
        return self._metric_values(heat.to_numpy(), heat.index, list(heat.columns), mask)

    def _metric_values(
        self, heat: np.ndarray, times: pd.DatetimeIndex, zones: Sequence[str], mask: np.ndarray
    ) -> dict[str, float]:
        """The outputs of :meth:`evaluate`.

        Parameters
        ----------
        heat : ndarray (n_steps, n_zones) [W]
            Identified heat per step and zone.
        times : DatetimeIndex
            The steps' start labels.
        zones : sequence of str
            The columns' zones.
        mask : ndarray of bool (n_steps,)
            The unoccupied steps (:func:`~thermocal.identification.metrics.unoccupied_steps`).
        """
        values = heat[mask]
        total = values.sum(axis=1)
        out = {
            METRIC: float(np.var(total)),
            "unoccupied_std": float(np.std(total)),
            "unoccupied_mean": float(np.mean(total)),
        }
        if self.zone_outputs:
            for zone, variance in zip(zones, np.var(values, axis=0), strict=True):
                out[f"zone_variance/{zone}"] = float(variance)
        if self.series_outputs:
            hours = pd.Series(total, index=times[mask]).groupby(times[mask].floor("1h")).mean()
            for i, value in enumerate(hours.to_numpy()):
                out[f"series/{i:05d}"] = float(value)
        return out

    def fingerprint(self) -> str:
        """A digest of everything that determines the outputs besides the parameters."""
        import hashlib

        digest = hashlib.sha256()
        digest.update(np.ascontiguousarray(self.reference.to_numpy(dtype=float)).tobytes())
        digest.update(repr(sorted(self.nominal.items())).encode())
        digest.update(
            repr(
                (
                    self.step,
                    str(self.start),
                    str(self.end),
                    self.method,
                    self.feedback,
                    _form_key(self.radiant_fraction),
                    self.settle,
                    self.warmup_days,
                    self.schedule.as_dict(),
                    None
                    if self.gains is None
                    else sorted((z, g.as_dict()) for z, g in self.gains.items()),
                    self.zone_outputs,
                    self.series_outputs,
                )
            ).encode()
        )
        digest.update(
            np.ascontiguousarray(
                self.weather.select_dtypes("number").to_numpy(dtype=float)
            ).tobytes()
        )
        return digest.hexdigest()[:16]


def problem_from_measurements(
    building,
    weather: pd.DataFrame,
    metadata: Mapping | None,
    sensor_log: pd.DataFrame,
    mapping,
    *,
    start=None,
    end=None,
    step: str = "5min",
    method: str = "inverse",
    feedback=None,
    radiant_fraction=None,
    gains: PIDGains | Mapping | None = None,
    tuning_zone: str | None = None,
    schedule: OccupancySchedule | None = None,
    settle: str | None = "1D",
    max_gap: str = "1h",
    silence: str = "15min",
    warmup_days: int = 7,
    options=None,
    zone_outputs: bool = False,
    log_name: str = "sensor log",
) -> tuple[IdentificationProblem, object]:
    """Build the problem from a sensor log and a mapping (references built once).

    A typical-year weather file follows the year of the measurements
    (:func:`thermocal.io.weather.weather_for_period`; ``problem.metadata["weather_year"]``).
    ``tuning_zone`` and ``gains`` (the PID loop's) are refused with ``method="inverse"``, and
    ``max_gap`` / ``silence`` must be durations of at least 0 / above 0
    (:func:`thermocal.identification.workflow.check_pid_only_options`, ``gap_duration``).

    Returns
    -------
    problem : IdentificationProblem
    report : thermocal.identification.sensors.ReferenceReport
    """
    from thermocal.identification.form import (
        building_to_simulate,
        declared_form,
        declared_form_requested,
    )
    from thermocal.identification.sensors import (
        ReferenceWarning,
        SensorMapping,
        frame_over_own_array,
        in_building_spelling,
        mapping_from_dict,
        zone_references,
    )
    from thermocal.identification.workflow import (
        DEFAULT_RADIANT_FRACTION,
        EquipmentFormWarning,
        _weather_for_log,
        check_pid_only_options,
        equipment_form_note,
        gap_duration,
        identified_heat_form,
        pid_gains_for,
    )
    from thermocal.multizone.simulation import Simulation

    check_pid_only_options(method, {"tuning_zone": tuning_zone, "gains": gains})
    gap_duration(max_gap, "max_gap", zero_allowed=True)
    gap_duration(silence, "silence", zero_allowed=False)
    if not isinstance(mapping, SensorMapping):
        mapping = mapping_from_dict(mapping)
    mapping, spelling = in_building_spelling(mapping, building)

    for note in spelling:
        warnings.warn(note, ReferenceWarning, stacklevel=2)
    # a typical-year file on the year of the measurements (as identify)
    weather, metadata = _weather_for_log(weather, metadata, sensor_log, start, end)
    declared = declared_form_requested(mapping, radiant_fraction)
    simulated, _ = building_to_simulate(building, mapping, declared)
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
    reference, report = zone_references(
        sensor_log,
        building,
        mapping,
        sim.times,
        sim.step_size,
        max_gap=max_gap,
        silence=silence,
        source=log_name,
    )
    if declared:
        radiant_fraction = declared_form(
            building, mapping, sim.times, sim.step_size, DEFAULT_RADIANT_FRACTION
        )
    form = identified_heat_form(building, mapping, feedback, radiant_fraction)
    note = equipment_form_note(
        building, form.loc[[z for z in form.index if z in reference.columns]], mapping,
        radiant_fraction, declared=declared,
    )  # fmt: skip
    if note:
        warnings.warn(note, EquipmentFormWarning, stacklevel=2)
    feedback = form["sensor_air_weight"].to_dict()
    if not _is_per_step(radiant_fraction):
        radiant_fraction = form["radiant_fraction"].to_dict()
    zone_gains = None
    if method == "pid":
        grid = sim.weather_on_grid
        zone_gains, _ = pid_gains_for(
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
            tracked=list(reference.columns),
        )
    reference, values = frame_over_own_array(reference)
    problem = IdentificationProblem(
        building=simulated,
        weather=weather,
        metadata=dict(metadata or {}),
        reference=reference,
        step=step,
        start=start,
        end=end,
        method=method,
        feedback=feedback,
        radiant_fraction=radiant_fraction,
        gains=zone_gains,
        schedule=schedule or OccupancySchedule(),
        settle=settle,
        warmup_days=warmup_days,
        options=options,
        zone_outputs=zone_outputs,
    )
    problem._sim = sim
    problem._reference = values
    problem._touched = set()
    return problem, report


def _holds_reference(values, reference: pd.DataFrame, zones: list) -> bool:
    """Whether ``values`` is the array ``reference`` is a view of, its columns being ``zones``
    in order (then the tracking reads it without a copy)."""
    return (
        isinstance(values, np.ndarray)
        and list(reference.columns) == list(zones)
        and values.shape == reference.shape
        and np.shares_memory(values, reference.to_numpy(dtype=float, copy=False))
    )


def split_outputs(outputs: Mapping[str, float], zones: Sequence[str]) -> pd.Series:
    """Per-zone variances of an :meth:`IdentificationProblem.evaluate` output [W^2]."""
    return pd.Series({z: outputs.get(f"zone_variance/{z}", np.nan) for z in zones})


def _refuse_diverged(diverged: Sequence[str]) -> None:
    """Refuse a run whose PID loop diverged in the zones ``diverged``."""
    if diverged:
        raise ThermocalInputError(
            f"the PID loop diverges with these parameters in zones {list(diverged)[:5]}"
        )


def _is_per_step(radiant_fraction) -> bool:
    return isinstance(radiant_fraction, pd.DataFrame)


def _form_key(radiant_fraction):
    """A value that identifies the form in the fingerprint (a per-step form by its values)."""
    if not _is_per_step(radiant_fraction):
        return radiant_fraction
    import hashlib

    digest = hashlib.sha256(np.ascontiguousarray(radiant_fraction.to_numpy(float)).tobytes())
    digest.update(repr(list(radiant_fraction.columns)).encode())
    return f"per step {digest.hexdigest()[:16]}"
