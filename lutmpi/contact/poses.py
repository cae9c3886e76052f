"""Reading pose lists and writing pose results as CSV (the I/O edge of ``lutmpi solve``):
mm in files, SI inside."""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import TextIO

from lutmpi.equilibrium.result import SIDES, PoseResult
from lutmpi.errors import ConfigError

SIDE_COLUMNS = ("n_contacts", "wheel_s_mm", "contact_angle_rad", "rolling_radius_mm", "x_mm",
                "rail_v_mm", "indentation_mm")
COLUMNS = (("y_mm", "yaw_rad", "method", "status", "message", "iterations", "z_g_mm", "roll_rad",
            "x_g_mm", "pitch_rad", "kc_N_per_m", "cpu_ms")
           + tuple(f"{s}_{c}" for s in SIDES for c in SIDE_COLUMNS))


def read_poses(path: str | Path) -> list[tuple[float, float]]:
    """Poses (y in m, yaw in rad) from a CSV with columns ``y_mm,yaw_rad`` (any order, more
    columns ignored). Errors name the file and line."""
    path = str(path)
    try:
        fh = open(path, newline="")
    except OSError as exc:
        raise ConfigError(f"cannot read poses file: {exc.strerror}", path=path) from None
    with fh:
        rows = [r for r in csv.reader(fh)]
    rows = [(i + 1, r) for i, r in enumerate(rows) if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise ConfigError("no header and no poses; expected a header 'y_mm,yaw_rad'", path=path)
    header = [h.strip() for h in rows[0][1]]
    missing = [c for c in ("y_mm", "yaw_rad") if c not in header]
    if missing:
        raise ConfigError(f"line {rows[0][0]}: header lacks {missing}; expected columns "
                          f"'y_mm,yaw_rad', got {header}", path=path)
    iy, iyaw = header.index("y_mm"), header.index("yaw_rad")
    out = []
    for line, r in rows[1:]:
        try:
            y, yaw = float(r[iy]), float(r[iyaw])
        except (ValueError, IndexError):
            raise ConfigError(f"line {line}: expected two numbers y_mm, yaw_rad, got {r}",
                              path=path) from None
        if not (math.isfinite(y) and math.isfinite(yaw)) or abs(y) > 100 or abs(yaw) > 0.5:
            raise ConfigError(f"line {line}: pose out of range (|y| <= 100 mm, |yaw| <= 0.5 rad),"
                              f" got y_mm={y}, yaw_rad={yaw}", path=path)
        out.append((y * 1e-3, yaw))
    if not out:
        raise ConfigError("the file has a header but no poses", path=path)
    return out


def result_row(res: PoseResult) -> dict[str, object]:
    """One CSV row (mm, rad) for a pose result; the primary contact is the most loaded one
    (slot 0 of a table, :func:`lutmpi.table.compute.slot_order`)."""
    from lutmpi.table.compute import slot_order

    row: dict[str, object] = {
        "y_mm": res.y * 1e3, "yaw_rad": res.yaw, "method": res.method, "status": res.status,
        "message": res.message, "iterations": res.nit, "z_g_mm": res.z_g * 1e3,
        "roll_rad": res.roll, "x_g_mm": res.x_g * 1e3, "pitch_rad": res.pitch,
        "kc_N_per_m": res.kc, "cpu_ms": res.time * 1e3}
    for side in SIDES:
        cs = res.contacts[side]
        row[f"{side}_n_contacts"] = len(cs)
        c = slot_order(cs)[0] if cs else None     # the table's slot 0 (compare with `query`)
        nan = float("nan")
        row[f"{side}_wheel_s_mm"] = c.wheel_s * 1e3 if c else nan
        row[f"{side}_contact_angle_rad"] = c.contact_angle if c else nan
        row[f"{side}_rolling_radius_mm"] = c.rolling_radius * 1e3 if c else nan
        row[f"{side}_x_mm"] = c.wheel_point[0] * 1e3 if c else nan
        row[f"{side}_rail_v_mm"] = c.rail_v * 1e3 if c else nan
        row[f"{side}_indentation_mm"] = c.indentation * 1e3 if c else nan
    return row


def write_results(out: str | Path | TextIO, results: list[PoseResult]) -> None:
    """CSV with one row per pose to a path or an open text stream; column names carry units."""
    if isinstance(out, (str, Path)):
        with open(out, "w", newline="") as fh:
            write_results(fh, results)
        return
    w = csv.DictWriter(out, fieldnames=list(COLUMNS))
    w.writeheader()
    for r in results:
        w.writerow({k: (f"{v:.10g}" if isinstance(v, float) else v)
                    for k, v in result_row(r).items()})
