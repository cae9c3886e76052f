"""Communicator helpers shared by the build and the sweep: the one-process communicator and
"rank 0 decides, then every rank returns its value or raises its exception" (STYLE 7)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


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

    def Abort(self, code: int = 1) -> None:  # noqa: N802 - mpi4py's name
        raise SystemExit(code)


def root_decides(comm: Any, fn: Callable[[], Any]) -> Any:
    """Run ``fn`` on rank 0 and broadcast its value or its exception; every rank returns/raises.

    No rank is left waiting: the broadcast happens whatever ``fn`` did.
    """
    value, error = None, None
    if comm.rank == 0:
        try:
            value = fn()
        except Exception as exc:  # broadcast, then every rank raises the same
            error = exc
    value, error = comm.bcast((value, error), root=0)
    if error is not None:
        if comm.rank != 0:     # this rank's copy of rank 0's error: see raised_on_root
            error.lutmpi_raised_on_root = True
        raise error
    return value


def raised_on_root(exc: BaseException) -> bool:
    """Whether ``exc`` is rank 0's exception raised again on this (another) rank by
    :func:`root_decides`: rank 0 raises the same one and can report it for every rank."""
    return bool(getattr(exc, "lutmpi_raised_on_root", False))
