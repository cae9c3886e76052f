"""The wheelset equations against closed forms derived here, not against the code's own numbers.

Coned wheels on knife-edge rails (:class:`~lutmpi.dynamics.contact_provider.ConedWheelProvider`)
give every contact quantity in closed form; each test below derives the expected value from
rigid-body mechanics (Euler's equations for the spinning axle), rolling kinematics (creepages
of a coned wheel), Hertz's theory (:func:`lutmpi.contact.stiffness.hertz_ellipse`, the
scalar Johnson solution) and Kalker's linear theory (the tabulated
:func:`lutmpi.dynamics.creep.kalker_coefficients`), with the elastic constants written out.
Track frame: x along the track, y to the left, z up; the axle spins at Omega > 0 about +y when
the wheelset rolls toward +x.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lutmpi.contact.stiffness import hertz_ellipse
from lutmpi.dynamics.contact_provider import ConedWheelProvider
from lutmpi.dynamics.creep import kalker_coefficients
from lutmpi.dynamics.wheelset import (
    ContactForces,
    WheelsetParams,
    accelerations,
    contact_forces,
)

R0, B, CROWN = 0.46, 0.75, 0.3   # nominal radius, half contact distance, rail crown radius, m
P = WheelsetParams(r0=R0)
#: no tangential force at all: the cap mu N is 0 (the loads then follow from statics alone)
FRICTIONLESS = P.with_(mu=0.0, saturation="cutoff")


def _no_forces() -> ContactForces:
    """Contact forces that are all zero: the accelerations are then inertia alone."""
    z2, z3 = np.zeros((2, 2)), np.zeros((2, 2, 3))
    return ContactForces(normal_force=z2, tangential=z3, spin_moment=z2, creepage=z3,
                         semi_axes=np.zeros((2, 2, 2)), wheel_force=np.zeros((2, 3)),
                         force=np.zeros(3), moment=np.zeros(3), lift=False)


def test_a_roll_rate_of_the_spinning_axle_needs_eulers_yaw_moment():
    """Euler: the axle's angular momentum H = I_yy Omega a (a the axle, +y) turned by a roll
    rate p about +x changes at dH/dt = p e_x x H = I_yy Omega p e_z; without a contact moment
    the yaw acceleration is therefore -I_yy Omega p / I_zz (a wheelset rolling forward whose
    left wheel rises yaws to the right). The roll rate of the coned wheelset is
    d(roll)/dy * vy, with roll = atan(k y), k = lam / (b - lam r0) (cones on knife edges, both
    wheels touching: ``test_dynamics.py``, the gravitational stiffness of coned wheels)."""
    lam, speed, vy = 0.2, 20.0, 0.05
    k = lam / (B - lam * R0)
    geom = ConedWheelProvider(R0, lam, B).evaluate(0.0, 0.0)
    assert geom.droll_dy == pytest.approx(k, rel=1e-6)            # the closed-form roll
    acc = accelerations(np.array([0.0, 0.0, vy, 0.0, 0.0]), speed, P, geom, _no_forces())
    omega = speed / R0
    expected = -P.I_yy * omega * k * vy / P.I_zz
    assert acc[3] == pytest.approx(expected, rel=1e-5)
    assert abs(expected) > 0.1                                    # rad/s^2: it can fail
    assert acc[2] == 0.0 and acc[4] == 0.0


def test_a_yawing_spinning_axle_takes_its_roll_moment_from_the_wheel_loads():
    """Euler again: a yaw rate r turns H = I_yy Omega e_y at dH/dt = r e_z x H = -I_yy Omega r
    e_x, a roll moment the rails must supply. On level contacts (vertical normals, Klingel's
    case) at +-b the loads then differ by Q_L - Q_R = -I_yy Omega r / b and still carry the
    weight and the vertical load, Q_L + Q_R = W (no friction: no other force)."""
    prov = ConedWheelProvider(R0, 0.1, B, gravitational=False)
    speed, r = 30.0, 0.4
    f = contact_forces(np.array([0.0, 0.0, 0.0, r, 0.0]), speed, FRICTIONLESS,
                       prov.evaluate(0.0, 0.0))
    q = f.normal_force[:, 0]
    transfer = -P.I_yy * (speed / R0) * r / B
    assert q.sum() == pytest.approx(P.total_load, rel=1e-12)
    assert q[0] - q[1] == pytest.approx(transfer, rel=1e-9)
    assert abs(transfer) > 1e3                                    # N: it can fail
    assert np.all(f.tangential == 0.0)


@pytest.mark.parametrize("y", [0.0, 3e-3, -6e-3])
def test_the_spin_creepage_of_a_coned_wheel_is_its_cone_angle_over_r0(y):
    """A coned wheel rolling freely turns at Omega = V / r0 about its axle; the contact normal
    is tilted from the axle's perpendicular by the cone angle delta = atan(lam) whatever the
    roll (the roll tilts axle and normal alike), so the spin creepage is
    phi = Omega (n . a) / V = -+ sin(delta) / r0 (left -, right +; n the rail's outward normal,
    a the axle), the same at every lateral shift y."""
    lam, speed = 0.2, 25.0
    prov = ConedWheelProvider(R0, lam, B)
    f = contact_forces(np.array([y, 0.0, 0.0, 0.0, 0.0]), speed, FRICTIONLESS,
                       prov.evaluate(y, 0.0))
    spin = math.sin(math.atan(lam)) / R0
    np.testing.assert_allclose(f.creepage[:, 0, 2], [-spin, spin], rtol=1e-6)


def test_creep_forces_are_kalker_linear_on_the_hertz_ellipse_of_the_contact():
    """A spin perturbation s of the axle speed (Omega = V / r0 + s) slips both contacts
    longitudinally by xi = (V - Omega r0) / V = -s r0 / V. Kalker's linear theory then gives
    F_x = -G a b C11 xi on each wheel, with G = E / (2 (1 + nu)), C11 from Kalker's table at the
    contact's a/b, and a, b the Hertz semi-axes of the wheel's rolling curvature cos(delta) / r0
    (Meusnier) against the rail crown's 1 / R_crown under the contact's normal load."""
    lam, speed, s = 0.05, 20.0, -5e-3
    prov = ConedWheelProvider(R0, lam, B, rail_crown_radius=CROWN)
    linear = P.with_(saturation="none")
    f = contact_forces(np.array([0.0, 0.0, 0.0, 0.0, s]), speed, linear,
                       prov.evaluate(0.0, 0.0))
    delta = math.atan(lam)
    xi = -s * R0 / speed
    # (the creepages divide by sqrt(V^2 + v_floor^2), v_floor = 0.01 m/s: 1.3e-7 at 20 m/s)
    np.testing.assert_allclose(f.creepage[:, 0, 0], xi, rtol=1e-6)
    # the contacts carry the weight and the vertical load (the static spin creep forces along
    # the inclined tangents take 0.2 % of it, so N is not W / (2 cos delta) exactly); 4e-6 is
    # left by the two fixed-point passes between the loads and the creep forces
    assert f.force[2] == pytest.approx(P.total_load, rel=2e-5)
    load = float(f.normal_force[0, 0])
    assert load == pytest.approx(P.total_load / (2.0 * math.cos(delta)), rel=5e-3)
    a, b, _, _ = hertz_ellipse(math.cos(delta) / R0, 0.0, 0.0, 1.0 / CROWN, load, P.young,
                               P.poisson)
    assert a / b > 1.2             # an ellipse, not a circle: a/b and b/a read other columns
    np.testing.assert_allclose(f.semi_axes[:, 0, 0], a, rtol=1e-4)
    np.testing.assert_allclose(f.semi_axes[:, 0, 1], b, rtol=1e-4)
    shear = P.young / (2.0 * (1.0 + P.poisson))
    c11 = kalker_coefficients(a, b, P.poisson)[0]
    fx = -shear * a * b * c11 * xi
    # the table is linear in a/b between its columns; the dynamics' lookup samples it in
    # ln(a/b): 1e-3 covers that interpolation, the Hertz lookup's 1e-4 on a*b, nothing else
    t1 = np.array([1.0, 0.0, 0.0])          # the rolling direction: x on the level tangent
    np.testing.assert_allclose(f.tangential[:, 0] @ t1, fx, rtol=1e-3)
    assert abs(fx) > 1e3                    # N
