"""``lutmpi conicity (TABLE.h5 | CONFIG.toml | --dr FILE.csv)``: equivalent conicity against
amplitude."""

from __future__ import annotations

import argparse
import csv
import logging
from pathlib import Path
from typing import Any

import numpy as np

log = logging.getLogger(__name__)


def register(subparsers: Any) -> None:
    from lutmpi.argtypes import positive

    p = subparsers.add_parser(
        "conicity", help="equivalent conicity vs amplitude (EN 15302 Annex B)",
        description="Equivalent conicity tan(gamma_e) against the amplitude of the kinematic "
                    "wheelset motion, by integration of the non-linear equation (EN 15302 Annex "
                    "B) with the singular end points treated exactly. Δr(y) comes from a table "
                    "(yaw = 0, r_left - r_right of the main contact, at its grid nodes, extra "
                    "knots and both sides of each contact jump), from a run config (.toml: its "
                    "y grid is solved at yaw 0 with its contact.method, serially, and its jumps "
                    "located and refined as a build does), or from a CSV file of "
                    "y [mm], Δr [mm] (positive for y > 0, i.e. EN 15302's r_right - r_left with "
                    "y to the right). Prints the curve and the value at 3 mm.")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("table", nargs="?", help="lookup table (HDF5) with yaw = 0 on its grid, or "
                     "a run config (.toml)")
    src.add_argument("--dr", metavar="CSV", help="Δr file: columns y_mm, delta_r_mm (header ok)")
    p.add_argument("--method", help="method group of the table (default: its first)")
    p.add_argument("--r0-mm", type=positive, default=None,
                   help="nominal rolling radius (default: the table's, else 460)")
    p.add_argument("--e-mm", type=positive, default=1500.0,
                   help="distance between the nominal contact points (default 1500); r0 and e "
                        "set the wavelength only, not the conicity")
    p.add_argument("--amplitudes", default="1:7.5:0.1",
                   help="mm: start:stop:step or a,b,c (default 1:7.5:0.1)")
    p.add_argument("-o", "--output", help="write amplitude, conicity, wavelength to this CSV")
    p.add_argument("--plot", help="write a PNG of conicity vs amplitude")
    p.set_defaults(func=run)


def read_dr_csv(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """``y`` and ``Δr`` in m from a two-column CSV in mm (a non-numeric first line is a header)."""
    from lutmpi.errors import ConfigError

    rows = []
    with open(path, newline="") as fh:
        for n, row in enumerate(csv.reader(fh), 1):
            if not row or row[0].lstrip().startswith("#"):
                continue
            try:
                rows.append((float(row[0]), float(row[1])))
            except (ValueError, IndexError) as exc:
                if n == 1:
                    continue                   # header
                raise ConfigError(f"line {n}: expected 'y_mm, delta_r_mm', got {row!r}",
                                  path=str(path)) from exc
    if len(rows) < 3:
        raise ConfigError("fewer than 3 rows of y_mm, delta_r_mm", path=str(path))
    data = np.array(sorted(rows)) * 1e-3
    return data[:, 0], data[:, 1]


def run(args: argparse.Namespace) -> int:
    from lutmpi.errors import ConfigError
    from lutmpi.outpath import check_output_file
    from lutmpi.reports.conicity import HoleError, check_dr, conicity_curve, parse_amplitudes

    for path, what in ((args.output, "CSV output"), (args.plot, "plot")):
        if path is not None:
            check_output_file(path, what, inputs=(args.table, args.dr))  # before the work
    r0_mm = args.r0_mm
    try:
        amps = parse_amplitudes(args.amplitudes)
    except ValueError as exc:
        raise ConfigError(str(exc), key="--amplitudes") from exc
    if args.dr:
        y, dr = read_dr_csv(args.dr)
        label = Path(args.dr).name
    elif Path(args.table).suffix.lower() == ".toml":
        y, dr, cfg_r0 = config_dr(args.table, args.method)
        r0_mm = r0_mm or cfg_r0
        label = Path(args.table).name
    else:
        y, dr, table_r0 = _table_dr(args)
        r0_mm = r0_mm or table_r0
        label = Path(args.table).name
    try:
        found = check_dr(y, dr, amps)
    except HoleError as exc:
        raise ConfigError(f"{label}: {exc}") from exc
    for line in found.warnings:
        log.warning("%s: %s", label, line)
    y, dr = found.y, found.dr
    if np.polyfit(y, dr, 1)[0] <= 0:
        log.warning("%s: Δr does not increase with y: no stable kinematic motion (check the sign "
                    "convention: Δr must be positive for y > 0)", label)
    res = conicity_curve(y, dr, amps, r0=(r0_mm or 460.0) * 1e-3, e=args.e_mm * 1e-3)
    unbounded = res.amplitude[np.isnan(res.tan_gamma_e) & ~np.isin(amps, found.beyond)]
    if unbounded.size:
        log.warning("%s: no bounded motion found for amplitudes %s mm (NaN)", label,
                    ", ".join(f"{a * 1e3:g}" for a in unbounded))
    print(f"# {label}: equivalent conicity, EN 15302 Annex B (r0 = {r0_mm or 460.0:g} mm, "
          f"e = {args.e_mm:g} mm)")
    for line in found.warnings:
        print(f"# warning: {line}")
    print("amplitude_mm,tan_gamma_e,wavelength_m")
    for a, c, w in zip(res.amplitude, res.tan_gamma_e, res.wavelength, strict=True):
        print(f"{a * 1e3:.3f},{c:.5f},{w:.3f}")
    if y.size >= 3 and min(-y[0], y[-1]) >= 3e-3:
        at3 = conicity_curve(y, dr, [3e-3]).tan_gamma_e[0]
        print(f"# tan gamma_e at 3 mm: {at3:.4f}")
    if args.output:
        np.savetxt(args.output, np.column_stack([res.amplitude * 1e3, res.tan_gamma_e,
                                                 res.wavelength]), delimiter=",",
                   header="amplitude_mm,tan_gamma_e,wavelength_m", comments="", fmt="%.6g")
    if args.plot:
        from lutmpi.reports.plots import conicity_plot

        conicity_plot({label: (res.amplitude, res.tan_gamma_e)}, args.plot)
    return 0


def config_dr(path: str | Path, method: str | None = None) -> tuple[np.ndarray, np.ndarray,
                                                                        float]:
    """``(y, Δr with NaN holes, r0 in mm)`` of a run config: its y grid solved at yaw 0 (the
    config's yaw axis is ignored) with ``method`` (default ``contact.method``), serially (one
    pose per orbit of the reflections with ``output.mirror``, as a build: on a symmetric pair
    and grid the poses y > 0 are the poses -y reflected), and
    its contact jumps located and the pieces between them refined as a build does (with
    ``output.jumps`` and ``output.refine``): Δr then steps at its jumps instead of running
    across a grid cell."""
    import dataclasses

    from lutmpi.config import load_config
    from lutmpi.parallel.jumps_step import mesh_resolution, mirror_of
    from lutmpi.reports.conicity import dr_from_table
    from lutmpi.scene import Scene
    from lutmpi.table import jumps as tj
    from lutmpi.table.compute import (
        compute_points,
        default_solver,
        empty_records,
        pose_to_record,
    )
    from lutmpi.table.grid import Grid
    from lutmpi.table.schema import (
        FIELDS,
        JUMPS_GROUP,
        KNOTS_GROUP,
        LIMITS_GROUP,
        J,
        limit_fields,
    )

    cfg = load_config(path)
    cfg = dataclasses.replace(cfg, grid=dataclasses.replace(cfg.grid, yaw_rad=(0.0, 0.0, 1)))
    name = method or cfg.contact.method
    grid = Grid.from_config(cfg.grid)
    scene, solver = Scene.from_config(cfg), default_solver()
    fields = limit_fields(FIELDS)
    # one point per orbit of the reflections (a symmetric pair: y -> -y), the others filled
    # from it, as a build's grid (Mirror.grid_plan)
    mirror = mirror_of(cfg, scene, solver, grid.y, grid.yaw)[0]
    todo = np.arange(grid.n_points)
    solved, images = mirror.grid_plan(todo) if mirror is not None else (todo, {})
    part, _ = compute_points(scene, grid, solved, [name], solver, fields)
    recs = empty_records(fields, [name], grid.n_points)
    for row, p in enumerate(solved.tolist()):
        for k, arr in recs[name].items():
            arr[p] = part[name][k][row]
        for q, g in images.get(p, []):
            g.fill_row(recs, p, q)
    group = {k: v[:, None] for k, v in recs[name].items()}   # (ny, nyaw = 1, ...)

    def solve(y: float, yaw: float) -> dict[str, np.ndarray]:
        return pose_to_record(solver(scene, y, yaw, name), fields)

    stored = {}
    if cfg.output.jumps:
        js = tj.locate_jumps(group, grid.y, grid.yaw, solve, fields, refine=cfg.output.refine,
                             mesh=mesh_resolution(scene, name), scale=cfg.output.refine_scale,
                             mirror=mirror)
        stored = {name: {"arrays": {**js.arrays, J.knot_y: js.knot_y}, KNOTS_GROUP: js.knots,
                         LIMITS_GROUP: js.limits}}
    y, dr = dr_from_table({"y": grid.y, "yaw": grid.yaw, "methods": {name: group},
                           JUMPS_GROUP: stored}, name)
    r0 = 0.5 * sum(cfg.wheel.side(s).nominal_radius_mm for s in ("left", "right"))
    return y, dr, r0


def _table_dr(args: argparse.Namespace) -> tuple[np.ndarray, np.ndarray, float]:
    """``(y, Δr with NaN holes, r0 in mm)`` of a table at yaw 0."""
    from lutmpi.errors import ConfigError
    from lutmpi.reports.conicity import dr_from_table
    from lutmpi.reports.pair import pair_info
    from lutmpi.table import Table

    table = Table.open(args.table, mask_failed=False)
    try:
        y, dr = dr_from_table(table, args.method)
    except (ValueError, KeyError) as exc:
        raise ConfigError(f"{args.table}: {exc}") from exc
    return y, dr, pair_info(table.config_toml).r0_mm
