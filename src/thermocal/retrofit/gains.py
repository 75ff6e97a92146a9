"""Internal gains of the retrofit analysis: the configured source plus the occupants.

``internal_gains.source`` gives what a meter, a schedule or a constant says (appliances,
lighting: ``none`` / ``constant`` / ``schedule`` / ``electricity``); the people who live in the
house are on no meter, yet every user knows how many they are. ``internal_gains.occupants``
adds their sensible heat on top of any source:

``phi_occ(hour) = n_occ * q_person * presence(hour)``  [W]

with the defaults of the Swiss standard for residential buildings, SIA 380/1:2016 ("Thermische
Energie im Hochbau"), standard use values of housing (Wohnen MFH and EFH): a heat emission of
**70 W per person** (:data:`OCCUPANT_SENSIBLE_W`; the sensible part of a seated adult at about
1.2 met, the same as ASHRAE Handbook of Fundamentals 2017, ch. 18, table 1, "seated, very light
work": 70 W sensible) and a presence of **12 hours a day** (:data:`OCCUPANT_PRESENCE_HOURS`, a
mean over the year, absences included). SIA 380/1 is a monthly method and gives no hours; the
hourly shape :data:`OCCUPANT_PRESENCE` is thermocal's (at home at night, partly away in the
daytime, back in the evening), scaled so that its 24 values add up to the standard's 12 hours.

The occupants' gains join the source's in one series ``phi_int`` (:func:`internal_gains`): the
calibration adds it to the metered heating power, the validation's heat check and the demand
put it into the air node (:func:`thermocal.retrofit.demand.with_gains`), the demand year with
the mean 24-hour profile (:func:`gains_day_profile`). One log-normal factor per draw scales the
total; its relative spread combines the source's ``rel_std`` and the occupants'
``occupants_rel_std`` as independent errors (:func:`combined_rel_std`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

#: Sensible heat per occupant [W], SIA 380/1:2016 standard use value of housing.
OCCUPANT_SENSIBLE_W = 70.0
#: Mean presence per occupant [h/day], SIA 380/1:2016 standard use value of housing.
OCCUPANT_PRESENCE_HOURS = 12.0
#: The hourly shape before scaling (hour 0..23, local standard time): asleep at home until
#: 06:00, leaving 07:00-08:00, a fifth at home in the daytime, back from 17:00.
_PRESENCE_SHAPE = np.array(
    [1.0] * 6 + [0.9, 0.6] + [0.2] * 9 + [0.5] + [0.8] * 4 + [1.0] * 2, dtype=float
)
#: Presence fraction per hour [-] (hour 0..23): the shape scaled to 12 hours a day.
OCCUPANT_PRESENCE = tuple(
    float(v) for v in _PRESENCE_SHAPE * OCCUPANT_PRESENCE_HOURS / _PRESENCE_SHAPE.sum()
)


def occupant_day_profile(cfg) -> np.ndarray | None:
    """The occupants' sensible heat over a day [W] (None: no ``occupants``).

    Parameters
    ----------
    cfg : thermocal.retrofit.config.InternalGainsConfig

    Returns
    -------
    np.ndarray (24,) [W] for hours 0..23: ``occupants * occupant_sensible_W * presence``.
    """
    if not cfg.occupants:
        return None
    presence = np.asarray(
        cfg.occupant_presence if cfg.occupant_presence is not None else OCCUPANT_PRESENCE, float
    )
    return float(cfg.occupants) * float(cfg.occupant_sensible_W) * presence


def source_gains(grid: pd.DataFrame, cfg) -> pd.Series | None:
    """The configured source's gains [W] on the measurement grid (None: ``source: none``).

    Parameters
    ----------
    grid : pd.DataFrame
        The measurement grid (``phi_el`` [W] from the electricity meter when metered).
    cfg : thermocal.retrofit.config.InternalGainsConfig
    """
    if cfg.source == "none":
        return None
    if cfg.source == "electricity":
        return grid["phi_el"].astype(float) * cfg.fraction_inside
    if cfg.source == "schedule":
        values = np.asarray(cfg.schedule_W, float)[np.asarray(grid.index.hour)]
        return pd.Series(values, index=grid.index)
    return pd.Series(float(cfg.constant_W), index=grid.index)


#: Mean metered electricity per heated floor area [W/m2] a home can have; outside, a unit
#: slip (homes average about 0.5-8 W/m2; a W/kW or Wh/kWh slip moves it by 1000).
ELECTRICITY_PER_AREA_RANGE = (0.05, 100.0)


def check_metered_electricity(
    grid: pd.DataFrame, cfg, floor_area: float, source: str, column: str
) -> None:
    """Refuse an electricity meter read in another unit than declared.

    A meter logged in W and declared as kW (``internal_gains.electricity_unit``) turns a
    house's 300 W into 300 kW of internal gains; the heat balance's check then blames the
    heating (its mean includes the gains). The metered mean per heated floor area outside
    :data:`ELECTRICITY_PER_AREA_RANGE` is refused naming the column and the key.

    Parameters
    ----------
    grid : pd.DataFrame
        The measurement grid with ``phi_el`` [W].
    cfg : thermocal.retrofit.config.InternalGainsConfig
    floor_area : float [m2]
        The building file's heated floor area.
    source, column : str
        The measurement file and the meter's column, for the message.
    """
    if cfg.source != "electricity" or "phi_el" not in grid or floor_area <= 0:
        return
    values = grid["phi_el"].to_numpy(float)
    if not np.isfinite(values).any():
        return
    mean = float(np.nanmean(values))
    per_area = mean / floor_area
    low, high = ELECTRICITY_PER_AREA_RANGE
    if low <= per_area <= high:
        return
    direction = "large" if per_area > high else "small"
    shown = f"{mean:,.0f}" if abs(mean) >= 10 else f"{mean:.3g}"
    raise ThermocalInputError(
        f"{source}, column '{column}' (the electricity meter): it averages {shown} W over "
        f"the measurements as read in {cfg.electricity_unit} (internal_gains."
        f"electricity_unit), {per_area:.3g} W per m2 of heated floor: far too {direction} for "
        f"a home ({low:g}-{high:g} W/m2; homes average about 0.5-8). Check internal_gains."
        "electricity_unit (W and kW, Wh and kWh differ by 1000; a meter reading needs "
        "electricity_cumulative: true)"
    )


def check_configured_gains(cfg, floor_area: float, building_name: str) -> None:
    """Refuse a constant or scheduled internal gain no home releases per m2 of heated floor.

    ``constant_W: 40000`` on 220 m2 (182 W/m2: the heating power, or a value in another unit)
    made the calibration fail its validation with a bias of +16 K, and a verification divide
    by a baseline that needed no heat. The upper end of :data:`ELECTRICITY_PER_AREA_RANGE`,
    the limit of a metered household's electricity (:func:`check_metered_electricity`),
    applies to the configured gains' mean too (small values are the configuration's
    ``MIN_HOUSEHOLD_GAINS_W`` check: a kW slip). Called wherever the building file is read
    beside the gains: ``thermocal retrofit`` (with ``--detailed-only`` too, when the
    configuration names the building) and ``thermocal verify``.

    Parameters
    ----------
    cfg : thermocal.retrofit.config.InternalGainsConfig
        ``internal_gains:`` of the configuration.
    floor_area : float [m2]
        The building file's heated floor area.
    building_name : str
        For the message.

    Raises
    ------
    ThermocalInputError
        Naming ``internal_gains.constant_W`` or ``schedule_W``, the gains per m2 and the limit.
    """
    if cfg.source not in ("constant", "schedule") or floor_area <= 0:
        return
    key = f"{cfg.source}_W"
    mean = float(np.mean(cfg.constant_W if cfg.source == "constant" else cfg.schedule_W))
    per_area = mean / floor_area
    high = ELECTRICITY_PER_AREA_RANGE[1]
    if per_area <= high:
        return
    raise ThermocalInputError(
        f"internal_gains.{key}: {mean:,.0f} W"
        f"{' on average' if cfg.source == 'schedule' else ''} is {per_area:.3g} W per m2 of "
        f"heated floor ({floor_area:g} m2 in building {building_name!r}), more than any "
        f"home's internal gains (at most {high:g} W/m2; homes average about 0.5-8 W/m2, a "
        "few hundred W for a house: appliances, lights, people); give the gains in W, "
        "without the heating"
    )


def internal_gains(grid: pd.DataFrame, cfg) -> pd.Series | None:
    """All internal gains [W] on the measurement grid: the source's plus the occupants'.

    Parameters
    ----------
    grid : pd.DataFrame
        The measurement grid (``phi_el`` [W] from the electricity meter when metered).
    cfg : thermocal.retrofit.config.InternalGainsConfig

    Returns
    -------
    pd.Series [W] on ``grid.index``, or None when there is neither a source nor occupants.
    """
    gains = source_gains(grid, cfg)
    people = occupant_day_profile(cfg)
    if people is None:
        return gains
    occ = pd.Series(people[np.asarray(grid.index.hour)], index=grid.index)
    return occ if gains is None else gains + occ


def gains_day_profile(phi_int: pd.Series, cfg) -> np.ndarray:
    """Mean 24-hour profile [W] of the gains for the demand year.

    Parameters
    ----------
    phi_int : pd.Series [W]
        The gains on the measurement grid (:func:`internal_gains`); an electricity meter's
        day is its mean over these rows (occupants included, their profile is the same every
        day).
    cfg : thermocal.retrofit.config.InternalGainsConfig

    Returns
    -------
    np.ndarray (24,) [W], hours 0..23.
    """
    from thermocal.retrofit.metrics import daily_profile

    if cfg.source == "electricity":
        return daily_profile(phi_int)
    day = (
        np.asarray(cfg.schedule_W, float) if cfg.source == "schedule"
        else np.full(24, float(cfg.constant_W)) if cfg.source == "constant"
        else np.zeros(24)
    )  # fmt: skip
    people = occupant_day_profile(cfg)
    return day if people is None else day + people


def combined_rel_std(day: np.ndarray, cfg) -> float:
    """Relative standard deviation [-] of the total gains (source and occupants independent).

    ``sqrt((r_s G_s)^2 + (r_o G_o)^2) / (G_s + G_o)`` with the mean gains ``G`` [W] of the
    source and of the occupants over ``day`` and their relative spreads ``rel_std`` and
    ``occupants_rel_std``.

    Parameters
    ----------
    day : np.ndarray (24,) [W]
        The total gains' day (:func:`gains_day_profile`).
    cfg : thermocal.retrofit.config.InternalGainsConfig
    """
    people = occupant_day_profile(cfg)
    g_occ = 0.0 if people is None else float(np.mean(people))
    g_src = max(float(np.mean(day)) - g_occ, 0.0)
    total = g_src + g_occ
    if total <= 0.0:
        return float(cfg.rel_std)
    return float(np.hypot(cfg.rel_std * g_src, cfg.occupants_rel_std * g_occ) / total)


def has_gains(cfg) -> bool:
    """Whether the configuration gives internal gains at all (a source or occupants)."""
    return cfg.source != "none" or bool(cfg.occupants)
