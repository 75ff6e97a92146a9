"""The pieces of the compiled time loop (numba): the sparse LU substitutions and their factors,
interior convection (TARP, EnergyPlus' Simple), People's sensible heat beyond its reference, and
the ideal loads' active-set solution. :func:`thermocal.multizone._kernel.run_steps` strings them
into a step.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: Zone temperature at which the scheduled People gains hold their sensible heat [C]
#: (``thermocal.multizone.idf.loads.PEOPLE_SENSIBLE_REFERENCE_TEMPERATURE``; tested equal)
PEOPLE_T0 = 22.0


def prepare_factors(lower, upper, perm_r, perm_c):
    """The factors of ``Pr A Pc = L U`` (SuperLU, unit lower ``L``) as :func:`lu_solve` reads them.

    Each strictly triangular part is one flat list of entries in the order the substitution
    applies them (``L`` by ascending column, ``U`` by descending column, each column's entries
    in row order): row, column and value per entry, so that the substitution is a single loop
    over the entries, without a loop per column whose few entries (about two here: the wall
    chains) end at a branch the processor cannot predict. Then the inverse diagonal of ``U`` and
    the permutations.

    Returns
    -------
    tuple
        ``(l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c)``: int32 rows
        and columns, float64 values [-], ``1 / diag(U)``, the inverse row permutation and the
        column permutation (int64).
    """
    lower = lower.tocsc()
    upper = upper.tocsc()
    n = lower.shape[0]
    diag = upper.diagonal()
    strict_l = (lower - _sparse_diag(lower.diagonal())).tocsc()
    strict_u = (upper - _sparse_diag(diag)).tocsc()
    strict_l.eliminate_zeros()
    strict_u.eliminate_zeros()
    strict_l.sort_indices()
    strict_u.sort_indices()
    inverse_r = np.empty(n, dtype=np.int64)
    inverse_r[np.asarray(perm_r)] = np.arange(n)
    l_row, l_col, l_val = _entries(strict_l, np.arange(n))
    u_row, u_col, u_val = _entries(strict_u, np.arange(n - 1, -1, -1))
    return (
        l_row, l_col, l_val, u_row, u_col, u_val,
        1.0 / diag,
        inverse_r,
        np.asarray(perm_c, dtype=np.int64),
    )  # fmt: skip


def _entries(matrix, columns):
    """Rows, columns and values of a sorted CSC ``matrix``'s entries, column by column in the
    order ``columns``, each column's entries in row order."""
    counts = np.diff(matrix.indptr)[columns]
    starts = matrix.indptr[columns]
    # the positions of the entries: each column's start plus 0, 1, ..., count - 1
    offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    positions = np.repeat(starts, counts) + offsets
    return (
        matrix.indices[positions].astype(np.int32),
        np.repeat(columns, counts).astype(np.int32),
        matrix.data[positions].copy(),
    )


def _sparse_diag(values):
    import scipy.sparse as sp

    return sp.diags(values, format="csc")


@njit(cache=True, error_model="numpy", fastmath={"contract", "nsz", "nnan", "ninf"})
def lu_solve(l_row, l_col, l_val, u_row, u_col, u_val, inv_diag, inverse_r, perm_c, b, work, out):
    """Solve ``A x = b`` with the factors of :func:`prepare_factors`.

    Column-oriented substitutions, one entry at a time: an entry of column ``j`` is applied
    once every entry of the columns before ``j`` (after, for ``U``) has been, so the value it
    reads is final. ``U``'s column value is ``work[j] / U[j, j]``, recomputed per entry (the
    same product each time); the floating-point flags allow contraction to fused multiply-adds
    but not reassociation, so the result is that of the loop per column, bit for bit.
    """
    n = b.shape[0]
    for j in range(n):
        work[j] = b[inverse_r[j]]
    for p in range(l_val.shape[0]):
        work[l_row[p]] -= l_val[p] * work[l_col[p]]
    for p in range(u_val.shape[0]):
        j = u_col[p]
        work[u_row[p]] -= u_val[p] * (work[j] * inv_diag[j])
    for i in range(n):
        j = perm_c[i]
        out[i] = work[j] * inv_diag[j]


@njit(cache=True, error_model="numpy", fastmath=True)
def cube_root_update(x, guess):
    """Cube root of ``x >= 0`` by three Newton steps from ``guess`` (the previous step's root).

    Surface-air temperature differences change little from one step to the next, so the root of
    the previous step is an excellent start; this is much cheaper than ``cbrt`` in the hot loop.
    """
    x = max(x, 1e-6)
    y = max(guess, 1e-2)
    for _ in range(3):
        y = (2.0 * y + x / (y * y)) / 3.0
    return y


@njit(cache=True, error_model="numpy", fastmath=True)
def people_excess(t_air, a, b, c, limit):
    """People's sensible heat at ``t_air`` minus its value at ``PEOPLE_T0`` [W].

    ``a + b T + c T^2`` (sums over a zone's People of number x the per-person coefficients of
    EnergyPlus' autocalculated sensible fraction [W], [W/K], [W/K^2]), each value clipped to
    ``[0, limit]`` with ``limit`` the zone's total metabolic heat [W] (number x activity level),
    as EnergyPlus clips the sensible heat per person. The scheduled gains hold the value at
    ``PEOPLE_T0``; this is the lagged correction the time loop adds to the zone air.
    """
    at_t = a + b * t_air + c * t_air * t_air
    at_0 = a + b * PEOPLE_T0 + c * PEOPLE_T0 * PEOPLE_T0
    at_t = min(max(at_t, 0.0), limit)
    at_0 = min(max(at_0, 0.0), limit)
    return at_t - at_0


@njit(cache=True, error_model="numpy")
def tarp(delta_t, cos_up):
    """TARP natural convection (scalar version of network.tarp_natural_convection)."""
    return tarp_from_root(delta_t, np.cbrt(abs(delta_t)), cos_up)


@njit(cache=True, error_model="numpy", fastmath=True)
def tarp_excess(dt, root, cos_up, num_up, num_down, den_up, den_down, h_max, h0, area, excess):
    """TARP natural convection of every face beyond its matrix coefficient [W/K], in place.

    ``excess = (min(max(num root / den, 0.1), h_max) - h0) area`` with ``root = |dt|^(1/3)`` by
    :func:`cube_root_update`'s three Newton steps from ``root`` (updated) and ``num / den`` the
    coefficient for the direction of the heat flow (``up``: ``dt cos_up > 0``, unstable):
    :func:`tarp_from_root`'s arithmetic without its branches, so that the compiler can run
    several faces at once in the processor's vector units.

    Parameters
    ----------
    dt : ndarray (n,)
        Surface minus air temperature [K].
    root : ndarray (n,)
        Previous step's cube roots [K^(1/3)], updated.
    cos_up : ndarray (n,)
        Cosine of each face's tilt from facing up [-].
    num_up, num_down, den_up, den_down : ndarray (n,)
        Each face's coefficient ``num / den`` [W/(m2 K^(4/3))] for either direction of the
        flow (:func:`tarp_coefficients`).
    h_max : ndarray (n,)
        Largest coefficient [W/(m2 K)].
    h0 : ndarray (n,)
        The matrix's coefficient [W/(m2 K)].
    area : ndarray (n,)
        [m2].
    excess : ndarray (n,)
        Output [W/K].
    """
    for f in range(dt.shape[0]):
        d = dt[f]
        a = max(abs(d), 1e-6)
        y = max(root[f], 1e-2)
        y = (2.0 * y + a / (y * y)) / 3.0
        y = (2.0 * y + a / (y * y)) / 3.0
        y = (2.0 * y + a / (y * y)) / 3.0
        root[f] = y
        unstable = d * cos_up[f] > 0.0
        num = num_up[f] if unstable else num_down[f]
        den = den_up[f] if unstable else den_down[f]
        h = min(max(num * y / den, 0.1), h_max[f])
        excess[f] = (h - h0[f]) * area[f]


@njit(cache=True, error_model="numpy")
def tarp_coefficients(cos_up):
    """Numerators and denominators of TARP's coefficient per face for either direction of the
    heat flow (:func:`tarp_from_root`): ``(num_up, num_down, den_up, den_down)`` [-]."""
    n = cos_up.shape[0]
    num_up, num_down = np.empty(n), np.empty(n)
    den_up, den_down = np.empty(n), np.empty(n)
    for f in range(n):
        abs_cos = abs(cos_up[f])
        if abs_cos < 1e-3:
            num_up[f], num_down[f], den_up[f], den_down[f] = 1.31, 1.31, 1.0, 1.0
        else:
            num_up[f], num_down[f] = 9.482, 1.810
            den_up[f], den_down[f] = 7.238 - abs_cos, 1.382 + abs_cos
    return num_up, num_down, den_up, den_down


@njit(cache=True, error_model="numpy", fastmath=True)
def tarp_from_root(delta_t, root, cos_up):
    """TARP coefficient given ``root = |delta_t|^(1/3)``."""
    abs_cos = abs(cos_up)
    if abs_cos < 1e-3:
        h = 1.31 * root
    elif delta_t * cos_up > 0.0:
        h = 9.482 * root / (7.238 - abs_cos)
    else:
        h = 1.810 * root / (1.382 + abs_cos)
    return max(h, 0.1)


@njit(cache=True, error_model="numpy")
def iso15099_window_interior(t_surface, t_air, height, tilt, sin_tilt, ra_cv, pressure):
    """Room-side natural convection of a window, ISO 15099 §8.3.2.2, as EnergyPlus' TARP
    algorithm takes it for windows (ConvectionCoefficients.cc, CalcISO15099WindowIntConvCoeff)
    [W/(m2 K)].

    ``h = Nu k / H`` with ``Ra = rho^2 H^3 g c_p |dT| / (T_f mu k)`` at the film temperature
    ``T_f = T_air + (T_surface - T_air)/4`` (air conductivity and viscosity of ISO 15099 Annex B,
    dry-air density at ``pressure``); the tilt is measured from facing up and replaced by
    ``180 - tilt`` when the glass is warmer than the air. At least 0.1.

    Parameters
    ----------
    t_surface, t_air : float [C]
    height : float [m]
        Glazing height.
    tilt : float [deg]
        0 facing up, 90 vertical.
    sin_tilt : float [-]
    ra_cv : (float, float)
        The critical Rayleigh number of the 15-90 degree correlation at ``tilt`` (glass colder
        than the air) and at ``180 - tilt`` (warmer), computed once per window
        (:func:`thermocal.multizone.network.iso15099_critical_rayleigh`) [-].
    pressure : float [Pa]
    """
    # the time loop calls it for differences below 100 K (beyond, TARP); the film temperature
    # is held to the air properties' range, so a diverging air node keeps a finite coefficient
    dt = t_surface - t_air
    t_film = min(max(t_air + 273.15 + 0.25 * dt, 200.0), 500.0)
    k = 2.873e-3 + 7.76e-5 * t_film
    mu = 3.723e-6 + 4.94e-8 * t_film
    rho = pressure / (287.05 * t_film)
    cp = 1006.0
    ra = rho * rho * height * height * height * 9.81 * cp * abs(dt) / (t_film * mu * k)
    angle = tilt
    critical = ra_cv[0]
    if dt > 0.0:
        angle = 180.0 - tilt
        critical = ra_cv[1]
    if angle < 15.0:
        nu = 0.13 * np.cbrt(ra)
    elif angle <= 90.0:
        s = max(sin_tilt, 1e-6)
        if ra <= critical:
            nu = 0.56 * np.sqrt(np.sqrt(ra * s))
        else:
            nu = 0.13 * (np.cbrt(ra) - np.cbrt(critical)) + 0.56 * np.sqrt(np.sqrt(critical * s))
    elif angle <= 179.0:
        x = min(max(ra * sin_tilt, 1.0e5), 1.0e11)
        nu = 0.56 * np.sqrt(np.sqrt(x))
    else:
        if ra > 1.0e11:
            nu = 0.58 * 1.0e11**0.2
        else:
            nu = 0.58 * ra**0.2
    return max(nu * k / height, 0.1)


@njit(cache=True, error_model="numpy")
def simple_interior(delta_t, cos_up):
    """EnergyPlus' "Simple" interior coefficient (ASHRAE): 3.076 on vertical faces; on horizontal
    (tilted) faces 4.040 (3.870) when the heat flow is unstable (a face warmer than the air facing
    up, colder facing down), else 0.948 (2.281)."""
    abs_cos = abs(cos_up)
    product = delta_t * cos_up
    if abs_cos < 0.3827 or product == 0.0:
        return 3.076
    if abs_cos >= 0.9239:
        return 4.040 if product > 0.0 else 0.948
    return 3.870 if product > 0.0 else 2.281


@njit(cache=True, error_model="numpy")
def _sync_inverse(g, active, cache_member, cache_inv, cache_m):
    """Make ``cache_inv`` the inverse of ``g`` on the active set (embedded by zone index).

    The cached set is moved to the active one by rank-one down- and updates (bordering
    formulas, O(m^2) each; ``g`` need not be symmetric: mirrored outside faces make the network
    slightly non-reciprocal); a fresh inversion when many zones change, when the cache is
    invalid (``cache_m[0] < 0``) or after 512 updates (round-off control).
    """
    nc = active.shape[0]
    n_diff = 0
    for c in range(nc):
        if cache_member[c] != (active[c] != 0):
            n_diff += 1
    if n_diff == 0 and cache_m[0] >= 0:
        return
    m_new = 0
    for c in range(nc):
        if active[c] != 0:
            m_new += 1
    if cache_m[0] < 0 or cache_m[1] + n_diff > 512 or n_diff > max(8, m_new // 3):
        idx = np.empty(m_new, dtype=np.int64)
        j = 0
        for c in range(nc):
            cache_member[c] = active[c] != 0
            if active[c] != 0:
                idx[j] = c
                j += 1
        if m_new > 0:
            block = np.empty((m_new, m_new))
            for a in range(m_new):
                for b in range(m_new):
                    block[a, b] = g[idx[a], idx[b]]
            inverse = np.linalg.inv(block)
            for a in range(m_new):
                for b in range(m_new):
                    cache_inv[idx[a], idx[b]] = inverse[a, b]
        cache_m[0] = m_new
        cache_m[1] = 0
        cache_m[2] += 1
        return
    # removals
    for r in range(nc):
        if cache_member[r] and active[r] == 0:
            pivot = cache_inv[r, r]
            for c in range(nc):
                if cache_member[c] and c != r:
                    f = cache_inv[c, r] / pivot
                    for d in range(nc):
                        if cache_member[d] and d != r:
                            cache_inv[c, d] -= f * cache_inv[r, d]
            cache_member[r] = False
            cache_m[1] += 1
            cache_m[3] += 1
    # additions: u = inv g[:, r] (column), w = g[r, :] inv (row)
    u = np.zeros(nc)
    w = np.zeros(nc)
    for r in range(nc):
        if active[r] != 0 and not cache_member[r]:
            schur = g[r, r]
            for c in range(nc):
                if cache_member[c]:
                    acc = 0.0
                    acc_w = 0.0
                    for d in range(nc):
                        if cache_member[d]:
                            acc += cache_inv[c, d] * g[d, r]
                            acc_w += g[r, d] * cache_inv[d, c]
                    u[c] = acc
                    w[c] = acc_w
                    schur -= g[r, c] * acc
            for c in range(nc):
                if cache_member[c]:
                    for d in range(nc):
                        if cache_member[d]:
                            cache_inv[c, d] += u[c] * w[d] / schur
                    cache_inv[c, r] = -u[c] / schur
                    cache_inv[r, c] = -w[c] / schur
            cache_inv[r, r] = 1.0 / schur
            cache_member[r] = True
            cache_m[1] += 1
            cache_m[3] += 1
    cache_m[0] = m_new


@njit(cache=True, error_model="numpy", fastmath=True, inline="always")
def zone_mean_radiant(x, face_node, face_zone, face_area, zone_face_area, air_node, out):
    """Each zone's area-weighted interior surface temperature of the state ``x`` [C] into
    ``out``; the air temperature for a zone without faces (the time loop's outputs, its
    operative thermostats and its operative tracking)."""
    for z in range(out.shape[0]):
        out[z] = 0.0
    for f in range(face_node.shape[0]):
        out[face_zone[f]] += face_area[f] * x[face_node[f]]
    for z in range(out.shape[0]):
        if zone_face_area[z] > 0:
            out[z] /= zone_face_area[z]
        else:
            out[z] = x[air_node[z]]


@njit(cache=True, error_model="numpy")
def ideal_loads(t_free, heat_sp, cool_sp, g, active, q, cache_member, cache_inv, cache_m):
    """Heating (+) / cooling (-) powers that bring every controlled zone inside its set points.

    Active-set method on ``T = t_free + G q``: zones at a set point ("active") get the power that
    holds them exactly there (the inverse of the active block of ``G``), the others none. The
    iteration starts from the previous step's active set; the inverse is cached and updated by
    rank-one steps when zones join or leave, so a step costs O(m^2) instead of O(m^3).
    ``q`` is written in place; ``active`` updated.
    """
    nc = t_free.shape[0]
    idx = np.empty(nc, dtype=np.int64)
    rv = np.empty(nc)
    for _ in range(4 * nc + 4):
        cache_m[4] += 1
        _sync_inverse(g, active, cache_member, cache_inv, cache_m)
        m = 0
        for c in range(nc):
            q[c] = 0.0
            if active[c] != 0:
                idx[m] = c
                m += 1
        for b in range(m):
            cb = idx[b]
            target = heat_sp[cb] if active[cb] == 1 else cool_sp[cb]
            rv[b] = target - t_free[cb]
        for a in range(m):
            row = cache_inv[idx[a]]
            acc = 0.0
            for b in range(m):
                acc += row[idx[b]] * rv[b]
            q[idx[a]] = acc
        changed = False
        # release zones whose power has the wrong sign
        for a in range(m):
            c = idx[a]
            if (active[c] == 1 and q[c] < 0.0) or (active[c] == -1 and q[c] > 0.0):
                active[c] = 0
                changed = True
        if changed:
            continue
        # add free zones outside their band
        for c in range(nc):
            if active[c] == 0:
                t = t_free[c]
                for a in range(m):
                    t += g[c, idx[a]] * q[idx[a]]
                if t < heat_sp[c] - 1e-9:
                    active[c] = 1
                    changed = True
                elif t > cool_sp[c] + 1e-9:
                    active[c] = -1
                    changed = True
        if not changed:
            return


@njit(cache=True, error_model="numpy", fastmath=True)
def _refined_solve(inv, g, d, b, y, r, d_left):
    """Solve ``(I + G diag(d)) y = b`` (``d_left``: ``(I + diag(d) G) y = b``) with ``inv`` the
    inverse of the system at a nearby ``d`` (iterative refinement, at most 4 corrections).

    Returns True when the residual is below 1e-10 of ``b``; False (``y`` not usable): invert
    the system at this ``d``.
    """
    m = b.shape[0]
    scale = 0.0
    for i in range(m):
        scale = max(scale, abs(b[i]))
    tol = 1e-10 * (1.0 + scale)
    for i in range(m):
        acc = 0.0
        for j in range(m):
            acc += inv[i, j] * b[j]
        y[i] = acc
    last = np.inf
    for _ in range(5):
        worst = 0.0
        for i in range(m):
            acc = 0.0
            if d_left:
                for j in range(m):
                    acc += g[i, j] * y[j]
                acc *= d[i]
            else:
                for j in range(m):
                    acc += g[i, j] * d[j] * y[j]
            r[i] = b[i] - y[i] - acc
            worst = max(worst, abs(r[i]))
        if worst <= tol:
            return True
        if worst >= last:
            return False
        last = worst
        for i in range(m):
            acc = 0.0
            for j in range(m):
                acc += inv[i, j] * r[j]
            y[i] += acc
    return False


@njit(cache=True, error_model="numpy", fastmath=True)
def _invert_into(g, d, out, d_store, d_left):
    """``out = inv(I + G diag(d))`` (``d_left``: ``inv(I + diag(d) G)``); ``d_store`` keeps ``d``
    and its last entry marks the inverse valid."""
    m = d.shape[0]
    mat = np.empty((m, m))
    for i in range(m):
        for j in range(m):
            mat[i, j] = (d[i] if d_left else d[j]) * g[i, j]
        mat[i, i] += 1.0
    inv = np.linalg.inv(mat)
    for i in range(m):
        d_store[i] = d[i]
        for j in range(m):
            out[i, j] = inv[i, j]
    d_store[m] = 1.0


@njit(cache=True, error_model="numpy", fastmath=True)
def outdoor_air_excess(k, z, ratio, base, column, scheduled):
    """Outdoor-air conductance of zone ``z`` at step ``k`` beyond its matrix value [W/K].

    ``ratio[k] base[z]`` (the air density's variation of a constant rate) or, for a zone with
    its own schedule (``column[z] >= 0``), ``scheduled[k, column[z]]``
    (:class:`thermocal.multizone._simtools.OutdoorAirExcess`).
    """
    c = column[z]
    if c < 0:
        return ratio[k] * base[z]
    return scheduled[k, c]
