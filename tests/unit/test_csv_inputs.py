"""The small CSV inputs and option values a hostile tester broke (2026-11-28): each is now a
clear error naming the file and line (or the option), never a traceback or a silent number.

* a poses file (``solve``, ``query``) with a decimal comma lost its yaw's digits (extra fields
  dropped: yaw 0), and a Latin-1 or UTF-16 file ended in a UnicodeDecodeError;
* ``conicity --dr`` read its columns by position (``delta_r_mm,y_mm`` taken as y, Δr), refused a
  comment before the header, ended in tracebacks on a repeated y and on Latin-1 text, and exited
  0 with nothing but NaN;
* ``report --error-target rolling_radius=5um`` ended in a traceback, ``=nan`` was accepted.
"""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.cli import main
from lutmpi.commands.conicity import read_dr_csv
from lutmpi.contact.poses import read_poses
from lutmpi.errors import ConfigError

pytestmark = pytest.mark.timeout(300)


def _file(tmp_path, text: str | bytes, name: str = "in.csv"):
    p = tmp_path / name
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text, encoding="utf-8")
    return p


def _cone_csv(tmp_path, lam: float = 0.2, half_mm: float = 3.0, name: str = "cone.csv",
              header: str = "y_mm,delta_r_mm"):
    """A pure cone, Δr = 2 λ y, sampled every 0.1 mm on ±half_mm (mm in the file)."""
    y = np.round(np.arange(-half_mm, half_mm + 1e-9, 0.1), 10)
    lines = [header] + [f"{v:.2f},{2 * lam * v:.6f}" for v in y]
    if header.startswith("delta_r_mm"):
        lines = [header] + [f"{2 * lam * v:.6f},{v:.2f}" for v in y]
    return _file(tmp_path, "\n".join(lines) + "\n", name)


# -- poses: "1.5,0,005 is read as yaw 0" --------------------------------------------------------
@pytest.mark.parametrize("text, match", [
    ("y_mm,yaw_rad\n1.5,0,005\n", r"line 2: expected 2 fields .*got 3.*decimal comma"),
    ("# poses\ny_mm,yaw_rad\n\n1.5,0.005\n2,0.01,7\n", r"line 5: expected 2 fields .*got 3"),
    ("y_mm,yaw_rad,note\n1.5,0.005\n", r"line 2: expected 3 fields .*got 2"),
])
def test_a_poses_row_must_have_the_headers_field_count(tmp_path, text, match):
    p = _file(tmp_path, text)
    with pytest.raises(ConfigError, match=match) as exc:
        read_poses(p)
    assert str(p) in str(exc.value)


def test_a_spreadsheets_trailing_empty_fields_are_no_data(tmp_path):
    p = _file(tmp_path, "y_mm,yaw_rad\n1.5,0.005,\n2,0,,\n")
    assert read_poses(p) == [(1.5e-3, 0.005), (2e-3, 0.0)]


def test_poses_keep_comments_blank_lines_and_named_extra_columns(tmp_path):
    p = _file(tmp_path, "# made by hand\n\ny_mm,note,yaw_rad\n# first\n1.5,a,0.005\n\n2,b,0\n")
    assert read_poses(p) == [(1.5e-3, 0.005), (2e-3, 0.0)]


def test_a_decimal_comma_pose_fails_the_query_instead_of_yaw_0(tmp_path, capsys):
    p = _file(tmp_path, "y_mm,yaw_rad\n1.5,0,005\n")
    assert main(["query", str(tmp_path / "no_table.h5"), "--poses", str(p)]) == 1
    err = capsys.readouterr().err
    assert "error:" in err and "line 2" in err and "decimal comma" in err
    assert "Traceback" not in err


@pytest.mark.parametrize("data, match", [
    ("y_mm,yaw_rad\n1.5,0.005\n\u00b55,0\n".encode("latin-1"),
     r"line 3: poses file is not UTF-8 text \(byte 0xb5"),
    ("y_mm,yaw_rad\n1,0\n".encode("utf-16"), r"UTF-16 text .*expected UTF-8"),
    ("y_mm,yaw_rad\n1,0\n".encode("utf-16-le"), r"line 1: .*NUL"),
])
def test_a_poses_file_that_is_not_utf8_names_file_and_line(tmp_path, data, match):
    p = _file(tmp_path, data)
    with pytest.raises(ConfigError, match=match) as exc:
        read_poses(p)
    assert str(p) in str(exc.value)


def test_a_quoted_field_over_two_lines_gives_the_line_of_the_bad_row(tmp_path):
    p = _file(tmp_path, 'y_mm,yaw_rad\n"1.5\n",0\n3,x\n')
    with pytest.raises(ConfigError, match="line 4:"):
        read_poses(p)


# -- conicity --dr: columns by name, comments anywhere, repeated y, encoding --------------------
def test_dr_columns_are_read_by_their_names(tmp_path):
    y, dr = read_dr_csv(_cone_csv(tmp_path, header="delta_r_mm,y_mm"))
    np.testing.assert_allclose(dr, 0.4 * y, atol=1e-12)
    assert y[0] == pytest.approx(-3e-3) and y[-1] == pytest.approx(3e-3)


def test_swapped_dr_columns_give_the_cones_conicity(tmp_path, capsys):
    p = _cone_csv(tmp_path, header="delta_r_mm,y_mm")
    assert main(["conicity", "--dr", str(p), "--amplitudes", "1,2"]) == 0
    out = capsys.readouterr().out
    assert "1.000,0.20000" in out and "2.000,0.20000" in out


def test_dr_comments_and_blank_lines_anywhere(tmp_path):
    p = _file(tmp_path, "# measured 2026-11-28\n\ny_mm,delta_r_mm\n-1,-0.2\n# mid\n\n0,0\n"
                        "1,0.2\n")
    y, dr = read_dr_csv(p)
    np.testing.assert_allclose(y, [-1e-3, 0.0, 1e-3])
    np.testing.assert_allclose(dr, [-0.2e-3, 0.0, 0.2e-3])


@pytest.mark.parametrize("text, match", [
    ("y_mm,delta_r_mm\n-2,-0.8\n-1,-0.4\n0,0\n0,0.01\n1,0.4\n", r"lines 4 and 5: y_mm = 0 "),
    ("y_mm,delta_r_mm\n0,0\n-1,-0.4\n1,0.4\n0,0.01\n", r"lines 2 and 5: y_mm = 0 "),
    ("1,2\n-2,-0.8\n-1,-0.4\n0,0\n1,0.4\n", r"line 1: expected the header 'y_mm,delta_r_mm'"),
    ("y_mm,delta_r_mm,extra\n-1,-0.4,5\n0,0,5\n1,0.4,5\n", r"line 1: unexpected column.*extra"),
    ("y,dr\n-1,-0.4\n0,0\n1,0.4\n", r"line 1: header lacks \['y_mm', 'delta_r_mm'\]"),
    ("y_mm,delta_r_mm,y_mm\n-1,-0.4,1\n", r"more than once"),
    ("y_mm,delta_r_mm\n-1,-0.4\n0,0,1\n1,0.4\n", r"line 3: expected 2 fields"),
    ("y_mm,delta_r_mm\n-1,-0.4\n0,x\n1,0.4\n", r"line 3: expected two numbers"),
    ("y_mm,delta_r_mm\n-1,inf\n0,0\n1,0.4\n", r"line 2: expected a finite"),
    ("y_mm,delta_r_mm\n-1,-0.4\n0,0\n", r"2 rows .* at least 3"),
    ("", r"no header"),
    ("y_mm,delta_r_mm\n# r\u00e9sultats\n-1,-0.4\n".encode("latin-1"),
     r"line 2: Δr file is not UTF-8 text \(byte 0xe9"),
])
def test_bad_dr_files_name_file_and_line(tmp_path, text, match):
    p = _file(tmp_path, text)
    with pytest.raises(ConfigError, match=match) as exc:
        read_dr_csv(p)
    assert str(p) in str(exc.value)


@pytest.mark.parametrize("text", [
    "y_mm,delta_r_mm\n-2,-0.8\n-1,-0.4\n0,0\n0,0.01\n1,0.4\n2,0.8\n",
    "y_mm,delta_r_mm\n# r\u00e9sultats\n-1,-0.4\n0,0\n1,0.4\n",
])
def test_bad_dr_files_are_one_line_at_the_command_line(tmp_path, capsys, text):
    p = _file(tmp_path, text.encode("latin-1"))
    assert main(["conicity", "--dr", str(p), "--amplitudes", "1"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("lutmpi conicity: error: ") and str(p) in err


def test_conicity_at_the_datas_edge_is_the_cones(tmp_path, capsys):
    """An amplitude of half the data's span (±3 mm, amplitude 3 mm) was NaN and "no bounded
    motion" by a rounding of the turning-point bracket; also when "2.9:3:0.1" makes it
    3.0000000000000004 mm."""
    p = _cone_csv(tmp_path)
    for amps in ("2.9,3", "2.9:3:0.1"):
        assert main(["conicity", "--dr", str(p), "--amplitudes", amps]) == 0
        cap = capsys.readouterr()
        assert "3.000,0.20000" in cap.out and "tan gamma_e at 3 mm: 0.2000" in cap.out
        assert "no bounded motion" not in cap.err


@pytest.mark.parametrize("amps, why", [("4,5", "4, 5 mm beyond the usable Δr data"),
                                       ("1,2", "1, 2 mm without a bounded motion")])
def test_conicity_with_nan_at_every_amplitude_fails(tmp_path, capsys, amps, why):
    wrong = "y_mm,delta_r_mm\n" + "".join(f"{v},{-0.4 * v:g}\n" for v in range(-3, 4))
    p = _cone_csv(tmp_path) if amps == "4,5" else _file(tmp_path, wrong)
    out = tmp_path / "c.csv"
    assert main(["conicity", "--dr", str(p), "--amplitudes", amps, "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert "error:" in err and "no conicity at any of the 2 amplitudes" in err and why in err


def test_conicity_with_some_nan_still_writes_its_csv(tmp_path, capsys):
    p, out = _cone_csv(tmp_path), tmp_path / "c.csv"
    assert main(["conicity", "--dr", str(p), "--amplitudes", "1,5", "-o", str(out)]) == 0
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    assert rows[0, 1] == pytest.approx(0.2, abs=1e-6) and np.isnan(rows[1, 1])


# -- report --error-target ----------------------------------------------------------------------
@pytest.mark.parametrize("value, shown", [
    ("rolling_radius=5um", "rolling_radius: expected a number > 0 in m"),
    ("rolling_radius=nan", "rolling_radius: expected a number > 0 in m"),
    ("contact_angle=-1e-3", "contact_angle: expected a number > 0 in rad"),
    ("roll=inf", "roll: expected a number > 0 in rad"),
    ("z_g=", "z_g: expected a number > 0 in m"),
    ("stiffness=1", "expected Q=V with Q one of rolling_radius"),
    ("rolling_radius", "expected Q=V"),
])
def test_a_bad_error_target_is_a_usage_error_before_any_work(tmp_path, capsys, value, shown):
    with pytest.raises(SystemExit) as exc:
        main(["report", str(tmp_path / "no_table.h5"), "-o", str(tmp_path / "rep"),
              "--table-error", "--error-target", value])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "argument --error-target" in err and shown in err
    assert not (tmp_path / "rep").exists()


def test_error_target_values_are_si_numbers():
    from lutmpi.commands.report import error_target

    assert error_target("rolling_radius=5e-6") == ("rolling_radius", 5e-6)
    assert error_target("contact_angle=5e-4") == ("contact_angle", 5e-4)


def test_error_target_without_table_error_is_refused(tmp_path, capsys):
    assert main(["report", str(tmp_path / "t.h5"), "-o", str(tmp_path / "rep"),
                 "--error-target", "roll=1e-6"]) == 1
    assert "[--error-target] takes effect only with --table-error" in capsys.readouterr().err
