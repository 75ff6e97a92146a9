"""An IDF's RunPeriod dated as EnergyPlus dates it: its End Year, a period that crosses new year
and an end on 29 February of a common year (``thermocal simulate`` without --start/--end)."""

from __future__ import annotations

import datetime as dt
import json
import re

import pandas as pd
import pytest
from typer.testing import CliRunner

from thermocal.cli import app
from thermocal.errors import ThermocalInputError
from thermocal.multizone.idf.site import RunPeriod, run_period_dates

WHERE = "RunPeriod 'R' (box.idf line 9)"


def _period(begin, end, begin_year=None, end_year=None) -> RunPeriod:
    return RunPeriod("R", *begin, *end, begin_year, end_year, WHERE)


@pytest.mark.parametrize(
    ("period", "weather_year", "dates"),
    [
        # the fuzzed file: 12/1/2009 to 1/31/2010 with both years (was "ends before it starts")
        (_period((12, 1), (1, 31), 2009, 2010), 2009, ("2009-12-01", "2010-01-31")),
        # blank years: an end before the begin in the year is in the next year (EnergyPlus)
        (_period((12, 1), (1, 31)), 2023, ("2023-12-01", "2024-01-31")),
        (_period((12, 1), (1, 31), 2009), 2009, ("2009-12-01", "2010-01-31")),
        (_period((1, 1), (12, 31), 2009, 2009), 2009, ("2009-01-01", "2009-12-31")),
        (_period((2, 1), (2, 29)), 2016, ("2016-02-01", "2016-02-29")),  # a leap weather year
        (_period((3, 1), (2, 29)), 2015, ("2015-03-01", "2016-02-29")),  # ends in a leap year
    ],
)
def test_run_period_dates_as_energyplus(period, weather_year, dates):
    begin, last, notes = run_period_dates(period, weather_year)
    assert (str(begin), str(last)) == dates
    assert notes == []


def test_an_end_on_february_29_of_a_common_year_ends_with_february_noted():
    """Blank years on a common weather year: before, an internal error (DateParseError:
    2023-02-29); now the end of February, 2/28 inclusive, with a note naming the RunPeriod."""
    begin, last, notes = run_period_dates(_period((2, 1), (2, 29)), 2023)
    assert (begin, last) == (dt.date(2023, 2, 1), dt.date(2023, 2, 28))
    assert len(notes) == 1 and notes[0].startswith(WHERE), notes
    assert "2/29 does not exist in 2023" in notes[0] and "ends on 2/28" in notes[0]


@pytest.mark.parametrize(
    ("period", "message"),
    [
        (_period((2, 1), (2, 29), 2023, 2023), r"field 'End Year' = 2023 is a common year.*2/29"),
        (_period((2, 29), (3, 31)), r"begin date 2/29 does not exist in 2023 .*'Begin Year' is bl"),
        (_period((2, 29), (3, 31), 2023), r"2/29 does not exist in 2023 .field 'Begin Year'"),
        (_period((3, 1), (2, 1), 2009, 2009), r"end on 2009-02-01 .* before it begins on 2009-03"),
        (_period((13, 1), (12, 31)), r"'Begin Month' = 13 and 'Begin Day of Month' = 1 are not a"),
        (_period((1, 1), (4, 31)), r"'End Month' = 4 and 'End Day of Month' = 31 are not a date"),
    ],
)
def test_run_periods_that_are_no_period_are_refused_by_their_fields(period, message):
    with pytest.raises(ThermocalInputError, match=message) as info:
        run_period_dates(period, 2023)
    assert str(info.value).startswith(WHERE)


def _case_600(shared_data, tmp_path, fields: str, name: str = "rp.idf"):
    """Case 600 of ASHRAE 140 (EnergyPlus 25.2) with its RunPeriod's Begin Month to Day of
    Week for Start Day replaced by ``fields`` (comma-separated)."""
    text = shared_data("energyplus_reference", "case_600_v25.idf").read_text()
    head, rest = text.split("RunPeriod,\n", 1)
    lines = rest.split("\n")
    new = [f"  {value},  !- field" for value in fields.split(",")]
    path = tmp_path / name
    path.write_text(head + "RunPeriod,\n" + "\n".join([lines[0], *new, *lines[8:]]))
    return path


def _simulate(building, weather, out):
    return CliRunner().invoke(
        app, ["simulate", str(building), str(weather), "--step", "1h", "--out", str(out)]
    )


def test_the_run_period_reads_its_end_year(shared_data, tmp_path):
    from thermocal.multizone.files import load_building
    from thermocal.multizone.idf import IdfImportWarning

    with pytest.warns(IdfImportWarning):  # Case 600's ideal loads: not this test's matter
        building = load_building(_case_600(shared_data, tmp_path, "12,1,2009,1,31,2010,"))
    period = building.idf_info.run_period
    assert (period.begin_year, period.end_year) == (2009, 2010)
    assert re.fullmatch(r"RunPeriod 'Run Period 1' \(rp.idf line \d+\)", period.where)


def test_simulate_runs_a_period_across_new_year_on_a_typical_year(shared_data, tmp_path):
    """12/1/2009 to 1/31/2010 with the years given (and with them blank) on Denver's TMY3:
    before, refused as "period [2009-12-01, 2009-02-01) is empty"; now December and January,
    the typical year repeated in January."""
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    for fields, first, last in [
        ("12,1,2009,1,31,2010,", "2009-12-01 00:00", "2010-01-31 23:00"),
        ("12,1,,1,31,,", "2023-12-01 00:00", "2024-01-31 23:00"),  # the TMY's year: 2023
    ]:
        out = tmp_path / f"out{first[:4]}"
        result = _simulate(_case_600(shared_data, tmp_path, fields), weather, out)
        assert result.exit_code == 0, (fields, result.output, result.exception)
        times = pd.read_csv(out / "zone_heat_flows.csv")["time"]  # step starts
        assert (times.iloc[0][:16], times.iloc[-1][:16], len(times)) == (first, last, 62 * 24)
        notes = json.loads((out / "summary.json").read_text())["approximations"]
        assert any("crosses new year: the typical-year weather repeats" in n for n in notes)


def test_simulate_says_when_an_actual_year_weather_cannot_cover_a_new_year_period(
    shared_data, tmp_path
):
    weather = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    result = _simulate(_case_600(shared_data, tmp_path, "12,1,,1,31,,"), weather, tmp_path / "o")
    assert isinstance(result.exception, ThermocalInputError), result.output
    text = str(result.exception)
    assert "RunPeriod 'Run Period 1' crosses new year" in text and "2016-01-31" in text, text
    assert "actual-year file" in text and "Zuerich-SMA_2015.epw" in text
    assert "ends before it starts" not in text and "truncated" not in text


def test_simulate_ends_a_february_29_run_period_of_a_common_year_on_february_28(
    shared_data, tmp_path
):
    """The fuzzed file (2/1 to 2/29, blank years) on a common typical year: before, an internal
    error; now February to the 28th, noted in summary.json; with a common End Year given,
    refused naming the field (EnergyPlus refuses it too)."""
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    out = tmp_path / "feb"
    result = _simulate(_case_600(shared_data, tmp_path, "2,1,,2,29,,"), weather, out)
    assert result.exit_code == 0, (result.output, result.exception)
    times = pd.read_csv(out / "zone_heat_flows.csv")["time"]  # step starts
    assert times.iloc[-1].startswith("2023-02-28 23:00") and len(times) == 28 * 24
    notes = json.loads((out / "summary.json").read_text())["approximations"]
    assert any("2/29 does not exist in 2023" in n and "ends on 2/28" in n for n in notes), notes
    given = _case_600(shared_data, tmp_path, "2,1,,2,29,2023,", name="given.idf")
    result = _simulate(given, weather, tmp_path / "given")
    assert isinstance(result.exception, ThermocalInputError), result.output
    assert "field 'End Year' = 2023 is a common year" in str(result.exception)


def test_a_zone_multiplier_counts_in_the_building_totals(shared_data, tmp_path):
    """Case 600 with its zone's Multiplier at 3: the zone's own rows are one zone's, as
    EnergyPlus reports zone variables; the building's totals count it three times, as
    EnergyPlus' facility totals do (they were one zone's, a third of EnergyPlus', with only
    "1 other" among the console's import notes; exploratory test, 2026-11-30)."""
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    text = _case_600(shared_data, tmp_path, "1,1,,1,14,,").read_text()
    once = tmp_path / "once.idf"
    once.write_text(text)
    zone_head = text.index("Zone,")
    marker = "  1,                                    !- Multiplier"
    at = text.index(marker, zone_head)
    thrice = tmp_path / "thrice.idf"
    thrice.write_text(text[:at] + marker.replace("1,", "3,", 1) + text[at + len(marker):])
    runs = {}
    for path in (once, thrice):
        result = _simulate(path, weather, tmp_path / path.stem)
        assert result.exit_code == 0, (result.output, result.exception)
        runs[path.stem] = (json.loads((tmp_path / path.stem / "summary.json").read_text()),
                           result.output)  # fmt: skip
    (one, _), (three, printed) = runs["once"], runs["thrice"]
    zone = next(iter(one["zones"]))
    assert three["zones"][zone]["heating_kWh"] == pytest.approx(one["zones"][zone]["heating_kWh"])
    assert three["building"]["heating_kWh"] == pytest.approx(3 * one["building"]["heating_kWh"])
    assert three["building"]["zone_multipliers"] == {zone: 3.0}
    assert "zone multipliers counted in the building's totals" in " ".join(printed.split())


def test_ideal_loads_settings_the_model_does_not_apply_are_named(shared_data, tmp_path):
    """Case 600 with its ideal-loads system always off (EnergyPlus: a free float, 0 kWh) or
    limited to 1 kW of heating (3,024 kWh against the unlimited 4,244). Both were silent, and
    heated and cooled at the set points (exploratory test, 2026-11-30). A system never
    available now leaves its zone without that set point (0 kWh, as EnergyPlus); a limit, or
    an availability for part of the year, is named in full in the import warning."""
    from thermocal.multizone.files import load_building
    from thermocal.multizone.idf import IdfImportWarning
    from thermocal.multizone.idf.report import import_summary

    text = shared_data("energyplus_reference", "case_600_v25.idf").read_text()
    field = "  ,                                     !- Availability Schedule Name"
    assert field in text
    cases = {
        "off": text.replace(field, "  AlwaysOffSch,  !- Availability Schedule Name", 1)
        + "\nSchedule:Constant, AlwaysOffSch, , 0;\n",
        "limited": text.replace(
            "  ,                                     !- Heating Limit",
            "  LimitCapacity,  !- Heating Limit", 1,
        ).replace(
            "  ,                                     !- Maximum Sensible Heating Capacity {W}",
            "  1000,  !- Maximum Sensible Heating Capacity {W}", 1,
        ),
        "plain": text,
    }
    found = {}
    for name, content in cases.items():
        path = tmp_path / f"{name}.idf"
        path.write_text(content)
        with pytest.warns(IdfImportWarning):
            building = load_building(path)
        found[name] = [n for n in building.idf_info.notes if n.startswith("Ideal loads")]
        if found[name]:
            assert found[name][0] in import_summary(path.name, building.idf_info)
    assert found["plain"] == []
    # never available: applied, the zone floats as in EnergyPlus (0 kWh both ways)
    assert found["off"] == [found["off"][0]] and "settings applied" in found["off"][0]
    assert "never available for heating and cooling" in found["off"][0]
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    result = _simulate(tmp_path / "off.idf", weather, tmp_path / "off_out")
    assert result.exit_code == 0, (result.output, result.exception)
    totals = json.loads((tmp_path / "off_out" / "summary.json").read_text())["building"]
    assert totals["heating_kWh"] == 0.0 and totals["cooling_kWh"] == 0.0
    # a limit is not applied: said in full
    assert "Heating Limit 'LimitCapacity' (capacity W 1000)" in found["limited"][0]
    assert "unlimited and always available" in found["limited"][0]


def test_temperature_rows_are_stamped_with_their_instant(shared_data, tmp_path):
    """zone_temperatures holds each step's end state, stamped with that instant (as a logger and
    EnergyPlus stamp it); zone_heat_flows holds each step's mean, stamped with its start. Fed
    back to identify as a sensor log, start stamps had put every thermostat step one step early
    (heat spikes of 1-2 kW at each; exploratory test, 2026-11-30)."""
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    out = tmp_path / "stamps"
    result = _simulate(_case_600(shared_data, tmp_path, "1,1,,1,2,,"), weather, out)
    assert result.exit_code == 0, (result.output, result.exception)
    temps = pd.read_csv(out / "zone_temperatures.csv")["time"]
    flows = pd.read_csv(out / "zone_heat_flows.csv")["time"]
    assert flows.iloc[0].startswith("2023-01-01 00:00")
    assert temps.iloc[0].startswith("2023-01-01 01:00")
    assert temps.iloc[-1].startswith("2023-01-03 00:00") and len(temps) == len(flows) == 48


def test_start_and_end_take_a_typical_year_to_their_year(shared_data, tmp_path):
    """Case 600's RunPeriod begins in 2009 and runs there by default; --start 2009-06-01 was
    refused as outside the weather ("the weather runs in 2023"), which forced another calendar
    (exploratory test, 2026-11-30). A typical year now takes the year the period asks for."""
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    idf = shared_data("energyplus_reference", "case_600_v25.idf")
    for year in (2009, 2023):
        out = tmp_path / str(year)
        result = CliRunner().invoke(app, [
            "simulate", str(idf), str(weather), "--step", "1h", "--start", f"{year}-06-01",
            "--end", f"{year}-06-03", "--out", str(out),
        ])  # fmt: skip
        assert result.exit_code == 0, (result.output, result.exception)
        times = pd.read_csv(out / "zone_heat_flows.csv")["time"]
        assert times.iloc[0].startswith(f"{year}-06-01 00:00") and len(times) == 48


def test_start_keeps_an_actual_year_weather_file_in_its_own_year(shared_data, tmp_path):
    """--start in another year than an actual-year file's is refused as before (the period's
    year was forced onto every weather file: Zurich 2015 ran silently as 2021; review of
    2026-11-30); inside its year it runs."""
    weather = shared_data("weather_switzerland", "Zuerich-SMA_2015.epw")
    idf = shared_data("energyplus_reference", "case_600_v25.idf")

    def run(start, end, name):
        return CliRunner().invoke(app, [
            "simulate", str(idf), str(weather), "--step", "1h", "--start", start, "--end", end,
            "--out", str(tmp_path / name),
        ])  # fmt: skip

    refused = run("2021-01-05", "2021-01-07", "y2021")
    assert refused.exit_code != 0 and "2015" in str(refused.exception) + refused.output
    inside = run("2015-01-05", "2015-01-07", "y2015")
    assert inside.exit_code == 0, (inside.output, inside.exception)


def test_ideal_loads_fields_of_a_file_before_energyplus_8_8():
    """EnergyPlus 8.8 added the System Inlet Air Node Name: an 8.5 file's later fields sit
    one position earlier (its cooling availability was read as the heating one, and the
    dehumidification control type as a schedule; review of 2026-11-30)."""
    from types import SimpleNamespace

    from thermocal.multizone.idf.hvac import ideal_loads_records

    fields_85 = ["Ideal", "", "N3", "N2", "", "", "0.01", "0.01", "", "", "", "", "", "",
                 "", "AlwaysOff", "ConstantSupplyHumidityRatio"]  # fmt: skip
    obj = SimpleNamespace(fields=fields_85)
    (rec,) = ideal_loads_records({"ZONEHVAC:IDEALLOADSAIRSYSTEM": [obj]}, (8, 5))
    assert rec["heating_availability_schedule_name"] == ""
    assert rec["cooling_availability_schedule_name"] == "AlwaysOff"
    (new,) = ideal_loads_records({"ZONEHVAC:IDEALLOADSAIRSYSTEM": [obj]}, (25, 2))
    assert new["heating_availability_schedule_name"] == "AlwaysOff"


def test_run_periods_energyplus_would_run_and_simulate_does_not_are_named(shared_data, tmp_path):
    """A second RunPeriod (NREL's test files often give January and July) was dropped without a
    word, as was a SimulationControl that runs only the design days (exploratory test,
    2026-11-30): both are now named in the import warning."""
    from thermocal.multizone.files import load_building
    from thermocal.multizone.idf import IdfImportWarning

    path = _case_600(shared_data, tmp_path, "1,1,2009,1,31,2009,Thursday", name="two.idf")
    runs = "  Yes;                                  !- Run Simulation for Weather File Run Periods"
    assert runs in path.read_text()
    path.write_text(
        path.read_text().replace(runs, "  No;  !- Run Simulation for Weather File Run Periods")
        + "\nRunPeriod, Summer, 7, 1, 2009, 7, 31, 2009, Wednesday, No, No, No, Yes, Yes;\n"
    )
    with pytest.warns(IdfImportWarning) as caught:
        building = load_building(path)
    printed = " ".join(str(w.message) for w in caught)
    assert re.search(
        r"RunPeriod 'Summer' \(two.idf line \d+\) \(7/1 to 7/31, month/day\) is not simulated",
        printed,
    ), printed
    assert "simulate it with --start and --end" in printed
    assert "'Run Simulation for Weather File Run Periods' is No" in printed
    assert building.idf_info.run_period.name == "Run Period 1"
    plain = _case_600(shared_data, tmp_path, "1,1,2009,1,31,2009,Thursday", name="one.idf")
    with pytest.warns(IdfImportWarning) as caught:
        load_building(plain)
    assert "is not simulated" not in " ".join(str(w.message) for w in caught)


def test_set_point_profile_leaves_out_the_steps_the_system_is_off(shared_data, tmp_path):
    """The hourly set points identify reads (setpoint_profile) stayed on where the ideal-loads
    system's availability schedule switches it off (a review, 2026-11-30)."""
    from thermocal.multizone.files import load_building
    from thermocal.multizone.idf import IdfImportWarning

    text = shared_data("energyplus_reference", "case_600_v25.idf").read_text()
    field = "  ,                                     !- Availability Schedule Name"
    path = tmp_path / "half.idf"
    path.write_text(
        text.replace(field, "  OffFirstHalf,  !- Availability Schedule Name", 1)
        + "\nSchedule:Compact, OffFirstHalf, , Through: 1/15, For: AllDays, Until: 24:00, 0,"
        " Through: 12/31, For: AllDays, Until: 24:00, 1;\n"
    )
    with pytest.warns(IdfImportWarning):
        building = load_building(path)
    times = pd.date_range("2009-01-14", periods=72, freq="h")
    profile = building.idf_info.setpoint_profile(times)
    heating = profile[("ZONE ONE", "heating")]
    assert heating.iloc[:48].isna().all()
    assert (heating.iloc[48:] == 20.0).all()
