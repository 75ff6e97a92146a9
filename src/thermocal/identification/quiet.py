"""Quiet hours from the data: when the building's internal and HVAC heat is really constant.

The calibration metric is the variance of the identified heat over hours whose internal gains
are constant, so that what varies is the envelope's error. The published method fixes those
hours by a schedule (nights 20-04, Saturdays 11-20, Sundays); a building whose equipment runs on
Saturday mornings or whose night set-back starts at 22:00 puts occupied hours into the metric,
and the calibration then fits occupancy, not the envelope.

Here the quiet hours are read off the identified heat itself: its hour-of-week profile (the
median over the weeks of each weekday and hour, which averages the weather out) has a low
plateau when nothing runs; an hour of the week is quiet when its median lies within a small
fraction of the occupied swing above that plateau, and stays so for the hour before (the
radiant and stored part of the gains decays over an hour or more). A metered electricity
series can be given instead of the identified heat.

The result is an ordinary :class:`~thermocal.identification.occupancy.OccupancySchedule`, so
the metric, the report and the campaign file treat it like any other schedule;
:func:`check_schedule` says whether a given schedule (the paper's) is demonstrably not quiet.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.identification.occupancy import (
    DAY_NAMES,
    OccupancySchedule,
    UnoccupiedWindow,
    unoccupied_mask,
)
from thermocal.textformat import shortened_list

__all__ = ["QuietHours", "ScheduleCheck", "check_schedule", "hour_of_week_profile", "quiet_hours"]

#: An hour is quiet when its median heat is within this fraction of the occupied swing
#: (90th minus 10th percentile of the hour-of-week profile) above the plateau [-].
QUIET_FRACTION = 0.15
#: A schedule is demonstrably not quiet when its hours that are not quiet raise the standard
#: deviation of its hour-of-week heat profile by more than this fraction [-] (the metric is a
#: variance: four occupied hours a week can dominate it).
NOT_QUIET_STD_INCREASE = 0.10
#: Fewest weeks of data for an hour-of-week profile [-].
MIN_WEEKS = 2


def hour_of_week_profile(heat: pd.Series) -> pd.Series:
    """Median over the weeks of the hourly mean heat, per weekday and hour.

    Parameters
    ----------
    heat : Series
        Building-wide heat per step [W], indexed by the step start (local time).

    Returns
    -------
    Series
        Index 0..167 (Monday 00-01 = 0) [W]; NaN where no data.
    """
    hourly = heat.astype(float).resample("1h").mean().dropna()
    how = hourly.index.day_of_week * 24 + hourly.index.hour
    return hourly.groupby(how).median().reindex(range(168))


@dataclass(frozen=True)
class QuietHours:
    """Quiet hours found in the data.

    Attributes
    ----------
    mask : ndarray of bool (168,)
        Quiet hours of the week (Monday 00-01 = 0).
    profile : Series
        Hour-of-week median heat [W].
    plateau : float
        Heat level of the quiet plateau (10th percentile of the profile) [W].
    threshold : float
        Highest median heat of a quiet hour [W].
    schedule : OccupancySchedule
        The quiet hours as unoccupied windows.
    """

    mask: np.ndarray
    profile: pd.Series
    plateau: float
    threshold: float
    schedule: OccupancySchedule

    @property
    def hours_per_week(self) -> int:
        """Number of quiet hours in a week [h]."""
        return int(self.mask.sum())

    def describe(self) -> str:
        """The quiet windows in words, e.g. ``Mon 21:00-24:00; Tue 00:00-05:00; ...``."""
        return "; ".join(
            f"{DAY_NAMES[w.days[0]]} {w.start:02.0f}:00-{w.end:02.0f}:00"
            for w in self.schedule.windows
        )


def _schedule_from_mask(mask: np.ndarray) -> OccupancySchedule:
    """Unoccupied windows (one per day and contiguous run) of an hour-of-week mask."""
    windows = []
    for day in range(7):
        hours = mask[day * 24:(day + 1) * 24]
        start = None
        for h in range(25):
            on = h < 24 and bool(hours[h])
            if on and start is None:
                start = h
            elif not on and start is not None:
                windows.append(UnoccupiedWindow((day,), float(start), float(h)))
                start = None
    return OccupancySchedule(tuple(windows), ())


def quiet_hours(heat: pd.Series, *, fraction: float = QUIET_FRACTION) -> QuietHours:
    """The hours of the week whose heat is at the quiet plateau.

    Parameters
    ----------
    heat : Series
        Building-wide identified heat (or metered electricity) per step [W], indexed by the
        step start in the building's local time; at least two weeks.
    fraction : float
        Share of the occupied swing above the plateau still counted as quiet [-].

    Returns
    -------
    QuietHours

    Raises
    ------
    ThermocalInputError
        Less than two weeks of data, or no hour at the plateau.
    """
    if not isinstance(heat.index, pd.DatetimeIndex) or len(heat) < 2:
        raise ThermocalInputError("quiet hours: the heat needs a time index")
    span = heat.index[-1] - heat.index[0]
    if span < pd.Timedelta(weeks=MIN_WEEKS) - pd.Timedelta("1h"):
        raise ThermocalInputError(
            f"quiet hours: {span} of data; at least {MIN_WEEKS} weeks are needed to tell "
            "weekly routines from weather (give an occupancy schedule instead)"
        )
    profile = hour_of_week_profile(heat)
    values = profile.to_numpy()
    finite = np.isfinite(values)
    plateau, top = np.nanpercentile(values, [10, 90])
    threshold = plateau + float(fraction) * max(top - plateau, 0.0)
    # the weather leaves its own scatter on the plateau (a few weeks do not average it out):
    # an hour within three robust standard deviations of the plateau's centre is quiet too
    near = values[finite & (values <= threshold)]
    if near.size >= 8:
        centre = float(np.median(near))
        scatter = 1.4826 * float(np.median(np.abs(near - centre)))
        threshold = max(threshold, min(centre + 3.0 * scatter, 0.5 * (plateau + top)))
    low = finite & (values <= threshold)
    # the hour before must be quiet too: stored and radiant gains decay over an hour or more
    mask = low & np.roll(low, 1)
    if not mask.any():
        raise ThermocalInputError(
            "quiet hours: no hour of the week has a steady low heat; give an occupancy schedule"
        )
    return QuietHours(mask, profile, float(plateau), float(threshold), _schedule_from_mask(mask))


@dataclass(frozen=True)
class ScheduleCheck:
    """How quiet a schedule's unoccupied hours are in the data.

    Attributes
    ----------
    hours : int
        Unoccupied hours of the week in the schedule [h].
    not_quiet : list of int
        Those whose median heat is above the quiet threshold (hour of week).
    excess : float
        Mean heat of those hours above the plateau [W].
    std_increase : float
        How much those hours raise the standard deviation of the schedule's hour-of-week heat
        profile, relative to its quiet hours alone [-].
    """

    hours: int
    not_quiet: list
    excess: float
    std_increase: float = 0.0

    @property
    def share_not_quiet(self) -> float:
        """Share of the schedule's hours that are not quiet [-]."""
        return len(self.not_quiet) / self.hours if self.hours else 0.0

    @property
    def quiet(self) -> bool:
        """False when the schedule demonstrably is not quiet."""
        return not self.not_quiet or self.std_increase <= NOT_QUIET_STD_INCREASE

    def describe(self) -> str:
        """In words, naming the first offending hours."""
        if not self.not_quiet:
            return f"all {self.hours} unoccupied hours of the schedule are quiet in the data"
        first = shortened_list(f"{DAY_NAMES[h // 24]} {h % 24:02d}:00" for h in self.not_quiet)
        return (
            f"{len(self.not_quiet)} of the schedule's {self.hours} unoccupied hours a week "
            f"({self.share_not_quiet:.0%}) are not quiet in the data, on average "
            f"{self.excess / 1000:.2f} kW above the quiet level ({first}); they raise the "
            f"spread of the metric's hours by {self.std_increase:.0%}"
        )


def check_schedule(quiet: QuietHours, schedule: OccupancySchedule) -> ScheduleCheck:
    """Which of a schedule's unoccupied hours the data show not to be quiet.

    Parameters
    ----------
    quiet : QuietHours
        From :func:`quiet_hours`.
    schedule : OccupancySchedule
        E.g. the published method's.

    Returns
    -------
    ScheduleCheck
    """
    week = pd.date_range("2001-01-01", periods=168, freq="h")  # 2001-01-01 is a Monday
    unocc = unoccupied_mask(week, schedule)
    values = quiet.profile.to_numpy()
    bad = [int(h) for h in np.flatnonzero(unocc & np.isfinite(values)
                                          & (values > quiet.threshold))]
    excess = float(np.mean(values[bad]) - quiet.plateau) if bad else 0.0
    inside = unocc & np.isfinite(values)
    calm = inside.copy()
    calm[bad] = False
    increase = 0.0
    if bad and calm.sum() >= 2:
        std_all, std_calm = np.std(values[inside]), np.std(values[calm])
        increase = float(std_all / std_calm - 1.0) if std_calm > 0 else float("inf")
    return ScheduleCheck(int(unocc.sum()), bad, excess, increase)
