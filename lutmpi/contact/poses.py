"""Reading pose lists (the input edge of ``lutmpi solve``): mm in files, SI inside. The results
are written by ``lutmpi.commands.solve`` with the schema's columns."""

from __future__ import annotations

import csv
import math
from pathlib import Path

from lutmpi.errors import ConfigError

#: the largest |y_g| (mm) and |yaw| (rad) a pose may have: the config's grid limits
Y_MAX_MM, YAW_MAX_RAD = 100.0, 0.5


def check_pose(y_mm: float, yaw: float, where: str, path: str | None = None) -> None:
    """Raise :class:`ConfigError` naming ``where`` (a file line, a command-line option) when a
    pose is not finite or lies beyond :data:`Y_MAX_MM` / :data:`YAW_MAX_RAD`."""
    if not (math.isfinite(y_mm) and math.isfinite(yaw)) or abs(y_mm) > Y_MAX_MM \
            or abs(yaw) > YAW_MAX_RAD:
        raise ConfigError(f"{where}: pose out of range (|y| <= {Y_MAX_MM:g} mm, |yaw| <= "
                          f"{YAW_MAX_RAD:g} rad), got y_mm={y_mm}, yaw_rad={yaw}", path=path)


def read_poses(path: str | Path) -> list[tuple[float, float]]:
    """Poses (y in m, yaw in rad) from a CSV with columns ``y_mm,yaw_rad`` (any order, more
    columns ignored). Errors name the file and line."""
    path = str(path)
    try:
        fh = open(path, newline="", encoding="utf-8-sig")   # a BOM (Excel's CSV) is no text
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
    twice = sorted({c for c in ("y_mm", "yaw_rad") if header.count(c) > 1})
    if twice:
        raise ConfigError(f"line {rows[0][0]}: the header names {twice} more than once, got "
                          f"{header}", path=path)
    iy, iyaw = header.index("y_mm"), header.index("yaw_rad")
    out = []
    for line, r in rows[1:]:
        try:
            y, yaw = float(r[iy]), float(r[iyaw])
        except (ValueError, IndexError):
            raise ConfigError(f"line {line}: expected two numbers y_mm, yaw_rad, got {r}",
                              path=path) from None
        check_pose(y, yaw, f"line {line}", path)
        out.append((y * 1e-3, yaw))
    if not out:
        raise ConfigError("the file has a header but no poses", path=path)
    return out
