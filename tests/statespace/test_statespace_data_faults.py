"""Faults of the data a plausible user makes and the fit must name (fuzzing round 5): an outdoor
temperature in Fahrenheit, an irradiance 1000 times too small for its unit, a logger's
missing-value codes in the output, times that are neither numeric nor ISO 8601, and other data
given to the results without the fit's time unit."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.statespace import RCModel, time_axis
from thermocal.statespace.estimation import simulate_stochastic

REPO = Path(__file__).resolve().parents[2]

SPEC = {
    "name": "TiTe",
    "states": {
        "Ti": {"capacity": "Ci", "noise": "si", "initial_mean": "Ti0", "initial_std": 0.2},
        "Te": {"capacity": "Ce", "noise": "se", "initial_mean": "Te0", "initial_std": 1.0},
    },
    "conductances": [
        {"between": ["Ti", "Te"], "conductance": "Hie"},
        {"between": ["Te", "Ta"], "conductance": "Hea"},
    ],
    "heat_inputs": [
        {"column": "Ph", "into": "Ti", "unit": "W"},
        {"column": "Ps", "into": "Ti", "unit": "W/m2", "scale": "Aw"},
    ],
    "outputs": [{"column": "y", "state": "Ti", "noise": "e"}],
    "parameters": {
        "Ci": {"value": 1.0, "unit": "MJ/K"},
        "Ce": {"value": 20.0, "unit": "MJ/K"},
        "Hie": {"value": 300.0, "unit": "W/K"},
        "Hea": {"value": 120.0, "unit": "W/K"},
        "Aw": {"value": 2.0, "unit": "m2"},
        "si": {"value": 0.05, "unit": "K/sqrt(h)"},
        "se": {"value": 0.05, "unit": "K/sqrt(h)"},
        "e": {"value": 0.02, "unit": "K"},
        "Ti0": {"value": 20.0, "unit": "C"},
        "Te0": {"value": 12.0, "unit": "C"},
    },
}


def house(days: float = 3.0, step_h: float = 0.5) -> pd.DataFrame:
    """A heated house (about 85 W/K) with sun: numeric times ``t`` in hours."""
    n = int(days * 24 / step_h)
    hours = np.arange(n) * step_h
    rng = np.random.default_rng(5)
    df = pd.DataFrame({
        "t": hours, "Ta": 3 + 2 * np.sin(2 * np.pi * hours / 24),
        "Ph": 600.0 + 1800.0 * (rng.uniform(size=n) > 0.5),
        "Ps": 500.0 * np.clip(np.sin(2 * np.pi * (hours % 24 - 6) / 24), 0, None),
    })  # fmt: skip
    df.index = pd.Index(hours * 3600.0)
    df["y"] = simulate_stochastic(RCModel.from_dict(SPEC), df, seed=1)["y"].to_numpy()
    return df.reset_index(drop=True)


def flags_of(df: pd.DataFrame, words: str) -> list[str]:
    """The flags of the model evaluated at its declared values on ``df`` that contain
    ``words``."""
    res = RCModel.from_dict(SPEC).evaluate(df, time_column="t", time_unit="h")
    return [f for f in res.flags if words in f]


def test_outdoor_temperature_in_fahrenheit_is_flagged_with_the_conversion():
    """F-S1 (fuzz5 f26): the outdoor air logged in Fahrenheit (34.7 'C' against 20 C indoors,
    the heating on). Before: 9.8 W/K for 236 and a misleading 'depends on the period' flag,
    nothing on the balance. The flag names both means and Ta read as Fahrenheit; plain data
    and the indoor temperature's own missing codes (below) do not raise it."""
    df = house()
    words = "while heat input 'Ph' averages"
    assert not flags_of(df, words)
    fahrenheit = df.assign(Ta=df["Ta"] * 9 / 5 + 32)
    (flag,) = flags_of(fahrenheit, words)
    assert "'Ta'" in flag and "Fahrenheit?" in flag and "(F - 32) x 5/9" in flag
    mean_f = fahrenheit["Ta"].mean()
    assert f"'Ta' {mean_f:.1f} F = {(mean_f - 32) * 5 / 9:.1f} C" in flag
    # the first flag after the verdict's: the data's faults come before the estimates'
    res = RCModel.from_dict(SPEC).evaluate(fahrenheit, time_column="t", time_unit="h")
    assert words in res.flags[0]


def test_select_refuses_a_room_heated_while_colder_than_the_outdoor_air():
    """F-S1 (fuzz5 s16): `select` scaled the family to such data silently (scale 1) and
    reported 'heat loss coefficient 1 W/K, Wald nan to nan' with exit 0. The family's only
    boundary is the outdoor air: refused, naming Fahrenheit and --bounds family."""
    from thermocal.statespace.families import family_scale

    n = 48
    df = pd.DataFrame({"Ta": np.full(n, 34.7), "yTi": np.full(n, 18.0), "Ph": np.full(n, 2.85)})
    with pytest.raises(ThermocalInputError, match=r"Fahrenheit\? \('Ta' 34\.7 F = 1\.5 C") as e:
        family_scale(df, "kW", source="hourly_ta_F.csv")
    assert "hourly_ta_F.csv" in str(e.value) and "--bounds family" in str(e.value)
    # a summer period without heating, or indoors warmer: no refusal
    assert family_scale(df.assign(Ph=0.0), "kW")[0] == 1.0
    assert family_scale(df.assign(Ta=1.5), "kW")[0] == 1.0


def test_irradiance_too_dim_for_its_declared_unit_is_flagged():
    """F-S2 (fuzz5 s04): irradiance in kW/m2 declared W/m2 (peak 0.5 'W/m2' over three days);
    the free aperture absorbs the factor and no unit check spoke. Flagged with the unit that
    gives a physical peak; not over less than two days, nor in the right unit."""
    df = house()
    dim = df.assign(Ps=df["Ps"] / 1000.0)
    (flag,) = flags_of(dim, "never exceeds")
    assert "irradiance 'Ps' never exceeds 0.5 W/m2 over 2.98 days" in flag
    assert "set 'unit: kW/m2'" in flag and "--solar-unit kW/m2" in flag
    assert not flags_of(df, "never exceeds")
    assert not flags_of(dim.iloc[:80], "never exceeds")  # 1.6 days: a dull spell


def test_dim_irradiance_is_one_check_that_leaves_out_the_polar_night():
    """Review of fuzz5 F-S2 (item 7): fit's flag and the retrofit workflow's refusal of an
    irradiance too dim for W/m2 were two copies (fit flagged a polar night, retrofit refused
    it). One helper now: a maximum below 5 W/m2 over two days or more; with the site's
    latitude, days whose noon sun stays below 10 deg do not count (Tromso in December and at
    the winter solstice; not in June, nor Munich in December)."""
    from thermocal.statespace.units import daylight_rows, dim_irradiance

    hours = np.arange(3 * 24) / 24.0
    assert dim_irradiance(np.full(hours.size, 0.8), hours) == (0.8, pytest.approx(71 / 24))
    assert dim_irradiance(np.full(hours.size, 300.0), hours) is None
    assert dim_irradiance(np.full(40, 0.8), hours[:40]) is None  # 1.6 days: a dull spell
    assert dim_irradiance(np.full(hours.size, np.nan), hours) is None  # no values, no unit
    two = np.column_stack([np.full(hours.size, 0.8), np.full(hours.size, 1.2)])
    assert dim_irradiance(two, hours)[0] == 1.2  # several columns: the larger
    days = pd.to_datetime(["2023-12-01", "2023-12-21", "2023-06-21"]).tz_localize("UTC")
    assert daylight_rows(days, 69.65).tolist() == [False, False, True]
    assert daylight_rows(days, 48.14).tolist() == [True, True, True]
    dark = daylight_rows(pd.date_range("2023-12-01", periods=hours.size, freq="1h"), 69.65)
    assert dim_irradiance(np.full(hours.size, 0.8), hours, dark) is None


def test_missing_value_codes_in_the_output_are_flagged_by_row():
    """F-S3 (fuzz5 f35, f36): -9999 and 999 in the output, which the physical range check of
    the boundary temperatures did not cover (before: 2,385 W/K and only 'residuals beyond 5
    sigma'). The flag lists the rows with their values and times and says NaN; the codes do
    not make the room look colder than its surroundings."""
    df = house()
    coded = df.copy()
    coded.loc[[40, 41, 42], "y"] = -9999.0
    coded.loc[90, "y"] = 999.0
    (flag,) = flags_of(coded, "outside the physical range [-90, 150] C")
    assert flag.startswith("output 'y' (temperature [C]) has 4 value(s)")
    assert "-9999 in row 40 (t = 20 h)" in flag and "999 in row 90 (t = 45 h)" in flag
    assert "set those values to NaN" in flag
    assert not flags_of(coded, "while heat input")
    assert not flags_of(df, "outside the physical range")


@pytest.mark.parametrize(
    ("times", "remedy"),
    [
        (lambda t: t.strftime("%d/%m/%Y %H:%M"), "--time-format '%d/%m/%Y %H:%M'"),
        (lambda t: t.strftime("%d.%m.%Y %H:%M"), "--time-format '%d.%m.%Y %H:%M'"),
        (lambda t: t.strftime("%m/%d/%Y %H:%M"), "--time-format '%m/%d/%Y %H:%M'"),
        (lambda t: [f"{h:.4f}".replace(".", ",") for h in np.arange(len(t)) / 12],
         "--decimal ','"),
        (lambda t: [f"{h:.4f}" if h else "0" for h in np.arange(len(t)) / 12],
         "leave out --decimal ','"),
    ],
)  # fmt: skip
def test_unreadable_times_name_the_option_that_reads_them(times, remedy):
    """U3 (fuzz5 f08, f09, f28, f30): day-first dates (ambiguous days decided by the order that
    reads a regular axis), month-first dates (a second field above 12), decimal commas, and
    numbers stored as text (a dot file read with --decimal ','). Before: only 'write the times
    as ISO 8601 or give numeric times', none of the options that read them."""
    stamps = pd.date_range("2009-02-05 14:26", periods=400, freq="5min")
    df = pd.DataFrame({"t": times(stamps), "x": 1.0})
    with pytest.raises(ThermocalInputError, match="neither numeric nor ISO 8601") as e:
        time_axis(df, time_column="t", source="log.csv")
    assert remedy in str(e.value)


def test_other_data_are_read_with_the_fits_time_column_and_unit():
    """A-S1 and D2 (fuzz5 a02, a03): a fit on times in hours, then `smooth` and `simulate` of
    another period as docs/model-file.md writes them (no time arguments), or naming the time
    column alone. Before: 'no time axis', or 0.083-second steps simulated without a word (RMSE
    6.9 K). Now the fit's column and unit; a unit that makes the axis implausible is refused."""
    df = house(days=4.0)
    fit_data, other = df.iloc[:120], df.iloc[120:]
    res = RCModel.from_dict(SPEC).fit(fit_data, time_column="t", time_unit="h", n_starts=1)
    explicit = res.smooth(other, time_column="t", time_unit="h")
    pd.testing.assert_frame_equal(res.smooth(other), explicit)
    start = {s: explicit[s].iloc[0] for s in res.model.state_names}
    simulated = res.simulate(other, time_column="t", initial_state=start)
    pd.testing.assert_frame_equal(
        simulated, res.simulate(other, time_column="t", time_unit="h", initial_state=start)
    )
    assert float(np.sqrt(np.mean((simulated["y"] - other["y"].to_numpy()) ** 2))) < 1.0
    with pytest.raises(ThermocalInputError, match=r"interval of 't' is 0\.5 s when read with"):
        res.simulate(other, time_column="t", time_unit="s")  # hours read as seconds
    with pytest.raises(ThermocalInputError, match=r"0\.5 s when read with .*time_unit='h'"):
        RCModel.from_dict(SPEC).loglike(df, time_column="t")  # hours read as seconds


def test_time_stamp_check_reads_the_data_like_the_fit():
    """D2 (fuzz5 a04): `time_stamp_check(results, data)` as documented, on data with numeric
    times in hours. Before: 'no time axis' unless the time arguments were repeated."""
    from thermocal.statespace.checks import time_stamp_check

    df = house(days=2.0)
    res = RCModel.from_dict(SPEC).fit(df, time_column="t", time_unit="h", n_starts=1)
    check = time_stamp_check(res, df)
    assert check == time_stamp_check(res, df, time_column="t", time_unit="h")
    assert check["suggested"] == "start" and check["supported"]


def test_documented_per_period_example_runs_as_written():
    """D2: the Python block of docs/model-file.md's *Heat loss coefficient per period*, run as
    written on data with numeric times ``t`` in hours (before, the docs gave
    `split_halves(data)` and `heat_loss_regime_check(model, {label: data})`, which stop with
    'no time axis' on such data)."""
    text = (REPO / "docs" / "model-file.md").read_text()
    section = text[text.index("## Heat loss coefficient per period"):]
    block = re.search(r"```python\n(.*?)```", section, flags=re.S).group(1)
    spec = {**SPEC, "heat_inputs": SPEC["heat_inputs"][:1]}
    spec["parameters"] = {k: v for k, v in SPEC["parameters"].items() if k != "Aw"}
    namespace = {"data": house(days=4.0), "model": RCModel.from_dict(spec)}
    exec(block, namespace)  # noqa: S102 - the documented example itself
    check = namespace["check"]
    assert check["comparable"] and check["agree"] and check["message"] is None
    assert list(namespace["periods"]) == ["until 70.0", "from 70.0"]
