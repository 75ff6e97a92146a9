"""Re-analysis of a stored campaign: another metric or meta-model without simulating again."""

from __future__ import annotations

import json

import numpy as np
import pytest
from test_calibration_workflow import _campaign

from thermocal.calibration.config import load_campaign
from thermocal.calibration.workflow import calibrate, reanalyse
from thermocal.errors import ThermocalInputError
from thermocal.identification.problem import IdentificationProblem


def _comparable(result) -> dict:
    data = result.as_dict()
    data.pop("timings_s")
    data.pop("model_runs")
    data["samples"].pop("wall_time_s")
    data["samples"].pop("backend")
    return data


@pytest.fixture(scope="module")
def stored(tmp_path_factory):
    folder = tmp_path_factory.mktemp("reanalysis")
    path = _campaign(folder, samples=24)
    text = path.read_text().replace("{starts: 4, seed: 1}", "{starts: 2, seed: 1, refine: 2}")
    path.write_text(text)
    result = calibrate(
        load_campaign(path),
        workers=1,
        store_path=folder / "store.sqlite",
        progress=False,
        log=lambda line: None,
    )
    return folder, path, result


@pytest.fixture()
def no_simulation(monkeypatch):
    """Counts the model runs (a re-analysis must make none)."""
    calls = []
    original = IdentificationProblem.run

    def counted(self, parameters=None):
        calls.append(parameters)
        return original(self, parameters)

    monkeypatch.setattr(IdentificationProblem, "run", counted)
    return calls


def test_reanalysis_reproduces_the_campaign_without_simulating(stored, no_simulation):
    folder, path, original = stored
    # by default the calibrated model changes only what the posterior says the data determine
    determined = original.posterior.determined
    assert original.confirmed["calibrated_parameters"] == [
        n for n in original.space.names if n in determined
    ]
    calibrated = original.calibrated_building.parameters()
    nominal = original.space.nominal_dict()
    for name in original.space.names:
        if name not in determined:
            assert calibrated[name] == pytest.approx(nominal[name], rel=1e-12), name
    assert original.runs["simulated"] >= 4  # nominal, minimum, maximum, refinement...
    again = reanalyse(load_campaign(path), folder / "store.sqlite", log=lambda line: None)
    assert no_simulation == []
    assert again.runs["simulated"] == 0 and again.runs["from_store"] >= 4
    assert _comparable(again) == _comparable(original)
    assert again.calibrated_building_text() == original.calibrated_building_text()
    written = {p.name for p in again.to_files(folder / "again")}
    assert {"report.html", "q_id_cases.png", "calibration.json"} <= written


def test_reanalysis_with_another_metamodel_and_metric(stored, no_simulation):
    folder, path, original = stored
    text = path.read_text()
    other = folder / "other.yaml"
    other.write_text(text.replace("kind: auto", "kind: svr") + "metric: groups\n")
    again = reanalyse(load_campaign(other), folder / "store.sqlite", log=lambda line: None)
    assert no_simulation == []
    assert type(again.surrogate).__name__ == "SVRSurrogate"
    assert again.metric == "groups"
    assert json.loads(json.dumps(again.as_dict()))["metric"] == "groups"
    # the calibrated model is a confirmed one (stored), never an unconfirmed prediction
    assert np.isfinite(again.confirmed["calibrated"]["confirmed"])
    assert again.confirmed["calibrated"]["confirmed"] <= again.nominal_metric


def test_reanalysis_of_another_campaign_is_refused(stored, tmp_path):
    folder, path, _ = stored
    other = tmp_path / "other.yaml"
    other.write_text(
        path.read_text()
        .replace("default_range: 0.6", "default_range: 0.5")
        .replace("building: building.yaml", f"building: {folder}/building.yaml")
        .replace("sensors: sensors.csv", f"sensors: {folder}/sensors.csv")
        .replace("mapping: mapping.yaml", f"mapping: {folder}/mapping.yaml")
    )
    with pytest.raises(ThermocalInputError, match="another campaign.*space"):
        reanalyse(load_campaign(other), folder / "store.sqlite", log=lambda line: None)
    with pytest.raises(ThermocalInputError, match="does not exist"):
        reanalyse(load_campaign(path), tmp_path / "none.sqlite", log=lambda line: None)


def test_reanalyse_cli_bad_input(tmp_path):
    import subprocess
    import sys

    def run(*args):
        return subprocess.run(
            [sys.executable, "-m", "thermocal", "calibrate", *args],
            capture_output=True,
            text=True,
            timeout=300,
        )

    done = run("--demo", "--reanalyse", "--out", str(tmp_path / "none"))
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "holds no demo campaign" in done.stderr, done.stderr
    done = run("--demo", "--reanalyse", "--samples", "3", "--out", str(tmp_path / "none"))
    assert done.returncode == 2 and "leave out --samples" in done.stderr, done.stderr


def test_an_uncertain_input_runs_once_is_kept_and_read_by_a_reanalysis(stored, no_simulation):
    """``posterior.uncertain`` on a stored campaign: a re-analysis cannot simulate the input's
    run (noted, nothing integrated out); ``--resume`` simulates it once and keeps it; a
    re-analysis then reads it and integrates the input out without simulating."""
    folder, path, original = stored
    uncertain = folder / "uncertain.yaml"
    uncertain.write_text(
        path.read_text() + "posterior: {uncertain: {'infiltration/row * west/ach': 0.4}}\n"
    )
    label = "infiltration/row * west/ach"
    first = reanalyse(load_campaign(uncertain), folder / "store.sqlite", log=lambda line: None)
    assert no_simulation == []
    assert any("Not marginalised" in note and label in note for note in first.notes)
    assert first.posterior.uncertain == []
    resumed = calibrate(
        load_campaign(uncertain),
        workers=1,
        store_path=folder / "store.sqlite",
        resume=True,
        progress=False,
        log=lambda line: None,
    )
    perturbed = [p for p in no_simulation if p and all("west" in name for name in p)]
    assert len(perturbed) == 1 and len(perturbed[0]) == 2  # both rows' west groups, one run
    (item,) = resumed.posterior.uncertain
    assert item["label"] == label and item["effect"]
    del no_simulation[:]
    again = reanalyse(load_campaign(uncertain), folder / "store.sqlite", log=lambda line: None)
    assert no_simulation == []
    assert again.posterior.uncertain == resumed.posterior.uncertain
    assert not any("Not marginalised" in note for note in again.notes)
    assert again.posterior.summary["q95"].to_dict() == resumed.posterior.summary["q95"].to_dict()
