"""What the data say about the varied constructions together: their total conductance.

A building's summed heat often cannot tell one element from another: the roof and the walls
compensate each other, and neither resistance is determined. Their sum may still be: the
conductance to outdoors of the varied constructions together, ``U A`` summed with
``U = 1 / (R + R_films)`` per construction (its layers' resistance ``R`` and the ISO 6946
films of :data:`thermocal.calibration.coordinates.FILM_RESISTANCE`) over the net opaque areas of
its exterior surfaces. This module takes it from the posterior's draws of the resistances,
with its 90 % credible interval, and calls it determined by the criterion the single
parameters have (:data:`thermocal.calibration.posterior.DETERMINED_FRACTION`): its interval is
narrower than that fraction of what the prior alone allows (the prior's 90 % interval of the
total over 0.9, so that for one parameter with a uniform prior it is the same test).

Measured on the EnergyPlus twin of 5ZoneAirCooled with the building-total metric (2026-11-30):
roof and walls 216 W/K [180, 252] against the truth 205.9 W/K (the hidden envelope, walls x 0.6 and
roof x 1.5 in insulation, keeps the total: nominal 206.1 W/K), 12 % of the prior's range, while
the roof's interval spans 64 % of its range and the walls' 74 %.
"""

from __future__ import annotations

import numpy as np

from thermocal.calibration.coordinates import FILM_RESISTANCE
from thermocal.calibration.posterior import DETERMINED_FRACTION

__all__ = ["exterior_opaque_areas", "total_conductance", "total_conductance_sentence"]

#: Draws of the prior (uniform in each resistance between its bounds) for the total's prior
#: interval [-].
PRIOR_DRAWS = 4000


def exterior_opaque_areas(building) -> dict[str, float]:
    """Net opaque area of each construction's exterior surfaces [m2].

    Gross areas of the surfaces with boundary ``outdoors`` minus their windows' areas, summed
    per construction name.
    """
    windows: dict[str, float] = {}
    for window in building.windows.values():
        windows[window.surface] = windows.get(window.surface, 0.0) + window.area
    areas: dict[str, float] = {}
    for surface in building.surfaces.values():
        if surface.boundary == "outdoors":
            net = surface.area - windows.get(surface.name, 0.0)
            areas[surface.construction] = areas.get(surface.construction, 0.0) + net
    return areas


def _construction(name: str) -> str | None:
    """``construction/<name>/resistance`` -> ``<name>`` (None for any other parameter)."""
    parts = name.split("/")
    if len(parts) == 3 and parts[0] == "construction" and parts[2] == "resistance":
        return parts[1]
    return None


def total_conductance(posterior, space, building, *, seed: int = 0) -> dict:
    """The varied constructions' total conductance to outdoors from the posterior's draws.

    Parameters
    ----------
    posterior : Posterior
        With draws (``samples``) of ``construction/<name>/resistance`` [m2 K/W].
    space : ParameterSpace
        The campaign's parameters: bounds and nominal values [m2 K/W].
    building : Building
        The nominal building (its exterior surfaces' areas).
    seed : int
        Seed of the prior's draws.

    Returns
    -------
    dict
        Empty with fewer than two such resistances on exterior surfaces; else
        ``constructions`` (name -> net opaque area [m2]), ``median_W_per_K``, ``q05_W_per_K``,
        ``q95_W_per_K``, ``nominal_W_per_K``, ``prior_q05_W_per_K``, ``prior_q95_W_per_K``,
        ``width_fraction`` (the posterior's 90 % width over the prior's, times 0.9) [-],
        ``determined`` (bool) and ``separately_determined`` (the constructions each
        determined alone, list).
    """
    areas = exterior_opaque_areas(building)
    names = [
        n for n in space.names
        if _construction(n) in areas and areas[_construction(n)] > 0 and n in posterior.samples
    ]  # fmt: skip
    if len(names) < 2:
        return {}
    area = np.array([areas[_construction(n)] for n in names])
    index = [space.index(n) for n in names]

    def total(resistances: np.ndarray) -> np.ndarray:
        return (area / (resistances + FILM_RESISTANCE)).sum(axis=-1)

    draws = total(posterior.samples[names].to_numpy(float))
    rng = np.random.default_rng(seed)
    prior = total(rng.uniform(space.lower[index], space.upper[index], (PRIOR_DRAWS, len(names))))
    q05, q50, q95 = np.quantile(draws, [0.05, 0.5, 0.95])
    p05, p95 = np.quantile(prior, [0.05, 0.95])
    fraction = float(0.9 * (q95 - q05) / (p95 - p05))
    return {
        "constructions": {_construction(n): float(a) for n, a in zip(names, area, strict=True)},
        "median_W_per_K": float(q50),
        "q05_W_per_K": float(q05),
        "q95_W_per_K": float(q95),
        "nominal_W_per_K": float(total(space.nominal[index])),
        "prior_q05_W_per_K": float(p05),
        "prior_q95_W_per_K": float(p95),
        "width_fraction": fraction,
        "determined": fraction < DETERMINED_FRACTION,
        "separately_determined": [_construction(n) for n in names if n in posterior.determined],
    }


def total_conductance_sentence(total: dict) -> str | None:
    """The total in plain words, when it says more than the single resistances do (some of
    them not determined alone); None otherwise."""
    if not total or len(total["separately_determined"]) == len(total["constructions"]):
        return None
    listed = ", ".join(f"{c} ({a:.0f} m2)" for c, a in total["constructions"].items())
    verdict = (
        "determined by the data although not every one of them is alone: the data fix the "
        "sum, not the split"
        if total["determined"]
        else "not determined either"
    )
    return (
        f"The varied constructions together (U A to outdoors of {listed}): "
        f"{total['median_W_per_K']:.0f} W/K ({total['q05_W_per_K']:.0f} to "
        f"{total['q95_W_per_K']:.0f} W/K; nominal {total['nominal_W_per_K']:.0f} W/K), {verdict}."
    )
