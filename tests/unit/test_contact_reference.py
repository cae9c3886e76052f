"""Sanity of the semi-analytic reference (contact-locus) solver on S1002 / UIC60 1:20.

The yaw-0 oracle is :func:`contact_fixtures.rigid_2d`: at yaw 0 the rigid problem is planar, so
the contact is the minimum of the vertical gap between the rolled wheel generator
``(side (d + s), -r(s))`` and the placed rail ``z = zr(u)`` — solved by dense sampling plus
bounded minimisation and Brent on the roll, sharing no code with the locus solver.
"""

from __future__ import annotations

import numpy as np
import pytest
from contact_fixtures import MM, rigid_2d, standard_scene

from lutmpi.contact.locus import local_minima
from lutmpi.pose.solve import solve_pose


@pytest.fixture(scope="module")
def scene():
    return standard_scene()


@pytest.mark.parametrize("y_mm", (0.0, 3.0, -4.0, 9.0, -9.0))
def test_reference_equals_planar_oracle_at_zero_yaw(scene, y_mm):
    y = y_mm * MM
    ex = rigid_2d(scene, y)
    r = solve_pose(scene, y, 0.0, "reference")
    print(f"\ny={y_mm:+.0f} mm: dz_g={r.z_g - ex['z_g']:.1e} m droll={r.roll - ex['roll']:.1e} "
          f"ds_L={(r.contacts['left'][0].wheel_s - ex['s_left']) * 1e3:.4f} mm")
    assert r.z_g == pytest.approx(ex["z_g"], abs=1e-8)
    assert r.roll == pytest.approx(ex["roll"], abs=1e-8)
    # s is ill-conditioned where wheel and rail conform (flat gap minimum): 10 um
    assert r.contacts["left"][0].wheel_s == pytest.approx(ex["s_left"], abs=1e-5)
    assert r.contacts["right"][0].wheel_s == pytest.approx(ex["s_right"], abs=1e-5)


def _mirror_point(p):
    return np.array([p[0], -p[1], p[2]])


@pytest.mark.parametrize("y_mm, yaw", [(3.0, 0.05), (7.0, -0.12), (9.0, 0.12), (-5.5, 0.08)])
def test_mirror_symmetry(scene, y_mm, yaw):
    """Mirroring the track about its centre plane (y -> -y) maps (y, yaw, roll) to
    (-y, -yaw, -roll) and swaps the wheels; profile coordinates are unchanged."""
    a = solve_pose(scene, y_mm * MM, yaw, "reference")
    b = solve_pose(scene, -y_mm * MM, -yaw, "reference")
    assert a.z_g == pytest.approx(b.z_g, abs=1e-10)
    assert a.roll == pytest.approx(-b.roll, abs=1e-10)
    for na, nb in (("left", "right"), ("right", "left")):
        assert len(a.contacts[na]) == len(b.contacts[nb])
        for ca, cb in zip(a.contacts[na], b.contacts[nb], strict=True):
            np.testing.assert_allclose(ca.wheel_point, _mirror_point(cb.wheel_point), atol=1e-9)
            np.testing.assert_allclose(ca.rail_point, _mirror_point(cb.rail_point), atol=1e-9)
            assert ca.wheel_s == pytest.approx(cb.wheel_s, abs=1e-9)
            assert ca.contact_angle == pytest.approx(cb.contact_angle, abs=1e-9)


def test_centred_pose_is_symmetric(scene):
    r = solve_pose(scene, 0.0, 0.0, "reference")
    assert r.roll == pytest.approx(0.0, abs=1e-14)
    (cl,), (cr,) = r.contacts["left"], r.contacts["right"]
    assert cl.wheel_s == pytest.approx(cr.wheel_s, abs=1e-12)
    assert cl.rolling_radius == pytest.approx(cr.rolling_radius, abs=1e-12)
    np.testing.assert_allclose(cl.wheel_point, _mirror_point(cr.wheel_point), atol=1e-12)
    # the right rail as the solver places it: the mirror of the left one (gauge point at
    # -717.5 mm), so the rail contact points mirror too and their profile coordinates agree
    np.testing.assert_allclose(cl.rail_point, _mirror_point(cr.rail_point), atol=1e-12)
    assert cl.rail_v == pytest.approx(cr.rail_v, abs=1e-12)
    assert cl.contact_angle == pytest.approx(cr.contact_angle, abs=1e-12)


def _z_s(scene, y, yaw):
    r = solve_pose(scene, y, yaw, "reference")
    assert r.success
    return r.z_g, r.roll, r.contacts["left"][0].wheel_s


@pytest.mark.parametrize("yaw", (0.0, 0.12))
def test_pose_continuous_contact_jumps(scene, yaw):
    """The rigid height is minus the minimum gap, a continuous function of the pose, so z_g and
    roll are continuous in y even where the contact point jumps. A Lipschitz bound would be
    loose: on S1002's 70 deg flank the roll about G (0.46 m above the rail) nearly cancels the
    climb (linearised: droll/dy = sin g / (2 h cos g - l sin g) with lever h ~ 0.72 m and height
    l ~ 0.45 m, singular at g = 72.6 deg), so dz_g/dy reaches ~12 there. Test by refinement:
    on the worst 0.1 mm step, an 8x finer sampling must shrink the largest sub-step of z_g and
    roll (a jump would keep its size), while the contact-point jump keeps its size."""
    h = 0.1 * MM
    ys = np.arange(-9.0, 9.0 + 1e-9, 0.1) * MM
    z, roll, s = map(np.array, zip(*[_z_s(scene, y, yaw) for y in ys], strict=True))
    for name, q in (("z_g", z), ("roll", roll)):
        i = int(np.argmax(np.abs(np.diff(q))))
        fine = np.linspace(ys[i], ys[i] + h, 9)
        qf = np.array([_z_s(scene, y, yaw)[0 if name == "z_g" else 1] for y in fine])
        ratio = np.max(np.abs(np.diff(qf))) / abs(q[i + 1] - q[i])
        print(f"\nyaw={yaw}: worst {name} step {abs(q[i + 1] - q[i]):.2e} at y={ys[i] / MM:.1f} mm;"
              f" largest of 8 sub-steps is {ratio:.2f} of it")
        assert ratio < 0.5
    j = int(np.argmax(np.abs(np.diff(s))))
    assert abs(s[j + 1] - s[j]) > 2 * MM  # the tread-to-flange jump is in the range
    fine = np.linspace(ys[j], ys[j] + h, 9)
    sf = np.array([_z_s(scene, y, yaw)[2] for y in fine])
    print(f"contact jump {abs(s[j + 1] - s[j]) / MM:.2f} mm at y={ys[j] / MM:.1f} mm; "
          f"largest sub-step {np.max(np.abs(np.diff(sf))) / MM:.2f} mm")
    assert np.max(np.abs(np.diff(sf))) > 0.5 * abs(s[j + 1] - s[j])


def test_flange_contact_at_9mm(scene):
    """At y = 9 mm the left wheel touches on its flange. The contact angle of the left wheel at
    yaw 0 is, from the wheel's own geometry, atan(-dr/ds(s)) + roll (the rail normal into the
    wheel is the rolled profile normal). S1002's 70 deg flank line spans only s in [-39.8, -38.4]
    mm: the contact angle exceeds 1 rad (70 deg + roll) there, around y = 6.45 mm; at 9 mm the
    rigid contact has passed it onto the R20 arc toward the tip (s ~ -43 mm, ~50 deg) — the
    planar oracle (test above) confirms s at 9 mm to 1e-5 m."""
    r = solve_pose(scene, 9 * MM, 0.0, "reference")
    (c,) = r.contacts["left"]
    expected = np.arctan(-float(scene.wheel.dr(c.wheel_s))) + r.roll
    print(f"\ny=9 mm: s={c.wheel_s * 1e3:.3f} mm, contact angle {c.contact_angle:.4f} rad "
          f"(profile: {expected:.4f})")
    assert c.wheel_s < -30 * MM
    # the reported angle is the rail normal's; tangency makes it the wheel's to the locus
    # resolution (position error ~1 um on the R13 gauge corner: ~1e-4 rad)
    assert c.contact_angle == pytest.approx(expected, abs=2e-4)
    assert c.contact_angle > 0.8
    # somewhere between the double-contact range (5-7 mm, test below) and 9 mm the rigid
    # contact crosses the 70 deg flank line; scan for it instead of restating where (issue 16:
    # the constant y = 6.45 mm used to be copied from the output)
    on_flank = []
    for y in np.arange(5.0, 9.0 + 1e-9, 0.05) * MM:
        f = solve_pose(scene, y, 0.0, "reference").contacts["left"][0]
        if -39.8 * MM < f.wheel_s < -38.4 * MM:
            on_flank.append((y, f.contact_angle))
    assert on_flank, "the rigid contact never lands on the 70 deg flank line"
    # 70 deg = 1.22 rad on the flank, plus the roll (a few mrad): above 1 rad
    assert all(angle > 1.0 for _, angle in on_flank)
    # the right wheel stays on its tread
    assert r.contacts["right"][0].wheel_s > 0.0


def test_double_contact_between_5_and_7_mm(scene):
    ys = np.arange(5.0, 7.0 + 1e-9, 0.02) * MM
    flagged = []
    for y in ys:
        rig = scene.locus.solve(y, 0.0)
        if len(rig.contacts["left"]) == 2:
            g = rig.loci["left"].gap
            mins = local_minima(g)
            second = np.sort(g[mins])[:2]
            # the gap really has two minima, both touching (within the double tolerance)
            assert second[1] - second[0] <= scene.locus.double_tol
            c1, c2 = rig.contacts["left"]
            assert abs(c1.s - c2.s) > 2 * MM  # tread and flange root, not one flat minimum
            flagged.append(y)
    print(f"\ndouble contact flagged at y in [{min(flagged) / MM:.2f}, {max(flagged) / MM:.2f}] "
          f"mm ({len(flagged)} of {ys.size} samples)")
    assert flagged
