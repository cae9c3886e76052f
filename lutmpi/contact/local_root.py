"""The local solve of the contact locus (:mod:`lutmpi.contact.locus`): the rigid root near roll
0 by the secant method on the samples near the gap minima, Brent's root finder where it
brackets one (SciPy's ``brentq``, step for step: the same bits), checked on the whole
profiles. Per-side arguments: :mod:`lutmpi.contact.rigid_kernels`.
"""


from __future__ import annotations

import numpy as np
from numba import njit

from lutmpi.contact.rigid_kernels import full_locus, rotation, side_gaps

# -- the local solve: secant from roll 0 on the samples near the gap minima --------------------
LOCAL_BAND = 5e-4  # m, gap minima this close to a side's smallest are the candidates' centres
LOCAL_HALF = 30  # samples either side of a candidate minimum
LOCAL_CHECK = 1e-12  # m, candidate and full touching heights agree to this at an accepted root
BRENTQ_ITER = 100  # SciPy's default
#: status of :func:`local_root`
LOCAL_OK, LOCAL_NONE, LOCAL_NOCONV, LOCAL_NAN = 0, 1, 2, 3


@njit(cache=True)
def heights(y, yaw, roll, left, right, idx_l, idx_r, gap_l, gap_r):
    """Touching heights (left, right) of G at this roll on the samples ``idx_l``/``idx_r``
    (gaps written into ``gap_l``/``gap_r``) and the positions of the gap minima in them;
    ``left``/``right``: ``(s, r, dr, d, tabz, lim)``."""
    R = rotation(yaw, roll)
    s, r, dr, d, tab, lim = left
    none = np.empty(0)
    zl, il = side_gaps(idx_l, 1.0, s, r, dr, d, R, y, lim[0], lim[1], tab, lim[2], lim[3], gap_l,
                       none)
    s, r, dr, d, tab, lim = right
    zr, ir = side_gaps(idx_r, -1.0, s, r, dr, d, R, y, lim[0], lim[1], tab, lim[2], lim[3],
                       gap_r, none)
    return zl, zr, il, ir


@njit(cache=True)
def h_of(y, yaw, roll, left, right, idx_l, idx_r, gap_l, gap_r):
    """``h = z_left - z_right`` (NaN unless both heights are finite)."""
    zl, zr, _, _ = heights(y, yaw, roll, left, right, idx_l, idx_r, gap_l, gap_r)
    if np.isfinite(zl) and np.isfinite(zr):
        return zl - zr
    return np.nan


@njit(cache=True)
def candidates(gap, band, half):
    """Sorted sample indices within ``half`` of every local minimum of ``gap`` whose value is
    within ``band`` of the smallest local minimum (every index when there is none): the only
    samples that can hold the minimum for small roll changes."""
    n = gap.size
    g = np.where(np.isfinite(gap), gap, np.inf)
    is_min = np.zeros(n, dtype=np.bool_)
    for i in range(1, n - 1):
        is_min[i] = g[i] < g[i - 1] and g[i] <= g[i + 1]
    if n > 1:
        is_min[0] = np.isfinite(g[0]) and g[0] < g[1]
        is_min[n - 1] = np.isfinite(g[n - 1]) and g[n - 1] < g[n - 2]
    if not is_min.any():
        return np.arange(n)
    gmin = np.inf
    for i in range(n):
        if is_min[i] and g[i] < gmin:
            gmin = g[i]
    keep = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        if is_min[i] and g[i] <= gmin + band:
            keep[max(i - half, 0):min(i + half, n - 1) + 1] = True
    return np.nonzero(keep)[0]


@njit(cache=True)
def brentq_h(xa, xb, xtol, rtol, maxiter, y, yaw, left, right, idx_l, idx_r, gap_l, gap_r):
    """Root of ``h`` on ``[xa, xb]`` on the samples ``idx_l``/``idx_r``: SciPy's ``brentq``
    (its C code step for step). Returns ``(x, calls, status)``: status 0 converged, 2 not
    converged in ``maxiter`` iterations, 3 ``h`` was NaN (SciPy raises for both)."""
    xpre, xcur = xa, xb
    xblk = fblk = spre = scur = 0.0
    fpre = h_of(y, yaw, xpre, left, right, idx_l, idx_r, gap_l, gap_r)
    if np.isnan(fpre):
        return xpre, 1, LOCAL_NAN
    fcur = h_of(y, yaw, xcur, left, right, idx_l, idx_r, gap_l, gap_r)
    calls = 2
    if np.isnan(fcur):
        return xcur, calls, LOCAL_NAN
    if fpre * fcur > 0:
        return 0.0, calls, LOCAL_NONE
    if fpre == 0:
        return xpre, calls, LOCAL_OK
    if fcur == 0:
        return xcur, calls, LOCAL_OK
    for _ in range(maxiter):
        if fpre * fcur < 0:
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur, calls, LOCAL_OK
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre, scur = scur, stry  # good short step
            else:
                spre = scur = sbis  # bisect
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = h_of(y, yaw, xcur, left, right, idx_l, idx_r, gap_l, gap_r)
        calls += 1
        if np.isnan(fcur):
            return xcur, calls, LOCAL_NAN
    return xcur, calls, LOCAL_NOCONV


@njit(cache=True)
def secant(roll0, lever, xtol, max_secant, y, yaw, left, right, idx_l, idx_r):
    """Secant iteration on ``h`` (samples ``idx_l``/``idx_r``) from ``roll0``; where it stops
    without converging, Brent's method on the first sign change among its points. Returns
    ``(roll, calls, status)``."""
    gl, gr = np.empty(idx_l.size), np.empty(idx_r.size)
    xs = np.empty(max_secant + 2)
    fs = np.empty(max_secant + 2)
    x0 = roll0
    f0 = h_of(y, yaw, x0, left, right, idx_l, idx_r, gl, gr)
    calls = 1
    if not np.isfinite(f0):
        return np.nan, calls, LOCAL_NONE
    x1 = x0 + f0 / (2.0 * lever)
    f1 = h_of(y, yaw, x1, left, right, idx_l, idx_r, gl, gr)
    calls += 1
    xs[0], fs[0], xs[1], fs[1] = x0, f0, x1, f1
    k = 2
    for _ in range(max_secant):
        if not np.isfinite(f1) or f1 == f0:
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
        x0, f0, x1 = x1, f1, x2
        f1 = h_of(y, yaw, x1, left, right, idx_l, idx_r, gl, gr)
        calls += 1
        xs[k], fs[k] = x1, f1
        k += 1
        if abs(x1 - x0) <= xtol or f1 == 0.0:
            return x1, calls, LOCAL_OK
    fin = np.isfinite(fs[:k])
    px, pf = xs[:k][fin], fs[:k][fin]
    order = np.argsort(px, kind="mergesort")
    px, pf = px[order], pf[order]
    for i in range(px.size - 1):
        if pf[i] * pf[i + 1] <= 0:
            x, c, status = brentq_h(px[i], px[i + 1], xtol, 4 * np.finfo(np.float64).eps,
                                    BRENTQ_ITER, y, yaw, left, right, idx_l, idx_r, gl, gr)
            return x, calls + c, status
    return np.nan, calls, LOCAL_NONE


@njit(cache=True)
def _no_locus():
    """A :func:`full_locus` result of no samples (the ``full`` of an unsuccessful
    :func:`local_root`)."""
    none = np.empty(0)
    return none, none, np.nan, -1, none, none, np.nan, -1


@njit(cache=True)
def local_root(y, yaw, xtol, max_secant, lever, left, right):
    """The rigid root near roll 0: :func:`secant` on the samples near the gap minima, checked
    on the whole profiles (solved again, at most three times, where the minimum moved: a
    contact jump). Returns ``(roll, calls, status, full)`` (:data:`LOCAL_OK` ...) with
    ``full`` the :func:`full_locus` of the whole profiles at ``roll`` when the status is
    :data:`LOCAL_OK` (the check computed it; the pose's result reuses it). A root whose check
    fails three times is :data:`LOCAL_NONE`: it is a root of the candidate samples only (a worn
    flange thinned by 1.5 mm, y = -0.9 mm, yaw 0.06 rad: 4.1 mm of height mismatch on the whole
    profiles there, stored as a converged root until 2026-11-25)."""
    all_l, all_r = np.arange(left[0].size), np.arange(right[0].size)
    gl, gr = np.empty(all_l.size), np.empty(all_r.size)
    calls = 1
    full = _no_locus()
    if not np.isfinite(h_of(y, yaw, 0.0, left, right, all_l, all_r, gl, gr)):
        return np.nan, calls, LOCAL_NONE, full
    roll = 0.0
    for _ in range(3):
        sub_l = candidates(gl, LOCAL_BAND, LOCAL_HALF)
        sub_r = candidates(gr, LOCAL_BAND, LOCAL_HALF)
        roll, c, status = secant(roll, lever, xtol, max_secant, y, yaw, left, right, sub_l,
                                 sub_r)
        calls += c
        if status != LOCAL_OK:
            return roll, calls, status, full
        pl, pr, _, _ = heights(y, yaw, roll, left, right, sub_l, sub_r, np.empty(sub_l.size),
                               np.empty(sub_r.size))
        # the whole profiles' heights at the root, with their loci (kept for the result)
        full = full_locus(y, yaw, roll, left, right)
        gl, fl, gr, fr = full[1], full[2], full[5], full[6]
        calls += 2
        if abs(pl - fl) <= LOCAL_CHECK and abs(pr - fr) <= LOCAL_CHECK:
            return roll, calls, LOCAL_OK, full
    # the whole profiles disagreed at every root (the minima moved each time: the iteration
    # jumps between contacts): no checked root, the scan decides
    return roll, calls, LOCAL_NONE, _no_locus()
