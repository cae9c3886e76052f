"""Kalker's linear creep coefficients and the saturated linear force law (issue 6, item 1).

Reference numbers are typed in here independently of the module's table, from Kalker,
*Three-dimensional elastic bodies in rolling contact* (1990), Table E.3, as transcribed in
Vollebregt's CONTACT (``m_hertz.f90``, ``linrol``) for C11/C22/C23; C33 from the same table as
reproduced in textbooks (see the module docstring for its provenance caveat).
"""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.dynamics.creep import (
    KALKER_TABLE_A_GT_B,
    KALKER_TABLE_A_LE_B,
    kalker_coefficients,
    linear_creep_forces,
    saturation_factor,
)

# (a/b, ν) → (C11, C22, C23, C33), Kalker Table E.3
TABULATED = [
    ((0.1, 0.0), (2.51, 2.51, 0.334, 6.42)),
    ((0.5, 0.25), (3.62, 3.01, 0.929, 1.93)),
    ((0.8, 0.25), (3.91, 3.41, 1.25, 1.37)),
    ((1.0, 0.25), (4.12, 3.67, 1.47, 1.19)),
    ((1.0, 0.5), (5.20, 3.98, 1.63, 1.16)),
    ((1 / 0.5, 0.0), (4.37, 4.37, 2.35, 0.958)),
    ((1 / 0.2, 0.5), (8.82, 9.79, 7.89, 0.341)),
    ((1 / 0.1, 0.25), (11.7, 12.8, 14.6, 0.526)),
]


@pytest.mark.parametrize("ratio_nu,expected", TABULATED)
def test_tabulated_points(ratio_nu, expected):
    ratio, nu = ratio_nu
    got = kalker_coefficients(ratio * 0.004, 0.004, nu)  # a = ratio · b, b = 4 mm
    assert got == pytest.approx(expected, rel=1e-9)


def test_linear_interpolation_between_points():
    # a/b = 0.45, ν = 0.3: mean of rows 0.4 and 0.5, then 0.8·(ν=0.25) + 0.2·(ν=0.5).
    c11_025 = 0.5 * (3.53 + 3.62)
    c11_050 = 0.5 * (4.82 + 4.83)
    got = kalker_coefficients(0.45, 1.0, 0.3)[0]
    assert got == pytest.approx(0.8 * c11_025 + 0.2 * c11_050, rel=1e-12)


def test_only_ratio_matters_and_branches_meet_at_circle():
    assert kalker_coefficients(2e-3, 5e-3, 0.3) == pytest.approx(kalker_coefficients(2, 5, 0.3))
    below = kalker_coefficients(1.0 - 1e-9, 1.0, 0.28)
    above = kalker_coefficients(1.0 + 1e-9, 1.0, 0.28)
    assert below == pytest.approx(above, rel=1e-7)


def test_table_monotonicity():
    # Along a/b from 0.1 up to 1 and on to a/b = 10: C11, C22, C23 rise, C33 falls (all ν).
    rows = np.concatenate([KALKER_TABLE_A_LE_B, KALKER_TABLE_A_GT_B[::-1][1:]])  # (19, 4, 3)
    d = np.diff(rows, axis=0)
    assert np.all(d[:, 1:3, :] > 0)
    assert np.all(d[:, 0, :2] > 0)
    # C11 at ν = 0.5 dips (4.85, 4.81, 4.80, 4.82 for a/b = 0.1…0.4) on its way to the asymptote
    # π²/(4(1 − ν)) = 4.93 as a/b → 0: a genuine feature of the table, monotone from a/b = 0.3 on.
    assert np.all(d[2:, 0, 2] > 0) and d[0, 0, 2] < 0
    assert np.all(d[:, 3, :] < 0)
    # C11 = C22 at ν = 0 (Kalker: for ν = 0 longitudinal and lateral creep are alike).
    assert np.array_equal(rows[:, 0, 0], rows[:, 1, 0])
    # C11, C22, C23 increase with ν.
    assert np.all(np.diff(rows[:, :3, :], axis=2) > 0)


def test_asymptotes_a_much_less_than_b():
    # Kalker: a/b → 0: C11 → π²/(4(1−ν)), C22 → π²/4, C23 → 0, C33 ~ π²/(16(1−ν) a/b).
    nu = 0.25
    c11, c22, c23, c33 = kalker_coefficients(1e-5, 1.0, nu)
    assert c11 == pytest.approx(np.pi**2 / (4 * (1 - nu)), rel=1e-3)
    assert c22 == pytest.approx(np.pi**2 / 4, rel=1e-3)
    assert 0 < c23 < 0.02
    assert c33 * 1e-5 == pytest.approx(np.pi**2 / (16 * (1 - nu)), rel=1e-3)
    # The C33 asymptote is within 6 % of the tabulated g = 0.1 row for every ν (a check on the
    # transcribed C33 column, which has no second source here).
    for nu_i, tab in zip((0.0, 0.25, 0.5), (6.42, 8.28, 11.7), strict=True):
        assert np.pi**2 / (16 * (1 - nu_i) * 0.1) == pytest.approx(tab, rel=0.06)


def test_asymptotes_a_much_greater_than_b_and_continuity():
    # b/a → 0: C11, C22 ~ 1/(g ln(16/g²)), C23 ~ g^{-3/2}/ln: all grow without bound.
    prev = None
    for ratio in (5.0, 9.99, 10.0, 10.01, 30.0, 100.0, 1e3):
        c = np.array(kalker_coefficients(ratio, 1.0, 0.3))
        if prev is not None:
            assert np.all(c[:3] > prev[:3])
        prev = c
    lo = np.array(kalker_coefficients(9.999, 1.0, 0.3))
    hi = np.array(kalker_coefficients(10.001, 1.0, 0.3))
    assert hi == pytest.approx(lo, rel=1e-3)
    lo = np.array(kalker_coefficients(0.0999, 1.0, 0.3))
    hi = np.array(kalker_coefficients(0.1001, 1.0, 0.3))
    assert hi == pytest.approx(lo, rel=5e-3)


def test_invalid_inputs():
    with pytest.raises(ValueError, match="nu"):
        kalker_coefficients(1.0, 1.0, 0.6)
    with pytest.raises(ValueError, match="semi-axes"):
        kalker_coefficients(0.0, 1.0, 0.3)
    with pytest.raises(ValueError, match="valid: cutoff, shen_hedrick_elkins"):
        saturation_factor(1.0, 1.0, "polach")


# ----------------------------------------------------------------------------- force law

G = 8.0e10
A, B = 6e-3, 4e-3
N = 7.5e4
MU = 0.2


def _c():
    return kalker_coefficients(A, B, 0.3)


def test_zero_creepage_zero_force():
    fx, fy, mz = linear_creep_forces((0.0, 0.0, 0.0), A, B, G, _c(), N, MU)
    assert (fx, fy, mz) == (0.0, 0.0, 0.0)


def test_small_creepage_is_kalker_linear():
    c11, c22, c23, c33 = _c()
    xi, eta, phi = 1e-6, -2e-6, 1e-5
    fx, fy, mz = linear_creep_forces((xi, eta, phi), A, B, G, (c11, c22, c23, c33), N, MU)
    c = np.sqrt(A * B)
    fx_lin = -G * c**2 * c11 * xi
    fy_lin = -G * c**2 * (c22 * eta + c * c23 * phi)
    mz_lin = -G * c**3 * (-c23 * eta + c * c33 * phi)
    beta = np.hypot(fx_lin, fy_lin) / (MU * N)
    assert beta < 0.01  # well inside the linear range: SHE reduces by ≈ β/3
    assert fx == pytest.approx(fx_lin, rel=beta)
    assert fy == pytest.approx(fy_lin, rel=beta)
    assert mz == pytest.approx(mz_lin, rel=beta)
    assert np.sign(fx) == -np.sign(xi) and np.sign(fy_lin) == np.sign(fy)


@pytest.mark.parametrize("law", ["shen_hedrick_elkins", "cutoff"])
def test_saturation_is_exactly_mu_n_and_keeps_direction(law):
    creep = (0.02, -0.01, 0.0)  # β ≫ 3
    c11, c22, _, _ = _c()
    fx, fy, _ = linear_creep_forces(creep, A, B, G, _c(), N, MU, law)
    assert np.hypot(fx, fy) == pytest.approx(MU * N, rel=1e-12)
    # direction of the linear force (−C11 ξ, −C22 η) kept
    assert np.arctan2(fy, fx) == pytest.approx(np.arctan2(c22 * 0.01, -c11 * 0.02), abs=1e-12)


def test_she_curve_values():
    # Johnson–Vermeulen: F/μN = β − β²/3 + β³/27 (β < 3); at β = 1: 19/27, at β = 3: 1.
    eps = saturation_factor(np.array([0.0, 1.0, 3.0, 6.0]), 1.0)
    assert eps == pytest.approx([1.0, 19 / 27, 1 / 3, 1 / 6])
    assert saturation_factor(5.0, 0.0) == 0.0  # no normal load → no tangential force


def test_broadcasting_over_contacts():
    xi = np.array([0.0, 1e-4, 1e-2])
    n = np.array([N, N, 0.0])
    fx, fy, mz = linear_creep_forces((xi, 0.0, 0.0), A, B, G, _c(), n, MU)
    assert fx.shape == (3,)
    assert fx[0] == 0.0 and fx[1] < 0.0 and fx[2] == 0.0
    assert np.all(fy == 0.0) and np.all(mz[:2] == 0.0)
