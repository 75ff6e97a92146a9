"""Posterior sampling to a stated Monte Carlo precision (used by :mod:`.posterior`).

Two samplers, both run until their kept draws are worth a set number of independent ones by
the integrated autocorrelation time (Sokal 1997, with emcee's estimator):

- :func:`truncated_gaussian_gibbs`: the exact posterior of the affine meta-model, a Gaussian
  in the log-parameters truncated to the prior box, by Gibbs sampling with each conditional
  drawn by the inverse of its truncated normal distribution (Geweke 1991; Robert 1995). Its
  draws are a continuous function of the posterior's mean and precision for fixed random
  numbers, so a round-off change of the identified heat moves the interval by round-off, not
  by a different Markov chain.
- :func:`ensemble_until_precise`: emcee's affine-invariant ensemble sampler (Foreman-Mackey et
  al. 2013) for any log-density (the meta-model with curvature).

:func:`thermocal.montecarlo.quantile_standard_error` (re-exported here) gives the Monte Carlo
standard error of an interval end.

References
----------
.. [1] Geweke J. (1991), Efficient simulation from the multivariate normal and Student-t
   distributions subject to linear constraints, Computer Science and Statistics 23, 571-578.
.. [2] Robert C.P. (1995), Simulation of truncated normal variables, Statistics and Computing
   5, 121-125.
.. [3] Sokal A. (1997), Monte Carlo methods in statistical mechanics: foundations and new
   algorithms, in Functional Integration, Springer, 131-192.
.. [4] Foreman-Mackey D., Hogg D.W., Lang D., Goodman J. (2013), emcee: the MCMC hammer,
   Publications of the Astronomical Society of the Pacific 125, 306-312.
.. [5] Vehtari A., Gelman A., Simpson D., Carpenter B., Buerkner P.-C. (2021),
   Rank-normalization, folding, and localization: an improved R-hat for assessing
   convergence of MCMC, Bayesian Analysis 16, 667-718.
"""

from __future__ import annotations

import numpy as np
from scipy import special

from thermocal.montecarlo import quantile_standard_error

__all__ = [
    "ensemble_until_precise",
    "quantile_standard_error",
    "truncated_gaussian_gibbs",
]

#: Effective (independent) posterior draws the sampler runs for [-]: the 5 % and 95 % quantiles
#: are then known to about +-0.35 percentage points of probability (Monte Carlo), so a 90 %
#: interval does not move by more than its stated Monte Carlo error between two runs.
POSTERIOR_EFFECTIVE_DRAWS = 4000
#: Smallest ensemble of walkers [-] (more walkers per step amortise the per-step overhead).
POSTERIOR_WALKERS = 128
#: At most this many times the requested steps are run while the effective draws fall short
#: (the shortfall is then reported) [-].
POSTERIOR_MAX_STEP_FACTOR = 8
#: Parallel Gibbs chains of the truncated Gaussian [-].
GIBBS_CHAINS = 512
#: Fewest Gibbs sweeps [-] (the chains are parallel: 512 x 100 kept draws at the least).
GIBBS_SWEEPS = 200
#: The kept part of a chain must be this many autocorrelation times long before its estimate
#: of the autocorrelation time (and so the effective draws) is trusted [-].
CHAIN_LENGTH_IN_TAU = 20


def ensemble_until_precise(
    log_probability, start: np.ndarray, steps: int, seed: int, effective_draws: int
) -> tuple[np.ndarray, float, float, float]:
    """Run emcee's ensemble sampler until its kept draws are worth ``effective_draws``
    independent ones.

    Parameters
    ----------
    log_probability : callable
        Vectorised log-density of ``z`` (shape (k, d)) [-].
    start : ndarray (walkers, d)
        Initial walkers [-].
    steps : int
        Fewest steps per walker [-]; the first half of all steps is burn-in.
    seed : int
        Seed of the sampler [-].
    effective_draws : int
        Wanted effective draws [-].

    Returns
    -------
    chain : ndarray (draws, d)
        Kept draws, walkers flattened [-].
    effective : float
        Their effective number: kept draws over the largest integrated autocorrelation time
        of the parameters [-].
    tau : float
        That autocorrelation time [steps].
    acceptance : float
        Mean acceptance fraction [-].
    """
    import emcee

    walkers, d = start.shape
    sampler = emcee.EnsembleSampler(walkers, d, log_probability, vectorize=True)
    sampler.random_state = np.random.RandomState(int(seed)).get_state()
    state = sampler.run_mcmc(start, int(steps), progress=False)
    most = POSTERIOR_MAX_STEP_FACTOR * int(steps)
    while True:
        total = sampler.iteration
        kept = sampler.get_chain(discard=total // 2)
        tau = _autocorrelation_time(kept)
        effective = walkers * kept.shape[0] / tau
        trusted = kept.shape[0] >= CHAIN_LENGTH_IN_TAU * tau
        if (effective >= effective_draws and trusted) or total >= most:
            break
        wanted = _steps_wanted(effective_draws, walkers, tau)
        state = sampler.run_mcmc(state, int(min(max(wanted - total, steps // 4), most - total)),
                                 progress=False)  # fmt: skip
    chain = kept.reshape(-1, d)
    return chain, float(effective), float(tau), float(np.mean(sampler.acceptance_fraction))


def _steps_wanted(effective_draws: int, chains: int, tau: float) -> int:
    """Total steps whose kept half gives ``effective_draws`` over ``chains`` parallel chains
    at the autocorrelation time ``tau`` [steps], and is long enough to trust it, with 10 %
    to spare [-]."""
    per_chain = max(effective_draws / chains, CHAIN_LENGTH_IN_TAU)
    return int(np.ceil(2.0 * per_chain * tau * 1.1))


def _autocorrelation_time(kept: np.ndarray) -> float:
    """Largest integrated autocorrelation time of the parameters [steps] of an ensemble chain
    (steps, walkers, d), by emcee's estimator with Sokal's automatic window, at least 1."""
    import emcee

    tau = np.array(
        [emcee.autocorr.integrated_time(kept[:, :, [j]], tol=0)[0] for j in range(kept.shape[2])]
    )
    tau = tau[np.isfinite(tau)]
    return float(max(tau.max(), 1.0)) if tau.size else 1.0


def truncated_gaussian_gibbs(
    precision: np.ndarray,
    linear: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    start: np.ndarray,
    *,
    sweeps: int,
    seed: int,
    effective_draws: int,
    chains: int = GIBBS_CHAINS,
    conductance: np.ndarray | None = None,
) -> tuple[np.ndarray, float, float, float]:
    """Draws of ``p(z) ~ exp(-z^T Q z / 2 + b^T z - 2 sum_c log(1 - z_c))`` on the box
    ``lower <= z <= upper``.

    Parallel Gibbs chains (Geweke 1991); each sweep draws every coordinate from its
    conditional, a normal of precision ``Q_jj`` and mean ``(b_j - sum_k!=j Q_jk z_k) / Q_jj``
    truncated to the box (an exponential on the interval when ``Q_jj`` is zero), by its
    inverse distribution function. The coordinates ``c`` flagged in ``conductance`` (a
    resistance uniform in ``R`` in its conductance coordinate, ``(1 - z)^-2``) carry that factor
    in their conditional (:func:`_conditional_draw_convex`). The sweeps continue (up to
    ``POSTERIOR_MAX_STEP_FACTOR`` times ``sweeps``) until the kept half is worth
    ``effective_draws`` independent draws.

    Parameters
    ----------
    precision : ndarray (d, d)
        ``Q``, symmetric positive semi-definite [-].
    linear : ndarray (d,)
        ``b`` [-].
    lower, upper : ndarray (d,)
        The box [-].
    start : ndarray (d,)
        Where every chain starts (inside the box) [-].
    sweeps : int
        Fewest sweeps [-]; the first half of all sweeps is burn-in.
    seed : int
        Seed of the uniform numbers [-].
    effective_draws : int
        Wanted effective draws [-].
    chains : int
        Parallel chains [-].
    conductance : ndarray of bool (d,), optional
        The coordinates whose prior carries ``(1 - z)^-2`` (none by default); their ``upper``
        must be below 1.

    Returns
    -------
    chain : ndarray (draws, d)
        Kept draws [-].
    effective : float
        Their effective number [-].
    tau : float
        Largest integrated autocorrelation time [sweeps].
    acceptance : float
        1 (every Gibbs draw is accepted) [-].
    """
    Q = np.asarray(precision, dtype=float)
    b = np.asarray(linear, dtype=float)
    lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    d = b.size
    convex = np.zeros(d, dtype=bool) if conductance is None else np.asarray(conductance, bool)
    knots = {j: _conductance_knots(lower[j], upper[j]) for j in np.flatnonzero(convex)}
    diagonal = np.diag(Q).copy()
    off = Q - np.diag(diagonal)
    rng = np.random.default_rng(int(seed))
    z = np.tile(np.clip(np.asarray(start, dtype=float), lower, upper), (int(chains), 1))
    history: list[np.ndarray] = []
    most = POSTERIOR_MAX_STEP_FACTOR * int(sweeps)
    target = int(sweeps)
    while True:
        while len(history) < target:
            u = rng.random((int(chains), d))
            for j in range(d):
                shift = b[j] - z @ off[j]
                if convex[j]:
                    z[:, j] = _conditional_draw_convex(shift, diagonal[j], knots[j], u[:, j])
                else:
                    z[:, j] = _conditional_draw(shift, diagonal[j], lower[j], upper[j], u[:, j])
            history.append(z.copy())
        kept = np.asarray(history[len(history) // 2 :])
        tau = _autocorrelation_time(kept)
        effective = int(chains) * kept.shape[0] / tau
        trusted = kept.shape[0] >= CHAIN_LENGTH_IN_TAU * tau
        if (effective >= effective_draws and trusted) or len(history) >= most:
            break
        wanted = _steps_wanted(effective_draws, int(chains), tau)
        target = min(max(wanted, len(history) + int(sweeps) // 4), most)
    return kept.reshape(-1, d), float(effective), float(tau), 1.0


def _conditional_draw(shift, q, lower, upper, u):
    """Inverse-distribution draws of ``exp(-q x^2 / 2 + shift x)`` on ``[lower, upper]``.

    Parameters
    ----------
    shift : ndarray (k,)
        Linear coefficient of each chain's conditional [-].
    q : float
        Conditional precision, >= 0 [-].
    lower, upper : float or ndarray (k,)
        Interval [-].
    u : ndarray (k,)
        Uniform numbers in [0, 1) [-].

    Returns
    -------
    ndarray (k,)
    """
    if q * float(np.max(np.maximum(lower * lower, upper * upper))) <= 1e-12:
        # the quadratic term varies by less than 1e-12 over the interval: the tilted uniform
        # (a Gaussian branch would put its mean shift / q astronomically far off)
        return _tilted_uniform_draw(np.asarray(shift, dtype=float), lower, upper, u)
    sd = 1.0 / np.sqrt(q)
    mean = shift / q
    a, b = (lower - mean) / sd, (upper - mean) / sd
    flip, lo, hi, log_pa, log_pb = _lower_tail(a, b)
    with np.errstate(divide="ignore"):
        # log(pa + u (pb - pa)), pa <= pb
        log_p = log_pb + np.log(u + (1.0 - u) * np.exp(log_pa - log_pb))
    x = special.ndtri_exp(log_p)
    x = np.clip(np.nan_to_num(x, nan=0.0, posinf=np.inf, neginf=-np.inf), lo, hi)
    x = np.where(flip, -x, x)
    return np.clip(mean + sd * x, lower, upper)


#: Pieces of the linear interpolation of a conductance coordinate's prior term
#: ``-2 log(1 - z)`` in its conditional draw [-]: knots equally spaced in ``log(1 - z)`` (in
#: the logarithm of ``R + f``), where the term is linear, so the interpolation's error in the
#: log-density is at most ``(delta / 2)^2``, ``delta`` the spacing: 0.0012 for a resistance
#: ranging over a factor of 9 (``log 9 / 32``; 0.0005 on a +-75 % box).
CONDUCTANCE_PIECES = 32


def _conductance_knots(lower: float, upper: float) -> np.ndarray:
    """Knots on ``[lower, upper]`` equally spaced in ``log(1 - z)`` [-] (``upper < 1``)."""
    if not upper < 1.0:
        raise ValueError(f"a conductance coordinate must stay below 1, got {upper}")
    fraction = np.linspace(0.0, 1.0, CONDUCTANCE_PIECES + 1)
    knots = 1.0 - (1.0 - lower) * ((1.0 - upper) / (1.0 - lower)) ** fraction
    knots[0], knots[-1] = lower, upper
    return knots


def _conditional_draw_convex(shift, q, knots, u):
    """Inverse-distribution draws of ``exp(-q x^2 / 2 + shift x) (1 - x)^-2`` on
    ``[knots[0], knots[-1]]``.

    ``-2 log(1 - x)`` is replaced by its linear interpolation on ``knots``
    (:func:`_conductance_knots`); on each piece the density is then a Gaussian (an exponential
    when ``q`` is nil) with the piece's slope added to ``shift``, whose mass is known in closed
    form: the piece is chosen by ``u`` against the pieces' cumulative masses and the draw made
    within it by its own inverse distribution function (:func:`_conditional_draw`) at ``u``'s
    position within the piece's share. Exact but for the interpolation (its error in the
    log-density is bounded in :data:`CONDUCTANCE_PIECES`) and, as the Gaussian draw, a
    continuous function of ``shift`` and ``q`` for a fixed ``u``.

    Parameters
    ----------
    shift : ndarray (k,)
        Linear coefficient of each chain's conditional [-].
    q : float
        Conditional precision, >= 0 [-].
    knots : ndarray (m + 1,)
        Increasing, below 1 [-].
    u : ndarray (k,)
        Uniform numbers in [0, 1) [-].

    Returns
    -------
    ndarray (k,)
    """
    shift = np.asarray(shift, dtype=float)
    lo, hi = knots[:-1], knots[1:]
    g_lo, g_hi = -2.0 * np.log1p(-lo), -2.0 * np.log1p(-hi)
    slope = (g_hi - g_lo) / (hi - lo)
    intercept = g_lo - slope * lo
    k = shift[:, None] + slope[None, :]  # (chains, pieces)
    # the quadratic term varying by less than 1e-6 over the box: exponentials on the pieces
    # (below it a Gaussian's log-mass, k^2 / 2q minus a tail of the same size, would lose
    # more than that to round-off)
    flat = q * max(knots[0] ** 2, knots[-1] ** 2) <= 1e-6
    if flat:
        log_mass = intercept + _log_exponential_mass(k, lo, hi)
    else:
        sd = 1.0 / np.sqrt(q)
        mean = k / q
        log_mass = intercept + 0.5 * q * mean * mean + _log_normal_mass(
            (lo - mean) / sd, (hi - mean) / sd
        )  # fmt: skip
    top = log_mass.max(axis=1, keepdims=True)
    share = np.exp(log_mass - top)
    cumulative = np.cumsum(share, axis=1)
    cumulative /= cumulative[:, -1:]
    piece = np.minimum((cumulative < u[:, None]).sum(axis=1), len(lo) - 1)
    rows = np.arange(len(u))
    before = np.where(piece > 0, cumulative[rows, piece - 1], 0.0)
    width = cumulative[rows, piece] - before
    local = np.clip((u - before) / np.where(width > 0, width, 1.0), 0.0, np.nextafter(1.0, 0.0))
    a, b = lo[piece], hi[piece]
    if flat:
        x = _tilted_uniform_draw(k[rows, piece], a, b, local)
    else:  # q over the threshold above, so _conditional_draw takes its Gaussian branch
        x = _conditional_draw(k[rows, piece], q, a, b, local)
    return np.clip(x, knots[0], knots[-1])


def _log_normal_mass(alpha, beta):
    """``log(Phi(beta) - Phi(alpha))`` for ``alpha < beta`` (elementwise), accurate in both
    tails [-]."""
    _, _, _, log_lo, log_hi = _lower_tail(alpha, beta)
    with np.errstate(divide="ignore"):
        return log_hi + np.log1p(-np.exp(np.minimum(log_lo - log_hi, 0.0)))


def _lower_tail(alpha, beta):
    """A standard normal interval ``[alpha, beta]`` moved into the lower tail: mirrored where
    ``alpha > 0`` (``flip``), its ends ``lo <= hi`` and their ``log Phi``; both ends may lie
    dozens of standard deviations out, where only the logarithm of the distribution function
    keeps its precision [-]."""
    flip = alpha > 0
    lo, hi = np.where(flip, -beta, alpha), np.where(flip, -alpha, beta)
    return flip, lo, hi, special.log_ndtr(lo), special.log_ndtr(hi)


def _log_exponential_mass(k, lo, hi):
    """``log of the integral of exp(k x)`` over ``[lo, hi]`` (elementwise) [-]."""
    w = hi - lo
    kw = k * w
    small = np.abs(kw) < 1e-8
    safe = np.where(small, 1.0, k)
    with np.errstate(invalid="ignore", divide="ignore"):  # the branches np.where leaves out
        rising = k * hi + np.log(-np.expm1(-kw) / safe)
        falling = k * lo + np.log(np.expm1(kw) / safe)
    return np.where(small, k * lo + np.log(w), np.where(kw > 0, rising, falling))


def _tilted_uniform_draw(shift, lower, upper, u):
    """Inverse-distribution draws of ``exp(shift x)`` on ``[lower, upper]`` (a conditional
    without curvature: the parameter's effect is nil, only the prior's tilt is left).

    Parameters
    ----------
    shift : ndarray (k,)
        Exponent's slope [-].
    lower, upper : float
        Interval [-].
    u : ndarray (k,)
        Uniform numbers in [0, 1) [-].

    Returns
    -------
    ndarray (k,)
    """
    width = upper - lower
    t = shift * width
    x = u * width  # |t| tiny: uniform
    rising, falling = t > 1e-8, t < -1e-8
    # F^-1(u) = log(1 + u (e^t - 1)) / shift, written without overflow on either side
    x = np.where(
        rising, width + np.log(u + (1.0 - u) * np.exp(-np.where(rising, t, 0.0))) / np.where(
            rising, shift, 1.0), x)  # fmt: skip
    x = np.where(
        falling, np.log1p(u * np.expm1(np.where(falling, t, 0.0))) / np.where(
            falling, shift, 1.0), x)  # fmt: skip
    return np.clip(lower + x, lower, upper)
