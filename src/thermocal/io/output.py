"""Output folders written safely: complete or absent, never mixed.

Every command writes its results through :func:`output_folder`:

* ``--out`` is checked before any computation: a file, an unwritable parent or a folder
  holding someone else's files is refused with a message saying what to do. A folder thermocal
  wrote carries a marker listing every file it wrote with its size and modification time; a
  file added or changed since (a user's notes, an edited configuration) makes the folder
  someone else's too, except the files a command keeps up to date in place (``state``: a
  calibration campaign's store);
* a lock (``.NAME.lock`` beside the folder, an OS file lock released even when the process
  dies) refuses a second run into the same folder while the first is writing;
* the results go into a temporary sibling folder (``.NAME.tmp-*``) that replaces ``--out`` in
  one rename at the end, so an interrupted or failed run leaves the previous results
  untouched and never a newer run's files beside an older one's.
"""

from __future__ import annotations

import contextlib
import errno
import fnmatch
import json
import os
import shutil
import signal
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

from thermocal.errors import ThermocalInputError
from thermocal.io.atomic import current_umask

#: Name of the marker file identifying a folder written by thermocal.
MARKER = ".thermocal-output"

#: What happened to the output folder of the last run interrupted in this process (for the
#: one-line message of the command line); None when no output folder was being written.
last_interrupted: str | None = None

#: The output folder the last run of this process completed (its results in place), for the
#: message of a signal that arrives after it: the folder then holds the new results.
last_completed: Path | None = None

try:  # POSIX file locks; on other systems the lock file's exclusive creation is used
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]


def _describe_os_error(exc: OSError) -> str:
    if exc.errno == errno.ENOSPC:
        return "the disk is full; free some space or choose another --out"
    if exc.errno in (errno.EACCES, errno.EPERM):
        return "permission denied; choose a folder you can write to with --out"
    if exc.errno == errno.EROFS:
        return "the file system is read-only; choose another --out"
    return f"{exc.strerror or exc}; choose another --out"


def check_output_folder(
    out: Path,
    *,
    signature: Iterable[str] = (),
    state: Iterable[str] = (),
    inputs: Iterable[Path | str | None] = (),
) -> None:
    """Refuse an ``--out`` that cannot hold this command's results.

    Parameters
    ----------
    out : Path
        The output folder.
    state : iterable of str
        Patterns (``fnmatch``, relative paths) of the files the command keeps up to date in
        ``out`` between runs (a campaign's store): they may differ from the marker's list.
    inputs : iterable of path or None
        The command's input files (None skipped): one inside ``out`` is refused, since the
        new results would replace the folder and delete it (a demo's ``data/config.yaml``
        run into the demo's own folder).
    signature : iterable of str
        File names this command writes; an existing folder is replaced only when it is empty,
        carries the thermocal marker or holds one of these files (a previous run's results).

    Raises
    ------
    ThermocalInputError
        ``out`` is a file, lies below a file, is the current folder or one of its parents,
        or holds files thermocal did not write.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ThermocalInputError(
            f"--out {out} is a file, not a folder; give a folder name (it is created)"
        )
    for parent in out.parents:
        if parent.exists() and not parent.is_dir():
            raise ThermocalInputError(
                f"--out {out}: {parent} is a file, not a folder; choose another --out"
            )
        if parent.exists():
            break
    resolved = out.resolve()
    for path in inputs:
        if path is not None and resolved in Path(path).resolve().parents:
            raise ThermocalInputError(
                f"--out {out} holds the input {path}; thermocal replaces its output folder as a "
                "whole and would delete it: choose another --out (or move the input out first)"
            )
    cwd = Path.cwd().resolve()
    if resolved == cwd or resolved in cwd.parents:
        raise ThermocalInputError(
            f"--out {out} is the current folder (or contains it); thermocal replaces its "
            "output folder as a whole, so give a new folder name, e.g. --out results"
        )
    if out.is_dir():
        try:
            entries = {p.name for p in out.iterdir()}
        except OSError as exc:
            raise ThermocalInputError(f"--out {out}: {_describe_os_error(exc)}") from None
        kept = {
            name
            for name in entries
            if _is_lock(name) or any(fnmatch.fnmatch(name, pattern) for pattern in state)
        }
        if MARKER not in entries and entries - set(signature) - kept:
            # without the marker (a first run interrupted, thermocal before it, or someone
            # else's folder) only the command's own result and state files may be there
            entries = entries - set(signature) - kept
            shown = ", ".join(sorted(entries)[:5]) + (", ..." if len(entries) > 5 else "")
            raise ThermocalInputError(
                f"--out {out} already holds files thermocal did not write ({shown}); "
                "thermocal replaces its output folder as a whole, so choose a new or empty "
                "folder"
            )
        if MARKER in entries:
            foreign, changed = _not_as_written(out, tuple(state))
            if foreign or changed:
                names = foreign + changed
                shown = ", ".join(names[:5]) + (", ..." if len(names) > 5 else "")
                what = (
                    "files thermocal did not write" if not changed
                    else "files changed since thermocal wrote them" if not foreign
                    else "files thermocal did not write or that changed since"
                )  # fmt: skip
                raise ThermocalInputError(
                    f"--out {out} holds {what} ({shown}); thermocal replaces its output folder "
                    "as a whole and would delete them: move them elsewhere or choose another "
                    "--out"
                )


def _is_lock(name: str) -> bool:
    """Whether a file name is a lock file (``.NAME.lock``): one a killed process left behind
    is harmless (its OS lock died with it) and belongs to nobody's results."""
    return name.startswith(".") and name.endswith(".lock")


def _manifest(folder: Path) -> dict[str, list[int]]:
    """Every file below ``folder`` but the marker: relative path -> [size, mtime_ns]."""
    files = {}
    for path in sorted(folder.rglob("*")):
        if path.is_file() and path.name != MARKER:
            info = path.stat()
            files[path.relative_to(folder).as_posix()] = [info.st_size, info.st_mtime_ns]
    return files


def _not_as_written(out: Path, state: tuple[str, ...]) -> tuple[list[str], list[str]]:
    """The files of ``out`` not in its marker's list, and those whose size or modification
    time differ from it (both as relative paths); ``state`` patterns are left out. A marker
    without a list (thermocal before 2026-11-30) lists nothing to compare: ([], [])."""
    try:
        written = json.loads((out / MARKER).read_text(encoding="utf-8"))["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return [], []
    foreign, changed = [], []
    for name, stamp in _manifest(out).items():
        if _is_lock(Path(name).name) or any(fnmatch.fnmatch(name, pattern) for pattern in state):
            continue
        if name not in written:
            foreign.append(name)
        elif list(written[name]) != stamp:
            changed.append(name)
    return foreign, changed


class FileLock:
    """An exclusive OS lock on a lock file (released when the process dies, even by SIGKILL).

    Parameters
    ----------
    path : Path
        The lock file; created, and removed on :meth:`release`.
    busy : str
        Message of the error raised when another process holds the lock.
    what : str
        Prefix of the message when the lock file cannot be created (e.g. ``"--out X"``).
    """

    def __init__(self, path: Path, *, busy: str, what: str) -> None:
        self.path = Path(path)
        self.busy = busy
        self.what = what
        self.fd: int | None = None

    def acquire(self) -> FileLock:
        """Take the lock or raise :class:`ThermocalInputError` (``busy``)."""
        busy = ThermocalInputError(self.busy)
        for _ in range(20):
            try:
                flags = os.O_RDWR | os.O_CREAT | (0 if fcntl else os.O_EXCL)
                fd = os.open(self.path, flags, 0o644)
            except FileExistsError:  # pragma: no cover - without fcntl
                raise busy from None
            except OSError as exc:
                raise ThermocalInputError(f"{self.what}: {_describe_os_error(exc)}") from None
            if fcntl is None:  # pragma: no cover
                self.fd = fd
                return self
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(fd)
                raise busy from None
            # the holder before us may have removed the file after we opened it: retry then
            try:
                same = os.path.samestat(os.fstat(fd), os.stat(self.path))
            except FileNotFoundError:
                same = False
            if same:
                self.fd = fd
                os.write(fd, f"{os.getpid()}\n".encode())
                return self
            os.close(fd)
        raise busy  # pragma: no cover - twenty races in a row

    def release(self) -> None:
        """Remove the lock file and release the lock (idempotent)."""
        if self.fd is None:
            return
        with contextlib.suppress(OSError):
            os.unlink(self.path)
        os.close(self.fd)
        self.fd = None


def _output_lock(out: Path) -> FileLock:
    """The lock ``.NAME.lock`` beside an output folder."""
    path = out.parent / f".{out.name}.lock"
    return FileLock(
        path,
        busy=f"--out {out}: another thermocal run is writing this folder (lock {path}); wait "
        "for it to finish or choose another --out",
        what=f"--out {out}",
    )


@contextlib.contextmanager
def _signals_blocked() -> Iterator[None]:
    """Hold SIGINT/SIGTERM back during the final renames (delivered right after)."""
    mask = getattr(signal, "pthread_sigmask", None)
    if mask is None:  # pragma: no cover - Windows
        yield
        return
    import threading

    if threading.current_thread() is not threading.main_thread():  # pragma: no cover
        yield
        return
    old = mask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        mask(signal.SIG_SETMASK, old)


def _replace(tmp: Path, out: Path) -> None:
    """Move the completed ``tmp`` into place of ``out`` (the old folder removed after)."""
    old: Path | None = None
    placed = False
    try:
        with _signals_blocked():
            if out.exists():
                old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
                old.rmdir()
                os.replace(out, old)
            try:
                os.replace(tmp, out)
            except OSError:
                if old is not None:
                    os.replace(old, out)  # if this fails too, the old results stay in old
                raise
            placed = True
    finally:  # also when a signal held back during the renames arrives as they end
        if placed and old is not None:
            shutil.rmtree(old, ignore_errors=True)


@contextlib.contextmanager
def output_folder(
    out: Path | str, *, command: str, signature: Iterable[str] = (), state: Iterable[str] = ()
) -> Iterator[Path]:
    """Write a command's results into ``out`` atomically.

    Yields a temporary folder beside ``out``; write everything there. When the block ends
    normally, the temporary folder replaces ``out`` (an older run's results are removed in the
    same step); when it raises (an error, Ctrl-C, SIGTERM), the temporary folder is removed
    and ``out`` is left as it was.

    Parameters
    ----------
    out : Path or str
        The output folder (``--out``).
    command : str
        The command's name, written into the marker file.
    signature : iterable of str
        File names the command writes (see :func:`check_output_folder`).
    state : iterable of str
        Patterns of the files the command keeps up to date in ``out`` (see
        :func:`check_output_folder`).

    Raises
    ------
    ThermocalInputError
        ``out`` is unusable (see :func:`check_output_folder`), its parent is not writable or
        another run is writing it.
    """
    global last_interrupted, last_completed
    out = Path(out)
    check_output_folder(out, signature=signature, state=state)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ThermocalInputError(
            f"--out {out}: cannot create {out.parent}: {_describe_os_error(exc)}"
        ) from None
    lock = _output_lock(out).acquire()
    tmp: Path | None = None
    last_interrupted = None
    last_completed = None
    try:
        try:
            tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.tmp-", dir=out.parent))
            os.chmod(tmp, 0o777 & ~current_umask())  # mkdtemp's 0700 would survive the rename
            (tmp / MARKER).write_text(f"written by thermocal {command}\n", encoding="utf-8")
        except OSError as exc:
            raise ThermocalInputError(f"--out {out}: {_describe_os_error(exc)}") from None
        try:
            yield tmp
        except OSError as exc:
            if exc.errno in (errno.ENOSPC, errno.EACCES, errno.EPERM, errno.EROFS, errno.EDQUOT):
                kept = " (its previous contents are kept)" if out.exists() else ""
                raise ThermocalInputError(
                    f"writing the results into {out} failed: {_describe_os_error(exc)}; "
                    f"nothing was written{kept}"
                ) from None
            raise
        except BaseException:
            last_interrupted = (
                f"nothing written; {out} keeps its previous results"
                if out.exists()
                else "nothing written"
            )
            raise
        try:
            # the marker lists what this run wrote: a later run refuses the folder once a
            # file is added or changed (it would delete it)
            (tmp / MARKER).write_text(
                json.dumps({"written_by": f"thermocal {command}", "files": _manifest(tmp)}),
                encoding="utf-8",
            )
            _replace(tmp, out)
        except OSError as exc:
            raise ThermocalInputError(
                f"moving the results into {out} failed: {_describe_os_error(exc)}"
            ) from None
        except BaseException:
            # a signal held back during the renames arrives as they end: the results are
            # then complete and in place
            if not tmp.exists():
                last_interrupted = f"after the results were complete: {out} holds them"
                tmp = None
            raise
        tmp = None
        last_completed = out
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        lock.release()
