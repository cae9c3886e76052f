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
