"""``thermocal calibrate`` against EnergyPlus 25.2 on the large building it did not write.

The twin (``tests/reference/calibration_energyplus_outpatient``): the DOE outpatient prototype (118
zones on three storeys) run by EnergyPlus for January free float with its loads and the hidden
envelope of issue 26: wall insulation R / 1.5, roof insulation R / 0.6, every infiltration object
x1.4; the air temperatures of 87 zones (committed, 10 minutes, 0.01 K) are the sensor log, the other
31 float. thermocal gets the nominal IDF with its load objects, the identified heat in the form they
declare (the floating zones keep the file's loads), Chicago O'Hare's TMY3 and the log, and
calibrates the exterior wall's and the roof's resistance with the zone-group metric (24 Sobol'
samples, 30-minute steps, January 4-31: leaner than the script's 32 samples at 10 minutes, same
findings). The infiltration is not varied here (the element level offers one parameter per zone, 56
of them: the twin's script varies them all, ``results.md``); its x1.4 is a model error the wall may
absorb, since the file's infiltration is a flow per exterior-wall area.

Targets (issue 26 item 7): the element resistances the posterior declares determined within 15 % of
the truth, their 90 % intervals covering it, the confirmed metric within 1.2x the true envelope's
and never below it without a flag. Measured 2026-11-30 with the series meta-model in the physical
coordinates (the default since then): wall 1.207 m2 K/W, median 1.179 [1.086, 1.289] (truth 1.355,
-10.9 %), roof 4.524, 4.388 [3.948, 4.626] (truth 4.391, +3.0 %), both determined, the wall's
interval missing the truth (strict xfail below: the unvaried infiltration), metric 0.976x the true
envelope's, flagged. In log p, measured 2026-11-29 (this test's campaign, 16 s on a quiet 2-core
machine, the independent hours counted by the longer of the residual's integrated and lag-1
autocorrelation times): wall 1.309 m2 K/W [1.179, 1.454] (truth 1.355, -3.4 %), roof 4.006 [3.733,
4.300] (truth 4.391, -8.8 %), both determined, the roof's interval missing the truth (then a strict
xfail); metric 0.998x the true envelope's, flagged "below model error" (2026-11-28, by the lag-1
autocorrelation: wall 1.273 [1.173, 1.385], roof 4.029 [3.792, 4.273]). The script's campaign (32
samples, 10 minutes): wall -2.9 % covered, roof -7.7 % [3.831, 4.285] missed, metric 1.002x. With
the building-total metric nothing is determined (the script's ``results_fixed_infiltration.md``).

A heavy reference run (71-98 s): it runs with ``THERMOCAL_REFERENCE_RUNS=1`` only.
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

import pytest
from twin_checks import check_metric_near_the_true_envelope

from conftest import load_script, reference_run, requires_energyplus

REFERENCE = Path(__file__).resolve().parents[1] / "reference"
FOLDER = REFERENCE / "calibration_energyplus_outpatient"

pytestmark = [pytest.mark.slow, requires_energyplus, reference_run]

SAMPLES = 24
STEP = "30min"


def _twin_script():
    """The outpatient twin's script, loaded from its file (the 5-zone twin's script has the
    same module name and is imported by it as ``calibrate_twin``)."""
    needed = (
        REFERENCE / "identification_outpatient" / "outpatient_FF_v25.idf",
        FOLDER / "sensors.csv.gz",
        FOLDER / "truth.json",
    )
    missing = [p.name for p in needed if not p.exists()]
    if missing:
        pytest.skip(f"the outpatient twin's files are absent: {missing}")
    sys.path.insert(0, str(REFERENCE / "calibration_energyplus_5zone"))
    return load_script(FOLDER / "calibrate_twin.py", "calibrate_twin_outpatient")


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """The campaign over wall and roof resistance with the zone-group metric."""
    ct = _twin_script()
    base = ct.base
    base.WALL, base.ROOF = ct.WALL, ct.ROOF  # the pair whose posterior correlation is reported

    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate

    folder = tmp_path_factory.mktemp("calibration_outpatient")
    path = ct.prepare(
        folder,
        SAMPLES,
        include=(ct.WALL, ct.ROOF),
        step=STEP,
        extra="metamodel: {kind: series}\nmetric: groups\n",
    )
    truth_file = json.loads((FOLDER / "truth.json").read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        campaign = load_campaign(path)
        result = calibrate(
            campaign, workers=1, store_path=folder / "s.sqlite", progress=False, log=lambda s: 0
        )
        out = base.summarise(result, campaign, truth_file, "groups")
        # the same samples with the unvaried infiltration given as uncertain (posterior:
        # {uncertain: auto}): one more model run
        uncertain = folder / "uncertain.yaml"
        uncertain.write_text(path.read_text() + "posterior: {uncertain: auto}\n")
        campaign = load_campaign(uncertain)
        again = calibrate(
            campaign,
            workers=1,
            store_path=folder / "s.sqlite",
            resume=True,
            progress=False,
            log=lambda s: 0,
        )
        out["uncertain"] = base.summarise(again, campaign, truth_file, "groups")
        out["uncertain_posterior"] = again.posterior
        return out


def _rows(summary) -> dict:
    return {r["parameter"].split("/")[1]: r for r in summary["rows"]}


def test_the_groups_determine_wall_and_roof_within_15_percent(twin):
    rows = _rows(twin)
    for name in ("Steel Frame Non-res Ext Wall", "IEAD Non-res Roof"):
        assert rows[name]["determined"], rows[name]
        assert abs(rows[name]["error"]) <= 0.15, rows[name]


@pytest.mark.xfail(
    strict=True,
    reason="measured 2026-11-30 with the series meta-model in the physical coordinates (the "
    "default): the wall's resistance is determined at 1.207 m2 K/W (median 1.175), 90 % "
    "interval [1.086, 1.289], against a truth of 1.355 (-10.9 %, inside the 15 % target): the "
    "interval ends 5.3 % below. The unvaried infiltration (x1.4 in the truth) is a model error "
    "the wall absorbs; with the curvature term the wall is -9.8 % [1.075, 1.263]; in log p "
    "the wall covered ([1.128, 1.392], -7.5 %) and the roof missed (-8.8 %, [3.732, 4.300]), "
    "the log-linearisation's bias offsetting the infiltration's on the wall",
)
def test_the_wall_interval_covers_the_truth(twin):
    row = _rows(twin)["Steel Frame Non-res Ext Wall"]
    assert row["covers"], row


def test_the_roof_interval_covers_the_truth(twin):
    """Measured 2026-11-30 (physical coordinates): roof 4.524 m2 K/W, median 4.369 [3.924,
    4.624] against 4.391 (+3.0 %). In log p its interval lay wholly below the truth: 4.006
    [3.733, 4.300] (-8.8 %; a strict xfail until 2026-11-30)."""
    row = _rows(twin)["IEAD Non-res Roof"]
    assert row["covers"], row


def test_the_metric_ends_near_the_true_envelope_and_never_below_it_unflagged(twin):
    check_metric_near_the_true_envelope(twin)


def test_the_reports_track_record_is_this_run(twin):
    """The calibration report states how the default calibration held on this building
    (``thermocal.calibration.track_record``); a change that moves a figure beyond its rounding
    fails here, so the report never states a stale record."""
    from calibrate_twin import check_track_record  # the 5-zone twin's script, on the path

    check_track_record(twin, "calibration_energyplus_outpatient")


def test_infiltration_given_as_uncertain_is_named_as_the_walls_twin(twin):
    """With ``posterior: {uncertain: auto}`` (the building's infiltration, not varied, x1.4 in
    the truth, uncertain by 40 %) the wall is no longer called determined: this file's
    infiltration is a flow per exterior-wall area, whose change of the unoccupied heat is much
    the wall's (their signatures' correlation about -0.87), so in the joint posterior the two
    compensate each other and the wall is set by the infiltration's prior, not by the data
    (measured 2026-11-29: 2.080 [1.723, 2.512] m2 K/W against a truth of 1.355, nominal 1.947).
    The roof stays determined: 3.956 [3.686, 4.247], truth 4.391, still missed."""
    from thermocal.multizone.parameters import INFILTRATION_FACTOR

    rows = _rows(twin["uncertain"])
    assert not rows["Steel Frame Non-res Ext Wall"]["determined"]
    assert rows["IEAD Non-res Roof"]["determined"]
    (item,) = twin["uncertain_posterior"].uncertain
    assert item["label"] == INFILTRATION_FACTOR and item["rel_std"] == 0.4
    wall = "construction/Steel Frame Non-res Ext Wall/resistance"
    assert list(item["compensates"]) == [wall]
    words = " ".join(twin["uncertain_posterior"].sentences())
    assert "compensate each other" in words and "pressurisation test" in words
