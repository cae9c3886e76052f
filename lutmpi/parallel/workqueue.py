"""Dynamic hand-out of work items: a shared counter every rank advances atomically (MPI RMA).

Why not a master rank with send/recv: the master would either idle (one rank of two wasted on a
2-core node) or compute too, and then answer requests only between two of its own solves (a
solve can take 100 s). With passive-target one-sided atomics (``MPI_Fetch_and_op`` on a window
held by rank 0) a rank takes the next item without rank 0 doing anything: there is no message
protocol, no tags, and no rank ever waits for another until all items are taken.

On one node Open MPI serves the window from shared memory (checked: rank 0 sleeping in a 1 s
"solve" does not delay the others). Across nodes, hardware atomics (UCX/verbs) do the same; a
transport without them progresses the requests when rank 0 next calls MPI, which delays the others
by at most one of rank 0's solves. ``lutmpi build --split cyclic`` avoids the window altogether.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class LocalCounter:
    """The counter of a single process."""

    def __init__(self) -> None:
        self._next = 0

    def next(self) -> int:
        """The next item index (0, 1, 2, ...)."""
        value = self._next
        self._next += 1
        return value

    def free(self) -> None:
        pass


class SharedCounter:
    """A counter on rank 0 advanced atomically by every rank. Creation and :meth:`free` are
    collective; :meth:`next` is not (each call is one ``MPI_Fetch_and_op``)."""

    def __init__(self, comm: Any) -> None:
        from mpi4py import MPI

        self._mpi = MPI
        self._win = MPI.Win.Allocate(8 if comm.rank == 0 else 0, 8, comm=comm)
        if comm.rank == 0:
            self._win.Lock(0, MPI.LOCK_EXCLUSIVE)
            np.frombuffer(self._win.tomemory(), dtype=np.int64)[:] = 0
            self._win.Unlock(0)
        comm.Barrier()  # nobody fetches before the counter is zeroed
        self._one = np.ones(1, dtype=np.int64)
        self._got = np.zeros(1, dtype=np.int64)

    def next(self) -> int:
        """Fetch-and-increment: the index of this rank's next item."""
        mpi = self._mpi
        self._win.Lock(0, mpi.LOCK_SHARED)
        self._win.Fetch_and_op(self._one, self._got, 0, op=mpi.SUM)
        self._win.Unlock(0)
        return int(self._got[0])

    def free(self) -> None:
        """Release the window (collective)."""
        self._win.Free()


def make_counter(comm: Any) -> LocalCounter | SharedCounter:
    """A shared counter for an MPI communicator of size > 1, else a local one."""
    return SharedCounter(comm) if getattr(comm, "size", 1) > 1 else LocalCounter()
