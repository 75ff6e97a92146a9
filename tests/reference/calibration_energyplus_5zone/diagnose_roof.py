"""Why does the zone-group calibration find the roof of 5ZoneAirCooled ~6 % too conductive?

Run from the repository root (EnergyPlus 25.2 and ../shared/data needed, about 3 minutes)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_5zone/diagnose_roof.py

Writes ``diagnose_roof.json`` and ``diagnose_roof.md`` beside this script (issues 26 and 28).

Five measurements, from the physics to the statistics:

1. **Forward paths.** EnergyPlus 25.2 (1-minute steps) and thermocal (5-minute steps) run the
   same true-envelope file (:func:`make_reference.perturbed`, loads included, January). EnergyPlus
   reports the heat balance of every plenum surface (hourly ``Surface Inside/Outside Face ...``
   variables); thermocal's are computed from its node temperatures, step by step
   (:func:`thermocal_paths`: a face's heat into its construction is the storage of its node plus
   the conduction to the construction's next node; convection as the kernel applies it, the
   matrix coefficient at the new state plus the lagged "Simple" excess; long-wave is the rest).
   Means over January 2-31 and hourly statistics of each path, in W.
2. **Coefficients on EnergyPlus' own states.** The roof's outside SimpleCombined coefficient at
   EnergyPlus' surface wind speed and its inside "Simple" coefficient at EnergyPlus' surface and
   air temperatures, against the coefficients EnergyPlus reports.
3. **The roof conductance the calibration's answer means**: ``A / (R + films)`` at the truth and
   at the calibrated 4.886 m2 K/W, times EnergyPlus' mean air-to-air difference: the path error
   (W) the calibration's roof would compensate if the cause were physics.
4. **The metric itself** (the campaign of ``calibrate_twin.py``: nominal file without loads,
   committed sensor log, 15-minute steps, the zone-group unoccupied variance): scanned along the
   roof resistance with every other parameter at its truth, and minimised directly over all
   seven parameters (Nelder-Mead from the truth, no meta-model).
5. **The meta-model.** The campaign's 48 Sobol' samples (``calibrate_twin.py``'s design), the
   series meta-model of ``thermocal.calibration.surrogate.SeriesSurrogate`` (hourly group heat
   affine in ``log(p / p_nominal)``) and its bounded least-squares minimum, against the same
   ridge regressions on conductance-like features (``p_nominal / p - 1`` for a resistance,
   ``p / p_nominal - 1`` for an air change rate: the heat through an element is linear in
   those, not in the logarithm), and the one-parameter picture: the zero of a straight line in
   ``log p`` fitted to ``1 / (p + films) - 1 / (p_true + films)`` over the prior's range.
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "tests" / "identification"))
sys.path.insert(0, str(HERE))
sys.modules.pop("make_reference", None)

from energyplus_twin import IDF_NAME, WEATHER_NAME, twin_idf  # noqa: E402
from make_reference import SHARED, perturbed  # noqa: E402

DAYS = 31
PLENUM = "PLENUM-1"
ROOF_SURFACE = "TOP-1"
#: calibrate_twin.py's zone-group answer for the roof (tests/calibration xfail, 2026-11-25)
CALIBRATED_ROOF = 4.886
#: half width of the second, local campaign around the first answer [-]
LOCAL_RANGE = 0.15
PLENUM_MINIMUM = "minimum of the plenum group's variance, roof R / truth"
#: hourly EnergyPlus outputs of every surface (and the site)
SURFACE_VARIABLES = (
    "Surface Inside Face Temperature",
    "Surface Outside Face Temperature",
    "Surface Inside Face Conduction Heat Transfer Rate",
    "Surface Outside Face Conduction Heat Transfer Rate",
    "Surface Inside Face Convection Heat Gain Rate",
    "Surface Inside Face Net Surface Thermal Radiation Heat Gain Rate",
    "Surface Inside Face Solar Radiation Heat Gain Rate",
    "Surface Inside Face Internal Gains Radiation Heat Gain Rate",
    "Surface Outside Face Convection Heat Gain Rate",
    "Surface Outside Face Net Thermal Radiation Heat Gain Rate",
    "Surface Outside Face Solar Radiation Heat Gain Rate",
    "Surface Outside Face Convection Heat Transfer Coefficient",
    "Surface Inside Face Convection Heat Transfer Coefficient",
    "Surface Outside Face Outdoor Air Wind Speed",
    "Zone Mean Air Temperature",
    "Site Outdoor Air Drybulb Temperature",
    "Site Wind Speed",
)


def true_envelope_text() -> str:
    """The hidden-envelope IDF text with its loads (what EnergyPlus ran for the sensor log)."""
    return perturbed((SHARED / IDF_NAME).read_text())


# ---- 1. forward paths ---------------------------------------------------------------------------
def energyplus_surfaces(text: str, folder: Path) -> pd.DataFrame:
    """EnergyPlus on ``text`` at 1-minute steps: hourly surface and zone outputs (by hour start)."""
    from thermocal.multizone.energyplus import energyplus_weather_folder, read_eso, run_energyplus

    idf = twin_idf(text, DAYS, timesteps_per_hour=60)
    idf += "".join(f"\nOutput:Variable,\n  *,\n  {v},\n  Hourly;\n" for v in SURFACE_VARIABLES)
    path = folder / "true_envelope_60.idf"
    path.write_text(idf)
    eso = run_energyplus(path, energyplus_weather_folder() / WEATHER_NAME, folder / "energyplus")
    return read_eso(eso, year=2023, frequency="hourly")


def thermocal_forward(text: str, folder: Path):
    """thermocal's free-floating run of ``text`` at 5-minute steps, every node kept:
    ``(simulation, states (n_steps + 1, n_nodes))`` (row 0 after the warm-up)."""
    from thermocal.io.weather import read_weather
    from thermocal.multizone.energyplus import energyplus_weather_folder
    from thermocal.multizone.idf import read_idf
    from thermocal.multizone.simulation import Simulation

    path = folder / "true_envelope_12.idf"
    path.write_text(twin_idf(text, DAYS, timesteps_per_hour=12))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(path)
        weather, metadata = read_weather(energyplus_weather_folder() / WEATHER_NAME)
        year = int(weather.index[0].year)
        sim = Simulation(
            building,
            weather,
            metadata,
            step="5min",
            start=f"{year}-01-01",
            end=f"{year}-02-01",
            store_surfaces=False,
        )
        states = np.empty((len(sim.times) + 1, sim.network.n_nodes))
        states[0] = sim._x
        for k in range(len(sim.times)):
            sim.step()
            states[k + 1] = sim._x
    return sim, states


def _construction_nodes(net, face: int) -> tuple[int, set[int]]:
    """The node on the other side of a face's construction and the construction's nodes
    (a construction's nodes are contiguous, outside face first)."""
    name, node = net.face_names[face], int(net.face_node[face])
    if name in net.ext_names:
        other = int(net.ext_node[net.ext_names.index(name)])
    else:  # a partition: the nearest face node of another zone
        others = [
            int(net.face_node[j])
            for j in range(len(net.face_names))
            if net.face_zone[j] != net.face_zone[face] and not net.face_is_window[j]
        ]
        other = min(others, key=lambda j: abs(j - node))
    lo, hi = sorted((node, other))
    return other, set(range(lo, hi + 1))


def thermocal_paths(sim, states, zone: str = PLENUM) -> pd.DataFrame:
    """Hourly heat paths [W] and temperatures [C] of every face of ``zone`` (thermocal).

    Columns ``(face, quantity)``: ``T_inside``, ``T_other`` (the construction's other face),
    ``into_construction`` (heat entering the construction at the inside face: convection +
    long-wave + short-wave there, EnergyPlus' ``- Inside Face Conduction``),
    ``convection_gain`` (air -> face), ``longwave_gain``, ``shortwave_gain``,
    ``h_inside``; for an exterior face also ``outside_solar``, ``outside_combined`` (the
    SimpleCombined convective + radiative exchange with the outdoor air, EnergyPlus'
    ``Outside Face Convection Heat Gain Rate``), ``outside_into_construction`` and ``T_outside``.
    """
    from thermocal.multizone._kernel import simple_interior

    net = sim.network
    dt = sim.dt
    conductance = net.conductance.tocsr()
    inputs = net.inputs.tocsr()
    forcing = sim._fine.inputs
    x0, x1 = states[:-1], states[1:]
    z = net.zone_names.index(zone)
    air = int(net.air_node[z])

    def entering(node: int, construction: set[int]) -> np.ndarray:
        q = net.capacity[node] / dt * (x1[:, node] - x0[:, node])
        row = conductance.getrow(node)
        for j, v in zip(row.indices, row.data, strict=True):
            if j != node and j in construction:
                q = q - v * (x1[:, node] - x1[:, j])
        return q

    out = {}
    for f in np.flatnonzero(net.face_zone == z):
        name, node = net.face_names[f], int(net.face_node[f])
        other, construction = _construction_nodes(net, f)
        area, h0, cos = net.face_area[f], net.face_h0[f], net.face_cos_up[f]
        h_step = np.array([simple_interior(d, cos) for d in x0[:, node] - x0[:, air]])
        convection = h0 * area * (x1[:, air] - x1[:, node]) + (h_step - h0) * area * (
            x0[:, air] - x0[:, node]
        )
        shortwave = np.asarray(inputs.getrow(node) @ forcing.T).ravel()
        total = entering(node, construction)
        out[(name, "T_inside")] = x1[:, node]
        out[(name, "T_other")] = x1[:, other]
        out[(name, "into_construction")] = total
        out[(name, "convection_gain")] = convection
        out[(name, "shortwave_gain")] = shortwave
        out[(name, "longwave_gain")] = total - convection - shortwave
        out[(name, "h_inside")] = h_step
        if name in net.ext_names:
            e = net.ext_names.index(name)
            outer = int(net.ext_node[e])
            row = inputs.getrow(outer)
            solar = sum(
                v * forcing[:, j]
                for j, v in zip(row.indices, row.data, strict=True)
                if net.input_names[j].startswith("poa_global")
            )
            into = entering(outer, construction)
            out[(name, "outside_solar")] = solar
            out[(name, "outside_combined")] = into - solar
            out[(name, "outside_into_construction")] = into
            out[(name, "T_outside")] = x1[:, outer]
    out[(zone, "T_air")] = x1[:, air]
    frame = pd.DataFrame(out, index=sim.times.tz_localize(None))
    return frame.groupby(frame.index.floor("1h")).mean()


def _ep(ep: pd.DataFrame, key: str, variable: str) -> pd.Series:
    return ep[f"{key}:{variable}"]


def path_table(ep: pd.DataFrame, tc: pd.DataFrame, start="2023-01-02") -> dict:
    """Path by path: EnergyPlus and thermocal means [W] (or C, W/(m2 K)), their difference,
    the RMS of the hourly difference and the hourly regression slope thermocal / EnergyPlus."""
    ep = ep[ep.index >= start]
    tc = tc.reindex(ep.index)
    plenum_faces = sorted({f for f, _ in tc.columns if f != PLENUM})
    ceilings = [f for f in plenum_faces if f.startswith("C")]
    walls = [f for f in plenum_faces if f.startswith("WALL")]
    into = "Surface Inside Face Conduction Heat Transfer Rate [W]"
    rows: dict[str, tuple[pd.Series, pd.Series]] = {}

    def add(label, e, t):
        rows[label] = (e, t)

    r = ROOF_SURFACE
    add(
        "roof: outside solar absorbed [W]",
        _ep(ep, r, "Surface Outside Face Solar Radiation Heat Gain Rate [W]"),
        tc[(r, "outside_solar")],
    )
    add(
        "roof: outside convection + long-wave (SimpleCombined) [W]",
        _ep(ep, r, "Surface Outside Face Convection Heat Gain Rate [W]")
        + _ep(ep, r, "Surface Outside Face Net Thermal Radiation Heat Gain Rate [W]"),
        tc[(r, "outside_combined")],
    )
    add(
        "roof: conduction out of the outside face [W]",
        _ep(ep, r, "Surface Outside Face Conduction Heat Transfer Rate [W]"),
        -tc[(r, "outside_into_construction")],
    )
    add(
        "roof: conduction into the inside face from the plenum [W]",
        -_ep(ep, r, into),
        tc[(r, "into_construction")],
    )
    add(
        "roof: inside convection gain [W]",
        _ep(ep, r, "Surface Inside Face Convection Heat Gain Rate [W]"),
        tc[(r, "convection_gain")],
    )
    add(
        "roof: inside long-wave gain [W]",
        _ep(ep, r, "Surface Inside Face Net Surface Thermal Radiation Heat Gain Rate [W]"),
        tc[(r, "longwave_gain")],
    )
    add(
        "roof: outside face temperature [C]",
        _ep(ep, r, "Surface Outside Face Temperature [C]"),
        tc[(r, "T_outside")],
    )
    add(
        "roof: inside face temperature [C]",
        _ep(ep, r, "Surface Inside Face Temperature [C]"),
        tc[(r, "T_inside")],
    )
    add(
        "roof: inside convection coefficient [W/(m2 K)]",
        _ep(ep, r, "Surface Inside Face Convection Heat Transfer Coefficient [W/m2-K]"),
        tc[(r, "h_inside")],
    )
    add(
        "plenum: air temperature [C]",
        _ep(ep, PLENUM, "Zone Mean Air Temperature [C]"),
        tc[(PLENUM, "T_air")],
    )
    for label, faces in (
        ("plenum floors (ceilings of the offices, 5)", ceilings),
        ("plenum walls (4)", walls),
    ):
        add(
            f"{label}: conduction into the plenum-side face [W]",
            sum(-_ep(ep, f.upper(), into) for f in faces),
            sum(tc[(f, "into_construction")] for f in faces),
        )
        add(
            f"{label}: convection gain [W]",
            sum(
                _ep(ep, f.upper(), "Surface Inside Face Convection Heat Gain Rate [W]")
                for f in faces
            ),
            sum(tc[(f, "convection_gain")] for f in faces),
        )
        add(
            f"{label}: long-wave gain [W]",
            sum(
                _ep(
                    ep,
                    f.upper(),
                    "Surface Inside Face Net Surface Thermal Radiation Heat Gain Rate [W]",
                )
                for f in faces
            ),
            sum(tc[(f, "longwave_gain")] for f in faces),
        )
    add(
        "plenum: convection from all faces into the air [W]",
        -sum(
            _ep(ep, f.upper(), "Surface Inside Face Convection Heat Gain Rate [W]")
            for f in plenum_faces
        ),
        -sum(tc[(f, "convection_gain")] for f in plenum_faces),
    )
    table = {}
    for label, (e, t) in rows.items():
        d = t - e
        slope = (
            float(np.polyfit(e - e.mean(), t - t.mean(), 1)[0]) if e.std() > 1e-9 else float("nan")
        )
        table[label] = {
            "energyplus": round(float(e.mean()), 3),
            "thermocal": round(float(t.mean()), 3),
            "difference": round(float(d.mean()), 3),
            "hourly_rms_difference": round(float(np.sqrt((d**2).mean())), 3),
            "hourly_slope_thermocal_on_energyplus": round(slope, 4),
        }
    return table


# ---- 2. coefficients on EnergyPlus' states ------------------------------------------------------
def coefficients_on_energyplus_states(ep: pd.DataFrame, sim, start="2023-01-02") -> dict:
    """The roof's outside SimpleCombined and inside Simple coefficients as thermocal computes
    them from EnergyPlus' hourly wind speed and temperatures, against EnergyPlus' values."""
    from thermocal.multizone._kernel import simple_interior
    from thermocal.multizone.network import simple_combined_exterior_coefficient

    ep = ep[ep.index >= start]
    net = sim.network
    e = net.ext_names.index(ROOF_SURFACE)
    r = ROOF_SURFACE
    wind = _ep(ep, r, "Surface Outside Face Outdoor Air Wind Speed [m/s]")
    station = ep["Environment:Site Wind Speed [m/s]"]
    h_out = simple_combined_exterior_coefficient(wind.to_numpy(), net.ext_roughness[e])
    f = net.face_names.index(ROOF_SURFACE)
    t_in = _ep(ep, r, "Surface Inside Face Temperature [C]").to_numpy()
    t_air = _ep(ep, PLENUM, "Zone Mean Air Temperature [C]").to_numpy()
    h_in = np.array([simple_interior(a, net.face_cos_up[f]) for a in t_in - t_air])
    ep_out = _ep(ep, r, "Surface Outside Face Convection Heat Transfer Coefficient [W/m2-K]")
    ep_in = _ep(ep, r, "Surface Inside Face Convection Heat Transfer Coefficient [W/m2-K]")
    return {
        "roof wind speed factor (thermocal, EnergyPlus mean ratio)": [
            round(float(net.ext_wind_factor[e]), 4),
            round(float(wind.mean() / station.mean()), 4),
        ],
        "roof outside SimpleCombined coefficient [W/(m2 K)] (EnergyPlus, thermocal on its wind)": [
            round(float(ep_out.mean()), 4),
            round(float(np.mean(h_out)), 4),
        ],
        "roof inside Simple coefficient [W/(m2 K)] (EnergyPlus, thermocal on its temperatures; "
        "hourly means of 1-minute values)": [
            round(float(ep_in.mean()), 4),
            round(float(np.mean(h_in)), 4),
        ],
    }


# ---- 3. what the calibrated roof means -----------------------------------------------------------
def roof_equivalent(ep: pd.DataFrame, truth_r: float, start="2023-01-02") -> dict:
    """Roof UA [W/K] at the truth and at :data:`CALIBRATED_ROOF` (EnergyPlus' mean films) and the
    heat it moves at EnergyPlus' mean plenum-air to outdoor-air difference [W]."""
    ep = ep[ep.index >= start]
    r = ROOF_SURFACE
    area = 463.6
    t_air = _ep(ep, PLENUM, "Zone Mean Air Temperature [C]").mean()
    t_out = ep["Environment:Site Outdoor Air Drybulb Temperature [C]"].mean()
    h_in = _ep(ep, r, "Surface Inside Face Convection Heat Transfer Coefficient [W/m2-K]").mean()
    h_out = _ep(ep, r, "Surface Outside Face Convection Heat Transfer Coefficient [W/m2-K]").mean()
    # inside film: convection plus long-wave (~0.9 x 4 sigma T^3 at 15 C, about 4.9 W/(m2 K))
    films = 1.0 / (h_in + 4.9) + 1.0 / h_out
    ua = {
        name: area / (value + films)
        for name, value in (("truth", truth_r), ("calibrated", CALIBRATED_ROOF))
    }
    conduction = -_ep(ep, r, "Surface Inside Face Conduction Heat Transfer Rate [W]").mean()
    return {
        "roof area [m2]": area,
        "films (inside conv + long-wave, outside combined) [m2 K/W]": round(float(films), 4),
        "UA at the truth, at the calibrated R [W/K]": [
            round(float(ua["truth"]), 2),
            round(float(ua["calibrated"]), 2),
        ],
        "mean plenum air - outdoor air [K]": round(float(t_air - t_out), 3),
        "EnergyPlus mean roof conduction [W]": round(float(conduction), 1),
        "extra roof loss the calibrated R means [W] (UA ratio x EnergyPlus' conduction)": round(
            float(conduction * (ua["calibrated"] / ua["truth"] - 1.0)), 1
        ),
    }


# ---- 4. the metric ------------------------------------------------------------------------------
def campaign_problem(folder: Path):
    """calibrate_twin.py's campaign (zone-group metric, 48 samples): ``(campaign, inputs,
    problem, evaluator)`` with the quiet hours chosen as ``calibrate`` chooses them."""
    import calibrate_twin as ct

    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.spatial import campaign_evaluator
    from thermocal.calibration.workflow import build_problem, choose_quiet_hours, load_inputs

    folder.mkdir(parents=True, exist_ok=True)
    path = ct.prepare(folder, 48)
    path.write_text(ct.campaign_text(48, extra="metric: groups\n"))
    campaign = load_campaign(path)
    inputs = load_inputs(campaign)
    problem, _ = build_problem(campaign, inputs)
    problem.series_outputs = True
    evaluator = campaign_evaluator(problem, inputs.building)
    nominal = problem.run({})
    problem.schedule, _ = choose_quiet_hours(campaign, nominal.heat.sum(axis=1), log=lambda s: 0)
    return campaign, inputs, problem, evaluator


def group_metrics(evaluator, parameters: dict) -> tuple[float, dict]:
    """The groups metric [W^2] and each group's variance for one parameter set."""
    from thermocal.calibration.spatial import group_segments

    out = evaluator.outputs(evaluator.problem.run(parameters).heat)
    columns, segments = group_segments(list(out))
    labels = {i: label for i, label in enumerate(evaluator.labels)}
    per = {
        labels.get(int(columns[a].split("/")[1]), columns[a].split("/")[1]): float(
            np.var([out[c] for c in columns[a:b]])
        )
        for a, b in segments
    }
    return float(sum(per.values())), per


def metric_along_roof(evaluator, truth: dict, names) -> dict:
    """The groups metric with the roof resistance scanned, every other parameter at its truth;
    the minimum of a parabola through the three lowest points."""
    import calibrate_twin as ct

    base = {n: truth[n] for n in names}
    ratios = (0.88, 0.92, 0.94, 0.96, 0.98, 1.0, 1.02, 1.04, 1.08)
    scan = {}
    for q in ratios:
        total, per = group_metrics(evaluator, {**base, ct.ROOF: truth[ct.ROOF] * q})
        scan[q] = {"metric": total, "groups": per}
    values = np.array([scan[q]["metric"] for q in ratios])
    i = int(np.clip(np.argmin(values), 1, len(ratios) - 2))
    a, b, _ = np.polyfit(np.array(ratios[i - 1 : i + 2]), values[i - 1 : i + 2], 2)
    plenum = [k for k in scan[1.0]["groups"] if "top floor" in k]
    pv = np.array([scan[q]["groups"][plenum[0]] for q in ratios]) if plenum else values
    j = int(np.clip(np.argmin(pv), 1, len(ratios) - 2))
    pa, pb, _ = np.polyfit(np.array(ratios[j - 1 : j + 2]), pv[j - 1 : j + 2], 2)
    return {
        "scan (roof R / truth -> metric W^2, per group)": {
            str(q): {
                "metric": round(v["metric"], 1),
                **{k: round(x, 1) for k, x in v["groups"].items()},
            }
            for q, v in scan.items()
        },
        "minimum of the groups metric, roof R / truth": round(float(-b / (2 * a)), 4),
        PLENUM_MINIMUM: round(float(-pb / (2 * pa)), 4),
    }


def direct_minimum(evaluator, truth: dict, names, calibrated: dict | None) -> dict:
    """Nelder-Mead on the groups metric itself (no meta-model), from the truth, in log-ratios."""
    from scipy.optimize import minimize

    def f(z):
        return group_metrics(
            evaluator, {n: truth[n] * float(np.exp(v)) for n, v in zip(names, z, strict=True)}
        )[0]

    found = minimize(
        f,
        np.zeros(len(names)),
        method="Nelder-Mead",
        options={"xatol": 1e-3, "fatol": 1.0, "maxfev": 800},
    )
    out = {
        "metric at the truth [W^2]": round(f(np.zeros(len(names))), 1),
        "direct minimum [W^2]": round(float(found.fun), 1),
        "evaluations": int(found.nfev),
        "direct minimum / truth per parameter": {
            n: round(float(np.exp(v)), 4) for n, v in zip(names, found.x, strict=True)
        },
    }
    if calibrated:
        total, per = group_metrics(evaluator, calibrated)
        roof_true = dict(calibrated)
        import calibrate_twin as ct

        roof_true[ct.ROOF] = truth[ct.ROOF]
        total_rt, per_rt = group_metrics(evaluator, roof_true)
        out["metric at calibrate_twin's committed answer (results.json) [W^2]"] = round(total, 1)
        out["same, roof at its truth [W^2]"] = round(total_rt, 1)
        out["plenum group at the answer, with the roof at its truth [W^2]"] = [
            round(v, 1) for k in per if "top floor" in k for v in (per[k], per_rt[k])
        ]
    return out


# ---- 5. the meta-model --------------------------------------------------------------------------
def _features(X: np.ndarray, names, nominal: dict, kind: str) -> np.ndarray:
    ref = np.array([nominal[n] for n in names])
    if kind == "log":
        return np.log(X / ref)
    # conductance-like: a resistance's heat goes as 1 / R, an air change rate's as the rate
    resistance = np.array([n.endswith("/resistance") for n in names])
    return np.where(resistance[None, :], ref / X - 1.0, X / ref - 1.0)


def _from_features(F: np.ndarray, names, nominal: dict, kind: str) -> np.ndarray:
    ref = np.array([nominal[n] for n in names])
    if kind == "log":
        return ref * np.exp(F)
    resistance = np.array([n.endswith("/resistance") for n in names])
    return np.where(resistance, ref / (F + 1.0), ref * (F + 1.0))


def series_minimum(X, series, segments, names, nominal, lower, upper, kind: str) -> np.ndarray:
    """The bounded least-squares minimum of the groups metric predicted by hourly ridge
    regressions on ``kind`` features ("log": ``SeriesSurrogate``'s; "conductance")."""
    from scipy.optimize import lsq_linear
    from sklearn.linear_model import RidgeCV

    F = _features(X, names, nominal, kind)
    model = RidgeCV(alphas=np.logspace(-4, 3, 30)).fit(F, series)
    coef, intercept = np.atleast_2d(model.coef_), np.asarray(model.intercept_).ravel()
    weights = np.empty(intercept.size)
    a_rows, r0 = coef.copy(), intercept.copy()
    for a, b in segments:
        weights[a:b] = 1.0 / np.sqrt(b - a)
        a_rows[a:b] -= a_rows[a:b].mean(axis=0, keepdims=True)
        r0[a:b] -= r0[a:b].mean()
    bounds = np.sort(
        np.stack(
            [
                _features(lower[None], names, nominal, kind)[0],
                _features(upper[None], names, nominal, kind)[0],
            ]
        ),
        axis=0,
    )
    fit = lsq_linear(
        a_rows * weights[:, None], -r0 * weights, bounds=(bounds[0], bounds[1]), method="bvls"
    )
    return _from_features(fit.x, names, nominal, kind)


def metamodel_study(campaign, inputs, evaluator, truth: dict) -> dict:
    """The campaign's samples, the log-affine and the conductance-affine series models' minima."""
    from thermocal.calibration.sampling import sample
    from thermocal.calibration.spatial import group_segments
    from thermocal.calibration.surrogate import SeriesSurrogate
    from thermocal.calibration.workflow import campaign_space

    space = campaign_space(campaign, inputs.building)
    names = list(space.names)
    samples = sample(
        space, campaign.sampling.samples, campaign.sampling.method, seed=campaign.sampling.seed
    )
    X = samples.values[names].to_numpy(dtype=float)
    rows, y = [], []
    for x in X:
        out = evaluator.evaluate(dict(zip(names, x, strict=True)))
        columns, segments = group_segments(list(out))
        rows.append([out[c] for c in columns])
        y.append(sum(np.var(np.array(rows[-1])[a:b]) for a, b in segments))
    series = np.array(rows)
    nominal = space.nominal_dict()
    lower, upper = np.asarray(space.lower, float), np.asarray(space.upper, float)
    # the package's own model and its bounded minimum (as the calibration's optimum)
    model = SeriesSurrogate(series=series, nominal=nominal, segments=segments, seed=1)
    model.fit(pd.DataFrame(X, columns=names), np.array(y))
    package = model.box_optimum("min", lower, upper)[0]
    log_min = series_minimum(X, series, segments, names, nominal, lower, upper, "log")
    cond_min = series_minimum(X, series, segments, names, nominal, lower, upper, "conductance")
    # a second campaign of as many samples in +-15 % around the first answer, the same model
    from thermocal.calibration.sampling import unit_sample

    low = np.maximum(package * (1.0 - LOCAL_RANGE), lower)
    high = np.minimum(package * (1.0 + LOCAL_RANGE), upper)
    X2 = low + unit_sample(len(names), len(X), method="sobol", seed=1) * (high - low)
    rows2 = []
    for x in X2:
        out = evaluator.evaluate(dict(zip(names, x, strict=True)))
        rows2.append([out[c] for c in group_segments(list(out))[0]])
    local = series_minimum(X2, np.array(rows2), segments, names, nominal, low, high, "log")
    ratio = {
        "SeriesSurrogate.box_optimum (affine in log p)": package,
        "ridge affine in log p (this script)": log_min,
        "ridge affine in conductance-like features": cond_min,
        f"ridge affine in log p on {len(X)} more samples within +-15 % of the first answer": local,
    }
    return {
        "samples": int(len(X)),
        "prior": {
            n: [round(float(lo), 4), round(float(hi), 4)]
            for n, lo, hi in zip(names, lower, upper, strict=True)
        },
        "minimum / truth per parameter": {
            label: {n: round(float(v / truth[n]), 4) for n, v in zip(names, values, strict=True)}
            for label, values in ratio.items()
        },
    }


def one_parameter_picture(truth_ratio: float, films_ratio: float, lower=0.25, upper=1.75) -> dict:
    """The zero of a straight line in ``log p`` fitted (uniform p over the prior) to the roof's
    heat signature ``1 / (p + films) - 1 / (p_true + films)`` (p, films in nominal R units)."""
    p = np.linspace(lower, upper, 20001)
    z = np.log(p)
    signature = 1.0 / (p + films_ratio) - 1.0 / (truth_ratio + films_ratio)
    b, a = np.polyfit(z, signature, 1)
    zero = float(np.exp(-a / b))
    u = 1.0 / p - 1.0  # conductance-like feature: the signature is linear in it without films
    b2, a2 = np.polyfit(u, signature, 1)
    zero_cond = float(1.0 / (1.0 - a2 / b2))
    return {
        "truth (x nominal)": truth_ratio,
        "films (x nominal R)": round(films_ratio, 4),
        "zero of the log-affine fit / truth - 1": round(zero / truth_ratio - 1.0, 4),
        "zero of the conductance-affine fit / truth - 1": round(zero_cond / truth_ratio - 1.0, 4),
    }


def markdown(r: dict) -> str:
    lines = [
        "# Why the zone-group calibration finds the roof of 5ZoneAirCooled too conductive",
        "",
        "Generated by `diagnose_roof.py` (issues 26 and 28). EnergyPlus 25.2 at 1-minute steps and "
        "thermocal at 5-minute steps on the same true-envelope file (wall R x0.6, roof R x1.5, "
        "infiltration x1.4, loads included), January, Chicago O'Hare TMY3; means over January "
        "2-31.",
        "",
        "## 1. Forward paths (plenum and roof, true envelope)",
        "",
        "| path | EnergyPlus | thermocal | difference | hourly RMS of the difference "
        "| hourly slope tc/E+ |",
        "|---|---|---|---|---|---|",
    ]
    for label, v in r["paths"].items():
        lines.append(
            f"| {label} | {v['energyplus']:.2f} | {v['thermocal']:.2f} | {v['difference']:+.2f} | "
            f"{v['hourly_rms_difference']:.2f} | {v['hourly_slope_thermocal_on_energyplus']:.3f} |"
        )
    lines += ["", "## 2. Roof coefficients on EnergyPlus' own states", ""]
    lines += [f"- {k}: {v}" for k, v in r["coefficients"].items()]
    lines += ["", "## 3. What the calibrated roof (4.886 m2 K/W) would compensate", ""]
    lines += [f"- {k}: {v}" for k, v in r["equivalent"].items()]
    lines += ["", "## 4. The metric itself (campaign of calibrate_twin.py, 15-minute steps)", ""]
    m = r["metric_along_roof"]
    for key in ("minimum of the groups metric, roof R / truth", PLENUM_MINIMUM):
        lines.append(f"- {key} (every other parameter at its truth): {m[key]}")
    lines += [f"- {k}: {v}" for k, v in r["direct_minimum"].items()]
    lines += ["", "## 5. The meta-model", ""]
    lines += [f"- {k}: {v}" for k, v in r["metamodel"]["minimum / truth per parameter"].items()]
    lines += [f"- one-parameter picture, prior +-75 %: {r['one_parameter']}"]
    lines += [f"- one-parameter picture, +-15 % around the truth: {r['one_parameter_local']}"]
    lines += ["", "## Conclusion", "", r["conclusion"], ""]
    return "\n".join(lines)


def main() -> int:
    import calibrate_twin as ct

    t0 = time.perf_counter()
    truth_file = json.loads((HERE / "truth.json").read_text())
    truth = truth_file["truth"]
    names = [ct.WALL, ct.ROOF, *ct.INFILTRATION]
    text = true_envelope_text()
    results: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        ep = energyplus_surfaces(text, tmp)
        sim, states = thermocal_forward(text, tmp)
        tc = thermocal_paths(sim, states)
        results["paths"] = path_table(ep, tc)
        results["coefficients"] = coefficients_on_energyplus_states(ep, sim)
        results["equivalent"] = roof_equivalent(ep, truth[ct.ROOF])
        print(json.dumps(results, indent=1), flush=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            campaign, inputs, problem, evaluator = campaign_problem(tmp / "campaign")
            results["metric_along_roof"] = metric_along_roof(evaluator, truth, names)
            committed = json.loads((HERE / "results.json").read_text())["groups"]["rows"]
            calibrated = {row["parameter"]: row["calibrated"] for row in committed}
            results["direct_minimum"] = direct_minimum(evaluator, truth, names, calibrated)
            results["metamodel"] = metamodel_study(campaign, inputs, evaluator, truth)
    films = results["equivalent"]["films (inside conv + long-wave, outside combined) [m2 K/W]"]
    nominal_roof = truth_file["nominal"][ct.ROOF]
    results["one_parameter"] = one_parameter_picture(
        truth[ct.ROOF] / nominal_roof, films / nominal_roof
    )
    results["one_parameter_local"] = one_parameter_picture(
        truth[ct.ROOF] / nominal_roof,
        films / nominal_roof,
        lower=truth[ct.ROOF] / nominal_roof * (1.0 - LOCAL_RANGE),
        upper=truth[ct.ROOF] / nominal_roof * (1.0 + LOCAL_RANGE),
    )
    results["conclusion"] = CONCLUSION
    results["seconds"] = round(time.perf_counter() - t0, 1)
    (HERE / "diagnose_roof.json").write_text(json.dumps(results, indent=1) + "\n")
    (HERE / "diagnose_roof.md").write_text(markdown(results))
    print(markdown(results))
    return 0


CONCLUSION = (
    "Not the roof's physics. With the true envelope, every heat path of the roof and of the "
    "plenum agrees with EnergyPlus within 2 W of the roof's 1510 W (0.1 %; the roof's solar "
    "gain +0.9 % and its SimpleCombined loss -0.9 % cancel at the outside face), the roof's "
    "coefficients computed on EnergyPlus' own wind and temperatures equal EnergyPlus' to 1e-3 "
    "W/(m2 K), and the calibrated 4.886 m2 K/W would need a systematic 95 W of missing roof "
    "loss. The calibration's metric itself has its minimum at the truth: along the roof with "
    "the other parameters true at +0.1 %, over all seven parameters at +0.8 % (direct "
    "Nelder-Mead, no meta-model), and the committed answer's metric drops when only its roof "
    "is set to the truth (plenum group 3056 -> 1934 W^2). The -6 % comes from the series "
    "meta-model, which writes each hour's identified heat as affine in log(p / p_nominal) "
    "over the whole +-75 % prior: the heat through the roof goes as 1 / (R + films), convex in "
    "log R, and a straight line fitted over [0.25, 1.75] x nominal crosses zero 6-7 % below "
    "the truth (the one-parameter picture); on the campaign's own 48 samples its minimum is "
    "the roof at -6.6 %. A second campaign of 48 samples in +-15 % around that answer with "
    "the same model finds the roof at +0.9 % and the wall at -2.2 %, like the direct minimum "
    "(the one-parameter bias is +0.35 % over +-15 %); conductance-like features over the "
    "whole prior overshoot the other way (+5 %, the films). The fix belongs in the "
    "calibration (a local refit or a curvature term in the series model), not in multizone."
)

if __name__ == "__main__":
    raise SystemExit(main())
