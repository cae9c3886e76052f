"""Compiled node loops (numba) for the contact search of one wheel: eq. (2) pairing and the three
contact-point methods. Same algorithm as the vectorized reference in :mod:`lutmpi.contact.methods`
(a test checks that both agree); this one is what the solver calls."""

from __future__ import annotations

import numpy as np
from numba import njit

MD, MND, LC = 0, 1, 2
METHOD_IDS = {"max_distance": MD, "max_normal_distance": MND, "load_centre": LC}
MAX_VOL = 16


@njit(cache=True)
def _nearest_rail(u, z, ru, rz, K):
    n = ru.size
    i0 = np.searchsorted(ru, u)
    best, bi = 1e300, 0
    for i in range(max(i0 - K, 0), min(i0 + K + 1, n)):
        d2 = (ru[i] - u) ** 2 + (rz[i] - z) ** 2
        if d2 < best:
            best, bi = d2, i
    return bi


@njit(cache=True)
def _nearest_slice(uw, rho, ws, wr, d, K):
    n = ws.size
    s = uw - d
    i0 = np.searchsorted(ws, s)
    best, bi = 1e300, 0
    for i in range(max(i0 - K, 0), min(i0 + K + 1, n)):
        d2 = (ws[i] - s) ** 2 + (wr[i] - rho) ** 2
        if d2 < best:
            best, bi = d2, i
    return bi


@njit(cache=True)
def _interp(x, xs, ys):
    n = xs.size
    i = np.searchsorted(xs, x) - 1
    if i < 0:
        i = 0
    if i > n - 2:
        i = n - 2
    t = (x - xs[i]) / (xs[i + 1] - xs[i])
    return ys[i] + t * (ys[i + 1] - ys[i])


@njit(cache=True)
def _wheel_normal(p, side, centre, R, d, ts, tdr, s_lo, s_hi):
    """Outward wheel normal (track) at the wheel-surface location of ``p``, and its s."""
    q0 = p[0] - centre[0]
    q1 = p[1] - centre[1]
    q2 = p[2] - centre[2]
    c0 = R[0, 0] * q0 + R[1, 0] * q1 + R[2, 0] * q2
    c1 = R[0, 1] * q0 + R[1, 1] * q1 + R[2, 1] * q2
    c2 = R[0, 2] * q0 + R[1, 2] * q1 + R[2, 2] * q2
    s = side * c1 - d
    s = min(max(s, s_lo), s_hi)
    phi = np.arctan2(c0, -c2)
    dr = _interp(s, ts, tdr)
    inv = 1.0 / np.sqrt(1.0 + dr * dr)
    nb0, nb1, nb2 = np.sin(phi) * inv, -side * dr * inv, -np.cos(phi) * inv
    out = np.empty(3)
    for a in range(3):
        out[a] = R[a, 0] * nb0 + R[a, 1] * nb1 + R[a, 2] * nb2
    return out, s


@njit(cache=True)
def contacts_side(
    method,
    side,
    body_pts,
    body_nrm,
    kidx,
    centre,
    R,
    ru,
    rz,
    rnu,
    rnz,
    h_x,
    rail_pts,
    rail_nrm,
    ws,
    wr,
    wdr,
    d,
    dphi,
    ts,
    tdr,
    s_lo,
    s_hi,
    K,
):
    """Contacts of one wheel at pose (centre, R).

    Returns (n, wheel_point (MAX_VOL,3), rail_point (MAX_VOL,3), n_wheel (MAX_VOL,3),
    C (MAX_VOL,), s (MAX_VOL,), n_w (MAX_VOL,), n_r (MAX_VOL,)) with volumes unsorted.
    """
    nw = body_pts.shape[0]
    P = np.empty((nw, 3))
    N = np.empty((nw, 3))
    Pj = np.empty((nw, 3))
    inside = np.zeros(nw, dtype=np.bool_)
    for i in range(nw):
        for a in range(3):
            P[i, a] = (
                centre[a]
                + R[a, 0] * body_pts[i, 0]
                + R[a, 1] * body_pts[i, 1]
                + R[a, 2] * body_pts[i, 2]
            )
            N[i, a] = R[a, 0] * body_nrm[i, 0] + R[a, 1] * body_nrm[i, 1] + R[a, 2] * body_nrm[i, 2]
        u = side * P[i, 1]
        lj = _nearest_rail(u, P[i, 2], ru, rz, K)
        Pj[i, 0] = np.round(P[i, 0] / h_x) * h_x
        Pj[i, 1] = side * ru[lj]
        Pj[i, 2] = rz[lj]
        nj1, nj2 = side * rnu[lj], rnz[lj]
        v0, v1, v2 = Pj[i, 0] - P[i, 0], Pj[i, 1] - P[i, 1], Pj[i, 2] - P[i, 2]
        vni = v0 * N[i, 0] + v1 * N[i, 1] + v2 * N[i, 2]
        inside[i] = (v1 * nj1 + v2 * nj2 >= 0.0) and (vni <= 0.0)
    # volumes: wheel nodes are sorted by slice; split where a whole slice is outside V_int
    vol = np.full(nw, -1)
    nvol = 0
    last_k = -(10**9)
    for i in range(nw):
        if inside[i]:
            if kidx[i] > last_k + 1 or nvol == 0:
                if nvol < MAX_VOL:
                    nvol += 1
            vol[i] = nvol - 1
            last_k = kidx[i]
    WP = np.zeros((MAX_VOL, 3))
    RP = np.zeros((MAX_VOL, 3))
    NW = np.zeros((MAX_VOL, 3))
    C = np.full(MAX_VOL, -1e300)
    S = np.zeros(MAX_VOL)
    NWn = np.zeros(MAX_VOL, dtype=np.int64)
    NRn = np.zeros(MAX_VOL, dtype=np.int64)
    if nvol == 0:
        return 0, WP, RP, NW, C, S, NWn, NRn
    kmin = np.full(MAX_VOL, 10**9)
    kmax = np.full(MAX_VOL, -(10**9))
    for i in range(nw):
        g = vol[i]
        if g < 0:
            continue
        NWn[g] += 1
        kmin[g] = min(kmin[g], kidx[i])
        kmax[g] = max(kmax[g], kidx[i])
        if method == MD or method == MND:
            c = (
                (P[i, 0] - Pj[i, 0]) * N[i, 0]
                + (P[i, 1] - Pj[i, 1]) * N[i, 1]
                + (P[i, 2] - Pj[i, 2]) * N[i, 2]
            )
            rp = Pj[i].copy()
            if method == MND:
                c, rp = _normal_to_rail(P[i], N[i], side, ru, rz, c)
            if c > C[g]:
                C[g] = c
                WP[g] = P[i]
                RP[g] = rp
                NW[g] = N[i]
        else:
            for a in range(3):
                WP[g, a] += P[i, a]
    if method == LC:
        _load_centres(
            nvol,
            WP,
            RP,
            NW,
            C,
            S,
            NWn,
            NRn,
            kmin,
            kmax,
            vol,
            Pj,
            side,
            centre,
            R,
            rail_pts,
            rail_nrm,
            ws,
            wr,
            wdr,
            d,
            dphi,
            ts,
            tdr,
            s_lo,
            s_hi,
            K,
        )
    else:
        for g in range(nvol):
            _, S[g] = _wheel_normal(WP[g], side, centre, R, d, ts, tdr, s_lo, s_hi)
    return nvol, WP, RP, NW, C, S, NWn, NRn


@njit(cache=True)
def _normal_to_rail(p, n, side, ru, rz, t0):
    """Distance along -n from p to the piecewise-linear rail profile, and the rail point."""
    u0, z0 = side * p[1], p[2]
    nu, nz = side * n[1], n[2]
    t = t0
    m = ru.size
    for _ in range(4):
        u = u0 - t * nu
        i = np.searchsorted(ru, u) - 1
        i = min(max(i, 0), m - 2)
        sl = (rz[i + 1] - rz[i]) / (ru[i + 1] - ru[i])
        zr = rz[i] + sl * (u - ru[i])
        f = (z0 - t * nz) - zr
        df = -nz + sl * nu
        if abs(df) > 1e-12:
            t = t - f / df
    rp = np.empty(3)
    for a in range(3):
        rp[a] = p[a] - t * n[a]
    return t, rp


@njit(cache=True)
def _load_centres(
    nvol,
    WP,
    RP,
    NW,
    C,
    S,
    NWn,
    NRn,
    kmin,
    kmax,
    vol,
    Pj,
    side,
    centre,
    R,
    rail_pts,
    rail_nrm,
    ws,
    wr,
    wdr,
    d,
    dphi,
    ts,
    tdr,
    s_lo,
    s_hi,
    K,
):
    nr = rail_pts.shape[0]
    for j in range(nr):
        q0 = rail_pts[j, 0] - centre[0]
        q1 = rail_pts[j, 1] - centre[1]
        q2 = rail_pts[j, 2] - centre[2]
        c0 = R[0, 0] * q0 + R[1, 0] * q1 + R[2, 0] * q2
        c1 = R[0, 1] * q0 + R[1, 1] * q1 + R[2, 1] * q2
        c2 = R[0, 2] * q0 + R[1, 2] * q1 + R[2, 2] * q2
        rho = np.sqrt(c0 * c0 + c2 * c2)
        k = _nearest_slice(side * c1, rho, ws, wr, d, K)
        g = -1
        for h in range(nvol):
            if kmin[h] - 1 <= k <= kmax[h] + 1:
                g = h
                break
        if g < 0:
            continue
        phi = np.round(np.arctan2(c0, -c2) / dphi) * dphi
        r, dr = wr[k], wdr[k]
        b0, b1, b2 = r * np.sin(phi), side * (d + ws[k]), -r * np.cos(phi)
        inv = 1.0 / np.sqrt(1.0 + dr * dr)
        n0, n1, n2 = np.sin(phi) * inv, -side * dr * inv, -np.cos(phi) * inv
        v = np.empty(3)
        vn = 0.0
        vm = 0.0
        for a in range(3):
            pa = centre[a] + R[a, 0] * b0 + R[a, 1] * b1 + R[a, 2] * b2
            na = R[a, 0] * n0 + R[a, 1] * n1 + R[a, 2] * n2
            v[a] = rail_pts[j, a] - pa
            vn += v[a] * rail_nrm[j, a]
            vm += v[a] * na
        if vn >= 0.0 and vm <= 0.0:
            NRn[g] += 1
            for a in range(3):
                RP[g, a] += rail_pts[j, a]
    nw = vol.size
    for g in range(nvol):
        for a in range(3):
            WP[g, a] /= NWn[g]
        if NRn[g] > 0:
            for a in range(3):
                RP[g, a] /= NRn[g]
        else:  # no rail node inside yet: the wheel nodes' nearest rail nodes
            cnt = 0
            for i in range(nw):
                if vol[i] == g:
                    cnt += 1
                    for a in range(3):
                        RP[g, a] += Pj[i, a]
            for a in range(3):
                RP[g, a] /= cnt
        nwv, s = _wheel_normal(WP[g], side, centre, R, d, ts, tdr, s_lo, s_hi)
        NW[g] = nwv
        S[g] = s
        C[g] = (
            (WP[g, 0] - RP[g, 0]) * nwv[0]
            + (WP[g, 1] - RP[g, 1]) * nwv[1]
            + (WP[g, 2] - RP[g, 2]) * nwv[2]
        )


@njit(cache=True)
def _parabola(g, lo, hi, i):
    """Value of the parabola through g[i-1], g[i], g[i+1] at its vertex (within ±0.5 sample),
    restricted to the run [lo, hi) of one side; g[i] when the neighbours are missing."""
    if i <= lo or i >= hi - 1:
        return g[i]
    gm, g0, gp = g[i - 1], g[i], g[i + 1]
    if not (np.isfinite(gm) and np.isfinite(gp)):
        return g0
    den = gm - 2.0 * g0 + gp
    if den <= 0.0:
        return g0
    t = 0.5 * (gm - gp) / den
    t = min(max(t, -0.5), 0.5)
    return g0 - 0.25 * (gm - gp) * t


@njit(cache=True)
def locus_heights(idx, n, side2, s2, r2, dr2, d, R, y, u0, du, tabz, u_min, u_max, gap):
    """Vertical gaps of the locus points ``idx`` (indices into both sides' concatenated samples;
    the left side is ``idx < n``) at the pose (y, R) with G at height 0, written into ``gap``,
    and the touching heights (left, right) from each side's minimum (parabolic refinement)."""
    a, b, c = R[0, 0], R[0, 1], R[0, 2]
    amp = np.sqrt(a * a + c * c)
    beta = np.arctan2(c, a)
    nt = tabz.size
    best_l, best_r = np.inf, np.inf
    il, ir = -1, -1
    n_left = 0
    for q in range(idx.size):
        k = idx[q]
        side = side2[k]
        x = b * side * dr2[k] / amp
        x = min(max(x, -1.0), 1.0)
        phi = beta + np.arcsin(x)
        r = r2[k]
        bx, by, bz = r * np.sin(phi), side * (d + s2[k]), -r * np.cos(phi)
        py = R[1, 0] * bx + R[1, 1] * by + R[1, 2] * bz + y
        pz = R[2, 0] * bx + R[2, 1] * by + R[2, 2] * bz
        u = side * py
        g = np.inf
        if u >= u_min and u <= u_max:
            f = (u - u0) / du
            j = min(max(int(f), 0), nt - 2)
            t = f - j
            g = pz - (tabz[j] + t * (tabz[j + 1] - tabz[j]))
        gap[q] = g
        if k < n:
            n_left += 1
            if g < best_l:
                best_l, il = g, q
        elif g < best_r:
            best_r, ir = g, q
    if il < 0 or ir < 0:
        return -np.inf, -np.inf
    hl = -_parabola(gap, 0, n_left, il)
    hr = -_parabola(gap, n_left, idx.size, ir)
    return hl, hr


@njit(cache=True)
def window_wheel_nodes(side, ks, mc, mh, s, r, dr, d, dphi, centre, R, u0, du, tabz, u_min,
                       u_max, limit, filt):
    """Wheel nodes of a window: slices ``ks`` with angle indices ``mc ± mh``; with ``filt``,
    only the nodes whose vertical gap to the rail is at most ``limit``. Returns (k, m, body
    points, body normals, track points)."""
    total = 0
    for q in range(ks.size):
        total += 2 * mh[q] + 1
    K = np.empty(total, dtype=np.int64)
    M = np.empty(total, dtype=np.int64)
    BP = np.empty((total, 3))
    BN = np.empty((total, 3))
    TP = np.empty((total, 3))
    nt = tabz.size
    cnt = 0
    for q in range(ks.size):
        kk = ks[q]
        rk, drk = r[kk], dr[kk]
        inv = 1.0 / np.sqrt(1.0 + drk * drk)
        by = side * (d + s[kk])
        for mm in range(mc[q] - mh[q], mc[q] + mh[q] + 1):
            phi = mm * dphi
            sp, cp = np.sin(phi), np.cos(phi)
            bx, bz = rk * sp, -rk * cp
            tx = centre[0] + R[0, 0] * bx + R[0, 1] * by + R[0, 2] * bz
            ty = centre[1] + R[1, 0] * bx + R[1, 1] * by + R[1, 2] * bz
            tz = centre[2] + R[2, 0] * bx + R[2, 1] * by + R[2, 2] * bz
            u = side * ty
            if u < u_min or u > u_max:
                continue
            if filt:
                f = (u - u0) / du
                j = min(max(int(f), 0), nt - 2)
                t = f - j
                if tz - (tabz[j] + t * (tabz[j + 1] - tabz[j])) > limit:
                    continue
            K[cnt], M[cnt] = kk, mm
            BP[cnt, 0], BP[cnt, 1], BP[cnt, 2] = bx, by, bz
            BN[cnt, 0], BN[cnt, 1], BN[cnt, 2] = sp * inv, -side * drk * inv, -cp * inv
            TP[cnt, 0], TP[cnt, 1], TP[cnt, 2] = tx, ty, tz
            cnt += 1
    return K[:cnt], M[:cnt], BP[:cnt], BN[:cnt], TP[:cnt]


@njit(cache=True)
def window_rail_nodes(side, k, m, tp, ru, rz, rnu, rnz, h_x, ws, wr, d, dphi, centre, R, KN,
                      filt):
    """Rail nodes in the box spanned by the window's wheel nodes (two nodes of margin); with
    ``filt``, only those whose nearest wheel node is (next to) a window node. Returns (track
    points, track normals)."""
    n = k.size
    umin, umax, xmin, xmax = np.inf, -np.inf, np.inf, -np.inf
    for i in range(n):
        u = side * tp[i, 1]
        umin, umax = min(umin, u), max(umax, u)
        xmin, xmax = min(xmin, tp[i, 0]), max(xmax, tp[i, 0])
    l_lo = max(np.searchsorted(ru, umin) - 2, 0)
    l_hi = min(np.searchsorted(ru, umax) + 2, ru.size - 1)
    j_lo = int(np.floor(xmin / h_x)) - 2
    j_hi = int(np.ceil(xmax / h_x)) + 2
    k0, m0 = k.min() - 1, m.min() - 1
    gk, gm = k.max() - k0 + 2, m.max() - m0 + 2
    grid = np.zeros((gk, gm), dtype=np.bool_)
    for i in range(n):
        for a in range(-1, 2):
            for b in range(-1, 2):
                grid[k[i] - k0 + a, m[i] - m0 + b] = True
    total = (l_hi - l_lo + 1) * (j_hi - j_lo + 1)
    P = np.empty((total, 3))
    N = np.zeros((total, 3))
    cnt = 0
    for ll in range(l_lo, l_hi + 1):
        for jj in range(j_lo, j_hi + 1):
            px, py, pz = jj * h_x, side * ru[ll], rz[ll]
            if filt:
                q0, q1, q2 = px - centre[0], py - centre[1], pz - centre[2]
                c0 = R[0, 0] * q0 + R[1, 0] * q1 + R[2, 0] * q2
                c1 = R[0, 1] * q0 + R[1, 1] * q1 + R[2, 1] * q2
                c2 = R[0, 2] * q0 + R[1, 2] * q1 + R[2, 2] * q2
                kk = _nearest_slice(side * c1, np.sqrt(c0 * c0 + c2 * c2), ws, wr, d, KN)
                mm = int(np.round(np.arctan2(c0, -c2) / dphi))
                ik, im = kk - k0, mm - m0
                if ik < 0 or ik >= gk or im < 0 or im >= gm or not grid[ik, im]:
                    continue
            P[cnt, 0], P[cnt, 1], P[cnt, 2] = px, py, pz
            N[cnt, 1], N[cnt, 2] = side * rnu[ll], rnz[ll]
            cnt += 1
    return P[:cnt], N[:cnt]
