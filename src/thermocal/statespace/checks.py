"""Checks of the data against the assumptions behind a fit: the time-stamp convention and a
heat loss coefficient that depends on the test regime.

- :func:`time_stamp_check`: the zero-order hold applies the input of row ``k`` from its time
  stamp to the next. Loggers often stamp the mean over the interval ENDING at ``t_k``; the
  inputs are then one step late, which biases the dynamics and the heat loss coefficient
  (a twin-house TiTe moved from 60 to 96 W/K). The model is refitted on the same rows with the
  inputs where the convention puts them and moved one sample either way, and the likelihoods
  compared: a convention is supported only when both neighbours lose.
- :func:`identifiability_check`: data that cannot determine the free parameters at all (fewer
  observations than free parameters; no heat input of known power, where only the time
  constants are identifiable), refused before fitting.
- :func:`heat_loss_regime_check`: the heat loss coefficient of a model with one boundary
  temperature (outdoor air) is the ratio of heat to indoor-outdoor difference only in the
  regime the data cover. Fitted on a heating sequence alone (little change of the mean
  indoor-outdoor difference), or in a building whose adjacent spaces (cellar, attic,
  neighbours) follow the test, it can differ from the same building's steady periods. The
  check fits the model on the given periods separately and compares the intervals.
"""

from __future__ import annotations

import math

import numpy as np

from thermocal.errors import ThermocalInputError

#: Log-likelihood difference [-] between the two time-stamp conventions above which one is
#: recommended: a likelihood ratio of e^3 (about 20) between fits with the same parameters.
TIME_STAMP_EVIDENCE = 3.0


#: A mean indoor temperature more than this [K] below the mean of every boundary temperature
#: while the heating adds heat on average inverts the steady energy balance
#: (:func:`inverted_balance_message`).
INVERTED_BALANCE_K = 1.0


def inverted_balance_message(
    indoor: str, mean_indoor: float, boundaries: dict[str, float], heat: str, mean_heat: float
) -> str | None:
    """The message for data whose room is heated while colder than all its surroundings.

    Heat added on average to a room that stays more than :data:`INVERTED_BALANCE_K` colder
    on average than every boundary temperature cannot leave it: the steady energy balance
    needs an outward temperature difference. Over days of data (longer than the time
    constants) no building does that without cooling; a boundary temperature logged in
    Fahrenheit (34.7 F for 1.5 C), swapped columns or a heat input of the wrong sign do.

    Parameters
    ----------
    indoor : str
        The indoor (output) column.
    mean_indoor : float [C]
        Its mean.
    boundaries : dict
        Boundary column -> its mean [C].
    heat : str
        The heat input(s) and their mean in their unit, for the message ("'Ph' averages
        2.85 kW").
    mean_heat : float [W]
        The mean heat input.

    Returns
    -------
    str or None
        None when the balance is not inverted (no heating on average, or a boundary not
        warmer than the room by :data:`INVERTED_BALANCE_K`).
    """
    from thermocal.statespace.data import celsius

    if not (mean_heat > 0 and boundaries and math.isfinite(mean_indoor)):
        return None
    if not all(m - mean_indoor > INVERTED_BALANCE_K for m in boundaries.values()):
        return None
    means = ", ".join(f"'{b}' {m:.1f} C" for b, m in boundaries.items())
    as_f = ", ".join(f"'{b}' {m:.1f} F = {celsius(m, 'Fahrenheit'):.1f} C"
                     for b, m in boundaries.items())  # fmt: skip
    return (
        f"the mean indoor temperature '{indoor}' ({mean_indoor:.1f} C) is below the mean "
        f"boundary temperature(s) ({means}) while heat input {heat}: a room heated while "
        "colder than all its surroundings cannot lose its heat in steady state, and the "
        "estimates (heat loss coefficient, capacities) mean nothing. A boundary temperature "
        f"in Fahrenheit? ({as_f}: convert with (F - 32) x 5/9); otherwise check the column "
        "mapping (swapped columns) and the sign of the heat input"
    )


def scale_ridge(model, U: np.ndarray) -> dict | None:
    """The one-factor ridge of a model without a heat input of known power.

    With every capacity, conductance and the scale of every heat input that is not zero divided
    by one factor ``k`` and every resistance multiplied by it, ``dT/dt`` is unchanged: the
    likelihood is flat along that line unless a heat input of known gain (a unit, no free
    scale) is non-zero, or one of those quantities is fixed (a constant or a fixed parameter).
    Only the time constants and ratios are then identifiable, not the heat loss coefficient
    [W/K] nor the capacities.

    Parameters
    ----------
    model : RCModel
    U : ndarray (N, n_inputs)
        Inputs in ``model.input_names`` order.

    Returns
    -------
    dict or None
        None when no such ridge exists; else ``zero`` (heat columns of known gain that are zero
        in every row) and ``scaled`` (column -> free scale parameter of the non-zero ones).
    """
    st = model.structure()
    names = list(model.parameters)
    free = set(model.free_parameter_names)
    cap_idx, link_idx, link_res = st.arrays[0], st.arrays[4], st.arrays[5]
    heat_input, heat_scale = st.arrays[7], st.arrays[9]

    def free_name(i: int) -> str | None:
        return names[i] if 0 <= i < len(names) and names[i] in free else None

    down = {free_name(int(i)) for i in cap_idx}
    down |= {free_name(int(i)) for i, r in zip(link_idx, link_res, strict=True) if not r}
    up = {free_name(int(i)) for i, r in zip(link_idx, link_res, strict=True) if r}
    active = np.any(np.nan_to_num(U) != 0, axis=0)
    zero, scaled = [], {}
    for j, k in zip(heat_input, heat_scale, strict=True):
        col = model.input_names[int(j)]
        if not active[int(j)]:
            zero += [] if k >= 0 and free_name(int(k)) else [col]
            continue
        scaled[col] = free_name(int(k)) if k >= 0 else None
        down.add(scaled[col])
    if None in down or None in up or down & up:
        return None  # a fixed quantity (or one parameter scaled both ways) anchors the scale
    return {"zero": list(dict.fromkeys(zero)), "scaled": scaled}


def identifiability_check(model, prep, source: str = "data") -> None:
    """Refuse data that cannot determine the free parameters, before fitting.

    - fewer observed output values than free parameters (plus one): the likelihood has no
      unique maximum;
    - no heat input of known power (:func:`scale_ridge`): heating zero in every row (a
      free-floating period) with the other heat inputs entering through free scales (solar
      apertures), or no heat input at all. The temperatures then follow only the time
      constants ``C R`` and the ratios of the gains; the heat loss coefficient [W/K] and the
      capacities are not identifiable (the profile likelihood of the heat loss coefficient is
      flat).

    Parameters
    ----------
    model : RCModel
        With its periods (:meth:`RCModel.with_periods`) when the likelihood is split.
    prep : PreparedData
    source : str
        Name of the data, for the message.

    Raises
    ------
    ThermocalInputError
        Naming the output or heat columns, the numbers and the remedy.
    """
    if prep.nobs <= model.n_free:
        raise ThermocalInputError(
            f"{source}: output(s) {', '.join(map(repr, model.output_names))} have "
            f"{prep.nobs} observed value(s) for the {model.n_free} free parameters of model "
            f"'{model.name}': at least {model.n_free + 1} are needed (many more for useful "
            "estimates); check the output column(s) and the period, or fix parameters "
            "(fixed: true)"
        )
    ridge = scale_ridge(model, prep.U)
    if ridge is None:
        return
    why = [f"heat input '{c}' is zero in every row (no heating: a free-floating period)"
           for c in ridge["zero"]] or ["the model has no heat input of known power"]  # fmt: skip
    why += [f"'{c}' enters through the free scale '{p}'" for c, p in ridge["scaled"].items()]
    raise ThermocalInputError(
        f"{source}: no heat input of known power for model '{model.name}': {'; '.join(why)}. "
        "Dividing every capacity and scale and multiplying every resistance by one factor "
        "then gives the same temperatures: the data determine the time constants (C x R) but "
        "not the heat loss coefficient [W/K] nor the capacities. Remedy: fit data with "
        "heating, or fix one capacity, resistance or scale at a known value (fixed: true) to "
        "estimate the time constants"
    )


def _refit(res, data, fit_kw):
    """``res.model`` refitted on ``data``: from its declared values and from ``res``'s
    estimates (two starts, no Hessian)."""
    from thermocal.statespace.estimation import fit

    return fit(
        res.model, data, n_starts=1, warm_start=res.params.to_dict(), compute_hessian=False,
        n_jobs=1, progress=False, **fit_kw,
    )  # fmt: skip


#: Shift of the inputs [samples] each time-stamp convention applies to the data as stamped
#: (input of row k = stamped input of row k - shift): ``end`` moves them one sample earlier.
STAMP_SHIFTS = {"start": 0, "end": -1}


def _shift_text(shift: int) -> str:
    """An input shift [samples] in words."""
    if shift == 0:
        return "as stamped"
    n = abs(shift)
    return f"{n} sample{'s' if n > 1 else ''} {'earlier' if shift < 0 else 'later'}"


def time_stamp_check(
    res,
    data,
    *,
    stamps: str = "start",
    time_column: str | None = None,
    time_unit: str | None = None,
    input_gaps: str = "interpolate",
    max_gap: int = 3,
) -> dict:
    """Which time-stamp convention the data support, by a likelihood comparison.

    The model of ``res`` is refitted (from its declared values and from ``res``'s estimates)
    on the same rows three times: with the inputs where the convention used puts them, and
    moved one sample either way. For ``start`` (each row's input holds from its stamp to the
    next) the neighbours are ``end`` (moved one sample earlier: each value is the mean over the
    interval ending at its stamp, see :func:`thermocal.statespace.data.end_stamped_inputs`)
    and the inputs one sample later; for ``end`` they are ``start`` and two samples earlier.
    The rows without an input in one of the shifts (the first and last) are left out of all,
    so the likelihoods cover the same outputs. The fits have the same parameters, so the
    differences of their log-likelihoods are the evidence (:data:`TIME_STAMP_EVIDENCE`).

    The convention used is *supported* only when it beats both neighbours. The other
    convention is suggested when it beats the one used; a neighbour that no convention gives
    (inputs one sample later than stamped: a lag the model lacks, such as a heater's or a
    sensor's capacity, or stamps one sample early) is reported in ``note``, not suggested.

    Parameters
    ----------
    res : FitResults
        A fit of the data (with either convention).
    data : DataFrame
        The data AS STAMPED (before any shift).
    stamps : {"start", "end"}
        The convention ``res`` was fitted with.
    time_column, time_unit : str, optional
        As for the fit; default: the fit's (:meth:`FitResults.time_options`).
    input_gaps, max_gap :
        As for the fit.

    Returns
    -------
    dict
        ``loglike_start``, ``loglike_end`` [-], ``loglikes`` ({shift [samples]:
        log-likelihood}, the inputs moved that many rows, negative: earlier), ``used``,
        ``supported`` (the convention used beats both neighbours), ``suggested`` (``"start"``,
        ``"end"`` or None: the other convention when it beats the one used, else the one used
        when supported), ``difference`` (the other convention's log-likelihood minus the used
        one's), ``message`` (None, or the flag: refit with the other convention) and ``note``
        (None, or a better neighbour that no convention gives).
    """
    from thermocal.statespace.data import shifted_inputs

    if stamps not in STAMP_SHIFTS:
        raise ThermocalInputError(f"time stamps {stamps!r}: use start or end")
    if len(data) < 10:
        raise ThermocalInputError("time-stamp check: at least 10 rows are needed")
    time_column, time_unit = res.time_options(data, time_column, time_unit)
    fit_kw = {"hold": res.hold, "time_column": time_column, "time_unit": time_unit,
              "input_gaps": input_gaps, "max_gap": max_gap}  # fmt: skip
    inputs = res.model.input_names
    used = STAMP_SHIFTS[stamps]
    other = "end" if stamps == "start" else "start"
    shifts = sorted({*STAMP_SHIFTS.values(), used - 1, used + 1})
    rows = slice(max(shifts), len(data) + min(shifts))  # every shift has its inputs there
    ll = {
        shift: float(_refit(res, shifted_inputs(data, inputs, shift).iloc[rows], fit_kw).loglike)
        for shift in shifts
    }
    diff = ll[STAMP_SHIFTS[other]] - ll[used]
    lead = ll[used] - max(ll[used - 1], ll[used + 1])
    supported = lead > TIME_STAMP_EVIDENCE
    suggested = other if diff > TIME_STAMP_EVIDENCE else stamps if supported else None
    message = note = None
    if suggested == other:
        meaning = (
            "the mean over the interval ENDING at each stamp"
            if other == "end"
            else "the value from each stamp to the next"
        )
        message = (
            f"time stamps: the data fit {diff:.1f} log-units better with --time-stamps {other} "
            f"(inputs {', '.join(inputs)} as {meaning}); the fit used '{stamps}', which "
            "shifts the inputs one sample against the response and biases the dynamics and "
            f"the heat loss coefficient; refit with --time-stamps {other}"
        )
    else:
        best = max(ll, key=ll.get)
        gain = ll[best] - ll[used]
        if best not in STAMP_SHIFTS.values() and gain > TIME_STAMP_EVIDENCE:
            note = (
                f"time stamps: '{stamps}' is not supported: the data fit {gain:.1f} "
                f"log-units better with the inputs {_shift_text(best - used)} than "
                f"--time-stamps {stamps} puts them, which no --time-stamps setting gives; the "
                "model may lack a lag of the response (a heater's or a sensor's capacity), "
                "or the stamps are one sample early; compare with a model with a heater "
                "state before trusting the dynamics"
            )
    return {
        "loglike_start": ll[STAMP_SHIFTS["start"]],
        "loglike_end": ll[STAMP_SHIFTS["end"]],
        "loglikes": {str(k): v for k, v in ll.items()},
        "used": stamps,
        "supported": bool(supported),
        "suggested": suggested,
        "difference": float(diff),
        "message": message,
        "note": note,
    }


def _overlap(a: dict, b: dict) -> bool:
    """True when two heat-loss intervals (``lower``/``upper``, else the Wald ones) overlap."""
    lo_a, hi_a = _ends(a)
    lo_b, hi_b = _ends(b)
    return lo_a <= hi_b and lo_b <= hi_a


def _ends(h: dict) -> tuple[float, float]:
    """The interval's ends [W/K]; an end of the profile not found (None) is unbounded."""
    if h.get("interval") == "profile":
        lower, upper = h["lower"], h["upper"]
        return (-math.inf if lower is None else lower), (math.inf if upper is None else upper)
    return h["wald_lower"], h["wald_upper"]


def heat_loss_path_parameters(model) -> set[str]:
    """The parameters of the conductances on the heat loss path of ``model``.

    The heat loss coefficient (:meth:`RCModel.heat_loss_coefficient`) is the steady heat flow
    from the observed state to the boundary temperatures; it depends on a conductance exactly
    when the link lies on a path from that state to a boundary that visits no state twice. A
    link to a dead end (a heater state, a thermal mass hanging off the interior) carries no
    steady flow and leaves the coefficient alone.

    Parameters
    ----------
    model : RCModel
        A model whose structure implies a heat loss coefficient.

    Returns
    -------
    set of str
        Names of the conductance [W/K] and resistance [K/W] parameters of those links (empty
        when the model implies no coefficient).
    """
    state = model.heat_loss_state()
    if state is None:
        return set()
    st = model.structure()
    edge_a, edge_b, link_ptr, link_idx = st.arrays[1:5]
    boundary = -1  # every boundary temperature: all held 1 K below the state
    ends = [
        (int(a), int(b) if b >= 0 else boundary) for a, b in zip(edge_a, edge_b, strict=True)
    ]
    on_path: set[int] = set()

    def walk(node: int, visited: frozenset, edges: tuple) -> None:
        for e, (a, b) in enumerate(ends):
            if node not in (a, b):
                continue
            other = b if node == a else a
            if other == boundary:
                on_path.update((*edges, e))
            elif other not in visited:
                walk(other, visited | {other}, (*edges, e))

    start = model.state_names.index(state)
    walk(start, frozenset({start}), ())
    names = model.parameter_names
    return {
        names[i]
        for e in on_path
        for i in link_idx[link_ptr[e] : link_ptr[e + 1]]
        if i < len(names)  # the rest are the model's constants
    }


def not_comparable(h: dict) -> str | None:
    """Why a period's heat loss coefficient cannot be compared with another's, or None.

    An interval that is not a number or has no width (a Wald interval without standard error,
    estimates held on a bound) says nothing about the period; a conductance or resistance on
    the heat loss path estimated on a bound (``h["at_bound_on_heat_loss_path"]``, see
    :func:`heat_loss_path_parameters`) makes the coefficient the bound's, not the data's (a
    unit slip or a wrong model shows that way), and two such coefficients differing says
    nothing about the regime. Other estimates on a bound (capacities, scales, fractions, links
    off the path) leave the coefficient to the data: the periods are compared, with a caveat
    (:func:`bound_caveat`).

    Parameters
    ----------
    h : dict
        A period's heat loss coefficient [W/K] (:meth:`FitResults.heat_loss_coefficient`) with
        ``at_bound_on_heat_loss_path``.

    Returns
    -------
    str or None
        The reason, for the message.
    """
    on_path = h.get("at_bound_on_heat_loss_path")
    if on_path:
        names = ", ".join(on_path)
        return f"a conductance or resistance of the heat loss path on a bound ({names})"
    lo, hi = _ends(h)
    if math.isnan(lo) or math.isnan(hi) or not hi > lo:
        return "no interval (no standard error)"
    return None


def bound_caveat(periods: dict) -> str | None:
    """The caveat for compared periods with estimates on a bound off the heat loss path.

    Parameters
    ----------
    periods : dict
        ``{label: heat loss coefficient dict}`` with ``at_bound`` (physical estimates on a
        bound) and ``at_bound_on_heat_loss_path``.

    Returns
    -------
    str or None
        None when no period has such an estimate.
    """
    parts = []
    for label, h in periods.items():
        off_path = [n for n in h["at_bound"] if n not in h["at_bound_on_heat_loss_path"]]
        if off_path:
            parts.append(f"'{label}': {', '.join(off_path)}")
    if not parts:
        return None
    return (
        "Estimates on a bound (" + "; ".join(parts) + ") do not set the coefficients, but the "
        "other estimates were fitted with them held there (a capacity on its bound: a period "
        "too short for the slow dynamics; a scale or fraction at 0: an input the period hardly "
        "excites); confirm with those bounds widened or the parameters fixed"
    )


def heat_loss_regime_check(
    model,
    periods: dict,
    *,
    hold: str = "zoh",
    time_column: str | None = None,
    time_unit: str = "s",
    profile: bool = True,
    alpha: float = 0.05,
    n_starts: int | None = None,
    seed: int | None = None,
    input_gaps: str = "error",
    max_gap: int = 3,
) -> dict:
    """Heat loss coefficients of the same model fitted on separate periods, compared.

    The coefficient of a model whose only boundary is the outdoor air is the steady heat flow
    per kelvin to it in the regime the data cover. When adjacent spaces (cellar, attic,
    neighbours) are not in the model and follow the test regime, or the period is a heating
    sequence whose mean indoor-outdoor difference hardly changes (Bacher & Madsen 2011: a
    pseudo-random sequence identifies the dynamics well and the steady level poorly), the
    coefficients of different periods disagree. Each period is fitted and its coefficient
    given with its interval (profile likelihood, Pawitan 2001; else Wald); the check is
    flagged when two intervals do not overlap.

    Parameters
    ----------
    model : RCModel
    periods : dict
        ``{label: DataFrame}``, e.g. a randomised heating sequence and a steady period.
    hold, time_column, time_unit, n_starts, seed, input_gaps, max_gap :
        As for :meth:`RCModel.fit`.
    profile : bool
        Profile-likelihood intervals (else Wald).
    alpha : float
        1 - confidence level of the intervals.

    Returns
    -------
    dict
        ``periods`` ({label: heat loss coefficient dict with ``loglike``, ``converged``,
        ``at_bound`` (physical estimates on a bound), ``at_bound_on_heat_loss_path`` (those
        of them on the heat loss path, :func:`heat_loss_path_parameters`) and the regime:
        ``mean_heat`` [W], ``mean_difference`` [K] and ``balance`` [W/K], the ratio of the
        two}), ``comparable`` (every period has a finite interval of some width and no
        conductance or resistance of the heat loss path on a bound, :func:`not_comparable`),
        ``agree`` (every pair of intervals overlaps; None when not comparable), ``message``
        (None, the warning with the numbers and the caveat of :func:`bound_caveat`, or why the
        periods were not compared).
    """
    from thermocal.statespace.selection import physical_at_bound

    if model.heat_loss_state() is None:
        raise ThermocalInputError(
            f"model '{model.name}' implies no heat loss coefficient (no output observes a "
            "single state connected to a boundary temperature)"
        )
    if len(periods) < 2:
        raise ThermocalInputError("heat-loss regime check: give at least two periods")
    out = {}
    for label, data in periods.items():
        res = model.fit(
            data, hold=hold, time_column=time_column, time_unit=time_unit, n_starts=n_starts,
            seed=seed, progress=False, source=f"period '{label}'", input_gaps=input_gaps,
            max_gap=max_gap,
        )  # fmt: skip
        h = res.heat_loss_coefficient(profile=profile, alpha=alpha)
        at_bound = physical_at_bound(res)
        on_path = heat_loss_path_parameters(res.model)
        h |= {"loglike": res.loglike, "converged": bool(res.converged), "at_bound": at_bound,
              "at_bound_on_heat_loss_path": [n for n in at_bound if n in on_path]}  # fmt: skip
        h |= _regime(res)
        out[label] = h
    labels = list(out)
    reasons = {label: not_comparable(out[label]) for label in labels}
    if any(reasons.values()):
        parts = [f"'{label}': {why}" for label, why in reasons.items() if why]
        message = (
            "heat loss coefficient per period not compared: " + "; ".join(parts) + ". A "
            "coefficient without an interval, or whose heat loss path is held on a bound (the "
            "coefficient is then the bound's), says nothing about the period: see the flags of "
            "the fit (a unit slip, a wrong column, a model that does not fit the data) before "
            "judging the period dependence"
        )
        return {"periods": out, "comparable": False, "agree": None, "message": message}
    disagree = [
        (a, b)
        for i, a in enumerate(labels)
        for b in labels[i + 1 :]
        if not _overlap(out[a], out[b])
    ]
    message = None
    if disagree:
        parts = []
        for label in labels:
            lo, hi = _ends(out[label])
            parts.append(f"{label}: {out[label]['value']:.4g} W/K [{lo:.4g}, {hi:.4g}]")
        message = (
            "heat loss coefficient depends on the period: " + "; ".join(parts) + ". The "
            "intervals of " + ", ".join(f"'{a}' and '{b}'" for a, b in disagree) + " do not "
            "overlap: the coefficient to the outdoor air holds only in the regime of each "
            "period (a heating sequence alone identifies the steady level poorly; adjacent "
            "unheated spaces that follow the test are not in the model). Report the one of "
            "the period that represents the use you need, or model the adjacent spaces as "
            "boundary temperatures"
        )
        caveat = bound_caveat(out)
        if caveat:
            message += ". " + caveat
    return {"periods": out, "comparable": True, "agree": not disagree, "message": message}


def _regime(res) -> dict:
    """Mean heat input [W] (heating and solar gains at the estimates), mean difference between
    the observed state and the boundary temperatures [K] and their ratio [W/K] over the fitted
    data: the steady energy balance of the period."""
    from thermocal.statespace import kernels

    model, prep = res.model, res.data
    st = model.structure()
    s = model.state_names.index(model.heat_loss_state())
    r = next(
        r for r in range(st.C.shape[0]) if st.C[r, s] == 1.0 and np.count_nonzero(st.C[r]) == 1
    )
    _, _, B_raw, _ = kernels.build_network(
        model.values_si(res.params.to_dict()), *st.arrays[:15], st.arrays[18], st.n_inputs
    )
    n_b = len(model.boundary_names)
    u = np.nanmean(prep.U, axis=0)
    heat = float(B_raw[:, n_b:].sum(axis=0) @ u[n_b:])
    diff = float(np.nanmean(prep.Y[:, r]) - u[:n_b].mean())
    balance = heat / diff if abs(diff) > 1e-9 else math.nan
    return {"mean_heat": heat, "mean_difference": diff, "balance": balance}


def split_at(data, splits, *, time_column: str | None = None, time_unit: str = "s",
             source: str = "data") -> dict:  # fmt: skip
    """``data`` cut into consecutive periods at the given times.

    Parameters
    ----------
    data : DataFrame
    splits : sequence of str or float
        Times where a new period starts: ISO 8601 stamps for datetime axes (in the data's time
        zone when they carry no offset), numbers in ``time_unit`` for numeric axes.
    time_column, time_unit, source :
        See :func:`thermocal.statespace.data.time_axis`.

    Returns
    -------
    dict
        ``{"until <t1>": rows before t1, "<t1> to <t2>": ..., "from <tk>": ...}``.
    """
    import pandas as pd

    from thermocal.statespace.data import time_axis

    index, _ = time_axis(data, time_column=time_column, time_unit=time_unit, source=source)
    cuts = []
    for s in splits:
        try:
            if isinstance(index, pd.DatetimeIndex):
                t = pd.Timestamp(s)
                if t.tzinfo is None and index.tz is not None:
                    t = t.tz_localize(index.tz)
            else:
                t = float(s)
        except (ValueError, TypeError):
            kind = "an ISO 8601 time stamp" if isinstance(index, pd.DatetimeIndex) else (
                f"a number in {time_unit}")  # fmt: skip
            raise ThermocalInputError(f"{source}: split time {s!r}: give {kind}") from None
        if not index[0] < t <= index[-1]:
            raise ThermocalInputError(
                f"{source}: split time {s!r} is not inside the data ({index[0]} to {index[-1]})"
            )
        cuts.append((t, str(s)))
    cuts.sort(key=lambda c: c[0])
    bounds = [None, *[c[0] for c in cuts], None]
    names = [c[1] for c in cuts]
    periods = {}
    for i in range(len(bounds) - 1):
        lo, hi = bounds[i], bounds[i + 1]
        mask = np.ones(len(index), dtype=bool)
        if lo is not None:
            mask &= np.asarray(index >= lo)
        if hi is not None:
            mask &= np.asarray(index < hi)
        if i == 0:
            label = f"until {names[0]}"
        elif i == len(bounds) - 2:
            label = f"from {names[-1]}"
        else:
            label = f"{names[i - 1]} to {names[i]}"
        if mask.sum() < 10:
            raise ThermocalInputError(f"{source}: period '{label}' has fewer than 10 rows")
        periods[label] = data.iloc[np.flatnonzero(mask)]
    return periods


def split_halves(data, *, time_column: str | None = None, time_unit: str = "s",
                 source: str = "data") -> dict:  # fmt: skip
    """``data`` cut into its first and second half (by rows), for
    :func:`heat_loss_regime_check` when no period is given.

    An experiment whose regime changes (a randomised heating sequence followed by steady
    phases, adjacent spaces conditioned differently) usually changes it somewhere inside; the
    halves then see different regimes and their heat loss coefficients differ.

    Returns
    -------
    dict
        ``{"first half (until <t>)": rows before t, "second half (from <t>)": the rest}``.
    """
    from thermocal.statespace.data import time_axis

    index, _ = time_axis(data, time_column=time_column, time_unit=time_unit, source=source)
    n = len(index)
    if n < 20:
        raise ThermocalInputError(f"{source}: {n} rows, too few to compare two halves")
    cut = index[n // 2]
    stamp = cut.isoformat() if hasattr(cut, "isoformat") else f"{cut:g} {time_unit}"
    return {
        f"first half (until {stamp})": data.iloc[: n // 2],
        f"second half (from {stamp})": data.iloc[n // 2 :],
    }
