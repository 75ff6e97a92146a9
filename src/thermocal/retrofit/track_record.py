"""How the retrofit analysis held on houses thermocal did not write (its track record).

The retrofit report states, next to its intervals, how far the same analysis with its default
settings was from EnergyPlus 25.2 on the independent references of the test suite
(docs/retrofit-twins.md, "EnergyPlus twin: NREL SingleFamilyHouse in Zurich" and "Second EnergyPlus
twin"): a user reads the headline numbers against a measured tolerance, not against the
intervals alone; the verification report does the same with the EnergyPlus house of
docs/verify.md. The values are those the references' tests measure
(``tests/retrofit/test_retrofit_energyplus_twin.py``, ``test_retrofit_energyplus_basement.py``,
``test_retrofit_verify.py``, all in CI): they fail when a change of the analysis moves a figure
beyond its rounding, so a report never states a stale record.
"""

from __future__ import annotations

from dataclasses import dataclass

from thermocal.records import differs_from

__all__ = [
    "DETAILED_CHECKS",
    "DetailedCheck",
    "INDEPENDENT_CHECKS",
    "IN_SITU_CHECKS",
    "INDEPENDENT_VERIFICATIONS",
    "IndependentCheck",
    "IndependentVerification",
    "differs_from",
    "measured_check",
    "measured_detailed_check",
    "measured_verification",
]


@dataclass(frozen=True)
class IndependentCheck:
    """One house thermocal did not write, analysed as a user would, against EnergyPlus.

    Attributes
    ----------
    house : str
        What the house is.
    hlc_error_pct, demand_error_pct : float
        Heat loss coefficient and annual heating demand, thermocal / EnergyPlus - 1 [%].
    savings_mean_abs_pp, savings_max_abs_pp : float
        Mean and largest absolute difference of the 15 strategies' savings [percentage points].
    within_3pp, covered : int
        Strategies within 3 pp, and whose 90 % interval contains EnergyPlus's saving [-].
    median_half_width_pp : float
        Median half-width of the savings' 90 % intervals [percentage points].
    gate_passed : bool
        Whether the validation gate passed on the test period.
    note : str
        What explains the largest differences.
    """

    house: str
    hlc_error_pct: float
    demand_error_pct: float
    savings_mean_abs_pp: float
    savings_max_abs_pp: float
    within_3pp: int
    covered: int
    median_half_width_pp: float
    gate_passed: bool
    note: str


#: Measured 2026-11-29, the savings again 2026-11-30 after new windows kept the old ones' films
#: correction, and again 2026-11-30 after the heat fit's controller took the boundary between two
#: measured interval means as their mean (docs/retrofit.md, "The heat fit's set point at the
#: interval boundary (2026-11-30)"; Zurich 2015; six weeks of measurements, 200 draws), keyed by
#: the reference folder under ``tests/reference``.
INDEPENDENT_CHECKS: dict[str, IndependentCheck] = {
    "retrofit_energyplus_house": IndependentCheck(
        house="NREL SingleFamilyHouse (one storey, block walls, slab, attic)",
        hlc_error_pct=-4.6,
        demand_error_pct=10.1,
        savings_mean_abs_pp=5.4,
        savings_max_abs_pp=10.3,
        within_3pp=5,
        covered=13,
        median_half_width_pp=11.8,
        gate_passed=True,
        note="every saving but the slab's below EnergyPlus's: the building file's default air "
        "change (0.5 1/h) against the house's 0.08 1/h puts too much of the loss where no "
        "envelope measure acts, and the new windows' lower g costs the model more of the sun "
        "than EnergyPlus loses; the slab's insulation saves 6 % against Kiva's 0.7 % (ISO "
        "13370 does not see the ground under the house follow its summer)",
    ),
    "retrofit_energyplus_basement": IndependentCheck(
        house="DOE/PNNL single-family prototype (two storeys, unheated basement, attic)",
        hlc_error_pct=0.3,
        demand_error_pct=-3.6,
        savings_mean_abs_pp=3.3,
        savings_max_abs_pp=5.8,
        within_3pp=5,
        covered=15,
        median_half_width_pp=10.7,
        gate_passed=True,
        note="every saving but the attic's above EnergyPlus's, by up to 5.8 pp (walls, "
        "windows and cellar ceiling): the data fix the total heat loss but leave the walls and "
        "windows at 1.01 and 0.94 of their rated U A, where EnergyPlus's conduct 0.88 and "
        "about 0.80, so their measures remove too large a share of the loss "
        "(savings_decomposition.py beside the reference); the report recommended the strategy "
        "EnergyPlus's own savings choose by the same rule (new windows)",
    ),
}


#: The same houses with one more input an energy auditor has: a heat-flux plate on the north
#: wall for two weeks of February (ISO 9869-1, ``in_situ.walls``; EnergyPlus's wall, the plate
#: reading 3 % high). Measured 2026-11-29 (again 2026-11-30 with the heat fit's set point at the
#: interval boundary), same weather, period and draws; the twins' tests
#: ``test_twin_with_an_in_situ_wall_u_value`` keep them current.
IN_SITU_CHECKS: dict[str, IndependentCheck] = {
    "retrofit_energyplus_house": IndependentCheck(
        house="NREL SingleFamilyHouse, with a heat-flux plate on the north wall",
        hlc_error_pct=-5.1,
        demand_error_pct=9.7,
        savings_mean_abs_pp=4.2,
        savings_max_abs_pp=8.1,
        within_3pp=5,
        covered=14,
        median_half_width_pp=8.4,
        gate_passed=True,
        note="the walls' measures within 3 pp of EnergyPlus; the windows' still 5 pp below it: "
        "their U-value part agrees within 1 pp, but the new glass's lower g costs the model "
        "more heat (its window sun goes to the air and the internal mass) than EnergyPlus, "
        "where a third of that sun left through the uninsulated walls anyway",
    ),
    "retrofit_energyplus_basement": IndependentCheck(
        house="DOE/PNNL single-family prototype, with a heat-flux plate on the north wall",
        hlc_error_pct=0.3,
        demand_error_pct=-3.2,
        savings_mean_abs_pp=2.7,
        savings_max_abs_pp=5.1,
        within_3pp=7,
        covered=14,
        median_half_width_pp=9.5,
        gate_passed=True,
        note="the plate brings the walls' measures nearer EnergyPlus (mean difference 3.3 -> "
        "2.7 pp, 5 -> 7 of 15 within 3 pp); the strategies with new windows stay up to 5.1 pp "
        "above it",
    ),
}


@dataclass(frozen=True)
class DetailedCheck:
    """One EnergyPlus house's 16 strategies with the detailed model (the IDF EnergyPlus ran).

    Attributes
    ----------
    house : str
        What the house is.
    baseline_error_pct : float
        The house as it is: thermocal / EnergyPlus's annual heating - 1 [%] (EnergyPlus's first
        year, the reference runs).
    savings_mean_abs_pp, savings_max_abs_pp : float
        Mean and largest absolute difference of the 15 strategies' savings [percentage points].
    within_3pp : int
        Strategies within 3 pp [-].
    note : str
        What is left.
    """

    house: str
    baseline_error_pct: float
    savings_mean_abs_pp: float
    savings_max_abs_pp: float
    within_3pp: int
    note: str


#: Measured 2026-11-30 (Zurich 2015 after a warm-up year, 15-minute steps;
#: ``tests/reference/retrofit_energyplus_house/measure_detailed.py``), keyed by the reference
#: folder; ``tests/retrofit/test_retrofit_detailed.py`` keeps them current.
DETAILED_CHECKS: dict[str, DetailedCheck] = {
    "retrofit_energyplus_house": DetailedCheck(
        house="NREL SingleFamilyHouse (slab on Kiva, attic, garage)",
        baseline_error_pct=-8.4,
        savings_mean_abs_pp=1.3,
        savings_max_abs_pp=3.0,
        within_3pp=15,
        note="against EnergyPlus's second year (its ground after a year of the house, as the "
        "warm-up year here) the baseline is -5.7 %; with the floors adiabatic the two engines "
        "agree (9,208 against 9,195 kWh): the gap is the ground's share of the heating "
        "(229 against about 810 kWh in the second years): below the floor's surface the ground "
        "section conducts 22 % less than Kiva's",
    ),
    "retrofit_energyplus_basement": DetailedCheck(
        house="DOE/PNNL single-family prototype (unheated basement on Kiva, attic)",
        baseline_error_pct=-0.8,
        savings_mean_abs_pp=0.2,
        savings_max_abs_pp=0.3,
        within_3pp=15,
        note="the basement's air 0.9-1.2 K warmer than EnergyPlus's in winter, up to 1.7 K in "
        "summer",
    ),
}


def measured_detailed_check(result, reference: dict, measures) -> dict:
    """The figures of a :class:`DetailedCheck` from a detailed-model run and its reference.

    Parameters
    ----------
    result : thermocal.retrofit.detailed.DetailedRetrofitResult
        The strategies, the first without measures.
    reference : dict
        The reference's ``reference.json`` (``annual_heating_kWh`` and ``saving_pct`` by
        strategy key, the measures joined by "+" in the order of ``measures``).
    measures : sequence of str

    Returns
    -------
    dict
        The fields of :class:`DetailedCheck` but ``house`` and ``note`` (unrounded).
    """
    import numpy as np

    diff = []
    for strategy, saving in zip(result.strategies[1:], result.saving_pct[1:], strict=True):
        key = "+".join(m for m in measures if m in strategy.measures)
        diff.append(abs(float(saving) - reference["saving_pct"][key]))
    diff = np.asarray(diff)
    base = float(result.annual_kwh[0])
    return {
        "baseline_error_pct": 100.0 * (base / reference["annual_heating_kWh"]["none"] - 1.0),
        "savings_mean_abs_pp": float(diff.mean()),
        "savings_max_abs_pp": float(diff.max()),
        "within_3pp": int((diff <= 3.0).sum()),
    }


@dataclass(frozen=True)
class IndependentVerification:
    """One post-retrofit verification of a house thermocal did not write, against EnergyPlus.

    Attributes
    ----------
    case : str
        The house, its control and the retrofit.
    error_pp : float
        The verified (normalised, reference-year) saving minus EnergyPlus's annual saving
        [percentage points].
    covered : bool
        Whether the verified saving's 90 % interval contains EnergyPlus's.
    post_period_error_pp : float
        The post period's avoided-energy saving minus EnergyPlus's own counterfactual
        (the house without the retrofit over the same weeks) [percentage points].
    verdict : str
        The verdict the verification gave.
    """

    case: str
    error_pp: float
    covered: bool
    post_period_error_pp: float
    verdict: str


#: Measured 2026-11-29, again 2026-11-30 with the heat fit's set point at the interval boundary
#: (``tests/reference/verify_energyplus_house`` with its configuration:
#: Chicago TMY3 reference year, the heat fit with the split inside, 40 draws), keyed by variant.
#: With the default 200 draws the set-back case's interval is 21.1-44.9 %, wider than the
#: inconclusive limit (10 pp either side): its verdict is then "inconclusive".
INDEPENDENT_VERIFICATIONS: dict[str, IndependentVerification] = {
    "constant_20": IndependentVerification(
        case="EnergyPlus house held at 20 C, walls 12 -> 30 cm mineral wool (40 draws)",
        error_pp=0.9,
        covered=True,
        post_period_error_pp=0.1,
        verdict="delivered",
    ),
    "setback": IndependentVerification(
        case="the same house with its 4 K night set-back, four zones on their own schedules "
        "(40 draws; with 200 its interval, 21-45 %, is too wide: inconclusive)",
        error_pp=2.6,
        covered=True,
        post_period_error_pp=2.6,
        # the rooms 1.0 K warmer after the retrofit (the insulated house cools less at
        # night) take back 5.3 pp since the comfort baseline takes the residual adjustment
        # at its own indoor-outdoor difference (2026-12-01; 4.8 pp before: delivered)
        verdict="rebound",
    ),
}


def measured_verification(verification, truth: dict) -> dict:
    """The figures of an :class:`IndependentVerification` from a run and its truth.

    Parameters
    ----------
    verification : thermocal.retrofit.verify.Verification
        The run.
    truth : dict
        The reference's ``truth.json``: ``annual_saving_pct`` and ``post_period_saving_pct``
        [%].

    Returns
    -------
    dict
        The fields of :class:`IndependentVerification` but ``case`` (unrounded).
    """
    av = verification.avoided
    norm = av["normalised_saving_pct"]
    true = truth["annual_saving_pct"]
    return {
        "error_pp": float(norm["value"] - true),
        "covered": bool(norm["lo"] <= true <= norm["hi"]),
        "post_period_error_pp": float(av["saving_pct"] - truth["post_period_saving_pct"]),
        "verdict": str(verification.comparison["verdict"]),
    }


def measured_check(results: dict, reference: dict, measures) -> dict:
    """The figures of an :class:`IndependentCheck` from one analysis and its reference.

    Parameters
    ----------
    results : dict
        ``results.json`` of ``thermocal retrofit`` on the house.
    reference : dict
        The reference's ``reference.json``: ``heat_loss_coefficient_W_per_K`` [W/K],
        ``annual_heating_kWh`` by strategy key ("none" the house as it is) [kWh] and
        ``saving_pct`` by strategy key [%], a key being the strategy's measures joined by "+"
        in the order of ``measures``.
    measures : sequence of str
        The measure names in the order the reference's keys use.

    Returns
    -------
    dict
        The fields of :class:`IndependentCheck` but ``house`` and ``note`` (percentages and
        percentage points unrounded).
    """
    import numpy as np

    diff, covered, half = [], 0, []
    for s in results["scenarios"][1:]:
        truth = reference["saving_pct"]["+".join(m for m in measures if m in s["measures"])]
        diff.append(abs(s["saving_pct"] - truth))
        covered += s["saving_pct_p05"] <= truth <= s["saving_pct_p95"]
        half.append(0.5 * (s["saving_pct_p95"] - s["saving_pct_p05"]))
    diff = np.asarray(diff)
    hlc = results["heat_loss_coefficient_W_per_K"]["value"]
    demand = results["annual_heating_demand_kWh"]["value"]
    return {
        "hlc_error_pct": 100.0 * (hlc / reference["heat_loss_coefficient_W_per_K"] - 1.0),
        "demand_error_pct": 100.0 * (demand / reference["annual_heating_kWh"]["none"] - 1.0),
        "savings_mean_abs_pp": float(diff.mean()),
        "savings_max_abs_pp": float(diff.max()),
        "within_3pp": int((diff <= 3.0).sum()),
        "covered": int(covered),
        "median_half_width_pp": float(np.median(half)),
        "gate_passed": bool(results["validation_gate"]["passed"]),
    }


def reference_recommendation(results: dict, reference: dict, measures) -> str | None:
    """The strategy the report's rule (:func:`thermocal.retrofit.economics.recommend`) chooses
    from the reference's own annual heating, with the run's costs and prices.

    Parameters
    ----------
    results : dict
        ``results.json`` of ``thermocal retrofit``: the scenarios' investments and the
        economics' ``system_efficiency`` and ``energy_price``.
    reference : dict
        The reference's ``reference.json`` (``annual_heating_kWh`` by strategy key).
    measures : sequence of str
        The measure names in the order the reference's keys use.

    Returns
    -------
    The strategy's code, or None when nothing pays back.
    """
    import numpy as np
    import pandas as pd

    from thermocal.retrofit.economics import recommend

    eco = results["economics"]
    rows = results["scenarios"]
    kwh = np.array([
        reference["annual_heating_kWh"]["+".join(m for m in measures if m in s["measures"])
                                        or "none"]
        for s in rows
    ])  # fmt: skip
    cost = kwh / eco["system_efficiency"] * eco["energy_price"]
    saving = cost[0] - cost
    invest = np.array([s["economics"]["investment"] for s in rows])
    with np.errstate(divide="ignore", invalid="ignore"):
        payback = np.where(saving > 0, invest / saving, np.nan)
    table = pd.DataFrame({"code": [s["code"] for s in rows], "cost_saving_per_year": saving,
                          "payback_years": payback})  # fmt: skip
    rec = recommend(table, 100.0 * (1.0 - kwh / kwh[0]))
    return None if rec is None else str(rec["code"])
