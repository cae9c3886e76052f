"""The set-up's kernel warm-up (issue 14, start-up): it solves with every registered method, so
every method's compiled stage is in numba's cache after ``scripts/setup.sh``."""

from __future__ import annotations

from lutmpi.contact.methods import METHODS
from lutmpi.warmup import warm_kernels


def test_warmup_compiles_every_mesh_method():
    assert warm_kernels() > 0.0
    for m in METHODS.values():
        if m.uses_mesh:
            assert m.kernel.signatures, m.name  # compiled (or loaded from the cache) for use
