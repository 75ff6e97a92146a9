"""The post-retrofit verification's outputs: ``verify.json``, its figures and the
self-contained HTML report (:func:`write_verify_outputs`)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.retrofit.verify import (
    ASHRAE_14,
    FORSSELL_LJUNG_1999,
    IPMVP,
    REDDY_CLARIDGE_2000,
    SUNIKKA_BLANK_2012,
    Verification,
    results_dict,
)

__all__ = ["make_figures", "write_report", "write_verify_outputs"]


def make_figures(ver: Verification) -> dict:
    """Figures of the report: daily heat measured vs baseline; HLC before / after."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figs = {}
    d = ver.daily
    fig, ax = plt.subplots(figsize=(9, 3.6))
    ax.plot(d.index, d["measured"], "o-", ms=3, color="k", label="measured")
    ax.plot(d.index, d["baseline"], "s-", ms=3, color="tab:red",
            label="baseline model (calibrated before the retrofit)")  # fmt: skip
    ax.axvline(ver.retrofit_date, color="grey", ls="--", label="retrofit")
    post = d["period"] == "post"
    ax.fill_between(d.index[post], d["measured"][post], d["baseline"][post], color="tab:green",
                    alpha=0.25, label="avoided energy")  # fmt: skip
    ax.set_ylabel("heat per day [kWh]")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    fig.autofmt_xdate()
    fig.tight_layout()
    figs["daily_heat"] = fig

    from thermocal.report.figures import plot_bars_with_intervals

    hlc = ver.physical["heat_loss_coefficient_W_per_K"]
    labels, vals, lo, hi = [], [], [], []
    for key, name in (("pre", "HLC before"), ("post", "HLC after")):
        labels.append(name)
        vals.append(hlc[key]["value"])
        lo.append(hlc[key]["lo"])
        hi.append(hlc[key]["hi"])
    for v in ver.physical["groups"].values():
        for key, name in (("pre", "before"), ("post", "after")):
            labels.append(f"{v['label']} {name}")
            vals.append(v[key]["value"])
            lo.append(v[key]["lo"])
            hi.append(v[key]["hi"])
    figs["conductances"] = plot_bars_with_intervals(
        labels, vals, lo, hi, ylabel="W/K", title="Calibrated conductances before and after",
        interval_label=f"{100 * ver.config.retrofit.uncertainty.interval:.0f} % interval",
    )  # fmt: skip
    return figs


def _pct(v: dict, digits: int = 1) -> str:
    if v.get("lo") is None:
        return f"{v['value']:.{digits}f} %"
    return f"{v['value']:.{digits}f} % ({v['lo']:.{digits}f} to {v['hi']:.{digits}f} %)"


def write_report(ver: Verification, results: dict, figures: dict, path: Path) -> Path:
    """The self-contained report.html (same builder and style as the retrofit report)."""
    from thermocal.report import HtmlReport

    cfg = ver.config.retrofit
    pct = f"{100 * cfg.uncertainty.interval:.0f} %"
    comp, av, ph = ver.comparison, ver.avoided, ver.physical
    rep = HtmlReport(
        f"Retrofit verification: {ver.building.name}",
        subtitle="Measured against predicted saving (IPMVP Option D, ASHRAE Guideline "
        "14-2014) with calibrated fifth-order RC models before and after the retrofit",
    )
    rep.section("Verdict")
    rep.paragraph(f"{comp['verdict'].upper()}: {comp['explanation']}.", css_class="lead")
    for key in ("baseline_days_after_retrofit", "retrofitted_days_before_the_date"):
        warning = av.get(key, {}).get("warning")
        if warning:
            rep.flags([warning[0].upper() + warning[1:] + "."])
    # the metered heat's scale against the building file and between the periods
    for warning in comp.get("warnings") or []:
        rep.flags([warning[0].upper() + warning[1:] + "."])
    m, p, dd = comp["measured_saving_pct"], comp["predicted_saving_pct"], comp["difference_pp"]
    rep.key_values({
        "measured saving (reference year, normalised)": _pct(m),
        "predicted saving": _pct(p) + f" - {p['source']}",
        "difference": f"{dd['value']:+.1f} pp ({pct} interval {dd['lo']:+.1f} to "
        f"{dd['hi']:+.1f} pp)",
        "avoided energy, post period": f"{av['avoided_kWh']:,.0f} kWh of "
        f"{av['baseline_kWh']:,.0f} kWh ({av['saving_pct']:.1f} %, {pct} interval "
        f"{av['saving_pct_lo']:.1f} to {av['saving_pct_hi']:.1f} %)",
        "retrofit": f"{', '.join(ver.prediction.measures)} on {ver.retrofit_date:%Y-%m-%d}",
        "periods": f"before {ver.pre[0]:%Y-%m-%d} to {ver.pre[1]:%Y-%m-%d}, after "
        f"{ver.post[0]:%Y-%m-%d} to {ver.post[1]:%Y-%m-%d}",
    })  # fmt: skip
    _verification_track_record(rep)
    rep.paragraph(
        "Delivered: the measured saving agrees with the prediction within the uncertainty. "
        "Rebound: the house saves less than predicted (higher indoor temperatures after the "
        "retrofit, or a performance gap of the measures). Prebound: it saves more, typically "
        "because the house used less energy before the retrofit than its description said "
        "(Sunikka-Blank and Galvin 2012). Inconclusive: the data cannot tell."
    )
    rep.section("Avoided energy (IPMVP Option D, ASHRAE Guideline 14-2014)")
    rep.paragraph(
        "The fifth-order model calibrated on the pre-retrofit period is driven by the "
        "post-retrofit period's measured weather and follows the indoor temperature its "
        "heating held (the measured one while heated; at most the thermostat's hour-of-day "
        "profile while the house floated above it): the heat it needs is what the house "
        "would have used without the retrofit. Avoided energy = that baseline minus the "
        "measured heat. "
        + (
            "The indoor temperature was held by a thermostat (median deviation "
            f"{av['indoor_control']['mad_K']:.2f} K), so the model was fitted to the metered "
            "heat, not to the indoor temperature (closed loop). "
            if av["calibration"] == "heat"
            else "The model was fitted to the measured indoor temperature (the retrofit "
            "method's maximum-likelihood calibration). "
        )
        + (
            "The daily residuals of the pre period grow with the indoor-outdoor difference "
            f"({av['adjustment']['slope_kWh_per_day_K']:.2f} +/- "
            f"{av['adjustment']['slope_se']:.2f} kWh/day per K, e.g. air change rising with "
            "the stack effect and the wind): the baseline of the post period (mean "
            f"difference {av['adjustment']['mean_dT_K']['post']:.1f} K against "
            f"{av['adjustment']['mean_dT_K']['pre']:.1f} K) is adjusted by "
            f"{av['adjustment']['post_period_kWh']:+,.0f} kWh."
            if av["adjustment"]["applied"]
            else ""
        )
    )
    if "daily_heat" in figures:
        rep.figure(
            figures["daily_heat"],
            caption="Daily heat measured and of the baseline model; shaded: avoided energy.",
        )
    ok = "meets" if av["baseline_meets_criteria"] else "does NOT meet"
    rep.key_values({
        "baseline model, pre period (daily)": f"NMBE {av['baseline_nmbe_pct']:+.1f} %, "
        f"CV(RMSE) {av['baseline_cv_rmse_pct']:.1f} % over {av['days_pre']} days: {ok} the "
        f"criteria (|NMBE| <= {av['criteria']['max_abs_nmbe_pct']:g} %, CV(RMSE) <= "
        f"{av['criteria']['max_cv_rmse_pct']:g} %)",
        "post period": f"{av['days_post']} days: baseline {av['baseline_kWh']:,.0f} kWh, "
        f"measured {av['measured_kWh']:,.0f} kWh",
        "fractional savings uncertainty": f"{100 * av['fsu']:.0f} % at {pct} confidence, "
        f"{100 * av['fsu_at_68pct']:.0f} % at 68 % (Guideline 14 asks below 50 % at 68 %)",
        "formula": av["fsu_formula"] + f"; lag-1 autocorrelation of the daily residuals "
        f"{av['residual_lag1_autocorrelation']:.2f}, n' = {av['n_eff']:.1f}",
        "comfort take-back": f"mean indoor temperature {av['mean_indoor_C']['pre']:.1f} C "
        f"before, {av['mean_indoor_C']['post']:.1f} C after; at the old indoor profile the "
        f"baseline is {av['baseline_at_pre_comfort_kWh']:,.0f} kWh and the saving "
        f"{av['saving_with_take_back_pct']:.1f} % ({av['take_back_pp']:+.1f} pp taken back)",
        "normalised to the reference year": f"{_pct(av['normalised_saving_pct'])}, "
        f"{av['normalised_avoided_kWh']:,.0f} kWh/a: the measured fraction of the baseline "
        "over the post period carried to the reference year by the model's ratio of "
        "retrofitted to baseline demand over the year divided by the same ratio over the "
        f"post period (measured-to-expected {av['measured_to_expected_ratio']:.3f})",
    })  # fmt: skip
    rep.section("Physical change: the model calibrated on each period")
    hl = ph["heat_loss_coefficient_W_per_K"]
    rows = [["heat loss coefficient [W/K]", *(_iv(hl[k]) for k in ("pre", "post", "change"))]]
    for g in ph["groups"].values():
        rows.append([f"{g['label']} [W/K]", *(_iv(g[k]) for k in ("pre", "post", "change"))])
    ak = ph["annual_kWh"]
    rows.append(["annual heating demand [kWh]", _iv(ak["pre"], ",.0f"),
                 _iv(ak["post"], ",.0f"), ""])  # fmt: skip
    rep.table(
        pd.DataFrame(rows, columns=["", "before", "after", "change"]),
        caption=f"Estimates with {pct} intervals (posterior draws); annual demand over the "
        f"reference year ({ph['weather']}) at the "
        + {"measured": "pre period's measured", "the prediction's": "prediction's"}.get(
            ph["indoor_profile"], "constant"
        )
        + f" indoor profile (mean {np.mean(ph['indoor_profile_C']):.1f} C).",
    )
    mi = ph["mean_indoor_C"]
    with_post = (
        f"; with the post period's indoor profile for the retrofitted house: "
        f"{_pct(ph['normalised_saving_pct'])}"
        if ph["normalised_saving_pct"] != ph["saving_pct"]
        else ""
    )
    rep.paragraph(
        f"Saving of the envelope alone (both models at the same indoor profile): "
        f"{_pct(ph['saving_pct'])}{with_post}. Mean measured indoor temperature "
        f"{mi['pre']:.1f} C before, {mi['post']:.1f} C after."
    )
    if "conductances" in figures:
        rep.figure(
            figures["conductances"],
            caption="Heat loss coefficient and the retrofitted element groups, before and after.",
        )
    if ver.truth is not None:
        tc = results["truth_check"]
        a = tc["annual_saving_pct"]
        rep.section("Demo: check against the generator")
        rep.paragraph(
            f"The demo house was simulated by the detailed multi-zone model with roof and walls "
            f"retrofitted on {ver.retrofit_date:%Y-%m-%d}. True annual saving at 20 C "
            f"{a['true']:.1f} %, verified {a['verified']:.1f} % ({a['lo']:.1f} to "
            f"{a['hi']:.1f} %, error {a['error_pp']:+.1f} pp, "
            f"{'covered' if a['covered'] else 'NOT covered'}). True heat loss coefficient "
            f"{tc['heat_loss_coefficient_W_per_K']['pre']['true']:.0f} W/K before, "
            f"{tc['heat_loss_coefficient_W_per_K']['post']['true']:.0f} W/K after. "
            "In the post period, the same house without the retrofit under the same controls "
            f"would have used {ver.truth['post_period_heat_kWh']['without_retrofit']:,.0f} kWh "
            f"({tc['post_period_saving_pct_same_controls']['true']:.1f} % saved, the warmer "
            "rooms of the insulated house included); verified with the take-back: "
            f"{av['saving_with_take_back_pct']:.1f} %. The avoided energy of IPMVP "
            f"({av['saving_pct']:.1f} %) counts the warmer rooms as a condition of the post "
            "period."
        )
    rep.section("Calibrations")
    for name, cal in (("before", ver.calibration_pre), ("after", ver.calibration_post)):
        rep.heading(f"Model calibrated {name} the retrofit")
        if cal.correction is not None:
            rep.paragraph(cal.correction.summary())
        if cal.flags:
            rep.flags(cal.flags)
    if ver.notes:
        rep.bullets(ver.notes, intro="Notes")
    rep.section("References")
    rep.references([r.entry() for r in (IPMVP, ASHRAE_14, REDDY_CLARIDGE_2000,
                                         SUNIKKA_BLANK_2012, FORSSELL_LJUNG_1999)])  # fmt: skip
    return rep.write(path)


def _verification_track_record(rep) -> None:
    """How the same verification held on a house thermocal did not write (EnergyPlus 25.2)."""
    from thermocal.retrofit.track_record import INDEPENDENT_VERIFICATIONS

    rows = [
        {
            "case": c.case,
            "verified - EnergyPlus's annual saving": f"{c.error_pp:+.1f} pp",
            "90 % interval covers it": "yes" if c.covered else "no",
            "post period's avoided energy - EnergyPlus's": f"{c.post_period_error_pp:+.1f} pp",
            "verdict": c.verdict,
        }
        for c in INDEPENDENT_VERIFICATIONS.values()
    ]
    rep.paragraph(
        "How far such a verification can be off: the same analysis on a house thermocal did "
        "not write, measured by EnergyPlus 25.2 before and after a wall retrofit, against "
        "EnergyPlus's own annual saving and its run without the retrofit over the same weeks "
        "(pp: percentage points):"
    )
    rep.table(pd.DataFrame(rows), caption="The verification against EnergyPlus")


def _iv(v: dict, spec: str = ".0f") -> str:
    return f"{v['value']:{spec}} ({v['lo']:{spec}} to {v['hi']:{spec}})"


def write_verify_outputs(ver: Verification, out_dir: Path | str) -> dict:
    """Write verify.json, daily_heat.csv, figures/*.png and report.html into ``out_dir``."""
    from thermocal.report.figures import close, figure_to_png

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    results = results_dict(ver)
    (out / "verify.json").write_text(json.dumps(results, indent=2))
    daily = ver.daily.copy()
    daily.index = daily.index.tz_localize(None) if daily.index.tz is not None else daily.index
    daily.rename(columns={"measured": "measured_kWh", "baseline": "baseline_kWh"}).to_csv(
        out / "daily_heat.csv", index_label="date", float_format="%.3f"
    )
    fig_dir = out / "figures"
    fig_dir.mkdir(exist_ok=True)
    figures = {}
    for name, fig in make_figures(ver).items():
        figures[name] = figure_to_png(fig)
        close(fig)
        (fig_dir / f"{name}.png").write_bytes(figures[name])
    write_report(ver, results, figures, out / "report.html")
    return results


