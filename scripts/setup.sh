#!/usr/bin/env bash
# Set up lutmpi on a fresh Debian machine: Open MPI + parallel HDF5 from Debian, a venv in .venv/,
# mpi4py (wheel, finds Debian's libmpi), h5py built from source against parallel HDF5.
# Idempotent: a second run checks and returns in a few seconds.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
export DEBIAN_FRONTEND=noninteractive
log() { echo "[setup] $*"; }

need_apt=0
for p in openmpi-bin libopenmpi-dev libhdf5-openmpi-dev pkg-config; do
  dpkg -s "$p" >/dev/null 2>&1 || need_apt=1
done
if [ "$need_apt" = 1 ]; then
  log "installing Debian packages (Open MPI, parallel HDF5)"
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends openmpi-bin libopenmpi-dev libhdf5-openmpi-dev pkg-config >/dev/null
fi

PY="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  log "creating .venv with $($PY --version)"
  "$PY" -m venv .venv
fi
VPY=.venv/bin/python
stamp=.venv/.lutmpi-deps-$(sha1sum pyproject.toml | cut -c1-12)
if [ ! -f "$stamp" ]; then
  log "installing Python dependencies"
  $VPY -m pip install -q --upgrade pip
  $VPY -m pip install -q -U "numpy>=2" "scipy>=1.11" matplotlib "mpi4py>=4" numba \
      pytest pytest-mpi pytest-timeout hypothesis ruff "Cython>=3" pkgconfig "setuptools>=77" wheel
fi
if ! $VPY -c 'import h5py, sys; sys.exit(0 if h5py.get_config().mpi else 1)' 2>/dev/null; then
  log "building h5py against Debian's parallel HDF5 (about 3 minutes)"
  CC=mpicc HDF5_MPI=ON HDF5_PKGCONFIG_NAME=hdf5-openmpi H5PY_SETUP_REQUIRES=0 \
    $VPY -m pip install -q --no-build-isolation --no-binary=h5py --no-cache-dir --force-reinstall --no-deps h5py
fi
if [ ! -f "$stamp" ]; then
  $VPY -m pip install -q --no-build-isolation -e . >/dev/null
  touch "$stamp"
fi
$VPY -c 'import h5py, mpi4py; assert h5py.get_config().mpi, "h5py has no MPI support"; print("[setup] ok: h5py", h5py.__version__, "(mpi) mpi4py", mpi4py.__version__)'
