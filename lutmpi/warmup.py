"""Load (or, on a cold cache, compile) every compiled kernel of the pose solve once.

numba caches compiled kernels on disk (``lutmpi.NUMBA_CACHE_DIR``, a folder keyed on the
sources); a cold cache costs a new checkout ~1.5 min of compilation on 2 cores in its first
solve. ``scripts/setup.sh`` runs this module so that cost is paid by the setup, not by the first
build, and the cache is marked complete (:func:`kernels_ready`):

    .venv/bin/python -m lutmpi.warmup
"""

from __future__ import annotations

import fcntl
import logging
import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

log = logging.getLogger(__name__)

#: written into the kernels' cache folder once :func:`warm_kernels` has filled it
READY_NAME = "lutmpi-kernels-ready"
#: the file in that folder a process holds locked while it fills the folder (:func:`compile_lock`)
LOCK_NAME = "lutmpi-compile.lock"


def ready_marker() -> Path:
    """The file that says this source tree's kernel cache is complete
    (``lutmpi.NUMBA_CACHE_DIR``, keyed on the sources)."""
    from lutmpi import NUMBA_CACHE_DIR

    return Path(NUMBA_CACHE_DIR) / READY_NAME


def kernels_ready() -> bool:
    """True when :func:`warm_kernels` has completed with this cache folder: a build then only
    loads kernels, and its ranks may do so at once. Otherwise they would compile at once and
    write the same cache entries concurrently, which numba does not guard against (overloads
    of one function saved by two processes can overwrite each other's data files)."""
    return ready_marker().is_file()


@contextmanager
def compile_lock() -> Iterator[None]:
    """Hold the kernel cache folder's compile lock (an exclusive ``flock`` of
    :data:`LOCK_NAME` there), waiting while another process holds it: two processes filling
    one cold folder at once (two jobs started together after the sources changed, two set-ups)
    would write the same cache entries concurrently. The lock goes with the process, however
    it ends; the file stays (removing it would let a third process lock a new file). A folder
    where the file cannot be made or locked is not locked (numba cannot cache there either)."""
    path = ready_marker().with_name(LOCK_NAME)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    except OSError as exc:
        log.debug("kernel cache %s not locked: %s", path.parent, exc)
        yield
        return
    try:
        try:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                log.warning("another process is compiling the kernels into %s: waiting for "
                            "it", path.parent)
                fcntl.flock(fd, fcntl.LOCK_EX)
        except OSError as exc:   # a file system without locks
            log.debug("kernel cache %s not locked: %s", path.parent, exc)
        yield
    finally:
        os.close(fd)


def warm_kernels() -> float:
    """Solve one flange pose with every registered method on a small generated scene (S1002 on
    UIC60, coarse meshes), which compiles (cold cache) or loads every kernel a build uses, then
    mark the cache ready (:func:`kernels_ready`); returns the wall time, s, waiting for
    another process filling the folder included (:func:`compile_lock`)."""
    t0 = time.perf_counter()
    with compile_lock():
        _solve_every_method()
        _mark_ready()
    return time.perf_counter() - t0


def load_kernels() -> None:
    """Load every compiled kernel a build uses into this process (from the cache; a kernel the
    cache lacks is compiled), without :func:`warm_kernels`'s lock and mark: for the ranks of a
    job once the cache is complete (:func:`kernels_ready`)."""
    _solve_every_method()


def _solve_every_method() -> None:
    from lutmpi.contact.methods import METHOD_NAMES, get_method
    from lutmpi.pose.mesh import warm_rare_paths
    from lutmpi.pose.solve import solve_pose
    from lutmpi.profiles.standard import generate
    from lutmpi.scene import Scene

    scene = Scene.from_profiles(generate("S1002"), generate("UIC60"),
                                spacing=(1e-3, 1e-3, 1e-3, 1e-3))
    for method in METHOD_NAMES:
        solve_pose(scene, 6e-3, 0.05, method)
        warm_rare_paths(scene, get_method(method))


def _mark_ready() -> None:
    marker = ready_marker()
    tmp = marker.with_name(f"{marker.name}.{os.urandom(8).hex()}.tmp")
    try:
        marker.parent.mkdir(parents=True, exist_ok=True)
        tmp.write_text("complete\n")
        os.replace(tmp, marker)
    except OSError as exc:   # numba could not cache there either: compiled, not kept
        log.warning("the compiled kernels' cache %s cannot be marked complete: %s",
                    marker.parent, exc)


if __name__ == "__main__":
    import lutmpi

    if lutmpi.CACHE_NOTE:
        print(f"[setup] warning: {lutmpi.CACHE_NOTE}")
    print(f"[setup] compiled kernels ready ({warm_kernels():.1f} s)")
