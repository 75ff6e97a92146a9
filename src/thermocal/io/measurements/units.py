"""Units and quantities of sensor logs: the known units, conversion to thermocal's units, physical
limits and the unit slips of a temperature column.

Part of :mod:`thermocal.io.measurements`; see its docstring for the conventions.
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

#: Known units: name -> (quantity, factor, offset, canonical unit); canonical = value * factor +
#: offset. Names are matched case-sensitively first, then case-insensitively.
UNITS: dict[str, tuple[str, float, float, str]] = {
    # temperature -> C
    "C": ("temperature", 1.0, 0.0, "C"),
    "°C": ("temperature", 1.0, 0.0, "C"),
    "degC": ("temperature", 1.0, 0.0, "C"),
    "deg C": ("temperature", 1.0, 0.0, "C"),
    "celsius": ("temperature", 1.0, 0.0, "C"),
    "K": ("temperature", 1.0, -273.15, "C"),
    "kelvin": ("temperature", 1.0, -273.15, "C"),
    "F": ("temperature", 5.0 / 9.0, -32.0 * 5.0 / 9.0, "C"),
    "°F": ("temperature", 5.0 / 9.0, -32.0 * 5.0 / 9.0, "C"),
    "degF": ("temperature", 5.0 / 9.0, -32.0 * 5.0 / 9.0, "C"),
    # volume flow -> m3/s
    "m3/s": ("flow", 1.0, 0.0, "m3/s"),
    "m³/s": ("flow", 1.0, 0.0, "m3/s"),
    "m3/h": ("flow", 1.0 / 3600.0, 0.0, "m3/s"),
    "m³/h": ("flow", 1.0 / 3600.0, 0.0, "m3/s"),
    "l/s": ("flow", 1e-3, 0.0, "m3/s"),
    "l/min": ("flow", 1e-3 / 60.0, 0.0, "m3/s"),
    "l/h": ("flow", 1e-3 / 3600.0, 0.0, "m3/s"),
    # power -> W
    "W": ("power", 1.0, 0.0, "W"),
    "kW": ("power", 1e3, 0.0, "W"),
    "MW": ("power", 1e6, 0.0, "W"),
    # energy -> J
    "J": ("energy", 1.0, 0.0, "J"),
    "kJ": ("energy", 1e3, 0.0, "J"),
    "MJ": ("energy", 1e6, 0.0, "J"),
    "Wh": ("energy", 3600.0, 0.0, "J"),
    "kWh": ("energy", 3.6e6, 0.0, "J"),
    "MWh": ("energy", 3.6e9, 0.0, "J"),
    # irradiance -> W/m2
    "W/m2": ("irradiance", 1.0, 0.0, "W/m2"),
    "W/m²": ("irradiance", 1.0, 0.0, "W/m2"),
    "kW/m2": ("irradiance", 1e3, 0.0, "W/m2"),
    "kW/m²": ("irradiance", 1e3, 0.0, "W/m2"),
    # relative humidity -> %
    "%": ("relative_humidity", 1.0, 0.0, "%"),
    "%RH": ("relative_humidity", 1.0, 0.0, "%"),
    "% RH": ("relative_humidity", 1.0, 0.0, "%"),
    # CO2 -> ppm
    "ppm": ("co2", 1.0, 0.0, "ppm"),
    # pressure -> Pa
    "Pa": ("pressure", 1.0, 0.0, "Pa"),
    "hPa": ("pressure", 100.0, 0.0, "Pa"),
    "mbar": ("pressure", 100.0, 0.0, "Pa"),
    "kPa": ("pressure", 1e3, 0.0, "Pa"),
    "bar": ("pressure", 1e5, 0.0, "Pa"),
    # speed -> m/s
    "m/s": ("speed", 1.0, 0.0, "m/s"),
    "km/h": ("speed", 1.0 / 3.6, 0.0, "m/s"),
    # dimensionless
    "-": ("dimensionless", 1.0, 0.0, "-"),
    "1": ("dimensionless", 1.0, 0.0, "-"),
}


_UNITS_FOLDED = {name.casefold(): name for name in UNITS}


#: Canonical unit per quantity.
CANONICAL_UNITS: dict[str, str] = {
    "temperature": "C",
    "flow": "m3/s",
    "power": "W",
    "energy": "J",
    "irradiance": "W/m2",
    "relative_humidity": "%",
    "co2": "ppm",
    "pressure": "Pa",
    "speed": "m/s",
    "dimensionless": "-",
}


#: Physically possible range per quantity, in canonical units: (low, high, reason). Values
#: outside are removed before resampling and listed in the report. Temperatures: building air,
#: outdoor air and hydronic heating water; flows: a building's heating circuit (360 m3/h max).
PHYSICAL_LIMITS: dict[str, tuple[float, float, str]] = {
    "temperature": (-60.0, 110.0, "building, outdoor and heating-water temperatures lie in"),
    "flow": (0.0, 0.1, "a heating-circuit volume flow lies in"),
    "power": (0.0, 1e8, "a heat or electric power lies in"),
    "energy": (0.0, math.inf, "a meter reading lies in"),
    "irradiance": (-20.0, 1600.0, "solar irradiance lies in"),
    "relative_humidity": (0.0, 100.0, "relative humidity lies in"),
    "co2": (0.0, 50_000.0, "a CO2 concentration lies in"),
    "pressure": (30_000.0, 110_000.0, "atmospheric pressure lies in"),
    "speed": (0.0, 100.0, "a wind or air speed lies in"),
}


#: Smallest deviation from the local median that can be a spike, per quantity (canonical units).
#: Quantities not listed (flow, power, irradiance, energy) legitimately jump and are not screened.
OUTLIER_FLOORS: dict[str, float] = {
    "temperature": 1.5,
    "relative_humidity": 10.0,
    "co2": 300.0,
    "pressure": 500.0,
}


#: How a real excursion's size grows with the time between readings, per quantity (canonical
#: units): (fastest rise or fall [unit/h], largest floor [unit]). The spike floor of a run of
#: readings is ``max(OUTLIER_FLOORS, slope * span / 2)``, at most the ceiling, ``span`` the time
#: from the reading before it to the reading after it
#: (:func:`thermocal.io.measurements.quality.spike_threshold`). Temperature: 10 K/h, three
#: times the fastest float-and-return of rooms between set points in EnergyPlus 25.2 twins of
#: NREL files (Golden and Tampa, January and July: 3.1 K above both neighbours read hourly,
#: 1.3 K every 30 min); 1.5 K up to 18 min between the neighbours (5-minute readings keep the
#: old floor), 10 K from 2 h (hourly readings): no room goes 10 K away and back between two
#: readings (a dropout to 0 C, a DS18B20's 85 C do). Quantities not listed keep their floor.
OUTLIER_SLOPES: dict[str, tuple[float, float]] = {
    "temperature": (10.0, 10.0),
}


#: Resampling operations (see the module docstring).
OPERATIONS: tuple[str, ...] = (
    "mean",
    "mean_linear",
    "last",
    "first",
    "min",
    "max",
    "sum",
    "count",
)


_DEFAULT_OPERATION = {"energy": "last"}


_NA_TOKENS = ["", "NA", "N/A", "NaN", "nan", "NAN", "null", "NULL", "None", "-", "#N/A"]


_TIME_CANDIDATES = ("time", "timestamp", "datetime", "date_time", "date", "zeit", "t")


_HEADER_UNIT = re.compile(r"^(?P<name>.*?)\s*[\[(](?P<unit>[^\[\]()]*)[\])]\s*$")


_TEMPERATURE_NAME = re.compile(
    r"(?i:temp|theta)|^[tT]($|[_\-\s\d])|^[tT][a-z]{1,2}$|^T[A-Z][a-z]|(^|_)[tT](_|$)"
)


_FLOW_NAME = re.compile(r"(?i)flow|durchfluss|^v_?dot|volume_?rate")


def _split_header_unit(column: str) -> tuple[str, str | None]:
    match = _HEADER_UNIT.match(str(column))
    if match and match.group("name").strip():
        return match.group("name").strip(), match.group("unit").strip()
    return str(column).strip(), None


def _resolve_unit(unit: str, where: str) -> str:
    if unit in UNITS:
        return unit
    folded = _UNITS_FOLDED.get(unit.casefold())
    if folded is not None:
        return folded
    close = difflib.get_close_matches(unit, list(UNITS), n=1)
    suggestion = f"; did you mean '{close[0]}'?" if close else ""
    raise ThermocalInputError(
        f"{where}: unknown unit '{unit}'{suggestion} (known units: {', '.join(UNITS)})"
    )


def _suggest(name: str, options: Sequence[str]) -> str:
    close = difflib.get_close_matches(name, list(options), n=1)
    return f"; did you mean '{close[0]}'?" if close else ""


def _guess_quantity(name: str) -> str | None:
    if _FLOW_NAME.search(name):
        return "flow"
    if _TEMPERATURE_NAME.search(name):
        return "temperature"
    return None


#: Temperatures a building's measurements can have (outdoor air included) [C].
PLAUSIBLE_TEMPERATURE = (-50.0, 60.0)


#: Mean indoor temperature a zone can have over a measured period [C]; outside, a unit slip.
INDOOR_MEAN_RANGE = (-30.0, 35.0)


#: A sensor whose mean differs from its neighbours' median by more than this is checked for a
#: unit slip [K] (an unheated cellar or attic may legitimately differ by 10-15 K).
NEIGHBOUR_TOLERANCE = 15.0


#: A converted mean this close to the neighbours' median identifies the unit slip [K].
UNIT_MATCH = 5.0


#: Unit slips of a temperature logged where degrees C are expected: (name, the unit to
#: declare, conversion of a mean to C).
TEMPERATURE_UNIT_SLIPS = (
    (
        "Kelvin?",
        "declare its unit as K (in the header, e.g. 'NAME [K]', a unit column, units= in "
        "Python, or measurements.temperature_unit: K in a retrofit configuration)",
        lambda v: v - 273.15,
    ),
    (
        "Fahrenheit?",
        "declare its unit as F (in the header, e.g. 'NAME [F]', a unit column, units= in "
        "Python, or measurements.temperature_unit: F in a retrofit configuration)",
        lambda v: (v - 32.0) * 5.0 / 9.0,
    ),
    (
        "tenths of a degree? (202 for 20.2 C)",
        "divide its values by 10 in the file",
        lambda v: v / 10.0,
    ),
    (
        "hundredths of a degree? (2020 for 20.20 C)",
        "divide its values by 100 in the file",
        lambda v: v / 100.0,
    ),
)


def temperature_unit_slip(
    mean: float,
    reference: float | None = None,
    *,
    plausible: tuple[float, float] = INDOOR_MEAN_RANGE,
):
    """The unit slip that explains a temperature read as C best, or None when it is plausible.

    Parameters
    ----------
    mean : float
        The (mean) value as read [C].
    reference : float, optional
        What it should be near: the neighbouring sensors' median or the sensor's typical day
        [C] (None: 20 C is used to rank the candidates). A reference outside ``plausible`` is
        read in the same wrong unit and is no yardstick: it is ignored.
    plausible : (float, float)
        Range of a plausible value [C]. A value outside it is always a slip (the best
        candidate, or "not an indoor temperature" when none fits); one inside it is a slip
        only when it is more than :data:`NEIGHBOUR_TOLERANCE` from ``reference`` and a
        conversion brings it within :data:`UNIT_MATCH` of it.

    Returns
    -------
    tuple or None
        ``(label, remedy, value in C)``: e.g. ``("Fahrenheit?", "declare its unit as F (...)",
        10.0)``; ``NAME`` in the remedy stands for the column.
    """
    low, high = plausible
    if reference is not None and not low <= reference <= high:
        reference = None
    is_plausible = low <= mean <= high
    if is_plausible and (reference is None or abs(mean - reference) <= NEIGHBOUR_TOLERANCE):
        return None
    candidates = temperature_unit_candidates(mean, reference, plausible=plausible)
    if candidates:
        return candidates[0]
    return None if is_plausible else ("not an indoor temperature", "check its unit", float("nan"))


def temperature_unit_candidates(
    mean: float,
    reference: float | None = None,
    *,
    plausible: tuple[float, float] = INDOOR_MEAN_RANGE,
) -> list[tuple[str, str, float]]:
    """Every unit slip that makes a temperature read as C plausible, the likeliest first.

    Parameters
    ----------
    mean : float
        The (mean) value as read [C].
    reference : float, optional
        What it should be near [C] (:func:`temperature_unit_slip`); None, or outside
        ``plausible`` (read in the same wrong unit), ranks the slips by how common they are.
    plausible : (float, float)
        Range of a plausible value [C].

    Returns
    -------
    list of (label, remedy, value in C)
        With a reference: the slips within :data:`UNIT_MATCH` of it (most common first), then
        the others nearest first. Without: every slip whose value is plausible, most common
        first (an outdoor 281 K is 8 C, not 28.1 C in tenths; a room's 285 K is 12 C before
        28.5 C in tenths). A plausible ``mean`` lists only slips within :data:`UNIT_MATCH` of
        the reference (20 C without one).
    """
    low, high = plausible
    if reference is not None and not low <= reference <= high:
        reference = None
    target = 20.0 if reference is None else reference
    is_plausible = low <= mean <= high
    fits = []
    for label, remedy, convert in TEMPERATURE_UNIT_SLIPS:  # in order of how common the slip is
        value = convert(mean)
        if low <= value <= high and (not is_plausible or abs(value - target) <= UNIT_MATCH):
            fits.append((abs(value - target), label, remedy, value))
    if reference is None:
        return [fit[1:] for fit in fits]
    close = [fit for fit in fits if fit[0] <= UNIT_MATCH]
    far = sorted(fit for fit in fits if fit[0] > UNIT_MATCH)
    return [fit[1:] for fit in close + far]


#: Median of a building's indoor sensors [C] that a unit conversion must give to be named when
#: the log as a whole is in another unit (:func:`log_unit_slips`): a building's rooms together
#: average 10-35 C, heated, cooled or free-floating in a mild season; a conversion giving a
#: median of 2.9 C (285 read as hundredths) or 5.7 C (57 read as tenths) is not named.
BUILDING_MEDIAN_RANGE = (10.0, 35.0)


def log_unit_slips(mean: float, median: float) -> list[tuple[str, str, float, float]]:
    """The unit slips that explain a log whose sensors read no indoor temperature as C.

    When the other sensors' median is itself outside :data:`INDOOR_MEAN_RANGE`, the whole log
    is in another unit and the sensors cannot be compared with each other: a slip is named when
    it makes the sensor's mean an indoor temperature and the median a building's
    (:data:`BUILDING_MEDIAN_RANGE`). 290 fits both Kelvin (16.9 C) and tenths (29.0 C): both are
    named, the more common first.

    Parameters
    ----------
    mean : float
        One sensor's mean as read [C].
    median : float
        The median of the other sensors' means as read [C].

    Returns
    -------
    list of (label, remedy, the sensor's mean in C, the median in C)
        Most common slip first (:data:`TEMPERATURE_UNIT_SLIPS`); empty when none fits.
    """
    slips = []
    for label, remedy, convert in TEMPERATURE_UNIT_SLIPS:
        value, typical = convert(mean), convert(median)
        in_room = INDOOR_MEAN_RANGE[0] <= value <= INDOOR_MEAN_RANGE[1]
        in_building = BUILDING_MEDIAN_RANGE[0] <= typical <= BUILDING_MEDIAN_RANGE[1]
        if in_room and in_building:
            slips.append((label, remedy, value, typical))
    return slips


def _convert_units(
    name: str,
    values: np.ndarray,
    *,
    unit: str | None,
    quantity: str | None,
    source: str,
    column_label: str,
    lines: np.ndarray | None,
) -> tuple[np.ndarray, str | None, str, str | None]:
    """Convert to canonical units; returns (values, quantity, canonical unit, conversion note)."""
    where = f"{source}, column '{column_label}'"
    finite = values[np.isfinite(values)]
    if unit is not None:
        unit = _resolve_unit(unit, where)
        unit_quantity, factor, offset, canonical = UNITS[unit]
        if quantity is not None and quantity != unit_quantity:
            raise ThermocalInputError(
                f"{where}: declared quantity '{quantity}' does not match unit '{unit}' "
                f"({unit_quantity})"
            )
        quantity = unit_quantity
        if quantity == "temperature" and canonical == unit and finite.size:
            low_share = np.mean(finite < 100.0)
            if low_share < 0.5 and np.median(finite) > 150.0:
                median = float(np.median(finite))
                slip = temperature_unit_slip(median, plausible=PLAUSIBLE_TEMPERATURE)
                label, remedy = (
                    ("Kelvin?", "declare [K] if they are")
                    if slip is None or slip[0] == "not an indoor temperature"
                    else slip[:2]
                )
                raise ThermocalInputError(
                    f"{where}: the unit is declared as {unit} but the values (median "
                    f"{median:.1f}) look like {label.replace('?', '')}; "
                    f"{remedy.replace('NAME', name)}, or fix the values"
                )
        if quantity == "temperature" and unit == "K" and finite.size:
            median = float(np.median(finite))
            if median < 150.0:  # below -123 C as Kelvin: degrees C (or F) declared as K
                raise ThermocalInputError(
                    f"{where}: the unit is declared as K but the values (median {median:.1f}) "
                    f"would be {median - 273.15:.0f} C: they are not Kelvin (degrees C?); "
                    "remove the K declaration (the header's [K], the unit column, units= in "
                    "Python, measurements.temperature_unit in a retrofit configuration) or fix "
                    "the values"
                )
        note = None
        if factor != 1.0 or offset != 0.0:
            values = values * factor + offset
            note = f"{unit} -> {canonical}"
        return values, quantity, canonical, note
    if quantity is not None and quantity not in CANONICAL_UNITS:
        raise ThermocalInputError(
            f"{where}: unknown quantity '{quantity}'{_suggest(quantity, CANONICAL_UNITS)} "
            f"(known: {', '.join(CANONICAL_UNITS)})"
        )
    if quantity is None:
        quantity = _guess_quantity(name)
    if quantity == "temperature" and finite.size:
        celsius_like = finite < 100.0
        kelvin_like = (finite > 200.0) & (finite < 400.0)
        if kelvin_like.any() and celsius_like.any():
            index_c = int(np.flatnonzero(np.isfinite(values) & (values < 100.0))[0])
            index_k = int(np.flatnonzero((values > 200.0) & (values < 400.0))[0])
            line_c = f" (line {lines[index_c]})" if lines is not None else ""
            line_k = f" (line {lines[index_k]})" if lines is not None else ""
            raise ThermocalInputError(
                f"{where}: temperature unit ambiguous: {values[index_c]:g}{line_c} looks like "
                f"Celsius but {values[index_k]:g}{line_k} like Kelvin "
                f"({int(celsius_like.sum())} values below 100, {int(kelvin_like.sum())} above "
                f"200); declare the unit ('{name} [K]' in the header or units={{'{name}': 'K'}}) "
                f"and fix the values that are in the other unit"
            )
        median_c = float(np.median(finite)) - 273.15
        plausible_kelvin = PLAUSIBLE_TEMPERATURE[0] <= median_c <= PLAUSIBLE_TEMPERATURE[1]
        if kelvin_like.all() and plausible_kelvin:  # 202 is 20.2 C in tenths, not -71 C
            return (
                values - 273.15,
                quantity,
                "C",
                f"K -> C (detected: values {finite.min():g} to {finite.max():g}, no unit declared)",
            )
    if quantity == "flow" and finite.size and np.nanmax(np.abs(finite)) > 0.1:
        raise ThermocalInputError(
            f"{where}: flow without a declared unit and values up to {np.max(finite):g}, "
            f"impossible in m3/s for a building; declare the unit in the header ('{name} [l/h]', "
            f"'[m3/h]') or with units={{'{name}': 'l/h'}}"
        )
    canonical = CANONICAL_UNITS.get(quantity, "") if quantity else ""
    note = None
    if quantity == "flow":
        note = "no unit declared: assumed m3/s"
    return values, quantity, canonical, note


def _as_timedelta(value: Any, name: str) -> pd.Timedelta | None:
    if value is None:
        return None
    from thermocal.textformat import unitless_duration

    if unitless_duration(value):
        raise ThermocalInputError(
            f"{name} = {value!r} has no unit (it would be read as nanoseconds); write it with "
            f"one, e.g. '{value}min' or '{value}h'"
        )
    try:
        delta = pd.Timedelta(value)
    except (ValueError, TypeError):
        raise ThermocalInputError(
            f"{name} = {value!r} is not a duration; use e.g. '5min', '1h' or a Timedelta"
        ) from None
    if pd.isna(delta) or delta <= pd.Timedelta(0):
        raise ThermocalInputError(f"{name} = {value!r} must be a positive duration")
    return delta
