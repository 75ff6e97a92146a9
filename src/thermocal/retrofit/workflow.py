"""The retrofit analysis (fifth-order RC method), end to end.

:func:`run_retrofit` reads the building file, the measurements and a typical-year weather file,
calibrates the fifth-order model on the training period, validates it on training and test
periods, simulates the annual heating demand and the 16 retrofit strategies with parameter
uncertainty, and returns everything as a :class:`RetrofitAnalysis`, which
:mod:`thermocal.retrofit.outputs` writes as results.json, CSV tables, figures and report.html.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.jsonsafe import json_number
from thermocal.montecarlo import interval_ends
from thermocal.physics.ground import ground_temperature, ground_temperature_parameters
from thermocal.retrofit.airchange import adjust_demand, air_change_summary, estimate_slope
from thermocal.retrofit.calibration import (
    BOUNDARY_COLUMNS,
    HEAT_COLUMNS,
    MIN_INDOOR_COVERAGE,
    OUTPUT_COLUMN,
    RETROFIT_HEAT_BLOCK_H,
    Calibration,
    calibrate,
    calibrate_to_heat,
    check_heating_power_magnitude,
    check_training_data,
    draw_parameters,
    heat_unit_keys,
    heating_setpoint,
    tight_control,
)
from thermocal.retrofit.config import RetrofitConfig
from thermocal.retrofit.correction import corrects_the_ground_path
from thermocal.retrofit.data import (
    check_irradiance_limits,
    check_temperature_units,
    clock_notes,
    log_interval,
    prepare_measurements,
    read_raw_measurements,
    removed_values_notes,
    with_beam_and_diffuse,
)
from thermocal.retrofit.demand import DEMAND_INPUTS, DemandResult, simulate_demand
from thermocal.retrofit.gains import (
    check_configured_gains,
    check_metered_electricity,
    combined_rel_std,
    gains_day_profile,
    internal_gains,
)
from thermocal.retrofit.gate import heat_to_follow_measured, heat_validation, validation_gate
from thermocal.retrofit.ground_draws import draw_ground_inputs, ground_overrides
from thermocal.retrofit.in_situ import in_situ_priors, measure_in_situ
from thermocal.retrofit.inputs import solar_inputs
from thermocal.retrofit.metrics import daily_profile, validation_metrics
from thermocal.retrofit.model import (
    ESTIMATED_PARAMETERS,
    STATE_NAMES,
    FifthOrderModel,
    build_fifth_order_model,
    calculated_hlc,
    check_measures,
    check_ventilation_measures,
    simulation_network,
)
from thermocal.retrofit.strategies import Measure, Strategy


@dataclass
class RetrofitAnalysis:
    """Everything the retrofit workflow computed (inputs to the output writers)."""

    config: RetrofitConfig
    building: Any
    model: FifthOrderModel
    calibration: Calibration
    data: pd.DataFrame  # measurement grid with model inputs and Ti_measured
    training: tuple[pd.Timestamp, pd.Timestamp]
    test: tuple[pd.Timestamp, pd.Timestamp] | None
    simulated_ti: pd.Series
    validation: dict[str, dict[str, float]]
    indoor_profile: np.ndarray
    strategies: list[Strategy]
    demand: DemandResult
    weather_meta: dict
    year_inputs: pd.DataFrame | None = None  # demand-model inputs of the weather year
    envelopes: list | None = None  # per strategy (and per draw with uncertain U-values)
    draws: dict[str, np.ndarray] | None = None  # parameter sets (SI), first = estimate
    timings: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    measurements_quality: Any = None  # thermocal.io.measurements.QualityReport of the grid
    heat_validation: dict | None = None  # daily heat of model vs meter, test period
    gate: dict | None = None  # verdict of thermocal.retrofit.gate.validation_gate
    year_gains: np.ndarray | None = None  # [W] internal gains of the demand year
    gains_rel_std: float = 0.0  # [-] relative spread of those gains in the draws
    calibration_method: dict | None = None  # :func:`calibration_method` (what was fitted, why)
    air_change: dict | None = None  # :func:`thermocal.retrofit.airchange.estimate_slope`
    #: component -> :class:`thermocal.retrofit.in_situ.InSituMeasurement` (``in_situ:``)
    in_situ: dict = field(default_factory=dict)


def load_building(source, *, config_source: str = "the retrofit configuration"):
    """A :class:`thermocal.io.envelope.EnvelopeDescription` from a path or an inline mapping.

    Both go through :mod:`thermocal.io.envelope` (``read_envelope`` / ``envelope_from_dict``),
    so invalid input raises :class:`ThermocalInputError` naming the field, the component, the
    YAML line (files), the plausible range with unit and likely typos.

    Parameters
    ----------
    source : path or dict
        Building file, or the building description given inline under ``building:``.
    config_source : str
        Where an inline description comes from, for error messages.
    """
    from thermocal.io.envelope import envelope_from_dict, read_envelope

    if isinstance(source, dict):
        return envelope_from_dict(source, source=f"building (inline in {config_source})")
    return read_envelope(Path(source))


def building_name(cfg: RetrofitConfig) -> str:
    """The configuration's building file, or "the inline building", for messages."""
    return str(cfg.building if isinstance(cfg.building, Path) else "the inline building")


def resolve_weather_path(path) -> Path:
    """A weather path; ``pvlib:NAME`` (e.g. ``pvlib:723170TYA.CSV``) names a file shipped
    with pvlib."""
    text = str(path)
    if "pvlib:" in text:
        name = text.split("pvlib:", 1)[1]
        return Path(__import__("pvlib").__file__).parent / "data" / name
    return Path(path)


#: How a retrofit configuration asks for the weather file's site (named in the refusal of a
#: building far from its weather, and in the note when the site was replaced).
SITE_OPT_IN = "weather.site: weather in the retrofit configuration"


def building_at_weather_site(
    building,
    cfg: RetrofitConfig,
    *,
    building_source: str,
    weather_meta: dict | None = None,
    opt_in: str = SITE_OPT_IN,
):
    """The building at the site ``weather.site`` of the configuration chooses.

    :func:`thermocal.io.weather.building_site_or_weather` for a retrofit configuration: with
    ``weather.site: building`` (the default) a building more than 300 km from the weather file's
    site is refused, the message naming ``opt_in``; with ``weather.site: weather`` the weather
    file's latitude, longitude and altitude replace the building's (its time zone kept), as
    EnergyPlus does for a weather-file run, and the note saying so is returned.

    Parameters
    ----------
    building : EnvelopeDescription or thermocal.multizone.Building
        The building as read (an envelope is frozen: a copy is returned).
    cfg : RetrofitConfig
        ``weather.file``, ``weather.format``, ``weather.columns``, ``weather.site``.
    building_source : str
        The building file, for the messages.
    weather_meta : dict, optional
        The weather reader's metadata when already read (else the file is read).
    opt_in : str
        How the user asks for the weather's site, for the messages.

    Returns
    -------
    (building, str or None)
        The building (with the weather's site when it was replaced) and the note, else None.
    """
    from types import SimpleNamespace

    from thermocal.io.weather import building_site_or_weather, read_weather

    if weather_meta is None:
        path = resolve_weather_path(cfg.weather.file)
        if not path.is_file():
            raise ThermocalInputError(f"weather file {path} not found (weather.file)")
        _, weather_meta = read_weather(
            path, format=cfg.weather.format, columns=cfg.weather.columns
        )
    holder = SimpleNamespace(location=building.location)
    note = building_site_or_weather(
        holder,
        weather_meta,
        cfg.weather.site,
        building_source=building_source,
        weather_source=str(cfg.weather.file),
        option="weather.site",
        opt_in=opt_in,
    )
    if note is None:
        return building, None
    if hasattr(building, "model_copy"):  # the envelope description is frozen
        return building.model_copy(update={"location": holder.location}), note
    building.location = holder.location
    return building, note


#: Said with every analysis of a pyranometer's global irradiance (measurements.irradiance: ghi).
IRRADIANCE_SPLIT_NOTE = (
    "beam and diffuse irradiance split from the measured global horizontal irradiance "
    "(Erbs et al. 1982 correlation): against measured beam and diffuse, the savings moved by "
    "at most 0.2 and 1.0 pp on two EnergyPlus houses, 0.25 pp on the demo and up to 3.5 pp "
    "(the strategies with the walls) on a synthetic house; the intervals do not include this "
    "error"
)


def load_weather_year(cfg: RetrofitConfig, step: pd.Timedelta) -> tuple[pd.DataFrame, dict]:
    """The typical-year weather on the model step, with interval-mean air temperature (one
    whole year: :func:`thermocal.io.weather.check_full_year`, for every caller: the command,
    ``thermocal demo --weather``, verify, a script)."""
    from thermocal.io.weather import check_full_year, read_weather, resample_weather

    path = resolve_weather_path(cfg.weather.file)
    if not path.is_file():
        raise ThermocalInputError(f"weather file {path} not found (weather.file)")
    weather, meta = read_weather(path, format=cfg.weather.format, columns=cfg.weather.columns)
    check_full_year(weather, meta, source=str(cfg.weather.file))
    for col in ("temp_air", "dni", "dhi"):
        if col not in weather:
            raise ThermocalInputError(
                f"weather file {path} has no {col!r}; the annual demand needs air temperature, "
                "DNI and DHI"
            )
    w_step = weather.index[1] - weather.index[0]
    if w_step != step:
        weather = resample_weather(weather, step)
    # instant temperatures -> interval means (thermocal weather convention)
    temp = weather["temp_air"].to_numpy(float)
    weather = weather.copy()
    weather["temp_air_mean"] = 0.5 * (temp + np.roll(temp, -1))
    weather.iloc[-1, weather.columns.get_loc("temp_air_mean")] = temp[-1]
    return weather, meta


def _periods(grid: pd.DataFrame, cfg: RetrofitConfig, source: str):
    start = grid.index[0]
    if cfg.periods.training_start is not None:
        start = pd.Timestamp(cfg.periods.training_start)
        if start.tz is None:
            start = start.tz_localize(grid.index.tz)
    step = grid.index[1] - grid.index[0]
    end_data = grid.index[-1] + step
    # a start on the log's first day before its first row is fine (fewer training hours)
    first_end = start + pd.Timedelta(days=cfg.periods.training_days)
    if not (start < end_data and first_end > grid.index[0]):
        raise ThermocalInputError(
            f"{source}: periods.training_start {start} is outside the measurements, which run "
            f"from {grid.index[0]} to {end_data}; give a start inside them (or leave "
            "periods.training_start out: the first measurement)"
        )
    train_end = start + pd.Timedelta(days=cfg.periods.training_days)
    if train_end > end_data:
        have = (end_data - start) / pd.Timedelta(days=1)
        raise ThermocalInputError(
            f"{source}: the measurements from {start} cover {have:.1f} days, shorter than the "
            f"requested training period of {cfg.periods.training_days:g} days "
            "(periods.training_days); shorten it or supply more data"
        )
    test = None
    notes = []
    if cfg.periods.test_days > 0:
        test_end = min(train_end + pd.Timedelta(days=cfg.periods.test_days), end_data)
        if test_end - train_end < pd.Timedelta(days=1):
            notes.append("no test period: the measurements end with the training period")
        else:
            if test_end < train_end + pd.Timedelta(days=cfg.periods.test_days):
                notes.append(
                    f"test period shortened to {(test_end - train_end) / pd.Timedelta(days=1):.1f}"
                    " days (end of the measurements)"
                )
            test = (train_end, test_end)
    return (start, train_end), test, notes


def model_inputs(
    frame: pd.DataFrame, building, ground_params: dict, *, temp_col: str, solar: bool, depth: float
) -> pd.DataFrame:
    """Te, Tgr and the solar inputs of the model on the frame's index."""
    out = pd.DataFrame(index=frame.index)
    out["Te"] = frame[temp_col].to_numpy(float)
    out["Tgr"] = ground_temperature(frame.index, depth, **ground_params).to_numpy()
    if solar:
        sol = solar_inputs(frame, building)
        # missing irradiance is missing sun, never zero sun: the checks downstream name it
        dark = frame[["dni", "dhi"]].isna().any(axis=1).to_numpy()
        for c in sol:
            out[c] = np.where(dark, np.nan, sol[c].to_numpy())
    else:
        for c in ("phi_sol", "phi_abs_roof", "phi_abs_walls"):
            out[c] = 0.0
    return out


def simulate_indoor(
    model: FifthOrderModel,
    params_si: dict,
    x0: np.ndarray,
    inputs: pd.DataFrame,
    envelope=None,
    *,
    interval_means: bool = False,
) -> pd.DataFrame:
    """Deterministic multi-step simulation of all states (C) over ``inputs``.

    The network of :func:`thermocal.retrofit.model.network_spec` simulated by
    :meth:`thermocal.statespace.RCModel.simulate` (exact zero-order-hold discretisation).
    States are reported at the interval starts (the first row is ``x0``), or with
    ``interval_means`` as their means over the interval each label starts, which is what the
    measured series hold (interval means labelled by their start). ``envelope``: the
    calibrated (corrected) U-values (default: the building file's).
    """
    h = model.conductances(envelope)
    rc = simulation_network(h, demand=False)
    values = {**h, **{k: float(v) for k, v in params_si.items()}}
    x = np.asarray(x0, float)
    states = rc.simulate(
        inputs,
        values,
        initial_state={s: x[i] for i, s in enumerate(STATE_NAMES)},
        interval_means=interval_means,
    )
    return states[list(STATE_NAMES)]


#: A gap of the measured indoor temperature longer than this is left out of the heat check of
#: the test period, the model following its own simulated temperature across it [duration];
#: shorter gaps are bridged linearly.
FOLLOW_GAP = pd.Timedelta("6h")


def long_gaps(series: pd.Series, longest: pd.Timedelta) -> np.ndarray:
    """Boolean mask of the intervals inside gaps (NaN runs) longer than ``longest``.

    Parameters
    ----------
    series : Series
        On a regular index (NaN: missing).
    longest : Timedelta
        Longest gap bridged [duration].

    Returns
    -------
    ndarray of bool
    """
    from thermocal.io.measurements.quality import true_runs

    step = series.index[1] - series.index[0]
    most = max(1, int(longest / step))
    inside = np.zeros(len(series), dtype=bool)
    for start, end in zip(*true_runs(series.isna().to_numpy()), strict=True):
        if end - start > most:
            inside[start:end] = True
    return inside


def check_test_period(data: pd.DataFrame, source: str) -> None:
    """Refuse a test period whose inputs have gaps longer than :data:`FOLLOW_GAP`, or whose
    indoor temperature is measured in less than half of it.

    The validation simulates the test period from the calibrated state with the inputs bridged
    linearly: four days of outdoor temperature drawn as a straight line drifted the model 2.3 K
    off and failed a good model's gate, blaming the building file; 5 indoor temperatures in 21
    days made the temperature check's MAE one of 5 hours (exploratory test, 2026-11-30).

    Parameters
    ----------
    data : DataFrame
        The test period's model inputs and measured indoor temperature (NaN: missing).
    source : str
        The measurement file, for the messages.

    Raises
    ------
    thermocal.errors.ThermocalInputError
        Naming the column, the gap and the keys that move the period.
    """
    keys = "periods.test_days (or the training period before it)"
    for col in BOUNDARY_COLUMNS + HEAT_COLUMNS:
        if col not in data or not data[col].isna().any():
            continue
        gap = long_gaps(data[col], FOLLOW_GAP)
        if gap.any():
            first = data.index[int(np.argmax(gap))]
            hours = FOLLOW_GAP / pd.Timedelta("1h")
            raise ThermocalInputError(
                f"{source}: input {col!r} has a gap of more than {hours:g} h in the test period "
                f"({int(gap.sum())} intervals, the first at {first}); the validation would draw "
                f"it as a straight line: fill it in the file, or move {keys} to leave it out"
            )
    measured = int(data[OUTPUT_COLUMN].notna().sum())
    if 0 < measured < MIN_INDOOR_COVERAGE * len(data):
        raise ThermocalInputError(
            f"{source}: the indoor temperature (temp_in) is measured in only {measured} of the "
            f"{len(data)} intervals of the test period ({100 * measured / len(data):.0f} %); "
            f"the validation would check the model on those alone: move {keys} to where it is "
            "measured, or fill the log"
        )


def run_retrofit(cfg: RetrofitConfig, *, progress=None) -> RetrofitAnalysis:
    """Run the whole retrofit analysis.

    Parameters
    ----------
    cfg : RetrofitConfig
    progress : callable(str), optional
        Called with a short message at the start of each stage.

    Returns
    -------
    RetrofitAnalysis
    """
    import logging

    log = logging.getLogger("thermocal.retrofit")

    def say(msg: str) -> None:
        log.info(msg)
        if progress is not None:
            progress(msg)

    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    say("reading building, measurements and weather")
    building = load_building(
        cfg.building, config_source=f"the retrofit configuration in {cfg.base_dir}"
    )
    site_note = None
    if cfg.weather.site == "weather":  # the default's refusal: the command, before computing
        building, site_note = building_at_weather_site(
            building, cfg, building_source=building_name(cfg)
        )
        if site_note:
            log.warning(site_note)
    source = str(cfg.measurements.file)
    if cfg.model.solar_gains and not building.windows:
        raise ThermocalInputError(
            f"building {building.name!r} has no window components but solar gains are requested "
            "(model.solar_gains: true); add the windows to the building file or set "
            "model.solar_gains: false"
        )
    mc = cfg.measurements
    ig = cfg.internal_gains
    check_configured_gains(ig, float(building.heated_floor_area), building.name)
    metered = ig.source == "electricity"
    raw = read_raw_measurements(
        mc, default_tz=_location_tz(building), electricity_unit=ig.electricity_unit if metered
        else None,
    )  # fmt: skip
    try:
        grid, quality = prepare_measurements(
            raw,
            mc.step,
            heat_source=mc.heat_source,
            heat_energy=mc.heat_unit not in ("W", "kW"),
            heat_cumulative=mc.heat_cumulative,
            boiler_efficiency=mc.boiler_efficiency,
            electricity_energy=ig.electricity_unit not in ("W", "kW"),
            electricity_cumulative=ig.electricity_cumulative,
            columns=mc.columns,
        )
    except ThermocalInputError as exc:
        if "flow" not in str(exc):
            raise
        raise ThermocalInputError(  # name the configured column and unit
            f"{source}: heating flow column {cfg.measurements.columns['flow']!r} read in "
            f"{cfg.measurements.flow_unit} (measurements.flow_unit): {exc}"
        ) from None
    # the clock first: a wrong time zone also puts sunlight where the sun is low
    clock = clock_notes(raw, cfg.measurements, building.location)
    check_irradiance_limits(grid, cfg.measurements, building.location, source)
    grid = with_beam_and_diffuse(grid, cfg.measurements, building.location)
    step = grid.index[1] - grid.index[0]
    weather, weather_meta = load_weather_year(cfg, step)
    ground_params = ground_temperature_parameters(weather)
    training, test, notes = _periods(grid, cfg, source)
    if site_note:
        notes.insert(0, site_note)
    notes += cfg.economics_notes()
    if cfg.measurements.irradiance == "ghi":
        notes.append(IRRADIANCE_SPLIT_NOTE)
    for note in clock + (
        check_temperature_units(grid, weather, cfg.measurements, source)
    ):
        log.warning(note)
        notes.append(note)
    for note in removed_values_notes(quality, cfg.measurements.columns):
        log.warning(note)
        notes.append(note)
    end = test[1] if test else training[1]
    grid = grid.loc[(grid.index >= training[0]) & (grid.index < end)]
    model = build_fifth_order_model(
        building,
        solar_to_internal_mass=cfg.model.solar_to_internal_mass,
        bounds=cfg.model.bounds,
        fixed=cfg.model.fixed,
        interior=interior_for(cfg.model.interior),  # auto: settled with the method below
    )
    check_measures(model.envelope, cfg.measure_objects(), building.name)
    in_situ = measure_in_situ(cfg, building, _location_tz(building))
    if in_situ:
        if cfg.model.correction != "groups" or cfg.uncertainty.u_value_rel_std <= 0:
            raise ThermocalInputError(
                "in_situ: the in-situ U-values correct the description through the group "
                "factors; they need model.correction: groups and uncertainty.u_value_rel_std > 0"
            )
        model = replace(model, in_situ=in_situ_priors(in_situ))
        notes += [f"in_situ.{c}: {n}" for c, m in in_situ.items()
                  for n in m.result.warnings + m.result.notes]  # fmt: skip
        for m in in_situ.values():
            say(
                f"in situ: {m.component} U = {m.result.u_value:.3g} W/(m2 K) +- "
                f"{100 * m.result.rel_std:.0f} % ({m.source}), {m.ratio:.2f} x the described "
                f"{m.described_u:.3g}"
            )
    inputs = model_inputs(
        grid,
        building,
        ground_params,
        temp_col="temp_out",
        solar=cfg.model.solar_gains,
        depth=cfg.model.ground_depth,
    )
    # internal gains: in the calibration added to the heating power (the heating-system node
    # passes heat to the air within minutes), in the demand an input into the air node
    check_metered_electricity(
        grid, ig, float(building.heated_floor_area), source,
        cfg.measurements.columns.get("electricity", "electricity"),
    )  # fmt: skip
    gains = internal_gains(grid, ig)
    inputs["phi_h_measured"] = grid["phi_h"].to_numpy(float)
    inputs["phi_int"] = 0.0 if gains is None else gains.to_numpy(float)
    inputs["phi_h"] = inputs["phi_h_measured"] + inputs["phi_int"]
    inputs[OUTPUT_COLUMN] = grid["temp_in"].to_numpy(float)
    timings["inputs"] = time.perf_counter() - t0

    say("calibrating the fifth-order model")
    t1 = time.perf_counter()
    train = inputs.loc[inputs.index < training[1]]
    check_training_data(train, source, heat_source=mc.heat_source)
    if test is not None:
        check_test_period(inputs.loc[(inputs.index >= test[0]) & (inputs.index < test[1])], source)
    check_heating_power_magnitude(
        train,
        building.transmission_heat_transfer_coefficient,
        source,
        unit_hint=heat_unit_keys(mc),
    )
    setpoint = heating_setpoint(
        inputs[OUTPUT_COLUMN], inputs["phi_h_measured"], [training] + ([test] if test else [])
    )
    method = calibration_method(cfg.model.calibration, train)
    interior = interior_for(cfg.model.interior, method["method"])
    if interior != model.interior:
        model = replace(model, interior=interior)
    if cfg.model.interior == "auto":
        method["summary"] += (
            f" The room's inside is {interior} (model.interior: auto: split with the heat fit, "
            "combined with the temperature fit)."
        )
    say(method["summary"])
    correct = cfg.model.correction == "groups" and cfg.uncertainty.u_value_rel_std > 0
    if method["method"] == "heat":
        cal = calibrate_to_heat(
            model, train, setpoint[train.index], gains=gains is not None, correction=correct,
            u_value_rel_std=cfg.uncertainty.u_value_rel_std,
            heat_rel_std=cfg.uncertainty.heat_rel_std, block_h=RETROFIT_HEAT_BLOCK_H,
        )  # fmt: skip
    else:
        cal = calibrate(
            model,
            train,
            n_starts=cfg.model.n_starts,
            seed=cfg.model.seed,
            max_correlation=cfg.model.max_correlation,
            # U-values declared exact (u_value_rel_std 0): nothing to correct, the published
            # model
            correction=correct,
            fixed_noise=cfg.model.fixed_diffusions(),
            heat_rel_std=cfg.uncertainty.heat_rel_std,
            u_value_rel_std=cfg.uncertainty.u_value_rel_std,
            log_interval=log_interval(raw),
        )
    if cal.correction is not None:
        say(cal.correction.summary())
    timings["calibration"] = time.perf_counter() - t1

    say("validating")
    t2 = time.perf_counter()
    filled = inputs.copy()
    filled[list(BOUNDARY_COLUMNS + HEAT_COLUMNS)] = filled[
        list(BOUNDARY_COLUMNS + HEAT_COLUMNS)
    ].interpolate(limit_direction="both")
    states = simulate_indoor(model, cal.estimates_si, cal.x0, filled, cal.envelope)
    # the measured Ti are interval means labelled by their start: the simulation is compared
    # as the same (the state at the label is half an interval early; on the EnergyPlus twins'
    # hourly logs the test MAE is 0.05-0.06 K lower compared like with like, 2026-11-30)
    sim_ti = simulate_indoor(
        model, cal.estimates_si, cal.x0, filled, cal.envelope, interval_means=True
    )["Ti"].rename("Ti_simulated")
    validation = {}
    for name, period in (("train", training), ("test", test)):
        if period is None:
            continue
        sel = (inputs.index >= period[0]) & (inputs.index < period[1])
        if not inputs[OUTPUT_COLUMN][sel].notna().any():
            raise ThermocalInputError(
                f"{source}: no measured indoor temperature (temp_in) in the {name} period "
                f"{period[0]} - {period[1]}; supply it or set periods.test_days: 0"
            )
        validation[name] = validation_metrics(sim_ti[sel], inputs[OUTPUT_COLUMN][sel])
        validation[name]["start"] = str(period[0])
        validation[name]["end"] = str(period[1])
    heat_check = None
    if test is not None:
        sel = (inputs.index >= test[0]) & (inputs.index < test[1])
        # the heat fit's model follows the thermostat's set point; the temperature fit's the
        # measured indoor temperature (as the method validates it)
        followed = (setpoint if method["method"] == "heat" else inputs[OUTPUT_COLUMN]).loc[sel]
        gap = long_gaps(followed, FOLLOW_GAP)
        if gap.any():
            # across a long gap the model follows its own simulated temperature (a straight
            # line there drifted its states: 8 missing days of a 21-day test period took the
            # CV(RMSE) from 19 % to 34 % on the demo's own model), and those days check nothing
            followed = followed.where(~gap, sim_ti.loc[sel].to_numpy())
        model_heat = heat_to_follow_measured(
            model,
            cal.estimates_si,
            cal.envelope,
            states.loc[sel].iloc[0].to_numpy(float),
            filled.loc[sel, list(DEMAND_INPUTS)],
            followed,
            None if gains is None else inputs.loc[sel, "phi_int"],
        )
        heat_check = heat_validation(
            model_heat, inputs.loc[sel, "phi_h_measured"].where(~gap)
        )
    gate = validation_gate(
        validation, heat_check, cfg.validation.model_dump(),
        unit_keys=heat_unit_keys(cfg.measurements), heat_source=cfg.measurements.heat_source,
    )  # fmt: skip
    air_change = None
    if cfg.model.air_change == "slope":
        # the air change's growth with the indoor-outdoor difference, from the calibration
        # period's daily heat residuals (thermocal.retrofit.airchange)
        sel = np.asarray(inputs.index < training[1])
        follow = (setpoint if method["method"] == "heat" else inputs[OUTPUT_COLUMN]).loc[sel]
        train_heat = heat_to_follow_measured(
            model, cal.estimates_si, cal.envelope, states.loc[sel].iloc[0].to_numpy(float),
            filled.loc[sel, list(DEMAND_INPUTS)], follow,
            None if gains is None else inputs.loc[sel, "phi_int"],
        )  # fmt: skip
        air_change = estimate_slope(
            inputs.loc[sel, "phi_h_measured"], train_heat, follow.interpolate(
                limit_direction="both"), filled.loc[sel, "Te"], cal.estimates_si["H_est"],
        )  # fmt: skip
        say(air_change_summary(air_change))
    (log.info if gate["passed"] else log.warning)("%s", gate["summary"])
    timings["validation"] = time.perf_counter() - t2

    say("simulating annual demand and retrofit strategies")
    t3 = time.perf_counter()
    if cfg.demand.indoor_profile == "measured":
        ti = inputs[OUTPUT_COLUMN]
        if cfg.demand.profile_period == "training":
            ti = ti[ti.index < training[1]]
        profile = daily_profile(ti)
    else:
        profile = np.full(24, float(cfg.demand.indoor_profile))
    year = model_inputs(
        weather,
        building,
        ground_params,
        temp_col="temp_air_mean",
        solar=cfg.model.solar_gains,
        depth=cfg.model.ground_depth,
    )
    weather_columns = [c for c in BOUNDARY_COLUMNS + HEAT_COLUMNS if c in year]
    gaps = year[weather_columns].isna().any(axis=1)
    if gaps.any():
        columns = [c for c in weather_columns if year[c].isna().any()]
        raise ThermocalInputError(
            f"weather file {cfg.weather.file}: {int(gaps.sum())} of {len(year)} steps of the "
            f"demand year lack {', '.join(columns)} (from missing temperature or irradiance, "
            f"first at {year.index[int(np.argmax(gaps.to_numpy()))]}); the annual demand needs "
            "a complete weather year: use a complete file (e.g. a TMY) or fill the gaps"
        )
    strategies = cfg.strategy_list()
    notes += check_ventilation_measures(
        strategies, cfg.measure_objects(), float(building.volume), cal.estimates_si["H_est"]
    )
    year_gains = None
    gains_std = 0.0
    if gains is not None:  # the source's and the occupants' (thermocal.retrofit.gains)
        day = gains_day_profile(inputs["phi_int"], ig)
        year_gains = day[np.asarray(year.index.hour)]
        gains_std = combined_rel_std(day, ig)
    ground = None
    if cfg.uncertainty.ground and cfg.uncertainty.draws > 0:
        # the ground's uncertain inputs (thermocal.retrofit.ground_draws); the calibration
        # period's means keep each draw's heat balance
        cal_rows = np.asarray(inputs.index < training[1])
        ground = {
            "inputs": draw_ground_inputs(
                building, model, cfg.uncertainty.draws + 1, seed=cfg.uncertainty.seed,
                # a floor on the ground: the floor group's correction carries the soil
                soil=cal.correction is None or not corrects_the_ground_path(model.envelope),
            ),
            "means": {
                c: float(np.nanmean(inputs[col].to_numpy(float)[cal_rows]))
                for c, col in (("Ti", OUTPUT_COLUMN), ("Te", "Te"), ("Tgr", "Tgr"))
            },
        }
        ground["overrides"] = ground_overrides(building, model, ground["inputs"])
    if cal.correction is not None:
        draws, envelopes = corrected_scenarios(
            model, cal, strategies, cfg.measure_objects(), cfg.uncertainty.draws,
            seed=cfg.uncertainty.seed, ground=ground,
        )  # fmt: skip
    else:
        draws = draw_parameters(cal, model, cfg.uncertainty.draws, seed=cfg.uncertainty.seed)
        envelopes = scenario_envelopes(
            model,
            strategies,
            cfg.measure_objects(),
            draws,
            cfg.uncertainty.u_value_rel_std,
            seed=cfg.uncertainty.seed,
            ground=ground,
        )
    if ground is not None:
        draws.update(ground["inputs"])
    if gains is not None:  # their uncertainty: one log-normal factor per draw (first: 1)
        sigma = np.sqrt(np.log1p(gains_std**2))
        rng = np.random.default_rng(cfg.uncertainty.seed + 104729)
        factor = np.exp(rng.normal(-0.5 * sigma**2, sigma, len(draws["H_est"])))
        factor[0] = 1.0
        draws["gain_factor"] = factor
        # The calibration saw the same gains: had they been f times the input, its energy
        # balance would have given a total conductance larger by (f - 1) G / dT (the mean gains
        # and indoor-outdoor difference of the calibration period). Each draw's H_est carries
        # that shift, so the gains' uncertainty reaches the demand only where the year's
        # conditions differ from the calibration's; drawn independently of the fit it counted
        # an error the calibrated parameters had already absorbed (basement twin: demand
        # interval 7,311-12,318 kWh around 9,422 with an HLC interval of -4/+9 %).
        cal_rows = np.asarray(inputs.index < training[1])
        g_cal = float(np.nanmean(inputs["phi_int"].to_numpy(float)[cal_rows]))
        dt_cal = float(np.nanmean((inputs[OUTPUT_COLUMN] - inputs["Te"]).to_numpy(float)[cal_rows]))
        if dt_cal > 1.0 and g_cal > 0.0:
            draws["H_est"] = np.maximum(draws["H_est"] + (factor - 1.0) * g_cal / dt_cal, 1.0)
    demand = simulate_demand(
        model, draws, envelopes, year[list(DEMAND_INPUTS)], profile, gains=year_gains
    )
    if air_change is not None:
        demand = adjust_demand(demand, air_change, year["Te"], profile, cfg.uncertainty.seed)
    timings["demand"] = time.perf_counter() - t3
    timings["total"] = time.perf_counter() - t0
    log.info(
        "retrofit analysis done in %.1f s (calibration %.1f s, demand %.1f s)",
        timings["total"], timings["calibration"], timings["demand"],
    )  # fmt: skip
    return RetrofitAnalysis(
        config=cfg, building=building, model=model, calibration=cal, data=inputs,
        training=training, test=test, simulated_ti=sim_ti, validation=validation,
        indoor_profile=profile, strategies=strategies, demand=demand,
        weather_meta=weather_meta, year_inputs=year[list(DEMAND_INPUTS)], draws=draws,
        year_gains=year_gains, gains_rel_std=gains_std,
        envelopes=envelopes,
        timings=timings, notes=notes, measurements_quality=quality,
        heat_validation=heat_check, gate=gate, calibration_method=method,
        air_change=air_change, in_situ=in_situ,
    )  # fmt: skip


def interior_for(requested: str, method: str | None = None) -> str:
    """The room's inside (``model.interior``) the model gets with a calibration method.

    ``auto``: the split inside (convection to the air, radiation among the surfaces,
    :mod:`thermocal.retrofit.interior`) with the heat fit, whose house a thermostat holds at
    its air temperature, so that the losses referenced to that air are what the split inside
    computes; the method's combined surface resistances with the temperature fit, on which the
    split inside's likelihood has several optima (docs/retrofit.md, "The room's inside").

    Parameters
    ----------
    requested : {"auto", "combined", "split"}
        The configuration's ``model.interior``.
    method : {"heat", "temperature"} or None
        The calibration method chosen (:func:`calibration_method`); None before it is known
        (``auto`` then gives the combined inside until the method settles it).

    Returns
    -------
    str
        "combined" or "split".
    """
    if requested != "auto":
        return requested
    return "split" if method == "heat" else "combined"


def calibration_method(requested: str, train: pd.DataFrame) -> dict:
    """Which quantity the calibration fits, and why (``model.calibration``).

    ``auto``: the metered heat (:func:`thermocal.retrofit.calibration.calibrate_to_heat`) when
    a thermostat holds the indoor temperature over the training period
    (:func:`thermocal.retrofit.calibration.tight_control`): the temperature then carries no
    information on the losses, the heat does; otherwise the indoor temperature (the method's
    maximum-likelihood fit, :func:`thermocal.retrofit.calibration.calibrate`).

    Parameters
    ----------
    requested : {"auto", "temperature", "heat"}
    train : pd.DataFrame
        Training data with the measured indoor temperature [C] and ``phi_h_measured`` [W].

    Returns
    -------
    dict: ``method`` ("heat" or "temperature"), ``requested``, ``tight_control`` (the
    deviation ``mad_K`` [K], ``tight``, ``limit_K`` [K]) and ``summary`` (one sentence).
    """
    control = tight_control(train[OUTPUT_COLUMN], train["phi_h_measured"])
    method = requested
    if requested == "auto":
        method = "heat" if control["tight"] else "temperature"
    held = (
        f"the indoor temperature deviates by {control['mad_K']:.2f} K (median) from the "
        f"thermostat's daily profile while heating (tight control below {control['limit_K']:g}"
        " K)"
    )
    what = (
        "fitted to the metered heat the model needs to follow the thermostat's set point "
        "(closed-loop identification)"
        if method == "heat"
        else "fitted to the measured indoor temperature (maximum likelihood, Kalman filter)"
    )
    why = (
        f"chosen automatically: {held}"
        if requested == "auto"
        else f"model.calibration: {requested}; {held}"
    )
    return {"method": method, "requested": requested, "tight_control": control,
            "summary": f"The model was {what}; {why}."}  # fmt: skip


def _location_tz(building):
    """Fixed-offset local STANDARD time of the building (naive measurement timestamps)."""
    import datetime as _dt
    from zoneinfo import ZoneInfo

    tz = building.location.timezone
    if isinstance(tz, int | float):
        return float(tz)
    try:
        zone = ZoneInfo(str(tz))
    except Exception:  # noqa: BLE001 - leave it to pandas
        return tz
    offset = _dt.datetime(2001, 1, 15, tzinfo=zone).utcoffset()
    return offset.total_seconds() / 3600.0


def scenario_envelopes(
    model: FifthOrderModel,
    strategies,
    measures: dict,
    draws: dict[str, np.ndarray],
    u_value_rel_std: float = 0.0,
    seed: int = 0,
    ground: dict | None = None,
):
    """Envelopes (U-values) of every strategy, optionally per draw with uncertain audit U.

    ``measures`` maps a name to a :class:`~thermocal.retrofit.strategies.Measure`, or (the
    method's short form) a component name to its U-value after the retrofit [W/(m2 K)].

    With ``u_value_rel_std > 0`` each draw (except the first, the estimate) multiplies the
    audit U-values of roof, walls, windows and floor by independent log-normal factors of
    that relative spread. The data identify the total heat loss coefficient, not its split,
    so the draw's ``H_est`` is shifted to keep the calibrated HLC (``draws`` is updated in
    place, clipped at 1 W/K). Each draw's retrofitted components keep its correction: an opaque
    one gets the measure's insulation, a new window the old ones' films
    (:meth:`~thermocal.retrofit.model.EnvelopeComponents.apply`).

    ``ground`` (``inputs``, ``overrides``, ``means``; :mod:`thermocal.retrofit.ground_draws`)
    gives each draw its ground path; its ``H_est`` keeps the calibration period's heat
    balance (:func:`~thermocal.retrofit.ground_draws.h_est_shifts`).

    Returns
    -------
    list (one per strategy) of EnvelopeComponents, or of lists of them (one per draw).
    """
    measures = {
        name: m if isinstance(m, Measure) else Measure(name, name, u_value=float(m))
        for name, m in measures.items()
    }
    if u_value_rel_std <= 0 and ground is None:
        return [model.apply_measures([measures[m] for m in s.measures]) for s in strategies]
    n = len(draws["H_est"])
    rng = np.random.default_rng(seed + 7919)
    sigma = np.sqrt(np.log1p(u_value_rel_std**2))
    factors = np.exp(rng.normal(-0.5 * sigma**2, sigma, size=(n, 4)))
    factors[0] = 1.0
    base = model.envelope
    hlc0 = calculated_hlc(model.conductances(base))
    per_draw = []
    for d in range(n):
        f = factors[d]
        env = base.with_measures(
            {
                "roof": base.roof_u * f[0],
                "walls": base.walls_u * f[1],
                "windows": base.windows_u * f[2],
                "cellar_ceiling": base.floor_u * f[3],
            }
        )
        shift = hlc0 - calculated_hlc(model.conductances(env))
        draws["H_est"][d] = max(draws["H_est"][d] + shift, 1.0)
        per_draw.append(env)
    per_draw = _with_ground(model, per_draw, draws, ground)
    return [
        [model.apply_measures([measures[m] for m in s.measures], env) for env in per_draw]
        for s in strategies
    ]


def _with_ground(model, envelopes: list, draws: dict, ground: dict | None) -> list:
    """Each draw's envelope with its drawn ground; its ``H_est`` shifted (in place) to keep
    the calibration period's heat balance."""
    if ground is None:
        return envelopes
    from thermocal.retrofit.ground_draws import h_est_shifts

    overrides = ground["overrides"]
    shifts = h_est_shifts(model, envelopes, overrides, ground["means"])
    draws["H_est"] = np.maximum(np.asarray(draws["H_est"], float) + shifts, 1.0)
    return [replace(env, **fields) for env, fields in zip(envelopes, overrides, strict=True)]


def corrected_scenarios(
    model, cal, strategies, measures: dict, n_draws: int, seed: int = 0, ground=None
):
    """Parameter draws and per-draw envelopes of every strategy from the posterior of the
    group corrections (:mod:`thermocal.retrofit.correction`).

    Each draw scales the building file's U-values by its group factors; a measure then adds
    its insulation to the construction it retrofits, the other components keep the draw's
    corrected U-value. ``ground``: as :func:`scenario_envelopes`.

    Returns
    -------
    draws : dict name -> ndarray (n_draws + 1,) in SI (first = the estimate), with the group
        factors ``k_env``, ``k_win``, ``k_floor`` and those of components measured in situ
        (``k_walls``, ...) [-]
    envelopes : list (per strategy) of lists (per draw) of EnvelopeComponents
    """
    from thermocal.retrofit.correction import draw_corrected, scaled_envelope

    corr = cal.correction
    z = draw_corrected(corr, n_draws, seed=seed)
    draws = {n: np.full(len(z), v) for n, v in cal.estimates_si.items()}
    draws.update(corr.physical_si(z))
    factors = corr.group_factors(z)
    draws.update(factors)
    measures = {
        name: m if isinstance(m, Measure) else Measure(name, name, u_value=float(m))
        for name, m in measures.items()
    }
    base = [
        scaled_envelope(model.envelope, {g: v[d] for g, v in factors.items()})
        for d in range(len(z))
    ]
    base = _with_ground(model, base, draws, ground)
    envelopes = [
        [model.apply_measures([measures[m] for m in s.measures], env) for env in base]
        for s in strategies
    ]
    return draws, envelopes


def compare_with_reference_demands(
    analysis: RetrofitAnalysis, reference_kwh: dict[str, float], setpoint: float = 20.0
) -> dict:
    """The model's annual demand and savings at a constant set point next to reference values.

    Parameters
    ----------
    analysis : RetrofitAnalysis
    reference_kwh : dict code -> annual demand [kWh]
        e.g. the demo generator's multi-zone answer for the 16 strategies.
    setpoint : float [C]
        Constant indoor set point used for both.

    Returns
    -------
    dict with ``setpoint_C`` and ``strategies``: per code the model's annual kWh (estimate,
    p05, p95), saving [%] (estimate, p05, p95), the reference kWh and saving [%]; the p05 and
    p95 (and the monthly ones) are None without draws (``uncertainty.draws: 0``).
    """
    cfg = analysis.config
    envelopes = analysis.envelopes
    res = simulate_demand(
        analysis.model, analysis.draws, envelopes, analysis.year_inputs, float(setpoint),
        gains=analysis.year_gains,
    )  # fmt: skip
    if analysis.air_change is not None:
        res = adjust_demand(
            res, analysis.air_change, analysis.year_inputs["Te"], float(setpoint),
            cfg.uncertainty.seed,
        )  # fmt: skip
    annual = res.annual_kwh()
    interval = cfg.uncertainty.interval
    lo_q = 0.5 * (1.0 - interval)
    base_ref = reference_kwh.get("0")
    rows = []
    for i, s in enumerate(analysis.strategies):
        sv = 100.0 * (1.0 - annual[i] / annual[0])
        ref = reference_kwh.get(s.code)
        kwh_lo, kwh_hi = (json_number(v) for v in interval_ends(annual[i, 1:], interval))
        sv_lo, sv_hi = (json_number(v) for v in interval_ends(sv[1:], interval))
        rows.append({
            "code": s.code,
            "model_kWh": float(annual[i, 0]),
            "model_kWh_p05": kwh_lo,
            "model_kWh_p95": kwh_hi,
            "model_saving_pct": float(sv[0]),
            "model_saving_pct_p05": sv_lo,
            "model_saving_pct_p95": sv_hi,
            "reference_kWh": None if ref is None else float(ref),
            "reference_saving_pct": None if ref is None or not base_ref
            else float(100.0 * (1.0 - ref / base_ref)),
        })  # fmt: skip
    monthly = res.monthly_kwh()[0]
    has_draws = monthly.shape[0] > 1
    return {
        "setpoint_C": float(setpoint),
        "strategies": rows,
        "monthly_model_kWh": [float(v) for v in monthly[0]],
        "monthly_model_kWh_p05": [float(v) for v in np.quantile(monthly[1:], lo_q, axis=0)]
        if has_draws else None,
        "monthly_model_kWh_p95": [float(v) for v in np.quantile(monthly[1:], 1 - lo_q, axis=0)]
        if has_draws else None,
    }  # fmt: skip


def heat_loss_coefficient_draws(analysis: RetrofitAnalysis, h_est: np.ndarray) -> np.ndarray:
    """HLC [W/K] for given ``H_est`` values (the calculated part is fixed)."""
    return calculated_hlc(analysis.model.conductances()) + np.asarray(h_est, float)


__all__ = ["ESTIMATED_PARAMETERS", "RetrofitAnalysis", "run_retrofit"]
