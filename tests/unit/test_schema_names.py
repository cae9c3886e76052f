"""Issue 15, outputs' part: exports, reports and their commands never spell a dataset name.

Every list of stored quantities there comes from ``lutmpi.table.schema`` (``FIELDS`` or the name
tuple ``D``); this test walks the AST of those modules and fails on a string constant equal to a
dataset name (docstrings aside; a line marked ``# not a dataset`` is a key of something else,
e.g. the sweep index's member status).
"""

from __future__ import annotations

import ast

import pytest

from lutmpi.paths import REPO_ROOT
from lutmpi.table.schema import FIELDS, D

PKG = REPO_ROOT / "lutmpi"
AREA = sorted((PKG / "reports").glob("*.py")) + sorted((PKG / "export").glob("*.py")) + [
    PKG / "commands" / f"{n}.py" for n in ("report", "export", "conicity", "plot", "solve")]
NAMES = {f.name for f in FIELDS}


def literal_names(source: str) -> list[tuple[int, str]]:
    tree = ast.parse(source)
    docs = {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, ast.Module | ast.FunctionDef | ast.ClassDef | ast.AsyncFunctionDef)
            and n.body and isinstance(n.body[0], ast.Expr)
            and isinstance(n.body[0].value, ast.Constant)}
    lines = source.splitlines()
    return [(n.lineno, n.value) for n in ast.walk(tree)
            if isinstance(n, ast.Constant) and isinstance(n.value, str) and n.value in NAMES
            and id(n) not in docs and "# not a dataset" not in lines[n.lineno - 1]]


@pytest.mark.parametrize("path", AREA, ids=lambda p: str(p.relative_to(PKG)))
def test_no_dataset_name_literal(path):
    assert literal_names(path.read_text()) == [], path


def test_the_check_finds_a_literal():
    assert literal_names('x = t.get("rolling_radius")\n') == [(1, "rolling_radius")]
    assert literal_names('x = t.get("rolling_radius")  # not a dataset\n') == []


def test_names_tuple_is_the_schema():
    assert list(D._fields) == [f.name for f in FIELDS]
    assert all(getattr(D, f.name) == f.name for f in FIELDS)
