"""Contact stiffness (§4.4–4.5): eq. (10), Hertz point contact, eq. (11), flange cantilever.

Oracles: the closed-form sphere-on-plane solution, the classical Hertz coefficient table
(m, n vs θ), the paper's printed numbers, and arithmetic done by hand in the comments.
"""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.contact.stiffness import (
    PAPER_K_EL_TF,
    PAPER_K_HERTZ_BF,
    PAPER_K_HERTZ_TF,
    admissible_indentation,
    axis_ratio_from_curvatures,
    cantilever_stiffness,
    contact_modulus,
    flange_kc_scale,
    hertz_ellipse,
    hertz_geometry,
    hertz_stiffness_eq11,
    hertz_tangent_stiffness,
    paper_flange_chi,
    series,
)

E = 2.06e11
NU = 0.3
E_STAR = E / (2 * (1 - NU**2))  # 1.1319e11 Pa


# ----------------------------------------------------------------------------- eq. (10)


@pytest.mark.parametrize("radius", [0.46, 0.49])
def test_admissible_indentation_paper_data(radius):
    # Paper §4.4: P = 75 kN, L = 5 mm, R = wheel radius (0.46 m nominal S1002 wheel; 0.49 also
    # tried), steel. Hand: K = 0.91/(π·2.06e11) = 1.4062e-12; 2PK/L = 4.219e-5 m;
    # ln(5e-7/(2·K·P·0.46)) = ln(5.154) = 1.640 → 1.113e-4 m. The paper says ≈ 0.11 mm.
    c = admissible_indentation(75e3, 5e-3, radius, E, NU)
    assert c == pytest.approx(0.11e-3, rel=0.03)


def test_admissible_indentation_hand_value_and_validation():
    assert admissible_indentation(75e3, 5e-3, 0.46, E, NU) == pytest.approx(1.1130e-4, rel=2e-3)
    with pytest.raises(ValueError, match="L must be > 0"):
        admissible_indentation(75e3, 0.0, 0.46, E, NU)


# ----------------------------------------------------------------------------- Hertz ellipse


@pytest.mark.parametrize("radius,load", [(0.01, 100.0), (0.46, 75e3), (2.0, 1e5)])
def test_sphere_on_plane_closed_form(radius, load):
    a, b, delta, g = hertz_ellipse(1 / radius, 1 / radius, 0.0, 0.0, load, E, NU)
    a_ref = (3 * load * radius / (4 * E_STAR)) ** (1 / 3)
    assert g == 1.0
    assert a == pytest.approx(a_ref, rel=1e-12)
    assert b == pytest.approx(a_ref, rel=1e-12)
    assert delta == pytest.approx(a_ref**2 / radius, rel=1e-12)


def test_crossed_equal_cylinders_are_a_sphere():
    # Wheel curvature 1/R in rolling only, rail 1/R lateral only: A = B = 1/(2R) → sphere R.
    r, load = 0.3, 5e4
    a, b, delta, _ = hertz_ellipse(1 / r, 0.0, 0.0, 1 / r, load, E, NU)
    a_ref = (3 * load * r / (4 * E_STAR)) ** (1 / 3)
    assert (a, b, delta) == pytest.approx((a_ref, a_ref, a_ref**2 / r), rel=1e-10)


# Timoshenko & Goodier, Theory of Elasticity (1951), §140 table (also Boresi & Schmidt, Advanced
# Mechanics of Materials, Table of Hertz coefficients): cos θ = (B − A)/(A + B),
# a = m (3πN(k1+k2)/(4(A+B)))^{1/3}, b = n (same), k_i = (1 − ν_i²)/(π E_i). Three figures;
# such tables carry last-digit errors (Cooper, "Tables of Hertzian contact-stress coefficients",
# 1968), e.g. n(70°) = 0.802 against 0.7999 computed: tolerance 2.5e-3.
HERTZ_TABLE = [  # θ [deg], m, n
    (30, 2.731, 0.493),
    (40, 2.136, 0.567),
    (50, 1.754, 0.641),
    (60, 1.486, 0.717),
    (70, 1.284, 0.802),
    (80, 1.128, 0.893),
    (90, 1.000, 1.000),
]


@pytest.mark.parametrize("theta,m_coef,n_coef", HERTZ_TABLE)
def test_hertz_coefficient_table(theta, m_coef, n_coef):
    a_plus_b = 3.0  # 1/m, arbitrary
    c = np.cos(np.radians(theta))
    big_a, big_b = 0.5 * a_plus_b * (1 - c), 0.5 * a_plus_b * (1 + c)  # A ≤ B → major along x
    load = 5e4
    # curvatures: put everything on the wheel (the split between bodies does not matter)
    a, b, _, _ = hertz_ellipse(2 * big_a, 2 * big_b, 0.0, 0.0, load, E, NU)
    k_sum = 2 * (1 - NU**2) / (np.pi * E)
    scale = (3 * np.pi * load * k_sum / (4 * a_plus_b)) ** (1 / 3)
    assert a / scale == pytest.approx(m_coef, abs=2.5e-3)
    assert b / scale == pytest.approx(n_coef, abs=2.5e-3)


def test_major_axis_follows_smaller_curvature():
    # Tread-like: wheel rolling radius 0.46 m, rail head R300 → A = 1.087, B = 1.667: A < B,
    # so the ellipse is longer in the rolling direction.
    a, b, _, g = hertz_ellipse(1 / 0.46, 0.0, 0.0, 1 / 0.3, 75e3, E, NU)
    assert a > b and g == pytest.approx(b / a)
    a2, b2, _, g2 = hertz_ellipse(0.0, 1 / 0.46, 1 / 0.3, 0.0, 75e3, E, NU)  # swapped
    assert (a2, b2, g2) == pytest.approx((b, a, g), rel=1e-12)


def test_axis_ratio_solver_extremes_and_continuity():
    assert axis_ratio_from_curvatures(1.0) == 1.0
    g_near = axis_ratio_from_curvatures(1.0 + 1e-9)
    assert 0.999 < g_near < 1.0
    # Large ratio: g → 0 monotonically, and the solver stays within its bracket.
    gs = [axis_ratio_from_curvatures(r) for r in (2.0, 10.0, 1e2, 1e4, 1e6)]
    assert all(x > y for x, y in zip(gs, gs[1:], strict=False))
    assert gs[-1] > 0.0
    with pytest.raises(ValueError, match=">= 1"):
        axis_ratio_from_curvatures(0.5)


def test_line_contact_rejected():
    with pytest.raises(ValueError, match="line contact"):
        hertz_geometry(0.0, 1.0)
    with pytest.raises(ValueError, match="> 0"):
        hertz_ellipse(1.0, 1.0, 0.0, 0.0, 0.0, E, NU)


# ----------------------------------------------------------------------------- eq. (11)


def test_eq11_sphere_is_four_thirds_estar_sqrt_r():
    # N = (4/3) E* R^{1/2} δ^{3/2} for a sphere on a plane (Johnson eq. 4.23).
    r = 0.05
    k = hertz_stiffness_eq11(1 / r, 1 / r, 0.0, 0.0, E, NU)
    assert k == pytest.approx(4 / 3 * contact_modulus(E, NU) * np.sqrt(r), rel=1e-12)


@pytest.mark.parametrize(
    "curv",
    [
        (1 / 0.46, 0.0, 0.0, 1 / 0.3),  # tread on R300
        (1 / 0.47, 0.0, 0.0, 1 / 0.013),  # flange flank on the R13 gauge corner
        (1 / 0.46, -1 / 0.0135, 0.0, 1 / 0.013),  # near-conformal root
        (0.3, 1 / 0.012, 0.0, 1 / 0.013),  # flange tip R12 on R13, elongated (g ≈ 0.02)
    ],
)
def test_eq11_is_the_hertz_load_approach_law(curv):
    # eq. (11) is printed as a formula in G, ν, D and elliptic integrals; hertz_ellipse computes δ
    # by Johnson's route. Both must satisfy N = K δ^{3/2} at any load.
    k = hertz_stiffness_eq11(*curv, E, NU)
    for load in (1e3, 7.5e4, 2e5):
        _, _, delta, _ = hertz_ellipse(*curv, load, E, NU)
        assert load == pytest.approx(k * delta**1.5, rel=1e-9)


def test_tangent_stiffness_matches_finite_difference():
    curv = (1 / 0.46, 0.0, 0.0, 1 / 0.3)
    load = 75e3
    kt = hertz_tangent_stiffness(*curv, load, E, NU)
    d1 = hertz_ellipse(*curv, load * (1 - 1e-5), E, NU)[2]
    d2 = hertz_ellipse(*curv, load * (1 + 1e-5), E, NU)[2]
    assert kt == pytest.approx(2e-5 * load / (d2 - d1), rel=1e-6)
    k11 = hertz_stiffness_eq11(*curv, E, NU)
    delta = hertz_ellipse(*curv, load, E, NU)[2]
    assert kt == pytest.approx(1.5 * k11 * np.sqrt(delta), rel=1e-10)


def test_eq11_with_s1002_uic60_curvatures():
    """Paper eq. (13): 7.87e10 (flange base) and 7.09e9 (flange tip).

    S1002 (EN 13715): flange root circle R13 (concave), flank line at ~70°, flange tip R12 (convex);
    UIC60: gauge corner R13, R80 and R300 arcs. Rolling curvature of the wheel at a point of contact
    angle γ and radius r is cos γ / r (Meusnier). Results (E = 206 GPa, ν = 0.3):
    """
    base = hertz_stiffness_eq11(np.cos(np.radians(70)) / 0.47, 0.0, 0.0, 1 / 0.013, E, NU)
    # flange flank (γ = 70°, r = 0.47 m) on the R13 gauge corner: 7.98e10, within 2 % of 7.87e10.
    assert base == pytest.approx(PAPER_K_HERTZ_BF, rel=0.02)
    # Every plausible tip geometry (R12 on R13, on R80, on the flank line; rolling curvature from
    # 1/r down to cos 88°/r) gives 4.9e10 … 2e11: eq. (11) as printed cannot produce 7.09e9.
    r_tip = 0.488
    tips = [
        hertz_stiffness_eq11(cl, 1 / 0.012, 0.0, cr, E, NU)
        for cl in (1 / r_tip, np.cos(np.radians(80)) / r_tip, np.cos(np.radians(88)) / r_tip)
        for cr in (1 / 0.013, 1 / 0.080, 0.0)
    ]
    assert min(tips) > 4 * PAPER_K_HERTZ_TF


# ----------------------------------------------------------------------------- Table 1, §4.5


def test_cantilever_table1_arithmetic():
    # 0.32 · 0.045³ · 2.06e11 / (4 · 0.0275³) = 6.0069e6 / 8.3188e-5 = 7.221e10, not 7.6e10.
    assert cantilever_stiffness(0.32, 0.045, 0.0275, E) == pytest.approx(7.221e10, rel=1e-3)
    # l = 27.0 mm reproduces the printed 7.6e10 (7.63e10).
    assert cantilever_stiffness(0.32, 0.045, 0.027, E) == pytest.approx(7.6e10, rel=0.01)


def test_flange_tip_series_and_chi_from_paper_numbers():
    k_tf = series(PAPER_K_HERTZ_TF, PAPER_K_EL_TF)
    assert k_tf == pytest.approx(6.48e9, rel=1e-3)  # 7.09e9·7.6e10/8.309e10 = 6.485e9
    assert paper_flange_chi() == pytest.approx(0.082, abs=5e-4)  # 6.485e9/7.87e10 = 0.0824
    # With the Table 1 arithmetic (7.22e10) instead: 6.46e9 and still χ = 0.082.
    k_tf2 = series(PAPER_K_HERTZ_TF, cantilever_stiffness(0.32, 0.045, 0.0275, E))
    assert k_tf2 == pytest.approx(6.456e9, rel=1e-3)
    assert series(np.array([1.0, 2.0]), np.array([1.0, 2.0])) == pytest.approx([0.5, 1.0])


def test_flange_kc_scale():
    r_base, r_tip, chi = 0.47, 0.488, 0.082
    r = np.array([0.40, r_base, 0.5 * (r_base + r_tip), r_tip, 0.6])
    out = flange_kc_scale(r, r_base, r_tip, chi)
    assert out == pytest.approx([1.0, 1.0, 0.5 * (1 + chi), chi, chi], abs=1e-15)
    assert flange_kc_scale(0.479, r_base, r_tip, chi) == pytest.approx(1 + (chi - 1) * 0.5)
    assert isinstance(flange_kc_scale(0.3, r_base, r_tip, chi), float)
    with pytest.raises(ValueError, match="r_tip > r_base"):
        flange_kc_scale(r, r_tip, r_base, chi)
    with pytest.raises(ValueError, match="chi"):
        flange_kc_scale(r, r_base, r_tip, 0.0)
