"""Where the annual heating demand of the fifth-order model goes: its heat balance per path.

The demand simulation (:func:`thermocal.retrofit.demand.simulate_demand`) reports only the heat
the ideal controller delivers. To compare a model with a reference's own energy balance (e.g.
EnergyPlus's surface conduction, infiltration, transmitted sun and internal gains) the same
simulation is run once more for the estimate and the heat leaving the indoor air node is
summed per path and month:

- ``envelope`` -- into the roof / wall element (``H_env_in (Ti - Tenv)``: walls, roof, ceilings
  under an unheated attic, walls to unheated spaces; the sun absorbed outside on roof and walls
  is in it, as in a reference's inside-face conduction);
- ``windows`` -- ``H_win (Ti - Te)``;
- ``air_change`` -- ``H_est (Ti - Te)`` (ventilation, infiltration and everything else the
  calibration put there);
- ``floor`` -- into the floor element (``H_gf_in (Ti - Tgf)``, the path to the ground or an
  unheated basement);
- ``sun`` -- minus the sun through the windows (all of it, also the share that reaches the air
  through the internal mass);
- ``gains`` -- minus the internal gains;
- ``stored`` -- what the air and the internal mass keep or give back (the rest of the balance,
  close to zero over a month).

With the split inside (``model.interior: split``, :mod:`thermocal.retrofit.interior`) the
element paths are the heat their inner surfaces conduct into the element (the inside-face
conduction, as a reference reports it): heat out of the room (its air, internal mass and
surfaces together) rather than out of the air node alone.

Every column is a heat flow OUT of the indoor air [kWh] (sun and gains negative), and they add
up to ``heating`` by construction. Interval means of the states are taken as the mean of the
start and end states (trapezoid); the air change's temperature slope
(:mod:`thermocal.retrofit.airchange`), added after the simulation, is not in it.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.retrofit.demand import DEMAND_INPUTS, setpoint_series, with_gains
from thermocal.retrofit.model import (
    FifthOrderModel,
    discrete_system_matrices,
    steady_states_with_indoor,
    system_matrices,
)
from thermocal.retrofit.simulation import ideal_heating_states

#: the paths of :func:`heat_balance`, in order
BALANCE_PATHS: tuple[str, ...] = (
    "envelope", "windows", "air_change", "floor", "sun", "gains", "stored",
)  # fmt: skip


def heat_balance(
    model: FifthOrderModel,
    params_si: dict[str, float],
    envelope,
    inputs: pd.DataFrame,
    profile,
    *,
    gains=None,
    warmup_days: float = 14.0,
) -> pd.DataFrame:
    """Monthly heat balance of the indoor air in the demand simulation, per path [kWh].

    Parameters
    ----------
    model : FifthOrderModel
    params_si : dict
        One parameter set in SI (``H_est`` [W/K], capacities [J/K]), e.g. the estimate.
    envelope : EnvelopeComponents or None
        U-values (the calibrated envelope; None: the model's own).
    inputs : pd.DataFrame
        The demand year: regular index, columns ``DEMAND_INPUTS`` (Te, Tgr [C]; sun [W]).
    profile : float or array (24,) [C]
        Indoor set point.
    gains : array-like (n_steps,) [W], optional
        Internal gains into the air node.
    warmup_days : float
        As :func:`thermocal.retrofit.demand.simulate_demand`: the last days run first.

    Returns
    -------
    pd.DataFrame, index 1..12 (months), columns :data:`BALANCE_PATHS` and ``heating`` [kWh],
    plus the monthly mean ``Ti`` and ``Tgr`` [C].
    """
    index = inputs.index
    dt = (index[1] - index[0]).total_seconds()
    u = inputs.loc[:, list(DEMAND_INPUTS)].to_numpy(dtype=float)
    sp = setpoint_series(index, profile)
    h = model.conductances(envelope)
    p = {k: float(v) for k, v in params_si.items()}
    a, b = system_matrices(h, p, indoor_input=True)
    ad, bd = discrete_system_matrices(h, p, dt, indoor_input=True)
    g = np.zeros(len(index)) if gains is None else np.asarray(gains, dtype=float)
    a, b, ad, bd, u = with_gains(a, b, ad, bd, u, g, None)
    n_warm = min(int(round(warmup_days * 86400 / dt)), len(index) - 1)
    x0 = steady_states_with_indoor(a, b, u[-n_warm:].mean(axis=0) if n_warm else u[0],
                                   float(sp[-1]))[0]  # fmt: skip
    if n_warm:
        x0 = ideal_heating_states(ad[0], bd[0], x0, u[-n_warm:], sp[-n_warm:])[0][-1]
    x, heat = ideal_heating_states(ad[0], bd[0], x0, u, sp)
    mean = 0.5 * (x[:-1] + x[1:])
    ti, tenv, tgf = mean[:, 0], mean[:, 1], mean[:, 2]
    te = inputs["Te"].to_numpy(float)
    h_est = max(p["H_est"] + float(h.get("H_est_change", 0.0)), 0.0)
    interior = model.reduced_interior(envelope)
    if interior is None:
        into = {"Tenv": h["H_env_in"] * (ti - tenv), "Te": h["H_win"] * (ti - te),
                "Tgf": h["H_gf_in"] * (ti - tgf)}  # fmt: skip
    else:
        # the split inside: what the inner surfaces conduct into each element (the room's
        # air, its internal mass and its surfaces together lose it)
        into = interior.inside_face_flows(
            {"Ti": ti, "Tenv": tenv, "Tgf": tgf, "Tim": mean[:, 3], "Te": te}
        )
    flows = pd.DataFrame(
        {
            "envelope": into["Tenv"],
            "windows": into["Te"],
            "air_change": h_est * (ti - te),
            "floor": into["Tgf"],
            "sun": -float(h.get("g_factor", 1.0)) * inputs["phi_sol"].to_numpy(float),
            "gains": -g,
            "heating": heat,
        },
        index=index,
    )
    flows["stored"] = flows["heating"] - flows[list(BALANCE_PATHS[:-1])].sum(axis=1)
    months = index.month
    out = flows.groupby(months).sum() * (dt / 3.6e6)
    out = out[list(BALANCE_PATHS) + ["heating"]]
    out["Ti"] = pd.Series(ti, index=index).groupby(months).mean()
    out["Tgr"] = inputs["Tgr"].groupby(months).mean()
    out.index.name = "month"
    return out
