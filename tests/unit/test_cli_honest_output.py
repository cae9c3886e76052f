"""What a hostile tester found in the output of ``query``, ``report``, ``conicity --dr`` and
``sweep`` (2026-11-28), each now said as it is:

* ``query`` printed a pose 1e-12 mm beyond the grid's last y as that y (10 significant digits)
  with the bare message "outside the table grid", and a ``compute_time_s`` of 0 (a point filled
  by reflection) or nothing (between points): no property of a pose;
* ``report`` into a folder of an earlier report left the figures the new one did not draw,
  looking current;
* the sweep report's wear figures: legend entries for members without a value (no curve),
  coincident members' curves hidden under the last one, and Δr cut at the first failed pose
  (±3.5 mm for a hole at ±4 mm) instead of the table's y range;
* ``conicity --dr`` named the rows of a Δr file whose value is ``nan`` "failed poses" to
  "rebuild";
* ``sweep``: the first member built's wall time held the loading of the compiled kernels
  (0.2 s from the cache, 1.5 min compiling a cold one), the others' not; a built member's index
  message said "not reached yet".
"""

from __future__ import annotations

import csv
import io
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from lutmpi.cli import main
from lutmpi.paths import REPO_ROOT
from tests.support.tables import write_config

pytestmark = pytest.mark.timeout(400)

HOOK = ["--solver", "tests.support.faulty_solver:solve"]
#: the paper's pair on a small grid; the rigid reference solver keeps the build cheap
REFERENCE = """[wheel]
generator = "S1002"
[rail]
generator = "UIC60"
[grid]
y_mm = [-4.0, 4.0, 5]
yaw_rad = [-0.01, 0.01, 3]
[contact]
method = "reference"
[output]
methods = ["reference"]
"""


@pytest.fixture(scope="module")
def hook_table(tmp_path_factory):
    """S1002/UIC60 by the closed-form test solver: y in [-9, 9] mm (3), yaw in [-0.12, 0.12]
    rad (3)."""
    d = tmp_path_factory.mktemp("honest")
    cfg = write_config(d, ny=3, nyaw=3)
    assert main(["build", str(cfg), "-o", str(d / "t.h5"), *HOOK]) == 0
    return d / "t.h5"


# -- query ---------------------------------------------------------------------------------------
def _rows(text: str) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(text)))


def test_a_pose_just_beyond_the_grid_says_by_how_much(hook_table, capsys):
    capsys.readouterr()
    assert main(["query", str(hook_table), "--pose", "9.000000000001", "0",
                 "--pose", "9", "0", "--pose", "0", "-0.1200000000001"]) == 1
    cap = capsys.readouterr()
    beyond, edge, yaw = _rows(cap.out)
    assert beyond["y_mm"] == "9" and beyond["out_of_range"] == "1"     # 10 digits: looks on it
    # the float nearest 9.000000000001 mm lies 9.98e-13 mm beyond: said as it is
    said = r"y = 9\.000000000001 mm is (9\.98e-13|1e-12) mm above the grid's range \[-9, 9\] mm"
    assert re.search(said, beyond["message"]), beyond["message"]
    assert "never clamps" in beyond["message"]
    assert edge["out_of_range"] == "0" and edge["message"] == "converged"
    assert re.search(r"yaw = -0\.1200000000001 rad is (1e-13|9\.99e-14) rad below the grid's "
                     r"range \[-0\.12, 0\.12\] rad", yaw["message"]), yaw["message"]
    assert re.search("first: " + said, cap.err), cap.err


def test_query_leaves_out_the_cpu_time_of_the_grid_points(hook_table, capsys):
    """A grid point's solve time is 0 where the point was filled by reflection and no value
    between points: no property of a pose. The column stays (solve's columns), empty."""
    capsys.readouterr()
    assert main(["query", str(hook_table), "--pose", "9", "0.12", "--pose", "-9", "0.12",
                 "--pose", "1", "0.05"]) == 0
    rows = _rows(capsys.readouterr().out)
    assert [r["compute_time_s"] for r in rows] == ["", "", ""]
    assert all(r["z_g_mm"] != "" for r in rows)


# -- report into the folder of an earlier one ----------------------------------------------------
@pytest.fixture(scope="module")
def reference_table(tmp_path_factory):
    d = tmp_path_factory.mktemp("ref")
    (d / "c.toml").write_text(REFERENCE)
    assert main(["build", str(d / "c.toml"), "-o", str(d / "t.h5")]) == 0
    return d / "t.h5"


def test_a_report_again_removes_the_figures_of_the_earlier_one_and_nothing_else(
        reference_table, tmp_path):
    from lutmpi.reports.owned import MANIFEST

    rep = tmp_path / "rep"
    assert main(["report", str(reference_table), "-o", str(rep), "--at-y-mm", "1", "2"]) == 0
    assert (rep / "pair_y+1.0mm.png").is_file() and (rep / "pair_y+2.0mm.png").is_file()
    mine = {"notes.png": b"mine", "data.csv": b"1,2\n"}
    for name, data in mine.items():
        (rep / name).write_bytes(data)
    assert main(["report", str(reference_table), "-o", str(rep)]) == 0     # 0 and 4 mm
    assert not (rep / "pair_y+1.0mm.png").exists() and not (rep / "pair_y+2.0mm.png").exists()
    assert (rep / "pair_y+0.0mm.png").is_file() and (rep / "pair_y+4.0mm.png").is_file()
    assert {n: (rep / n).read_bytes() for n in mine} == mine
    listed = (rep / MANIFEST).read_text().split()
    assert "report.md" in listed and "pair_y+4.0mm.png" in listed and "notes.png" not in listed
    text = (rep / "report.md").read_text()
    pngs = {p.name for p in rep.glob("*.png")} - set(mine)
    assert pngs == set(re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", text))   # each one current


def test_a_folder_of_a_report_made_before_the_list_is_cleared_by_its_links(tmp_path):
    from lutmpi.reports.owned import MANIFEST, report_files

    rep = tmp_path / "rep"
    rep.mkdir()
    (rep / "report.md").write_text("# Contact geometry: S1002 / UIC60\n\n![old.png](old.png)\n"
                                   "![x](../outside.png)\n")
    for name in ("old.png", "mine.png"):
        (rep / name).write_bytes(b"png")
    (tmp_path / "outside.png").write_bytes(b"png")
    with report_files(rep):
        (rep / "new.png").write_bytes(b"png")
    assert sorted(p.name for p in rep.iterdir()) == [MANIFEST, "mine.png", "new.png"]
    assert (tmp_path / "outside.png").exists()                  # a path out is never followed
    # a report.md that is no lutmpi report names nothing of ours
    (rep / "report.md").write_text("# My notes\n\n![mine.png](mine.png)\n")
    (rep / MANIFEST).unlink()
    with report_files(rep):
        pass
    assert (rep / "mine.png").exists() and (rep / "new.png").exists()


# -- the sweep report's wear figures ------------------------------------------------------------
def test_the_wear_curves_legend_names_only_what_is_drawn_each_visible():
    import matplotlib.pyplot as plt

    from lutmpi.reports.plots import draw_curves

    y = np.linspace(-8e-3, 8e-3, 17)
    fig, ax = plt.subplots()
    try:
        empty = draw_curves(ax, {"none": (y, np.full(y.size, np.nan)), "a": (y, 0.1 * y),
                                 "b": (y, 0.1 * y)}, 1e3, 1e3)
        assert empty == ["none"]
        assert [t.get_text() for t in ax.get_legend().get_texts()] == ["a", "b"]
        a, b = ax.get_lines()
        assert (a.get_linestyle(), a.get_color()) != (b.get_linestyle(), b.get_color())
        assert b.get_linewidth() < a.get_linewidth()             # b drawn over a, a still seen
        assert any("no value: none" in t.get_text() for t in ax.texts)
    finally:
        plt.close(fig)


def test_the_wear_dr_covers_the_tables_y_range_with_its_holes_as_gaps(tmp_path, monkeypatch):
    """The test solver raises at y = 4 mm, yaw 0: before, the Δr figure stopped at 3 mm (the
    grid point before it), where the conicity's integration stops."""
    sweep = tmp_path / "s.toml"
    sweep.write_text('[base.wheel]\ngenerator = "S1002"\n[base.rail]\ngenerator = "UIC60"\n'
                     '[base.grid]\ny_mm = [-8.0, 8.0, 17]\nyaw_rad = [-0.01, 0.01, 3]\n'
                     '[base.output]\njumps = false\n[[sweep]]\nproduct = { '
                     '"wear.wheel.flange_thinning_mm" = [0.0, 1.0] }\n')
    out, rep = tmp_path / "out", tmp_path / "rep"
    monkeypatch.setenv("LUTMPI_FAULT", "raise@4/0.0")
    assert main(["sweep", str(sweep), "-o", str(out), *HOOK]) == 0
    assert main(["report", str(out), "-o", str(rep)]) == 0
    rows = list(csv.DictReader(open(rep / "wear_dr.csv")))
    assert {r["member"] for r in rows} == {"ft-0", "ft-1"}
    for member in ("ft-0", "ft-1"):
        got = {float(r["y_mm"]): r["delta_r_mm"] for r in rows if r["member"] == member}
        assert min(got) == -8.0 and max(got) == 8.0 and len(got) == 17
        assert got[4.0] == "" and got[3.0] != "" and got[5.0] != "" and got[-8.0] != ""
    text = (rep / "report.md").read_text()
    assert "whole y range" in text and "y = 4 mm (failed poses)" in text
    assert "wear_dr.csv" in (rep / ".lutmpi-report-files").read_text()


# -- conicity --dr -------------------------------------------------------------------------------
def test_a_dr_files_missing_values_are_named_by_file_and_line(tmp_path, capsys):
    p = tmp_path / "dr.csv"
    p.write_text("y_mm,delta_r_mm\n-4,-1.6\n-3,nan\n-2,-0.8\n-1,-0.4\n0,0\n1,0.4\n2,0.8\n3,1.2\n"
                 "4,nan\n")
    assert main(["conicity", "--dr", str(p), "--amplitudes", "1,3.5"]) == 1
    err = capsys.readouterr().err
    assert f"y = -3 mm (delta_r_mm = nan on line 3 of {p})" in err, err
    assert "give those rows their Δr" in err and "failed poses" not in err
    assert "rebuild" not in err
    assert main(["conicity", "--dr", str(p), "--amplitudes", "1,2"]) == 0
    err = capsys.readouterr().err
    assert f"y = -3, 4 mm (delta_r_mm = nan on lines 3, 10 of {p}), outside the amplitudes" \
        in err, err


# -- sweep: the kernels loaded outside the members' times ----------------------------------------
def test_the_first_members_time_holds_no_kernel_loading(tmp_path):
    """The production solver in a fresh process (whose kernels are not loaded yet): they are
    loaded once before the first member, timed apart; the first member's own warm-up is then
    the others' (a few ms), not the loading (before: 0.2 s of a 0.5 s member, from the cache)."""
    sweep = tmp_path / "s.toml"
    sweep.write_text('[base.wheel]\ngenerator = "S1002"\n[base.rail]\ngenerator = "UIC60"\n'
                     '[base.grid]\ny_mm = [-4.0, 4.0, 5]\nyaw_rad = [-0.01, 0.01, 3]\n'
                     '[base.contact]\nmethod = "reference"\n'
                     '[base.output]\nmethods = ["reference"]\n'
                     '[[sweep]]\nproduct = { "rail.inclination" = ["1:20", "1:40"] }\n')
    out = tmp_path / "out"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [
        str(REPO_ROOT), os.environ.get("PYTHONPATH")])))
    proc = subprocess.run([sys.executable, "-m", "lutmpi.cli", "sweep", str(sweep), "-o",
                           str(out)], env=env, cwd=REPO_ROOT, capture_output=True, text=True,
                          timeout=360, stdin=subprocess.DEVNULL)
    assert proc.returncode == 0, proc.stderr[-3000:]
    loaded = re.search(r"compiled kernels loaded in ([\d.]+) s before the first member",
                       proc.stderr)
    assert loaded, proc.stderr[-3000:]
    per_member = [float(v) for v in re.findall(
        r"compiled kernels loaded before the grid: \[([\d.]+)\] s per rank", proc.stderr)]
    assert len(per_member) == 2, proc.stderr[-3000:]
    assert per_member[0] < 0.25 * float(loaded.group(1)), (per_member, loaded.group(0))
    members = json.loads((out / "index.json").read_text())["members"]
    assert [m["message"] for m in members] == ["built", "built"]
