"""Geometry indices (lutmpi/reports/indices.py): a pure cone's functions give each index's
closed form.

The functions fed here are the idealised cone's, Klingel's: Δr(y) = 2 λ y (each wheel's rolling
radius changes by λ per unit of lateral shift) and both contact angles the cone angle atan(λ).
Then tan γe(ŷ) = λ for every amplitude (Klingel; EN 15302 Annex B reduces to it), Polach's
NP = (tan γe(4) − tan γe(2)) / 2 mm = 0, the rolling-radii coefficient (half the LSQ slope of Δr)
= λ, and Δtanγ ≡ 0. (A solved cone on a real rail is not quite that: the wheelset's roll moves
each contact along its cone and tilts both normals, so Δr = 2 λ y b / (b − λ r0) on knife-edge
rails and Δtanγ ≈ 2 roll; the indices are linear in their inputs, so the closed forms above
scale with it.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lutmpi.reports import indices as ix

LAMS = [0.025, 0.05, 0.2]   # 1:40, 1:20, 1:5 cones


@pytest.mark.parametrize("lam", LAMS)
def test_cone_closed_forms(lam):
    y = np.linspace(-9e-3, 9e-3, 181)            # 0.1 mm steps, as EN 15302's data
    res = ix.indices(y, 2.0 * lam * y)
    np.testing.assert_allclose(res.conicity, lam, rtol=1e-6)
    np.testing.assert_allclose(res.rolling_radii, lam, rtol=1e-12)
    assert res.nonlinearity == pytest.approx(0.0, abs=1e-6 * lam / 2e-3)
    ang = np.full((y.size, 2, 2), math.atan(lam))
    np.testing.assert_allclose(ix.delta_tan_gamma(ang), 0.0, atol=1e-15)
    assert res.warnings == []


def test_cone_through_a_table_mapping_with_a_diameter_offset():
    """A 1 mm radius offset (r_left = r_right + 1 mm): Δr = 2 λ y + 1 mm, still a cone; the
    oscillation centres off zero and every index keeps its cone value."""
    lam = 0.05
    y = np.linspace(-20e-3, 20e-3, 401)
    yaw = np.array([-0.01, 0.0, 0.01])
    rr = np.full((y.size, 3, 2, 2), np.nan)
    rr[:, :, 0, 0] = 0.461 + lam * y[:, None]
    rr[:, :, 1, 0] = 0.460 - lam * y[:, None]
    table = {"y": y, "yaw": yaw, "methods": {"m": {"rolling_radius": rr,
                                                   "status": np.zeros((y.size, 3), np.int8)}}}
    res = ix.table_indices(table)
    np.testing.assert_allclose(res.conicity, lam, rtol=1e-6)
    np.testing.assert_allclose(res.rolling_radii, lam, rtol=1e-9)


def test_nonlinearity_parameter_sign_follows_the_conicity_slope():
    """Δr growing faster than linearly (a hollow-worn-like flank) raises tan γe with amplitude:
    NP > 0; a flattening Δr gives NP < 0. NP is the finite difference of the conicity function."""
    y = np.linspace(-9e-3, 9e-3, 181)
    up = 0.1 * y + 400.0 * y**3
    down = 0.1 * y - 150.0 * y**3
    from lutmpi.reports.conicity import equivalent_conicity

    for dr, sign in ((up, 1), (down, -1)):
        np_ = ix.nonlinearity_parameter(y, dr)
        lam2, lam4 = equivalent_conicity(y, dr, [2e-3, 4e-3])
        assert np.sign(np_) == sign
        assert np_ == pytest.approx((lam4 - lam2) / 2e-3, rel=1e-12)


def test_rolling_radii_coefficient_needs_the_whole_range():
    y = np.linspace(-3e-3, 3e-3, 61)
    assert math.isnan(ix.rolling_radii_coefficient(y, 0.1 * y, 4e-3))   # range not covered
