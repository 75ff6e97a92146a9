"""Reduced-order conduction models (``NetworkOptions.conduction = "reduced"``) against truths we
did not make: the transfer-matrix (quadrupole) admittance of layered walls, the series solution
of a slab's step response, and the finite-difference model they replace."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from thermocal.demos.buildings import single_family_house
from thermocal.errors import ThermocalInputError
from thermocal.multizone import conduction_reduction as cr
from thermocal.multizone.model import Material, NoMassMaterial
from thermocal.multizone.network import NetworkOptions, assemble, construction_template

CONCRETE = Material("concrete", 1.4, 2300.0, 1000.0, 0.20)
BRICK = Material("brick", 0.7, 1800.0, 900.0, 0.10)
INSULATION = Material("insulation", 0.04, 30.0, 1400.0, 0.10)
GAP = NoMassMaterial("gap", 0.18)
PLASTER = Material("plaster", 0.5, 1300.0, 1000.0, 0.015)


def transfer_matrix_admittance(layers, omega):
    """Exact surface admittance ``Y(i w)`` of a layered wall by the transfer-matrix method
    (Carslaw and Jaeger 1959; Pipes 1957) [W/(m2 K)], shape (n_w, 2, 2)."""
    out = np.empty((len(omega), 2, 2), dtype=complex)
    for j, w in enumerate(omega):
        m = np.eye(2, dtype=complex)
        for layer in layers:
            if isinstance(layer, Material):
                gamma = np.sqrt(1j * w / layer.diffusivity)
                x = gamma * layer.thickness
                k_gamma = layer.conductivity * gamma
                layer_m = np.array(
                    [[np.cosh(x), np.sinh(x) / k_gamma], [k_gamma * np.sinh(x), np.cosh(x)]]
                )
            else:
                layer_m = np.array([[1.0, layer.resistance], [0.0, 1.0]])
            m = m @ layer_m
        a, b, d = m[0, 0], m[0, 1], m[1, 1]
        out[j] = np.array([[d / b, -1.0 / b], [-1.0 / b, a / b]])
    return out


def _fine(layers, cells=30):
    tpl = construction_template(layers, 300.0, NetworkOptions(cells_per_layer=cells))
    return cr.chain_matrices(tpl.conductance, tpl.capacity)


@pytest.mark.parametrize(
    "layers", [[CONCRETE], [BRICK, INSULATION, CONCRETE], [BRICK, GAP, INSULATION, PLASTER]]
)
def test_reduced_wall_matches_transfer_matrix_admittance(layers):
    """A fine finite-difference wall (30 cells per layer) reduced at 1e-3 K/K keeps the exact
    surface response within 2e-3 K/K from an hour to a year, with a handful of states."""
    k, c = _fine(layers)
    reduced = cr.reduce_construction(-np.diag(k, 1), c, 300.0, 1e-3)
    omega = np.logspace(np.log10(2 * np.pi / cr.YEAR), np.log10(2 * np.pi / 3600.0), 60)
    exact = transfer_matrix_admittance(layers, omega)
    s = 1j * omega
    y_fd = cr.surface_admittance(k, c, s)
    y_red = cr.surface_admittance(reduced.conductance, reduced.capacity, s)
    fd_error = cr.reduction_error(exact, y_fd)
    red_error = cr.reduction_error(exact, y_red)
    assert fd_error < 1e-2, fd_error  # the finite-difference reference itself
    assert red_error < 2e-3 + fd_error, (red_error, fd_error, reduced.n_states)
    assert reduced.n_states <= 16 and reduced.n_states < (len(c) - 2) / 3, reduced.n_states
    # steady state exact: the transmittance at zero frequency is 1 / R
    resistance = sum(
        layer.thickness / layer.conductivity if isinstance(layer, Material) else layer.resistance
        for layer in layers
    )
    y0 = cr.surface_admittance(reduced.conductance, reduced.capacity, [0.0])[0]
    np.testing.assert_allclose(-y0[0, 1].real, 1.0 / resistance, rtol=1e-10)
    # and without the states that the tolerance asks for it would fail
    if reduced.n_states > 0:
        k_r, c_r = cr.balanced_reduction(k, c, reduced.n_states - 1)
        assert cr.reduction_error(exact, cr.surface_admittance(k_r, c_r, s)) > 2e-3


def _series_insulated_face(fourier, n_terms=200):
    """Series solution: temperature of the insulated face of a slab initially at 1 whose other
    face is held at 0 from t = 0 (Carslaw and Jaeger 1959, 3.3)."""
    n = np.arange(n_terms)
    lam = (2 * n + 1) * np.pi / 2
    return float(np.sum(4 / ((2 * n + 1) * np.pi) * (-1.0) ** n * np.exp(-(lam**2) * fourier)))


def test_reduced_slab_step_response_matches_series_solution():
    """Unit step on one face of a slab, the other face insulated: the reduced model of a
    40-cell slab follows the series solution within 3e-3 K with a quarter of the states."""
    slab = Material("slab", 1.4, 2000.0, 1000.0, 0.2)
    k, c = _fine([slab], cells=40)
    reduced = cr.reduce_construction(-np.diag(k, 1), c, 300.0, 1e-3)
    k_r, c_r = reduced.conductance, reduced.capacity
    free = np.arange(1, len(c_r))  # node 0 held at 1 K from t = 0, the rest starts at 0
    a = -k_r[np.ix_(free, free)] / c_r[free, None]
    forcing = -k_r[free, 0] / c_r[free]
    found = {}
    for fourier in (0.05, 0.1, 0.3, 1.0):
        t = fourier * slab.thickness**2 / slab.diffusivity
        x = np.linalg.solve(a, (expm(a * t) - np.eye(len(free))) @ forcing)
        found[fourier] = x[-1] - (1.0 - _series_insulated_face(fourier))
    assert max(abs(v) for v in found.values()) < 3e-3, found
    assert reduced.n_states <= 10 < len(c) - 2, reduced.n_states


@pytest.mark.parametrize(
    "layers", [[CONCRETE], [BRICK, INSULATION, CONCRETE], [PLASTER, GAP, PLASTER]]
)
def test_reduced_block_is_a_passive_network_with_uniform_steady_state(layers):
    tpl = construction_template(layers, 300.0, NetworkOptions(conduction="reduced"))
    k_r = tpl.matrix
    assert k_r is not None and len(tpl.capacity) <= tpl.n_full
    np.testing.assert_allclose(k_r, k_r.T, atol=0)
    np.testing.assert_allclose(k_r.sum(axis=1), 0.0, atol=1e-9 * np.abs(k_r).max())
    assert np.all(tpl.capacity >= 0) and np.all(tpl.capacity[1:-1] > 0)
    assert np.linalg.eigvalsh(k_r).min() > -1e-9 * np.abs(k_r).max()  # positive semi-definite
    # the two surface nodes keep the finite-difference surface capacities
    full = construction_template(layers, 300.0, NetworkOptions())
    assert tpl.capacity[0] == full.capacity[0] and tpl.capacity[-1] == full.capacity[-1]
    assert tpl.resistance == full.resistance


def test_reduction_error_is_measured_against_the_finite_difference_model():
    """The chosen state count is the smallest within the tolerance at the time step's
    frequencies, and the error measure sees a wrong model."""
    tpl = construction_template([BRICK, INSULATION, CONCRETE], 300.0, NetworkOptions())
    k, c = cr.chain_matrices(tpl.conductance, tpl.capacity)
    s = cr.backward_euler_frequencies(300.0)
    y_full = cr.surface_admittance(k, c, s)
    reduced = cr.reduce_construction(tpl.conductance, tpl.capacity, 300.0, 1e-3)
    assert reduced.error <= 1e-3
    assert cr.reduction_error(
        y_full, cr.surface_admittance(reduced.conductance, reduced.capacity, s)
    ) == pytest.approx(reduced.error, rel=1e-9)
    fewer = cr.balanced_reduction(k, c, reduced.n_states - 1)
    assert cr.reduction_error(y_full, cr.surface_admittance(*fewer, s)) > 1e-3
    wrong_capacity = reduced.capacity * np.r_[1.0, np.full(len(reduced.capacity) - 2, 1.2), 1.0]
    assert (
        cr.reduction_error(y_full, cr.surface_admittance(reduced.conductance, wrong_capacity, s))
        > 1e-2
    )


def test_reduced_house_simulation_matches_finite_difference():
    """The same house and weather, full and reduced conduction: fewer nodes, the zone air and
    interior surface temperatures within 0.05 K over two weeks of January at 15 min."""
    import pandas as pd

    building = single_family_house()
    times = pd.date_range("2023-01-01", periods=24 * 21, freq="1h", tz="UTC")
    hours = np.arange(len(times))
    weather = pd.DataFrame(
        {
            "temp_air": 2.0 + 6.0 * np.sin(2 * np.pi * (hours - 9) / 24),
            "ghi": np.clip(400 * np.sin(2 * np.pi * (hours - 6) / 24), 0, None),
            "dni": np.clip(500 * np.sin(2 * np.pi * (hours - 6) / 24), 0, None),
            "dhi": np.clip(100 * np.sin(2 * np.pi * (hours - 6) / 24), 0, None),
            "wind_speed": 3.0,
            "relative_humidity": 70.0,
            "pressure": 101325.0,
        },
        index=times,
    )
    from thermocal.multizone.simulation import Simulation

    results = {}
    nodes = {}
    for conduction in ("full", "reduced"):
        sim = Simulation(
            building,
            weather,
            {"latitude": 48.0, "longitude": 11.0, "altitude": 500.0},
            step="15min",
            start="2023-01-08",
            end="2023-01-22",
            options=NetworkOptions(conduction=conduction),
            warmup_days=7,
        )
        nodes[conduction] = sim.network.n_nodes
        results[conduction] = sim.run(free_float=True)
    assert nodes["reduced"] < nodes["full"], nodes
    air = results["reduced"].air_temperature - results["full"].air_temperature
    surf = results["reduced"].surface_temperature - results["full"].surface_temperature
    assert np.abs(air.to_numpy()).max() < 0.05, np.abs(air.to_numpy()).max()
    assert np.abs(surf.to_numpy()).max() < 0.05, np.abs(surf.to_numpy()).max()
    swing = float(np.ptp(results["full"].air_temperature.to_numpy()))
    assert swing > 2.0  # the comparison is not of two constant series


def test_bad_conduction_options_are_named():
    with pytest.raises(ThermocalInputError, match="conduction must be 'full' or 'reduced'"):
        NetworkOptions(conduction="modal")
    with pytest.raises(ThermocalInputError, match="conduction_tolerance must be a positive"):
        NetworkOptions(conduction="reduced", conduction_tolerance=0.0)


def test_full_conduction_is_unchanged_by_default():
    building = single_family_house()
    net = assemble(building, 900.0)
    assert NetworkOptions().conduction == "full"
    tpl = construction_template([CONCRETE], 900.0, NetworkOptions())
    assert tpl.matrix is None and len(tpl.capacity) == tpl.n_full
    assert net.n_nodes > 0
