"""The set-up's kernel warm-up (issue 14, start-up): it solves with every registered method, so
every method's compiled stage is in numba's cache after ``scripts/setup.sh``, and it marks the
cache it filled: a multi-rank build reads the mark to decide whether its ranks may load kernels
at once or rank 0 must compile them first (``tests/mpi/test_cold_cache_mpi.py``)."""

from __future__ import annotations

import lutmpi
from lutmpi import warmup
from lutmpi.contact.methods import METHODS


def test_warmup_compiles_every_mesh_method_and_marks_the_cache(tmp_path, monkeypatch):
    folder = tmp_path / "lutmpi-0123456789abcdef"
    monkeypatch.setattr(lutmpi, "NUMBA_CACHE_DIR", str(folder))  # the mark only: numba's own
    assert warmup.ready_marker() == folder / warmup.READY_NAME   # cache stays where it is
    assert not warmup.kernels_ready()
    assert warmup.warm_kernels() > 0.0
    for m in METHODS.values():
        if m.uses_mesh:
            assert m.kernel.signatures, m.name  # compiled (or loaded from the cache) for use
    assert warmup.kernels_ready()
    # no temporary left; the lock's file stays
    assert sorted(p.name for p in folder.iterdir()) == sorted([warmup.LOCK_NAME,
                                                               warmup.READY_NAME])


def test_a_second_process_filling_the_folder_waits_for_the_first(tmp_path):
    """Two processes filling one cache folder are ordered (issue 14, two jobs started together
    on a cold cache): while this process holds the folder's compile lock, ``python -m
    lutmpi.warmup`` on that folder says it waits and marks nothing; released, it completes
    and marks the folder. Real processes, the real folder (warm: loading is quick)."""
    import fcntl
    import os
    import subprocess
    import sys
    import time

    from lutmpi.paths import REPO_ROOT

    marker = warmup.ready_marker()
    lock = marker.with_name(warmup.LOCK_NAME)
    lock.parent.mkdir(parents=True, exist_ok=True)
    err = tmp_path / "stderr"
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        before = marker.stat().st_ino if marker.exists() else None
        with open(err, "w") as fh:
            proc = subprocess.Popen([sys.executable, "-m", "lutmpi.warmup"], cwd=REPO_ROOT,
                                    stdout=subprocess.PIPE, stderr=fh, text=True)
        deadline = time.monotonic() + 120
        while "waiting for it" not in err.read_text() and time.monotonic() < deadline:
            assert proc.poll() is None, err.read_text()
            time.sleep(0.2)
        assert "waiting for it" in err.read_text()
        time.sleep(1.0)
        assert proc.poll() is None
        assert (marker.stat().st_ino if marker.exists() else None) == before
    finally:
        os.close(fd)   # releases the lock
    out, _ = proc.communicate(timeout=300)
    assert proc.returncode == 0, err.read_text()
    assert "compiled kernels ready" in out
    assert marker.stat().st_ino != before
