"""The clock of a log checked against the sun: time stamps whose measured irradiance does not
follow the sun are refused.

Part of :mod:`thermocal.io.measurements`; see its docstring for the conventions.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

#: A clock this far off the sun is refused [h]; one hour is left alone (interval means labelled
#: by their start or end, or a daylight-saving hour, shift the profile by up to an hour).
MAX_SUN_SHIFT_H = 2.0


#: Whole days of data with daylight needed to read the clock from the day's edges [-].
MIN_DAYLIGHT_DAYS = 3
#: Irradiance this much above the data's night-time median (the sun 6 degrees or more below
#: the horizon: a pyranometer's offset) marks daylight [W/m2]. Low, so that dawn and dusk are
#: cut alike however cloudy either is (a threshold of 9 W/m2 put the centre of Zurich's foggy
#: February 2015 mornings half an hour late).
DAYLIGHT_THRESHOLD = 2.0


def hours_text(hours: float) -> str:
    """An offset's size for a message: ``"1 h"``, ``"0.5 h"`` (one decimal, none when whole).

    Parameters
    ----------
    hours : float
        The offset [h]; its sign is not shown.

    Returns
    -------
    str
    """
    return f"{abs(hours):.1f}".removesuffix(".0") + " h"


def daylight_centre_offset(
    values: pd.Series, elevation: np.ndarray, mid: pd.DatetimeIndex, step: pd.Timedelta
) -> float | None:
    """How much later the data's daylight is centred than the sun's, over whole days.

    Each interval is daylight in the data when its irradiance exceeds the night's median by
    :data:`DAYLIGHT_THRESHOLD`, and daylight at the site when the sun is above the horizon at
    its middle. On each day with every interval present and a dawn and a dusk in both (not
    the polar day or night), the centre of the daylight intervals' UTC times of day (a
    circular mean) is compared; the first and last intervals of daylight, cut by the
    threshold alike at dawn and dusk, leave the centre where it is.

    Parameters
    ----------
    values : pandas.Series
        Irradiance [W/m2], finite values on a regular tz-aware index (interval starts).
    elevation : ndarray
        The sun's elevation at the middle of each interval [deg].
    mid : pandas.DatetimeIndex
        The middle of each interval (tz-aware).
    step : pandas.Timedelta
        The interval.

    Returns
    -------
    float or None
        The offset [h] (positive: the data's clock is late), the days' mean trimmed of its
        lowest and highest fifths; None with fewer than :data:`MIN_DAYLIGHT_DAYS` such days.
    """
    irradiance = values.to_numpy(dtype=float)
    night = irradiance[np.asarray(elevation) < -6.0]
    offset = float(np.median(night)) if night.size else 0.0
    lit = irradiance > offset + DAYLIGHT_THRESHOLD
    up = np.asarray(elevation) > 0.0
    utc = mid.tz_convert("UTC")
    hour = (utc.asi8 // 10**9 % 86400) / 3600.0
    frame = pd.DataFrame({"day": utc.normalize(), "hour": hour, "lit": lit, "up": up})
    per_day = int(round(pd.Timedelta("1D") / step))
    grouped = frame.groupby("day", sort=True)
    whole = grouped["hour"].transform("size").to_numpy() == per_day
    # a day whose daylight has no edge (all dark, or the midnight sun) has no centre
    edged = np.ones(len(frame), dtype=bool)
    for column in ("lit", "up"):
        share = grouped[column].transform("mean").to_numpy()
        edged &= (share > 0.0) & (share < 1.0)
    frame = frame[whole & edged]
    if frame.empty:
        return None
    angle = 2.0 * np.pi * frame["hour"] / 24.0
    lit_centre = _circular_mean_hour(angle, frame["lit"], frame["day"])
    sun_centre = _circular_mean_hour(angle, frame["up"], frame["day"])
    both = lit_centre.notna() & sun_centre.notna()
    if int(both.sum()) < MIN_DAYLIGHT_DAYS:
        return None
    difference = np.sort(((lit_centre - sun_centre)[both] + 12.0) % 24.0 - 12.0)
    # each day's centre moves in half steps; the days' sunrises, moving through the steps,
    # dither that away in a mean, trimmed of its outer fifths (days the data got wrong)
    cut = len(difference) // 5
    return float(np.mean(difference[cut : len(difference) - cut]))


def _circular_mean_hour(angle: pd.Series, member: pd.Series, day: pd.Series) -> pd.Series:
    """Per day, the centre of the member intervals' times of day on the 24-h circle [h]
    (a daylight spanning midnight UTC, as in the Americas' evenings, stays one arc); NaN for
    a day without members."""
    cos = np.cos(angle).where(member).groupby(day).mean()
    sin = np.sin(angle).where(member).groupby(day).mean()
    return (np.degrees(np.arctan2(sin, cos)) / 15.0) % 24.0


def check_clock_against_sun(
    irradiance: pd.Series,
    latitude: float,
    longitude: float,
    *,
    source: str,
    column: str,
    timezone_setting: str = "the time zone",
) -> float:
    """Refuse time stamps whose measured irradiance does not follow the sun.

    The centre of each day's daylight in the data (the hours with irradiance) is compared
    with the centre of the hours the sun is up at the site (:func:`daylight_centre_offset`):
    the mean difference over the days is the error of the clock. Clouds change how much
    irradiance there is, not when the day starts and ends, so a month of morning fog (Zurich,
    February 2015) does not move it, while it moves the peak of the mean daily profile by an
    hour. With fewer than :data:`MIN_DAYLIGHT_DAYS` whole days of data the mean daily profile
    of the measured irradiance is compared with that of the sine of the sun's elevation
    instead (both by time of day in UTC; the circular shift that makes them agree best). A
    wrong time zone (Europe/Zurich for North Carolina data: 6 h) moves the sun and every solar
    gain by hours without any other sign.

    Parameters
    ----------
    irradiance : pandas.Series
        Irradiance [W/m2] (e.g. DNI + DHI) on a regular, tz-aware index of at most one hour,
        interval means labelled by their start.
    latitude, longitude : float
        The site [deg N, deg E].
    source, column : str
        For the message.
    timezone_setting : str
        The setting that fixes the clock (e.g. ``"measurements.timezone (now -5)"``).

    Returns
    -------
    float
        The clock's offset from the sun [h] (positive: the stamps are late), to 0.01 h from the
        day's edges, else in whole steps; 0 when the data have too little sun to tell.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        The offset is :data:`MAX_SUN_SHIFT_H` or more, naming the two times of the daily
        maximum and the offset.
    """
    from thermocal.physics.solar import solar_position

    values = irradiance.astype(float)
    values = values[np.isfinite(values.to_numpy())]
    if len(values) < 48 or values.index.tz is None:
        return 0.0
    values.index = pd.DatetimeIndex(values.index).as_unit("ns")
    step = pd.Timedelta(np.median(np.diff(values.index.asi8)), unit="ns")
    if not pd.Timedelta("1min") <= step <= pd.Timedelta("1h"):
        return 0.0
    mid = values.index + step / 2
    elevation = solar_position(mid, latitude, longitude)["elevation"].to_numpy()
    sun = np.clip(np.sin(np.radians(elevation)), 0.0, None)
    bins = int(round(pd.Timedelta("1D") / step))
    utc_seconds = (mid.asi8 // 10**9) % 86400
    which = (utc_seconds // int(step.total_seconds())).astype(int) % bins
    counts = np.bincount(which, minlength=bins)
    seen = counts > 0
    measured = np.bincount(which, weights=values.to_numpy(), minlength=bins)
    expected = np.bincount(which, weights=sun, minlength=bins)
    if seen.sum() < 0.9 * bins or measured.max() <= 0:
        return 0.0
    measured = np.where(seen, measured / np.maximum(counts, 1), 0.0)
    expected = np.where(seen, expected / np.maximum(counts, 1), 0.0)
    if measured.max() < 20.0:  # too little sun in the data to tell
        return 0.0

    def score(shift: int) -> float:
        a, b = measured, np.roll(expected, shift)
        a, b = a - a.mean(), b - b.mean()
        return float(a @ b / np.sqrt((a @ a) * (b @ b) + 1e-300))

    scores = np.array([score(k) for k in range(bins)])
    best = int(np.argmax(scores))
    if best > bins // 2:
        best -= bins
    hours = best * step / pd.Timedelta("1h")
    clear = scores[best % bins] - scores[0] > 0.05
    daylight = daylight_centre_offset(values, elevation, mid, step)
    if daylight is not None:  # the day's edges, which clouds do not move, decide
        hours, clear = round(daylight, 2), True
    if abs(hours) >= MAX_SUN_SHIFT_H and clear:
        tz = values.index.tz
        day = values.index[0].normalize()

        def clock(position: int) -> str:
            return (
                pd.Timestamp(day.tz_convert("UTC").normalize() + position * step + step / 2)
                .tz_convert(tz)
                .strftime("%H:%M")
            )

        peak = clock(int(np.argmax(measured)))
        raise ThermocalInputError(
            f"{source}: the irradiance ({column}) is highest around {peak} by the file's "
            f"clock, but at latitude {latitude:.2f}, longitude {longitude:.2f} the "
            f"sun is highest around {clock(int(np.argmax(expected)))}: the time stamps are "
            f"{hours_text(hours)} {'late' if hours > 0 else 'early'} (in UTC), which would move "
            f"every solar gain. Check {timezone_setting} and the UTC offsets of the time "
            "stamps (and the building's location)"
        )
    return hours
