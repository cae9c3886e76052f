"""``lutmpi inspect TABLE.h5``: what a table holds (metadata, grid, methods, status, ranges)."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from lutmpi.table.schema import D, J


def register(subparsers: Any) -> None:
    p = subparsers.add_parser("inspect", help="describe a lookup table file",
                              description="Print a table's metadata, grid, methods, status counts "
                                          "and the range and units of every quantity.")
    p.add_argument("table", help="table file (HDF5)")
    p.add_argument("--config", action="store_true", help="also print the stored config TOML")
    p.set_defaults(func=run)


def describe(table: Any, show_config: bool = False) -> str:
    """The text ``lutmpi inspect`` prints for a :class:`lutmpi.table.Table`."""
    a = table.attrs
    lines = [f"table      {table.path}",
             f"schema     {a.get('schema_version')}   complete {bool(a.get('complete'))}",
             f"lutmpi     {a.get('lutmpi_version')}   git {a.get('git_commit') or 'unknown'}",
             f"created    {a.get('created_utc')}   ranks {a.get('ranks')}   "
             f"grid wall {float(a.get('wall_time_s', float('nan'))):.2f} s",
             f"grid       y   {table.y.size:4d} points  {table.y[0] * 1e3:+.3f} .. "
             f"{table.y[-1] * 1e3:+.3f} mm",
             f"           yaw {table.yaw.size:4d} points  {table.yaw[0]:+.4f} .. "
             f"{table.yaw[-1]:+.4f} rad",
             f"methods    {', '.join(table.methods)}"]
    for method in table.methods:
        lines.append(f"\n[{method}]  status: " + ", ".join(
            f"{k} {v}" for k, v in table.status_counts(method).items()))
        lines += _failed_lines(table, method)
        ct = table.get(D.compute_time, method, raw=True) if D.compute_time in table.quantities \
            else None
        stored = table.jumps.get(method)
        if ct is not None:   # the run's own clock, on one line: the grid's points, the jump step
            step = "" if stored is None else (
                f"; jump step wall {float(stored['attrs'].get('wall_time_s', np.nan)):.2f} s")
            lines.append(f"  compute time per point: mean {np.nanmean(ct) * 1e3:.1f} ms, "
                         f"max {np.nanmax(ct) * 1e3:.1f} ms, total {np.nansum(ct):.1f} s{step}")
        lines += _jump_lines(stored)
        lines.append(f"  {'quantity':24s} {'shape':>16s} {'units':>6s} {'min':>12s} "
                     f"{'max':>12s} {'NaN %':>6s}")
        for name in table.quantities:
            arr = table.get(name, method, raw=True)
            lines.append("  " + _row(name, arr, table.units(name, method)))
    if show_config:
        lines += ["", "# stored configuration", table.config_toml]
    return "\n".join(lines)


#: failed grid points listed per method (the rest counted)
MAX_FAILED_LISTED = 20


def _failed_lines(table: Any, method: str) -> list[str]:
    """The grid points of ``method`` that did not converge: ``y`` (mm), yaw (rad) and status,
    at most :data:`MAX_FAILED_LISTED` of them (lookups there read NaN)."""
    from lutmpi.equilibrium.result import CONVERGED, STATUS

    status = table.get(D.status, method, raw=True)
    bad = np.argwhere(status != CONVERGED)
    if not bad.size:
        return []
    out = [f"  did not converge ({len(bad)} grid points; lookups there read NaN):"]
    for iy, j in bad[:MAX_FAILED_LISTED]:
        code = int(status[iy, j])
        out.append(f"    y {table.y[iy] * 1e3:+9.3f} mm  yaw {table.yaw[j]:+.5f} rad  "
                   f"{STATUS.get(code, str(code)).split(':')[0]}")
    if len(bad) > MAX_FAILED_LISTED:
        out.append(f"    ... and {len(bad) - MAX_FAILED_LISTED} more")
    return out


def _jump_lines(stored: dict[str, Any] | None) -> list[str]:
    """The jump step's summary of one method (issue 11) from its stored jumps group
    (:attr:`lutmpi.table.Table.jumps`): jumps located, per yaw column at most, extra knots and
    the refinement's scale (its wall time is on the compute-time line); none stored: say so."""
    if stored is None:
        return ["  jumps: none stored (built with output.jumps = false, or before jumps were "
                "located, or an empty grid): lookups between grid points interpolate across "
                "contact jumps"]
    jy = np.asarray(stored["arrays"][J.jump_y], float)
    knots = stored["arrays"].get(J.knot_y)
    n_knots = 0 if knots is None else int(np.isfinite(np.asarray(knots, float)).sum())
    per = np.isfinite(jy).sum(axis=1) if jy.size else np.zeros(1, int)
    at = stored["attrs"]
    return [f"  jumps: {int(per.sum())} located (per yaw column at most {int(per.max())}), "
            f"{n_knots} extra knots, refine_scale {float(at.get('refine_scale', 1.0)):g}"]


def _row(name: str, arr: np.ndarray, units: str) -> str:
    finite = arr[np.isfinite(arr)] if arr.dtype.kind == "f" else arr.ravel()
    lo, hi = (f"{finite.min():12.5g}", f"{finite.max():12.5g}") if finite.size else ("-", "-")
    nan = 100.0 * np.isnan(arr).mean() if arr.dtype.kind == "f" else 0.0
    return f"{name:24s} {str(arr.shape):>16s} {units:>6s} {lo:>12s} {hi:>12s} {nan:6.1f}"


def run(args: argparse.Namespace) -> int:
    from lutmpi.table import Table

    print(describe(Table.open(args.table), args.config))
    return 0
