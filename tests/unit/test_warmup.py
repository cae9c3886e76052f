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
    assert [p.name for p in folder.iterdir()] == [warmup.READY_NAME]   # no temporary left
