"""Profile-likelihood confidence intervals of parameters and derived quantities.

The profile log-likelihood of a quantity ``g`` is ``l_p(c) = max { l(theta) : g(theta) = c }``;
the interval ``{c : 2 (l_hat - l_p(c)) <= chi2_(1-alpha)(1)}`` (Wilks) follows the likelihood
where it is skewed or bounded, unlike the Wald interval from the curvature at the optimum.

- a parameter: ``g`` is the parameter itself; each ``l_p(c)`` is a fit of the model with that
  parameter fixed at ``c``, warm-started from the nearest profile point already computed;
- a derived quantity (``derived:`` in the model file): each ``l_p(c)`` is a constrained
  maximisation (SLSQP on the unconstrained parameters, the equality ``g(theta) = c``).

The end points are found by bracketing outwards from the Wald end points and Brent's method.

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
from scipy import optimize, stats

from thermocal.errors import ThermocalInputError

#: Largest number of outward steps per side before the interval is declared open.
MAX_STEPS = 12
#: Stall tolerance of the profile fits (tighter than the default fit's).
PROFILE_STALL_TOLERANCE = 1e-5


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
        self.cache: dict[float, tuple[float, dict]] = {self.center: (res.loglike, res.params)}

    def value(self, t: float) -> float:
        return self.p.from_unconstrained(t)

    def __call__(self, t: float) -> float:
        from thermocal.statespace.estimation import fit

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
            fitted = fit(
                model, self.res.data, hold=self.res.hold, n_starts=1, compute_hessian=False,
                n_jobs=1, progress=False, stall_tolerance=PROFILE_STALL_TOLERANCE,
            )  # fmt: skip
            ll, params = fitted.loglike, fitted.params
        self.cache[t] = (ll, params)
        return ll


class _DerivedProfile:
    """``l_p`` of a derived quantity, on its natural scale."""

    def __init__(self, res, name: str) -> None:
        from thermocal.statespace.estimation import LikelihoodProblem, _hold_flag

        self.res = res
        self.name = name
        self.expr = res.model.derived[name][0]
        self.problem = LikelihoodProblem(res.model, res.data, _hold_flag(res.hold))
        self.free = [res.model.parameters[n] for n in res.model.free_parameter_names]
        self.center = float(self.g(res.theta))
        derived = res.derived()
        se = float(derived.loc[name, "std_error"]) if name in derived.index else math.nan
        self.step = se if math.isfinite(se) and se > 0 else 0.1 * max(abs(self.center), 1e-6)
        self.cache: dict[float, tuple[float, np.ndarray]] = {
            self.center: (res.loglike, np.asarray(res.theta, dtype=float))
        }

    def g(self, theta) -> float:
        values = self.res.params.to_dict()
        for p, t in zip(self.free, theta, strict=True):
            values[p.name] = p.from_unconstrained(float(t))
        return self.res.model.derived_values(values)[self.name]

    def value(self, c: float) -> float:
        return c

    def __call__(self, c: float) -> float:
        nearest = min(self.cache, key=lambda s: abs(s - c))
        theta0 = self.problem.clip(self.cache[nearest][1])
        scale = max(abs(self.step), 1e-12)

        def constraint(theta):
            return (self.g(theta) - c) / scale

        res = optimize.minimize(
            self.problem.objective, theta0, jac=True, method="SLSQP",
            constraints=[{"type": "eq", "fun": constraint}],
            options={"maxiter": 500, "ftol": 1e-13},
        )  # fmt: skip
        theta = self.problem.clip(res.x)
        if abs(constraint(theta)) > 1e-4:
            raise ThermocalInputError(
                f"profile of '{self.name}': the constraint {self.name} = {c:.6g} could not be "
                f"met ({res.message}); the quantity may not reach that value within the bounds"
            )
        ll = self.problem.loglike(theta)
        self.cache[c] = (ll, theta)
        return ll


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
        bound), ``threshold`` (the profile log-likelihood at the end points), ``evaluations``
        (profile points computed) and ``points`` (value -> profile log-likelihood).
    """
    model = res.model
    if name in model.free_parameter_names:
        prof = _ParameterProfile(res, name)
    elif name in model.derived:
        prof = _DerivedProfile(res, name)
    else:
        raise ThermocalInputError(
            f"profile: '{name}' is neither a free parameter nor a derived quantity of model "
            f"'{model.name}' (free: {', '.join(model.free_parameter_names)}; derived: "
            f"{', '.join(model.derived) or 'none'})"
        )
    if not 0 < alpha < 1:
        raise ThermocalInputError(f"profile: alpha must lie in (0, 1), got {alpha}")
    drop = 0.5 * float(stats.chi2.ppf(1 - alpha, 1))
    threshold = res.loglike - drop
    ends, open_end = {}, {}
    z = math.sqrt(2 * drop)
    for side in (-1.0, 1.0):
        inner, outer = prof.center, None
        step = z * prof.step
        for _ in range(MAX_STEPS):
            t = inner + side * step
            if isinstance(prof, _ParameterProfile) and abs(t - prof.center) > 40:
                break  # the logit/log scale has reached the bound
            try:
                ll = prof(t)
            except ThermocalInputError:
                break
            if ll < threshold:
                outer = t
                break
            inner = t
            step *= 2.0
        if outer is None:
            if name in model.parameters:  # the bound in this direction of the scale
                p = model.parameters[name]
                going_up = prof.value(inner + side) > prof.value(inner)
                ends[side] = p.upper if going_up else p.lower
            else:
                ends[side] = prof.value(inner)
            open_end[side] = True
            continue
        root = optimize.brentq(
            lambda t: prof(t) - threshold, min(inner, outer), max(inner, outer),
            xtol=1e-6 * max(1.0, abs(prof.center)), rtol=1e-8, maxiter=40,
        )  # fmt: skip
        ends[side] = prof.value(root)
        open_end[side] = False
    (lower, open_lower), (upper, open_upper) = sorted(
        [(ends[-1.0], open_end[-1.0]), (ends[1.0], open_end[1.0])]
    )
    points = {prof.value(t): ll for t, (ll, _) in sorted(prof.cache.items())}
    return {
        "estimate": prof.value(prof.center),
        "lower": lower,
        "upper": upper,
        "open_lower": open_lower,
        "open_upper": open_upper,
        "threshold": threshold,
        "alpha": alpha,
        "evaluations": len(prof.cache) - 1,
        "points": points,
    }
