"""What a hostile tester found in sweeps, their reports and plots (2026-11-28): a report measuring
members against the reference of another track, an interrupted sweep reported as complete,
``--only`` erasing the other members and taking a misspelt ID, a side's own wear crashing every
command that names the pair, and a 1-D table plotted as nothing."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from lutmpi.cli import main
from lutmpi.paths import REPO_ROOT
from lutmpi.reports.pair import pair_info

pytestmark = pytest.mark.timeout(400)

HOOK = ["--solver", "tests.support.faulty_solver:solve"]
BASE = """
[base.wheel]
generator = "S1002"
[base.rail]
generator = "UIC60"
[base.grid]
y_mm = [-8.0, 8.0, 17]
yaw_rad = [-0.01, 0.01, 3]
[base.output]
jumps = false
"""


def _index(out):
    return {m["id"]: m for m in json.loads((out / "index.json").read_text())["members"]}


def test_only_names_members_and_keeps_the_complete_ones(tmp_path, capsys):
    sweep = tmp_path / "s.toml"
    sweep.write_text(BASE + '[[sweep]]\nproduct = { "wear.wheel.flange_thinning_mm" = '
                            '[0.0, 1.0, 2.0] }\n')
    out = tmp_path / "out"
    assert main(["sweep", str(sweep), "-o", str(out), *HOOK]) == 0
    before = _index(out)
    ids = list(before)
    assert main(["sweep", str(sweep), "-o", str(out), *HOOK, "--only", ids[1]]) == 0
    after = _index(out)
    assert [after[i]["status"] for i in ids] == ["ok"] * 3      # still on disk, still theirs
    assert after[ids[0]]["points"] == before[ids[0]]["points"] > 0
    capsys.readouterr()
    assert main(["sweep", str(sweep), "-o", str(out), *HOOK, "--only", ids[1][:-1] + "x"]) == 1
    err = capsys.readouterr().err
    assert "[--only]" in err and ids[0] in err and "Traceback" not in err
    assert _index(out) == after


def test_an_interrupted_sweep_lists_every_member_and_its_report_says_incomplete(tmp_path):
    sweep = tmp_path / "s.toml"
    sweep.write_text(BASE + '[[sweep]]\nproduct = { "wear.wheel.flange_thinning_mm" = '
                            '[0.0, 0.5, 1.0, 1.5] }\n')
    out = tmp_path / "out"
    env = dict(os.environ, LUTMPI_FAULT="sleep=0.03",
               PYTHONPATH=os.pathsep.join(filter(None, [str(REPO_ROOT),
                                                        os.environ.get("PYTHONPATH")])))
    proc = subprocess.Popen([sys.executable, "-m", "lutmpi.cli", "sweep", str(sweep), "-o",
                             str(out), *HOOK], env=env, cwd=REPO_ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        t_end = time.monotonic() + 240
        while time.monotonic() < t_end:     # until the first member is done
            if (out / "index.json").is_file() and "ok" in {
                    m["status"] for m in _index(out).values()}:
                break
            time.sleep(0.1)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    finally:
        proc.kill()
    assert proc.returncode != 0
    index = _index(out)
    assert len(index) == 4                          # every member, reached or not
    statuses = [m["status"] for m in index.values()]
    assert statuses[0] == "ok" and "interrupted" in statuses
    assert set(statuses) <= {"ok", "interrupted", "pending"}
    assert "sweep interrupted at member" in err
    assert main(["report", str(out), "-o", str(tmp_path / "rep")]) == 0
    text = (tmp_path / "rep" / "report.md").read_text()
    assert "The sweep is incomplete" in text


def test_a_report_compares_each_member_with_the_reference_of_its_own_track(tmp_path):
    sweep = tmp_path / "s.toml"
    sweep.write_text(BASE + '[[sweep]]\nproduct = { "contact.method" = ["load_centre", '
                            '"reference"], "rail.inclination" = ["1:20", "1:40"] }\n')
    out = tmp_path / "out"
    assert main(["sweep", str(sweep), "-o", str(out), *HOOK]) == 0
    assert main(["report", str(out), "-o", str(tmp_path / "rep")]) == 0
    text = (tmp_path / "rep" / "report.md").read_text()
    assert "2 geometry cases" in text
    cases = text.split("### Case ")[1:]
    assert len(cases) == 2
    for case in cases:       # the member and its reference share the cant
        cant = "1in20" if "'1:20'" in case.splitlines()[0] else "1in40"
        refs = [ln for ln in case.splitlines() if ln.startswith("Reference: ")]
        assert refs and cant in refs[0], case[:400]


def test_a_sides_own_wear_names_the_pair_and_plots(tmp_path):
    cfg = tmp_path / "w.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
                   '[grid]\ny_mm = [-4.0, 4.0, 5]\nyaw_rad = [0.0, 0.0, 1]\n'
                   '[wear.wheel.left]\nflange_thinning_mm = 1.0\n')
    t = tmp_path / "w.h5"
    assert main(["build", str(cfg), "-o", str(t), *HOOK]) == 0
    from lutmpi.table import Table

    assert pair_info(Table.open(t).config_toml).wear == "wheel left flange thinning 1 mm"
    assert main(["plot", str(t), "z_g", "-o", str(tmp_path / "z.png")]) == 0     # a 1-D table
    assert (tmp_path / "z.png").stat().st_size > 10_000


def test_plot_options_a_quantity_has_no_use_for_are_errors(tmp_path, capsys):
    cfg = tmp_path / "p.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
                   '[grid]\ny_mm = [-4.0, 4.0, 5]\nyaw_rad = [-0.01, 0.01, 3]\n')
    t = tmp_path / "p.h5"
    assert main(["build", str(cfg), "-o", str(t), *HOOK]) == 0
    for extra, key in ((["--side", "right"], "[--side]"), (["--slot", "1"], "[--slot]"),
                       (["--component", "0"], "[--component]")):
        capsys.readouterr()
        assert main(["plot", str(t), "z_g", "-o", str(tmp_path / "x.png"), *extra]) == 1
        assert key in capsys.readouterr().err
    assert main(["plot", str(t), "wheel_point", "-o", str(tmp_path / "w.png"), "--side",
                 "right", "--slot", "1", "--component", "0"]) == 0


def test_report_options_of_one_table_are_refused_on_a_sweep_folder(tmp_path, capsys):
    folder = tmp_path / "sweep_out"
    folder.mkdir()
    for extra, key in ((["--method", "load_centre"], "[--method]"),
                       (["--at-y-mm", "3"], "[--at-y-mm]"),
                       (["--table-error"], "[--table-error]")):
        capsys.readouterr()
        assert main(["report", str(folder), "-o", str(tmp_path / "r"), *extra]) == 1
        err = capsys.readouterr().err
        assert key in err and "sweep folder" in err and "Traceback" not in err
    assert not (tmp_path / "r").exists()


def test_the_jobs_script_refuses_a_rank_count_of_zero(tmp_path):
    run = subprocess.run(["bash", str(REPO_ROOT / "jobs" / "build_table.sh"), "c.toml",
                          str(tmp_path / "t.h5")], env=dict(os.environ, NP="0"),
                         capture_output=True, text=True, timeout=60, check=False)
    assert run.returncode == 2 and "NP must be a number of ranks >= 1, got '0'" in run.stderr


def test_check_says_n_a_where_it_measured_nothing(tmp_path, capsys):
    cfg = tmp_path / "one.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
                   '[grid]\ny_mm = [-4.0, 4.0, 5]\nyaw_rad = [0.0, 0.0, 1]\n'
                   '[contact]\nmethod = "reference"\n[output]\nmethods = ["reference"]\n')
    capsys.readouterr()
    main(["check", str(cfg), "--fast", "--method", "reference"])
    out = capsys.readouterr().out
    rows = {ln.split("  ")[0]: ln for ln in out.splitlines()}
    for name in ("accuracy vs reference", "mesh spacing", "mesh window"):
        assert " n/a " in rows[name] + " ", (name, out)
    assert "not applicable" in out and "PASS: 10/10" not in out
