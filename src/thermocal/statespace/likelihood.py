"""The negative log-likelihood of a state-space model on prepared data as a function of the
free parameters' unconstrained values ``theta``: value, batch of values, gradient and Hessian by
central differences, priors, and the search box the optimiser works in.

:mod:`thermocal.statespace.estimation` optimises it; :mod:`thermocal.statespace.profile` holds
parameters fixed in it.
"""

from __future__ import annotations

import math

import numpy as np

from thermocal.statespace import kernels
from thermocal.statespace.data import PreparedData
from thermocal.statespace.kalman import _periods

#: Relative step of the central-difference gradient in theta.
GRADIENT_STEP = 1e-6
#: Half-width of the search box in theta (see :class:`LikelihoodProblem`).
THETA_SPAN = 25.0


class LikelihoodProblem:
    """The negative log-likelihood of a model on prepared data, as a function of ``theta``."""

    def __init__(self, model, prep: PreparedData, foh: bool) -> None:
        self.model = model
        self.prep = prep
        self.foh = foh
        st = model.structure()
        self.tr = model.transform_arrays()
        self.st = st.arrays
        self.C = st.C
        self.scale = float(max(prep.nobs, 1))
        self.seg = np.asarray(prep.segments, dtype=np.int64)
        _periods(model, prep)  # the model has an initial state per period
        self.iterations = 0  # optimiser iterations over all runs
        free = model.free_parameter_names
        self.priors = [
            (i, model.parameters[n]) for i, n in enumerate(free) if model.parameters[n].prior
        ]
        # box in theta: a factor e^THETA_SPAN either way of the start for log transforms,
        # +-THETA_SPAN for logits (1e-13 of the range from a bound); a parameter running away
        # towards a bound (e.g. a noise std to 0) stops there instead of wandering to -1e3
        theta0 = model.theta0()
        kinds = self.tr[1]
        log_kind = (kinds == kernels.TRANSFORM_LOG) | (kinds == kernels.TRANSFORM_NEGLOG)
        logit = kinds == kernels.TRANSFORM_LOGIT
        self.lo = np.where(log_kind, theta0 - THETA_SPAN, np.where(logit, -THETA_SPAN, -np.inf))
        self.hi = np.where(log_kind, theta0 + THETA_SPAN, np.where(logit, THETA_SPAN, np.inf))

    def clip(self, theta: np.ndarray) -> np.ndarray:
        """``theta`` limited to the search box."""
        return np.clip(np.asarray(theta, dtype=float), self.lo, self.hi)

    def loglike(self, theta: np.ndarray) -> float:
        """Log-likelihood at ``theta``."""
        p = self.prep
        return float(
            kernels.loglike_theta(
                np.asarray(theta, dtype=float),
                self.tr,
                self.st,
                self.C,
                p.dts,
                p.U,
                p.Y,
                self.foh,
                self.seg,
            )  # fmt: skip
        )

    def loglike_many(self, thetas: np.ndarray) -> np.ndarray:
        """Log-likelihoods at the rows of ``thetas``, evaluated together (the same values as
        :meth:`loglike` row by row, see :func:`kernels.loglike_batch`)."""
        p = self.prep
        thetas = np.ascontiguousarray(np.atleast_2d(np.asarray(thetas, dtype=float)))
        return kernels.loglike_batch(
            thetas, self.tr, self.st, self.C, p.dts, p.U, p.Y, self.foh, self.seg
        )

    def target_many(self, thetas: np.ndarray) -> np.ndarray:
        """:meth:`target` at the rows of ``thetas``."""
        ll = self.loglike_many(thetas)
        if self.priors:
            ll = ll + np.array([self.logprior(t)[0] for t in np.atleast_2d(thetas)])
        return ll

    def logprior(self, theta: np.ndarray) -> tuple[float, np.ndarray]:
        """Log prior density (declared units, no Jacobian) and its gradient in ``theta``."""
        total, grad = 0.0, np.zeros(len(theta))
        for i, p in self.priors:
            x = p.from_unconstrained(theta[i])
            value, slope = p.log_prior(x)
            total += value
            grad[i] = slope * p.derivative(theta[i])
        return total, grad

    def target(self, theta: np.ndarray) -> float:
        """The maximised function: log-likelihood, plus the log prior density with priors."""
        ll = self.loglike(theta)
        return ll + self.logprior(np.asarray(theta, dtype=float))[0] if self.priors else ll

    def objective(self, theta: np.ndarray) -> tuple[float, np.ndarray]:
        """Negative log-likelihood (log posterior with priors) per observation and gradient.

        Scaling by the number of observations keeps the gradient of order one, so the first
        quasi-Newton step (taken with an identity metric) stays reasonable. Non-finite values are
        replaced by a large penalty.
        """
        p = self.prep
        theta = np.asarray(theta, dtype=float)
        clipped = self.clip(theta)
        f, g = kernels.negloglike_and_gradient(
            clipped, self.tr, self.st, self.C, p.dts, p.U, p.Y, self.foh, self.seg,
            GRADIENT_STEP,
        )  # fmt: skip
        if self.priors:
            lp, lg = self.logprior(clipped)
            f, g = f - lp, g - lg
        if not math.isfinite(f):
            return 1e20, np.zeros_like(theta)
        g = np.where(np.isfinite(g) & (clipped == theta), g, 0.0)  # flat outside the box
        return float(f) / self.scale, g / self.scale

    def hessian(self, theta: np.ndarray) -> np.ndarray:
        """Central-difference Hessian of :meth:`target` (the log-likelihood, plus the log prior
        density when priors are declared) in ``theta``."""
        theta = np.asarray(theta, dtype=float)
        k = theta.size
        h = np.finfo(float).eps ** 0.25 * np.maximum(np.abs(theta), 1.0)
        # all points of the central differences, evaluated together
        points = [theta]
        for i in range(k):
            e = np.zeros(k)
            e[i] = h[i]
            points += [theta + e, theta - e]
        pairs = [(i, j) for i in range(k) for j in range(i + 1, k)]
        for i, j in pairs:
            ei = np.zeros(k)
            ej = np.zeros(k)
            ei[i] = h[i]
            ej[j] = h[j]
            points += [theta + ei + ej, theta + ei - ej, theta - ei + ej, theta - ei - ej]
        values = self.target_many(np.array(points))
        f0 = values[0]
        H = np.empty((k, k))
        for i in range(k):
            fp, fm = values[1 + 2 * i], values[2 + 2 * i]
            H[i, i] = (fp - 2.0 * f0 + fm) / h[i] ** 2
        for q, (i, j) in enumerate(pairs):
            fpp, fpm, fmp, fmm = values[1 + 2 * k + 4 * q : 5 + 2 * k + 4 * q]
            H[i, j] = H[j, i] = (fpp - fpm - fmp + fmm) / (4.0 * h[i] * h[j])
        return H
