"""A 2-D table between its yaw columns: the jump-aware interpolation against direct solves with
the table's own method, at poses on the columns and between them, for this tree and
(``--base``) another tree's interpolation of the same file.

    .venv/bin/python benchmarks/between_columns.py TABLE.h5 [--method load_centre] \
        [--random 1500] [--base /tmp/base] [--direct D.npz]

Poses: those of ``lutmpi report --table-error`` (0.3 of the way into every grid cell along y, at
every yaw column and halfway between columns, and 100 random ones) plus ``--random`` uniform
random poses over the grid (seed 7). The direct solves (``solve_pose`` with the scene of the
table's stored config) run once in this tree; ``--direct`` keeps them in a file and reads them
back on the next run. Each tree's interpolation (``Table.interp``, jump-aware) runs in a
subprocess that imports that tree's lutmpi. Poses within 0.02 mm of a located jump are left
out (there the answer may be either side's, both are right).

Printed per tree, on the columns and between them: the largest error over both wheels of the
primary rolling radius (RMS, median, count above 0.1 mm and 1 mm, maximum, um), the primary
contact angle (RMS, maximum, mrad) and z_g (RMS, um); and of the wheels in double contact (two
direct contacts), how many the table gives a primary contact strictly between the two, more than
0.1 mm of rolling radius from both (a contact blended from two).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
#: the tree whose lutmpi this process imports (the subprocess of ``--base`` sets it)
TREE_ENV = "BETWEEN_COLUMNS_TREE"
sys.path.insert(0, os.environ.get(TREE_ENV, str(ROOT)))

NEAR_M = 2e-5
NAMES = ("rolling_radius", "contact_angle", "z_g")


def direct_solves(table_path: Path, method: str, n_random: int) -> dict[str, np.ndarray]:
    """Poses and their direct solves (this tree's solver)."""
    from lutmpi.config import config_from_dict
    from lutmpi.pose.solve import solve_pose
    from lutmpi.reports import table_error
    from lutmpi.scene import Scene
    from lutmpi.table import Table
    from lutmpi.table.compute import pose_to_record
    from lutmpi.table.schema import FIELDS

    table = Table.open(table_path)
    scene = Scene.from_config(config_from_dict(tomllib.loads(table.config_toml)))
    y, yaw = table_error.test_poses(table.y, table.yaw, 100)
    rng = np.random.default_rng(7)
    y = np.concatenate([y, rng.uniform(table.y[0], table.y[-1], n_random)])
    yaw = np.concatenate([yaw, rng.uniform(table.yaw[0], table.yaw[-1], n_random)])
    out: dict[str, list] = {n: [] for n in NAMES}
    for a, b in zip(y, yaw, strict=True):
        rec = pose_to_record(solve_pose(scene, float(a), float(b), method), FIELDS)
        for n in NAMES:
            out[n].append(rec[n])
    return {"y": y, "yaw": yaw, **{n: np.array(v, float) for n, v in out.items()}}


def evaluate(table_path: Path, method: str, direct_path: Path) -> dict[str, dict[str, float]]:
    """Error figures of this process's interpolation (the tree on ``sys.path``)."""
    from lutmpi.table import Table

    d = np.load(direct_path)
    y, yaw = d["y"], d["yaw"]
    table = Table.open(table_path)
    q = table.interp(y, yaw, method, list(NAMES), info=True)
    n = y.size

    def primary(name: str) -> np.ndarray:   # (n, wheels): the main contact of each wheel
        return np.asarray(q[name], float).reshape(n, 2, -1)[:, :, 0]

    rr = np.nanmax(np.abs(primary("rolling_radius")
                          - d["rolling_radius"].reshape(n, 2, -1)[:, :, 0]), axis=1)
    ga = np.nanmax(np.abs(primary("contact_angle")
                          - d["contact_angle"].reshape(n, 2, -1)[:, :, 0]), axis=1)
    zg = np.abs(np.asarray(q["z_g"], float) - d["z_g"])
    # a wheel in double contact (two direct contacts) whose table primary contact lies strictly
    # between them, farther than 0.1 mm of rolling radius from both: a contact the table
    # invented by blending two different ones
    both = d["rolling_radius"].reshape(n, 2, -1)[:, :, :2]
    tp = primary("rolling_radius")
    double = np.isfinite(both).all(axis=2)
    lo, hi = np.nanmin(both, axis=2), np.nanmax(both, axis=2)
    phantom = double & (tp > lo + 1e-4) & (tp < hi - 1e-4)
    on = np.isin(np.round(yaw, 12), np.round(table.yaw, 12))
    away = ~(np.abs(q["jump_distance"]) <= NEAR_M)
    out = {}
    for label, sel in (("on the columns", on & away), ("between columns", ~on & away)):
        e, g, z = rr[sel], ga[sel], zg[sel]
        e, g, z = e[np.isfinite(e)], g[np.isfinite(g)], z[np.isfinite(z)]
        out[label] = {
            "poses": int(sel.sum()), "rr_rms_um": 1e6 * float(np.sqrt(np.mean(e ** 2))),
            "rr_median_um": 1e6 * float(np.median(e)), "rr_over_0.1mm": int((e > 1e-4).sum()),
            "rr_over_1mm": int((e > 1e-3).sum()), "rr_max_um": 1e6 * float(e.max()),
            "angle_rms_mrad": 1e3 * float(np.sqrt(np.mean(g ** 2))),
            "angle_max_mrad": 1e3 * float(g.max()),
            "zg_rms_um": 1e6 * float(np.sqrt(np.mean(z ** 2))),
            "without_answer": int(np.isnan(rr[sel]).sum()),
            "double": int(double[sel].sum()), "phantom": int(phantom[sel].sum()),
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("table", type=Path)
    ap.add_argument("--method", default="load_centre")
    ap.add_argument("--random", type=int, default=1500, help="random poses added")
    ap.add_argument("--base", type=Path, help="another tree whose interpolation to compare")
    ap.add_argument("--direct", type=Path, help="file of the direct solves (made if missing)")
    ap.add_argument("--evaluate-only", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.evaluate_only:
        print(json.dumps(evaluate(args.table, args.method, args.evaluate_only)))
        return
    direct = args.direct or args.table.with_suffix(f".{args.method}.direct.npz")
    if not direct.exists():
        np.savez(direct, **direct_solves(args.table, args.method, args.random))
        print(f"direct solves written to {direct}")
    trees = [("this tree", ROOT)] + ([("base", args.base.resolve())] if args.base else [])
    for label, tree in trees:
        env = {**os.environ, "PYTHONPATH": str(tree), TREE_ENV: str(tree)}
        res = subprocess.run([sys.executable, str(Path(__file__).resolve()), str(args.table),
                              "--method", args.method, "--evaluate-only", str(direct)],
                             env=env, cwd=tree, capture_output=True, text=True, check=True)
        figures = json.loads(res.stdout.strip().splitlines()[-1])
        print(f"{label} ({tree}):")
        for where, f in figures.items():
            print(f"  {where:16s} {f['poses']:5d} poses: rolling radius RMS {f['rr_rms_um']:.1f} "
                  f"median {f['rr_median_um']:.1f} max {f['rr_max_um']:.0f} um, "
                  f"> 0.1 mm {f['rr_over_0.1mm']}, > 1 mm {f['rr_over_1mm']}; contact angle "
                  f"RMS {f['angle_rms_mrad']:.3f} max {f['angle_max_mrad']:.2f} mrad; "
                  f"z_g RMS {f['zg_rms_um']:.2f} um; no answer {f['without_answer']}; "
                  f"double contacts {f['double']}, primary between the two {f['phantom']}")


if __name__ == "__main__":
    main()
