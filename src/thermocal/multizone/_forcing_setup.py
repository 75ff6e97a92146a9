"""The forcing of a run prepared once: shadows and sky-diffuse ratios, where the beam lands inside,
the input matrix, ground temperatures, exterior convection and the people's limits.

A part of :class:`thermocal.multizone.simulation.Simulation`, which inherits it; the methods
work on the simulation's state.
"""

from __future__ import annotations

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone._simtools import OutdoorAirExcess
from thermocal.multizone.forcing import (
    _ground_reflectance,
    _irradiance,
    _period_sun_vectors,
    _sun_position,
    _window_inputs,
    dew_point_temperature,
    rain_steps,
    wet_bulb_temperature,
)
from thermocal.multizone.network import (
    AIR_SPECIFIC_HEAT,
    IN_ONE,
    IN_TEMP_GROUND,
    IN_TEMP_OUT,
    IN_TEMP_SKY,
    KIVA_WALL_SUN,
    air_density,
    exterior_convection,
    mowitt_forced,
)


class ForcingSetup:
    """The forcing of a run prepared once (part of
    :class:`~thermocal.multizone.simulation.Simulation`).
    """

    #: EnergyPlus' convection coefficient of a wet outside face [W/m2K]
    WET_H = 1000.0

    def _rain_setup(self, weather) -> None:
        """Wet steps (``_rain_flags`` (steps,) uint8, empty when no step of the period is wet or
        rain is off) and the outdoor wet bulb of each step ``_t_wb`` [C]."""
        self._rain_flags = np.zeros(0, dtype=np.uint8)
        self._t_wb = np.zeros(0)
        self._rain_source = None
        if not self.rain:
            return
        flags = rain_steps(weather, self._grid, self.step_size, self.weather_interpolation)
        self._rain_source = "none" if flags is None else "weather"
        if flags is None or not flags.any():
            return
        g = self._grid
        t_air = g["temp_air_mean"].to_numpy(dtype=float)
        if "temp_dew" in g:
            dew = g["temp_dew"].to_numpy(dtype=float)
        elif "relative_humidity" in g:
            dew = dew_point_temperature(t_air, g["relative_humidity"].to_numpy(dtype=float))
        else:  # no humidity at all: the wet faces at the dry bulb (said in the run's notes)
            dew = np.full_like(t_air, np.nan)
            self._rain_source = "weather, no humidity"
        if "pressure" in g:
            pressure = g["pressure"].to_numpy(dtype=float)
            pressure = np.where(np.isfinite(pressure), pressure, 101325.0)
        else:
            pressure = np.full_like(t_air, 101325.0)
        t_wb = wet_bulb_temperature(t_air, np.where(np.isfinite(dew), dew, t_air), pressure)
        self._t_wb = np.ascontiguousarray(t_wb)
        self._rain_flags = flags.astype(np.uint8)

    def _wet_arrays(self, context, dirichlet: bool = False) -> tuple:
        """Kernel arrays of the wet faces for ``context`` (cached in it): ``(wet_of, wet_node,
        wet_d, wet_h0a, wet_m, wet_c)``, see :func:`thermocal.multizone._kernel.run_steps`;
        ``dirichlet``: their response with the context's tracked air held (the exact inverse)."""
        key = "wet_dirichlet" if dirichlet else "wet"
        cached = context.implicit.get(key)
        if cached is not None:
            return cached
        factors = context.dirichlet if dirichlet else context.factors
        from thermocal.multizone._kernel_parts import lu_solve

        net = self.network
        n_ext = len(net.ext_node)
        # the faces EnergyPlus wets: wind-exposed ones (NoWind faces have no wind factor)
        idx = np.flatnonzero(np.asarray(net.ext_wind_factor) > 0.0)
        m = len(idx)
        wet_of = np.full(n_ext, -1, dtype=np.int64)
        wet_of[idx] = np.arange(m)
        wet_node = np.ascontiguousarray(net.ext_node[idx], dtype=np.int64)
        hc0 = np.asarray(net.ext_hc0, dtype=float)[idx]
        area = np.asarray(net.ext_area, dtype=float)[idx]
        wet_d = (self.WET_H - hc0) * area
        wet_h0a = hc0 * area
        n = net.n_nodes
        g = np.empty((m, m))
        b = np.zeros(n)
        work = np.empty(n)
        out = np.empty(n)
        for j in range(m):
            b[wet_node[j]] = 1.0
            lu_solve(*factors, b, work, out)
            b[wet_node[j]] = 0.0
            g[:, j] = out[wet_node]
        wet_m = np.linalg.inv(np.eye(m) + g * wet_d[None, :])
        wet_c = wet_m @ (g @ wet_d)
        cached = (
            wet_of,
            wet_node,
            np.ascontiguousarray(wet_d),
            np.ascontiguousarray(wet_h0a),
            np.ascontiguousarray(wet_m),
            np.ascontiguousarray(wet_c),
        )
        context.implicit[key] = cached
        return cached

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
        out = {"beam": {}, "sky": {}, "horizon": {}}
        for name in caster.shaded:
            beam, dome, band = caster.beam_and_sky(name, sun[evaluated], tau_eval, mean_tau)
            out["beam"][name] = beam[inverse]
            out["sky"][name] = dome
            out["horizon"][name] = band
        return out

    def _shadow_suns(self):
        """Sun vectors per step for the shadow calculations, the steps evaluated and, per step,
        the evaluated step that serves it.

        EnergyPlus' "Periodic" shadow calculation (PerformSolarCalculations): one day of sunlit
        fractions serves each period of N days, computed step by step with the sun of the
        period's mean declination (of its sine) and mean equation of time over the period's
        days within the run period; "Timestep" (N = 0): every step its own sun.
        """
        key = (self.times[0], len(self.times), self.dt, self._sun_at_end)
        cached = self.__dict__.get("_shadow_suns_cache")
        if cached is not None and cached[0] == key:
            return cached[1]
        from thermocal.multizone.shading import sun_vectors

        info = self._idf_info
        site = self._site
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
        else:
            position = _sun_position(self._grid.index, site, self._sun_at_end)
            sun = sun_vectors(position["apparent_zenith"], position["azimuth"])
        evaluated, inverse = np.unique(step_index, return_inverse=True)
        self._shadow_suns_cache = (key, (sun, evaluated, inverse))
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
            # nor its host, however far the file's coordinates put the window off its plane
            faces.pop(window.surface, None)
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
            # kept per evaluated step (one day per shadow period); expanded where used
            out[window.name] = (names, np.ascontiguousarray(shares[:, reached]), inverse)
        return out or None

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
        used_windows: set = set()
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
                if len(key) == 3:  # a shaded receiver, or a given view factor to the ground
                    source = irr[key[:2]]
                    if self._shadows and key[2] in self._shadows["beam"]:
                        source = self._shaded(source, key[2])
                    u[:, col] = self._ground_viewed(source, key, grid)["poa_global"]
                else:
                    u[:, col] = irr[key]["poa_global"]
            for wkey, cols in net.window_inputs.items():
                wt_name, tilt, az = wkey[:3]
                wt = self.building.window_types[wt_name]
                key = ("window", wt_name, wt.shgc, wt.solar_transmittance, *wkey[1:])
                used_windows.add(key)
                if key not in self._input_cache:
                    source = irr[(tilt, az)]
                    if len(wkey) == 4:
                        source = self._shaded(source, wkey[3])
                    self._input_cache[key] = _window_inputs(wt, source, n_steps)
                for col, values in zip(cols, self._input_cache[key], strict=True):
                    u[:, col] = values
        _drop_unused(self._input_cache, "window", used_windows)
        if KIVA_WALL_SUN in net.input_names:
            # a foundation wall above the grade: Kiva's two-dimensional wall sees the beam on a
            # vertical cylinder, half the sky and half the grade's reflection
            # (Ground::setBoundaryConditions, the grade's absorptance Kiva's default)
            from thermocal.multizone.foundation import GRADE_ABSORPTANCE

            horizontal = self._irradiance_cache[(0.0, 0.0)]
            beam_h = np.nan_to_num(np.asarray(horizontal["poa_direct"], dtype=float))
            diffuse_h = np.nan_to_num(np.asarray(horizontal["poa_sky_diffuse"], dtype=float))
            dni = np.nan_to_num(grid["dni"].to_numpy(dtype=float))
            beam_cylinder = np.sqrt(np.maximum(dni**2 - beam_h**2, 0.0)) / np.pi
            beam_cylinder[beam_h <= 0.0] = 0.0
            global_h = beam_h + diffuse_h
            wall_sun = beam_cylinder + 0.5 * diffuse_h + 0.5 * (1.0 - GRADE_ABSORPTANCE) * global_h
            wall_sun[global_h <= 0.0] = 0.0
            u[:, net.input_names.index(KIVA_WALL_SUN)] = wall_sun
        interior = []
        for window, (beam_col, area, targets) in net.window_beam_targets.items():
            names, shares, step_row = self._interior_beam[window]
            # transmitted beam [W] landing on each face, all faces of the window in one block
            # (the same products as face by face: (beam x area) x share)
            cols = [col for _, col in targets]
            beam = u[:, beam_col] * area
            landing = shares[:, [names.index(face) for face, _ in targets]][step_row]
            u[:, cols] = beam[:, None] * landing
            interior.extend(cols)
        if self.weather_interpolation == "energyplus":
            # rows hold the curve at each step's end: the step is forced by the mean of its start
            # and end values (the first step keeps its end value)
            weather_driven = [IN_TEMP_OUT, IN_TEMP_SKY, *net.orientation_inputs.values()]
            if KIVA_WALL_SUN in net.input_names:
                weather_driven.append(net.input_names.index(KIVA_WALL_SUN))
            weather_driven += [col for cols in net.window_inputs.values() for col in cols]
            weather_driven += interior
            # the mean over all columns, copied into the weather-driven ones: the same values
            # as gathering and scattering those columns (ten times slower on a large building)
            driven = np.zeros(u.shape[1], dtype=bool)
            driven[weather_driven] = True
            mean = u[1:] + u[:-1]
            mean *= 0.5
            np.copyto(u[1:], mean, where=driven[None, :])
            del mean
            t_out = u[:, IN_TEMP_OUT]
        # explicit corrections: exterior convection (wind) and infiltration air density
        key = ("doe2", tuple(net.ext_names))
        if key not in self._input_cache:
            self._input_cache[key] = self._exterior_convection_excess()
        self._ext_dh_raw, self._ext_class = self._input_cache[key]
        faces = net.ground_faces
        if len(faces.column):
            # the foundations' faces: Kiva's forced term at the wind at the grade's roughness
            # height each step, appended as classes of their own (the kernel's gf_class)
            station = grid["wind_speed"].to_numpy() if "wind_speed" in grid else np.zeros(n_steps)
            local = np.nan_to_num(station)[:, None] * faces.wind_factor[None, :]
            forced = np.where(
                faces.leeward_mean[None, :],
                0.5 * (mowitt_forced(local, True) + mowitt_forced(local, False)),
                mowitt_forced(local, True),
            )
            if self.options.exterior_convection == "fixed":
                forced = np.zeros_like(forced)
            self._gf_class = self._ext_dh_raw.shape[1] + np.arange(len(faces.column))
            self._ext_dh_raw = np.ascontiguousarray(np.hstack([self._ext_dh_raw, forced]))
        else:
            self._gf_class = np.zeros(0, dtype=np.int64)
        pressure = grid["pressure"].to_numpy() if "pressure" in grid else None
        if pressure is None or not np.isfinite(pressure).all():
            pressure = np.full(n_steps, self._pressure)
        rho = air_density(pressure, t_out)
        ratio = rho / net.reference_density - 1.0
        n_zones = len(net.zone_names)
        inf_column = np.full(n_zones, -1, dtype=np.int64)
        inf_scheduled = np.zeros((n_steps, 0))
        self._inf_dt = np.zeros((0, len(net.zone_names)))
        self._people = (np.zeros((0, len(net.zone_names))),) * 4
        self._people_face_w = np.zeros(len(net.face_node))
        scheduled = self._scheduled
        if scheduled is not None:
            if scheduled.people_per_kelvin is not None and np.any(scheduled.people_per_kelvin):
                # People's sensible heat at the zone temperature (lagged), beyond its 22 C value,
                # clipped to [0, activity] in the time loop
                people_a, people_max, people_radiant = self._people_limits()
                self._people_face_w = np.ascontiguousarray(
                    people_radiant[net.face_zone] * net.face_radiant_share
                )
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
                inf_column[zones] = np.arange(len(zones))
                inf_scheduled = (
                    rho[:, None] * per_ach[zones] * ach - net.zone_infiltration[zones][None, :]
                )
                ach_dt = scheduled.infiltration_ach_per_kelvin * self._inf_scale[None, :]
                if np.any(ach_dt):
                    self._inf_dt = np.ascontiguousarray(rho[:, None] * per_ach[None, :] * ach_dt)
        self._inf_dh = OutdoorAirExcess(
            np.ascontiguousarray(ratio),
            np.ascontiguousarray(net.zone_infiltration, dtype=float),
            inf_column,
            np.ascontiguousarray(inf_scheduled),
        )
        self._vent = self._ventilation_arrays(rho, n_steps)
        return u

    def _ground_viewed(self, irradiance: dict, key, grid) -> dict:
        """The ground-reflected part with the surface's given view factor to the ground
        (EnergyPlus: ground solar x 'View Factor to Ground'), when it has one."""
        if "_vf_overrides" not in self.__dict__:
            self._vf_overrides = self._ground_view_overrides()
        overrides = self._vf_overrides
        name = key[2]
        if name not in overrides:
            return irradiance
        tilt = float(key[0])
        vf_tilt = 0.5 * (1.0 - np.cos(np.radians(tilt)))
        out = dict(irradiance)
        if vf_tilt > 1e-6:
            out["poa_ground_diffuse"] = irradiance["poa_ground_diffuse"] * overrides[name] / vf_tilt
        else:  # a horizontal face given a view of the ground: the ground's reflected sun
            albedo = _ground_reflectance(grid, self.building.ground_reflectance)
            if isinstance(albedo, str):
                albedo = grid["albedo"].fillna(0.2).to_numpy()
            ghi = np.nan_to_num(grid["ghi"].to_numpy())
            out["poa_ground_diffuse"] = ghi * albedo * overrides[name]
        out["poa_global"] = out["poa_direct"] + out["poa_sky_diffuse"] + out["poa_ground_diffuse"]
        return out

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

    def _exterior_convection_excess(self) -> tuple[np.ndarray, np.ndarray]:
        """Wind-driven exterior convection minus its matrix part [W/(m2 K)], one series per class
        of exterior faces that share it, and each face's class.

        Returns ``(series, face_class)``: ``series`` (steps, classes) and ``face_class`` (faces,)
        int64, so that face ``e`` at step ``k`` takes ``series[k, face_class[e]]`` (a month at 5
        minutes of the clinic's faces in one array per face was 24 MiB of a campaign worker).
        """
        net = self.network
        grid = self._grid
        n_steps = len(grid)
        n_ext = len(net.ext_node)
        if self.options.exterior_convection == "fixed" or not n_ext:
            return np.zeros((n_steps, min(n_ext, 1))), np.zeros(n_ext, dtype=np.int64)
        station = grid["wind_speed"].to_numpy() if "wind_speed" in grid else np.zeros(n_steps)
        station = np.nan_to_num(station)
        if self.options.exterior_convection == "simple_combined":
            from thermocal.multizone.network import simple_combined_exterior_coefficient

            # opaque faces: the long-wave part is the network's (all with the outdoor air);
            # windows: all of it convective, their long-wave exchange apart (EnergyPlus)
            radiative = np.where(net.ext_is_window, 0.0, net.ext_hr0 * net.ext_emissivity)
            exposure = np.round(np.stack([net.ext_roughness, net.ext_wind_factor], axis=1), 6)
            classes = np.concatenate([exposure, radiative[:, None], net.ext_hc0[:, None]], axis=1)
            _, first, inverse = np.unique(classes, axis=0, return_index=True, return_inverse=True)
            rough, factor = exposure[first].T
            hc = simple_combined_exterior_coefficient(station[:, None] * factor, rough[None, :])
            hc -= radiative[first][None, :]
            series = np.maximum(hc, 0.0) - net.ext_hc0[first][None, :]
            return np.ascontiguousarray(series), np.ravel(inverse).astype(np.int64)
        if "wind_direction" in grid:
            direction = np.nan_to_num(grid["wind_direction"].to_numpy())
        else:
            direction = np.zeros(n_steps)
        # faces of equal orientation and exposure share the series: one per class
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
        if self.options.exterior_convection == "doe2":
            keys = keys[:, [0, 1, 5]]  # MoWiTT's forced term: orientation and wind speed only
        unique, inverse = np.unique(np.round(keys, 6), axis=0, return_inverse=True)
        face_class = np.ravel(inverse).astype(np.int64)
        if self.options.exterior_convection == "doe2":
            tilt, azimuth, factor = unique.T
        else:
            tilt, azimuth, hc0, h_natural, roughness, factor, p_over_a = unique.T
        # EnergyPlus' Windward(): within 90 degrees of the outward normal, or |cos tilt| >= 0.98
        diff = np.abs((direction[:, None] - azimuth[None, :] + 180.0) % 360.0 - 180.0)
        horizontal = np.abs(np.cos(np.radians(tilt))) >= 0.98
        windward = (diff <= 90.0 + 1e-3) | horizontal[None, :]
        local = station[:, None] * factor[None, :]
        if self.options.exterior_convection == "doe2":
            # the kernel combines it with the natural part at each step's face temperature
            return np.ascontiguousarray(mowitt_forced(local, windward)), face_class
        hc = exterior_convection(
            self.options.exterior_convection,
            local,
            windward,
            h_natural=h_natural[None, :],
            roughness_factor=roughness[None, :],
            perimeter_over_area=p_over_a[None, :],
        )
        if self.options.exterior_convection == "tarp":  # the forced part alone
            return np.ascontiguousarray(hc - h_natural[None, :]), face_class
        return np.ascontiguousarray(hc - hc0[None, :]), face_class

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
        rows = np.stack(
            [
                np.full(n_ext, mode),
                net.ext_roughness,
                np.cos(np.radians(net.ext_tilt)),
                net.ext_hc0,
                upper[:n_ext],
            ],
            axis=1,
        )
        faces = net.ground_faces
        if len(faces.column):
            # then the foundations' faces (the kernel's rows n_ext + g): Kiva's DOE-2 with
            # TARP's natural part at each step's face-to-air difference (a fixed exterior
            # convection: the matrix's constant, the series zero in mode 0)
            gf_mode = 0.0 if self.options.exterior_convection == "fixed" else 1.0
            gf_rows = np.stack(
                [
                    np.full(len(faces.column), gf_mode),
                    faces.roughness,
                    np.cos(np.radians(faces.tilt)),
                    faces.hc0,
                    upper[n_ext:],
                ],
                axis=1,
            )
            rows = np.concatenate([rows, gf_rows])
        return np.ascontiguousarray(rows)

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

    def _people_limits(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Constant term [W] and upper limit [W] of the People sensible heat per zone and step,
        and the radiant fraction [-] of each zone's People sensible heat.

        For People with an autocalculated sensible fraction: ``sum(number x a(activity))`` of
        :func:`~thermocal.multizone.idf.loads.people_sensible_coefficients` and
        ``sum(number x activity)`` (EnergyPlus clips each person's sensible heat to
        ``[0, activity]``; clipping the zone's sum is the same when its People share one activity
        schedule). The radiant fraction is each People object's ``Fraction Radiant`` weighted by
        its mean constant term (exact when a zone's People share one fraction): EnergyPlus
        splits the sensible heat at the zone temperature, not at a reference, into radiant and
        convective parts, so the time loop's temperature correction is split the same way.
        """
        from thermocal.multizone.idf.loads import people_sensible_coefficients

        info = self._idf_info
        names = list(self.building.zones)
        n, nz = len(self.times), len(names)
        constant = np.zeros((n, nz))
        limit = np.zeros((n, nz))
        radiant_weight = np.zeros(nz)
        total_weight = np.zeros(nz)
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
            weight = float(np.mean(gain.people_count * fraction * a))
            radiant_weight[z] += weight * gain.radiant_fraction
            total_weight[z] += weight
        radiant = np.divide(radiant_weight, total_weight, out=np.zeros(nz), where=total_weight > 0)
        return np.ascontiguousarray(constant), np.ascontiguousarray(limit), radiant


def _drop_unused(cache: dict, kind: str, used: set) -> None:
    """Forget the entries of ``kind`` (their keys' first item) that the current network does not
    use: a calibration campaign changes a window's SHGC at every sample, and each value's
    window inputs (4 columns of the period, ~0.3 MB a window orientation on the clinic's month)
    would otherwise stay for the rest of the campaign.

    Parameters
    ----------
    cache : dict
        Keys are tuples whose first item names their kind.
    kind : str
    used : set
        The keys of ``kind`` to keep.
    """
    stale = [key for key in cache if key[0] == kind and key not in used]
    for key in stale:
        del cache[key]
