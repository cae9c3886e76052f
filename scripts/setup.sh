#!/usr/bin/env bash
# Set up lutmpi on a fresh Debian machine: Open MPI + parallel HDF5 from Debian, a venv in .venv/,
# mpi4py (PyPI wheel, finds Debian's libmpi), h5py built from source against parallel HDF5, and an
# editable install of lutmpi (so .venv/bin/lutmpi works).
#
# Idempotent: each step checks first and is skipped when already done; a second run takes ~1 s.
# Works as root without a TTY (CI=true); as another user it uses sudo for apt-get.
# Exits non-zero with a clear message if the result cannot do parallel HDF5.
#   PYTHON=python3.11 bash scripts/setup.sh    # choose the interpreter for a new venv (>= 3.11)
#   LUTMPI_REBUILD=1 bash scripts/setup.sh     # recreate .venv from scratch
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
export DEBIAN_FRONTEND=noninteractive PIP_NO_INPUT=1 PIP_DISABLE_PIP_VERSION_CHECK=1
log() { echo "[setup] $*"; }
die() { echo "[setup] ERROR: $*" >&2; exit 1; }
# pip, quietly; drops the machine's harmless "Location ... is ignored" notes, keeps pip's status
pip_q() {
  local rc
  "$VPY" -m pip "$@" 2> >(grep -v "^WARNING: Location 'file:" >&2)
  rc=$?
  return $rc
}

# --- 1. Debian: Open MPI and parallel HDF5 -------------------------------------------------------
APT_PKGS=(openmpi-bin libopenmpi-dev libhdf5-openmpi-dev hdf5-tools pkg-config)
missing=()
for p in "${APT_PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  command -v apt-get >/dev/null || die "apt-get not found: this script needs Debian/Ubuntu (missing: ${missing[*]})"
  SUDO=()
  if [ "$(id -u)" != 0 ]; then
    command -v sudo >/dev/null || die "not root and no sudo: install ${missing[*]} by hand"
    SUDO=(sudo -n)
  fi
  log "installing Debian packages: ${missing[*]}"
  "${SUDO[@]}" apt-get update -qq || die "apt-get update failed"
  "${SUDO[@]}" apt-get install -y -qq --no-install-recommends -o Dpkg::Use-Pty=0 \
    "${APT_PKGS[@]}" >/dev/null || die "apt-get install ${APT_PKGS[*]} failed"
fi
command -v mpicc >/dev/null || die "mpicc not found after installing libopenmpi-dev"
command -v mpirun >/dev/null || die "mpirun not found after installing openmpi-bin"
pkg-config --exists hdf5-openmpi || die "pkg-config cannot find hdf5-openmpi (libhdf5-openmpi-dev)"

# --- 2. The virtual environment ------------------------------------------------------------------
VPY="$here/.venv/bin/python"
venv_ok() {
  [ -x "$VPY" ] && "$VPY" -c 'import sys; sys.exit(not (sys.version_info >= (3, 11)
      and sys.prefix == sys.argv[1]))' "$here/.venv" 2>/dev/null
}
if [ "${LUTMPI_REBUILD:-0}" = 1 ] || ! venv_ok; then
  PY="${PYTHON:-python3}"
  command -v "$PY" >/dev/null || die "$PY not found (set PYTHON=/path/to/python3.11+)"
  "$PY" -c 'import sys; sys.exit(sys.version_info < (3, 11))' \
    || die "$PY is $("$PY" --version 2>&1); lutmpi needs Python >= 3.11 (set PYTHON=...)"
  [ -e .venv ] && log "removing unusable or unwanted .venv" && rm -rf .venv
  log "creating .venv with $("$PY" --version 2>&1)"
  "$PY" -m venv .venv || die "python -m venv failed (Debian: apt-get install python3-venv)"
fi

# --- 3. Python dependencies (stamp keyed on pyproject.toml and this list) ------------------------
DEPS=("numpy>=2" "scipy>=1.11" matplotlib "mpi4py>=4" numba pytest pytest-mpi pytest-timeout
      "pytest-xdist>=3" hypothesis ruff "Cython>=3" pkgconfig "setuptools>=77" wheel)
MODULES="numpy scipy matplotlib mpi4py numba pytest pytest_mpi pytest_timeout xdist hypothesis ruff
         Cython pkgconfig setuptools wheel"
stamp=".venv/.lutmpi-deps-$(cat pyproject.toml <(printf '%s\n' "${DEPS[@]}") | sha1sum | cut -c1-12)"
deps_ok() {
  [ -f "$stamp" ] && "$VPY" -c 'import importlib.util as u, sys
sys.exit(any(u.find_spec(m) is None for m in sys.argv[1:]))' $MODULES 2>/dev/null
}
if ! deps_ok; then
  log "installing Python dependencies (about 1 minute)"
  rm -f .venv/.lutmpi-deps-*
  pip_q install -q --upgrade pip || die "pip upgrade failed"
  pip_q install -q "${DEPS[@]}" || die "pip install of the dependencies failed"
fi

# --- 3b. The compiled kernels (step 7) start now, in the background: on a fresh machine their
# compilation (~2 min) runs beside h5py's build (~3 min), which keeps one core busy. The solve
# path imports neither h5py nor mpi4py, and lutmpi is imported from this folder (the editable
# install below changes none of its sources, so the kernels' cache folder is the same).
warm_log="$(mktemp "${TMPDIR:-/tmp}/lutmpi-warmup.XXXXXX")"
"$VPY" -m lutmpi.warmup >"$warm_log" 2>&1 &
warm_pid=$!
# a failed step below ends the script: the warm-up goes with it (a partial cache is not marked
# complete, so the next run compiles what is missing)
trap 'kill "$warm_pid" 2>/dev/null || true; rm -f "$warm_log"' EXIT

# --- 4. h5py with MPI, built against Debian's parallel HDF5 (see shared/SETUP_NOTES.md) -----------
h5py_mpi() { "$VPY" -c 'import h5py, sys; sys.exit(0 if h5py.get_config().mpi else 1)' 2>/dev/null; }
if ! h5py_mpi; then
  log "building h5py against Debian's parallel HDF5 (about 3 minutes)"
  # no isolation: its build env would compile mpi4py 4.0.0 (20+ min); no cache: a cached serial
  # wheel would be reused silently
  CC=mpicc HDF5_MPI=ON HDF5_PKGCONFIG_NAME=hdf5-openmpi H5PY_SETUP_REQUIRES=0 \
    pip_q install -q --no-build-isolation --no-binary=h5py --no-cache-dir --force-reinstall \
    --no-deps h5py || die "building h5py with MPI failed (see the compiler output above)"
fi

# --- 5. lutmpi itself, editable (after h5py: pip then finds h5py satisfied and keeps it) ----------
lutmpi_ok() {
  [ -x .venv/bin/lutmpi ] && [ -f "$stamp" ] && "$VPY" -c 'import sys, importlib.util as u
s = u.find_spec("lutmpi"); sys.exit(s is None or not s.origin.startswith(sys.argv[1]))' \
    "$here/lutmpi/" 2>/dev/null
}
if ! lutmpi_ok; then
  log "installing lutmpi (editable)"
  pip_q install -q --no-build-isolation -e ".[test]" >/dev/null 2>&1 \
    || pip_q install --no-build-isolation -e ".[test]" \
    || die "editable install of lutmpi failed"
  touch "$stamp"
fi

# --- 6. The check that matters -------------------------------------------------------------------
"$VPY" - <<'EOF' || die "the environment cannot do parallel HDF5: see the message above"
import sys
import h5py
import mpi4py
if not h5py.get_config().mpi:
    sys.exit(f"h5py {h5py.__version__} has no MPI support (h5py.get_config().mpi is False); "
             "rerun with LUTMPI_REBUILD=1 bash scripts/setup.sh")
print(f"[setup] ok: h5py {h5py.__version__} (mpi, HDF5 {h5py.version.hdf5_version}), "
      f"mpi4py {mpi4py.__version__}, python {sys.version.split()[0]}")
EOF

# --- 7. Compiled kernels ready: numba's on-disk cache (.numba_cache/, keyed on the sources) filled
# (~0.5–2.5 min on a cold cache, a second when warm; started in step 3b), so a first build does
# not compile
warm_rc=0
wait "$warm_pid" || warm_rc=$?
trap - EXIT
if [ "$warm_rc" = 0 ]; then
  cat "$warm_log"
  rm -f "$warm_log"
else
  cat "$warm_log" >&2
  rm -f "$warm_log"
  die "compiling the numba kernels failed (see above)"
fi
