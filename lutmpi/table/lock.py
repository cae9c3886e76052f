"""An exclusive lock on a table's output path, held for the whole build: ``<out>.lock``.

``flock(LOCK_EX | LOCK_NB)`` on a lock file beside the output, which records the holder (pid, host,
start time). A second writer is refused at once with a message naming the holder. The kernel drops
the lock when the holder dies, even by ``kill -9``, so a stale lock file never blocks a resume.
The file is removed on release; an acquirer checks that the file it locked is still the one at the
path (a releaser may have removed it meanwhile) and retries otherwise.
"""

from __future__ import annotations

import fcntl
import json
import os
import socket
from datetime import UTC, datetime
from pathlib import Path

from lutmpi.errors import TableError


def lock_path(out: str | os.PathLike[str]) -> Path:
    """The lock file of ``out``: ``<out>.lock``."""
    out = Path(out)
    return out.with_name(out.name + ".lock")


class OutputLock:
    """The lock of one output path (acquire on one process only: rank 0)."""

    def __init__(self, out: str | os.PathLike[str]):
        self.out = Path(out)
        self.path = lock_path(out)
        self._fd: int | None = None

    def acquire(self) -> None:
        """Take the lock or raise at once.

        Raises
        ------
        TableError
            Another process holds it (named), or the lock file cannot be created.
        """
        for _ in range(10):
            fd = self._open()
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                holder = _read_holder(fd)
                os.close(fd)
                raise TableError(f"{self.out} is being written by another lutmpi build "
                                 f"({holder}; lock {self.path}); wait for it to finish or stop "
                                 "it first") from None
            if _same_file(fd, self.path):
                self._fd = fd
                self._record()
                return
            os.close(fd)              # removed by a releaser between open and lock: try again
        raise TableError(f"cannot take the lock {self.path}: it keeps being replaced")

    def _open(self) -> int:
        if self.path.is_symlink() or (self.path.exists() and not self.path.is_file()):
            raise TableError(f"{self.path} exists and is not a regular file; lutmpi uses that "
                             "name as the lock of the output: remove it")
        try:
            return os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except OSError as exc:
            raise TableError(f"output directory {self.path.parent} is not writable: cannot "
                             f"create the lock file {self.path.name} ({exc.strerror or exc})"
                             ) from exc

    def _record(self) -> None:
        info = {"pid": os.getpid(), "host": socket.gethostname(),
                "since_utc": datetime.now(UTC).isoformat(timespec="seconds")}
        data = (json.dumps(info) + "\n").encode()
        if self._fd is None:
            return
        os.ftruncate(self._fd, 0)
        os.pwrite(self._fd, data, 0)

    def release(self) -> None:
        """Remove the lock file and drop the lock (idempotent)."""
        if self._fd is None:
            return
        try:
            if _same_file(self._fd, self.path):
                self.path.unlink()
        except OSError:
            pass
        os.close(self._fd)
        self._fd = None

    @property
    def held(self) -> bool:
        return self._fd is not None


def _same_file(fd: int, path: Path) -> bool:
    try:
        a, b = os.fstat(fd), os.stat(path)
    except OSError:
        return False
    return (a.st_dev, a.st_ino) == (b.st_dev, b.st_ino)


def _read_holder(fd: int) -> str:
    try:
        info = json.loads(os.pread(fd, 4096, 0).decode() or "{}")
        return f"pid {info['pid']} on host {info['host']} since {info['since_utc']}"
    except (OSError, ValueError, KeyError, TypeError):
        return "holder unknown"
