"""Posterior of the calibrated parameters and what the data determine (beyond the paper).

The calibration's metric is the variance of the building's identified heat over the unoccupied
hours: with the right envelope that heat is the constant internal gain plus noise. The series
meta-model (:class:`~thermocal.calibration.surrogate.SeriesSurrogate`) predicts the whole hourly
series as affine in a coordinate of each parameter, ``q(t) = q0(t) + J(t) z``, with ``z`` the
change of a construction's conductance ``1 / (R + films)``, the relative change of a window's
U-value or SHGC or an air change rate, and ``log(p / p_nominal)`` for the rest
(:mod:`~thermocal.calibration.coordinates`; ``log(p / p_nominal)`` for all in the published
form), or with a per-parameter curvature ``+ K(t) z^2``. Removing the
hourly mean (the constant gain, unknown), the residual series
``r(z) = (q0 - mean q0) + (J - mean J) z [+ (K - mean K) z^2]`` is the envelope's error
signal; modelled as
Gaussian noise of variance ``sigma^2`` it gives the likelihood

``log L(z) = -(n_eff / n) * |r(z)|^2 / (2 sigma^2)``,

with ``sigma^2`` the residual variance at the best bounded fit (the noise level of the residual
identified heat, model error included: the honest floor) plus the meta-model's own out-of-fold
error (:func:`emulator_variance`), and ``n_eff = sum_g n_g / tau_g`` the number of
independent hours given each series' correlation time ``tau_g`` (the longer of its integrated
and its lag-1 autocorrelation times, :func:`effective_hours`). The prior is
the campaign's: uniform in each parameter between its bounds (in a construction's conductance
coordinate the density ``(1 - z)^-2``, in that coordinate's Gibbs conditional), or, for
an element measured in situ (a heat-flux meter, ISO 9869-1), log-normal around the measurement
within the same bounds (:func:`measured_prior`). With the affine model the
posterior is a Gaussian in ``z`` truncated to the prior box, sampled exactly by Gibbs sweeps
(:func:`~thermocal.calibration.mcmc.truncated_gaussian_gibbs`); with curvature by emcee's
affine-invariant ensemble sampler (Foreman-Mackey et al. 2013); either until the draws are
worth a set number of independent ones, the Monte Carlo error of each interval end reported.

Identifiability: the Fisher information ``F = (n_eff / n) J_c^T J_c / sigma^2`` of all campaign
parameters (``J_c`` the hour-centred Jacobian, at the best fit when there is curvature) says
which directions the data fix; a parameter is *determined* when its 90 % credible interval is
narrower than half its prior range and its fitted effect stands out of the meta-model's
estimation noise (:func:`effect_to_noise`: a parameter with no effect at all gets a fitted
Jacobian of pure noise, whose norm over hundreds of hours would otherwise look like
information) and it does not compensate an uncertain input (posterior correlation beyond 0.7 in
magnitude in their joint Gaussian: then the input's prior, not the data, sets it), and two
parameters *compensate* each other when their posterior correlation exceeds 0.7 in magnitude
(the data fix a combination of them, not each one).

References
----------
.. [1] Foreman-Mackey D., Hogg D.W., Lang D., Goodman J. (2013), emcee: the MCMC hammer,
   Publications of the Astronomical Society of the Pacific 125, 306-312.
.. [2] Kennedy M.C., O'Hagan A. (2001), Bayesian calibration of computer models, Journal of
   the Royal Statistical Society B 63, 425-464.
.. [3] Hoerl A.E., Kennard R.W. (1970), Ridge regression: biased estimation for nonorthogonal
   problems, Technometrics 12, 55-67.
.. [4] Brynjarsdottir J., O'Hagan A. (2014), Learning about physical parameters: the importance
   of model discrepancy, Inverse Problems 30, 114007 (the opt-in ``discrepancy`` term,
   :func:`discrepancy_basis`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd

from thermocal.calibration.coordinates import from_coordinates, to_coordinates
from thermocal.calibration.mcmc import (
    GIBBS_SWEEPS,
    POSTERIOR_EFFECTIVE_DRAWS,
    POSTERIOR_WALKERS,
    ensemble_until_precise,
    quantile_standard_error,
    truncated_gaussian_gibbs,
)
from thermocal.errors import ThermocalInputError

__all__ = [
    "Posterior",
    "calibration_posterior",
    "discrepancy_basis",
    "emulator_variance",
    "linear_heat_model",
]

#: A parameter is determined when its 90 % credible interval is narrower than this fraction of
#: its prior range [-].
DETERMINED_FRACTION = 0.5
#: Posterior correlation above which two parameters are said to compensate each other [-].
COMPENSATION_CORRELATION = 0.7
#: A parameter is determined only when its fitted effect on the hour-centred series is this many
#: times (in squared norm) what the meta-model's own estimation noise gives an inert parameter
#: [-]; under no effect the ratio is about 1.
EFFECT_TO_NOISE = 4.0


@dataclass(frozen=True)
class LinearHeatModel:
    """Hour-centred affine (or per-parameter quadratic) model of the unoccupied heat in the
    parameters' coordinates (:mod:`thermocal.calibration.coordinates`).

    Attributes
    ----------
    names : tuple of str
        Parameters (columns of ``jacobian``).
    offset : ndarray (n_hours,)
        Hour-centred series at the nominal parameters [W].
    jacobian : ndarray (n_hours, n_parameters)
        Hour-centred derivative of the series by the coordinates ``z`` [W].
    nominal, lower, upper : ndarray (n_parameters,)
        Nominal values and prior bounds [unit of each parameter].
    curvature : ndarray (n_hours, n_parameters) or None
        Hour-centred coefficients of ``z**2`` [W] (None: affine).
    kinds : tuple of str
        The coordinate ``z`` of each parameter (:mod:`thermocal.calibration.coordinates`;
        empty: ``log(p / p_nominal)`` for every one, the published form).
    """

    names: tuple[str, ...]
    offset: np.ndarray
    jacobian: np.ndarray
    nominal: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    series_count: int = 1
    segments: tuple = ()
    curvature: np.ndarray | None = None
    kinds: tuple = ()

    def residual(self, z: np.ndarray) -> np.ndarray:
        """Residual series for coordinates ``z`` (shape (d,) or (m, d)) [W]."""
        z = np.asarray(z)
        out = self.offset + z @ self.jacobian.T
        if self.curvature is not None:
            out = out + (z**2) @ self.curvature.T
        return out

    def jacobian_at(self, z: np.ndarray) -> np.ndarray:
        """Derivative of the residual series by ``z`` at one point ``z`` (shape (d,)) [W]."""
        if self.curvature is None:
            return self.jacobian
        return self.jacobian + 2.0 * self.curvature * np.asarray(z, dtype=float)[None, :]

    def features(self, z: np.ndarray) -> np.ndarray:
        """The model's features of ``z`` (shape (m, d)): ``z``, or ``[z, z**2]`` [-]."""
        z = np.atleast_2d(np.asarray(z, dtype=float))
        return z if self.curvature is None else np.hstack([z, z**2])

    @property
    def coefficients(self) -> np.ndarray:
        """The residual's coefficients of :meth:`features`, (n_hours, d or 2 d) [W]."""
        if self.curvature is None:
            return self.jacobian
        return np.hstack([self.jacobian, self.curvature])

    def local(self, z: np.ndarray) -> LinearHeatModel:
        """The affine model tangent at ``z`` (its Jacobian there; the offset is kept)."""
        return replace(self, jacobian=self.jacobian_at(z), curvature=None)

    @property
    def coordinate_kinds(self) -> tuple[str, ...]:
        """The coordinate of each parameter (``"log"`` for all in the published form)."""
        return tuple(self.kinds) or tuple("log" for _ in self.names)

    @property
    def z_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Bounds of the coordinates ``z`` (``log(p / p_nominal)`` in the published form) [-]."""
        kinds = self.coordinate_kinds
        return (
            to_coordinates(self.lower, self.nominal, kinds),
            to_coordinates(self.upper, self.nominal, kinds),
        )

    def values(self, z: np.ndarray) -> np.ndarray:
        """Parameter values of coordinates ``z`` (shape (d,) or (m, d)) [unit of each]."""
        return from_coordinates(z, self.nominal, self.coordinate_kinds)

    def prior_tilt(self, measured_precision: np.ndarray) -> np.ndarray:
        """Coefficients of ``z`` in the log-density of the prior uniform in ``p`` [-].

        ``p = p_nominal exp(z)`` gives the density ``exp(z)`` in ``z``; a linear coordinate
        none; a resistance's conductance coordinate a non-linear one
        (:meth:`prior_log_density_rest`). A measured parameter's log-normal replaces it.
        """
        log = np.array([k == "log" for k in self.coordinate_kinds], dtype=bool)
        return (log & (np.asarray(measured_precision) == 0)).astype(float)

    def prior_log_density_rest(self, z: np.ndarray, measured_precision: np.ndarray) -> np.ndarray:
        """The part of the uniform prior's log-density in ``z`` that is not linear: for a
        resistance's conductance coordinate ``R + f = (R_0 + f) / (1 - z)``, so the density
        of ``R`` uniform is ``(1 - z)^-2`` in ``z``: ``-2 log(1 - z)`` summed over those
        parameters (not measured ones) [-].

        Parameters
        ----------
        z : ndarray (m, d) [-]
        measured_precision : ndarray (d,) [-]

        Returns
        -------
        ndarray (m,) [-]
        """
        z = np.atleast_2d(np.asarray(z, dtype=float))
        use = self.conductance_prior(measured_precision)
        if not use.any():
            return np.zeros(len(z))
        return -2.0 * np.log1p(-z[:, use]).sum(axis=1)

    def conductance_prior(self, measured_precision: np.ndarray) -> np.ndarray:
        """Which coordinates carry the prior term ``-2 log(1 - z)`` of
        :meth:`prior_log_density_rest`: the resistances in their conductance coordinate that
        no in-situ measurement gives a prior of its own (bool (d,))."""
        kinds = np.array([k == "conductance" for k in self.coordinate_kinds], dtype=bool)
        return kinds & (np.asarray(measured_precision) == 0)


def linear_heat_model(surrogate, names: Sequence[str], lower, upper) -> LinearHeatModel:
    """The hour-centred linear model of a fitted series meta-model, for some parameters.

    Parameters
    ----------
    surrogate : SeriesSurrogate
        Fitted on the campaign's samples.
    names : sequence of str
        Parameters to keep (the others stay at their nominal values, ``z = 0``).
    lower, upper : array-like
        Prior bounds of ``names`` [unit of each parameter].

    Returns
    -------
    LinearHeatModel
    """
    features = [str(n) for n in surrogate.feature_names_in_]
    missing = [n for n in names if n not in features]
    if missing:
        raise ThermocalInputError(f"posterior: parameters {missing[:3]} not in the meta-model")
    idx = [features.index(n) for n in names]
    if hasattr(surrogate, "hour_centred"):
        offset, jacobian, curvature = surrogate.hour_centred()
    else:
        coef = np.atleast_2d(np.asarray(surrogate.estimator_.coef_, dtype=float))
        intercept = np.asarray(surrogate.estimator_.intercept_, dtype=float).ravel()
        offset = intercept - intercept.mean()
        jacobian, curvature = coef - coef.mean(axis=0, keepdims=True), None
    return LinearHeatModel(
        names=tuple(str(n) for n in names),
        offset=offset,
        jacobian=jacobian[:, idx],
        curvature=None if curvature is None else curvature[:, idx],
        nominal=np.array([surrogate.nominal[n] for n in names], dtype=float),
        lower=np.asarray(lower, dtype=float),
        upper=np.asarray(upper, dtype=float),
        series_count=len(getattr(surrogate, "segments", [None])),
        segments=tuple(
            (int(a), int(b)) for a, b in getattr(surrogate, "segments", [(0, len(offset))])
        ),
        kinds=tuple(surrogate.kinds_[i] for i in idx) if hasattr(surrogate, "kinds_") else (),
    )


#: Hour shifts of a parameter's signature whose residual energy estimates, with
#: ``discrepancy="neighbours"``, the discrepancy along the signature itself [h].
NEIGHBOUR_SHIFTS = (-12, -6, -3, -2, -1, 1, 2, 3, 6, 12)


def _neighbour_variance(signature, others, residual) -> float:
    """Mean squared residual along the shifted copies of a signature, per hour [W^2].

    Each copy is made orthogonal to the fitted signatures and to a constant (the directions
    the fit already used, where the residual is zero), so the residual's energy along it is
    observed; under white noise it is the noise variance per direction, under a smooth model
    error it is larger."""
    n = len(signature)
    basis, _ = np.linalg.qr(np.column_stack([np.ones(n), others]))
    energies = []
    for shift in NEIGHBOUR_SHIFTS:
        if abs(shift) >= n // 4:
            continue
        v = np.roll(signature, shift)
        v = v - basis @ (basis.T @ v)
        norm2 = float(v @ v)
        if norm2 > 1e-12 * float(signature @ signature):
            energies.append(float(residual @ v) ** 2 / norm2)
    return float(np.mean(energies)) / n if energies else 0.0


def discrepancy_basis(
    model: LinearHeatModel, residual: np.ndarray, scale: str = "neighbours"
) -> tuple[np.ndarray, np.ndarray]:
    """Parameter-like model discrepancy: its directions and prior variances.

    The true envelope's own unoccupied heat is not constant (the model's error), and the part
    of it that looks like a parameter change never shows in the residual the noise level is
    taken from (Brynjarsdottir and O'Hagan 2014). This discrepancy is modelled explicitly: in
    each series ``g`` (zone group, or the building) and for each parameter ``k``, a component
    ``b_gk u_gk(t)`` along the parameter's own hour-centred signature in that series
    (``u_gk = J_gk / rms(J_gk)``, unit RMS per hour), with ``b_gk ~ N(0, tau_gk^2)``
    independent across groups and parameters. Its prior scale ``tau_gk^2`` [W^2]:

    * ``"floor"``: the series' residual variance per hour at the best bounded fit (the
      model-error floor that series shows across the parameters' directions, assumed as
      large along one of them: the upper bound, the whole model error mimicking a parameter);
    * ``"shared"``: that floor shared among the ``d`` parameters' signatures,
      ``tau_gk^2 = floor_g / d`` (the model error's energy per hour bounds the part of it
      that mimics the parameters, all of them together);
    * ``"neighbours"``: the residual's energy along the signature shifted by 1 to 12 hours
      (made orthogonal to what the fit used), per hour: a model error that mimics a
      parameter's signature is assumed as large as along its slightly shifted copies, which
      the data do show (a smoothness assumption on the discrepancy; under white noise this
      is the noise's own level and the intervals widen by about sqrt(2)).

    Parameters
    ----------
    model : LinearHeatModel
    residual : ndarray (n_hours,)
        Residual series at the best bounded fit [W].
    scale : {"neighbours", "floor", "shared"}
        How the prior scale is set.

    Returns
    -------
    basis : ndarray (n_hours, m)
        Unit-RMS signatures, zero outside their series [-].
    variance : ndarray (m,)
        Prior variance of each component's amplitude [W^2].
    """
    if scale not in ("neighbours", "floor", "shared"):
        raise ThermocalInputError(
            "posterior: discrepancy must be 'none', 'neighbours', 'floor' or 'shared', got "
            f"{scale!r}"
        )
    n, d = model.jacobian.shape
    columns, variances = [], []
    for a, b in model.segments or ((0, n),):
        r = residual[a:b]
        floor = float(np.mean(r**2))
        for k in range(d):
            signature = model.jacobian[a:b, k]
            rms = float(np.sqrt(np.mean(signature**2)))
            if rms <= 0:
                continue
            if scale == "neighbours":
                tau2 = _neighbour_variance(signature, model.jacobian[a:b], r)
            else:
                tau2 = floor / (d if scale == "shared" else 1)
            if tau2 <= 0:
                continue
            column = np.zeros(n)
            column[a:b] = signature / rms
            columns.append(column)
            variances.append(tau2)
    if not columns:
        return np.zeros((n, 0)), np.zeros(0)
    return np.column_stack(columns), np.array(variances)


@dataclass(frozen=True)
class Posterior:
    """Posterior of the calibrated parameters and the identifiability verdicts.

    Attributes
    ----------
    summary : DataFrame
        Index: parameter; columns ``unit``, ``nominal``, ``map`` (best bounded fit), ``median``,
        ``q05``, ``q95`` [unit of each parameter], ``prior_lower``, ``prior_upper``,
        ``width_fraction`` (90 % interval over prior range) [-] and ``determined`` (bool).
    correlation : DataFrame
        Posterior correlation of the parameters [-].
    compensating : list of (str, str, float)
        Pairs whose posterior correlation exceeds 0.7 in magnitude, with the correlation.
    noise_std : float
        Standard deviation of the hourly unoccupied heat's error: the residual at the best fit
        and the meta-model's own error together [W].
    emulator_std : float
        The meta-model's part of it [W].
    effective_hours : float
        Independent hours given the residual's autocorrelation [-].
    fisher_singular_values : ndarray
        Singular values of the square root of the Fisher information of all campaign
        parameters in their coordinates ``z`` [-], largest first (in the physical coordinates
        not comparable with results in ``log p`` before 2026-11-30).
    acceptance : float
        Mean acceptance fraction of the sampler [-].
    samples : DataFrame
        Posterior draws [unit of each parameter].
    effective_draws : float
        What the draws are worth as independent ones (their number over the integrated
        autocorrelation time) [-].
    autocorrelation_steps : float
        The sampler's largest integrated autocorrelation time [steps].
    in_situ : dict
        The in-situ measurements in the prior: parameter -> the measurement
        (:meth:`thermocal.physics.heat_flux.InSituUValue.as_dict` and its ``source``).
    advice : dict
        Which in-situ measurement would determine which parameters
        (:func:`thermocal.calibration.advice.advise_measurements`; empty when not asked).
    envelope_total : dict
        The varied elements' and air changes' total conductances with their intervals, per part
        (:func:`thermocal.calibration.envelope_total.total_conductance`; empty when fewer than
        two parameters have one).
    uncertain : list of dict
        The uncertain inputs the posterior marginalised (:mod:`thermocal.calibration.uncertain`):
        ``label``, ``rel_std`` [-], ``parameters`` (the names it scales), ``effect`` (False: it
        does not change the series and was left out) and ``compensates`` (parameter ->
        posterior correlation [-] beyond 0.7 in magnitude); empty when none.
    """

    summary: pd.DataFrame
    correlation: pd.DataFrame
    compensating: list = field(default_factory=list)
    noise_std: float = float("nan")
    emulator_std: float = 0.0
    effective_hours: float = float("nan")
    fisher_singular_values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    acceptance: float = float("nan")
    samples: pd.DataFrame = field(default_factory=pd.DataFrame)
    effective_draws: float = float("nan")
    autocorrelation_steps: float = float("nan")
    in_situ: dict = field(default_factory=dict)
    advice: dict = field(default_factory=dict)
    uncertain: list = field(default_factory=list)
    envelope_total: dict = field(default_factory=dict)

    @property
    def determined(self) -> list[str]:
        """Parameters the data determine."""
        return [n for n, d in self.summary["determined"].items() if d]

    def sentences(self) -> list[str]:
        """The verdicts in plain words, for the report and the terminal."""
        s = self.summary
        out = []
        det = self.determined
        measured = [n for n in s.index if "measured" in s and bool(s.at[n, "measured"])]
        if det:
            out.append(
                "Determined by the data (90 % credible interval"
                + ("; * with an in-situ measurement" if measured else "")
                + "): "
                + "; ".join(
                    f"{n}{'*' if n in measured else ''} {s.at[n, 'median']:.4g} "
                    f"({s.at[n, 'q05']:.4g} to {s.at[n, 'q95']:.4g}"
                    f" {s.at[n, 'unit']}, nominal {s.at[n, 'nominal']:.4g})"
                    for n in det
                )
                + "."
            )
        compensating = {n for u in self.uncertain for n in u.get("compensates", {})}
        loose = [n for n in s.index if n not in det and n not in compensating]
        if loose:
            out.append(
                "Not determined (the interval spans more than half the prior range): "
                + ", ".join(loose)
                + "."
            )
        effective = [u for u in self.uncertain if u.get("effect", True)]
        if effective:
            out.append(
                "The intervals include the uncertainty of inputs the campaign did not vary: "
                + "; ".join(
                    f"{u['label']} (+-{100 * u['rel_std']:.0f} %, {len(u['parameters'])} "
                    f"parameter{'s' if len(u['parameters']) != 1 else ''})"
                    for u in effective
                )
                + "."
            )
        for item in self.uncertain:
            if not item.get("effect", True):
                out.append(
                    f"{item['label']} does not change the unoccupied heat: not integrated out."
                )
            for name, r in item.get("compensates", {}).items():
                out.append(
                    f"{name} and the uncertain input {item['label']} compensate each other "
                    f"(posterior correlation {r:+.2f}): the data fix a combination of the two, "
                    f"so {name} is set by what {item['label']}'s prior assumes, not by the "
                    f"data, and is not called determined; a measurement of {item['label']}"
                    + (" (a pressurisation test, ISO 9972)" if "infiltration" in item["label"]
                       else "")
                    + " would separate them."
                )  # fmt: skip
        for a, b, r in self.compensating:
            out.append(
                f"{a} and {b} compensate each other (posterior correlation {r:+.2f}): the data "
                "fix a combination of the two, not each one."
            )
        from thermocal.calibration.envelope_total import total_conductance_sentences

        out.extend(total_conductance_sentences(self.envelope_total))
        if self.advice:
            out.append(self.advice["summary"] + ".")
        out.append(
            f"Error level of the unoccupied heat {self.noise_std / 1000:.2f} kW per hour (of "
            f"which the meta-model's own {self.emulator_std / 1000:.2f} kW) over "
            f"{self.effective_hours:.0f} effectively independent hours."
        )
        if "q05_mcse" in s and np.isfinite(self.effective_draws):
            relative = np.nanmax(
                np.concatenate([s["q05_mcse"] / s["q05"].abs(), s["q95_mcse"] / s["q95"].abs()])
            )
            out.append(
                f"The interval ends come from {self.effective_draws:.0f} effectively independent "
                f"posterior draws: known to {100 * relative:.1f} % or better (Monte Carlo "
                "standard error)."
            )
        return out

    def to_dict(self) -> dict:
        """JSON-ready form (summary, compensating pairs, noise, sampler diagnostics)."""
        return {
            "parameters": {
                n: {
                    k: (bool(v) if k in ("determined", "measured") else v if k == "unit"
                        else float(v))
                    for k, v in row.items()
                }
                for n, row in self.summary.iterrows()
            },
            "compensating": [[a, b, float(r)] for a, b, r in self.compensating],
            "noise_std_W": float(self.noise_std),
            "emulator_std_W": float(self.emulator_std),
            "effective_hours": float(self.effective_hours),
            "fisher_singular_values": [float(v) for v in self.fisher_singular_values],
            "acceptance_fraction": float(self.acceptance),
            "effective_draws": float(self.effective_draws),
            "autocorrelation_steps": float(self.autocorrelation_steps),
            "in_situ": self.in_situ,
            "advice": self.advice,
            "uncertain": self.uncertain,
            "envelope_total": self.envelope_total,
            "sentences": self.sentences(),
        }


def emulator_variance(surrogate, X, *, folds: int = 5, seed: int = 0) -> float:
    """Out-of-fold error variance of a series meta-model's hourly predictions [W^2].

    The meta-model is an approximation of the detailed model: its own error on samples it
    did not see (each predicted series minus the simulated one, both centred over the hours,
    since a constant offset is the unknown internal gain) is added to the residual noise, so
    that the posterior does not claim more than the meta-model knows (Kennedy and O'Hagan
    2001).

    Parameters
    ----------
    surrogate : SeriesSurrogate
        Fitted; its ``series`` and chosen ridge penalty are used.
    X : DataFrame
        The samples' parameters it was fitted on [unit of each parameter].
    folds : int
        Cross-validation folds [-].
    seed : int
        Seed of the fold split [-].

    Returns
    -------
    float
        Mean squared hour-centred out-of-fold error [W^2].
    """
    from sklearn.linear_model import Ridge
    from sklearn.model_selection import KFold

    Z = surrogate._log_parameters(np.asarray(X[list(surrogate.feature_names_in_)], dtype=float))
    if hasattr(surrogate, "design"):
        Z = surrogate.design(Z)
    S = np.asarray(surrogate.series, dtype=float)
    k = min(int(folds), Z.shape[0])
    if k < 2:
        return 0.0
    errors = []
    for train, test in KFold(k, shuffle=True, random_state=int(seed)).split(Z):
        fit = Ridge(alpha=float(surrogate.estimator_.alpha_)).fit(Z[train], S[train])
        e = fit.predict(Z[test]) - S[test]
        errors.append(
            surrogate.centred(e)
            if hasattr(surrogate, "centred")
            else e - e.mean(axis=1, keepdims=True)
        )
    return float(np.mean(np.concatenate(errors) ** 2))


def effect_to_noise(surrogate, names: Sequence[str], emulator_error: float) -> np.ndarray:
    """Squared norm of each parameter's fitted hour-centred effect over its estimation noise.

    The ridge regression of the series on the coordinates ``Z`` estimates each hour's
    effect with the variance ``s2 [A G A]_pp``, ``G = Zc^T Zc``, ``A = (G + alpha I)^-1``
    (``s2`` the meta-model's hourly error variance, ``Zc`` the centred design; Hoerl and
    Kennard 1970); summed over the ``H`` hours, an inert parameter's fitted effect has the
    squared norm ``H s2 [A G A]_pp`` on average. The ratio is about 1 for a parameter without
    effect and grows with a real one.

    Parameters
    ----------
    surrogate : SeriesSurrogate
        Fitted (its design ``log_parameters_`` and ridge penalty are used).
    names : sequence of str
    emulator_error : float
        The meta-model's hourly error variance (:func:`emulator_variance`) [W^2].

    Returns
    -------
    ndarray
        One ratio per name [-]; infinite when the meta-model's error is zero.
    """
    features = [str(f) for f in surrogate.feature_names_in_]
    # the whole design (with the curvature's columns after the d linear ones): the variance
    # of each linear coefficient given the others
    Z = np.asarray(getattr(surrogate, "design_", surrogate.log_parameters_), dtype=float)
    Zc = Z - Z.mean(axis=0)
    alpha = float(getattr(surrogate.estimator_, "alpha_", 0.0))
    gram = Zc.T @ Zc
    A = np.linalg.pinv(gram + alpha * np.eye(Z.shape[1]))
    inverse = A @ gram @ A
    coef = np.atleast_2d(np.asarray(surrogate.estimator_.coef_, dtype=float))
    centred = getattr(surrogate, "centred", lambda a: a - a.mean(axis=-1, keepdims=True))
    jac = centred(coef[:, : len(features)].T)  # (parameters, hours)
    hours = jac.shape[1]
    out = []
    for name in names:
        p = features.index(str(name))
        noise = hours * max(float(emulator_error), 0.0) * inverse[p, p]
        signal = float(jac[p] @ jac[p])
        out.append(np.inf if noise <= 0 else signal / noise)
    return np.array(out)


def _noise(model: LinearHeatModel) -> tuple[np.ndarray, float, float, float]:
    """Best bounded fit ``z``, residual variance [W^2], effective and total hours [-]."""
    from thermocal.calibration.surrogate import bounded_series_fit

    zl, zu = model.z_bounds
    n, d = model.jacobian.shape
    z = bounded_series_fit(model.offset, model.jacobian, model.curvature, zl, zu)
    r = model.residual(z)
    # the hourly mean of each series (the unknown constant gains) and d parameters
    dof = max(n - model.series_count - d, 1)
    variance = float(r @ r) / dof
    return z, max(variance, 1e-12), effective_hours(r, model.segments or ((0, n),)), float(n)


#: Fewest hours of a series for its integrated autocorrelation time; a shorter one is taken at
#: the lag-1 time ``(1 + rho) / (1 - rho)`` alone [h].
IACT_MIN_HOURS = 50


def effective_hours(residual: np.ndarray, segments) -> float:
    """Effectively independent hours of a residual series, summed over its series [h].

    Each series (zone group, or the building) counts ``n_g / tau_g`` hours, with ``tau_g`` the
    longer of two correlation times of its residual, at least 1:

    * the integrated autocorrelation time: the sum of its autocorrelations up to Sokal's (1997)
      automatic window (the smallest lag ``M >= 5 tau(M)``; emcee's estimator, the one the
      posterior's chains are judged by). It sees the slow structure of the weather and of a
      model error that lasts for days (measured on the 118-zone outpatient twin: 2.5-14 h);
    * the lag-1 time ``(1 + rho) / (1 - rho)`` of a first-order autoregression (the form used
      alone before, 1.1-10 h there). For a smooth residual that oscillates over a day or two the
      integrated time sums the oscillation's negative lobes away, as they would cancel in a
      mean; along a parameter's signature, which has its own daily shape, they need not, and
      the lag-1 time is the longer one.

    The longer of the two is a conservative rule: it never counts more independent hours than
    the lag-1 form alone did, so the intervals only widen. The exact answer for each parameter
    would be the long-run (HAC) variance of the residual along that parameter's own signature;
    a single count scales every direction alike. The series hold the quiet hours only, one
    after the other, so a lag is a quiet hour, not a clock hour.

    Parameters
    ----------
    residual : ndarray (n_hours,)
        The residual series at the best fit, the series one after the other [W].
    segments : sequence of (int, int)
        Each series' start and end in ``residual`` [-].

    Returns
    -------
    float
        The effectively independent hours of all series together [h].
    """
    import emcee

    total = 0.0
    for a, b in segments:
        r = np.asarray(residual[a:b], dtype=float)
        n = len(r)
        if n < 4 or np.std(r) <= 0:
            total += n
            continue
        rho = float(np.corrcoef(r[:-1], r[1:])[0, 1])
        rho = min(max(rho if np.isfinite(rho) else 0.0, 0.0), 0.99)
        tau = (1.0 + rho) / (1.0 - rho)
        if n >= IACT_MIN_HOURS:
            integrated = float(emcee.autocorr.integrated_time(r, c=5, tol=0)[0])
            tau = max(tau, integrated if np.isfinite(integrated) else 1.0)
        total += n / max(tau, 1.0)
    return total


def residual_quadratic_form(model: LinearHeatModel, basis: np.ndarray | None = None):
    """``|r(z)|^2`` and ``U^T r(z)`` of the residual series, computed in parameter space.

    With ``r(z) = r0 + A w(z)`` (``w`` the model's :meth:`~LinearHeatModel.features`, ``A``
    its coefficients), ``|r|^2 = r0.r0 + 2 (A^T r0).w + w^T (A^T A) w`` and
    ``U^T r = U^T r0 + (A^T U)^T w``: each evaluation costs O(d^2 + d m) instead of
    O(n_hours d), which is what the sampler's hundred thousand evaluations spend.

    Parameters
    ----------
    model : LinearHeatModel
    basis : ndarray (n_hours, m), optional
        Directions ``U`` to project the residual on (the model discrepancy's).

    Returns
    -------
    callable
        ``z`` (shape (k, d)) -> (``|r|^2`` [W^2] shape (k,), ``U^T r`` [W] shape (k, m) or
        None).
    """
    A = model.coefficients
    r0 = model.offset
    gram, linear, constant = A.T @ A, A.T @ r0, float(r0 @ r0)
    if basis is not None and basis.size:
        projected0, mixed = basis.T @ r0, A.T @ basis
    else:
        projected0 = mixed = None

    def evaluate(z: np.ndarray):
        w = model.features(z)
        quadratic = constant + 2.0 * (w @ linear) + np.einsum("ij,ij->i", w @ gram, w)
        projected = None if mixed is None else projected0 + w @ mixed
        return np.maximum(quadratic, 0.0), projected

    return evaluate


def _gaussian_form(model: LinearHeatModel, basis, woodbury, scale: float, prior):
    """Precision ``Q`` and linear term ``b`` of the affine model's log-posterior in ``z``,
    ``-z^T Q z / 2 + b^T z`` (+ constant), the prior included.

    With ``r(z) = r0 + A z`` and the discrepancy's Woodbury term ``W`` on ``U^T r``:
    ``|r|^2 - (U^T r)^T W (U^T r)`` has the quadratic part ``A^T A - (A^T U) W (A^T U)^T``
    and the linear part ``2 (A^T r0 - (A^T U) W U^T r0)``; the log-posterior is ``-scale``
    times that plus the prior's log-density in ``z`` (``z`` for the uniform prior in ``p``, the
    log-normal of a parameter measured in situ).

    Parameters
    ----------
    model : LinearHeatModel
        Affine (no curvature).
    basis : ndarray (n_hours, m)
        The discrepancy's directions ``U`` (unused without ``woodbury``) [W].
    woodbury : ndarray (m, m) or None
        ``(a T^-1 + U^T U)^-1`` [-].
    scale : float
        ``(n_eff / n) / (2 sigma^2)`` [1/W^2].
    prior : (ndarray, ndarray)
        :func:`measured_prior`'s mean and precision.

    Returns
    -------
    precision : ndarray (d, d)
    linear : ndarray (d,)
    """
    A, r0 = model.coefficients, model.offset
    gram, cross = A.T @ A, A.T @ r0
    if woodbury is not None:
        mixed = A.T @ basis
        gram = gram - mixed @ woodbury @ mixed.T
        cross = cross - mixed @ (woodbury @ (basis.T @ r0))
    mean, measured_precision = prior
    # the uniform prior in p tilts z by exp(z); a measured parameter's log-normal replaces it
    tilt = model.prior_tilt(measured_precision)
    precision = 2.0 * scale * (gram + gram.T) / 2.0 + np.diag(measured_precision)
    return precision, tilt + measured_precision * mean - 2.0 * scale * cross


def _log_probability(model: LinearHeatModel, basis, woodbury, scale: float, prior):
    """The log-posterior of ``z`` (any model, curvature included) for the ensemble sampler:
    ``-scale`` times the residual's quadratic form (the discrepancy's Woodbury term removed)
    plus the prior's log-density (``z`` for the uniform prior in ``p``, the log-normal of a
    measured parameter), ``-inf`` outside the box.

    Parameters
    ----------
    model : LinearHeatModel
    basis, woodbury, scale, prior
        As :func:`_gaussian_form`.

    Returns
    -------
    callable
        ``z`` (shape (k, d)) -> log-density (shape (k,)) [-].
    """
    zl, zu = model.z_bounds
    squared_norm = residual_quadratic_form(model, basis if woodbury is not None else None)
    mean, measured_precision = prior
    tilt = model.prior_tilt(measured_precision)

    def log_probability(z: np.ndarray) -> np.ndarray:
        z = np.atleast_2d(z)
        inside = np.all((z >= zl) & (z <= zu), axis=1)
        quadratic, projected = squared_norm(z)
        if woodbury is not None:
            quadratic = quadratic - np.einsum("ij,ij->i", projected @ woodbury, projected)
        # uniform prior in the parameter p = p_nominal exp(z): density exp(z) in z (and
        # (1 - z)^-2 for a conductance coordinate); a measured parameter's log-normal instead
        lp = -scale * quadratic + z @ tilt - 0.5 * ((z - mean) ** 2 @ measured_precision)
        with np.errstate(invalid="ignore", divide="ignore"):
            lp = lp + model.prior_log_density_rest(np.where(inside[:, None], z, 0.0),
                                                   measured_precision)  # fmt: skip
        return np.where(inside, lp, -np.inf)

    return log_probability


#: The standard normal's 95 % quantile [-]
_Z90 = 1.6448536269514722


def measured_prior(names, nominal, measured: dict, kinds=None) -> tuple[np.ndarray, np.ndarray]:
    """Mean and precision of the priors of in-situ measured parameters, in ``z``.

    A measurement's log-normal (median the value, ``ln p`` of standard deviation ``s``,
    ``s^2 = ln(1 + r^2)``) is exact in the published coordinate ``log(p / p_nominal)``. In
    another coordinate (:mod:`thermocal.calibration.coordinates`) the Gaussian whose 5 % and
    95 % quantiles are the log-normal's, mapped (every coordinate increases with ``p``): the
    prior's 90 % interval is the measurement's exactly. (The delta method at the value, until
    2026-11-30, stretched the upper tail of a plate with 25 % uncertainty: 95 % at 4.97
    against the log-normal's 4.50 m2 K/W for a reading of 3; a review.)

    Parameters
    ----------
    names : sequence of str
        The posterior's parameters.
    nominal : array-like
        Their nominal values [unit of each].
    measured : dict
        name -> (value [unit of the parameter], relative standard uncertainty [-]); every name
        must be in ``names``.
    kinds : sequence of str, optional
        The coordinate of each parameter (default ``log`` for all).

    Returns
    -------
    mean : ndarray
        The midpoint of the mapped quantiles, ``ln(value / nominal)`` in the published form (0
        where not measured) [-].
    precision : ndarray
        ``(2 x 1.645 / (z_95 - z_05))^2``, ``1 / ln(1 + r^2)`` in the published form (0 where
        not measured) [-].
    """
    names = list(names)
    kinds = ["log"] * len(names) if kinds is None or not len(kinds) else list(kinds)
    unknown = [n for n in measured if n not in names]
    if unknown:
        raise ThermocalInputError(
            f"in-situ measurement of {unknown[0]!r}: not a parameter of the posterior "
            f"({', '.join(names)})"
        )
    mean, precision = np.zeros(len(names)), np.zeros(len(names))
    for name, (value, rel_std) in measured.items():
        i = names.index(name)
        if not (value > 0 and rel_std > 0):
            raise ThermocalInputError(
                f"in-situ measurement of {name!r}: value {value} and relative uncertainty "
                f"{rel_std} must be positive"
            )
        reference, kind = float(np.asarray(nominal)[i]), kinds[i]
        spread = _Z90 * np.sqrt(np.log1p(rel_std**2))
        z05, z95 = to_coordinates(
            value * np.exp([-spread, spread]), [reference, reference], [kind, kind]
        )
        mean[i] = 0.5 * (z05 + z95)
        precision[i] = (2.0 * _Z90 / (z95 - z05)) ** 2
    return mean, precision


def calibration_posterior(
    surrogate,
    names: Sequence[str],
    lower,
    upper,
    *,
    all_lower=None,
    all_upper=None,
    units: Sequence[str] | None = None,
    emulator_error: float = 0.0,
    discrepancy: str | bool = "none",
    walkers: int | None = None,
    steps: int = 2000,
    seed: int = 0,
    effective_draws: int = POSTERIOR_EFFECTIVE_DRAWS,
    measured: dict | None = None,
    uncertain: Sequence = (),
) -> Posterior:
    """Sample the posterior of some parameters from a fitted series meta-model.

    Parameters
    ----------
    surrogate : SeriesSurrogate
        Fitted on the campaign's samples (its hourly regressions give the linear model).
    names : sequence of str
        The calibrated parameters (e.g. the critical ones); the others stay nominal.
    lower, upper : array-like
        Prior bounds of ``names`` (the campaign's) [unit of each parameter].
    all_lower, all_upper : array-like, optional
        Bounds of every meta-model parameter, for the Fisher information of the whole space
        [unit of each parameter]; default: only ``names``.
    units : sequence of str, optional
        Units of ``names`` for the tables.
    emulator_error : float
        Variance of the meta-model's own hourly error (:func:`emulator_variance`), added to the
        residual noise [W^2].
    discrepancy : {"none", "neighbours", "floor", "shared"}
        Add the parameter-like model discrepancy of :func:`discrepancy_basis` (with that prior
        scale; ``True`` means ``"neighbours"``) to the likelihood, marginalised analytically
        (Gaussian, by the Woodbury identity): the intervals then include what a model error
        that mimics a parameter change may shift.
    walkers : int, optional
        Ensemble size of the sampler with curvature [-]; default ``max(128, 8 d)``.
    steps : int
        Fewest steps per walker (for the affine model's Gibbs sampler at most ``GIBBS_SWEEPS``
        sweeps) [-]; the first half of all steps run is discarded as burn-in.
    seed : int
        Seed of the sampler [-].
    effective_draws : int
        The sampler runs on (up to ``POSTERIOR_MAX_STEP_FACTOR`` times ``steps``) until the
        kept draws are worth this many independent ones, by the integrated autocorrelation
        time (Goodman and Weare 2010; Sokal 1997) [-]. The Monte Carlo standard errors of the
        interval ends are in the summary (``q05_mcse``, ``q95_mcse``).
    measured : dict, optional
        In-situ measurements of some of ``names``: name -> (value [unit of the parameter],
        relative standard uncertainty [-]). Each replaces the parameter's uniform prior by a
        log-normal one within the same bounds, ``z ~ N(ln(value / nominal), ln(1 + r^2))``
        (:func:`measured_prior`).
    uncertain : sequence of (dict, ndarray, float)
        Inputs the campaign did not vary whose values are not known either (e.g. the
        infiltration without a pressurisation test): per input its description (``label``,
        ``rel_std``, ``parameters``, for the result), its signature (the series' change per
        unit change of the log of the input, the series one after the other as the
        meta-model's) [W] and the prior variance of that log [-]. Each enters the
        likelihood's covariance as ``variance * s s^T`` (``s`` the signature centred over
        each series' hours), marginalised analytically with the model discrepancy: the
        exact marginal of a Gaussian nuisance parameter of the affine model
        (:mod:`thermocal.calibration.uncertain`).

    Returns
    -------
    Posterior
    """
    names = [str(n) for n in names]
    model = linear_heat_model(surrogate, names, lower, upper)
    d = len(names)
    if d == 0:
        raise ThermocalInputError("posterior: no parameter to calibrate")
    prior_mean, prior_precision = measured_prior(
        names, model.nominal, measured or {}, model.coordinate_kinds
    )
    z_hat, residual_variance, n_eff, n = _noise(model)
    variance = residual_variance + max(float(emulator_error), 0.0)
    scale = (n_eff / n) / (2.0 * variance)
    zl, zu = model.z_bounds
    if discrepancy is True:
        discrepancy = "neighbours"
    if discrepancy in (False, None, "none"):
        basis, tau2 = np.zeros((0, 0)), []
    else:
        # the signatures at the best fit (with curvature, the tangent model's)
        basis, tau2 = discrepancy_basis(model.local(z_hat), model.residual(z_hat), str(discrepancy))
    a = 1.0 / (2.0 * scale)
    inputs = _uncertain_columns(model, uncertain)
    correlations = _input_correlations(model.local(z_hat), basis, tau2, a, inputs, prior_precision)
    if inputs:
        n_hours = len(model.offset)
        basis = basis if np.size(basis) else np.zeros((n_hours, 0))
        basis = np.column_stack([basis] + [column for _, column, _ in inputs])
        tau2 = np.concatenate([np.asarray(tau2, dtype=float), [v for _, _, v in inputs]])
    if len(tau2):
        # covariance a I + U T U^T with a = 1 / (2 scale): its inverse by Woodbury,
        # r^T S^-1 r = (|r|^2 - (U^T r)^T (a T^-1 + U^T U)^-1 (U^T r)) / a
        woodbury = np.linalg.inv(np.diag(a / tau2) + basis.T @ basis)
    else:
        woodbury = None

    if model.curvature is None:
        # affine: the posterior is a Gaussian in z truncated to the box; sampled exactly
        precision, linear = _gaussian_form(
            model, basis, woodbury, scale, (prior_mean, prior_precision)
        )
        # the prior's non-linear part (a resistance uniform in R in its conductance
        # coordinate) in the conditionals of those coordinates
        chain, effective, tau, acceptance = truncated_gaussian_gibbs(
            precision, linear, zl, zu, z_hat, sweeps=min(int(steps), GIBBS_SWEEPS), seed=int(seed),
            effective_draws=int(effective_draws),
            conductance=model.conductance_prior(prior_precision),
        )  # fmt: skip
    else:
        rng = np.random.default_rng(int(seed))
        n_walkers = int(walkers or max(POSTERIOR_WALKERS, 8 * d))
        n_walkers += n_walkers % 2
        # start in a small ball around the best fit, inside the bounds
        width = np.maximum(zu - zl, 1e-9)
        start = np.clip(
            z_hat + 1e-3 * width * rng.standard_normal((n_walkers, d)),
            zl + 1e-6 * width,
            zu - 1e-6 * width,
        )
        log_probability = _log_probability(
            model, basis, woodbury, scale, (prior_mean, prior_precision)
        )

        chain, effective, tau, acceptance = ensemble_until_precise(
            log_probability, start, int(steps), int(seed), int(effective_draws)
        )
    values = model.values(chain)
    draws = pd.DataFrame(values, columns=names)
    q05, q50, q95 = np.quantile(values, [0.05, 0.5, 0.95], axis=0)
    mcse05, mcse95 = (quantile_standard_error(values, p, effective) for p in (0.05, 0.95))
    prior_width = model.upper - model.lower
    fraction = (q95 - q05) / np.where(prior_width > 0, prior_width, np.nan)
    if hasattr(surrogate, "log_parameters_"):
        significance = effect_to_noise(surrogate, names, emulator_error)
    else:
        significance = np.full(d, np.inf)
    uncertain_inputs = _input_descriptions(uncertain, inputs, correlations, names)
    # a parameter that compensates an uncertain input is fixed by that input's prior, an
    # assumption, not by the data (unless it was measured)
    confounded = np.array(
        [any(n in item["compensates"] for item in uncertain_inputs) for n in names], dtype=bool
    )
    summary = pd.DataFrame(
        {
            "unit": list(units) if units is not None else ["?"] * d,
            "nominal": model.nominal,
            "map": model.values(z_hat),
            "median": q50,
            "q05": q05,
            "q95": q95,
            "q05_mcse": mcse05,
            "q95_mcse": mcse95,
            "prior_lower": model.lower,
            "prior_upper": model.upper,
            "width_fraction": fraction,
            "effect_to_noise": significance,
            "measured": prior_precision > 0,
            # a parameter measured in situ is determined by the measurement and the data
            "determined": (fraction < DETERMINED_FRACTION)
            & ((significance > EFFECT_TO_NOISE) | (prior_precision > 0))
            & ~(confounded & (prior_precision == 0)),
        },
        index=pd.Index(names, name="parameter"),
    )
    corr = np.corrcoef(chain, rowvar=False) if d > 1 else np.ones((1, 1))
    correlation = pd.DataFrame(np.atleast_2d(corr), index=names, columns=names)
    pairs = [
        (names[i], names[j], float(corr[i, j]))
        for i in range(d)
        for j in range(i + 1, d)
        if abs(corr[i, j]) > COMPENSATION_CORRELATION
    ]
    full_names = [str(f) for f in surrogate.feature_names_in_]
    if all_lower is not None and all_upper is not None:
        full = linear_heat_model(surrogate, full_names, all_lower, all_upper)
        z_full = np.zeros(len(full_names))
        z_full[[full_names.index(n) for n in names]] = z_hat
    else:
        full, z_full = model, z_hat
    jacobian = full.jacobian_at(z_full)  # at the best fit (the same as at 0 when affine)
    singular = np.linalg.svd(jacobian * np.sqrt(2.0 * scale), compute_uv=False)
    return Posterior(
        summary=summary,
        correlation=correlation,
        compensating=sorted(pairs, key=lambda p: -abs(p[2])),
        noise_std=float(np.sqrt(variance)),
        emulator_std=float(np.sqrt(max(float(emulator_error), 0.0))),
        effective_hours=float(n_eff),
        fisher_singular_values=singular,
        acceptance=float(acceptance),
        samples=draws,
        effective_draws=float(effective),
        autocorrelation_steps=float(tau),
        uncertain=uncertain_inputs,
    )


def _centred(values: np.ndarray, segments, n: int) -> np.ndarray:
    """``values`` (the series one after the other) minus each series' mean."""
    out = np.array(values, dtype=float, copy=True)
    for a, b in segments or ((0, n),):
        out[a:b] -= out[a:b].mean()
    return out


def _uncertain_columns(model: LinearHeatModel, uncertain) -> list:
    """The uncertain inputs' directions for the likelihood's covariance.

    Each signature is centred over each series' hours (the residual's unknown constant gains,
    as the meta-model's coefficients) and scaled to unit RMS, its variance by the same factor
    squared [W^2].

    Returns
    -------
    list of (int, ndarray, float)
        Per input with an effect: its position in ``uncertain``, the unit-RMS column and the
        variance [W^2].
    """
    n = model.offset.shape[0]
    out = []
    for i, (description, signature, variance) in enumerate(uncertain):
        signature = np.asarray(signature, dtype=float)
        if signature.shape != (n,):
            raise ThermocalInputError(
                f"posterior: the signature of {description['label']} has "
                f"{signature.shape[0]} hours, the meta-model's series {n}"
            )
        centred = _centred(signature, model.segments, n)
        rms = float(np.sqrt(np.mean(centred**2)))
        if rms > 0 and variance > 0:
            out.append((i, centred / rms, float(variance) * rms**2))
    return out


def _input_correlations(model: LinearHeatModel, basis, tau2, a: float, inputs, measured):
    """Posterior correlations of the parameters with the uncertain inputs, (d, m).

    From the joint Gaussian of ``z`` and the inputs' amplitudes (each with its prior
    variance), the likelihood's covariance ``a I`` plus the model discrepancy's ``U T U^T``
    (by Woodbury); ``z``'s uniform prior enters as a Gaussian of the same variance (its box's
    width over sqrt(12)) and a measured parameter's log-normal with its precision. The box's
    truncation is not taken into account (a diagnostic, not the sampler's posterior).

    Parameters
    ----------
    model : LinearHeatModel
        Affine (the tangent model at the best fit when there is curvature).
    basis, tau2 : ndarray, sequence
        The discrepancy's unit-RMS directions and variances [W^2].
    a : float
        The likelihood's variance per hour [W^2].
    inputs : list
        :func:`_uncertain_columns`.
    measured : ndarray (d,)
        Precision of the measured parameters' priors (0 where not measured) [-].

    Returns
    -------
    ndarray (d, len(inputs))
    """
    d = model.jacobian.shape[1]
    if not inputs:
        return np.zeros((d, 0))
    X = np.column_stack([model.jacobian] + [column for _, column, _ in inputs])
    if np.size(basis):
        U = basis
        inverse = np.linalg.inv(np.diag(a / np.asarray(tau2, dtype=float)) + U.T @ U)
        solved = (X - U @ (inverse @ (U.T @ X))) / a
    else:
        solved = X / a
    precision = X.T @ solved
    zl, zu = model.z_bounds
    box = 12.0 / np.maximum(zu - zl, 1e-12) ** 2
    precision[:d, :d] += np.diag(np.where(measured > 0, measured, box))
    precision[d:, d:] += np.diag([1.0 / v for _, _, v in inputs])
    covariance = np.linalg.pinv((precision + precision.T) / 2.0)
    sd = np.sqrt(np.maximum(np.diag(covariance), 1e-300))
    return (covariance / np.outer(sd, sd))[:d, d:]


def _input_descriptions(uncertain, inputs, correlations, names) -> list[dict]:
    """The uncertain inputs for the result: each description with ``effect`` (whether it
    changes the series at all) and ``compensates`` (parameter -> posterior correlation beyond
    :data:`COMPENSATION_CORRELATION` in magnitude)."""
    column = {i: k for k, (i, _, _) in enumerate(inputs)}
    out = []
    for i, (description, _, _) in enumerate(uncertain):
        k = column.get(i)
        compensates = {}
        if k is not None:
            compensates = {
                name: float(correlations[j, k])
                for j, name in enumerate(names)
                if abs(correlations[j, k]) > COMPENSATION_CORRELATION
            }
        out.append({**description, "effect": k is not None, "compensates": compensates})
    return out
