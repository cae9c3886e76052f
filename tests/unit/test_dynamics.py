"""Wheelset dynamics (issue 6) on the analytic coned-wheel provider: oracles that can fail."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lutmpi.contact.stiffness import hertz_ellipse
from lutmpi.dynamics.contact_provider import ConedWheelProvider
from lutmpi.dynamics.critical import (
    jacobian_critical_speed,
    linear_critical_speed,
    linear_parameters,
    max_real_part,
    state_matrix,
)
from lutmpi.dynamics.simulate import classify, nadal_limit, simulate
from lutmpi.dynamics.wheelset import WheelsetParams, contact_forces, hertz_fast, wheelset_rhs

R0, B = 0.46, 0.75
P = WheelsetParams()


def _zero_crossing_period(t: np.ndarray, y: np.ndarray) -> float:
    s = np.sign(y)
    k = np.nonzero(s[1:] * s[:-1] < 0)[0]
    tz = t[k] - y[k] * (t[k + 1] - t[k]) / (y[k + 1] - y[k])   # linear interpolation
    return 2.0 * float(np.mean(np.diff(tz)))


def test_no_creep_forces_at_rest():
    """V -> 0 with zero rates (pure rolling spin V/r0 -> 0): every creep force vanishes, linearly
    in V once V is below the creepage regularisation speed."""
    prov = ConedWheelProvider(R0, 0.05, B)
    g = prov.evaluate(3e-3, 0.01)
    x = np.array([3e-3, 0.01, 0.0, 0.0, 0.0])

    def peak(V: float) -> float:
        f = contact_forces(x, V, P, g)
        return float(max(np.max(np.abs(f.tangential)), np.max(np.abs(f.spin_moment))))

    at_speed = peak(12.0)
    assert at_speed > 1e3                      # the check can fail: forces exist at speed
    assert peak(1e-6) < 1e-3 * at_speed
    assert peak(1e-8) == pytest.approx(peak(1e-6) / 100, rel=1e-3)


def test_centred_rolling_is_an_equilibrium():
    prov = ConedWheelProvider(R0, 0.05, B)
    dx = wheelset_rhs(0.0, np.zeros(5), 20.0, P, prov)
    assert np.max(np.abs(dx[:4])) < 1e-9
    # the spin moments of the coned contacts have a tiny component along the axle (< 1 N m)
    assert abs(dx[4]) * P.I_yy < 1.0
    f = contact_forces(np.zeros(5), 20.0, P, prov.evaluate(0.0, 0.0))
    assert f.force[2] == pytest.approx(P.total_load, rel=1e-4)


def test_mirror_symmetric_initial_conditions_give_mirror_responses():
    prov = ConedWheelProvider(R0, 0.1, B)
    a = simulate(prov, P, 15.0, 1.5, y0=1e-3, vy0=0.05, vyaw0=0.01, events=False)
    b = simulate(prov, P, 15.0, 1.5, y0=-1e-3, vy0=-0.05, vyaw0=-0.01, events=False)
    scale = np.max(np.abs(a.y))
    assert np.max(np.abs(a.y + b.y)) < 1e-4 * scale
    assert np.max(np.abs(a.yaw + b.yaw)) < 1e-4 * np.max(np.abs(a.yaw))
    np.testing.assert_allclose(a.normal_force[:, 0], b.normal_force[:, 1], rtol=1e-6)
    np.testing.assert_allclose(a.lateral_creep_force[:, 0], -b.lateral_creep_force[:, 1],
                               atol=1e-4 * np.max(np.abs(a.lateral_creep_force)))


def test_klingel_wavelength_without_gravitational_stiffness():
    """Coned wheels, vertical normals (no gravitational stiffness): L = 2 pi sqrt(r0 b / lam)."""
    lam, V = 0.1, 3.0
    prov = ConedWheelProvider(R0, lam, B, gravitational=False)
    r = simulate(prov, P, V, 25.0, y0=2e-3, vy0=0.0, events=False, dt_out=0.01)
    klingel = 2 * math.pi * math.sqrt(R0 * B / lam)
    assert _zero_crossing_period(r.t, r.y) * V == pytest.approx(klingel, rel=0.01)


def test_gravitational_stiffness_of_coned_wheels_on_knife_edges():
    """Virtual work: z_G = r0 + lam y^2 / (b - lam r0), so F_y = -2 W lam / (b - lam r0) y."""
    lam = 0.05
    lp = linear_parameters(ConedWheelProvider(R0, lam, B), P, amplitude=1e-3)
    assert lp.k_gy == pytest.approx(2 * P.total_load * lam / (B - lam * R0), rel=0.01)
    assert lp.lam_e == pytest.approx(lam, rel=1e-9)
    assert lp.rho == pytest.approx(lam / B, rel=1e-6)


def test_linear_free_wheelset_without_gravitational_stiffness_is_always_unstable():
    lp = linear_parameters(ConedWheelProvider(R0, 0.05, B, gravitational=False), P)
    assert lp.k_gy == pytest.approx(0.0, abs=1e-6)
    assert all(max_real_part(lp, P, v) > 0 for v in (2.0, 10.0, 40.0))
    # low-speed frequency is Klingel's
    ev = np.linalg.eigvals(state_matrix(lp, P, 2.0))
    w = np.max(np.abs(ev.imag))
    assert 2 * math.pi * 2.0 / w == pytest.approx(2 * math.pi * math.sqrt(R0 * B / 0.05), rel=0.01)


@pytest.mark.slow
def test_linear_and_nonlinear_agree_on_the_critical_speed():
    """1:20 cone, linear creep: the nonlinear model decays 10 % below the linear critical speed
    and grows 10 % above it, at the rates the linearisation predicts.

    Both with linear creep: the Shen-Hedrick-Elkins law is not linear even at small creepage (its
    slope is 1 - 2 beta/3), which alone moves this weakly damped boundary.

    Why the tolerances matter (issue 16): the free wheelset is barely damped near V_c -- the
    eigenvalue's real part is only -3.3e-5 1/s at 0.9 V_c and +3.8e-5 1/s at 1.1 V_c, so over
    40 s the amplitude changes by 0.15 %. The lateral creep damping (2 f22 / (m V) ~ 4000 1/s)
    kills the initial lateral velocity within ms and leaves a hunting mode of y0 ~ vy0 / 4000:
    ~1 um for vy0 = 5 mm/s, ~25 um for 0.1 m/s. This test used to run with solve_ivp's default
    atol (1e-8 m on y, 1 % of a 1 um amplitude per step): the integrator's error then damps the
    motion at ~1e-4 1/s, more than the physical growth, and the run at 1.1 V_c came out at
    -1.9e-4 1/s ("stable"). The physics was right and the claim was right; the measurement was
    not. Tolerances now scale with the amplitude (as ``nonlinear_critical_speed`` does), and the
    simulated growth rate is compared with the eigenvalue of the model's own Jacobian.
    """
    from lutmpi.dynamics.critical import rhs_jacobian

    prov = ConedWheelProvider(R0, 0.05, B)
    p = P.with_(saturation="none")
    lp = linear_parameters(prov, p)
    vc = linear_critical_speed(lp, p).speed
    # Wickens (1965) / Garg & Dukkipati eq. for a free wheelset with gravitational stiffness:
    # the classical model's V_c is a few m/s for a 1:20 cone; the full Jacobian (spin dof,
    # gyroscopic terms) must agree with it (measured 0.8 % apart; 2 % allowed)
    vj, _ = jacobian_critical_speed(prov, p, amplitude=3.5e-4)
    assert vj == pytest.approx(vc, rel=0.02)
    # amplitude-scaled tolerances: y ~ 25 um, so atol 1e-11 m is 4e-7 of it
    atol = np.array([1e-11, 1e-11, 1e-10, 1e-10, 1e-8])
    kw = dict(vy0=0.1, events=False, rtol=1e-9, atol=atol, dt_out=0.02, max_step=0.05)
    for factor in (0.9, 1.1):
        v = factor * vc
        ev = np.linalg.eigvals(rhs_jacobian(prov, p, v))
        sigma = float(np.max(ev.real))       # linear growth rate of the hunting mode, 1/s
        run = simulate(prov, p, v, 40.0, **kw)
        rate = run.summary.growth_rate
        assert np.sign(rate) == np.sign(sigma) == np.sign(factor - 1.0)
        # the nonlinear run at 25 um is in the linear regime: its envelope grows at the
        # eigenvalue's rate (measured within 3 %; 10 % allowed)
        assert rate == pytest.approx(sigma, rel=0.10)


def test_hertz_fast_matches_hertz_ellipse():
    for kl, kt, n in [(1 / 0.46, 1 / 0.3, 5e4), (2.2, 0.05, 6e4), (2.2, 100.0, 1e4)]:
        a, b = hertz_fast(np.array([kl]), np.array([kt]), np.array([n]), 206e9, 0.3)
        ea, eb, _, _ = hertz_ellipse(kl, kt, 0.0, 0.0, n, 206e9, 0.3)
        assert a[0] == pytest.approx(ea, rel=1e-4) and b[0] == pytest.approx(eb, rel=1e-4)


def test_nadal_limit_and_classify():
    assert nadal_limit(math.radians(70), 0.2) == pytest.approx(
        (math.tan(math.radians(70)) - 0.2) / (1 + 0.2 * math.tan(math.radians(70))))
    t = np.linspace(0, 10, 2001)
    assert classify(t, np.exp(-0.3 * t) * np.sin(6 * t)).kind == "stable"
    assert classify(t, np.exp(0.1 * t) * np.sin(6 * t)).kind == "hunting"
    lc = classify(t, 3e-3 * np.sin(6 * t))
    assert lc.kind == "hunting" and lc.amplitude == pytest.approx(3e-3, rel=0.01)


def test_params_from_config_text():
    p = WheelsetParams.from_toml_text('[material]\nyoung_GPa = 210.0\npoisson = 0.28\n'
                                      '[wheel]\nnominal_radius_mm = 450.0\n')
    assert (p.young, p.poisson, p.r0, p.mass, p.I_yy) == (210e9, 0.28, 0.45, 1595.0, 174.0)


def test_jacobian_model_agrees_with_the_classical_model_on_a_cone():
    """The eigenvalues of the simulated rhs's own Jacobian (what the CLI reports as the linear
    critical speed) against the classical Wickens model on a 1:20 cone with linear creep."""
    from lutmpi.dynamics.critical import jacobian_critical_speed

    prov = ConedWheelProvider(R0, 0.05, B)
    p = P.with_(saturation="none")
    vc = linear_critical_speed(linear_parameters(prov, p), p).speed
    vj, fj = jacobian_critical_speed(prov, p, amplitude=1e-4)
    # the full model adds the spin dof and the gyroscopic load shift to Wickens': measured
    # 2.512 vs 2.491 m/s (0.85 %), hunting at 0.156 vs 0.149 Hz; 2 % and 10 % allowed (issue 16:
    # was 10 % and fj > 0, which could barely fail)
    assert vj == pytest.approx(vc, rel=0.02)
    f_classical = linear_critical_speed(linear_parameters(prov, p), p).frequency
    assert fj == pytest.approx(f_classical, rel=0.10)


def test_two_different_wheels_are_linearised_about_their_rolling_offset():
    """Coned wheels whose radii differ by 2 lam y_e roll purely at y = y_e (closed form): the
    rolling offset is found there, and both linear models there equal the centred wheelset's
    (the geometry is the centred one moved by y_e) to the y_e / b = 0.33 % by which the contact
    points on the knife-edge rails move relative to the wheelset centre. Linearised at y = 0
    instead, the wheelset would carry a steady longitudinal creep (Wickens: 3.4 % off) and the
    Jacobian would not be about a steady state."""
    from lutmpi.dynamics.critical import rhs_jacobian, rolling_offset

    p = WheelsetParams(r0=R0)
    centred = ConedWheelProvider(R0, 0.1, B)
    moved = ConedWheelProvider(R0, 0.1, B, offset=-2.5e-3)
    assert rolling_offset(centred) == 0.0
    assert rolling_offset(moved) == pytest.approx(-2.5e-3, abs=1e-8)
    lin = [linear_critical_speed(linear_parameters(pr, p), p).speed for pr in (centred, moved)]
    assert lin[1] == pytest.approx(lin[0], rel=1e-2)
    jac = [jacobian_critical_speed(pr, p, amplitude=1e-4)[0] for pr in (centred, moved)]
    assert jac[1] == pytest.approx(jac[0], rel=1e-2)
    # the steady state the Jacobian is taken about: no accelerations, unlike y = 0
    x0 = np.array([0.0, 0.0, 0.0, 0.0, 0.0])
    assert abs(wheelset_rhs(0.0, x0, 20.0, p, moved)[3]) > 1e-3
    J = rhs_jacobian(moved, p, 20.0, amplitude=1e-4)
    assert np.all(np.isfinite(J))
