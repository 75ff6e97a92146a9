"""Results of a maximum-likelihood fit, in the statsmodels spirit (model separate from results)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.jsonsafe import json_ready as _jsonable
from thermocal.statespace import kernels
from thermocal.statespace.convergence import (
    AGREEMENT_TOLERANCE,
    BOUND_TOLERANCE,
    CONVERGENCE_GAIN,
    CORRELATION_LIMIT,
)
from thermocal.statespace.data import PreparedData, prepare_data
from thermocal.statespace.distributions import normal_quantile
from thermocal.statespace.kalman import _hold_flag, filter_arrays, rts_smoother, simulate
from thermocal.statespace.units import (
    DIM_IRRADIANCE_W_M2,
    HEAT_UNIT_SLIPS,
    PLAUSIBLE_HEAT_LOSS_W_PER_K,
    TIME_UNITS,
    dim_irradiance,
    heat_unit_slip,
)

#: Standard error above this fraction of the estimate flags a positive parameter.
RELATIVE_SE_LIMIT = 0.5
#: A state whose diffusion-only stationary standard deviation exceeds this multiple of the
#: spread of its deterministic simulation is diffusion-dominated.
DIFFUSION_RATIO_LIMIT = 1.0
#: Ljung-Box lags and level of the residual-whiteness flag.
LJUNG_BOX_LAGS = 20
LJUNG_BOX_ALPHA = 0.01
#: Standardised one-step residuals beyond this many standard deviations are flagged.
OUTLIER_SIGMA = 5.0
OUTLIERS_LISTED = 10
#: An input value more than this many robust standard deviations from its median is a spike
#: (:func:`robust_range`).
SPIKE_SCALES = 10.0
#: Negative heat-input values smaller in size than this fraction of the 90 % quantile of |u|
#: are sensor offsets (a pyranometer at night), not flagged.
NEGATIVE_OFFSET_FRACTION = 0.05
#: Physical limits in SI of boundary temperatures [C] and irradiances [W/m2] (above the solar
#: constant, 1361 W/m2, Kopp & Lean 2011, with margin for reflections).
PHYSICAL_LIMITS = {"C": (-90.0, 150.0), "W/m2": (-50.0, 1500.0)}
#: Out-of-range output values listed by row in a flag.
ROWS_LISTED = 5
#: A fit more than this below its nested model's log-likelihood is flagged.
NESTED_TOLERANCE = 1e-2


class FitResults:
    """Estimates, uncertainty and diagnostics of a fitted :class:`RCModel`.

    Attributes
    ----------
    model : RCModel
        The model that was fitted (declared values untouched).
    params : pandas.Series
        All parameters [declared units]; fixed ones at their fixed value.
    bse : pandas.Series
        Standard errors [declared units] (NaN for fixed parameters or a singular Hessian).
    loglike : float
        Maximised log-likelihood (natural log) of the observations.
    nobs : int
        Number of observed scalar output values.
    aic, bic : float
        ``-2 loglike + 2 k`` and ``-2 loglike + k ln(nobs)``, ``k`` free parameters.
    converged : bool
    fit_seconds : float [s]
    flags : list of str
        Warnings: non-convergence, non-finite or not positive definite Hessian,
        |correlation| > 0.98 (naming the pair), parameters at a bound.
    """

    def __init__(
        self,
        *,
        model,
        theta: np.ndarray,
        loglike: float,
        hessian: np.ndarray | None,
        nobs: int,
        converged: bool,
        message: str,
        n_iterations: int,
        gradient_norm: float,
        start_loglikes: list[float],
        hold: str,
        data: PreparedData,
        fit_seconds: float,
        gradient: np.ndarray | None = None,
        nested=None,
        logprior: float | None = None,
        agreement: dict | None = None,
        fitter=None,
    ) -> None:
        self.model = model
        self.theta = theta
        #: The function that made this fit (:func:`thermocal.statespace.estimation.fit`), for
        #: :meth:`refit`.
        self._fitter = fitter
        self.loglike = float(loglike)
        #: Log prior density at the estimates (None without priors: maximum likelihood).
        self.logprior = logprior
        #: Maximised log posterior (log-likelihood + log prior), None without priors.
        self.logposterior = None if logprior is None else self.loglike + float(logprior)
        self.hessian = hessian
        self.nobs = int(nobs)
        self.converged = bool(converged)
        self.message = message
        self.n_iterations = n_iterations
        self.gradient_norm = gradient_norm
        self.start_loglikes = start_loglikes
        self.hold = hold
        self.data = data
        self.fit_seconds = float(fit_seconds)
        free = model.free_parameter_names
        values = {p.name: p.value for p in model.parameters.values()}
        for i, name in enumerate(free):
            values[name] = model.parameters[name].from_unconstrained(theta[i])
        self.params = pd.Series(values, name="estimate", dtype=float)
        # the data's own faults first (after the verdict's flags, inserted before them)
        self.flags: list[str] = data_flags(model, data)
        at_bound = self._bound_flags(model, free)
        self.at_bound = [free[i] for i in at_bound]
        jac = np.array([model.parameters[n].derivative(theta[i]) for i, n in enumerate(free)])
        cov = np.full((len(free), len(free)), np.nan)
        self._cov_theta = np.full((len(free), len(free)), np.nan)
        #: Log-likelihood a Newton step from the end point would still gain (NaN without
        #: Hessian); the convergence criterion.
        self.expected_gain = float("nan")
        if hessian is not None:
            cov = self._covariance(hessian, jac, free, at_bound)
            if gradient is not None and gradient.size == len(free):
                keep = np.flatnonzero(np.isfinite(np.diag(self._cov_theta)))
                g = np.asarray(gradient, dtype=float)[keep]
                if keep.size and np.all(np.isfinite(g)):
                    ct = self._cov_theta[np.ix_(keep, keep)]
                    self.expected_gain = float(0.5 * g @ ct @ g)
                    # judged at the end point, not by the optimiser's message
                    self.converged = self.expected_gain < CONVERGENCE_GAIN
                    if self.converged and not converged:
                        self.message = (
                            f"{message}; at the end point a Newton step would gain "
                            f"{self.expected_gain:.2g} log-units (< {CONVERGENCE_GAIN:g})"
                        )
        if not self.converged:
            extra = (
                f"; a Newton step from the end point would still gain "
                f"{self.expected_gain:.3g} log-units"
                if math.isfinite(self.expected_gain)
                else ""
            )
            self.flags.insert(
                0,
                f"optimiser did not converge: {message}{extra}; remedy: more starts "
                "(--n-starts), a smaller stall_tolerance, or fix poorly determined parameters",
            )
        #: Agreement of the optimiser starts (see
        #: :func:`thermocal.statespace.estimation.start_agreement`): ``n_starts``, ``n_best``
        #: (starts that reached the best log-likelihood), ``best``, ``runner_up``.
        self.agreement = dict(agreement) if agreement else None
        if self.agreement and self.agreement["n_starts"] >= 2 and self.agreement["n_best"] < 2:
            self.converged = False
            gap = self.agreement["best"] - self.agreement["runner_up"]
            self.flags.insert(
                0,
                f"global optimum not confirmed: the best log-likelihood ({self.loglike:.2f}) was "
                f"reached by 1 of {self.agreement['n_starts']} optimiser starts (the next best "
                f"ends {gap:.3g} log-units lower); another start may find a better optimum; "
                "remedy: more starts (--n-starts) or start values closer to physical ones",
            )
        self._cov = pd.DataFrame(cov, index=free, columns=free)
        bse = pd.Series(np.nan, index=self.params.index, name="std_error")
        diag = np.diag(cov)
        bse[free] = np.where(diag >= 0, np.sqrt(np.abs(diag)), np.nan)
        self.bse = bse
        with np.errstate(invalid="ignore", divide="ignore"):
            sd = np.sqrt(np.diag(cov))
            corr = cov / np.outer(sd, sd)
        self.correlation = pd.DataFrame(corr, index=free, columns=free)
        for i in range(len(free)):
            for j in range(i + 1, len(free)):
                if abs(corr[i, j]) > CORRELATION_LIMIT:
                    self.flags.append(
                        f"|correlation({free[i]}, {free[j]})| = {abs(corr[i, j]):.3f} > "
                        f"{CORRELATION_LIMIT}: over-parameterised, fix one of them"
                    )
        #: Checks of the estimates, the residuals and the data (see :meth:`_diagnose`).
        self.checks: dict[str, Any] = {}
        self._diagnose(nested)

    def _diagnose(self, nested) -> None:
        """Flags beyond the optimiser's: each names the problem and a remedy.

        - an optimum below a nested (restricted) model's log-likelihood;
        - relative standard errors above :data:`RELATIVE_SE_LIMIT` (capacities, conductances,
          resistances, scales, fractions);
        - a diffusion-dominated state: the stationary standard deviation its diffusion alone
          gives the state (continuous Lyapunov equation) exceeds the spread of its
          deterministic simulation over the data;
        - time constants (``-1/Re(eig A)``) shorter than the sampling interval or longer than the
          data span;
        - non-white one-step residuals (Ljung-Box p below :data:`LJUNG_BOX_ALPHA`);
        - standardised one-step residuals beyond :data:`OUTLIER_SIGMA` (time stamps listed);
        - heat inputs with negative values, inputs far outside their robust range.
        """
        from scipy import linalg

        from thermocal.statespace.diagnostics import ljung_box

        model, prep, checks = self.model, self.data, self.checks
        if nested is not None and self.loglike < nested.loglike - NESTED_TOLERANCE:
            self.converged = False  # a better optimum (the nested one, embedded) was seen
            self.flags.append(
                f"log-likelihood {self.loglike:.3f} is below that of the nested model "
                f"'{nested.model.name}' ({nested.loglike:.3f}) although this model contains it: "
                "a poor local optimum; remedy: more starts (--n-starts), or check that the "
                "models are nested (shared parameter names)"
            )
        # relative standard errors of physical quantities (noise standard deviations often
        # have large relative errors without harm)
        roles = model.structure().roles
        positive = {"capacity", "conductance", "resistance", "scale", "fraction"}
        for name in model.free_parameter_names:
            est, se = float(self.params[name]), float(self.bse[name])
            if not (roles.get(name, set()) & positive) or name in self.at_bound:
                continue
            if math.isfinite(se) and est != 0 and se / abs(est) > RELATIVE_SE_LIMIT:
                self.flags.append(
                    f"parameter '{name}' = {est:.4g} {model.parameters[name].unit} has a "
                    f"standard error of {se / abs(est):.0%} of its value (> "
                    f"{RELATIVE_SE_LIMIT:.0%}): the data hardly determine it; remedy: fix it at "
                    "a physical value, give it a prior, or simplify the model"
                )
        params = self.params.to_dict()
        try:
            A, _, _, _ = model.continuous_matrices(params)
            sigma = np.diag(model.diffusion_matrix(params))
        except Exception:  # noqa: BLE001 - a degenerate system at the estimates
            return
        eig = np.linalg.eigvals(A) if np.all(np.isfinite(A)) else np.array([])
        taus = np.sort(-1.0 / eig.real[eig.real < 0])
        # the observations' interval (on a grid observed every m-th row by design, e.g.
        # statespace.data.midpoint_observations, the other rows carry only inputs)
        steps = np.diff(prep.seconds[observation_rows(prep.Y)])
        dt = float(np.median(steps)) if steps.size else float("nan")
        span = float(prep.seconds[-1] - prep.seconds[0])
        checks["time_constants_h"] = [float(t / 3600.0) for t in taus]
        for tau in taus:
            if tau < dt:
                self.flags.append(
                    f"time constant {_duration(tau)} is shorter than the sampling interval "
                    f"({_duration(dt)}): the data cannot resolve that mode; remedy: remove the "
                    "fast node (merge it with its neighbour) or fix its capacity"
                )
            elif tau > span:
                self.flags.append(
                    f"time constant {_duration(tau)} is longer than the data span "
                    f"({_duration(span)}): the slow dynamics are extrapolated, not measured; "
                    "remedy: longer data, or fix the capacity or conductances from physics"
                )
        # diffusion-dominated states
        stable = eig.size and np.all(eig.real < 0)
        if stable and np.any(sigma > 0):
            sim = self.simulate()
            ratios = {}
            for i, state in enumerate(model.state_names):
                if sigma[i] <= 0:
                    continue
                Q = np.zeros_like(A)
                Q[i, i] = sigma[i] ** 2
                try:
                    P = linalg.solve_continuous_lyapunov(A, -Q)
                except (linalg.LinAlgError, ValueError):
                    continue
                noise_sd = math.sqrt(max(P[i, i], 0.0))
                drift_sd = float(np.std(sim[state].to_numpy()))
                ratio = noise_sd / drift_sd if drift_sd > 0 else math.inf
                ratios[state] = ratio
                if ratio > DIFFUSION_RATIO_LIMIT:
                    noise = model._states[state].get("noise")
                    self.flags.append(
                        f"state '{state}' is diffusion-dominated: its diffusion alone gives it a "
                        f"stationary standard deviation of {noise_sd:.3g} K, more than the "
                        f"spread of its deterministic simulation ({drift_sd:.3g} K); the state "
                        "absorbs model error and the physical parameters around it are not "
                        f"trustworthy; remedy: fix its diffusion ('{noise}') at a small value "
                        "(a deterministic state), add the missing input or state, or compare "
                        "with a simpler model"
                    )
            checks["diffusion_ratio"] = ratios
        # residuals
        try:
            res = self.one_step_residuals()
        except Exception:  # noqa: BLE001 - a filter failure is reported elsewhere
            return
        checks["ljung_box"] = {}
        checks["outliers"] = {}
        for r, col in enumerate(model.output_names):
            z = res[f"{col}_standardized"].to_numpy()
            rows = observation_rows(prep.Y[:, [r]])  # each output at its own rate
            if np.isfinite(z[rows]).sum() >= 20:
                q, p = ljung_box(z[rows], nlags=LJUNG_BOX_LAGS)
                checks["ljung_box"][col] = {"statistic": q, "pvalue": p}
                if not np.isfinite(p):
                    self.flags.append(
                        f"the whiteness of the one-step residuals of '{col}' could not be "
                        "tested (Ljung-Box undefined on this pattern of missing values)"
                    )
                elif p < LJUNG_BOX_ALPHA:
                    self.flags.append(
                        f"one-step residuals of '{col}' are not white (Ljung-Box "
                        f"Q({min(LJUNG_BOX_LAGS, np.isfinite(z[rows]).sum() // 5)}) = {q:.1f}, "
                        f"p = {p:.2g}): the model misses dynamics or an input; see the ACF and "
                        "cumulated periodogram; remedy: add a state or an input, or a finer "
                        "model of the heating"
                    )
            big = np.flatnonzero(np.abs(np.nan_to_num(z)) > OUTLIER_SIGMA)
            if big.size:
                checks["outliers"][col] = [
                    {"time": _stamp(prep, k), "standardized": float(z[k])} for k in big
                ]
                shown = ", ".join(f"{_stamp(prep, k)} ({z[k]:+.1f})" for k in big[:OUTLIERS_LISTED])
                extra = big.size - OUTLIERS_LISTED
                more = f" and {extra} more" if extra > 0 else ""
                self.flags.append(
                    f"{big.size} standardised one-step residual(s) of '{col}' beyond "
                    f"{OUTLIER_SIGMA:g} sigma at {shown}{more}: a jump or spike in the data, "
                    "or an event the model lacks; remedy: check the data there, remove the "
                    "values (NaN) or cut the period"
                )
        self.flags.extend(input_flags(model, prep))
        if not heat_unit_flags(model, prep):  # the declared values' balance names no slip
            self.flags.extend(heat_loss_unit_flags(model, self.params.to_dict(), prep))
        self.flags.extend(time_unit_flags(model, prep))

    def refit(self, model, **options) -> FitResults:
        """Fit ``model`` (e.g. this model with a parameter held fixed: the profile
        likelihood's refits) on this fit's data, with its hold, by the function that made it.

        ``options`` go to :func:`thermocal.statespace.estimation.fit`.
        """
        if self._fitter is None:
            raise ThermocalInputError(
                "refit: these results were not made by fit(); fit the model to refit it"
            )
        return self._fitter(model, self.data, hold=self.hold, **options)

    def _bound_flags(self, model, free: list[str]) -> list[int]:
        """Flag estimates at a bound; return their positions in ``free``."""
        at = []
        for i, name in enumerate(free):
            p = model.parameters[name]
            x = self.params[name]
            if p.transform == kernels.TRANSFORM_LOGIT:
                if p.lower > 0 and p.upper / p.lower > 100:
                    # a positive range over orders of magnitude: distance on a log scale
                    span = math.log(p.upper / p.lower)
                    d_lo, d_hi = math.log(x / p.lower) / span, math.log(p.upper / x) / span
                else:
                    span = p.upper - p.lower
                    d_lo, d_hi = (x - p.lower) / span, (p.upper - x) / span
                near = p.lower if d_lo < d_hi else p.upper
                at_bound = min(d_lo, d_hi) < BOUND_TOLERANCE
            elif p.transform == kernels.TRANSFORM_LOG:
                near = p.lower
                at_bound = (x - p.lower) < BOUND_TOLERANCE * (p.value - p.lower)
            elif p.transform == kernels.TRANSFORM_NEGLOG:
                near = p.upper
                at_bound = (p.upper - x) < BOUND_TOLERANCE * (p.upper - p.value)
            else:
                at_bound = False
            if at_bound:
                at.append(i)
                self.flags.append(
                    f"parameter '{name}' = {x:.6g} {p.unit} is at its bound {near:g}: widen the "
                    "bound, fix the parameter, or simplify the model"
                )
        return at

    def _covariance(self, hessian, jac, free, at_bound) -> np.ndarray:
        """Delta-method covariance [declared units] from the Hessian in theta.

        Parameters at a bound have a flat likelihood in theta; when the full information matrix
        is not positive definite, they are held fixed (their standard error is NaN) and the
        covariance of the others is computed from the reduced matrix. If that is still not
        positive definite, the parameters that dominate the flattest direction are held fixed
        one by one (flagged by name), so the identifiable parameters keep standard errors
        conditional on them.
        """
        k = len(free)
        cov = np.full((k, k), np.nan)
        if not np.all(np.isfinite(hessian)):
            self.flags.append("Hessian of the log-likelihood is not finite: no standard errors")
            return cov
        info = -0.5 * (hessian + hessian.T)
        keep = np.arange(k)
        if not _positive_definite(info):
            keep = np.array([i for i in range(k) if i not in at_bound], dtype=int)
            if len(keep) < k and _positive_definite(info[np.ix_(keep, keep)]):
                self.flags.append(
                    "standard errors computed with the parameters at a bound held fixed"
                )
            unidentified = []
            while len(keep) and not _positive_definite(info[np.ix_(keep, keep)]):
                _, v = np.linalg.eigh(info[np.ix_(keep, keep)])
                worst = int(np.argmax(np.abs(v[:, 0])))
                unidentified.append(free[keep[worst]])
                keep = np.delete(keep, worst)
            if unidentified:
                pronoun = "them" if len(unidentified) > 1 else "it"
                others = (
                    f"standard errors of the others are conditional on {pronoun} being fixed"
                    if len(keep)
                    else "no standard errors"
                )
                self.flags.append(
                    "Hessian is not negative definite (not identifiable, mostly along "
                    f"{' and '.join(unidentified)}): {others}; fix or remove parameters"
                )
            if not len(keep):
                return cov
        cov_theta = np.linalg.inv(info[np.ix_(keep, keep)])
        self._cov_theta[np.ix_(keep, keep)] = cov_theta
        cov[np.ix_(keep, keep)] = jac[keep, None] * cov_theta * jac[None, keep]
        return cov

    # ------------------------------------------------------------------ statistics
    @property
    def n_free(self) -> int:
        """Number of estimated parameters."""
        return len(self.model.free_parameter_names)

    @property
    def aic(self) -> float:
        """Akaike information criterion."""
        return -2.0 * self.loglike + 2.0 * self.n_free

    @property
    def bic(self) -> float:
        """Bayesian information criterion."""
        return -2.0 * self.loglike + self.n_free * math.log(self.nobs)

    def cov_params(self) -> pd.DataFrame:
        """Covariance matrix of the free-parameter estimates [declared units]."""
        return self._cov.copy()

    def conf_int(self, alpha: float = 0.05, *, scale: str = "transformed") -> pd.DataFrame:
        """Confidence intervals [declared units] of the free parameters.

        Parameters
        ----------
        alpha : float
            1 - confidence level.
        scale : {"transformed", "natural"}
            ``"transformed"`` (default): the Wald interval on the optimiser's unconstrained
            scale (log for one-sided bounds, logit between two bounds), mapped back, so a
            positive parameter never gets a negative bound and a bounded one stays inside its
            bounds; the interval is asymmetric where the likelihood is. ``"natural"``: the
            symmetric Wald interval ``estimate +- z se`` in declared units.
        """
        if scale not in ("transformed", "natural"):
            raise ValueError("scale must be 'transformed' or 'natural'")
        z = normal_quantile(1 - alpha / 2)
        free = self.model.free_parameter_names
        est, se = self.params[free], self.bse[free]
        if scale == "natural":
            return pd.DataFrame({"lower": est - z * se, "upper": est + z * se})
        se_theta = np.sqrt(np.diag(self._cov_theta))
        lower, upper = [], []
        for i, name in enumerate(free):
            p = self.model.parameters[name]
            if not math.isfinite(se_theta[i]):
                lower.append(math.nan)
                upper.append(math.nan)
                continue
            a = p.from_unconstrained(self.theta[i] - z * se_theta[i])
            b = p.from_unconstrained(self.theta[i] + z * se_theta[i])
            lower.append(min(a, b))
            upper.append(max(a, b))
        return pd.DataFrame({"lower": lower, "upper": upper}, index=pd.Index(free))

    def heat_loss_coefficient(self, *, alpha: float = 0.05, profile: bool = True) -> dict | None:
        """The heat loss coefficient the model's structure implies, at the estimates.

        See :meth:`RCModel.heat_loss_coefficient` (steady-state heat flow from the observed
        state to all boundary temperatures per kelvin). Returns None when the structure implies
        none.

        Returns
        -------
        dict
            ``value`` and ``std_error`` (delta method) [W/K], ``wald_lower``/``wald_upper``
            (``value +- z se``), with ``profile``: ``lower``/``upper`` and
            ``open_lower``/``open_upper`` of the profile-likelihood interval (Pawitan 2001)
            [W/K], an end None when it could not be located (the reason in
            ``not_found_lower``/``not_found_upper``, and a flag);
            ``interval`` names the one to show first: ``"profile"`` (always computed
            when asked) or ``"wald"``; ``disagree`` is True when an end of the Wald interval is
            more than 10 % of the profile interval's width off; ``state`` and ``boundaries``
            (the boundary columns the heat flows to; with more than one, the coefficient
            depends on their temperatures, e.g. a cellar or attic that follows the test).
        """
        if self.model.heat_loss_state() is None:
            return None
        model = self.model
        base = self.params.to_dict()
        value = model.heat_loss_coefficient(base)
        free = model.free_parameter_names
        grad = np.zeros(len(free))
        for i, p in enumerate(free):
            h = 1e-6 * max(abs(base[p]), 1e-8)
            up = model.heat_loss_coefficient({**base, p: base[p] + h})
            down = model.heat_loss_coefficient({**base, p: base[p] - h})
            grad[i] = (up - down) / (2 * h)
        cov = self._cov.to_numpy()
        known = np.isfinite(np.diag(cov)) | (grad == 0)
        se = math.nan
        if np.all(known) and cov.size:
            se = float(np.sqrt(max(grad @ np.where(np.isfinite(cov), cov, 0.0) @ grad, 0.0)))
        z = float(normal_quantile(1 - alpha / 2))
        out = {
            "value": value, "std_error": se, "unit": "W/K",
            "wald_lower": value - z * se, "wald_upper": value + z * se,
            "state": model.heat_loss_state(), "boundaries": list(model.boundary_names),
            "alpha": alpha, "interval": "wald", "disagree": False,
            # free parameters at a bound that the coefficient depends on: it is then the
            # bound's, and no interval is its uncertainty (248.5 W/K [246.6, 250.3] for a
            # truth of 166.7 with a resistance's upper bound too low, without a word)
            "held_by_bounds": [p for i, p in enumerate(free) if p in self.at_bound and grad[i]],
        }  # fmt: skip
        if profile:
            try:
                prof = self.profile_interval("heat_loss_coefficient", alpha=alpha)
            except ThermocalInputError as exc:
                out["profile_error"] = str(exc)
                return out
            out = with_profile_interval(out, prof)
        return out

    def note_better_optimum(self, loglike: float, where: str) -> None:
        """Record that a point with a log-likelihood clearly above this optimum was seen
        (``where``: how it was found): the fit is then not converged, and flagged."""
        if loglike <= self.loglike + AGREEMENT_TOLERANCE:
            return
        self.converged = False
        self.flags.insert(
            0,
            f"a better optimum was seen: {where} reached log-likelihood {loglike:.2f}, "
            f"{loglike - self.loglike:.3g} above this fit's {self.loglike:.2f}; the estimates "
            "are a local optimum; remedy: refit with more starts (--n-starts) or from there",
        )

    def profile_interval(self, name: str, *, alpha: float = 0.05) -> dict:
        """Profile-likelihood confidence interval of a free parameter or a derived quantity
        [declared unit]; see :func:`thermocal.statespace.profile.profile_interval`."""
        from thermocal.statespace.profile import profile_interval

        return profile_interval(self, name, alpha=alpha)

    def profile_intervals(self, names, *, alpha: float = 0.05) -> pd.DataFrame:
        """:meth:`profile_interval` of several names: estimate, lower, upper, open ends."""
        rows = {}
        for name in names:
            r = self.profile_interval(name, alpha=alpha)
            rows[name] = {k: r[k] for k in ("estimate", "lower", "upper", "open_lower",
                                            "open_upper", "evaluations")}  # fmt: skip
        return pd.DataFrame.from_dict(rows, orient="index")

    def derived(self) -> pd.DataFrame:
        """Derived quantities declared in the model (``derived:``) with delta-method standard
        errors: value, std_error, unit, one row per quantity.

        The gradient with respect to the free parameters [declared units] is a central
        difference (relative step 1e-6); ``std_error = sqrt(g' cov g)``.
        """
        rows = []
        free = self.model.free_parameter_names
        cov = self._cov.to_numpy()
        base = self.params.to_dict()
        for name, (expr, unit) in self.model.derived.items():
            value = self.model.derived_values(base)[name]
            grad = np.zeros(len(free))
            for i, p in enumerate(free):
                h = 1e-6 * max(abs(base[p]), 1e-8)
                up = self.model.derived_values({**base, p: base[p] + h})[name]
                down = self.model.derived_values({**base, p: base[p] - h})[name]
                grad[i] = (up - down) / (2 * h)
            known = np.isfinite(np.diag(cov)) | (grad == 0)
            if np.all(known):
                c = np.where(np.isfinite(cov), cov, 0.0)
                se = float(np.sqrt(max(grad @ c @ grad, 0.0)))
            else:
                se = math.nan
            rows.append(
                {
                    "quantity": name,
                    "value": value,
                    "std_error": se,
                    "unit": unit,
                    "expression": expr,
                }
            )
        columns = ["value", "std_error", "unit", "expression"]
        if not rows:
            return pd.DataFrame(columns=columns, index=pd.Index([], name="quantity"))
        return pd.DataFrame(rows).set_index("quantity")[columns]

    @property
    def fitted_model(self):
        """Copy of the model with the estimates as declared values."""
        return self.model.with_parameters(self.params.to_dict())

    # ------------------------------------------------------------------ use of the estimates
    def _prep(self, data, time_column=None, time_unit=None, require_outputs=True) -> PreparedData:
        """``data`` (None: the fit data) prepared for this model, its time axis read like the
        fit's unless given (:meth:`time_options`)."""
        if data is None:
            return self.data
        if isinstance(data, PreparedData):
            return data
        time_column, time_unit = self.time_options(data, time_column, time_unit)
        return prepare_data(
            self.model,
            data,
            time_column=time_column,
            time_unit=time_unit,
            require_outputs=require_outputs,
        )

    def time_options(self, data, time_column=None, time_unit=None) -> tuple[str | None, str]:
        """The time column and unit to read other ``data`` with: those given, else the fit's.

        The fit's time column is taken only when ``data`` has it (data with a DatetimeIndex
        instead keep their index); its unit whenever none is given, so numeric times in hours
        are not read as seconds (a time column given alone takes the fit's unit too).

        Parameters
        ----------
        data : DataFrame
        time_column : str, optional
        time_unit : str, optional
            ``s``, ``min``, ``h`` or ``d``.

        Returns
        -------
        (time_column, time_unit)
        """
        if time_column is None and self.data.time_column is not None:
            if isinstance(data, pd.DataFrame) and self.data.time_column in data.columns:
                time_column = self.data.time_column
        if time_unit is None:
            time_unit = self.data.time_unit
        return time_column, time_unit

    def simulate(
        self,
        data=None,
        *,
        time_column=None,
        time_unit=None,
        initial_state=None,
        interval_means=False,
    ) -> pd.DataFrame:
        """Deterministic simulation at the estimates (default: over the fit data).

        Other ``data`` are read with the fit's time column and unit unless given
        (:meth:`time_options`).

        It starts from the estimated initial means, which belong to the start of the fit data;
        for another period give ``initial_state`` ({state: temperature [C]}), e.g. the measured
        output or the smoothed states at its first sample. ``interval_means``: each value is
        the mean over the interval its label starts [C] (to compare with a logger's interval
        means), not the value at the label.
        """
        prep = self._prep(data, time_column, time_unit, require_outputs=False)
        return simulate(
            self.model,
            prep,
            self.params.to_dict(),
            hold=self.hold,
            initial_state=initial_state,
            interval_means=interval_means,
        )

    def _filter(self, prep):
        return filter_arrays(self.model, prep, self.params.to_dict(), _hold_flag(self.hold))

    def one_step_residuals(self, data=None, *, time_column=None, time_unit=None) -> pd.DataFrame:
        """One-step predictions and residuals of each output [C] (other ``data`` read with the
        fit's time column and unit unless given, :meth:`time_options`).

        Columns per output ``y``: ``y`` (measured), ``y_pred`` (one-step prediction),
        ``y_std`` (its standard deviation incl. measurement noise [K]), ``y_residual``,
        ``y_standardized``.
        """
        prep = self._prep(data, time_column, time_unit)
        f = self._filter(prep)
        C, R = f["C"], f["meas_var"]
        pred = f["xp"] @ C.T
        var = np.einsum("ri,kij,rj->kr", C, f["Pp"], C) + R[None, :]
        out = pd.DataFrame(index=prep.index)
        for r, col in enumerate(self.model.output_names):
            out[col] = prep.Y[:, r]
            out[f"{col}_pred"] = pred[:, r]
            out[f"{col}_std"] = np.sqrt(var[:, r])
            out[f"{col}_residual"] = prep.Y[:, r] - pred[:, r]
            out[f"{col}_standardized"] = out[f"{col}_residual"] / out[f"{col}_std"]
        return out

    @property
    def residuals(self) -> pd.DataFrame:
        """One-step residuals [C] of each output over the fit data (columns = outputs)."""
        res = self.one_step_residuals()
        return res[[f"{c}_residual" for c in self.model.output_names]].rename(
            columns=lambda c: c.removesuffix("_residual")
        )

    def predict(
        self, data=None, steps: int = 1, *, time_column=None, time_unit=None
    ) -> pd.DataFrame:
        """k-step-ahead predictions of the outputs: mean [C] and standard deviation [K] (other
        ``data`` read with the fit's time column and unit unless given, :meth:`time_options`).

        The prediction at sample ``t`` uses the observations up to ``t - steps`` and the known
        inputs; the first ``steps`` rows are NaN. ``steps=1`` is the one-step prediction.
        """
        if steps < 1:
            raise ValueError("steps must be >= 1")
        prep = self._prep(data, time_column, time_unit)
        f = self._filter(prep)
        lam, T, Tinv, TB, M = f["system"]
        Xk, Pk = kernels.predict_ahead(
            lam, T, Tinv, TB, M, f["xf"], f["Pf"], prep.dts, prep.U, _hold_flag(self.hold), steps
        )
        for start in prep.segments:  # no prediction across the gap before a new period
            Xk[start : start + steps] = np.nan
            Pk[start : start + steps] = np.nan
        C, R = f["C"], f["meas_var"]
        out = pd.DataFrame(index=prep.index)
        mean = Xk @ C.T
        var = np.einsum("ri,kij,rj->kr", C, Pk, C) + R[None, :]
        for r, col in enumerate(self.model.output_names):
            out[col] = mean[:, r]
            out[f"{col}_std"] = np.sqrt(var[:, r])
        return out

    def smooth(self, data=None, *, time_column=None, time_unit=None) -> pd.DataFrame:
        """RTS-smoothed states: mean [C] and standard deviation [K] (columns ``s``, ``s_std``);
        other ``data`` read with the fit's time column and unit unless given
        (:meth:`time_options`)."""
        prep = self._prep(data, time_column, time_unit)
        xs, Ps = rts_smoother(self._filter(prep))
        out = pd.DataFrame(index=prep.index)
        for i, s in enumerate(self.model.state_names):
            out[s] = xs[:, i]
            out[f"{s}_std"] = np.sqrt(np.maximum(Ps[:, i, i], 0.0))
        return out

    # ------------------------------------------------------------------ reporting
    def parameter_table(self) -> pd.DataFrame:
        """Estimates, standard errors, bounds, units and fixed flags, one row per parameter."""
        rows = []
        for name, p in self.model.parameters.items():
            rows.append(
                {
                    "parameter": name,
                    "value": float(self.params[name]),
                    "std_error": float(self.bse[name]),
                    "unit": p.unit,
                    "lower": p.lower,
                    "upper": p.upper,
                    "fixed": p.fixed,
                }
            )
        return pd.DataFrame(rows).set_index("parameter")

    def summary(self) -> str:
        """Plain-text summary: fit statistics, parameter table, flags."""
        lines = [
            f"Model: {self.model.name}   states: {', '.join(self.model.state_names)}",
            f"Log-likelihood: {self.loglike:.4f}   AIC: {self.aic:.2f}   BIC: {self.bic:.2f}"
            + (
                ""
                if self.logposterior is None
                else f"   log posterior (MAP): {self.logposterior:.4f}"
            ),
            f"Observations: {self.nobs}   free parameters: {self.n_free}   hold: {self.hold}",
            f"Converged: {self.converged} ({self.message})   iterations: {self.n_iterations}   "
            f"time: {self.fit_seconds:.3f} s",
        ]
        if len(self.start_loglikes) > 1:
            ends = ", ".join(f"{v:.2f}" for v in self.start_loglikes)
            lines.append(f"Optimiser starts ({len(self.start_loglikes)}), log-likelihoods: {ends}")
        if self.agreement:
            lines.append(
                f"Best log-likelihood reached by {self.agreement['n_best']} of "
                f"{self.agreement['n_starts']} starts (within 0.1 log-units)"
            )
        lines += [
            "",
            f"{'parameter':<16}{'value':>14}{'std error':>12}  {'unit':<11}{'lower':>11}"
            f"{'upper':>11}  fixed",
        ]
        for name, row in self.parameter_table().iterrows():
            lines.append(
                f"{name:<16}{row['value']:>14.6g}{row['std_error']:>12.4g}  {row['unit']:<11}"
                f"{row['lower']:>11.4g}{row['upper']:>11.4g}  {'yes' if row['fixed'] else ''}"
            )
        derived = self.derived()
        if len(derived):
            lines += ["", f"{'derived quantity':<28}{'value':>14}{'std error':>12}  unit"]
            for name, row in derived.iterrows():
                lines.append(
                    f"{name:<28}{row['value']:>14.6g}{row['std_error']:>12.4g}  {row['unit']}"
                )
        taus = self.checks.get("time_constants_h")
        if taus:
            lines.append("Time constants [h]: " + ", ".join(f"{t:.4g}" for t in taus))
        if self.data.notes:
            lines += ["", "Data notes:"] + [f"  - {n}" for n in self.data.notes]
        if self.flags:
            lines += ["", "Flags:"] + [f"  - {f}" for f in self.flags]
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"<FitResults {self.model.name}: loglike={self.loglike:.3f}, k={self.n_free}>"

    def to_dict(self) -> dict[str, Any]:
        """The content of ``fit.json``."""

        def num(x: float) -> float | None:
            return float(x) if math.isfinite(x) else None

        params = {}
        for name, row in self.parameter_table().iterrows():
            params[name] = {
                "value": float(row["value"]),
                "std_error": num(row["std_error"]),
                "lower": num(row["lower"]),
                "upper": num(row["upper"]),
                "fixed": bool(row["fixed"]),
                "unit": row["unit"],
            }
        corr = self.correlation
        return {
            "model": self.model.name,
            "loglike": self.loglike,
            "logposterior": self.logposterior,
            "logprior": self.logprior,
            "aic": self.aic,
            "bic": self.bic,
            "nobs": self.nobs,
            "n_free_parameters": self.n_free,
            "converged": self.converged,
            "optimizer_message": self.message,
            "start_loglikes": [num(v) for v in self.start_loglikes],
            "starts_at_best": None if not self.agreement else self.agreement["n_best"],
            "fit_seconds": self.fit_seconds,
            "hold": self.hold,
            "params": params,
            "correlation": {
                "names": list(corr.index),
                "matrix": [[num(v) for v in row] for row in corr.to_numpy()],
            },
            "derived": {
                name: {
                    "value": num(row["value"]),
                    "std_error": num(row["std_error"]),
                    "unit": row["unit"],
                    "expression": row["expression"],
                }
                for name, row in self.derived().iterrows()
            },
            "flags": list(self.flags),
            "data_notes": list(self.data.notes),
            "checks": _jsonable(self.checks),
            "expected_gain": num(self.expected_gain),
        }


# the fits whose heat loss coefficients are profiled, in each worker process of the pool
_HLC_FITS: dict = {}


def _load_hlc_kernels(res) -> None:
    """Call the compiled functions of a heat loss coefficient's profile once (numba loads
    them from its cache on the first call)."""
    from thermocal.statespace import kernels

    model = res.model
    st = model.structure()
    state = model.state_names.index(model.heat_loss_state())
    kernels.heat_loss_theta(
        np.asarray(res.theta, dtype=float), model.transform_arrays(), st.arrays, st.n_inputs,
        state,
    )  # fmt: skip


def with_profile_interval(hlc: dict, prof: dict) -> dict:
    """A heat loss coefficient dict (Wald, see :meth:`FitResults.heat_loss_coefficient`) with
    the ends of its profile-likelihood interval ``prof`` [W/K] (from
    :func:`thermocal.statespace.profile.profile_interval`; an end not found is None, with the
    reason); ``disagree`` when an end of the Wald interval is more than 10 % of the profile
    interval's width off (never with an end not found)."""
    out = hlc | {
        "lower": prof["lower"], "upper": prof["upper"],
        "open_lower": prof["open_lower"], "open_upper": prof["open_upper"],
        "not_found_lower": prof.get("not_found_lower"),
        "not_found_upper": prof.get("not_found_upper"),
        "interval": "profile", "disagree": False,
    }  # fmt: skip
    if prof["lower"] is None or prof["upper"] is None:
        return out  # an end not found (see profile_side): nothing to compare
    width = prof["upper"] - prof["lower"]
    off = max(abs(hlc["wald_lower"] - prof["lower"]), abs(hlc["wald_upper"] - prof["upper"]))
    return out | {"disagree": bool(not math.isfinite(hlc["std_error"]) or off > 0.1 * width)}


def _hlc_side_worker(args):
    """One side of the heat loss coefficient's profile of ``_HLC_FITS[name]``, in a worker.

    ``args``: ``(name, side, alpha, centre)``; ``centre``, when not None, replaces the profile
    point at the estimate before the side is computed (the point as the other side left it,
    see :func:`_centre_moved`).

    Returns ``(name, side, end, cache, error)``: the end [W/K] and whether it is open, the
    profile points computed (value [W/K] -> (log-likelihood, theta)), or the message of the
    input error that stopped it (``end`` and ``cache`` then None).
    """
    from thermocal.errors import ThermocalInputError
    from thermocal.statespace.convergence import one_blas_thread
    from thermocal.statespace.profile import profile_setup, profile_side

    name, side, alpha, centre = args
    one_blas_thread()  # for the worker's lifetime: the pool is the parallelism
    try:
        prof, threshold, drop = profile_setup(_HLC_FITS[name], "heat_loss_coefficient",
                                              alpha=alpha)  # fmt: skip
        if centre is not None:
            prof.cache[prof.center] = centre
        end = profile_side(prof, side, threshold, drop)
    except ThermocalInputError as exc:
        return name, side, None, None, str(exc)
    return name, side, end, prof.cache, None


def _centre_moved(res, cache) -> tuple | None:
    """The profile point at the estimate as a side of the profile left it (``cache``), when it
    is no longer the fit's own (log-likelihood and theta): Brent's method evaluates the
    profile at the estimate when the first step out already crosses the threshold, and that
    constrained fit replaces the point; the other side then starts from it. None otherwise."""
    if cache is None or not cache:
        return None
    ll, theta = next(iter(cache.values()))  # the estimate: the first point of every profile
    same = ll == res.loglike and np.array_equal(theta, np.asarray(res.theta, dtype=float))
    return None if same else (ll, theta)


def _hlc_from_sides(res, alpha: float, sides: dict) -> dict:
    """:meth:`FitResults.heat_loss_coefficient` with the profile from its two sides computed
    apart (``sides``: side -> ``(end, cache, error)`` of :func:`_hlc_side_worker`, the upper
    side started from the estimate's point as the lower side left it): the same dict, flags
    and convergence as computed in one piece."""
    from thermocal.statespace.profile import SIDES, profile_setup, profile_summary

    out = res.heat_loss_coefficient(alpha=alpha, profile=False)
    for side in SIDES:  # the first error, as in one piece (lower side first)
        if sides[side][2] is not None:
            return out | {"profile_error": sides[side][2]}
    name = "heat_loss_coefficient"
    prof, threshold, _ = profile_setup(res, name, alpha=alpha)
    for side in SIDES:
        prof.cache.update(sides[side][1])
    ends = [sides[side][0] for side in SIDES]
    return with_profile_interval(out, profile_summary(res, name, prof, ends, threshold, alpha))


def _hlc_sides(pool, fits, todo, alpha) -> dict:
    """Both sides of the heat loss coefficient's profile of each fit in ``todo``, as tasks of
    ``pool`` (the longest profiles, most free parameters, first).

    The sides share one point, the estimate's (see :func:`_centre_moved`): the upper side is
    computed from the fit's own point, and computed again from the lower side's when that
    side moved it, so the results are those of the two sides one after the other.

    Returns
    -------
    dict
        ``{(name, side): (end, cache, error)}``.
    """
    from thermocal.statespace.profile import SIDES

    lower, upper = SIDES
    order = sorted(todo, key=lambda n: -fits[n].n_free)
    tasks = [(n, side, alpha, None) for n in order for side in SIDES]
    done = {(n, side): rest for n, side, *rest in pool.map(_hlc_side_worker, tasks)}
    again = []
    for n in order:
        if done[n, lower][2] is None:
            centre = _centre_moved(fits[n], done[n, lower][1])
            if centre is not None:
                again.append((n, upper, alpha, centre))
    for n, side, *rest in pool.map(_hlc_side_worker, again):
        done[n, side] = tuple(rest)
    return {key: tuple(value) for key, value in done.items()}


def heat_loss_coefficients(
    fits, *, profile=(), alpha: float = 0.05, n_jobs: int | None = None
) -> dict:
    """:meth:`FitResults.heat_loss_coefficient` of several fits, with the profile-likelihood
    intervals of the fits named in ``profile`` computed in parallel processes (each profile is
    a series of constrained refits; on ``n_jobs`` cores they run side by side).

    Parameters
    ----------
    fits : mapping
        ``FitResults`` by name.
    profile : collection of str
        Names whose interval is the profile-likelihood one (the others: Wald).
    alpha : float
        1 - confidence level.
    n_jobs : int, optional
        Processes (default: the number of CPUs, at most one per profile).

    Returns
    -------
    dict
        ``{name: heat loss coefficient dict}`` for the fits whose structure implies one. A
        profile that finds a better optimum marks its fit not converged and flags it, as when
        computed in this process.
    """
    import os

    from thermocal.statespace.profile import SIDES

    names = [n for n, r in fits.items() if r.model.heat_loss_state() is not None]
    todo = [n for n in names if n in set(profile)]
    out = {}
    if n_jobs is None:
        n_jobs = min(len(SIDES) * len(todo), os.cpu_count() or 1)
    if todo and n_jobs > 1:
        import multiprocessing as mp
        from concurrent.futures import ProcessPoolExecutor

        global _HLC_FITS
        _HLC_FITS = {n: fits[n] for n in todo}
        ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else None)
        if ctx.get_start_method() == "fork":
            _load_hlc_kernels(fits[todo[0]])  # here once, inherited by the forked workers
        try:
            with ProcessPoolExecutor(min(n_jobs, len(SIDES) * len(todo)), mp_context=ctx) as pool:
                done = _hlc_sides(pool, fits, todo, alpha)
        finally:
            _HLC_FITS = {}
        for n in todo:
            out[n] = _hlc_from_sides(fits[n], alpha, {side: done[n, side] for side in SIDES})
    for name in names:
        if name not in out:
            out[name] = fits[name].heat_loss_coefficient(alpha=alpha, profile=name in todo)
    return {n: out[n] for n in names}


def observation_rows(Y: np.ndarray) -> np.ndarray:
    """The rows the residual tests take [-]: every row, or, when the outputs are observed
    only on every m-th row by design (:func:`thermocal.statespace.data.midpoint_observations`:
    every second), those rows, so that a lag is an observation interval and the unobserved
    rows do not turn every odd lag's autocorrelation into NaN.

    Parameters
    ----------
    Y : ndarray (samples, outputs)
        Observed outputs, NaN where missing.
    """
    observed = np.flatnonzero(np.isfinite(Y).any(axis=1))
    everything = np.arange(Y.shape[0])
    if observed.size < 2:
        return everything
    stride = int(np.gcd.reduce(np.diff(observed)))
    if stride <= 1:
        return everything
    return everything[observed[0] :: stride]


def _duration(seconds: float) -> str:
    """A duration in the most readable unit."""
    if seconds < 120:
        return f"{seconds:.3g} s"
    if seconds < 7200:
        return f"{seconds / 60:.3g} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 86400:.3g} d"


def _stamp(prep: PreparedData, k: int) -> str:
    """The time label of sample ``k``, readable."""
    t = prep.index[k]
    if isinstance(t, (float, np.floating, int, np.integer)):
        return f"t = {float(t):.6g} {prep.time_unit}"
    return str(t)


def _listed(prep: PreparedData, j: int, rows: np.ndarray, unit: str, n: int = 3) -> str:
    """The ``n`` most extreme of ``rows`` of input ``j``: 'value unit at time', largest first."""
    u = prep.U[rows, j]
    order = rows[np.argsort(-np.abs(u - np.nanmedian(prep.U[:, j])), kind="stable")][:n]
    return ", ".join(f"{prep.U[k, j]:.4g}{' ' + unit if unit else ''} at {_stamp(prep, k)}"
                     for k in order)  # fmt: skip


def robust_range(u: np.ndarray) -> tuple[float, float, float]:
    """(centre, scale, level) of a series from robust statistics.

    ``centre`` is the median; ``scale`` the larger of 1.4826 MAD (the standard deviation of
    normal data) and ``(q90 - q10) / 2.563`` (the same for normal data, and not zero for on/off
    series whose median absolute deviation is); ``level`` the 90 % quantile of ``|u|``, the
    typical magnitude of a heat input. None of them moves with fewer than 10 % outliers, unlike
    the 1-99 % quantile range (a few 245 kW spikes stretch it to 85 kW).
    """
    centre = float(np.median(u))
    mad = 1.4826 * float(np.median(np.abs(u - centre)))
    q10, q90 = np.quantile(u, [0.1, 0.9])
    scale = max(mad, float(q90 - q10) / 2.563)
    return centre, scale, float(np.quantile(np.abs(u), 0.9))


def data_flags(model, prep: PreparedData) -> list[str]:
    """Faults of the data themselves, whatever the estimates: output temperatures outside
    the physical range (:func:`output_range_flags`), a heated room colder than all its
    surroundings (:func:`inverted_balance_flags`) and an irradiance too dim for its unit
    (:func:`dim_irradiance_flags`).

    Parameters
    ----------
    model : RCModel
    prep : PreparedData
        The data as fitted (inputs in their columns' units, outputs [C]).

    Returns
    -------
    list of str
        The flags, each with its remedy.
    """
    return (
        output_range_flags(model, prep)
        + inverted_balance_flags(model, prep)
        + dim_irradiance_flags(model, prep)
    )


def output_range_flags(model, prep: PreparedData) -> list[str]:
    """Output temperatures outside the physical range (:data:`PHYSICAL_LIMITS`), the check the
    boundary temperatures get (:func:`input_flags`): a logger's missing-value code (-9999,
    999) read as a temperature.

    Parameters
    ----------
    model : RCModel
    prep : PreparedData
        The data as fitted (inputs in their columns' units, outputs [C]).

    Returns
    -------
    list of str
        One flag per output column, naming the number of values, the first rows (0-based data
        rows; times only when the likelihood is split into periods, whose rows are renumbered)
        with their values and times, and the remedy (NaN: the filter skips missing outputs).
    """
    lo, hi = PHYSICAL_LIMITS["C"]
    flags = []
    for r, col in enumerate(model.output_names):
        y = prep.Y[:, r]
        with np.errstate(invalid="ignore"):
            bad = np.flatnonzero((y < lo) | (y > hi))
        if not bad.size:
            continue
        shown = ", ".join(
            f"{y[k]:.6g} at {_stamp(prep, k)}" if prep.segments.size
            else f"{y[k]:.6g} in row {k} ({_stamp(prep, k)})"
            for k in bad[:ROWS_LISTED]
        )  # fmt: skip
        more = f" and {bad.size - ROWS_LISTED} more" if bad.size > ROWS_LISTED else ""
        flags.append(
            f"output '{col}' (temperature [C]) has {bad.size} value(s) outside the physical "
            f"range [{lo:g}, {hi:g}] C: {shown}{more}; a logger's missing-value code (-9999, "
            "999)? remedy: set those values to NaN (leave the cells empty): the filter skips "
            "missing outputs; the estimates of this fit are distorted by them"
        )
    return flags


def inverted_balance_flags(model, prep: PreparedData) -> list[str]:
    """A heated room colder on average than all its boundary temperatures
    (:func:`thermocal.statespace.checks.inverted_balance_message`): an outdoor temperature in
    Fahrenheit, swapped columns or a heat input of the wrong sign.

    The heat is that of the heat inputs of known power without a scale (W, kW, MW); the
    room's temperature the output observing the heat-loss state
    (:func:`thermocal.statespace.data.indoor_outputs`), its values inside the physical range
    (:func:`output_range_flags` names the others).

    Parameters
    ----------
    model : RCModel
    prep : PreparedData
        The data as fitted (inputs in their columns' units, outputs [C]).

    Returns
    -------
    list of str
        At most one flag.
    """
    from thermocal.statespace.checks import inverted_balance_message
    from thermocal.statespace.data import indoor_outputs
    from thermocal.statespace.units import HEAT_COLUMN_UNITS

    indoor = [c for c in model.output_names if c in indoor_outputs(model)]
    n_b = len(model.boundary_names)
    if not indoor or not n_b:
        return []
    known = dict.fromkeys(
        (h["column"], h.get("unit") or "W") for h in model._heat_inputs
        if h.get("scale") is None and not (h.get("unit") or "W").endswith("/m2")
    )  # fmt: skip
    means = {(c, u): float(np.nanmean(prep.U[:, model.input_names.index(c)])) for c, u in known}
    y = prep.Y[:, model.output_names.index(indoor[0])]
    lo, hi = PHYSICAL_LIMITS["C"]
    with np.errstate(invalid="ignore"):
        y = y[(y >= lo) & (y <= hi)]  # missing-value codes are flagged on their own
    if not means or not y.size:
        return []
    heat = sum(m * HEAT_COLUMN_UNITS[u] for (_, u), m in means.items())
    text = "; ".join(f"'{c}' averages {m:.4g} {u}" for (c, u), m in means.items())
    boundaries = {b: float(np.nanmean(prep.U[:, j])) for j, b in enumerate(model.boundary_names)}
    message = inverted_balance_message(indoor[0], float(np.nanmean(y)), boundaries, text, heat)
    return [] if message is None else [message]


def dim_irradiance_flags(model, prep: PreparedData) -> list[str]:
    """Irradiance columns too dim for their declared unit
    (:func:`thermocal.statespace.units.dim_irradiance`: a maximum below
    :data:`~thermocal.statespace.units.DIM_IRRADIANCE_W_M2` over at least
    :data:`~thermocal.statespace.units.DIM_IRRADIANCE_DAYS` days, where the sun gives hundreds
    of W/m2 every day): a column in kW/m2 declared W/m2. A free aperture absorbs the factor (it
    runs to its upper bound), so the heat-unit checks stay silent. The fit knows no site, so
    every day counts: data of a polar night are flagged too (a flag, not a refusal; the
    retrofit workflow, which knows the latitude, leaves those days out).

    Parameters
    ----------
    model : RCModel
    prep : PreparedData
        The data as fitted (inputs in their columns' units, outputs [C]).

    Returns
    -------
    list of str
        One flag per column, naming its maximum, the span, and the unit that would give it a
        physical peak.
    """
    from thermocal.statespace.units import HEAT_COLUMN_UNITS

    days = (prep.seconds - prep.seconds[0]) / 86400.0
    flags = []
    for col, unit in dict.fromkeys(
        (h["column"], h.get("unit") or "W") for h in model._heat_inputs
    ):
        if not unit.endswith("/m2"):
            continue
        u = prep.U[:, model.input_names.index(col)]
        dim = dim_irradiance(u * HEAT_COLUMN_UNITS[unit], days)
        if dim is None:
            continue
        peak, span_days = dim[0] / HEAT_COLUMN_UNITS[unit], dim[1]
        alt = [a for a, f in HEAT_UNIT_SLIPS.get(unit, [])
               if DIM_IRRADIANCE_W_M2 <= peak * HEAT_COLUMN_UNITS[unit] * f
               <= PHYSICAL_LIMITS["W/m2"][1]]  # fmt: skip
        remedy = (
            f"is the column in {alt[0]}? (its peak would be "
            f"{peak * HEAT_COLUMN_UNITS[alt[0]]:.4g} W/m2) remedy: set 'unit: {alt[0]}' for "
            f"'{col}' in heat_inputs (or convert the column); thermocal select: --solar-unit "
            f"{alt[0]}"
            if alt
            else "check the unit and the sensor (covered, disconnected)"
        )
        flags.append(
            f"irradiance '{col}' never exceeds {peak:.4g} {unit} over {span_days:.3g} days: "
            f"sunlight gives hundreds of W/m2 on most days (beyond "
            f"{DIM_IRRADIANCE_W_M2:g} W/m2 every day but in a polar night, which this check "
            f"cannot tell without the site: ignore the flag for data of a polar night); "
            f"{remedy}; a free aperture absorbs the factor and ends on its bound"
        )
    return flags


def single_start_flag(results) -> str | None:
    """The flag of a fit whose global optimum was not checked: one optimiser start (with a
    finite end), so no second start could reach the best value (``converged`` then rests on
    the Newton criterion at that end point alone).

    Parameters
    ----------
    results : FitResults

    Returns
    -------
    str or None
    """
    agreement = results.agreement
    if not agreement or agreement["n_starts"] >= 2:
        return None
    return (
        "global optimum not checked: a single optimiser start, so no second start could reach "
        "the best value; 'converged' rests on the Newton criterion at this end point alone; "
        "remedy: more starts (--n-starts)"
    )


def input_flags(model, prep: PreparedData) -> list[str]:
    """Flags on the input columns, from robust statistics (:func:`robust_range`).

    - negative values of a heat input beyond :data:`NEGATIVE_OFFSET_FRACTION` of its typical
      level (smaller ones are sensor offsets, a pyranometer at night), unless the model file
      declares the column ``allow_negative`` (ventilation, extraction);
    - spikes: values more than :data:`SPIKE_SCALES` robust standard deviations from the median;
    - values outside the physical limits of the declared unit (:data:`PHYSICAL_LIMITS`).

    Each flag names the column, the number of values, and the most extreme ones with their time
    stamps.
    """
    from thermocal.statespace.units import HEAT_COLUMN_UNITS

    flags = []
    heat = {h["column"]: h for h in model._heat_inputs}
    for j, col in enumerate(model.input_names):
        u = prep.U[:, j]
        finite = u[np.isfinite(u)]
        if not finite.size:
            continue
        spec = heat.get(col)
        unit = (spec.get("unit") or "W") if spec else "C"
        centre, scale, level = robust_range(finite)
        with np.errstate(invalid="ignore"):
            if spec is not None and not spec.get("allow_negative"):
                offset = NEGATIVE_OFFSET_FRACTION * level
                neg = np.flatnonzero(u < -offset)
                if neg.size:
                    flags.append(
                        f"heat input '{col}' has {neg.size} negative value(s) below -{offset:.3g} "
                        f"{unit} (5 % of its 90 % level), most negative "
                        f"{_listed(prep, j, neg, unit)}: a heat input is >= 0 unless it "
                        "includes cooling; remedy: check the meter sign and the supply/return "
                        "temperatures, set the values to NaN, or declare the column "
                        "'allow_negative: true' in heat_inputs when it is a ventilation or "
                        "extraction heat flow"
                    )
            if scale > 0:
                far = np.flatnonzero(np.abs(u - centre) > SPIKE_SCALES * scale)
                if far.size:
                    lo, hi = centre - SPIKE_SCALES * scale, centre + SPIKE_SCALES * scale
                    flags.append(
                        f"input '{col}' has {far.size} value(s) far outside its robust range "
                        f"[{lo:.4g}, {hi:.4g}] {unit} (median +- {SPIKE_SCALES:g} robust standard "
                        f"deviations), e.g. {_listed(prep, j, far, unit)}: a spike or unit "
                        "error; remedy: check the data there and remove the values (NaN) or cut "
                        "the period"
                    )
            limits = None
            if spec is None:
                limits, si, what = PHYSICAL_LIMITS["C"], 1.0, "temperature [C]"
            elif unit.endswith("/m2"):
                limits, si = PHYSICAL_LIMITS["W/m2"], HEAT_COLUMN_UNITS.get(unit, 1.0)
                what = f"irradiance [{unit}]"
            if limits is not None:
                lo, hi = limits
                bad = np.flatnonzero((u * si < lo) | (u * si > hi))
                if bad.size:
                    flags.append(
                        f"input '{col}' ({what}) has {bad.size} value(s) outside the physical "
                        f"range [{lo / si:.4g}, {hi / si:.4g}] {unit}: "
                        f"{_listed(prep, j, bad, unit)}; remedy: check the unit (Kelvin? "
                        "W/m2 vs kW/m2?) and the sensor"
                    )
    return flags + heat_unit_flags(model, prep)


#: Declared heat-column unit -> (the unit a factor 1000 off, the factor to it).
_UNIT_SLIPS = HEAT_UNIT_SLIPS
#: The energy-balance check speaks when the declared unit misses the mean measured output by
#: more than this [K] and the alternative unit comes this many times closer.
UNIT_SLIP_MISS_K = 5.0
UNIT_SLIP_IMPROVEMENT = 5.0


def heat_unit_flags(model, prep: PreparedData) -> list[str]:
    """Heat inputs whose magnitude does not fit the model's conductances (W vs kW).

    A steady-state energy balance at the *declared* parameter values (the user's physics, not
    the estimates, which absorb a unit slip): the outputs the model would settle at under the
    mean inputs, ``C (-A^-1 B u_mean)``, against the mean measured outputs. When reading one
    heat column in the unit a factor 1000 away brings them within reach while the declared unit
    misses by more than :data:`UNIT_SLIP_MISS_K`, the column's unit is probably wrong.
    """
    try:
        A, B, C, _ = model.continuous_matrices()
        A_inv = np.linalg.inv(A)
    except (np.linalg.LinAlgError, ValueError):
        return []  # no path to a boundary: no steady state
    u_mean = np.nanmean(prep.U, axis=0)
    y_mean = np.array([np.nanmean(prep.Y[:, r]) for r in range(prep.Y.shape[1])])
    if not (np.all(np.isfinite(u_mean)) and np.all(np.isfinite(A_inv))):
        return []

    def miss(u) -> tuple[float, np.ndarray]:
        y = C @ (-A_inv @ (B @ u))
        return float(np.nanmax(np.abs(y - y_mean))), y

    base_miss, base_y = miss(u_mean)
    if not base_miss > UNIT_SLIP_MISS_K:
        return []
    units = {h["column"]: h.get("unit") or "W" for h in model._heat_inputs}
    flags = []
    for j, col in enumerate(model.input_names):
        if col not in units or u_mean[j] == 0:
            continue
        for alt, factor in _UNIT_SLIPS.get(units[col], []):
            u = u_mean.copy()
            u[j] *= factor
            alt_miss, alt_y = miss(u)
            if alt_miss * UNIT_SLIP_IMPROVEMENT < base_miss and alt_miss < UNIT_SLIP_MISS_K:
                out = model.output_names[0]
                flags.append(
                    f"heat input '{col}' is declared in {units[col]}, but at the declared "
                    f"parameter values its mean ({u_mean[j]:.4g} {units[col]}) would hold "
                    f"'{out}' at {base_y[0]:.4g} C in steady state against {y_mean[0]:.4g} C "
                    f"measured; read as {alt} it would be {alt_y[0]:.4g} C: is the column in "
                    f"{alt}? remedy: set 'unit: {alt}' for '{col}' in heat_inputs (or convert "
                    "the column); estimates fitted with the wrong unit end at their bounds"
                )
                break
    return flags


def known_power_columns(model, prep: PreparedData) -> list[tuple[str, str]]:
    """The heat inputs of known power that are not zero: ``(column, unit)`` of the columns in
    W, kW or MW entering with no scale or a fixed one (a constant or a fixed parameter)."""
    free = set(model.free_parameter_names)
    out = []
    for h in model._heat_inputs:
        unit, scale, col = h.get("unit") or "W", h.get("scale"), h["column"]
        if unit.endswith("/m2") or (isinstance(scale, str) and scale in free):
            continue
        if np.any(np.nan_to_num(prep.U[:, model.input_names.index(col)]) != 0):
            out.append((col, unit))
    return list(dict.fromkeys(out))


def heat_loss_unit_flags(model, params, prep: PreparedData) -> list[str]:
    """A heat column probably in another unit, judged by the estimated heat loss coefficient.

    With one heat input of known power (:func:`known_power_columns`), the fitted coefficient
    is proportional to that column's unit: capacities, coefficient and free scales (solar
    apertures) follow it, the time constants do not. A coefficient outside the range of
    buildings (:data:`~thermocal.statespace.units.PLAUSIBLE_HEAT_LOSS_W_PER_K`) that the
    column read a factor 1000 away brings inside is flagged
    (:func:`~thermocal.statespace.units.heat_unit_slip`). Complements
    :func:`heat_unit_flags`, which needs declared values near the building's.

    Parameters
    ----------
    model : RCModel
    params : mapping
        The estimates [declared units].
    prep : PreparedData

    Returns
    -------
    list of str
        At most one flag, naming the column, both units and both coefficients [W/K].
    """
    known = known_power_columns(model, prep)
    if model.heat_loss_state() is None or len(known) != 1:
        return []  # several columns of known power: no single factor to blame
    (col, unit), (lo, hi) = known[0], PLAUSIBLE_HEAT_LOSS_W_PER_K
    try:
        value = model.heat_loss_coefficient(params)
    except ThermocalInputError:
        return []
    slip = heat_unit_slip(value, unit)
    if slip is None:
        return []
    alt, alt_value = slip
    return [
        f"heat loss coefficient {value:.4g} W/K at the estimates lies outside the range of "
        f"buildings ({lo:g} to {hi:g} W/K); heat input '{col}' is declared in {unit}: read as "
        f"{alt} it would be about {alt_value:.4g} W/K: is the column in {alt}? remedy: set "
        f"'unit: {alt}' for '{col}' in heat_inputs (or convert the column); for a building "
        "that size indeed, ignore this flag"
    ]


#: A daily cycle shows as an autocorrelation of at least DAILY_ACF at the lag of one day and
#: DAILY_CONTRAST more than at half a day (night against day): the irradiance of the Bacher &
#: Madsen data gives 0.62 and -0.26, a smooth series without daily cycle less at a day than
#: at half of it.
DAILY_ACF = 0.3
DAILY_CONTRAST = 0.5


def daily_cycle(u: np.ndarray, step: float) -> bool | None:
    """Whether a series repeats every 24 h (night and day), at a sampling interval ``step``.

    Parameters
    ----------
    u : ndarray
        The series (an irradiance), NaN left out of the autocorrelation.
    step : float [s]
        Its sampling interval.

    Returns
    -------
    bool or None
        None when the series covers fewer than two days at ``step`` or a half day is shorter
        than two samples (nothing to judge).
    """
    half = int(round(43200.0 / step))
    x = np.asarray(u, dtype=float)
    if half < 2 or 4 * half > x.size:
        return None
    x = np.where(np.isfinite(x), x - np.nanmean(x), 0.0)
    power = float(x @ x)
    if not power > 0:
        return None
    day, night = (float(x[:-lag] @ x[lag:]) / power for lag in (2 * half, half))
    return day >= DAILY_ACF and day - night >= DAILY_CONTRAST


def time_unit_flags(model, prep: PreparedData) -> list[str]:
    """Numeric times probably given in another unit, judged by the sun's daily cycle.

    An irradiance column (a heat input in W/m2 or kW/m2) repeats every 24 h. When it shows
    no daily cycle with the times read in the given unit (or covers less than two days in it)
    but does with the times read in another of
    :data:`~thermocal.statespace.units.TIME_UNITS`, the unit is probably wrong: capacities and
    time constants scale with it (hours read as minutes make them 60 times too small). Only
    for numeric times (date-times carry their unit) and roughly uniform sampling (the median
    interval is used). The outdoor temperature is not used: weather hides its daily cycle
    (autocorrelation 0.24 at 24 h, 0.33 at 12 h on the Bacher & Madsen data).

    Returns
    -------
    list of str
        At most one flag, naming the column, the given and the likely unit.
    """
    if isinstance(prep.index, pd.DatetimeIndex) or prep.time_unit not in TIME_UNITS:
        return []
    step = float(np.median(prep.dts))
    given = TIME_UNITS[prep.time_unit]
    for h in model._heat_inputs:
        if not (h.get("unit") or "W").endswith("/m2"):
            continue
        col = h["column"]
        u = prep.U[:, model.input_names.index(col)]
        if daily_cycle(u, step):
            continue
        for alt, seconds in TIME_UNITS.items():
            if alt != prep.time_unit and daily_cycle(u, step * seconds / given):
                span = (prep.seconds[-1] - prep.seconds[0]) / given
                return [
                    f"irradiance '{col}' shows no daily cycle with the times in "
                    f"{prep.time_unit} (--time-unit {prep.time_unit}: the data span "
                    f"{span:.4g} {prep.time_unit}), but one of 24 h with the times in {alt}: "
                    f"are the times in {alt}? remedy: --time-unit {alt} (time_unit='{alt}'); "
                    f"read in {prep.time_unit}, capacities and time constants are "
                    f"{max(seconds / given, given / seconds):g} times too "
                    f"{'small' if seconds > given else 'large'}"
                ]
    return []


def _positive_definite(matrix: np.ndarray) -> bool:
    """True when the symmetric ``matrix`` has a Cholesky factor."""
    try:
        np.linalg.cholesky(matrix)
    except np.linalg.LinAlgError:
        return False
    return True
