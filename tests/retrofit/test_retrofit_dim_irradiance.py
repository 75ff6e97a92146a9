"""The retrofit workflow's check of an irradiance too dim for W/m2 (one helper with `fit`'s,
:func:`thermocal.statespace.units.dim_irradiance`): a log in kW/m2 is refused, a polar night
at the building's latitude is not."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.retrofit.config import MeasurementsConfig
from thermocal.retrofit.data import (
    check_irradiance_limits,
    prepare_measurements,
    read_raw_measurements,
)

TROMSO = SimpleNamespace(latitude=69.65, longitude=18.96, altitude=0.0, timezone="UTC")
MUNICH = SimpleNamespace(latitude=48.14, longitude=11.58, altitude=0.0, timezone="UTC")


def _log(tmp_path, start: str, days: int, sunlight) -> MeasurementsConfig:
    """An hourly hydronic log of ``days`` days from ``start`` (UTC): direct normal and diffuse
    irradiance ``sunlight(hour of day)`` [W/m2] (DNI twice the diffuse), a heated house."""
    index = pd.date_range(start, periods=24 * days, freq="1h", tz="UTC")
    hours = index.hour.to_numpy() + 0.5
    diffuse = np.asarray(sunlight(hours), float)
    frame = pd.DataFrame(
        {"time": index.strftime("%Y-%m-%dT%H:%M:%S+00:00"), "temp_out": -5.0,
         "flow": 1.0e-4, "temp_supply": 50.0, "temp_return": 40.0, "dni": 2.0 * diffuse,
         "dhi": diffuse, "temp_in": 21.0},
    )  # fmt: skip
    path = tmp_path / f"log_{start}.csv"
    frame.to_csv(path, index=False)
    return MeasurementsConfig(file=path, timezone="UTC")


def _checked(mc: MeasurementsConfig, location) -> None:
    """The measurements read and checked as the retrofit workflow and verify do."""
    raw = read_raw_measurements(mc)
    grid, _ = prepare_measurements(raw, mc.step)
    check_irradiance_limits(grid, mc, location, str(mc.file))


def _twilight(hours):
    """Up to 1.5 W/m2 of diffuse light around noon, nothing at night [W/m2]."""
    return np.clip(1.5 * np.cos((hours - 12.0) / 24.0 * 2 * np.pi), 0.0, None)


def _sunny_in_kw(hours):
    """A clear day of up to 0.35 kW/m2 diffuse (0.7 direct normal), as a log in kW/m2."""
    return np.clip(0.35 * np.sin((hours - 6.0) / 12.0 * np.pi), 0.0, None)


def test_a_polar_night_is_not_refused_as_an_irradiance_unit_slip(tmp_path):
    """Review of fuzz5 F-S2 (item 7): ten days of December in Tromso (the sun below the
    horizon all day, a few W/m2 of twilight at most) were refused as 'never exceed 2.97 ...
    they must be in W/m2' by the retrofit workflow (its own copy of fit's check, without the site),
    while fit only flagged them. Now the days whose noon sun stays low at the building's
    latitude do not count: read and checked without error."""
    _checked(_log(tmp_path, "2023-12-01", 10, _twilight), TROMSO)


def test_the_same_twilight_where_the_sun_climbs_and_a_log_in_kw_are_refused(tmp_path):
    """The same twilight in Munich in December (noon sun 18 deg) is no irradiance in W/m2:
    refused, naming the columns, their keys and the remedy; and so is a log in kW/m2 in
    Tromso in March (noon sun 16-20 deg), with the same remedy."""
    with pytest.raises(ThermocalInputError) as munich:
        _checked(_log(tmp_path, "2023-12-01", 10, _twilight), MUNICH)
    text = str(munich.value)
    assert "'dni' and 'dhi' never exceed 2.97 W/m2 over 9.96 days" in text
    assert "measurements.columns.dni and measurements.columns.dhi" in text
    assert "kWh/m2: multiply by 1000" in text
    assert "not counted" not in text  # every day counts in Munich

    with pytest.raises(ThermocalInputError, match=r"'dni' and 'dhi' never exceed 0\.69 W/m2"):
        _checked(_log(tmp_path, "2023-03-10", 10, _sunny_in_kw), TROMSO)
    # an overcast spell in W/m2 (up to 100 W/m2 diffuse) on the same days passes
    _checked(_log(tmp_path, "2023-03-20", 10, lambda h: 300.0 * _sunny_in_kw(h)), TROMSO)


def test_polar_night_days_are_left_out_of_a_log_that_reaches_the_sun(tmp_path):
    """A log in kW/m2 from the end of the polar night into March in Tromso: the days with the
    noon sun above 10 deg (from about 24 February) are enough to refuse it; the message says
    the other days were not counted."""
    mc = _log(tmp_path, "2024-01-20", 45, _sunny_in_kw)
    with pytest.raises(ThermocalInputError, match=r"never exceed .* \(days of a polar night"):
        _checked(mc, TROMSO)
