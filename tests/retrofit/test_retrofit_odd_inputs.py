"""Inputs a user gets slightly wrong (found by fuzzing the commands): each gets a message that
names the key and what to do, instead of a wrong number or advice that makes it worse."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements.units import _convert_units, temperature_unit_slip


def _convert(values, unit):
    return _convert_units(
        "Te", np.asarray(values, float), unit=unit, quantity=None, source="log.csv",
        column_label="Te", lines=np.arange(2, 2 + len(values)),
    )  # fmt: skip


def test_an_outdoor_temperature_in_kelvin_is_called_kelvin_not_tenths():
    """February outdoors, 281 K: before, 'look like tenths of a degree: divide by 10' (28 C)."""
    with pytest.raises(ThermocalInputError) as info:
        _convert(np.linspace(275.0, 288.0, 50), "C")
    message = str(info.value)
    assert "look like Kelvin" in message and "measurements.temperature_unit: K" in message
    assert "tenths" not in message
    # an indoor log in tenths stays tenths; a neighbour's reference still decides
    assert temperature_unit_slip(202.0)[0].startswith("tenths")
    assert temperature_unit_slip(293.0)[0] == "Kelvin?"


def test_celsius_values_declared_as_kelvin_are_named():
    """Before: 'temp_supply = -248.45 C is outside the range of liquid heating water'."""
    with pytest.raises(ThermocalInputError, match=r"declared as K but the values \(median 8\.0\)"):
        _convert(np.linspace(2.0, 14.0, 49), "K")
    values, _, canonical, _ = _convert(np.array([275.15, 281.15]), "K")
    assert canonical == "C" and values.tolist() == pytest.approx([2.0, 8.0])


def test_a_predicted_saving_written_as_a_fraction_is_refused():
    """0.35 for 35 %: before, verify compared the measured 58 % with 0.35 % and said prebound."""
    from pydantic import ValidationError

    from thermocal.retrofit.verify import PredictionConfig

    with pytest.raises(ValidationError, match="write 35 if you meant 35 %"):
        PredictionConfig(measures=["roof", "walls"], saving_pct=0.35)
    assert PredictionConfig(measures=["roof"], saving_pct=35.0).saving_pct == 35.0


def test_a_step_that_does_not_divide_an_hour_is_refused():
    """7 min on an hourly log: before, 'input Te has 1 missing values ... at 23:55' (before the
    data start)."""
    from thermocal.retrofit.data import prepare_measurements

    index = pd.date_range("2021-01-01", periods=48, freq="h", tz="UTC")
    raw = pd.DataFrame({"temp_out": 5.0, "temp_in": 20.0, "heat": 1000.0}, index=index)
    with pytest.raises(ThermocalInputError, match="'7min': does not divide an hour"):
        prepare_measurements(raw, "7min", heat_source="meter")


def _config(step: str):
    from thermocal.retrofit.config import parse_config

    return parse_config(
        {"building": "b.yaml", "measurements": {"file": "m.csv", "step": step},
         "weather": {"file": "w.epw"}},
        source="cfg.yaml",
    )  # fmt: skip


def test_a_step_above_an_hour_is_refused_by_the_configuration():
    """2h: before, the configuration passed and the analysis crashed with an internal error
    ('no data for hours [1, 3, ...] of the day', the hour-of-day indoor profile)."""
    from thermocal.retrofit.data import prepare_measurements

    with pytest.raises(ThermocalInputError) as info:
        _config("2h")
    message = str(info.value)
    assert "measurements.step = '2h': coarser than an hour" in message
    assert "hourly at most" in message and "use 1h or a divisor of it" in message
    with pytest.raises(ThermocalInputError, match="'7min': does not divide an hour"):
        _config("7min")
    with pytest.raises(ThermocalInputError, match="'fivemin': not a duration"):
        _config("fivemin")
    assert _config("1h").measurements.step == "1h"
    assert _config("15min").measurements.step == "15min"
    # the same rule where the step is applied (a caller without the configuration)
    index = pd.date_range("2021-01-01", periods=48, freq="h", tz="UTC")
    raw = pd.DataFrame({"temp_out": 5.0, "temp_in": 20.0, "heat": 1000.0}, index=index)
    with pytest.raises(ThermocalInputError, match="'2h': coarser than an hour"):
        prepare_measurements(raw, "2h", heat_source="meter")


def _log(freq: str, periods: int = 96, jitter_s: float = 0.0) -> pd.DataFrame:
    index = pd.date_range("2021-01-01", periods=periods, freq=freq, tz="UTC")
    if jitter_s:
        index = index + pd.to_timedelta(
            np.random.default_rng(0).uniform(-jitter_s, jitter_s, periods), unit="s"
        )
    raw = pd.DataFrame({"temp_out": 5.0, "temp_in": 20.0, "heat": 1000.0}, index=index)
    raw.attrs["measurements"] = {"source": "log.csv"}
    return raw


def test_a_step_finer_than_the_log_is_refused():
    """15 min on an hourly log: before, accepted, each value held over four steps, and the
    savings moved (verify demo: predicted 61.1 % -> 71.8 %, the verdict flipped; retrofit
    strategy 2a 60.5 % -> 66.2 %)."""
    from thermocal.retrofit.data import prepare_measurements

    with pytest.raises(ThermocalInputError) as info:
        prepare_measurements(_log("h"), "15min", heat_source="meter")
    message = str(info.value)
    assert "measurements.step '15min' is finer than the interval of the log log.csv (1h" in message
    assert "set measurements.step to the log's interval or coarser (1h)" in message
    with pytest.raises(ThermocalInputError, match=r"log.csv \(15min.*or coarser \(15min, 20min"):
        prepare_measurements(_log("15min"), "5min", heat_source="meter")
    # a log coarser than an hour: no step is allowed, the remedy is another log
    with pytest.raises(ThermocalInputError, match="give a log with an interval of 1 h or less"):
        prepare_measurements(_log("2h"), "1h", heat_source="meter")
    # at the log's interval or coarser: accepted, also with time stamps jittering by seconds
    assert len(prepare_measurements(_log("h"), "1h", heat_source="meter")[0]) == 96
    assert len(prepare_measurements(_log("10min"), "1h", heat_source="meter")[0]) == 16
    jittered = _log("10min", jitter_s=20.0)
    assert len(prepare_measurements(jittered, "10min", heat_source="meter")[0]) >= 95


def test_a_prediction_interval_must_surround_its_saving_in_percent():
    """Before, each was accepted and silently gave nonsense or was ignored: [0.75, 0.85] with
    80 % (fractions), a reversed interval, an interval without saving_pct (ignored: the
    method's own prediction was used), a saving outside its own interval."""
    from pydantic import ValidationError

    from thermocal.retrofit.verify import PredictionConfig

    def refused(match, **kw):
        with pytest.raises(ValidationError, match=match):
            PredictionConfig(measures=["roof", "walls"], **kw)

    refused(r"\[0.75, 0.85\] is in fractions.*write \[75, 85\] if you meant percent",
            saving_pct=80, saving_pct_interval=(0.75, 0.85))  # fmt: skip
    refused(r"\[69, 51\] is reversed.*write \[51, 69\]",
            saving_pct=61, saving_pct_interval=(69, 51))  # fmt: skip
    refused(r"\[20, 30\] without saving_pct.*give verify.prediction.saving_pct",
            saving_pct_interval=(20, 30))  # fmt: skip
    refused(r"\[35, 45\] does not contain saving_pct 30",
            saving_pct=30, saving_pct_interval=(35, 45))  # fmt: skip
    refused(r"\[40, 40\] has no width", saving_pct=40, saving_pct_interval=(40, 40))
    refused(r"between -100 and 100", saving_pct=50, saving_pct_interval=(20, 150))
    ok = PredictionConfig(measures=["roof"], saving_pct=80, saving_pct_interval=(75, 85))
    assert ok.saving_pct_interval == (75.0, 85.0)
    assert PredictionConfig(measures=["roof"], saving_pct=30, saving_pct_interval=(25, 35))
    assert PredictionConfig(measures=["roof"], saving_pct=0.0, saving_pct_interval=(-0.5, 0.5))
    # a saving written as a fraction is named once, by its own check
    with pytest.raises(ValidationError) as info:
        PredictionConfig(measures=["roof"], saving_pct=0.8, saving_pct_interval=(0.75, 0.85))
    assert info.value.error_count() == 1 and "write 80 if you meant 80 %" in str(info.value)


def test_a_prediction_interval_is_refused_with_its_key(tmp_path):
    """Through the configuration reader: the key verify.prediction.saving_pct_interval."""
    from thermocal.retrofit.verify import parse_verify_config

    data = {
        "building": "b.yaml", "measurements": {"file": "m.csv"}, "weather": {"file": "w"},
        "verify": {"retrofit_date": "2001-02-19",
                   "prediction": {"saving_pct_interval": [20, 30], "measures": ["roof"]}},
    }  # fmt: skip
    with pytest.raises(ThermocalInputError) as info:
        parse_verify_config(data, base_dir=tmp_path, source="cfg.yaml")
    message = str(info.value)
    assert "cfg.yaml" in message
    assert "verify.prediction.saving_pct_interval: [20, 30] without saving_pct" in message


@pytest.mark.parametrize(
    "beside", [{"saving_pct": 40}, {"saving_pct": 40, "saving_pct_interval": [30, 50]},
               {"measures": ["roof"]}],
)  # fmt: skip
def test_a_results_prediction_beside_another_is_refused(tmp_path, beside):
    """verify.prediction.results with saving_pct (or measures) beside it: the results file's
    strategy won and the other prediction was silently ignored (fuzzing round 3)."""
    from thermocal.retrofit.verify import parse_verify_config

    data = {
        "building": "b.yaml", "measurements": {"file": "m.csv"}, "weather": {"file": "w"},
        "verify": {"retrofit_date": "2001-02-19",
                   "prediction": {"results": "results.json", "strategy": "2a", **beside}},
    }  # fmt: skip
    with pytest.raises(ThermocalInputError) as info:
        parse_verify_config(data, base_dir=tmp_path, source="cfg.yaml")
    message = str(info.value)
    key = next(iter(beside))
    assert "cfg.yaml" in message and f"verify.prediction.{key} are two predictions" in message


def test_a_training_start_outside_the_measurements_is_named():
    """Before: 'the measurements from 2005-01-01 cover -1387.0 days'."""
    from types import SimpleNamespace

    from thermocal.retrofit.workflow import _periods

    index = pd.date_range("2001-02-02", periods=24 * 42, freq="h", tz="Etc/GMT+5")
    grid = pd.DataFrame({"Te": 0.0}, index=index)

    def cfg(start):
        periods = SimpleNamespace(training_start=start, training_days=21, test_days=14)
        return SimpleNamespace(periods=periods)

    with pytest.raises(ThermocalInputError, match="training_start 2005-01-01.* is outside the"):
        _periods(grid, cfg("2005-01-01"), "log.csv")
    train, test, _ = _periods(grid, cfg("2001-02-05"), "log.csv")
    assert train[0] == pd.Timestamp("2001-02-05", tz="Etc/GMT+5") and test is not None


def test_ventilation_measures_beyond_the_houses_air_change_loss_are_refused():
    """Before: -0.6, -1.5 and -2.9 1/h gave the same saving (the loss clipped at zero) and the
    measure was recommended."""
    from thermocal.retrofit.model import check_ventilation_measures
    from thermocal.retrofit.strategies import Measure, Strategy

    tighter = Measure(name="tighter", component="airtightness", air_change_rate_change=-1.5)
    hr = Measure(
        name="hr", component="heat_recovery", heat_recovery_air_change_rate=0.4,
        heat_recovery_efficiency=0.8,
    )  # fmt: skip
    measures = {"tighter": tighter, "hr": hr}
    with pytest.raises(ThermocalInputError, match=r"measures.tighter: .* about 0\.42 1/h"):
        check_ventilation_measures([Strategy("1", ("tighter",))], measures, 624.0, 87.0)
    # tightening within the loss and heat recovery together: kept (a deep-retrofit package),
    # clipped at zero as before, and said
    small = {"tighter": Measure(name="tighter", component="airtightness",
                                air_change_rate_change=-0.2), "hr": hr}  # fmt: skip
    strategies = [Strategy("2", ("hr",)), Strategy("3", ("tighter", "hr"))]
    notes = check_ventilation_measures(strategies, small, 624.0, 87.0)
    assert len(notes) == 1 and notes[0].startswith("strategy 3:"), notes


@pytest.mark.parametrize(
    ("section", "words"),
    [
        ({"measures": {"t": {"component": "airtightness", "air_change_rate_change": 0.3}}},
         "makes the envelope leakier"),
        ({"economics": {"energy_price": 12}}, "in cents\\? write 0.12"),
        ({"economics": {"emission_factor": 310}}, "in g/kWh\\? write 0.31"),
        ({"uncertainty": {"draws": 1}}, "1 draws give no 90 % interval"),
        ({"internal_gains": {"source": "constant", "constant_W": 0.4}}, "in kW\\? then write 400"),
        ({"internal_gains": {"source": "none", "constant_W": 400}}, "would be ignored"),
    ],
)  # fmt: skip
def test_configuration_values_in_another_unit_or_ignored_are_refused(tmp_path, section, words):
    """Before: a leakier 'measure' was a strategy of -15 %, a price in cents made every payback
    0 years, g/kWh put 9,000 t of CO2 on a house, 1 draw printed a '90 % interval' without the
    estimate, gains in kW were 0.4 W, and constant_W under source: none was dropped."""
    import yaml

    from thermocal.demos.retrofit import prepare_demo
    from thermocal.retrofit import load_config

    path, _ = prepare_demo(tmp_path)
    config = yaml.safe_load(path.read_text())
    for key, value in section.items():
        config[key] = {**config.get(key, {}), **value} if key != "measures" else value
    path.write_text(yaml.safe_dump(config))
    with pytest.raises(ThermocalInputError, match=words):
        load_config(path)


def test_the_advice_says_when_a_plate_would_widen_the_intervals():
    """A tiny configuration's advice table offered 'walls 3.7 -> 6.2 pp' without a word."""
    from thermocal.retrofit.advice import ComponentAdvice, advice_summary

    def advice(component, now, expected):
        return ComponentAdvice(
            component=component, where=component, described_u=1.0, expected_u=1.0,
            reading_rel_std=0.15, median_half_width_pp=now,
            expected_median_half_width_pp=expected, recommended_half_width_pp=now,
            expected_recommended_half_width_pp=expected, half_widths_pp={}, seconds=1.0,
        )  # fmt: skip

    rows = [advice("roof", 3.7, 2.8), advice("cellar_ceiling", 3.7, 3.7), advice("walls", 3.7, 6.2)]
    text = advice_summary(rows, 0.26, 0.071, {"passed": True})
    assert text.startswith("A heat-flux plate on the roof would narrow")
    assert "A heat-flux plate on the walls would widen them (3.7 -> 6.2 pp" in text
    assert "not a measurement to make" in text
    quiet = advice_summary(rows[:2], 0.26, 0.071, {"passed": True})
    assert "widen" not in quiet


def test_the_demo_measures_in_the_heating_season_of_its_weathers_hemisphere(shared_data, tmp_path):
    """Before: a southern-hemisphere weather file put the demo's measured weeks in summer (the
    indoor profile of a hot February became the heating set point: demand x2, a gate failure
    blamed on the building); a tropical one ran to the same end."""
    from thermocal.demos.retrofit import PERIOD, SOUTHERN_PERIOD, demo_period, generate_demo_data

    assert demo_period(47.4) == PERIOD and demo_period(-37.8) == SOUTHERN_PERIOD
    source = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    lines = source.read_text().splitlines()
    for i in range(8, len(lines)):
        fields = lines[i].split(",")
        fields[6] = f"{float(fields[6]) + 26.0:.1f}"  # a tropical year
        fields[7] = f"{float(fields[7]) + 26.0:.1f}"
        lines[i] = ",".join(fields)
    path = tmp_path / "tropic.epw"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ThermocalInputError, match=r"outdoors, no heating season"):
        generate_demo_data(path)


@pytest.mark.parametrize(
    ("strategies", "words"),
    [
        ({}, "no strategy besides '0'"),
        ({"0": []}, "no strategy besides '0'"),
        ({"a": []}, "lists no measure"),
        ({"a": ["roof"], "b": ["roof"]}, "the same measures as strategy 'a'"),
    ],
)
def test_strategy_lists_that_analyse_nothing_new_are_refused(strategies, words):
    """Before: {} ran the house as it is alone, {a: []} repeated it, two equal lists gave two
    identical rows."""
    from thermocal.retrofit.strategies import Measure, listed_strategies

    measures = {"roof": Measure(name="roof", component="roof", u_value=0.2)}
    with pytest.raises(ValueError, match=words):
        listed_strategies(strategies, measures)


def test_odd_indoor_profile_gets_no_meaningless_unit_hint():
    """200 was answered 'Kelvin? write -73.15'."""
    from pydantic import ValidationError

    from thermocal.retrofit.config import DemandConfig

    with pytest.raises(ValidationError) as info:
        DemandConfig(indoor_profile=200)
    assert "Kelvin" not in str(info.value) and "not an indoor temperature" in str(info.value)
    with pytest.raises(ValidationError, match=r"Kelvin\? write 20.00"):
        DemandConfig(indoor_profile=293.15)


def test_review_fixes_keep_valid_input_valid():
    """A training start on the log's first day before its first row (was refused by the new
    range check); a nominal on the model's own limit (a window U of 10: was 'a fraction ...
    exceeds 1'); a price per MWh gets the per-MWh hint."""
    from types import SimpleNamespace

    from thermocal.calibration.space import ParameterSpace
    from thermocal.retrofit.config import EconomicsConfig
    from thermocal.retrofit.workflow import _periods

    index = pd.date_range("2001-02-02 08:00", periods=24 * 42, freq="h", tz="Etc/GMT+5")
    periods = SimpleNamespace(training_start="2001-02-02", training_days=21, test_days=14)
    train, _, _ = _periods(pd.DataFrame({"Te": 0.0}, index=index), SimpleNamespace(
        periods=periods), "log.csv")  # fmt: skip
    assert train[0] == pd.Timestamp("2001-02-02", tz="Etc/GMT+5")
    space = ParameterSpace.from_parameters({"window/w/u_value": 10.0, "window/w/shgc": 1.0})
    assert space.upper.tolist() == [10.0, 1.0]
    with pytest.raises(ValueError, match=r"per MWh\? write 0.095"):
        EconomicsConfig(currency="EUR", energy_price=95.0)


def test_a_missing_semicolon_names_the_class_not_a_zone_written_like_one():
    """A DesignBuilder zone 'Block1:Office' was named as the swallowed object."""
    from thermocal.multizone.idf import parse_idf, record

    for end in (",", ""):  # the ';' replaced by a comma, or deleted
        text = (
            "Lights, L1, Block1:Office, Always, LightingLevel, 100, , , 0, 0.2, 0.2, 1, General, "
            f"No{end}\nElectricEquipment, E1, Block1:Office, Always, EquipmentLevel, 200;"
        )
        with pytest.raises(ThermocalInputError, match=r"is 'ElectricEquipment': the ';'"):
            record(parse_idf(text)[0])


def test_no_draws_give_no_interval_rather_than_one_of_zero_width(tmp_path):
    """uncertainty.draws: 0 asks for no uncertainty analysis. Before, the console, the report
    and results.json gave the estimate as its own 90 % interval ('saves about 25 % of the heat
    (90 % interval 25 to 25 %)', '19–19'), which reads as certainty."""
    import json
    import re

    from typer.testing import CliRunner

    from thermocal.cli import app

    out = tmp_path / "demo"
    result = CliRunner().invoke(app, ["demo", "--out", str(out), "--draws", "0"])
    assert result.exit_code == 0, result.output
    results = json.loads((out / "results.json").read_text())
    demand = results["annual_heating_demand_kWh"]
    assert [demand[k] for k in ("p05", "p95", "monthly_p05", "monthly_p95")] == [None] * 4
    for row in results["scenarios"]:
        ends = [row[k] for k in ("annual_kWh_p05", "annual_kWh_p95", "saving_pct_p05",
                                 "saving_pct_p95")]  # fmt: skip
        assert ends == [None] * 4, row
        assert row["economics"]["payback_years_lo"] is None
        assert row["economics"]["cost_saving_per_year_hi"] is None
    for row in results["reference_check"]["strategies"]:
        assert row["model_saving_pct_p05"] is None and row["model_kWh_p95"] is None
    # the console: the demand says so, the strategy table has no interval column
    said = f"annual heating demand {demand['value']:,.0f} kWh, no interval (uncertainty.draws: 0)"
    assert said in result.output
    rows = {line.split()[0]: line for line in result.output.splitlines() if line.strip()}
    one = results["scenarios"][1]
    shown = ["1a", "R", f"{one['annual_kWh']:,.0f}", f"{one['saving_pct']:.1f}"]
    assert rows["1a"].split()[:4] == shown and "–" not in rows["1a"]
    # the report: one note, no interval of zero width anywhere, sentences without one
    text = re.sub(r"<[^>]+>", " ", (out / "report.html").read_text())
    assert "Demands, savings and paybacks: no interval (uncertainty.draws: 0)." in text
    assert not re.search(r"\b(\d[\d,.]*) (?:to|–) \1\b", text)
    assert re.search(r"saves about \d+ % of the heat, about", text)
    # the heat loss coefficient keeps its interval: the calibration's own, not the draws'
    hlc = results["heat_loss_coefficient_W_per_K"]
    assert hlc["p05"] < hlc["value"] < hlc["p95"]


def test_advice_without_draws_is_refused_before_anything_runs(tmp_path):
    """--advise compares the widths of the savings' intervals; uncertainty.draws: 0 asks for
    none. Before, the demo ran 10 analyses at 1,000 draws to advise on intervals its report
    did not show."""
    import yaml
    from typer.testing import CliRunner

    from thermocal.cli import app
    from thermocal.demos.retrofit import prepare_demo

    out = tmp_path / "demo"
    result = CliRunner().invoke(app, ["demo", "--out", str(out), "--draws", "0", "--advise"])
    assert isinstance(result.exception, ThermocalInputError)
    message = str(result.exception)
    assert "--advise compares the widths of the savings' intervals, but --draws 0" in message
    assert "give --draws 200" in message and not out.exists()
    path, _ = prepare_demo(tmp_path / "own", draws=200)
    config = yaml.safe_load(path.read_text())
    config["uncertainty"]["draws"] = 0
    path.write_text(yaml.safe_dump(config))
    args = ["retrofit", str(path), "--advise", "--out", str(tmp_path / "r")]
    result = CliRunner().invoke(app, args)
    assert isinstance(result.exception, ThermocalInputError)
    assert f"uncertainty.draws: 0 in {path} asks for none" in str(result.exception)
    assert not (tmp_path / "r").exists()


def test_an_impossible_date_in_the_periods_is_refused_with_its_key(tmp_path):
    """Review: YAML keeps an unquoted impossible date (2005-02-30) as text; the configuration
    took it and the analysis stopped later with an internal error (DateParseError)."""
    from thermocal.demos.retrofit import prepare_demo
    from thermocal.retrofit import load_config

    path, _ = prepare_demo(tmp_path)
    text = path.read_text()
    assert "\nperiods:\n" in text  # a block mapping: the date goes in as its first key
    path.write_text(text.replace("\nperiods:\n", "\nperiods:\n  training_start: 2005-02-30\n", 1))
    with pytest.raises(ThermocalInputError, match=r"training_start.*'2005-02-30' is not a date"):
        load_config(path)


def _measurements(**keys) -> dict:
    from thermocal.retrofit.config import parse_config

    return parse_config(
        {"building": "b.yaml", "measurements": {"file": "m.csv", **keys},
         "weather": {"file": "w.epw"}},
        source="cfg.yaml",
    )  # fmt: skip


def test_a_heat_meter_beside_the_hydronic_heat_source_is_refused():
    """Fuzzing r07: ``columns.heat`` and ``heat_unit: kWh`` under the default
    ``heat_source: hydronic`` were ignored without a word (the results equal the flow's), and
    a user with a flow sensor and a heat meter believed the meter was used."""
    with pytest.raises(ThermocalInputError, match=(
        r"measurements: columns\.heat \('Q_kW'\) and heat_unit \('kWh'\): a heat or fuel "
        r"meter's keys, but heat_source is 'hydronic' .* or remove columns\.heat and heat_unit"
    )):  # fmt: skip
        _measurements(columns={"heat": "Q_kW"}, heat_unit="kWh")
    with pytest.raises(ThermocalInputError, match="heat_cumulative: a heat or fuel meter's key"):
        _measurements(heat_cumulative=True)
    # the example configuration's heat_unit: kW (the default) and a meter that is used pass
    _measurements(heat_unit="kW", heat_cumulative=False)
    _measurements(heat_source="heat_meter", columns={"heat": "Q_kW"}, heat_unit="kWh")


@pytest.mark.parametrize(
    ("measurements", "economics", "words"),
    [
        ({"heat_unit": "m3", "fuel_kWh_per_unit": 37.8}, {},
         r"37\.8 kWh per m3 is no fuel gas's .*looks like MJ/m3: divide by 3\.6 and write 10\.5"),
        ({"heat_unit": "l", "fuel_kWh_per_unit": 36.0}, {},
         r"36 kWh per l is no liquid fuel's .*looks like MJ/l: divide by 3\.6 and write 10$"),
        ({"heat_unit": "m3", "fuel_kWh_per_unit": 20.0}, {"energy_carrier": "natural gas"},
         r"20 kWh per m3 is not natural gas's \(economics\.energy_carrier: 8-12\.5 kWh/m3\)"),
    ],
)  # fmt: skip
def test_a_fuels_energy_per_unit_in_megajoules_is_refused(measurements, economics, words):
    """Fuzzing v35: ``fuel_kWh_per_unit: 37.8`` (natural gas in MJ/m3) was accepted; verify
    then gave an HLC of 1,245 instead of 578 W/K and blamed ASHRAE Guideline 14 alone."""
    from thermocal.retrofit.config import parse_config

    fuel = {"file": "m.csv", "heat_source": "fuel_meter", "columns": {"heat": "fuel"},
            "boiler_efficiency": 0.9, **measurements}  # fmt: skip
    config = {"building": "b.yaml", "measurements": fuel, "weather": {"file": "w.epw"}}
    with pytest.raises(ThermocalInputError, match=words):
        parse_config({**config, "economics": economics}, source="cfg.yaml")
    # the fuels of those units, in kWh, pass: natural gas, propane without a carrier, LPG, oil
    for unit, value in (("m3", 10.5), ("m3", 26.0), ("l", 7.0), ("l", 10.0)):
        ok = {**fuel, "heat_unit": unit, "fuel_kWh_per_unit": value}
        parse_config({**config, "measurements": ok}, source="cfg.yaml")


def test_internal_gains_beyond_a_homes_per_floor_area_are_refused(tmp_path):
    """Fuzzing r12: ``constant_W: 40000`` (182 W per m2 of heated floor) was accepted; the
    calibration failed its validation (bias +16 K) and the summary crashed (below)."""
    import yaml
    from retrofit_synthetic import building_dict

    from thermocal.retrofit.config import parse_config
    from thermocal.retrofit.workflow import run_retrofit

    building = building_dict()
    (tmp_path / "b.yaml").write_text(yaml.safe_dump(building))
    area = float(building["heated_floor_area"])
    for gains, words in (
        ({"source": "constant", "constant_W": 200.0 * area},
         rf"internal_gains\.constant_W: {200 * area:,.0f} W is 200 W per m2 of heated floor"),
        ({"source": "schedule", "schedule_W": [150.0 * area] * 24},
         r"internal_gains\.schedule_W: .* W on average is 150 W per m2"),
    ):  # fmt: skip
        cfg = parse_config(
            {"building": "b.yaml", "measurements": {"file": "missing.csv"},
             "weather": {"file": "missing.epw"}, "internal_gains": gains},
            base_dir=tmp_path, source="cfg.yaml",
        )  # fmt: skip
        with pytest.raises(ThermocalInputError, match=words):
            run_retrofit(cfg)  # refused before the measurements are read


def test_internal_gains_beyond_a_home_are_refused_with_the_detailed_model_alone(tmp_path):
    """Review of fuzz round 5: the gains limit ran in ``run_retrofit`` only; ``--detailed-only``
    with a building file beside ``constant_W: 40000`` went on without a word. The check lives
    in ``gains.check_configured_gains`` and runs wherever the building file is read."""
    import yaml
    from retrofit_synthetic import building_dict
    from typer.testing import CliRunner

    from thermocal.cli import app

    building = building_dict()
    (tmp_path / "b.yaml").write_text(yaml.safe_dump(building))
    cfg = {"building": "b.yaml", "weather": {"file": "w.epw"},
           "internal_gains": {"source": "constant", "constant_W": 40000}}  # fmt: skip
    (tmp_path / "cfg.yaml").write_text(yaml.safe_dump(cfg))
    args = ["retrofit", str(tmp_path / "cfg.yaml"), "--detailed-only", "--detailed",
            str(tmp_path / "missing.idf"), "--out", str(tmp_path / "out")]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert isinstance(result.exception, ThermocalInputError), result.output
    assert str(result.exception).startswith("internal_gains.constant_W: 40,000 W is ")
    # without a building file there is no floor to compare with (the detailed model does not
    # use the configuration's gains): the run goes on to the detailed building
    del cfg["building"]
    (tmp_path / "cfg.yaml").write_text(yaml.safe_dump(cfg))
    result = CliRunner().invoke(app, args)
    assert "missing.idf not found" in str(result.exception), result.exception


def test_the_summary_shows_a_missing_interval_end_as_na(capsys, tmp_path):
    """Fuzzing r12: a failed calibration whose draws left no demand to save from gave null
    interval ends in results.json, and the terminal summary crashed on them (TypeError in
    ``print_summary``, exit 70) after the outputs were written."""
    from thermocal.commands.retrofit import print_summary

    scenario = {"code": "0", "measures": [], "annual_kWh": 2294.0, "saving_pct": 0.0,
                "saving_pct_p05": 0.0, "saving_pct_p95": 0.0, "saving_pct_mcse": 0.0,
                "economics": {"investment": 0.0, "cost_saving_per_year": 0.0}}  # fmt: skip
    results = {
        "heat_loss_coefficient_W_per_K": {"value": 1859.0, "std": 122.0, "p05": 1478.0,
                                          "p95": 1871.0},
        "annual_heating_demand_kWh": {"value": 2294.0, "p05": 0.0, "p95": 5244.0},
        "validation": {},
        "scenarios": [scenario, {**scenario, "code": "1a", "measures": ["roof"],
                                 "annual_kWh": 57.6, "saving_pct": 97.5, "saving_pct_p05": None,
                                 "saving_pct_p95": None}],
        "economics": {"currency": "CHF"},
        "calibration": {"flags": []},
    }  # fmt: skip
    print_summary(results, tmp_path)
    rows = {line.split()[0]: line.split() for line in capsys.readouterr().out.splitlines()
            if line.strip()}  # fmt: skip
    assert rows["1a"][:5] == ["1a", "R", "58", "97.5", "n/a"]
    assert rows["0"][:5] == ["0", "none", "2,294", "0.0", "0–0"]
