"""Ziegler-Nichols tuning of the identification PID on one zone, by experiment and exactly.

The paper's experiment (eq. 9 and its Fig. 3): integral and derivative gains at zero, constant
outdoor temperature, a step in the reference, the proportional gain raised until the zone
temperature oscillates with constant amplitude; that gain is the ultimate gain ``Ku`` and the
oscillation's period the ultimate period ``Pu``. :func:`ultimate_gain_by_experiment` does it by
bisection on simulated oscillations (growing or decaying).

The loop is linear (the network's matrix part; the lagged explicit corrections are small), so
``Ku`` also follows exactly from the discrete closed loop: with
``x[k+1] = A^-1 (C/dt x[k] + e q[k])`` (backward Euler of the network, ``A = C/dt + K``), the
tracked temperature ``y[k] = c x[k]`` and the
proportional controller ``q[k] = Kp (r - y[k])`` (it sees the temperature at the end of the
previous step), the closed-loop poles are the open-loop poles moved by the rank-one feedback; a
pole crosses the unit circle when ``1 + Kp G(z) = 0`` on ``|z| = 1`` with
``G(z) = c (z A - C/dt)^-1 e``. :func:`ultimate_gain_exact` finds the first frequency where
``G`` is real and negative (phase crossover) and ``Ku = -1 / G``; :func:`critical_pole` computes
the closed-loop eigenvalue nearest to that point of the unit circle (ARPACK, shift-invert with a
Sherman-Morrison rank-one solve), whose modulus crosses 1 at ``Ku``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.sparse as sp
from scipy.optimize import brentq
from scipy.sparse.linalg import LinearOperator, eigs, splu

from thermocal.errors import ThermocalInputError
from thermocal.identification.pid import PIDGains, ziegler_nichols


@dataclass
class LinearLoopPlant:
    """Discrete linear plant of one zone: its heat -> its tracked temperature.

    Parameters
    ----------
    matrix : sparse (n, n)
        Backward-Euler system matrix ``A = C/dt + K`` [W/K].
    capacity_dt : ndarray (n,)
        ``C / dt`` per node [W/K].
    input_node : int
        Node receiving the heat (the zone air).
    output : ndarray (n,)
        Weights of the tracked temperature (air: a unit vector; operative: half air, half the
        area-weighted interior surfaces) [-].
    ts : float [s]
        Step (sampling time).
    input_weights : ndarray (n,), optional
        Share of the heat entering each node [-] (a radiant part on the zone's surfaces);
        default all into ``input_node``.
    """

    matrix: sp.spmatrix
    capacity_dt: np.ndarray
    input_node: int
    output: np.ndarray
    ts: float
    input_weights: np.ndarray | None = None

    @property
    def input_vector(self) -> np.ndarray:
        """``e``: the heat's share per node [-]."""
        if self.input_weights is not None:
            return np.asarray(self.input_weights, dtype=float)
        e = np.zeros(self.matrix.shape[0])
        e[self.input_node] = 1.0
        return e

    def frequency_response(self, z: complex) -> complex:
        """``G(z) = c (z A - C/dt)^-1 e`` [K/W]."""
        system = (z * self.matrix - sp.diags(self.capacity_dt)).tocsc().astype(complex)
        rhs = self.input_vector.astype(complex)
        return complex(self.output @ splu(system).solve(rhs))


def ultimate_gain_exact(
    frequency_response: Callable[[complex], complex],
    ts: float,
    *,
    n_grid: int = 48,
    grid: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[float, float, float]:
    """Ultimate gain and period from the discrete frequency response (phase crossover).

    Parameters
    ----------
    frequency_response : callable
        ``G(z)`` of the plant seen by the controller (delay included) [K/W].
    ts : float [s]
        Sampling time.
    n_grid : int
        Frequencies of the initial scan in (0, pi] (log-spaced, then refined by Brent's method).
    grid : (omegas, values), optional
        A scan already computed (frequencies increasing to pi, ``G`` there).

    Returns
    -------
    ultimate_gain : float [W/K]
    ultimate_period : float [s]
    omega : float [rad/sample]
        Frequency of the crossover.
    """
    if grid is None:
        omegas = np.pi * np.logspace(-4, 0, n_grid)
        values = np.array([frequency_response(np.exp(1j * w)) for w in omegas])
    else:
        omegas, values = grid
    for i in range(len(omegas) - 1):
        a, b = values[i].imag, values[i + 1].imag
        if a == 0.0 or a * b < 0.0:
            w = (
                omegas[i]
                if a == 0.0
                else brentq(
                    lambda w: frequency_response(np.exp(1j * w)).imag,
                    omegas[i],
                    omegas[i + 1],
                    xtol=1e-12,
                )
            )
            g = frequency_response(np.exp(1j * w))
            if g.real < 0:
                return -1.0 / g.real, 2.0 * np.pi / w * ts, float(w)
    g = values[-1]
    if g.real < 0:  # crossover at the Nyquist frequency: period of two steps
        return -1.0 / g.real, 2.0 * ts, float(np.pi)
    raise ThermocalInputError(
        "Ziegler-Nichols: the loop has no phase crossover (it does not oscillate for any "
        "proportional gain); give the PID gains explicitly"
    )


def loop_gain_margin(
    controller: Callable[[np.ndarray], np.ndarray],
    omegas: np.ndarray,
    plant_response: np.ndarray,
) -> float:
    """Gain margin of the loop ``H(z) G(z)`` from its frequency response on a grid [-].

    The smallest ``-1 / Re L`` over the phase crossovers (sign changes of ``Im L`` with
    ``Re L < 0``, linearly interpolated, and the Nyquist frequency); ``inf`` without crossover.
    A margin below 1 means an unstable closed loop.

    Parameters
    ----------
    controller : callable
        ``H(z)`` [W/K], vectorised.
    omegas : ndarray [rad/sample]
        Increasing frequencies in (0, pi], the last one pi.
    plant_response : ndarray (complex) [K/W]
        ``G(exp(i omega))`` on ``omegas``.
    """
    loop = controller(np.exp(1j * omegas)) * plant_response
    margins = []
    for i in range(len(loop) - 1):
        a, b = loop[i].imag, loop[i + 1].imag
        if a * b < 0.0 or b == 0.0:
            t = a / (a - b) if a != b else 1.0
            real = loop[i].real + t * (loop[i + 1].real - loop[i].real)
            if real < 0:
                margins.append(-1.0 / real)
    if np.isclose(omegas[-1], np.pi) and loop[-1].real < 0:
        margins.append(-1.0 / loop[-1].real)
    return float(min(margins)) if margins else float("inf")


def critical_pole(plant: LinearLoopPlant, gain: float, omega: float) -> complex:
    """Closed-loop eigenvalue nearest ``exp(i omega)`` under proportional gain ``gain`` [W/K].

    The closed loop is ``M - gain A^-1 e c`` with ``M = A^-1 C/dt``; shift-invert ARPACK at
    ``sigma = exp(i omega)`` with ``(M_cl - sigma I)^-1 v = (S - gain e c)^-1 A v``,
    ``S = C/dt - sigma A``, solved by one sparse LU of ``S`` and the Sherman-Morrison formula.
    """
    sigma = np.exp(1j * omega)
    a = plant.matrix.tocsc()
    n = a.shape[0]
    a_lu = splu(a)
    s_lu = splu((sp.diags(plant.capacity_dt) - sigma * a).tocsc().astype(complex))
    e = plant.input_vector.astype(complex)
    s_inv_e = s_lu.solve(e)
    c = plant.output
    denominator = 1.0 - gain * (c @ s_inv_e)

    def closed_loop(v):
        return _apply_closed_loop(a_lu, plant, gain, c, np.asarray(v, dtype=complex).ravel())

    def shift_invert(v):
        v = np.asarray(v, dtype=complex).ravel()
        av = a @ v
        w = s_lu.solve(av)
        return w + gain * s_inv_e * (c @ w) / denominator

    operator = LinearOperator((n, n), matvec=closed_loop, dtype=complex)
    inverse = LinearOperator((n, n), matvec=shift_invert, dtype=complex)
    values = eigs(operator, k=1, sigma=sigma, OPinv=inverse, which="LM", return_eigenvectors=False)
    return complex(values[0])


def _apply_closed_loop(a_lu, plant, gain, c, v):
    """``(A^-1 C/dt - gain A^-1 e c) v`` for complex ``v``."""
    rhs = plant.capacity_dt * v
    rhs = rhs.astype(complex)
    rhs -= gain * (c @ v) * plant.input_vector
    return a_lu.solve(rhs.real) + 1j * a_lu.solve(rhs.imag)


def oscillation_growth(values: np.ndarray) -> float:
    """Ratio of the oscillation amplitude in the last third to the middle third [-].

    The amplitude is the largest step-to-step change, which removes the slow drift of a step
    response; > 1 means a growing oscillation (unstable loop), < 1 a decaying one.
    """
    values = np.asarray(values, dtype=float)
    if not np.isfinite(values).all():  # the run diverged (stopped by the kernel)
        return float("inf")
    change = np.abs(np.diff(values))
    n = len(change)
    middle = change[n // 3 : 2 * n // 3].max()
    last = change[2 * n // 3 :].max()
    if middle == 0.0:
        return 0.0
    return float(last / middle)


def oscillation_period(values: np.ndarray, ts: float) -> float:
    """Period of the dominant oscillation of the second half of ``values`` [s].

    Peak of the periodogram of the step-to-step changes, refined by parabolic interpolation.
    """
    change = np.diff(np.asarray(values, dtype=float))
    tail = change[len(change) // 2 :]
    tail = tail - tail.mean()
    n = len(tail)
    spectrum = np.abs(np.fft.rfft(tail * np.hanning(n))) ** 2
    k = int(np.argmax(spectrum[1:])) + 1
    if 0 < k < len(spectrum) - 1:
        a, b, c = np.log(spectrum[k - 1 : k + 2] + 1e-300)
        shift = 0.5 * (a - c) / (a - 2 * b + c) if (a - 2 * b + c) != 0 else 0.0
    else:
        shift = 0.0
    frequency = (k + shift) / n  # cycles per sample
    return float(ts / frequency)


def ultimate_gain_by_experiment(
    simulate: Callable[[float], np.ndarray],
    ts: float,
    *,
    initial_gain: float,
    rtol: float = 2e-3,
    max_runs: int = 60,
) -> tuple[float, float, list[tuple[float, float]]]:
    """Ultimate gain and period by the paper's experiment: bisection on simulated oscillations.

    Parameters
    ----------
    simulate : callable
        ``simulate(kp)`` -> tracked temperature per step of the P-controlled zone after a
        reference step [C].
    ts : float [s]
    initial_gain : float [W/K]
        First proportional gain tried; doubled (or halved) until the loop's stability changes.
    rtol : float [-]
        Relative width of the final bracket.
    max_runs : int

    Returns
    -------
    ultimate_gain : float [W/K]
    ultimate_period : float [s]
    trials : list of (gain [W/K], growth ratio [-])
    """
    trials: list[tuple[float, float]] = []

    def growth(kp):
        ratio = oscillation_growth(simulate(kp))
        trials.append((kp, ratio))
        return ratio

    low = high = None
    kp = float(initial_gain)
    for _ in range(40):
        if growth(kp) > 1.0:
            high = kp
            kp /= 2.0
            if low is not None:
                break
        else:
            low = kp
            kp *= 2.0
            if high is not None:
                break
        if low is not None and high is not None:
            break
    if low is None or high is None:
        raise ThermocalInputError(
            "Ziegler-Nichols experiment: no sustained oscillation between "
            f"{initial_gain / 2**40:.3g} and {initial_gain * 2**40:.3g} W/K"
        )
    while high - low > rtol * high and len(trials) < max_runs:
        middle = 0.5 * (low + high)
        if growth(middle) > 1.0:
            high = middle
        else:
            low = middle
    ku = 0.5 * (low + high)
    period = oscillation_period(simulate(low), ts)
    return ku, period, trials


@dataclass
class TuningResult:
    """Ziegler-Nichols tuning of one zone.

    Attributes
    ----------
    zone : str
    volume : float [m3]
    ultimate_gain, ultimate_period : float [W/K], [s]
        From the closed-loop poles (exact).
    experiment_gain, experiment_period : float [W/K], [s]
        From the paper's simulated experiment (bisection); None when not run.
    critical_pole_modulus : tuple of float [-]
        Modulus of the critical closed-loop pole at 0.98, 1 and 1.02 times the ultimate gain.
    gains : PIDGains
        Discrete gains used: eq. 9 from the exact ultimate gain and period, scaled down (all
        three by one factor) when their loop's gain margin is below the requested one.
    paper_gains : PIDGains
        The unscaled gains of eq. 9.
    paper_gain_margin, gain_margin : float [-]
        Gain margin of the tuned zone's PID loop with the paper's and with the used gains.
    oscillation : DataFrame
        Tracked temperature [C] and reference [C] of the experiment at the ultimate gain (the
        paper's Fig. 3), indexed by time [h].
    trials : list of (gain, growth ratio)
    outdoor_temperature : float [C]
    """

    zone: str
    volume: float
    ultimate_gain: float
    ultimate_period: float
    experiment_gain: float | None
    experiment_period: float | None
    critical_pole_modulus: tuple[float, float, float]
    gains: PIDGains
    oscillation: pd.DataFrame | None = None
    trials: list = field(default_factory=list)
    outdoor_temperature: float = 0.0
    paper_gains: PIDGains | None = None
    paper_gain_margin: float = float("inf")
    gain_margin: float = float("inf")
    experiment_note: str | None = None

    def as_dict(self) -> dict:
        out = {
            "zone": self.zone,
            "volume_m3": self.volume,
            "ultimate_gain_W_per_K": self.ultimate_gain,
            "ultimate_period_s": self.ultimate_period,
            "experiment_ultimate_gain_W_per_K": self.experiment_gain,
            "experiment_ultimate_period_s": self.experiment_period,
            "critical_pole_modulus_at_0.98_1_1.02_Ku": list(self.critical_pole_modulus),
            "outdoor_temperature_C": self.outdoor_temperature,
            "gains": self.gains.as_dict(),
            "paper_gains": None if self.paper_gains is None else self.paper_gains.as_dict(),
            "paper_gain_margin": self.paper_gain_margin,
            "gain_margin": self.gain_margin,
        }
        if self.experiment_gain is not None:
            out["experiment_vs_exact_gain_ratio"] = self.experiment_gain / self.ultimate_gain
        if self.experiment_note:
            out["experiment_note"] = self.experiment_note
        return out


def median_volume_zone(building) -> str:
    """The zone whose volume is the median of the building's (the default tuned zone)."""
    zones = sorted(building.zones.values(), key=lambda z: (z.volume, z.name))
    return zones[(len(zones) - 1) // 2].name


def check_tuning_zone(building, zone: str) -> None:
    """Refuse a tuning zone that is not a zone of the building, naming the closest ones.

    Parameters
    ----------
    building : thermocal.multizone.Building
    zone : str
        The zone named for the Ziegler-Nichols tuning (``--tuning-zone``, ``tuning_zone=``).

    Raises
    ------
    thermocal.errors.ThermocalInputError
        ``zone`` is not one of ``building.zones``; the message suggests up to three close names.
    """
    if zone in building.zones:
        return
    import difflib

    close = difflib.get_close_matches(str(zone), list(building.zones), n=3)
    hint = f"; did you mean {', '.join(map(repr, close))}?" if close else ""
    raise ThermocalInputError(
        f"tuning zone {zone!r} is not a zone of the building {building.name!r}{hint}"
    )


def zone_plant(sim, zone: str, feedback="air", radiant_fraction: float = 0.0) -> LinearLoopPlant:
    """The linear plant of ``zone`` in a :class:`~thermocal.multizone.Simulation`'s network.

    ``feedback``: "air", "operative" or the air weight [-] of the sensed temperature;
    ``radiant_fraction`` [-]: share of the heat on the zone's surfaces (as
    :meth:`~thermocal.multizone.Simulation.track` distributes it).
    """
    from thermocal.identification.sensors import sensor_weight

    net = sim.network
    names = list(net.zone_names)
    if zone not in names:
        raise ThermocalInputError(f"tuning: zone {zone!r} is not a zone of the building")
    z = names.index(zone)
    n = net.n_nodes
    output = np.zeros(n)
    air = int(net.air_node[z])
    weight = sensor_weight(feedback, "tuning")
    faces = np.flatnonzero(net.face_zone == z)
    area = net.face_area[faces].sum()
    if weight < 1.0 and area > 0:
        np.add.at(output, net.face_node[faces], (1.0 - weight) * net.face_area[faces] / area)
        output[air] += weight
    else:
        output[air] = 1.0
    ptr, idx, val = sim._heat_distribution(np.array([z]), np.array([float(radiant_fraction)]))
    weights = np.zeros(n)
    np.add.at(weights, idx, val)
    return LinearLoopPlant(
        matrix=net.system_matrix(sim.dt).tocsc(),
        capacity_dt=np.asarray(net.capacity, dtype=float) / sim.dt,
        input_node=air,
        output=output,
        ts=sim.dt,
        input_weights=weights,
    )


def constant_weather(
    start, days: int, temperature: float, *, wind_speed: float = 0.0, tz=None
) -> pd.DataFrame:
    """Hourly weather frame with a constant outdoor temperature, no sun [C], [m/s]."""
    index = pd.date_range(pd.Timestamp(start), periods=24 * days + 1, freq="1h", tz=tz)
    sky = 5.670374419e-8 * (float(temperature) + 273.15) ** 4  # sky at the air temperature
    return pd.DataFrame(
        {
            "temp_air": float(temperature),
            "temp_dew": float(temperature) - 5.0,
            "ghi_infrared": sky,
            "dni": 0.0,
            "dhi": 0.0,
            "ghi": 0.0,
            "wind_speed": float(wind_speed),
        },
        index=index,
    )


def _tuning_failed(zone: str, exc: Exception) -> ThermocalInputError:
    """The Ziegler-Nichols failure of a zone, named, with what to try."""
    return ThermocalInputError(
        f"PID tuning in zone {zone!r}: {exc}. The Ziegler-Nichols experiment needs a zone whose "
        "air temperature responds to its heat within a few steps; what to try: another tuning "
        "zone (--tuning-zone, or identification.tuning_zone in a campaign file; an ordinary "
        "room rather than a plenum, shaft or vestibule), --method inverse (the exact inverse "
        "needs no tuning), or a shorter --step"
    )


def tune_zone(
    building,
    *,
    zone: str | None = None,
    step: str | pd.Timedelta = "5min",
    outdoor_temperature: float = 0.0,
    wind_speed: float = 0.0,
    feedback="air",
    radiant_fraction: float = 0.0,
    options=None,
    metadata=None,
    experiment: bool = True,
    days: int = 2,
    reference_step: float = 1.0,
    gain_margin: float | None = 1.7,
) -> TuningResult:
    """Ziegler-Nichols tuning of one zone (default: the zone with the median volume).

    Parameters
    ----------
    building : thermocal.multizone.Building
    zone : str, optional
    step : str or Timedelta
        Sampling time of the controller (the identification's step).
    outdoor_temperature : float [C]
        Constant outdoor temperature of the experiment (the identification uses the period's
        mean).
    wind_speed : float [m/s]
    feedback : {"air", "operative"} or float
        Sensor model: "air", "operative" or the air weight [-] of the sensed temperature.
    radiant_fraction : float [-]
        Share of the zone's heat on its surfaces (the form of the identified heat).
    options : NetworkOptions, optional
    metadata : dict, optional
        Site (latitude, longitude, altitude) for the simulation.
    experiment : bool
        Also run the paper's simulated experiment (bisection); the exact analysis always runs.
    days : int
        Length of each experiment run [d].
    reference_step : float [K]
        Height of the reference step above the initial (outdoor) temperature.
    gain_margin : float or None [-]
        When the PID loop of the tuned zone with the gains of eq. 9 has a smaller gain margin
        (below 1: it diverges), all three gains are scaled by one factor to reach this margin
        (1.7 is the margin the rule's ``KP = Ku / 1.7`` aims at). None keeps the paper's gains.

    Notes
    -----
    With the controller seeing the temperature at the end of the previous step (one step of
    delay, as in a co-simulation) and a thermal RC network (real, stable poles), the phase of
    ``G`` stays in (-180, 0) degrees below the Nyquist frequency, so the ultimate period is
    exactly two steps and ``Ku = -1 / G(-1)``. With ``Pu = 2 ts`` the gains of eq. 9 give
    ``H(-1) = (1/1.7 + 1/3.4 + 2/6.8) Ku = 1.18 Ku``: the paper's rule yields a loop that
    oscillates with growing amplitude at the Nyquist frequency on such a model, hence the
    ``gain_margin`` scaling.

    Returns
    -------
    TuningResult
    """
    from thermocal.multizone.simulation import Simulation

    zone = zone or median_volume_zone(building)
    check_tuning_zone(building, zone)
    site = metadata or {
        "latitude": building.location.latitude,
        "longitude": building.location.longitude,
        "altitude": building.location.altitude,
    }
    weather = constant_weather(
        "2001-01-01", days + 1, outdoor_temperature, wind_speed=wind_speed, tz="UTC"
    )
    sim = Simulation(
        building,
        weather,
        site,
        step=step,
        start=weather.index[0],
        end=weather.index[0] + pd.Timedelta(days=days),
        options=options,
        warmup_days=0,
        initial_temperature=outdoor_temperature,
        store_surfaces=False,
    )
    sim.explicit_corrections = False  # the experiment on the same linear plant as the analysis
    ts = sim.dt
    plant = zone_plant(sim, zone, feedback, radiant_fraction)
    omegas = np.pi * np.logspace(-3, 0, 32)
    response = np.array([plant.frequency_response(np.exp(1j * w)) for w in omegas])
    try:
        ku, pu, omega = ultimate_gain_exact(plant.frequency_response, ts,
                                            grid=(omegas, response))
    except ThermocalInputError as exc:
        raise _tuning_failed(zone, exc) from None
    paper = ziegler_nichols(ku, pu, ts)
    paper_margin = loop_gain_margin(paper.transfer_function, omegas, response)
    gains, margin = paper, paper_margin
    if gain_margin is not None and paper_margin < gain_margin:
        gains = paper.scaled(paper_margin / gain_margin)
        margin = loop_gain_margin(gains.transfer_function, omegas, response)
    moduli = tuple(abs(critical_pole(plant, f * ku, omega)) for f in (0.98, 1.0, 1.02))
    n_steps = len(sim.times)
    reference = np.full((n_steps, 1), outdoor_temperature + reference_step)

    def simulate(kp):
        result = sim.track(
            reference,
            zones=[zone],
            method="pid",
            feedback=feedback,
            radiant_fraction=radiant_fraction,
            pid=(np.array([kp]), np.zeros(1), np.zeros(1)),
        )
        return result.tracked_temperature().to_numpy()[:, 0]

    ku_exp = pu_exp = None
    trials: list = []
    experiment_note = None
    if experiment:
        # the experiment checks the exact analysis (the gains come from the latter): a zone
        # whose simulated loop does not oscillate is reported, not a reason to stop
        try:
            ku_exp, pu_exp, trials = ultimate_gain_by_experiment(simulate, ts,
                                                                 initial_gain=0.5 * ku)
        except ThermocalInputError as exc:
            experiment_note = (
                f"the simulated Ziegler-Nichols experiment in zone {zone!r} did not confirm "
                f"the exact ultimate gain {ku:.4g} W/K ({exc}); the gains rest on the exact "
                "analysis of the zone's linear plant"
            )
    trace = simulate(0.999 * (ku_exp if ku_exp is not None else ku))
    hours = (np.arange(1, n_steps + 1) * ts) / 3600.0
    oscillation = pd.DataFrame(
        {"model_temperature_C": trace, "reference_C": reference[:, 0]},
        index=pd.Index(hours, name="time_h"),
    )
    return TuningResult(
        zone=zone,
        volume=building.zones[zone].volume,
        ultimate_gain=ku,
        ultimate_period=pu,
        experiment_gain=ku_exp,
        experiment_period=pu_exp,
        critical_pole_modulus=moduli,
        gains=gains,
        oscillation=oscillation,
        trials=trials,
        outdoor_temperature=outdoor_temperature,
        paper_gains=paper,
        paper_gain_margin=paper_margin,
        gain_margin=margin,
        experiment_note=experiment_note,
    )


def volume_scaled_gains(building, tuning: TuningResult, zones=None) -> dict[str, PIDGains]:
    """Gains of every zone: the tuned gains times the zone's volume over the tuned zone's [W/K].

    The same ratio for the three gains, as the paper scales them.
    """
    names = list(building.zones) if zones is None else list(zones)
    return {
        name: tuning.gains.scaled(building.zones[name].volume / tuning.volume) for name in names
    }
