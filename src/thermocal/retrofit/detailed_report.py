"""HTML report of the retrofit strategies simulated with the detailed multi-zone model.

The same report machinery as the RC analysis (:class:`thermocal.report.HtmlReport`, the figures
of :mod:`thermocal.report.figures`), from the ``detailed_model`` section of results.json
(:func:`thermocal.retrofit.detailed.detailed_results`).
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

__all__ = ["write_detailed_report"]


def _strategy_table(det: dict, rc: dict | None, cur: str) -> pd.DataFrame:
    rc_saving = {s["code"]: s["saving_pct"] for s in (rc or {}).get("scenarios", [])}
    rows = []
    for s in det["scenarios"]:
        e = s["economics"]
        row = {
            "code": s["code"],
            "measures": " + ".join(m.replace("_", " ") for m in s["measures"]) or "no retrofit",
            "heating [kWh/a]": s["annual_kWh"],
            "saving [%]": s["saving_pct"],
        }
        if rc_saving:
            row["RC model saving [%]"] = rc_saving.get(s["code"], float("nan"))
        row.update({
            f"investment [{cur}]": e["investment"],
            f"cost saving [{cur}/a]": e["cost_saving_per_year"],
            "CO2 saving [kg/a]": e["co2_saving_kg_per_year"],
            "payback [a]": float("nan") if e["payback_years"] is None else e["payback_years"],
        })  # fmt: skip
        rows.append(row)
    return pd.DataFrame(rows)


def _changes_table(det: dict) -> pd.DataFrame:
    seen, rows = set(), []
    for s in det["scenarios"]:
        for c in s["changes"]:
            key = (c["measure"], c["construction"])
            if key in seen:
                continue
            seen.add(key)
            rows.append({
                "measure": c["measure"].replace("_", " "),
                "construction / window type": c["construction"],
                "area [m2]": c["area_m2"],
                "U before [W/(m2 K)]": c["u_before"],
                "U after [W/(m2 K)]": c["u_after"],
                "added insulation [cm]": 100.0 * c["insulation_m"]
                if "insulation_m" in c else float("nan"),
                "g after [-]": c.get("g_after", float("nan")),
            })  # fmt: skip
    return pd.DataFrame(rows)


def write_detailed_report(det: dict, path: Path | str, *, rc: dict | None = None) -> Path:
    """Write the self-contained HTML report of the detailed-model retrofit.

    Parameters
    ----------
    det : dict
        :func:`thermocal.retrofit.detailed.detailed_results`.
    path : str or Path
        The HTML file to write.
    rc : dict, optional
        The RC analysis' results.json (its savings are shown beside).

    Returns
    -------
    Path
    """
    from thermocal.report import HtmlReport
    from thermocal.report.figures import plot_monthly_bars

    cur = det["economics"]["currency"]
    rep = HtmlReport(
        f"Retrofit on the detailed model: {det['building']}",
        subtitle="Annual heating of envelope-retrofit strategies simulated with the detailed "
        "multi-zone model",
    )
    best = det.get("recommendation")
    by_code = {s["code"]: s for s in det["scenarios"]}
    rep.section("Summary")
    tiles = {
        "annual heating demand": f"{det['annual_heating_demand_kWh']:,.0f} kWh",
        "heated zones": str(len(det["heated_zones"])),
        "strategies": str(len(det["scenarios"])),
    }
    if best is not None:
        s = by_code[best]
        tiles["recommended"] = f"{best}: {' + '.join(s['measures'])}"
        tiles["its saving"] = f"{s['saving_pct']:.1f} %"
    rep.key_values(tiles)
    if best is not None:
        rep.paragraph(f"Recommended strategy {best}, chosen as {det['recommendation_rule']}.")
    else:
        rep.paragraph("No strategy pays back: nothing is recommended.")
    rep.note(
        "One simulation per strategy (no uncertainty interval). Unlike the RC model, this model "
        "is not checked against measurements here: calibrate it first (thermocal calibrate) "
        "for a decision."
    )
    record = det.get("track_record") or []
    if record:
        rep.paragraph(
            "How the same analysis held on houses thermocal did not write, against EnergyPlus "
            "25.2 on the same IDF (the strategies' savings in percentage points): "
            + "; ".join(
                f"{r['house']}: baseline {r['baseline_error_pct']:+.1f} %, savings within "
                f"{r['savings_max_abs_pp']:.1f} pp (mean {r['savings_mean_abs_pp']:.1f}), "
                f"{r['within_3pp']} of 15 within 3 pp"
                for r in record
            )
            + ". A model of the building as it is, calibrated or not, is what these figures "
            "assume."
        )
    rep.section("Strategies")
    rep.table(
        _strategy_table(det, rc, cur),
        number_format="{:,.1f}",
        highlight_rows=[i for i, s in enumerate(det["scenarios"]) if s["code"] == best],
        caption=f"Useful heat, savings, investment, running cost and CO2 (final energy: "
        f"{det['economics']['energy_carrier']}, efficiency "
        f"{det['economics']['system_efficiency']:g}, {det['economics']['energy_price']:g} "
        f"{cur}/kWh, {det['economics']['emission_factor']:g} kg CO2-eq/kWh)",
    )
    monthly = det["monthly_heating_kWh"]
    if best is not None and best in monthly:
        fig = plot_monthly_bars(
            monthly["0"],
            reference=monthly[best],
            label="no retrofit",
            reference_label=f"strategy {best}",
            title="Monthly heating, detailed model",
        )
        rep.figure(fig, caption="Monthly heating delivered to the heated zones")
    rep.section("What the measures change")
    rep.table(
        _changes_table(det),
        number_format="{:,.3g}",
        caption="Insulation (lambda 0.035 W/(m K)) added to reach each measure's U-value "
        "(ISO 6946 surface resistances); new glazing by EnergyPlus's simple glazing model",
    )
    rep.section("Model and approximations")
    rep.bullets(
        [det["method"], f"time step {det['step']}, heated zones: {', '.join(det['heated_zones'])}"]
        + list(det["notes"])
    )
    rep.references(
        [
            "ISO 6946:2017, thermal resistance and thermal transmittance (surface resistances).",
            "Kruis, N. and Krarti, M. (2017), Three-dimensional accuracy of two-dimensional "
            "approximations of foundation heat transfer, Journal of Building Performance "
            "Simulation 10(3) (the ground under floors on EnergyPlus's Foundation boundary).",
        ]
    )
    return rep.write(path)
