"""``build_table``: the only orchestration of a table build (serial or MPI).

Flow (every rank runs it; ``comm=None`` means one process):

1. Pure set-up on every rank (grid, methods, fields: a bad config fails everywhere alike).
2. Rank 0 decides alone (the writer's output checks and lock, the journal check on resume, the
   metadata, the scene) and broadcasts the value *or the exception*; every rank then raises the same
   error, nobody waits in a barrier.
3. The :class:`~lutmpi.parallel.writer.TableWriter` creates the partial file collectively and
   loads the verified points of a resumed build.
4. The points still to do are handed out one at a time from a counter every rank advances
   atomically (``workqueue``; static splits on request) and solved with no communication at all;
   each batch is journaled by its rank the moment it is computed.
5. The writer writes the table collectively, sets ``complete`` and renames it into place.

Any exception after step 2 on any rank is logged with the rank (and the grid point when a solve
raised) and ends the whole job with ``comm.Abort(1)``: no rank is left in a collective call; an
error rank 0 decided for every rank (``root_decides``) is logged by rank 0 alone. A
SIGINT/SIGTERM ends the build with a message saying the journal keeps what was computed (from
rank 0; the other ranks say so only if rank 0 does not end the job, :data:`ROOT_REPORTS_S`).
The table never depends on the number of ranks: every point is solved by the same pure code, and
where it was solved does not enter the file.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import json
import logging
import os
import signal
import subprocess
import threading
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
from lutmpi.errors import BuildInterruptedError, ConfigError, LutmpiError
from lutmpi.parallel import partition
from lutmpi.parallel.comm import SelfComm, raised_on_root, root_decides
from lutmpi.parallel.jumps_step import add_jumps, mirror_of
from lutmpi.parallel.workqueue import make_counter
from lutmpi.parallel.writer import TableWriter
from lutmpi.table.compute import Solver, compute_points, default_solver
from lutmpi.table.grid import Grid
from lutmpi.table.mirror import Reflection
from lutmpi.table.provenance import input_record
from lutmpi.table.schema import (
    SCHEMA_VERSION,
    D,
    select_fields,
)

log = logging.getLogger(__name__)

#: a static split hands a rank its points in at most this many batches (progress per batch)
N_STEPS = 200
PROGRESS_EVERY_S = 10.0
#: a rank other than 0 whose error rank 0 has too (raised by root_decides on every rank; a
#: signal, which mpirun sends every rank and an abort sends the ranks it kills) waits this long
#: for rank 0 to report it and abort the job before it reports and aborts itself: one report of
#: one failure, not one per rank
ROOT_REPORTS_S = 5.0


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
    journal_s: float = 0.0          # writing + syncing the journal, summed over ranks
    #: per rank: the grid loop's time outside the solves (records, journal, hand-out), s
    overhead_s: list[float] = field(default_factory=list)

    @property
    def overhead_fraction(self) -> float:
        """The largest rank's grid-loop time outside its solves over its busy time (issue 14:
        records, journal and hand-out should cost at most 5 % of the solving)."""
        return max((o / b for o, b in zip(self.overhead_s, self.busy_s, strict=False)
                    if b > 0), default=0.0)

    @property
    def parallel_efficiency(self) -> float:
        """Sum of busy time over ``ranks * wall time``: the busy fraction of the ranks (not a
        speed-up against one rank; ``benchmarks/strong_scaling.py`` measures that)."""
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


def with_methods(config: Config, methods: tuple[str, ...]) -> Config:
    """``config`` building ``methods``: ``output.methods`` set to them, ``contact.method``
    kept where it is one of them, else the first (a config names one of its methods)."""
    method = config.contact.method if config.contact.method in methods else methods[0]
    return dataclasses.replace(
        config, output=dataclasses.replace(config.output, methods=tuple(methods)),
        contact=dataclasses.replace(config.contact, method=method))


def git_commit() -> str:
    """The commit of the source tree lutmpi runs from, or ``""`` when unknown."""
    root = Path(__file__).resolve().parents[2]
    try:
        out = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True,
                             text=True, timeout=5, check=False)
    except (OSError, subprocess.SubprocessError):
        return ""
    return out.stdout.strip() if out.returncode == 0 else ""


def make_scene(config: Config) -> Any:
    """The production scene of ``config`` (:meth:`lutmpi.scene.Scene.from_config`)."""
    from lutmpi.scene import Scene

    return Scene.from_config(config)


def build_table(config: Config, output_path: str | os.PathLike[str], comm: Any = None, *,
                solver: Solver | None = None, force: bool = False, resume: bool = False,
                methods: Sequence[str] | None = None,
                scene_factory: Callable[[Config], Any] | None = None,
                checkpoint_interval_s: float = 10.0, split: str = "dynamic") -> BuildSummary:
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
        :func:`lutmpi.pose.solve.solve_pose`.
    force : bool
        Overwrite an existing table, discard an unfinished build.
    resume : bool
        Continue an unfinished build (its journal ``<out>.journal/``) when there is one, computing
        only the points not verified there; refused, naming the input, when the inputs' content
        hashes differ.
    methods : sequence of str, optional
        Override ``output.methods``.
    scene_factory : callable, optional
        ``scene_factory(config) -> scene``; default :meth:`lutmpi.scene.Scene.from_config`.
    checkpoint_interval_s : float
        Longest time a journaled point waits for ``fsync`` (every point is written to the journal
        the moment it is computed, which is what survives a kill).
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
    BuildInterruptedError
        SIGINT or SIGTERM during compute (one process; under MPI the job is aborted).
    """
    comm = SelfComm() if comm is None else comm
    t_start = time.perf_counter()
    grid = Grid.from_config(config.grid)
    chosen = resolve_methods(config, methods)
    if methods:   # the stored config says what was built: --method replaces output.methods
        config = with_methods(config, chosen)
    fields = select_fields(config.output.quantities)
    solver = solver or default_solver()
    factory = scene_factory or make_scene
    inputs = input_record(config) if comm.rank == 0 else None
    inputs = comm.bcast(inputs, root=0)
    writer = TableWriter(output_path, comm, grid, chosen, fields, inputs,
                         sync_interval_s=checkpoint_interval_s)
    try:   # an error here is raised on every rank alike (root_decides): nobody waits
        prep = root_decides(comm, lambda: _prepare(writer, config, factory, force, resume))
    except BaseException:
        writer.close()
        raise
    log.debug("prepared in %.3f s", time.perf_counter() - t_start)
    try:
        return _run(comm, writer, solver, prep, t_start, split, config)
    except BaseException as exc:
        writer.close()
        if isinstance(exc, BuildInterruptedError) and comm.rank == 0:
            log.error("build of %s %s; the points computed so far are kept in %s: rerun with "
                      "--resume to continue", writer.out, exc, writer.journal_dir)
        if comm.size > 1:
            _abort(comm, exc)
        raise


def _prepare(writer: TableWriter, config: Config, factory: Callable[[Config], Any], force: bool,
             resume: bool) -> dict[str, Any]:
    """Rank 0: the writer's decision, the run metadata and the scene."""
    plan = writer.prepare(force=force, resume=resume)
    return {"plan": plan, "config_toml": config.text,
            "created_utc": datetime.now(UTC).isoformat(timespec="seconds"),
            "git_commit": git_commit(), "scene": factory(config)}


def _abort(comm: Any, exc: BaseException) -> None:
    if comm.rank != 0 and (raised_on_root(exc) or isinstance(exc, BuildInterruptedError)):
        time.sleep(ROOT_REPORTS_S)   # ended by rank 0's Abort; speaks only if that never came
    notes = "; ".join(getattr(exc, "__notes__", []))
    if isinstance(exc, BuildInterruptedError):
        log.critical("rank %d/%d %s -- ending the job; the journal keeps the points computed "
                     "so far: rerun with --resume", comm.rank, comm.size, exc)
    else:
        log.critical("rank %d/%d failed: %s: %s%s -- aborting the job", comm.rank, comm.size,
                     type(exc).__name__, exc, f" ({notes})" if notes else "",
                     exc_info=None if isinstance(exc, LutmpiError) else exc)
    for handler in logging.getLogger().handlers:
        handler.flush()
    comm.Abort(1)


def _run(comm: Any, writer: TableWriter, solver: Solver, prep: dict[str, Any], t_start: float,
         split: str, config: Config) -> BuildSummary:
    grid, methods = writer.grid, writer.methods
    attrs = {"config_toml": prep["config_toml"], "lutmpi_version": __version__,
             "git_commit": prep["git_commit"], "created_utc": prep["created_utc"],
             "schema_version": SCHEMA_VERSION, "methods": json.dumps(list(methods)),
             "quantities": json.dumps([f.name for f in writer.fields]),
             "inputs": json.dumps(writer.inputs, sort_keys=True),
             "ranks": comm.size, "wall_time_s": float("nan"),
             "rank_busy_s": np.full(comm.size, np.nan)}
    done = writer.begin(prep["plan"], attrs)
    if prep["plan"].resume:
        log.info("resuming %s: %d of %d points verified in the journal and reused", writer.out,
                 int(done.sum()), grid.n_points)
    todo = np.flatnonzero(~done)
    mirror, why = mirror_of(config, prep["scene"], solver, grid.y, grid.yaw)
    solve, images = mirror.grid_plan(todo) if mirror is not None else (todo, {})
    if comm.rank == 0 and len(todo):
        log.info("grid: %d of %d points to do solved, %d filled by reflection (%s)",
                 len(solve), len(todo), len(todo) - len(solve),
                 why if mirror is not None else f"none: {why}")
    _compile_once(comm)   # also with nothing left to do: the jump step after the grid solves
    # the counter's window is collective: made before the warm-up, so a rank whose kernels load
    # sooner starts on the points at once instead of waiting for the slowest to load
    counter = make_counter(comm) if split == "dynamic" else None
    warm, warm_s = getattr(solver, "warm", None), 0.0
    if warm is not None and len(solve):   # kernels loaded before the grid, outside busy time
        t0 = time.perf_counter()
        y, yaw = grid.pose(int(solve[0]))
        for method in methods:
            warm(prep["scene"], method, y, yaw)
        warm_s = time.perf_counter() - t0
    busy, loop = _compute_all(comm, writer, grid, prep["scene"], methods, solver,
                              _batches(comm, solve, split, counter), len(solve), images)
    if counter is not None:
        counter.free()  # collective: not on an error path (that aborts the job instead)
    wall = comm.bcast(time.perf_counter() - t_start, root=0)
    busy_all = np.asarray(comm.bcast(comm.gather(busy, root=0), root=0), dtype=float)
    loop_all = np.asarray(comm.bcast(comm.gather(loop, root=0), root=0), dtype=float)
    warm_all = comm.gather(warm_s, root=0)
    journal_s = float(comm.allreduce(writer.journal_seconds))
    writer.finish({"wall_time_s": wall, "rank_busy_s": busy_all}, after_grid=functools.partial(
        add_jumps, comm, grid, config, prep["scene"], solver, methods, writer.fields,
        split=split, mirror=(mirror, why)))  # issue 11
    total = time.perf_counter() - t_start
    if comm.rank == 0:
        # the grid's figures below exclude this: say what the whole build took
        log.info("after the grid: jump location/refinement and the final write %.2f s; whole "
                 "build %.2f s", total - wall, total)
        log.info("journal: %.3f s of writing and syncing over all ranks (%.2f %% of busy time)",
                 journal_s, 100 * journal_s / max(float(busy_all.sum()), 1e-12))
    summary = _summarize(comm, writer, busy_all, len(todo), wall)
    summary.journal_s = journal_s
    summary.overhead_s = [float(x) for x in loop_all - busy_all]
    if comm.rank == 0 and len(todo):
        log.info("compiled kernels loaded before the grid: %s s per rank",
                 "[" + ", ".join(f"{w:.2f}" for w in warm_all) + "]")
        log.info("grid loop outside the solves (records, journal, hand-out): %s s per rank, at "
                 "most %.1f %% of a rank's busy time",
                 "[" + ", ".join(f"{o:.2f}" for o in summary.overhead_s) + "]",
                 100 * summary.overhead_fraction)
    return summary


def _compile_once(comm: Any) -> None:
    """On a cold kernel cache (setup not run since the sources changed), one rank per cache
    folder compiles every kernel first (:func:`lutmpi.warmup.warm_kernels`, ~1.5 min on 2 cores)
    while the other ranks wait, then they load them: ranks compiling at once would write the same
    cache entries concurrently, which numba does not guard against. The folder is usually one
    for all ranks (next to the package, or ``NUMBA_CACHE_DIR`` on a shared file system);
    node-local caches (``NUMBA_CACHE_DIR`` on a node's scratch disk) make one per node
    (:func:`_cache_leader`). A rank whose folder cannot be written compiles what it needs in
    its first solves (numba cannot cache there either). Two jobs on one cold folder are
    ordered by the compile's lock (:func:`lutmpi.warmup.compile_lock`). A cache warm on every
    rank (the usual case) costs one reduction."""
    if comm.size == 1:
        return
    from lutmpi import warmup

    ready = warmup.kernels_ready()
    if not comm.allreduce(0 if ready else 1):
        return
    folder = warmup.ready_marker().parent
    leader, writable = _cache_leader(comm, folder)
    if comm.rank == leader and writable and not ready:
        log.warning("the compiled kernels' cache %s is not filled (run scripts/setup.sh or "
                    "`python -m lutmpi.warmup` after changing the sources; with NUMBA_CACHE_DIR "
                    "on node-local scratch, point it at a shared folder filled once instead): "
                    "rank %d compiles them (~1.5 min) before any rank using that folder loads "
                    "them", folder, comm.rank)
        log.info("kernels compiled in %.1f s", warmup.warm_kernels())
    comm.Barrier()   # all ranks wait (the build's collective end waits for the compiles anyway)


def _cache_leader(comm: Any, folder: Path) -> tuple[int, bool]:
    """The lowest rank whose kernel cache folder is this rank's ``folder``, whatever its path
    says, and whether this rank can write there. One path can name one folder on every node (a
    shared file system) or one per node (local scratch), which no comparison of names tells
    apart. Each rank creates a probe file named by a fresh token and its rank in its folder,
    then looks up the lower ranks' probes by name (a lookup of a name never seen before asks
    the file server; a directory listing may be cached on NFS); a rank that cannot write there
    leads itself. A job killed between the probes' creation and removal leaves them behind
    (``.lutmpi-probe-<token>-<rank>``: harmless, and safe to delete). Collective."""
    token = comm.bcast(os.urandom(8).hex() if comm.rank == 0 else None, root=0)
    prefix = f".lutmpi-probe-{token}-"
    probe: Path | None = folder / f"{prefix}{comm.rank}"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe.touch()
    except OSError:
        probe = None
    comm.Barrier()   # every probe is written before any is looked for
    leader = comm.rank
    if probe is not None:
        leader = next((r for r in range(comm.rank) if (folder / f"{prefix}{r}").exists()),
                      comm.rank)
    comm.Barrier()   # every rank has looked before any probe goes
    if probe is not None:
        probe.unlink(missing_ok=True)
    return leader, probe is not None


def _batches(comm: Any, todo: np.ndarray, how: str,
             counter: Any = None) -> Iterator[tuple[np.ndarray, int]]:
    """This rank's points, in batches, each with an estimate of the global count handed out.

    ``"dynamic"``: one point at a time from ``counter``, shared by all ranks (no rank waits for
    another; :func:`lutmpi.parallel.workqueue.make_counter`); the static splits of
    :mod:`lutmpi.parallel.partition` otherwise.
    """
    if how == "dynamic":
        while (k := counter.next()) < len(todo):
            yield todo[k:k + 1], k + 1
        return
    mine = todo[partition.split(len(todo), comm.size, comm.rank, how)]
    step = max(1, len(mine) // N_STEPS)
    for start in range(0, len(mine), step):
        yield mine[start:start + step], min((start + step) * comm.size, len(todo))


def _compute_all(comm: Any, writer: TableWriter, grid: Grid, scene: Any,
                 methods: tuple[str, ...], solver: Solver,
                 batches: Iterator[tuple[np.ndarray, int]], n_todo: int,
                 images: dict[int, list[tuple[int, Reflection]]] | None = None
                 ) -> tuple[float, float]:
    """Solve this rank's points without waiting for any other rank; journal each batch at once,
    with the points that are reflections of its points (``images``:
    :meth:`lutmpi.table.mirror.Mirror.grid_plan`) filled from them. Rank 0 logs the estimated
    global progress. SIGINT/SIGTERM raise :class:`~lutmpi.errors.BuildInterruptedError`.

    Returns ``(busy, loop)``: the time spent in the solver and the loop's time from its first
    hand-out to its last point journaled (the difference is the per-point overhead; the wait
    for the other ranks' last points at the counter's collective release is not in it), s.
    """
    busy = 0.0
    t0 = last_log = end = time.perf_counter()
    with _signals_raise():
        for points, handed_out in batches:
            extra = [(q, g, n) for n, p in enumerate(points.tolist())
                     for q, g in (images or {}).get(p, ())]
            rows, first = writer.claim(len(points) + len(extra))
            _, spent = compute_points(scene, grid, points, methods, solver, writer.fields,
                                      out=rows, first=first)
            busy += spent
            for k, (_, g, n) in enumerate(extra):
                writer.reflect(first + n, first + len(points) + k, g)
            writer.commit(np.concatenate([points, np.array([q for q, _, _ in extra],
                                                           dtype=points.dtype)]))
            end = time.perf_counter()
            if comm.rank == 0 and end - last_log >= PROGRESS_EVERY_S:
                _log_progress(handed_out, n_todo, end - t0, "~")
                last_log = end
    return busy, end - t0


@contextlib.contextmanager
def _signals_raise() -> Iterator[None]:
    """Turn SIGINT and SIGTERM into :class:`~lutmpi.errors.BuildInterruptedError` (main thread
    only; the previous handlers are restored after)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum: int, frame: Any) -> None:
        raise BuildInterruptedError(signum)

    old = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)


def _log_progress(done: int, total: int, elapsed: float, approx: str = "") -> None:
    rate = done / elapsed if elapsed > 0 else 0.0
    eta = (total - done) / rate if rate > 0 else float("nan")
    log.info("points %s%d/%d (%.0f %%), %.2f points/s, ETA %.0f s, elapsed %.0f s", approx, done,
             total, 100.0 * done / max(total, 1), rate, eta, elapsed)


def _summarize(comm: Any, writer: TableWriter, busy_all: np.ndarray, computed: int,
               wall: float) -> BuildSummary:
    counts = np.zeros(len(STATUS), dtype=np.int64)
    for rec in writer.blocks.values():
        codes = rec[D.status].ravel().astype(np.int64)
        counts += np.bincount(codes[(codes >= 0) & (codes < len(STATUS))], minlength=len(STATUS))
    counts = comm.allreduce(counts)
    names = {code: text.split(":")[0] for code, text in STATUS.items()}
    grid, out = writer.grid, writer.out
    summary = BuildSummary(output=out, points=grid.n_points, computed=computed,
                           reused=grid.n_points - computed,
                           status_counts={names[c]: int(n) for c, n in enumerate(counts) if n},
                           wall_time_s=wall, busy_s=[float(b) for b in busy_all], ranks=comm.size)
    if comm.rank == 0:
        log.info("table %s: %d points (%d computed, %d reused) x %d method(s); status %s",
                 out, summary.points, computed, summary.reused, len(writer.methods),
                 summary.status_counts)
        failed = {k: n for k, n in summary.status_counts.items() if k != "converged"}
        if failed:
            log.warning("%d of %d point results did not converge %s: stored with their status "
                        "(lookups there give NaN); `lutmpi inspect` lists them, `lutmpi check` "
                        "says why", sum(failed.values()), int(counts.sum()), failed)
        # names that say what they are: busy/(ranks x wall) is how busy the ranks were, not a
        # speed-up; summed busy / wall is the speed-up over one rank only if a point costs the
        # same with N ranks busy (measure it: benchmarks/strong_scaling.py)
        log.info("grid: wall %.2f s on %d rank(s); busy per rank %s s; imbalance %.3f; busy "
                 "fraction %.1f %%; summed busy / wall %.2f (the speed-up over 1 rank if points "
                 "cost the same on N)", wall, comm.size,
                 "[" + ", ".join(f"{b:.2f}" for b in summary.busy_s) + "]",
                 summary.imbalance, 100 * summary.parallel_efficiency,
                 sum(summary.busy_s) / wall if wall > 0 else 0.0)
    return summary
