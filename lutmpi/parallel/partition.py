"""Splitting a global index range over ranks: pure arithmetic, unit-tested for every (n, size).

Two splits are used by the table build:

* the **compute split** is *cyclic* over the flat point list (point ``k`` of the work list goes to
  rank ``k % size``). Flange points (large ``|y|``) cost several times a tread point and sit in
  whole rows of the grid; a cyclic deal gives every rank the same mix of rows, so the work is
  balanced to within one point whatever the cost profile across rows (see BENCHMARKS.md).
* the **write split** is in *blocks of rows* (:func:`block_range` over ``ny``): every rank owns a
  contiguous hyperslab of the file and writes it collectively.

No mpi4py here.
"""

from __future__ import annotations

import numpy as np

SPLITS = ("cyclic", "block")


def block_range(n: int, size: int, rank: int) -> tuple[int, int]:
    """Contiguous share of ``range(n)`` for ``rank`` of ``size``: ``(start, count)``.

    The first ``n % size`` ranks get one item more; ranks beyond ``n`` get ``count == 0``.
    """
    if size < 1 or not 0 <= rank < size or n < 0:
        raise ValueError(f"need n >= 0, size >= 1, 0 <= rank < size; got {n=}, {size=}, {rank=}")
    base, extra = divmod(n, size)
    start = rank * base + min(rank, extra)
    return start, base + (1 if rank < extra else 0)


def cyclic_indices(n: int, size: int, rank: int) -> np.ndarray:
    """Indices ``rank, rank + size, rank + 2 size, ... < n`` (int64, possibly empty)."""
    if size < 1 or not 0 <= rank < size or n < 0:
        raise ValueError(f"need n >= 0, size >= 1, 0 <= rank < size; got {n=}, {size=}, {rank=}")
    return np.arange(rank, n, size, dtype=np.int64)


def split(n: int, size: int, rank: int, how: str = "cyclic") -> np.ndarray:
    """Positions in ``range(n)`` handled by ``rank`` with the split ``how`` (see :data:`SPLITS`)."""
    if how == "cyclic":
        return cyclic_indices(n, size, rank)
    if how == "block":
        start, count = block_range(n, size, rank)
        return np.arange(start, start + count, dtype=np.int64)
    raise ValueError(f"unknown split {how!r}; valid: {', '.join(SPLITS)}")


def owner_of_rows(ny: int, size: int) -> np.ndarray:
    """Rank owning each row under the write split: array of shape ``(ny,)``."""
    owners = np.empty(ny, dtype=np.int64)
    for rank in range(size):
        start, count = block_range(ny, size, rank)
        owners[start:start + count] = rank
    return owners
