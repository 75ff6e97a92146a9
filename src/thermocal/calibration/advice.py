"""Which in-situ measurement would determine which envelope parameters (``posterior.advise``).

"Is it the roof or the walls?" is what a building's heat data answer worst when roof and
walls change the heat with the same time signature: the posterior then determines neither and
says they compensate (:mod:`thermocal.calibration.posterior`). A heat-flux plate on one element
(ISO 9869-1, the campaign's ``in_situ`` section) settles it: measured, its resistance gets a
log-normal prior, and the data's combination then fixes the other. Which element to measure is
answered before anyone goes on site, without simulating: for each element-level resistance in
the posterior that is not measured yet, the posterior is recomputed from the same meta-model
with the plate's reading as an in-situ measurement of the typical uncertainty
(:data:`thermocal.io.heat_flux_log.TYPICAL_REL_STD`). The reading is drawn from what the plate
may give -- the parameter's present posterior (its 90 % interval in log space) widened by the
plate's own spread -- at the three points of a Gauss-Hermite rule (-sqrt(3), 0, +sqrt(3)
standard deviations, weights 1/6, 2/3, 1/6): a parameter is *determined* by the plate with the
weights of the readings after which the posterior determines it (preposterior analysis, Raiffa
and Schlaifer 1961). In the meta-model's coordinates the affine posterior narrows by about the
same amount wherever the reading falls (exactly so in ``log p``, the published coordinates);
whether that is narrow enough to call the parameter determined (its interval against the
sampled range) depends on the level, hence the three readings.

The plate's relative uncertainty applies to the resistance directly: a plate with surface
thermometers measures ``R`` as the ratio of the face-to-face difference to the heat flux, so
its calibration and its spot scale ``R`` as they scale the flux.

Checked against EnergyPlus (docs/calibration.md, "Which measurement next"): on the
5ZoneAirCooled twin with the building-total metric, where neither the roof nor the wall is
determined, the advice expects a plate on the wall to determine both and one on the roof to
determine the roof (the wall only at its outer readings); the real roof plate (EnergyPlus's
roof, ISO 9869-1) narrowed the roof's and the wall's intervals to log widths within 15 % of
the advice's expectation.

References
----------
H. Raiffa and R. Schlaifer, Applied Statistical Decision Theory, Harvard University, 1961.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from thermocal.io.heat_flux_log import TYPICAL_REL_STD
from thermocal.montecarlo import GAUSS_HERMITE_3

__all__ = ["advise_measurements", "measurable_parameters"]


def measurable_parameters(names: Sequence[str], measured) -> list[str]:
    """The element-level resistances a heat-flux plate could measure, not measured yet.

    Parameters
    ----------
    names : sequence of str
        The posterior's parameters.
    measured : collection of str
        The parameters measured in situ already.

    Returns
    -------
    list of str
        The ``construction/<name>/resistance`` among ``names`` not in ``measured``.
    """
    return [
        n for n in names
        if n.startswith("construction/") and n.endswith("/resistance") and n not in measured
    ]  # fmt: skip


def _intervals(posterior) -> dict[str, dict]:
    """Per parameter: median, 90 % interval [unit of each], its width over the sampled range
    [-] and whether the posterior determines it."""
    s = posterior.summary
    return {
        n: {
            "median": float(s.at[n, "median"]),
            "q05": float(s.at[n, "q05"]),
            "q95": float(s.at[n, "q95"]),
            "width_fraction": float(s.at[n, "width_fraction"]),
            "determined": bool(s.at[n, "determined"]),
        }
        for n in s.index
    }


def advise_measurements(
    surrogate,
    names: Sequence[str],
    lower,
    upper,
    posterior,
    *,
    measured: dict | None = None,
    plate_rel_std: float = TYPICAL_REL_STD,
    **posterior_arguments,
) -> dict:
    """The posterior each heat-flux plate would give, against the present one.

    Parameters
    ----------
    surrogate, names, lower, upper
        As for :func:`thermocal.calibration.posterior.calibration_posterior` (the present
        posterior's meta-model, parameters and bounds [unit of each parameter]).
    posterior : Posterior
        The present posterior.
    measured : dict, optional
        The campaign's in-situ measurements: name -> (value, relative standard uncertainty).
    plate_rel_std : float [-]
        Relative standard uncertainty of a plate's resistance (module docstring).
    **posterior_arguments
        The other arguments of the present posterior (bounds of the whole space, units,
        seed, emulator error, discrepancy).

    Returns
    -------
    dict
        ``available``, ``reason`` (when not), ``method``, ``plate_rel_std``, ``now`` (each
        parameter's median, 90 % interval, width over the prior range and whether determined)
        and ``candidates`` (per measurable parameter: the three ``readings``, each
        parameter's ``determined_probability``, those at 0.5 or more as ``determined``, the
        ``expected`` intervals at the median reading and their ``mean_width_fraction``, the
        ``expected_by_reading`` intervals after each of the three readings; the one
        determining most besides its own parameter first), ``summary``.
    """
    from thermocal.calibration.posterior import calibration_posterior

    measured = dict(measured or {})
    method = (
        "preposterior analysis: the posterior recomputed from the same meta-model with each "
        "element's plate readings (three-point Gauss-Hermite rule over what the plate may "
        "read; no simulation)"
    )
    candidates = measurable_parameters(names, measured)
    if not candidates:
        return {
            "available": False,
            "method": method,
            "reason": "no element-level resistance (construction/<name>/resistance, "
            "parameters.level: element) in the posterior that is not measured already",
            "summary": "No measurement advice: no element-level resistance to measure",
        }
    now = _intervals(posterior)
    s_plate = float(np.sqrt(np.log1p(plate_rel_std**2)))
    rows = []
    for name in candidates:
        i = list(names).index(name)
        median = now[name]["median"]
        # the reading's spread: the parameter's present posterior (its draws' in log space)
        # and the plate's
        spread = np.hypot(float(np.std(np.log(posterior.samples[name]))), s_plate)
        probability = dict.fromkeys(now, 0.0)
        readings, central, by_reading = [], None, []
        for z, w in zip(*GAUSS_HERMITE_3, strict=True):
            reading = float(np.clip(median * np.exp(z * spread), lower[i], upper[i]))
            expected = _intervals(
                calibration_posterior(
                    surrogate, names, lower, upper,
                    measured={**measured, name: (reading, plate_rel_std)}, **posterior_arguments,
                )  # fmt: skip
            )
            readings.append(reading)
            by_reading.append(expected)
            for n, v in expected.items():
                probability[n] += w * v["determined"]
            if z == 0.0:
                central = expected
        probability = {n: round(p, 9) for n, p in probability.items()}
        rows.append(
            {
                "parameter": name,
                "readings": readings,
                "determined_probability": probability,
                "determined": [n for n, p in probability.items() if p >= 0.5],
                "mean_width_fraction": float(
                    np.mean([v["width_fraction"] for v in central.values()])
                ),
                "expected": central,
                "expected_by_reading": by_reading,
            }
        )
    # a plate determines what it measures: ranked by what else it settles, then by how much
    # it narrows the intervals
    rows.sort(
        key=lambda r: (
            -sum(p for n, p in r["determined_probability"].items() if n != r["parameter"]),
            r["mean_width_fraction"],
        )
    )
    best = rows[0]
    determined_now = [n for n, v in now.items() if v["determined"]]
    others = [n for n in best["determined"] if n not in determined_now and n != best["parameter"]]
    if others:
        summary = (
            f"A heat-flux plate on {_element(best['parameter'])} (ISO 9869-1, "
            f"{100 * plate_rel_std:.0f} %) would determine {best['parameter']} and, through "
            f"the data, {', '.join(others)} (determined now: {', '.join(determined_now) or 'none'})"
        )
    else:
        summary = (
            "No heat-flux plate would determine a parameter the data leave open other than the "
            f"one it measures (the most informative, on {_element(best['parameter'])}, "
            f"narrows the intervals to {100 * best['mean_width_fraction']:.0f} % of the sampled "
            "ranges on average)"
        )
    return {
        "available": True,
        "method": method,
        "plate_rel_std": plate_rel_std,
        "now": now,
        "candidates": rows,
        "summary": summary,
    }


def _element(parameter: str) -> str:
    """``construction/ROOF-1/resistance`` -> ``construction ROOF-1``."""
    return "construction " + parameter.split("/")[1]
