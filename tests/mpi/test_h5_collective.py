"""Parallel HDF5 smoke test (issue 2): every rank writes its own slab of one dataset collectively,
one rank with zero rows still taking part, then the file is read back and every value checked.

Run with ``mpirun -n 2`` and ``mpirun -n 4`` (oversubscribed) via ``scripts/test.sh``.

Why the zero-row rank needs the low-level call: h5py's high-level ``dset[a:a] = empty`` and
``dset[a:a]`` return without calling ``H5Dwrite``/``H5Dread`` at all, so in collective mode the
other ranks wait for it forever (checked with h5py 3.16 / HDF5 1.10.8: the job hangs). Its
high-level read ignores ``dset.collective`` altogether (fast path), so reads are low level here.
"""

from __future__ import annotations

import numpy as np
import pytest

pytestmark = [pytest.mark.mpi(min_size=2), pytest.mark.timeout(60)]

NCOL = 3


def _row_counts(size: int) -> list[int]:
    """Uneven rows per rank; the last rank has none."""
    return [r + 3 for r in range(size - 1)] + [0]


def _expected(rows: np.ndarray) -> np.ndarray:
    return 1000.0 * rows[:, None] + np.arange(NCOL)[None, :] + 0.25


def _collective_xfer():
    import h5py

    dxpl = h5py.h5p.create(h5py.h5p.DATASET_XFER)
    dxpl.set_dxpl_mpio(h5py.h5fd.MPIO_COLLECTIVE)
    return dxpl


def _empty_spaces(dset):
    """File and memory dataspaces that select nothing, plus a dummy buffer for them."""
    import h5py

    fspace = dset.id.get_space()
    fspace.select_none()
    mspace = h5py.h5s.create_simple((1,) + dset.shape[1:])
    mspace.select_none()
    return fspace, mspace, np.zeros((1,) + dset.shape[1:], dtype=dset.dtype)


def write_rows_collective(dset, start: int, block: np.ndarray) -> None:
    """Write ``block`` to rows ``start:start+len(block)`` in one collective call, even if empty."""
    block = np.ascontiguousarray(block, dtype=dset.dtype)
    if block.shape[0] == 0:
        fspace, mspace, buf = _empty_spaces(dset)
        dset.id.write(mspace, fspace, buf, dxpl=_collective_xfer())
        return
    with dset.collective:
        dset[start:start + block.shape[0]] = block


def read_rows_collective(dset, start: int, count: int) -> np.ndarray:
    """Read rows ``start:start+count`` in one collective call, even if ``count`` is 0.

    Low level on every rank: h5py's high-level read takes a fast path that ignores the
    ``dset.collective`` transfer list, so it would not meet the others' collective ``H5Dread``.
    """
    if count == 0:
        fspace, mspace, buf = _empty_spaces(dset)
        dset.id.read(mspace, fspace, buf, dxpl=_collective_xfer())
        return np.empty((0,) + dset.shape[1:], dtype=dset.dtype)
    import h5py

    out = np.empty((count,) + dset.shape[1:], dtype=dset.dtype)
    fspace = dset.id.get_space()
    fspace.select_hyperslab((start,) + (0,) * (dset.ndim - 1), out.shape)
    dset.id.read(h5py.h5s.create_simple(out.shape), fspace, out, dxpl=_collective_xfer())
    return out


def test_collective_slab_write_with_an_empty_rank_reads_back(mpi_tmp_path):
    import h5py
    from mpi4py import MPI

    from lutmpi.parallel.mpi import require_parallel_h5py

    require_parallel_h5py()
    comm = MPI.COMM_WORLD
    rank, size = comm.rank, comm.size
    counts = _row_counts(size)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(int)
    nrows = int(sum(counts))
    start, count = int(starts[rank]), counts[rank]
    mine = np.arange(start, start + count)
    path = mpi_tmp_path / "collective.h5"

    with h5py.File(path, "w", driver="mpio", comm=comm) as f:
        # every rank creates every dataset with its global shape (a collective metadata operation)
        values = f.create_dataset("values", shape=(nrows, NCOL), dtype="f8", fillvalue=np.nan)
        writer = f.create_dataset("writer", shape=(nrows,), dtype="i4", fillvalue=-1)
        write_rows_collective(values, start, _expected(mine))
        write_rows_collective(writer, start, np.full(count, rank))
    comm.Barrier()

    with h5py.File(path, "r", driver="mpio", comm=comm) as f:
        assert f["values"].shape == (nrows, NCOL)
        slab = read_rows_collective(f["values"], start, count)
        np.testing.assert_array_equal(slab, _expected(mine))
        everything = f["values"][...]
        owners = f["writer"][...]
    np.testing.assert_array_equal(everything, _expected(np.arange(nrows)))
    np.testing.assert_array_equal(owners, np.repeat(np.arange(size), counts))

    # a serial reader sees the same file once the parallel handles are closed
    comm.Barrier()
    if rank == 0:
        with h5py.File(path, "r") as f:
            np.testing.assert_array_equal(f["values"][...], everything)
