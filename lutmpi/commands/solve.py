"""``lutmpi solve CONFIG --poses POSES.csv | --pose Y_MM YAW_RAD ... [--method M] -o OUT.csv``:
single poses, serially (no MPI)."""

from __future__ import annotations

import logging
import sys
from typing import Any

from lutmpi.contact.solve import METHOD_NAMES
from lutmpi.errors import ConfigError

log = logging.getLogger(__name__)


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "solve", help="solve single wheelset poses (serial)",
        description="Solve the contact of the wheelset at given poses (y_g in mm, yaw in rad) "
                    "and write one CSV row per pose (column names carry units).")
    p.add_argument("config", help="run configuration (TOML)")
    p.add_argument("--poses", help="CSV file with columns y_mm,yaw_rad")
    p.add_argument("--pose", nargs=2, action="append", metavar=("Y_MM", "YAW_RAD"), type=float,
                   default=[], help="one pose (repeatable)")
    p.add_argument("--method", choices=METHOD_NAMES, help="contact method (default: the config's)")
    p.add_argument("-o", "--output", default="-", help="output CSV (default: standard output)")
    p.set_defaults(func=run)


def run(args: Any) -> int:
    from lutmpi.config import load_config
    from lutmpi.contact.poses import read_poses, write_results
    from lutmpi.contact.solve import solve_pose
    from lutmpi.scene import Scene

    poses = read_poses(args.poses) if args.poses else []
    poses += [(y * 1e-3, yaw) for y, yaw in args.pose]
    if not poses:
        raise ConfigError("no poses: give --poses FILE.csv or --pose Y_MM YAW_RAD")
    cfg = load_config(args.config)
    scene = Scene.from_config(cfg)
    results = [solve_pose(scene, y, yaw, args.method) for y, yaw in poses]
    failed = [r for r in results if not r.success]
    for r in failed:
        log.warning("pose y=%.3f mm yaw=%.4f rad: %s", r.y * 1e3, r.yaw, r.message)
    write_results(sys.stdout if args.output == "-" else args.output, results)
    log.info("%d poses solved, %d not converged", len(results), len(failed))
    return 0

