"""Guards and progress of a campaign: a filled store refused before the set-up, a campaign
estimated to take too long refused, store errors in one line, progress lines for logs, a
re-analysis of a store written for another campaign refused.
"""

from __future__ import annotations

import contextlib
import json
import os
import sqlite3
import time
from pathlib import Path

from thermocal.errors import ThermocalInputError


def refuse_filled_store(path: Path, resume: bool, samples: int) -> None:
    """Refuse at once (before the set-up, which takes a while on a large building) a store that
    already holds samples when ``--resume`` is not given; the full check of the campaign's
    definition happens when the store is opened."""
    if resume or not path.is_file():
        return
    try:
        con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
        try:
            done = con.execute("SELECT COUNT(*) FROM results").fetchone()[0]
            row = con.execute("SELECT value FROM campaign WHERE key = 'definition'").fetchone()
        finally:
            con.close()
        stored = int(json.loads(row[0])["sampler"]["samples"])
    except (sqlite3.Error, TypeError, KeyError, ValueError):
        return  # not a readable campaign store: opening it says why
    if not done:
        return
    remedy = "use another --out (or store), or delete the file to start afresh"
    if stored != samples:
        raise ThermocalInputError(
            f"store {path} already holds {done} finished sample(s) of a campaign of {stored} "
            f"samples; pass --resume to extend it to {samples} (the same sampling sequence; "
            f"a store of another campaign is then refused, naming what differs), or {remedy}"
        )
    raise ThermocalInputError(
        f"store {path} already holds {done} finished sample(s); pass --resume to continue "
        f"the campaign (a store of another campaign is then refused, naming what differs), or "
        f"{remedy}"
    )


def check_same_campaign(campaign, space, stored: dict, path) -> None:
    """Refuse a re-analysis of a store written for other inputs, parameters or sampling."""
    from thermocal.calibration.store import _definition_differences

    settings = dict(stored.get("problem") or {})
    current = {
        "space": space.to_dict(),
        "sampler": {"method": campaign.sampling.method, "seed": campaign.sampling.seed},
        "problem": {k: v for k, v in campaign.problem_settings().items() if k in settings},
    }
    before = {
        "space": stored.get("space"),
        "sampler": {k: v for k, v in (stored.get("sampler") or {}).items() if k != "samples"},
        "problem": {k: settings[k] for k in current["problem"]},
    }
    diffs = _definition_differences(
        json.loads(json.dumps(before, default=str)), json.loads(json.dumps(current, default=str))
    )
    if diffs:
        raise ThermocalInputError(
            f"store {path} holds another campaign than {campaign.path}: "
            + "; ".join(diffs[:8])
            + ". A re-analysis may change the metric, meta-model, optimisation and posterior "
            "settings, not the inputs, parameters or sampling (run thermocal calibrate for those)"
        )


def _seconds(value: float) -> str:
    """A time in seconds with two digits below 10 s (a fast model's 0.04), whole above."""
    return f"{value:.2g}" if value < 10 else f"{value:.0f}"


def _format_duration(seconds: float) -> str:
    seconds = max(0.0, float(seconds))
    if seconds < 10:
        return f"{seconds:.2g} s"  # a fast model's few seconds: not "0 s"
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def check_campaign_time(
    pending: int,
    seconds_per_sample: float,
    *,
    workers: int | None,
    scheduler=None,
    max_hours: float | None = 24.0,
    log=print,
) -> float:
    """Log the campaign's estimated duration; refuse one longer than ``max_hours``.

    Parameters
    ----------
    pending : int
        Samples still to evaluate [-].
    seconds_per_sample : float
        Measured time of one identification (the nominal run) [s].
    workers : int or None
        Local processes (None: all cores) [-].
    scheduler : optional
        A Dask scheduler: its workers are unknown, so the estimate is per worker and no limit
        applies.
    max_hours : float or None
        Limit [h]; None: none.
    log : callable

    Returns
    -------
    float
        The estimate [s].
    """
    if scheduler is not None:
        estimate = pending * seconds_per_sample
        log(
            f"estimate: {pending} samples x {_seconds(seconds_per_sample)} s = "
            f"{_format_duration(estimate)} of work, divided among the Dask workers"
        )
        return estimate
    n_workers = max(1, min(int(workers or os.cpu_count() or 1), max(pending, 1)))
    estimate = pending * seconds_per_sample / n_workers
    log(
        f"estimate: {pending} samples x {_seconds(seconds_per_sample)} s / {n_workers} worker(s) = "
        f"about {_format_duration(estimate)}"
    )
    if max_hours is not None and estimate > max_hours * 3600.0:
        raise ThermocalInputError(
            f"the campaign would take about {_format_duration(estimate)} ({pending} samples x "
            f"{_seconds(seconds_per_sample)} s per identification / {n_workers} worker(s)), "
            f"more than --max-hours {max_hours:g}; use fewer --samples, more --workers or a Dask "
            "--scheduler, or raise --max-hours (the campaign is resumable: --resume continues "
            "an interrupted one)"
        )
    return estimate


class ProgressLines:
    """``on_result`` callback that logs a progress line about every 5 % or every minute.

    For logs and CI, where a progress bar is invisible (it is drawn only on a terminal).
    """

    def __init__(self, pending: int, done: int, log, *, every_s: float = 60.0) -> None:
        self.pending, self.done, self.log = int(pending), int(done), log
        self.every = max(1, self.pending // 20)
        self.every_s = float(every_s)
        self.evaluated = self.failed = 0
        self.start = self.last = time.perf_counter()

    def __call__(self, result) -> None:
        self.evaluated += 1
        self.failed += result.error is not None
        now = time.perf_counter()
        if (
            self.evaluated % self.every
            and now - self.last < self.every_s
            and self.evaluated != self.pending
        ):
            return
        self.last = now
        elapsed = now - self.start
        left = elapsed / self.evaluated * (self.pending - self.evaluated)
        total = self.pending + self.done
        self.log(
            f"campaign: {self.done + self.evaluated}/{total} samples ({self.failed} failed), "
            f"{_format_duration(elapsed)} elapsed, about {_format_duration(left)} left"
        )


@contextlib.contextmanager
def store_errors(path: Path):
    """SQLite's 'disk is full' / read-only errors of the store as one clear input error."""
    try:
        yield
    except sqlite3.OperationalError as exc:
        text = str(exc)
        if "full" in text:
            what = "the disk is full; free some space or choose another --out (or store)"
        elif "readonly" in text or "read-only" in text or "unable to open" in text:
            what = "it cannot be written (read-only folder or file); choose another --out"
        else:
            raise
        raise ThermocalInputError(
            f"store {path}: {what}; the samples recorded so far are kept, and --resume continues"
        ) from None
