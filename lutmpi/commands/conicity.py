"""``lutmpi conicity (TABLE.h5 | --dr FILE.csv)``: equivalent conicity against amplitude."""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path
from typing import Any

import numpy as np


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "conicity", help="equivalent conicity vs amplitude (EN 15302 Annex B)",
        description="Equivalent conicity tan(gamma_e) against the amplitude of the kinematic "
                    "wheelset motion, by integration of the non-linear equation (EN 15302 Annex "
                    "B) with the singular end points treated exactly. Δr(y) comes from a table "
                    "(yaw = 0, r_left - r_right of the main contact) or from a CSV file of "
                    "y [mm], Δr [mm] (positive for y > 0, i.e. EN 15302's r_right - r_left with "
                    "y to the right). Prints the curve and the value at 3 mm.")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("table", nargs="?", help="lookup table (HDF5) with yaw = 0 on its grid")
    src.add_argument("--dr", metavar="CSV", help="Δr file: columns y_mm, delta_r_mm (header ok)")
    p.add_argument("--method", help="method group of the table (default: its first)")
    p.add_argument("--r0-mm", type=float, default=None,
                   help="nominal rolling radius (default: the table's, else 460)")
    p.add_argument("--e-mm", type=float, default=1500.0,
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
    import tomllib

    from lutmpi.errors import ConfigError
    from lutmpi.outpath import check_output_file
    from lutmpi.reports.conicity import conicity_curve, dr_from_table, parse_amplitudes

    for path, what in ((args.output, "CSV output"), (args.plot, "plot")):
        if path is not None:
            check_output_file(path, what)
    r0_mm = args.r0_mm
    if args.dr:
        y, dr = read_dr_csv(args.dr)
        label = Path(args.dr).name
    else:
        from lutmpi.table.h5io import read_table

        table = read_table(args.table)
        try:
            y, dr = dr_from_table(table, args.method)
        except (ValueError, KeyError) as exc:
            raise ConfigError(f"{args.table}: {exc}") from exc
        if len(y) < 3:       # e.g. every point of the table failed
            raise ConfigError(f"{args.table}: {len(y)} converged point(s) at yaw = 0, a Δr(y) "
                              "curve needs at least 3 (see `lutmpi inspect` for the statuses)")
        if r0_mm is None:
            cfg = tomllib.loads(table["attrs"].get("config_toml", ""))
            r0_mm = float(cfg.get("wheel", {}).get("nominal_radius_mm", 460.0))
        label = Path(args.table).name
    try:
        amps = parse_amplitudes(args.amplitudes)
    except ValueError as exc:
        raise ConfigError(str(exc), key="--amplitudes") from exc
    if np.polyfit(y, dr, 1)[0] <= 0:
        print("warning: Δr does not increase with y: no stable kinematic motion (check the sign "
              "convention: Δr must be positive for y > 0)", file=sys.stderr)
    res = conicity_curve(y, dr, amps, r0=(r0_mm or 460.0) * 1e-3, e=args.e_mm * 1e-3)
    print(f"# {label}: equivalent conicity, EN 15302 Annex B (r0 = {r0_mm or 460.0:g} mm, "
          f"e = {args.e_mm:g} mm)")
    print("amplitude_mm,tan_gamma_e,wavelength_m")
    for a, c, w in zip(res.amplitude, res.tan_gamma_e, res.wavelength, strict=True):
        print(f"{a * 1e3:.3f},{c:.5f},{w:.3f}")
    at3 = conicity_curve(y, dr, [3e-3]).tan_gamma_e[0]
    print(f"# tan gamma_e at 3 mm: {at3:.4f}", file=sys.stdout)
    if args.output:
        np.savetxt(args.output, np.column_stack([res.amplitude * 1e3, res.tan_gamma_e,
                                                 res.wavelength]), delimiter=",",
                   header="amplitude_mm,tan_gamma_e,wavelength_m", comments="", fmt="%.6g")
    if args.plot:
        from lutmpi.reports.plots import conicity_plot

        conicity_plot({label: (res.amplitude, res.tan_gamma_e)}, args.plot)
    return 0
