"""Data that correct the building description in both directions: one multiplicative factor
per envelope group on the calculated U-values, estimated with a prior (maximum a posteriori).

The published fifth-order method calculates the transmission conductances from the audit
U-values and estimates a single extra loss ``H_est`` (ventilation, infiltration, thermal
bridges) on top: the data can add losses to the description, never remove them. Yet
calculated losses are more often too high than too low -- the *prebound effect*: measured
consumption of existing houses lies on average some 30 % below the calculated rating
(Sunikka-Blank and Galvin 2012), and in-situ U-values of old solid walls are mostly lower
than the tabulated ones (Baker 2011; Li et al. 2015). So the calibration estimates, with the
capacities and ``H_est``:

- ``k_env`` (roof + walls), ``k_win`` (windows), ``k_floor`` (cellar ceiling or ground floor):
  the construction's U-value is ``k U_audit``; the element's inner and outer conductances and
  its share of absorbed solar radiation follow (:meth:`FifthOrderModel.conductances`), so the
  calibrated network is the one the strategies use. For a floor on the ground ``k_floor``
  scales the ground path as a whole, with the soil's uncertainty added to its prior
  (:func:`group_prior_std_log`). Prior ``ln k ~ N(0, s^2)`` with
  ``s = sqrt(ln(1 + r^2))`` from the relative U-value uncertainty ``r``
  (``uncertainty.u_value_rel_std``): centred on the description, no direction built in;
- ``H_est``: prior ``ln H_est ~ N(ln H_est0, 0.5^2)`` around the building file's allowance
  (its ``air_change_rate``, default 0.5 1/h, thermal bridges, doors): air-change rates of
  houses range over a factor of about 2 either way.
- capacities: flat within their bounds.

The nuisance parameters (diffusions, measurement noise, initial states) stay at their
maximum-likelihood values; the posterior is maximised over ``z = ln`` (factors, ``H_est``,
capacities) with the engine's Kalman-filter log-likelihood
(:meth:`thermocal.statespace.RCModel.loglike`). Laplace approximation at the optimum: the
log-likelihood's curvature (projected onto positive semi-definite) plus the prior precisions
(capacities: a standard deviation of ln 2) give a Gaussian posterior in ``z``. Draws from it
(truncated to the bounds) carry the uncertainty of
the factors, of ``H_est`` and of capacities at a bound (whose log-likelihood stays defined
beyond it) into every demand and saving.

Identifiability: a group is *separated by the data* when its posterior standard deviation is
below 0.7 of its prior one (the measurements removed at least half of the prior variance);
otherwise the prior decides its share and the data only fix the total heat loss coefficient.

References
----------
M. Sunikka-Blank and R. Galvin, "Introducing the prebound effect: the gap between performance
and actual energy consumption", Building Research & Information 40(3), 2012.
P. Baker, "U-values and traditional buildings", Historic Scotland Technical Paper 10, 2011.
F. G. N. Li et al., "Solid-wall U-values: heat flux measurements compared with standard
assumptions", Building Research & Information 43(2), 2015.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from thermocal.montecarlo import truncated_gaussian_draws

#: Correction groups and the envelope components they can scale; the floor group scales
#: whichever floor the building has (:func:`group_components`).
GROUPS: dict[str, tuple[str, ...]] = {
    "k_env": ("roof", "walls", "attic_ceiling", "wall_to_unheated"),
    "k_win": ("windows",),
    "k_floor": ("cellar_ceiling", "ground_floor"),
}
#: What the floor group's component is, by the ground path's kind (ISO 13370 clause).
FLOOR_DESCRIPTIONS: dict[str, str] = {
    "unheated_basement": "ceiling over an unheated basement (ISO 13370 clause 9.3)",
    "slab": "slab on ground (ISO 13370 clause 9.1); the factor scales its ground path as a "
    "whole, the soil's uncertainty in its prior",
    "heated_basement": "floor of a heated basement (ISO 13370 clause 9.2); the factor scales "
    "its ground path as a whole, the soil's uncertainty in its prior",
}


def group_components(envelope, ground_kind: str, in_situ=()) -> dict[str, dict]:
    """The components each correction group scales in this building, and what the floor is.

    Parameters
    ----------
    envelope : EnvelopeComponents
        The building file's envelope; its ``floor_kind`` is the floor's component type
        (``cellar_ceiling`` or ``ground_floor``).
    ground_kind : str
        :attr:`GroundPath.kind` of the model (``unheated_basement``, ``slab``,
        ``heated_basement``).

    Returns
    -------
    dict group -> {"label": str, "components": list of str[, "description": str]}
        The floor group names the building's floor component only, with its description.
    """
    measured = set(in_situ)
    out = {g: {"label": GROUP_LABELS[g], "components": [c for c in comps if c not in measured]}
           for g, comps in GROUPS.items() if g != "k_floor"}  # fmt: skip
    if measured & set(GROUPS["k_env"]):
        out["k_env"]["label"] = _unmeasured_words(envelope, measured)
    for g, c in IN_SITU_GROUPS.items():
        if c in measured:
            out[g] = {"label": GROUP_LABELS[g], "components": [c],
                      "description": "measured in situ (ISO 9869-1)"}  # fmt: skip
    out["k_floor"] = {
        "label": GROUP_LABELS["k_floor"] + (" (in situ)" if "cellar_ceiling" in measured else ""),
        "components": [envelope.floor_kind],
        "description": FLOOR_DESCRIPTIONS.get(ground_kind, ground_kind)
        + ("; measured in situ (ISO 9869-1)" if "cellar_ceiling" in measured else ""),
    }
    return out


#: Components of ``k_env`` that take a factor of their own when measured in situ
#: (:mod:`thermocal.retrofit.in_situ`), with their envelope attribute; a measured cellar
#: ceiling is the floor group's only component, so its measurement is ``k_floor``'s prior.
IN_SITU_GROUPS: dict[str, str] = {
    "k_roof": "roof",
    "k_walls": "walls",
    "k_attic_ceiling": "attic_ceiling",
    "k_wall_to_unheated": "wall_to_unheated",
}
_COMPONENT_PRESENT = {
    "roof": "roof_area",
    "walls": "walls_area",
    "attic_ceiling": "attic_area",
    "wall_to_unheated": "adjacent_area",
}


def is_factor(name: str) -> bool:
    """Whether ``name`` (an entry of :attr:`Correction.names`) is a group factor."""
    return name in GROUPS or name in IN_SITU_GROUPS


def correction_groups(model) -> list[str]:
    """The factors the calibration estimates for this model, in order.

    ``k_env`` over the roof and walls not measured in situ (absent when all were), one
    ``k_<component>`` per measured component of it, ``k_win``, ``k_floor`` -- each when the
    building has the components.
    """
    env = model.envelope
    measured = set(getattr(model, "in_situ", {}) or {})
    out = []
    for g in GROUPS:
        if g == "k_env":
            if shared_factor_components(env, measured):
                out.append(g)
            present = [c for c in GROUPS[g] if getattr(env, _COMPONENT_PRESENT[c]) > 0]
            out += [f"k_{c}" for c in present if c in measured]
        elif _group_present(env, g):
            out.append(g)
    return out


def shared_factor_components(envelope, measured=()) -> list[str]:
    """The building's components that share the roof-and-walls factor ``k_env``: present and
    not measured in situ (their measures' intervals assume their descriptions are off by the
    same factor).

    Parameters
    ----------
    envelope : EnvelopeComponents
    measured : iterable of str
        The components measured in situ (``in_situ`` keys).
    """
    measured = set(measured)
    return [
        c for c in GROUPS["k_env"]
        if c not in measured and getattr(envelope, _COMPONENT_PRESENT[c]) > 0
    ]  # fmt: skip


def _unmeasured_words(envelope, measured) -> str:
    """The building's components of ``k_env`` not measured in situ, in words."""
    return " + ".join(COMPONENT_WORDS[c] for c in shared_factor_components(envelope, measured))


def group_label(group: str, model) -> str:
    """What a factor scales, in words (``k_env`` names only its unmeasured components when
    some have factors of their own)."""
    measured = set(getattr(model, "in_situ", {}) or {})
    if group == "k_env" and measured & set(GROUPS["k_env"]):
        return _unmeasured_words(model.envelope, measured)
    if group == "k_floor" and "cellar_ceiling" in measured:
        return "floor (in situ)"
    return GROUP_LABELS[group]


def measured_groups(groups, model) -> tuple[str, ...]:
    """The factors among ``groups`` whose prior is an in-situ measurement."""
    in_situ = getattr(model, "in_situ", {}) or {}
    return tuple(
        g for g in groups
        if IN_SITU_GROUPS.get(g) in in_situ or (g == "k_floor" and "cellar_ceiling" in in_situ)
    )  # fmt: skip


def group_priors(groups, rel_std: float, model) -> tuple[np.ndarray, np.ndarray]:
    """Prior mean and standard deviation of each factor's ``ln k`` [-].

    Centred on the description (0) with :func:`group_prior_std_log`, except a component
    measured in situ: ``ln(U_measured / U_described)`` with the measurement's uncertainty
    (:attr:`thermocal.retrofit.in_situ.InSituMeasurement.prior`).
    """
    in_situ = getattr(model, "in_situ", {}) or {}
    std = group_prior_std_log(groups, rel_std, model.envelope)
    mean = np.zeros(len(groups))
    for i, g in enumerate(groups):
        component = IN_SITU_GROUPS.get(g) or ("cellar_ceiling" if g == "k_floor" else None)
        if component in in_situ:
            mean[i], std[i] = in_situ[component]
    return mean, std


#: Prior standard deviation of ln H_est (air change rates: a factor ~2 either way).
H_EST_PRIOR_STD_LOG = 0.5
#: A group is separated by the data when posterior / prior standard deviation is below this.
SEPARATED_RATIO = 0.7
#: A group whose ln k correlates with ln H_est at or below minus this shares its loss with
#: H_est: the summary says the priors decide their split.
SHARED_CORRELATION = 0.5
#: Bounds of the factors [-].
FACTOR_BOUNDS = (0.3, 3.0)


def prior_std_log(rel_std: float) -> float:
    """Standard deviation of ``ln k`` for a relative standard deviation ``rel_std`` of U."""
    return float(np.sqrt(np.log1p(float(rel_std) ** 2)))


def corrects_the_ground_path(envelope) -> bool:
    """Whether the floor group's factor scales the ground path as a whole (a floor on the
    ground: slab or heated basement, whose loss is the soil's) rather than the floor's U-value
    (a ceiling over an unheated basement, whose insulation decides its loss)."""
    return envelope.floor_kind == "ground_floor"


def group_prior_std_log(groups, rel_std: float, envelope) -> np.ndarray:
    """Prior standard deviation of each group's ``ln k`` [-].

    ``prior_std_log(rel_std)`` for every group, except the floor of a house on the ground
    (slab or heated basement, ISO 13370): its factor corrects the ground path as a whole
    (:func:`scaled_envelope`), whose loss is the soil's far more than the construction's, so
    its prior also carries the soil conductivity's (log-normal around ISO 13370's default,
    :data:`thermocal.retrofit.ground_draws.SOIL_STD_LOG`):
    ``sqrt(prior_std_log(rel_std)^2 + SOIL_STD_LOG^2)``.
    """
    from thermocal.retrofit.ground_draws import SOIL_STD_LOG

    s_k = prior_std_log(rel_std)
    on_ground = corrects_the_ground_path(envelope)
    return np.array(
        [np.hypot(s_k, SOIL_STD_LOG) if g == "k_floor" and on_ground else s_k for g in groups]
    )


def scaled_envelope(envelope, factors: dict[str, float]):
    """The envelope with its U-values multiplied by the group factors.

    Always a new object, so :meth:`FifthOrderModel.conductances` treats it as a changed
    construction. The floor group's factor scales the floor's U-value above an unheated
    basement (its construction decides the loss) and, for a floor on the ground (slab or heated
    basement), the ground path's conductance as a whole (``floor_factor``): its loss is the
    soil's far more than the slab's (the first EnergyPlus twin: a factor on the uninsulated
    slab's construction of 0.7 moved the ISO 13370 ground loss by 5 %), so the data could not
    correct it; a measure adds its insulation in series with the corrected path.
    """
    k_env = float(factors.get("k_env", 1.0))
    k_floor = float(factors.get("k_floor", 1.0))
    on_ground = corrects_the_ground_path(envelope)

    def k(component):  # a component measured in situ has its own factor
        return float(factors.get(f"k_{component}", k_env))

    return replace(
        envelope,
        roof_u=envelope.roof_u * k("roof"),
        walls_u=envelope.walls_u * k("walls"),
        attic_u=envelope.attic_u * k("attic_ceiling"),
        adjacent_u=envelope.adjacent_u * k("wall_to_unheated"),
        windows_u=envelope.windows_u * float(factors.get("k_win", 1.0)),
        floor_u=envelope.floor_u if on_ground else envelope.floor_u * k_floor,
        floor_factor=envelope.floor_factor * k_floor if on_ground else envelope.floor_factor,
    )


@dataclass
class Correction:
    """The estimated group factors and their posterior (log space)."""

    factors: dict[str, float]  # MAP [-]
    names: list[str]  # order of z: factors, H_est, free capacities
    z_map: np.ndarray  # ln of the MAP values (H_est [W/K], capacities [J/K])
    cov_z: np.ndarray  # posterior covariance of z (with the heat meter's common factor)
    cov_data: np.ndarray  # the posterior from the data and priors alone (identifiability)
    z_lower: np.ndarray
    z_upper: np.ndarray
    prior_std: dict[str, float]  # ln k and ln H_est
    posterior_std: dict[str, float]
    separated: dict[str, bool]  # group -> the data determine it
    log_posterior: float = 0.0
    map_values: dict = field(default_factory=dict)  # every parameter of the network, declared
    correlation: dict[str, float] = field(default_factory=dict)  # pairs of z with |r| > 0.9
    #: posterior correlation of each group's ln k with ln H_est (data and priors)
    h_est_correlation: dict[str, float] = field(default_factory=dict)
    #: what each factor scales, in words (:func:`group_label`); default GROUP_LABELS
    labels: dict[str, str] = field(default_factory=dict)
    #: prior mean of each factor's ln k (non-zero for a component measured in situ)
    prior_mean: dict[str, float] = field(default_factory=dict)
    #: the factors whose prior is an in-situ measurement
    measured: tuple = ()

    def label(self, group: str) -> str:
        """What ``group`` scales, in words."""
        return self.labels.get(group) or GROUP_LABELS[group]

    def physical_si(self, z: np.ndarray) -> dict[str, np.ndarray]:
        """Estimated parameters in SI (W/K, J/K) of draws ``z`` (n, len(names))."""
        z = np.atleast_2d(z)
        return {n: np.exp(z[:, i]) for i, n in enumerate(self.names) if not is_factor(n)}

    def group_factors(self, z: np.ndarray) -> dict[str, np.ndarray]:
        """Group factors [-] of draws ``z`` (n, len(names))."""
        z = np.atleast_2d(z)
        return {n: np.exp(z[:, i]) for i, n in enumerate(self.names) if is_factor(n)}

    def summary(self) -> str:
        """One sentence on what the data correct and what they separate."""
        parts = []
        for g, k in self.factors.items():
            if g in self.measured:
                parts.append(
                    f"{self.label(g)} x {k:.2f} (measured in situ x "
                    f"{np.exp(self.prior_mean[g]):.2f}, sd of ln k {self.prior_std[g]:.2f}; "
                    f"posterior {self.posterior_std[g]:.2f})"
                )
                continue
            parts.append(
                f"{self.label(g)} x {k:.2f} (posterior sd of ln k {self.posterior_std[g]:.2f}"
                f" vs prior {self.prior_std[g]:.2f}: "
                + ("separated by the data" if self.separated[g] else "prior-dominated")
                + ")"
            )
        shared = [
            f"{self.label(g)} (posterior correlation {r:+.2f})"
            for g, r in self.h_est_correlation.items() if r <= -SHARED_CORRELATION
        ]  # fmt: skip
        text = "calculated U-values corrected by the data: " + "; ".join(parts)
        if shared:
            text += (
                "; the estimated extra loss H_est shares the loss with "
                + ", ".join(shared)
                + ": the data fix their sum, the priors mostly their split (the intervals "
                "carry it); a measured air change moves that split towards the house's (the "
                "building file's air_change_rate [1/h], e.g. a blower-door test's n50 / 20)"
            )
        if "k_env" in self.factors and not self.separated.get("k_env", True):
            # the remedy the analysis can take: the roof-and-walls group's own measurement
            text += (
                f"; the data leave the {self.label('k_env')} to the prior: an in-situ U-value "
                "of its largest element (a heat-flux plate, ISO 9869-1: the retrofit "
                "configuration's in_situ section) gives that element a factor of its own"
            )
        return text


GROUP_LABELS = {
    "k_env": "roof + walls",
    "k_win": "windows",
    "k_floor": "floor",
    "k_roof": "roof (in situ)",
    "k_walls": "walls (in situ)",
    "k_attic_ceiling": "ceiling under the attic (in situ)",
    "k_wall_to_unheated": "walls to unheated spaces (in situ)",
}
#: The components of ``k_env`` in words.
COMPONENT_WORDS = {
    "roof": "roof",
    "walls": "walls",
    "attic_ceiling": "ceiling under the attic",
    "wall_to_unheated": "walls to unheated spaces",
    "cellar_ceiling": "cellar ceiling",
}


def estimate_correction(
    rc,
    params,
    data,
    model,
    *,
    rel_std: float,
    h_est_prior: float,
    seed: int = 0,
    heat_rel_std: float = 0.0,
) -> Correction:
    """Maximum a posteriori group factors, ``H_est`` and capacities (see module docstring).

    Parameters
    ----------
    rc : thermocal.statespace.RCModel
        The calibration network with the calculated conductances and factors as (fixed)
        parameters (:func:`thermocal.retrofit.calibration.rc_spec`).
    params : pd.Series
        Maximum-likelihood estimates of every parameter of ``rc`` [declared units]: the
        nuisance parameters stay there, the physical ones are the starting point.
    data : pd.DataFrame
        Training data.
    model : FifthOrderModel
    rel_std : float [-]
        Relative standard deviation of the audit U-values (the prior of the factors).
    h_est_prior : float [W/K]
        Median of the ``H_est`` prior.
    heat_rel_std : float [-]
        Relative standard uncertainty of the measured heat as a whole (a meter's systematic
        error): scaling the heat by ``f`` scales every conductance and capacity the data
        imply by about ``f`` (exactly without solar gains), so ``(ln f)^2`` is added to the
        covariance of every pair of ``z`` (fully correlated). The identifiability check uses
        the posterior before it.

    Returns
    -------
    Correction
    """
    from scipy.optimize import minimize

    from thermocal.retrofit.model import CALCULATED_CONDUCTANCES, ESTIMATED_PARAMETERS
    from thermocal.statespace import prepare_data

    prep = prepare_data(rc, data)
    base = {n: float(params[n]) for n in rc.parameter_names}
    groups = correction_groups(model)
    phys = [n for n in ESTIMATED_PARAMETERS if n not in model.fixed]
    names = groups + phys
    scale = {n: 1e6 if model.estimated[n][3] == "MJ/K" else 1.0 for n in phys}
    s_k = prior_std_log(rel_std)
    m_groups, s_groups = group_priors(groups, rel_std, model)
    lo = [np.log(FACTOR_BOUNDS[0])] * len(groups)
    hi = [np.log(FACTOR_BOUNDS[1])] * len(groups)
    for n in phys:
        lo.append(np.log(model.estimated[n][0] * scale[n]))
        hi.append(np.log(model.estimated[n][2] * scale[n]))
    lo, hi = np.array(lo), np.array(hi)
    z0 = np.array(list(m_groups) + [np.log(base[n] * scale[n]) for n in phys])
    z0 = np.clip(z0, lo + 1e-6, hi - 1e-6)
    ln_h0 = np.log(h_est_prior)
    i_h = names.index("H_est") if "H_est" in names else None

    def values(z):
        vals = dict(base)
        k = dict(zip(groups, np.exp(z[: len(groups)]), strict=True))
        env = scaled_envelope(model.envelope, k)
        h = model.conductances(env)
        for n in CALCULATED_CONDUCTANCES + ("share_roof", "share_walls"):
            if n in vals:
                vals[n] = float(h[n])
        for j, n in enumerate(phys):
            vals[n] = float(np.exp(z[len(groups) + j]) / scale[n])
        return vals

    def neg_log_post(z):
        ll = rc.loglike(prep, values(z))
        if not np.isfinite(ll):
            return 1e12
        lp = -0.5 * np.sum(((z[: len(groups)] - m_groups) / s_groups) ** 2) if s_k > 0 else 0.0
        if i_h is not None:
            lp += -0.5 * ((z[i_h] - ln_h0) / H_EST_PRIOR_STD_LOG) ** 2
        return -(ll + lp)

    res = minimize(
        neg_log_post,
        z0,
        method="L-BFGS-B",
        bounds=list(zip(lo, hi, strict=True)),
        options={"eps": 1e-5, "maxiter": 200},
    )
    z = res.x

    # Laplace approximation: the curvature of the log-likelihood (projected onto positive
    # semi-definite: at a bound or in a flat direction it can bend the wrong way) plus the
    # prior precisions; a capacity the data ignore (no prior) gets a standard deviation of
    # ln 2 (a factor of two), the draws are truncated to its bounds
    def neg_ll(zz):
        ll = rc.loglike(prep, values(zz))
        return -ll if np.isfinite(ll) else 1e12

    hess = _hessian(neg_ll, z, 1e-3)
    w, v = np.linalg.eigh(0.5 * (hess + hess.T))
    precision = (v * np.clip(w, 0.0, None)) @ v.T
    prior_precision = np.full(len(names), 1.0 / np.log(2.0) ** 2)
    if s_k > 0:
        prior_precision[: len(groups)] = 1.0 / s_groups**2
    if i_h is not None:
        prior_precision[i_h] = 1.0 / H_EST_PRIOR_STD_LOG**2
    precision += np.diag(prior_precision)
    cov = np.linalg.inv(precision)
    sd = np.sqrt(np.diag(cov))
    prior = {g: float(s) for g, s in zip(groups, s_groups, strict=True)}
    post = {g: float(sd[i]) for i, g in enumerate(groups)}
    if i_h is not None:
        prior["H_est"] = H_EST_PRIOR_STD_LOG
        post["H_est"] = float(sd[i_h])
    corr = cov / np.outer(sd, sd)
    pairs = {
        f"{names[i]}/{names[j]}": float(corr[i, j])
        for i in range(len(names))
        for j in range(i)
        if abs(corr[i, j]) > 0.9
    }
    cov_data = cov
    # a MAP on a bound of a capacity comes back through exp(ln x) one rounding step outside
    # it (C_env 147.30000000000004 vs 147.3 on the EnergyPlus twin house), and the engine
    # evaluates only strictly inside its bounds: keep the physical values inside
    map_values = values(z)
    for n in phys:
        lo_n, _, hi_n, _ = model.estimated[n]
        pad = 1e-9 * (hi_n - lo_n)
        map_values[n] = float(min(max(map_values[n], lo_n + pad), hi_n - pad))
    if heat_rel_std > 0:
        cov = cov + np.log1p(heat_rel_std**2) * np.ones_like(cov)
    return Correction(
        factors={g: float(np.exp(z[i])) for i, g in enumerate(groups)},
        names=names,
        z_map=z,
        cov_z=cov,
        cov_data=cov_data,
        z_lower=lo,
        z_upper=hi,
        prior_std=prior,
        posterior_std=post,
        separated={g: bool(post[g] < SEPARATED_RATIO * prior[g]) for g in groups},
        log_posterior=float(-res.fun),
        map_values=map_values,
        correlation=pairs,
        h_est_correlation={} if i_h is None else {
            g: float(corr[i, i_h]) for i, g in enumerate(groups)},
        labels={g: group_label(g, model) for g in groups},
        prior_mean={g: float(m) for g, m in zip(groups, m_groups, strict=True)},
        measured=measured_groups(groups, model),
    )  # fmt: skip


def _group_present(envelope, group: str) -> bool:
    if group == "k_env":
        return envelope.roof_area + envelope.walls_area + envelope.attic_area > 0 or (
            envelope.adjacent_area > 0
        )
    if group == "k_win":
        return envelope.windows_area > 0
    return envelope.floor_area > 0


def _hessian(f, x, h):
    """Central-difference Hessian of ``f`` at ``x`` with step ``h``."""
    n = len(x)
    out = np.empty((n, n))
    f0 = f(x)
    e = np.eye(n) * h
    fp = [f(x + e[i]) for i in range(n)]
    fm = [f(x - e[i]) for i in range(n)]
    for i in range(n):
        out[i, i] = (fp[i] - 2 * f0 + fm[i]) / h**2
        for j in range(i):
            v = f(x + e[i] + e[j]) - f(x + e[i] - e[j]) - f(x - e[i] + e[j]) + f(x - e[i] - e[j])
            out[i, j] = out[j, i] = v / (4 * h * h)
    return out


def draw_corrected(correction: Correction, n_draws: int, seed: int = 0):
    """Draws of z from the Gaussian posterior, truncated to the bounds (first = the MAP).

    Returns
    -------
    ndarray (n_draws + 1, len(names))
    """
    rng = np.random.default_rng(seed)
    out = truncated_gaussian_draws(
        rng, correction.z_map, correction.cov_z, correction.z_lower, correction.z_upper, n_draws
    )
    return np.vstack([correction.z_map[None, :], out])
