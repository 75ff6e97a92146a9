"""Annual heating demand of the fifth-order model (retrofit method: "Heating demand simulation").

The indoor temperature becomes an input: a 24-hour profile from the measured ``Ti``, repeated
every day, is the set point of an ideal heating-only controller, and a year of hourly weather
drives the model. The heat delivered each hour to hold the profile (never negative; when sun
or stored heat lift ``Ti`` above the profile the building floats) gives hourly, monthly and
annual demand. All uncertainty draws and retrofit scenarios run as one batch: the matrices come
from the model's RC network (:func:`thermocal.retrofit.model.network_spec` through
:mod:`thermocal.statespace`), are discretised once per draw and scenario by the
engine's exact discretisation, and the controller loop is compiled (numba).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from thermocal.retrofit.model import (
    ESTIMATED_PARAMETERS,
    EnvelopeComponents,
    FifthOrderModel,
    discrete_system_matrices,
    steady_states_with_indoor,
    system_matrices,
)
from thermocal.retrofit.simulation import ideal_heating_batch, ideal_heating_binned

#: Inputs of the demand model, in order (the heating power is appended by the simulation).
DEMAND_INPUTS: tuple[str, ...] = ("Te", "Tgr", "phi_sol", "phi_abs_roof", "phi_abs_walls")


@dataclass
class DemandResult:
    """Heating demand of every scenario and draw.

    Attributes
    ----------
    monthly : ndarray (n_scenarios, n_draws, 12) [kWh]
    hourly : ndarray (n_scenarios, n_steps) [W]
        Step-mean heating power of the FIRST draw (the estimate) of each scenario.
    index : pd.DatetimeIndex of the steps (interval starts)
    """

    monthly: np.ndarray
    hourly: np.ndarray
    index: pd.DatetimeIndex

    @property
    def step_hours(self) -> float:
        return (self.index[1] - self.index[0]) / pd.Timedelta(hours=1)

    def annual_kwh(self) -> np.ndarray:
        """Annual demand [kWh], shape (n_scenarios, n_draws)."""
        return self.monthly.sum(axis=-1)

    def monthly_kwh(self) -> np.ndarray:
        """Monthly demand [kWh], shape (n_scenarios, n_draws, 12)."""
        return self.monthly


def setpoint_series(index: pd.DatetimeIndex, profile) -> np.ndarray:
    """The controller's set point [C] from a 24-hour profile (hour 0..23) or a constant.

    The profile's value of hour ``h`` is the mean indoor temperature over that hour (the
    measured interval means labelled by their start, :func:`thermocal.retrofit.metrics.
    daily_profile`); the controller's set point applies at the END of each interval
    (:func:`thermocal.retrofit.simulation.ideal_heating_batch`). At the boundary between
    two hours that is the mean of the two hours' values, as the heat fit's controller
    takes the measured series (:func:`thermocal.retrofit.gate.heat_to_follow`); inside an
    hour (steps shorter than an hour) the hour's value. (Until 2026-11-30 the next hour's
    value: every step of the profile, a morning recovery or a night set-back, one hour
    early.)

    Parameters
    ----------
    index : pd.DatetimeIndex
        Interval starts; the set point applies at the END of each interval.
    profile : float or array-like (24,) [C]
    """
    if np.ndim(profile) == 0:
        return interval_setpoint(index, profile)
    step = index[1] - index[0]
    return 0.5 * (interval_setpoint(index, profile) + interval_setpoint(index + step, profile))


def interval_setpoint(index: pd.DatetimeIndex, profile) -> np.ndarray:
    """The mean indoor set point over each interval [C]: the profile's value of the hour the
    interval starts in (a constant as it is); what a quantity of the whole interval, as the
    air change's stack term on the hour's heat (:func:`thermocal.retrofit.airchange.
    apply_slope`), sees, where the controller holds :func:`setpoint_series` at its end.

    Parameters
    ----------
    index : pd.DatetimeIndex
        Interval starts.
    profile : float or array-like (24,) [C]
    """
    prof = np.asarray(profile, dtype=float)
    if prof.ndim == 0:
        return np.full(len(index), float(prof))
    if prof.shape != (24,):
        raise ValueError(f"indoor profile needs 24 hourly values, got shape {prof.shape}")
    return prof[np.asarray(index.hour)]


def simulate_demand(
    model: FifthOrderModel,
    params_si: dict[str, np.ndarray],
    envelopes: list[EnvelopeComponents],
    inputs: pd.DataFrame,
    profile,
    *,
    warmup_days: float = 14.0,
    gains=None,
) -> DemandResult:
    """Heating demand of every (scenario, draw) pair over the weather in ``inputs``.

    Parameters
    ----------
    model : FifthOrderModel
    params_si : dict
        Estimated parameters in SI (``H_est`` [W/K], capacities [J/K]), each an array of shape
        (n_draws,) (the first draw is usually the estimate itself).
    envelopes : list of EnvelopeComponents, or of lists of EnvelopeComponents
        One per scenario (U-values after the retrofit); or, per scenario, one per draw (when
        the U-values themselves are uncertain).
    inputs : pd.DataFrame
        Regular time index; columns ``DEMAND_INPUTS`` (Te, Tgr [C]; gains [W]).
    profile : float or array (24,) [C]
        Indoor set point.
    warmup_days : float
        The last days of the period run first to bring the capacities to a periodic state
        (a typical year wraps from December 31 to January 1).
    gains : array-like (n_steps,) [W], optional
        Internal gains into the air node, like the heating; ``params_si["gain_factor"]``
        (per draw, default 1) scales them (their uncertainty).

    Returns
    -------
    DemandResult
    """
    index = inputs.index
    dt = (index[1] - index[0]).total_seconds()
    u = inputs.loc[:, list(DEMAND_INPUTS)].to_numpy(dtype=float)
    sp = setpoint_series(index, profile)
    n_draws = len(np.atleast_1d(params_si["H_est"]))
    n_scen = len(envelopes)
    h_all: dict[str, list] = {}
    for env in envelopes:
        per_draw = env if isinstance(env, list | tuple) else [env] * n_draws
        if len(per_draw) != n_draws:
            raise ValueError(f"{len(per_draw)} envelopes for {n_draws} parameter draws")
        cache: dict[int, dict] = {}
        for e in per_draw:
            if id(e) not in cache:
                cache[id(e)] = model.conductances(e)
            for k, v in cache[id(e)].items():
                h_all.setdefault(k, []).append(v)
    h = {k: np.asarray(v, dtype=float) for k, v in h_all.items()}
    p = {
        k: np.tile(np.atleast_1d(np.asarray(params_si[k], dtype=float)), n_scen)
        for k in ESTIMATED_PARAMETERS
    }
    a, b = system_matrices(h, p, indoor_input=True)
    ad, bd = discrete_system_matrices(h, p, dt, indoor_input=True)
    if gains is not None:
        a, b, ad, bd, u = with_gains(a, b, ad, bd, u, gains, params_si.get("gain_factor"), n_scen)
    n_warm = min(int(round(warmup_days * 86400 / dt)), len(index) - 1)
    # initial state: steady state with the mean warm-up inputs and zero heating from the
    # set point, then the warm-up period
    u0 = u[-n_warm:].mean(axis=0) if n_warm else u[0]
    x0 = steady_states_with_indoor(a, b, u0, float(sp[-1]))
    if n_warm:
        _, _, x0 = ideal_heating_batch(ad, bd, x0, u[-n_warm:], sp[-n_warm:])
    # monthly energy of all draws (memory O(n x 12)); hourly series of the estimate only
    bins = index.month.to_numpy() - 1
    monthly = ideal_heating_binned(ad, bd, x0, u, sp, bins, 12) * (dt / 3.6e6)
    first = np.arange(n_scen) * n_draws
    hourly, _, _ = ideal_heating_batch(ad[first], bd[first], x0[first], u, sp)
    return DemandResult(monthly.reshape(n_scen, n_draws, 12), hourly, index)


def with_gains(a, b, ad, bd, u, gains, factor, n_repeat: int = 1):
    """Systems and inputs with internal gains as one more input column into the air node.

    The gains enter where the heating does (the last column of ``b`` / ``bd``), scaled per
    system by ``factor`` (an array over the draws, repeated ``n_repeat`` times for the
    scenarios; None: 1); the heating stays the last column, so the controller is unchanged.

    Returns
    -------
    a, b, ad, bd, u with the gains column inserted before the heating column.
    """
    g = np.asarray(gains, dtype=float).reshape(-1, 1)
    f = np.ones(ad.shape[0])
    if factor is not None:
        f = np.tile(np.atleast_1d(np.asarray(factor, dtype=float)), n_repeat)
    col_b = b[:, :, -1:] * f[:, None, None]
    col_bd = bd[:, :, -1:] * f[:, None, None]
    b = np.concatenate([b[:, :, :-1], col_b, b[:, :, -1:]], axis=2)
    bd = np.concatenate([bd[:, :, :-1], col_bd, bd[:, :, -1:]], axis=2)
    return a, b, ad, bd, np.hstack([u, g])


def steady_state_demand(
    model: FifthOrderModel,
    h_est: float,
    temp_in: float,
    temp_out: float,
    envelope: EnvelopeComponents | None = None,
) -> float:
    """Hand calculation: heating power [W] = HLC x (Ti - Te), ground at outdoor temperature."""
    from thermocal.retrofit.model import calculated_hlc

    hlc = calculated_hlc(model.conductances(envelope)) + h_est
    return max(hlc * (temp_in - temp_out), 0.0)
