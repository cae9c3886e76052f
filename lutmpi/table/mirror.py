"""The reflections of a table's grid (step 3 of :mod:`lutmpi.table.jumps`). Pure: numpy only.

*Mirror* (:class:`Mirror`): a wheel is a body of revolution and a rail an extrusion along
x, so the pose (y, -yaw) is the pose (y, yaw) reflected in the track's y-z plane, for any
pair; on a symmetric pair (both wheels one profile on one rail profile) the pose (-y, -yaw)
is the pose (y, yaw) with the wheels swapped, and (-y, yaw) both
(:meth:`lutmpi.table.schema.Field.reflected`). On a grid symmetric about zero in yaw (and
in y), a cell or an interval that is the image of another searched or refined takes that
one's poses reflected instead of solving its own: half the solves (a quarter on a symmetric
pair), the same table to rounding.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from lutmpi.table.jump_search import Item, Jump, Record
from lutmpi.table.schema import FIELDS_BY_NAME, TIMING_FIELDS


class ColumnRecord(dict):
    """A pose record that is row ``row`` of the stacked ``columns`` (name -> array, one row a
    record), as the jump step's results reach every rank (:func:`lutmpi.parallel.jumps_step.
    _share`, on one rank too). A plain dict of those rows to every reader, and read-only (its
    values are views of shared columns, and its reflection reads the columns);
    :meth:`Reflection.record` reflects it by reflecting its columns once for all their rows
    (:meth:`~lutmpi.table.schema.Field.reflected_column`) instead of one record at a time: a
    mirrored jump step takes ~3 records reflected per record solved (docs/TABLES.md,
    § Reflections), on every rank. Made by :meth:`at`."""

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
        """:func:`~lutmpi.table.jump_search.refine_cell`'s result for the image of its cell."""
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
        """:func:`mirror_pairs` of refinement intervals
        (:func:`~lutmpi.table.refine.refinement_plan`): an image has the reflected ends and
        outer knots (swapped where y changes sign) in the image's column."""
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
