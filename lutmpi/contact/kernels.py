"""Compiled (numba) kernels: the typed aggregates they take, the shared stages of the contact
search of §4.2 (eq. 2 pairing, §4.6 split, the wheel normal off the nodes), the window and the
locus heights. The method-specific stage of each contact method lives in its own module of
:mod:`lutmpi.contact.methods` and calls these.

Aggregates (named tuples, built once per mesh or window; numba types them as records):

* :class:`WheelArrays` -- the wheel grid: slices ``s, r, dr`` (m, m, 1), ``d`` (m), ``dphi`` (rad),
  the 10 µm slope table ``tab_s, tab_dr`` and the profile's ``s_lo, s_hi`` (m);
* :class:`RailArrays` -- the rail grid: profile nodes ``u, z`` (m), unit normals ``nu, nz``,
  longitudinal step ``h_x`` (m), and the placed rail's height table (first ``tab_u0``, step
  ``tab_du``, heights ``tab_z``; m) over ``[u_min, u_max]`` (m);
* :class:`WindowArrays` -- one wheel's window: ``side`` (+1 left, -1 right), slice index ``k`` of
  each wheel node, wheelset-frame ``body_pts, body_nrm`` (n, 3), track-frame ``rail_pts,
  rail_nrm`` (m, 3);
* :class:`Pose` -- ``centre`` (3,) m and rotation ``R`` (3, 3) of the wheelset;
* :class:`Contacts` -- what a method's stage fills: ``n`` volumes, and per volume (first
  ``n`` rows of :data:`MAX_VOL`) wheel point, rail point, wheel outward normal, indentation
  ``C`` (m), profile coordinate ``s`` (m), node counts; all of them views of one array ``buf``
  (:data:`COLUMNS`), so that a stage returns ``(n, buf)`` (:func:`packed`) and crossing back to
  Python boxes one array instead of seven.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

MAX_VOL = 16
#: nodes searched either side of the sorted position for the nearest node
K_NEAR = 3


class WheelArrays(NamedTuple):
    s: np.ndarray
    r: np.ndarray
    dr: np.ndarray
    d: float
    dphi: float
    tab_s: np.ndarray
    tab_dr: np.ndarray
    s_lo: float
    s_hi: float
    sin_t: np.ndarray   # :func:`angle_table`: sin and cos of the grid's angles m dphi
    cos_t: np.ndarray
    tan_b: np.ndarray   # :func:`angle_bounds`: tangents of the angles half-way between them


class RailArrays(NamedTuple):
    u: np.ndarray
    z: np.ndarray
    nu: np.ndarray
    nz: np.ndarray
    h_x: float
    tab_u0: float
    tab_du: float
    tab_z: np.ndarray
    u_min: float
    u_max: float


class WindowArrays(NamedTuple):
    side: float
    k: np.ndarray
    body_pts: np.ndarray
    body_nrm: np.ndarray
    rail_pts: np.ndarray
    rail_nrm: np.ndarray


class Pose(NamedTuple):
    centre: np.ndarray
    R: np.ndarray


#: the columns of a :class:`Contacts` buffer
COLUMNS = {"wheel_point": slice(0, 3), "rail_point": slice(3, 6), "n_wheel": slice(6, 9),
           "C": 9, "s": 10, "n_wheel_nodes": 11, "n_rail_nodes": 12}


class Contacts(NamedTuple):
    n: int
    buf: np.ndarray
    wheel_point: np.ndarray
    rail_point: np.ndarray
    n_wheel: np.ndarray
    C: np.ndarray
    s: np.ndarray
    n_wheel_nodes: np.ndarray
    n_rail_nodes: np.ndarray


class WheelSearch(NamedTuple):
    P: np.ndarray  # (n, 3) wheel nodes, track frame
    N: np.ndarray  # (n, 3) their outward normals
    Pj: np.ndarray  # (n, 3) nearest rail node of each
    vol: np.ndarray  # (n,) volume of each node in V_int, -1 outside
    nvol: int
    n_nodes: np.ndarray  # (MAX_VOL,) wheel nodes per volume
    kmin: np.ndarray  # (MAX_VOL,) slice span of each volume
    kmax: np.ndarray


@njit(cache=True)
def nearest_from(x, y, xs, ys, K, i0):
    """The nearest of the points ``(xs, ys)`` (``xs`` sorted) to ``(x, y)`` among the ``K``
    either side of ``x``'s sorted position (``searchsorted``, left), and that position: a wheel
    node's nearest rail node (``x = u``, ``y = z``), a rail node's nearest wheel slice
    (``x = s``, ``y`` = radius). The position is found by walking from ``i0``, the previous
    query's: consecutive window nodes lie a node or two apart, so this takes a step or two where
    the bisection takes ten unpredictable branches (~30 % of the load-centre search). It ends
    on ``searchsorted``'s answer, so the result is the same (``tests/unit/test_contact_mesh.py``
    checks it against the bisection).

    Returns
    -------
    (int, int)
        Index of the nearest point, sorted position of ``x`` (the next query's ``i0``).
    """
    n = xs.size
    while i0 > 0 and xs[i0 - 1] >= x:
        i0 -= 1
    while i0 < n and xs[i0] < x:
        i0 += 1
    best, bi = 1e300, 0
    for i in range(max(i0 - K, 0), min(i0 + K + 1, n)):
        d2 = (xs[i] - x) ** 2 + (ys[i] - y) ** 2
        if d2 < best:
            best, bi = d2, i
    return bi, i0


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
def wheel_normal(p, side, pose, wheel):
    """Outward wheel normal (track frame) at the wheel-surface location of ``p``, and its
    profile coordinate ``s`` (slope from the 10 µm table)."""
    centre, R = pose.centre, pose.R
    q0 = p[0] - centre[0]
    q1 = p[1] - centre[1]
    q2 = p[2] - centre[2]
    c0 = R[0, 0] * q0 + R[1, 0] * q1 + R[2, 0] * q2
    c1 = R[0, 1] * q0 + R[1, 1] * q1 + R[2, 1] * q2
    c2 = R[0, 2] * q0 + R[1, 2] * q1 + R[2, 2] * q2
    s = side * c1 - wheel.d
    s = min(max(s, wheel.s_lo), wheel.s_hi)
    phi = np.arctan2(c0, -c2)
    dr = _interp(s, wheel.tab_s, wheel.tab_dr)
    inv = 1.0 / np.sqrt(1.0 + dr * dr)
    nb0, nb1, nb2 = np.sin(phi) * inv, -side * dr * inv, -np.cos(phi) * inv
    out = np.empty(3)
    for a in range(3):
        out[a] = R[a, 0] * nb0 + R[a, 1] * nb1 + R[a, 2] * nb2
    return out, s


@njit(cache=True)
def search_wheel_nodes(win, rail, pose):
    """Eq. (2) for every wheel node of the window, and the volumes of §4.6.

    A wheel node ``P_i`` (outward normal ``N_i``), paired with its nearest rail node ``P_j``
    (normal ``N_j``), is in the intersecting volume when ``V_ij . N_j >= 0`` and
    ``V_ij . N_i <= 0`` with ``V_ij = P_j - P_i`` (eq. 2). §4.6: the nodes of V_int (sorted by
    slice) are split into separate volumes wherever a whole slice is outside V_int."""
    side, centre, R = win.side, pose.centre, pose.R
    body_pts, body_nrm, kidx = win.body_pts, win.body_nrm, win.k
    ru, rz, h_x = rail.u, rail.z, rail.h_x
    nw = body_pts.shape[0]
    P = np.empty((nw, 3))
    N = np.empty((nw, 3))
    Pj = np.empty((nw, 3))
    inside = np.zeros(nw, dtype=np.bool_)
    pos = 0
    for i in range(nw):
        for a in range(3):
            P[i, a] = (
                centre[a]
                + R[a, 0] * body_pts[i, 0]
                + R[a, 1] * body_pts[i, 1]
                + R[a, 2] * body_pts[i, 2]
            )
        u = side * P[i, 1]
        lj, pos = nearest_from(u, P[i, 2], ru, rz, K_NEAR, pos)
        Pj[i, 1] = side * ru[lj]
        Pj[i, 2] = rz[lj]
        v1, v2 = Pj[i, 1] - P[i, 1], Pj[i, 2] - P[i, 2]
        nj1, nj2 = side * rail.nu[lj], rail.nz[lj]
        if not v1 * nj1 + v2 * nj2 >= 0.0:
            continue  # eq. (2), rail side: outside (N and Pj's x are read only inside)
        for a in range(3):
            N[i, a] = R[a, 0] * body_nrm[i, 0] + R[a, 1] * body_nrm[i, 1] + R[a, 2] * body_nrm[i, 2]
        Pj[i, 0] = np.round(P[i, 0] / h_x) * h_x
        v0 = Pj[i, 0] - P[i, 0]
        inside[i] = v0 * N[i, 0] + v1 * N[i, 1] + v2 * N[i, 2] <= 0.0  # eq. (2), wheel side
    # §4.6: a new volume wherever a whole slice between two V_int nodes is outside
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
    n_nodes = np.zeros(MAX_VOL, dtype=np.int64)
    kmin = np.full(MAX_VOL, 10**9)
    kmax = np.full(MAX_VOL, -(10**9))
    for i in range(nw):
        g = vol[i]
        if g < 0:
            continue
        n_nodes[g] += 1
        kmin[g] = min(kmin[g], kidx[i])
        kmax[g] = max(kmax[g], kidx[i])
    return WheelSearch(P, N, Pj, vol, nvol, n_nodes, kmin, kmax)


@njit(cache=True)
def empty_contacts(ws):
    """The :class:`Contacts` of a search, to be filled by a method's stage."""
    buf = np.zeros((MAX_VOL, 13))
    buf[:, 9] = -1e300
    buf[:, 11] = ws.n_nodes
    return Contacts(ws.nvol, buf, buf[:, 0:3], buf[:, 3:6], buf[:, 6:9], buf[:, 9], buf[:, 10],
                    buf[:, 11], buf[:, 12])


@njit(cache=True)
def packed(out):
    """What a method's stage returns: ``(n, buf)`` of its :class:`Contacts`."""
    return out.n, out.buf


@njit(cache=True)
def set_profile_coordinates(out, side, pose, wheel):
    """``s`` of each contact's wheel point (the methods that pick a node)."""
    for g in range(out.n):
        _, out.s[g] = wheel_normal(out.wheel_point[g], side, pose, wheel)


@njit(cache=True)
def locus_at_slices(ws, ls, lphi, lgap):
    """The rigid locus (samples ``ls`` with angles ``lphi`` and gaps ``lgap``, m; +inf or NaN:
    not over the rail) interpolated at the mesh slices ``ws``: locus angle and gap per slice,
    the gap +inf off the samples and where no point is over the rail. ``np.interp`` of both (a
    non-finite gap taken as 1 m), the two in one walk along the samples: the same bits for
    strictly increasing ``ls`` (``tests/unit/test_contact_mesh.py``), a third of the time for
    increasing ``ws``."""
    n, m = ws.size, ls.size
    phi, gap = np.empty(n), np.empty(n)
    j = 0
    for i in range(n):
        x = ws[i]
        if np.isnan(x):  # np.interp: NaN in, NaN out
            phi[i], gap[i] = x, x
            continue
        while j > 0 and ls[j] > x:
            j -= 1
        while j < m - 1 and ls[j + 1] <= x:
            j += 1
        if x < ls[0]:  # np.interp: the first value left of the samples, the last right
            phi[i], gap[i] = lphi[0], np.inf
            continue
        if x > ls[m - 1]:
            phi[i], gap[i] = lphi[m - 1], np.inf
            continue
        g0 = lgap[j] if np.isfinite(lgap[j]) else 1.0
        if j == m - 1 or ls[j] == x:
            p, g = lphi[j], g0
        else:
            g1 = lgap[j + 1] if np.isfinite(lgap[j + 1]) else 1.0
            p = _interp_step(x, ls[j], ls[j + 1], lphi[j], lphi[j + 1])
            g = _interp_step(x, ls[j], ls[j + 1], g0, g1)
        phi[i], gap[i] = p, (np.inf if g >= 1.0 else g)
    return phi, gap


@njit(cache=True, inline="always")
def _interp_step(x, x0, x1, f0, f1):
    """``np.interp`` between two samples (numba's and numpy's formula, with its retry from the
    right where the left's gives NaN)."""
    slope = (f1 - f0) / (x1 - x0)
    v = slope * (x - x0) + f0
    if np.isnan(v):
        v = slope * (x - x1) + f1
        if np.isnan(v) and f0 == f1:
            v = f0
    return v


@njit(cache=True)
def window_slices(gap_k, phi_star, r, depth, h_circ, dphi):
    """The slices of a window: every slice next to (or at) one whose locus gap ``gap_k`` is
    within ``depth`` of the smallest, with the angle index of its locus point ``mc`` and its
    angular half-width in nodes ``mh`` (circle against a rail of effective radius at most
    ``r / 0.2``: a conservative bound, plus two nodes). Returns ``(ks, mc, mh)``."""
    n = gap_k.size
    limit = np.min(gap_k) + depth
    mark = np.zeros(n, dtype=np.bool_)
    for k in range(n):
        if gap_k[k] <= limit:
            mark[max(k - 1, 0)] = True
            mark[k] = True
            mark[min(k + 1, n - 1)] = True
    ks = np.nonzero(mark)[0]
    mc = np.empty(ks.size, dtype=np.int64)
    mh = np.empty(ks.size, dtype=np.int64)
    for q in range(ks.size):
        k = ks[q]
        half_arc = np.sqrt(2.0 * (r[k] / 0.2) * depth) + 2.0 * h_circ
        mc[q] = int(np.round(phi_star[k] / dphi))
        mh[q] = int(np.ceil(half_arc / h_circ))
    return ks, mc, mh


@njit(cache=True)
def angle_table(dphi, half):
    """``sin`` and ``cos`` of the wheel grid's angles ``m * dphi`` for ``m = -half ... half``
    (index ``m + half``), computed as :func:`window_wheel_nodes` computes them (the same
    bits: the scalar library functions, numba's SVML off; ``tests/unit/test_contact_mesh.py``)."""
    n = 2 * half + 1
    sin_t, cos_t = np.empty(n), np.empty(n)
    for i in range(n):
        phi = (i - half) * dphi
        sin_t[i], cos_t[i] = np.sin(phi), np.cos(phi)
    return sin_t, cos_t


#: margin of :func:`_row_tangents`' and :func:`grid_angle`'s bounds (tangent of the angle, ~rad
#: here): far above the rounding of ``atan2`` and ``tan`` (~1e-16), far below a node's angular
#: step (~1e-3 rad)
TAN_MARGIN = 1e-9


@njit(cache=True)
def angle_bounds(dphi, half):
    """The tangent of the angle ``(m + 1/2) dphi`` half-way between the wheel grid's angles
    ``m dphi`` and ``(m + 1) dphi``, for ``m = -half ... half`` (index ``m + half``); NaN where
    ``|angle| >= 1.4`` rad (the tangent grows too steep to decide by)."""
    n = 2 * half + 1
    out = np.empty(n)
    for i in range(n):
        a = (i - half + 0.5) * dphi
        out[i] = np.tan(a) if -1.4 < a < 1.4 else np.nan
    return out


@njit(cache=True, inline="always")
def grid_angle(c0, c2, wheel):
    """The wheel grid's angle index ``m`` nearest the angle ``atan2(c0, -c2)`` of a point at
    wheel-frame ``(c0, ., c2)``: ``np.round(atan2(c0, -c2) / dphi)``, and the sine and cosine
    of ``m dphi`` (from :func:`angle_table`, the same bits as computing them). Below the axle
    (``-c2 > 0``) the tangent ``c0 / -c2`` decides between the two angles' half-way tangents
    (:func:`angle_bounds`) where it lies farther than :data:`TAN_MARGIN` from both; elsewhere,
    and where a series estimate of the index misses, ``atan2`` is computed (issue 14)."""
    dphi, sin_t, cos_t, tan_b = wheel.dphi, wheel.sin_t, wheel.cos_t, wheel.tan_b
    half = (sin_t.size - 1) // 2
    if c2 < 0.0:
        t = c0 / -c2
        if -0.3 < t < 0.3:
            t2 = t * t
            m = int(np.round(t * (1.0 - t2 * (1.0 / 3.0 - 0.2 * t2)) / dphi))
            i = m + half
            if (1 <= i < sin_t.size and tan_b[i - 1] + TAN_MARGIN < t
                    and t < tan_b[i] - TAN_MARGIN):
                return m, sin_t[i], cos_t[i]
    mf = np.round(np.arctan2(c0, -c2) / dphi)
    m = int(mf)
    i = m + half
    if 0 <= i < sin_t.size:
        return m, sin_t[i], cos_t[i]
    phi = mf * dphi
    return m, np.sin(phi), np.cos(phi)


@njit(cache=True)
def window_wheel_nodes(side, ks, mc, mh, wheel, rail, pose, limit, filt, sin_t, cos_t):
    """Wheel nodes of a window: slices ``ks`` with angle indices ``mc ± mh``; with ``filt``,
    only the nodes whose vertical gap to the rail is at most ``limit`` (m). ``sin_t, cos_t``:
    the :func:`angle_table` (an angle outside it is computed). Returns (k, m, body points, body
    normals, track points)."""
    s, r, dr, d, dphi = wheel.s, wheel.r, wheel.dr, wheel.d, wheel.dphi
    half = (sin_t.size - 1) // 2
    centre, R = pose.centre, pose.R
    u0, du, tabz, u_min, u_max = rail.tab_u0, rail.tab_du, rail.tab_z, rail.u_min, rail.u_max
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
            it = mm + half
            if 0 <= it < sin_t.size:
                sp, cp = sin_t[it], cos_t[it]
            else:
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
def window_nodes(side, ks, mc, mh, wheel, rail, pose, limit, filt, sin_t, cos_t, with_rail):
    """A window's nodes in one call: :func:`window_wheel_nodes`, then (``with_rail``, and
    where a wheel node was kept) :func:`window_rail_nodes` (one dispatch of the meshes'
    arrays instead of two, ~5 us each). Returns (k, m, body points, body normals, rail track
    points, rail track normals)."""
    k, m, pts, nrm, tp = window_wheel_nodes(side, ks, mc, mh, wheel, rail, pose, limit, filt,
                                            sin_t, cos_t)
    if with_rail and k.size:
        rp, rn = window_rail_nodes(side, k, m, tp, wheel, rail, pose, filt)
    else:
        rp, rn = np.zeros((0, 3)), np.zeros((0, 3))
    return k, m, pts, nrm, rp, rn


@njit(cache=True)
def locus_window(side, ls, lphi, lgap, depth, h_circ, wheel, rail, pose, with_rail, max_nodes):
    """A wheel's window from its rigid locus in one call: :func:`locus_at_slices` at the mesh
    slices, :func:`window_slices` and :func:`window_nodes` (filtered, nodes within ``depth``
    of the smallest gap), as :func:`lutmpi.contact.mesh.build_window` calls them one by one
    (the same bits; the glue between them cost a fifth of a window). Returns ``(n_nodes, k,
    m, body points, body normals, rail track points, rail track normals)``: ``n_nodes`` the
    wheel nodes the slices span, and no node where that is above ``max_nodes``."""
    phi, gap = locus_at_slices(wheel.s, ls, lphi, lgap)
    ks, mc, mh = window_slices(gap, phi, wheel.r, depth, h_circ, wheel.dphi)
    n_nodes = 0
    for q in range(mh.size):
        n_nodes += 2 * mh[q] + 1
    if n_nodes > max_nodes:
        e = np.zeros(0, dtype=np.int64)
        z = np.zeros((0, 3))
        return n_nodes, e, e, z, z, z, z
    k, m, pts, nrm, rp, rn = window_nodes(side, ks, mc, mh, wheel, rail, pose, np.min(gap) + depth,
                                          True, wheel.sin_t, wheel.cos_t, with_rail)
    return n_nodes, k, m, pts, nrm, rp, rn


@njit(cache=True)
def _row_tangents(grid, m0, dphi):
    """Per row ``ik`` of a window's node grid: the tangents ``t_lo, t_hi`` of the angles
    ``(m_lo - 1/2) dphi`` and ``(m_hi + 1/2) dphi`` that round to its first and last marked
    angle index, where every index between them is marked; NaN where not (each node of the
    row is then decided by ``atan2``); ``t_lo = +inf, t_hi = -inf`` where the row is empty.
    A rail node at tangent ``t = c0 / -c2`` of its angle ``atan2(c0, -c2)`` (``-c2 > 0``)
    then lies on a marked cell of the row when ``t`` is inside ``(t_lo, t_hi)`` by more than
    :data:`TAN_MARGIN`, and on none when outside ``[t_lo, t_hi]`` by more: the same answer as
    rounding ``atan2 / dphi``, whose library call is then needed only within the margin (or
    at a NaN ``t``) (issue 14)."""
    gk, gm = grid.shape
    t_lo, t_hi = np.full(gk, np.inf), np.full(gk, -np.inf)
    for ik in range(gk):
        lo, hi = -1, -1
        for im in range(gm):
            if grid[ik, im]:
                if lo < 0:
                    lo = im
                hi = im
        if lo < 0:
            continue
        full = True
        for im in range(lo, hi + 1):
            if not grid[ik, im]:
                full = False
                break
        a_lo, a_hi = (lo + m0 - 0.5) * dphi, (hi + m0 + 0.5) * dphi
        if full and -1.4 < a_lo and a_hi < 1.4:
            t_lo[ik], t_hi[ik] = np.tan(a_lo), np.tan(a_hi)
        else:
            t_lo[ik], t_hi[ik] = np.nan, np.nan
    return t_lo, t_hi


@njit(cache=True)
def window_rail_nodes(side, k, m, tp, wheel, rail, pose, filt):
    """Rail nodes in the box spanned by the window's wheel nodes (two nodes of margin); with
    ``filt``, only those whose nearest wheel node is (next to) a window node. Returns (track
    points, track normals)."""
    ru, rz, rnu, rnz, h_x = rail.u, rail.z, rail.nu, rail.nz, rail.h_x
    ws, wr, d, dphi = wheel.s, wheel.r, wheel.d, wheel.dphi
    centre, R = pose.centre, pose.R
    KN = K_NEAR
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
    t_lo, t_hi = _row_tangents(grid, m0, dphi) if filt else (np.empty(0), np.empty(0))
    total = (l_hi - l_lo + 1) * (j_hi - j_lo + 1)
    P = np.empty((total, 3))
    N = np.zeros((total, 3))
    cnt = 0
    pos = 0
    for ll in range(l_lo, l_hi + 1):
        for jj in range(j_lo, j_hi + 1):
            px, py, pz = jj * h_x, side * ru[ll], rz[ll]
            if filt:
                q0, q1, q2 = px - centre[0], py - centre[1], pz - centre[2]
                c0 = R[0, 0] * q0 + R[1, 0] * q1 + R[2, 0] * q2
                c1 = R[0, 1] * q0 + R[1, 1] * q1 + R[2, 1] * q2
                c2 = R[0, 2] * q0 + R[1, 2] * q1 + R[2, 2] * q2
                kk, pos = nearest_from(side * c1 - d, np.sqrt(c0 * c0 + c2 * c2), ws, wr, KN,
                                       pos)
                ik = kk - k0
                if ik < 0 or ik >= gk:
                    continue
                # the angle's node index only where the tangent cannot decide (_row_tangents)
                tv = c0 / -c2 if c2 < 0.0 else np.nan
                if tv > t_lo[ik] + TAN_MARGIN and tv < t_hi[ik] - TAN_MARGIN:
                    pass  # inside the row's marked angles, all of them marked
                elif tv < t_lo[ik] - TAN_MARGIN or tv > t_hi[ik] + TAN_MARGIN:
                    continue  # outside them
                else:
                    im = int(np.round(np.arctan2(c0, -c2) / dphi)) - m0
                    if im < 0 or im >= gm or not grid[ik, im]:
                        continue
            P[cnt, 0], P[cnt, 1], P[cnt, 2] = px, py, pz
            N[cnt, 1], N[cnt, 2] = side * rnu[ll], rnz[ll]
            cnt += 1
    return P[:cnt], N[:cnt]
