"""``thermocal calibrate --demo`` end to end (a short campaign on the clinic with known truth)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest


@pytest.mark.slow
def test_calibrate_demo_quick(tmp_path):
    out = tmp_path / "cal"
    done = subprocess.run(
        [sys.executable, "-m", "thermocal", "calibrate", "--demo", "--samples", "12",
         "--workers", "1", "--out", str(out)],
        capture_output=True, text=True, timeout=900,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "Traceback" not in done.stderr
    result = json.loads((out / "calibration.json").read_text())
    assert result["samples"]["successful"] == 12
    confirmed = result["confirmation"]
    # the calibrated model is better than the nominal one on the unoccupied variance
    assert confirmed["calibrated"]["confirmed"] < confirmed["nominal"]["confirmed"]
    assert len(result["table1"]) == 10
    perturbed = [r for r in result["truth_comparison"] if r["perturbed_in_truth"]]
    assert len(perturbed) == 10
    for name in ("calibrated_building.yaml", "table1.csv", "report.html", "campaign.sqlite",
                 "sensitivity.png", "q_id_cases.png", "demo_campaign.yaml"):
        assert (out / name).is_file(), name
    # resuming a finished campaign repeats nothing and gives the same table
    again = subprocess.run(
        [sys.executable, "-m", "thermocal", "calibrate", "--demo", "--samples", "12",
         "--workers", "1", "--out", str(out), "--resume"],
        capture_output=True, text=True, timeout=900,
    )
    assert again.returncode == 0, again.stderr[-3000:]
    second = json.loads((out / "calibration.json").read_text())
    assert second["samples"]["successful"] == 12
    assert second["table1"] == result["table1"]
    # more samples of the same sequence without --resume: refused, saying --resume extends it
    other = subprocess.run(
        [sys.executable, "-m", "thermocal", "calibrate", "--demo", "--samples", "13",
         "--workers", "1", "--out", str(out)],
        capture_output=True, text=True, timeout=900,
    )
    assert other.returncode == 2 and "Traceback" not in other.stderr
    assert "pass --resume to extend it to 13" in other.stderr, other.stderr
    assert json.loads((out / "calibration.json").read_text()) == second  # untouched
