"""``lutmpi conicity (TABLE.h5 | CONFIG.toml | --dr FILE.csv)``: equivalent conicity against
amplitude."""

from __future__ import annotations

import argparse
import logging
import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from lutmpi.reports.conicity import DrCheck

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
    src.add_argument("--dr", metavar="CSV",
                     help="Δr file (UTF-8): a header 'y_mm,delta_r_mm' (the columns read by "
                          "name, in any order), then one row per y in mm; '#' lines skipped")
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


#: the columns of a ``--dr`` file (any order, exactly these)
DR_COLUMNS = ("y_mm", "delta_r_mm")


def read_dr_csv(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """``y`` and ``Δr`` in m from a Δr file (:func:`read_dr_rows` without the line numbers)."""
    y, dr, _ = read_dr_rows(path)
    return y, dr


def read_dr_rows(path: str | Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``y`` and ``Δr`` in m from a UTF-8 CSV in mm with the header ``y_mm,delta_r_mm``.

    The columns are read by their names (any order); another column is an error naming it.
    Comment (``#``) and blank lines are skipped anywhere. The rows may come in any order; a y
    given twice is an error naming both lines. A Δr of ``nan`` is a missing value (a hole,
    see :func:`lutmpi.reports.conicity.check_dr`).

    Parameters
    ----------
    path : str or Path
        The Δr file.

    Returns
    -------
    y, dr : ndarray, shape (n,)
        m, ``y`` strictly increasing.
    lines : ndarray of int, shape (n,)
        The file's line number of each row.

    Raises
    ------
    ConfigError
        Naming the file and the line: not UTF-8, no or a wrong header, a row with the wrong
        number of fields, a value that is not a number (or an infinite one, or a NaN y), a
        repeated y, fewer than 3 rows.
    """
    from lutmpi.contact.poses import check_field_count, read_csv_records
    from lutmpi.errors import ConfigError

    path = str(path)
    records = read_csv_records(path, "Δr file")
    if not records:
        raise ConfigError(f"no header and no rows; expected a header '{','.join(DR_COLUMNS)}'",
                          path=path)
    index = _dr_header(records[0], path)
    lines, rows = [], []
    for n, row in records[1:]:
        check_field_count(n, row, [c.strip() for c in records[0][1]], path)
        try:
            y, dr = (float(row[index[c]]) for c in DR_COLUMNS)
        except ValueError:
            raise ConfigError(f"line {n}: expected two numbers {', '.join(DR_COLUMNS)}, got "
                              f"{row!r}", path=path) from None
        if not math.isfinite(y) or math.isinf(dr):
            raise ConfigError(f"line {n}: expected a finite y_mm and delta_r_mm (nan marks a "
                              f"missing Δr), got {row!r}", path=path)
        lines.append(n)
        rows.append((y, dr))
    if len(rows) < 3:
        raise ConfigError(f"{len(rows)} rows of {', '.join(DR_COLUMNS)}, expected at least 3",
                          path=path)
    data = np.array(rows)
    order = np.argsort(data[:, 0], kind="stable")
    y_mm = data[order, 0]
    same = np.flatnonzero(np.diff(y_mm) == 0)
    if same.size:
        a, b = sorted((lines[order[same[0]]], lines[order[same[0] + 1]]))
        raise ConfigError(f"lines {a} and {b}: y_mm = {y_mm[same[0]]:g} given twice; expected "
                          "one Δr per y", path=path)
    return y_mm * 1e-3, data[order, 1] * 1e-3, np.asarray(lines)[order]


def _dr_file_holes(path: str, y: np.ndarray, lines: np.ndarray) -> Callable[[np.ndarray], str]:
    """``name_holes`` of :func:`lutmpi.reports.conicity.check_dr` for a Δr file: a hole is a
    row whose ``delta_r_mm`` is ``nan``, named by its line (not a failed pose of a table)."""

    def name(ys: np.ndarray) -> str:
        at = lines[np.isin(y, ys)]
        return (f"y = {', '.join(f'{v * 1e3:g}' for v in np.sort(ys))} mm (delta_r_mm = nan "
                f"on line{'s' if at.size > 1 else ''} {', '.join(map(str, sorted(at)))} of "
                f"{path})")

    return name


def _dr_header(record: tuple[int, list[str]], path: str) -> dict[str, int]:
    """Column index of each of :data:`DR_COLUMNS` in the header ``record`` (ConfigError naming
    the line when one is missing, named twice, or another column is there)."""
    from lutmpi.errors import ConfigError

    line, header = record[0], [h.strip() for h in record[1]]
    want = f"expected the header '{','.join(DR_COLUMNS)}' (columns in any order)"
    if all(_is_number(h) for h in header):
        raise ConfigError(f"line {line}: {want}, got the numbers {header}: name the columns "
                          "(the order of a file without a header is a guess)", path=path)
    missing = [c for c in DR_COLUMNS if c not in header]
    if missing:
        raise ConfigError(f"line {line}: header lacks {missing}; {want}, got {header}",
                          path=path)
    twice = sorted({c for c in header if header.count(c) > 1})
    if twice:
        raise ConfigError(f"line {line}: the header names {twice} more than once; {want}",
                          path=path)
    other = [c for c in header if c not in DR_COLUMNS]
    if other:
        raise ConfigError(f"line {line}: unexpected column(s) {other}; {want}", path=path)
    return {c: header.index(c) for c in DR_COLUMNS}


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


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
    holes: dict[str, Any] = {}
    if args.dr:
        y, dr, lines = read_dr_rows(args.dr)
        label = Path(args.dr).name
        holes = {"name_holes": _dr_file_holes(args.dr, y, lines),
                 "remedy": "give those rows their Δr"}
    elif Path(args.table).suffix.lower() == ".toml":
        y, dr, cfg_r0 = config_dr(args.table, args.method)
        r0_mm = r0_mm or cfg_r0
        label = Path(args.table).name
    else:
        y, dr, table_r0 = _table_dr(args)
        r0_mm = r0_mm or table_r0
        label = Path(args.table).name
    try:
        found = check_dr(y, dr, amps, **holes)
    except HoleError as exc:
        raise ConfigError(f"{label}: {exc}") from exc
    for line in found.warnings:
        log.warning("%s: %s", label, line)
    y, dr = found.y, found.dr
    if y.size < 3:
        raise ConfigError(f"{label}: {y.size} Δr values in the run around y = 0 that holds no "
                          "missing value, expected at least 3")
    if np.polyfit(y, dr, 1)[0] <= 0:
        log.warning("%s: Δr does not increase with y: no stable kinematic motion (check the sign "
                    "convention: Δr must be positive for y > 0)", label)
    res = conicity_curve(y, dr, amps, r0=(r0_mm or 460.0) * 1e-3, e=args.e_mm * 1e-3)
    unbounded = res.amplitude[np.isnan(res.tan_gamma_e) & ~np.isin(amps, found.beyond)]
    if not np.isfinite(res.tan_gamma_e).any():   # nothing to print but NaN: a failed command
        raise ConfigError(f"{label}: no conicity at any of the {amps.size} amplitudes: "
                          + _why_none(found, unbounded))
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


def _why_none(found: DrCheck, unbounded: np.ndarray) -> str:
    """Why no amplitude has a conicity: those beyond the usable Δr data, those without a
    bounded motion (``found`` a :class:`~lutmpi.reports.conicity.DrCheck`, lengths in m)."""
    parts = []
    if found.beyond.size and found.y.size:
        parts.append(f"{_mm(found.beyond)} mm beyond the usable Δr data (y from "
                     f"{found.y[0] * 1e3:g} to {found.y[-1] * 1e3:g} mm)")
    if unbounded.size:
        parts.append(f"{_mm(unbounded)} mm without a bounded motion (Δr must increase "
                     "through its zero, positive for y > 0)")
    return "; ".join(parts)


def _mm(values: np.ndarray) -> str:
    """Amplitudes in m as a short mm list (first and last of a long one)."""
    v = np.asarray(values) * 1e3
    return ", ".join(f"{a:g}" for a in v) if v.size <= 4 else f"{v[0]:g} to {v[-1]:g}"


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
