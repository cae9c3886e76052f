"""``build_table``: the only orchestration of a table build (serial or MPI).

Flow (every rank runs it; ``comm=None`` means one process):

1. Pure set-up on every rank (grid, methods, fields: a bad config fails everywhere alike).
2. Rank 0 decides alone (output checks, metadata, the scene) and broadcasts the value *or the
   exception*; every rank then raises the same error, nobody waits in a barrier.
3. The partial file ``<out>.partial`` is created (or, with ``resume``, read back) collectively.
4. The points still to do are handed out one at a time from a counter every rank advances
   atomically (``workqueue``; static splits on request) and solved with no communication
   at all; each rank checkpoints its own points into the partial file (independent raw-data
   writes) every ``checkpoint_interval_s``. At the end the results travel to the rank owning their
   rows (one ``alltoall``) and every rank writes its row block collectively.
5. ``complete`` is set last, rank 0 renames the partial file to the output path.

Any exception after step 2 on any rank is logged with the rank (and the grid point when a solve
raised) and ends the whole job with ``comm.Abort(1)``: no rank is left in a collective call.
The table never depends on the number of ranks: every point is solved by the same pure code, and
where it was solved does not enter the file.
"""

from __future__ import annotations

import json
import logging
import os
import subprocess
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from lutmpi import __version__
from lutmpi.config.model import ALL_METHODS, Config
from lutmpi.equilibrium.result import STATUS
from lutmpi.errors import ConfigError
from lutmpi.parallel import partition
from lutmpi.parallel.jumps_step import add_jumps
from lutmpi.parallel.workqueue import make_counter
from lutmpi.table import h5io
from lutmpi.table.compute import Records, Solver, compute_points, default_solver
from lutmpi.table.grid import Grid
from lutmpi.table.schema import SCHEMA_VERSION, select_fields

log = logging.getLogger(__name__)

#: a rank looks at the clock (checkpoint, progress) this many times over its points, at most
N_STEPS = 200
PROGRESS_EVERY_S = 10.0


class SelfComm:
    """The communicator of a single process (no MPI): the collectives are identities."""

    rank = 0
    size = 1

    def bcast(self, obj: Any, root: int = 0) -> Any:
        return obj

    def allreduce(self, obj: Any, op: Any = None) -> Any:
        return obj

    def gather(self, obj: Any, root: int = 0) -> list[Any]:
        return [obj]

    def alltoall(self, objs: list[Any]) -> list[Any]:
        return list(objs)

    def Barrier(self) -> None:  # noqa: N802 - mpi4py's name
        pass


@dataclass
class BuildSummary:
    """What a build did (the same object on every rank)."""

    output: Path
    points: int
    computed: int
    reused: int
    status_counts: dict[str, int]
    wall_time_s: float
    busy_s: list[float] = field(default_factory=list)
    ranks: int = 1

    @property
    def parallel_efficiency(self) -> float:
        """Sum of busy time over ``ranks * wall time``."""
        return sum(self.busy_s) / (self.ranks * self.wall_time_s) if self.wall_time_s > 0 else 0.0

    @property
    def imbalance(self) -> float:
        """Max busy time / mean busy time (1 = perfect)."""
        mean = sum(self.busy_s) / len(self.busy_s) if self.busy_s else 0.0
        return max(self.busy_s) / mean if mean > 0 else 1.0


def resolve_methods(config: Config, methods: Sequence[str] | None) -> tuple[str, ...]:
    """The methods to build: ``methods`` (CLI ``--method``) if given, else ``output.methods``."""
    chosen = tuple(dict.fromkeys(methods or config.output.methods))
    unknown = [m for m in chosen if m not in ALL_METHODS]
    if not chosen or unknown:
        raise ConfigError(f"unknown or no contact method(s) {unknown or list(chosen)}; valid: "
                          f"{', '.join(ALL_METHODS)}", key="output.methods")
    return chosen


def git_commit() -> str:
    """The commit of the source tree lutmpi runs from, or ``""`` when unknown."""
    root = Path(__file__).resolve().parents[2]
    try:
        out = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True,
                             text=True, timeout=5, check=False)
    except (OSError, subprocess.SubprocessError):
        return ""
    return out.stdout.strip() if out.returncode == 0 else ""


def _root_decides(comm: Any, fn: Callable[[], Any]) -> Any:
    """Run ``fn`` on rank 0 and broadcast its value or its exception; every rank returns/raises."""
    value, error = None, None
    if comm.rank == 0:
        try:
            value = fn()
        except Exception as exc:  # broadcast, then every rank raises the same
            error = exc
    value, error = comm.bcast((value, error), root=0)
    if error is not None:
        raise error
    return value


def _make_scene(config: Config) -> Any:
    from lutmpi.scene import Scene

    return Scene.from_config(config)


def build_table(config: Config, output_path: str | os.PathLike[str], comm: Any = None, *,
                solver: Solver | None = None, force: bool = False, resume: bool = False,
                methods: Sequence[str] | None = None,
                scene_factory: Callable[[Config], Any] | None = None,
                checkpoint_interval_s: float = 60.0, split: str = "dynamic") -> BuildSummary:
    """Build the lookup table of ``config`` into ``output_path``.

    Parameters
    ----------
    config : Config
        Resolved configuration; ``[grid]`` and ``[output]`` define the table.
    output_path : path
        The final table; it appears only once complete.
    comm : mpi4py communicator, optional
        ``None`` for one process. Only the CLI passes ``MPI.COMM_WORLD``.
    solver : callable, optional
        ``solver(scene, y, yaw, method) -> PoseResult``; default
        :func:`lutmpi.contact.solve.solve_pose`.
    force : bool
        Overwrite an existing table, discard an unfinished build.
    resume : bool
        Continue from ``<out>.partial`` when present (same config), computing only missing points.
    methods : sequence of str, optional
        Override ``output.methods``.
    scene_factory : callable, optional
        ``scene_factory(config) -> scene``; default :meth:`lutmpi.scene.Scene.from_config`.
    checkpoint_interval_s : float
        Minimum time between two checkpoints of a rank's points into the partial file.
    split : {"dynamic", "scattered", "cyclic", "block"}
        How the remaining points are dealt to ranks: handed out one at a time from a shared
        counter (default; see :mod:`lutmpi.parallel.workqueue`) or a static split.

    Returns
    -------
    BuildSummary

    Raises
    ------
    TableError, ConfigError, GeometryError
        Problems found before compute, raised on every rank alike.
    """
    comm = SelfComm() if comm is None else comm
    t_start = time.perf_counter()
    out = Path(output_path)
    grid = Grid.from_config(config.grid)
    chosen = resolve_methods(config, methods)
    fields = select_fields(config.output.quantities)
    solver = solver or default_solver()
    factory = scene_factory or _make_scene

    def prepare() -> dict[str, Any]:
        need = h5io.estimate_bytes(grid.n_points, len(chosen))
        resuming = h5io.preflight(out, force=force, resume=resume, need_bytes=need)
        toml = config.text
        done = (h5io.check_partial(h5io.partial_path(out), chosen, fields, toml) if resuming
                else None)
        return {"done": done, "config_toml": toml,
                "created_utc": datetime.now(UTC).isoformat(timespec="seconds"),
                "git_commit": git_commit(), "scene": factory(config)}

    plan = _root_decides(comm, prepare)
    log.debug("prepared in %.3f s", time.perf_counter() - t_start)
    try:
        return _run(comm, config, out, grid, chosen, fields, solver, plan, t_start,
                    checkpoint_interval_s, split)
    except BaseException as exc:
        if comm.size > 1:
            _abort(comm, exc)
        raise


def _abort(comm: Any, exc: BaseException) -> None:
    notes = "; ".join(getattr(exc, "__notes__", []))
    log.critical("rank %d/%d failed: %s: %s%s -- aborting the job", comm.rank, comm.size,
                 type(exc).__name__, exc, f" ({notes})" if notes else "", exc_info=exc)
    for handler in logging.getLogger().handlers:
        handler.flush()
    comm.Abort(1)


@dataclass
class _State:
    """This rank's owned rows (write split) and the records waiting to be sent to their owners."""

    row_start: int
    row_count: int
    blocks: dict[str, dict[str, np.ndarray]]
    done_rows: np.ndarray
    pending: list[tuple[np.ndarray, Records]] = field(default_factory=list)


def _run(comm: Any, config: Config, out: Path, grid: Grid, methods: tuple[str, ...],
         fields: Sequence[Any], solver: Solver, plan: dict[str, Any], t_start: float,
         interval: float, split: str) -> BuildSummary:
    partial = h5io.partial_path(out)
    row_start, row_count = partition.block_range(grid.shape[0], comm.size, comm.rank)
    if plan["done"] is not None:
        done = plan["done"]
        blocks = h5io.read_rows(partial, row_start, row_count, methods, fields)
        comm.Barrier()  # every read handle closed before the file is opened for writing
        log.info("resuming %s: %d of %d points already done", partial, int(done.sum()),
                 grid.n_points)
    else:
        attrs = {"config_toml": plan["config_toml"], "lutmpi_version": __version__,
                 "git_commit": plan["git_commit"], "created_utc": plan["created_utc"],
                 "schema_version": SCHEMA_VERSION, "methods": json.dumps(list(methods)),
                 "quantities": json.dumps([f.name for f in fields])}
        h5io.create_partial(partial, comm, grid, methods, fields, attrs)
        done = np.zeros(grid.shape, dtype=bool)
        blocks = {m: {f.name: f.empty((row_count, grid.shape[1])) for f in fields}
                  for m in methods}
    log.debug("partial file ready at %.3f s", time.perf_counter() - t_start)
    state = _State(row_start, row_count, blocks,
                   done[row_start:row_start + row_count].astype(np.uint8))
    todo = np.flatnonzero(~done.ravel())
    f = h5io.open_rw(partial, comm)
    busy = _compute_all(comm, f, grid, plan["scene"], methods, fields, solver, state,
                        _batches(comm, todo, split), len(todo), interval)
    _exchange(comm, grid, state)
    h5io.write_blocks(f, comm, state.row_start, state.blocks, state.done_rows)
    add_jumps(comm, f, grid, config, plan["scene"], solver, methods, fields, state.row_start,
              state.blocks)   # issue 11: post-build step, jumps + dynamics attributes
    log.debug("computed and written at %.3f s", time.perf_counter() - t_start)
    wall = comm.bcast(time.perf_counter() - t_start, root=0)
    busy_all = np.asarray(comm.bcast(comm.gather(busy, root=0), root=0), dtype=float)
    h5io.finalize(f, {"ranks": comm.size, "wall_time_s": wall, "created_utc": plan["created_utc"],
                      "rank_busy_s": busy_all})
    comm.Barrier()
    _root_decides(comm, lambda: os.replace(partial, out))
    return _summarize(comm, out, grid, state, busy_all, len(todo), wall)


def _batches(comm: Any, todo: np.ndarray, how: str) -> Iterator[tuple[np.ndarray, int]]:
    """This rank's points, in batches, each with an estimate of the global count handed out.

    ``"dynamic"``: one point at a time from a counter shared by all ranks (no rank waits for
    another); the static splits of :mod:`lutmpi.parallel.partition` otherwise.
    """
    if how == "dynamic":
        counter = make_counter(comm)
        try:
            while (k := counter.next()) < len(todo):
                yield todo[k:k + 1], k + 1
        finally:
            counter.free()
        return
    mine = todo[partition.split(len(todo), comm.size, comm.rank, how)]
    step = max(1, len(mine) // N_STEPS)
    for start in range(0, len(mine), step):
        yield mine[start:start + step], min((start + step) * comm.size, len(todo))


def _compute_all(comm: Any, f: Any, grid: Grid, scene: Any, methods: tuple[str, ...],
                 fields: Any, solver: Solver, state: _State,
                 batches: Iterator[tuple[np.ndarray, int]], n_todo: int,
                 interval: float) -> float:
    """Solve this rank's points without waiting for any other rank; checkpoint them into the
    partial file independently every ``interval`` seconds. Rank 0 logs the estimated global
    progress."""
    busy = 0.0
    t0 = last_flush = last_log = time.perf_counter()
    unflushed: list[tuple[np.ndarray, Records]] = []
    for points, handed_out in batches:
        records, spent = compute_points(scene, grid, points, methods, solver, fields)
        busy += spent
        state.pending.append((points, records))
        unflushed.append((points, records))
        now = time.perf_counter()
        if now - last_flush >= interval:
            for pts, recs in unflushed:
                h5io.write_points(f, grid, pts, recs)
            unflushed.clear()
            last_flush = now
        if comm.rank == 0 and now - last_log >= PROGRESS_EVERY_S:
            _log_progress(handed_out, n_todo, now - t0, "~")
            last_log = now
    return busy


def _log_progress(done: int, total: int, elapsed: float, approx: str = "") -> None:
    rate = done / elapsed if elapsed > 0 else 0.0
    eta = (total - done) / rate if rate > 0 else float("nan")
    log.info("points %s%d/%d (%.0f %%), %.2f points/s, ETA %.0f s, elapsed %.0f s", approx, done,
             total, 100.0 * done / max(total, 1), rate, eta, elapsed)


def _exchange(comm: Any, grid: Grid, state: _State) -> None:
    """Send pending records to the ranks owning their rows; store what this rank receives."""
    owners = partition.owner_of_rows(grid.shape[0], comm.size)
    outgoing: list[list[tuple[np.ndarray, Records]]] = [[] for _ in range(comm.size)]
    for points, records in state.pending:
        dest = owners[points // grid.shape[1]]
        for rank in np.unique(dest):
            sel = dest == rank
            outgoing[rank].append((points[sel], {m: {k: v[sel] for k, v in r.items()}
                                                 for m, r in records.items()}))
    state.pending.clear()
    for batch in comm.alltoall(outgoing):
        for points, records in batch:
            iy, iyaw = np.divmod(points, grid.shape[1])
            rows = iy - state.row_start
            for m, rec in records.items():
                for k, v in rec.items():
                    state.blocks[m][k][rows, iyaw] = v
            state.done_rows[rows, iyaw] = 1


def _summarize(comm: Any, out: Path, grid: Grid, state: _State, busy_all: np.ndarray,
               computed: int, wall: float) -> BuildSummary:
    counts = np.zeros(len(STATUS), dtype=np.int64)
    for rec in state.blocks.values():
        codes = rec["status"].ravel().astype(np.int64)
        counts += np.bincount(codes[(codes >= 0) & (codes < len(STATUS))], minlength=len(STATUS))
    counts = comm.allreduce(counts)
    names = {code: text.split(":")[0] for code, text in STATUS.items()}
    summary = BuildSummary(output=out, points=grid.n_points, computed=computed,
                           reused=grid.n_points - computed,
                           status_counts={names[c]: int(n) for c, n in enumerate(counts) if n},
                           wall_time_s=wall, busy_s=[float(b) for b in busy_all], ranks=comm.size)
    if comm.rank == 0:
        log.info("table %s: %d points (%d computed, %d reused) x %d method(s); status %s",
                 out, summary.points, computed, summary.reused, len(state.blocks),
                 summary.status_counts)
        log.info("wall %.2f s on %d rank(s); busy per rank %s s; imbalance %.3f; parallel "
                 "efficiency %.1f %%", wall, comm.size,
                 "[" + ", ".join(f"{b:.2f}" for b in summary.busy_s) + "]",
                 summary.imbalance, 100 * summary.parallel_efficiency)
    return summary
