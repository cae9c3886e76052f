"""Contact jumps as data, jump-aware interpolation, the out-of-range policy, ``lutmpi query`` and
the dynamics stopping at the table's edge (issue 11).

The pure tests use a closed-form "solver" whose contact jumps at a known position, so every
located jump and every interpolated value has an exact oracle; the real-profile tests compare
``lutmpi query`` with ``lutmpi solve`` (direct solves, the same method) column by column.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from lutmpi.cli import main
from lutmpi.config.load import load_config
from lutmpi.equilibrium.result import CONVERGED
from lutmpi.paths import REPO_ROOT
from lutmpi.table import interp as ti
from lutmpi.table import jump_search as tjs
from lutmpi.table import jumps as tj
from lutmpi.table import mirror as tm
from lutmpi.table import refine as trf
from lutmpi.table.schema import FIELDS, limit_fields

NAMES = ("status", "n_contacts", "wheel_s", "rail_v", "rolling_radius", "z_g")
FLDS = limit_fields([f for f in FIELDS if f.name in NAMES])


def jump_at(yaw: float) -> float:
    """Closed-form jump position of the synthetic contact, m: 1.234 mm + 10 mm/rad * yaw."""
    return 1.234e-3 + 1e-2 * yaw


def synthetic(y: float, yaw: float) -> dict[str, np.ndarray]:
    """Left wheel: tread contact (s = 2 y, r = 0.46 + 0.05 y) below the jump, flange contact
    (s = -30 mm + y, r = 0.47 + y) above it; the right wheel is smooth."""
    rec = {f.name: f.empty((1,))[0] for f in FLDS}
    flange = y >= jump_at(yaw)
    rec["status"] = np.int8(CONVERGED)
    rec["n_contacts"] = np.array([1, 1], np.int8)
    rec["z_g"] = np.float64(0.46 + 0.1 * y * y)
    rec["wheel_s"][:, 0] = [(-0.03 + y) if flange else 2 * y, -y]
    rec["rail_v"][:, 0] = [(-0.02 + y) if flange else 2 * y, y]
    rec["rolling_radius"][:, 0] = [(0.47 + y) if flange else 0.46 + 0.05 * y, 0.46 - 0.05 * y]
    return rec


def grid_arrays(y_axis: np.ndarray, yaw_axis: np.ndarray) -> dict[str, np.ndarray]:
    out = {f.name: f.empty((y_axis.size, yaw_axis.size)) for f in FLDS}
    for i, y in enumerate(y_axis):
        for j, yaw in enumerate(yaw_axis):
            for name, v in synthetic(float(y), float(yaw)).items():
                out[name][i, j] = v
    return out


@pytest.fixture(scope="module")
def synthetic_table():
    y_axis = np.linspace(-4e-3, 4e-3, 17)          # 0.5 mm step
    yaw_axis = np.linspace(-0.02, 0.02, 5)
    arrays = grid_arrays(y_axis, yaw_axis)
    calls = []

    def solve(y, yaw):
        calls.append(y)
        return synthetic(y, yaw)

    js = tj.locate_jumps(arrays, y_axis, yaw_axis, solve, FLDS)
    ip = ti.build(y_axis, yaw_axis, arrays, js.arrays, js.limits, js.knot_y, js.knots)
    return y_axis, yaw_axis, arrays, js, ip, calls


def test_each_jump_is_located_within_the_tolerance(synthetic_table):
    _, yaw_axis, _, js, _, calls = synthetic_table
    assert js.count.tolist() == [1] * yaw_axis.size
    for j, yaw in enumerate(yaw_axis):
        lo, hi = js.arrays["jump_y_lo"][j, 0], js.arrays["jump_y_hi"][j, 0]
        assert lo < jump_at(yaw) <= hi and hi - lo <= tjs.TOL_M       # the bracket holds it
        assert abs(js.arrays["jump_y"][j, 0] - jump_at(yaw)) <= tjs.TOL_M / 2
        assert js.arrays["jump_kind"][j, 0] == 1 and js.arrays["jump_side"][j, 0] == 1
        # one-sided limits are the two closed-form branches
        assert js.limits["wheel_s"][j, 0, 0, 0, 0] == pytest.approx(2 * lo)
        assert js.limits["wheel_s"][j, 0, 1, 0, 0] == pytest.approx(-0.03 + hi)
    # bisection from 0.5 mm to 5 um: 7 solves per jump, plus the refinement midpoints
    assert len(calls) < 7 * yaw_axis.size + 200


def test_a_query_across_a_jump_never_returns_a_blend(synthetic_table):
    """Near the jump every interpolated rolling radius is on one of the two branches; the plain
    interpolation over the grid nodes blends them (by millimetres). The branches here are
    linear in y and stay put while the jump moves with yaw: read at y the jump-aware answer
    would be exact; within a grid step of the jump each column is read at the query's distance
    from its own jump instead (``lookup._warp``: a flange onset moves with its jump), which
    for branches that stay put costs their slope times the jump's shift between the columns
    (here up to 0.5 um)."""
    y_axis, yaw_axis, arrays, _, ip, _ = synthetic_table
    plain = ti.build(y_axis, yaw_axis, arrays)
    off = ip.layout.slots["rolling_radius"][0]
    rng = np.random.default_rng(7)
    yaw = rng.uniform(-0.02, 0.02, 400)
    y = jump_at(yaw) + rng.uniform(-0.5e-3, 0.5e-3, 400)
    y = np.concatenate([y, jump_at(yaw_axis)])              # exactly at the jump: upper side
    yaw = np.concatenate([yaw, yaw_axis])
    far = np.abs(y - jump_at(yaw)) > tjs.TOL_M / 2          # inside the bracket: either side
    want = np.where(y >= jump_at(yaw), 0.47 + y, 0.46 + 0.05 * y)
    got = ip.evaluate(y, yaw)[0][:, off]
    tread, flange = 0.46 + 0.05 * y, 0.47 + y
    on_a_branch = np.minimum(np.abs(got - tread), np.abs(got - flange))
    assert on_a_branch.max() < 1e-6
    assert np.abs(got - want)[far].max() < 1e-6
    blended = plain.evaluate(y, yaw)[0][:, off]
    assert np.minimum(np.abs(blended - tread), np.abs(blended - flange)).max() > 1e-3


def test_a_small_jump_on_a_slowly_moving_contact_is_located():
    """On a worn flange the contact point creeps (0.2 mm per mm of y here) and then jumps by
    1 mm, with no change of contact count: a cell's end-to-end movement (1.1 mm) stays below
    the fixed candidate threshold (2 mm), but it is five times its neighbours'. The jump is
    located within the tolerance, and nothing else is."""
    y_axis = np.linspace(-4e-3, 4e-3, 17)
    yaw_axis = np.array([0.0])
    at = 1.234e-3

    def creeping(y: float, yaw: float) -> dict[str, np.ndarray]:
        rec = synthetic(y, yaw)
        s = -0.04 + 0.2 * y - (1e-3 if y >= at else 0.0)
        rec["wheel_s"][:, 0] = [s, -0.2 * y]
        rec["rail_v"][:, 0] = [0.5 * s, 0.2 * y]
        rec["rolling_radius"][:, 0] = [0.478 - s, 0.46]
        rec["n_contacts"] = np.array([1, 1], np.int8)
        return rec

    out = {f.name: f.empty((y_axis.size, 1)) for f in FLDS}
    for i, y in enumerate(y_axis):
        for name, v in creeping(float(y), 0.0).items():
            out[name][i, 0] = v
    assert tjs.candidate_cells(out, threshold=tjs.CANDIDATE_M) == [(0, 10)]
    js = tj.locate_jumps(out, y_axis, yaw_axis, creeping, FLDS, refine=False)
    assert js.count.tolist() == [1]
    assert abs(js.arrays["jump_y"][0, 0] - at) <= tjs.TOL_M / 2
    assert js.arrays["jump_kind"][0, 0] == 1 and js.arrays["jump_side"][0, 0] == 1


def test_a_cluster_of_jumps_is_located_from_the_poses_already_solved():
    """A second contact appears, the primary contact moves over to the flange, the second
    contact goes, within 15 um of one cell (as on the Manchester pair's flange root). Each
    jump is located within the tolerance; the second and third are bisected from the poses the
    first search solved next to them, not from the whole cell again: 10 solves for the three
    (the cell bisected afresh for each cost 15)."""
    at = (1.234e-3, 1.2412e-3, 1.2483e-3)

    def cluster(y: float, yaw: float) -> dict[str, np.ndarray]:
        rec = synthetic(y, yaw)
        s = 2 * y if y < at[1] else -0.03 + y
        rec["wheel_s"][:, 0] = [s, -y]
        rec["rail_v"][:, 0] = [s, y]
        rec["n_contacts"] = np.array([2 if at[0] <= y < at[2] else 1, 1], np.int8)
        return rec

    y_axis, yaw_axis = np.linspace(-4e-3, 4e-3, 17), np.array([0.0])
    out = {f.name: f.empty((y_axis.size, 1)) for f in FLDS}
    for i, y in enumerate(y_axis):
        for name, v in cluster(float(y), 0.0).items():
            out[name][i, 0] = v
    calls = []

    def solve(y: float, yaw: float) -> dict[str, np.ndarray]:
        calls.append(y)
        return cluster(y, yaw)

    js = tj.locate_jumps(out, y_axis, yaw_axis, solve, FLDS, refine=False)
    assert js.count.tolist() == [3]
    assert np.abs(js.arrays["jump_y"][0, :3] - np.array(at)).max() <= tjs.TOL_M / 2
    assert js.arrays["jump_kind"][0, :3].tolist() == [2, 1, 2]
    assert len(calls) <= 10


def test_outside_the_grid_is_flagged_with_nan(synthetic_table):
    _, _, _, _, ip, _ = synthetic_table
    value, _, _, flags, piece, _ = ip.evaluate(np.array([0.0, 5e-3, 0.0, np.nan]),
                                               np.array([0.0, 0.0, 0.03, 0.0]))
    assert (flags & ti.OUT_OF_RANGE).tolist() == [0, 1, 1, 1]
    assert np.isnan(value[1:]).all() and np.isfinite(value[0]).any() and piece[1] == -1


def _two_curves_and_clusters(yaw: float) -> list[tuple[float, float]]:
    """Jumps ``(y m, step of the rolling radius m)`` of one column of a synthetic table: two
    jump curves moving with yaw (10 mm/rad) and a cluster of two small opposite steps (as the
    load centre's mesh-step jumps come) at y = -3.2 mm for yaw < 0 and at +3.2 mm for yaw >= 0,
    so neighbouring columns across yaw 0 hold the same count of jumps but not the same jumps."""
    curves = [(-1.0e-3 + 1e-2 * yaw, 2e-3), (1.234e-3 + 1e-2 * yaw, 8e-3)]
    cluster = ([(-3.21e-3, 1e-5), (-3.2e-3, -1e-5)] if yaw < 0.0
               else [(3.2e-3, 1e-5), (3.21e-3, -1e-5)])
    return sorted(curves + cluster)


def _stepped(y: float, jumps: list[tuple[float, float]]) -> float:
    return 0.46 + 0.05 * y + sum(step for yj, step in jumps if y >= yj)


def test_columns_with_as_many_but_other_jumps_are_read_on_the_same_side_of_each_curve():
    """Two neighbouring columns with the same number of jumps, on the same wheel, are not
    taken to hold the same jumps: each jump curve's position is interpolated between its own
    two positions, and every query between the columns lands on its exact branch. (Pairing
    the jumps by their index put jump curves 4 mm apart together: between the columns either
    side of yaw 0 the answer took the other side's branch.)"""
    y_axis = np.linspace(-4e-3, 4e-3, 17)
    yaw_axis = np.linspace(-0.02, 0.02, 5)
    cols = [_two_curves_and_clusters(float(a)) for a in yaw_axis]
    rr = np.array([[_stepped(float(y), c) for c in cols] for y in y_axis])
    pos = np.array([[yj for yj, _ in c] for c in cols])
    lo, hi = pos - 2e-6, pos + 2e-6
    jumps = {"jump_y": pos, "jump_y_lo": lo, "jump_y_hi": hi,
             "jump_side": np.ones(pos.shape, np.int8)}
    limits = {"rolling_radius": np.stack(
        [[[_stepped(float(a), c), _stepped(float(b), c)] for a, b in zip(lo[j], hi[j], strict=True)]
         for j, c in enumerate(cols)])}
    ip = ti.build(y_axis, yaw_axis, {"rolling_radius": rr}, jumps, limits,
                  modes={"rolling_radius": "pchip"})
    assert [len(c) for c in cols] == [4] * 5
    rng = np.random.default_rng(11)
    yaw = rng.uniform(-0.02, 0.02, 2000)
    y = rng.uniform(-2.5e-3, 2.5e-3, 2000)
    curves = [(-1.0e-3 + 1e-2 * yaw, 2e-3), (1.234e-3 + 1e-2 * yaw, 8e-3)]
    far = np.all([np.abs(y - c) > 5e-6 for c, _ in curves], axis=0)
    want = 0.46 + 0.05 * y + sum(np.where(y >= c, step, 0.0) for c, step in curves)
    got, _, _, flags, _, _ = ip.evaluate(y[far], yaw[far])
    assert np.abs(got[:, 0] - want[far]).max() < 1e-12
    # between the two curves both columns' pieces are bounded by the same (paired) jumps: the
    # cubic in yaw (but within the curve's move between columns, 0.1 mm, of a jump, where one
    # column answers alone); below or above them a cluster bounds one column's piece only
    middle = ((y > curves[0][0] + 0.1e-3) & (y < curves[1][0] - 0.1e-3))[far]
    assert middle.sum() > 500 and not (flags[middle] & ti.UNMATCHED).any()
    assert (flags[~middle] & ti.UNMATCHED).any()
    # the cell either side of yaw 0 had the wrong side before: it is in the sample
    assert ((yaw[far] > -0.01) & (yaw[far] < 0.0)).sum() > 100


def test_the_wheelset_pose_is_never_taken_to_jump():
    """On a flat tread z_g hardly moves from node to node, so the micrometre it moves at a
    contact jump is many of its median steps; it still only kinks there, and stays interpolated
    across yaw. The same numbers as a contact coordinate do count as a jump."""
    y_axis = np.linspace(-2e-3, 2e-3, 9)
    yaw_axis = np.array([-0.01, 0.0, 0.01])
    flat = 0.46 + 1e-9 * np.arange(9)[:, None] + 1e-6 * (y_axis[:, None] >= 0.1e-3)
    grid = np.repeat(flat, 3, axis=1)
    pos = np.full((3, 1), 0.1e-3)
    lim = np.stack([np.full((3, 1), 0.46), np.full((3, 1), 0.460001)], axis=2)
    jumps = {"jump_y": pos, "jump_y_lo": pos - 2e-6, "jump_y_hi": pos + 2e-6,
             "jump_side": np.ones((3, 1), np.int8)}
    ip = ti.build(y_axis, yaw_axis, {"z_g": grid, "wheel_s": grid}, jumps,
                  {"z_g": lim, "wheel_s": lim})
    assert ip.jumps.tolist() == [False, True]


def test_jumps_of_neighbouring_columns_pair_by_position_and_wheel():
    mm = 1e-3
    step = 0.5 * mm                                   # reach: two steps unless jumps move far
    a, b = ti.pair_jumps(np.array([-3.21, -3.2, -1.0, 1.234]) * mm, np.ones(4, np.int8),
                         np.array([-0.9, 1.334, 3.2, 3.21]) * mm, np.ones(4, np.int8), step)
    assert a.tolist() == [-1, -1, 0, 1] and b.tolist() == [2, 3, -1, -1]
    # another wheel: no partner; one far beyond what the others moved: none either
    a, b = ti.pair_jumps(np.array([0.0]) * mm, np.array([1], np.int8),
                         np.array([0.0]) * mm, np.array([2], np.int8), step)
    assert a.tolist() == [-1] and b.tolist() == [-1]
    a, b = ti.pair_jumps(np.array([-1.0, 0.0, 2.0]) * mm, np.ones(3, np.int8),
                         np.array([-0.9, 0.1, 4.0]) * mm, np.ones(3, np.int8), step)
    assert a.tolist() == [0, 1, -1] and b.tolist() == [0, 1, -1]
    # a jump that appears between two others keeps the others paired
    a, b = ti.pair_jumps(np.array([-1.0, 1.0]) * mm, np.ones(2, np.int8),
                         np.array([-0.8, 0.1, 1.2]) * mm, np.ones(3, np.int8), step)
    assert a.tolist() == [0, 2] and b.tolist() == [0, -1, 1]
    # a coarse yaw grid: the jumps moved 3 steps, each still the other's nearest: paired
    a, b = ti.pair_jumps(np.array([-4.0, 2.0]) * mm, np.array([2, 1], np.int8),
                         np.array([-2.5, 0.5]) * mm, np.array([2, 1], np.int8), step)
    assert a.tolist() == [0, 1] and b.tolist() == [0, 1]
    # ... and where one more jump appears, the others' shift sets the reach
    a, b = ti.pair_jumps(np.array([-4.0, 2.0]) * mm, np.array([2, 1], np.int8),
                         np.array([-2.5, 0.5, 3.9]) * mm, np.array([2, 1, 1], np.int8), step)
    assert a.tolist() == [0, 1] and b.tolist() == [0, 1, -1]


def test_a_jump_flagged_on_both_wheels_pairs_with_its_one_wheel_image_in_the_next_column():
    """A fold is flagged on both wheels (3) in one column and on the right wheel (2) in the
    next, where the left wheel's change fell below the confirmation: one jump, paired (it went
    unpaired, and each column was read on its own side between them: a measured worn flange
    pair, 6.2 mm of rolling radius off at 0.01 rad yaw steps). A jump of the same mask is
    preferred where both are near; masks that share no wheel never pair, and a shared wheel
    pairs only within half the reach."""
    mm = 1e-3
    step = 0.5 * mm
    a, b = ti.pair_jumps(np.array([-6.549]) * mm, np.array([3], np.int8),
                         np.array([-6.71]) * mm, np.array([2], np.int8), step)
    assert a.tolist() == [0] and b.tolist() == [0]
    a, b = ti.pair_jumps(np.array([0.0]) * mm, np.array([3], np.int8),
                         np.array([-0.05, 0.1]) * mm, np.array([2, 3], np.int8), step)
    assert a.tolist() == [1] and b.tolist() == [-1, 0]
    a, b = ti.pair_jumps(np.array([0.0]) * mm, np.array([1], np.int8),
                         np.array([0.0]) * mm, np.array([2], np.int8), step)
    assert a.tolist() == [-1] and b.tolist() == [-1]
    a, b = ti.pair_jumps(np.array([0.0]) * mm, np.array([3], np.int8),
                         np.array([0.6]) * mm, np.array([2], np.int8), step)
    assert a.tolist() == [-1] and b.tolist() == [-1]      # 0.6 mm: beyond half the 1 mm reach


def test_jumps_that_move_the_main_contact_alike_pair_before_nearer_ones():
    """The paper's pair (load centre), left wheel, yaw 0.027 and 0.033 rad: one column's main
    contact goes from tread to flange through a cluster (a 0.7 mm tread step, a second contact's
    onset, the swap of the two, the loss of the tread contact: at 6.154, 6.158, 6.162 and
    6.170 mm), the next column's through the flange contact's onset as the main one and the
    tread contact's loss (6.041, 6.053 mm). By distance alone the tread step paired with the
    flange jump, and between the columns a tread contact was blended with a flange one (6.5 mm
    of rolling radius off); the main contact's movement along the wheel pairs the two jumps to
    the flange and the two losses."""
    mm = 1e-3
    ya = np.array([6.1543, 6.1582, 6.1621, 6.1699]) * mm
    yb = np.array([6.041, 6.0527]) * mm
    side = np.ones(4, np.int8)
    ma = np.array([[0.668, 0.161], [0.045, 0.0], [-44.877, 0.0], [-0.032, 0.062]]) * mm
    mb = np.array([[-45.654, 0.04], [-0.031, 0.006]]) * mm
    a, b = ti.pair_jumps(ya, side, yb, side[:2], 0.5 * mm, ma, mb)
    assert a.tolist() == [-1, -1, 0, 1] and b.tolist() == [2, 3]
    a, b = ti.pair_jumps(ya, side, yb, side[:2], 0.5 * mm)       # by distance alone
    assert a.tolist() == [0, 1, -1, -1] and b.tolist() == [0, 1]
    # alike movements leave the pairing by distance as it was; an unlike pair still pairs
    # where nothing alike is near (it costs what leaving the moving jump unpaired does)
    a, b = ti.pair_jumps(ya[2:], side[2:], yb, side[:2], 0.5 * mm, ma[2:], mb)
    assert a.tolist() == [0, 1] and b.tolist() == [0, 1]
    a, b = ti.pair_jumps(ya[:1], side[:1], yb[:1], side[:1], 0.5 * mm, ma[:1], mb[:1])
    assert a.tolist() == [0] and b.tolist() == [0]
    # a column without jumps next to one with some (its movements an empty (0, wheels) array)
    a, b = ti.pair_jumps(ya[:0], side[:0], yb, side[:2], 0.5 * mm, ma[:0], mb)
    assert a.tolist() == [] and b.tolist() == [-1, -1]
    # one wheel's movements as 1-D arrays; the alike jump 0.45 mm away wins over a still one
    # 0.05 mm away (a jump moving the contact the other way repels half as much: it wins there)
    one = np.ones(2, np.int8)
    a, b = ti.pair_jumps(np.array([0.0]), one[:1], np.array([0.05, 0.45]) * mm, one, 0.5 * mm,
                         np.array([5.0]) * mm, np.array([0.0, 5.0]) * mm)
    assert a.tolist() == [1] and b.tolist() == [-1, 0]
    a, b = ti.pair_jumps(np.array([0.0]), one[:1], np.array([0.05, 0.45]) * mm, one, 0.5 * mm,
                         np.array([5.0]) * mm, np.array([-5.0, 5.0]) * mm)
    assert a.tolist() == [0] and b.tolist() == [0, -1]


def test_jumps_moving_the_main_contact_by_amounts_far_apart_are_unlike():
    """The README's measured asymmetric pair, reference method, yaw -0.1 and -0.09 rad, right
    wheel (1 mm steps of y): the main contact leaves the flange for the tread by 44.2 mm of
    wheel profile at y = -5.627 mm in one column and by 38.6 mm at -5.803 mm in the next; a
    1.3 mm step of the flange contact lies just before each (-5.764, -6.260 mm). By direction
    alone the 44 mm jump paired with a 5.3 mm one 0.6 mm away and the 38.6 mm jump with the
    1.3 mm step, and between the columns the tread and flange contacts were blended (6.5 mm of
    rolling radius off at y = -5.70, yaw -0.095). Amounts more than three times apart are unlike:
    44 pairs with 38.6 and 1.32 with 1.26."""
    mm = 1e-3
    ya = np.array([-6.3848, -5.7793, -5.7637, -5.748, -5.627, -5.1816]) * mm
    yb = np.array([-6.2715, -6.2598, -6.2441, -5.8066, -5.8027, -5.7988, -5.5215, -5.0449,
                   -4.5723]) * mm
    sa = np.array([1, 2, 2, 2, 2, 2], np.int8)
    sb = np.full(9, 2, np.int8)
    ma = np.zeros((6, 2))
    ma[2, 1], ma[4, 1] = 1.32 * mm, 44.24 * mm
    mb = np.zeros((9, 2))
    mb[1, 1], mb[4, 1], mb[7, 1] = 1.26 * mm, 38.64 * mm, 5.27 * mm
    a, b = ti.pair_jumps(ya, sa, yb, sb, 1.0 * mm, ma, mb)
    assert a[4] == 4 and a[2] == 1                   # 44.2 with 38.6 mm, 1.32 with 1.26 mm
    assert b[4] == 4 and b[1] == 2 and b[7] != 4      # and the 5.3 mm jump not with the 44


def test_an_unpaired_jump_is_never_read_across_a_paired_one_the_curve_put_below():
    """Column 0's jumps: an unpaired one on the right wheel at 1.02 mm, then the left wheel's
    at 1.2 mm, paired with column 1's at 0.7 mm. Halfway between the columns the pair's curve
    lies at 0.95 mm: a query at 0.99 mm is above it, so column 0 is read above its 1.2 mm jump
    too. By its own position the unpaired jump at 1.02 mm counted as above the query, and
    column 0 was read between its two jumps, on the tread (the paper's pair at yaw 0.03 rad,
    y = 6.15 mm: 6.5 mm of rolling radius off). Here column 0's piece above 1.2 mm would be
    extended too far, so column 1 answers alone: its flange value."""
    mm = 1e-3
    y_axis = np.linspace(-2, 2, 9) * mm
    yaw_axis = np.array([0.0, 0.01])
    at = np.array([[1.02, 1.2], [0.7, np.nan]]) * mm
    rr = np.empty((9, 2))
    rr[:, 0] = np.where(y_axis >= at[0, 1], 0.47, np.where(y_axis >= at[0, 0], 0.461, 0.46))
    rr[:, 1] = np.where(y_axis >= at[1, 0], 0.47, 0.46)
    lo, hi = at - 2e-6, at + 2e-6
    lim = np.full((2, 2, 2), np.nan)
    lim[0, 0], lim[0, 1], lim[1, 0] = (0.46, 0.461), (0.461, 0.47), (0.46, 0.47)
    jumps = {"jump_y": at, "jump_y_lo": lo, "jump_y_hi": hi,
             "jump_side": np.array([[2, 1], [1, 0]], np.int8)}
    ip = ti.build(y_axis, yaw_axis, {"rolling_radius": rr}, jumps, {"rolling_radius": lim})
    assert ip.up[0].tolist() == [-1, 0] and ip.down[1, :1].tolist() == [1]
    v = ip.evaluate(np.array([0.99 * mm]), np.array([0.005]))[0]
    assert v[0] == pytest.approx(0.47, abs=1e-12)
    v = ip.evaluate(np.array([0.9 * mm]), np.array([0.005]))[0]      # below the curve: tread
    assert v[0] < 0.4611


def test_the_pose_keeps_its_cubic_in_yaw_away_from_the_jumps_of_unmatched_pieces():
    """z_g quadratic in yaw over five 0.05 rad columns; the middle column holds a jump its
    neighbours do not (a worn pair's flickering contact), so between it and the next column
    the two pieces are not bounded by the same jumps. Far from every jump z_g still takes the
    cubic through the outer columns (exact for a quadratic), not the straight line, which
    misses by c h^2 / 4 = 62.5 um here (on the audit's 0.05 rad worn pairs the poses off by
    more than 20 um of z_g fell by 11-40 % where the cubic came back). Within a grid step of
    a jump the line stays: there the outer columns' kinks lie elsewhere."""
    y_axis = np.linspace(-4e-3, 4e-3, 17)
    yaw_axis = np.linspace(-0.1, 0.1, 5)
    z = 0.46 + 0.1 * yaw_axis[None, :] ** 2 + 0.01 * y_axis[:, None]
    rr = np.full((17, 5), 0.46)
    at = np.full((5, 1), np.nan)
    at[2, 0] = 3e-3
    rr[y_axis >= at[2, 0], 2] = 0.47
    lim = np.full((5, 1, 2), np.nan)
    lim[2, 0] = (0.46, 0.47)
    zlim = np.full((5, 1, 2), np.nan)
    zlim[2, 0] = 0.46 + 0.01 * (at[2, 0] + np.array([-2e-6, 2e-6]))
    jumps = {"jump_y": at, "jump_y_lo": at - 2e-6, "jump_y_hi": at + 2e-6,
             "jump_side": np.where(np.isfinite(at), 1, 0).astype(np.int8)}
    ip = ti.build(y_axis, yaw_axis, {"z_g": z, "rolling_radius": rr}, jumps,
                  {"rolling_radius": lim, "z_g": zlim})
    v, _, _, flags, _, _ = ip.evaluate(np.array([-2e-3, 2.8e-3]), np.array([0.025, 0.025]))
    exact = 0.46 + 0.1 * 0.025 ** 2 + 0.01 * np.array([-2e-3, 2.8e-3])
    assert (flags & ti.UNMATCHED).all()
    assert v[0, 0] == pytest.approx(exact[0], abs=1e-12)          # the cubic
    assert v[1, 0] - exact[1] == pytest.approx(0.1 * 0.05 ** 2 / 4, rel=1e-6)  # the line


def _branch(y, upper):
    """Rolling radius (m) of :func:`_one_jump_curve`'s table: flange branch above its jump."""
    return np.where(upper, 0.47 + y, 0.46 + 0.05 * y)


def _one_jump_curve(at, mode: str):
    """A table over y +-4 mm (0.5 mm steps) x yaw +-0.02 rad (5 columns) whose rolling radius
    jumps from :func:`_branch`'s tread to its flange at y = ``at(yaw)``; returns the yaw axis and
    the interpolator (``mode`` for the rolling radius)."""
    y_axis = np.linspace(-4e-3, 4e-3, 17)
    yaw_axis = np.linspace(-0.02, 0.02, 5)
    rr = _branch(y_axis[:, None], y_axis[:, None] >= at(yaw_axis)[None, :])
    pos = at(yaw_axis)[:, None]
    lo, hi = pos - 2e-6, pos + 2e-6
    jumps = {"jump_y": pos, "jump_y_lo": lo, "jump_y_hi": hi,
             "jump_side": np.ones(pos.shape, np.int8)}
    limits = {"rolling_radius": np.stack([_branch(lo, False), _branch(hi, True)], axis=2)}
    return yaw_axis, ti.build(y_axis, yaw_axis, {"rolling_radius": rr}, jumps, limits,
                              modes={"rolling_radius": mode})


def test_a_jump_moving_several_steps_between_columns_is_still_followed():
    """A coarse yaw grid: the jump curve moves 1.5 mm (3 grid steps) from column to column, and
    every query between the columns still lands on its exact branch (nothing blended)."""
    at = lambda yaw: 0.2e-3 + 0.15 * yaw                        # noqa: E731 - m
    yaw_axis, ip = _one_jump_curve(at, "pchip")
    rng = np.random.default_rng(5)
    yaw = rng.uniform(-0.02, 0.02, 1000)
    y = at(yaw) + rng.uniform(-0.75e-3, 0.75e-3, 1000)
    far = np.abs(y - at(yaw)) > 5e-6
    got, _, _, flags, _, _ = ip.evaluate(y[far], yaw[far])
    assert np.abs(got[:, 0] - _branch(y, y >= at(yaw))[far]).max() < 1e-12
    # a pose is flagged (one column answering) only where a column's own jump lies between it
    # and the jump curve at its yaw
    j = np.clip(np.searchsorted(yaw_axis, yaw[far]) - 1, 0, 3)
    own = np.stack([at(yaw_axis[j]), at(yaw_axis[j + 1])])
    side = y[far] >= at(yaw[far])
    crossed = ((own <= y[far]) != side).any(axis=0)
    assert not (flags[~crossed] & ti.UNMATCHED).any() and (flags[crossed] & ti.UNMATCHED).any()


def test_a_steep_onset_moving_with_its_jump_is_read_at_the_jump_distance_in_each_column():
    """Beside a flange jump the contact runs up a steep onset that moves with the jump (here
    0.47 + 2 mm * sqrt(u / 1 mm), u the distance above the jump, which moves 40 um per 10 mrad
    column). Between columns each column is read at the query's distance from its own jump
    (``lookup._warp``), so the columns agree and the blend is the onset itself; read at the same
    y they sit at points of the onset 40 um apart and the blend misses it by up to 38 um (with
    the warp off, ``WARP_STEPS = 0``; 0.017 um with it, the columns' own interpolation)."""
    at = lambda yaw: 0.2e-3 + 0.004 * yaw                          # noqa: E731 - m
    onset = lambda u: 0.47 + 2e-3 * np.sqrt(np.maximum(u, 0.0) / 1e-3)   # noqa: E731
    y_axis = np.linspace(-4e-3, 4e-3, 17)
    yaw_axis = np.linspace(-0.02, 0.02, 5)
    pos = at(yaw_axis)

    def value(y, yaw_pos):
        return np.where(y >= yaw_pos, onset(y - yaw_pos), 0.46 + 0.05 * y)

    rr = value(y_axis[:, None], pos[None, :])
    lo, hi = pos - 2e-6, pos + 2e-6
    jumps = {"jump_y": pos[:, None], "jump_y_lo": lo[:, None], "jump_y_hi": hi[:, None],
             "jump_side": np.ones((5, 1), np.int8)}
    limits = {"rolling_radius": np.stack([value(lo, pos + 1.0), value(hi, pos)],
                                         axis=1)[:, None, :]}
    # the refinement's knots above each column's jump (every 5 um up to 0.6 mm)
    u = np.arange(5e-6, 0.6e-3, 5e-6)
    knot_y = pos[:, None] + u[None, :]
    knots = {"rolling_radius": onset(u)[None, :].repeat(5, axis=0)}
    ip = ti.build(y_axis, yaw_axis, {"rolling_radius": rr}, jumps, limits, knot_y, knots,
                  modes={"rolling_radius": "pchip"})
    rng = np.random.default_rng(11)
    yaw = rng.uniform(-0.015, 0.015, 400)
    yaw = yaw[~np.isin(np.round(yaw, 9), np.round(yaw_axis, 9))]
    q = rng.uniform(20e-6, 200e-6, yaw.size)              # above the jump curve, in its onset
    got = ip.evaluate(at(yaw) + q, yaw)[0][:, 0]
    assert np.abs(got - onset(q)).max() < 2e-6     # measured 0.017 um; 38 um read at y


def test_a_jump_curve_bending_with_yaw_is_followed_where_it_bends():
    """A jump curve bends with yaw (evenly about yaw 0 on a symmetric pair): here y = 0.2 mm +
    8 m/rad^2 yaw^2 on five columns 10 mrad apart, 0.2 mm off the straight line between two
    columns at their middle. Between columns the jump lies on the cubic through the partners in
    the four nearest columns (Catmull-Rom; one-sided second-order slopes in an edge cell), which
    a quadratic curve it follows exactly: every query's distance to the jump is exact, and a
    query between the straight line and the curve lands on the curve's side."""
    at = lambda yaw: 0.2e-3 + 8.0 * yaw ** 2                       # noqa: E731 - m
    yaw_axis, ip = _one_jump_curve(at, "linear")
    rng = np.random.default_rng(8)
    yaw = rng.uniform(-0.02, 0.02, 2000)
    y = at(yaw) + rng.uniform(-0.3e-3, 0.3e-3, 2000)
    got, _, _, _, _, dist = ip.evaluate(y, yaw)
    assert np.abs(dist - (y - at(yaw))).max() < 1e-12
    # the straight line between the two columns' positions
    j = np.clip(np.searchsorted(yaw_axis, yaw) - 1, 0, 3)
    w = (yaw - yaw_axis[j]) / (yaw_axis[j + 1] - yaw_axis[j])
    chord = (1 - w) * at(yaw_axis[j]) + w * at(yaw_axis[j + 1])
    between = (np.minimum(chord, at(yaw)) + 5e-6 < y) & (y < np.maximum(chord, at(yaw)) - 5e-6)
    assert between.sum() > 200
    far = np.abs(y - at(yaw)) > 5e-6
    assert np.abs(got[far, 0] - _branch(y, y >= at(yaw))[far]).max() < 1e-12


def test_a_column_does_not_answer_far_beyond_its_piece_but_the_pose_still_interpolates():
    """The jump moves 1 mm (2 grid steps) per column and the upper branch kinks at y = 0.5 mm,
    between a query and the jump of the column that has not reached it yet: extending that
    column's piece would miss the kink, so the other column (whose piece holds the query)
    answers alone. The wheelset's height, which only kinks at a jump, still interpolates in
    yaw (exactly, being linear in yaw here)."""
    y_axis = np.linspace(-4e-3, 4e-3, 17)
    yaw_axis = np.linspace(-0.02, 0.02, 5)
    at = lambda yaw: -0.1e-3 + 0.1 * yaw                                    # noqa: E731 - m

    def rr(y, upper):
        return np.where(upper, 0.47 + y + 0.1 * np.maximum(0.0, 0.5e-3 - y), 0.46 + 0.05 * y)

    def zg(y, yaw):
        return 0.46 + 0.1 * yaw + 1e-3 * y

    ys, yaws = y_axis[:, None], yaw_axis[None, :]
    arrays = {"rolling_radius": rr(ys, ys >= at(yaws)), "z_g": zg(ys, yaws)}
    pos = at(yaw_axis)[:, None]
    lo, hi = pos - 2e-6, pos + 2e-6
    jumps = {"jump_y": pos, "jump_y_lo": lo, "jump_y_hi": hi,
             "jump_side": np.ones(pos.shape, np.int8)}
    limits = {"rolling_radius": np.stack([rr(lo, False), rr(hi, True)], axis=2),
              "z_g": np.stack([zg(lo, yaw_axis[:, None]), zg(hi, yaw_axis[:, None])], axis=2)}
    ip = ti.build(y_axis, yaw_axis, arrays, jumps, limits,
                  modes={"rolling_radius": "linear", "z_g": "linear"})
    assert ip.jumps.tolist() == [True, False]          # rolling radius jumps, z_g does not
    rng = np.random.default_rng(2)
    yaw = rng.uniform(-0.02, 0.02, 2000)
    y = at(yaw) + rng.uniform(-0.9e-3, 0.9e-3, 2000)
    keep = np.abs(y - at(yaw)) > 5e-6
    y, yaw = y[keep], yaw[keep]
    got, _, _, flags, _, _ = ip.evaluate(y, yaw)
    # exact up to round-off (extending the far column's piece instead: 7e-6 off)
    assert np.abs(got[:, 0] - rr(y, y >= at(yaw))).max() < 1e-12
    assert np.abs(got[:, 1] - zg(y, yaw)).max() < 1e-12
    # the poses answered by one column are flagged, and they are where the kink lies between
    assert (flags & ti.UNMATCHED).any() and not (flags & ti.UNMATCHED).all()


def test_pchip_slopes_match_scipy():
    """The piecewise slopes are SciPy's PchipInterpolator's (an independent implementation)."""
    from scipy.interpolate import PchipInterpolator

    x = np.array([0.0, 0.3, 0.5, 1.1, 1.2, 2.0])
    v = np.column_stack([np.sin(3 * x), x ** 3 - x, np.exp(-x)])
    want = PchipInterpolator(x, v, axis=0).derivative()(x)
    np.testing.assert_allclose(ti.pchip_slopes(x, v), want, rtol=1e-12, atol=1e-14)


def test_a_one_value_y_axis_interpolates_between_yaw_columns():
    """A grid of one lateral shift and several yaws (``grid.y_mm = [y, y, 1]``) answers between
    its yaw columns (the limit on a piece's extension is in grid steps of y, of which it has
    none: it divided by zero)."""
    ip = ti.build(np.array([0.0]), np.array([-0.01, 0.0, 0.01]),
                  {"z_g": np.array([[0.46, 0.461, 0.462]])})
    value, _, slope, flags, _, _ = ip.evaluate(np.array([0.0]), np.array([0.005]))
    assert value[0, 0] == pytest.approx(0.4615, abs=1e-15) and flags[0] == 0
    assert slope[0, 0] == pytest.approx(0.1, rel=1e-12)


def test_a_one_value_yaw_axis_is_a_valid_1d_grid(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
                   '[grid]\ny_mm = [-1.0, 1.0, 3]\nyaw_rad = [0.0, 0.0, 1]\n')
    assert load_config(cfg).grid.yaw_rad == (0.0, 0.0, 1)
    cfg.write_text(cfg.read_text().replace("[0.0, 0.0, 1]", "[0.0, 0.0, 2]"))
    with pytest.raises(Exception, match="grid.yaw_rad"):
        load_config(cfg)


# -- real profiles: Manchester S1002 / UIC60 1:40, the reference method ----------------------
MANCHESTER = REPO_ROOT / "configs" / "manchester_s1002_uic60_1in40.toml"


def _manchester_1d(tmp: Path, y_mm: tuple[float, float, int]) -> Path:
    text = MANCHESTER.read_text().replace("../profiles", str(REPO_ROOT / "profiles"))
    text = text.replace("y_mm = [-9.0, 9.0, 37]", f"y_mm = [{y_mm[0]}, {y_mm[1]}, {y_mm[2]}]")
    text = text.replace("yaw_rad = [-0.12, 0.12, 37]", "yaw_rad = [0.0, 0.0, 1]")
    text = text.replace('method = "load_centre"', 'method = "reference"')
    cfg = tmp / "m.toml"
    cfg.write_text(text + '\n[output]\nmethods = ["reference"]\n')
    return cfg


def _rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_query_agrees_with_solve_column_by_column(tmp_path):
    """Issue 11's must-show on a band of the Manchester 1-D table (0.5 mm step over 4..7 mm,
    two flange jumps): `query` at 0.05 mm vs `solve` (direct reference solves) -- rolling radii
    within 5 um and contact angles within 0.5 mrad farther than 0.02 mm from a located jump."""
    cfg = _manchester_1d(tmp_path, (4.0, 7.0, 7))
    table = tmp_path / "m.h5"
    assert main(["build", str(cfg), "-o", str(table)]) == 0
    poses = tmp_path / "p.csv"
    poses.write_text("y_mm,yaw_rad\n" + "".join(f"{4 + 0.05 * k:.2f},0\n" for k in range(61)))
    assert main(["query", str(table), "--poses", str(poses), "-o", str(tmp_path / "q.csv")]) == 0
    assert main(["solve", str(cfg), "--poses", str(poses), "-o", str(tmp_path / "s.csv")]) == 0
    q, s = _rows(tmp_path / "q.csv"), _rows(tmp_path / "s.csv")
    assert list(q[0])[:len(s[0])] == list(s[0])          # the same columns, same order
    far = [abs(float(r["jump_distance_mm"])) > 0.02 for r in q]
    assert sum(far) >= 55
    # primary contact (slot 0) of each wheel: 5 um, 0.5 mrad = 0.02865 deg (the targets)
    for col, tol in (("rolling_radius_{}_s0_mm", 5e-3),
                     ("contact_angle_{}_s0_deg", math.degrees(5e-4))):
        for side in ("left", "right"):
            c = col.format(side)
            err = [abs(float(a[c]) - float(b[c])) for a, b, f in zip(q, s, far, strict=True) if f]
            assert max(err) <= tol, (c, max(err))
    assert all(a["status"] == b["status"] == "0" for a, b in zip(q, s, strict=True))


def test_located_jumps_lie_where_direct_solves_put_them(tmp_path):
    """Each located jump J: direct solves at J - 0.01 mm and J + 0.01 mm differ (a contact
    count, or the primary contact point by more than the confirmation movement), so the jump the
    solver sees lies within +-0.01 mm of J; and a jump-free window of the same width does not."""
    from lutmpi.pose.solve import solve_pose
    from lutmpi.scene import Scene
    from lutmpi.table import Table
    from lutmpi.table.compute import pose_to_record

    cfg = _manchester_1d(tmp_path, (4.0, 7.0, 7))
    out = tmp_path / "m.h5"
    assert main(["build", str(cfg), "-o", str(out)]) == 0
    jy = Table.open(out).jump_positions()[0]
    jy = jy[np.isfinite(jy)]
    assert jy.size >= 2
    scene = Scene.from_config(load_config(cfg))

    def change(a, b):
        ka, kb = (tjs.state_key(pose_to_record(solve_pose(scene, y, 0.0, "reference"), FIELDS))
                  for y in (a, b))
        return tjs.classify(ka, kb, tjs.CONFIRM_M)[0]

    for y in jy:
        assert change(y - 1e-5, y + 1e-5), y
    quiet = 5.5e-3                                     # no located jump within 0.5 mm
    assert np.abs(jy - quiet).min() > 5e-4 and not change(quiet - 1e-5, quiet + 1e-5)


def test_refine_scale_is_stored_and_coarsens_only_the_refinement(tmp_path):
    """``output.refine_scale = 10`` on the Manchester band: the same jumps (their bisection does
    not use it), fewer extra knots, the factor in the jumps group's attributes and in the
    table-error report's rows (error against run time)."""
    import h5py

    from lutmpi.table import Table

    cfg = _manchester_1d(tmp_path, (4.0, 7.0, 7))
    coarse = tmp_path / "coarse.toml"
    coarse.write_text(cfg.read_text() + "refine_scale = 10.0\n")
    tables = {}
    for name, path in (("fine", cfg), ("coarse", coarse)):
        tables[name] = tmp_path / f"{name}.h5"
        assert main(["build", str(path), "-o", str(tables[name])]) == 0
    knots, scales = {}, {}
    for name, path in tables.items():
        with h5py.File(path, "r") as f:
            g = f["reference/jumps"]
            knots[name] = int(np.isfinite(g["knot_y"][()]).sum())
            scales[name] = float(g.attrs["refine_scale"])
    assert scales == {"fine": 1.0, "coarse": 10.0}
    np.testing.assert_array_equal(Table.open(tables["fine"]).jump_positions(),
                                  Table.open(tables["coarse"]).jump_positions())
    assert knots["coarse"] < knots["fine"], knots
    rep = tmp_path / "rep"
    assert main(["report", str(tables["fine"]), "-o", str(rep), "--table-error",
                 str(tables["coarse"])]) == 0
    rows = [line.split("|") for line in (rep / "table_error.md").read_text().splitlines()
            if line.startswith("| ") and "rolling_radius" in line]
    assert [(r[1].strip(), r[7].strip()) for r in rows] == [("fine.h5", "1"), ("coarse.h5", "10")]
    assert "0.3 into every grid cell along y, off the knots" in (rep / "table_error.md").read_text()


def test_simulate_leaving_the_table_stops_with_a_message_naming_the_pose(tmp_path, capsys):
    """A ±0.2 mm table: the paper's initial lateral velocity carries the wheelset beyond it
    (first peak ~0.44 mm at 27 m/s on this profile pair, README); the run stops non-zero."""
    cfg = tmp_path / "c.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
                   'inclination = "1:20"\n[grid]\ny_mm = [-0.2, 0.2, 5]\n'
                   'yaw_rad = [-0.004, 0.004, 3]\n[contact]\nmethod = "reference"\n'
                   '[output]\nmethods = ["reference"]\n')
    table = tmp_path / "t.h5"
    assert main(["build", str(cfg), "-o", str(table)]) == 0
    rc = main(["simulate", str(cfg), "--table", str(table), "--duration", "1", "--no-plots",
               "-o", str(tmp_path / "run.h5")])
    out = capsys.readouterr().out
    assert rc == 1
    assert "left the table at t = " in out and "pose y = " in out
    y = float(out.split("pose y = ")[1].split(" mm")[0])
    yaw = float(out.split("yaw = ")[1].split(" rad")[0])
    # stopped on the edge: located as an event, not a sample beyond it
    assert math.isclose(abs(y), 0.2, abs_tol=1e-4) or math.isclose(abs(yaw), 0.004, abs_tol=1e-6)
    assert abs(y) <= 0.2 + 1e-4 and abs(yaw) <= 0.004 + 1e-6


def test_table_error_report_equals_a_direct_recomputation(tmp_path):
    """The report's max errors are what Table.interp and direct solves give at its poses."""
    from lutmpi.pose.solve import solve_pose
    from lutmpi.reports import table_error
    from lutmpi.scene import Scene
    from lutmpi.table import Table
    from lutmpi.table.compute import pose_to_record

    cfg = _manchester_1d(tmp_path, (4.0, 7.0, 7))
    out = tmp_path / "m.h5"
    assert main(["build", str(cfg), "-o", str(out)]) == 0
    table = Table.open(out)
    scene = Scene.from_config(load_config(cfg))

    def solve(y, yaw):
        return pose_to_record(solve_pose(scene, y, yaw, "reference"), FIELDS)

    res = table_error.measure(table, solve, n_random=10)
    y, yaw = table_error.test_poses(table.y, table.yaw, 10)
    assert res.n_poses == y.size == 6 + 10 and res.n_failed == 0
    # off the knots: a cell midpoint is the refinement's first knot, where the table reads a
    # stored solve back and would report no error at all
    knots = table.jumps["reference"]["arrays"]["knot_y"]
    assert not np.isin(y, knots[np.isfinite(knots)]).any()
    q = table.interp(y, yaw, info=True)
    lin = table.interp(y, yaw, jump_aware=False)
    away = np.abs(q["jump_distance"]) > table_error.NEAR_M
    for name in ("rolling_radius", "contact_angle"):
        direct = np.array([solve(a, b)[name][:, 0] for a, b in zip(y, yaw, strict=True)])
        for interp, vals in (("jump_aware", q), ("linear", lin)):
            err = np.abs(vals[name][:, :, 0] - direct)[away]
            assert res.stats[interp][name]["away"][0] == err.max()
            assert res.stats[interp][name]["away"][1] == pytest.approx(
                np.sqrt(np.mean(err ** 2)), rel=1e-12)
    assert res.max_away("rolling_radius") <= 5e-6            # the must-show target
    assert res.max_away("rolling_radius", "linear") > 1e-4    # linear blends across the jumps
    assert table_error.cheapest([res], {"rolling_radius": 5e-6}) is res
    assert table_error.cheapest([res], {"rolling_radius": 1e-12}) is None


def test_simulate_reaching_a_failed_point_stops_with_its_status(tmp_path):
    """The test solver's corner (y < -8.9 mm, yaw < -0.119 rad) does not converge: a run started
    there stops at once with ON_FAILED_POINT and a message naming the pose, no number."""
    from lutmpi.dynamics.contact_provider import TableProvider
    from lutmpi.dynamics.simulate import ON_FAILED_POINT, simulate
    from lutmpi.parallel.runner import build_table
    from lutmpi.providers import params_from_table
    from lutmpi.table import Table
    from tests.support import faulty_solver
    from tests.support.tables import write_config

    cfg = load_config(write_config(tmp_path, ny=7, nyaw=5, methods=("reference",)))
    out = tmp_path / "t.h5"
    build_table(cfg, out, solver=faulty_solver.solve, scene_factory=faulty_solver.make_scene)
    table = Table.open(out)
    # the status change is a located jump (kind 4) next to the failed corner
    kinds = table.jumps["reference"]["arrays"]["jump_kind"][0]
    assert any(k & 4 for k in kinds)
    res = simulate(TableProvider(table), params_from_table(table), 27.0, 0.5, y0=-8.95e-3,
                   yaw0=-0.12, events=False)
    assert not res.success and res.status == ON_FAILED_POINT
    assert "reached a failed table point at t = 0.00000 s, pose y = -8.9500 mm" in res.message


# -- refinement bounded by the mesh (issue 14): the mesh's steps are not chased ---------------
H = 0.25e-3                                      # lateral node spacing of both meshes, m
GAMMA = math.radians(70.0)                       # a flange contact angle
REF_NAMES = ("status", "n_contacts", "rolling_radius", "contact_angle", "z_g", "roll",
             "indentation", "curv_wheel_transverse", "curv_rail_transverse")
REF_FLDS = limit_fields([f for f in FIELDS if f.name in REF_NAMES])


def flange_record(radius: float, *, delta: float = 5e-6, kappa: float = 0.0
                  ) -> dict[str, np.ndarray]:
    """A converged pose whose left wheel's primary contact has rolling radius ``radius`` at a
    70 degree contact angle (indentation ``delta``, both curvatures ``kappa``), everything else
    constant."""
    rec = {f.name: f.empty((1,))[0] for f in REF_FLDS}
    rec["status"] = np.int8(CONVERGED)
    rec["n_contacts"] = np.array([1, 1], np.int8)
    rec["z_g"], rec["roll"] = np.float64(0.46), np.float64(0.0)
    for name, v in (("rolling_radius", [radius, 0.46]), ("contact_angle", [GAMMA, 0.003]),
                    ("indentation", [delta, delta]), ("curv_wheel_transverse", [kappa, kappa]),
                    ("curv_rail_transverse", [kappa, kappa])):
        rec[name][:, 0] = v
    return rec


def node_mesh(centroid: bool = False) -> trf.MeshResolution:
    return trf.MeshResolution(np.full((2, 2), H), centroid)


def test_tolerances_follow_the_step_the_mesh_resolves():
    """Closed forms: a node-picking method steps by h sin(gamma) in rolling radius and
    h kappa in contact angle; a centroid over n = 2 a / h node columns, a = sqrt(2 delta /
    (kappa_w + kappa_r)), by 1/n of that; no mesh, or a conformal pair: the fixed tolerances."""
    kappa = 80.0
    recs = [flange_record(0.47, kappa=kappa)] * 3
    tol = trf.tolerances(recs, node_mesh())
    assert tol["rolling_radius"][0] == pytest.approx(0.5 * H * math.sin(GAMMA))
    assert tol["rolling_radius"][1] == trf.REFINE_TOL["rolling_radius"]   # 0.003 rad: below
    assert tol["contact_angle"][0] == pytest.approx(0.5 * H * kappa)
    n = 2.0 * math.sqrt(2.0 * 5e-6 / (2 * kappa)) / H                   # 2.0 node columns
    tol = trf.tolerances(recs, node_mesh(centroid=True))
    assert tol["rolling_radius"][0] == pytest.approx(0.5 * H * math.sin(GAMMA) / n)
    assert tol["contact_angle"][0] == pytest.approx(0.5 * H * kappa / n)
    assert trf.tolerances(recs, None) == trf.REFINE_TOL
    conformal = [flange_record(0.47, kappa=-1.0)] * 3
    tol = trf.tolerances(conformal, node_mesh(centroid=True))
    assert tol["rolling_radius"][0] == trf.REFINE_TOL["rolling_radius"]


def test_variation_below_the_mesh_step_is_not_chased_and_above_it_is_refined_to_it():
    """On a 70 degree flange a node-picking solver's rolling radius moves in steps of
    h sin(gamma) = 235 um: variation below half of that is below what the solver resolves. A
    square-root onset whose misses stay below it (50 um at 0.5 mm, falling by 0.71 per halving)
    is refined down to the minimum width when the refinement ignores the mesh, and left at one
    midpoint with the mesh's tolerance. A true curvature far above the step (c y^2) is still
    refined until a straight line between knots misses by at most the mesh's tolerance, and no
    further."""
    step = H * math.sin(GAMMA)
    w = 0.5e-3
    a = 50e-6 / ((math.sqrt(0.5) - 0.5) * math.sqrt(w))

    def onset(y, yaw):
        return flange_record(0.47 + a * math.sqrt(y))

    r0, r1 = onset(0.0, 0.0), onset(w, 0.0)
    free = trf.refine_interval(0.0, r0, w, r1, 0.0, onset)
    bounded = trf.refine_interval(0.0, r0, w, r1, 0.0, onset, mesh=node_mesh())
    # unbounded: the interval at the onset halves from 500 um while it is at least twice
    # MIN_WIDTH_M (10 um) wide (6 midpoints; its miss 0.207 a sqrt(w) stays above 1 um and
    # falls by 0.71), and its right siblings [w, 2w] (miss 0.0176 a sqrt(w) >= 1 um) are
    # refined too: 19 knots, the narrowest 7.8 um apart
    assert len(bounded) == 1 and len(free) >= 16
    gaps = np.diff([y for y, _ in free])
    assert trf.MIN_WIDTH_M <= gaps.min() < 4 * trf.MIN_WIDTH_M   # down to the floor, never below

    c = 1e4                                      # 1/m: misses c w^2 / 4 = 625 um over 0.5 mm

    def bowl(y, yaw):
        return flange_record(0.47 + c * y * y)

    knots = trf.refine_interval(0.0, bowl(0.0, 0.0), w, bowl(w, 0.0), 0.0, bowl, mesh=node_mesh())
    ys = [0.0] + [y for y, _ in knots] + [w]
    widths = np.diff(ys)
    floor = 0.5 * step
    # each last interval (two knot spacings wide: its midpoint is a knot) met the tolerance,
    # its parent did not
    assert (c * (2 * widths) ** 2 / 4 <= floor).all()
    assert (c * (4 * widths) ** 2 / 4 > floor).all()
    assert len(knots) == 7


def test_refine_scale_multiplies_every_tolerance_and_refines_to_it():
    """``output.refine_scale``: every tolerance (fixed or the mesh's) times the factor, 1 the
    same numbers; a bowl ``c y^2`` (midpoint miss ``c w^2 / 4`` on an interval of width ``w``)
    is refined until each last interval meets the scaled rolling-radius tolerance and its
    parent does not, so a factor of 16 leaves knots 4 times wider."""
    recs = [flange_record(0.47, kappa=80.0)] * 3
    for mesh in (None, node_mesh(), node_mesh(centroid=True)):
        base = trf.tolerances(recs, mesh)
        same, scaled = trf.tolerances(recs, mesh, 1.0), trf.tolerances(recs, mesh, 3.0)
        assert same.keys() == scaled.keys() == base.keys()
        for name in base:
            np.testing.assert_array_equal(same[name], base[name])
            np.testing.assert_allclose(scaled[name], 3.0 * np.asarray(base[name]), rtol=1e-15)
    c, w = 1e2, 4e-3                              # misses 400 um over 4 mm

    def bowl(y, yaw):
        return flange_record(0.47 + c * y * y)

    widths = {}
    for scale in (1.0, 16.0):
        knots = trf.refine_interval(0.0, bowl(0.0, 0.0), w, bowl(w, 0.0), 0.0, bowl,
                                   scale=scale)
        widths[scale] = np.diff([0.0] + [y for y, _ in knots] + [w])
        tol = scale * trf.REFINE_TOL["rolling_radius"]
        assert (c * (2 * widths[scale]) ** 2 / 4 <= tol).all()
        assert (c * (4 * widths[scale]) ** 2 / 4 > tol).all()
    assert widths[16.0].min() == pytest.approx(4 * widths[1.0].min())
    assert widths[1.0].size > 3 * widths[16.0].size


def test_pchip_mid_is_the_tables_monotone_cubic():
    """The refinement's scalar cubic (:func:`lutmpi.table.refine.pchip_mid`, Python floats) is
    the table's PCHIP through the same two to four knots, to the bit: monotone and
    non-monotone data, a flat secant, the piece's first and last interval."""
    rng = np.random.default_rng(7)
    checked = 0
    for trial in range(600):
        n = int(rng.integers(2, 5))
        x = np.sort(rng.uniform(0.0, 1e-3, n))
        if np.diff(x).min() < 1e-6:
            continue
        v = np.cumsum(rng.uniform(0.0, 1e-5, n)) if trial % 2 else rng.normal(0.46, 1e-5, n)
        if trial % 5 == 0:
            v[1] = v[0]
        for has_left in ((False, True) if n == 3 else (n == 4,)):
            i = 1 if has_left else 0
            xm = x[i] + rng.uniform() * (x[i + 1] - x[i])
            want = ti._predict_pchip(x, v[:, None], np.array([xm]))[0, 0]
            assert trf.pchip_mid(x.tolist(), v.tolist(), has_left, float(xm)) == want
            checked += 1
    assert checked > 500


def _bowl_pose(c: float):
    """A solver whose pose is a bowl, ``z_g = 0.46 + c y^2`` (m), contact constant."""
    def solve(y, yaw):
        rec = flange_record(0.47)
        rec["z_g"] = np.float64(0.46 + c * y * y)
        return rec
    return solve


def test_the_pose_is_refined_against_the_cubic_through_its_neighbours():
    """z_g (and roll) are smooth within a piece and the table interpolates them by the
    monotone cubic: an interval is refined while that cubic, through its knots and their
    neighbours in the piece, misses the midpoint by more than 2 um, not the straight line. A
    bowl z_g = 0.46 + c y^2 over grid knots 0.5 mm apart (c = 1000 /m: the straight line misses
    a midpoint by c w^2 / 4 = 62.5 um) needs knots 62.5 um apart for the straight line; the
    cubic far fewer. The rule bounds the cubic's miss at each midpoint it solves, with the
    slopes the knots had then; a knot's PCHIP slope moves when a neighbouring interval gains
    knots later (here 2.4 um between 1.5 and 1.75 mm, next to a knot whose neighbours end up
    62.5 and 250 um away), so the table built from them is held to half as much again."""
    c, tol = 1e3, trf.REFINE_TOL["z_g"]
    y_axis = np.linspace(0.5e-3, 4e-3, 8)
    solve = _bowl_pose(c)
    recs = [solve(float(y), 0.0) for y in y_axis]
    arrays = {f.name: np.stack([r[f.name] for r in recs])[:, None] for f in REF_FLDS}
    js = tj.locate_jumps(arrays, y_axis, np.zeros(1), solve, REF_FLDS)
    knots = np.sort(js.knot_y[0][np.isfinite(js.knot_y[0])])
    # the straight line's rule: misses 31, 7.8, 2.0 and 0.49 times 2 um at widths 0.5, 0.25,
    # 0.125 and 0.0625 mm, each falling by 1/4 (REFINE_GAIN holds): 1 + 2 + 4 + 8 midpoints in
    # each of the 7 grid intervals
    line = 7 * (1 + 2 + 4 + 8)
    assert 0 < knots.size <= line / 4
    ip = ti.build(y_axis, np.zeros(1), arrays, js.arrays, js.limits, js.knot_y, js.knots,
                  modes={"z_g": "pchip"})
    yq = np.linspace(y_axis[0], y_axis[-1], 2001)
    z = ip.evaluate(yq, np.zeros_like(yq))[0][:, ip.layout.slots["z_g"][0]]
    assert np.abs(z - (0.46 + c * yq * yq)).max() <= 1.5 * tol


def test_the_pose_is_always_read_with_the_cubic_it_was_refined_for():
    """``choose_modes`` picks by measured error, but not for the pose: its knots were placed for
    the monotone cubic, so z_g and roll are ``pchip`` even where the straight line predicts
    the knots as well (data linear in y: a tie, which goes to ``linear`` for the rest)."""
    y_axis = np.linspace(0.0, 4e-3, 9)
    ramp = (0.46 + 1e-3 * y_axis)[:, None]
    arrays = {"status": np.full((9, 1), CONVERGED, np.int8), "z_g": ramp.copy(),
              "roll": 1e-2 * ramp, "x_g": ramp.copy()}
    modes = ti.choose_modes(y_axis, arrays)
    assert modes == {"z_g": "pchip", "roll": "pchip", "x_g": "linear"}


def test_contact_quantities_keep_the_straight_line_with_neighbours_given():
    """The rolling radius and contact angle are refined against the straight line whatever the
    neighbours (their table interpolant is chosen from their knots, often linear): a bowl in
    the rolling radius gives the same knots with and without them."""
    c, w = 1e2, 4e-3

    def bowl(y, yaw):
        return flange_record(0.47 + c * y * y)

    plain = trf.refine_interval(0.0, bowl(0.0, 0.0), w, bowl(w, 0.0), 0.0, bowl)
    outer = ((-w, bowl(-w, 0.0)), (2 * w, bowl(2 * w, 0.0)))
    given = trf.refine_interval(0.0, bowl(0.0, 0.0), w, bowl(w, 0.0), 0.0, bowl, outer=outer)
    assert [y for y, _ in given] == [y for y, _ in plain] and len(plain) > 3


def test_neighbours_stay_in_the_piece():
    """The outer knots of a knot pair are its neighbours in the same piece, None across a
    jump or at the column's ends."""
    rec = flange_record(0.47)
    knots = [(0.0, rec, 0), (1.0, rec, 0), (2.0, rec, 0), (3.0, rec, 1), (4.0, rec, 1)]
    assert [(a and a[0], b and b[0]) for a, b in
            (trf.neighbours(knots, k) for k in (0, 1, 3))] == [(None, 2.0), (0.0, None),
                                                              (None, None)]


def test_records_cross_ranks_as_columns_unchanged():
    """The jump step's transport (:func:`lutmpi.parallel.jumps_step._pack`): records inside
    lists, tuples and jumps come back with the same names, dtypes, shapes and bits."""
    import pickle

    from lutmpi.parallel import jumps_step as js

    recs = [flange_record(0.47 + 1e-6 * k, kappa=float(k)) for k in range(5)]
    jump = tjs.Jump(3, 1e-3, 1.005e-3, recs[0], recs[1], 1, 2)
    done = [(0, ([jump], [(1e-3, recs[2])])), (4, [(2e-3, recs[3]), (3e-3, recs[4])])]
    back = js._unpack(*pickle.loads(pickle.dumps(js._pack(done))))
    assert back[0][0] == 0 and back[1][0] == 4
    pairs = [(jump.rec_lo, back[0][1][0][0].rec_lo), (jump.rec_hi, back[0][1][0][0].rec_hi),
             (recs[2], back[0][1][1][0][1]), (recs[3], back[1][1][0][1]),
             (recs[4], back[1][1][1][1])]
    assert back[0][1][0][0].lo == jump.lo and back[1][1][1][0] == 3e-3
    for want, got in pairs:
        assert list(want) == list(got)
        for name in want:
            a, b = np.asarray(want[name]), np.asarray(got[name])
            assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def test_records_of_grid_nodes_and_solves_cross_ranks_together():
    """A bracket end the bisection kept is a grid node's record, with the timing fields a
    solved record leaves out; a rank's share can start with either. The transport sends the
    names all its records hold (it raised KeyError when a grid node's record came first)."""
    from lutmpi.parallel import jumps_step as js

    solved = [flange_record(0.47 + 1e-6 * k) for k in range(3)]
    node = dict(solved[0], compute_time=np.float64(1e-3))
    jump = tjs.Jump(0, 1e-3, 1.005e-3, node, solved[1], 1, 1)
    for done in ([(0, ([jump], [(1e-3, solved[2])]))],                # the node's record first
                 [(0, ([], [(1e-3, solved[2])])), (1, ([jump], []))]):  # a solved one first
        back = js._unpack(*js._pack(done))
        jp = next(j for _, (jps, _) in back for j in jps)
        assert set(jp.rec_lo) == set(solved[0])
        assert jp.rec_lo["z_g"].tobytes() == node["z_g"].tobytes()
        assert jp.rec_hi["rolling_radius"].tobytes() == solved[1]["rolling_radius"].tobytes()


@pytest.mark.parametrize("steps, in_part", [(5, False), (11, True)])
def test_a_cell_with_more_jumps_than_the_search_takes_is_reported(steps, in_part, caplog):
    """A left contact point that jumps by 2.5 mm ``steps`` times inside one 0.5 mm cell (every
    30 um from y = 0.1 mm): 5 jumps are all located; 11 exceed MAX_PER_CELL (8), the cell is
    searched in part, and that is reported (a warning naming the cell, and
    :func:`searched_in_part`), not left silent."""
    assert tjs.MAX_PER_CELL == 8
    at = 0.1e-3 + 30e-6 * np.arange(steps)

    def staircase(y: float, yaw: float) -> dict[str, np.ndarray]:
        rec = synthetic(-1e-3, yaw)                     # below the synthetic jump: smooth
        k = int(np.sum(y >= at))
        rec["wheel_s"][0, 0] += 2.5e-3 * k
        rec["rail_v"][0, 0] += 2.5e-3 * k
        return rec

    y_axis = np.array([-0.5e-3, 0.0, 0.5e-3, 1.0e-3])
    yaw_axis = np.array([0.0])
    arrays = {f.name: f.empty((y_axis.size, 1)) for f in FLDS}
    for i, y in enumerate(y_axis):
        for name, v in staircase(float(y), 0.0).items():
            arrays[name][i, 0] = v
    cells = tjs.candidate_cells(arrays)
    assert cells == [(0, 1)]
    res = [tjs.refine_cell(arrays, y_axis, yaw_axis, c, staircase) for c in cells]
    jumps = res[0][0]
    assert len(jumps) == min(steps, tjs.MAX_PER_CELL)
    assert all(any(jp.lo < t <= jp.hi for t in at) for jp in jumps)
    got = tjs.searched_in_part(arrays, y_axis, cells, res)
    assert got == ([(0, 0.0, 0.5e-3)] if in_part else [])
    with caplog.at_level("WARNING", logger="lutmpi.table.jump_search"):
        tj.locate_jumps(arrays, y_axis, yaw_axis, staircase, FLDS, refine=False)
    assert ("located in part" in caplog.text) == in_part


def _column(fn, y_axis: np.ndarray) -> dict[str, np.ndarray]:
    """One yaw column (yaw 0) of the closed-form ``fn(y, yaw) -> record`` at ``y_axis``."""
    out = {f.name: f.empty((y_axis.size, 1)) for f in FLDS}
    for i, y in enumerate(y_axis):
        for name, v in fn(float(y), 0.0).items():
            out[name][i, 0] = v
    return out


def _fast_flange(at: float):
    """A left contact that runs 1.9 mm along the profile per mm of y and steps by 0.85 mm at
    ``at`` (rolling radius 0.478 m - s: a 0.85 mm step), the contacts unchanged: what a
    hostile tester met on a measured worn flange (Car7216 on the Manchester rail, yaw 0.05)."""
    def fast(y: float, yaw: float) -> dict[str, np.ndarray]:
        rec = synthetic(-1e-3, yaw)                      # smooth base: tread side
        s = -0.04 - 1.9 * y - (0.85e-3 if y >= at else 0.0)
        rec["wheel_s"][:, 0] = [s, -y]
        rec["rail_v"][:, 0] = [-0.03 - 0.2 * y, y]
        rec["rolling_radius"][:, 0] = [0.478 - s, 0.46]
        rec["z_g"] = np.float64(0.46 + 0.02 * y)
        return rec
    return fast


def test_a_step_inside_a_fast_moving_contact_is_located_by_the_refinement():
    """No cell shows the step: the cell holding it moves 1.8 mm (below 2 mm) and less than
    twice its neighbours' 0.95 mm. The refinement's miss does not fall when the interval
    halves while the contact moves by more than CONFIRM_M: the interval is searched, the jump
    located within the tolerance, and the table reads both branches exactly beside it.
    Before, the refinement ran a straight line across it (0.42 mm of rolling radius at the
    step); it still does with ``refine=False``, which finds nothing."""
    at = 1.234e-3
    fast = _fast_flange(at)
    y_axis, yaw_axis = np.linspace(-2e-3, 4e-3, 13), np.array([0.0])
    arrays = _column(fast, y_axis)
    assert tjs.candidate_cells(arrays) == []
    assert tj.locate_jumps(arrays, y_axis, yaw_axis, fast, FLDS, refine=False).count.tolist() == [0]
    js = tj.locate_jumps(arrays, y_axis, yaw_axis, fast, FLDS)
    assert js.count.tolist() == [1]
    lo, hi = js.arrays["jump_y_lo"][0, 0], js.arrays["jump_y_hi"][0, 0]
    assert lo < at <= hi and hi - lo <= tjs.TOL_M
    assert js.arrays["jump_kind"][0, 0] == 1 and js.arrays["jump_side"][0, 0] == 1
    ip = ti.build(y_axis, yaw_axis, arrays, js.arrays, js.limits, js.knot_y, js.knots)
    off = ip.layout.slots["rolling_radius"][0]
    y = at + np.array([-200e-6, -20e-6, -4e-6, 4e-6, 20e-6, 200e-6])
    want = [fast(v, 0.0)["rolling_radius"][0, 0] for v in y]
    got = ip.evaluate(y, np.zeros(y.size))[0][:, off]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)


def test_changes_that_cancel_within_a_cell_are_located_by_the_refinement():
    """A second contact comes and goes within 40 um of one cell, the contact otherwise still:
    the cell's ends agree, so no cell is searched. The refinement's midpoint lands in it, and
    both changes are located (before, that midpoint was dropped and the table ran across
    them); the table then reads two contacts inside and one outside."""
    at = (0.2312e-3, 0.2688e-3)

    def flicker(y: float, yaw: float) -> dict[str, np.ndarray]:
        rec = synthetic(-1e-3, yaw)
        rec["n_contacts"] = np.array([2 if at[0] <= y < at[1] else 1, 1], np.int8)
        return rec

    y_axis, yaw_axis = np.linspace(-0.5e-3, 1.0e-3, 4), np.array([0.0])
    arrays = _column(flicker, y_axis)
    assert tjs.candidate_cells(arrays) == []
    js = tj.locate_jumps(arrays, y_axis, yaw_axis, flicker, FLDS)
    assert js.count.tolist() == [2]
    assert np.abs(js.arrays["jump_y"][0, :2] - np.array(at)).max() <= tjs.TOL_M / 2
    assert js.arrays["jump_kind"][0, :2].tolist() == [2, 2]
    ip = ti.build(y_axis, yaw_axis, arrays, js.arrays, js.limits, js.knot_y, js.knots)
    off = ip.layout.slots["n_contacts"][0]
    y = np.array([0.2e-3, 0.25e-3, 0.3e-3])
    got = ip.evaluate(y, np.zeros(3))[0][:, off]
    assert got.tolist() == [1, 2, 1]


def test_a_jump_the_refinement_finds_is_reflected_into_the_image_column():
    """On a grid symmetric in yaw, the interval of yaw -a is refined and the one of +a is its
    image (x -> -x): the jump found inside the one is stored in both columns, at the same y,
    and the image's interval is not solved."""
    at = 1.234e-3
    fast = _fast_flange(at)
    y_axis, yaw_axis = np.linspace(-2e-3, 4e-3, 13), np.array([-0.01, 0.0, 0.01])
    arrays = {f.name: f.empty((y_axis.size, yaw_axis.size)) for f in FLDS}
    for i, y in enumerate(y_axis):
        for j, yaw in enumerate(yaw_axis):
            for name, v in fast(float(y), float(yaw)).items():
                arrays[name][i, j] = v
    counts = {}
    for mirror in (None, tm.Mirror.of(y_axis, yaw_axis, False)):
        calls: list[tuple[float, float]] = []

        def solve(y: float, yaw: float, calls: list = calls) -> dict[str, np.ndarray]:
            calls.append((y, yaw))
            return fast(y, yaw)

        js = tj.locate_jumps(arrays, y_axis, yaw_axis, solve, FLDS, mirror=mirror)
        assert js.count.tolist() == [1, 1, 1]
        np.testing.assert_array_equal(js.arrays["jump_y"][0], js.arrays["jump_y"][2])
        counts[mirror is None] = len(calls)
        if mirror is not None:
            assert all(yaw <= 0.0 for _, yaw in calls)
    assert counts[False] < counts[True]


def _readme_pair_column(tmp: Path, y_mm: tuple[float, float, int], yaw: float):
    """The README's asymmetric pair built with the reference method on one yaw column: its
    scene, the table and the column's located jumps (m)."""
    from lutmpi.scene import Scene
    from lutmpi.table import Table
    from tests.support.tables import README_ASYMMETRIC

    cfg = tmp / "asym.toml"
    cfg.write_text(README_ASYMMETRIC + f"""[grid]
y_mm = [{y_mm[0]}, {y_mm[1]}, {y_mm[2]}]
yaw_rad = [{yaw}, {yaw}, 1]
[contact]
method = "reference"
""")
    out = tmp / "a.h5"
    assert main(["build", str(cfg), "-o", str(out)]) == 0
    table = Table.open(out)
    jy = table.jump_positions()[0]
    return Scene.from_config(load_config(cfg)), table, jy[np.isfinite(jy)]


def test_a_measured_worn_flange_step_no_cell_shows_is_in_the_table(tmp_path):
    """The hostile tester's pair (the README's asymmetric example: measured worn wheels
    Car7216 / Car7358 on the Manchester rail / a worn rail), yaw 0.05 rad, 1 mm grid: on the
    left flange the contact runs ~1.9 mm per mm of y and steps by 0.85 mm at y = 5.2495 mm
    (rolling radius +1.4 mm), in a cell no candidate rule flags. The table now holds a jump
    there, and `query` agrees with `solve` beside it (the rolling radius was 0.79 mm off at
    5.24 mm, z_g 49 um)."""
    from lutmpi.pose.solve import solve_pose

    scene, table, jy = _readme_pair_column(tmp_path, (3.0, 7.0, 5), 0.05)
    assert np.abs(jy - 5.2495e-3).min() < 20e-6, jy * 1e3
    y = np.array([5.10, 5.20, 5.24, 5.255, 5.28, 5.40]) * 1e-3
    assert np.abs(y[:, None] - jy[None, :]).min() > 5e-6
    q = table.interp(y, np.full(y.size, 0.05))
    for i, yi in enumerate(y):
        r = solve_pose(scene, float(yi), 0.05, "reference")
        left = r.contacts["left"][0]                      # the reference's touching contact
        assert abs(q["rolling_radius"][i][0, 0] - left.rolling_radius) < 20e-6, yi
        assert abs(q["z_g"][i] - r.z_g) < 2e-6, yi



def test_a_jump_the_refinement_finds_is_reflected_onto_the_other_wheel():
    """A symmetric pair (each wheel the other's image in y): the left wheel's contact runs
    fast along its flange and steps at +at, the right wheel's at -at. On a grid symmetric in y
    and yaw the refinement's intervals for y < 0 are the images of those for y > 0 with the
    wheels swapped (``Mirror`` with ``symmetric_pair``): the jump found at +at (left wheel)
    is stored at -at too, on the right wheel (side bit 2), its bracket's ends swapped, with
    the same jumps as a direct run (no mirror) and fewer solves."""
    at, rate, step = 1.234e-3, 1.9, 0.85e-3

    def g(y: float) -> float:
        return -0.04 - rate * y - (step if y >= at else 0.0)

    def pair(y: float, yaw: float) -> dict[str, np.ndarray]:
        rec = {f.name: f.empty((1,))[0] for f in FLDS}
        rec["status"] = np.int8(CONVERGED)
        rec["n_contacts"] = np.array([1, 1], np.int8)
        rec["z_g"] = np.float64(0.46 + 0.1 * y * y)
        s_l, s_r = g(y), g(-y)
        rec["wheel_s"][:, 0] = [s_l, s_r]
        rec["rail_v"][:, 0] = [-0.03 - 0.2 * y, -0.03 + 0.2 * y]
        rec["rolling_radius"][:, 0] = [0.478 - s_l, 0.478 - s_r]
        return rec

    y_axis, yaw_axis = np.linspace(-4e-3, 4e-3, 17), np.array([0.0])
    arrays = _column(pair, y_axis)
    assert tjs.candidate_cells(arrays) == []
    got = {}
    for mirror in (None, tm.Mirror.of(y_axis, yaw_axis, True)):
        calls: list[float] = []

        def solve(y: float, yaw: float, calls: list = calls) -> dict[str, np.ndarray]:
            calls.append(y)
            return pair(y, yaw)

        js = tj.locate_jumps(arrays, y_axis, yaw_axis, solve, FLDS, mirror=mirror)
        got[mirror is None] = (js, len(calls))
    (direct, n_direct), (mirrored, n_mirrored) = got[True], got[False]
    assert n_mirrored < n_direct
    for js in (direct, mirrored):
        assert js.count.tolist() == [2]
        lo, hi = js.arrays["jump_y_lo"][0, :2], js.arrays["jump_y_hi"][0, :2]
        assert lo[0] < -at + 1e-12 and -at - 1e-12 <= hi[0] and lo[1] < at <= hi[1]
        assert (hi - lo).max() <= tjs.TOL_M
        assert js.arrays["jump_side"][0, :2].tolist() == [2, 1]
    np.testing.assert_allclose(mirrored.arrays["jump_y"], direct.arrays["jump_y"], atol=1e-15)
    # the one-sided limits are the branches: below -at the right wheel is past its step
    lo, hi = mirrored.arrays["jump_y_lo"][0, 0], mirrored.arrays["jump_y_hi"][0, 0]
    right = mirrored.limits["wheel_s"][0, 0, :, 1, 0]
    assert right.tolist() == pytest.approx([g(-lo), g(-hi)])


def test_an_interval_at_the_refinements_floor_whose_contact_still_moves_is_searched():
    """Two knots 7.8 um apart (narrower than twice MIN_WIDTH_M: the refinement halves no
    further) whose primary contact lies 1.3 mm apart: the interval is searched as a cell's
    bracket is, and the jump stored within TOL_M / 2 with a solve or two. Without ``found``
    (nothing kept) and where the contact moves less than CONFIRM_M nothing is solved."""
    at = 3.1e-6

    def switch(y: float, yaw: float) -> dict[str, np.ndarray]:
        rec = synthetic(-1e-3, yaw)
        s = -0.0400 - 0.1 * y + (1.3e-3 if y >= at else 0.0)
        rec["wheel_s"][:, 0] = [s, -y]
        rec["rolling_radius"][:, 0] = [0.478 - s, 0.46]
        return rec

    w = 7.8e-6
    assert w < 2 * trf.MIN_WIDTH_M
    calls: list[float] = []

    def solve(y: float, yaw: float) -> dict[str, np.ndarray]:
        calls.append(y)
        return switch(y, yaw)

    r0, r1 = switch(0.0, 0.0), switch(w, 0.0)
    assert trf.refine_interval(0.0, r0, w, r1, 0.0, solve) == [] and calls == []
    found: list = []
    knots = trf.refine_interval(0.0, r0, w, r1, 0.0, solve, found=found, iyaw=2)
    assert len(found) == 1 and 1 <= len(calls) <= 2
    jp = found[0]
    assert jp.iyaw == 2 and jp.lo < at <= jp.hi and jp.hi - jp.lo <= tjs.TOL_M
    assert jp.kind == 1 and jp.side == 1
    assert all(not jp.lo < y < jp.hi for y, _ in knots)
    calls.clear()
    still = switch(w, 0.0)
    still["wheel_s"][0, 0] = r0["wheel_s"][0, 0] + 0.4e-3      # moves less than CONFIRM_M
    assert trf.refine_interval(0.0, r0, w, still, 0.0, solve, found=found) == []
    assert calls == [] and len(found) == 1


def test_a_primary_switch_between_knots_at_the_refinements_floor_is_in_the_table(tmp_path):
    """The README's asymmetric pair at yaw -0.1 rad: the right wheel has two contacts between
    y = -5.7793 and -5.7480 mm, and within that its primary contact (the larger force) moves
    from the flange root to the flange at y = -5.7637 mm (rolling radius -2.4 mm). The cell
    search bisects the contact count's changes; the switch fell between two of its samples
    7.8 um apart, narrower than the refinement halves, and the table ran a straight line
    across it (1.2 mm off in the middle). An interval at the refinement's floor whose
    contact still moves by more than CONFIRM_M is now searched as a bracket."""
    from lutmpi.pose.solve import solve_pose

    scene, table, jy = _readme_pair_column(tmp_path, (-7.0, -5.0, 3), -0.1)

    def right_primary(y: float):
        r = solve_pose(scene, y, -0.1, "reference")
        return max(r.contacts["right"], key=lambda c: float(c.force))

    # a jump the direct solves confirm: within 3 um either side of it the right wheel's primary
    # contact lies more than 1 mm apart along the profile, the rolling radius 2 mm apart
    window = jy[(jy > -5.775e-3) & (jy < -5.752e-3)]     # between the count changes
    assert window.size == 1, jy * 1e3
    below, above = right_primary(float(window[0]) - 3e-6), right_primary(float(window[0]) + 3e-6)
    assert abs(above.wheel_s - below.wheel_s) > 1e-3
    assert abs(above.rolling_radius - below.rolling_radius) > 2e-3
    y = np.array([-5.7700, -5.7690, -5.7600, -5.7590, -5.7560]) * 1e-3
    assert np.abs(y[:, None] - jy[None, :]).min() > 3e-6
    q = table.interp(y, np.full(y.size, -0.1))
    for i, yi in enumerate(y):
        r = solve_pose(scene, float(yi), -0.1, "reference")
        assert abs(q["rolling_radius"][i][1, 0] - right_primary(float(yi)).rolling_radius) < 20e-6
        assert abs(q["z_g"][i] - r.z_g) < 2e-6, yi


def test_a_query_typed_at_a_grid_value_is_read_on_that_column_and_knot():
    """The grid's yaw 0.05 is 0.05000000000000002 (``numpy.linspace(-0.1, 0.1, 5)``): a user's
    0.05 lies 4e-16 below it, in the cell below, with a weight of 1e-16 on the column beyond.
    A NaN there (a failed pose, or a second contact that column lacks) made the answer NaN
    although the query is on a column whose value is known (a measured pair: the second
    contact's rolling radius NaN at y = -3.47 mm, yaw 0.05; the whole pose NaN on another).
    The same along y at a knot. Within :data:`lutmpi.table.lookup.SNAP` of the interval the
    query is read on the column, or the knot, alone; exactly between them nothing changes."""
    y_axis, yaw_axis = np.linspace(-9e-3, 9e-3, 19), np.linspace(-0.1, 0.1, 5)
    assert yaw_axis[3] != 0.05 and y_axis[5] != -4e-3
    z = 0.46 + 0.01 * y_axis[:, None] + 0.02 * yaw_axis[None, :]
    z[:, 2] = np.nan                                      # the yaw-0 column failed
    z[4, :] = np.nan                                      # the y = -5 mm row failed
    ip = ti.build(y_axis, yaw_axis, {"z_g": z})
    y = np.array([1e-3, 1e-3, -4e-3, y_axis[5]])
    value = ip.evaluate(y, np.array([0.05, yaw_axis[3], 0.07, 0.07]))[0][:, 0]
    want = 0.46 + 0.01 * y + 0.02 * np.array([yaw_axis[3], yaw_axis[3], 0.07, 0.07])
    np.testing.assert_allclose(value, want, rtol=0, atol=1e-12)
    assert np.isnan(ip.evaluate(np.array([1e-3]), np.array([0.04]))[0][0, 0])   # a true blend


def test_two_columns_ordering_one_double_contact_differently_blend_contact_by_contact():
    """A double contact on the left wheel at s = 7.33 and 3.48 mm in one yaw column and the
    same two contacts in the other order in the next (a column orders its contacts by force;
    the reference method by the solver's order, which flips): blended slot by slot they read
    as two contacts at 5.4 mm between the columns, where there is none (a hostile audit's
    phantom on a measured asymmetric pair; 1.2 mm of rolling radius on a flange). Each column's
    contacts are matched to the nearer column's along the profile first; a column holding one
    contact, and the right wheel's single contacts, are blended as before."""
    y_axis, yaw_axis = np.array([-1e-3, 0.0, 1e-3]), np.array([0.0, 0.01])
    s = np.full((3, 2, 2, 2), np.nan)
    s[:, 0, 0, :] = [7.33e-3, 3.48e-3]
    s[:, 1, 0, :] = [3.50e-3, 7.31e-3]                 # the same two contacts, swapped
    s[:, :, 1, 0] = -2e-3                               # the right wheel: one contact
    rr = 0.46 - 0.5 * s                                 # a cone: radius from s
    ip = ti.build(y_axis, yaw_axis, {"wheel_s": s, "rolling_radius": rr})
    out = ip.layout.unpack(ip.evaluate(np.array([0.0, 0.0, 0.0]),
                                       np.array([0.003, 0.007, 0.0]))[0],
                           ["wheel_s", "rolling_radius"],
                           {"wheel_s": np.dtype(float), "rolling_radius": np.dtype(float)})
    near = [[7.33e-3, 3.48e-3], [3.50e-3, 7.31e-3], [7.33e-3, 3.48e-3]]    # nearer column's
    for i, order in enumerate(near):
        got = out["wheel_s"][i, 0]
        assert np.abs(got - np.array(order)).max() < 0.03e-3, (i, got)
        np.testing.assert_allclose(out["rolling_radius"][i, 0], 0.46 - 0.5 * got, atol=1e-12)
        assert out["wheel_s"][i, 1, 0] == pytest.approx(-2e-3, abs=1e-15)
    one = s.copy()
    one[:, 1, 0, 1] = np.nan                            # the next column: one contact
    ip = ti.build(y_axis, yaw_axis, {"wheel_s": one})
    got = ip.evaluate(np.array([0.0]), np.array([0.003]))[0][0]
    assert np.isnan(got[1])                             # its second slot: no answer
