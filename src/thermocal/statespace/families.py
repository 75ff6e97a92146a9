"""Candidate model families for forward selection.

:func:`bacher_madsen_family` generates the RC models of Bacher & Madsen (2011) for a single-zone
building with an ambient temperature, a heating power, optionally a solar irradiance, and one
indoor temperature: ``Ti`` extended by an envelope state ``Te`` (``Rie``, ``Rea``, ``Ce``), a
heater state ``Th`` (``Rih``, ``Ch``; the heating then goes into the heater), an internal medium
``Tm`` (``Rim``, ``Cm``) and a direct interior-ambient resistance ``Ria``. The parameters,
bounds and start values are those of ``examples/models/<name>.yaml`` (capacities in kWh/K,
resistances in K/kW, diffusion in K/sqrt(h)); the column units are given.

References
----------
.. [1] P. Bacher, H. Madsen, "Identifying suitable models for the heat dynamics of buildings",
   Energy and Buildings 43(7), 1511-1522, 2011, sec. 4 and fig. 6 (the model tree).
"""

from __future__ import annotations

import math

from thermocal.errors import ThermocalInputError
from thermocal.statespace.checks import inverted_balance_message
from thermocal.statespace.model import RCModel
from thermocal.statespace.units import (
    HEAT_COLUMN_UNITS,
    PLAUSIBLE_HEAT_LOSS_W_PER_K,
    heat_unit_slip,
)

#: Family members: (has Tm, has Te, has Th, has Ria with Te), in selection order.
_MEMBERS = {
    "Ti": (False, False, False),
    "TiTe": (False, True, False),
    "TiTh": (False, False, True),
    "TiTeTh": (False, True, True),
    "TiTeThRia": (False, True, True, "Ria"),
    "TiTmTeTh": (True, True, True),
    "TiTmTeThRia": (True, True, True, "Ria"),
    "TiTeAe": (False, True, False, "Ae"),
    "TiTeThAe": (False, True, True, "Ae"),
    "TiTeThAeRia": (False, True, True, "Ria", "Ae"),
    "TiTmTeThAe": (True, True, True, "Ae"),
    "TiTmTeThAeRia": (True, True, True, "Ria", "Ae"),
}
#: Members whose solar input also heats the envelope state (aperture ``Ae``): the sun on the
#: walls and roof, absorbed there, which the interior's aperture ``Aw`` cannot stand for. An
#: extension of the published tree: on ASHRAE 140 Case 900 held at 20 C by a thermostat
#: (EnergyPlus 25.2, a Denver January), the interior-only models gave 52.8 W/K [48.0, 58.5]
#: against the steady 87.4 W/K, TiTeAe 86.1 [75.2, 102.6] (+104 log-units for one parameter;
#: ``tests/statespace/test_statespace_select_solar_envelope.py``).
_SOLAR_ENVELOPE = tuple(name for name, flags in _MEMBERS.items() if "Ae" in flags[3:])
#: Extensions of each member by one element (the part of the tree fitted by the reference).
BACHER_MADSEN_EXTENSIONS = {
    "Ti": ["TiTe", "TiTh"],
    "TiTe": ["TiTeTh", "TiTeAe"],
    "TiTh": ["TiTeTh"],
    "TiTeTh": ["TiTeThRia", "TiTmTeTh", "TiTeThAe"],
    "TiTeThRia": ["TiTmTeThRia", "TiTeThAeRia"],
    "TiTmTeTh": ["TiTmTeThRia", "TiTmTeThAe"],
    "TiTmTeThRia": ["TiTmTeThAeRia"],
    "TiTeAe": ["TiTeThAe"],
    "TiTeThAe": ["TiTeThAeRia", "TiTmTeThAe"],
    "TiTeThAeRia": ["TiTmTeThAeRia"],
    "TiTmTeThAe": ["TiTmTeThAeRia"],
}
_DESCRIPTIONS = {
    "Ti": "One state, the interior (air and everything in contact with it).",
    "TiTe": "Interior and building envelope.",
    "TiTh": "Interior and heater.",
    "TiTeTh": "Interior, envelope and heater.",
    "TiTeThRia": "TiTeTh plus a direct interior-ambient resistance (ventilation, windows).",
    "TiTmTeTh": "TiTeTh plus an internal thermal medium (furniture, inner walls).",
    "TiTmTeThRia": "TiTmTeTh plus a direct interior-ambient resistance.",
    "TiTeAe": "TiTe with the sun also heating the envelope.",
    "TiTeThAe": "TiTeTh with the sun also heating the envelope.",
    "TiTeThAeRia": "TiTeThRia with the sun also heating the envelope.",
    "TiTmTeThAe": "TiTmTeTh with the sun also heating the envelope.",
    "TiTmTeThAeRia": "TiTmTeThRia with the sun also heating the envelope.",
}
_PARAMETERS = {
    "Ci": {"value": 0.5, "lower": 1.0e-4, "upper": 50, "unit": "kWh/K"},
    "Cm": {"value": 2.0, "lower": 1.0e-4, "upper": 100, "unit": "kWh/K"},
    "Ce": {"value": 3.0, "lower": 1.0e-4, "upper": 100, "unit": "kWh/K"},
    "Ch": {"value": 0.2, "lower": 1.0e-4, "upper": 50, "unit": "kWh/K"},
    "Rih": {"value": 0.5, "lower": 0.001, "upper": 100, "unit": "K/kW"},
    "Rim": {"value": 1.0, "lower": 0.001, "upper": 100, "unit": "K/kW"},
    "Rie": {"value": 1.0, "lower": 0.001, "upper": 100, "unit": "K/kW"},
    "Rea": {"value": 5.0, "lower": 0.001, "upper": 100, "unit": "K/kW"},
    "Ria": {"value": 20, "lower": 0.01, "upper": 1000, "unit": "K/kW"},
    "Aw": {"value": 5.0, "lower": 0.01, "upper": 200, "unit": "m2"},
    "Ae": {"value": 5.0, "lower": 0.01, "upper": 200, "unit": "m2"},
    "sigma_i": {"value": 0.1, "lower": 0, "unit": "K/sqrt(h)"},
    "sigma_m": {"value": 0.1, "lower": 0, "unit": "K/sqrt(h)"},
    "sigma_e": {"value": 0.1, "lower": 0, "unit": "K/sqrt(h)"},
    "sigma_h": {"value": 0.1, "lower": 0, "unit": "K/sqrt(h)"},
    "e_std": {"value": 0.05, "lower": 0, "unit": "K"},
    "Ti0": {"value": 21, "lower": 0, "upper": 40, "unit": "C"},
    "Tm0": {"value": 20, "lower": 0, "upper": 40, "unit": "C"},
    "Te0": {"value": 15, "lower": -20, "upper": 40, "unit": "C"},
    "Th0": {"value": 25, "lower": 0, "upper": 80, "unit": "C"},
}


#: Parameters whose bounds ``bound_factor`` widens (capacities, resistances, aperture).
_WIDENED = ("Ci", "Cm", "Ce", "Ch", "Rih", "Rim", "Rie", "Rea", "Ria", "Aw", "Ae")
#: Parameters that grow with the building (start values and bounds multiplied by the scale).
_EXTENSIVE = ("Ci", "Cm", "Ce", "Ch", "Aw", "Ae")
#: Parameters that shrink with the building (divided by the scale).
_INTENSIVE = ("Rih", "Rim", "Rie", "Rea", "Ria")
#: Heat loss coefficient the family's values were made for [W/K]: the FlexHouse test building
#: of Bacher & Madsen (2011), ~ 170 W/K (mean heating 2.85 kW over a mean indoor-outdoor
#: difference of 16.5 K; the envelope path of the declared values, 1 / (Rie + Rea), is 167 W/K).
FAMILY_HEAT_LOSS = 1000.0 / 6.0


def family_scale(data, heat_unit: str = "kW", source: str = "data") -> tuple[float, float]:
    """Scale of the family for a building: a power of ten near ``H / FAMILY_HEAT_LOSS``.

    ``H = mean(Ph) / mean(yTi - Ta)`` [W/K] is the steady energy balance of the data (solar
    and internal gains left out, so it errs low; the LR tests are not affected, only the start
    values and bounds). Capacities and the aperture are multiplied by the scale, resistances
    divided (time constants kept), so that a building ten or a thousand times the FlexHouse
    has its parameters as far inside the bounds as the FlexHouse has. Rounded to a power of
    ten, so data like the FlexHouse's keep the family as published (scale 1).

    Parameters
    ----------
    data : DataFrame
        Columns ``Ph`` [``heat_unit``], ``yTi`` and ``Ta`` [C].
    heat_unit : str
        Unit of ``Ph``.
    source : str
        Name of the data, for error messages.

    Returns
    -------
    (scale, H)
        The power of ten [-] and the energy-balance heat loss coefficient [W/K].

    Raises
    ------
    ThermocalInputError
        When ``H`` lies above the range of buildings and ``Ph`` read a factor 1000 smaller
        brings it inside (:func:`~thermocal.statespace.units.heat_unit_slip`; a scale of about
        10^3): ``Ph`` in W read as kW. The message names the unit to use, and ``--bounds
        family`` with ``--bound-factor`` for a building that size indeed. A balance below the
        range is not refused: it leaves out the gains and errs low (a test cell, a mostly
        free-floating period); ``thermocal select`` notes the unit that would bring it inside.
        When the room is heated on average while colder than the outdoor air by more than
        :data:`~thermocal.statespace.checks.INVERTED_BALANCE_K`
        (:func:`~thermocal.statespace.checks.inverted_balance_message`: ``Ta`` in Fahrenheit,
        swapped columns): no energy balance gives a scale, and the family's fits mean nothing.
    """
    import numpy as np

    if heat_unit not in HEAT_COLUMN_UNITS:
        raise ThermocalInputError(
            f"heating column unit {heat_unit!r}: use one of {', '.join(HEAT_COLUMN_UNITS)}"
        )
    missing = [c for c in ("Ph", "yTi", "Ta") if c not in data.columns]
    if missing:
        raise ThermocalInputError(
            f"{source}: scaling the family to the data needs column(s) {', '.join(missing)}"
        )
    heat = np.asarray(data["Ph"], dtype=float) * HEAT_COLUMN_UNITS[heat_unit]
    indoor = np.asarray(data["yTi"], dtype=float)
    outdoor = np.asarray(data["Ta"], dtype=float)
    ok = np.isfinite(heat) & np.isfinite(indoor) & np.isfinite(outdoor)
    if ok.sum() < 2:
        return 1.0, math.nan
    mean_heat, mean_diff = float(heat[ok].mean()), float((indoor - outdoor)[ok].mean())
    inverted = inverted_balance_message(
        "yTi", float(indoor[ok].mean()), {"Ta": float(outdoor[ok].mean())},
        f"'Ph' averages {mean_heat / HEAT_COLUMN_UNITS[heat_unit]:.4g} {heat_unit}", mean_heat,
    )  # fmt: skip
    if inverted is not None:
        raise ThermocalInputError(
            f"{source}: {inverted}. For data where this is real, --bounds family fits the "
            "family as published (its fits flag the same)"
        )
    if not (mean_heat > 0 and mean_diff > 0.5):
        # no net heating or no indoor-outdoor difference (cooling season, a free-floating
        # test): no energy balance to scale with; the family as published
        return 1.0, math.nan
    h = mean_heat / mean_diff
    slip = heat_unit_slip(h, heat_unit)
    # only the upward slip: the energy balance leaves out the gains and errs low (a mostly
    # free-floating or sunny period, a test cell), so a small H is no sign of a unit
    if slip is not None and h > PLAUSIBLE_HEAT_LOSS_W_PER_K[1]:
        alt, alt_h = slip
        lo, hi = PLAUSIBLE_HEAT_LOSS_W_PER_K
        raise ThermocalInputError(
            f"{source}: heating 'Ph' read in {heat_unit} (--heat-unit {heat_unit}) gives an "
            f"energy-balance heat loss coefficient of {h:.4g} W/K (mean Ph "
            f"{mean_heat / HEAT_COLUMN_UNITS[heat_unit]:.4g} {heat_unit} over a mean indoor-"
            f"outdoor difference of {mean_diff:.3g} K), outside the range of buildings ({lo:g} "
            f"to {hi:g} W/K); read in {alt} it would be {alt_h:.4g} W/K. Ph in {alt}? use "
            f"--heat-unit {alt}. For a building of {h:.4g} W/K indeed, give --bounds family "
            "--bound-factor 1000 (the family as published, its bounds widened a factor 1000)"
        )
    return 10.0 ** round(math.log10(h / FAMILY_HEAT_LOSS)), h


def bacher_madsen_spec(
    name: str,
    *,
    heat_unit: str = "kW",
    solar_unit: str | None = "kW/m2",
    bound_factor: float = 1.0,
    scale: float = 1.0,
) -> dict:
    """Model-file dictionary of one member (see :func:`bacher_madsen_family`)."""
    if not (scale > 0 and math.isfinite(scale)):
        raise ThermocalInputError(f"family scale {scale!r}: give a positive finite number")
    if not (bound_factor >= 1.0 and math.isfinite(bound_factor)):
        raise ThermocalInputError(
            f"bound factor {bound_factor!r}: give a finite number >= 1 (1: the family's bounds, "
            "10: a decade wider on both sides)"
        )
    if name not in _MEMBERS:
        raise ThermocalInputError(
            f"Bacher & Madsen family: no model '{name}'; members: {', '.join(_MEMBERS)}"
        )
    for unit, what in ((heat_unit, "heating"), (solar_unit, "solar")):
        if unit is not None and unit not in HEAT_COLUMN_UNITS:
            raise ThermocalInputError(
                f"{what} column unit {unit!r}: use one of {', '.join(HEAT_COLUMN_UNITS)}"
            )
    tm, te, th, *rest = _MEMBERS[name]
    ria = not te or "Ria" in rest
    ae = "Ae" in rest
    if ae and solar_unit is None:
        raise ThermocalInputError(f"Bacher & Madsen family: '{name}' needs a solar input (Ps)")
    states = {"Ti": {"capacity": "Ci", "noise": "sigma_i", "initial_mean": "Ti0",
                     "initial_std": 0.1}}  # fmt: skip
    conductances = []
    for flag, s, cap in ((tm, "Tm", "Cm"), (te, "Te", "Ce"), (th, "Th", "Ch")):
        if flag:
            states[s] = {"capacity": cap, "noise": f"sigma_{s[1]}", "initial_mean": f"{s}0",
                         "initial_std": 1.0}  # fmt: skip
    if th:
        conductances.append({"between": ["Ti", "Th"], "resistance": "Rih"})
    if tm:
        conductances.append({"between": ["Ti", "Tm"], "resistance": "Rim"})
    if te:
        conductances.append({"between": ["Ti", "Te"], "resistance": "Rie"})
        conductances.append({"between": ["Te", "Ta"], "resistance": "Rea"})
    if ria:
        conductances.append({"between": ["Ti", "Ta"], "resistance": "Ria"})
    heat_inputs = [{"column": "Ph", "unit": heat_unit, "into": "Th" if th else "Ti"}]
    if solar_unit is not None:
        heat_inputs.append({"column": "Ps", "unit": solar_unit, "into": "Ti", "scale": "Aw"})
    if ae:
        heat_inputs.append({"column": "Ps", "unit": solar_unit, "into": "Te", "scale": "Ae"})
    used = {"Ci", "sigma_i", "e_std", "Ti0"} | ({"Aw"} if solar_unit is not None else set())
    used |= {"Ae"} if ae else set()
    for c in conductances:
        used.add(c["resistance"])
    for spec in states.values():
        used |= {spec["capacity"], spec["noise"], spec["initial_mean"]}
    return {
        "name": name,
        "description": _DESCRIPTIONS[name],
        "states": states,
        "conductances": conductances,
        "heat_inputs": heat_inputs,
        "outputs": [{"column": "yTi", "state": "Ti", "noise": "e_std"}],
        "parameters": {
            k: _widened(k, _scaled(k, v, scale), bound_factor)
            for k, v in _PARAMETERS.items()
            if k in used
        },  # fmt: skip
    }


def _scaled(name: str, spec: dict, scale: float) -> dict:
    out = dict(spec)
    if scale != 1.0 and name in _EXTENSIVE + _INTENSIVE:
        f = scale if name in _EXTENSIVE else 1.0 / scale
        for key in ("value", "lower", "upper"):
            out[key] = spec[key] * f
    return out


def _widened(name: str, spec: dict, factor: float) -> dict:
    out = dict(spec)
    if name in _WIDENED and factor != 1.0:
        out["lower"] = spec["lower"] / factor
        out["upper"] = spec["upper"] * factor
    return out


def bacher_madsen_family(
    *,
    heat_unit: str = "kW",
    solar_unit: str | None = "kW/m2",
    bound_factor: float = 1.0,
    scale: float = 1.0,
) -> tuple[dict[str, RCModel], dict[str, list[str]], str]:
    """The Bacher & Madsen (2011) candidate models, their extensions and the start model.

    Parameters
    ----------
    heat_unit : str
        Unit of the heating column ``Ph``: ``W``, ``kW``, ``MW``.
    solar_unit : str or None
        Unit of the irradiance column ``Ps`` (``W/m2``, ``kW/m2``); None: no solar input.
    bound_factor : float
        The bounds of the capacities [kWh/K], resistances [K/kW] and the aperture [m2] widened
        by this factor on both sides (lower / factor, upper * factor); the defaults were made
        for the FlexHouse data (a 120 m2 test building) and a large building's capacities or
        small resistances can lie beyond them.
    scale : float
        Capacities and the aperture (start values and bounds) multiplied by this factor,
        resistances divided by it: the family for a building ``scale`` times the FlexHouse's
        heat loss coefficient (see :func:`family_scale`, which derives it from the data).

    Returns
    -------
    models : dict
        ``RCModel`` by name (data columns ``Ta`` [C], ``Ph``, ``Ps``, ``yTi`` [C]).
    extensions : dict
        For :func:`thermocal.statespace.forward_selection`.
    start : str
        ``"Ti"``.
    """
    members = [n for n in _MEMBERS if solar_unit is not None or n not in _SOLAR_ENVELOPE]
    models = {
        name: RCModel.from_dict(
            bacher_madsen_spec(
                name,
                heat_unit=heat_unit,
                solar_unit=solar_unit,
                bound_factor=bound_factor,
                scale=scale,
            ),
            source=f"Bacher & Madsen family ({name})",
        )
        for name in members
    }
    extensions = {
        k: [e for e in v if e in models]
        for k, v in BACHER_MADSEN_EXTENSIONS.items()
        if k in models
    }
    return models, extensions, "Ti"


FAMILIES = {"bacher-madsen": bacher_madsen_family}
