"""Campaign files of ``thermocal calibrate`` that used to run a wrong campaign, crash or blame
the wrong thing: each is now refused before any sample (or, for a missing ``period:``, given the
sensor log's span), with a message naming the file's key."""

from __future__ import annotations

import pandas as pd
import pytest
from clinic_sensor_log import weather_path, write_clinic_inputs

from thermocal.calibration.config import load_campaign, parse_campaign
from thermocal.calibration.inputs import load_inputs
from thermocal.calibration.space import ParameterSpace
from thermocal.calibration.workflow import calibrate
from thermocal.errors import ThermocalInputError

START, END = "2001-01-08", "2001-01-12"
PERIOD = f"period: {{start: {START}, end: {END}}}\n"


@pytest.fixture(scope="module")
def clinic(tmp_path_factory):
    """The 12-zone clinic's nominal file, a 4-day log every 15 minutes and its mapping."""
    folder = tmp_path_factory.mktemp("clinic")
    write_clinic_inputs(folder, {}, step="15min", start=START, end=END, warmup_days=2)
    return folder


def _campaign(
    folder, name: str, extra: str, *, metamodel: str = "{kind: auto, top_k: 2}", samples=12
):
    """A small campaign file on the clinic's inputs with ``extra`` sections, loaded."""
    path = folder / f"{name}.yaml"
    path.write_text(
        f"""building: building.yaml
weather: {weather_path()}
sensors: sensors.csv
mapping: mapping.yaml
step: 15min
identification: {{method: inverse, settle: 1D, warmup_days: 2}}
parameters:
  include: ["window/Exterior window/u_value", "infiltration/corridor 1/ach"]
sampling: {{method: sobol, samples: {samples}, seed: 1}}
metamodel: {metamodel}
{extra}"""
    )
    return load_campaign(path)


def _refused(campaign, folder, name: str, match: str, **options):
    """Run ``campaign`` expecting a refusal; returns the message and the lines logged."""
    lines: list[str] = []
    store = folder / f"{name}.sqlite"
    with pytest.raises(ThermocalInputError, match=match) as info:
        calibrate(campaign, workers=1, store_path=store, progress=False, log=lines.append,
                  **options)  # fmt: skip
    assert not store.exists(), "refused after the campaign began"
    return str(info.value), lines


def test_a_validation_period_inside_the_calibration_period_is_refused(clinic):
    """Before: accepted, and the 'validation' repeated the calibration's own data."""
    campaign = _campaign(
        clinic, "inside", PERIOD + "validation: {start: 2001-01-09, end: 2001-01-11}\n"
    )
    message, lines = _refused(
        campaign,
        clinic,
        "inside",
        r"validation period \[2001-01-09 00:00:00-05:00, 2001-01-11.*overlaps the calibration "
        r"period \[2001-01-08 00:00:00-05:00, 2001-01-12.* by 48\.0 h",
    )
    assert "inside.yaml" in message and not any("nominal model" in line for line in lines)


def test_validation_periods_that_only_touch_the_calibration_period_are_apart():
    from thermocal.calibration.inputs import check_validation_apart

    day = pd.Timestamp("2001-01-08", tz="Etc/GMT+5")
    week = (day, day + pd.Timedelta("7D"))
    check_validation_apart(week, (week[1], week[1] + pd.Timedelta("7D")), source="c.yaml")
    check_validation_apart(week, (day - pd.Timedelta("7D"), day), source="c.yaml")
    with pytest.raises(ThermocalInputError, match=r"c\.yaml: .* by 24\.0 h"):
        check_validation_apart(week, (week[1] - pd.Timedelta("1D"), week[1] + pd.Timedelta("1D")),
                               source="c.yaml")  # fmt: skip


def test_range_patterns_that_disagree_on_a_parameter_are_refused():
    """Before: the key listed last won, silently (+-10 % or +-90 % by the keys' order). Now the
    most specific pattern counts (one matching a strict subset of the other's parameters);
    crossing patterns that disagree are refused, in either order."""
    nominal = {"window/W/u_value": 2.0, "window/W/shgc": 0.5, "material/M/conductivity": 1.0,
               "construction/roof/u_value": 0.3}  # fmt: skip
    for ranges in ({"window/*": 0.9, "*/u_value": 0.1}, {"*/u_value": 0.1, "window/*": 0.9}):
        with pytest.raises(
            ThermocalInputError,
            match=r"parameters\.ranges: parameter 'window/W/u_value' matches .*'window/\*' "
            r"\(\+-90 %\).*different ranges",
        ) as info:
            ParameterSpace.from_parameters(nominal, ranges=ranges)
        assert "'*/u_value' (+-10 %)" in str(info.value)
    # nested: 'window/*/u_value' matches a part of what 'window/*' matches, whatever the order
    for ranges in ({"window/*": 0.9, "window/*/u_value": 0.1},
                   {"window/*/u_value": 0.1, "window/*": 0.9}):  # fmt: skip
        space = ParameterSpace.from_parameters(nominal, ranges=ranges)
        got = dict(zip(space.names, space.relative_range, strict=True))
        assert got["window/W/u_value"] == 0.1 and got["window/W/shgc"] == 0.9, got
    same = ParameterSpace.from_parameters(
        nominal, ranges={"window/*": 0.2, "*/u_value": 0.2, "*/conductivity": 0.5}
    )
    assert dict(zip(same.names, same.relative_range, strict=True)) == {
        "window/W/u_value": 0.2,
        "window/W/shgc": 0.2,
        "material/M/conductivity": 0.5,
        "construction/roof/u_value": 0.2,
    }


@pytest.mark.parametrize("section", ["sampling", "optimisation", "morris"])
@pytest.mark.parametrize("seed", [-1, 2**32])
def test_a_seed_numpy_or_scikit_learn_refuses_is_refused_with_its_key(section, seed):
    """Before: -1 crashed in the sampler after the nominal identification (ValueError), 2**32
    in scikit-learn after the whole campaign."""
    with pytest.raises(ThermocalInputError, match=rf"{section}\.seed: .*whole number from 0"):
        parse_campaign({"building": "demo:clinic", section: {"seed": seed}})


def test_a_schedule_without_unoccupied_hours_is_refused_before_any_sample(clinic):
    """Before: 'nan kW' and numpy warnings, the whole campaign, then an error on the store."""
    campaign = _campaign(clinic, "occupied", PERIOD + "occupancy: {unoccupied: []}\n")
    message, lines = _refused(
        campaign,
        clinic,
        "occupied",
        r"occupied\.yaml: occupancy: .*fewer than two unoccupied steps in the calibration period",
    )
    assert "occupancy: data" in message
    assert not any("nan" in line or line.startswith("campaign:") for line in lines), lines


@pytest.mark.parametrize(
    ("samples", "given"), [(None, r"folds\.yaml: sampling\.samples is 12"), (12, r"--samples 12")]
)
def test_too_many_folds_for_the_samples_name_cv_folds_and_where_the_samples_come_from(
    clinic, samples, given
):
    """Before: '--samples 12: ... at least 52', --samples not given and cv_folds not named."""
    campaign = _campaign(clinic, "folds", PERIOD, metamodel="{kind: auto, cv_folds: 50}")
    message, lines = _refused(
        campaign,
        clinic,
        "folds",
        rf"{given}: .*metamodel\.cv_folds: 50\) needs at least 52 .*lower metamodel\.cv_folds",
        samples=samples,
    )
    assert lines == [] and (samples is None) == ("--samples" not in message)


def test_too_few_samples_name_the_campaign_files_key(clinic):
    campaign = _campaign(clinic, "few", PERIOD, samples=4)
    message, _ = _refused(
        campaign, clinic, "few", r"sampling\.samples is 4: a meta-model needs at least 10"
    )
    assert "--samples" not in message and "cv_folds" not in message


def test_a_period_beyond_the_log_is_told_in_the_campaign_files_terms(clinic):
    """Before: 'end the period there (--end)', an option calibrate does not have."""
    campaign = _campaign(clinic, "beyond", "period: {start: 2001-01-08, end: 2001-01-20}\n")
    message, _ = _refused(
        campaign, clinic, "beyond", r"end the period there \(period: \{end: \.\.\.\} in .*beyond"
    )
    assert "--end" not in message


def test_without_a_period_the_campaign_takes_the_sensor_logs_span(clinic):
    """Before: the whole weather year, refused as 'no data for the last 8568 h ... (--end)'."""
    campaign = _campaign(clinic, "span", "")
    inputs = load_inputs(campaign)
    # the log is stamped at each step's end: its first reading is at 00:15
    assert inputs.start == pd.Timestamp("2001-01-08 00:15", tz=inputs.start.tz)
    assert inputs.end == pd.Timestamp("2001-01-12 00:00", tz=inputs.start.tz)
    assert inputs.period_from_log
    # said in the log; a validation period inside the log overlaps that span
    with_validation = _campaign(
        clinic, "span_validation", "validation: {start: 2001-01-10, end: 2001-01-12}\n"
    )
    _, lines = _refused(
        with_validation, clinic, "span_validation", r"overlaps .*the sensor log's span"
    )
    assert lines[0].startswith("period: [2001-01-08 00:15:00-05:00, 2001-01-12 00:00:00-05:00)")
    assert "sensors.csv" in lines[0] and "period: {start: ..., end: ...}" in lines[0]


def test_a_pid_option_with_the_inverse_method_is_named_in_the_campaign_files_terms(clinic):
    """Review: the refusal of a tuning zone with the exact inverse named neither the campaign
    file nor its key ('tuning_zone only applies ... method inverse')."""
    campaign = _campaign(clinic, "tuning", PERIOD)
    text = campaign.path.read_text().replace(
        "warmup_days: 2}", 'warmup_days: 2, tuning_zone: "Room 1"}'
    )
    campaign.path.write_text(text)
    message, _ = _refused(
        load_campaign(campaign.path), clinic, "tuning",
        r"tuning\.yaml: identification\.tuning_zone only applies to the PID loop, which "
        r"identification\.method inverse does not run",
    )  # fmt: skip
    assert "identification.method pid or both" in message
