"""The ``thermocal`` command line.

Each subcommand lives in its own module under :mod:`thermocal.commands` and registers
itself on :data:`app`; heavy imports happen inside the command bodies so that
``thermocal --help`` stays fast.
"""

from __future__ import annotations

import importlib
import logging
import os
import signal
import sys
from pathlib import Path
from typing import Annotated

import typer

app = typer.Typer(
    name="thermocal",
    help=(
        "Calibrated thermal models of buildings from cheap measurements.\n\n"
        "Grey-box RC estimation (fit), detailed multi-zone simulation (simulate), "
        "retrofit analysis with the fifth-order RC method (retrofit), a built-in "
        "demonstration (demo), heat-balance identification by per-zone control (identify) "
        "and envelope calibration campaigns (calibrate)."
    ),
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_show_locals=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)

#: Log levels of ``-q`` (quiet), the default, ``-v`` and ``-vv``.
_LEVELS = (logging.ERROR, logging.WARNING, logging.INFO, logging.DEBUG)


def configure_logging(verbosity: int) -> None:
    """Send the ``thermocal`` loggers to stderr at the level of ``-q`` / ``-v`` / ``-vv``.

    Parameters
    ----------
    verbosity : int
        -1 quiet (errors only), 0 warnings (default), 1 info, 2 or more debug.
    """
    level = _LEVELS[max(0, min(verbosity + 1, len(_LEVELS) - 1))]
    logger = logging.getLogger("thermocal")
    for handler in list(logger.handlers):
        if getattr(handler, "_thermocal_cli", False):
            logger.removeHandler(handler)
    import sys

    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(levelname)s: %(message)s"))
    handler._thermocal_cli = True  # type: ignore[attr-defined]
    logger.addHandler(handler)
    logger.setLevel(level)


def _print_version(value: bool) -> None:
    if value:
        from thermocal import __version__

        typer.echo(f"thermocal {__version__}")
        raise typer.Exit()


#: Subcommand modules, in the order they appear in ``--help``.
COMMAND_MODULES = (
    "demo",
    "fit",
    "select",
    "simulate",
    "retrofit",
    "verify",
    "identify",
    "calibrate",
    "insitu",
)


def reflow_help(doc: str) -> str:
    """A command's docstring with each paragraph's lines joined, for the terminal to wrap.

    typer keeps the single line breaks of a docstring's later paragraphs; at the terminal's
    80 columns each 95-character source line then wraps into one full and one short line.
    Lines that begin a list item (``-``, ``*``) or are indented further keep their breaks.

    Parameters
    ----------
    doc : str
        The docstring (dedented or not).

    Returns
    -------
    str
        Paragraphs separated by blank lines, each one line (list items one line each).
    """
    import inspect

    paragraphs = []
    for paragraph in inspect.cleandoc(doc).split("\n\n"):
        lines: list[str] = []
        for line in paragraph.splitlines():
            item = line.lstrip().startswith(("- ", "* ")) or line.startswith(" ")
            if lines and not item:
                lines[-1] = f"{lines[-1]} {line.strip()}"
            else:
                lines.append(line.rstrip())
        paragraphs.append("\n".join(lines))
    return "\n\n".join(paragraphs)


def _register_commands() -> None:
    for name in COMMAND_MODULES:
        try:
            importlib.import_module(f"thermocal.commands.{name}")
        except ModuleNotFoundError as exc:  # a command module not written yet
            if exc.name != f"thermocal.commands.{name}":
                raise
    for command in app.registered_commands:
        doc = command.help or (command.callback.__doc__ if command.callback else None)
        if doc:
            command.help = reflow_help(doc)


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            "-V",
            callback=_print_version,
            is_eager=True,
            help="Print the version and exit.",
        ),
    ] = False,
    verbose: Annotated[
        int,
        typer.Option("--verbose", "-v", count=True, help="More messages on stderr (-vv: debug)."),
    ] = 0,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Only errors on stderr.")] = False,
) -> None:
    """Calibrated thermal models of buildings from cheap measurements."""
    configure_logging(-1 if quiet else verbose)


@app.command()
def version() -> None:
    """Print the thermocal version."""
    from thermocal import __version__

    typer.echo(__version__)


_register_commands()


class Terminated(KeyboardInterrupt):
    """Raised in the main process on SIGTERM (a subclass of KeyboardInterrupt, so that every
    clean-up written for Ctrl-C runs)."""


#: Exit status after Ctrl-C (SIGINT) and SIGTERM: 128 + the signal number.
EXIT_INTERRUPTED, EXIT_TERMINATED = 130, 143
#: Exit status of an unexpected internal error (input errors exit with 2).
EXIT_INTERNAL = 70

_state: dict = {"pid": None, "signal": None, "pending": None}


#: The Python functions that compiled code calls back through ctypes while numba compiles
#: (llvmlite's object-cache hooks, which run numba's ``_object_compiled_hook`` and
#: ``_object_getbuffer_hook``): an exception raised inside them is printed as "Exception ignored
#: on calling ctypes callback function" with a traceback and lost, and the run goes on. Anywhere
#: else in numba's compiler (pure Python) a KeyboardInterrupt propagates normally.
_CTYPES_CALLBACKS = frozenset({"_raw_object_cache_notify", "_raw_object_cache_getbuffer"})
_CALLBACK_FILE = f"{os.sep}llvmlite{os.sep}"
#: Python also swallows, with an "Exception ignored in" traceback, an exception raised in a
#: weakref callback or a finaliser: the import system's own weakref callback on its module
#: locks (``cb`` in ``importlib._bootstrap``, run whenever a module lock is released during an
#: import) and any ``__del__``. A Ctrl-C during an import was lost there (1 of 7 clean runs of
#: the signal tests on 2026-11-29).
_SWALLOWING = frozenset({("cb", "<frozen importlib._bootstrap>")})
#: The standard library's weakref callbacks (WeakSet, WeakValueDictionary, weakref.finalize),
#: by function and file name.
_SWALLOWING_STDLIB = frozenset(
    {("_remove", "_weakrefset.py"), ("remove", "weakref.py"), ("__call__", "weakref.py")}
)
#: Seconds between two checks whether a deferred signal can be raised.
_DEFER_POLL_S = 0.05


def _inside_swallowing_callback(frame) -> bool:
    """Whether the interrupted Python code runs where an exception would be swallowed: a
    ctypes callback of llvmlite, the import system's weakref callback on a module lock, or a
    finaliser (``__del__``).

    Only those frames swallow an exception; the rest of a numba compilation (type inference,
    lowering, the cache) is ordinary Python, so a signal there is raised at once and Ctrl-C
    stops a first run within a fraction of a second instead of after the whole compilation.
    """
    while frame is not None:
        code = frame.f_code
        if code.co_name in _CTYPES_CALLBACKS and _CALLBACK_FILE in code.co_filename:
            return True
        if code.co_name == "__del__" or (code.co_name, code.co_filename) in _SWALLOWING:
            return True
        if (code.co_name, os.path.basename(code.co_filename)) in _SWALLOWING_STDLIB:
            return True
        frame = frame.f_back
    return False


def _raise_for(signum: int) -> None:
    _state["signal"] = signum
    if signum == signal.SIGTERM:
        raise Terminated
    raise KeyboardInterrupt


def _on_signal(signum, frame) -> None:
    """SIGINT/SIGTERM: raise in the main process, or defer inside a callback that would
    swallow the exception.

    A signal that arrives while llvmlite runs one of numba's hooks through a ctypes callback
    (during the first, uncached compilation of a kernel), while the import system runs its
    weakref callback on a module lock, or in a finaliser is remembered and raised as soon as the
    callback has returned, polled with a short interval timer: raised inside the callback it
    would be swallowed, printed with a traceback, and the run would go on.
    """
    if os.getpid() != _state["pid"]:  # a forked worker: the parent reports, quietly
        os._exit(128 + signum)
    if _inside_swallowing_callback(frame):
        if _state.get("pending") != signal.SIGTERM:  # SIGTERM wins over a later Ctrl-C
            _state["pending"] = signum
        signal.setitimer(signal.ITIMER_REAL, _DEFER_POLL_S)
        return
    _raise_for(signum)


def _on_deferred_check(signum, frame) -> None:  # noqa: ARG001 - the signal-handler signature
    """SIGALRM of the poll timer: raise the deferred signal once out of the callback."""
    pending = _state.get("pending")
    if pending is None or os.getpid() != _state["pid"]:
        return
    if _inside_swallowing_callback(frame):
        signal.setitimer(signal.ITIMER_REAL, _DEFER_POLL_S)
        return
    _state["pending"] = None
    _raise_for(pending)


def _install_signal_handlers() -> None:
    import threading

    if threading.current_thread() is not threading.main_thread():
        return
    _state["pid"] = os.getpid()
    _state["signal"] = None
    _state["pending"] = None
    signal.signal(signal.SIGINT, _on_signal)
    signal.signal(signal.SIGTERM, _on_signal)
    signal.signal(signal.SIGALRM, _on_deferred_check)


def _exit_interrupted() -> None:
    """One line on stderr (what happened to the output folder), exit 130 or 143."""
    from thermocal.io import output

    terminated = _state["signal"] == signal.SIGTERM
    what = "terminated (SIGTERM)" if terminated else "interrupted (Ctrl-C)"
    kept = output.last_interrupted
    if kept is None and output.last_completed is not None:
        kept = f"after the results were complete: {output.last_completed} holds them"
    typer.secho(f"{what}; {kept}" if kept else what, err=True, fg=typer.colors.YELLOW)
    code = EXIT_TERMINATED if terminated else EXIT_INTERRUPTED
    if _state.get("signal") is not None:
        # the output folder is already cleaned up (its context manager ran while the exception
        # propagated); exit now, so that a signal still pending or a worker pool's shutdown
        # cannot turn the exit into death by the signal (exit status -2 instead of 130)
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        signal.setitimer(signal.ITIMER_REAL, 0)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    raise SystemExit(code) from None


def _write_error_log(exc: BaseException) -> Path | None:
    """The traceback of an unexpected error in a log file (its path, or None)."""
    import datetime
    import tempfile
    import traceback

    from thermocal import __version__

    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    try:
        fd, name = tempfile.mkstemp(prefix=f"thermocal-error-{stamp}-", suffix=".log")
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(f"thermocal {__version__}\ncommand: {' '.join(sys.argv)}\n")
            fh.write(f"python {sys.version}\n\n")
            fh.write("".join(traceback.format_exception(type(exc), exc, exc.__traceback__)))
        return Path(name)
    except OSError:
        return None


def _install_warning_format() -> None:
    """Print thermocal's own warnings (an IDF's import notes, a substituted sensor) as one
    ``warning:`` line, without the Python source line a bare ``warnings.warn`` shows; other
    libraries' warnings keep Python's format."""
    import warnings

    default = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        if category.__module__.split(".")[0] == "thermocal":
            typer.secho(f"warning: {message}", err=True, fg=typer.colors.YELLOW)
        else:
            default(message, category, filename, lineno, file, line)

    warnings.showwarning = show


#: glibc's ``mallopt`` option number (malloc.h) and the fixed mmap threshold the commands use:
#: arrays from 4 MiB up (a month-long series of the clinic is 7-13 MiB) [bytes].
_M_MMAP_THRESHOLD, MMAP_THRESHOLD = -3, 4 << 20


def _return_freed_arrays_to_the_system() -> bool:
    """Keep glibc's allocator handing freed large arrays back to the system (a process-wide
    setting of the command, not of the library).

    glibc serves an allocation above its mmap threshold (128 KiB at start) from a mapping of
    its own, unmapped when freed, but raises that threshold to the size of any such block
    freed (up to 32 MiB), after which the arrays of a month-long series come from the heap,
    whose freed holes stay in the process's memory. A sensor log's read and the
    identification's frames left ~50 MiB of the clinic month's peak in such holes. A fixed
    threshold of :data:`MMAP_THRESHOLD` keeps every array of 4 MiB or more in its own mapping
    (smaller ones reuse the heap: with glibc's 128 KiB, `thermocal simulate` of the 180-zone
    grid spent 0.35 s more in page faults; with 4 MiB its time is unchanged); measured in
    benchmarks/README.md, "Memory of the clinic month, fourth round". Dask's worker processes
    set glibc's trim threshold for the same reason. Nothing happens on another C library or
    when the user set ``MALLOC_MMAP_THRESHOLD_`` themselves.

    Returns
    -------
    bool
        Whether the setting was applied.
    """
    import ctypes
    import os
    import platform

    if platform.libc_ver()[0] != "glibc" or "MALLOC_MMAP_THRESHOLD_" in os.environ:
        return False
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD) == 1


def _arrow_on_the_system_allocator() -> bool:
    """Let pyarrow allocate through the C library, so that the command's allocator setting
    (:func:`_return_freed_arrays_to_the_system`) reaches a parquet read's buffers too (a
    process-wide setting of the command, not of the library).

    pyarrow's default pool (mimalloc in its wheels) keeps the pages of freed buffers for
    reuse: the identification demo's sensor log (810,893 rows of parquet) left about 16 MiB of
    them in the process after its read, and its read peaked 40 MiB higher
    (benchmarks/README.md, "Memory of the clinic month, fifth round"). Nothing happens when
    the user chose a pool (``ARROW_DEFAULT_MEMORY_POOL``).

    Returns
    -------
    bool
        Whether the setting was applied.
    """
    if "ARROW_DEFAULT_MEMORY_POOL" in os.environ:
        return False
    try:
        import pyarrow  # already imported with pandas: no start-up cost
    except ImportError:  # pragma: no cover - pyarrow is a dependency
        return False
    pyarrow.set_memory_pool(pyarrow.system_memory_pool())
    return True


def _error(message: str) -> None:
    typer.secho(f"error: {message}", err=True, fg=typer.colors.RED)


def main() -> None:
    """Entry point of the ``thermocal`` console script.

    Input errors (:class:`thermocal.errors.ThermocalInputError`) are printed as one clear
    message, without a traceback, and exit with status 2. Ctrl-C and SIGTERM print one line
    (what happened to the output folder) and exit with 130 and 143. A file-system error
    (disk full, permission denied) is one line naming the file, exit 2. Any other error is
    an internal error: one line with the path of a log file holding the traceback, exit 70.
    """
    from thermocal.errors import ThermocalInputError

    _install_signal_handlers()
    _install_warning_format()
    _return_freed_arrays_to_the_system()
    _arrow_on_the_system_allocator()
    try:
        app()
    except SystemExit:
        if _state["signal"] is not None:  # typer turns KeyboardInterrupt into exit 130, quietly
            _exit_interrupted()
        raise
    except ThermocalInputError as exc:
        _error(str(exc))
        raise SystemExit(2) from None
    except KeyboardInterrupt:
        _exit_interrupted()
    except OSError as exc:
        if _state["signal"] is not None:  # a signal that arrived inside a worker or kernel
            _exit_interrupted()
        where = f"{exc.filename}: " if exc.filename else ""
        _error(f"{where}{exc.strerror or exc}; check the path and that it is readable/writable")
        raise SystemExit(2) from None
    except Exception as exc:  # noqa: BLE001 - the boundary: no traceback on the terminal
        if _state["signal"] is not None:  # e.g. numba's SystemError around a KeyboardInterrupt
            _exit_interrupted()
        log = _write_error_log(exc)
        where = f"; the details are in {log}" if log else ""
        _error(
            f"internal error ({type(exc).__name__}: {exc}); please report it with the "
            f"command line{' and the log file' if log else ''}{where}"
        )
        raise SystemExit(EXIT_INTERNAL) from None


#: Exit status when the standard streams cannot be flushed at exit (the interpreter's own).
_FLUSH_FAILED = 120


def _exit_code(exc: SystemExit) -> int:
    """The process exit status a :class:`SystemExit` stands for (as the interpreter maps it)."""
    if exc.code is None:
        return 0
    if isinstance(exc.code, int):
        return exc.code
    print(exc.code, file=sys.stderr)
    return 1


def _other_threads_running() -> bool:
    """Whether a thread the interpreter would wait for at exit is still running."""
    import threading

    return any(
        thread.is_alive() and not thread.daemon
        for thread in threading.enumerate()
        if thread is not threading.main_thread()
    )


def run() -> None:
    """The console script: :func:`main`, then an exit that skips the interpreter's teardown.

    A finished command has written and closed its files; what the interpreter does after that
    (clearing every module of numpy, pandas, scipy, numba and pvlib one by one and a last
    garbage collection) took 0.25-0.33 s of a 3.4-s ``thermocal simulate``. The exit handlers
    still run (``atexit``: the logging handlers' flush, temporary folders, multiprocessing) and
    the standard streams are flushed; then the process ends with :func:`os._exit`, as a forked
    worker does. Where a stream cannot be flushed (a closed pipe), the status is 120, as the
    interpreter's own; where the interpreter would wait for another thread, the ordinary exit
    is taken instead. :func:`main` itself raises :class:`SystemExit` as before, for callers in
    the same process (the tests).
    """
    try:
        main()
        code = 0
    except SystemExit as exc:
        code = _exit_code(exc)
    if _other_threads_running():
        raise SystemExit(code)
    import atexit

    atexit._run_exitfuncs()  # noqa: SLF001 - the interpreter's own exit handlers, once
    for stream in (sys.stdout, sys.stderr):  # each, even when the other cannot be flushed
        try:
            stream.flush()
        except (OSError, ValueError, AttributeError):
            code = _FLUSH_FAILED
    os._exit(code)


if __name__ == "__main__":
    run()
