"""``lutmpi report (T.h5 | OUTDIR) -o REPORT``: the geometry report of one table, or the convergence
/ wear report of a sweep directory."""

from __future__ import annotations

import argparse
from typing import Any


def register(subparsers: Any) -> None:
    from lutmpi.argtypes import within

    p = subparsers.add_parser(
        "report", help="geometry report of a table, or convergence report of a sweep",
        description="For a table (T.h5): report.md with the contact-geometry functions of y "
                    "(Δr, rolling radii, contact angles in degrees, Δtanγ, roll, z_g), the contact "
                    "points on both profiles, the pair to scale, the equivalent conicity and the "
                    "indices (Polach's nonlinearity parameter, rolling-radii coefficient), the "
                    "contact lead against yaw and the status maps. "
                    "For a sweep directory: for each method x mesh member, max and RMS errors of "
                    "z_g, roll, contact positions on wheel and rail, contact angle and normal "
                    "direction against a reference table, CPU and wall time, and the observed "
                    "order. Writes REPORT/report.md, errors.csv and PNG plots; for wear sweeps "
                    "also Δr(y), contact angle, roll and equivalent conicity per member.")
    p.add_argument("outdir", help="a table file, or a directory written by lutmpi sweep")
    p.add_argument("-o", "--output", required=True, metavar="REPORT", help="report directory")
    p.add_argument("--reference", choices=("reference", "finest"), default="reference",
                   help="error reference: the semi-analytic solver's member (default) or each "
                        "method's finest mesh")
    p.add_argument("--wear", action=argparse.BooleanOptionalAction, default=None,
                   help="force the wear/conicity section on or off (default: when the sweep "
                        "varies profiles or wear)")
    p.add_argument("--method", default=None, help="table: contact method (default: the first)")
    p.add_argument("--at-y-mm", type=within(100.0), nargs="+", default=None, metavar="Y",
                   help="table: lateral shifts drawn to scale (default: 0 and the largest y)")
    p.add_argument("--en15302-case", default=None, metavar="E1..E9",
                   choices=[f"E{k}" for k in range(1, 10)],
                   help="table: draw this EN 15302 Annex E case's conicity tolerance band")
    # -- issue 11: the table-error section (jumps) --------------------------------------------
    p.add_argument("--table-error", nargs="*", default=None, metavar="OTHER.h5",
                   help="table: measure its interpolation error at off-grid poses against direct "
                        "solves (and that of OTHER tables of the same pair, e.g. other densities),"
                        " jump-aware vs linear, against build time and size; writes "
                        "REPORT/table_error.md")
    p.add_argument("--error-target", nargs="+", default=None, metavar="Q=V", type=error_target,
                   help="with --table-error: name the cheapest table meeting e.g. "
                        "rolling_radius=5e-6 contact_angle=5e-4 (V a number > 0 in SI: m for "
                        "rolling_radius and z_g, rad for contact_angle and roll; no unit suffix)")
    p.set_defaults(func=run)


def error_target(text: str) -> tuple[str, float]:
    """``Q=V`` of ``--error-target``: a quantity of the table-error report and a finite V > 0 in
    its SI unit (the schema's: m or rad); anything else is an argparse usage error (exit 2, the
    option named), given before any table is opened or pose solved."""
    import math

    from lutmpi.reports.table_error import QUANTITIES
    from lutmpi.table.schema import FIELDS_BY_NAME

    key, sep, value = text.partition("=")
    key = key.strip()
    if not sep or key not in QUANTITIES:
        raise argparse.ArgumentTypeError(
            f"expected Q=V with Q one of {', '.join(QUANTITIES)}, got {text!r}")
    unit = FIELDS_BY_NAME[key].units
    try:
        v = float(value)
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and v > 0.0):
        example = {"m": "5 um is 5e-6", "rad": "0.5 mrad is 5e-4"}.get(unit, "")
        raise argparse.ArgumentTypeError(
            f"{key}: expected a number > 0 in {unit} (SI, no unit suffix: {example}), got "
            f"{value.strip()!r}")
    return key, v


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from lutmpi.errors import ConfigError
    from lutmpi.outpath import check_output_dir

    if args.error_target and args.table_error is None:
        raise ConfigError("takes effect only with --table-error (the table-error section)",
                          key="--error-target")
    if Path(args.outdir).is_dir():   # a sweep folder: the options of one table do not apply
        given = [name for name, value in (("--method", args.method), ("--at-y-mm", args.at_y_mm),
                                          ("--en15302-case", args.en15302_case),
                                          ("--table-error", args.table_error)) if value is not None]
        if given:
            raise ConfigError(f"{args.outdir} is a sweep folder; {', '.join(given)} appl"
                              f"{'ies' if len(given) == 1 else 'y'} to one table (T.h5): give "
                              "a member's table, e.g. "
                              f"{Path(args.outdir) / '<member>.h5'}", key=given[0])
    elif Path(args.outdir).is_file() and (args.reference != "reference" or args.wear is not None):
        raise ConfigError(f"{args.outdir}: --reference and --wear apply to a sweep folder, not "
                          "to one table", key="--reference" if args.reference != "reference"
                          else "--wear")
    check_output_dir(args.output, "report folder")
    if args.table_error is not None:
        return _table_error(args)
    if Path(args.outdir).is_file():
        from lutmpi.reports.table_report import build_table_report

        print(build_table_report(args.outdir, args.output, method=args.method,
                                 at_y_mm=tuple(args.at_y_mm) if args.at_y_mm else None,
                                 band_case=args.en15302_case))
        return 0
    from lutmpi.reports.report import build_report

    path = build_report(args.outdir, args.output, reference=args.reference, wear=args.wear)
    print(path)
    return 0


# -- issue 11: the table-error section (owner: jumps) ---------------------------------------------
def _table_error(args: argparse.Namespace) -> int:
    """``--table-error``: :mod:`lutmpi.reports.table_error` on the table(s), direct solves with
    each table's own stored config and method."""
    from pathlib import Path

    from lutmpi.pose.solve import solve_pose, warm
    from lutmpi.reports import table_error
    from lutmpi.scene import Scene
    from lutmpi.table import Table
    from lutmpi.table.compute import pose_to_record
    from lutmpi.table.schema import FIELDS

    target = dict(args.error_target or [])   # (Q, V in SI), checked by error_target
    results = []
    for path in [args.outdir, *args.table_error]:
        table = Table.open(path)
        method = args.method or table.methods[0]
        scene = Scene.from_config(table.built_config())   # its profiles, unchanged

        def solve(y: float, yaw: float, scene: object = scene, method: str = method) -> dict:
            return pose_to_record(solve_pose(scene, y, yaw, method), FIELDS)

        warm(scene, method)   # kernels loaded outside the first pose's time budget

        results.append(table_error.measure(table, solve, method))
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    text = table_error.markdown(results, target or None)
    (out / "table_error.md").write_text(text)
    print(text)
    return 0
