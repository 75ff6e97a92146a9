"""Dask distributed backend: equal results to the local pool; unreachable scheduler."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pandas as pd
import pytest
from calibration_evaluators import QuadraticEvaluator

from thermocal.calibration.runner import run_campaign
from thermocal.calibration.sampling import sample
from thermocal.calibration.space import ParameterSpace
from thermocal.calibration.store import CampaignStore, campaign_definition
from thermocal.errors import ThermocalInputError

distributed = pytest.importorskip("distributed")
HERE = Path(__file__).resolve().parent
PARAMS = {"material/a/conductivity": 1.0, "material/a/density": 2.0, "window/w/u_value": 1.5}


def _values(store):
    return store.to_frame().drop(columns=["runtime_s", "worker", "finished_at"])


def test_local_cluster_equals_local_pool(tmp_path, monkeypatch):
    # worker processes must import the evaluator's module
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(HERE), os.environ.get("PYTHONPATH",
                                                                                 "")]))
    space = ParameterSpace.from_parameters(PARAMS)
    samples = sample(space, 12, seed=4)
    definition = campaign_definition(space, method="sobol", seed=4, samples=12, problem="t")
    # one sample fails: failures travel through Dask too
    threshold = float(samples.values.iloc[:, 0].max()) - 1e-12
    with CampaignStore.open(tmp_path / "pool.sqlite", definition=definition) as store:
        run_campaign(QuadraticEvaluator(fail_above=threshold), samples.values, store, workers=2,
                     progress=False)
        expected = _values(store)
    log = tmp_path / "dask.log"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with CampaignStore.open(tmp_path / "dask.sqlite", definition=definition) as store:
            summary = run_campaign(QuadraticEvaluator(log=log, fail_above=threshold),
                                   samples.values, store, scheduler=cluster, progress=False)
            got = _values(store)
    assert summary.backend.startswith("dask(")
    pd.testing.assert_frame_equal(got, expected)
    assert got["error"].notna().sum() == 1
    text = log.read_text()
    assert 1 <= text.count("build") <= 2  # once per worker, not once per sample
    assert text.count("eval") == 11


def test_unreachable_scheduler_fails_fast_with_a_clear_message(tmp_path):
    space = ParameterSpace.from_parameters(PARAMS)
    samples = sample(space, 4, seed=1)
    definition = campaign_definition(space, method="sobol", seed=1, samples=4, problem="t")
    with CampaignStore.open(tmp_path / "s.sqlite", definition=definition) as store:
        start = time.monotonic()
        with pytest.raises(ThermocalInputError, match="no Dask scheduler answered within 2 s"):
            run_campaign(QuadraticEvaluator(), samples.values, store,
                         scheduler="tcp://127.0.0.1:9", connect_timeout=2.0, progress=False)
        assert time.monotonic() - start < 15
        with pytest.raises(ThermocalInputError, match="tcp://HOST:PORT"):
            run_campaign(QuadraticEvaluator(), samples.values, store, scheduler="localhost",
                         progress=False)
        assert store.count() == 0
