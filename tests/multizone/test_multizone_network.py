"""Conduction, network assembly and time stepping against analytical solutions."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest
from scipy.linalg import expm

from thermocal.errors import ThermocalInputError
from thermocal.multizone.model import (
    Building,
    Construction,
    Location,
    Material,
    NoMassMaterial,
    Surface,
    Window,
    WindowType,
    Zone,
)
from thermocal.multizone.network import (
    STEFAN_BOLTZMANN,
    NetworkOptions,
    assemble,
    cells_per_layer,
    construction_template,
    doe2_exterior_convection,
    mrt_network_conductances,
    tarp_natural_convection,
)
from thermocal.multizone.simulation import Simulation, steady_state_heat_loss_coefficient


def constant_weather(days=20, temp=0.0, step="1h", wind=0.0):
    """Dark, calm weather at constant temperature with the sky at air temperature."""
    index = pd.date_range("2021-01-01", periods=int(days * 24), freq="1h", tz="UTC+01:00")
    frame = pd.DataFrame(
        {
            "temp_air": temp,
            "ghi": 0.0,
            "dni": 0.0,
            "dhi": 0.0,
            "ghi_infrared": STEFAN_BOLTZMANN * (temp + 273.15) ** 4,
            "wind_speed": wind,
            "wind_direction": 180.0,
            "pressure": 101325.0,
        },
        index=index,
    )
    return frame, {"latitude": 47.4, "longitude": 8.5, "altitude": 0.0}


def box_building(layers, heating=20.0):
    """A 30 m2-per-face cube-like zone whose six faces have the same construction, outdoors."""
    surfaces = [
        Surface("roof", "room", "wall", 30.0, 0, 0),
        Surface("floor", "room", "wall", 30.0, 180, 0),
    ] + [Surface(f"wall {az}", "room", "wall", 30.0, 90, az) for az in (0, 90, 180, 270)]
    return Building(
        name="box",
        location=Location(47.4, 8.5, 0.0),
        materials=layers,
        constructions=[Construction("wall", tuple(m.name for m in layers))],
        zones=[Zone("room", 150.0, 30.0, heating_setpoint=heating)],
        surfaces=surfaces,
    )


def test_steady_state_heat_flow_equals_u_a_dt():
    layers = [
        Material("brick", 0.8, 1800.0, 900.0, 0.25),
        NoMassMaterial("gap", 0.17),
        Material("insulation", 0.04, 30.0, 1400.0, 0.08),
        Material("plaster", 0.7, 1400.0, 1000.0, 0.015),
    ]
    building = box_building(layers)
    h_in, h_out = 3.0, 20.0
    options = NetworkOptions(
        interior_convection="fixed",
        h_interior_fixed=h_in,
        exterior_convection="fixed",
        h_exterior_fixed=h_out,
        exact_sky_longwave=False,
    )
    weather, meta = constant_weather(days=20)
    result = Simulation(building, weather, meta, step="1h", options=options).run()
    # hand computation: interior radiation nets to zero by symmetry (all faces equal), exterior
    # long-wave linearised at the mean outdoor temperature (sky and ground at air temperature)
    h_r = 4.0 * STEFAN_BOLTZMANN * 273.15**3 * 0.9
    r_total = 1 / h_in + 0.25 / 0.8 + 0.17 + 0.08 / 0.04 + 0.015 / 0.7 + 1 / (h_out + h_r)
    expected = 6 * 30.0 * 20.0 / r_total
    heating = result.heating["room"].iloc[-1]
    assert heating == pytest.approx(expected, rel=1e-3)
    assert result.air_temperature["room"].iloc[-1] == pytest.approx(20.0, abs=1e-9)


def _slab_insulated_face(fourier, n_terms=200):
    """Analytical temperature of the insulated face of a slab after a unit step at the other."""
    n = np.arange(n_terms)
    lam = (2 * n + 1) * np.pi / 2
    return float(np.sum(4 / ((2 * n + 1) * np.pi) * (-1.0) ** n * np.exp(-(lam**2) * fourier)))


def _slab_numerical(cells, fourier):
    layer = Material("slab", 1.4, 2000.0, 1000.0, 0.2)
    options = NetworkOptions(cells_per_layer=cells)
    tpl = construction_template([layer], 3600.0, options)
    g, c = tpl.conductance, tpl.capacity
    n = len(c) - 1  # node 0 is held at 0 (Dirichlet), nodes 1..n are free
    k = np.zeros((n, n))
    for j in range(len(g)):
        a, b = j - 1, j  # free-node indices of nodes j and j+1
        k[b, b] += g[j]
        if a >= 0:
            k[a, a] += g[j]
            k[a, b] -= g[j]
            k[b, a] -= g[j]
    time = fourier * layer.thickness**2 / layer.diffusivity
    x = expm(-np.diag(1 / c[1:]) @ k * time) @ np.ones(n)
    return x[-1]


def test_slab_step_response_converges_to_series_solution():
    errors = {}
    for cells in (1, 2, 4, 8, 16):
        err = [abs(_slab_numerical(cells, fo) - _slab_insulated_face(fo)) for fo in (0.1, 0.3, 1.0)]
        errors[cells] = max(err)
    values = [errors[c] for c in (1, 2, 4, 8, 16)]
    assert all(b < a for a, b in zip(values, values[1:], strict=False)), errors
    assert errors[4] / errors[16] > 8  # second order in space
    assert errors[16] < 1e-3


def test_default_criterion_is_accurate_at_the_resolved_time_scale():
    concrete = Material("concrete", 1.4, 2000.0, 1000.0, 0.2)
    step = 900.0
    cells = cells_per_layer(concrete.thickness, concrete.diffusivity, step)
    assert 2 <= cells <= 12
    # error of the insulated-face response at a time scale of six steps .. one day
    worst = 0.0
    for hours in (1.5, 6.0, 24.0):
        fo = concrete.diffusivity * hours * 3600 / concrete.thickness**2
        worst = max(worst, abs(_slab_numerical(cells, fo) - _slab_insulated_face(fo)))
    assert worst < 0.02
    # the criterion refines with thicker layers and shorter time scales, within its bounds
    assert cells_per_layer(0.4, concrete.diffusivity, step) > cells
    assert cells_per_layer(0.2, concrete.diffusivity, 3 * 3600.0) < cells
    assert cells_per_layer(5.0, concrete.diffusivity, step) == 12


def test_air_node_matches_backward_euler_closed_form():
    """A zone without surfaces, coupled by infiltration only: the exact discrete solution."""
    building = Building(
        name="air",
        zones=[Zone("room", 100.0, 40.0, infiltration_ach=2.0)],
    )
    weather, meta = constant_weather(days=2, temp=0.0)
    sim = Simulation(building, weather, meta, step="10min", warmup_days=0, initial_temperature=20.0)
    result = sim.run(free_float=True)
    net = sim.network
    conductance = net.zone_infiltration[0]
    capacity = net.capacity[0]
    dt = 600.0
    k = np.arange(1, 11)
    expected = 20.0 * (1.0 / (1.0 + dt * conductance / capacity)) ** k
    assert np.allclose(result.air_temperature["room"].to_numpy()[:10], expected, rtol=1e-10)


def test_ideal_loads_hold_set_points_exactly_and_step_api_matches_run():
    layers = [Material("timber", 0.14, 650.0, 1200.0, 0.05), Material("wool", 0.04, 20, 840, 0.1)]
    building = box_building(layers, heating=21.0)
    weather, meta = constant_weather(days=3, temp=-5.0, wind=3.0)
    sim = Simulation(building, weather, meta, step="15min", warmup_days=1)
    result = sim.run()
    assert np.allclose(result.air_temperature["room"], 21.0, atol=1e-9)
    assert (result.heating["room"] > 0).all()
    # given heat: the stepping API reproduces run(heat_input=...) step by step
    heat = result.heating[["room"]] * 0.8
    given = sim.run(free_float=True, heat_input=heat)
    sim.reset(free_float=True)
    temps = [sim.step([q]) for q in heat["room"].to_numpy()[:50]]
    assert np.allclose(np.ravel(temps), given.air_temperature["room"].to_numpy()[:50], atol=1e-10)
    assert given.air_temperature["room"].iloc[-1] < 20.0


def test_set_parameters_changes_the_heat_loss():
    layers = [Material("timber", 0.14, 650.0, 1200.0, 0.05), Material("wool", 0.04, 20, 840, 0.1)]
    building = box_building(layers)
    base = steady_state_heat_loss_coefficient(building)
    thicker = steady_state_heat_loss_coefficient(
        building.with_parameters({"material/wool/thickness": 0.2})
    )
    assert thicker < 0.6 * base
    weather, meta = constant_weather(days=2, temp=0.0)
    sim = Simulation(building, weather, meta, step="1h", warmup_days=0)
    q_before = sim.run().heating["room"].iloc[-1]
    sim.set_parameters({"material/wool/thickness": 0.2})
    q_after = sim.run().heating["room"].iloc[-1]
    assert q_after < 0.65 * q_before


def test_heat_loss_coefficient_of_box_by_hand():
    layers = [Material("wool", 0.04, 20.0, 840.0, 0.1)]
    building = box_building(layers)
    options = NetworkOptions(
        interior_convection="fixed",
        h_interior_fixed=2.5,
        exterior_convection="fixed",
        h_exterior_fixed=20.0,
    )
    h_r = 4.0 * STEFAN_BOLTZMANN * 273.15**3 * 0.9
    expected = 6 * 30.0 / (1 / 2.5 + 0.1 / 0.04 + 1 / (20.0 + h_r))
    assert steady_state_heat_loss_coefficient(building, options=options) == pytest.approx(
        expected, rel=1e-9
    )


def test_tarp_and_mrt_coefficients():
    # vertical 1.31 dT^(1/3); warm floor (unstable) > cold floor (stable)
    assert tarp_natural_convection(8.0, 0.0) == pytest.approx(2.62)
    assert tarp_natural_convection(8.0, 1.0) == pytest.approx(9.482 * 2 / 6.238)
    assert tarp_natural_convection(-8.0, 1.0) == pytest.approx(1.81 * 2 / 2.382)
    # two black faces that see only each other (parallel plates): exchange h_b A
    g = mrt_network_conductances(np.array([10.0, 10.0]), np.array([1.0, 1.0]), 5.0)
    assert 1 / (1 / g[0] + 1 / g[1]) == pytest.approx(5.0 * 10.0, rel=1e-6)
    # Carroll factors: equal faces get F = 2, so each face conductance is 2 A h_b
    assert g[0] == pytest.approx(2 * 10.0 * 5.0, rel=1e-6)


def test_doe2_exterior_convection_uses_energyplus_mowitt_terms_and_smooth_glass():
    # EnergyPlus DOE-2 model: h = h_n + R_f (sqrt(h_n^2 + (a V^b)^2) - h_n) with the MoWiTT
    # smooth-surface forced terms a V^b = 3.26 V^0.89 (windward), 3.55 V^0.617 (leeward)
    h_n, wind = 1.5, 4.0
    windward = h_n + 1.67 * (np.hypot(h_n, 3.26 * wind**0.89) - h_n)
    leeward = h_n + 1.67 * (np.hypot(h_n, 3.55 * wind**0.617) - h_n)
    assert doe2_exterior_convection(wind, True, h_natural=h_n) == pytest.approx(windward)
    assert doe2_exterior_convection(wind, False, h_natural=h_n) == pytest.approx(leeward)
    # in a network, glass is "very smooth" (R_f = 1) whatever the opaque roughness option
    layers = [Material("insulation", 0.04, 30.0, 1400.0, 0.1)]
    building = box_building(layers)
    building = Building(
        name="box with window",
        location=building.location,
        materials=layers,
        constructions=building.constructions,
        window_types=[WindowType("double", 2.8, 0.6)],
        zones=building.zones,
        surfaces=building.surfaces,
        windows=[Window("south window", "wall 180", "double", 4.0)],
    )
    net = assemble(building, 900.0, mean_wind_speed=wind)
    local = wind * NetworkOptions().wind_speed_factor
    window = net.ext_names.index("south window")
    wall = net.ext_names.index("wall 180")
    assert net.ext_roughness[window] == 1.0 and net.ext_roughness[wall] == 1.67
    for k, r_f in ((window, 1.0), (wall, 1.67)):
        hn = net.ext_h_natural[k]
        expected = hn + r_f * (
            0.5 * (np.hypot(hn, 3.26 * local**0.89) + np.hypot(hn, 3.55 * local**0.617)) - hn
        )
        assert net.ext_hc0[k] == pytest.approx(expected)


def test_tarp_and_mowitt_exterior_convection_by_hand():
    from thermocal.multizone.network import (
        mowitt_exterior_convection,
        tarp_exterior_convection,
    )

    # EnergyPlus TARP outside: h_n + 2.537 W_f R_f sqrt(P V / A), W_f 1 windward / 0.5 leeward
    h_n, wind, p_over_a = 1.5, 4.0, 0.75
    forced = 2.537 * 1.67 * np.sqrt(0.75 * 4.0)
    windward = tarp_exterior_convection(wind, True, h_natural=h_n, perimeter_over_area=p_over_a)
    leeward = tarp_exterior_convection(wind, False, h_natural=h_n, perimeter_over_area=p_over_a)
    assert windward == pytest.approx(h_n + forced)
    assert leeward == pytest.approx(h_n + 0.5 * forced)
    # MoWiTT: sqrt((0.84 dT^(1/3))^2 + (a V^b)^2); still air leaves the natural part
    assert mowitt_exterior_convection(0.0, True, delta_t=8.0) == pytest.approx(0.84 * 2.0)
    assert mowitt_exterior_convection(wind, False, delta_t=8.0) == pytest.approx(
        np.hypot(1.68, 3.55 * wind**0.617)
    )


@pytest.mark.parametrize("algorithm", ["doe2", "tarp", "mowitt", "simple_combined"])
def test_exterior_convection_follows_each_surface_wind_factor(algorithm):
    """A sheltered wall (local wind 0) keeps only natural convection; the step series of the
    wind-driven part is the algorithm's coefficient at the surface's own wind speed."""
    layers = [Material("insulation", 0.04, 30.0, 1400.0, 0.1)]
    base = box_building(layers)
    building = Building(
        name="box with sheltered north wall",
        location=base.location,
        materials=layers,
        constructions=[Construction("wall", ("insulation",))],
        zones=[Zone("room", 150.0, 30.0, heating_setpoint=20.0)],
        surfaces=[
            dataclasses.replace(s, wind_speed_factor=0.0 if s.name == "wall 0" else 0.5)
            for s in base.surfaces.values()
        ],
    )
    options = NetworkOptions(exterior_convection=algorithm)
    net = assemble(building, 900.0, mean_wind_speed=5.0, options=options)
    sheltered = net.ext_names.index("wall 0")
    exposed = net.ext_names.index("wall 180")
    assert net.ext_wind_factor[sheltered] == 0.0 and net.ext_wind_factor[exposed] == 0.5
    calm = assemble(building, 900.0, mean_wind_speed=0.0, options=options)
    assert net.ext_hc0[sheltered] == pytest.approx(calm.ext_hc0[sheltered])
    assert net.ext_hc0[exposed] > calm.ext_hc0[exposed] + 0.5


def test_window_glass_conductance_ratio_acts_as_a_conductance_in_steady_state():
    from thermocal.multizone.network import window_film_resistance

    # a window whose glass-to-glass conductance is doubled at every temperature loses exactly
    # what a window with half the glass resistance loses (the kernel's lagged correction)
    layers = [Material("insulation", 0.04, 30.0, 1400.0, 0.1)]
    base = box_building(layers)
    r_glass = 1 / 2.0 - window_film_resistance(2.0)
    u_equivalent = 2.0  # the films depend on the U-value: fixed point of U = 1/(R_f(U) + R_g/2)
    for _ in range(100):
        u_equivalent = 1 / (window_film_resistance(u_equivalent) + r_glass / 2)

    def with_window(window_type):
        return Building(
            name="box with window",
            location=base.location,
            materials=layers,
            constructions=base.constructions,
            window_types=[window_type],
            zones=base.zones,
            surfaces=base.surfaces,
            windows=[Window("window", "wall 180", window_type.name, 6.0)],
        )

    doubled = with_window(
        WindowType(
            "w", 2.0, 0.6, glass_conductance_temperatures=(-50, 150), glass_conductance_ratio=(2, 2)
        )
    )
    equivalent = with_window(WindowType("w", u_equivalent, 0.6))
    plain = with_window(WindowType("w", 2.0, 0.6))
    options = NetworkOptions(
        interior_convection="fixed", exterior_convection="fixed", exact_sky_longwave=False
    )
    weather, meta = constant_weather(days=10)
    heating = {
        key: Simulation(b, weather, meta, step="1h", options=options).run().heating["room"].iloc[-1]
        for key, b in (("doubled", doubled), ("equivalent", equivalent), ("plain", plain))
    }
    assert heating["doubled"] == pytest.approx(heating["equivalent"], rel=1e-6)
    assert heating["doubled"] > 1.05 * heating["plain"]


def test_period_must_be_whole_steps_and_warmup_non_negative():
    # [00:00, 00:30) at 1 h steps, or two days at 7 min, used to simulate a longer period silently
    layers = [Material("insulation", 0.04, 30.0, 1400.0, 0.1)]
    building = box_building(layers)
    weather, meta = constant_weather(days=3)
    for start, end, step in (
        ("2021-01-01 00:00", "2021-01-01 00:30", "1h"),
        ("2021-01-01 00:00", "2021-01-03 00:00", "7min"),
        ("2021-01-01 00:03", "2021-01-02 00:03", "5min"),
    ):
        with pytest.raises(ThermocalInputError, match="not a whole number of"):
            Simulation(building, weather, meta, step=step, start=start, end=end)
    sim = Simulation(
        building, weather, meta, step="5min", start="2021-01-01 00:05", end="2021-01-02"
    )
    assert len(sim.times) == 24 * 12 - 1 and sim.times[0].minute == 5
    with pytest.raises(ThermocalInputError, match="warmup_days"):
        Simulation(building, weather, meta, step="1h", warmup_days=-1)


def test_exact_interior_longwave_removes_the_linearisation_temperature():
    # hot steady state (outdoors 60 C, zone cooled to 35 C): faces at different temperatures
    # (ISO 6946 coefficients differ by direction) exchange long-wave radiation; with the exact
    # sigma T^4 correction the result no longer depends on where the matrix part is linearised
    import dataclasses

    layers = [Material("board", 0.2, 800.0, 1000.0, 0.05)]
    building = box_building(layers)
    building = dataclasses.replace(
        building,
        zones={
            "room": dataclasses.replace(
                building.zones["room"], heating_setpoint=None, cooling_setpoint=35.0
            )
        },
    )
    weather, meta = constant_weather(days=10, temp=60.0)

    def cooling(radiant_temperature, exact):
        options = NetworkOptions(
            interior_convection="fixed",
            exterior_convection="fixed",
            exact_sky_longwave=False,
            radiant_temperature=radiant_temperature,
            exact_interior_longwave=exact,
        )
        sim = Simulation(building, weather, meta, step="1h", options=options)
        return sim.run().cooling["room"].iloc[-1]

    exact_low, exact_high = cooling(20.0, True), cooling(50.0, True)
    linear_low, linear_high = cooling(20.0, False), cooling(50.0, False)
    assert exact_low == pytest.approx(exact_high, rel=1e-6)
    assert abs(linear_low - linear_high) > 20 * abs(exact_low - exact_high)
    assert exact_low == pytest.approx(linear_high, rel=1e-3)  # 50 C is close to the face temps


def test_energyplus_convection_algorithms_from_the_idf():
    from thermocal.multizone.idf import IdfImportInfo
    from thermocal.multizone.network import simple_combined_exterior_coefficient

    # EnergyPlus Engineering Reference, Simple Combined: rough 12.49 + 4.065 V + 0.028 V^2
    np.testing.assert_allclose(
        simple_combined_exterior_coefficient([0.0, 4.0], 1.67), [12.49, 12.49 + 16.26 + 0.448]
    )
    np.testing.assert_allclose(simple_combined_exterior_coefficient(2.0, 1.0), 8.23 + 6.66 - 0.144)
    info = IdfImportInfo(source="x.idf", version=(25, 2))
    info.convection = {"inside": "Simple", "outside": "SimpleCombined"}
    options, notes = info.network_options()
    assert (options.interior_convection, options.exterior_convection, notes) == (
        "simple",
        "simple_combined",
        [],
    )
    info.convection = {"inside": "TARP", "outside": "MoWiTT"}
    options, notes = info.network_options()
    assert (options.interior_convection, options.exterior_convection, notes) == (
        "tarp",
        "mowitt",
        [],
    )
    info.convection = {"inside": "AdaptiveConvectionAlgorithm", "outside": "TARP"}
    options, notes = info.network_options()
    assert (options.interior_convection, options.exterior_convection) == ("tarp", "tarp")
    assert len(notes) == 1 and "Inside AdaptiveConvectionAlgorithm approximated" in notes[0]
    info.convection = {"inside": "CeilingDiffuser", "outside": "AdaptiveConvectionAlgorithm"}
    options, notes = info.network_options()
    assert (options.interior_convection, options.exterior_convection) == ("tarp", "tarp")
    assert "CeilingDiffuser is not available: TARP used" in notes[0]
    assert "Outside AdaptiveConvectionAlgorithm approximated by TARP" in notes[1]


def test_approximate_solar_view_factors_match_energyplus_case600():
    """EnergyPlus 25.2 on Case 600FF (FullInteriorAndExterior): the transmitted diffuse of a south
    window first absorbed (alpha 0.6) on E/W 25.0, N 34.5, floor/roof 100.3 W of 285.1 W, the
    south wall and the coplanar windows none ("Surface Inside Face Initial Transmitted Diffuse
    Absorbed Solar Radiation Rate", annual means)."""
    from thermocal.multizone.network import approximate_view_factors

    area = [48.0, 48.0, 21.6, 9.6, 16.2, 16.2, 6.0, 6.0]
    tilt = [180.0, 0.0, 90.0, 90.0, 90.0, 90.0, 90.0, 90.0]
    azimuth = [0.0, 0.0, 0.0, 180.0, 90.0, 270.0, 180.0, 180.0]
    f = approximate_view_factors(area, tilt, azimuth)
    np.testing.assert_allclose(f.sum(axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose(np.array(area)[:, None] * f, (np.array(area)[:, None] * f).T)
    expected = np.array([100.3, 100.3, 34.5, 0.0, 25.0, 25.0, 0.0, 0.0]) / 285.1
    np.testing.assert_allclose(f[6], expected, atol=0.001)


def test_solar_absorbed_by_a_single_layer_window_sits_at_the_middle_of_the_layer():
    """One layer between the window's two nodes (EnergyPlus' simple-glazing equivalent layer):
    its absorbed solar goes half to each face, so that the inward-flowing fraction is
    (R_out + R_layer / 2) / R_total as EnergyPlus has it; panes of a double glazing keep their
    own faces."""
    from thermocal.multizone.network import _window_back_absorptance
    from thermocal.multizone.simulation import _window_inputs

    angles = (0.0, 30.0, 60.0, 90.0)
    single = WindowType(
        "simple-glazing layer",
        1.4,
        0.55,
        solar_transmittance=0.45,
        pane_absorptances=(0.2,),
        incidence_angles=angles,
        relative_transmittance=(1.0, 0.98, 0.83, 0.0),
    )
    double = WindowType(
        "double",
        2.7,
        0.79,
        solar_transmittance=0.75,
        pane_absorptances=(0.064, 0.052),
        incidence_angles=angles,
        relative_transmittance=(1.0, 0.98, 0.83, 0.0),
    )
    irradiance = {
        "poa_direct": np.array([500.0, 0.0]),
        "poa_sky_diffuse": np.array([100.0, 50.0]),
        "poa_ground_diffuse": np.array([0.0, 0.0]),
        "aoi": np.array([0.0, 45.0]),
    }
    _, _, outer, inner = _window_inputs(single, irradiance, 2)
    absorbed = 0.2 * 500.0 + single.diffuse_pane_absorptance_values[0] * 100.0
    np.testing.assert_allclose([outer[0], inner[0]], [0.5 * absorbed, 0.5 * absorbed])
    _, _, outer, inner = _window_inputs(double, irradiance, 2)
    assert outer[0] == pytest.approx(0.064 * 500 + double.diffuse_pane_absorptance_values[0] * 100)
    assert inner[0] == pytest.approx(0.052 * 500 + double.diffuse_pane_absorptance_values[1] * 100)
    back = single.diffuse_pane_absorptance_values[0]
    assert _window_back_absorptance(single) == pytest.approx((0.5 * back, 0.5 * back))


def test_shading_hides_the_sky_in_the_long_wave_and_radiant_gains_follow_area_emissivity():
    """A shaded receiver's sky view factor is multiplied by its isotropic sky shading ratio
    (EnergyPlus' ViewFactorSkyIR x DifShdgRatioIsoSky), the rest exchanged at the air
    temperature; radiant gains are shared by area x thermal absorptance."""
    from thermocal.demos import buildings as generators
    from thermocal.multizone.network import assemble, radiant_gain_shares

    building = generators.clinic(12, n_corridors=1, corridor_sections=2)
    plain = assemble(building, 300.0)
    name = next(n for n, win in zip(plain.ext_names, plain.ext_is_window, strict=True) if win)
    shaded = assemble(building, 300.0, sky_view_ratio={name: 0.4})
    i = plain.ext_names.index(name)
    assert shaded.ext_view_sky[i] == pytest.approx(0.4 * plain.ext_view_sky[i])
    assert shaded.ext_view_sky[i] + shaded.ext_view_air[i] == pytest.approx(1.0)
    others = np.arange(len(plain.ext_names)) != i
    np.testing.assert_array_equal(shaded.ext_view_sky[others], plain.ext_view_sky[others])
    shares = radiant_gain_shares([0, 0, 1], [10.0, 30.0, 5.0], [0.9, 0.6, 0.9], 2)
    np.testing.assert_allclose(shares, [9.0 / 27.0, 18.0 / 27.0, 1.0])
    assert plain.face_radiant_share.sum() == pytest.approx(len(building.zones))


def test_grey_exchange_factors_and_the_pairwise_interior_long_wave_option():
    """Two parallel grey plates exchange with 1 / (1/eps1 + 1/eps2 - 1); the "view_factors"
    option links every pair of faces of a zone except co-planar ones (a wall and its window)."""
    from thermocal.demos import buildings as generators
    from thermocal.multizone.network import (
        NetworkOptions,
        assemble,
        grey_exchange_factors,
    )

    plates = grey_exchange_factors(np.array([[0.0, 1.0], [1.0, 0.0]]), np.array([0.9, 0.6]))
    assert plates[0, 1] == pytest.approx(1.0 / (1.0 / 0.9 + 1.0 / 0.6 - 1.0))
    assert plates[0, 0] == 0.0 and plates[1, 0] == pytest.approx(plates[0, 1])
    building = generators.clinic(12, n_corridors=1, corridor_sections=2)
    star = assemble(building, 300.0)
    pairs = assemble(
        building, 300.0, options=NetworkOptions(interior_longwave_exchange="view_factors")
    )
    assert len(star.lw_pair_g) == 0 and (star.face_mrt_node >= 0).any()
    assert len(pairs.lw_pair_g) > 0 and (pairs.face_mrt_node < 0).all()
    assert pairs.n_nodes == star.n_nodes - int((star.mrt_node >= 0).sum())
    window = int(np.flatnonzero(pairs.face_is_window)[0])
    host = pairs.face_names.index(pairs.face_names[window].rsplit(" window", 1)[0])
    conductance = {}
    for a, b, g in zip(pairs.lw_pair_a, pairs.lw_pair_b, pairs.lw_pair_g, strict=True):
        if pairs.face_node[window] in (a, b):
            conductance[int(b if a == pairs.face_node[window] else a)] = g
    # the window does not see its own wall: only inter-reflections (emissivity 0.9) link them
    assert conductance[int(pairs.face_node[host])] < 0.05 * max(conductance.values())
    with pytest.raises(ThermocalInputError, match="interior_longwave_exchange"):
        assemble(building, 300.0, options=NetworkOptions(interior_longwave_exchange="bogus"))


@pytest.mark.parametrize("algorithm", ["doe2", "tarp"])
def test_exterior_natural_convection_at_the_face_temperature(algorithm):
    """In still air the DOE-2 and TARP outside coefficients reduce to TARP's natural convection
    at the face's own difference from the air (EnergyPlus' ``CalcASHRAETARPNatural`` with the
    outside face temperature), not at a nominal 3 K: a poorly insulated box held at 20 C in 0 C
    air, its faces 8-10 K above the air, loses what the per-face balance solved by hand gives."""
    from scipy.optimize import brentq

    layers = [Material("concrete", 1.4, 2000.0, 1000.0, 0.1)]
    building = box_building(layers)
    h_in = 8.0
    options = NetworkOptions(
        interior_convection="fixed",
        h_interior_fixed=h_in,
        interior_longwave=False,
        exterior_convection=algorithm,
        exact_sky_longwave=False,
    )
    weather, meta = constant_weather(days=10, wind=0.0)
    result = Simulation(building, weather, meta, step="1h", options=options).run()
    h_r = 4.0 * STEFAN_BOLTZMANN * 273.15**3 * 0.9  # sky and ground at the air temperature
    r_in = 1 / h_in + 0.1 / 1.4
    expected = 0.0
    for surface in building.surfaces.values():
        cos_up = np.cos(np.radians(surface.tilt))

        def balance(ts, cos_up=cos_up):
            h_c = float(tarp_natural_convection(ts, cos_up))
            return (20.0 - ts) / r_in - (h_c + h_r) * ts

        ts = brentq(balance, 0.0, 20.0)
        expected += surface.area * (20.0 - ts) / r_in
    assert result.heating["room"].iloc[-1] == pytest.approx(expected, rel=2e-3)


# ----------------------------------------------------------------------------------------------
# the assembly's blocks of links (issue 22: a calibration sample's re-assembly)
# ----------------------------------------------------------------------------------------------


def _one_at_a_time(links):
    """The triplets of links added one at a time, as ``assemble``'s ``link`` adds them."""
    rows, cols, vals = [], [], []
    for i, j, g in links:
        rows.extend((i, j, i, j))
        cols.extend((i, j, j, i))
        vals.extend((g, g, -g, -g))
    return rows, cols, vals


def test_links_added_as_blocks_keep_the_order_of_one_at_a_time():
    from thermocal.multizone.network import _Triplets

    rng = np.random.default_rng(3)
    first = [(int(a), int(b), float(g)) for a, b, g in zip(*rng.integers(0, 9, (2, 5)),
                                                           rng.random(5), strict=True)]  # fmt: skip
    block = rng.integers(0, 9, (2, 7))
    block_g = rng.random(7)
    last = (4, 2, 0.25)
    entries = _Triplets()
    for i, j, g in first:
        entries.rows.extend((i, j, i, j))
        entries.cols.extend((i, j, j, i))
        entries.vals.extend((g, g, -g, -g))
    entries.add_links(block[0], block[1], block_g)
    entries.vals.append(0.5)  # a single boundary entry
    entries.rows.append(last[0])
    entries.cols.append(last[0])
    entries.add_links([last[0]], [last[1]], [last[2]], before_pending=True)
    vals, (rows, cols) = entries.arrays()
    expected = _one_at_a_time(first + list(zip(*block.tolist(), block_g.tolist(), strict=True)))
    expected_last = _one_at_a_time([last])
    assert rows.tolist() == expected[0] + expected_last[0] + [last[0]]
    assert cols.tolist() == expected[1] + expected_last[1] + [last[0]]
    assert vals.tolist() == expected[2] + expected_last[2] + [0.5]


@pytest.mark.parametrize("conduction", ["full", "reduced"])
def test_chain_links_of_many_surfaces_are_each_template_link_times_its_area(conduction):
    from thermocal.multizone.network import _chain_links

    options = NetworkOptions(conduction=conduction)
    wall = [Material("brick", 0.8, 1800.0, 900.0, 0.2), NoMassMaterial("film", 0.5),
            Material("wool", 0.04, 30.0, 1000.0, 0.1)]  # fmt: skip
    slab = [Material("concrete", 1.8, 2300.0, 900.0, 0.25)]
    templates = [construction_template(layers, 300.0, options) for layers in (wall, slab)]
    chains = [(templates[0], 4, 12.5), (templates[1], 40, 3.0), (templates[0], 90, 0.7)]
    i, j, g = _chain_links(chains)
    expected = [
        (first + a, first + b, c * area) for tpl, first, area in chains for a, b, c in tpl.links
    ]
    assert len(expected) > 6
    assert i.tolist() == [e[0] for e in expected]
    assert j.tolist() == [e[1] for e in expected]
    assert g.tolist() == [e[2] for e in expected]
    empty = _chain_links([])
    assert all(len(a) == 0 for a in empty)


def test_zone_members_are_each_zones_faces_in_ascending_order():
    from thermocal.multizone.network import _zone_members

    face_zone = np.array([2, 0, 2, 3, 0, 2, 3, 3, 0, 5])
    members = _zone_members(face_zone, 7)
    assert len(members) == 7
    for z in range(7):
        assert members[z].tolist() == np.flatnonzero(face_zone == z).tolist()
