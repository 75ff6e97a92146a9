"""The identification section of the self-contained HTML report."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.identification import REFERENCE
from thermocal.io.atomic import atomic_write
from thermocal.report.html import HtmlReport


def add_section(
    report: HtmlReport,
    result,
    *,
    title: str = "Heat-balance identification",
    pngs: dict | None = None,
):
    """Append the identification's tables and figures to ``report``.

    ``pngs``: figures already rendered (PNG bytes by the stems of
    :func:`~thermocal.identification.figures.identification_figures`), to avoid drawing twice.
    """
    from thermocal.identification import figures

    pngs = pngs or {}

    def figure(stem, make):
        return pngs[stem] if stem in pngs else make()

    report.section(title)
    report.paragraph(
        "For every zone and step, the heat Q_ID that the detailed model needs to follow the "
        "measured room temperature: internal loads + HVAC + envelope error. The calibration "
        "metric is the variance of the building-wide Q_ID over the unoccupied steps."
    )
    std = np.sqrt(result.unoccupied_variance())
    mask = result.unoccupied_mask()
    items = {
        "Metric source": "exact inverse" if result.metric_source == "inverse" else "PID",
        "Tracked temperature": result.feedback,
        "Unoccupied std of Q_ID": f"{std / 1000:.3f} kW",
        "Unoccupied mean of Q_ID": f"{result.building_heat.to_numpy()[mask].mean() / 1000:.2f} kW",
        "Zones": f"{result.q_id.shape[1]}",
        "Steps": f"{result.q_id.shape[0]}",
    }
    clock = getattr(result, "log_clock", None)
    items["Sensor log's clock"] = _clock_item(clock)
    for key, value in result.timings.items():
        items[f"time: {key}"] = f"{value:.2f} s"
    report.key_values(items)
    for note in result.notes:
        report.note(note)
    if clock is not None and clock["passed"] is not False:  # passed, or not made: why
        report.note(clock["note"])
    elif clock is not None:  # a log an hour off: a warning box
        report.flags([clock["note"]])
    report.figure(
        figure("building_q_id", lambda: figures.building_heat(result)),
        caption="Building-wide identified heat.",
    )
    difference = result.method_difference()
    if difference is not None:
        labels = {
            "building_rms_W": "building total: RMS of the difference [W]",
            "building_max_abs_W": "building total: largest difference [W]",
            "building_inverse_std_W": "building total: std of the inverse's Q_ID [W]",
            "worst_zone": "zone with the largest RMS difference",
            "worst_zone_rms_W": "its RMS difference [W]",
            "unoccupied_variance_pid_W2": "unoccupied variance, PID [W2]",
            "unoccupied_variance_inverse_W2": "unoccupied variance, inverse [W2]",
        }
        report.table(
            pd.DataFrame(
                {
                    "quantity": [labels.get(k, k) for k in difference],
                    "value": [
                        str(v) if isinstance(v, str) else f"{v:,.4g}" for v in difference.values()
                    ],
                }
            ),
            caption="PID minus exact inverse",
        )
    if result.tuning is not None:
        t = result.tuning
        report.table(
            pd.DataFrame(
                {
                    "exact (closed-loop poles)": [t.ultimate_gain, t.ultimate_period],
                    "experiment (bisection)": [t.experiment_gain, t.experiment_period],
                },
                index=["ultimate gain Ku [W/K]", "ultimate period Pu [s]"],
            ),
            caption=f"Ziegler-Nichols tuning on {t.zone} ({t.volume:.0f} m3)",
            index=True,  # the rows' names: the gain and the period
            number_format="{:,.4g}",
        )
        if getattr(t, "experiment_note", None):
            report.note(t.experiment_note)
        report.figure(
            figure("tuning_oscillation", lambda: figures.tuning_oscillation(t)),
            caption="Tuning experiment at the ultimate gain.",
        )
    report.figure(
        figure("typical_zone", lambda: figures.typical_zone(result)),
        caption="A typical zone (median tracking RMSE).",
    )
    report.table(
        result.worst_tracked(10).reset_index(),
        caption="Worst-tracked zones",
        number_format="{:,.3f}",
    )
    counts = result.sources["source"].value_counts().to_dict()
    report.paragraph(
        "Zone references: "
        + ", ".join(f"{n} {kind}" for kind, n in counts.items())
        + " (sensor: own sensor; named: a substitute named in the mapping; neighbour: an "
        "adjacent zone's data; float: no reference, the zone is simulated with Q_ID = 0 and its "
        "temperature reported)."
    )
    if result.form is not None:
        tracked = result.form[result.form["treatment"] == "tracked"]
        fractions = ", ".join(f"{f:g}" for f in sorted(set(tracked["radiant_fraction"].round(3))))
        report.paragraph(
            f"Form of the identified heat: radiant fraction {fractions} (the share put on the "
            "zone's surfaces as EnergyPlus distributes radiant internal gains, by area x thermal "
            f"absorptance; the rest into the zone air); sensor model {result.feedback} (the "
            "model temperature compared with the sensors: air weight 1 = air, 0.5 = operative). "
            "The method's paper puts all of the heat into the air and tracks the air "
            "temperature (radiant fraction 0, air)."
        )
    report.table(
        result.zone_table(),
        caption="Every zone: the source of its reference, its treatment and the form of its "
        "identified heat",
    )
    if result.substituted is not None and not result.substituted.empty:
        report.table(result.substituted, caption="Long gaps filled from an adjacent zone")
    if result.interpolated is not None and not result.interpolated.empty:
        report.table(result.interpolated, caption="Short gaps interpolated")
    if result.import_notes:
        report.bullets(
            result.import_notes,
            intro="What the building import and the simulation flattened, skipped or approximated:",
        )
    report.references([REFERENCE])
    return report


def _clock_item(clock: dict | None) -> str:
    """The key-value line of the sensor log's clock check (``result.log_clock``; None: switched
    off): its verdict, or why it was not made."""
    if clock is None:
        return "not checked (switched off)"
    if clock["passed"] is None:
        return f"not checked: {clock['reason']}"
    if clock["passed"]:
        return "as written"
    if (clock.get("halves") or {}).get("disagree"):
        return f"{clock['best']:+g} h fits better in one half only (a clock jump?): see the note"
    least = "at least " if clock.get("at_limit") else ""
    return f"{least}{clock['best']:+g} h fits better: see the note"


def write_report(result, path: str | Path, *, pngs: dict | None = None) -> Path:
    """A self-contained report of one identification run (written atomically)."""
    report = HtmlReport("Heat-balance identification", subtitle=REFERENCE)
    add_section(report, result, pngs=pngs)
    return atomic_write(path, report.write)
