"""Kalker's linear creep theory with a saturation to μN (§6 of the paper; issue 6).

Coefficients
------------
C11, C22, C23, C33 are Kalker's creepage and spin coefficients of the linear theory of rolling
contact for elliptical contact areas, Table E.3 of

    J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer, 1990
    (first published in J. J. Kalker, *On the rolling contact of two elastic bodies in the
    presence of dry friction*, thesis, Delft, 1967),

tabulated for g = a/b (a ≤ b) and g = b/a (a > b) at g = 0.1, 0.2, …, 1.0 and ν = 0, 0.25, 0.5;
a is the semi-axis in the rolling direction, b the lateral one. Provenance of the numbers below:
C11, C22, C23 were checked entry by entry against the transcription of Table E.3 in E. Vollebregt's
CONTACT (``m_hertz``, subroutine ``linrol``), which carries one typo in some copies (C23 at
a/b = 0.8, ν = 0.25 printed 1.15 — the table value is 1.25; the monotonicity test catches it).
C33 is not in that routine; its rows were transcribed from Table E.3 as it is reproduced in
railway textbooks, but no second copy could be retrieved during this work to check them against:
treat the last digit of C33 as unverified (the g → 0 asymptote and the circular-contact value are
tested).

Interpolation is linear in g inside the table and linear in ν between the tabulated ν
(CONTACT interpolates 1/C parabolically in ν instead; at ν = 0.3 the two differ by up to 5 %
for the most curved columns, C23 and C33 at the table ends).
Below g = 0.1 Kalker's asymptotes (book, Appendix E; same formulas as CONTACT's ``linrol``) are
used for C11, C22, C23 and, for a ≪ b, C33 ≈ π²/(16 (1 − ν) g); each asymptote is multiplied by
``1 + (r − 1) g / 0.1`` with r = table(0.1)/asymptote(0.1), so the curve is continuous at g = 0.1
and tends to the pure asymptote as g → 0. For a ≫ b, C33 is held at its g = 0.1 value (no
asymptote used).

Force law (Kalker's linear theory; signs as in Kalker 1990 and Garg & Dukkipati)
----------------------------------------------------------------------------------
With c² = a b, G the combined shear modulus, creepages ξ (longitudinal, –), η (lateral, –) and
spin φ (1/m), all defined as (velocity of the wheel's material point − rail's) / V:

    F_x = −G c² C11 ξ
    F_y = −G c² (C22 η + c C23 φ)
    M_z = −G c³ (−C23 η + c C33 φ)

These are the forces *on the wheel*, opposing the slip. The coupling terms have opposite signs
(Kalker's reciprocity).

Saturation
----------
The tangential force is limited to μN by the Shen–Hedrick–Elkins (1983) use of the Johnson–
Vermeulen cubic on the resultant: with F = |(F_x, F_y)| and β = F / (μN),

    F_sat = μN (β − β²/3 + β³/27) for β < 3,  F_sat = μN for β ≥ 3,

and F_x, F_y, M_z are all multiplied by ε = F_sat / F (direction kept). ``saturation="cutoff"``
uses F_sat = min(F, μN) instead.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "KALKER_G",
    "KALKER_NU",
    "KALKER_TABLE_A_GT_B",
    "KALKER_TABLE_A_LE_B",
    "SATURATION_LAWS",
    "kalker_coefficients",
    "linear_creep_forces",
    "saturation_factor",
]

KALKER_G = np.round(np.arange(1, 11) * 0.1, 10)
KALKER_NU = np.array([0.0, 0.25, 0.5])

# Kalker (1990) Table E.3. Shape (10 rows g = 0.1…1.0, 4 coefficients C11 C22 C23 C33, 3 ν).
KALKER_TABLE_A_LE_B = np.array(
    [  # g = a/b
        [[2.51, 3.31, 4.85], [2.51, 2.52, 2.53], [0.334, 0.473, 0.731], [6.42, 8.28, 11.7]],
        [[2.59, 3.37, 4.81], [2.59, 2.63, 2.66], [0.483, 0.603, 0.809], [3.46, 4.27, 5.66]],
        [[2.68, 3.44, 4.80], [2.68, 2.75, 2.81], [0.607, 0.715, 0.889], [2.49, 2.96, 3.72]],
        [[2.78, 3.53, 4.82], [2.78, 2.88, 2.98], [0.720, 0.823, 0.977], [2.02, 2.32, 2.77]],
        [[2.88, 3.62, 4.83], [2.88, 3.01, 3.14], [0.827, 0.929, 1.07], [1.74, 1.93, 2.22]],
        [[2.98, 3.72, 4.91], [2.98, 3.14, 3.31], [0.930, 1.03, 1.18], [1.56, 1.68, 1.86]],
        [[3.09, 3.81, 4.97], [3.09, 3.28, 3.48], [1.03, 1.14, 1.29], [1.43, 1.50, 1.60]],
        [[3.19, 3.91, 5.05], [3.19, 3.41, 3.65], [1.13, 1.25, 1.40], [1.34, 1.37, 1.42]],
        [[3.29, 4.01, 5.12], [3.29, 3.54, 3.82], [1.23, 1.36, 1.51], [1.27, 1.27, 1.27]],
        [[3.40, 4.12, 5.20], [3.40, 3.67, 3.98], [1.33, 1.47, 1.63], [1.21, 1.19, 1.16]],
    ]
)
KALKER_TABLE_A_GT_B = np.array(
    [  # g = b/a
        [[10.7, 11.7, 12.9], [10.7, 12.8, 16.0], [12.2, 14.6, 18.0], [0.795, 0.526, 0.228]],
        [[6.96, 7.78, 8.82], [6.96, 8.14, 9.79], [5.72, 6.63, 7.89], [0.828, 0.601, 0.341]],
        [[5.57, 6.34, 7.34], [5.57, 6.40, 7.51], [3.79, 4.32, 5.01], [0.868, 0.674, 0.446]],
        [[4.84, 5.57, 6.57], [4.84, 5.48, 6.31], [2.88, 3.24, 3.70], [0.912, 0.747, 0.550]],
        [[4.37, 5.10, 6.11], [4.37, 4.90, 5.56], [2.35, 2.62, 2.96], [0.958, 0.819, 0.650]],
        [[4.06, 4.78, 5.80], [4.06, 4.50, 5.04], [2.01, 2.23, 2.50], [1.01, 0.892, 0.748]],
        [[3.82, 4.54, 5.58], [3.82, 4.21, 4.67], [1.76, 1.95, 2.18], [1.05, 0.965, 0.852]],
        [[3.65, 4.36, 5.42], [3.65, 3.99, 4.39], [1.58, 1.75, 1.94], [1.10, 1.04, 0.954]],
        [[3.51, 4.22, 5.30], [3.51, 3.81, 4.16], [1.44, 1.59, 1.77], [1.16, 1.11, 1.06]],
        [[3.40, 4.12, 5.20], [3.40, 3.67, 3.98], [1.33, 1.47, 1.63], [1.21, 1.19, 1.16]],
    ]
)


def _interp_nu(row: np.ndarray, nu: float) -> np.ndarray:
    """Linear interpolation in ν of a (4, 3) block → (4,)."""
    return np.array([np.interp(nu, KALKER_NU, row[i]) for i in range(row.shape[0])])


def _table(table: np.ndarray, g: float, nu: float) -> np.ndarray:
    """Linear in g (0.1 ≤ g ≤ 1) and in ν: (C11, C22, C23, C33)."""
    by_nu = np.array([_interp_nu(table[k], nu) for k in range(table.shape[0])])  # (10, 4)
    return np.array([np.interp(g, KALKER_G, by_nu[:, i]) for i in range(4)])


def _asymptote_a_le_b(g: float, nu: float) -> np.ndarray:
    """Kalker's asymptotes for a/b = g → 0 (narrow ellipse across the rolling direction)."""
    c11 = np.pi**2 / (4.0 * (1.0 - nu))
    c22 = np.pi**2 / 4.0
    c23 = np.pi * np.sqrt(g) / (3.0 * (1.0 - nu)) * (1.0 + nu * (np.log(16.0 / g) - 5.0))
    c33 = np.pi**2 / (16.0 * (1.0 - nu) * g)
    return np.array([c11, c22, c23, c33])


def _asymptote_a_gt_b(g: float, nu: float) -> np.ndarray:
    """Kalker's asymptotes for b/a = g → 0 (long ellipse in the rolling direction); C33 = NaN."""
    lam = np.log(16.0 / g**2)
    k = 3.0 - np.log(4.0)
    c11 = 2.0 * np.pi / ((lam - 2.0 * nu) * g) * (1.0 + k / (lam - 2.0 * nu))
    d = (1.0 - nu) * lam + 2.0 * nu
    c22 = 2.0 * np.pi / g * (1.0 + (1.0 - nu) * k / d) / d
    c23 = 2.0 * np.pi / (3.0 * g**1.5 * ((1.0 - nu) * lam - 2.0 + 4.0 * nu))
    return np.array([c11, c22, c23, np.nan])


def _below_table(table: np.ndarray, asym: Callable, g: float, nu: float) -> np.ndarray:
    """g < 0.1: asymptote blended to meet the table continuously at g = 0.1."""
    g0 = KALKER_G[0]
    at_edge = _table(table, g0, nu)
    ratio = at_edge / asym(g0, nu)
    out = asym(g, nu) * (1.0 + (ratio - 1.0) * g / g0)
    return np.where(np.isnan(out), at_edge, out)


def kalker_coefficients(a: float, b: float, nu: float) -> tuple[float, float, float, float]:
    """Kalker's linear creep coefficients for an ellipse with semi-axes a (rolling) and b.

    Parameters
    ----------
    a, b : float
        Semi-axes of the contact ellipse in the rolling and lateral directions [m], > 0.
    nu : float
        Poisson's ratio, 0 ≤ ν ≤ 0.5.

    Returns
    -------
    (C11, C22, C23, C33) : tuple of float
        Dimensionless coefficients of Kalker's linear theory.
    """
    if not (a > 0.0 and b > 0.0):
        raise ValueError(f"kalker_coefficients: semi-axes must be > 0, got a = {a!r}, b = {b!r}")
    if not 0.0 <= nu <= 0.5:
        raise ValueError(f"kalker_coefficients: need 0 <= nu <= 0.5, got {nu!r}")
    if a <= b:
        g, table, asym = a / b, KALKER_TABLE_A_LE_B, _asymptote_a_le_b
    else:
        g, table, asym = b / a, KALKER_TABLE_A_GT_B, _asymptote_a_gt_b
    c = _table(table, g, nu) if g >= KALKER_G[0] else _below_table(table, asym, g, nu)
    return float(c[0]), float(c[1]), float(c[2]), float(c[3])


# --------------------------------------------------------------------------- force law


def _she(beta: np.ndarray) -> np.ndarray:
    """Johnson–Vermeulen cubic as used by Shen, Hedrick & Elkins (1983): F_sat / (μN)."""
    b = np.minimum(beta, 3.0)
    return b - b**2 / 3.0 + b**3 / 27.0


def _cutoff(beta: np.ndarray) -> np.ndarray:
    return np.minimum(beta, 1.0)


#: Saturation laws by name: β = F_linear / (μN) → F_saturated / (μN).
SATURATION_LAWS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "shen_hedrick_elkins": _she,
    "cutoff": _cutoff,
}


def saturation_factor(
    f_linear: ArrayLike, mu_n: ArrayLike, law: str = "shen_hedrick_elkins"
) -> np.ndarray:
    """Factor ε = F_sat / F_linear ≤ 1 applied to the linear creep forces (1 at F_linear = 0)."""
    try:
        fn = SATURATION_LAWS[law]
    except KeyError:
        valid = ", ".join(sorted(SATURATION_LAWS))
        raise ValueError(f"unknown saturation law {law!r}; valid: {valid}") from None
    f = np.asarray(f_linear, float)
    cap = np.asarray(mu_n, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        beta = f / cap
        eps = fn(beta) / beta
    eps = np.where(cap > 0.0, eps, 0.0)  # no friction or no load: nothing transmitted
    return np.where(f > 0.0, eps, 1.0)


def linear_creep_forces(
    creepages: tuple[ArrayLike, ArrayLike, ArrayLike],
    a: ArrayLike,
    b: ArrayLike,
    G: float,
    C: tuple[ArrayLike, ArrayLike, ArrayLike, ArrayLike],
    N: ArrayLike,
    mu: float,
    saturation: str = "shen_hedrick_elkins",
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Kalker's linear creep forces, saturated to μN. Broadcasts over array inputs.

    Parameters
    ----------
    creepages : (ξ, η, φ)
        Longitudinal and lateral creepage [–], spin creepage [1/m].
    a, b : array_like
        Semi-axes of the contact ellipse, rolling and lateral [m].
    G : float
        Shear modulus [Pa].
    C : (C11, C22, C23, C33)
        Kalker coefficients (``kalker_coefficients``).
    N : array_like
        Normal force [N], ≥ 0 (no force is transmitted at N = 0).
    mu : float
        Friction coefficient.
    saturation : str
        ``"shen_hedrick_elkins"`` (default) or ``"cutoff"``.

    Returns
    -------
    Fx, Fy : ndarray
        Longitudinal and lateral creep forces on the wheel [N].
    Mz : ndarray
        Spin moment about the contact normal [N m].
    """
    xi, eta, phi = (np.asarray(v, float) for v in creepages)
    c11, c22, c23, c33 = (np.asarray(v, float) for v in C)
    c2 = np.asarray(a, float) * np.asarray(b, float)
    c = np.sqrt(c2)
    fx = -G * c2 * c11 * xi
    fy = -G * c2 * (c22 * eta + c * c23 * phi)
    mz = -G * c2 * c * (-c23 * eta + c * c33 * phi)
    eps = saturation_factor(np.hypot(fx, fy), mu * np.asarray(N, float), saturation)
    return fx * eps, fy * eps, mz * eps
