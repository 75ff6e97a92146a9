"""``thermocal identify`` on the built-in demo and with bad arguments."""

from __future__ import annotations

import json
import subprocess
import sys


def _run(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "thermocal", *args], capture_output=True, text=True, cwd=cwd
    )


def test_identify_demo_writes_results(tmp_path):
    out = tmp_path / "ident"
    done = _run("identify", "--demo", "--out", str(out))
    assert done.returncode == 0, done.stderr
    result = json.loads((out / "identification.json").read_text())
    assert result["metric_source"] == "inverse"
    assert result["tuning"]["experiment_vs_exact_gain_ratio"] == __import__("pytest").approx(
        1.0, abs=0.01
    )
    kinds = {zone["source"] for zone in result["zones"]}
    assert kinds == {"sensor", "neighbour", "named"}
    assert len(result["zones"]) == 186
    # the identified heat's uncertainty from the sensors' accuracy: stated per zone and for
    # the building; zones following a neighbour's sensor share its offset
    uncertainty = result["sensor_uncertainty"]
    assert uncertainty["accuracy_K"] == 0.2
    assert uncertainty["sensors"] < len(uncertainty["independent"]["zones"])
    assert 0 < uncertainty["independent"]["building_kwh"] < uncertainty["shared"]["building_kwh"]
    assert any(note.startswith("Sensor accuracy") for note in result["notes"])
    for name in ("q_id.parquet", "report.html", "building_q_id.png", "tuning_oscillation.png"):
        assert (out / name).is_file()
    assert "Traceback" not in done.stderr


def test_identify_without_inputs_is_a_clear_error(tmp_path):
    done = _run("identify", "--out", str(tmp_path / "x"))
    assert done.returncode == 2
    assert "identify needs BUILDING, WEATHER, SENSORS, --mapping" in done.stderr
    assert "Traceback" not in done.stderr


def test_identify_radiant_fraction_out_of_range_is_a_clear_error(tmp_path):
    done = _run("identify", "--demo", "--radiant-fraction", "1.5", "--out", str(tmp_path / "x"))
    assert done.returncode == 2
    assert "--radiant-fraction '1.5': give a number in [0, 1]" in done.stderr
    assert "or declared" in done.stderr and "Traceback" not in done.stderr


def test_sensor_accuracy_out_of_range_is_a_clear_error(tmp_path):
    done = _run("identify", "--demo", "--sensor-accuracy", "0", "--out", str(tmp_path / "x"))
    assert done.returncode == 2
    assert "--sensor-accuracy 0: give a sensor's standard uncertainty" in done.stderr
