"""The identified heat alone: the tracking loop of :meth:`Simulation.track` without its result
frames, for calibration campaigns (issue 22).

A campaign sample only needs the heat of the tracked zones; :meth:`Simulation.track` also
returns the air, operative, reference and sensed temperatures as month-long data frames (on the
clinic, 5 frames of 8,928 x 186 values, ~0.1 s a sample). Both run the one tracking loop here
(:meth:`TrackedHeat._tracking_loop`); :meth:`TrackedHeat.track_heat` keeps only its heat,
:meth:`Simulation.track` builds the frames from it (the heat bit-identical, tested for every
mode in ``tests/multizone/test_multizone_track_heat.py``).

A part of :class:`thermocal.multizone.simulation.Simulation`, which inherits it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone._simtools import _progress, _tracking_form, kernel_array
from thermocal.multizone._tracking import _chunks, _radiant_rows


class IdentifiedHeat(NamedTuple):
    """The result of :meth:`TrackedHeat.track_heat`.

    Attributes
    ----------
    heat : ndarray (n_steps, n_tracked) [W]
        Heat delivered to each tracked zone over each step, as ``TrackingResult.heat``.
    zones : list of str
        The tracked zones (the columns of ``heat``).
    diverged : list of str
        Zones whose loop diverged (the run stopped there; the rest of ``heat`` is NaN).
    """

    heat: np.ndarray
    zones: list
    diverged: list


class TrackingLoop(NamedTuple):
    """What the tracking run leaves (:meth:`TrackedHeat._tracking_loop`).

    Attributes
    ----------
    heat : ndarray (n_steps, n_tracked) [W]
    air, mrt : ndarray (n_steps, n_zones) or None
        Every zone's air and mean radiant temperature [C] (None without ``temperatures``).
    tracked : ndarray of int
        Indices of the tracked zones.
    names : list of str
        Their names.
    air_weight : ndarray (n_tracked,)
        The sensor's air weight ``w`` [-].
    reference : ndarray (n_steps, n_tracked) [C]
    diverged : list of str
    """

    heat: np.ndarray
    air: np.ndarray | None
    mrt: np.ndarray | None
    tracked: np.ndarray
    names: list
    air_weight: np.ndarray
    reference: np.ndarray
    diverged: list


class TrackedHeat:
    """The identified heat alone (part of :class:`~thermocal.multizone.simulation.Simulation`)."""

    def track_heat(
        self,
        reference: np.ndarray,
        *,
        zones=None,
        method: str = "inverse",
        feedback="air",
        radiant_fraction=0.0,
        pid: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
        limits: tuple[np.ndarray, np.ndarray] | None = None,
        heat_input=None,
    ) -> IdentifiedHeat:
        """The heat of :meth:`track` without its temperature frames.

        Parameters
        ----------
        reference : ndarray (n_steps, n_zones) [C]
        zones : sequence of str or int, optional
        method : {"inverse", "pid"}
        feedback : {"air", "operative"}, float or ndarray (n_zones,)
        radiant_fraction : float, ndarray (n_zones,) or ndarray (n_steps, n_zones) [-]
        pid : tuple of three ndarray (n_zones,), optional
        limits : tuple of two ndarray (n_zones,), optional [W]
        heat_input : DataFrame or ndarray, optional [W]
            As in :meth:`track`.

        Returns
        -------
        IdentifiedHeat
            The heat [W] (bit-identical to ``track(...).heat``), the tracked zones and the
            diverged ones.
        """
        loop = self._tracking_loop(
            reference, zones=zones, method=method, feedback=feedback,
            radiant_fraction=radiant_fraction, pid=pid, limits=limits, heat_input=heat_input,
            temperatures=False,
        )  # fmt: skip
        return IdentifiedHeat(heat=loop.heat, zones=loop.names, diverged=loop.diverged)

    def _tracking_loop(
        self,
        reference: np.ndarray,
        *,
        zones=None,
        method: str = "inverse",
        feedback="air",
        radiant_fraction=0.0,
        pid=None,
        limits=None,
        heat_input=None,
        temperatures: bool = True,
        progress: bool = False,
    ) -> TrackingLoop:
        """The tracking run of :meth:`track` and :meth:`track_heat` (one implementation):
        arguments as :meth:`track`; ``temperatures``: also keep every zone's air and mean
        radiant temperature per step (what :meth:`track`'s frames need)."""
        net = self.network
        nz = len(net.zone_names)
        n_steps = len(self.times)
        tracked = self._zone_indices(zones)
        nt = len(tracked)
        reference = kernel_array(reference)
        if reference.shape != (n_steps, nt):
            raise ThermocalInputError(
                f"track: reference must have shape (n_steps, n_zones) = ({n_steps}, {nt}), got "
                f"{reference.shape}"
            )
        if not np.isfinite(reference).all():
            raise ThermocalInputError("track: the reference contains NaN or infinite values")
        if method not in ("inverse", "pid"):
            raise ThermocalInputError(f"track: method must be 'inverse' or 'pid', got {method!r}")
        rows, starts = _radiant_rows(radiant_fraction, n_steps, nt)
        form = _tracking_form(feedback, rows.mean(axis=0) if starts else radiant_fraction, nt)
        pid = _pid_coefficients(method, pid, nt)
        q_low, q_high = _heat_limits(limits, nt)
        heat = self._heat_array(heat_input, n_steps, nz)
        self._x = self._initial_state(self.initial_temperature)
        self._face_root = np.ones(len(net.face_node))
        self._reset_ideal_state()
        self._k = 0
        fine, g_fine, distribution = self._tracking_context(tracked, form, coarse=False)
        # pieces of constant form: (first step, its form), in step order
        pieces = [(0, form)]
        if starts:
            pieces = [(k, (form[0], tuple(float(v) for v in rows[k]))) for k in starts]
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
        q = np.empty((n_steps, nt))
        air = np.empty((n_steps, nz)) if temperatures else None
        mrt = np.empty((n_steps, nz)) if temperatures else None
        bar = _progress(progress, n_steps)
        bounds = [k for k, _ in pieces[1:]] + [n_steps]
        try:
            for k0, n, piece in _chunks(bounds, n_steps):
                if len(pieces) > 1:
                    fine, g_fine, distribution = self._tracking_context(
                        tracked, pieces[piece][1], coarse=False
                    )
                    state.update(general=g_fine.shape[0] > 0, distribution=distribution)
                state.update(
                    mode=1 if method == "inverse" else 2,
                    reference=reference[k0 : k0 + n],
                    g_inverse=g_fine,
                    out_q=q[k0 : k0 + n],
                )
                out = self._advance(
                    k0, n, heat[k0 : k0 + n], ideal=False, store=False, context=fine,
                    tracking=state,
                )  # fmt: skip
                if temperatures:
                    air[k0 : k0 + n] = out[0]
                    mrt[k0 : k0 + n] = out[1]
                if bar is not None:
                    bar[0].update(bar[1], advance=n)
                if not np.isfinite(state["feedback"]).all():
                    q[k0 + n :] = np.nan
                    if temperatures:
                        air[k0 + n :] = np.nan
                        mrt[k0 + n :] = np.nan
                    break
        finally:
            if bar is not None:
                bar[0].stop()
        self._k = n_steps
        names = [net.zone_names[i] for i in tracked]
        bad = ~np.isfinite(state["feedback"])
        return TrackingLoop(
            heat=q, air=air, mrt=mrt, tracked=tracked, names=names,
            air_weight=np.asarray(form[0], dtype=float), reference=reference,
            diverged=[name for name, b in zip(names, bad, strict=True) if b],
        )  # fmt: skip

def _pid_coefficients(method: str, pid, n_tracked: int) -> tuple:
    """The PID's controller-canonical coefficients per tracked zone ``(D, C1, C2)`` [W/K]
    (zeros for the inverse), validated as :meth:`Simulation.track` does."""
    if method != "pid":
        return (np.zeros(n_tracked), np.zeros(n_tracked), np.zeros(n_tracked))
    if pid is None:
        raise ThermocalInputError("track: method='pid' needs the controller coefficients")
    return tuple(kernel_array(np.broadcast_to(c, n_tracked)) for c in pid)


def _heat_limits(limits, n_tracked: int) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper limit of each tracked zone's PID output [W] (unlimited when None)."""
    if limits is None:
        return np.full(n_tracked, -np.inf), np.full(n_tracked, np.inf)
    q_low = kernel_array(np.broadcast_to(limits[0], n_tracked))
    q_high = kernel_array(np.broadcast_to(limits[1], n_tracked))
    if np.any(q_low > q_high):
        raise ThermocalInputError("track: a lower heat limit exceeds its upper limit")
    return q_low, q_high
