"""The pre and post periods of a post-retrofit verification: where they split, whether each is
long and cold enough, days on the wrong side of the retrofit date, and sensors that changed
between them (:func:`thermocal.retrofit.verify.run_verify` uses them).

The retrofit date a user gives may be off by days (the work took longer, or the insulation was
finished before the paperwork). Days after the date that still behave like the baseline, or days
before it that already behave like the retrofitted house, are found by a least-squares change
point of the daily residuals of the baseline model (:func:`baseline_days_after_retrofit`,
:func:`retrofitted_days_before_the_date`), judged in standard errors that account for the
residuals' day-to-day autocorrelation.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.retrofit.config import MIN_TRAINING_DAYS

if TYPE_CHECKING:
    from thermocal.retrofit.verify import VerifySection

__all__ = [
    "BASELINE_DAYS_Z",
    "HEATING_LIMIT_C",
    "MIN_HEATING_DAYS",
    "baseline_days_after_retrofit",
    "baseline_days_note",
    "check_period",
    "data_end",
    "meter_gap_message",
    "missing_heat_message",
    "unmetered_heat_runs",
    "weather_extrapolation",
    "retrofitted_days_before_the_date",
    "retrofitted_days_note",
    "sensor_change_notes",
    "split_periods",
]

#: Fewest heating days (daily mean outdoor temperature below 12 C, the heating limit of the
#: 20/12 heating degree days) the post period must hold.
MIN_HEATING_DAYS = 7
#: Heating limit [C] of a heating day.
HEATING_LIMIT_C = 12.0
#: Standard errors by which the first days of the reporting period must look more like the
#: baseline than the rest does (:func:`baseline_days_after_retrofit`).
BASELINE_DAYS_Z = 3.0
#: Shortest run of zero metered heat [h] checked against the baseline's need
#: (:func:`unmetered_heat_runs`): a day, the resolution of the saving's daily sums.
ZERO_RUN_HOURS = 24.0
#: Metered heat power [W] at or below which an interval counts as zero.
ZERO_HEAT_W = 1.0
#: Share of the period's median daily baseline heat the baseline must need over a zero run
#: (per day) for the zeros to be a meter's gap rather than a day the gains covered.
SUBSTANTIAL_BASELINE_SHARE = 0.25
#: The rooms count as held over a zero run when their mean temperature is at most this far
#: [K] from the period's median indoor temperature (heating really off: they cool; the sun
#: or the gains heating them above the set point: they warm).
HELD_INDOOR_K = 1.0
#: Share of a zero run's intervals that must lie within :data:`HELD_INDOOR_K` of the median.
HELD_SHARE = 0.9
#: The residual adjustment's share [%] of the post period's baseline beyond which the saving
#: rests on the adjustment's line more than on the measurements
#: (:func:`weather_extrapolation`; 10-15 % on the EnergyPlus house's periods, 46-100 % where
#: the post period reached far into spring).
MAX_ADJUSTMENT_SHARE_PCT = 25.0


def _stamp(text: str | None, tz, default: pd.Timestamp) -> pd.Timestamp:
    if text is None:
        return default
    t = pd.Timestamp(text)
    return t.tz_localize(tz) if t.tz is None else t.tz_convert(tz)


def data_end(index: pd.DatetimeIndex, heat: pd.Series | None = None) -> pd.Timestamp:
    """End of the measurements a period can use: of the last row with metered heat.

    A cumulative meter reading has no next reading for its last row (its heat is missing),
    and a log may go on after the heat meter stopped; rows without heat cannot be
    calibrated on.

    Parameters
    ----------
    index : pd.DatetimeIndex
        The regular grid of the model inputs (interval starts).
    heat : pd.Series, optional
        Metered heat [W] on ``index``; None (or no heat at all): the end of the last row.

    Returns
    -------
    pd.Timestamp
        The end of the last row with heat (interval start plus the grid step).
    """
    step = index[1] - index[0]
    if heat is not None:
        present = np.flatnonzero(np.isfinite(np.asarray(heat, float)))
        if present.size:
            return index[int(present[-1])] + step
    return index[-1] + step


def split_periods(
    index: pd.DatetimeIndex, sec: VerifySection, source: str, heat: pd.Series | None = None
) -> tuple[tuple, tuple, pd.Timestamp, list[str]]:
    """Pre and post periods [start, end) from the ``verify:`` section; refuses overlaps.

    The outer ends default to the measurements' (the post period's to the last row with
    metered heat, :func:`data_end`); an outer end given beyond the measurements is moved to
    theirs with a note, so the periods reported are those analysed; an inner end beyond them
    (a period without data) is refused.

    Parameters
    ----------
    index : pd.DatetimeIndex
        The regular grid of the model inputs (interval starts, tz-aware).
    sec : VerifySection
        The ``verify:`` section (dates as text, local standard time when naive).
    source : str
        The measurement file, for messages.
    heat : pd.Series, optional
        Metered heat [W] on ``index`` (:func:`data_end`).

    Returns
    -------
    pre, post : tuple of pd.Timestamp
        Start and end of each period.
    date : pd.Timestamp
        The retrofit date.
    notes : list of str
        One per end moved to the measurements'.
    """
    tz = index.tz
    step = index[1] - index[0]
    first, end_data = index[0], index[-1] + step
    date = _stamp(sec.retrofit_date, tz, first)
    if not first < date < end_data:
        raise ThermocalInputError(
            f"verify.retrofit_date {sec.retrofit_date}: the measurements in {source} run from "
            f"{first} to {end_data}; the retrofit date must lie inside them (data before and "
            "after it)"
        )
    last = data_end(index, heat)
    pre = [_stamp(sec.pre_start, tz, first), _stamp(sec.pre_end, tz, date)]
    post = [_stamp(sec.post_start, tz, date), _stamp(sec.post_end, tz, last)]
    notes = []
    if pre[0] < first:
        notes.append(
            f"verify.pre_start {sec.pre_start} lies before the first measurement in {source} "
            f"({first:%Y-%m-%d %H:%M}): the pre-retrofit period starts there"
        )
        pre[0] = first
    if post[1] > last:
        notes.append(
            f"verify.post_end {sec.post_end} lies after the last measured heat in {source} "
            f"(up to {last:%Y-%m-%d %H:%M}): the post-retrofit period ends there"
        )
        post[1] = last
    if pre[1] <= first:
        raise ThermocalInputError(
            f"verify.pre_end {sec.pre_end}: the measurements in {source} start at {first}; "
            "the pre-retrofit period must hold some of them (set verify.pre_end later, or "
            "remove it to end the period at the retrofit date)"
        )
    if post[0] >= last:
        start = sec.post_start or f"(default: verify.retrofit_date {sec.retrofit_date})"
        raise ThermocalInputError(
            f"verify.post_start {start}: the measured heat in "
            f"{source} ends at {last}; the post-retrofit period must hold some of it (set "
            "verify.post_start earlier, or measure longer after the retrofit)"
        )
    pre, post = tuple(pre), tuple(post)
    if pre[1] > post[0]:
        relation = "come in the wrong order" if post[1] <= pre[0] else "overlap"
        raise ThermocalInputError(
            f"the pre-retrofit period ({pre[0]} - {pre[1]}) and the post-retrofit period "
            f"({post[0]} - {post[1]}) {relation}; the pre period must end before the post "
            "period starts (verify.pre_end, verify.post_start)"
        )
    if pre[1] > date or post[0] < date:
        raise ThermocalInputError(
            f"the periods must lie on either side of the retrofit (verify.retrofit_date "
            f"{date}): pre ends {pre[1]}, post starts {post[0]}"
        )
    for name, (a, b) in (("pre", pre), ("post", post)):
        if not a < b:
            raise ThermocalInputError(f"verify.{name}_start must be before verify.{name}_end")
    return pre, post, date, notes


def unmetered_heat_runs(
    measured: pd.Series,
    baseline: pd.Series,
    indoor: pd.Series,
    *,
    min_hours: float = ZERO_RUN_HOURS,
) -> list[dict]:
    """Runs of zero metered heat while the rooms are held warm and the baseline needs heat.

    A heat meter's gap exported as zeros (or a stuck cumulative reading) reads as heat the
    house did without: in February, with the rooms at their set point, the calibrated baseline
    model needs tens of kWh a day there. A run of at least ``min_hours`` of metered heat at or
    below :data:`ZERO_HEAT_W` is reported when the baseline model needs, per day of the run, at
    least :data:`SUBSTANTIAL_BASELINE_SHARE` of the period's median daily heat and the indoor
    temperature stays within :data:`HELD_INDOOR_K` of the period's median (in
    :data:`HELD_SHARE` of the run's intervals)
    (heating really switched off lets the rooms cool; sun or gains that cover the losses warm
    them above the set point).

    Parameters
    ----------
    measured : pd.Series [W]
        Metered heat power of one period on its regular grid.
    baseline : pd.Series [W]
        The baseline model's heat power on the same grid.
    indoor : pd.Series [C]
        The measured indoor temperature on the same grid.
    min_hours : float [h]
        Shortest run reported.

    Returns
    -------
    list of dict
        Per run: ``start``, ``end`` (end of its last interval), ``hours`` [h],
        ``baseline_kWh`` [kWh] (the baseline's heat over the run), ``indoor_C`` [C] (mean
        over the run) and ``usual_indoor_C`` [C] (the period's median).
    """
    from thermocal.io.measurements.quality import true_runs

    if len(measured) < 2:
        return []
    step = measured.index[1] - measured.index[0]
    step_h = step / pd.Timedelta(hours=1)
    m = measured.to_numpy(float)
    q = baseline.reindex(measured.index).to_numpy(float)
    ti = indoor.reindex(measured.index).to_numpy(float)
    # the period's typical day: its median daily baseline heat (at least its mean) [kWh]
    daily_q = np.nansum(q) * step_h / 1000.0 / max(len(q) * step_h / 24.0, 1e-9)
    per_day = pd.Series(q, index=measured.index).groupby(measured.index.normalize()).sum()
    median_day = float(np.median(per_day.to_numpy(float)) * step_h / 1000.0)
    usual = float(np.nanmedian(ti)) if np.isfinite(ti).any() else float("nan")
    starts, ends = true_runs(np.isfinite(m) & (m <= ZERO_HEAT_W))
    runs = []
    for a, b in zip(starts, ends, strict=True):
        hours = (b - a) * step_h
        if hours < min_hours:
            continue
        need = float(np.nansum(q[a:b]) * step_h / 1000.0)
        held = float(np.nanmean(ti[a:b])) if np.isfinite(ti[a:b]).any() else float("nan")
        if need < SUBSTANTIAL_BASELINE_SHARE * max(median_day, daily_q) * hours / 24.0:
            continue
        # held throughout: not cooled (heating off) nor warmed above (sun, gains)
        near = np.abs(ti[a:b] - usual) <= HELD_INDOOR_K
        if not near.mean() >= HELD_SHARE:
            continue
        runs.append({
            "start": measured.index[a], "end": measured.index[b - 1] + step, "hours": hours,
            "baseline_kWh": need, "indoor_C": held, "usual_indoor_C": usual,
        })  # fmt: skip
    return runs


def weather_extrapolation(
    te_pre: np.ndarray,
    te_post: np.ndarray,
    dt_pre: np.ndarray,
    dt_post: np.ndarray,
    adjustment_kwh: float,
    baseline_kwh: float,
    applied: bool,
) -> dict | None:
    """The post period's weather outside the pre period's: the baseline is extrapolated.

    The baseline's residual adjustment (:func:`thermocal.retrofit.airchange.residual_adjustment`)
    is a line in the daily indoor-outdoor difference fitted on the pre period's days; a post
    period whose mean difference lies outside the range of the pre period's days takes that
    line beyond its data (a pre period at -4.6 C, a post period at 8.0 C: a normalised saving of
    -57 % against EnergyPlus' 30 %), and one that needs an adjustment of more than
    :data:`MAX_ADJUSTMENT_SHARE_PCT` of its baseline leans on the line's far end (post period
    5 K warmer: -245 kWh on a 242 kWh baseline, 4.5 % against 30.1 %). Measuring longer in the
    same weather does not help.

    Parameters
    ----------
    te_pre, te_post : ndarray [C]
        Daily mean outdoor temperatures of the pre and post periods' days.
    dt_pre, dt_post : ndarray [K]
        Daily mean indoor (set point) minus outdoor temperature of the same days.
    adjustment_kwh : float [kWh]
        The adjustment summed over the post period.
    baseline_kwh : float [kWh]
        The adjusted baseline heat of the post period.
    applied : bool
        Whether the adjustment was applied.

    Returns
    -------
    dict or None
        ``warning`` (the full text), ``short`` (for the verdict's explanation: "lies outside
        the pre period's: ..." or "reaches the edge of ...") and the ranges;
        None when the post period's mean difference lies within the pre period's days and
        the adjustment is at most :data:`MAX_ADJUSTMENT_SHARE_PCT` of the baseline.
    """
    dt_pre = np.asarray(dt_pre, float)
    dt_post = np.asarray(dt_post, float)
    if not (np.isfinite(dt_pre).any() and np.isfinite(dt_post).any()):
        return None
    lo, hi = float(np.nanmin(dt_pre)), float(np.nanmax(dt_pre))
    mean_pre, mean_post = float(np.nanmean(dt_pre)), float(np.nanmean(dt_post))
    share = 100.0 * adjustment_kwh / baseline_kwh if baseline_kwh > 0 else float("inf")
    outside = not lo <= mean_post <= hi
    if not outside and not (applied and abs(share) > MAX_ADJUSTMENT_SHARE_PCT):
        return None
    te_pre = np.asarray(te_pre, float)
    te_post = np.asarray(te_post, float)
    beyond = mean_post - hi if mean_post > hi else lo - mean_post
    relation = "lies outside" if outside else "reaches the edge of"
    short = (
        f"{relation} the pre period's: daily mean outdoor temperatures "
        f"{np.nanmin(te_post):.1f} to {np.nanmax(te_post):.1f} C (mean "
        f"{np.nanmean(te_post):.1f} C) after the retrofit, {np.nanmin(te_pre):.1f} to "
        f"{np.nanmax(te_pre):.1f} C (mean {np.nanmean(te_pre):.1f} C) before"
    )
    if applied:
        reach = (
            f"is extrapolated {beyond:.1f} K beyond them"
            if outside
            else f"is carried from their mean {mean_pre:.1f} K to the edge of its data"
        )
        what = (
            f"the baseline's residual adjustment, a line fitted over the pre period's "
            f"indoor-outdoor differences ({lo:.1f} to {hi:.1f} K), {reach} at the post period's "
            f"mean {mean_post:.1f} K and adds {adjustment_kwh:+,.0f} kWh ({share:+.0f} % of the "
            "baseline)"
        )
    else:
        what = (
            f"the baseline model, calibrated over indoor-outdoor differences of {lo:.1f} to "
            f"{hi:.1f} K, is extrapolated {beyond:.1f} K beyond them to the post period's mean "
            f"{mean_post:.1f} K"
        )
    warning = (
        f"the post period's weather {short}; {what}, so the "
        "measured saving rests on that extrapolation, not on the measurements. Measuring "
        "longer in this weather does not help: a pre period reaching the post period's weather "
        "does (move verify.pre_start / verify.pre_end), or a post period in weather like the "
        "pre period's (verify.post_start / verify.post_end, the next heating season)"
    )
    return {"warning": warning, "short": short, "dt_pre_K": (lo, hi), "dt_post_mean_K": mean_post}


def meter_gap_message(runs: list[dict], name: str, source: str) -> str:
    """The refusal of a period whose heat meter reads zero while the house needed heat.

    Parameters
    ----------
    runs : list of dict
        :func:`unmetered_heat_runs` of the period (not empty).
    name : {"pre", "post"}
    source : str
        The measurement file.

    Returns
    -------
    str
    """
    period = f"{name}-retrofit period"
    shown = "; ".join(
        f"{r['start']:%Y-%m-%d %H:%M} - {r['end']:%Y-%m-%d %H:%M} ({r['hours']:g} h, the "
        f"baseline model needs {r['baseline_kWh']:,.0f} kWh there)"
        for r in runs[:3]
    )
    more = f" and {len(runs) - 3} more" if len(runs) > 3 else ""
    total = sum(r["baseline_kWh"] for r in runs)
    effect = (
        "counted as heat saved" if name == "post" else "counted as heat the old house did without"
    )
    return (
        f"{source} ({period}): the metered heat is zero over {shown}{more}, while the rooms "
        f"stayed at their usual temperature ({runs[0]['indoor_C']:.1f} C, the period's median "
        f"{runs[0]['usual_indoor_C']:.1f} C): a heat meter that did not "
        f"record (a gap exported as zeros, a stuck reading), not a house that needed no heat; "
        f"the {total:,.0f} kWh would be {effect}. Mark these rows missing (leave the heat "
        f"empty, not 0) and move verify.{name}_start / verify.{name}_end to leave them out "
        "(verify needs every hour's metered heat); if the heating was really off and the rooms "
        "were kept warm otherwise (a stove, a second heater), that heat is not metered and no "
        "saving can be measured over those days either"
    )


def missing_heat_message(
    heat: pd.Series, name: str, source: str, *, cumulative: bool = False
) -> str | None:
    """The refusal of a period with missing metered heat, and how to mark and leave it out.

    Verify sums the metered heat of every hour of both periods and refuses gaps; writing
    zeros into a gap reads as heat saved (:func:`unmetered_heat_runs`), and interpolating the
    heat power over hours makes up the quantity measured.

    Parameters
    ----------
    heat : pd.Series [W]
        The period's metered heat power (``phi_h``).
    name : {"pre", "post"}
    source : str
    cumulative : bool
        The meter is read cumulatively (``measurements.heat_cumulative``).

    Returns
    -------
    str or None
        None when no value is missing.
    """
    gap = heat.isna().to_numpy()
    if not gap.any():
        return None
    from thermocal.io.measurements.quality import true_runs

    starts, ends = true_runs(gap)
    step = heat.index[1] - heat.index[0] if len(heat) > 1 else pd.Timedelta(hours=1)
    longest = int(np.argmax(ends - starts))
    a, b = heat.index[starts[longest]], heat.index[ends[longest] - 1] + step
    bridge = (
        "If the meter's reading after the gap is right, interpolate the cumulative readings "
        "linearly across the gap: its heat is then spread evenly and its total kept. "
        if cumulative
        else ""
    )
    return (
        f"{source} ({name}-retrofit period): the metered heat (phi_h) is missing in "
        f"{int(gap.sum())} intervals in {len(starts)} gap(s), the longest {a:%Y-%m-%d %H:%M} - "
        f"{b:%Y-%m-%d %H:%M}; verify needs every hour's metered heat. {bridge}Otherwise leave "
        f"the rows empty (never 0: a zero counts as heat saved) and move verify.{name}_start "
        f"/ verify.{name}_end to leave the gap out"
    )


def check_period(frame: pd.DataFrame, name: str, min_days: float, source: str) -> None:
    """Refuse a period too short (measured days) or, for the post period, without heating."""
    step_h = (frame.index[1] - frame.index[0]) / pd.Timedelta(hours=1) if len(frame) > 1 else 1
    ok = frame[["phi_h_measured", "Ti_measured", "Te"]].notna().all(axis=1)
    days = float(ok.sum() * step_h / 24.0)
    if days < min_days:
        raise ThermocalInputError(
            f"{source}: the {name}-retrofit period has {days:.1f} days of measurements "
            f"(heat, indoor and outdoor temperature); a verification needs at least "
            f"{min_days:g} days in each period (verify.min_days): the fifth-order model needs "
            f"{MIN_TRAINING_DAYS:g} days to tell the heat loss from the capacities and the "
            "method calibrates on 21; measure longer"
        )
    if name == "post":
        daily_te = frame["Te"].groupby(frame.index.normalize()).mean()
        heating = int((daily_te < HEATING_LIMIT_C).sum())
        if heating < MIN_HEATING_DAYS:
            raise ThermocalInputError(
                f"{source}: the post-retrofit period {frame.index[0]:%Y-%m-%d} - "
                f"{frame.index[-1]:%Y-%m-%d} has {heating} heating days (daily mean outdoor "
                f"temperature below {HEATING_LIMIT_C:g} C), at least {MIN_HEATING_DAYS} are "
                "needed: a heating-demand saving can only be measured in the heating season; "
                "measure in the next heating season"
            )


def baseline_days_after_retrofit(
    measured: np.ndarray, baseline: np.ndarray, rho: float, z: float = BASELINE_DAYS_Z
) -> dict:
    """Leading days of the reporting period that behave like the baseline (a late retrofit).

    After the retrofit the measured daily heat is a roughly constant fraction ``m`` of the
    baseline model's. Days before the works were finished, counted in the reporting period
    because the stated retrofit date is too early, follow the baseline itself (``m = 1``)
    and lower the measured saving. The change point ``k`` is fitted by least squares:
    ``measured = baseline`` on the first ``k`` days, ``m x baseline`` (``m`` fitted) on the
    rest, for ``k = 0 .. n // 2``; the daily errors are taken equal in kWh (the baseline
    model's day-to-day error). A step is reported when ``k >= 2`` (one day is an outlier, not
    a period) and the fit improves on ``k = 0`` by more than ``z^2`` error variances, the
    variance widened for the lag-1 autocorrelation ``rho`` of the daily residuals by
    ``(1 + rho) / (1 - rho)``. ``z`` is 3, not 2, because the change point is searched for:
    on simulated reporting periods without a step (the verify demo's daily error and
    autocorrelation, savings 0-60 %) 2 gave up to 9 % false alarms, 3 at most 1.2 %, and
    still finds 2, 4 and 7 baseline days in about 60, 90 and 97 % of the cases.

    Parameters
    ----------
    measured, baseline : ndarray [kWh]
        Daily measured heat and the (adjusted) baseline model's of the reporting period's
        days, in order.
    rho : float [-]
        Lag-1 autocorrelation of the baseline period's daily residuals (clipped to 0-0.9).
    z : float [-]
        Standard errors the step must exceed.

    Returns
    -------
    dict
        ``days`` (leading days that behave like the baseline, 0 when no step is found;
        counted in the input's order, days without data included), ``candidate_days`` (the
        fitted change point, likewise), ``ratio_first`` and ``ratio_rest`` (measured over
        baseline heat of the first ``candidate_days`` days and of the rest [-]),
        ``statistic`` (the fit's improvement in error variances) and ``threshold`` (``z^2``).
    """
    out = {"days": 0, "candidate_days": 0, "ratio_first": float("nan"),
           "ratio_rest": float("nan"), "statistic": 0.0, "threshold": float(z * z)}  # fmt: skip
    step = _leading_step(measured, baseline, rho, fitted="rest")
    if step is None:
        return out
    out.update(
        candidate_days=step["span"], ratio_rest=step["ratio"], statistic=step["statistic"],
        ratio_first=step["leading_ratio"],
        days=step["span"] if step["k"] >= 2 and step["statistic"] > z * z else 0,
    )  # fmt: skip
    return out


def _leading_step(measured, baseline, rho: float, *, fitted: str) -> dict | None:
    """The least-squares change point of the daily heat after its leading days, shared by
    :func:`baseline_days_after_retrofit` and (on the reversed days)
    :func:`retrofitted_days_before_the_date`.

    On the first ``k`` days and on the rest, the measured heat is the baseline model's or a
    fitted fraction ``m`` of it: ``fitted`` says which part has the fraction ("rest" or
    "leading"); ``k = 0 .. n // 2``. Days without heat data (or a baseline of 0) are skipped.

    Parameters
    ----------
    measured, baseline : array-like [kWh]
        Daily measured heat and the baseline model's, in order.
    rho : float [-]
        Lag-1 autocorrelation of the daily residuals (clipped to 0-0.9).
    fitted : {"rest", "leading"}

    Returns
    -------
    dict or None
        ``k`` (leading days with data), ``span`` (the days they cover, skipped ones
        included), ``ratio`` (the fitted ``m``; 1 for ``k = 0`` with "leading"),
        ``leading_ratio`` and ``rest_ratio`` (measured over baseline heat of the two parts;
        NaN for no leading day), ``statistic`` (the fit's improvement on ``k = 0`` in error
        variances widened for ``rho``); None with fewer than 6 days.
    """
    y = np.asarray(measured, float)
    b = np.asarray(baseline, float)
    ok = np.isfinite(y) & np.isfinite(b) & (b > 0)  # days without heat data are skipped
    where = np.flatnonzero(ok)
    y, b = y[ok], b[ok]
    n = len(y)
    if n < 6:
        return None
    sse, ratios = [], []
    for k in range(n // 2 + 1):
        if fitted == "rest":
            m = float(np.dot(y[k:], b[k:]) / np.dot(b[k:], b[k:]))
            lead, rest = 1.0, m
        else:
            m = float(np.dot(y[:k], b[:k]) / np.dot(b[:k], b[:k])) if k else 1.0
            lead, rest = m, 1.0
        sse.append(float(np.sum((y[:k] - lead * b[:k]) ** 2) + np.sum((y[k:] - rest * b[k:]) ** 2)))
        ratios.append(m)
    k = int(np.argmin(sse))
    r = min(max(float(rho), 0.0), 0.9) if np.isfinite(rho) else 0.0
    var = sse[k] / (n - 2) * (1.0 + r) / (1.0 - r)
    return {
        "k": k,
        "span": int(where[k - 1]) + 1 if k else 0,  # up to the last such day
        "ratio": ratios[k],
        "leading_ratio": float(y[:k].sum() / b[:k].sum()) if k else float("nan"),
        "rest_ratio": float(y[k:].sum() / b[k:].sum()),
        "statistic": float((sse[0] - sse[k]) / var) if var > 0 else 0.0,
    }


def retrofitted_days_before_the_date(
    measured: np.ndarray, baseline: np.ndarray, rho: float, z: float = BASELINE_DAYS_Z
) -> dict:
    """Trailing days of the baseline period that behave unlike the baseline (a retrofit
    finished before the stated date).

    The mirror of :func:`baseline_days_after_retrofit`: on the last ``k`` days of the
    baseline period the measured daily heat is a fitted fraction ``m`` of the baseline
    model's, on the days before it the model's (``m = 1``); ``k = 0 .. n // 2`` by least
    squares, reported when ``k >= 2``, ``m < 1`` (the house needed less: retrofitted) and the
    fit improves on ``k = 0`` by more than ``z^2`` error variances (widened for the lag-1
    autocorrelation ``rho``). The baseline model was calibrated on those days too, so the
    contrast is smaller than after the date, and the test conservative.

    Parameters
    ----------
    measured, baseline : ndarray [kWh]
        Daily measured heat and the baseline model's of the baseline period's days, in order.
    rho : float [-]
        Lag-1 autocorrelation of the daily residuals (clipped to 0-0.9).
    z : float [-]
        Standard errors the step must exceed.

    Returns
    -------
    dict
        ``days`` (trailing days that behave like a retrofitted house, 0 when no step is
        found; counted back from the last day, days without data included),
        ``candidate_days``, ``ratio_last`` and ``ratio_before`` (measured over baseline heat of
        the last ``candidate_days`` days and of the days before [-]), ``statistic`` and
        ``threshold``.
    """
    out = {"days": 0, "candidate_days": 0, "ratio_last": float("nan"),
           "ratio_before": float("nan"), "statistic": 0.0, "threshold": float(z * z)}  # fmt: skip
    step = _leading_step(
        np.asarray(measured, float)[::-1], np.asarray(baseline, float)[::-1], rho,
        fitted="leading",
    )  # fmt: skip
    if step is None:
        return out
    k = step["k"]
    out.update(
        candidate_days=step["span"], ratio_last=step["ratio"] if k else float("nan"),
        ratio_before=step["rest_ratio"], statistic=step["statistic"],
        days=step["span"] if k >= 2 and step["ratio"] < 1.0 and step["statistic"] > z * z
        else 0,
    )  # fmt: skip
    return out


def retrofitted_days_note(step: dict, days: pd.DatetimeIndex) -> str | None:
    """The warning of :func:`retrofitted_days_before_the_date`, None without a step.

    Parameters
    ----------
    step : dict
        Its result.
    days : pd.DatetimeIndex
        The baseline period's days, in order (the last ``step["days"]`` are named).
    """
    k = step["days"]
    if not k:
        return None
    first, last = days[len(days) - k], days[-1]
    return (
        f"the last {k} days of the baseline period ({first:%Y-%m-%d} to {last:%Y-%m-%d}) "
        f"behave like a retrofitted house: it used {100 * step['ratio_last']:.0f} % of the "
        f"baseline model's heat on them, {100 * step['ratio_before']:.0f} % before (a step of "
        f"{np.sqrt(step['statistic']):.1f} standard errors, {np.sqrt(step['threshold']):g} "
        "needed). Was the retrofit finished earlier? Then set verify.retrofit_date (or "
        f"verify.pre_end) to {first:%Y-%m-%d}: days of the new house in the baseline lower "
        "the baseline and the measured saving, and spoil the baseline's fit"
    )


def baseline_days_note(step: dict, days: pd.DatetimeIndex) -> str | None:
    """The warning of :func:`baseline_days_after_retrofit`, None without a step.

    Parameters
    ----------
    step : dict
        Its result.
    days : pd.DatetimeIndex
        The reporting period's days, in order (the first ``step["days"]`` are named).
    """
    k = step["days"]
    if not k:
        return None
    first, last = days[0], days[k - 1]
    return (
        f"the first {k} days of the reporting period ({first:%Y-%m-%d} to {last:%Y-%m-%d}) "
        f"behave like the baseline: the house used {100 * step['ratio_first']:.0f} % of the "
        f"baseline model's heat on them, {100 * step['ratio_rest']:.0f} % on the rest (a step "
        f"of {np.sqrt(step['statistic']):.1f} standard errors, {np.sqrt(step['threshold']):g} "
        "needed). Was the retrofit finished later? Then set verify.retrofit_date (or "
        f"verify.post_start) to {last + pd.Timedelta(days=1):%Y-%m-%d}: days of the old house "
        "counted after the retrofit lower the measured saving"
    )


#: reading steps a sensor or meter may have [unit of its values]
_READING_STEPS = (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.25, 0.5, 1, 2, 5, 10, 20, 50)


def _resolution(values: np.ndarray) -> float:
    """The sensor's reading step [unit of the values]: the largest of the usual steps of
    which at least 99 % of its non-zero readings are multiples; NaN when there are fewer than
    20 non-zero readings or none fits (continuous readings).

    The values must be in the file's own unit (:func:`thermocal.retrofit.data.
    values_in_file_units`): a meter's 0.1 kWh is no step of its readings in J. A reading is
    a multiple when it lies within 1e-6 steps of one, an absolute tolerance: a relative one
    lets every large value pass (readings of 1e7 J "are" multiples of 50 within 10 J).

    Parameters
    ----------
    values : ndarray
        A sensor's readings in the file's unit.
    """
    values = values[np.isfinite(values) & (values != 0)]
    if len(values) < 20:
        return float("nan")
    for step in reversed(_READING_STEPS):
        ratio = values / step
        # within 1e-6 of a step (float error grows with the value: 1e-12 of it)
        off = np.abs(ratio - np.round(ratio))
        if np.mean(off < 1e-6 * np.maximum(1.0, 1e-6 * np.abs(ratio))) >= 0.99:
            return float(step)
    return float("nan")


def _logging_interval(times: pd.DatetimeIndex) -> pd.Timedelta | None:
    """Median time between a column's readings, None with fewer than 3 readings."""
    if len(times) < 3:
        return None
    return pd.Series(times).diff().median()


def sensor_change_notes(
    raw: pd.DataFrame, pre: tuple, post: tuple, columns: dict, source: str
) -> list[str]:
    """Signs that a sensor or meter was exchanged between the periods.

    A replaced sensor usually reads with another resolution (e.g. 0.1 K -> 0.5 K, a heat
    meter's 1 kWh -> 0.1 kWh) or logs at another interval; its readings before and after are
    then not the same measurement and the verified saving can move with the change (ASHRAE
    Guideline 14 asks for the same metering in both periods). Each column whose reading step
    or logging interval differs by a factor of 2 or more between the periods is named.

    Parameters
    ----------
    raw : DataFrame
        Measurements as read (standard column names, original time stamps), in the file's
        units (:func:`thermocal.retrofit.data.values_in_file_units`: a reading step is one
        of the file's unit).
    pre, post : tuple of Timestamp
        Start and end of the pre- and post-retrofit periods.
    columns : dict
        Standard name -> the file's column name (for the messages).
    source : str
        Measurement file (for the messages).

    Returns
    -------
    list of str
        One note per changed column (empty when nothing changed).
    """
    out = []
    for name in raw.columns:
        series = raw[name].dropna()
        before = series[(series.index >= pre[0]) & (series.index < pre[1])]
        after = series[(series.index >= post[0]) & (series.index < post[1])]
        if before.empty or after.empty:
            continue
        label = f"{source}, column {columns.get(name, name)!r}"
        r0 = _resolution(before.to_numpy(float))
        r1 = _resolution(after.to_numpy(float))
        if np.isfinite(r0) and np.isfinite(r1) and max(r0, r1) >= 2.0 * min(r0, r1):
            out.append(
                f"{label}: the readings change resolution at the retrofit ({r0:g} before, "
                f"{r1:g} after): a sensor or meter was probably exchanged; check that both "
                "measure the same quantity in the same place, else the verified saving carries "
                "the difference"
            )
        i0, i1 = _logging_interval(before.index), _logging_interval(after.index)
        if i0 is not None and i1 is not None and max(i0, i1) >= 2 * min(i0, i1):
            out.append(
                f"{label}: the logging interval changes at the retrofit "
                f"({i0 / pd.Timedelta('1min'):g} min before, {i1 / pd.Timedelta('1min'):g} min "
                "after): a sensor or logger was probably exchanged; check that both measure the "
                "same quantity in the same place"
            )
    return out
