"""The roll scan of ``h(roll) = z_left - z_right`` (:mod:`lutmpi.contact.locus`), no root
skipped, and the one-dimensional searches on it (bisection, SciPy's bounded Brent method),
ported step for step so that a compiled search returns the same bits as the SciPy call it
replaces. Per-side arguments: :mod:`lutmpi.contact.rigid_kernels`.
"""


from __future__ import annotations

import numpy as np
from numba import njit

from lutmpi.contact.rigid_kernels import rotation, scan_side_info

# -- the brackets of the roll scan (:func:`lutmpi.contact.locus.find_brackets`) --------------
#: a scan point next to a sign change whose two neighbouring chords' slopes differ by more
#: than this factor is a fold's: :func:`bracket_searches` searches its same-sign side
FOLD_RATIO = 3.0


@njit(cache=True)
def bracket_searches(x, h, lip):
    """What the scan ``(x, h)`` needs searched between its points: the NaN edges (pairs
    ``(a, b)``, ``a`` finite and ``b`` NaN, where ``|h(a)|`` is at most ``lip`` times the step:
    a root may lie before the NaN range), the dips (index ``i`` of a scan point whose ``|h|``
    is at most both neighbours', all three of one sign and finite, and not shallow compared to
    its distance from zero) and the folds beside a sign change (index ``i`` of a scan point
    next to a sign change whose other neighbour has the same sign and at least its ``|h|``,
    the chords on the two sides of ``i`` differing in slope by more than
    :data:`FOLD_RATIO`). Where three roots meet within a scan step (a tread and a flange root
    with the unstable one between) the sign change alone gives one of them, and the other two
    hide on either side of ``i`` (a measured worn flange, Car7216 on the Manchester rail,
    y = 4.749 mm: roots at 1.41, 1.58 and 1.86 mrad, the scan's points at 1.116, 1.616 and
    2.116 mrad with ``h`` +420, +1.4 and -17.5 um). Returns ``(edges (m, 2), dips (k,),
    folds (p,))``."""
    n = x.size
    edges = np.empty((max(n - 1, 0), 2))
    ne = 0
    for i in range(n - 1):
        fa, fb = np.isfinite(h[i]), np.isfinite(h[i + 1])
        if fa == fb:
            continue
        if fa:
            a, b, ha = x[i], x[i + 1], h[i]
        else:
            a, b, ha = x[i + 1], x[i], h[i + 1]
        if abs(ha) > lip * abs(b - a):
            continue
        edges[ne, 0], edges[ne, 1] = a, b
        ne += 1
    dips = np.empty(max(n - 2, 0), dtype=np.int64)
    folds = np.empty(max(n - 2, 0), dtype=np.int64)
    nd = nf = 0
    for i in range(1, n - 1):
        hm, h0, hp = h[i - 1], h[i], h[i + 1]
        if not (np.isfinite(hm) and np.isfinite(hp) and np.isfinite(h0)):
            continue
        if hm * h0 > 0 and h0 * hp > 0:      # one sign: a dip of |h| toward zero?
            if (abs(h0) <= abs(hm) and abs(h0) <= abs(hp)
                    and abs(h0) <= max(abs(hm - h0), abs(hp - h0))):
                dips[nd] = i
                nd += 1
            continue
        if hm * h0 > 0 and h0 * hp < 0:      # beside a sign change: a fold?
            j, k = i - 1, i + 1
        elif hp * h0 > 0 and h0 * hm < 0:
            j, k = i + 1, i - 1
        else:
            continue
        if abs(h[j]) < abs(h0):
            continue
        same = abs(h[j] - h0) / abs(x[j] - x[i])
        other = abs(h[k] - h0) / abs(x[k] - x[i])
        if max(same, other) > FOLD_RATIO * min(same, other):
            folds[nf] = i
            nf += 1
    return edges[:ne], dips[:nd], folds[:nf]


@njit(cache=True)
def bracket_ends(x, h, X, H):
    """The brackets of the scan ``(x, h)`` with the searched points appended (``X, H``: the
    scan points, then the points the edge and dip searches found): sign changes and exact zeros
    between neighbours in order of roll (then ``h``; a stable order), a bracket only within one
    finite run of the scan. Returns ``(a, b, stable)`` arrays (``a == b`` at an exact zero;
    ``stable``: ``h`` falls through zero)."""
    m = X.size
    order = np.arange(m)
    for i in range(1, m):  # stable insertion sort by (X, H); the scan points are in order
        v = order[i]
        j = i - 1
        while j >= 0 and (X[order[j]] > X[v] or (X[order[j]] == X[v] and H[order[j]] > H[v])):
            order[j + 1] = order[j]
            j -= 1
        order[j + 1] = v
    xf, hf = np.empty(m), np.empty(m)
    nf = 0
    for i in range(m):
        if np.isfinite(H[order[i]]):
            xf[nf], hf[nf] = X[order[i]], H[order[i]]
            nf += 1
    nan_before = np.zeros(x.size + 1, dtype=np.int64)  # NaN scan points before x[k]
    for k in range(x.size):
        nan_before[k + 1] = nan_before[k] + (0 if np.isfinite(h[k]) else 1)
    a, b = np.empty(nf + 1), np.empty(nf + 1)
    st = np.empty(nf + 1, dtype=np.bool_)
    nb = 0
    for i in range(nf):
        xa, fa = xf[i], hf[i]
        last = i == nf - 1
        if not (fa == 0.0 or (not last and fa * hf[i + 1] < 0)):
            continue
        if fa == 0.0:
            prev = hf[i - 1] if i > 0 else np.nan
            nxt = hf[i + 1] if not last else np.nan
            a[nb], b[nb], st[nb] = xa, xa, prev > 0 or nxt < 0
            nb += 1
        else:
            xb = xf[i + 1]
            # one finite run: no NaN scan point strictly between the two
            if (nan_before[np.searchsorted(x, xb, "left")]
                    == nan_before[np.searchsorted(x, xa, "right")]):
                a[nb], b[nb], st[nb] = xa, xb, fa > 0
                nb += 1
    return a[:nb], b[:nb], st[:nb]


#: fraction of the two-point step :func:`scan_adaptive` tries (below 1, so that the try
#: succeeds while ``|dh/droll|`` stays under ``(1/LOOKAHEAD - 1) lip``, ~2.1 m/rad on the
#: paper's pair against ~1.5 there; 0.9, with a try that fails on the approach to a root, scans
#: ~4 % slower, 0.8 ~2 %)
LOOKAHEAD = 0.85


@njit(cache=True)
def slope_table(tabz, du):
    """The sparse table of range maxima of a rail height table's slopes ``|tabz[j + 1] -
    tabz[j]| / du`` (row ``k``: the largest over ``2 ** k`` cells from each cell; padded with
    zeros), for :func:`range_slope`."""
    n = max(tabz.size - 1, 1)
    levels = 1
    while (1 << levels) <= n:
        levels += 1
    st = np.zeros((levels, n))
    for j in range(tabz.size - 1):
        st[0, j] = abs(tabz[j + 1] - tabz[j]) / du
    for k in range(1, levels):
        w = 1 << (k - 1)
        for j in range(n - (1 << k) + 1):
            st[k, j] = max(st[k - 1, j], st[k - 1, j + w])
    return st


@njit(cache=True, inline="always")
def range_slope(st, j0, j1):
    """The steepest slope of the cells ``j0 ... j1`` (clipped to the table) from
    :func:`slope_table`'s ``st``."""
    n = st.shape[1]
    j0, j1 = max(j0, 0), min(j1, n - 1)
    if j1 < j0:
        return 0.0
    k = 0
    while (2 << k) <= j1 - j0 + 1:
        k += 1
    return max(st[k, j0], st[k, j1 - (1 << k) + 1])


@njit(cache=True, inline="always")
def local_slope_bound(side, st, turn_yaw, rate_yaw, sx, ib, u, dx):
    """A bound of ``|d gap / d roll|`` (m/rad) of coarse sample ``ib``'s locus point while the
    roll moves by at most ``dx`` (rad) from a scan point where its lateral rail coordinate is
    ``u`` (m); +inf where it does not apply (the point could leave the rail's data, or its
    locus angle could turn too fast to bound). ``sx``: the sine of the scan's end roll;
    ``turn_yaw = |tan(yaw)|``, ``rate_yaw = |sin(yaw)| sx / cos(yaw)^3`` (:func:`_yaw_terms`).

    The point ``b = (r sin(phi), sgn (d + s), -r cos(phi))`` of the wheelset frame moves with
    the roll by ``dp_z <= |d + s| + r sx`` and ``|dp_y| <= r + |d + s| sx`` per radian
    (:meth:`lutmpi.contact.locus.LocusSolver._lipschitz`), and along its circle by ``r`` per
    radian of its locus angle ``phi = beta + arcsin(X)``, which turns with the roll by at most
    ``|beta'| + |X'| / sqrt(1 - X^2)``: ``beta = atan2(sin(yaw) sin(x), cos(yaw))`` gives
    ``|beta'| <= |tan(yaw)|`` and ``X = -sgn sin(yaw) cos(x) dr / amp`` (``amp >= cos(yaw)``)
    gives ``|X| <= |dr tan(yaw)|`` and ``|X'| <= |dr sin(yaw)| sx / cos(yaw)^3``. So its gap
    ``p_z - z_rail(u)`` changes by at most ``A + M S`` per radian, ``M`` the rate of ``u``
    and ``S`` the steepest slope of the rail's height table within ``M dx`` of ``u``: the
    rail's slopes where this point can be, not the steepest anywhere."""
    s_c, r_c, dr_c, d, lim = side[7], side[8], side[9], side[4], side[6]
    by, r, g = abs(d + s_c[ib]), r_c[ib], abs(dr_c[ib])
    dxr = g * rate_yaw
    xm = g * turn_yaw + dxr * dx
    if not xm < 0.9:
        return np.inf
    turn = turn_yaw + dxr / np.sqrt(1.0 - xm * xm)
    rate = r + by * sx + r * turn
    half = rate * dx
    u0, du, u_min, u_max = lim[0], lim[1], lim[2], lim[3]
    if not (u - half >= u_min and u + half <= u_max):
        return np.inf
    slope = range_slope(st, int((u - half - u0) / du) - 1, int((u + half - u0) / du) + 1)
    return by + r * sx + r * turn + rate * slope


@njit(cache=True, inline="always")
def _yaw_terms(yaw, sx):
    """``(|tan(yaw)|, |sin(yaw)| sx / cos(yaw)^3)`` of :func:`local_slope_bound`."""
    sy, cy = abs(np.sin(yaw)), abs(np.cos(yaw))
    return sy / cy, sy * sx / (cy * cy * cy)


@njit(cache=True, inline="always")
def _reach(pt, dx, lip, yt, left, right, bound):
    """How far (rad, at most ``dx`` beyond ``|h| / lip``) from the scan point ``pt``
    (:func:`_scan_info`) ``h`` keeps its sign, on an interval of at most ``dx`` (``yt``: the
    pose's :func:`_yaw_terms`). Where ``h >
    0`` the left wheel's height can only fall as fast as its smallest coarse sample's gap
    rises (:func:`local_slope_bound`, from the refined height less the refinement's gain over
    that sample), and the right's rise at most by its whole bound ``lip_r``; ``h < 0`` the
    other way round. 0 at a NaN point."""
    h = pt[0]
    if not np.isfinite(h):
        return 0.0
    out = abs(h) / lip
    lip_l, lip_r, sx, st_l, st_r = bound
    ty, ry = yt
    if h > 0.0:
        gain, hard = pt[1], lip_r
        easy = local_slope_bound(left, st_l, ty, ry, sx, pt[2], pt[3], dx)
    else:
        gain, hard = pt[4], lip_l
        easy = local_slope_bound(right, st_r, ty, ry, sx, pt[5], pt[6], dx)
    if np.isfinite(easy):
        out = max(out, min(dx, (abs(h) - gain) / (easy + hard)))
    return out


@njit(cache=True, inline="always")
def _one_step(pt, lip, yt, left, right, bound):
    """The root-free reach of the scan point ``pt`` on its own (:func:`_reach` over the
    largest interval it could certify, and half and a quarter of it: a shorter interval meets
    fewer steep rail cells)."""
    h = pt[0]
    if not np.isfinite(h):
        return 0.0
    hard = bound[1] if h > 0.0 else bound[0]
    cap = max(abs(h) - (pt[1] if h > 0.0 else pt[4]), 0.0) / hard
    out = abs(h) / lip
    for f in (1.0, 0.5, 0.25):
        out = max(out, _reach(pt, f * cap, lip, yt, left, right, bound))
    return out


@njit(cache=True, inline="always")
def _certified(pa, pb, dx, lip, yt, left, right, bound):
    """True when no root of ``h`` lies between two scan points ``dx`` apart (:func:`_scan_info`
    each: ``h`` finite, one sign, and their reaches over the interval, :func:`_reach`, cover
    it)."""
    ha, hb = pa[0], pb[0]
    if not (np.isfinite(ha) and np.isfinite(hb) and ha * hb > 0.0):
        return False
    return (_reach(pa, dx, lip, yt, left, right, bound)
            + _reach(pb, dx, lip, yt, left, right, bound) >= dx)


@njit(cache=True)
def scan_adaptive(lo, hi, step, lip, yaw, y, left, right, bound):
    """``h`` from ``lo`` to ``hi`` (rad), no root skipped: ``lip`` bounds ``|dh/droll|``, so no
    root lies within ``|h| / lip`` of a point, and the local bound of :func:`_reach` (``bound
    = (lip_l, lip_r, sx, st_l, st_r)``: each wheel's share of ``lip``, the sine of the scan's
    end roll and each rail's :func:`slope_table`) often certifies further (the one-point step,
    at least ``step``; a NaN point takes ``step``). Where the two-point step (twice the
    one-point reach) exceeds ``step``, the point :data:`LOOKAHEAD` times that far is tried
    first: it is kept when the interval up to it is root-free by both ends
    (:func:`_certified`), which far from the roots nearly doubles the step; otherwise the
    one-point step is taken, and the tried point kept after it when the interval between them
    is root-free. Returns the rolls and ``h`` there (``hi`` always included)."""
    n_max = int((hi - lo) / step) + 3
    xs = np.empty(n_max)
    hs = np.empty(n_max)
    gl, gr, fine, U, PZ = _scratch(left, right)
    yt = _yaw_terms(yaw, bound[2])
    x = lo
    pt = _scan_info(x, yaw, y, left, right, gl, gr, fine, U, PZ)
    xs[0], hs[0] = x, pt[0]
    k = 1
    while x < hi and k < n_max:
        h = pt[0]
        one = step
        reach = _one_step(pt, lip, yt, left, right, bound)
        if np.isfinite(h):
            one = max(step, reach)
        two = LOOKAHEAD * 2.0 * reach if np.isfinite(h) else 0.0
        if two > one and x + one < hi:
            xt = min(x + two, hi)
            pt_t = _scan_info(xt, yaw, y, left, right, gl, gr, fine, U, PZ)
            if _certified(pt, pt_t, xt - x, lip, yt, left, right, bound):
                x, pt = xt, pt_t
                xs[k], hs[k] = x, pt[0]
                k += 1
                continue
            x = x + one
            pt = _scan_info(x, yaw, y, left, right, gl, gr, fine, U, PZ)
            xs[k], hs[k] = x, pt[0]
            k += 1
            if k < n_max and _certified(pt, pt_t, xt - x, lip, yt, left, right, bound):
                x, pt = xt, pt_t
                xs[k], hs[k] = x, pt[0]
                k += 1
            continue
        x = min(x + one, hi)
        pt = _scan_info(x, yaw, y, left, right, gl, gr, fine, U, PZ)
        xs[k], hs[k] = x, pt[0]
        k += 1
    return xs[:k], hs[:k]


@njit(cache=True)
def _scratch(left, right):
    """Work arrays of :func:`_scan_one` for the per-side arguments ``left``, ``right``."""
    m = max(left[0].size, right[0].size, left[1].size, right[1].size)
    return (np.empty(left[0].size), np.empty(right[0].size), np.empty(m), np.empty(m),
            np.empty(m))


@njit(cache=True)
def _scan_one(x, yaw, y, left, right, gl, gr, fine, U, PZ):
    """``h`` at roll ``x`` with the work arrays of :func:`_scratch` (allocated once per scan,
    not once per roll)."""
    return _scan_info(x, yaw, y, left, right, gl, gr, fine, U, PZ)[0]


@njit(cache=True)
def _scan_info(x, yaw, y, left, right, gl, gr, fine, U, PZ):
    """``h`` at roll ``x`` and what :func:`_reach` bounds its change by: ``(h, gain_l, ib_l,
    u_l, gain_r, ib_r, u_r)``, per wheel the refinement's gain over its smallest coarse
    sample's height, that sample and its lateral rail coordinate (:func:`scan_side_info`)."""
    R = rotation(yaw, x)
    hl, cl, il, ul = scan_side_info(1.0, left, R, y, gl, fine, U, PZ)
    hr, cr, ir, ur = scan_side_info(-1.0, right, R, y, gr, fine, U, PZ)
    h = hl - hr if (np.isfinite(hl) and np.isfinite(hr)) else np.nan
    return h, hl - cl, il, ul, hr - cr, ir, ur


@njit(cache=True)
def scan(rolls, yaw, y, left, right):
    """``h(roll) = z_left - z_right`` at every roll of ``rolls`` (NaN where a wheel has no point
    over its rail), pitch 0 (per-side arguments: the module's docstring)."""
    out = np.empty(rolls.size)
    gl, gr, fine, U, PZ = _scratch(left, right)
    for i in range(rolls.size):
        out[i] = _scan_one(rolls[i], yaw, y, left, right, gl, gr, fine, U, PZ)
    return out


@njit(cache=True)
def scan_at(x, yaw, y, sides):
    """``h`` at one roll ``x`` (:func:`scan`; ``sides``: its ``(left, right)`` arguments)."""
    return scan(np.array([x]), yaw, y, sides[0], sides[1])[0]


@njit(cache=True)
def edge_bisect(a, b, n, yaw, y, sides):
    """The last finite point of ``h`` between ``a`` (finite) and ``b`` (NaN) by ``n``
    bisections, and ``h`` there."""
    for _ in range(n):
        m = 0.5 * (a + b)
        if np.isfinite(scan_at(m, yaw, y, sides)):
            a = m
        else:
            b = m
    return a, scan_at(a, yaw, y, sides)


@njit(cache=True)
def bounded_min(lo, hi, sgn, xatol, maxfun, yaw, y, sides):
    """Minimum of ``sgn * h`` on ``[lo, hi]``: SciPy's bounded Brent method
    (``minimize_scalar(method="bounded")``, step for step, so the result is the same to the
    bit); returns ``(x, sgn * h(x))``."""
    sqrt_eps = np.sqrt(2.2e-16)
    golden_mean = 0.5 * (3.0 - np.sqrt(5.0))
    a, b = lo, hi
    fulc = a + golden_mean * (b - a)
    nfc, xf = fulc, fulc
    rat = e = 0.0
    x = xf
    fx = sgn * scan_at(x, yaw, y, sides)
    num = 1
    ffulc = fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = sqrt_eps * np.abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while np.abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = True
        if np.abs(e) > tol1:  # parabolic fit
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = np.abs(q)
            r = e
            e = rat
            if (np.abs(p) < np.abs(0.5 * q * r)) and (p > q * (a - xf)) and (p < q * (b - xf)):
                rat = (p + 0.0) / q
                x = xf + rat
                if ((x - a) < tol2) or ((b - x) < tol2):
                    rat = tol1 * (np.sign(xm - xf) + (1.0 if xm - xf == 0 else 0.0))
            else:
                golden = True
        if golden:
            e = a - xf if xf >= xm else b - xf
            rat = golden_mean * e
        x = xf + (np.sign(rat) + (1.0 if rat == 0 else 0.0)) * max(np.abs(rat), tol1)
        fu = sgn * scan_at(x, yaw, y, sides)
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if (fu <= fnfc) or (nfc == xf):
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif (fu <= ffulc) or (fulc == xf) or (fulc == nfc):
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = sqrt_eps * np.abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxfun:
            break
    return xf, fx

