"""``TableWriter``: the one object that writes a table, for 1 rank as for N.

It owns every path of a build of ``OUT``:

* ``OUT.lock``     the exclusive lock, held by rank 0 from the first check to the final rename
  (:mod:`lutmpi.table.lock`): a second build of the same output is refused at once;
* ``OUT.journal/`` every computed point, appended and checksummed the moment it is computed
  (:mod:`lutmpi.table.journal`): it survives ``kill -9`` of any rank at any moment, and resume
  reuses exactly the records that pass their checks;
* ``OUT.partial``  the HDF5 file, created (storage allocated) before compute and written once, at
  the end, by the strategy for the rank count (:class:`lutmpi.table.h5io.SerialH5` or
  :class:`~lutmpi.table.h5io.MpioH5`);
* ``OUT``          appears only by the final rename of a complete ``OUT.partial``.

Protocol (the runner calls, every rank):

1. :meth:`prepare` on rank 0 only (inside the runner's "root decides, then broadcasts the value or
   the exception"): validate the paths, take the lock, check free space, and on resume verify the
   journal's inputs (by content hash) and records. Returns the done mask.
2. :meth:`begin` (collective): create or recreate the partial file, a fresh journal if not resuming,
   open this rank's journal file, and load this rank's share of the verified records.
3. :meth:`claim` and :meth:`commit` (no communication): the rows of this rank's store, filled in
   place by the solves and journaled as they are. Rank 0 also looks, once per sync interval, that
   the output folder and ``OUT.partial`` are still there (:meth:`check_files`): appends to a
   journal whose folder was removed still succeed, so without the look a removed folder would
   show only at the end.
4. :meth:`finish` (collective): sync the journals, check the files again (rank 0 decides), send
   every record to the rank owning its rows (one ``alltoall``), write the row blocks, set
   ``complete``, rename, drop the journal, unlock.
5. :meth:`close` (every rank, always): release the lock and files if anything failed.

A file operation that fails after :meth:`prepare` raises :class:`~lutmpi.errors.TableError` naming
the file and the reason (the runner reports it in one line and ends the job).
"""

from __future__ import annotations

import logging
import os
import shutil
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lutmpi.errors import TableError
from lutmpi.parallel import partition
from lutmpi.parallel.comm import root_decides
from lutmpi.table import h5io, journal, provenance
from lutmpi.table.grid import Grid
from lutmpi.table.lock import OutputLock, lock_path
from lutmpi.table.schema import Field, RowReflection, row_reflection

log = logging.getLogger(__name__)

Records = dict[str, dict[str, np.ndarray]]

#: rows of a rank's store allocated at a time (its points are handed out one by one)
STORE_CHUNK = 256


@dataclass
class Plan:
    """What rank 0 decided before compute (broadcast to every rank)."""

    resume: bool
    done: np.ndarray | None           # flat done mask of a resumed build
    files: list[Path] = field(default_factory=list)     # journal files to reuse
    run_id: str = ""


class TableWriter:
    """Writes one table ``out`` from ``comm``'s ranks (``comm.size == 1``: serially).

    Parameters
    ----------
    out : path
        The final table file.
    comm : communicator
        mpi4py communicator or :class:`lutmpi.parallel.runner.SelfComm`.
    grid : Grid
    methods : sequence of str
    fields : sequence of Field
    inputs : dict
        :func:`lutmpi.table.provenance.input_record` of the build's config.
    sync_interval_s : float
        Longest time a journaled point waits for ``fsync``.
    """

    def __init__(self, out: str | os.PathLike[str], comm: Any, grid: Grid,
                 methods: Sequence[str], fields: Sequence[Field], inputs: dict[str, Any],
                 sync_interval_s: float = 10.0):
        if not str(out).strip() or not Path(out).name:   # same on every rank: no collective yet
            raise TableError(f"the output path {str(out)!r} names no file; give one such as "
                             "-o table.h5")
        self.out = Path(out)
        self.partial = h5io.partial_path(self.out)
        self.journal_dir = journal.journal_dir(self.out)
        self.comm, self.grid = comm, grid
        self.methods, self.fields = tuple(methods), tuple(fields)
        self.inputs = inputs
        self.dtype = journal.record_dtype(self.methods, self.fields)
        self.io = h5io.strategy(comm)
        self.sync_interval_s = sync_interval_s
        self.row_start, self.row_count = partition.block_range(grid.shape[0], comm.size,
                                                               comm.rank)
        self.blocks: Records = {m: {f.name: f.empty((self.row_count, grid.shape[1]))
                                    for f in fields} for m in self.methods}
        self.pending: list[tuple[np.ndarray, Records]] = []
        #: this rank's computed points, in the journal's record layout, filled in place
        #: (:meth:`claim`): the chunks, each with its rows committed so far
        self._store: list[tuple[np.ndarray, int]] = []
        self._views: Records = {}
        self._bytes = np.zeros((0, 0), dtype=np.uint8)   # the last chunk's rows as bytes
        self._reflections: dict[Any, RowReflection] = {}  # Reflection -> its row_reflection
        self._lock = OutputLock(self.out)
        self._journal: journal.JournalWriter | None = None
        self._partial_id: tuple[int, int] | None = None   # (st_dev, st_ino) made by begin
        self._next_check = 0.0                              # rank 0's next check_files, monotonic

    # -- 1. rank 0 decides ------------------------------------------------------------------
    def prepare(self, *, force: bool, resume: bool) -> Plan:
        """Validate the output, take the lock, decide fresh or resume (rank 0 only).

        Raises
        ------
        TableError
            A bad or busy output path, too little space, or a partial build that cannot be
            resumed by this build (the message names the input that changed).
        """
        check_output_target(self.out)
        _check_directory(self.out.parent if str(self.out.parent) else Path("."), 0)
        self._lock.acquire()
        try:
            return self._decide(force, resume)
        except BaseException:
            self._lock.release()
            raise

    def _decide(self, force: bool, resume: bool) -> Plan:
        out, partial, jdir = self.out, self.partial, self.journal_dir
        if out.exists() and not force:
            raise TableError(f"{out} exists; pass --force to overwrite it")
        _must_be_regular(out, "the output")
        _must_be_regular(partial, "the unfinished build's file")
        if jdir.exists() and not journal.owns(jdir):
            raise TableError(f"{jdir} exists and is not a journal lutmpi wrote (it holds other "
                             "files or is not a folder); lutmpi never replaces it: remove it")
        unfinished = jdir.exists() or partial.exists()
        if unfinished and not (resume or force):
            raise TableError(f"an unfinished build of {out} exists ({jdir.name}); pass --resume "
                             "to continue it or --force to start over")
        need = h5io.estimate_bytes(self.grid.n_points, len(self.methods))
        _check_directory(out.parent if str(out.parent) else Path("."), 2 * need)
        if resume and unfinished and not force:
            return self._verify_journal()
        return Plan(resume=False, done=None, run_id=journal.new_run_id())

    def _verify_journal(self) -> Plan:
        jdir = self.journal_dir
        if not jdir.exists():
            raise TableError(f"cannot resume {self.out}: {self.partial} has no journal "
                             f"{jdir.name}/ (written by an older lutmpi, or removed); pass --force "
                             "to start over")
        if not (jdir / journal.HEADER_NAME).exists() and not journal.record_files(jdir):
            log.info("the journal %s was never started (killed while creating it): starting "
                     "afresh", jdir)
            return Plan(resume=False, done=None, run_id=journal.new_run_id())
        header = journal.read_header(jdir)
        diffs = provenance.differences(header.inputs, self.inputs)
        if diffs:
            raise TableError(f"cannot resume {self.out}: its unfinished build was computed from "
                             f"other inputs: {'; '.join(diffs)}. Pass --force to recompute it "
                             "from the current inputs")
        wanted = journal.make_header(self.inputs, self.methods, self.fields, self.grid.shape)
        if (header.methods, header.quantities, header.shape, header.dtype) != (
                wanted.methods, wanted.quantities, wanted.shape, wanted.dtype):
            raise TableError(f"cannot resume {self.out}: its unfinished build holds methods "
                             f"{header.methods} and quantities {header.quantities}, this build "
                             f"asks for {wanted.methods} and {wanted.quantities}; pass --force "
                             "to start over")
        done, reports = journal.scan(jdir, self.dtype, self.inputs["sha256"], self.grid.n_points)
        for r in reports:
            if r.bad:
                log.warning("journal %s: %d damaged or torn stretch(es) skipped; their points "
                            "are computed again (%d good records kept)", r.path, r.bad, r.good)
        return Plan(resume=True, done=done, files=[r.path for r in reports],
                    run_id=journal.new_run_id())

    # -- 2. collective start ------------------------------------------------------------------
    def begin(self, plan: Plan, attrs: dict[str, Any]) -> np.ndarray:
        """Create the partial file (and a fresh journal); return the flat done mask."""
        comm = self.comm

        def fresh_journal() -> None:
            if not plan.resume:
                journal.remove(self.journal_dir)
                try:
                    journal.create(self.journal_dir, journal.make_header(
                        self.inputs, self.methods, self.fields, self.grid.shape))
                except OSError as exc:
                    raise self._file_error(f"creating the journal {self.journal_dir}",
                                           exc) from exc

        root_decides(comm, fresh_journal)
        try:
            h5io.create_partial(self.partial, self.io, comm.rank, self.grid, self.methods,
                                self.fields, attrs)
            st = os.stat(self.partial)
        except OSError as exc:
            raise self._file_error(f"creating {self.partial}", exc) from exc
        self._partial_id = (st.st_dev, st.st_ino)
        self._next_check = time.monotonic() + self.sync_interval_s
        self._journal = journal.JournalWriter(
            self.journal_dir, comm.rank, plan.run_id, self.dtype, self.inputs["sha256"],
            self.sync_interval_s)
        if not plan.resume or plan.done is None:
            return np.zeros(self.grid.n_points, dtype=bool)
        mine = [p for i, p in enumerate(plan.files) if i % comm.size == comm.rank]
        reused = np.zeros(self.grid.n_points, dtype=bool)
        for points, records in journal.iter_records(mine, self.dtype, self.inputs["sha256"],
                                                    self.grid.n_points, self.methods, self.fields):
            reused[points] = True
            self.pending.append((points, records))
        if not np.array_equal(comm.allreduce(reused.astype(np.int64)) > 0, plan.done):
            raise TableError(f"the journal {self.journal_dir} changed while being read")
        return plan.done

    # -- 3. during compute ---------------------------------------------------------------------
    def claim(self, n: int) -> tuple[Records, int]:
        """Rows for ``n`` points to be computed, in this rank's store (issue 14: no per-point
        records on the hot path): ``method -> name ->`` fill-valued arrays to fill in place from
        the returned row on (:func:`lutmpi.table.compute.compute_points`); :meth:`commit` then
        journals them. Claiming again before committing hands out the same rows."""
        if not self._store or self._store[-1][1] + n > len(self._store[-1][0]):
            chunk = journal.empty_rows(self.dtype, self.methods, self.fields,
                                       max(STORE_CHUNK, n))
            self._store.append((chunk, 0))
            self._views = {m: {f.name: chunk[f"{m}/{f.name}"] for f in self.fields}
                           for m in self.methods}
            self._bytes = chunk.view(np.uint8).reshape(len(chunk), chunk.dtype.itemsize)
        return self._views, self._store[-1][1]

    def reflect(self, src: int, dst: int, g: Any) -> None:
        """Row ``dst`` of the rows last claimed set to row ``src`` reflected by ``g`` (a
        :class:`~lutmpi.table.mirror.Reflection`): the whole row at once on its bytes
        (:func:`lutmpi.table.schema.row_reflection`, its plan kept per reflection), both row
        numbers as :meth:`claim` counts."""
        plan = self._reflections.get(g)
        if plan is None:
            plan = self._reflections[g] = row_reflection(self.dtype, g.sides, g.longitudinal)
        plan.apply_bytes(self._bytes, src, dst)

    def commit(self, points: np.ndarray) -> None:
        """Journal the ``len(points)`` rows last claimed, now filled, as ``points``' records
        (this rank only, no communication)."""
        if self._journal is None:
            raise TableError("TableWriter.commit called before begin")
        chunk, used = self._store[-1]
        rows = chunk[used:used + len(points)]
        rows["point"] = points
        self._journal.append_rows(rows)
        self._store[-1] = (chunk, used + len(points))
        # one rank looks (the folder is one for all): a removed folder is reported once
        if self.comm.rank == 0 and time.monotonic() >= self._next_check:
            self._next_check = time.monotonic() + self.sync_interval_s
            self.check_files()

    def check_files(self) -> None:
        """Raise :class:`~lutmpi.errors.TableError` when the output folder or ``OUT.partial``
        was removed or replaced since :meth:`begin` (two ``stat`` calls; any rank)."""
        why = self._removed()
        if why is not None:
            raise TableError(why)

    def _removed(self) -> str | None:
        """The message for this build's folder or partial file removed (or replaced) since
        :meth:`begin`, or ``None`` while they are in place."""
        folder = self.out.parent
        if not folder.is_dir():
            return (f"output folder {folder} was removed during the build, with the unfinished "
                    f"table {self.partial.name} and the journal {self.journal_dir.name}/: "
                    f"nothing was written to {self.out}; rerun the build")
        if self._partial_id is None:
            return None
        try:
            st = os.stat(self.partial)
        except FileNotFoundError:
            st = None
        except OSError:        # not a removal; the operation that needs the file says what
            return None
        if st is not None and (st.st_dev, st.st_ino) == self._partial_id:
            return None
        return (f"the unfinished table {self.partial} was "
                f"{'removed' if st is None else 'replaced'} during the build: nothing was "
                f"written to {self.out}; {self._what_now()}")

    def _file_error(self, what: str, exc: OSError) -> TableError:
        """The error for a failed file operation ``what`` of this build: a removed folder or
        partial file said so, anything else with the reason."""
        why = self._removed()
        if why is not None:
            return TableError(why)
        return TableError(f"{what} failed: {exc.strerror or exc}; nothing was written to "
                          f"{self.out}; {self._what_now()}")

    def _what_now(self) -> str:
        if self.journal_dir.is_dir():
            return (f"the points computed so far are kept in {self.journal_dir}: rerun with "
                    "--resume")
        return f"the journal {self.journal_dir} is gone: rerun the build"

    @property
    def journal_seconds(self) -> float:
        """Time this rank spent writing and syncing its journal, s."""
        return self._journal.seconds if self._journal is not None else 0.0

    # -- 4. collective end ---------------------------------------------------------------------
    def finish(self, run_attrs: dict[str, Any], after_grid: Any = None) -> None:
        """Write the table and make it appear at ``out`` (collective).

        ``after_grid(f, io, row_start, blocks)``, when given, runs on every rank once the grid
        is written and before ``complete`` is set (the post-build step: contact jumps)."""
        if self._journal is not None:
            self._journal.sync()      # every point is on disk before the table is written
            self._journal.close()
        root_decides(self.comm, self.check_files)   # one report, every rank raises it
        self._exchange()
        try:
            f = self.io.open(self.partial, "r+")
            h5io.write_blocks(f, self.io, self.row_start, self.blocks)
            if after_grid is not None:
                after_grid(f, self.io, self.row_start, self.blocks)
            h5io.finalize(f, run_attrs)
        except OSError as exc:
            raise self._file_error(f"writing {self.partial}", exc) from exc
        self.comm.Barrier()
        root_decides(self.comm, self._publish)

    def _publish(self) -> None:
        self.check_files()      # the jump step may have run long after the last look
        try:
            fd = os.open(self.partial, os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
            os.replace(self.partial, self.out)
        except OSError as exc:
            raise self._file_error(f"renaming {self.partial} to {self.out}", exc) from exc
        journal.fsync_dir(self.out.parent if str(self.out.parent) else Path("."))
        try:
            journal.remove(self.journal_dir)
        except (OSError, TableError) as exc:
            log.warning("the table is complete but its journal could not be removed: %s", exc)
        self._lock.release()

    def _exchange(self) -> None:
        """Send pending records to the ranks owning their rows; store what this rank receives."""
        comm, grid = self.comm, self.grid
        owners = partition.owner_of_rows(grid.shape[0], comm.size)
        outgoing: list[list[tuple[np.ndarray, Records]]] = [[] for _ in range(comm.size)]
        stored = [journal.to_records(chunk[:used], self.methods, self.fields)
                  for chunk, used in self._store]
        self._store, self._views = [], {}
        for points, records in self.pending + stored:
            dest = owners[points // grid.shape[1]]
            for rank in np.unique(dest):
                sel = dest == rank
                outgoing[rank].append((points[sel], {m: {k: v[sel] for k, v in r.items()}
                                                     for m, r in records.items()}))
        self.pending.clear()
        for batch in comm.alltoall(outgoing):
            for points, records in batch:
                iy, iyaw = np.divmod(points, grid.shape[1])
                rows = iy - self.row_start
                for m, rec in records.items():
                    for k, v in rec.items():
                        self.blocks[m][k][rows, iyaw] = v

    # -- 5. always -------------------------------------------------------------------------------
    def close(self) -> None:
        """Close this rank's journal and, on rank 0, release the lock (idempotent)."""
        if self._journal is not None:
            self._journal.close()
        self._lock.release()


def check_output_target(out: Path) -> None:
    """The output path itself is usable: not empty, not a folder, its folder exists."""
    if out.is_dir():
        raise TableError(f"{out} is a folder; give a file name inside it, e.g. {out / 'table.h5'}")
    for related in (lock_path(out),):
        if related.is_dir():
            raise TableError(f"{related} is a folder; lutmpi needs that name for the output's "
                             "lock: remove it")


def _must_be_regular(path: Path, what: str) -> None:
    if path.is_symlink() or (path.exists() and not path.is_file()):
        raise TableError(f"{path} ({what}) exists and is not a regular file; lutmpi never "
                         "replaces it, even with --force: remove it or choose another output")


def _check_directory(directory: Path, need_bytes: int) -> None:
    if not directory.is_dir():
        raise TableError(f"output directory {directory} does not exist or is not a directory")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise TableError(f"output directory {directory} is not writable")
    free = shutil.disk_usage(directory).free
    if need_bytes and free < need_bytes:
        raise TableError(f"output directory {directory} has {free / 1e6:.1f} MB free, the table "
                         f"and its journal need about {need_bytes / 1e6:.1f} MB")
