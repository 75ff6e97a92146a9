"""Meta-models of the campaign metric: support vector regression and Gaussian process.

Both share one small scikit-learn-style API: ``fit(X, y)`` returns self, fitted attributes end in
``_``, ``predict(X, return_std=False)``.  After ``fit`` they carry the cross-validated quality:
``cv_r2_``, ``cv_rmse_`` (in the unit of the metric) and ``oof_prediction_`` (out-of-fold
predictions from :func:`sklearn.model_selection.cross_val_predict`, for a parity plot).

:class:`SVRSurrogate` is the paper's meta-model: an RBF support vector regression on standardised
inputs, with the target standardised too; ``C``, ``epsilon`` and ``gamma`` are chosen by a grid
search with seeded shuffled K-fold cross-validation.  The out-of-fold predictions reuse the chosen
hyper-parameters, so the reported R2 is slightly optimistic (no nested cross-validation).

:class:`GPSurrogate` is a Gaussian process with an anisotropic Matern-5/2 kernel plus a white-noise
kernel on standardised inputs (``normalize_y=True``); it also gives a predictive standard
deviation.

``log_target=True`` fits the logarithm of the metric (useful when the metric is a variance that
spans decades; the paper fits the variance itself).  Predictions are then ``exp`` of the fitted
mean (the median of a log-normal), and the GP standard deviation is propagated to first order
(``exp(mu) * sigma``).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import pandas as pd
from sklearn.base import clone
from sklearn.compose import TransformedTargetRegressor
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import ConstantKernel, Matern, WhiteKernel
from sklearn.model_selection import GridSearchCV, KFold, cross_val_predict
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVR

from thermocal.calibration.coordinates import coordinate_kinds, from_coordinates, to_coordinates
from thermocal.errors import ThermocalInputError

__all__ = [
    "SERIES_TERMS",
    "GPSurrogate",
    "SVRSurrogate",
    "bounded_series_fit",
    "make_surrogate",
    "regression_scores",
    "series_design",
]

#: forms of the series meta-model's hourly regressions in its coordinates ``z``: affine
#: (the published form), with a per-parameter quadratic term, or chosen by cross-validation
SERIES_TERMS = ("auto", "affine", "quadratic")


def series_design(Z: np.ndarray, terms: str) -> np.ndarray:
    """Features of the series meta-model's hourly regressions.

    Parameters
    ----------
    Z : ndarray (n, d)
        Coordinates of the parameters (:mod:`thermocal.calibration.coordinates`) [-].
    terms : {"affine", "quadratic"}
        ``z`` alone, or ``z`` and each ``z_k^2`` (no cross terms): ``[z, z**2]``.

    Returns
    -------
    ndarray (n, d) or (n, 2 d) [-]
    """
    Z = np.atleast_2d(np.asarray(Z, dtype=float))
    if terms == "affine":
        return Z
    if terms == "quadratic":
        return np.hstack([Z, Z**2])
    raise ThermocalInputError(f"series meta-model: terms {terms!r} unknown; use affine/quadratic")


def bounded_series_fit(
    offset: np.ndarray,
    jacobian: np.ndarray,
    curvature: np.ndarray | None,
    lower: np.ndarray,
    upper: np.ndarray,
) -> np.ndarray:
    """The coordinates that minimise ``|offset + J z + K z^2|^2`` within bounds.

    Without curvature the problem is linear: bounded-variable least squares (the global
    minimum). With per-parameter curvature ``K`` (``z^2`` taken element-wise) it is a bounded
    non-linear least-squares problem, solved by a trust-region reflective method
    (``scipy.optimize.least_squares``) from the linear problem's solution, from the nominal
    point and from the box centre; the lowest end is kept.

    Parameters
    ----------
    offset : ndarray (n,)
        Residual series at ``z = 0`` [W].
    jacobian, curvature : ndarray (n, d)
        Its derivative by ``z`` at ``z = 0`` and the coefficients of ``z**2`` [W]
        (``curvature`` None: none).
    lower, upper : ndarray (d,)
        Bounds of ``z`` [-].

    Returns
    -------
    ndarray (d,)
        The best ``z`` found [-].
    """
    from scipy.optimize import least_squares, lsq_linear

    lower = np.asarray(lower, dtype=float)
    upper = np.maximum(np.asarray(upper, dtype=float), lower + 1e-12)
    linear = lsq_linear(jacobian, -offset, bounds=(lower, upper), method="bvls").x
    if curvature is None or not np.any(curvature):
        return linear

    def residual(z):
        return offset + jacobian @ z + curvature @ (z**2)

    def derivative(z):
        return jacobian + 2.0 * curvature * z[None, :]

    best, cost = linear, float(residual(linear) @ residual(linear))
    for start in (linear, np.zeros_like(lower), 0.5 * (lower + upper)):
        x0 = np.clip(start, lower + 1e-12 * (upper - lower), upper - 1e-12 * (upper - lower))
        fit = least_squares(residual, x0, jac=derivative, bounds=(lower, upper), method="trf")
        if 2.0 * fit.cost < cost:
            best, cost = fit.x, 2.0 * fit.cost
    return best


def regression_scores(y_true: np.ndarray, y_pred: np.ndarray) -> dict[str, float]:
    """Coefficient of determination and root-mean-square error.

    Parameters
    ----------
    y_true, y_pred : ndarray
        Observed and predicted metric [unit of the metric].

    Returns
    -------
    dict
        ``r2`` [-] and ``rmse`` [unit of the metric].
    """
    y_true = np.asarray(y_true, dtype=float)
    y_pred = np.asarray(y_pred, dtype=float)
    ss_res = float(np.sum((y_true - y_pred) ** 2))
    ss_tot = float(np.sum((y_true - y_true.mean()) ** 2))
    return {
        "r2": 1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan"),
        "rmse": float(np.sqrt(ss_res / max(y_true.size, 1))),
    }


def _check_xy(X: Any, y: Any, what: str = "metamodel") -> tuple[np.ndarray, np.ndarray, list[str]]:
    if isinstance(X, pd.DataFrame):
        names = [str(c) for c in X.columns]
        Xa = X.to_numpy(dtype=float)
    else:
        Xa = np.asarray(X, dtype=float)
        if Xa.ndim == 1:
            Xa = Xa[:, None]
        names = [f"x{i}" for i in range(Xa.shape[1])]
    ya = np.asarray(y, dtype=float).ravel()
    if Xa.ndim != 2 or Xa.shape[0] != ya.size:
        raise ThermocalInputError(
            f"{what}: X has {Xa.shape[0]} rows but the metric has {ya.size} values"
        )
    if Xa.shape[0] < 5:
        raise ThermocalInputError(
            f"{what}: only {Xa.shape[0]} successful samples; a meta-model needs many more "
            "(the paper used 500)"
        )
    bad = ~np.isfinite(ya)
    if bad.any():
        raise ThermocalInputError(
            f"{what}: {int(bad.sum())} metric value(s) are NaN or infinite (failed samples?); "
            "drop them before fitting"
        )
    if not np.isfinite(Xa).all():
        raise ThermocalInputError(f"{what}: the parameter values contain NaN or infinite entries")
    return Xa, ya, names


class _Surrogate:
    """Shared fit/predict/cross-validation logic; subclasses define ``_estimator``."""

    log_target: bool
    cv_folds: int
    seed: int

    def _estimator(self, n_features: int) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def _target(self, y: np.ndarray) -> np.ndarray:
        if self.log_target:
            if np.any(y <= 0):
                raise ThermocalInputError(
                    "metamodel.log_target: the metric has zero or negative values; its "
                    "logarithm is undefined (set log_target: false)"
                )
            return np.log(y)
        return y

    def _fit_estimator(self, Xa: np.ndarray, t: np.ndarray) -> Any:  # default: plain fit
        est = self._estimator(Xa.shape[1])
        est.fit(Xa, t)
        return est

    def fit(self, X: Any, y: Any) -> _Surrogate:
        """Fit the meta-model and cross-validate it.

        Parameters
        ----------
        X : DataFrame or ndarray, shape (n, d)
            Parameter values of the successful samples [unit of each parameter].
        y : array-like, shape (n,)
            Metric of each sample [unit of the metric].

        Returns
        -------
        self
        """
        from sklearn.exceptions import ConvergenceWarning

        Xa, ya, names = _check_xy(X, y)
        self.feature_names_in_ = np.array(names, dtype=object)
        self.n_features_in_ = Xa.shape[1]
        t = self._target(ya)
        with warnings.catch_warnings():
            # a GP length scale at its bound is a parameter without effect on the metric, which
            # the ranking and the Sobol indices report; sklearn's one warning per dimension and
            # fold (printed with its source line) tells a user nothing more
            warnings.simplefilter("ignore", ConvergenceWarning)
            self.estimator_ = self._fit_estimator(Xa, t)
            if self.cv_folds and self.cv_folds >= 2:
                folds = KFold(
                    n_splits=min(int(self.cv_folds), Xa.shape[0]),
                    shuffle=True,
                    random_state=int(self.seed),
                )
                oof = cross_val_predict(clone(self.estimator_), Xa, t, cv=folds)
        if self.cv_folds and self.cv_folds >= 2:
            self.oof_prediction_ = np.exp(oof) if self.log_target else oof
            scores = regression_scores(ya, self.oof_prediction_)
            self.cv_r2_ = scores["r2"]
            self.cv_rmse_ = scores["rmse"]
        else:
            self.oof_prediction_ = None
            self.oof_bias_ = 0.0
            self.cv_r2_ = float("nan")
            self.cv_rmse_ = float("nan")
        return self

    def _as_array(self, X: Any) -> np.ndarray:
        if not hasattr(self, "estimator_"):
            raise ThermocalInputError("the meta-model is not fitted yet; call fit(X, y) first")
        if isinstance(X, pd.DataFrame):
            missing = [n for n in self.feature_names_in_ if n not in X.columns]
            if missing:
                raise ThermocalInputError(
                    f"predict: columns {missing[:5]} missing (the meta-model was fitted on "
                    f"{len(self.feature_names_in_)} parameters)"
                )
            return X[list(self.feature_names_in_)].to_numpy(dtype=float)
        Xa = np.asarray(X, dtype=float)
        if Xa.ndim == 1:
            Xa = Xa[None, :]
        if Xa.shape[1] != self.n_features_in_:
            raise ThermocalInputError(
                f"predict: X has {Xa.shape[1]} columns, the meta-model {self.n_features_in_}"
            )
        return Xa

    def summary(self) -> dict[str, Any]:
        """JSON-ready description: kind, hyper-parameters, cross-validated R2 and RMSE."""
        return {
            "kind": self.kind,
            "log_target": bool(self.log_target),
            "cv_folds": int(self.cv_folds),
            "cv_r2": float(self.cv_r2_),
            "cv_rmse": float(self.cv_rmse_),
            "hyperparameters": self.hyperparameters_(),
        }

    kind = "base"

    def hyperparameters_(self) -> dict[str, Any]:  # pragma: no cover - overridden
        return {}


class SVRSurrogate(_Surrogate):
    """Support vector regression meta-model (the paper's), hyper-parameters by grid search.

    Parameters
    ----------
    C : sequence of float, optional
        Candidate regularisation constants [-] (on the standardised target); default
        ``(1, 10, 100)``.
    epsilon : sequence of float, optional
        Candidate widths of the insensitive tube [-] (standardised target); default
        ``(0.02, 0.1)``.
    gamma : sequence of float, optional
        Candidate RBF inverse squared length scales [-] on standardised inputs; default
        ``(0.1, 0.3, 1, 3) / d`` for ``d`` parameters (24 candidates in all, each fitted
        ``cv_folds`` times; a smaller epsilon and a larger C fit closer but cost more).
    cv_folds : int
        Folds of the shuffled K-fold cross-validation [-] (hyper-parameter search and the
        reported R2/RMSE).
    log_target : bool
        Fit ``log(metric)`` instead of the metric.
    seed : int
        Seed of the fold shuffling [-].
    n_jobs : int, optional
        Parallel jobs of the grid search (default 1).

    Attributes
    ----------
    estimator_ : sklearn estimator
        The refitted best pipeline.
    best_params_ : dict
        Chosen ``C``, ``epsilon``, ``gamma``.
    cv_r2_, cv_rmse_ : float
        Cross-validated R2 [-] and RMSE [unit of the metric].
    oof_prediction_ : ndarray
        Out-of-fold predictions [unit of the metric].
    """

    kind = "svr"

    def __init__(
        self,
        *,
        C: Sequence[float] | None = None,
        epsilon: Sequence[float] | None = None,
        gamma: Sequence[float] | None = None,
        cv_folds: int = 5,
        log_target: bool = False,
        seed: int = 0,
        n_jobs: int | None = None,
    ) -> None:
        self.C = C
        self.epsilon = epsilon
        self.gamma = gamma
        self.cv_folds = cv_folds
        self.log_target = log_target
        self.seed = seed
        self.n_jobs = n_jobs

    def _estimator(self, n_features: int) -> Any:
        return TransformedTargetRegressor(
            regressor=Pipeline([("scale", StandardScaler()), ("svr", SVR(kernel="rbf"))]),
            transformer=StandardScaler(),
        )

    def _fit_estimator(self, Xa: np.ndarray, t: np.ndarray) -> Any:
        d = Xa.shape[1]
        grid = {
            "regressor__svr__C": list(self.C or (1.0, 10.0, 100.0)),
            "regressor__svr__epsilon": list(self.epsilon or (0.02, 0.1)),
            "regressor__svr__gamma": list(self.gamma or [g / d for g in (0.1, 0.3, 1.0, 3.0)]),
        }
        folds = KFold(
            n_splits=max(2, min(int(self.cv_folds or 5), Xa.shape[0])),
            shuffle=True,
            random_state=int(self.seed),
        )
        search = GridSearchCV(
            self._estimator(d), grid, cv=folds, scoring="r2", n_jobs=self.n_jobs, refit=True
        )
        search.fit(Xa, t)
        self.search_ = search
        self.best_params_ = {
            k.rsplit("__", 1)[-1]: float(v) for k, v in search.best_params_.items()
        }
        return search.best_estimator_

    def hyperparameters_(self) -> dict[str, Any]:
        return dict(self.best_params_)

    def predict(self, X: Any, return_std: bool = False) -> np.ndarray:
        """Predicted metric.

        Parameters
        ----------
        X : DataFrame or ndarray, shape (n, d)
            Parameter values [unit of each parameter].
        return_std : bool
            Not available for SVR (raises); use :class:`GPSurrogate`.

        Returns
        -------
        ndarray, shape (n,)
            Predicted metric [unit of the metric].
        """
        if return_std:
            raise ThermocalInputError(
                "the SVR meta-model has no predictive standard deviation; use the Gaussian "
                "process (metamodel.kind: gp)"
            )
        pred = self.estimator_.predict(self._as_array(X))
        return np.exp(pred) if self.log_target else pred


class GPSurrogate(_Surrogate):
    """Gaussian-process meta-model with an anisotropic Matern-5/2 + white-noise kernel.

    Parameters
    ----------
    cv_folds : int
        Folds of the cross-validation reported in ``cv_r2_``/``cv_rmse_`` [-]; 0 skips it
        (each fold refits all length scales, which costs time with many parameters).
    log_target : bool
        Fit ``log(metric)``.
    seed : int
        Seed of the optimiser restarts and fold shuffling [-].
    n_restarts : int
        Extra restarts of the kernel hyper-parameter optimiser [-].

    Attributes
    ----------
    estimator_ : Pipeline
        Scaler + fitted ``GaussianProcessRegressor``.
    kernel_ : kernel
        Fitted kernel (length scale per parameter in standardised units).
    """

    kind = "gp"

    def __init__(
        self, *, cv_folds: int = 5, log_target: bool = False, seed: int = 0, n_restarts: int = 1
    ) -> None:
        self.cv_folds = cv_folds
        self.log_target = log_target
        self.seed = seed
        self.n_restarts = n_restarts

    def _estimator(self, n_features: int) -> Any:
        kernel = ConstantKernel(1.0, (1e-3, 1e3)) * Matern(
            length_scale=np.ones(n_features), length_scale_bounds=(1e-2, 1e3), nu=2.5
        ) + WhiteKernel(1e-3, (1e-8, 1.0))
        gp = GaussianProcessRegressor(
            kernel=kernel,
            normalize_y=True,
            n_restarts_optimizer=int(self.n_restarts),
            random_state=int(self.seed),
        )
        return Pipeline([("scale", StandardScaler()), ("gp", gp)])

    def _fit_estimator(self, Xa: np.ndarray, t: np.ndarray) -> Any:
        est = super()._fit_estimator(Xa, t)
        self.kernel_ = est.named_steps["gp"].kernel_
        return est

    def hyperparameters_(self) -> dict[str, Any]:
        return {"kernel": str(self.kernel_)}

    def predict(self, X: Any, return_std: bool = False) -> Any:
        """Predicted metric and, optionally, its predictive standard deviation.

        Parameters
        ----------
        X : DataFrame or ndarray, shape (n, d)
            Parameter values [unit of each parameter].
        return_std : bool
            Also return the predictive standard deviation.

        Returns
        -------
        mean : ndarray, shape (n,)
            Predicted metric [unit of the metric].
        std : ndarray, shape (n,)
            Predictive standard deviation [unit of the metric] (only with ``return_std``).
        """
        Xa = self._as_array(X)
        if not return_std:
            mu = self.estimator_.predict(Xa)
            return np.exp(mu) if self.log_target else mu
        mu, sd = self.estimator_.predict(Xa, return_std=True)
        if self.log_target:
            mean = np.exp(mu)
            return mean, mean * sd
        return mu, sd


class SeriesSurrogate(_Surrogate):
    """Linear model of the unoccupied heat series; the metric is the variance of its prediction.

    The identified heat of each unoccupied hour, ``q(t)``, is close to affine in a coordinate
    ``z`` of each envelope parameter, so one ridge regression per hour,
    ``q(t) = q0(t) + J(t) z``, fitted jointly on all samples (every sample
    gives a whole series, not one number), predicts the whole series of a new parameter set;
    the metric follows as its variance plus the mean within-hour part of the campaign's
    metrics. This uses the structure of the metric (the variance of a nearly linear function:
    a quadratic valley) that a generic regression of the scalar metric has to discover, and
    predicts far better from few samples (cross-validated R2 0.59 against about -0.1 for the
    SVR and the GP with 64 samples of 70 parameters on the clinic demo). Beyond the paper.

    Coordinates (``coordinates``): the published form takes ``z = log(p / p_nominal)`` for
    every parameter (``"log"``). The heat through an element goes as its conductance
    ``1 / (R + films)``, and an air change's as the rate itself, both convex in ``log p``;
    over a +-75 % prior (``log p`` spans 1.9) a straight line in ``log p`` puts the zero of a
    resistance's signature several per cent off (-6.6 % for the roof of the EnergyPlus twin
    of 5ZoneAirCooled, +19 % for the same building with other windows). ``"physical"`` (the
    default) takes each parameter's coordinate in which its heat is affine: a construction's
    conductance, a window's U-value and SHGC, an air change rate, the logarithm of the rest
    (:mod:`thermocal.calibration.coordinates`); the twins' roofs then come within 3 % with
    the same number of coefficients.

    Curvature (``terms``): ``terms="quadratic"`` adds one ``z_k^2`` per parameter,
    ``q(t) = q0(t) + J(t) z + K(t) z^2`` (no cross terms; the same ridge penalty, which
    regularises when the samples are fewer than the ``2 d`` coefficients); ``"auto"`` keeps
    it only when its out-of-fold hourly error (hour-centred, what the posterior and the
    optimum use) is below the affine model's, so that a small campaign is not over-fitted;
    ``"affine"`` (the default) is the published form. The curvature removes the
    linearisation's bias of the optimum, and with it most of the meta-model's own error: the
    posterior's intervals then rest on the residual noise and the model discrepancy alone,
    and narrow (docs/calibration.md, "Curvature of the series meta-model").

    Parameters
    ----------
    series : ndarray (n_samples, n_hours) [W]
        Hourly means of the building-wide heat over the unoccupied steps of each sample, in
        the order of the rows given to :meth:`fit`.
    nominal : mapping of parameter -> value [unit of each parameter]
        Nominal values (the reference of the logarithms).
    alphas : sequence of float, optional
        Ridge penalties tried (efficient leave-one-out; default 1e-4 ... 1e3).
    cv_folds : int
    seed : int
    segments : sequence of (start, stop), optional
        Column ranges of several series side by side (e.g. one per zone group, see
        :mod:`thermocal.calibration.spatial`); the metric is then the sum of their variances.
        Default: one series.
    terms : {"auto", "affine", "quadratic"}
        Form of the hourly regressions in ``z`` (see above).
    coordinates : {"physical", "log"}
        What ``z`` is for each parameter (see above).

    Attributes
    ----------
    terms_ : {"affine", "quadratic"}
        The form used.
    kinds_ : tuple of str
        The coordinate of each fitted parameter (:func:`coordinate_kinds`).
    term_errors_ : dict of str to float
        Out-of-fold RMS hourly error of each form tried by ``"auto"`` [W] (empty otherwise).
    """

    kind = "series"
    log_target = False

    def __init__(
        self,
        *,
        series: Any,
        nominal: Any,
        alphas: Any = None,
        cv_folds: int = 5,
        seed: int = 0,
        segments: Any = None,
        terms: str = "affine",
        coordinates: str = "physical",
    ) -> None:
        coordinate_kinds((), coordinates)  # checks the name
        self.coordinates = coordinates
        if terms not in SERIES_TERMS:
            raise ThermocalInputError(
                f"series meta-model: terms {terms!r} unknown; use one of {', '.join(SERIES_TERMS)}"
            )
        self.terms = terms
        self.series = np.asarray(series, dtype=float)
        self.nominal = dict(nominal)
        self.alphas = alphas
        self.cv_folds = cv_folds
        self.seed = seed
        self.segments = (
            [(0, self.series.shape[-1])]
            if segments is None
            else [(int(a), int(b)) for a, b in segments]
        )

    def series_variance(self, series: np.ndarray) -> np.ndarray:
        """The sum over the segments of the variance of each row's series [W^2]."""
        series = np.atleast_2d(series)
        return sum(series[:, a:b].var(axis=1) for a, b in self.segments)

    def centred(self, values: np.ndarray) -> np.ndarray:
        """``values`` (rows: series over the last axis) minus each segment's mean."""
        out = np.array(values, dtype=float, copy=True)
        for a, b in self.segments:
            out[..., a:b] -= out[..., a:b].mean(axis=-1, keepdims=True)
        return out

    def _log_parameters(self, Xa: np.ndarray) -> np.ndarray:
        """The coordinates ``z`` of parameter rows ``Xa`` [-] (the logarithms relative to the
        nominal values in the published form; :mod:`thermocal.calibration.coordinates`)."""
        reference = np.array([self.nominal[n] for n in self.feature_names_in_], dtype=float)
        return to_coordinates(Xa, reference, self.kinds_)

    def _from_coordinates(self, Z: np.ndarray) -> np.ndarray:
        """Parameter rows of coordinates ``Z`` [unit of each parameter]."""
        reference = np.array([self.nominal[n] for n in self.feature_names_in_], dtype=float)
        return from_coordinates(Z, reference, self.kinds_)

    def design(self, Z: np.ndarray) -> np.ndarray:
        """The regressions' features of coordinates ``Z`` in the fitted form [-]."""
        return series_design(Z, getattr(self, "terms_", self.terms))

    def compare_terms(self) -> dict[str, float]:
        """Out-of-fold RMS hour-centred error of the affine and the quadratic form on the
        fitted samples [W] (what ``terms="auto"`` chooses by; stored in ``term_errors_``)."""
        if not self.term_errors_:
            self.term_errors_ = self._term_errors(self.log_parameters_)
        return dict(self.term_errors_)

    def _term_errors(self, Z: np.ndarray) -> dict[str, float]:
        """Out-of-fold RMS hour-centred error of the affine and the quadratic form [W]."""
        folds = KFold(
            n_splits=min(max(int(self.cv_folds or 5), 2), Z.shape[0]),
            shuffle=True,
            random_state=int(self.seed),
        )
        out = {}
        for terms in ("affine", "quadratic"):
            F = series_design(Z, terms)
            squared = []
            for train, test in folds.split(F):
                error = self._ridge().fit(F[train], self.series[train]).predict(F[test])
                squared.append(self.centred(error - self.series[test]) ** 2)
            out[terms] = float(np.sqrt(np.mean(np.concatenate(squared))))
        return out

    def _ridge(self) -> Any:
        from sklearn.linear_model import RidgeCV

        alphas = self.alphas if self.alphas is not None else np.logspace(-4, 3, 30)
        return RidgeCV(alphas=alphas)

    def fit(self, X: Any, y: Any) -> SeriesSurrogate:
        """Fit the hourly regressions on the samples' parameters ``X`` and metric ``y``."""
        Xa, ya, names = _check_xy(X, y)
        if self.series.shape[0] != Xa.shape[0]:
            raise ThermocalInputError(
                f"series meta-model: {self.series.shape[0]} series for {Xa.shape[0]} samples"
            )
        missing = [n for n in names if n not in self.nominal]
        if missing:
            raise ThermocalInputError(f"series meta-model: no nominal value for {missing[:3]}")
        self.feature_names_in_ = np.array(names, dtype=object)
        self.n_features_in_ = Xa.shape[1]
        self.kinds_ = coordinate_kinds([str(n) for n in names], self.coordinates)
        Z = self._log_parameters(Xa)
        within = ya - self.series_variance(self.series)
        self.term_errors_ = {}
        if self.terms == "auto":
            self.term_errors_ = self._term_errors(Z)
            better = self.term_errors_["quadratic"] < self.term_errors_["affine"]
            self.terms_ = "quadratic" if better else "affine"
        else:
            self.terms_ = self.terms
        F = self.design(Z)
        self.estimator_ = self._ridge().fit(F, self.series)
        self.variance_form_ = self._variance_form()
        self.log_parameters_ = Z
        self.design_ = F  # the design, for the significance of each fitted effect
        self.within_hour_ = float(within.mean())
        if self.cv_folds and self.cv_folds >= 2:
            folds = KFold(
                n_splits=min(int(self.cv_folds), Xa.shape[0]),
                shuffle=True,
                random_state=int(self.seed),
            )
            oof = np.empty_like(ya)
            for train, test in folds.split(F):
                model = self._ridge().fit(F[train], self.series[train])
                oof[test] = self.series_variance(model.predict(F[test])) + within[train].mean()
            self.oof_prediction_ = oof
            # a simulated metric holds the meta-model's own error (its energy summed over the
            # series), which a prediction lacks: on samples it did not see, by this much (over
            # all samples; over the lowest quarter of the metrics it was about zero on the
            # multifamily twin and left its group calibration unflagged)
            self.oof_bias_ = max(float(np.mean(ya - oof)), 0.0)
            scores = regression_scores(ya, oof)
            self.cv_r2_, self.cv_rmse_ = scores["r2"], scores["rmse"]
        else:
            self.oof_prediction_ = None
            self.oof_bias_ = 0.0
            self.cv_r2_ = self.cv_rmse_ = float("nan")
        return self

    def predict(self, X: Any, return_std: bool = False) -> np.ndarray:
        """Predicted metric [unit of the metric] (no predictive std: ``return_std`` raises)."""
        if return_std:
            raise ThermocalInputError("the series meta-model gives no predictive std")
        F = self.design(self._log_parameters(self._as_array(X)))
        gram, linear, constant = self.variance_form_
        variance = constant + 2.0 * (F @ linear) + np.einsum("ij,ij->i", F @ gram, F)
        return np.maximum(variance, 0.0) + self.within_hour_

    def _variance_form(self) -> tuple[np.ndarray, np.ndarray, float]:
        """The predicted sum of the series' variances as a quadratic form of the features.

        Each series' variance is ``|c0 + C f|^2 / n_g`` with ``c0``, ``C`` the hour-centred
        intercept and coefficients of its ``n_g`` hours and ``f`` the features; summed over the
        series it is ``k + 2 b.f + f^T G f``, evaluated in O(p^2) per row instead of O(p n)
        (the Sobol indices and the optimisers evaluate it tens of thousands of times).

        Returns
        -------
        gram : ndarray (p, p) [W^2]
        linear : ndarray (p,) [W^2]
        constant : float [W^2]
        """
        offset, jacobian, curvature = self.hour_centred()
        coef = jacobian if curvature is None else np.hstack([jacobian, curvature])
        weights = np.empty(offset.size)
        for a, b in self.segments:
            weights[a:b] = 1.0 / (b - a)
        weighted = coef * weights[:, None]
        return weighted.T @ coef, weighted.T @ offset, float(offset @ (offset * weights))

    def hour_centred(self) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """The fitted regressions, centred over each series' hours.

        Returns
        -------
        offset : ndarray (n_hours,)
            Centred series at the nominal parameters [W].
        jacobian : ndarray (n_hours, d)
            Centred coefficients of ``z`` [W].
        curvature : ndarray (n_hours, d) or None
            Centred coefficients of ``z**2`` [W] (None: the affine form).
        """
        coef = np.atleast_2d(np.asarray(self.estimator_.coef_, dtype=float))
        intercept = np.asarray(self.estimator_.intercept_, dtype=float).ravel()
        d = self.n_features_in_
        jacobian = self.centred(coef[:, :d].T).T
        curvature = self.centred(coef[:, d:].T).T if coef.shape[1] > d else None
        return self.centred(intercept), jacobian, curvature

    #: largest number of parameters whose box maximum is found by visiting every vertex
    MAX_VERTEX_PARAMETERS = 12

    def box_optimum(self, sense: str, lower: Any, upper: Any) -> tuple[np.ndarray, float] | None:
        """The exact minimum or maximum of the predicted metric over a box of parameters.

        In the affine form the prediction is a convex quadratic in the coordinates ``z``
        (the variance of an affine series): its minimum over the box is a bounded linear
        least-squares problem (``scipy.optimize.lsq_linear``, bounded-variable least squares:
        the global minimum), and its maximum lies at a vertex of the box (all are visited up
        to :data:`MAX_VERTEX_PARAMETERS` parameters; beyond, None). With the quadratic terms
        the minimum is a bounded non-linear least-squares problem
        (:func:`bounded_series_fit`) and the maximum a bounded local search (L-BFGS-B) from
        the best vertex.

        Parameters
        ----------
        sense : {"min", "max"}
        lower, upper : array-like
            Bounds of the fitted parameters, in their order [unit of each parameter].

        Returns
        -------
        (ndarray, float) or None
            The optimal parameters [unit of each] and the predicted metric there.
        """
        zl = self._log_parameters(np.asarray(lower, dtype=float))
        zu = self._log_parameters(np.asarray(upper, dtype=float))
        if sense == "min":
            offset, jacobian, curvature = self.hour_centred()
            weights = np.empty(offset.size)
            for a, b in self.segments:
                weights[a:b] = 1.0 / np.sqrt(b - a)
            z = bounded_series_fit(
                offset * weights,
                jacobian * weights[:, None],
                None if curvature is None else curvature * weights[:, None],
                zl,
                zu,
            )
            # within the box despite the coordinates' round trip (a U-value of 10.000000000000002)
            x = np.clip(self._from_coordinates(z), lower, upper)
        else:
            d = zl.size
            if d > self.MAX_VERTEX_PARAMETERS:
                return None
            corners = (np.arange(2**d)[:, None] >> np.arange(d)[None, :]) & 1
            Z = np.where(corners == 1, zu, zl)
            values = self.predict(self._from_coordinates(Z))
            z = Z[int(np.argmax(values))]
            if self.terms_ != "affine":  # no longer convex: a bounded local search from there
                from scipy.optimize import minimize

                found = minimize(
                    lambda v: -float(self.predict(self._from_coordinates(v)[None, :])[0]),
                    z,
                    method="L-BFGS-B",
                    bounds=list(zip(zl, np.maximum(zu, zl), strict=True)),
                )
                if -found.fun > float(values.max()):
                    z = found.x
            x = np.clip(self._from_coordinates(z), lower, upper)
        value = float(self.predict(x[None, :])[0])
        return x, value

    def hyperparameters_(self) -> dict[str, Any]:
        out = {
            "alpha": float(self.estimator_.alpha_),
            "within_hour_W2": self.within_hour_,
            "hours": int(self.series.shape[1]),
            "terms": self.terms_,
            "coordinates": getattr(self, "coordinates", "log"),
        }
        if self.term_errors_:
            out["oof_hourly_rms_W"] = dict(self.term_errors_)
        return out


def make_surrogate(kind: Literal["svr", "gp"] = "svr", **options: Any) -> _Surrogate:
    """An unfitted meta-model by name.

    Parameters
    ----------
    kind : {"svr", "gp"}
        Support vector regression or Gaussian process.
    **options
        Keyword arguments of :class:`SVRSurrogate` or :class:`GPSurrogate`.
    """
    if kind == "svr":
        return SVRSurrogate(**options)
    if kind == "gp":
        return GPSurrogate(**options)
    raise ThermocalInputError(f"metamodel.kind {kind!r} is unknown; use 'svr' or 'gp'")
