"""Durable result store of a calibration campaign (SQLite).

One row per finished sample, committed as the sample finishes, so a campaign killed at any point
(SIGKILL included) keeps every committed result and a restart evaluates only what is missing.
The ``campaign`` table holds a fingerprint of the campaign definition; a store opened for another
definition refuses with a message saying what differs.

Tables
------
``campaign(key TEXT PRIMARY KEY, value TEXT)``
    ``fingerprint``, ``definition`` (JSON), ``campaign_text`` (the campaign file), ``created_at``,
    ``schema_version``.
``results(sample INTEGER PRIMARY KEY, parameters TEXT, outputs TEXT, runtime_s REAL, error TEXT,
worker TEXT, finished_at TEXT)``
    ``parameters`` and ``outputs`` are JSON objects (name -> value); ``error`` is NULL for a
    successful sample; ``runtime_s`` is the evaluation wall time [s].
``runs(key TEXT PRIMARY KEY, parameters TEXT, outputs TEXT, heat TEXT)``
    The model runs of the analysis besides the samples (nominal, confirmations, posterior
    median, refinement steps), keyed by their parameter values, with the building-wide
    identified heat per step (``{"start", "step_s", "values"}``): a re-analysis finds them here
    instead of simulating again.
``campaign`` keys ``info:<name>``
    What the analysis needs besides the samples (the chosen unoccupied hours, the zone groups,
    the weather on the simulation grid), JSON.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import math
import sqlite3
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.io.atomic import atomic_write
from thermocal.io.output import FileLock, _describe_os_error

__all__ = [
    "CampaignStore",
    "SampleResult",
    "atomic_write",
    "campaign_definition",
    "campaign_fingerprint",
]

SCHEMA_VERSION = "1"
_SQLITE_MAGIC = b"SQLite format 3\x00"


def _canonical(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=_json_default)


def _json_default(obj: Any) -> Any:
    if hasattr(obj, "item"):
        return obj.item()
    if hasattr(obj, "tolist"):
        return obj.tolist()
    if isinstance(obj, Path | _dt.date):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj)}")


def campaign_definition(
    space: Any,
    *,
    method: str,
    seed: int,
    samples: int,
    problem: str | Mapping[str, Any],
) -> dict[str, Any]:
    """The campaign definition that the store's fingerprint covers.

    Parameters
    ----------
    space : ParameterSpace or mapping
        The parameter space (its :meth:`to_dict` is used) [-].
    method : str
        Sampler name [-].
    seed : int
        Sampler seed [-].
    samples : int
        Number of samples [-].
    problem : str or mapping
        Everything else that determines the metric (building, weather, measurements,
        identification options), supplied by the caller: best a mapping of named settings
        (file digests, period, options), so that a mismatch names the setting in words [-].

    Returns
    -------
    dict
        JSON-ready definition.
    """
    space_dict = space.to_dict() if hasattr(space, "to_dict") else dict(space)
    return {
        "space": space_dict,
        "sampler": {"method": str(method), "seed": int(seed), "samples": int(samples)},
        "problem": json.loads(_canonical(problem))
        if isinstance(problem, Mapping)
        else str(problem),
    }


def campaign_fingerprint(definition: Mapping[str, Any]) -> str:
    """SHA-256 hex digest of a campaign definition (canonical JSON, sorted keys).

    Parameters
    ----------
    definition : mapping
        As returned by :func:`campaign_definition` (or any JSON-ready mapping) [-].

    Returns
    -------
    str
        64 hexadecimal characters.
    """
    return hashlib.sha256(_canonical(definition).encode()).hexdigest()


@dataclass(frozen=True)
class SampleResult:
    """The outcome of one sample.

    Attributes
    ----------
    sample : int
        Sample index [-].
    parameters : dict
        Parameter values [unit of each parameter].
    outputs : dict
        Named outputs, e.g. ``{"unoccupied_variance": ...}`` [unit of each output]; empty when
        the sample failed.
    runtime_s : float
        Evaluation wall time [s].
    error : str or None
        Error text of a failed sample, None when it succeeded.
    worker : str
        Host and process that evaluated it.
    """

    sample: int
    parameters: dict[str, float]
    outputs: dict[str, float]
    runtime_s: float
    error: str | None = None
    worker: str = ""


def _is_digest(value: Any) -> bool:
    return (
        isinstance(value, str) and len(value) >= 32 and all(c in "0123456789abcdef:" for c in value)
    )


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _definition_differences(old: Mapping[str, Any], new: Mapping[str, Any]) -> list[str]:
    diffs: list[str] = []

    def walk(a: Any, b: Any, where: str) -> None:
        if isinstance(a, Mapping) and isinstance(b, Mapping):
            for k in sorted(set(a) | set(b), key=str):
                walk(a.get(k), b.get(k), f"{where}.{k}" if where else str(k))
        elif a != b:
            where_text = where + (f" ({CAMPAIGN_KEYS[where]})" if where in CAMPAIGN_KEYS else "")
            if isinstance(a, list) and isinstance(b, list) and len(a) > 6:
                changed = [i for i in range(min(len(a), len(b))) if a[i] != b[i]]
                if len(a) == len(b) and changed:
                    shown = ", ".join(
                        f"entry {i}: {_short(a[i])} in the store, {_short(b[i])} now"
                        for i in changed[:3]
                    )
                    more = f" and {len(changed) - 3} more" if len(changed) > 3 else ""
                    diffs.append(f"{where_text}: {shown}{more}")
                else:
                    diffs.append(f"{where_text} (list of {len(a)} vs {len(b)} entries)")
            elif _is_digest(a) and _is_digest(b):
                diffs.append(f"{where}: changed since the store was written (its content differs)")
            else:
                diffs.append(f"{where_text}: {_short(a)} in the store, {_short(b)} now")

    walk(dict(old), dict(new), "")
    return diffs


#: The campaign file's keys behind a store definition's entries, for the messages.
CAMPAIGN_KEYS = {
    "space.relative_range": "parameters.default_range / parameters.ranges",
    "space.names": "parameters.include / exclude",
}


class CampaignStore:
    """SQLite store of a campaign's finished samples.

    Open it with :meth:`open`; use it as a context manager or call :meth:`close`.
    Only one process writes (the campaign runner's parent); WAL mode lets readers look in
    while it runs.
    """

    def __init__(self, path: Path, connection: sqlite3.Connection, fingerprint: str) -> None:
        self.path = path
        self.fingerprint = fingerprint
        self._con = connection
        self._lock: FileLock | None = None

    # ------------------------------------------------------------------------------------------
    @classmethod
    def open(
        cls,
        path: Path | str,
        fingerprint: str | None = None,
        *,
        definition: Mapping[str, Any] | None = None,
        campaign_text: str = "",
        resume: bool = True,
        expected: pd.DataFrame | None = None,
    ) -> CampaignStore:
        """Open (or create) the store of a campaign.

        Parameters
        ----------
        path : path-like
            SQLite file, created with its folder if absent.
        fingerprint : str, optional
            Campaign fingerprint; default :func:`campaign_fingerprint` of ``definition``.
        definition : mapping, optional
            Campaign definition (JSON-ready), stored to explain a later mismatch.
        campaign_text : str
            Text of the campaign file, stored for the record.
        resume : bool
            When False, an existing store that already holds results of this campaign is an
            error (the caller asked for a fresh run); when True it is continued. A resumed
            store whose definition differs only in the number of samples is extended (or
            read in part) when its samples are the first ones of ``expected``.
        expected : DataFrame, optional
            The campaign's parameter values (index: sample) [unit of each]; on resume the
            stored samples must equal these rows (the same sequence).

        Returns
        -------
        CampaignStore

        Raises
        ------
        ThermocalInputError
            The file is not SQLite, is an SQLite file of another program, belongs to another
            campaign, is being written by another run (lock ``.NAME.lock`` beside it), or
            holds results while ``resume`` is False.
        """
        path = Path(path)
        if fingerprint is None:
            if definition is None:
                raise ThermocalInputError("CampaignStore.open needs a fingerprint or a definition")
            fingerprint = campaign_fingerprint(definition)
        remedy = (
            "use another store (the campaign file's store: key, or another --out), or delete "
            "the file to start afresh"
        )
        if path.exists():
            if path.is_dir():
                raise ThermocalInputError(f"store {path} is a folder; give a file name ({remedy})")
            with open(path, "rb") as fh:
                head = fh.read(16)
            if head and head != _SQLITE_MAGIC:
                raise ThermocalInputError(
                    f"store {path} is not an SQLite database (a campaign store is written by "
                    f"thermocal calibrate); {remedy}"
                )
        else:
            try:
                path.parent.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise ThermocalInputError(f"store {path}: {_describe_os_error(exc)}") from None
        lock = FileLock(
            path.parent / f".{path.name}.lock",
            busy=f"store {path} is in use by another thermocal calibrate run (lock "
            f".{path.name}.lock beside it); wait for it to finish, or give this run another "
            "--out or store",
            what=f"store {path}",
        ).acquire()
        try:
            return cls._open_locked(
                path, fingerprint, definition, campaign_text, resume, expected, remedy, lock
            )
        except BaseException:
            lock.release()
            raise

    @classmethod
    def _open_locked(
        cls, path, fingerprint, definition, campaign_text, resume, expected, remedy, lock
    ) -> CampaignStore:
        try:
            con = sqlite3.connect(str(path), timeout=30.0, isolation_level=None)
            tables = {
                row[0] for row in con.execute("SELECT name FROM sqlite_master WHERE type = 'table'")
            }
            if tables and not {"campaign", "results"} <= tables:
                con.close()
                shown = ", ".join(sorted(tables)[:6])
                raise ThermocalInputError(
                    f"store {path} is an SQLite database of another program (tables {shown}), "
                    f"not a thermocal campaign store; it was left unchanged; {remedy}"
                )
            con.execute("PRAGMA journal_mode=WAL")
            con.execute("PRAGMA synchronous=NORMAL")
            con.execute("CREATE TABLE IF NOT EXISTS campaign (key TEXT PRIMARY KEY, value TEXT)")
            con.execute(
                "CREATE TABLE IF NOT EXISTS results (sample INTEGER PRIMARY KEY, "
                "parameters TEXT NOT NULL, outputs TEXT NOT NULL, runtime_s REAL, error TEXT, "
                "worker TEXT, finished_at TEXT)"
            )
            con.execute(
                "CREATE TABLE IF NOT EXISTS runs (key TEXT PRIMARY KEY, parameters TEXT NOT NULL, "
                "outputs TEXT NOT NULL, heat TEXT)"
            )
            rows = dict(con.execute("SELECT key, value FROM campaign").fetchall())
        except sqlite3.DatabaseError as exc:
            raise ThermocalInputError(
                f"store {path} is not a usable SQLite campaign store ({exc}); {remedy}"
            ) from None
        if not rows:
            now = _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")
            with con:
                con.executemany(
                    "INSERT INTO campaign (key, value) VALUES (?, ?)",
                    [
                        ("fingerprint", fingerprint),
                        ("definition", _canonical(definition or {})),
                        ("campaign_text", campaign_text),
                        ("created_at", now),
                        ("schema_version", SCHEMA_VERSION),
                    ],
                )
        elif rows.get("fingerprint") != fingerprint:
            old: dict = {}
            diffs: list[str] = []
            if definition is not None and rows.get("definition"):
                try:
                    old = json.loads(rows["definition"])
                    diffs = _definition_differences(old, definition)
                except json.JSONDecodeError:
                    diffs = []
            only_count = bool(diffs) and all(d.startswith("sampler.samples:") for d in diffs)
            if only_count and resume:
                # the same sequence with another count: extended when the stored samples are
                # its first ones (checked below), otherwise refused there
                with con:
                    con.execute(
                        "UPDATE campaign SET value = ? WHERE key = 'fingerprint'", (fingerprint,)
                    )
                    con.execute(
                        "UPDATE campaign SET value = ? WHERE key = 'definition'",
                        (_canonical(definition or {}),),
                    )
            else:
                con.close()
                if only_count:
                    what = (
                        f" It holds a campaign of {old['sampler']['samples']} samples of the same "
                        f"sequence; pass --resume to extend it to "
                        f"{definition['sampler']['samples']}."
                    )
                elif diffs:
                    what = " What differs: " + "; ".join(diffs[:8]) + "."
                else:
                    what = ""
                raise ThermocalInputError(
                    f"store {path} belongs to another campaign and cannot be continued with "
                    f"this campaign file.{what} {remedy[0].upper()}{remedy[1:]}."
                )
        store = cls(path, con, fingerprint)
        store._lock = lock
        if expected is not None and resume:
            store._check_same_sequence(expected, remedy)
        if not resume and rows and store.count() > 0:
            n = store.count()
            store.close()
            raise ThermocalInputError(
                f"store {path} already holds {n} finished sample(s) of this campaign; pass "
                f"--resume to continue it, or {remedy}"
            )
        return store

    def close(self) -> None:
        """Close the database connection and release the store's lock."""
        self._con.close()
        if self._lock is not None:
            self._lock.release()
            self._lock = None

    def _check_same_sequence(self, expected: pd.DataFrame, remedy: str) -> None:
        """Refuse stored samples that are not the rows of ``expected`` with their index."""
        stored = self.parameters(successful=False)
        if stored.empty:
            return
        extra = sorted(set(stored.index) - set(expected.index))
        common = stored.index.intersection(expected.index)
        columns = [c for c in expected.columns if c in stored.columns]
        same = len(columns) == len(expected.columns) and np.allclose(
            stored.loc[common, columns].to_numpy(float),
            expected.loc[common, columns].to_numpy(float),
            rtol=1e-9,
            atol=0.0,
            equal_nan=True,
        )
        if extra and same:
            return  # a shorter campaign reads the first samples of a longer one
        if not same:
            self.close()
            raise ThermocalInputError(
                f"store {self.path}: its {len(stored)} sample(s) are not the first samples of "
                "this campaign's sequence (a Latin hypercube design changes with the count; "
                "Sobol' and Halton sequences only grow), so they cannot be reused; resume with "
                f"the count of the store, or {remedy}"
            )

    def __enter__(self) -> CampaignStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------------------------------
    def meta(self, key: str) -> str | None:
        """A value of the ``campaign`` table (``"campaign_text"``, ``"definition"``...)."""
        row = self._con.execute("SELECT value FROM campaign WHERE key = ?", (key,)).fetchone()
        return None if row is None else row[0]

    @classmethod
    def existing(cls, path: Path | str) -> CampaignStore:
        """Open the store of a finished (or interrupted) campaign as it is, for a re-analysis.

        Raises
        ------
        ThermocalInputError
            No such file, not a campaign store, or in use by a running campaign.
        """
        path = Path(path)
        if not path.is_file():
            raise ThermocalInputError(
                f"store {path} does not exist: a re-analysis needs the store of a campaign run "
                "before (thermocal calibrate writes OUT/campaign.sqlite, or the campaign file's "
                "'store')"
            )
        try:
            con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
            try:
                row = con.execute("SELECT value FROM campaign WHERE key = 'fingerprint'").fetchone()
            finally:
                con.close()
        except sqlite3.DatabaseError:
            row = None
        if row is None:
            raise ThermocalInputError(
                f"store {path} is not a thermocal campaign store (no campaign fingerprint); "
                "give the store written by thermocal calibrate"
            )
        return cls.open(path, row[0], resume=True)

    def definition(self) -> dict:
        """The campaign definition the store was written with (JSON)."""
        text = self.meta("definition")
        return json.loads(text) if text else {}

    def set_info(self, name: str, value: Any) -> None:
        """Store a JSON value under ``info:<name>`` (replacing an older one)."""
        with self._con:
            self._con.execute(
                "INSERT OR REPLACE INTO campaign (key, value) VALUES (?, ?)",
                (f"info:{name}", _canonical(value)),
            )

    def info(self, name: str) -> Any:
        """The JSON value stored under ``info:<name>``, None when absent."""
        text = self.meta(f"info:{name}")
        return None if text is None else json.loads(text)

    def record_run(
        self,
        parameters: Mapping[str, float],
        outputs: Mapping[str, float],
        heat: pd.Series | None = None,
        tag: str = "",
    ) -> None:
        """Store one analysis run (see the ``runs`` table) and commit at once.

        Parameters
        ----------
        parameters : mapping
            The parameters that differ from the nominal model [unit of each].
        outputs : mapping
            Its outputs (as a sample's) [unit of each].
        heat : Series, optional
            Building-wide identified heat on a regular time index [W].
        tag : str
            The problem it ran ("" the campaign's, ``"validation"`` the validation period).
        """
        stored = None
        if heat is not None:
            step = (heat.index[1] - heat.index[0]).total_seconds() if len(heat) > 1 else 0.0
            stored = json.dumps(
                {
                    "start": heat.index[0].isoformat(),
                    "step_s": step,
                    "name": heat.name,
                    "values": [_num(v) for v in heat.to_numpy()],
                }
            )
        with self._con:
            self._con.execute(
                "INSERT OR REPLACE INTO runs (key, parameters, outputs, heat) VALUES (?, ?, ?, ?)",
                (
                    run_key(parameters, tag),
                    json.dumps({k: _num(v) for k, v in parameters.items()}),
                    json.dumps({k: _num(v) for k, v in outputs.items()}),
                    stored,
                ),
            )

    def find_run(
        self, parameters: Mapping[str, float], tag: str = ""
    ) -> tuple[dict, pd.Series | None] | None:
        """Outputs and heat of a stored analysis run with these parameters, or None."""
        row = self._con.execute(
            "SELECT outputs, heat FROM runs WHERE key = ?", (run_key(parameters, tag),)
        ).fetchone()
        if row is None:
            return None
        outputs = {k: _float(v) for k, v in json.loads(row[0]).items()}
        heat = None
        if row[1]:
            data = json.loads(row[1])
            index = pd.date_range(
                pd.Timestamp(data["start"]),
                periods=len(data["values"]),
                freq=pd.Timedelta(seconds=data["step_s"] or 1.0),
            )
            heat = pd.Series([_float(v) for v in data["values"]], index=index, name=data["name"])
        return outputs, heat

    def count(self, *, failed: bool | None = None) -> int:
        """Number of finished samples (``failed=True``/``False`` to count only those) [-]."""
        sql = "SELECT COUNT(*) FROM results"
        if failed is True:
            sql += " WHERE error IS NOT NULL"
        elif failed is False:
            sql += " WHERE error IS NULL"
        return int(self._con.execute(sql).fetchone()[0])

    def done(self, *, include_failed: bool = True) -> set[int]:
        """Indices of finished samples (failed ones too unless ``include_failed`` is False)."""
        sql = "SELECT sample FROM results"
        if not include_failed:
            sql += " WHERE error IS NULL"
        return {int(r[0]) for r in self._con.execute(sql)}

    def pending(self, indices: Iterable[int], *, retry_failed: bool = False) -> list[int]:
        """Sample indices (among ``indices``) that still have to be evaluated, in order.

        Parameters
        ----------
        indices : iterable of int
            All sample indices of the campaign [-].
        retry_failed : bool
            Also return the samples that finished with an error.
        """
        done = self.done(include_failed=not retry_failed)
        return sorted({int(i) for i in indices} - done)

    def record(self, result: SampleResult) -> bool:
        """Store one finished sample and commit at once.

        A successful result is never overwritten; a failed one may be replaced by a retry.

        Returns
        -------
        bool
            True when the row was written, False when the sample already had a success.
        """
        finished = _dt.datetime.now(_dt.UTC).isoformat(timespec="milliseconds")
        cur = self._con.execute(
            "INSERT INTO results (sample, parameters, outputs, runtime_s, error, worker, "
            "finished_at) VALUES (?, ?, ?, ?, ?, ?, ?) "
            "ON CONFLICT(sample) DO UPDATE SET parameters=excluded.parameters, "
            "outputs=excluded.outputs, runtime_s=excluded.runtime_s, error=excluded.error, "
            "worker=excluded.worker, finished_at=excluded.finished_at "
            "WHERE results.error IS NOT NULL",
            (
                int(result.sample),
                json.dumps({k: _num(v) for k, v in result.parameters.items()}),
                json.dumps({k: _num(v) for k, v in result.outputs.items()}),
                float(result.runtime_s),
                result.error,
                result.worker,
                finished,
            ),
        )
        return cur.rowcount > 0

    # ------------------------------------------------------------------------------------------
    def to_frame(self) -> pd.DataFrame:
        """All finished samples, one row each, ordered by sample index.

        Returns
        -------
        DataFrame
            Index ``sample``; the parameter columns (names as in the space) [unit of each],
            the output columns (prefixed ``out:``, e.g. ``out:unoccupied_variance``), then
            ``runtime_s`` [s], ``error``, ``worker``, ``finished_at``.
        """
        rows = self._con.execute(
            "SELECT sample, parameters, outputs, runtime_s, error, worker, finished_at "
            "FROM results ORDER BY sample"
        ).fetchall()
        records = []
        for sample, params, outputs, runtime, error, worker, finished in rows:
            rec: dict[str, Any] = {"sample": sample}
            rec.update({k: _float(v) for k, v in json.loads(params).items()})
            rec.update({f"out:{k}": _float(v) for k, v in json.loads(outputs).items()})
            rec.update(runtime_s=runtime, error=error, worker=worker, finished_at=finished)
            records.append(rec)
        if not records:
            return pd.DataFrame(
                columns=["runtime_s", "error", "worker", "finished_at"],
                index=pd.Index([], name="sample", dtype=int),
            )
        frame = pd.DataFrame.from_records(records).set_index("sample")
        tail = ["runtime_s", "error", "worker", "finished_at"]
        params = [c for c in frame.columns if c not in tail and not c.startswith("out:")]
        outs = [c for c in frame.columns if c.startswith("out:")]
        return frame[params + outs + tail]

    def parameters(self, *, successful: bool = True) -> pd.DataFrame:
        """Parameter values of the finished samples (only successful ones by default)."""
        frame = self.to_frame()
        if successful:
            frame = frame[frame["error"].isna()]
        cols = [
            c
            for c in frame.columns
            if not c.startswith("out:") and c not in ("runtime_s", "error", "worker", "finished_at")
        ]
        return frame[cols]

    def outputs(self, *, successful: bool = True) -> pd.DataFrame:
        """Named outputs of the finished samples (column names without the ``out:`` prefix)."""
        frame = self.to_frame()
        if successful:
            frame = frame[frame["error"].isna()]
        outs = frame[[c for c in frame.columns if c.startswith("out:")]]
        return outs.rename(columns=lambda c: c[4:])

    def export(self, path: Path | str) -> Path:
        """Write :meth:`to_frame` to ``.parquet`` or ``.csv``, atomically.

        Parameters
        ----------
        path : path-like
            Destination; the suffix chooses the format.

        Returns
        -------
        Path
        """
        path = Path(path)
        frame = self.to_frame()
        suffix = path.suffix.lower()
        if suffix == ".parquet":
            return atomic_write(path, lambda p: frame.to_parquet(p))
        if suffix == ".csv":
            return atomic_write(path, lambda p: frame.to_csv(p))
        raise ThermocalInputError(f"export file {path} must end in .parquet or .csv")


def run_key(parameters: Mapping[str, float], tag: str = "") -> str:
    """Key of an analysis run: its parameters to 12 significant digits, sorted by name, and a
    tag naming the problem it ran (e.g. ``"validation"``)."""
    items = sorted((str(k), float(f"{float(v):.12g}")) for k, v in parameters.items())
    return hashlib.sha256(_canonical([tag, items]).encode()).hexdigest()


def _num(value: Any) -> float | None:
    v = float(value)
    return v if math.isfinite(v) else None


def _float(value: Any) -> float:
    return math.nan if value is None else float(value)
