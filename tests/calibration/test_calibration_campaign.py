"""Campaign store and runner: kill and resume, failures, foreign and broken stores."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import textwrap
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

HERE = Path(__file__).resolve().parent
PARAMS = {"material/a/conductivity": 1.0, "material/a/density": 2.0, "window/w/u_value": 1.5}
N = 16


def _campaign(n=N, seed=1, method="sobol"):
    space = ParameterSpace.from_parameters(PARAMS)
    samples = sample(space, n, method, seed=seed)
    definition = campaign_definition(space, method=method, seed=seed, samples=n, problem="test")
    return space, samples, definition


def _values(store: CampaignStore) -> pd.DataFrame:
    frame = store.to_frame()
    return frame.drop(columns=["runtime_s", "worker", "finished_at"])


SCRIPT = textwrap.dedent(
    """
    import sys
    sys.path.insert(0, {here!r})
    from calibration_evaluators import QuadraticEvaluator
    from thermocal.calibration.runner import run_campaign
    from thermocal.calibration.sampling import sample
    from thermocal.calibration.space import ParameterSpace
    from thermocal.calibration.store import CampaignStore, campaign_definition

    if __name__ == "__main__":
        params = {params!r}
        space = ParameterSpace.from_parameters(params)
        samples = sample(space, {n}, "sobol", seed=1)
        definition = campaign_definition(space, method="sobol", seed=1, samples={n},
                                         problem="test")
        store = CampaignStore.open(sys.argv[1], definition=definition, resume=True)
        evaluator = QuadraticEvaluator(log=sys.argv[2], sleep=float(sys.argv[3]))
        run_campaign(evaluator, samples.values, store, workers=int(sys.argv[4]), progress=False)
    """
)


def _evaluations(log: Path, samples: pd.DataFrame) -> list[int]:
    """Sample indices evaluated, from the evaluator's log (one line per finished evaluation)."""
    keys = {repr(sorted({k: float(v) for k, v in row.items()}.items())): int(i)
            for i, row in samples.iterrows()}
    out = []
    for line in log.read_text().splitlines():
        if line.startswith("eval "):
            out.append(keys[line.split(" ", 2)[2]])
    return out


@pytest.mark.parametrize("workers", [1, 2])
def test_killed_campaign_resumes_without_loss_or_repetition(tmp_path, workers):
    _, samples, definition = _campaign()
    script = tmp_path / "campaign.py"
    script.write_text(SCRIPT.format(here=str(HERE), params=PARAMS, n=N))
    store_path, log = tmp_path / "store.sqlite", tmp_path / "evaluations.log"

    proc = subprocess.Popen([sys.executable, str(script), str(store_path), str(log), "0.25",
                             str(workers)], start_new_session=True)
    deadline = time.monotonic() + 60
    committed = 0
    while time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
        if store_path.exists():
            try:
                with sqlite3.connect(store_path) as con:
                    committed = con.execute("SELECT COUNT(*) FROM results").fetchone()[0]
            except sqlite3.OperationalError:
                continue
            if committed >= 4:
                break
    assert proc.poll() is None, "the campaign finished before it could be killed"
    os.killpg(proc.pid, signal.SIGKILL)  # the whole campaign: parent and pool workers
    proc.wait()
    with CampaignStore.open(store_path, definition=definition) as store:
        done_at_kill = store.done()
    assert 4 <= len(done_at_kill) < N

    # resume: only the missing samples run
    subprocess.run([sys.executable, str(script), str(store_path), str(log), "0", str(workers)],
                   check=True, timeout=120)
    evaluated = _evaluations(log, samples.values)
    for i in done_at_kill:  # a committed sample is never evaluated again
        assert evaluated.count(i) == 1
    repeated = {i for i in evaluated if evaluated.count(i) > 1}
    # only samples in flight at the kill (at most one per worker) can be evaluated twice
    assert len(repeated) <= workers
    assert sorted(set(evaluated)) == list(range(N))

    reference_path = tmp_path / "reference.sqlite"
    with CampaignStore.open(reference_path, definition=definition) as ref:
        run_campaign(QuadraticEvaluator(), samples.values, ref, workers=1, progress=False)
        expected = _values(ref)
    with CampaignStore.open(store_path, definition=definition) as store:
        got = _values(store)
    pd.testing.assert_frame_equal(got, expected)
    assert got["error"].isna().all() and len(got) == N


def test_failed_sample_is_recorded_and_campaign_continues(tmp_path):
    _, samples, definition = _campaign()
    log = tmp_path / "log"
    first = samples.values.columns[0]
    threshold = float(samples.values[first].median())
    with CampaignStore.open(tmp_path / "s.sqlite", definition=definition) as store:
        summary = run_campaign(QuadraticEvaluator(log=log, fail_above=threshold), samples.values,
                               store, workers=1, progress=False)
        frame = store.to_frame()
        n_fail = int((samples.values[first] > threshold).sum())
        assert summary.evaluated == N and summary.failed == n_fail > 0
        failed = frame[frame["error"].notna()]
        assert len(failed) == n_fail
        assert failed["error"].str.contains("synthetic failure").all()
        assert failed["out:metric"].isna().all()
        assert len(store.outputs()) == N - n_fail
        # state built once (in-process: one build)
        assert log.read_text().count("build") == 1
        # a rerun has nothing to do; retry_failed re-runs only the failures
        again = run_campaign(QuadraticEvaluator(), samples.values, store, workers=1,
                             progress=False)
        assert again.evaluated == 0 and again.already_done == N
        retry = run_campaign(QuadraticEvaluator(), samples.values, store, workers=1,
                             progress=False, retry_failed=True)
        assert retry.evaluated == n_fail and store.count(failed=True) == 0


def test_pool_builds_the_evaluator_once_per_worker(tmp_path):
    _, samples, definition = _campaign()
    log = tmp_path / "log"
    with CampaignStore.open(tmp_path / "s.sqlite", definition=definition) as store:
        run_campaign(QuadraticEvaluator(log=log), samples.values, store, workers=2,
                     progress=False)
        assert store.count() == N
    text = log.read_text()
    assert 1 <= text.count("build") <= 2
    assert text.count("eval") == N


def test_store_of_another_campaign_refuses(tmp_path):
    _, samples, definition = _campaign()
    path = tmp_path / "s.sqlite"
    with CampaignStore.open(path, definition=definition, campaign_text="a: 1") as store:
        run_campaign(QuadraticEvaluator(), samples.values.iloc[:3], store, workers=1,
                     progress=False)
        assert store.meta("campaign_text") == "a: 1"
    _, _, other = _campaign(seed=2)
    with pytest.raises(ThermocalInputError, match="belongs to another campaign") as info:
        CampaignStore.open(path, definition=other)
    message = str(info.value)
    assert str(path) in message and "sampler.seed: 1 in the store, 2 now" in message
    # no --store option exists (it named one): the campaign file's store: key or --out
    assert "--store" not in message and "the campaign file's store: key" in message
    # a list of ranges names its campaign key and the entries that changed
    from thermocal.calibration.store import _definition_differences

    old_space = {"space": {"relative_range": [0.5] * 47}}
    new_space = {"space": {"relative_range": [0.5] * 46 + [0.4]}}
    assert _definition_differences(old_space, new_space) == [
        "space.relative_range (parameters.default_range / parameters.ranges): entry 46: 0.5 in "
        "the store, 0.4 now"
    ]
    with pytest.raises(ThermocalInputError, match="--resume"):
        CampaignStore.open(path, definition=definition, resume=False)


@pytest.mark.parametrize("content", [b"this is not a database\n", b"\x00" * 200])
def test_non_sqlite_store_is_refused(tmp_path, content):
    path = tmp_path / "results.sqlite"
    path.write_bytes(content)
    _, _, definition = _campaign()
    with pytest.raises(ThermocalInputError, match="not an SQLite database|not a usable SQLite"):
        CampaignStore.open(path, definition=definition)


def test_export_parquet_and_csv(tmp_path):
    _, samples, definition = _campaign()
    with CampaignStore.open(tmp_path / "s.sqlite", definition=definition) as store:
        run_campaign(QuadraticEvaluator(), samples.values, store, workers=1, progress=False)
        pq = store.export(tmp_path / "out" / "results.parquet")
        csv = store.export(tmp_path / "out" / "results.csv")
        frame = store.to_frame()
        with pytest.raises(ThermocalInputError, match=".parquet or .csv"):
            store.export(tmp_path / "results.xlsx")
    back = pd.read_parquet(pq)
    pd.testing.assert_frame_equal(back, frame)
    assert len(pd.read_csv(csv)) == N
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["results.csv",
                                                                   "results.parquet"]
