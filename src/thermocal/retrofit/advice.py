"""Which measurement would narrow the savings most: the expected intervals after an in-situ
U-value of each envelope component the building has (value of information).

The heating data fix a house's total heat loss; how it splits over roof, walls and the rest is
mostly the prior's (the U-value uncertainty), and each measure's saving depends on that split
(:mod:`thermocal.retrofit.correction`). A heat-flux plate on one component for a week or two of
winter (ISO 9869-1, :mod:`thermocal.retrofit.in_situ`) gives that component a factor of its
own; how much it narrows the savings' intervals depends on the component's share and on what
the plate will read. This module answers before anyone goes on site, by preposterior analysis
(Raiffa and Schlaifer 1961): for each component that can carry a plate and is not yet measured,
the plate's reading is drawn from what the calibrated model now expects of it -- the
component's current factor ``k`` with its posterior spread and the plate's own uncertainty,
``ln U_plate ~ N(ln(k U_described), s_k^2 + s_plate^2)`` -- at the three points of a
Gauss-Hermite rule (weights 1/6, 2/3, 1/6 at -sqrt(3), 0, +sqrt(3) standard deviations), the
whole analysis is run again with that reading as ``in_situ``, and the half-widths of the
savings' intervals are averaged with the rule's weights. Each run is the analysis itself (one
implementation of the calibration and the draws). The plate splits the component from the
roof-and-walls group, whose shared factor the data fixed together with its other members: the
component's own factor is then known only to the description's spread, so the readings are
drawn with the wider of the group's posterior spread and its prior one.

The runs draw at least :data:`ADVICE_DRAWS` parameter sets: a plate adds a factor, so its runs
draw other random numbers than the present analysis, and what the advice compares carries the
Monte Carlo error of the intervals' ends (the results' ``saving_pct_mcse``: its median over
the strategies 0.47 pp on the basement house at 1,000 draws; the median half-width over the
strategies: 12.0 and 12.3 pp with seeds 0 and 1 on the first EnergyPlus house, 12.6 and 12.2
pp with 200 draws). A narrowing smaller than the present run's median end error is reported
as none.

Checked against EnergyPlus (docs/retrofit.md, "Which measurement next"): on both independent
houses the expected median half-width after a plate on the walls lies within 1 pp of what the
real plate then gave.

References
----------
H. Raiffa and R. Schlaifer, Applied Statistical Decision Theory, Harvard University, 1961
(preposterior analysis, the expected value of sample information).
ISO 9869-1:2014, Thermal insulation -- Building elements -- In-situ measurement of thermal
resistance and thermal transmittance -- Part 1: Heat flow meter method.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.io.heat_flux_log import TYPICAL_REL_STD, InSituConfig
from thermocal.montecarlo import GAUSS_HERMITE_3
from thermocal.retrofit.config import MIN_DRAWS

__all__ = [
    "ADVICE_DRAWS",
    "PLATE_REL_STD",
    "ComponentAdvice",
    "advice_summary",
    "advise_measurements",
    "check_advice_draws",
    "measurable_components",
]

#: Relative standard uncertainty [-] of the plate the advice assumes
#: (:data:`thermocal.io.heat_flux_log.TYPICAL_REL_STD`).
PLATE_REL_STD = TYPICAL_REL_STD
#: Parameter draws of the analyses the advice compares (module docstring: their Monte Carlo
#: error).
ADVICE_DRAWS = 1000
#: The largest U-value an ``in_situ`` entry takes [W/(m2 K)] (:class:`InSituConfig`).
_MAX_U = next(m.le for m in InSituConfig.model_fields["u_value"].metadata if hasattr(m, "le"))


@dataclass(frozen=True)
class ComponentAdvice:
    """What a heat-flux plate on one component is expected to do to the savings' intervals.

    Attributes
    ----------
    component : str
        An ``in_situ`` key (``walls``, ``roof``, ...).
    where : str
        The building-file component the plate would go on (the largest of its type).
    described_u, expected_u : float [W/(m2 K)]
        The building file's U-value and the calibrated model's current estimate of it.
    reading_rel_std : float [-]
        Relative spread of the expected reading (the estimate's and the plate's).
    median_half_width_pp, expected_median_half_width_pp : float [percentage points]
        Median over the strategies of their savings' interval half-widths, now and expected
        after the plate.
    recommended_half_width_pp, expected_recommended_half_width_pp : float or None [pp]
        The same for the recommended strategy (None: nothing recommended).
    half_widths_pp : dict code -> (now, expected) [pp]
        Per strategy.
    seconds : float [s]
        Wall time of its three analyses (their share of the pool's).
    """

    component: str
    where: str
    described_u: float
    expected_u: float
    reading_rel_std: float
    median_half_width_pp: float
    expected_median_half_width_pp: float
    recommended_half_width_pp: float | None
    expected_recommended_half_width_pp: float | None
    half_widths_pp: dict
    seconds: float

    @property
    def element(self) -> str:
        """The component in words."""
        from thermocal.retrofit.correction import COMPONENT_WORDS

        return COMPONENT_WORDS[self.component]

    @property
    def label(self) -> str:
        """The measurement in words."""
        return f"heat-flux plate on the {self.element}"


def measurable_components(cfg, building) -> list[tuple[str, str, float]]:
    """The components a plate could go on that are not measured yet.

    Returns
    -------
    list of (in_situ key, building-file component name, described U [W/(m2 K)])
        One per type present (its largest component), in the order of
        :data:`thermocal.retrofit.config.IN_SITU_COMPONENTS`.
    """
    from thermocal.retrofit.config import IN_SITU_COMPONENTS

    out = []
    for key, (_, kind, _) in IN_SITU_COMPONENTS.items():
        if key in cfg.in_situ:
            continue
        of_kind = [c for c in building.components if c.type == kind and float(c.area) > 0]
        if of_kind:
            largest = max(of_kind, key=lambda c: float(c.area))
            out.append((key, largest.name, float(largest.u_value)))
    return out


def _half_widths(results: dict) -> tuple[dict[str, float], float]:
    """Half-width [pp] of every strategy's saving interval (results.json ``scenarios``), and
    the median Monte Carlo error of their ends [pp]."""
    scenarios = results["scenarios"][1:]
    widths = {s["code"]: 0.5 * (s["saving_pct_p95"] - s["saving_pct_p05"]) for s in scenarios}
    return widths, float(np.median([s.get("saving_pct_mcse") or 0.0 for s in scenarios]))


def _group_of(component: str) -> str:
    from thermocal.retrofit.correction import GROUPS

    return next(g for g, members in GROUPS.items() if component in members)


@contextmanager
def _quiet():
    """The repeated analyses' warnings were the first analysis's: not logged again."""
    logger = logging.getLogger("thermocal")
    level = logger.level
    logger.setLevel(logging.ERROR)
    try:
        yield
    finally:
        logger.setLevel(level)


def _half_widths_of(variant) -> tuple[dict[str, float], float]:
    """:func:`_half_widths` of an analysis of ``variant`` (a configuration)."""
    from thermocal.retrofit import run_retrofit
    from thermocal.retrofit.outputs import results_dict

    with _quiet():
        return _half_widths(results_dict(run_retrofit(variant)))


def _run_all(variants: list, workers: int, progress) -> list[tuple[dict[str, float], float]]:
    """:func:`_half_widths_of` of every variant, on a pool of ``workers`` processes."""
    import os

    workers = min(int(workers), os.cpu_count() or 1)
    if workers <= 1 or len(variants) == 1:
        out = []
        for i, v in enumerate(variants):
            if progress:
                progress(f"measurement advice: analysis {i + 1} of {len(variants)}")
            out.append(_half_widths_of(v))
        return out
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor

    # spawned: the analysis has used OpenMP (numba, BLAS) by now, after which fork is unsafe
    ctx = mp.get_context("spawn")
    with ProcessPoolExecutor(min(workers, len(variants)), mp_context=ctx) as pool:
        futures = [pool.submit(_half_widths_of, v) for v in variants]
        out = []
        for i, f in enumerate(futures):
            out.append(f.result())
            if progress:
                progress(f"measurement advice: {i + 1} of {len(variants)} analyses done")
        return out


def advice_summary(advice: list, mcse: float, plate_rel_std: float, gate: dict | None) -> str:
    """The sentence of the advice: the most narrowing plate, or none; a plate that widens.

    Parameters
    ----------
    advice : list of ComponentAdvice
        The most narrowing first.
    mcse : float
        The present run's median Monte Carlo error of an interval end [pp].
    plate_rel_std : float
        The plate's relative standard uncertainty [-].
    gate : dict or None
        The validation gate's verdict (``passed``).

    Returns
    -------
    str
    """
    best = advice[0]
    summary = (
        f"A {best.label} would narrow the savings' intervals most: their median half-width "
        f"{best.median_half_width_pp:.1f} pp -> {best.expected_median_half_width_pp:.1f} pp "
        f"expected (plate {100 * plate_rel_std:.0f} %)"
    )
    if best.expected_median_half_width_pp > best.median_half_width_pp - max(0.5, mcse):
        summary = (
            "No heat-flux plate would narrow the savings' intervals by more than their Monte "
            f"Carlo error ({mcse:.1f} pp; the best, on the {best.element}: median half-width "
            f"{best.median_half_width_pp:.1f} -> {best.expected_median_half_width_pp:.1f} pp): "
            "what is left is not the envelope's split (the windows, the air change, the inputs)"
        )
    # a plate gives its element a factor of its own: another model, whose intervals can be wider
    widening = [
        a
        for a in advice
        if a.expected_median_half_width_pp > a.median_half_width_pp + max(0.5, 2.0 * mcse)
    ]
    if widening:
        text = "; ".join(
            f"a {a.label} would widen them ({a.median_half_width_pp:.1f} -> "
            f"{a.expected_median_half_width_pp:.1f} pp, averaged over the readings it can give)"
            for a in widening
        )
        summary += f". {text[0].upper()}{text[1:]}: not a measurement to make for these savings"
    if gate is not None and not gate["passed"]:
        summary = (
            "The calibrated model failed its validation, so its intervals are not reliable "
            "either; were it valid: " + summary[0].lower() + summary[1:]
        )
    return summary


def check_advice_draws(draws: int, option: str = "uncertainty.draws:", source: str = "") -> None:
    """Refuse ``--advise`` for an analysis without intervals (``uncertainty.draws: 0``).

    The advice compares the widths of the savings' intervals before and after a heat-flux
    plate; an analysis that asks for no uncertainty analysis has none to narrow.

    Parameters
    ----------
    draws : int
        Parameter draws of the analysis [-].
    option : str
        How the user set them, for the message: ``"uncertainty.draws:"`` (the retrofit
        configuration) or ``"--draws"`` (``thermocal demo``).
    source : str
        The configuration file, for the message ("" when none).

    Raises
    ------
    ThermocalInputError
        When ``draws`` is 0.
    """
    if draws == 0:
        where = f" in {source}" if source else ""
        raise ThermocalInputError(
            f"--advise compares the widths of the savings' intervals, but {option} 0{where} "
            f"asks for none (no uncertainty analysis): give {option} 200 (the default; at "
            f"least {MIN_DRAWS}) or drop --advise"
        )


def advise_measurements(
    cfg,
    analysis,
    *,
    components: Sequence[str] | None = None,
    plate_rel_std: float = PLATE_REL_STD,
    draws: int | None = None,
    workers: int = 2,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """The expected savings' intervals after an in-situ U-value of each measurable component.

    Parameters
    ----------
    cfg : RetrofitConfig
        The analysis's configuration.
    analysis : RetrofitAnalysis
        Its result (:func:`thermocal.retrofit.run_retrofit`).
    components : sequence of str, optional
        Only these ``in_situ`` keys (default: every measurable one).
    plate_rel_std : float [-]
        Relative standard uncertainty of the plate's U-value.
    draws : int, optional
        Parameter draws [-] of every analysis the advice runs, the present one included (at
        least the configuration's; default :data:`ADVICE_DRAWS`; module docstring: their
        Monte Carlo error).
    workers : int
        Processes running the analyses [-] (at most the machine's cores).
    progress : callable, optional
        Called with a message as the analyses run.

    Returns
    -------
    dict
        ``available`` (bool), ``reason`` (when not), ``method``, ``plate_rel_std``,
        ``draws``, ``mcse_pp`` (the present run's median Monte Carlo error of an interval
        end), ``components`` (:class:`ComponentAdvice` as dicts with their ``label`` and
        ``element``, the most narrowing first) and ``summary`` (one sentence).
    """
    from thermocal.retrofit.correction import (
        FACTOR_BOUNDS,
        prior_std_log,
        shared_factor_components,
    )
    from thermocal.retrofit.tables import _recommended_code

    check_advice_draws(cfg.uncertainty.draws, source="the retrofit configuration")
    method = (
        "preposterior analysis: the plate's reading drawn from the calibrated model's current "
        "estimate of the component (three-point Gauss-Hermite rule), the analysis rerun with "
        "it as in_situ, the savings' interval half-widths averaged"
    )
    correction = analysis.calibration.correction
    if correction is None:
        return {
            "available": False,
            "method": method,
            "reason": "the envelope groups are not corrected (model.correction: none or "
            "uncertainty.u_value_rel_std 0): an in-situ U-value would have nothing to inform",
        }
    candidates = measurable_components(cfg, analysis.building)
    if components is not None:
        candidates = [c for c in candidates if c[0] in set(components)]
    if not candidates:
        return {
            "available": False,
            "method": method,
            "reason": "every component a heat-flux plate can measure is measured or absent",
        }
    draws = max(int(ADVICE_DRAWS if draws is None else draws), cfg.uncertainty.draws)
    base = cfg.model_copy(
        update={"uncertainty": cfg.uncertainty.model_copy(update={"draws": draws})}
    )
    s_plate = prior_std_log(plate_rel_std)
    low, high = FACTOR_BOUNDS
    shared = shared_factor_components(analysis.model.envelope, cfg.in_situ)
    nodes, weights = GAUSS_HERMITE_3
    variants, plan = [base], []
    for key, name, described in candidates:
        group = _group_of(key)
        k_now = float(correction.factors[group])
        spread_k = correction.posterior_std.get(group, 0.0)
        if group == "k_env" and len(shared) > 1:
            # split from the group, the component's own factor is known to its prior's spread
            spread_k = max(spread_k, correction.prior_std.get(group, 0.0))
        spread = float(np.hypot(spread_k, s_plate))
        plan.append((key, name, described, k_now, spread))
        for z in nodes:
            k = float(np.clip(k_now * np.exp(z * spread), low * 1.001, high * 0.999))
            spec = InSituConfig(
                u_value=round(min(k * described, _MAX_U), 6),
                rel_std=plate_rel_std,
                component=name,
            )
            variants.append(base.model_copy(update={"in_situ": {**cfg.in_situ, key: spec}}))
    t0 = time.perf_counter()
    widths = _run_all(variants, workers, progress)
    seconds = (time.perf_counter() - t0) / len(variants)
    now, mcse = widths[0]
    recommended = _recommended_code(analysis)
    advice = []
    for i, (key, name, described, k_now, spread) in enumerate(plan):
        runs = [w for w, _ in widths[1 + 3 * i : 4 + 3 * i]]
        expected = {c: sum(w * r[c] for w, r in zip(weights, runs, strict=True)) for c in now}
        advice.append(
            ComponentAdvice(
                component=key,
                where=name,
                described_u=described,
                expected_u=k_now * described,
                reading_rel_std=float(np.sqrt(np.expm1(spread**2))),
                median_half_width_pp=float(np.median(list(now.values()))),
                expected_median_half_width_pp=float(np.median(list(expected.values()))),
                recommended_half_width_pp=now.get(recommended),
                expected_recommended_half_width_pp=expected.get(recommended),
                half_widths_pp={c: (now[c], expected[c]) for c in now},
                seconds=3 * seconds,
            )
        )
    advice.sort(key=lambda a: a.expected_median_half_width_pp)
    summary = advice_summary(advice, mcse, plate_rel_std, analysis.gate)
    return {
        "available": True,
        "method": method,
        "plate_rel_std": plate_rel_std,
        "draws": draws,
        "mcse_pp": mcse,
        "components": [asdict(a) | {"label": a.label, "element": a.element} for a in advice],
        "summary": summary,
    }
