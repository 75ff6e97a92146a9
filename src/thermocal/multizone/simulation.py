"""Time simulation of a multi-zone building and its steady-state heat loss coefficient.

Time convention: the run is a sequence of steps ``[t_k, t_k + dt)`` labelled by their start ``t_k``
(as the weather frames of :mod:`thermocal.io.weather`).  Within a step the forcing is the interval
mean (irradiance means; temperatures the mean of the interval's end values; with
``weather_interpolation="energyplus"`` the mean of the EnergyPlus-interpolated weather at the
step's start and end); backward Euler gives
the node temperatures at ``t_k + dt``, which are reported under the label ``t_k``.  Heating,
cooling and given heat are constant powers over the step.

See :mod:`thermocal.multizone.network` for the network and :mod:`thermocal.multizone._kernel` for
the compiled loop.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np
import pandas as pd
from scipy.sparse.linalg import splu

from thermocal.errors import ThermocalInputError
from thermocal.multizone._forcing_setup import ForcingSetup
from thermocal.multizone._network_setup import NetworkSetup
from thermocal.multizone._outputs import Outputs
from thermocal.multizone._simtools import (  # noqa: F401 - re-exported
    _CHUNK,
    _NO_IMPLICIT,
    _NO_TRACKED_AIR,
    _NO_VENT,
    _Context,
    _factorise,
    _hourly_first_day,
    _no_tracking,
    _progress,
    _tracking_form,
)
from thermocal.multizone._stepping import Stepping
from thermocal.multizone._tracking import Tracking
from thermocal.multizone._tracking_heat import TrackedHeat
from thermocal.multizone.forcing import (  # noqa: F401 - re-exported
    _energyplus_weather,
    _ground_reflectance,
    _irradiance,
    _period_sun_vectors,
    _sun_position,
    _weather_grid,
    _window_inputs,
)
from thermocal.multizone.model import Building
from thermocal.multizone.network import (
    IN_TEMP_GROUND,
    NetworkOptions,
    assemble,
)
from thermocal.multizone.results import (  # noqa: F401 - re-exported
    OUTPUT_QUANTITIES,
    SimulationResult,
    TrackingResult,
    _hourly_mean,
    _write_csv,
    _write_parquet,
    output_quantities,
)
from thermocal.textformat import unitless_duration

#: EnergyPlus' initial zone air and surface temperature before its warm-up [C]
ENERGYPLUS_INITIAL_TEMPERATURE = 23.0


class Simulation(NetworkSetup, ForcingSetup, Stepping, Tracking, TrackedHeat, Outputs):
    """Simulate a :class:`~thermocal.multizone.model.Building` over a weather period.

    Parameters
    ----------
    building : Building
    weather : pandas.DataFrame
        Standard weather frame (:func:`thermocal.io.weather.read_weather`): ``temp_air`` [C],
        ``dni``, ``dhi`` [W/m2] required; ``ghi``, ``ghi_infrared``, ``temp_dew``, ``wind_speed``,
        ``wind_direction``, ``pressure``, ``albedo`` used when present.
    metadata : dict
        Weather metadata (``latitude``, ``longitude``, ``altitude``; optional
        ``ground_temperatures``).
        Missing site data fall back to ``building.location``.
    step : str or Timedelta
        Time step, e.g. ``"5min"`` or ``"1h"`` (must divide the simulated period).
    start, end : timestamp-like, optional
        Period ``[start, end)``; default: the whole weather frame.
    options : NetworkOptions, optional
    warmup_days : int
        Repetitions of the period's first day before the run to reach a periodic initial state
        (as EnergyPlus' warm-up; for a building imported from an IDF file the least number, the
        file's own convergence rule deciding the rest, see :meth:`_warm_up`); 0 = start from
        ``initial_temperature``.
    initial_temperature : float, optional [C]
        Uniform temperature the warm-up (or the run) starts from; default 23 C for a building
        imported from an IDF file (EnergyPlus' start), else 20 C.
    store_surfaces : bool
        Keep interior surface temperatures in the result.
    sky_model : {"perez", "isotropic"}
        Sky diffuse model of the transposition.
    schedules : {"file", "constant"}
        For buildings imported from an IDF file (``building.idf_info``): ``"file"`` applies the
        file's schedules step by step (set points, internal gains split into convective, radiant
        and latent parts, infiltration with its schedule and its wind and temperature terms at
        the zone's height); ``"constant"`` simulates the constant approximation stored on the
        zones (annual-mean gains, most frequent set point, infiltration at 4.47 m/s).
        Ignored for other buildings.
    shading : bool
        For buildings imported from an IDF file: shadows of the file's shading surfaces
        (``Shading:Zone/Building/Site:Detailed``, overhangs, fins) on windows and outdoor
        surfaces, beam and the sky's circumsolar part by the sunlit fraction of each step, the
        sky dome and horizon band by their unshaded views, as EnergyPlus
        (:mod:`thermocal.multizone.shading`); False ignores them.
    rain : bool or None
        Wet exterior faces on rain steps as EnergyPlus (wind-exposed faces: 1000 W/m2K to the
        outdoor wet bulb; rain from the weather's liquid precipitation, >= 0.8 mm/h, and present
        weather). None: an imported IDF follows its RunPeriod 'Use Weather File Rain Indicators',
        other models are dry.
    weather_interpolation : {None, "hold", "energyplus"}
        How hourly weather becomes sub-hourly steps. ``"hold"``: irradiance means held over each
        hour, each step's air temperature the mean of its end values (linear in time between the
        hourly instants), the sun representative of the step's interval. ``"energyplus"``: the
        weather curve of EnergyPlus: irradiance (``ghi``, ``dni``, ``dhi``) interpolated
        linearly between the hourly values placed at the half hours, the horizontal infrared,
        temperatures, humidity, pressure and wind linearly between the hourly instants, the sun
        position at each instant (hourly weather and a step dividing the hour required); each
        step is forced by the mean of the outdoor and sky temperatures and the solar inputs at
        its start and end (the interval mean of that piecewise-linear curve; EnergyPlus itself
        takes the end values, which delays its answer by about half a step: see
        docs/energyplus.md). ``None`` (default): ``"energyplus"`` for buildings imported from
        an IDF file with hourly weather, else ``"hold"``.

    Notes
    -----
    Stepping API for closed loops: :meth:`reset`, then :meth:`step` once per step with the heat
    delivered to each zone's air; :meth:`set_parameters` changes envelope parameters (network values
    re-assembled and refactorised, the state is kept).
    """

    def __init__(
        self,
        building: Building,
        weather: pd.DataFrame,
        metadata: Mapping | None = None,
        *,
        step: str | pd.Timedelta = "5min",
        start=None,
        end=None,
        options: NetworkOptions | None = None,
        warmup_days: int = 7,
        initial_temperature: float | None = None,
        store_surfaces: bool = True,
        sky_model: str = "perez",
        schedules: str = "file",
        shading: bool = True,
        weather_interpolation: str | None = None,
        rain: bool | None = None,
    ) -> None:
        if not isinstance(building, Building):
            raise ThermocalInputError("Simulation: building must be a thermocal Building")
        self.building = building
        self.metadata = dict(metadata or {})
        info = getattr(building, "idf_info", None)
        self._convection_notes: list[str] = []
        if options is None and info is not None and hasattr(info, "network_options"):
            # the file's SurfaceConvectionAlgorithm:Inside/Outside, and EnergyPlus' interior
            # long-wave exchange (pairwise grey-body factors on its approximate view factors,
            # which exclude co-planar faces: a wall does not see its own windows)
            options, self._convection_notes = info.network_options()
            options = dataclasses.replace(options, interior_longwave_exchange="view_factors")
        self.options = options or NetworkOptions()
        if unitless_duration(step):
            raise ThermocalInputError(
                f"step {step!r} has no unit: write it with one, e.g. '{step}min' or '{step}h'"
            )
        try:
            self.step_size = pd.Timedelta(step)
        except ValueError as exc:
            raise ThermocalInputError(f"step {step!r} is not a duration (e.g. '5min')") from exc
        if self.step_size <= pd.Timedelta(0) or self.step_size > pd.Timedelta("1h"):
            raise ThermocalInputError(f"step must lie in (0, 1h], got {step!r}")
        self.dt = self.step_size.total_seconds()
        self.warmup_days = int(warmup_days)
        if self.warmup_days < 0:
            raise ThermocalInputError(
                f"Simulation: warmup_days (--warmup-days) must be >= 0, got {warmup_days!r}"
            )
        if initial_temperature is None:
            # EnergyPlus starts its warm-up from 23 C (zone air and surfaces)
            initial_temperature = ENERGYPLUS_INITIAL_TEMPERATURE if info is not None else 20.0
        self.initial_temperature = float(initial_temperature)
        self.store_surfaces = bool(store_surfaces)
        self.sky_model = sky_model
        self._weather = weather
        if weather_interpolation is None:
            from thermocal.io.weather import weather_step

            hourly = (
                isinstance(weather, pd.DataFrame)
                and isinstance(weather.index, pd.DatetimeIndex)
                and len(weather) > 1
                and weather_step(weather) == pd.Timedelta("1h")
            )
            imported = getattr(building, "idf_info", None) is not None
            weather_interpolation = "energyplus" if imported and hourly else "hold"
        if weather_interpolation not in ("hold", "energyplus"):
            raise ThermocalInputError(
                "Simulation: weather_interpolation must be 'hold' or 'energyplus', got "
                f"{weather_interpolation!r}"
            )
        self.weather_interpolation = weather_interpolation
        #: EnergyPlus interpolation: the sun at each step's end, as the weather values
        self._sun_at_end = self.step_size if weather_interpolation == "energyplus" else None
        self._grid = _weather_grid(
            weather, self.step_size, start, end, interpolation=weather_interpolation
        )
        self.times = self._grid.index
        if rain is None:
            # an imported model follows its RunPeriod ('Use Weather File Rain Indicators', Yes
            # when blank), as EnergyPlus; thermocal's own models stay dry unless asked
            rain = bool(getattr(info, "use_weather_rain", True)) if info is not None else False
        self.rain = bool(rain)
        self._rain_setup(weather)
        if schedules not in ("file", "constant"):
            raise ThermocalInputError(
                f"Simulation: schedules must be 'file' or 'constant', got {schedules!r}"
            )
        self.schedules = schedules
        calendar = getattr(info, "schedules", None)
        if calendar is not None and "holidays" in self.metadata:  # EPW holidays and DST period
            calendar.set_weather_calendar(
                self.metadata["holidays"],
                self.metadata.get("daylight_saving"),
                self.metadata.get("source", ""),
            )
        self._scheduled = self._evaluate_schedules()
        self._site = self._site_from(self.metadata, building)
        self.shading = bool(shading)
        self._shadows = self._shadow_setup()
        self._interior_beam = self._interior_beam_setup()
        #: solve with prescribed air temperatures when every controlled zone sits at a set point
        self.use_dirichlet = True
        #: False: only the linear network (no lagged state-dependent corrections: TARP, exact
        #: long-wave, wind and air-density excess, window gap conductance), the plant of the
        #: exact loop analysis of :mod:`thermocal.identification.tuning`
        self.explicit_corrections = True
        self._assembly_cache: dict = {}
        self._input_cache: dict = {}
        self._build()
        self.reset()

    # ------------------------------------------------------------------------------------------
    def reset(self, *, free_float: bool = True, initial_temperature: float | None = None) -> None:
        """Restart the stepping API at the first step.

        Parameters
        ----------
        free_float : bool
            True: :meth:`step` applies only the given heat; False: also the ideal heating and
            cooling of zones with set points.
        initial_temperature : float or None [C]
            Uniform initial temperature; None = the constructor's value (with warm-up).
        """
        temp = self.initial_temperature if initial_temperature is None else initial_temperature
        self._x = self._initial_state(float(temp))
        self._face_root = np.ones(len(self.network.face_node))
        self._reset_ideal_state()
        self._k = 0
        self._step_free_float = bool(free_float)
        if self.warmup_days > 0 and initial_temperature is None:
            self._warm_up(ideal=not free_float)

    def step(self, zone_heat_W=None) -> np.ndarray:
        """Advance one step with ``zone_heat_W`` [W] delivered to each zone's air.

        Parameters
        ----------
        zone_heat_W : array-like (n_zones,) [W] or None
            Heat per zone in the order of ``building.zones``; None = no heat.

        Returns
        -------
        numpy.ndarray [C]
            Zone air temperatures at the end of the step.
        """
        nz = len(self.building.zones)
        if self._k >= len(self.times):
            raise ThermocalInputError(
                f"Simulation.step: the period has {len(self.times)} steps and all were run; "
                "call reset() to start again"
            )
        heat = np.zeros((1, nz)) if zone_heat_W is None else np.asarray(zone_heat_W, dtype=float)
        heat = heat.reshape(1, nz) if heat.size == nz else None
        if heat is None:
            raise ThermocalInputError(f"Simulation.step: zone_heat_W must have {nz} values")
        if not np.isfinite(heat).all():
            raise ThermocalInputError(
                "Simulation.step: zone_heat_W contains NaN or infinite values (an unstable "
                "controller?)"
            )
        out = self._advance(self._k, 1, heat, ideal=not self._step_free_float, store=False)
        self._k += 1
        self.last_heating = out[2][0]
        self.last_cooling = out[3][0]
        return out[0][0].copy()

    @property
    def current_time(self) -> pd.Timestamp:
        """Start label of the next step."""
        return self.times[min(self._k, len(self.times) - 1)]

    @property
    def weather_on_grid(self) -> pd.DataFrame:
        """The weather resampled to the simulation steps (``temp_air`` [C], irradiance [W/m2])."""
        return self._grid

    @property
    def zone_names(self) -> list[str]:
        """Zone order of all per-zone arrays."""
        return list(self.building.zones)

    def set_parameters(self, mapping: Mapping[str, float]) -> None:
        """Change envelope parameters (names of :meth:`Building.parameters`).

        The network is re-assembled (vectorised) and refactorised; the weather-driven inputs are
        reused where the network layout allows, and the current state is kept when the number of
        nodes is unchanged (otherwise it restarts from the initial temperature).
        """
        x_old = self._x
        k_old = self._k
        self.building = self.building.with_parameters(mapping)
        self._build()
        if len(x_old) == self.network.n_nodes:
            self._x = x_old
            self._k = k_old
            ground = self.network.foundation_nodes
            if len(ground):  # a changed section's states are another basis: restart them
                self._x[ground] = self._initial_state(self.initial_temperature)[ground]
        else:
            self._x = self._initial_state(self.initial_temperature)
            self._face_root = np.ones(len(self.network.face_node))

    # ------------------------------------------------------------------------------------------
    def run(
        self,
        *,
        free_float: bool = False,
        heat_input: pd.DataFrame | np.ndarray | None = None,
        progress: bool = False,
    ) -> SimulationResult:
        """Simulate the whole period.

        Parameters
        ----------
        free_float : bool
            Ignore the zones' heating/cooling set points.
        heat_input : DataFrame or ndarray or None [W]
            Given heat per zone and step (rows = steps; DataFrame columns = zone names, missing
            zones get 0), delivered to the zone air.
        progress : bool
            Show a rich progress bar.

        Returns
        -------
        SimulationResult
        """
        net = self.network
        nz = len(net.zone_names)
        n_steps = len(self.times)
        heat = self._heat_array(heat_input, n_steps, nz)
        self._x = self._initial_state(self.initial_temperature)
        self._face_root = np.ones(len(net.face_node))
        self._reset_ideal_state()
        self._k = 0
        if self.warmup_days > 0:
            self._warm_up(ideal=not free_float)
        store = self.store_surfaces
        n_faces = len(net.face_node)
        air = np.empty((n_steps, nz))
        mrt = np.empty((n_steps, nz))
        heating = np.zeros((n_steps, nz))
        cooling = np.zeros((n_steps, nz))
        faces = np.empty((n_steps, n_faces), dtype=np.float32) if store else None
        bar = _progress(progress, n_steps)
        try:
            for k0 in range(0, n_steps, _CHUNK):
                n = min(_CHUNK, n_steps - k0)
                out = self._advance(k0, n, heat[k0 : k0 + n], ideal=not free_float, store=store)
                air[k0 : k0 + n] = out[0]
                mrt[k0 : k0 + n] = out[1]
                heating[k0 : k0 + n] = out[2]
                cooling[k0 : k0 + n] = out[3]
                if store:
                    faces[k0 : k0 + n] = out[4]
                if bar is not None:
                    bar[0].update(bar[1], advance=n)
        finally:
            if bar is not None:
                bar[0].stop()
        self._k = n_steps
        return self._result(air, mrt, heating, cooling, heat, faces)


def notes_summary(notes) -> str:
    """A few-line summary of the import and approximation notes: counts per kind.

    The kind of a note is its first words (at most four) up to a name in quotes, a colon, a
    comma or a parenthesis ("infiltration", "objects not represented", "schedule calendar").

    Parameters
    ----------
    notes : sequence of str
        E.g. :meth:`Simulation.approximations`.

    Returns
    -------
    str
        ``"N notes: k1 (n1), k2 (n2), ..."``, or "" without notes.
    """
    import re

    counts: dict[str, int] = {}
    for note in notes:
        head = re.split(r"\s'|:|\(|;|,", str(note).strip(), maxsplit=1)[0]
        kind = " ".join(head.split()[:4]) or "other"
        counts[kind] = counts.get(kind, 0) + 1
    if not counts:
        return ""
    total = sum(counts.values())
    parts = ", ".join(f"{kind} ({n})" for kind, n in sorted(counts.items(), key=lambda kv: -kv[1]))
    return f"{total} note{'s' if total != 1 else ''}: {parts}"


# ----------------------------------------------------------------------------------------------
# weather on the simulation grid
# ----------------------------------------------------------------------------------------------


# ----------------------------------------------------------------------------------------------
# steady state
# ----------------------------------------------------------------------------------------------


def steady_state_heat_loss_coefficient(
    building: Building,
    *,
    ground_at_outdoor: bool = True,
    wind_speed: float = 4.0,
    options: NetworkOptions | None = None,
) -> float:
    """Heat needed to hold every conditioned zone 1 K above outdoors, per kelvin [W/K].

    Steady state of the network with no sun and no internal gains, sky and ground at the outdoor
    temperature (``ground_at_outdoor=True``) or ground at the indoor temperature (``False``: the
    losses to the ground temperature excluded; a floor on a two-dimensional ground section,
    ``Building.foundations``, still loses through it to the outdoor air), unconditioned zones
    floating. Interior coefficients as in the simulation
    (matrix part), exterior convection at ``wind_speed``.

    With ``interior_convection="tarp"`` (the default) the simulation adds a temperature-difference
    dependent part to the interior convection at every step; it is not in this linear steady
    state (its matrix part is TARP at a nominal 2 K surface-air difference), so a simulation
    held at a large indoor-outdoor difference loses more: ``generators.single_family_house()``
    without gains, 20 K, 4 m/s, dark: 535 W/K simulated vs 499 W/K from this function. Pass
    ``NetworkOptions(interior_convection="fixed")`` for a coefficient that such a simulation
    reproduces within about 1 % (556 vs 550 W/K; what the retrofit demo compares against).

    Parameters
    ----------
    building : Building
    ground_at_outdoor : bool
    wind_speed : float [m/s]
    options : NetworkOptions, optional

    Returns
    -------
    float [W/K]
    """
    options = options or NetworkOptions()
    net = assemble(
        building, 3600.0, options=options, mean_wind_speed=wind_speed, mean_outdoor_temperature=0.0
    )
    zones = list(building.zones.values())
    ctrl = np.array([i for i, z in enumerate(zones) if z.conditioned], dtype=int)
    if len(ctrl) == 0:
        raise ThermocalInputError(
            f"building '{building.name}' has no conditioned zone (no heating or cooling set "
            "point); the heat loss coefficient refers to conditioned zones"
        )
    k = net.conductance.tocsr()
    b = net.inputs.tocsr()
    u = np.zeros(len(net.input_names))
    if not ground_at_outdoor:
        u[IN_TEMP_GROUND] = 1.0
    rhs = b @ u
    air = net.air_node[ctrl]
    n = net.n_nodes
    fixed = np.zeros(n, dtype=bool)
    fixed[air] = True
    free = ~fixed
    x_fixed = np.ones(len(air))
    k_ff = k[free][:, free].tocsc()
    k_fc = k[free][:, fixed]
    x_free = splu(k_ff).solve(rhs[free] - k_fc @ x_fixed)
    x = np.empty(n)
    x[free] = x_free
    x[fixed] = x_fixed
    heat = k[fixed] @ x - rhs[fixed]
    return float(heat.sum())
