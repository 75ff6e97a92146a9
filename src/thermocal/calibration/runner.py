"""Run a campaign: evaluate samples locally (process pool) or on a Dask cluster, store each result.

The *evaluator* is any picklable object with a method
``evaluate(parameters: dict[str, float]) -> dict[str, float]`` returning named outputs.  It may
build heavy state (the perturbable model, the measurements) lazily on its first call; that state is
built **once per worker**, not once per sample:

* ``workers=1``: evaluated in this process, no pool;
* local pool (``workers=N``): a :class:`concurrent.futures.ProcessPoolExecutor` whose initializer
  stores the evaluator in a module global of each worker process (started with ``forkserver`` on
  POSIX, so the evaluator's class must be importable);
* Dask (``scheduler="tcp://HOST:PORT"`` or a ``distributed.Client``/``LocalCluster``): the
  evaluator is scattered once to every worker (``broadcast=True``) and each sample is a task that
  receives that worker's copy.

Results are written to the :class:`~thermocal.calibration.store.CampaignStore` by this (parent)
process as each sample finishes, one committed row per sample.  A sample that raises is recorded
with its error text and the campaign goes on.  Only samples missing from the store are submitted,
so a campaign killed at any point and restarted loses nothing committed and repeats nothing
committed (samples that were being evaluated at the moment of the kill, at most one per worker,
are evaluated again).  Outputs depend only on the parameters, so local and Dask runs give equal
stores (ordered by sample index).
"""

from __future__ import annotations

import multiprocessing
import os
import socket
import sys
import time
import traceback
from collections.abc import Callable, Iterable, Iterator, Mapping
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from typing import Any, Protocol

import pandas as pd

from thermocal.calibration.store import CampaignStore, SampleResult
from thermocal.errors import ThermocalInputError

__all__ = ["CampaignSummary", "Evaluator", "evaluate_sample", "run_campaign"]


class Evaluator(Protocol):
    """What the runner needs: a picklable object mapping parameters to named outputs."""

    def evaluate(self, parameters: dict[str, float]) -> dict[str, float]:  # pragma: no cover
        ...


@dataclass(frozen=True)
class CampaignSummary:
    """What a call of :func:`run_campaign` did.

    Attributes
    ----------
    total : int
        Samples in the campaign [-].
    already_done : int
        Samples found finished in the store before this call [-].
    evaluated : int
        Samples evaluated by this call [-].
    failed : int
        Samples of this call that raised [-].
    wall_time_s : float
        Wall time of this call [s].
    backend : str
        ``"in-process"``, ``"process-pool(N)"`` or ``"dask(ADDRESS)"``.
    """

    total: int
    already_done: int
    evaluated: int
    failed: int
    wall_time_s: float
    backend: str


# ----------------------------------------------------------------------------------------------
# worker side
# ----------------------------------------------------------------------------------------------
_WORKER_EVALUATOR: Any = None


def _init_worker(evaluator: Any) -> None:
    global _WORKER_EVALUATOR
    _WORKER_EVALUATOR = evaluator


def _worker_name() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


def evaluate_sample(evaluator: Any, sample: int, parameters: Mapping[str, float]) -> SampleResult:
    """Evaluate one sample, turning an exception into a recorded error.

    Parameters
    ----------
    evaluator : Evaluator
        Object with ``evaluate(parameters) -> dict``.
    sample : int
        Sample index [-].
    parameters : mapping of str to float
        Parameter values [unit of each parameter].

    Returns
    -------
    SampleResult
        Outputs and runtime [s], or the error text (exception type, message and the last
        traceback lines) with empty outputs.
    """
    params = {str(k): float(v) for k, v in parameters.items()}
    start = time.perf_counter()
    try:
        outputs = evaluator.evaluate(dict(params))
        if not isinstance(outputs, Mapping):
            raise TypeError(
                f"evaluate() must return a dict of named outputs, got {type(outputs).__name__}"
            )
        outputs = {str(k): float(v) for k, v in outputs.items()}
        error = None
    except Exception as exc:  # noqa: BLE001 - a failed sample is recorded, never fatal
        tb = traceback.format_exception(type(exc), exc, exc.__traceback__)
        error = f"{type(exc).__name__}: {exc}\n" + "".join(tb[-3:])
        outputs = {}
    return SampleResult(
        sample=int(sample),
        parameters=params,
        outputs=outputs,
        runtime_s=time.perf_counter() - start,
        error=error,
        worker=_worker_name(),
    )


def _pool_task(sample: int, parameters: dict[str, float]) -> SampleResult:
    return evaluate_sample(_WORKER_EVALUATOR, sample, parameters)


def _dask_task(evaluator: Any, sample: int, parameters: dict[str, float]) -> SampleResult:
    return evaluate_sample(evaluator, sample, parameters)


# ----------------------------------------------------------------------------------------------
# parent side
# ----------------------------------------------------------------------------------------------
def _iter_in_process(
    evaluator: Any, jobs: list[tuple[int, dict[str, float]]]
) -> Iterator[SampleResult]:
    for sample, params in jobs:
        yield evaluate_sample(evaluator, sample, params)


def _iter_pool(
    evaluator: Any,
    jobs: list[tuple[int, dict[str, float]]],
    workers: int,
    mp_context: str | None,
) -> Iterator[SampleResult]:
    method = mp_context or ("forkserver" if sys.platform != "win32" else "spawn")
    ctx = multiprocessing.get_context(method)
    with ProcessPoolExecutor(
        max_workers=workers, mp_context=ctx, initializer=_init_worker, initargs=(evaluator,)
    ) as pool:
        # keep a bounded number of tasks in flight: a kill loses at most these
        queue = list(reversed(jobs))
        running: set[Future] = set()
        try:
            while queue or running:
                while queue and len(running) < 2 * workers:
                    sample, params = queue.pop()
                    running.add(pool.submit(_pool_task, sample, params))
                finished, running = wait(running, return_when=FIRST_COMPLETED)
                for fut in finished:
                    yield fut.result()
        finally:
            for fut in running:
                fut.cancel()


def _connect_dask(scheduler: Any, timeout: float) -> tuple[Any, bool, str]:
    """Client for ``scheduler`` (address, Client or cluster); True when we own it."""
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover
        raise ThermocalInputError(
            "--scheduler needs dask.distributed: pip install 'dask[distributed]'"
        ) from None
    if isinstance(scheduler, Client):
        return scheduler, False, str(scheduler.scheduler.address)
    if hasattr(scheduler, "scheduler_address"):  # LocalCluster, SpecCluster...
        client = Client(scheduler, timeout=timeout, set_as_default=False)
        return client, True, str(scheduler.scheduler_address)
    address = str(scheduler)
    if "://" not in address:
        raise ThermocalInputError(
            f"--scheduler {address!r} is not a Dask scheduler address; use tcp://HOST:PORT"
        )
    try:
        client = Client(address, timeout=timeout, set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise ThermocalInputError(
            f"--scheduler {address}: no Dask scheduler answered within {timeout:g} s ({exc}); "
            "check the address and that `dask scheduler` runs there, or drop --scheduler to "
            "run on the local process pool"
        ) from None
    except ValueError as exc:
        raise ThermocalInputError(f"--scheduler {address}: {exc}") from None
    return client, True, address


def _iter_dask(
    evaluator: Any,
    jobs: list[tuple[int, dict[str, float]]],
    client: Any,
) -> Iterator[SampleResult]:
    from distributed import as_completed

    if not client.scheduler_info().get("workers"):
        client.wait_for_workers(1, timeout=60)
    handle = client.scatter(evaluator, broadcast=True, hash=False)
    token = os.urandom(4).hex()
    by_future = {
        client.submit(_dask_task, handle, sample, params, pure=False,
                      key=f"thermocal-sample-{sample}-{token}"): (sample, params)
        for sample, params in jobs
    }
    futures = list(by_future)
    try:
        for fut in as_completed(futures, loop=client.loop):
            try:
                yield fut.result()
            except Exception as exc:  # noqa: BLE001 - worker died: record, go on
                sample, params = by_future[fut]
                yield SampleResult(sample, params, {}, 0.0,
                                   f"{type(exc).__name__}: {exc} (Dask task failed)", "dask")
    finally:
        client.cancel(futures)


def run_campaign(
    evaluator: Any,
    samples: pd.DataFrame,
    store: CampaignStore,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    progress: bool = True,
    connect_timeout: float = 10.0,
    retry_failed: bool = False,
    mp_context: str | None = None,
    description: str = "calibration campaign",
    on_result: Callable[[SampleResult], None] | None = None,
) -> CampaignSummary:
    """Evaluate every sample not yet in the store and record each as it finishes.

    Parameters
    ----------
    evaluator : Evaluator
        Picklable object with ``evaluate(parameters: dict[str, float]) -> dict[str, float]``;
        built once per worker (see the module docstring).
    samples : DataFrame
        Rows: samples, indexed by sample index; columns: parameter names [unit of each
        parameter] (``SampleSet.values``).
    store : CampaignStore
        Where results go; samples already there are skipped.
    workers : int, optional
        Local worker processes [-]; default ``os.cpu_count()``; 1 runs in this process.
        Ignored with ``scheduler``.
    scheduler : str or distributed.Client or cluster, optional
        Dask scheduler address ``"tcp://HOST:PORT"``, or a client/cluster object.
    progress : bool
        Show a progress bar with an ETA (rich).
    connect_timeout : float
        Seconds to wait for a Dask scheduler before giving up with a clear message [s].
    retry_failed : bool
        Evaluate again the samples stored with an error.
    mp_context : str, optional
        Start method of the local pool (default ``"forkserver"`` on POSIX).
    description : str
        Label of the progress bar.
    on_result : callable, optional
        Called with each :class:`SampleResult` after it is committed.

    Returns
    -------
    CampaignSummary

    Raises
    ------
    ThermocalInputError
        Bad samples frame, bad ``workers``, unreachable scheduler.
    """
    if not isinstance(samples, pd.DataFrame) or samples.empty:
        raise ThermocalInputError("samples must be a non-empty DataFrame (SampleSet.values)")
    if not samples.index.is_unique:
        raise ThermocalInputError("samples: the sample index has duplicates")
    if not hasattr(evaluator, "evaluate"):
        raise ThermocalInputError(
            f"evaluator {type(evaluator).__name__} has no evaluate(parameters) method"
        )
    if workers is None:
        workers = os.cpu_count() or 1
    if int(workers) < 1:
        raise ThermocalInputError(f"--workers must be at least 1, got {workers}")
    workers = int(workers)

    total = len(samples)
    todo = store.pending(samples.index, retry_failed=retry_failed)
    already = total - len(todo)
    columns = [str(c) for c in samples.columns]
    rows = samples.loc[todo].to_numpy(dtype=float) if todo else []
    jobs = [
        (int(i), dict(zip(columns, map(float, row), strict=True)))
        for i, row in zip(todo, rows, strict=True)
    ]

    owned_client = None
    if scheduler is not None:
        client, owned, address = _connect_dask(scheduler, connect_timeout)
        owned_client = client if owned else None
        backend = f"dask({address})"
        results: Iterable[SampleResult] = _iter_dask(evaluator, jobs, client)
    elif workers == 1 or len(jobs) <= 1:
        backend = "in-process"
        results = _iter_in_process(evaluator, jobs)
    else:
        backend = f"process-pool({workers})"
        results = _iter_pool(evaluator, jobs, min(workers, len(jobs)), mp_context)

    start = time.perf_counter()
    evaluated = failed = 0
    bar = _progress(progress, description, total, already)
    try:
        if bar is not None:
            bar[0].start()
        for result in results if jobs else ():
            store.record(result)
            evaluated += 1
            failed += result.error is not None
            if bar is not None:
                bar[0].update(bar[1], advance=1, failed=failed)
            if on_result is not None:
                on_result(result)
    finally:
        if bar is not None:
            bar[0].stop()
        if hasattr(results, "close"):
            results.close()
        if owned_client is not None:
            owned_client.close()
    return CampaignSummary(
        total=total,
        already_done=already,
        evaluated=evaluated,
        failed=failed,
        wall_time_s=time.perf_counter() - start,
        backend=backend,
    )


def _progress(enabled: bool, description: str, total: int, done: int) -> Any:
    if not enabled:
        return None
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    bar = Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("failed {task.fields[failed]}"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
        transient=False,
    )
    task = bar.add_task(description, total=total, completed=done, failed=0)
    return bar, task
