"""Load (or, on a cold cache, compile) every compiled kernel of the pose solve once.

numba caches compiled kernels on disk next to their modules (``__pycache__``); a cold cache costs
a new checkout ~15 s of compilation in its first solve. ``scripts/setup.sh`` runs this module so
that cost is paid by the setup, not by the first build:

    .venv/bin/python -m lutmpi.warmup
"""

from __future__ import annotations

import logging
import time

log = logging.getLogger(__name__)


def warm_kernels() -> float:
    """Solve one flange pose with every registered method on a small generated scene (S1002 on
    UIC60, coarse meshes); returns the wall time, s."""
    from lutmpi.contact.methods import METHOD_NAMES, get_method
    from lutmpi.pose.mesh import warm_rare_paths
    from lutmpi.pose.solve import solve_pose
    from lutmpi.profiles.standard import generate
    from lutmpi.scene import Scene

    t0 = time.perf_counter()
    scene = Scene.from_profiles(generate("S1002"), generate("UIC60"),
                                spacing=(1e-3, 1e-3, 1e-3, 1e-3))
    for method in METHOD_NAMES:
        solve_pose(scene, 6e-3, 0.05, method)
        warm_rare_paths(scene, get_method(method))
    return time.perf_counter() - t0


if __name__ == "__main__":
    print(f"[setup] compiled kernels ready ({warm_kernels():.1f} s)")
