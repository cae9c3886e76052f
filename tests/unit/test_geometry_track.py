"""Placement of rails and wheels on the track, and the rotation convention (issue 3).

Expected values are computed here from the profiles themselves (dense resampling, our own
rotation), never read back from the placed objects' internals.
"""

from __future__ import annotations

import numpy as np
import pytest
from contact_fixtures import INC_20, INC_40
from scipy.optimize import brentq

from lutmpi.contact.mesh import WheelMesh
from lutmpi.errors import GeometryError
from lutmpi.geometry.pose import wheelset_rotation
from lutmpi.geometry.track import PlacedRail, WheelGeometry
from lutmpi.paths import REPO_ROOT
from lutmpi.profiles import read_profile
from lutmpi.profiles.standard import s1002, uic60

GAUGE, DEPTH = 1.435, 0.014


def _mbench():
    return read_profile(REPO_ROOT / "profiles" / "MBench_UIC60_v3.prr", kind="rail")


RAILS = {
    "UIC60 1:20": (uic60, INC_20),
    "UIC60 1:40": (uic60, INC_40),
    "MBench (canted) 0": (_mbench, 0.0),
}


def _own_placement(profile, inc, step=1e-6):
    """Incline the upright profile ourselves (head toward the track centre = rotate the (v, w)
    plane by +inc, so the crown normal (0, 1) becomes (-sin inc, cos inc): toward -u), and return
    (v', w'), the top w'_top and the gauge v'_gp (min v' with w' >= w'_top - DEPTH)."""
    v = np.arange(profile.y_min, profile.y_max, step)
    w = profile.z_at(v)
    c, s = np.cos(inc), np.sin(inc)
    vp, wp = v * c - w * s, v * s + w * c
    top = wp.max()
    return vp, wp, top, vp[wp >= top - DEPTH].min()


def _gauge_u_of_curve(u, z, depth=DEPTH):
    """Min u of the polyline (u, z) where it is at or above z = -depth (linear between samples)."""
    above = z >= -depth
    cands = [u[above].min()]
    for i in np.nonzero(above[:-1] != above[1:])[0]:
        t = (-depth - z[i]) / (z[i + 1] - z[i])
        cands.append(u[i] + t * (u[i + 1] - u[i]))
    return min(cands)


@pytest.mark.parametrize("name", RAILS)
def test_gauge_point_at_half_gauge(name):
    """The gauge point lies on the profile's own curve ``DEPTH`` below the top, at u = gauge / 2:
    against our own resampling every 1 um (a chord of it misses the curve by < 1 nm), and where
    the placed rail's spline crosses the gauge depth. A crossing taken between the placement's
    own samples (0.05 mm apart in v, ~0.4 mm of arc on a steep face) missed it by 1.7 um on the
    canted Manchester rail."""
    gen, inc = RAILS[name]
    prof = gen()
    rail = PlacedRail.place(prof, inc, GAUGE, DEPTH)
    vp, wp, top, _ = _own_placement(prof, inc)
    v_gp = _gauge_u_of_curve(vp, wp - top)
    assert rail.v_gp == pytest.approx(v_gp, abs=1e-8)
    u_cross = brentq(lambda u: rail.height(u) + DEPTH, rail.u_min, 0.7175 + 2e-3)
    print(f"\n{name}: the placed rail crosses the gauge depth at u = {u_cross * 1e3:.5f} mm "
          "(expected 717.5)")
    assert u_cross == pytest.approx(0.7175, abs=5e-7)
    # the right rail is the mirror image (u = -y); that the pose solve really uses it so is
    # checked through the solver in test_contact_reference.py::test_centred_pose_is_symmetric
    # (issue 16: a negated restatement of the line above used to stand here)


# -- a measured rail whose gauge side ends above the gauge depth (review of 2026-11-24) ---------
def _avg_low():
    """The averaged measured low rail: its gauge side ends ~12.7 mm below the top (1:40), and
    its file lists the field side first."""
    return read_profile(REPO_ROOT / "profiles" / "avg_low2.ban", kind="rail")


def test_a_gauge_side_ending_above_the_gauge_depth_says_how_deep_it_reaches():
    """``gauge_point = "depth"`` cannot find the gauge face 14 mm down: the error says how deep
    the gauge side reaches (our own inclination of the profile) and which keys to set; at a
    depth it reaches, the gauge point is found."""
    prof = _avg_low()
    vp, wp, top, _ = _own_placement(prof, INC_40)
    reach = top - wp[np.argmin(vp)]
    with pytest.raises(GeometryError, match=rf"ends {reach * 1e3:.2f} mm below the top of rail, "
                                            r"above the gauge depth of 14\.00 mm") as err:
        PlacedRail.place(prof, INC_40, GAUGE, DEPTH)
    assert "rail.gauge_depth_mm" in str(err.value)
    assert f'rail.gauge_point ("last": the file\'s gauge-side end, at v = {prof.y_min * 1e3:.3f} ' \
        'mm' in str(err.value)
    rail = PlacedRail.place(prof, INC_40, GAUGE, reach - 1e-4)
    assert brentq(lambda u: rail.height(u) + reach - 1e-4, rail.u_min, 0.7175 + 2e-3) == \
        pytest.approx(0.7175, abs=5e-7)


def test_a_gauge_point_on_the_field_side_of_the_top_is_refused():
    """The file's first point is on the field side: as the gauge point it put the rail ~76 mm
    toward the track centre, and the wheels rode on their flange tips, reported converged."""
    prof = _avg_low()
    first = prof.meta["file_first_point_mm"][0] * 1e-3
    with pytest.raises(GeometryError, match="on the field side of the top of rail"):
        PlacedRail.place(prof, INC_40, GAUGE, DEPTH, gauge_v=first)


def test_the_files_last_point_names_the_gauge_side_end_even_when_reading_dropped_it(tmp_path):
    """avg_low2.ban extends its gauge face straight down by 1 um as its last point, which
    reading drops (shadowed by the steep face): ``gauge_point = "last"`` is the profile's
    gauge-side end, not an error; the pose at y = 0 is then on the treads."""
    from lutmpi.config import load_config
    from lutmpi.pose.solve import solve_pose
    from lutmpi.scene import Scene

    prof = _avg_low()
    assert prof.meta["file_last_point_mm"][0] * 1e-3 < prof.y_min   # dropped, by ~1 um
    cfg = tmp_path / "c.toml"
    cfg.write_text(f'[wheel]\nprofile = "{REPO_ROOT / "profiles" / "avg_wheel.whl"}"\n'
                   f'[rail]\nprofile = "{REPO_ROOT / "profiles" / "avg_low2.ban"}"\n'
                   'inclination = "1:40"\ngauge_point = "last"\n[grid]\ny_mm = [-1.0, 1.0, 3]\n'
                   'yaw_rad = [0.0, 0.0, 1]\n[contact]\nmethod = "reference"\n'
                   '[output]\nmethods = ["reference"]\n')
    scene = Scene.from_config(load_config(cfg))
    rail = scene.side("left").rail
    w = float(prof.z_at(prof.y_min))
    assert rail.v_gp == pytest.approx(prof.y_min * np.cos(INC_40) - w * np.sin(INC_40), abs=1e-12)
    res = solve_pose(scene, 0.0, 0.0, "reference")
    assert res.success
    for side in ("left", "right"):            # a worn pair: two tread contacts per wheel here
        assert res.contacts[side]
        for c in res.contacts[side]:
            assert abs(c.contact_angle) < np.radians(5.0), (side, c.contact_angle)


@pytest.mark.parametrize("name", RAILS)
def test_placed_rail_equals_own_rotation(name):
    """Height of the placed rail against our own inclination + shift of the raw profile."""
    gen, inc = RAILS[name]
    prof = gen()
    rail = PlacedRail.place(prof, inc, GAUGE, DEPTH)
    vp, wp, top, v_gp = _own_placement(prof, inc)
    u_own, z_own = GAUGE / 2 + vp - v_gp, wp - top
    # compare on the contact part (between the gauge point and 20 mm field-side of it)
    sel = (u_own > 0.7175) & (u_own < 0.7175 + 0.045) & np.r_[np.diff(u_own) > 0, False]
    # distance normal to the curve (the gauge corner is steep: compare dz cos(slope angle))
    dz = rail.height(u_own[sel]) - z_own[sel]
    dn = np.abs(dz) / np.hypot(1.0, rail.slope(u_own[sel]))
    i = int(np.argmax(dn))
    err = dn[i]
    print(f"\n{name}: max normal distance placed vs own = {err:.2e} m at u = "
          f"{u_own[sel][i] * 1e3:.3f} mm, z = {z_own[sel][i] * 1e3:.3f} mm")
    # 2 um: the placement re-splines the rotated profile from samples 0.05 mm apart in v, which
    # on the steep gauge corner (slope up to tan 85 deg) are sparse in u; 2 um is 1 % of the mesh
    # spacing and 20 % of the allowed indentation
    assert err < 2e-6
    # top of rail at z = 0 (to the 5e-5 m resampling of the placement: curvature h^2/8 ~ 1e-9 m)
    uu = np.linspace(rail.u_min, rail.u_max, 200001)
    assert abs(rail.height(uu).max()) < 1e-8


@pytest.mark.parametrize("inc", (INC_20, INC_40))
def test_inclination_moves_top_field_side(inc):
    """After inclining by delta toward the track centre, the highest point of the head is the
    upright-profile point whose slope is -tan(delta) (tangent horizontal after rotation): on the
    R300 crown that would be v = 300 tan(delta) = 15 mm, beyond the crown's end (~10 mm), so it
    lies on the R80 arc — the top moves field-side of the head centre line by ~ 80 sin(delta)
    past the R300/R80 tangent point. The crown normal at v = 0 tilts toward the centre."""
    prof = uic60()
    v_star = brentq(lambda v: prof.slope(v) + np.tan(inc), 0.0, 0.03)
    w_star = prof.z_at(v_star)
    rail = PlacedRail.place(prof, inc, GAUGE, DEPTH)
    _, _, _, v_gp = _own_placement(prof, inc)
    u_top_expected = GAUGE / 2 + (v_star * np.cos(inc) - w_star * np.sin(inc)) - v_gp
    uu = np.linspace(rail.u_min, rail.u_max, 400001)
    u_top = uu[np.argmax(rail.height(uu))]
    # the head centre line v = 0 (top of the upright profile) after placement:
    u_axis = GAUGE / 2 + (0.0 - prof.z_at(0.0) * np.sin(inc)) - v_gp
    print(f"\ninc={inc:.4f}: top at v*={v_star * 1e3:.3f} mm on the upright profile; "
          f"placed top u={u_top * 1e3:.3f} mm (expected {u_top_expected * 1e3:.3f}), "
          f"{(u_top - u_axis) * 1e3:.3f} mm field-side of the head centre line")
    assert v_star > 0.0  # field side
    assert u_top == pytest.approx(u_top_expected, abs=1e-4)  # the top is flat: 0.1 mm
    assert u_top > u_axis + 5e-3
    # crown normal at v = 0 after inclination: (-sin, cos) in (u, z), i.e. toward the centre
    sl = float(rail.slope(u_axis))
    assert sl == pytest.approx(np.tan(inc) - prof.slope(0.0), abs=2e-3)  # rising toward +u
    assert sl > 0


def test_wheel_tape_circles_at_750mm():
    """Back-to-back 1360 mm, S1002 flange back at s = -70 mm: tape circles at 680 + 70 = 750 mm."""
    prof = s1002()
    assert prof.y_min == pytest.approx(-0.070, abs=1e-9)
    d = 1.360 / 2 + (0.0 - prof.y_min)
    assert d == pytest.approx(0.75)
    wheel = WheelGeometry.place(prof, 0.46, d)
    mesh = WheelMesh.build(wheel, 2.5e-4, 5e-4)
    k0 = int(np.argmin(np.abs(mesh.s)))
    assert abs(mesh.s[k0]) < 1e-12  # a slice on the tape circle
    for side in (1.0, -1.0):
        p, n = mesh.body_points(side, np.array([k0]), np.array([0]))
        assert p[0, 1] == pytest.approx(side * 0.75, abs=1e-12)
        assert p[0, 2] == pytest.approx(-0.46 - prof.z_at(0.0), abs=1e-12)  # lowest point
        assert n[0, 2] < -0.99  # outward normal points down at the bottom


def _rx(a):
    return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])


def _ry(a):
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def _rz(a):
    return np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])


def test_rotation_order_and_roll_sign():
    yaw, roll, pitch = 0.1, -0.03, 0.2
    R = wheelset_rotation(yaw, roll, pitch)
    np.testing.assert_allclose(R, _rz(yaw) @ _rx(roll) @ _ry(pitch), atol=1e-15)
    # a different order gives a different matrix (the test can tell them apart)
    assert np.max(np.abs(R - _rx(roll) @ _rz(yaw) @ _ry(pitch))) > 1e-3
    # positive roll raises the left (y > 0) side, also when yawed (roll about the yawed x axis)
    for y in (0.0, 0.1):
        left = wheelset_rotation(y, 0.01) @ np.array([0.0, 0.75, 0.0])
        right = wheelset_rotation(y, 0.01) @ np.array([0.0, -0.75, 0.0])
        assert left[2] == pytest.approx(0.75 * np.sin(0.01)) and right[2] < 0
    # yaw turns the axle counter-clockwise seen from above: the left end moves to -x
    assert (wheelset_rotation(0.1, 0.0) @ np.array([0.0, 0.75, 0.0]))[0] < 0
