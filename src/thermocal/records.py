"""Stated track records against what a run measures (shared by the retrofit and the
calibration reports, whose records of the independent references the twins' tests keep
current)."""

from __future__ import annotations

__all__ = ["differs_from"]


def differs_from(check, measured: dict, *, tolerance: float = 0.05 + 1e-9) -> dict:
    """The fields where a measured check differs from the stated one beyond its rounding.

    Parameters
    ----------
    check : dataclass instance
        The record a report states (e.g. :class:`thermocal.retrofit.track_record.
        IndependentCheck`), with an attribute per key of ``measured``.
    measured : dict
        The same figures of a run (e.g.
        :func:`thermocal.retrofit.track_record.measured_check`).
    tolerance : float
        Largest difference of a stated decimal figure from the measured one: half its last
        digit, so that the measured value rounds to the stated one [% or pp].

    Returns
    -------
    dict
        Field -> (stated, measured), empty when the record holds.
    """
    out = {}
    for name, value in measured.items():
        stated = getattr(check, name)
        # a stated decimal figure is the measured one rounded; a count, a flag or a word exactly
        if isinstance(stated, float):
            same = abs(stated - float(value)) <= tolerance
        else:
            same = stated == value
        if not same:
            out[name] = (stated, value)
    return out
