"""``thermocal calibrate`` against EnergyPlus 25.2 on a second building it did not write.

The twin (``tests/reference/calibration_energyplus_multifamily``): the PNNL/DOE multifamily
prototype (18 flats on three storeys, breezeway, vented attic) run by EnergyPlus for January with a
hidden envelope: wall insulation R x1.5, attic-floor insulation R x0.6, every effective leakage area
x1.4; its zone air temperatures (committed, 10 minutes, 0.01 K) are the sensor log. thermocal gets
the nominal IDF without its loads, Chicago O'Hare's TMY3 and the log, and calibrates the exterior
wall's and the top flats' ceiling resistance and the attic's infiltration with a small campaign (32
Sobol' samples), with the published building-total metric and the posterior's default
model-discrepancy term (``neighbours``), then the same samples with the (default) zone-group metric
(``--resume``: nothing sampled again, only that metric's optima and refinement run with the model).

Targets (issue 26 item 7): the element resistances the posterior declares determined within 15 % of
the truth, every 90 % interval covering the truth, the confirmed metric within 1.2x the true
envelope's and never below it without a flag. Since 2026-11-29 (evening) the campaign has three
parameters: the ceiling's attic side (``Interior Ceiling (reversed)``), which an earlier campaign
varied as a fourth, is the far side of walls the model builds from ``Interior Ceiling`` and had
no effect (its "covered" interval was the prior's); the changed design moved the intervals
below (the attic's infiltration now misses with both metrics, the wall with the group metric;
since 2026-11-30, windows with ISO 15099's room-side convection as in EnergyPlus, the building
metric's intervals all cover).
Measured 2026-11-28 (re-analyses of
``tests/reference/calibration_discrepancy/measure.py``): every interval covers with both metrics
(without the discrepancy term the attic infiltration, and with the group metric the wall, were
missed). After the forward model's mirrored adiabatic faces and constant infiltration schedule
(issue 28, 2026-11-28) the group metric's attic infiltration interval misses again (+10 %; strict
xfail below). With the posterior sampled to a stated precision (2026-11-28) the building metric's
attic infiltration interval missed too, by 0.7 % of its lower end; since the independent hours are
counted by the residual's integrated autocorrelation time (2026-11-29) it covers, by 0.1 %. The
meta-model is the series model (the posterior uses it whatever the kind; the GP's fit would triple
the time). Needs EnergyPlus only for its weather file.
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

import pytest
from twin_checks import check_metric_near_the_true_envelope

from conftest import load_script, requires_energyplus

REFERENCE = Path(__file__).resolve().parents[1] / "reference"
FOLDER = REFERENCE / "calibration_energyplus_multifamily"

pytestmark = [pytest.mark.slow, requires_energyplus]

SAMPLES = 32
#: The flats' infiltration, which the campaign holds at its nominal value (x1.4 in the truth)
FLATS = "zone/living_unit*/infiltration_ach"


def _twin_script():
    """The multifamily twin's script, loaded from its file (the 5-zone twin's script has the
    same module name and is imported by it as ``calibrate_twin``)."""
    sys.path.insert(0, str(REFERENCE / "calibration_energyplus_5zone"))
    return load_script(FOLDER / "calibrate_twin.py", "calibrate_twin_multifamily")


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """The campaign with the default (building-total) metric, then the zone-group metric on
    the same samples."""
    ct = _twin_script()
    base = ct.base
    base.WALL, base.ROOF = ct.WALL, ct.CEILING  # the pair whose posterior correlation is reported

    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.workflow import calibrate

    folder = tmp_path_factory.mktemp("calibration_multifamily")
    path = ct.prepare(folder, SAMPLES, extra="metamodel: {kind: series}\nmetric: building\n")
    truth_file = json.loads((FOLDER / "truth.json").read_text())
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        campaign = load_campaign(path)
        result = calibrate(
            campaign, workers=1, store_path=folder / "s.sqlite", progress=False, log=lambda s: 0
        )
        out["building"] = base.summarise(result, campaign, truth_file, "building")
        other = folder / "groups.yaml"
        other.write_text(path.read_text().replace("metric: building\n", "metric: groups\n"))
        groups = load_campaign(other)
        again = calibrate(
            groups,
            workers=1,
            store_path=folder / "s.sqlite",
            resume=True,
            progress=False,
            log=lambda s: 0,
        )
        out["groups"] = base.summarise(again, groups, truth_file, "groups")
        out["groups_summary"] = again.summary
        # the flats' infiltration, not varied, given as uncertain: one more model run, then
        # both metrics on the same samples again
        for metric in ("building", "groups"):
            text = path.read_text().replace("metric: building\n", f"metric: {metric}\n")
            uncertain = folder / f"uncertain_{metric}.yaml"
            uncertain.write_text(text + f"posterior: {{uncertain: {{'{FLATS}': 0.4}}}}\n")
            campaign = load_campaign(uncertain)
            result = calibrate(
                campaign,
                workers=1,
                store_path=folder / "s.sqlite",
                resume=True,
                progress=False,
                log=lambda s: 0,
            )
            out[f"uncertain_{metric}"] = base.summarise(result, campaign, truth_file, metric)
            out[f"uncertain_{metric}_posterior"] = result.posterior
    return out


def _uncovered(summary) -> list[dict]:
    """The rows whose 90 % interval misses the truth."""
    return [r for r in summary["rows"] if not r.get("covers", True)]


def _check(summary):
    rows = {r["parameter"]: r for r in summary["rows"]}
    determined = [n for n, r in rows.items() if r.get("determined")]
    for name in determined:
        if name.endswith("/resistance"):
            assert abs(rows[name]["error"]) <= 0.15, (name, rows[name])
    check_metric_near_the_true_envelope(summary)
    return determined


@pytest.mark.parametrize("metric", ["building", "groups"])
def test_calibration_finds_the_multifamily_envelope(twin, metric):
    determined = _check(twin[metric])
    # not vacuous: the data determine the wall and the attic floor the truth changed
    assert {name for name in determined if name.endswith("/resistance")} >= {
        "construction/Exterior Wall/resistance",
        "construction/Interior Ceiling/resistance",
    }


def test_every_interval_covers_the_truth_with_the_building_metric(twin):
    """Every interval reaches the truth within the Monte Carlo precision of its ends (two of
    the reported standard errors). Measured 2026-11-30 with the series meta-model in the
    physical coordinates (the default): wall -0.2 % [3.427, 4.669] (truth 4.011), ceiling -4.9 %
    [3.727, 5.718] (4.737), the attic's infiltration +7.3 % [0.808, 0.975] 1/h (0.827). In log
    p, since windows take ISO 15099's room-side
    convection as in EnergyPlus: the attic's infiltration 0.954 1/h against 0.827 (+15 %),
    interval 0.820-1.026 (covered; it missed by 1.0 % before, a strict xfail), the wall -5.4 %
    and the ceiling +1.1 % covered. History: with a fourth parameter that had no effect (the
    ceiling's attic side, ``Interior Ceiling (reversed)``, the far side of walls the model
    builds from ``Interior Ceiling``) the Sobol' design differed and the attic's interval was
    0.826-1.026 1/h, covering by 0.1 % on 6 of 8 sampler seeds; before the independent hours
    were counted by the integrated autocorrelation time, 0.833-1.027 (a miss of 0.7 %)."""
    for row in twin["building"]["rows"]:
        if "q05" not in row:
            continue
        low = row["q05"] - 2.0 * row["q05_mcse"]
        high = row["q95"] + 2.0 * row["q95_mcse"]
        assert low <= row["truth"] <= high, row


@pytest.mark.xfail(
    strict=True,
    reason="measured 2026-11-30 with the series meta-model in the physical coordinates (the "
    "default): with the zone-group metric the wall -6.7 % (median 3.952 [3.562, 4.422], truth "
    "4.011) covers, the ceiling's calibrated value 4.566 (-3.6 %) but its median 4.001 [3.590, "
    "4.515] ends 4.7 % below the truth 4.737, the attic's infiltration +4.8 % [0.833, 0.906] "
    "(truth 0.827) 0.7 % above. The unvaried flats' infiltration is a model error they absorb; "
    "in log p the wall missed by 3.3 % and the attic by 9 %, the ceiling covered (+6.8 %); "
    "with the curvature term (series_terms: auto) the ceiling and the attic cover and the wall "
    "misses (-13.7 %)",
)
def test_every_interval_covers_the_truth_with_the_group_metric(twin):
    missed = _uncovered(twin["groups"])
    assert not missed, [
        (r["parameter"], r["calibrated"], r["truth"], r.get("p05"), r.get("p95")) for r in missed
    ]


def test_a_calibrated_value_outside_its_own_interval_is_flagged(twin):
    """With the zone-group metric the best confirmed run puts the top-floor ceiling at 4.566
    m2 K/W (-3.6 %), outside its own 90 % interval [3.61, 4.56] (median 4.03, -14.9 %; truth
    4.737; measured 2026-11-30): the calibration says so and names the interval as the answer.
    Nothing inside its interval is flagged that way."""
    rows = {r["parameter"]: r for r in twin["groups"]["rows"]}
    outside = {f["parameter"] for f in twin["groups"]["flags"] if f["kind"] == "outside interval"}
    expected = {
        name
        for name, row in rows.items()
        if row["determined"] and not row["q05"] <= row["calibrated"] <= row["q95"]
    }
    assert outside == expected, (outside, rows)
    assert "construction/Interior Ceiling/resistance" in outside


def test_second_metric_resumes_without_sampling_again(twin):
    summary = twin["groups_summary"]
    assert summary.evaluated == 0 and summary.already_done == SAMPLES


def test_the_reports_track_record_is_this_run(twin):
    """The calibration report states how the default calibration held on this building
    (``thermocal.calibration.track_record``); a change that moves a figure beyond its rounding
    fails here, so the report never states a stale record."""
    from calibrate_twin import check_track_record  # the 5-zone twin's script, on the path

    check_track_record(twin["groups"], "calibration_energyplus_multifamily")


def test_the_flats_infiltration_given_as_uncertain_with_the_group_metric(twin):
    """``posterior.uncertain`` with the flats' infiltration (not varied, x1.4 in the truth) by
    40 %, the zone-group metric: measured 2026-11-30 (physical coordinates), wall median 4.214
    [3.751, 4.713] m2 K/W (truth 4.011) covers (3.952 [3.562, 4.422] without), the ceiling
    4.014 [3.604, 4.529] (4.737) and the attic's infiltration 0.869 [0.833, 0.906] 1/h (0.827)
    miss as without it (in log p on 2026-11-29 the ceiling covered and the attic missed); the
    flats' infiltration compensates none of the three (their signatures' correlation -0.53 with
    the wall at most), so all stay determined and the targets on the values hold (metric 0.932x
    the true envelope's, flagged)."""
    summary = twin["uncertain_groups"]
    _check(summary)
    rows = {r["parameter"]: r for r in summary["rows"]}
    covered = {name for name, row in rows.items() if row["covers"]}
    assert "construction/Exterior Wall/resistance" in covered, rows
    assert all(row["determined"] for row in rows.values()), rows
    (item,) = twin["uncertain_groups_posterior"].uncertain
    assert item["label"] == FLATS and len(item["parameters"]) == 18
    assert item["effect"] and item["compensates"] == {}


def test_the_flats_infiltration_given_as_uncertain_with_the_building_total(twin):
    """The same with the building-total metric: every interval covers (wall 4.265 [3.693,
    4.781], ceiling 4.201 [3.139, 5.630], attic 0.854 [0.673, 1.010]; the attic's missed by
    1.0 % without), but the total cannot tell the flats' infiltration from the wall or the
    attic's (posterior correlations +0.85 and -0.80): both are then set by the input's prior,
    not called determined and left nominal, and the calibrated model moves the ceiling alone
    (5.606, +18 %, beyond the 15 % target; metric 2.79x the true envelope's against the
    nominal's 2.99x). The honest answer of a metric that sums the zones."""
    summary = twin["uncertain_building"]
    rows = {r["parameter"]: r for r in summary["rows"]}
    assert all(row["covers"] for row in rows.values()), rows
    (item,) = twin["uncertain_building_posterior"].uncertain
    assert set(item["compensates"]) == {
        "construction/Exterior Wall/resistance",
        "zone/attic/infiltration_ach",
    }
    assert {n for n, row in rows.items() if row["determined"]} == {
        "construction/Interior Ceiling/resistance"
    }
