"""Compiled time loop of the multi-zone simulation (numba).

One backward-Euler step of the network assembled in :mod:`thermocal.multizone.network`:

1. ``rhs = C/dt x_old + B u_k`` (``B`` in CSR form, ``u_k`` one row of the input matrix);
2. explicit corrections evaluated with ``x_old``: wind-dependent exterior convection minus its
   matrix part, exact ``sigma T^4`` exterior long-wave exchange minus its linearisation, TARP
   interior convection minus its matrix part, air-density variation of the infiltration;
2'. scheduled or temperature-switched outdoor air of the free zones implicit in its own step: the
   step's conductance beyond the matrix value enters through the zones' air-temperature response
   (a Woodbury correction costing one more substitution, see :func:`run_steps`);
3. ``x_free = A^{-1} rhs`` by forward/backward substitution with the sparse LU factors of
   ``A = C/dt + K`` (computed once by SuperLU; the loop's pieces are in
   :mod:`thermocal.multizone._kernel_parts`);
4. ideal loads by superposition: ``T_air = T_free + G q`` with ``G`` the air-temperature response to
   unit heat in each controlled zone (precomputed); the active set (zones at their heating or
   cooling set point) is found by a small active-set iteration, ``q`` from the dense system on the
   active set, and ``x = A^{-1}(rhs + E q)`` by a second substitution (set points are met
   exactly, no iteration on the network).

Tracking modes (heat-balance identification, :mod:`thermocal.identification`): instead of the
ideal loads, every tracked zone (``ctrl_zone``) receives the heat that makes the model follow a
reference temperature ``track_ref``:

- ``track_mode == 1`` (exact inverse): the heat of the step that puts the zone's sensed
  temperature exactly on the reference at the end of the step: air temperature with the heat in
  the air (Dirichlet system, one substitution), or in general (``track_general``) by
  superposition with the inverse ``g_track_inv`` of the sensed-temperature response to unit
  heat distributed as the zone's heat is;
- ``track_mode == 2`` (discrete PID per zone in controller canonical form): the heat of the step
  from the error between the reference and the model's sensed temperature at the end of the
  previous step (``track_fb``), as a co-simulated controller sees it; optional output limits
  with conditional integration.

The sensed temperature of tracked zone ``c`` is ``w T_air + (1 - w) T_surf`` with
``w = track_w_air[c]`` and ``T_surf`` the area-weighted interior surface temperature (``w = 1``
air, ``0.5`` operative); in a run (``track_mode == 0``) ``track_w_air`` weighs the temperature
the ideal loads hold (an operative thermostat: ``1 - f``, ``f`` its radiative fraction); a
tracked zone's heat enters the nodes ``track_idx[track_ptr[c]:track_ptr[c+1]]``
with weights ``track_val`` summing to one (the air node, and the zone's faces for a radiant
part).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from thermocal.multizone._kernel_parts import (  # noqa: F401 - the loop's pieces, re-exported
    PEOPLE_T0,
    _invert_into,
    _refined_solve,
    _sparse_diag,
    _sync_inverse,
    cube_root_update,
    ideal_loads,
    iso15099_window_interior,
    lu_solve,
    outdoor_air_excess,
    people_excess,
    prepare_factors,
    simple_interior,
    tarp,
    tarp_coefficients,
    tarp_excess,
    tarp_from_root,
    zone_mean_radiant,
)

SIGMA = 5.670374419e-8
KELVIN = 273.15


@njit(cache=True, error_model="numpy", fastmath=True, inline="always")
def exterior_excess(
    ts, t_out, t_sky, dh, mode, rough, cos_up, hc0, hmax, area, area_eps, view_air, view_sky, hr0,
    exact,
):  # fmt: skip
    """An exterior face's lagged correction [W]: its convection beyond the matrix's ``hc0`` and,
    with ``exact``, its long-wave's exact ``sigma T^4`` beyond the matrix's linearisation
    ``hr0``, at the face's temperature ``ts`` of the previous step.

    ``mode``, ``rough``, ``cos_up``, ``hc0``, ``hmax`` are the face's row of ``ext_natural`` (mode,
    DOE-2 roughness multiplier, cosine of the tilt, ``hc0``, largest excess; scalars: passing
    the row cost the clinic's step 5-8 us); ``dh`` the step's wind series: mode 0 the excess over
    ``hc0``, 1 DOE-2 and 2 TARP the forced term, combined with TARP's natural part at the face's
    difference from the air (EnergyPlus' outside ``CalcASHRAETARPNatural``)."""
    if mode < 0.0:
        dh = 0.0  # no convection excess (a wet face)
    elif mode == 0.0:
        # the series is the excess over hc0: clipped to the stable range of the lag
        dh = min(max(dh, 0.1 - hc0), hmax)
    else:
        hn = tarp(ts - t_out, cos_up)
        if mode == 1.0:
            hc = hn + rough * (np.sqrt(hn * hn + dh * dh) - hn)
        else:
            hc = hn + dh
        dh = min(max(hc - hc0, 0.1 - hc0), hmax)
    corr = dh * area * (t_out - ts)
    if exact:
        ts2 = (ts + KELVIN) * (ts + KELVIN)
        to2 = (t_out + KELVIN) * (t_out + KELVIN)
        tk2 = (t_sky + KELVIN) * (t_sky + KELVIN)
        ts4 = ts2 * ts2
        to4 = to2 * to2
        tk4 = tk2 * tk2
        exact_flux = SIGMA * (view_air * (to4 - ts4) + view_sky * (tk4 - ts4))
        linear = hr0 * (view_air * (t_out - ts) + view_sky * (t_sky - ts))
        corr += area_eps * (exact_flux - linear)
    return corr


@njit(cache=True, error_model="numpy", fastmath=True)
def run_steps(
    k0,
    n_steps,
    x,
    c_dt,
    b_row,
    b_col,
    b_val,
    u,
    heat_extra,
    l_row,
    l_col,
    l_val,
    u_row,
    u_col,
    u_val,
    inv_diag,
    inverse_r,
    perm_c,
    ext_node,
    ext_area_eps,
    ext_view_air,
    ext_view_sky,
    ext_hr0,
    ext_dh,
    ext_class,
    ext_natural,
    exact_sky,
    face_node,
    face_air,
    face_area,
    face_cos,
    face_h0,
    face_hmax,
    tarp_on,
    face_root,
    face_iso,
    iso_pressure,
    air_node,
    inf_ratio,
    inf_base,
    inf_column,
    inf_scheduled,
    inf_dt,
    people_a,
    people_b,
    people_c,
    people_max,
    people_face_w,
    ctrl_zone,
    ctrl_heat_sp,
    ctrl_cool_sp,
    g_ctrl,
    ideal_on,
    face_zone,
    zone_face_area,
    out_air,
    out_mrt,
    out_heat,
    out_cool,
    out_face,
    store_faces,
    active,
    cache_member,
    cache_inv,
    cache_m,
    use_dirichlet,
    dl_row,
    dl_col,
    dl_val,
    du_row,
    du_col,
    du_val,
    d_inv_diag,
    d_inverse_r,
    d_perm_c,
    a_ptr,
    a_idx,
    a_val,
    win_outer,
    win_inner,
    win_g0,
    win_ratio,
    win_grid0,
    win_grid_step,
    exact_interior,
    face_mrt,
    face_mrt_g,
    lw_pair_a,
    lw_pair_b,
    lw_pair_g,
    h_black,
    track_mode,
    track_ref,
    track_general,
    track_w_air,
    track_ptr,
    track_idx,
    track_val,
    pid_d,
    pid_c1,
    pid_c2,
    pid_state,
    track_fb,
    q_lo,
    q_hi,
    g_track_inv,
    out_q,
    imp_zone,
    imp_g,
    imp_d,
    imp_inv,
    imp_free,
    vent_zone,
    vent_g,
    vent_gdt,
    vent_fan,
    vent_tmin,
    vent_tmax,
    vent_delta,
    vent_open,
    gt_zone,
    gt_aq,
    gt_k,
    gt_m,
    gt_d,
    gt_inv,
    rain,
    t_wb,
    wet_of,
    wet_node,
    wet_d,
    wet_h0a,
    wet_m,
    wet_c,
    gf_column,
    gf_class,
    gf_out_ptr,
    gf_out_idx,
    gf_out_val,
    gf_u_ptr,
    gf_u_idx,
    gf_u_val,
    gf_eps,
    gf_view_air,
    gf_view_sky,
    gf_hr0,
    gf_exact,
):
    """Advance ``n_steps`` steps from step index ``k0``; ``x`` is updated in place.

    ``active`` (ideal-load state of each controlled zone: 1 heating, -1 cooling, 0 free) and the
    cached inverse of the active block of ``g_ctrl`` persist between calls (warm start).
    With ``track_mode`` 1 or 2 the controlled zones are the tracked ones (see the module
    docstring); ``pid_state`` (nc, 2) and ``track_fb`` (nc,) persist between calls; the heat of
    each tracked zone is written to ``out_q`` (n_steps, nc) [W].

    Outdoor air of the zones ``imp_zone`` (m,) is implicit: the step's conductance beyond the
    matrix value, ``d`` (:func:`outdoor_air_excess`: ``inf_ratio[k] inf_base[z]``, or
    ``inf_scheduled[k, inf_column[z]]`` for a scheduled zone) plus the open indoor-limited
    ventilation objects, enters the step it belongs to through the air-temperature response
    ``imp_g`` (m, m) [K/W] of the first solve's system (Woodbury: ``(I + G diag(d)) y = y0 + G d
    T_out``); ``imp_d`` (m + 1,) and ``imp_inv`` (m, m) cache the last ``d`` and the inverse
    (``imp_d[m]`` 0: invalid). The
    other zones take it with their previous temperature, except the zones tracked by the exact
    air inverse that a free run treats implicitly (``imp_free`` (nz,) true): at their reference,
    their end-of-step temperature, so that tracking a free run's temperatures is exact.

    The wind's exterior convection ``ext_dh`` is one series per class of faces (steps,
    classes): face ``e`` takes ``ext_dh[k, ext_class[e]]``.

    Indoor-limited ventilation objects ``vent_zone`` (j,): open at step ``k`` when the zone air
    temperature of the previous step ``T`` satisfies ``vent_tmin <= T <= vent_tmax`` and
    ``T - T_out >= vent_delta`` (EnergyPlus tests the zone temperature of the previous step);
    open, they add ``vent_g`` [W/K] to the zone's outdoor-air conductance, ``vent_gdt |dT|``
    [W/K^2] lagged and the fan heat ``vent_fan`` [W]; ``vent_open[k, j]`` records the open
    fraction (an object crossing its lower limit within the step is open for a fraction of it).

    Rain (``rain`` (steps,) nonzero on wet steps; empty: no rain in the period): the
    wind-exposed exterior faces ``wet_node`` (m,) (``wet_of`` (n_ext,): index among them or -1)
    take, as EnergyPlus' wet outside faces, a convection coefficient of 1000 W/m2K to the outdoor
    wet-bulb temperature ``t_wb`` (steps,) instead of the wind's coefficient to the dry bulb: the
    matrix part ``hc0 A`` is moved to the wet bulb (``wet_h0a``, explicit), the excess
    ``wet_d = (1000 - hc0) A`` is implicit in the step (Woodbury on the faces' response: with
    ``y0`` their temperatures without it, ``y = wet_m y0 + wet_c T_wb``, ``wet_m = (I + G D)^-1``,
    ``wet_c = wet_m G D 1``, one more substitution per wet step, with the tracked air held in the
    exact inverse) and the wind's explicit excess is not applied.

    General exact inverse (``track_general``): the tracked zones ``gt_zone`` (mt,) with
    scheduled outdoor air take it in the step it belongs to, solved with the tracking heat:
    with ``q0`` the heat without it and ``a1 = a0 + gt_aq q0`` their air temperatures,
    ``(I + D gt_m) h = D (T_out - a1)``, ``q = q0 - gt_k h`` (``gt_aq`` (mt, nc) air response to
    the tracked heat, ``gt_k`` (nc, mt) = inverse sensed response x sensed response to air heat,
    ``gt_m = A_h - gt_aq gt_k`` (mt, mt)); ``gt_d``, ``gt_inv`` cache ``D`` and the inverse.
    """
    factors = (l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c)
    d_factors = (dl_row, dl_col, dl_val, du_row, du_col, du_val, d_inv_diag, d_inverse_r, d_perm_c)
    n = x.shape[0]
    nz = air_node.shape[0]
    nc = ctrl_zone.shape[0]
    rhs = np.empty(n)
    work = np.empty(n)
    x_new = np.empty(n)
    q = np.zeros(nc)
    t_free = np.empty(nc)
    rhs_d = np.empty(n)
    mrt_tmp = np.zeros(nz)
    # a run's ideal loads holding an operative temperature (track_w_air < 1 for that zone)
    operative = False
    if track_mode == 0 and track_w_air.shape[0] == nc:
        for c in range(nc):
            if track_w_air[c] < 1.0:
                operative = True
    face_excess = np.zeros(face_node.shape[0])
    face_lw = np.zeros(face_node.shape[0])
    zone_excess = np.zeros(nz)
    zone_g0 = np.zeros(nz)
    zone_scale = np.ones(nz)
    sp_rows = ctrl_heat_sp.shape[0]
    dt_rows = inf_dt.shape[0]
    people_rows = people_b.shape[0]
    # People's temperature correction split as EnergyPlus splits their sensible heat: the
    # radiant share onto the zone's faces (people_face_w), the rest into the air
    people_air_w = np.ones(nz)
    if people_rows > 0:
        for f in range(people_face_w.shape[0]):
            people_air_w[face_zone[f]] -= people_face_w[f]
    zone_people = np.zeros(nz)
    m_imp = imp_zone.shape[0]
    n_vent = vent_zone.shape[0]
    gdt_rows = vent_gdt.shape[0]
    imp_of = np.full(nz, -1, dtype=np.int64)
    for i in range(m_imp):
        imp_of[imp_zone[i]] = i
    d_now = np.zeros(m_imp)
    y_imp = np.zeros(m_imp)
    b_imp = np.zeros(m_imp)
    h_col = np.zeros(m_imp)
    g_col = np.zeros(m_imp)
    r_imp = np.zeros(m_imp)
    vent_d = np.zeros(nz)
    inf_temp = np.empty(nz)
    dirichlet_first = track_mode == 1 and not track_general
    mt = gt_zone.shape[0]
    gt_of = np.full(nz, -1, dtype=np.int64)
    for i in range(mt):
        gt_of[gt_zone[i]] = i
    d_t = np.zeros(mt)
    r_t = np.zeros(mt)
    h_t = np.zeros(mt)
    res_t = np.zeros(mt)
    n_faces = face_node.shape[0]
    rain_rows = rain.shape[0]
    m_wet = wet_node.shape[0]
    wet_x = np.empty(n if rain_rows > 0 else 0)
    wet_y = np.empty(m_wet)
    # the zones' interior convective conductance in the matrix (constant over the steps)
    for f in range(n_faces):
        zone_g0[face_zone[f]] += face_h0[f] * face_area[f]
    # TARP's coefficients per face and direction of the flow, and the windows (ISO 15099)
    tarp_num_up, tarp_num_down, tarp_den_up, tarp_den_down = tarp_coefficients(face_cos)
    face_dt = np.empty(n_faces)
    n_windows = 0
    for f in range(n_faces):
        if face_iso[f, 0] > 0.0:
            n_windows += 1
    window_faces = np.empty(n_windows, dtype=np.int64)
    i_window = 0
    for f in range(n_faces):
        if face_iso[f, 0] > 0.0:
            window_faces[i_window] = f
            i_window += 1
    for s in range(n_steps):
        k = k0 + s
        # set points: one row per step, or a single row for the whole run
        sp_k = k if sp_rows > 1 else 0
        heat_sp_k = ctrl_heat_sp[sp_k]
        cool_sp_k = ctrl_cool_sp[sp_k]
        # 0. the foundations' exterior faces (Kiva's grade, the walls above it): their lagged
        # correction per m2 into their input columns, the faces' temperatures the ground
        # sections' outputs at the previous step's end (its states and, through the quasi-static
        # states, its inputs); the same excess as the exterior faces' (2. below). At a run's
        # first step the states alone: the inputs' row before it is not this run's (a column
        # would hold an earlier run's correction, and the result would depend on it)
        n_ext = ext_node.shape[0]
        for g in range(gf_column.shape[0]):
            ts = 0.0
            for p in range(gf_out_ptr[g], gf_out_ptr[g + 1]):
                ts += gf_out_val[p] * x[gf_out_idx[p]]
            if k > 0:
                for p in range(gf_u_ptr[g], gf_u_ptr[g + 1]):
                    ts += gf_u_val[p] * u[k - 1, gf_u_idx[p]]
            f = n_ext + g
            u[k, gf_column[g]] = exterior_excess(
                ts, u[k, 0], u[k, 1], ext_dh[k, gf_class[g]], ext_natural[f, 0],
                ext_natural[f, 1], ext_natural[f, 2], ext_natural[f, 3], ext_natural[f, 4], 1.0,
                gf_eps[g], gf_view_air[g], gf_view_sky[g], gf_hr0, gf_exact,
            )  # fmt: skip
        # 1. rhs = C/dt x + B u_k
        for i in range(n):
            rhs[i] = c_dt[i] * x[i]
        for p in range(b_val.shape[0]):  # one loop over B's entries, row by row (no branch per row)
            rhs[b_row[p]] += b_val[p] * u[k, b_col[p]]
        for z in range(nz):
            rhs[air_node[z]] += heat_extra[s, z]
        t_out = u[k, 0]
        t_sky = u[k, 1]
        wet = rain_rows > 0 and rain[k] != 0
        # 2. explicit corrections
        for e in range(ext_node.shape[0]):
            node = ext_node[e]
            ts = x[node]
            # the wind's series is shared by the faces of one class (orientation, exposure)
            if wet and wet_of[e] >= 0:
                # a wet face: convection to the wet bulb (1b below), no wind excess
                corr = exterior_excess(
                    ts, t_out, t_sky, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, ext_area_eps[e, 0],
                    ext_area_eps[e, 1], ext_view_air[e], ext_view_sky[e], ext_hr0, exact_sky,
                )  # fmt: skip
            else:
                corr = exterior_excess(
                    ts, t_out, t_sky, ext_dh[k, ext_class[e]], ext_natural[e, 0],
                    ext_natural[e, 1], ext_natural[e, 2], ext_natural[e, 3], ext_natural[e, 4],
                    ext_area_eps[e, 0], ext_area_eps[e, 1], ext_view_air[e], ext_view_sky[e],
                    ext_hr0, exact_sky,
                )  # fmt: skip
            rhs[node] += corr
        if tarp_on == 1:
            # TARP on every face at once (vector code), then ISO 15099 on the windows
            for f in range(n_faces):
                face_dt[f] = x[face_node[f]] - x[face_air[f]]
            tarp_excess(face_dt, face_root, face_cos, tarp_num_up, tarp_num_down, tarp_den_up,
                        tarp_den_down, face_hmax, face_h0, face_area, face_excess)  # fmt: skip
            for i in range(window_faces.shape[0]):
                f = window_faces[i]
                if abs(face_dt[f]) < 100.0:
                    # ISO 15099 at its height (EnergyPlus' TARP for windows); beyond 100 K (a
                    # diverging run) TARP, whose growth lets the loop's checks see it
                    h = iso15099_window_interior(
                        x[face_node[f]],
                        x[face_air[f]],
                        face_iso[f, 0],
                        face_iso[f, 1],
                        face_iso[f, 2],
                        face_iso[f, 3:5],
                        iso_pressure,
                    )
                    if h > face_hmax[f]:
                        h = face_hmax[f]
                    face_excess[f] = (h - face_h0[f]) * face_area[f]
        elif tarp_on:
            # EnergyPlus' Simple algorithm (tarp_on 2), per face
            for f in range(n_faces):
                dt_s = x[face_node[f]] - x[face_air[f]]
                face_root[f] = cube_root_update(abs(dt_s), face_root[f])
                h = simple_interior(dt_s, face_cos[f])
                if h > face_hmax[f]:
                    h = face_hmax[f]
                face_excess[f] = (h - face_h0[f]) * face_area[f]
        if tarp_on:
            # per zone, in face order (the same sums as one pass)
            for z in range(nz):
                zone_excess[z] = 0.0
            for f in range(n_faces):
                if face_excess[f] > 0.0:
                    zone_excess[face_zone[f]] += face_excess[f]
            # the excess conductances of a zone's faces all act on its air node, lagged: with
            # the surfaces held, the air's deviation from them is multiplied by
            # (C/dt - Gx) / (C/dt + G0) each step, so a positive excess Gx above
            # (4 C/dt + G0) / 3 (a factor below -1/3: a growing or ringing oscillation, small
            # rooms at long steps; 2 kW in a 3 m concrete box at 1 h grew 4-fold per step) is
            # scaled down to that limit
            for z in range(nz):
                limit = (c_dt[air_node[z]] * 4.0 + zone_g0[z]) / 3.0
                zone_scale[z] = 1.0
                if zone_excess[z] > limit:
                    zone_scale[z] = limit / zone_excess[z]
            for f in range(face_node.shape[0]):
                node = face_node[f]
                an = face_air[f]
                g_x = face_excess[f]
                if g_x > 0.0:
                    g_x *= zone_scale[face_zone[f]]
                corr = g_x * (x[an] - x[node])
                rhs[node] += corr
                rhs[an] -= corr
        # exact interior long-wave exchange: face <-> radiant star node with the coefficient
        # sigma (Tf^2 + Tr^2)(Tf + Tr) instead of 4 sigma T0^3
        if exact_interior:
            # the corrections first (independent per face), then added in face order
            for f in range(n_faces):
                r_node = face_mrt[f]
                if r_node < 0:
                    continue
                node = face_node[f]
                tf = x[node] + KELVIN
                tr = x[r_node] + KELVIN
                h_exact = SIGMA * (tf * tf + tr * tr) * (tf + tr)
                face_lw[f] = face_mrt_g[f] * (h_exact / h_black - 1.0) * (x[r_node] - x[node])
            for f in range(n_faces):
                r_node = face_mrt[f]
                if r_node < 0:
                    continue
                rhs[face_node[f]] += face_lw[f]
                rhs[r_node] -= face_lw[f]
            # pairwise exchange factors: the same correction between the two faces of a pair
            for p in range(lw_pair_a.shape[0]):
                a = lw_pair_a[p]
                b = lw_pair_b[p]
                ta = x[a] + KELVIN
                tb = x[b] + KELVIN
                h_exact = SIGMA * (ta * ta + tb * tb) * (ta + tb)
                corr = lw_pair_g[p] * (h_exact / h_black - 1.0) * (x[b] - x[a])
                rhs[a] += corr
                rhs[b] -= corr
        # temperature-dependent glass-to-glass conductance of windows (gas gaps): the excess over
        # the matrix value, interpolated at the mean of the two glass faces
        n_grid = win_ratio.shape[1]
        for j in range(win_outer.shape[0]):
            o = win_outer[j]
            i_node = win_inner[j]
            pos = (0.5 * (x[o] + x[i_node]) - win_grid0) / win_grid_step
            if pos <= 0.0:
                ratio = win_ratio[j, 0]
            elif pos >= n_grid - 1:
                ratio = win_ratio[j, n_grid - 1]
            else:
                g = int(pos)
                frac = pos - g
                ratio = win_ratio[j, g] * (1.0 - frac) + win_ratio[j, g + 1] * frac
            corr = (ratio - 1.0) * win_g0[j] * (x[i_node] - x[o])
            rhs[i_node] -= corr
            rhs[o] += corr
        # outdoor air: the temperature it meets (previous step; a zone tracked by the exact
        # air inverse is at its reference at the end of the step)
        for z in range(nz):
            inf_temp[z] = x[air_node[z]]
            vent_d[z] = 0.0
        if dirichlet_first:
            for c in range(nc):
                if imp_free[ctrl_zone[c]]:
                    inf_temp[ctrl_zone[c]] = track_ref[s, c]
        # indoor-limited ventilation: open or closed on the previous step's zone temperature
        for j in range(n_vent):
            z = vent_zone[j]
            an = air_node[z]
            t_zone = x[an]
            if (
                t_zone >= vent_tmin[k, j]
                and t_zone <= vent_tmax[k, j]
                and t_zone - t_out >= vent_delta[k, j]
            ):
                vent_open[k, j] = 1.0
                vent_d[z] += vent_g[k, j]
                rhs[an] += vent_fan[k, j]
                if gdt_rows > 0:
                    diff = t_out - inf_temp[z]
                    rhs[an] += vent_gdt[k, j] * abs(diff) * diff
            else:
                vent_open[k, j] = 0.0
        for z in range(nz):
            if imp_of[z] >= 0 or gt_of[z] >= 0:
                continue
            an = air_node[z]
            d_air = outdoor_air_excess(k, z, inf_ratio, inf_base, inf_column, inf_scheduled)
            rhs[an] += (d_air + vent_d[z]) * (t_out - inf_temp[z])
        # infiltration temperature term (conductance per kelvin of |T_zone - T_out|), lagged
        if dt_rows > 0:
            dt_k = k if dt_rows > 1 else 0
            for z in range(nz):
                an = air_node[z]
                diff = t_out - inf_temp[z]
                rhs[an] += inf_dt[dt_k, z] * abs(diff) * diff
        # People's sensible heat at the zone air temperature (lagged) beyond its value at the
        # reference temperature the gains hold: a + b T + c T^2 clipped to [0, activity] as
        # EnergyPlus does (above ~35 C the polynomial turns negative: occupants are no sinks)
        if people_rows > 0:
            for z in range(nz):
                an = air_node[z]
                zone_people[z] = people_excess(
                    x[an], people_a[k, z], people_b[k, z], people_c[k, z], people_max[k, z]
                )
                rhs[an] += people_air_w[z] * zone_people[z]
            for f in range(people_face_w.shape[0]):
                rhs[face_node[f]] += people_face_w[f] * zone_people[face_zone[f]]
        # 1''. PID heat from the error at the start of the step: known before the solve, so the
        #      PID zones' outdoor air is implicit in the step as a free-floating zone's (2')
        if track_mode == 2:
            for c in range(nc):
                e = track_ref[s, c] - track_fb[c]
                u_c = pid_c1[c] * pid_state[c, 0] + pid_c2[c] * pid_state[c, 1] + pid_d[c] * e
                integrate = 1.0
                if u_c > q_hi[c]:
                    u_c = q_hi[c]
                    if e > 0.0:
                        integrate = 0.0
                elif u_c < q_lo[c]:
                    u_c = q_lo[c]
                    if e < 0.0:
                        integrate = 0.0
                # canonical form x1' = x1 + e, x2' = x1; with the integration frozen the
                # derivative memory x1 - x2 still equals the last error
                pid_state[c, 0] += integrate * e
                pid_state[c, 1] = pid_state[c, 0] - e
                q[c] = u_c
                for p in range(track_ptr[c], track_ptr[c + 1]):
                    rhs[track_idx[p]] += track_val[p] * u_c
        # 1b. rain: the wet faces' convection to the wet bulb, implicit in the step
        if wet and m_wet > 0:
            twb = t_wb[k]
            for i in range(m_wet):
                rhs[wet_node[i]] += wet_h0a[i] * (twb - t_out)
            if dirichlet_first:  # the tracked zones' air at its reference (the step's system)
                for i in range(n):
                    rhs_d[i] = rhs[i]
                for c in range(nc):
                    rhs_d[air_node[ctrl_zone[c]]] = track_ref[s, c]
                lu_solve(*d_factors, rhs_d, work, wet_x)
            else:
                lu_solve(*factors, rhs, work, wet_x)
            for i in range(m_wet):
                acc = wet_c[i] * twb
                for j in range(m_wet):
                    acc += wet_m[i, j] * wet_x[wet_node[j]]
                wet_y[i] = acc
            for i in range(m_wet):
                rhs[wet_node[i]] += wet_d[i] * (twb - wet_y[i])
        # 2'. outdoor air of the implicit zones in the step it belongs to (Woodbury on the first
        #     solve's system): y = air temperatures without it, then (I + G D) y = y0 + G D T_out
        if m_imp > 0:
            any_d = n_vent > 0
            for i in range(m_imp):
                z = imp_zone[i]
                d_air = outdoor_air_excess(k, z, inf_ratio, inf_base, inf_column, inf_scheduled)
                d_now[i] = d_air + vent_d[z]
                if d_now[i] != 0.0:
                    any_d = True
            if any_d:
                if imp_d[m_imp] == 0.0:
                    _invert_into(imp_g, d_now, imp_inv, imp_d, False)
                if dirichlet_first:
                    for i in range(n):
                        rhs_d[i] = rhs[i]
                    for c in range(nc):
                        rhs_d[air_node[ctrl_zone[c]]] = track_ref[s, c]
                    lu_solve(*d_factors, rhs_d, work, x_new)
                else:
                    lu_solve(*factors, rhs, work, x_new)
                for i in range(m_imp):
                    acc = x_new[air_node[imp_zone[i]]]
                    for j in range(m_imp):
                        acc += imp_g[i, j] * d_now[j] * t_out
                    b_imp[i] = acc
                # the inverse of a nearby step's D refined (the air density and the wind change
                # D a little every step); inverted again when the refinement does not converge
                if not _refined_solve(imp_inv, imp_g, d_now, b_imp, y_imp, r_imp, False):
                    _invert_into(imp_g, d_now, imp_inv, imp_d, False)
                    _refined_solve(imp_inv, imp_g, d_now, b_imp, y_imp, r_imp, False)
                # an indoor-limited object that would cross its lower limit (minimum indoor
                # temperature, or outdoor + delta) within the step is open for the fraction of
                # its flow that ends the step at the limit, as EnergyPlus' shorter system steps
                # switch it inside a zone step (exact for one object: Sherman-Morrison on the
                # implicit response H = (I + G D)^-1 G)
                for j in range(n_vent):
                    z = vent_zone[j]
                    i = imp_of[z]
                    g_open = vent_g[k, j]
                    if i < 0 or g_open <= 0.0:
                        continue
                    lower = max(vent_tmin[k, j], t_out + vent_delta[k, j])
                    f0 = vent_open[k, j]
                    if f0 > 0.5:
                        if y_imp[i] >= lower:
                            continue
                    elif x[air_node[z]] > vent_tmax[k, j] or y_imp[i] <= lower:
                        continue
                    for r in range(m_imp):
                        g_col[r] = imp_g[r, i]
                    if not _refined_solve(imp_inv, imp_g, d_now, g_col, h_col, r_imp, False):
                        _invert_into(imp_g, d_now, imp_inv, imp_d, False)
                        _refined_solve(imp_inv, imp_g, d_now, g_col, h_col, r_imp, False)
                    fan_per_g = vent_fan[k, j] / g_open
                    denom = h_col[i] * (t_out - lower + fan_per_g)
                    if abs(denom) < 1e-300:
                        continue
                    delta = (lower - y_imp[i]) / denom
                    delta = min(max(delta, -g_open * f0), g_open * (1.0 - f0))
                    y_i = (y_imp[i] + h_col[i] * delta * (t_out + fan_per_g)) / (
                        1.0 + h_col[i] * delta
                    )
                    dq = delta * (t_out - y_i + fan_per_g)
                    for r in range(m_imp):
                        y_imp[r] += h_col[r] * dq
                    d_now[i] += delta
                    rhs[air_node[z]] += delta * fan_per_g
                    vent_open[k, j] = f0 + delta / g_open
                for i in range(m_imp):
                    rhs[air_node[imp_zone[i]]] += d_now[i] * (t_out - y_imp[i])
        # 3'. tracking: PID heat from the error at the start of the step, or the exact inverse
        done = False
        if track_mode == 2:
            # the PID heat is already in rhs (before the outdoor air, see 1'')
            lu_solve(*factors, rhs, work, x_new)
            done = True
        elif track_mode == 1 and not track_general:
            for i in range(n):
                rhs_d[i] = rhs[i]
            for c in range(nc):
                rhs_d[air_node[ctrl_zone[c]]] = track_ref[s, c]
            lu_solve(*d_factors, rhs_d, work, x_new)
            for c in range(nc):
                acc = -rhs[air_node[ctrl_zone[c]]]
                for p in range(a_ptr[c], a_ptr[c + 1]):
                    acc += a_val[p] * x_new[a_idx[p]]
                q[c] = acc
            done = True
        elif track_mode == 1:
            lu_solve(*factors, rhs, work, x_new)
            zone_mean_radiant(
                x_new, face_node, face_zone, face_area, zone_face_area, air_node, mrt_tmp
            )
            for c in range(nc):
                z = ctrl_zone[c]
                mrt = mrt_tmp[z]
                w = track_w_air[c]
                t_free[c] = track_ref[s, c] - (w * x_new[air_node[z]] + (1.0 - w) * mrt)
            for c in range(nc):
                acc = 0.0
                for d in range(nc):
                    acc += g_track_inv[c, d] * t_free[d]
                q[c] = acc
            if mt > 0:
                for i in range(mt):
                    z = gt_zone[i]
                    d_air = outdoor_air_excess(k, z, inf_ratio, inf_base, inf_column, inf_scheduled)
                    d_t[i] = d_air + vent_d[z]
                if gt_d[mt] == 0.0:
                    _invert_into(gt_m, d_t, gt_inv, gt_d, True)
                for i in range(mt):
                    acc = x_new[air_node[gt_zone[i]]]
                    for c in range(nc):
                        acc += gt_aq[i, c] * q[c]
                    r_t[i] = d_t[i] * (t_out - acc)
                if not _refined_solve(gt_inv, gt_m, d_t, r_t, h_t, res_t, True):
                    _invert_into(gt_m, d_t, gt_inv, gt_d, True)
                    _refined_solve(gt_inv, gt_m, d_t, r_t, h_t, res_t, True)
                for i in range(mt):
                    rhs[air_node[gt_zone[i]]] += h_t[i]
                for c in range(nc):
                    acc = 0.0
                    for i in range(mt):
                        acc += gt_k[c, i] * h_t[i]
                    q[c] -= acc
            for c in range(nc):
                for p in range(track_ptr[c], track_ptr[c + 1]):
                    rhs[track_idx[p]] += track_val[p] * q[c]
            lu_solve(*factors, rhs, work, x_new)
            done = True
        # 3. every controlled zone at a set point in the previous step: try the Dirichlet system
        #    (controlled air temperatures prescribed) -- one substitution; accept when the implied
        #    powers have the right signs, else fall back to the general superposition below
        if ideal_on and nc > 0 and use_dirichlet and not done:
            all_active = True
            for c in range(nc):
                if active[c] == 0:
                    all_active = False
                    break
            if all_active:
                for i in range(n):
                    rhs_d[i] = rhs[i]
                for c in range(nc):
                    an = air_node[ctrl_zone[c]]
                    rhs_d[an] = heat_sp_k[c] if active[c] == 1 else cool_sp_k[c]
                lu_solve(*d_factors, rhs_d, work, x_new)
                done = True
                for c in range(nc):
                    an = air_node[ctrl_zone[c]]
                    acc = -rhs[an]
                    for p in range(a_ptr[c], a_ptr[c + 1]):
                        acc += a_val[p] * x_new[a_idx[p]]
                    q[c] = acc
                    if (active[c] == 1 and acc < 0.0) or (active[c] == -1 and acc > 0.0):
                        done = False
                if not done:
                    cache_m[5] += 1
        if not done and track_mode == 0:
            # free response
            lu_solve(*factors, rhs, work, x_new)
            for c in range(nc):
                q[c] = 0.0
        # 4. ideal loads
        if ideal_on and nc > 0 and not done:
            for c in range(nc):
                t_free[c] = x_new[air_node[ctrl_zone[c]]]
            if operative:
                zone_mean_radiant(
                    x_new, face_node, face_zone, face_area, zone_face_area, air_node, mrt_tmp
                )
                for c in range(nc):
                    z = ctrl_zone[c]
                    w = track_w_air[c]
                    if w < 1.0 and zone_face_area[z] > 0:
                        t_free[c] = w * t_free[c] + (1.0 - w) * mrt_tmp[z]
            cache_m[6] += 1
            ideal_loads(
                t_free,
                heat_sp_k,
                cool_sp_k,
                g_ctrl,
                active,
                q,
                cache_member,
                cache_inv,
                cache_m,
            )
            any_q = False
            for c in range(nc):
                if q[c] != 0.0:
                    any_q = True
            if any_q:
                for c in range(nc):
                    rhs[air_node[ctrl_zone[c]]] += q[c]
                lu_solve(*factors, rhs, work, x_new)
        # 4'. a zone the ideal loads hold at a set point meets its scheduled outdoor air at that
        #     set point, not at its previous temperature: the load takes the difference (the
        #     temperatures do not change while the zone stays held)
        if ideal_on and track_mode == 0:
            for c in range(nc):
                if active[c] == 0 or (operative and track_w_air[c] < 1.0):
                    continue  # (an operative thermostat's air is not at the set point)
                z = ctrl_zone[c]
                if imp_of[z] >= 0 or gt_of[z] >= 0:
                    continue
                held_t = heat_sp_k[c] if active[c] == 1 else cool_sp_k[c]
                lag = inf_temp[z]
                d_air = outdoor_air_excess(k, z, inf_ratio, inf_base, inf_column, inf_scheduled)
                extra = (d_air + vent_d[z]) * (lag - held_t)
                if dt_rows > 0:
                    g_dt = inf_dt[k if dt_rows > 1 else 0, z]
                    d_held = t_out - held_t
                    d_lag = t_out - lag
                    extra += g_dt * (abs(d_held) * d_held - abs(d_lag) * d_lag)
                q[c] -= extra
        for i in range(n):
            x[i] = x_new[i]
        # 5. outputs
        for z in range(nz):
            out_air[s, z] = x[air_node[z]]
        zone_mean_radiant(x, face_node, face_zone, face_area, zone_face_area, air_node, out_mrt[s])
        if store_faces:
            for f in range(face_node.shape[0]):
                out_face[s, f] = x[face_node[f]]
        if track_mode != 0:
            diverged = False
            for c in range(nc):
                z = ctrl_zone[c]
                out_q[s, c] = q[c]
                w = track_w_air[c]
                track_fb[c] = w * out_air[s, z] + (1.0 - w) * out_mrt[s, z]
                if not abs(track_fb[c]) < 1.0e4:
                    diverged = True
                    track_fb[c] = np.nan
            if diverged:
                # an unstable loop: mark the rest of the chunk as NaN and stop (the caller
                # raises a clear error) instead of overflowing inside the network
                for r in range(s, n_steps):
                    for z in range(nz):
                        out_air[r, z] = np.nan
                        out_mrt[r, z] = np.nan
                    for c in range(nc):
                        out_q[r, c] = np.nan
                return
            continue
        for c in range(nc):
            z = ctrl_zone[c]
            if q[c] > 0:
                out_heat[s, z] = q[c]
                out_cool[s, z] = 0.0
            else:
                out_heat[s, z] = 0.0
                out_cool[s, z] = -q[c]
