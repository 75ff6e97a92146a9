"""The calibration section of the self-contained HTML report."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.identification import REFERENCE
from thermocal.io.atomic import atomic_write
from thermocal.report.html import HtmlReport
from thermocal.textformat import format_number

#: How the report names each total of :mod:`thermocal.calibration.envelope_total`.
TOTAL_NAMES = {
    "conduction": "U A to outdoors",
    "air": "air changes",
    "all": "both (varied part of the heat loss coefficient)",
}


def add_section(report: HtmlReport, result, *, pngs: dict | None = None) -> HtmlReport:
    """Append the calibration's tables and figures to ``report``."""
    from thermocal.calibration import figures

    pngs = pngs or {}

    def figure(stem, make):
        return pngs[stem] if stem in pngs else make()

    data = result.as_dict()
    report.section("Envelope calibration")
    report.paragraph(
        "Envelope parameters were sampled around their nominal values; for each sample the "
        "heat each zone needs to follow the sensors was identified, and the variance of its "
        "building-wide sum over the unoccupied hours computed. A meta-model of that variance "
        "ranks the parameters; the critical ones are optimised (interior point) for the "
        "minimum variance (the calibrated model) and the maximum (for contrast), and both "
        "optima are confirmed with the full model."
    )
    samples = data["samples"]
    confirm = result.confirmed
    items = {
        "Samples": f"{samples['successful']} ok, {samples['failed']} failed",
        "Campaign time": f"{samples['wall_time_s']:.0f} s ({samples['backend']})"
        if result.summary.evaluated
        else f"all {samples['successful']} samples from the store",
        "Meta-model R2 (cross-validated)": f"{result.surrogate.cv_r2_:.3f}",
        "Nominal unoccupied std": f"{np.sqrt(result.nominal_metric) / 1000:.3f} kW",
        "Calibrated unoccupied std": f"{confirm['calibrated']['confirmed_std_W'] / 1000:.3f} kW",
        "Calibrated parameters from": confirm["calibrated"]["source"],
        "Maximum-variance std": _kw(confirm["max"]["confirmed_std_W"]),
        "Metric": data["metric_description"],
        "Model runs": f"{data['model_runs'].get('simulated', 0)} simulated, "
        f"{data['model_runs'].get('from_store', 0)} read from the store",
    }
    zoom = result.zoom
    if zoom:
        runs = zoom["runs"]
        items["Zoom stage"] = (
            f"{zoom['samples']} samples in a box of +-{zoom['standard_deviations']:g} posterior "
            f"sd around the first answer ({runs['simulated']} simulated, {runs['from_store']} "
            f"from the store); local meta-model R2 {zoom['cv_r2']:.3f}"
        )
    report.key_values(items)
    for note in result.notes:
        report.note(note)
    table = (
        result.table1()
        .reset_index()
        .rename(columns={"min_metric": "minimum variance", "max_metric": "maximum variance"})
    )
    report.table(table, caption="Critical parameters: nominal, minimum and maximum variance")
    if result.posterior is not None:
        post = result.posterior
        for sentence in post.sentences():
            report.paragraph(sentence)
        report.table(
            post.summary[["unit", "nominal", "median", "q05", "q95", "determined"]]
            .reset_index()
            .rename(columns={"q05": "5 %", "q95": "95 %"}),
            caption="Posterior of the critical parameters (series meta-model, uniform prior on "
            "the sampled range, log-normal around an in-situ measurement, noise level from the "
            "residual identified heat; emcee, Foreman-Mackey et al. 2013): median and 90 % "
            "credible interval",
        )
        if post.envelope_total:
            report.table(
                pd.DataFrame(
                    [
                        {
                            "together": TOTAL_NAMES[part],
                            "of": ", ".join(total["elements"]),
                            "nominal [W/K]": f"{total['nominal_W_per_K']:.0f}",
                            "median [W/K]": f"{total['median_W_per_K']:.0f}",
                            "90 % interval [W/K]": f"{total['q05_W_per_K']:.0f} to "
                            f"{total['q95_W_per_K']:.0f}",
                            "determined": "yes" if total["determined"] else "no",
                            "alone": ", ".join(total["separately_determined"]) or "none",
                        }
                        for part, total in post.envelope_total.items()
                    ]
                ),
                caption="The varied elements together (thermocal.calibration.envelope_total): "
                "U A to outdoors, the air changes' design conductance and both, from the "
                "posterior's draws; 'alone': those determined by themselves",
            )
        if post.in_situ:
            report.table(
                pd.DataFrame(
                    [
                        {
                            "parameter": name,
                            "measured R [m2 K/W]": f"{m['resistance_m2K_per_W']:.3g}",
                            "std. unc.": f"{100 * m['resistance_rel_std']:.1f} %",
                            "days / mean dT": "given" if not m["days"] else
                            f"{m['days']} / {m['mean_difference_K']:.1f} K",
                            "source": m["source"],
                        }
                        for name, m in post.in_situ.items()
                    ]
                ),
                caption="In-situ measurements in the posterior (ISO 9869-1 average method)",
            )  # fmt: skip
        if post.advice.get("available"):
            report.table(
                pd.DataFrame(
                    [
                        {
                            "heat-flux plate on": c["parameter"],
                            "readings": " / ".join(f"{r:.3g}" for r in c["readings"]),
                            "determined then (probability)": ", ".join(
                                f"{n} ({p:.0%})"
                                for n, p in c["determined_probability"].items() if p > 0
                            ) or "none",
                            "mean interval / range": f"{100 * c['mean_width_fraction']:.0f} %",
                        }
                        for c in post.advice["candidates"]
                    ]
                ),
                caption="Which measurement next: the posterior recomputed with each element's "
                "plate readings (its present median and +-1.73 sd of what the plate may read, "
                "weights 1/6, 2/3, 1/6; plate "
                f"{100 * post.advice['plate_rel_std']:.0f} %; no simulation; preposterior "
                "analysis, Raiffa and Schlaifer 1961); the mean interval at the median reading",
            )
    if zoom:
        report.table(
            pd.DataFrame(zoom["box"])
            .T.rename(columns={"center": "first answer", "log_sd": "posterior sd of log p"})
            .reset_index(names="parameter"),
            caption="Zoom stage: the box of the local campaign (uniform in log p; +-"
            f"{zoom['standard_deviations']:g} posterior sd of the first stage, at least +-"
            f"{100 * zoom['min_half_width_log']:.0f} %, within the sampled range); the "
            "meta-model refitted on its samples gives the posterior above (sequential design, "
            "Kennedy and O'Hagan 2001)",
        )
    if result.posterior is not None:
        _track_record(report)
    if result.truth_comparison is not None:
        truth = result.truth_comparison.reset_index().rename(
            columns={
                "perturbed_in_truth": "perturbed",
                "moved_towards_truth": "towards truth",
                "recovered_fraction": "share recovered",
            }
        )
        report.table(
            truth,
            caption="Demo: calibrated values against the generator's truth (share recovered = "
            "(calibrated - nominal) / (true - nominal))",
        )
    report.table(
        pd.DataFrame(
            {
                case: {
                    "predicted by meta-model [W2]": confirm[case].get("predicted", np.nan),
                    "confirmed with the full model [W2]": confirm[case]["confirmed"],
                }
                for case in ("nominal", "min", "calibrated", "max")
            }
        ).reset_index(),
        caption="Confirmation runs",
    )
    if result.validation is not None:
        report.table(
            pd.DataFrame([result.validation]),
            caption="Validation on a period the calibration did not see",
        )
    report.figure(
        figure("sensitivity", lambda: figures.sensitivity_bars(result)),
        caption="Parameter influence (critical parameters coloured).",
    )
    report.figure(
        figure("q_id_cases", lambda: figures.heat_cases(result)),
        caption="Building-wide identified heat for the three parameter sets.",
    )
    report.figure(
        figure("metamodel_parity", lambda: figures.parity(result)),
        caption="Meta-model parity (out-of-fold predictions).",
    )
    if result.morris is not None:
        report.table(
            result.morris.head(15).reset_index(),
            caption="Morris screening on the model itself (elementary effects over the full "
            "ranges, W2)",
        )
    if result.sobol is not None:
        top = result.sobol.sort_values("ST", ascending=False).head(15).reset_index()
        report.table(top, caption="Sobol indices on the meta-model (95 % confidence)")
    report.references([REFERENCE])
    return report


def _track_record(report: HtmlReport) -> None:
    """How the same calibration held on buildings thermocal did not write (EnergyPlus twins)."""
    from thermocal.calibration.track_record import INDEPENDENT_CALIBRATIONS

    checks = list(INDEPENDENT_CALIBRATIONS.values())
    report.paragraph(
        "How far such answers can be off: small campaigns (24 to 48 samples) of the same "
        f"calibration with the zone-group metric (the default) on {len(checks)} hidden "
        "envelopes of buildings thermocal did not write, EnergyPlus 25.2 running each and "
        "thermocal given the nominal file, the weather and the zone temperatures. A negative "
        "metric difference means the calibrated model follows the sensors better than the true "
        "envelope does: it fits model error as well as the envelope."
    )
    rows = [
        {
            "building": c.building,
            "resistances determined": c.determined_resistances,
            "their largest error": f"{c.max_resistance_error_pct:.1f} %",
            "90 % intervals covering the truth, of the determined": (
                f"{c.determined_covered} of {c.determined}"
            ),
            "of all (an undetermined one: its prior)": f"{c.covered} of {c.parameters}",
            "metric vs the true envelope's": f"{c.metric_vs_truth_pct:+.1f} %",
            "element totals covering the truth": f"{c.totals_covered} of {c.totals}",
        }
        for c in checks
    ]
    report.table(
        pd.DataFrame(rows), caption="The calibration against the truth of independent buildings"
    )
    report.bullets([f"{c.building}: {c.note}" for c in checks])


def _kw(value: float) -> str:
    """A standard deviation [W] in kW, or "not simulated" for a run a re-analysis did not
    make."""
    text = format_number(value / 1000 if value is not None else None, ".3f", "not simulated")
    return text if text == "not simulated" else f"{text} kW"


def write_report(result, path, *, pngs: dict | None = None) -> Path:
    """A self-contained calibration report (written atomically)."""
    report = HtmlReport("Envelope calibration", subtitle=REFERENCE)
    add_section(report, result, pngs=pngs)
    return atomic_write(path, report.write)
