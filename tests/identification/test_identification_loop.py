"""The closed loop inside the multi-zone kernel: exact inverse, PID, the metric, bad input."""

from __future__ import annotations

import functools

import numpy as np
import pandas as pd
import pytest

from thermocal.demos import buildings as generators
from thermocal.errors import ThermocalInputError
from thermocal.identification.metrics import unoccupied_variance
from thermocal.identification.occupancy import OccupancySchedule, unoccupied_mask
from thermocal.identification.pid import PIDGains
from thermocal.identification.tuning import tune_zone
from thermocal.identification.workflow import identify
from thermocal.multizone import Simulation

START, END = "2001-01-08", "2001-01-13"


@functools.cache
def _weather():
    from thermocal.demos.retrofit import pvlib_weather_path
    from thermocal.io.weather import read_weather

    return read_weather(pvlib_weather_path())


def _building():
    return generators.clinic(12, n_corridors=1, corridor_sections=2)


def _simulation(building, **kwargs):
    weather, meta = _weather()
    kwargs.setdefault("store_surfaces", False)
    return Simulation(building, weather, meta, step="5min", start=START, end=END, **kwargs)


def _square_wave(sim, zone_index, amplitude=500.0):
    n, nz = len(sim.times), len(sim.building.zones)
    heat = np.zeros((n, nz))
    heat[(np.arange(n) // 36) % 2 == 0, zone_index] = amplitude
    return heat


@pytest.mark.parametrize("feedback", ["air", "operative"])
def test_inverse_recovers_an_injected_heat_to_numerical_precision(feedback):
    building = _building()
    sim = _simulation(building, warmup_days=0, initial_temperature=5.0)
    heat = _square_wave(sim, 3)
    forward = sim.run(free_float=True, heat_input=heat)
    reference = (
        forward.air_temperature if feedback == "air" else forward.operative_temperature
    ).to_numpy()
    tracked = sim.track(reference, method="inverse", feedback=feedback)
    q = tracked.heat.to_numpy()
    np.testing.assert_allclose(q, heat, atol=1e-6 * 500)
    np.testing.assert_allclose(tracked.tracked_temperature().to_numpy(), reference, atol=1e-8)


def test_pid_recovers_the_injected_heat_within_its_tracking_error():
    building = _building()
    sim = _simulation(building, warmup_days=0, initial_temperature=5.0)
    heat = _square_wave(sim, 3)
    reference = sim.run(free_float=True, heat_input=heat).air_temperature.to_numpy()
    tuning = tune_zone(building, experiment=False, outdoor_temperature=5.0)
    gains = [tuning.gains.scaled(z.volume / tuning.volume) for z in building.zones.values()]
    from thermocal.identification.pid import kernel_coefficients

    tracked = sim.track(reference, method="pid", pid=kernel_coefficients(gains))
    q = tracked.heat.to_numpy()
    error = tracked.tracked_temperature().to_numpy() - reference
    rmse = np.sqrt((error**2).mean(axis=0))
    assert rmse.max() < 0.15  # K
    # over each 3-hour half period the mean heat of the loaded zone is recovered
    halves = q[:, 3].reshape(-1, 36).mean(axis=1)
    truth = heat[:, 3].reshape(-1, 36).mean(axis=1)
    assert np.abs(halves - truth)[1:].max() < 60.0
    others = np.delete(q, 3, axis=1)
    assert np.abs(others[288:]).mean() < 25.0  # W: near zero elsewhere
    assert np.abs(q[288:, 3] - heat[288:, 3]).mean() < 0.2 * 500


def test_ziegler_nichols_eigenvalue_and_experiment_agree_on_a_clinic_zone():
    tuning = tune_zone(generators.clinic(), outdoor_temperature=0.0)
    assert tuning.zone.startswith("Room")
    assert tuning.experiment_gain == pytest.approx(tuning.ultimate_gain, rel=5e-3)
    assert tuning.experiment_period == pytest.approx(tuning.ultimate_period, rel=1e-2)
    below, at, above = tuning.critical_pole_modulus
    assert below < 1.0 < above and at == pytest.approx(1.0, abs=1e-6)
    # the paper's rule diverges at a two-step period; the used gains have margin 1.7
    assert tuning.paper_gain_margin < 1.0
    assert tuning.gain_margin == pytest.approx(1.7, rel=1e-6)


def _sensor_log(building, air: pd.DataFrame, every=1):
    """A wide log of some zones' air temperatures, stamped at the end of each step."""
    log = air.iloc[:, ::every].copy()
    log.index = log.index + pd.Timedelta("5min")
    names = {zone: f"S{i:02d}" for i, zone in enumerate(log.columns)}
    mapping = {"sensors": {sensor: zone for zone, sensor in names.items()}}
    return log.rename(columns=names), mapping


def test_unoccupied_variance_near_zero_with_the_true_envelope_and_grows_when_perturbed():
    nominal = _building()
    truth = nominal.with_parameters(
        {
            "material/R16 insulation/resistance": 2.818 * 0.5,
            "window/Exterior window/u_value": 4.0 * 1.4,
            "infiltration/row 1 west/ach": 0.25 * 2.0,
        }
    )
    sim = _simulation(truth)
    air = sim.run(free_float=True).air_temperature
    log, mapping = _sensor_log(truth, air)
    weather, meta = _weather()
    common = dict(start=START, end=END, method="inverse", settle="1D")
    true_model = identify(truth, weather, meta, log, mapping, **common)
    nominal_model = identify(nominal, weather, meta, log, mapping, **common)
    v_true = true_model.unoccupied_variance()
    v_nominal = nominal_model.unoccupied_variance()
    assert np.sqrt(v_true) < 5.0  # W, for a building losing kilowatts
    assert v_nominal > 100 * v_true
    assert np.sqrt(v_nominal) > 50.0


def test_identify_both_methods_report_and_files(tmp_path):
    building = _building()
    sim = _simulation(building)
    heat = _square_wave(sim, 2, 300.0)
    air = sim.run(free_float=True, heat_input=heat).air_temperature
    log, mapping = _sensor_log(building, air, every=2)
    weather, meta = _weather()
    result = identify(building, weather, meta, log, mapping, start=START, end=END)
    assert result.metric_source == "inverse"
    kinds = result.sources.set_index("zone")["source"]
    # zones without a sensor float by default: simulated with Q_ID = 0, temperature reported
    assert set(kinds) == {"sensor", "float"}
    assert (kinds == "sensor").sum() == len(log.columns)
    floating = list(kinds.index[kinds == "float"])
    assert (result.q_id[floating] == 0.0).all().all()
    assert (result.q_pid[floating] == 0.0).all().all()
    assert list(result.floating_temperature.columns) == floating
    assert result.floating_temperature.notna().all().all()
    stored_zones = {z["zone"]: z for z in result.as_dict()["zones"]}
    assert stored_zones[floating[0]]["treatment"] == "floating"
    assert stored_zones[floating[0]]["source"] == "float"
    assert stored_zones[kinds.index[0]]["treatment"] == "tracked"
    difference = result.method_difference()
    assert difference["building_rms_W"] < difference["building_inverse_std_W"]
    written = result.to_files(tmp_path)
    names = {p.name for p in written}
    assert {"identification.json", "q_id.parquet", "report.html", "building_q_id.png"} <= names
    stored = pd.read_parquet(tmp_path / "q_id.parquet")
    assert "inverse|total" in stored and "pid|total" in stored
    assert not list(tmp_path.glob(".*.tmp"))


def test_occupancy_schedule_of_the_paper():
    times = pd.date_range("2001-01-05 00:00", "2001-01-08 00:00", freq="1h", inclusive="left")
    mask = pd.Series(unoccupied_mask(times), index=times)
    assert mask["2001-01-05 03:00"] and not mask["2001-01-05 04:00"]  # Friday
    assert not mask["2001-01-05 19:00"] and mask["2001-01-05 20:00"]
    assert not mask["2001-01-06 10:00"] and mask["2001-01-06 11:00"]  # Saturday
    assert mask["2001-01-07"].all()  # Sunday
    schedule = OccupancySchedule.from_dict(
        {
            "unoccupied": [{"days": "all", "from": "22:00", "to": "06:00"}],
            "holidays": ["2001-01-05"],
        }
    )
    mask = pd.Series(unoccupied_mask(times, schedule), index=times)
    assert mask["2001-01-05"].all() and not mask["2001-01-07 12:00"]
    with pytest.raises(ThermocalInputError, match="day 'Funday'"):
        OccupancySchedule.from_dict({"unoccupied": [{"days": ["Funday"], "from": 1, "to": 2}]})


def test_unoccupied_variance_is_the_brute_force_variance():
    index = pd.date_range("2001-01-01", periods=3 * 288, freq="5min", tz="UTC")
    rng = np.random.default_rng(0)
    q = pd.DataFrame(rng.normal(size=(len(index), 3)), index=index)
    mask = unoccupied_mask(index) & (index >= index[0] + pd.Timedelta("1D"))
    total = q.sum(axis=1).to_numpy()[mask]
    expected = ((total - total.mean()) ** 2).sum() / len(total)
    assert unoccupied_variance(q) == pytest.approx(expected, rel=1e-12)


def test_bad_input_gets_clear_messages(tmp_path):
    building = _building()
    sim = _simulation(building)
    air = sim.run(free_float=True).air_temperature
    weather, meta = _weather()
    log, mapping = _sensor_log(building, air)
    run = functools.partial(identify, building, weather, meta, start=START, end=END)
    # a sensor mapped to no zone
    extra = log.assign(S99=log.iloc[:, 0])
    with pytest.raises(ThermocalInputError, match="S99.*mapped to no zone"):
        run(extra, mapping)
    # a sensor mapped to a zone that does not exist
    bad = {"sensors": {**mapping["sensors"], "S00": "Room 100"}}
    with pytest.raises(ThermocalInputError, match="Room 100.*not a zone"):
        run(log, bad)
    # a zone with no sensor and no sensored neighbour floats under the neighbour rule (it
    # stopped the run before)
    from thermocal.identification.sensors import mapping_from_dict, zone_sources

    only_one = {"sensors": {"S00": mapping["sensors"]["S00"]}, "unsensed": "neighbour"}
    sources = zone_sources(building, mapping_from_dict(only_one))
    far = [z for z, src in sources.items() if src.kind == "float"]
    assert far and all("no adjacent zone with a sensor" in sources[z].reason for z in far)
    assert {src.kind for src in sources.values()} == {"sensor", "neighbour", "float"}
    # a gap longer than max_gap and no neighbour with data to take over
    gappy = log.copy()
    gappy.iloc[300:500, :] = np.nan
    with pytest.raises(ThermocalInputError, match="longer than max_gap"):
        run(gappy, mapping)
    # a log that does not overlap the period (another year)
    shifted = log.copy()
    shifted.index = shifted.index - pd.Timedelta(days=400)
    with pytest.raises(ThermocalInputError, match="does not overlap"):
        run(shifted, mapping)
    # a sensor in Kelvin
    kelvin = log.copy()
    kelvin["S01"] = kelvin["S01"] + 273.15
    with pytest.raises(ThermocalInputError, match="Kelvin"):
        run(kelvin, mapping)
    # unstable gains that no retuning (gains halved four times) rescues
    with pytest.raises(ThermocalInputError, match="diverges"):
        run(log, mapping, method="pid", gains=PIDGains(1.0e6, 0.0, 0.0))
    # the declared form of a building that declares no load objects, or a misspelt form
    declared = {**mapping, "identified_heat": {"radiant_fraction": "declared"}}
    with pytest.raises(ThermocalInputError, match="declares none: give the IDF file"):
        run(log, declared)
    with pytest.raises(ThermocalInputError, match="a number in \\[0, 1\\] or 'declared'"):
        run(log, mapping, radiant_fraction="declard")
    misspelt = {**mapping, "identified_heat": {"radiant_fraction": "declard"}}
    with pytest.raises(ThermocalInputError, match="number in \\[0, 1\\] \\(or declared"):
        run(log, misspelt)


def test_unsensed_zones_neighbour_rule_per_zone_and_globally():
    building = _building()
    sim = _simulation(building)
    air = sim.run(free_float=True).air_temperature
    log, mapping = _sensor_log(building, air, every=2)
    weather, meta = _weather()
    unsensed = [z for z in building.zones if z not in mapping["sensors"].values()]
    common = dict(start=START, end=END, method="inverse", warmup_days=1)
    # globally: every unsensed zone takes a sensored neighbour's data or floats without one
    glob = identify(building, weather, meta, log, {**mapping, "unsensed": "neighbour"}, **common)
    kinds = glob.sources.set_index("zone")["source"]
    assert "neighbour" in set(kinds[unsensed])
    assert set(kinds[unsensed]) <= {"neighbour", "float"}
    isolated = kinds.index[kinds == "float"]
    reasons = glob.sources.set_index("zone")["reason"]
    assert all("no adjacent zone with a sensor" in reasons[z] for z in isolated)
    # per zone: one zone follows its neighbour, the rest float
    chosen = next(z for z in unsensed if kinds[z] == "neighbour")
    per_zone = {**mapping, "zones": {chosen: {"unsensed": "neighbour"}}}
    one = identify(building, weather, meta, log, per_zone, **common)
    kinds = one.sources.set_index("zone")["source"]
    assert kinds[chosen] == "neighbour"
    assert set(kinds[[z for z in unsensed if z != chosen]]) == {"float"}
    with pytest.raises(ThermocalInputError, match="'float' .* or 'neighbour'"):
        identify(building, weather, meta, log, {**mapping, "unsensed": "nearest"}, **common)


@pytest.mark.parametrize("feedback", ["air", 0.7])
def test_inverse_recovers_a_radiant_heat_with_its_form(feedback):
    """A zone's constant gains, 60 % radiant (on its surfaces through the network's gain
    inputs), sensed as air or a mix: the inverse with the same form returns them exactly; put
    into the air, the identified heat is wrong."""
    import copy

    building = _building()
    zone = list(building.zones)[2]
    loaded = copy.deepcopy(building)
    loaded.zones[zone].internal_gains = 800.0
    loaded.zones[zone].internal_gains_radiative_fraction = 0.6
    forward = _simulation(loaded, warmup_days=0, initial_temperature=5.0).run(free_float=True)
    weight = 1.0 if feedback == "air" else feedback
    reference = (
        weight * forward.air_temperature + (1 - weight) * forward.mean_radiant_temperature
    ).to_numpy()
    sim = _simulation(building, warmup_days=0, initial_temperature=5.0)
    fraction = np.zeros(len(building.zones))
    fraction[2] = 0.6
    tracked = sim.track(reference, method="inverse", feedback=feedback, radiant_fraction=fraction)
    expected = np.zeros(reference.shape)
    expected[:, 2] = 800.0
    np.testing.assert_allclose(tracked.heat.to_numpy(), expected, atol=1e-6 * 800.0)
    np.testing.assert_allclose(tracked.tracked_temperature().to_numpy(), reference, atol=1e-8)
    into_air = sim.track(reference, method="inverse", feedback=feedback).heat.to_numpy()
    assert np.abs(into_air[:, 2] - 800.0).max() > 20.0


def test_inverse_recovers_gains_whose_composition_changes_with_a_per_step_form():
    """800 W radiant all the time plus 500 W into the air every other 3 hours: the radiant
    share changes from 1 to 0.62 and back. With the form given per step the inverse returns
    the total exactly (the run split where the form changes); with one constant fraction (the
    period's mean) it cannot."""
    import copy

    building = _building()
    zone = list(building.zones)[2]
    loaded = copy.deepcopy(building)
    loaded.zones[zone].internal_gains = 800.0
    loaded.zones[zone].internal_gains_radiative_fraction = 1.0
    sim_loaded = _simulation(loaded, warmup_days=0, initial_temperature=5.0)
    heat = _square_wave(sim_loaded, 2)
    reference = sim_loaded.run(free_float=True, heat_input=heat).air_temperature.to_numpy()
    total = 800.0 + heat[:, 2]
    fraction = np.zeros(reference.shape)
    fraction[:, 2] = 800.0 / total
    sim = _simulation(building, warmup_days=0, initial_temperature=5.0)
    tracked = sim.track(reference, method="inverse", radiant_fraction=fraction)
    expected = np.zeros(reference.shape)
    expected[:, 2] = total
    np.testing.assert_allclose(tracked.heat.to_numpy(), expected, atol=1e-6 * 800.0)
    np.testing.assert_allclose(tracked.tracked_temperature().to_numpy(), reference, atol=1e-8)
    constant = sim.track(reference, method="inverse", radiant_fraction=fraction.mean(axis=0))
    assert np.abs(constant.heat.to_numpy()[:, 2] - total).max() > 50.0
    with pytest.raises(ThermocalInputError, match="per-step radiant_fraction must have shape"):
        sim.track(reference, method="inverse", radiant_fraction=fraction[:-1])
    fraction[5, 2] = 1.5
    with pytest.raises(ThermocalInputError, match="in \\[0, 1\\] at every step"):
        sim.track(reference, method="inverse", radiant_fraction=fraction)


def test_long_gap_takes_the_nearest_zone_with_data_through_floating_zones():
    from thermocal.identification.sensors import mapping_from_dict, shared_areas, zone_references

    building = _building()
    sim = _simulation(building)
    air = sim.run(free_float=True).air_temperature
    log, mapping = _sensor_log(building, air, every=2)
    mapping = mapping_from_dict(mapping)
    sensed = set(mapping.sensors.values())
    # a sensed zone whose neighbours all float (no sensor): before, a long gap there stopped
    zone = next(z for z in sorted(sensed) if not set(shared_areas(building, z)) & sensed)
    sensor = next(s for s, z in mapping.sensors.items() if z == zone)
    gappy = log.copy()
    gappy.iloc[300:400, gappy.columns.get_loc(sensor)] = np.nan
    reference, report = zone_references(gappy, building, mapping, sim.times, sim.step_size)
    row = report.substituted.set_index("zone").loc[zone]
    assert row["from_zone"] in sensed and row["from_zone"] not in shared_areas(building, zone)
    assert reference[zone].notna().all()


def test_diverging_pid_zone_is_retuned_or_left_out_under_both():
    building = _building()
    sim = _simulation(building)
    air = sim.run(free_float=True).air_temperature
    log, mapping = _sensor_log(building, air)
    weather, meta = _weather()
    tuning = tune_zone(building, experiment=False, outdoor_temperature=5.0)
    gains = {
        name: tuning.gains.scaled(zone.volume / tuning.volume)
        for name, zone in building.zones.items()
    }
    wild = list(building.zones)[3]
    # the tuned plant: heat into the air, air sensor
    common = dict(start=START, end="2001-01-10", warmup_days=1, radiant_fraction=0.0)
    # 3x the stable gains (margin 1.7 / 3 < 1): unstable; halved once (x1.5, margin 1.13) the
    # loop is stable and the run goes on
    retuned = identify(
        building,
        weather,
        meta,
        log,
        mapping,
        method="both",
        gains={**gains, wild: gains[wild].scaled(3.0)},
        **common,
    )
    assert any("retuned" in note and wild in note for note in retuned.notes)
    assert retuned.q_pid is not None and np.isfinite(retuned.q_pid.to_numpy()).all()
    assert retuned.gains[wild].kp == pytest.approx(1.5 * gains[wild].kp)
    # gains no halving rescues (x1000): under "both" the PID is left out and reported
    hopeless = {**gains, wild: gains[wild].scaled(1000.0)}
    result = identify(
        building, weather, meta, log, mapping, method="both", gains=hopeless, **common
    )
    assert result.q_pid is None and result.q_inverse is not None
    assert any("left out" in note and wild in note for note in result.notes)
    with pytest.raises(ThermocalInputError, match="diverges in 1 zone"):
        identify(building, weather, meta, log, mapping, method="pid", gains=hopeless, **common)


def test_import_notes_summarised_in_a_line_per_kind():
    from thermocal.multizone.simulation import notes_summary

    notes = [f"infiltration 'Zone {i} Infil': schedule 'INFIL-SCH' applied" for i in range(431)]
    notes += ["objects not represented (skipped): Output:Variable (4)", "schedule calendar: 0"]
    line = notes_summary(notes)
    assert line == (
        "433 notes: infiltration (431), objects not represented (1), schedule calendar (1)"
    )
    assert len(line) < 100 and notes_summary([]) == ""


def test_floating_zones_are_simulated_exactly_while_the_others_are_tracked():
    """Every other zone tracked: the floating ones (Q_ID = 0) follow the forward run exactly and
    the heat of the tracked loaded zone is recovered."""
    building = _building()
    sim = _simulation(building, warmup_days=0, initial_temperature=5.0)
    heat = _square_wave(sim, 2)
    forward = sim.run(free_float=True, heat_input=heat)
    tracked = list(range(0, len(building.zones), 2))
    reference = forward.air_temperature.to_numpy()[:, tracked]
    result = sim.track(reference, zones=tracked, method="inverse")
    np.testing.assert_allclose(result.heat.to_numpy(), heat[:, tracked], atol=1e-6 * 500)
    np.testing.assert_allclose(
        result.air_temperature.to_numpy(), forward.air_temperature.to_numpy(), atol=1e-8
    )


def test_each_form_of_the_heat_is_combined_from_two_responses_as_a_direct_solve_gives():
    """The tracked zones' sensed response to their heat, for a radiant fraction and sensor mix
    per zone, is combined from the responses to heat in the air and on the faces (linear in
    the fraction); a direct solve with the form's own distribution gives the same matrix."""
    import scipy.sparse as sp

    building = _building()
    sim = _simulation(building, warmup_days=0)
    net = sim.network
    zones = np.arange(len(building.zones))
    rng = np.random.default_rng(7)
    fraction = rng.uniform(0.0, 1.0, len(zones))
    fraction[0] = 0.0  # a zone whose heat stays in the air
    air_weight = rng.uniform(0.3, 1.0, len(zones))
    form = (tuple(air_weight), tuple(fraction))
    context, g_inverse, (ptr, idx, val) = sim._tracking_context(zones, form, coarse=False)
    columns = np.repeat(np.arange(len(zones)), np.diff(ptr))
    unit = sp.csc_matrix((val, (idx, columns)), shape=(net.n_nodes, len(zones))).toarray()
    response = context.lu.solve(unit)
    area = sim._zone_face_area[zones]
    weights = sp.csr_matrix(
        (net.face_area, (net.face_zone, net.face_node)), shape=(len(zones), net.n_nodes)
    )
    air = response[net.air_node[zones], :]
    mrt = np.asarray(weights @ response) / area[:, None]
    sensed = air_weight[:, None] * air + (1.0 - air_weight[:, None]) * mrt
    np.testing.assert_allclose(g_inverse @ sensed, np.eye(len(zones)), atol=1e-9)
    np.testing.assert_allclose(np.linalg.inv(sensed), g_inverse, rtol=1e-9)
