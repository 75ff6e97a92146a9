"""``thermocal fit`` end to end on a small synthetic data set, and its input errors."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
from typer.testing import CliRunner

from thermocal.cli import app
from thermocal.statespace import RCModel
from thermocal.statespace.estimation import simulate_stochastic

REPO = Path(__file__).resolve().parents[2]
MODEL = REPO / "examples" / "models" / "two_state_envelope.yaml"


def write_data(path: Path, n: int = 240) -> pd.DataFrame:
    model = RCModel.from_yaml(MODEL)
    rng = np.random.default_rng(0)
    t = pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC")
    hours = np.arange(n)
    df = pd.DataFrame(
        {
            "Te": 2 + 4 * np.sin(2 * np.pi * hours / 24) + rng.normal(0, 0.5, n),
            "phi_h": 4000.0 * (rng.uniform(size=n) > 0.5),
            "ghi": np.clip(500 * np.sin(2 * np.pi * (hours % 24 - 6) / 24), 0, None),
        },
        index=t,
    )
    df["Ti"] = simulate_stochastic(model, df, seed=2)["Ti"].round(3)
    out = df.copy()
    out.index.name = "time"
    out.to_csv(path)
    return df


def test_fit_command_writes_json_and_figures(tmp_path):
    data = tmp_path / "data.csv"
    write_data(data)
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["fit", str(MODEL), str(data), "--out", str(out)])
    assert result.exit_code == 0, result.output
    content = json.loads((out / "fit.json").read_text())
    for key in ("loglike", "aic", "bic", "nobs", "converged", "fit_seconds", "params",
                "correlation", "flags"):  # fmt: skip
        assert key in content
    assert content["nobs"] == 240
    assert set(content["params"]["H_v"]) >= {"value", "std_error", "lower", "upper", "fixed"}
    names = content["correlation"]["names"]
    assert len(content["correlation"]["matrix"]) == len(names)
    assert (out / "prediction_Ti.png").stat().st_size > 10_000
    assert (out / "residuals_Ti.png").stat().st_size > 10_000
    assert "log-likelihood" in result.output
    # the same fit through the Python API
    df = pd.read_csv(data)
    res = RCModel.from_yaml(MODEL).fit(df, time_column="time")
    assert (
        res.loglike == np.float64(content["loglike"])
        or abs(res.loglike - content["loglike"]) < 1e-6
    )


def test_fit_command_numeric_time_and_separator(tmp_path):
    data = tmp_path / "data.csv"
    df = write_data(data, n=120)
    df2 = df.reset_index(drop=True)
    df2.insert(0, "t", np.arange(len(df2)) * 1.0)  # hours
    semi = tmp_path / "semi.csv"
    df2.to_csv(semi, sep=";", index=False)
    out = tmp_path / "out"
    args = ["fit", str(MODEL), str(semi), "--out", str(out), "--time-column", "t",
            "--time-unit", "h", "--no-figures"]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert json.loads((out / "fit.json").read_text())["nobs"] == 120


def test_fit_command_reports_unknown_column_without_traceback(tmp_path):
    data = tmp_path / "data.csv"
    df = write_data(data, n=60)
    df.rename(columns={"phi_h": "heating"}).to_csv(data)
    model = tmp_path / "model.yaml"
    shutil.copy(MODEL, model)
    import subprocess
    import sys

    proc = subprocess.run(
        [sys.executable, "-c", "from thermocal.cli import main; main()", "fit", str(model),
         str(data), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
    )  # fmt: skip
    assert proc.returncode == 2
    assert "'phi_h' (heat input)" in proc.stderr and "Traceback" not in proc.stderr
