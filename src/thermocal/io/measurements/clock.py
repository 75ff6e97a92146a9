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

    The mean daily profile of the measured irradiance is compared with that of the sine of the
    sun's elevation at the site (both by time of day in UTC); the circular shift that makes
    them agree best is the error of the clock. A wrong time zone (Europe/Zurich for North
    Carolina data: 6 h) moves the sun and every solar gain by hours without any other sign.

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
        The clock's offset from the sun [h] (positive: the stamps are late); 0 when the data
        have too little sun to tell.

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
    if abs(hours) >= MAX_SUN_SHIFT_H and scores[best % bins] - scores[0] > 0.05:
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
            f"{abs(hours):.0f} h {'late' if hours > 0 else 'early'} (in UTC), which would move "
            f"every solar gain. Check {timezone_setting} and the UTC offsets of the time "
            "stamps (and the building's location)"
        )
    return hours
