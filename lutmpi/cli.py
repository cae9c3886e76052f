"""Thin command line: ``lutmpi <command> ...``. Each command lives in ``lutmpi/commands/<name>.py``
and exposes ``register(subparsers)`` which adds its parser and sets ``func`` (one library call).
Only this layer (and ``lutmpi/parallel``, ``lutmpi/table/h5io.py``) touches MPI."""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import pkgutil
import sys
from typing import NoReturn

import lutmpi
from lutmpi import __version__
from lutmpi.errors import LutmpiError
from lutmpi.parallel.comm import raised_on_root


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="lutmpi",
        description="Wheel-rail contact lookup tables built with MPI "
                    "(Bozzone, Pennestri, Salvini 2011).")
    parser.add_argument("--version", action="version", version=f"lutmpi {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="debug logging")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    import lutmpi.commands as commands

    for mod in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if mod.name.startswith("_"):
            continue
        module = importlib.import_module(f"lutmpi.commands.{mod.name}")
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    from lutmpi.log import setup_logging

    setup_logging(verbose=args.verbose, comm=getattr(args, "comm", None))
    if lutmpi.CACHE_NOTE:   # each rank's own cache folder: every rank that has one says so
        logging.getLogger("lutmpi").warning("%s", lutmpi.CACHE_NOTE)
    try:
        rc = args.func(args)
    except LutmpiError as exc:
        if not raised_on_root(exc):   # rank 0 prints what it decided for every rank, once
            print(f"lutmpi {args.command}: error: {exc}", file=sys.stderr)
        return 128 + exc.signum if hasattr(exc, "signum") else 1
    except KeyboardInterrupt:     # Ctrl-C outside a build's compute loop: no traceback
        print(f"lutmpi {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:       # the reader of standard output went away (``| head``)
        try:                      # nothing more reaches it; Python's own flush at exit must
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # not complain
        except OSError:
            pass
        return 141               # as a process ended by SIGPIPE (128 + 13)
    except OSError as exc:        # a file the command reads or writes: its path and the reason
        name = f": {exc.filename}" if exc.filename else ""
        print(f"lutmpi {args.command}: error: {exc.strerror or exc}{name}", file=sys.stderr)
        return 1
    return int(rc or 0)


def run() -> NoReturn:
    """The ``lutmpi`` console script: :func:`main`, then, on success, the process ends at once.

    Python's own end tears down every module and object, and with numba's compiled kernels
    loaded that costs 0.3-0.5 s per process (LLVM's code and modules freed one by one;
    BENCHMARKS.md), on every rank, after the work is done. A command that succeeded has closed
    its files (tables, journals and locks are closed or renamed before :func:`main` returns):
    logging and the standard streams are flushed, MPI is finalized when it was started, and
    ``os._exit`` ends the process. A failed command ends the usual way.
    """
    rc = main()
    if rc == 0:
        _end_now()
    sys.exit(rc)


def _end_now() -> None:
    """Flush, finalize MPI (when started) and ``os._exit(0)``; return if a flush fails (the
    caller then ends the usual way, which reports it)."""
    logging.shutdown()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        return
    mpi = sys.modules.get("mpi4py.MPI")
    if mpi is not None and mpi.Is_initialized() and not mpi.Is_finalized():
        mpi.Finalize()
    os._exit(0)


if __name__ == "__main__":  # pragma: no cover
    run()
