"""calibrate with ``identification.site: weather``: the replaced site is in the outputs' notes.

Before: the campaign warned that the weather file's site replaced the building's, and
calibration.json and the report said nothing of it. Now the note is among the campaign
inputs' notes (``CampaignInputs.notes``), with which thermocal.calibration.workflow.calibrate
begins the calibration's notes (calibration.json, the report); the campaign's store keeps them
(``input_notes``) for a re-analysis.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from thermocal.calibration.inputs import load_inputs
from thermocal.errors import ThermocalInputError

GREENSBORO = Path(__import__("pvlib").__file__).parent / "data" / "723170TYA.CSV"
DOC = Path(__file__).parents[2] / "docs" / "multizone-file.md"


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict:
    """A Zurich two-room building (docs/multizone-file.md), its mapping and a 3-day log."""
    d = tmp_path_factory.mktemp("site")
    building = d / "two_rooms.yaml"
    building.write_text(re.search(r"## Example\s+```yaml\n(.*?)```", DOC.read_text(), re.S)[1])
    assert "location:" in building.read_text()
    mapping = d / "mapping.yaml"
    mapping.write_text("sensors: {S1: living, S2: kitchen}\n")
    times = pd.date_range("2015-02-02", periods=3 * 96, freq="15min")
    rng = np.random.default_rng(1)
    log = d / "log.csv"
    pd.DataFrame(
        {"time": times.astype(str), "S1": 21 + rng.normal(0, 0.1, len(times)),
         "S2": 20 + rng.normal(0, 0.1, len(times))}
    ).to_csv(log, index=False)  # fmt: skip
    return {"building": building, "mapping": mapping, "log": log}


def _campaign(files, **identification):
    return SimpleNamespace(
        is_demo=False, path="campaign.yaml", building=files["building"],
        building_path=files["building"], mapping=files["mapping"], weather=GREENSBORO,
        sensors=files["log"], identification={"tz": -5, **identification}, period=None,
        step_timedelta=lambda: pd.Timedelta("15min"),
    )  # fmt: skip


def test_the_default_refuses_naming_the_key(files):
    with pytest.raises(ThermocalInputError) as info:
        load_inputs(_campaign(files))
    assert "identification.site: weather in the campaign file runs at the weather" in str(
        info.value
    )


def test_site_weather_is_a_note_of_the_inputs(files):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        inputs = load_inputs(_campaign(files, site="weather"))
    (note,) = inputs.notes
    assert note.startswith("site replaced (identification.site: weather in the campaign file)")
    assert "km apart" in note and "as EnergyPlus does" in note
    assert any(str(w.message) == note for w in caught)  # the warning says the same
    assert round(inputs.building.location.latitude, 2) == round(inputs.metadata["latitude"], 2)


def test_a_building_at_its_weather_site_has_no_note(files):
    from thermocal.io.weather import read_weather

    _, meta = read_weather(GREENSBORO)
    text = files["building"].read_text()
    near = files["building"].with_name("near.yaml")
    near.write_text(
        re.sub(r"location:.*\n", f"location: {{latitude: {meta['latitude']}, longitude: "
               f"{meta['longitude']}, timezone: -5}}\n", text, count=1)
    )  # fmt: skip
    inputs = load_inputs(
        SimpleNamespace(**{**vars(_campaign(files, site="weather")), "building": near,
                           "building_path": near})
    )  # fmt: skip
    assert inputs.notes == []

