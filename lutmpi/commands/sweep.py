"""``lutmpi sweep SWEEP.toml -o OUTDIR``: one table per sweep member, serially or under mpirun."""

from __future__ import annotations

import argparse
import logging
from typing import Any

log = logging.getLogger(__name__)


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "sweep", help="build the table of every member of a sweep (run under mpirun)",
        description="Expand SWEEP (products/zips of config keys) and build one table per member "
                    "into OUTDIR/<member id>.h5, each with all ranks; write OUTDIR/index.csv and "
                    "index.json (parameters, status, wall and CPU time). A rerun skips members "
                    "whose complete table is there; a member that fails is recorded as failed "
                    "and the others still run.")
    p.add_argument("sweep", help="sweep TOML file")
    p.add_argument("-o", "--output", required=True, metavar="OUTDIR", help="output directory")
    p.add_argument("--force", action="store_true", help="rebuild members with a complete table")
    p.add_argument("--only", action="append", metavar="ID", help="run only this member (repeat)")
    p.add_argument("--list", action="store_true", help="list the members and exit")
    p.add_argument("--solver", default=None, help=argparse.SUPPRESS)   # test hook, as in build
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from lutmpi.parallel.mpi import command_comm
    from lutmpi.parallel.solver_hook import load_solver_hook

    if args.list:
        from lutmpi.config.sweep import expand_sweep

        for m in expand_sweep(args.sweep):
            print(f"{m.id}\t{m.params}")
        return 0
    from lutmpi.parallel.sweep_runner import run_sweep

    comm = command_comm()
    solver = scene_factory = None
    if args.solver:
        solver, scene_factory = load_solver_hook(args.solver)
        log.warning("using solver hook %s (not the production solver)", args.solver)
    summary = run_sweep(args.sweep, args.output, comm, solver=solver, scene_factory=scene_factory,
                        force=args.force, only=args.only)
    return 1 if summary.failed else 0
