"""The schema is the only list of dataset names (issue 15).

1. Every dataset of ``table/schema.py`` is filled from the pose result by its name: a per-point
   field from the :class:`PoseResult` attribute of that name, a per-contact field from the
   :class:`ContactResult` attribute (``table/compute.py``: one short alias map for older names).
2. No module of ``lutmpi/`` but ``table/schema.py`` spells a table dataset name as a string literal
   (code writes ``schema.D.z_g``, ``schema.J.jump_y``, ``schema.Y_AXIS``). Read with ``ast``, string
   constants outside docstrings: a per-point/per-contact/jump dataset name counts wherever it
   appears; the axis and group names (``y``, ``yaw``, ``jumps``, ``limits``, ``knots``), which are
   also ordinary words, count only as a key (``x["y"]``, ``x.get("y")``, ``"y" in x``).
   What :data:`ALLOWED` still lists are the same words used for something else (a simulation run
   file, a sweep index, a compiled buffer), each with its reason; a stale entry fails.
"""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import numpy as np
import pytest

from lutmpi.equilibrium.result import ContactResult, PoseResult
from lutmpi.paths import REPO_ROOT
from lutmpi.pose.solve import POINT_QUANTITIES
from lutmpi.table import schema
from lutmpi.table.compute import ATTRIBUTE_OF, DERIVED, fill_record, result_attribute
from lutmpi.table.schema import FIELDS, FIELDS_BY_NAME


def _attributes(cls) -> set[str]:
    return {f.name for f in dataclasses.fields(cls)} | {
        n for n, v in vars(cls).items() if isinstance(v, property)}


def test_every_field_is_an_attribute_of_the_pose_result():
    # a per-point value is a declared attribute or one the pose layer sets (POINT_QUANTITIES)
    point = _attributes(PoseResult) | set(POINT_QUANTITIES)
    contact = _attributes(ContactResult)
    missing = [f.name for f in FIELDS if f.name not in DERIVED
               and result_attribute(f.name) not in (contact if f.per_contact else point)]
    assert not missing, f"schema fields with no result attribute to fill them from: {missing}"


def test_a_point_quantity_of_the_pose_layer_is_stored_and_an_error_record_keeps_the_fill():
    """``n_roots`` is set by the pose layer's registry, not declared on PoseResult: a solved pose
    stores its value, a result made elsewhere (an error record) the field's fill value."""
    from lutmpi.config import load_config
    from lutmpi.pose.solve import solve_pose
    from lutmpi.scene import Scene
    from lutmpi.table.compute import pose_to_record

    assert "n_roots" not in _attributes(PoseResult)
    scene = Scene.from_config(load_config(REPO_ROOT / "configs" / "small_test.toml"))
    fields = [FIELDS_BY_NAME[schema.D.n_roots]]
    solved = pose_to_record(solve_pose(scene, 0.0, 0.0, "reference"), fields)
    assert solved[schema.D.n_roots] == scene.locus.solve(0.0, 0.0).n_roots >= 1
    error = pose_to_record(PoseResult(0.0, 0.0, "reference"), fields)
    assert error[schema.D.n_roots] == FIELDS_BY_NAME[schema.D.n_roots].fill


def test_alias_map_names_only_schema_fields():
    # a stale alias (a renamed or removed field) would silently never be used
    assert set(ATTRIBUTE_OF) | set(DERIVED) <= set(FIELDS_BY_NAME)


def test_a_field_without_an_attribute_fails_loudly(monkeypatch):
    # a new schema line whose value nobody produces must not become a silent column of NaN
    monkeypatch.setitem(FIELDS_BY_NAME, "not_a_result_attribute", FIELDS_BY_NAME["z_g"])
    with pytest.raises(AttributeError, match="not_a_result_attribute"):
        fill_record({"not_a_result_attribute": np.zeros(1)}, 0, PoseResult(0.0, 0.0, "reference"))


# -- 2. no dataset name spelled outside the schema ---------------------------------------------

PKG = REPO_ROOT / "lutmpi"
#: names that are datasets and nothing else: a literal of one is a dataset name wherever it is
DATASET_NAMES = frozenset(schema.D) | frozenset(schema.J)
#: names that are datasets (or groups) but also ordinary words: counted only as keys
KEY_NAMES = frozenset(schema.AXES) | {schema.JUMPS_GROUP, schema.LIMITS_GROUP, schema.KNOTS_GROUP}
#: (module path, name) -> why it is still spelled out. Lead's decision; each entry must still match.
ALLOWED: dict[tuple[str, str], str] = {
    # not table datasets: the same words in another file or record
    **{("lutmpi/commands/simulate.py", n): "a dataset of the simulation run file (write_run)"
       for n in ("z_g", "roll", "contact_angle", "n_contacts")},
    ("lutmpi/reports/dynamics_plots.py", "roll"): "a series of a simulation run",
    **{("lutmpi/table/compute.py", n): "ATTRIBUTE_OF value: the result attribute of that name"
       for n in ("indentation", "kc")},
    ("lutmpi/parallel/sweep_runner.py", "status"): "a column of the sweep's index.json",
    **{("lutmpi/contact/kernels.py", n): "a column of the compiled Contacts buffer (perf)"
       for n in ("wheel_point", "rail_point")},
    ("lutmpi/reports/report.py", "status"): "STATUS_KEY: the member-status key of index.json",
    # table/api.py: Table.interp's info key named like the jump dataset it reports (jumps)
    ("lutmpi/table/api.py", "jump_side"): "interp info key (INFO_KEYS), returned per query",
    ("lutmpi/commands/query.py", "jump_side"): "query CSV column = Table.interp info key",
}


def _docstrings(tree: ast.AST) -> set[int]:
    kinds = (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)
    return {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, kinds) and n.body and isinstance(n.body[0], ast.Expr)
            and isinstance(n.body[0].value, ast.Constant)}


def _key_constants(tree: ast.AST) -> set[int]:
    """String constants used as a key: ``x["k"]``, ``x.get("k", ...)``, ``"k" in x``."""
    keys = set()
    for n in ast.walk(tree):
        if isinstance(n, ast.Subscript):
            keys.add(id(n.slice))
        elif isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) \
                and n.func.attr == "get" and n.args:
            keys.add(id(n.args[0]))
        elif isinstance(n, ast.Compare) and isinstance(n.ops[0], (ast.In, ast.NotIn)):
            keys.add(id(n.left))
    return keys


def spelled_names(source: str) -> list[tuple[int, str]]:
    """``(line, name)`` for every dataset name spelled as a literal in ``source`` (rule 2)."""
    tree = ast.parse(source)
    skip, keys = _docstrings(tree), _key_constants(tree)
    found = []
    for n in ast.walk(tree):
        if not (isinstance(n, ast.Constant) and isinstance(n.value, str)) or id(n) in skip:
            continue
        # a path ("load_centre/status", "/y") counts by its parts
        parts = [x for x in n.value.split("/") if x] if "/" in n.value and " " not in n.value \
            else [n.value]
        for part in parts:
            if part in DATASET_NAMES or (part in KEY_NAMES and (id(n) in keys or len(parts) > 1)):
                found.append((n.lineno, part))
    return found


def all_spellings() -> dict[tuple[str, str], list[int]]:
    out: dict[tuple[str, str], list[int]] = {}
    for path in sorted(PKG.rglob("*.py")):
        rel = path.relative_to(REPO_ROOT).as_posix()
        if rel == "lutmpi/table/schema.py":
            continue
        for line, name in spelled_names(path.read_text(encoding="utf-8")):
            out.setdefault((rel, name), []).append(line)
    return out


@pytest.mark.parametrize(("source", "found"), [
    ('f["z_g"]', ["z_g"]), ('x = ("status", "iterations")', ["status", "iterations"]),
    ('g.get("jump_y")', ["jump_y"]), ('p = f"{m}/rolling_radius"', ["rolling_radius"]),
    ('d = f["y"]', ["y"]), ('if "knots" in g: pass', ["knots"]),
    ('p = "/load_centre/yaw"', ["yaw"]),
    # ordinary words and prose are not dataset names
    ('COMPONENTS = ("x", "y", "z")', []), ('log.info("roll of the wheelset")', []),
    ('def f():\n    """z_g"""\n', []), ('m = cfg.contact.method', []), ('k = "z_g_mm"', []),
])
def test_spelling_detector(source, found):
    assert [name for _, name in spelled_names(source)] == found


def test_no_dataset_name_spelled_outside_the_schema():
    new = {k: v for k, v in all_spellings().items() if k not in ALLOWED}
    where = "\n".join(f"  {path}:{lines} {name!r}" for (path, name), lines in sorted(new.items()))
    assert not new, ("dataset names spelled as literals (use schema.D / schema.J / schema.AXES "
                     f"or the group constants of lutmpi/table/schema.py):\n{where}")


def test_allowed_spellings_still_exist():
    stale = sorted(set(ALLOWED) - set(all_spellings()))
    assert not stale, f"fixed: remove from ALLOWED in {Path(__file__).name}: {stale}"
