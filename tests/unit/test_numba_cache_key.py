"""numba's cache of compiled kernels is keyed on a digest of the package's sources
(``lutmpi/__init__.py``): numba does not invalidate a cached function when a function it calls
from another file changes, so an edit anywhere must start a fresh cache, and child processes
must share their parent's."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import lutmpi

PKG = Path(lutmpi.__file__).resolve().parent


def _folder(pkg_parent: Path, env: dict[str, str]) -> str:
    code = "import lutmpi, os; print(lutmpi.NUMBA_CACHE_DIR); print(os.environ['NUMBA_CACHE_DIR'])"
    out = subprocess.run([sys.executable, "-c", code], cwd=pkg_parent, env=env,
                         capture_output=True, text=True, check=True).stdout.split()
    assert out[0] == out[1]  # what numba reads is what lutmpi chose
    return out[0]


def test_an_edit_in_any_module_moves_the_cache_and_children_follow(tmp_path):
    tree = tmp_path / "tree"
    shutil.copytree(PKG, tree / "lutmpi", ignore=shutil.ignore_patterns("__pycache__"))
    env = {k: v for k, v in os.environ.items()
           if k not in ("NUMBA_CACHE_DIR", "LUTMPI_NUMBA_CACHE_ROOT")}
    env["PYTHONPATH"] = str(tree)
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "cache")
    first = _folder(tree, env)
    assert Path(first).parent == tmp_path / "cache" and Path(first).name.startswith("lutmpi-")
    # a child process (mpirun, a test's subprocess) inherits the chosen folder: the same one
    child = dict(env, NUMBA_CACHE_DIR=first, LUTMPI_NUMBA_CACHE_ROOT=str(tmp_path / "cache"))
    assert _folder(tree, child) == first
    # an edit in a module that only other modules' compiled functions call
    stiff = tree / "lutmpi" / "contact" / "stiffness.py"
    stiff.write_text(stiff.read_text() + "\n# edited\n")
    assert _folder(tree, env) != first
    # without NUMBA_CACHE_DIR: next to the package
    plain = {k: v for k, v in env.items() if k != "NUMBA_CACHE_DIR"}
    assert Path(_folder(tree, plain)).parent == tree / ".numba_cache"


def _tree(tmp_path: Path) -> tuple[Path, dict[str, str]]:
    tree = tmp_path / "tree"
    shutil.copytree(PKG, tree / "lutmpi", ignore=shutil.ignore_patterns("__pycache__"))
    env = {k: v for k, v in os.environ.items()
           if k not in ("NUMBA_CACHE_DIR", "LUTMPI_NUMBA_CACHE_ROOT", "XDG_CACHE_HOME", "TMPDIR")}
    env["PYTHONPATH"] = str(tree)
    return tree, env


def _run(tree: Path, env: dict[str, str], code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], cwd=tree, env=env, capture_output=True,
                          text=True, check=True)


UNWRITABLE = "/proc/lutmpi-no-such-folder"   # not even root can create it


def test_an_unwritable_cache_folder_moves_to_a_keyed_user_folder_not_numbas_own(tmp_path):
    """numba skips a cache folder it cannot write and caches in the package's ``__pycache__``
    or its user folder, neither keyed on lutmpi's sources (the stale cross-file kernels the
    key exists to prevent); lutmpi moves to a keyed folder it can write, and says so."""
    tree, env = _tree(tmp_path)
    env.update(NUMBA_CACHE_DIR=UNWRITABLE, XDG_CACHE_HOME=str(tmp_path / "xdg"))
    out = _run(tree, env, "import lutmpi, os\n"
               "from lutmpi.contact.rigid_kernels import rotation\n"
               "rotation(0.0, 0.0)\n"      # compiles one kernel and caches it
               "print(lutmpi.NUMBA_CACHE_DIR, os.environ['LUTMPI_NUMBA_CACHE_ROOT'])\n"
               "print(lutmpi.CACHE_NOTE)")
    folder, root, note = out.stdout.split(maxsplit=2)
    assert Path(root) == tmp_path / "xdg" / "lutmpi"
    assert Path(folder).parent == Path(root) and Path(folder).name.startswith("lutmpi-")
    assert "cannot be written" in note and UNWRITABLE in note and "$NUMBA_CACHE_DIR" in note
    assert list(Path(folder).rglob("*.nbi"))                       # cached in the keyed folder
    assert not list((tree / "lutmpi").rglob("*.nbi"))              # not in the tree
    # a child inherits the folder chosen, without trying the unwritable one again
    child = dict(env, LUTMPI_NUMBA_CACHE_ROOT=root)
    again = _run(tree, child, "import lutmpi; print(lutmpi.NUMBA_CACHE_DIR, lutmpi.CACHE_NOTE)")
    assert again.stdout.split() == [folder, "None"]
    # the command line says it, with the rank, before doing anything else
    cli = subprocess.run([sys.executable, "-m", "lutmpi.cli", "inspect", str(tmp_path / "no.h5")],
                         cwd=tree, env=env, capture_output=True, text=True)
    assert "WARNING lutmpi: the compiled kernels' cache folder" in cli.stderr


def test_without_a_writable_user_folder_the_cache_goes_to_a_private_tmp_folder(tmp_path):
    tree, env = _tree(tmp_path)
    env.update(NUMBA_CACHE_DIR=UNWRITABLE, XDG_CACHE_HOME=UNWRITABLE + "-xdg",
               TMPDIR=str(tmp_path / "tmp"))
    code = "import lutmpi; print(lutmpi.NUMBA_CACHE_DIR); print(lutmpi.CACHE_NOTE)"
    folder = _run(tree, env, code).stdout.split("\n")[0]
    private = tmp_path / "tmp" / f"lutmpi-numba-{os.getuid()}"
    assert Path(folder).parent == private and private.stat().st_mode & 0o777 == 0o700
    # a temporary folder others can write (planted by another user) is never used
    private.chmod(0o777)
    squatted = _run(tree, env, code).stdout.split("\n")
    assert Path(squatted[0]).parent == Path(UNWRITABLE) and "no folder" in squatted[1]
    # none writable: the folder asked for, and the note says what that costs
    env["TMPDIR"] = UNWRITABLE + "-tmp"
    out = _run(tree, env, code).stdout.split("\n")
    assert Path(out[0]).parent == Path(UNWRITABLE)
    assert "every process compiles them" in out[1]
