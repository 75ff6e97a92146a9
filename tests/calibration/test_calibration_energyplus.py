"""``thermocal calibrate`` against EnergyPlus 25.2 on a building thermocal did not write.

The twin (``tests/reference/calibration_energyplus_5zone``): NREL's 5ZoneAirCooled run by
EnergyPlus for January with a hidden envelope, wall insulation resistance x0.6, roof
insulation x1.5 and every zone's infiltration x1.4; its zone air temperatures (committed,
5 minutes, 0.01 K) are the sensor log. thermocal gets the nominal IDF without its loads, the
weather and the log, and calibrates the element-level parameters (exterior wall and roof
resistance, each office's infiltration) with a small campaign (48 Sobol' samples, 15-minute
steps, January 4-31). The truth is what thermocal reads from the perturbed file.

Targets (issue 26 item 7): the element resistances the posterior declares determined within
15 % of the truth, every 90 % interval covering the truth, the confirmed metric within 1.2x
the true envelope's and never below it without a flag. Measured (2026-11-25; the full table
in the reference folder's ``results.md``) with the zone-group metric: roof 4.95 m2 K/W
[4.67, 5.24] (truth 5.20, -4.9 %), wall 1.59 [1.34, 1.88] (truth 1.61, -1.4 %), the core
office's and one perimeter office's infiltration determined within 7 %, every interval covering
the truth, metric 1.06x the true envelope's. With the published building-total metric the data
determine nothing (roof and wall compensate, posterior correlation -0.90), the nominal building
is returned and its metric is 1.30x the true envelope's: that target fails (strict xfail).

With the zoom stage (``sampling.zoom: 32``, off by default: the meta-model refitted on 32
samples in a box around the first answer) the zone-group roof is +1.2 % [4.82, 5.76], the wall
-2.4 % [1.39, 1.88], every interval covering the truth, metric 1.02x the true envelope's
(measured 2026-11-28, ``zoom.md``). Without it, the roof's interval with the zone groups and the
default (published) series meta-model, affine in log p, misses the truth (measured 2026-11-29:
4.86 [4.62, 5.12], truth 5.20, -6.5 %; wall +8.9 %; 2026-11-28, the independent hours by lag 1
alone: 4.87 [4.56, 5.17], wall +7.8 %): the straight line in log R of a heat that
goes as 1 / (R + films) puts the minimum low (``diagnose_roof.md``). With the curvature term
(``metamodel: {kind: series, series_terms: auto}``, the same samples, 6-10 confirmation runs)
the roof is 5.25 m2 K/W (+0.8 %; median 5.23 [4.76, 5.85]), the wall 1.56 (-3.1 %; 1.63 [1.42,
1.91]), three offices' infiltration within 7.4 %, every interval covering the truth, metric
1.02x the true envelope's (1.15x before): a normal test below. Since 2026-11-30 the series
meta-model is affine in each construction's conductance and the offices' air change rates (the
physical coordinates, the default): without the zoom the roof is +2.6 % [4.87, 5.75], the wall
-4.7 % [1.41, 1.84], every interval covering, metric 1.02x. Takes 60-90 s of CPU (the
campaign 6-12 s of it, the default analysis with the GP meta-model's fit and Sobol' indices most
of the rest).
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from twin_checks import check_metric_near_the_true_envelope

from conftest import requires_energyplus, shared_data_path

REFERENCE = Path(__file__).resolve().parents[1] / "reference" / "calibration_energyplus_5zone"
sys.path.insert(0, str(REFERENCE))

pytestmark = [pytest.mark.slow, requires_energyplus]

SAMPLES = 48


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """The campaign with the zone-group metric, then the same samples re-analysed with the
    building-total metric (nothing simulated again)."""
    shared = shared_data_path("energyplus_reference")
    import calibrate_twin as ct

    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate, reanalyse

    folder = tmp_path_factory.mktemp("calibration_5zone")
    path = ct.prepare(folder, SAMPLES, extra="metric: groups\n", shared=shared, zoom=32)
    truth_file = json.loads((REFERENCE / "truth.json").read_text())
    out = {}

    def resume(campaign):  # every sample, and every run the analysis confirms, from the store
        return calibrate(
            campaign, workers=1, store_path=folder / "s.sqlite", resume=True, progress=False,
            log=lambda s: 0,
        )  # fmt: skip

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        groups = load_campaign(path)
        result = calibrate(
            groups, workers=1, store_path=folder / "s.sqlite", progress=False, log=lambda s: 0
        )
        out["groups"] = ct.summarise(result, groups, truth_file, "groups")
        written = folder / "calibrated_building.yaml"
        written.write_text(result.calibrated_building_text(folder))
        out["calibrated"] = (result.calibrated_building, written)
        # the same campaign without the zoom stage (every run read from the store)
        before = folder / "no_zoom.yaml"
        before.write_text(path.read_text().replace("zoom: 32}", "zoom: 0}", 1))
        no_zoom = load_campaign(before)
        result = resume(no_zoom)
        out["groups_no_zoom"] = ct.summarise(result, no_zoom, truth_file, "groups")
        out["no_zoom_runs"] = result.runs
        other = folder / "building.yaml"
        other.write_text(path.read_text().replace("metric: groups\n", "metric: building\n"))
        building = load_campaign(other)
        again = reanalyse(building, folder / "s.sqlite", log=lambda s: 0)
        out["building"] = ct.summarise(again, building, truth_file, "building")
        out["reanalysis_runs"] = again.runs
        # the analysis the real roof plate below enters (no zoom, the building total) asked
        # which heat-flux plate would determine what (no simulation)
        building_text = before.read_text().replace("metric: groups\n", "metric: building\n")
        advised = folder / "building_advice.yaml"
        advised.write_text(building_text + "posterior: {advise: true}\n")
        out["building_advice"] = reanalyse(
            load_campaign(advised), folder / "s.sqlite", log=lambda s: 0
        ).posterior.advice
        curved = folder / "curvature.yaml"
        curved.write_text(
            before.read_text() + "metamodel: {kind: series, series_terms: auto}\n"
        )  # without the zoom: the curvature term's own answer
        curvature = load_campaign(curved)
        result = resume(curvature)
        out["curvature"] = ct.summarise(result, curvature, truth_file, "groups")
        out["curvature_terms"] = result.confirmed["series_metamodel"]["terms"]
        out["curvature_summary"] = result.summary
        # the published building-total metric with a heat-flux plate on the roof (ISO 9869-1,
        # make_reference.py --heat-flux): the same samples, the posterior's median confirmed
        plate = folder / "roof_plate.yaml"
        plate.write_text(building_text + ROOF_PLATE)
        measured = load_campaign(plate)
        result = resume(measured)
        out["roof_plate"] = ct.summarise(result, measured, truth_file, "building")
        out["roof_plate_posterior"] = result.posterior.to_dict()
        from thermocal.calibration.report import write_report

        out["roof_plate_report"] = write_report(result, folder / "roof_plate.html").read_text()
    return out


#: The campaign's in-situ roof measurement (the plate's log beside the twin's files).
ROOF_PLATE = f"""in_situ:
  construction/ROOF-1/resistance:
    file: {REFERENCE / "heat_flux_roof.csv"}
    columns: {{heat_flux: q_W_m2, temp_in: Tsi, temp_out: Tse}}
    temperatures: surface
"""


def _check_elements(summary, *, coverage: bool = True):
    rows = {r["parameter"]: r for r in summary["rows"]}
    determined = [n for n, r in rows.items() if r.get("determined")]
    for name in determined:
        if name.startswith("construction/") and name.endswith("/resistance"):
            assert abs(rows[name]["error"]) <= 0.15, (name, rows[name])
    if coverage:
        _check_coverage(summary)
    return determined


def _check_coverage(summary):
    rows = {r["parameter"]: r for r in summary["rows"]}
    uncovered = [n for n, r in rows.items() if not r.get("covers", True)]
    assert not uncovered, [rows[n] for n in uncovered]


def _check_metric(summary):
    check_metric_near_the_true_envelope(summary)


def test_group_metric_finds_roof_and_walls_of_the_energyplus_twin(twin):
    summary = twin["groups"]
    determined = _check_elements(summary, coverage=False)
    # not vacuous: the data determine both envelope elements the truth changed
    assert {"construction/WALL-1/resistance", "construction/ROOF-1/resistance"} <= set(determined)
    _check_metric(summary)


def test_group_metric_intervals_cover_the_energyplus_twin(twin):
    """With the zoom stage (``sampling.zoom: 32``): measured 2026-11-28, roof +1.2 %
    [4.82, 5.76] (truth 5.203), wall -2.4 % [1.39, 1.88] (truth 1.613), metric 1.02x the true
    envelope's; without it (next test) the roof's interval misses."""
    summary = twin["groups"]
    _check_coverage(summary)
    zoom = summary["zoom"]
    assert zoom is not None and zoom["runs"]["simulated"] == 32
    rows = {r["parameter"]: r for r in summary["rows"]}
    # the first stage's -6 % roof (next test) is gone: within 3 % of the truth
    assert abs(rows["construction/ROOF-1/resistance"]["error"]) <= 0.03, rows


def test_group_metric_intervals_without_the_zoom_cover_the_energyplus_twin(twin):
    """Without the zoom stage (``sampling.zoom: 0``), the first stage's campaign alone: measured
    2026-11-30 with the series meta-model in the physical coordinates (the default): roof +2.6 %
    (median 5.28 [4.87, 5.75], truth 5.203), wall -4.7 % (1.60 [1.41, 1.84], truth 1.613),
    every interval covering, metric 1.02x the true envelope's. In the published coordinates
    (affine in log p) the roof's interval ended below the truth: 4.86 [4.62, 5.12], -6.5 %
    (the log-linearisation of the roof's 1 / (R + films), diagnose_roof.md; a strict xfail
    until 2026-11-30)."""
    assert twin["no_zoom_runs"]["simulated"] == 0  # the first stage's runs, from the store
    assert twin["groups_no_zoom"]["zoom"] is None
    _check_coverage(twin["groups_no_zoom"])


def test_group_metric_with_curvature_finds_and_covers_the_energyplus_twin(twin):
    """The series meta-model with a curvature term per parameter (``series_terms: auto``,
    chosen by its out-of-fold hourly error) on the same samples. Before (affine, the default):
    roof 4.87 [4.56, 5.17] (-6.4 %, the interval missing the truth 5.203), wall +7.8 %,
    metric 1.15x the true envelope's. After (measured 2026-11-28): roof 5.25 (+0.8 %; median
    5.23 [4.76, 5.85]), wall 1.56 (-3.1 %; 1.63 [1.42, 1.91], truth 1.61), every interval
    covering the truth, metric 1.02x (flagged below the model error's 5 % quantile)."""
    summary = twin["curvature"]
    assert twin["curvature_terms"] == "quadratic"
    assert twin["curvature_summary"].evaluated == 0  # the campaign's samples, not sampled again
    determined = _check_elements(summary)
    assert {"construction/WALL-1/resistance", "construction/ROOF-1/resistance"} <= set(determined)
    _check_metric(summary)


def test_building_metric_elements_of_the_energyplus_twin(twin):
    # nothing simulated again; the intervals cover the truth (none is narrow enough to be
    # "determined": the roof and the walls compensate in the building's sum)
    assert twin["reanalysis_runs"].get("simulated", 0) == 0
    _check_elements(twin["building"])


def test_building_metric_determines_roof_and_walls_together(twin):
    """With the building-total metric neither the roof nor the walls is determined, but their
    sum is: the varied constructions' U A to outdoors (``thermocal.calibration.envelope_total``),
    measured 2026-11-30: 216 W/K [180, 252], 21 % of the prior's 90 % width, against the truth
    205.9 W/K. The hidden envelope (wall insulation x 0.6, roof x 1.5) keeps the total (nominal
    206.1 W/K): the building's sum cannot see it, and says so. With the zone groups each one is
    determined and the total 206 W/K [195, 217]."""
    building = twin["building"]["envelope_total"]["conduction"]
    groups = twin["groups"]["envelope_total"]["conduction"]
    assert set(building["elements"]) == {"ROOF-1", "WALL-1"}
    assert building["determined"] and not building["separately_determined"], building
    assert building["width_fraction"] < 0.35, building  # (0.21)
    for total in (building, groups):
        assert total["q05_W_per_K"] <= total["truth_W_per_K"] <= total["q95_W_per_K"], total
    assert abs(building["truth_W_per_K"] / building["nominal_W_per_K"] - 1) < 0.01
    assert set(groups["separately_determined"]) == {"ROOF-1", "WALL-1"}
    # the areas: the roof's and the walls' net opaque exterior areas of 5ZoneAirCooled
    assert building["elements"]["ROOF-1"] == pytest.approx(463.6, abs=0.1)
    assert building["elements"]["WALL-1"] == pytest.approx(213.3, abs=0.1)
    # the five offices' air changes together and everything together (building total): the air
    # 225 W/K [180, 265] is not determined (truth 258.7, nominal 184.8), everything 440 W/K
    # [386, 493] is (truth 464.6); every interval covers its truth
    totals = twin["building"]["envelope_total"]
    assert not totals["air"]["determined"] and totals["all"]["determined"], totals
    for part in ("air", "all"):
        total = totals[part]
        assert total["q05_W_per_K"] <= total["truth_W_per_K"] <= total["q95_W_per_K"], total


@pytest.mark.xfail(
    strict=True,
    reason="measured 2026-11-25: with the building-total metric nothing is "
    "determined, the nominal building is returned, metric 1.30x the true envelope's (target "
    "1.2x)",
)
def test_building_metric_confirmed_within_1_2_of_the_true_envelope(twin):
    _check_metric(twin["building"])


def test_a_roof_plate_determines_roof_and_wall_with_the_building_metric(twin):
    """With the published building-total metric the data determine neither the roof nor the
    wall (they compensate: roof 3.72 [2.44, 5.76], wall 2.49 [1.19, 4.07], truth 5.20 and
    1.61). A heat-flux plate on the roof for two weeks (ISO 9869-1 with surface temperatures,
    EnergyPlus's roof reading 3 % high: 4.99 m2 K/W +- 7.6 %, truth 5.20) determines both: the
    roof by the measurement, the wall through the data's roof-wall combination. Measured
    2026-11-29: roof 4.92 [4.35, 5.56] (-5.4 %), wall 1.68 [1.09, 2.59] (+3.8 %), both covering
    the truth; the calibrated building is the posterior's median."""
    rows = {r["parameter"]: r for r in twin["roof_plate"]["rows"]}
    roof, wall = rows["construction/ROOF-1/resistance"], rows["construction/WALL-1/resistance"]
    plain = {r["parameter"]: r for r in twin["building"]["rows"]}
    assert not plain["construction/ROOF-1/resistance"]["determined"]
    assert not plain["construction/WALL-1/resistance"]["determined"]
    for row in (roof, wall):
        assert row["determined"] and row["covers"], row
        assert abs(row["error"]) <= 0.15, row
    posterior = twin["roof_plate_posterior"]
    assert posterior["parameters"]["construction/ROOF-1/resistance"]["measured"]
    measurement = posterior["in_situ"]["construction/ROOF-1/resistance"]
    assert measurement["converged"] and measurement["days"] == 14
    truth = json.loads((REFERENCE / "truth.json").read_text())["truth"]
    r_true = truth["construction/ROOF-1/resistance"]
    assert abs(measurement["resistance_m2K_per_W"] / r_true - 1) < measurement["resistance_rel_std"]
    report = twin["roof_plate_report"]
    assert "In-situ measurements in the posterior" in report and "heat_flux_roof.csv" in report
    # the element totals' table (roof and walls together)
    assert "The varied elements together" in report and "U A to outdoors" in report


def test_the_advice_names_the_plates_that_determine_roof_and_wall(twin):
    """With the building-total metric, where the data determine neither roof nor wall, the
    measurement advice (``posterior: {advise: true}``, no simulation) says which plate settles
    them: on the wall, both; on the roof, the roof surely and the wall at its outer readings. Its
    expected intervals hold against the real roof plate (EnergyPlus's roof, ISO 9869-1, read at
    4.99 m2 K/W, between the advice's median and upper readings): the log widths of the 90 %
    intervals the real plate gave lie within what the advice expected over its three readings,
    give or take 15 %, for the roof and for the wall. Measured 2026-11-30, in the physical
    coordinates, where the narrowing depends on where the reading falls (the conductance
    coordinate and the range's bounds): roof 0.214 / 0.227 / 0.176 expected at the readings
    2.16 / 3.54 / 5.81 m2 K/W, real 0.244; wall 0.488 / 0.878 / 0.661, real 0.740. 2026-11-29, in
    log p, where it does not: roof 0.23 (real 0.25), wall 0.81 (0.87). The wall plate determines
    both with probability 1."""
    roof, wall = "construction/ROOF-1/resistance", "construction/WALL-1/resistance"
    advice = twin["building_advice"]
    assert advice["available"] and not advice["now"][roof]["determined"]
    assert not advice["now"][wall]["determined"]
    assert [c["parameter"] for c in advice["candidates"]] == [wall, roof]  # most decisive first
    plates = {c["parameter"]: c for c in advice["candidates"]}
    assert plates[wall]["determined_probability"][roof] == 1.0
    assert plates[wall]["determined_probability"][wall] == 1.0
    assert plates[roof]["determined_probability"][roof] == 1.0
    # the wall only after the roof's outer readings (1/6 each), not after its median (after
    # one of them only while the conductance coordinate's prior was uniform in U, 2026-11-30)
    assert plates[roof]["determined_probability"][wall] == pytest.approx(1 / 3)
    assert not plates[roof]["expected"][wall]["determined"]
    assert advice["summary"].startswith("A heat-flux plate on construction WALL-1")
    real = {r["parameter"]: r for r in twin["roof_plate"]["rows"]}
    reading = twin["roof_plate_posterior"]["in_situ"][roof]["resistance_m2K_per_W"]
    readings = np.log(plates[roof]["readings"])
    assert readings[0] < np.log(reading) < readings[-1], (reading, readings)
    for name in (roof, wall):
        widths = [
            np.log(e[name]["q95"] / e[name]["q05"]) for e in plates[roof]["expected_by_reading"]
        ]
        real_width = np.log(real[name]["q95"] / real[name]["q05"])
        assert 0.85 * min(widths) < real_width < 1.15 * max(widths), (name, widths, real_width)


def test_the_reports_track_record_is_this_run(twin):
    """The calibration report states how the default calibration held on this building
    (``thermocal.calibration.track_record``); a change that moves a figure beyond its rounding
    fails here, so the report never states a stale record."""
    from calibrate_twin import check_track_record  # the 5-zone twin's script, on the path

    check_track_record(twin["groups_no_zoom"], "calibration_energyplus_5zone")


def test_the_calibrated_file_of_an_idf_is_the_idf_with_the_calibrated_values(twin):
    """A calibrated building imported from an IDF is written as the IDF and the calibrated
    values: read back it is the calibrated model, with the IDF's schedules, loads, airflows and
    shading (the YAML form dropped them: a twin's round trip ran 1.7-2.9 K colder)."""
    from thermocal.multizone.elements import element_parameters
    from thermocal.multizone.files import load_building

    calibrated, written = twin["calibrated"]
    text = written.read_text()
    assert "\nidf: " in text and "parameters:" in text and "zones:" not in text
    from thermocal.multizone.files import BuildingFileWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        back = load_building(written)
    # the IDF is the one calibrated on: no warning about it
    assert not [w for w in caught if issubclass(w.category, BuildingFileWarning)]
    assert back.idf_info is not None
    assert back.parameters() == pytest.approx(calibrated.parameters(), rel=1e-12)
    assert element_parameters(back) == pytest.approx(element_parameters(calibrated), rel=1e-12)
    assert [z.infiltration_ach for z in back.zones.values()] == pytest.approx(
        [z.infiltration_ach for z in calibrated.zones.values()], rel=1e-12
    )
