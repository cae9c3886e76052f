"""Thin command line: ``lutmpi <command> ...``. Each command lives in ``lutmpi/commands/<name>.py``
and exposes ``register(subparsers)`` which adds its parser and sets ``func`` (one library call).
Only this layer (and ``lutmpi/parallel``, ``lutmpi/table/h5io.py``) touches MPI."""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

from lutmpi import __version__
from lutmpi.errors import LutmpiError


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
    try:
        rc = args.func(args)
    except LutmpiError as exc:
        print(f"lutmpi {args.command}: error: {exc}", file=sys.stderr)
        return 128 + exc.signum if hasattr(exc, "signum") else 1
    except KeyboardInterrupt:     # Ctrl-C outside a build's compute loop: no traceback
        print(f"lutmpi {args.command}: interrupted", file=sys.stderr)
        return 130
    return int(rc or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
