"""Closed-form contact cases (issue 3, "Must show": closed-form tests; STYLE practice 11).

a. Coned wheels ``dr(s) = -lam s`` on upright circular-crown rails (radius Rr), yaw 0.
   At yaw 0 the problem is planar (x = 0): the lowest generator of each wheel is a straight line in
   the wheelset frame, ``Z = A + side lam Y`` with ``A = -r0 - lam d`` (``Y = side (d + s)``,
   ``Z = -(r0 - lam s)``); its unit normal is tilted by ``alpha = atan(lam)`` toward the track
   centre, and the line lies at signed distance ``A cos(alpha)`` from G along that normal. After
   the roll ``theta`` the normal of the left (right) line is tilted by ``beta = theta + alpha``
   (``theta - alpha``): ``n = (-sin beta, cos beta)`` in (y, z). The rail crown of side ``side`` is
   a circle of centre ``C = (side u_c, -Rr)``. Tangency of line and circle (centre below the line,
   at distance Rr):

       (C - G) . n = A cos(alpha) - Rr,      G = (y_g, z_g)            (one equation per wheel)

   Two equations for (z_g, theta) — solved here with fsolve. The contact point is the foot of the
   perpendicular ``C + Rr n``; its wheel coordinate is ``s = side Y - d`` with
   ``Y = cos(theta) (p_y - y_g) + sin(theta) (p_z - z_g)``.
   Linearising the difference of the two equations in (y, theta):
   ``theta = y lam / (u_c - (Rr + z_g) lam)``; and ``dr = r_L - r_R = -lam (s_L - s_R)`` gives
   ``dr = 2 lam y [1 + lam (Rr + z_g) / (u_c - (Rr + z_g) lam)] + O(y^2)`` — the classical
   ``2 lam y`` plus the part of the roll that carries the contact across the crown (~5 % here).

b. A cylinder (``dr = 0``) on the crown rails at yaw psi, roll 0: the lowest generator of the
   cylinder is the horizontal line ``G + t (-sin psi, cos psi, 0) - r0 e_z``; the crown ridge is
   the horizontal line ``y = side u_c, z = 0``. The cylinder lies on both ridges when
   ``z_g = r0`` (roll 0 by symmetry of the two ridges), and touches at the crossing of the two
   lines: ``t = (side u_c - y_g) / cos psi``, i.e. ``x = -t sin psi``, ``s = side t - d``. The
   point lies in the axle's vertical plane: ``(P - G) . (cos psi, sin psi, 0) = 0``. The left
   wheel's tape-circle centre is at ``t = d``: ``x = -d sin psi``.
"""

from __future__ import annotations

import numpy as np
import pytest
from contact_fixtures import (
    D_TAPE,
    MESH_METHODS,
    MM,
    R0,
    cone_wheel,
    crown_rail,
    synthetic_scene,
)
from scipy.optimize import fsolve

from lutmpi.pose.solve import solve_pose

LAM, RR, U_C = 0.05, 0.3, D_TAPE
Y_CONE = (0.0, 2 * MM, -2 * MM, 5 * MM, -5 * MM)


@pytest.fixture(scope="module")
def cone_scene():
    return synthetic_scene(cone_wheel(LAM), crown_rail(RR))


@pytest.fixture(scope="module")
def cylinder_scene():
    return synthetic_scene(cone_wheel(0.0), crown_rail(RR))


def cone_oracle(y: float) -> dict:
    """z_g, roll and contact points of the cone on crowns (module docstring, case a)."""
    alpha = np.arctan(LAM)
    A = -R0 - LAM * D_TAPE
    k = A * np.cos(alpha) - RR

    def eqs(q):
        z, th = q
        out = []
        for side, beta in ((1.0, th + alpha), (-1.0, th - alpha)):
            n = np.array([-np.sin(beta), np.cos(beta)])
            C = np.array([side * U_C, -RR])
            out.append((C - np.array([y, z])) @ n - k)
        return out

    z, th = fsolve(eqs, [R0, 0.0], xtol=1e-13)
    assert np.max(np.abs(eqs([z, th]))) < 1e-14  # tangency holds to rounding
    res = {"z_g": z, "roll": th}
    for name, side, beta in (("left", 1.0, th + alpha), ("right", -1.0, th - alpha)):
        n = np.array([-np.sin(beta), np.cos(beta)])
        p = np.array([side * U_C, -RR]) + RR * n
        Y = np.cos(th) * (p[0] - y) + np.sin(th) * (p[1] - z)
        res[name] = {"point": p, "s": side * Y - D_TAPE}
    return res


@pytest.mark.parametrize("y", Y_CONE)
def test_cone_reference_matches_closed_form(cone_scene, y):
    ex = cone_oracle(y)
    r = solve_pose(cone_scene, y, 0.0, "reference")
    assert r.success
    print(f"\ncone ref y={y / MM:+.0f} mm: dz_g={r.z_g - ex['z_g']:.2e} m "
          f"droll={r.roll - ex['roll']:.2e} rad")
    # README: "the reference solver within 2e-9 m / 1e-11 rad" (issue 16: asserted at the stated
    # precision). z_g: a common offset of both sides, the same 1.03e-9 m at every y -- the placed
    # rail top is known to its 0.05 mm resampling (~1e-9 m on the R300 crown); the roll is the
    # difference of the two sides' heights over 2 u_c, in which that offset cancels: measured
    # 4.6e-12 rad at y = 5 mm (the README said 1.5e-13 before issue 16 re-measured it)
    assert r.z_g == pytest.approx(ex["z_g"], abs=2e-9)
    assert r.roll == pytest.approx(ex["roll"], abs=1e-11)
    for name in ("left", "right"):
        (c,) = r.contacts[name]
        assert c.wheel_s == pytest.approx(ex[name]["s"], abs=1e-6)
        np.testing.assert_allclose(c.wheel_point[1:], ex[name]["point"], atol=2e-6)
        np.testing.assert_allclose(c.rail_point[1:], ex[name]["point"], atol=2e-6)
        assert abs(c.wheel_point[0]) < 1e-12  # planar problem: x = 0


@pytest.mark.parametrize("method", MESH_METHODS)
@pytest.mark.parametrize("y", Y_CONE)
def test_cone_mesh_methods_match_closed_form(cone_scene, method, y):
    """Default mesh (0.25 mm lateral): tolerances from the mesh, not from the code's output —
    the contact position is resolved to about one lateral spacing (0.25 mm), which on a 1:20 cone
    moves the radius by 12 um; the rigid pose is recovered by the zero-indentation extrapolation to
    a small fraction of the allowed indentation (10 um), so z_g to 5 um, roll to 5 um / 0.75 m."""
    ex = cone_oracle(y)
    r = solve_pose(cone_scene, y, 0.0, method)
    assert r.success, r.message
    errs = (r.z_g - ex["z_g"], r.roll - ex["roll"],
            max(abs(r.contacts[n][0].wheel_s - ex[n]["s"]) for n in ("left", "right")))
    print(f"\ncone {method} y={y / MM:+.0f} mm: dz_g={errs[0]:.2e} m droll={errs[1]:.2e} rad "
          f"ds={errs[2] * 1e3:.3f} mm")
    # README: "the mesh methods within 1 um / 1e-7 rad" on this case (measured <= 1.8e-7 m and
    # 4.9e-8 rad, load centre at y = ±2 / ±5 mm): the stated precision, 5x tighter than the
    # mesh-based bound of the docstring (5 um)
    assert abs(errs[0]) < 1e-6
    assert abs(errs[1]) < 1e-7
    assert errs[2] < 0.25 * MM


def test_cone_rolling_radius_difference_is_2_lambda_y(cone_scene):
    """dr = r_L - r_R is 2 lam y to first order; the first-order coefficient including the roll
    (module docstring) is 1 + lam (Rr + r0) / (u_c - (Rr + r0) lam)."""
    coef = 1.0 + LAM * (RR + R0) / (U_C - (RR + R0) * LAM)
    for y in (1 * MM, 2 * MM, 5 * MM):
        r = solve_pose(cone_scene, y, 0.0, "reference")
        ex = cone_oracle(y)
        dr = r.contacts["left"][0].rolling_radius - r.contacts["right"][0].rolling_radius
        dr_ex = -LAM * (ex["left"]["s"] - ex["right"]["s"])
        print(f"\ny={y / MM:.0f} mm: dr/(2 lam y)={dr / (2 * LAM * y):.5f}  "
              f"(linear theory {coef:.5f}); roll/y={r.roll / y:.5f} "
              f"(linear {LAM / (U_C - (RR + R0) * LAM):.5f})")
        assert dr == pytest.approx(dr_ex, abs=1e-7)
        assert dr / (2 * LAM * y) == pytest.approx(coef, rel=2e-3)
        assert dr / (2 * LAM * y) == pytest.approx(1.0, abs=0.1)  # "2 lam y to first order"
        assert r.roll / y == pytest.approx(LAM / (U_C - (RR + R0) * LAM), rel=2e-3)


YAWS = (0.0, 0.05, 0.12)


def cylinder_oracle(y: float, yaw: float) -> dict:
    out = {"z_g": R0, "roll": 0.0}
    for name, side in (("left", 1.0), ("right", -1.0)):
        t = (side * U_C - y) / np.cos(yaw)
        out[name] = {"point": np.array([-t * np.sin(yaw), y + t * np.cos(yaw), 0.0]),
                     "s": side * t - D_TAPE}
    return out


@pytest.mark.parametrize("y", (0.0, 3 * MM))
@pytest.mark.parametrize("yaw", YAWS)
def test_yawed_cylinder_reference(cylinder_scene, yaw, y):
    ex = cylinder_oracle(y, yaw)
    r = solve_pose(cylinder_scene, y, yaw, "reference")
    assert r.success
    assert r.z_g == pytest.approx(R0, abs=1e-7)
    assert r.roll == pytest.approx(0.0, abs=1e-9)
    axis_x = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    G = np.array([0.0, y, r.z_g])
    for name in ("left", "right"):
        (c,) = r.contacts[name]
        # in the axle's vertical plane, on the crown ridge
        assert abs((c.wheel_point - G) @ axis_x) < 1e-9
        np.testing.assert_allclose(c.wheel_point, ex[name]["point"], atol=1e-6)
        assert c.wheel_s == pytest.approx(ex[name]["s"], abs=1e-6)
    # the left wheel's centre is at x = -d sin(yaw): the contact is at x = -(u_c - y) tan(yaw)
    xl = r.contacts["left"][0].wheel_point[0]
    print(f"\nyaw={yaw}: left contact x={xl * 1e3:.3f} mm, wheel centre x="
          f"{-D_TAPE * np.sin(yaw) * 1e3:.3f} mm")


@pytest.mark.parametrize("method", MESH_METHODS)
@pytest.mark.parametrize("yaw", YAWS)
def test_yawed_cylinder_mesh_methods(cylinder_scene, method, yaw):
    """Mesh methods at the default mesh: the contact patch of a cylinder crossing a crown at an
    angle is an ellipse centred on the crossing, so every method lands on it to a mesh spacing
    (0.5 mm circumferential); z_g and roll to the same 5 um as the cone."""
    y = 3 * MM
    ex = cylinder_oracle(y, yaw)
    r = solve_pose(cylinder_scene, y, yaw, method)
    assert r.success, r.message
    axis_x = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    G = np.array([0.0, y, r.z_g])
    dev = max(abs((r.contacts[n][0].wheel_point - G) @ axis_x) for n in ("left", "right"))
    dp = max(np.linalg.norm(r.contacts[n][0].wheel_point[:2] - ex[n]["point"][:2])
             for n in ("left", "right"))
    print(f"\ncyl {method} yaw={yaw}: dz_g={r.z_g - R0:.2e} roll={r.roll:.2e} "
          f"off-plane={dev * 1e3:.4f} mm, |dP|={dp * 1e3:.4f} mm")
    assert r.z_g == pytest.approx(R0, abs=5e-6)
    assert abs(r.roll) < 5e-6 / D_TAPE
    assert dev < 0.5 * MM
    assert dp < 0.5 * MM
