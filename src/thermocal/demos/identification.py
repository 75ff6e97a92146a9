"""Demo data of the identification workflow: a "real" clinic and its sensor network.

The building is :func:`thermocal.demos.buildings.clinic` (180 rooms in six rows along three
corridors, each corridor cut into two zones: 186 zones, 70 envelope parameters). It is NOT
shipped: the identification model is ``clinic()`` with its nominal parameters. The "real"
building differs from it in two ways that the model does not know about:

1. **Envelope.** :data:`TRUE_FACTORS` multiplies ten influential envelope parameters (wall
   insulation, exterior windows, roof insulation, infiltration of three groups, carpet on the
   slab, roof decking). The truth lives in ``truth.json``, read only by the demo report and the
   tests.
2. **Unknown loads** (the paper's Q_Int + Q_HVAC), delivered to the zone air through
   :meth:`Simulation.step` (the same as ``Simulation.run(heat_input=...)``):

   - *idle load*, CONSTANT all the time, per zone: rooms 1-3 W/m2 (uniform draw), 12
     equipment rooms 6-10 W/m2 (refrigerators, servers), corridors 1 W/m2 (emergency
     lighting). It is the only load in unoccupied hours (the paper expects such constant loads).
   - *internal gains*, occupied hours only, rooms other than equipment rooms: 10-15 W/m2
     (people + equipment + lights; uniform per room) times a day profile (weekdays 04-07 h 0.2
     cleaning, 07-08 h 0.6, 08-17 h 1.0 but 0.7 at 12-13 h, 17-20 h 0.4; Saturdays 04-08 h 0.2,
     08-11 h 0.6) times a factor per room and day, uniform in [0.8, 1.1].
   - *HVAC*, occupied hours only (the AHUs are off otherwise): the paper's dual-duct mixing
     boxes under pneumatic thermostats, simulated in closed loop (:func:`_operate`). Box
     capacity ``rho c V = s (1.53 H + 0.5 A)`` [W/K] with ``H`` the zone's nominal heat loss
     coefficient to outdoors and ground (:func:`zone_heat_loss_coefficients`), ``A`` its floor
     area and ``s`` a log-normal sizing factor (median 1, sigma 0.3); thermostat set point
     N(21.5, 1.0) C clipped to [19, 24]; hot deck reset 40 C at -10 C outdoors to 28 C at
     15 C (:func:`hot_deck_temperature`), cold deck 13 C; 3 boxes stuck on the hot deck and 3
     on the cold deck. So the heat depends on the outdoor temperature and differs per room:
     some rooms overheated, some cold, as in the paper's building.

   ``generate()`` returns every zone's loads (``loads``, ``components``) and the per-zone table
   (``zones``); the building totals per step are shipped in ``true_loads.parquet``.

Occupancy (the case study's): occupied = NOT (20:00-04:00 every night, 11:00-20:00 on Saturdays, all
Sunday) in local standard time; :func:`occupancy_mask`.

Simulation: 5-minute steps, January of the weather file's year (default pvlib's TMY3
``723170TYA.CSV``, Greensboro NC, year 2001: [2001-01-01, 2001-02-01) local standard time,
UTC-05:00). The 14 days before the period are simulated with the same loads so that the
building enters January in its operating state; for a one-year weather file they are the last
14 days of its December moved one year back (the usual wrap of a typical year). The run
starts with the simulation's own 7-day warm-up on the first pre-run day. Zone air temperature
(``SimulationResult.air_temperature`` row k = the state at the END of step k, i.e. at
``times[k] + 5 min``) is what the sensors see.

Sensor network (the case study: 82 Inovonics EN 1723 transmitters): 82 sensors ``S01`` ... ``S82``
in 79 rooms (three rooms carry two sensors, meant to be averaged); corridors and the 12
equipment rooms have none. Each sensor:

- sees the zone air temperature plus a constant offset drawn from a normal distribution with
  standard deviation 0.22 C truncated to +-0.44 C (the datasheet's "typical accuracy 0.44 C"
  read as a 2-sigma bound; redrawn outside), plus white noise of 0.02 C at every 5-minute
  model output; between outputs the signal is linear in time;
- reports every 5 minutes (its own heartbeat phase, a whole number of seconds in [0, 300)) or
  as soon as its reading differs by 0.28 C from the reading at its last report, whichever
  comes first; the heartbeat restarts at every report; crossings are stamped at the next whole
  second, values are quantised to 0.05 C;
- the log covers [period start - 1 h, period end + 1 h) so that the period's first and last
  5-minute intervals are fully covered.

Defects (drawn with the seed, listed in ``truth.json`` and ``metadata["defects"]``): six
dropouts (lost radio packets, 30 min to 4 h, in five sensors: reports inside the window are
lost, the sensor keeps running) and one dead sensor (stops reporting for good after 9-14
days). Resample with a ``max_gap`` of about 10 minutes to see them as gaps:
``resample_measurements(raw, "5min", max_gap="10min")``.

Shipped files (``src/thermocal/data/identification_demo/``, :data:`DEMO_FOLDER`)
------------------------------------------------------------------------------
``sensors.parquet``
    The log, long layout: ``time`` (tz-aware timestamps, UTC-05:00), ``sensor``, ``value``
    [C], ``unit`` ("C"), sorted by time then sensor. Read with
    ``thermocal.io.measurements.read_measurements(path, layout="long")``.
``mapping.yaml``
    Sensors -> zones, and named substitutes for zones without a sensor::

        sensors:            # every sensor -> the zone it hangs in (several per zone: averaged)
          S01: Room 2
          S02: Room 4
          S03: Room 4
        zones:              # optional: zones without a sensor that use another zone's data
          Room 29: {use: Room 27}

    ``sensors`` is required, a mapping of sensor name -> zone name (strings). ``zones`` is
    optional, a mapping of zone name -> ``{use: <zone with data>}`` (the parser,
    :func:`thermocal.identification.sensors.load_mapping`, also accepts ``ignore: [S77]``).
    ``unsensed: neighbour``: zones in neither section take an automatically chosen adjacent zone
    with a sensor (the method's rule; without it they would float), and ``identified_heat``
    puts the identified heat into the air (``radiant_fraction: 0``), where the generator puts
    its loads. In this demo
    the named substitutes (31) are the unsensored rooms without a sensored room beside them in
    the same row (the nearest sensored room of the row); the 6 corridor zones and the other 76
    unsensored rooms (equipment rooms included) are left to the automatic choice.
``truth.json``
    ``parameters`` (per parameter: nominal, true, factor, unit), ``sensor_offsets`` [C],
    ``defects``, ``loads`` (building totals [W] and per-zone summaries), ``generator``.
``true_loads.parquet``
    Building totals of the unknown loads per 5-minute step (labelled by its start) [W]:
    ``idle``, ``gains``, ``hvac``, ``total`` (demo report and tests only).
``README.md``
    How the data were made (generator, seed, weather, the truth table).

Regenerate: ``python -m thermocal.demos.identification --write DIR [--weather FILE]
[--seed N]``. Everything is deterministic with the seed (numpy ``default_rng``).
"""

from __future__ import annotations

import argparse
import json
import time as _time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from numba import njit

from thermocal.errors import ThermocalInputError

__all__ = [
    "DEFAULT_SEED",
    "DEMO_FOLDER",
    "TRUE_FACTORS",
    "generate",
    "load_demo",
    "occupancy_mask",
    "true_parameters",
    "zone_heat_loss_coefficients",
    "write_demo",
]

#: Folder of the shipped demo data.
DEMO_FOLDER = Path(__file__).resolve().parent.parent / "data" / "identification_demo"
#: Seed of the shipped data.
DEFAULT_SEED = 2013
STEP = "5min"
PRE_RUN_DAYS = 14
LOG_MARGIN = pd.Timedelta("1h")
REPORT_INTERVAL = 300  # [s] heartbeat
REPORT_THRESHOLD = 0.28  # [C] report on this change
QUANTUM = 0.05  # [C] reported resolution
OFFSET_STD = 0.22  # [C] sensor offset, normal ...
OFFSET_LIMIT = 0.44  # [C] ... truncated to +- this
NOISE_STD = 0.02  # [C] white noise at each model output
N_SENSOR_ROOMS = 79
N_DOUBLE = 3
N_EQUIPMENT = 12
DROPOUT_MINUTES = (30, 50, 90, 140, 200, 240)  # [min] lost-packet windows
THROTTLING_RANGE = 3.0  # [K] pneumatic thermostat
THERMOSTAT_LAG = 600.0  # [s] sensing element
ACTUATOR_LAG = 1200.0  # [s] pneumatic damper actuator
SOFT_START = 10.0  # [W/m2 per step] largest change of a box's heat from one step to the next

#: Factor true / nominal of the envelope parameters of the "real" clinic (others are nominal).
TRUE_FACTORS: dict[str, float] = {
    "material/R16 insulation/resistance": 0.6,  # compressed / missing batts
    "window/Exterior window/u_value": 1.25,  # worn seals, aluminium frames
    "window/Exterior window/shgc": 0.6,  # interior blinds
    "material/Roof insulation/conductivity": 1.5,  # wet insulation
    "material/Roof insulation/thickness": 0.8,
    "infiltration/row 1 west/ach": 2.0,  # leaky south-west wing
    "infiltration/row 6 east/ach": 1.6,
    "infiltration/corridor 1/ach": 1.5,  # exterior doors
    "material/Carpet/conductivity": 0.7,  # thicker carpet and underlay on the slab
    "material/Metal decking/thickness": 3.0,
}


_RHO_CP_AIR = 1.2 * 1005.0  # [J/(m3 K)]


def _default_weather_path() -> Path:
    from thermocal.demos.retrofit import pvlib_weather_path

    return pvlib_weather_path("723170TYA.CSV")


def parameter_unit(name: str) -> str:
    """Unit of a :meth:`Building.parameters` name (from its last part)."""
    from thermocal.multizone.parameters import parameter_unit as unit

    return unit(name, "-")


def true_parameters(building) -> dict[str, float]:
    """The perturbed parameters of the "real" building: nominal x :data:`TRUE_FACTORS`.

    Parameters
    ----------
    building : Building
        ``buildings.clinic()`` (nominal).

    Returns
    -------
    dict
        Parameter name -> true value (only the perturbed ones; pass to
        ``building.with_parameters``).
    """
    nominal = building.parameters()
    missing = [name for name in TRUE_FACTORS if name not in nominal]
    if missing:
        raise ThermocalInputError(
            f"true_parameters: the building '{building.name}' has no parameters {missing}; "
            "the demo truth is defined for buildings.clinic()"
        )
    return {name: float(nominal[name]) * factor for name, factor in TRUE_FACTORS.items()}


# ----------------------------------------------------------------------------------------------
# occupancy
# ----------------------------------------------------------------------------------------------
def _occupancy_mask(times) -> np.ndarray:
    index = pd.DatetimeIndex(times)
    hour = index.hour.to_numpy() + index.minute.to_numpy() / 60.0
    weekday = index.day_of_week.to_numpy()  # Monday = 0
    night = (hour >= 20.0) | (hour < 4.0)
    saturday = (weekday == 5) & (hour >= 11.0)
    sunday = weekday == 6
    return ~(night | saturday | sunday)


def occupancy_mask(times) -> np.ndarray:
    """Occupied steps of the case study's clinic (local time of ``times``).

    Unoccupied: 20:00-04:00 every night, 11:00-20:00 on Saturdays, all Sunday; occupied
    otherwise. A step labelled ``t`` is judged by ``t`` (its start).

    Parameters
    ----------
    times : DatetimeIndex or array-like of timestamps

    Returns
    -------
    numpy.ndarray of bool
    """
    try:  # the identification package's schedule when the lead has written it
        from thermocal.identification.occupancy import occupancy_mask as shared
    except ImportError:
        return _occupancy_mask(times)
    try:
        return np.asarray(shared(times), dtype=bool)
    except TypeError:
        return _occupancy_mask(times)


# ----------------------------------------------------------------------------------------------
# the building's zones: kinds, heat loss coefficients
# ----------------------------------------------------------------------------------------------
def _room_number(zone: str) -> int | None:
    if zone.startswith("Room "):
        return int(zone.split()[1])
    return None


def _rows(building) -> list[list[str]]:
    """Rooms per row, west to east (``clinic()`` numbers them row by row)."""
    rooms = sorted((z for z in building.zones if _room_number(z) is not None), key=_room_number)
    n_rows = 6
    per_row = len(rooms) // n_rows
    return [rooms[r * per_row : (r + 1) * per_row] for r in range(n_rows)]


def zone_heat_loss_coefficients(building) -> dict[str, float]:
    """Per zone: U A to outdoors and ground (ISO 6946 surface resistances) + infiltration [W/K]."""
    from thermocal.multizone.model import construction_u_value

    windows_by_surface: dict[str, list] = {}
    for w in building.windows.values():
        windows_by_surface.setdefault(w.surface, []).append(w)
    out = {name: 0.0 for name in building.zones}
    for s in building.surfaces.values():
        if s.boundary not in ("outdoors", "ground"):
            continue
        if s.tilt < 60:
            r_si = 0.10
        elif s.tilt > 120:
            r_si = 0.17
        else:
            r_si = 0.13
        u = construction_u_value(
            building.construction_layers(s.construction),
            inside_resistance=r_si,
            outside_resistance=0.04 if s.boundary == "outdoors" else 0.0,
        )
        out[s.zone] += u * building.net_area(s.name)
        for w in windows_by_surface.get(s.name, []):
            out[s.zone] += building.window_types[w.window_type].u_value * w.area
    for name, zone in building.zones.items():
        out[name] += zone.infiltration_ach * zone.volume / 3600.0 * _RHO_CP_AIR
    return out


# ----------------------------------------------------------------------------------------------
# the sensor network
# ----------------------------------------------------------------------------------------------
def _design_network(building, rng: np.random.Generator) -> dict:
    """Equipment rooms, sensored rooms, sensors, offsets, phases, named substitutes."""
    rows = _rows(building)
    rooms = [r for row in rows for r in row]
    # equipment rooms: two per row, not at the row ends
    equipment: list[str] = []
    for row in rows:
        picks = rng.choice(np.arange(2, len(row) - 2), size=N_EQUIPMENT // len(rows), replace=False)
        equipment += [row[i] for i in sorted(picks)]
    candidates = [r for r in rooms if r not in set(equipment)]
    # sensored rooms: stratified by row (paper: "strategically placed" over the whole building)
    per_row = np.full(len(rows), N_SENSOR_ROOMS // len(rows))
    per_row[: N_SENSOR_ROOMS - per_row.sum()] += 1
    sensored: list[str] = []
    for r, row in enumerate(rows):
        pool = [z for z in row if z in set(candidates)]
        picks = rng.choice(len(pool), size=int(per_row[r]), replace=False)
        sensored += [pool[i] for i in sorted(picks)]
    sensored_set = set(sensored)
    doubles = set(rng.choice(sorted(sensored, key=_room_number), size=N_DOUBLE, replace=False))
    sensors: list[tuple[str, str]] = []
    for zone in sorted(sensored, key=_room_number):
        for _ in range(2 if zone in doubles else 1):
            sensors.append((f"S{len(sensors) + 1:02d}", zone))
    n = len(sensors)
    offsets = rng.normal(0.0, OFFSET_STD, size=n)
    while np.any(np.abs(offsets) > OFFSET_LIMIT):
        bad = np.abs(offsets) > OFFSET_LIMIT
        offsets[bad] = rng.normal(0.0, OFFSET_STD, size=int(bad.sum()))
    phases = rng.integers(0, REPORT_INTERVAL, size=n)
    # named substitutes: unsensored rooms without a sensored neighbour in their row
    substitutes: dict[str, str] = {}
    for row in rows:
        for i, zone in enumerate(row):
            if zone in sensored_set:
                continue
            beside = [row[j] for j in (i - 1, i + 1) if 0 <= j < len(row)]
            if any(z in sensored_set for z in beside):
                continue
            with_data = [j for j, z in enumerate(row) if z in sensored_set]
            nearest = min(with_data, key=lambda j: (abs(j - i), j))
            substitutes[zone] = row[nearest]
    return {
        "equipment": equipment,
        "sensors": sensors,
        "offsets": offsets,
        "phases": phases,
        "substitutes": substitutes,
    }


def _draw_defects(sensor_names: list[str], start, end, rng: np.random.Generator) -> dict:
    n = len(sensor_names)
    order = rng.permutation(n)
    dead = sensor_names[order[0]]
    dead_after = (
        start + pd.Timedelta(days=9) + pd.Timedelta(seconds=int(rng.integers(0, 5 * 86400)))
    )
    dropout_sensors = [sensor_names[i] for i in order[1:6]]
    durations = rng.permutation(DROPOUT_MINUTES)
    dropouts = []
    for k in range(len(DROPOUT_MINUTES)):
        sensor = dropout_sensors[k % len(dropout_sensors)]
        minutes = int(durations[k])
        begin = start + pd.Timedelta(
            seconds=int(rng.integers(86400, (end - start).days * 86400 - 86400))
        )
        dropouts.append(
            {"sensor": sensor, "start": begin, "end": begin + pd.Timedelta(minutes=minutes)}
        )
    dropouts.sort(key=lambda d: (d["sensor"], d["start"]))
    return {"dead_sensor": dead, "dead_after": dead_after, "dropouts": dropouts}


@njit(cache=True)
def _sample_sensor(t_grid, y, t_begin, t_end, phase, interval, threshold):  # pragma: no cover
    """Reports of one sensor: every ``interval`` [s] or on a ``threshold`` [C] change.

    ``t_grid`` [s] and ``y`` [C]: the reading at the model outputs, linear in between. The
    first report is at ``t_begin + phase``; the heartbeat restarts at every report; a crossing
    is stamped at the next whole second. Returns report times [s] and readings (not quantised).
    """
    n_seg = len(t_grid) - 1
    cap = int((t_end - t_begin) / 1.0) // 60 + 16
    times = np.empty(cap)
    values = np.empty(cap)
    t_last = t_begin + phase
    j = np.searchsorted(t_grid, t_last, side="right") - 1
    v_last = y[j] + (y[j + 1] - y[j]) * (t_last - t_grid[j]) / (t_grid[j + 1] - t_grid[j])
    times[0] = t_last
    values[0] = v_last
    m = 1
    while True:
        t_hb = t_last + interval
        t_next = t_hb
        jj = j
        while jj < n_seg and t_grid[jj] < t_hb:
            ta = max(t_grid[jj], t_last)
            tb = min(t_grid[jj + 1], t_hb)
            slope = (y[jj + 1] - y[jj]) / (t_grid[jj + 1] - t_grid[jj])
            ya = y[jj] + slope * (ta - t_grid[jj])
            yb = y[jj] + slope * (tb - t_grid[jj])
            if abs(yb - v_last) >= threshold:
                if abs(ya - v_last) >= threshold:
                    tc = ta
                else:
                    target = v_last + threshold if yb > v_last else v_last - threshold
                    tc = ta + (target - ya) / (yb - ya) * (tb - ta)
                tc = np.ceil(tc)
                if tc <= t_last:
                    tc = t_last + 1.0
                if tc < t_next:
                    t_next = tc
                break
            jj += 1
        if t_next >= t_end:
            break
        j = np.searchsorted(t_grid, t_next, side="right") - 1
        if j >= n_seg:
            break
        v_last = y[j] + (y[j + 1] - y[j]) * (t_next - t_grid[j]) / (t_grid[j + 1] - t_grid[j])
        t_last = t_next
        if m == cap:
            break
        times[m] = t_last
        values[m] = v_last
        m += 1
    return times[:m], values[:m]


def _quantise(values: np.ndarray) -> np.ndarray:
    return np.round(np.round(values / QUANTUM) * QUANTUM, 2)


# ----------------------------------------------------------------------------------------------
# weather and loads
# ----------------------------------------------------------------------------------------------
def _period(weather: pd.DataFrame):
    tz = weather.index.tz
    year = int(weather.index[0].year)
    start = pd.Timestamp(year=year, month=1, day=1, tz=tz)
    if weather.index[0] > start:  # e.g. a file starting later: its first full month
        first = weather.index[0]
        start = pd.Timestamp(
            year=first.year, month=first.month, day=1, tz=tz
        ) + pd.offsets.MonthBegin(1)
    return start, start + pd.offsets.MonthBegin(1)


def _extended_weather(
    weather: pd.DataFrame, start: pd.Timestamp
) -> tuple[pd.DataFrame, pd.Timestamp, str]:
    """Weather covering ``start - PRE_RUN_DAYS``: the file itself, or its December wrapped."""
    pre = start - pd.Timedelta(days=PRE_RUN_DAYS)
    if weather.index[0] <= pre:
        return weather, pre, "pre-run from the weather file itself"
    next_year = pre + pd.DateOffset(years=1)
    tail = weather.loc[
        (weather.index >= next_year) & (weather.index < start + pd.DateOffset(years=1))
    ]
    expected = int(round(PRE_RUN_DAYS * pd.Timedelta("1D") / (weather.index[1] - weather.index[0])))
    if len(tail) >= expected and tail.index[0] == next_year:
        tail = tail.copy()
        tail.index = tail.index - pd.DateOffset(years=1)
        return (
            pd.concat([tail, weather.loc[weather.index >= start]]),
            pre,
            f"pre-run: the file's last {PRE_RUN_DAYS} days moved one year back (typical-year wrap)",
        )
    return weather, start, "no pre-run (the weather file does not cover it): warm-up only"


def _gains_profile(times: pd.DatetimeIndex, occupied: np.ndarray) -> np.ndarray:
    hour = times.hour.to_numpy() + times.minute.to_numpy() / 60.0
    saturday = times.day_of_week.to_numpy() == 5
    weekday = np.select(
        [hour < 4, hour < 7, hour < 8, hour < 12, hour < 13, hour < 17, hour < 20],
        [0.0, 0.2, 0.6, 1.0, 0.7, 1.0, 0.4],
        0.0,
    )
    sat = np.select([hour < 4, hour < 8, hour < 11], [0.0, 0.2, 0.6], 0.0)
    return np.where(saturday, sat, weekday) * occupied


def hot_deck_temperature(temp_out):
    """Hot-deck reset of the dual-duct AHUs: 40 C at -10 C outdoors, 28 C at 15 C [C]."""
    t = np.asarray(temp_out, dtype=float)
    return np.clip(40.0 + (t + 10.0) * (28.0 - 40.0) / 25.0, 28.0, 40.0)


def _zone_table(building, equipment, rng: np.random.Generator) -> pd.DataFrame:
    """Per zone: kind, loads and the mixing box (drawn in a fixed order)."""
    names = list(building.zones)
    nz = len(names)
    equipment = set(equipment)
    h = zone_heat_loss_coefficients(building)
    area = np.array([building.zones[z].floor_area for z in names])
    kind, idle_density, gains_density = [], np.empty(nz), np.zeros(nz)
    for i, z in enumerate(names):
        if z.startswith("Corridor"):
            kind.append("corridor")
            idle_density[i] = 1.0
        elif z in equipment:
            kind.append("equipment")
            idle_density[i] = rng.uniform(6.0, 10.0)
        else:
            kind.append("room")
            idle_density[i] = rng.uniform(1.0, 3.0)
            gains_density[i] = rng.uniform(10.0, 15.0)
    h_arr = np.array([h[z] for z in names])
    sizing = np.exp(rng.normal(0.0, 0.3, size=nz))
    setpoint = np.clip(rng.normal(21.5, 1.0, size=nz), 19.0, 24.0)
    # box capacity rho c V [W/K]: full hot deck (40 C) holds 21 C at -8 C outdoors, x sizing
    capacity = sizing * (h_arr * 29.0 / 19.0 + 0.5 * area)
    stuck = np.full(nz, "", dtype=object)
    rooms = [i for i, k in enumerate(kind) if k == "room"]
    picks = rng.choice(rooms, size=6, replace=False)
    stuck[picks[:3]] = "hot"
    stuck[picks[3:]] = "cold"
    return pd.DataFrame(
        {
            "kind": kind,
            "floor_area": area,
            "heat_loss_coefficient": h_arr,
            "idle": idle_density * area,
            "gains_density": gains_density,
            "box_capacity": capacity,
            "box_sizing": sizing,
            "setpoint": setpoint,
            "stuck": stuck,
        },
        index=pd.Index(names, name="zone"),
    )


def _operate(sim, zones: pd.DataFrame, temp_out, rng: np.random.Generator):
    """Run the "real" clinic step by step with its thermostats: the unknown loads [W].

    Mixing box per zone (occupied hours only; the AHUs are off otherwise): supply air
    ``x T_hot + (1 - x) T_cold`` (cold deck 13 C), ``x = clip(0.5 + (T_set - T_s) / 3 K, 0, 1)``
    from a pneumatic thermostat with a 3 K throttling range that senses the air temperature
    through a 10-minute first-order lag ``T_s``, moved by a damper actuator with a 20-minute
    lag; heat ``rho c V (T_supply - T_s)`` (the lagged room temperature: with the air
    temperature of the previous step this explicit loop oscillates in rooms that start cold).
    Stuck boxes hold ``x = 1`` (hot) or ``x = 0`` (cold). The heat of a box changes by at
    most :data:`SOFT_START` (10 W/m2) from one 5-minute step to the next (fan ramp and coil
    warm-up at the AHU start; it also keeps the large Monday-morning heat steps from exciting
    the lagged TARP convection correction of the multi-zone kernel, which oscillates when a
    cold room receives several kW at once).
    """
    times = sim.times
    n, nz = len(times), len(zones)
    occupied = occupancy_mask(times)
    days = (times.normalize() - times[0].normalize()).days.to_numpy()
    day_factor = rng.uniform(0.8, 1.1, size=(int(days.max()) + 1, nz))
    gains = (
        _gains_profile(times, occupied)[:, None]
        * day_factor[days]
        * (zones["gains_density"] * zones["floor_area"]).to_numpy()[None, :]
    )
    idle = zones["idle"].to_numpy()
    capacity = zones["box_capacity"].to_numpy()
    setpoint = zones["setpoint"].to_numpy()
    stuck = zones["stuck"].to_numpy()
    hot = hot_deck_temperature(temp_out)
    cold = 13.0
    dt = sim.dt
    lag = dt / (THERMOSTAT_LAG + dt)
    stroke = dt / (ACTUATOR_LAG + dt)
    x = np.full(nz, 0.5)
    ramp = SOFT_START * zones["floor_area"].to_numpy()  # [W per step]
    hvac = np.zeros((n, nz))
    air = np.empty((n, nz))
    sim.reset(free_float=True)
    t_air = sensed = None  # the first step (00:00 of the pre-run) is unoccupied
    for k in range(n):
        if t_air is not None:
            sensed = t_air.copy() if sensed is None else sensed + lag * (t_air - sensed)
            if occupied[k]:
                target = np.clip(0.5 + (setpoint - sensed) / THROTTLING_RANGE, 0.0, 1.0)
                x = x + stroke * (target - x)
                x = np.where(stuck == "hot", 1.0, np.where(stuck == "cold", 0.0, x))
                supply = x * hot[k] + (1.0 - x) * cold
                wanted = capacity * (supply - sensed)
                hvac[k] = hvac[k - 1] + np.clip(wanted - hvac[k - 1], -ramp, ramp)
        t_air = sim.step(idle + gains[k] + hvac[k])
        air[k] = t_air
    components = {"idle": idle, "gains": gains, "hvac": hvac}
    loads = pd.DataFrame(idle[None, :] + gains + hvac, index=times, columns=zones.index)
    air = pd.DataFrame(air, index=times, columns=zones.index)
    return loads, air, components


# ----------------------------------------------------------------------------------------------
# generation
# ----------------------------------------------------------------------------------------------
def generate(weather_path=None, seed: int = DEFAULT_SEED) -> dict:
    """Simulate the "real" clinic and its sensor network.

    Parameters
    ----------
    weather_path : str or Path, optional
        EPW/TMY3/CSV weather (:func:`thermocal.io.weather.read_weather`); default pvlib's
        TMY3 ``723170TYA.CSV``. The period is January of its year (or its first full month).
    seed : int
        Seed of every random draw.

    Returns
    -------
    dict
        ``log`` (DataFrame: time, sensor, value, unit), ``mapping`` (dict, the content of
        ``mapping.yaml``), ``truth`` (dict, ``truth.json``), ``building`` (nominal),
        ``true_building``, ``weather``, ``weather_metadata``, ``temperatures`` (true zone air
        temperature [C], indexed by the END of each step of the period), ``loads`` (unknown
        loads [W] per step start and zone over the period), ``components`` (``idle`` Series
        [W], ``gains`` and ``hvac`` DataFrames [W]), ``true_loads`` (building totals per step),
        ``zones`` (per-zone table: kind, floor area, heat loss coefficient, idle load, gains
        density, box capacity, sizing, set point, stuck), ``metadata``.
    """
    from thermocal.demos import buildings
    from thermocal.io.weather import read_weather
    from thermocal.multizone.simulation import Simulation

    clock = _time.perf_counter()
    weather_path = Path(weather_path) if weather_path is not None else _default_weather_path()
    weather, wmeta = read_weather(weather_path)
    start, end = _period(weather)
    sim_weather, sim_start, pre_note = _extended_weather(weather, start)
    sim_end = end + LOG_MARGIN
    if sim_weather.index[-1] < sim_end:
        sim_end = end
    rng = np.random.default_rng(seed)

    building = buildings.clinic()
    true_building = building.with_parameters(true_parameters(building))
    network = _design_network(building, rng)
    sensor_names = [s for s, _ in network["sensors"]]
    defects = _draw_defects(sensor_names, start, end, rng)

    sim = Simulation(
        true_building, sim_weather, wmeta, step=STEP, start=sim_start, end=sim_end,
        store_surfaces=False,
    )  # fmt: skip
    times = sim.times
    zones = _zone_table(building, network["equipment"], rng)
    temp_out = np.interp(  # outdoor air for the hot-deck reset [C]
        (times - start).total_seconds().to_numpy(),
        (sim_weather.index - start).total_seconds().to_numpy(),
        sim_weather["temp_air"].to_numpy(dtype=float),
    )
    t_sim = _time.perf_counter()
    loads, air, comps = _operate(sim, zones, temp_out, rng)
    t_sim = _time.perf_counter() - t_sim  # row k of air: state at times[k] + step

    # sensor readings at the model outputs
    t_grid = ((times + pd.Timedelta(STEP)) - start).total_seconds().to_numpy()  # [s] from start
    log_begin = -LOG_MARGIN.total_seconds() if sim_start <= start - LOG_MARGIN else t_grid[0]
    log_end = (min(sim_end, end + LOG_MARGIN) - start).total_seconds()
    noise = rng.normal(0.0, NOISE_STD, size=(len(times), len(sensor_names)))
    frames = []
    dead_s = (defects["dead_after"] - start).total_seconds()
    for i, (sensor, zone) in enumerate(network["sensors"]):
        y = air[zone].to_numpy() + network["offsets"][i] + noise[:, i]
        t, v = _sample_sensor(
            t_grid,
            y,
            float(log_begin),
            float(log_end),
            float(network["phases"][i]),
            float(REPORT_INTERVAL),
            REPORT_THRESHOLD,
        )
        keep = np.ones(len(t), dtype=bool)
        if sensor == defects["dead_sensor"]:
            keep &= t <= dead_s
        for d in defects["dropouts"]:
            if d["sensor"] == sensor:
                a = (d["start"] - start).total_seconds()
                b = (d["end"] - start).total_seconds()
                keep &= ~((t >= a) & (t < b))
        t, v = t[keep], v[keep]
        frames.append(
            pd.DataFrame({"t": t.astype(np.int64), "sensor": sensor, "value": _quantise(v)})
        )
    log = pd.concat(frames, ignore_index=True)
    log = log.sort_values(["t", "sensor"], kind="stable").reset_index(drop=True)
    log.insert(0, "time", start + pd.to_timedelta(log.pop("t"), unit="s"))
    log["time"] = log["time"].astype(f"datetime64[ns, {start.tz}]")
    log["unit"] = "C"

    mapping = {
        # the case study's choices: unsensed zones take a neighbour's data; the generator puts
        # its loads into the zone air, so the identified heat goes there too
        "unsensed": "neighbour",
        "identified_heat": {"radiant_fraction": 0.0, "sensor": "air"},
        "sensors": {s: z for s, z in network["sensors"]},
        "zones": {
            z: {"use": u}
            for z, u in sorted(network["substitutes"].items(), key=lambda kv: _room_number(kv[0]))
        },
    }

    period = (times >= start) & (times < end)
    occupied = occupancy_mask(times[period])
    nominal = building.parameters()
    truth = {
        "description": "Truth of the identification demo: read only by the demo report and tests.",
        "parameters": {
            name: {
                "nominal": float(nominal[name]),
                "true": float(nominal[name]) * factor,
                "factor": factor,
                "unit": parameter_unit(name),
            }
            for name, factor in TRUE_FACTORS.items()
        },
        "sensor_offsets": {
            s: round(float(o), 4) for s, o in zip(sensor_names, network["offsets"], strict=True)
        },
        "sensor_noise_std": NOISE_STD,
        "defects": {
            "dead_sensor": defects["dead_sensor"],
            "dead_after": defects["dead_after"].isoformat(),
            "dropouts": [
                {
                    "sensor": d["sensor"],
                    "start": d["start"].isoformat(),
                    "end": d["end"].isoformat(),
                }
                for d in defects["dropouts"]
            ],
        },
        "equipment_rooms": network["equipment"],
        "loads": {
            "idle_total_W": round(float(comps["idle"].sum()), 1),
            "unoccupied_total_W": round(
                float(loads.to_numpy()[period][~occupied].sum(axis=1).mean()), 1
            ),
            "occupied_mean_total_W": round(
                float(loads.to_numpy()[period][occupied].sum(axis=1).mean()), 1
            ),
            "occupied_mean_gains_W": round(
                float(comps["gains"][period][occupied].sum(axis=1).mean()), 1
            ),
            "occupied_mean_hvac_W": round(
                float(comps["hvac"][period][occupied].sum(axis=1).mean()), 1
            ),
            "per_zone": {
                z: {
                    k: (round(float(v), 4) if not isinstance(v, str) else v) for k, v in row.items()
                }
                for z, row in zones.to_dict(orient="index").items()
            },
        },
        "generator": {
            "module": "thermocal.demos.identification",
            "seed": int(seed),
            "weather": weather_path.name,
            "period": [start.isoformat(), end.isoformat()],
            "step": STEP,
        },
    }
    metadata = {
        "period": (start, end),
        "step": pd.Timedelta(STEP),
        "weather": str(weather_path),
        "weather_name": weather_path.name,
        "seed": int(seed),
        "pre_run": pre_note,
        "simulation_start": sim_start,
        "n_sensors": len(sensor_names),
        "n_reports": len(log),
        "defects": truth["defects"],
        "simulation_seconds": t_sim,
        "generation_seconds": _time.perf_counter() - clock,
    }
    total = {name: comps[name][period].sum(axis=1) for name in ("gains", "hvac")}
    true_loads = pd.DataFrame(
        {
            "idle": np.full(int(period.sum()), float(comps["idle"].sum())),
            "gains": total["gains"],
            "hvac": total["hvac"],
            "total": loads.to_numpy()[period].sum(axis=1),
        },
        index=pd.Index(times[period], name="time"),
    )
    temperatures = air.copy()
    temperatures.index = times + pd.Timedelta(STEP)
    return {
        "log": log,
        "mapping": mapping,
        "truth": truth,
        "building": building,
        "true_building": true_building,
        "weather": weather,
        "weather_metadata": wmeta,
        "temperatures": temperatures[(temperatures.index > start) & (temperatures.index <= end)],
        "loads": loads.loc[period],
        "zones": zones,
        "metadata": metadata,
        "true_loads": true_loads,
        "components": {
            "idle": pd.Series(comps["idle"], index=zones.index),
            "gains": pd.DataFrame(comps["gains"][period], index=times[period], columns=zones.index),
            "hvac": pd.DataFrame(comps["hvac"][period], index=times[period], columns=zones.index),
        },
    }


# ----------------------------------------------------------------------------------------------
# files
# ----------------------------------------------------------------------------------------------
SENSORS_FILE = "sensors.parquet"
MAPPING_FILE = "mapping.yaml"
TRUTH_FILE = "truth.json"
TRUE_LOADS_FILE = "true_loads.parquet"
README_FILE = "README.md"
#: Resampling gap limit that shows the demo's dropouts (the heartbeat is 5 minutes).
MAX_GAP = "10min"


def _write_log(log: pd.DataFrame, path: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    tz = log["time"].dt.tz
    offset = pd.Timestamp("2001-01-01", tz=tz).strftime("%z")
    table = pa.table(
        {
            "time": pa.array(log["time"].dt.tz_convert("UTC").dt.tz_localize(None).to_numpy())
            .cast(pa.timestamp("s"))
            .cast(pa.timestamp("s", tz=f"{offset[:3]}:{offset[3:]}")),
            "sensor": pa.array(log["sensor"].astype(str).to_numpy(), pa.string()),
            "value": pa.array(log["value"].to_numpy(dtype=float), pa.float64()),
            "unit": pa.array(log["unit"].astype(str).to_numpy(), pa.string()),
        }
    )
    pq.write_table(
        table,
        path,
        compression="zstd",
        compression_level=19,
        use_dictionary=["sensor", "value", "unit"],
        column_encoding={"time": "DELTA_BINARY_PACKED"},
    )


def _mapping_text(mapping: dict) -> str:
    head = (
        "# Sensor -> zone mapping of the identification demo\n"
        "# (generated by thermocal.demos.identification).\n"
        "# sensors: every sensor and the zone it hangs in; several sensors in one zone are\n"
        "#          averaged.\n"
        "# zones:   zones without a sensor that take the data of a named zone ({use: <zone>});\n"
        "#          here the unsensored rooms with no sensored room beside them in the same row.\n"
        "# unsensed: neighbour -- zones in neither section (corridors, equipment rooms, other\n"
        "#          unsensored rooms) take an automatically chosen adjacent zone, as in the\n"
        "#          method's case study (the default, float, simulates them with Q_ID = 0).\n"
        "# identified_heat: the generator's loads enter the zone air, so the identified heat\n"
        "#          is put there (radiant_fraction 0) and compared with air temperatures.\n"
    )
    return head + yaml.safe_dump(mapping, sort_keys=False, allow_unicode=True, width=100)


def _readme_text(out: dict) -> str:
    meta = out["metadata"]
    truth = out["truth"]
    start, end = meta["period"]
    rows = "\n".join(
        f"| `{name}` | {p['nominal']:.6g} | {p['true']:.6g} | {p['factor']:g} | {p['unit']} |"
        for name, p in truth["parameters"].items()
    )
    loads = truth["loads"]
    d = truth["defects"]
    drops = "; ".join(
        f"{x['sensor']} {x['start'][5:16]} to {x['end'][5:16]}" for x in d["dropouts"]
    )
    n_rooms = len(set(out["mapping"]["sensors"].values()))
    idle, occ = loads["idle_total_W"] / 1e3, loads["occupied_mean_total_W"] / 1e3
    gains, hvac = loads["occupied_mean_gains_W"] / 1e3, loads["occupied_mean_hvac_W"] / 1e3
    lines = [
        "# Identification demo data",
        "",
        "Generated by `python -m thermocal.demos.identification --write DIR` (module "
        f"`thermocal.demos.identification`, seed {meta['seed']}); the module docstring "
        "describes every modelling choice. `tests/identification/test_identification_demo_data.py` "
        "regenerates the data and compares them with this copy.",
        "",
        "- **Building**: `thermocal.demos.buildings.clinic()` (186 zones), NOT shipped; the "
        f'"real" building is it with the {len(truth["parameters"])} parameters below multiplied '
        "by their factor.",
        f"- **Weather**: `{meta['weather_name']}` (read with `thermocal.io.weather.read_weather`); "
        f"period [{start.isoformat()}, {end.isoformat()}), 5-minute steps; {meta['pre_run']}.",
        "- **Unknown loads** (not in the model; building totals): constant idle load "
        f"{idle:.1f} kW (the only load in unoccupied hours); occupied-hour mean {occ:.1f} kW, of "
        f"which internal gains {gains:.1f} kW and HVAC {hvac:.1f} kW (dual-duct mixing boxes under "
        "pneumatic thermostats, 3 boxes stuck hot, 3 stuck cold). Occupied = not (20-04 h every "
        "night, Saturday 11-20 h, Sunday).",
        f"- **Sensors**: {meta['n_sensors']} sensors in {n_rooms} rooms, {meta['n_reports']} "
        "reports; a report every 5 min or on a 0.28 C change, values quantised to 0.05 C, constant "
        "offset N(0, 0.22 C) truncated to +-0.44 C, white noise 0.02 C. The log runs from 1 h "
        "before to 1 h after the period.",
        f"- **Defects**: dead sensor {d['dead_sensor']} (no reports after {d['dead_after']}); "
        f'dropouts: {drops}. `resample_measurements(raw, "5min", max_gap="{MAX_GAP}")` '
        "lists them as gaps.",
        "",
        "| file | content |",
        "|---|---|",
        f"| `{SENSORS_FILE}` | sensor log (long): time (UTC-05:00), sensor, value [C], unit |",
        f"| `{MAPPING_FILE}` | sensor -> zone, named substitute zones |",
        f"| `{TRUTH_FILE}` | true parameters, sensor offsets, defects, loads per zone |",
        f"| `{TRUE_LOADS_FILE}` | unknown loads, building totals per step [W] |",
        "",
        "`truth.json` and `true_loads.parquet` are for the demo report and the tests only.",
        "",
        "True envelope parameters:",
        "",
        "| parameter | nominal | true | factor | unit |",
        "|---|---:|---:|---:|---|",
        rows,
        "",
    ]
    return "\n".join(lines)


def write_demo(
    folder=DEMO_FOLDER, *, weather_path=None, seed: int = DEFAULT_SEED, out=None
) -> dict:
    """Generate (or take ``out`` from :func:`generate`) and write the demo files to ``folder``.

    Returns
    -------
    dict
        The generated data (as :func:`generate`) with ``paths`` (file name -> Path) added.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    if out is None:
        out = generate(weather_path, seed)
    paths = {
        name: folder / name
        for name in (SENSORS_FILE, MAPPING_FILE, TRUTH_FILE, TRUE_LOADS_FILE, README_FILE)
    }
    _write_log(out["log"], paths[SENSORS_FILE])
    paths[MAPPING_FILE].write_text(_mapping_text(out["mapping"]), encoding="utf-8")
    paths[TRUTH_FILE].write_text(json.dumps(out["truth"], indent=1) + "\n", encoding="utf-8")
    totals = out["true_loads"].reset_index()
    totals.to_parquet(paths[TRUE_LOADS_FILE], index=False, compression="zstd")
    paths[README_FILE].write_text(_readme_text(out), encoding="utf-8")
    out["paths"] = paths
    return out


def load_demo(folder=DEMO_FOLDER, *, weather_path=None):
    """The shipped demo: ``(building, weather, metadata, raw_sensor_log, mapping, truth)``.

    Parameters
    ----------
    folder : str or Path
        Default: the shipped :data:`DEMO_FOLDER`; or a folder written by :func:`write_demo`.
    weather_path : str or Path, optional
        The weather file the data were generated with (default: pvlib's TMY3 file when
        ``truth.json`` names it, else a file of that name in ``folder``).

    Returns
    -------
    building : Building
        ``buildings.clinic()`` with its NOMINAL parameters (what the identification models).
    weather : DataFrame
        :func:`thermocal.io.weather.read_weather` of the weather file (default pvlib's
        ``723170TYA.CSV``), the whole file: simulate ``metadata["period"]`` of it.
    metadata : dict
        ``period`` (start, end) [tz-aware], ``step`` (5 min), ``max_gap`` ("10min"),
        ``weather`` (the weather metadata), ``measurements`` (the reader's metadata),
        ``folder``, ``files``.
    raw_sensor_log : DataFrame
        :func:`thermocal.io.measurements.read_measurements` of ``sensors.parquet`` (long).
    mapping : dict
        ``mapping.yaml`` as read by :func:`thermocal.io.yamlfile.read_yaml`.
    truth : dict
        ``truth.json`` (for the demo report and tests only).
    """
    from thermocal.demos import buildings
    from thermocal.io.measurements import read_measurements
    from thermocal.io.weather import read_weather
    from thermocal.io.yamlfile import read_yaml

    folder = Path(folder)
    for name in (SENSORS_FILE, MAPPING_FILE, TRUTH_FILE):
        if not (folder / name).is_file():
            raise ThermocalInputError(
                f"identification demo: {folder / name} is missing; regenerate it with "
                f"`python -m thermocal.demos.identification --write {folder}`"
            )
    truth = json.loads((folder / TRUTH_FILE).read_text(encoding="utf-8"))
    name = truth["generator"]["weather"]
    if weather_path is None:
        for candidate in (_default_weather_path(), folder / name):
            if candidate.name == name and candidate.is_file():
                weather_path = candidate
                break
        else:
            raise ThermocalInputError(
                f"identification demo in {folder} was generated with the weather file {name}, "
                f"which is neither pvlib's nor in {folder}: pass load_demo(weather_path=...)"
            )
    weather, wmeta = read_weather(weather_path)
    raw, mmeta = read_measurements(folder / SENSORS_FILE, layout="long")
    mapping = read_yaml(folder / MAPPING_FILE, what="mapping file")
    start, end = (pd.Timestamp(t) for t in truth["generator"]["period"])
    metadata = {
        "period": (start, end),
        "step": pd.Timedelta(truth["generator"]["step"]),
        "max_gap": MAX_GAP,
        "seed": truth["generator"]["seed"],
        "weather": wmeta,
        "measurements": mmeta,
        "folder": folder,
        "files": {
            name: folder / name
            for name in (SENSORS_FILE, MAPPING_FILE, TRUTH_FILE, TRUE_LOADS_FILE)
        },
    }
    return buildings.clinic(), weather, metadata, raw, mapping, truth


def main(argv=None) -> int:
    """``python -m thermocal.demos.identification --write DIR [--weather FILE] [--seed N]``."""
    parser = argparse.ArgumentParser(
        prog="python -m thermocal.demos.identification",
        description="Generate the identification demo data (clinic, January, 82 sensors).",
    )
    parser.add_argument("--write", metavar="DIR", default=str(DEMO_FOLDER), help="output folder")
    parser.add_argument("--weather", metavar="FILE", default=None, help="EPW/TMY3 weather file")
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    args = parser.parse_args(argv)
    clock = _time.perf_counter()
    out = write_demo(args.write, weather_path=args.weather, seed=args.seed)
    meta = out["metadata"]
    sizes = ", ".join(f"{p.name} {p.stat().st_size / 1e3:.0f} kB" for p in out["paths"].values())
    print(
        f"wrote {args.write}: {meta['n_sensors']} sensors, {meta['n_reports']} reports; {sizes}; "
        f"simulation {meta['simulation_seconds']:.1f} s, total {_time.perf_counter() - clock:.1f} s"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
