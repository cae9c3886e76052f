"""What a hostile tester found at the command line (2026-11-27), each a clear one-line error or a
warning instead of a lost input, a traceback or a silent number: an output that is the
command's input, option values no run can use, a gauge point of a file on a generator rail, a
zero load, a flange thinning that folds the face, output folders that do not exist, failed
points in a build, a closed pipe, Excel's CSV."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from lutmpi.cli import main
from lutmpi.config import load_config
from lutmpi.errors import ConfigError, ProfileError
from lutmpi.profiles.standard import s1002
from lutmpi.profiles.wear import flange_thinning
from lutmpi.table import Table
from tests.support.tables import write_config

pytestmark = pytest.mark.timeout(300)

HOOK = ["--solver", "tests.support.faulty_solver:solve"]


@pytest.fixture(scope="module")
def table(tmp_path_factory):
    d = tmp_path_factory.mktemp("hostile")
    cfg = write_config(d, ny=5, nyaw=3)
    assert main(["build", str(cfg), "-o", str(d / "t.h5"), *HOOK]) == 0
    return cfg, d / "t.h5"


def _bytes(path):
    return path.read_bytes()


def test_an_output_that_is_an_input_is_refused_and_the_input_kept(table, capsys):
    cfg, t = table
    before, cfg_before = _bytes(t), _bytes(cfg)
    for argv in (["query", str(t), "--pose", "0", "0", "-o", str(t)],
                 ["export", str(t), "--format", "csv", "-o", str(t)],
                 ["simulate", str(cfg), "--table", str(t), "--duration", "0.1", "-o", str(t)],
                 ["solve", str(cfg), "--pose", "0", "0", "-o", str(cfg)],
                 ["plot", str(t), "z_g", "-o", str(t)]):
        capsys.readouterr()
        assert main(argv) == 1, argv
        err = capsys.readouterr().err
        assert "is the command's input" in err and "Traceback" not in err, argv
    assert _bytes(t) == before and _bytes(cfg) == cfg_before
    assert Table.open(t).attrs["complete"]


@pytest.mark.parametrize("argv", [
    ["simulate", "C", "--table", "T", "--duration", "0", "-o", "X.h5"],
    ["simulate", "C", "--table", "T", "--speed", "nan", "-o", "X.h5"],
    ["simulate", "C", "--table", "T", "--speed", "-5", "-o", "X.h5"],
    ["conicity", "T", "--e-mm", "0"],
    ["conicity", "T", "--r0-mm", "0"],
    ["conicity", "T", "--r0-mm", "-5"],
    ["export", "T", "--format", "csv", "--yaw-rad", "nan", "-o", "X.csv"],
    ["report", "T", "-o", "R", "--at-y-mm", "nan"],
    ["report", "T", "-o", "R", "--en15302-case", "E42"],
    ["profile", "plot", "C", "--y-mm", "1000"],
])
def test_an_option_value_no_run_can_use_is_a_usage_error(table, argv, capsys):
    cfg, t = table
    argv = [str(cfg) if a == "C" else str(t) if a == "T" else a for a in argv]
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "expected" in err or "invalid choice" in err


@pytest.mark.parametrize("amps", ["0", "-1,2", "nan", "1:7.5:0.0000001"])
def test_conicity_amplitudes_no_curve_can_take_are_refused(table, amps, capsys):
    _, t = table
    assert main(["conicity", str(t), f"--amplitudes={amps}"]) == 1
    err = capsys.readouterr().err
    assert "--amplitudes" in err and "Traceback" not in err


def test_gauge_point_of_a_file_on_a_generator_rail_names_the_key(tmp_path, capsys):
    cfg = tmp_path / "g.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
                   'gauge_point = "first"\n[grid]\ny_mm = [-2.0, 2.0, 3]\n'
                   'yaw_rad = [0.0, 0.0, 1]\n')
    assert main(["solve", str(cfg), "--pose", "0", "0"]) == 1
    err = capsys.readouterr().err
    assert "rail.gauge_point" in err and "generator" in err and "Traceback" not in err


@pytest.mark.parametrize(("rail", "key"), [
    ('gauge_point = 120.0\n', "[rail.gauge_point]"),
    ('[rail.left]\ngauge_point = "first"\n', "[rail.left.gauge_point]"),
    ('[rail.right]\ngauge_point = -150\n', "[rail.right.gauge_point]")])
def test_a_bad_gauge_point_names_its_own_key(tmp_path, capsys, rail, key):
    """A gauge point the rail cannot have (a file's end on a generated rail, a lateral
    coordinate off the profile) names the key that set it, the side's own where it is one."""
    cfg = tmp_path / "g.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n' + rail
                   + '[grid]\ny_mm = [-2.0, 2.0, 3]\nyaw_rad = [0.0, 0.0, 1]\n')
    assert main(["solve", str(cfg), "--pose", "0", "0"]) == 1
    err = capsys.readouterr().err
    assert key in err and "Traceback" not in err, err
    assert "generator" in err or "outside the rail profile" in err, err


def test_a_zero_vertical_load_is_a_config_error(tmp_path):
    cfg = tmp_path / "z.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
                   '[equilibrium]\nvertical_load_N = 0.0\n')
    with pytest.raises(ConfigError, match="vertical_load_N"):
        load_config(cfg)


def test_a_flange_thinning_that_folds_the_face_says_how_much_the_wheel_takes():
    wheel = s1002()
    flange_thinning(wheel, 4.5)                          # deep, and still a profile
    with pytest.raises(ProfileError, match=r"flange_thinning_mm = 5 folds.*at most 4\.\d\d mm"):
        flange_thinning(wheel, 5.0)


def test_an_output_in_a_missing_folder_is_one_line_before_the_work(table, tmp_path, capsys):
    cfg, t = table
    for argv in (["query", str(t), "--pose", "0", "0", "-o", str(tmp_path / "no" / "q.csv")],
                 ["export", str(t), "--format", "csv", "-o", str(tmp_path / "no" / "e.csv")],
                 ["solve", str(cfg), "--pose", "0", "0", "-o", str(tmp_path / "no" / "s.csv")],
                 ["plot", str(t), "z_g", "-o", str(tmp_path / "z.txt")]):
        capsys.readouterr()
        assert main(argv) == 1, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "error:" in err, (argv, err)


def test_a_build_with_failed_points_warns(tmp_path, capfd):
    cfg = write_config(tmp_path, ny=5, nyaw=3)
    capfd.readouterr()
    assert main(["build", str(cfg), "-o", str(tmp_path / "t.h5"), *HOOK]) == 0
    # the faulty solver's corner pose stops at max_iterations
    err = capfd.readouterr().err
    assert "WARNING" in err and "1 of 15 point results did not converge" in err


def test_a_closed_pipe_ends_quietly(table):
    _, t = table
    env = dict(os.environ, PYTHONPATH=os.getcwd())
    proc = subprocess.run(f"{sys.executable} -m lutmpi.cli inspect {t} | head -1", shell=True,
                          capture_output=True, text=True, env=env, timeout=100)
    assert proc.stdout.strip() and "Traceback" not in proc.stderr
    assert "BrokenPipe" not in proc.stderr


def test_a_poses_file_from_excel_reads_and_a_doubled_column_is_refused(tmp_path):
    from lutmpi.contact.poses import read_poses

    p = tmp_path / "p.csv"
    p.write_bytes("\ufeffy_mm,yaw_rad\r\n1.5,0.01\r\n".encode())
    assert read_poses(p) == [(1.5e-3, 0.01)]
    p.write_text("y_mm,yaw_rad,y_mm\n1.5,0.01,2.0\n")
    with pytest.raises(ConfigError, match="more than once"):
        read_poses(p)


def test_a_query_on_a_failed_point_warns_and_report_names_what_it_takes(table, tmp_path,
                                                                        capfd):
    _, t = table
    capfd.readouterr()
    # the faulty solver's point (-9 mm, -0.12 rad) stopped at max_iterations
    assert main(["query", str(t), "--pose", "-9", "-0.12", "--pose", "0", "0",
                 "-o", str(tmp_path / "q.csv")]) == 0
    err = capfd.readouterr().err
    assert "WARNING" in err and "1 of 2 poses lie where the table's points did not converge" in err
    assert main(["report", str(tmp_path / "none.h5"), "-o", str(tmp_path / "r")]) == 1
    assert "no such table file or sweep directory" in capfd.readouterr().err
