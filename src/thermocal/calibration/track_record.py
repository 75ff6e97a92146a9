"""How the element calibration held on buildings thermocal did not write (its track record).

The report states, beside the posterior, how far small campaigns of the same calibration with
the zone-group metric (the default; no zoom stage) were from the hidden truth on the EnergyPlus
25.2 twins of the test suite (docs/calibration.md): which elements they declared determined, how
far those were from the truth, how many 90 % intervals covered it and where the confirmed metric
ended against the true envelope's. The twins' tests (``tests/calibration/
test_calibration_energyplus*.py``) fail when a change moves a figure beyond its rounding: the
5-zone and multifamily twins' in CI, the outpatient's with the heavy reference runs
(``THERMOCAL_REFERENCE_RUNS=1``) only.
"""

from __future__ import annotations

from dataclasses import dataclass

from thermocal.records import differs_from

__all__ = ["INDEPENDENT_CALIBRATIONS", "IndependentCalibration", "differs_from"]


@dataclass(frozen=True)
class IndependentCalibration:
    """One building thermocal did not write, calibrated as a user would, against its truth.

    Attributes
    ----------
    building : str
        What the building is and what the hidden truth changed.
    determined_resistances : int
        Element resistances the posterior declared determined [-].
    max_resistance_error_pct : float
        Largest |calibrated / truth - 1| among them [%].
    covered, parameters : int
        Parameters whose 90 % credible interval contains the truth, of those in the posterior.
    determined_covered, determined : int
        The same among the parameters the posterior declared determined: an undetermined
        parameter's interval is about its prior range, which covers the truth by its width
        rather than by what the data said [-].
    metric_vs_truth_pct : float
        The confirmed metric against the true envelope's, ratio - 1 [%].
    note : str
        What the misses are.
    """

    building: str
    determined_resistances: int
    max_resistance_error_pct: float
    covered: int
    parameters: int
    determined_covered: int
    determined: int
    metric_vs_truth_pct: float
    note: str


#: Measured 2026-11-29 (every twin again on 2026-11-30, after the windows took ISO 15099's
#: room-side convection; the multifamily twin on 2026-11-30, after the roofs' long-wave took
#: their tilt instead of the file's view factor to the ground), keyed by the reference folder under
#: ``tests/reference``.
INDEPENDENT_CALIBRATIONS: dict[str, IndependentCalibration] = {
    "calibration_energyplus_5zone": IndependentCalibration(
        building="NREL 5ZoneAirCooled (wall R x0.6, roof R x1.5, infiltration x1.4 hidden; "
        "48 samples)",
        determined_resistances=2,
        max_resistance_error_pct=9.1,
        covered=6,
        parameters=7,
        determined_covered=2,
        determined=3,
        metric_vs_truth_pct=14.8,
        note="the roof's interval ends 1.6 % below its truth (-6.6 %): the affine meta-model "
        "in log R; the zoom stage (sampling.zoom: 32) or the curvature term "
        "(metamodel.series_terms: auto) cover it",
    ),
    "calibration_energyplus_multifamily": IndependentCalibration(
        building="DOE/PNNL multifamily prototype (wall R x1.5, attic floor R x0.6, leakage x1.4 "
        "hidden; 32 samples)",
        determined_resistances=2,
        max_resistance_error_pct=8.4,
        covered=1,
        parameters=3,
        determined_covered=1,
        determined=3,
        metric_vs_truth_pct=-2.6,
        note="the attic's infiltration +10 %, its interval 9 % above the truth, and the wall "
        "-8.4 %, its interval 3.3 % below: the unvaried flats' infiltration (+4-10 %) is a "
        "model error they absorb",
    ),
    "calibration_energyplus_outpatient": IndependentCalibration(
        building="DOE outpatient prototype, 118 zones (wall R / 1.5, roof R / 0.6, infiltration "
        "x1.4 hidden, wall and roof varied; 24 samples)",
        determined_resistances=2,
        max_resistance_error_pct=8.8,
        covered=1,
        parameters=2,
        determined_covered=1,
        determined=2,
        metric_vs_truth_pct=-1.2,
        note="the roof -8.8 %, its interval 2.1 % below the truth (the unvaried infiltration "
        "is a model error the envelope absorbs)",
    ),
    "calibration_energyplus_5zone_windows": IndependentCalibration(
        building="NREL 5ZoneAirCooled (low-e glazing: window U -34 %, ground slab R x2, roof R "
        "x0.7 hidden; 48 samples)",
        determined_resistances=3,
        max_resistance_error_pct=19.1,
        covered=3,
        parameters=6,
        determined_covered=3,
        determined=6,
        metric_vs_truth_pct=-5.0,
        note="the roof +19 % and the unchanged wall -17 % (it trades with the window U, found at "
        "-11 %); the slab's x2 lies beyond the default range; the SHGC ends at the glazing's "
        "limit: the model wants more sun through this glazing than EnergyPlus admits (also "
        "with the file's clear glazing)",
    ),
}
