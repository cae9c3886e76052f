"""lutmpi: MPI-parallel wheel-rail contact lookup tables."""

import hashlib
import os
import sys
from pathlib import Path

__version__ = "0.1.0"


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
    ``LUTMPI_NUMBA_CACHE_ROOT`` and land in the same folder."""
    pkg = Path(__file__).resolve().parent
    digest = hashlib.sha1()
    for path in sorted(pkg.rglob("*.py")):
        digest.update(path.relative_to(pkg).as_posix().encode())
        digest.update(path.read_bytes())
    root = (os.environ.get("LUTMPI_NUMBA_CACHE_ROOT") or os.environ.get("NUMBA_CACHE_DIR")
            or str(pkg.parent / ".numba_cache"))
    folder = os.path.join(root, f"lutmpi-{digest.hexdigest()[:16]}")
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
