"""``thermocal select``: the generated Bacher & Madsen family and forward selection end to end."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from thermocal.cli import app
from thermocal.statespace import RCModel
from thermocal.statespace.estimation import simulate_stochastic
from thermocal.statespace.families import BACHER_MADSEN_EXTENSIONS, bacher_madsen_family

REPO = Path(__file__).resolve().parents[2]


def test_generated_family_equals_the_example_model_files():
    """Same states, paths, inputs, parameters (order, values, bounds): the same fits."""
    models, extensions, start = bacher_madsen_family()
    assert start == "Ti" and extensions == BACHER_MADSEN_EXTENSIONS
    for name, model in models.items():
        example = RCModel.from_yaml(REPO / "examples" / "models" / f"{name}.yaml").to_dict()
        generated = model.to_dict()
        for key in ("states", "conductances", "heat_inputs", "outputs", "parameters"):
            assert generated[key] == example[key], (name, key)
        assert list(generated["parameters"]) == list(example["parameters"]), name
    without_sun, _, _ = bacher_madsen_family(heat_unit="W", solar_unit=None)
    assert without_sun["TiTh"].input_names == ["Ta", "Ph"]
    assert "Aw" not in without_sun["TiTh"].parameters


def test_select_command_runs_forward_selection_with_mapped_columns(tmp_path):
    """Data from the TiTh member (heater state): the selection accepts TiTh over Ti, never
    reports an extension below its parent (warm starts), writes every fit."""
    models, _, _ = bacher_madsen_family(heat_unit="W", solar_unit=None)
    truth = models["TiTh"].with_parameters(
        {
            "Ci": 0.8,
            "Ch": 0.3,
            "Rih": 2.0,
            "Ria": 8.0,
            "sigma_i": 0.05,
            "sigma_h": 0.2,
            "e_std": 0.02,
            "Ti0": 20.0,
            "Th0": 30.0,
        }  # fmt: skip
    )
    rng = np.random.default_rng(1)
    n = 300
    hours = np.arange(n) / 4.0  # 15-minute samples
    df = pd.DataFrame(
        {"Ta": 3 + 4 * np.sin(hours / 24 * 2 * np.pi), "Ph": 2000.0 * (rng.uniform(size=n) > 0.5)},
        index=pd.date_range("2024-01-01", periods=n, freq="15min", tz="UTC"),
    )
    df["yTi"] = simulate_stochastic(truth, df, seed=2)["yTi"]
    table = df.rename(columns={"Ta": "T_out", "Ph": "heat_W", "yTi": "T_living"})
    table.index.name = "time"
    path = tmp_path / "house.csv"
    table.to_csv(path)
    out = tmp_path / "sel"
    args = ["select", str(path), "--out", str(out), "--map", "Ta=T_out", "--map", "Ph=heat_W"]
    args += ["--map", "yTi=T_living", "--heat-unit", "W", "--n-starts", "2", "--seed", "0"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    content = json.loads((out / "selection.json").read_text())
    assert content["path"][:2] == ["Ti", "TiTh"]
    rows = pd.DataFrame(content["table"])
    loglike = dict(zip(rows["model"], rows["loglike"], strict=False))
    for _, row in rows.iterrows():
        if row["parent"]:
            assert row["loglike"] >= loglike[row["parent"]] - 0.05, row["model"]
            assert row["statistic"] >= -0.1
    assert "| 1 | TiTh | Ti |" in (out / "selection.md").read_text()
    for name in rows["model"]:
        fit = json.loads((out / name / "fit.json").read_text())
        assert fit["loglike"] == pytest.approx(loglike[name])
        assert (out / name / "model.yaml").exists()
    assert "no solar column Ps" in " ".join(content["data_notes"])
    # a missing column is named with the --map remedy
    bad = CliRunner().invoke(app, ["select", str(path), "--out", str(tmp_path / "x")])
    assert bad.exit_code != 0 and "--map Ta=" in str(bad.exception)
