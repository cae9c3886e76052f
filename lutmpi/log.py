"""Rank-aware logging, configured once by the CLI.

Library code uses ``logging.getLogger(__name__)``."""

from __future__ import annotations

import logging
import os
import sys


def _rank_size() -> tuple[int, int]:
    # Read Open MPI's environment rather than importing mpi4py: logging must not initialise MPI.
    for r, s in (("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"), ("PMI_RANK", "PMI_SIZE")):
        if r in os.environ:
            return int(os.environ[r]), int(os.environ.get(s, "1"))
    return 0, 1


def setup_logging(verbose: bool = False, comm: object | None = None) -> None:
    """Configure the root logger: ``rank/size`` in every line, non-root ranks at WARNING."""
    rank, size = _rank_size()
    level = logging.DEBUG if verbose else logging.INFO
    if rank != 0:
        level = max(level, logging.WARNING)
    fmt = f"%(asctime)s [{rank}/{size}] %(levelname)s %(name)s: %(message)s"
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter(fmt, datefmt="%H:%M:%S"))
    root = logging.getLogger()
    root.handlers[:] = [handler]
    root.setLevel(level)
