"""Likelihood split at long gaps: periods with their own initial states."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.statespace import RCModel
from thermocal.statespace.data import prepare_data
from thermocal.statespace.estimation import simulate_stochastic

TRUTH = {"Ci": 2.0, "Ce": 20.0, "Hie": 300.0, "Hea": 200.0, "si": 0.1, "e": 0.1, "Ti0": 20.0}
UNITS = {"Ci": "MJ/K", "Ce": "MJ/K", "Hie": "W/K", "Hea": "W/K", "si": "K/sqrt(h)", "e": "K"}


def model() -> RCModel:
    m = RCModel("two_state")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.01)
    m.add_state("Te", capacity="Ce", noise=0.0, initial_mean=10.0, initial_std=2.0)
    m.add_conductance("Ti", "Te", conductance="Hie")
    m.add_conductance("Te", "Ta", conductance="Hea")
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    for name, value in TRUTH.items():
        bounds = {"lower": 5.0, "upper": 35.0} if name == "Ti0" else {}
        m.add_parameter(name, value, unit=UNITS.get(name, "C"), **bounds)
    return m


def inputs(n: int, seed: int, start: str = "2024-01-01") -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    hours = np.arange(n)
    return pd.DataFrame(
        {
            "Ta": 5 + 3 * np.sin(hours / 24 * 2 * np.pi) + rng.normal(0, 0.5, n),
            "Ph": 3000.0 * (rng.uniform(size=n) > 0.5),
        },
        index=pd.date_range(start, periods=n, freq="h", tz="UTC"),
    )


def two_periods(gap: int = 20, n: int = 200, ti0_b: float = 26.0):
    """Period A from Ti0 = 20 C, a gap of ``gap`` hours without heating data, period B starting
    at ``ti0_b``: each simulated from its own initial state."""
    a = inputs(n, 1)
    b = inputs(n, 2, start=str(a.index[-1] + pd.Timedelta(hours=gap + 1)))
    a["y"] = simulate_stochastic(model(), a, seed=3)["y"]
    b["y"] = simulate_stochastic(model().with_parameters({"Ti0": ti0_b}), b, seed=4)["y"]
    hole = inputs(gap, 5, start=str(a.index[-1] + pd.Timedelta(hours=1)))
    hole["Ph"] = np.nan
    hole["y"] = np.nan
    return a, b, pd.concat([a, hole, b])


def test_split_likelihood_is_the_sum_of_the_periods():
    a, b, data = two_periods()
    m = model()
    prep = prepare_data(m, data, input_gaps="split")
    assert prep.n_periods == 2 and prep.segments.tolist() == [len(a)]
    assert "split into 2 period(s)" in prep.notes[0] and "20 row(s)" in prep.notes[0]
    split = m.with_periods([{"Ti": 24.0}])
    assert split.parameters["Ti0_p2"].value == 24.0
    params = {**TRUTH, "Hie": 280.0, "Ti0_p2": 25.5}
    expected = m.loglike(a, params) + m.loglike(b, {**params, "Ti0": 25.5})
    assert split.loglike(prep, params) == pytest.approx(expected, rel=1e-12)
    # rows missing altogether (a jump of the time axis) split the same way
    prep_jump = prepare_data(m, pd.concat([a, b]), input_gaps="split")
    assert prep_jump.segments.tolist() == [len(a)]
    assert split.loglike(prep_jump, params) == pytest.approx(expected, rel=1e-12)
    # the deterministic simulation restarts from the period's own initial state
    sim = split.simulate(prep, params)
    assert sim["Ti"].iloc[len(a)] == pytest.approx(25.5)
    # without the split policy the long gap stops with the remedy
    with pytest.raises(ThermocalInputError, match="split the likelihood there"):
        prepare_data(m, data, input_gaps="interpolate")


def test_split_fit_recovers_parameters_and_period_states():
    _, _, data = two_periods(ti0_b=26.0)
    res = model().fit(data, input_gaps="split")
    assert "Ti0_p2" in res.params.index
    assert res.params["Ti0_p2"] == pytest.approx(26.0, abs=0.5)
    for name in ("Hie", "Hea", "Ci"):
        assert abs(res.params[name] - TRUTH[name]) < 3 * res.bse[name] + 0.1 * TRUTH[name], name
    assert any("split into 2 period(s)" in n for n in res.data.notes)
    pred = res.predict(steps=2)
    assert len(pred) == 400 and pred["y"].iloc[200:202].isna().all()
    assert pred["y"].iloc[2:200].notna().all() and pred["y"].iloc[202:].notna().all()
    smooth = res.smooth()
    assert np.isfinite(smooth["Ti"]).all()


def test_rows_missing_from_the_time_axis_are_a_gap_like_empty_cells():
    """The 20-hour gap with its rows deleted instead of left empty: refused naming the rows
    with input_gaps "error" or "interpolate", as the empty cells are, instead of holding the
    inputs across it; two rows missing are bridged and noted (refused with max_gap 1);
    "split" splits there. Jitter of the sampling is no jump."""
    from thermocal.statespace.data import time_axis_jumps

    _, _, data = two_periods(gap=20)
    deleted = data.dropna()
    for mode in ("error", "interpolate"):
        with pytest.raises(
            ThermocalInputError,
            match=r"time axis jumps from .* \(rows 199 and 200\): 20 sample\(s\).*--max-gap",
        ):
            prepare_data(model(), deleted, input_gaps=mode, max_gap=3)
    with pytest.raises(ThermocalInputError, match="missing for 20 consecutive samples"):
        prepare_data(model(), data, input_gaps="interpolate", max_gap=3)
    assert prepare_data(model(), deleted, input_gaps="split").segments.tolist() == [200]
    short = deleted.drop(deleted.index[50:52])
    prep = prepare_data(model(), short.iloc[:150], max_gap=3)
    assert prep.notes == ["time axis: 1 jump(s) of at most 2 missing sample(s) bridged (the "
                          "inputs held over them)"]  # fmt: skip
    with pytest.raises(ThermocalInputError, match=r"rows 49 and 50\): 2 sample\(s\)"):
        prepare_data(model(), short.iloc[:150], input_gaps="interpolate", max_gap=1)
    # a simulation of given inputs (no outputs to fit: FitResult.simulate, predict) holds
    # them over the jump, as before, with the note (review of the fuzzing round's fix)
    held = prepare_data(model(), deleted, require_outputs=False)
    assert held.notes == ["time axis: 1 jump(s) of at most 20 missing sample(s) bridged (the "
                          "inputs held over them)"]  # fmt: skip
    jitter = np.arange(100) * 300.0 + np.random.default_rng(0).uniform(-50, 50, 100)
    assert time_axis_jumps(jitter)[0].size == 0
    assert time_axis_jumps(np.array([0.0, 1, 2, 5, 6]))[1].tolist() == [2]
