"""Contact jumps of a table, located and stored as data (issue 11). Pure: numpy only.

Along y, at fixed yaw, the contact of a wheel can jump: the contact point leaves the tread for the
flange (the rigid contact is the lowest of several gap minima, and the lowest changes), a second
contact appears or disappears, or the solve stops converging. Every continuous interpolant errs by
about half the jump next to it, whatever the step, so the jumps are located and interpolation never
crosses them (:mod:`lutmpi.table.interp`).


Per yaw column, in four modules:

1. *Search* (:mod:`lutmpi.table.jump_search`): grid cells whose ends differ in status or
   contact count, or whose contact point moves far or suddenly, are bisected with direct pose
   solves down to a bracket of :data:`~lutmpi.table.jump_search.TOL_M`; a bracket whose ends
   still differ is a jump, its two end records the one-sided limits of every stored quantity.
2. *Refinement* (:mod:`lutmpi.table.refine`): between neighbouring knots of one piece the
   midpoint is solved where the table's interpolant misses it, recursively; every pose solved
   is kept as an extra knot, and a jump no cell showed is searched there and kept.
3. *Mirror* (:mod:`lutmpi.table.mirror`): a cell or an interval that is the image of another
   under a reflection of the track takes that one's poses reflected instead of solving its own.
4. *Assembly* (here): the jumps and extra knots as the arrays of ``/<method>/jumps``
   (:class:`JumpSet`), and :func:`locate_jumps`, the whole step serially (the build runs it in
   parallel: :mod:`lutmpi.parallel.jumps_step`).

Everything depends only on the table and the solver, never on who solved what, so the result
is the same for any number of ranks (:func:`~lutmpi.table.jump_search.refine_cell` and
:func:`~lutmpi.table.refine.refine_item` take any subset of cells and intervals).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from lutmpi.table.jump_search import (
    CANDIDATE_M,
    Jump,
    PoseSolver,
    Record,
    candidate_cells,
    found_and_samples,
    refine_cell,
    searched_in_part,
    warn_in_part,
)
from lutmpi.table.mirror import Mirror, mirrored_map
from lutmpi.table.refine import MeshResolution, refine_item, refinement_plan
from lutmpi.table.schema import JUMP_FIELDS, Field, J


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
    build runs in parallel: :func:`candidate_cells`, :func:`refine_cell`,
    :func:`~lutmpi.table.refine.column_knots`, :func:`~lutmpi.table.refine.refine_interval`
    with the factor ``scale`` on its tolerances, :func:`assemble`;
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
