"""``thermocal fit`` end to end on a small synthetic data set, and its input errors."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
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
    # the heat loss coefficient the structure implies, profile interval first
    hlc = content["heat_loss_coefficient"]
    assert hlc["value"] == pytest.approx(
        res.heat_loss_coefficient(profile=False)["value"], rel=1e-6
    )
    assert hlc["interval"] == "profile" and hlc["lower"] < hlc["value"] < hlc["upper"]
    assert (
        "heat loss coefficient" in result.output and "profile-likelihood interval" in result.output
    )
    # the written model file holds the estimates
    import yaml

    fitted = yaml.safe_load((out / "model_fitted.yaml").read_text())
    for name, entry in fitted["parameters"].items():
        assert entry["value"] == pytest.approx(res.params[name], rel=1e-6, abs=1e-8), name
    assert (
        res.loglike == np.float64(content["loglike"])
        or abs(res.loglike - content["loglike"]) < 1e-6
    )
    # every parameter with its estimate and bounds; the correlation of the free ones
    assert set(content["params"]) == set(res.params.index)
    for name, entry in content["params"].items():
        p = res.model.parameters[name]
        assert entry["value"] == pytest.approx(res.params[name], rel=1e-6)
        assert entry["fixed"] is p.fixed
        assert entry["lower"] == p.lower
        assert entry["upper"] == (None if p.upper == np.inf else p.upper)
    assert names == res.model.free_parameter_names
    corr = np.array(content["correlation"]["matrix"], dtype=float)
    np.testing.assert_allclose(corr, corr.T, atol=1e-12)
    np.testing.assert_allclose(np.diag(corr)[np.isfinite(np.diag(corr))], 1.0, atol=1e-12)
    assert content["aic"] == pytest.approx(-2 * content["loglike"] + 2 * len(names))
    assert content["bic"] == pytest.approx(-2 * content["loglike"] + len(names) * np.log(240))


def test_fit_command_numeric_time_and_separator(tmp_path):
    data = tmp_path / "data.csv"
    df = write_data(data, n=120)
    df2 = df.reset_index(drop=True)
    df2.insert(0, "t", np.arange(len(df2)) * 1.0)  # hours
    semi = tmp_path / "semi.csv"
    df2.to_csv(semi, sep=";", index=False)
    out = tmp_path / "out"
    args = ["fit", "--no-hlc", str(MODEL), str(semi), "--out", str(out), "--time-column", "t",
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
        [sys.executable, "-c", "from thermocal.cli import main; main()", "fit", "--no-hlc",
         str(model),
         str(data), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
    )  # fmt: skip
    assert proc.returncode == 2
    assert "'phi_h' (heat input)" in proc.stderr and "Traceback" not in proc.stderr


def _bad_case(tmp_path: Path, case: str) -> tuple[Path, Path, list[str]]:
    """A model file and a data file with one defect of the issue's bad-input list."""
    data = tmp_path / "data.csv"
    df = write_data(data, n=40)
    df.index.name = "time"
    model_text = MODEL.read_text()
    expected = []
    if case == "empty file":
        data.write_text("")
        expected = [str(data), "could not be read"]
    elif case == "corrupt parquet":
        data = tmp_path / "data.parquet"
        data.write_text("not a parquet file")
        expected = [str(data), "could not be read as Parquet"]
    elif case == "unknown column":
        model_text = model_text.replace("column: phi_h", "column: phi_heating")
        expected = [str(data), "'phi_heating'", "not in the data"]
    elif case == "state without capacity":
        model_text = model_text.replace("Tenv: {capacity: Cenv, ", "Tenv: {")
        expected = ["model.yaml", "state 'Tenv' has no capacity"]
    elif case == "parameter outside bounds":
        model_text = model_text.replace("H_v: {value: 80", "H_v: {value: 8000")
        expected = ["model.yaml", "'H_v'", "outside its bounds"]
    elif case == "duplicated time stamp":
        pd.concat([df.iloc[:10], df.iloc[9:]]).to_csv(data)
        expected = [str(data), "duplicated time stamp", "row 10"]
    elif case == "non-increasing time stamps":
        pd.concat([df.iloc[:10], df.iloc[[11, 10]], df.iloc[12:]]).to_csv(data)
        expected = [str(data), "not increasing", "row 11", "sort the data"]
    elif case == "all-NaN output":
        df.assign(Ti=np.nan).to_csv(data)
        expected = [str(data), "'Ti'", "all NaN"]
    elif case == "no heating":  # a free-floating period: the heat loss coefficient is not
        df.assign(phi_h=0.0).to_csv(data)  # identifiable (only the time constants are)
        expected = [str(data), "no heat input of known power", "'phi_h' is zero in every row",
                    "'ghi' enters through the free scale 'Aw'", "fixed: true"]  # fmt: skip
    elif case == "one observation":
        df.assign(Ti=[df["Ti"].iloc[0]] + [np.nan] * (len(df) - 1)).to_csv(data)
        expected = [str(data), "'Ti'", "1 observed value(s) for the 11 free parameters"]
    elif case == "rows missing from the time axis":
        pd.concat([df.iloc[:10], df.iloc[30:]]).to_csv(data)
        expected = [str(data), "the time axis jumps", "(rows 9 and 10): 20 sample(s)",
                    "--gaps split"]  # fmt: skip
    elif case == "indoor in Fahrenheit":
        df.assign(Ti=df["Ti"] * 9 / 5 + 32).to_csv(data)
        expected = [str(data), "indoor (output) temperature column 'Ti'", "Fahrenheit"]
    model = tmp_path / "model.yaml"
    model.write_text(model_text)
    return model, data, expected


@pytest.mark.parametrize(
    "case",
    ["empty file", "corrupt parquet", "unknown column", "state without capacity",
     "parameter outside bounds", "duplicated time stamp", "non-increasing time stamps",
     "all-NaN output", "no heating", "one observation", "rows missing from the time axis",
     "indoor in Fahrenheit"],
)  # fmt: skip
def test_fit_command_bad_input_gives_one_clear_message(tmp_path, case):
    from thermocal.errors import ThermocalInputError

    model, data, expected = _bad_case(tmp_path, case)
    result = CliRunner().invoke(
        app, ["fit", "--no-hlc", str(model), str(data), "--out", str(tmp_path / "o")]
    )
    assert isinstance(result.exception, ThermocalInputError), result.output
    message = str(result.exception)
    for text in expected:
        assert text in message, message
    assert not (tmp_path / "o" / "fit.json").exists()


def test_fit_reads_data_as_users_have_it(tmp_path):
    """Day-first time stamps, a unit row, decimal commas with ';', a renamed column, short
    input gaps: the same optimum as the clean file, with notes; provenance and CSV outputs."""
    clean = tmp_path / "clean.csv"
    df = write_data(clean)
    ref = tmp_path / "ref"
    result = CliRunner().invoke(
        app, ["fit", "--no-hlc", str(MODEL), str(clean), "--out", str(ref), "--no-figures"]
    )
    assert result.exit_code == 0, result.output
    messy = df.rename(columns={"ghi": "Gv"})
    messy.index = messy.index.tz_localize(None).strftime("%d.%m.%Y %H:%M")
    messy.index.name = "Zeit"
    messy.iloc[[50, 51], messy.columns.get_loc("Te")] = np.nan  # 2-sample gap
    text = messy.to_csv(sep=";", decimal=",")
    lines = text.splitlines()
    lines.insert(1, "[dd.mm.yyyy];[C];[W];[W/m2];[C]")
    path = tmp_path / "messy.csv"
    path.write_text("\n".join(lines) + "\n")
    out = tmp_path / "out"
    args = [
        "fit",
        "--no-hlc",
        str(MODEL),
        str(path),
        "--out",
        str(out),
        "--no-figures",
        "--decimal",
        ",",
    ]
    args += ["--time-format", "%d.%m.%Y %H:%M", "--map", "ghi=Gv", "--time-column", "Zeit"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    content = json.loads((out / "fit.json").read_text())
    notes = " | ".join(content["data_notes"])
    assert "unit row under the header dropped" in notes
    assert "Gv -> ghi" in notes
    assert "input 'Te': 2 missing value(s) in 1 gap(s) of at most 2 sample(s)" in notes
    reference = json.loads((ref / "fit.json").read_text())
    # the interpolated outdoor temperature differs in two samples only: nearly the same optimum
    assert content["loglike"] == pytest.approx(reference["loglike"], abs=1.0)
    assert content["nobs"] == reference["nobs"] == 240
    prov = content["provenance"]
    assert prov["files"][str(path)]["sha256"] and prov["thermocal_version"]
    params = pd.read_csv(out / "parameters.csv", index_col=0)
    assert params.loc["H_v", "value"] == pytest.approx(content["params"]["H_v"]["value"])
    pred = pd.read_csv(out / "predictions.csv")
    assert {"Ti", "Ti_pred", "Ti_std", "Ti_residual", "Ti_simulated"} <= set(pred.columns)
    assert len(pred) == 240
    # a long gap stops with the period to cut
    messy.iloc[100:110, messy.columns.get_loc("Te")] = np.nan
    text = messy.to_csv(sep=";", decimal=",")
    path.write_text(text)
    result = CliRunner().invoke(app, args)
    assert result.exit_code != 0
    assert "missing for 10 consecutive samples" in str(result.exception)
    assert "rows 100 to 109" in str(result.exception)


def test_strict_exits_non_zero_when_a_flag_is_raised(tmp_path):
    data = tmp_path / "data.csv"
    df = write_data(data)
    df.iloc[-1, df.columns.get_loc("Ti")] += 5.0  # a jump in the last sample
    df.index.name = "time"
    df.to_csv(data)
    out = tmp_path / "out"
    args = ["fit", "--no-hlc", str(MODEL), str(data), "--out", str(out), "--no-figures", "--strict"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 3, result.output
    assert "beyond 5 sigma" in result.output and "--strict" in result.output


def test_fit_reads_excel_with_columns_from_the_model_file_and_splits_long_gaps(tmp_path):
    """An .xlsx sheet (openpyxl), the model file's ``columns:`` mapping, and --gaps split: the
    same optimum as the CSV when nothing is missing; with a 12-hour heating gap the likelihood
    is split into two periods with their own initial states."""
    import yaml

    clean = tmp_path / "clean.csv"
    df = write_data(clean, n=120)
    ref = tmp_path / "ref"
    args = ["--no-figures", "--n-starts", "1"]
    result = CliRunner().invoke(
        app, ["fit", "--no-hlc", str(MODEL), str(clean), "--out", str(ref), *args]
    )
    assert result.exit_code == 0, result.output
    spec = yaml.safe_load(MODEL.read_text())
    spec["columns"] = {"phi_h": "Heizung", "Ti": "T_innen"}
    model_file = tmp_path / "model.yaml"
    model_file.write_text(yaml.safe_dump(spec))
    sheet = df.rename(columns={"phi_h": "Heizung", "Ti": "T_innen"})
    sheet.index = sheet.index.tz_localize(None)
    sheet.index.name = "time"
    xlsx = tmp_path / "data.xlsx"
    sheet.to_excel(xlsx, sheet_name="Messung")
    out = tmp_path / "out"
    cmd = ["fit", str(model_file), str(xlsx), "--out", str(out), "--sheet", "Messung", *args]
    cmd.append("--no-hlc")
    result = CliRunner().invoke(app, [*cmd, "--profile", "H_v"])
    assert result.exit_code == 0, result.output
    content = json.loads((out / "fit.json").read_text())
    interval = content["profile_intervals"]["H_v"]
    assert interval["lower"] < content["params"]["H_v"]["value"] < interval["upper"]
    assert "profile 95 % interval H_v" in result.output
    reference = json.loads((ref / "fit.json").read_text())
    assert content["loglike"] == pytest.approx(reference["loglike"], abs=1e-6)
    assert "Heizung -> phi_h" in " ".join(content["data_notes"])
    # a 12-hour gap of the heating data: stop by default, split on request
    sheet.iloc[50:62, sheet.columns.get_loc("Heizung")] = np.nan
    sheet.to_excel(xlsx, sheet_name="Messung")
    result = CliRunner().invoke(app, [*cmd[:4], str(tmp_path / "o2"), *cmd[5:]])
    assert result.exit_code != 0 and "--gaps split" in str(result.exception)
    result = CliRunner().invoke(app, [*cmd[:4], str(tmp_path / "o3"), *cmd[5:], "--gaps", "split"])
    assert result.exit_code == 0, result.output
    split = json.loads((tmp_path / "o3" / "fit.json").read_text())
    assert "split into 2 period(s)" in " ".join(split["data_notes"])
    # the checks --gaps split leaves out are said, not skipped silently (exploratory test,
    # 2026-12-01: no time_stamp_check and no note)
    assert "time stamps not checked: with --gaps split" in " ".join(split["data_notes"])
    assert split["time_stamp_check"]["skipped"] == "--gaps split"
    assert {"Ti0_p2", "Tenv0_p2"} <= set(split["params"])
    assert split["nobs"] == 108


def test_fit_refuses_work_beyond_its_limits(tmp_path, monkeypatch):
    """Large data gets a measured work estimate; beyond --max-hours, or beyond the memory of
    the stored filter moments, the fit is refused before computing, naming the remedy."""
    from thermocal.commands import fit as fit_command

    data = tmp_path / "data.csv"
    write_data(data, n=150)
    monkeypatch.setattr(fit_command, "ESTIMATE_ROWS", 100)
    args = ["fit", "--no-hlc", str(MODEL), str(data), "--out", str(tmp_path / "o"), "--no-figures"]
    result = CliRunner().invoke(app, [*args, "--max-hours", "1e-9"])
    assert result.exit_code != 0
    assert "the fit would take about" in str(result.exception)
    assert "more than --max-hours" in str(result.exception)
    assert "work estimate: 150 rows x 2 states" in result.output
    monkeypatch.setattr(fit_command, "MAX_STORE_BYTES", 1e4)
    result = CliRunner().invoke(app, args)
    assert "150 rows x 2 states need about" in str(result.exception)
    assert not (tmp_path / "o").exists()


def test_interval_end_time_stamps_shift_the_inputs_onto_the_hold(tmp_path):
    """Data stamped at the end of each interval (the input over [t_k-1, t_k] labelled t_k):
    with --time-stamps end the fit equals that of the same data stamped at the start (without
    its first and last rows); without it the inputs act one step late and the likelihood is
    lower."""
    start = tmp_path / "start.csv"
    df = write_data(start, n=120)
    end = df.copy()
    end[["Te", "phi_h", "ghi"]] = end[["Te", "phi_h", "ghi"]].shift(1)
    end = end.iloc[1:]
    end.index.name = "time"
    end.to_csv(tmp_path / "end.csv")
    trimmed = df.iloc[1:-1]  # the rows that keep both an input and an output
    trimmed.index.name = "time"
    trimmed.to_csv(tmp_path / "trimmed.csv")
    base = ["fit", "--no-hlc", str(MODEL), "--no-figures", "--n-starts", "1"]

    def loglike(csv, *extra):
        out = tmp_path / f"o_{csv}_{len(extra)}"
        result = CliRunner().invoke(app, [*base, str(tmp_path / csv), "--out", str(out), *extra])
        assert result.exit_code == 0, result.output
        return json.loads((out / "fit.json").read_text())

    shifted = loglike("end.csv", "--time-stamps", "end")
    reference = loglike("trimmed.csv")
    assert shifted["nobs"] == reference["nobs"] == 118
    assert shifted["loglike"] == pytest.approx(reference["loglike"], abs=1e-6)
    assert any("--time-stamps end" in n for n in shifted["data_notes"])
    late = loglike("end.csv")
    assert shifted["loglike"] > late["loglike"]


def test_a_single_start_is_flagged_global_optimum_not_checked(tmp_path):
    """I1 (fuzz5 m32): `--n-starts 1` gave `converged: true` with `starts_at_best: 1` and no
    word that no second start could confirm the optimum (docs/model-file.md: converged needs
    two starts that agree). Now the first flag says so; with two starts it is absent."""
    write_data(tmp_path / "d.csv", n=120)
    base = ["fit", str(MODEL), str(tmp_path / "d.csv"), "--no-figures", "--no-hlc",
            "--no-time-stamp-check"]  # fmt: skip
    ran = CliRunner().invoke(app, [*base, "--n-starts", "1", "--out", str(tmp_path / "one")])
    assert ran.exit_code == 0, ran.output
    content = json.loads((tmp_path / "one" / "fit.json").read_text())
    assert content["flags"][0].startswith("global optimum not checked: a single optimiser start")
    ran = CliRunner().invoke(app, [*base, "--n-starts", "2", "--out", str(tmp_path / "two")])
    assert ran.exit_code == 0, ran.output
    content = json.loads((tmp_path / "two" / "fit.json").read_text())
    assert not [f for f in content["flags"] if f.startswith("global optimum not checked")]


def test_model_file_docs_name_python_objects_that_exist():
    """D3 (fuzz5 a04): docs/model-file.md named `forward_selection` beside
    `thermocal.statespace.families`, where it is not. Every dotted `thermocal.statespace...`
    name the page gives resolves (module, then attribute)."""
    import importlib
    import re

    text = (REPO / "docs" / "model-file.md").read_text()
    names = set(re.findall(r"`(thermocal\.statespace(?:\.[A-Za-z_]\w*)+)", text))
    assert "thermocal.statespace.selection.forward_selection" in names
    for name in sorted(names):
        parts = name.split(".")
        for cut in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:cut]))
            except ModuleNotFoundError:
                continue
            for attr in parts[cut:]:
                obj = getattr(obj, attr, None)
                assert obj is not None, name
            break


def test_fit_reads_thousands_separators_of_a_decimal_comma_export(tmp_path):
    """A European export writes 4000 W as '4.000,0': replacing the comma alone read it as 4 W
    (a heat loss coefficient of 1,230 W/K instead of 499 on an exploratory tester's file,
    2026-11-30). The same data with and without thousands separators (and Excel's trailing
    separators, refused before as a column named twice) give the same fit; a point that groups
    no thousands ('7.5') is refused, naming the row."""
    df = write_data(tmp_path / "clean.csv")

    def export(frame, path, grouped: bool):
        text = frame.copy()
        text.index = text.index.tz_localize(None).strftime("%d.%m.%Y %H:%M")
        text.index.name = "Zeit"
        for column in text.columns:
            values = [f"{v:,.2f}" if grouped else f"{v:.2f}" for v in frame[column]]
            text[column] = [v.replace(",", "_").replace(".", ",").replace("_", ".") for v in values]
        text.to_csv(path, sep=";")
        if grouped:  # and Excel's trailing separators: two unnamed, empty columns
            lines = path.read_text().splitlines()
            path.write_text("\n".join(f"{line};;" for line in lines) + "\n")

    runs = {}
    for grouped in (False, True):
        path = tmp_path / f"grouped_{grouped}.csv"
        export(df, path, grouped)
        assert ("4.000,00" in path.read_text()) is grouped
        out = tmp_path / f"out_{grouped}"
        args = ["fit", "--no-hlc", str(MODEL), str(path), "--out", str(out), "--no-figures",
                "--decimal", ",", "--time-format", "%d.%m.%Y %H:%M",
                "--time-column", "Zeit"]  # fmt: skip
        result = CliRunner().invoke(app, args)
        assert result.exit_code == 0, result.output
        runs[grouped] = json.loads((out / "fit.json").read_text())
    assert runs[True]["loglike"] == pytest.approx(runs[False]["loglike"], rel=1e-12)
    assert runs[True]["params"]["H_v"]["value"] == pytest.approx(
        runs[False]["params"]["H_v"]["value"], rel=1e-9
    )
    path = tmp_path / "grouped_True.csv"
    lines = path.read_text().splitlines()
    lines[5] = lines[5].replace("4.000,00", "4000.5") if "4.000,00" in lines[5] else lines[5]
    assert "4000.5" in lines[5]
    path.write_text("\n".join(lines) + "\n")
    result = CliRunner().invoke(app, args)  # the grouped file, edited
    assert result.exit_code != 0
    assert "'4000.5' has a decimal point" in str(result.exception)
    assert "row 4 (file line 6)" in str(result.exception)


def test_fit_says_when_a_bound_holds_the_heat_loss_coefficient_and_runs_on_few_rows(tmp_path):
    """An exploratory round, 2026-11-30: a resistance's bound held the heat loss coefficient
    (248.5 W/K [246.6, 250.3] for a truth of 166.7) and the headline said nothing; a fit of 12
    rows for 10 parameters succeeded, then the time-stamp check's refits (two rows fewer)
    stopped the command, blaming the data."""
    data = tmp_path / "data.csv"
    write_data(data)
    bounded = tmp_path / "bounded.yaml"
    text = MODEL.read_text()
    line = "  H_v: {value: 80, lower: 0.1, upper: 2000, unit: W/K}"
    assert line in text
    bounded.write_text(text.replace(line, "  H_v: {value: 10, lower: 0.1, upper: 20, unit: W/K}"))
    out = tmp_path / "out"
    result = CliRunner().invoke(
        app, ["fit", str(bounded), str(data), "--out", str(out), "--no-figures"], terminal_width=200
    )
    assert result.exit_code == 0, result.output
    printed = " ".join(result.output.split())
    assert "HELD BY A BOUND: H_v at its bound" in printed
    content = json.loads((out / "fit.json").read_text())
    assert content["heat_loss_coefficient"]["held_by_bounds"] == ["H_v"]
    few = tmp_path / "few.csv"
    pd.read_csv(data).iloc[:12].to_csv(few, index=False)
    result = CliRunner().invoke(
        app, ["fit", "--no-hlc", str(MODEL), str(few), "--out", str(tmp_path / "few"),
              "--no-figures"],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    notes = json.loads((tmp_path / "few" / "fit.json").read_text())["data_notes"]
    assert any(n.startswith("time stamps not checked") for n in notes), notes


def test_fit_table_shows_no_standard_error_at_a_bound(tmp_path):
    """A capacity at its bound got 4 +- 1.5e-07 kWh/K (an exploratory round, 2026-11-30): the
    delta method maps the wide spread of its log scale to a tiny one. The table says 'at
    bound'."""
    data = tmp_path / "data.csv"
    write_data(data)
    text = MODEL.read_text()
    line = "  Cenv: {value: 50, lower: 1, upper: 2000, unit: MJ/K}"
    assert line in text
    bounded = tmp_path / "bounded.yaml"
    bounded.write_text(text.replace(line, "  Cenv: {value: 1.5, lower: 1, upper: 2, unit: MJ/K}"))
    result = CliRunner().invoke(
        app, ["fit", "--no-hlc", str(bounded), str(data), "--out", str(tmp_path / "o"),
              "--no-figures"], terminal_width=200,
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    row = next(line for line in result.output.splitlines() if "│ Cenv" in line)
    assert "at bound" in row, row
