"""Heat-flux logs whose result cannot be a building element's (a heat flux in mW/m2, an
"outside" sensor that is a second inside one), the plate's sign when ``--inward`` is already
given, and bad option values of ``thermocal insitu``: refused with what to check, named by the
command's options, never a negative resistance or uncertainty."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from thermocal.cli import app
from thermocal.errors import ThermocalInputError
from thermocal.physics.heat_flux import InSituUValue, average_method

REF = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_house"
LOG = REF / "heat_flux_north_wall.csv"


def _steady(u, n_days=5, ti=20.0, te=0.0):
    times = pd.date_range("2025-01-06", periods=24 * n_days, freq="1h")
    tin, tout = np.full(len(times), ti), np.full(len(times), te)
    return times, u * (tin - tout), tin, tout


def test_a_u_value_above_what_the_surface_resistances_allow_is_refused():
    """A wall's ISO 6946 films (0.13 + 0.04) allow at most 1 / 0.17 = 5.88 W/(m2 K); above it
    the element's resistance would be negative: refused with the value, the limit and the
    causes to check, not returned with a negative resistance and uncertainty."""
    times, q, ti, te = _steady(1.2)
    with pytest.raises(ValueError) as info:
        average_method(times, 1000.0 * q, ti, te)  # the plate's log in mW/m2
    text = str(info.value)
    assert "U-value 1200 W/(m2 K)" in text and "negative" in text and "5.88 W/(m2 K)" in text
    for cause in ("mW/m2", "outside", "sensitivity"):
        assert cause in text, text
    # an "outside" sensor indoors: 0.2 K below the inside one, the wall's flux 20 K would give
    times, q, ti, te = _steady(1.2, te=19.8)
    with pytest.raises(ValueError, match="impossible.*difference of 0.2 K"):
        average_method(times, 1.2 * 20.0 * np.ones(len(q)), ti, te)
    # towards an unheated space the inside film is on both sides: at most 1 / 0.26
    times, q, ti, te = _steady(4.0)
    with pytest.raises(ValueError, match="3.85 W/"):
        average_method(times, q, ti, te, surface_resistances=(0.13, 0.13))


def test_a_spike_that_makes_the_u_value_impossible_is_named():
    times, q, ti, te = _steady(1.2)
    q[50] = 1e6  # one reading of a logger fault
    with pytest.raises(ValueError, match="impossible.*2025-01-08 02:00, 1e.06 W/m2.*a spike"):
        average_method(times, q, ti, te)
    times, q, ti, te = _steady(1.2)
    with pytest.raises(ValueError) as info:  # a uniform factor is no spike
        average_method(times, 1000.0 * q, ti, te)
    assert "spike" not in str(info.value)


def test_thin_real_elements_are_not_refused_but_noted():
    """Single glazing (about 5.8 W/(m2 K) air to air, 4 mm of glass) is a real element: kept,
    with a note that only glazing, sheet metal or a thin bare slab is that conductive; an
    ordinary wall gets no such note."""
    times, q, ti, te = _steady(5.8)
    glazing = average_method(times, q, ti, te)
    assert glazing.u_value == pytest.approx(5.8)
    assert 0 < glazing.resistance < 0.01 and glazing.resistance_rel_std > 0
    assert any("glazing" in note for note in glazing.notes)
    times, q, ti, te = _steady(1.2)
    assert not any("glazing" in note for note in average_method(times, q, ti, te).notes)


def test_no_negative_resistance_uncertainty_is_reported():
    """A value whose resistance is not positive (a given U above the films' limit) has no
    resistance uncertainty: NaN, written as null, never negative."""
    given = InSituUValue(u_value=6.0, rel_std=0.1)
    assert given.resistance < 0
    assert np.isnan(given.resistance_rel_std)
    assert given.as_dict()["resistance_rel_std"] is None


def test_a_given_u_value_above_the_films_limit_is_refused():
    from thermocal.io.heat_flux_log import InSituConfig, measure_in_situ_value

    spec = InSituConfig(u_value=5.0, rel_std=0.1, other_side="unheated")
    with pytest.raises(ThermocalInputError, match="in_situ.walls: u_value 5 W/.*3.85"):
        measure_in_situ_value(spec, "in_situ.walls")
    ok, _ = measure_in_situ_value(InSituConfig(u_value=5.0, rel_std=0.1), "in_situ.walls")
    assert ok.resistance > 0 and ok.resistance_rel_std > 0


def _log(tmp_path, change):
    log = pd.read_csv(LOG).rename(columns={"q_W_m2": "q"})
    change(log)
    path = tmp_path / "plate.csv"
    log.to_csv(path, index=False)
    return path


@pytest.mark.parametrize(
    "change",
    [
        lambda log: log.__setitem__("q", 1000.0 * log["q"]),  # mW/m2
        lambda log: log.__setitem__("Te", log["Ti"] - 0.2),  # a second inside sensor
    ],
    ids=["mW_per_m2", "outside_sensor_inside"],
)
def test_the_command_refuses_an_impossible_u_value(tmp_path, change):
    result = CliRunner().invoke(app, ["insitu", str(_log(tmp_path, change))], terminal_width=80)
    assert isinstance(result.exception, ThermocalInputError), result.output
    text = str(result.exception)
    assert "plate.csv" in text and "impossible" in text and "at most 5.88" in text
    assert "mW/m2" in text and "outside" in text and "sensitivity" in text
    assert "--surface" in text and "LOG" not in text
    assert "rel_std" not in result.output and "resistance:" not in result.output


def test_the_sign_message_says_to_drop_inward_when_it_is_given(tmp_path):
    path = _log(tmp_path, lambda log: None)  # outward positive, as the plate should
    result = CliRunner().invoke(app, ["insitu", str(path), "--inward"])
    assert isinstance(result.exception, ThermocalInputError), result.output
    text = str(result.exception)
    assert "drop --inward" in text and "set --inward" not in text, text
    # without it a log reporting inward flow as positive is still told to set it
    path = _log(tmp_path, lambda log: log.__setitem__("q", -log["q"]))
    text = str(CliRunner().invoke(app, ["insitu", str(path)]).exception)
    assert "set --inward" in text and "drop" not in text, text


@pytest.mark.parametrize(
    ("options", "named"),
    [
        (["--heat-capacity", "-5"], r"--heat-capacity -5(\.0)?: .*greater than 0"),
        (["--heat-capacity", "nan"], r"--heat-capacity nan: .*finite"),
        (["--heat-capacity", "inf"], r"--heat-capacity inf: .*finite"),
        (["--heat-capacity", "5000"], r"--heat-capacity 5000(\.0)?: .*2000"),
        (["--temp-in", "Ti", "--temp-out", "Ti"], r"--temp-in and --temp-out both name .*'Ti'"),
        (["--heat-flux", "Ti"], r"--heat-flux and --temp-in both name the log column 'Ti'"),
    ],
)
def test_bad_option_values_are_named_by_the_option_without_pydantic_text(tmp_path, options, named):
    path = _log(tmp_path, lambda log: None)
    result = CliRunner().invoke(app, ["insitu", str(path), *options])
    assert isinstance(result.exception, ThermocalInputError), result.output
    text = str(result.exception)
    assert re.search(named, text), text
    for boilerplate in (
        "validation error",
        "pydantic",
        "type=",
        "input_value",
        "Value error",
        "InSituConfig",
        "areal_heat_capacity",
        "columns",
    ):
        assert boilerplate not in text, text
    if "--heat-capacity" in options:  # what is allowed
        assert "kJ/(m2 K)" in text and "2000" in text, text


def test_an_implausibly_thick_element_is_noted_with_its_flux_and_the_causes():
    """A plate logged in mV without its sensitivity (0.0625 mV per W/m2) reads a 0.495 W/(m2 K)
    wall as 0.031 (R 32 m2 K/W): every ISO criterion passes, so before it was reported without
    a word. The mean flux over the mean difference is the finding: noted first with both, the
    heat-flux column and the causes; a passive-house wall (U 0.1) and a wall measured with its
    surface temperatures below the limit get no such note."""
    times, q, ti, te = _steady(0.495, ti=20.0, te=4.4)
    r = average_method(times, 0.0625 * q, ti, te, heat_flux_column="q_plate")
    assert r.converged and r.resistance == pytest.approx(1 / (0.0625 * 0.495) - 0.17)
    note = r.notes[0]
    assert note.startswith("implausibly high resistance: the element's 32.2 m2 K/W"), note
    for part in ("above the 12", "mean heat flux 0.483 W/m2", "difference of 15.6 K",
                 "U = 0.0309 W/(m2 K)", "'q_plate'", "mV", "sensitivity", "contact"):  # fmt: skip
        assert part in note, (part, note)
    times, q, ti, te = _steady(0.1)  # a passive-house wall: R 9.8 m2 K/W
    assert not any("implausibly" in n for n in average_method(times, q, ti, te).notes)
    times, q, ti, te = _steady(0.05)  # surface temperatures: Lambda 0.05, R 20
    lam = average_method(times, q, ti, te, temperatures="surface")
    assert lam.resistance == pytest.approx(20.0)
    assert lam.notes[0].startswith("implausibly"), lam.notes
    assert "Lambda (surface to surface) = 0.05" in lam.notes[0]
    assert "column 'q" not in lam.notes[0]  # no column given: none named


def test_the_command_warns_of_an_implausibly_thick_element_and_analyses_take_the_note(tmp_path):
    """``thermocal insitu`` shows the note as a warning (exit 0: the log itself is valid) and
    the retrofit and calibration configurations' in_situ entries carry it in their notes."""
    from thermocal.io.heat_flux_log import InSituConfig, measure_in_situ_value

    times, q, ti, te = _steady(0.495, ti=20.0, te=4.4)
    path = tmp_path / "mV.csv"
    pd.DataFrame({"time": times, "q": 0.0625 * q, "Ti": ti, "Te": te}).to_csv(path, index=False)
    result = CliRunner().invoke(app, ["insitu", str(path)], terminal_width=200)
    assert result.exit_code == 0, result.output
    assert "warning: implausibly high resistance" in result.output, result.output
    assert "heat-flux column 'q'" in result.output
    spec = InSituConfig(file=path)
    measured, _ = measure_in_situ_value(spec, "in_situ.walls", default_tz="UTC")
    assert measured.notes[0].startswith("implausibly high resistance")
