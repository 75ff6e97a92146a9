"""The command line: help texts, the version command and the retrofit summary tables."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

from thermocal import __version__
from thermocal.cli import COMMAND_MODULES, app


def test_help_lists_every_command():
    result = CliRunner().invoke(app, ["--help"])
    assert result.exit_code == 0
    for name in ("version", *COMMAND_MODULES):
        assert f" {name} " in result.output, name


def test_version():
    result = CliRunner().invoke(app, ["version"])
    assert result.exit_code == 0
    assert result.output.strip() == __version__


def test_retrofit_and_demo_help_name_their_inputs_and_outputs():
    runner = CliRunner()
    retro = runner.invoke(app, ["retrofit", "--help"], terminal_width=120)
    assert retro.exit_code == 0
    assert "CONFIG" in retro.output.upper() and "--out" in retro.output
    assert "results.json" in retro.output and "report.html" in retro.output
    demo = runner.invoke(app, ["demo", "--help"], terminal_width=120)
    assert demo.exit_code == 0
    for option in ("--out", "--weather", "--regenerate", "--draws"):
        assert option in demo.output


def _results(interval: float) -> dict:
    from thermocal.retrofit.strategies import all_strategies

    metrics = {"mae": 0.86, "mape": 3.92, "mse": 1.25, "mean_simulated": 21.64,
               "mean_measured": 21.91, "mean_deviation_pct": -1.27}  # fmt: skip
    scenarios = [
        {"code": s.code, "measures": list(s.measures), "annual_kWh": 1000.0 * (16 - i),
         "saving_pct": 6.25 * i, "saving_pct_p05": 5.0 * i, "saving_pct_p95": 7.5 * i}
        for i, s in enumerate(all_strategies())
    ]  # fmt: skip
    return {
        "heat_loss_coefficient_W_per_K": {"value": 484.0, "std": 12.0},
        "validation": {"train": {**metrics, "mae": 1.06}, "test": metrics},
        "annual_heating_demand_kWh": {
            "value": 28630.0,
            "p05": 27000.0,
            "p95": 30000.0,
            "references": {"SIA 380/1": 39170.0, "measured fuel use": 30660.0},
        },  # fmt: skip
        "scenarios": scenarios,
        "uncertainty": {"interval": interval},
        "calibration": {"flags": ["parameter C_i at its bound"]},
    }


def test_retrofit_summary_tables(capsys, caplog):
    from thermocal.commands.retrofit import print_summary

    print_summary(_results(0.8), Path("out"))
    text = capsys.readouterr().out
    assert "HLC 484 ± 12 W/K" in text
    assert "80 % interval" in text and "90 %" not in text  # the configured interval
    assert "1.06" in text and "0.86" in text and "-1.27" in text  # both validation periods
    assert "SIA 380/1: 39,170 kWh" in text and "30,660 kWh" in text  # references side by side
    rows = {line.split()[0]: line for line in text.splitlines() if line.strip()}
    for code in ("1a", "2f", "3c", "4"):
        assert code in rows
    # the method's Table 3, one row per strategy in 80 columns: measures abbreviated + legend
    assert rows["3c"].split()[1] == "R+Wi+C"
    assert "measures: R roof, Wa walls, Wi windows, C cellar ceiling" in text
    assert "C_i at its bound" not in text  # warnings are log records (stderr), not results
    assert any(
        r.levelname == "WARNING" and "C_i at its bound" in r.getMessage() for r in caplog.records
    )
    assert "paper 000" not in text


def test_demo_rejects_negative_draws_before_running():
    result = CliRunner().invoke(app, ["demo", "--draws", "-5", "--out", "unused"])
    assert result.exit_code != 0
    assert "--draws" in result.output


def test_version_options_and_short_help():
    runner = CliRunner()
    for args in (["--version"], ["-V"]):
        result = runner.invoke(app, args)
        assert result.exit_code == 0
        assert result.output.strip() == f"thermocal {__version__}"
    short = runner.invoke(app, ["-h"])
    assert short.exit_code == 0 and "Usage" in short.output and "--install-completion" in (
        short.output
    )
    sub = runner.invoke(app, ["retrofit", "-h"])
    assert sub.exit_code == 0 and "CONFIG" in sub.output.upper()
    assert "paper 000" not in short.output + sub.output


def _stderr_logging_script(flags: str) -> str:
    return (
        "import logging, sys\n"
        "from thermocal.cli import app\n"
        "import typer\n"
        "@app.command('emit-test')\n"
        "def emit():\n"
        "    logging.getLogger('thermocal.retrofit').info('an info line')\n"
        "    logging.getLogger('thermocal.retrofit').warning('a warning line')\n"
        "    print('result on stdout')\n"
        f"sys.argv = ['thermocal', *{flags.split()!r}, 'emit-test']\n"
        "app()\n"
    )


def test_log_levels_go_to_stderr():
    import subprocess
    import sys

    def run(flags):
        proc = subprocess.run(
            [sys.executable, "-c", _stderr_logging_script(flags)],
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert proc.returncode == 0, proc.stderr
        return proc.stdout, proc.stderr

    out, err = run("")
    assert out.strip() == "result on stdout"
    assert "WARNING: a warning line" in err and "an info line" not in err
    out, err = run("-v")
    assert "INFO: an info line" in err and "a warning line" in err
    assert "info" not in out.lower()
    out, err = run("-q")
    assert err == "" and out.strip() == "result on stdout"


def test_configure_logging_levels():
    import logging

    from thermocal.cli import configure_logging

    logger = logging.getLogger("thermocal")
    for verbosity, level in ((-1, logging.ERROR), (0, logging.WARNING), (1, logging.INFO),
                             (2, logging.DEBUG), (5, logging.DEBUG)):  # fmt: skip
        configure_logging(verbosity)
        assert logger.level == level
        assert sum(getattr(h, "_thermocal_cli", False) for h in logger.handlers) == 1
    configure_logging(0)


REPO = Path(__file__).resolve().parents[1]


def _thermocal(*args, cwd=REPO):
    import subprocess
    import sys

    return subprocess.run(
        [sys.executable, "-m", "thermocal", *map(str, args)],
        capture_output=True, text=True, cwd=cwd, timeout=300,
    )  # fmt: skip


def test_simulate_runs_the_multizone_example_and_refuses_the_retrofit_building_file(tmp_path):
    import json

    import pvlib

    weather = Path(pvlib.__file__).parent / "data" / "723170TYA.CSV"
    wrong = _thermocal("simulate", "examples/buildings/single_family_house_1953.yaml", weather,
                       "--out", tmp_path / "wrong")  # fmt: skip
    assert wrong.returncode == 2 and "Traceback" not in wrong.stderr
    lines = wrong.stderr.strip().splitlines()
    assert len(lines) == 1 and "is an envelope description" in lines[0]
    assert "examples/buildings/multizone_single_family_house.yaml" in lines[0]
    assert not (tmp_path / "wrong").exists()
    run = _thermocal("simulate", "examples/buildings/multizone_single_family_house.yaml",
                     weather, "--start", "2001-01-10", "--end", "2001-01-12", "--step", "1h",
                     "--warmup-days", "1", "--out", tmp_path / "sim")  # fmt: skip
    assert run.returncode == 0, run.stderr
    summary = json.loads((tmp_path / "sim" / "summary.json").read_text())
    assert "attic south" in json.dumps(summary)


def _wait_for_path(pattern: str, parent: Path, proc, timeout: float = 120.0) -> None:
    import time

    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if list(parent.glob(pattern)):
            return
        if proc.poll() is not None:
            break
        time.sleep(0.05)
    raise AssertionError(f"never saw {pattern}: {proc.communicate()[1]}")


@pytest.mark.parametrize(("sig", "code", "word"), [("SIGINT", 130, "interrupted"),
                                                   ("SIGTERM", 143, "terminated")])  # fmt: skip
def test_interrupted_demo_leaves_the_previous_results_untouched(tmp_path, sig, code, word):
    """Ctrl-C / SIGTERM while the demo computes: exit 130 / 143, one line, the output folder
    exactly as the previous run left it, no temporary folder or lock beside it."""
    import signal
    import subprocess
    import sys

    from thermocal.commands.retrofit import RETROFIT_SIGNATURE
    from thermocal.io.output import output_folder

    out = tmp_path / "demo"
    with output_folder(out, command="demo", signature=RETROFIT_SIGNATURE) as tmp:
        (tmp / "results.json").write_text('{"previous": true}')
        (tmp / "report.html").write_text("<html>previous</html>")
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    proc = subprocess.Popen(
        [sys.executable, "-m", "thermocal", "demo", "--out", str(out), "--draws", "20"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
    )  # fmt: skip
    _wait_for_path(".demo.tmp-*/data/config.yaml", tmp_path, proc)  # computing now
    proc.send_signal(getattr(signal, sig))
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == code, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith(word) and "Traceback" not in err, err
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo"]


def test_thermocals_own_warnings_are_one_line_without_the_source(capsys):
    """Before: `thermocal calibrate` printed '.../multizone/files.py:74: IdfImportWarning: ...'
    and the source line 'return read_idf(path)'."""
    import warnings

    from thermocal.cli import _install_warning_format
    from thermocal.multizone.idf import IdfImportWarning

    saved = warnings.showwarning
    others = []
    try:
        warnings.showwarning = lambda message, category, *args, **kwargs: others.append(category)
        _install_warning_format()
        with warnings.catch_warnings():
            warnings.simplefilter("always")
            warnings.warn("house.idf: 3 import notes", IdfImportWarning, stacklevel=1)
            warnings.warn("from another library", DeprecationWarning, stacklevel=1)
    finally:
        warnings.showwarning = saved
    err = capsys.readouterr().err
    assert "warning: house.idf: 3 import notes" in err
    assert "IdfImportWarning" not in err and "warnings.warn" not in err
    assert others == [DeprecationWarning]  # other libraries' keep the handler they had


_FREED_ARRAYS_SCRIPT = """
import sys
import numpy as np
from thermocal.cli import _return_freed_arrays_to_the_system
if sys.argv[1] == "set":
    assert _return_freed_arrays_to_the_system()
def rss():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS"):
            return int(line.split()[1]) / 1024
big = np.ones((24 << 20) // 8)
del big  # glibc's dynamic threshold now serves arrays up to 24 MiB from the heap
base = rss()
arrays = [np.ones((6 << 20) // 8) for _ in range(30)]
kept = arrays[::2]
del arrays
print(rss() - base)
"""


def test_the_command_hands_freed_arrays_back_to_the_system():
    """The command's allocator setting (issue 22, the clinic month's memory): 30 arrays of
    6 MiB, every other one freed, after a 24-MiB one was freed. With glibc's dynamic mmap
    threshold the freed ones stay in the heap's holes (180 MiB resident); with the command's
    setting each went back to the system when freed (90 MiB)."""
    import platform
    import subprocess
    import sys

    if platform.system() != "Linux" or platform.libc_ver()[0] != "glibc":
        pytest.skip("glibc's allocator setting: Linux with glibc only")
    env = {k: v for k, v in __import__("os").environ.items() if not k.startswith("MALLOC_")}
    grown = {
        mode: float(
            subprocess.run(
                [sys.executable, "-c", _FREED_ARRAYS_SCRIPT, mode],
                capture_output=True, text=True, check=True, env=env,
            ).stdout.split()[-1]
        )
        for mode in ("default", "set")
    }  # fmt: skip
    assert grown["default"] > 160.0, grown
    assert 80.0 < grown["set"] < 110.0, grown


_ARROW_POOL_SCRIPT = """
import pyarrow as pa
from thermocal.cli import _arrow_on_the_system_allocator
applied = _arrow_on_the_system_allocator()
print(applied, pa.default_memory_pool().backend_name)
"""


def test_the_command_reads_parquet_through_the_system_allocator():
    """pyarrow's own pool keeps freed buffers' pages (issue 22, the clinic month's memory):
    the command hands pyarrow the C library's allocator, whose large blocks go back to the
    system when freed; a pool the user chose in ``ARROW_DEFAULT_MEMORY_POOL`` is kept."""
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k != "ARROW_DEFAULT_MEMORY_POOL"}

    def run(extra):
        out = subprocess.run(
            [sys.executable, "-c", _ARROW_POOL_SCRIPT],
            capture_output=True, text=True, check=True, env={**env, **extra},
        )  # fmt: skip
        return out.stdout.split()

    assert run({}) == ["True", "system"]
    assert run({"ARROW_DEFAULT_MEMORY_POOL": "jemalloc"}) == ["False", "jemalloc"]


def test_command_help_paragraphs_wrap_at_the_terminal_width():
    # typer kept each docstring line's break: at 80 columns a 95-character source line became
    # one full and one short line ("checks the" / "standard's convergence criteria ...")
    from thermocal.cli import reflow_help

    result = CliRunner().invoke(app, ["insitu", "--help"], terminal_width=80)
    assert result.exit_code == 0
    lines = [line.strip(" │") for line in result.output.splitlines()]
    paragraph = " ".join(lines[lines.index(next(x for x in lines if x.startswith("Sums"))):])
    assert "checks the standard's convergence criteria" in paragraph
    short = [x for x in lines[:12] if 0 < len(x) < 40 and not x.startswith("Usage")]
    assert len(short) <= 2, short  # the two paragraphs' last lines at most
    assert reflow_help("First.\n\nOne\ntwo\n- item a\n- item b\n  more") == (
        "First.\n\nOne two\n- item a\n- item b\n  more"
    )
