"""Time per pose of each contact method at a config's mesh (issue 3), and lookup vs online.

    .venv/bin/python benchmarks/contact_methods.py configs/paper_s1002_uic60_1in20.toml

Prints, for ``reference`` and the three mesh methods, the CPU time per pose (mean, median, 90th
and 99th percentile, max) over a sample of the config's grid (``--ny/--nyaw``, default 9 x 5) or
over a whole grid (``--grid NY NYAW``: the config's range at that count, e.g. 37 37 for the
paper's table, 145 73 for the dense grid of issue 14), the mean number of contact evaluations, and
the cost of one bilinear lookup of a whole table record (``Table.interp``) against one online
solve. CPU time (``time.process_time``) is used so that other load on the machine inflates the
figures as little as possible; the machine and date are printed for BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import time
from pathlib import Path

import numpy as np

import lutmpi
from lutmpi.config import load_config

try:
    from lutmpi.pose.solve import solve_pose
except ImportError:       # a tree before the pose pipeline moved out of contact/ (compare_trees)
    from lutmpi.contact.solve import solve_pose
try:
    from lutmpi.pose.solve import warm
except ImportError:       # a tree before pose.solve.warm: one solve warms what it can
    def warm(scene, method):
        solve_pose(scene, 0.0, 0.0, method)
from lutmpi.scene import Scene

METHODS = ("reference", "max_distance", "max_normal_distance", "load_centre")


def sample_poses(cfg, n_y: int, n_yaw: int) -> list[tuple[float, float]]:
    """``n_y x n_yaw`` poses spread evenly over the config's grid range (m, rad)."""
    (y0, y1, _), (a0, a1, _) = cfg.grid.y_mm, cfg.grid.yaw_rad
    return [(y * 1e-3, a) for y in np.linspace(y0, y1, n_y) for a in np.linspace(a0, a1, n_yaw)]


def time_method(scene, poses, method: str) -> dict[str, float]:
    warm(scene, method)                         # compile / warm the caches
    cpu, nit, bad = [], [], 0
    for y, yaw in poses:
        t = time.process_time()
        r = solve_pose(scene, y, yaw, method)
        cpu.append(time.process_time() - t)
        nit.append(r.nit)
        bad += not r.success
    c = np.array(cpu) * 1e3
    return {"mean": c.mean(), "median": float(np.median(c)), "p90": float(np.percentile(c, 90)),
            "p99": float(np.percentile(c, 99)), "max": float(c.max()),
            "nit": float(np.mean(nit)), "failed": bad}


def time_lookup(table_path: str, n: int = 20000) -> float:
    from lutmpi.table import Table

    t = Table.open(table_path)
    rng = np.random.default_rng(0)
    y = rng.uniform(t.y[0], t.y[-1], n)
    yaw = rng.uniform(t.yaw[0], t.yaw[-1], n)
    t.interp(y[:10], yaw[:10])
    t0 = time.process_time()
    for i in range(200):
        t.interp(y[i:i + 1], yaw[i:i + 1])
    single = (time.process_time() - t0) / 200
    t0 = time.process_time()
    t.interp(y, yaw)
    vector = (time.process_time() - t0) / n
    return single, vector


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--ny", type=int, default=9)
    ap.add_argument("--nyaw", type=int, default=5)
    ap.add_argument("--grid", type=int, nargs=2, metavar=("NY", "NYAW"),
                    help="time every pose of an NY x NYAW grid over the config's range")
    ap.add_argument("--methods", nargs="+", default=list(METHODS))
    ap.add_argument("--table", help="a table built from CONFIG, for the lookup figures")
    a = ap.parse_args()
    cfg = load_config(a.config)
    scene = Scene.from_config(cfg)
    poses = sample_poses(cfg, *(a.grid or (a.ny, a.nyaw)))
    node = f"{platform.node()}  {platform.processor() or platform.machine()}"
    print(f"# {datetime.date.today()}  {node}"
          f"  cpus={os.cpu_count()}  load={os.getloadavg()[0]:.1f}  lutmpi from "
          f"{Path(lutmpi.__file__).parent}")
    m = cfg.mesh
    print(f"# config {a.config}: mesh {m.wheel_lateral_mm}/{m.wheel_circumferential_mm}/"
          f"{m.rail_lateral_mm}/{m.rail_longitudinal_mm} mm, allowed indentation "
          f"{cfg.contact.allowed_indentation_mm} mm, {len(poses)} poses")
    print(f"{'method':22s} {'mean ms':>8s} {'median':>8s} {'p90':>8s} {'p99':>8s} {'max':>8s} "
          f"{'evals':>6s} {'failed':>6s}")
    online = {}
    for meth in a.methods:
        s = time_method(scene, poses, meth)
        online[meth] = s["mean"]
        print(f"{meth:22s} {s['mean']:8.2f} {s['median']:8.2f} {s['p90']:8.2f} {s['p99']:8.2f} "
              f"{s['max']:8.1f} {s['nit']:6.1f} {s['failed']:6d}", flush=True)
    if a.table:
        single, vector = time_lookup(a.table)
        print(f"lookup (Table.interp, all quantities): {single * 1e6:.1f} us per single call, "
              f"{vector * 1e6:.3f} us per point vectorized")
        for meth, ms in online.items():
            print(f"  online {meth}: {ms * 1e-3 / single:.0f}x a single lookup, "
                  f"{ms * 1e-3 / vector:.0f}x a vectorized lookup")


if __name__ == "__main__":
    main()
