"""Errors per concern. Messages say what was expected, what was found, and where (file, line, key,
grid point). Only programming errors raise anything else."""

from __future__ import annotations


class LutmpiError(Exception):
    """Base class of every error lutmpi raises on purpose."""


class ProfileError(LutmpiError, ValueError):
    """A profile file or profile data is malformed (names the file and line when known)."""

    def __init__(self, message: str, *, path: str | None = None, line: int | None = None):
        where = ""
        if path is not None:
            where = f"{path}"
            if line is not None:
                where += f":{line}"
            where += ": "
        super().__init__(where + message)
        self.path = path
        self.line = line


class ConfigError(LutmpiError, ValueError):
    """A configuration or sweep file is invalid (names the key and the file)."""

    def __init__(self, message: str, *, path: str | None = None, key: str | None = None):
        where = ""
        if path is not None:
            where += f"{path}: "
        if key is not None:
            where += f"[{key}] "
        super().__init__(where + message)
        self.path = path
        self.key = key


class GeometryError(LutmpiError, ValueError):
    """Wheel/rail/track geometry cannot be built (e.g. no gauge point within the gauge depth)."""


class ConvergenceError(LutmpiError, RuntimeError):
    """Raised only where a caller asked for an exception instead of a result with a status."""


class TableError(LutmpiError, RuntimeError):
    """A lookup table file is missing, incomplete, of a newer schema, or cannot be written."""


class MissingQuantityError(TableError):
    """A table does not store a quantity asked of it (built with a subset of
    ``output.quantities``)."""


class MPIUnavailableError(LutmpiError, RuntimeError):
    """MPI or parallel HDF5 is needed but not available (e.g. h5py built without MPI)."""


class BuildInterruptedError(LutmpiError):
    """A build was stopped by a signal (SIGINT, SIGTERM); its journal keeps the points done."""

    def __init__(self, signum: int):
        import signal

        self.signum = signum
        super().__init__(f"interrupted by {signal.Signals(signum).name}")


class OutputError(LutmpiError, RuntimeError):
    """An output path cannot be written (missing or read-only folder, not a regular file, ...)."""
