"""YAML building files, the generators and the ``thermocal simulate`` command."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from thermocal.cli import app
from thermocal.demos import buildings as generators
from thermocal.errors import ThermocalInputError
from thermocal.multizone.files import building_from_dict, load_building, save_building
from thermocal.multizone.simulation import Simulation, steady_state_heat_loss_coefficient

DOC = Path(__file__).resolve().parents[2] / "docs" / "multizone-file.md"


def _doc_example(tmp_path) -> Path:
    text = DOC.read_text()
    block = re.search(r"## Example\s+```yaml\n(.*?)```", text, re.S).group(1)
    path = tmp_path / "two_rooms.yaml"
    path.write_text(block)
    return path


def test_documented_example_loads(tmp_path):
    building = load_building(_doc_example(tmp_path))
    assert list(building.zones) == ["living", "kitchen"]
    assert building.net_area("living south") == pytest.approx(11.0)
    assert building.surfaces["kitchen|living"].other_surface == "living|kitchen"


def test_yaml_roundtrip_keeps_physics():
    house = generators.single_family_house()
    assert steady_state_heat_loss_coefficient(house) == pytest.approx(
        steady_state_heat_loss_coefficient(building_from_dict(_roundtrip(house))), rel=1e-12
    )


def _roundtrip(building):
    import yaml

    from thermocal.multizone.files import building_to_dict

    return yaml.safe_load(yaml.safe_dump(building_to_dict(building)))


def test_yaml_errors_name_the_object(tmp_path):
    data = {
        "name": "x",
        "materials": [
            {
                "name": "brick",
                "conductivity": 0.8,
                "density": 1800,
                "specific_heat": 900,
                "thicknes": 0.2,
            }
        ],
        "zones": [{"name": "z", "volume": 10, "floor_area": 4}],
    }
    with pytest.raises(ThermocalInputError, match=r"material 'brick'.*'thicknes'.*'thickness'"):
        building_from_dict(data)
    path = tmp_path / "b.json"
    path.write_text("{}")
    with pytest.raises(ThermocalInputError, match="unknown extension"):
        load_building(path)
    bad = tmp_path / "bad.yaml"
    bad.write_text(
        "name: x\nzones:\n  - {name: z, volume: 10, floor_area: 4}\nsurfaces:\n"
        "  - {name: s, zone: q, construction: c, area: 3}\n"
    )
    with pytest.raises(ThermocalInputError, match=r"bad.yaml.*surface 's'"):
        load_building(bad)


def test_house_matches_the_1950s_brief():
    house = generators.single_family_house()
    assert house.conditioned_floor_area == pytest.approx(220.0)
    hlc = steady_state_heat_loss_coefficient(house)
    assert 450.0 <= hlc <= 550.0
    # ventilation share: 0.45 ach of the heated volume
    heated = [z for z in house.zones.values() if z.conditioned]
    ventilation = sum(z.volume * z.infiltration_ach for z in heated) / 3600 * 1.2 * 1006
    assert 0.1 < ventilation / hlc < 0.25
    # without heating set points nothing is conditioned
    with pytest.raises(ThermocalInputError, match="no conditioned zone"):
        steady_state_heat_loss_coefficient(generators.single_family_house(heating_setpoint=None))


def test_clinic_size_and_parameters():
    clinic = generators.clinic()
    rooms = [z for z in clinic.zones if z.startswith("Room")]
    assert len(rooms) == 180 and len(clinic.zones) == 186
    assert 60 <= len(clinic.parameters()) <= 75
    assert "material/R16 insulation/resistance" in clinic.parameters()
    small = generators.clinic(12, n_corridors=1, corridor_sections=1)
    assert len(small.zones) == 13
    with pytest.raises(ThermocalInputError, match="multiple of 2"):
        generators.clinic(13, n_corridors=1)


def test_clinic_south_rooms_warmer_than_north_rooms(shared_data):
    """Free-floating small clinic in a sunny Denver January: south rooms gain more sun."""
    from thermocal.io.weather import read_weather

    weather, meta = read_weather(shared_data("ashrae140_bestest", "725650TYCST.epw"))
    clinic = generators.clinic(12, n_corridors=1, corridor_sections=1)
    sim = Simulation(clinic, weather, meta, step="1h", start="2023-01-15", end="2023-01-22")
    result = sim.run(free_float=True)
    south = [f"Room {i}" for i in range(2, 6)]  # row 1 faces south (ends excluded)
    north = [f"Room {i}" for i in range(8, 12)]
    assert (
        result.air_temperature[south].mean().mean()
        > result.air_temperature[north].mean().mean() + 1
    )
    solar = result.transmitted_solar
    assert solar[south].sum().sum() > 2 * solar[north].sum().sum()
    assert np.isfinite(result.air_temperature.to_numpy()).all()


def test_cli_simulate_writes_outputs(tmp_path, shared_data):
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    building = save_building(generators.single_family_house(), tmp_path / "house.yaml")
    out = tmp_path / "out"
    result = CliRunner().invoke(
        app,
        [
            "simulate",
            str(building),
            str(weather),
            "--start",
            "2023-01-10",
            "--end",
            "2023-01-13",
            "--step",
            "15min",
            "--out",
            str(out),
            "--format",
            "parquet",
        ],
    )
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "summary.json").read_text())
    assert summary["zones"]["ground living"]["air_temperature_min_C"] == pytest.approx(20, abs=1e-6)
    assert summary["zones"]["cellar"]["heating_kWh"] == 0.0
    assert summary["building"]["heating_kWh"] > 0
    temps = pd.read_parquet(out / "zone_temperatures.parquet")
    assert len(temps) == 3 * 96
    free = CliRunner().invoke(
        app,
        [
            "simulate",
            str(building),
            str(weather),
            "--start",
            "2023-01-10",
            "--end",
            "2023-01-11",
            "--step",
            "1h",
            "--out",
            str(tmp_path / "ff"),
            "--free-float",
        ],
    )
    assert free.exit_code == 0, free.output
    ff = json.loads((tmp_path / "ff" / "summary.json").read_text())
    assert ff["building"]["heating_kWh"] == 0.0
    assert ff["zones"]["ground living"]["air_temperature_min_C"] < 20.0


def test_multizone_ideal_loads_active_set_and_dirichlet_path_agree(shared_data):
    """Heating and cooling set points in many coupled zones: both solution paths, exact bands."""
    from thermocal.io.weather import read_weather

    weather, meta = read_weather(shared_data("ashrae140_bestest", "725650TYCST.epw"))
    clinic = generators.clinic(
        12,
        n_corridors=1,
        corridor_sections=2,
        heating_setpoint=20.0,
        cooling_setpoint=22.0,
        internal_gains_per_area=8.0,
    )
    results = []
    for use_dirichlet in (True, False):
        sim = Simulation(clinic, weather, meta, step="30min", start="2023-03-01", end="2023-03-08")
        sim.use_dirichlet = use_dirichlet
        results.append(sim.run())
    fast, reference = results
    air = fast.air_temperature.to_numpy()
    assert air.min() >= 20.0 - 1e-7 and air.max() <= 22.0 + 1e-7
    # some zones heat while others cool in the same step (sunny March days)
    both = ((fast.heating > 0).any(axis=1) & (fast.cooling > 0).any(axis=1)).sum()
    assert both > 0
    assert np.allclose(fast.heating, reference.heating, atol=1e-6)
    assert np.allclose(fast.cooling, reference.cooling, atol=1e-6)
    # never heat and cool a zone at once, and free-floating zones need no power
    assert not ((fast.heating > 0) & (fast.cooling > 0)).to_numpy().any()
    inside = (air > 20.0 + 1e-6) & (air < 22.0 - 1e-6)
    assert (fast.heating.to_numpy()[inside] == 0).all() and (
        fast.cooling.to_numpy()[inside] == 0
    ).all()


def test_set_parameters_equals_a_fresh_simulation(shared_data):
    """The caches reused by set_parameters must not leak the old parameter values."""
    from thermocal.io.weather import read_weather

    weather, meta = read_weather(shared_data("ashrae140_bestest", "725650TYCST.epw"))
    clinic = generators.clinic(12, n_corridors=1, corridor_sections=2, heating_setpoint=20.0)
    change = {
        "material/Concrete block/conductivity": 1.2,
        "material/Gypsum board/thickness": 0.03,
        "material/R16 insulation/resistance": 1.5,
        "material/Roof insulation/density": 400.0,
        "material/Carpet/specific_heat": 1500.0,
        "window/Exterior window/u_value": 2.0,
        "window/Exterior window/shgc": 0.3,
        "window/Skylight/shgc": 0.4,
        "infiltration/row 1 west/ach": 0.8,
        "infiltration/corridor 1/ach": 0.05,
    }
    kwargs = dict(step="1h", start="2023-02-01", end="2023-02-05")
    sim = Simulation(clinic, weather, meta, **kwargs)
    before = sim.run()
    sim.set_parameters(change)
    after = sim.run()
    fresh = Simulation(clinic.with_parameters(change), weather, meta, **kwargs).run()
    assert np.allclose(after.heating, fresh.heating, rtol=1e-9, atol=1e-6)
    assert np.allclose(after.transmitted_solar, fresh.transmitted_solar, rtol=1e-12)
    assert not np.allclose(after.heating, before.heating, rtol=1e-3)


def test_cli_simulate_writes_only_the_quantities_asked_for(tmp_path, shared_data):
    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    building = save_building(generators.single_family_house(), tmp_path / "house.yaml")
    common = [str(building), str(weather), "--start", "2023-01-10", "--end", "2023-01-11"]
    out = tmp_path / "out"
    result = CliRunner().invoke(
        app, ["simulate", *common, "--step", "1h", "--out", str(out), "--outputs", "heating"]
    )
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == [
        "summary.json",
        "zone_heat_flows.csv",
    ]
    flows = pd.read_csv(out / "zone_heat_flows.csv", index_col=0)
    assert len(flows) == 24 and all(c.endswith("|heating_W") for c in flows.columns)
    summary = json.loads((out / "summary.json").read_text())
    total = flows.sum().sum() / 1000.0  # 1-h steps: W -> kWh
    assert total == pytest.approx(summary["building"]["heating_kWh"], rel=1e-6)
    bad = CliRunner().invoke(
        app, ["simulate", *common, "--out", str(tmp_path / "bad"), "--outputs", "heat,air"]
    )
    assert isinstance(bad.exception, ThermocalInputError)
    message = str(bad.exception)
    assert "--outputs" in message and "'heat'" in message and "heating" in message


def _small_result(step="15min", periods=8 * 4, start="2023-01-10"):
    """A two-zone result whose values are their step's position (known means per interval)."""
    from thermocal.multizone.results import SimulationResult

    index = pd.date_range(start, periods=periods, freq=step)
    ramp = pd.DataFrame(
        {"a": np.arange(periods, dtype=float), "b": 2.0 * np.arange(periods)}, index=index
    )
    return SimulationResult(
        air_temperature=ramp,
        operative_temperature=ramp + 0.5,
        mean_radiant_temperature=ramp + 1.0,
        heating=ramp * 10.0,
        cooling=ramp * 0.0,
        heat_input=ramp * 0.0,
        transmitted_solar=ramp * 0.0,
        infiltration=ramp * 0.0,
        surface_temperature=None,
        step=pd.Timedelta(step),
    )


def test_reporting_interval_rows_are_interval_means_stamped_as_energyplus(tmp_path):
    """Hourly rows: the mean of the four 15-min steps starting in the hour; temperatures (the
    steps' end states) stamped at the hour's end, heat flows at its start."""
    result = _small_result()
    result.to_files(tmp_path, report="hourly")
    temps = pd.read_csv(tmp_path / "zone_temperatures.csv", index_col="time", parse_dates=True)
    flows = pd.read_csv(tmp_path / "zone_heat_flows.csv", index_col="time", parse_dates=True)
    assert len(temps) == len(flows) == 8
    assert temps.index[0] == pd.Timestamp("2023-01-10 01:00")
    assert flows.index[0] == pd.Timestamp("2023-01-10 00:00")
    # steps 0..3 -> mean 1.5; steps 4..7 -> 5.5
    assert temps["a|air_temperature_C"].iloc[:2].tolist() == [1.5, 5.5]
    assert temps["b|operative_temperature_C"].iloc[0] == pytest.approx(3.5)
    assert flows["a|heating_W"].iloc[:2].tolist() == [15.0, 55.0]
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["report"]["interval"] == "1h"
    assert summary["report"]["partial_intervals"] == []
    # the summary is every step's, whatever the interval: 10 x (0 + ... + 31) W x 0.25 h
    assert summary["zones"]["a"]["heating_kWh"] == pytest.approx(10 * 496 * 0.25 / 1000)


def test_reporting_interval_names_partial_intervals_and_refuses_odd_ones(tmp_path):
    from thermocal.errors import ThermocalInputError
    from thermocal.multizone.results import report_rule

    step = pd.Timedelta("15min")
    assert report_rule(None, step) is None
    assert report_rule("timestep", step) is None
    assert report_rule("15min", step) is None
    assert report_rule("Hourly", step) == "h"
    assert report_rule("daily", step) == "24h"
    assert report_rule("monthly", step) == "MS"
    # durations pandas reads but does not resample by ('2 hours' crashed after the run), and a
    # week of seven days, not weeks anchored on Sundays
    assert report_rule("2 hours", step) == "2h"
    assert report_rule("PT1H", step) == "h"
    assert report_rule("1W", step) == "168h"
    for bad, says in (
        ("20min", "whole number of the 15min time step"),
        ("5min", "whole number"),
        ("weekly-ish", "give timestep, hourly"),
        ("2", "duration with its unit"),
    ):
        with pytest.raises(ThermocalInputError, match=says):
            report_rule(bad, step)
    # a run starting at 00:30: its first hour holds two of four steps
    result = _small_result(start="2023-01-10 00:30", periods=6)
    result.to_files(tmp_path, report="1h", quantities="heating")
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["report"]["partial_intervals"] == ["2023-01-10 00:00:00"]
    flows = pd.read_csv(tmp_path / "zone_heat_flows.csv", index_col="time")
    assert flows["a|heating_W"].tolist() == [5.0, 35.0]


def test_cli_simulate_refuses_a_reporting_interval_before_the_run(tmp_path, shared_data):
    from thermocal.errors import ThermocalInputError

    weather = shared_data("ashrae140_bestest", "725650TYCST.epw")
    building = save_building(generators.single_family_house(), tmp_path / "house.yaml")
    common = [
        "simulate", str(building), str(weather), "--start", "2023-01-10", "--end", "2023-01-11",
        "--step", "15min",
    ]
    odd = "whole number of the 15min time step: give a multiple of it (e.g. 30min)"
    for report, says in (("20min", odd), ("3", "has no unit")):
        result = CliRunner().invoke(
            app, [*common, "--out", str(tmp_path / "x"), "--report", report]
        )
        assert isinstance(result.exception, ThermocalInputError), result.output
        assert says in str(result.exception)
        assert not (tmp_path / "x").exists()
    result = CliRunner().invoke(
        app, [*common, "--out", str(tmp_path / "d"), "--report", "daily"]
    )
    assert result.exit_code == 0, result.output
    temps = pd.read_csv(tmp_path / "d" / "zone_temperatures.csv", index_col="time")
    assert len(temps) == 1
