"""Maximum-likelihood estimation, simulation and filtering of :class:`RCModel` objects.

The optimiser works on the unconstrained vector ``theta`` of the free parameters (log, negated
log or bounded-logit transforms of the declared-unit values, see :class:`Parameter`). The
gradient is a central difference computed inside the compiled kernel; standard errors come from a
central-difference Hessian of the log-likelihood in ``theta`` mapped to the declared units by the
delta method.

References
----------
.. [1] N. R. Kristensen, H. Madsen, S. B. Jorgensen, "Parameter estimation in stochastic grey-box
   models", Automatica 40(2), 225-237, 2004.
.. [2] P. Bacher, H. Madsen, "Identifying suitable models for the heat dynamics of buildings",
   Energy and Buildings 43(7), 1511-1522, 2011.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from contextlib import contextmanager

import numpy as np
from scipy import optimize

from thermocal.errors import ThermocalInputError
from thermocal.statespace import kernels
from thermocal.statespace.convergence import (  # noqa: F401 - re-exported
    AGREEMENT_TOLERANCE,
    BOUND_TOLERANCE,
    CONVERGENCE_GAIN,
    CORRELATION_LIMIT,
    one_blas_thread,
    start_agreement,
)
from thermocal.statespace.data import PreparedData, prepare_data
from thermocal.statespace.exchange import exchange_pairs, exchanged_values
from thermocal.statespace.kalman import (  # noqa: F401 - re-exported
    _hold_flag,
    _loglike_values,
    _periods,
    filter_arrays,
    nonfinite_culprit,
    rts_smoother,
    simulate,
    simulate_stochastic,
)
from thermocal.statespace.likelihood import (  # noqa: F401 - re-exported
    GRADIENT_STEP,
    THETA_SPAN,
    LikelihoodProblem,
)

#: The optimiser stops when the log-likelihood gained less than STALL_TOLERANCE over the last
#: STALL_WINDOW iterations (far below what matters for likelihood-ratio tests or standard errors).
STALL_TOLERANCE = 1e-3
STALL_WINDOW = 10
#: A noise standard deviation that ends below this fraction of its start value is taken as
#: collapsed (see :func:`_escape_vanishing_noise`).
COLLAPSE_FRACTION = 0.02


def _prepared(
    model, data, time_column, time_unit, source="data", input_gaps="error", max_gap=3
) -> PreparedData:
    if isinstance(data, PreparedData):
        return data
    return prepare_data(
        model,
        data,
        time_column=time_column,
        time_unit=time_unit,
        source=source,
        input_gaps=input_gaps,
        max_gap=max_gap,
    )


def loglike(model, data, params=None, *, hold="zoh", time_column=None, time_unit="s") -> float:
    """Log-likelihood [-] of the outputs in ``data`` at ``params`` [declared units]."""
    prep = _prepared(model, data, time_column, time_unit)
    return _loglike_values(model, model.values_si(params), prep, _hold_flag(hold))


def period_start_guesses(model, prep: PreparedData) -> list[dict[str, float]]:
    """For each period after the first: {state: first measured value of an output observing
    that state alone [C]}, start values of the period's initial means."""
    C = model.structure().C
    guesses = []
    for start in prep.segments:
        end = prep.Y.shape[0]
        guess: dict[str, float] = {}
        for r in range(C.shape[0]):
            nz = np.flatnonzero(C[r])
            if nz.size != 1 or C[r, nz[0]] != 1.0:
                continue
            col = prep.Y[start:end, r]
            finite = np.flatnonzero(np.isfinite(col))
            if finite.size:
                guess[model.state_names[nz[0]]] = float(col[finite[0]])
        guesses.append(guess)
    return guesses


#: A bounded positive range wider than this ratio (upper / lower) is sampled on a log scale.
LOG_RANGE_RATIO = 100.0


def _start_points(model, n_starts: int, seed: int | None) -> list[np.ndarray]:
    """The declared values, then ``n_starts - 1`` random starts in theta.

    Bounded ranges are sampled uniformly over their middle 98 %, except positive ranges over
    more than two decades (capacities, resistances declared in [1e-4, 50]): uniform sampling
    would put nearly every start at the top of the range, orders of magnitude from the declared
    value; they are sampled like one-sided bounds, a factor ``e`` (one standard deviation in
    log) either way of the declared value, kept inside the middle 98 % of the log range.
    """
    theta0 = model.theta0()
    starts = [theta0]
    rng = np.random.default_rng(seed)
    free = [model.parameters[n] for n in model.free_parameter_names]
    for _ in range(max(n_starts, 1) - 1):
        theta = theta0.copy()
        for i, p in enumerate(free):
            if p.transform == kernels.TRANSFORM_LOGIT:
                if p.lower > 0 and p.upper > LOG_RANGE_RATIO * p.lower:
                    lo, hi = math.log(p.lower), math.log(p.upper)
                    margin = 0.01 * (hi - lo)
                    log_x = math.log(p.value) + rng.normal(0.0, 1.0)
                    theta[i] = p.to_unconstrained(
                        math.exp(min(max(log_x, lo + margin), hi - margin))
                    )
                    continue
                # uniform over the middle 98 % of the bounded range
                u = rng.uniform(0.01, 0.99)
                theta[i] = math.log(u) - math.log1p(-u)
            elif p.transform in (kernels.TRANSFORM_LOG, kernels.TRANSFORM_NEGLOG):
                theta[i] = theta0[i] + rng.normal(0.0, 1.0)  # a factor e either way
            else:
                theta[i] = theta0[i] + rng.normal(0.0, max(1.0, 0.2 * abs(theta0[i])))
        starts.append(theta)
    return starts


def _diagonal_metric(problem: LikelihoodProblem, theta: np.ndarray, h: float = 1e-2) -> np.ndarray:
    """Initial inverse-Hessian guess: inverse of the diagonal curvature of the objective.

    With the identity as initial metric, the first BFGS step is the raw gradient, which for
    capacities and conductances in log space can jump by factors of e^100 into degenerate regions.
    """
    theta = problem.clip(theta)
    k = theta.size
    points = [theta]
    for i in range(k):
        e = np.zeros(k)
        e[i] = h
        points += [theta + e, theta - e]
    values = -problem.target_many(np.array(points)) / problem.scale
    f0 = values[0]
    curv = np.empty(k)
    for i in range(k):
        fp, fm = values[1 + 2 * i], values[2 + 2 * i]
        curv[i] = (fp - 2.0 * f0 + fm) / h**2
    curv = np.abs(curv)
    floor = max(1e-2 * curv.max(), 1e-8) if np.all(np.isfinite(curv)) else 1.0
    curv = np.where(np.isfinite(curv), np.maximum(curv, floor), 1.0 / floor)
    return np.diag(1.0 / curv)


def _usable_metric(metric) -> np.ndarray | None:
    """A symmetric, well-conditioned positive definite copy of ``metric``, or None."""
    if not isinstance(metric, np.ndarray) or not np.all(np.isfinite(metric)):
        return None
    metric = 0.5 * (metric + metric.T)
    eig = np.linalg.eigvalsh(metric)
    if eig[0] <= 1e-12 * eig[-1]:
        return None
    return metric


def _minimize(
    problem: LikelihoodProblem,
    theta_start,
    method: str,
    maxiter: int,
    metric=None,
    stall_tolerance: float = STALL_TOLERANCE,
):
    options = {"maxiter": maxiter}
    metric = _usable_metric(metric)
    if method == "L-BFGS-B":
        options |= {"ftol": 1e-15, "gtol": 1e-9}
    elif method == "BFGS":
        if metric is None:
            metric = _diagonal_metric(problem, np.asarray(theta_start))
        options |= {"gtol": 1e-7, "hess_inv0": metric}
    history: list[float] = []

    def stall(intermediate_result):
        # stop when the log-likelihood gained less than stall_tolerance over STALL_WINDOW
        # iterations: typically a noise std creeping towards zero with negligible gain
        history.append(-float(intermediate_result.fun) * problem.scale)
        if len(history) > STALL_WINDOW and (
            history[-1] - history[-1 - STALL_WINDOW] < stall_tolerance
        ):
            raise StopIteration

    res = optimize.minimize(
        problem.objective, theta_start, jac=True, method=method, options=options, callback=stall
    )
    problem.iterations += int(getattr(res, "nit", 0))
    if not res.success and len(history) > STALL_WINDOW and "StopIteration" in str(res.message):
        res.success = True
        res.message = (
            f"converged: log-likelihood gain below {stall_tolerance:g} over {STALL_WINDOW} "
            "iterations"
        )
    return res


def _escape_vanishing_noise(
    model, problem: LikelihoodProblem, best, method: str, maxiter: int, stall_tolerance: float
):
    """Restart from the optimum with collapsed noise standard deviations reset.

    The likelihood of a stochastic state-space model often has a local maximum where a noise
    standard deviation (measurement or diffusion) runs to zero; a gradient method started on the
    wrong side stays there. When a noise parameter ends below COLLAPSE_FRACTION of its start
    value, it is reset to the start value (the other parameters kept at the optimum) and the fit
    restarted; the better of the two optima is kept.
    """
    roles = model.structure().roles
    names = model.free_parameter_names
    theta0 = model.theta0()
    theta = problem.clip(best.x)
    collapsed = []
    for i, name in enumerate(names):
        p = model.parameters[name]
        if roles.get(name, set()) & {"noise", "measurement noise"}:
            value = p.from_unconstrained(theta[i])
            if value - p.lower < COLLAPSE_FRACTION * (p.value - p.lower):
                collapsed.append(i)
    if not collapsed:
        return best
    theta[collapsed] = theta0[collapsed]
    metric = None
    hess_inv = getattr(best, "hess_inv", None)
    if method == "BFGS" and isinstance(hess_inv, np.ndarray):
        # keep the metric learnt by the first run, re-initialised along the collapsed directions
        diag = np.diag(_diagonal_metric(problem, theta))
        metric = hess_inv.copy()
        metric[collapsed, :] = 0.0
        metric[:, collapsed] = 0.0
        metric[collapsed, collapsed] = diag[collapsed]
    res = _minimize(problem, theta, method, maxiter, metric, stall_tolerance)
    return res if res.fun < best.fun else best


def _polished_start(problem: LikelihoodProblem, theta_start, method, maxiter, stall_tolerance):
    """One optimiser start taken to its end: the same treatment for every start.

    BFGS from ``theta_start``; when it stops on a failed line search ("precision loss", often
    before the optimum) it is restarted once from there with the metric it learnt; then the
    vanishing-noise escape (:func:`_escape_vanishing_noise`). Returns the scipy result (``fun``
    the negative log-likelihood per observation at the end) or None when the likelihood is not
    finite at the start.
    """
    f0, _ = problem.objective(theta_start)
    if f0 >= 1e19:
        return None
    res = _minimize(problem, theta_start, method, maxiter, None, stall_tolerance)
    if not res.success:
        metric = res.hess_inv if isinstance(getattr(res, "hess_inv", None), np.ndarray) else None
        again = _minimize(problem, res.x, method, maxiter, metric, stall_tolerance)
        if again.fun <= res.fun:
            res = again
    res = _escape_vanishing_noise(problem.model, problem, res, method, maxiter, stall_tolerance)
    res.nit_total = problem.iterations
    return res


# the problem of the current multi-start fit, in each worker process of the pool
_WORKER_PROBLEM: LikelihoodProblem | None = None


def _init_worker(problem: LikelihoodProblem) -> None:
    global _WORKER_PROBLEM
    _WORKER_PROBLEM = problem
    one_blas_thread()  # for the worker's lifetime: the pool is the parallelism


def _worker_start(args):
    theta_start, method, maxiter, stall_tolerance = args
    problem = _WORKER_PROBLEM
    problem.iterations = 0
    return _polished_start(problem, theta_start, method, maxiter, stall_tolerance)


def _shared_worker_start(args):
    """:func:`_worker_start` in a worker of the shared pool: the problem comes with the task
    (about 0.1 MB pickled for a four-state model on 1,691 samples)."""
    problem, theta_start, method, maxiter, stall_tolerance = args
    problem.iterations = 0
    return _polished_start(problem, theta_start, method, maxiter, stall_tolerance)


# the pool of :func:`shared_pool` while its block runs
_SHARED_POOL = None


def _init_shared_worker() -> None:
    global _SHARED_POOL
    _SHARED_POOL = None  # a worker runs its tasks itself
    one_blas_thread()  # for the worker's lifetime: the pool is the parallelism


def load_kernels(problem: LikelihoodProblem) -> None:
    """Call the compiled functions an optimiser start of ``problem`` uses (the likelihood with
    its gradient, the batched likelihoods of the initial metric) once: numba loads them from
    its cache on the first call, and processes forked afterwards inherit them."""
    if problem.model.n_free == 0:
        return
    theta = problem.clip(problem.model.theta0())
    problem.objective(theta)
    problem.loglike_many(theta[None, :])


@contextmanager
def shared_pool(problems=(), n_jobs: int | None = None):
    """A process pool for the optimiser starts of every fit inside the block.

    Without it each multi-start fit forks a pool per batch of starts (about 0.1 s each, ~14
    times in `thermocal select`, and each pool's workers load the compiled kernels they need
    again); inside it the starts of all fits go to one pool forked once, each task with its
    problem. The starts are computed as before (the same problem, one BLAS thread per worker),
    so the results are the same bit for bit. A block inside another uses the outer pool.

    Parameters
    ----------
    problems : iterable of LikelihoodProblem
        Problems whose compiled kernels are loaded here before the workers are forked
        (:func:`load_kernels`), so that no worker loads them from numba's cache itself.
    n_jobs : int, optional
        Worker processes (default: the number of CPUs); with one, no pool (starts run in
        this process, as without the block).

    Yields
    ------
    ProcessPoolExecutor or None
    """
    import multiprocessing as mp
    import os
    from concurrent.futures import ProcessPoolExecutor

    global _SHARED_POOL
    n_jobs = int(n_jobs or os.cpu_count() or 1)
    if _SHARED_POOL is not None or n_jobs < 2 or "fork" not in mp.get_all_start_methods():
        yield _SHARED_POOL
        return
    for problem in problems:
        load_kernels(problem)
    pool = ProcessPoolExecutor(n_jobs, mp_context=mp.get_context("fork"),
                               initializer=_init_shared_worker)  # fmt: skip
    _SHARED_POOL = pool
    try:
        yield pool
    finally:
        _SHARED_POOL = None
        pool.shutdown()


#: Seed of the random starts when none is given.
DEFAULT_SEED = 2011
#: Fewest optimiser starts used by default (the agreement criterion needs at least two).
MIN_DEFAULT_STARTS = 3
#: Default starts per free parameter (above :data:`MIN_DEFAULT_STARTS`).
STARTS_PER_PARAMETER = 0.5


def default_n_starts(model) -> int:
    """Starts used when ``n_starts`` is not given: ``max(3, ceil(n_free / 2))``.

    The random starts add to the declared values and the energy-balance start (see
    :func:`_energy_balance_start`), so a model with ``k`` free parameters gets about ``k / 2 + 1``
    starts; the agreement of the best of them is part of the convergence criterion
    (:data:`AGREEMENT_TOLERANCE`).
    """
    return max(MIN_DEFAULT_STARTS, math.ceil(STARTS_PER_PARAMETER * model.n_free))


def _energy_balance_start(model, prep: PreparedData) -> np.ndarray | None:
    """A physically derived start: the declared values with every conductance, resistance and
    capacity scaled by one factor so that the steady state under the mean inputs matches the
    mean of the first output (time constants unchanged), and the initial means of observed
    states at their first measured value.

    The heat-driven part of a linear RC network's steady state scales as ``1/s`` when all
    conductances are multiplied by ``s``; ``s`` follows from the declared-value steady state
    ``y_ss = y_b + y_h`` (``y_b`` from the boundary temperatures, ``y_h`` from the heat inputs)
    and the measured mean ``y_m``: ``s = y_h / (y_m - y_b)``. Returns None when the model has no
    steady state, no heat input or when ``s`` is not a positive finite number.
    """
    try:
        A, B, C, _ = model.continuous_matrices()
        A_inv = np.linalg.inv(A)
    except (np.linalg.LinAlgError, ValueError, ZeroDivisionError):
        return None
    n_b = len(model.boundary_names)
    u = np.nanmean(prep.U, axis=0) if prep.U.size else np.zeros(B.shape[1])
    y = prep.Y[:, 0]
    if not (np.all(np.isfinite(u)) and np.isfinite(y).any() and np.all(np.isfinite(A_inv))):
        return None
    u_b = u.copy()
    u_b[n_b:] = 0.0
    y_b = float(C[0] @ (-A_inv @ (B @ u_b)))
    y_h = float(C[0] @ (-A_inv @ (B @ u))) - y_b
    y_m = float(np.nanmean(y))
    if not (abs(y_m - y_b) > 1e-9 and abs(y_h) > 1e-12):
        return None
    s = y_h / (y_m - y_b)
    if not (math.isfinite(s) and s > 0):
        return None
    roles = model.structure().roles
    values = {}
    for name in model.free_parameter_names:
        p, role = model.parameters[name], roles.get(name, set())
        if role == {"conductance"} or role == {"capacity"}:
            values[name] = p.value * s
        elif role == {"resistance"}:
            values[name] = p.value / s
    first = np.flatnonzero(np.isfinite(prep.Y).all(axis=1))
    if first.size:
        for r in range(C.shape[0]):
            nz = np.flatnonzero(C[r])
            if nz.size == 1 and C[r, nz[0]] == 1.0:
                state = model._states[model.state_names[nz[0]]]
                mean = state.get("initial_mean")
                if isinstance(mean, str) and mean in model.parameters:
                    values[mean] = float(prep.Y[first[0], r])
    if not values:
        return None
    return _warm_start_theta(model, values)


def _run_starts(problem, starts, method, maxiter, stall_tolerance, n_jobs, progress):
    """Polish every start (in a process pool when ``n_jobs > 1``); results in start order."""
    import os

    n = len(starts)
    if n_jobs is None:
        n_jobs = min(n, os.cpu_count() or 1)
    n_jobs = max(1, min(int(n_jobs), n))
    if progress is None:
        import sys

        progress = n > 1 and sys.stderr.isatty()
    bar, task = None, None
    if progress and n > 1:
        from rich.progress import Progress

        bar = Progress(transient=True)
        bar.start()
        task = bar.add_task(f"{problem.model.name}: {n} optimiser starts", total=n)
    results: list = [None] * n
    iterations = 0
    try:
        if n_jobs == 1:
            for i, theta in enumerate(starts):
                before = problem.iterations
                results[i] = _polished_start(problem, theta, method, maxiter, stall_tolerance)
                iterations += problem.iterations - before
                if bar is not None:
                    bar.advance(task)
        elif _SHARED_POOL is not None:
            futures = {
                _SHARED_POOL.submit(
                    _shared_worker_start, (problem, theta, method, maxiter, stall_tolerance)
                ): i
                for i, theta in enumerate(starts)
            }
            iterations = _collect(futures, results, bar, task)
        else:
            import multiprocessing as mp
            from concurrent.futures import ProcessPoolExecutor

            ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else None)
            if ctx.get_start_method() == "fork":
                # the compiled kernels loaded here once, inherited by the forked workers
                # (otherwise each worker loads them from numba's cache on its first start)
                problem.objective(starts[0])
            with ProcessPoolExecutor(
                n_jobs, mp_context=ctx, initializer=_init_worker, initargs=(problem,)
            ) as pool:
                futures = {
                    pool.submit(_worker_start, (theta, method, maxiter, stall_tolerance)): i
                    for i, theta in enumerate(starts)
                }
                iterations = _collect(futures, results, bar, task)
    finally:
        if bar is not None:
            bar.stop()
    problem.iterations = iterations
    return results


def _collect(futures, results: list, bar=None, task=None) -> int:
    """Results of the start futures (future -> index) into ``results`` as they finish (the
    progress bar advanced); the optimiser iterations of all of them."""
    from concurrent.futures import as_completed

    iterations = 0
    for fut in as_completed(futures):
        res = fut.result()
        results[futures[fut]] = res
        if res is not None:
            iterations += int(getattr(res, "nit_total", 0))
        if bar is not None:
            bar.advance(task)
    return iterations


def prepared_problem(model, data, *, hold="zoh", time_column=None, time_unit="s",
                     input_gaps="error", max_gap=3) -> LikelihoodProblem:  # fmt: skip
    """The likelihood problem :func:`fit` optimises for ``model`` on ``data`` (same
    preparation, periods added when the data are split)."""
    prep = _prepared(model, data, time_column, time_unit, "data", input_gaps, max_gap)
    if prep.segments.size and len(model.period_initial_means) != prep.segments.size:
        model = model.with_periods(period_start_guesses(model, prep))
    return LikelihoodProblem(model, prep, _hold_flag(hold))


def _start_key(theta) -> bytes:
    """Key of an optimiser start: its exact start point."""
    return np.ascontiguousarray(np.asarray(theta, dtype=float)).tobytes()


def _reusable_ends(reuse, model, prep: PreparedData, hold: str, method: str, maxiter: int,
                   stall_tolerance: float) -> dict:  # fmt: skip
    """The polished ends of the starts of an earlier fit that a new fit may take over: only
    from a fit of the same model (declared values and bounds) on the same observations with
    the same optimiser settings, where a start from the same point ends at the same point."""
    ends = getattr(reuse, "_start_ends", None)
    if not ends:
        return {}
    same = (
        reuse.model.to_dict() == model.to_dict()
        and reuse.nobs == prep.nobs
        and reuse.hold == hold
        and getattr(reuse, "_optimiser", None) == (method, maxiter, stall_tolerance)
        and np.array_equal(reuse.data.Y, prep.Y, equal_nan=True)
        and np.array_equal(reuse.data.U, prep.U, equal_nan=True)
        and np.array_equal(reuse.data.dts, prep.dts)
    )
    return dict(ends) if same else {}


def _run_new_starts(problem, starts, method, maxiter, stall_tolerance, n_jobs, progress, ends):
    """:func:`_run_starts` for the starts whose end is not in ``ends`` (start key -> result,
    updated); results in start order."""
    keys = [_start_key(t) for t in starts]
    todo = [i for i, k in enumerate(keys) if k not in ends]
    if todo:
        done = _run_starts(problem, [starts[i] for i in todo], method, maxiter, stall_tolerance,
                           n_jobs, progress)  # fmt: skip
        for i, r in zip(todo, done, strict=True):
            ends[keys[i]] = r
    else:
        problem.iterations = 0
    return [ends[k] for k in keys]


#: Ends of the best group exchanged per round (two: the fewest that can agree).
EXCHANGE_GROUP = 2
#: Rounds of state-exchange starts at most (a round follows only when the previous one found
#: a better optimum).
EXCHANGE_ROUNDS = 3


def _exchange_thetas(problem, results, start_loglikes, pairs, origin) -> tuple[list, list]:
    """State-exchange starts (see :mod:`~thermocal.statespace.exchange`) from the ends of the
    best :data:`EXCHANGE_GROUP` starts within :data:`AGREEMENT_TOLERANCE` of the best, one per
    exchangeable pair of states and end, except the pair that produced the end (``origin[i]``:
    index of that pair, -1 for the other starts; swapping back returns to where it came from).

    Returns
    -------
    (list of ndarray, list of int)
        The start points and the index of their pair.
    """
    model = problem.model
    free = model.free_parameter_names
    ll = np.array([v if math.isfinite(v) else -np.inf for v in start_loglikes])
    order = [i for i in np.argsort(-ll, kind="stable") if ll[i] >= ll.max() - AGREEMENT_TOLERANCE]
    thetas, pair_of = [], []
    for i in order[:EXCHANGE_GROUP]:
        x = problem.clip(results[i].x)
        values = {n: model.parameters[n].from_unconstrained(x[k]) for k, n in enumerate(free)}
        for j, swaps in enumerate(pairs):
            if origin[i] == j:
                continue
            moved = exchanged_values(values, swaps)
            thetas.append(problem.clip(_warm_start_theta(model, moved)))
            pair_of.append(j)
    return thetas, pair_of


def _exchange_rounds(problem, results, start_loglikes, method, maxiter, stall_tolerance, n_jobs,
                     progress, ends) -> list:  # fmt: skip
    """Run state-exchange starts from the best ends until a round finds no better optimum
    (at most :data:`EXCHANGE_ROUNDS`); their results, in order. ``problem.iterations`` counts
    the iterations of all starts so far."""
    pairs = exchange_pairs(problem.model)
    if not pairs or not np.any(np.isfinite(start_loglikes)):
        return []
    results, start_loglikes = list(results), list(start_loglikes)
    origin = [-1] * len(results)
    added: list = []
    for _ in range(EXCHANGE_ROUNDS):
        best = float(np.nanmax(start_loglikes))
        thetas, pair_of = _exchange_thetas(problem, results, start_loglikes, pairs, origin)
        if not thetas:
            break
        iterations = problem.iterations
        more = _run_new_starts(problem, thetas, method, maxiter, stall_tolerance, n_jobs,
                               progress, ends)  # fmt: skip
        problem.iterations += iterations
        lls = [float("nan") if r is None else -float(r.fun) * problem.scale for r in more]
        added += more
        results += more
        start_loglikes += lls
        origin += pair_of
        if not np.any(np.asarray(lls) > best + AGREEMENT_TOLERANCE):
            break
    return added


def _warm_start_theta(model, warm_start) -> np.ndarray:
    """Start point in theta from the estimates of another fit (or a mapping of values).

    Parameters the two share take the given value; a value on or beyond a bound of this model
    (a noise fixed at 0 in a restricted model, free with lower bound 0 here) is moved just inside
    it (1e-8 of the way to the declared value), so the start reproduces the other model's
    likelihood to within a negligible amount and the optimum here can only be higher.
    """
    values = warm_start.params if hasattr(warm_start, "params") else warm_start
    theta = model.theta0()
    for i, name in enumerate(model.free_parameter_names):
        if name not in values:
            continue
        p = model.parameters[name]
        v = float(values[name])
        if not math.isfinite(v):
            continue
        inside = 1e-8
        if v <= p.lower:
            v = p.lower + inside * (p.value - p.lower)
        elif v >= p.upper:
            v = p.upper - inside * (p.upper - p.value)
        elif p.transform == kernels.TRANSFORM_LOGIT:
            span = p.upper - p.lower
            v = min(max(v, p.lower + 1e-12 * span), p.upper - 1e-12 * span)
        theta[i] = p.to_unconstrained(v)
    return theta


def fit(
    model,
    data,
    *,
    hold: str = "zoh",
    n_starts: int | None = None,
    seed: int | None = None,
    time_column: str | None = None,
    time_unit: str = "s",
    method: str = "BFGS",
    maxiter: int = 2000,
    source: str = "data",
    compute_hessian: bool = True,
    stall_tolerance: float = STALL_TOLERANCE,
    warm_start=None,
    n_jobs: int | None = None,
    progress: bool | None = None,
    input_gaps: str = "error",
    max_gap: int = 3,
    reuse=None,
):
    """Estimate the free parameters of ``model`` by maximum likelihood.

    Parameters
    ----------
    model : RCModel
    data : DataFrame
        Inputs and outputs with a DatetimeIndex, a numeric index in ``time_unit`` or a
        ``time_column``.
    hold : {"zoh", "foh"}
        Input interpolation between samples: zero-order hold (``u[k]`` over ``[t_k, t_k+1)``) or
        first-order hold (linear from ``u[k]`` to ``u[k+1]``).
    n_starts : int, optional
        Number of optimiser starts: the declared values first, then random starts (uniform in
        bounded ranges, a factor ``e`` either way of the declared value for one-sided bounds and
        positive ranges over more than two decades). Every start is polished the same way
        (restart after a failed line search, vanishing-noise escape) and the best polished end
        point wins. With two starts or more, an extra start is derived from the data (every
        conductance and capacity scaled by one factor so that the steady state under the mean
        inputs matches the mean output, see :func:`_energy_balance_start`). Default:
        :func:`default_n_starts` (``max(3, ceil(n_free / 2))``) and, when the best end is reached
        by one start only, as many more random starts. With two starts or more, models with
        two hidden states that can exchange roles
        (:func:`thermocal.statespace.exchange.exchange_pairs`) get state-exchange starts from
        the two best ends, in rounds while they find a better optimum (random starts can agree
        on the poorer of two such optima). The fit counts as converged only when at least two
        starts reach the best log-likelihood (within :data:`AGREEMENT_TOLERANCE`), besides
        the Newton-step criterion at the end point (``results.agreement``).
    seed : int, optional
        Seed of the random starts (default :data:`DEFAULT_SEED`: the same model and data give
        the same fit; the convergence verdict depends on the agreement of the starts).
    time_column, time_unit : str
        See :func:`thermocal.statespace.data.time_axis`.
    method : str
        ``scipy.optimize.minimize`` method using the gradient (``BFGS``, ``L-BFGS-B``, ...).
    maxiter : int
        Iteration limit per start.
    source : str
        Name of the data, for error messages.
    compute_hessian : bool
        Compute standard errors (skip for speed when only the optimum is needed).
    stall_tolerance : float
        The optimiser stops when the log-likelihood gained less than this over the last
        ``STALL_WINDOW`` (10) iterations. The default 1e-3 can stop up to about 0.02 short of
        the optimum when the maximum lies on a flat ridge (a parameter running to a bound, a
        pair correlated at 0.999); 1e-5 gets within about 1e-3 at two to three times the
        iterations, e.g. to compare optima with other tools.
    warm_start : FitResults or mapping, optional
        An extra start (after the declared values) at the estimates of another fit, typically
        a nested (restricted) model: shared parameters take its values, values on a bound here
        are moved just inside. When it is a ``FitResults`` of a model with fewer free
        parameters on the same observations, an optimum below its log-likelihood is flagged.
    n_jobs : int, optional
        Processes for the starts (default: one per start up to the number of CPUs).
    progress : bool, optional
        Show a progress bar over the starts (default: when more than one start and standard
        error is a terminal).
    input_gaps, max_gap :
        Missing input values: ``"error"``, ``"interpolate"`` gaps of at most ``max_gap``
        samples, or ``"split"``: interpolate short gaps and split the likelihood at longer ones
        (and at jumps of the time axis) into periods with their own initial states; the
        results then belong to ``model.with_periods(...)`` (parameters ``Ti0_p2``, ...). See
        :func:`thermocal.statespace.data.prepare_data`; noted in the results.
    reuse : FitResults, optional
        An earlier fit of the same model on the same data (e.g. before a new ``warm_start``
        was known): its starts from the same points are not run again; their polished ends
        are taken over (the same start on the same problem ends at the same point, so the
        results are those of a full refit). Ignored unless model, observations, hold and
        optimiser settings are the same.

    Returns
    -------
    FitResults
    """
    from thermocal.statespace.results import FitResults

    t_start = time.perf_counter()
    foh = _hold_flag(hold)
    prep = _prepared(model, data, time_column, time_unit, source, input_gaps, max_gap)
    if prep.segments.size and len(model.period_initial_means) != prep.segments.size:
        model = model.with_periods(period_start_guesses(model, prep))
    if model.n_free == 0:
        raise ThermocalInputError(
            f"model '{model.name}' has no free parameter to estimate; set 'fixed: false' on some"
        )
    from thermocal.statespace.checks import identifiability_check

    identifiability_check(model, prep, source)
    if seed is None:  # reproducible by default: the same data and model give the same fit
        seed = DEFAULT_SEED
    adaptive = n_starts is None
    if n_starts is None:
        n_starts = default_n_starts(model)
    problem = LikelihoodProblem(model, prep, foh)
    starts = _start_points(model, n_starts, seed)
    if n_starts > 1:
        physical = _energy_balance_start(model, prep)
        if physical is not None:
            starts.insert(1, problem.clip(physical))
    if warm_start is not None:
        starts.insert(1, problem.clip(_warm_start_theta(model, warm_start)))
    ends = _reusable_ends(reuse, model, prep, hold, method, maxiter, stall_tolerance)
    results = _run_new_starts(problem, starts, method, maxiter, stall_tolerance, n_jobs, progress,
                              ends)  # fmt: skip
    start_loglikes = [float("nan") if r is None else -float(r.fun) * problem.scale for r in results]
    if adaptive and n_starts > 1 and start_agreement(start_loglikes)["n_best"] < 2:
        # the best optimum was reached once: one more batch of random starts (default starts
        # only; an explicit n_starts is respected) before judging agreement
        extra_seed = None if seed is None else int(seed) + 7919
        extra = _start_points(model, n_starts + 1, extra_seed)[1:]
        iterations = problem.iterations
        more = _run_new_starts(problem, extra, method, maxiter, stall_tolerance, n_jobs,
                               progress, ends)  # fmt: skip
        problem.iterations += iterations
        results += more
        start_loglikes += [float("nan") if r is None else -float(r.fun) * problem.scale
                           for r in more]  # fmt: skip
    if n_starts > 1:
        more = _exchange_rounds(problem, results, start_loglikes, method, maxiter,
                                stall_tolerance, n_jobs, progress, ends)  # fmt: skip
        results += more
        start_loglikes += [float("nan") if r is None else -float(r.fun) * problem.scale
                           for r in more]  # fmt: skip
    finished = [r for r in results if r is not None]
    if not finished:
        raise ThermocalInputError(
            f"model '{model.name}': the likelihood is not finite at any start: "
            f"{nonfinite_culprit(model, prep, foh)}"
        )
    best = min(finished, key=lambda r: r.fun)
    theta = problem.clip(best.x)
    ll = problem.loglike(theta)
    _, grad = problem.objective(theta)
    grad = grad * problem.scale  # gradient of the negative log-likelihood in theta
    grad_norm = float(np.max(np.abs(grad))) if grad.size else 0.0
    hessian = problem.hessian(theta) if compute_hessian else None
    nested = None
    if warm_start is not None and hasattr(warm_start, "loglike") and hasattr(warm_start, "nobs"):
        if warm_start.nobs == prep.nobs and warm_start.n_free < model.n_free:
            nested = warm_start
    out = FitResults(
        model=model,
        theta=theta,
        loglike=ll,
        hessian=hessian,
        nobs=prep.nobs,
        converged=bool(best.success) or grad_norm < 1e-3,
        message=str(best.message),
        n_iterations=problem.iterations,
        gradient_norm=grad_norm,
        start_loglikes=start_loglikes,
        hold=hold,
        data=prep,
        fit_seconds=time.perf_counter() - t_start,
        gradient=grad,
        nested=nested,
        logprior=problem.logprior(theta)[0] if problem.priors else None,
        agreement=start_agreement(start_loglikes),
        fitter=fit,
    )
    # the polished end of every start, for a later fit of the same problem (``reuse``)
    out._start_ends = ends
    out._optimiser = (method, maxiter, stall_tolerance)
    return out


def evaluate(
    model,
    data,
    params: Mapping[str, float] | None = None,
    *,
    hold: str = "zoh",
    time_column: str | None = None,
    time_unit: str = "s",
    source: str = "data",
):
    """A :class:`FitResults` at given parameter values, without optimisation.

    Useful to filter, smooth, predict or simulate with known or previously estimated parameters
    (e.g. on a validation period). Standard errors are not computed (NaN).
    """
    from thermocal.statespace.results import FitResults

    t_start = time.perf_counter()
    prep = _prepared(model, data, time_column, time_unit, source)
    model = model.with_parameters(params or {})
    theta = model.theta0()
    ll = _loglike_values(model, model.values_si(), prep, _hold_flag(hold))
    return FitResults(
        model=model,
        theta=theta,
        loglike=ll,
        hessian=None,
        nobs=prep.nobs,
        converged=True,
        message="evaluated at given parameters (no optimisation)",
        n_iterations=0,
        gradient_norm=float("nan"),
        start_loglikes=[ll],
        hold=hold,
        data=prep,
        fit_seconds=time.perf_counter() - t_start,
        fitter=fit,
    )
