"""The compiled evaluation of a table's jump-aware interpolant (:mod:`lutmpi.table.interp`, whose
docstring gives the representation and the rules): a query's piece in each neighbouring yaw
column, its jump curves, the column values along y and their blend along yaw. Pure: numba.
"""

from __future__ import annotations

import numba
import numpy as np

#: a column whose piece would be extended by more than this many grid steps of y beyond its end
#: knots to reach a query between columns does not answer it for the quantities that jump (the
#: other column alone does; an outer column gives no slope)
EXTEND_STEPS = 0.1
#: a piece narrower than this many grid steps of y (in a column, or between the jump curves at
#: the query's yaw) is read at the query's y, not at its distance from the jumps
#: (:func:`_warp`): the load centre's second contact comes and goes several times within a
#: grid step, and which jumps of two columns' clusters pair up is arbitrary
NARROW_STEPS = 0.25
#: the reach of :func:`_warp` beside a jump, in grid steps of y
WARP_STEPS = 1.0
#: an outer yaw column whose piece does not correspond still gives the quantities that do not
#: jump their cubic in yaw where it and the two inner columns hold no jump within this many grid
#: steps of y of the query (:func:`lookup_one`)
OUTER_STEPS = 1.0
#: a query this close to a knot or a yaw column (a fraction of the interval) is read on it:
#: the yaw 0.05 typed by a user lies 4e-16 below the grid's 0.05000000000000002, in the cell
#: below with a weight of 1e-16 on the column beyond, whose NaN (a failed pose, a second
#: contact that column does not have) then made the whole answer NaN
SNAP = 1e-9


@numba.njit(cache=True)
def _piece_eval(ky, kv, kd, mode, j, s, e, y, w, out_v, out_d, acc):  # noqa: ANN001
    """Add ``w`` times piece ``[s, e)`` of column ``j`` at ``y`` to ``out_v`` / ``out_d``
    (``acc`` False: overwrite). Linear extension beyond the piece's end knots. The interval's
    basis weights are computed once and shared by every value column."""
    q = kv.shape[2]
    if e - s == 1:
        for c in range(q):
            v = kv[j, s, c]
            out_v[c] = w * v + (out_v[c] if acc else 0.0)
            out_d[c] = out_d[c] if acc else 0.0
        return
    lo, hi = s, e - 1          # find k in [s, e-2] with ky[k] <= y < ky[k+1]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ky[j, mid] <= y:
            lo = mid
        else:
            hi = mid
    k = lo
    y0, y1 = ky[j, k], ky[j, k + 1]
    h = y1 - y0
    t = (y - y0) / h
    if abs(t) <= SNAP:                                  # on the knot (:data:`SNAP`)
        t = 0.0
    elif abs(t - 1.0) <= SNAP:
        t = 1.0
    inside = 0.0 < t < 1.0
    # cubic Hermite basis (values) and its derivative / h (slopes), shared by all columns
    t2 = t * t
    t3 = t2 * t
    b00, b10 = 2 * t3 - 3 * t2 + 1, (t3 - 2 * t2 + t) * h
    b01, b11 = -2 * t3 + 3 * t2, (t3 - t2) * h
    g00, g10 = (6 * t2 - 6 * t) / h, 3 * t2 - 4 * t + 1
    g01, g11 = (-6 * t2 + 6 * t) / h, 3 * t2 - 2 * t
    near_first = t < 0.5
    for c in range(q):
        v0, v1 = kv[j, k, c], kv[j, k + 1, c]
        m = mode[c]
        if m == 2:                                      # nearest
            v = v0 if near_first else v1
            d = 0.0
        elif t == 0.0:                                  # on a knot: its value alone
            v = v0
            d = (v1 - v0) / h if m == 0 else kd[j, k, c]
        elif t == 1.0:
            v = v1
            d = (v1 - v0) / h if m == 0 else kd[j, k + 1, c]
        elif m == 0:                                    # linear (also extends the piece)
            d = (v1 - v0) / h
            v = v0 + t * (v1 - v0)
        elif inside:                                    # pchip: cubic Hermite
            d0, d1 = kd[j, k, c], kd[j, k + 1, c]
            v = b00 * v0 + b10 * d0 + b01 * v1 + b11 * d1
            d = g00 * v0 + g10 * d0 + g01 * v1 + g11 * d1
        elif t < 0.0:                                   # pchip extended beyond the piece
            d = kd[j, k, c]
            v = v0 + d * (y - y0)
        else:
            d = kd[j, k + 1, c]
            v = v1 + d * (y - y1)
        if acc:
            out_v[c] += w * v
            out_d[c] += w * d
        else:
            out_v[c] = w * v
            out_d[c] = w * d


@numba.njit(cache=True)
def match_slots(tmp_v, tmp_d, r, ref, slot_pair, slot_wheel, slot_s):  # noqa: ANN001
    """Reorder row ``r``'s first two contacts of each wheel (values ``tmp_v``, slopes
    ``tmp_d``) to match row ``ref``'s, where the two hold two contacts each and the crossed
    pairing lies nearer along the wheel profile (``wheel_s``) than the slot by slot one: a
    column orders its contacts by force (the reference method: the solver's order), and two
    columns can order one double contact differently (:func:`lutmpi.table.interp.
    slot_matching`). Rows that agree are left as they are, to the bit."""
    for wh in range(slot_s.shape[0]):
        i0, i1 = slot_s[wh, 0], slot_s[wh, 1]
        if i0 < 0:
            return
        a0, a1, b0, b1 = tmp_v[r, i0], tmp_v[r, i1], tmp_v[ref, i0], tmp_v[ref, i1]
        if not (np.isfinite(a0) and np.isfinite(a1) and np.isfinite(b0) and np.isfinite(b1)):
            continue
        if abs(a0 - b1) + abs(a1 - b0) < abs(a0 - b0) + abs(a1 - b1):
            for c in range(slot_pair.size):
                if slot_wheel[c] == wh:
                    o = slot_pair[c]
                    tmp_v[r, c], tmp_v[r, o] = tmp_v[r, o], tmp_v[r, c]
                    tmp_d[r, c], tmp_d[r, o] = tmp_d[r, o], tmp_d[r, c]


@numba.njit(cache=True)
def _piece_of(jy, nj, j, y):  # noqa: ANN001
    p = 0
    for k in range(nj[j]):
        if jy[j, k] <= y:
            p += 1
    return p


@numba.njit(cache=True)
def _unpaired_below(jy, nj, pair, c, y, below, above):  # noqa: ANN001
    """How many of column ``c``'s unpaired jumps (``pair`` < 0) lie below the query at ``y``:
    those below its paired jump of index ``below`` that the jump curves put below ``y``, none
    above the paired one of index ``above`` put above it, the others by their own position. By
    position alone an unpaired jump between ``y`` and a paired one the curves put below it
    counted as above, and the column was read in a piece both jumps bound it away from (the
    paper's pair at yaw 0.027 rad, a load centre's flickering second contact at y = 6.154 and
    6.158 mm before the main contact's jump at 6.162: at yaw 0.03, y = 6.15, that column read
    on the tread past the flange jump, the rolling radius 6.5 mm off)."""
    n = 0
    for k in range(nj[c]):
        if pair[c, k] >= 0:
            continue
        if k < below or (k < above and jy[c, k] <= y):
            n += 1
    return n


@numba.njit(cache=True)
def _gap_to_jumps(jy, nj, c, y):  # noqa: ANN001
    """Distance (m) from ``y`` to column ``c``'s nearest jump (inf: none)."""
    out = np.inf
    for k in range(nj[c]):
        out = min(out, abs(y - jy[c, k]))
    return out


@numba.njit(cache=True)
def _jump_at(jy, up, down, j, k, m, w):  # noqa: ANN001
    """Position (m) of the jump curve through jump ``k`` of column ``j`` and its partner ``m``
    of column j + 1, a fraction ``w`` of the way between them: a cubic in yaw (Catmull-Rom,
    through the partners in columns j - 1 and j + 2 where paired, else one-sided; the secant
    where neither is). A jump curve bends with yaw (evenly about yaw 0); on a coarse yaw grid a
    straight line between two columns misses it by tenths of a millimetre, the width of the
    steep onset next to a flange jump. Computed once per paired jump, it decides the side for
    both columns."""
    a = jy[j, k]
    b = jy[j + 1, m]
    if w == 0.0:
        return a
    if w == 1.0:
        return b
    lo = down[j, k] if j >= 1 else -1
    hi = up[j + 1, m] if j + 2 < jy.shape[0] else -1
    ma = b - a
    mb = b - a
    if lo >= 0:
        ma = 0.5 * (b - jy[j - 1, lo])
        if hi < 0:
            mb = 0.5 * (3 * b - 4 * a + jy[j - 1, lo])
    if hi >= 0:
        mb = 0.5 * (jy[j + 2, hi] - a)
        if lo < 0:
            ma = 0.5 * (-3 * a + 4 * b - jy[j + 2, hi])
    w2 = w * w
    w3 = w2 * w
    return ((2 * w3 - 3 * w2 + 1) * a + (w3 - 2 * w2 + w) * ma + (-2 * w3 + 3 * w2) * b
            + (w3 - w2) * mb)


@numba.njit(cache=True)
def _beyond(ky, pstart, j, p, y):  # noqa: ANN001
    """How far (m) ``y`` lies outside the knots of piece ``p`` of column ``j`` (0 inside)."""
    lo = ky[j, pstart[j, p]]
    hi = ky[j, pstart[j, p + 1] - 1]
    return max(lo - y, y - hi, 0.0)


@numba.njit(cache=True)
def _corresponding(pair, nj, j, o, p):  # noqa: ANN001
    """The piece of column ``o`` (j +- 1; ``pair`` = ``up`` or ``down``) whose bounds are the
    partners of the jumps bounding piece ``p`` of column ``j`` (the grid's ends bound the first
    and last pieces); -1 where a bound has no partner or a jump of ``o`` lies between them."""
    if p == 0:
        lo = 0
    else:
        m = pair[j, p - 1]
        if m < 0:
            return -1
        lo = m + 1
    if p == nj[j]:
        hi = nj[o]
    else:
        m = pair[j, p]
        if m < 0:
            return -1
        hi = m
    return lo if lo == hi else -1


@numba.njit(cache=True)
def _warp(y, lo_s, lo_c, hi_s, hi_c, reach):  # noqa: ANN001
    """Where a column is evaluated for a query at ``y`` in a piece bounded by paired jumps at
    ``lo_s``, ``hi_s`` on their jump curves at the query's yaw and at ``lo_c``, ``hi_c`` in
    that column (NaN: the grid's end, no jump): ``(y_c, dy_c/dy, ok)``. Within half of ``reach``
    from a bound the column is read at the same distance from its own jump as the query is
    from the curve (``y_c - lo_c = y - lo_s``), blending linearly back to ``y_c = y`` at
    ``reach``; where the two zones would overlap (a piece narrower than twice the reach) the
    piece is mapped affinely onto the column's. Only where each jump lies within a quarter of
    the reach of its curve (the map then increases, slope >= 1/2) and the piece is not narrow
    (:data:`NARROW_STEPS`); else at ``y`` itself, and ``ok`` is False (the lookup then reads
    every column at ``y``: a query's columns are read alike). Beside a jump the contact runs
    up its steep onset within tenths of a millimetre (a flange: tens of degrees of contact
    angle): read at the same y, two columns whose jumps lie apart by a fraction of that are
    at different points of the onset, and their blend errs by millimetres."""
    has_lo = not np.isnan(lo_s)
    has_hi = not np.isnan(hi_s)
    if has_lo and has_hi and not (min(hi_s - lo_s, hi_c - lo_c) >= NARROW_STEPS * reach):
        # a narrow piece (a contact flickering within a cluster of jumps: which of the
        # cluster's jumps pair up is arbitrary) or curves that crossed: read at y
        return y, 1.0, False
    s_lo = lo_c - lo_s if has_lo else 0.0
    s_hi = hi_c - hi_s if has_hi else 0.0
    if max(abs(s_lo), abs(s_hi)) > 0.25 * reach:
        # a jump that moves farther than that between columns: what lies beside it
        # in one column need not lie beside it in the other (a branch that stays put in y
        # while its jump moves); read at y
        return y, 1.0, False
    if has_lo and has_hi and 2.0 * reach > hi_s - lo_s:
        k = (hi_c - lo_c) / (hi_s - lo_s)
        return lo_c + (y - lo_s) * k, k, True
    if has_lo and y - lo_s < reach:
        if y - lo_s <= 0.5 * reach:
            return y + s_lo, 1.0, True
        return y + 2.0 * s_lo * (1.0 - (y - lo_s) / reach), 1.0 - 2.0 * s_lo / reach, True
    if has_hi and hi_s - y < reach:
        if hi_s - y <= 0.5 * reach:
            return y + s_hi, 1.0, True
        return y + 2.0 * s_hi * (1.0 - (hi_s - y) / reach), 1.0 + 2.0 * s_hi / reach, True
    return y, 1.0, True


@numba.njit(cache=True)
def _bound(jy, nj, c, p):  # noqa: ANN001
    """The jumps bounding piece ``p`` of column ``c``: ``(lower, upper)`` (m; NaN: the grid's
    end)."""
    lo = jy[c, p - 1] if p >= 1 else np.nan
    hi = jy[c, p] if p < nj[c] else np.nan
    return lo, hi


@numba.njit(cache=True)
def lookup_one(y_axis, yaw_axis, ky, kv, kd, pstart, jy, nj, up, down, mode,  # noqa: ANN001
               jumps, slot_pair, slot_wheel, slot_s, y, yaw, out_v, out_dy, out_dw, tmp_v,
               tmp_d):
    """One pose into ``out_v``, ``out_dy``, ``out_dw`` (Q,); ``tmp_v``, ``tmp_d`` (8, Q) scratch
    (the columns j - 1 .. j + 2 around the query's yaw, rows 0-3 read at ``y``, rows 4-7 where
    :func:`_warp` moves them, for the quantities that jump).

    Returns ``(flags, piece, jump_dist)`` (see :meth:`~lutmpi.table.interp.Interpolator.evaluate`).
    """
    q = kv.shape[2]
    na = yaw_axis.size
    if (not (y >= y_axis[0] and y <= y_axis[-1]) or not (yaw >= yaw_axis[0]
                                                       and yaw <= yaw_axis[-1])):
        for c in range(q):
            out_v[c] = np.nan
            out_dy[c] = np.nan
            out_dw[c] = np.nan
        return 1, -1, np.nan
    flags = 0
    if na == 1:
        j, w = 0, 0.0
    else:
        lo, hi = 0, na - 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if yaw_axis[mid] <= yaw:
                lo = mid
            else:
                hi = mid
        j = lo
        w = (yaw - yaw_axis[j]) / (yaw_axis[j + 1] - yaw_axis[j])
        if abs(w) <= SNAP:        # on the column (:data:`SNAP`)
            w = 0.0
        elif abs(w - 1.0) <= SNAP:
            w = 1.0
    # the piece of each column: by the jump curves at this yaw (paired jumps), or by a column's
    # own jump where the other column holds no partner
    dist = np.nan
    best = np.inf
    paired = False
    if na == 1:
        p0 = _piece_of(jy, nj, j, y)
        p1 = p0
        for k in range(nj[j]):
            if abs(y - jy[j, k]) < best:
                best = abs(y - jy[j, k])
                dist = y - jy[j, k]
    else:
        # each column's piece: the number of its jumps at or below y, a paired jump at its
        # curve's position at this yaw (:func:`_jump_at`, computed once for both columns), an
        # unpaired one at its own but never across a paired one of its column (below a paired
        # jump the curve puts below y, above one it puts above: :func:`_unpaired_below`); the
        # distance: to the paired jumps and the nearer column's unpaired ones
        p0 = 0
        p1 = 0
        below0, above0, below1, above1 = -1, nj[j], -1, nj[j + 1]
        for k in range(nj[j]):
            m = up[j, k]
            if m < 0:
                yj = jy[j, k]
                if w >= 0.5:
                    continue
            else:
                yj = _jump_at(jy, up, down, j, k, m, w)
                if yj <= y:
                    p0 += 1
                    p1 += 1
                    below0, below1 = max(below0, k), max(below1, m)
                else:
                    above0, above1 = min(above0, k), min(above1, m)
            if abs(y - yj) < best:
                best = abs(y - yj)
                dist = y - yj
        for k in range(nj[j + 1]):
            if down[j + 1, k] < 0 and w >= 0.5 and abs(y - jy[j + 1, k]) < best:
                best = abs(y - jy[j + 1, k])
                dist = y - jy[j + 1, k]
        p0 += _unpaired_below(jy, nj, up, j, y, below0, above0)
        p1 += _unpaired_below(jy, nj, down, j + 1, y, below1, above1)
        paired = _corresponding(up, nj, j, j + 1, p0) == p1
        if w > 0.0 and not paired:
            flags |= 2   # the two pieces are not bounded by the same jumps: a linear blend
    p = p0 if w < 0.5 else p1
    _piece_eval(ky, kv, kd, mode, j, pstart[j, p0], pstart[j, p0 + 1], y, 1.0, tmp_v[1],
                tmp_d[1], False)
    if na == 1:
        for c in range(q):
            out_v[c] = tmp_v[1, c]
            out_dy[c] = tmp_d[1, c]
            out_dw[c] = np.nan
        return flags, p, dist
    _piece_eval(ky, kv, kd, mode, j + 1, pstart[j + 1, p1], pstart[j + 1, p1 + 1], y, 1.0,
                tmp_v[2], tmp_d[2], False)
    h_y = (y_axis[-1] - y_axis[0]) / (y_axis.size - 1) if y_axis.size > 1 else 0.0
    # the outer columns' pieces (the cubic in yaw below)
    pl = _corresponding(down, nj, j, j - 1, p0) if paired and j >= 1 else -1
    pu = _corresponding(up, nj, j + 1, j + 2, p1) if paired and j + 2 <= na - 1 else -1
    lower = pl >= 0
    upper = pu >= 0
    # the quantities that do not jump (the wheelset's pose, which only kinks at a jump) read an
    # outer column whose piece does not correspond in its own piece at y, where that column and
    # the two inner ones hold no jump within OUTER_STEPS grid steps of y: their cubic in yaw
    # stays (a straight line between 0.05 rad columns misses z_g by c h^2 / 4, ~60 um on a worn
    # pair); nearer a jump the outer column's kink lies elsewhere and its slope would mislead
    ql, qu = pl, pu
    outer_l = not lower and j >= 1
    outer_u = not upper and j + 2 <= na - 1
    if outer_l or outer_u:
        near = OUTER_STEPS * h_y
        inner = min(_gap_to_jumps(jy, nj, j, y), _gap_to_jumps(jy, nj, j + 1, y))
        if outer_l:
            ql = (_piece_of(jy, nj, j - 1, y)
                  if min(inner, _gap_to_jumps(jy, nj, j - 1, y)) >= near else -1)
        if outer_u:
            qu = (_piece_of(jy, nj, j + 2, y)
                  if min(inner, _gap_to_jumps(jy, nj, j + 2, y)) >= near else -1)
    # the quantities that jump are read in each column at the query's distance from the
    # piece's bounding jumps (:func:`_warp`), where the pieces correspond and every column
    # allows it
    warp = paired and w > 0.0 and w < 1.0
    ls, us = np.nan, np.nan
    if warp:
        if p0 >= 1:
            ls = _jump_at(jy, up, down, j, p0 - 1, up[j, p0 - 1], w)
        if p0 < nj[j]:
            us = _jump_at(jy, up, down, j, p0, up[j, p0], w)
    # where each column j - 1 .. j + 2 is read for the quantities that jump, and dy_c/dy
    # (scalars, not arrays: this runs once per lookup)
    yc0, yc1, yc2, yc3 = y, y, y, y
    k0, k1, k2, k3 = 1.0, 1.0, 1.0, 1.0
    lower_j, upper_j = lower, upper   # the outer columns that answer the quantities that jump
    if warp:
        pieces = (pl, p0, p1, pu)          # column j - 1 + r's piece, and whether it answers
        answers = (lower, True, True, upper)
        for r in range(4):
            if not answers[r]:
                continue
            lc, uc = _bound(jy, nj, j - 1 + r, pieces[r])
            yc, kc, ok = _warp(y, ls, lc, us, uc, WARP_STEPS * h_y)
            if r == 0:
                yc0, k0 = yc, kc
            elif r == 1:
                yc1, k1 = yc, kc
            elif r == 2:
                yc2, k2 = yc, kc
            else:
                yc3, k3 = yc, kc
            if not ok and r in (1, 2):
                warp = False      # the two columns are read alike, or both at y
            elif not ok and r == 0:
                lower_j = False   # an outer column that cannot be read alike gives no
            elif not ok:          # slope to the quantities that jump
                upper_j = False
    if warp and (yc0 == y and yc1 == y and yc2 == y and yc3 == y and k0 == 1.0 and k1 == 1.0
                 and k2 == 1.0 and k3 == 1.0 and lower_j == lower and upper_j == upper):
        warp = False   # every column read at y after all (away from the jumps): the rows at y
    if not warp:       # are the same evaluations, to the bit
        yc0, yc1, yc2, yc3 = y, y, y, y
        k0, k1, k2, k3 = 1.0, 1.0, 1.0, 1.0
        lower_j, upper_j = lower, upper
    # the rows the quantities that jump read: 4-7 where they are read apart from y, else the
    # same rows as the others (0-3)
    ow = 4 if warp else 0
    if ql >= 0:
        _piece_eval(ky, kv, kd, mode, j - 1, pstart[j - 1, ql], pstart[j - 1, ql + 1], y, 1.0,
                    tmp_v[0], tmp_d[0], False)
    if qu >= 0:
        _piece_eval(ky, kv, kd, mode, j + 2, pstart[j + 2, qu], pstart[j + 2, qu + 1], y, 1.0,
                    tmp_v[3], tmp_d[3], False)
    if warp:
        if lower:
            _piece_eval(ky, kv, kd, mode, j - 1, pstart[j - 1, pl], pstart[j - 1, pl + 1], yc0,
                        1.0, tmp_v[4], tmp_d[4], False)
        _piece_eval(ky, kv, kd, mode, j, pstart[j, p0], pstart[j, p0 + 1], yc1, 1.0,
                    tmp_v[5], tmp_d[5], False)
        _piece_eval(ky, kv, kd, mode, j + 1, pstart[j + 1, p1], pstart[j + 1, p1 + 1], yc2, 1.0,
                    tmp_v[6], tmp_d[6], False)
        if upper:
            _piece_eval(ky, kv, kd, mode, j + 2, pstart[j + 2, pu], pstart[j + 2, pu + 1], yc3,
                        1.0, tmp_v[7], tmp_d[7], False)
    # each column's contacts in the order of the nearer column's (:func:`match_slots`)
    ref = 1 if w < 0.5 else 2
    for r in range(4):
        if r != ref and (r in (1, 2) or (r == 0 and ql >= 0) or (r == 3 and qu >= 0)):
            match_slots(tmp_v, tmp_d, r, ref, slot_pair, slot_wheel, slot_s)
            if warp and (r in (1, 2) or (r == 0 and lower_j) or (r == 3 and upper_j)):
                match_slots(tmp_v, tmp_d, r + 4, ref + 4, slot_pair, slot_wheel, slot_s)
    # a column whose piece would be extended far beyond its end knots (its jump moved farther
    # than the grid resolves between the columns) does not answer: the other column alone
    only = -1
    lim = EXTEND_STEPS * h_y
    if w > 0.0 and w < 1.0:
        e0 = _beyond(ky, pstart, j, p0, yc1)
        e1 = _beyond(ky, pstart, j + 1, p1, yc2)
        if e0 > lim and e1 <= lim:
            only = 2
        elif e1 > lim and e0 <= lim:
            only = 1
    if only > 0:
        flags |= 2
    # cubic in yaw (Catmull-Rom: centred-difference slopes from the outer columns) where the
    # outer columns hold the corresponding piece; the contact varies ~ quadratically with yaw
    # (even in yaw at yaw 0), which linear blending between columns misses by c h^2 / 4
    # (on a column too: its yaw slope is the cubic's, the same from either cell)
    # (an outer column whose piece would be extended far to reach the query gives no slope to
    # the quantities that jump)
    lo_far = lower and _beyond(ky, pstart, j - 1, pl, yc0) > lim
    up_far = upper and _beyond(ky, pstart, j + 2, pu, yc3) > lim
    step = yaw_axis[j + 1] - yaw_axis[j]
    w2 = w * w
    w3 = w2 * w
    h00, h10, h01, h11 = 2 * w3 - 3 * w2 + 1, w3 - 2 * w2 + w, -2 * w3 + 3 * w2, w3 - w2
    g00, g10, g01, g11 = 6 * w2 - 6 * w, 3 * w2 - 4 * w + 1, -6 * w2 + 6 * w, 3 * w2 - 2 * w
    for c in range(q):
        # the quantities that jump: the warped rows, their y slopes times dy_c/dy
        if jumps[c]:
            o, s0, s1, s2, s3 = ow, k0, k1, k2, k3
        else:
            o, s0, s1, s2, s3 = 0, 1.0, 1.0, 1.0, 1.0
        a, b = tmp_v[1 + o, c], tmp_v[2 + o, c]
        da, db = tmp_d[1 + o, c] * s1, tmp_d[2 + o, c] * s2
        v0, v3 = tmp_v[o, c], tmp_v[3 + o, c]
        d0, d3 = tmp_d[o, c] * s0, tmp_d[3 + o, c] * s3
        if mode[c] == 2:
            out_v[c] = a if w < 0.5 else b
            out_dy[c] = 0.0
            out_dw[c] = (b - a) / step
            continue
        ma = b - a           # slopes per unit w: one-sided unless an outer column answers
        mb = b - a
        sa = db - da
        sb = db - da
        lo_ok = (lower_j if jumps[c] else ql >= 0) and np.isfinite(v0) and not (
            lo_far and jumps[c])
        up_ok = (upper_j if jumps[c] else qu >= 0) and np.isfinite(v3) and not (
            up_far and jumps[c])
        if lo_ok:
            ma = 0.5 * (b - v0)
            sa = 0.5 * (db - d0)
            if not up_ok:        # edge cell: second-order one-sided slope at j + 1
                mb = 0.5 * (3 * b - 4 * a + v0)
                sb = 0.5 * (3 * db - 4 * da + d0)
        if up_ok:
            mb = 0.5 * (v3 - a)
            sb = 0.5 * (d3 - da)
            if not lo_ok:        # edge cell: second-order one-sided slope at j
                ma = 0.5 * (-3 * a + 4 * b - v3)
                sa = 0.5 * (-3 * da + 4 * db - d3)
        if w == 0.0:
            out_v[c] = a
            out_dy[c] = da
        elif w == 1.0:
            out_v[c] = b
            out_dy[c] = db
        else:
            out_v[c] = h00 * a + h10 * ma + h01 * b + h11 * mb
            out_dy[c] = h00 * da + h10 * sa + h01 * db + h11 * sb
        out_dw[c] = (g00 * a + g10 * ma + g01 * b + g11 * mb) / step
        if only > 0 and jumps[c]:
            out_v[c] = tmp_v[only + ow, c]
            out_dy[c] = tmp_d[only + ow, c] * (k1 if only == 1 else k2)
            out_dw[c] = 0.0
    return flags, p, dist


@numba.njit(cache=True)
def lookup_many(arrays, y, yaw, out_v, out_dy, out_dw, flags, piece, dist):  # noqa: ANN001
    """:func:`lookup_one` over a batch (``arrays``:
    :attr:`~lutmpi.table.interp.Interpolator.arrays`)."""
    y_axis, yaw_axis, ky, kv, kd, pstart, jy, nj, up, down, mode, jumps, sp, sw, ss = arrays
    q = kv.shape[2]
    tmp_v = np.empty((8, q))
    tmp_d = np.empty((8, q))
    for i in range(y.size):
        f, p, d = lookup_one(y_axis, yaw_axis, ky, kv, kd, pstart, jy, nj, up, down, mode,
                             jumps, sp, sw, ss, y[i], yaw[i], out_v[i], out_dy[i], out_dw[i],
                             tmp_v, tmp_d)
        flags[i] = f
        piece[i] = p
        dist[i] = d


@numba.njit(cache=True)
def lookup_point(arrays, y, yaw, out_v, out_dy, out_dw, tmp_v, tmp_d):  # noqa: ANN001
    """:func:`lookup_one` for one pose (``arrays``:
    :attr:`~lutmpi.table.interp.Interpolator.arrays`): the compiled lookup of the dynamics;
    returns ``(flags, piece, jump_dist)``."""
    y_axis, yaw_axis, ky, kv, kd, pstart, jy, nj, up, down, mode, jumps, sp, sw, ss = arrays
    return lookup_one(y_axis, yaw_axis, ky, kv, kd, pstart, jy, nj, up, down, mode, jumps, sp,
                      sw, ss, y, yaw, out_v, out_dy, out_dw, tmp_v, tmp_d)
