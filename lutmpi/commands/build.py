"""``lutmpi build CONFIG -o TABLE.h5``: build a lookup table, serially or under ``mpirun``."""

from __future__ import annotations

import argparse
import importlib
import logging
import os
from typing import Any

log = logging.getLogger(__name__)
# set by mpirun (Open MPI), Hydra/PMI-2, PMIx and srun: only then is MPI initialised
_LAUNCHER_VARS = ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "SLURM_PROCID")


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "build", help="build a lookup table (run under mpirun for several ranks)",
        description="Build the (y_g x yaw) lookup table of CONFIG into one HDF5 file. Under "
                    "mpirun the grid is split over the ranks and the file written collectively. "
                    "The table appears at OUT only when complete; an interrupted build leaves "
                    "OUT.partial, which --resume continues.")
    p.add_argument("config", help="configuration TOML file")
    p.add_argument("-o", "--output", required=True, help="table file to write (HDF5)")
    p.add_argument("--force", action="store_true",
                   help="overwrite an existing table and discard an unfinished build")
    p.add_argument("--resume", action="store_true",
                   help="continue OUT.partial from an interrupted build (same config)")
    p.add_argument("--method", action="append", dest="methods", metavar="NAME",
                   help="contact method to build (repeatable); default: [output] methods")
    p.add_argument("--checkpoint-interval", type=float, default=60.0, metavar="SECONDS",
                   help="minimum time between two checkpoints of OUT.partial (default 60)")
    # Test/debug hooks: a solver 'module:function' (optionally with make_scene(config) in the same
    # module) replaces the production solver; the split of points over ranks.
    p.add_argument("--solver", default=None, help=argparse.SUPPRESS)
    p.add_argument("--split", default="dynamic",
                   choices=("dynamic", "scattered", "cyclic", "block"), help=argparse.SUPPRESS)
    p.set_defaults(func=run)


def load_solver_hook(spec: str) -> tuple[Any, Any]:
    """``"module:function"`` -> ``(solver, make_scene or None)``."""
    from lutmpi.errors import ConfigError

    module_name, sep, func_name = spec.partition(":")
    try:
        module = importlib.import_module(module_name) if sep else None
        return getattr(module, func_name), getattr(module, "make_scene", None)
    except (ImportError, AttributeError) as exc:
        raise ConfigError(f"--solver expects an importable module:function, got {spec!r} "
                          f"({exc})") from exc


def run(args: argparse.Namespace) -> int:
    from lutmpi.config.load import load_config
    from lutmpi.parallel.mpi import get_comm, require_parallel_h5py
    from lutmpi.parallel.runner import build_table

    comm = None
    if any(key in os.environ for key in _LAUNCHER_VARS):
        comm = get_comm()
        if comm.size > 1:
            require_parallel_h5py()   # fail early and clearly, on every rank alike
        else:
            comm = None
    config = load_config(args.config)
    solver = scene_factory = None
    if args.solver:
        solver, scene_factory = load_solver_hook(args.solver)
        if comm is None or comm.rank == 0:
            log.warning("using solver hook %s (not the production solver)",
                        args.solver)
    build_table(config, args.output, comm, solver=solver, force=args.force, resume=args.resume,
                methods=args.methods, scene_factory=scene_factory,
                checkpoint_interval_s=args.checkpoint_interval, split=args.split)
    return 0
