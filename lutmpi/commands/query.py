"""``lutmpi query T.h5 --poses P.csv | --pose Y_MM YAW_RAD ... [--method M] -o OUT.csv``:
interpolated poses from a table, in the columns and units of ``lutmpi solve`` (so the two files
compare column by column), plus the side of the jumps and the distance to the nearest one."""

from __future__ import annotations

import logging
import sys
from typing import Any

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
                    "units of `lutmpi solve` (every stored quantity, mm and deg; compute_time_s "
                    "empty: the cost of a grid point's solve is no property of a pose), plus "
                    "out_of_range (1: outside the grid, however little, values empty; the "
                    "message says by how much), jump_side (number of "
                    "jumps below the pose at its yaw; a pose "
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
               ) -> tuple[list[str], list[list[Any]]]:
    """Header and rows of ``lutmpi solve``'s CSV (``y_mm, yaw_rad, method, message``, the
    schema's columns in mm/deg, ``status_text``) plus :data:`EXTRA_COLUMNS`, for poses (m, rad).
    """
    from lutmpi.equilibrium.result import STATUS
    from lutmpi.export.csv_format import record_cells, status_text
    from lutmpi.table.schema import TIMING_FIELDS, D

    method = method or table.methods[0]
    y = np.array([p[0] for p in poses], float)
    yaw = np.array([p[1] for p in poses], float)
    q = table.interp(y, yaw, method, outside="flag", info=True)
    names = [n for n in table.quantities if n in q]
    # a grid point's CPU time is no value at a pose (0 where the point was filled by
    # reflection, none between points): the column stays, as solve's, empty
    for n in TIMING_FIELDS:
        if n in q:
            q[n] = np.full(q[n].shape, np.nan)
    header: list[str] = []
    rows = []
    for k in range(len(poses)):
        record = {n: q[n][k] for n in names}
        cols, values = record_cells(record)
        code = int(q[D.status][k])
        outside = bool(q["out_of_range"][k])
        message = (f"outside the table grid: {beyond_grid(table, y[k], yaw[k])}" if outside
                   else STATUS.get(code, str(code)))
        header = (["y_mm", "yaw_rad", "method", "message"] + cols + ["status_text"]
                  + list(EXTRA_COLUMNS))
        rows.append([y[k] * 1e3, yaw[k], method, message] + values
                    + ["outside" if outside else status_text(code), int(outside),
                       int(q["jump_side"][k]), float(q["jump_distance"][k]) * 1e3])
    return header, rows


def beyond_grid(table: Any, y: float, yaw: float) -> str:
    """How far a pose (m, rad) lies outside the grid of ``table``, axis by axis, with the
    pose's own digits: the CSV's 10 significant digits print a pose 1e-12 mm beyond the
    last y as that y, which the row would then seem to call outside."""
    parts = []
    for name, v, axis, scale, unit in (("y", y, table.y, 1e3, "mm"),
                                       ("yaw", yaw, table.yaw, 1.0, "rad")):
        lo, hi = float(axis[0]) * scale, float(axis[-1]) * scale
        v = float(v) * scale
        if v < lo or v > hi:
            side, edge = ("below", lo) if v < lo else ("above", hi)
            parts.append(f"{name} = {v:.15g} {unit} is {abs(v - edge):.3g} {unit} {side} the "
                         f"grid's range [{lo:.15g}, {hi:.15g}] {unit}")
    return "; ".join(parts) + " (a table never clamps a pose to its edge)"


def run(args: Any) -> int:
    from lutmpi.contact.poses import check_pose, read_poses
    from lutmpi.outpath import check_output_file
    from lutmpi.table import Table

    if args.output != "-":
        check_output_file(args.output, "query output", inputs=(args.table, args.poses))
    poses = read_poses(args.poses) if args.poses else []
    for k, (y, yaw) in enumerate(args.pose):
        check_pose(y, yaw, f"--pose number {k + 1}")
        poses.append((y * 1e-3, yaw))
    if not poses:
        raise ConfigError("no poses: give --poses FILE.csv or --pose Y_MM YAW_RAD")
    from lutmpi.equilibrium.result import CONVERGED
    from lutmpi.export.csv_format import status_text, write_rows

    table = Table.open(args.table)
    header, rows = query_rows(table, poses, args.method)
    if args.output == "-":
        write_rows(sys.stdout, header, rows)
    else:
        with open(args.output, "w", newline="") as fh:
            write_rows(fh, header, rows)
    flag = header.index("out_of_range")
    text = header.index("status_text")
    failed = [r for r in rows if not r[flag] and r[text] != status_text(CONVERGED)]
    if failed:
        log.warning("%d of %d poses lie where the table's points did not converge (first: "
                    "y = %.4f mm, yaw = %.5f rad, %s): their values are empty", len(failed),
                    len(rows), failed[0][0], failed[0][1], failed[0][text])
    outside = [r for r in rows if r[flag]]
    if outside:
        log.error("%d of %d poses outside the table grid (first: %s); their rows are flagged "
                  "out_of_range = 1", len(outside), len(rows),
                  outside[0][header.index("message")].split(": ", 1)[1])
        return 1
    log.info("%d poses interpolated", len(rows))
    return 0
