"""``Simulation.track_heat``, the identified heat without the result frames (a campaign
sample's lean path, issue 22): bit-identical to ``track(...).heat`` in every mode."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from thermocal.demos import buildings as generators
from thermocal.errors import ThermocalInputError
from thermocal.identification.pid import PIDGains, kernel_coefficients
from thermocal.multizone import Simulation

START, END = "2001-01-08", "2001-01-11"


@functools.cache
def _weather():
    from thermocal.demos.retrofit import pvlib_weather_path
    from thermocal.io.weather import read_weather

    return read_weather(pvlib_weather_path())


@functools.cache
def _case():
    """A 12-zone clinic, its forward run with a square wave of heat in zone 3 (references)."""
    building = generators.clinic(12, n_corridors=1, corridor_sections=2)
    weather, meta = _weather()
    sim = Simulation(
        building, weather, meta, step="5min", start=START, end=END, store_surfaces=False,
        warmup_days=1,
    )  # fmt: skip
    n, nz = len(sim.times), len(building.zones)
    heat = np.zeros((n, nz))
    heat[(np.arange(n) // 36) % 2 == 0, 3] = 500.0
    forward = sim.run(free_float=True, heat_input=heat)
    return sim, forward.air_temperature.to_numpy() + 0.3, heat


def _pid(n: int, scale: float = 1.0) -> tuple:
    gains = [PIDGains(kp=200.0 * scale, ki=2.0 * scale, kd=0.0)] * n
    return kernel_coefficients(gains)


def _per_step_fraction(n_steps: int, n_zones: int) -> np.ndarray:
    fraction = np.full((n_steps, n_zones), 0.3)
    fraction[(np.arange(n_steps) // 72) % 2 == 1, :2] = 0.7
    return fraction


CASES = {
    "inverse, air, all zones": lambda n, nz: {},
    "inverse, operative, radiant fraction, every other zone": lambda n, nz: {
        "zones": list(range(0, nz, 2)),
        "feedback": "operative",
        "radiant_fraction": 0.4,
    },
    "inverse, per-step radiant fraction": lambda n, nz: {
        "radiant_fraction": _per_step_fraction(n, nz)
    },
    "inverse, given heat": lambda n, nz: {"heat_input": np.full((n, nz), 50.0)},
    "pid with limits": lambda n, nz: {
        "method": "pid",
        "pid": _pid(nz),
        "limits": (np.full(nz, -2000.0), np.full(nz, 800.0)),
    },
}


@pytest.mark.parametrize("case", list(CASES))
def test_track_heat_is_the_heat_of_track_bit_for_bit(case):
    sim, reference, _ = _case()
    kwargs = CASES[case](*reference.shape)
    columns = kwargs.get("zones", list(range(reference.shape[1])))
    reference = np.ascontiguousarray(reference[:, columns])
    if "radiant_fraction" in kwargs and np.ndim(kwargs["radiant_fraction"]) == 2:
        kwargs["radiant_fraction"] = kwargs["radiant_fraction"][:, columns]
    full = sim.track(reference, **kwargs)
    lean = sim.track_heat(reference, **kwargs)
    assert lean.zones == list(full.heat.columns)
    assert lean.diverged == full.diverged == []
    assert np.array_equal(lean.heat, full.heat.to_numpy())
    # the simulation is left where track leaves it: a second lean run gives the same heat
    assert np.array_equal(sim.track_heat(reference, **kwargs).heat, lean.heat)


def test_track_heat_reports_a_diverging_pid_as_track_does():
    sim, reference, _ = _case()
    nz = reference.shape[1]
    pid = _pid(nz)
    wild = tuple(c.copy() for c in pid)
    for c in wild:
        c[3] *= 1e4
    full = sim.track(reference, method="pid", pid=wild)
    lean = sim.track_heat(reference, method="pid", pid=wild)
    assert full.diverged == lean.diverged == [sim.zone_names[3]]
    assert np.array_equal(np.isnan(lean.heat), np.isnan(full.heat.to_numpy()))
    finite = np.isfinite(lean.heat)
    assert np.array_equal(lean.heat[finite], full.heat.to_numpy()[finite])


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"method": "pid"}, "needs the controller coefficients"),
        ({"method": "bang-bang"}, "method must be"),
        ({"limits": (1.0, 0.0)}, "lower heat limit exceeds"),
    ],
)
def test_track_heat_refuses_what_track_refuses(kwargs, match):
    sim, reference, _ = _case()
    for call in (sim.track, sim.track_heat):
        with pytest.raises(ThermocalInputError, match=match):
            call(reference, **kwargs)
    with pytest.raises(ThermocalInputError, match="reference must have shape"):
        sim.track_heat(reference[:-1])


def test_result_frames_hold_their_own_data():
    """The frames of ``run`` and ``track`` take the loop's arrays without copying (issue 22,
    memory): the caller's heat and reference are still copied, and a second call does not
    write into the first call's frames."""
    sim, reference, heat = _case()
    given = heat.copy()
    first = sim.run(free_float=True, heat_input=given)
    kept = {q: getattr(first, q).to_numpy().copy() for q in ("air_temperature", "heating")}
    given[:] = 12345.0  # the caller reuses its array
    assert not np.any(first.heat_input.to_numpy() == 12345.0)
    sim.run(free_float=True, heat_input=heat * 2.0)  # another run on the same simulation
    for q, values in kept.items():
        np.testing.assert_array_equal(getattr(first, q).to_numpy(), values)
    target = reference.copy()
    tracked = sim.track(target, method="inverse")
    heat_before = tracked.heat.to_numpy().copy()
    target[:] = 0.0
    assert np.all(tracked.reference.to_numpy() == reference)
    sim.track(reference + 1.0, method="inverse")
    np.testing.assert_array_equal(tracked.heat.to_numpy(), heat_before)


def test_the_time_loop_is_compiled_for_writable_arrays_only():
    """Every mode gives the time loop writable arrays, whatever the caller gives: one read-only
    argument (a broadcast view of the PID's coefficients or heat limits did, and a reference or
    heat input from a pandas frame under copy-on-write) compiles the whole loop a second time,
    about 12 s of a first run. Checked on every signature this process has compiled."""
    from numba import types

    from thermocal.multizone import _kernel

    sim, reference, heat = _case()
    nz = reference.shape[1]
    sim.track_heat(reference, method="pid", pid=_pid(nz), limits=(-1e4, 1e4))
    sim.track_heat(reference, method="pid", pid=tuple(float(c[0]) for c in _pid(nz)))
    # a user's read-only arrays (a pandas frame's values under copy-on-write)
    frozen_reference, frozen_heat = reference.copy(), heat.copy()
    frozen_reference.flags.writeable = frozen_heat.flags.writeable = False
    sim.track_heat(frozen_reference)
    sim.run(free_float=True, heat_input=frozen_heat)
    read_only = [
        (i, t)
        for signature in _kernel.run_steps.signatures
        for i, t in enumerate(signature)
        if isinstance(t, types.Array) and not t.mutable
    ]
    assert not read_only
