"""The Open MPI settings have one source (mpi.env) seen identically from Python and the shell, and
the parallel-HDF5 guard fails clearly."""

from __future__ import annotations

import subprocess
import sys
import types

import pytest

from lutmpi.errors import MPIUnavailableError
from lutmpi.parallel import mpi
from lutmpi.paths import REPO_ROOT

REQUIRED = {
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
    "OMPI_MCA_btl": "self,vader",
    "OMPI_MCA_btl_vader_single_copy_mechanism": "none",
}


def test_env_file_has_what_open_mpi_needs_here():
    env = mpi.parse_env_file(mpi.ENV_FILE.read_text(), str(mpi.ENV_FILE))
    assert REQUIRED.items() <= env.items()


def test_mpirun_env_adds_settings_and_keeps_callers_values():
    env = mpi.mpirun_env({"PATH": "/bin", "OMPI_MCA_btl": "self,tcp"})
    assert env["PATH"] == "/bin"
    assert env["OMPI_MCA_btl"] == "self,tcp"
    assert env["OMPI_ALLOW_RUN_AS_ROOT"] == "1"


def test_shell_and_python_see_the_same_values():
    keys = list(mpi.parse_env_file(mpi.ENV_FILE.read_text()))
    script = f"source '{REPO_ROOT}/scripts/mpienv.sh' && " + " && ".join(
        f'echo "{k}=${{{k}}}"' for k in keys)
    clean = {"PATH": "/usr/bin:/bin", "OMPI_MCA_btl": "self,tcp"}
    out = subprocess.run(["bash", "-c", script], env=clean, capture_output=True, text=True,
                         check=True, timeout=30).stdout
    assert mpi.parse_env_file(out) == {k: mpi.mpirun_env(clean)[k] for k in keys}


@pytest.mark.parametrize("bad", ["NOEQUALS", "=1", "A = 1", "A=1 2"])
def test_malformed_env_line_is_rejected_with_its_line(bad):
    with pytest.raises(ValueError, match=r"mpi.env:2"):
        mpi.parse_env_file(f"# c\n{bad}\n", "mpi.env")


def test_require_parallel_h5py_names_the_fix(monkeypatch):
    config = types.SimpleNamespace(mpi=False)
    fake = types.SimpleNamespace(__version__="9.9", get_config=lambda: config)
    monkeypatch.setitem(sys.modules, "h5py", fake)
    with pytest.raises(MPIUnavailableError, match=r"without MPI.*scripts/setup.sh"):
        mpi.require_parallel_h5py()


def test_installed_h5py_is_parallel():
    mpi.require_parallel_h5py()


def test_importing_mpi_helpers_does_not_initialise_mpi():
    code = "import sys, lutmpi.parallel.mpi, lutmpi.cli; sys.exit('mpi4py' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], timeout=60).returncode == 0
