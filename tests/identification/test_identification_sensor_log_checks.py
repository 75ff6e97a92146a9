"""The sensor log and its mapping as ``identify`` and ``calibrate`` read them (fuzzing round 4).

Before the fixes:

* a log in Kelvin without a unit (every sensor 280-290) was called "tenths of a degree? (as
  28.5 C)": the other sensors' median, read in the same wrong unit, ranked the conversions;
  dividing by 10 as told then ran silently with every room near 28.5 C. A Fahrenheit log
  declared C compared a sensor with the others' "57.2 C";
* two sensors of one zone 4.4 K apart on average were averaged without a word;
* ``0101: SPACE1-1`` in the mapping was read by YAML as the octal number 65;
* a mapping zone ``Space1-1`` for the IDF's ``SPACE1-1`` was refused without "did you mean";
* an hourly log printed one three-line warning per sensor (82 on the clinic);
* ``ignore: [S99]`` for a sensor not in the log, and a sensor both mapped and ignored, were
  silent.

The references are built on a tiny stand-in building (zones only: every zone here has a sensor
or floats), so each test takes a fraction of a second.
"""

from __future__ import annotations

import types
import warnings

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.identification.sensors import (
    SENSOR_DISAGREEMENT,
    ReferenceWarning,
    check_sensor_plausibility,
    load_mapping,
    mapping_from_dict,
    zone_references,
    zone_sources,
)
from thermocal.io.measurements.units import temperature_unit_slip

STEP = pd.Timedelta("15min")
ZONES = ("SPACE1-1", "SPACE2-1", "SPACE3-1")
BUILDING = types.SimpleNamespace(name="Building", zones=dict.fromkeys(ZONES), surfaces={})
TIMES = pd.date_range("2024-01-08", periods=3 * 96, freq=STEP, tz="UTC")


def _log(columns: dict[str, float], every: str = "5min") -> pd.DataFrame:
    """A wide log around the period: each sensor its mean [C] plus a daily wave of 1 K."""
    index = pd.date_range(
        "2024-01-07 22:00", "2024-01-11 02:00", freq=every, tz="UTC", name="time"
    )
    hours = (index - index[0]) / pd.Timedelta("1h")
    wave = np.sin(2 * np.pi * np.asarray(hours) / 24.0)
    return pd.DataFrame({name: mean + wave for name, mean in columns.items()}, index=index)


def _references(log, mapping: dict, **kwargs):
    """zone_references with every warning recorded: (reference, the ReferenceWarning texts)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        reference, _ = zone_references(
            log, BUILDING, mapping_from_dict(mapping, source="mapping.yaml"), TIMES, STEP,
            source="log.csv", **kwargs,
        )  # fmt: skip
    return reference, [str(w.message) for w in caught if issubclass(w.category, ReferenceWarning)]


# ---------------------------------------------------------------------------------------------
# a whole log in another unit
# ---------------------------------------------------------------------------------------------
def _grid(means: dict[str, float]) -> pd.DataFrame:
    wave = np.sin(np.arange(len(TIMES)) * 2 * np.pi / 96)
    return pd.DataFrame({name: mean + 0.3 * wave for name, mean in means.items()}, index=TIMES)


CLINIC_IN_KELVIN = {"S04": 285.45, "S05": 287.0, "S06": 287.25, "S07": 287.4}
MAPPING_4 = mapping_from_dict(
    {"sensors": {"S04": "Room 7", "S05": "Room 7", "S06": "Room 9", "S07": "Room 11"}},
    source="mapping.yaml",
)


def test_a_log_in_kelvin_without_unit_names_kelvin_first_and_tenths_with_both_values():
    """285.45 among others at 287.25 (all Kelvin): Kelvin is named first (12.3 C), tenths
    (28.5 C) second as it fits too, each with what it gives for the sensor and the others."""
    with pytest.raises(ThermocalInputError) as caught:
        check_sensor_plausibility(_grid(CLINIC_IN_KELVIN), MAPPING_4, STEP, "log.csv")
    message = str(caught.value)
    assert "sensor 'S04' (zone 'Room 7') reads 285.4 on average" in message
    assert "the whole log seems to be in another unit than C" in message
    assert "Kelvin? (12.3 C for S04, 14.1 C for the others' median if so)" in message
    assert "tenths of a degree? (202 for 20.2 C) (28.5 C for S04" in message
    assert message.index("Kelvin?") < message.index("tenths")
    assert "if Kelvin: declare its unit as K" in message
    assert "hundredths" not in message  # 2.9 C for a building's median: not named
    assert "average 287.2 C" not in message and "average 287.3 C" not in message


def test_a_sensor_among_others_in_the_same_wrong_unit_is_ranked_by_commonness():
    """The ranking itself: a reference outside the plausible range is no yardstick."""
    assert temperature_unit_slip(285.5, 287.2)[0] == "Kelvin?"
    # a reference that is an indoor temperature still decides (a tenths sensor among rooms)
    assert temperature_unit_slip(285.5, 28.0)[0].startswith("tenths")


def test_a_fahrenheit_log_declared_celsius_is_not_compared_with_equally_wrong_sensors():
    means = {"S04": 54.2, "S05": 57.0, "S06": 57.2, "S07": 57.5}
    with pytest.raises(ThermocalInputError) as caught:
        check_sensor_plausibility(_grid(means), MAPPING_4, STEP, "log.csv")
    message = str(caught.value)
    assert "and the other 3 sensor(s) 57.2 (their median): neither is an indoor" in message
    assert "Fahrenheit? (12.3 C for S04, 14.0 C for the others' median if so)" in message
    assert "average 57.2 C" not in message and "tenths" not in message
    # the unit the log declares (its unit column says C) is named
    units = dict.fromkeys(means, "C")
    with pytest.raises(ThermocalInputError, match=r"another unit than the C it declares: Fahr"):
        check_sensor_plausibility(_grid(means), MAPPING_4, STEP, "log.csv", declared_units=units)


def test_one_sensor_in_kelvin_among_celsius_sensors_keeps_its_message():
    means = {"S04": 293.5, "S05": 20.0, "S06": 21.0, "S07": 19.5}
    with pytest.raises(ThermocalInputError, match=r"others?.* average 20\.0 C: Kelvin\? \(as 20"):
        check_sensor_plausibility(_grid(means), MAPPING_4, STEP, "log.csv")


# ---------------------------------------------------------------------------------------------
# two sensors of one zone far apart
# ---------------------------------------------------------------------------------------------
def test_two_sensors_of_one_zone_far_apart_are_warned_naming_both():
    mapping = {"sensors": {"S0": "SPACE1-1", "S1": "SPACE1-1", "S2": "SPACE2-1"}}
    _, texts = _references(_log({"S0": 16.0, "S1": 20.5, "S2": 20.0}), mapping)
    (text,) = texts
    assert "zone 'SPACE1-1': sensors 'S0' and 'S1' in log.csv differ by 4.5 K on average" in text
    assert "(largest 4.5 K)" in text and f"more than the {SENSOR_DISAGREEMENT:g} K" in text


def test_two_sensors_of_one_zone_within_the_threshold_are_not_warned():
    mapping = {"sensors": {"S0": "SPACE1-1", "S1": "SPACE1-1", "S2": "SPACE2-1"}}
    _, texts = _references(_log({"S0": 19.0, "S1": 20.5, "S2": 20.0}), mapping)
    assert texts == []
    # sensors that see the surfaces (operative) may differ more: 2.5 K is no warning there
    operative = {**mapping, "zones": {"SPACE1-1": {"sensor": "operative"}}}
    _, texts = _references(_log({"S0": 18.0, "S1": 20.5, "S2": 20.0}), operative)
    assert texts == []


# ---------------------------------------------------------------------------------------------
# a log sparser than --silence: one warning, not one per sensor
# ---------------------------------------------------------------------------------------------
def test_a_whole_hourly_log_gives_one_warning_not_one_per_sensor(caplog):
    names = [f"S{i:02d}" for i in range(1, 8)]
    mapping = {"sensors": {name: ZONES[i % 3] for i, name in enumerate(names)}}
    log = _log(dict.fromkeys(names, 20.0), every="1h")
    with caplog.at_level("DEBUG", logger="thermocal.identification.sensors"):
        _, texts = _references(log, mapping)
    (text,) = texts
    assert "log.csv: 7 sensors (S01, S02, S03, S04, S05, ...) report every 1h" in text
    assert "--silence 1h makes that the rule" in text
    assert sum("reports every 1h" in r.getMessage() for r in caplog.records) == 7
    reference, texts = _references(log, mapping, silence="1h")
    assert texts == [] and reference.notna().all().all()


# ---------------------------------------------------------------------------------------------
# ignore:
# ---------------------------------------------------------------------------------------------
def test_an_ignored_sensor_that_is_not_in_the_log_is_warned():
    mapping = {"sensors": {"S1": "SPACE1-1", "S2": "SPACE2-1"}, "ignore": ["S99"]}
    _, texts = _references(_log({"S1": 20.0, "S2": 20.0}), mapping)
    (text,) = texts
    assert "mapping.yaml: ignore: sensor(s) ['S99'] do not occur in log.csv" in text


def test_a_sensor_mapped_and_ignored_is_warned_with_what_its_zone_becomes():
    """Mapped and ignored is what the remedies of a sensor without data, stuck or too sparse
    tell the user to write: it stays legitimate (the sensor is left out), and is said."""
    mapping = {"sensors": {"S1": "SPACE1-1", "S2": "SPACE2-1", "S3": "SPACE2-1"}}
    log = _log({"S1": 20.0, "S2": 20.0, "S3": 20.2})
    reference, texts = _references(log, {**mapping, "ignore": ["S1", "S3"]})
    (text,) = texts
    assert "'S1' (zone 'SPACE1-1': no sensor left, it floats with Q_ID = 0)" in text
    assert "'S3' (zone 'SPACE2-1': its reference from sensor(s) S2)" in text
    assert "are mapped under 'sensors:' and listed under 'ignore:'" in text
    assert list(reference.columns) == ["SPACE2-1"]


# ---------------------------------------------------------------------------------------------
# the mapping file
# ---------------------------------------------------------------------------------------------
def test_zero_padded_sensor_ids_are_read_as_written(tmp_path):
    """YAML reads 0101 as the octal 65: the mapping's names are taken as written."""
    path = tmp_path / "mapping.yaml"
    path.write_text(
        "sensors:\n  0100: PLENUM-1\n  0101: SPACE1-1\n  '0102': SPACE2-1\n  1.10: 0101\n"
        "zones:\n  0101: {use: 0102}\n  SPACE3-1: {radiant_fraction: 0.25}\n"
        "ignore: [0107, yes]\n",
        encoding="utf-8",
    )
    mapping = load_mapping(path)
    assert mapping.sensors == {
        "0100": "PLENUM-1",
        "0101": "SPACE1-1",
        "0102": "SPACE2-1",
        "1.10": "0101",
    }
    assert mapping.substitutes == {"0101": "0102"}
    assert mapping.zone_radiant_fraction == {"SPACE3-1": 0.25}
    assert mapping.ignore == ("0107", "yes")


def test_a_sensor_without_zone_is_still_refused_when_read_as_written(tmp_path):
    path = tmp_path / "mapping.yaml"
    path.write_text("sensors:\n  0101:\n", encoding="utf-8")
    with pytest.raises(ThermocalInputError, match=r"sensor '0101' is mapped to None"):
        load_mapping(path)


def test_a_zone_written_in_another_case_is_refused_with_the_right_spelling():
    mapping = mapping_from_dict({"sensors": {"S1": "Space1-1"}}, source="mapping.yaml")
    with pytest.raises(
        ThermocalInputError,
        match=r"mapped to 'Space1-1', which is not a zone of building 'Building' \(did you "
        r"mean 'SPACE1-1'\? names are matched as written, case included\)",
    ):
        zone_sources(BUILDING, mapping)
    # a per-zone entry in another case would be left out without a word: refused too
    per_zone = mapping_from_dict(
        {"sensors": {"S1": "SPACE1-1"}, "zones": {"space2-1": {"radiant_fraction": 0.2}}},
        source="mapping.yaml",
    )
    with pytest.raises(ThermocalInputError, match=r"zones\.space2-1: .*did you mean 'SPACE2-1'"):
        zone_sources(BUILDING, per_zone)


def test_two_sensors_in_kelvin_among_three_are_named_each_not_the_whole_log():
    """Review: with two of three sensors in Kelvin the median of the others mixed a Kelvin and
    a Celsius value (157) and the message called the whole log another unit, 'divide ... for
    every sensor'. Each is now judged against the sensors that read an indoor temperature."""
    means = {"S04": 293.5, "S05": 294.0, "S06": 20.5}
    mapping = mapping_from_dict(
        {"sensors": {"S04": "Room 7", "S05": "Room 9", "S06": "Room 11"}}, source="mapping.yaml"
    )
    with pytest.raises(ThermocalInputError) as caught:
        check_sensor_plausibility(_grid(means), mapping, STEP, "log.csv")
    message = str(caught.value)
    assert "sensor 'S04'" in message and "Kelvin" in message, message
    assert "for every sensor" not in message and "whole log" not in message, message


def test_zone_names_in_another_case_are_read_as_the_buildings():
    """EnergyPlus reads names regardless of case: a mapping written 'Space1-1' for the IDF's
    SPACE1-1 was refused (/tmp/fuzz4/e23_zone_lowercase). identify and a campaign's problem
    now take the building's spelling (unique ignoring case), with a note; the lower-level checks
    above still name an unknown name."""
    from thermocal.identification.sensors import in_building_spelling

    mapping = mapping_from_dict(
        {"sensors": {"S1": "Space1-1", "S2": "SPACE3-1"},
         "zones": {"space2-1": {"radiant_fraction": 0.2, "use": "space1-1"}}},
        source="mapping.yaml",
    )  # fmt: skip
    respelled, notes = in_building_spelling(mapping, BUILDING)
    assert respelled.sensors == {"S1": "SPACE1-1", "S2": "SPACE3-1"}
    assert respelled.zone_radiant_fraction == {"SPACE2-1": 0.2}
    assert set(respelled.substitutes.items()) <= {("SPACE2-1", "SPACE1-1")}
    assert len(notes) == 1 and "'Space1-1' as 'SPACE1-1'" in notes[0] and "mapping.yaml" in notes[0]
    sources = zone_sources(BUILDING, respelled)
    assert sources["SPACE1-1"].sensors == ("S1",)
    # an exact name is kept, a name matching none (or two zones) is left for the checks
    same, none = in_building_spelling(
        mapping_from_dict({"sensors": {"S1": "SPACE1-1"}}, source="m"), BUILDING
    )
    assert none == [] and same.sensors == {"S1": "SPACE1-1"}
    twins = types.SimpleNamespace(name="B", zones=dict.fromkeys(("Hall", "HALL")), surfaces={})
    kept, none = in_building_spelling(mapping_from_dict({"sensors": {"S1": "hall"}}, source="m"),
                                      twins)  # fmt: skip
    assert none == [] and kept.sensors == {"S1": "hall"}


# ---------------------------------------------------------------------------------------------
# impossible readings, spikes and dropouts (exploratory test, 2026-11-30)
# ---------------------------------------------------------------------------------------------
MAPPING_3 = {"sensors": {"S1": "SPACE1-1", "S2": "SPACE2-1", "S3": "SPACE3-1"}}


def test_missing_value_codes_and_spikes_of_unnamed_sensors_become_gaps():
    """Sensors named S1..S3 (no unit, no name that says temperature) were not screened: 13
    readings of -999 (a logger's missing-value code) made the exact inverse's heat run away
    (4e12 W, then NaN for 2.5 days) while the metric, dropping the NaN, looked better than the
    clean log's; one 85 C reading (a DS18B20's power-on value) gave 200 times the metric. Every
    mapped sensor is an air temperature: the code is removed as impossible, the spike as an
    isolated spike, both bridged as gaps and named in a warning."""
    clean = _log({"S1": 20.0, "S2": 21.0, "S3": 19.0})
    bad = clean.copy()
    bad.iloc[500:513, 1] = -999.0
    bad.iloc[700, 2] = 85.0
    reference, said = _references(bad, MAPPING_3)
    expected, _ = _references(clean, MAPPING_3)
    assert np.abs(reference.to_numpy() - expected.to_numpy()).max() < 0.05
    assert any("'S2'" in w and "13 reading(s) removed as impossible" in w for w in said), said
    assert any("'S3'" in w and "removed as outlier" in w and "85" in w for w in said), said


def test_a_dropout_to_zero_for_hours_is_refused():
    """Six hours of exactly 0.0 C in a room at 20 C (a logger's dropout) are shorter than a
    stuck sensor's day and inside physical limits: refused as a jump away and back."""
    log = _log({"S1": 20.0, "S2": 21.0, "S3": 19.0})
    log.iloc[400:472, 0] = 0.0
    with pytest.raises(ThermocalInputError, match=r"sensor 'S1' \(zone 'SPACE1-1'\) reads about "
                       r"0.0 C from .* jumping there from about 2\d.\d C and back"):  # fmt: skip
        _references(log, MAPPING_3)


def test_level_excursions_are_jumps_away_and_back_not_steps_or_ramps():
    from thermocal.io.measurements.quality import level_excursions

    base = np.full(100, 20.0)
    spike = base.copy()
    spike[[40, 41]] = [85.0, 85.0]
    assert level_excursions(spike, 10.0, 5) == [(40, 42)]
    dropout = base.copy()
    dropout[10:30] = 0.0
    dropout[15] = np.nan  # a missing reading inside the run
    assert level_excursions(dropout, 10.0, 50) == [(10, 30)]
    assert level_excursions(dropout, 10.0, 10) == []  # longer than max_run
    step = base.copy()
    step[50:] = 5.0  # a jump that stays (no return): not an excursion
    assert level_excursions(step, 10.0, 50) == []
    ramp = 20.0 - 15.0 * np.sin(np.linspace(0, np.pi, 100))  # a deep but gradual dip
    assert level_excursions(ramp, 10.0, 100) == []
    setback = base.copy()
    setback[30:60] = 14.0  # a set-back of 6 K and its recovery: below the jump
    assert level_excursions(setback, 10.0, 100) == []


def test_an_identified_heat_that_is_not_finite_is_refused():
    from thermocal.identification.workflow import _refuse_non_finite_heat

    index = pd.date_range("2024-01-08", periods=10, freq="5min")
    heat = pd.DataFrame({"A": np.arange(10.0), "B": np.arange(10.0)}, index=index)
    reference = pd.DataFrame({"A": 20.0, "B": 21.0}, index=index)
    _refuse_non_finite_heat(heat, reference, "exact inverse")  # finite: nothing
    heat.iloc[6:, 1] = np.nan
    expected = (
        r"exact inverse identification of zone 'B' is not finite from 2024-01-08 00:30:00 "
        r"\(1 zone\(s\), 4 step\(s\)\)"
    )
    with pytest.raises(ThermocalInputError, match=expected):
        _refuse_non_finite_heat(heat, reference, "exact inverse")


def test_an_hourly_float_above_the_set_point_is_the_rooms_not_a_spike():
    """Hourly readings of a room that floats 2-3 K in the afternoon sun and comes back
    (EnergyPlus 25.2's zone SPHW of NREL's WindowTestsSimple, Golden, 12 January: 20.13, 23.21,
    22.66, 20.42 C between readings of 20 C) were removed as spikes under the fixed 1.5 K floor;
    the 3 h silence then had no zone to take over: "zone 'SPACE1-1' has no data for ...". Now
    the readings are kept and the reference goes through them."""
    log = _log({"S1": 20.0, "S2": 21.0, "S3": 19.0}, every="1h")
    at = log.index.get_loc(pd.Timestamp("2024-01-09 13:00", tz="UTC"))
    log.iloc[at : at + 4, 0] = [20.128, 23.21, 22.663, 20.415]
    log.iloc[at + 1 : at + 3, 0] += log.iloc[at, 0] - 20.128  # on the wave's level
    reference, said = _references(log, MAPPING_3)
    assert not any("removed" in w for w in said), said
    peak = reference["SPACE1-1"].max()
    assert peak == pytest.approx(log.iloc[at + 1, 0], abs=0.3), (peak, log.iloc[at + 1, 0])
