"""The quality report of a resampled sensor log: gaps, flags, coverage and actions; the spike test.

Part of :mod:`thermocal.io.measurements`; see its docstring for the conventions.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd


def spike_threshold(
    span_hours, floor: float, slope: float | None = None, ceiling: float | None = None
) -> np.ndarray:
    """Smallest jump away and back that can be a logger's spike, for an excursion's span.

    A room's reading that leaves its level and comes back within ``span`` hours, rising and
    falling at most ``slope`` per hour, gets at most ``slope * span / 2`` away (the peak of a
    rise and fall over the span); a spike must go further than that, and further than
    ``floor``. ``ceiling`` caps the threshold: no real excursion of the quantity goes that far
    away and back between two readings, however far apart (a missing-value code, a dropout to
    0, a sensor's power-on value do).

    Parameters
    ----------
    span_hours : float or array [h]
        Time from the reading before the excursion to the reading after it.
    floor : float [unit]
        Smallest threshold (the sensor's noise and a quick draught at short spacing).
    slope : float or None [unit/h]
        Fastest rise or fall of a real excursion; None: the threshold is ``floor``.
    ceiling : float or None [unit]
        Largest threshold; None: no cap.

    Returns
    -------
    ndarray [unit]
    """
    span = np.asarray(span_hours, dtype=float)
    if slope is None:
        return np.full(span.shape, float(floor))
    threshold = np.maximum(floor, 0.5 * slope * np.nan_to_num(span, nan=0.0))
    return threshold if ceiling is None else np.minimum(threshold, max(ceiling, floor))


def _spikes(
    values: np.ndarray,
    n_sigma: float,
    floor: float,
    max_run: int = 2,
    *,
    times_s: np.ndarray | None = None,
    slope: float | None = None,
    ceiling: float | None = None,
) -> np.ndarray:
    """Boolean mask of spikes: runs of at most ``max_run`` reports that jump away and back.

    A run ``values[i:i + r]`` (1 <= r <= max_run) is a spike when every value in it lies more
    than the threshold above (or below) both neighbours ``values[i - 1]`` and ``values[i + r]``,
    and the neighbours agree within the threshold (the signal comes back). The threshold is the
    larger of ``n_sigma * 1.4826 * MAD(first differences)`` (the signal's own jitter) and a
    floor that grows with the time the run spans (:func:`spike_threshold`: ``floor``, or
    ``slope`` times half the time from the reading before the run to the reading after it, at
    most ``ceiling``). A step (no return) and a real event reported by several change-triggered
    reports (small successive differences) are not spikes.

    Why the floor grows with the spacing: a logger's spike (a missing-value code, a mains
    glitch, a power-on value) is one reading far from the readings around it whatever the
    spacing, but a room's real excursion grows with the time between readings. A room held at
    its set points has almost no jitter (MAD 0), so the threshold is the floor alone; read
    every 5 minutes, 1.5 K away and back is a glitch, but read every hour a room in the sun
    floats 2-3 K above its heating set point for one or two readings and comes back (an
    EnergyPlus 25.2 twin of NREL's WindowTestsSimple, Golden in January, hourly: 20.13, 23.21,
    22.66, 20.42 C; up to 3.1 K above both neighbours, against 0.05 K read every 5 minutes).
    A fixed 1.5 K removed those readings and the identification then invented heat across the
    gap. The other sensors' simultaneous readings are not used: a multi-channel logger's glitch
    hits every channel at once, and a room in the sun floats alone.

    Parameters
    ----------
    values : ndarray [unit]
        One sensor's readings in time order (finite).
    n_sigma : float [-]
        Threshold in robust standard deviations of the successive differences.
    floor : float [unit]
        Smallest threshold.
    max_run : int
        Longest run of readings called a spike.
    times_s : ndarray or None [s]
        Reading times; None: the threshold is ``floor`` at any spacing.
    slope, ceiling : float or None [unit/h], [unit]
        See :func:`spike_threshold`.

    Returns
    -------
    ndarray of bool

    References
    ----------
    .. [1] U.S. IOOS (2020). Manual for Real-Time Quality Control of In-situ Temperature and
       Salinity Data, version 2.1, QARTOD test 9 (spike test).
    """
    n = values.size
    spikes = np.zeros(n, dtype=bool)
    if n < 3:
        return spikes
    steps = np.diff(values)
    mad = float(np.median(np.abs(steps - np.median(steps))))
    jitter = n_sigma * 1.4826 * mad
    for run in range(1, max_run + 1):
        if n < run + 2:
            break
        before = values[: n - run - 1]
        after = values[run + 1 :]
        if times_s is None or slope is None:
            span = np.zeros(n - run - 1)
        else:
            times = np.asarray(times_s, dtype=float)
            span = (times[run + 1 :] - times[: n - run - 1]) / 3600.0
        threshold = np.maximum(jitter, spike_threshold(span, floor, slope, ceiling))
        window = np.lib.stride_tricks.sliding_window_view(values[1 : n - 1], run)
        low_run, high_run = window.min(axis=1), window.max(axis=1)
        returns = np.abs(before - after) <= threshold
        up = low_run - np.maximum(before, after) > threshold
        down = np.minimum(before, after) - high_run > threshold
        for first in np.flatnonzero(returns & (up | down)):
            spikes[first + 1 : first + 1 + run] = True
    return spikes


def true_runs(mask) -> tuple[np.ndarray, np.ndarray]:
    """Starts and ends (exclusive) of the runs of True in a boolean mask.

    Parameters
    ----------
    mask : array-like of bool

    Returns
    -------
    (ndarray, ndarray)
        Positions of each run's first element and of the element after its last.
    """
    edges = np.flatnonzero(np.diff(np.concatenate([[0], np.asarray(mask).astype(int), [0]])))
    return edges[::2], edges[1::2]


def level_excursions(
    values: np.ndarray, jump: float, max_run: int, min_run: int = 1
) -> list[tuple[int, int]]:
    """Runs of readings that jump away by more than ``jump`` and jump back.

    A run ``values[i:j]`` (at most ``max_run`` readings, NaN left out) is an excursion when the
    readings before and after it agree within ``jump`` and every reading of the run lies more
    than ``jump`` above (or below) both: a logger's dropout to 0, a missing-value code
    (-999, a sensor's power-on 85 C) or a mains spike, where a room's air never jumps by that
    much in one reporting interval and back. A real event (a window opened, a heating
    set-back) changes the temperature gradually or stays at its new level: it is not one.

    Parameters
    ----------
    values : array [C]
        One sensor's readings in time order (NaN: none).
    jump : float [K]
        Smallest jump into and out of the run.
    max_run : int
        Longest run [readings].
    min_run : int
        Shortest run [readings] (e.g. 3, when the spike test takes the runs of 1 and 2).

    Returns
    -------
    list of (int, int)
        ``(first, end)`` positions in ``values`` (``end`` exclusive) of each excursion.
    """
    finite = np.flatnonzero(np.isfinite(values))
    v = values[finite]
    if v.size < 3:
        return []
    steps = np.diff(v)
    big = np.flatnonzero(np.abs(steps) > jump)
    found = []
    for n, a in enumerate(big):
        if found and a < found[-1][1]:
            continue  # inside the previous excursion
        before = v[a]
        for b in big[n + 1 :]:
            if b - a > max_run:
                break
            if np.sign(steps[b]) == np.sign(steps[a]):
                continue
            after, run = v[b + 1], v[a + 1 : b + 1]
            if abs(after - before) <= jump and (
                run.min() - max(before, after) > jump or min(before, after) - run.max() > jump
            ):
                if b - a >= min_run:
                    found.append((a + 1, b + 1))
                break
    return [(int(finite[i]), int(finite[j - 1]) + 1) for i, j in found]


@dataclass
class QualityReport:
    """What :func:`resample_measurements` did and found.

    Attributes
    ----------
    step : Timedelta
        Grid step.
    start, end : Timestamp
        First interval start and last interval end of the grid.
    sensors : DataFrame
        One row per sensor: quantity, unit, operation, n_reports, median_interval [s],
        max_interval [s], n_gaps, gap_hours [h], n_impossible, n_outliers, n_outliers_removed,
        coverage [-] (mean covered fraction of the intervals), n_missing (NaN intervals).
    gaps : DataFrame
        One row per silence longer than ``max_gap``: sensor, start (last report before), end
        (first report after, or the end of the data), duration [h], n_missing (NaN intervals).
    flags : DataFrame
        One row per flagged report: sensor, time, value, line (1-based line in the file, long
        logs from :func:`read_measurements`; else None), flag ("impossible" or "outlier"),
        action ("removed" or "kept"), reason.
    coverage : DataFrame
        Covered fraction of every interval [-] (grid x sensors).
    actions : list of str
        Plain-language account of everything done (conversions, removals, gaps left NaN).
    """

    step: pd.Timedelta
    start: pd.Timestamp
    end: pd.Timestamp
    sensors: pd.DataFrame
    gaps: pd.DataFrame
    flags: pd.DataFrame
    coverage: pd.DataFrame
    actions: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """True when there were no gaps, impossible values or outliers."""
        return self.gaps.empty and self.flags.empty

    def summary(self) -> str:
        """Plain-text summary (one line per sensor, then the actions)."""
        head = (
            f"Measurement quality: {len(self.sensors)} sensor(s), grid {self.start.isoformat()} "
            f"to {self.end.isoformat()}, step {self.step}"
        )
        columns = [
            "quantity",
            "unit",
            "operation",
            "n_reports",
            "coverage",
            "n_gaps",
            "gap_hours",
            "n_impossible",
            "n_outliers",
            "n_missing",
        ]
        table = self.sensors[columns].to_string(float_format=lambda x: f"{x:.3g}")
        body = "\n".join(f"- {a}" for a in self.actions) if self.actions else "- nothing to report"
        return f"{head}\n{table}\n{body}"

    def __str__(self) -> str:
        return self.summary()

    def to_dict(self) -> dict:
        """JSON-serialisable content (times as ISO 8601 strings)."""

        def records(frame: pd.DataFrame) -> list[dict]:
            out = frame.copy()
            for column in out.columns:
                if isinstance(out[column].dtype, pd.DatetimeTZDtype):
                    out[column] = out[column].map(lambda x: x.isoformat())
            return out.astype(object).where(out.notna(), None).to_dict(orient="records")

        sensors = self.sensors.reset_index()
        return {
            "step_seconds": self.step.total_seconds(),
            "start": self.start.isoformat(),
            "end": self.end.isoformat(),
            "sensors": records(sensors),
            "gaps": records(self.gaps),
            "flags": records(self.flags),
            "actions": list(self.actions),
        }


def _sensor_row(
    name,
    quantity,
    unit,
    operation,
    n_reports,
    median_interval,
    max_interval,
    n_gaps,
    gap_hours,
    n_impossible,
    n_outliers,
    n_removed,
    coverage,
    n_missing,
) -> dict:
    return {
        "sensor": name,
        "quantity": quantity or "",
        "unit": unit or "",
        "operation": operation,
        "n_reports": int(n_reports),
        "median_interval": median_interval,
        "max_interval": max_interval,
        "n_gaps": int(n_gaps),
        "gap_hours": gap_hours,
        "n_impossible": int(n_impossible),
        "n_outliers": int(n_outliers),
        "n_outliers_removed": int(n_removed),
        "coverage": coverage,
        "n_missing": int(n_missing),
    }
