"""Occupants as users know them (issue 25 item 4): a count on top of any gains source, with
SIA 380/1:2016's standard use values of housing (70 W, 12 h a day) as defaults."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import yaml
from pydantic import ValidationError
from retrofit_synthetic import make_dataset

from thermocal.retrofit import load_config, run_retrofit
from thermocal.retrofit.config import InternalGainsConfig
from thermocal.retrofit.gains import (
    OCCUPANT_PRESENCE,
    combined_rel_std,
    gains_day_profile,
    has_gains,
    internal_gains,
    occupant_day_profile,
)


def _grid(days: int = 3) -> pd.DataFrame:
    index = pd.date_range("2015-02-02", periods=24 * days, freq="h")
    return pd.DataFrame({"phi_el": np.full(len(index), 400.0)}, index=index)


def test_default_presence_is_twelve_hours_at_home_at_night():
    """SIA 380/1:2016 housing: 12 h of presence a day; the shape is at home at night."""
    presence = np.asarray(OCCUPANT_PRESENCE)
    assert presence.shape == (24,)
    assert presence.sum() == pytest.approx(12.0)
    assert presence.min() >= 0.0 and presence.max() <= 1.0
    assert presence[2] > 2.0 * presence[11]  # 02:00 at home, 11:00 mostly away


def test_three_occupants_on_top_of_an_electricity_meter():
    cfg = InternalGainsConfig(source="electricity", electricity_unit="W", occupants=3)
    grid = _grid()
    gains = internal_gains(grid, cfg)
    people = 3 * 70.0 * np.asarray(OCCUPANT_PRESENCE)
    np.testing.assert_allclose(gains.to_numpy()[:24], 400.0 + people)
    # 3 x 70 W x 12 h = 2.52 kWh a day, 920 kWh a year
    assert (gains - 400.0).sum() / 3 / 1000.0 == pytest.approx(2.52)
    day = gains_day_profile(gains, cfg)
    np.testing.assert_allclose(day, 400.0 + people)
    # the meter alone: unchanged by the occupants' keys' defaults
    alone = InternalGainsConfig(source="electricity", electricity_unit="W")
    np.testing.assert_allclose(internal_gains(grid, alone).to_numpy(), 400.0)
    assert occupant_day_profile(alone) is None


@pytest.mark.parametrize("source", ["none", "constant", "schedule"])
def test_occupants_on_top_of_every_source(source):
    extra = {"constant": {"constant_W": 300.0}, "schedule": {"schedule_W": [300.0] * 24}}
    cfg = InternalGainsConfig(
        source=source, occupants=2, occupant_sensible_W=80.0, **extra.get(source, {})
    )
    assert has_gains(cfg)
    grid = _grid()
    gains = internal_gains(grid, cfg)
    base = 0.0 if source == "none" else 300.0
    people = 2 * 80.0 * np.asarray(OCCUPANT_PRESENCE)
    np.testing.assert_allclose(gains.to_numpy()[24:48], base + people)
    np.testing.assert_allclose(gains_day_profile(gains, cfg), base + people)


def test_combined_uncertainty_of_source_and_occupants():
    """Independent errors: sqrt((0.3 G_s)^2 + (0.3 G_o)^2) / (G_s + G_o)."""
    cfg = InternalGainsConfig(source="constant", constant_W=420.0, occupants=1,
                              occupant_presence=[1.0] * 24, occupant_sensible_W=70.0)  # fmt: skip
    day = gains_day_profile(pd.Series(dtype=float), cfg)
    assert day.mean() == pytest.approx(490.0)
    expected = np.hypot(0.3 * 420.0, 0.3 * 70.0) / 490.0
    assert combined_rel_std(day, cfg) == pytest.approx(expected)
    only = InternalGainsConfig(occupants=2, occupants_rel_std=0.4)
    assert combined_rel_std(gains_day_profile(pd.Series(dtype=float), only), only) == (
        pytest.approx(0.4)
    )


@pytest.mark.parametrize(
    ("keys", "match"),
    [
        ({"occupants": -1}, "number of people"),
        ({"occupants": 400}, "number of people"),
        ({"occupants": 3, "occupant_sensible_W": 0.07}, "is it in kW"),
        ({"occupants": 3, "occupant_sensible_W": 900}, "sensible heat of one person"),
        ({"occupants": 3, "occupant_presence": [0.5] * 23}, "24 hourly"),
        ({"occupants": 3, "occupant_presence": [1.5] + [0.5] * 23}, "between 0 and 1"),
        ({"occupant_sensible_W": 80}, "without occupants"),
        ({"occupants": 3, "occupants_rel_std": 2.0}, "less than or equal"),
    ],
)
def test_bad_occupant_values_are_refused(keys, match):
    with pytest.raises(ValidationError, match=match):
        InternalGainsConfig(**keys)


def test_occupants_recover_the_house_their_heat_was_taken_from(tmp_path):
    """The synthetic house's metered heat minus three occupants' sensible heat (on no meter):
    without ``occupants`` the calibration sees less heat and a smaller heat loss coefficient;
    with ``occupants: 3`` it finds the house of the whole heat again (within 2 %), and the
    occupants lower the annual demand."""
    from thermocal.physics.hydronics import heating_power

    config = make_dataset(tmp_path, days=28.0)
    cfg = yaml.safe_load(config.read_text())
    cfg["uncertainty"] = {"draws": 20}
    config.write_text(yaml.safe_dump(cfg))
    whole = run_retrofit(load_config(config))
    meas = pd.read_csv(tmp_path / "measurements.csv")
    phi = heating_power(meas["V_dot"] / 3.6e6, meas["T_supply"], meas["T_return"]).to_numpy()
    hours = pd.to_datetime(meas[cfg["measurements"].get("time_column", "time")]).dt.hour
    people = 3 * 70.0 * np.asarray(OCCUPANT_PRESENCE)[hours.to_numpy()]
    meas["Q_kW"] = np.maximum(phi - people, 0.0) / 1000.0
    meas.drop(columns=["V_dot", "T_supply", "T_return"]).to_csv(tmp_path / "m.csv", index=False)
    cols = {k: v for k, v in cfg["measurements"]["columns"].items()
            if k not in ("flow", "temp_supply", "temp_return")}  # fmt: skip
    cfg["measurements"].update(
        file=str(tmp_path / "m.csv"), heat_source="heat_meter", heat_unit="kW",
        columns={**cols, "heat": "Q_kW"},
    )  # fmt: skip
    (tmp_path / "without.yaml").write_text(yaml.safe_dump(cfg))
    cfg["internal_gains"] = {"occupants": 3}
    (tmp_path / "with.yaml").write_text(yaml.safe_dump(cfg))
    without = run_retrofit(load_config(tmp_path / "without.yaml"))
    with_people = run_retrofit(load_config(tmp_path / "with.yaml"))
    truth = whole.calibration.heat_loss_coefficient
    assert with_people.calibration.heat_loss_coefficient == pytest.approx(truth, rel=0.02)
    missed = without.calibration.heat_loss_coefficient / truth - 1.0
    found = with_people.calibration.heat_loss_coefficient / truth - 1.0
    assert abs(found) < abs(missed), (missed, found)
    assert with_people.year_gains is not None
    assert with_people.demand.annual_kwh()[0, 0] < whole.demand.annual_kwh()[0, 0]
