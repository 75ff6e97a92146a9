"""Tracking measured zone temperatures (the identification's inverse and PID loops): which zones,
how the heat is distributed, the implicit arrays and the tracked run.

A part of :class:`thermocal.multizone.simulation.Simulation`, which inherits it; the methods
work on the simulation's state.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import scipy.sparse as sp

from thermocal.errors import ThermocalInputError
from thermocal.multizone._simtools import (
    _CHUNK,
    _NO_IMPLICIT,
    _Context,
    _hourly_first_day,
)
from thermocal.multizone.results import (
    TrackingResult,
)


class Tracking:
    """Tracking measured zone temperatures (the identification's inverse and PID loops) (part of
    :class:`~thermocal.multizone.simulation.Simulation`).
    """

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
        # the Dirichlet system depends on the tracked zones only: built once, shared by every
        # form (a time-varying radiant fraction asks for one form per distinct row)
        base_key = ("base", key[0], key[2])
        if base_key not in cache:
            if coarse:
                cache[base_key] = self._coarse_context(
                    controlled=zones, ideal=False, base=self._coarse
                )
            else:
                cache[base_key] = self._context(
                    self.dt,
                    self._inputs,
                    self._ext_dh_raw,
                    self._inf_dh,
                    controlled=zones,
                    ideal=False,
                    base=self._fine,
                )
        if cache[base_key] is None:
            cache[key] = None
            return None
        context = dataclasses.replace(cache[base_key], implicit=dict(cache[base_key].implicit))
        air_weight = np.asarray(form[0], dtype=float)
        distribution = self._heat_distribution(zones, np.asarray(form[1], dtype=float))
        g_inverse = np.zeros((0, 0))
        if np.any(air_weight != 1.0) or np.any(np.asarray(form[1]) != 0.0):
            fraction = np.asarray(form[1], dtype=float)[None, :]
            parts = self._tracking_responses(base_key, context, zones)

            def combined(name):
                # the response to a zone's heat is linear in its radiant fraction f: (1 - f) x
                # the response to heat in its air + f x the response to heat on its faces
                return parts[name][0] * (1.0 - fraction) + parts[name][1] * fraction

            w_air = air_weight[:, None]
            sensed = w_air * combined("air") + (1.0 - w_air) * combined("mrt")
            g_inverse = np.ascontiguousarray(np.linalg.inv(sensed))
            # tracked zones with scheduled outdoor air: their air flow in the step it belongs
            # to, solved with the tracking heat (see the kernel's general inverse)
            if parts["held"] is not None:
                held, held_air, held_mrt, held_self = parts["held"]
                a_q = combined("held_rows")
                k_h = g_inverse @ (w_air * held_air + (1.0 - w_air) * held_mrt)
                m_h = held_self - a_q @ k_h
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

    def _tracking_responses(self, base_key: tuple, context, zones: np.ndarray) -> dict:
        """The tracked zones' responses in the Dirichlet system ``context`` (cached with it), from
        which every form of the identified heat is combined without another solve.

        Returns a dict of ``(response to heat in the air, response to heat on the faces)`` pairs
        (zones x zones, the faces' share as the radiant internal gains): ``air`` the zones' air
        temperatures [K/W], ``mrt`` their area-weighted surface temperatures [K/W] (the air's
        where a zone has no faces), ``held_rows`` the air temperatures of the tracked zones with
        scheduled outdoor air; and ``held``: None, or those zones, the air and surface responses
        of the tracked zones to unit heat in their air [K/W] and those zones' own air rows.
        """
        cache = self.__dict__.setdefault("_tracking_cache", {})
        key = ("responses", *base_key[1:])
        if key in cache:
            return cache[key]
        net = self.network
        zones = np.asarray(zones, dtype=np.int64)
        columns = np.arange(len(zones))
        air_unit = np.zeros((net.n_nodes, len(zones)))
        air_unit[net.air_node[zones], columns] = 1.0
        face_unit = air_unit.copy()  # a zone without faces keeps its radiant heat in the air
        for column, zone in enumerate(zones):
            members = np.flatnonzero(net.face_zone == zone)
            if len(members):
                face_unit[net.air_node[zone], column] = 0.0
                np.add.at(face_unit[:, column], net.face_node[members],
                          net.face_radiant_share[members])  # fmt: skip
        weights = sp.csr_matrix(
            (net.face_area, (net.face_zone, net.face_node)),
            shape=(len(net.zone_names), net.n_nodes),
        )[zones]
        area = self._zone_face_area[zones]
        air_nodes = net.air_node[zones]

        def project(response):
            air = response[air_nodes, :]
            mrt = np.asarray(weights @ response)
            mrt = np.where(area[:, None] > 0, mrt / np.where(area > 0, area, 1.0)[:, None], air)
            return air, mrt

        to_air = context.lu.solve(air_unit)
        to_faces = context.lu.solve(face_unit)
        (air0, mrt0), (air1, mrt1) = project(to_air), project(to_faces)
        parts = {"air": (air0, air1), "mrt": (mrt0, mrt1), "held": None}
        inf = {int(z) for z in getattr(self, "_inf_zones", ())}
        held = np.asarray([int(z) for z in zones if int(z) in inf], dtype=np.int64)
        if len(held):
            held_air = net.air_node[held]
            unit = np.zeros((net.n_nodes, len(held)))
            unit[held_air, np.arange(len(held))] = 1.0
            response = context.lu.solve(unit)
            parts["held_rows"] = (to_air[held_air, :], to_faces[held_air, :])
            parts["held"] = (held, *project(response), response[held_air, :])
        cache[key] = parts
        return parts

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
        radiant_fraction : float, ndarray (n_zones,) or ndarray (n_steps, n_zones) [-]
            Where the identified heat goes: ``1 - f`` into the zone air, ``f`` over the zone's
            surfaces as radiant internal gains are distributed (area x thermal absorptance,
            :func:`~thermocal.multizone.network.radiant_gain_shares`); one, per zone, or per
            step and zone (a form that follows the composition of the gains hour by hour, e.g.
            :func:`~thermocal.multizone.idf.loads.declared_radiant_fraction`), in ``[0, 1]``.
            0 (default): all into the air. Per step, the run is split where a row changes (the
            warm-up uses the period's mean row).
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
        loop = self._tracking_loop(
            reference, zones=zones, method=method, feedback=feedback,
            radiant_fraction=radiant_fraction, pid=pid, limits=limits, heat_input=heat_input,
            temperatures=True, progress=progress,
        )  # fmt: skip
        zone_names = self.network.zone_names
        names, air, mrt, weight = loop.names, loop.air, loop.mrt, loop.air_weight
        index = self.times

        def frame(values, columns, own=True):
            # the loop's own arrays become the frames' blocks (no copy); the caller's reference
            # (kept as given when it is already a float array) is copied
            return pd.DataFrame(values, index=index, columns=columns, copy=not own)

        # in place: a month of a large building's (n_steps, n_zones) arrays is ~13 MB each
        sensed = np.take(air, loop.tracked, axis=1)
        sensed *= weight
        radiant = np.take(mrt, loop.tracked, axis=1)
        radiant *= 1.0 - weight
        sensed += radiant
        del radiant
        operative = mrt  # the loop's own array, not used after this
        operative += air
        operative *= 0.5
        return TrackingResult(
            air_temperature=frame(air, zone_names),
            operative_temperature=frame(operative, zone_names),
            heat=frame(loop.heat, names),
            reference=frame(loop.reference, names, own=False),
            feedback=feedback,
            method=method,
            step=self.step_size,
            diverged=loop.diverged,
            sensed_temperature=frame(sensed, names),
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


def _radiant_rows(radiant_fraction, n_steps: int, n_tracked: int) -> tuple[np.ndarray, list]:
    """A per-step radiant fraction ``(n_steps, n_tracked)`` [-], validated, and the steps where
    its row changes (the first included); ``(empty, [])`` for a constant form."""
    if np.ndim(radiant_fraction) != 2:
        return np.zeros((0, n_tracked)), []
    rows = np.asarray(radiant_fraction, dtype=float)
    if rows.shape != (n_steps, n_tracked):
        raise ThermocalInputError(
            f"track: a per-step radiant_fraction must have shape (n_steps, n_zones) = "
            f"({n_steps}, {n_tracked}), got {rows.shape}"
        )
    if not np.all((rows >= 0.0) & (rows <= 1.0)):
        raise ThermocalInputError("track: radiant_fraction must lie in [0, 1] at every step")
    changed = np.flatnonzero(np.any(rows[1:] != rows[:-1], axis=1)) + 1
    return rows, [0, *(int(k) for k in changed)]


def _chunks(bounds: list, n_steps: int):
    """``(first step, steps, piece)`` of the kernel calls: chunks of at most ``_CHUNK`` steps
    that never cross the end of a piece of constant form (``bounds``: each piece's end)."""
    k0, piece = 0, 0
    while k0 < n_steps:
        while bounds[piece] <= k0:
            piece += 1
        n = min(_CHUNK, bounds[piece] - k0)
        yield k0, n, piece
        k0 += n
