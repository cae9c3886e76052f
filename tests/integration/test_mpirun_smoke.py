"""mpirun works here as configured by ``lutmpi/parallel/mpi.env`` (as root, oversubscribed, shared
memory only): a serial test that launches real MPI jobs and checks that every rank ran.

Serial tier (not under tests/mpi/, where pytest-mpi treats every test as an MPI test).
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys

import pytest

from lutmpi.parallel.mpi import mpirun_env

HELLO = ("import sys; from mpi4py import MPI; c = MPI.COMM_WORLD; "
         "sys.stdout.write(f'hello {c.rank} of {c.size} sum={c.allreduce(c.rank)}\\n'); "
         "sys.stdout.flush()")


def _mpirun(n: int, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        pytest.fail("mpirun not found: scripts/setup.sh installs Debian's openmpi-bin")
    res = subprocess.run([mpirun, "-n", str(n), sys.executable, *args], env=mpirun_env(),
                         capture_output=True, timeout=timeout, stdin=subprocess.DEVNULL)
    # Open MPI 4.1.4's banner ends in a NUL byte: strip it before treating the output as text
    res.stdout = res.stdout.replace(b"\0", b"").decode(errors="replace")
    res.stderr = res.stderr.replace(b"\0", b"").decode(errors="replace")
    return res


@pytest.mark.parametrize("n", [2, 4])
def test_every_rank_runs_and_communicates(n):
    res = _mpirun(n, "-c", HELLO)
    assert res.returncode == 0, res.stderr
    # mpirun forwards each rank's output in chunks that may interleave: match, don't split lines
    seen = sorted(re.findall(r"hello (\d+) of (\d+) sum=(\d+)", res.stdout))
    total = n * (n - 1) // 2
    assert seen == sorted((str(r), str(n), str(total)) for r in range(n)), res.stdout


def test_collective_hdf5_self_check_under_mpirun(tmp_path):
    res = _mpirun(2, "-m", "lutmpi.parallel.mpi", str(tmp_path / "check.h5"))
    assert res.returncode == 0, res.stdout + res.stderr
    assert "collective HDF5 write/read with 2 rank(s): ok" in res.stdout
    assert res.stdout.count("[mpi-check] rank ") == 2
