"""``thermocal insitu LOG``: the average method of ISO 9869-1 on a heat-flux meter's log from
the command line (the EnergyPlus wall of the retrofit twin), its files and its messages."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest
from typer.testing import CliRunner

from thermocal.cli import app
from thermocal.errors import ThermocalInputError

REF = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_house"
LOG = REF / "heat_flux_north_wall.csv"


def test_the_wall_of_the_energyplus_twin(tmp_path):
    runner = CliRunner()
    out = tmp_path / "out"
    result = runner.invoke(
        app, ["insitu", str(LOG), "--heat-flux", "q_W_m2", "--out", str(out)], terminal_width=80
    )
    assert result.exit_code == 0, result.output
    assert "1.578 W/(m2 K)" in result.output and "7.3 %" in result.output
    assert "first vs last 2/3" in result.output and "FAILS" not in result.output
    assert max(len(line) for line in result.output.splitlines()) <= 80
    saved = json.loads((out / "in_situ.json").read_text())
    assert saved["u_value_W_per_m2K"] == pytest.approx(1.578, abs=1e-3)
    assert saved["converged"] and saved["days"] == 14
    running = pd.read_csv(out / "running_average.csv")
    assert len(running) == 14
    assert running.iloc[-1, 1] == pytest.approx(saved["u_value_W_per_m2K"])
    assert (out / "figures" / "running_average.png").stat().st_size > 1000


@pytest.mark.parametrize(
    ("rows", "options", "message"),
    [
        (None, [], "'q'.*--heat-flux, --temp-in and --temp-out.*columns: time, q_W_m2, Ti, Te"),
        ("kelvin", ["--heat-flux", "q_W_m2"], "--temperature-unit"),
        ("inward", ["--heat-flux", "q_W_m2"], "--inward"),
        (None, ["--heat-flux", "q_W_m2", "--temp-in", "Te"], "its own log column"),
    ],
)
def test_mistakes_are_named_with_the_commands_options(tmp_path, rows, options, message):
    path = LOG
    if rows is not None:
        log = pd.read_csv(LOG)
        if rows == "kelvin":
            log["Ti"] += 273.15
        else:
            log["q_W_m2"] = -log["q_W_m2"]
        path = tmp_path / "plate.csv"
        log.to_csv(path, index=False)
    result = CliRunner().invoke(app, ["insitu", str(path), *options])
    assert isinstance(result.exception, ThermocalInputError), result.output
    assert pytest.importorskip("re").search(message, str(result.exception)), result.exception
    assert "LOG." not in str(result.exception)


def test_a_log_that_has_not_converged_is_shown_and_exits_with_1(tmp_path):
    """Two days: the table says which criterion fails (the analyses would refuse the log) and
    the command exits with 1 after writing what it found."""
    path = tmp_path / "two_days.csv"
    pd.read_csv(LOG).iloc[:48].to_csv(path, index=False)
    out = tmp_path / "out"
    result = CliRunner().invoke(
        app, ["insitu", str(path), "--heat-flux", "q_W_m2", "--out", str(out)], terminal_width=80
    )
    assert result.exit_code == 1, result.output
    assert "FAILS" in result.output and "NOT CONVERGED" in result.output
    assert "duration: 2 days < 3" in " ".join(result.output.split())
    assert not json.loads((out / "in_situ.json").read_text())["converged"]



def test_numeric_times_and_header_units(tmp_path):
    """A logger's Unix seconds (the reader's message named --time-unit, which this command did
    not have) and units in the header under other names ('W/m²', '°C', refused as disagreeing
    with the configured 'W/m2' and 'C'; exploratory test, 2026-11-30): the same U-value."""
    log = pd.read_csv(LOG)
    stamps = pd.to_datetime(log["time"], utc=True)
    if stamps.dt.tz is None:  # pragma: no cover - the file's stamps carry their offset
        stamps = stamps.dt.tz_localize("UTC")
    epoch = log.assign(time=(stamps - pd.Timestamp("1970-01-01", tz="UTC")).dt.total_seconds())
    epoch.to_csv(tmp_path / "epoch.csv", index=False)
    units = log.rename(columns={"q_W_m2": "q [W/m²]", "Ti": "Ti [°C]", "Te": "Te [°C]"})
    units.to_csv(tmp_path / "units.csv", index=False)
    found = {}
    for name, options in (
        ("epoch", ["--heat-flux", "q_W_m2", "--time-unit", "s"]),
        ("units", ["--heat-flux", "q"]),
    ):
        out = tmp_path / name
        result = CliRunner().invoke(
            app, ["insitu", str(tmp_path / f"{name}.csv"), *options, "--out", str(out)]
        )
        assert result.exit_code == 0, (result.output, result.exception)
        found[name] = json.loads((out / "in_situ.json").read_text())["u_value_W_per_m2K"]
    assert found["epoch"] == pytest.approx(1.578, abs=1e-3)
    assert found["units"] == pytest.approx(1.578, abs=1e-3)
    refused = CliRunner().invoke(app, ["insitu", str(tmp_path / "epoch.csv"), "--heat-flux",
                                       "q_W_m2"])  # fmt: skip
    assert isinstance(refused.exception, ThermocalInputError)
    assert "(--time-unit)" in str(refused.exception)


def test_header_unit_against_the_option_names_the_option(tmp_path):
    log = pd.read_csv(LOG).rename(columns={"Ti": "Ti [°F]"})
    log.to_csv(tmp_path / "f.csv", index=False)
    result = CliRunner().invoke(app, ["insitu", str(tmp_path / "f.csv"), "--heat-flux", "q_W_m2"])
    assert isinstance(result.exception, ThermocalInputError)
    assert "declares '°F' but --temperature-unit says 'C'" in str(result.exception)


def test_a_units_row_and_a_foreign_unit_in_the_header_are_named(tmp_path):
    """A row of units under the header was 'cannot read nan as a time' with no hint of the
    units row; a heat flux headed in Btu/(h ft2) was 'not found'. Both now say what they are
    and what to do."""
    log = pd.read_csv(LOG).rename(columns={"q_W_m2": "q"})
    units = tmp_path / "units_row.csv"
    units.write_text("time,q,Ti,Te\n,W/m2,C,C\n" + log.to_csv(index=False, header=False))
    result = CliRunner().invoke(app, ["insitu", str(units)])
    assert isinstance(result.exception, ThermocalInputError), result.output
    assert "line 2 is a row of units (W/m2, C, C), not a reading: delete it" in str(
        result.exception)
    btu = tmp_path / "btu.csv"
    log.assign(q=log["q"] / 3.1546).rename(columns={"q": "q [Btu/(h ft2)]"}).to_csv(btu,
                                                                                  index=False)
    result = CliRunner().invoke(app, ["insitu", str(btu)])
    assert isinstance(result.exception, ThermocalInputError), result.output
    text = str(result.exception)
    assert "'q [Btu/(h ft2)]' is --heat-flux 'q' in 'Btu/(h ft2)'" in text, text
    assert "convert the column to W/m2 (1 Btu/(h ft2) = 3.1546 W/m2)" in text and "LOG" not in text
