"""Retrofit on the detailed multi-zone model (issue 25, item 7).

Truth we did not make: EnergyPlus 25.2 ran NREL's SingleFamilyHouse (``house_v25.idf``) for
Zurich 2015 and each strategy with insulation layers that take the constructions' nominal
U-values to the measures' (``tests/reference/retrofit_energyplus_house/make_reference.py``).
thermocal gets the same IDF and the same measure definitions. The full 16-strategy table is
``measure_detailed.py`` beside the reference (docs/retrofit.md).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from typer.testing import CliRunner

from conftest import shared_data_path
from thermocal.cli import app
from thermocal.errors import ThermocalInputError
from thermocal.retrofit import detailed as det
from thermocal.retrofit.strategies import Measure, Strategy

REF = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_house"
IDF = REF / "house_v25.idf"


def _reference() -> dict:
    return json.loads((REF / "reference.json").read_text())


def _measures() -> dict[str, Measure]:
    return {
        name: Measure(name=name, component=name, u_value=m["u_value"], g_value=m.get("g_value"))
        for name, m in _reference()["measures"].items()
    }


def _make_reference():
    sys.path.insert(0, str(REF))
    sys.modules.pop("make_reference", None)  # other references' scripts share the name
    try:
        import make_reference
    finally:
        sys.path.remove(str(REF))
    return make_reference


@pytest.fixture(scope="module")
def house():
    building = det.load_detailed_building(IDF)
    return building, building, list(building.idf_info.notes)


def test_layers_added_as_energyplus_added_them(house):
    """Each opaque measure adds lambda 0.035 insulation of the thickness make_reference.py gave
    EnergyPlus (nominal ISO 6946 U-value -> target), on the side EnergyPlus put it."""
    mr = _make_reference()
    _, grounded, _ = house
    measures = _measures()
    expected = {
        "walls": mr.insulation_thickness(mr.U_WALL, 0.19),
        "attic_ceiling": mr.insulation_thickness(mr.U_ATTIC_CEILING, 0.10),
        "ground_floor": mr.insulation_thickness(mr.U_SLAB, 0.25),
    }
    for name, thickness in expected.items():
        changed, changes = det.apply_measures(grounded, [measures[name]])
        assert len(changes) == 1, changes
        assert changes[0]["insulation_m"] == pytest.approx(thickness, rel=1e-6)
        layers = changed.constructions[f"{changes[0]['construction']} + {name}"].layers
        if name == "walls":  # between the stucco and the block, as in EnergyPlus
            assert layers[0] == "A1 - 1 IN STUCCO" and layers[2] == "CB11"
        if name == "attic_ceiling":  # on the attic side; the attic's floor mirrored
            assert layers[0].startswith("attic_ceiling insulation")
            partner = changed.surfaces["Attic:LivingFloor"].construction
            assert changed.constructions[partner].layers == tuple(reversed(layers))
        if name == "ground_floor":  # under the concrete, on the ground section
            assert layers[0].startswith("ground_floor insulation") and layers[1] == "CC03"
    # only the heated zone: the garage's walls and floor keep their constructions
    changed, _ = det.apply_measures(grounded, [measures["walls"]])
    assert changed.surfaces["Garage:EastWall"].construction == "EXTWALL:GARAGE"
    assert sorted(det.measure_surfaces(grounded, "walls")) == sorted(
        ["Living:North", "Living:East", "Living:South", "Living:West"]
    )


def test_windows_get_the_simple_glazing_model(house):
    _, grounded, _ = house
    changed, changes = det.apply_measures(grounded, [_measures()["windows"]])
    new = changed.window_types[changed.windows["SouthWindow"].window_type]
    assert new.u_value == pytest.approx(0.76)
    assert new.shgc == pytest.approx(0.50, abs=0.01)
    assert changes[0]["area_m2"] == pytest.approx(4 * 4.572 * 1.524, rel=1e-6)


def test_foundation_floors_get_their_ground_section(house):
    """The import gives each floor on Kiva's Foundation its two-dimensional ground section
    (thermocal.multizone.foundation): the file's exposed perimeters (49.12 and 19.12 m), its
    footing wall (EXTWALL:GARAGE: block inside, stucco outside) and, without a
    Foundation:Kiva:Settings object, EnergyPlus's own soil (0.864 W/(m K))."""
    building, _, notes = house
    for name, perimeter in (("Living:Floor", 49.121), ("Garage:Floor", 19.115)):
        assert building.surfaces[name].boundary == "ground"
        ground = building.foundations[name]
        assert ground.exposed_perimeter == pytest.approx(perimeter)
        assert ground.soil == (0.864, 1510.0, 1260.0)
        assert [round(layer[0], 4) for layer in ground.wall_layers] == [0.2032, 0.0254]
        assert ground.wall_height_above_grade == 0.2
    assert any("EnergyPlus's own soil (conductivity 0.864" in n for n in notes)
    assert "Foundation:Kiva" not in building.idf_info.unsupported


def test_bad_measures_are_refused_with_a_clear_message(house):
    _, grounded, _ = house
    with pytest.raises(ThermocalInputError, match="does not improve construction 'EXTWALL"):
        det.apply_measures(grounded, [Measure("walls", "walls", u_value=3.0)])
    with pytest.raises(ThermocalInputError, match="no such surface.*components found: walls"):
        det.apply_measures(grounded, [Measure("cellar", "cellar_ceiling", u_value=0.2)])
    with pytest.raises(ThermocalInputError, match="not available with the detailed model"):
        det.apply_measures(grounded, [Measure("tight", "airtightness", air_change_rate_change=-1)])
    with pytest.raises(ThermocalInputError, match="not found"):
        det.load_detailed_building(REF / "no_such_house.idf")


@pytest.fixture(scope="module")
def house_strategies():
    """The 16 strategies of the NREL house with the detailed model (about 8 s)."""
    from thermocal.io.weather import read_weather
    from thermocal.retrofit.strategies import all_strategies

    weather, meta = read_weather(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"))
    measures = _measures()
    strategies = all_strategies(tuple(measures))
    building = det.load_detailed_building(IDF)
    return det.simulate_strategies(building, weather, meta, strategies, measures, source=IDF)


@pytest.fixture(scope="module")
def year_run(house_strategies):
    """The house as it is and its four single measures (of the 16 strategies)."""
    result, ref = house_strategies, _reference()
    assert any("Foundation floors" in n for n in result.notes)
    return {
        s.measures[0] if s.measures else "none": (kwh, sav, ref["annual_heating_kWh"], ref)
        for s, kwh, sav in zip(result.strategies, result.annual_kwh, result.saving_pct, strict=True)
        if len(s.measures) <= 1
    }


@pytest.mark.slow
@pytest.mark.parametrize("folder", ["retrofit_energyplus_house", "retrofit_energyplus_basement"])
def test_the_reports_detailed_track_record_is_this_run(folder, request):
    """The detailed report states how the detailed model held on the two EnergyPlus houses
    (``thermocal.retrofit.track_record.DETAILED_CHECKS``); a change that moves a figure beyond
    its rounding fails here, so the report never states a stale record."""
    from thermocal.retrofit.track_record import (
        DETAILED_CHECKS,
        differs_from,
        measured_detailed_check,
    )

    if folder == "retrofit_energyplus_house":
        result, ref = request.getfixturevalue("house_strategies"), _reference()
    else:
        _, result, ref = request.getfixturevalue("basement_year")
    measured = measured_detailed_check(result, ref, tuple(ref["measures"]))
    assert not differs_from(DETAILED_CHECKS[folder], measured), measured


def _spun_up() -> dict:
    """EnergyPlus's second year (Kiva's ground after a year of the house, make_reference.py
    --ground-dynamics): the periodic state the detailed retrofit's warm-up year reaches."""
    return json.loads((REF / "ground_dynamics.json").read_text())


@pytest.mark.slow
def test_baseline_demand_within_10_percent_of_energyplus(year_run):
    kwh, _, ref_kwh, _ = year_run["none"]
    spun_up = _spun_up()["reference"]["second_year"]["heating_kWh"]
    # measured (Kiva's exterior boundary: the foundation wall's sun above the grade, the grade's
    # convection and long-wave every step): 9,437 kWh against EnergyPlus's spun-up 10,005
    # (-5.7 %; its first year 10,302, -8.4 %). With one grade coefficient and no wall sun
    # 9,793 (-2.1 %), partly by compensation: the floors adiabatic, 9,208 against 9,195 kWh in
    # both engines. Before, the ISO 13370 soil layer at 2.0 W/(m K) gave 10,387 (+0.8 %) by
    # compensation: at the file's soil (0.864) it gave 8,959 (-13 %).
    assert kwh == pytest.approx(spun_up, rel=0.10)
    assert kwh == pytest.approx(9437, rel=0.03)


@pytest.mark.slow
@pytest.mark.parametrize("measure", ["attic_ceiling", "windows", "walls", "ground_floor"])
def test_saving_within_3_points_of_energyplus(year_run, measure):
    _, saving, _, ref = year_run[measure]
    # measured (Kiva's exterior boundary in the ground section): attic ceiling 6.4 vs 5.3 %,
    # windows 20.1 vs 20.8 %, walls 61.3 vs 59.3 %, slab 1.1 vs 0.7 % (EnergyPlus's spun-up
    # year -0.4 %; 6.2, 19.4, 59.5 and 2.2 % with one grade coefficient). With the ISO 13370
    # soil layer before: 5.2, 18.5, 56.4 and 12.8 %.
    assert saving == pytest.approx(ref["saving_pct"][measure], abs=3.0)


@pytest.mark.slow
def test_slab_saving_against_the_spun_up_energyplus(year_run):
    kwh, saving, _, _ = year_run["ground_floor"]
    runs = _spun_up()
    base = runs["reference"]["second_year"]["heating_kWh"]
    slab = runs["reference_slab"]["second_year"]["heating_kWh"]
    assert saving == pytest.approx(100.0 * (1.0 - slab / base), abs=3.0)  # 1.1 vs -0.4 %


BASEMENT = REF.parent / "retrofit_energyplus_basement"


@pytest.fixture(scope="module")
def basement_year():
    """The DOE/PNNL prototype with its unheated basement on Kiva (the second EnergyPlus
    twin): its 16 strategies with the detailed model, a year of Zurich 2015 after a warm-up
    year (about 11 s)."""
    from thermocal.io.weather import read_weather
    from thermocal.retrofit.strategies import all_strategies

    weather, meta = read_weather(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"))
    ref = json.loads((BASEMENT / "reference.json").read_text())
    measures = {
        name: Measure(name=name, component=name, u_value=m["u_value"], g_value=m.get("g_value"))
        for name, m in ref["measures"].items()
    }
    strategies = all_strategies(tuple(measures))
    building = det.load_detailed_building(BASEMENT / "house_v25.idf")
    result = det.simulate_strategies(
        building, weather, meta, strategies, measures, source=BASEMENT / "house_v25.idf"
    )
    return building, result, ref


@pytest.mark.slow
def test_basement_house_against_energyplus(basement_year):
    """A basement on Kiva (walls and floor on one Foundation:Kiva): the import gives the floor
    its ground section with the four walls' outside faces beside the soil. Measured with Kiva's
    grade convection and long-wave every step: baseline 9,223 kWh against EnergyPlus's 9,297
    (-0.8 %; -1.1 % with one grade coefficient), every one of the 16 strategies within 0.3 pp
    (docs/retrofit.md). Before (floor and walls adiabatic, the roofs' long-wave from
    the file's view factor): +3.0 %, the cellar ceiling +0.9 pp."""
    building, result, ref = basement_year
    ground = building.foundations["Extfloor_unit1"]
    assert ground.basement_depth == pytest.approx(2.134, abs=0.01)
    assert {w for w, _ in ground.walls} == {
        "BGWall_lower_ldf", "BGWall_lower_sdr", "BGWall_lower_ldb", "BGWall_lower_sdl"
    }  # fmt: skip
    assert sum(share for _, share in ground.walls) == pytest.approx(1.0)
    assert result.annual_kwh[0] == pytest.approx(ref["annual_heating_kWh"]["none"], rel=0.05)
    for strategy, saving in zip(result.strategies[1:], result.saving_pct[1:], strict=True):
        key = "+".join(m for m in ref["measures"] if m in strategy.measures)
        assert saving == pytest.approx(ref["saving_pct"][key], abs=1.0), key


@pytest.mark.slow
def test_basement_temperature_against_energyplus(basement_year):
    """The unheated basement's monthly air temperature against EnergyPlus's (reference.json):
    January-March +0.9 to +1.2 K; the summer warmer by up to 1.7 K (July; 2.8 K while the
    grade had one coefficient at the year's mean wind and a linearised long-wave: Kiva takes
    both every step, as the section's lagged correction now does); the walls' one outside node
    (Kiva's face varies with depth) is the remaining candidate."""
    import pandas as pd  # noqa: PLC0415

    from thermocal.io.weather import read_weather
    from thermocal.multizone import Simulation
    from thermocal.retrofit.detailed import _with_year_before

    building, _, ref = basement_year
    weather, meta = read_weather(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"))
    both, start = _with_year_before(weather)
    sim = Simulation(building, both, meta, step="15min", store_surfaces=False)
    air = sim.run().air_temperature["unheatedbsmt_unit1"]
    monthly = air[air.index >= start].resample("MS").mean().to_numpy()
    energyplus = ref["basement"]["none"]["basement_C_monthly"]
    assert len(monthly) == 12 and isinstance(air.index, pd.DatetimeIndex)
    for month in range(3):
        assert monthly[month] == pytest.approx(energyplus[month], abs=1.6), month
    assert max(monthly - energyplus) < 2.2


@pytest.mark.slow
def test_cli_detailed_only_writes_economics(tmp_path):
    weather = shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
    cfg = {
        "weather": {"file": str(weather)},
        "measures": {"windows": {"u_value": 0.76, "g_value": 0.5, "cost_per_m2": 800}},
        "economics": {"energy_price": 0.2, "system_efficiency": 0.9},
    }
    (tmp_path / "cfg.yaml").write_text(yaml.safe_dump(cfg))
    args = ["retrofit", str(tmp_path / "cfg.yaml"), "--detailed", str(IDF), "--detailed-only"]
    result = CliRunner().invoke(app, [*args, "--out", str(tmp_path / "r")])
    assert result.exit_code == 0, result.output
    res = json.loads((tmp_path / "r" / "results.json").read_text())["detailed_model"]
    base, win = res["scenarios"]
    # the economics of the RC workflow: cost saving = saved useful heat / efficiency x price
    saved = base["annual_kWh"] - win["annual_kWh"]
    assert win["economics"]["cost_saving_per_year"] == pytest.approx(saved / 0.9 * 0.2)
    assert win["economics"]["investment"] == pytest.approx(800 * 4 * 4.572 * 1.524, rel=1e-6)
    assert res["recommendation"] == "1"
    csv = pd.read_csv(tmp_path / "r" / "strategies_detailed.csv")
    assert list(csv["code"].astype(str)) == ["0", "1"]
    report = (tmp_path / "r" / "report.html").read_text()
    assert "Retrofit on the detailed model" in report and "Recommended strategy 1" in report


def test_cli_detailed_only_needs_a_building(tmp_path):
    (tmp_path / "cfg.yaml").write_text("weather: {file: w.epw}\n")
    result = CliRunner().invoke(app, ["retrofit", str(tmp_path / "cfg.yaml"), "--detailed-only"])
    assert isinstance(result.exception, ThermocalInputError)  # main() prints it, exit 2
    assert "--detailed-only needs --detailed" in str(result.exception)


@pytest.mark.slow
def test_yaml_building_walls_saving_matches_its_steady_state(tmp_path):
    """A thermocal building YAML (the demo's 9-zone house, as ``thermocal calibrate`` writes
    one): the walls measure's saving over three cold January weeks equals the change of the
    model's steady-state heat loss coefficient times the degree-hours (heating on all the time)
    within 15 % (measured 2026-11-25: 1,300 vs 1,214 kWh, +7 %; TARP's extra interior
    convection at large temperature differences is not in the steady coefficient)."""
    from thermocal.demos import buildings as generators
    from thermocal.io.weather import read_weather
    from thermocal.multizone import save_building, steady_state_heat_loss_coefficient
    from thermocal.retrofit.strategies import paper_measures

    weather, meta = read_weather(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"))
    save_building(generators.single_family_house(), tmp_path / "house.yaml")
    building = det.load_detailed_building(tmp_path / "house.yaml")
    measures = paper_measures()
    assert len(det.measure_surfaces(building, "walls")) == 20
    assert len(det.measure_surfaces(building, "cellar_ceiling")) == 3
    strategies = [Strategy("0", ()), Strategy("1", ("walls",))]
    result = det.simulate_strategies(
        building, weather, meta, strategies, measures, start="2015-01-05", end="2015-01-26"
    )
    walls, _ = det.apply_measures(building, [measures["walls"]])
    dh = steady_state_heat_loss_coefficient(building) - steady_state_heat_loss_coefficient(walls)
    te = weather["temp_air"].loc["2015-01-05":"2015-01-25 23:00"]
    assert te.mean() < 5.0  # a cold spell: the heating runs nearly all the time
    expected = dh * float((20.0 - te).sum()) / 1000.0
    saved = result.annual_kwh[0] - result.annual_kwh[1]
    assert saved == pytest.approx(expected, rel=0.15)


def test_a_building_without_set_points_needs_one():
    """A calibrated_building.yaml carries no set points (calibrate identifies the heat):
    refused with the remedy; --setpoint heats every zone of such a building (and is refused
    for a building that already heats some: its unheated cellar stays unheated)."""
    from thermocal.demos import buildings as generators

    free = generators.single_family_house(heating_setpoint=None)
    index = pd.date_range("2015-01-01", periods=8760, freq="h")
    weather = pd.DataFrame({"temp_air": 5.0, "dni": 0.0, "dhi": 0.0}, index=index)
    with pytest.raises(ThermocalInputError, match="no zone with a heating set point.*--setpoint"):
        det.simulate_strategies(free, weather, {}, [Strategy("0", ())], {})
    heated = det.with_heating_setpoint(free, 21.0)
    assert all(z.heating_setpoint == 21.0 for z in heated.zones.values())
    with pytest.raises(ThermocalInputError, match="already heats 8 zone"):
        det.with_heating_setpoint(generators.single_family_house(), 21.0)
    with pytest.raises(ThermocalInputError, match="not an indoor temperature"):
        det.with_heating_setpoint(free, 293.15)


def test_both_models_side_by_side(tmp_path, capsys):
    """With --detailed beside the RC analysis: results.json keeps the RC results and gains
    'detailed_model'; the summary and report_detailed.html show the RC saving beside."""
    from thermocal.commands.retrofit import _add_detailed, print_detailed_summary
    from thermocal.retrofit.config import EconomicsConfig

    strategies = [Strategy("0", ()), Strategy("1a", ("walls",))]
    result = det.DetailedRetrofitResult(
        strategies=strategies,
        annual_kwh=np.array([10_000.0, 6_000.0]),
        monthly_kwh=pd.DataFrame({"0": [1000.0] * 10, "1a": [600.0] * 10}, index=range(1, 11)),
        changes={"0": [], "1a": []},
        areas={"walls": 100.0},
        building_name="house",
        source="house.yaml",
        heated_zones=["living"],
        step="15min",
    )

    class Cfg:
        economics = EconomicsConfig()

        @staticmethod
        def measure_objects():
            return {"walls": Measure("walls", "walls", u_value=0.2, cost_per_m2=250.0)}

    out = det.detailed_results(result, Cfg())
    assert out["scenarios"][1]["saving_pct"] == pytest.approx(40.0)
    assert out["scenarios"][1]["economics"]["investment"] == pytest.approx(25_000.0)
    # 4,000 kWh of useful heat / 0.85 x 0.12 CHF/kWh (the default economics)
    assert out["scenarios"][1]["economics"]["cost_saving_per_year"] == pytest.approx(
        4000 / 0.85 * 0.12
    )
    rc = {"heat_loss_coefficient_W_per_K": {"value": 300.0}, "scenarios": [
        {"code": "0", "saving_pct": 0.0}, {"code": "1a", "saving_pct": 35.5}]}  # fmt: skip
    (tmp_path / "results.json").write_text(json.dumps(rc))
    _add_detailed(tmp_path, out, "report_detailed.html")
    both = json.loads((tmp_path / "results.json").read_text())
    assert both["heat_loss_coefficient_W_per_K"]["value"] == 300.0
    assert both["detailed_model"]["annual_heating_demand_kWh"] == 10_000.0
    assert "35.5" in (tmp_path / "report_detailed.html").read_text()
    print_detailed_summary(out, rc)
    printed = capsys.readouterr().out
    assert "RC %" in printed and "35.5" in printed and "40.0" in printed
    assert max(len(line) for line in printed.splitlines()) <= 80
