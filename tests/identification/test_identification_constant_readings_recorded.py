"""Accepted long constant readings are kept with the results, not only said on the console.

Before: a sensor reading one value for a day or more that a set point, the log's resolution
or the mapping's ``constant_readings: accept`` explained was accepted with a console warning
only; identification.json and the report did not say which readings were taken as a held room.
Now each accepted run is a record under ``accepted_constant_readings`` (sensor, zone, value,
start, end, duration, why) and each sensor a note in ``notes`` and the report.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from test_identification_constant_readings import STEP, TIMES, _grid, _mapping, _setpoints

from conftest import shared_data_path
from thermocal.errors import ThermocalInputError
from thermocal.identification.sensors import (
    ReferenceReport,
    accepted_constant_notes,
    check_sensor_plausibility,
)


def _accepted(grid, mapping=None, **kwargs) -> list[dict]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return check_sensor_plausibility(
            grid, mapping or _mapping(), STEP, "log.csv", raw=grid, **kwargs
        )


def test_an_accepted_run_is_returned_as_a_record():
    records = _accepted(_grid(20.0, resolution=0.01), setpoints=_setpoints(20.0, 26.0))
    assert len(records) == 1
    record = records[0]
    assert {k: record[k] for k in ("sensor", "zone", "value_C", "duration_h")} == {
        "sensor": "S1", "zone": "office", "value_C": 20.0, "duration_h": 36.0,
    }  # fmt: skip
    assert record["start"] == str(TIMES[96]) and record["end"] == str(TIMES[96 + 144])
    assert record["why"].startswith("20 C is the heating set point the building declares")


@pytest.mark.parametrize(
    ("kwargs", "why"),
    [
        ({}, r"the log's resolution of 0\.1 K explains it"),
        ({"mapping": _mapping(constant_readings="accept")},
         r"'constant_readings' in mapping\.yaml accepts it"),
        ({"mapping": _mapping(constant_readings={"S1": "accept"})},
         r"'constant_readings' in mapping\.yaml accepts it"),
    ],
    ids=["resolution", "mapping-all", "mapping-sensor"],
)  # fmt: skip
def test_every_rule_names_its_reason_in_the_record(kwargs, why):
    records = _accepted(_grid(20.0, resolution=0.1), **kwargs)
    assert [r["sensor"] for r in records] == ["S1"]
    assert re.search(why, records[0]["why"]), records[0]["why"]


def test_nothing_constant_or_refused_records_nothing():
    hours = np.arange(len(TIMES)) * 0.25
    moving = pd.DataFrame({"S1": 20 + 0.5 * np.sin(hours), "S2": 19 + np.cos(hours)}, TIMES)
    assert _accepted(moving) == []
    with pytest.raises(ThermocalInputError, match="reads exactly 20 C"):
        _accepted(_grid(20.0, resolution=0.01))  # no rule explains it: nothing accepted


def test_the_notes_say_each_sensor_once():
    records = _accepted(_grid(20.0, resolution=0.1))
    notes = accepted_constant_notes(records + [dict(records[0], start="2024-01-20 00:00")])
    assert len(notes) == 1
    start = records[0]["start"]
    assert notes[0].startswith(
        "Constant reading accepted: sensor 'S1' (zone 'office') reads exactly 20 C from "
        f"{start} for 1.5 days (the log's"
    )
    assert "from 2024-01-20 00:00" in notes[0]
    assert "accepted_constant_readings in identification.json" in notes[0]
    report = ReferenceReport({}, pd.DataFrame(), pd.DataFrame(), None, records)
    assert report.constant_notes() == accepted_constant_notes(records)
    assert ReferenceReport({}, pd.DataFrame(), pd.DataFrame(), None).constant_notes() == []


def test_identify_writes_the_accepted_readings(tmp_path):
    """The command on a two-room building (set points 20 C) whose living-room sensor reads
    exactly 20.0 C for 1.5 days: accepted by the set point, in identification.json (the
    record and a note) and in report.html."""
    doc = (Path(__file__).parents[2] / "docs" / "multizone-file.md").read_text()
    building = tmp_path / "two_rooms.yaml"
    building.write_text(re.search(r"## Example\s+```yaml\n(.*?)```", doc, re.S).group(1))
    mapping = tmp_path / "mapping.yaml"
    mapping.write_text("sensors: {S1: living, S2: kitchen}\n")
    times = pd.date_range("2015-02-02", periods=3 * 96, freq="15min")
    hours = np.arange(len(times)) * 0.25
    s1 = 20.0 + 0.4 * np.sin(2 * np.pi * hours / 24)
    held = (times >= "2015-02-03") & (times < "2015-02-04 12:00")
    s1[held] = 20.0
    s2 = 19.0 + 0.5 * np.sin(2 * np.pi * hours / 24 + 1)
    log = tmp_path / "log.csv"
    pd.DataFrame({"time": times.astype(str), "S1": s1.round(3), "S2": s2.round(3)}).to_csv(
        log, index=False
    )
    out = tmp_path / "out"
    weather = shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
    done = subprocess.run(
        [sys.executable, "-m", "thermocal", "identify", building, weather, log, "--mapping",
         mapping, "--out", out, "--method", "inverse", "--tz", "1", "--no-clock-check"],
        capture_output=True, text=True,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "not refused as a stuck sensor" in " ".join(done.stderr.split())  # the warning
    result = json.loads((out / "identification.json").read_text())
    (record,) = result["accepted_constant_readings"]
    assert (record["sensor"], record["zone"], record["value_C"]) == ("S1", "living", 20.0)
    assert record["duration_h"] >= 24 and "heating set point" in record["why"]
    notes = [n for n in result["notes"] if n.startswith("Constant reading accepted")]
    assert len(notes) == 1 and "sensor 'S1' (zone 'living')" in notes[0]
    html = (out / "report.html").read_text()
    assert "Constant reading accepted: sensor" in html.replace("&#x27;", "'")
