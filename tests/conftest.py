"""Shared fixtures, and the guard that ends an MPI job as soon as one rank fails a test.

mpi4py is imported only under ``mpirun`` and only when an MPI test has failed, so the serial tier
never initialises MPI.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

import pytest

import lutmpi


def _worker_kernel_cache() -> None:
    """Under pytest-xdist (``scripts/test.sh`` runs the serial tier on two workers), point this
    worker, and every process its tests start, at its own copy of the kernels' cache folder.

    The setup fills one folder (``lutmpi.NUMBA_CACHE_DIR``); tests then compile kernels the
    warm-up does not reach (the table lookup's, ~60 cache files a run), and two processes
    saving overloads of one function into one folder at once can overwrite each other's data
    files, which numba does not guard against (:func:`lutmpi.warmup.kernels_ready`). Each
    worker copies the warmed folder once (~15 MB) to ``<root>/xdist-<worker>/`` and works
    there; the root reaches child processes through ``LUTMPI_NUMBA_CACHE_ROOT``."""
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    if not worker:
        return
    from lutmpi.warmup import READY_NAME

    shared = Path(lutmpi.NUMBA_CACHE_DIR)
    os.environ["LUTMPI_NUMBA_CACHE_ROOT"] = str(shared.parent / f"xdist-{worker}")
    lutmpi.NUMBA_CACHE_DIR = lutmpi._key_numba_cache()   # makes the (empty) folder
    own = Path(lutmpi.NUMBA_CACHE_DIR)
    # copied once per worker and sources; an unwarmed folder is not copied (each worker then
    # compiles into its own)
    if (shared / READY_NAME).is_file() and not (own / READY_NAME).is_file():
        shutil.copytree(shared, own, dirs_exist_ok=True)


_worker_kernel_cache()

from lutmpi.parallel.mpi import launched_rank_size  # noqa: E402  (after the cache is chosen)
from lutmpi.paths import REPO_ROOT  # noqa: E402
from lutmpi.paths import shared_dir as _shared_dir  # noqa: E402


def mpi_world_size() -> int:
    """Size of the MPI job this process belongs to, from the launcher's environment (1 if none)."""
    return (launched_rank_size() or (0, 1))[1]


def mpi_world_rank() -> int:
    """Rank of this process, from the launcher's environment (0 if not under mpirun)."""
    return (launched_rank_size() or (0, 1))[0]


@pytest.fixture(scope="session")
def repo_root() -> Path:
    """The repository root (where ``configs/``, ``profiles/``, ``scripts/`` are)."""
    return REPO_ROOT


@pytest.fixture(scope="session")
def shared_dir() -> Path:
    """The ``shared/`` folder (paper, reference profiles); the test is skipped when it is absent."""
    path = _shared_dir()
    if path is None:
        pytest.skip("shared/ not found (set LUTMPI_SHARED, or put shared/ beside the repository)")
    return path


MPI_TEST_DIR = Path(__file__).resolve().parent / "mpi"


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark every test under ``tests/mpi/`` with ``mpi``.

    pytest-mpi already treats them as MPI tests (it looks the name up in ``item.keywords``, which
    includes the directory name), so the marker makes ``-m "not mpi"`` and the abort guard agree.
    """
    for item in items:
        if MPI_TEST_DIR in Path(str(item.path)).resolve().parents \
                and item.get_closest_marker("mpi") is None:
            item.add_marker(pytest.mark.mpi)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo) -> pytest.TestReport:
    """Abort the whole MPI job when an ``mpi`` test fails on any rank of a job with size > 1.

    Otherwise the failing rank moves on to the next test while the others wait in a collective
    call for it, and the job hangs until a timeout.
    """
    report = yield
    if report.failed and item.get_closest_marker("mpi") is not None and mpi_world_size() > 1:
        _abort_job(item, report)
    return report


def _abort_job(item: pytest.Item, report: pytest.TestReport) -> None:
    rank, size = mpi_world_rank(), mpi_world_size()
    stream = sys.__stderr__
    stream.write(f"\n[rank {rank}/{size}] FAILED {item.nodeid} ({report.when}); "
                 "calling MPI.COMM_WORLD.Abort(1) so no rank is left waiting\n")
    stream.write(report.longreprtext + "\n")
    stream.flush()
    sys.stdout.flush()
    from mpi4py import MPI

    MPI.COMM_WORLD.Abort(1)
