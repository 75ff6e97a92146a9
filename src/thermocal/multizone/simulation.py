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
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from thermocal.errors import ThermocalInputError
from thermocal.multizone import _kernel
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
    AIR_SPECIFIC_HEAT,
    IN_ONE,
    IN_TEMP_GROUND,
    IN_TEMP_OUT,
    IN_TEMP_SKY,
    WINDOW_TEMPERATURE_GRID,
    NetworkOptions,
    air_density,
    assemble,
    exterior_convection,
    mowitt_forced,
    pressure_at_altitude,
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

_CHUNK = 2048


@dataclass
class _Context:
    """Everything of the time loop that depends on the step size."""

    dt: float
    lu: object
    factors: tuple
    dirichlet: tuple
    air_rows: tuple
    c_dt: np.ndarray
    g_ctrl: np.ndarray
    inputs: np.ndarray
    ext_dh: np.ndarray
    inf_dh: np.ndarray
    face_hmax: np.ndarray
    ext_natural: np.ndarray = None  # (n_ext, 5): mode, roughness, cos tilt, hc0, max excess
    heat_sp: np.ndarray = None  # (1 or n_steps, n_controlled) [C]
    cool_sp: np.ndarray = None
    inf_dt: np.ndarray = None  # (0, 1 or n_steps, n_zones) [W/K^2]
    people_a: np.ndarray = None  # (0 or n_steps, n_zones) [W]
    people_b: np.ndarray = None  # (0 or n_steps, n_zones) [W/K]
    people_c: np.ndarray = None  # (0 or n_steps, n_zones) [W/K^2]
    people_max: np.ndarray = None  # (0 or n_steps, n_zones) [W]
    d_lu: object = None  # factorisation of the Dirichlet system (None: no controlled zones)
    vent: tuple = None  # indoor-limited ventilation arrays of the kernel (see _ventilation_arrays)
    implicit: dict = field(default_factory=dict)  # implicit outdoor-air sets -> kernel arrays


class Simulation:
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
        Days of the period's first day repeated before the run to reach a periodic initial state
        (as EnergyPlus' warm-up), 0 = start from ``initial_temperature``.
    initial_temperature : float [C]
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
        initial_temperature: float = 20.0,
        store_surfaces: bool = True,
        sky_model: str = "perez",
        schedules: str = "file",
        shading: bool = True,
        weather_interpolation: str | None = None,
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
    @staticmethod
    def _site_from(metadata, building):
        loc = building.location
        return {
            "latitude": float(metadata.get("latitude", loc.latitude)),
            "longitude": float(metadata.get("longitude", loc.longitude)),
            "altitude": float(metadata.get("altitude", loc.altitude) or 0.0),
        }

    def _build(self) -> None:
        grid = self._grid
        pressure = (
            float(np.nanmean(grid["pressure"]))
            if "pressure" in grid and grid["pressure"].notna().any()
            else pressure_at_altitude(self._site["altitude"])
        )
        self._pressure = pressure
        self._mean_wind = float(np.nanmean(grid["wind_speed"])) if "wind_speed" in grid else 0.0
        self._mean_tout = float(np.nanmean(grid["temp_air"]))
        network_building, gain_zones = self._network_building()
        self.network = assemble(
            network_building,
            self.dt,
            options=self.options,
            mean_wind_speed=self._mean_wind,
            mean_outdoor_temperature=self._mean_tout,
            pressure=pressure,
            cache=self._assembly_cache,
            gain_input_zones=gain_zones,
            own_solar_inputs=frozenset(self._shadows["beam"]) if self._shadows else frozenset(),
            sky_view_ratio=self._shadows["sky"] if self._shadows else None,
            interior_beam=(
                {w: names for w, (names, _) in self._interior_beam.items()}
                if self._interior_beam
                else None
            ),
        )
        self._inputs = self._input_matrix()
        self._factorise()

    def _evaluate_schedules(self):
        """The IDF file's schedules on the grid (None: no file schedules or 'constant')."""
        info = self._idf_info = getattr(self.building, "idf_info", None)
        if self.schedules != "file" or info is None or getattr(info, "schedules", None) is None:
            return None
        scheduled = info.scheduled_inputs(
            list(self.building.zones), self.times, self.step_size, self._grid
        )
        zones = list(self.building.zones.values())
        # zones whose gains / infiltration vary (the others keep the exact constant path)
        gains = scheduled.gains_convective + scheduled.gains_radiant
        self._gain_zones = [
            z.name for i, z in enumerate(zones) if np.ptp(gains[:, i]) > 1e-9 * (1 + gains[0, i])
        ]
        ach = scheduled.infiltration_ach
        gated = set() if scheduled.ventilation is None else set(scheduled.ventilation["zone"])
        self._inf_zones = [
            i
            for i, z in enumerate(zones)
            if np.ptp(ach[:, i]) > 1e-12
            or np.any(scheduled.infiltration_ach_per_kelvin[:, i])
            or i in gated
        ]
        return scheduled

    def _shadow_setup(self) -> dict | None:
        """Sunlit fractions (per step) and sky-diffuse ratios of the shaded receivers."""
        info = getattr(self.building, "idf_info", None)
        shaders = getattr(info, "shading_surfaces", None) if info is not None else None
        if not self.shading or not shaders:
            return None
        from thermocal.multizone.shading import ShadowCaster

        vertices = info.surface_vertices
        receivers = {}
        for surface in self.building.surfaces.values():
            if surface.boundary == "outdoors" and surface.sun_exposed and surface.name in vertices:
                holes = [
                    vertices[h] for h in info.subsurfaces_of.get(surface.name, []) if h in vertices
                ]
                receivers[surface.name] = (vertices[surface.name], holes)
        for window in self.building.windows.values():
            if self.building.surfaces[window.surface].sun_exposed and window.name in vertices:
                receivers[window.name] = (vertices[window.name], ())
        caster = ShadowCaster(shaders, receivers)
        if not caster.shaded:
            return None
        sun, evaluated, inverse = self._shadow_suns()
        tau = None
        if any(s.transmittance_schedule for s in shaders):
            tau = np.zeros((len(self.times), len(shaders)))
            for k, s in enumerate(shaders):
                if s.transmittance_schedule:
                    tau[:, k] = np.clip(
                        info.schedules.on_grid(
                            s.transmittance_schedule, self.times, self.step_size
                        ),
                        0.0,
                        1.0,
                    )
        mean_tau = None if tau is None else tau.mean(axis=0)
        tau_eval = None if tau is None else tau[evaluated]
        ratios = {name: caster.sky_diffuse_ratios(name, mean_tau) for name in caster.shaded}
        return {
            "beam": {
                name: caster.sunlit_fraction(name, sun[evaluated], tau_eval)[inverse]
                for name in caster.shaded
            },
            "sky": {name: dome for name, (dome, _) in ratios.items()},
            "horizon": {name: band for name, (_, band) in ratios.items()},
        }

    def _shadow_suns(self):
        """Sun vectors per step for the shadow calculations, the steps evaluated and, per step,
        the evaluated step that serves it.

        EnergyPlus' "Periodic" shadow calculation (PerformSolarCalculations): one day of sunlit
        fractions serves each period of N days, computed step by step with the sun of the
        period's mean declination (of its sine) and mean equation of time over the period's
        days within the run period; "Timestep" (N = 0): every step its own sun.
        """
        from thermocal.multizone.shading import sun_vectors

        info = self._idf_info
        site = self._site
        position = _sun_position(self._grid.index, site, self._sun_at_end)
        sun = sun_vectors(position["apparent_zenith"], position["azimuth"])
        days = int(getattr(info, "shadow_update_days", 0)) if info is not None else 0
        per_day = int(round(86400.0 / self.dt))
        step_index = np.arange(len(self.times))
        if days > 0 and abs(per_day * self.dt - 86400.0) < 1e-6:
            elapsed = ((self.times - self.times[0]) // self.step_size).to_numpy()
            first = (elapsed // per_day // days) * days * per_day + elapsed % per_day
            step_index = np.minimum(first, len(self.times) - 1)
            sun = _period_sun_vectors(
                self.times, self.step_size, self._sun_at_end, site, elapsed // per_day // days, days
            )
        evaluated, inverse = np.unique(step_index, return_inverse=True)
        return sun, evaluated, inverse

    def _interior_beam_setup(self) -> dict | None:
        """EnergyPlus' ``FullInteriorAndExterior``: per window, the faces of its zone and the
        share of its transmitted beam landing on each, per step (rays along the sun, one day per
        shadow period as the exterior shadows); None for other solar distributions or without
        the geometry."""
        info = self._idf_info
        if info is None:
            return None
        key = str(getattr(info, "solar_distribution", "")).replace(" ", "").upper()
        if not key.startswith("FULLINTERIORANDEXTERIOR"):
            return None
        from thermocal.multizone.shading import interior_beam_fractions

        vertices = info.surface_vertices
        sun, evaluated, inverse = self._shadow_suns()
        out = {}
        cache: dict[tuple, np.ndarray] = {}
        for window in self.building.windows.values():
            host = self.building.surfaces[window.surface]
            if not host.sun_exposed or window.name not in vertices:
                continue
            # windows first: where a window and its host wall share a plane, the window is hit
            faces = {
                w.name: vertices[w.name]
                for w in self.building.windows.values()
                if self.building.surfaces[w.surface].zone == host.zone and w.name in vertices
            }
            faces.update(
                (s.name, vertices[s.name])
                for s in self.building.surfaces.values()
                if s.zone == host.zone and s.name in vertices
            )
            faces.pop(window.name, None)
            # zones of the same shape (a grid of rooms) share the result: the key is the
            # geometry relative to the window's first vertex
            anchor = np.asarray(vertices[window.name], dtype=float)[0]
            key = tuple(
                np.round(np.asarray(v, dtype=float) - anchor, 4).tobytes()
                for v in (vertices[window.name], *faces.values())
            )
            if key not in cache:
                cache[key] = interior_beam_fractions(vertices[window.name], faces, sun[evaluated])
            shares = cache[key]
            reached = shares.any(axis=0)
            if not reached.any():
                continue
            names = [name for name, r in zip(faces, reached, strict=True) if r]
            out[window.name] = (names, np.ascontiguousarray(shares[:, reached][inverse]))
        return out or None

    def _network_building(self):
        """Building handed to the network: scheduled gains as inputs, infiltration at its mean."""
        import dataclasses

        if self._scheduled is None:
            return self.building, ()
        info = self._idf_info
        zones = dict(self.building.zones)
        self._inf_scale = np.ones(len(zones))
        names = list(zones)
        for i in self._inf_zones:
            zone = zones[names[i]]
            nominal = info.zone_nominal_ach.get(zone.name, 0.0)
            # a calibrated infiltration parameter scales the file's rate
            scale = zone.infiltration_ach / nominal if nominal > 0 else 0.0
            self._inf_scale[i] = scale
            mean = float(np.mean(self._scheduled.infiltration_ach[:, i])) * scale
            zones[zone.name] = dataclasses.replace(zone, infiltration_ach=mean)
        for name in self._gain_zones:
            zones[name] = dataclasses.replace(zones[name], internal_gains=0.0)
        return dataclasses.replace(self.building, zones=zones), tuple(self._gain_zones)

    def _setpoint_arrays(self, heat_sp, cool_sp):
        """Per-step set points of the controlled zones, or one row when they are constant."""
        heat = heat_sp[None, :]
        cool = cool_sp[None, :]
        if self._scheduled is not None and len(self._ctrl):
            h = self._scheduled.heating_setpoint[:, self._ctrl]
            c = self._scheduled.cooling_setpoint[:, self._ctrl]
            h = np.where(np.isnan(h), -np.inf, h)
            c = np.where(np.isnan(c), np.inf, c)
            # a zone without the schedule keeps its constant value
            h = np.where(np.isfinite(heat) & ~np.isfinite(h), heat, h)
            c = np.where(np.isfinite(cool) & ~np.isfinite(c), cool, c)
            if (
                np.ptp(np.where(np.isfinite(h), h, 0.0), axis=0).any()
                or np.ptp(np.where(np.isfinite(c), c, 0.0), axis=0).any()
            ):
                heat, cool = h, c
        return np.ascontiguousarray(heat, dtype=float), np.ascontiguousarray(cool, dtype=float)

    def _factorise(self) -> None:
        net = self.network
        zones = list(self.building.zones.values())
        ctrl = [i for i, z in enumerate(zones) if z.conditioned]
        self._ctrl = np.asarray(ctrl, dtype=np.int64)
        heat_sp = [zones[i].heating_setpoint for i in ctrl]
        cool_sp = [zones[i].cooling_setpoint for i in ctrl]
        self._heat_sp = np.array([-np.inf if t is None else t for t in heat_sp], dtype=float)
        self._cool_sp = np.array([np.inf if t is None else t for t in cool_sp], dtype=float)
        self._heat_sp_steps, self._cool_sp_steps = self._setpoint_arrays(
            self._heat_sp, self._cool_sp
        )
        b = net.inputs.tocsr()
        b.sort_indices()
        self._b = (b.indptr.astype(np.int64), b.indices.astype(np.int64), b.data)
        counts = np.bincount(net.face_zone, weights=net.face_area, minlength=len(zones))
        self._zone_face_area = counts.astype(float)
        # second column: the area of the exact sigma T^4 correction of the exterior long-wave;
        # EnergyPlus' SimpleCombined coefficient of an opaque face is a constant combined
        # coefficient (its radiative part linear in T_out - T_s): no correction there (on
        # 5ZoneAirCooled's south walls in the sun it made the outside faces 1-1.6 K too cold)
        longwave_area = net.ext_area * net.ext_emissivity
        if self.options.exterior_convection == "simple_combined":
            longwave_area = np.where(net.ext_is_window, longwave_area, 0.0)
        self._ext_area_eps = np.ascontiguousarray(np.stack([net.ext_area, longwave_area], axis=1))
        self._tracking_cache = {}
        self._fine = self._context(self.dt, self._inputs, self._ext_dh_raw, self._inf_dh)
        self._lu = self._fine.lu
        self._coarse = None
        self._reset_ideal_state()

    def _tracking_context(self, zones: np.ndarray, form: tuple, coarse: bool):
        """Fine (or hourly first-day) context whose Dirichlet system prescribes ``zones``.

        ``form = (air_weight, radiant_fraction)``, two tuples over ``zones`` (see
        :meth:`track`). Returns ``(context, g_inverse, distribution)``: ``g_inverse`` is the
        inverse of the sensed-temperature response of the tracked zones to their unit heat (empty
        when the sensors read the air and the heat goes into the air: the Dirichlet system
        solves that case), ``distribution`` the kernel's CSR of the nodes each zone's heat enters.
        Cached until the network changes (:meth:`set_parameters`).
        """
        key = (tuple(int(z) for z in zones), form, bool(coarse))
        cache = self.__dict__.setdefault("_tracking_cache", {})
        if key in cache:
            return cache[key]
        if coarse:
            context = self._coarse_context(controlled=zones, ideal=False, base=self._coarse)
            if context is None:
                cache[key] = None
                return None
        else:
            context = self._context(
                self.dt,
                self._inputs,
                self._ext_dh_raw,
                self._inf_dh,
                controlled=zones,
                ideal=False,
                base=self._fine,
            )
        air_weight = np.asarray(form[0], dtype=float)
        distribution = self._heat_distribution(zones, np.asarray(form[1], dtype=float))
        g_inverse = np.zeros((0, 0))
        if np.any(air_weight != 1.0) or np.any(np.asarray(form[1]) != 0.0):
            net = self.network
            ptr, idx, val = distribution
            rows = np.repeat(np.arange(len(zones)), np.diff(ptr))
            unit = sp.csc_matrix((val, (idx, rows)), shape=(net.n_nodes, len(zones))).toarray()
            response = context.lu.solve(unit)
            weights = sp.csr_matrix(
                (net.face_area, (net.face_zone, net.face_node)),
                shape=(len(net.zone_names), net.n_nodes),
            )
            area = self._zone_face_area[zones]
            mrt = np.asarray(weights[zones] @ response)
            air = response[net.air_node[zones], :]
            mrt = np.where(area[:, None] > 0, mrt / np.where(area > 0, area, 1.0)[:, None], air)
            sensed = air_weight[:, None] * air + (1.0 - air_weight[:, None]) * mrt
            g_inverse = np.ascontiguousarray(np.linalg.inv(sensed))

            def sensed_of(resp):
                m_rt = np.asarray(weights[zones] @ resp)
                a_ir = resp[net.air_node[zones], :]
                m_rt = np.where(
                    area[:, None] > 0, m_rt / np.where(area > 0, area, 1.0)[:, None], a_ir
                )
                return air_weight[:, None] * a_ir + (1.0 - air_weight[:, None]) * m_rt

            # tracked zones with scheduled outdoor air: their air flow in the step it belongs
            # to, solved with the tracking heat (see the kernel's general inverse)
            inf = set(int(z) for z in getattr(self, "_inf_zones", ()))
            held = np.asarray([int(z) for z in zones if int(z) in inf], dtype=np.int64)
            if len(held):
                air_t = net.air_node[held]
                unit_t = np.zeros((net.n_nodes, len(held)))
                unit_t[air_t, np.arange(len(held))] = 1.0
                resp_t = context.lu.solve(unit_t)
                a_q = response[air_t, :]
                k_h = g_inverse @ sensed_of(resp_t)
                m_h = resp_t[air_t, :] - a_q @ k_h
                context.implicit["tracked"] = (
                    held,
                    np.ascontiguousarray(a_q),
                    np.ascontiguousarray(k_h),
                    np.ascontiguousarray(m_h),
                    np.zeros(len(held) + 1),
                    np.zeros((len(held), len(held))),
                )
        cache[key] = (context, g_inverse, distribution)
        return cache[key]

    def _heat_distribution(self, zones: np.ndarray, radiant_fraction: np.ndarray) -> tuple:
        """Nodes and weights of each tracked zone's heat: ``1 - f`` into the air, ``f`` over
        its faces as the radiant internal gains (:func:`~thermocal.multizone.network.
        radiant_gain_shares`); CSR arrays ``(ptr, idx, val)`` for the kernel."""
        net = self.network
        ptr, idx, val = [0], [], []
        for z, fraction in zip(zones, radiant_fraction, strict=True):
            members = np.flatnonzero(net.face_zone == z)
            if fraction == 0.0 or len(members) == 0:
                idx.append(int(net.air_node[z]))
                val.append(1.0)
            else:
                idx.append(int(net.air_node[z]))
                val.append(1.0 - float(fraction))
                idx.extend(int(n) for n in net.face_node[members])
                val.extend(float(fraction) * net.face_radiant_share[members])
            ptr.append(len(idx))
        return (
            np.asarray(ptr, dtype=np.int64),
            np.asarray(idx, dtype=np.int64),
            np.asarray(val, dtype=float),
        )

    def _reset_ideal_state(self) -> None:
        nc = len(self._ctrl)
        self._active = np.zeros(nc, dtype=np.int64)
        self._cache_member = np.zeros(nc, dtype=np.bool_)
        self._cache_inv = np.zeros((nc, nc))
        # diagnostics: members (-1: invalid), updates since inversion, inversions, rank-one
        # updates, active-set iterations, Dirichlet rejections, superposition calls
        self._cache_m = np.zeros(8, dtype=np.int64)
        self._cache_m[0] = -1

    def _context(
        self,
        dt: float,
        inputs,
        ext_dh_raw,
        inf_dh,
        *,
        controlled=None,
        ideal: bool = True,
        base: _Context | None = None,
    ) -> _Context:
        """Factorisation and step-size dependent arrays for steps of ``dt`` seconds.

        ``controlled``: zone indices whose air temperatures the Dirichlet system prescribes
        (default: the conditioned zones); ``ideal=False`` skips the ideal-load response matrix;
        ``base``: a context of the same network and step whose factorisation is reused.
        """
        net = self.network
        controlled = self._ctrl if controlled is None else np.asarray(controlled, dtype=np.int64)
        matrix = net.system_matrix(dt)
        if base is not None and base.dt == dt:
            lu, factors = base.lu, base.factors
        else:
            lu = _factorise(matrix)
            factors = _kernel.prepare_factors(lu.L, lu.U, lu.perm_r, lu.perm_c)
        dirichlet = factors
        d_lu = None
        rows = (np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0))
        if len(controlled):
            # the same system with the controlled air temperatures prescribed (identity rows)
            air = net.air_node[controlled]
            keep = np.ones(net.n_nodes)
            keep[air] = 0.0
            prescribed = sp.diags(keep) @ matrix + sp.diags(1.0 - keep)
            d_lu = _factorise(prescribed.tocsc())
            dirichlet = _kernel.prepare_factors(d_lu.L, d_lu.U, d_lu.perm_r, d_lu.perm_c)
            air_rows = matrix.tocsr()[air]
            air_rows.sort_indices()
            rows = (
                air_rows.indptr.astype(np.int64),
                air_rows.indices.astype(np.int64),
                air_rows.data.copy(),
            )
        if len(controlled) and ideal:
            unit = np.zeros((net.n_nodes, len(controlled)))
            unit[net.air_node[controlled], np.arange(len(controlled))] = 1.0
            g_ctrl = np.ascontiguousarray(lu.solve(unit)[net.air_node[controlled], :])
        else:
            g_ctrl = np.zeros((0, 0))
        # explicit-correction bounds (stability of the lagged terms, see network module)
        face_hmax = 2.0 * net.face_h0 + net.face_capacity / dt
        upper = net.ext_hc0 + net.ext_hr0 * net.ext_emissivity + net.ext_capacity / dt
        ext_natural = self._ext_natural(upper)
        plain = ext_natural[:, 0] == 0.0
        clipped = np.clip(ext_dh_raw, 0.1 - net.ext_hc0[None, :], upper[None, :])
        ext_dh = np.where(plain[None, :], clipped, ext_dh_raw)
        per_step = (
            self._heat_sp_steps,
            self._cool_sp_steps,
            self._inf_dt,
            *self._people,
        )
        vent = self._vent
        if dt == self.dt:
            heat_sp, cool_sp, inf_dt, people_a, people_b, people_c, people_max = per_step
        else:  # hourly warm-up context of the first day
            per_day = int(round(86400.0 / self.dt))
            m = int(round(3600.0 / self.dt))
            heat_sp, cool_sp, inf_dt, people_a, people_b, people_c, people_max = (
                a if a.shape[0] <= 1 else _hourly_first_day(a, per_day, m) for a in per_step
            )
            vent = (
                (vent[0],)
                + tuple(
                    a if a.shape[0] <= 1 else _hourly_first_day(a, per_day, m) for a in vent[1:-1]
                )
                + (np.zeros((per_day // m, vent[0].shape[0])),)
            )
        return _Context(
            d_lu=d_lu,
            vent=vent,
            heat_sp=np.ascontiguousarray(heat_sp),
            cool_sp=np.ascontiguousarray(cool_sp),
            inf_dt=np.ascontiguousarray(inf_dt),
            people_a=np.ascontiguousarray(people_a),
            people_b=np.ascontiguousarray(people_b),
            people_c=np.ascontiguousarray(people_c),
            people_max=np.ascontiguousarray(people_max),
            dt=dt,
            lu=lu,
            factors=factors,
            dirichlet=dirichlet,
            air_rows=rows,
            c_dt=net.capacity / dt,
            g_ctrl=g_ctrl,
            inputs=np.ascontiguousarray(inputs),
            ext_dh=np.ascontiguousarray(ext_dh),
            inf_dh=np.ascontiguousarray(inf_dh),
            face_hmax=face_hmax,
            ext_natural=ext_natural,
        )

    def _coarse_context(self, **kwargs) -> _Context | None:
        """Hourly context over the first day of the period, for the warm-up (or None).

        Keyword arguments go to :meth:`_context` (a tracking context is not cached).
        """
        per_hour = 3600.0 / self.dt
        per_day = int(round(86400.0 / self.dt))
        if per_hour <= 1 or not float(per_hour).is_integer() or len(self.times) < per_day:
            return None
        if self._coarse is None or kwargs:
            m = int(per_hour)
            context = self._context(
                3600.0,
                _hourly_first_day(self._inputs, per_day, m),
                _hourly_first_day(self._ext_dh_raw, per_day, m),
                _hourly_first_day(self._inf_dh, per_day, m),
                **kwargs,
            )
            if kwargs:
                return context
            self._coarse = context
        return self._coarse

    # ------------------------------------------------------------------------------------------
    def _ground_temperature(self) -> np.ndarray:
        months = self.times.month.to_numpy() - 1
        if self.building.ground_temperatures is not None:
            monthly = np.asarray(self.building.ground_temperatures)
        else:
            table = self.metadata.get("ground_temperatures") or {}
            if table:
                depth = min(table, key=lambda d: abs(float(d) - 2.0))
                monthly = np.asarray(table[depth], dtype=float)
            else:
                return self._kusuda_ground_temperature()
        return monthly[months]

    def _kusuda_ground_temperature(self) -> np.ndarray:
        """Undisturbed ground at 2 m from the weather's annual wave, else the mean outdoor air."""
        from thermocal.physics.ground import ground_temperature, ground_temperature_parameters

        try:
            params = ground_temperature_parameters(self._weather)
        except (ThermocalInputError, ValueError):
            return np.full(len(self.times), self._mean_tout)
        return ground_temperature(self.times, 2.0, **params).to_numpy(dtype=float)

    def _input_matrix(self) -> np.ndarray:
        """Inputs ``u`` (n_steps x n_inputs) and the explicit-correction coefficient series."""
        net = self.network
        grid = self._grid
        n_steps = len(grid)
        u = np.zeros((n_steps, len(net.input_names)))
        t_out = grid["temp_air_mean"].to_numpy()
        u[:, IN_TEMP_OUT] = t_out
        u[:, IN_TEMP_SKY] = grid["temp_sky"].to_numpy()
        u[:, IN_TEMP_GROUND] = self._ground_temperature()
        u[:, IN_ONE] = 1.0
        # solar
        orientations = {k[:2] for k in net.orientation_inputs}
        orientations.update((k[1], k[2]) for k in net.window_inputs)
        if orientations:
            cache = self.__dict__.setdefault("_irradiance_cache", {})
            missing = sorted(o for o in orientations if o not in cache)
            if missing:
                cache.update(
                    _irradiance(
                        grid,
                        self._site,
                        missing,
                        self.sky_model,
                        self._sun_at_end,
                        albedo=_ground_reflectance(grid, self.building.ground_reflectance),
                    )
                )
            irr = cache
            for key, col in net.orientation_inputs.items():
                if len(key) == 3:  # a shaded receiver
                    u[:, col] = self._shaded(irr[key[:2]], key[2])["poa_global"]
                else:
                    u[:, col] = irr[key]["poa_global"]
            for wkey, cols in net.window_inputs.items():
                wt_name, tilt, az = wkey[:3]
                wt = self.building.window_types[wt_name]
                key = ("window", wt_name, wt.shgc, wt.solar_transmittance, *wkey[1:])
                if key not in self._input_cache:
                    source = irr[(tilt, az)]
                    if len(wkey) == 4:
                        source = self._shaded(source, wkey[3])
                    self._input_cache[key] = _window_inputs(wt, source, n_steps)
                for col, values in zip(cols, self._input_cache[key], strict=True):
                    u[:, col] = values
        interior = []
        for window, (beam_col, area, targets) in net.window_beam_targets.items():
            names, shares = self._interior_beam[window]
            for face, col in targets:
                # transmitted beam [W] landing on the face
                u[:, col] = u[:, beam_col] * area * shares[:, names.index(face)]
                interior.append(col)
        if self.weather_interpolation == "energyplus":
            # rows hold the curve at each step's end: the step is forced by the mean of its start
            # and end values (the first step keeps its end value)
            weather_driven = [IN_TEMP_OUT, IN_TEMP_SKY, *net.orientation_inputs.values()]
            weather_driven += [col for cols in net.window_inputs.values() for col in cols]
            weather_driven += interior
            u[1:, weather_driven] = 0.5 * (u[1:, weather_driven] + u[:-1, weather_driven])
            t_out = u[:, IN_TEMP_OUT]
        # explicit corrections: exterior convection (wind) and infiltration air density
        key = ("doe2", tuple(net.ext_names))
        if key not in self._input_cache:
            self._input_cache[key] = self._exterior_convection_excess()
        self._ext_dh_raw = self._input_cache[key]
        pressure = grid["pressure"].to_numpy() if "pressure" in grid else None
        if pressure is None or not np.isfinite(pressure).all():
            pressure = np.full(n_steps, self._pressure)
        rho = air_density(pressure, t_out)
        ratio = rho / net.reference_density - 1.0
        inf_dh = ratio[:, None] * net.zone_infiltration[None, :]
        self._inf_dt = np.zeros((0, len(net.zone_names)))
        self._people = (np.zeros((0, len(net.zone_names))),) * 4
        scheduled = self._scheduled
        if scheduled is not None:
            if scheduled.people_per_kelvin is not None and np.any(scheduled.people_per_kelvin):
                # People's sensible heat at the zone temperature (lagged), beyond its 22 C value,
                # clipped to [0, activity] in the time loop
                people_a, people_max = self._people_limits()
                self._people = (
                    people_a,
                    np.ascontiguousarray(scheduled.people_per_kelvin),
                    np.ascontiguousarray(scheduled.people_per_kelvin2),
                    people_max,
                )
            names = list(net.zone_names)
            for name in self._gain_zones:
                z = names.index(name)
                u[:, net.input_names.index(f"gains_convective/{name}")] = (
                    scheduled.gains_convective[:, z]
                )
                u[:, net.input_names.index(f"gains_radiant/{name}")] = scheduled.gains_radiant[:, z]
            volume = np.array([z.volume for z in self.building.zones.values()])
            per_ach = AIR_SPECIFIC_HEAT * volume / 3600.0  # [J/(m3 K)] x [m3] / [s/h]
            zones = np.asarray(self._inf_zones, dtype=np.int64)
            if len(zones):
                ach = scheduled.infiltration_ach[:, zones] * self._inf_scale[zones]
                inf_dh[:, zones] = (
                    rho[:, None] * per_ach[zones] * ach - net.zone_infiltration[zones][None, :]
                )
                ach_dt = scheduled.infiltration_ach_per_kelvin * self._inf_scale[None, :]
                if np.any(ach_dt):
                    self._inf_dt = np.ascontiguousarray(rho[:, None] * per_ach[None, :] * ach_dt)
        self._inf_dh = np.ascontiguousarray(inf_dh)
        self._vent = self._ventilation_arrays(rho, n_steps)
        return u

    def _ventilation_arrays(self, rho: np.ndarray, n_steps: int) -> tuple:
        """Kernel arrays of the ventilation objects with indoor-temperature limits.

        ``(zone (j,), conductance [W/K], per kelvin [W/K^2] (0 rows when none), fan heat [W],
        minimum [C], maximum [C], delta [K], open state (n_steps, j))``, per step and object,
        the flow scaled with a calibrated infiltration rate of the zone as the file's other
        outdoor air.
        """
        scheduled = self._scheduled
        vent = None if scheduled is None else scheduled.ventilation
        if vent is None:
            empty = np.zeros((0, 0))
            return (np.zeros(0, dtype=np.int64), empty, empty, empty, empty, empty, empty, empty)
        zones = vent["zone"]
        volume = np.array([z.volume for z in self.building.zones.values()])[zones]
        per_ach = rho[:, None] * AIR_SPECIFIC_HEAT * volume[None, :] / 3600.0
        scale = self._inf_scale[zones][None, :]
        gdt = per_ach * vent["ach_per_kelvin"] * scale
        return (
            np.ascontiguousarray(zones, dtype=np.int64),
            np.ascontiguousarray(per_ach * vent["ach"] * scale),
            np.ascontiguousarray(gdt if np.any(gdt) else np.zeros((0, len(zones)))),
            np.ascontiguousarray(vent["fan_heat"] * scale),
            np.ascontiguousarray(vent["minimum"]),
            np.ascontiguousarray(vent["maximum"]),
            np.ascontiguousarray(vent["delta"]),
            np.zeros((n_steps, len(zones))),
        )

    def _people_limits(self) -> tuple[np.ndarray, np.ndarray]:
        """Constant term [W] and upper limit [W] of the People sensible heat per zone and step.

        For People with an autocalculated sensible fraction: ``sum(number x a(activity))`` of
        :func:`~thermocal.multizone.idf.loads.people_sensible_coefficients` and
        ``sum(number x activity)`` (EnergyPlus clips each person's sensible heat to
        ``[0, activity]``; clipping the zone's sum is the same when its People share one activity
        schedule).
        """
        from thermocal.multizone.idf.loads import people_sensible_coefficients

        info = self._idf_info
        names = list(self.building.zones)
        n, nz = len(self.times), len(names)
        constant = np.zeros((n, nz))
        limit = np.zeros((n, nz))
        sched = info.schedules
        for gain in info.internal_gains:
            if (
                gain.zone not in self.building.zones
                or gain.people_count <= 0
                or gain.activity_schedule is None
                or gain.sensible_fraction is not None
            ):
                continue
            z = names.index(gain.zone)
            fraction = (
                np.ones(n)
                if gain.schedule is None
                else sched.on_grid(gain.schedule, self.times, self.step_size)
            )
            activity = sched.on_grid(gain.activity_schedule, self.times, self.step_size)
            a, _, _ = people_sensible_coefficients(activity)
            constant[:, z] += gain.people_count * fraction * a
            limit[:, z] += gain.people_count * fraction * activity
        return np.ascontiguousarray(constant), np.ascontiguousarray(limit)

    def _shaded(self, irradiance: dict, name: str) -> dict:
        """Irradiance on a shaded receiver, as EnergyPlus' ``AnisoSkyViewFactors``: beam and
        the sky's circumsolar part x the sunlit fraction, the dome x its unshaded share
        (``DifShdgRatioIsoSky``), the horizon band x its own (``DifShdgRatioHoriz``)."""
        out = dict(irradiance)
        sunlit = self._shadows["beam"][name]
        out["poa_direct"] = irradiance["poa_direct"] * sunlit
        out["poa_sky_diffuse"] = np.maximum(
            irradiance["poa_sky_isotropic"] * self._shadows["sky"][name]
            + irradiance["poa_sky_circumsolar"] * sunlit
            + irradiance["poa_sky_horizon"] * self._shadows["horizon"][name],
            0.0,
        )
        out["poa_global"] = out["poa_direct"] + out["poa_sky_diffuse"] + out["poa_ground_diffuse"]
        return out

    def _exterior_convection_excess(self) -> np.ndarray:
        """Wind-driven exterior convection minus its matrix part, per step and face [W/(m2 K)]."""
        net = self.network
        grid = self._grid
        n_steps = len(grid)
        if self.options.exterior_convection == "fixed" or not len(net.ext_node):
            return np.zeros((n_steps, len(net.ext_node)))
        station = grid["wind_speed"].to_numpy() if "wind_speed" in grid else np.zeros(n_steps)
        station = np.nan_to_num(station)
        if self.options.exterior_convection == "simple_combined":
            from thermocal.multizone.network import simple_combined_exterior_coefficient

            keys = np.stack([net.ext_roughness, net.ext_wind_factor], axis=1)
            unique, inverse = np.unique(np.round(keys, 6), axis=0, return_inverse=True)
            rough, factor = unique.T
            hc = simple_combined_exterior_coefficient(station[:, None] * factor, rough[None, :])
            # opaque faces: the long-wave part is the network's (all with the outdoor air);
            # windows: all of it convective, their long-wave exchange apart (EnergyPlus)
            radiative = np.where(net.ext_is_window, 0.0, net.ext_hr0 * net.ext_emissivity)
            hc = hc[:, np.ravel(inverse)] - radiative
            return np.ascontiguousarray(np.maximum(hc, 0.0) - net.ext_hc0[None, :])
        if "wind_direction" in grid:
            direction = np.nan_to_num(grid["wind_direction"].to_numpy())
        else:
            direction = np.zeros(n_steps)
        # faces of equal orientation and exposure share the series: compute per class, broadcast
        keys = np.stack(
            [
                net.ext_tilt,
                net.ext_azimuth,
                net.ext_hc0,
                net.ext_h_natural,
                net.ext_roughness,
                net.ext_wind_factor,
                net.ext_perimeter_over_area,
            ],
            axis=1,
        )
        unique, inverse = np.unique(np.round(keys, 6), axis=0, return_inverse=True)
        tilt, azimuth, hc0, h_natural, roughness, factor, p_over_a = unique.T
        # EnergyPlus' Windward(): within 90 degrees of the outward normal, or |cos tilt| >= 0.98
        diff = np.abs((direction[:, None] - azimuth[None, :] + 180.0) % 360.0 - 180.0)
        horizontal = np.abs(np.cos(np.radians(tilt))) >= 0.98
        windward = (diff <= 90.0 + 1e-3) | horizontal[None, :]
        local = station[:, None] * factor[None, :]
        if self.options.exterior_convection == "doe2":
            # the kernel combines it with the natural part at each step's face temperature
            forced = mowitt_forced(local, windward)
            return np.ascontiguousarray(forced[:, np.ravel(inverse)])
        hc = exterior_convection(
            self.options.exterior_convection,
            local,
            windward,
            h_natural=h_natural[None, :],
            roughness_factor=roughness[None, :],
            perimeter_over_area=p_over_a[None, :],
        )
        if self.options.exterior_convection == "tarp":  # the forced part alone
            return np.ascontiguousarray((hc - h_natural[None, :])[:, np.ravel(inverse)])
        return np.ascontiguousarray((hc - hc0[None, :])[:, np.ravel(inverse)])

    def _ext_natural(self, upper: np.ndarray) -> np.ndarray:
        """Per exterior face: how the kernel takes the natural part of the outside convection.

        Columns: mode (0 the series is the excess over ``hc0``; 1 DOE-2, 2 TARP: the series is
        the forced term and the natural part is TARP's at each step's face-to-air difference,
        as EnergyPlus' ``CalcASHRAETARPNatural`` with the outside face temperature), the DOE-2
        roughness multiplier [-], the cosine of the tilt [-], ``hc0`` [W/(m2 K)] and the largest
        excess over ``hc0`` that keeps the lagged term stable [W/(m2 K)].
        """
        net = self.network
        mode = {"doe2": 1.0, "tarp": 2.0}.get(self.options.exterior_convection, 0.0)
        n_ext = len(net.ext_node)
        if not n_ext:
            return np.zeros((0, 5))
        return np.ascontiguousarray(
            np.stack(
                [
                    np.full(n_ext, mode),
                    net.ext_roughness,
                    np.cos(np.radians(net.ext_tilt)),
                    net.ext_hc0,
                    upper,
                ],
                axis=1,
            )
        )

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
        self._x = np.full(self.network.n_nodes, float(temp))
        self._face_root = np.ones(len(self.network.face_node))
        self._reset_ideal_state()
        self._k = 0
        self._step_free_float = bool(free_float)
        if self.warmup_days > 0 and initial_temperature is None:
            self._warm_up(ideal=not free_float)

    def _warm_up(self, *, ideal: bool) -> None:
        """Repeat the period's first day ``warmup_days`` times (hourly steps when possible)."""
        context = self._coarse_context() or self._fine
        n_day = min(int(round(86400.0 / context.dt)), len(context.inputs))
        zeros = np.zeros((n_day, len(self.building.zones)))
        for _ in range(self.warmup_days):
            self._advance(0, n_day, zeros, ideal=ideal, store=False, context=context)

    def _advance(
        self,
        k0: int,
        n: int,
        heat: np.ndarray,
        *,
        ideal: bool,
        store: bool,
        context: _Context | None = None,
        tracking: dict | None = None,
    ):
        context = context or self._fine
        if getattr(self, "_last_context", None) is not context:
            self._cache_m[0] = -1  # the cached active-block inverse belongs to another step size
            self._last_context = context
        net = self.network
        nz = len(net.zone_names)
        out_air = np.empty((n, nz))
        out_mrt = np.empty((n, nz))
        out_heat = np.zeros((n, nz))
        out_cool = np.zeros((n, nz))
        n_faces = len(net.face_node)
        out_face = np.empty((n, n_faces if store else 0), dtype=np.float64)
        linear = not self.explicit_corrections
        # state-dependent interior convection: 1 TARP, 2 EnergyPlus' Simple (by heat-flow direction)
        tarp_on = 0
        if not linear and self.options.interior_convection == "tarp":
            tarp_on = 1
        elif (
            not linear
            and self.options.interior_convection == "simple"
            and self.options.h_interior_fixed is None
        ):
            tarp_on = 2
        ext_dh = np.zeros_like(context.ext_dh) if linear else context.ext_dh
        inf_dh = np.zeros_like(context.inf_dh) if linear else context.inf_dh
        window_ratio = (
            np.ones_like(net.window_conductance_ratio) if linear else net.window_conductance_ratio
        )
        track = tracking if tracking is not None else _no_tracking(n)
        controlled = track.get("zones", self._ctrl)
        dirichlet_first = track["mode"] == 1 and not track["general"]
        if linear:
            imp = _NO_IMPLICIT[:4] + (np.zeros(nz, dtype=np.bool_),)
            vent = _NO_VENT
        else:
            # zones whose air temperature the step holds (ideal loads, the exact inverse); a PID
            # zone's heat is known before the solve, so its outdoor air is implicit as a free one's
            inverse = tracking is not None and track["mode"] == 1
            held = controlled if (ideal or inverse) else ()
            imp = self._implicit_arrays(context, held, dirichlet_first)
            vent = context.vent
        general = tracking is not None and track["mode"] == 1 and track["general"]
        tracked_air = context.implicit.get("tracked", _NO_TRACKED_AIR) if general else None
        if tracked_air is None or linear:
            tracked_air = _NO_TRACKED_AIR
        try:
            _kernel.run_steps(
                k0,
                n,
                self._x,
                context.c_dt,
                *self._b,
                context.inputs,
                np.ascontiguousarray(heat, dtype=float),
                *context.factors,
                net.ext_node,
                self._ext_area_eps,
                net.ext_view_air,
                net.ext_view_sky,
                net.ext_hr0,
                ext_dh,
                np.zeros_like(context.ext_natural) if linear else context.ext_natural,
                self.options.exact_sky_longwave and not linear,
                net.face_node,
                net.air_node[net.face_zone],
                net.face_area,
                net.face_cos_up,
                net.face_h0,
                context.face_hmax,
                tarp_on,
                self._face_root,
                net.air_node,
                inf_dh,
                np.zeros((0, nz)) if linear else context.inf_dt,
                np.zeros((0, nz)) if linear else context.people_a,
                np.zeros((0, nz)) if linear else context.people_b,
                np.zeros((0, nz)) if linear else context.people_c,
                np.zeros((0, nz)) if linear else context.people_max,
                controlled,
                context.heat_sp if tracking is None else track["dummy_sp"],
                context.cool_sp if tracking is None else track["dummy_sp"],
                context.g_ctrl,
                bool(ideal),
                net.face_zone,
                self._zone_face_area,
                out_air,
                out_mrt,
                out_heat,
                out_cool,
                out_face,
                bool(store),
                self._active,
                self._cache_member,
                self._cache_inv,
                self._cache_m,
                len(self._ctrl) > 0 and self.use_dirichlet,
                *context.dirichlet,
                *context.air_rows,
                net.window_outer,
                net.window_inner,
                net.window_conductance,
                window_ratio,
                WINDOW_TEMPERATURE_GRID[0],
                WINDOW_TEMPERATURE_GRID[1] - WINDOW_TEMPERATURE_GRID[0],
                self.options.exact_interior_longwave
                and self.options.interior_longwave
                and not linear,
                net.face_mrt_node,
                net.face_mrt_conductance,
                net.lw_pair_a,
                net.lw_pair_b,
                net.lw_pair_g,
                net.h_black,
                track["mode"],
                track["reference"],
                track["general"],
                track["w_air"],
                *track["distribution"],
                *track["pid"],
                track["pid_state"],
                track["feedback"],
                track["q_low"],
                track["q_high"],
                track["g_inverse"],
                track["out_q"],
                *imp,
                *vent,
                *tracked_air,
            )
        except ZeroDivisionError:
            self._diverged(k0, n, None)
        if tracking is None:  # a diverging tracking loop is marked and handled by its caller
            self._diverged(k0, n, out_air)
        return out_air, out_mrt, out_heat, out_cool, out_face

    def _diverged(self, k0: int, n: int, air) -> None:
        """Refuse a run whose temperatures became NaN or infinite (an unstable step)."""
        if air is not None:
            bad = ~np.isfinite(air)
            if not bad.any():
                return
            zones = [self.network.zone_names[z] for z in np.flatnonzero(bad.any(axis=0))]
        else:
            x = self._x[self.network.air_node]
            bad = ~np.isfinite(x)
            zones = [self.network.zone_names[z] for z in np.flatnonzero(bad)] or list(
                self.network.zone_names
            )
        raise ThermocalInputError(
            f"the simulation diverged between steps {k0} and {k0 + n} "
            f"({self.times[min(k0, len(self.times) - 1)]} onwards) in zone(s) "
            f"{', '.join(repr(z) for z in zones[:5])}: the step ({self.step_size}) is too long "
            "for these zones' air capacity and gains; use a shorter step (e.g. '15min' or "
            "'5min') or check the zone's volume and gains"
        )

    def _implicit_arrays(self, context: _Context, held, dirichlet: bool) -> tuple:
        """Kernel arrays of the zones whose outdoor air is implicit in the step.

        The zones with scheduled or indoor-limited outdoor air apart from ``held`` (zones the
        ideal loads or the tracking hold at a temperature); ``imp_g`` is their air-temperature
        response [K/W] to unit heat in their air in the system of the kernel's first solve (the
        Dirichlet system when ``dirichlet``). Cached per context.
        """
        if not len(getattr(self, "_inf_zones", ())):
            return _NO_IMPLICIT[:4] + (np.zeros(len(self.network.zone_names), dtype=np.bool_),)
        held = {int(z) for z in held}
        zones = tuple(int(z) for z in self._inf_zones if int(z) not in held)
        key = (zones, bool(dirichlet), tuple(sorted(held)) if dirichlet else ())
        if key in context.implicit:
            return context.implicit[key]
        if not zones:
            free = np.zeros(len(self.network.zone_names), dtype=np.bool_)
            free[np.asarray(self._inf_zones, dtype=np.int64)] = True
            context.implicit[key] = _NO_IMPLICIT[:4] + (free,)
            return context.implicit[key]
        net = self.network
        air = net.air_node[np.asarray(zones, dtype=np.int64)]
        unit = np.zeros((net.n_nodes, len(zones)))
        unit[air, np.arange(len(zones))] = 1.0
        if dirichlet:
            if context.d_lu is None:
                raise RuntimeError("tracking by the Dirichlet system without its factorisation")
            lu = context.d_lu
        else:
            lu = context.lu
        g = np.ascontiguousarray(lu.solve(unit)[air, :])
        m = len(zones)
        free = np.zeros(len(net.zone_names), dtype=np.bool_)
        free[np.asarray(self._inf_zones, dtype=np.int64)] = True
        arrays = (
            np.asarray(zones, dtype=np.int64),
            g,
            np.zeros(m + 1),
            np.zeros((m, m)),
            free,
        )
        context.implicit[key] = arrays
        return arrays

    def track(
        self,
        reference: np.ndarray,
        *,
        zones=None,
        method: str = "inverse",
        feedback="air",
        radiant_fraction=0.0,
        pid: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
        limits: tuple[np.ndarray, np.ndarray] | None = None,
        heat_input: pd.DataFrame | np.ndarray | None = None,
        progress: bool = False,
    ) -> TrackingResult:
        """Closed loop over the whole period: the heat each zone needs to follow ``reference``.

        The loop runs inside the compiled kernel (one call per chunk of 2,048 steps), all zones at
        once. Before the period, the first day of the reference is tracked ``warmup_days`` times
        with the exact inverse at hourly steps (hourly means of the reference), so that walls and
        floors start in a state consistent with the measurements; the PID integrators then start
        bumplessly at the last warm-up heat (``x1 = x2 = q0 / KI``).

        Parameters
        ----------
        reference : ndarray (n_steps, n_zones) [C]
            Temperature to reach at the end of each step (rows = steps labelled by their start,
            columns = ``zones``). Must be finite.
        zones : sequence of str or int, optional
            Tracked zones (names or indices into ``building.zones``); default all zones.
        method : {"inverse", "pid"}
            "inverse": the heat of each step that puts the zone temperature exactly on the
            reference at the end of the step (one linear solve per step; exact up to the
            network's lagged explicit corrections, which are evaluated at the start of the step).
            "pid": a discrete PID per zone on the error between the reference of the step and
            the model temperature at the end of the previous step, as in a co-simulation.
        feedback : {"air", "operative"}, float or ndarray (n_zones,)
            The sensor model, the tracked model temperature ``w T_air + (1 - w) T_surf``
            (``T_surf`` the area-weighted interior surface temperature): "air" (``w = 1``),
            "operative" (``w = 0.5``) or the air weight ``w`` [-] in ``[0, 1]``, one or per zone.
        radiant_fraction : float or ndarray (n_zones,) [-]
            Where the identified heat goes: ``1 - f`` into the zone air, ``f`` over the zone's
            surfaces as radiant internal gains are distributed (area x thermal absorptance,
            :func:`~thermocal.multizone.network.radiant_gain_shares`); one or per zone, in
            ``[0, 1]``. 0 (default): all into the air.
        pid : tuple of three ndarray (n_zones,), optional
            Controller-canonical coefficients per zone ``(D, C1, C2) = (KP + KI + KD, KI - KD,
            KD)`` with discrete gains [W/K] (see :mod:`thermocal.identification.pid`); required
            for ``method="pid"``.
        limits : tuple of two ndarray (n_zones,), optional [W]
            Lower and upper limit of the PID output (conditional integration while limited);
            None = unlimited. Ignored by the inverse.
        heat_input : DataFrame or ndarray, optional [W]
            Known heat per zone and step (as in :meth:`run`), added before the identified heat.
        progress : bool
            Show a progress bar.

        Returns
        -------
        TrackingResult
        """
        net = self.network
        nz = len(net.zone_names)
        n_steps = len(self.times)
        tracked = self._zone_indices(zones)
        nt = len(tracked)
        reference = np.ascontiguousarray(reference, dtype=float)
        if reference.shape != (n_steps, nt):
            raise ThermocalInputError(
                f"track: reference must have shape (n_steps, n_zones) = ({n_steps}, {nt}), got "
                f"{reference.shape}"
            )
        if not np.isfinite(reference).all():
            raise ThermocalInputError("track: the reference contains NaN or infinite values")
        if method not in ("inverse", "pid"):
            raise ThermocalInputError(f"track: method must be 'inverse' or 'pid', got {method!r}")
        form = _tracking_form(feedback, radiant_fraction, nt)
        if method == "pid":
            if pid is None:
                raise ThermocalInputError("track: method='pid' needs the controller coefficients")
            pid = tuple(np.ascontiguousarray(np.broadcast_to(c, nt), dtype=float) for c in pid)
        else:
            pid = (np.zeros(nt), np.zeros(nt), np.zeros(nt))
        if limits is None:
            q_low, q_high = np.full(nt, -np.inf), np.full(nt, np.inf)
        else:
            q_low = np.ascontiguousarray(np.broadcast_to(limits[0], nt), dtype=float)
            q_high = np.ascontiguousarray(np.broadcast_to(limits[1], nt), dtype=float)
            if np.any(q_low > q_high):
                raise ThermocalInputError("track: a lower heat limit exceeds its upper limit")
        heat = self._heat_array(heat_input, n_steps, nz)
        self._x = np.full(net.n_nodes, self.initial_temperature)
        self._face_root = np.ones(len(net.face_node))
        self._reset_ideal_state()
        self._k = 0
        fine, g_fine, distribution = self._tracking_context(tracked, form, coarse=False)
        state = {
            "zones": tracked,
            "dummy_sp": np.zeros((1, nt)),
            "general": g_fine.shape[0] > 0,
            "w_air": np.asarray(form[0], dtype=float),
            "distribution": distribution,
            "pid": pid,
            "pid_state": np.zeros((nt, 2)),
            "feedback": reference[0].copy(),
            "q_low": q_low,
            "q_high": q_high,
        }
        q0 = np.zeros(nt)
        if self.warmup_days > 0:
            q0 = self._warm_up_tracking(tracked, form, reference, state)
        if method == "pid":
            ki = pid[1] + pid[2]  # C1 + C2 = KI
            start = np.divide(np.clip(q0, q_low, q_high), ki, out=np.zeros(nt), where=ki > 0)
            state["pid_state"][:, 0] = start
            state["pid_state"][:, 1] = start
        air = np.empty((n_steps, nz))
        mrt = np.empty((n_steps, nz))
        q = np.empty((n_steps, nt))
        bar = _progress(progress, n_steps)
        try:
            for k0 in range(0, n_steps, _CHUNK):
                n = min(_CHUNK, n_steps - k0)
                state.update(
                    mode=1 if method == "inverse" else 2,
                    reference=reference[k0 : k0 + n],
                    g_inverse=g_fine,
                    out_q=np.empty((n, nt)),
                )
                out = self._advance(
                    k0,
                    n,
                    heat[k0 : k0 + n],
                    ideal=False,
                    store=False,
                    context=fine,
                    tracking=state,
                )
                air[k0 : k0 + n] = out[0]
                mrt[k0 : k0 + n] = out[1]
                q[k0 : k0 + n] = state["out_q"]
                if bar is not None:
                    bar[0].update(bar[1], advance=n)
                if not np.isfinite(state["feedback"]).all():
                    air[k0 + n :] = np.nan
                    mrt[k0 + n :] = np.nan
                    q[k0 + n :] = np.nan
                    break
        finally:
            if bar is not None:
                bar[0].stop()
        self._k = n_steps
        weight = np.asarray(form[0], dtype=float)
        diverged = ~np.isfinite(state["feedback"])
        names = [net.zone_names[i] for i in tracked]
        index = self.times
        return TrackingResult(
            air_temperature=pd.DataFrame(air, index=index, columns=net.zone_names),
            operative_temperature=pd.DataFrame(
                0.5 * (air + mrt), index=index, columns=net.zone_names
            ),
            heat=pd.DataFrame(q, index=index, columns=names),
            reference=pd.DataFrame(reference, index=index, columns=names),
            feedback=feedback,
            method=method,
            step=self.step_size,
            diverged=[name for name, bad in zip(names, diverged, strict=True) if bad],
            sensed_temperature=pd.DataFrame(
                weight * air[:, tracked] + (1.0 - weight) * mrt[:, tracked],
                index=index,
                columns=names,
            ),
        )

    def _zone_indices(self, zones) -> np.ndarray:
        names = list(self.building.zones)
        if zones is None:
            return np.arange(len(names), dtype=np.int64)
        out = []
        for zone in zones:
            if isinstance(zone, int | np.integer):
                if not 0 <= int(zone) < len(names):
                    raise ThermocalInputError(f"zone index {zone} outside [0, {len(names)})")
                out.append(int(zone))
            elif zone in self.building.zones:
                out.append(names.index(zone))
            else:
                import difflib

                close = difflib.get_close_matches(str(zone), names, n=3)
                hint = f"; did you mean {', '.join(map(repr, close))}?" if close else ""
                raise ThermocalInputError(
                    f"zone {zone!r} is not a zone of building '{self.building.name}'{hint}"
                )
        if len(set(out)) != len(out):
            raise ThermocalInputError("track: a zone is listed twice")
        return np.asarray(out, dtype=np.int64)

    def _warm_up_tracking(self, tracked, form, reference, state) -> np.ndarray:
        """Track the first day's reference ``warmup_days`` times; the last heat [W]."""
        coarse = self._tracking_context(tracked, form, coarse=True)
        if coarse is None:  # no hourly context: the first day at the fine step
            context, g_inverse, _ = self._tracking_context(tracked, form, coarse=False)
            n_day = min(int(round(86400.0 / self.dt)), len(reference))
            day = reference[:n_day]
        else:
            context, g_inverse, _ = coarse
            per_hour = int(round(3600.0 / self.dt))
            day = _hourly_first_day(reference, 24 * per_hour, per_hour)
            n_day = 24
        nz = len(self.building.zones)
        state.update(mode=1, reference=np.ascontiguousarray(day), g_inverse=g_inverse)
        for _ in range(self.warmup_days):
            state["out_q"] = np.empty((n_day, len(tracked)))
            self._advance(
                0,
                n_day,
                np.zeros((n_day, nz)),
                ideal=False,
                store=False,
                context=context,
                tracking=state,
            )
        return state["out_q"][-1].copy()

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
        else:
            self._x = np.full(self.network.n_nodes, self.initial_temperature)
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
        self._x = np.full(net.n_nodes, self.initial_temperature)
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

    def _heat_array(self, heat_input, n_steps: int, nz: int) -> np.ndarray:
        if heat_input is None:
            return np.zeros((n_steps, nz))
        if isinstance(heat_input, pd.DataFrame):
            unknown = [c for c in heat_input.columns if c not in self.building.zones]
            if unknown:
                raise ThermocalInputError(
                    f"heat_input: columns {unknown} are not zones of building "
                    f"'{self.building.name}'"
                )
            frame = heat_input.reindex(columns=list(self.building.zones), fill_value=0.0)
            if len(frame) != n_steps:
                raise ThermocalInputError(
                    f"heat_input has {len(frame)} rows but the period has {n_steps} steps"
                )
            values = frame.to_numpy(dtype=float)
        else:
            values = np.asarray(heat_input, dtype=float)
            if values.shape != (n_steps, nz):
                raise ThermocalInputError(
                    f"heat_input must have shape (n_steps, n_zones) = ({n_steps}, {nz}), got "
                    f"{values.shape}"
                )
        if not np.isfinite(values).all():
            raise ThermocalInputError("heat_input contains NaN or infinite values")
        return values

    def _result(self, air, mrt, heating, cooling, heat, faces) -> SimulationResult:
        net = self.network
        index = self.times
        zones = net.zone_names

        def frame(values):
            return pd.DataFrame(values, index=index, columns=zones)

        transmitted = np.asarray(net.zone_transmitted @ self._inputs.T).T
        t_out = self._inputs[:, IN_TEMP_OUT]
        conductance = net.zone_infiltration[None, :] + self._inf_dh
        if len(self._inf_dt):
            conductance = conductance + self._inf_dt * np.abs(t_out[:, None] - air)
        zone, g, gdt, _, _, _, _, opened = self._vent
        if len(zone):
            # indoor-limited ventilation as the time loop switched it
            extra = opened * g
            if len(gdt):
                extra = extra + opened * gdt * np.abs(t_out[:, None] - air[:, zone])
            conductance = conductance.copy()
            np.add.at(conductance.T, zone, extra.T)
        infiltration = conductance * (t_out[:, None] - air)
        return SimulationResult(
            air_temperature=frame(air),
            operative_temperature=frame(0.5 * (air + mrt)),
            mean_radiant_temperature=frame(mrt),
            heating=frame(heating),
            cooling=frame(cooling),
            heat_input=frame(heat),
            transmitted_solar=frame(transmitted),
            infiltration=frame(infiltration),
            surface_temperature=None
            if faces is None
            else pd.DataFrame(faces, index=index, columns=net.face_names),
            step=self.step_size,
            approximations=self.approximations(),
        )

    def approximations(self) -> list[str]:
        """What the IDF import (and this run) flattened, skipped or replaced, one line each."""
        info = self._idf_info
        if info is None:
            return []
        out = []
        if info.unsupported:
            out.append(
                "objects not represented (skipped): "
                + ", ".join(f"{cls} ({n})" for cls, n in info.unsupported.items())
            )
        if self._scheduled is not None:
            out.append(
                "schedules applied step by step (set points, internal gains, infiltration); "
                "People sensible heat at the previous step's zone air temperature, clipped to "
                "[0, activity] as EnergyPlus, all of its change with temperature to the zone air"
            )
            out.extend(
                note
                for note in info.notes
                if "schedules='constant'" not in note and "varies" not in note
            )
        else:
            out.extend(info.notes)
        out.extend(self._convection_notes)
        if self.weather_interpolation == "energyplus":
            out.append(
                "hourly weather interpolated as EnergyPlus (irradiance between hourly values "
                "placed at the half hours); each step forced by the mean of its start and end "
                "values (EnergyPlus takes the end values)"
            )
        else:
            out.append("weather held over each hour (weather_interpolation='hold')")
        shaders = getattr(info, "shading_surfaces", None)
        if shaders:
            if self._shadows is not None:
                out.append(
                    f"{len(shaders)} shading surfaces cast shadows on {len(self._shadows['beam'])} "
                    "windows and surfaces (beam by the sampled sunlit fraction, "
                    + (
                        f"updated every {info.shadow_update_days} days as EnergyPlus' "
                        "ShadowCalculation; "
                        if info.shadow_update_days
                        else "every step; "
                    )
                    + "sky diffuse as EnergyPlus: its circumsolar part like the beam, the dome "
                    "and the horizon band by their unshaded views; ground-reflected not shaded)"
                    + (
                        ", the building's own surfaces among them"
                        if any("(building surface)" in str(s.name) for s in shaders)
                        else "; the building's own surfaces cast no shadows"
                    )
                )
            elif not self.shading:
                out.append(f"{len(shaders)} shading surfaces ignored (shading=False)")
        return out


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


def _tracking_form(feedback, radiant_fraction, n_tracked: int) -> tuple:
    """``(air_weight, radiant_fraction)`` tuples over the tracked zones, validated."""
    if isinstance(feedback, str):
        if feedback not in ("air", "operative"):
            raise ThermocalInputError(
                f"track: feedback must be 'air', 'operative' or an air weight in [0, 1], got "
                f"{feedback!r}"
            )
        feedback = 1.0 if feedback == "air" else 0.5
    out = []
    for name, value in (("feedback air weight", feedback), ("radiant_fraction", radiant_fraction)):
        try:
            array = np.broadcast_to(np.asarray(value, dtype=float), n_tracked)
        except (TypeError, ValueError):
            raise ThermocalInputError(
                f"track: {name} must be a number or one per tracked zone ({n_tracked}), got "
                f"{value!r}"
            ) from None
        if not np.all((array >= 0.0) & (array <= 1.0)):
            raise ThermocalInputError(f"track: {name} must lie in [0, 1], got {value!r}")
        out.append(tuple(float(v) for v in array))
    return tuple(out)


_NO_IMPLICIT = (np.zeros(0, dtype=np.int64), np.zeros((0, 0)), np.zeros(1), np.zeros((0, 0)))
_NO_VENT = (np.zeros(0, dtype=np.int64),) + (np.zeros((0, 0)),) * 7
_NO_TRACKED_AIR = (
    np.zeros(0, dtype=np.int64),
    np.zeros((0, 0)),
    np.zeros((0, 0)),
    np.zeros((0, 0)),
    np.zeros(1),
    np.zeros((0, 0)),
)


def _no_tracking(n: int) -> dict:
    """Kernel arguments of the tracking modes when no zone is tracked."""
    empty = np.zeros(0)
    return {
        "mode": 0,
        "reference": np.zeros((n, 0)),
        "general": False,
        "w_air": np.zeros(0),
        "distribution": (np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0)),
        "pid": (empty, empty, empty),
        "pid_state": np.zeros((0, 2)),
        "feedback": empty,
        "q_low": empty,
        "q_high": empty,
        "g_inverse": np.zeros((0, 0)),
        "out_q": np.zeros((n, 0)),
    }


def _hourly_first_day(values: np.ndarray, per_day: int, per_hour: int) -> np.ndarray:
    """Hourly means of the first day of a per-step array (rows = steps)."""
    first = values[:per_day]
    return first.reshape(24, per_hour, *first.shape[1:]).mean(axis=1)


def _factorise(matrix):
    """Sparse LU with a symmetric minimum-degree ordering (the matrices are symmetric M-matrices,
    so diagonal pivots are safe and the fill stays minimal)."""
    return splu(
        matrix,
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )


def _progress(enabled: bool, total: int):
    if not enabled:
        return None
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    bar = Progress(
        TextColumn("simulating"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeRemainingColumn(),
    )
    bar.start()
    task = bar.add_task("simulate", total=total)
    return bar, task


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
    temperature (``ground_at_outdoor=True``) or ground at the indoor temperature (``False``: ground
    losses excluded), unconditioned zones floating. Interior coefficients as in the simulation
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
