"""The zoom stage: its box, its design, the local refit that removes the global fit's curvature
bias, its runs kept in the store (a resume simulates nothing) and its configuration."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from calibration_evaluators import QuadraticEvaluator, roof_and_wall_heat

from conftest import reference_run
from thermocal.calibration.config import load_campaign
from thermocal.calibration.sampling import unit_sample
from thermocal.calibration.store import CampaignStore
from thermocal.calibration.surrogate import SeriesSurrogate
from thermocal.calibration.workflow import RunCache
from thermocal.calibration.zoom import (
    ZOOM_MIN_HALF_WIDTH,
    box_space,
    inside_box,
    narrowed,
    run_zoom,
    zoom_box,
    zoom_design,
)
from thermocal.errors import ThermocalInputError

ROOF, WALL = "construction/ROOF/resistance", "construction/WALL/resistance"
NAMES = [ROOF, WALL]
NOMINAL = {ROOF: 1.0, WALL: 1.0}
TRUTH = np.array([1.5, 0.7])
FILMS = 0.05  # [m2 K/W]


def _hourly_heat(X: np.ndarray) -> np.ndarray:
    """The two elements' heat at this test's truth and films (:func:`roof_and_wall_heat`) [W]."""
    return roof_and_wall_heat(X, TRUTH, FILMS)


def _series_minimum(X: pd.DataFrame, lower, upper) -> np.ndarray:
    """The affine-in-log series meta-model's minimum over the box, fitted on ``X``."""
    series = _hourly_heat(X.to_numpy())
    y = series.var(axis=1)
    model = SeriesSurrogate(series=series, nominal=NOMINAL, cv_folds=0).fit(X, y)
    x, _ = model.box_optimum("min", lower, upper)
    return np.asarray(x)


def test_local_refit_removes_the_global_fits_curvature_bias():
    lower, upper = np.array([0.25, 0.25]), np.array([1.75, 1.75])
    X = pd.DataFrame(lower + unit_sample(2, 48, seed=1) * (upper - lower), columns=NAMES)
    first = _series_minimum(X, lower, upper)
    # the straight line in log R fitted over +-75 % misses the truth (diagnose_roof.md)
    assert np.max(np.abs(first / TRUTH - 1.0)) > 0.03, first
    # a box of +-3 sd of a first posterior (sd 5 % in log p), at least +-10 %
    box_lower, box_upper = zoom_box(lower, upper, first, [0.05, 0.05])
    assert np.all(box_lower <= TRUTH) and np.all(TRUTH <= box_upper), (box_lower, box_upper)
    local = zoom_design(NAMES, box_lower, box_upper, 32, seed=2)
    assert inside_box(local, box_lower, box_upper).all()
    second = _series_minimum(local, box_lower, box_upper)
    assert np.abs(second / TRUTH - 1.0) == pytest.approx([0, 0], abs=0.01), second
    assert np.all(np.abs(second / TRUTH - 1.0) < np.abs(first / TRUTH - 1.0))


def test_zoom_box_width_and_clipping():
    lower, upper = np.array([0.25, 0.25, 0.25, 0.25]), np.array([1.75, 1.75, 1.75, 1.75])
    center = np.array([1.0, 1.0, 1.7, 1.0])
    sd = np.array([0.001, 0.05, 0.05, np.nan])
    lo, hi = zoom_box(lower, upper, center, sd)
    # a very narrow posterior: the smallest half-width
    assert np.log(hi[0] / center[0]) == pytest.approx(ZOOM_MIN_HALF_WIDTH)
    assert np.log(center[0] / lo[0]) == pytest.approx(ZOOM_MIN_HALF_WIDTH)
    # otherwise +-3 sd in log p
    assert np.log(hi[1] / lo[1]) == pytest.approx(6 * 0.05)
    # clipped to the campaign's bounds; a parameter without a posterior keeps its range
    assert hi[2] == pytest.approx(1.75) and lo[2] == pytest.approx(1.7 * np.exp(-0.15))
    assert (lo[3], hi[3]) == pytest.approx((0.25, 1.75))
    design = zoom_design(["a", "b", "c", "d"], lo, hi, 64, seed=3)
    assert inside_box(design, lo, hi).all()
    # uniform in log p: as many points below the box's geometric centre as above
    below = (np.log(design["b"]) < np.log(lo[1] * hi[1]) / 2).mean()
    assert below == pytest.approx(0.5, abs=0.1)


def test_no_zoom_where_the_first_posterior_narrows_nothing():
    lower, upper = np.array([0.25, 0.25]), np.array([1.75, 1.75])
    # a wide posterior (sd 0.3 in log p: +-3 sd spans most of the range) narrows nothing
    lo, hi = zoom_box(lower, upper, [1.0, 1.0], [0.3, 0.3])
    assert not narrowed(lower, upper, lo, hi).any()
    lo, hi = zoom_box(lower, upper, [1.0, 1.0], [0.3, 0.04])
    assert narrowed(lower, upper, lo, hi).tolist() == [False, True]


def test_box_space_keeps_the_names_nominal_values_and_limits():
    from thermocal.calibration.space import ParameterSpace

    space = ParameterSpace.from_parameters({ROOF: 2.0, WALL: 3.0}, default_range=0.75)
    box = box_space(space, [1.8, 2.5], [2.2, 3.5])
    assert box.names == space.names and np.allclose(box.nominal, space.nominal)
    assert np.allclose(box.lower, [1.8, 2.5]) and np.allclose(box.upper, [2.2, 3.5])
    assert np.allclose(box.limit_lower, space.limit_lower)


class _Refuses(QuadraticEvaluator):
    def evaluate(self, parameters):
        raise AssertionError("a stored zoom sample was simulated again")


def test_zoom_runs_are_stored_and_reused(tmp_path):
    """The zoom campaign's runs go to the store: a resume simulates nothing, a larger zoom only
    its new points, a re-analysis (no evaluator) reads them."""
    lo, hi = np.array([0.8, 0.9]), np.array([1.2, 1.1])
    path = tmp_path / "campaign.sqlite"
    with CampaignStore.open(path, definition={"test": "zoom"}) as store:
        runs = RunCache(store, QuadraticEvaluator(), workers=1)
        X, outputs, counts = run_zoom(runs, zoom_design(NAMES, lo, hi, 12, seed=2))
        assert counts == {"simulated": 12, "from_store": 0, "failed": 0, "missing": 0}
        assert runs.simulated == 12 and len(X) == 12
        expected = ((X - 1.0) ** 2).sum(axis=1).to_numpy()
        assert outputs["metric"].to_numpy() == pytest.approx(expected)
    with CampaignStore.open(path, definition={"test": "zoom"}) as store:
        runs = RunCache(store, _Refuses(), workers=1)
        again, outputs_again, counts = run_zoom(runs, zoom_design(NAMES, lo, hi, 12, seed=2))
        assert counts["simulated"] == 0 and counts["from_store"] == 12 and runs.simulated == 0
        pd.testing.assert_frame_equal(outputs_again, outputs)
        # Sobol' designs grow: 16 points with the same seed start with the 12
        runs = RunCache(store, QuadraticEvaluator(), workers=1)
        _, _, counts = run_zoom(runs, zoom_design(NAMES, lo, hi, 16, seed=2))
        assert counts["simulated"] == 4 and counts["from_store"] == 12
        reader = RunCache(store)
        _, read, counts = run_zoom(reader, zoom_design(NAMES, lo, hi, 20, seed=2))
        assert counts == {"simulated": 0, "from_store": 16, "failed": 0, "missing": 4}
        assert len(read) == 16


def _campaign(folder, sampling: str):
    path = folder / "campaign.yaml"
    path.write_text(f"building: demo:clinic\nsampling: {sampling}\n")
    return path


def test_zoom_configuration(tmp_path):
    assert load_campaign(_campaign(tmp_path, "{samples: 64}")).sampling.zoom == 0
    assert load_campaign(_campaign(tmp_path, "{samples: 64, zoom: 0}")).sampling.zoom == 0
    assert load_campaign(_campaign(tmp_path, "{zoom: 48}")).sampling.zoom == 48
    # the zoom is a stage of the analysis: it leaves the first campaign's fingerprint alone
    a = load_campaign(_campaign(tmp_path, "{samples: 64, zoom: 0}")).fingerprint()
    assert a == load_campaign(_campaign(tmp_path, "{samples: 64, zoom: 16}")).fingerprint()
    for bad in ("5", "-1", "many", "true", "12.5"):
        with pytest.raises(ThermocalInputError, match=r"sampling\.zoom: .*0 \(off\).*at least 10"):
            load_campaign(_campaign(tmp_path, f"{{samples: 64, zoom: {bad}}}"))


@reference_run
def test_zoom_stage_in_the_workflow_resumes_and_reanalyses_without_simulating(tmp_path):
    """The clinic campaign of test_calibration_workflow with a zoom stage: it runs, says so
    (calibration.json, report), a resume and a re-analysis simulate nothing and agree."""
    from test_calibration_reanalysis import _comparable
    from test_calibration_workflow import _campaign

    from thermocal.calibration.workflow import calibrate, reanalyse

    path = _campaign(tmp_path, samples=24, zoom=16)
    store = tmp_path / "store.sqlite"

    def run(resume):
        return calibrate(
            load_campaign(path), workers=1, store_path=store, resume=resume, progress=False,
            log=lambda line: None,
        )  # fmt: skip

    first = run(False)
    zoom = first.as_dict()["zoom"]
    assert zoom is not None and zoom["runs"]["simulated"] == 16 and zoom["local_samples"] == 16
    assert any(note.startswith("Zoom stage: a second campaign of 16") for note in first.notes)
    again = run(True)
    assert again.runs["simulated"] == 0 and again.zoom["runs"]["from_store"] == 16
    stored = reanalyse(load_campaign(path), store, log=lambda line: None)
    assert stored.runs["simulated"] == 0

    def same(result):
        data = _comparable(result)
        data["zoom"].pop("runs")
        return data

    assert same(again) == same(first) == same(stored)
    written = {p.name for p in first.to_files(tmp_path / "out")}
    assert "report.html" in written
    assert "Zoom stage" in (tmp_path / "out" / "report.html").read_text()
