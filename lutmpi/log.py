"""Rank-aware logging, configured once by the CLI.

Library code uses ``logging.getLogger(__name__)``."""

from __future__ import annotations

import logging
import sys


def _rank_size() -> tuple[int, int]:
    # The launcher's environment, not mpi4py: logging must not initialise MPI.
    from lutmpi.parallel.mpi import launched_rank_size

    return launched_rank_size() or (0, 1)


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
