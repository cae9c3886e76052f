"""lutmpi: MPI-parallel wheel-rail contact lookup tables."""

import hashlib
import os
import stat
import sys
from pathlib import Path

__version__ = "0.1.0"


#: why the kernels' cache is not where it was asked to be (None: it is); the CLI logs it
CACHE_NOTE: str | None = None


def _writable(folder: str) -> bool:
    """numba's own test of a cache folder (created, a file written in it): a locator that fails
    it is skipped, and numba falls back to caches that are not keyed on these sources. The test
    file's name is random (ranks of several nodes share pids and may share the folder)."""
    probe = os.path.join(folder, f".lutmpi-write-test-{os.urandom(8).hex()}")
    try:
        os.makedirs(folder, exist_ok=True)
        os.close(os.open(probe, os.O_CREAT | os.O_WRONLY | os.O_EXCL, 0o600))
        os.unlink(probe)
    except OSError:
        return False
    return True


def _private(root: str) -> bool:
    """True when ``root`` is (made) a folder of this user's that nobody else can write: a
    shared temporary folder must not hold a cache another user could have planted (numba's
    index files are pickles)."""
    try:
        os.makedirs(root, mode=0o700, exist_ok=True)
        st = os.lstat(root)
    except OSError:
        return False
    return stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid() and not st.st_mode & 0o022


def _cache_root(wanted: str, name: str, asked_by: str) -> tuple[str, str | None]:
    """The root of the kernels' cache (``wanted``, else a keyed user or private temporary one)
    and, when it is not ``wanted``, what to tell the user."""
    if _writable(os.path.join(wanted, name)):
        return wanted, None
    user = os.path.join(os.environ.get("XDG_CACHE_HOME")
                        or os.path.join(os.path.expanduser("~"), ".cache"), "lutmpi")
    temp = os.path.join(os.environ.get("TMPDIR") or "/tmp", f"lutmpi-numba-{os.getuid()}")
    for root in (user, temp):
        if (root != temp or _private(root)) and _writable(os.path.join(root, name)):
            return root, (f"the compiled kernels' cache folder {os.path.join(wanted, name)} "
                          f"({asked_by}) cannot be written; using {os.path.join(root, name)}, "
                          "which starts empty (its first build compiles for ~1.5 min; "
                          "`python -m lutmpi.warmup` fills it ahead)")
    return wanted, (f"no folder for the compiled kernels' cache can be written (tried "
                    f"{os.path.join(wanted, name)} ({asked_by}), {user} and {temp}): every "
                    "process compiles them (~1.5 min), and numba may cache them where a later "
                    "change to lutmpi's sources does not reach; set NUMBA_CACHE_DIR to a "
                    "folder you can write")


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
    ``LUTMPI_NUMBA_CACHE_ROOT`` and land in the same folder. Where it cannot be written
    (:func:`_cache_root`), numba would silently cache in the package's ``__pycache__`` or its
    own user folder, neither keyed on the sources: the folder moves to
    ``$XDG_CACHE_HOME/lutmpi`` (``~/.cache/lutmpi``), else ``$TMPDIR/lutmpi-numba-<uid>``
    (``/tmp`` when unset; only a private folder), and :data:`CACHE_NOTE` says so."""
    global CACHE_NOTE
    pkg = Path(__file__).resolve().parent
    digest = hashlib.sha1()
    for path in sorted(pkg.rglob("*.py")):
        digest.update(path.relative_to(pkg).as_posix().encode())
        digest.update(path.read_bytes())
    var = next((v for v in ("LUTMPI_NUMBA_CACHE_ROOT", "NUMBA_CACHE_DIR") if os.environ.get(v)),
               None)
    wanted = os.environ[var] if var else str(pkg.parent / ".numba_cache")
    name = f"lutmpi-{digest.hexdigest()[:16]}"
    root, CACHE_NOTE = _cache_root(wanted, name,
                                   f"${var}" if var else "the default, next to the package")
    folder = os.path.join(root, name)
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
