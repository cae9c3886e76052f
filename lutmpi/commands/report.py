"""``lutmpi report OUTDIR -o REPORT``: convergence / wear report of a sweep directory."""

from __future__ import annotations

import argparse
from typing import Any


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "report", help="convergence report of a sweep: error against run time",
        description="For each method x mesh member of a sweep directory: max and RMS errors of "
                    "z_g, roll, contact positions on wheel and rail, contact angle and normal "
                    "direction against a reference table, CPU and wall time, and the observed "
                    "order. Writes REPORT/report.md, errors.csv and PNG plots; for wear sweeps "
                    "also Δr(y), contact angle, roll and equivalent conicity per member.")
    p.add_argument("outdir", help="directory written by lutmpi sweep")
    p.add_argument("-o", "--output", required=True, metavar="REPORT", help="report directory")
    p.add_argument("--reference", choices=("reference", "finest"), default="reference",
                   help="error reference: the semi-analytic solver's member (default) or each "
                        "method's finest mesh")
    p.add_argument("--wear", action=argparse.BooleanOptionalAction, default=None,
                   help="force the wear/conicity section on or off (default: when the sweep "
                        "varies profiles or wear)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from lutmpi.outpath import check_output_dir
    from lutmpi.reports.report import build_report

    check_output_dir(args.output, "report folder")

    path = build_report(args.outdir, args.output, reference=args.reference, wear=args.wear)
    print(path)
    return 0
