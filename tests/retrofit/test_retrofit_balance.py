"""The demand simulation's heat balance per path (``thermocal.retrofit.balance``): it closes
on the controller's heat, and at steady state it is the hand calculation per path."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from retrofit_synthetic import building_dict

from thermocal.io.envelope import EnvelopeDescription
from thermocal.retrofit.balance import BALANCE_PATHS, heat_balance
from thermocal.retrofit.demand import simulate_demand
from thermocal.retrofit.model import build_fifth_order_model

PARAMS = {"H_est": 150.0, "C_env": 4e7, "C_gf": 1e7, "C_im": 2e7, "C_i": 2e6, "C_h": 4e5}


def _model():
    return build_fifth_order_model(EnvelopeDescription.model_validate(building_dict()))


def _year(te, tgr, sun):
    idx = pd.date_range("2001-01-01", periods=24 * 365, freq="h", tz="UTC")
    return pd.DataFrame(
        {"Te": te, "Tgr": tgr, "phi_sol": sun, "phi_abs_roof": 0.5 * sun,
         "phi_abs_walls": 0.3 * sun},
        index=idx,
    )  # fmt: skip


def test_balance_heating_is_the_demand_simulation():
    """A year with weather-like swings, sun and gains: the balance's heating is the demand
    simulation's (same controller, same start), and the paths add up to it."""
    m = _model()
    hours = np.arange(24 * 365)
    te = 8.0 - 10.0 * np.cos(2 * np.pi * hours / 8760) - 4.0 * np.cos(2 * np.pi * hours / 24)
    sun = np.clip(3000.0 * np.sin(2 * np.pi * (hours % 24 - 6) / 24), 0.0, None)
    year = _year(te, 9.0 - 4.0 * np.cos(2 * np.pi * (hours - 900) / 8760), sun)
    gains = np.where(hours % 24 < 8, 200.0, 600.0)
    bal = heat_balance(m, PARAMS, None, year, 20.0, gains=gains)
    res = simulate_demand(m, {k: np.array([v]) for k, v in PARAMS.items()}, [m.envelope],
                          year, 20.0, gains=gains)  # fmt: skip
    np.testing.assert_allclose(bal["heating"].to_numpy(), res.monthly[0, 0], rtol=1e-9)
    paths = bal[list(BALANCE_PATHS)].sum(axis=1)
    np.testing.assert_allclose(paths.to_numpy(), bal["heating"].to_numpy(), rtol=1e-9)
    assert bal["gains"].sum() == pytest.approx(-gains.sum() / 1000.0)
    assert bal["sun"].sum() == pytest.approx(-sun.sum() / 1000.0)
    # the air and the internal mass store little over a month
    assert np.abs(bal["stored"]).max() < 0.02 * np.abs(bal[list(BALANCE_PATHS)]).sum(axis=1).max()


def test_balance_at_steady_state_is_the_hand_calculation():
    """Constant Te = Tgr, no sun, no gains: each path carries its conductance x (Ti - Te)."""
    m = _model()
    year = _year(-2.0, -2.0, 0.0)
    bal = heat_balance(m, PARAMS, None, year, 20.0)
    h = m.conductances()
    hours_jan = 31 * 24
    env = 1.0 / (1.0 / h["H_env_in"] + 1.0 / h["H_env_out"])
    floor = 1.0 / (1.0 / h["H_gf_in"] + 1.0 / (h["H_gf_gr"] + h["H_gf_e"]))
    for path, conductance in (
        ("envelope", env), ("windows", h["H_win"]), ("air_change", PARAMS["H_est"]),
        ("floor", floor),
    ):  # fmt: skip
        assert bal.loc[1, path] == pytest.approx(conductance * 22.0 * hours_jan / 1000, rel=1e-6)
    assert bal.loc[1, "stored"] == pytest.approx(0.0, abs=1e-6)
