"""What a second hostile tester found at the command line (2026-11-28): outputs written over the
command's own inputs (a build's config or profile, a profile's ``--points``), exports and reports
made from profile files changed since the build, failed points written as numbers, KPF stems
with dots, a ``--method`` build storing another config, a build in which no point converged
reported as a success, a failed-point listing promised but not there, and intervals no build
can use."""

from __future__ import annotations

import csv
import shutil
import tomllib

import numpy as np
import pytest

from lutmpi.cli import main
from lutmpi.paths import REPO_ROOT
from lutmpi.table import Table
from tests.support.tables import write_config

pytestmark = pytest.mark.timeout(300)

HOOK = ["--solver", "tests.support.faulty_solver:solve"]
PROFILES = REPO_ROOT / "profiles"


def _profile_config(d, name="c.toml", grid="y_mm = [-3.0, 3.0, 3]\nyaw_rad = [0.0, 0.0, 1]\n",
                    extra=""):
    """A config reading its wheel from ``d/w.whl`` (a copy of a measured wheel)."""
    shutil.copy(PROFILES / "avg_wheel.whl", d / "w.whl")
    cfg = d / name
    cfg.write_text('[wheel]\nprofile = "w.whl"\n[rail]\ngenerator = "UIC60"\n'
                   f'[grid]\n{grid}[contact]\nmethod = "reference"\n'
                   f'[output]\nmethods = ["reference"]\n{extra}')
    return cfg


@pytest.fixture(scope="module")
def hook_table(tmp_path_factory):
    d = tmp_path_factory.mktemp("kept")
    cfg = write_config(d, ny=5, nyaw=3)
    assert main(["build", str(cfg), "-o", str(d / "t.h5"), *HOOK]) == 0
    return cfg, d / "t.h5"


def test_a_build_never_writes_over_its_config_or_a_profile(tmp_path, capsys):
    cfg = _profile_config(tmp_path)
    before = {p: p.read_bytes() for p in (cfg, tmp_path / "w.whl")}
    for out in (cfg, tmp_path / "w.whl"):
        capsys.readouterr()
        assert main(["build", str(cfg), "-o", str(out), "--force", *HOOK]) == 1
        err = capsys.readouterr().err
        assert "is the command's input" in err and "Traceback" not in err, err
    # solve checks the profiles the config names too
    assert main(["solve", str(cfg), "--pose", "0", "0", "-o", str(tmp_path / "w.whl")]) == 1
    assert {p: p.read_bytes() for p in before} == before


def test_profile_show_never_writes_its_points_over_the_profile(tmp_path, capsys):
    prof = tmp_path / "mine.whl"
    shutil.copy(PROFILES / "avg_wheel.whl", prof)
    before = prof.read_bytes()
    assert main(["profile", "show", str(prof), "--points", str(prof)]) == 1
    assert "is the command's input" in capsys.readouterr().err
    assert prof.read_bytes() == before
    assert main(["profile", "show", str(prof), "--points", str(tmp_path / "pts.txt")]) == 0
    assert np.loadtxt(tmp_path / "pts.txt").shape[1] == 2


def test_kpf_export_and_report_refuse_a_profile_changed_since_the_build(tmp_path, capsys):
    cfg = _profile_config(tmp_path)
    t = tmp_path / "c.h5"
    assert main(["build", str(cfg), "-o", str(t), *HOOK]) == 0
    assert main(["export", str(t), "--format", "kpf", "-o", str(tmp_path / "before")]) == 0
    shutil.copy(PROFILES / "Car7216_0001r.whl", tmp_path / "w.whl")     # another wheel
    capsys.readouterr()
    assert main(["export", str(t), "--format", "kpf", "-o", str(tmp_path / "after")]) == 1
    err = capsys.readouterr().err
    assert "[wheel.left.profile]" in err or "[wheel.profile]" in err, err
    assert "content differs" in err and "Traceback" not in err
    assert not (tmp_path / "after.wheel").exists()
    assert main(["report", str(t), "-o", str(tmp_path / "rep")]) == 1
    assert "content differs" in capsys.readouterr().err
    assert not (tmp_path / "rep").exists()        # refused before any figure
    shutil.copy(PROFILES / "avg_wheel.whl", tmp_path / "w.whl")          # the table's again
    assert main(["export", str(t), "--format", "kpf", "-o", str(tmp_path / "again")]) == 0
    assert (tmp_path / "again.wheel").read_bytes().split(b"\n", 2)[2] == \
        (tmp_path / "before.wheel").read_bytes().split(b"\n", 2)[2]


def test_csv_export_leaves_the_values_of_failed_points_empty(hook_table, tmp_path):
    _, t = hook_table
    out = tmp_path / "e.csv"
    assert main(["export", str(t), "--format", "csv", "--yaw-rad", "-0.12", "-o", str(out)]) == 0
    rows = list(csv.reader(line for line in out.read_text().splitlines()
                           if not line.startswith("#")))
    head, body = rows[0], rows[1:]
    failed = [r for r in body if r[-1] != "converged"]
    assert failed, "the faulty solver's corner pose is at yaw -0.12"
    z = head.index("z_g_mm")
    for r in failed:
        assert r[z] == "", r
    assert all(r[z] != "" for r in body if r[-1] == "converged")


def test_kpf_stems_keep_their_dots(hook_table, tmp_path):
    _, t = hook_table
    for stem in ("caseA.v2", "caseA.v3"):
        assert main(["export", str(t), "--format", "kpf", "-o", str(tmp_path / stem)]) == 0
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["caseA.v2.rail", "caseA.v2.wheel", "caseA.v3.rail", "caseA.v3.wheel"]
    assert main(["export", str(t), "--format", "kpf", "-o", str(tmp_path / "x.wheel")]) == 0
    assert (tmp_path / "x.wheel").exists() and (tmp_path / "x.rail").exists()


def test_a_build_with_method_stores_the_config_it_built(tmp_path):
    cfg = write_config(tmp_path, ny=3, nyaw=3, methods=("load_centre",))
    t = tmp_path / "m.h5"
    assert main(["build", str(cfg), "-o", str(t), "--method", "reference", *HOOK]) == 0
    table = Table.open(t)
    stored = tomllib.loads(table.config_toml)
    assert table.methods == ["reference"]
    assert stored["output"]["methods"] == ["reference"]
    assert stored["contact"]["method"] == "reference"


def test_inspect_lists_the_failed_points(hook_table, capsys):
    _, t = hook_table
    capsys.readouterr()
    assert main(["inspect", str(t)]) == 0
    out = capsys.readouterr().out
    assert "did not converge (1 grid points" in out
    assert "-9.000 mm  yaw -0.12000 rad  max_iterations" in out


@pytest.mark.parametrize("value", ["nan", "-5", "inf"])   # 0: every point synced at once
def test_a_checkpoint_interval_no_build_can_use_is_a_usage_error(tmp_path, value, capsys):
    cfg = write_config(tmp_path, ny=3, nyaw=3)
    with pytest.raises(SystemExit) as exc:
        main(["build", str(cfg), "-o", str(tmp_path / "t.h5"), f"--checkpoint-interval={value}"])
    assert exc.value.code == 2 and "expected" in capsys.readouterr().err


def test_a_build_in_which_no_point_converged_is_not_a_success(tmp_path, capfd):
    # metres under an mm key: the wheels sit 1.36 mm apart and miss their rails at every pose
    cfg = tmp_path / "b2b.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
                   '[wheelset]\nback_to_back_mm = 1.36\n'
                   '[grid]\ny_mm = [-2.0, 2.0, 3]\nyaw_rad = [0.0, 0.0, 1]\n'
                   '[contact]\nmethod = "reference"\n[output]\nmethods = ["reference"]\n'
                   'jumps = false\n')
    capfd.readouterr()
    assert main(["build", str(cfg), "-o", str(tmp_path / "t.h5")]) == 3
    err = capfd.readouterr().err
    assert "no grid point" in err and "back_to_back_mm" in err and "Traceback" not in err
    assert Table.open(tmp_path / "t.h5").status_counts() == {"no_contact": 3}


@pytest.mark.parametrize("rail", ['[rail.right]\ngauge_point = 50.0\n', 'gauge_point = "first"\n'])
def test_a_gauge_point_error_names_the_config_file(tmp_path, rail, capsys):
    cfg = tmp_path / "g.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n' + rail
                   + '[grid]\ny_mm = [-2.0, 2.0, 3]\nyaw_rad = [0.0, 0.0, 1]\n')
    assert main(["solve", str(cfg), "--pose", "0", "0"]) == 1
    err = capsys.readouterr().err
    assert f"{cfg}: [rail." in err and "gauge_point]" in err, err


def test_export_paths_and_options_are_checked_before_the_work(hook_table, tmp_path, capsys):
    _, t = hook_table
    (tmp_path / "m1.mat").mkdir()       # the .mat the writer would add is a folder
    assert main(["export", str(t), "--format", "mat", "-o", str(tmp_path / "m1")]) == 1
    err = capsys.readouterr().err
    assert "m1.mat" in err and "folder" in err and "Traceback" not in err, err
    (tmp_path / "kp.rail").mkdir()      # checked before kp.wheel is written
    assert main(["export", str(t), "--format", "kpf", "-o", str(tmp_path / "kp")]) == 1
    assert not (tmp_path / "kp.wheel").exists()
    capsys.readouterr()
    assert main(["export", str(t), "--format", "mat", "--method", "bogus",
                 "-o", str(tmp_path / "x.mat")]) == 1
    assert "[--method]" in capsys.readouterr().err and not (tmp_path / "x.mat").exists()


def test_csv_export_to_standard_output(hook_table, capsys):
    _, t = hook_table
    capsys.readouterr()
    assert main(["export", str(t), "--format", "csv", "-o", "-"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("# lutmpi table") and "y_mm," in out
    assert not (REPO_ROOT / "-").exists()


def test_a_profile_path_that_is_a_folder_says_so(tmp_path, capsys):
    (tmp_path / "w.whl").mkdir()
    cfg = tmp_path / "c.toml"
    cfg.write_text('[wheel]\nprofile = "w.whl"\n[rail]\ngenerator = "UIC60"\n')
    assert main(["solve", str(cfg), "--pose", "0", "0"]) == 1
    err = capsys.readouterr().err
    assert "[wheel.profile]" in err and "is a folder" in err, err


def test_a_report_of_a_table_of_some_quantities_leaves_out_what_it_cannot_show(tmp_path):
    cfg = write_config(tmp_path, ny=5, nyaw=3, quantities=("z_g", "rolling_radius"))
    t = tmp_path / "q.h5"
    assert main(["build", str(cfg), "-o", str(t), *HOOK]) == 0
    assert main(["report", str(t), "-o", str(tmp_path / "rep")]) == 0
    text = (tmp_path / "rep" / "report.md").read_text()
    assert "left out: the table does not store" in text and "contact_angle" in text
    assert "delta_r.png" in text and "z_g.png" in text and "contact_angles.png" not in text
