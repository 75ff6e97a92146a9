# ruff: noqa: E501 - one row per case reads best on one line
"""Bad input across the four commands: one row per case (issue 13).

Every row runs the real entry point (:func:`thermocal.cli.main`, in process) and asserts the
exit code, that no traceback is printed, that the message names the culprit (file, column,
row, option or parameter) and says what to do, and that no output folder is left behind.
Every case stops before any computation, so the table is fast.
"""

from __future__ import annotations

import re
import shutil
import signal
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from thermocal.cli import main

REPO = Path(__file__).resolve().parents[2]
MODEL = REPO / "examples" / "models" / "two_state_envelope.yaml"
TMY3 = Path(__import__("pvlib").__file__).parent / "data" / "723170TYA.CSV"
DEMO = REPO / "src" / "thermocal" / "data" / "retrofit_demo"
DOC = REPO / "docs" / "multizone-file.md"

BOMB = "\n".join(
    [f"{chr(97)}: &{chr(97)} [lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    + [
        f"{chr(97 + i)}: &{chr(97 + i)} [" + ", ".join([f"*{chr(96 + i)}"] * 9) + "]"
        for i in range(1, 9)
    ]
)


def run(args: list[str], capsys) -> tuple[int, str]:
    """Run ``thermocal ARGS`` through the console-script entry point; (exit code, stderr)."""
    handlers = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    argv = sys.argv
    sys.argv = ["thermocal", *map(str, args)]
    try:
        main()
        code = 0
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    finally:
        sys.argv = argv
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
    captured = capsys.readouterr()
    return code, captured.err + captured.out


# ------------------------------------------------------------------------------------------
# good inputs, each case breaks one thing
# ------------------------------------------------------------------------------------------
def _data(n: int = 48) -> pd.DataFrame:
    hours = np.arange(n)
    return pd.DataFrame(
        {
            "time": pd.date_range("2024-01-01", periods=n, freq="h", tz="UTC").astype(str),
            "Te": 5 + 4 * np.sin(2 * np.pi * hours / 24),
            "phi_h": np.where(hours % 3 == 0, 3000.0, 0.0),
            "ghi": np.clip(500 * np.sin(2 * np.pi * (hours % 24 - 6) / 24), 0, None),
            "Ti": 20 + 0.5 * np.sin(2 * np.pi * hours / 24),
        }
    )


def _building_yaml() -> str:
    text = DOC.read_text()
    return re.search(r"## Example\s+```yaml\n(.*?)```", text, re.S).group(1)


def _retrofit_config() -> dict:
    cfg = yaml.safe_load((REPO / "examples" / "retrofit" / "config.yaml").read_text())
    cfg["building"] = str(DEMO / "building.yaml")
    cfg["measurements"]["file"] = str(DEMO / "measurements.csv")
    return cfg


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("bad")
    f: dict[str, Path] = {"dir": d / "a_folder"}
    f["dir"].mkdir()
    f["afile"] = d / "afile.txt"
    f["afile"].write_text("not a folder")
    f["binary"] = d / "binary.yaml"
    f["binary"].write_bytes(bytes(range(256)) * 4)
    f["latin1"] = d / "latin1.yaml"
    f["latin1"].write_bytes("name: Zürich\n".encode("latin-1"))
    f["bomb"] = d / "bomb.yaml"
    f["bomb"].write_text(BOMB + "\n")
    f["deep"] = d / "deep.yaml"
    f["deep"].write_text("x: " + "[" * 2000 + "]" * 2000 + "\n")

    # fit
    model = MODEL.read_text()
    f["model"] = d / "model.yaml"
    f["model"].write_text(model)
    f["model_dup"] = d / "model_dup.yaml"
    f["model_dup"].write_text(model + "name: again\n")
    f["model_list"] = d / "model_list.yaml"
    f["model_list"].write_text(model.replace("Ci: {value: 5,", "Ci: {value: [5, 6],"))
    data = _data()
    f["data"] = d / "data.csv"
    data.to_csv(f["data"], index=False)
    f["header_only"] = d / "header_only.csv"
    f["header_only"].write_text("time,Te,phi_h,ghi,Ti\n")
    f["empty_csv"] = d / "empty.csv"
    f["empty_csv"].write_text("")
    f["latin1_csv"] = d / "latin1.csv"
    f["latin1_csv"].write_bytes(data.to_csv(index=False).replace("Te", "Té").encode("latin-1"))
    f["dupcols"] = d / "dupcols.csv"
    f["dupcols"].write_text(data.to_csv(index=False).replace("ghi", "Te", 1))
    hours = data.copy()
    hours["time"] = np.arange(len(data), dtype=float)  # hours, read with the default 's'
    f["hours"] = d / "hours.csv"
    hours.to_csv(f["hours"], index=False)
    days = data.copy()
    days["time"] = np.arange(len(data), dtype=float) * 3600.0  # seconds, read as days
    f["seconds"] = d / "seconds.csv"
    days.to_csv(f["seconds"], index=False)
    shuffled = data.copy()
    shuffled.loc[[10, 11], "time"] = shuffled.loc[[11, 10], "time"].to_numpy()
    f["unsorted"] = d / "unsorted.csv"
    shuffled.to_csv(f["unsorted"], index=False)
    dup = data.copy()
    dup.loc[20, "time"] = dup.loc[19, "time"]
    f["duptime"] = d / "duptime.csv"
    dup.to_csv(f["duptime"], index=False)
    mixed = data.copy()
    mixed["time"] = mixed["time"].str.replace("+00:00", "", regex=False)
    mixed.loc[30:, "time"] = data.loc[30:, "time"]
    f["mixed_tz"] = d / "mixed_tz.csv"
    mixed.to_csv(f["mixed_tz"], index=False)
    text = data.copy()
    text["Te"] = text["Te"].astype(object)
    text.loc[25, "Te"] = "n.a."
    f["text_value"] = d / "text_value.csv"
    text.to_csv(f["text_value"], index=False)
    f["no_Te"] = d / "no_Te.csv"
    data.drop(columns="Te").to_csv(f["no_Te"], index=False)
    f["decimal_comma"] = d / "decimal_comma.csv"
    data.to_csv(f["decimal_comma"], index=False, sep=";", decimal=",")
    f["kelvin"] = d / "kelvin.csv"
    kelvin = data.copy()
    kelvin["Ti"] += 273.15
    kelvin.to_csv(f["kelvin"], index=False)
    f["bad_parquet"] = d / "bad.parquet"
    f["bad_parquet"].write_bytes(b"PAR1 not really")
    local = pd.DataFrame(_data(n=72).drop(columns="time"))
    spring = pd.date_range("2024-03-30 12:00", periods=72, freq="h", tz="Europe/Zurich")
    local["time"] = spring.tz_localize(None).astype(str)  # naive local: 02:00 is skipped
    f["spring"] = d / "spring.csv"
    local.to_csv(f["spring"], index=False)
    autumn = pd.date_range("2024-10-26 12:00", periods=72, freq="h", tz="Europe/Zurich")
    local["time"] = autumn.tz_localize(None).astype(str)  # naive local: 02:00 twice
    f["autumn"] = d / "autumn.csv"
    local.to_csv(f["autumn"], index=False)
    f["bad_time"] = d / "bad_time.csv"
    bad_time = data.copy()
    bad_time.loc[40, "time"] = "2024-01-02 16:00 next"
    bad_time.to_csv(f["bad_time"], index=False)

    # simulate
    building = _building_yaml()
    f["bldg"] = d / "two_rooms.yaml"
    f["bldg"].write_text(building)
    f["bldg_dup"] = d / "bldg_dup.yaml"
    f["bldg_dup"].write_text(building + "name: again\n")
    f["bldg_k"] = d / "bldg_k.yaml"
    f["bldg_k"].write_text(building.replace("conductivity: 0.44", "conductivity: 1.0e30"))
    f["bldg_thin"] = d / "bldg_thin.yaml"
    f["bldg_thin"].write_text(building.replace("thickness: 0.30", "thickness: 1.0e-9"))
    f["bldg_kelvin_sp"] = d / "bldg_kelvin_sp.yaml"
    f["bldg_kelvin_sp"].write_text(
        building.replace("infiltration_ach: 0.5, heating_setpoint: 20}",
                         "infiltration_ach: 0.5, heating_setpoint: 293.15}", 1)
    )  # fmt: skip
    f["bldg_density"] = d / "bldg_density.yaml"
    f["bldg_density"].write_text(building.replace("density: 1200", "density: 1.2"))
    f["bldg_list"] = d / "bldg_list.yaml"
    f["bldg_list"].write_text(building.replace("volume: 75", "volume: [75, 80]"))
    f["bldg_neg_area"] = d / "bldg_neg_area.yaml"
    f["bldg_neg_area"].write_text(building.replace("area: 15, azimuth: 180", "area: -15, azimuth: 180"))
    f["bldg_txt"] = d / "two_rooms.txt"
    f["bldg_txt"].write_text(building)
    f["weather"] = TMY3
    f["weather_bin"] = d / "weather.epw"
    f["weather_bin"].write_bytes(bytes(range(256)) * 40)

    # retrofit
    def config(name: str, edit) -> Path:
        cfg = _retrofit_config()
        edit(cfg)
        path = d / f"{name}.yaml"
        path.write_text(yaml.safe_dump(cfg, sort_keys=False))
        return path

    f["cfg_dup"] = d / "cfg_dup.yaml"
    f["cfg_dup"].write_text(yaml.safe_dump(_retrofit_config()) + "uncertainty: {draws: 5}\n")
    f["cfg_no_meas"] = config("cfg_no_meas", lambda c: c["measurements"].update(file="gone.csv"))
    f["cfg_days_list"] = config("cfg_days_list", lambda c: c["periods"].update(training_days=[21]))
    f["cfg_days_huge"] = config("cfg_days_huge", lambda c: c["periods"].update(training_days=1e12))
    f["cfg_flow_unit"] = config("cfg_flow_unit", lambda c: c["measurements"].update(flow_unit="gal"))
    f["cfg_column"] = config(
        "cfg_column", lambda c: c["measurements"]["columns"].update(temp_in="T_inside")
    )
    f["cfg_draws"] = config("cfg_draws", lambda c: c["uncertainty"].update(draws=10_000_000))
    f["cfg_unknown"] = config("cfg_unknown", lambda c: c.update(measurment={}))
    f["cfg_weather"] = config("cfg_weather", lambda c: c["weather"].update(file=str(d / "a_folder")))
    f["cfg_bldg_dir"] = config("cfg_bldg_dir", lambda c: c.update(building=str(d / "a_folder")))
    f["cfg_bldg_bomb"] = config("cfg_bldg_bomb", lambda c: c.update(building=str(d / "bomb.yaml")))
    return f


def F(key):  # noqa: N802 - reads like a placeholder in the table
    """A fixture file, resolved when the case runs."""
    return ("file", key)


# id, arguments, exit code, regular expressions the message must contain (all of them)
CASES = [
    # ---------------------------------------------------------------- fit: files
    ("fit-model-missing", ["fit", "nowhere.yaml", F("data")], 2, [r"model file nowhere\.yaml does not exist"]),
    ("fit-model-folder", ["fit", F("dir"), F("data")], 2, [r"a_folder is a folder, not a file"]),
    ("fit-model-binary", ["fit", F("binary"), F("data")], 2, [r"binary\.yaml", r"binary file|UTF-8"]),
    ("fit-model-latin1", ["fit", F("latin1"), F("data")], 2, [r"latin1\.yaml", r"save the model file as UTF-8"]),
    ("fit-model-duplicate-key", ["fit", F("model_dup"), F("data")], 2, [r"model_dup\.yaml", r"'name' appears twice \(lines \d+ and \d+\)"]),
    ("fit-model-alias-bomb", ["fit", F("bomb"), F("data")], 2, [r"bomb\.yaml", r"aliases"]),
    ("fit-model-deep", ["fit", F("deep"), F("data")], 2, [r"deep\.yaml", r"nested too deeply"]),
    ("fit-model-list-for-number", ["fit", F("model_list"), F("data")], 2, [r"model_list\.yaml", r"Ci"]),
    ("fit-data-missing", ["fit", F("model"), "nowhere.csv"], 2, [r"data file nowhere\.csv does not exist"]),
    ("fit-data-folder", ["fit", F("model"), F("dir")], 2, [r"a_folder is a folder, not a file"]),
    ("fit-data-header-only", ["fit", F("model"), F("header_only")], 2, [r"header_only\.csv", r"no data rows"]),
    ("fit-data-empty", ["fit", F("model"), F("empty_csv")], 2, [r"empty\.csv", r"empty"]),
    ("fit-data-latin1", ["fit", F("model"), F("latin1_csv")], 2, [r"latin1\.csv", r"UTF-8"]),
    ("fit-data-binary", ["fit", F("model"), F("binary")], 2, [r"binary\.yaml", r"not a (CSV|text)"]),
    ("fit-data-duplicate-columns", ["fit", F("model"), F("dupcols")], 2, [r"dupcols\.csv", r"'Te' appears twice"]),
    ("fit-data-bad-parquet", ["fit", F("model"), F("bad_parquet")], 2, [r"bad\.parquet", r"Parquet"]),
    ("fit-sep-empty", ["fit", F("model"), F("data"), "--sep", ""], 2, [r"--sep", r"one character"]),
    ("fit-decimal-bad", ["fit", F("model"), F("data"), "--decimal", "x"], 2, [r"--decimal", r"'\.' or ','"]),
    ("fit-decimal-comma-unsaid", ["fit", F("model"), F("decimal_comma")], 2, [r"decimal_comma\.csv", r"--decimal ,"]),
    # ---------------------------------------------------------------- fit: time axis and options
    ("fit-hours-read-as-seconds", ["fit", F("model"), F("hours")], 2, [r"hours\.csv", r"1 s", r"--time-unit"]),
    ("fit-seconds-read-as-days", ["fit", F("model"), F("seconds"), "--time-unit", "d"], 2, [r"seconds\.csv", r"--time-unit"]),
    ("fit-time-unit-unknown", ["fit", F("model"), F("data"), "--time-unit", "fortnight"], 2, [r"--time-unit", r"fortnight"]),
    ("fit-hold-unknown", ["fit", F("model"), F("data"), "--hold", "cubic"], 2, [r"--hold", r"zoh or foh"]),
    ("fit-time-column-absent", ["fit", F("model"), F("data"), "--time-column", "stamp"], 2, [r"no time column 'stamp'", r"--time-column"]),
    ("fit-time-format-mismatch", ["fit", F("model"), F("data"), "--time-format", "%d.%m.%Y"], 2, [r"--time-format"]),
    ("fit-map-malformed", ["fit", F("model"), F("data"), "--map", "Ti"], 2, [r"--map 'Ti'", r"MODEL_COLUMN=DATA_COLUMN"]),
    ("fit-map-absent", ["fit", F("model"), F("data"), "--map", "Ti=T_room"], 2, [r"'T_room'", r"columns present"]),
    ("fit-unsorted-times", ["fit", F("model"), F("unsorted")], 2, [r"unsorted\.csv", r"row"]),
    ("fit-duplicate-times", ["fit", F("model"), F("duptime")], 2, [r"duptime\.csv", r"row"]),
    ("fit-mixed-naive-aware", ["fit", F("model"), F("mixed_tz")], 2, [r"mixed_tz\.csv", r"row \d+", r"time zone|offset"]),
    ("fit-spring-clock-change", ["fit", F("model"), F("spring")], 2, [r"spring\.csv", r"row 14", r"spring clock change", r"UTC offset"]),
    ("fit-autumn-clock-change", ["fit", F("model"), F("autumn")], 2, [r"autumn\.csv", r"row 15", r"autumn clock change", r"UTC offset"]),
    ("fit-bad-time-value-row", ["fit", F("model"), F("bad_time")], 2, [r"bad_time\.csv", r"next"]),
    ("fit-text-in-numbers", ["fit", F("model"), F("text_value")], 2, [r"text_value\.csv", r"Te", r"n\.a\."]),
    ("fit-missing-model-column", ["fit", F("model"), F("no_Te")], 2, [r"Te"]),
    ("fit-kelvin-output", ["fit", F("model"), F("kelvin")], 2, [r"Ti", r"Kelvin|273"]),
    ("fit-n-starts-zero", ["fit", F("model"), F("data"), "--n-starts", "0"], 2, [r"--n-starts"]),
    ("fit-jobs-zero", ["fit", F("model"), F("data"), "--jobs", "0"], 2, [r"--jobs"]),
    ("fit-max-gap-negative", ["fit", F("model"), F("data"), "--max-gap", "-1"], 2, [r"--max-gap"]),
    ("fit-out-is-file", ["fit", F("model"), F("data"), "--out", F("afile")], 2, [r"afile\.txt is a file, not a folder"]),
    ("fit-out-below-file", ["fit", F("model"), F("data"), "--out", ("sub", "afile")], 2, [r"afile\.txt is a file"]),
    ("fit-out-foreign-folder", ["fit", F("model"), F("data"), "--out", ("foreign",)], 2, [r"thermocal did not write"]),
    # ---------------------------------------------------------------- simulate
    ("simulate-building-missing", ["simulate", "nowhere.yaml", F("weather")], 2, [r"nowhere\.yaml does not exist"]),
    ("simulate-building-folder", ["simulate", F("dir"), F("weather")], 2, [r"a_folder is a folder, not a file"]),
    ("simulate-building-extension", ["simulate", F("bldg_txt"), F("weather")], 2, [r"two_rooms\.txt", r"\.yaml"]),
    ("simulate-building-binary", ["simulate", F("binary"), F("weather")], 2, [r"binary\.yaml", r"binary file|UTF-8"]),
    ("simulate-building-latin1", ["simulate", F("latin1"), F("weather")], 2, [r"latin1\.yaml", r"UTF-8"]),
    ("simulate-building-alias-bomb", ["simulate", F("bomb"), F("weather")], 2, [r"bomb\.yaml", r"aliases"]),
    ("simulate-building-duplicate-key", ["simulate", F("bldg_dup"), F("weather")], 2, [r"bldg_dup\.yaml", r"appears twice"]),
    ("simulate-conductivity-absurd", ["simulate", F("bldg_k"), F("weather")], 2, [r"bldg_k\.yaml", r"brick", r"conductivity"]),
    ("simulate-thickness-absurd", ["simulate", F("bldg_thin"), F("weather")], 2, [r"bldg_thin\.yaml", r"brick", r"thickness"]),
    ("simulate-density-absurd", ["simulate", F("bldg_density"), F("weather")], 2, [r"bldg_density\.yaml", r"brick", r"density"]),
    ("simulate-setpoint-kelvin", ["simulate", F("bldg_kelvin_sp"), F("weather")], 2, [r"living", r"293\.15", r"Kelvin"]),
    ("simulate-list-for-number", ["simulate", F("bldg_list"), F("weather")], 2, [r"bldg_list\.yaml", r"living", r"volume"]),
    ("simulate-negative-area", ["simulate", F("bldg_neg_area"), F("weather")], 2, [r"bldg_neg_area\.yaml", r"living south", r"area"]),
    ("simulate-weather-missing", ["simulate", F("bldg"), "nowhere.epw"], 2, [r"nowhere\.epw"]),
    ("simulate-weather-folder", ["simulate", F("bldg"), F("dir")], 2, [r"a_folder", r"folder"]),
    ("simulate-weather-binary", ["simulate", F("bldg"), F("weather_bin")], 2, [r"weather\.epw"]),
    ("simulate-format-unknown", ["simulate", F("bldg"), F("weather"), "--format", "xml"], 2, [r"--format must be csv or parquet"]),
    ("simulate-step-unknown", ["simulate", F("bldg"), F("weather"), "--step", "often"], 2, [r"--step|step", r"often"]),
    ("simulate-step-zero", ["simulate", F("bldg"), F("weather"), "--step", "0min"], 2, [r"step"]),
    # a bare number was one nanosecond: a grid of 2.7e15 steps, "internal error (MemoryError)"
    ("simulate-step-without-unit", ["simulate", F("bldg"), F("weather"), "--step", "1"], 2, [r"--step .1. has no unit", r"1min"]),
    ("simulate-start-after-end", ["simulate", F("bldg"), F("weather"), "--start", "2001-03-01", "--end", "2001-02-01"], 2, [r"period \[2001-03-01.*2001-02-01.*empty"]),
    ("simulate-warmup-negative", ["simulate", F("bldg"), F("weather"), "--warmup-days", "-1"], 2, [r"warmup"]),
    ("simulate-warmup-absurd", ["simulate", F("bldg"), F("weather"), "--warmup-days", "100000000"], 2, [r"--warmup-days"]),
    ("simulate-out-is-file", ["simulate", F("bldg"), F("weather"), "--out", F("afile")], 2, [r"afile\.txt is a file, not a folder"]),
    # ---------------------------------------------------------------- retrofit
    ("retrofit-config-missing", ["retrofit", "nowhere.yaml"], 2, [r"nowhere\.yaml not found"]),
    ("retrofit-config-folder", ["retrofit", F("dir")], 2, [r"a_folder is a folder, not a file"]),
    ("retrofit-config-binary", ["retrofit", F("binary")], 2, [r"binary\.yaml", r"binary file|UTF-8"]),
    ("retrofit-config-latin1", ["retrofit", F("latin1")], 2, [r"latin1\.yaml", r"save the configuration file as UTF-8"]),
    ("retrofit-config-duplicate-key", ["retrofit", F("cfg_dup")], 2, [r"cfg_dup\.yaml", r"'uncertainty' appears twice"]),
    ("retrofit-config-alias-bomb", ["retrofit", F("bomb")], 2, [r"bomb\.yaml", r"aliases"]),
    ("retrofit-config-deep", ["retrofit", F("deep")], 2, [r"deep\.yaml", r"nested too deeply"]),
    ("retrofit-measurements-missing", ["retrofit", F("cfg_no_meas")], 2, [r"gone\.csv"]),
    ("retrofit-list-for-number", ["retrofit", F("cfg_days_list")], 2, [r"training_days"]),
    ("retrofit-huge-training-days", ["retrofit", F("cfg_days_huge")], 2, [r"training_days"]),
    ("retrofit-flow-unit-unknown", ["retrofit", F("cfg_flow_unit")], 2, [r"measurements\.flow_unit", r"'l/h'"]),
    ("retrofit-column-absent", ["retrofit", F("cfg_column")], 2, [r"T_inside"]),
    ("retrofit-draws-absurd", ["retrofit", F("cfg_draws")], 2, [r"draws"]),
    ("retrofit-unknown-key", ["retrofit", F("cfg_unknown")], 2, [r"measurment"]),
    ("retrofit-weather-folder", ["retrofit", F("cfg_weather")], 2, [r"a_folder"]),
    ("retrofit-building-folder", ["retrofit", F("cfg_bldg_dir")], 2, [r"a_folder is a folder"]),
    ("retrofit-building-alias-bomb", ["retrofit", F("cfg_bldg_bomb")], 2, [r"bomb\.yaml", r"aliases"]),
    ("retrofit-out-is-file", ["retrofit", F("cfg_column"), "--out", F("afile")], 2, [r"afile\.txt is a file, not a folder"]),
    # ---------------------------------------------------------------- demo
    ("demo-out-is-file", ["demo", "--out", F("afile")], 2, [r"afile\.txt is a file, not a folder"]),
    ("demo-out-foreign-folder", ["demo", "--out", ("foreign",)], 2, [r"thermocal did not write"]),
    ("demo-weather-missing", ["demo", "--weather", "nowhere.epw", "--out", ("demo",)], 2, [r"--weather nowhere\.epw", r"not found"]),
    ("demo-weather-folder", ["demo", "--weather", F("dir"), "--out", ("demo",)], 2, [r"a_folder", r"folder"]),
    ("demo-draws-negative", ["demo", "--draws", "-1", "--out", ("demo",)], 2, [r"--draws"]),
    ("demo-draws-absurd", ["demo", "--draws", "10000000", "--out", ("demo",)], 2, [r"--draws", r"at most"]),
]  # fmt: skip


@pytest.mark.parametrize(("args", "code", "patterns"), [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])  # fmt: skip
def test_bad_input(files, tmp_path, monkeypatch, capsys, args, code, patterns):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "foreign").mkdir()
    (tmp_path / "foreign" / "notes.txt").write_text("mine")
    resolved, has_out = [], False
    for arg in args:
        if isinstance(arg, tuple) and arg[0] == "file":
            resolved.append(files[arg[1]])
        elif isinstance(arg, tuple):  # (name,): a folder here; (name, key): below a file
            resolved.append(files[arg[1]] / arg[0] if len(arg) == 2 else tmp_path / arg[0])
        else:
            resolved.append(arg)
        has_out = has_out or arg == "--out"
    if not has_out:
        resolved += ["--out", "results"]
    status, message = run(resolved, capsys)
    assert "Traceback" not in message, message
    assert status == code, message
    for pattern in patterns:
        assert re.search(pattern, message), f"{pattern!r} not in: {message}"
    assert not (tmp_path / "results").exists()
    assert not (tmp_path / "demo").exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []
    assert (tmp_path / "foreign" / "notes.txt").read_text() == "mine"


def test_the_table_is_broad():
    commands = {c[1][0] for c in CASES}
    assert commands == {"fit", "simulate", "retrofit", "demo"}
    assert len(CASES) >= 60
    assert len({c[0] for c in CASES}) == len(CASES)


def test_internal_error_is_one_line_with_a_log_file(capsys, monkeypatch, tmp_path):
    """An unexpected exception: 'internal error, please report' and the log's path, exit 70."""
    import thermocal.commands.fit as fit_module

    def broken(*args, **kwargs):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(fit_module, "read_table", broken)
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    status, message = run(["fit", str(MODEL), "x.csv", "--out", str(tmp_path / "o")], capsys)
    assert status == 70
    assert "Traceback" not in message
    assert "internal error (ZeroDivisionError: float division by zero)" in message
    assert "please report" in message
    log = next(tmp_path.glob("thermocal-error-*.log"))
    assert "Traceback" in log.read_text() and "ZeroDivisionError" in log.read_text()
    assert str(log) in message
    shutil.rmtree(tmp_path / "o", ignore_errors=True)
