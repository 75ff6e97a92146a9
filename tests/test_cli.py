"""The command line: help texts, the version command and the retrofit summary tables."""

from pathlib import Path

from typer.testing import CliRunner

from thermocal import __version__
from thermocal.cli import COMMAND_MODULES, app


def test_help_lists_every_command():
    result = CliRunner().invoke(app, ["--help"])
    assert result.exit_code == 0
    for name in ("version", *COMMAND_MODULES):
        assert f" {name} " in result.output, name


def test_version():
    result = CliRunner().invoke(app, ["version"])
    assert result.exit_code == 0
    assert result.output.strip() == __version__


def test_retrofit_and_demo_help_name_their_inputs_and_outputs():
    runner = CliRunner()
    retro = runner.invoke(app, ["retrofit", "--help"], terminal_width=120)
    assert retro.exit_code == 0
    assert "CONFIG" in retro.output.upper() and "--out" in retro.output
    assert "results.json" in retro.output and "report.html" in retro.output
    demo = runner.invoke(app, ["demo", "--help"], terminal_width=120)
    assert demo.exit_code == 0
    for option in ("--out", "--weather", "--regenerate", "--draws"):
        assert option in demo.output


def _results(interval: float) -> dict:
    from thermocal.retrofit.strategies import all_strategies

    metrics = {"mae": 0.86, "mape": 3.92, "mse": 1.25, "mean_simulated": 21.64,
               "mean_measured": 21.91, "mean_deviation_pct": -1.27}  # fmt: skip
    scenarios = [
        {"code": s.code, "measures": list(s.measures), "annual_kWh": 1000.0 * (16 - i),
         "saving_pct": 6.25 * i, "saving_pct_p05": 5.0 * i, "saving_pct_p95": 7.5 * i}
        for i, s in enumerate(all_strategies())
    ]  # fmt: skip
    return {
        "heat_loss_coefficient_W_per_K": {"value": 484.0, "std": 12.0},
        "validation": {"train": {**metrics, "mae": 1.06}, "test": metrics},
        "annual_heating_demand_kWh": {
            "value": 28630.0,
            "p05": 27000.0,
            "p95": 30000.0,
            "references": {"SIA 380/1": 39170.0, "measured fuel use": 30660.0},
        },  # fmt: skip
        "scenarios": scenarios,
        "uncertainty": {"interval": interval},
        "calibration": {"flags": ["parameter C_i at its bound"]},
    }


def test_retrofit_summary_tables(capsys):
    from thermocal.commands.retrofit import print_summary

    print_summary(_results(0.8), Path("out"))
    text = capsys.readouterr().out
    assert "HLC 484 ± 12 W/K" in text
    assert "80 % interval" in text and "90 %" not in text  # the configured interval
    assert "1.06" in text and "0.86" in text and "-1.27" in text  # both validation periods
    assert "SIA 380/1: 39,170 kWh" in text and "30,660 kWh" in text  # references side by side
    for code in ("1a", "2f", "3c", "4"):
        assert f"│ {code:>4} │" in text
    assert "│   3c │ roof + windows + cellar" in text  # paper 000 Table 3 (rows may wrap)
    assert "flag:" in text and "C_i at its bound" in text


def test_demo_rejects_negative_draws_before_running():
    result = CliRunner().invoke(app, ["demo", "--draws", "-5", "--out", "unused"])
    assert result.exit_code != 0
    assert "--draws" in result.output
