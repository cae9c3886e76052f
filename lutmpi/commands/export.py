"""``lutmpi export TABLE.h5 --format F -o OUT``: a table in a format other tools read."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any


def register(subparsers: Any) -> None:
    from lutmpi.argtypes import finite
    from lutmpi.export import FORMATS, format_module

    p = subparsers.add_parser(
        "export", help="write a table as CSV, MATLAB .mat or GENSYS KPF profiles",
        description="Export a lookup table. Formats: " + "; ".join(
            f"{name}: {format_module(name).DESCRIPTION}" for name in FORMATS) + ".")
    p.add_argument("table", help="lookup table (HDF5)")
    p.add_argument("--format", required=True, choices=list(FORMATS), help="output format")
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="output file (or an existing directory: the name follows the table's)")
    p.add_argument("--yaw-rad", type=finite, default=0.0,
                   help="csv: the yaw of the 1-D functions, rad, a grid value (default 0)")
    p.add_argument("--method", default=None, help="csv: contact method (default: the first)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import sys

    from lutmpi.errors import ConfigError
    from lutmpi.export import export
    from lutmpi.outpath import check_output_dir, check_output_file

    if args.format != "csv" and args.method is not None:
        raise ConfigError(f"--method {args.method!r} applies to --format csv only: the "
                          f"{args.format} export holds "
                          + ("every method" if args.format == "mat" else "the profile pair"),
                          key="--method")
    if args.format == "csv" and args.output == "-":     # standard output, as query and solve
        from lutmpi.export.csv_format import write_to
        from lutmpi.table import Table

        write_to(sys.stdout, Table.open(args.table, mask_failed=False), yaw=args.yaw_rad,
                 method=args.method)
        return 0
    if args.format == "mat":
        from lutmpi.export.mat_format import output_path

        check_output_file(output_path(args.table, Path(args.output)), "mat output",
                          inputs=(args.table,))
    elif args.format == "kpf" and Path(args.output).is_dir():
        check_output_dir(args.output, "KPF output folder")
    elif args.format == "kpf":      # a stem: <stem>.wheel, <stem>.rail (and per side)
        from lutmpi.export.kpf_format import stem_of, with_ext

        for ext in (".wheel", ".rail"):
            check_output_file(with_ext(stem_of(Path(args.output)), ext), "KPF output",
                              inputs=(args.table,))
    else:
        check_output_file(args.output, f"{args.format} output", inputs=(args.table,))
    for path in export(args.table, args.format, args.output, yaw=args.yaw_rad,
                       method=args.method):
        print(path)
    return 0
