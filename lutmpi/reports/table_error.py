"""A table's own interpolation error against its cost (issue 11): pure metrics, no HDF5.

Test poses are off the grid and off the knots -- a point :data:`CELL_FRACTION` into every grid
cell along y at every yaw column (and, for a 2-D table, at the middle between yaw columns) plus
seeded uniform random poses -- and each is
checked against a direct solve with the table's own method. Per quantity (the primary contact's
rolling radius and contact angle of each wheel, z_g, roll) the report gives the max and RMS
error near the located jumps (within ``near_m``) and away from them, for the jump-aware
interpolation and for plain linear interpolation over the grid nodes, with the table's build time,
file size and knot count. Given an error target, :func:`cheapest` names the cheapest table (least
build time) that meets it away from the jumps.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from lutmpi.table.schema import D, J

#: quantity -> (scale to display units, unit)
QUANTITIES = {D.rolling_radius: (1e6, "um"), D.contact_angle: (1e3, "mrad"),
              D.z_g: (1e6, "um"), D.roll: (1e6, "urad")}
INTERPOLATIONS = ("jump_aware", "linear")
NEAR_M = 2e-5
#: where in each grid cell along y the test poses sit: not a dyadic fraction, so never a knot
#: of the build's bisection or refinement (both halve intervals; a cell midpoint is the
#: refinement's first knot, where the table answers with a stored solve and errs by nothing)
CELL_FRACTION = 0.3


def test_poses(y_axis: np.ndarray, yaw_axis: np.ndarray, n_random: int = 100, seed: int = 11
               ) -> tuple[np.ndarray, np.ndarray]:
    """Off-grid poses (m, rad): :data:`CELL_FRACTION` into every grid cell in y at every yaw
    column (and between yaw columns, at the same y), then ``n_random`` seeded uniform poses
    inside the grid."""
    ym = y_axis[:-1] + CELL_FRACTION * (y_axis[1:] - y_axis[:-1])
    cols = list(yaw_axis)
    if yaw_axis.size > 1:
        cols += list(0.5 * (yaw_axis[1:] + yaw_axis[:-1]))
    y = np.concatenate([ym for _ in cols])
    yaw = np.concatenate([np.full(ym.size, c) for c in cols])
    rng = np.random.default_rng(seed)
    ry = rng.uniform(y_axis[0], y_axis[-1], n_random)
    ryaw = (rng.uniform(yaw_axis[0], yaw_axis[-1], n_random) if yaw_axis.size > 1
            else np.full(n_random, yaw_axis[0]))
    return np.concatenate([y, ry]), np.concatenate([yaw, ryaw])


def _primary(values: np.ndarray, name: str) -> np.ndarray:
    """(n,) scalar quantity or (n, 2) primary contact per wheel."""
    v = np.asarray(values, float)
    return v[:, :, 0] if v.ndim == 3 else v[:, None]


@dataclass(frozen=True)
class TableError:
    """Errors of one table. ``stats[interp][quantity][region] = (max, rms, count)`` in SI
    (region ``"away"`` / ``"near"`` the jumps); ``build_s``: the build's wall time plus the
    jump step of this method (s); ``refine_scale``: the factor on the refinement's tolerances
    it was built with (``output.refine_scale``; 1 for a table older than the setting)."""

    name: str
    n_poses: int
    n_failed: int
    stats: dict[str, dict[str, dict[str, tuple[float, float, int]]]]
    build_s: float
    file_bytes: int
    knots: int
    jumps: int
    refine_scale: float = 1.0

    def max_away(self, quantity: str, interp: str = "jump_aware") -> float:
        return self.stats[interp][quantity]["away"][0]


def measure(table: Any, solve: Callable[[float, float], dict[str, np.ndarray]],
            method: str | None = None, *, n_random: int = 100, near_m: float = NEAR_M,
            name: str | None = None) -> TableError:
    """Interpolation errors of ``table`` at :func:`test_poses`, against ``solve``.

    Parameters
    ----------
    table : lutmpi.table.Table
    solve : callable
        ``solve(y, yaw) -> record`` (schema field name -> array): a direct solve with the
        table's method.
    method : str, optional
    n_random : int
    near_m : float
        Poses within this distance of a located jump count as "near", m.
    """
    method = method or table.methods[0]
    y, yaw = test_poses(table.y, table.yaw, n_random)
    recs = [solve(float(a), float(b)) for a, b in zip(y, yaw, strict=True)]
    ok = np.array([int(r[D.status]) == 0 for r in recs])
    names = [q for q in QUANTITIES if q in table.quantities]
    direct = {q: _primary(np.stack([np.asarray(r[q], float) for r in recs]), q) for q in names}
    stats: dict[str, dict[str, dict[str, tuple[float, float, int]]]] = {}
    dist = table.interp(y, yaw, method, names, info=True)["jump_distance"]
    near = np.abs(dist) <= near_m
    for interp in INTERPOLATIONS:
        q = table.interp(y, yaw, method, names, jump_aware=interp == "jump_aware")
        stats[interp] = {}
        for name_ in names:
            a, b = _primary(q[name_], name_), direct[name_]
            err = np.where(np.isnan(a) & np.isnan(b), 0.0, np.where(
                np.isnan(a) ^ np.isnan(b), np.inf, np.abs(a - b)))
            stats[interp][name_] = {region: _stat(err[ok & mask])
                                    for region, mask in (("away", ~near), ("near", near))}
    knots = int(np.isfinite(table.jumps[method]["arrays"][J.knot_y]).sum()) \
        if method in table.jumps else 0
    jattrs = table.jumps[method]["attrs"] if method in table.jumps else {}
    post = float(jattrs.get("wall_time_s", 0.0))
    return TableError(name or os.path.basename(table.path), int(y.size), int((~ok).sum()), stats,
                      float(table.attrs.get("wall_time_s", math.nan)) + post,
                      os.path.getsize(table.path), table.y.size * table.yaw.size + knots,
                      int(np.isfinite(table.jump_positions(method)).sum()),
                      float(jattrs.get("refine_scale", 1.0)))


def _stat(err: np.ndarray) -> tuple[float, float, int]:
    """(max, RMS, count); a contact present on one side only (table or direct solve) is an
    infinite error, left out of the RMS."""
    e = err
    if not e.size:
        return (math.nan, math.nan, 0)
    fin = e[np.isfinite(e)]
    return (float(e.max()), float(np.sqrt(np.mean(fin ** 2))) if fin.size else math.nan,
            int(e.shape[0]))


def cheapest(results: Sequence[TableError], target: dict[str, float]) -> TableError | None:
    """The table of least build time whose jump-aware max error away from the jumps meets every
    target (quantity -> SI value); None if none does."""
    good = [r for r in results if all(r.max_away(q) <= v for q, v in target.items())]
    return min(good, key=lambda r: r.build_s) if good else None


def markdown(results: Sequence[TableError], target: dict[str, float] | None = None) -> str:
    """The report section: one table of errors per table file, then the cheapest grid."""
    lines = ["## Table error against run time", "",
             f"Off-grid poses ({CELL_FRACTION:g} into every grid cell along y, off the knots, "
             "and seeded random poses) checked by direct solves with the table's method; near = "
             f"within {NEAR_M * 1e3:.3f} mm of a located jump.",
             "", "| table | poses | build s | MB | knots | jumps | refine scale | quantity | "
             "jump-aware max away | RMS away | max near | linear max away | linear RMS away | "
             "linear max near |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        for q, (scale, unit) in QUANTITIES.items():
            if q not in r.stats["jump_aware"]:
                continue
            a, b = r.stats["jump_aware"][q], r.stats["linear"][q]
            lines.append(
                f"| {r.name} | {r.n_poses} | {r.build_s:.2f} | {r.file_bytes / 1e6:.2f} | "
                f"{r.knots} | {r.jumps} | {r.refine_scale:g} | {q} ({unit}) | "
                f"{a['away'][0] * scale:.3g} | "
                f"{a['away'][1] * scale:.3g} | {a['near'][0] * scale:.3g} | "
                f"{b['away'][0] * scale:.3g} | {b['away'][1] * scale:.3g} | "
                f"{b['near'][0] * scale:.3g} |")
    if target:
        best = cheapest(results, target)
        want = ", ".join(f"{q} <= {v * QUANTITIES[q][0]:g} {QUANTITIES[q][1]}"
                         for q, v in target.items())
        lines += ["", f"Target ({want}, away from jumps): " + (
            f"cheapest table **{best.name}** ({best.build_s:.2f} s to build)" if best
            else "no table meets it: refine the grid (or lower output.refine_scale)")]
    return "\n".join(lines) + "\n"
