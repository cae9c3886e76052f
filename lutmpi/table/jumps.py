"""Contact jumps of a table, located and stored as data (issue 11). Pure: numpy only.

Along y, at fixed yaw, the contact of a wheel can jump: the contact point leaves the tread for the
flange (the rigid contact is the lowest of several gap minima, and the lowest changes), a second
contact appears or disappears, or the solve stops converging. Every continuous interpolant errs by
about half the jump next to it, whatever the step, so the jumps are located and interpolation never
crosses them (:mod:`lutmpi.table.interp`).

Algorithm, per yaw column and per grid cell ``[y_i, y_i+1]``:

1. *Candidate*: the two end states differ in a discrete key (status, contacts per wheel) or the
   primary contact point of a wheel moves by more than :data:`CANDIDATE_M` (wheel ``s`` or rail
   ``v``) between them, or by more than :data:`CONFIRM_M` and :data:`RATE_RATIO` times as far as
   in the slower of the two neighbouring cells (a smaller jump on a slowly moving contact: on a
   worn flange the contact point jumps by ~1 mm, which the fixed threshold alone let through,
   and the table ran straight across it). Such a cell is searched with :data:`CONFIRM_M` as
   its threshold.
2. *Bisection* with direct pose solves: the midpoint state joins the end it is closer to (a
   discrete mismatch counts more than any movement), until the bracket ``[lo, hi]`` is at most
   :data:`TOL_M` wide; the jump lies at its middle, within ``TOL_M / 2``.
3. *Confirmation*: a bracket whose ends still differ discretely, or whose contact point still moves
   by more than :data:`CONFIRM_M`, is a jump; otherwise the cell was merely steep (the contact
   moving fast but continuously), and nothing is stored.
4. The two sub-intervals left of ``lo`` and right of ``hi`` are searched again (a cell can hold
   several jumps: the second contact of a double contact appears, takes the larger force, goes),
   the bisection taking the poses already solved inside its bracket before solving new ones
   (the jumps of such a cluster lie micrometres apart: bisected from the whole sub-interval
   again, each cost nearly as many solves as the first). Changes that cancel between two
   solved poses (the contact count flickering within micrometres) are not looked for.

5. *Refinement* (:func:`refine_interval`): between neighbouring knots of one piece (grid nodes,
   bisection samples, bracket ends) the midpoint is solved; where the table's interpolant
   through the knots misses it by more than :data:`REFINE_TOL` (rolling radius, contact angle:
   the straight line through the two knots; z_g, roll: the monotone cubic through them and
   their neighbours in the piece, :data:`CUBIC_TESTED`), both halves are refined again, down to
   :data:`MIN_WIDTH_M`, as long as the miss keeps falling (:data:`REFINE_GAIN`; solver noise
   does not fall, so noise is not chased). Every pose solved after the build is kept as an
   extra knot of its column: the table is the grid plus what the jumps and the curvature of
   the contact needed. A jump no cell showed (changes that cancel within a cell, a step inside
   a fast-moving contact) shows in the refinement, which then searches that interval as a cell
   (:func:`refine_item`) and keeps the jumps it finds.
6. *Mirror* (:class:`Mirror`): a wheel is a body of revolution and a rail an extrusion along
   x, so the pose (y, -yaw) is the pose (y, yaw) reflected in the track's y-z plane, for any
   pair; on a symmetric pair (both wheels one profile on one rail profile) the pose (-y, -yaw)
   is the pose (y, yaw) with the wheels swapped, and (-y, yaw) both
   (:meth:`lutmpi.table.schema.Field.reflected`). On a grid symmetric about zero in yaw (and
   in y), a cell or an interval that is the image of another searched or refined takes that
   one's poses reflected instead of solving its own: half the solves (a quarter on a symmetric
   pair), the same table to rounding.

The states at ``lo`` and ``hi`` are full pose records: the one-sided limits of every stored
quantity. Everything depends only on the table and the solver, never on who solved what, so the
result is the same for any number of ranks (:func:`refine_cells` takes any subset of cells).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from lutmpi.table.interp import KINKING
from lutmpi.table.schema import FIELDS_BY_NAME, JUMP_FIELDS, TIMING_FIELDS, D, Field, J

log = logging.getLogger(__name__)

#: primary contact point movement (m) between neighbours that makes a cell a candidate
CANDIDATE_M = 2e-3
#: movement (m) still left across a refined bracket that confirms a contact-point jump
CONFIRM_M = 0.5e-3
#: a cell whose contact point moves by more than CONFIRM_M and this many times as far as in the
#: slower of its neighbouring cells is a candidate too
RATE_RATIO = 2.0
#: width (m) of a refined bracket: the jump is located within +-TOL_M / 2
TOL_M = 5e-6
#: most jumps searched in one grid cell. A cell holding more is searched in part (which of its
#: jumps are found then depends on the bisection's order: a cell and its mirror image could keep
#: different ones) and is reported (:func:`searched_in_part`). On the paper's pair near yaw 0 the
#: load centre's second contact comes and goes up to 6 times within a 0.5 mm cell (4 kept 214
#: of the table's 236 jumps); the budget bounds the cost of a cell whose contacts flicker
MAX_PER_CELL = 8
#: refinement: largest miss of the straight line at an interval's midpoint, per checked quantity
#: (m, rad, m, rad); refined below, down to intervals of MIN_WIDTH_M
REFINE_TOL = {D.rolling_radius: 1e-6, D.contact_angle: 1e-4, D.z_g: 2e-6, D.roll: 2e-5}
#: narrowest knot spacing the refinement makes (m): the width of a jump's bracket, within which
#: the table cannot say where its jump lies, so finer knots next to a jump resolve nothing it
#: can place. At 1 um, on the Manchester table (load centre, 37 x 9), a sixth of the step's
#: solves went into intervals narrower than 10 um, half of them within 14 um of a jump;
#: without them the 1-D tables between their points are unchanged (load centre) or within
#: 0.22 um of direct solves instead of 0.08 um (reference) (BENCHMARKS.md, 2026-11-25)
MIN_WIDTH_M = TOL_M
#: quantities whose miss is that of the monotone cubic (PCHIP) through an interval's knots and
#: their neighbours in the piece, not of the straight line: the wheelset's pose, smooth within a
#: piece (it only kinks at a jump: :data:`lutmpi.table.interp.KINKING`), which the table
#: always interpolates by that cubic (:func:`~lutmpi.table.interp.choose_modes`). Tested by
#: the straight line, its curvature drew 42 % of the refinement's solves on the Manchester
#: table (load centre, 37 x 9: the jump step's 3 240 solves, 905 of them the jump search's,
#: fell to 2 260 without them), knots the cubic does not need (BENCHMARKS.md, 2026-11-27).
#: Per-point (scalar) quantities only (:func:`_miss`)
CUBIC_TESTED = KINKING
#: a child interval is refined further only if its miss fell below this fraction of its parent's
#: (a smooth function: 1/4 per halving, a kink: 1/2, a square-root onset next to a jump: 0.71;
#: solver noise does not fall: stop there)
REFINE_GAIN = 0.8
#: a mesh method's contact point moves along the profile in steps (the nodes in contact change
#: one at a time): a whole node spacing h for a method that picks a node, about h / n for a
#: centroid over n node columns across the patch (:func:`tolerances`); a straight line between
#: knots on two steps misses the midpoint by up to half a step, so a quantity's tolerance is at
#: least this fraction of its step (refining below it chases the mesh, not the contact)
MESH_STEP_FRACTION = 0.5


@dataclass(frozen=True)
class MeshResolution:
    """What bounds the refinement of a mesh method's table (:func:`tolerances`).

    Attributes
    ----------
    spacing : ndarray, shape (2, 2)
        Per wheel (left, right): the lateral node spacing of the wheel and of the rail mesh, m.
    centroid : bool
        The method's contact point is a weighted mean over the nodes in contact.
    """

    spacing: np.ndarray
    centroid: bool

Record = dict[str, np.ndarray]


class ColumnRecord(dict):
    """A pose record that is row ``row`` of the stacked ``columns`` (name -> array, one row a
    record), as the jump step's results reach every rank (:func:`lutmpi.parallel.jumps_step.
    _share`, on one rank too). A plain dict of those rows to every reader, and read-only (its
    values are views of shared columns, and its reflection reads the columns);
    :meth:`Reflection.record` reflects it by reflecting its columns once for all their rows
    (:meth:`Field.reflected_column`) instead of one record at a time: a mirrored jump step
    takes ~3 records reflected per record solved (docs/TABLES.md, § Reflections), on every
    rank. Made by :meth:`at`."""

    __slots__ = ("columns", "row", "images")

    @classmethod
    def at(cls, columns: dict[str, np.ndarray], row: int, images: dict[tuple[bool, bool], Any]
           ) -> ColumnRecord:
        """Row ``row`` of ``columns``; ``images``: the columns' reflections made so far
        (shared by the rows of these columns, filled by :meth:`reflected`)."""
        rec = cls({n: c[row] for n, c in columns.items()})
        rec.columns, rec.row, rec.images = columns, row, images
        return rec

    def _read_only(self, *args: Any, **kwargs: Any) -> None:
        raise TypeError("a ColumnRecord is read-only (a row of shared columns): copy it with "
                        "dict(record) to change it")

    __setitem__ = __delitem__ = update = setdefault = pop = popitem = clear = _read_only

    def reflected(self, sides: bool, longitudinal: bool) -> ColumnRecord:
        """This record at the reflected pose (:meth:`Reflection.record`)."""
        key = (sides, longitudinal)
        image = self.images.get(key)
        if image is None:          # the columns reflected once, shared by all their rows
            image = self.images[key] = ({
                n: FIELDS_BY_NAME[n].reflected_column(c, sides, longitudinal)
                for n, c in self.columns.items()}, {})
        return ColumnRecord.at(image[0], self.row, image[1])


PoseSolver = Callable[[float, float], Record]


@dataclass(frozen=True)
class Jump:
    """One located jump at one yaw.

    Attributes
    ----------
    iyaw : int
        Yaw column.
    lo, hi : float
        Bracket ends (m): solved poses on either side, ``hi - lo <= TOL_M``.
    rec_lo, rec_hi : dict
        The pose records at ``lo`` and ``hi`` (schema field name -> array).
    kind, side : int
        Bit masks (:data:`lutmpi.table.schema.JUMP_KIND_BITS`, ``JUMP_SIDE_BITS``).
    """

    iyaw: int
    lo: float
    hi: float
    rec_lo: Record
    rec_hi: Record
    kind: int
    side: int

    @property
    def y(self) -> float:
        """Located position, the bracket's middle, m."""
        return 0.5 * (self.lo + self.hi)


def _disc(rec: Record) -> tuple[int, ...]:
    """Discrete key of a record: status, contacts per wheel."""
    disc = (int(rec[D.status]),)
    if D.n_contacts in rec:
        disc += tuple(np.asarray(rec[D.n_contacts], dtype=np.int64).ravel().tolist())
    return disc


def _keys(rec: Record) -> tuple[tuple[int, ...], np.ndarray]:
    """Discrete key (:func:`_disc`) and the primary contact coordinates per wheel (wheel s,
    rail v; shape (2, 2), m) of a record."""
    disc = _disc(rec)
    cols = [np.asarray(rec[n], float)[:, 0] for n in (D.wheel_s, D.rail_v) if n in rec]
    cont = np.stack(cols, axis=1) if cols else np.zeros((2, 0))
    return disc, cont


def _movement(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Per wheel: largest movement of the primary contact (m); inf where it exists on one side
    only."""
    fa, fb = np.isfinite(a), np.isfinite(b)
    d = np.where(fa & fb, np.abs(a - b), np.where(fa ^ fb, np.inf, 0.0))
    return d.max(axis=1) if d.shape[1] else np.zeros(d.shape[0])


def _distance(ka: tuple, kb: tuple) -> float:
    """Dissimilarity of two states: 10 per discrete mismatch plus the contact movement (m)."""
    mism = sum(x != y for x, y in zip(ka[0], kb[0], strict=True))
    move = _movement(ka[1], kb[1])
    return 10.0 * mism + float(np.minimum(move, 1.0).max(initial=0.0))


def classify(ka: tuple, kb: tuple, threshold: float) -> tuple[int, int]:
    """``(kind, side)`` bit masks of the change between two states (0, 0 when none counts)."""
    kind = side = 0
    if ka[0][0] != kb[0][0]:
        kind |= 4
        side |= 3
    for s in range(2):
        if len(ka[0]) > 1 + s and ka[0][1 + s] != kb[0][1 + s]:
            kind |= 2
            side |= 1 << s
    move = _movement(ka[1], kb[1])
    for s in range(2):
        if move[s] > threshold:
            kind |= 1
            side |= 1 << s
    return kind, side


def candidate_cells(arrays: dict[str, np.ndarray], threshold: float = CANDIDATE_M,
                    ) -> list[tuple[int, int]]:
    """Grid cells ``(iyaw, iy)`` (between ``iy`` and ``iy + 1``) that may hold a jump, in a fixed
    order (yaw column, then y).

    Parameters
    ----------
    arrays : dict
        The table's raw arrays of one method (name -> ``(ny, nyaw, *suffix)``); ``status`` and,
        when stored, ``n_contacts``, ``wheel_s``, ``rail_v`` are used.
    threshold : float
        Primary contact point movement that makes a cell a candidate, m.
    """
    ny, nyaw = arrays[D.status].shape
    out = []
    for j in range(nyaw):
        keys = [_keys(_node(arrays, i, j)) for i in range(ny)]
        moves = [_movement(keys[i][1], keys[i + 1][1]) for i in range(ny - 1)]
        for i in range(ny - 1):
            if classify(keys[i], keys[i + 1], threshold)[0] or _sudden(moves, i):
                out.append((j, i))
    return out


def _sudden(moves: list[np.ndarray], i: int) -> bool:
    """Whether cell ``i``'s primary contact moves (per wheel, ``moves[i]``, m) by more than
    :data:`CONFIRM_M` and :data:`RATE_RATIO` times as far as in the slower neighbouring cell."""
    near = [moves[k] for k in (i - 1, i + 1) if 0 <= k < len(moves)]
    if not near:
        return False
    slower = np.minimum.reduce(near)
    m = moves[i]
    return bool(np.any(np.isfinite(m) & (m > CONFIRM_M) & (m > RATE_RATIO * slower)))


def _node(arrays: dict[str, np.ndarray], i: int, j: int) -> Record:
    return {name: np.asarray(arr[i, j]) for name, arr in arrays.items()}


def refine_cell(arrays: dict[str, np.ndarray], y_axis: np.ndarray, yaw_axis: np.ndarray,
                cell: tuple[int, int], solve: PoseSolver, *, tol: float = TOL_M,
                threshold: float = CANDIDATE_M, confirm: float = CONFIRM_M
                ) -> tuple[list[Jump], list[tuple[float, Record]]]:
    """Locate the jumps of one candidate cell by bisection with direct solves.

    Parameters
    ----------
    arrays : dict
        Raw table arrays of one method.
    y_axis, yaw_axis : ndarray
        Grid axes, m and rad.
    cell : (int, int)
        ``(iyaw, iy)`` from :func:`candidate_cells`.
    solve : callable
        ``solve(y, yaw) -> record`` (schema field name -> array), the table's own method.
    tol, threshold, confirm : float
        Bracket width, candidate and confirmation movements, m.

    Returns
    -------
    jumps : list of Jump
        Sorted by y (empty when the cell was only steep).
    samples : list of (float, dict)
        Every pose solved, ``(y, record)``.
    """
    j, i = cell
    yaw = float(yaw_axis[j])
    lo, hi = float(y_axis[i]), float(y_axis[i + 1])
    samples: list[tuple[float, Record]] = []

    def sampled(y: float) -> Record:
        rec = solve(y, yaw)
        samples.append((y, rec))
        return rec

    rlo, rhi = _node(arrays, i, j), _node(arrays, i + 1, j)
    if not classify(_keys(rlo), _keys(rhi), threshold)[0]:
        threshold = confirm       # a candidate by its sudden movement (:func:`_sudden`)
    found = _search(lo, rlo, hi, rhi, sampled, j, tol, threshold, confirm, MAX_PER_CELL,
                    samples)
    return found, samples


def _search(lo: float, rlo: Record, hi: float, rhi: Record, solve: Callable[[float], Record],
            j: int, tol: float, threshold: float, confirm: float, budget: int,
            known: Sequence[tuple[float, Record]]) -> list[Jump]:
    """The jumps between ``lo`` and ``hi`` (:func:`refine_cell`'s steps 2-4). ``known``: the
    poses the cell's search has solved so far (``(y, record)``: the list that ``solve``
    appends each of its solves to, :func:`refine_cell`'s ``samples``, so that the later
    searches see the earlier ones' poses); while one lies inside the bracket, the bisection
    takes the one nearest its middle instead of solving the middle (the same rule, at a point
    already solved), so that the second and third jump of a cluster (a second contact
    appearing, the contact moving over, the first contact going, within micrometres) are not
    bisected again from the whole sub-interval."""
    klo, khi = _keys(rlo), _keys(rhi)
    if budget <= 0 or not classify(klo, khi, threshold)[0]:
        return []
    a, ra, ka, b, rb, kb = lo, rlo, klo, hi, rhi, khi
    while b - a > tol:
        mid = a + 0.5 * (b - a)
        inside = [(y, r) for y, r in known if a < y < b]
        if inside:
            m, rm = min(inside, key=lambda p: (abs(p[0] - mid), p[0]))
        else:
            m, rm = mid, solve(mid)
        km = _keys(rm)
        if _distance(km, ka) <= _distance(km, kb):
            a, ra, ka = m, rm, km
        else:
            b, rb, kb = m, rm, km
    kind, side = classify(ka, kb, confirm)
    if not kind:
        return []
    found = Jump(j, a, b, ra, rb, kind, side)
    left = _search(lo, rlo, a, ra, solve, j, tol, threshold, confirm, budget - 1, known)
    right = _search(b, rb, hi, rhi, solve, j, tol, threshold, confirm,
                    budget - 1 - len(left), known)
    return left + [found] + right


def _primaries(recs: Sequence[Record], name: str) -> list[list[float]]:
    """Per wheel, a per-contact quantity's primary contact in each of ``recs`` (Python floats:
    the refinement's bookkeeping runs for every pose it solves, and numpy's per-call cost on
    a few values was most of it)."""
    cols = [np.asarray(r[name], float)[:, 0].tolist() for r in recs]
    return [[c[s] for c in cols] for s in range(2)]


def _primary_max(recs: Sequence[Record], name: str) -> np.ndarray:
    """Per wheel, the largest magnitude of a per-contact quantity's primary contact over
    ``recs`` (NaN where no record has a finite one; shape (2,))."""
    out = []
    for vals in _primaries(recs, name):
        fin = [abs(v) for v in vals if math.isfinite(v)]
        out.append(max(fin) if fin else math.nan)
    return np.array(out)


def tolerances(recs: Sequence[Record], mesh: MeshResolution | None, scale: float = 1.0
               ) -> dict[str, Any]:
    """Refinement tolerance per quantity for an interval with knot and midpoint records
    ``recs``: :data:`REFINE_TOL`, raised for a mesh method to :data:`MESH_STEP_FRACTION` of the
    step its contact point moves in (per wheel, primary contact), all times ``scale`` (the
    config's ``output.refine_scale``: above 1 a coarser table between the grid points, built
    with fewer solves).

    The point moves along the profile in steps of ``h / n``: ``n = 1`` for a method that picks
    a node; for a centroid, ``n = 2 a / h`` node columns across the patch, whose half-width
    ``a = sqrt(2 delta / (kappa_w + kappa_r))`` follows from the indentation ``delta`` and the
    transverse curvatures (no floor where the pair is conformal, ``kappa_w + kappa_r <= 0``, or
    these quantities are not stored). The rolling radius then moves in steps of
    ``h |sin(gamma)| / n``, the contact angle in steps of ``max(h_w |kappa_w|, h_r |kappa_r|) / n``
    (``gamma``: contact angle).

    Parameters
    ----------
    recs : sequence of dict
        The records of the interval (ends and midpoint).
    mesh : MeshResolution or None
        The method's mesh; None for a method without one (the reference).
    scale : float
        Factor on every tolerance (1: as above).

    Returns
    -------
    dict
        Quantity -> tolerance (float, or (2,) per wheel for the per-contact quantities).
    """
    tol = _raised(recs, mesh)
    return tol if scale == 1.0 else {name: t * scale for name, t in tol.items()}


def _raised(recs: Sequence[Record], mesh: MeshResolution | None) -> dict[str, Any]:
    """:func:`tolerances` before its scale."""
    tol: dict[str, Any] = dict(REFINE_TOL)
    names = recs[0].keys()
    curv = D.curv_wheel_transverse in names and D.curv_rail_transverse in names
    if mesh is None or not curv:
        return tol
    hw, hr = mesh.spacing[:, 0], mesh.spacing[:, 1]
    kw = _primary_max(recs, D.curv_wheel_transverse)
    kr = _primary_max(recs, D.curv_rail_transverse)
    n = np.ones(2)
    if mesh.centroid:
        if D.indentation not in names:
            return tol
        half = []
        for kws, krs, deltas in zip(_primaries(recs, D.curv_wheel_transverse),
                                    _primaries(recs, D.curv_rail_transverse),
                                    _primaries(recs, D.indentation), strict=True):
            best = math.inf
            for kw_, kr_, delta in zip(kws, krs, deltas, strict=True):
                krel = kw_ + kr_
                q = 2.0 * delta / krel if krel != 0.0 else math.nan
                if math.isfinite(q) and q >= 0.0:       # else NaN or inf: conformal
                    best = min(best, math.sqrt(q))      # patch half-width, m
            half.append(best)
        n = np.maximum(1.0, 2.0 * np.array(half) / np.minimum(hw, hr))
    if D.contact_angle in names:
        gamma = np.minimum(_primary_max(recs, D.contact_angle), 0.5 * math.pi)
        tol[D.rolling_radius] = np.fmax(REFINE_TOL[D.rolling_radius],
                                        MESH_STEP_FRACTION * hw * np.sin(gamma) / n)
    tol[D.contact_angle] = np.fmax(REFINE_TOL[D.contact_angle],
                                   MESH_STEP_FRACTION * np.fmax(hw * kw, hr * kr) / n)
    return tol


Knot = tuple[float, Record]


def _miss(knots: Sequence[Knot | None], xm: float, rm: Record, tols: dict[str, Any]) -> float:
    """Largest miss of the interpolant between an interval's knots at its midpoint ``(xm, rm)``,
    in units of ``tols`` (:func:`tolerances`; NaN-safe: a quantity missing anywhere is not
    checked). ``knots``: ``(left neighbour, x0, x1, right neighbour)``, the neighbours None
    where the piece ends. The straight line through ``x0, x1`` predicts the midpoint, the
    monotone cubic through all the knots given (:func:`pchip_mid`) for :data:`CUBIC_TESTED`."""
    _, (x0, r0), (x1, r1), _ = knots
    worst = 0.0
    for name in REFINE_TOL:
        if name not in rm:
            continue
        if name in CUBIC_TESTED:         # a per-point quantity (float() refuses any other)
            given = [k for k in knots if k is not None]
            rows = [(pchip_mid([x for x, _ in given], [float(r[name]) for _, r in given],
                               knots[0] is not None, xm), float(rm[name]), float(tols[name]))]
        elif np.ndim(rm[name]):          # per contact: the primary contact of each wheel
            tol = np.broadcast_to(tols[name], (2,)).tolist()
            rows = [(0.5 * (a + b), m, t) for (a, b, m), t
                    in zip(_primaries((r0, r1, rm), name), tol, strict=True)]
        else:
            rows = [(0.5 * (float(r0[name]) + float(r1[name])), float(rm[name]),
                     float(tols[name]))]
        for pred, m, t in rows:          # Python floats: the same arithmetic as on arrays
            d = abs(pred - m) / t
            if math.isfinite(d):
                worst = max(worst, d)
    return worst


def pchip_mid(x: Sequence[float], v: Sequence[float], has_left: bool, xm: float) -> float:
    """The monotone cubic (Fritsch-Carlson, as :func:`lutmpi.table.interp.pchip_slopes`) through
    two to four knots ``x`` (increasing, m) with values ``v`` at ``xm``, inside the interval that
    starts at the second knot when ``has_left`` (a left neighbour comes first), else at the
    first (the piece starts there). Python floats: it runs for every pose the refinement
    solves."""
    i = 1 if has_left else 0
    h = [x[k + 1] - x[k] for k in range(len(x) - 1)]
    delta = [(v[k + 1] - v[k]) / h[k] for k in range(len(h))]
    if len(x) == 2:
        d0 = d1 = delta[0]
    else:
        d0 = _pchip_slope(h, delta, i)
        d1 = _pchip_slope(h, delta, i + 1)
    t = (xm - x[i]) / h[i]
    t2, t3 = t * t, t * t * t
    return ((2 * t3 - 3 * t2 + 1) * v[i] + (t3 - 2 * t2 + t) * h[i] * d0
            + (-2 * t3 + 3 * t2) * v[i + 1] + (t3 - t2) * h[i] * d1)


def _pchip_slope(h: list[float], delta: list[float], k: int) -> float:
    """The Fritsch-Carlson slope at knot ``k`` from the spacings ``h`` and secants ``delta``
    (at an end SciPy's shape-preserving three-point formula)."""
    n = len(h)
    if k == 0 or k == n:
        h0, h1, m0, m1 = (h[0], h[1], delta[0], delta[1]) if k == 0 else (
            h[-1], h[-2], delta[-1], delta[-2])
        d = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        if _sign(d) != _sign(m0):
            return 0.0
        if _sign(m0) != _sign(m1) and abs(d) > abs(3 * m0):
            return 3 * m0
        return d
    m0, m1 = delta[k - 1], delta[k]
    if math.isnan(m0) or math.isnan(m1):
        return math.nan
    if not _sign(m0) * _sign(m1) > 0:
        return 0.0
    w1, w2 = 2 * h[k] + h[k - 1], h[k] + 2 * h[k - 1]
    return (w1 + w2) / (w1 / m0 + w2 / m1)


def _sign(a: float) -> float:
    """``numpy.sign`` of a Python float (NaN for NaN)."""
    return math.nan if math.isnan(a) else float(a > 0) - float(a < 0)


def refine_interval(x0: float, r0: Record, x1: float, r1: Record, yaw: float, solve: PoseSolver,
                    min_width: float = MIN_WIDTH_M, mesh: MeshResolution | None = None,
                    parent: tuple[float, dict] | None = None, scale: float = 1.0,
                    outer: tuple[Knot | None, Knot | None] = (None, None),
                    found: list[Jump] | None = None, iyaw: int = 0
                    ) -> list[tuple[float, Record]]:
    """Midpoint solves of one interval of a piece, recursively where the interpolant misses
    the midpoint (:func:`_miss`) by more than its :func:`tolerances` (``mesh``: the method's
    mesh, ``scale``: the factor on the tolerances, as there) and by less than
    :data:`REFINE_GAIN` times the parent interval's miss (``parent``: its miss and tolerances;
    both misses in the parent's tolerances). ``outer``: the knots next to ``x0`` and ``x1`` in
    the piece (:func:`neighbours`; None where it ends), which the cubic of
    :data:`CUBIC_TESTED` goes through; a half's are the other end and the outer knot on its
    side.

    A jump the grid-level search did not see shows here in one of two ways: a midpoint whose
    discrete state (status, contact count) differs from an end (two changes that cancel in
    one cell), or a miss that does not fall when the interval halves while the contact point
    moves by more than :data:`CONFIRM_M` between the ends (a step hidden in a fast-moving
    contact: on a worn flange the contact ran 1.9 mm per mm of y and jumped 0.85 mm within
    it, a rolling radius step of 1.4 mm that no cell's movement flagged). With ``found`` (a
    list) the interval is then searched as a cell is (:func:`_search`, with the poses it
    solved), the jumps appended to ``found`` (column ``iyaw``) and the pieces between them
    refined on their own; without it such a midpoint is dropped and the interval keeps its two
    knots (the straight line across the change).

    Returns
    -------
    list of (float, dict)
        The solved poses ``(y, record)`` kept as knots, sorted by y.
    """
    if x1 - x0 < 2 * min_width:
        return []
    xm = x0 + 0.5 * (x1 - x0)
    rm = solve(xm, yaw)
    km = _disc(rm)
    if km != _disc(r0) or km != _disc(r1):
        if found is None:
            return []
        return _split(x0, r0, x1, r1, (xm, rm), yaw, solve, found, iyaw, min_width, mesh,
                      scale, outer)
    out = [(xm, rm)]
    tols = tolerances((r0, r1, rm), mesh, scale)
    knots = (outer[0], (x0, r0), (x1, r1), outer[1])
    miss = _miss(knots, xm, rm, tols)
    if miss > 1.0 and (parent is None
                       or _miss(knots, xm, rm, parent[1]) < REFINE_GAIN * parent[0]):
        here = (miss, tols)
        n_found = len(found) if found is not None else 0
        left = refine_interval(x0, r0, xm, rm, yaw, solve, min_width, mesh, here, scale,
                               (outer[0], (x1, r1)), found, iyaw)
        # a jump just found left of xm: x0 lies across it, no neighbour of the right half's
        near = (x0, r0) if found is None or len(found) == n_found else None
        out = (left + out
               + refine_interval(xm, rm, x1, r1, yaw, solve, min_width, mesh, here, scale,
                                 (near, outer[1]), found, iyaw))
    elif (miss > 1.0 and found is not None
          and classify(_keys(r0), _keys(r1), CONFIRM_M)[0]):
        # the miss did not fall by halving, and the contact moved: a step, not a curvature
        return _split(x0, r0, x1, r1, (xm, rm), yaw, solve, found, iyaw, min_width, mesh,
                      scale, outer)
    return out


def _split(x0: float, r0: Record, x1: float, r1: Record, mid: Knot, yaw: float,
           solve: PoseSolver, found: list[Jump], iyaw: int, min_width: float,
           mesh: MeshResolution | None, scale: float,
           outer: tuple[Knot | None, Knot | None]) -> list[tuple[float, Record]]:
    """:func:`refine_interval` where the interval holds a change its ends do not tell: the
    jumps between ``x0``, the solved midpoint ``mid`` and ``x1`` located by :func:`_search`
    (a cell's steps 2-4, at most :data:`MAX_PER_CELL`, with :data:`CONFIRM_M` as the
    threshold: what a cell searched by its sudden movement takes), appended to ``found``; the
    pieces between them refined as intervals of their own. Returns every pose solved here
    (but those strictly inside a bracket), sorted by y. Where no jump is confirmed (a
    continuous contact that is merely steep) the poses are knots and nothing else changes."""
    samples: list[tuple[float, Record]] = [mid]

    def sampled(y: float) -> Record:
        rec = solve(y, yaw)
        samples.append((y, rec))
        return rec

    here: list[Jump] = []
    for (a, ra), (b, rb) in (((x0, r0), mid), (mid, (x1, r1))):
        here += _search(a, ra, b, rb, sampled, iyaw, TOL_M, CONFIRM_M, CONFIRM_M,
                        MAX_PER_CELL - len(here), samples)
    if not here:
        return sorted(samples, key=lambda p: p[0])
    if len(here) >= MAX_PER_CELL:
        log.warning("%d jumps between y = %.4f and %.4f mm at yaw %.4g rad found by the "
                    "refinement, its search's limit: located in part (the table may "
                    "interpolate across others there)", len(here), x0 * 1e3, x1 * 1e3, yaw)
    here.sort(key=lambda jp: jp.lo)
    found.extend(here)
    kept = sorted((p for p in samples if not any(jp.lo < p[0] < jp.hi for jp in here)),
                  key=lambda p: p[0])
    # the pieces: x0 .. first bracket, between brackets, last bracket .. x1; each piece's
    # knots are its ends and the poses solved inside it, each pair refined with its neighbours
    bounds = [((x0, r0), outer[0])] + [((jp.hi, jp.rec_hi), None) for jp in here]
    ends = [((jp.lo, jp.rec_lo), None) for jp in here] + [((x1, r1), outer[1])]
    out = list(kept)
    for (start, left), (stop, right) in zip(bounds, ends, strict=True):
        inner = [p for p in kept if start[0] < p[0] < stop[0]]
        piece = [start] + inner + [stop]
        for k in range(len(piece) - 1):
            before = piece[k - 1] if k > 0 else left
            after = piece[k + 2] if k + 2 < len(piece) else right
            ka = _disc(piece[k][1])
            same = [n if n is not None and _disc(n[1]) == ka else None for n in (before, after)]
            out += refine_interval(piece[k][0], piece[k][1], piece[k + 1][0], piece[k + 1][1],
                                   yaw, solve, min_width, mesh, None, scale,
                                   (same[0], same[1]), found, iyaw)
    return sorted(out, key=lambda p: p[0])


def refine_item(iyaw: int, x0: float, r0: Record, x1: float, r1: Record, yaw: float,
                solve: PoseSolver, *, mesh: MeshResolution | None = None, scale: float = 1.0,
                outer: tuple[Knot | None, Knot | None] = (None, None)
                ) -> tuple[list[Jump], list[tuple[float, Record]]]:
    """One refinement interval of column ``iyaw`` (:func:`refinement_plan`'s item):
    :func:`refine_interval` with the jumps it finds kept.

    Parameters
    ----------
    iyaw : int
        The interval's yaw column (the jumps' ``iyaw``).
    x0, r0, x1, r1 : float, dict
        The interval's ends (y, m) and their records.
    yaw : float
        The column's yaw, rad.
    solve : callable
        ``solve(y, yaw) -> record``, the table's own method.
    mesh, scale, outer
        As :func:`refine_interval` takes them.

    Returns
    -------
    jumps : list of Jump
        Sorted by y.
    samples : list of (float, dict)
        The poses solved and kept as knots ``(y, record)``, sorted by y: the shape of
        :func:`refine_cell`'s result, and reflected as it is (:meth:`Mirror.cell_result`).
    """
    found: list[Jump] = []
    knots = refine_interval(x0, r0, x1, r1, yaw, solve, mesh=mesh, scale=scale, outer=outer,
                            found=found, iyaw=iyaw)
    return sorted(found, key=lambda jp: jp.lo), knots


def column_knots(arrays: dict[str, np.ndarray], y_axis: np.ndarray, j: int,
                 jumps: Sequence[Jump], samples: Sequence[tuple[float, Record]]
                 ) -> list[tuple[float, Record, int]]:
    """The knots of column ``j`` sorted by y: ``(y, record, piece)`` for grid nodes, samples and
    bracket ends (samples strictly inside a bracket are dropped)."""
    col = sorted((jp for jp in jumps if jp.iyaw == j), key=lambda jp: jp.lo)
    pts = [(float(y_axis[i]), _node(arrays, i, j)) for i in range(y_axis.size)]
    pts += [(y, r) for y, r in samples]
    pts += [(jp.lo, jp.rec_lo) for jp in col] + [(jp.hi, jp.rec_hi) for jp in col]
    out, seen = [], set()
    for y, r in sorted(pts, key=lambda p: p[0]):
        if y in seen or any(jp.lo < y < jp.hi for jp in col):
            continue
        seen.add(y)
        out.append((y, r, sum(jp.y <= y for jp in col)))
    return out


def refinement_items(knots: Sequence[tuple[float, Record, int]], min_width: float = MIN_WIDTH_M
                     ) -> list[int]:
    """Indices k of the knot pairs (k, k + 1) of one column that lie in one piece and are wide
    enough to refine."""
    return [k for k in range(len(knots) - 1)
            if knots[k][2] == knots[k + 1][2] and knots[k + 1][0] - knots[k][0] >= 2 * min_width]


def neighbours(knots: Sequence[tuple[float, Record, int]], k: int
               ) -> tuple[Knot | None, Knot | None]:
    """The knots next to the pair ``(k, k + 1)`` of one column (:func:`column_knots`) in the
    same piece and discrete state (status, contacts: a change the jump search left unlocated is
    no neighbour), ``(y, record)`` each; None where the piece ends (the ``outer`` of
    :func:`refine_interval`)."""
    piece, disc = knots[k][2], _disc(knots[k][1])

    def same(i: int) -> bool:
        return 0 <= i < len(knots) and knots[i][2] == piece and _disc(knots[i][1]) == disc

    return (knots[k - 1][:2] if same(k - 1) else None,
            knots[k + 2][:2] if same(k + 2) else None)


@dataclass(frozen=True)
class JumpSet:
    """The jumps of one method as arrays (the layout of ``/<method>/jumps``).

    Attributes
    ----------
    arrays : dict
        :data:`lutmpi.table.schema.JUMP_FIELDS` name -> ``(nyaw, K)``.
    limits : dict
        Field name -> ``(nyaw, K, 2, *suffix)``: the records at ``jump_y_lo`` / ``jump_y_hi``.
    knot_y : ndarray, (nyaw, E)
        Extra knots (every pose solved after the build but the bracket ends), NaN padded.
    knots : dict
        Field name -> ``(nyaw, E, *suffix)``.
    """

    arrays: dict[str, np.ndarray]
    limits: dict[str, np.ndarray]
    knot_y: np.ndarray
    knots: dict[str, np.ndarray]

    @property
    def count(self) -> np.ndarray:
        """Jumps per yaw column, (nyaw,)."""
        return np.isfinite(self.arrays[J.jump_y]).sum(axis=1)


def assemble(jumps: Sequence[Jump], extra: Sequence[tuple[int, float, Record]], nyaw: int,
             fields: Sequence[Field]) -> JumpSet:
    """Arrange located jumps and extra knots ``(iyaw, y, record)`` into :class:`JumpSet` arrays
    (sorted by y in each column; extra knots that are bracket ends are left out)."""
    per = [sorted((jp for jp in jumps if jp.iyaw == j), key=lambda jp: jp.lo) for j in range(nyaw)]
    k = max((len(p) for p in per), default=0)
    arrays = {f.name: np.full((nyaw, k), np.nan if f.dtype.startswith("f") else 0, f.dtype)
              for f in JUMP_FIELDS}
    limits = {f.name: f.empty((nyaw, k, 2)) for f in fields}
    for j, col in enumerate(per):
        for n, jp in enumerate(col):
            for name, value in ((J.jump_y, jp.y), (J.jump_y_lo, jp.lo), (J.jump_y_hi, jp.hi),
                                (J.jump_kind, jp.kind), (J.jump_side, jp.side)):
                arrays[name][j, n] = value
            for f in fields:
                limits[f.name][j, n, 0] = jp.rec_lo[f.name]
                limits[f.name][j, n, 1] = jp.rec_hi[f.name]
    ends = {(jp.iyaw, y) for jp in jumps for y in (jp.lo, jp.hi)}
    cols: list[dict[float, Record]] = [{} for _ in range(nyaw)]
    for j, y, rec in extra:
        if (j, y) not in ends:
            cols[j][y] = rec
    e = max((len(c) for c in cols), default=0)
    knot_y = np.full((nyaw, e), np.nan)
    knots = {f.name: f.empty((nyaw, e)) for f in fields}
    for j, col in enumerate(cols):
        for n, y in enumerate(sorted(col)):
            knot_y[j, n] = y
            for f in fields:
                knots[f.name][j, n] = col[y][f.name]
    return JumpSet(arrays, limits, knot_y, knots)


def locate_jumps(arrays: dict[str, np.ndarray], y_axis: np.ndarray, yaw_axis: np.ndarray,
                 solve: PoseSolver, fields: Sequence[Field], *, refine: bool = True,
                 mesh: MeshResolution | None = None, scale: float = 1.0,
                 mirror: Mirror | None = None, **kw: Any) -> JumpSet:
    """Every jump of one method of a table, and the refinement knots, serially (the steps the
    build runs in parallel: :func:`candidate_cells`, :func:`refine_cell`, :func:`column_knots`,
    :func:`refine_interval` with the factor ``scale`` on its tolerances, :func:`assemble`;
    ``mirror``: a cell or an interval that is the image of another searched or refined
    before it takes that one's poses reflected, not solved)."""
    cells = candidate_cells(arrays, kw.get("threshold", CANDIDATE_M))
    res = mirrored_map(cells, lambda todo: [refine_cell(arrays, y_axis, yaw_axis, c, solve, **kw)
                                            for c in todo],
                       mirror.cells(cells) if mirror else None,
                       mirror.cell_result if mirror else None)
    found, extra = found_and_samples(cells, res)
    warn_in_part(searched_in_part(arrays, y_axis, cells, res), yaw_axis)
    if refine:
        items = refinement_plan(arrays, y_axis, yaw_axis.size, found, extra)
        refined = mirrored_map(items, lambda todo: [refine_item(
            j, x0, r0, x1, r1, float(yaw_axis[j]), solve, mesh=mesh, scale=scale, outer=outer)
            for j, (x0, r0), (x1, r1), outer in todo], mirror.items(items) if mirror else None,
            mirror.cell_result if mirror else None)
        found += [jp for jps, _ in refined for jp in jps]
        extra += [(it[0], y, r) for it, (_, rs) in zip(items, refined, strict=True)
                  for y, r in rs]
    return assemble(found, extra, yaw_axis.size, fields)


#: one refinement interval: ``(iyaw, (x0, r0), (x1, r1), outer)`` (:func:`refine_interval`'s
#: ends and outer knots)
Item = tuple[int, Knot, Knot, tuple[Knot | None, Knot | None]]


def found_and_samples(cells: Sequence[tuple[int, int]],
                      res: Sequence[tuple[list[Jump], list[tuple[float, Record]]]]
                      ) -> tuple[list[Jump], list[tuple[int, float, Record]]]:
    """The jumps and the solved poses ``(iyaw, y, record)`` of the searched ``cells``
    (:func:`refine_cell`'s results ``res``, in cell order)."""
    found = [jp for jps, _ in res for jp in jps]
    extra = [(c[0], y, r) for c, (_, samples) in zip(cells, res, strict=True) for y, r in samples]
    return found, extra


def searched_in_part(arrays: dict[str, np.ndarray], y_axis: np.ndarray,
                     cells: Sequence[tuple[int, int]],
                     res: Sequence[tuple[list[Jump], list[tuple[float, Record]]]]
                     ) -> list[tuple[int, float, float]]:
    """The cells whose search stopped at :data:`MAX_PER_CELL` jumps with a change it would
    have searched still left between two of its pieces' ends (the change and threshold of
    :func:`refine_cell`; no solve: the grid nodes and the jumps' one-sided records), as
    ``(iyaw, y_lo, y_hi)`` (m): between those ends the table interpolates across a jump it did
    not locate."""
    out = []
    for (j, i), (jps, _) in zip(cells, res, strict=True):
        if len(jps) < MAX_PER_CELL:
            continue
        lo, hi = _node(arrays, i, j), _node(arrays, i + 1, j)
        threshold = (CANDIDATE_M if classify(_keys(lo), _keys(hi), CANDIDATE_M)[0]
                     else CONFIRM_M)
        col = sorted(jps, key=lambda jp: jp.lo)
        ends = [lo] + [r for jp in col for r in (jp.rec_lo, jp.rec_hi)] + [hi]
        if any(classify(_keys(ends[k]), _keys(ends[k + 1]), threshold)[0]
               for k in range(0, len(ends), 2)):
            out.append((j, float(y_axis[i]), float(y_axis[i + 1])))
    return out


def warn_in_part(in_part: Sequence[tuple[int, float, float]], yaw_axis: np.ndarray,
                 method: str = "") -> None:
    """A warning for each cell of :func:`searched_in_part` (``method``: the table's, named
    first when given)."""
    for j, lo, hi in in_part:
        log.warning("%smore than %d jumps between y = %.4f and %.4f mm at yaw %.4g rad: located "
                    "in part (the table interpolates across the others)",
                    f"{method}: " if method else "", MAX_PER_CELL, lo * 1e3, hi * 1e3,
                    yaw_axis[j])


def refinement_plan(arrays: dict[str, np.ndarray], y_axis: np.ndarray, nyaw: int,
                    found: Sequence[Jump], extra: Sequence[tuple[int, float, Record]]
                    ) -> list[Item]:
    """Every interval to refine (:func:`refinement_items` of each column's knots), in column
    order: ``(iyaw, (x0, r0), (x1, r1), outer)``."""
    items: list[Item] = []
    for j in range(nyaw):
        knots = column_knots(arrays, y_axis, j, found, [(y, r) for jj, y, r in extra if jj == j])
        items += [(j, knots[k][:2], knots[k + 1][:2], neighbours(knots, k))
                  for k in refinement_items(knots)]
    return items


T = TypeVar("T")
R = TypeVar("R")
#: :func:`mirror_pairs`' answer: item index -> (index of the item it is the image of, the
#: reflection that maps that one onto it)
Pairs = dict[int, tuple[int, "Reflection"]]


def mirrored_map(items: Sequence[T], run: Callable[[list[T]], list[R]], pairs: Pairs | None,
                 flip: Callable[[Reflection, R], R] | None) -> list[R]:
    """``run`` on the items that are no other's image, the rest by ``flip(reflection,
    result)`` of their image's result (``pairs``: :meth:`Mirror.cells`, :meth:`Mirror.items`;
    everything run when None)."""
    pairs = pairs or {}
    got = iter(run([it for n, it in enumerate(items) if n not in pairs]))
    out: list[R] = []
    for n in range(len(items)):
        if n in pairs:
            m, g = pairs[n]
            out.append(flip(g, out[m]))
        else:
            out.append(next(got))
    return out


def mirror_pairs(keys: Sequence[Hashable], images: Sequence[tuple[Reflection, Callable[
        [Any], Hashable]]]) -> Pairs:
    """``{n: (m, g)}`` for every ``keys[n]`` that is the image under a reflection ``g`` of
    ``keys[m]``, ``m < n`` and ``m`` no image itself (solved); ``images``: each reflection
    with its map of keys (an involution). An item that is only its own image, or whose images
    are not among ``keys``, is no pair (solved)."""
    first: dict[Hashable, int] = {}
    for n, k in enumerate(keys):
        first.setdefault(k, n)
    out: Pairs = {}
    for n, k in enumerate(keys):
        for g, image in images:
            m = first.get(image(k))
            if m is not None and m < n and m not in out:
                out[n] = (m, g)
                break
    return out


#: largest asymmetry of a grid axis about zero (m, rad) that :meth:`Mirror.of` accepts:
#: ``numpy.linspace(-a, a, n)`` is symmetric to a few ulp (4e-15 m on the default grid)
MIRROR_AXIS_TOL = 1e-12


@dataclass(frozen=True)
class Reflection:
    """A reflection of the track frame that maps the table's poses onto poses of its grid.

    Attributes
    ----------
    sides : bool
        In the x-z plane: y -> -y, the wheels swapped (a symmetric pair only).
    longitudinal : bool
        In the y-z plane: x -> -x (any pair: wheels of revolution, rails extruded along x).

    The pose ``(y, yaw)`` goes to ``(-y, -yaw)`` (sides), ``(y, -yaw)`` (longitudinal) or
    ``(-y, yaw)`` (both).
    """

    sides: bool
    longitudinal: bool

    @property
    def flips_yaw(self) -> bool:
        return self.sides != self.longitudinal

    def record(self, rec: Record) -> Record:
        """A pose record at the reflected pose (:meth:`lutmpi.table.schema.Field.reflected`;
        a :class:`ColumnRecord` through its columns, the same values)."""
        if isinstance(rec, ColumnRecord):
            return rec.reflected(self.sides, self.longitudinal)
        return {name: FIELDS_BY_NAME[name].reflected(v, self.sides, self.longitudinal)
                for name, v in rec.items()}

    def fill_row(self, rows: dict[str, dict[str, np.ndarray]], src: int, dst: int) -> None:
        """Row ``dst`` of every method's records (``method -> name -> array``) set to row
        ``src`` reflected; its compute time 0 (not solved)."""
        for arrays in rows.values():
            for name, arr in arrays.items():
                if name in TIMING_FIELDS:
                    arr[dst] = 0.0
                else:
                    arr[dst] = FIELDS_BY_NAME[name].reflected(arr[src], self.sides,
                                                              self.longitudinal)


@dataclass(frozen=True)
class Mirror:
    """The reflections that map a table's grid onto itself (:class:`Reflection`): cell
    ``(j, i)`` goes to ``(nyaw - 1 - j, ...)`` where the yaw changes sign and to
    ``(..., ny - 2 - i)`` where y does; a grid node to its mirror node, any other position
    ``y`` to ``-y``.

    Attributes
    ----------
    nodes : dict
        Grid node y -> its mirror node's y (m).
    ny, nyaw : int
        Grid size.
    reflections : tuple of Reflection
        Those that apply (not the identity): a group with it.
    """

    nodes: dict[float, float]
    ny: int
    nyaw: int
    reflections: tuple[Reflection, ...]

    @classmethod
    def of(cls, y_axis: np.ndarray, yaw_axis: np.ndarray, symmetric_pair: bool
           ) -> Mirror | None:
        """The reflections a grid allows (an axis symmetric about zero within
        :data:`MIRROR_AXIS_TOL`; y -> -y only with a ``symmetric_pair``), or None when none
        does."""
        y, yaw = np.asarray(y_axis, float), np.asarray(yaw_axis, float)
        sym_y = bool(np.max(np.abs(y + y[::-1])) <= MIRROR_AXIS_TOL) and symmetric_pair
        sym_yaw = bool(np.max(np.abs(yaw + yaw[::-1])) <= MIRROR_AXIS_TOL) and yaw.size > 1
        refl = tuple(g for g, ok in ((Reflection(False, True), sym_yaw),
                                     (Reflection(True, False), sym_y and sym_yaw),
                                     (Reflection(True, True), sym_y)) if ok)
        if not refl:
            return None
        return cls({float(a): float(b) for a, b in zip(y, y[::-1], strict=True)}, y.size,
                   yaw.size, refl)

    def describe(self) -> str:
        """The reflections in words (the build log)."""
        names = {(False, True): "(y, yaw) -> (y, -yaw)", (True, False): "(y, yaw) -> (-y, -yaw)",
                 (True, True): "(y, yaw) -> (-y, yaw)"}
        return ", ".join(names[(g.sides, g.longitudinal)] for g in self.reflections)

    def y(self, g: Reflection, v: float) -> float:
        """The image of the position ``v`` (m)."""
        return self.nodes.get(v, -v) if g.sides else v

    def column(self, g: Reflection, j: int) -> int:
        return self.nyaw - 1 - j if g.flips_yaw else j

    def jump(self, g: Reflection, jp: Jump) -> Jump:
        """The image of a jump (a reflection in y swaps its bracket's ends and its sides)."""
        j = self.column(g, jp.iyaw)
        if not g.sides:
            return Jump(j, jp.lo, jp.hi, g.record(jp.rec_lo), g.record(jp.rec_hi), jp.kind,
                        jp.side)
        side = ((jp.side & 1) << 1) | ((jp.side & 2) >> 1)
        return Jump(j, self.y(g, jp.hi), self.y(g, jp.lo), g.record(jp.rec_hi),
                    g.record(jp.rec_lo), jp.kind, side)

    def samples(self, g: Reflection, samples: list[tuple[float, Record]]
                ) -> list[tuple[float, Record]]:
        """Solved poses ``(y, record)`` reflected (reversed where y changes sign: sorted stays
        sorted)."""
        out = [(self.y(g, y), g.record(r)) for y, r in samples]
        return out[::-1] if g.sides else out

    def cell_result(self, g: Reflection, res: tuple[list[Jump], list[tuple[float, Record]]]
                    ) -> tuple[list[Jump], list[tuple[float, Record]]]:
        """:func:`refine_cell`'s result for the image of its cell."""
        jps, samples = res
        jps = [self.jump(g, jp) for jp in jps]
        return (jps[::-1] if g.sides else jps), self.samples(g, samples)

    def grid_plan(self, todo: np.ndarray) -> tuple[np.ndarray, dict[int, list[tuple[
            int, Reflection]]]]:
        """Which of the grid points ``todo`` (flat indices, row-major ``(iy, iyaw)``) to solve
        and which to fill by reflection: ``(solve, images)``, ``images[p]`` the points of
        ``todo`` that are images of the solved point ``p``, each with its reflection. A point
        is solved when it is the smallest of its orbit, or when that one is not in ``todo``
        (done before: a resumed build)."""
        todo = np.asarray(todo, dtype=np.int64)
        pending = set(todo.tolist())
        solve: list[int] = []
        images: dict[int, list[tuple[int, Reflection]]] = {}
        for p in todo.tolist():
            i, j = divmod(p, self.nyaw)
            orbit: dict[int, Reflection] = {}
            for g in self.reflections:
                q = ((self.ny - 1 - i) if g.sides else i) * self.nyaw + self.column(g, j)
                if q != p:
                    orbit.setdefault(q, g)
            rep = min(orbit, default=p)
            if rep < p and rep in pending:
                continue          # filled from its orbit's smallest point
            solve.append(p)       # the smallest, or (resumed) the smallest is done: solved
            images[p] = [(q, g) for q, g in sorted(orbit.items())
                         if q in pending] if rep >= p else []
        return np.asarray(solve, dtype=np.int64), images

    def cells(self, cells: Sequence[tuple[int, int]]) -> Pairs:
        """:func:`mirror_pairs` of candidate cells ``(iyaw, iy)``."""
        def image(g: Reflection) -> Callable[[tuple[int, int]], tuple[int, int]]:
            return lambda c: (self.column(g, c[0]), self.ny - 2 - c[1] if g.sides else c[1])

        return mirror_pairs(cells, [(g, image(g)) for g in self.reflections])

    def items(self, items: Sequence[Item]) -> Pairs:
        """:func:`mirror_pairs` of refinement intervals (:func:`refinement_plan`): an image
        has the reflected ends and outer knots (swapped where y changes sign) in the image's
        column."""
        def key(it: Item) -> tuple:
            j, a, b, (o0, o1) = it
            return (j, a[0], b[0], None if o0 is None else o0[0], None if o1 is None else o1[0])

        def image(g: Reflection) -> Callable[[tuple], tuple]:
            def f(k: tuple) -> tuple:
                j, a, b, o0, o1 = k
                ys = [None if v is None else self.y(g, v) for v in (a, b, o0, o1)]
                if g.sides:
                    ys = [ys[1], ys[0], ys[3], ys[2]]
                return (self.column(g, j), *ys)
            return f

        return mirror_pairs([key(it) for it in items], [(g, image(g)) for g in self.reflections])


def wheel_flange_angle(wheel: Any) -> float:
    """Steepest angle of a wheel profile's flange flank (rad), between the flange tip and the tape
    circle (``s = 0``): the angle of Nadal's derailment limit.

    Parameters
    ----------
    wheel : lutmpi.profiles.model.Profile
        Wheel profile (``y_min``, ``z_at``, ``slope``; s in m, positive toward the field side).
    """
    s = np.linspace(wheel.y_min, 0.0, 4000)
    tip = s[int(np.argmax(wheel.z_at(s)))]
    flank = np.linspace(tip, 0.0, 4000)
    return float(np.arctan(np.max(-wheel.slope(flank))))


def wheelset_flange_angle(wheels: Any) -> float:
    """The wheelset's one flange angle (rad) from its wheel profiles: the smaller one's, whose
    Nadal limit is the lower (the dynamics has one flange angle for both wheels)."""
    return min(wheel_flange_angle(w) for w in wheels)


def dynamics_attributes(config: Any, wheels: Any) -> dict[str, float]:
    """What the dynamics reads from a table (:data:`lutmpi.table.schema.DYNAMICS_ATTRIBUTES`),
    SI, from the resolved config and the (worn) wheel profiles it was built with.

    ``wheels`` maps ``"left"`` / ``"right"`` to the wheel profiles. The wheelset model has one
    flange angle and one nominal radius: the flange angle is the smaller of the two wheels'
    (the lower, conservative Nadal limit), the nominal radius their mean (the forward rolling
    speed; each wheel's own radius enters through the table's rolling radius)."""
    radii = [config.wheel.side(name).nominal_radius_m for name in wheels]
    return {"wheel_flange_angle": wheelset_flange_angle(wheels.values()),
            "young_modulus": config.material.young_GPa * 1e9,
            "poisson_ratio": float(config.material.poisson),
            "nominal_radius": float(np.mean(radii)),
            "vertical_load": float(config.equilibrium.vertical_load_N)}
