"""In-situ U-value of a building element from a heat-flux meter: the average method of
ISO 9869-1:2014.

A heat-flux plate on the inside face of a wall, roof or ceiling measures the density of heat
flow rate ``q`` through it; with the inside and outside air temperatures the element's
air-to-air thermal transmittance is the ratio of the sums over whole days

    ``U = sum(q dt) / sum((T_i - T_e) dt)``                       (ISO 9869-1, 7.2)

With the element's inside and outside *surface* temperatures the ratio is its surface-to-surface
conductance ``Lambda``, and ``U = 1 / (R_si + 1/Lambda + R_se)`` with ISO 6946's conventional
surface resistances. The average is right when the heat stored in the element at the end equals
that at the start, which long tests over whole days approach; ISO 9869-1 (7.2.1) ends a test
when

a) it lasted at least 72 h (and is an integer number of days: only whole days are used);
b) the value at its end is within 5 % of the value 24 h earlier;
c) the value from the first ``INT(2 D / 3)`` days is within 5 % of that from the last as many
   days (``D`` the test's days);
d) the change of the heat stored in the element is below 5 % of the heat that passed through
   it (checked when the element's areal heat capacity is given).

The result's standard uncertainty combines, as independent relative parts: the plate's
calibration, the temperature sensors' error over the mean difference, the convergence (the
larger deviation of b or c as the half-width of a rectangular distribution) and how well one
spot stands for the element (thermal bridges, workmanship, moisture). ISO 9869-1 (clause 9)
puts the total at 14-28 % for a careful measurement; the parts here are the user's to state.

References
----------
ISO 9869-1:2014, Thermal insulation -- Building elements -- In-situ measurement of thermal
resistance and thermal transmittance -- Part 1: Heat flow meter method.
ISO 6946:2017, Building components and building elements -- Thermal resistance and thermal
transmittance -- Calculation methods (surface resistances, Table 7).
K. Gaspar, M. Casals and M. Gangolells, "In situ measurement of facades with a low U-value:
Avoiding deviations", Energy and Buildings 170, 2018 (the criteria in practice).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

__all__ = [
    "CONVERGENCE_LIMIT",
    "MIN_DAYS",
    "MIN_MEAN_DIFFERENCE_K",
    "SURFACE_RESISTANCES",
    "InSituUValue",
    "InwardHeatFlux",
    "average_method",
]

#: ISO 9869-1 7.2.1: shortest test [days] and the relative limit of criteria b, c and d [-].
MIN_DAYS = 3
CONVERGENCE_LIMIT = 0.05
#: Smallest plausible heat flux over temperature difference of a building element [W/(m2 K)]
#: (a resistance of 50 m2 K/W; the best passive-house walls have about 10).
MIN_CONDUCTANCE = 0.02
#: Least share of each whole day the valid rows must cover (ISO 9869-1 asks for a continuous
#: record; a day with a longer gap is refused, not counted) [-].
MIN_DAY_COVERAGE = 0.9
#: Below this mean inside-outside difference [K] the temperature sensors' error weighs on the
#: result; practice asks for at least 10 K (Gaspar et al. 2018): reported, not refused.
MIN_MEAN_DIFFERENCE_K = 10.0
#: ISO 6946 Table 7 conventional surface resistances [m2 K/W] by the heat flow's direction
#: through the element: (inside, outside).
SURFACE_RESISTANCES: dict[str, tuple[float, float]] = {
    "horizontal": (0.13, 0.04),
    "upward": (0.10, 0.04),
    "downward": (0.17, 0.04),
}


class InwardHeatFlux(ValueError):
    """The heat flows inwards on average while the inside is warmer: the plate's sign."""


@dataclass(frozen=True)
class InSituUValue:
    """An element's measured U-value with its standard uncertainty.

    Attributes
    ----------
    u_value : float
        Air-to-air thermal transmittance [W/(m2 K)].
    rel_std : float
        Relative standard uncertainty of ``u_value`` [-].
    days : int
        Whole days of the log the value is from [d] (0 when the value was given, not measured).
    mean_difference_K : float
        Mean inside-outside temperature difference of those days [K] (NaN when given).
    checks : dict
        ISO 9869-1's criteria: name -> {"value", "limit", "passed"} (relative values [-],
        duration [d]).
    uncertainty : dict
        The relative standard uncertainties combined in ``rel_std``, by source [-].
    conductance : float
        Surface-to-surface conductance ``Lambda`` [W/(m2 K)] when surface temperatures were
        measured, else NaN.
    notes : list of str
        What was assumed or not checked.
    """

    u_value: float
    rel_std: float
    days: int = 0
    mean_difference_K: float = float("nan")
    checks: dict = field(default_factory=dict)
    uncertainty: dict = field(default_factory=dict)
    conductance: float = float("nan")
    notes: list = field(default_factory=list)
    #: the surface resistances (inside, outside) [m2 K/W] between U and the element's own
    #: resistance (ISO 6946 Table 7; Rsi on both sides towards an unheated space)
    surface_resistances: tuple = SURFACE_RESISTANCES["horizontal"]

    @property
    def resistance(self) -> float:
        """The element's surface-to-surface thermal resistance [m2 K/W]: ``1 / Lambda`` when
        surface temperatures were measured, else ``1 / U`` less ISO 6946's surface
        resistances."""
        if np.isfinite(self.conductance):
            return 1.0 / self.conductance
        r_si, r_se = self.surface_resistances
        return 1.0 / self.u_value - r_si - r_se

    @property
    def resistance_rel_std(self) -> float:
        """Relative standard uncertainty of :attr:`resistance` [-] (a relative error of U
        moves ``1 / U`` alike, and ``R`` by ``1 / (U R)`` of it)."""
        if np.isfinite(self.conductance):
            return self.rel_std * self.conductance / self.u_value
        return self.rel_std / (self.u_value * self.resistance)

    @property
    def converged(self) -> bool:
        """Whether every checked criterion of ISO 9869-1 7.2.1 holds."""
        return all(c["passed"] for c in self.checks.values())

    def failed(self) -> list[str]:
        """The criteria that failed, each in a few words with its value and limit."""
        out = []
        for name, c in self.checks.items():
            if not c["passed"]:
                value, limit = c["value"], c["limit"]
                if name == "duration":
                    out.append(f"{name}: {value:g} days < {limit:g}")
                else:
                    out.append(f"{name}: {100 * value:.1f} % > {100 * limit:.0f} %")
        return out

    def as_dict(self) -> dict:
        """JSON-ready form (results.json)."""
        return {
            "u_value_W_per_m2K": self.u_value,
            "rel_std": self.rel_std,
            "days": self.days,
            "mean_difference_K": None if np.isnan(self.mean_difference_K) else
            self.mean_difference_K,
            "conductance_W_per_m2K": None if np.isnan(self.conductance) else self.conductance,
            "resistance_m2K_per_W": self.resistance,
            "resistance_rel_std": self.resistance_rel_std,
            "converged": self.converged,
            "checks": self.checks,
            "uncertainty": self.uncertainty,
            "notes": list(self.notes),
        }  # fmt: skip


#: A spacing longer than this many times the local logging interval (the median of the
#: neighbouring spacings) is a gap: the row before it stands for one local interval only.
GAP_FACTOR = 2.0
#: Neighbouring spacings the local logging interval is the median of [-].
GAP_WINDOW = 25


def _interval_seconds(times: pd.DatetimeIndex) -> tuple[np.ndarray, np.ndarray]:
    """Each row's start after the first row's [s] and its weight [s]: the time to the next
    row, except before a gap (a spacing over :data:`GAP_FACTOR` times the local interval, the
    median of the :data:`GAP_WINDOW` neighbouring spacings), where the row stands for one local
    interval only; a logger that changes its interval or jitters keeps its rows' own spacing."""
    t = np.asarray((times - times[0]) / pd.Timedelta(seconds=1), float) if len(times) else []
    if len(t) < 2:
        return np.asarray(t, float), np.full(len(t), 3600.0)
    dt = np.diff(t)
    local = pd.Series(dt).rolling(GAP_WINDOW, center=True, min_periods=1).median().to_numpy()
    weight = np.where(dt > GAP_FACTOR * local, local, dt)
    return t, np.append(weight, local[-1])


@dataclass(frozen=True)
class _Days:
    """A log from its first valid row, its rows' weights and its whole days' sums."""

    first: int  # the first valid row of the log as given
    times: pd.DatetimeIndex  # from it
    ok: np.ndarray  # rows with the heat flux and both temperatures
    day: np.ndarray  # each row's day from the first valid row [-]
    weight: np.ndarray  # each row's interval [s] (:func:`_interval_seconds`)
    days: int  # whole days
    flux: np.ndarray  # per whole day: sum of q dt over its valid rows [J/m2]
    difference: np.ndarray  # per whole day: sum of dT dt [K s]
    covered: np.ndarray  # per whole day: the valid rows' time [s]


def _whole_days(times, q, ti, te) -> _Days | None:
    """The log's whole days and their sums (None without a valid row)."""
    ok = np.isfinite(q) & np.isfinite(ti) & np.isfinite(te)
    if not ok.any():
        return None
    start = int(np.argmax(ok))  # the days count from the first valid row
    times, q, dtemp, ok = times[start:], q[start:], (ti - te)[start:], ok[start:]
    elapsed, weight = _interval_seconds(times)
    days = int((elapsed[-1] + weight[-1]) // 86400.0)
    day = (elapsed // 86400.0).astype(int)
    whole = day < days
    w = np.where(ok & whole, weight, 0.0)

    def per_day(values):
        return np.bincount(day[whole], weights=(np.where(ok, values, 0.0) * w)[whole],
                           minlength=days)  # fmt: skip

    return _Days(
        start, times, ok, day, weight, days, per_day(q), per_day(dtemp), per_day(np.ones(len(q)))
    )


def average_method(
    times: pd.DatetimeIndex,
    heat_flux: np.ndarray,
    temp_in: np.ndarray,
    temp_out: np.ndarray,
    *,
    temperatures: str = "air",
    flow: str = "horizontal",
    surface_resistances: tuple[float, float] | None = None,
    plate_rel_std: float = 0.05,
    temperature_std_K: float = 0.1,
    spot_rel_std: float = 0.05,
    areal_heat_capacity: float | None = None,
) -> InSituUValue:
    """The average method of ISO 9869-1 (7.2) on a heat-flux meter's log.

    Parameters
    ----------
    times : DatetimeIndex
        Start of each logged interval; the rows are interval means.
    heat_flux : ndarray [W/m2]
        Density of heat flow rate through the element, positive from inside to outside.
    temp_in, temp_out : ndarray [C]
        Inside and outside air temperatures (``temperatures="air"``), or the element's inside
        and outside surface temperatures (``"surface"``).
    temperatures : {"air", "surface"}
        What ``temp_in`` and ``temp_out`` are.
    flow : {"horizontal", "upward", "downward"}
        Direction of the heat flow through the element (walls horizontal, roofs and ceilings
        upward, floors downward): ISO 6946's surface resistances for ``"surface"``.
    surface_resistances : (float, float), optional
        Inside and outside surface resistances [m2 K/W] instead of ``flow``'s (an element
        towards an unheated space has the inside one on both sides).
    plate_rel_std : float [-]
        Relative standard uncertainty of the plate's calibration and of its disturbance of the
        flow (ISO 9869-1 clause 9: about 5 % together).
    temperature_std_K : float [K]
        Standard uncertainty of each temperature sensor (a constant offset).
    spot_rel_std : float [-]
        How well the measured spot stands for the whole element (relative standard
        uncertainty; thermal bridges, workmanship, moisture).
    areal_heat_capacity : float [J/(m2 K)], optional
        The element's heat capacity per area, for criterion d; unchecked when None.

    Returns
    -------
    InSituUValue
        From the log's whole days (a partial last day is left out).

    Raises
    ------
    ValueError
        Fewer than one whole day, a whole day whose valid rows (heat flux and both
        temperatures) cover less than :data:`MIN_DAY_COVERAGE` of it (named), a heat flux that
        sums to zero or reads almost nothing or inwards, or a mean difference that is not
        positive, each with what to check.
    """
    times = pd.DatetimeIndex(times)
    q = np.asarray(heat_flux, float)
    ti = np.asarray(temp_in, float)
    te = np.asarray(temp_out, float)
    log = _whole_days(times, q, ti, te)
    if log is None:
        raise ValueError("no row has the heat flux and both temperatures")
    days, times = log.days, log.times
    if days < 1:
        raise ValueError("the heat-flux log covers less than one whole day")
    coverage = log.covered / 86400.0
    short = np.flatnonzero(coverage < MIN_DAY_COVERAGE)
    if short.size:
        named = ", ".join(
            f"{(times[0] + pd.Timedelta(days=int(i))).strftime('%Y-%m-%d %H:%M')} "
            f"({100 * coverage[i]:.0f} %)"
            for i in short[:5]
        )
        raise ValueError(
            f"{short.size} of the log's {days} whole days are not covered by rows with the heat "
            f"flux and both temperatures to {100 * MIN_DAY_COVERAGE:.0f} %: the days from "
            f"{named}{' ...' if short.size > 5 else ''}; the average method needs a continuous "
            "record of whole days: fill the gap or cut the log to a continuous stretch"
        )
    flux, difference = log.flux.sum(), log.difference.sum()
    if flux == 0.0:
        raise ValueError(
            "the heat flux sums to zero over the log (a dead or unconnected plate?); check "
            "the heat-flux column"
        )
    mean_dt = float(difference / log.covered.sum())
    if not mean_dt > 0:
        raise ValueError(
            f"the mean inside-outside temperature difference is {mean_dt:.2f} K: the average "
            "method needs the inside warmer than the outside (a heating-season measurement; "
            "check that the inside and outside columns are not swapped)"
        )
    ratio = float(flux / difference)
    if ratio <= -MIN_CONDUCTANCE:
        raise InwardHeatFlux(
            "the heat flows inwards on average while the inside is warmer: the plate reports "
            "the other direction (its sign)"
        )
    if abs(ratio) < MIN_CONDUCTANCE:
        raise ValueError(
            f"the heat flux over the temperature difference is {ratio:.2g} W/(m2 K), below any "
            f"building element's ({MIN_CONDUCTANCE:g}): the plate reads (almost) nothing; check "
            "its connection and the heat-flux column"
        )

    def between(first: int, last: int) -> float:  # the days first .. last - 1
        return float(log.flux[first:last].sum() / log.difference[first:last].sum())

    checks = {"duration": {"value": days, "limit": MIN_DAYS, "passed": days >= MIN_DAYS}}
    if days >= 2:
        change = float(abs(ratio - between(0, days - 1)) / abs(ratio))
        checks["last day"] = {
            "value": change, "limit": CONVERGENCE_LIMIT, "passed": change <= CONVERGENCE_LIMIT
        }  # fmt: skip
    part = int(2 * days / 3)
    if part >= 1 and days >= 2:
        spread = float(abs(between(0, part) - between(days - part, days)) / abs(ratio))
        checks["first vs last 2/3"] = {
            "value": spread, "limit": CONVERGENCE_LIMIT, "passed": spread <= CONVERGENCE_LIMIT
        }  # fmt: skip
    notes = []
    if areal_heat_capacity is not None:
        mid = 0.5 * (ti + te)[log.first :]

        def day_mean(i):
            rows = (log.day == i) & log.ok
            return np.average(mid[rows], weights=log.weight[rows])

        stored = abs(float(areal_heat_capacity) * float(day_mean(days - 1) - day_mean(0)))
        share = float(stored / abs(flux))
        checks["heat stored"] = {
            "value": share, "limit": CONVERGENCE_LIMIT, "passed": share <= CONVERGENCE_LIMIT
        }  # fmt: skip
    else:
        notes.append(
            "criterion d (heat stored in the element below 5 % of the heat through it) not "
            "checked: give the element's areal heat capacity"
        )
    if mean_dt < MIN_MEAN_DIFFERENCE_K:
        notes.append(
            f"mean inside-outside difference {mean_dt:.1f} K below the {MIN_MEAN_DIFFERENCE_K:g} "
            "K practice asks for: the sensors' error weighs more"
        )
    convergence = max(
        [c["value"] for k, c in checks.items() if k in ("last day", "first vs last 2/3")],
        default=0.0,
    )
    parts = {
        "plate": float(plate_rel_std),
        "temperatures": float(np.sqrt(2.0) * temperature_std_K / mean_dt),
        "convergence": float(convergence / np.sqrt(3.0)),
        "spot": float(spot_rel_std),
    }
    conductance = float("nan")
    u = ratio
    films = tuple(surface_resistances or SURFACE_RESISTANCES[flow])
    if temperatures == "surface":
        r_si, r_se = films
        conductance = ratio
        u = 1.0 / (r_si + 1.0 / ratio + r_se)
        # the conventional surface resistances' share of the result is not measured: a
        # relative error of Lambda moves U by U / Lambda of it
        parts = {k: v * u / ratio for k, v in parts.items()}
    elif temperatures != "air":
        raise ValueError(f"temperatures must be 'air' or 'surface', not {temperatures!r}")
    rel_std = float(np.sqrt(sum(v * v for v in parts.values())))
    return InSituUValue(
        u_value=float(u),
        rel_std=rel_std,
        days=days,
        mean_difference_K=mean_dt,
        checks=checks,
        uncertainty=parts,
        conductance=conductance,
        notes=notes,
        surface_resistances=films,
    )


def running_average(
    times: pd.DatetimeIndex, heat_flux: np.ndarray, temp_in: np.ndarray, temp_out: np.ndarray
) -> pd.Series:
    """The average method's ratio at the end of each whole day, from the log's first valid
    row: how the estimate converges (ISO 9869-1 reads its criteria b and c off it).

    Parameters
    ----------
    times, heat_flux, temp_in, temp_out
        As :func:`average_method` [W/m2, C].

    Returns
    -------
    Series
        The ratio ``sum(q dt) / sum(dT dt)`` over the days up to each one [W/(m2 K)] (U with
        air temperatures, Lambda with surface ones), indexed by the day's end; NaN where no
        valid row has come yet.
    """
    log = _whole_days(
        pd.DatetimeIndex(times), np.asarray(heat_flux, float), np.asarray(temp_in, float),
        np.asarray(temp_out, float),
    )  # fmt: skip
    if log is None:
        return pd.Series(dtype=float)
    q_sum, t_sum, times, days = np.cumsum(log.flux), np.cumsum(log.difference), log.times, log.days
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(t_sum != 0, q_sum / t_sum, np.nan)
    ends = times[0] + pd.to_timedelta(np.arange(1, days + 1), unit="D")
    return pd.Series(ratio, index=ends, name="running_average_W_per_m2K")
