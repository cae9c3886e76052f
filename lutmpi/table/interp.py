"""Jump-aware interpolation over the (y, yaw) grid of a table, compiled. Pure: numpy and numba.

Representation (built once per table and method, :func:`build`):

* Every stored quantity is flattened into one column of a value vector of length Q (integer
  datasets too, as floats).
* Each yaw column is a sequence of *pieces* separated by its located jumps
  (:mod:`lutmpi.table.jumps`). A piece's knots are the grid nodes strictly inside it plus the
  bracket ends of the jumps that bound it, carrying the one-sided limits. Nothing is ever
  interpolated between two pieces.
* Per quantity an interpolant along y (:data:`MODES`): ``linear``, ``pchip`` (monotone cubic,
  Fritsch-Carlson slopes computed inside each piece) or ``nearest`` (codes and counts), chosen by
  :func:`choose_modes` from the error each makes predicting the table's own nodes from every other
  node (a measured error at twice the step, no extra solve); the wheelset's pose is always
  ``pchip``, the cubic its refinement tested (:data:`lutmpi.table.refine.CUBIC_TESTED`).
* The jumps of neighbouring yaw columns are paired one by one (:func:`pair_jumps`: the
  order-keeping pairing of least distance, on the same wheel (or wheel masks that share one, at
  a cost: :func:`_mask_cost`), within :data:`PAIR_STEPS` grid steps of y or farther where the
  jumps all moved farther; alike jumps first, by how they move each wheel's main contact:
  :func:`_move_classes`). The same count of jumps is not taken
  to mean the same jumps: a cluster of the load centre's mesh-step jumps can lose a member while
  another cluster gains one (on the Manchester 37x37 load-centre table, pairing by index put
  jumps 4 mm apart together and the rolling radius between those columns erred by up to 8.9 mm).
* A paired jump's position at the query's yaw lies on its jump curve, a cubic in yaw through its
  positions in up to four columns (:func:`~lutmpi.table.lookup._jump_at`); it decides the side for
  both columns. An unpaired jump decides only for its own column, and never across a paired
  jump of that column (:func:`~lutmpi.table.lookup._unpaired_below`).
* Along yaw: a cubic (Catmull-Rom: centred-difference slopes from the outer columns j - 1 and j +
  2) between the two neighbouring columns, every column evaluated *on the same side of the same
  jump curve*. A column whose own jump lies on the other side of the query is evaluated by
  extending its piece (never a blend of two sides). The contact varies about quadratically with yaw
  (evenly around yaw 0), which linear blending misses by c h^2 / 4: 59 um of rolling radius on the
  Manchester flange at 5 mrad steps, 4.8 um with the cubic. The cubic needs the two columns' pieces
  bounded by paired jumps (or the grid's ends); an outer column answers where its piece corresponds
  too, else the slope there is the second-order one-sided one (in an edge cell too), or the secant
  when neither outer column answers. Where the two pieces do not correspond (a jump without a
  partner bounds one of them) the blend is linear. The quantities that do not jump (the
  wheelset's pose) are the exception: an outer column whose piece does not correspond (the
  inner ones' pieces corresponding or not) still answers them, read in its own piece at y,
  where neither it nor the two inner columns holds a jump within
  :data:`~lutmpi.table.lookup.OUTER_STEPS` grid steps of y. On a column the yaw slope is the
  cubic's (the same from either cell).
* Beside a paired jump (within :data:`~lutmpi.table.lookup.WARP_STEPS` grid steps of y), the
  quantities that jump are read in each column at the query's distance from that column's own jump,
  not at the query's y (:func:`~lutmpi.table.lookup._warp`): the contact runs up a steep onset next
  to a flange jump, and two columns read at one y sit at different points of it (on the paper and
  Manchester 37x37 load-centre tables, 15 and 17 of ~2 850 poses between columns erred by more than
  0.1 mm of rolling radius read at y, 8 and 9 read so). Not where a jump moves more than a quarter
  of that reach between the columns (a branch that stays put in y while its jump moves), nor in a
  piece narrower than :data:`~lutmpi.table.lookup.NARROW_STEPS` grid steps (a flickering second
  contact, whose cluster of jumps pairs arbitrarily); an outer column that cannot be read so gives
  those quantities no slope. The wheelset's pose is read at y.
* A piece is extended by at most :data:`~lutmpi.table.lookup.EXTEND_STEPS` grid steps for the
  quantities that jump with the contact (:func:`_jumping`: contact points, radii, angles, forces):
  farther, that column does not answer them and the other column, whose piece holds the query,
  answers alone (an outer column gives no slope). Next to a flange jump the contact runs up
  steeply, and a piece extended across that onset errs by millimetres. The wheelset's pose (z_g,
  roll) only kinks at a jump and is interpolated as above. Flag :data:`UNMATCHED`: a linear blend,
  or one column answering.

* A wheel's contacts are blended between columns contact by contact: each column's first two
  are put in the order of the nearer column's along the wheel profile first
  (:func:`slot_matching`, :func:`~lutmpi.table.lookup.match_slots`; a column orders them by
  force, and two columns can order one double contact differently).

Queries:

* Within :data:`~lutmpi.table.lookup.SNAP` of an interval of a knot or a yaw column, a query
  is read on it (a yaw typed as 0.05 is not the grid's 0.05000000000000002).
* At a jump position exactly, the *upper* piece answers (y >= jump -> above it). Between a
  bracket's ends (``TOL_M`` wide) a piece is extended to the jump position.
* Outside the grid (either axis, NaN input) every value is NaN and the query carries
  :data:`OUT_OF_RANGE`; :meth:`lutmpi.table.Table.interp` raises or returns the flag, it never
  clips. A 1-D table (one yaw value) answers only at that yaw.
* NaN policy: a knot whose value is NaN (missing contact, failed point) makes every query that
  gives it a non-zero weight NaN; a query exactly on a good knot is not affected by a NaN
  neighbour.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from lutmpi.table.lookup import lookup_many
from lutmpi.table.schema import FIELDS_BY_NAME, SIDES, D, J

MODES = ("linear", "pchip", "nearest")
LINEAR, PCHIP, NEAREST = 0, 1, 2
#: flags of a query (bit mask)
OUT_OF_RANGE, UNMATCHED = 1, 2
#: the jumps of neighbouring yaw columns are paired (on the same wheel) within a reach of this
#: many grid steps of y, or of PAIR_SPREAD times the median shift of the jumps that are each
#: other's nearest where that is larger (a coarse yaw grid, jumps moving far between columns)
PAIR_STEPS = 2.0
PAIR_SPREAD = 3.0
#: what :func:`pair_jumps` adds per wheel whose main contact a jump moves, where the jump is
#: left unpaired or paired with one that moves it otherwise (:func:`_move_classes`), in
#: reaches; and the movement of the main contact along the wheel profile up to which a jump
#: counts as not moving it, m (the jump search's confirmation,
#: :data:`lutmpi.table.jump_search.CONFIRM_M`)
MOVE_WEIGHT = 0.25
MOVE_FLOOR_M = 0.5e-3
#: two jumps moving a wheel's main contact the same way by amounts more than this factor apart
#: move it otherwise (:func:`_unlike`)
MOVE_RATIO = 3.0
#: a quantity whose one-sided limits at some jump differ by more than this many times its
#: median change over one grid step jumps with the contact (else it only kinks there)
JUMPING_STEPS = 10.0
#: the wheelset's pose: continuous where the contact jumps (a kink), never treated as jumping
KINKING = (D.z_g, D.roll)


@dataclass(frozen=True)
class Layout:
    """Where each quantity sits in the flat value vector: ``name -> (offset, suffix)``."""

    slots: dict[str, tuple[int, tuple[int, ...]]]
    size: int

    @classmethod
    def of(cls, arrays: dict[str, np.ndarray]) -> Layout:
        slots, off = {}, 0
        for name, arr in arrays.items():
            suffix = tuple(arr.shape[2:])
            slots[name] = (off, suffix)
            off += int(np.prod(suffix, dtype=int))
        return cls(slots, off)

    def pack(self, arrays: dict[str, np.ndarray], lead: int) -> np.ndarray:
        """``(lead..., Q)`` float array from ``name -> (lead..., *suffix)``."""
        parts = [np.asarray(arrays[n], float).reshape(arrays[n].shape[:lead] + (-1,))
                 for n in self.slots]
        return np.concatenate(parts, axis=-1)

    def unpack(self, flat: np.ndarray, names: list[str], dtypes: dict[str, np.dtype]
               ) -> dict[str, np.ndarray]:
        """``name -> (q..., *suffix)`` from ``(q..., Q)``."""
        out = {}
        for n in names:
            off, suffix = self.slots[n]
            size = int(np.prod(suffix, dtype=int))
            v = flat[..., off:off + size].reshape(flat.shape[:-1] + suffix)
            if dtypes[n].kind in "iu":
                v = np.where(np.isfinite(v), v, -1).astype(dtypes[n])
            out[n] = v
        return out


@dataclass(frozen=True)
class Interpolator:
    """Compiled-ready arrays of one method of a table (see the module docstring).

    Attributes
    ----------
    y_axis, yaw_axis : ndarray
        Grid axes, m and rad.
    ky : ndarray, (nyaw, M)
        Knot positions per column (padded with +inf).
    kv, kd : ndarray, (nyaw, M, Q)
        Knot values and the slopes d/dy of the ``pchip`` quantities.
    pstart : ndarray of int64, (nyaw, K + 2)
        Knot index where piece p of a column starts; piece p ends where p + 1 starts.
    jy : ndarray, (nyaw, K)
        Jump positions (NaN padded); ``nj`` (nyaw,) their count; ``jside`` (nyaw, K) wheel masks.
    up, down : ndarray of int64, (nyaw, K)
        The jump of column j + 1 (``up``) or j - 1 (``down``) paired with jump k of column j
        (:func:`pair_jumps`), -1 where none.
    mode : ndarray of int64, (Q,)
        Interpolant per value column.
    jumps : ndarray of bool, (Q,)
        Whether the value column jumps at the located jumps (:func:`_jumping`).
    layout : Layout
    slot_pair, slot_wheel, slot_s : ndarray of int64, (Q,), (Q,) and (2, 2)
        The matching of two columns' contacts (:func:`slot_matching`).
    """

    y_axis: np.ndarray
    yaw_axis: np.ndarray
    ky: np.ndarray
    kv: np.ndarray
    kd: np.ndarray
    pstart: np.ndarray
    jy: np.ndarray
    nj: np.ndarray
    jside: np.ndarray
    up: np.ndarray
    down: np.ndarray
    mode: np.ndarray
    jumps: np.ndarray
    layout: Layout
    slot_pair: np.ndarray
    slot_wheel: np.ndarray
    slot_s: np.ndarray

    def evaluate(self, y: np.ndarray, yaw: np.ndarray) -> tuple[np.ndarray, ...]:
        """Values and slopes at poses ``(y, yaw)`` (1-D arrays of equal length, m and rad).

        Returns
        -------
        value, d_dy, d_dyaw : ndarray, (n, Q)
            Values, their y slopes (per m) and yaw slopes (per rad; NaN on a 1-D table).
        flags : ndarray of int64, (n,)
            :data:`OUT_OF_RANGE`, :data:`UNMATCHED` bits.
        piece : ndarray of int64, (n,)
            Which piece of the column answered: the number of jumps below the query.
        jump_dist : ndarray, (n,)
            Signed distance to the nearest jump, ``y - y_j`` (m; > 0: above it; NaN when the
            column has none): a paired jump at its curve's position at the query's yaw, an
            unpaired one at its own (whose sign can then disagree with ``piece``, where the
            jump is counted on the side of a paired one of its column).
        """
        y = np.ascontiguousarray(y, dtype=float).ravel()
        yaw = np.ascontiguousarray(yaw, dtype=float).ravel()
        n, q = y.size, self.kv.shape[2]
        out = (np.empty((n, q)), np.empty((n, q)), np.empty((n, q)), np.empty(n, np.int64),
               np.empty(n, np.int64), np.empty(n))
        lookup_many(self.arrays, y, yaw, *out)
        return out

    @property
    def arrays(self) -> tuple[np.ndarray, ...]:
        """The arguments of the compiled kernels, in their order."""
        return (self.y_axis, self.yaw_axis, self.ky, self.kv, self.kd, self.pstart, self.jy,
                self.nj, self.up, self.down, self.mode, self.jumps, self.slot_pair, self.slot_wheel,
                self.slot_s)


# -- building ---------------------------------------------------------------------------------
def build(y_axis: np.ndarray, yaw_axis: np.ndarray, arrays: dict[str, np.ndarray],
          jumps: dict[str, np.ndarray] | None = None, limits: dict[str, np.ndarray] | None = None,
          knot_y: np.ndarray | None = None, knots: dict[str, np.ndarray] | None = None,
          modes: dict[str, str] | None = None) -> Interpolator:
    """Arrange a table's arrays for jump-aware interpolation.

    Parameters
    ----------
    y_axis, yaw_axis : ndarray
        Increasing grid axes, m and rad.
    arrays : dict
        name -> ``(ny, nyaw, *suffix)`` (already masked: failed points NaN).
    jumps : dict, optional
        ``jump_y``, ``jump_y_lo``, ``jump_y_hi``, ``jump_side`` ``(nyaw, K)``; none: no jumps
        (plain piecewise interpolation over the grid).
    limits : dict, optional
        name -> ``(nyaw, K, 2, *suffix)``, the one-sided limits at ``jump_y_lo`` / ``jump_y_hi``
        (masked like ``arrays``); a quantity without limits is NaN between the bracket ends.
        Those of ``wheel_s`` pair the jumps of neighbouring columns (:func:`_moves`) whether
        or not ``arrays`` holds it: pass every quantity's limits.
    knot_y : ndarray, (nyaw, E), optional
        Extra knots (poses solved after the build), m, NaN padded.
    knots : dict, optional
        name -> ``(nyaw, E, *suffix)``, their values (masked like ``arrays``).
    modes : dict, optional
        name -> one of :data:`MODES`; default ``linear`` for floats, ``nearest`` for integers.
    """
    layout = Layout.of(arrays)
    ny, nyaw = arrays[next(iter(arrays))].shape[:2]
    grid = layout.pack(arrays, 2)                                   # (ny, nyaw, Q)
    k = 0 if jumps is None else jumps[J.jump_y].shape[1]
    lim = None
    if k:
        full = {n: (limits[n] if limits and n in limits else
                    np.full((nyaw, k, 2) + arrays[n].shape[2:], np.nan)) for n in arrays}
        lim = layout.pack(full, 3)                                  # (nyaw, K, 2, Q)
    mode = _mode_vector(layout, arrays, modes or {})
    ex = None
    if knot_y is not None and knot_y.size:
        ex = (knot_y, layout.pack({n: (knots[n] if n in knots else np.full(
            knot_y.shape + arrays[n].shape[2:], np.nan)) for n in arrays}, 2))
    cols = [_column(y_axis, grid[:, j], jumps, lim, ex, j, k) for j in range(nyaw)]
    m = max(c[0].size for c in cols)
    ky = np.full((nyaw, m), np.inf)
    kv = np.full((nyaw, m, layout.size), np.nan)
    pstart = np.zeros((nyaw, k + 2), np.int64)
    for j, (cy, cv, starts) in enumerate(cols):
        ky[j, :cy.size], kv[j, :cy.size] = cy, cv
        pstart[j, :starts.size] = starts
        pstart[j, starts.size:] = cy.size
    kd = _slopes(ky, kv, pstart, mode == PCHIP)
    jy = np.full((nyaw, k), np.nan) if not k else np.asarray(jumps[J.jump_y], float)
    nj = np.isfinite(jy).sum(axis=1).astype(np.int64)
    jside = (np.zeros((nyaw, k), np.int64) if not k
             else np.asarray(jumps[J.jump_side], np.int64))
    up = np.full((nyaw, k), -1, np.int64)
    down = np.full((nyaw, k), -1, np.int64)
    step = float(np.max(np.diff(y_axis))) if len(y_axis) > 1 else 0.0
    moves = _moves(limits, k)
    for j in range(nyaw - 1):
        a, b = pair_jumps(jy[j, :nj[j]], jside[j, :nj[j]], jy[j + 1, :nj[j + 1]],
                          jside[j + 1, :nj[j + 1]], step,
                          None if moves is None else moves[j, :nj[j]],
                          None if moves is None else moves[j + 1, :nj[j + 1]])
        up[j, :nj[j]] = a
        down[j + 1, :nj[j + 1]] = b
    return Interpolator(np.asarray(y_axis, float), np.asarray(yaw_axis, float), ky, kv, kd,
                        pstart, np.where(np.isfinite(jy), jy, np.inf), nj, jside, up,
                        down, mode, _jumping(grid, lim, layout), layout, *slot_matching(layout))


def _moves(limits: dict[str, np.ndarray] | None, k: int) -> np.ndarray | None:
    """Per column and jump, how far each wheel's main contact moves along the wheel profile
    across it (``wheel_s`` of the first slot, upper limit less lower, m; NaN where either is
    missing), ``(nyaw, K, wheels)``; None without jumps or ``wheel_s`` limits. Read from the
    limits whatever quantities the interpolator holds: the pairing of the jumps, and so every
    answer, must not depend on which quantities a caller asks for."""
    ws = None if not k or not limits else limits.get(D.wheel_s)
    if ws is None or ws.ndim < 5:
        return None
    ws = np.asarray(ws, float)
    return ws[:, :, 1, :, 0] - ws[:, :, 0, :, 0]


def slot_matching(layout: Layout) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What the blend between yaw columns matches a wheel's two contacts by
    (:func:`~lutmpi.table.lookup.match_slots`): per value column in the first slot of a
    per-contact quantity (:attr:`lutmpi.table.schema.Field.per_contact`), the value column of
    the same quantity, wheel and component in the second slot and the wheel (-1 elsewhere);
    and the value columns of ``wheel_s`` per wheel and slot (-1 without it: nothing is
    matched).

    A column orders a wheel's contacts by force (the reference method: the solver's order),
    and two columns can order the same two contacts differently: blended slot by slot, a
    double contact on the tread at s = 7.3 and 3.5 mm read as two contacts at 5.4 mm between
    the columns (a measured asymmetric pair, yaw steps of 0.01 rad; on its flange 1.2 mm of
    rolling radius off)."""
    pair = np.full(layout.size, -1, np.int64)
    wheel = np.full(layout.size, -1, np.int64)
    s_cols = np.full((len(SIDES), 2), -1, np.int64)
    for name, (off, suffix) in layout.slots.items():
        field = FIELDS_BY_NAME.get(name)
        if field is None or not field.per_contact or suffix[:2] != field.suffix[:2] or (
                suffix[1] < 2):
            continue
        idx = np.arange(int(np.prod(suffix, dtype=int))).reshape(suffix) + off
        pair[idx[:, 0]] = idx[:, 1]
        for w in range(suffix[0]):
            wheel[idx[w, 0]] = w
        if name == D.wheel_s:
            s_cols[:] = idx[:, :2]
    return pair, wheel, s_cols


def _jumping(grid: np.ndarray, lim: np.ndarray | None, layout: Layout) -> np.ndarray:
    """Per value column, whether it jumps where the contact does: at some located jump its
    one-sided limits differ by more than :data:`JUMPING_STEPS` times its median change over one
    grid step in y (a contact point, radius or angle). Never the wheelset's pose
    (:data:`KINKING`): it only kinks at a contact jump, and a piece is extended for it as for a
    smooth quantity (on a flat tread its median step is so small that the µm it moves at a
    jump would count as one)."""
    out = np.zeros(grid.shape[-1], bool)
    if lim is None or not lim.size:
        return out
    with warnings.catch_warnings():           # an all-NaN column (never solved) has no steps
        warnings.simplefilter("ignore", RuntimeWarning)
        typical = np.nanmedian(np.abs(np.diff(grid, axis=0)), axis=(0, 1))
        step = np.nanmax(np.abs(lim[:, :, 1] - lim[:, :, 0]), axis=(0, 1))
    out = np.nan_to_num(step) > JUMPING_STEPS * np.nan_to_num(typical)
    for name in KINKING:
        if name in layout.slots:
            off, suffix = layout.slots[name]
            out[off:off + int(np.prod(suffix, dtype=int))] = False
    return out


def pair_jumps(ya: np.ndarray, sa: np.ndarray, yb: np.ndarray, sb: np.ndarray, step: float,
               ma: np.ndarray | None = None, mb: np.ndarray | None = None
               ) -> tuple[np.ndarray, np.ndarray]:
    """Pair the jumps of two neighbouring yaw columns (positions ``ya``, ``yb`` in m, sorted;
    wheel masks ``sa``, ``sb``; ``step``: the grid's y step, m; ``ma``, ``mb``: optional, per
    jump how far each wheel's main contact moves along the wheel profile, m, ``(n, wheels)``).

    Where every jump's nearest on its wheel in the other column is its partner by order, both
    ways (the same jumps, however far they moved), the pairing is one to one. Otherwise it is
    the order-keeping pairing of least cost: a pair costs the distance of its positions (same
    wheel mask, within the reach only; masks that share a wheel, :func:`_mask_cost`), a jump
    left unpaired half the reach; a jump that moves a wheel's main contact
    (:func:`_move_classes`) adds :data:`MOVE_WEIGHT` reaches per such wheel where it is left
    unpaired or paired with one that moves it otherwise (:func:`_unlike`), so that alike jumps
    pair first. The reach is :data:`PAIR_STEPS` grid steps, or :data:`PAIR_SPREAD` times the
    median shift of the jumps that are each other's nearest where larger. The same count of
    jumps is not taken to mean the same jumps: a cluster of the load centre's mesh-step jumps
    can lose a member while another gains one.

    Returns
    -------
    a_to_b, b_to_a : ndarray of int64
        The partner of each jump of either column, -1 where none.
    """
    na, nb = len(ya), len(yb)
    a_near = _nearest_on_wheel(ya, sa, yb, sb)
    b_near = _nearest_on_wheel(yb, sb, ya, sa)
    if (na == nb and np.array_equal(sa, sb) and np.array_equal(a_near, np.arange(na))
            and np.array_equal(b_near, np.arange(nb))):
        return np.arange(na, dtype=np.int64), np.arange(nb, dtype=np.int64)
    shifts = [abs(float(ya[i]) - float(yb[a_near[i]])) for i in range(na)
              if a_near[i] >= 0 and b_near[a_near[i]] == i]
    reach = PAIR_STEPS * step
    if shifts:
        reach = max(reach, PAIR_SPREAD * float(np.median(shifts)))
    gap = 0.5 * reach
    # a jump that moves a wheel's main contact pays MOVE_WEIGHT reaches per such wheel left
    # unpaired, or paired with one that moves it otherwise (_unlike): alike pairs first
    if ma is None or mb is None:
        ma = mb = None
    else:
        ma = np.asarray(ma, float).reshape(na, -1) if na else np.zeros((0, 1))
        mb = np.asarray(mb, float).reshape(nb, -1) if nb else np.zeros((0, 1))
    ka, kb = _move_classes(ma, na), _move_classes(mb, nb)
    wm = MOVE_WEIGHT * reach
    lone_a = gap + wm * (ka != 0).sum(axis=1)
    lone_b = gap + wm * (kb != 0).sum(axis=1)
    cost = np.full((na + 1, nb + 1), np.inf)
    move = np.zeros((na + 1, nb + 1), np.int64)   # 0: pair, 1: a's jump unpaired, 2: b's
    cost[0, 0] = 0.0
    cost[0, 1:] = np.cumsum(lone_b)
    cost[1:, 0] = np.cumsum(lone_a)
    move[1:, 0], move[0, 1:] = 1, 2
    for i in range(1, na + 1):
        for k in range(1, nb + 1):
            best, how = cost[i - 1, k] + lone_a[i - 1], 1
            if cost[i, k - 1] + lone_b[k - 1] < best:
                best, how = cost[i, k - 1] + lone_b[k - 1], 2
            d = abs(float(ya[i - 1]) - float(yb[k - 1])) + _mask_cost(sa[i - 1], sb[k - 1],
                                                                     reach)
            unlike = 0.0 if ma is None else wm * float(_unlike(ka[i - 1], kb[k - 1], ma, mb,
                                                                 i - 1, k - 1))
            if d < reach and cost[i - 1, k - 1] + d + unlike <= best:
                best, how = cost[i - 1, k - 1] + d + unlike, 0
            cost[i, k], move[i, k] = best, how
    a_to_b = np.full(na, -1, np.int64)
    b_to_a = np.full(nb, -1, np.int64)
    i, k = na, nb
    while i > 0 or k > 0:
        how = move[i, k]
        if how == 0:
            a_to_b[i - 1], b_to_a[k - 1] = k - 1, i - 1
            i, k = i - 1, k - 1
        elif how == 1:
            i -= 1
        else:
            k -= 1
    return a_to_b, b_to_a


def _mask_cost(a: int, b: int, reach: float) -> float:
    """What pairing two jumps with wheel masks ``a``, ``b`` (:data:`lutmpi.table.schema.
    JUMP_SIDE_BITS`) adds to their distance in :func:`pair_jumps`: nothing for the same mask,
    half the reach where they share a wheel (a pair then only within half the reach, and an
    equal mask preferred), inf where they do not. A fold flagged on both wheels in one column
    can be flagged on one in the next (the other wheel's change fell below the confirmation
    there); unpaired, each column was read on its own side across the band between the two
    jumps (on a worn flange pair at 0.01 rad yaw steps the rolling radius 6.2 mm off 0.1 mm
    from the jump, and a failed pose's NaN spread over 0.3 mm of y between the columns)."""
    if a == b:
        return 0.0
    return 0.5 * reach if int(a) & int(b) else math.inf


def _move_classes(m: np.ndarray | None, n: int) -> np.ndarray:
    """Per jump and wheel, how the jump moves the wheel's main contact along the wheel profile
    (``m``, m, ``(n, wheels)``, :func:`_moves`): +1 or -1 by more than :data:`MOVE_FLOOR_M`
    up or down the profile, else 0 (also where unknown). ``(n, wheels)`` int; ``(n, 0)``
    without ``m``.

    :func:`pair_jumps` pairs alike jumps first. A load centre's second contact comes and goes
    in steps of a few µm before the main contact moves to the flange: one column's cluster can
    hold an onset, a swap of the two contacts and a loss, the next column's a single jump of
    the main contact (the paper's pair at yaw 0.027 and 0.033 rad, y = 6.04 and 6.16 mm). By
    distance alone the onset paired with that jump, and between the columns a tread contact
    read in one column was blended with a flange contact of the other (rolling radius 6.5 mm
    off)."""
    if m is None:
        return np.zeros((n, 0), np.int64)
    out = np.where(m > MOVE_FLOOR_M, 1, np.where(m < -MOVE_FLOOR_M, -1, 0))
    return out.astype(np.int64)


def _unlike(ka: np.ndarray, kb: np.ndarray, ma: np.ndarray, mb: np.ndarray, i: int, k: int
            ) -> int:
    """How many wheels jumps ``i`` (of ``ma``, classes ``ka``) and ``k`` (of ``mb``, ``kb``)
    move the main contact of otherwise (:func:`pair_jumps`): in other classes
    (:func:`_move_classes`: an unknown movement, NaN beside a failed pose, is class 0), or the
    same way by amounts more than :data:`MOVE_RATIO` apart. On a measured pair the main contact
    leaves the flange by 44 and 39 mm of wheel profile in two neighbouring columns, a 1.3 mm
    step of the flange contact just before each: by direction alone the 39 mm jump paired with
    the 1.3 mm step.

    One per wheel, whether one or both of the two move it: an unlike pair of two moving jumps
    costs less than leaving both unpaired, so a jump moving the contact the other way repels
    half as much as one not moving it. Charging each moving jump (what leaving it unpaired
    costs) measured worse on the paper's 37x37 table (5 poses between columns above 0.1 mm of
    rolling radius against 2, one above 1 mm): in a flickering cluster it pairs more of the
    non-moving jumps instead (BENCHMARKS.md, 2026-11-28, third part)."""
    n = 0
    for w in range(ka.size):
        if ka[w] != kb[w]:
            n += 1
        elif ka[w] != 0:
            a, b = abs(float(ma[i, w])), abs(float(mb[k, w]))
            if max(a, b) > MOVE_RATIO * min(a, b):
                n += 1
    return n


def _nearest_on_wheel(ya: np.ndarray, sa: np.ndarray, yb: np.ndarray, sb: np.ndarray
                      ) -> np.ndarray:
    """For each jump of ``ya``, the index of the nearest jump of ``yb`` on the same wheel mask
    (the lower one on a tie), -1 where none."""
    out = np.full(len(ya), -1, np.int64)
    for i in range(len(ya)):
        same = np.flatnonzero(np.asarray(sb) == sa[i])
        if same.size:
            out[i] = same[np.argmin(np.abs(np.asarray(yb, float)[same] - float(ya[i])))]
    return out


def _mode_vector(layout: Layout, arrays: dict[str, np.ndarray], modes: dict[str, str]
                 ) -> np.ndarray:
    mode = np.zeros(layout.size, np.int64)
    for name, (off, suffix) in layout.slots.items():
        size = int(np.prod(suffix, dtype=int))
        if arrays[name].dtype.kind in "iu":
            code = NEAREST
        else:
            chosen = modes.get(name, "linear")
            if chosen not in MODES:
                raise ValueError(f"interpolant of {name!r} must be one of {MODES}, got {chosen!r}")
            code = MODES.index(chosen)
        mode[off:off + size] = code
    return mode


def _column(y_axis: np.ndarray, values: np.ndarray, jumps: dict[str, np.ndarray] | None,
            lim: np.ndarray | None, extra: tuple[np.ndarray, np.ndarray] | None, j: int, k: int
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Knots ``(y (m,), values (m, Q))`` of one column and the start index of each piece.

    Knots: grid nodes, extra knots and bracket ends, sorted; the piece of a knot is the number of
    jumps at or below it; a knot strictly inside a bracket is dropped."""
    n = 0 if not k else int(np.isfinite(jumps[J.jump_y][j]).sum())
    jy = np.asarray([] if not n else jumps[J.jump_y][j, :n], float)
    lo = np.asarray([] if not n else jumps[J.jump_y_lo][j, :n], float)
    hi = np.asarray([] if not n else jumps[J.jump_y_hi][j, :n], float)
    ys = [np.asarray(y_axis, float)]
    vs = [values]
    if extra is not None:
        ok = np.isfinite(extra[0][j])
        ys.append(extra[0][j][ok])
        vs.append(extra[1][j][ok])
    if n:
        ys += [lo, hi]
        vs += [lim[j, :n, 0], lim[j, :n, 1]]
    y = np.concatenate(ys)
    v = np.concatenate(vs, axis=0)
    inside = ((y[:, None] > lo[None, :]) & (y[:, None] < hi[None, :])).any(axis=1)
    y, v = y[~inside], v[~inside]
    order = np.argsort(y, kind="stable")
    y, v = y[order], v[order]
    keep = np.concatenate([[True], np.diff(y) > 0])
    y, v = y[keep], v[keep]
    piece = (jy[None, :] <= y[:, None]).sum(axis=1)
    starts = np.searchsorted(piece, np.arange(n + 1), side="left")
    return y, v, starts


def _slopes(ky: np.ndarray, kv: np.ndarray, pstart: np.ndarray, pchip: np.ndarray) -> np.ndarray:
    """Fritsch-Carlson (PCHIP) slopes at the knots, computed inside each piece."""
    kd = np.zeros_like(kv)
    if not pchip.any():
        return kd
    cols = np.flatnonzero(pchip)
    for j in range(ky.shape[0]):
        for p in range(pstart.shape[1] - 1):
            s, e = pstart[j, p], pstart[j, p + 1]
            if e - s >= 2:
                kd[j, s:e][:, cols] = pchip_slopes(ky[j, s:e], kv[j, s:e][:, cols])
    return kd


def pchip_slopes(x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Monotone cubic (Fritsch-Carlson, as SciPy's ``PchipInterpolator``) slopes at knots ``x``
    (n,) of values ``v`` (n, Q); secant slopes for two knots."""
    h = np.diff(x)[:, None]
    delta = np.diff(v, axis=0) / h
    d = np.zeros_like(v)
    if x.size == 2:
        return np.repeat(delta, 2, axis=0)
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    same = (np.sign(delta[1:]) * np.sign(delta[:-1]) > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        harm = (w1 + w2) / (w1 / delta[:-1] + w2 / delta[1:])
    d[1:-1] = np.where(same, harm, 0.0)
    d[1:-1] = np.where(np.isnan(delta[1:]) | np.isnan(delta[:-1]), np.nan, d[1:-1])
    d[0] = _edge(h[0], h[1], delta[0], delta[1])
    d[-1] = _edge(h[-1], h[-2], delta[-1], delta[-2])
    return d


def _edge(h0: np.ndarray, h1: np.ndarray, m0: np.ndarray, m1: np.ndarray) -> np.ndarray:
    """One-sided three-point end slope, shape preserving (SciPy's ``_edge_case``)."""
    d = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    d = np.where(np.sign(d) != np.sign(m0), 0.0, d)
    return np.where((np.sign(m0) != np.sign(m1)) & (np.abs(d) > np.abs(3 * m0)), 3 * m0, d)


def choose_modes(y_axis: np.ndarray, arrays: dict[str, np.ndarray],
                 jumps: dict[str, np.ndarray] | None = None,
                 limits: dict[str, np.ndarray] | None = None, knot_y: np.ndarray | None = None,
                 knots: dict[str, np.ndarray] | None = None) -> dict[str, str]:
    """The interpolant of each float quantity: ``pchip`` where predicting every other knot of
    each piece from the rest errs less (RMS over the table) than ``linear``, else ``linear``;
    always ``pchip`` for the wheelset's pose (:data:`KINKING`), whose refinement between the
    knots tested that cubic (:data:`lutmpi.table.refine.CUBIC_TESTED`): read with the straight
    line, its knots would not hold the tolerance they were placed for.

    The comparison uses only the table's own nodes and jump limits: the measured error at twice
    the grid step, which ranks the two interpolants as at the step itself (both converge at their
    order away from jumps).
    """
    floats = {n: a for n, a in arrays.items() if a.dtype.kind == "f"}
    ip = build(y_axis, np.arange(arrays[D.status].shape[1], dtype=float), floats, jumps, limits,
               knot_y, knots)
    err = np.zeros((2, ip.layout.size))
    for j in range(ip.ky.shape[0]):
        for p in range(ip.pstart.shape[1] - 1):
            s, e = ip.pstart[j, p], ip.pstart[j, p + 1]
            if e - s < 5:
                continue
            x, v = ip.ky[j, s:e], ip.kv[j, s:e]
            keep = np.arange(0, x.size, 2)
            if keep[-1] != x.size - 1:
                keep = np.append(keep, x.size - 1)
            test = np.setdiff1d(np.arange(x.size), keep)
            lin = _predict_linear(x[keep], v[keep], x[test])
            pch = _predict_pchip(x[keep], v[keep], x[test])
            for row, pred in enumerate((lin, pch)):
                e2 = (pred - v[test]) ** 2
                err[row] += np.where(np.isfinite(e2), e2, 0.0).sum(axis=0)
    out = {}
    for name, (off, suffix) in ip.layout.slots.items():
        size = int(np.prod(suffix, dtype=int))
        lin, pch = err[0, off:off + size].sum(), err[1, off:off + size].sum()
        out[name] = "pchip" if pch < lin or name in KINKING else "linear"
    return out


def _predict_linear(x: np.ndarray, v: np.ndarray, xt: np.ndarray) -> np.ndarray:
    i = np.clip(np.searchsorted(x, xt) - 1, 0, x.size - 2)
    t = ((xt - x[i]) / (x[i + 1] - x[i]))[:, None]
    return v[i] * (1 - t) + v[i + 1] * t


def _predict_pchip(x: np.ndarray, v: np.ndarray, xt: np.ndarray) -> np.ndarray:
    d = pchip_slopes(x, v)
    i = np.clip(np.searchsorted(x, xt) - 1, 0, x.size - 2)
    h = (x[i + 1] - x[i])[:, None]
    t = (xt - x[i])[:, None] / h
    return _hermite(t, h, v[i], v[i + 1], d[i], d[i + 1])


def _hermite(t, h, v0, v1, d0, d1):  # noqa: ANN001, ANN202 - numpy or scalars
    t2, t3 = t * t, t * t * t
    return ((2 * t3 - 3 * t2 + 1) * v0 + (t3 - 2 * t2 + t) * h * d0 + (-2 * t3 + 3 * t2) * v1
            + (t3 - t2) * h * d1)
