"""Wheel-rail contact geometry indices from the 1-D functions of a table at yaw 0 (pure, SI).

Definitions and their sources
-----------------------------
* **Rolling-radius difference function** ``Δr(y) = r_left(y) − r_right(y)`` of the main contact
  (slot 0), EN 15302's Δr with lutmpi's y to the left (see :func:`lutmpi.reports.conicity.
  dr_from_table`).
* **Equivalent conicity function** ``tan γe(ŷ)``: EN 15302:2008+A1:2010, Annex B (integration of
  the non-linear kinematic equation), :func:`lutmpi.reports.conicity.conicity_curve`. A cone of
  conicity λ gives ``tan γe(ŷ) = λ`` at every amplitude.
* **Nonlinearity parameter** ``NP``: O. Polach, "Characteristic parameters of nonlinear wheel/rail
  contact geometry", Vehicle System Dynamics 48 (Suppl. 1), 2010, 19–36: the slope of the
  equivalent conicity function between the amplitudes 2 mm and 4 mm,
  ``NP = (tan γe(4 mm) − tan γe(2 mm)) / (4 mm − 2 mm)``; stored in 1/m, shown in 1/mm as in the
  paper. NP < 0 (conicity falling with amplitude) tends to a subcritical Hopf bifurcation, NP > 0
  to a supercritical one. A cone gives NP = 0.
* **Rolling-radii coefficient** ``κ(ŷ)``: half the slope of the least-squares straight line through
  Δr(y) over ``|y| ≤ ŷ`` -- the conicity of the cone whose Δr fits the profile pair's best over
  that range (the "linear regression of the Δr function" of EN 15302). EN 15302:2021 lists a
  rolling radii coefficient among its parameters; its text was not available to this project, so
  this definition is lutmpi's and is named here as such. A cone gives ``κ = λ``.
* **Δtanγ function** ``Δtanγ(y) = tan γ_left(y) − tan γ_right(y)`` of the main contacts (contact
  angle positive toward the flange on both wheels), as plotted by the profile-analysis tools and
  used by Polach (2010) next to Δr; its linear coefficient is the contact-angle parameter
  ``ε = e Δtanγ / (2 y)`` of the linear wheelset model (Wickens). A cone's contact angles are
  its cone angle plus and minus the wheelset's roll, so ``Δtanγ ≈ 2 roll`` (0 for Klingel's
  idealised cone without roll).

Not implemented: the radial steering index and GENSYS's GIP (gradient index profile) -- public
definitions were not found in the material available to this project.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from lutmpi.reports import conicity as con

#: amplitudes of Polach's nonlinearity parameter, m
NP_AMPLITUDES = (2e-3, 4e-3)
#: amplitudes at which the indices are tabulated, m
REPORT_AMPLITUDES = (1e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3)


def nonlinearity_parameter(y, dr) -> float:
    """Polach's NP, 1/m: ``(tan γe(4 mm) − tan γe(2 mm)) / 2 mm`` (NaN if either is missing)."""
    a2, a4 = NP_AMPLITUDES
    lam = con.equivalent_conicity(y, dr, [a2, a4])
    return float((lam[1] - lam[0]) / (a4 - a2))


#: the step (m) at which :func:`rolling_radii_coefficient` samples Δr between its data points
KAPPA_STEP = 1e-5


def rolling_radii_coefficient(y, dr, amplitude: float) -> float:
    """κ(ŷ): half the least-squares slope of Δr over ``|y| ≤ ŷ`` (dimensionless; NaN when fewer
    than 3 samples lie in the range or the range is not covered by the data). Δr, linear between
    its samples, is fitted at points every :data:`KAPPA_STEP`, so the samples' own spacing (a
    table's grid nodes, its extra knots, both sides of each jump) does not weight the fit."""
    y = np.asarray(y, float)
    dr = np.asarray(dr, float)
    m = (np.abs(y) <= amplitude + 1e-12) & np.isfinite(dr)
    if m.sum() < 3 or y.min() > -amplitude + 1e-12 or y.max() < amplitude - 1e-12:
        return math.nan
    ok = np.isfinite(dr)
    yu = np.linspace(-amplitude, amplitude, int(round(2 * amplitude / KAPPA_STEP)) + 1)
    return float(0.5 * np.polyfit(yu, np.interp(yu, y[ok], dr[ok]), 1)[0])


def delta_tan_gamma(contact_angle: np.ndarray) -> np.ndarray:
    """``tan γ_left − tan γ_right`` of slot 0 from ``contact_angle`` of shape ``(n, 2, 2)``, rad."""
    a = np.asarray(contact_angle, float)
    return np.tan(a[:, 0, 0]) - np.tan(a[:, 1, 0])


@dataclass
class Indices:
    """The indices of one Δr / contact-angle pair of functions (SI)."""

    amplitudes: np.ndarray
    conicity: np.ndarray
    rolling_radii: np.ndarray
    nonlinearity: float
    warnings: list[str]

    def row(self) -> dict[str, float]:
        """Flat ``name -> value`` with units in the names (mm at the edge)."""
        out = {}
        for a, c, k in zip(self.amplitudes, self.conicity, self.rolling_radii, strict=True):
            out[f"tan_gamma_e_{a * 1e3:g}mm"] = float(c)
            out[f"rolling_radii_coeff_{a * 1e3:g}mm"] = float(k)
        out["nonlinearity_parameter_per_mm"] = self.nonlinearity * 1e-3
        return out


def indices(y, dr, amplitudes=REPORT_AMPLITUDES) -> Indices:
    """Every index of a Δr(y) function with NaN holes (holes limit the amplitudes, never joined).

    Parameters
    ----------
    y, dr : array_like, shape (n,)
        m; ``dr`` NaN at failed poses.
    amplitudes : sequence of float
        m.
    """
    amps = np.asarray(amplitudes, float)
    found = con.check_dr(y, dr, np.r_[amps, NP_AMPLITUDES], refuse_holes=False)
    if found.y.size < 3:
        nan = np.full(amps.size, np.nan)
        return Indices(amps, nan, nan, math.nan, found.warnings + ["fewer than 3 Δr values"])
    lam = con.equivalent_conicity(found.y, found.dr, amps)
    kap = np.array([rolling_radii_coefficient(found.y, found.dr, a) for a in amps])
    return Indices(amps, lam, kap, nonlinearity_parameter(found.y, found.dr), found.warnings)


def table_indices(table: Any, method: str | None = None,
                  amplitudes=REPORT_AMPLITUDES) -> Indices:
    """:func:`indices` of a :class:`~lutmpi.table.Table` at yaw 0 (failed poses are holes)."""
    y, dr = con.dr_from_table(table, method)
    return indices(y, dr, amplitudes)
