"""``thermocal calibrate --demo`` end to end (a short campaign on the clinic with known truth)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest


@pytest.mark.slow
def test_calibrate_demo_quick(tmp_path):
    from thermocal.commands.calibrate import DEMO_CAMPAIGN

    out = tmp_path / "cal"
    out.mkdir()
    # the demo's campaign file, calibrating every varied parameter (the published method):
    # 12 samples of 70 parameters determine none on their own, and the default (only the
    # determined ones, tests/calibration/test_calibration_reanalysis.py) keeps the nominal
    # (two refinement steps instead of eight: the refinement is checked in
    # test_calibration_workflow.py; each step is a full run and a meta-model fit)
    assert "optimisation: {starts: 8, seed: 1}" in DEMO_CAMPAIGN
    (out / "demo_campaign.yaml").write_text(
        DEMO_CAMPAIGN.replace(
            "optimisation: {starts: 8, seed: 1}",
            "optimisation: {starts: 8, seed: 1, calibrate: all, refine: 2}",
        )
    )
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "thermocal",
            "calibrate",
            "--demo",
            "--samples",
            "12",
            "--workers",
            "1",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "Traceback" not in done.stderr
    result = json.loads((out / "calibration.json").read_text())
    assert result["samples"]["successful"] == 12
    # 12 samples of 70 parameters: a meta-model no better than the mean is said to be so
    r2 = result["metamodel"]["cv_r2"]
    said = any("worse than their mean" in note for note in result["notes"])
    assert said == (r2 < 0.0), (r2, result["notes"])
    confirmed = result["confirmation"]
    # the calibrated model is better than the nominal one on the unoccupied variance
    assert confirmed["calibrated"]["confirmed"] < confirmed["nominal"]["confirmed"]
    assert len(result["table1"]) == 10
    perturbed = [r for r in result["truth_comparison"] if r["perturbed_in_truth"]]
    assert len(perturbed) == 10
    for name in (
        "calibrated_building.yaml",
        "table1.csv",
        "report.html",
        "campaign.sqlite",
        "sensitivity.png",
        "q_id_cases.png",
        "demo_campaign.yaml",
    ):
        assert (out / name).is_file(), name
    # resuming a finished campaign repeats nothing and gives the same table
    again = subprocess.run(
        [
            sys.executable,
            "-m",
            "thermocal",
            "calibrate",
            "--demo",
            "--samples",
            "12",
            "--workers",
            "1",
            "--out",
            str(out),
            "--resume",
        ],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert again.returncode == 0, again.stderr[-3000:]
    second = json.loads((out / "calibration.json").read_text())
    assert second["samples"]["successful"] == 12
    assert second["table1"] == result["table1"]
    # ... nor the analysis' model runs (confirmations, refinement): read from the store
    assert second["model_runs"]["simulated"] == 0, second["model_runs"]
    assert second["confirmation"]["calibrated"] == result["confirmation"]["calibrated"]
    # a re-analysis simulates nothing and, with nothing changed, gives the same results
    third = subprocess.run(
        [
            sys.executable,
            "-m",
            "thermocal",
            "calibrate",
            "--demo",
            "--reanalyse",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert third.returncode == 0, third.stderr[-3000:]
    reanalysed = json.loads((out / "calibration.json").read_text())
    assert reanalysed["model_runs"]["simulated"] == 0
    for key in ("table1", "confirmation", "posterior", "truth_comparison", "critical"):
        assert reanalysed[key] == second[key], key
    assert (out / "campaign.sqlite").is_file()
    # --advise: which plate would determine what; the demo's parameters are materials', so it
    # says why it has no advice, and the analysis is otherwise the same
    advised = subprocess.run(
        [sys.executable, "-m", "thermocal", "calibrate", "--demo", "--reanalyse", "--advise",
         "--out", str(out)],
        capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert advised.returncode == 0, advised.stderr[-3000:]
    with_advice = json.loads((out / "calibration.json").read_text())
    advice = with_advice["posterior"]["advice"]
    assert not advice["available"] and "parameters.level: element" in advice["reason"]
    for key in ("table1", "confirmation", "truth_comparison", "critical"):
        assert with_advice[key] == reanalysed[key], key
    for key, value in reanalysed["posterior"].items():
        if key not in ("advice", "sentences"):
            assert with_advice["posterior"][key] == value, key
    # more samples of the same sequence without --resume: refused, saying --resume extends it
    other = subprocess.run(
        [
            sys.executable,
            "-m",
            "thermocal",
            "calibrate",
            "--demo",
            "--samples",
            "13",
            "--workers",
            "1",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert other.returncode == 2 and "Traceback" not in other.stderr
    assert "pass --resume to extend it to 13" in other.stderr, other.stderr
    assert json.loads((out / "calibration.json").read_text()) == with_advice  # untouched
