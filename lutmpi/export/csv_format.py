"""``csv``: the 1-D contact functions of y at one yaw, both wheels, both contact slots.

One row per lateral shift ``y``; the columns are every stored dataset of :mod:`lutmpi.table.schema`
(see :func:`lutmpi.reports.units.columns`), lengths in mm, angles in degrees, the unit at the end of
each column name (``rolling_radius_left_s0_mm``, ``contact_angle_right_s1_deg``,
``normal_y_left_s0``
dimensionless). ``status_text`` names the solve status; points that did not converge keep their
status but their float values are empty (NaN), so no number stands for a failed solve. Header lines
starting with ``#`` give the table, method, yaw, case and the status codes.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from lutmpi.equilibrium.result import STATUS
from lutmpi.errors import ConfigError
from lutmpi.reports.units import all_columns, edge_unit
from lutmpi.table.schema import D

NAME = "csv"
DESCRIPTION = "1-D functions of y at one yaw (both wheels, both contacts), mm and deg"


def yaw_index(table: Any, yaw: float) -> int:
    """Index of the grid yaw equal to ``yaw`` (rad, within 1e-9 rad); raises naming the grid."""
    j = int(np.argmin(np.abs(table.yaw - yaw)))
    if abs(table.yaw[j] - yaw) > 1e-9:
        raise ConfigError(f"{table.path}: yaw {yaw:g} rad is not on the grid (nearest "
                          f"{table.yaw[j]:g} rad; grid {table.yaw[0]:g} .. {table.yaw[-1]:g} rad, "
                          f"{table.yaw.size} values)", key="--yaw-rad")
    return j


def record_cells(record: Mapping[str, np.ndarray]) -> tuple[list[str], list[Any]]:
    """Column names and values of one per-point record (``field name -> array of the field's
    suffix shape``, SI): every schema field present, in mm/deg (:mod:`lutmpi.reports.units`)."""
    header: list[str] = []
    values: list[Any] = []
    for f, col, idx in all_columns(list(record)):
        v = np.asarray(record[f.name])[idx]
        header.append(col)
        values.append(float(v) * edge_unit(f.units)[1] if np.dtype(f.dtype).kind == "f"
                      else int(v))
    return header, values


def status_text(code: int) -> str:
    """``converged``, ``max_iterations``, ... for a status code."""
    return STATUS.get(int(code), str(code)).split(":")[0]


def rows(table: Any, j: int, method: str | None = None) -> tuple[list[str], list[list[Any]]]:
    """Header and rows of the 1-D functions at yaw index ``j`` (masked: NaN where not converged)."""
    from lutmpi.table.api import mask_failed

    names = table.quantities
    header: list[str] = []
    out = []
    # masked here, whatever the table was opened with (export opens it raw for the .mat)
    grid = mask_failed({n: table.get(n, method, raw=True) for n in names})
    for iy, y in enumerate(table.y):
        record = {n: grid[n][iy, j] for n in names}
        header, values = record_cells(record)
        status = table.get(D.status, method, raw=True)[iy, j]
        out.append([y * 1e3] + values + [status_text(status)])
    return ["y_mm"] + header + ["status_text"], out


def write_rows(fh: TextIO, header: list[str], data: list[list[Any]]) -> None:
    """CSV rows: NaN as an empty cell, floats with 10 significant digits."""
    w = csv.writer(fh)
    w.writerow(header)
    for row in data:
        w.writerow(["" if isinstance(v, float) and np.isnan(v) else
                    (f"{v:.10g}" if isinstance(v, float) else v) for v in row])


def write(table: Any, out: Path, *, yaw: float = 0.0, method: str | None = None,
          **_: Any) -> list[Path]:
    """Write the CSV of the functions at ``yaw`` (rad) to ``out`` (a file, or a directory)."""
    j = yaw_index(table, yaw)
    method = method or table.methods[0]
    if out.is_dir():
        out = out / f"{Path(table.path).stem}_{method}_yaw{table.yaw[j]:+.4f}.csv"
    with open(out, "w", newline="") as fh:
        write_to(fh, table, yaw=yaw, method=method)
    return [out]


def write_to(fh: TextIO, table: Any, *, yaw: float = 0.0, method: str | None = None) -> None:
    """The CSV of the functions at ``yaw`` (rad) into an open text stream (a file, stdout)."""
    from lutmpi.reports.pair import pair_info

    j = yaw_index(table, yaw)
    method = method or table.methods[0]     # an unknown one: rows() raises naming the stored
    header, data = rows(table, j, method)
    fh.write(f"# lutmpi table {table.path}, method {method}, yaw {table.yaw[j]:.6g} rad\n")
    fh.write(f"# {pair_info(table.config_toml).title}\n")
    fh.write("# status codes: " + "; ".join(f"{k} {status_text(k)}" for k in STATUS) + "\n")
    write_rows(fh, header, data)
