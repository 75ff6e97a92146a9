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


def test_identify_writes_the_removed_readings(tmp_path):
    """The command on a two-room building whose living-room sensor reads 85 C once (a
    DS18B20's power-on value) and whose kitchen sensor reads -999 (a missing-value code)."""
    doc = (Path(__file__).parents[2] / "docs" / "multizone-file.md").read_text()
    building = tmp_path / "two_rooms.yaml"
    building.write_text(re.search(r"## Example\s+```yaml\n(.*?)```", doc, re.S).group(1))
    mapping = tmp_path / "mapping.yaml"
    mapping.write_text("sensors: {S1: living, S2: kitchen}\n")
    times = pd.date_range("2015-02-02", periods=3 * 96, freq="15min")
    hours = np.arange(len(times)) * 0.25
    s1 = (20.0 + 0.4 * np.sin(2 * np.pi * hours / 24)).round(3)
    s2 = (19.0 + 0.5 * np.sin(2 * np.pi * hours / 24 + 1)).round(3)
    s1[150] = 85.0
    s2[200] = -999.0
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
    said = " ".join(done.stderr.split())
    assert "removed_readings in identification.json lists each" in said, said
    result = json.loads((out / "identification.json").read_text())
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
    html = (out / "report.html").read_text()
    assert "2 sensor reading(s) removed before the identification" in html
