"""A peer commit's ``src`` for the benchmarks that time this tree against another commit."""

from __future__ import annotations

import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def peer_source(commit: str) -> Path:
    """``src`` of ``commit``, extracted once into the user's cache with ``git archive``."""
    target = Path.home() / ".cache" / "thermocal-bench" / commit / "src"
    if not target.exists():
        target.parent.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(REPO), "archive", commit, "src"],
                                 check=True, capture_output=True).stdout  # fmt: skip
        subprocess.run(["tar", "-x", "-C", str(target.parent)], input=archive, check=True)
    return target
