"""Files written by :func:`thermocal.io.atomic.atomic_write` get the permissions of an ordinary
file: 0666 less the umask when new, the old file's mode when replacing one.

Before: the temporary file of ``tempfile.mkstemp`` (mode 0600) was renamed into place, so
``thermocal identify`` wrote ``identification.json``, ``q_id.parquet``, ``report.html`` and the
figures as ``-rw-------`` while ``thermocal simulate`` wrote ``-rw-r--r--`` under the same umask
022 (fuzzing round 6, ``30_id_baseline``).
"""

from __future__ import annotations

import os
import stat

import pandas as pd
import pytest

from thermocal.io.atomic import atomic_parquet, atomic_write


@pytest.fixture
def umask():
    """Set a umask for one test, restored after it."""
    saved = os.umask(0o022)
    os.umask(saved)

    def set_umask(value):
        os.umask(value)

    yield set_umask
    os.umask(saved)


def _mode(path):
    return stat.S_IMODE(path.stat().st_mode)


@pytest.mark.parametrize(("mask", "expected"), [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_new_file_honours_the_umask(tmp_path, umask, mask, expected):
    umask(mask)
    plain = tmp_path / "plain.json"
    plain.write_text("{}")
    written = atomic_write(tmp_path / "out.json", lambda tmp: tmp.write_text("{}"))
    assert _mode(written) == _mode(plain) == expected


def test_parquet_honours_the_umask(tmp_path, umask):
    umask(0o022)
    written = atomic_parquet(tmp_path / "q_id.parquet", pd.DataFrame({"q": [1.0, 2.0]}))
    assert _mode(written) == 0o644


def test_replaced_file_keeps_its_mode(tmp_path, umask):
    umask(0o022)
    path = tmp_path / "report.html"
    path.write_text("old")
    path.chmod(0o640)
    atomic_write(path, lambda tmp: tmp.write_text("new"))
    assert path.read_text() == "new"
    assert _mode(path) == 0o640
    assert [p.name for p in tmp_path.iterdir()] == ["report.html"]  # no temporary left
