"""report.html of the retrofit workflow: a deliverable a consultant can hand to a client.

Order: executive summary (recommendation in two sentences), strategies with final energy, cost,
CO2, investment and payback, what the intervals cover, annual demand, assumptions, calibration,
validation with residual diagnostics, data and data quality, (demo) the check against the
generator, references, provenance. The method is cited once, in the references section.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.retrofit import references as refs
from thermocal.retrofit.config import MIN_DRAWS, NO_INTERVAL
from thermocal.retrofit.economics import measure_areas, measure_investment, recommend
from thermocal.retrofit.gains import has_gains
from thermocal.retrofit.model import ESTIMATED_PARAMETERS
from thermocal.retrofit.tables import has_intervals
from thermocal.retrofit.workflow import RetrofitAnalysis
from thermocal.textformat import format_number

MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")

#: Sources of the economic defaults, shown next to the values the report used.
ECONOMICS_SOURCES = {
    "system_efficiency": "assumption: annual efficiency of an older oil or gas boiler with "
    "its distribution losses (no measurement of the system); set economics.system_efficiency",
    "energy_price": "placeholder of the order of Swiss heating-oil prices of recent years "
    "(about 100-130 CHF per 100 litres at about 10 kWh per litre); set economics.energy_price",
    "emission_factor": f"{refs.GEG_2020.key}: heating oil 310 g CO2-eq/kWh; set "
    "economics.emission_factor for another energy carrier (natural gas 240, grid electricity "
    "560, wood 20)",
    "measure_costs": "indicative full costs per m2 (placeholders, not quotes); set "
    "measures.<name>.cost_per_m2 and measures.<name>.cost",
}


def economics_source(config, key: str) -> str:
    """Where the value of ``economics.<key>`` comes from, for the report's assumptions.

    Parameters
    ----------
    config : RetrofitConfig
    key : {"system_efficiency", "energy_price", "emission_factor"}

    Returns
    -------
    str
        "given in the configuration", the carrier's default with its source, the measured
        boiler's efficiency, or the heating-oil placeholder of :data:`ECONOMICS_SOURCES`.
    """
    from thermocal.retrofit.config import CARRIER_EMISSION_FACTORS, CARRIER_SYSTEM_EFFICIENCY

    eco = config.economics
    if eco.given(key):
        return f"given in the configuration (economics.{key})"
    carrier = eco.carrier()
    measurements = config.measurements
    if key == "system_efficiency":
        if carrier in CARRIER_SYSTEM_EFFICIENCY:
            why = {
                "heat pump": "useful heat per kWh of electricity: an assumed seasonal COP",
                "electricity": "useful heat per kWh of electricity, direct electric heating",
                "district heating": "the heat bought is the heat metered at the building's "
                "substation",
            }.get(carrier, "the carrier's default")
            return f"default for {carrier} ({why}); set economics.system_efficiency"
        if measurements is not None and measurements.heat_source == "fuel_meter":
            return (
                "the measured boiler's (measurements.boiler_efficiency, with which the fuel "
                "meter was turned into useful heat); set economics.system_efficiency"
            )
    if key == "emission_factor" and carrier != "heating oil":
        if carrier in CARRIER_EMISSION_FACTORS:
            return (
                f"{refs.GEG_2020.key}: {carrier} {1000 * eco.emission_factor:.0f} g CO2-eq/kWh; "
                "set economics.emission_factor"
            )
        return (
            f"heating oil's {1000 * eco.emission_factor:.0f} g CO2-eq/kWh ({refs.GEG_2020.key}) "
            f"kept as a placeholder: {eco.energy_carrier}'s depends on its supplier; set "
            "economics.emission_factor"
        )
    if key == "energy_price" and carrier != "heating oil":
        return (
            f"not {eco.energy_carrier}'s: {ECONOMICS_SOURCES['energy_price']} (the heating-oil "
            "placeholder)"
        )
    return ECONOMICS_SOURCES[key]


def _money(value, currency: str) -> str:
    return f"{format_number(value, ',.0f')} {currency}"


def interval_labels(interval: float) -> tuple[str, str]:
    """Names of the lower and upper interval quantiles, e.g. ("p05", "p95") for 90 %."""
    lo = round(50.0 * (1.0 - interval), 6)

    def name(q: float) -> str:
        return f"p{q:02.0f}" if q == int(q) else f"p{q:g}"

    return name(lo), name(100.0 - lo)


def heating_degree_days(temp_air: pd.Series, base: float = 20.0, limit: float = 12.0) -> float:
    """Heating degree days [K d]: sum over days with a mean below ``limit`` of ``base - mean``.

    Parameters
    ----------
    temp_air : pd.Series [C] with a DatetimeIndex (any step; daily means are taken).
    base, limit : float [C]
        Indoor base temperature and heating limit (20/12 as in SIA 381/3 and VDI 3807).
    """
    daily = temp_air.resample("1D").mean().dropna()
    return float((base - daily[daily < limit]).sum())


def _latlon(weather: dict) -> str:
    lat, lon = weather.get("latitude"), weather.get("longitude")
    if lat is None or lon is None:
        return "location not given"
    return f"{abs(lat):.2f}° {'N' if lat >= 0 else 'S'}, {abs(lon):.2f}° {'E' if lon >= 0 else 'W'}"


def _measures_label(measures) -> str:
    return " + ".join(m.replace("_", " ") for m in measures) if measures else "no retrofit"


def write_report(
    analysis: RetrofitAnalysis,
    results: dict,
    tables: dict,
    figures: dict,
    path: Path,
    *,
    title: str | None = None,
    logo: bytes | Path | str | None = None,
    client: str | None = None,
) -> Path:
    """Write the self-contained report.html and return its path.

    Parameters
    ----------
    analysis, results, tables, figures
        From :func:`thermocal.retrofit.outputs.write_outputs`.
    logo : PNG/SVG/JPEG bytes or a path, optional
        Shown in the header (embedded, the file stays offline).
    client : str, optional
        Line under the title (e.g. the client's name and address).
    """
    from thermocal.report import HtmlReport

    cfg = analysis.config
    eco = cfg.economics
    cur = eco.currency
    hlc = results["heat_loss_coefficient_W_per_K"]
    dem = results["annual_heating_demand_kWh"]
    b = analysis.building
    scen = tables["scenarios"]
    econ = tables["economics"]
    pct = f"{100 * cfg.uncertainty.interval:.0f} %"
    low, high = interval_labels(cfg.uncertainty.interval)
    intervals = has_intervals(results)  # uncertainty.draws: 0 -> none, said once in a note
    measures = cfg.measure_objects()
    gate = analysis.gate or {"passed": True, "summary": ""}
    # a model that failed its validation on the test period recommends nothing
    rec = recommend(econ, scen["saving_pct"]) if gate["passed"] else None
    subtitle = (
        "Heating demand and envelope-retrofit strategies from a calibrated fifth-order RC model"
        + (f" - {client}" if client else "")
    )
    rep = HtmlReport(title or f"Retrofit analysis: {b.name}", subtitle=subtitle, logo=logo)

    # ------------------------------------------------------------------ executive summary
    rep.section("Executive summary")
    if not gate["passed"]:
        rep.paragraph(gate["summary"], css_class="lead")
    base = econ.iloc[0]
    today = (
        f"Today the house needs about {dem['value']:,.0f} kWh of heat a year"
        + (f" ({pct} interval {dem['p05']:,.0f} to {dem['p95']:,.0f} kWh)" if intervals else "")
        + f", that is {base['final_energy_kWh']:,.0f} "
        f"kWh of {eco.energy_carrier}, about {_money(base['cost_per_year'], cur)} and "
        f"{base['co2_kg_per_year'] / 1000:,.1f} t CO2 a year."
    )
    if rec is not None:
        r = rec["row"]
        srow = scen[scen["code"] == rec["code"]].iloc[0]
        names = next(s.measures for s in analysis.strategies if s.code == rec["code"])
        none_within = "none pays back" in str(rec.get("rule", ""))
        opening = (
            "No strategy pays for itself within 30 years (a typical service life of envelope "
            "measures) at today's energy price; the one that pays back soonest is strategy "
            if none_within
            else "We recommend strategy "
        )
        advice = (
            f"{opening}{rec['code']} ({_measures_label(names)}): it saves about "
            f"{srow['saving_pct']:.0f} % of the heat"
            + (f" ({pct} interval {format_number(srow['saving_pct_p05'], '.0f')} to "
               f"{format_number(srow['saving_pct_p95'], '.0f')} %)" if intervals else "")
            + f", about {_money(r['cost_saving_per_year'], cur)}"
            f" and {r['co2_saving_kg_per_year'] / 1000:,.1f} t CO2 a year, costs about "
            f"{_money(r['investment'], cur)} and pays for itself in about "
            f"{format_number(r['payback_years'], '.0f')} years "
            + (f"({format_number(r['payback_years_lo'], '.0f')} to "
               f"{format_number(r['payback_years_hi'], '.0f')} years) " if intervals else "")
            + "at today's energy price."
        )  # fmt: skip
    elif not gate["passed"]:
        advice = (
            "These figures come from a model that failed its validation (above): read them as "
            "a rough indication only; the strategy table below is not a recommendation."
        )
    else:
        advice = "None of the strategies saves running cost at the configured prices."
    rep.paragraph(f"{today} {advice}", css_class="lead")
    if not intervals:
        rep.note(_no_interval_note(pct))
    if gate["passed"] and gate.get("summary"):
        rep.paragraph(gate["summary"])
    if (results["calibration"].get("method") or {}).get("summary"):
        rep.paragraph(results["calibration"]["method"]["summary"])
    corr = results["calibration"].get("correction")
    if corr:
        in_situ = set(corr.get("measured_in_situ") or ())
        parts = [
            f"{corr['groups'][g]['label']} {100 * (k - 1):+.0f} %"
            + (
                "" if g in in_situ  # its label says "(in situ)"
                else " (measured)" if corr["separated_by_data"][g]
                else " (not separable: prior)"
            )
            for g, k in corr["factors"].items()
        ]  # fmt: skip
        rep.paragraph(
            "The measurements correct the heat losses calculated from the building file: "
            + ", ".join(parts)
            + f"; heat loss coefficient {hlc['value']:.0f} W/K ({pct} interval "
            f"{format_number(hlc['p05'], '.0f')} to {format_number(hlc['p95'], '.0f')} W/K) "
            "against "
            f"{hlc['audit_prior']:.0f} W/K from the building file alone (section Calibration)."
        )
    tiles = {
        "Heat demand today": f"{dem['value']:,.0f} kWh/a",
        **({f"{pct} interval": f"{dem['p05']:,.0f} – {dem['p95']:,.0f} kWh/a"} if intervals
           else {"Uncertainty": NO_INTERVAL}),
        "Heat loss coefficient": f"{hlc['value']:.0f} W/K "
        f"({pct}: {format_number(hlc['p05'], '.0f')} – {format_number(hlc['p95'], '.0f')})",
        "Running cost today": f"{_money(base['cost_per_year'], cur)}/a",
    }
    if rec is not None:
        r = rec["row"]
        tiles[f"Recommended: {rec['code']}"] = (
            f"-{scen.loc[scen['code'] == rec['code'], 'saving_pct'].iloc[0]:.0f} % heat"
        )
        tiles["Investment"] = _money(r["investment"], cur)
        tiles["Simple payback"] = f"{format_number(r['payback_years'], '.0f')} years"
    if "true" in hlc:
        tiles["True HLC (demo generator)"] = (
            f"{hlc['true']:.0f} W/K ({hlc['relative_error_pct']:+.1f} %)"
        )
    rep.key_values(tiles)
    if rec is not None:
        rep.paragraph(
            f"How the recommendation is chosen: {rec['rule']}. Payback is simple (investment "
            "divided by the yearly saving of running cost, no interest, no price changes, no "
            "subsidies); the costs are those of the configuration (see Assumptions). A "
            "consultant should check them against quotes before advising."
        )
    flags = results["calibration"]["flags"]
    if flags:
        rep.note(
            f"The calibration raised {len(flags)} point(s) to check (section Calibration). "
            "They concern how well single parameters are determined"
            + (
                "; the heat loss coefficient and the demand above are checked on the test "
                "period (section Validation)."
                if gate["passed"]
                else "."
            )
        )
    for note in analysis.notes:
        rep.note(note)
    rep.paragraph(
        f"Building: {b.name}, {b.floors} floors, {b.heated_floor_area:.0f} m² heated floor "
        f"area, {b.volume:.0f} m³, emitters: {b.emitter}. Measurements: training "
        f"{analysis.training[0]:%Y-%m-%d} to {analysis.training[1]:%Y-%m-%d}"
        + (f", test to {analysis.test[1]:%Y-%m-%d}." if analysis.test else ".")
    )

    # ------------------------------------------------------------------ strategies
    rep.section("Retrofit strategies: energy, cost, CO2 and payback")
    areas = measure_areas(analysis.model.envelope, float(b.heated_floor_area))
    mrows = []
    for name, m in measures.items():
        what = []
        if m.u_value is not None:
            what.append(f"U = {m.u_value:g} W/(m² K)")
        if m.g_value is not None:
            what.append(f"g = {m.g_value:g}")
        if m.air_change_rate_change:
            what.append(f"air change {m.air_change_rate_change:+g} 1/h")
        if m.heat_recovery_air_change_rate:
            what.append(
                f"ventilation {m.heat_recovery_air_change_rate:g} 1/h with "
                f"{100 * m.heat_recovery_efficiency:.0f} % heat recovery"
            )
        mrows.append({
            "measure": name.replace("_", " "),
            "acts on": m.component.replace("_", " "),
            "after retrofit": ", ".join(what),
            "area [m²]": areas[m.component],
            f"cost per m² [{cur}]": m.cost_per_m2,
            f"fixed cost [{cur}]": m.cost,
            f"investment [{cur}]": measure_investment(m, areas),
            "description": m.description,
        })  # fmt: skip
    rep.table(
        pd.DataFrame(mrows),
        caption="Measures (area of the component; heated floor area for ventilation measures)",
        number_format="{:,.0f}",
    )
    codes = list(scen["code"])
    e = econ.copy()
    e.insert(1, "measures", [_measures_label(s.measures) for s in analysis.strategies])
    e["saving [%]"] = scen["saving_pct"].to_numpy()
    e["saving interval [%]"] = [
        f"{format_number(a, '.0f')} – {format_number(c, '.0f')}"
        for a, c in zip(scen["saving_pct_p05"], scen["saving_pct_p95"], strict=True)
    ]  # fmt: skip
    e["payback interval [a]"] = [
        "" if not np.isfinite(p) else f"{format_number(a, '.0f')} – {format_number(c, '.0f', '∞')}"
        for p, a, c in zip(e["payback_years"], e["payback_years_lo"], e["payback_years_hi"],
                           strict=True)
    ]  # fmt: skip
    shown = {
        "code": "code",
        "measures": "measures",
        "useful_heat_kWh": "useful heat [kWh/a]",
        "saving [%]": "saving [%]",
        "saving interval [%]": f"{pct} interval",
        "final_energy_kWh": f"final energy [kWh/a] ({eco.energy_carrier})",
        "cost_per_year": f"running cost [{cur}/a]",
        "co2_kg_per_year": "CO2 [kg/a]",
        "investment": f"investment [{cur}]",
        "cost_saving_per_year": f"saving [{cur}/a]",
        "payback_years": "simple payback [a]",
        "payback interval [a]": f"payback {pct} interval [a]",
    }
    if not intervals:  # no columns of empty cells: the caption and the note say why
        del shown["saving interval [%]"], shown["payback interval [a]"]
    table = e[list(shown)].rename(columns=shown)
    table.loc[0, shown["payback_years"]] = np.nan
    rep.table(
        table,
        caption=(
            f"Strategies: useful heat (what the radiators deliver), final energy = useful heat / "
            f"{eco.system_efficiency:g} system efficiency, at {eco.energy_price:g} {cur}/kWh "
            f"and {eco.emission_factor:g} kg CO2/kWh"
            + (f"; highlighted: the recommended strategy {rec['code']}" if rec else "")
            + ("" if intervals else f"; {NO_INTERVAL}")
        ),
        number_format={
            shown["saving [%]"]: "{:.1f}",
            shown["payback_years"]: "{:.0f}",
            **{v: "{:,.0f}" for k, v in shown.items() if k not in ("saving [%]", "payback_years")},
        },
        highlight_rows=[codes.index(rec["code"])] if rec else (),
    )
    end_error = float(scen["saving_pct_mcse"].max()) if "saving_pct_mcse" in scen else 0.0
    if end_error > 0:
        rep.paragraph(
            f"The savings' interval ends come from {analysis.config.uncertainty.draws} parameter "
            f"draws: they are known to about ±{end_error:.1f} percentage points (Monte Carlo "
            "standard error of the less precise end; more draws narrow it: "
            "uncertainty.draws)"
            + _interval_precision(results)
            + "."
        )
    rep.figure(
        figures["scenario_savings"],
        caption="Saving of heat per strategy; "
        + (f"whiskers: {pct} interval (parameter uncertainty)" if intervals else NO_INTERVAL),
        close_figure=False,
    )
    rep.figure(
        figures["scenario_demand"], caption="Annual heat demand per strategy", close_figure=False
    )

    # ------------------------------------------------------------------ intervals
    if intervals:
        rep.section("What the intervals cover, and what they do not")
        _interval_coverage(rep, analysis, results)
    else:
        rep.section("Uncertainty")
        rep.paragraph(
            f"The demands and savings of this report have {NO_INTERVAL}: the estimates alone "
            "(executive summary)."
        )
    _track_record(rep)
    if results.get("measurement_advice"):
        _measurement_advice(rep, results["measurement_advice"], pct)

    # ------------------------------------------------------------------ annual demand
    rep.section("Annual heating demand")
    ref_items = {k: v for k, v in dem["references"].items() if not isinstance(v, list)}
    ref_text = "; ".join(f"{k}: {v:,.0f} kWh" for k, v in ref_items.items())
    rep.paragraph(
        f"Simulated over {_weather_year_text(dem['weather'])} "
        f"with the 24-hour indoor temperature profile (see Assumptions) and ideal heating: "
        f"{dem['value']:,.0f} kWh/a ({dem['per_m2_kWh']:.0f} kWh per m² heated floor area)."
        + (f" References: {ref_text}." if ref_text else "")
    )
    rep.figure(figures["monthly_demand"], caption="Monthly heating demand", close_figure=False)
    if "annual_comparison" in figures:
        rep.figure(figures["annual_comparison"], caption="Annual demand vs references")
    mon = pd.DataFrame({"month": list(MONTHS), "demand [kWh]": dem["monthly"]})
    if intervals:
        mon[f"{low} [kWh]"], mon[f"{high} [kWh]"] = dem["monthly_p05"], dem["monthly_p95"]
    rep.table(
        mon,
        caption="Monthly demand [kWh]" + ("" if intervals else f"; {NO_INTERVAL}"),
        number_format="{:,.0f}",
    )

    # ------------------------------------------------------------------ assumptions
    rep.section("Assumptions")
    _assumptions(rep, analysis, results)

    # ------------------------------------------------------------------ calibration
    rep.section("Calibration")
    _calibration(rep, analysis, results, tables)

    # ------------------------------------------------------------------ validation
    rep.section("Validation")
    _validation(rep, analysis, results, tables, figures)

    # ------------------------------------------------------------------ data
    rep.section("Measured data and data quality")
    _data_quality(rep, analysis, results, figures)

    if "reference_check" in results:
        rep.section("Check against a known answer (demo)")
        _reference_check(rep, results, figures, pct if intervals else None, low, high)

    # ------------------------------------------------------------------ references
    rep.section("References")
    rep.paragraph(
        "Method: the fifth-order RC model, its calibration, validation, demand simulation and "
        "strategy coding follow the first reference; parameter correlation limit |r| < 0.98 "
        "and residual checks follow Madsen et al. (2016)."
    )
    rep.references([r.entry() for r in refs.ALL])
    prov = results.get("provenance", {})
    if prov:
        inputs = "; ".join(
            f"{k}: {v['file']} (sha256 {str(v['sha256'])[:12]}…)" for k, v in prov["inputs"].items()
        )
        rep.paragraph(
            f"Produced by thermocal {prov['thermocal_version']} on {prov['created']} "
            f"({prov['command_line'] or 'Python API'}); seeds {prov['seeds']}; inputs: {inputs}.",
            css_class="small",
        )
    return rep.write(path)


def _interval_coverage(rep, analysis: RetrofitAnalysis, results: dict) -> None:
    """What the demand's and the savings' intervals cover and what they do not (bullets)."""
    cfg = analysis.config
    pct = f"{100 * cfg.uncertainty.interval:.0f} %"
    low, high = interval_labels(cfg.uncertainty.interval)
    at_bound = results["calibration"]["parameters_at_bounds"]
    fixed = results["calibration"].get("parameters_fixed", [])
    corrected = analysis.calibration.correction is not None
    covered = [
        f"the estimation uncertainty of the calibrated parameters (heat loss coefficient part "
        f"H_est and the heat capacities), {cfg.uncertainty.draws} draws from their estimated "
        "covariance",
    ]
    if corrected:
        covered = [
            f"the posterior uncertainty of the corrections of the audit U-values (prior "
            f"{100 * cfg.uncertainty.u_value_rel_std:.0f} % relative spread per envelope group, "
            "narrowed where the measurements separate the group), of H_est and of the heat "
            f"capacities, including those on a bound: {cfg.uncertainty.draws} draws"
        ]
    elif cfg.uncertainty.u_value_rel_std > 0:
        covered.append(
            f"the uncertainty of the audit U-values ({100 * cfg.uncertainty.u_value_rel_std:.0f}"
            " % relative spread, keeping the measured heat loss coefficient), which decides "
            "how much each single measure saves"
        )
    ground = (results.get("uncertainty") or {}).get("ground")
    if ground:
        labels = {
            "soil_conductivity": "the soil's thermal conductivity",
            "basement_air_change_rate": "the unheated basement's air change",
            "slab_edge_psi_change": "the slab edge a floor-insulation measure leaves "
            "uninsulated (linear thermal bridge)",
        }
        covered.append(
            "the ground's inputs the description does not know, each draw keeping the "
            "measured heat balance: "
            + "; ".join(
                f"{labels[k]} ({v['distribution']}; drawn 5-95 %: {v['p05']:.2g}-{v['p95']:.2g})"
                for k, v in ground.items()
            )
        )
    rep.bullets(covered, intro=f"The {pct} intervals ({low} to {high}) cover:")
    not_covered = [
        "the weather: one typical year is used; a cold winter needs more, a mild one less "
        "(roughly in proportion to the heating degree days, see Assumptions)",
        "the occupants: set-point temperatures and window airing as during the measurements"
        + (
            "; internal gains as during the measurements (not an input: internal_gains: in "
            "the configuration); other habits change the demand"
            if not has_gains(cfg.internal_gains)
            else f"; other habits change the demand (the internal gains' "
            f"{100 * _gains_rel_std(analysis):.0f} % uncertainty is covered)"
        ),
        "the model structure: five lumped temperatures stand for the whole house; effects it "
        "cannot represent (thermal bridges a retrofit changes other than the slab edge, "
        "moisture, zones held at other temperatures) are not in the intervals",
        "prices, system efficiency and costs: the economic figures are computed at the "
        "configured values and scale directly with them",
    ]
    if corrected:
        from thermocal.retrofit.correction import COMPONENT_WORDS, shared_factor_components

        model = analysis.model
        shared = [
            f"the {COMPONENT_WORDS[c]}"
            for c in shared_factor_components(model.envelope, model.in_situ or ())
        ]
        if len(shared) > 1:
            not_covered.append(
                "differences between the description errors of "
                + (", ".join(shared[:-1]) + " and " + shared[-1])
                + ": they share one correction factor, so a measure on one of them is "
                "taken to be off by the same factor as the others (an in-situ U-value gives "
                "a component its own; thermocal retrofit --advise shows what one would change)"
            )
    held = list(fixed) if corrected else at_bound + list(fixed)
    if held:
        not_covered.append(
            "parameters on an estimation bound or fixed ("
            + ", ".join(held)
            + "): they are held at their value in every draw"
        )
    rep.bullets(not_covered, intro="They do not cover:")
    rep.paragraph(
        "Savings are computed in pairs (the same parameter draw with and without the "
        "retrofit), so a strategy's saving interval is narrower than the difference of the two "
        "demand intervals."
    )


def _no_interval_note(pct: str) -> str:
    """The report's one note on the missing intervals of ``uncertainty.draws: 0``."""
    return (
        f"Demands, savings and paybacks: {NO_INTERVAL}. The configuration asks for no "
        "uncertainty analysis, so they are the calibrated model's estimates alone, not "
        "certain figures (the heat loss coefficient's interval is the calibration's own); "
        f"uncertainty.draws: 200 (the default; at least {MIN_DRAWS}) gives their {pct} "
        "intervals."
    )


def _track_record(rep) -> None:
    """How the same analysis held on houses thermocal did not write (EnergyPlus 25.2 twins,
    their 90 % intervals whatever this run's ``uncertainty.interval``)."""
    from thermocal.retrofit.track_record import IN_SITU_CHECKS, INDEPENDENT_CHECKS

    checks = list(INDEPENDENT_CHECKS.values())
    rep.paragraph(
        "How far such figures can be off: the same analysis, with its default settings, on "
        f"{len(checks)} houses thermocal did not write, each simulated by EnergyPlus 25.2 "
        "(the measurements a user would have, the year and the 15 retrofit strategies; "
        "thermocal given only the areas and nominal U-values of the building file; pp: "
        "percentage points):"
    )
    rows = [_track_record_row(c) for c in checks]
    rep.table(pd.DataFrame(rows), caption="The analysis against EnergyPlus on independent houses")
    rep.bullets([f"{c.house}: {c.note}" for c in checks])
    plates = list(IN_SITU_CHECKS.values())
    rep.paragraph(
        "With one more measurement an energy auditor makes, a heat-flux plate on one wall for "
        "two weeks of winter (in-situ U-value, ISO 9869-1; the configuration's in_situ "
        "section), on the same houses:"
    )
    rep.table(
        pd.DataFrame([_track_record_row(c) for c in plates]),
        caption="The analysis with an in-situ wall U-value against EnergyPlus",
    )
    rep.bullets([f"{c.house}: {c.note}" for c in plates])


def _measurement_advice(rep, advice: dict, pct: str) -> None:
    """Which heat-flux plate would narrow the savings' intervals most (``--advise``)."""
    rep.heading("Which measurement next")
    if not advice["available"]:
        rep.paragraph(f"No measurement advice: {advice['reason']}.")
        return
    rep.paragraph(
        f"{advice['summary']}. How it was found: for each component a heat-flux plate can "
        "measure, the plate's reading was drawn from what the calibrated model now expects of "
        "that component (its current estimate with its uncertainty and the plate's, "
        f"{100 * advice['plate_rel_std']:.0f} %), the whole analysis was run again with that "
        f"reading, and the half-widths of the savings' {pct} intervals were averaged over the "
        f"readings (preposterior analysis; {advice['draws']:,} draws in every run, so the "
        "present figures differ a little from the strategy table's). On the two EnergyPlus "
        "houses "
        "the expected median half-width after a plate on the walls was within 1 pp of what "
        "the real plate then gave."
    )
    rows = []
    for a in advice["components"]:
        row = {
            "measurement": a["label"],
            "on": a["where"],
            "U described / now": f"{a['described_u']:.3g} / {a['expected_u']:.3g}",
            "expected reading": f"+-{100 * a['reading_rel_std']:.0f} %",
            "median half-width": f"{a['median_half_width_pp']:.1f} -> "
            f"{a['expected_median_half_width_pp']:.1f} pp",
        }
        if a["recommended_half_width_pp"] is not None:
            row["recommended strategy"] = (
                f"{a['recommended_half_width_pp']:.1f} -> "
                f"{a['expected_recommended_half_width_pp']:.1f} pp"
            )
        rows.append(row)
    rep.table(
        pd.DataFrame(rows),
        caption="Expected half-widths of the savings' intervals after one heat-flux plate "
        "[W/(m2 K); percentage points]",
    )


def _track_record_row(c) -> dict:
    """One house's row of the track record tables."""
    return {
        "house": c.house,
        "heat loss coefficient": f"{c.hlc_error_pct:+.1f} %",
        "demand": f"{c.demand_error_pct:+.1f} %",
        "savings: mean / max difference": f"{c.savings_mean_abs_pp:.1f} / "
        f"{c.savings_max_abs_pp:.1f} pp",
        "savings within 3 pp": f"{c.within_3pp} of 15",
        "90 % intervals covering": f"{c.covered} of 15",
        "median half-width": f"{c.median_half_width_pp:.1f} pp",
        "validation": "passed" if c.gate_passed else "failed",
    }


def _assumptions(rep, analysis: RetrofitAnalysis, results: dict) -> None:
    cfg = analysis.config
    eco = cfg.economics
    dem = results["annual_heating_demand_kWh"]
    prof = np.asarray(analysis.indoor_profile, float)
    w = dem["weather"]
    year = analysis.year_inputs
    hdd_year = heating_degree_days(year["Te"]) if year is not None else float("nan")
    d = analysis.data
    hdd_meas = heating_degree_days(d["Te"])
    days_meas = (d.index[-1] - d.index[0]) / pd.Timedelta(days=1)
    profile_text = (
        "24-hour profile of the measured indoor temperature, repeated every day"
        if cfg.demand.indoor_profile == "measured"
        else f"constant {float(cfg.demand.indoor_profile):.1f} C"
    )
    rows = [
        ("Indoor temperature", f"{profile_text}: mean {prof.mean():.1f} C, "
         f"{prof.min():.1f} to {prof.max():.1f} C"),
        ("Heating control", "ideal heating only: exactly the heat needed to hold the profile, "
         "never cooling; the house floats above it when sun or stored heat warm it"),
        ("Internal gains", _gains_text(analysis)),
        ("Ventilation and infiltration", "part of the estimated conductance H_est with thermal "
         "bridges and doors (calibrated H_est "
         f"{results['heat_loss_coefficient_W_per_K']['H_est']:.0f} W/K; the building file "
         f"suggests {analysis.model.audit_h_est:.0f} W/K at "
         f"{float(analysis.building.air_change_rate):g} air changes per hour); "
         "envelope measures leave it unchanged, ventilation measures change it"),
        ("Weather", f"{w.get('name') or 'typical year'} ({_latlon(w)}), file "
         f"{results.get('provenance', {}).get('inputs', {}).get('weather', {}).get('file', '')}"),
        ("Heating degree days (20/12)", f"typical year {hdd_year:,.0f} K d; measurement period "
         f"{hdd_meas:,.0f} K d over {days_meas:.0f} days"),
        ("Retrofits", "change U-values (and for windows optionally the g-value) of the "
         "components; heat capacities and the estimated H_est stay as calibrated"),
        ("Heating system", f"{eco.energy_carrier}, annual efficiency {eco.system_efficiency:g} "
         f"(useful heat / final energy). Source: {economics_source(cfg, 'system_efficiency')}"),
        ("Energy price", f"{eco.energy_price:g} {eco.currency}/kWh of final energy. Source: "
         f"{economics_source(cfg, 'energy_price')}"),
        ("Emission factor", f"{eco.emission_factor:g} kg CO2-eq/kWh of final energy. Source: "
         f"{economics_source(cfg, 'emission_factor')}"),
        ("Measure costs", ECONOMICS_SOURCES["measure_costs"]),
    ]  # fmt: skip
    rep.table(pd.DataFrame(rows, columns=["assumption", "value"]), caption="Assumptions")
    rep.table(
        pd.DataFrame({"hour": np.arange(24), "indoor set point [C]": prof})
        .T.reset_index(drop=True)
        .set_axis([f"{h:02d}" for h in range(24)], axis=1)
        .iloc[1:],
        caption="Indoor temperature profile [C] by hour of the day (the mean over the hour "
        "from hh:00; the controller holds the mean of two hours at their boundary)",
        number_format="{:.1f}",
    )


def _calibration(rep, analysis: RetrofitAnalysis, results: dict, tables: dict) -> None:
    cfg = analysis.config
    cal = results["calibration"]
    hlc = results["heat_loss_coefficient_W_per_K"]
    method = cal.get("method") or {}
    if method.get("summary"):
        rep.paragraph(
            method["summary"]
            + (
                " Under a thermostat the heat is the controller's answer to every disturbance "
                "and the indoor temperature barely moves, so a fit of the temperature biases "
                "the estimates (closed-loop identification, Ljung 1999 sec. 13.4; Forssell and "
                "Ljung 1999); the fit of the heat is the part of the model the demand and the "
                "savings use. model.calibration: temperature | heat | auto selects it."
                if method.get("method") == "heat"
                else " model.calibration: temperature | heat | auto selects it."
            )
        )
    fit = (
        "Least-squares fit of the heat"
        if method.get("method") == "heat"
        else ("Maximum-likelihood fit")
    )
    rep.paragraph(
        f"{fit} of the fifth-order model on the training period: log-"
        f"likelihood {cal['loglike']:.1f}, AIC {cal['aic']:.1f}, converged: "
        f"{cal['converged']}, {cal['fit_seconds']:.1f} s. Largest |correlation| between the "
        "estimated physical parameters: "
        f"{format_number(cal['max_abs_correlation_physical'], '.3f')} "
        f"(limit {cfg.model.max_correlation}, Madsen et al. 2016)."
    )
    corr = cal.get("correction")
    if cal.get("in_situ"):
        _in_situ_table(rep, cal["in_situ"])
    if corr:
        rep.paragraph(
            "The data correct the building description in both directions: one factor per "
            "envelope group multiplies the calculated U-values (maximum a posteriori with a "
            f"log-normal prior of {100 * cfg.uncertainty.u_value_rel_std:.0f} % relative spread "
            "per group, uncertainty.u_value_rel_std; model.correction: none restores the "
            "published topology where only H_est is added). Prebound effect: calculated losses "
            "of existing houses are more often too high than too low (Sunikka-Blank and Galvin "
            "2012). A group is separated by the data when they narrow its prior standard "
            "deviation by at least 30 %; otherwise its share follows the prior and only the "
            "total heat loss coefficient is measured."
            + (
                " A component measured in situ has a factor of its own, its prior the "
                "measurement (above)."
                if corr.get("measured_in_situ")
                else ""
            )
        )
        rep.table(
            pd.DataFrame(
                [
                    {
                        "group": corr["groups"][g]["label"],
                        "factor on U": f"{k:.2f}",
                        "prior sd of ln k": f"{corr['prior_std_log'][g]:.2f}",
                        "posterior sd of ln k": f"{corr['posterior_std_log'][g]:.2f}",
                        "data separate it": "measured in situ"
                        if g in corr.get("measured_in_situ", ())
                        else "yes" if corr["separated_by_data"][g] else "no (prior)",
                    }
                    for g, k in corr["factors"].items()
                ]
            ),  # fmt: skip
            caption="Corrections of the calculated U-values per envelope group",
        )
    if cal["flags"]:
        rep.flags(cal["flags"])
    if cal["parameters_at_bounds"]:
        rep.note(
            "What a parameter on its bound means here: the capacities decide how fast the house "
            "cools and warms, not how much heat a year it needs. A capacity pushed to the edge "
            "of its plausible range (from ISO 52016-1 classes) means the data could not pin it "
            "down within that range; the annual demand depends on the heat loss coefficient, "
            "which stays well determined (its standard error is shown). Savings are computed "
            "with the capacities unchanged, so a capacity at a bound changes them only through "
            "the timing of solar and stored heat."
        )
    p = tables["parameters"]
    p = p[p["estimated"]].copy()
    se = []
    for _, row in p.iterrows():
        status = row["status"]
        if status == "at bound" and analysis.calibration.correction is not None:
            se.append(f"{format_number(row['std_error'], ',.4g')} (at bound, posterior)")
        elif status == "at bound":
            se.append("n/a (at bound)")
        elif status == "fixed":
            se.append("n/a (fixed)")
        else:
            se.append(format_number(row["std_error"], ",.4g"))
    p["std_error"] = se
    p["bounds from"] = [
        results["calibration"]["params"][n].get("bounds_from", "") for n in p["parameter"]
    ]
    rep.table(
        p.drop(columns=["estimated"]).rename(columns={"std_error": "standard error"}),
        caption="Estimated parameters (bounds from the building file unless configured)",
        number_format="{:,.4g}",
    )
    hc = pd.DataFrame([
        {"conductance": k, "value": v}
        for k, v in cal["calculated_conductances_W_per_K"].items()
        if k not in ("g_factor", "H_est_change", "interior_split")
    ])  # fmt: skip
    rep.table(
        hc,
        caption="Calculated conductances [W/K] and shares [-] (ISO 52016-1, ISO 13370)",
        number_format="{:,.4g}",
    )
    rep.paragraph(
        f"HLC = calculated part {hlc['calculated_part']:.1f} W/K + H_est {hlc['H_est']:.1f} W/K "
        f"= {hlc['value']:.1f} W/K (standard error {format_number(hlc['std'], '.1f')} W/K). "
        f"The building file alone suggests {hlc['audit_prior']:.1f} W/K."
    )
    if cal.get("interior") == "split":
        rep.paragraph(
            "The room's inside is split: each element's inner surface exchanges heat with the "
            "air by convection and with the other surfaces by long-wave radiation (ISO 52016-1 "
            "air and surface nodes), reduced to the pair conductances G_<a>_<b> above; the "
            "element paths of the heat balance are inside-face conduction. "
            + (
                "Chosen with the heat fit (model.interior: auto): a thermostat holds the air "
                "temperature, and the losses referenced to it are the split inside's."
                if cfg.model.interior == "auto"
                else "Set by model.interior: split."
            )
        )
    phys = [n for n in ESTIMATED_PARAMETERS if n in analysis.calibration.correlation.columns]
    if phys:
        corr = analysis.calibration.correlation.loc[phys, phys].reset_index(names="parameter")
        rep.table(
            corr,
            caption=f"Correlation of the estimated parameters (|r| < {cfg.model.max_correlation}"
            " required; n/a for parameters at a bound)",
            number_format="{:+.3f}",
        )


_LIMIT_SIGN = {True: "± ", False: "<= "}


def _gains_rel_std(analysis) -> float:
    """Relative uncertainty [-] of all internal gains in the draws (the analysis' own; the
    configured ``rel_std`` when the demand year has no gains)."""
    if analysis.year_gains is None:
        return float(analysis.config.internal_gains.rel_std)
    return float(analysis.gains_rel_std)


def _gains_text(analysis) -> str:
    """The assumptions row on internal gains."""
    from thermocal.retrofit.gains import OCCUPANT_PRESENCE, occupant_day_profile

    ig = analysis.config.internal_gains
    if not has_gains(ig):
        return (
            "not a separate input (internal_gains.source: none): the gains of occupants and "
            "appliances during the measurements are contained in the calibrated heat balance "
            "(mostly in H_est), so the demand assumes the same use of the house"
        )
    year = analysis.year_gains
    step_h = analysis.demand.step_hours
    kwh = float(np.sum(year)) * step_h / 1000.0 if year is not None else 0.0
    # only the chosen source's text is formatted: the others' values are None
    if ig.source == "electricity":
        what = (
            f"the electricity meter x {ig.fraction_inside:g} during the measurements, its mean "
            "daily profile in the demand year"
        )
    elif ig.source == "schedule":
        what = "a 24-hour schedule (internal_gains.schedule_W)"
    elif ig.source == "constant":
        what = f"a constant {ig.constant_W:g} W (internal_gains.constant_W)"
    else:
        what = ""
    people = occupant_day_profile(ig)
    if people is not None:
        hours = float(np.sum(ig.occupant_presence if ig.occupant_presence is not None
                             else OCCUPANT_PRESENCE))  # fmt: skip
        occ_kwh = float(np.mean(people)) * 8760.0 / 1000.0
        source = (
            "internal_gains.occupant_presence" if ig.occupant_presence is not None
            else "SIA 380/1:2016 standard use values of housing"
        )  # fmt: skip
        occ = (
            f"{ig.occupants:g} occupants x {ig.occupant_sensible_W:g} W sensible heat, present "
            f"{hours:.1f} h a day ({source}): {occ_kwh:,.0f} kWh a year"
        )
        what = f"{what}; plus {occ}" if what else occ
    return (
        f"an input into the indoor air: {what}; {kwh:,.0f} kWh a year in all, "
        f"{100 * _gains_rel_std(analysis):.0f} % relative uncertainty in the intervals. In the "
        "calibration they are added to the measured heating power"
    )


def _validation(rep, analysis, results, tables, figures) -> None:
    shown = {
        "period": ("period", None), "mae": ("MAE [K]", "{:.3f}"),
        "mape": ("MAPE [%]", "{:.2f}"), "mse": ("MSE [K²]", "{:.3f}"),
        "mean_simulated": ("mean simulated [C]", "{:.2f}"),
        "mean_measured": ("mean measured [C]", "{:.2f}"),
        "mean_deviation_pct": ("deviation of the mean [%]", "{:+.2f}"), "n": ("hours", "{:.0f}"),
    }  # fmt: skip
    val = tables["validation"][list(shown)].rename(columns={k: v[0] for k, v in shown.items()})
    rep.table(
        val,
        caption="Multi-step simulation of the indoor temperature from the inputs alone",
        number_format={v[0]: v[1] for v in shown.values() if v[1]},
    )
    gate = analysis.gate
    if gate is not None:
        rep.heading("Validation gate (test period)")
        rep.paragraph(gate["summary"])
        if gate["checks"]:
            rep.table(
                pd.DataFrame(
                    [
                        {
                            "criterion": c["name"],
                            "value": f"{c['value']:+.2f} {c['unit']}",
                            "limit": f"{_LIMIT_SIGN[c['absolute']]}{c['limit']:g} {c['unit']}",
                            "verdict": "passed" if c["passed"] else "FAILED",
                        }
                        for c in gate["checks"]
                    ]
                ),  # fmt: skip
                caption="Criteria of the validation gate (configuration key validation:). "
                "Heat: the daily heat the calibrated model needs to follow the measured indoor "
                "temperature against the measured heat (ASHRAE Guideline 14-2014 NMBE and "
                "CV(RMSE); positive NMBE: the model needs less heat than measured)",
            )
    for key, label in (("ti_training", "training"), ("ti_test", "test")):
        if key in figures:
            rep.figure(
                figures[key],
                caption=f"Indoor air temperature over the {label} period: measured and "
                "simulated from the inputs alone (no feedback of the measurements)",
                close_figure=False,
            )
    diag = results["calibration"].get("residual_diagnostics")
    if "residuals" in figures and diag:
        rep.heading("Residual diagnostics")
        white = diag["share_of_lags_outside_band"] <= 0.1 and (
            diag["periodogram_share_outside_band"] <= 0.05
        )
        rep.paragraph(
            "One-step-ahead prediction errors of the indoor temperature over the training "
            f"period: mean {diag['mean_K']:+.3f} K, standard deviation {diag['std_K']:.3f} K, "
            f"autocorrelation at lag 1 {diag['acf_lag1']:+.2f}"
            + (f" and at 24 h {diag['acf_lag24']:+.2f}" if diag.get("acf_lag24") is not None
               else "")
            + f"; {100 * diag['share_of_lags_outside_band']:.0f} % of the lags 1-48 and "
            f"{100 * diag['periodogram_share_outside_band']:.0f} % of the cumulated periodogram "
            "lie outside their white-noise bands. "
            + ("The residuals are close to white noise: the model uses the information in the "
               "data." if white else
               "The residuals are not white noise: some dynamics (e.g. daily solar or occupant "
               "patterns the inputs do not describe) are left in them. The heat loss "
               "coefficient can still be right, but its standard error is then optimistic.")
        )  # fmt: skip
        rep.figure(
            figures["residuals"],
            caption="Residuals of the fifth-order model (Madsen et al. 2016: for a model that "
            "uses all information the autocorrelation stays inside the band and the cumulated "
            "periodogram follows the diagonal)",
            close_figure=False,
        )


def _data_quality(rep, analysis, results, figures) -> None:
    if "inputs" in figures:
        rep.figure(
            figures["inputs"],
            caption="Measured temperatures, heating power (flow x water temperature difference) "
            "and the solar gains computed from the irradiance (ISO 52010-1)",
            close_figure=False,
        )
    q = results.get("measurements_quality")
    if not q:
        rep.paragraph("No data-quality report (the measurements came on a regular grid).")
        return
    sensors = pd.DataFrame(q["sensors"])
    cols = {
        "sensor": "sensor", "quantity": "quantity", "unit": "unit", "n_reports": "readings",
        "coverage": "coverage [%]", "n_gaps": "gaps", "gap_hours": "gap hours",
        "n_impossible": "impossible values", "n_outliers": "outliers",
        "n_outliers_removed": "outliers removed", "n_missing": "missing intervals",
    }  # fmt: skip
    sensors = sensors[[c for c in cols if c in sensors]].rename(columns=cols)
    if "coverage [%]" in sensors:
        sensors["coverage [%]"] = 100.0 * sensors["coverage [%]"].astype(float)
    rep.table(
        sensors,
        caption=f"Data quality per sensor, {q['start'][:16]} to {q['end'][:16]}, step "
        f"{q['step_seconds'] / 3600:g} h",
        number_format="{:,.4g}",
    )
    if q.get("gaps"):
        rep.table(pd.DataFrame(q["gaps"]), caption="Gaps longer than allowed")
    if q.get("flags"):
        flags = pd.DataFrame(q["flags"])
        rep.table(flags.head(50), caption=f"Flagged readings ({len(flags)}; first 50 shown)")
    if q.get("actions"):
        rep.bullets(q["actions"], intro="What was done to the data:")


def _reference_check(rep, results, figures, pct, low, high) -> None:
    """The demo's check of the model against its generator; ``pct`` None: no intervals
    (uncertainty.draws: 0), so no coverage is claimed and no interval columns shown."""
    check = results["reference_check"]
    measures_of = {s["code"]: s["measures"] for s in results["scenarios"]}
    rows = [{**r, "measures": measures_of.get(r["code"], ())} for r in check["strategies"]]
    base = rows[0]
    bias = 100.0 * (base["model_kWh"] / base["reference_kWh"] - 1.0) if base[
        "reference_kWh"] else float("nan")  # fmt: skip
    inside_base = pct is not None and (
        base["model_kWh_p05"] <= (base["reference_kWh"] or -1) <= base["model_kWh_p95"]
    )
    diffs = [
        (r["code"], r["model_saving_pct"] - r["reference_saving_pct"])
        for r in rows[1:]
        if r["reference_saving_pct"] is not None
    ]
    covered = sum(
        1 for r in rows[1:] if pct is not None and r["reference_saving_pct"] is not None
        and r["model_saving_pct_p05"] <= r["reference_saving_pct"] <= r["model_saving_pct_p95"]
    )  # fmt: skip
    worst = max(diffs, key=lambda t: abs(t[1])) if diffs else None
    worst_measures = next((r.get("measures") for r in rows if worst and r["code"] == worst[0]), ())
    rep.paragraph(
        f"The demo data come from a detailed model, {check['reference']}, so the right answers "
        f"are known. At a constant {check['setpoint_C']:.0f} C the calibrated model's demand "
        f"without retrofit is {bias:+.0f} % off the reference"
        + (f" ({'inside' if inside_base else 'outside'} its {pct} interval). " if pct
           else ". ")
        + (f"Its savings differ from the reference's by {min(d for _, d in diffs):+.0f} to "
           f"{max(d for _, d in diffs):+.0f} percentage points (largest: strategy {worst[0]}, "
           f"{_measures_label(worst_measures)})"
           + (f"; the {pct} interval contains the reference's saving for {covered} of "
              f"{len(diffs)} strategies." if pct else ".") if diffs else "")
    )  # fmt: skip
    hlc = results["heat_loss_coefficient_W_per_K"]
    hlc_text = ""
    if "true" in hlc:
        hlc_text = (
            f"Here the heat loss coefficient agrees with the reference's within "
            f"{abs(hlc['relative_error_pct']):.0f} %, so a baseline bias comes mostly from the "
            "gains: the five-node model credits the sun, the ground and the stored heat with a "
            "different share of the heating than the multi-zone house receives. "
        )
    rep.paragraph(
        "What this means: the baseline bias scales every strategy's demand alike and leaves "
        f"their ranking unchanged. {hlc_text}Differences in the savings come from the split of "
        "the losses between the components: the data identify the total heat loss, not its "
        "split, which comes from the audit U-values and areas; a measure on a component the "
        "model weights more than the reference saves more in the model."
        + (" The intervals cover the estimation uncertainty (and the audit U-value spread when "
           "configured), not this structural difference between a five-node model and a "
           "multi-zone one; where the reference lies outside them, that difference dominates."
           if pct else "")
    )  # fmt: skip
    rep.figure(figures["reference_check"], caption="Savings: model vs reference")
    if "monthly_reference_check" in figures:
        rep.figure(
            figures["monthly_reference_check"],
            caption=f"Monthly demand at {check['setpoint_C']:.0f} C: model vs {check['reference']}",
        )
    names = {
        "model_kWh": "model [kWh]", "model_kWh_p05": f"model {low} [kWh]",
        "model_kWh_p95": f"model {high} [kWh]", "model_saving_pct": "model saving [%]",
        "model_saving_pct_p05": f"model saving {low} [%]",
        "model_saving_pct_p95": f"model saving {high} [%]", "reference_kWh": "reference [kWh]",
        "reference_saving_pct": "reference saving [%]",
    }  # fmt: skip
    table = pd.DataFrame(check["strategies"])
    if pct is None:
        table = table.drop(columns=[c for c in names if c.endswith(("_p05", "_p95"))])
    rep.table(
        table.rename(columns=names),
        caption="Model vs reference at constant set point"
        + ("" if pct else f"; {NO_INTERVAL}"),
        number_format={v: "{:,.0f}" if "kWh" in v else "{:.1f}" for v in names.values()},
    )


def _interval_precision(results: dict) -> str:
    """The Monte Carlo precision of the heat loss coefficient's and the demand's interval ends,
    as a clause ("" when they are not in ``results``)."""
    parts = []
    for key, what, unit, fmt in (
        ("heat_loss_coefficient_W_per_K", "the heat loss coefficient's", "W/K", ".1f"),
        ("annual_heating_demand_kWh", "the annual demand's", "kWh", ",.0f"),
    ):
        error = (results.get(key) or {}).get("interval_mcse")
        if error is not None and error > 0:
            parts.append(f"{what} to ±{format(error, fmt)} {unit}")
    return "; " + " and ".join(parts) if parts else ""


def _in_situ_table(rep, in_situ: dict) -> None:
    """The in-situ U-values (ISO 9869-1) the calibration took as its components' priors."""
    rep.paragraph(
        "In-situ U-values: a heat-flux meter's log is reduced by the average method of ISO "
        "9869-1 (the sums of heat flux and temperature difference over whole days, checked by "
        "the standard's convergence criteria); the component gets a correction factor of its "
        "own whose prior is the measured over the described U-value, with the measurement's "
        "standard uncertainty (plate calibration, temperature sensors, convergence, how well "
        "the spot stands for the element). The heating data still fix the total heat loss."
    )
    rows = []
    for component, m in in_situ.items():
        given = m["days"] == 0
        rows.append(
            {
                "component": component,
                "described U": f"{m['described_u_W_per_m2K']:.3g}",
                "measured U": f"{m['u_value_W_per_m2K']:.3g}",
                "x described": f"{m['measured_over_described']:.2f}",
                "std. unc.": f"{100 * m['rel_std']:.1f} %",
                "days / mean dT": "given" if given else
                f"{m['days']} / {m['mean_difference_K']:.1f} K",
                "ISO 9869-1": "-" if given else ("converged" if m["converged"] else "not"),
            }
        )  # fmt: skip
    rep.table(pd.DataFrame(rows), caption="In-situ U-values [W/(m2 K)]")


def _weather_year_text(weather: dict) -> str:
    """"the typical year of NAME" for a typical-year file (its rows put on one year), "the
    measured year of NAME" for an actual year (the Zurich 2015 file was called typical)."""
    name = weather.get("name") or "the weather file"
    if "coerced_year" in weather and weather["coerced_year"] is None:
        return f"the measured year of {name} (the weather file's own year, not a typical one)"
    return f"the typical year of {name}"
