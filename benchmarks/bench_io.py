"""Benchmark: read and resample a month of event-based logs from 100 sensors.

Target (issue 3): reading and resampling a month of 5-minute logs from 100 sensors <= 2 s.

The log is synthetic and irregular like the envelope-calibration case study's wireless sensors:
each sensor reports every 5 minutes or as soon as its value has changed by 0.28 C since the last
report, whichever comes first (simulated on a 10-second grid). The room temperatures follow a daily
heating cycle, a random walk, window airing (drops of 1-3 K in minutes, recovering over about an
hour) and measurement noise; a few sensors have a lost-radio gap and every sensor has 3 single-
report glitches (+8 K). The file is written once (not timed); the timed part is
``read_measurements`` + ``resample_measurements`` (with the spike screening and gap report),
repeated; best and median reported.

Run: ``/work/venv/bin/python benchmarks/bench_io.py [--repeats 5] [--keep]``
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import tempfile
import time
from pathlib import Path

import numba
import numpy as np
import pandas as pd

from thermocal.io.measurements import read_measurements, resample_measurements

N_SENSORS = 100
DAYS = 30
FINE_STEP = 10  # [s] simulation grid of the "true" temperature
HEARTBEAT = 300  # [s] report at least every 5 min
THRESHOLD = 0.28  # [K] report on a change of 0.28 C
TARGET_SECONDS = 2.0
GLITCHES = 3  # injected single-report spikes per sensor
START = pd.Timestamp("2019-02-01", tz="UTC")
END = START + pd.Timedelta(days=DAYS)


@numba.njit(cache=True)
def event_reports(signal, step, heartbeat, threshold):
    """Indices of the fine-grid samples a report-on-change-or-heartbeat sensor would send."""
    out = np.empty(signal.size, dtype=np.int64)
    n = 0
    last_value = signal[0]
    last_time = 0
    out[n] = 0
    n += 1
    for i in range(1, signal.size):
        t = i * step
        if abs(signal[i] - last_value) >= threshold or t - last_time >= heartbeat:
            out[n] = i
            n += 1
            last_value = signal[i]
            last_time = t
    return out[:n]


@numba.njit(cache=True)
def airing_deficit(opening, step, depth, tau_open, tau_closed):
    """Temperature drop [K] of a room while a window is open and its recovery afterwards."""
    out = np.empty(opening.size)
    deficit = 0.0
    for i in range(opening.size):
        if opening[i]:
            deficit += (depth - deficit) * step / tau_open
        else:
            deficit -= deficit * step / tau_closed
        out[i] = deficit
    return out


def synthetic_log(path: Path, seed: int = 0) -> tuple[int, int, set]:
    """Write the long-format log; returns (rows, n_sensors, injected spikes (sensor, time))."""
    rng = np.random.default_rng(seed)
    n_fine = DAYS * 86400 // FINE_STEP
    seconds = np.arange(n_fine) * FINE_STEP
    start = np.datetime64("2019-02-01T00:00:00", "s")
    day_phase = 2 * np.pi * seconds / 86400.0
    times, sensors, values = [], [], []
    injected: set[tuple[str, pd.Timestamp]] = set()
    for k in range(N_SENSORS):
        comfort = 20.5 + rng.normal(0, 1.0)
        heating = 1.5 * np.clip(np.sin(day_phase - 1.3 + rng.normal(0, 0.3)), -0.4, 1.0)
        drift = np.cumsum(rng.normal(0, 0.004, n_fine))
        # window airing: twice a day on average a window opens for 5-20 min; the room cools
        # towards 4 K below (time constant 10 min) and recovers afterwards (time constant 30 min)
        opening = np.zeros(n_fine, dtype=np.bool_)
        for first in rng.integers(0, n_fine - 1, DAYS * 2):
            opening[first : first + int(rng.integers(30, 120))] = True
        airing = airing_deficit(opening, FINE_STEP, 4.0, 600.0, 1800.0)
        signal = comfort + heating + drift - airing + rng.normal(0, 0.03, n_fine)
        index = event_reports(signal, FINE_STEP, HEARTBEAT, THRESHOLD)
        if k % 17 == 3:  # a lost radio for 6 hours
            lost = (index * FINE_STEP > 10 * 86400) & (index * FINE_STEP < 10 * 86400 + 6 * 3600)
            index = index[~lost]
        times.append(start + seconds[index].astype("timedelta64[s]"))
        sensors.append(np.full(index.size, k, dtype=np.int16))
        reported = np.round(signal[index], 2)
        # radio glitches: GLITCHES single reports 8 K off (never the first or last report)
        glitch = rng.choice(np.arange(50, index.size - 50), GLITCHES, replace=False)
        reported[glitch] += 8.0
        injected.update(
            (
                f"room_{k:03d}_temp",
                pd.Timestamp(start + np.timedelta64(int(seconds[i]), "s"), tz="UTC"),
            )
            for i in index[glitch]
        )
        values.append(reported)
    time_all = np.concatenate(times)
    order = np.argsort(time_all, kind="stable")
    names = np.array([f"room_{k:03d}_temp" for k in range(N_SENSORS)])
    frame = pd.DataFrame(
        {
            "time": np.char.add(np.datetime_as_string(time_all[order], unit="s"), "Z"),
            "sensor": names[np.concatenate(sensors)[order]],
            "value": np.concatenate(values)[order],
        }
    )
    frame.to_csv(path, index=False)
    return len(frame), N_SENSORS, injected


def regular_wide_log(path: Path, seed: int = 1) -> tuple[int, int]:
    """A regular 5-minute wide log (8640 rows x 100 columns) for comparison."""
    rng = np.random.default_rng(seed)
    index = pd.date_range("2019-02-01", periods=DAYS * 288, freq="5min", tz="UTC")
    data = 21 + np.cumsum(rng.normal(0, 0.05, (index.size, N_SENSORS)), axis=0)
    frame = pd.DataFrame(
        np.round(data, 2), index=index, columns=[f"T_room_{k:03d} [C]" for k in range(N_SENSORS)]
    )
    frame.index.name = "time"
    frame.to_csv(path, date_format="%Y-%m-%dT%H:%M:%SZ")
    return len(frame), N_SENSORS


def timed(function, repeats: int) -> tuple[list[float], list[float]]:
    """Wall-clock and process CPU durations of ``repeats`` calls [s]."""
    durations, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        function()
        durations.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return durations, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--keep", action="store_true", help="keep the generated CSV files")
    args = parser.parse_args()

    folder = Path(tempfile.mkdtemp(prefix="thermocal_bench_io_"))
    long_path = folder / "event_log_long.csv"
    wide_path = folder / "regular_log_wide.csv"
    t0 = time.perf_counter()
    rows, sensors, injected = synthetic_log(long_path)
    wide_rows, _ = regular_wide_log(wide_path)
    generation = time.perf_counter() - t0

    cases = []

    def long_5min():
        raw, _ = read_measurements(long_path)
        return resample_measurements(raw, "5min", max_gap="30min", start=START, end=END)

    def long_1h():
        raw, _ = read_measurements(long_path)
        return resample_measurements(raw, "1h", max_gap="30min", start=START, end=END)

    def wide_5min():
        raw, _ = read_measurements(wide_path)
        return resample_measurements(raw, "5min", max_gap="30min", start=START, end=END)

    def read_only():
        return read_measurements(long_path)

    data, report = long_5min()  # warm-up, and a sanity check of the result
    assert data.shape == (DAYS * 288, N_SENSORS), data.shape
    n_gap_sensors = int((report.sensors["n_gaps"] > 0).sum())
    assert n_gap_sensors == len([k for k in range(N_SENSORS) if k % 17 == 3]), n_gap_sensors
    spikes = report.flags[report.flags["flag"] == "outlier"]
    n_spikes = len(spikes)
    found = set(zip(spikes["sensor"], spikes["time"], strict=True))
    n_true = len(found & injected)

    for label, function, n_rows in (
        ("event log, long, 100 sensors -> 5 min grid", long_5min, rows),
        ("event log, long, 100 sensors -> 1 h grid", long_1h, rows),
        ("  of which reading only", read_only, rows),
        ("regular 5-min log, wide 100 columns -> 5 min grid", wide_5min, wide_rows),
    ):
        durations, cpu = timed(function, args.repeats)
        cases.append(
            (label, n_rows, min(durations), statistics.median(durations), statistics.median(cpu))
        )

    size_mb = long_path.stat().st_size / 1e6
    print(f"date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, python {platform.python_version()}"
        f", pandas {pd.__version__}"
    )
    print(
        f"event log: {rows} reports from {sensors} sensors over {DAYS} days ({size_mb:.1f} MB), "
        f"{n_gap_sensors} sensors with a 6 h gap (all found); {len(injected)} injected "
        f"spikes, {n_spikes} flagged, {n_true} of them injected; generation {generation:.1f} s "
        "(not timed)"
    )
    print(f"repeats: {args.repeats}; target <= {TARGET_SECONDS} s (read + resample)\n")
    print(f"load average before timing: {os.getloadavg()[0]:.1f}")
    print("| case | rows | best [s] | median [s] | median CPU [s] | target [s] | pass |")
    print("|---|---|---|---|---|---|---|")
    for label, n_rows, best, median, cpu in cases:
        target = "" if label.startswith("  ") else f"{TARGET_SECONDS:g}"
        verdict = "" if not target else ("pass" if median <= TARGET_SECONDS else "FAIL")
        print(
            f"| {label.strip()} | {n_rows} | {best:.3f} | {median:.3f} | {cpu:.3f} | {target} "
            f"| {verdict} |"
        )
    if args.keep:
        print(f"\nfiles kept in {folder}")
    else:
        long_path.unlink()
        wide_path.unlink()
        folder.rmdir()


if __name__ == "__main__":
    main()
