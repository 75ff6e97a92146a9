"""Outputs of the retrofit workflow: results.json, CSV tables, figures and report.html."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from thermocal.jsonsafe import json_number as _num
from thermocal.jsonsafe import json_ready as _clean
from thermocal.montecarlo import interval_end_error, interval_ends
from thermocal.retrofit.economics import measure_investment
from thermocal.retrofit.model import ESTIMATED_PARAMETERS
from thermocal.retrofit.tables import (  # noqa: F401 (scenario_table: public here too)
    _areas,
    _measures_short,
    _recommendation_rule,
    _recommended_code,
    economics_table,
    scenario_table,
)
from thermocal.retrofit.workflow import (
    RetrofitAnalysis,
    heat_loss_coefficient_draws,
    resolve_weather_path,
)

MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")


def results_dict(analysis: RetrofitAnalysis, *, true_hlc: float | None = None) -> dict:
    """The content of results.json."""
    cfg = analysis.config
    cal = analysis.calibration
    model = analysis.model
    lo_q = 0.5 * (1.0 - cfg.uncertainty.interval)
    params = {}
    for name in cal.params.index:
        unit = ""
        if name in model.estimated:
            unit = model.estimated[name][3]
        status = "estimated"
        if name in model.fixed:
            status = "fixed"
        elif name in cal.at_bounds:
            status = "at bound"
        params[name] = {
            "value": _num(cal.params[name]),
            # a curvature-based standard error means nothing at a bound: none is reported
            # (the posterior of the group corrections does include parameters at a bound)
            "std_error": _num(cal.bse.get(name, np.nan))
            if status == "estimated" or (status == "at bound" and cal.correction is not None)
            else None,
            "unit": unit or _unit_guess(name),
            "estimated": bool(name in cal.correlation.columns or name in model.estimated),
            "status": status,
        }
        if name in model.estimated:
            lo, ini, hi, _ = model.estimated[name]
            params[name].update({
                "lower": lo, "initial": ini, "upper": hi,
                "bounds_from": model.bounds_source.get(name, "building file"),
            })  # fmt: skip
    corr = cal.correlation.to_numpy(float)
    off = corr[~np.eye(len(corr), dtype=bool)] if corr.size else np.array([])
    phys = [n for n in ESTIMATED_PARAMETERS if n in cal.correlation.columns]
    cphys = cal.correlation.loc[phys, phys].to_numpy(float)
    off_phys = cphys[~np.eye(len(cphys), dtype=bool)]
    if cal.heat_loss_coefficient_draws is not None:  # posterior of the group corrections
        hlc_draws = cal.heat_loss_coefficient_draws
    else:
        hlc_draws = heat_loss_coefficient_draws(
            analysis,
            np.random.default_rng(0).normal(
                cal.estimates_si["H_est"], max(cal.heat_loss_coefficient_std, 0), 2000
            ),
        )
    hlc = {
        "value": _num(cal.heat_loss_coefficient),
        "std": _num(cal.heat_loss_coefficient_std),
        "p05": _num(np.quantile(hlc_draws, lo_q)),
        "p95": _num(np.quantile(hlc_draws, 1 - lo_q)),
        # Monte Carlo standard error of the less precise interval end [W/K]
        "interval_mcse": _num(interval_end_error(hlc_draws, cfg.uncertainty.interval)),
        "calculated_part": _num(cal.heat_loss_coefficient - cal.estimates_si["H_est"]),
        "H_est": _num(cal.estimates_si["H_est"]),
        "audit_prior": _num(model.calculated_heat_loss_coefficient() + model.audit_h_est),
    }
    if cfg.reference.audit_heat_loss_coefficient_W_per_K is not None:
        hlc["audit"] = cfg.reference.audit_heat_loss_coefficient_W_per_K
    true = true_hlc if true_hlc is not None else cfg.reference.true_heat_loss_coefficient_W_per_K
    if true is not None:
        hlc["true"] = float(true)
        hlc["relative_error_pct"] = 100.0 * (cal.heat_loss_coefficient - true) / true
    monthly = analysis.demand.monthly_kwh()  # (S, D+1, 12)
    annual = analysis.demand.annual_kwh()
    has_draws = annual.shape[1] > 1  # uncertainty.draws: 0 -> no interval, null ends
    base_lo, base_hi = interval_ends(annual[0, 1:], cfg.uncertainty.interval)
    mdraws = monthly[0, 1:]
    demand = {
        "value": _num(annual[0, 0]),
        "p05": _num(base_lo),
        "p95": _num(base_hi),
        # Monte Carlo standard error of the less precise interval end [kWh]
        "interval_mcse": _num(interval_end_error(annual[0, 1:], cfg.uncertainty.interval))
        if has_draws else None,
        "monthly": [_num(v) for v in monthly[0, 0]],
        "monthly_p05": [_num(v) for v in np.quantile(mdraws, lo_q, axis=0)]
        if has_draws else None,
        "monthly_p95": [_num(v) for v in np.quantile(mdraws, 1 - lo_q, axis=0)]
        if has_draws else None,
        "indoor_profile_C": [_num(v) for v in analysis.indoor_profile],
        "weather": {
            k: analysis.weather_meta.get(k)
            for k in ("name", "latitude", "longitude", "source", "coerced_year")
        },
        "per_m2_kWh": _num(annual[0, 0] / float(analysis.building.heated_floor_area)),
    }
    ref = cfg.reference
    references = {}
    if ref.rating_kWh is not None:
        references[ref.rating_label] = ref.rating_kWh
    if ref.measured_fuel_kWh is not None:
        references["measured fuel use"] = ref.measured_fuel_kWh
        if ref.boiler_efficiency is not None:
            references["measured fuel use x boiler efficiency"] = (
                ref.measured_fuel_kWh * ref.boiler_efficiency
            )
    if ref.rating_monthly_kWh is not None:
        references[f"{ref.rating_label} monthly"] = ref.rating_monthly_kWh
    demand["references"] = references
    scen = scenario_table(analysis)
    econ = economics_table(analysis)
    scenarios = []
    for row, erow, s in zip(
        scen.to_dict("records"), econ.to_dict("records"), analysis.strategies, strict=True
    ):
        scenarios.append(
            {
                **row,
                "measures": list(s.measures),
                "u_values": {
                    m: cfg.measures[m].u_value
                    for m in s.measures
                    if cfg.measures[m].u_value is not None
                },
                "economics": {k: v for k, v in erow.items() if k != "code"},
            }
        )
    h = model.conductances()
    if model.interior != "split":  # the combined inside: its pairs repeat the four paths
        h = {k: v for k, v in h.items() if not k.startswith("G_") and k != "interior_split"}
    return _clean({
        "thermocal_workflow": "retrofit (the fifth-order RC method)",
        "building": analysis.building.name,
        "periods": {
            "training": [str(analysis.training[0]), str(analysis.training[1])],
            "test": [str(analysis.test[0]), str(analysis.test[1])] if analysis.test else None,
        },
        "air_change_adjustment": analysis.air_change,
        "calibration": {
            "method": analysis.calibration_method,
            "interior": model.interior,
            "params": params,
            "calculated_conductances_W_per_K": h,
            "max_abs_correlation": _num(np.nanmax(np.abs(off))) if off.size else None,
            "max_abs_correlation_physical": _num(np.nanmax(np.abs(off_phys)))
            if off_phys.size else None,
            "max_abs_pairwise_correlation_physical": _max_off_diagonal(cal.pairwise_correlation),
            "correlated_pairs": [
                {"a": a, "b": b, "r": r} for a, b, r in cal.correlated_pairs
            ],
            "loglike": cal.loglike,
            "aic": cal.aic,
            "bic": cal.bic,
            "converged": cal.converged,
            "flags": cal.flags,
            "full_fit_flags": cal.nuisance_flags,
            "parameters_at_bounds": cal.at_bounds,
            "parameters_fixed": sorted(model.fixed),
            "residual_diagnostics": residual_summary(cal.residuals),
            "fit_seconds": cal.fit_seconds,
            "correction": _correction_dict(cal.correction, model),
            "in_situ": {c: m.as_dict() for c, m in analysis.in_situ.items()} or None,
        },
        "heat_loss_coefficient_W_per_K": hlc,
        "validation": analysis.validation,
        "heat_validation": analysis.heat_validation,
        "validation_gate": analysis.gate,
        "recommendation": _recommended_code(analysis),
        "recommendation_rule": (_recommendation_rule(analysis) or {}).get("rule"),
        "annual_heating_demand_kWh": demand,
        "heat_balance_kWh": heat_balance_dict(analysis),
        "scenarios": scenarios,
        "measures_u_values": {
            k: m.u_value for k, m in cfg.measures.items() if m.u_value is not None
        },
        "measures": {k: m.model_dump() for k, m in cfg.measures.items()},
        "economics": {
            **cfg.economics.model_dump(),
            "measure_investment": {
                name: measure_investment(m, _areas(analysis))
                for name, m in cfg.measure_objects().items()
            },
        },
        "provenance": provenance(analysis),
        "uncertainty": {"draws": cfg.uncertainty.draws, "interval": cfg.uncertainty.interval,
                        "seed": cfg.uncertainty.seed, "ground": _ground_draws_dict(analysis)},
        "measurements_quality": _quality_dict(analysis.measurements_quality),
        "notes": analysis.notes,
        "timings_s": analysis.timings,
    })  # fmt: skip


def heat_balance_dict(analysis) -> dict | None:
    """The estimate's monthly heat balance per path in the demand year
    (:func:`thermocal.retrofit.balance.heat_balance`) for results.json [kWh]."""
    from thermocal.retrofit.balance import BALANCE_PATHS, heat_balance

    if analysis.year_inputs is None:
        return None
    env = analysis.envelopes[0] if analysis.envelopes else analysis.calibration.envelope
    if isinstance(env, list | tuple):
        env = env[0]
    draws = analysis.draws or analysis.calibration.estimates_si
    params = {k: float(np.atleast_1d(draws[k])[0]) for k in ESTIMATED_PARAMETERS}
    bal = heat_balance(analysis.model, params, env, analysis.year_inputs,
                       analysis.indoor_profile, gains=analysis.year_gains)  # fmt: skip
    columns = list(BALANCE_PATHS) + ["heating"]
    return {
        "note": "the estimate's heat flows out of the indoor air per path and month (sun and "
        "gains negative; they add up to the heating); the air change's temperature slope is "
        "not in it (thermocal.retrofit.balance)",
        "monthly": {c: [float(v) for v in bal[c]] for c in columns},
        "annual": {c: float(bal[c].sum()) for c in columns},
        "monthly_mean_Ti_C": [float(v) for v in bal["Ti"]],
        "monthly_mean_Tgr_C": [float(v) for v in bal["Tgr"]],
    }


def _ground_draws_dict(analysis) -> dict | None:
    """The ground's inputs drawn (thermocal.retrofit.ground_draws): distribution, 5/50/95 %.

    An input held at the building file's value in every draw is not listed (a slab's soil
    when the floor group's correction carries its uncertainty).
    """
    from thermocal.retrofit.ground_draws import DESCRIPTION

    draws = analysis.draws or {}
    out = {}
    for name, text in DESCRIPTION.items():
        if name in draws and len(draws[name]) > 1:
            v = np.asarray(draws[name][1:], float)
            if np.all(v == draws[name][0]):
                continue
            out[name] = {"distribution": text, "estimate": float(draws[name][0]),
                         "p05": float(np.quantile(v, 0.05)), "p50": float(np.median(v)),
                         "p95": float(np.quantile(v, 0.95))}  # fmt: skip
    return out or None


def _correction_dict(corr, model) -> dict | None:
    """The group corrections of the calibrated U-values (None: the published topology).

    Each group lists the components it scales in this building (the floor group: the
    building's ``cellar_ceiling`` or ``ground_floor``, with what it is).
    """
    if corr is None:
        return None
    from thermocal.retrofit.correction import group_components

    groups = group_components(model.envelope, model.ground.kind, model.in_situ)
    return {
        "method": "maximum a posteriori, prior ln k ~ N(0, s^2) per envelope group; a "
        "component measured in situ: its own factor, ln k ~ N(ln(U_measured / U_described), "
        "s_measured^2)",
        "prior_mean_log": corr.prior_mean,
        "measured_in_situ": list(corr.measured),
        "factors": corr.factors,
        "groups": {g: groups[g] for g in corr.factors},
        "prior_std_log": corr.prior_std,
        "posterior_std_log": corr.posterior_std,
        "separated_by_data": corr.separated,
        "strong_correlations": corr.correlation,
        "correlation_with_H_est": corr.h_est_correlation,
        "summary": corr.summary(),
    }  # fmt: skip


def _sha256(path: Path) -> str | None:
    import hashlib

    try:
        h = hashlib.sha256()
        with open(path, "rb") as fh:
            for chunk in iter(lambda: fh.read(1 << 20), b""):
                h.update(chunk)
        return h.hexdigest()
    except OSError:
        return None


def _portable(path: Path, base: Path) -> str:
    """``path`` relative to ``base`` when it lies below it, else its file name only."""
    try:
        return Path(path).resolve().relative_to(Path(base).resolve()).as_posix()
    except ValueError:
        return Path(path).name


def provenance(analysis: RetrofitAnalysis) -> dict:
    """Version, command line, seeds, input files (relative names and SHA-256) and time."""
    import datetime as _dt
    import sys

    from thermocal import __version__

    cfg = analysis.config
    files = {}
    if not isinstance(cfg.building, dict):
        files["building"] = Path(cfg.building)
    files["measurements"] = Path(cfg.measurements.file)
    weather = str(cfg.weather.file)
    files["weather"] = resolve_weather_path(cfg.weather.file)
    inputs = {}
    for key, path in files.items():
        pvlib_file = key == "weather" and "pvlib:" in weather
        name = (
            "pvlib:" + weather.split("pvlib:", 1)[1]
            if pvlib_file
            else _portable(path, cfg.base_dir)
        )
        inputs[key] = {"file": name, "sha256": _sha256(path)}
    argv = [Path(sys.argv[0]).name, *sys.argv[1:]] if sys.argv else []
    return {
        "thermocal_version": __version__,
        "command_line": " ".join(argv),
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "seeds": {"model": cfg.model.seed, "uncertainty": cfg.uncertainty.seed},
        "inputs": inputs,
    }


def _quality_dict(report) -> dict | None:
    """The measurement QualityReport as JSON content, with its plain-text summary."""
    if report is None:
        return None
    return {"summary": report.summary(), **report.to_dict()}


def _interval_labels(interval: float) -> tuple[str, str]:
    """Names of the lower and upper interval quantiles, e.g. ("p05", "p95") for 90 %."""
    lo = round(50.0 * (1.0 - interval), 6)

    def name(q: float) -> str:
        return f"p{q:02.0f}" if q == int(q) else f"p{q:g}"

    return name(lo), name(100.0 - lo)


def _max_off_diagonal(corr: pd.DataFrame | None) -> float | None:
    """Largest finite |off-diagonal| entry of a correlation matrix, None when there is none."""
    if corr is None or corr.shape[0] < 2:
        return None
    c = np.abs(corr.to_numpy(float))[~np.eye(corr.shape[0], dtype=bool)]
    return _num(np.nanmax(c)) if np.isfinite(c).any() else None


def _unit_guess(name: str) -> str:
    from thermocal.retrofit.model import CALCULATED_CONDUCTANCES, CALCULATED_FACTORS

    if name in CALCULATED_CONDUCTANCES:
        return "W/K"
    if name in CALCULATED_FACTORS:
        return "-"
    if name.startswith("sigma_"):
        return "K/sqrt(h)"
    if name.endswith("0") or name == "e_std":
        return "C"
    return ""


def write_outputs(
    analysis: RetrofitAnalysis,
    out_dir: Path | str,
    *,
    true_hlc: float | None = None,
    title: str | None = None,
    reference_demands: dict[str, float] | None = None,
    reference_monthly: list[float] | None = None,
    reference_label: str = "reference",
    measurement_advice: dict | None = None,
) -> dict:
    """Write results.json, the CSV tables, the figures and report.html into ``out_dir``.

    Parameters
    ----------
    measurement_advice : dict, optional
        :func:`thermocal.retrofit.advice.advise_measurements` (results.json
        ``measurement_advice`` and a table in the report).
    reference_demands : dict code -> kWh, optional
        Annual demands at a constant 20 C of some or all strategies from another model (the
        demo: the multi-zone generator); compared with the model's at 20 C.

    Returns
    -------
    dict
        The results.json content.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    results = results_dict(analysis, true_hlc=true_hlc)
    if reference_demands:
        from thermocal.retrofit.workflow import compare_with_reference_demands

        check = compare_with_reference_demands(analysis, reference_demands)
        check["reference"] = reference_label
        if reference_monthly is not None:
            check["monthly_reference_kWh"] = list(reference_monthly)
        results["reference_check"] = _clean(check)
    if measurement_advice is not None:
        results["measurement_advice"] = _clean(measurement_advice)
    (out / "results.json").write_text(json.dumps(results, indent=2))
    tables = write_tables(analysis, out, results)
    from thermocal.report.figures import close, figure_to_png

    fig_dir = out / "figures"
    fig_dir.mkdir(exist_ok=True)
    figures = {}
    from thermocal.retrofit.figures import make_figures

    for name, fig in make_figures(analysis, results).items():
        figures[name] = figure_to_png(fig)  # rendered once: file and report share the bytes
        close(fig)
        (fig_dir / f"{name}.png").write_bytes(figures[name])
    from thermocal.retrofit.report import write_report

    write_report(analysis, results, tables, figures, out / "report.html", title=title)
    return results


def write_tables(analysis: RetrofitAnalysis, out: Path, results: dict) -> dict[str, pd.DataFrame]:
    """CSV tables (temperatures in C, energies in kWh)."""
    cal = analysis.calibration
    params = pd.DataFrame([
        {"parameter": k, "value": v["value"], "std_error": v["std_error"], "unit": v["unit"],
         "lower": v.get("lower"), "upper": v.get("upper"), "estimated": v["estimated"]}
        for k, v in results["calibration"]["params"].items()
    ])  # fmt: skip
    ts = pd.DataFrame({
        "Te_C": analysis.data["Te"], "Tgr_C": analysis.data["Tgr"],
        "phi_h_W": analysis.data["phi_h_measured"], "phi_int_W": analysis.data["phi_int"],
        "phi_sol_W": analysis.data["phi_sol"],
        "Ti_measured_C": analysis.data["Ti_measured"], "Ti_simulated_C": analysis.simulated_ti,
    })  # fmt: skip
    ts["period"] = np.where(ts.index < analysis.training[1], "train", "test")
    ts.index.name = "time"
    val = pd.DataFrame(analysis.validation).T.reset_index(names="period")
    monthly = analysis.demand.monthly_kwh()[:, 0, :]
    monthly_df = pd.DataFrame(monthly, columns=list(MONTHS))
    monthly_df.insert(0, "code", [s.code for s in analysis.strategies])
    hourly = pd.DataFrame(
        {
            f"heating_W_{s.code}": analysis.demand.hourly[i]
            for i, s in enumerate(analysis.strategies)
        },
        index=analysis.demand.index,
    )
    hourly.index.name = "time"
    scen = scenario_table(analysis)
    econ = economics_table(analysis)
    econ.to_csv(out / "economics.csv", index=False)
    params.insert(3, "status", [v["status"] for v in results["calibration"]["params"].values()])
    corr = cal.correlation
    params.to_csv(out / "calibration_parameters.csv", index=False)
    corr.to_csv(out / "calibration_correlation.csv")
    ts.to_csv(out / "validation_timeseries.csv")
    val.to_csv(out / "validation_metrics.csv", index=False)
    hourly.to_csv(out / "demand_hourly.csv")
    monthly_df.to_csv(out / "demand_monthly.csv", index=False)
    scen.to_csv(out / "scenarios.csv", index=False)
    return {
        "parameters": params, "validation": val, "monthly": monthly_df, "scenarios": scen,
        "economics": econ,
    }  # fmt: skip


def residual_summary(res: pd.DataFrame | None) -> dict | None:
    """Numbers behind the residual figure: mean, std, lag-1 and lag-24 autocorrelation, the
    share of lags 1..48 outside the white-noise band and of the periodogram outside its band."""
    if res is None:
        return None
    from thermocal.statespace.diagnostics import (
        autocorrelation,
        cumulated_periodogram,
        fraction_outside_band,
    )

    col = [c for c in res.columns if c.endswith("_residual")][0]
    e = res[col].to_numpy(float)
    acf = autocorrelation(e, nlags=min(48, len(e) - 2))
    out = np.abs(acf["acf"].iloc[1:]) > acf["bound"].iloc[1:]
    return {
        "mean_K": _num(np.nanmean(e)),
        "std_K": _num(np.nanstd(e)),
        "acf_lag1": _num(acf["acf"].iloc[1]),
        "acf_lag24": _num(acf["acf"].iloc[24]) if len(acf) > 24 else None,
        "share_of_lags_outside_band": _num(out.mean()),
        "periodogram_share_outside_band": _num(fraction_outside_band(cumulated_periodogram(e))),
    }
