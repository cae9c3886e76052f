"""Solving a list of grid points and turning each :class:`PoseResult` into schema-shaped records.

Pure: no MPI, no HDF5. The solver is injected (``solver(scene, y, yaw, method) -> PoseResult``); a
non-converged point is data (its ``status``), an exception is a programming error and propagates
with a note naming the grid point and method.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np

from lutmpi.contact.methods import get_method
from lutmpi.equilibrium.result import SIDES, PoseResult
from lutmpi.pose.mesh import warm_rare_paths
from lutmpi.pose.solve import POINT_QUANTITIES, solve_pose
from lutmpi.table.grid import Grid
from lutmpi.table.schema import FIELDS_BY_NAME, N_SLOTS, D, Field

Solver = Callable[[Any, float, float, str], PoseResult]
Records = dict[str, dict[str, np.ndarray]]   # method -> field name -> array (n_points, *suffix)

#: a dataset is read from the :class:`PoseResult` (per point) or :class:`ContactResult` (per
#: contact) attribute of the same name; these datasets keep older attribute names (dataset -> attr)
ATTRIBUTE_OF = {D.iterations: "nit", D.compute_time: "time", D.indentation_max: "indentation",
                D.kc_contact: "kc", D.curv_wheel_rolling: "wheel_curv_rolling",
                D.curv_wheel_transverse: "wheel_curv_transverse",
                D.curv_rail_transverse: "rail_curv_transverse"}
#: point datasets that are not an attribute of the result (filled from its contacts)
DERIVED = (D.n_contacts,)


def result_attribute(name: str) -> str:
    """The result attribute a dataset is read from (its own name unless in :data:`ATTRIBUTE_OF`)."""
    return ATTRIBUTE_OF.get(name, name)


class PoseSolver:
    """The production solver, :func:`lutmpi.pose.solve.solve_pose`, whose compiled kernels are
    loaded (numba's cache, ~0.3 s) by :meth:`warm` once per method and process, outside any
    pose's time: the first call of a method warms it unless the caller already did (results
    are identical: the solve is pure).

    Attributes
    ----------
    warm_s : float
        Time spent warming so far, s.
    reflection_symmetric : bool
        Its results at reflected poses are the reflected results (a build may fill a pose
        from its image: :meth:`lutmpi.table.jumps.Mirror.grid_plan`;
        ``tests/unit/test_table_mirror.py``). A solver without this attribute true is solved
        at every pose.
    """

    reflection_symmetric = True

    def __init__(self) -> None:
        self._warm: set[str] = set()
        self.warm_s = 0.0

    def warm(self, scene: Any, method: str, y: float = 0.0, yaw: float = 0.0) -> None:
        """Load ``method``'s compiled kernels, its rarely reached paths included (once), by a
        solve at ``(y, yaw)`` (m, rad) whose result is dropped."""
        if method in self._warm:
            return
        t0 = time.perf_counter()
        self._warm.add(method)
        solve_pose(scene, y, yaw, method)
        warm_rare_paths(scene, get_method(method))
        self.warm_s += time.perf_counter() - t0

    def __call__(self, scene: Any, y: float, yaw: float, method: str) -> PoseResult:
        self.warm(scene, method, y, yaw)
        return solve_pose(scene, y, yaw, method)


def default_solver() -> PoseSolver:
    """The production solver (:class:`PoseSolver`)."""
    return PoseSolver()


def empty_records(fields: Sequence[Field], methods: Iterable[str], n: int) -> Records:
    """Fill-valued records for ``n`` points of every method."""
    return {m: {f.name: f.empty((n,)) for f in fields} for m in methods}


@functools.lru_cache(maxsize=16)
def _empty_record(fields: tuple[Field, ...]) -> dict[str, np.ndarray]:
    """A fill-valued one-point record of ``fields``, never written: copied for each pose of the
    jump step (thousands)."""
    return {f.name: f.empty((1,)) for f in fields}


def slot_order(contacts: Iterable[Any]) -> list[Any]:
    """A wheel's contacts in slot order: by decreasing normal force, stable (slot 0 = primary).
    A NaN force (the rigid ``reference`` solve) keeps the solver's order, whose first contact is
    the rigid contact itself. ``lutmpi solve``'s primary contact is slot 0 of this order."""
    return sorted(contacts, key=lambda c: -float(c.force))


@functools.lru_cache(maxsize=64)
def _fill_plan(names: tuple[str, ...]) -> tuple[tuple[tuple[str, str, bool], ...],
                                                tuple[tuple[str, str], ...]]:
    """What :func:`fill_record` reads for the datasets ``names``: per point ``(dataset,
    attribute, optional)`` (optional: a pose solve's quantity, absent from an error record)
    and per contact ``(dataset, attribute)``."""
    point, contact = [], []
    for name in names:
        if FIELDS_BY_NAME[name].per_contact:
            contact.append((name, result_attribute(name)))
        elif name not in DERIVED:
            attr = result_attribute(name)
            point.append((name, attr, attr in POINT_QUANTITIES))
    return tuple(point), tuple(contact)


def fill_record(out: dict[str, np.ndarray], i: int, result: PoseResult) -> None:
    """Write ``result`` into row ``i`` of the per-method arrays ``out`` (only the fields present).

    Contacts of each wheel are ordered by decreasing normal force (stable): slot 0 is the primary
    contact. Slots beyond :data:`N_SLOTS` are dropped but counted in ``n_contacts``.
    """
    point, wanted = _fill_plan(tuple(out))
    for name, attr, optional in point:
        if optional and not hasattr(result, attr):
            continue           # not a pose solve's result (an error record): the fill value
        out[name][i] = getattr(result, attr)
    if D.n_contacts in out:
        out[D.n_contacts][i] = [len(result.contacts.get(s, [])) for s in SIDES]
    if not wanted:
        return
    for iside, side in enumerate(SIDES):
        contacts = slot_order(result.contacts.get(side, []))
        for slot, contact in enumerate(contacts[:N_SLOTS]):
            for name, attr in wanted:
                out[name][i, iside, slot] = getattr(contact, attr)


def pose_to_record(result: PoseResult, fields: Sequence[Field]) -> dict[str, np.ndarray]:
    """The flat per-point record of one pose: field name -> array of the field's suffix shape."""
    out = {name: arr.copy() for name, arr in _empty_record(tuple(fields)).items()}
    fill_record(out, 0, result)
    return {name: arr[0] for name, arr in out.items()}


def compute_points(scene: Any, grid: Grid, points: np.ndarray, methods: Sequence[str],
                   solver: Solver, fields: Sequence[Field],
                   on_point: Callable[[int], None] | None = None, *,
                   out: Records | None = None, first: int = 0) -> tuple[Records, float]:
    """Solve ``points`` (flat grid indices) for every method.

    Parameters
    ----------
    scene : object
        Passed through to ``solver``.
    grid : Grid
    points : ndarray of int, shape (n,)
        Flat indices into ``grid``.
    methods : sequence of str
        Contact methods to solve (only these are computed).
    solver : callable
        ``solver(scene, y, yaw, method) -> PoseResult``.
    fields : sequence of Field
        Fields to record.
    on_point : callable, optional
        Called with the number of points finished so far (progress).
    out : dict, optional
        Arrays to fill in place (``method -> name -> array``, fill-valued, rows ``first`` to
        ``first + n``; e.g. a build's preallocated store,
        :meth:`lutmpi.parallel.writer.TableWriter.claim`); default: new fill-valued records.
    first : int
        The row of ``out`` the first point goes to.

    Returns
    -------
    records : dict
        ``out``, or ``method -> name -> array (n, *suffix)``.
    busy : float
        Wall time spent solving, s.

    Raises
    ------
    Exception
        Whatever the solver raised, with a note naming the grid point and the method.
    """
    records = empty_records(fields, methods, len(points)) if out is None else out
    busy = 0.0
    for i, k in enumerate(points):
        y, yaw = grid.pose(int(k))
        for method in methods:
            t0 = time.perf_counter()
            try:
                result = solver(scene, y, yaw, method)
            except Exception as exc:
                exc.add_note(f"lutmpi: raised while solving {grid.describe(int(k))}, "
                             f"method {method!r}")
                raise
            busy += time.perf_counter() - t0
            fill_record(records[method], first + i, result)
        if on_point is not None:
            on_point(i + 1)
    return records, busy
