"""CLI subcommands, one module each, discovered by :mod:`lutmpi.cli`."""
