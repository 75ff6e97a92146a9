"""retrofit and verify with a building far from its weather: refused naming the opt-in, or run
at the weather file's site with ``weather.site: weather``, said in a warning and the notes.

Before: both commands refused such a pair with no way to do what EnergyPlus (and now
``identify --site weather``) does: use the weather file's site for a stale building location.
"""

from __future__ import annotations

import logging
from types import SimpleNamespace

import pytest
import yaml

from conftest import shared_data_path
from thermocal.errors import ThermocalInputError
from thermocal.retrofit.config import parse_config

REPO = __import__("pathlib").Path(__file__).parents[2]
DEMO = REPO / "src" / "thermocal" / "data" / "retrofit_demo"  # a house in North Carolina
ZURICH = shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
OPT_IN = "weather.site: weather in the retrofit configuration runs at the weather file's site"


def _cfg(**weather):
    data = yaml.safe_load((REPO / "examples" / "retrofit" / "config.yaml").read_text())
    data["building"] = str(DEMO / "building.yaml")
    data["measurements"]["file"] = str(DEMO / "measurements.csv")
    data["weather"] = {"file": str(ZURICH), **weather}
    return parse_config(data, source="config.yaml")


def test_the_refusal_names_the_opt_in():
    from thermocal.commands.retrofit import _check_site
    from thermocal.retrofit.verify import VERIFY_SITE_OPT_IN

    with pytest.raises(ThermocalInputError) as info:
        _check_site(_cfg())
    message = " ".join(str(info.value).split())
    assert "latitude 36.10, longitude -79.95" in message and "km apart" in message
    assert OPT_IN in message
    with pytest.raises(ThermocalInputError) as info:
        _check_site(_cfg(site="building"), opt_in=VERIFY_SITE_OPT_IN)
    assert "weather.site: weather in the verification configuration runs at" in str(info.value)


def test_an_unknown_site_is_refused_naming_the_key():
    with pytest.raises(ThermocalInputError, match=r"weather\.site"):
        _cfg(site="here")


def test_site_weather_replaces_the_house_location():
    from thermocal.commands.retrofit import _check_site
    from thermocal.retrofit.workflow import building_at_weather_site, load_building

    cfg = _cfg(site="weather")
    note = _check_site(cfg)
    assert note.startswith("site replaced (weather.site: weather in the retrofit configuration)")
    assert "as EnergyPlus does" in note
    house = load_building(cfg.building)
    moved, again = building_at_weather_site(house, cfg, building_source="building.yaml")
    assert again.startswith("site replaced") and "building.yaml" in again
    loc = moved.location
    assert (round(loc.latitude, 2), round(loc.longitude, 2)) == (47.38, 8.57)
    assert loc.timezone == house.location.timezone  # its clock kept
    assert house.location.latitude == pytest.approx(36.1, abs=0.01)  # the file's, unchanged
    near = _cfg(site="weather")
    near.weather.file = "pvlib:723170TYA.CSV"  # Greensboro, the demo's own: nothing replaced
    same, none = building_at_weather_site(house, near, building_source="b")
    assert none is None and same is house


class _Stop(Exception):
    pass


def test_the_analysis_runs_at_the_weather_site_and_warns(monkeypatch, caplog):
    """run_retrofit replaces the location before reading the measurements (their sun and
    clock checks use it) and warns at once."""
    from thermocal.retrofit import workflow

    seen = {}

    def stop(mc, **kwargs):
        raise _Stop

    def gains(ig, area, name):
        seen["called"] = True

    monkeypatch.setattr(workflow, "read_raw_measurements", stop)
    monkeypatch.setattr(workflow, "check_configured_gains", gains)
    original = workflow.building_at_weather_site

    def spy(building, cfg, **kwargs):
        out = original(building, cfg, **kwargs)
        seen["location"] = out[0].location
        return out

    monkeypatch.setattr(workflow, "building_at_weather_site", spy)
    with caplog.at_level(logging.WARNING, logger="thermocal.retrofit"), pytest.raises(_Stop):
        workflow.run_retrofit(_cfg(site="weather"))
    assert round(seen["location"].latitude, 2) == 47.38 and seen["called"]
    assert any(r.getMessage().startswith("site replaced (weather.site") for r in caplog.records)


def test_verify_inputs_run_at_the_weather_site(monkeypatch, caplog):
    from thermocal.retrofit import data, verify

    def stop(mc, **kwargs):
        raise _Stop

    monkeypatch.setattr(data, "read_raw_measurements", stop)
    with caplog.at_level(logging.WARNING, logger="thermocal.retrofit"), pytest.raises(_Stop):
        verify.prepare_inputs(_cfg(site="weather"), "verify.yaml")
    assert any(
        "site replaced (weather.site: weather in the verification configuration)"
        in r.getMessage()
        for r in caplog.records
    )


def test_the_detailed_model_notes_the_site(monkeypatch):
    from thermocal.multizone.model import Location
    from thermocal.retrofit import detailed

    building = SimpleNamespace(location=Location(latitude=35.8, longitude=-78.6, timezone=-5))
    monkeypatch.setattr(detailed, "heated_detailed_building", lambda path, setpoint: building)
    monkeypatch.setattr(
        detailed, "simulate_strategies",
        lambda b, *args, **kwargs: SimpleNamespace(notes=["simulation note"], building=b),
    )  # fmt: skip
    with pytest.raises(ThermocalInputError, match=OPT_IN):
        detailed.run_detailed_retrofit(_cfg(), "house.idf")
    result = detailed.run_detailed_retrofit(_cfg(site="weather"), "house.idf")
    assert result.notes[0].startswith("site replaced (weather.site: weather in the retrofit")
    assert "house.idf" in result.notes[0] and result.notes[1] == "simulation note"
    assert result.building.location.latitude == pytest.approx(47.38, abs=0.01)
