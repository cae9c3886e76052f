"""Splitting a global index range over ranks: pure arithmetic, unit-tested for every (n, size).

Two splits are used by the table build:

* the **compute split** deals the points still to do over the ranks (the default build hands them
  out dynamically instead, :mod:`lutmpi.parallel.workqueue`; these static splits remain
  selectable). Measured per-point costs of the solver (``benchmarks/table_build.py``,
  BENCHMARKS.md) are not smooth: most points cost a few ms, flange rows ~3x the tread rows and a
  few poses next to a contact jump 10-30x the median, and they come in mirror pairs
  (y, yaw) / (-y, -yaw). A plain
  cyclic deal of the row-major flat index puts both points of every mirror pair on the same rank
  when the grid has an odd number of points and 2 ranks (k and N-1-k have the same parity), the
  worst case; blocks depend on where the costly rows fall. The default, **scattered**, deals a
  fixed pseudo-random permutation cyclically: counts balanced to one point, and the costly points
  spread independently of the grid's symmetry. ``cyclic`` and ``block`` remain selectable.
* the **write split** is in *blocks of rows* (:func:`block_range` over ``ny``): every rank owns a
  contiguous hyperslab of the file and writes it collectively.

No mpi4py here.
"""

from __future__ import annotations

import numpy as np

SPLITS = ("scattered", "cyclic", "block")
#: fixed seed of the scattered split: the split is part of no result, but keep runs reproducible
SCATTER_SEED = 20110101


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


def scattered_indices(n: int, size: int, rank: int, seed: int = SCATTER_SEED) -> np.ndarray:
    """Cyclic deal of a fixed pseudo-random permutation of ``range(n)``; sorted, int64.

    Counts per rank are those of :func:`cyclic_indices` (balanced to one item); which items a rank
    gets is decorrelated from the grid's structure (see the module docstring).
    """
    cyclic = cyclic_indices(n, size, rank)
    return np.sort(np.random.default_rng(seed).permutation(n)[cyclic]).astype(np.int64)


def split(n: int, size: int, rank: int, how: str = "scattered") -> np.ndarray:
    """Positions in ``range(n)`` handled by ``rank`` with the split ``how`` (see :data:`SPLITS`)."""
    if how == "scattered":
        return scattered_indices(n, size, rank)
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
