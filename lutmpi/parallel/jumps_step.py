"""The post-build step of a table: locate its contact jumps and store them, with the
attributes the dynamics reads (issues 11 and 15).

Runs on every rank once the grid is complete and written (one call from
:func:`lutmpi.parallel.runner.build_table`). Each rank holds its row block; the blocks are shared
(the table is small next to the solves), every rank lists the same candidate cells and takes
them one at a time from a shared counter (:mod:`lutmpi.parallel.workqueue`, as the grid's points;
a static split with ``--split``), refines each with direct solves
(:func:`lutmpi.table.jump_search.refine_cell`, pure), and the found jumps are gathered in cell
order; the refinement intervals that follow are handed out alike. The result is the same for
any number of ranks and any hand-out.
"""

from __future__ import annotations

import dataclasses
import json
import logging
import time
from typing import Any

import numpy as np

from lutmpi.parallel import partition
from lutmpi.parallel.workqueue import make_counter
from lutmpi.table import h5io
from lutmpi.table import interp as _interp
from lutmpi.table import jump_search as _js
from lutmpi.table import jumps as _jumps
from lutmpi.table import mirror as _mirror
from lutmpi.table import refine as _refine
from lutmpi.table.compute import pose_to_record
from lutmpi.table.schema import limit_fields

log = logging.getLogger(__name__)


def _all_rows(comm: Any, row_start: int, blocks: dict[str, dict[str, np.ndarray]]
              ) -> dict[str, dict[str, np.ndarray]]:
    """Every rank's row blocks joined into the full arrays, on every rank."""
    parts = comm.bcast(comm.gather((row_start, blocks), root=0), root=0)
    parts = sorted(parts, key=lambda p: p[0])
    return {m: {k: np.concatenate([p[1][m][k] for p in parts], axis=0) for k in blocks[m]}
            for m in blocks}


def add_jumps(comm: Any, grid: Any, config: Any, scene: Any, solver: Any,
              methods: tuple[str, ...], fields: Any, f: Any, io: Any, row_start: int,
              blocks: dict[str, dict[str, np.ndarray]], split: str = "dynamic",
              mirror: tuple[_mirror.Mirror | None, str] | None = None) -> None:
    """Locate, refine and write the jumps of every method (unless ``output.jumps`` is false),
    and the dynamics attributes.

    Parameters
    ----------
    comm : communicator (or :class:`lutmpi.parallel.runner.SelfComm`)
    grid, config, scene, solver, methods, fields
        As in the build.
    f : h5py.File
        The open partial file (collective with several ranks).
    io : lutmpi.table.h5io.SerialH5
        The writer's HDF5 strategy.
    row_start, blocks
        This rank's complete row block (method -> name -> array).
    mirror : (Mirror or None, str), optional
        :func:`mirror_of` as the build's grid used it (computed here when not given).
    split : str
        How cells and intervals are handed out: ``"dynamic"`` (a shared counter) or a static
        split of :mod:`lutmpi.parallel.partition`; the build's ``--split``.
    """
    from lutmpi.scene_config import side_profiles
    from lutmpi.table.api import mask_failed

    t0 = time.perf_counter()
    full = _all_rows(comm, row_start, blocks)
    lfields = limit_fields(fields)
    spent = [0.0, 0]   # this rank's pose solves: seconds, count (the grid's "busy" alike)
    if not config.output.jumps and comm.rank == 0:
        log.info("jump step left out (output.jumps = false): the table holds its grid's points "
                 "only, and lutmpi's lookups on it interpolate across contact jumps")
    mirror, why = mirror or mirror_of(config, scene, solver, grid.y, grid.yaw)
    for method in methods if config.output.jumps else ():
        t_method = time.perf_counter()
        arrays = full[method]

        def solve(y: float, yaw: float, method: str = method) -> dict[str, np.ndarray]:
            t = time.perf_counter()
            rec = pose_to_record(solver(scene, y, yaw, method), lfields)
            spent[0] += time.perf_counter() - t
            spent[1] += 1
            return rec

        mesh = mesh_resolution(scene, method)
        # the grid nodes as the search sees them: the fields a solved record holds (not timing)
        limits = {f.name: arrays[f.name] for f in lfields}
        js, counts = _locate(comm, grid, limits, solve, lfields, config.output.refine,
                                      mesh, split, config.output.refine_scale, mirror)
        modes = _interp.choose_modes(grid.y, mask_failed(arrays), js.arrays,
                                     mask_failed(js.limits), js.knot_y, mask_failed(js.knots))
        h5io.write_jumps(f, io, comm.rank, method, js.arrays, js.limits, js.knot_y, js.knots, {
            "interpolants": json.dumps(modes), "candidate_m": _js.CANDIDATE_M,
            "confirm_m": _js.CONFIRM_M, "candidate_rate_ratio": _js.RATE_RATIO,
            "tol_m": _js.TOL_M,
            "refine_tol": json.dumps(_refine.REFINE_TOL), "min_width_m": _refine.MIN_WIDTH_M,
            "refine_mesh_spacing_m": json.dumps(None if mesh is None else mesh.spacing.tolist()),
            "refine_mesh_centroid": bool(mesh is not None and mesh.centroid),
            "refine_mesh_step_fraction": _refine.MESH_STEP_FRACTION,
            "refine_scale": float(config.output.refine_scale),
            "mirrored": mirror is not None,
            "max_per_cell": _js.MAX_PER_CELL,
            "cells_searched_in_part": len(counts["in_part"]),
            # the same value on every rank (collective metadata): rank 0's
            "wall_time_s": comm.bcast(time.perf_counter() - t_method, root=0)})
        if comm.rank == 0:
            log.info("%s: %d candidate cells, %d jumps located (per yaw: max %d; %d of them "
                     "by the refinement between the cells' jumps), %d extra knots; "
                     "interpolants %s", method, counts["cells"], int(js.count.sum()),
                     int(js.count.max(initial=0)), counts["in_refinement"],
                     int(np.isfinite(js.knot_y).sum()),
                     {k: v for k, v in modes.items() if v != "linear"} or "all linear")
            _js.warn_in_part(counts["in_part"], grid.yaw, method)
            if mirror is not None:
                log.info("%s: mirrored (%s): %d of %d candidate cells and %d of %d refined "
                         "intervals taken from their images, not solved", method, why,
                         counts["cells_mirrored"], counts["cells"], counts["intervals_mirrored"],
                         counts["intervals"])
            else:
                log.info("%s: not mirrored: %s", method, why)
    wheels, _ = side_profiles(config)
    h5io.write_root_attributes(f, _jumps.dynamics_attributes(config, wheels))
    _log_work(comm, time.perf_counter() - t0, spent)


def _log_work(comm: Any, wall: float, spent: list) -> None:
    """The jump step's figures in the build log (rank 0), named as the grid's are: its wall
    time, each rank's summed pose-solve time ("busy") and count, and summed busy / wall, which
    is the speed-up over one rank only where a solve costs the same on N ranks (issue 14)."""
    busy = comm.gather((spent[0], spent[1]), root=0)
    wall = comm.bcast(wall, root=0)
    if comm.rank == 0:
        total = sum(b for b, _ in busy)
        log.info("jump step: wall %.2f s on %d rank(s); %d pose solves; busy per rank %s s; "
                 "summed busy / wall %.2f; busy fraction %.1f %%", wall, comm.size,
                 sum(n for _, n in busy), [round(b, 2) for b, _ in busy],
                 total / wall if wall > 0 else 0.0,
                 100 * total / (comm.size * wall) if wall > 0 else 0.0)


def mirror_of(config: Any, scene: Any, solver: Any, y_axis: np.ndarray, yaw_axis: np.ndarray
              ) -> tuple[_mirror.Mirror | None, str]:
    """The grid's :class:`~lutmpi.table.mirror.Mirror` when a build may fill poses by
    reflection (its grid and its jump step), else None; and the reflections or why none, in
    words for the build log. It may with ``output.mirror``, a solver whose results are
    symmetric (``reflection_symmetric``: lutmpi's own, and a sweep's wrapper of it) and a grid
    symmetric about yaw = 0, or about y = 0 on a scene whose two sides are one wheel profile
    on one rail profile."""
    from lutmpi.scene import Scene

    if not config.output.mirror:
        return None, "output.mirror = false"
    if not getattr(solver, "reflection_symmetric", False) or not isinstance(scene, Scene):
        return None, "a solver hook solves the poses (its symmetry is unknown)"
    mirror = _mirror.Mirror.of(y_axis, yaw_axis, scene.symmetric)
    pair = ("a symmetric pair" if scene.symmetric else
            "the two sides' wheel or rail profiles (or their placing) differ")
    if mirror is None:
        return None, (f"the grid is not symmetric about yaw = 0 or y = 0 (within "
                      f"{_mirror.MIRROR_AXIS_TOL:g}; {pair})")
    return mirror, f"{mirror.describe()}; {pair}"


def mesh_resolution(scene: Any, method: str) -> _refine.MeshResolution | None:
    """The mesh that bounds the refinement of a mesh method's table
    (:func:`lutmpi.table.refine.tolerances`): per wheel (left, right) the lateral node spacing of
    the wheel and the rail mesh; None for a method without a mesh, or when the solve is not
    lutmpi's own on a :class:`~lutmpi.scene.Scene` (a solver hook: its mesh is unknown)."""
    from lutmpi.contact.methods import get_method
    from lutmpi.equilibrium.result import SIDES
    from lutmpi.scene import Scene

    m = get_method(method)
    if not m.uses_mesh or not isinstance(scene, Scene):
        return None
    return _refine.MeshResolution(
        np.array([[scene.side(n).wheel_mesh.h_lat, scene.side(n).rail_mesh.h_lat]
                  for n in SIDES]), m.centroid)


def _share(comm: Any, items: list[Any], work: Any, split: str = "dynamic") -> list[Any]:
    """``work(item)`` for ``items`` shared among the ranks; every rank gets all results in item
    order (the pose records in them travel as columns: :func:`_pack`).

    ``"dynamic"``: a rank takes the next item whenever it is free (a shared counter). An item
    costs from one solve to ~50 (a cell's bisections, an interval's refinement), so a static
    share leaves ranks idle: on the Manchester table's jump step (37 x 37), counted in solves,
    a cyclic share keeps 16 ranks 92 % busy and the counter 99 % (BENCHMARKS.md). A static
    ``split`` of :mod:`lutmpi.parallel.partition` otherwise."""
    if split == "dynamic":
        counter = make_counter(comm)
        done = []
        while (k := counter.next()) < len(items):
            done.append((k, work(items[k])))
        counter.free()  # collective: not on an error, which ends the job (the CLI aborts)
    else:
        done = [(int(k), work(items[k]))
                for k in partition.split(len(items), comm.size, comm.rank, split)]
    # packed on one rank too: the records become columns (ColumnRecord) that the mirrored
    # items reflect at once, and every rank count reads the same kind of record
    parts = comm.bcast(comm.gather(_pack(done), root=0), root=0)
    done = [it for part in parts for it in _unpack(*part)]
    return [r for _, r in sorted(done, key=lambda it: it[0])]


class _Ref(int):
    """A pose record's row in the columns of :func:`_pack`."""


def _map_records(obj: Any, fn: Any) -> Any:
    """``obj`` (lists, tuples, :class:`~lutmpi.table.jump_search.Jump`, pose records) with every
    pose record (a dict; a :class:`_Ref` when unpacking) replaced by ``fn(record)``."""
    if isinstance(obj, dict | _Ref):
        return fn(obj)
    if isinstance(obj, _js.Jump):
        return dataclasses.replace(obj, rec_lo=fn(obj.rec_lo), rec_hi=fn(obj.rec_hi))
    if isinstance(obj, list | tuple):
        return type(obj)(_map_records(x, fn) for x in obj)
    return obj


def _pack(obj: Any) -> tuple[Any, dict[str, np.ndarray]]:
    """``obj`` as a skeleton whose pose records are :class:`_Ref` rows, and the records stacked
    per name. Sent between ranks, thousands of records pickled one by one cost seconds; their
    columns do not. Only the names every record has are sent: the search's grid-node records
    (bracket ends the bisection kept) and its solved ones both hold the limit fields
    (:func:`add_jumps`), and the rule keeps any other mix of records sendable too."""
    recs: list[dict[str, np.ndarray]] = []

    def ref(rec: dict[str, np.ndarray]) -> _Ref:
        recs.append(rec)
        return _Ref(len(recs) - 1)

    skeleton = _map_records(obj, ref)
    names = [n for n in recs[0] if all(n in r for r in recs)] if recs else []
    return skeleton, {n: np.stack([np.asarray(r[n]) for r in recs]) for n in names}


def _unpack(skeleton: Any, columns: dict[str, np.ndarray]) -> Any:
    """The object :func:`_pack` packed (each record's arrays are rows of the columns: a
    :class:`~lutmpi.table.mirror.ColumnRecord`, which reflects in columns)."""
    images: dict[tuple[bool, bool], Any] = {}
    return _map_records(skeleton, lambda row: _mirror.ColumnRecord.at(columns, row, images))


def _locate(comm: Any, grid: Any, arrays: dict[str, np.ndarray], solve: Any, fields: Any,
            refine: bool, mesh: _refine.MeshResolution | None, split: str = "dynamic",
            scale: float = 1.0, mirror: _mirror.Mirror | None = None
            ) -> tuple[_jumps.JumpSet, dict[str, int]]:
    """Jumps (bisection over the candidate cells), then (``refine``) refinement of every piece
    interval with the factor ``scale`` on its tolerances, both shared among the ranks;
    ``mirror``: a cell or an interval that is the image of another takes its poses reflected,
    not solved (:func:`lutmpi.table.mirror.mirrored_map`). Returns the jumps and the counts of
    candidate cells and refined intervals, and of those taken from their images, and the cells
    searched in part (:func:`lutmpi.table.jump_search.searched_in_part`)."""
    t0 = time.perf_counter()
    cells = _js.candidate_cells(arrays)
    cell_pairs = mirror.cells(cells) if mirror else {}
    res = _mirror.mirrored_map(cells, lambda todo: _share(comm, todo, lambda c: _js.refine_cell(
        arrays, grid.y, grid.yaw, c, solve), split), cell_pairs,
        mirror.cell_result if mirror else None)
    t1 = time.perf_counter()
    found, extra = _js.found_and_samples(cells, res)
    in_part = _js.searched_in_part(arrays, grid.y, cells, res)
    items = (_refine.refinement_plan(arrays, grid.y, grid.yaw.size, found, extra) if refine
             else [])
    item_pairs = mirror.items(items) if mirror else {}
    refined = _mirror.mirrored_map(items, lambda todo: _share(comm, todo, lambda it: (
        _refine.refine_item(it[0], it[1][0], it[1][1], it[2][0], it[2][1],
                           float(grid.yaw[it[0]]), solve, mesh=mesh, scale=scale, outer=it[3])),
        split), item_pairs, mirror.cell_result if mirror else None)
    log.debug("jump search: %d cells, %.2f s; refinement: %d intervals, %.2f s", len(cells),
              t1 - t0, len(items), time.perf_counter() - t1)
    between = [jp for jps, _ in refined for jp in jps]
    found += between
    extra += [(it[0], y, r) for it, (_, rs) in zip(items, refined, strict=True) for y, r in rs]
    counts = {"cells": len(cells), "cells_mirrored": len(cell_pairs), "intervals": len(items),
              "intervals_mirrored": len(item_pairs), "in_part": in_part,
              "in_refinement": len(between)}
    return _jumps.assemble(found, extra, grid.yaw.size, fields), counts
