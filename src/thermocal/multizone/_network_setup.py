"""The network of a run and its factorised step matrices: site, schedules on the grid, the
assembled network, set points, ventilation, and the kernel's context.

A part of :class:`thermocal.multizone.simulation.Simulation`, which inherits it; the methods
work on the simulation's state.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from thermocal.multizone import _kernel
from thermocal.multizone._simtools import (
    _Context,
    _factorise,
    _hourly_first_day,
)
from thermocal.multizone.network import (
    AIR_SPECIFIC_HEAT,
    assemble,
    pressure_at_altitude,
)


class NetworkSetup:
    """The network of a run and its factorised step matrices (part of
    :class:`~thermocal.multizone.simulation.Simulation`).
    """

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
            own_solar_inputs=(frozenset(self._shadows["beam"]) if self._shadows else frozenset())
            | frozenset(self._ground_view_overrides()),
            sky_view_ratio=self._shadows["sky"] if self._shadows else None,
            interior_beam=(
                {w: names for w, (names, *_) in self._interior_beam.items()}
                if self._interior_beam
                else None
            ),
        )
        self._inputs = self._input_matrix()
        self._factorise()

    def _initial_state(self, temperature: float) -> np.ndarray:
        """Node temperatures [C] to start from: ``temperature`` everywhere but in the
        foundations' ground sections, which start from the building's steady state at the
        weather's annual mean air temperature (sky and ground alike), without sun or gains, its
        heated zones at their heating set points (else at ``temperature``) and the others
        floating: an unheated basement's ground starts near the basement's temperature, as
        EnergyPlus's Kiva starts from a steady state (at the conditions of 120 days before the
        start, then three months ahead)."""
        import scipy.sparse.linalg as spla

        net = self.network
        x = np.full(net.n_nodes, float(temperature))
        ground = net.foundation_nodes
        if not len(ground):
            return x
        weather = getattr(self, "_weather", None)
        if weather is not None and "temp_air" in weather and weather["temp_air"].notna().any():
            mean_out = float(np.nanmean(weather["temp_air"]))
        else:
            mean_out = self._mean_tout
        u = np.zeros(len(net.input_names))
        u[:3] = mean_out  # outdoor air, sky and ground temperatures
        u[3] = 1.0  # the constant column
        zones = self.building.zones
        fixed, values = [], []
        for i, name in enumerate(net.zone_names):
            setpoint = zones[name].heating_setpoint if name in zones else None
            if setpoint is not None:
                fixed.append(int(net.air_node[i]))
                values.append(float(setpoint))
        if not fixed:  # nothing heated: the first zone at the given temperature
            fixed, values = [int(net.air_node[0])], [float(temperature)]
        free = np.ones(net.n_nodes, dtype=bool)
        free[fixed] = False
        k = net.conductance.tocsr()
        rhs = net.inputs[free] @ u - k[free][:, fixed] @ np.asarray(values)
        steady = np.empty(net.n_nodes)
        steady[fixed] = values
        steady[free] = spla.spsolve(k[free][:, free].tocsc(), rhs)
        x[ground] = steady[ground]
        return x

    def _ground_view_overrides(self) -> dict[str, float]:
        """Sun-exposed exterior surfaces whose given view factor to the ground departs from
        the tilt's ``(1 - cos)/2``: name -> the given factor. EnergyPlus takes the field for the
        ground-reflected solar (its long-wave follows the tilt, see network.assemble)."""
        import math

        out = {}
        for surface in self.building.surfaces.values():
            vf = surface.view_factor_ground
            if vf is None or surface.boundary != "outdoors" or not surface.sun_exposed:
                continue
            if abs(vf - 0.5 * (1.0 - math.cos(math.radians(surface.tilt)))) > 1e-3:
                out[surface.name] = float(vf)
        return out

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

    def _network_building(self):
        """Building handed to the network: scheduled gains as inputs, infiltration at its mean
        over the run.

        A zone whose scheduled infiltration or gains do not vary over the run keeps the exact
        constant path, at the run's value: the zone's own ``infiltration_ach`` and
        ``internal_gains`` are the file's nominal rate (schedule left out) and annual mean, not
        what the schedules give in the run's days (the outpatient's INFIL_SCH is 0.5 on every
        day but the design days: the nominal rate doubled its infiltration).
        """
        import dataclasses

        if self._scheduled is None:
            return self.building, ()
        info = self._idf_info
        zones = dict(self.building.zones)
        self._inf_scale = np.ones(len(zones))
        names = list(zones)
        for i, name in enumerate(names):
            zone = zones[name]
            nominal = info.zone_nominal_ach.get(zone.name, 0.0)
            if i not in self._inf_zones and nominal <= 0:
                continue  # no outdoor air from the file: the zone's own rate
            # a calibrated infiltration parameter scales the file's rate
            scale = zone.infiltration_ach / nominal if nominal > 0 else 0.0
            self._inf_scale[i] = scale
            mean = float(np.mean(self._scheduled.infiltration_ach[:, i])) * scale
            zones[zone.name] = dataclasses.replace(zone, infiltration_ach=mean)
        for name in self._gain_zones:
            zones[name] = dataclasses.replace(zones[name], internal_gains=0.0)
        filed = {gain.zone for gain in info.internal_gains} | {
            inf.zone for inf in info.infiltration if inf.fan_heat_per_flow > 0
        }
        for i, name in enumerate(names):
            if name in self._gain_zones or name not in filed:
                continue
            convective = float(self._scheduled.gains_convective[0, i])
            radiant = float(self._scheduled.gains_radiant[0, i])
            total = convective + radiant
            zones[name] = dataclasses.replace(
                zones[name],
                internal_gains=total,
                internal_gains_radiative_fraction=(
                    radiant / total if total > 0 else zones[name].internal_gains_radiative_fraction
                ),
            )
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
            # a zone without the schedule keeps its constant value; one whose thermostat's
            # control type varies has none on the steps its control type leaves out
            switched = getattr(self._scheduled, "setpoint_switched", None)
            keep = (
                np.isfinite(heat) if switched is None else np.isfinite(heat) & ~switched[self._ctrl]
            )
            h = np.where(keep & ~np.isfinite(h), heat, h)
            keep = (
                np.isfinite(cool) if switched is None else np.isfinite(cool) & ~switched[self._ctrl]
            )
            c = np.where(keep & ~np.isfinite(c), cool, c)
            # an ideal-loads system switched off by its availability schedules: no set point
            # on those steps (the zone floats, as in EnergyPlus)
            for available, array, off in (
                (getattr(self._scheduled, "heating_available", None), "h", -np.inf),
                (getattr(self._scheduled, "cooling_available", None), "c", np.inf),
            ):
                if available is None or (available.strides == (0, 0) and available.flat[0] > 0):
                    continue  # no schedule, or available on every step
                on = available[:, self._ctrl] > 0.0
                if array == "h":
                    h = np.where(on, np.broadcast_to(h, on.shape), off)
                else:
                    c = np.where(on, np.broadcast_to(c, on.shape), off)
            if (
                np.ptp(np.where(np.isfinite(h), h, 0.0), axis=0).any()
                or np.ptp(np.where(np.isfinite(c), c, 0.0), axis=0).any()
            ):
                heat, cool = h, c
            elif len(h) and not (np.array_equal(h[:1], heat) and np.array_equal(c[:1], cool)):
                # constant over the run but not the zones' constants (the schedules' values in
                # effect most of the year): the run's own values
                heat, cool = h[:1], c[:1]
        return np.ascontiguousarray(heat, dtype=float), np.ascontiguousarray(cool, dtype=float)

    def _factorise(self) -> None:
        net = self.network
        zones = list(self.building.zones.values())
        ctrl = [i for i, z in enumerate(zones) if z.conditioned]
        self._ctrl = np.asarray(ctrl, dtype=np.int64)
        # air weight of each controlled zone's held temperature: 1 (air), 1 - f for an operative
        # thermostat of radiative fraction f (an imported ZoneControl:Thermostat:
        # OperativeTemperature)
        operative = getattr(getattr(self.building, "idf_info", None), "operative_fraction", {})
        self._ctrl_w_air = np.array(
            [1.0 - float(operative.get(zones[i].name, 0.0)) for i in ctrl], dtype=float
        )
        heat_sp = [zones[i].heating_setpoint for i in ctrl]
        cool_sp = [zones[i].cooling_setpoint for i in ctrl]
        self._heat_sp = np.array([-np.inf if t is None else t for t in heat_sp], dtype=float)
        self._cool_sp = np.array([np.inf if t is None else t for t in cool_sp], dtype=float)
        self._heat_sp_steps, self._cool_sp_steps = self._setpoint_arrays(
            self._heat_sp, self._cool_sp
        )
        b = net.inputs.tocsr()
        b.sort_indices()
        # B's entries row by row, each row's in column order (the time loop's one flat loop)
        b_row = np.repeat(np.arange(b.shape[0]), np.diff(b.indptr))
        self._b = (b_row.astype(np.int64), b.indices.astype(np.int64), b.data)
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
        # the building's own thermostats (an operative one holds a mix of air and surfaces); a
        # caller's zones are tracked by their air temperature
        thermostats = controlled is None
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
            response = lu.solve(unit)
            g_ctrl = response[net.air_node[controlled], :]
            w_air = self._ctrl_w_air if thermostats else np.ones(len(controlled))
            for c in np.flatnonzero(w_air < 1.0):
                # an operative thermostat: its held temperature responds as w T_air + (1 - w)
                # T_mrt, T_mrt the zone's area-weighted interior surface temperature
                faces = np.flatnonzero(net.face_zone == controlled[c])
                area = net.face_area[faces]
                mrt = area @ response[net.face_node[faces], :] / area.sum()
                g_ctrl[c] = w_air[c] * g_ctrl[c] + (1.0 - w_air[c]) * mrt
            g_ctrl = np.ascontiguousarray(g_ctrl)
        else:
            g_ctrl = np.zeros((0, 0))
        # explicit-correction bounds (stability of the lagged terms, see network module)
        face_hmax = 2.0 * net.face_h0 + net.face_capacity / dt
        iso = np.flatnonzero(net.face_iso[:, 0] > 0.0) if len(net.face_iso) else []
        if base is not None and base.dt == dt:
            face_hmax = base.face_hmax  # the same system: the same bounds
        elif len(iso):
            # windows with ISO 15099's room side: their massless inner pane is also held by
            # the glass and the long-wave exchange, which 2 h0 leaves out (it clipped a
            # sloped skylight's 3.4-3.8 W/(m2 K) to 2.9); the bound of the step's own system
            face_hmax[iso] = np.maximum(
                face_hmax[iso],
                net.face_h0[iso]
                + LAGGED_FACE_MARGIN
                / (net.face_area[iso] * _lagged_resistance(lu, net, net.face_node[iso], iso)),
            )
        upper = net.ext_hc0 + net.ext_hr0 * net.ext_emissivity + net.ext_capacity / dt
        faces = net.ground_faces
        upper = np.concatenate(
            [upper, faces.hc0 + faces.hr0 * faces.emissivity + faces.capacity / dt]
        )
        # the loop clips each face's excess to [0.1 - hc0, upper] (the series is per class)
        ext_natural = self._ext_natural(upper)
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
            ext_dh=np.ascontiguousarray(ext_dh_raw),
            inf_dh=inf_dh,
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
                self._inf_dh.hourly_first_day(per_day, m),
                **kwargs,
            )
            if kwargs:
                return context
            self._coarse = context
        return self._coarse

    def _reset_ideal_state(self) -> None:
        nc = len(self._ctrl)
        self._active = np.zeros(nc, dtype=np.int64)
        self._cache_member = np.zeros(nc, dtype=np.bool_)
        self._cache_inv = np.zeros((nc, nc))
        # diagnostics: members (-1: invalid), updates since inversion, inversions, rank-one
        # updates, active-set iterations, Dirichlet rejections, superposition calls
        self._cache_m = np.zeros(8, dtype=np.int64)
        self._cache_m[0] = -1


#: Largest decay factor (magnitude) per step of a lagged face-to-air correction at its bound
#: (:func:`_lagged_resistance`).
LAGGED_FACE_MARGIN = 0.5


def _lagged_resistance(lu, net, nodes, faces, chunk: int = 64) -> np.ndarray:
    """Resistance [K/W] between each face node and its zone's air node in the step's system
    ``lu`` (conductances, capacities over the step, boundaries held): ``e^T A^-1 e`` with
    ``e = e_face - e_air``.

    A lagged excess conductance ``g`` between them (the time loop's interior convection beyond
    the matrix part) multiplies their difference's deviation by ``-g R`` each step, so
    ``g <= margin / R`` keeps it decaying (:data:`LAGGED_FACE_MARGIN`).
    """
    nodes = np.asarray(nodes, dtype=np.int64)
    air = np.asarray(net.air_node, dtype=np.int64)[np.asarray(net.face_zone)[faces]]
    out = np.empty(len(nodes))
    for start in range(0, len(nodes), chunk):
        k = np.arange(start, min(start + chunk, len(nodes)))
        cols = np.arange(len(k))
        e = np.zeros((net.n_nodes, len(k)))
        e[nodes[k], cols] = 1.0
        e[air[k], cols] -= 1.0
        sol = lu.solve(e)
        out[k] = sol[nodes[k], cols] - sol[air[k], cols]
    return np.maximum(out, 1e-12)
