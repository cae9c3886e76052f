"""lutmpi: MPI-parallel wheel-rail contact lookup tables."""

import hashlib
import os
import sys
import warnings
from pathlib import Path

__version__ = "0.1.0"


def _writable(folder: str) -> bool:
    """numba's own test of a cache folder (created, a file written in it): a locator that fails
    it is skipped, and numba falls back to caches that are not keyed on these sources."""
    probe = os.path.join(folder, f".lutmpi-write-test-{os.getpid()}")
    try:
        os.makedirs(folder, exist_ok=True)
        os.close(os.open(probe, os.O_CREAT | os.O_WRONLY | os.O_TRUNC, 0o600))
        os.unlink(probe)
    except OSError:
        return False
    return True


def _key_numba_cache() -> str:
    """Point numba's on-disk cache of compiled kernels at a folder named after a digest of this
    package's sources, and return it.

    numba invalidates a cached function when its own file changes, not when a function it
    calls from another file does (a documented limitation): after an edit or an upgrade of,
    say, ``contact/stiffness.py``, the compiled Newton iteration of ``pose/newton.py`` would
    otherwise run the old flange factor from its cache. With the digest in the path, any change
    to any source starts a fresh cache (``scripts/setup.sh`` fills it). The folder is
    ``$NUMBA_CACHE_DIR/lutmpi-<digest>`` when the variable is set, else ``.numba_cache/`` next
    to the package; child processes (``mpirun``, test subprocesses) inherit the root through
    ``LUTMPI_NUMBA_CACHE_ROOT`` and land in the same folder.

    Where that folder cannot be written (a read-only installation, a ``NUMBA_CACHE_DIR`` that
    does not exist for this user), numba would silently cache in the package's
    ``__pycache__`` or its own user folder, neither keyed on the sources; the folder is then
    ``$XDG_CACHE_HOME/lutmpi`` (``~/.cache/lutmpi``), else ``$TMPDIR/lutmpi-numba-<uid>``, with
    a warning that says so."""
    pkg = Path(__file__).resolve().parent
    digest = hashlib.sha1()
    for path in sorted(pkg.rglob("*.py")):
        digest.update(path.relative_to(pkg).as_posix().encode())
        digest.update(path.read_bytes())
    name = f"lutmpi-{digest.hexdigest()[:16]}"
    wanted = (os.environ.get("LUTMPI_NUMBA_CACHE_ROOT") or os.environ.get("NUMBA_CACHE_DIR")
              or str(pkg.parent / ".numba_cache"))
    user = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    temp = os.path.join(os.environ.get("TMPDIR") or "/tmp", f"lutmpi-numba-{os.getuid()}")
    root = next((r for r in (wanted, os.path.join(user, "lutmpi"), temp)
                 if _writable(os.path.join(r, name))), wanted)
    folder = os.path.join(root, name)
    if root != wanted:
        warnings.warn(f"lutmpi: the compiled kernels' cache folder {os.path.join(wanted, name)} "
                      f"cannot be written; using {folder} (set NUMBA_CACHE_DIR to a writable "
                      "folder to choose another)", RuntimeWarning, stacklevel=2)
    elif not _writable(folder):
        warnings.warn(f"lutmpi: no writable folder for the compiled kernels' cache (tried "
                      f"{folder}, under {user} and {temp}): numba compiles them in every process "
                      "or caches them where lutmpi cannot key them on its sources",
                      RuntimeWarning, stacklevel=2)
    os.environ["LUTMPI_NUMBA_CACHE_ROOT"] = root
    os.environ["NUMBA_CACHE_DIR"] = folder
    if "numba" in sys.modules:  # imported before lutmpi: its configuration is already read
        from numba.core import config

        config.CACHE_DIR = folder
    return folder


NUMBA_CACHE_DIR = _key_numba_cache()


def __getattr__(name: str):
    # lazy: ``import lutmpi`` stays light; ``lutmpi.Table`` loads the table API on first use
    if name == "Table":
        from lutmpi.table import Table

        return Table
    raise AttributeError(f"module 'lutmpi' has no attribute {name!r}")
