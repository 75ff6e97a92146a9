"""Files written atomically: complete under their name, or not there at all."""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path


def atomic_write(path: Path | str, write: Callable[[Path], object]) -> Path:
    """Write a file atomically: ``write(tmp_path)`` into the same folder, then ``os.replace``.

    The file gets the permissions an ordinary write would give it (:func:`_ordinary_mode`), not
    the owner-only 0600 of the temporary file.

    Parameters
    ----------
    path : path-like
        Destination file.
    write : callable
        Called with the temporary path; must create the file there.

    Returns
    -------
    Path
        The destination.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    mode = _ordinary_mode(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        write(Path(tmp))
        os.chmod(tmp, mode)  # mkstemp's 0600 would survive the rename
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _ordinary_mode(path: Path) -> int:
    """The permission bits an ordinary ``open(path, "w")`` would leave on ``path``.

    Parameters
    ----------
    path : Path
        Destination file.

    Returns
    -------
    int
        The mode of the file being replaced when there is one (as opening it for writing keeps
        it), else ``0o666`` less the process's umask (0644 under umask 022).
    """
    try:
        return stat.S_IMODE(path.stat().st_mode)
    except FileNotFoundError:
        return 0o666 & ~current_umask()


def current_umask() -> int:
    """The process's file-mode creation mask.

    Read from ``/proc/self/status`` (Linux 4.7+) without changing it; elsewhere by setting and
    restoring it, which another thread creating a file in between would see as 0.

    Returns
    -------
    int
        E.g. ``0o022``.
    """
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    umask = os.umask(0)
    os.umask(umask)
    return umask


def atomic_parquet(path: Path | str, frame) -> Path:
    """Write a data frame as a parquet file atomically (:func:`atomic_write`), then hand the
    blocks Arrow's allocator kept from the conversion back to the system.

    Arrow's default allocator keeps freed blocks for reuse; after the identification's
    ``q_id.parquet`` of the clinic month (two methods, 374 columns) that was 40 MiB of the
    process's resident memory for the rest of the command.

    Parameters
    ----------
    path : path-like
        Destination file.
    frame : pandas.DataFrame
        What to write (``DataFrame.to_parquet``, its index kept).

    Returns
    -------
    Path
        The destination.
    """
    import pyarrow

    try:
        return atomic_write(path, frame.to_parquet)
    finally:
        pyarrow.default_memory_pool().release_unused()
