"""Small helpers of the simulation loop shared by its parts (chunking, tracking forms,
factorisation, progress)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from scipy.sparse.linalg import splu

from thermocal.errors import ThermocalInputError

_CHUNK = 2048


def _tracking_form(feedback, radiant_fraction, n_tracked: int) -> tuple:
    """``(air_weight, radiant_fraction)`` tuples over the tracked zones, validated."""
    if isinstance(feedback, str):
        if feedback not in ("air", "operative"):
            raise ThermocalInputError(
                f"track: feedback must be 'air', 'operative' or an air weight in [0, 1], got "
                f"{feedback!r}"
            )
        feedback = 1.0 if feedback == "air" else 0.5
    out = []
    for name, value in (("feedback air weight", feedback), ("radiant_fraction", radiant_fraction)):
        try:
            array = np.broadcast_to(np.asarray(value, dtype=float), n_tracked)
        except (TypeError, ValueError):
            raise ThermocalInputError(
                f"track: {name} must be a number or one per tracked zone ({n_tracked}), got "
                f"{value!r}"
            ) from None
        if not np.all((array >= 0.0) & (array <= 1.0)):
            raise ThermocalInputError(f"track: {name} must lie in [0, 1], got {value!r}")
        out.append(tuple(float(v) for v in array))
    return tuple(out)


_NO_IMPLICIT = (np.zeros(0, dtype=np.int64), np.zeros((0, 0)), np.zeros(1), np.zeros((0, 0)))


_NO_VENT = (np.zeros(0, dtype=np.int64),) + (np.zeros((0, 0)),) * 7


_NO_TRACKED_AIR = (
    np.zeros(0, dtype=np.int64),
    np.zeros((0, 0)),
    np.zeros((0, 0)),
    np.zeros((0, 0)),
    np.zeros(1),
    np.zeros((0, 0)),
)


def kernel_array(values) -> np.ndarray:
    """``values`` as the time loop takes them: contiguous float64 and writable, copied only when
    needed. A read-only array (a broadcast view, a pandas frame's values under copy-on-write)
    would compile the whole loop a second time, for that type: about 12 s of a first run."""
    array = np.ascontiguousarray(values, dtype=float)
    return array if array.flags.writeable else array.copy()


def _no_tracking(n: int) -> dict:
    """Kernel arguments of the tracking modes when no zone is tracked."""
    empty = np.zeros(0)
    return {
        "mode": 0,
        "reference": np.zeros((n, 0)),
        "general": False,
        "w_air": np.zeros(0),
        "distribution": (np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0)),
        "pid": (empty, empty, empty),
        "pid_state": np.zeros((0, 2)),
        "feedback": empty,
        "q_low": empty,
        "q_high": empty,
        "g_inverse": np.zeros((0, 0)),
        "out_q": np.zeros((n, 0)),
    }


def _hourly_first_day(values: np.ndarray, per_day: int, per_hour: int) -> np.ndarray:
    """Hourly means of the first day of a per-step array (rows = steps)."""
    first = values[:per_day]
    return first.reshape(24, per_hour, *first.shape[1:]).mean(axis=1)


def _factorise(matrix):
    """Sparse LU with a symmetric minimum-degree ordering (the matrices are M-matrices, symmetric
    but for the rows of mirrored outside faces, diagonally dominant by rows, so diagonal pivots
    are safe and the fill stays minimal)."""
    return splu(
        matrix,
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )


def _progress(enabled: bool, total: int):
    if not enabled:
        return None
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    bar = Progress(
        TextColumn("simulating"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeRemainingColumn(),
    )
    bar.start()
    task = bar.add_task("simulate", total=total)
    return bar, task


class OutdoorAirExcess(NamedTuple):
    """Outdoor-air conductance of each zone beyond its matrix value, per step, kept compact.

    Zone ``z`` at step ``k`` takes ``ratio[k] x base[z]`` (the air density's variation of a
    constant rate) when ``column[z] < 0``, else ``scheduled[k, column[z]]`` (a scheduled rate's
    own series): a month at 5 minutes of the clinic's 186 zones in one array per zone was
    13 MB of every campaign worker, of which the scheduled zones are usually few.
    """

    ratio: np.ndarray  # (steps,) [-]
    base: np.ndarray  # (zones,) [W/K]
    column: np.ndarray  # (zones,) int64, -1: ratio x base
    scheduled: np.ndarray  # (steps, scheduled zones) [W/K]

    def full(self, steps: int | None = None) -> np.ndarray:
        """The excess of every zone at each of the first ``steps`` steps (default: all),
        (steps, zones) [W/K]."""
        out = self.ratio[:steps, None] * self.base[None, :]
        own = np.flatnonzero(self.column >= 0)
        out[:, own] = self.scheduled[:steps, self.column[own]]
        return out

    def zero(self) -> OutdoorAirExcess:
        """The same layout with no excess (the linear network)."""
        return OutdoorAirExcess(
            np.zeros_like(self.ratio), self.base, self.column, np.zeros_like(self.scheduled)
        )

    def hourly_first_day(self, per_day: int, per_hour: int) -> OutdoorAirExcess:
        """Hourly means of the first day, every zone in its own column (24 rows)."""
        hourly = _hourly_first_day(self.full(per_day), per_day, per_hour)
        columns = np.arange(len(self.base), dtype=np.int64)
        return OutdoorAirExcess(np.zeros(24), self.base, columns, np.ascontiguousarray(hourly))


@dataclass
class _Context:
    """Everything of the time loop that depends on the step size."""

    dt: float
    lu: object
    factors: tuple
    dirichlet: tuple
    air_rows: tuple
    c_dt: np.ndarray
    g_ctrl: np.ndarray
    inputs: np.ndarray
    ext_dh: np.ndarray
    inf_dh: OutdoorAirExcess
    face_hmax: np.ndarray
    ext_natural: np.ndarray = None  # (n_ext, 5): mode, roughness, cos tilt, hc0, max excess
    heat_sp: np.ndarray = None  # (1 or n_steps, n_controlled) [C]
    cool_sp: np.ndarray = None
    inf_dt: np.ndarray = None  # (0, 1 or n_steps, n_zones) [W/K^2]
    people_a: np.ndarray = None  # (0 or n_steps, n_zones) [W]
    people_b: np.ndarray = None  # (0 or n_steps, n_zones) [W/K]
    people_c: np.ndarray = None  # (0 or n_steps, n_zones) [W/K^2]
    people_max: np.ndarray = None  # (0 or n_steps, n_zones) [W]
    d_lu: object = None  # factorisation of the Dirichlet system (None: no controlled zones)
    vent: tuple = None  # indoor-limited ventilation arrays of the kernel (see _ventilation_arrays)
    implicit: dict = field(default_factory=dict)  # implicit outdoor-air sets -> kernel arrays
