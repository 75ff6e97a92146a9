"""Benchmark: physics and weather (issue 3).

Target: a year of hourly solar gains for a building with 12 oriented surfaces <= 0.5 s
(sun position, Perez transposition per orientation, window and opaque gains incl. the sky term).
Also reported (no target): reading the EPW file, resampling a year to 5 minutes, and the same
gains on the 5-minute year.

Run: /work/venv/bin/python benchmarks/bench_physics.py [--repeats N]
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time
from pathlib import Path

from thermocal.io.weather import read_weather, resample_weather
from thermocal.physics.solar import building_solar_gains

EPW = (
    Path(__file__).resolve().parents[2]
    / "shared"
    / "data"
    / "weather_switzerland"
    / "Zuerich-SMA_2015.epw"
)
TARGET_SECONDS = 0.5


def twelve_surfaces():
    """4 windows, 4 walls, 4 roof planes: 12 distinct orientations."""
    windows = [
        {"name": f"window_{a}", "area": 6.0, "tilt": 90.0, "azimuth": a, "g_value": 0.6}
        for a in (0.0, 90.0, 180.0, 270.0)
    ]
    walls = [
        {"name": f"wall_{a}", "area": 60.0, "tilt": 88.0, "azimuth": a + 10.0, "u_value": 1.0}
        for a in (0.0, 90.0, 180.0, 270.0)
    ]
    roofs = [
        {"name": f"roof_{a}", "area": 50.0, "tilt": 35.0, "azimuth": a + 45.0, "u_value": 0.5}
        for a in (0.0, 90.0, 180.0, 270.0)
    ]
    return windows, walls + roofs


def timed(function, repeats):
    times = []
    result = None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), statistics.median(times), result


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    weather, meta = read_weather(EPW)  # warm-up (imports)
    windows, opaque = twelve_surfaces()
    lat, lon, alt = meta["latitude"], meta["longitude"], meta["altitude"]

    def gains(frame):
        return lambda: building_solar_gains(
            frame, lat, lon, altitude=alt, windows=windows, opaque=opaque
        )

    rows = []
    best, median, _ = timed(lambda: read_weather(EPW), args.repeats)
    rows.append(("read_weather (EPW, 8760 h)", best, median, None))
    best, median, fine = timed(lambda: resample_weather(weather, "5min"), args.repeats)
    rows.append(("resample_weather 1 h -> 5 min (1 year)", best, median, None))
    gains(weather)()  # warm-up
    best, median, result = timed(gains(weather), args.repeats)
    assert result.shape == (8760, 14)
    rows.append(("solar gains, 12 surfaces, 1 year hourly", best, median, TARGET_SECONDS))
    best, median, _ = timed(gains(fine), max(2, args.repeats // 3))
    rows.append(("solar gains, 12 surfaces, 1 year 5-min", best, median, None))

    print(f"date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(
        f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}"
    )
    print(f"{'case':45s} {'best [s]':>9s} {'median [s]':>10s} {'target':>8s} result")
    for name, best, median, target in rows:
        verdict = "" if target is None else ("PASS" if median <= target else "FAIL")
        target_text = "" if target is None else f"<= {target:g}"
        print(f"{name:45s} {best:9.3f} {median:10.3f} {target_text:>8s} {verdict}")


if __name__ == "__main__":
    main()
