"""The ideal heating controller of the demand simulation, compiled (numba).

The discrete matrices come from the grey-box engine
(:func:`thermocal.retrofit.model.discrete_system_matrices`); what is specific to the demand
is the control law: each step the least heat that brings the indoor air to its set point. It
runs for a batch of parameter sets (uncertainty draws x retrofit scenarios) that share one
input sequence, so the annual demand of 16 scenarios x 200 draws is one call. (The plain
simulation of the validation period is :meth:`thermocal.statespace.RCModel.simulate`.)
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, inline="always")
def _ideal_heating_step(ad, bd, b, x, xn, u_k, setpoint_k):  # pragma: no cover - compiled
    """One step of system ``b`` from ``x`` into ``xn``; returns the heating power [W]."""
    ns = x.shape[0]
    ni = u_k.shape[0]  # the heating column is bd[b, :, ni]
    for i in range(ns):
        acc = 0.0
        for j in range(ns):
            acc += ad[b, i, j] * x[j]
        for j in range(ni):
            acc += bd[b, i, j] * u_k[j]
        xn[i] = acc
    q = (setpoint_k - xn[0]) / bd[b, 0, ni]
    if q < 0.0:
        q = 0.0
    for i in range(ns):
        xn[i] += bd[b, i, ni] * q
    return q


@numba.njit(cache=True)
def _ideal_heating(ad, bd, x0, u, setpoint):  # pragma: no cover - compiled
    n, ns, _ = ad.shape
    nk = u.shape[0]
    heat = np.empty((n, nk))
    temp = np.empty((n, nk))
    final = np.empty((n, ns))
    for b in range(n):
        x = x0[b].copy()
        xn = np.empty(ns)
        for k in range(nk):
            heat[b, k] = _ideal_heating_step(ad, bd, b, x, xn, u[k], setpoint[k])
            temp[b, k] = xn[0]
            x, xn = xn, x
        final[b] = x
    return heat, temp, final


def ideal_heating_batch(ad, bd, x0, u, setpoint):
    """Heating-only ideal controller: the least heat that brings ``Ti`` to its set point.

    Over each step the heating power ``Q`` (the last input column of ``bd``) is held constant
    and chosen so that the indoor temperature (state 0) at the end of the step equals the set
    point; when the building floats above it (solar or stored heat), ``Q = 0`` and ``Ti``
    floats. This is the ideal-loads heating of EnergyPlus in discrete time; with constant
    boundary conditions it gives exactly ``Q = HLC (Ti - Te)``.

    Parameters
    ----------
    ad : ndarray (n, ns, ns)
    bd : ndarray (n, ns, ni + 1) last column = heat into the air node [K per W]
    x0 : ndarray (n, ns) [C]
    u : ndarray (nk, ni) the other inputs
    setpoint : ndarray (nk,) [C] indoor temperature at the end of each step

    Returns
    -------
    heat : ndarray (n, nk) [W] mean heating power over each step
    temp_in : ndarray (n, nk) [C] indoor temperature at the end of each step
    final_state : ndarray (n, ns) [C]
    """
    return _ideal_heating(
        np.ascontiguousarray(ad, dtype=float),
        np.ascontiguousarray(bd, dtype=float),
        np.ascontiguousarray(x0, dtype=float),
        np.ascontiguousarray(u, dtype=float),
        np.ascontiguousarray(setpoint, dtype=float),
    )


@numba.njit(cache=True)
def _ideal_heating_states(ad, bd, x0, u, setpoint):  # pragma: no cover - compiled
    ns = x0.shape[0]
    nk = u.shape[0]
    states = np.empty((nk + 1, ns))
    heat = np.empty(nk)
    states[0] = x0
    for k in range(nk):
        heat[k] = _ideal_heating_step(ad, bd, 0, states[k], states[k + 1], u[k], setpoint[k])
    return states, heat


def ideal_heating_states(ad, bd, x0, u, setpoint):
    """:func:`ideal_heating_batch` of one system that keeps every state at every step boundary
    (for a heat balance per path, :func:`thermocal.retrofit.balance.heat_balance`).

    Parameters
    ----------
    ad : ndarray (ns, ns); bd : ndarray (ns, ni + 1), the heating the last column [K per W]
    x0 : ndarray (ns,) [C]
    u : ndarray (nk, ni); setpoint : ndarray (nk,) [C]

    Returns
    -------
    states : ndarray (nk + 1, ns) [C]
    heat : ndarray (nk,) [W] mean heating power over each step
    """
    return _ideal_heating_states(
        np.ascontiguousarray(ad, dtype=float)[None],
        np.ascontiguousarray(bd, dtype=float)[None],
        np.ascontiguousarray(x0, dtype=float),
        np.ascontiguousarray(u, dtype=float),
        np.ascontiguousarray(setpoint, dtype=float),
    )


@numba.njit(cache=True, parallel=True)
def _ideal_heating_binned(ad, bd, x0, u, setpoint, bins, n_bins):  # pragma: no cover
    n, ns, _ = ad.shape
    nk = u.shape[0]
    energy = np.zeros((n, n_bins))
    for b in numba.prange(n):
        x = x0[b].copy()
        xn = np.empty(ns)
        for k in range(nk):
            q = _ideal_heating_step(ad, bd, b, x, xn, u[k], setpoint[k])
            x, xn = xn, x
            if bins[k] >= 0:
                energy[b, bins[k]] += q
    return energy


def ideal_heating_binned(ad, bd, x0, u, setpoint, bins, n_bins: int):
    """:func:`ideal_heating_batch` that only accumulates the heat per bin (e.g. month).

    Memory stays O(n x n_bins) however many draws and steps; steps with ``bins < 0`` (a
    warm-up) are simulated but not counted.

    Returns
    -------
    ndarray (n, n_bins) [W x steps]: sum of the step-mean heating powers per bin.
    """
    return _ideal_heating_binned(
        np.ascontiguousarray(ad, dtype=float),
        np.ascontiguousarray(bd, dtype=float),
        np.ascontiguousarray(x0, dtype=float),
        np.ascontiguousarray(u, dtype=float),
        np.ascontiguousarray(setpoint, dtype=float),
        np.ascontiguousarray(bins, dtype=np.int64),
        int(n_bins),
    )
