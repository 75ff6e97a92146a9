"""Retrofit input checks of issue 13: a flow-unit slip is refused, not turned into savings."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import yaml
from retrofit_synthetic import make_dataset

from thermocal.errors import ThermocalInputError
from thermocal.retrofit import load_config, run_retrofit
from thermocal.retrofit.calibration import OUTPUT_COLUMN, check_heating_power_magnitude


def _training(power: float, n: int = 240) -> pd.DataFrame:
    index = pd.date_range("2024-02-01", periods=n, freq="h", tz="UTC")
    return pd.DataFrame(
        {"Te": np.full(n, 2.0), OUTPUT_COLUMN: np.full(n, 20.0), "phi_h": np.full(n, power)},
        index=index,
    )


@pytest.mark.parametrize("factor", [1.0, 0.3, 3.0])
def test_plausible_heating_power_passes(factor):
    ratio = check_heating_power_magnitude(_training(factor * 400 * 18), 400.0)
    assert ratio == pytest.approx(factor)


@pytest.mark.parametrize(
    ("factor", "direction"), [(1e-3, "small"), (1 / 60, "small"), (60.0, "large"), (1e3, "large")]
)
def test_flow_unit_slip_is_refused_naming_the_setting(factor, direction):
    with pytest.raises(ThermocalInputError) as info:
        check_heating_power_magnitude(
            _training(0.7 * 400 * 18 * factor), 400.0, "meas.csv", flow_unit="l/h",
            flow_column="V_dot",
        )  # fmt: skip
    message = str(info.value)
    assert message.startswith("meas.csv: the measured heating power averages")
    assert f"far too {direction}" in message
    assert "measurements.flow_unit (now l/h" in message and "'V_dot'" in message


def test_mild_weather_is_not_judged():
    frame = _training(10.0)
    frame["Te"] = 18.5  # 1.5 K: the balance says nothing
    assert np.isnan(check_heating_power_magnitude(frame, 400.0))


def test_retrofit_with_flow_in_m3_per_hour_declared_as_l_per_hour(tmp_path):
    """The synthetic house: flow logged in m3/h while the configuration says l/h."""
    config = make_dataset(tmp_path, days=22.0)
    cfg = yaml.safe_load(config.read_text())
    measurements = tmp_path / cfg["measurements"]["file"]
    frame = pd.read_csv(measurements)
    column = cfg["measurements"]["columns"]["flow"]
    unit = cfg["measurements"].get("flow_unit", "m3/s")
    to_m3h = {"m3/s": 3600.0, "m3/h": 1.0, "l/s": 3.6, "l/min": 0.06, "l/h": 1e-3}[unit]
    frame[column] = frame[column] * to_m3h
    frame.to_csv(measurements, index=False)
    cfg["measurements"]["flow_unit"] = "l/h"
    config.write_text(yaml.safe_dump(cfg))
    with pytest.raises(ThermocalInputError, match=r"far too small.*flow_unit \(now l/h"):
        run_retrofit(load_config(config))


def test_missing_irradiance_is_not_zero_sun(tmp_path):
    """Two days of missing DNI in the training period: refused, not read as two dark days."""
    config = make_dataset(tmp_path, days=22.0)
    cfg = yaml.safe_load(config.read_text())
    measurements = tmp_path / cfg["measurements"]["file"]
    frame = pd.read_csv(measurements)
    column = cfg["measurements"]["columns"]["dni"]
    frame.loc[100:147, column] = np.nan
    frame.to_csv(measurements, index=False)
    with pytest.raises(ThermocalInputError, match=r"'phi_sol' has \d+ missing values in the "
                       r"training period \(from missing irradiance dni/dhi"):  # fmt: skip
        run_retrofit(load_config(config))


def test_irradiance_a_thousand_times_too_large_is_refused(tmp_path):
    """DNI/DHI written x1000: refused naming the column, not 40 % of the hours dropped."""
    config = make_dataset(tmp_path, days=16.0)  # training at least 7 days (issue 27)
    cfg = yaml.safe_load(config.read_text())
    measurements = tmp_path / cfg["measurements"]["file"]
    frame = pd.read_csv(measurements)
    column = cfg["measurements"]["columns"]["dni"]
    frame[column] = frame[column] * 1000.0
    frame.to_csv(measurements, index=False)
    with pytest.raises(ThermocalInputError, match=rf"'{column}' exceeds 1600 W/m2 in \d+ of \d+ "
                       r"sunny rows .* not in W/m2"):  # fmt: skip
        run_retrofit(load_config(config))


def test_an_impossible_irradiance_glitch_is_removed_aloud(caplog):
    """Two glitches of 5000 W/m2: removed, and said in a note (report, stderr), not only in
    the quality table of results.json."""
    from thermocal.retrofit.data import prepare_measurements, removed_values_notes

    index = pd.date_range("2001-02-01", periods=48, freq="h", tz="UTC")
    raw = pd.DataFrame(
        {"temp_out": 0.0, "flow": 1e-4, "temp_supply": 50.0, "temp_return": 40.0,
         "dni": 300.0, "dhi": 100.0, "temp_in": 20.0},
        index=index,
    )  # fmt: skip
    raw.iloc[[10, 30], raw.columns.get_loc("dni")] = 5000.0
    grid, report = prepare_measurements(raw, "1h")
    assert np.isnan(grid["dni"].iloc[10]) and grid["dni"].iloc[11] == 300.0
    notes = removed_values_notes(report, {"dni": "DNI", "flow": "V_dot"})
    assert len(notes) == 1
    assert "2 physically impossible value(s) of column 'DNI' removed" in notes[0]
    assert "5000" in notes[0]


def test_configuration_messages_echo_the_bad_value():
    from thermocal.retrofit.config import parse_config

    data = {
        "building": "b.yaml",
        "measurements": {"file": "m.csv", "flow_unit": "gal"},
        "weather": {"file": "w.epw"},
        "periods": {"training_days": "three weeks"},
    }
    with pytest.raises(ThermocalInputError) as info:
        parse_config(data, source="cfg.yaml")
    message = str(info.value)
    assert "measurements.flow_unit = 'gal': " in message and "'l/h'" in message
    assert "periods.training_days = 'three weeks': " in message
