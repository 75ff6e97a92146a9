"""Checks of the data against the fit's assumptions: the time-stamp convention (a one-step lag
of the inputs) and a heat loss coefficient that depends on the period's regime."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.statespace import RCModel
from thermocal.statespace.checks import heat_loss_regime_check, time_stamp_check
from thermocal.statespace.estimation import simulate_stochastic


def two_state() -> RCModel:
    m = RCModel("TiTe")
    m.add_state("Ti", capacity="Ci", noise="si", initial_mean="Ti0", initial_std=0.2)
    m.add_state("Te", capacity="Ce", noise="se", initial_mean="Te0", initial_std=1.0)
    m.add_conductance("Ti", "Te", conductance="Hie")
    m.add_conductance("Te", "Ta", conductance="Hea")
    m.add_heat_input("Ph", into="Ti")
    m.add_output("y", state="Ti", noise="e")
    for name, value, unit in [("Ci", 1.0, "MJ/K"), ("Ce", 20.0, "MJ/K"), ("Hie", 300.0, "W/K"),
                              ("Hea", 120.0, "W/K"), ("si", 0.05, "K/sqrt(h)"),
                              ("se", 0.05, "K/sqrt(h)"), ("e", 0.02, "K"), ("Ti0", 20.0, "C"),
                              ("Te0", 12.0, "C")]:  # fmt: skip
        m.add_parameter(name, value, unit=unit)
    return m


def prbs_data(model, n: int = 400, seed: int = 2) -> pd.DataFrame:
    """10-minute samples, heating switched at random every 30 minutes (time constant of the
    interior ~ 0.6 h, so a one-step lag is visible)."""
    rng = np.random.default_rng(seed)
    on = np.repeat(rng.uniform(size=n // 3 + 1) > 0.5, 3)[:n]
    df = pd.DataFrame(
        {"Ta": 4 + 2 * np.sin(np.arange(n) / 144 * 2 * np.pi), "Ph": 500.0 + 2500.0 * on},
        index=pd.date_range("2024-01-01", periods=n, freq="10min", tz="UTC"),
    )
    df["y"] = simulate_stochastic(model, df, seed=seed)["y"]
    return df


def test_time_stamp_check_finds_a_one_step_lag():
    """The same experiment as a logger stamping each mean at the END of its interval (inputs
    one row later): the check suggests --time-stamps end; on the data as simulated (inputs
    from each stamp to the next) it suggests nothing. Before, nothing warned."""
    model = two_state()
    df = prbs_data(model)
    end_stamped = df.copy()
    end_stamped[["Ta", "Ph"]] = df[["Ta", "Ph"]].shift(1)
    end_stamped = end_stamped.iloc[1:]

    on_grid = model.fit(df, n_starts=2)
    right = time_stamp_check(on_grid, df)
    assert right["suggested"] in (None, "start") and right["message"] is None
    assert right["loglike_start"] > right["loglike_end"]

    as_logged = model.fit(end_stamped, n_starts=2)
    lagged = time_stamp_check(as_logged, end_stamped)
    assert lagged["suggested"] == "end"
    assert lagged["difference"] > 3.0
    assert "--time-stamps end" in lagged["message"]
    # refitted as suggested, the heat loss coefficient is that of the data on the hold's grid
    # (the lagged fit's is far off: measured 40 W/K against 88)
    from thermocal.statespace.data import end_stamped_inputs

    fixed = model.fit(end_stamped_inputs(end_stamped, ["Ta", "Ph"]), n_starts=2)
    reference = on_grid.heat_loss_coefficient(profile=False)["value"]
    assert fixed.heat_loss_coefficient(profile=False)["value"] == pytest.approx(reference, rel=0.01)
    assert (
        abs(as_logged.heat_loss_coefficient(profile=False)["value"] - reference) > 0.1 * reference
    )


def test_fit_command_says_which_time_stamps_to_use(tmp_path):
    """`thermocal fit` on end-stamped data: fit.json holds the check and a flag naming
    --time-stamps end; with --time-stamps end the check is quiet."""
    import json

    import yaml
    from typer.testing import CliRunner

    from thermocal.cli import app

    model = two_state()
    df = prbs_data(model, n=300)
    logged = df.copy()
    logged[["Ta", "Ph"]] = df[["Ta", "Ph"]].shift(1)
    logged = logged.iloc[1:]
    logged.index.name = "time"
    logged.to_csv(tmp_path / "logged.csv")
    (tmp_path / "m.yaml").write_text(yaml.safe_dump(model.to_dict(), sort_keys=False))
    base = ["fit", str(tmp_path / "m.yaml"), str(tmp_path / "logged.csv"), "--no-hlc",
            "--no-figures", "--n-starts", "2"]  # fmt: skip
    ran = CliRunner().invoke(app, [*base, "--out", str(tmp_path / "a")])
    assert ran.exit_code == 0, ran.output
    content = json.loads((tmp_path / "a" / "fit.json").read_text())
    assert content["time_stamp_check"]["suggested"] == "end"
    assert "--time-stamps end" in content["flags"][0]
    ran = CliRunner().invoke(app, [*base, "--out", str(tmp_path / "b"), "--time-stamps", "end"])
    assert ran.exit_code == 0, ran.output
    content = json.loads((tmp_path / "b" / "fit.json").read_text())
    assert content["time_stamp_check"]["message"] is None
    assert content["time_stamp_check"]["suggested"] in (None, "end")
