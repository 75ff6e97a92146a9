"""What the data say about the varied elements together: their total conductance.

A building's summed heat often cannot tell one element from another: the roof and the walls
compensate each other, or the walls and the windows, or one office's air change and another's,
and none is determined alone. Their sum may still be. From the posterior's draws this module
takes three totals [W/K], each with its 90 % credible interval:

- ``conduction``: the varied elements' ``U A`` to outdoors, over each construction with
  ``U = 1 / (R + R_films)`` (its layers' resistance ``R``, the ISO 6946 films of
  :data:`thermocal.calibration.coordinates.FILM_RESISTANCE`) and the net opaque area of its
  exterior surfaces, and over each window type with its ``u_value`` and its windows' area;
- ``air``: the varied air changes' design conductance, ``rho c_p V n / 3600`` at the rates
  the parameters set (ISO 13789's ``rho c_p`` = 1200 J/(m3 K)); an imported file's infiltration
  schedule and wind or temperature terms act on top of it in the model, so it is the
  conductance at the design rate, not the mean flow;
- ``all``: both (at the design air change rates): the part of the heat loss coefficient the
  campaign varies where its elements bound conditioned zones; an element of an unconditioned
  zone (a return plenum's roof, an attic's air change) acts in series with the ceiling
  beneath it, so there the sum is a conductance to outdoors, not a share of the heat loss
  coefficient.

The films are ISO 6946's for horizontal heat flow on every element (0.14 m2 K/W for a roof's
upward flow, 0.21 for a floor's downward: about 1 % of a total at R = 3, 4 % at R = 0.5).
Each total is called determined by the width criterion of the single parameters
(:data:`thermocal.calibration.posterior.DETERMINED_FRACTION`): its interval is narrower than
that fraction of what the prior alone allows (the prior's 90 % interval of the total, from
uniform draws of each parameter in its range, over 0.9, so that for one parameter it is the same
test); and, as for a single parameter, not when one of its parameters compensates an input the
posterior integrates out (``posterior: {uncertain: ...}``) and is not measured in situ: that
input's prior, not the data, then narrows it; nor when one of its parameters has no effect on
the metric beyond the estimation noise (the single parameters'
:data:`thermocal.calibration.posterior.EFFECT_TO_NOISE`): such a parameter's Jacobian is noise
that can look like information, in a sum as alone.

Measured on the EnergyPlus twin of 5ZoneAirCooled with the building-total metric (2026-11-30):
roof and walls 216 W/K [180, 252] against the truth 205.9 W/K (the hidden envelope, walls x 0.6
and roof x 1.5 in insulation, keeps the total: nominal 206.1 W/K), while the roof's interval
spans 64 % of its range and the walls' 74 %; the five offices' air 225 W/K [180, 265] (truth
258.7, not determined); everything 440 W/K [386, 493] (truth 464.6, determined).
"""

from __future__ import annotations

import numpy as np

from thermocal.calibration.coordinates import FILM_RESISTANCE
from thermocal.calibration.posterior import DETERMINED_FRACTION, EFFECT_TO_NOISE

__all__ = [
    "conductance_terms",
    "exterior_opaque_areas",
    "total_conductance",
    "total_conductance_sentences",
    "window_areas",
]

#: Draws of the prior (uniform in each parameter between its bounds) for the total's prior
#: interval [-].
PRIOR_DRAWS = 4000


def exterior_opaque_areas(building) -> dict[str, float]:
    """Net opaque area of each construction's exterior surfaces [m2].

    :meth:`thermocal.multizone.Building.net_area` (gross minus its windows) of the surfaces
    with boundary ``outdoors``, summed per construction name.
    """
    areas: dict[str, float] = {}
    for surface in building.surfaces.values():
        if surface.boundary == "outdoors":
            net = building.net_area(surface.name)
            areas[surface.construction] = areas.get(surface.construction, 0.0) + net
    return areas


def window_areas(building) -> dict[str, float]:
    """Area of each window type's windows (glass and frame) [m2]."""
    areas: dict[str, float] = {}
    for window in building.windows.values():
        areas[window.window_type] = areas.get(window.window_type, 0.0) + window.area
    return areas


#: Volumetric heat capacity of air for an air change's conductance [J/(m3 K)] (ISO 13789's
#: rho c_p = 1200 J/(m3 K)).
AIR_HEAT_CAPACITY = 1200.0

#: The totals, in the order they are reported: the elements' U A, the air change's conductance,
#: and both (see the module's docstring for what their sum is).
PARTS = ("conduction", "air", "all")


def conductance_terms(names, building) -> dict[str, tuple[str, str, float, float]]:
    """Each parameter's term of the totals: name -> (part, label, size, weight); parameters
    without one (a layer's conductivity, an SHGC) are left out.

    A term's conductance [W/K] is ``weight / (value + FILM_RESISTANCE)`` for a construction's
    resistance (weight: its net opaque exterior area [m2]) and ``weight * value`` otherwise: a
    window type's U-value (its windows' area [m2]), an air change rate or the building's
    infiltration factor (``AIR_HEAT_CAPACITY / 3600`` times the air volume [m3]; for a group's
    mean rate its members' ``sum V r / mean r``; for the factor the zones' nominal ``sum V n``
    [m3/h]). ``size`` is the area [m2] or volume [m3] a report names. A campaign varying the
    building's factor together with zones' or groups' rates gets no air terms (the factor
    multiplies them).
    """
    opaque, glazed = exterior_opaque_areas(building), window_areas(building)
    zones = building.zones
    air = AIR_HEAT_CAPACITY / 3600.0
    terms = {}
    for name in names:
        kind, _, rest = name.partition("/")
        element, _, field = rest.rpartition("/")
        if kind == "construction" and field == "resistance" and opaque.get(element, 0) > 0:
            terms[name] = ("conduction", element, opaque[element], opaque[element])
        elif kind == "window" and field == "u_value" and glazed.get(element, 0) > 0:
            terms[name] = ("conduction", f"window {element}", glazed[element], glazed[element])
        elif kind == "zone" and field == "infiltration_ach" and element in zones:
            volume = zones[element].volume
            terms[name] = ("air", f"{element} air", volume, air * volume)
        elif name == "infiltration/building/factor":
            volume = sum(z.volume for z in zones.values() if z.infiltration_ach > 0)
            flow = sum(z.volume * z.infiltration_ach for z in zones.values())
            terms[name] = ("air", "the building's air", volume, air * flow)
        elif kind == "infiltration" and field == "ach":
            # the group's parameter is its members' mean rate; setting it scales each member's
            # rate in proportion (Building.with_parameters): V r summed over the mean
            members = [z for z in zones.values() if z.infiltration_group == element]
            mean = float(np.mean([z.infiltration_ach for z in members])) if members else 0.0
            if mean > 0:
                volume = sum(z.volume for z in members)
                flow = sum(z.volume * z.infiltration_ach for z in members) / mean
                terms[name] = ("air", f"{element} air", volume, air * flow)
    # the building's factor multiplies the zones' and groups' rates: their sum would not be the
    # model's conductance, so a campaign varying both gets no air total
    factor = "infiltration/building/factor"
    if factor in terms and sum(t[0] == "air" for t in terms.values()) > 1:
        terms = {n: t for n, t in terms.items() if t[0] != "air"}
    return terms


def total_conductance(posterior, space, building, *, seed: int = 0) -> dict:
    """The varied elements' and air change's total conductance from the posterior's draws.

    Parameters
    ----------
    posterior : Posterior
        With draws (``samples``) of the campaign's parameters [unit of each]; those that count
        toward the totals are ``construction/<name>/resistance`` [m2 K/W],
        ``window/<type>/u_value`` [W/(m2 K)], ``zone/<name>/infiltration_ach`` and
        ``infiltration/<group>/ach`` [1/h] and ``infiltration/building/factor`` [-].
    space : ParameterSpace
        The campaign's parameters: bounds and nominal values [unit of each].
    building : Building
        The nominal building (its exterior surfaces' and windows' areas, its zones' volumes).
    seed : int
        Seed of the prior's draws.

    Returns
    -------
    dict
        Per part of :data:`PARTS` with at least two parameters (``all`` only when both others
        have some): ``elements`` (label -> area [m2] or air volume [m3]), ``parameters`` (their
        names), ``median_W_per_K``, ``q05_W_per_K``, ``q95_W_per_K``, ``nominal_W_per_K``,
        ``prior_q05_W_per_K``, ``prior_q95_W_per_K``, ``width_fraction`` (the posterior's 90 %
        width over the prior's, times 0.9) [-], ``determined`` (bool),
        ``compensates_uncertain_input`` (its parameters that do, list), ``without_effect``
        (its parameters whose effect is within the estimation noise, list) and
        ``separately_determined`` (the elements each determined alone, list).
    """
    terms = conductance_terms([n for n in space.names if n in posterior.samples], building)
    rng = np.random.default_rng(seed)
    out = {}
    for part in PARTS:
        names = [n for n, t in terms.items() if part in ("all", t[0])]
        kinds = {terms[n][0] for n in names}
        if len(names) < 2 or (part == "all" and len(kinds) < 2):
            continue
        out[part] = _summary(names, terms, posterior, space, rng)
    return out


def _summary(names, terms, posterior, space, rng) -> dict:
    """One part's total: draws, prior and nominal (see :func:`total_conductance`)."""
    weight = np.array([terms[n][3] for n in names])
    inverse = np.array([n.endswith("/resistance") for n in names])
    index = [space.index(n) for n in names]

    def total(values: np.ndarray) -> np.ndarray:
        return (weight * np.where(inverse, 1.0 / (values + FILM_RESISTANCE), values)).sum(axis=-1)

    draws = total(posterior.samples[names].to_numpy(float))
    prior = total(rng.uniform(space.lower[index], space.upper[index], (PRIOR_DRAWS, len(names))))
    q05, q50, q95 = np.quantile(draws, [0.05, 0.5, 0.95])
    p05, p95 = np.quantile(prior, [0.05, 0.95])
    fraction = float(0.9 * (q95 - q05) / (p95 - p05))
    measured = set(getattr(posterior, "in_situ", {}) or {})
    confounded = sorted(
        n
        for item in getattr(posterior, "uncertain", []) or []
        for n in item.get("compensates", {})
        if n in names and n not in measured
    )
    # the single parameters' second condition: a parameter with no effect on the metric gets
    # a Jacobian of estimation noise that can look like information, and a sum of them too
    summary = getattr(posterior, "summary", None)
    without_effect = sorted(
        n
        for n in names
        if summary is not None and "effect_to_noise" in summary and n in summary.index
        and n not in measured
        and not float(summary.loc[n, "effect_to_noise"]) > EFFECT_TO_NOISE
    )  # fmt: skip
    return {
        "elements": {terms[n][1]: float(terms[n][2]) for n in names},
        "parameters": names,
        "median_W_per_K": float(q50),
        "q05_W_per_K": float(q05),
        "q95_W_per_K": float(q95),
        "nominal_W_per_K": float(total(space.nominal[index])),
        "prior_q05_W_per_K": float(p05),
        "prior_q95_W_per_K": float(p95),
        "width_fraction": fraction,
        "determined": fraction < DETERMINED_FRACTION and not confounded and not without_effect,
        "compensates_uncertain_input": confounded,
        "without_effect": without_effect,
        "separately_determined": [terms[n][1] for n in names if n in posterior.determined],
    }


#: How each part is named in a sentence.
PART_WORDS = {
    "conduction": "The varied elements together (U A to outdoors of {listed})",
    "air": "The varied air changes together (their design conductance, {listed})",
    "all": "Everything varied together (U A and air change conductance to outdoors; where the "
    "elements bound conditioned zones, the part of the heat loss coefficient the campaign varies)",
}


def total_conductance_sentences(totals: dict) -> list[str]:
    """The totals in plain words, each when it says more than its parts do alone (some of
    them not determined alone)."""
    out = []
    for part in PARTS:
        total = totals.get(part)
        if not total or len(total["separately_determined"]) == len(total["elements"]):
            continue
        listed = ", ".join(
            f"{label} ({size:.0f} {'m3' if part == 'air' or label.endswith(' air') else 'm2'})"
            for label, size in total["elements"].items()
        )
        if total["determined"]:
            verdict = (
                "determined by the data although not every one of them is alone: the data fix "
                "the sum, not the split"
            )
        elif total.get("compensates_uncertain_input"):
            verdict = (
                "not called determined: "
                + ", ".join(total["compensates_uncertain_input"])
                + " compensate(s) an input integrated out, whose prior sets it"
            )
        elif total.get("without_effect"):
            verdict = (
                "not called determined: "
                + ", ".join(total["without_effect"])
                + " change(s) the metric by no more than its estimation noise"
            )
        else:
            verdict = "not determined either"
        out.append(
            PART_WORDS[part].format(listed=listed)
            + f": {total['median_W_per_K']:.0f} W/K ({total['q05_W_per_K']:.0f} to "
            f"{total['q95_W_per_K']:.0f} W/K; nominal {total['nominal_W_per_K']:.0f} W/K), "
            f"{verdict}."
        )
    return out
