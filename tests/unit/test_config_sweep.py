"""Sweep expansion (issue 5 item 1): products, zips, IDs, determinism, bad sweeps."""

from __future__ import annotations

import copy
import re
import shutil
from pathlib import Path

import pytest

from lutmpi.config import expand_sweep
from lutmpi.config.sweep import SWEEP_KEYS
from lutmpi.errors import ConfigError

ROOT = Path(__file__).resolve().parents[2]
SHARED_PROFILES = ROOT / "profiles"   # the repository copies of shared/profiles (identical)
BASE = {"wheel": {"generator": "S1002"}, "rail": {"generator": "UIC60"},
        "grid": {"y_mm": [-4.0, 4.0, 5], "yaw_rad": [-0.01, 0.01, 3]}}


def _sweep(product=None, zip_=None, base=None):
    block = {}
    if product is not None:
        block["product"] = product
    if zip_ is not None:
        block["zip"] = zip_
    return {"base": copy.deepcopy(BASE if base is None else base), "sweep": block}


def test_product_order_ids_and_configs():
    specs = expand_sweep(_sweep({"contact.method": ["max_distance", "load_centre"],
                                 "mesh.spacing_mm": [1.0, 0.25]}))
    assert [s.id for s in specs] == ["m-max_distance__h-1", "m-max_distance__h-0.25",
                                     "m-load_centre__h-1", "m-load_centre__h-0.25"]
    last = specs[-1]
    assert last.params == {"contact.method": "load_centre", "mesh.spacing_mm": 0.25}
    mesh = last.config.mesh
    assert (mesh.wheel_lateral_mm, mesh.wheel_circumferential_mm, mesh.rail_lateral_mm,
            mesh.rail_longitudinal_mm) == (0.25,) * 4
    assert last.config.output.methods == ("load_centre",)
    assert last.config.grid.y_mm == (-4.0, 4.0, 5)


def test_zip_walks_together_and_combines_with_product():
    specs = expand_sweep(_sweep({"contact.allowed_indentation_mm": [0.01, 0.001]},
                                {"rail.inclination": ["1:20", "1:40", "none"],
                                 "wear.rail.side_mm": [0.0, 1.0, 2.5]}))
    assert len(specs) == 6
    assert specs[0].id == "d-0.01__inc-1in20__rs-0"
    assert specs[5].id == "d-0.001__inc-none__rs-2.5"
    assert [(s.config.rail.inclination, s.config.wear.rail.side_mm) for s in specs[:3]] == [
        ("1:20", 0.0), ("1:40", 1.0), ("none", 2.5)]


def test_bare_dotted_keys_equal_quoted_keys():
    bare = expand_sweep(_sweep({"contact": {"method": ["load_centre", "reference"]}}))
    quoted = expand_sweep(_sweep({"contact.method": ["load_centre", "reference"]}))
    assert bare == quoted


def test_expansion_is_deterministic_and_ids_are_stable(tmp_path):
    text = (ROOT / "configs" / "convergence_s1002_uic60.toml").read_text()
    first = expand_sweep(ROOT / "configs" / "convergence_s1002_uic60.toml")
    copy_path = tmp_path / "conv.toml"
    copy_path.write_text(text)
    second = expand_sweep(copy_path)
    assert [s.id for s in first] == [s.id for s in second]
    assert [s.params for s in first] == [s.params for s in second]
    assert [s.config.mesh for s in first] == [s.config.mesh for s in second]
    # golden IDs: a change here renames every stored table of every existing sweep
    assert first[0].id == "m-max_distance__h-2__d-0.04"
    assert first[6].id == "m-max_normal_distance__h-0.5__d-0.0025"
    assert first[-1].id == "m-reference"


def test_convergence_sweep_shape():
    specs = expand_sweep(ROOT / "configs" / "convergence_s1002_uic60.toml")
    methods = {s.config.contact.method for s in specs}
    spacings = {s.config.mesh.wheel_lateral_mm for s in specs
                if s.config.contact.method != "reference"}
    assert methods == {"max_distance", "max_normal_distance", "load_centre", "reference"}
    assert len(spacings) >= 4 and len(specs) == 13
    g = specs[0].config.grid
    assert g.y_mm[2] * g.yaw_rad[2] <= 50


def test_ids_are_unique_and_filesystem_safe():
    specs = expand_sweep(_sweep({"grid.y_mm": [[-9, 9, 9], [-9.5, 9.5, 17]],
                                 "rail.inclination": ["1:20", "none"],
                                 "flange.enabled": [True, False]}))
    ids = [s.id for s in specs]
    assert len(set(ids)) == len(ids) == 8
    assert all(re.fullmatch(r"[A-Za-z0-9._+~-]+", i) for i in ids)
    assert ids[0] == "y--9_9_9__inc-1in20__enabled-true"


def test_profile_ids_use_the_file_stem_and_replace_the_base_source(tmp_path):
    for name in ("Car7216_0001r.whl", "avg_wheel.whl"):
        (tmp_path / name).write_text("x")
    sweep = tmp_path / "s.toml"
    sweep.write_text('[base.wheel]\ngenerator = "S1002"\nnominal_radius_mm = 450\n'
                     '[base.rail]\ngenerator = "UIC60"\n'
                     '[sweep]\nproduct = { "wheel.profile" = ["Car7216_0001r.whl", '
                     '"avg_wheel.whl"] }\n')
    specs = expand_sweep(sweep)
    assert [s.id for s in specs] == ["w-Car7216_0001r", "w-avg_wheel"]
    assert specs[1].config.wheel.profile == (tmp_path / "avg_wheel.whl").resolve()
    assert specs[1].config.wheel.generator is None
    assert specs[1].config.wheel.nominal_radius_mm == 450.0


def test_same_stem_in_two_folders_gets_distinct_ids(tmp_path):
    for sub in ("a", "b"):
        (tmp_path / sub).mkdir()
        (tmp_path / sub / "w.whl").write_text("x")
    specs = expand_sweep(_sweep({"wheel.profile": ["a/w.whl", "b/w.whl"]}), base_dir=tmp_path)
    ids = [s.id for s in specs]
    assert len(set(ids)) == 2 and all(i.startswith("w-w~") for i in ids)
    assert ids == [s.id for s in expand_sweep(_sweep({"wheel.profile": ["a/w.whl", "b/w.whl"]}),
                                              base_dir=tmp_path)]


def test_base_file_with_its_own_relative_profiles(tmp_path):
    (tmp_path / "cfg").mkdir()
    (tmp_path / "prof").mkdir()
    (tmp_path / "prof" / "w.prw").write_text("x")
    (tmp_path / "cfg" / "base.toml").write_text(
        '[wheel]\nprofile = "../prof/w.prw"\n[rail]\ngenerator = "UIC60"\n')
    (tmp_path / "sweeps").mkdir()
    sweep = tmp_path / "sweeps" / "s.toml"
    sweep.write_text('base = "../cfg/base.toml"\n'
                     '[sweep]\nproduct = { "mesh.spacing_mm" = [1, 2] }\n')
    specs = expand_sweep(sweep)
    assert specs[0].config.wheel.profile == (tmp_path / "prof" / "w.prw").resolve()
    assert specs[0].id == "h-1"


def test_several_blocks_concatenate():
    doc = {"base": BASE, "sweep": [{"product": {"contact.method": ["load_centre"]}},
                                   {"zip": {"wear.wheel.flange_thinning_mm": [1.0, 2.0]}}]}
    assert [s.id for s in expand_sweep(doc)] == ["m-load_centre", "ft-1", "ft-2"]


def test_a_sides_own_key_names_its_side_and_ids_do_not_depend_on_other_blocks():
    left = {"product": {"wear.wheel.left.flange_thinning_mm": [2.0]}}
    right = {"product": {"wear.wheel.right.flange_thinning_mm": [2.0]}}
    both = {"product": {"wear.wheel.flange_thinning_mm": [2.0]}}
    assert [s.id for s in expand_sweep({"base": BASE, "sweep": [left]})] == ["ftL-2"]
    assert [s.id for s in expand_sweep({"base": BASE, "sweep": [both, left, right]})] == \
        ["ft-2", "ftL-2", "ftR-2"]
    pair = {"zip": {"wheel.left.nominal_radius_mm": [455.0],
                    "wheel.right.nominal_radius_mm": [460.0]}}
    assert [s.id for s in expand_sweep({"base": BASE, "sweep": [pair]})] == \
        ["nominal_radius_mmL-455__nominal_radius_mmR-460"]


# ----------------------------------------------------------------------------------- bad sweeps

@pytest.mark.parametrize(("doc", "key", "text"), [
    (_sweep({"mesh.spacing": [1.0]}), "sweep.product.mesh.spacing", "unknown sweep key"),
    (_sweep({"contact.method": []}), "sweep.product.contact.method", "empty list"),
    (_sweep({}), "sweep", "empty sweep"),
    (_sweep({"contact.method": "load_centre"}), "sweep.product.contact.method", "list of values"),
    (_sweep({"contact.method": ["load_centre"]}, {"contact.method": ["reference"]}),
     "sweep.contact.method", "both product and zip"),
    (_sweep(None, {"mesh.spacing_mm": [1, 2], "contact.method": ["load_centre"]}),
     "sweep.zip", "equal lengths"),
    (_sweep({"mesh.spacing_mm": [1], "mesh.rail_lateral_mm": [2]}), "sweep.mesh.rail_lateral_mm",
     "conflicts with mesh.spacing_mm"),
    (_sweep({"wheel.profile": ["a.whl"], "wheel.generator": ["S1002"]}), "sweep.wheel.generator",
     "one source"),
    (_sweep({"contact.method": ["load_centre", "load_centre"]}), "sweep", "listed twice"),
    ({"base": BASE}, "sweep", "[sweep]"),
    ({"sweep": {"product": {"contact.method": ["load_centre"]}}}, "base", "missing 'base'"),
    ({**_sweep({"contact.method": ["x"]}), "runs": 3}, "runs", "unknown top-level key"),
    ({"base": BASE, "sweep": {"product": {"contact.method": ["reference"]}, "grid": 1}},
     "sweep.grid", "valid keys: product, zip"),
])
def test_bad_sweep_names_the_key(doc, key, text):
    with pytest.raises(ConfigError) as err:
        expand_sweep(doc)
    assert err.value.key == key
    assert text in str(err.value)


def test_invalid_member_names_its_parameters_and_key(tmp_path):
    sweep = tmp_path / "s.toml"
    sweep.write_text('[base.wheel]\ngenerator = "S1002"\n[base.rail]\ngenerator = "UIC60"\n'
                     '[sweep]\nproduct = { "contact.method" = ["load_centre"], '
                     '"contact.allowed_indentation_mm" = [0.01, 2.0] }\n')
    with pytest.raises(ConfigError) as err:
        expand_sweep(sweep)
    msg = str(err.value)
    assert err.value.key == "contact.allowed_indentation_mm"
    assert "m-load_centre__d-2" in msg and "'contact.allowed_indentation_mm': 2.0" in msg
    assert str(sweep) in msg and msg.count(str(sweep)) == 1


def test_missing_profile_in_a_member(tmp_path):
    with pytest.raises(ConfigError, match=r"w-missing .*profile file not found") as err:
        expand_sweep(_sweep({"wheel.profile": ["missing.whl"]}), base_dir=tmp_path)
    assert err.value.key == "wheel.profile"


def test_sweep_toml_syntax_error(tmp_path):
    sweep = tmp_path / "s.toml"
    sweep.write_text("[sweep]\nproduct = { a = [1, }\n")
    with pytest.raises(ConfigError, match=r"s\.toml: TOML syntax error.*line 2"):
        expand_sweep(sweep)


def test_every_documented_key_is_sweepable():
    for key in ("wheel.profile", "rail.profile", "rail.inclination", "mesh.wheel_lateral_mm",
                "mesh.spacing_mm", "contact.method", "contact.allowed_indentation_mm", "grid.y_mm",
                "grid.yaw_rad", "wear.wheel.flange_thinning_mm", "wear.wheel.tread_hollowing_mm",
                "wear.rail.vertical_mm", "wear.rail.side_mm"):
        assert key in SWEEP_KEYS


def test_wear_sweep_expands_against_the_measured_profiles(tmp_path):
    names = ["Car7216_0001r.whl", "Car7358_0001r.whl", "whl_left_iter288.whl", "avg_wheel.whl",
             "rail_left_iter288.ban", "avg_low2.ban"]
    (tmp_path / "configs").mkdir()
    (tmp_path / "profiles").mkdir()
    for name in names:
        src = SHARED_PROFILES / name
        dst = tmp_path / "profiles" / name
        if src.exists():
            shutil.copy(src, dst)
        else:
            dst.write_text("placeholder")
    shutil.copy(ROOT / "configs" / "wear_sweep.toml", tmp_path / "configs")
    specs = expand_sweep(tmp_path / "configs" / "wear_sweep.toml")
    ids = [s.id for s in specs]
    assert len(ids) == len(set(ids)) == 4 + 8 + 4 + 4 + 4
    assert "w-Car7216_0001r" in ids
    assert "w-avg_wheel__r-avg_low2__inc-1in40__gauge_depth_mm-10" in ids
    wheels = {s.config.wheel.profile.name for s in specs if s.config.wheel.profile}
    assert wheels == set(names[:4])
    hollow = [s for s in specs if s.config.wear.wheel.tread_hollowing_mm > 0]
    assert len(hollow) == 4 and all(s.config.wheel.generator == "S1002" for s in hollow)
