"""Readings removed before the identification are kept with the results.

Before: the warning for readings removed as impossible or as isolated spikes said "the quality
report in identification.json lists them", but identification.json had no such key and no
record of the removed values, and report.html did not mention them. Now each removed reading
is a record under ``removed_readings`` (sensor, zone, time, value, flag, reason), with one note
in ``notes`` and report.html, and the warning names that key.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from conftest import shared_data_path
from thermocal.identification.sensors import removed_readings_note


def test_the_note_counts_the_readings_per_sensor():
    records = [
        {"sensor": "S1", "zone": "living", "time": "2015-02-02T10:00:00+01:00",
         "value_C": 85.0, "flag": "outlier", "reason": "spike"},
        {"sensor": "S1", "zone": "living", "time": "2015-02-02T11:00:00+01:00",
         "value_C": 85.0, "flag": "outlier", "reason": "spike"},
        {"sensor": "S2", "zone": "kitchen", "time": "2015-02-03T00:00:00+01:00",
         "value_C": -999.0, "flag": "impossible", "reason": "limits"},
    ]  # fmt: skip
    note = removed_readings_note(records)
    assert note.startswith("3 sensor reading(s) removed before the identification")
    assert "S1 (living): 2, the first 85 C at 2015-02-02T10:00:00+01:00" in note
    assert "S2 (kitchen): 1, the first -999 C" in note
    assert "removed_readings in identification.json" in note
    assert removed_readings_note([]) is None


def _two_rooms(tmp_path, freq="15min"):
    """The documented two-room building's readings: times and the two sensors' values [C]."""
    times = pd.date_range("2015-02-02", "2015-02-05", freq=freq, inclusive="left")
    hours = np.asarray((times - times[0]) / pd.Timedelta("1h"))
    s1 = (20.0 + 0.4 * np.sin(2 * np.pi * hours / 24)).round(3)
    s2 = (19.0 + 0.5 * np.sin(2 * np.pi * hours / 24 + 1)).round(3)
    return times, s1, s2


def _identify(tmp_path, times, s1, s2):
    """``thermocal identify`` on the two-room building: stderr (one line) and the result."""
    doc = (Path(__file__).parents[2] / "docs" / "multizone-file.md").read_text()
    building = tmp_path / "two_rooms.yaml"
    building.write_text(re.search(r"## Example\s+```yaml\n(.*?)```", doc, re.S).group(1))
    mapping = tmp_path / "mapping.yaml"
    mapping.write_text("sensors: {S1: living, S2: kitchen}\n")
    log = tmp_path / "log.csv"
    pd.DataFrame({"time": times.astype(str), "S1": s1, "S2": s2}).to_csv(log, index=False)
    out = tmp_path / "out"
    weather = shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
    done = subprocess.run(
        [sys.executable, "-m", "thermocal", "identify", building, weather, log, "--mapping",
         mapping, "--out", out, "--method", "inverse", "--tz", "1", "--no-clock-check"],
        capture_output=True, text=True,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return " ".join(done.stderr.split()), json.loads((out / "identification.json").read_text())


def test_identify_writes_the_removed_readings(tmp_path):
    """The command on a two-room building whose living-room sensor reads 85 C once (a
    DS18B20's power-on value) and whose kitchen sensor reads -999 (a missing-value code)."""
    times, s1, s2 = _two_rooms(tmp_path)
    s1[150] = 85.0
    s2[200] = -999.0
    said, result = _identify(tmp_path, times, s1, s2)
    assert "removed_readings in identification.json lists each" in said, said
    records = {r["sensor"]: r for r in result["removed_readings"]}
    assert set(records) == {"S1", "S2"}, result["removed_readings"]
    assert (records["S1"]["zone"], records["S1"]["value_C"], records["S1"]["flag"]) == (
        "living", 85.0, "outlier",
    )  # fmt: skip
    assert pd.Timestamp(records["S1"]["time"]) == pd.Timestamp(times[150], tz="+01:00")
    assert records["S1"]["reason"].startswith("spike: jumps away from both neighbours")
    assert (records["S2"]["zone"], records["S2"]["value_C"], records["S2"]["flag"]) == (
        "kitchen", -999.0, "impossible",
    )  # fmt: skip
    notes = [n for n in result["notes"] if "removed before the identification" in n]
    assert len(notes) == 1 and "S1 (living): 1, the first 85 C" in notes[0]
    html = (tmp_path / "out" / "report.html").read_text()
    assert "2 sensor reading(s) removed before the identification" in html


def test_more_than_a_thousand_removed_readings_are_all_counted(tmp_path):
    """A one-minute logger writing -999 on every other minute of three days (2,160 missing-value
    codes): the quality report lists the first 1000 of each sensor and kind. Before: the warning
    and the note said "1000 reading(s) removed" and that identification.json "lists each"."""
    times, s1, s2 = _two_rooms(tmp_path, freq="1min")
    s2[1::2] = -999.0
    said, result = _identify(tmp_path, times, s1, s2)
    assert "'S2' (zone 'kitchen'): 2160 reading(s) removed as impossible" in said, said
    assert "lists 1000 of them" in said and "lists each" not in said, said
    assert len(result["removed_readings"]) == 1000
    (note,) = [n for n in result["notes"] if "removed before the identification" in n]
    assert note.startswith("2160 sensor reading(s) removed"), note
    assert "S2 (kitchen): 2160, the first -999 C" in note
    assert "lists 1000 of them" in note and "the first 1000 of each" in note


def test_the_note_uses_the_true_counts():
    records = [
        {"sensor": "S2", "zone": "kitchen", "time": "2015-02-03T00:00:00+01:00",
         "value_C": -999.0, "flag": "impossible", "reason": "limits"},
    ]  # fmt: skip
    note = removed_readings_note(records, {"S2": 1500})
    assert note.startswith("1500 sensor reading(s) removed") and "S2 (kitchen): 1500" in note
    assert "lists 1 of them" in note
    assert "each with its time" in removed_readings_note(records, {"S2": 1})
