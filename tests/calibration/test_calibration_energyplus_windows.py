"""``thermocal calibrate`` against EnergyPlus 25.2 with hidden windows, floor and roof.

The twin (``tests/reference/calibration_energyplus_5zone_windows``): NREL's 5ZoneAirCooled, the
building of ``test_calibration_energyplus.py``, with a second hidden envelope: the offices'
double glazing given a low-e inner pane (emissivity 0.1 towards the gap, solar transmittance
0.70), so that the U-value thermocal reads moves from 2.725 to 1.794 W/(m2 K) (-34 %) and the
SHGC from 0.764 to 0.744; the ground floor slab's resistance x2 (0.078 -> 0.155 m2 K/W: the
offices float at 18-20 C, below the file's 20 C ground, so the floor moves them, by 0.2-0.6 K
on average alone, ``screen.json``); the roof insulation's resistance x0.7 (3.547 -> 2.553).
Walls and infiltration as in the file. thermocal gets the nominal IDF without its loads, the
weather and the log (6 zones, 5 minutes, 0.01 K) and calibrates, as a user would with the
defaults, the wall's, roof's and floor's resistance, the glazing's U-value and SHGC and one
factor on the infiltration (48 Sobol' samples, +-75 %, 15-minute steps, January 4-31, the
zone-group metric).

Targets (issue 26 item 7): the element resistances and window U the posterior declares determined
within 15 % of the truth, their 90 % intervals covering it, the confirmed metric within 1.2x the
true envelope's and never below it without a flag. Measured 2026-11-30 with the series meta-model
in the physical coordinates (the default since then: each construction's conductance, the window's
U and SHGC and the infiltration factor themselves; the prior uniform in each parameter;
``results.md``): roof 2.604 m2 K/W, median 2.599 [2.465, 2.768] (truth 2.553, +2.0 %, covered); the
wall not determined (it trades with the window U: median 2.444 [1.718, 3.613], 52 % of its range),
left nominal, which is its truth; floor 0.136 (truth 0.155, -12.5 %, at the default range's upper
bound, flagged, missed); window U 1.98, 1.87 [1.32, 2.32] (truth 1.794, +10.4 %, covered); SHGC
0.875 (truth 0.744, +17.7 %) at the glazing's limit, flagged as the model's limit; infiltration
factor +8.7 %, covered; metric 0.773x the true envelope's, the model's own minimum within the
ranges, flagged at those two bounds. Before, in log p (the published coordinates, same samples):
roof +19.1 % [2.905, 3.309] missed, wall called determined at -16.9 %, window U -10.6 %, metric
0.952x (the strict xfails of the roof and the wall until 2026-11-30). The floor's miss is a strict
xfail below, the SHGC at its limit a tested flag. A heat-flux plate on the wall, which the
measurement advice ranks first, determines the wall (wall and window U within 15 %, both covered).

A heavy reference run (about 20 s): it runs with ``THERMOCAL_REFERENCE_RUNS=1`` only.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from twin_checks import check_metric_near_the_true_envelope

from conftest import load_script, reference_run, requires_energyplus, shared_data_path

FOLDER = Path(__file__).resolve().parents[1] / "reference" / "calibration_energyplus_5zone_windows"

pytestmark = [pytest.mark.slow, requires_energyplus, reference_run]

SAMPLES = 48

ROOF, WALL = "construction/ROOF-1/resistance", "construction/WALL-1/resistance"
FLOOR = "construction/FLOOR-SLAB-1/resistance"
WINDOW_U = "window/Dbl Clr 3mm/13mm Air/u_value"


def _twin_script():
    """This twin's ``calibrate_twin.py``, loaded from its file (the 5-zone twin's script has
    the same module name)."""
    return load_script(FOLDER / "calibrate_twin.py", "calibrate_twin_windows")


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """The default campaign (zone-group metric, +-75 %) summarised against the truth."""
    shared = shared_data_path("energyplus_reference")
    ct = _twin_script()
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import reanalyse

    folder = tmp_path_factory.mktemp("calibration_5zone_windows")
    path = ct.prepare(folder, SAMPLES, shared=shared)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        campaign = load_campaign(path)
        result, _ = ct.base.timed_calibration(campaign, folder, workers=1, resume=False)
        summary = ct.base.summarise(result, campaign, ct.truth_file(), "groups")
        # which heat-flux plate would settle what, from the same posterior (no simulation)
        advised = folder / "advice.yaml"
        advised.write_text(path.read_text() + "posterior: {advise: true}\n")
        summary["advice"] = reanalyse(
            load_campaign(advised), folder / "campaign.sqlite", log=lambda s: 0
        ).posterior.advice
    summary["by_name"] = {r["parameter"]: r for r in summary["rows"]}
    summary["folder"], summary["campaign_text"] = folder, path.read_text()
    return summary


#: The in-situ wall measurement (``make_reference.py --heat-flux``: EnergyPlus's north office
#: wall BACK-1, ISO 9869-1 with surface temperatures, January 4-17, the plate 3 % high).
WALL_PLATE = f"""in_situ:
  construction/WALL-1/resistance:
    file: {FOLDER / "heat_flux_wall.csv"}
    columns: {{heat_flux: q_W_m2, temp_in: Tsi, temp_out: Tse}}
    temperatures: surface
"""


@pytest.fixture(scope="module")
def wall_plate(twin):
    """The default campaign's samples with the wall plate in the posterior (``--resume``:
    nothing sampled again; the posterior's median confirmed with the model)."""
    ct = _twin_script()
    from thermocal.calibration.config import load_campaign

    folder = twin["folder"]
    path = folder / "wall_plate.yaml"
    path.write_text(twin["campaign_text"] + WALL_PLATE)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        campaign = load_campaign(path)
        result, _ = ct.base.timed_calibration(campaign, folder, workers=1, resume=True)
        summary = ct.base.summarise(result, campaign, ct.truth_file(), "groups")
    summary["by_name"] = {r["parameter"]: r for r in summary["rows"]}
    summary["posterior"] = result.posterior.to_dict()
    summary["calibrated_source"] = result.confirmed["calibrated"].get("source")
    return summary


def _xfail(reason: str):
    return pytest.mark.xfail(strict=True, reason=reason)


ERROR_CASES = [
    pytest.param(ROOF, id="roof"),  # +2.0 % (+19.1 % in log R, the published coordinates)
    pytest.param(FLOOR, id="floor"),  # -12.5 %, at the default range's upper bound
    pytest.param(WINDOW_U, id="window_u"),  # +10.4 % (-10.9 % in log R)
]


@pytest.mark.parametrize("name", ERROR_CASES)
def test_determined_elements_within_15_percent_of_the_truth(twin, name):
    row = twin["by_name"][name]
    assert row["determined"], row
    assert abs(row["error"]) <= 0.15, row


COVER_CASES = [
    pytest.param(ROOF, id="roof"),  # [2.465, 2.768] against 2.553 ([2.905, 3.309] in log R)
    pytest.param(
        FLOOR,
        marks=_xfail(
            "measured 2026-11-30: the floor's truth 0.155 m2 K/W (x2) lies outside the default "
            "+-75 % range (upper bound 0.136); its interval [0.129, 0.136] cannot cover it"
        ),
        id="floor",
    ),
    pytest.param(WINDOW_U, id="window_u"),  # [1.323, 2.319] against 1.794
]


def test_the_wall_that_trades_with_the_window_is_not_called_determined(twin):
    """The wall, unchanged in the truth, and the window U change the same exterior-wall-area
    conduction: measured 2026-11-30 (physical coordinates, the prior uniform in R) the wall's
    90 % interval [1.718, 3.613] m2 K/W spans 52 % of its sampled range, so it is not called
    determined and stays nominal (= its truth, 2.451), its interval covering the truth; in log
    p it was called determined at -16.9 %. A plate on it settles it (below)."""
    row = twin["by_name"][WALL]
    assert not row["determined"] and row["covers"], row
    assert row["calibrated"] == pytest.approx(row["nominal"]), row


def test_walls_windows_and_roof_together(twin):
    """The wall trades with the window U (above); together with the roof their U A to outdoors
    (``posterior.envelope_total``) is determined: measured 2026-11-30, 344.9 W/K [328.8, 361.0]
    against the truth 343.6 (nominal 345.8), 7 % of the prior's 90 % width; the roof and the
    window U are determined alone, the wall is not."""
    total = twin["envelope_total"]["conduction"]
    assert set(total["elements"]) == {"ROOF-1", "WALL-1", "window Dbl Clr 3mm/13mm Air"}
    assert total["elements"]["window Dbl Clr 3mm/13mm Air"] == pytest.approx(51.24, abs=0.01)
    assert total["determined"] and "WALL-1" not in total["separately_determined"], total
    assert total["q05_W_per_K"] <= total["truth_W_per_K"] <= total["q95_W_per_K"], total
    assert total["width_fraction"] < 0.15, total  # (0.075)


@pytest.mark.parametrize("name", COVER_CASES)
def test_determined_intervals_cover_the_truth(twin, name):
    row = twin["by_name"][name]
    assert row["determined"], row
    assert row["covers"], row


def test_the_metric_ends_near_the_true_envelope_and_never_below_it_unflagged(twin):
    check_metric_near_the_true_envelope(twin)


def test_the_floor_outside_the_default_range_is_flagged_at_its_bound(twin):
    """The floor's truth (x2) lies beyond the default +-75 %: the calibration ends at the
    range's upper bound and says the range may be too narrow."""
    texts = " ".join(str(f.get("text", f)) for f in twin["flags"])
    assert "FLOOR-SLAB-1/resistance ends at its upper sampling bound" in texts, texts


@pytest.fixture(scope="module")
def log_coordinates(twin):
    """The default campaign's samples re-analysed with the series meta-model affine in ``log p``
    for every parameter (``metamodel.series_coordinates: log``, the published form; no
    simulation beyond the confirmations of its own candidates)."""
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import reanalyse

    folder = twin["folder"]
    path = folder / "log_coordinates.yaml"
    path.write_text(twin["campaign_text"] + "metamodel: {series_coordinates: log}\n")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = reanalyse(load_campaign(path), folder / "campaign.sqlite", log=lambda s: 0)
    rows = result.posterior.summary
    return {"flags": result.confirmed["flags"], "posterior": rows}


def test_the_roof_in_log_coordinates_is_biased_and_flagged_with_its_remedy(twin, log_coordinates):
    """The roof's error was the series meta-model's straight line in log R, not the forward model
    (``diagnose_forward_bias.py``: the forward model agrees with EnergyPlus element by element):
    the same samples in the published coordinates put the roof's posterior median at +21 %
    (measured 2026-11-30: 3.096 [2.905, 3.309] against 2.553), and the calibration says so,
    with the two forms' out-of-fold errors (67 against 14 W) and the remedy (the physical
    coordinates, the default: +1.8 %, [2.465, 2.768]); in the physical coordinates the
    straight line is not flagged (their out-of-fold error is the curvature's)."""
    median = float(log_coordinates["posterior"].loc[ROOF, "median"])
    truth = json.loads((FOLDER / "truth.json").read_text())["truth"][ROOF]
    assert median / truth - 1.0 > 0.15, median
    (flag,) = [f for f in log_coordinates["flags"] if f.get("kind") == "linearisation"]
    assert flag["quadratic_W"] <= 0.5 * flag["affine_W"], flag
    assert "series_coordinates: physical" in flag["text"] and "--reanalyse" in flag["text"]
    assert not [f for f in twin["flags"] if f.get("kind") == "linearisation"], twin["flags"]
    assert abs(twin["by_name"][ROOF]["median"] / truth - 1.0) < 0.05


def test_the_shgc_stops_at_what_the_glazing_can_give_and_is_flagged_as_the_models_limit(twin):
    """The glazing's optics give at most SHGC 0.8755; the campaign samples no further and the
    SHGC, pulled upward (more sun than EnergyPlus admits through this low-e glazing, see the
    reference's README.md), ends there: flagged as the model's limit, not as a range to widen."""
    row = twin["by_name"]["window/Dbl Clr 3mm/13mm Air/shgc"]
    assert row["calibrated"] <= 0.8756 and row["q95"] <= 0.8756, row
    (flag,) = [f for f in twin["flags"] if f.get("parameter", "").endswith("/shgc")]
    assert flag["at_limit"] and "physical limit" in flag["text"], flag


def test_the_advice_names_a_wall_plate_for_the_wall_window_trade(twin):
    """Every parameter is declared determined, but the wall and the window U compensate each
    other (posterior correlation +0.83) and the wall and the roof (-0.73): the measurement
    advice (``posterior: {advise: true}``, no simulation) ranks a plate on the wall first (no
    plate settles a parameter the data leave open, so the ranking is by how much it narrows
    the intervals). Measured 2026-11-30: a wall plate would narrow the intervals to 11 % of
    the sampled ranges on average, the wall's own from 35 % to 12 %."""
    advice = twin["advice"]
    assert advice["available"]
    assert twin["advice"]["candidates"][0]["parameter"] == WALL
    plate = twin["advice"]["candidates"][0]
    assert plate["expected"][WALL]["width_fraction"] < 0.5 * advice["now"][WALL]["width_fraction"]


def test_a_wall_plate_settles_the_wall_and_the_window_as_the_advice_expected(twin, wall_plate):
    """A real heat-flux plate on EnergyPlus's north office wall (``heat_flux_wall.csv``: ISO
    9869-1 with surface temperatures, two weeks, the plate 3 % high) brings the wall and the
    window U, which traded with each other, within 15 % of the truth with covering intervals,
    and the intervals narrow as the advice expected from the default campaign's posterior
    (their widths in log space within 15 %). Measured 2026-11-30: the plate reads 2.372 m2 K/W
    +- 7.1 % (truth 2.451); posterior medians, their errors and intervals: wall 2.32 (-5.3 %)
    [2.08, 2.59], without the plate 2.073 (-15.4 %) [1.490, 2.783]; window U 1.64 (-8.4 %)
    [1.41, 1.92], without it 1.526 (-15.0 %) [1.179, 1.930] (the calibrated values without the
    plate: -16.9 % and -10.6 %); the calibrated building is the posterior's median, confirmed
    with the model."""
    truth = json.loads((FOLDER / "truth.json").read_text())["truth"]
    measurement = wall_plate["posterior"]["in_situ"][WALL]
    assert measurement["converged"] and measurement["days"] == 14
    assert (
        abs(measurement["resistance_m2K_per_W"] / truth[WALL] - 1)
        < measurement["resistance_rel_std"]
    )
    assert wall_plate["posterior"]["parameters"][WALL]["measured"]
    plates = {c["parameter"]: c for c in twin["advice"]["candidates"]}
    for name in (WALL, WINDOW_U):
        row = wall_plate["by_name"][name]
        assert row["determined"] and row["covers"], row
        assert abs(row["error"]) <= 0.15, row
        expected = plates[WALL]["expected"][name]
        width = np.log(expected["q95"] / expected["q05"])
        real_width = np.log(row["q95"] / row["q05"])
        assert abs(width / real_width - 1.0) < 0.15, (name, width, real_width)
    # the plate determines the wall, which the heat alone left open
    assert not twin["by_name"][WALL]["determined"] and wall_plate["by_name"][WALL]["determined"]
    assert "median" in str(wall_plate["calibrated_source"]), wall_plate["calibrated_source"]


def test_with_the_wall_plate_the_roof_is_within_15_percent(wall_plate):
    """The plate settles the wall; the roof stays where the data put it (it was +19 % with the
    plate too while the meta-model was a straight line in log R: it traded with the floor at
    its range's bound and the SHGC at the glazing's limit, not with the wall)."""
    row = wall_plate["by_name"][ROOF]
    assert row["determined"] and abs(row["error"]) <= 0.15, row


def test_the_zoom_stage_below_the_true_envelope_is_flagged(tmp_path):
    """With the zoom stage (32 local samples) the calibrated metric ends at 0.774x the true
    envelope's (measured 2026-11-30, ``results_zoom32.md``; 0.768x on 2026-11-29), where the
    first stage in the physical coordinates already ends (0.773x): the model's own minimum
    within the ranges, below the truth's because the slab's truth lies beyond its range and the
    SHGC stops at the glazing's limit. Both are flagged at their bounds, which says the
    calibration absorbs an error of the model. (While the meta-model was a straight line in log
    R the model-error floor flagged it too: that floor, the campaign's first stage's
    posterior's 5 % quantile plus the meta-model's out-of-fold error, rested on the
    meta-model's own error, 67 W out of fold then, 14 W now.)"""
    shared = shared_data_path("energyplus_reference")
    ct = _twin_script()
    from thermocal.calibration.config import load_campaign

    path = ct.prepare(tmp_path, SAMPLES, shared=shared, zoom=32)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        campaign = load_campaign(path)
        result, _ = ct.base.timed_calibration(campaign, tmp_path, workers=1, resume=False)
        summary = ct.base.summarise(result, campaign, ct.truth_file(), "groups")
    ratio = summary["calibrated_metric"] / summary["true_metric"]
    assert ratio < 0.9, ratio
    check_metric_near_the_true_envelope(summary)
    bounds = {f["parameter"] for f in summary["flags"] if f.get("kind") == "at bound"}
    assert bounds == {FLOOR, "window/Dbl Clr 3mm/13mm Air/shgc"}, summary["flags"]


def test_the_reports_track_record_is_this_run(twin):
    """The calibration report states how the default calibration held on this building
    (``thermocal.calibration.track_record``)."""
    import sys

    sys.path.insert(0, str(FOLDER.parent / "calibration_energyplus_5zone"))
    from calibrate_twin import check_track_record  # the 5-zone twin's script

    check_track_record(twin, "calibration_energyplus_5zone_windows")
