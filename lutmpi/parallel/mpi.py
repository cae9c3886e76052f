"""The MPI environment: the communicator, the parallel-HDF5 check, and what ``mpirun`` needs here.

Nothing here binds a communicator at import time and mpi4py is imported only when asked for, so
importing this module never initialises MPI. The Open MPI settings (run as root, oversubscribe,
shared-memory transport) live in one file, ``lutmpi/parallel/mpi.env``, which ``scripts/mpienv.sh``
reads too.

``python -m lutmpi.parallel.mpi`` (under ``mpirun`` or not) is a self-check: every rank reports,
then all ranks write one HDF5 dataset collectively and read it back.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from lutmpi.errors import MPIUnavailableError

ENV_FILE = Path(__file__).with_name("mpi.env")
#: (rank, size) variables set by the launchers: Open MPI's mpirun, Hydra/PMI-2, PMIx, Slurm's srun
_LAUNCHER_VARS = (("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"), ("PMI_RANK", "PMI_SIZE"),
                  ("PMIX_RANK", None), ("SLURM_PROCID", "SLURM_NTASKS"))


def launched_rank_size(environ: Mapping[str, str] | None = None) -> tuple[int, int] | None:
    """THE answer to "am I under mpirun/srun?": ``(rank, size)`` from the launcher's environment,
    or ``None`` when no launcher started this process. Reads the environment only (importing
    mpi4py would initialise MPI); a launcher that gives no size counts as size 1 here."""
    env = os.environ if environ is None else environ
    for rank_var, size_var in _LAUNCHER_VARS:
        if rank_var in env:
            try:
                return int(env[rank_var]), int(env.get(size_var or "", "1") or 1)
            except ValueError:
                continue
    return None


def command_comm() -> Any:
    """The communicator a command runs on: ``MPI.COMM_WORLD`` under a launcher with more than one
    rank (parallel h5py required), else ``None`` (one process, no MPI)."""
    if launched_rank_size() is None:
        return None
    comm = get_comm()
    if comm.size <= 1:
        return None
    require_parallel_h5py()   # fail early and clearly, on every rank alike
    return comm


def get_comm() -> Any:
    """Return ``MPI.COMM_WORLD``, importing mpi4py (and so initialising MPI) only now.

    Returns
    -------
    mpi4py.MPI.Intracomm
        The world communicator.

    Raises
    ------
    MPIUnavailableError
        If mpi4py cannot be imported (not installed, or no MPI library found).
    """
    try:
        from mpi4py import MPI
    except ImportError as exc:  # pragma: no cover - depends on the installation
        raise MPIUnavailableError(
            f"mpi4py cannot be imported ({exc}); run scripts/setup.sh to install Open MPI "
            "and mpi4py") from exc
    return MPI.COMM_WORLD


def require_parallel_h5py() -> None:
    """Fail early and clearly unless h5py was built against parallel HDF5.

    Raises
    ------
    MPIUnavailableError
        If h5py is missing or ``h5py.get_config().mpi`` is false (e.g. a serial PyPI wheel).
    """
    try:
        import h5py
    except ImportError as exc:
        raise MPIUnavailableError(
            f"h5py cannot be imported ({exc}); run scripts/setup.sh") from exc
    if not h5py.get_config().mpi:
        raise MPIUnavailableError(
            f"h5py {h5py.__version__} was built without MPI support (h5py.get_config().mpi is "
            "False), so driver='mpio' is unavailable. Rebuild it against Debian's parallel HDF5 "
            "with scripts/setup.sh (it builds h5py from source with HDF5_MPI=ON).")


def parse_env_file(text: str, source: str = "<string>") -> dict[str, str]:
    """Parse ``KEY=VALUE`` lines (blank lines and ``#`` comment lines ignored).

    Parameters
    ----------
    text : str
        File contents.
    source : str
        Name used in error messages.

    Returns
    -------
    dict of str to str
        The variables, in file order.

    Raises
    ------
    ValueError
        On a line without ``=``, with an empty key, or with whitespace (unreadable by the shell).
    """
    env: dict[str, str] = {}
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        key, sep, value = line.partition("=")
        if not sep or not key or any(c.isspace() for c in line):
            raise ValueError(f"{source}:{lineno}: expected KEY=VALUE without spaces, got {raw!r}")
        env[key] = value
    return env


def mpirun_env(base: Mapping[str, str] | None = None) -> dict[str, str]:
    """Environment for launching ``mpirun`` from Python (tests, benchmarks).

    Parameters
    ----------
    base : mapping, optional
        Starting environment; defaults to ``os.environ``. A variable it already sets wins over
        ``mpi.env``, exactly as in ``scripts/mpienv.sh``.

    Returns
    -------
    dict of str to str
        ``base`` plus the Open MPI settings of ``lutmpi/parallel/mpi.env``.
    """
    env = dict(os.environ if base is None else base)
    if not ENV_FILE.is_file():
        raise MPIUnavailableError(f"{ENV_FILE} is missing: the package was installed without it")
    for key, value in parse_env_file(ENV_FILE.read_text(), str(ENV_FILE)).items():
        env.setdefault(key, value)
    return env


def self_check(path: str | os.PathLike[str] | None = None) -> int:
    """Every rank reports, then all write one dataset collectively and check it (rank 0 prints).

    Returns 0 on success, 1 on a wrong value (the same on every rank).
    """
    require_parallel_h5py()
    import tempfile

    import h5py
    import numpy as np

    comm = get_comm()
    rank, size = comm.rank, comm.size
    print(f"[mpi-check] rank {rank}/{size} on {os.uname().nodename} pid {os.getpid()}", flush=True)
    if path is None:
        tmp = tempfile.mkdtemp(prefix="lutmpi-mpicheck-") if rank == 0 else None
        path = os.path.join(comm.bcast(tmp, root=0), "check.h5")
    with h5py.File(path, "w", driver="mpio", comm=comm) as f:
        dset = f.create_dataset("rank", shape=(size,), dtype="i8")
        with dset.collective:
            dset[rank:rank + 1] = rank
    comm.Barrier()
    with h5py.File(path, "r", driver="mpio", comm=comm) as f:
        ok = bool(np.array_equal(f["rank"][...], np.arange(size)))
    ok = comm.allreduce(ok, op=_land())
    if rank == 0:
        print(f"[mpi-check] collective HDF5 write/read with {size} rank(s): "
              f"{'ok' if ok else 'WRONG VALUES'} ({path})", flush=True)
    return 0 if ok else 1


def _land() -> Any:
    from mpi4py import MPI

    return MPI.LAND


if __name__ == "__main__":  # pragma: no cover - exercised by tests through mpirun
    try:
        sys.exit(self_check(sys.argv[1] if len(sys.argv) > 1 else None))
    except MPIUnavailableError as exc:
        print(f"[mpi-check] error: {exc}", file=sys.stderr)
        sys.exit(1)
