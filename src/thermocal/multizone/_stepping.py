"""The time loop of a run: one call of the compiled kernel over a block of steps, the warm-up
that repeats the first day, and the refusal of a diverged run.

A part of :class:`thermocal.multizone.simulation.Simulation`, which inherits it; the methods
work on the simulation's state (the network, the state vector ``_x``, the prepared contexts).
"""

from __future__ import annotations

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone import _kernel
from thermocal.multizone._simtools import (
    _NO_IMPLICIT,
    _NO_TRACKED_AIR,
    _NO_VENT,
    _Context,
    _no_tracking,
    kernel_array,
)
from thermocal.multizone.network import WINDOW_TEMPERATURE_GRID


def _daily_extremes(air: np.ndarray) -> np.ndarray:
    """Each zone's maximum and minimum air temperature of a day [C] (steps x zones in)."""
    return np.concatenate([air.max(axis=0), air.min(axis=0)])

#: kernel arrays of a dry run (see the rain arguments of _kernel.run_steps)
_NO_RAIN = (
    np.zeros(0, dtype=np.uint8),
    np.zeros(0),
    np.zeros(0, dtype=np.int64),
    np.zeros(0, dtype=np.int64),
    np.zeros(0),
    np.zeros(0),
    np.zeros((0, 0)),
    np.zeros(0),
)


class Stepping:
    """The time loop (part of :class:`~thermocal.multizone.simulation.Simulation`)."""

    def _warm_up(self, *, ideal: bool) -> None:
        """Repeat the period's first day (hourly steps when possible) ``warmup_days`` times.

        A building imported from an IDF file warms up as EnergyPlus does with that file: the
        first day is repeated until no zone's daily maximum and minimum air temperature changes
        by more than the ``Building`` object's Temperature Convergence Tolerance Value between
        two repetitions, at least ``warmup_days`` and at most its Maximum Number of Warmup Days
        times (``IdfImportInfo.warmup``; EnergyPlus' defaults 0.4 K and 25 days). A room with a
        long time constant (a heavy room losing only through an insulated roof: ten days and
        more) is far from its periodic state after a week, and EnergyPlus' state is then the
        one its rule leaves: on a DOE prototype's top-floor storage rooms the fixed week left
        them 14 K warmer than EnergyPlus'. ``self.warmup_days_run`` holds the count.
        """
        context = self._coarse_context() or self._fine
        n_day = min(int(round(86400.0 / context.dt)), len(context.inputs))
        zeros = np.zeros((n_day, len(self.building.zones)))
        rule = getattr(getattr(self.building, "idf_info", None), "warmup", None)
        tolerance = None if rule is None else float(rule["tolerance_K"])
        most = self.warmup_days if rule is None else max(self.warmup_days, rule["maximum_days"])
        previous = None
        self.warmup_days_run = 0
        for day in range(most):
            air = self._advance(0, n_day, zeros, ideal=ideal, store=False, context=context)[0]
            self.warmup_days_run = day + 1
            if tolerance is None:
                continue
            extremes = _daily_extremes(air)
            settled = previous is not None and np.max(np.abs(extremes - previous)) <= tolerance
            if day + 1 >= self.warmup_days and (settled or not np.isfinite(extremes).all()):
                break
            previous = extremes

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
        faces = net.ground_faces
        inf_dh = context.inf_dh.zero() if linear else context.inf_dh
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
        # rain on the simulation's own steps (not a coarse warm-up's): a free run, the PID and
        # the exact air inverse (the tracked air held); ideal loads and the general inverse (a
        # radiant share or an operative sensor) with the free system's response of the wet
        # faces, the step's heat not fed back into them (their 1000 W/(m2 K) pins them)
        if len(self._rain_flags) and not linear and context.dt == self.dt:
            rain = (self._rain_flags, self._t_wb, *self._wet_arrays(context, dirichlet_first))
        else:
            rain = _NO_RAIN
        # a diverging step gives non-finite temperatures (numpy's error model in the kernel)
        _kernel.run_steps(
            k0,
            n,
            self._x,
            context.c_dt,
            *self._b,
            context.inputs,
            kernel_array(heat),
            *context.factors,
            net.ext_node,
            self._ext_area_eps,
            net.ext_view_air,
            net.ext_view_sky,
            net.ext_hr0,
            ext_dh,
            self._ext_class,
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
            net.face_iso,
            float(self._pressure),
            net.air_node,
            *inf_dh,
            np.zeros((0, nz)) if linear else context.inf_dt,
            np.zeros((0, nz)) if linear else context.people_a,
            np.zeros((0, nz)) if linear else context.people_b,
            np.zeros((0, nz)) if linear else context.people_c,
            np.zeros((0, nz)) if linear else context.people_max,
            self._people_face_w,
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
            # the Dirichlet system prescribes air temperatures: not for an operative thermostat
            len(self._ctrl) > 0 and self.use_dirichlet and bool(np.all(self._ctrl_w_air == 1.0)),
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
            # the sensed temperature's air weight; in a run, the held temperature's
            self._ctrl_w_air if tracking is None else track["w_air"],
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
            *rain,
            faces.column,
            self._gf_class,
            faces.out_ptr,
            faces.out_idx,
            faces.out_val,
            faces.u_ptr,
            faces.u_idx,
            faces.u_val,
            faces.emissivity,
            1.0 - faces.view_sky,
            faces.view_sky,
            faces.hr0,
            self.options.exact_sky_longwave and not linear,
        )
        if tracking is None:  # a diverging tracking loop is marked and handled by its caller
            self._diverged(k0, n, out_air)
        return out_air, out_mrt, out_heat, out_cool, out_face

    def _diverged(self, k0: int, n: int, air) -> None:
        """Refuse a run whose temperatures became NaN or infinite (an unstable step)."""
        bad = ~np.isfinite(air)
        if not bad.any():
            return
        zones = [self.network.zone_names[z] for z in np.flatnonzero(bad.any(axis=0))]
        raise ThermocalInputError(
            f"the simulation diverged between steps {k0} and {k0 + n} "
            f"({self.times[min(k0, len(self.times) - 1)]} onwards) in zone(s) "
            f"{', '.join(repr(z) for z in zones[:5])}: the step ({self.step_size}) is too long "
            "for these zones' air capacity and gains; use a shorter step (e.g. '15min' or "
            "'5min') or check the zone's volume and gains"
        )
