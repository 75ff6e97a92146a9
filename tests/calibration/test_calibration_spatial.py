"""The zone-group (spatial) metric: groups, their metric, the series meta-model per group."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.calibration.spatial import group_metric, group_outputs, group_segments, zone_groups
from thermocal.calibration.surrogate import SeriesSurrogate
from thermocal.demos import buildings as generators


def test_zone_groups_of_the_clinic_follow_its_envelope():
    building = generators.clinic(12, n_corridors=1, corridor_sections=2)
    groups = zone_groups(building, list(building.zones))
    # a single-storey building: every zone has a roof and a ground floor; the rooms face a
    # facade (their largest exterior wall), the corridor sections are core or end zones
    assert all(label.startswith("roof and ground, ") for label in groups.values())
    from thermocal.identification.sensors import main_orientation

    for zone, label in groups.items():
        orientation = main_orientation(building, zone)
        assert label.endswith("core" if orientation == "interior" else orientation), zone
    assert len(set(groups.values())) >= 2
    with pytest.raises(Exception, match="not a zone"):
        zone_groups(building, ["Nowhere"])


def test_group_outputs_are_hourly_means_of_the_group_sums():
    index = pd.date_range("2001-01-01", periods=24 * 4, freq="15min", tz="UTC")
    rng = np.random.default_rng(0)
    heat = pd.DataFrame(rng.normal(size=(len(index), 3)), index=index, columns=["a", "b", "c"])
    mask = np.asarray(index.hour < 6)
    groups = {"a": "g1", "b": "g1", "c": "g2"}
    out = group_outputs(heat, mask, groups, ["g1", "g2"])
    assert len(out) == 2 * 6
    first = heat[["a", "b"]].sum(axis=1)[:4].mean()  # hour 0 of group g1
    assert out["group/00/00000"] == pytest.approx(first, rel=1e-12)
    assert out["group/01/00005"] == pytest.approx(heat["c"].iloc[20:24].mean(), rel=1e-12)
    columns, segments = group_segments(list(out) + ["series/00000", "unoccupied_variance"])
    assert segments == [(0, 6), (6, 12)] and columns[0] == "group/00/00000"
    values = np.array([out[c] for c in columns])
    expected = values[:6].var() + values[6:].var()
    assert group_metric(values, segments) == pytest.approx(expected, rel=1e-12)


def test_group_metric_tells_apart_what_the_building_sum_cancels():
    """Two groups whose errors are opposite: the building sum sees nothing, the groups do."""
    t = np.arange(100)
    signal = np.sin(2 * np.pi * t / 24)
    series = np.concatenate([100 + 30 * signal, 200 - 30 * signal])
    segments = [(0, 100), (100, 200)]
    assert np.var(series[:100] + series[100:]) == pytest.approx(0.0, abs=1e-9)
    assert group_metric(series, segments) == pytest.approx(2 * 30**2 * np.var(signal), rel=1e-9)


def test_series_metamodel_with_groups_predicts_the_sum_of_their_variances():
    rng = np.random.default_rng(1)
    n, d, hours = 50, 6, 120
    names = [f"p{i}" for i in range(d)]
    X = pd.DataFrame(np.exp(rng.uniform(-0.5, 0.5, size=(n, d))), columns=names)
    t = np.arange(hours)
    jac = np.zeros((d, 2 * hours))
    jac[0, :hours] = 300 * np.sin(2 * np.pi * t / 24)  # a roof: group 1 only
    jac[1, hours:] = 200 * np.cos(2 * np.pi * t / 24)  # walls: group 2 only
    base = np.r_[np.full(hours, 500.0), np.full(hours, 800.0)]
    segments = [(0, hours), (hours, 2 * hours)]
    series = base + np.log(X.to_numpy()) @ jac + rng.normal(0, 1.0, size=(n, 2 * hours))
    y = group_metric(series, segments)
    model = SeriesSurrogate(
        series=series, nominal=dict.fromkeys(names, 1.0), cv_folds=5, seed=0, segments=segments
    ).fit(X, y)
    assert model.cv_r2_ > 0.99
    new = pd.DataFrame(np.exp(rng.uniform(-0.5, 0.5, size=(10, d))), columns=names)
    truth = group_metric(base + np.log(new.to_numpy()) @ jac, segments)
    np.testing.assert_allclose(model.predict(new), truth, rtol=0.02)
    assert model.within_hour_ == pytest.approx(0.0, abs=1e-6)
    # each group is centred on its own mean (its own unknown constant gain)
    centred = model.centred(base)
    assert centred[:hours] == pytest.approx(0.0) and centred[hours:] == pytest.approx(0.0)


def test_flags_parameters_at_bounds_and_a_metric_below_the_model_error():
    from thermocal.calibration.posterior import calibration_posterior, emulator_variance
    from thermocal.calibration.space import ParameterSpace
    from thermocal.calibration.workflow import calibration_flags

    nominal = {"window/W/u_value": 4.0, "construction/Roof/resistance": 2.0}
    space = ParameterSpace.from_parameters(nominal, default_range=0.5)
    names = list(space.names)
    window, roof_r = "window/W/u_value", "construction/Roof/resistance"
    rng = np.random.default_rng(3)
    n, hours = 40, 150
    X = pd.DataFrame({name: nominal[name] * np.exp(rng.uniform(-0.4, 0.4, n)) for name in names})
    t = np.arange(hours)
    roof = 300 * np.sin(2 * np.pi * t / 24)
    # the truth: roof resistance x1.3; the window U moves nothing the data can see; a fixed
    # pattern no parameter explains is the model's error (e.g. a sensor offset at night)
    model_error = 30.0 * np.sign(np.sin(2 * np.pi * t / 17 + 0.1))
    series = (
        np.log(X[roof_r].to_numpy() / 2.6)[:, None] * roof
        + model_error
        + rng.normal(0, 20.0, size=(n, hours))
    )
    model = SeriesSurrogate(series=series, nominal=nominal, cv_folds=5, seed=0).fit(
        X, series.var(axis=1)
    )
    post = calibration_posterior(
        model,
        names,
        space.lower,
        space.upper,
        steps=600,
        seed=0,
        emulator_error=emulator_variance(model, X, seed=0),
    )
    assert post.determined == [roof_r]
    values = {window: space.upper[space.index(window)], roof_r: 2.6}
    truth = {"parameters": {"construction/Roof/resistance": {"true": 2.6}}}
    flags = calibration_flags(space, values, 1.0, post, model, truth)
    kinds = {f["kind"]: f for f in flags}
    assert kinds["at bound"]["parameter"] == window
    assert "do not determine" in kinds["at bound"]["text"]
    assert "did not perturb" in kinds["at bound"]["text"]
    # 1 W2 is far below the model error the data leave (30 W per hour): flagged
    assert 0.5 * 30.0**2 < kinds["below model error"]["floor"] < 2 * 30.0**2
    # a calibration that ends inside the range and at the noise level is not flagged
    inside = {window: 4.0, roof_r: 2.6}
    assert calibration_flags(space, inside, 2 * 30.0**2, post, model, truth) == []
    # a determined parameter calibrated outside its own 90 % interval is flagged
    q05, q95 = post.summary.loc[roof_r, ["q05", "q95"]]
    outside = {window: 4.0, roof_r: q05 * 0.95}
    (flag,) = calibration_flags(space, outside, 2 * 30.0**2, post, model, truth)
    assert flag["kind"] == "outside interval" and flag["parameter"] == roof_r, flag
    assert flag["q05"] == q05 and "Take the interval as the answer" in flag["text"]


def test_model_error_floor_of_a_group_metric_is_that_of_a_simulated_run():
    """With several zone groups each simulated series holds an error no parameter explains
    (20 W per hour, new in every run); the metric of a run at the truth holds it in every
    group (4 x 20^2 W^2 besides the variance the truth leaves). The floor is what a run would
    give, not the meta-model's prediction, which lacks that error: the truth's run is not
    below it by more than its own spread."""
    from thermocal.calibration.posterior import calibration_posterior, emulator_variance
    from thermocal.calibration.space import ParameterSpace
    from thermocal.calibration.workflow import model_error_floor

    nominal = {"construction/Roof/resistance": 2.0}
    space = ParameterSpace.from_parameters(nominal, default_range=0.5)
    roof_r = "construction/Roof/resistance"
    rng = np.random.default_rng(8)
    n, hours, groups = 40, 120, 4
    X = pd.DataFrame({roof_r: 2.0 * np.exp(rng.uniform(-0.4, 0.4, n))})
    t = np.arange(hours)
    signature = np.concatenate([(g + 1) * 100 * np.sin(2 * np.pi * t / 24) for g in range(groups)])
    segments = [(g * hours, (g + 1) * hours) for g in range(groups)]

    def runs(values):
        z = np.log(np.asarray(values) / 2.6)[:, None]
        return z * signature + rng.normal(0, 20.0, size=(len(values), hours * groups))

    series = runs(X[roof_r].to_numpy())
    model = SeriesSurrogate(series=series, nominal=nominal, cv_folds=5, seed=0, segments=segments)
    model.fit(X, model.series_variance(series))
    post = calibration_posterior(
        model,
        [roof_r],
        space.lower,
        space.upper,
        steps=600,
        seed=0,
        emulator_error=emulator_variance(model, X, seed=0),
    )
    floor = model_error_floor(space, post, model)
    truth_runs = model.series_variance(runs(np.full(200, 2.6)))
    predicted = float(model.predict(pd.DataFrame({roof_r: [2.6]}))[0])
    assert predicted < 0.6 * truth_runs.mean()  # the prediction lacks the runs' own error
    assert np.quantile(truth_runs, 0.05) < floor < np.quantile(truth_runs, 0.95) * 1.2


def test_series_metamodel_box_optima_are_exact():
    """The minimum (bounded least squares) and the maximum (vertices) against brute force."""
    rng = np.random.default_rng(4)
    n, d, hours = 40, 3, 80
    names = ["a", "b", "c"]
    X = pd.DataFrame(np.exp(rng.uniform(-0.5, 0.5, size=(n, d))), columns=names)
    t = np.arange(hours)
    jac = np.vstack(
        [100 * np.sin(2 * np.pi * t / 24), 60 * np.cos(2 * np.pi * t / 24), 30 * (t > 40)]
    )
    series = 50 * np.sin(2 * np.pi * t / 24 + 0.3) + np.log(X.to_numpy()) @ jac
    segments = [(0, 40), (40, 80)]
    model = SeriesSurrogate(
        series=series, nominal=dict.fromkeys(names, 1.0), cv_folds=0, segments=segments
    ).fit(X, group_metric(series, segments))
    lower, upper = np.full(d, np.exp(-0.5)), np.full(d, np.exp(0.5))
    grid = np.exp(np.stack(np.meshgrid(*[np.linspace(-0.5, 0.5, 41)] * d), -1).reshape(-1, d))
    values = model.predict(grid)
    x_min, v_min = model.box_optimum("min", lower, upper)
    x_max, v_max = model.box_optimum("max", lower, upper)
    assert v_min <= values.min() + 1e-9 and v_max >= values.max() - 1e-9
    assert v_min == pytest.approx(model.predict(x_min[None, :])[0], rel=1e-12)
    assert np.all(x_min >= lower - 1e-12) and np.all(x_min <= upper + 1e-12)
