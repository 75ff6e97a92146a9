"""A profile likelihood across a failed refit: two resistances in series (their sum alone is
determined) have a flat profile; a single refit that failed from its warm start fell 170
log-units and ended the interval there (Rea1 in [0.001, 2.53] where fits fixed at 3 and 4
reach the optimum; exploratory test, 2026-11-30). A point that falls by more than the interval's
depth in one step is refitted from the optimum too."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from thermocal.statespace import RCModel
from thermocal.statespace.estimation import simulate_stochastic

TITE = Path(__file__).resolve().parents[2] / "examples" / "models" / "TiTe.yaml"


def _data() -> pd.DataFrame:
    spec = yaml.safe_load(TITE.read_text())
    truth = dict(Ci=2.0, Ce=10.0, Rie=1.0, Rea=5.0, Aw=5.0, sigma_i=0.05, sigma_e=0.02,
                 e_std=0.05, Ti0=20.0, Te0=12.0)  # fmt: skip
    for name, value in truth.items():
        spec["parameters"][name]["value"] = value
    rng = np.random.default_rng(0)
    n = 14 * 96
    t = np.arange(n) * 0.25
    data = pd.DataFrame(
        {
            "t": t,
            "Ta": 3 + 4 * np.sin(2 * np.pi * (t - 9) / 24) + rng.normal(0, 0.3, n),
            "Ps": np.clip(0.5 * np.sin(2 * np.pi * (t % 24 - 6) / 24), 0, None)
            * (0.6 + 0.4 * rng.uniform(size=n)),
            "Ph": 5.0 * (rng.uniform(size=n // 4 + 1) > 0.5).repeat(4)[:n],
        }
    )
    simulated = simulate_stochastic(RCModel.from_dict(spec), data, seed=1, time_column="t",
                                    time_unit="h")  # fmt: skip
    data["yTi"] = simulated["yTi"].round(4).to_numpy()
    return data


def test_profile_of_a_resistance_in_series_reaches_across_its_flat_range():
    data = _data()
    series = yaml.safe_load(TITE.read_text())  # the example's starting values
    rea = series["parameters"].pop("Rea")
    for conductance in series["conductances"]:
        if conductance.get("resistance") == "Rea":
            conductance["resistance"] = ["Rea1", "Rea2"]
    for name in ("Rea1", "Rea2"):
        series["parameters"][name] = {**rea, "value": 2.0}
    fit = RCModel.from_dict(series).fit(data, time_column="t", time_unit="h", n_starts=2)
    total = fit.params["Rea1"] + fit.params["Rea2"]
    assert abs(total - 5.0) < 0.5
    interval = fit.profile_interval("Rea1")
    # flat until Rea2 reaches its bound: the upper end near the sum, not at a failed refit
    assert interval["upper"] > 0.85 * total, interval
    assert interval["open_lower"]


def test_an_ordinary_profile_is_not_refitted_twice(monkeypatch):
    # the same model with one resistance: every profile close to its quadratic approximation;
    # a fall the approximation foresees is no sign of a failed refit (the first rule, a fall of
    # 1.92 from the nearest point, refitted 21 of 159 points a second time, to the same values)
    from thermocal.statespace import profile

    fit = RCModel.from_dict(yaml.safe_load(TITE.read_text())).fit(
        _data(), time_column="t", time_unit="h", n_starts=2
    )
    refits = []
    original = type(fit).refit
    monkeypatch.setattr(type(fit), "refit", lambda self, *a, **k: refits.append(1)
                        or original(self, *a, **k))  # fmt: skip

    def profile_all():
        refits.clear()
        names = ("Ci", "Rie", "Rea", "sigma_i", "Te0")
        return [fit.profile_interval(n) for n in names], len(refits)

    intervals, n_refits = profile_all()
    monkeypatch.setattr(profile, "PROFILE_JUMP", np.inf)
    never_again, n_once = profile_all()
    assert n_refits == n_once
    for got, once in zip(intervals, never_again, strict=True):
        assert got["lower"] == once["lower"] and got["upper"] == once["upper"]
