"""Issue 14: the roll scan skips a refinement window that cannot raise a wheel's touching height
(:func:`lutmpi.contact.rigid_kernels.window_floor`), and so returns the same bits as refining
every window.

Oracles: every window refined as the scan refined them before (the window's own compiled gap
run, :func:`~lutmpi.contact.rigid_kernels.run_gaps`), on the paper's pair, a thinned flange and
measured worn profiles at the end of a measured rail's data, at random poses over the whole
admissible roll range and yaw up to 0.12 rad.
"""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.contact import rigid_kernels as rk
from lutmpi.contact import roll_scan as rs
from tests.unit.test_rigid_roots import _local_bound_scene

MM = 1e-3
PAIRS = ["paper", "thinned", "measured"]


def _window_gap(sgn, side, q, R, y, fine, U, PZ):
    """What refining coarse sample ``q``'s window gives: its touching gap (m; +inf off the
    rail)."""
    idx, s, r, dr, d, tab, lim = side[:7]
    step = idx[1] - idx[0]
    lo, hi = max(idx[q] - step, 0), min(idx[q] + step + 1, s.size)
    h2, _ = rk.run_gaps(sgn, s[lo:hi], r[lo:hi], dr[lo:hi], d, R, y, lim[0], lim[1], tab, lim[2],
                        lim[3], fine, U, PZ, rk.WINDOW)
    return -h2


def _scan_setup(pair):
    """The pair's locus solver, its scan's per-side arguments and the scan's work arrays."""
    L = _local_bound_scene(pair).locus
    return L, L._scan_sides, rs._scratch(*L._scan_sides)


def _poses(L, n, seed):
    rng = np.random.default_rng(seed)
    lo, hi = float(L.scan_rolls[0]), float(L.scan_rolls[-1])
    for _ in range(n):
        yield (rng.uniform(-12, 12) * MM, float(rng.choice([0.0, 0.01, -0.03, 0.07, -0.12])),
               rng.uniform(lo, hi))


@pytest.mark.parametrize("pair", PAIRS)
def test_the_window_floor_bounds_every_window(pair):
    # the floor lies at or below the touching gap of every coarse sample's window (all of
    # them, not only the ones the scan refines), and it is close enough to skip most far
    # windows: a missing term (the Hermite overshoot, the parabola's dip, the locus angle's
    # range) would break the first, a floor at -inf the second
    L, sides, (gl, gr, fine, U, PZ) = _scan_setup(pair)
    checked = above = off = 0
    worst = np.inf
    for y, yaw, roll in _poses(L, 150, 3):
        R = rk.rotation(yaw, roll)
        for sgn, side in ((1.0, sides[0]), (-1.0, sides[1])):
            wr, zhi, zlo, d, lim, tab = side[10], side[11], side[12], side[4], side[6], side[5]
            for q in range(side[0].size):
                got = _window_gap(sgn, side, q, R, y, fine, U, PZ)
                floor = rk.window_floor(sgn, wr[q], d, R, y, lim, tab, zhi, zlo,
                                          *rk.floor_terms(sgn, R))
                if floor == np.inf:   # the bound says no point is over the rail: none is
                    assert got == np.inf, (pair, y, yaw, roll, sgn, q, got)
                    off += 1
                    continue
                if not np.isfinite(got):
                    continue
                assert floor <= got + 1e-12, (pair, y, yaw, roll, sgn, q, floor, got)
                worst = min(worst, got - floor)
                checked += 1
                above += np.isfinite(floor)
    assert checked > 5000 and off > 1000   # both branches of the bound are exercised
    assert above > 0.9 * checked   # a finite bound nearly everywhere
    assert worst < 1e-4, worst     # and a tight one somewhere (within 0.1 mm of the gap)


def _reference_height(sgn, side, R, y, gap, fine, U, PZ):
    """The touching height with every window the scan selects refined (the scan before the
    floor): the smallest coarse sample's gap, raised by each window's height."""
    idx, s, r, dr, d, tab, lim, s_c, r_c, dr_c = side[:10]
    h, ib = rk.run_gaps(sgn, s_c, r_c, dr_c, d, R, y, lim[0], lim[1], tab, lim[2], lim[3], gap,
                        U, PZ, rk.COARSE)
    if ib < 0:
        return h
    coarse = gap.copy()
    h = -coarse[ib]
    limit = coarse[ib] + rk.SCAN_BAND
    n = idx.size
    for q in range(n):
        g = coarse[q]
        if not np.isfinite(g):
            continue
        edge = q in (0, n - 1) or not (np.isfinite(coarse[q - 1]) and np.isfinite(coarse[q + 1]))
        if not edge and (g > limit or coarse[q - 1] < g or coarse[q + 1] < g):
            continue
        h = max(h, -_window_gap(sgn, side, q, R, y, fine, U, PZ))
    return h


@pytest.mark.parametrize("pair", PAIRS)
def test_the_scan_height_is_the_same_bits(pair):
    # the scan point's height with windows skipped by the floor equals the height with every
    # selected window refined, to the bit (the skipping itself: the test below)
    L, sides, (gl, gr, fine, U, PZ) = _scan_setup(pair)
    n = 0
    for y, yaw, roll in _poses(L, 400, 4):
        R = rk.rotation(yaw, roll)
        for sgn, side, gap in ((1.0, sides[0], gl), (-1.0, sides[1], gr)):
            got = rk.scan_side_info(sgn, side, R, y, gap, fine, U, PZ)[0]
            want = _reference_height(sgn, side, R, y, gap, fine, U, PZ)
            assert got == want or (np.isnan(got) and np.isnan(want)), (pair, y, yaw, roll, sgn)
            n += np.isfinite(want)
    assert n > 400


@pytest.mark.parametrize("pair", PAIRS)
def test_the_floor_skips_the_far_ends(pair):
    # at roll 0 and yaw 0 on every pair, the first and last coarse samples' windows (the ends of
    # the data, refined whatever their gap) lie far enough above the smallest gap that the
    # floor rules them out: the point of the floor
    _, sides, (gl, gr, fine, U, PZ) = _scan_setup(pair)
    skipped = 0
    for y in np.linspace(-4, 4, 9) * MM:
        R = rk.rotation(0.0, 0.0)
        for sgn, side, gap in ((1.0, sides[0], gl), (-1.0, sides[1], gr)):
            h = rk.scan_side_info(sgn, side, R, y, gap, fine, U, PZ)[0]
            wr, zhi, zlo, d, lim, tab = side[10], side[11], side[12], side[4], side[6], side[5]
            for q in (0, side[0].size - 1):
                skipped += rk.window_floor(sgn, wr[q], d, R, y, lim, tab, zhi, zlo,
                                           *rk.floor_terms(sgn, R)) > rk.FLOOR_EPS - h
    assert skipped >= 18, skipped   # of 36 ends, at least half


def test_the_floor_allows_for_the_parabolas_dip_below_a_corner():
    # a wheel whose radius peaks in an asymmetric corner between two samples (slopes +2 and
    # -0.05) over a flat rail at yaw and roll 0: the window's lowest point is the corner, which
    # the interval bound meets to rounding (flat rail, the radius's largest Hermite value), and
    # the parabolas of the resampling dip below it (a sample's neighbours 1 um and 200 um
    # above it): the floor must lie below the refined gap there too
    s = np.round(np.arange(-300, 301) * 1e-4, 12)
    s0 = 3.7e-5                                   # the corner, between two samples
    r = np.where(s < s0, 0.46 - 2.0 * (s0 - s), 0.46 - 0.05 * (s - s0))
    dr = np.where(s < s0, 2.0, -0.05)
    idx = np.unique(np.append(np.arange(0, s.size, 10), s.size - 1)).astype(np.int64)
    tab = np.zeros(20001)
    lim = np.array([0.6, 1e-5, 0.6, 0.8])
    side = (idx, s, r, dr, 0.75, tab, lim, s[idx].copy(), r[idx].copy(), dr[idx].copy(),
            rk.window_ranges(idx, s, r, dr), *rk.extreme_tables(tab))
    fine, U, PZ = np.empty(s.size), np.empty(s.size), np.empty(s.size)
    R = rk.rotation(0.0, 0.0)
    q = int(np.argmin(np.abs(s[idx] - s0)))
    got = _window_gap(1.0, side, q, R, 0.0, fine, U, PZ)
    floor = rk.window_floor(1.0, side[10][q], 0.75, R, 0.0, lim, tab, side[11], side[12],
                            *rk.floor_terms(1.0, R))
    corner = -float(side[10][q][3])               # minus the window's largest radius
    assert got < corner - 1e-9, (got, corner)     # the resampling's parabola dips below it
    assert floor <= got, (floor, got)
