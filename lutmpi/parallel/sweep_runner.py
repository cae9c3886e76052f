"""``run_sweep``: build one table per sweep member, serially or under ``mpirun``.

Design (every rank runs it; ``comm=None`` means one process):

1. The sweep is expanded on every rank (pure and deterministic: the same members everywhere). A bad
   sweep file (unknown key, empty product, missing profile) raises ``ConfigError`` on every rank
   before anything runs.
2. Members run one after another, each built by *all* ranks with
   :func:`lutmpi.parallel.runner.build_table` (a member's grid points are split over the ranks).
   So no rank idles while a member has at least as many points as there are ranks, and the table of
   a member is the same whatever the number of ranks.
3. A member whose complete table is already in ``OUTDIR``, computed from the same inputs (content
   hashes of the profiles and the resolved config, :mod:`lutmpi.table.provenance`), is skipped, so
   a rerun continues an interrupted sweep (an interrupted member resumes from its journal). A
   table computed from other inputs (a profile file edited since) is not kept: the member fails
   with a message naming the input, and ``--force`` recomputes it.
4. A member that cannot be built (a profile file that does not parse, a geometry that cannot be
   placed: errors raised before compute, on every rank alike) is recorded as ``failed`` with its
   message, and the sweep goes on. An exception raised by the solver at one grid point becomes that
   point's status 7 (``error``), counted in the index; a member whose every point failed is
   ``failed``.
5. Scenes are cached between members whose configurations differ only in what a scene does not
   depend on (grid, output selection, contact method), e.g. the methods of one mesh level.
6. Rank 0 writes ``OUTDIR/index.csv`` and ``OUTDIR/index.json`` with every member before the
   first (status ``pending``) and rewrites them after every member; a signal marks the member it
   stopped as ``interrupted`` and leaves the rest ``pending``. ``--only`` names members of the
   sweep (another ID is an error); the others keep the status of their complete table on disk,
   or are ``not selected``.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import logging
import math
import os
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lutmpi.config.model import Config, ContactConfig, GridConfig, OutputConfig
from lutmpi.equilibrium.result import ERROR, STATUS, PoseResult
from lutmpi.errors import BuildInterruptedError, ConfigError, LutmpiError
from lutmpi.parallel.comm import SelfComm, root_decides
from lutmpi.table import provenance

log = logging.getLogger(__name__)

Solver = Callable[[Any, float, float, str], PoseResult]
#: the index status of a member the sweep has not reached (yet, or ever: it was interrupted)
PENDING = "pending"
INDEX_FIELDS = ("id", "status", "message", "skipped", "points", "failed_points", "wall_s",
                "cpu_s", "ranks", "table", "params")


@dataclass
class MemberRecord:
    """One line of the sweep index."""

    id: str
    params: dict[str, Any]
    #: ok | partial (some poses failed) | failed | not selected | interrupted | pending
    status: str = PENDING
    message: str = ""
    skipped: bool = False           # complete table found, not rebuilt
    points: int = 0
    failed_points: int = 0          # points with status != 0
    wall_s: float = math.nan        # wall time of the member's build (this run, or as stored)
    cpu_s: float = math.nan         # sum of compute_time over the table
    ranks: int = 0
    table: str = ""                 # relative to OUTDIR

    def row(self) -> dict[str, Any]:
        out = {k: getattr(self, k) for k in INDEX_FIELDS}
        out["params"] = json.dumps(self.params, sort_keys=False, default=str)
        return out


@dataclass
class SweepSummary:
    """What a sweep did (the same on every rank)."""

    outdir: Path
    members: list[MemberRecord] = field(default_factory=list)
    #: the production solver's kernels loaded before the first member built (:func:`_warm`),
    #: s, the slowest rank's; None: no member built
    warmup_s: float | None = None

    @property
    def failed(self) -> list[MemberRecord]:
        """Members without a table (``partial`` and ``not selected`` are not failures)."""
        return [m for m in self.members if m.status == "failed"]


class SceneCache:
    """``scene_factory`` that reuses a scene between members sharing what the scene depends on.

    The key is the configuration with ``grid``, ``output``, ``contact.method`` and ``path`` set to
    fixed values: a scene holds profiles, geometry and meshes, not the grid or the method."""

    def __init__(self, factory: Callable[[Config], Any]):
        self.factory = factory
        self.scenes: dict[str, Any] = {}
        self.hits = 0

    @staticmethod
    def key(config: Config) -> str:
        neutral = dataclasses.replace(
            config, grid=GridConfig(), output=OutputConfig(), path=None,
            contact=dataclasses.replace(config.contact, method=ContactConfig.method))
        return repr(neutral)

    def __call__(self, config: Config) -> Any:
        k = self.key(config)
        if k in self.scenes:
            self.hits += 1
            return self.scenes[k]
        scene = self.factory(config)
        self.scenes = {k: scene}      # keep one: members sharing a scene are adjacent in sweeps
        return scene


class Tolerant:
    """``solver`` with an exception at one pose turned into a result with status ``ERROR``.

    One-off costs (numba's kernels loaded, caches) are kept out of every pose's time, so the
    error-against-time plots compare like with like: :meth:`warm`, which the build calls once
    per method before its grid, warms ``solver`` (its own ``warm`` when it has one, else a solve
    whose result is dropped), and a method's first solve warms it if the build did not.
    """

    def __init__(self, solver: Solver) -> None:
        self.solver = solver
        self._warm: set[str] = set()

    @property
    def reflection_symmetric(self) -> bool:
        """The wrapped solver's (a pose that raised is an error record at its image too)."""
        return bool(getattr(self.solver, "reflection_symmetric", False))

    def warm(self, scene: Any, method: str, y: float = 0.0, yaw: float = 0.0) -> None:
        """Warm ``method`` once (its first solve at ``(y, yaw)``, m and rad, when ``solver`` has
        no ``warm``); an exception there is left for that pose's own solve to report."""
        if method in self._warm:
            return
        self._warm.add(method)
        inner = getattr(self.solver, "warm", None)
        try:
            if inner is not None:
                inner(scene, method, y, yaw)
            else:
                self.solver(scene, y, yaw, method)
        except Exception:  # the pose's own solve raises it again and records it
            log.debug("warming %s at y=%.6g m, yaw=%.6g rad raised", method, y, yaw,
                      exc_info=True)

    def __call__(self, scene: Any, y: float, yaw: float, method: str) -> PoseResult:
        self.warm(scene, method, y, yaw)
        t0 = time.process_time()
        try:
            return self.solver(scene, y, yaw, method)
        except Exception as exc:  # a failed point is data (STYLE 4); logged with the pose
            log.warning("solver raised at y=%.6g m, yaw=%.6g rad, method %s: %s: %s", y, yaw,
                        method, type(exc).__name__, exc)
            return PoseResult(y=y, yaw=yaw, method=method, success=False, status=ERROR,
                              message=f"{STATUS[ERROR]} ({type(exc).__name__}: {exc})",
                              time=time.process_time() - t0)


def _table_state(path: Path, inputs: dict[str, Any]) -> tuple[str, str]:
    """``("absent"|"complete"|"different"|"broken", why)``: a complete table counts as this
    member's only when its recorded input hashes equal ``inputs`` (content, not paths)."""
    if not path.exists():
        return "absent", ""
    from lutmpi.table.h5io import read_attrs

    try:
        attrs = read_attrs(path)
        if not attrs.get("complete", False):
            return "broken", "incomplete table"
        stored = json.loads(attrs.get("inputs") or "{}")
    except (LutmpiError, ValueError) as exc:
        return "broken", str(exc)
    diffs = provenance.differences(stored, inputs)
    return ("different", "; ".join(diffs)) if diffs else ("complete", "")


def _table_stats(path: Path) -> dict[str, Any]:
    """Points, failed points, CPU seconds, stored wall time and ranks of a complete table."""
    import numpy as np

    from lutmpi.table import Table
    from lutmpi.table.schema import D

    table = Table.open(path, mask_failed=False)
    points = failed = 0
    cpu = 0.0
    for m in table.methods:
        status = table.get(D.status, m, raw=True)
        points += status.size
        failed += int(np.count_nonzero(status != 0))
        if D.compute_time in table.quantities:
            cpu += float(np.nansum(table.get(D.compute_time, m, raw=True)))
    return {"points": points, "failed_points": failed, "cpu_s": cpu,
            "wall_s": float(table.attrs.get("wall_time_s", math.nan)),
            "ranks": int(table.attrs.get("ranks", 0))}


def write_index(outdir: Path, records: Sequence[MemberRecord]) -> None:
    """Write ``index.csv`` and ``index.json`` atomically (rank 0 only).

    Raises
    ------
    OutputError
        A write error (disk full, I/O error), naming the folder; the tables are not affected.
    """
    from lutmpi.errors import OutputError

    try:
        _write_index(outdir, records)
    except OSError as exc:
        raise OutputError(f"cannot write the sweep index in {outdir}: {exc.strerror or exc}; "
                          "the member tables are kept: rerun the sweep to rewrite it") from exc


def _write_index(outdir: Path, records: Sequence[MemberRecord]) -> None:
    rows = [r.row() for r in records]
    tmp = outdir / "index.csv.tmp"
    with open(tmp, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=INDEX_FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, outdir / "index.csv")
    data = [dict(r.row(), params=r.params) for r in records]
    tmp = outdir / "index.json.tmp"
    tmp.write_text(json.dumps({"members": data}, indent=1, default=str) + "\n")
    os.replace(tmp, outdir / "index.json")


def run_sweep(sweep: str | os.PathLike[str], outdir: str | os.PathLike[str], comm: Any = None, *,
              solver: Solver | None = None, scene_factory: Callable[[Config], Any] | None = None,
              force: bool = False, only: Sequence[str] | None = None) -> SweepSummary:
    """Run every member of a sweep file into ``outdir``.

    Parameters
    ----------
    sweep : path
        Sweep TOML file (see :mod:`lutmpi.config.sweep`).
    outdir : path
        Output directory (created): ``<member id>.h5`` per member, ``index.csv``, ``index.json``.
    comm : mpi4py communicator, optional
        ``None`` for one process.
    solver : callable, optional
        ``solver(scene, y, yaw, method) -> PoseResult``; default: the production solver.
    scene_factory : callable, optional
        ``scene_factory(config) -> scene``; default :meth:`lutmpi.scene.Scene.from_config`.
    force : bool
        Rebuild every member, even those with a complete table.
    only : sequence of str, optional
        Run only these member IDs (others are listed in the index as they are on disk).

    Returns
    -------
    SweepSummary

    Raises
    ------
    ConfigError
        A bad sweep file, on every rank, before anything runs.
    """
    from lutmpi.config.sweep import expand_sweep
    from lutmpi.outpath import check_output_dir
    from lutmpi.parallel.runner import build_table, make_scene

    comm = SelfComm() if comm is None else comm
    out = Path(outdir)
    root_decides(comm, lambda: check_output_dir(out, "sweep output folder"))  # before any work
    root_decides(comm, lambda: len(expand_sweep(sweep)))   # a bad file: rank 0's error, once
    members = expand_sweep(sweep)                      # pure: same list on every rank
    if only:      # a misspelt ID would select nothing and end "done"
        root_decides(comm, lambda: _check_only(only, [m.id for m in members], sweep))
    root_decides(comm, lambda: _make_outdir(out))
    cache = SceneCache(scene_factory or make_scene)
    # every member is in the index from the start: an interrupted sweep lists what it did not
    # reach as pending, never as if the sweep had fewer members
    records = [MemberRecord(m.id, dict(m.params), table=f"{m.id}.h5", ranks=comm.size,
                            status=PENDING, message="not reached yet") for m in members]
    summary = SweepSummary(out, records)
    base_solver: Solver | None = solver
    root_decides(comm, lambda: write_index(out, records))
    n, rec = 0, records[0] if records else None
    try:
        for n, (member, rec) in enumerate(zip(members, records, strict=True), 1):
            path = out / rec.table
            state, why = root_decides(comm, lambda p=path, m=member: _table_state(
                p, provenance.input_record(m.config)))
            if only and member.id not in only:
                if state == "complete":     # on disk and this member's: listed as it is
                    _record_existing(comm, rec, path, state)
                    rec.message += " (not in --only)"
                else:
                    rec.status, rec.message = "not selected", "not in --only" + (
                        f"; its table on disk is {state}" if state != "absent" else "")
                root_decides(comm, lambda: write_index(out, records))
                continue
            if state == "complete" and not force:
                _record_existing(comm, rec, path, state)
                root_decides(comm, lambda: write_index(out, records))
                continue
            if state == "different" and not force:
                rec.status, rec.message = "failed", (
                    f"{path.name} exists, computed from other inputs ({why}); remove it or use "
                    "--force to recompute it")
                root_decides(comm, lambda: write_index(out, records))
                continue
            if summary.warmup_s is None:   # once, before the first member built
                base_solver, summary.warmup_s = _warm(comm, base_solver)
            log.info("member %d/%d %s", n, len(members), member.id)
            t0 = time.perf_counter()
            try:
                build_table(member.config, path, comm, solver=Tolerant(base_solver),
                            force=force or state == "broken", resume=True, scene_factory=cache)
            except BuildInterruptedError:   # a LutmpiError, but the sweep's end, not a member's
                raise
            except (LutmpiError, ImportError, OSError, ValueError, RuntimeError) as exc:
                # raised before compute, on every rank alike (comm.root_decides): not a hang
                rec.status, rec.message = "failed", f"{type(exc).__name__}: {exc}"
                log.error("member %s failed: %s", member.id, rec.message)
                log.debug("%s", traceback.format_exc())
            else:
                wall = time.perf_counter() - t0
                _record_built(comm, rec, path, wall)
            root_decides(comm, lambda: write_index(out, records))
    except (BuildInterruptedError, KeyboardInterrupt) as exc:   # a signal: the sweep ends here
        _interrupted(comm, out, records, rec, n, exc)
        raise
    log.info("sweep done: %d members: %s", len(records), _status_counts(records))
    return summary


def _warm(comm: Any, solver: Solver | None) -> tuple[Solver, float]:
    """``solver``, default the production solver with its compiled kernels loaded on every
    rank, and the time that took (the slowest rank's, s). Loaded inside the first member's
    build, they made its wall time that of the others plus the loading (0.2 s from a warm
    cache; 1.5 min compiling a cold one): members' times compared against their mesh or
    method compared the loading. A solver hook (tests) warms in each member's build (0 s)."""
    if solver is not None:
        return solver, 0.0
    from lutmpi import warmup
    from lutmpi.parallel.runner import _compile_once
    from lutmpi.table.compute import default_solver

    t0 = time.perf_counter()
    solver = default_solver()
    _compile_once(comm)   # a cold cache: one rank compiles while the others wait
    if warmup.kernels_ready():
        warmup.load_kernels()
    else:                 # one rank, or a cache nobody can write: compiled here
        warmup.warm_kernels()
    spent = comm.gather(time.perf_counter() - t0, root=0)
    if comm.rank == 0:
        log.info("compiled kernels loaded in %.2f s before the first member (not in any "
                 "member's wall time)", max(spent))
    return solver, comm.bcast(max(spent) if comm.rank == 0 else None, root=0)


def _interrupted(comm: Any, out: Path, records: list[MemberRecord], rec: MemberRecord | None,
                 n: int, exc: BaseException) -> None:
    """Mark member ``n`` (``rec``) interrupted in the index and say where the sweep stopped;
    the members after it stay ``pending``."""
    if rec is not None and rec.status == PENDING:    # stopped in this member, not after it
        rec.status = "interrupted"
        rec.message = (f"{exc or 'interrupted'}; its points so far are kept in "
                       f"{rec.table}.journal/ (if it got that far): rerun the sweep to resume it")
    if comm.rank == 0:     # no collective: the other ranks are being interrupted too
        try:
            write_index(out, records)
        except LutmpiError as err:
            log.error("%s", err)
    log.error("sweep interrupted at member %d/%d %s; %d not reached: rerun the same command to "
              "continue", n, len(records), rec.id if rec else "-", len(records) - n)


def _check_only(only: Sequence[str], ids: list[str], sweep: Any) -> None:
    """A ``--only`` ID that is no member of the sweep is a :class:`ConfigError` listing the
    members."""
    unknown = [i for i in only if i not in ids]
    if unknown:
        raise ConfigError(f"no member {', '.join(map(repr, unknown))} in {sweep}; its members: "
                          f"{', '.join(ids)}", key="--only")


def _make_outdir(out: Path) -> None:
    from lutmpi.errors import OutputError

    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"cannot create the sweep output folder {out}: {exc}") from exc


def _status_counts(records: Sequence[MemberRecord]) -> str:
    """``"9 ok, 2 partial (a, b), 1 failed (c), 3 not selected"``."""
    out = []
    for status in ("ok", "partial", "failed", "interrupted", "not selected", PENDING):
        ids = [r.id for r in records if r.status == status]
        if ids:
            named = status in ("partial", "failed")
            out.append(f"{len(ids)} {status}" + (f" ({', '.join(ids)})" if named else ""))
    return ", ".join(out) or "none"


def _partial(rec: MemberRecord) -> None:
    """A member with some failed poses is ``partial``, never ``ok`` (and says so at WARNING)."""
    if rec.points and rec.failed_points == rec.points:
        rec.status, rec.message = "failed", f"all {rec.points} points failed (see status)"
    elif rec.failed_points:
        rec.status = "partial"
        rec.message = f"{rec.failed_points} of {rec.points} points not converged (see status)"
        log.warning("member %s: %s", rec.id, rec.message)
    else:
        rec.status = "ok"


def _record_existing(comm: Any, rec: MemberRecord, path: Path, state: str) -> None:
    if state != "complete":
        rec.status, rec.message = "failed", f"not run ({state} table)"
        return
    stats = root_decides(comm, lambda: _table_stats(path))
    rec.skipped = True
    for k, v in stats.items():
        setattr(rec, k, v)
    _partial(rec)
    if rec.status == "ok":
        rec.message = "complete table found"


def _record_built(comm: Any, rec: MemberRecord, path: Path, wall: float) -> None:
    stats = root_decides(comm, lambda: _table_stats(path))
    for k, v in stats.items():
        setattr(rec, k, v)
    rec.wall_s = comm.bcast(wall, root=0)
    rec.ranks = comm.size
    rec.message = "built"          # not the "not reached yet" it was listed with
    _partial(rec)
