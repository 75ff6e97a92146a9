"""Bad input gives one clear ThermocalInputError naming the culprit and the remedy."""

from __future__ import annotations

import copy

import numpy as np
import pandas as pd
import pytest
import yaml

from thermocal.errors import ThermocalInputError
from thermocal.statespace import RCModel

SPEC = {
    "name": "TiTe",
    "states": {
        "Ti": {"capacity": "Ci", "noise": "sigma_i", "initial_mean": "Ti0", "initial_std": 0.5},
        "Te": {"capacity": "Ce", "initial_mean": 10.0},
    },
    "conductances": [
        {"between": ["Ti", "Te"], "conductance": "Hie"},
        {"between": ["Te", "Ta"], "resistance": "Rea"},
    ],
    "heat_inputs": [{"column": "Ph", "into": "Ti", "unit": "kW"}],
    "outputs": [{"column": "yTi", "state": "Ti", "noise": "e"}],
    "parameters": {
        "Ci": {"value": 2.0, "lower": 0.1, "upper": 10, "unit": "MJ/K"},
        "Ce": {"value": 20.0, "unit": "MJ/K"},
        "Hie": {"value": 300.0, "unit": "W/K"},
        "Rea": {"value": 5.0, "unit": "K/kW"},
        "sigma_i": {"value": 0.1, "unit": "K/sqrt(h)"},
        "e": {"value": 0.1, "unit": "K"},
        "Ti0": {"value": 20.0, "unit": "C"},
    },
}


def data(n: int = 50) -> pd.DataFrame:
    rng = np.random.default_rng(0)
    t = pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC")
    return pd.DataFrame(
        {
            "Ta": 5.0 + rng.normal(0, 1, n),
            "Ph": rng.uniform(0, 3, n),
            "yTi": 20 + rng.normal(0, 1, n),
        },
        index=t,
    )


def spec(**changes):
    s = copy.deepcopy(SPEC)
    for path, value in changes.items():
        target = s
        keys = path.split("__")
        for k in keys[:-1]:
            target = target[int(k)] if isinstance(target, list) else target[k]
        last = int(keys[-1]) if isinstance(target, list) else keys[-1]
        target[last] = value
    return s


def test_valid_spec_builds_and_matches_yaml_file(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(SPEC, sort_keys=False))
    a, b = RCModel.from_dict(SPEC), RCModel.from_yaml(path)
    assert a.input_names == b.input_names == ["Ta", "Ph"]
    for x, y in zip(a.continuous_matrices(), b.continuous_matrices(), strict=True):
        np.testing.assert_array_equal(x, y)
    # round trip through to_dict
    c = RCModel.from_dict(a.to_dict())
    np.testing.assert_array_equal(c.continuous_matrices()[0], a.continuous_matrices()[0])


def test_model_naming_unknown_column(tmp_path):
    model = RCModel.from_dict(spec(outputs=[{"column": "T_room", "state": "Ti", "noise": "e"}]))
    with pytest.raises(ThermocalInputError, match=r"'T_room' \(output.*not in the data.*yTi"):
        model.fit(data())


def test_state_without_capacity(tmp_path):
    s = spec()
    del s["states"]["Te"]["capacity"]
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(s))
    with pytest.raises(
        ThermocalInputError, match=r"bad.yaml.*state 'Te' has no capacity.*capacity:"
    ):
        RCModel.from_yaml(path)


def test_parameter_outside_its_bounds():
    with pytest.raises(
        ThermocalInputError, match=r"parameter 'Ci'.*30.*outside its bounds.*\[0.1, 10"
    ):
        RCModel.from_dict(spec(parameters__Ci__value=30.0))


@pytest.mark.parametrize("kind", ["duplicated", "decreasing"])
def test_bad_time_stamps(kind):
    df = data()
    idx = df.index.to_list()
    if kind == "duplicated":
        idx[7] = idx[6]
        expected = r"duplicated time stamp .* row 7"
    else:
        idx[7], idx[8] = idx[8], idx[7]
        expected = r"not increasing at row 8.*sort"
    df.index = pd.DatetimeIndex(idx)
    with pytest.raises(ThermocalInputError, match=expected):
        RCModel.from_dict(SPEC).fit(df)


def test_all_nan_output():
    df = data()
    df["yTi"] = np.nan
    with pytest.raises(ThermocalInputError, match=r"output column 'yTi' has no valid value"):
        RCModel.from_dict(SPEC).fit(df)


def test_missing_input_values_name_column_and_row():
    df = data()
    df.iloc[12, df.columns.get_loc("Ta")] = np.nan
    with pytest.raises(ThermocalInputError, match=r"input column 'Ta'.*row 12.*fill the gaps"):
        RCModel.from_dict(SPEC).fit(df)


def test_kelvin_temperatures_are_refused():
    df = data()
    df["Ta"] += 273.15
    with pytest.raises(ThermocalInputError, match=r"'Ta'.*looks like kelvin"):
        RCModel.from_dict(SPEC).fit(df)


def test_undeclared_parameter_reference():
    with pytest.raises(
        ThermocalInputError, match=r"'Rie'.*neither a declared parameter.*parameters:"
    ):
        RCModel.from_dict(spec(conductances__0={"between": ["Ti", "Te"], "resistance": "Rie"}))


def test_parameter_unit_must_fit_its_role():
    with pytest.raises(
        ThermocalInputError, match=r"'Hie' is used as conductance but has unit 'K/W'"
    ):
        RCModel.from_dict(spec(parameters__Hie={"value": 0.003, "unit": "K/W"}))


def test_unknown_unit_and_unknown_key():
    with pytest.raises(ThermocalInputError, match=r"'Ce': unknown unit 'MJ/C'"):
        RCModel.from_dict(spec(parameters__Ce={"value": 20.0, "unit": "MJ/C"}))
    with pytest.raises(ThermocalInputError, match=r"state 'Ti': unknown key\(s\) \['capcity'\]"):
        RCModel.from_dict(spec(states__Ti={"capcity": "Ci", "initial_mean": 20.0}))


def test_heat_into_unknown_state_and_isolated_state():
    with pytest.raises(ThermocalInputError, match=r"goes into 'Tx', which is not a state"):
        RCModel.from_dict(spec(heat_inputs=[{"column": "Ph", "into": "Tx"}]))
    s = spec()
    s["states"]["Tm"] = {"capacity": "Ce", "initial_mean": 20.0}
    with pytest.raises(ThermocalInputError, match=r"state 'Tm' has no conductance"):
        RCModel.from_dict(s)


def test_time_column_numeric_units_and_errors():
    df = data().reset_index(drop=True)
    df["t"] = np.arange(len(df)) * 60.0  # minutes
    model = RCModel.from_dict(SPEC)
    ll_min = model.loglike(df, time_column="t", time_unit="min")
    ll_idx = model.loglike(data())
    assert ll_min == pytest.approx(ll_idx, rel=1e-12)
    with pytest.raises(ThermocalInputError, match=r"unknown time unit 'hours'"):
        model.loglike(df, time_column="t", time_unit="hours")
    with pytest.raises(ThermocalInputError, match=r"no time column 'time'"):
        model.loglike(df, time_column="time")


def test_series_conductance_with_factor_syntax():
    """[He, "2*H"] is the series connection 1/(1/He + 1/(2 H)) (half of a wall layer)."""
    s = spec(conductances__1={"between": ["Te", "Ta"], "conductance": ["Hie", "2*Hea"]})
    s["parameters"]["Hea"] = {"value": 100.0, "unit": "W/K"}
    del s["parameters"]["Rea"]
    A, B, _, _ = RCModel.from_dict(s).continuous_matrices()
    g = 1.0 / (1.0 / 300.0 + 1.0 / 200.0)
    assert B[1, 0] == pytest.approx(g / 20e6, rel=1e-12)
    assert A[1, 1] == pytest.approx(-(300.0 + g) / 20e6, rel=1e-12)
    with pytest.raises(ThermocalInputError, match="factor in '-2\\*Hea' must be positive"):
        s["conductances"][1]["conductance"] = ["Hie", "-2*Hea"]
        RCModel.from_dict(s)


def test_data_without_time_axis_and_garbled_output():
    df = data().reset_index(drop=True)
    with pytest.raises(ThermocalInputError, match=r"no time axis.*time_column"):
        RCModel.from_dict(SPEC).fit(df)
    df = data()
    df["yTi"] = df["yTi"].astype(object)
    df.iloc[5, df.columns.get_loc("yTi")] = "n/a"
    with pytest.raises(ThermocalInputError, match=r"'yTi' has a non-numeric value 'n/a' in row 5"):
        RCModel.from_dict(SPEC).fit(df)


def test_non_iso_dates_are_refused_not_guessed():
    """'01.02.2019' must not silently become 2 January (a guessed month-first format)."""
    df = data(30).reset_index(drop=True)
    df["time"] = [f"{1 + k // 24:02d}.02.2019 {k % 24:02d}:00" for k in range(len(df))]
    with pytest.raises(ThermocalInputError, match=r"'time'.*ISO 8601.*'01.02.2019 00:00'"):
        RCModel.from_dict(SPEC).loglike(df, time_column="time")


def test_local_times_with_dst_offsets_are_read():
    df = data(30)
    local = df.index.tz_convert("Europe/Zurich")
    df2 = df.reset_index(drop=True)
    df2["time"] = [t.isoformat() for t in local]
    df2.loc[10:, "time"] = [
        (t + pd.Timedelta(hours=1)).isoformat().replace("+01:00", "+02:00") for t in local[10:]
    ]  # a fake DST switch: same instants, different offsets
    model = RCModel.from_dict(SPEC)
    assert model.loglike(df2, time_column="time") == pytest.approx(model.loglike(df), rel=1e-12)


@pytest.mark.parametrize(
    ("into", "extra", "message"),
    [
        ({"Ti": 1.5, "Te": "rest"}, {}, r"heat_inputs\[0\].*add up to 1.5 > 1"),
        ({"Ti": 0.7, "Te": 0.6}, {}, r"heat_inputs\[0\].*add up to 1.3 > 1"),
        ({"Ti": -0.2, "Te": "rest"}, {}, r"fraction into 'Ti' is -0.2.*\[0, 1\]"),
        ({"Ti": "f", "Te": "rest"}, {"f": {"value": 0.5, "unit": "-"}},
         r"parameter 'f' is a fraction with bounds \[-inf, inf\].*lower: 0"),
        ({"Ti": "f", "Te": "rest"}, {"f": {"value": 1.2, "unit": "-", "fixed": True}},
         r"parameter 'f' is a fraction and must lie in \[0, 1\]"),
    ],
)  # fmt: skip
def test_heat_fractions_must_split_at_most_the_whole_column(into, extra, message):
    """Fractions outside [0, 1] or adding up to more than 1 create heat out of nothing."""
    s = spec(heat_inputs=[{"column": "Ph", "into": into, "unit": "kW"}])
    s["parameters"].update(extra)
    with pytest.raises(ThermocalInputError, match=message):
        RCModel.from_dict(s)
    # the same split within [0, 1] is accepted and conserves the heat
    s = spec(heat_inputs=[{"column": "Ph", "into": {"Ti": 0.3, "Te": "rest"}, "unit": "kW"}])
    _, B, _, _ = RCModel.from_dict(s).continuous_matrices()
    caps = np.array([2.0e6, 20.0e6])
    assert (B[:, 1] * caps).sum() == pytest.approx(1000.0)  # 1 kW in total [W]


def test_fixed_must_be_a_boolean_and_listed_states_need_names():
    with pytest.raises(ThermocalInputError, match=r"parameter 'Ci': 'fixed' must be true or false"):
        RCModel.from_dict(spec(parameters__Ci__fixed="no"))
    s = spec()
    s["states"] = [{"capacity": "Ci", "noise": "sigma_i", "initial_mean": "Ti0"}]
    with pytest.raises(ThermocalInputError, match=r"states\[0\] needs a 'name'"):
        RCModel.from_dict(s)


def test_non_numeric_parameter_value_names_file_and_parameter(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(spec(parameters__Ci__value="2,5")))
    with pytest.raises(ThermocalInputError, match=r"m.yaml \(model 'TiTe'\).*'Ci' value: '2,5'"):
        RCModel.from_yaml(path)


def test_columns_section_maps_model_names_to_data_columns(tmp_path):
    """A model file's ``columns:`` renames data columns (model name: data name); the same fit
    as renaming the data; absent, clashing or unknown names are refused with both names."""
    df = data(80)
    reference = RCModel.from_dict(SPEC).loglike(df)
    mapped = RCModel.from_dict(spec(columns={"Ph": "heating_kW", "yTi": "T_living"}))
    renamed = df.rename(columns={"Ph": "heating_kW", "yTi": "T_living"})
    assert mapped.loglike(renamed) == pytest.approx(reference, rel=1e-12)
    assert mapped.to_dict()["columns"] == {"Ph": "heating_kW", "yTi": "T_living"}
    with pytest.raises(ThermocalInputError, match="maps 'Ph' to data column 'heating_kW'"):
        mapped.loglike(df.rename(columns={"yTi": "T_living"}).drop(columns="Ph"))
    with pytest.raises(ThermocalInputError, match="has a column 'Ph' as well"):
        mapped.loglike(renamed.assign(Ph=1.0))
    with pytest.raises(ThermocalInputError, match="'Qh' is not a column of the model"):
        RCModel.from_dict(spec(columns={"Qh": "heat"})).loglike(df)
    with pytest.raises(ThermocalInputError, match="both map to data column 'x'"):
        RCModel.from_dict(spec(columns={"Ph": "x", "Ta": "x"}))
    with pytest.raises(ThermocalInputError, match="'columns' must map"):
        RCModel.from_dict(spec(columns=["Ph"]))


def test_model_file_read_safely_and_initial_means_in_kelvin(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_text("name: a\nname: b\n")
    with pytest.raises(ThermocalInputError, match="name"):  # duplicate key, both lines
        RCModel.from_yaml(path)
    path.write_bytes(b"name: \xff\xfe\n")
    with pytest.raises(ThermocalInputError, match="UTF-8"):
        RCModel.from_yaml(path)
    kelvin = spec(parameters__Ti0={"value": 293.15, "unit": "K", "lower": 250, "upper": 320})
    with pytest.raises(ThermocalInputError, match=r"'Ti0' is an initial mean .* write unit: C "
                       r"and value 20 \(= 293.15 K - 273.15\)"):  # fmt: skip
        RCModel.from_dict(kelvin)
    with pytest.raises(ThermocalInputError, match="looks like kelvin"):
        RCModel.from_dict(spec(parameters__Ti0={"value": 293.0, "unit": "C"}))
    with pytest.raises(ThermocalInputError, match="initial_mean of 'Te' = 283.15 looks like"):
        RCModel.from_dict(spec(states__Te={"capacity": "Ce", "initial_mean": 283.15}))


def test_heat_input_in_watts_declared_in_kilowatts_is_flagged():
    """Steady-state energy balance at the declared values: 1.5 kW through H = 120 W/K holds
    Ti near 17.5 C (20 C measured): no flag; the same column written in W but declared kW
    would hold it at ~12,500 C: flagged, naming the column and the unit to use."""
    model = RCModel.from_dict(SPEC)
    clean = model.evaluate(data(80))
    assert not [f for f in clean.flags if "declared in" in f]
    in_watts = data(80).assign(Ph=lambda d: d["Ph"] * 1000.0)
    flags = [f for f in model.evaluate(in_watts).flags if "declared in" in f]
    assert len(flags) == 1
    assert "heat input 'Ph' is declared in kW" in flags[0] and "set 'unit: W'" in flags[0]


def test_likelihood_not_finite_names_the_row_and_column():
    df = data(60)
    df.iloc[30, df.columns.get_loc("Ph")] = 1e306  # finite, but the state overflows
    with pytest.raises(ThermocalInputError, match=r"non-finite at row 3[01] .*'Ph' = 1e\+306"):
        RCModel.from_dict(SPEC).fit(df)
    df = data(60)
    df.iloc[12, df.columns.get_loc("yTi")] = np.inf
    with pytest.raises(ThermocalInputError, match="output column 'yTi' is infinite in row 12"):
        RCModel.from_dict(SPEC).fit(df)


def test_fahrenheit_temperatures_are_refused_naming_column_median_and_celsius():
    """An indoor temperature in F (20 C read as 68) is no heated room's temperature in C:
    refused like kelvin, naming the column, its median and the value in C; the same data in
    C pass. A boundary as hot (a heating circuit's supply water at 55-77 C) may be real: only
    kelvin is refused there."""
    from thermocal.statespace.data import prepare_data

    model, df = RCModel.from_dict(SPEC), data()
    prepare_data(model, df)
    indoor = df.assign(yTi=df["yTi"] * 9 / 5 + 32)
    median = indoor["yTi"].median()
    with pytest.raises(
        ThermocalInputError,
        match=rf"indoor \(output\) temperature column 'yTi' has median {median:.1f}, which "
        rf"looks like Fahrenheit \({(median - 32) * 5 / 9:.1f} C\).*\(F - 32\) x 5/9",
    ):
        prepare_data(model, indoor)
    hot_boundary = df.assign(Ta=(df["Ta"] + 20) * 9 / 5 + 32)
    prepare_data(model, hot_boundary)
    with pytest.raises(ThermocalInputError, match=r"boundary temperature column 'Ta'.*kelvin"):
        prepare_data(model, df.assign(Ta=df["Ta"] + 273.15))


def test_data_without_a_heat_input_of_known_power_are_refused_before_fitting():
    """Heating zero in every row (a free-floating period): every capacity and conductance
    divided by one factor gives the same likelihood, so the heat loss coefficient is not
    identifiable; the fit is refused naming the column. A fixed capacity anchors the scale."""
    from thermocal.statespace.checks import scale_ridge
    from thermocal.statespace.data import prepare_data

    model = RCModel.from_dict(SPEC)
    df = data(80).assign(Ph=0.0)
    k = 3.0
    scaled = {"Ci": 2.0 / k, "Ce": 20.0 / k, "Hie": 300.0 / k, "Rea": 5.0 * k}
    assert model.loglike(df, scaled) == pytest.approx(model.loglike(df), rel=1e-9)
    with pytest.raises(
        ThermocalInputError,
        match=r"no heat input of known power.*'Ph' is zero in every row.*time constants",
    ):
        model.fit(df, n_starts=1)
    assert scale_ridge(model, prepare_data(model, data(80)).U) is None  # heated: identifiable
    fixed = RCModel.from_dict(spec(parameters__Ce={"value": 20.0, "unit": "MJ/K", "fixed": True}))
    assert scale_ridge(fixed, prepare_data(fixed, df).U) is None


def test_fewer_observations_than_free_parameters_are_refused_before_fitting():
    model = RCModel.from_dict(SPEC)
    df = data(40)
    df.loc[df.index[1:], "yTi"] = np.nan
    n = model.n_free
    with pytest.raises(
        ThermocalInputError,
        match=rf"'yTi'.* 1 observed value\(s\) for the {n} free parameters.*at least {n + 1}",
    ):
        model.fit(df, n_starts=1)


def test_heat_loss_coefficient_outside_buildings_names_the_heat_unit():
    """'Ph' in W declared as kW: estimates that fit the data have a heat loss coefficient of
    1.2e5 W/K, flagged with the unit that brings it to 120 W/K. The declared values' energy
    balance cannot tell when the declared values are such estimates (they hold the indoor
    temperature where it is measured)."""
    from thermocal.statespace.results import heat_loss_unit_flags, heat_unit_flags

    model, df = RCModel.from_dict(SPEC), data(80)
    huge = model.evaluate(df.assign(Ph=df["Ph"] * 1000.0), {"Hie": 3.0e5, "Rea": 0.005})
    assert huge.heat_loss_coefficient(profile=False)["value"] == pytest.approx(1.2e5)
    assert not heat_unit_flags(huge.model, huge.data)
    flags = [f for f in huge.flags if "outside the range of buildings" in f]
    assert len(flags) == 1
    assert "heat input 'Ph' is declared in kW: read as W it would be about 120 W/K" in flags[0]
    assert "set 'unit: W'" in flags[0]
    plain = model.evaluate(df)
    assert not heat_loss_unit_flags(model, plain.params.to_dict(), plain.data)


def _solar_spec():
    """SPEC with an irradiance input (W/m2 through an aperture Aw)."""
    s = spec()
    s["heat_inputs"].append({"column": "Ps", "into": "Ti", "unit": "W/m2", "scale": "Aw"})
    s["parameters"]["Aw"] = {"value": 5.0, "unit": "m2"}
    return s


def test_times_in_the_wrong_unit_are_flagged_by_the_daily_cycle_of_the_sun():
    """Six days of 5-minute data, times in hours: the irradiance repeats every 24 h. Read in
    minutes (a span of 144 min) it shows no daily cycle, read in hours it does: the flag names
    the unit; read in hours, no flag."""
    from thermocal.statespace.results import daily_cycle

    rng = np.random.default_rng(1)
    n = 6 * 288
    hours = np.arange(n) / 12.0
    sun = np.clip(np.sin(2 * np.pi * (hours % 24 - 6) / 24), 0, None)
    df = pd.DataFrame({
        "t": hours, "Ta": 3 + 2 * np.sin(2 * np.pi * hours / 24) + rng.normal(0, 0.2, n),
        "Ph": rng.uniform(0, 3, n), "Ps": 600 * sun * rng.uniform(0.3, 1.0, n),
        "yTi": 20 + rng.normal(0, 0.3, n),
    })  # fmt: skip
    model = RCModel.from_dict(_solar_spec())
    in_minutes = model.evaluate(df, time_column="t", time_unit="min")
    flags = [f for f in in_minutes.flags if "daily cycle" in f]
    assert len(flags) == 1
    assert "irradiance 'Ps'" in flags[0] and "--time-unit h" in flags[0]
    assert "60 times too small" in flags[0]
    in_hours = model.evaluate(df, time_column="t", time_unit="h")
    assert not [f for f in in_hours.flags if "daily cycle" in f]
    assert daily_cycle(df["Ps"].to_numpy(), 300.0)
    assert not daily_cycle(np.cumsum(rng.normal(size=n)), 300.0)  # a random walk: no cycle


def test_a_hot_output_of_another_state_is_no_fahrenheit():
    """A radiator's temperature observed beside the room's (review of the fuzzing round's
    fix): its median of 55 C is real; only the room's output is checked for Fahrenheit."""
    from pathlib import Path

    from thermocal.statespace.data import indoor_outputs, prepare_data

    models = Path(__file__).resolve().parents[2] / "examples" / "models"
    spec = yaml.safe_load((models / "TiTh.yaml").read_text())
    spec["outputs"].append({"column": "yTh", "state": "Th", "noise": "e_std"})
    model = RCModel.from_dict(spec)
    assert indoor_outputs(model) == {"yTi"}
    n = 60
    df = pd.DataFrame({"Ta": np.full(n, 2.0), "Ph": np.full(n, 1.0), "Ps": np.full(n, 0.1),
                       "yTi": np.full(n, 20.0), "yTh": np.full(n, 55.0)},
                      index=np.arange(n) * 3600.0)  # fmt: skip
    df.index.name = "t"
    prepare_data(model, df)
    with pytest.raises(ThermocalInputError, match=r"'yTi' has median 68\.0.*Fahrenheit"):
        prepare_data(model, df.assign(yTi=68.0))
