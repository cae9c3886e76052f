"""Contact stiffness of §4.4–4.5: admissible indentation, Hertz point contact, flange stiffness.

All inputs and outputs are SI (m, N, Pa, 1/m for curvatures). Curvatures are signed: positive when
the surface is convex toward the other body (a wheel tread in the rolling direction, the rail head's
R300/R80/R13 arcs), negative when concave (the S1002 flange-root fillet).

Elliptic integrals use SciPy's *parameter* convention m = k² = e²: ``ellipk(m)``, ``ellipe(m)``. The
paper's eq. (12) writes W(g), E(g) with integrand ``1 − (1 − g²) sin²ψ``, i.e. m = 1 − g² where
g = b/a ≤ 1 is the axis ratio (minor/major).

Hertz notation (Johnson, *Contact Mechanics*, 1985, §4.2): the gap between the undeformed
surfaces is h = A x² + B y² with A, B the half-sums of the principal curvatures in the rolling (x)
and lateral (y) directions — the paper's D_long and D_trasv. The major semi-axis of the ellipse
lies along the direction of the *smaller* of A, B. For two bodies of the same material the contact
modulus is E* = E / (2 (1 − ν²)).

Eq. (11) and its unit
---------------------
``K_hertz = 2πG/(3(1−ν)) · 1/sqrt(D_max + D_min) · sqrt(E(g)) / (g W(g)^{3/2})``. With
2G/(1 − ν) = E/(1 − ν²) = 2E*, this is exactly the Hertz load–approach law N = K_hertz · δ^{3/2}
(Johnson eqs. 4.36–4.39 eliminated for a and b), so K_hertz has unit N/m^{3/2}. The paper
quotes it in "N/m" as the stiffness "at unit indentation": the secant N/δ evaluated at δ = 1 m.
The tangent stiffness at an approach δ is dN/dδ = (3/2) K_hertz δ^{1/2} = (3/2) N/δ
(``hertz_tangent_stiffness``); at the paper's allowed indentation 0.01 mm the secant is
K_hertz·sqrt(1e-5) ≈ 3.2e-3 K_hertz.

The paper's numbers (eq. 13, Table 1)
-------------------------------------
* 7.6e10 N/m for the flange cantilever: Table 1 as printed (b = 0.32, h = 0.045, l = 0.0275 m,
  E = 2.06e11 Pa) gives b h³ E / (4 l³) = 7.22e10 N/m. l = 0.027 m gives 7.63e10 ≈ 7.6e10, so the
  paper most likely computed with l = 27 mm (E = 2.17e11 Pa would also do, but no other E is used).
* k_tf = series(7.09e9, 7.6e10) = 6.48e9 N/m and χ = 6.48e9 / 7.87e10 = 0.082 follow from the
  paper's own numbers (with 7.22e10 instead: 6.46e9 and 0.082).
* 7.87e10 (flange base) and 7.09e9 (flange tip) from eq. (11): see ``tests/unit/test_stiffness.py``
  (``test_eq11_with_s1002_uic60_curvatures``). With S1002/UIC60 curvatures eq. (11) gives
  5e10–2e11 N/m^{3/2} both at the base and at the tip; 7.87e10 is reproduced within a few per cent
  at the base (flank line on the rail's R13 gauge corner, rolling curvature cos γ / r, γ = 70°,
  r = 0.47 m: 7.98e10; the concave root polynomial, section C, at S = −32 mm — radius 15.4 mm,
  slope 27° — on R13: 7.38e10), but no plausible tip geometry brings eq. (11) down to 7.09e9:
  a sharper transverse curvature lowers 1/sqrt(D_max + D_min) by less than the elongated ellipse
  raises sqrt(E)/(g W^{3/2}), so eq. (11) is nearly flat along the flange. A tenfold drop needs a
  formula without the 1/g factor (which then gives 3e9–5e9 at the tip) — a possible slip in the
  paper's implementation that we do not adopt. The table uses χ from the paper's stated numbers.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import ArrayLike
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk, elliprd, elliprf

__all__ = [
    "PAPER_K_EL_TF",
    "PAPER_K_HERTZ_BF",
    "PAPER_K_HERTZ_TF",
    "admissible_indentation",
    "axis_ratio_from_curvatures",
    "cantilever_stiffness",
    "check_flange",
    "contact_modulus",
    "flange_factor_at",
    "flange_kc_scale",
    "flange_scale",
    "hertz_ellipse",
    "hertz_geometry",
    "hertz_stiffness_eq11",
    "hertz_tangent_stiffness",
    "paper_flange_chi",
    "relative_curvatures",
    "series",
]

#: eq. (13): Hertz stiffness at the flange base, as printed [N/m, i.e. N/m^{3/2} at δ = 1 m].
PAPER_K_HERTZ_BF = 7.87e10
#: eq. (13): Hertz stiffness at the flange tip, as printed.
PAPER_K_HERTZ_TF = 7.09e9
#: Table 1: flange cantilever stiffness, as printed [N/m].
PAPER_K_EL_TF = 7.6e10

_G_MIN = 1e-9  # smallest axis ratio the eccentricity solver brackets (B/A ≈ 1e17)


# --------------------------------------------------------------------------- eq. (10)


def admissible_indentation(P: float, L: float, R: float, E: float, nu: float) -> float:
    """Approach of a cylinder of length L pressed on a plane, eq. (10) of the paper.

    ``C = 2PK/L · (1 + ln(4L³ / (2KPR)))`` with ``K = (1 − ν²)/(π E)``.

    Parameters
    ----------
    P : float
        Load on the cylinder [N] (paper: 75 kN per wheel).
    L : float
        Cylinder length [m] (paper: 5 mm, the transverse size of a contact patch).
    R : float
        Cylinder radius [m] (paper: the wheel radius).
    E, nu : float
        Young's modulus [Pa] and Poisson's ratio of both bodies.

    Returns
    -------
    float
        Indentation [m]; ≈ 1.1e-4 m with the paper's data.
    """
    for name, value in (("P", P), ("L", L), ("R", R), ("E", E)):
        if not value > 0.0:
            raise ValueError(f"admissible_indentation: {name} must be > 0, got {value!r}")
    k = (1.0 - nu**2) / (np.pi * E)
    return float(2.0 * P * k / L * (1.0 + np.log(4.0 * L**3 / (2.0 * k * P * R))))


# --------------------------------------------------------------------------- Hertz point contact


def contact_modulus(E: float, nu: float) -> float:
    """Contact modulus E* [Pa] of two bodies of the same material: ``E / (2 (1 − ν²))``."""
    return E / (2.0 * (1.0 - nu**2))


def relative_curvatures(
    curv_w_long: ArrayLike, curv_w_trans: ArrayLike, curv_r_long: ArrayLike, curv_r_trans: ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """Half-sums of the principal curvatures: (A, B) = (D_long, D_trasv) of eq. (11) [1/m]."""
    a = 0.5 * (np.asarray(curv_w_long, float) + np.asarray(curv_r_long, float))
    b = 0.5 * (np.asarray(curv_w_trans, float) + np.asarray(curv_r_trans, float))
    return a, b


def _curvature_ratio(g: float) -> float:
    """B/A (≥ 1) as a function of the axis ratio g = b/a ≤ 1.

    Johnson's ``((1/g²) E(e) − K(e)) / (K(e) − E(e))`` suffers cancellation as e → 0. With Carlson's
    forms K = R_F(0, g², 1), K − E = (e²/3) R_D(0, g², 1) the e² factors cancel exactly:
    ``B/A = (3 R_F / R_D − 1) / g²``.
    """
    g2 = g * g
    return float((3.0 * elliprf(0.0, g2, 1.0) / elliprd(0.0, g2, 1.0) - 1.0) / g2)


def axis_ratio_from_curvatures(ratio: float) -> float:
    """Solve Hertz's eccentricity equation: the axis ratio g = b/a ≤ 1 for B/A = ``ratio`` ≥ 1.

    Brent's method on log g in [1e-9, 1]; ``ratio`` = 1 gives a circle (g = 1).
    """
    if not ratio >= 1.0:
        raise ValueError(f"curvature ratio B/A must be >= 1, got {ratio!r}")
    if ratio - 1.0 <= 1e-14:
        return 1.0
    lo = np.log(_G_MIN)
    if np.log(_curvature_ratio(_G_MIN)) < np.log(ratio):
        raise ValueError(
            f"curvature ratio B/A = {ratio:.3e} beyond the solver range (g < {_G_MIN})"
        )
    target = np.log(ratio)
    log_g = brentq(lambda x: np.log(_curvature_ratio(np.exp(x))) - target, lo, 0.0, xtol=1e-14)
    return float(np.exp(log_g))


def hertz_geometry(A: float, B: float) -> tuple[float, float, float, bool]:
    """Shape of the Hertz ellipse from the relative curvatures A (rolling) and B (lateral).

    Parameters
    ----------
    A, B : float
        Half-sums of principal curvatures in the rolling and lateral directions [1/m]; both > 0.

    Returns
    -------
    g : float
        Axis ratio minor/major, 0 < g ≤ 1 (the paper's ``min(a/b, b/a)``).
    K, E : float
        Complete elliptic integrals of the first and second kind at m = 1 − g² (eq. 12's W, E).
    major_along_rolling : bool
        True when the major axis is along the rolling direction (A ≤ B).
    """
    if not (A > 0.0 and B > 0.0):
        raise ValueError(
            "Hertz point contact needs both relative curvatures > 0 (convex gap); got "
            f"A = {A!r} 1/m (rolling), B = {B!r} 1/m (lateral). A zero value is a line contact."
        )
    small, large = (A, B) if A <= B else (B, A)
    g = axis_ratio_from_curvatures(large / small)
    m = 1.0 - g * g
    return g, float(ellipk(m)), float(ellipe(m)), bool(A <= B)


def hertz_ellipse(
    curv_w_long: float,
    curv_w_trans: float,
    curv_r_long: float,
    curv_r_trans: float,
    N: float,
    E: float,
    nu: float,
) -> tuple[float, float, float, float]:
    """Hertz contact ellipse and approach for a normal load N.

    Parameters
    ----------
    curv_w_long, curv_w_trans : float
        Wheel principal curvatures in the rolling and lateral directions [1/m], signed.
    curv_r_long, curv_r_trans : float
        Rail principal curvatures [1/m] (curv_r_long = 0 on straight track).
    N : float
        Normal load [N], > 0.
    E, nu : float
        Young's modulus [Pa] and Poisson's ratio (same for wheel and rail).

    Returns
    -------
    a : float
        Semi-axis in the rolling direction [m].
    b : float
        Semi-axis in the lateral direction [m].
    delta : float
        Approach of distant points [m].
    g : float
        min(a/b, b/a).

    Notes
    -----
    Johnson (1985) §4.2: A + B = p0 E(e) / (E* b_min), δ = p0 b_min K(e) / E*, N = 2π a b p0 / 3
    give ``b_min = (3 N g E(e) / (2π E* (A + B)))^{1/3}``, ``a_maj = b_min / g``,
    ``δ = b_min² (A + B) K(e) / E(e)``.
    """
    if not N > 0.0:
        raise ValueError(f"hertz_ellipse: normal load must be > 0 N, got {N!r}")
    A, B = relative_curvatures(curv_w_long, curv_w_trans, curv_r_long, curv_r_trans)
    g, k_int, e_int, major_rolling = hertz_geometry(float(A), float(B))
    s = float(A + B)
    b_min = (3.0 * N * g * e_int / (2.0 * np.pi * contact_modulus(E, nu) * s)) ** (1.0 / 3.0)
    a_maj = b_min / g
    delta = b_min**2 * s * k_int / e_int
    a, b = (a_maj, b_min) if major_rolling else (b_min, a_maj)
    return a, b, delta, g


def hertz_stiffness_eq11(
    curv_w_long: float,
    curv_w_trans: float,
    curv_r_long: float,
    curv_r_trans: float,
    E: float,
    nu: float,
) -> float:
    """Hertz stiffness "at unit indentation", eq. (11)–(12) exactly as printed.

    ``K = 2πG/(3(1−ν)) / sqrt(D_max + D_min) · sqrt(E(g)) / (g W(g)^{3/2})``, G = E/(2(1+ν)).

    Returns
    -------
    float
        K_hertz [N/m^{3/2}]: N = K δ^{3/2}. The paper reports it in N/m (its value at δ = 1 m).
    """
    A, B = relative_curvatures(curv_w_long, curv_w_trans, curv_r_long, curv_r_trans)
    g, w_int, e_int, _ = hertz_geometry(float(A), float(B))
    shear = E / (2.0 * (1.0 + nu))
    prefactor = 2.0 * np.pi * shear / (3.0 * (1.0 - nu))
    return float(prefactor / np.sqrt(A + B) * np.sqrt(e_int) / (g * w_int**1.5))


def hertz_tangent_stiffness(
    curv_w_long: float,
    curv_w_trans: float,
    curv_r_long: float,
    curv_r_trans: float,
    N: float,
    E: float,
    nu: float,
) -> float:
    """Classical Hertz tangent stiffness dN/dδ at the load N [N/m]: ``(3/2) N / δ``.

    Equals ``(3/2) K_eq11 δ^{1/2}`` with K_eq11 from ``hertz_stiffness_eq11``.
    """
    _, _, delta, _ = hertz_ellipse(curv_w_long, curv_w_trans, curv_r_long, curv_r_trans, N, E, nu)
    return 1.5 * N / delta


# --------------------------------------------------------------------------- flange, §4.5


def cantilever_stiffness(b: float, h: float, l: float, E: float) -> float:  # noqa: E741
    """Tip stiffness of the equivalent flange cantilever, Table 1: ``b h³ E / (4 l³)`` [N/m].

    Same as 3 E I / l³ with I = b h³ / 12. b is the beam width along the rail, h its thickness,
    l the free length [m].
    """
    return b * h**3 * E / (4.0 * l**3)


def series(k1: ArrayLike, k2: ArrayLike) -> np.ndarray | float:
    """Two springs in series: ``k1 k2 / (k1 + k2)`` [N/m]."""
    k1 = np.asarray(k1, float)
    k2 = np.asarray(k2, float)
    out = k1 * k2 / (k1 + k2)
    return float(out) if out.ndim == 0 else out


def paper_flange_chi(
    k_hertz_bf: float = PAPER_K_HERTZ_BF,
    k_hertz_tf: float = PAPER_K_HERTZ_TF,
    k_el_tf: float = PAPER_K_EL_TF,
) -> float:
    """χ = series(k_hertz_tf, k_el_tf) / k_hertz_bf (§4.5; 0.082 with the paper's numbers)."""
    return float(series(k_hertz_tf, k_el_tf)) / k_hertz_bf


def flange_kc_scale(
    r_contact: ArrayLike, r_base: float, r_tip: float, chi: float
) -> np.ndarray | float:
    """Factor on k_c along the flange (§4.5), vectorized over contact radii.

    Parameters
    ----------
    r_contact : array_like
        Distance from the contact point to the wheel axis [m].
    r_base, r_tip : float
        That distance at the flange base and at the flange tip [m], r_tip > r_base.
    chi : float
        Stiffness ratio tip/base, 0 < χ ≤ 1.

    Returns
    -------
    ndarray or float
        1 for r ≤ r_base, χ for r ≥ r_tip, linear in r in between.
    """
    check_flange(r_base, r_tip, chi)
    r = np.asarray(r_contact, float)
    out = _flange_scales(np.ascontiguousarray(r.ravel()), float(r_base), float(r_tip),
                         float(chi)).reshape(r.shape)
    return float(out) if np.ndim(out) == 0 else out


def check_flange(r_base: float, r_tip: float, chi: float) -> None:
    """Raise ``ValueError`` unless the flange radii and ratio make a §4.5 factor: ``r_tip >
    r_base`` (m) and ``0 < chi <= 1``."""
    if not r_tip > r_base:
        raise ValueError(f"flange_kc_scale: need r_tip > r_base, got {r_tip!r} <= {r_base!r}")
    if not 0.0 < chi <= 1.0:
        raise ValueError(f"flange_kc_scale: chi must be in (0, 1], got {chi!r}")


@njit(cache=True)
def flange_scale(r, r_base, r_tip, chi):
    """§4.5: the factor on k_c at contact radius ``r`` (m): 1 up to the flange base radius
    ``r_base``, ``chi`` from the tip radius ``r_tip`` on, linear in ``r`` between (unchecked:
    :func:`flange_kc_scale` validates)."""
    return np.interp(r, np.array([r_base, r_tip]), np.array([1.0, chi]))


@njit(cache=True)
def _flange_scales(r, r_base, r_tip, chi):
    out = np.empty(r.size)
    for i in range(r.size):
        out[i] = flange_scale(r[i], r_base, r_tip, chi)
    return out


@njit(cache=True)
def flange_factor_at(s, flange, samp_s, samp_r, r_base, r_tip, chi):
    """The §4.5 factor on k_c of a contact at wheel profile coordinate ``s`` (m): 1 on the
    tread (``s >= 0``: the flange is on the ``s < 0`` side of the tape circle) or without the
    flange model, else :func:`flange_scale` at the wheel radius there (interpolated in the
    wheel's samples ``samp_s``, ``samp_r``, m)."""
    if not flange or s >= 0.0:
        return 1.0
    return flange_scale(np.interp(s, samp_s, samp_r), r_base, r_tip, chi)
