"""Campaign file: valid example, and every bad input named with its key."""

from __future__ import annotations

import textwrap

import pytest

from thermocal.calibration.config import load_campaign
from thermocal.errors import ThermocalInputError

GOOD = """
building: clinic.yaml
weather: weather.epw
sensors: sensors.csv
mapping: mapping.yaml
period: {start: 2001-01-01, end: 2001-02-01}
step: 5min
identification: {method: inverse, feedback: air}
occupancy: null
parameters:
  include: ["material/*", "window/*", "infiltration/*", "zone/*"]
  exclude: []
  default_range: 0.75
  ranges: {"*/shgc": 100.0, "*/thickness": 10.0}
sampling: {method: sobol, samples: 500, seed: 1}
metamodel: {kind: svr, top_k: 10, cv_folds: 5, log_target: false}
optimisation: {starts: 8, seed: 1}
validation: {start: 2001-02-01, end: 2001-02-15}
store: campaign.sqlite
"""


@pytest.fixture
def folder(tmp_path):
    for name in ("clinic.yaml", "weather.epw", "sensors.csv", "mapping.yaml"):
        (tmp_path / name).write_text("x\n")
    return tmp_path


def _write(folder, text):
    path = folder / "campaign.yaml"
    path.write_text(textwrap.dedent(text))
    return path


def test_valid_campaign_file(folder):
    path = _write(folder, GOOD)
    c = load_campaign(path)
    assert c.weather == folder / "weather.epw" and c.store == folder / "campaign.sqlite"
    assert c.building == str(folder / "clinic.yaml")
    assert c.parameters.ranges == {"*/shgc": 100.0, "*/thickness": 10.0}
    assert c.sampling.samples == 500 and c.metamodel.top_k == 10
    assert c.identification == {"method": "inverse", "feedback": "air"}
    assert c.text == path.read_text() and c.path == path
    fp = c.fingerprint()
    assert fp == load_campaign(path).fingerprint()
    assert c.fingerprint(samples=64) != fp
    # the problem fingerprint follows the content of the input files
    problem = c.problem_fingerprint()
    (folder / "weather.epw").write_text("other\n")
    assert load_campaign(path).problem_fingerprint() != problem


def test_demo_needs_no_inputs(folder):
    c = load_campaign(_write(folder, "building: demo:clinic\nsampling: {samples: 64}\n"))
    assert c.is_demo and c.weather is None and c.sampling.method == "sobol"


@pytest.mark.parametrize(
    ("replace", "by", "expected"),
    [
        ("samples: 500", "samples: 0",
         r"sampling\.samples: .*greater than or equal to 1 \(got 0\)"),
        ("samples: 500", "samples: -4", r"sampling\.samples"),
        ("top_k: 10", "top_k: 0", r"metamodel\.top_k"),
        ("method: sobol", "method: random", r"sampling\.method: .*'sobol', 'lhs' or 'halton'"),
        ('"*/shgc": 100.0', '"*/shgc": -1.0', r"parameters\.ranges: .*non-negative"),
        ("default_range: 0.75", "default_range: -0.5", r"parameters\.default_range"),
        # a range of 0 ran the whole campaign, then stopped at the bounds (exploratory test)
        ("default_range: 0.75", "default_range: 0", r"default_range is 0: .*exclude"),
        ('"*/shgc": 100.0', '"*/shgc": 0', r"range of '\*/shgc' is 0: .*exclude: \['\*/shgc'\]"),
        ("seed: 1}\nmetamodel", "sead: 1}\nmetamodel", r"sampling\.sead: unknown key; did you "
                                                        r"mean 'seed'"),
        ("store: campaign", "stor: campaign", r"stor: unknown key; did you mean 'store'"),
        ("step: 5min", "step: fivemin", r"step: .*not a duration"),
        ("end: 2001-02-01}", "end: 2000-02-01}", r"period: .*must be after start"),
        ("weather: weather.epw", "weather: missing.epw", r"key 'weather': file .*missing.epw "
                                                         r"not found"),
        ("sensors: sensors.csv\n", "", r"sensors missing"),
        ("store: campaign.sqlite", "store: campaign.sqlite\nsampling: {samples: 3}",
         r"key 'sampling' appears twice"),
        ("store: campaign.sqlite", "store: campaign.sqlite\nposterior: {discrepancy: big}",
         r"posterior\.discrepancy: .*'none', 'neighbours', 'floor' or 'shared'"),
        ("  exclude: []", "  exclude: []\n  infiltration: buildings",
         r"parameters\.infiltration: .*'per_zone' or 'building'"),
    ],
)
def test_bad_campaign_files(folder, replace, by, expected):
    assert replace in GOOD
    path = _write(folder, GOOD.replace(replace, by, 1))
    with pytest.raises(ThermocalInputError, match=expected) as info:
        load_campaign(path)
    assert str(path) in str(info.value)


def test_not_a_mapping_and_missing_file(folder):
    with pytest.raises(ThermocalInputError, match="must be a YAML mapping"):
        load_campaign(_write(folder, "- a\n- b\n"))
    with pytest.raises(ThermocalInputError, match="does not exist"):
        load_campaign(folder / "nope.yaml")
    with pytest.raises(ThermocalInputError, match="not valid YAML"):
        load_campaign(_write(folder, "building: [unclosed\n"))


@pytest.mark.parametrize(
    ("entry", "expected"),
    [
        (
            "  material/IN46/conductivity: {resistance: 5.0, rel_std: 0.1}",
            "name it construction/<name>/resistance",
        ),
        (
            "  construction/ROOF-1/resistance: {u_value: 0.18, rel_std: 0.1}",
            "give flow: horizontal",
        ),
        (
            "  construction/ROOF-1/resistance: {file: plate.csv, temperatures: surface}",
            "in_situ.construction/ROOF-1/resistance.file': file .*plate.csv not found",
        ),
        (
            "  construction/ROOF-1/resistance: {resistance: 5.0}",
            "give its rel_std too",
        ),
        (
            "  construction/ROOF-1/resistance: {resistance: 5.0, rel_std: 0.1, component: x}",
            "the parameter's name says which construction",
        ),
    ],
)
def test_in_situ_entries_are_checked(folder, entry, expected):
    """An in-situ measurement names a construction's resistance, says how to get the
    resistance from a U-value, and points at a file that exists."""
    (folder / "c.yaml").write_text(ELEMENT + "in_situ:\n" + entry + "\n")
    with pytest.raises(ThermocalInputError, match=expected):
        load_campaign(folder / "c.yaml")


#: The example campaign at element level.
ELEMENT = GOOD.replace("parameters:\n", "parameters:\n  level: element\n", 1)


def test_in_situ_entry_resolved_against_the_campaign_file(folder):
    (folder / "plate.csv").write_text("time,q,Tsi,Tse\n")
    (folder / "c.yaml").write_text(
        ELEMENT + "in_situ:\n  construction/ROOF-1/resistance: {file: plate.csv, "
        "temperatures: surface}\n"
    )
    campaign = load_campaign(folder / "c.yaml")
    assert campaign.in_situ["construction/ROOF-1/resistance"].file == folder / "plate.csv"
    # element-level parameters only: a material-level campaign has no construction resistance
    (folder / "m.yaml").write_text(
        GOOD + "in_situ:\n  construction/ROOF-1/resistance: {resistance: 5.0, rel_std: 0.1}\n"
    )
    with pytest.raises(ThermocalInputError, match="set parameters.level: element"):
        load_campaign(folder / "m.yaml")


def test_in_situ_measurement_outside_the_campaigns_range_is_refused():
    """A measured resistance beyond the parameter's range (a dead plate's 20 m2 K/W on a roof
    sampled up to 5.25) stops the command before any simulation, naming the range."""
    from types import SimpleNamespace

    import numpy as np

    from thermocal.calibration.analysis import measure_in_situ
    from thermocal.io.heat_flux_log import InSituConfig

    name = "construction/ROOF-1/resistance"
    space = SimpleNamespace(
        names=[name], index=lambda n: 0, lower=np.array([0.9]), upper=np.array([5.25])
    )
    for value, ok in ((4.0, True), (20.0, False)):
        campaign = SimpleNamespace(in_situ={name: InSituConfig(resistance=value, rel_std=0.1)})
        if ok:
            assert measure_in_situ(campaign, space)[name][0].resistance == pytest.approx(value)
        else:
            with pytest.raises(ThermocalInputError, match="outside the campaign's range"):
                measure_in_situ(campaign, space)
    campaign = SimpleNamespace(in_situ={"construction/X/resistance": InSituConfig(
        resistance=1.0, rel_std=0.1)})  # fmt: skip
    with pytest.raises(ThermocalInputError, match="not a parameter of the campaign"):
        measure_in_situ(campaign, space)



def test_mostly_clipped_parameters_are_said_with_the_percentage_hint():
    """default_range: 50 meant +-50 %: +-5000 % clipped half the wall insulation's samples to
    the floor and the posterior called a conductivity 7 times too good "determined"; the only
    word was a count of clipped samples (exploratory test, 2026-11-30)."""
    from types import SimpleNamespace

    import pandas as pd

    from thermocal.calibration.analysis import _campaign_notes, _range_hint

    counts = pd.DataFrame(
        {"lower": [8, 1], "upper": [0, 0], "total": [8, 1], "fraction": [0.5, 1 / 16]},
        index=["material/IN02/conductivity", "window/G/shgc"],
    )
    campaign = SimpleNamespace(parameters=SimpleNamespace(default_range=50.0))
    (note,) = _campaign_notes(SimpleNamespace(clip_counts=counts), {}, _range_hint(campaign))
    assert "material/IN02/conductivity (8), window/G/shgc (1)" in note
    assert "material/IN02/conductivity: more than 25 % of the samples at a limit" in note
    assert "+-5000 %" in note and "did you mean 0.5?" in note
    assert "window/G/shgc:" not in note
    quiet = counts.assign(fraction=[0.1, 0.05])
    (note,) = _campaign_notes(SimpleNamespace(clip_counts=quiet), {}, _range_hint(campaign))
    assert "narrow the range" not in note
