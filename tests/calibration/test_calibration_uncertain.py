"""Uncertain inputs a campaign holds nominal (``posterior.uncertain``): which, and their runs."""

from __future__ import annotations

import numpy as np
import pytest

from thermocal.calibration.uncertain import (
    INFILTRATION_REL_STD,
    uncertain_inputs,
    uncertain_signatures,
)
from thermocal.errors import ThermocalInputError
from thermocal.multizone.parameters import INFILTRATION_FACTOR

NOMINAL = {
    "construction/Roof/resistance": 3.0,
    "construction/Wall/resistance": 2.0,
    "zone/A/infiltration_ach": 0.5,
    "zone/B/infiltration_ach": 0.3,
    "zone/C/infiltration_ach": 0.0,
    INFILTRATION_FACTOR: 1.0,
}
VARIED = ["construction/Roof/resistance", "construction/Wall/resistance"]


def test_auto_marks_the_infiltration_uncertain_only_when_no_infiltration_is_varied():
    (item,) = uncertain_inputs("auto", NOMINAL, VARIED)
    assert item.nominal == {INFILTRATION_FACTOR: 1.0}
    assert item.rel_std == INFILTRATION_REL_STD
    assert item.perturbed()[INFILTRATION_FACTOR] == pytest.approx(np.exp(item.log_sd))
    assert item.log_sd == pytest.approx(np.sqrt(np.log(1 + INFILTRATION_REL_STD**2)))
    assert uncertain_inputs("auto", NOMINAL, [*VARIED, "zone/A/infiltration_ach"]) == []
    assert uncertain_inputs("auto", NOMINAL, [*VARIED, INFILTRATION_FACTOR]) == []
    no_air = {k: (0.0 if k.endswith("_ach") else v) for k, v in NOMINAL.items()}
    assert uncertain_inputs("auto", no_air, VARIED) == []
    assert uncertain_inputs({}, NOMINAL, VARIED) == []


def test_a_pattern_scales_every_rate_it_matches_together_and_leaves_zeros_out():
    (item,) = uncertain_inputs({"zone/*/infiltration_ach": 0.3}, NOMINAL, VARIED)
    assert item.nominal == {"zone/A/infiltration_ach": 0.5, "zone/B/infiltration_ach": 0.3}
    factor = np.exp(np.sqrt(np.log(1.09)))
    assert item.perturbed() == pytest.approx(
        {"zone/A/infiltration_ach": 0.5 * factor, "zone/B/infiltration_ach": 0.3 * factor}
    )
    assert item.description()["parameters"] == sorted(item.nominal)


@pytest.mark.parametrize(
    ("spec", "words"),
    [
        ({"zone/*/infiltration": 0.3}, "matches no parameter"),
        ({"Construction/roof/resistance": 0.2}, "did you mean"),
        ({"construction/*/resistance": 0.2}, "is varied by the campaign"),
        ({"zone/C/infiltration_ach": 0.2}, "scaling it changes nothing"),
        ({"zone/A/infiltration_ach": 0.0}, "must be a number in (0, 2]"),
        ({"zone/A/infiltration_ach": 30}, "0.3 for +-30 %"),
        ({"infiltration/*": 0.3, "*infiltration*": 0.3}, "give one of the two"),
    ],
)
def test_entries_that_name_nothing_or_a_calibrated_parameter_are_refused(spec, words):
    with pytest.raises(ThermocalInputError, match="uncertain") as error:
        uncertain_inputs(spec, NOMINAL, VARIED, where="c.yaml: posterior")
    assert words in str(error.value)
    assert str(error.value).startswith("c.yaml: posterior.uncertain[")


def test_the_signature_is_the_series_change_per_unit_log_and_a_missing_run_is_named():
    (item,) = uncertain_inputs("auto", NOMINAL, VARIED)
    nominal_outputs = {"unoccupied_variance": 4.0, "series/000": 10.0, "series/001": 20.0}
    changed = {"unoccupied_variance": 9.0, "series/000": 13.0, "series/001": 18.0}
    signatures, missing = uncertain_signatures(
        [item], lambda p: changed, nominal_outputs, "building"
    )
    ((description, signature, variance),) = signatures
    assert missing == []
    assert signature == pytest.approx(np.array([3.0, -2.0]) / item.log_sd)
    assert variance == pytest.approx(item.log_sd**2)
    assert description["label"] == INFILTRATION_FACTOR
    assert uncertain_signatures([item], lambda p: None, nominal_outputs, "building") == (
        [],
        [INFILTRATION_FACTOR],
    )


def _clinic():
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from clinic_sensor_log import small_clinic

    return small_clinic()


def test_auto_finds_infiltration_that_zones_share_in_groups():
    """The generated clinic's zones share their infiltration objects (``infiltration/<group>/
    ach``, no ``zone/*/infiltration_ach``): ``auto`` still marks the building's infiltration."""
    from thermocal.calibration.uncertain import nominal_values

    building = _clinic()
    nominal = nominal_values(building)
    assert not any(name.startswith("zone/") for name in nominal)
    (item,) = uncertain_inputs("auto", nominal, ["construction/Roof/resistance"])
    assert item.nominal == {INFILTRATION_FACTOR: 1.0}
    assert uncertain_inputs("auto", nominal, ["infiltration/corridor 1/ach"]) == []


def test_the_signature_run_goes_down_where_up_leaves_the_valid_range_and_is_refused_if_both_do():
    """A window's SHGC of 0.8 cannot be raised by 50 %: the run goes one standard deviation
    down; an uncertainty that the model refuses both ways is an error naming the key."""
    from thermocal.calibration.uncertain import model_refusal, nominal_values

    building = _clinic()
    nominal, refusal = nominal_values(building), model_refusal(building)
    (item,) = uncertain_inputs({"window/*/shgc": 0.5}, nominal, [], invalid=refusal)
    assert item.direction == -1 and item.step < 0
    assert refusal(item.perturbed()) is None
    (roof,) = uncertain_inputs({"window/Skylight/u_value": 0.2}, nominal, [], invalid=refusal)
    assert roof.direction == 1
    signatures, _ = uncertain_signatures(
        [item], lambda i: {"unoccupied_variance": 1.0, "series/000": 12.0},
        {"unoccupied_variance": 1.0, "series/000": 10.0}, "building",
    )  # fmt: skip
    assert signatures[0][1] == pytest.approx([2.0 / item.step])  # the change per unit log


def test_an_entry_that_scales_what_the_campaign_varies_is_refused():
    with pytest.raises(ThermocalInputError, match="scales the air change rates"):
        uncertain_inputs({INFILTRATION_FACTOR: 0.4}, NOMINAL, [*VARIED, "zone/A/infiltration_ach"])
    with pytest.raises(ThermocalInputError, match="scales the air change rates"):
        uncertain_inputs({"zone/*/infiltration_ach": 0.4}, NOMINAL, [*VARIED, INFILTRATION_FACTOR])


def test_a_bad_entry_stops_the_campaign_before_anything_is_simulated(tmp_path, monkeypatch):
    """The pattern is checked against the building with the other inputs, not after an hour of
    samples."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from test_calibration_workflow import _campaign

    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate
    from thermocal.identification.problem import IdentificationProblem

    path = _campaign(tmp_path, samples=12, extra="posterior: {uncertain: {'zone/*/ach': 0.3}}")
    runs = []
    monkeypatch.setattr(IdentificationProblem, "run", lambda self, p=None: runs.append(p))
    with pytest.raises(ThermocalInputError, match=r"posterior\.uncertain\['zone/\*/ach'\]"):
        calibrate(load_campaign(path), workers=1, store_path=tmp_path / "s.sqlite",
                  progress=False, log=lambda line: None)  # fmt: skip
    assert runs == []
