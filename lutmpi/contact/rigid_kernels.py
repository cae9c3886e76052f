"""Compiled kernels of the contact-locus solver (:mod:`lutmpi.contact.locus`): the vertical gaps
of one wheel's locus points to its rail and the touching height they give, the end circles, the
rigid contacts, the wheelset's rotation. The roll scan of ``h(roll) = z_left - z_right`` and
its searches are :mod:`lutmpi.contact.roll_scan`, the local solve near roll 0
:mod:`lutmpi.contact.local_root`.

Per-side arguments of the local solve (``left``, ``right``): ``(s, r, dr, d, tabz, lim)``: the
wheel's samples (profile coordinate, radius, slope), the tape-circle distance, the rail's height
table and ``lim = (u0, du, u_min, u_max)``; those of the roll scan add the coarse samples:
``(idx, s, r, dr, d, tabz, lim, s_c, r_c, dr_c)`` with ``idx`` their indices and ``s_c = s[idx]``
etc. (contiguous copies: the scan's loops then run over plain arrays, which the compiler
vectorises). The left side's sign is +1, the right side's -1.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from lutmpi.geometry.fused import body_to_track
from lutmpi.profiles.spline import ppoly_at

SCAN_BAND = 5e-3  # m, coarse gap minima this close to the smallest are refined on all samples
#: a locus gap minimum whose neighbouring samples lie more than this above it (or off the rail)
#: is resampled between them (:func:`resampled_min`), m
DIP_M = 1e-6
#: sub-intervals per sample interval of that resampling
DIP_SUB = 10
#: a discrete gap minimum other than the smallest is resampled too when its sample lies within
#: this of the smallest (a dip between samples can undercut it: 0.13 mm on a measured worn flange
#: tip at the end of a rail's data; a rail slope of tan 85 deg over the 0.4 mm that a yawed
#: flange's locus sweeps per sample bounds it by ~4.6 mm), m
DIP_BAND = SCAN_BAND
_NO_IDX = np.empty(0, dtype=np.int64)  # "the samples themselves" (:func:`lowest_gap`)
#: what :func:`run_gaps` resamples: nothing (the scan's coarse samples), the minima (the scan's
#: refinement windows), the minima and an unresolved smallest's neighbours (whole profiles)
COARSE, WINDOW, WHOLE = 0, 1, 2


# -- compiled gap loops -------------------------------------------------------------------------
@njit(cache=True)
def side_gaps(idx, sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max, gap, phis):
    """Vertical gaps (G at height 0) of the locus points ``idx`` of one wheel (side sign
    ``sgn``) to its rail, written into ``gap`` (and their locus angles into ``phis`` unless it
    is empty); returns the touching height (minus the parabolic minimum over the samples, -inf
    when no point is over the rail) and the index of the minimum within ``idx`` (-1 when
    none)."""
    keep_phi = phis.size > 0
    a, b, c = R[0, 0], R[0, 1], R[0, 2]
    amp = np.sqrt(a * a + c * c)
    beta = np.arctan2(c, a)
    if idx.size == s.size:  # every sample (sorted, unique: idx is arange): run_gaps' loops
        if keep_phi:
            bs = b * sgn
            for q in range(s.size):
                phis[q] = beta + np.arcsin(min(max(bs * dr[q] / amp, -1.0), 1.0))
        return run_gaps(sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max, gap,
                        np.empty(s.size), np.empty(s.size), WHOLE)
    sb, cb = c / amp, a / amp  # sin(beta), cos(beta)
    nt = tabz.size
    best, ib = np.inf, -1
    nmin, prev, down = 0, np.inf, False  # discrete minima so far (those of :func:`lowest_gap`)
    for q in range(idx.size):
        k = idx[q]
        x = b * sgn * dr[k] / amp
        x = min(max(x, -1.0), 1.0)
        rk = r[k]
        if keep_phi:
            phis[q] = beta + np.arcsin(x)
        # sin and cos of phi = beta + arcsin(x) by the angle-sum identity (run_gaps)
        cx = np.sqrt(1.0 - x * x)
        bx, by, bz = rk * (sb * cx + cb * x), sgn * (d + s[k]), -rk * (cb * cx - sb * x)
        py = R[1, 0] * bx + R[1, 1] * by + R[1, 2] * bz + y
        pz = R[2, 0] * bx + R[2, 1] * by + R[2, 2] * bz
        u = sgn * py
        g = np.inf
        if u >= u_min and u <= u_max:
            f = (u - u0) / du
            j = min(max(int(f), 0), nt - 2)
            t = f - j
            g = pz - (tabz[j] + t * (tabz[j + 1] - tabz[j]))
        gap[q] = g
        if g < best:
            best, ib = g, q
        if down and prev <= g:  # gap[q - 1] is a discrete minimum
            nmin += 1
        down, prev = g < prev, g
    val, ib, _ = lowest_gap(gap, idx, idx.size, ib, nmin + down > 1, sgn, s, r, dr, d, R, y, u0,
                            du, tabz, u_min, u_max, True)
    return -val, ib


@njit(cache=True)
def _locus_gap(sgn, s, r, dr, d, R, y, amp, sb, cb, bs, u0, du, tabz, u_min, u_max):
    """The vertical gap (G at height 0) of the locus point of one wheel circle (profile
    coordinate ``s``, radius ``r``, slope ``dr``), as :func:`run_gaps` computes it; +inf off the
    rail."""
    x = min(max(bs * dr / amp, -1.0), 1.0)
    cx = np.sqrt(1.0 - x * x)
    bx = r * (sb * cx + cb * x)
    by = sgn * (d + s)
    bz = -r * (cb * cx - sb * x)
    u = sgn * (R[1, 0] * bx + R[1, 1] * by + R[1, 2] * bz + y)
    if not (u >= u_min and u <= u_max):
        return np.inf
    pz = R[2, 0] * bx + R[2, 1] * by + R[2, 2] * bz
    nt = tabz.size
    f = (u - u0) / du
    j = min(max(int(f), 0), nt - 2)
    t = f - j
    return pz - (tabz[j] + t * (tabz[j + 1] - tabz[j]))


@njit(cache=True)
def resampled_min(k, gk, sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max):
    """The smallest gap of one wheel's locus next to its sample ``k`` (gap ``gk``, a discrete
    minimum), where the samples do not resolve it, and its profile coordinate (m); ``(NaN,
    NaN)`` where they do.

    A yawed flange on a steep gauge face sweeps the rail fast along the locus (its lateral
    position moves ~3.6 mm per mm of profile, the locus angle ~0.17 rad ahead of the axle): the
    gap then dips between two 0.1 mm samples, and the parabola through three samples missed the
    dip by up to 0.15 mm on measured worn pairs at yaw 0.05-0.1 rad (a wheel penetrating its rail
    at a "converged" rigid root, and the mirror pose choosing another root). Where a neighbour
    of ``k`` lies more than :data:`DIP_M` above ``gk`` or off the rail, the locus between the
    neighbours is resampled :data:`DIP_SUB` times per interval (radius and slope by cubic
    Hermite interpolation of the samples' own values and slopes), once more :data:`DIP_SUB`
    times finer between the sub-samples next to the smallest where they too lie more than
    :data:`DIP_M` above it, and the parabola is taken through the smallest of those and its
    neighbours. A well-resolved minimum (the tread, any contact where the neighbours lie within
    ``DIP_M``) is left to :func:`touch_height`. The coordinate is that of the smallest
    sub-sample plus the parabola's offset."""
    n = s.size
    if k <= 0 or k >= n - 1:
        return np.nan, np.nan
    a, b, c = R[0, 0], R[0, 1], R[0, 2]
    amp = np.sqrt(a * a + c * c)
    sb, cb = c / amp, a / amp
    bs = b * sgn
    gm = _locus_gap(sgn, s[k - 1], r[k - 1], dr[k - 1], d, R, y, amp, sb, cb, bs, u0, du,
                    tabz, u_min, u_max)
    gp = _locus_gap(sgn, s[k + 1], r[k + 1], dr[k + 1], d, R, y, amp, sb, cb, bs, u0, du,
                    tabz, u_min, u_max)
    if gm - gk <= DIP_M and gp - gk <= DIP_M:
        return np.nan, np.nan
    return _span_min(k - 1, 2, gm, gk, gp, sgn, s, r, dr, d, R, y, amp, sb, cb, bs, u0, du, tabz,
                     u_min, u_max)


@njit(cache=True)
def _span_min(i0, nint, g0, g1, g2, sgn, s, r, dr, d, R, y, amp, sb, cb, bs, u0, du, tabz,
              u_min, u_max):
    """The smallest gap of one wheel's locus over the ``nint`` (1 or 2) sample intervals from
    sample ``i0`` (whose gaps are ``g0, g1`` and, for two, ``g2``), resampled :data:`DIP_SUB`
    times per interval, once more :data:`DIP_SUB` times finer between the sub-samples next to
    the smallest where they lie more than :data:`DIP_M` above it, and the parabola through the
    smallest and its neighbours (:func:`resampled_min`); and its profile coordinate (m)."""
    m = DIP_SUB
    vals = np.empty(nint * m + 1)
    vals[0], vals[m] = g0, g1
    if nint == 2:
        vals[2 * m] = g2
    for half in range(nint):
        for q in range(1, m):
            vals[half * m + q] = _hermite_gap(i0 + half, q / m, sgn, s, r, dr, d, R, y, amp,
                                              sb, cb, bs, u0, du, tabz, u_min, u_max)
    nv = nint * m + 1
    ib = 0
    for q in range(1, nv):
        if vals[q] < vals[ib]:
            ib = q
    val, t = parabola_min(vals, ib, nv)
    if 0 < ib < nv - 1 and (vals[ib - 1] - vals[ib] > DIP_M or vals[ib + 1] - vals[ib] > DIP_M):
        # still not resolved (a dip sharper than 1 um over 10 um): once more between the
        # sub-samples next to the smallest, DIP_SUB times finer
        m2 = m * m
        v2 = np.empty(2 * m + 1)
        v2[0], v2[m], v2[2 * m] = vals[ib - 1], vals[ib], vals[ib + 1]
        for q in range(1, 2 * m):
            if q != m:
                x = (ib - 1) * m + q  # in 1/m2 of a sample interval from s[i0]
                v2[q] = _hermite_gap(i0 + x // m2, (x % m2) / m2, sgn, s, r, dr, d, R, y, amp,
                                     sb, cb, bs, u0, du, tabz, u_min, u_max)
        i2 = 0
        for q in range(1, 2 * m + 1):
            if v2[q] < v2[i2]:
                i2 = q
        val, t = parabola_min(v2, i2, 2 * m + 1)
        pos = ((ib - 1) * m + i2 + t) / m2
    else:
        pos = (ib + t) / m
    # its profile coordinate, in the sample interval it lies in (sample units from s[i0]; an
    # interval's end belongs to the interval below it)
    seg = min(max(int(np.ceil(pos)) - 1, 0), nint - 1)
    return val, s[i0 + seg] + (pos - seg) * (s[i0 + seg + 1] - s[i0 + seg])


@njit(cache=True, inline="always")
def _hermite_gap(i0, t, sgn, s, r, dr, d, R, y, amp, sb, cb, bs, u0, du, tabz, u_min, u_max):
    """:func:`_locus_gap` at ``t`` (0-1) of the sample interval from ``s[i0]``: radius and slope
    by cubic Hermite interpolation of the samples' own values and slopes."""
    s0, s1 = s[i0], s[i0 + 1]
    h = s1 - s0
    r0, r1, d0, d1 = r[i0], r[i0 + 1], dr[i0], dr[i0 + 1]
    t2 = t * t
    t3 = t2 * t
    rq = ((2 * t3 - 3 * t2 + 1) * r0 + (t3 - 2 * t2 + t) * h * d0
          + (-2 * t3 + 3 * t2) * r1 + (t3 - t2) * h * d1)
    dq = ((6 * t2 - 6 * t) * (r0 - r1) / h + (3 * t2 - 4 * t + 1) * d0
          + (3 * t2 - 2 * t) * d1)
    return _locus_gap(sgn, s0 + t * h, rq, dq, d, R, y, amp, sb, cb, bs, u0, du, tabz, u_min,
                      u_max)


@njit(cache=True, inline="always")
def lowest_gap(gap, idx, n, ib, others, sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max,
               neighbours):
    """The smallest gap of one wheel's locus from its sample gaps ``gap[:n]`` (of the samples
    ``idx``, or of ``s[:n]`` itself when ``idx`` is empty) and the index ``ib`` of the smallest:
    the parabola through it and its neighbours (:func:`touch_height`) or, where the samples do
    not resolve it, :func:`resampled_min`; and :func:`resampled_min` of every other discrete
    local minimum within :data:`DIP_BAND` of the smallest sample, which a dip between its
    samples can take below it (a yawed worn flange tip on the end of a rail's data: 0.13 mm).
    Returns ``(gap, index of the minimum it belongs to, its profile coordinate)``: ``+inf, -1,
    NaN`` when no point is over the rail; the coordinate is NaN where the samples' parabola
    gives the gap (the caller has it). ``others``: False when the smallest is the only discrete
    minimum (a sample below its left neighbour and not above its right one, non-finite gaps
    counting as +inf; the callers count them as they compute the gaps): none is looked for.
    ``neighbours``: also :func:`neighbour_dip` where the smallest is not resolved (the whole
    profiles' heights, whose roots are the poses; not the roll scan's windows, which only
    bracket them)."""
    if ib < 0:
        return np.inf, -1, np.nan
    k = idx[ib] if idx.size else ib
    best, sbest = resampled_min(k, gap[ib], sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max)
    q_best = ib
    j = -1
    if np.isnan(best):
        best = parabola_min(gap, ib, n)[0]
    elif neighbours:   # unresolved: a dip may lie next to a neighbour as low
        g2, s2, j = neighbour_dip(k, best, sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max)
    if j >= 0:
        best, sbest = g2, s2
        if idx.size == 0:
            q_best = j
        elif 0 <= ib + j - k < n and idx[ib + j - k] == j:
            q_best = ib + j - k
    limit = gap[ib] + DIP_BAND
    for q in range(n if others else 0):
        g = gap[q]
        if q == ib or not g <= limit or not _discrete_min(gap, q, n):
            continue
        g2, s2 = resampled_min(idx[q] if idx.size else q, g, sgn, s, r, dr, d, R, y, u0, du,
                               tabz, u_min, u_max)
        if g2 < best:
            best, sbest, q_best = g2, s2, q
    return best, q_best, sbest


@njit(cache=True)
def neighbour_dip(k, best, sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max):
    """The sample intervals beyond the two samples next to the smallest, ``k``, resampled
    (:func:`_span_min`) where the samples do not resolve its minimum (its own resampled gap,
    over the two intervals next to it, is ``best``): ``(gap, profile coordinate, index of the
    neighbour next to it)`` of the lower one when it lies below ``best``, else ``(inf, NaN,
    -1)``.

    Two neighbouring samples can be nearly equally low while a narrow dip lies on the far side
    of one of them: around the smallest alone, the dip is resampled only while that one is the
    smallest, and the touching height jumps by the dip's depth where the two swap. On a yawed
    worn flange against a gauge face (``Car7358_0001r.whl`` on the Manchester ``.ban`` rail,
    y = 5.5 mm, yaw 0.12 rad) it jumped by 89 um within 1e-9 rad of roll, and Brent's method
    stopped on that jump: a "converged" root with the wheels 29 um apart in height."""
    out, s_out, j_out = np.inf, np.nan, -1
    a, b, c = R[0, 0], R[0, 1], R[0, 2]
    amp = np.sqrt(a * a + c * c)
    sb, cb, bs = c / amp, a / amp, b * sgn
    for j, i0 in ((k - 1, k - 2), (k + 1, k + 1)):   # the interval beyond each neighbour
        if i0 < 0 or i0 + 1 > s.size - 1:
            continue
        ga = _locus_gap(sgn, s[i0], r[i0], dr[i0], d, R, y, amp, sb, cb, bs, u0, du, tabz,
                        u_min, u_max)
        gb = _locus_gap(sgn, s[i0 + 1], r[i0 + 1], dr[i0 + 1], d, R, y, amp, sb, cb, bs, u0,
                        du, tabz, u_min, u_max)
        g2, s2 = _span_min(i0, 1, ga, gb, np.nan, sgn, s, r, dr, d, R, y, amp, sb, cb, bs, u0,
                           du, tabz, u_min, u_max)
        if g2 < best and g2 < out:
            out, s_out, j_out = g2, s2, j
    return out, s_out, j_out


@njit(cache=True, inline="always")
def _discrete_min(gap, q, n):
    """True when ``gap[q]`` lies below its left neighbour and not above its right one (a
    non-finite neighbour, or none, counting as +inf)."""
    gl = gap[q - 1] if q > 0 and np.isfinite(gap[q - 1]) else np.inf
    gr = gap[q + 1] if q < n - 1 and np.isfinite(gap[q + 1]) else np.inf
    return gap[q] < gl and gap[q] <= gr


@njit(cache=True, inline="always")
def parabola_min(gap, ib, n):
    """Minimum of the parabola through ``gap[ib]`` and its neighbours (``gap[ib]`` itself at an
    end, next to a non-finite gap or where the parabola opens downward) and its offset from
    ``ib`` in samples (within +-0.5)."""
    val, t = gap[ib], 0.0
    if 0 < ib < n - 1:
        gm, gp = gap[ib - 1], gap[ib + 1]
        if np.isfinite(gm) and np.isfinite(gp):
            den = gm - 2.0 * val + gp
            if den > 0.0:
                t = 0.5 * (gm - gp) / den
                t = min(max(t, -0.5), 0.5)
                val = val - 0.25 * (gm - gp) * t
    return val, t


@njit(cache=True)
def touch_height(gap, ib, n):
    """The touching height from the gaps ``gap[:n]`` and the index ``ib`` of their smallest:
    minus the minimum of the parabola through it and its neighbours (-inf when ``ib < 0``)."""
    if ib < 0:
        return -np.inf, -1
    return -parabola_min(gap, ib, n)[0], ib


@njit(cache=True)
def run_gaps(sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max, gap, U, PZ, resample):
    """:func:`side_gaps` of the roll scan on contiguous samples ``s, r, dr`` (all of them), with
    ``sin`` and ``cos`` of the locus angle ``beta + arcsin(x)`` by the angle-sum identity (one
    square root instead of three transcendental functions; equal to rounding). The points come
    first in one loop of plain arithmetic (vectorised; ``U``, ``PZ``: scratch of their lateral
    coordinate and height), the rail's table and the minimum in a second. ``resample``:
    :data:`COARSE` (the scan's coarse samples: the parabola through the smallest),
    :data:`WINDOW` (the scan's refinement windows: :func:`lowest_gap`) or :data:`WHOLE` (a
    whole profile's samples: :func:`lowest_gap` with :func:`neighbour_dip`)."""
    a, b, c = R[0, 0], R[0, 1], R[0, 2]
    amp = np.sqrt(a * a + c * c)
    sb, cb = c / amp, a / amp  # sin(beta), cos(beta)
    r10, r11, r12, r20, r21, r22 = R[1, 0], R[1, 1], R[1, 2], R[2, 0], R[2, 1], R[2, 2]
    bs = b * sgn
    n = s.size
    for q in range(n):
        x = min(max(bs * dr[q] / amp, -1.0), 1.0)
        cx = np.sqrt(1.0 - x * x)
        bx = r[q] * (sb * cx + cb * x)
        by = sgn * (d + s[q])
        bz = -r[q] * (cb * cx - sb * x)
        U[q] = sgn * (r10 * bx + r11 * by + r12 * bz + y)
        PZ[q] = r20 * bx + r21 * by + r22 * bz
    nt = tabz.size
    best, ib = np.inf, -1
    nmin, prev, down = 0, np.inf, False  # discrete minima so far, as in side_gaps
    for q in range(n):
        u = U[q]
        g = np.inf
        if u >= u_min and u <= u_max:
            f = (u - u0) / du
            j = min(max(int(f), 0), nt - 2)
            t = f - j
            g = PZ[q] - (tabz[j] + t * (tabz[j + 1] - tabz[j]))
        gap[q] = g
        if g < best:
            best, ib = g, q
        if down and prev <= g:
            nmin += 1
        down, prev = g < prev, g
    if resample != COARSE:   # all samples (not the scan's coarse ones): the minima resampled
        val, ib, _ = lowest_gap(gap, _NO_IDX, n, ib, nmin + down > 1, sgn, s, r, dr, d, R, y,
                                u0, du, tabz, u_min, u_max, resample == WHOLE)
        return -val, ib
    return touch_height(gap, ib, n)


@njit(cache=True)
def full_locus(y, yaw, roll, left, right):
    """Both wheels' whole loci (every sample) at this roll: per side the locus angles ``phi``
    (rad), the vertical gaps (m, G at height 0, +inf where a point is not over the rail), the
    touching height and the index of the gap minimum (:func:`side_gaps`), left then right;
    ``left``/``right``: ``(s, r, dr, d, tabz, lim)``."""
    R = rotation(yaw, roll)
    s, r, dr, d, tab, lim = left
    phl, gpl = np.empty(s.size), np.empty(s.size)
    zl, il = side_gaps(np.arange(s.size), 1.0, s, r, dr, d, R, y, lim[0], lim[1], tab, lim[2],
                       lim[3], gpl, phl)
    s, r, dr, d, tab, lim = right
    phr, gpr = np.empty(s.size), np.empty(s.size)
    zr, ir = side_gaps(np.arange(s.size), -1.0, s, r, dr, d, R, y, lim[0], lim[1], tab, lim[2],
                       lim[3], gpr, phr)
    return phl, gpl, zl, il, phr, gpr, zr, ir


#: arc length (m) between the samples of an end circle's angle (:func:`end_circle_gap`)
END_ARC = 1e-3
#: golden-section steps refining an end circle's smallest sample (its bracket of two sample
#: steps shrinks to 0.618 ** 40 ~ 4e-9 of that: well below a nanometre of gap)
END_GOLDEN = 40


@njit(cache=True, inline="always")
def _circle_gap(phi, sgn, s, r, d, R, y, z_g, u0, du, tabz, u_min, u_max):
    """Vertical gap (m) of the point at angle ``phi`` of the wheel circle ``(s, r)`` (G at
    height ``z_g``) to the rail; +inf off the rail's data."""
    bx, by, bz = r * np.sin(phi), sgn * (d + s), -r * np.cos(phi)
    u = sgn * (R[1, 0] * bx + R[1, 1] * by + R[1, 2] * bz + y)
    if not (u >= u_min and u <= u_max):
        return np.inf
    f = (u - u0) / du
    j = min(max(int(f), 0), tabz.size - 2)
    t = f - j
    return (R[2, 0] * bx + R[2, 1] * by + R[2, 2] * bz + z_g
            - (tabz[j] + t * (tabz[j + 1] - tabz[j])))


@njit(cache=True)
def end_circle_gap(sgn, s, r, d, R, y, z_g, u0, du, tabz, u_min, u_max, zmax):
    """Smallest vertical gap (m) over the whole circle ``(s, r)`` of one wheel (G at height
    ``z_g``) to its rail, and its angle (rad): ``(+inf, NaN)`` where no point of the circle is
    below the rail's highest point ``zmax`` over its data.

    The contact locus holds the one point of each circle where the wheel's surface can touch
    an extruded rail (its normal has no component along x); the circle at the end of a wheel's
    data is the surface's edge, which can touch the rail anywhere on it. With ``phi = 0`` the
    circle's lowest point, ``p_z = z_g + sin(roll) b_y - cos(roll) r cos(phi)``, so only
    ``cos(phi) >= c0`` can reach down to ``zmax``; where that arc's lateral reach meets the
    rail's data, it is sampled every :data:`END_ARC` of length and its smallest sample
    refined by golden section (:data:`END_GOLDEN` steps)."""
    by = sgn * (d + s)
    c0 = (z_g + R[2, 1] * by - zmax) / (R[2, 2] * r)
    if c0 > 1.0:
        return np.inf, np.nan
    half = np.arccos(max(c0, -1.0))
    # u = sgn (y + R11 b_y + r (R10 sin(phi) - R12 cos(phi))): the arc's lateral reach
    uc = sgn * (y + R[1, 1] * by)
    reach = r * (abs(R[1, 0]) * np.sin(min(half, 0.5 * np.pi)) + abs(R[1, 2]))
    if uc + reach < u_min or uc - reach > u_max:
        return np.inf, np.nan
    n = int(np.ceil(2.0 * half * r / END_ARC)) + 1
    step = 2.0 * half / (n - 1) if n > 1 else 0.0
    best, qb = np.inf, -1
    for q in range(n):
        g = _circle_gap(-half + q * step, sgn, s, r, d, R, y, z_g, u0, du, tabz, u_min, u_max)
        if g < best:
            best, qb = g, q
    if qb < 0:
        return np.inf, np.nan
    a, b = -half + max(qb - 1, 0) * step, -half + min(qb + 1, n - 1) * step
    phib = -half + qb * step
    k = 0.5 * (np.sqrt(5.0) - 1.0)
    x1, x2 = b - k * (b - a), a + k * (b - a)
    f1 = _circle_gap(x1, sgn, s, r, d, R, y, z_g, u0, du, tabz, u_min, u_max)
    f2 = _circle_gap(x2, sgn, s, r, d, R, y, z_g, u0, du, tabz, u_min, u_max)
    for _ in range(END_GOLDEN):
        if f1 <= f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - k * (b - a)
            f1 = _circle_gap(x1, sgn, s, r, d, R, y, z_g, u0, du, tabz, u_min, u_max)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + k * (b - a)
            f2 = _circle_gap(x2, sgn, s, r, d, R, y, z_g, u0, du, tabz, u_min, u_max)
    for x, f in ((x1, f1), (x2, f2)):
        if f < best:
            best, phib = f, x
    return best, phib


@njit(cache=True)
def rim_gaps(y, yaw, roll, z_g, left, right, ends):
    """:func:`end_circle_gap` of both end circles of both wheels in one call: ``ends[k, e]``
    ``(s, r, zmax)`` of side ``k`` (left, right) and end ``e``; ``left``/``right`` as
    :func:`full_locus`'s. Returns ``out[k, e] = (gap, phi)``."""
    R = rotation(yaw, roll)
    out = np.empty((2, 2, 2))
    for k in range(2):
        s, r, dr, d, tab, lim = left if k == 0 else right
        sgn = 1.0 if k == 0 else -1.0
        for e in range(2):
            out[k, e, 0], out[k, e, 1] = end_circle_gap(
                sgn, ends[k, e, 0], ends[k, e, 1], d, R, y, z_g, lim[0], lim[1], tab, lim[2],
                lim[3], ends[k, e, 2])
    return out


@njit(cache=True)
def contact_minima(gap, double_tol, max_contacts):
    """Sample indices of the contact(s) of one wheel's locus gaps ``gap`` (m): the global
    minimum, then each further discrete local minimum (by increasing gap, ties by index) whose
    gap is within ``double_tol`` of it and that is separated from every chosen one by a gap
    maximum 0.1 µm above it, at most ``max_contacts`` in all. A local minimum is a finite
    sample below its left neighbour and not above its right one, or an end sample below its
    neighbour (non-finite gaps count as +inf)."""
    n = gap.size
    mins = np.empty(n, dtype=np.int64)
    nm = 0
    if n >= 2 and np.isfinite(gap[0]) and gap[0] < (gap[1] if np.isfinite(gap[1]) else np.inf):
        mins[nm] = 0
        nm += 1
    for i in range(1, n - 1):
        gi = gap[i] if np.isfinite(gap[i]) else np.inf
        gm = gap[i - 1] if np.isfinite(gap[i - 1]) else np.inf
        gp = gap[i + 1] if np.isfinite(gap[i + 1]) else np.inf
        if gi < gm and gi <= gp:
            mins[nm] = i
            nm += 1
    if n >= 2 and np.isfinite(gap[n - 1]) and gap[n - 1] < (
            gap[n - 2] if np.isfinite(gap[n - 2]) else np.inf):
        mins[nm] = n - 1
        nm += 1
    out = np.empty(max(min(max_contacts, nm), 0), dtype=np.int64)
    if nm == 0 or out.size == 0:
        return out[:0]
    mins = mins[:nm]
    order = mins[np.argsort(gap[mins], kind="mergesort")]
    out[0] = order[0]
    k = 1
    g0 = gap[order[0]]
    for q in range(1, nm):
        i = order[q]
        if k >= max_contacts or gap[i] - g0 > double_tol:
            break
        ok = True
        for c in range(k):
            j = out[c]
            top, nan = -np.inf, False
            for t in range(min(i, j), max(i, j) + 1):
                if np.isnan(gap[t]):
                    nan = True
                elif gap[t] > top:
                    top = gap[t]
            if nan or not top > gap[i] + 1e-7:
                ok = False
                break
        if ok:
            out[k] = i
            k += 1
    return out[:k]


@njit(cache=True)
def scan_side_info(sgn, side, R, y, gap, fine, U, PZ):
    """Touching height of one wheel from its coarse samples, refined on every sample within one
    coarse step of each coarse local minimum less than :data:`SCAN_BAND` above the smallest and
    of each coarse sample next to the end of the data (a narrow minimum, e.g. a yawed flange
    flank on the last points of a rail, falls between coarse samples: up to 3 mm of gap on the
    measured profiles, and 29 mm on a worn wheel at the end of a measured rail's data, whose
    coarse sample lay 26 mm above the smallest: no band bounds it); -inf when no point is over
    the rail. Returns ``(z, z_c, ib, u)``: the height, minus the smallest coarse sample's own
    gap (``z >= z_c``: the refinement only raises it), that sample's index among the coarse
    ones (-1 when none) and its lateral rail coordinate (m), which
    :func:`~lutmpi.contact.roll_scan.local_slope_bound` bounds the scan's steps by."""
    idx, s, r, dr, d, tab, lim, s_c, r_c, dr_c, wr, zhi, zlo = side
    h, ib = run_gaps(sgn, s_c, r_c, dr_c, d, R, y, lim[0], lim[1], tab, lim[2], lim[3], gap, U,
                     PZ, COARSE)
    if ib < 0:
        return h, h, ib, np.nan
    u_ib = U[ib]
    # the smallest coarse sample's own gap, not the parabola through it and its neighbours:
    # 1 mm apart on a worn flange's corner the parabola dips 7 mm below every sample, and the
    # refined runs below can only raise the height (a worn flange thinned by 1.5 mm, y = -1 mm,
    # yaw 0.06 rad: the scan's h 8 mm off, the pose's roots missed: a no_contact hole). The run
    # around this sample is always refined (first: the others are then bounded against it), so
    # the height is the samples' own
    step = idx[1] - idx[0] if idx.size > 1 else 1
    lo, hi = max(idx[ib] - step, 0), min(idx[ib] + step + 1, s.size)
    h2, _ = run_gaps(sgn, s[lo:hi], r[lo:hi], dr[lo:hi], d, R, y, lim[0], lim[1], tab, lim[2],
                     lim[3], fine, U, PZ, WINDOW)
    h = max(-gap[ib], h2)
    limit = gap[ib] + SCAN_BAND
    n = idx.size
    sb, cb, f = floor_terms(sgn, R)
    for q in range(n):
        g = gap[q]
        if q == ib or not np.isfinite(g):
            continue
        edge = q == 0 or q == n - 1 or not (np.isfinite(gap[q - 1]) and np.isfinite(gap[q + 1]))
        if not edge:  # the end of the data (a knife edge) is always refined
            if g > limit or gap[q - 1] < g or gap[q + 1] < g:
                continue  # not a coarse local minimum near the smallest
        # a window whose every gap (and every parabola through them) lies above the height's
        # gap cannot raise the height (the maximum of the windows' heights, whatever their
        # order): not refined (issue 14; the same bits, ~3 us of a scan point's ~9 on the paper's
        # pair, where both wheels' two ends were refined at every point)
        if window_floor(sgn, wr[q], d, R, y, lim, tab, zhi, zlo, sb, cb, f) > FLOOR_EPS - h:
            continue
        lo, hi = max(idx[q] - step, 0), min(idx[q] + step + 1, s.size)
        h2, _ = run_gaps(sgn, s[lo:hi], r[lo:hi], dr[lo:hi], d, R, y, lim[0], lim[1], tab,
                         lim[2], lim[3], fine, U, PZ, WINDOW)
        h = max(h, h2)
    return h, -gap[ib], ib, u_ib


#: m: rounding allowance of :func:`window_floor`'s bound (the gaps are sums of terms of ~0.5 m,
#: exact to ~1e-15 m)
FLOOR_EPS = 1e-9


def window_ranges(idx: np.ndarray, s: np.ndarray, r: np.ndarray, dr: np.ndarray) -> np.ndarray:
    """Per coarse sample ``idx[q]`` of the roll scan, what :func:`window_floor` bounds its
    refinement window's gaps by: ``(s_lo, s_hi, r_lo, r_hi, dr_lo, dr_hi)`` (m, m, -) over the
    window's samples ``s[lo:hi]`` (:func:`scan_side_info`'s ``lo, hi``) and every point between
    two of them that the resampling evaluates (:func:`_span_min`: ``1 / DIP_SUB**2`` of an
    interval apart; radius and slope by :func:`_hermite_gap`'s cubic Hermite interpolation,
    which can overshoot the samples). Pose-independent: once per wheel. Returns shape
    ``(idx.size, 6)``."""
    step = int(idx[1] - idx[0]) if idx.size > 1 else 1
    m2 = DIP_SUB * DIP_SUB
    t = np.arange(m2 + 1) / m2
    t2, t3 = t * t, t * t * t
    h = np.diff(s)[:, None]
    r0, r1, d0, d1 = r[:-1, None], r[1:, None], dr[:-1, None], dr[1:, None]
    rq = ((2 * t3 - 3 * t2 + 1) * r0 + (t3 - 2 * t2 + t) * h * d0
          + (-2 * t3 + 3 * t2) * r1 + (t3 - t2) * h * d1)
    dq = ((6 * t2 - 6 * t) * (r0 - r1) / h + (3 * t2 - 4 * t + 1) * d0
          + (3 * t2 - 2 * t) * d1)
    out = np.empty((idx.size, 6))
    for q, k in enumerate(idx):
        lo, hi = max(k - step, 0), min(k + step + 1, s.size)
        rr, dd = r[lo:hi], dr[lo:hi]
        if hi - lo > 1:
            rr = np.concatenate([rr, rq[lo:hi - 1].ravel()])
            dd = np.concatenate([dd, dq[lo:hi - 1].ravel()])
        out[q] = s[lo], s[hi - 1], rr.min(), rr.max(), dd.min(), dd.max()
    return out


def extreme_tables(tabz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sparse tables of range maxima and minima of a rail height table's nodes (row ``k``: over
    ``2 ** k`` nodes from each node, padded with the node's own value), for
    :func:`window_floor`."""
    n = tabz.size
    levels = max(int(n).bit_length(), 1)
    hi, lo = np.empty((levels, n)), np.empty((levels, n))
    hi[0], lo[0] = tabz, tabz
    for k in range(1, levels):
        w = 1 << (k - 1)
        hi[k], lo[k] = hi[k - 1], lo[k - 1]
        hi[k, :n - w] = np.maximum(hi[k - 1, :n - w], hi[k - 1, w:])
        lo[k, :n - w] = np.minimum(lo[k - 1, :n - w], lo[k - 1, w:])
    return hi, lo


@njit(cache=True, inline="always")
def _range_extreme(st, j0, j1, top):
    """The largest (``top``) or smallest node of ``j0 ... j1`` from :func:`extreme_tables`."""
    k = 0
    while (2 << k) <= j1 - j0 + 1:
        k += 1
    a, b = st[k, j0], st[k, j1 - (1 << k) + 1]
    return max(a, b) if top else min(a, b)


@njit(cache=True, inline="always")
def _product(a_lo, a_hi, b_lo, b_hi):
    """The interval ``[a_lo, a_hi] * [b_lo, b_hi]``."""
    p, q, r, t = a_lo * b_lo, a_lo * b_hi, a_hi * b_lo, a_hi * b_hi
    return min(min(p, q), min(r, t)), max(max(p, q), max(r, t))


@njit(cache=True, inline="always")
def floor_terms(sgn, R):
    """What :func:`window_floor` takes of the rotation ``R`` (once per wheel and roll): the sine
    and cosine of :func:`run_gaps`' angle ``beta`` and the factor of a slope in the ``arcsin``'s
    argument."""
    a, b, c = R[0, 0], R[0, 1], R[0, 2]
    amp = np.sqrt(a * a + c * c)
    return c / amp, a / amp, b * sgn / amp


@njit(cache=True, inline="always")
def _linear(e0, e1, e2, x_lo, x_hi, y_lo, y_hi, z_lo, z_hi):
    """The interval ``e0 x + e1 y + e2 z`` over the box ``x, y, z``."""
    lo = min(e0 * x_lo, e0 * x_hi) + min(e1 * y_lo, e1 * y_hi) + min(e2 * z_lo, e2 * z_hi)
    hi = max(e0 * x_lo, e0 * x_hi) + max(e1 * y_lo, e1 * y_hi) + max(e2 * z_lo, e2 * z_hi)
    return lo, hi


@njit(cache=True)
def window_floor(sgn, w, d, R, y, lim, tab, zhi, zlo, sb, cb, f):
    """A lower bound (m) of the touching gap a roll scan refinement window can give (what
    :func:`run_gaps` with :data:`WINDOW` returns, negated), from its ranges ``w``
    (:func:`window_ranges`): interval arithmetic on :func:`_locus_gap`'s point (profile
    coordinate, radius and slope within their ranges, the locus angle within the range its
    ``arcsin`` gives; ``d``: the tape-circle distance), the rail's highest node under the lateral
    range it can reach (``zhi, zlo``: :func:`extreme_tables` of the height table ``tab``),
    less the most a parabola through three gaps of that range dips below the smallest
    (:func:`parabola_min`: an eighth of the range). ``+inf`` where no point of the window can be
    over the rail, ``-inf`` where the range leaves the table by more than a cell. ``sb, cb, f``:
    the pose's :func:`floor_terms`."""
    s_lo, s_hi, r_lo, r_hi, dr_lo, dr_hi = w[0], w[1], w[2], w[3], w[4], w[5]
    x0, x1 = min(max(f * dr_lo, -1.0), 1.0), min(max(f * dr_hi, -1.0), 1.0)
    x0, x1 = min(x0, x1), max(x0, x1)
    # sin and cos of the locus angle beta + arcsin(x), x in [x0, x1] (increasing in x): at the
    # ends by run_gaps' identity, and their extremes inside (sin = +-1 at x = +-cb where
    # beta is of that sign, cos = 1 at x = -sb), widened by rounding's allowance
    c0, c1 = np.sqrt(1.0 - x0 * x0), np.sqrt(1.0 - x1 * x1)
    sn0, sn1 = sb * c0 + cb * x0, sb * c1 + cb * x1
    cs0, cs1 = cb * c0 - sb * x0, cb * c1 - sb * x1
    sn_lo, sn_hi = min(sn0, sn1) - 1e-12, max(sn0, sn1) + 1e-12
    cs_lo, cs_hi = min(cs0, cs1) - 1e-12, max(cs0, cs1) + 1e-12
    if sb >= 0.0 and x0 <= cb <= x1:
        sn_hi = 1.0
    if sb <= 0.0 and x0 <= -cb <= x1:
        sn_lo = -1.0
    if x0 <= -sb <= x1:
        cs_hi = 1.0
    bx_lo, bx_hi = _product(r_lo, r_hi, sn_lo, sn_hi)
    nz_lo, nz_hi = _product(r_lo, r_hi, cs_lo, cs_hi)   # -bz
    by0, by1 = sgn * (d + s_lo), sgn * (d + s_hi)
    by_lo, by_hi = min(by0, by1), max(by0, by1)
    bz_lo, bz_hi = -nz_hi, -nz_lo
    u_lo, u_hi = _linear(R[1, 0], R[1, 1], R[1, 2], bx_lo, bx_hi, by_lo, by_hi, bz_lo, bz_hi)
    u_lo, u_hi = u_lo + y, u_hi + y
    pz_lo, pz_hi = _linear(R[2, 0], R[2, 1], R[2, 2], bx_lo, bx_hi, by_lo, by_hi, bz_lo, bz_hi)
    u_lo, u_hi = min(sgn * u_lo, sgn * u_hi), max(sgn * u_lo, sgn * u_hi)
    u0, du, u_min, u_max = lim[0], lim[1], lim[2], lim[3]
    u_lo, u_hi = max(u_lo, u_min), min(u_hi, u_max)
    if not u_lo <= u_hi:
        return np.inf       # every point off the rail: the window's gaps are all +inf
    nt = tab.size
    # a point past the table's end nodes (u_max lies ~1e-13 m past the last one) extrapolates
    # the end cell: by at most this over the nodes' extremes
    over = max(u0 - u_lo, u_hi - (u0 + (nt - 1) * du)) / du
    if over > 1.0:
        return -np.inf
    ext = max(over, 0.0) * max(abs(tab[1] - tab[0]), abs(tab[nt - 1] - tab[nt - 2]))
    j0 = min(max(int((u_lo - u0) / du), 0), nt - 2)
    j1 = min(max(int((u_hi - u0) / du), 0), nt - 2) + 1
    lb = pz_lo - _range_extreme(zhi, j0, j1, True) - ext
    ub = pz_hi - _range_extreme(zlo, j0, j1, False) + ext
    return lb - 0.125 * (ub - lb)


@njit(cache=True)
def dip_minima(gap, sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max):
    """The whole locus's gaps ``gap`` (G at height 0) with every discrete minimum that
    :func:`lowest_gap` resamples (the smallest, its neighbours where :func:`neighbour_dip`
    finds a lower gap, and the minima within :data:`DIP_BAND` of it) set to
    its resampled gap where the samples do not resolve it, and those minima's profile
    coordinates (NaN elsewhere): what :func:`rigid_contacts` chooses and places the contacts
    by. Returns ``(gaps, s_fix)``."""
    n = gap.size
    out, s_fix = gap.copy(), np.full(n, np.nan)
    best, ib = np.inf, -1
    for q in range(n):
        if gap[q] < best:
            best, ib = gap[q], q
    if ib < 0:
        return out, s_fix
    limit = best + DIP_BAND
    for q in range(n):
        g = gap[q]
        if not g <= limit or (q != ib and not _discrete_min(gap, q, n)):
            continue
        g2, s2 = resampled_min(q, g, sgn, s, r, dr, d, R, y, u0, du, tabz, u_min, u_max)
        if not np.isnan(g2):
            out[q], s_fix[q] = g2, s2
    # an unresolved smallest's neighbours, as lowest_gap resamples them (neighbour_dip)
    if np.isfinite(s_fix[ib]):
        g2, s2, j = neighbour_dip(ib, out[ib], sgn, s, r, dr, d, R, y, u0, du, tabz, u_min,
                                  u_max)
        if j >= 0:
            out[j], s_fix[j] = g2, s2
    return out, s_fix


@njit(cache=True)
def rigid_contacts(gap, s, sgn, d, r0, pp, y, yaw, roll, z_g, double_tol, max_contacts,
                   s_fix):
    """The rigid contacts of one wheel (side sign ``sgn``) at the converged pose from its
    locus gaps ``gap`` (m, lifted to G at ``z_g``) on the samples ``s``: the gap minima of
    :func:`contact_minima`, each refined by the parabola through its neighbours (offset within
    half a sample) or, where ``s_fix`` is finite (:func:`dip_minima`: the samples do not
    resolve the minimum), placed at ``s_fix``, and the wheel point there on the profile ``pp``
    (``(c, x, c1, x1)`` of :attr:`lutmpi.profiles.model.Profile.ppolys`; radius ``r0`` +
    spline, m) at its locus angle.

    Returns
    -------
    ndarray, shape (n, 8)
        Per contact: profile coordinate ``s`` (m), locus angle ``phi`` (rad), track-frame point
        ``x, y, z`` (m), rail coordinate ``u = sgn y`` (m), gap (m) and ``at_end`` (1.0 when the
        minimum is a first or last usable sample, or next to one not over the rail).
    """
    zc, zx, dc, dx = pp
    idx = contact_minima(gap, double_tol, max_contacts)
    R = rotation(yaw, roll)
    a, b, c = R[0, 0], R[0, 1], R[0, 2]
    amp = np.hypot(a, c)
    beta = np.arctan2(c, a)
    n = gap.size
    ds = s[1] - s[0]
    out = np.empty((idx.size, 8))
    for q in range(idx.size):
        i = idx[q]
        t, g = 0.0, gap[i]
        inner = 0 < i < n - 1
        if inner and np.isfinite(gap[i - 1] + gap[i + 1]):
            gm, g0, gp = gap[i - 1], gap[i], gap[i + 1]
            den = gm - 2.0 * g0 + gp
            if den > 0.0:
                t = min(max(0.5 * (gm - gp) / den, -0.5), 0.5)
                g = g0 - 0.25 * (gm - gp) * t
        sv = s[i] + t * ds
        if np.isfinite(s_fix[i]):   # resampled: the gap array holds its minimum already
            sv, g = s_fix[i], gap[i]
        r = r0 + ppoly_at(zc, zx, sv)
        x = b * (sgn * ppoly_at(dc, dx, sv)) / amp
        phi = beta + np.arcsin(min(max(x, -1.0), 1.0))
        px, py, pz = body_to_track(R, r * np.sin(phi), sgn * (d + sv), -r * np.cos(phi),
                                   0.0, y, z_g)
        end = not (inner and np.isfinite(gap[i - 1]) and np.isfinite(gap[i + 1]))
        out[q, 0], out[q, 1], out[q, 2], out[q, 3], out[q, 4] = sv, phi, px, py, pz
        out[q, 5], out[q, 6], out[q, 7] = sgn * py, g, 1.0 if end else 0.0
    return out


@njit(cache=True)
def rotation(yaw, roll):
    """``R = Rz(yaw) Rx(roll)`` (pitch 0), shape (3, 3) in closed form: the bits of
    :func:`lutmpi.geometry.pose.wheelset_rotation`'s matrix products, signed zeros included
    (``+ 0.0`` turns a product's signed zero into the sum's), at a fraction of their cost; the
    one rotation of the pose solve (tested)."""
    cy, sy, cr, sr = np.cos(yaw), np.sin(yaw), np.cos(roll), np.sin(roll)
    R = np.empty((3, 3))
    R[0, 0], R[0, 1], R[0, 2] = cy, -sy * cr + 0.0, sy * sr + 0.0
    R[1, 0], R[1, 1], R[1, 2] = sy + 0.0, cy * cr, -cy * sr + 0.0
    R[2, 0], R[2, 1], R[2, 2] = 0.0, sr + 0.0, cr
    return R

