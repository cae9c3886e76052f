"""``lutmpi solve CONFIG --poses POSES.csv | --pose Y_MM YAW_RAD ... [--method M] -o OUT.csv``:
single poses, serially (no MPI)."""

from __future__ import annotations

import logging
import sys
from typing import Any

from lutmpi.errors import ConfigError
from lutmpi.pose.solve import METHOD_NAMES

log = logging.getLogger(__name__)


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "solve", help="solve single wheelset poses (serial)",
        description="Solve the contact of the wheelset at given poses (y_g in mm, yaw in rad) "
                    "and write one CSV row per pose: the pose, the method and its message, then "
                    "every stored quantity of a table (the schema's columns, as `lutmpi export "
                    "--format csv` writes them: mm, deg, both wheels, both contacts).")
    p.add_argument("config", help="run configuration (TOML)")
    p.add_argument("--poses", help="CSV file with columns y_mm,yaw_rad")
    p.add_argument("--pose", nargs=2, action="append", metavar=("Y_MM", "YAW_RAD"), type=float,
                   default=[], help="one pose (repeatable)")
    p.add_argument("--method", choices=METHOD_NAMES, help="contact method (default: the config's)")
    p.add_argument("-o", "--output", default="-", help="output CSV (default: standard output)")
    p.set_defaults(func=run)


def run(args: Any) -> int:
    from lutmpi.config import load_config
    from lutmpi.contact.poses import check_pose, read_poses
    from lutmpi.outpath import check_output_file
    from lutmpi.pose.solve import solve_pose, warm
    from lutmpi.scene import Scene
    from lutmpi.table.provenance import input_files

    cfg = load_config(args.config)
    if args.output != "-":
        check_output_file(args.output, "solve output",
                          inputs=(args.config, args.poses, *input_files(cfg).values()))
    poses = read_poses(args.poses) if args.poses else []
    for k, (y, yaw) in enumerate(args.pose):
        check_pose(y, yaw, f"--pose number {k + 1}")
        poses.append((y * 1e-3, yaw))
    if not poses:
        raise ConfigError("no poses: give --poses FILE.csv or --pose Y_MM YAW_RAD")
    scene = Scene.from_config(cfg)
    # the kernels loaded (or, on a cold cache, compiled) before the first pose, outside its
    # time budget (equilibrium.max_pose_time_s), as a build does
    warm(scene, args.method or scene.settings.method)
    results = [solve_pose(scene, y, yaw, args.method) for y, yaw in poses]
    failed = [r for r in results if not r.success]
    for r in failed:
        log.warning("pose y=%.3f mm yaw=%.4f rad: %s", r.y * 1e3, r.yaw, r.message)
    if args.output == "-":
        write_results(sys.stdout, results)
    else:
        with open(args.output, "w", newline="") as fh:
            write_results(fh, results)
    log.info("%d poses solved, %d not converged", len(results), len(failed))
    return 0



def write_results(fh: Any, results: list[Any]) -> None:
    """One CSV row per pose: ``y_mm, yaw_rad, method, message``, the schema's columns (mm, deg;
    :func:`lutmpi.export.csv_format.record_cells`), ``status_text``."""
    from lutmpi.export.csv_format import record_cells, status_text, write_rows
    from lutmpi.table.compute import pose_to_record
    from lutmpi.table.schema import FIELDS, D

    header: list[str] = []
    rows = []
    for r in results:
        record = pose_to_record(r, FIELDS)
        cols, values = record_cells(record)
        header = ["y_mm", "yaw_rad", "method", "message"] + cols + ["status_text"]
        rows.append([r.y * 1e3, r.yaw, r.method, r.message] + values
                    + [status_text(record[D.status])])
    write_rows(fh, header, rows)
