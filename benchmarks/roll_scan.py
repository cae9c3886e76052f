"""The rigid start's all-roots roll scan on a config's grid (issue 14): scan points per pose and
CPU time of the scan per pose, and of the whole reference solve, in this tree.

    .venv/bin/python benchmarks/roll_scan.py configs/paper_s1002_uic60_1in20.toml [--grid 37 37]

Run it in two trees alternately to compare them (``cp benchmarks/roll_scan.py /tmp/base/
benchmarks/`` and run that copy for the base: the script imports the tree it lies in): the
point count does not depend on the machine, the times do. A tree before the scan's local bound
(2026-11-27) takes the global bound's arguments only; both are handled.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lutmpi.config import load_config  # noqa: E402
from lutmpi.contact import roll_scan as rs  # noqa: E402
from lutmpi.contact.locus import SCAN_STEP  # noqa: E402
from lutmpi.pose.solve import solve_pose, warm  # noqa: E402
from lutmpi.scene import Scene  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--grid", type=int, nargs=2, default=(37, 37), metavar=("NY", "NYAW"))
    a = ap.parse_args()
    cfg = load_config(a.config)
    scene = Scene.from_config(cfg)
    warm(scene, "reference")
    L = scene.locus
    (y0, y1, _), (w0, w1, _) = cfg.grid.y_mm, cfg.grid.yaw_rad
    poses = [(y * 1e-3, w) for y in np.linspace(y0, y1, a.grid[0])
             for w in np.linspace(w0, w1, a.grid[1])]
    bound = getattr(L, "_scan_bound", None)
    lo, hi = float(L.scan_rolls[0]), float(L.scan_rolls[-1])

    def scan(y: float, yaw: float) -> np.ndarray:
        args = (lo, hi, SCAN_STEP, L.lipschitz, float(yaw), float(y), *L._scan_sides)
        return rs.scan_adaptive(*args, bound)[0] if bound is not None else \
            rs.scan_adaptive(*args)[0]

    scan(*poses[0])
    points, t = 0, time.process_time()
    for y, yaw in poses:
        points += scan(y, yaw).size
    t_scan = time.process_time() - t
    t = time.process_time()
    for y, yaw in poses:
        solve_pose(scene, y, yaw, "reference")
    t_ref = time.process_time() - t
    n = len(poses)
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  {a.config}  grid "
          f"{a.grid[0]} x {a.grid[1]}  local bound: {'yes' if bound is not None else 'no'}")
    print(f"scan points per pose {points / n:.1f}; scan {t_scan / n * 1e3:.3f} ms per pose "
          f"({t_scan / points * 1e6:.2f} us per point); reference solve {t_ref / n * 1e3:.3f} ms "
          "per pose (CPU)")


if __name__ == "__main__":
    main()
