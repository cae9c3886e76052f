"""``lutmpi query T.h5 --poses P.csv | --pose Y_MM YAW_RAD ... [--method M] -o OUT.csv``:
interpolated poses from a table, in the columns and units of ``lutmpi solve`` (so the two files
compare column by column), plus the side of the jumps and the distance to the nearest one."""

from __future__ import annotations

import csv
import logging
import sys
import time
from typing import Any, TextIO

import numpy as np

from lutmpi.errors import ConfigError

log = logging.getLogger(__name__)

#: the columns ``lutmpi query`` adds to :data:`lutmpi.contact.poses.COLUMNS`
EXTRA_COLUMNS = ("out_of_range", "jump_side", "jump_distance_mm")


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "query", help="interpolate a table at given poses (CSV, the columns of `solve`)",
        description="Interpolate a lookup table at poses (y_g in mm, yaw in rad), never across a "
                    "located contact jump, and write one CSV row per pose with the columns and "
                    "units of `lutmpi solve`, plus out_of_range (1: outside the grid, values "
                    "empty), jump_side (number of jumps below the pose at its yaw; a pose "
                    "exactly at a jump is on its upper side) and jump_distance_mm (signed "
                    "distance to the nearest jump). Exit status 1 when any pose is outside.")
    p.add_argument("table", help="lookup table (HDF5)")
    p.add_argument("--poses", help="CSV file with columns y_mm,yaw_rad")
    p.add_argument("--pose", nargs=2, action="append", metavar=("Y_MM", "YAW_RAD"), type=float,
                   default=[], help="one pose (repeatable)")
    p.add_argument("--method", help="contact method group (default: the table's first)")
    p.add_argument("-o", "--output", default="-", help="output CSV (default: standard output)")
    p.set_defaults(func=run)


def query_rows(table: Any, poses: list[tuple[float, float]], method: str | None = None
               ) -> list[dict[str, object]]:
    """Rows (mm, rad) of ``lutmpi solve``'s CSV plus :data:`EXTRA_COLUMNS` for poses (m, rad)."""
    from lutmpi.equilibrium.result import SIDES, STATUS

    method = method or table.methods[0]
    y = np.array([p[0] for p in poses], float)
    yaw = np.array([p[1] for p in poses], float)
    table.interpolator(method)            # built once; its set-up is not the query's cost
    t0 = time.perf_counter()
    q = table.interp(y, yaw, method, outside="flag", info=True)
    per_pose_ms = (time.perf_counter() - t0) / max(len(poses), 1) * 1e3
    nan = float("nan")

    def get(name: str, k: int, *index: int) -> float:
        return float(q[name][(k,) + index]) if name in q else nan

    rows = []
    for k in range(len(poses)):
        status = int(q["status"][k])
        row: dict[str, object] = {
            "y_mm": y[k] * 1e3, "yaw_rad": yaw[k], "method": method, "status": status,
            "message": "outside the table grid" if q["out_of_range"][k] else
            STATUS.get(status, str(status)), "iterations": int(q["iterations"][k]),
            "z_g_mm": get("z_g", k) * 1e3, "roll_rad": get("roll", k),
            "x_g_mm": get("x_g", k) * 1e3, "pitch_rad": get("pitch", k),
            "kc_N_per_m": get("kc", k), "cpu_ms": per_pose_ms}
        for s, side in enumerate(SIDES):
            row[f"{side}_n_contacts"] = int(q["n_contacts"][k, s]) if "n_contacts" in q else -1
            row[f"{side}_wheel_s_mm"] = get("wheel_s", k, s, 0) * 1e3
            row[f"{side}_contact_angle_rad"] = get("contact_angle", k, s, 0)
            row[f"{side}_rolling_radius_mm"] = get("rolling_radius", k, s, 0) * 1e3
            row[f"{side}_x_mm"] = get("wheel_point", k, s, 0, 0) * 1e3
            row[f"{side}_rail_v_mm"] = get("rail_v", k, s, 0) * 1e3
            row[f"{side}_indentation_mm"] = get("indentation", k, s, 0) * 1e3
        row["out_of_range"] = int(q["out_of_range"][k])
        row["jump_side"] = int(q["jump_side"][k])
        row["jump_distance_mm"] = float(q["jump_distance"][k]) * 1e3
        rows.append(row)
    return rows


def write_rows(out: str | TextIO, rows: list[dict[str, object]]) -> None:
    """CSV: the columns of ``lutmpi solve`` then :data:`EXTRA_COLUMNS`."""
    from lutmpi.contact.poses import COLUMNS

    if isinstance(out, str):
        with open(out, "w", newline="") as fh:
            write_rows(fh, rows)
        return
    w = csv.DictWriter(out, fieldnames=list(COLUMNS) + list(EXTRA_COLUMNS))
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in r.items()})


def run(args: Any) -> int:
    from lutmpi.contact.poses import read_poses
    from lutmpi.table import Table

    poses = read_poses(args.poses) if args.poses else []
    poses += [(y * 1e-3, yaw) for y, yaw in args.pose]
    if not poses:
        raise ConfigError("no poses: give --poses FILE.csv or --pose Y_MM YAW_RAD")
    table = Table.open(args.table)
    rows = query_rows(table, poses, args.method)
    write_rows(sys.stdout if args.output == "-" else args.output, rows)
    outside = [r for r in rows if r["out_of_range"]]
    if outside:
        r = outside[0]
        log.error("%d of %d poses outside the table grid (first: y = %.4f mm, yaw = %.5f rad); "
                  "their rows are flagged out_of_range = 1", len(outside), len(rows), r["y_mm"],
                  r["yaw_rad"])
        return 1
    log.info("%d poses interpolated", len(rows))
    return 0
