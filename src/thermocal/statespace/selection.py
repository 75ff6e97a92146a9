"""Forward model selection with likelihood-ratio tests (Bacher & Madsen 2011): from the
simplest model, fit every extension of the current one, take the best eligible and accept it
while the test rejects the simpler model.

References
----------
.. [1] P. Bacher, H. Madsen, "Identifying suitable models for the heat dynamics of buildings",
   Energy and Buildings 43(7), 1511-1522, 2011, sec. 4 (forward selection with likelihood-ratio
   tests).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.statespace.diagnostics import likelihood_ratio_test


@dataclass
class SelectionResult:
    """Outcome of :func:`forward_selection`.

    Attributes
    ----------
    path : list of str
        Models accepted, from the start model to the selected one.
    table : DataFrame
        One row per fitted candidate: iteration, model, parent, loglike, n_free, statistic, df,
        pvalue, selected (best candidate of its iteration), accepted.
    fits : dict
        ``FitResults`` by model name.
    """

    path: list[str]
    table: pd.DataFrame
    fits: dict = field(default_factory=dict)

    @property
    def selected(self) -> str:
        """Name of the finally selected model."""
        return self.path[-1]


#: Parameter roles whose estimate on a bound disqualifies a candidate in forward selection
#: (a noise standard deviation at 0 is a legitimate special case, a capacity at a bound is not).
PHYSICAL_ROLES = frozenset({"capacity", "conductance", "resistance", "scale", "fraction"})
#: A re-polished fit replaces the previous one when it gains more than this [log-units].
REPOLISH_GAIN = 1e-2


def physical_at_bound(res) -> list[str]:
    """Free physical parameters (capacities, conductances, resistances, scales, fractions) of
    a fit whose estimates lie on a bound."""
    roles = res.model.structure().roles
    return [n for n in res.at_bound if roles.get(n, set()) & PHYSICAL_ROLES]


def _confirm_by_extension(res, ext_fit) -> None:
    """Confirm a fit whose only doubt is the agreement of its starts when it reaches the
    converged optimum of a model that contains it: that optimum bounds the restricted model's
    from above, so the restricted optimum is global."""
    from thermocal.statespace.convergence import AGREEMENT_TOLERANCE, CONVERGENCE_GAIN

    if res.converged or not ext_fit.converged:
        return
    if not (math.isfinite(res.expected_gain) and res.expected_gain < CONVERGENCE_GAIN):
        return
    if res.loglike < ext_fit.loglike - AGREEMENT_TOLERANCE:
        return
    res.converged = True
    res.flags = [f for f in res.flags if not f.startswith("global optimum not confirmed")]
    res.flags.append(
        f"global optimum confirmed by the extension '{ext_fit.model.name}': its converged "
        f"optimum ({ext_fit.loglike:.2f}), an upper bound of this model's, is reached"
    )


def _shared_values(res, model) -> dict:
    """Estimates of ``res`` for the free parameters of ``model`` with the same name."""
    return {n: float(res.params[n]) for n in model.free_parameter_names if n in res.params.index}


def forward_selection(
    models: Mapping[str, object],
    extensions: Mapping[str, Sequence[str]],
    data,
    *,
    start: str,
    alpha: float = 0.05,
    n_starts: int | None = None,
    seed: int | None = None,
    hold: str = "zoh",
    time_column: str | None = None,
    time_unit: str = "s",
    callback: Callable[[str, object], None] | None = None,
    input_gaps: str = "error",
    max_gap: int = 3,
) -> SelectionResult:
    """Forward model selection with likelihood-ratio tests (Bacher & Madsen 2011).

    Start with the simplest model; in each iteration fit every extension of the current model,
    take the one with the highest likelihood among the eligible ones and test it against the
    current model; accept it while the test rejects the simpler model at level ``alpha``.

    A candidate is eligible only when its fit converged (the optimiser's criterion and the
    agreement of the best starts, see :func:`thermocal.statespace.estimation.fit`) and none
    of its physical parameters (:data:`PHYSICAL_ROLES`) ends on a bound; the likelihood-ratio
    test is computed only between converged fits. Both directions of nesting are used to
    escape local optima: each extension gets an extra start at the parent's estimates, and the
    parent is re-polished from each extension's estimates (shared parameters); when that
    improves the parent by more than :data:`REPOLISH_GAIN`, the parent's fit is replaced and
    the tests of the iteration use it. The refits this triggers (the parent's multi-start with
    the new start, the extensions from the better parent) take over the ends of the starts
    they share with the earlier fits (``reuse`` of :func:`~thermocal.statespace.estimation.fit`:
    the same start on the same problem ends at the same point) and run only the new ones.

    The eligibility rule holds for the model's best fit, not only for the fit it was accepted
    with: when the re-polish of an accepted model (the current one) finds a better optimum that
    is not eligible (not converged, or a physical parameter on a bound), the pre-polish fit is
    not kept (it is shown not to be the model's optimum, so its test was against a point the
    model does not end at); the model is withdrawn instead: its row says so and is no longer
    accepted, the path steps back to its parent, and the parent's extensions are chosen among
    again without it (in a new iteration of the table). The start model is not withdrawn.

    Parameters
    ----------
    models : mapping
        ``RCModel`` by name.
    extensions : mapping
        For each model name, the names of the models that extend it by one element.
    data : DataFrame
        Inputs and outputs of all models.
    start : str
        Name of the start model.
    alpha : float
        Significance level of the likelihood-ratio tests.
    n_starts, seed, hold, time_column, time_unit, input_gaps, max_gap :
        Passed to :meth:`RCModel.fit`.
    callback : callable, optional
        Called as ``callback(name, fit_results)`` after each fit (progress reporting).

    Returns
    -------
    SelectionResult
        Its table has, besides the test, ``converged``, ``at_bound`` (physical parameters on a
        bound, comma-separated), ``starts_at_best`` and ``status`` (why a candidate was not
        accepted).
    """
    for name in [start, *[c for cs in extensions.values() for c in cs]]:
        if name not in models:
            raise ThermocalInputError(
                f"forward selection: model '{name}' is not among {list(models)}"
            )
    fit_kw = {
        "hold": hold, "time_column": time_column, "time_unit": time_unit,
        "input_gaps": input_gaps, "max_gap": max_gap,
    }  # fmt: skip
    from thermocal.statespace.estimation import shared_pool

    # the starts of all fits in one process pool, forked once with every candidate's
    # compiled kernels loaded
    with shared_pool(_candidate_problems(models, extensions, start, data, fit_kw)):
        return _forward_selection(models, extensions, data, start, alpha, n_starts, seed,
                                  fit_kw, callback)  # fmt: skip


def _candidate_problems(models, extensions, start: str, data, fit_kw: dict) -> list:
    """The likelihood problems of the start model and of every extension (each model once);
    a model whose data cannot be prepared is left out (its fit reports why)."""
    from thermocal.statespace.estimation import prepared_problem

    names = dict.fromkeys([start, *[c for cs in extensions.values() for c in cs]])
    problems = []
    for name in names:
        try:
            problems.append(prepared_problem(models[name], data, **fit_kw))
        except ThermocalInputError:
            continue
    return problems


def _forward_selection(models, extensions, data, start, alpha, n_starts, seed, fit_kw,
                       callback) -> SelectionResult:  # fmt: skip
    """:func:`forward_selection` after the checks, in its process pool."""
    fits: dict = {}

    def fit_model(name, parent_fit=None, reuse=None):
        res = models[name].fit(
            data, n_starts=n_starts, seed=seed, warm_start=parent_fit, reuse=reuse, **fit_kw
        )
        fits[name] = res
        if callback is not None:
            callback(name, res)
        return res

    def repolish(parent: str, ext_fit) -> bool:
        """Refit ``parent`` from the extension's estimates; True when it improved."""
        old = fits[parent]
        start_values = _shared_values(ext_fit, models[parent])
        if not start_values:
            return False
        # one new start, at the extension's estimates (the declared values' end is taken
        # over from the previous fit)
        probe = models[parent].fit(
            data, n_starts=1, seed=seed, warm_start=start_values, compute_hessian=False,
            reuse=old, **fit_kw,
        )  # fmt: skip
        if probe.loglike > old.loglike + REPOLISH_GAIN:
            # a better parent optimum exists: the full multi-start with that start, so that
            # the agreement of the starts is judged as for any fit (the starts run for the
            # previous fit and the probe are taken over, not run again)
            again = models[parent].fit(
                data, n_starts=n_starts, seed=seed, warm_start=start_values, reuse=probe,
                **fit_kw,
            )  # fmt: skip
            if again.loglike < probe.loglike - REPOLISH_GAIN:
                return False  # pragma: no cover - the warm start is among the starts
            again.flags.insert(
                0,
                f"re-polished from the estimates of the extension '{ext_fit.model.name}': "
                f"log-likelihood {old.loglike:.2f} -> {again.loglike:.2f}",
            )
            if old.converged:  # the previous fit had claimed convergence at a poorer point
                again.flags.append(
                    f"the fit inside the selection stopped {again.loglike - old.loglike:.3g} "
                    "log-units below this optimum"
                )
            _confirm_by_extension(again, ext_fit)
            fits[parent] = again
            if callback is not None:
                callback(parent, again)
            return True
        return False

    def status(res) -> str:
        notes = []
        if not res.converged:
            notes.append("not converged")
        bound = physical_at_bound(res)
        if bound:
            notes.append("at bound: " + ", ".join(bound))
        return "; ".join(notes)

    def row(iteration, name, parent, test, selected, accepted, note):
        res = fits[name]
        agreement = res.agreement or {}
        return {
            "iteration": iteration,
            "model": name,
            "parent": parent,
            "loglike": res.loglike,
            "n_free": res.n_free,
            "statistic": np.nan if test is None else test.statistic,
            "df": np.nan if test is None else test.df,
            "pvalue": np.nan if test is None else test.pvalue,
            "selected": selected,
            "accepted": accepted,
            "converged": bool(res.converged),
            "at_bound": ", ".join(physical_at_bound(res)),
            "starts_at_best": agreement.get("n_best", np.nan),
            "status": note,
        }

    fit_model(start)
    rows = [row(0, start, "", None, True, True, status(fits[start]) or "start model")]
    path = [start]
    current = start
    iteration = 0
    withdrawn: set[str] = set()  # accepted, then ineligible after a re-polish
    while extensions.get(current):
        iteration += 1
        candidates = list(extensions[current])
        for cand in candidates:
            if cand not in fits:
                fit_model(cand, fits[current])
        # the other direction: the parent from each extension's estimates
        improved = False
        for cand in candidates:
            improved |= repolish(current, fits[cand])
        if improved:
            # the parent's own row (and its test against its parent) with the better fit
            for r in rows:
                if r["model"] == current:
                    grand = r["parent"]
                    test = likelihood_ratio_test(fits[grand], fits[current]) if grand else None
                    new = row(r["iteration"], current, grand, test, r["selected"],
                              r["accepted"], r["status"])  # fmt: skip
                    new["status"] = "; ".join(
                        filter(None, [status(fits[current]), "re-polished from an extension"])
                    )
                    r.update(new)
            if status(fits[current]) and len(path) > 1:
                # the accepted model's better optimum is not eligible: not accepted after all,
                # the selection steps back to its parent and chooses again without it
                grand = path[-2]
                for r in rows:
                    if r["model"] == current and r["accepted"]:
                        r["accepted"] = False
                        r["status"] = "; ".join([
                            r["status"], "no longer eligible after the re-polish: not accepted, "
                            f"the selection steps back to '{grand}'",
                        ])  # fmt: skip
                for cand in candidates:
                    rows.append(
                        row(iteration, cand, current, None, False, False,
                            "; ".join(filter(None, [status(fits[cand]), f"parent '{current}' "
                                                    "not accepted after its re-polish: no test"])))
                    )  # fmt: skip
                withdrawn.add(current)
                path.pop()
                current = grand
                continue
            # the extensions again from the better parent
            for cand in candidates:
                old = fits[cand]
                fit_model(cand, fits[current], reuse=old)
                if fits[cand].loglike < old.loglike:
                    fits[cand] = old
        parent_ok = fits[current].converged
        tests, notes = {}, {}
        for cand in candidates:
            res = fits[cand]
            note = status(res)
            if parent_ok and res.converged:
                tests[cand] = likelihood_ratio_test(fits[current], res)
            elif not parent_ok:
                note = "; ".join(filter(None, [note, f"parent '{current}' not converged: no test"]))
            notes[cand] = note
        eligible = [
            c for c in candidates
            if c in tests and not physical_at_bound(fits[c]) and c not in withdrawn
        ]  # fmt: skip
        best = max(eligible, key=lambda c: fits[c].loglike) if eligible else None
        accepted = best is not None and tests[best].reject(alpha)
        for cand in candidates:
            note = notes[cand]
            if cand == best and not accepted:
                note = note or f"likelihood-ratio test not significant at {alpha:g}"
            elif cand in withdrawn:
                note = note or "withdrawn after a re-polish made it ineligible"
            elif cand in tests and cand not in eligible:
                note = note or "not eligible"
            rows.append(
                row(iteration, cand, current, tests.get(cand), cand == best,
                    cand == best and accepted, note)
            )  # fmt: skip
        if not accepted:
            break
        path.append(best)
        current = best
    return SelectionResult(path=path, table=pd.DataFrame(rows), fits=fits)
