"""The search for a table's contact jumps (step 1 of :mod:`lutmpi.table.jumps`). Pure:
numpy only.

Per yaw column and per grid cell ``[y_i, y_i+1]``:

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
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from lutmpi.table.schema import D

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

Record = dict[str, np.ndarray]
PoseSolver = Callable[[float, float], Record]
Knot = tuple[float, Record]
#: one refinement interval: ``(iyaw, (x0, r0), (x1, r1), outer)`` (the ends and outer knots
#: of :func:`~lutmpi.table.refine.refine_interval`)
Item = tuple[int, Knot, Knot, tuple[Knot | None, Knot | None]]


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


def discrete_key(rec: Record) -> tuple[int, ...]:
    """Discrete key of a record: status, contacts per wheel."""
    disc = (int(rec[D.status]),)
    if D.n_contacts in rec:
        disc += tuple(np.asarray(rec[D.n_contacts], dtype=np.int64).ravel().tolist())
    return disc


def state_key(rec: Record) -> tuple[tuple[int, ...], np.ndarray]:
    """Discrete key (:func:`discrete_key`) and the primary contact coordinates per wheel (wheel s,
    rail v; shape (2, 2), m) of a record."""
    disc = discrete_key(rec)
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
        keys = [state_key(grid_record(arrays, i, j)) for i in range(ny)]
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


def grid_record(arrays: dict[str, np.ndarray], i: int, j: int) -> Record:
    return {name: np.asarray(arr[i, j]) for name, arr in arrays.items()}


def recording(solve: PoseSolver, yaw: float, samples: list[tuple[float, Record]]
              ) -> Callable[[float], Record]:
    """``solve`` at this yaw as a function of y that appends each pose it solves to
    ``samples`` as ``(y, record)`` (the searches' record of the poses they solved)."""
    def sampled(y: float) -> Record:
        rec = solve(y, yaw)
        samples.append((y, rec))
        return rec

    return sampled


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
    sampled = recording(solve, yaw, samples)
    rlo, rhi = grid_record(arrays, i, j), grid_record(arrays, i + 1, j)
    if not classify(state_key(rlo), state_key(rhi), threshold)[0]:
        threshold = confirm       # a candidate by its sudden movement (:func:`_sudden`)
    found = search_bracket(lo, rlo, hi, rhi, sampled, j, tol, threshold, confirm,
                           MAX_PER_CELL, samples)
    return found, samples


def search_bracket(lo: float, rlo: Record, hi: float, rhi: Record,
                   solve: Callable[[float], Record], j: int, tol: float, threshold: float,
                   confirm: float, budget: int, known: Sequence[tuple[float, Record]]
                   ) -> list[Jump]:
    """The jumps between ``lo`` and ``hi`` (:func:`refine_cell`'s steps 2-4). ``known``: the
    poses the cell's search has solved so far (``(y, record)``: the list that ``solve``
    appends each of its solves to, :func:`refine_cell`'s ``samples``, so that the later
    searches see the earlier ones' poses); while one lies inside the bracket, the bisection
    takes the one nearest its middle instead of solving the middle (the same rule, at a point
    already solved), so that the second and third jump of a cluster (a second contact
    appearing, the contact moving over, the first contact going, within micrometres) are not
    bisected again from the whole sub-interval."""
    klo, khi = state_key(rlo), state_key(rhi)
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
        km = state_key(rm)
        if _distance(km, ka) <= _distance(km, kb):
            a, ra, ka = m, rm, km
        else:
            b, rb, kb = m, rm, km
    kind, side = classify(ka, kb, confirm)
    if not kind:
        return []
    found = Jump(j, a, b, ra, rb, kind, side)
    left = search_bracket(lo, rlo, a, ra, solve, j, tol, threshold, confirm, budget - 1, known)
    right = search_bracket(b, rb, hi, rhi, solve, j, tol, threshold, confirm,
                           budget - 1 - len(left), known)
    return left + [found] + right


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
        lo, hi = grid_record(arrays, i, j), grid_record(arrays, i + 1, j)
        threshold = (CANDIDATE_M if classify(state_key(lo), state_key(hi), CANDIDATE_M)[0]
                     else CONFIRM_M)
        col = sorted(jps, key=lambda jp: jp.lo)
        ends = [lo] + [r for jp in col for r in (jp.rec_lo, jp.rec_hi)] + [hi]
        if any(classify(state_key(ends[k]), state_key(ends[k + 1]), threshold)[0]
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

