"""What the data say about the varied elements together: their total conductance.

A building's summed heat often cannot tell one element from another: the roof and the walls
compensate each other, or the walls and the windows, and neither is determined. Their sum may
still be: the conductance to outdoors of the varied elements together, ``U A`` summed over each
construction with ``U = 1 / (R + R_films)`` (its layers' resistance ``R`` and the ISO 6946
films of :data:`thermocal.calibration.coordinates.FILM_RESISTANCE`) and the net opaque areas of
its exterior surfaces, and over each window type with its ``u_value`` and its windows' areas.
This module takes it from the posterior's draws, with its 90 % credible interval, and calls it
determined by the criterion the single
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

__all__ = [
    "exterior_opaque_areas",
    "total_conductance",
    "total_conductance_sentence",
    "window_areas",
]

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


def window_areas(building) -> dict[str, float]:
    """Area of each window type's windows (glass and frame) [m2]."""
    areas: dict[str, float] = {}
    for window in building.windows.values():
        areas[window.window_type] = areas.get(window.window_type, 0.0) + window.area
    return areas


def _element(name: str) -> tuple[str, str] | None:
    """``construction/<c>/resistance`` -> ("construction", c), ``window/<w>/u_value`` ->
    ("window", w); None for any other parameter."""
    kind, _, rest = name.partition("/")
    element, _, field = rest.rpartition("/")
    if kind == "construction" and field == "resistance" and element:
        return kind, element
    if kind == "window" and field == "u_value" and element:
        return kind, element
    return None


def total_conductance(posterior, space, building, *, seed: int = 0) -> dict:
    """The varied elements' total conductance to outdoors from the posterior's draws.

    Parameters
    ----------
    posterior : Posterior
        With draws (``samples``) of ``construction/<name>/resistance`` [m2 K/W] and
        ``window/<type>/u_value`` [W/(m2 K)].
    space : ParameterSpace
        The campaign's parameters: bounds and nominal values [unit of each].
    building : Building
        The nominal building (its exterior surfaces' and windows' areas).
    seed : int
        Seed of the prior's draws.

    Returns
    -------
    dict
        Empty with fewer than two such elements on the building's outside; else ``elements``
        (a construction's name or ``window <type>`` -> its area [m2]), ``parameters`` (their
        names), ``median_W_per_K``, ``q05_W_per_K``, ``q95_W_per_K``, ``nominal_W_per_K``,
        ``prior_q05_W_per_K``, ``prior_q95_W_per_K``, ``width_fraction`` (the posterior's 90 %
        width over the prior's, times 0.9) [-], ``determined`` (bool) and
        ``separately_determined`` (the elements each determined alone, list).
    """
    areas = {"construction": exterior_opaque_areas(building), "window": window_areas(building)}

    def area_of(name: str) -> float:
        kind, element = _element(name) or ("", "")
        return areas.get(kind, {}).get(element, 0.0)

    names = [n for n in space.names if area_of(n) > 0 and n in posterior.samples]
    if len(names) < 2:
        return {}
    area = np.array([area_of(n) for n in names])
    window = np.array([_element(n)[0] == "window" for n in names])
    index = [space.index(n) for n in names]

    def total(values: np.ndarray) -> np.ndarray:
        u = np.where(window, values, 1.0 / (values + FILM_RESISTANCE))
        return (area * u).sum(axis=-1)

    draws = total(posterior.samples[names].to_numpy(float))
    rng = np.random.default_rng(seed)
    prior = total(rng.uniform(space.lower[index], space.upper[index], (PRIOR_DRAWS, len(names))))
    q05, q50, q95 = np.quantile(draws, [0.05, 0.5, 0.95])
    p05, p95 = np.quantile(prior, [0.05, 0.95])
    fraction = float(0.9 * (q95 - q05) / (p95 - p05))
    return {
        "elements": {_label(n): float(a) for n, a in zip(names, area, strict=True)},
        "parameters": names,
        "median_W_per_K": float(q50),
        "q05_W_per_K": float(q05),
        "q95_W_per_K": float(q95),
        "nominal_W_per_K": float(total(space.nominal[index])),
        "prior_q05_W_per_K": float(p05),
        "prior_q95_W_per_K": float(p95),
        "width_fraction": fraction,
        "determined": fraction < DETERMINED_FRACTION,
        "separately_determined": [_label(n) for n in names if n in posterior.determined],
    }


def _label(name: str) -> str:
    """A construction's name, or ``window <type>``."""
    kind, element = _element(name)
    return element if kind == "construction" else f"window {element}"


def total_conductance_sentence(total: dict) -> str | None:
    """The total in plain words, when it says more than the single resistances do (some of
    them not determined alone); None otherwise."""
    if not total or len(total["separately_determined"]) == len(total["elements"]):
        return None
    listed = ", ".join(f"{c} ({a:.0f} m2)" for c, a in total["elements"].items())
    verdict = (
        "determined by the data although not every one of them is alone: the data fix the "
        "sum, not the split"
        if total["determined"]
        else "not determined either"
    )
    return (
        f"The varied elements together (U A to outdoors of {listed}): "
        f"{total['median_W_per_K']:.0f} W/K ({total['q05_W_per_K']:.0f} to "
        f"{total['q95_W_per_K']:.0f} W/K; nominal {total['nominal_W_per_K']:.0f} W/K), {verdict}."
    )
