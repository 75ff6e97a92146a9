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
    "D_NOT_CHECKED",
    "HEAVY_ELEMENT",
    "IMPLAUSIBLY_THICK",
    "MIN_DAYS",
    "MIN_MEAN_DIFFERENCE_K",
    "SURFACE_RESISTANCES",
    "THICK_ELEMENT_RESISTANCE",
    "THIN_ELEMENT_RESISTANCE",
    "InSituUValue",
    "InwardHeatFlux",
    "average_method",
]

#: ISO 9869-1 7.2.1: shortest test [days] and the relative limit of criteria b, c and d [-].
MIN_DAYS = 3
CONVERGENCE_LIMIT = 0.05
#: ISO 9869-1 (7.2.1) asks criterion d of every element whose areal heat capacity is above this
#: [J/(m2 K)]; most walls are (12.5 mm of plasterboard and a timber frame about 30 kJ/(m2 K),
#: 36 cm of brick about 580).
HEAVY_ELEMENT = 20e3
#: :attr:`InSituUValue.status` of a log that passes criteria a-c while d was not checked.
D_NOT_CHECKED = "criteria a-c pass; d (heat stored) not checked"
#: Smallest heat flux over temperature difference [W/(m2 K)] a plate can be said to measure
#: anything at (a resistance of 50 m2 K/W; the best passive-house walls have about 10): below
#: it the log is refused as a dead plate; between it and :data:`THICK_ELEMENT_RESISTANCE` a
#: result is noted.
MIN_CONDUCTANCE = 0.02
#: Element resistance [m2 K/W] above which a result is noted (not refused) as beyond almost
#: any building element's: passive-house walls have about 10 (U 0.1 W/(m2 K)), the best roofs
#: about 12 (U 0.08); vacuum panels or half a metre of insulation go beyond, a plate in mV
#: without its sensitivity applied (some 10 to 100 times too low) far beyond.
THICK_ELEMENT_RESISTANCE = 12.0
#: How the note on such a resistance starts (``thermocal insitu`` shows it as a warning).
IMPLAUSIBLY_THICK = "implausibly high resistance"
#: Element resistance [m2 K/W] below which a result is noted (not refused) as only glazing,
#: sheet metal or a thin bare slab's: 10 cm of concrete (lambda 2.0) has 0.05, 4 mm of glass
#: 0.004 (single glazing, about 5.8 W/(m2 K) air to air), a steel sheet almost nothing.
THIN_ELEMENT_RESISTANCE = 0.05
#: Least share of each whole day the valid rows must cover (ISO 9869-1 asks for a continuous
#: record; a day with a longer gap is refused, not counted) [-].
MIN_DAY_COVERAGE = 0.9
#: A time of day is missing on a day when less than half of its :data:`SLOT_MINUTES` is covered
#: by valid rows; missing on more than half of the days (and on two at least) it recurs, and
#: recurring slots of :data:`MIN_RECURRING_GAP_MINUTES` or more a day are refused
#: (:func:`_recurring_gaps`).
SLOT_MINUTES = 30
MIN_RECURRING_GAP_MINUTES = 60
#: Below this mean inside-outside difference [K] the temperature sensors' error weighs on the
#: result; practice asks for at least 10 K (Gaspar et al. 2018): reported, not refused.
MIN_MEAN_DIFFERENCE_K = 10.0
#: With air temperatures, below this mean difference [K] the outside face's radiation (sky,
#: sun), which the outdoor air temperature does not see, is warned of: it moved the outside face
#: some 1.5-2.5 K from the air on EnergyPlus north walls in Chicago (2006 TMY3), biasing U by
#: that over the mean difference (-26 % at 11.5 K over 3 April days, -8 % at 21 K in January).
MILD_DIFFERENCE_K = 15.0
#: The outside face's typical offset from the outdoor air by radiation [K] (as above).
RADIATION_OFFSET_K = 2.0
#: Local hours [h] of the day and night windows of :func:`_sunlit_ratio`: (from, to).
DAY_HOURS, NIGHT_HOURS = (10, 16), (22, 4)
#: Local hour [h] at which the outdoor air's daily cycle peaks: its daily maximum comes some two
#: hours after solar noon (Parton and Logan 1981: 1.86 h at screen height); the EnergyPlus
#: Chicago winter logs' first harmonic peaks at 14.4-15.0 h local standard time.
AIR_PEAK_HOUR = 14.0
#: Stamps without a known local zone (UTC) whose outdoor air peaks within this many hours [h] of
#: :data:`AIR_PEAK_HOUR` are taken as local clock time (the peak itself varies that much).
CLOCK_TOLERANCE_H = 2.0
#: The outdoor air's daily cycle places day and night only when its mean first harmonic is at
#: least this [K] and the whole days' own harmonics agree in phase to a mean resultant length
#: of :data:`MIN_PHASE_AGREEMENT` [-] (1: every day peaks at the same hour; 0: at random).
MIN_AIR_CYCLE_K, MIN_PHASE_AGREEMENT = 0.5, 0.5
#: A day/night ratio of the flux over the air-to-air difference below this [-] is warned of as
#: a sunlit outside face: EnergyPlus south timber walls (Chicago, winter) 0.30-0.76, the north
#: ones 0.97-1.54.
SUNLIT_RATIO = 0.8
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
        What was assumed.
    warnings : list of str
        What may make the value wrong beyond its uncertainty (criterion d not checked, the
        sun on the outside face, a mild period): shown as warnings, recorded in in_situ.json
        and results.json.
    """

    u_value: float
    rel_std: float
    days: int = 0
    mean_difference_K: float = float("nan")
    checks: dict = field(default_factory=dict)
    uncertainty: dict = field(default_factory=dict)
    conductance: float = float("nan")
    notes: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
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
        moves ``1 / U`` alike, and ``R`` by ``1 / (U R)`` of it); NaN when the resistance is
        not positive (a U-value the surface resistances alone do not allow)."""
        if np.isfinite(self.conductance):
            return self.rel_std * self.conductance / self.u_value
        resistance = self.resistance
        if not resistance > 0:  # no element left beyond the films: no uncertainty of it
            return float("nan")
        return self.rel_std / (self.u_value * resistance)

    @property
    def converged(self) -> bool:
        """Whether every checked criterion of ISO 9869-1 7.2.1 holds (see :attr:`status` for
        whether criterion d was among them)."""
        return all(c["passed"] for c in self.checks.values())

    @property
    def status(self) -> str:
        """ISO 9869-1 7.2.1's verdict: ``"converged"`` (a-d pass), ``"not converged"`` (a
        checked criterion fails), :data:`D_NOT_CHECKED` (a-c pass, the element's heat capacity
        was not given: convergence is *not* shown for an element above
        :data:`HEAVY_ELEMENT`) or ``"given"`` (a value, not a log)."""
        if not self.checks:
            return "given"
        if not self.converged:
            return "not converged"
        return "converged" if "heat stored" in self.checks else D_NOT_CHECKED

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
            "resistance_rel_std": None if np.isnan(self.resistance_rel_std) else
            self.resistance_rel_std,
            "converged": self.converged,
            "status": self.status,
            "checks": self.checks,
            "uncertainty": self.uncertainty,
            "warnings": list(self.warnings),
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


def _recurring_gaps(log: _Days) -> tuple[str, int, int] | None:
    """Times of day that lack valid rows on most days of a log, else None.

    Each whole day's coverage rule (:data:`MIN_DAY_COVERAGE`) treats missing rows as random; a
    gap at the same hour every day (a logger's schedule or download) passes it yet leaves the
    same part of the daily cycle out of both sums. The log's whole days are cut into clock
    slots of :data:`SLOT_MINUTES`; a slot less than half covered by valid rows (each standing
    for its weight, :func:`_interval_seconds`) is missing that day. The whole days need not
    start at midnight: they span parts of one more clock day than they count, and a slot counts
    only on the clock days the whole days hold at least half of it.

    Parameters
    ----------
    log : _Days
        The log's whole days.

    Returns
    -------
    (str, int, int) or None
        The recurring spans of clock time (``"06:00-08:00"``, comma-separated), on how many
        days the most-missed slot is missing, of how many; None when the recurring slots are
        fewer than :data:`MIN_RECURRING_GAP_MINUTES` a day.
    """
    if log.days < 2:
        return None
    elapsed = np.asarray((log.times - log.times[0]) / pd.Timedelta(seconds=1), float)
    n = log.days * 1440
    rows = log.ok & (log.day < log.days)
    first = np.clip(np.floor(elapsed[rows] / 60.0).astype(int), 0, n)
    last = np.clip(np.floor((elapsed[rows] + log.weight[rows]) / 60.0).astype(int), 0, n)
    diff = np.zeros(n + 1)
    np.add.at(diff, first, 1.0)
    np.add.at(diff, last, -1.0)
    covered = np.cumsum(diff)[:n] > 0.5
    start = log.times[0]
    clock = int((start - start.normalize()) / pd.Timedelta(minutes=1)) + np.arange(n)
    per_day = 1440 // SLOT_MINUTES
    key = (clock // 1440) * per_day + (clock % 1440) // SLOT_MINUTES
    size = -(-(int(key[-1]) + 1) // per_day) * per_day  # whole clock days: partial ones padded
    within = np.bincount(key, minlength=size).reshape(-1, per_day)
    cov = np.bincount(key, weights=covered.astype(float), minlength=size).reshape(-1, per_day)
    present = within >= SLOT_MINUTES / 2
    missing = present & (cov < 0.5 * within)
    n_missing, n_present = missing.sum(axis=0), present.sum(axis=0)
    recurring = (n_missing >= 2) & (n_missing > 0.5 * n_present)
    if recurring.sum() * SLOT_MINUTES < MIN_RECURRING_GAP_MINUTES:
        return None
    spans, slot = [], 0
    while slot < per_day:
        if recurring[slot]:
            end = slot
            while end + 1 < per_day and recurring[end + 1]:
                end += 1
            a, b = slot * SLOT_MINUTES, (end + 1) * SLOT_MINUTES
            spans.append(f"{a // 60:02d}:{a % 60:02d}-{b // 60:02d}:{b % 60:02d}")
            slot = end + 1
        else:
            slot += 1
    worst = int(np.argmax(np.where(recurring, n_missing, -1)))
    return ", ".join(spans), int(n_missing[worst]), int(n_present[worst])


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
    heat_flux_column: str | None = None,
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
    heat_flux_column : str, optional
        The log's heat-flux column, named in the note on an implausibly high resistance.

    Returns
    -------
    InSituUValue
        From the log's whole days (a partial last day is left out).

    Raises
    ------
    ValueError
        Fewer than one whole day, a whole day whose valid rows (heat flux and both
        temperatures) cover less than :data:`MIN_DAY_COVERAGE` of it (named), rows missing at
        the same time of day on most days (:func:`_recurring_gaps`, the hours named), a heat
        flux that sums to zero or reads almost nothing or inwards, a mean difference that is
        not positive, or (with air temperatures) a U-value of ``1 / (R_si + R_se)`` or more, which
        would leave the element a negative resistance (a heat flux in mW/m2, an "outside"
        sensor indoors), each with what to check.
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
    recurring = _recurring_gaps(log)
    if recurring is not None:
        spans, on, of = recurring
        raise ValueError(
            f"rows with the heat flux and both temperatures are missing at the same time of "
            f"day on most days: {spans} (to the half hour) on {on} of the {of} days from "
            f"{times[0].strftime('%Y-%m-%d')}; each day passes the {100 * MIN_DAY_COVERAGE:.0f} "
            "% coverage, but the sums leave out the same part of the daily cycle, which biases "
            "U (an EnergyPlus timber wall missing 06:00-08:10 every day: -16 % against -9 % "
            "with every row); log around the clock (a logger's schedule, a nightly download or "
            "a timer?) or fill the hours from a second logger"
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

    films = tuple(surface_resistances or SURFACE_RESISTANCES[flow])
    if temperatures == "air":
        valid = q[log.first :][log.ok]
        peak = int(np.argmax(np.abs(valid)))
        _refuse_impossible(
            ratio, films, float(flux / log.covered.sum()), mean_dt,
            (times[log.ok][peak], float(valid[peak]), float(np.median(np.abs(valid)))),
        )  # fmt: skip

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
    notes, warnings = [], []
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
    elif all(c["passed"] for c in checks.values()):
        warnings.append(_d_not_checked(days))
    if temperatures == "air":
        warnings += _air_temperature_cautions(log, q[log.first :], (ti - te)[log.first :],
                                              te[log.first :], mean_dt, notes)  # fmt: skip
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
    resistance = 1.0 / ratio if temperatures == "surface" else 1.0 / u - sum(films)
    thick = _thick_element_note(
        resistance, float(flux / log.covered.sum()), mean_dt, temperatures == "surface",
        heat_flux_column,
    )  # fmt: skip
    if thick:  # first: a likely fault of the log, before what was not checked
        notes.insert(0, thick)
    if resistance < THIN_ELEMENT_RESISTANCE:
        # noted, not refused: see _refuse_impossible
        notes.append(
            f"the element's resistance {resistance:.2g} m2 K/W is that of glazing, sheet metal "
            f"or at most 10 cm of bare concrete ({THIN_ELEMENT_RESISTANCE:g}): for any other "
            "element check the heat-flux unit (W/m2), the plate's sensitivity and that the "
            "other side's temperature is measured there"
        )
    return InSituUValue(
        u_value=float(u),
        rel_std=rel_std,
        days=days,
        mean_difference_K=mean_dt,
        checks=checks,
        uncertainty=parts,
        conductance=conductance,
        notes=notes,
        warnings=warnings,
        surface_resistances=films,
    )


def _local_hours(log: _Days, temp_out: np.ndarray) -> tuple[np.ndarray, int | None]:
    """Each row's local hour of day [h] for the day and night windows, and how many hours the
    stamps' clock is taken to run ahead of local time (None: the stamps' clock hours are taken
    unchecked).

    Stamps in a local zone (time-zone aware, not UTC) give their clock hours. Stamps in UTC, or
    without a zone (a log read without ``timezone`` is read as UTC), do not say the site's
    local time: the outdoor air's daily cycle places it. Its first harmonic over the whole days
    (each day's mean removed) peaks some two hours after solar noon
    (:data:`AIR_PEAK_HOUR`; Parton and Logan 1981); a peak within :data:`CLOCK_TOLERANCE_H`
    of it leaves the clock hours as they are (local stamps), a peak further off shifts them by
    the whole hours between. A cycle too weak or too irregular to place
    (:data:`MIN_AIR_CYCLE_K`, :data:`MIN_PHASE_AGREEMENT`) leaves the clock hours (None).

    Parameters
    ----------
    log : _Days
    temp_out : ndarray [C]
        The outdoor air temperature from the log's first valid row.

    Returns
    -------
    hours : ndarray [h]
        In [0, 24).
    offset : int or None [h]
        The stamps' clock minus local time; 0 for a local zone or local-looking stamps.
    """
    times = log.times
    clock = np.asarray(times.hour + times.minute / 60.0 + times.second / 3600.0, float)
    if times.tz is not None and str(times.tz) not in ("UTC", "Etc/UTC", "UTC+00:00"):
        return clock, 0
    use = log.ok & (log.day < log.days) & np.isfinite(temp_out)
    w = np.where(use, log.weight, 0.0)
    day = np.where(use, log.day, 0)
    total = np.bincount(day, weights=w, minlength=log.days)
    mean = np.bincount(day, weights=w * np.where(use, temp_out, 0.0), minlength=log.days)
    anomaly = np.where(use, temp_out - (mean / np.where(total > 0, total, 1.0))[day], 0.0)
    phasor = np.exp(2j * np.pi * clock / 24.0)
    per_day = np.bincount(day, weights=(w * anomaly * phasor.real), minlength=log.days) + 1j * (
        np.bincount(day, weights=(w * anomaly * phasor.imag), minlength=log.days)
    )
    resultant = np.abs(per_day.sum())
    amplitude = 2.0 * resultant / max(float(total.sum()), 1.0)
    agreement = resultant / max(float(np.abs(per_day).sum()), 1e-300)
    if amplitude < MIN_AIR_CYCLE_K or agreement < MIN_PHASE_AGREEMENT:
        return clock, None
    peak = float(np.angle(per_day.sum()) * 24.0 / (2 * np.pi)) % 24.0
    ahead = (peak - AIR_PEAK_HOUR + 12.0) % 24.0 - 12.0
    if abs(ahead) <= CLOCK_TOLERANCE_H:
        return clock, 0
    offset = int(np.round(ahead))
    return (clock - offset) % 24.0, offset


def _sunlit_ratio(log: _Days, q: np.ndarray, dtemp: np.ndarray, hours: np.ndarray) -> float:
    """The flux over the air-to-air difference between :data:`DAY_HOURS` over that between
    :data:`NIGHT_HOURS` (local hours, :func:`_local_hours`) on its whole days [-]; NaN when a
    window's difference does not sum positive.

    The sun warms a sunlit outside face well above the outdoor air, so through a light element
    the flux falls in the day while the air-to-air difference does not: the ratio falls well
    below 1. Through a heavy one the day's sun arrives damped and late, and the ratio does not
    show it (the EnergyPlus brick walls: 1.31 north, 1.47 south); hence a warning on a low
    ratio, never a pass on a high one.

    Parameters
    ----------
    log : _Days
    q, dtemp : ndarray
        The heat flux [W/m2] and the inside-outside difference [K] from the log's first valid
        row.
    hours : ndarray [h]
        Each row's local hour of day.

    Returns
    -------
    float
    """
    use = log.ok & (log.day < log.days)
    day = use & (hours >= DAY_HOURS[0]) & (hours < DAY_HOURS[1])
    night = use & ((hours >= NIGHT_HOURS[0]) | (hours < NIGHT_HOURS[1]))
    w = log.weight
    d_day, d_night = np.sum((dtemp * w)[day]), np.sum((dtemp * w)[night])
    if not (d_day > 0 and d_night > 0):
        return float("nan")
    n_day = np.sum((q * w)[night]) / d_night
    return float(np.sum((q * w)[day]) / d_day / n_day) if n_day > 0 else float("nan")


def _air_temperature_cautions(
    log: _Days, q: np.ndarray, dtemp: np.ndarray, temp_out: np.ndarray, mean_dt: float,
    notes: list,
) -> list[str]:  # fmt: skip
    """What the outdoor air temperature does not see: a note always, warnings on a sunlit face
    (:func:`_sunlit_ratio` below :data:`SUNLIT_RATIO`) and on a mild period (a mean difference
    below :data:`MILD_DIFFERENCE_K`).

    ISO 9869-1 (6) asks to protect the measured spot from rain, snow and direct sun, or to
    choose a face out of direct sun; the outside face's radiation to the sky and from the sun
    is not in the air-to-air difference, so it biases U beyond the stated uncertainty, by about
    its offset over the mean difference. Face temperatures (``temperatures: surface``) see it.

    Parameters
    ----------
    log : _Days
    q, dtemp : ndarray
        As :func:`_sunlit_ratio` [W/m2, K].
    temp_out : ndarray [C]
        The outdoor air temperature from the log's first valid row (:func:`_local_hours`).
    mean_dt : float
        The log's mean difference [K].
    notes : list of str
        Appended to: the note, and one on how the day and night windows were placed when the
        stamps do not carry the local zone and are not taken as local time.

    Returns
    -------
    list of str
        The warnings.
    """
    bias = 100 * RADIATION_OFFSET_K / mean_dt
    notes.append(
        "air temperatures: the outside face's radiation (the sun on it, the night sky) is not "
        "in the outdoor air temperature nor in the uncertainty; ISO 9869-1 asks to shield the "
        "spot from sun and rain or to choose a face out of direct sun (EnergyPlus south walls, "
        "Chicago, 14 winter days: U 28-42 % low, within 6 % with face temperatures; north "
        f"walls: the face some {RADIATION_OFFSET_K:g} K off the air, about {bias:.0f} % of U "
        f"at this {mean_dt:.1f} K); face temperatures (--surface, temperatures: surface) see it"
    )
    warnings = []
    hours, offset = _local_hours(log, temp_out)
    stamps = ""
    if offset is None:
        notes.append(
            "the stamps are in UTC or carry no time zone, and the outdoor air has no regular "
            "daily cycle to place the local time: the sunlit-face check takes day "
            f"({DAY_HOURS[0]:02d}:00-{DAY_HOURS[1]:02d}:00) and night by the stamps' clock; "
            "give the log's time zone (--timezone, timezone) if they are not local time"
        )
    elif offset:
        a, b, c, d = ((h + offset) % 24 for h in DAY_HOURS + NIGHT_HOURS)
        stamps = f"; the stamps' {a:02d}:00-{b:02d}:00 and {c:02d}:00-{d:02d}:00"
        notes.append(
            "the stamps are in UTC or carry no time zone, and the outdoor air's daily cycle "
            f"puts them {offset:+d} h from local time (the air is warmest near "
            f"{AIR_PEAK_HOUR:g}:00 local, some two hours after solar noon: Parton and Logan "
            f"1981): the sunlit-face check takes the local day {DAY_HOURS[0]:02d}:00-"
            f"{DAY_HOURS[1]:02d}:00 and night {NIGHT_HOURS[0]:02d}:00-{NIGHT_HOURS[1]:02d}:00 "
            f"as the stamps' {a:02d}:00-{b:02d}:00 and {c:02d}:00-{d:02d}:00; give the log's "
            "time zone (--timezone, timezone) to use the local clock"
        )
    ratio = _sunlit_ratio(log, q, dtemp, hours)
    if ratio < SUNLIT_RATIO:
        warnings.append(
            f"a sunlit outside face? The heat flux over the air-to-air difference between "
            f"{DAY_HOURS[0]:02d}:00 and {DAY_HOURS[1]:02d}:00 local time is {ratio:.2f} of the "
            f"night's ({NIGHT_HOURS[0]:02d}:00-{NIGHT_HOURS[1]:02d}:00{stamps}; below "
            f"{SUNLIT_RATIO:g}): the "
            "sun warms the outside face beyond the outdoor air, and U comes out low (EnergyPlus "
            "south timber walls, Chicago, winter: 28-42 % low at ratios 0.30-0.76, north walls "
            "0.97-1.54). Shield the spot or choose a face out of direct sun (ISO 9869-1), or "
            "measure the face temperatures (--surface, temperatures: surface)"
        )
    if mean_dt < MILD_DIFFERENCE_K:
        warnings.append(
            f"mild period: a mean difference of {mean_dt:.1f} K, below "
            f"{MILD_DIFFERENCE_K:g} K, with air temperatures: the outside face's radiation, "
            f"some {RADIATION_OFFSET_K:g} K off the outdoor air, biases U by about {bias:.0f} %, "
            "beyond the uncertainty (EnergyPlus north timber wall, Chicago, 3 April days at "
            "11.5 K: 26 % low; 8 % at 21 K in January); measure in colder weather or the face "
            "temperatures (--surface, temperatures: surface)"
        )
    return warnings


def _d_not_checked(days: int) -> str:
    """The warning on a log that passes criteria a-c without the element's heat capacity.

    Criterion d is not refused for want of the heat capacity: ISO 9869-1 (7.2.1) asks it only
    of elements above :data:`HEAVY_ELEMENT`, which the log cannot tell, and a long log of a
    heavy wall passing a-c comes close (an EnergyPlus 365 mm brick wall, 583 kJ/(m2 K), with
    face temperatures: within 6 % from 10 days on). Nor is it passed silently: short logs of
    the same wall passing a-c were 18 % low (3 days) and 22 % high (4 days), outside their
    stated uncertainty, and failed d once its heat capacity was given.

    Parameters
    ----------
    days : int
        The log's whole days [d].

    Returns
    -------
    str
        Starting with :data:`D_NOT_CHECKED`.
    """
    return (
        f"{D_NOT_CHECKED}: convergence is NOT shown for an element above "
        f"{HEAVY_ELEMENT / 1e3:g} kJ/(m2 K), of which ISO 9869-1 (7.2.1) requires criterion d "
        "(the change of the heat stored in the element below 5 % of the heat through it); most "
        "walls are (a timber frame with plasterboard about 30, 36 cm of brick about 580). On an "
        "EnergyPlus brick wall logs of 3 and 4 days passing a-c were 18 % low and 22 % high. "
        "Give the element's areal heat capacity (--heat-capacity, areal_heat_capacity)"
        + (" or log longer (10 days or more)" if days < 10 else "")
    )


def _thick_element_note(
    resistance: float, mean_flux: float, mean_dt: float, surface: bool, column: str | None = None
) -> str | None:
    """A note on a resistance beyond almost any building element's, else None.

    The log's mean heat flux over its mean temperature difference is the measured U (or
    Lambda): a mean of a few W/m2 or less over the 10 K or more of a winter measurement is the
    same finding as the resistance above :data:`THICK_ELEMENT_RESISTANCE`, so both are told in
    one note. Noted, not refused, like a thin element's (the log does not say what the element
    is: vacuum panels or half a metre of insulation go beyond); a plate reading almost nothing
    is refused before (:data:`MIN_CONDUCTANCE`).

    Parameters
    ----------
    resistance : float
        The element's surface-to-surface resistance [m2 K/W].
    mean_flux : float
        The log's mean heat flux [W/m2].
    mean_dt : float
        Its mean inside-outside (surface or air) temperature difference [K].
    surface : bool
        Whether the temperatures are the element's surfaces (the ratio is then Lambda, not U).
    column : str, optional
        The log's heat-flux column, for the note.

    Returns
    -------
    str or None
        The note, with the flux and difference it comes from and the causes to check.
    """
    if not resistance > THICK_ELEMENT_RESISTANCE:
        return None
    ratio = mean_flux / mean_dt
    what = "Lambda (surface to surface)" if surface else "U"
    named = f"the heat-flux column {column!r}" if column else "the heat-flux column"
    return (
        f"{IMPLAUSIBLY_THICK}: the element's {resistance:.3g} m2 K/W is above the "
        f"{THICK_ELEMENT_RESISTANCE:g} of the best passive-house elements (walls about 10, U "
        f"0.1 W/(m2 K)); the log's mean heat flux {mean_flux:.3g} W/m2 over a mean difference "
        f"of {mean_dt:.3g} K gives {what} = {ratio:.3g} W/(m2 K). Unless the element is "
        "super-insulated (vacuum panels, half a metre of insulation), check the unit of "
        f"{named} (W/m2: a plate's voltage in mV must be "
        "divided by its sensitivity, typically 0.01-0.1 mV per W/m2, or it reads 10-100 times "
        "too low) and the plate's contact with the surface (an air gap or loose tape lets the "
        "heat pass around it)"
    )


#: A reading this many times the log's median heat flux is named as a spike when the U-value
#: is impossible [-].
SPIKE_FACTOR = 100.0


def _refuse_impossible(
    u: float, films: tuple[float, float], mean_flux: float, mean_dt: float, peak: tuple
) -> None:
    """Refuse an air-to-air U-value the surface resistances alone do not allow.

    ``U = 1 / (R_si + R + R_se)`` with the element's resistance ``R >= 0``, so no element has a
    U-value of ``1 / (R_si + R_se)`` or more (5.88 W/(m2 K) for a wall); above it the element's
    resistance would be negative, and so its uncertainty.

    A positive but implausibly small resistance is *not* refused: the log does not say what the
    element is, and real ones come close to the limit (single glazing, 4 mm of glass, has
    0.004 m2 K/W: about 5.8 W/(m2 K); a steel sheet or a metal door almost nothing), so any
    floor above zero would refuse a real measurement. A plate in mW/m2 (x 1000) or an "outside"
    sensor indoors (a difference of tenths of a kelvin) lands far beyond the limit; a plate
    sensitivity off by some factor may land below it, which only the element's description can
    tell: the result gets a note below :data:`THIN_ELEMENT_RESISTANCE` instead.

    Parameters
    ----------
    u : float
        The air-to-air ratio [W/(m2 K)].
    films : (float, float)
        Inside and outside surface resistances [m2 K/W].
    mean_flux, mean_dt : float
        The log's mean heat flux [W/m2] and inside-outside difference [K], for the message.
    peak : (Timestamp, float, float)
        The largest reading's time and heat flux and the median absolute heat flux [W/m2]:
        a reading :data:`SPIKE_FACTOR` times the median is named.

    Raises
    ------
    ValueError
        With the U-value, the limit and the causes to check.
    """
    r_si, r_se = films
    limit = 1.0 / (r_si + r_se)
    if u < limit:
        return
    when, high, median = peak
    spike = ""
    if median > 0 and abs(high) > SPIKE_FACTOR * median:
        spike = (
            f"the reading at {when.strftime('%Y-%m-%d %H:%M')}, {high:g} W/m2, is "
            f"{abs(high) / median:.0f} times the log's median: a spike (remove the row or "
            "empty its cell); "
        )
    raise ValueError(
        f"the measured U-value {u:.4g} W/(m2 K) is impossible: the element's own resistance "
        f"would be negative ({1.0 / u - r_si - r_se:.3g} m2 K/W), as the surface resistances "
        f"alone ({r_si:g} + {r_se:g} m2 K/W, ISO 6946) allow at most {limit:.2f} W/(m2 K) "
        f"(single glazing has about 5.8); the log's mean heat flux is {mean_flux:.1f} W/m2 "
        f"over a mean inside-outside difference of {mean_dt:.2g} K; {spike}check the "
        "heat-flux unit "
        "(W/m2: in mW/m2 it is 1000 times too high), that the outside temperature is measured "
        "outside (not a second sensor indoors) and the plate's sensitivity (its calibration "
        "factor); a thin element (glazing, sheet metal) is measured with its surface "
        "temperatures"
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
