"""The console script's exit (:func:`thermocal.cli.run`): the status, the streams and the exit
handlers as an ordinary interpreter exit gives them, without the interpreter's teardown."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from importlib.metadata import version

import pytest


def _run(script: str, tmp_path, *args: str) -> subprocess.CompletedProcess:
    path = tmp_path / "script.py"
    path.write_text(textwrap.dedent(script))
    return subprocess.run([sys.executable, str(path), *args], capture_output=True, text=True,
                          timeout=120, cwd=tmp_path)  # fmt: skip


_ATEXIT = """
    import atexit, sys
    from pathlib import Path
    atexit.register(lambda: Path("atexit_ran").write_text("yes"))
    sys.argv = ["thermocal"] + sys.argv[1:]
    from thermocal.cli import run
    run()
    raise AssertionError("run() returned")
"""


@pytest.mark.parametrize(
    ("args", "status", "stream"),
    [
        (["version"], 0, version("thermocal")),  # success: what it printed reaches the pipe
        (["simulate", "no_such_building.idf", "no_such_weather.epw"], 2, "error"),  # bad input
        (["no-such-command"], 2, "No such command"),  # typer's usage error
    ],
)
def test_status_streams_and_exit_handlers_are_those_of_an_ordinary_exit(
    tmp_path, args, status, stream
):
    done = _run(_ATEXIT, tmp_path, *args)
    assert done.returncode == status, done.stderr[-2000:]
    assert stream in done.stdout + done.stderr
    assert (tmp_path / "atexit_ran").read_text() == "yes"
    assert "Traceback" not in done.stderr


def test_a_running_thread_is_waited_for(tmp_path):
    done = _run(
        """
        import sys, threading, time
        from pathlib import Path
        def late():
            time.sleep(0.5)
            Path("thread_done").write_text("yes")
        threading.Thread(target=late).start()
        sys.argv = ["thermocal", "version"]
        from thermocal.cli import run
        run()
        """,
        tmp_path,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert (tmp_path / "thread_done").read_text() == "yes"


def test_a_closed_pipe_ends_as_the_ordinary_exit_does(tmp_path):
    # ``thermocal --help | true``: the reader is gone before anything is written; click ends
    # quietly with status 1, and the quick exit must say the same, without a traceback
    def pipeline(entry: str) -> tuple[int, str]:
        done = subprocess.run(
            ["bash", "-c", f'{sys.executable} -c "{entry}" --help | true; '
             'echo "status ${PIPESTATUS[0]}"'],
            capture_output=True, text=True, timeout=120, cwd=tmp_path,
        )  # fmt: skip
        return int(done.stdout.split()[-1]), done.stderr

    quick, quick_err = pipeline("from thermocal.cli import run; run()")
    ordinary, _ = pipeline("from thermocal.cli import main; main()")
    assert quick == ordinary
    assert "Traceback" not in quick_err and "Exception ignored" not in quick_err
