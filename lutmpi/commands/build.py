"""``lutmpi build CONFIG -o TABLE.h5``: build a lookup table, serially or under ``mpirun``."""

from __future__ import annotations

import argparse
import logging
from typing import Any

log = logging.getLogger(__name__)

#: exit status of a build that wrote its table but in which no grid point converged
NO_POINT_CONVERGED = 3


def register(subparsers: Any) -> None:
    from lutmpi.argtypes import nonnegative

    p = subparsers.add_parser(
        "build", help="build a lookup table (run under mpirun for several ranks)",
        description="Build the (y_g x yaw) lookup table of CONFIG into one HDF5 file. Under "
                    "mpirun the grid is split over the ranks and the file written collectively. "
                    "The table appears at OUT only when complete; an interrupted build leaves "
                    "OUT.journal/ (every computed point, checksummed), which --resume continues. "
                    "OUT.lock keeps a second build of the same OUT out.")
    p.add_argument("config", help="configuration TOML file")
    p.add_argument("-o", "--output", required=True, help="table file to write (HDF5)")
    p.add_argument("--force", action="store_true",
                   help="overwrite an existing table and discard an unfinished build")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted build from OUT.journal/ (same inputs by content "
                        "hash; the profiles and config may have moved)")
    p.add_argument("--method", action="append", dest="methods", metavar="NAME",
                   help="contact method to build (repeatable); default: [output] methods")
    p.add_argument("--checkpoint-interval", type=nonnegative, default=10.0, metavar="SECONDS",
                   help="longest time a computed point waits for fsync in OUT.journal/ (default "
                        "10; every point is written there the moment it is computed)")
    # Test/debug hooks: a solver 'module:function' (optionally with make_scene(config) in the same
    # module) replaces the production solver; the split of points over ranks.
    p.add_argument("--solver", default=None, help=argparse.SUPPRESS)
    p.add_argument("--split", default="dynamic",
                   choices=("dynamic", "scattered", "cyclic", "block"), help=argparse.SUPPRESS)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from lutmpi.config.load import load_config
    from lutmpi.outpath import check_not_input
    from lutmpi.parallel.comm import root_decides
    from lutmpi.parallel.mpi import command_comm
    from lutmpi.parallel.runner import build_table
    from lutmpi.parallel.solver_hook import load_solver_hook
    from lutmpi.table.provenance import input_files

    comm = command_comm()
    if comm is not None:   # a bad config: rank 0's error on every rank, printed once
        root_decides(comm, lambda: load_config(args.config).text)
    config = load_config(args.config)
    # never over an input: ``-o`` given the config or a profile file (--force would replace it)
    inputs = (args.config, *input_files(config).values())
    if comm is not None:
        root_decides(comm, lambda: check_not_input(args.output, "table output", inputs))
    else:
        check_not_input(args.output, "table output", inputs)
    solver = scene_factory = None
    if args.solver:
        solver, scene_factory = load_solver_hook(args.solver)
        if comm is None or comm.rank == 0:
            log.warning("using solver hook %s (not the production solver)",
                        args.solver)
    summary = build_table(config, args.output, comm, solver=solver, force=args.force,
                          resume=args.resume, methods=args.methods, scene_factory=scene_factory,
                          checkpoint_interval_s=args.checkpoint_interval, split=args.split)
    if summary.points and not summary.status_counts.get("converged"):
        # a table of statuses only: written, but no batch script may take it for a result
        if comm is None or comm.rank == 0:
            log.error("no grid point of %s converged (%s): the table holds no number. A "
                      "wheelset that misses its rails everywhere often is a unit slip in the "
                      "config (a length in m under a *_mm key: [wheelset] back_to_back_mm, "
                      "gauge_mm, tape_offset_mm); `lutmpi check %s` says why",
                      args.output, summary.status_counts, args.config)
        return NO_POINT_CONVERGED
    return 0
