"""The pure numerical packages never import mpi4py or h5py (STYLE.md, practice 1).

Walks the AST of every module, so an import inside a function or under ``if TYPE_CHECKING`` counts
too: the rule is about what the module could ever load, not about what one test run loads.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from lutmpi.paths import REPO_ROOT

PKG = REPO_ROOT / "lutmpi"
PURE_PACKAGES = ("profiles", "geometry", "contact", "equilibrium", "dynamics", "reports")
PURE_MODULES = ("table/compute.py", "table/interp.py", "table/grid.py")
FORBIDDEN = frozenset({"mpi4py", "h5py"})


def pure_modules() -> list[Path]:
    """Every existing module the rule applies to."""
    files: list[Path] = []
    for name in PURE_PACKAGES:
        files += sorted((PKG / name).rglob("*.py"))
    files += [PKG / rel for rel in PURE_MODULES if (PKG / rel).is_file()]
    return files


def forbidden_imports(source: str, filename: str = "<string>") -> list[tuple[int, str]]:
    """``(line, module)`` for every import of a forbidden top-level package in ``source``."""
    found = []
    for node in ast.walk(ast.parse(source, filename)):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        else:
            continue
        found += [(node.lineno, n) for n in names if n.split(".")[0] in FORBIDDEN]
    return found


@pytest.mark.parametrize(
    "source",
    ["import h5py", "import numpy, mpi4py.MPI as M", "from mpi4py import MPI",
     "def f():\n    from h5py import File\n", "from h5py._hl import files"])
def test_detector_catches_every_import_form(source):
    assert forbidden_imports(source)


@pytest.mark.parametrize(
    "source",
    ["import numpy", "from .h5py import x", "h5py = None", "import h5pyx", "# import h5py"])
def test_detector_ignores_lookalikes(source):
    assert forbidden_imports(source) == []


def test_pure_packages_exist():
    # if the package layout moves, this test must move with it rather than silently check nothing
    assert all((PKG / name / "__init__.py").is_file() for name in PURE_PACKAGES)


@pytest.mark.parametrize("path", pure_modules(), ids=lambda p: str(p.relative_to(PKG)))
def test_pure_module_does_not_import_mpi_or_h5py(path):
    bad = forbidden_imports(path.read_text(encoding="utf-8"), str(path))
    where = ", ".join(f"{path.relative_to(REPO_ROOT)}:{line} {mod}" for line, mod in bad)
    assert not bad, f"pure module imports MPI/HDF5 (only h5io, parallel/, CLI may): {where}"
