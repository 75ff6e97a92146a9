"""Profile-likelihood confidence intervals of parameters and derived quantities.

The profile log-likelihood of a quantity ``g`` is ``l_p(c) = max { l(theta) : g(theta) = c }``;
the interval ``{c : 2 (l_hat - l_p(c)) <= chi2_(1-alpha)(1)}`` (Wilks) follows the likelihood
where it is skewed or bounded, unlike the Wald interval from the curvature at the optimum.

- a parameter: ``g`` is the parameter itself; each ``l_p(c)`` is a fit of the model with that
  parameter fixed at ``c``, warm-started from the nearest profile point already computed;
- a derived quantity (``derived:`` in the model file): each ``l_p(c)`` is a constrained
  maximisation (SLSQP on the unconstrained parameters, the equality ``g(theta) = c``).

The end points are found by bracketing outwards from the Wald end points (doubling steps; a
failed or out-of-range step is taken back and halved) and Brent's method. An end is "open" only
when the profile stays above the threshold up to the parameter's bound (or the edge of the range
a derived quantity can reach within the bounds).

References
----------
.. [1] Y. Pawitan, "In All Likelihood", Oxford University Press, 2001, sec. 2.9 and 3.4
   (profile likelihood, likelihood-based intervals).
.. [2] D. J. Venzon, S. H. Moolgavkar, "A method for computing profile-likelihood-based
   confidence intervals", Applied Statistics 37(1), 87-94, 1988.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from scipy import optimize

from thermocal.errors import ThermocalInputError
from thermocal.statespace.convergence import AGREEMENT_TOLERANCE
from thermocal.statespace.distributions import chi2_quantile

#: Largest number of outward steps per side before the interval is declared open.
MAX_STEPS = 12
#: Steps taken back and halved in a row (after a failed profile point) before the edge of the
#: reachable range is taken as reached.
MAX_HALVINGS = 8
#: Iteration limit of a constrained profile fit (SLSQP): with unidentifiable directions it
#: otherwise spends 500 iterations (20 s on 300 samples) for a gain of a few 1e-3 log-units.
SLSQP_MAXITER = 150
#: Distance on a parameter's unconstrained (log/logit) scale taken as its bound.
BOUND_SPAN = 40.0
#: Stall tolerance of the profile fits (tighter than the default fit's).
PROFILE_STALL_TOLERANCE = 1e-5
#: Fall of the profile log-likelihood from the nearest point already computed, beyond what the
#: quadratic approximation at the optimum foresees, above which a point is refitted from the
#: optimum too [log-units]: the 95 % interval's whole depth (1.92).
PROFILE_JUMP = 1.92


def _inside(model, values: dict) -> dict:
    """``values`` moved strictly inside the bounds of ``model``'s free parameters."""
    out = dict(values)
    for name in model.free_parameter_names:
        p = model.parameters[name]
        v = float(out.get(name, p.value))
        span = p.upper - p.lower
        eps = 1e-9 * span if math.isfinite(span) else 1e-9 * max(abs(v), 1.0)
        if math.isfinite(p.lower):
            v = max(v, p.lower + eps)
        if math.isfinite(p.upper):
            v = min(v, p.upper - eps)
        out[name] = v
    return out


class _ParameterProfile:
    """``l_p`` of one free parameter, on its unconstrained scale ``t``."""

    def __init__(self, res, name: str) -> None:
        self.res = res
        self.name = name
        self.p = res.model.parameters[name]
        self.i = res.model.free_parameter_names.index(name)
        self.center = float(res.theta[self.i])
        se = math.sqrt(res._cov_theta[self.i, self.i]) if res._cov_theta.size else math.nan
        self.step = se if math.isfinite(se) and se > 0 else 0.5
        #: the standard error the quadratic approximation foresees falls with (nan: none)
        self.se = se if math.isfinite(se) and se > 0 else math.nan
        self.cache: dict[float, tuple[float, dict]] = {self.center: (res.loglike, res.params)}

    def value(self, t: float) -> float:
        return self.p.from_unconstrained(t)

    def __call__(self, t: float) -> float:
        nearest = min(self.cache, key=lambda s: abs(s - t))
        start = _inside(self.res.model, self.cache[nearest][1].to_dict())
        start[self.name] = self.value(t)
        model = self.res.model.with_parameters(start)
        model.parameters[self.name].fixed = True
        model._structure = None
        if model.n_free == 0:
            ll = model.loglike(self.res.data, hold=self.res.hold)
            params = pd.Series(start)
        else:
            fitted = self.res.refit(
                model, n_starts=1, compute_hessian=False, n_jobs=1, progress=False,
                stall_tolerance=PROFILE_STALL_TOLERANCE,
            )  # fmt: skip
            ll, params = fitted.loglike, fitted.params
            if self.cache[nearest][0] - ll - self.foreseen_fall(nearest, t) > PROFILE_JUMP:
                # a fall this much larger than foreseen may be a refit that failed from its
                # start (it poisoned the points after it: two resistances in series, whose
                # profile is flat, ended at 2.53 where 4 reaches the optimum); again from the
                # optimum
                again = _inside(self.res.model, self.res.params.to_dict())
                again[self.name] = self.value(t)
                retry = self.res.refit(
                    model.with_parameters(again), n_starts=1, compute_hessian=False, n_jobs=1,
                    progress=False, stall_tolerance=PROFILE_STALL_TOLERANCE,
                )  # fmt: skip
                if retry.loglike > ll:
                    ll, params = retry.loglike, retry.params
        self.cache[t] = (ll, params)
        return ll

    def foreseen_fall(self, s: float, t: float) -> float:
        """The fall of the log-likelihood from ``s`` to ``t`` (unconstrained scale) that the
        quadratic approximation at the optimum foresees [log-units]; 0 where it rises or
        without a standard error."""
        if not math.isfinite(self.se):
            return 0.0
        fall = ((t - self.center) ** 2 - (s - self.center) ** 2) / (2.0 * self.se**2)
        return max(fall, 0.0)


class _DerivedProfile:
    """``l_p`` of a derived quantity, on its natural scale."""

    def __init__(self, res, name: str, func=None, se: float = math.nan, theta_func=None) -> None:
        from thermocal.statespace.kalman import _hold_flag
        from thermocal.statespace.likelihood import LikelihoodProblem

        self.res = res
        self.name = name
        #: {parameter: value [declared units]} -> the quantity
        self.func = func or (lambda values: res.model.derived_values(values)[name])
        #: the same as a function of the unconstrained free parameters (faster), optional
        self.theta_func = theta_func
        self.problem = LikelihoodProblem(res.model, res.data, _hold_flag(res.hold))
        self.free = [res.model.parameters[n] for n in res.model.free_parameter_names]
        self.base = res.params.to_dict()
        self.center = float(self.g(res.theta))
        if func is None:
            derived = res.derived()
            se = float(derived.loc[name, "std_error"]) if name in derived.index else math.nan
        self.step = se if math.isfinite(se) and se > 0 else 0.1 * max(abs(self.center), 1e-6)
        self.cache: dict[float, tuple[float, np.ndarray]] = {
            self.center: (res.loglike, np.asarray(res.theta, dtype=float))
        }

    def g(self, theta) -> float:
        if self.theta_func is not None:
            return float(self.theta_func(np.asarray(theta, dtype=float)))
        values = dict(self.base)
        for p, t in zip(self.free, theta, strict=True):
            values[p.name] = p.from_unconstrained(float(t))
        return self.func(values)

    def value(self, c: float) -> float:
        return c

    def __call__(self, c: float) -> float:
        nearest = min(self.cache, key=lambda s: abs(s - c))
        theta0 = self.problem.clip(self.cache[nearest][1])
        scale = max(abs(self.step), 1e-12)

        def constraint(theta):
            return (self.g(theta) - c) / scale

        def solve(start):
            out = optimize.minimize(
                self.problem.objective, start, jac=True, method="SLSQP",
                constraints=[{"type": "eq", "fun": constraint}],
                options={"maxiter": SLSQP_MAXITER, "ftol": 1e-13},
            )  # fmt: skip
            return out, self.problem.clip(out.x)

        res, theta = solve(theta0)
        if abs(constraint(theta)) > 1e-4 and nearest != self.center:
            # from the ML estimates instead (a far profile point can be a poor start)
            res, theta = solve(self.problem.clip(self.cache[self.center][1]))
        if abs(constraint(theta)) > 1e-4:
            raise ThermocalInputError(
                f"profile of '{self.name}': the constraint {self.name} = {c:.6g} could not be "
                f"met ({res.message}); the quantity may not reach that value within the bounds"
            )
        ll = self.problem.loglike(theta)
        self.cache[c] = (ll, theta)
        return ll


def _bracket(prof, side: float, step: float, threshold: float):
    """Walk outwards from the estimate until the profile drops below ``threshold``.

    Doubling steps; a step that fails (the constrained fit cannot meet the constraint, the
    likelihood is not finite) or leaves the parameter's range is taken back and halved, up to
    :data:`MAX_HALVINGS` times in a row, so an end close to a bound or to the edge of the range
    a derived quantity can reach is still bracketed. A parameter's bound is tried itself (on
    the unconstrained scale, :data:`BOUND_SPAN` from the estimate) before an end is called open.

    Returns
    -------
    (inner, outer)
        The last point above the threshold and the first below it; ``outer`` is None when the
        profile stays above the threshold up to the bound or the edge of the reachable range.
    """
    inner = prof.center
    halvings = 0
    bound_tried = False
    for _ in range(MAX_STEPS + MAX_HALVINGS):
        t = inner + side * step
        if isinstance(prof, _ParameterProfile) and abs(t - prof.center) > BOUND_SPAN:
            if bound_tried:
                return inner, None
            bound_tried = True
            t = prof.center + side * BOUND_SPAN  # at the bound, as far as the scale goes
            step = abs(t - inner)
        try:
            ll = prof(t)
            failed = not math.isfinite(ll)
        except ThermocalInputError:
            failed = True
        if failed:
            halvings += 1
            if halvings > MAX_HALVINGS:
                return inner, None
            step *= 0.5
            continue
        if ll < threshold:
            return inner, t
        if bound_tried:
            return t, None  # above the threshold at the bound itself: open
        inner = t
        step *= 2.0 if halvings == 0 else 1.0  # after a step back, no more doubling
    return inner, None


def profile_interval(res, name: str, *, alpha: float = 0.05) -> dict:
    """Profile-likelihood confidence interval of a free parameter or a derived quantity.

    Parameters
    ----------
    res : FitResults
        A maximum-likelihood fit (with priors, the profile of the likelihood alone is used).
    name : str
        A free parameter or a quantity declared under ``derived:``.
    alpha : float
        1 - confidence level.

    Returns
    -------
    dict
        ``estimate``, ``lower``, ``upper`` [declared unit], ``open_lower`` / ``open_upper``
        (the profile stays above the threshold up to the parameter's bound: the end is the
        bound), ``not_found_lower`` / ``not_found_upper`` (why an end could not be located,
        then None, see :func:`profile_side`; None when found), ``threshold`` (the profile
        log-likelihood at the end points), ``evaluations``
        (profile points computed), ``points`` (value -> profile log-likelihood) and
        ``better_optimum`` (None, or the value and log-likelihood of a profile point more than
        0.1 above the fit's optimum: the fit is then marked not converged and flagged).

    The constrained fits run with one BLAS thread (see
    :func:`thermocal.statespace.estimation.one_blas_thread`: with two, the heat loss
    coefficient's profile of a four-state model took 16-18 CPU-s instead of 3.7-4.7 s).
    """
    from thermocal.statespace.convergence import one_blas_thread

    with one_blas_thread():
        return _profile_interval(res, name, alpha=alpha)


def _profile_interval(res, name: str, *, alpha: float) -> dict:
    """:func:`profile_interval` in the current thread settings."""
    prof, threshold, drop = profile_setup(res, name, alpha=alpha)
    ends = [profile_side(prof, side, threshold, drop) for side in (-1.0, 1.0)]
    return profile_summary(res, name, prof, ends, threshold, alpha)


#: The two ends of a profile interval: below and above the estimate (on the profiled scale).
SIDES = (-1.0, 1.0)


def profile_setup(res, name: str, *, alpha: float = 0.05):
    """The profile-likelihood function of ``name`` and the threshold of its interval.

    Parameters
    ----------
    res : FitResults
    name : str
        A free parameter, a quantity declared under ``derived:`` or
        ``"heat_loss_coefficient"``.
    alpha : float
        1 - confidence level.

    Returns
    -------
    (profile, threshold, drop)
        The profile (callable: value on its scale -> profile log-likelihood, with its cache of
        computed points), the log-likelihood at the interval's ends [-] and its distance below
        the optimum [-].
    """
    model = res.model
    if name in model.free_parameter_names:
        prof = _ParameterProfile(res, name)
    elif name in model.derived:
        prof = _DerivedProfile(res, name)
    elif name == "heat_loss_coefficient":  # implied by the network [W/K]
        from thermocal.statespace import kernels

        hlc = res.heat_loss_coefficient(profile=False)
        tr, st = model.transform_arrays(), model.structure()
        state = model.state_names.index(model.heat_loss_state())
        prof = _DerivedProfile(
            res, name, lambda values: model.heat_loss_coefficient(values), hlc["std_error"],
            theta_func=lambda theta: kernels.heat_loss_theta(
                theta, tr, st.arrays, st.n_inputs, state
            ),
        )  # fmt: skip
    else:
        raise ThermocalInputError(
            f"profile: '{name}' is neither a free parameter nor a derived quantity of model "
            f"'{model.name}' (free: {', '.join(model.free_parameter_names)}; derived: "
            f"{', '.join(model.derived) or 'none'})"
        )
    if not 0 < alpha < 1:
        raise ThermocalInputError(f"profile: alpha must lie in (0, 1), got {alpha}")
    drop = 0.5 * float(chi2_quantile(1 - alpha, 1))
    return prof, res.loglike - drop, drop


def profile_side(
    prof, side: float, threshold: float, drop: float
) -> tuple[float, bool, str | None]:
    """One end of a profile interval: bracketing outwards from the estimate, then Brent.

    The profile points of one side are warm-started from the nearest point computed so far,
    which is the estimate or a point of the same side, so the two sides can be computed
    apart (e.g. in two processes, their caches merged afterwards) with the same numbers.

    Parameters
    ----------
    prof : profile from :func:`profile_setup`
    side : {-1.0, 1.0}
        Below or above the estimate.
    threshold, drop : float
        From :func:`profile_setup` [-].

    Returns
    -------
    (end, open, not_found)
        The end [declared unit] and whether it is open (the profile stays above the threshold
        up to the parameter's bound or the edge of the reachable range); when the crossing of
        the threshold cannot be located (a flat or ragged profile: the constrained fits do not
        reproduce, or Brent's method does not converge), the end is NaN and ``not_found`` says
        why (else None).
    """
    inner, outer = _bracket(prof, side, math.sqrt(2 * drop) * prof.step, threshold)
    if outer is None:
        if isinstance(prof, _ParameterProfile):  # the bound in this direction
            p = prof.res.model.parameters[prof.name]
            return (p.upper if _going_up(prof, side) else p.lower), True, None
        return prof.value(inner), True, None  # the edge of the range reached within the bounds

    def excess(t):
        try:
            return prof(t) - threshold
        except ThermocalInputError:
            return -drop  # infeasible inside a bracket: below the threshold

    try:
        root = optimize.brentq(
            excess, min(inner, outer), max(inner, outer),
            xtol=1e-6 * max(1.0, abs(prof.center)), rtol=1e-8, maxiter=BRENT_MAXITER,
        )  # fmt: skip
    except (ValueError, RuntimeError) as exc:
        return math.nan, False, _not_found(prof, inner, outer, exc)
    return prof.value(root), False, None


#: Iterations of Brent's method for an end of a profile interval.
BRENT_MAXITER = 40


def _going_up(prof, side: float) -> bool:
    """Whether ``side`` of the profiled scale goes to larger values of the quantity."""
    return prof.value(prof.center + side * 1e-3) > prof.value(prof.center)


def _not_found(prof, inner: float, outer: float, exc: Exception) -> str:
    """Why the end between ``inner`` and ``outer`` (profiled scale) was not located: the
    exception of Brent's method (``ValueError``: no sign change on evaluating the bracket
    again; ``RuntimeError``: no convergence), in words."""
    a, b = sorted((prof.value(inner), prof.value(outer)))
    where = f"between {a:.6g} and {b:.6g}"
    if isinstance(exc, ValueError):
        return (
            f"the profile log-likelihood fell below the threshold {where} while bracketing, but "
            "not when computed again there (the constrained fits do not reproduce: a flat or "
            "ragged profile)"
        )
    return (
        f"Brent's method found no crossing of the threshold {where} in {BRENT_MAXITER} "
        "iterations (a flat or ragged profile)"
    )


def profile_summary(res, name: str, prof, ends, threshold: float, alpha: float) -> dict:
    """The interval of :func:`profile_interval` from its two ends.

    Parameters
    ----------
    res : FitResults
        The fit; marked not converged and flagged when a profile point is more than
        :data:`AGREEMENT_TOLERANCE` above its optimum.
    name : str
    prof : profile from :func:`profile_setup`
        Its cache holds the points of both sides.
    ends : sequence of (float, bool, str or None)
        :func:`profile_side` of the sides in :data:`SIDES` order.
    threshold, alpha : float

    Returns
    -------
    dict
        As :func:`profile_interval`; an end that was not found is None, with the reason in
        ``not_found_lower`` / ``not_found_upper`` (None when found) and a flag on ``res``.
    """
    (lower, open_lower, why_lower), (upper, open_upper, why_upper) = _lower_first(prof, ends)
    for which, why in (("lower", why_lower), ("upper", why_upper)):
        if why is not None:
            res.flags.append(
                f"profile-likelihood interval of '{name}': its {which} end was not found: "
                f"{why}; reported as not found (null): the data hardly determine '{name}' "
                "there"
            )
    points = {prof.value(t): ll for t, (ll, _) in sorted(prof.cache.items())}
    better = max(points.items(), key=lambda item: item[1])
    better_optimum = None
    if better[1] > res.loglike + AGREEMENT_TOLERANCE:
        better_optimum = {"value": better[0], "loglike": better[1]}
        res.note_better_optimum(better[1], f"the profile of '{name}' at {name} = {better[0]:.6g}")
    return {
        "estimate": prof.value(prof.center),
        "lower": None if why_lower else lower,
        "upper": None if why_upper else upper,
        "open_lower": open_lower,
        "open_upper": open_upper,
        "not_found_lower": why_lower,
        "not_found_upper": why_upper,
        "threshold": threshold,
        "alpha": alpha,
        "evaluations": len(prof.cache) - 1,
        "points": points,
        "better_optimum": better_optimum,
    }


def _lower_first(prof, ends) -> list:
    """The two ends of :func:`profile_side` (in :data:`SIDES` order), lower end first: by
    value when both were found, else by the direction of each side on the profiled scale."""
    if all(why is None for _, _, why in ends):
        return sorted(ends, key=lambda end: end[:2])
    return list(ends) if _going_up(prof, SIDES[1]) else list(ends)[::-1]
