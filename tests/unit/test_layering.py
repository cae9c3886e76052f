"""The direction of imports inside lutmpi (STYLE.md practice 1 and its dependency rule; issue 15).

Walks the AST of every module, so an import inside a function or under ``if TYPE_CHECKING`` counts
too: the rules are about what a module could ever load, not about what one test run loads. One more
test imports the pure chain in a fresh interpreter and checks what it loaded at run time (a package
``__init__`` can pull in h5py where no line says ``import h5py``).

Rules:

1. **Direction.** ``profiles -> geometry -> contact -> equilibrium -> table schema -> pose ->
   table core (compute, grid, interp, jumps) -> dynamics`` stay pure: a module of one layer imports
   only its own layer, the layers before it and :data:`BASE` -- never a later layer and never an
   unlayered module (``config``, ``scene``, ``parallel``, ``table.h5io``/``api``, ``reports``,
   ``commands``, ...).
2. **MPI and HDF5** are imported only by :data:`MPI_HDF5_MODULES`.
3. **The command line is the top**: nothing imports ``lutmpi.commands`` but ``lutmpi/cli.py``.

A known violation that is not fixed yet is listed in :data:`ALLOWED` with the reason; an entry that
no longer matches an import fails too, so the list can only shrink.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

from lutmpi.paths import REPO_ROOT

PKG = REPO_ROOT / "lutmpi"
FORBIDDEN = frozenset({"mpi4py", "h5py"})
#: importable from every layer
BASE = frozenset({"lutmpi", "lutmpi.errors", "lutmpi.paths"})
#: the pure chain, lowest first: module-name prefixes of each layer
LAYERS: tuple[tuple[str, ...], ...] = (
    ("lutmpi.profiles",),
    ("lutmpi.geometry",),
    ("lutmpi.contact",),
    ("lutmpi.equilibrium",),
    ("lutmpi.table.schema",),
    ("lutmpi.pose",),
    ("lutmpi.table.compute", "lutmpi.table.grid", "lutmpi.table.interp", "lutmpi.table.jumps",
     "lutmpi.table.jump_search", "lutmpi.table.refine", "lutmpi.table.mirror",
     "lutmpi.table.lookup"),
    ("lutmpi.dynamics",),
)
#: the only modules (or packages, by prefix) that may import mpi4py or h5py
MPI_HDF5_MODULES = ("lutmpi.table.h5io", "lutmpi.table.api", "lutmpi.parallel", "lutmpi.commands",
                    "lutmpi.cli")
#: (importer, imported) -> why it is still there. Lead's decision; each entry must still match.
ALLOWED: dict[tuple[str, str], str] = {
}


def module_name(path: Path) -> str:
    """``lutmpi/table/schema.py`` -> ``lutmpi.table.schema``; a package ``__init__`` -> the
    package."""
    parts = path.relative_to(REPO_ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES: dict[str, Path] = {module_name(p): p for p in sorted(PKG.rglob("*.py"))}


def imported_modules(source: str, importer: str, is_package: bool = False,
                     known: frozenset[str] | None = None) -> list[tuple[int, str]]:
    """``(line, module)`` for every import in ``source``, relative imports resolved against
    ``importer``. ``from P import x`` counts as ``P.x`` when that is a module in ``known``
    (else as ``P``)."""
    known = frozenset(MODULES) if known is None else known
    package = importer.split(".") if is_package else importer.split(".")[:-1]
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - (node.level - 1)]
                parent = ".".join(base + ([node.module] if node.module else []))
            else:
                parent = node.module or ""
            for alias in node.names:
                sub = f"{parent}.{alias.name}"
                found.append((node.lineno, sub if sub in known else parent))
    return found


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


def _under(module: str, prefix: str) -> bool:
    return module == prefix or module.startswith(prefix + ".")


def layer_of(module: str) -> int | None:
    """Index in :data:`LAYERS` (0 = lowest), or None for a module outside the pure chain."""
    for i, prefixes in enumerate(LAYERS):
        if any(_under(module, p) for p in prefixes):
            return i
    return None


def layering_violations(importer: str, imports: list[tuple[int, str]]) -> list[tuple[int, str]]:
    """Imports of lutmpi modules that ``importer`` may not make (rules 1 and 3)."""
    bad = []
    rank = layer_of(importer)
    for line, mod in imports:
        if not _under(mod, "lutmpi") or mod in BASE:
            continue
        if rank is not None and (layer_of(mod) is None or layer_of(mod) > rank):
            bad.append((line, mod))
        elif _under(mod, "lutmpi.commands") and not _may_import_commands(importer, mod):
            bad.append((line, mod))
    return bad


def _may_import_commands(importer: str, mod: str) -> bool:
    # the CLI registers the commands; the package itself is an empty namespace for them
    return importer == "lutmpi.cli" or mod == "lutmpi.commands" or importer == mod


def _imports_of(name: str) -> list[tuple[int, str]]:
    path = MODULES[name]
    return imported_modules(path.read_text(encoding="utf-8"), name, path.name == "__init__.py")


def all_violations() -> dict[tuple[str, str], list[int]]:
    """``(importer, imported) -> lines`` over the whole package (rules 1 and 3)."""
    out: dict[tuple[str, str], list[int]] = {}
    for name in MODULES:
        for line, mod in layering_violations(name, _imports_of(name)):
            out.setdefault((name, mod), []).append(line)
    return out


# -- the detectors -------------------------------------------------------------------------------

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


@pytest.mark.parametrize(("source", "importer", "expected"), [
    # absolute, function-level, TYPE_CHECKING, relative (one and two levels), from-package-import
    ("import lutmpi.config.model", "lutmpi.geometry.track", "lutmpi.config.model"),
    ("def f():\n    from lutmpi.scene import Scene\n", "lutmpi.contact.mesh", "lutmpi.scene"),
    ("if TYPE_CHECKING:\n    from lutmpi.config import model\n", "lutmpi.table.grid",
     "lutmpi.config.model"),
    ("from .records import x", "lutmpi.contact.locus", "lutmpi.contact.records"),
    ("from ..contact import records", "lutmpi.pose.solve", "lutmpi.contact.records"),
    ("from ..parallel import runner", "lutmpi.table.compute", "lutmpi.parallel.runner"),
    ("from lutmpi.table import Table", "lutmpi.dynamics.simulate", "lutmpi.table"),
])
def test_import_reader_resolves_every_form(source, importer, expected):
    assert [m for _, m in imported_modules(source, importer)] == [expected]


@pytest.mark.parametrize(("importer", "imported", "bad"), [
    ("lutmpi.geometry.track", "lutmpi.profiles.model", False),      # downward
    ("lutmpi.geometry.track", "lutmpi.contact.mesh", True),         # upward in the chain
    ("lutmpi.profiles.model", "lutmpi.errors", False),              # base
    ("lutmpi.table.compute", "lutmpi.pose.solve", False),
    ("lutmpi.contact.methods.base", "lutmpi.pose.mesh", True),      # contact -> the pipeline
    ("lutmpi.pose.mesh", "lutmpi.equilibrium.solver", False),
    ("lutmpi.table.compute", "lutmpi.config.model", True),          # pure -> config (the edge)
    ("lutmpi.table.grid", "lutmpi.table", True),                    # package init loads the API
    ("lutmpi.dynamics.simulate", "lutmpi.parallel.runner", True),
    ("lutmpi.reports.report", "lutmpi.table.h5io", False),          # above the chain: rule 2 only
    ("lutmpi.cli", "lutmpi.commands.build", False),
    ("lutmpi.commands.build", "lutmpi.commands.sweep", True),       # command -> command
    ("lutmpi.reports.report", "lutmpi.commands.report", True),      # library -> command
])
def test_layering_rule_cases(importer, imported, bad):
    assert bool(layering_violations(importer, [(1, imported)])) is bad


# -- the package ---------------------------------------------------------------------------------

def test_layers_exist():
    # if the package layout moves, this test must move with it rather than silently check nothing
    for prefixes in LAYERS:
        for p in prefixes:
            assert p in MODULES, f"layer module {p} not found under {PKG}"


def test_imports_go_one_way():
    found = all_violations()
    new = {k: v for k, v in found.items() if k not in ALLOWED}
    where = "\n".join(f"  {MODULES[a].relative_to(REPO_ROOT)}:{lines} imports {b}"
                      for (a, b), lines in sorted(new.items()))
    assert not new, ("imports against the layering (profiles -> geometry -> contact -> "
                     "equilibrium -> schema -> pose -> table core -> dynamics; commands only from "
                     f"cli):\n{where}")


def test_allowed_violations_still_exist():
    stale = sorted(set(ALLOWED) - set(all_violations()))
    assert not stale, f"fixed: remove from ALLOWED in {Path(__file__).name}: {stale}"


@pytest.mark.parametrize("name", sorted(MODULES), ids=str)
def test_only_io_modules_import_mpi_or_h5py(name):
    if any(_under(name, p) for p in MPI_HDF5_MODULES):
        return
    path = MODULES[name]
    bad = forbidden_imports(path.read_text(encoding="utf-8"), str(path))
    where = ", ".join(f"{path.relative_to(REPO_ROOT)}:{line} {mod}" for line, mod in bad)
    assert not bad, f"imports MPI/HDF5 (only {', '.join(MPI_HDF5_MODULES)} may): {where}"


def test_pure_chain_loads_no_mpi_or_h5py():
    # a fresh interpreter: what importing every pure module loads at run time, package __init__
    # files included (``import lutmpi.table.schema`` runs ``lutmpi/table/__init__.py``)
    pure = [m for m in MODULES if layer_of(m) is not None and not m.endswith("warmup")]
    code = (f"import importlib, sys\nfor m in {pure!r}: importlib.import_module(m)\n"
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'h5py', 'mpi4py'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, cwd=REPO_ROOT, check=True)
    assert out.stdout.strip() == "[]", f"the pure chain loads {out.stdout.strip()}"
