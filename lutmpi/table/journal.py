"""The journal of an unfinished build: every computed point on disk the moment it is computed.

``<out>.journal/`` holds ``inputs.json`` (what the build is computed from, its methods, quantities,
grid shape and record layout; written once, atomically) and one append-only file per rank and run,
``rank-<k>-<run>.jnl``. Each rank appends one record per batch of points with a single ``write``
(so a ``kill -9`` at any moment loses at most the record being written) and ``fsync``\\ s at most
every ``sync_interval_s`` and before the table is written (so a power cut loses at most that much).
No rank waits for another; the HDF5 file is never the only place a result lives.

A record is ``MAGIC | n points | payload bytes | digest | payload``; the payload is a structured
array (the point's flat index and every field of every method, little-endian) and the digest a
BLAKE2b-128 keyed with the build's input hash, so a torn tail, a flipped bit, a doctored value or a
record from a build of other inputs fails the check. The reader resynchronises on the magic after
a bad record and keeps every record that passes; only those points are reused on resume.

No MPI, no HDF5.
"""

from __future__ import annotations

import functools
import hashlib
import json
import logging
import os
import struct
import time
import uuid
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from lutmpi.errors import TableError
from lutmpi.table.schema import Field

log = logging.getLogger(__name__)

FORMAT = 1
MAGIC = b"LUTJREC1"
_HEAD = struct.Struct("<8sII16s")        # magic, n points, payload bytes, digest
HEADER_NAME = "inputs.json"
SUFFIX = ".jnl"

Records = dict[str, dict[str, np.ndarray]]


def journal_dir(out: str | os.PathLike[str]) -> Path:
    """The journal folder of ``out``: ``<out>.journal``."""
    out = Path(out)
    return out.with_name(out.name + ".journal")


def record_dtype(methods: Sequence[str], fields: Sequence[Field]) -> np.dtype:
    """Layout of one journaled point: its flat index and every field of every method."""
    parts: list[tuple[Any, ...]] = [("point", "<i8")]
    for m in methods:
        for f in fields:
            parts.append((f"{m}/{f.name}", np.dtype(f.dtype).newbyteorder("<"), f.suffix))
    return np.dtype(parts)


def owns(directory: Path) -> bool:
    """True when ``directory`` holds nothing but journal files (it may be removed)."""
    try:
        return directory.is_dir() and not directory.is_symlink() and all(
            p.is_file() and not p.is_symlink()
            and (p.name == HEADER_NAME or p.name.endswith((SUFFIX, ".tmp")))
            for p in directory.iterdir())
    except OSError:
        return False


def remove(directory: Path) -> None:
    """Remove a journal folder this build owns (nothing else in it is touched)."""
    if not directory.exists():
        return
    if not owns(directory):
        raise TableError(f"{directory} holds files lutmpi did not write; remove it yourself")
    for p in directory.iterdir():
        p.unlink()
    directory.rmdir()


@dataclass(frozen=True)
class Header:
    """``inputs.json``: what the journaled records were computed from."""

    inputs: dict[str, Any]
    methods: list[str]
    quantities: list[str]
    shape: list[int]
    dtype: str

    def to_json(self) -> str:
        return json.dumps({"format": FORMAT, "inputs": self.inputs, "methods": self.methods,
                           "quantities": self.quantities, "shape": self.shape,
                           "dtype": self.dtype}, indent=1)


def make_header(inputs: dict[str, Any], methods: Sequence[str], fields: Sequence[Field],
                shape: tuple[int, int]) -> Header:
    return Header(inputs, list(methods), [f.name for f in fields], list(shape),
                  str(record_dtype(methods, fields).descr))


def create(directory: Path, header: Header) -> None:
    """Make the journal folder and write its header atomically (one process)."""
    directory.mkdir()
    tmp = directory / (HEADER_NAME + ".tmp")
    with open(tmp, "w") as fh:
        fh.write(header.to_json())
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, directory / HEADER_NAME)
    fsync_dir(directory)
    fsync_dir(directory.parent)


def read_header(directory: Path) -> Header:
    """The header of an existing journal.

    Raises
    ------
    TableError
        Missing or unreadable header (names the file).
    """
    path = directory / HEADER_NAME
    try:
        data = json.loads(path.read_text())
        if data.get("format") != FORMAT:
            raise ValueError(f"format {data.get('format')!r}, expected {FORMAT}")
        return Header(data["inputs"], data["methods"], data["quantities"], data["shape"],
                      data["dtype"])
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise TableError(f"the journal header {path} cannot be read ({exc}); pass --force to "
                         "start over") from exc


def record_files(directory: Path) -> list[Path]:
    """Every rank file of a journal, in a fixed order."""
    return sorted(p for p in directory.iterdir() if p.name.endswith(SUFFIX))


def _key(inputs_sha256: str) -> bytes:
    return hashlib.sha256(("lutmpi-journal:" + inputs_sha256).encode()).digest()


def _digest(key: bytes, payload: bytes) -> bytes:
    return hashlib.blake2b(payload, digest_size=16, key=key).digest()


@dataclass
class ScanReport:
    """What a read of one journal file found."""

    path: Path
    good: int = 0            # records that passed
    bad: int = 0             # records (or stretches of bytes) that failed and were skipped


def read_records(path: Path, dtype: np.dtype, inputs_sha256: str,
                 n_points: int) -> tuple[list[np.ndarray], ScanReport]:
    """Every record of one journal file that passes its checks, as structured arrays.

    A record is kept when its header is complete, its length matches ``dtype``, its digest
    matches, and its point indices are in ``range(n_points)``. Anything else is skipped
    (counted in ``bad``) and the reader resynchronises on the next magic.
    """
    key = _key(inputs_sha256)
    data = path.read_bytes()
    report, out, pos = ScanReport(path), [], 0
    while pos < len(data):
        start = data.find(MAGIC, pos)
        if start != pos:
            report.bad += 1            # bytes that are no record (a torn tail, an overwrite)
            if start < 0:
                break
        arr = _parse(data, start, dtype, key, n_points)
        if arr is None:
            report.bad += 1
            nxt = data.find(MAGIC, start + 1)
            pos = len(data) if nxt < 0 else nxt
            continue
        out.append(arr)
        report.good += 1
        pos = start + _HEAD.size + arr.nbytes
    return out, report


def _parse(data: bytes, start: int, dtype: np.dtype, key: bytes,
           n_points: int) -> np.ndarray | None:
    if start + _HEAD.size > len(data):
        return None
    _, n, nbytes, digest = _HEAD.unpack_from(data, start)
    end = start + _HEAD.size + nbytes
    if nbytes != n * dtype.itemsize or n == 0 or end > len(data):
        return None
    payload = data[start + _HEAD.size:end]
    if _digest(key, payload) != digest:
        return None
    arr = np.frombuffer(payload, dtype=dtype)
    if arr["point"].min() < 0 or arr["point"].max() >= n_points:
        return None
    return arr


def scan(directory: Path, dtype: np.dtype, inputs_sha256: str,
         n_points: int) -> tuple[np.ndarray, list[ScanReport]]:
    """The flat indices of every verified point of a journal, and a report per file."""
    done = np.zeros(n_points, dtype=bool)
    reports = []
    for path in record_files(directory):
        arrays, report = read_records(path, dtype, inputs_sha256, n_points)
        for arr in arrays:
            done[arr["point"]] = True
        reports.append(report)
    return done, reports


def done_points(directory: Path) -> np.ndarray:
    """The flat indices of every verified point of an existing journal (for tools and tests)."""
    from lutmpi.table.schema import FIELDS

    header = read_header(directory)
    by_name = {f.name: f for f in FIELDS}
    fields = [by_name[n] for n in header.quantities]
    dtype = record_dtype(header.methods, fields)
    done, _ = scan(directory, dtype, header.inputs["sha256"], int(np.prod(header.shape)))
    return np.flatnonzero(done)


def empty_rows(dtype: np.dtype, methods: Sequence[str], fields: Sequence[Field],
               n: int) -> np.ndarray:
    """``n`` rows of the record's layout (:func:`record_dtype`), every field at its fill value
    (:meth:`Field.empty`) and ``point`` at -1: a store that a build fills in place and journals
    as it is (:meth:`JournalWriter.append_rows`)."""
    rows = np.empty(n, dtype=dtype)
    rows[:] = _fill_row(dtype, tuple(methods), tuple(fields))
    return rows


@functools.lru_cache(maxsize=16)
def _fill_row(dtype: np.dtype, methods: tuple[str, ...], fields: tuple[Field, ...]) -> np.ndarray:
    row = np.zeros((), dtype=dtype)
    row["point"] = -1
    for m in methods:
        for f in fields:
            row[f"{m}/{f.name}"] = f.empty(())
    return row


def to_records(arr: np.ndarray, methods: Sequence[str],
               fields: Sequence[Field]) -> tuple[np.ndarray, Records]:
    """A structured journal array -> ``(points, method -> field -> array)`` in native dtypes."""
    points = arr["point"].astype(np.int64)
    recs = {m: {f.name: arr[f"{m}/{f.name}"].astype(f.dtype) for f in fields} for m in methods}
    return points, recs


def iter_records(files: Sequence[Path], dtype: np.dtype, inputs_sha256: str, n_points: int,
                 methods: Sequence[str], fields: Sequence[Field]) -> Iterator[tuple[np.ndarray,
                                                                                    Records]]:
    """Every verified record of ``files`` as ``(points, records)``."""
    for path in files:
        arrays, _ = read_records(path, dtype, inputs_sha256, n_points)
        for arr in arrays:
            yield to_records(arr, methods, fields)


class JournalWriter:
    """One rank's append-only journal file of this run."""

    def __init__(self, directory: Path, rank: int, run_id: str, dtype: np.dtype,
                 inputs_sha256: str, sync_interval_s: float):
        self.path = directory / f"rank-{rank:05d}-{run_id}{SUFFIX}"
        self.dtype = dtype
        self._key = _key(inputs_sha256)
        self.sync_interval_s = sync_interval_s
        self._last_sync = time.monotonic()
        self._dirty = False
        self.bytes_written = 0
        self.seconds = 0.0            # time spent writing and syncing (BENCHMARKS.md)
        try:
            self._fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_APPEND | os.O_CLOEXEC,
                               0o644)
        except OSError as exc:
            raise _write_error(self.path, exc) from exc

    def append_rows(self, rows: np.ndarray) -> None:
        """Write rows in the record's layout (``dtype``, ``point`` set; a build's store,
        :func:`empty_rows`) as one record, their bytes as they are (one ``write``); sync when
        the interval has passed."""
        t0 = time.perf_counter()
        if rows.dtype != self.dtype or rows.ndim != 1:
            raise TypeError(f"journal rows must be a 1-D array of the record's dtype, got "
                            f"{rows.dtype} with shape {rows.shape}")
        payload = rows.tobytes()
        blob = _HEAD.pack(MAGIC, len(rows), len(payload), _digest(self._key, payload)) + payload
        try:
            view = memoryview(blob)
            while view:
                view = view[os.write(self._fd, view):]
        except OSError as exc:
            raise _write_error(self.path, exc) from exc
        self.bytes_written += len(blob)
        self._dirty = True
        if time.monotonic() - self._last_sync >= self.sync_interval_s:
            self.sync()
        self.seconds += time.perf_counter() - t0

    def sync(self) -> None:
        """``fsync`` what was written (raises the write error of any earlier ``write``)."""
        if self._dirty:
            try:
                os.fsync(self._fd)
            except OSError as exc:
                raise _write_error(self.path, exc) from exc
            self._dirty = False
        self._last_sync = time.monotonic()

    def close(self) -> None:
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1


def _write_error(path: Path, exc: OSError) -> TableError:
    return TableError(f"writing the journal {path} failed: {exc.strerror or exc}; the points "
                      "journaled so far are kept: make room and rerun with --resume")


def new_run_id() -> str:
    """A name part unique to one run of a build (time-ordered)."""
    return time.strftime("%Y%m%dT%H%M%S", time.gmtime()) + "-" + uuid.uuid4().hex[:8]


def fsync_dir(directory: Path) -> None:
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
