"""``lutmpi solve``: poses in, one CSV row per pose out; bad pose files name file and line."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from lutmpi.cli import main
from lutmpi.contact.poses import read_poses
from lutmpi.errors import ConfigError

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "configs" / "paper_s1002_uic60_1in20.toml"


def test_solve_writes_one_row_per_pose_with_units(tmp_path):
    poses = tmp_path / "p.csv"
    poses.write_text("y_mm,yaw_rad\n0,0\n-3,0.05\n")
    out = tmp_path / "o.csv"
    rc = main(["solve", str(CONFIG), "--poses", str(poses), "--pose", "4", "-0.02",
               "--method", "reference", "-o", str(out)])
    assert rc == 0
    rows = list(csv.DictReader(out.open()))
    assert [float(r["y_mm"]) for r in rows] == [0.0, -3.0, 4.0]
    # the schema's columns, as `lutmpi export --format csv` writes them (mm, deg)
    for col in ("z_g_mm", "roll_deg", "wheel_s_left_s0_mm", "contact_angle_right_s0_deg",
                "rolling_radius_left_s0_mm", "wheel_point_x_right_s0_mm", "n_contacts_left",
                "status", "status_text", "message"):
        assert col in rows[0]
    assert all(r["status"] == "0" and r["status_text"] == "converged" for r in rows)
    # symmetry of the centred pose: equal rolling radii, zero roll
    r0 = rows[0]
    assert float(r0["roll_deg"]) == pytest.approx(0.0, abs=1e-10)
    assert float(r0["rolling_radius_left_s0_mm"]) == pytest.approx(
        float(r0["rolling_radius_right_s0_mm"]), abs=1e-9)
    # a lateral shift to the right (y < 0) rolls the wheelset toward the right
    assert float(rows[1]["roll_deg"]) < 0 < float(rows[2]["roll_deg"])


@pytest.mark.parametrize("text, match", [
    ("y,yaw\n0,0\n", "header lacks"),
    ("y_mm,yaw_rad\n0,abc\n", "line 2"),
    ("y_mm,yaw_rad\n0,0\n1\n", "line 3"),
    ("y_mm,yaw_rad\n500,0\n", "out of range"),
    ("y_mm,yaw_rad\nnan,0\n", "out of range"),
    ("y_mm,yaw_rad\n", "no poses"),
    ("", "no header"),
])
def test_bad_pose_files_name_file_and_line(tmp_path, text, match):
    f = tmp_path / "bad.csv"
    f.write_text(text)
    with pytest.raises(ConfigError, match=match) as exc:
        read_poses(f)
    assert str(f) in str(exc.value)


def test_missing_pose_file_is_a_clear_error(tmp_path):
    rc = main(["solve", str(CONFIG), "--poses", str(tmp_path / "nope.csv")])
    assert rc == 1


@pytest.mark.parametrize("command", ["solve", "query"])
@pytest.mark.parametrize("pose, shown", [(("nan", "0"), "y_mm=nan"),
                                         (("0", "1.2"), "yaw_rad=1.2"),
                                         (("150", "0"), "y_mm=150")])
def test_a_bad_command_line_pose_is_an_error_naming_it(tmp_path, capsys, command, pose, shown):
    """``--pose`` values are checked as a poses file's are (a hostile tester's find: a NaN pose
    or a yaw of 1.2 rad came back as a ``no_contact`` row): exit 1, the option and the value
    named, nothing written."""
    out = tmp_path / "o.csv"
    source = str(CONFIG) if command == "solve" else str(tmp_path / "t.h5")
    rc = main([command, source, "--pose", "1", "0", "--pose", *pose, "-o", str(out)])
    assert rc == 1
    err = capsys.readouterr().err
    assert "--pose number 2" in err and shown in err and "out of range" in err
    assert not out.exists()
