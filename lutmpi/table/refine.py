"""The refinement between a table's knots (step 2 of :mod:`lutmpi.table.jumps`). Pure: numpy
only.

*Refinement* (:func:`refine_interval`): between neighbouring knots of one piece (grid nodes,
bisection samples, bracket ends) the midpoint is solved; where the table's interpolant
through the knots misses it by more than :data:`REFINE_TOL` (rolling radius, contact angle:
the straight line through the two knots; z_g, roll: the monotone cubic through them and
their neighbours in the piece, :data:`CUBIC_TESTED`), both halves are refined again, down to
:data:`MIN_WIDTH_M`, as long as the miss keeps falling (:data:`REFINE_GAIN`; solver noise
does not fall, so noise is not chased). Every pose solved after the build is kept as an
extra knot of its column: the table is the grid plus what the jumps and the curvature of
the contact needed. A jump no cell showed (changes that cancel within a cell, a step inside
a fast-moving contact) shows in the refinement, which then searches that interval as a cell
(:func:`refine_item`) and keeps the jumps it finds; so does an interval where the halving
stops whose contact still moves by more than :data:`CONFIRM_M` between its ends
(:func:`_narrow`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from lutmpi.table.interp import KINKING
from lutmpi.table.jump_search import (
    CONFIRM_M,
    MAX_PER_CELL,
    TOL_M,
    Item,
    Jump,
    Knot,
    PoseSolver,
    Record,
    classify,
    discrete_key,
    grid_record,
    recording,
    search_bracket,
    state_key,
)
from lutmpi.table.schema import D

log = logging.getLogger(__name__)

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

    A jump the grid-level search did not see shows here in one of three ways: a midpoint whose
    discrete state (status, contact count) differs from an end (two changes that cancel in
    one cell), a miss that does not fall when the interval halves while the contact point
    moves by more than :data:`CONFIRM_M` between the ends (a step hidden in a fast-moving
    contact: on a worn flange the contact ran 1.9 mm per mm of y and jumped 0.85 mm within
    it, a rolling radius step of 1.4 mm that no cell's movement flagged); and an interval too
    narrow to halve whose contact still moves that far (:func:`_narrow`). With ``found`` (a
    list) the interval is then searched as a cell is (:func:`search_bracket`, with the poses it
    solved), the jumps appended to ``found`` (column ``iyaw``) and the pieces between them
    refined on their own; without it such a midpoint is dropped and the interval keeps its two
    knots (the straight line across the change).

    Returns
    -------
    list of (float, dict)
        The solved poses ``(y, record)`` kept as knots, sorted by y.
    """
    if x1 - x0 < 2 * min_width:
        if found is not None and classify(state_key(r0), state_key(r1), CONFIRM_M)[0]:
            return _narrow(x0, r0, x1, r1, yaw, solve, found, iyaw)
        return []
    xm = x0 + 0.5 * (x1 - x0)
    rm = solve(xm, yaw)
    km = discrete_key(rm)
    if km != discrete_key(r0) or km != discrete_key(r1):
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
          and classify(state_key(r0), state_key(r1), CONFIRM_M)[0]):
        # the miss did not fall by halving, and the contact moved: a step, not a curvature
        return _split(x0, r0, x1, r1, (xm, rm), yaw, solve, found, iyaw, min_width, mesh,
                      scale, outer)
    return out


def _narrow(x0: float, r0: Record, x1: float, r1: Record, yaw: float, solve: PoseSolver,
            found: list[Jump], iyaw: int) -> list[tuple[float, Record]]:
    """:func:`refine_interval` at its narrowest where the contact still moves by more than
    :data:`CONFIRM_M` between the two ends: the interval searched as a cell's bracket is
    (:func:`search_bracket`, one or two solves at this width), the jumps appended to
    ``found``. A fold of the rigid roots reaches this: the contact runs up a square-root onset
    (the miss falls by ~0.71 per halving, so the refinement goes on) and jumps at its end; on
    a measured worn flange (the README's asymmetric pair, reference, yaw 0) the rolling radius
    stepped by 2.4 mm between two knots 7.8 um apart, and the table ran a straight line
    across it. Returns the poses solved but those strictly inside a bracket, sorted by y."""
    samples: list[tuple[float, Record]] = []
    sampled = recording(solve, yaw, samples)
    here = search_bracket(x0, r0, x1, r1, sampled, iyaw, TOL_M, CONFIRM_M, CONFIRM_M,
                          MAX_PER_CELL, samples)
    found.extend(sorted(here, key=lambda jp: jp.lo))
    return sorted((p for p in samples if not any(jp.lo < p[0] < jp.hi for jp in here)),
                  key=lambda p: p[0])


def _split(x0: float, r0: Record, x1: float, r1: Record, mid: Knot, yaw: float,
           solve: PoseSolver, found: list[Jump], iyaw: int, min_width: float,
           mesh: MeshResolution | None, scale: float,
           outer: tuple[Knot | None, Knot | None]) -> list[tuple[float, Record]]:
    """:func:`refine_interval` where the interval holds a change its ends do not tell: the
    jumps between ``x0``, the solved midpoint ``mid`` and ``x1`` located by :func:`search_bracket`
    (a cell's steps 2-4, at most :data:`MAX_PER_CELL`, with :data:`CONFIRM_M` as the
    threshold: what a cell searched by its sudden movement takes), appended to ``found``; the
    pieces between them refined as intervals of their own. Returns every pose solved here
    (but those strictly inside a bracket), sorted by y. Where no jump is confirmed (a
    continuous contact that is merely steep) the poses are knots and nothing else changes."""
    samples: list[tuple[float, Record]] = [mid]
    sampled = recording(solve, yaw, samples)
    here: list[Jump] = []
    for (a, ra), (b, rb) in (((x0, r0), mid), (mid, (x1, r1))):
        here += search_bracket(a, ra, b, rb, sampled, iyaw, TOL_M, CONFIRM_M, CONFIRM_M,
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
            ka = discrete_key(piece[k][1])
            same = [n if n is not None and discrete_key(n[1]) == ka else None
                    for n in (before, after)]
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
        :func:`~lutmpi.table.jump_search.refine_cell`'s result, and reflected as it is
        (:meth:`~lutmpi.table.mirror.Mirror.cell_result`).
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
    pts = [(float(y_axis[i]), grid_record(arrays, i, j)) for i in range(y_axis.size)]
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
    piece, disc = knots[k][2], discrete_key(knots[k][1])

    def same(i: int) -> bool:
        return 0 <= i < len(knots) and knots[i][2] == piece and discrete_key(knots[i][1]) == disc

    return (knots[k - 1][:2] if same(k - 1) else None,
            knots[k + 2][:2] if same(k + 2) else None)


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
