"""Units and conventions at lutmpi's edges against values computed by hand or from a standard.

Each test puts a known physical quantity through an edge of the program (an export column, the
``conicity`` command, a profile file read with a reading option) and checks the number that
comes out against its closed form: a curvature in 1/mm is the inverse of its radius in mm,
Klingel's wavelength of a cone, the S1002 radius function of EN 13715.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lutmpi.cli import main
from lutmpi.export.csv_format import record_cells
from lutmpi.profiles.options import ReadOptions
from lutmpi.profiles.readers import read_profile
from lutmpi.profiles.standard import s1002_radius_mm
from lutmpi.table.schema import D


def test_exported_curvatures_are_the_inverse_of_the_exported_radii():
    """A wheel of rolling radius r = 0.46 m has the rolling curvature 1/r: exported in mm and
    1/mm, the two columns multiply to exactly 1 (460 mm times 1/460 1/mm), whatever the
    factor each unit took on its way out."""
    r = np.array([[0.46, 0.52], [0.44, 0.50]])                  # m, (side, slot)
    header, values = record_cells({D.rolling_radius: r, D.curv_wheel_rolling: 1.0 / r})
    cells = dict(zip(header, values, strict=True))
    assert cells["rolling_radius_left_s0_mm"] == pytest.approx(460.0, rel=1e-12)
    assert cells["curv_wheel_rolling_left_s0_per_mm"] == pytest.approx(1.0 / 460.0, rel=1e-12)
    for side, slot in (("left", 1), ("right", 0), ("right", 1)):
        radius = cells[f"rolling_radius_{side}_s{slot}_mm"]
        curvature = cells[f"curv_wheel_rolling_{side}_s{slot}_per_mm"]
        assert radius * curvature == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("r0_mm,e_mm", [(460.0, 1500.0), (500.0, 1493.0)])
def test_conicity_command_gives_klingels_wavelength_of_a_cone(tmp_path, capsys, r0_mm, e_mm):
    """A cone of conicity lam has Δr = 2 lam y and Klingel's kinematic wavelength
    2 pi sqrt(r0 e / (2 lam)), e the distance between the contact points (2 b): the command's
    CSV must hold lam at every amplitude and that wavelength for the --r0-mm and --e-mm given
    in mm."""
    lam = 0.1
    y = np.round(np.arange(-5.0, 5.0 + 1e-9, 0.1), 10)           # mm
    dr_file = tmp_path / "cone.csv"
    dr_file.write_text("y_mm,delta_r_mm\n" + "".join(f"{v:.2f},{2 * lam * v:.6f}\n" for v in y))
    out = tmp_path / "c.csv"
    assert main(["conicity", "--dr", str(dr_file), "--amplitudes", "1,3", "--r0-mm",
                 str(r0_mm), "--e-mm", str(e_mm), "-o", str(out)]) == 0
    capsys.readouterr()
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(rows[:, 1], lam, rtol=1e-5)
    klingel = 2.0 * math.pi * math.sqrt(r0_mm * 1e-3 * e_mm * 1e-3 / (2.0 * lam))   # m
    np.testing.assert_allclose(rows[:, 2], klingel, rtol=1e-5)


def test_a_wheel_file_measured_from_the_flange_back_reads_as_s1002(tmp_path):
    """S1002 (EN 13715) written as a measuring device does: the lateral coordinate from the
    flange back, 70 mm inside the tape circle, and the heights from an arbitrary datum (here
    5 mm below the tape circle). Read with ``origin = "flange_back"`` it must be S1002 again: s
    from the tape circle, the radius increment F(s) with F(0) = 0."""
    s = np.round(np.arange(-69.0, 60.0 + 1e-9, 0.1), 10)          # mm, from the tape circle
    f = s1002_radius_mm(s)
    assert abs(s1002_radius_mm(np.array([0.0]))[0]) < 1e-12      # the tape circle: F = 0
    path = tmp_path / "flange_back.csv"
    path.write_text("# kind: wheel\n" + "".join(f"{a + 70.0:.4f},{b + 5.0:.8f}\n"
                                                 for a, b in zip(s, f, strict=True)))
    prof = read_profile(path, kind="wheel", options=ReadOptions(origin="flange_back"))
    assert prof.y_min <= -0.060 and prof.y_max >= 0.059           # the flange and the tread
    # 0.1 um: the standard's sections meet with rounding steps up to 1e-4 mm at their joints
    # (s1002_joint_jumps), and a sample on a joint may be taken from either section
    np.testing.assert_allclose(prof.z, s1002_radius_mm(prof.y * 1e3) * 1e-3, rtol=0, atol=1e-7)
    assert float(prof.z_at(0.0)) == pytest.approx(0.0, abs=1e-10)
