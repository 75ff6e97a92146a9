"""What the sensors' accuracy leaves uncertain in the identified heat.

The identified heat is the heat that holds the model on the measured temperatures, so a
sensor's calibration offset passes straight into it. The model is linear in the held
temperatures apart from its lagged corrections, and a constant offset acts, beyond the first
hours, through the building's steady-state conductances: holding zone ``j`` ``delta`` K warmer
needs ``K[z, j] * delta`` W more heat in every held zone ``z``, where ``K`` is the network's
conductance matrix reduced to the held zones' air nodes (the Schur complement over every other
node: walls, surfaces, zones without a sensor). Over a period of ``T`` hours that is
``K[z, j] * delta * T / 1000`` kWh.

Two cases are stated, as a metrology budget states them (JCGM 100:2008, the GUM, 5.1 and
5.2): offsets independent from sensor to sensor (each sensor calibrated on its own), which
mostly move heat between neighbouring zones, and one offset shared by every sensor (one
logger type, one calibration), which moves the building's total. Neither includes the model's
own error (the envelope's parameters: that is what calibration estimates).

References
----------
.. [1] JCGM 100:2008, "Evaluation of measurement data - Guide to the expression of uncertainty
   in measurement" (GUM), sections 5.1 (uncorrelated) and 5.2 (correlated input quantities).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

#: Default standard uncertainty of a room-temperature sensor [K]: the +-0.2 K class of
#: common data loggers' thermistors (e.g. the manufacturers' stated accuracy of 0.2 K at
#: 0-50 C), taken as one standard uncertainty.
DEFAULT_SENSOR_ACCURACY_K = 0.2


def held_zone_conductance(conductance: sp.spmatrix, held_nodes: np.ndarray) -> np.ndarray:
    """Steady-state conductance matrix between held nodes, every other node free [W/K].

    The Schur complement ``K = G_hh - G_hr G_rr^-1 G_rh`` of the network's conductance
    matrix ``G`` (boundaries such as the outdoor air and the ground enter its diagonal): the
    extra heat each held node needs when the held temperatures rise by a unit each.

    Parameters
    ----------
    conductance : sparse matrix (n, n) [W/K]
        The network's conductance matrix (no heat capacities).
    held_nodes : ndarray of int
        Nodes held at given temperatures (the zones' air nodes with a sensor).

    Returns
    -------
    ndarray (h, h) [W/K]
        Row ``z``, column ``j``: the heat into held node ``z`` per kelvin at held node ``j``.
    """
    from scipy.sparse.linalg import splu

    g = sp.csc_matrix(conductance)
    held = np.asarray(held_nodes, dtype=np.int64)
    rest = np.setdiff1d(np.arange(g.shape[0]), held)
    g_hh = g[held][:, held].toarray()
    if not len(rest):
        return g_hh
    g_rh = g[rest][:, held].toarray()
    g_hr = g[held][:, rest]
    solved = splu(sp.csc_matrix(g[rest][:, rest])).solve(g_rh)
    return g_hh - np.asarray(g_hr @ solved)


def sensor_heat_uncertainty(
    conductance_between_zones: np.ndarray,
    zones: list[str],
    hours: float,
    identified_kwh: np.ndarray,
    accuracy: float = DEFAULT_SENSOR_ACCURACY_K,
    zone_sensors: dict | None = None,
) -> dict:
    """Standard uncertainty of each zone's and the building's identified heat from the
    sensors' accuracy [kWh].

    Parameters
    ----------
    conductance_between_zones : ndarray (h, h) [W/K]
        :func:`held_zone_conductance` of the held zones.
    zones : list of str
        The held zones, in the matrix's order.
    hours : float [h]
        Length of the identified period.
    identified_kwh : ndarray (h,) [kWh]
        Each zone's identified heat over the period (its sum of absolute values per step:
        heating and cooling alike), the scale the uncertainty is compared with.
    accuracy : float [K]
        Standard uncertainty of each sensor's offset.
    zone_sensors : dict, optional
        Zone -> the sensors its reference is the mean of (a zone without a sensor of its own
        follows a neighbour's: the two share that sensor's offset). Default: each zone its
        own sensor.

    Returns
    -------
    dict
        ``accuracy_K``; ``independent``: ``building_kwh`` and per zone ``zones`` ->
        ``kwh`` and ``share`` of its identified heat; ``shared``: ``building_kwh`` (every
        sensor off by the same ``accuracy``) and ``building_share``; ``kwh_per_K`` per zone
        (the heat a shared offset of 1 K moves in it); ``sensors``: how many distinct sensors.
    """
    k = np.asarray(conductance_between_zones, dtype=float)
    # kWh per kelvin of each sensor's offset: the zones' offsets are their sensors' means
    energy = (k * hours / 1000.0) @ sensor_weights(zones, zone_sensors)
    per_zone = accuracy * np.sqrt((energy**2).sum(axis=1))
    building_independent = accuracy * float(np.sqrt((energy.sum(axis=0) ** 2).sum()))
    building_shared = accuracy * float(energy.sum())
    scale = np.asarray(identified_kwh, dtype=float)
    total = float(scale.sum())
    share = np.divide(per_zone, scale, out=np.full(len(scale), np.nan), where=scale > 0)
    return {
        "accuracy_K": float(accuracy),
        "hours": float(hours),
        "independent": {
            "building_kwh": building_independent,
            "building_share": building_independent / total if total > 0 else None,
            "zones": {
                z: {"kwh": float(u), "share": None if not np.isfinite(s) else float(s)}
                for z, u, s in zip(zones, per_zone, share, strict=True)
            },
        },
        "shared": {
            "building_kwh": abs(building_shared),
            "building_share": abs(building_shared) / total if total > 0 else None,
        },
        "kwh_per_K": {z: float(v) for z, v in zip(zones, energy.sum(axis=1), strict=True)},
        "sensors": int(energy.shape[1]),
    }


def sensor_weights(zones: list[str], zone_sensors: dict | None) -> np.ndarray:
    """Matrix (zones, sensors) [-] of each zone's reference as a mean of sensors.

    Parameters
    ----------
    zones : list of str
        The held zones.
    zone_sensors : dict or None
        Zone -> sequence of sensor names (or one comma-separated string); None or a zone
        missing: the zone is its own sensor.

    Returns
    -------
    ndarray (h, s)
        Rows summing to 1.
    """
    rows = []
    for zone in zones:
        given = (zone_sensors or {}).get(zone)
        if isinstance(given, str):
            given = [x.strip() for x in given.split(",") if x.strip()]
        rows.append(list(given) if given else [f"zone:{zone}"])
    names = sorted({name for row in rows for name in row})
    column = {name: j for j, name in enumerate(names)}
    weights = np.zeros((len(zones), len(names)))
    for i, row in enumerate(rows):
        for name in row:
            weights[i, column[name]] += 1.0 / len(row)
    return weights


def uncertainty_note(uncertainty: dict, shown: int = 3) -> str:
    """One sentence for the terminal and the notes: the building's and the most uncertain
    zones' share of their identified heat."""
    acc = uncertainty["accuracy_K"]
    ind, shared = uncertainty["independent"], uncertainty["shared"]

    def pct(x):
        return "n/a" if x is None else f"{100 * x:.1f} %"

    zones = sorted(
        ((z, v) for z, v in ind["zones"].items() if v["share"] is not None),
        key=lambda item: -item[1]["share"],
    )
    worst = ", ".join(f"'{z}' {pct(v['share'])}" for z, v in zones[:shown])
    return (
        f"Sensor accuracy (standard uncertainty {acc:g} K per sensor; --sensor-accuracy): the "
        f"building's identified heat is uncertain by {shared['building_kwh']:,.0f} kWh "
        f"({pct(shared['building_share'])}) if every sensor is off alike, "
        f"{ind['building_kwh']:,.0f} kWh ({pct(ind['building_share'])}) if each is off on "
        f"its own; a zone's by up to {worst} of its heat (offsets of neighbours move heat "
        "through the walls between them). The model's own error is not included."
    )
